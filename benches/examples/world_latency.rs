//! The time from a move on one server to the frame on another server's player, for BENCHMARKS.md ("The
//! shared world on Redis"), end to end: a `redis-server` of its own on loopback, two `mazewalk serve
//! --world` processes (the release binary), and two scripted SSH players (russh's client): the mover on
//! server A steps back and forth along a corridor, the watcher on server B stands at its west end
//! looking east, where the mover's figure is. The maze has no exit (no clock ticks), so every frame
//! the watcher gets is the mover's step. Latency: from the mover's key to the watcher's next frame.
//!
//! ```sh
//! cargo build --release && cargo run --release -p mazewalk-bench --example world_latency -- 20   # 20 s
//! ```

use mazewalk_testkit::load;
use mazewalk_testkit::redis_async as redis_server;
use mazewalk_testkit::server_process;

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use load::{Connected, connect, quantile};
use redis_server::{Persistence, RedisServer};
use russh::ChannelMsg;

/// A corridor 12 tiles east from the start, and no exit.
const CORRIDOR: &str =
    "mazewalk-grid 1\ntile 4\nfacing east\n\n##############\n#@...........#\n##############\n";
const QUERY: &[u8] = b"\x1b[c";
const ANSWER: &[u8] = b"\x1b[?62;22c";

/// A server process, killed on drop.
struct ServerProcess {
    child: Child,
    addr: SocketAddr,
}

impl ServerProcess {
    fn start(scratch: &Path, name: &str, maze: &Path, world: &str) -> ServerProcess {
        let bin = server_process::release_binary();
        assert!(bin.exists(), "{} is missing: run `cargo build --release` first", bin.display());
        let mut child = Command::new(&bin)
            .args(["serve", "--open", "--no-records", "--listen", "127.0.0.1:0", "--world", world])
            .arg("--host-key")
            .arg(scratch.join(format!("host_key_{name}")))
            .arg(maze)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start the server");
        let (addr, stdout) = server_process::announced(&mut child);
        server_process::drain(stdout);
        ServerProcess { child, addr }
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Reads what arrives until `until`, answering every frame's query; returns when each frame came.
async fn frames_until(connected: &mut Connected, until: Instant, times: &mut Vec<Instant>) {
    let mut carry: Vec<u8> = Vec::new();
    loop {
        let message = tokio::time::timeout_at(until.into(), connected.channel.wait()).await;
        let Ok(message) = message else { return };
        match message {
            Some(ChannelMsg::Data { data }) => {
                carry.extend_from_slice(&data);
                let n = carry.windows(QUERY.len()).filter(|w| *w == QUERY).count();
                let keep = carry.len().min(QUERY.len() - 1);
                carry.drain(..carry.len() - keep);
                for _ in 0..n {
                    times.push(Instant::now());
                    let _ = connected.channel.data(ANSWER).await;
                }
            }
            Some(ChannelMsg::Eof | ChannelMsg::Close) | None => return,
            _ => {}
        }
    }
}

#[tokio::main]
async fn main() {
    let seconds: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(20.0);
    let redis = RedisServer::start(Persistence::None).await;
    let scratch: PathBuf =
        std::env::temp_dir().join(format!("mazewalk-world-latency-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch");
    let maze = scratch.join("corridor.grid");
    std::fs::write(&maze, CORRIDOR).expect("the maze");
    let a = ServerProcess::start(&scratch, "a", &maze, &redis.url(0));
    let b = ServerProcess::start(&scratch, "b", &maze, &redis.url(0));
    let size = (120, 40);
    let mut watcher = connect(b.addr, "watcher", size).await.expect("the watcher on B");
    let mut ignored = Vec::new();
    frames_until(&mut watcher, Instant::now() + Duration::from_millis(500), &mut ignored).await;
    let mut mover = connect(a.addr, "mover", size).await.expect("the mover on A");
    // The mover walks 4 steps east, in front of the watcher; both settle.
    let settle = Instant::now() + Duration::from_millis(300);
    frames_until(&mut mover, settle, &mut ignored).await;
    for _ in 0..4 {
        mover.channel.data(&b"w"[..]).await.expect("a key");
        frames_until(&mut mover, Instant::now() + Duration::from_millis(100), &mut ignored).await;
    }
    frames_until(&mut watcher, Instant::now() + Duration::from_millis(500), &mut ignored).await;

    // Then a step back or forth every 250 ms; each of the watcher's frames after a step is timed.
    let mut latencies = Vec::new();
    let (mut missed, mut steps) = (0usize, 0usize);
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    let mover_task = tokio::spawn(async move {
        let mut keys = Vec::new();
        let mut forward = false;
        let mut frames = Vec::new();
        while Instant::now() < end {
            let key: &[u8] = if forward { b"w" } else { b"s" };
            forward = !forward;
            keys.push(Instant::now());
            if mover.channel.data(key).await.is_err() {
                break;
            }
            frames_until(&mut mover, Instant::now() + Duration::from_millis(250), &mut frames).await;
        }
        keys
    });
    let mut seen = Vec::new();
    frames_until(&mut watcher, end + Duration::from_millis(300), &mut seen).await;
    let keys = mover_task.await.expect("the mover");
    for (i, &key) in keys.iter().enumerate() {
        steps += 1;
        let next_key = keys.get(i + 1).copied().unwrap_or(end + Duration::from_millis(300));
        match seen.iter().find(|&&t| t >= key && t < next_key) {
            Some(&t) => latencies.push((t - key).as_secs_f64()),
            None => missed += 1,
        }
    }
    let n = latencies.len();
    let (p50, p99, max) =
        (quantile(&mut latencies, 0.5), quantile(&mut latencies, 0.99), quantile(&mut latencies, 1.0));
    println!(
        "move on A → frame on B's player: p50 {:.1} ms, p99 {:.1} ms, max {:.1} ms ({n} of {steps} steps \
         seen; {missed} without a frame before the next step; the watcher got {} frames in all)",
        p50 * 1e3,
        p99 * 1e3,
        max * 1e3,
        seen.len()
    );
    drop((a, b));
    let _ = std::fs::remove_dir_all(&scratch);
}
