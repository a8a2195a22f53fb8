//! Issue #40's attack on the shared world, against two server binaries in one run — "before" and
//! "after" — for BENCHMARKS.md ("A Redis writer that lies"). One writer with the Redis password
//! publishes Full messages from 10 invented server ids, each with 4,096 valid players and a finish
//! for each, and a winner claim naming a new winner every time (W1, W2, …), re-sent every `period`
//! with new headings (≈ 1.2 MB/s at 2 s). The world's true winner is set in Redis before the servers
//! start, so that every claim contradicts it.
//!
//! For each binary and period: a `redis-server` of its own on loopback, two `mazewalk serve --world`
//! processes (their logs in files), and a witness player on server A turning at 10 keys a second
//! (russh's client); its key-to-frame latency is measured during the flood and for as long again
//! after it stops. Reported: the witness's p50/p99 during and after, each server's RSS when idle and
//! its peak (`VmHWM`), its CPU seconds, and its log bytes per minute during the flood.
//!
//! Then, for each binary, the **claims** flood alone: small full messages from one invented server,
//! each naming a new winner, published as fast as one pipelined connection can for `seconds`; and
//! the **junk** flood: 200 KB messages that are not messages, as fast. Each server's log bytes per
//! minute, its RSS idle and peak, and the SETs Redis counted (`INFO commandstats`) are reported.
//! `--periods none` runs these two only.
//!
//! ```sh
//! cargo build --release                           # the "after" binary: target/release/mazewalk
//! git worktree add /tmp/world-before <commit> && (cd /tmp/world-before && cargo build --release)
//! cargo run --release -p mazewalk-bench --example world_flood -- \
//!     --before /tmp/world-before/target/release/mazewalk --seconds 20 [--periods 2,1]
//! ```
//!
//! Only flags both binaries know are passed: each server's caps are its defaults.

use mazewalk_testkit::load;
use mazewalk_testkit::redis_async as redis_server;
use mazewalk_testkit::server_process;

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use glam::Vec2;
use load::{connect, cpu_seconds, quantile, rss_bytes};
use mazewalk_maze::Maze;
use mazewalk_serve::shared::codec::{
    self, Body, Bounds, Finish, Message, PlayerRecord, ServerId, Whereabouts, WinnerRecord, maze_tag,
};
use mazewalk_serve::shared::redis::Keys;
use redis_server::{Persistence, RedisServer};

/// A room 32 × 32 tiles with no exit (no clock ticks): the flood's players stand all over it.
fn room() -> String {
    let mut text = String::from("mazewalk-grid 1\ntile 4\nfacing east\n\n");
    text.push_str(&"#".repeat(34));
    text.push('\n');
    for row in 0..32 {
        text.push('#');
        text.push_str(&(0..32).map(|col| if (row, col) == (16, 16) { '@' } else { '.' }).collect::<String>());
        text.push_str("#\n");
    }
    text.push_str(&"#".repeat(34));
    text.push('\n');
    text
}

/// Invented servers in the flood, and players each.
const SERVERS: u64 = 10;
const PLAYERS: u32 = 4096;

struct Args {
    before: Option<PathBuf>,
    after: PathBuf,
    seconds: f64,
    periods: Vec<f64>,
}

/// What `--help` prints, and a refusal with it.
const USAGE: &str =
    "usage: cargo run --release -p mazewalk-bench --example world_flood -- [--before BIN] [--after BIN]
    [--seconds S] [--periods 2,1|none]
(see the example's doc)";

fn args() -> Args {
    let after = server_process::release_binary();
    let mut a = Args { before: None, after, seconds: 20.0, periods: vec![2.0, 1.0] };
    for (flag, value) in server_process::flags(USAGE) {
        match flag.as_str() {
            "--before" => a.before = Some(value.into()),
            "--after" => a.after = value.into(),
            "--seconds" => a.seconds = server_process::value("--seconds", &value, USAGE),
            "--periods" if value == "none" => a.periods = Vec::new(),
            "--periods" => {
                a.periods = value.split(',').map(|p| server_process::value("--periods", p, USAGE)).collect()
            }
            other => server_process::refuse(&format!("unknown argument {other}"), USAGE),
        }
    }
    a
}

/// A server process with its log in a file, killed on drop.
struct ServerProcess {
    child: Child,
    addr: SocketAddr,
    log: PathBuf,
}

impl ServerProcess {
    fn start(bin: &Path, scratch: &Path, name: &str, maze: &Path, world: &str) -> ServerProcess {
        let log = scratch.join(format!("log_{name}"));
        let mut child = Command::new(bin)
            .args(["serve", "--open", "--no-records", "--listen", "127.0.0.1:0", "--world", world])
            .arg("--host-key")
            .arg(scratch.join(format!("host_key_{name}")))
            .arg(maze)
            .env("HOME", scratch)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).expect("log file"))
            .spawn()
            .expect("start the server");
        let (addr, stdout) = server_process::announced(&mut child);
        server_process::drain(stdout);
        ServerProcess { child, addr, log }
    }

    fn pid(&self) -> Option<u32> {
        Some(self.child.id())
    }

    fn log_bytes(&self) -> u64 {
        std::fs::metadata(&self.log).map_or(0, |m| m.len())
    }

    /// The peak resident memory so far, bytes (`VmHWM`).
    fn peak_rss(&self) -> u64 {
        std::fs::read_to_string(format!("/proc/{}/status", self.child.id()))
            .ok()
            .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).map(str::to_string))
            .and_then(|l| l.split_whitespace().nth(1).and_then(|kb| kb.parse::<u64>().ok()))
            .map_or(0, |kb| kb * 1024)
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The flood's message `round` from invented server `k`: everyone, each with a finish, and a new
/// winner claimed.
fn flood_message(tag: u64, bounds: &Bounds, k: u64, round: u64) -> Vec<u8> {
    let size = bounds.max - bounds.min;
    let players: Vec<PlayerRecord> = (0..PLAYERS)
        .map(|i| {
            let spot = Vec2::new((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5) / 64.0;
            PlayerRecord {
                id: i,
                joined_ms: 1_000,
                color: (i % 8) as u8,
                label: char::from(b'A' + (i % 26) as u8),
                name: format!("x{:03x}", i),
                at: Whereabouts {
                    position: bounds.min + spot * size,
                    heading_deg: ((round * 37 + u64::from(i)) % 360) as f32,
                    pitch_deg: 0.0,
                    cell: i % bounds.cells,
                },
            }
        })
        .collect();
    let finished: Vec<Finish> = (0..PLAYERS)
        .map(|i| Finish { id: i, name: format!("x{:03x}", i), seconds: 1.0 + f64::from(i), won: false })
        .collect();
    let claim =
        WinnerRecord { server: ServerId(k), id: 0, seconds: 0.1, name: format!("W{}", round * SERVERS + k) };
    let message = Message {
        maze: tag,
        server: ServerId(0xf100_0000 + k),
        seq: round + 1,
        sent_ms: 0,
        body: Body::Full { players, finished, winner: Some(claim) },
    };
    let mut out = Vec::new();
    codec::encode(&message, &mut out);
    out
}

/// What a claims or junk flood did to one binary.
struct Flooded {
    messages: u64,
    log_per_minute: [f64; 2],
    sets_per_second: f64,
    idle_rss: [u64; 2],
    peak_rss: [u64; 2],
}

/// A world of its own for one run of `bin`, in the folder `scratch`: a `redis-server`, the room,
/// the world's true winner set in Redis before anyone joins, and two servers on it, left idle 2 s.
struct World {
    redis: RedisServer,
    scratch: PathBuf,
    maze: Maze,
    hash: String,
    keys: Keys,
    con: redis::aio::MultiplexedConnection,
    servers: [ServerProcess; 2],
}

async fn world(bin: &Path, scratch: PathBuf) -> World {
    let redis = RedisServer::start(Persistence::None).await;
    std::fs::create_dir_all(&scratch).expect("scratch");
    let text = room();
    let maze_path = scratch.join("room.grid");
    std::fs::write(&maze_path, &text).expect("the maze");
    let maze: Maze = mazewalk_maze::parse("room.grid", text.as_bytes()).expect("the room");
    let hash = maze.content_hash().to_string();
    let keys = Keys::new(&hash, 0);
    let mut con = redis.connection(0).await;
    let truth = WinnerRecord { server: ServerId(1), id: 0, seconds: 42.0, name: "truth".into() };
    let _: () = redis::cmd("SET")
        .arg(&keys.winner)
        .arg(codec::encode_winner(&truth))
        .query_async(&mut con)
        .await
        .unwrap();
    let servers = [
        ServerProcess::start(bin, &scratch, "a", &maze_path, &redis.url(0)),
        ServerProcess::start(bin, &scratch, "b", &maze_path, &redis.url(0)),
    ];
    tokio::time::sleep(Duration::from_secs(2)).await;
    World { redis, scratch, maze, hash, keys, con, servers }
}

/// The claims flood (or with `junk`, the junk flood) against `bin`.
async fn claims(bin: &Path, seconds: f64, junk: bool) -> Flooded {
    let scratch = std::env::temp_dir().join(format!("mazewalk-world-claims-{}", std::process::id()));
    // (`_redis` lives to the end: the servers' world)
    let World { redis: _redis, scratch, hash, keys, mut con, servers, .. } = world(bin, scratch).await;
    let log0 = [servers[0].log_bytes(), servers[1].log_bytes()];
    let idle_rss = [rss_bytes(servers[0].pid()), rss_bytes(servers[1].pid())];
    let sets0 = redis_server::command_calls(&mut con, "set").await.unwrap_or(0);
    let garbage: Vec<u8> = (0..200_000u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 24) as u8).collect();
    let start = std::time::Instant::now();
    let mut n = 0u64;
    while start.elapsed().as_secs_f64() < seconds {
        let mut pipe = redis::pipe();
        for _ in 0..if junk { 20 } else { 500 } {
            n += 1;
            if junk {
                pipe.cmd("PUBLISH").arg(&keys.channel).arg(&garbage).ignore();
                continue;
            }
            let claim = WinnerRecord { server: ServerId(7), id: 0, seconds: 0.1, name: format!("W{n}") };
            let message = Message {
                maze: maze_tag(&hash),
                server: ServerId(0xbad),
                seq: n,
                sent_ms: 0,
                body: Body::Full { players: vec![], finished: vec![], winner: Some(claim) },
            };
            let mut out = Vec::new();
            codec::encode(&message, &mut out);
            pipe.cmd("PUBLISH").arg(&keys.channel).arg(out).ignore();
        }
        if pipe.query_async::<()>(&mut con).await.is_err() {
            break;
        }
    }
    let elapsed = start.elapsed().as_secs_f64();
    tokio::time::sleep(Duration::from_secs(2)).await; // what the servers still had to read
    let sets = redis_server::command_calls(&mut con, "set").await.unwrap_or(0) - sets0;
    let logs = [servers[0].log_bytes() - log0[0], servers[1].log_bytes() - log0[1]];
    let peak_rss = [servers[0].peak_rss(), servers[1].peak_rss()];
    drop(servers);
    let _ = std::fs::remove_dir_all(&scratch);
    Flooded {
        messages: n,
        log_per_minute: logs.map(|b| b as f64 * 60.0 / (elapsed + 2.0)),
        sets_per_second: sets as f64 / (elapsed + 2.0),
        idle_rss,
        peak_rss,
    }
}

/// What the flood did to one binary.
struct Outcome {
    during: (f64, f64),
    after: (f64, f64),
    keys: (usize, usize),
    idle_rss: [u64; 2],
    peak_rss: [u64; 2],
    cpu: [f64; 2],
    log_per_minute: [f64; 2],
    published: u64,
    bytes: u64,
}

/// The witness's p50 and p99, ms, and how many keys it timed.
fn figures(mut latencies: Vec<f64>) -> ((f64, f64), usize) {
    let n = latencies.len();
    ((quantile(&mut latencies, 0.5) * 1e3, quantile(&mut latencies, 0.99) * 1e3), n)
}

async fn run(bin: &Path, period: f64, seconds: f64) -> Outcome {
    let scratch = std::env::temp_dir().join(format!("mazewalk-world-flood-{}-{period}", std::process::id()));
    let World { redis, scratch, maze, hash, keys, servers, .. } = world(bin, scratch).await;
    let bounds = Bounds::of(&maze);
    let idle_rss = [rss_bytes(servers[0].pid()), rss_bytes(servers[1].pid())];
    let cpu0 = [cpu_seconds(servers[0].pid()), cpu_seconds(servers[1].pid())];
    let log0 = [servers[0].log_bytes(), servers[1].log_bytes()];

    // The flood, on a thread of its own (its encoding is not the servers' time).
    let stop = Arc::new(AtomicBool::new(false));
    let (published, bytes) = (Arc::new(AtomicU64::new(0)), Arc::new(AtomicU64::new(0)));
    let flood = {
        let (stop, published, bytes) = (Arc::clone(&stop), Arc::clone(&published), Arc::clone(&bytes));
        let (channel, tag) = (keys.channel.clone(), maze_tag(&hash));
        let mut con = redis.connection(0).await;
        tokio::spawn(async move {
            let mut ticker = tokio::time::interval(Duration::from_secs_f64(period));
            let mut round = 0;
            while !stop.load(Ordering::Relaxed) {
                ticker.tick().await;
                let messages = tokio::task::spawn_blocking(move || {
                    (0..SERVERS).map(|k| flood_message(tag, &bounds, k, round)).collect::<Vec<_>>()
                })
                .await
                .expect("encode");
                let mut pipe = redis::pipe();
                for m in &messages {
                    bytes.fetch_add(m.len() as u64, Ordering::Relaxed);
                    pipe.cmd("PUBLISH").arg(&channel).arg(m).ignore();
                }
                if pipe.query_async::<()>(&mut con).await.is_ok() {
                    published.fetch_add(SERVERS, Ordering::Relaxed);
                }
                round += 1;
            }
        })
    };
    let witness = connect(servers[0].addr, "witness", (80, 24)).await.expect("the witness");
    let during = load::walk(witness, 10.0, seconds, b"\x1b[D").await;
    stop.store(true, Ordering::Relaxed);
    let _ = flood.await;
    let flood_seconds = seconds;
    let logs = [servers[0].log_bytes() - log0[0], servers[1].log_bytes() - log0[1]];
    let witness = connect(servers[0].addr, "witness2", (80, 24)).await.expect("the witness, after");
    let after = load::walk(witness, 10.0, seconds, b"\x1b[D").await;
    let peak_rss = [servers[0].peak_rss(), servers[1].peak_rss()];
    let cpu = [cpu_seconds(servers[0].pid()) - cpu0[0], cpu_seconds(servers[1].pid()) - cpu0[1]];
    let (during_fig, during_n) = figures(during.latencies);
    let (after_fig, after_n) = figures(after.latencies);
    drop(servers);
    let _ = std::fs::remove_dir_all(&scratch);
    Outcome {
        during: during_fig,
        after: after_fig,
        keys: (during_n, after_n),
        idle_rss,
        peak_rss,
        cpu,
        log_per_minute: logs.map(|b| b as f64 * 60.0 / flood_seconds),
        published: published.load(Ordering::Relaxed),
        bytes: bytes.load(Ordering::Relaxed),
    }
}

fn print(label: &str, period: f64, seconds: f64, o: &Outcome) {
    let mb = |b: u64| b as f64 / (1 << 20) as f64;
    println!(
        "{label:>6} period {period} s: witness p50/p99 during {:.1}/{:.1} ms ({} keys), after {:.1}/{:.1} ms \
         ({} keys); RSS idle → peak A {:.1} → {:.1} MB, B {:.1} → {:.1} MB; CPU A {:.1} s, B {:.1} s in {:.0} s; \
         log A {:.0} KB/min, B {:.0} KB/min; flood {} messages, {:.1} MB",
        o.during.0,
        o.during.1,
        o.keys.0,
        o.after.0,
        o.after.1,
        o.keys.1,
        mb(o.idle_rss[0]),
        mb(o.peak_rss[0]),
        mb(o.idle_rss[1]),
        mb(o.peak_rss[1]),
        o.cpu[0],
        o.cpu[1],
        2.0 * seconds,
        o.log_per_minute[0] / 1024.0,
        o.log_per_minute[1] / 1024.0,
        o.published,
        mb(o.bytes),
    );
}

#[tokio::main]
async fn main() {
    let args = args();
    let mut bins: Vec<(&str, &Path)> = Vec::new();
    if let Some(before) = &args.before {
        bins.push(("before", before));
    }
    bins.push(("after", &args.after));
    for (_, bin) in &bins {
        assert!(bin.exists(), "{} is missing: run `cargo build --release` first", bin.display());
    }
    for &period in &args.periods {
        for (label, bin) in &bins {
            let outcome = run(bin, period, args.seconds).await;
            print(label, period, args.seconds, &outcome);
        }
    }
    let mb = |b: u64| b as f64 / (1 << 20) as f64;
    for (what, junk) in [("claims", false), ("junk", true)] {
        for (label, bin) in &bins {
            let f = claims(bin, args.seconds, junk).await;
            println!(
                "{label:>6} {what}: {} messages in {} s; log A {:.0} KB/min, B {:.0} KB/min; RSS idle → peak \
                 A {:.1} → {:.1} MB, B {:.1} → {:.1} MB; {:.0} SETs/s into Redis (2 presence keys a second are \
                 the servers' own)",
                f.messages,
                args.seconds,
                f.log_per_minute[0] / 1024.0,
                f.log_per_minute[1] / 1024.0,
                mb(f.idle_rss[0]),
                mb(f.peak_rss[0]),
                mb(f.idle_rss[1]),
                mb(f.peak_rss[1]),
                f.sets_per_second,
            );
        }
    }
}
