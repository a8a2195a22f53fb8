//! Issue #35: a shared world's best times in a real `redis-server` (started on a free loopback port,
//! killed at the end), behind the records' `Store`: two servers' stores rank their players together,
//! a slower finish keeps the best, what Redis holds that is not a name and a time stays out of the
//! table, and a Redis away fails one finish (a transient fault) without ending the records.
#![cfg(target_os = "linux")]

use mazewalk_testkit::redis_async as redis_server;

use mazewalk_maze::ContentHash;
use mazewalk_serve::records::{Fault, Finish, Store};
use mazewalk_serve::shared::records::RedisStore;
use redis_server::{Persistence, RedisServer};

fn finish(maze: ContentHash, player: &str, seconds: f64, at: i64) -> Finish {
    Finish { maze, maze_name: "maze.grid".into(), player: player.into(), seconds, at, run: None }
}

#[test]
fn two_servers_keep_one_table_of_best_times_in_redis() {
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let mut redis = runtime.block_on(RedisServer::start(Persistence::None));
    let maze = ContentHash([7; 32]);
    // (The stores run on the records thread, outside any runtime: here, the test's own thread.)
    let mut a = RedisStore::new(&redis.url(0), None, maze).expect("store A");
    let mut b = RedisStore::new(&redis.url(0), None, maze).expect("store B");

    let alice = a.record(&finish(maze, "alice", 61.5, 1_000)).expect("alice's finish");
    assert_eq!((alice.rank, alice.players, alice.best), (1, 1, 61.5));
    let bob = b.record(&finish(maze, "bob", 12.0, 1_001)).expect("bob's finish");
    assert_eq!((bob.rank, bob.players), (1, 2), "ranked among both servers' players");
    let names: Vec<(&str, f64, i64)> = bob.top.iter().map(|t| (t.player.as_str(), t.seconds, t.at)).collect();
    assert_eq!(names, [("bob", 12.0, 1_001), ("alice", 61.5, 1_000)]);
    // A slower finish keeps the best (and when it was made); a better one replaces it.
    let again = a.record(&finish(maze, "alice", 70.0, 1_002)).expect("slower");
    assert_eq!((again.best, again.rank), (61.5, 2));
    assert_eq!(again.top[1].at, 1_000);
    let better = a.record(&finish(maze, "alice", 10.0, 1_003)).expect("better");
    assert_eq!((better.best, better.rank, better.top[0].player.as_str()), (10.0, 1, "alice"));

    // The world task may put a finish's time in the set before the records do: its date is kept all
    // the same.
    runtime.block_on(async {
        let mut con = redis.connection(0).await;
        let best = "mazewalk:{0707070707070707}:best";
        let _: i64 =
            redis::cmd("ZADD").arg(best).arg("LT").arg(40.0).arg("dave").query_async(&mut con).await.unwrap();
    });
    let dave = b.record(&finish(maze, "dave", 40.0, 1_006)).expect("dave's finish");
    assert_eq!(dave.top.iter().find(|t| t.player == "dave").map(|t| t.at), Some(1_006));

    // What Redis holds is untrusted: a name no player has, a time that is not one, stay out.
    runtime.block_on(async {
        let mut con = redis.connection(0).await;
        let best = "mazewalk:{0707070707070707}:best";
        let _: i64 =
            redis::cmd("ZADD").arg(best).arg(1.0).arg("\x1b[2Jevil").query_async(&mut con).await.unwrap();
        let _: i64 = redis::cmd("ZADD").arg(best).arg("-inf").arg("neg").query_async(&mut con).await.unwrap();
    });
    let records = b.mazes(Some(&maze)).expect("the world's records");
    assert_eq!(records.len(), 1);
    let shown: Vec<&str> = records[0].top.iter().map(|t| t.player.as_str()).collect();
    assert_eq!(shown, ["alice", "bob", "dave"], "{records:?}");
    assert_eq!((records[0].finishes, records[0].name.as_str()), (5, "maze.grid"));
    assert!(b.mazes(Some(&ContentHash([8; 32]))).expect("another maze").is_empty());

    // Redis away: that finish fails as a passing fault; back, the next is kept.
    redis.stop();
    let err = a.record(&finish(maze, "carol", 30.0, 1_004)).expect_err("Redis is away");
    assert_eq!(err.fault, Fault::Unreachable, "{err}");
    assert!(err.is_transient());
    runtime.block_on(redis.restart());
    let carol = a.record(&finish(maze, "carol", 30.0, 1_005)).expect("Redis is back");
    assert_eq!((carol.rank, carol.players), (1, 1), "an empty Redis after the restart");

    // A connection left idle across a restart failed its next read ("broken pipe", logged by the
    // records thread as "cannot read the best run"): a read is asked again on a new connection.
    assert!(b.run(&maze, None).expect("a read on B's connection").is_none(), "carol kept no run");
    runtime.block_on(redis.restart());
    assert!(b.run(&maze, None).expect("a read after Redis came back").is_none());
    let records = b.mazes(Some(&maze)).expect("and the records, on the same connection");
    assert!(records.is_empty() || records[0].top.is_empty(), "{records:?}");
}

/// A run of `seconds` walking east from (2, 2) in the maze of hash `maze`, encoded.
fn run_bytes(maze: ContentHash, holder: &str, seconds: f64) -> Vec<u8> {
    use mazewalk_walk::run::{Pose, Run};
    let millis = (seconds * 1000.0) as u32;
    let samples = (0..=millis / 100)
        .map(|k| Pose { position: glam::Vec2::new(2.0 + 0.1 * k as f32, 2.0), yaw_deg: 0.0, pitch_deg: 0.0 })
        .collect();
    Run { maze, holder: holder.into(), millis, samples }.encode().unwrap()
}

// Issue #43: a world keeps the runs of its best players' bests in Redis, one per player, and gives
// back the best run — never more than a run's cap, whatever Redis holds.
#[test]
fn a_world_keeps_its_best_runs_in_redis_bounded() {
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let redis = runtime.block_on(RedisServer::start(Persistence::None));
    let maze = ContentHash([7; 32]);
    let mut a = RedisStore::new(&redis.url(0), None, maze).expect("store A");
    let mut b = RedisStore::new(&redis.url(0), None, maze).expect("store B");
    assert_eq!(a.run(&maze, None).expect("no run yet"), None);
    let with_run = |player: &str, seconds: f64| Finish {
        run: Some(run_bytes(maze, player, seconds)),
        ..finish(maze, player, seconds, 1_000)
    };
    a.record(&with_run("alice", 30.0)).expect("alice");
    b.record(&with_run("bob", 20.0)).expect("bob");
    a.record(&with_run("alice", 40.0)).expect("alice, slower: her run stays the 30 s one");
    let best = a.run(&maze, None).expect("the best run").expect("kept");
    assert_eq!((best.player.as_str(), best.seconds), ("bob", 20.0));
    assert_eq!(best.bytes, run_bytes(maze, "bob", 20.0), "read by the other server's store");
    let alice = b.run(&maze, Some("alice")).expect("alice's").expect("kept");
    assert_eq!(alice.bytes, run_bytes(maze, "alice", 30.0));
    assert_eq!(a.run(&ContentHash([8; 32]), None).expect("another maze"), None);
    // Redis holds anything: bob's run swapped for more than a run may be, it is not read back (the
    // next one with a run is); a hash stuffed with others' fields is cleared at the next write
    runtime.block_on(async {
        let mut con = redis.connection(0).await;
        let runs = "mazewalk:{0707070707070707}:runs";
        let huge = vec![b'x'; mazewalk_walk::run::MAX_BYTES + 1];
        let _: i64 = redis::cmd("HSET").arg(runs).arg("bob").arg(huge).query_async(&mut con).await.unwrap();
        for k in 0..100 {
            let _: i64 = redis::cmd("HSET")
                .arg(runs)
                .arg(format!("junk{k}"))
                .arg("x")
                .query_async(&mut con)
                .await
                .unwrap();
        }
    });
    let next = a.run(&maze, None).expect("the best run").expect("alice's, bob's being too long");
    assert_eq!(next.player, "alice");
    b.record(&with_run("carol", 25.0)).expect("carol");
    let fields: usize = runtime.block_on(async {
        let mut con = redis.connection(0).await;
        redis::cmd("HLEN").arg("mazewalk:{0707070707070707}:runs").query_async(&mut con).await.unwrap()
    });
    assert_eq!(fields, 1, "the junk cleared; carol's run kept");
}

/// Red-team pass 3: one best-times member that is not UTF-8 (`ZADD …:best 0.5 "\xff\xfe"`) failed
/// every later finish of the world ("Incompatible type - Cannot convert from UTF-8"), and so did a
/// `:at` that is not a number. What Redis holds is read as bytes: such entries are left out and
/// counted, a `:at` or a count that is not a number reads as 0 (a count that is none does not fail
/// the finish either), a maze name that is not UTF-8 is read lossily; the finish is kept and ranked.
#[test]
fn bytes_that_are_not_utf_8_in_redis_are_left_out_not_fatal() {
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let redis = runtime.block_on(RedisServer::start(Persistence::None));
    let maze = ContentHash([7; 32]);
    let mut store = RedisStore::new(&redis.url(0), None, maze).expect("store");
    store.record(&finish(maze, "alice", 61.5, 1_000)).expect("alice's finish");
    store
        .record(&Finish { run: Some(run_bytes(maze, "alice", 61.5)), ..finish(maze, "alice", 61.0, 1_001) })
        .expect("alice's run");
    let link =
        mazewalk_serve::shared::redis::Link::new(&redis.url(0), &maze.to_string(), None).expect("link");
    runtime.block_on(async {
        let mut con = redis.connection(0).await;
        let tag = "mazewalk:{0707070707070707}";
        let best = format!("{tag}:best");
        for member in [&b"\xff\xfe"[..], b"ok\xc3", b"\xe2\x82"] {
            let _: i64 =
                redis::cmd("ZADD").arg(&best).arg(0.5).arg(member).query_async(&mut con).await.unwrap();
        }
        let _: i64 = redis::cmd("HSET")
            .arg(format!("{best}:at"))
            .arg("alice")
            .arg(&b"\xffsoon"[..])
            .query_async(&mut con)
            .await
            .unwrap();
        let _: i64 = redis::cmd("HSET")
            .arg(format!("{tag}:runs"))
            .arg(&b"\xff"[..])
            .arg("x")
            .query_async(&mut con)
            .await
            .unwrap();
        let _: () =
            redis::cmd("SET").arg(format!("{tag}:finishes")).arg("many").query_async(&mut con).await.unwrap();
        let _: () = redis::cmd("SET")
            .arg(format!("{tag}:name"))
            .arg(&b"maze\xff"[..])
            .query_async(&mut con)
            .await
            .unwrap();
        // (the world task's own reading of the best times: the same answer)
        let shown =
            mazewalk_serve::shared::redis::best(&mut con, &link.keys, 10).await.expect("the best times");
        assert_eq!(shown, [("alice".to_string(), 61.0)]);
    });
    let bob = store
        .record(&Finish { run: Some(run_bytes(maze, "bob", 12.0)), ..finish(maze, "bob", 12.0, 1_002) })
        .expect("bob's finish, with garbage in Redis");
    let shown: Vec<(&str, f64, i64)> = bob.top.iter().map(|t| (t.player.as_str(), t.seconds, t.at)).collect();
    assert_eq!(shown, [("bob", 12.0, 1_002), ("alice", 61.0, 0)], "a :at that is no number reads as 0");
    assert_eq!((bob.rank, bob.players), (4, 5), "ranked in Redis's own count, behind the three left out");
    assert!(store.left_out() >= 4, "left out and counted: {}", store.left_out());
    let records = store.mazes(Some(&maze)).expect("the world's records");
    assert_eq!(records[0].name, "maze\u{fffd}");
    assert_eq!(records[0].finishes, 0, "a count that is no number reads as 0");
    assert_eq!(records[0].top.len(), 2);
    let run = store.run(&maze, None).expect("the best run").expect("bob's");
    assert_eq!(run.player, "bob");
    runtime.block_on(async {
        let mut con = redis.connection(0).await;
        let fields: Vec<Vec<u8>> =
            redis::cmd("HKEYS").arg("mazewalk:{0707070707070707}:runs").query_async(&mut con).await.unwrap();
        assert!(!fields.contains(&b"\xff".to_vec()), "a field that is no player's went with the others");
    });
}
