//! Issue #40: Redis as a peer that may lie. Anyone with the Redis password can publish on the world's
//! channel and write its keys; each test starts its own `redis-server` on a free loopback port and
//! plays that writer against world tasks (`mazewalk_testkit::world_host`): the caps bound what an invented
//! crowd can put in view (and count the rest), a winner a message claims is never shown nor written
//! back, a flood of winner claims makes a bounded number of log lines and Redis reads, and names
//! from Redis that are not player names never reach a host.
#![cfg(target_os = "linux")]

use mazewalk_testkit::redis_async as redis_server;
use mazewalk_testkit::world_host as host;

use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use glam::Vec2;
use host::{TestHost, at};
use mazewalk_serve::shared::codec::{
    self, Body, Bounds, Finish, Message, PlayerRecord, ServerId, WinnerRecord, maze_tag,
};
use mazewalk_serve::shared::redis::Keys;
use mazewalk_serve::shared::{Caps, SharedWorld, WorldConfig};
use mazewalk_testkit::eventually;
use redis::aio::MultiplexedConnection;
use redis_server::{Persistence, RedisServer};

const MAZE: &str = "11a70123456789abcdef11a70123456789abcdef";

fn config(redis: &RedisServer) -> WorldConfig {
    let bounds = Bounds { min: Vec2::ZERO, max: Vec2::splat(100.0), cells: 100 };
    WorldConfig::new(&redis.url(0), MAZE, bounds)
}

async fn join(config: WorldConfig, host: &Arc<TestHost>) -> SharedWorld {
    SharedWorld::join(config, Arc::clone(host) as Arc<dyn mazewalk_serve::shared::Host>)
        .await
        .expect("joins the world")
}

/// The log lines of every test in this binary (one subscriber per process); each test picks its
/// own by its Redis's port.
#[derive(Clone, Default)]
struct Log(Arc<Mutex<Vec<u8>>>);

impl Log {
    fn get() -> &'static Log {
        static LOG: OnceLock<Log> = OnceLock::new();
        LOG.get_or_init(|| {
            let log = Log::default();
            let writer = log.clone();
            tracing_subscriber::fmt().with_writer(move || writer.clone()).with_ansi(false).init();
            log
        })
    }

    fn text(&self) -> String {
        String::from_utf8_lossy(&self.0.lock().unwrap()).into_owned()
    }

    /// The lines naming `port` (the world's URL).
    fn lines_of(&self, port: u16) -> Vec<String> {
        let needle = format!("127.0.0.1:{port}");
        self.text().lines().filter(|l| l.contains(&needle)).map(str::to_string).collect()
    }
}

impl std::io::Write for Log {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A full message from invented server `server`.
fn full(
    server: u64,
    seq: u64,
    players: Vec<PlayerRecord>,
    finished: Vec<Finish>,
    winner: Option<WinnerRecord>,
) -> Vec<u8> {
    let message = Message {
        maze: maze_tag(MAZE),
        server: ServerId(server),
        seq,
        sent_ms: 0,
        body: Body::Full { players, finished, winner },
    };
    let mut out = Vec::new();
    codec::encode(&message, &mut out);
    out
}

fn player(id: u32, name: &str) -> PlayerRecord {
    PlayerRecord {
        id,
        joined_ms: 0,
        color: 1,
        label: 'Z',
        name: name.into(),
        at: at(1.0 + id as f32 * 0.01, 1.0),
    }
}

async fn publish(con: &mut MultiplexedConnection, bytes: &[u8]) {
    let keys = Keys::new(MAZE, 0);
    let _: i64 = redis::cmd("PUBLISH").arg(&keys.channel).arg(bytes).query_async(con).await.unwrap();
}

async fn stored_winner(con: &mut MultiplexedConnection) -> Option<Vec<u8>> {
    redis::cmd("GET").arg(Keys::new(MAZE, 0).winner).query_async(con).await.unwrap()
}

/// 10 invented servers of 40 players each against caps of 3 servers and 50 players: the view holds
/// 50 players of 3 servers, the rest counted; a real server is kept out while the crowd lasts, and
/// comes into view once the crowd falls silent.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_caps_bound_what_a_writer_can_put_in_view() {
    let redis = RedisServer::start(Persistence::None).await;
    let a = Arc::new(TestHost::default());
    let caps = Caps { servers: 3, players: 50 };
    let world_a = join(WorldConfig { caps, ..config(&redis) }, &a).await;
    eventually(Duration::from_secs(2), "online", || a.lock().online).await;
    let mut con = redis.connection(0).await;
    let crowd = |k: u64| (0..40).map(|i| player(i, &format!("s{k}p{i}"))).collect::<Vec<_>>();
    let b = Arc::new(TestHost::default());
    b.join("bob", at(2.0, 2.0));
    let mut world_b = None;
    // Three rounds a second apart, as a writer keeping its crowd alive would.
    for round in 1..=3 {
        for k in 0..10 {
            publish(&mut con, &full(0xc0de_0000 + k, round, crowd(k), vec![], None)).await;
        }
        if round == 1 {
            world_b = Some(join(config(&redis), &b).await); // a real server, the eleventh
        }
        tokio::time::sleep(Duration::from_millis(900)).await;
        let others = a.lock().others.clone();
        let servers: std::collections::BTreeSet<ServerId> = others.iter().map(|(s, _)| *s).collect();
        // 40 of the first server, 10 of the second; the third is kept with no room for players.
        assert_eq!((others.len(), servers.len()), (50, 2), "round {round}");
    }
    assert!(a.other("bob").is_none(), "the crowd's servers came first");
    let heard = world_a.stats().heard;
    // Each round: 7 servers over the cap, 30 + 40 players left out; bob's messages over it too.
    assert!(heard.over_servers >= 3 * 7, "{heard:?}");
    assert!(heard.over_players >= 3 * 70, "{heard:?}");
    // The crowd falls silent: within its silence (3 s) and bob's next full message, bob is in view.
    eventually(Duration::from_secs(6), "bob, once the crowd is gone", || a.other("bob").is_some()).await;
    assert_eq!(a.lock().others.len(), 1);
    world_a.leave().await;
    if let Some(world_b) = world_b {
        world_b.leave().await;
    }
}

/// issue #40: one message naming a winner showed "FAKEwinner reached the exit first" everywhere,
/// and after a Redis restart the servers stored it themselves. Now the claim is checked against
/// Redis's winner key: nothing is shown, nothing is stored, before or after a restart; a real win
/// is still announced.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_winner_claimed_in_a_message_is_never_shown_nor_stored() {
    let mut redis = RedisServer::start(Persistence::None).await;
    let (a, b) = (Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    let alice = a.join("alice", at(1.0, 1.0));
    let (world_a, world_b) = (join(config(&redis), &a).await, join(config(&redis), &b).await);
    eventually(Duration::from_secs(2), "online", || a.lock().online && b.lock().online).await;
    let mut con = redis.connection(0).await;
    let fake = WinnerRecord { server: ServerId(0xfa4e), id: 1, seconds: 0.1, name: "FAKEwinner".into() };
    let fake_finish = Finish { id: 1, name: "FAKEwinner".into(), seconds: 0.1, won: true };
    let liar = vec![player(1, "FAKEwinner")];
    publish(&mut con, &full(0xfa4e, 1, liar.clone(), vec![fake_finish], Some(fake.clone()))).await;
    eventually(Duration::from_secs(2), "the liar's player is in view", || a.other("FAKEwinner").is_some())
        .await;
    eventually(Duration::from_secs(2), "Redis was asked", || world_a.stats().winner_reads >= 1).await;
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(a.lock().winners.is_empty() && b.lock().winners.is_empty(), "no winner shown");
    assert_eq!(stored_winner(&mut con).await, None, "none stored");

    redis.restart().await; // empty
    let mut con = redis.connection(0).await;
    eventually(Duration::from_secs(3), "online again", || a.lock().online && b.lock().online).await;
    publish(&mut con, &full(0xfa4e, 2, liar, vec![], Some(fake))).await;
    tokio::time::sleep(Duration::from_millis(1500)).await;
    assert_eq!(stored_winner(&mut con).await, None, "the claim was not written back");
    assert!(a.lock().winners.is_empty() && b.lock().winners.is_empty());

    a.finish(alice, 61.5);
    eventually(Duration::from_secs(2), "both know alice won", || {
        [&a, &b].iter().all(|h| h.lock().winners.iter().map(|w| w.name.as_str()).eq(["alice"]))
    })
    .await;
    let stored = stored_winner(&mut con).await.expect("alice's claim is stored");
    assert_eq!(codec::decode_winner(&stored).map(|w| w.name), Ok("alice".into()));
    world_a.leave().await;
    world_b.leave().await;
}

/// issue #40: once a winner was known, each message naming another (W1, W2, …) logged a line and
/// made every server send a SET: 32.6 MB of log per server in 10 s. Now 20,000 such messages in
/// about 2 s leave the winner as it is, make a few reads of the winner key (one a second at most)
/// and no write, and a bounded log.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flood_of_winner_claims_makes_a_bounded_log_and_a_read_a_second() {
    let log = Log::get();
    let redis = RedisServer::start(Persistence::None).await;
    let a = Arc::new(TestHost::default());
    let alice = a.join("alice", at(1.0, 1.0));
    let world_a = join(config(&redis), &a).await;
    eventually(Duration::from_secs(2), "online", || a.lock().online).await;
    a.finish(alice, 61.5);
    eventually(Duration::from_secs(2), "alice won", || !a.lock().winners.is_empty()).await;
    let mut con = redis.connection(0).await;
    let (sets, lines) =
        (redis_server::command_calls(&mut con, "set").await.unwrap(), log.lines_of(redis.port).len());
    let start = Instant::now();
    let mut sent = 0u64;
    for batch in 0..40u64 {
        let mut pipe = redis::pipe();
        for i in 0..500u64 {
            let n = batch * 500 + i + 1;
            let claim = WinnerRecord { server: ServerId(7), id: 0, seconds: 0.1, name: format!("W{n}") };
            pipe.cmd("PUBLISH")
                .arg(Keys::new(MAZE, 0).channel)
                .arg(full(0xbad, n, vec![], vec![], Some(claim)))
                .ignore();
        }
        pipe.query_async::<()>(&mut con).await.unwrap();
        sent += 500;
    }
    let seconds = start.elapsed().as_secs_f64();
    eventually(Duration::from_secs(5), "the flood is read", || {
        let s = world_a.stats();
        s.heard.applied + s.overflow >= sent
    })
    .await;
    let reads = world_a.stats().winner_reads;
    let new_lines = log.lines_of(redis.port).len() - lines;
    let new_sets = redis_server::command_calls(&mut con, "set").await.unwrap() - sets;
    eprintln!(
        "{sent} claims in {seconds:.2} s: {reads} reads of the winner, {new_sets} SETs, {new_lines} log lines"
    );
    assert!(reads >= 1 && reads as f64 <= seconds + 6.0, "{reads} reads in {seconds:.2} s (and the wait)");
    // Presence keys are SET once a second; the winner is never written.
    assert!(new_sets as f64 <= 2.0 * (seconds + 6.0), "{new_sets} SETs");
    assert!(new_lines <= 5, "{new_lines} lines:\n{}", log.lines_of(redis.port).join("\n"));
    assert_eq!(a.lock().winners.iter().map(|w| w.name.as_str()).collect::<Vec<_>>(), ["alice"]);
    world_a.leave().await;
}

/// Names from Redis that are not player names — in a message, in the winner key, in the best
/// times — never reach a host, and nothing from Redis puts an escape in the log.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hostile_names_from_redis_never_reach_a_host_or_the_log() {
    let log = Log::get();
    let redis = RedisServer::start(Persistence::None).await;
    let mut con = redis.connection(0).await;
    let keys = Keys::new(MAZE, 0);
    let hostile = ["\x1b]52;c;ZXZpbA==\x07", "\x1b]0;owned\x07", "\x1b[2J", "a\u{202e}b"];
    // The winner key holds a record with a hostile name (a writer set it by hand).
    let record = WinnerRecord { server: ServerId(5), id: 1, seconds: 1.0, name: hostile[0].into() };
    let _: () = redis::cmd("SET")
        .arg(&keys.winner)
        .arg(codec::encode_winner(&record))
        .query_async(&mut con)
        .await
        .unwrap();
    for (i, name) in hostile.iter().enumerate() {
        let _: i64 = redis::cmd("ZADD")
            .arg(&keys.best)
            .arg(1.0 + i as f64)
            .arg(*name)
            .query_async(&mut con)
            .await
            .unwrap();
    }
    let _: i64 =
        redis::cmd("ZADD").arg(&keys.best).arg(9.0).arg("carol").query_async(&mut con).await.unwrap();
    let a = Arc::new(TestHost::default());
    let world_a = join(config(&redis), &a).await;
    eventually(Duration::from_secs(2), "online", || a.lock().online).await;
    for (i, name) in hostile.iter().enumerate() {
        let claim = WinnerRecord { server: ServerId(5), id: 1, seconds: 1.0, name: (*name).into() };
        let bytes = full(0x5000 + i as u64, 1, vec![player(1, name)], vec![], Some(claim));
        publish(&mut con, &bytes).await;
    }
    publish(&mut con, &full(0x6000, 1, vec![player(1, "zed")], vec![], None)).await;
    eventually(Duration::from_secs(2), "zed, well-named, is heard", || a.other("zed").is_some()).await;
    assert_eq!(world_a.stats().heard.dropped, hostile.len() as u64, "each hostile message dropped, counted");
    assert_eq!(a.lock().others.len(), 1, "only zed");
    assert!(a.lock().winners.is_empty(), "the winner key's hostile record is not a winner");
    let best = world_a.best(10).await.expect("the records");
    assert_eq!(best, [("carol".to_string(), 9.0)], "hostile names left out of the best times");
    world_a.leave().await;
    let text = log.text();
    assert!(!text.contains('\x1b') && !text.contains('\u{202e}'), "the log holds a raw escape:\n{text:?}");
}

/// Keys a writer set to anything — the winner key a hash, a presence key a list or 1 MB, the
/// world's maze key 1 MB of escapes — are read with bounds: a server joins (or is refused with a
/// short, escaped reason), reads no more than a message's size of any key, and never goes offline
/// over a type error.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn keys_a_writer_set_to_anything_are_read_with_bounds() {
    let redis = RedisServer::start(Persistence::None).await;
    let mut con = redis.connection(0).await;
    let keys = Keys::new(MAZE, 0);
    let _: i64 = redis::cmd("HSET").arg(&keys.winner).arg("f").arg("v").query_async(&mut con).await.unwrap();
    let list = format!("{}00000000000000aa", keys.servers);
    let _: i64 = redis::cmd("RPUSH").arg(&list).arg("x").query_async(&mut con).await.unwrap();
    let huge = format!("{}00000000000000bb", keys.servers);
    let _: () = redis::cmd("SET").arg(&huge).arg(vec![b'M'; 1 << 20]).query_async(&mut con).await.unwrap();
    let a = Arc::new(TestHost::default());
    let alice = a.join("alice", at(1.0, 1.0));
    let world_a = join(config(&redis), &a).await;
    eventually(Duration::from_secs(2), "online", || a.lock().online).await;
    a.finish(alice, 10.0);
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let stats = world_a.stats();
    assert!(stats.online && stats.outages == 0, "no type error took the world offline: {stats:?}");
    assert!(a.lock().winners.is_empty(), "the winner key is not a winner record: no winner");
    // (Read, it would have been refused by the decoder and counted.)
    assert_eq!(stats.heard.dropped, 0, "the 1 MB presence key was not read: {stats:?}");
    world_a.leave().await;

    // The world's maze key, 1 MB of escapes: refused, in a line of reasonable length, escaped.
    let _: () = redis::cmd("SET")
        .arg(&keys.world)
        .arg("\x1b[2J".repeat(250_000))
        .query_async(&mut con)
        .await
        .unwrap();
    let err = SharedWorld::join(config(&redis), Arc::new(TestHost::default())).await.err().expect("refused");
    let text = err.to_string();
    assert!(text.len() < 1000 && !text.contains('\x1b'), "{} bytes: {text:?}", text.len());
}
