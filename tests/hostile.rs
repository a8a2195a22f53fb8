//! Hostile input through the CLI (issue #13): every file in `tests/hostile/`, plus huge inputs made
//! here, goes to `mazewalk check`. Each must end (the test bounds it with a timeout and kills it)
//! with exit 65 (bad data), 66 (cannot read) or 2 (usage), or 0 for the `ok-*` files, and a message of
//! one line, of bounded length, free of control characters. No timing is checked.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longest accepted error message, path excluded: a sentence plus a [`QUOTE_CHARS`] quote.
const MAX_MESSAGE: usize = 300;

/// How long a case may run before it counts as a hang (generous: a debug build on a busy machine).
const TIMEOUT: Duration = Duration::from_secs(60);

struct Outcome {
    code: Option<i32>,
    stderr: String,
}

/// This test's own scratch folder (tests run in parallel, each on a thread named after it).
fn scratch_dir() -> PathBuf {
    let test = std::thread::current().name().unwrap_or("main").replace("::", "-");
    std::env::temp_dir().join(format!("mazewalk-hostile-{}-{test}", std::process::id()))
}

fn scratch(name: &str) -> PathBuf {
    let dir = scratch_dir();
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Removes the test's scratch folder when the test ends, whether it passed or not.
struct Cleanup;

impl Drop for Cleanup {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(scratch_dir());
    }
}

/// Runs `mazewalk ARGS` with `stdin`, killing it after [`TIMEOUT`].
fn run(args: &[&str], stdin: Stdio) -> Outcome {
    let err_path = scratch(&format!("stderr-{}", args.join("_").replace('/', "_")));
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(args)
        .stdin(stdin)
        .stdout(Stdio::null())
        .stderr(File::create(&err_path).unwrap())
        .spawn()
        .expect("run mazewalk");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("mazewalk {args:?} did not end within {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let stderr = String::from_utf8_lossy(&std::fs::read(&err_path).unwrap()).into_owned();
    Outcome { code: status.code(), stderr }
}

/// Checks one case's exit code and message; `path` is what the message may name.
fn check_outcome(case: &str, path: &str, out: &Outcome, codes: &[i32]) {
    assert!(
        out.code.is_some_and(|c| codes.contains(&c)),
        "{case}: exit {:?}, wanted {codes:?}: {}",
        out.code,
        out.stderr
    );
    if out.code == Some(0) {
        return;
    }
    let message = out.stderr.strip_suffix('\n').unwrap_or(&out.stderr);
    assert!(!message.is_empty(), "{case}: no message");
    assert!(!message.contains('\n'), "{case}: more than one line: {message:?}");
    assert!(!message.chars().any(char::is_control), "{case}: a control character: {message:?}");
    let len = message.chars().count().saturating_sub(path.chars().count());
    assert!(len <= MAX_MESSAGE, "{case}: a message of {len} characters: {message:?}");
}

fn check_file(path: &Path, codes: &[i32]) -> Outcome {
    let p = path.to_str().unwrap();
    let out = run(&["check", p], Stdio::null());
    check_outcome(&path.file_name().unwrap().to_string_lossy(), p, &out, codes);
    out
}

const DATA_OR_INPUT: &[i32] = &[65, 66, 2];

#[test]
fn every_corpus_file_is_refused_or_accepted_cleanly() {
    let _cleanup = Cleanup;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    assert!(files.len() >= 40, "the corpus is in {}", dir.display());
    for path in files {
        let ok = path.file_name().unwrap().to_string_lossy().starts_with("ok-");
        check_file(&path, if ok { &[0] } else { DATA_OR_INPUT });
    }
}

#[test]
fn messages_name_the_problem() {
    let _cleanup = Cleanup;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile");
    for (name, wanted) in [
        ("utf16-bom.maze", ":1:1: this looks like UTF-16; save the file as UTF-8"),
        ("utf16-no-bom.maze", "this looks like UTF-16"),
        ("utf16-be.maze", "this looks like UTF-16"),
        ("grid-utf16.grid", "this looks like UTF-16"),
        (
            "escape-sequence.maze",
            ":2:3: expected a number (vertex 0 y), found `\\u{1b}]0;pwned\\u{7}\\u{1b}[2J\\u{1b}[H`",
        ),
        ("nul-inside.maze", "a NUL byte"),
        ("viewer-on-vertex.maze", "stands on wall"),
        ("viewer-on-wall.maze", ":13:1: the viewer at (2, 0) stands on wall 0"),
        ("tiny-area.maze", "has an area of"),
        ("grid-tab.grid", ":4:3: unknown tile `\\t` (a tab"),
    ] {
        let out = check_file(&dir.join(name), DATA_OR_INPUT);
        assert!(out.stderr.contains(wanted), "{name}: {}", out.stderr);
    }
}

#[test]
fn huge_tokens_lines_and_newlines_give_short_messages() {
    let _cleanup = Cleanup;
    let ten_mb = 10 << 20;
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("token.maze", [b"4\n".as_slice(), &vec![b'7'; ten_mb]].concat()),
        ("word.maze", [b"4\n0 ".as_slice(), &vec![b'x'; ten_mb]].concat()),
        ("line.maze", [b"1000000000 ".as_slice(), &b"0 ".repeat(ten_mb / 2)].concat()),
        ("newlines.maze", vec![b'\n'; ten_mb]),
        ("setting.grid", [b"mazewalk-grid 1\n".as_slice(), &vec![b'x'; ten_mb]].concat()),
        ("row.grid", [b"mazewalk-grid 1\n\n#@".as_slice(), &vec![b'.'; ten_mb]].concat()),
        ("newlines.grid", [b"mazewalk-grid 1\n".as_slice(), &vec![b'\n'; ten_mb]].concat()),
        ("nul.maze", [b"4\n".as_slice(), &vec![0; ten_mb]].concat()),
    ];
    for (name, bytes) in cases {
        let path = scratch(name);
        std::fs::write(&path, bytes).unwrap();
        let out = check_file(&path, &[65]);
        if name == "newlines.maze" {
            assert!(out.stderr.contains(":10485761:1: unexpected end of file"), "{}", out.stderr);
        }
        std::fs::remove_file(&path).unwrap();
    }
}

#[test]
fn special_files_and_sparse_giants_end_with_an_error() {
    let _cleanup = Cleanup;
    // a character device that never ends: refused unopened-for-reading
    check_file(Path::new("/dev/zero"), &[66]);
    // a FIFO with no writer: refused, not waited on
    let fifo = scratch("fifo.maze");
    let _ = std::fs::remove_file(&fifo);
    let made = Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let out = check_file(&fifo, &[66]);
        assert!(out.stderr.contains("not a regular file (a FIFO)"), "{}", out.stderr);
        std::fs::remove_file(&fifo).unwrap();
    }
    // 1 GB of nothing: refused by its size, before reading
    let sparse = scratch("sparse.maze");
    File::create(&sparse).unwrap().set_len(1 << 30).unwrap();
    let out = check_file(&sparse, &[65]);
    assert!(
        out.stderr.contains("larger than the limit of 268435456 bytes (1073741824 bytes)"),
        "{}",
        out.stderr
    );
    // the flag raises the limit: the same file is read, and its zeros stop the reading at once
    let p = sparse.to_str().unwrap();
    let out = run(&["check", "--max-file-size", "2G", p], Stdio::null());
    check_outcome("sparse, 2G", p, &out, &[65]);
    assert!(out.stderr.contains(":1:1: a NUL byte"), "{}", out.stderr);
    std::fs::remove_file(&sparse).unwrap();
    // a bad limit is a usage error
    let out = run(&["check", "--max-file-size", "lots", p], Stdio::null());
    assert_eq!(out.code, Some(2), "{}", out.stderr);
}

#[test]
fn stdin_is_read_with_the_same_limits() {
    let _cleanup = Cleanup;
    // `-` reads stdin: /dev/zero stops at its first byte
    let out = run(&["check", "-"], Stdio::from(File::open("/dev/zero").unwrap()));
    check_outcome("stdin /dev/zero", "-", &out, &[65]);
    // text beyond the limit
    let big = scratch("big.maze");
    std::fs::write(&big, "1 ".repeat(1 << 20)).unwrap();
    let out = run(&["check", "--max-file-size", "64K", "-"], Stdio::from(File::open(&big).unwrap()));
    check_outcome("stdin over the limit", "-", &out, &[65]);
    assert!(out.stderr.contains("larger than the limit of 65536 bytes (more)"), "{}", out.stderr);
    // and a maze
    let room = Path::new(env!("CARGO_MANIFEST_DIR")).join("mazes/tiny.maze");
    let out = run(&["check", "-"], Stdio::from(File::open(room).unwrap()));
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    std::fs::remove_file(&big).unwrap();
}
