//! The server under full load, for BENCHMARKS.md: `mazewalk serve` (the release binary, a process of
//! its own, so that its CPU and memory are its own) on loopback, and scripted russh clients in this
//! process.
//!
//! 1. Idle: N players connect (120×40) and stand still: the server's memory per player, its CPU and
//!    the bytes sent over a quiet spell.
//! 2. Walking: M players turn (every key changes the picture) at R keys a second for S seconds:
//!    frames delivered per second per player, key-to-frame latency p50 / p99, the server's CPU and
//!    memory, bytes per second per player.
//!
//! With `--servers N --world redis://…` (issue #35) it starts N servers in one shared world on that
//! Redis and spreads the players over them round-robin: the same figures, the CPU and memory summed
//! over the servers.
//!
//! ```sh
//! cargo build --release && cargo run --release -p mazewalk-bench --example load                # 1000 idle, 100 walking
//! cargo run --release -p mazewalk-bench --example load -- --idle 200 --walkers 50 --seconds 5   # smaller
//! cargo run --release -p mazewalk-bench --example load -- --idle 0 --walkers 90 --servers 3 --world redis://127.0.0.1:6379/0
//! ```
//!
//! Walkers come each from a loopback address of its own (127.1.x.y), as players on the internet do:
//! the server's drawing budget is per address; `--one-address true` brings them all from 127.0.0.1
//! (sharing one budget, 20 frames a second each at 120×40).
//!
//! With `--record-dir DIR` (issue #43) the server records every player's session there
//! (`serve --record-dir`): the same figures, to compare with a run without it.
//!
//! With `--callgrind FILE` (issue #42) the server runs under `valgrind --tool=callgrind` and is
//! stopped with SIGINT, so that it writes FILE: `scripts/callgrind_stages.py FILE` gives a served
//! frame's cost by stage. Under valgrind a server draws a few frames a second: keep the key rate
//! low enough that each key gets a frame of its own (`--idle 0 --walkers 4 --rate 4 --seconds 15`).
//! There the idle players' quiet spell (`--quiet S`, 10 s by default) is dumped on its own, as
//! `FILE.1`: an idle player's tick is its count over S × the idle players (`--idle 50 --walkers 0`).
//!
//! With `--first KEYS` each walker presses KEYS once before the clock starts: `--first f` turns the
//! magnified middle off, for the cost of the plain view.

use mazewalk_testkit::load;
use mazewalk_testkit::server_process;

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use load::{connect, cpu_seconds, quantile, rss_bytes};
use tokio::sync::{Semaphore, watch};

struct Args {
    idle: usize,
    walkers: usize,
    cols: u32,
    rows: u32,
    rate: f64,
    seconds: f64,
    /// The idle players' quiet spell measured, seconds.
    quiet: f64,
    servers: usize,
    world: Option<String>,
    callgrind: Option<String>,
    record_dir: Option<String>,
    one_address: bool,
    /// Keys each walker presses once before the clock starts (`--first f`: the magnified middle
    /// off, the plain view's cost).
    first: Vec<u8>,
}

/// What `--help` prints, and a refusal with it.
const USAGE: &str = "usage: cargo run --release -p mazewalk-bench --example load -- [--idle N] [--walkers N]
    [--rate KEYS_PER_S] [--seconds S] [--quiet S] [--size COLSxROWS] [--one-address true|false]
    [--servers N --world redis://…] [--record-dir DIR] [--callgrind FILE] [--first KEYS]
(the server is target/release/mazewalk: `cargo build --release` first; see the example's doc)";

fn args() -> Args {
    let mut a = Args {
        idle: 1000,
        walkers: 100,
        cols: 120,
        rows: 40,
        rate: 30.0,
        seconds: 10.0,
        quiet: 10.0,
        servers: 1,
        world: None,
        callgrind: None,
        record_dir: None,
        one_address: false,
        first: Vec::new(),
    };
    for (flag, value) in server_process::flags(USAGE) {
        match flag.as_str() {
            "--idle" => a.idle = server_process::value("--idle", &value, USAGE),
            "--walkers" => a.walkers = server_process::value("--walkers", &value, USAGE),
            "--rate" => a.rate = server_process::value("--rate", &value, USAGE),
            "--seconds" => a.seconds = server_process::value("--seconds", &value, USAGE),
            "--quiet" => a.quiet = server_process::value("--quiet", &value, USAGE),
            "--servers" => a.servers = server_process::value("--servers", &value, USAGE),
            "--world" => a.world = Some(value),
            "--callgrind" => a.callgrind = Some(value),
            "--record-dir" => a.record_dir = Some(value),
            "--first" => a.first = value.into_bytes(),
            "--one-address" => a.one_address = server_process::value("--one-address", &value, USAGE),
            "--size" => {
                let (c, r) = value.split_once('x').unwrap_or_else(|| {
                    server_process::refuse(&format!("--size COLSxROWS, not {value:?}"), USAGE)
                });
                (a.cols, a.rows) =
                    (server_process::value("--size", c, USAGE), server_process::value("--size", r, USAGE));
            }
            other => server_process::refuse(&format!("unknown argument {other}"), USAGE),
        }
    }
    if a.servers == 0 || (a.servers > 1 && a.world.is_none()) {
        server_process::refuse("--servers N: at least 1, and more than 1 needs --world URL", USAGE);
    }
    a
}

/// The server process, killed on drop (under callgrind: stopped by SIGINT, and waited for while it
/// writes its profile).
struct ServerProcess {
    child: Child,
    addr: SocketAddr,
    _scratch: PathBuf,
    callgrind: bool,
}

impl ServerProcess {
    fn start(
        n: usize,
        world: Option<&str>,
        callgrind: Option<&str>,
        record_dir: Option<&str>,
    ) -> ServerProcess {
        let bin = server_process::release_binary();
        assert!(bin.exists(), "{} is missing: run `cargo build --release` first", bin.display());
        let scratch = std::env::temp_dir().join(format!("mazewalk-load-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&scratch).expect("scratch");
        let mut command = match callgrind {
            Some(out) => {
                let mut valgrind = Command::new("valgrind");
                valgrind.args(["--tool=callgrind", &format!("--callgrind-out-file={out}")]).arg(&bin);
                valgrind
            }
            None => Command::new(&bin),
        };
        let mut child = command
            .args([
                "serve",
                "--open",
                "--listen",
                "127.0.0.1:0",
                "--max-players",
                "5000",
                "--max-per-address",
                "5000",
            ])
            .arg("--host-key")
            .arg(scratch.join("host_key"))
            .args(world.map(|url| ["--world", url]).into_iter().flatten())
            .args(record_dir.map(|dir| ["--record-dir", dir]).into_iter().flatten())
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("start the server");
        let (addr, stdout) = server_process::announced(&mut child);
        server_process::drain(stdout);
        ServerProcess { child, addr, _scratch: scratch, callgrind: callgrind.is_some() }
    }

    fn pid(&self) -> Option<u32> {
        Some(self.child.id())
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        if self.callgrind {
            let _ = Command::new("kill").args(["-INT", &self.child.id().to_string()]).status();
            let _ = self.child.wait();
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self._scratch);
    }
}

/// A TCP connection to the server at `to` from a loopback address of walker `i`'s own (127.1.x.y), as
/// players on the internet come each from its own: the server's drawing budget is an address
/// group's (`Limits::render_rate`), and 100 walkers from 127.0.0.1 would share one, at its floor of
/// 20 frames a second each (`--one-address true` measures that).
async fn from_own_address(to: SocketAddr, i: usize) -> tokio::net::TcpStream {
    let from = std::net::Ipv4Addr::new(127, 1, (i / 250) as u8, (i % 250 + 1) as u8);
    let socket = tokio::net::TcpSocket::new_v4().expect("a socket");
    socket.bind(SocketAddr::from((from, 0))).expect("bind a loopback address");
    socket.connect(to).await.expect("connect")
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

#[tokio::main]
async fn main() {
    let a = args();
    let servers: Vec<ServerProcess> = (0..a.servers)
        .map(|n| ServerProcess::start(n, a.world.as_deref(), a.callgrind.as_deref(), a.record_dir.as_deref()))
        .collect();
    let server = &servers[0];
    let (addr, pid) = (server.addr, server.pid());
    let addrs: Vec<SocketAddr> = servers.iter().map(|s| s.addr).collect();
    let pids: Vec<Option<u32>> = servers.iter().map(ServerProcess::pid).collect();
    let cpu_all = || pids.iter().map(|&p| cpu_seconds(p)).sum::<f64>();
    let rss_all = || pids.iter().map(|&p| rss_bytes(p)).sum::<u64>();
    let size = (a.cols, a.rows);
    tokio::time::sleep(Duration::from_millis(300)).await;
    let rss_empty = rss_bytes(pid);
    println!("server {addr}: {:.1} MiB resident with nobody in", mib(rss_empty));

    // 1. Idle players.
    let (stop, stopped) = watch::channel(false);
    let idle_bytes = Arc::new(AtomicU64::new(0));
    let gate = Arc::new(Semaphore::new(16)); // handshakes in flight at once
    let started = Instant::now();
    let mut connecting = Vec::new();
    for i in 0..a.idle {
        let (gate, stopped, idle_bytes) = (Arc::clone(&gate), stopped.clone(), Arc::clone(&idle_bytes));
        connecting.push(tokio::spawn(async move {
            let permit = gate.acquire_owned().await.expect("gate");
            let connected = connect(addr, &format!("idle{i}"), size).await.expect("connect an idle player");
            drop(permit);
            load::idle(connected, idle_bytes, stopped).await
        }));
    }
    // Wait until everyone has drawn and the joins' redraws have settled: then an idle player gets
    // only its HUD's exit clock, a tick a second (~21 bytes with the flow control's query), so two
    // seconds bring at most IDLE_TICK_BYTES each, twice running. (Waiting for no bytes at all never
    // ended in a maze with an exit; 200 a second let a run end while first paints, ~8 KB each,
    // still trickled out of a drawing budget shared by 1,000 players from one address.)
    const IDLE_TICK_BYTES: u64 = 2 * 40;
    let (mut last, mut quiet_spells) = (u64::MAX, 0);
    loop {
        tokio::time::sleep(Duration::from_secs(2)).await;
        let now = idle_bytes.load(Ordering::Relaxed);
        let settled = now.saturating_sub(last) <= IDLE_TICK_BYTES * a.idle as u64;
        quiet_spells = if last != u64::MAX && settled { quiet_spells + 1 } else { 0 };
        if quiet_spells >= 2 && started.elapsed() > Duration::from_secs(3) {
            break;
        }
        last = now;
    }
    let join_seconds = started.elapsed().as_secs_f64();
    let rss_idle = rss_bytes(pid);
    // Under callgrind, the quiet spell's count alone: zeroed at its start, dumped at its end.
    let callgrind = |what: &str| {
        if a.callgrind.is_some() {
            let pid = pid.expect("the server's pid").to_string();
            let done = Command::new("callgrind_control").args([what, &pid]).stdout(Stdio::null()).status();
            assert!(done.is_ok_and(|s| s.success()), "callgrind_control {what} {pid}");
        }
    };
    callgrind("--zero");
    let (cpu0, bytes0, t0) = (cpu_seconds(pid), idle_bytes.load(Ordering::Relaxed), Instant::now());
    tokio::time::sleep(Duration::from_secs_f64(a.quiet)).await;
    let quiet = t0.elapsed().as_secs_f64();
    callgrind("--dump");
    let idle_cpu = (cpu_seconds(pid) - cpu0) / quiet;
    let idle_sent = idle_bytes.load(Ordering::Relaxed) - bytes0;
    println!(
        "{} idle players (all in within {join_seconds:.0} s): server {:.1} MiB resident, {:.1} KiB per player; \
         over {quiet:.0} s: CPU {:.2} % of one core, {idle_sent} bytes sent ({:.0} B/s a player: the HUD's clock)",
        a.idle,
        mib(rss_idle),
        (rss_idle.saturating_sub(rss_empty)) as f64 / 1024.0 / a.idle.max(1) as f64,
        idle_cpu * 100.0,
        idle_sent as f64 / quiet / a.idle.max(1) as f64
    );
    stop.send_replace(true);
    for handle in connecting {
        let _ = handle.await;
    }
    tokio::time::sleep(Duration::from_secs(2)).await;

    // 2. Walking players.
    let mut walkers = Vec::new();
    for i in 0..a.walkers {
        let at = addrs[i % addrs.len()];
        let connected = if a.one_address {
            connect(at, &format!("walker{i}"), size).await
        } else {
            load::connect_over(from_own_address(at, i).await, &format!("walker{i}"), size).await
        };
        let connected = connected.expect("connect a walker");
        walkers.push(connected);
    }
    if !a.first.is_empty() {
        for walker in &walkers {
            walker.channel.data(&a.first[..]).await.expect("the first keys sent");
        }
    }
    tokio::time::sleep(Duration::from_secs(1)).await;
    let rss_walk_before = rss_all();
    let (cpu0, client_cpu0, t0) = (cpu_all(), cpu_seconds(None), Instant::now());
    let tasks: Vec<_> =
        walkers.into_iter().map(|c| tokio::spawn(load::walk(c, a.rate, a.seconds, b"\x1b[D"))).collect();
    let mut latencies = Vec::new();
    let (mut frames, mut bytes, mut closed) = (0u64, 0u64, 0usize);
    let mut rss_walk = 0;
    for task in tasks {
        let stats = task.await.expect("walker");
        rss_walk = rss_walk.max(rss_all());
        frames += stats.frames;
        bytes += stats.bytes_after_first;
        closed += usize::from(stats.closed);
        latencies.extend(stats.latencies);
    }
    let elapsed = t0.elapsed().as_secs_f64();
    let server_cpu = (cpu_all() - cpu0) / elapsed;
    let client_cpu = (cpu_seconds(None) - client_cpu0) / elapsed;
    let n = a.walkers.max(1) as f64;
    let (p50, p99, max) =
        (quantile(&mut latencies, 0.5), quantile(&mut latencies, 0.99), quantile(&mut latencies, 1.0));
    if a.servers > 1 {
        println!(
            "{} servers in one world ({} walkers each): CPU and memory summed",
            a.servers,
            a.walkers / a.servers
        );
    }
    println!(
        "{} walking at {} keys/s, {}x{}, {:.0} s: {:.1} frames/s per player delivered, key-to-frame p50 {:.1} ms \
         p99 {:.1} ms max {:.1} ms; server CPU {:.0} % of one core (load generator {:.0} %), {:.1} MiB resident \
         ({:.1} MiB before walking); {:.1} KiB/s per player; {closed} dropped",
        a.walkers,
        a.rate,
        a.cols,
        a.rows,
        a.seconds,
        frames as f64 / elapsed / n,
        p50 * 1e3,
        p99 * 1e3,
        max * 1e3,
        server_cpu * 100.0,
        client_cpu * 100.0,
        mib(rss_walk),
        mib(rss_walk_before),
        bytes as f64 / elapsed / n / 1024.0,
    );
}
