//! Red-team pass 8, finding 2: a Redis writer stored best-time members of 40 MB and presence keys
//! named with 20 MB, and a server read them whole (RSS 11 → 364 MB; 16 names: 373 MB at its peak).
//! Every read from the world's Redis is now bounded by the server's own request: Redis sends no
//! member longer than a player's name, no date longer than a date, no field of the runs nor name
//! under the presence prefix at all unless it can be one, no count longer than a count; what it
//! leaves out is counted. Each test starts its own `redis-server` on a free loopback port, plays the
//! writer (its big values made inside Redis by a script, so that this process never holds them),
//! and measures what Redis sent (`total_net_output_bytes`) and this process's peak resident memory
//! while the server reads.
#![cfg(target_os = "linux")]

use mazewalk_testkit::redis_async as redis_server;
use mazewalk_testkit::world_host as host;

use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use glam::Vec2;
use host::{TestHost, at};
use mazewalk_maze::ContentHash;
use mazewalk_serve::records::{Finish, Store};
use mazewalk_serve::shared::codec::{self, Body, Bounds, Message, PlayerRecord, ServerId, maze_tag};
use mazewalk_serve::shared::records::RedisStore;
use mazewalk_serve::shared::redis::{Keys, Link, best};
use mazewalk_serve::shared::{SharedWorld, WorldConfig};
use mazewalk_testkit::eventually;
use mazewalk_testkit::memory::{peak_kb, reset_peak};
use redis_server::{Persistence, RedisServer, net_output_bytes};

/// The tests of this file measure the whole process's memory: one at a time (under `cargo test`,
/// which runs them on threads of one process; nextest gives each a process of its own).
static MEMORY: Mutex<()> = Mutex::new(());

/// What Redis may send for all the reads a test makes, at most: a few commands' answers, of short
/// names and dates (and `INFO`'s own, about 2 KB). Before, the first read alone was tens of MB.
const SENT_AT_MOST: u64 = 64 * 1024;

/// This process's resident memory may grow by this much at most while the server reads (a tokio
/// runtime's worker stacks and buffers; before, it grew by about twice what Redis sent).
const GROWTH_AT_MOST_KB: u64 = 8 * 1024;

/// Runs `script` (a writer's) with `keys` and `args` in the test's Redis (on a connection with no
/// response timeout: a script making MBs may take a while), with `big(c, n)` (`n` bytes of `c`).
async fn writer(redis: &RedisServer, script: &str, keys: &[&str], args: &[&str]) {
    let client = redis::Client::open(redis.url(0)).expect("the URL");
    let config = redis::AsyncConnectionConfig::new().set_response_timeout(None);
    let mut con = client.get_multiplexed_async_connection_with_config(&config).await.expect("Redis answers");
    let big =
        "local function big(c, n) local s = c while #s < n do s = s .. s end return string.sub(s, 1, n) end ";
    let mut eval = redis::cmd("EVAL");
    eval.arg(format!("{big}{script}")).arg(keys.len()).arg(keys).arg(args);
    let _: redis::Value = eval.query_async(&mut con).await.expect("the writer's script");
}

/// A run of `seconds` walking east from (2, 2) in the maze of hash `maze`, encoded.
fn run_bytes(maze: ContentHash, holder: &str, seconds: f64) -> Vec<u8> {
    use mazewalk_walk::run::{Pose, Run};
    let millis = (seconds * 1000.0) as u32;
    let samples = (0..=millis / 100)
        .map(|k| Pose { position: Vec2::new(2.0 + 0.1 * k as f32, 2.0), yaw_deg: 0.0, pitch_deg: 0.0 })
        .collect();
    Run { maze, holder: holder.into(), millis, samples }.encode().unwrap()
}

fn finish(maze: ContentHash, player: &str, seconds: f64) -> Finish {
    Finish {
        maze,
        maze_name: "maze.grid".into(),
        player: player.into(),
        seconds,
        at: 1_000,
        run: Some(run_bytes(maze, player, seconds)),
    }
}

/// Each writer's value: 4 MB.
const BIG: usize = 4 << 20;

/// The best times hold 5 members of 4 MB ahead of everyone, bob's date is 4 MB, the runs hold 4
/// fields named with 4 MB, the count of finishes and the maze's name are 4 MB: a finish, the
/// records, the best run and the world task's best times read only the players' entries (bob's
/// date as none, the name cut), count what they left out, and Redis sends a few KB in all.
#[test]
fn the_records_never_read_a_member_a_date_or_a_field_longer_than_theirs() {
    let _one = MEMORY.lock().unwrap_or_else(PoisonError::into_inner);
    let runtime = tokio::runtime::Runtime::new().expect("a runtime");
    let redis = runtime.block_on(RedisServer::start(Persistence::None));
    let maze = ContentHash([7; 32]);
    let mut store = RedisStore::new(&redis.url(0), None, maze).expect("store");
    store.record(&finish(maze, "alice", 30.0)).expect("alice's finish");
    store.record(&finish(maze, "bob", 40.0)).expect("bob's finish");
    let link = Link::new(&redis.url(0), &maze.to_string(), None).expect("link");
    let tag = "mazewalk:{0707070707070707}";
    let mut con = runtime.block_on(redis.connection(0));
    runtime.block_on(writer(
        &redis,
        "for i = 1, 5 do redis.call('ZADD', KEYS[1], i / 1000, big(string.char(64 + i), tonumber(ARGV[1]))) end \
         redis.call('HSET', KEYS[2], 'bob', big('9', tonumber(ARGV[1]))) \
         for i = 1, 4 do redis.call('HSET', KEYS[3], big(string.char(96 + i), tonumber(ARGV[1])), 'x') end \
         redis.call('SET', KEYS[4], big('7', tonumber(ARGV[1]))) \
         redis.call('SET', KEYS[5], big('m', tonumber(ARGV[1])))",
        &[
            &format!("{tag}:best"),
            &format!("{tag}:best:at"),
            &format!("{tag}:runs"),
            &format!("{tag}:finishes"),
            &format!("{tag}:name"),
        ],
        &[&BIG.to_string()],
    ));

    let sent = runtime.block_on(net_output_bytes(&mut con)).expect("INFO");
    let left_out = store.left_out();
    let base = reset_peak();
    let carol = store.record(&finish(maze, "carol", 35.0)).expect("carol's finish");
    let records = store.mazes(Some(&maze)).expect("the records");
    let run = store.run(&maze, None).expect("the best run").expect("alice's");
    let world = runtime.block_on(best(&mut con, &link.keys, 10)).expect("the world task's best times");
    let growth = peak_kb() - base;
    let sent = runtime.block_on(net_output_bytes(&mut con)).expect("INFO") - sent;
    eprintln!("Redis sent {sent} bytes; this process grew by {growth} kB at its peak");
    assert!(sent <= SENT_AT_MOST, "Redis sent {sent} bytes");
    assert!(growth <= GROWTH_AT_MOST_KB, "this process grew by {growth} kB");

    let shown: Vec<(&str, f64, i64)> =
        carol.top.iter().map(|t| (t.player.as_str(), t.seconds, t.at)).collect();
    assert_eq!(
        shown,
        [("alice", 30.0, 1_000), ("carol", 35.0, 1_000), ("bob", 40.0, 0)],
        "bob's date is none"
    );
    assert_eq!((carol.rank, carol.players), (7, 8), "ranked in Redis's own count, behind the 6 ahead");
    assert_eq!(records[0].top, carol.top);
    assert_eq!(records[0].finishes, 0, "a count longer than a count reads as none");
    assert_eq!(records[0].name, "m".repeat(256), "the name is cut");
    assert_eq!((run.player.as_str(), run.bytes), ("alice", run_bytes(maze, "alice", 30.0)));
    assert_eq!(world, [("alice".to_string(), 30.0), ("carol".into(), 35.0), ("bob".into(), 40.0)]);
    let fields: usize =
        runtime.block_on(redis::cmd("HLEN").arg(format!("{tag}:runs")).query_async(&mut con)).expect("HLEN");
    assert_eq!(fields, 3, "the writer's fields went, unread; carol's run came");
    // Each read of the best times: 5 members and bob's date; the finish: the count it could not
    // add to and the 4 fields; the records: the count.
    assert_eq!(store.left_out() - left_out, 3 * 6 + 1 + 4 + 1, "each one left out, counted");
}

const MAZE: &str = "11a70123456789abcdef11a70123456789abcdef";

/// A full message of invented server `server` with one player, `name`.
fn full(server: u64, name: &str) -> Vec<u8> {
    let player =
        PlayerRecord { id: 1, joined_ms: 0, color: 1, label: 'Z', name: name.into(), at: at(2.0, 2.0) };
    let message = Message {
        maze: maze_tag(MAZE),
        server: ServerId(server),
        seq: 1,
        sent_ms: 0,
        body: Body::Full { players: vec![player], finished: vec![], winner: None },
    };
    let mut out = Vec::new();
    codec::encode(&message, &mut out);
    out
}

/// 16 keys under the presence prefix named with 2 MB each, one named as a server's but a list,
/// another holding more than a message: a server joining the world reads the one true presence
/// (zed's server's), counts the 2 that hold no message (Redis sends neither, nor the 16 names), and
/// Redis sends a few KB.
#[test]
fn presence_keys_of_any_name_or_size_are_read_with_bounds() {
    let _one = MEMORY.lock().unwrap_or_else(PoisonError::into_inner);
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    runtime.block_on(async {
        let redis = RedisServer::start(Persistence::None).await;
        let mut con = redis.connection(0).await;
        let keys = Keys::new(MAZE, 0);
        writer(
            &redis,
            "for i = 1, 16 do redis.call('SET', ARGV[1] .. big(string.char(96 + i), tonumber(ARGV[2])), 'x') end \
             redis.call('RPUSH', KEYS[1], 'x') \
             redis.call('SET', KEYS[2], big('M', tonumber(ARGV[3])))",
            &[&keys.server(ServerId(0x1157)), &keys.server(ServerId(0xb16))],
            &[&keys.servers, &(2 << 20).to_string(), &(1 << 20).to_string()],
        )
        .await;
        let zed = keys.server(ServerId(0x5e));
        let _: () = redis::cmd("SET").arg(zed).arg(full(0x5e, "zed")).query_async(&mut con).await.unwrap();

        let sent = net_output_bytes(&mut con).await.expect("INFO");
        let base = reset_peak();
        let a = Arc::new(TestHost::default());
        let bounds = Bounds { min: Vec2::ZERO, max: Vec2::splat(100.0), cells: 100 };
        let world_a = SharedWorld::join(
            WorldConfig::new(&redis.url(0), MAZE, bounds),
            Arc::clone(&a) as Arc<dyn mazewalk_serve::shared::Host>,
        )
        .await
        .expect("joins the world");
        eventually(Duration::from_secs(3), "zed, from his server's presence key", || a.other("zed").is_some()).await;
        eventually(Duration::from_secs(1), "the others counted", || world_a.stats().presences_left_out >= 2).await;
        let growth = peak_kb() - base;
        let sent = net_output_bytes(&mut con).await.expect("INFO") - sent;
        eprintln!("Redis sent {sent} bytes; this process grew by {growth} kB at its peak");
        assert!(sent <= SENT_AT_MOST, "Redis sent {sent} bytes");
        assert!(growth <= GROWTH_AT_MOST_KB, "this process grew by {growth} kB");
        let stats = world_a.stats();
        assert_eq!(stats.presences_left_out, 2, "{stats:?}");
        assert_eq!((stats.heard.dropped, a.lock().others.len()), (0, 1), "only zed's presence was read: {stats:?}");
        assert!(stats.online && stats.outages == 0, "{stats:?}");
        world_a.leave().await;
    });
}
