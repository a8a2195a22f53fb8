//! The records against the real SQLite (bundled): ranks and the best ten, two stores on one file at
//! once, and the faults — a database locked by another program, a read-only one, a damaged one, a
//! full one, one deleted, replaced or turned into a folder while serving — each reported once while
//! the game and its ranking go on; no file is memory-mapped (no SIGBUS); and the records thread
//! never keeps a player waiting.
#![cfg(unix)]

use std::os::unix::fs::FileTypeExt as _;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

use mazewalk_maze::ContentHash;
use mazewalk_serve::records::{
    FINISHES_PER_PLAYER, Fault, Finish, QUEUE, Records, Sqlite, SqliteOptions, Standing, Store,
    standing_lines,
};
use mazewalk_testkit::collector;
use mazewalk_testkit::scratch::Scratch;

const MAZE: ContentHash = ContentHash([7; 32]);
const OTHER: ContentHash = ContentHash([9; 32]);

fn finish(maze: ContentHash, player: &str, seconds: f64) -> Finish {
    Finish {
        maze,
        maze_name: "test.maze".into(),
        player: player.into(),
        seconds,
        at: 1_800_000_000,
        run: None,
    }
}

fn open(path: &Path) -> Sqlite {
    let (db, aside) = Sqlite::open(path, SqliteOptions::default()).expect("open the records");
    assert_eq!(aside, None);
    db
}

fn said(lines: &Arc<Mutex<Vec<String>>>) -> Vec<String> {
    lines.lock().unwrap_or_else(PoisonError::into_inner).clone()
}

/// Waits for a standing from the records thread.
fn answer(records: &Records, f: Finish) -> Option<Standing> {
    let pending = records.finish(f)?;
    let runtime = tokio::runtime::Builder::new_current_thread().enable_time().build().expect("runtime");
    runtime.block_on(async { tokio::time::timeout(Duration::from_secs(20), pending).await.ok()?.ok()? })
}

#[test]
fn a_finish_gets_its_rank_and_the_best_ten_each_player_once() {
    let scratch = Scratch::new("rank");
    let mut db = open(&scratch.db());
    db.record(&finish(MAZE, "alice", 50.0)).unwrap();
    db.record(&finish(MAZE, "bob", 40.0)).unwrap();
    let s = db.record(&finish(MAZE, "alice", 30.0)).unwrap();
    assert_eq!((s.rank, s.best, s.players), (1, 30.0, 2));
    let s = db.record(&finish(MAZE, "carol", 60.0)).unwrap();
    assert_eq!((s.rank, s.players), (3, 3));
    let names: Vec<(&str, f64)> = s.top.iter().map(|b| (b.player.as_str(), b.seconds)).collect();
    assert_eq!(names, [("alice", 30.0), ("bob", 40.0), ("carol", 60.0)], "each player once, at its best");
    let s = db.record(&finish(MAZE, "alice", 99.0)).unwrap();
    assert_eq!((s.rank, s.best), (1, 30.0), "a slower run keeps the best");
    // Another maze is another table of times.
    assert_eq!(db.record(&finish(OTHER, "bob", 70.0)).unwrap().rank, 1);
    // Past the ten: the rank says where.
    for i in 0..12 {
        db.record(&finish(MAZE, &format!("p{i:02}"), 10.0 + f64::from(i))).unwrap();
    }
    let s = db.record(&finish(MAZE, "zed", 80.0)).unwrap();
    assert_eq!((s.top.len(), s.rank, s.players), (10, 16, 16));
    let lines = standing_lines(&s, "zed");
    assert_eq!(lines[1], "Best times here (16 players)");
    assert_eq!(lines.last().unwrap(), "16. zed  1:20.0  you");
    assert_eq!(lines[2], " 1. p00  0:10.0");
    // Kept: a new connection reads them back.
    drop(db);
    let mut again = Sqlite::open_to_read(&scratch.db()).unwrap();
    let mazes = again.mazes(None).unwrap();
    assert_eq!(mazes.len(), 2);
    assert_eq!((mazes[0].players, mazes[0].finishes, mazes[0].name.as_str()), (16, 18, "test.maze"));
    assert_eq!(mazes[0].top[0].player, "p00");
    assert!(again.knows(&OTHER).unwrap() && !again.knows(&ContentHash([1; 32])).unwrap());
}

/// Two servers on one file (a rollback journal and a busy timeout): every finish of both is kept.
/// (Each writes 150 finishes back to back, each a transaction with its fsyncs: with a rollback
/// journal a writer can wait for the other's run of commits longer than the 2 s default allows on a
/// loaded machine, which servers, a finish now and then, never see. Here the wait is 30 s.)
#[test]
fn two_stores_on_one_file_keep_every_finish() {
    let scratch = Scratch::new("two");
    let path = scratch.db();
    drop(open(&path));
    let options = SqliteOptions { busy_timeout: Duration::from_secs(30), ..SqliteOptions::default() };
    let writers: Vec<_> = ["left", "right"]
        .into_iter()
        .map(|who| {
            let path = path.clone();
            std::thread::spawn(move || {
                let (mut db, _) = Sqlite::open(&path, options).expect("open the records");
                for i in 0..150 {
                    // (5 finishes a player: under FINISHES_PER_PLAYER, so every one is kept)
                    db.record(&finish(MAZE, &format!("{who}{}", i % 30), f64::from(i)))
                        .expect("a finish kept");
                }
            })
        })
        .collect();
    for writer in writers {
        writer.join().expect("a writer");
    }
    let mazes = Sqlite::open_to_read(&path).unwrap().mazes(Some(&MAZE)).unwrap();
    assert_eq!((mazes[0].finishes, mazes[0].players), (300, 60));
}

/// Another program holds the database: the finishes meanwhile are kept in memory (after the busy
/// timeout), said once for the streak; the game and its ranking go on, and once the lock is gone
/// they are written with the next.
#[test]
fn a_locked_database_skips_finishes_until_the_lock_goes() {
    let scratch = Scratch::new("locked");
    let path = scratch.db();
    let options = SqliteOptions { busy_timeout: Duration::from_millis(100), ..SqliteOptions::default() };
    let (db, _) = Sqlite::open(&path, options).unwrap();
    let (report, lines) = collector();
    let records = Records::start(db, report).unwrap();
    assert!(answer(&records, finish(MAZE, "ann", 10.0)).is_some());
    let other = rusqlite::Connection::open(&path).unwrap();
    other.execute_batch("BEGIN EXCLUSIVE").unwrap();
    for seconds in [9.0, 12.0, 11.0] {
        let standing = answer(&records, finish(MAZE, "bob", seconds)).expect("ranked from memory");
        assert_eq!((standing.rank, standing.best, standing.players), (1, 9.0, 2), "while locked");
    }
    let reported = said(&lines);
    assert_eq!(reported.len(), 1, "{reported:?}");
    assert!(reported[0].contains("locked by another program"), "{reported:?}");
    other.execute_batch("COMMIT").unwrap();
    let standing = answer(&records, finish(MAZE, "ann", 8.0)).expect("kept again");
    assert_eq!(standing.best, 8.0);
    drop(records);
    let mazes = Sqlite::open_to_read(&path).unwrap().mazes(Some(&MAZE)).unwrap();
    assert_eq!(
        (mazes[0].finishes, mazes[0].players),
        (5, 2),
        "the finishes made while locked, written after"
    );
}

/// The finishes counted in the file, read by another connection.
fn finishes_in(path: &Path) -> usize {
    Sqlite::open_to_read(path).unwrap().mazes(Some(&MAZE)).unwrap().first().map_or(0, |m| m.finishes)
}

/// The red team's MEDIUM finding: a finish kept in memory while the file was locked waited for a
/// later finish to be written, and was lost at shutdown if none came. Now it is tried again every
/// few seconds while the store fails, with no finish to carry it.
#[test]
fn a_finish_kept_while_locked_is_written_once_the_lock_goes_with_no_other_finish() {
    let scratch = Scratch::new("lockretry");
    let path = scratch.db();
    let options = SqliteOptions { busy_timeout: Duration::from_millis(100), ..SqliteOptions::default() };
    let (db, _) = Sqlite::open(&path, options).unwrap();
    let (report, _lines) = collector();
    let records = Records::start(db, report).unwrap();
    assert!(answer(&records, finish(MAZE, "ann", 10.0)).is_some());
    let other = rusqlite::Connection::open(&path).unwrap();
    other.execute_batch("BEGIN EXCLUSIVE").unwrap();
    answer(&records, finish(MAZE, "bob", 9.0)).expect("ranked from memory");
    other.execute_batch("COMMIT").unwrap();
    let deadline = Instant::now() + Duration::from_secs(20);
    while finishes_in(&path) < 2 {
        assert!(Instant::now() < deadline, "bob's finish was never written, though the file is free");
        std::thread::sleep(Duration::from_millis(100));
    }
    assert!(records.close(Duration::from_secs(10)));
    assert_eq!(finishes_in(&path), 2);
}

/// … and when the records thread stops (the server's shutdown), the finishes still in memory are
/// tried once more; those that cannot be kept are said, with their number.
#[test]
fn finishes_kept_in_memory_are_tried_at_the_end_and_the_lost_ones_said() {
    let scratch = Scratch::new("lockexit");
    let path = scratch.db();
    let options = SqliteOptions { busy_timeout: Duration::from_millis(100), ..SqliteOptions::default() };
    // The lock goes just before the end: the last try writes the finish.
    let (db, _) = Sqlite::open(&path, options).unwrap();
    let (report, lines) = collector();
    let records = Records::start(db, report).unwrap();
    let other = rusqlite::Connection::open(&path).unwrap();
    other.execute_batch("BEGIN EXCLUSIVE").unwrap();
    answer(&records, finish(MAZE, "bob", 9.0)).expect("ranked from memory");
    other.execute_batch("COMMIT").unwrap();
    assert!(records.close(Duration::from_secs(10)), "the thread stopped");
    assert_eq!(finishes_in(&path), 1, "the finish kept in memory, written at the end");
    assert!(!said(&lines).iter().any(|l| l.contains("could not be kept")), "{:?}", said(&lines));
    // The lock stays to the end: the finishes lost are said, with their number.
    let (db, _) = Sqlite::open(&path, options).unwrap();
    let (report, lines) = collector();
    let records = Records::start(db, report).unwrap();
    other.execute_batch("BEGIN EXCLUSIVE").unwrap();
    answer(&records, finish(MAZE, "cy", 8.0)).expect("ranked from memory");
    answer(&records, finish(MAZE, "dee", 7.0)).expect("ranked from memory");
    assert!(records.close(Duration::from_secs(10)), "the thread stopped");
    other.execute_batch("COMMIT").unwrap();
    let reported = said(&lines);
    assert!(reported.iter().any(|l| l.contains("2 finishes could not be kept")), "{reported:?}");
    assert_eq!(finishes_in(&path), 1);
}

/// Makes `path` impossible to write for this process: `chattr +i` for root (whom permissions do not
/// stop), mode 0444 otherwise. Undone on drop.
struct ReadOnly(PathBuf);

impl ReadOnly {
    fn make(path: &Path) -> ReadOnly {
        if rustix::process::geteuid().is_root() {
            let status = std::process::Command::new("chattr").arg("+i").arg(path).status().expect("chattr");
            assert!(status.success(), "chattr +i {} (root ignores file modes)", path.display());
        } else {
            use std::os::unix::fs::PermissionsExt as _;
            std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o444)).unwrap();
        }
        ReadOnly(path.to_path_buf())
    }
}

impl Drop for ReadOnly {
    fn drop(&mut self) {
        let _ = std::process::Command::new("chattr").arg("-i").arg(&self.0).status();
        use std::os::unix::fs::PermissionsExt as _;
        let _ = std::fs::set_permissions(&self.0, std::fs::Permissions::from_mode(0o644));
    }
}

/// A database that cannot be written is said so at once (the server then serves without records).
#[test]
fn a_read_only_database_is_refused_plainly() {
    let scratch = Scratch::new("readonly");
    let path = scratch.db();
    open(&path).record(&finish(MAZE, "ann", 10.0)).unwrap();
    // (no -wal or -shm left beside it: a clean close checkpoints the WAL)
    let _guard = ReadOnly::make(&path);
    let err = Sqlite::open(&path, SqliteOptions::default()).unwrap_err();
    assert!(matches!(err.fault, Fault::ReadOnly | Fault::CannotOpen), "{err}");
    assert!(err.to_string().starts_with(&path.display().to_string()), "{err}");
    // The records can still be read.
    let mazes = Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap();
    assert_eq!(mazes[0].finishes, 1);
}

// Red-team pass 11: `--records` at a device or a FIFO was opened by SQLite, which failed on it
// ("disk I/O error", the server then without records) and left a journal beside it:
// `--records /dev/zero` made `/dev/zero-journal`, mode 0666 as the device's. `mazewalk records`
// said "no such file". Now neither opens it, and each says what is there.
#[test]
fn a_path_that_is_not_a_regular_file_is_refused_and_nothing_made_beside_it() {
    let scratch = Scratch::new("notafile");
    let fifo = scratch.join("records.fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success(), "mkfifo made the FIFO");
    let folder = scratch.join("records.dir");
    std::fs::create_dir(&folder).unwrap();
    for (path, what) in [(&fifo, "a FIFO"), (&folder, "a directory")] {
        let err = Sqlite::open(path, SqliteOptions::default()).unwrap_err();
        assert_eq!(err.fault, Fault::CannotOpen, "{err}");
        assert!(err.to_string().contains(&format!("{what}, not a regular file")), "{err}");
        let Err(err) = Sqlite::open_to_read(path) else { panic!("{what} read as records") };
        assert!(err.to_string().contains(&format!("{what}, not a regular file")), "{err}");
    }
    let mut names: Vec<String> = std::fs::read_dir(scratch.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["records.dir", "records.fifo"], "nothing made beside them");
}

/// A file that is not a records database, or a damaged one, is kept aside unchanged and a new one
/// made.
#[test]
fn a_damaged_database_is_kept_aside_and_a_new_one_made() {
    let scratch = Scratch::new("damaged");
    let path = scratch.db();
    std::fs::write(&path, "these are not the records you are looking for\n".repeat(100)).unwrap();
    let (mut db, aside) = Sqlite::open(&path, SqliteOptions::default()).unwrap();
    let aside = aside.expect("kept aside");
    assert!(aside.display().to_string().contains("records.sqlite.damaged-"), "{}", aside.display());
    assert!(std::fs::read_to_string(&aside).unwrap().starts_with("these are not"), "kept as it was");
    assert_eq!(db.record(&finish(MAZE, "ann", 10.0)).unwrap().rank, 1, "a new one works");
    drop(db);
    // A real database whose pages were overwritten: found at the next start, kept aside too.
    let mut bytes = std::fs::read(&path).unwrap();
    assert!(bytes.len() >= 8192, "the premise: more than one page");
    for b in &mut bytes[4096..] {
        *b = 0xA5;
    }
    std::fs::write(&path, &bytes).unwrap();
    let (_, aside) = Sqlite::open(&path, SqliteOptions::default()).unwrap();
    assert_eq!(std::fs::read(aside.expect("kept aside")).unwrap(), bytes);
}

/// The red team's LOW finding: records could be filled (at the size limit every later finish
/// failed, for everyone). A full file now makes room by deleting the worst quarter of the fullest
/// maze's finishes: every finish is kept, the best ten stay, nothing is said, none is in memory.
#[test]
fn a_full_database_makes_room_by_deleting_the_worst_finishes() {
    let scratch = Scratch::new("full");
    let options = SqliteOptions { max_bytes: 128 * 1024, ..SqliteOptions::default() };
    let (db, _) = Sqlite::open(&scratch.db(), options).unwrap();
    let (report, lines) = collector();
    let records = Records::start(db, report).unwrap();
    let long_name = "x".repeat(60);
    for i in 0..500 {
        let standing = answer(&records, finish(MAZE, &format!("{long_name}{i}"), f64::from(i) + 10.0));
        assert!(standing.expect("ranked").rank <= i as usize + 1);
    }
    let late = format!("{long_name}late");
    let standing = answer(&records, finish(MAZE, &late, 1.0)).expect("ranked");
    assert_eq!((standing.rank, &standing.top[0].player), (1, &late));
    assert_eq!(said(&lines), Vec::<String>::new(), "a fault said");
    assert_eq!(records.written_failed(), (501, 0), "every finish written");
    assert!(records.close(Duration::from_secs(10)));
    let mazes = Sqlite::open_to_read(&scratch.db()).unwrap().mazes(Some(&MAZE)).unwrap();
    assert!(
        mazes[0].finishes > 100 && mazes[0].finishes < 501,
        "the premise: it filled up ({})",
        mazes[0].finishes
    );
    let best: Vec<&str> = mazes[0].top.iter().map(|b| b.player.as_str()).collect();
    let mut expected = vec![late.clone()];
    expected.extend((0..9).map(|i| format!("{long_name}{i}")));
    assert_eq!(best, expected.iter().map(String::as_str).collect::<Vec<_>>(), "the best ten kept");
}

/// One player finishing again and again keeps only its best finishes: it cannot fill the file.
#[test]
fn a_player_keeps_its_best_finishes_only() {
    let scratch = Scratch::new("perplayer");
    let mut db = open(&scratch.db());
    for i in 0..50 {
        db.record(&finish(MAZE, "ann", 100.0 - f64::from(i % 25))).unwrap();
    }
    db.record(&finish(MAZE, "bob", 80.0)).unwrap();
    let standing = db.record(&finish(MAZE, "ann", 99.5)).unwrap();
    assert_eq!((standing.best, standing.rank, standing.players), (76.0, 1, 2));
    let mazes = db.mazes(Some(&MAZE)).unwrap();
    assert_eq!(mazes[0].finishes, FINISHES_PER_PLAYER + 1, "ann's best {FINISHES_PER_PLAYER}, and bob's");
}

/// However slow the database, handing a finish over never waits: past the queue, finishes are dropped
/// (counted, said once).
#[test]
fn handing_a_finish_over_never_waits() {
    let scratch = Scratch::new("slow");
    let path = scratch.db();
    let options = SqliteOptions { busy_timeout: Duration::from_secs(1), ..SqliteOptions::default() };
    let (db, _) = Sqlite::open(&path, options).unwrap();
    let other = rusqlite::Connection::open(&path).unwrap();
    other.execute_batch("BEGIN EXCLUSIVE").unwrap(); // each finish waits its full second
    let (report, lines) = collector();
    let records = Records::start(db, report).unwrap();
    let started = Instant::now();
    let pending: Vec<_> = (0..QUEUE + 40).map(|i| records.finish(finish(MAZE, "ann", i as f64))).collect();
    let took = started.elapsed();
    assert!(took < Duration::from_millis(200), "handing {} finishes over took {took:?}", pending.len());
    assert!(records.dropped() >= 30, "past the queue: dropped ({})", records.dropped());
    assert!(said(&lines).iter().any(|l| l.contains("slow")), "{:?}", said(&lines));
    assert_eq!(said(&lines).iter().filter(|l| l.contains("slow")).count(), 1, "said once");
    drop(other);
}

/// Names a records file may hold that must never reach a terminal raw (issue #40): OSC 52 (writes the
/// clipboard), OSC 0 (the window title), a screen wipe, and U+202E (turns the text after it around).
const HOSTILE_NAMES: [&str; 4] =
    ["\x1b]52;c;ZXZpbA==\x07mallory", "\x1b]0;pwned\x07eve", "\x1b[2Jwipe", "\u{202e}evil"];

/// Whether `text` holds anything a terminal would act on or show turned around.
fn raw_escape(text: &str) -> bool {
    text.chars().any(|c| c.is_control() || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}'))
}

/// Issue #40, low: names in the records file went to the exit box as they were. Each is shown as SSH
/// user names are cleaned, and the player's own row is still marked.
#[test]
fn the_exit_box_shows_names_from_the_records_file_cleaned() {
    let scratch = Scratch::new("names");
    let mut db = open(&scratch.db());
    for (i, name) in HOSTILE_NAMES.iter().enumerate() {
        db.record(&finish(MAZE, name, 10.0 + i as f64)).unwrap();
    }
    let s = db.record(&finish(MAZE, "zed", 99.0)).unwrap();
    let lines = standing_lines(&s, "zed");
    assert!(lines.iter().all(|l| !raw_escape(l)), "{lines:?}");
    assert_eq!(lines[2], " 1. 52cZXZpbAmallory  0:10.0");
    assert_eq!(lines[3], " 2. 0pwnedeve         0:11.0");
    assert_eq!(lines[4], " 3. 2Jwipe            0:12.0");
    assert_eq!(lines[5], " 4. evil              0:13.0");
    assert_eq!(lines[6], " 5. zed               1:39.0  you");
}

/// The files beside the database (`-wal`, `-shm`, `-journal`) that exist now.
fn beside(path: &Path) -> Vec<String> {
    ["-wal", "-shm", "-journal"]
        .into_iter()
        .filter(|suffix| Path::new(&format!("{}{suffix}", path.display())).exists())
        .map(String::from)
        .collect()
}

/// Issue #40, medium: in WAL mode SQLite maps `-shm`; made immutable while serving (or its disk
/// remounted read-only), the next finish killed the server with SIGBUS. Now nothing is mapped: the
/// database uses a rollback journal, with no `-shm` at all while serving.
#[test]
fn no_file_is_mapped_while_serving() {
    let scratch = Scratch::new("nommap");
    let path = scratch.db();
    let mut db = open(&path);
    db.record(&finish(MAZE, "ann", 10.0)).unwrap();
    let other = rusqlite::Connection::open(&path).unwrap();
    let mode: String = other.query_row("PRAGMA journal_mode", [], |r| r.get(0)).unwrap();
    assert_eq!(mode, "delete");
    assert_eq!(beside(&path), Vec::<String>::new(), "no -shm, no -wal, while open");
    drop(other);
    // A file an older mazewalk left in WAL mode, its `-shm` immutable (as root; a mode otherwise):
    // taken out of WAL without the `-shm` mapped, and written. (A SIGBUS would end this test's process.)
    drop(db);
    // (another process, killed while serving — SQLite's locks are per process — leaves both files)
    let script = "import os, sqlite3, sys\n\
                  db = sqlite3.connect(sys.argv[1])\n\
                  db.execute('PRAGMA journal_mode=WAL').fetchall()\n\
                  db.execute('SELECT * FROM finishes').fetchall()\n\
                  os._exit(0)";
    let status = std::process::Command::new("python3").args(["-c", script]).arg(&path).status();
    assert!(status.expect("python3").success());
    let shm = PathBuf::from(format!("{}-shm", path.display()));
    assert!(shm.exists(), "the premise: WAL made its -shm");
    let _frozen = ReadOnly::make(&shm);
    let mut db = open(&path);
    assert_eq!(db.record(&finish(MAZE, "bob", 9.0)).unwrap().rank, 1);
    let mode: String =
        rusqlite::Connection::open_with_flags(&path, rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY)
            .unwrap()
            .query_row("PRAGMA journal_mode", [], |r| r.get(0))
            .unwrap();
    assert_eq!(mode, "delete", "out of WAL");
}

/// Red-team pass 13: `mazewalk records` on a file in WAL mode (one a server of an older mazewalk ran
/// on, or any file sent with its header so) had SQLite make a `-wal` and a `-shm` beside it, left
/// there, and map the `-shm` — the hazard issue #40 took out of the server — and failed in a folder
/// the reader may not write ("the database cannot be written"). Now such a file, with no log beside
/// it to read, is read as it is and nothing is made beside it; one whose `-wal` holds finishes not
/// yet in the file is refused, saying so, and what was beside it stays as it was.
#[test]
fn reading_a_file_in_wal_mode_makes_nothing_beside_it() {
    let scratch = Scratch::new("walread");
    let path = scratch.db();
    open(&path).record(&finish(MAZE, "ann", 10.0)).unwrap();
    let other = rusqlite::Connection::open(&path).unwrap();
    let mode: String = other.query_row("PRAGMA journal_mode=WAL", [], |r| r.get(0)).unwrap();
    drop(other); // (a clean close: the log checkpointed, `-wal` and `-shm` removed)
    assert_eq!((mode.as_str(), beside(&path)), ("wal", Vec::new()), "the premise: WAL, nothing beside");
    let mazes = Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap();
    assert_eq!((mazes[0].finishes, mazes[0].top[0].player.as_str()), (1, "ann"));
    assert_eq!(beside(&path), Vec::<String>::new(), "nothing made beside it, nothing mapped");
    // An empty `-wal` beside it (a server's clean start): the file is still the whole database.
    std::fs::write(format!("{}-wal", path.display()), b"").unwrap();
    assert_eq!(Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap()[0].finishes, 1);
    assert_eq!(beside(&path), ["-wal"], "no -shm made");
    std::fs::remove_file(format!("{}-wal", path.display())).unwrap();
    // A writer killed while its finishes were in the log: refused, naming the log; nothing changed.
    let script = "import os, sqlite3, sys\n\
                  db = sqlite3.connect(sys.argv[1])\n\
                  db.execute(\"INSERT INTO finishes VALUES (?, 'bob', 9.0, 1, NULL)\", (sys.argv[2],))\n\
                  db.commit()\n\
                  os._exit(0)";
    let status =
        std::process::Command::new("python3").args(["-c", script]).arg(&path).arg(MAZE.to_string()).status();
    assert!(status.expect("python3").success());
    let wal = PathBuf::from(format!("{}-wal", path.display()));
    let before: Vec<(String, u64)> = beside(&path)
        .into_iter()
        .map(|s| (s.clone(), std::fs::metadata(format!("{}{s}", path.display())).unwrap().len()))
        .collect();
    assert!(std::fs::metadata(&wal).unwrap().len() > 0, "the premise: a log that holds a finish");
    let err = Sqlite::open_to_read(&path).map(|_| ()).expect_err("a log of finishes not read");
    assert_eq!(err.fault, Fault::CannotOpen, "{err}");
    assert!(err.to_string().contains("-wal") && err.to_string().contains("not yet in the file"), "{err}");
    let after: Vec<(String, u64)> = beside(&path)
        .into_iter()
        .map(|s| (s.clone(), std::fs::metadata(format!("{}{s}", path.display())).unwrap().len()))
        .collect();
    assert_eq!(after, before, "what was beside it stays as it was");
    // A server takes the log in.
    let mut db = open(&path);
    assert_eq!(db.mazes(None).unwrap()[0].finishes, 2, "bob's finish, from the log");
}

/// A records file whose writer was killed inside a write (a hot rollback journal beside it): a
/// reader is told so, not that the file cannot be written; nothing beside it changes; a server
/// rolls the write back and reads what was kept before it.
#[test]
fn a_write_cut_off_is_said_to_the_reader_and_rolled_back_by_a_server() {
    mazewalk_testkit::require_tool("python3", "python3");
    let scratch = Scratch::new("hotjournal");
    let path = scratch.db();
    open(&path).record(&finish(MAZE, "ann", 10.0)).unwrap();
    // Many rows in one transaction with a one-page cache: pages spill to the file before the
    // commit, which never comes.
    let script = "import os, sqlite3, sys\n\
                  db = sqlite3.connect(sys.argv[1])\n\
                  db.execute('PRAGMA cache_size=1')\n\
                  db.execute('BEGIN')\n\
                  for i in range(2000):\n    \
                      db.execute(\"INSERT INTO finishes VALUES (?, 'bob', ?, 1, ?)\", (sys.argv[2], i, b'x' * 200))\n\
                  os._exit(0)";
    let status =
        std::process::Command::new("python3").args(["-c", script]).arg(&path).arg(MAZE.to_string()).status();
    assert!(status.expect("python3").success());
    let journal = PathBuf::from(format!("{}-journal", path.display()));
    let sizes =
        || (std::fs::metadata(&path).unwrap().len(), std::fs::metadata(&journal).map(|m| m.len()).ok());
    let before = sizes();
    assert!(before.1.is_some_and(|n| n > 0), "the premise: a hot journal beside the file");
    let err = Sqlite::open_to_read(&path).and_then(|mut db| db.mazes(None)).map(|_| ()).expect_err("cut off");
    assert_eq!(err.fault, Fault::CutOff, "{err}");
    assert!(!err.to_string().contains("cannot be written"), "{err}");
    assert_eq!(sizes(), before, "the file and its journal as they were");
    let mut db = open(&path);
    let mazes = db.mazes(None).unwrap();
    assert_eq!((mazes[0].finishes, mazes[0].top[0].player.as_str()), (1, "ann"), "the write rolled back");
}

/// `f` on a thread of its own, its result if it returned within `limit`; else `fifo` is opened for
/// writing without waiting (which lets a reader waiting in its open go on) and `None`.
fn returned_within<T: Send + 'static>(
    limit: Duration,
    fifo: &Path,
    f: impl FnOnce() -> T + Send + 'static,
) -> Option<T> {
    use std::os::unix::fs::OpenOptionsExt as _;
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    let got = rx.recv_timeout(limit).ok();
    if got.is_none() {
        // (O_NONBLOCK: with no reader in its open, this fails at once rather than wait too)
        let _ = std::fs::OpenOptions::new().write(true).custom_flags(0o4000).open(fifo);
    }
    got
}

/// Red-team pass 13: SQLite opens the `-journal` beside a records file itself (a hot journal's, to
/// read its first bytes), and a FIFO put there — in a folder others write to, or in a tar of a
/// records file — had `mazewalk records` wait for a writer for ever and `mazewalk serve` never start
/// (nor, put there while serving, the records thread take another finish). Now a `-journal`, `-wal`
/// or `-shm` beside it that is not a regular file is refused at once, saying what is there, at the
/// start and before every call; what was there stays.
#[test]
fn a_fifo_beside_the_records_file_is_refused_not_waited_on() {
    let scratch = Scratch::new("fifobeside");
    let path = scratch.db();
    let mut serving = open(&path);
    serving.record(&finish(MAZE, "ann", 10.0)).unwrap();
    for suffix in ["-journal", "-wal", "-shm"] {
        let fifo = PathBuf::from(format!("{}{suffix}", path.display()));
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
        assert!(made.success(), "mkfifo made the FIFO");
        let p = path.clone();
        let opened = returned_within(Duration::from_secs(10), &fifo, move || {
            let served = Sqlite::open(&p, SqliteOptions::default()).map(|_| ());
            let read = Sqlite::open_to_read(&p).map(|_| ());
            (served, read)
        });
        let Some((served, read)) = opened else { panic!("{suffix}: still waiting on the FIFO after 10 s") };
        for err in [served.unwrap_err(), read.unwrap_err()] {
            assert_eq!(err.fault, Fault::CannotOpen, "{err}");
            assert!(err.to_string().contains(&format!("{suffix} beside it is a FIFO")), "{err}");
        }
        // A server already serving: the next finish refused at once (kept in memory by the thread).
        let mut db = serving;
        let Some((db_back, err)) = returned_within(Duration::from_secs(10), &fifo, move || {
            let err = db.record(&finish(MAZE, "bob", 9.0)).map(|_| ()).unwrap_err();
            (db, err)
        }) else {
            panic!("{suffix}: a finish still waiting on the FIFO after 10 s")
        };
        serving = db_back;
        assert!(err.to_string().contains("a FIFO"), "{err}");
        assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo(), "{suffix}: left as it was");
        std::fs::remove_file(&fifo).unwrap();
    }
    // (and with them gone, the same file as before)
    assert_eq!(serving.record(&finish(MAZE, "bob", 9.0)).unwrap().rank, 1);
}

/// Issue #40, low: the records file deleted while serving lost every later finish silently. Now the
/// next finish notices (said once), a new file is made and the finishes go on into it; a file put in
/// its place is used.
#[test]
fn a_records_file_deleted_or_replaced_while_serving_is_made_again() {
    let scratch = Scratch::new("deleted");
    let path = scratch.db();
    let (report, lines) = collector();
    let records = Records::start(open(&path), report).unwrap();
    assert_eq!(answer(&records, finish(MAZE, "ann", 10.0)).unwrap().rank, 1);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(answer(&records, finish(MAZE, "bob", 20.0)).unwrap().players, 1, "the old file is gone");
    assert_eq!(answer(&records, finish(MAZE, "cid", 30.0)).unwrap().players, 2);
    let reported = said(&lines);
    assert_eq!(reported.len(), 1, "{reported:?}");
    assert!(reported[0].contains("was deleted while serving; a new one is made"), "{reported:?}");
    let kept = Sqlite::open_to_read(&path).unwrap().mazes(Some(&MAZE)).unwrap();
    assert_eq!((kept[0].finishes, kept[0].top[0].player.as_str()), (2, "bob"), "in the new file");
    // Another records file moved into its place: used from the next finish on.
    let other = scratch.join("other.sqlite");
    open(&other).record(&finish(MAZE, "dee", 5.0)).unwrap();
    std::fs::rename(&other, &path).unwrap();
    let standing = answer(&records, finish(MAZE, "eve", 6.0)).unwrap();
    assert_eq!((standing.rank, standing.players), (2, 2), "dee's file");
    let reported = said(&lines);
    assert_eq!(reported.len(), 2, "{reported:?}");
    assert!(reported[1].contains("was replaced while serving; the new one is used"), "{reported:?}");
}

/// Issue #40: a records file that cannot be written while serving (here a folder put in its place,
/// which stops root too): said once, the ranking goes on in memory from the file's last best ten,
/// and once a file can be made again the finishes go into it.
#[test]
fn a_records_file_that_cannot_be_written_keeps_the_ranking_in_memory() {
    let scratch = Scratch::new("folder");
    let path = scratch.db();
    let (report, lines) = collector();
    let records = Records::start(open(&path), report).unwrap();
    answer(&records, finish(MAZE, "ann", 50.0)).unwrap();
    answer(&records, finish(MAZE, "bob", 40.0)).unwrap();
    std::fs::rename(&path, scratch.join("moved.sqlite")).unwrap();
    std::fs::create_dir(&path).unwrap();
    let cid = answer(&records, finish(MAZE, "cid", 45.0)).expect("ranked from memory");
    let names: Vec<&str> = cid.top.iter().map(|b| b.player.as_str()).collect();
    assert_eq!((cid.rank, cid.players, names), (2, 3, vec!["bob", "cid", "ann"]));
    let dan = answer(&records, finish(MAZE, "dan", 30.0)).expect("ranked from memory");
    assert_eq!((dan.rank, dan.players), (1, 4));
    let reported = said(&lines);
    assert_eq!(reported.len(), 2, "the change and the fault, once each: {reported:?}");
    assert!(reported[0].contains("was replaced while serving and cannot be opened again"), "{reported:?}");
    assert!(reported[1].contains("kept in memory"), "{reported:?}");
    // The folder goes: a new file, the missed finishes written into it with the next.
    std::fs::remove_dir(&path).unwrap();
    assert!(answer(&records, finish(MAZE, "eve", 60.0)).is_some());
    drop(records);
    let kept = Sqlite::open_to_read(&path).unwrap().mazes(Some(&MAZE)).unwrap();
    let names: Vec<&str> = kept[0].top.iter().map(|b| b.player.as_str()).collect();
    assert_eq!(names, ["dan", "cid", "eve"], "the finishes made meanwhile, kept");
}

/// QA: the records hold names, dates and whole runs, so a records file made by mazewalk is mode
/// 0600 as the casts are (a new one made after keeping a damaged one aside too), whatever the
/// umask; and a path whose folder is missing is refused, naming it, with nothing made.
#[test]
fn a_new_records_file_is_private_and_no_folder_is_made() {
    use std::os::unix::fs::PermissionsExt as _;
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let scratch = Scratch::new("private");
    let path = scratch.db();
    let mut db = open(&path);
    db.record(&finish(MAZE, "ann", 10.0)).unwrap();
    drop(db);
    assert_eq!(mode(&path), 0o600, "a fresh records file");
    std::fs::write(&path, "not the records\n".repeat(100)).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o644)).unwrap();
    let (_, aside) = Sqlite::open(&path, SqliteOptions::default()).unwrap();
    assert_eq!(mode(&path), 0o600, "the new one made beside {:?}", aside.expect("kept aside"));

    let folder = path.with_file_name("missing");
    let nested = folder.join("dir").join("records.sqlite");
    let err = Sqlite::open(&nested, SqliteOptions::default()).map(|_| ()).expect_err("no folder");
    assert_eq!(err.fault, Fault::CannotOpen);
    assert!(err.to_string().contains(&folder.join("dir").display().to_string()), "{err}");
    assert!(!folder.exists(), "nothing made");
}

/// The tables and index of a records file, version 2, as the red team wrote them by hand (the
/// comments and white space of ours are not needed: only what they define).
const OUR_TABLES: &str = "
    CREATE TABLE mazes (hash TEXT PRIMARY KEY, name TEXT NOT NULL, first_seen INTEGER NOT NULL);
    CREATE TABLE finishes (maze TEXT NOT NULL REFERENCES mazes(hash), player TEXT NOT NULL,
                           seconds REAL NOT NULL, at INTEGER NOT NULL, run BLOB);
    CREATE INDEX finishes_by_maze ON finishes (maze, player, seconds);";

/// A file at `path` made by plain SQLite from `sql`, at schema version 2.
fn made_by_hand(path: &Path, sql: &str) {
    let _ = std::fs::remove_file(path);
    let conn = rusqlite::Connection::open(path).unwrap();
    conn.execute_batch(&format!("{sql}\nPRAGMA user_version = 2;")).unwrap();
}

/// Red-team pass 8 (local side), finding 1: `mazewalk records` ran its queries on whatever schema
/// the file defined. An 8 KB file whose `mazes` was a view over an endless recursive query made it
/// spin for ever while its sort filled the disk (1.4 GB in 10 s); another view made a 400 MB value.
/// Now a file whose schema is not exactly ours is refused at once, naming what is wrong, whether it
/// is read (`records`) or served (kept aside, as a damaged one, and a new one made).
#[test]
fn a_records_file_whose_schema_is_not_ours_is_refused_at_once() {
    let scratch = Scratch::new("schema");
    let path = scratch.db();
    let endless = "CREATE VIEW mazes AS WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n)
          SELECT printf('%064d', i) AS hash, 'endless' AS name, i AS first_seen FROM n;
        CREATE TABLE finishes (maze TEXT, player TEXT, seconds REAL, at INTEGER, run BLOB);";
    let huge = "CREATE VIEW mazes AS SELECT printf('%064d', 1) AS hash,
          printf('%.*c', 400000000, 'x') AS name, 0 AS first_seen;
        CREATE TABLE finishes (maze TEXT, player TEXT, seconds REAL, at INTEGER, run BLOB);";
    let trigger =
        format!("{OUR_TABLES} CREATE TRIGGER t AFTER INSERT ON finishes BEGIN DELETE FROM mazes; END;");
    let virtual_table = format!("{OUR_TABLES} CREATE VIRTUAL TABLE notes USING fts5(text);");
    let extra_table = format!("{OUR_TABLES} CREATE TABLE extra (x);");
    let partial =
        OUR_TABLES.replace("(maze, player, seconds);", "(maze, player, seconds) WHERE seconds > 0;");
    let checked =
        OUR_TABLES.replace("first_seen INTEGER NOT NULL)", "first_seen INTEGER NOT NULL CHECK (1))");
    let many: String = (0..40).map(|i| format!("CREATE TABLE t{i} (x);")).collect();
    let many = format!("{OUR_TABLES} {many}");
    let cases: [(&str, &str, &str); 8] = [
        ("an endless view", endless, "a view `mazes`"),
        ("a view of a 400 MB value", huge, "a view `mazes`"),
        ("a trigger", &trigger, "a trigger `t`"),
        ("a virtual table", &virtual_table, "a virtual table `notes`"),
        ("another table", &extra_table, "a table `extra` of its own"),
        ("a partial index", &partial, "its index `finishes_by_maze` is not as mazewalk makes it"),
        ("a CHECK constraint", &checked, "its table `mazes` is not as mazewalk makes it"),
        ("forty more tables", &many, "too many schema objects"),
    ];
    for (what, sql, why) in cases {
        made_by_hand(&path, sql);
        let started = Instant::now();
        let err = Sqlite::open_to_read(&path).map(|_| ()).expect_err(what);
        assert!(started.elapsed() < Duration::from_secs(10), "{what}: refused at once");
        assert_eq!(err.fault, Fault::Damaged, "{what}: {err}");
        let said = err.to_string();
        assert!(said.starts_with(&path.display().to_string()), "{what}: names the file: {said}");
        assert!(said.contains(why), "{what}: says what is wrong: {said}");
        // Served: kept aside as it was, and a new one made.
        let (mut db, aside) = Sqlite::open(&path, SqliteOptions::default()).expect(what);
        let aside = aside.unwrap_or_else(|| panic!("{what}: kept aside"));
        assert_eq!(db.record(&finish(MAZE, "ann", 10.0)).unwrap().rank, 1, "{what}: a new one works");
        let kept = rusqlite::Connection::open(&aside).unwrap();
        let objects: i64 = kept.query_row("SELECT COUNT(*) FROM sqlite_schema", [], |r| r.get(0)).unwrap();
        assert!(objects >= 2, "{what}: the file kept aside is as it was");
    }
}

/// What the schema check accepts: the files this mazewalk makes, and those the one before it made
/// (version 1, migrated by a server to version 2), however their SQL text was spaced.
#[test]
fn records_files_of_ours_and_of_the_previous_schema_pass_the_check() {
    let scratch = Scratch::new("ours");
    let path = scratch.db();
    open(&path).record(&finish(MAZE, "ann", 10.0)).unwrap();
    assert_eq!(Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap()[0].finishes, 1);
    made_by_hand(&path, &format!("{OUR_TABLES} INSERT INTO mazes VALUES ('{MAZE}', 'm', 1);"));
    assert_eq!(Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap().len(), 1, "spaced otherwise");
    // version 1, then migrated
    made_by_hand(&path, &OUR_TABLES.replace(", run BLOB", ""));
    rusqlite::Connection::open(&path).unwrap().execute_batch("PRAGMA user_version = 1").unwrap();
    assert_eq!(Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap(), Vec::new(), "version 1");
    let (mut db, aside) = Sqlite::open(&path, SqliteOptions::default()).unwrap();
    assert_eq!(aside, None, "migrated, not kept aside");
    db.record(&finish(MAZE, "ann", 10.0)).unwrap();
    drop(db);
    assert_eq!(Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap()[0].finishes, 1, "migrated");
    let (_, aside) = Sqlite::open(&path, SqliteOptions::default()).unwrap();
    assert_eq!(aside, None, "a migrated file opens again");
}

/// Finding 1's bounds, beyond the schema: a value no records file of ours holds (a maze name of
/// 2 MB) is refused as it is read rather than allocated, and a call that takes more VM steps than
/// its budget stops with a fault that says so.
#[test]
fn a_query_on_a_records_file_is_bounded_whatever_it_holds() {
    let scratch = Scratch::new("bounded");
    let path = scratch.db();
    made_by_hand(
        &path,
        &format!("{OUR_TABLES} INSERT INTO mazes VALUES ('{MAZE}', printf('%.*c', 2000000, 'x'), 1);"),
    );
    let err = Sqlite::open_to_read(&path).unwrap().mazes(None).expect_err("a 2 MB name read");
    assert_eq!(err.fault, Fault::Damaged, "{err}");
    assert!(err.to_string().contains("too big"), "{err}");

    // (opened empty, within its budget; then filled by another program)
    std::fs::remove_file(&path).unwrap();
    let small = SqliteOptions { max_steps: 100_000, ..SqliteOptions::default() };
    let (mut db, aside) = Sqlite::open(&path, small).unwrap();
    assert_eq!(aside, None);
    rusqlite::Connection::open(&path)
        .unwrap()
        .execute_batch(&format!(
            "INSERT INTO mazes VALUES ('{MAZE}', 'm', 1);
             WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n LIMIT 20000)
             INSERT INTO finishes SELECT '{MAZE}', 'p' || (i % 5000), i, i, NULL FROM n;"
        ))
        .unwrap();
    let err = db.mazes(None).expect_err("20,000 finishes listed in 100,000 steps");
    assert_eq!(err.fault, Fault::TooCostly, "{err}");
    // the budget is each call's: a call within it still works
    assert!(db.knows(&MAZE).unwrap());
    let listed = Sqlite::open_to_read(&path).unwrap().mazes(None).unwrap();
    assert_eq!((listed[0].finishes, listed[0].players), (20_000, 5000), "within the default budget");
}
