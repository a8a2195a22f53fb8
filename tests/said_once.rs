//! What is said in two places agrees. The README's lists of things defined elsewhere: every fuzz
//! target (`fuzz/` and `crates/math/fuzz/`) and every bench (`benches/Cargo.toml`) is named where the
//! README lists them, and nothing else is. The README's test command is the one `.ci/run` runs. The
//! keys: `mazewalk --help` shows the walk's own `?` help, and the README's keys table names every key
//! of it. `gen` and `--gen` make the same maze of a size when given the same options. Every property
//! takes its configuration from `mazewalk-testkit`, as the README says.

use std::collections::BTreeSet;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn read(path: &str) -> String {
    std::fs::read_to_string(format!("{ROOT}/{path}")).unwrap_or_else(|err| panic!("{path}: {err}"))
}

/// The `name`s of a manifest's `[[section]]` tables (`[[bin]]`, `[[bench]]`), in order.
fn target_names(manifest: &str, section: &str) -> BTreeSet<String> {
    let header = format!("[[{section}]]");
    let mut names = BTreeSet::new();
    let mut inside = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == header;
        } else if inside && let Some(value) = line.strip_prefix("name") {
            let value = value.trim_start().strip_prefix('=').expect("name = \"…\"").trim();
            names.insert(value.trim_matches('"').to_string());
        }
    }
    names
}

/// The README's paragraph that starts with `start` (up to the next blank line).
fn paragraph<'a>(readme: &'a str, start: &str) -> &'a str {
    let at = readme.find(start).unwrap_or_else(|| panic!("the README has a paragraph starting {start:?}"));
    let rest = &readme[at..];
    &rest[..rest.find("\n\n").unwrap_or(rest.len())]
}

/// The names written as `` `name` ( `` in `text`: how the README introduces each target it lists.
fn listed(text: &str) -> BTreeSet<String> {
    let parts: Vec<&str> = text.split('`').collect();
    (1..parts.len().saturating_sub(1))
        .step_by(2) // the code spans
        .filter(|&i| parts[i + 1].starts_with(" ("))
        .filter(|&i| parts[i].chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        .map(|i| parts[i].to_string())
        .collect()
}

#[test]
fn the_readme_lists_every_fuzz_target_and_no_other() {
    let readme = read("README.md");
    let fuzzing = paragraph(&readme, "Fuzzing uses");
    let mut targets = target_names(&read("fuzz/Cargo.toml"), "bin");
    targets.extend(target_names(&read("crates/math/fuzz/Cargo.toml"), "bin"));
    assert!(targets.contains("maze") && targets.contains("math"), "{targets:?}");
    let mut named = listed(fuzzing);
    // The math core's target is introduced by its folder: "(`crates/math/fuzz`: …)".
    if fuzzing.contains("(`crates/math/fuzz`") {
        named.insert("math".to_string());
    }
    assert_eq!(named, targets, "README's fuzzing paragraph:\n{fuzzing}");
}

#[test]
fn the_readme_lists_every_bench_and_no_other() {
    let readme = read("README.md");
    let line = readme
        .lines()
        .find(|l| l.starts_with("cargo bench -p mazewalk-bench"))
        .expect("the README's `cargo bench` line");
    let list = line.split_once("# criterion:").expect("its comment lists the benches").1;
    let named: BTreeSet<String> = list
        .split(',')
        .map(|item| item.split('(').next().unwrap_or("").trim().to_string())
        .filter(|name| !name.is_empty())
        .collect();
    assert_eq!(named, target_names(&read("benches/Cargo.toml"), "bench"), "{line}");
}

#[test]
fn ci_runs_the_readmes_test_command() {
    let readme = read("README.md");
    let block = readme.split("```sh\n").nth(1).expect("the README's first commands");
    let second = block.lines().nth(1).expect("a second command");
    let command = second.split('#').next().unwrap_or("").trim();
    assert_eq!(command, "scripts/test-all", "{second}");
    let ci = read(".ci/run");
    assert!(
        ci.lines().any(|l| l.trim() == command || l.trim().starts_with(&format!("{command} "))),
        ".ci/run runs {command}"
    );
    assert!(std::path::Path::new(&format!("{ROOT}/{command}")).is_file(), "{command} exists");
}

/// The walk's `?` help, as `(keys, what)` rows: the box's lines split where every line's key column
/// ends (they are padded to one width).
fn help_rows() -> Vec<(String, String)> {
    let lines = mazewalk_walk::overlay::help_lines(mazewalk_walk::overlay::Style::default(), false);
    let chars: Vec<Vec<char>> = lines.iter().map(|l| l.chars().collect()).collect();
    let width = (1..chars[0].len())
        .find(|&w| chars.iter().all(|l| l.get(w) == Some(&' ') && l.get(w + 1).is_some_and(|c| *c != ' ')))
        .expect("a key column");
    chars
        .iter()
        .map(|l| (l[..width].iter().collect::<String>().trim().to_string(), l[width + 1..].iter().collect()))
        .collect()
}

/// The keys of a help row's key column: `"q / Ctrl-C"` → `q`, `Ctrl-C`; `", . or < >"` → `,` `.` `<` `>`.
fn keys_of(column: &str) -> Vec<&str> {
    column.split_whitespace().filter(|k| !["/", "or"].contains(k)).collect()
}

#[test]
fn help_shows_the_walks_own_key_help() {
    let out =
        std::process::Command::new(env!("CARGO_BIN_EXE_mazewalk")).arg("--help").output().expect("mazewalk");
    let help = String::from_utf8_lossy(&out.stdout);
    let rows = help_rows();
    assert!(rows.len() > 10, "{rows:?}");
    for (keys, what) in &rows {
        let shown = help
            .lines()
            .any(|l| l.trim_start().starts_with(keys.as_str()) && l.trim_end().ends_with(what.as_str()));
        assert!(shown, "`{keys}  {what}` in --help:\n{help}");
    }
    for key in ["b", "v", "t"] {
        assert!(rows.iter().any(|(keys, _)| keys_of(keys).contains(&key)), "{key} is in the help");
    }
}

#[test]
fn the_readme_keys_table_names_every_key_of_the_help_and_no_other() {
    let readme = read("README.md");
    let table: Vec<&str> = readme
        .split("| keys | what |")
        .nth(1)
        .expect("the README's keys table")
        .lines()
        .skip(2) // the header's rule
        .take_while(|l| l.starts_with('|'))
        .collect();
    let first_column: Vec<&str> = table.iter().map(|row| row.split(" | ").next().unwrap_or("")).collect();
    let readme_keys: BTreeSet<&str> =
        first_column.iter().flat_map(|cell| cell.split('`').skip(1).step_by(2)).collect();
    let rows = help_rows();
    let help_text: String = rows.iter().map(|(k, w)| format!("{k} {w}\n")).collect();
    for (keys, _) in &rows {
        for key in keys_of(keys) {
            let named = readme_keys.contains(key)
                || table.iter().any(|row| row.contains(&format!("`{key}`")))
                || table.iter().any(|row| row.contains(&format!("| mouse {key} |")));
            assert!(named, "the help's key {key:?} is in the README's keys table");
        }
    }
    for key in readme_keys {
        assert!(
            help_text.split_whitespace().any(|w| w == key || w.trim_matches(|c| c == '(' || c == ',') == key),
            "the README's key `{key}` is in the help:\n{help_text}"
        );
    }
}

#[test]
fn gen_and_the_walks_gen_make_the_same_maze_by_default() {
    let dir = std::env::temp_dir().join(format!("mazewalk-said-once-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let file = dir.join("gen.maze");
    let mazewalk = |args: &[&str]| {
        let out =
            std::process::Command::new(env!("CARGO_BIN_EXE_mazewalk")).args(args).output().expect("mazewalk");
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        out.stdout
    };
    // (no seed given to either)
    mazewalk(&["gen", "--size", "6x5", "--loops", "0.1", "--exit", "-o", file.to_str().expect("utf-8")]);
    // (`--fov`: a generated maze in memory keeps a vertical field of view a file has no place for, so
    // on a wide view `--gen` shows more; the same horizontal field shows the same maze and viewer)
    let look = ["--size", "40x12", "--charset", "ascii", "--color", "none", "--heading", "45", "--fov", "90"];
    let from_file = mazewalk(&[&["render", file.to_str().expect("utf-8")][..], &look].concat());
    let generated = mazewalk(&[&["render", "--gen", "6x5"][..], &look].concat());
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(String::from_utf8_lossy(&from_file), String::from_utf8_lossy(&generated));
}

/// The Rust files below `dir` (the repository's own: `target/` and `fuzz/` left out), recursively.
fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|err| panic!("{}: {err}", dir.display())) {
        let path = entry.expect("a directory entry").path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if path.is_dir() && !["target", "fuzz"].contains(&name) {
            rust_files(&path, out);
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

// README "Tests, property tests and fuzzing": every property takes its configuration from
// mazewalk-testkit (its case count, which `PROPTEST_CASES` sets for all of them, and where failing
// cases are saved). A `proptest!` block whose first line is not testkit's `config()` or
// `config_cases(N)` runs proptest's own (256 cases, or its `cases: N` whatever `PROPTEST_CASES`
// says), and under `tests/` saves no failing case.
#[test]
fn every_property_takes_its_configuration_from_the_testkit() {
    let mut files = Vec::new();
    for dir in ["src", "tests", "crates"] {
        rust_files(&std::path::Path::new(ROOT).join(dir), &mut files);
    }
    let mut blocks = 0;
    let mut own = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap_or_else(|err| panic!("{}: {err}", file.display()));
        let lines: Vec<&str> = text.lines().collect();
        for (i, _) in lines.iter().enumerate().filter(|(_, l)| l.trim_start().starts_with("proptest! {")) {
            blocks += 1;
            // the block's first line that is not a comment or blank
            let first =
                lines[i + 1..].iter().map(|l| l.trim()).find(|l| !l.is_empty() && !l.starts_with("//"));
            let testkit = first.is_some_and(|l| {
                l.starts_with("#![proptest_config(")
                    && ["config()", "config_cases("].iter().any(|c| {
                        let at = "#![proptest_config(".len();
                        let call =
                            l[at..].trim_start_matches("mazewalk_testkit::").trim_start_matches("common::");
                        call.starts_with(c)
                    })
            });
            if !testkit {
                own.push(format!("{}:{}: {}", file.display(), i + 2, first.unwrap_or("")));
            }
        }
    }
    assert!(blocks > 30, "the properties were found: {blocks}");
    assert!(own.is_empty(), "properties with a configuration of their own:\n{}", own.join("\n"));
}
