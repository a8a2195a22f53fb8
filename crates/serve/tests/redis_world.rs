//! Issue #35: the shared world on a real `redis-server` (each test starts its own on a free loopback
//! port, and kills it at the end): servers joined to one world see each other's players; a server
//! that goes silent leaves the others' views within 5 s; Redis stopped for 10 s freezes the others
//! while every player keeps its pace, and within 2 s of Redis coming back the views agree again;
//! Redis restarted empty or from its file never crowns a second winner; garbage from Redis is
//! dropped and counted; a server with another maze is refused. The servers here are world tasks
//! on one runtime, each with its own host (`mazewalk_testkit::world_host`); the end-to-end test runs
//! `mazewalk serve` processes.
#![cfg(target_os = "linux")]

use mazewalk_testkit::redis_async as redis_server;
use mazewalk_testkit::world_host as host;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use glam::Vec2;
use host::{TestHost, at};
use mazewalk_serve::shared::codec::{
    self, Body, Bounds, Message, PlayerRecord, ServerId, WinnerRecord, maze_tag,
};
use mazewalk_serve::shared::{SharedWorld, WorldConfig, WorldError};
use mazewalk_testkit::eventually;
use redis_server::{Persistence, RedisServer};

const MAZE: &str = "5eed0123456789abcdef5eed0123456789abcdef";

fn bounds() -> Bounds {
    Bounds { min: Vec2::ZERO, max: Vec2::splat(100.0), cells: 100 }
}

fn config(redis: &RedisServer) -> WorldConfig {
    WorldConfig::new(&redis.url(0), MAZE, bounds())
}

async fn join(redis: &RedisServer, host: &Arc<TestHost>) -> SharedWorld {
    SharedWorld::join(config(redis), Arc::clone(host) as Arc<dyn mazewalk_serve::shared::Host>)
        .await
        .expect("joins the world")
}

async fn stored_winner(redis: &RedisServer) -> Option<WinnerRecord> {
    let mut con = redis.connection(0).await;
    let keys = mazewalk_serve::shared::redis::Keys::new(MAZE, 0);
    let bytes: Option<Vec<u8>> = redis::cmd("GET").arg(&keys.winner).query_async(&mut con).await.unwrap();
    bytes.map(|b| codec::decode_winner(&b).expect("a winner record"))
}

/// A player walking a circle at 30 steps a second, its step taken under its host's lock as a
/// player's task takes the world's, and its own lateness measured: how late each step came after
/// its due time (the longest, in microseconds).
struct Walker {
    paused: Arc<AtomicBool>,
    latest: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    task: tokio::task::JoinHandle<()>,
}

impl Walker {
    fn start(host: &Arc<TestHost>, id: u32, centre: Vec2) -> Walker {
        let (paused, latest, stop) =
            (Arc::new(AtomicBool::new(false)), Arc::new(AtomicU64::new(0)), Arc::new(AtomicBool::new(false)));
        let (host, p, l, s) = (Arc::clone(host), Arc::clone(&paused), Arc::clone(&latest), Arc::clone(&stop));
        let task = tokio::spawn(async move {
            let step = Duration::from_secs_f64(1.0 / 30.0);
            let mut due = Instant::now() + step;
            let mut angle = 0.0f32;
            while !s.load(Ordering::Relaxed) {
                tokio::time::sleep_until(due.into()).await;
                let late = Instant::now().saturating_duration_since(due);
                l.fetch_max(late.as_micros() as u64, Ordering::Relaxed);
                if !p.load(Ordering::Relaxed) {
                    angle += 0.05;
                    host.moved(id, at(centre.x + 3.0 * angle.cos(), centre.y + 3.0 * angle.sin()));
                    let _seen = host.lock().others.len(); // a look at the others
                }
                due += step;
            }
        });
        Walker { paused, latest, stop, task }
    }

    fn pause(&self, paused: bool) {
        self.paused.store(paused, Ordering::Relaxed);
    }

    fn latest(&self) -> Duration {
        Duration::from_micros(self.latest.load(Ordering::Relaxed))
    }

    fn reset_latest(&self) {
        self.latest.store(0, Ordering::Relaxed);
    }

    async fn stop(self) {
        self.stop.store(true, Ordering::Relaxed);
        let _ = self.task.await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn servers_share_their_players_and_a_silent_one_leaves_the_views_within_5_s() {
    let redis = RedisServer::start(Persistence::None).await;
    let (a, b, c) =
        (Arc::new(TestHost::default()), Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    let alice = a.join("alice", at(1.0, 1.0));
    let bob = b.join("bob", at(2.0, 2.0));
    let (world_a, world_b) = (join(&redis, &a).await, join(&redis, &b).await);
    eventually(Duration::from_secs(3), "each sees the other", || {
        a.other("bob").is_some_and(|p| p.label == 'B' && p.at == at(2.0, 2.0)) && b.other("alice").is_some()
    })
    .await;
    assert!(a.lock().online && b.lock().online);

    // Moves, joins and leaves reach the other server; a player never sees itself among the others.
    b.moved(bob, at(5.0, 6.0));
    eventually(Duration::from_secs(2), "bob's move", || a.other("bob").is_some_and(|p| p.at == at(5.0, 6.0)))
        .await;
    let bea = b.join("bea", at(3.0, 3.0));
    eventually(Duration::from_secs(2), "bea's join", || a.other("bea").is_some()).await;
    b.leave(bea);
    eventually(Duration::from_secs(2), "bea's leave", || a.other("bea").is_none()).await;
    assert!(a.other("alice").is_none() && b.other("bob").is_none());
    a.moved(alice, at(7.0, 7.0));
    eventually(Duration::from_secs(2), "alice's move", || {
        b.other("alice").is_some_and(|p| p.at == at(7.0, 7.0))
    })
    .await;

    // A server that leaves says goodbye: its players go at once.
    c.join("carol", at(4.0, 4.0));
    let world_c = join(&redis, &c).await;
    eventually(Duration::from_secs(2), "carol arrives", || a.other("carol").is_some()).await;
    world_c.leave().await;
    let gone = eventually(Duration::from_secs(2), "carol leaves", || a.other("carol").is_none()).await;
    assert!(gone < Duration::from_secs(1), "a goodbye is heard at once: {gone:?}");

    // One killed says nothing: its players go when its silence is noticed, within 5 s.
    drop(world_b);
    let killed = Instant::now();
    eventually(Duration::from_secs(5), "bob leaves alice's view after server B died", || {
        a.other("bob").is_none()
    })
    .await;
    assert!(killed.elapsed() > Duration::from_secs(1), "gone by silence, not by a goodbye");
    let stats = world_a.stats();
    assert!(stats.online && stats.heard.applied > 0 && stats.heard.dropped == 0, "{stats:?}");
    world_a.leave().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn redis_stopped_for_10_s_freezes_the_others_and_the_views_agree_within_2_s_of_its_return() {
    let mut redis = RedisServer::start(Persistence::None).await;
    let (a, b) = (Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    let alice = a.join("alice", at(10.0, 10.0));
    let bob = b.join("bob", at(20.0, 20.0));
    let (world_a, world_b) = (join(&redis, &a).await, join(&redis, &b).await);
    let walkers = [Walker::start(&a, alice, Vec2::splat(10.0)), Walker::start(&b, bob, Vec2::splat(20.0))];
    eventually(Duration::from_secs(3), "each sees the other walk", || {
        b.other("alice").is_some() && a.other("bob").is_some()
    })
    .await;
    for w in &walkers {
        w.reset_latest();
    }

    redis.stop();
    let stopped = Instant::now();
    eventually(Duration::from_secs(3), "both servers say the world is offline", || {
        !a.lock().online && !b.lock().online
    })
    .await;
    let frozen = a.other("bob").expect("bob stays in alice's view").at;
    tokio::time::sleep(Duration::from_secs(10).saturating_sub(stopped.elapsed())).await;
    assert_eq!(a.other("bob").map(|p| p.at), Some(frozen), "frozen in place while Redis is away");
    assert_ne!(b.position(bob), frozen.position, "while bob walked on");

    walkers[1].pause(true); // bob stands still from here: the views must agree exactly
    redis.restart().await;
    let back = Instant::now();
    let took = eventually(Duration::from_secs(2), "online again, and alice sees where bob is", || {
        a.lock().online && b.lock().online && a.other("bob").is_some_and(|p| p.at.position == b.position(bob))
    })
    .await;
    eventually(Duration::from_secs(2).saturating_sub(back.elapsed()), "bob sees where alice is", || {
        b.other("alice").is_some_and(|p| (p.at.position - a.position(alice)).length() < 0.5)
    })
    .await;
    for (w, who) in walkers.iter().zip(["alice", "bob"]) {
        assert!(
            w.latest() <= Duration::from_millis(100),
            "{who}'s steps were {:?} late at worst",
            w.latest()
        );
    }
    assert_eq!(world_a.stats().outages, 1);
    eprintln!("views agreed {took:?} after Redis came back");
    for w in walkers {
        w.stop().await;
    }
    world_a.leave().await;
    world_b.leave().await;
}

/// Redis restarted empty loses the winner's key: the servers that know the winner store it again,
/// and a later finish on another server is not a second winner.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn redis_restarted_empty_never_crowns_a_second_winner() {
    let mut redis = RedisServer::start(Persistence::None).await;
    let (a, b) = (Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    let alice = a.join("alice", at(1.0, 1.0));
    let bob = b.join("bob", at(2.0, 2.0));
    let (world_a, world_b) = (join(&redis, &a).await, join(&redis, &b).await);
    eventually(Duration::from_secs(3), "each sees the other", || {
        a.other("bob").is_some() && b.other("alice").is_some()
    })
    .await;
    a.finish(alice, 61.5);
    eventually(Duration::from_secs(2), "both know alice won", || {
        [&a, &b].iter().all(|h| h.lock().winners.last().is_some_and(|w| w.name == "alice"))
    })
    .await;
    assert_eq!(stored_winner(&redis).await.map(|w| w.name), Some("alice".into()));

    redis.restart().await; // empty
    let back = Instant::now();
    eventually(Duration::from_secs(2), "views agree again", || {
        a.lock().online && b.lock().online && a.other("bob").is_some() && b.other("alice").is_some()
    })
    .await;
    let mut stored = None;
    while back.elapsed() < Duration::from_secs(2) && stored.is_none() {
        stored = stored_winner(&redis).await;
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    assert_eq!(stored.map(|w| w.name), Some("alice".into()), "the winner is stored again");

    b.finish(bob, 30.0); // faster, but second
    eventually(Duration::from_secs(2), "alice's server hears bob's finish", || {
        a.lock().heard_finishes.iter().any(|(_, f)| f.name == "bob" && !f.won)
    })
    .await;
    tokio::time::sleep(Duration::from_millis(300)).await;
    for host in [&a, &b] {
        let names: Vec<String> = host.lock().winners.iter().map(|w| w.name.clone()).collect();
        assert_eq!(names, ["alice"], "one winner, told once");
    }
    assert_eq!(stored_winner(&redis).await.map(|w| w.name), Some("alice".into()));

    // A server started now learns the winner from Redis.
    let c = Arc::new(TestHost::default());
    let world_c = join(&redis, &c).await;
    assert_eq!(c.lock().winners.iter().map(|w| w.name.as_str()).collect::<Vec<_>>(), ["alice"]);
    for w in [world_a, world_b, world_c] {
        w.leave().await;
    }
}

/// A winner Redis persisted is not lost when Redis restarts with every server gone, and the
/// records of best times are kept with it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_winner_redis_persisted_outlives_a_restart_with_no_server_left() {
    let mut redis = RedisServer::start(Persistence::AppendOnly).await;
    let a = Arc::new(TestHost::default());
    let alice = a.join("alice", at(1.0, 1.0));
    let world_a = join(&redis, &a).await;
    a.finish(alice, 61.5);
    eventually(Duration::from_secs(2), "alice won", || !a.lock().winners.is_empty()).await;
    let recorded = Instant::now();
    while world_a.best(10).await.expect("the records").is_empty() {
        assert!(recorded.elapsed() < Duration::from_secs(2), "alice's time is not recorded");
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    world_a.leave().await;

    redis.restart().await; // from its append-only file
    let c = Arc::new(TestHost::default());
    let carol = c.join("carol", at(3.0, 3.0));
    let world_c = join(&redis, &c).await;
    assert_eq!(c.lock().winners.iter().map(|w| w.name.as_str()).collect::<Vec<_>>(), ["alice"]);
    c.finish(carol, 12.0);
    tokio::time::sleep(Duration::from_millis(500)).await;
    assert_eq!(c.lock().winners.len(), 1, "carol is faster but not first");
    assert_eq!(stored_winner(&redis).await.map(|w| w.name), Some("alice".into()));
    let best = world_c.best(10).await.expect("the records");
    assert_eq!(best, [("carol".to_string(), 12.0), ("alice".to_string(), 61.5)]);
    world_c.leave().await;
}

/// Whatever is published on the world's channel is untrusted: garbage, a 1 MB message, players
/// outside the maze, another maze's messages, a count beyond the bytes are dropped and counted,
/// and the server goes on hearing the well-formed ones.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn messages_from_redis_are_untrusted() {
    let redis = RedisServer::start(Persistence::None).await;
    let a = Arc::new(TestHost::default());
    a.join("alice", at(1.0, 1.0));
    let world_a = join(&redis, &a).await;
    eventually(Duration::from_secs(2), "online", || a.lock().online).await;
    let keys = mazewalk_serve::shared::redis::Keys::new(MAZE, 0);
    let mut con = redis.connection(0).await;
    let full = |maze: &str, seq: u64, players: Vec<PlayerRecord>| {
        let message = Message {
            maze: maze_tag(maze),
            server: ServerId(0xbad),
            seq,
            sent_ms: 0,
            body: Body::Full { players, finished: vec![], winner: None },
        };
        let mut out = Vec::new();
        codec::encode(&message, &mut out);
        out
    };
    let zed = |x: f32| PlayerRecord {
        id: 1,
        joined_ms: 0,
        color: 1,
        label: 'Z',
        name: "zed".into(),
        at: at(x, 1.0),
    };
    let mut huge_count = full(MAZE, 1, vec![]);
    huge_count[codec::HEADER_BYTES..codec::HEADER_BYTES + 2].copy_from_slice(&4000u16.to_le_bytes());
    let bad: Vec<Vec<u8>> = vec![
        b"garbage".to_vec(),
        vec![0x4d; 1 << 20],             // 1 MB
        full(MAZE, 1, vec![zed(1.0e6)]), // outside the maze
        full("another maze", 1, vec![zed(1.0)]),
        huge_count,
        vec![],
    ];
    for bytes in &bad {
        let _: i64 = redis::cmd("PUBLISH").arg(&keys.channel).arg(bytes).query_async(&mut con).await.unwrap();
    }
    let _: i64 = redis::cmd("PUBLISH")
        .arg(&keys.channel)
        .arg(full(MAZE, 2, vec![zed(5.0)]))
        .query_async(&mut con)
        .await
        .unwrap();
    eventually(Duration::from_secs(2), "zed, well-formed, is heard", || a.other("zed").is_some()).await;
    let stats = world_a.stats();
    assert_eq!((stats.too_long, stats.heard.dropped), (1, 5), "{stats:?}");
    assert_eq!(a.lock().others.len(), 1, "only zed");
    assert!(stats.online);
    world_a.leave().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_with_another_maze_is_refused_naming_both_hashes() {
    let redis = RedisServer::start(Persistence::None).await;
    let a = Arc::new(TestHost::default());
    let world_a = join(&redis, &a).await;
    let other = WorldConfig { maze_hash: "0ther0123456789abcdef".into(), ..config(&redis) };
    let err = SharedWorld::join(other, Arc::new(TestHost::default())).await.err().expect("refused");
    let text = err.to_string();
    assert!(matches!(err, WorldError::OtherMaze { .. }), "{text}");
    assert!(text.contains(MAZE) && text.contains("0ther0123456789abcdef"), "{text}");
    // Another database is another world.
    let elsewhere =
        WorldConfig { url: redis.url(1), maze_hash: "0ther0123456789abcdef".into(), ..config(&redis) };
    let world_b = SharedWorld::join(elsewhere, Arc::new(TestHost::default())).await.expect("db 1 is free");
    world_b.leave().await;
    world_a.leave().await;

    let nowhere = WorldConfig { url: "redis://127.0.0.1:1/".into(), ..config(&redis) };
    let err = SharedWorld::join(nowhere, Arc::new(TestHost::default())).await.err().expect("refused");
    assert!(matches!(err, WorldError::Unreachable { .. }), "{err}");
    assert!(err.to_string().starts_with("cannot reach the world at redis://127.0.0.1:1/"), "{err}");
}

/// Two players who joined on two servers at once with the same label: the later one takes another.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn labels_stay_unique_across_servers() {
    let redis = RedisServer::start(Persistence::None).await;
    let (a, b) = (Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    let anna = a.join_at("anna", at(1.0, 1.0), 1_000);
    let alan = b.join_at("alan", at(2.0, 2.0), 2_000);
    assert_eq!((a.label(anna), b.label(alan)), ('A', 'A'), "the premise: neither knew of the other");
    let (world_a, world_b) = (join(&redis, &a).await, join(&redis, &b).await);
    eventually(Duration::from_secs(3), "alan takes another label, and alice's server hears it", || {
        b.label(alan) == 'L' && a.other("alan").is_some_and(|p| p.label == 'L')
    })
    .await;
    assert_eq!(a.label(anna), 'A', "anna came first");
    world_a.leave().await;
    world_b.leave().await;
}

/// 100 walkers moving 100 times a second on one server: it publishes at most 30 times a second
/// (counted by Redis itself), and the other server sees all 100.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_server_publishes_at_most_30_times_a_second_whatever_its_players() {
    let redis = RedisServer::start(Persistence::None).await;
    let (a, b) = (Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    let ids: Vec<u32> = (0..100).map(|i| a.join(&format!("w{i}"), at(1.0, 1.0))).collect();
    let (world_a, world_b) = (join(&redis, &a).await, join(&redis, &b).await);
    eventually(Duration::from_secs(3), "all 100 seen", || b.lock().others.len() == 100).await;
    let mut con = redis.connection(0).await;
    let publishes = async |con: &mut redis::aio::MultiplexedConnection| -> u64 {
        let info: String = redis::cmd("INFO").arg("commandstats").query_async(con).await.unwrap();
        let line = info.lines().find(|l| l.starts_with("cmdstat_publish:")).unwrap_or("calls=0,");
        line.split("calls=")
            .nth(1)
            .and_then(|s| s.split(',').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or(0)
    };
    let before = publishes(&mut con).await;
    let start = Instant::now();
    let mut step = 0u32;
    while start.elapsed() < Duration::from_secs(2) {
        step += 1;
        for &id in &ids {
            a.moved(id, at(1.0 + (step % 50) as f32 * 0.1, 1.0 + id as f32 * 0.5));
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let seconds = start.elapsed().as_secs_f64();
    let published = publishes(&mut con).await - before;
    assert!(published as f64 <= 30.0 * seconds + 2.0, "{published} publishes in {seconds:.2} s");
    assert!(published as f64 >= 10.0 * seconds, "it did publish the moves: {published}");
    let last = at(1.0 + (step % 50) as f32 * 0.1, 1.0 + 99.0 * 0.5);
    eventually(Duration::from_secs(2), "the last moves arrive", || {
        b.other("w99").is_some_and(|p| p.at == last)
    })
    .await;
    world_a.leave().await;
    world_b.leave().await;
}

/// `rediss://`: two servers share a world over TLS, trusting the Redis's CA (`ca`); a server that
/// does not trust it is refused with the reason.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_world_over_tls() {
    let redis = RedisServer::start_tls().await;
    let tls = WorldConfig { ca: redis.ca(), ..config(&redis) };
    assert!(tls.url.starts_with("rediss://"));
    let (a, b) = (Arc::new(TestHost::default()), Arc::new(TestHost::default()));
    a.join("alice", at(1.0, 1.0));
    b.join("bob", at(2.0, 2.0));
    let world_a = SharedWorld::join(tls.clone(), Arc::clone(&a) as Arc<dyn mazewalk_serve::shared::Host>)
        .await
        .unwrap();
    let world_b = SharedWorld::join(tls.clone(), Arc::clone(&b) as Arc<dyn mazewalk_serve::shared::Host>)
        .await
        .unwrap();
    eventually(Duration::from_secs(3), "each sees the other", || {
        a.other("bob").is_some() && b.other("alice").is_some()
    })
    .await;
    let untrusting = WorldConfig { ca: None, ..tls };
    let err = SharedWorld::join(untrusting, Arc::new(TestHost::default())).await.err().expect("refused");
    assert!(matches!(err, WorldError::Unreachable { .. }), "{err}");
    assert!(err.to_string().to_lowercase().contains("certificate"), "{err}");
    world_a.leave().await;
    world_b.leave().await;
}

/// SCAN calls Redis has answered since its statistics were last reset (`INFO commandstats`).
async fn scan_calls(con: &mut redis::aio::MultiplexedConnection) -> u64 {
    let info: String = redis::cmd("INFO").arg("commandstats").query_async(con).await.unwrap();
    info.lines()
        .find_map(|l| l.strip_prefix("cmdstat_scan:calls="))
        .and_then(|rest| rest.split(',').next())
        .map_or(0, |n| n.parse().unwrap())
}

/// Red-team pass 3: each time the subscription came back the server SCANned the whole keyspace for
/// presence keys, with nothing to stop the scans piling up: with a million keys of another
/// application and a subscription killed every 100 ms, Redis spent 7 s of CPU in 10 s. The presence
/// keys are read one read in flight at most, two at once (the join's and a first comeback's), then
/// one every 5 s: 3 s of a subscription killed every 50 ms cost at most one more walk of the
/// keyspace than joining did.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flapping_subscription_walks_the_keyspace_at_most_once_in_5_s() {
    let redis = RedisServer::start(Persistence::None).await;
    let mut con = redis.connection(0).await;
    for batch in 0..50 {
        let mut mset = redis::cmd("MSET");
        for i in 0..1000 {
            mset.arg(format!("another:app:{batch}:{i}")).arg("x");
        }
        let () = mset.query_async(&mut con).await.unwrap();
    }
    let a = Arc::new(TestHost::default());
    let _alice = a.join("alice", at(1.0, 1.0));
    let () = redis::cmd("CONFIG").arg("RESETSTAT").query_async(&mut con).await.unwrap();
    let _world = join(&redis, &a).await;
    eventually(Duration::from_secs(3), "online", || a.lock().online).await;
    // (the join's read of the presence keys: done when its count stops growing)
    let (start, mut walk) = (Instant::now(), 0);
    loop {
        tokio::time::sleep(Duration::from_millis(200)).await;
        let calls = scan_calls(&mut con).await;
        if calls > 0 && calls == walk {
            break;
        }
        walk = calls;
        assert!(start.elapsed() < Duration::from_secs(3), "the join's read: {walk} SCAN calls so far");
    }
    assert!(walk >= 100, "one walk of 50,000 keys, 100 a call: {walk} calls");
    let () = redis::cmd("CONFIG").arg("RESETSTAT").query_async(&mut con).await.unwrap();
    let (start, mut kills, mut back) = (Instant::now(), 0, 0);
    while start.elapsed() < Duration::from_secs(3) {
        let killed: i64 =
            redis::cmd("CLIENT").arg("KILL").arg("TYPE").arg("pubsub").query_async(&mut con).await.unwrap();
        kills += killed;
        tokio::time::sleep(Duration::from_millis(50)).await;
        back += i64::from(killed > 0);
    }
    let calls = scan_calls(&mut con).await;
    assert!(back >= 5, "the subscription came back {back} times ({kills} killed)");
    assert!(calls <= walk + walk / 2, "{calls} SCAN calls in 3 s of flapping; one walk is {walk}");
}
