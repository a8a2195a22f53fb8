//! Issue #40, low: `mazewalk records` printed the player names in the records file as they were, so a
//! file holding OSC 52 (the clipboard), OSC 0 (the window title), `ESC[2J` or U+202E acted on the
//! terminal of whoever listed it. Each name is now shown as SSH user names are cleaned. Red-team
//! pass 8 (local side), finding 3: paths with escapes are quoted too.
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
