//! Issue #43, end to end: `mazewalk serve --record-dir DIR` (the built binary) records each player's
//! session as an asciicast v2 file; the player is the real OpenSSH client (`ssh -tt` in a
//! pseudo-terminal read by a `vt100` emulator, `tests/common`). Loopback only; every wait has a
//! deadline.
//!
//! Checks: the player's HUD says `recorded`; after it quits, one cast in DIR, named after it and
//! readable by the host only; it parses as asciicast v2 (header with the size, `TERM` and colour
//! depth; every event `[time, code, data]`, times in order; the resize as an `"r"` event); its
//! output is, byte for byte, what the client's terminal received; replayed into a terminal emulator
//! it ends on the screen the player saw last, before the goodbye; the real `asciinema cat` prints
//! those very bytes (where installed). A tiny `--record-max-bytes` stops
//! the cast at the cap, still whole lines, said in the log, and the game goes on.
#![cfg(unix)]

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::{Player, Scratch, Server, hud_row, nz, playing};

/// A corridor east from the start, and at its end a passage south (no exit: no clock ticking on
/// the HUD, so a screen holds still once the walk stops).
const CORRIDOR_AND_BEND: &str =
    "mazewalk-grid 1\ntile 4\nfacing east\n\n#######\n#@....#\n####..#\n####..#\n####..#\n#######\n";

/// Every cell of the screen, as it looks ([`common::looks`]).
fn whole(screen: &vt100::Screen) -> common::Cells {
    common::looks(screen, 0..screen.size().0.get())
}

/// The casts in `dir`, by name.
fn casts(dir: &Path) -> Vec<PathBuf> {
    let mut casts: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| entries.filter_map(|e| Some(e.ok()?.path())).collect())
        .unwrap_or_default();
    casts.retain(|p| p.extension().is_some_and(|e| e == "cast"));
    casts.sort();
    casts
}

/// Waits until `dir` holds one cast whose text satisfies `done` (it is written on a thread of its
/// own, after the player's goodbye), and returns its path and text.
fn wait_cast(dir: &Path, done: impl Fn(&str) -> bool) -> (PathBuf, String) {
    let deadline = Instant::now() + common::TIMEOUT;
    loop {
        if let [cast] = &casts(dir)[..]
            && let Ok(text) = std::fs::read_to_string(cast)
            && done(&text)
        {
            return (cast.clone(), text);
        }
        assert!(Instant::now() < deadline, "no finished cast in {}: {:?}", dir.display(), casts(dir));
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The cast's lines, parsed: the header, then the events as (time, code, data); panics on a line
/// that is not asciicast v2.
fn parse(text: &str) -> (serde_json::Value, Vec<(f64, String, String)>) {
    let mut lines = text.lines();
    let header: serde_json::Value =
        serde_json::from_str(lines.next().expect("a header")).expect("JSON header");
    assert_eq!(header["version"], 2, "{header}");
    let events = lines
        .map(|line| {
            let (time, code, data): (f64, String, String) =
                serde_json::from_str(line).unwrap_or_else(|e| panic!("not an event ({e}): {line}"));
            (time, code, data)
        })
        .collect();
    (header, events)
}

#[test]
fn a_players_session_is_recorded_and_replays_to_the_screen_it_showed() {
    let scratch = Scratch::new("record");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let dir = scratch.join("casts");
    let args = ["--open", "--record-dir", dir.to_str().expect("UTF-8"), maze.to_str().expect("UTF-8")];
    let server = Server::start(&scratch, &args);

    let mut alice = Player::connect(server.port, None, "alice", 100, 30);
    alice.wait_for("alice's game, told it is recorded", |s, _| {
        playing(s, &[]) && hud_row(s).contains("recorded")
    });
    alice.send(b"ww.");
    std::thread::sleep(Duration::from_millis(300));
    alice.resize(90, 28);
    alice.wait_for("the game at 90x28", |s, _| playing(s, &[]) && hud_row(s).trim_end().len() > 60);
    alice.send(b"w");
    // Still for a while: the last frame has arrived (no clock on the HUD: nothing else changes).
    std::thread::sleep(Duration::from_millis(800));
    let last = alice.read(whole);
    alice.send(b"q");
    assert!(alice.wait_exit().success(), "q ends the game with 0");

    let (path, text) = wait_cast(&dir, |text| text.contains("Thanks for walking."));
    let name = path.file_name().and_then(|n| n.to_str()).expect("a UTF-8 name");
    assert!(name.starts_with("mazewalk-") && name.ends_with("-alice.cast"), "{name}");
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&path).expect("the cast").permissions().mode();
        assert_eq!(mode & 0o077, 0, "the cast is readable by others: {mode:o}");
    }
    let (header, events) = parse(&text);
    assert_eq!((header["width"].as_u64(), header["height"].as_u64()), (Some(100), Some(30)), "{header}");
    assert_eq!(header["env"]["TERM"], "xterm-256color", "{header}");
    assert_eq!(header["mazewalk"]["color_depth"], "256", "{header}");
    assert!(events.windows(2).all(|w| w[0].0 <= w[1].0), "times go back");
    assert!(events.iter().all(|(_, code, _)| ["o", "r", "m"].contains(&code.as_str())), "unknown codes");
    assert!(events.iter().any(|(_, code, data)| code == "r" && data == "90x28"), "no resize event");

    // Byte for byte what the client's terminal received (ssh adds nothing in between).
    let recorded: Vec<u8> =
        events.iter().filter(|(_, code, _)| code == "o").flat_map(|(_, _, data)| data.bytes()).collect();
    let raw = alice.raw();
    let start = raw
        .windows(64)
        .position(|w| w == &recorded[..64])
        .expect("the cast's first bytes in what the client got");
    assert!(raw[start..].starts_with(&recorded), "the cast differs from what the client got");
    // The real asciinema reads it and prints those very bytes.
    if let Some(printed) = mazewalk_testkit::asciinema::cat(&path) {
        assert!(
            printed == recorded,
            "asciinema cat printed {} bytes, not the {} recorded",
            printed.len(),
            recorded.len()
        );
    }

    // Replayed into an emulator of the recorded size, resized as recorded: just before the goodbye
    // (which leaves the alternate screen) it shows what the player saw last.
    let mut replay = vt100::Parser::new(nz(30), nz(100), 0);
    let mut before_goodbye = None;
    for (_, code, data) in &events {
        match code.as_str() {
            "r" => {
                let (cols, rows) = data.split_once('x').expect("COLSxROWS");
                let size = |n: &str| nz(n.parse().expect("a number"));
                replay.screen_mut().set_size(size(rows), size(cols));
            }
            "o" => {
                if data.contains("\x1b[?1049l") && before_goodbye.is_none() {
                    before_goodbye = Some(whole(replay.screen()));
                }
                replay.process(data.as_bytes());
            }
            _ => {}
        }
    }
    let replayed = before_goodbye.expect("the goodbye leaves the alternate screen");
    assert_eq!(replayed.len(), last.len(), "rows");
    let differ = replayed.iter().zip(&last).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} rows differ between the replayed cast and the player's screen");
    assert!(replay.screen().contents().contains("Thanks for walking."), "the goodbye");
}

#[test]
fn a_tiny_record_max_bytes_stops_the_cast_at_the_cap() {
    let scratch = Scratch::new("recordcap");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let dir = scratch.join("casts");
    let dir_arg = dir.to_str().expect("UTF-8");
    let args = ["--open", "--record-dir", dir_arg, "--record-max-bytes", "8K", maze.to_str().expect("UTF-8")];
    let server = Server::start(&scratch, &args);

    let mut bob = Player::connect(server.port, None, "bob", 100, 30);
    bob.wait_for("bob's game", |s, _| playing(s, &[]) && hud_row(s).contains("recorded"));
    for _ in 0..6 {
        bob.send(b".");
        std::thread::sleep(Duration::from_millis(150));
    }
    server.wait_log("reached its cap", 1);
    // The game goes on past the cap.
    bob.send(b"w");
    std::thread::sleep(Duration::from_millis(200));
    bob.send(b"q");
    assert!(bob.wait_exit().success(), "q ends the game with 0");
    bob.wait_for("goodbye", |s, _| !s.alternate_screen() && s.contents().contains("Thanks for walking."));

    let (path, text) = wait_cast(&dir, |_| true);
    let size = std::fs::metadata(&path).expect("the cast").len();
    assert!(size <= 8 * 1024, "{size} bytes, over the cap");
    assert!(size > 8 * 1024 - 2000, "{size} bytes: stopped long before the cap");
    assert!(text.ends_with('\n'), "a cut line");
    let (header, events) = parse(&text); // every line whole and valid
    assert_eq!(header["width"], 100);
    assert!(!events.is_empty());
    assert!(!text.contains("Thanks for walking."), "written past the cap");
}

/// Red-team pass 17: a player's `TERM` (the pty request's) and `COLORTERM` (an environment request)
/// are the client's to choose, and went into the cast's header with serde_json's escaping alone,
/// which leaves C1 controls and bidi overrides raw: a host reading the cast with `head` had its
/// terminal take U+009B for CSI. Here a stock `ssh` sends both; the header says what it sent, with
/// none of them raw in the file.
#[test]
fn a_players_terminal_names_reach_the_casts_header_escaped() {
    let scratch = Scratch::new("recordterm");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let dir = scratch.join("casts");
    let args = ["--open", "--record-dir", dir.to_str().expect("UTF-8"), maze.to_str().expect("UTF-8")];
    let server = Server::start(&scratch, &args);

    let hostile = "xterm-256color\u{9b}31m\u{202e}gnp\u{61c}\u{2028}\"q\\\u{7f}";
    let env = [("TERM", hostile), ("COLORTERM", hostile)];
    let mut mallory = Player::connect_sending(None, server.port, None, "mallory", (100, 30), &env);
    mallory.wait_for("mallory's game, recorded", |s, _| playing(s, &[]) && hud_row(s).contains("recorded"));
    mallory.send(b"q");
    assert!(mallory.wait_exit().success(), "q ends the game with 0");

    let (_, text) = wait_cast(&dir, |text| text.contains("Thanks for walking."));
    let raw: Vec<char> = text.chars().filter(|&c| c != '\n' && mazewalk_maze::unseen(c)).collect();
    let head: String = text.chars().take(400).collect();
    assert!(raw.is_empty(), "raw {raw:?} in the cast, which starts:\n{head}");
    let (header, _) = parse(&text);
    assert_eq!((&header["env"]["TERM"], &header["env"]["COLORTERM"]), (&hostile.into(), &hostile.into()));
}

/// The red team's HIGH finding: idle players from one address once made the server delete every
/// earlier finished cast (each newcomer's whole `--record-max-bytes` was paid for by deleting them).
/// Now finished casts go only for bytes written, and one address has at most
/// `--record-max-per-address` (default 2) recordings at once: the others play unrecorded.
#[test]
fn idle_players_from_one_address_delete_no_finished_cast() {
    let scratch = Scratch::new("recordwipe");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let dir = scratch.join("casts");
    std::fs::create_dir_all(&dir).expect("the casts' folder");
    for t in 1..=12 {
        std::fs::write(dir.join(format!("mazewalk-{t:011}-1-000000-old.cast")), vec![b'x'; 1 << 20])
            .expect("an old cast");
    }
    let dir_arg = dir.to_str().expect("UTF-8");
    let args = [
        "--open",
        "--record-dir",
        dir_arg,
        "--record-max-bytes",
        "1M",
        "--record-max-total",
        "16M",
        maze.to_str().expect("UTF-8"),
    ];
    let server = Server::start(&scratch, &args);
    // six players, one after another (the order the recordings start in), from 127.0.0.1
    let mut players = Vec::new();
    for n in 0..6 {
        let player = Player::connect(server.port, None, &format!("idle{n}"), 80, 24);
        player.wait_for("a game", |s, _| playing(s, &[]));
        players.push(player);
    }
    let old = casts(&dir).iter().filter(|p| p.to_string_lossy().ends_with("-old.cast")).count();
    assert_eq!(old, 12, "finished casts deleted for bytes never written: {:?}", casts(&dir));
    let recorded: Vec<bool> = players.iter().map(|p| p.read(|s| hud_row(s).contains("recorded"))).collect();
    assert_eq!(recorded, [true, true, false, false, false, false], "two recorded from one address");
    assert_eq!(casts(&dir).len(), 14, "{:?}", casts(&dir));
    for mut player in players {
        player.send(b"q");
        assert!(player.wait_exit().success());
    }
}

/// Red-team pass 7: quick sessions from one address (log in, `q`: a cast of 2 KB each) filled the
/// directory's count of casts, and from then on each newcomer deleted the oldest cast, anyone's:
/// every other player's recordings were gone in 21 minutes. Now a full count deletes nothing: the
/// newcomer plays unrecorded, said once in the log. Here the count is lowered to 4 (eve from
/// 127.0.0.1, after alice from 127.0.0.2).
#[test]
fn quick_sessions_from_one_address_delete_no_other_players_cast() {
    let scratch = Scratch::new("recordcount");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let dir = scratch.join("casts");
    let dir_arg = dir.to_str().expect("UTF-8");
    let args = [
        "--open",
        "--no-records",
        "--record-dir",
        dir_arg,
        "--record-max-files",
        "4",
        maze.to_str().expect("UTF-8"),
    ];
    let server = Server::start(&scratch, &args);

    let mut alice = Player::connect_from(Some("127.0.0.2"), server.port, None, "alice", 80, 24);
    alice.wait_for("alice's game, recorded", |s, _| playing(s, &[]) && hud_row(s).contains("recorded"));
    alice.send(b"ww");
    alice.send(b"q");
    assert!(alice.wait_exit().success());
    let (alices, _) = wait_cast(&dir, |text| text.contains("Thanks for walking."));

    let mut recorded = Vec::new();
    for n in 0..6 {
        let mut eve = Player::connect(server.port, None, &format!("eve{n}"), 80, 24);
        eve.wait_for("eve's game", |s, _| playing(s, &[]));
        recorded.push(eve.read(|s| hud_row(s).contains("recorded")));
        eve.send(b"q");
        assert!(eve.wait_exit().success());
    }
    assert_eq!(recorded, [true, true, true, false, false, false], "the count is 4, alice's cast one");
    assert!(alices.exists(), "alice's cast deleted: {:?}", casts(&dir));
    assert_eq!(casts(&dir).len(), 4, "{:?}", casts(&dir));
    let log = server.log();
    assert_eq!(log.matches("new players are not recorded").count(), 1, "said once:\n{log}");
    assert!(!log.contains("deleted to make room"), "{log}");
}

/// The red team's LOW finding: a full disk left each cast in progress ending in a torn JSON line.
/// Here the server may write files of 32 KiB at most (`ulimit -f 64`, SIGXFSZ ignored, so a write
/// past it fails as a full disk's would, after writing what fits): the failure is said, and the
/// cast is cut back to whole lines, each valid asciicast, the header first.
#[test]
fn a_write_error_leaves_the_cast_whole_lines() {
    let scratch = Scratch::new("recordfull");
    let maze = scratch.maze(CORRIDOR_AND_BEND);
    let dir = scratch.join("casts");
    let dir_arg = dir.to_str().expect("UTF-8");
    let args = ["--open", "--no-records", "--record-dir", dir_arg, maze.to_str().expect("UTF-8")];
    let server = Server::start_after(&scratch, "trap '' XFSZ\nulimit -f 64", &args);

    let mut bob = Player::connect(server.port, None, "bob", 160, 50);
    bob.wait_for("bob's game", |s, _| playing(s, &[]) && hud_row(s).contains("recorded"));
    let deadline = Instant::now() + common::TIMEOUT;
    while !server.log().contains("cannot write the cast") {
        assert!(Instant::now() < deadline, "no write error; log:\n{}", server.log());
        bob.send(b"."); // a snap turn: new frames each time
        std::thread::sleep(Duration::from_millis(60));
    }
    bob.send(b"q");
    assert!(bob.wait_exit().success(), "q ends the game with 0: the game went on");
    let (_, text) = wait_cast(&dir, |_| true);
    assert!(text.len() <= 32 * 1024, "{} bytes: not stopped by the limit", text.len());
    assert!(text.ends_with('\n'), "a torn last line: {:?}", &text[text.len().saturating_sub(80)..]);
    let (header, events) = parse(&text); // every line whole and valid
    assert_eq!(header["width"], 160);
    assert!(!events.is_empty());
}
