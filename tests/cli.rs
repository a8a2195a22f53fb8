//! The binary as a user meets it: `render`, `gen`, `check` and the walk without a terminal, with their
//! outputs and exit codes (0 ok, 2 usage, 65 bad maze data, 66 unreadable file, 1 anything else).

use std::process::{Command, Output};

fn mazewalk(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(args)
        .env_remove("NO_COLOR")
        .env("COLORTERM", "truecolor")
        .env("TERM", "xterm-256color")
        .output()
        .expect("run mazewalk")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn maze(name: &str) -> String {
    format!("{}/mazes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// An eye put closer to a wall than the walk would ever stand (on it, a hair off it, in a viewer
/// line of the file) sees the wall, from where the walk would stand: the maze's clearance from it (1.6,
/// 2/5 of tiny.maze's 4-wide cell). It saw through the wall (the near plane lies inside it).
#[test]
fn an_eye_against_a_wall_sees_the_wall_from_where_the_walk_stands() {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-against-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tiny = std::fs::read_to_string(maze("tiny.maze")).unwrap();
    let against = dir.join("against.maze");
    let (from, to) = ("2 2 0 0 90", "0.001 2 0 180 90");
    assert!(tiny.lines().any(|l| l.trim() == from), "the premise: tiny.maze's viewer line");
    std::fs::write(&against, tiny.replace(from, to)).unwrap();
    let frame = |file: &str, at: Option<&str>| {
        let mut args = vec!["render", file, "--heading", "180", "--size", "40x12", "--charset", "ascii"];
        args.extend(["--color", "none"]);
        if let Some(at) = at {
            args.extend(["--at", at]);
        }
        let out = mazewalk(&args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        stdout(&out)
    };
    let tiny = maze("tiny.maze");
    let standing = frame(&tiny, Some("1.6,2"));
    for at in ["0,2", "0.0000001,2", "0.001,2", "0.1,2", "0.25,2", "0.9,2", "1,2", "1.5,2"] {
        assert_eq!(frame(&tiny, Some(at)), standing, "--at {at}");
    }
    assert_eq!(frame(against.to_str().unwrap(), None), standing, "the file's viewer at 0.001");
    // `render --stats` tells where the frame was seen from.
    let stats = mazewalk(&["render", &tiny, "--at", "0.001,2", "--stats", "--size", "8x4"]);
    let json: serde_json::Value = serde_json::from_slice(&stats.stderr).expect("--stats is JSON");
    let viewer = [&json["viewer"][0], &json["viewer"][1]].map(|v| v.as_f64().expect("two numbers"));
    assert!((1.6..1.6005).contains(&viewer[0]) && viewer[1] == 2.0, "{json}");
    // `check` tells the maze's author where the walk starts instead.
    let report = stdout(&mazewalk(&["check", against.to_str().unwrap()]));
    assert!(report.contains("closer than 1.6 to a wall: the walk starts at (1.6"), "{report}");
    assert!(!stdout(&mazewalk(&["check", &tiny])).contains("the walk starts"), "tiny's viewer is clear");
    // …and what it sees is the wall, as from further back, where no near plane reaches it.
    assert_eq!(standing, frame(&tiny, Some("1.65,2")));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `render --at` in a cell narrower than the viewer's disc: refused with the reason (from there the
/// near plane cut every wall away: a blank frame). The maze itself, whose viewer has room, renders.
#[test]
fn render_at_a_place_with_no_room_to_stand_is_refused() {
    let path = std::env::temp_dir().join(format!("mazewalk-cli-thin-{}.maze", std::process::id()));
    // A cell 0.3 wide, and a 4 × 4 room of its own beside it where the viewer stands.
    let thin = "8  0 0 0.3 0 0.3 4 0 4  10 0 14 0 14 4 10 4
        8  0 1 0 -1 1 1 1 1  1 2 0 -1 1 1 1 1  2 3 0 -1 1 1 1 1  3 0 0 -1 1 1 1 1
           4 5 1 -1 1 1 1 1  5 6 1 -1 1 1 1 1  6 7 1 -1 1 1 1 1  7 4 1 -1 1 1 1 1
        2  0 1 2 3  4 5 6 7
        12 2 0 90 90";
    std::fs::write(&path, thin).unwrap();
    let file = path.to_str().unwrap();
    let args = ["render", file, "--size", "20x6", "--color", "none", "--charset", "ascii"];
    assert!(mazewalk(&args).status.success(), "{}", stderr(&mazewalk(&args)));
    let out = mazewalk(&[&args[..], &["--at", "0.15,2"]].concat());
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--at 0.15,2 has no room to stand"), "{}", stderr(&out));
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn render_prints_one_frame_of_the_requested_size() {
    let out = mazewalk(&["render", "--size", "50x12", "--charset", "ascii", "--color", "none"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 12);
    assert!(lines.iter().all(|l| l.chars().count() == 50), "{text}");
    assert!(!text.contains('\x1b'), "--color none must be plain text");
    // The built-in maze's start faces down a corridor: walls left and right, something in between.
    assert!(lines.iter().any(|l| l.chars().collect::<std::collections::HashSet<_>>().len() >= 3), "{text}");
}

#[test]
fn render_in_colour_writes_ansi_that_resets_each_line() {
    let out = mazewalk(&["render", "--size", "30x8", "--charset", "half", "--color", "truecolor"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("\x1b[38;2;") || text.contains("\x1b[48;2;"), "{text:?}");
    assert!(text.lines().all(|l| l.ends_with("\x1b[0m") || !l.contains('\x1b')), "{text:?}");
    assert_eq!(text.lines().count(), 8);
}

/// `render` draws half blocks by default whatever `TERM` says (the walk draws ascii on a DEC
/// terminal, `render` writes what the terminal it was asked for shows).
#[test]
fn render_keeps_half_blocks_on_a_dec_term() {
    let run = |term: &str, args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(["render", "--size", "30x8", "--color", "truecolor"])
            .args(args)
            .env_remove("NO_COLOR")
            .env("TERM", term)
            .output()
            .expect("run mazewalk");
        assert!(out.status.success(), "{}", stderr(&out));
        stdout(&out)
    };
    let vt100 = run("vt100", &[]);
    assert!(vt100.contains('▀') || vt100.contains('▄'), "{vt100:?}");
    assert_eq!(vt100, run("vt100", &["--charset", "half"]));
    assert_eq!(vt100, run("xterm-256color", &[]));
    let help = run("vt100", &["--help"]);
    assert!(help.contains("the walk draws ascii where block glyphs cannot show"), "{help}");
}

#[test]
fn depth_out_matches_the_geometry_of_a_known_room() {
    // tiny.maze: two 4×4 cells side by side, x from 0 to 8; the viewer at (2, 2) faces +x with a 90°
    // field of view. Along the middle row (the horizon) the ray of column c has slope s = ndc_x
    // (tan 45° = 1): it meets the end wall x = 8 at view depth 6, or a side wall (y = 0 or 4) at 2 / |s|.
    let csv = std::env::temp_dir().join(format!("mazewalk-depth-{}.csv", std::process::id()));
    let (cols, rows) = (41, 11);
    let out = mazewalk(&[
        "render",
        &maze("tiny.maze"),
        "--size",
        &format!("{cols}x{rows}"),
        "--depth-out",
        csv.to_str().unwrap(),
        "--color",
        "none",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&csv).unwrap();
    let _ = std::fs::remove_file(&csv);
    let grid: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(grid.len(), rows);
    assert!(grid.iter().all(|r| r.len() == cols));
    let middle = &grid[rows / 2];
    for (c, field) in middle.iter().enumerate() {
        let ndc_x = (c as f32 + 0.5) / cols as f32 * 2.0 - 1.0;
        let expected = if ndc_x.abs() < 1e-6 { 6.0 } else { (2.0 / ndc_x.abs()).min(6.0) };
        let got: f32 = field.parse().unwrap_or_else(|_| panic!("column {c}: `{field}` is not a depth"));
        assert!(
            (got - expected).abs() < 1e-3 * expected.max(1.0),
            "column {c}: depth {got}, expected {expected}"
        );
    }
    // Looking up at the ceiling or down at the floor there is no wall at the top and bottom rows' middle.
    assert_eq!(grid[0][cols / 2], "", "the top row's centre sees the ceiling");
}

#[test]
fn stats_are_one_json_object_and_portal_culling_visits_few_cells() {
    let big = maze("prim-100x100.maze");
    let run = |culling: &str| {
        let out = mazewalk(&[
            "render",
            &big,
            "--size",
            "80x24",
            "--color",
            "none",
            "--stats",
            "--culling",
            culling,
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let line = stderr(&out).trim().to_string();
        assert!(line.starts_with('{') && line.ends_with('}'), "{line}");
        let field = |key: &str| -> u64 {
            let at = line.find(&format!("\"{key}\":")).unwrap_or_else(|| panic!("no {key} in {line}"));
            line[at + key.len() + 3..].split([',', '}']).next().unwrap().parse().unwrap()
        };
        (
            field("cells_visited"),
            field("portals_traversed"),
            field("walls_drawn"),
            field("triangles"),
            field("render_us"),
            stdout(&out),
        )
    };
    let (cells, portals, walls, _, _, portal_frame) = run("portal");
    let (_, _, all_walls, _, _, brute_frame) = run("none");
    assert!((1..10_000 / 20).contains(&cells), "visited {cells} of 10000 cells");
    assert!(portals >= 1 && walls < all_walls, "{walls} walls drawn of {all_walls}");
    assert_eq!(portal_frame, brute_frame, "culling changes nothing on screen");
}

#[test]
fn bad_render_arguments_are_usage_errors() {
    let cases: &[(&[&str], &str)] = &[
        (&["--charset", "braille"], "braille"),
        (&["--size", "0x0"], "1..="),
        (&["--size", "99999x10"], "1..="),
        (&["--size", "80"], "COLSxROWS"),
        (&["--fov", "NaN"], "finite"),
        (&["--fov", "200"], "--fov"),
        (&["--fov", "5"], "field of view of 5° is outside 10..=170°"),
        (&["--height", "1.5"], "height"),
        (&["--pitch", "inf"], "finite"),
        (&["--at", "1e9,3"], "outside the maze"),
        (&["--at", "10,46"], "inside a wall"),
        (&["--at", "nope"], "X,Y"),
        // bbA #4: finite numbers too large for an f32 are out of range, with the range
        (&["--at", "1e308,1e308"], "1e308 is out of range: a maze's X and Y are within ±1000000"),
        (&["--heading", "1e308"], "heading 1e308° is out of range: a heading must be within -36000..=36000"),
        (
            &["--height", "-1e99"],
            "eye height -1e99 is not strictly between the floor (-1) and the ceiling (+1)",
        ),
        (&["--at", "2,2,2"], "expected two numbers X,Y, e.g. 2.5,3, found `2,2,2`"),
        (&["--color", "mauve"], "colour depth"),
        (&["--projection", "fisheye"], "projection"),
        (&["--culling", "some"], "culling"),
        (&["--cell-aspect", "0"], "cell aspect"),
    ];
    for (args, needle) in cases {
        let mut all = vec!["render"];
        all.extend_from_slice(args);
        let out = mazewalk(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(needle), "{args:?}: expected `{needle}` in: {}", stderr(&out));
        assert!(out.stdout.is_empty(), "{args:?} printed a frame anyway");
    }
}

/// Red-team pass 8: a range's bounds, written as its own message writes them, are in it (`0.1` was
/// "outside 0.1..=4": the text's f64 was compared with the bound's f32, 0.100000001…); just past a
/// bound is still out.
#[test]
fn a_flags_range_takes_its_own_bounds_as_written() {
    for aspect in ["0.1", "4", "0.100000001"] {
        let out = mazewalk(&["render", "--cell-aspect", aspect, "--size", "20x8"]);
        assert_eq!(out.status.code(), Some(0), "--cell-aspect {aspect}: {}", stderr(&out));
    }
    for aspect in ["0.0999", "4.001"] {
        let out = mazewalk(&["render", "--cell-aspect", aspect, "--size", "20x8"]);
        assert_eq!(out.status.code(), Some(2), "--cell-aspect {aspect} taken");
    }
    // the walk's steps, parsed before it asks for a terminal (a usage error is exit 2, the missing
    // terminal something else)
    for (flag, bound) in [("--walk-step", "0.05"), ("--turn-step", "1"), ("--walk-step", "4")] {
        let out = mazewalk(&[flag, bound]);
        assert_ne!(out.status.code(), Some(2), "{flag} {bound}: {}", stderr(&out));
    }
}

#[test]
fn maze_errors_are_located_and_have_their_own_exit_codes() {
    let bad = std::env::temp_dir().join(format!("mazewalk-bad-{}.maze", std::process::id()));
    std::fs::write(&bad, "4\n0 0\n1 0\n1 banana\n").unwrap();
    for command in [&["check"][..], &["render"][..]] {
        let mut args = command.to_vec();
        args.push(bad.to_str().unwrap());
        let out = mazewalk(&args);
        assert_eq!(out.status.code(), Some(65), "{}", stderr(&out));
        assert!(stderr(&out).starts_with(&format!("{}:4:3: ", bad.display())), "{}", stderr(&out));
    }
    let _ = std::fs::remove_file(&bad);
    let out = mazewalk(&["check", "/nonexistent/maze.maze"]);
    assert_eq!(out.status.code(), Some(66), "{}", stderr(&out));
}

#[test]
fn gen_then_check_round_trips_through_a_file() {
    let path = std::env::temp_dir().join(format!("mazewalk-gen-{}.maze", std::process::id()));
    let out = mazewalk(&[
        "gen",
        "--size",
        "12x7",
        "--seed",
        "3",
        "--loops",
        "0.2",
        "--exit",
        "-o",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = mazewalk(&["check", path.to_str().unwrap()]);
    let _ = std::fs::remove_file(&path);
    assert!(out.status.success(), "{}", stderr(&out));
    let report = stdout(&out);
    assert!(report.contains("cells:    84"), "{report}");
    assert!(report.contains("perfect:  no"), "{report}");
    assert!(!report.contains("exit:     none"), "{report}");
    let spelled_out = mazewalk(&["generate", "--size", "12x7", "--seed", "3", "--loops", "0.2", "--exit"]);
    assert!(spelled_out.status.success(), "`generate` is `gen`: {}", stderr(&spelled_out));
    let out = mazewalk(&["gen", "--size", "0x5"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_walk_without_a_terminal_says_so_instead_of_breaking_anything() {
    let out = mazewalk(&[]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("needs a terminal"), "{}", stderr(&out));
    assert!(out.stdout.is_empty(), "nothing may reach stdout: {:?}", stdout(&out));
}

// bbA #2: `gen -o -` made a file named `-`, while `check -` and `render --png -` take `-` as standard
// input or output.
#[test]
fn gen_to_dash_writes_standard_output() {
    let dir = std::env::temp_dir().join(format!("mazewalk-gen-dash-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for format in ["cs559", "grid"] {
        let args = ["gen", "--size", "5x4", "--seed", "7", "--format", format];
        let plain = mazewalk(&args);
        let dash = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(args)
            .args(["-o", "-"])
            .current_dir(&dir)
            .output()
            .expect("run mazewalk");
        assert!(dash.status.success(), "{format}: {}", stderr(&dash));
        assert!(!plain.stdout.is_empty());
        assert_eq!(stdout(&dash), stdout(&plain), "{format}");
        assert!(!dir.join("-").exists(), "{format}: a file named `-`");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

// issue #13: a terminal that cannot take the full-screen walk is told so, not drawn on.
#[test]
fn a_dumb_or_unknown_terminal_is_told_clearly() {
    // bbA #6: an empty TERM was said to be unset
    for (term, says) in [(Some("dumb"), "TERM=dumb"), (Some(""), "TERM is empty"), (None, "TERM is unset")] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_mazewalk"));
        match term {
            Some(t) => cmd.env("TERM", t),
            None => cmd.env_remove("TERM"),
        };
        let out = cmd.output().expect("run mazewalk");
        assert_eq!(out.status.code(), Some(1), "TERM={term:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(says) && stderr(&out).contains("--force-terminal"), "{}", stderr(&out));
        assert!(out.stdout.is_empty());
    }
}

// bbA #7: a second maze file was taken for a subcommand ("the subcommand 'b.maze' cannot be used").
#[test]
fn a_second_maze_file_is_refused_as_one() {
    for args in [&["a.maze", "b.maze"][..], &["render", "a.maze", "b.maze"]] {
        let out = mazewalk(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains("one maze file at a time: `b.maze` is a second"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

// issue #13: `gen … | head` ends quietly, as other tools killed by SIGPIPE do; so does
// `render --png - | head -c 10` (it said "Broken pipe" and exited 1).
#[test]
fn a_reader_that_goes_away_ends_gen_and_render_quietly() {
    use std::io::Read;
    // Each writes far more than a pipe holds (64 KiB): a 600x300 picture is about 200 KB.
    for args in [&["gen", "--size", "400x400"][..], &["render", "--size", "600x300", "--png", "-"]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("run mazewalk");
        let mut head = [0u8; 10];
        child.stdout.take().expect("piped").read_exact(&mut head).expect("the first bytes");
        // The pipe's read end is dropped here: the next writes fail with EPIPE.
        let out = child.wait_with_output().expect("wait");
        assert_eq!(out.status.code(), Some(141), "{args:?}: {}", stderr(&out));
        assert!(out.stderr.is_empty(), "{args:?}: no message: {}", stderr(&out));
    }
}

// issue #13: with stdout closed, nothing claims success having written nothing.
#[test]
fn a_closed_stdout_is_an_error() {
    for args in [&["render"][..], &["check", "mazes/hand-drawn.grid"], &["gen", "--size", "3x3"]] {
        let out = Command::new("sh")
            .arg("-c")
            .arg("exec \"$0\" \"$@\" >&-")
            .arg(env!("CARGO_BIN_EXE_mazewalk"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("run sh");
        assert_eq!(out.status.code(), Some(1), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains("stdout is closed"), "{}", stderr(&out));
    }
    // `> /dev/null` is not closed.
    let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .arg("render")
        .stdout(std::process::Stdio::null())
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
}

// Red-team pass 8 (local side), finding 8: a stdout on /dev/null opened read-write (`1<>/dev/null`,
// Python's `subprocess.DEVNULL`, systemd's `StandardOutput=null`) was taken for a closed one, so
// `check` exited 1 for a good maze and a bad one alike, and `render` failed.
#[cfg(target_os = "linux")]
#[test]
fn dev_null_opened_read_write_is_an_open_stdout() {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-devnull-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.grid");
    std::fs::write(&bad, "mazewalk-grid 1\n\n###\n#@n\n###\n").unwrap();
    let bad = bad.to_str().unwrap();
    for (args, code) in [
        (&["check", "mazes/hand-drawn.grid"][..], 0),
        (&["check", bad], 65),
        (&["render", "mazes/hand-drawn.grid"], 0),
        (&["gen", "--size", "3x3"], 0),
    ] {
        let null = std::fs::OpenOptions::new().read(true).write(true).open("/dev/null").unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .stdout(null)
            .output()
            .expect("run mazewalk");
        assert_eq!(out.status.code(), Some(code), "{args:?}: {}", stderr(&out));
        assert!(!stderr(&out).contains("stdout is closed"), "{args:?}: {}", stderr(&out));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// issue #13: frame sizes past the documented maximum are refused before any memory is spent.
#[test]
fn render_refuses_frames_past_the_maximum() {
    for size in ["2000x2000", "1001x1000", "2001x10"] {
        let out = mazewalk(&["render", "--size", size, "--charset", "sextant"]);
        assert_eq!(out.status.code(), Some(2), "{size}: {}", stderr(&out));
    }
    assert!(
        mazewalk(&["render", "--size", "1000x1000", "--color", "none", "--charset", "ascii"])
            .status
            .success()
    );
}

#[test]
fn render_png_writes_the_frame_as_a_picture_of_its_cells() {
    let dir = std::env::temp_dir().join(format!("mazewalk-png-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("frame.png");
    let path_str = path.to_str().unwrap();
    let out = mazewalk(&["render", "--size", "40x12", "--color", "truecolor", "--png", path_str]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(out.stdout.is_empty(), "the picture instead of the text");
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, right after the signature and the chunk header.
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((width, height), (40 * 12, 12 * 24), "12×24 pixels a cell");
    // Written band by band: the whole image decodes, and shows the view (not one colour).
    let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes)).read_info().expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).expect("every row");
    assert_eq!((info.width, info.height, info.color_type), (width, height, png::ColorType::Rgb));
    let distinct: std::collections::HashSet<&[u8]> = pixels.chunks(3).collect();
    assert!(distinct.len() > 20, "{} colours", distinct.len());
    assert_ne!(pixels[..width as usize * 3], pixels[pixels.len() - width as usize * 3..], "ceiling vs floor");
    if std::path::Path::new("/dev/full").exists() {
        // A write that fails, even in the last buffered bytes, is an error, not a truncated picture.
        let full = mazewalk(&["render", "--size", "40x12", "--png", "/dev/full"]);
        assert_eq!(full.status.code(), Some(1), "{}", stderr(&full));
        assert!(stderr(&full).contains("/dev/full: cannot write"), "{}", stderr(&full));
    }
    let ascii = mazewalk(&["render", "--charset", "ascii", "--png", path_str]);
    assert_eq!(ascii.status.code(), Some(2), "ascii is text: {}", stderr(&ascii));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn render_outputs_go_to_standard_output_by_dash_one_at_a_time() {
    // `--png -`: the picture on standard output (a pipe here), whole.
    let out = mazewalk(&["render", "--size", "40x12", "--png", "-"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut reader = png::Decoder::new(std::io::Cursor::new(&out.stdout)).read_info().expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    assert_eq!(reader.next_frame(&mut pixels).expect("every row").width, 40 * 12);
    // `--depth-out -` beside a picture in a file: the depths on standard output, a line a row.
    let dir = std::env::temp_dir().join(format!("mazewalk-dash-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let picture = dir.join("frame.png");
    let picture = picture.to_str().unwrap();
    let out = mazewalk(&["render", "--size", "20x6", "--png", picture, "--depth-out", "-"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let csv = String::from_utf8(out.stdout).unwrap();
    assert_eq!(csv.lines().count(), 6, "{csv}");
    assert!(csv.lines().all(|line| line.split(',').count() == 20), "{csv}");
    assert!(csv.split([',', '\n']).any(|d| d.parse::<f32>().is_ok_and(|d| d > 0.0)), "{csv}");
    assert_eq!(&std::fs::read(picture).unwrap()[..4], b"\x89PNG");
    // Two outputs in one place: refused before anything is written.
    for (args, says) in [
        (&["--depth-out", "-"][..], "standard output already gets the frame"),
        (&["--png", "-", "--depth-out", "-"][..], "both write standard output"),
        (&["--png", picture, "--depth-out", picture][..], "both write"),
    ] {
        let out = mazewalk(&[&["render", "--size", "20x6"][..], args].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(says), "{args:?}: {}", stderr(&out));
        assert!(out.stdout.is_empty(), "{args:?}");
    }
    // A place the depths cannot go: refused before the frame is written (it was printed, then refused).
    let dir_str = dir.to_str().unwrap();
    let out = mazewalk(&["render", "--size", "20x6", "--depth-out", dir_str]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("cannot create"), "{}", stderr(&out));
    assert!(out.stdout.is_empty(), "{}", stdout(&out));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A maze that cannot be written says where: every write, not only the last flush (`gen -o
/// /dev/full` said only "No space left on device").
#[test]
fn gen_names_the_file_it_cannot_write() {
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    for format in ["cs559", "grid"] {
        let out = mazewalk(&["gen", "--size", "60x60", "--format", format, "-o", "/dev/full"]);
        assert_eq!(out.status.code(), Some(1), "{format}: {}", stderr(&out));
        assert!(stderr(&out).contains("/dev/full: cannot write"), "{format}: {}", stderr(&out));
    }
}

#[test]
fn a_server_whose_stdout_is_closed_keeps_serving() {
    // `mazewalk serve | head -1`, head gone: the banner cannot be written, the server goes on
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-serve-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["serve", "--open", "--listen", "127.0.0.1:0", "--host-key"])
        .arg(dir.join("key"))
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("start the server");
    drop(child.stdout.take()); // the read end closed before the banner is written
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let running = child.try_wait().unwrap().is_none();
    let _ = child.kill();
    let status = child.wait().unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(running, "the server ended: {status}");
}

/// A file may ask for any field of view a number holds: `render` draws what the walk starts with
/// (clamped to 10..=170°), as `check` accepts the file, where it used to refuse it as a usage error.
#[test]
fn a_files_field_of_view_out_of_range_is_clamped_as_the_walk_clamps_it() {
    let text = std::fs::read_to_string(maze("tiny.maze")).unwrap();
    assert!(text.contains("\n2 2 0 0 90"), "the viewer line of tiny.maze changed");
    let path = std::env::temp_dir().join(format!("mazewalk-fov-{}.maze", std::process::id()));
    for (fov, clamped) in [("5", "10"), ("179.5", "170")] {
        std::fs::write(&path, text.replace("\n2 2 0 0 90", &format!("\n2 2 0 0 {fov}"))).unwrap();
        let file = path.to_str().unwrap();
        assert!(mazewalk(&["check", file]).status.success(), "fov {fov}: check");
        let args = ["render", file, "--size", "40x12", "--color", "none", "--charset", "ascii"];
        let (as_file, explicit) = (mazewalk(&args), mazewalk(&[&args[..], &["--fov", clamped]].concat()));
        assert!(as_file.status.success(), "fov {fov}: {}", stderr(&as_file));
        assert_eq!(stdout(&as_file), stdout(&explicit), "fov {fov} renders as {clamped}");
    }
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn help_and_version_that_cannot_be_written_fail() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else { return };
    for args in [&["--help"][..], &["--version"], &["help", "serve"]] {
        let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(args)
            .stdout(full.try_clone().unwrap())
            .output()
            .expect("run mazewalk");
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(stderr(&out).contains("cannot write to stdout"), "{args:?}: {}", stderr(&out));
    }
    // Written, they succeed.
    assert!(mazewalk(&["--version"]).status.success());
}

#[test]
fn an_unwritable_stderr_changes_the_message_not_the_exit_code() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else { return };
    let run = |args: &[&str], stderr: std::fs::File| {
        Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(args)
            .stdout(std::process::Stdio::null())
            .stderr(stderr)
            .status()
            .expect("run mazewalk")
    };
    // The error cannot be told, but it is still the missing file's exit code, not a panic's (101).
    let missing = run(&["check", "/nonexistent/maze"], full.try_clone().unwrap());
    assert_eq!(missing.code(), Some(66));
    // --stats asked for numbers on stderr: not writing them is an error.
    assert_eq!(run(&["render", "--stats"], full).code(), Some(1));
}

/// The `mazewalk render …` commands README.md shows (in a code span, or a line of a code block),
/// each split into its arguments; not the synopsis (`[--at X,Y] …`) nor one that names a placeholder
/// (a word in capitals: FILE, N).
fn readme_render_commands() -> Vec<Vec<String>> {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let mut commands = Vec::new();
    let mut in_block = false;
    for line in readme.lines() {
        // (fences as CommonMark reads them: a block's ascii picture may have lines that start with
        // backticks, which close nothing unless they are backticks alone)
        let fence = line.trim_start();
        let run = fence.len() - fence.trim_start_matches('`').len();
        let toggles = if in_block { fence[run..].trim().is_empty() } else { !fence[run..].contains('`') };
        if run >= 3 && toggles {
            in_block = !in_block;
            continue;
        }
        let candidates: Vec<&str> =
            if in_block { vec![line.trim()] } else { line.split('`').skip(1).step_by(2).collect() };
        for text in candidates.into_iter().filter(|t| t.starts_with("mazewalk render")) {
            let words: Vec<String> = text.split_whitespace().map(str::to_owned).collect();
            let placeholder = |w: &String| {
                w.contains(['[', '…'])
                    || w.chars().any(|c| c.is_ascii_uppercase()) && !w.contains(char::is_lowercase)
            };
            if !words.iter().any(placeholder) {
                commands.push(words);
            }
        }
    }
    commands
}

// issue #39: README's `mazewalk render --size 100x30 --png` needed a file name. Every render command
// README shows runs as written, in an empty directory, where a user of tmux with
// `TERM=xterm-256color` and no COLORTERM would run it; each picture is written where it says, and
// where README shows that picture (`docs/images/…` of the same name) it is what the command draws.
#[test]
fn readme_render_commands_run_as_written() {
    let commands = readme_render_commands();
    let pictures = commands.iter().filter(|c| c.iter().any(|w| w == "--png")).count();
    assert!(commands.len() >= 6 && pictures >= 5, "README's render commands: {commands:?}");
    let dir = std::env::temp_dir().join(format!("mazewalk-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut compared = 0;
    for words in &commands {
        let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(&words[1..])
            .current_dir(&dir)
            .env("TERM", "xterm-256color")
            .env_remove("COLORTERM")
            .env_remove("NO_COLOR")
            .output()
            .unwrap();
        let command = words.join(" ");
        assert!(out.status.success(), "{command}: {}", stderr(&out));
        if let Some(at) = words.iter().position(|w| w == "--png") {
            let picture = std::fs::read(dir.join(&words[at + 1])).expect(&command);
            assert_eq!(&picture[..8], b"\x89PNG\r\n\x1a\n", "{command}");
            // README shows the picture its command draws, as the code draws it today.
            if let Some(shown) = docs_image(&words[at + 1]) {
                let committed = std::fs::read(&shown).unwrap();
                assert!(
                    png_pixels(&committed) == png_pixels(&picture),
                    "{} is not what `{command}` draws today: redraw it with that command",
                    shown.display()
                );
                compared += 1;
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(compared >= 5, "README's pictures compared with their commands: {compared}");
}

/// The picture of that file name under `docs/images/` (or a folder of it), if there is one.
fn docs_image(name: &str) -> Option<std::path::PathBuf> {
    let images = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/images");
    let mut dirs = vec![images];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().map(Result::unwrap) {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.file_name().is_some_and(|f| f == name) {
                return Some(path);
            }
        }
    }
    None
}

/// The pixels of a PNG.
fn png_pixels(bytes: &[u8]) -> Vec<u8> {
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut pixels).expect("every row");
    pixels
}

// issue #39: `render` draws the walk's view, a wide field's middle magnified (the foveated view);
// `--no-fovea` draws it with one scale across; a field of 60° or less (the lens's) is never warped.
#[test]
fn render_draws_the_walks_foveated_view_unless_no_fovea() {
    let dir = std::env::temp_dir().join(format!("mazewalk-fovea-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let depths = dir.join("depths.csv");
    // the frame and, on its middle row, the columns that see a wall 20 units or more away
    let frame = |extra: &[&str]| {
        let mut args = vec!["render", "--gen", "20x15", "--seed", "3", "--at", "78,6", "--heading", "180"];
        args.extend(["--size", "120x40", "--color", "none", "--charset", "ascii", "--depth-out"]);
        args.push(depths.to_str().unwrap());
        args.extend(extra);
        let out = mazewalk(&args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        let csv = std::fs::read_to_string(&depths).unwrap();
        let middle = csv.lines().nth(20).unwrap_or_default();
        let far = middle.split(',').filter(|v| v.parse::<f32>().is_ok_and(|d| d >= 20.0)).count();
        (stdout(&out), far)
    };
    let (foveated, plain) = (frame(&[]), frame(&["--no-fovea"]));
    assert_ne!(foveated.0, plain.0, "the middle magnified");
    // down a corridor eight cells long: its far cells over twice the columns
    assert!(foveated.1 > 2 * plain.1 && plain.1 > 0, "far columns: {} against {}", foveated.1, plain.1);
    assert_eq!(
        frame(&["--fov", "30"]),
        frame(&["--fov", "30", "--no-fovea"]),
        "a narrow field is never warped"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

// issue #39: `render --png` took its colour depth from TERM (256 colours in tmux without COLORTERM),
// not the picture's. A picture is in truecolor whatever the environment says, unless --color says.
#[test]
fn render_png_is_truecolor_unless_color_says_otherwise() {
    let picture = |color: Option<&str>, env: &[(&str, &str)]| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_mazewalk"));
        command
            .args(["render", "--size", "40x12", "--png", "-"])
            .args(color.map(|c| ["--color", c]).iter().flatten());
        command.env_remove("COLORTERM").env_remove("NO_COLOR").envs(env.iter().copied());
        let out = command.output().unwrap();
        assert!(out.status.success(), "{color:?} {env:?}: {}", stderr(&out));
        png_pixels(&out.stdout)
    };
    let truecolor = picture(Some("truecolor"), &[("TERM", "xterm-256color")]);
    let palette = picture(Some("256"), &[("COLORTERM", "truecolor")]);
    assert_ne!(truecolor, palette, "the premise: 256 colours look different");
    for env in
        [&[("TERM", "xterm-256color")][..], &[("TERM", "xterm")], &[("TERM", "dumb"), ("NO_COLOR", "1")]]
    {
        assert!(picture(None, env) == truecolor, "{env:?}: not the truecolor picture");
    }
    assert!(picture(Some("256"), &[("TERM", "xterm")]) == palette, "--color chooses");
}

/// `serve --record-dir` (issue #43): caps that could not hold one cast, or a cap without the
/// directory, are refused before listening as bad values (exit 2), and say why; so is a `--world`
/// that is not a Redis URL.
#[test]
fn serve_refuses_recording_caps_that_cannot_hold_a_cast() {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-record-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap(); // (DIR's folder: a missing one is refused first)
    let key = dir.join("key");
    let casts = dir.join("casts");
    let (key, casts) = (key.to_str().unwrap(), casts.to_str().unwrap());
    let serve = ["serve", "--open", "--listen", "127.0.0.1:0", "--host-key", key, "--no-records"];
    let cases: [(&[&str], i32, &str); 9] = [
        (&["--record-dir", casts, "--record-max-bytes", "512"], 2, "at least 1K"),
        (&["--record-dir", casts, "--record-max-per-address", "0"], 2, "--record-max-per-address"),
        (&["--record-dir", casts, "--record-max-files", "0"], 2, "--record-max-files"),
        (&["--record-max-files", "3"], 2, "--record-dir"),
        (&["--record-max-per-address", "3"], 2, "--record-dir"),
        (
            &["--record-dir", casts, "--record-max-bytes", "2M", "--record-max-total", "1M"],
            2,
            "not even one cast",
        ),
        (&["--record-max-bytes", "2M"], 2, "--record-dir"),
        // a shared world's URL that is not Redis's, or a CA for one without TLS: bad values too
        (&["--world", "http://localhost:6379"], 2, "--world http://localhost:6379"),
        (
            &[
                "--world",
                "redis://127.0.0.1:9",
                "--world-ca",
                concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"),
            ],
            2,
            "TLS",
        ),
    ];
    for (args, code, says) in cases {
        let out = mazewalk(&[&serve[..], args].concat());
        assert_eq!(out.status.code(), Some(code), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(says), "{args:?}: {}", stderr(&out));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// QA: a typo in `--records` or `--record-dir` must not make a tree of folders: a records file whose
/// folder is missing, or a DIR whose folder is missing, is refused before listening (exit 2), naming
/// the folder, and nothing is made; DIR itself (its folder there) is made, mode 0700.
#[test]
fn serve_makes_no_missing_folders_for_records_or_casts() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-folders-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let key = dir.join("key");
    let missing = dir.join("typo");
    let records = missing.join("deeper").join("r.sqlite");
    let casts = missing.join("casts");
    let (key, records, casts) = (key.to_str().unwrap(), records.to_str().unwrap(), casts.to_str().unwrap());
    // a taken port: a run that got past the checks ends at once (exit 1) rather than serving
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let listen = taken.local_addr().unwrap().to_string();
    let serve = ["serve", "--open", "--listen", &listen, "--host-key", key];
    let cases: [(&[&str], String); 2] = [
        (&["--records", records], missing.join("deeper").display().to_string()),
        (&["--no-records", "--record-dir", casts], missing.display().to_string()),
    ];
    for (args, names) in cases {
        let out = mazewalk(&[&serve[..], args].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        let says = format!("no folder {names} ");
        assert!(stderr(&out).contains(&says), "{args:?} names {names}: {}", stderr(&out));
        assert!(!missing.exists(), "{args:?}: nothing made");
    }
    // DIR itself is made when its folder is there (the taken port ends the run after that)
    let casts = dir.join("casts");
    let args = ["serve", "--open", "--listen", &listen, "--host-key", key, "--no-records", "--record-dir"];
    let out = mazewalk(&[&args[..], &[casts.to_str().unwrap()]].concat());
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(casts.is_dir(), "DIR made");
    assert_eq!(std::fs::metadata(&casts).unwrap().permissions().mode() & 0o777, 0o700);
    // red-team pass 10: a FIFO, a file or a dangling link at DIR said "File exists (os error 17)"
    let fifo = dir.join("fifo");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let file = dir.join("file");
    std::fs::write(&file, b"x").unwrap();
    let link = dir.join("link");
    std::os::unix::fs::symlink(dir.join("nowhere"), &link).unwrap();
    for (at, says) in
        [(fifo, "a FIFO is there"), (file, "a file is there"), (link, "a symbolic link to no folder")]
    {
        let out = mazewalk(&[&args[..], &[at.to_str().unwrap()]].concat());
        assert_eq!(out.status.code(), Some(2), "{at:?}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(says) && stderr(&out).contains("not a folder"),
            "{at:?}: {}",
            stderr(&out)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `records --world` with a URL that is not Redis's, or a CA for a world without TLS: a bad flag
/// value (exit 2), said before anything is read, as `serve` says it.
#[test]
fn records_refuses_a_world_url_that_is_not_redis() {
    let ca = concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml");
    let cases: [&[&str]; 2] = [
        &["records", "--builtin", "--world", "http://localhost:6379"],
        &["records", "--builtin", "--world", "redis://127.0.0.1:9", "--world-ca", ca],
    ];
    for args in cases {
        let out = mazewalk(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains("--world"), "{args:?}: {}", stderr(&out));
    }
}

/// `records --world` or `--export-run` without a maze named: a usage error (exit 2, as README's exit
/// codes say), said before any records file or Redis is opened (neither exists here).
#[test]
fn records_that_need_a_maze_say_so_as_a_usage_error() {
    let cases: [&[&str]; 2] = [
        &["records", "--world", "redis://127.0.0.1:9"],
        &["records", "--records", "/nonexistent/r.sqlite", "--export-run", "x.run"],
    ];
    for args in cases {
        let out = mazewalk(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains("name the maze"), "{args:?}: {}", stderr(&out));
    }
}

/// Issue #39: the walk's look-ahead lens (`z`) is `render --fov 30`'s camera. With the lens on, the
/// walk's view (the screen less its HUD row, map off, chalk off) at a pose down a long corridor is,
/// byte for byte, the frame `render --fov 30` prints there, but for the rows where the lens numbers
/// the floor's cell lines on its left edge (a digit there, the rest of the row as rendered is not
/// compared: the digit's colours change the row's codes); with the lens off it is not.
#[test]
fn the_walks_look_ahead_view_is_render_fov_40s_frame() {
    use mazewalk_maze::generate::{GenOptions, generate};
    use mazewalk_render::{Charset, RenderOptions};
    use mazewalk_term::encoder::ansi_lines;
    use mazewalk_term::frame::{ColorDepth, Frame};
    use mazewalk_term::input::{Key, KeyPhase};
    use mazewalk_walk::screen::{Hud, Screen, draw};
    use mazewalk_walk::state::stand;
    use mazewalk_walk::{App, MapMode};

    let (cols, rows) = (120, 40);
    let (at, heading) = (glam::Vec2::new(34.0, 6.0), 0.0);
    // the place as `render` flags, then the field or the lens
    let render = |lens: &[&str]| {
        let place = ["render", "--gen", "20x15", "--seed", "5", "--at", "34,6", "--heading", "0"];
        let look = ["--size", "120x39", "--color", "256", "--charset", "half"];
        mazewalk(&[&place[..], &look[..], lens].concat())
    };
    let out = render(&["--fov", "30"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));

    let maze = generate(&GenOptions::walk(20, 15, 5)).unwrap();
    let options =
        RenderOptions { charset: Charset::Half, color_depth: ColorDepth::Ansi256, ..Default::default() };
    let mut app = App::new(maze, options, 0.0).unwrap();
    let stands = stand(app.maze(), at).unwrap();
    (app.camera.position, app.cell, app.camera.yaw_deg) = (stands.pos, stands.cell, heading);
    (app.map, app.chalk) = (MapMode::Off, false);
    // the view's lines as `ansi_lines` prints them, and the rows with a digit on the left edge
    let view = |app: &App| {
        let mut frame = Frame::new(cols, rows);
        draw(app, &mut Screen::default(), &mut frame, &Hud::default());
        let mut view = Frame::new(cols, rows - 1);
        for y in 0..rows - 1 {
            for x in 0..cols {
                view.set(x, y, *frame.get(x, y).unwrap());
            }
        }
        let mut bytes = Vec::new();
        ansi_lines(&view, &mut bytes);
        let marked: Vec<usize> =
            (0..rows - 1).filter(|&y| view.get(0, y).unwrap().ch.is_ascii_digit()).collect();
        (bytes, marked)
    };
    let lines = |bytes: &[u8]| bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect::<Vec<_>>();
    let rendered = lines(&out.stdout);
    app.key(Key::Char('z'), KeyPhase::Press, 1.0);
    assert!(app.look_ahead());
    let (walked, marked) = view(&app);
    assert!(marked.len() >= 2, "the lens numbers the cell lines down the corridor: {marked:?}");
    let walked = lines(&walked);
    assert_eq!(walked.len(), rendered.len());
    for (y, (walk, render)) in walked.iter().zip(&rendered).enumerate() {
        assert!(
            marked.contains(&y) || walk == render,
            "row {y}: the walk's look-ahead view differs from render --fov 30's frame"
        );
    }
    // `render --look-ahead`: the lens as the walk shows it, its marks too, on every row
    let lens = render(&["--look-ahead"]);
    assert_eq!(lens.status.code(), Some(0), "{}", stderr(&lens));
    assert_eq!(lines(&lens.stdout), walked, "render --look-ahead is the walk's lens, marks and all");
    app.key(Key::Char('z'), KeyPhase::Press, 2.0);
    let (wide, marked) = view(&app);
    assert!(wide != out.stdout && marked.is_empty(), "without the lens the walk's view is the wide one");
}

/// QA finding 8: `--save-run` to a path that cannot be written is refused at the start, as `--record`
/// is (it used to fail after the whole walk, losing the run); a path that can is left as it was when
/// the walk leaves no run (here: no terminal to walk in).
#[cfg(unix)]
#[test]
fn save_run_to_a_path_that_cannot_be_written_is_refused_at_the_start() {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-saverun-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tiny = maze("tiny.maze");
    let walk = |run: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args([&tiny, "--save-run", run.to_str().unwrap()])
            .env("TERM", "xterm-256color")
            .stdin(std::process::Stdio::null())
            .output()
            .expect("run mazewalk")
    };
    for (run, says) in [
        (dir.join("no-such-dir").join("mine.run"), "No such file or directory"),
        (dir.clone(), "not a regular file"),
    ] {
        let out = walk(&run);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{}: {err}", run.display());
        assert!(err.contains("cannot write the run") && err.contains(says), "{}: {err}", run.display());
        assert!(!err.contains("needs a terminal"), "refused before looking for a terminal: {err}");
    }
    // Writable: the walk goes on to its own refusal (no terminal), and leaves no file behind, nor
    // touches one that was there.
    let new = dir.join("new.run");
    let out = walk(&new);
    assert!(String::from_utf8_lossy(&out.stderr).contains("needs a terminal"), "{out:?}");
    assert!(!new.exists(), "an empty run file was left behind");
    let old = dir.join("old.run");
    std::fs::write(&old, b"an older run").unwrap();
    let out = walk(&old);
    assert!(String::from_utf8_lossy(&out.stderr).contains("needs a terminal"), "{out:?}");
    assert_eq!(std::fs::read(&old).unwrap(), b"an older run");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Red-team pass 8 (local side), finding 7: `--save-run` checked the path's `metadata` (which
/// follows links) and then opened it through a symbolic link put there, so the run replaced the file
/// the link named. It is now refused at the start, as `--record` refuses one.
#[cfg(unix)]
#[test]
fn save_run_refuses_a_symbolic_link() {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-saverun-link-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "important contents\n").unwrap();
    let link = dir.join("mine.run");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&victim, &link).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args([&maze("tiny.maze"), "--save-run", link.to_str().unwrap()])
        .env("TERM", "xterm-256color")
        .stdin(std::process::Stdio::null())
        .output()
        .expect("run mazewalk");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("cannot write the run") && err.contains("a symbolic link, not followed"), "{err}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "important contents\n");
    let _ = std::fs::remove_dir_all(&dir);
}

/// QA finding 9: the loader's advice for a pipe (`<(…)`) led to `-`, which the walk refused for
/// want of a terminal: it now says what works, and so does the walk given `-`.
#[cfg(unix)]
#[test]
fn the_advice_for_a_piped_maze_is_no_dead_end() {
    use std::io::Write as _;
    let grid = mazewalk(&["gen", "--size", "6x4", "--seed", "2", "--exit", "--format", "grid"]).stdout;
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .arg("-")
        .env("TERM", "xterm-256color")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run mazewalk");
    let _ = child.stdin.take().unwrap().write_all(&grid); // (it may refuse before reading)
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("reads its keys from standard input") && err.contains("save it to a file"), "{err}");
    // `render -` still reads the pipe
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["render", "-", "--size", "20x6"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run mazewalk");
    child.stdin.take().unwrap().write_all(&grid).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // a FIFO: the loader's advice starts with what works everywhere
    let out = mazewalk(&["check", "/dev/zero"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not a regular file (a device); save it to a file"), "{err}");
}

/// A ghost or a replay run named by a FIFO, a device or a directory is refused as a maze would be
/// (exit 66, "not a regular file"), at once: a FIFO with no writer hung forever, and /dev/zero was
/// read up to the size limit and called too long.
#[cfg(unix)]
#[test]
fn a_run_that_is_not_a_regular_file_is_refused_at_once() {
    use std::time::Duration;
    let (dir, fifo) = dir_with_fifo("runfifo", "run.fifo");
    let tiny = maze("tiny.maze");
    let fifo = fifo.to_str().unwrap();
    let dir_s = dir.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["--ghost", fifo, &tiny], "a FIFO"),
        (&["replay", fifo, &tiny], "a FIFO"),
        (&["--ghost", "/dev/zero", &tiny], "a device"),
        (&["replay", "/dev/zero", &tiny], "a device"),
        (&["--ghost", dir_s, &tiny], "a directory"),
    ];
    for (args, what) in cases {
        let mut command = Command::new(env!("CARGO_BIN_EXE_mazewalk"));
        command.args(args).env("TERM", "xterm-256color");
        let Some((status, err)) = finished_within(&mut command, Duration::from_secs(30)) else {
            panic!("{args:?}: still waiting after 30 s")
        };
        assert_eq!(status.code(), Some(66), "{args:?}: {err}");
        assert!(err.contains(&format!("not a regular file ({what})")), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `check` says when the exit cannot be reached from where the walk starts (QA: it said `exit: cell
/// 1`, and only `perfect: no` hinted), in both formats; a reachable exit gets no such note. The
/// summary is still a success: `check` promises a summary or the error.
#[test]
fn check_says_when_the_exit_cannot_be_reached() {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-unreachable-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tiny = std::fs::read_to_string(maze("tiny.maze")).unwrap();
    let (open, shut) = ("1 4 0 1 0 0.5 0.5 0.5", "1 4 0 1 1 0.5 0.5 0.5");
    assert!(tiny.lines().any(|l| l == open), "the premise: tiny.maze's inner portal");
    assert!(tiny.lines().any(|l| l == "exit 1"), "the premise: tiny.maze's exit, beyond the portal");
    let cases = [
        ("sealed.maze", tiny.replace(open, shut), Some("cell 1 (not reachable")),
        ("open.maze", tiny.clone(), None),
        (
            "sealed.grid",
            "mazewalk-grid 1\n\n#######\n#@.##E#\n#######\n".into(),
            Some("cell 2 (not reachable"),
        ),
        ("walled.grid", "mazewalk-grid 1\n#####\n#@#E#\n#####\n".into(), Some("(not reachable")),
        ("open.grid", "mazewalk-grid 1\n#####\n#@.E#\n#####\n".into(), None),
    ];
    for (name, text, note) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let out = mazewalk(&["check", path.to_str().unwrap()]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        let report = stdout(&out);
        let exit = report.lines().find(|l| l.trim_start().starts_with("exit:")).expect("an exit line");
        match note {
            Some(note) => assert!(exit.contains(note), "{name}: {report}"),
            None => assert!(!exit.contains("not reachable"), "{name}: {report}"),
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Red-team pass 9: `--world-ca FILE` was read whole, whatever it named: `serve` and `records` with
/// `/dev/zero` grew by gigabytes, and with a FIFO waited before listening, for good. Now only a
/// regular file of at most 1 MiB is read; a FIFO, a device or a larger file is refused at once
/// (exit 1, as a host key that cannot be used), naming the flag. (Run under a 1 GiB address-space
/// limit, so that a reader without a bound fails here rather than taking the machine's memory.)
#[cfg(unix)]
#[test]
fn a_world_ca_that_is_not_a_small_regular_file_is_refused_at_once() {
    use std::time::Duration;
    let (dir, fifo) = dir_with_fifo("worldca", "ca.fifo");
    let big = dir.join("big.pem");
    std::fs::File::create(&big).unwrap().set_len((1 << 20) + 1).unwrap(); // sparse: nothing written
    let key = dir.join("key");
    let (fifo, big, key) = (fifo.to_str().unwrap(), big.to_str().unwrap(), key.to_str().unwrap());
    // (nothing listens on port 9: were a CA read, the commands would fail on the connection instead)
    let world = "rediss://127.0.0.1:9";
    let serve = ["serve", "--open", "--listen", "127.0.0.1:0", "--host-key", key, "--world", world];
    let records = ["records", "--builtin", "--world", world];
    let mut cases: Vec<(Vec<&str>, &str)> = Vec::new();
    for command in [&serve[..], &records[..]] {
        for (file, says) in [
            (fifo, "not a regular file (a FIFO)"),
            ("/dev/zero", "not a regular file (a device)"),
            (big, "larger than 1024 KiB"),
        ] {
            cases.push(([command, &["--world-ca", file]].concat(), says));
        }
    }
    for (args, says) in cases {
        let mut command = Command::new("sh");
        command.args(["-c", "ulimit -v 1048576 && exec \"$0\" \"$@\"", env!("CARGO_BIN_EXE_mazewalk")]);
        command.args(&args).env("XDG_STATE_HOME", &dir);
        let Some((status, err)) = finished_within(&mut command, Duration::from_secs(30)) else {
            panic!("{args:?}: still waiting after 30 s")
        };
        assert_eq!(status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("--world-ca") && err.contains(says), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// Red-team pass 11: `gen -o`, `render --png` and `--depth-out` at a FIFO nobody reads waited for a
// reader for ever; a FIFO somebody reads (a pipe, as `-o >(gzip > m.gz)` makes) still gets it all.
#[cfg(unix)]
#[test]
fn an_output_at_a_fifo_nobody_reads_is_refused_at_once() {
    use std::time::Duration;
    let (dir, fifo) = dir_with_fifo("outfifo", "out.fifo");
    let path = fifo.to_str().unwrap();
    for args in [
        &["gen", "--size", "5x5", "-o", path][..],
        &["render", "--png", path, "--color", "truecolor"],
        &["render", "--depth-out", path],
    ] {
        let mut command = Command::new(env!("CARGO_BIN_EXE_mazewalk"));
        command.args(args);
        let Some((status, err)) = finished_within(&mut command, Duration::from_secs(10)) else {
            panic!("{args:?}: still waiting for a reader after 10 s")
        };
        assert_eq!(status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(path) && err.contains("a FIFO nobody reads"), "{args:?}: {err}");
    }
    // With a reader: the whole maze, as on standard output.
    let reader = std::thread::spawn({
        let fifo = fifo.clone();
        move || std::fs::read_to_string(fifo).unwrap()
    });
    let mut command = Command::new(env!("CARGO_BIN_EXE_mazewalk"));
    command.args(["gen", "--size", "5x5", "--format", "grid", "-o", path]);
    let mut written = None;
    for _ in 0..200 {
        // (the reader's open may come a moment after this one: until then the FIFO has no reader)
        let (status, err) = finished_within(&mut command, Duration::from_secs(10)).expect("no wait");
        if status.success() {
            written = Some(err);
            break;
        }
        assert!(err.contains("a FIFO nobody reads"), "{err}");
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(written.is_some(), "the reader never opened the FIFO");
    let expected = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["gen", "--size", "5x5", "--format", "grid"])
        .output()
        .unwrap()
        .stdout;
    assert_eq!(reader.join().unwrap().as_bytes(), expected, "the reader got the whole maze");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `command` run with no input and its output dropped: its exit status and standard error once it
/// ends, or `None` (killed) if it is still running after `limit`.
fn finished_within(
    command: &mut Command,
    limit: std::time::Duration,
) -> Option<(std::process::ExitStatus, String)> {
    use std::process::Stdio;
    let mut child =
        command.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("run it");
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    Some((status, err))
}

/// A test's own folder (`mazewalk-cli-TAG-PID` in the temporary directory) holding a FIFO `name`: the
/// folder and the FIFO's path.
#[cfg(unix)]
fn dir_with_fifo(tag: &str, name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("mazewalk-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join(name);
    let made = Command::new("mkfifo").arg(&fifo).status().expect("run mkfifo");
    assert!(made.success(), "mkfifo {}", fifo.display());
    (dir, fifo)
}

/// Red-team pass 15: a negative number given to a flag is that flag's usage error, named (it was
/// "unexpected argument '-1' found", with a tip to write `-- -1`, which makes it a maze file).
#[test]
fn a_negative_number_is_refused_by_its_flag() {
    let cases: &[(&[&str], &str)] = &[
        (&["gen", "--size", "5x5", "--seed", "-1"], "'--seed <SEED>'"),
        (&["gen", "--size", "-1x5"], "'--size <SIZE>': each side must be an integer in 1..=1000, found `-1`"),
        (&["render", "--size", "-5x10"], "'--size <COLSxROWS>'"),
        (&["render", "--repeat", "-1"], "'--repeat <N>'"),
        (&["check", "--max-file-size", "-1", "x.maze"], "'--max-file-size <BYTES>'"),
        (&["--gen", "-3x3"], "'--gen <WxH>'"),
        (&["serve", "--max-players", "-1"], "'--max-players <N>'"),
    ];
    for (args, needle) in cases {
        let out = mazewalk(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(needle), "{args:?}: expected `{needle}` in: {}", stderr(&out));
    }
}
