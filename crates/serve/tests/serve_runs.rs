//! Issue #43: runs kept with the finishes in the records database (real SQLite): the best ten
//! players' bests keep their runs and no others, a file of the previous schema is migrated in place,
//! and the records thread offers the maze's best run to its players only once it decodes and stays
//! inside the maze (a damaged one is said, and is no ghost).
#![cfg(unix)]

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glam::Vec2;
use mazewalk_maze::{Aabb, ContentHash};
use mazewalk_serve::records::{Finish, Race, Records, Sqlite, SqliteOptions, Store};
use mazewalk_testkit::collector;
use mazewalk_testkit::scratch::Scratch;
use mazewalk_walk::run::{Pose, Run};

const MAZE: ContentHash = ContentHash([7; 32]);
const EXTENTS: Aabb = Aabb { min: Vec2::ZERO, max: Vec2::new(100.0, 100.0) };

/// A run of `seconds` walking east from (2, 2).
fn run(holder: &str, seconds: f64) -> Run {
    let millis = (seconds * 1000.0) as u32;
    let samples = (0..=millis / 100)
        .map(|k| Pose { position: Vec2::new(2.0 + 0.1 * k as f32, 2.0), yaw_deg: 0.0, pitch_deg: 0.0 })
        .collect();
    Run { maze: MAZE, holder: holder.into(), millis, samples }
}

fn finish(player: &str, seconds: f64) -> Finish {
    let run = run(player, seconds).encode().unwrap();
    Finish {
        maze: MAZE,
        maze_name: "m".into(),
        player: player.into(),
        seconds,
        at: 1_800_000_000,
        run: Some(run),
    }
}

#[test]
fn the_best_ten_players_bests_keep_their_runs() {
    let scratch = Scratch::new("top");
    let (mut db, _) = Sqlite::open(&scratch.db(), SqliteOptions::default()).unwrap();
    assert_eq!(db.run(&MAZE, None).unwrap(), None, "no finish, no run");
    db.record(&finish("ada", 30.0)).unwrap();
    db.record(&finish("ada", 20.0)).unwrap();
    db.record(&finish("ada", 25.0)).unwrap(); // slower than her best: its run is not kept
    let best = db.run(&MAZE, None).unwrap().expect("the best run");
    assert_eq!((best.player.as_str(), best.seconds), ("ada", 20.0));
    assert_eq!(best.bytes, run("ada", 20.0).encode().unwrap(), "the best finish's own run");
    for k in 0..12 {
        db.record(&finish(&format!("p{k:02}"), 40.0 + f64::from(k))).unwrap();
    }
    let conn = rusqlite::Connection::open(scratch.db()).unwrap();
    let kept: Vec<(String, f64)> = conn
        .prepare("SELECT player, seconds FROM finishes WHERE run IS NOT NULL ORDER BY seconds")
        .unwrap()
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(kept.len(), 10, "{kept:?}");
    assert_eq!(kept[0], ("ada".into(), 20.0));
    assert_eq!(kept[9], ("p08".into(), 48.0), "the tenth player's best; none after");
    assert_eq!(db.run(&MAZE, Some("p03")).unwrap().map(|r| r.seconds), Some(43.0));
    assert_eq!(db.run(&MAZE, Some("p11")).unwrap(), None, "eleventh: no run kept");
    let finishes: i64 = conn.query_row("SELECT COUNT(*) FROM finishes", [], |r| r.get(0)).unwrap();
    assert_eq!(finishes, 15, "every finish is kept, with or without its run");
}

#[test]
fn a_records_file_of_the_previous_schema_is_migrated_and_keeps_its_finishes() {
    let scratch = Scratch::new("migrate");
    {
        // version 1, as the previous mazewalk made it
        let conn = rusqlite::Connection::open(scratch.db()).unwrap();
        conn.execute_batch(
            "CREATE TABLE mazes (hash TEXT PRIMARY KEY, name TEXT NOT NULL, first_seen INTEGER NOT NULL);
             CREATE TABLE finishes (maze TEXT NOT NULL REFERENCES mazes(hash), player TEXT NOT NULL,
                                    seconds REAL NOT NULL, at INTEGER NOT NULL);
             CREATE INDEX finishes_by_maze ON finishes (maze, player, seconds);
             INSERT INTO mazes VALUES ('0707070707070707070707070707070707070707070707070707070707070707', 'm', 1);
             INSERT INTO finishes VALUES ('0707070707070707070707070707070707070707070707070707070707070707', 'old', 9.0, 1);
             PRAGMA user_version = 1;",
        )
        .unwrap();
    }
    // read only, an old file reads as it is: finishes, no runs
    let mut reader = Sqlite::open_to_read(&scratch.db()).unwrap();
    assert_eq!(reader.mazes(Some(&MAZE)).unwrap()[0].top[0].player, "old");
    assert_eq!(reader.run(&MAZE, None).unwrap(), None);
    drop(reader);
    let (mut db, aside) = Sqlite::open(&scratch.db(), SqliteOptions::default()).unwrap();
    assert_eq!(aside, None, "migrated, not kept aside");
    let s = db.record(&finish("ada", 12.0)).unwrap();
    assert_eq!((s.players, s.top[0].player.as_str()), (2, "old"), "the old finish is still there");
    assert_eq!(db.run(&MAZE, None).unwrap().map(|r| r.player), Some("ada".into()));
    let conn = rusqlite::Connection::open(scratch.db()).unwrap();
    let version: i64 = conn.query_row("PRAGMA user_version", [], |r| r.get(0)).unwrap();
    assert_eq!(version, 2);
}

/// Waits (bounded) until `f` holds.
fn eventually(what: &str, f: impl Fn() -> bool) {
    let until = Instant::now() + Duration::from_secs(20);
    while !f() {
        assert!(Instant::now() < until, "{what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The records thread of a race on [`MAZE`] over a store that already holds bob's 50 s run, and
/// what it reports.
fn racing_after_bobs_run(scratch: &Scratch) -> (Records, Arc<Mutex<Vec<String>>>) {
    {
        let (mut db, _) = Sqlite::open(&scratch.db(), SqliteOptions::default()).unwrap();
        db.record(&finish("bob", 50.0)).unwrap();
    }
    let race = Race { maze: MAZE, extents: EXTENTS };
    let (db, _) = Sqlite::open(&scratch.db(), SqliteOptions::default()).unwrap();
    let (report, said) = collector();
    (Records::start_racing(db, report, Some(race)).unwrap(), said)
}

#[test]
fn the_records_thread_offers_the_best_run_checked_and_refuses_a_damaged_one() {
    let scratch = Scratch::new("offer");
    let (records, said) = racing_after_bobs_run(&scratch);
    eventually("the stored best run at start", || records.best_run().is_some());
    assert_eq!(records.best_run().unwrap().holder, "bob");
    // a better finish: its run is offered next
    drop(records.finish(finish("ada", 20.0)).unwrap());
    eventually("ada's run offered", || records.best_run().is_some_and(|r| r.holder == "ada"));
    assert!(said.lock().unwrap().is_empty());
    // a better finish whose run leaves the maze: said, and no ghost (not bob's either: the best is
    // the best, a damaged one is none)
    let mut outside = run("eve", 10.0);
    outside.samples[5].position.x = 5000.0;
    let bad = Finish { run: Some(outside.encode().unwrap()), ..finish("eve", 10.0) };
    drop(records.finish(bad).unwrap());
    eventually("the damaged run refused", || records.best_run().is_none());
    let lines = said.lock().unwrap().clone();
    assert!(lines.iter().any(|l| l.contains("eve's") && l.contains("outside the maze")), "{lines:?}");
    // garbage written into the file by anything else: refused the same way
    let conn = rusqlite::Connection::open(scratch.db()).unwrap();
    conn.execute("UPDATE finishes SET run = x'4d5a52554e01ff' WHERE player = 'eve'", []).unwrap();
    drop(records.finish(finish("zed", 60.0)).unwrap());
    eventually("a second report", || said.lock().unwrap().len() >= 2);
    assert!(records.best_run().is_none());
    assert!(records.close(Duration::from_secs(10)));
}

// Issue #43: another server's better run (here written to the same file by another store, as
// another server in the world writes to its Redis) is offered within a few seconds once asked
// (`Records::reread_best_run`, which a remote finish calls), not at the 30 s reread; asking again
// and again while a request waits queues no more than one, and never drops a finish.
#[test]
fn an_asked_reread_offers_another_servers_better_run_within_seconds() {
    let scratch = Scratch::new("reread");
    let (records, said) = racing_after_bobs_run(&scratch);
    eventually("bob's run at start", || records.best_run().is_some_and(|r| r.holder == "bob"));
    // "another server": ada's better finish, straight into the store
    {
        let (mut other, _) = Sqlite::open(&scratch.db(), SqliteOptions::default()).unwrap();
        other.record(&finish("ada", 20.0)).unwrap();
    }
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(records.best_run().unwrap().holder, "bob", "read again unasked");
    let asked = Instant::now();
    for _ in 0..1000 {
        records.reread_best_run(); // one request queued, the rest the same one
    }
    eventually("ada's run offered", || records.best_run().is_some_and(|r| r.holder == "ada"));
    assert!(asked.elapsed() < Duration::from_secs(5), "{:?}", asked.elapsed());
    // the queue was not filled by the requests: a finish still gets its standing
    let standing = records.finish(finish("cy", 30.0)).expect("queued, not dropped");
    assert!(standing.blocking_recv().unwrap().is_some());
    assert_eq!(records.dropped(), 0);
    assert!(said.lock().unwrap().is_empty());
    assert!(records.close(Duration::from_secs(10)));
}
