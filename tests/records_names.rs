//! Issue #40, low: `mazewalk records` printed the player names in the records file as they were, so a
//! file holding OSC 52 (the clipboard), OSC 0 (the window title), `ESC[2J` or U+202E acted on the
//! terminal of whoever listed it. Each name is now shown as SSH user names are cleaned. Red-team
//! pass 8 (local side): paths with escapes are quoted too (finding 3), and `--export-run` writes no
//! file through a symbolic link (finding 7).
#![cfg(all(unix, feature = "serve"))]

use std::process::Command;

use mazewalk_maze::ContentHash;
use mazewalk_serve::records::{Finish, Sqlite, SqliteOptions, Store};

#[test]
fn records_prints_hostile_names_cleaned() {
    let dir = std::env::temp_dir().join(format!("mazewalk-records-names-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let path = dir.join("records.sqlite");
    let hostile = ["\x1b]52;c;ZXZpbA==\x07mallory", "\x1b]0;pwned\x07eve", "\x1b[2Jwipe", "\u{202e}evil"];
    {
        let (mut db, _) = Sqlite::open(&path, SqliteOptions::default()).expect("open the records");
        for (i, player) in hostile.iter().enumerate() {
            let finish = Finish {
                maze: ContentHash([3; 32]),
                maze_name: "x.maze".into(),
                player: (*player).into(),
                seconds: 10.0 + i as f64,
                at: 1_800_000_000,
                run: None,
            };
            db.record(&finish).expect("keep a finish");
        }
    }
    let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["records", "--records"])
        .arg(&path)
        .output()
        .expect("mazewalk records");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8(out.stdout).expect("UTF-8");
    let raw = |c: char| {
        c.is_control() && c != '\n' || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}')
    };
    assert!(!stdout.chars().any(raw), "{stdout:?}");
    for name in ["52cZXZpbAmallory", "0pwnedeve", "2Jwipe", "evil"] {
        assert!(stdout.contains(name), "{name} in {stdout:?}");
    }
}

/// Finding 3: `records --records PATH` printed PATH raw in its errors: a file named with
/// `ESC ] 2 ; pwn BEL` in it set the terminal's title.
#[test]
fn records_quotes_a_path_holding_escapes() {
    let dir = mazewalk_testkit::scratch::Scratch::new("records-path");
    let path = dir.join("e\x1b]2;pwn\x07.sqlite");
    let out = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["records", "--records"])
        .arg(&path)
        .output()
        .expect("mazewalk records");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains('\x1b') && !stderr.contains('\x07'), "{stderr:?}");
    assert!(stderr.contains("e\\u{1b}]2;pwn\\u{7}.sqlite: the database cannot be opened"), "{stderr:?}");
}

/// Finding 7: `records --export-run … FILE` wrote with `std::fs::write`, which follows a symbolic
/// link put at FILE and replaces the file it names. It is refused now, as `--save-run` and
/// `--record` refuse one; a plain file is written (and one already there replaced).
#[test]
fn export_run_refuses_a_symbolic_link() {
    use mazewalk_walk::run::{Pose, Run};
    let dir = mazewalk_testkit::scratch::Scratch::new("export-link");
    let db = dir.join("records.sqlite");
    let maze = mazewalk_maze::builtin().expect("the built-in maze").content_hash();
    // (2 s at 10 samples a second, both ends)
    let samples = (0..=20)
        .map(|k| Pose { position: glam::Vec2::new(1.0 + 0.1 * k as f32, 1.0), yaw_deg: 0.0, pitch_deg: 0.0 })
        .collect();
    let run = Run { maze, holder: "ada".into(), millis: 2000, samples };
    {
        let (mut store, _) = Sqlite::open(&db, SqliteOptions::default()).expect("open the records");
        let finish = Finish {
            maze,
            maze_name: "built-in maze".into(),
            player: "ada".into(),
            seconds: 2.0,
            at: 1_800_000_000,
            run: Some(run.encode().expect("encode")),
        };
        store.record(&finish).expect("keep a finish");
    }
    let export = |to: &std::path::Path| {
        Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .args(["records", "--builtin", "--records"])
            .arg(&db)
            .arg("--export-run")
            .arg(to)
            .output()
            .expect("mazewalk records --export-run")
    };
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "important contents\n").unwrap();
    let link = dir.join("best.run");
    std::os::unix::fs::symlink(&victim, &link).unwrap();
    let out = export(&link);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("a symbolic link, not followed"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "important contents\n");
    // a file: written, its old contents replaced
    let file = dir.join("mine.run");
    std::fs::write(&file, "x".repeat(10_000)).unwrap();
    let out = export(&file);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read(&file).unwrap(), run.encode().unwrap(), "the stored run, and only it");
}
