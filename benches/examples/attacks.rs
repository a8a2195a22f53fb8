//! Issue #34's attacks on `mazewalk serve`, reproduced at full strength against two server binaries in
//! one run — "before" and "after" — for BENCHMARKS.md ("The server on the open internet"). Each
//! server is a process of its own on loopback (its CPU and log are its own); the clients are in this
//! process. Throughout each attack a witness player turns at 10 keys a second; its key-to-frame
//! latency (p50, p99, worst) says what the attack costs the players already in.
//!
//! 1. **group18**: two attackers at once, again and again, offer only
//!    `diffie-hellman-group18-sha512` and send an 8192-bit half they never computed.
//! 2. **junk kex**: four attackers at once, again and again, offer 600 junk key exchange names
//!    (15 KB); the server's log growth is measured.
//! 3. **held slots**: a server of 11 players; 10 log in, quit with `q` and keep their connections
//!    open; a newcomer then tries to log in.
//! 4. **handshakes**: 16 addresses (127.0.0.2–17) × 16 connections that say their version and
//!    nothing more, held; a newcomer from another address then tries to log in.
//! 5. **idle handshakes** (issue #40): attackers on `--addresses` loopback addresses (127.1.x.y, one
//!    after another) open connections that say `SSH-2.0-x` and wait, `--rates` a second (each rate a
//!    run of its own, on a fresh server); meanwhile newcomers — stock `ssh -tt` in a pty, one after
//!    another, each from an address of its own (127.2.x.y) — count as in when the game's first frame
//!    (its alternate screen) arrives within 3 s.
//!
//! 6. **http** (issue #44; a binary that knows `--http` only): the server also serves `--http`;
//!    three attackers at once, again and again: a slowloris (half a request head, held), an
//!    event-stream client (`GET /events`, held), a 32 KiB header; up to 2,000 of their connections
//!    held open at once.
//! 7. **render** (red-team pass 3): 16 connections from one address (127.0.0.9, the default
//!    `--max-per-address`) with 400×150 ptys turn 60 times a second in sextants (`cc`), with
//!    textures (`t`) and culling off (`b`, where the binary lets a served player have it). Its note
//!    counts the frames drawn for them: with one drawing budget per address group
//!    (`Limits::render_rate`), about 4 a second between the 16.
//! 8. **spectators** (red-team pass 12): 255 idle players (and the witness) walk the maze; four
//!    spectators of one address (`ssh watch@…`, the default per-address share) each send `l`
//!    (follow the leader) at 15 KiB a second, just under the input rate.
//!
//! ```sh
//! cargo build --release                           # the "after" binary: target/release/mazewalk
//! git worktree add /tmp/serve-before <commit> && (cd /tmp/serve-before && cargo build --release)
//! cargo run --release -p mazewalk-bench --example attacks -- \
//!     --before /tmp/serve-before/target/release/mazewalk --seconds 10   # [--only group18]
//! cargo run --release -p mazewalk-bench --example attacks -- --only idle \
//!     --addresses 1000 --rates 100,500,2000 --seconds 20    # [--before …] [--max-handshakes N]
//! ```
//!
//! Only flags both binaries know are passed: `--open --listen --host-key --max-players
//! --max-per-address`; each server's limits are otherwise its defaults.

use mazewalk_testkit::load;
use mazewalk_testkit::raw_ssh as raw;
use mazewalk_testkit::server_process;

use std::io::{BufRead as _, Write as _};
use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use load::{connect, cpu_seconds, quantile};

struct Args {
    before: Option<PathBuf>,
    after: PathBuf,
    seconds: f64,
    only: Option<String>,
    /// Idle handshakes opened a second, one run each (attack 5).
    rates: Vec<f64>,
    /// The addresses they come from (attack 5).
    addresses: u32,
    /// `--max-handshakes` for the servers of attack 5 (their default if not given).
    max_handshakes: Option<u32>,
}

/// What `--help` prints, and a refusal with it.
const USAGE: &str =
    "usage: cargo run --release -p mazewalk-bench --example attacks -- [--before BIN] [--after BIN]
    [--seconds S] [--only NAME] [--rates R,R,…] [--addresses N] [--max-handshakes N]
(see the example's doc for the attacks and their names)";

fn args() -> Args {
    let mut a = Args {
        before: None,
        after: server_process::release_binary(),
        seconds: 10.0,
        only: None,
        rates: vec![500.0],
        addresses: 1000,
        max_handshakes: None,
    };
    for (flag, value) in server_process::flags(USAGE) {
        match flag.as_str() {
            "--before" => a.before = Some(value.into()),
            "--after" => a.after = value.into(),
            "--seconds" => a.seconds = server_process::value("--seconds", &value, USAGE),
            "--only" => a.only = Some(value),
            "--rates" => {
                a.rates = value.split(',').map(|r| server_process::value("--rates", r, USAGE)).collect()
            }
            "--addresses" => a.addresses = server_process::value("--addresses", &value, USAGE),
            "--max-handshakes" => {
                a.max_handshakes = Some(server_process::value("--max-handshakes", &value, USAGE))
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
    /// Its `--http` address, when given one.
    http: Option<SocketAddr>,
    log: PathBuf,
    scratch: PathBuf,
}

impl ServerProcess {
    fn start(bin: &Path, max_players: u32, max_per_address: u32) -> ServerProcess {
        ServerProcess::start_with(bin, max_players, max_per_address, &[])
    }

    fn start_with(bin: &Path, max_players: u32, max_per_address: u32, more: &[String]) -> ServerProcess {
        static RUN: AtomicU64 = AtomicU64::new(0);
        let scratch = std::env::temp_dir().join(format!(
            "mazewalk-attacks-{}-{}",
            std::process::id(),
            RUN.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&scratch).expect("scratch");
        let log = scratch.join("log");
        let mut child = Command::new(bin)
            .args(["serve", "--open", "--listen", "127.0.0.1:0"])
            .args([
                "--max-players",
                &max_players.to_string(),
                "--max-per-address",
                &max_per_address.to_string(),
            ])
            .args(more)
            .arg("--host-key")
            .arg(scratch.join("host_key"))
            .env("HOME", &scratch)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(std::fs::File::create(&log).expect("log file"))
            .spawn()
            .expect("start the server");
        let (addr, mut stdout) = server_process::announced(&mut child);
        let mut http = None;
        if more.iter().any(|m| m == "--http") {
            let mut next = String::new();
            while http.is_none() && stdout.read_line(&mut next).expect("a line") > 0 {
                http = next
                    .trim()
                    .strip_prefix("metrics at http://")
                    .and_then(|a| a.strip_suffix("/metrics")?.parse().ok());
                next.clear();
            }
        }
        server_process::drain(stdout);
        ServerProcess { child, addr, http, log, scratch }
    }

    fn pid(&self) -> Option<u32> {
        Some(self.child.id())
    }

    fn log_bytes(&self) -> u64 {
        std::fs::metadata(&self.log).map_or(0, |m| m.len())
    }
}

impl Drop for ServerProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.scratch);
    }
}

/// What one attack did to one server.
#[derive(Default)]
struct Outcome {
    p50_ms: f64,
    p99_ms: f64,
    max_ms: f64,
    keys: usize,
    server_cpu: f64,
    note: String,
}

/// Runs `attack` while a witness turns for `seconds`; returns the witness's latencies and the
/// server's CPU seconds meanwhile.
async fn witnessed<F>(server: &ServerProcess, seconds: f64, attack: F) -> (Outcome, F::Output)
where
    F: std::future::Future + Send + 'static,
    F::Output: Send + 'static,
{
    let witness = connect(server.addr, "witness", (80, 24)).await.expect("the witness");
    let cpu0 = cpu_seconds(server.pid());
    let attack = tokio::spawn(attack);
    let stats = load::walk(witness, 10.0, seconds, b"\x1b[D").await;
    let result = attack.await.expect("the attack");
    let server_cpu = cpu_seconds(server.pid()) - cpu0;
    let mut latencies = stats.latencies;
    let outcome = Outcome {
        p50_ms: quantile(&mut latencies, 0.5) * 1e3,
        p99_ms: quantile(&mut latencies, 0.99) * 1e3,
        max_ms: quantile(&mut latencies, 1.0) * 1e3,
        keys: latencies.len(),
        server_cpu,
        note: String::new(),
    };
    (outcome, result)
}

/// Runs `one` on `threads` threads again and again until `stop`; returns how many times it ran.
async fn repeat(threads: usize, stop: Arc<AtomicBool>, one: impl Fn(u64) + Send + Sync + 'static) -> u64 {
    let one = Arc::new(one);
    let count = Arc::new(AtomicU64::new(0));
    let tasks: Vec<_> = (0..threads)
        .map(|_| {
            let (one, stop, count) = (Arc::clone(&one), Arc::clone(&stop), Arc::clone(&count));
            tokio::task::spawn_blocking(move || {
                while !stop.load(Ordering::Relaxed) {
                    one(count.fetch_add(1, Ordering::Relaxed));
                }
            })
        })
        .collect();
    for task in tasks {
        let _ = task.await;
    }
    count.load(Ordering::Relaxed)
}

/// Stops `stop` after `seconds`.
fn stop_after(seconds: f64) -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    std::thread::spawn(move || {
        std::thread::sleep(Duration::from_secs_f64(seconds));
        flag.store(true, Ordering::Relaxed);
    });
    stop
}

async fn group18(bin: &Path, seconds: f64) -> Outcome {
    let server = ServerProcess::start(bin, 256, 16);
    let addr = server.addr;
    let (mut outcome, handshakes) = witnessed(&server, seconds, async move {
        repeat(2, stop_after(seconds), move |i| {
            if let Ok(mut stream) = raw::connect(None, addr) {
                let _ = stream.write_all(&raw::kexinit("diffie-hellman-group18-sha512"));
                let _ = stream.write_all(&raw::kexdh_init(8192, i));
                // the server's reply (it computed its half) or its refusal: then the next one
                let _ = raw::until_answered(&mut stream, Duration::from_secs(10));
            }
        })
        .await
    })
    .await;
    outcome.note = format!("{handshakes} handshakes tried");
    outcome
}

async fn junk_kex(bin: &Path, seconds: f64) -> Outcome {
    let server = ServerProcess::start(bin, 256, 16);
    let addr = server.addr;
    let log0 = server.log_bytes();
    let kexinit = Arc::new(raw::junk_kexinit(600));
    let (mut outcome, connections) = witnessed(&server, seconds, async move {
        repeat(4, stop_after(seconds), move |_| {
            if let Ok(mut stream) = raw::connect(None, addr) {
                let _ = stream.write_all(&kexinit);
                let _ = raw::until_closed(&mut stream, Duration::from_secs(2));
            }
        })
        .await
    })
    .await;
    let grown = server.log_bytes() - log0;
    outcome.note = format!(
        "{connections} connections; log grew {:.1} KiB ({:.1} KiB/s)",
        grown as f64 / 1024.0,
        grown as f64 / 1024.0 / seconds
    );
    outcome
}

async fn held_slots(bin: &Path, seconds: f64) -> Outcome {
    let server = ServerProcess::start(bin, 11, 100);
    let addr = server.addr;
    let (mut outcome, newcomer) = witnessed(&server, seconds, async move {
        let mut held = Vec::new();
        for i in 0..10 {
            if let Ok(load::Connected { handle, channel }) =
                connect(addr, &format!("holder{i}"), (80, 24)).await
            {
                let _ = channel.data(&b"q"[..]).await;
                held.push((handle, channel)); // the game ends; the connection is kept
            }
        }
        tokio::time::sleep(Duration::from_secs_f64(seconds / 2.0)).await;
        let still_open = held.iter().filter(|(h, _)| !h.is_closed()).count();
        let started = Instant::now();
        let newcomer = connect(addr, "newcomer", (80, 24)).await;
        (still_open, newcomer.is_ok(), started.elapsed())
    })
    .await;
    let (still_open, got_in, took) = newcomer;
    outcome.note = format!(
        "{still_open} of 10 quit connections still open after {:.0} s; a newcomer {}",
        seconds / 2.0,
        if got_in { format!("got in ({:.0} ms)", took.as_secs_f64() * 1e3) } else { "was refused".into() }
    );
    outcome
}

async fn handshakes(bin: &Path, seconds: f64) -> Outcome {
    let server = ServerProcess::start(bin, 256, 16);
    let addr = server.addr;
    let (mut outcome, newcomer) = witnessed(&server, seconds, async move {
        let held = tokio::task::spawn_blocking(move || {
            let mut held = Vec::new();
            for n in 2..18u8 {
                for _ in 0..16 {
                    if let Ok(stream) = raw::connect(Some(IpAddr::from([127, 0, 0, n])), addr) {
                        held.push(stream);
                    }
                }
            }
            held
        })
        .await
        .expect("the flood");
        tokio::time::sleep(Duration::from_secs_f64(seconds / 2.0)).await;
        let socket = tokio::net::TcpSocket::new_v4().expect("socket");
        socket.bind(SocketAddr::new(IpAddr::from([127, 0, 0, 200]), 0)).expect("bind");
        let started = Instant::now();
        let newcomer = match socket.connect(addr).await {
            Ok(stream) => load::connect_over(stream, "newcomer", (80, 24)).await.is_ok(),
            Err(_) => false,
        };
        let took = started.elapsed();
        drop(held);
        (newcomer, took)
    })
    .await;
    let (got_in, took) = newcomer;
    outcome.note = format!(
        "256 silent connections from 16 addresses held; a newcomer {}",
        if got_in { format!("got in ({:.0} ms)", took.as_secs_f64() * 1e3) } else { "was refused".into() }
    );
    outcome
}

async fn render(bin: &Path, seconds: f64) -> Outcome {
    let server = ServerProcess::start(bin, 256, 16);
    let addr = server.addr;
    let (mut outcome, (heavy, frames)) = witnessed(&server, seconds, async move {
        let tasks: Vec<_> = (0..16)
            .map(|i| {
                tokio::spawn(async move {
                    let socket = tokio::net::TcpSocket::new_v4().ok()?;
                    socket.bind(SocketAddr::new(IpAddr::from([127, 0, 0, 9]), 0)).ok()?;
                    let stream = socket.connect(addr).await.ok()?;
                    let connected =
                        load::connect_over(stream, &format!("heavy{i}"), (400, 150)).await.ok()?;
                    connected.channel.data(&b"bcct"[..]).await.ok()?;
                    Some(load::walk(connected, 60.0, seconds, b"\x1b[D").await.frames)
                })
            })
            .collect();
        let (mut heavy, mut frames) = (0, 0);
        for task in tasks {
            if let Some(n) = task.await.ok().flatten() {
                (heavy, frames) = (heavy + 1, frames + n);
            }
        }
        (heavy, frames)
    })
    .await;
    outcome.note =
        format!("{heavy} connections from one address at 400×150, sextants: {frames} frames drawn for them");
    outcome
}

/// Idle players in attack 8, beside the witness.
const CROWD: usize = 255;

async fn spectators(bin: &Path, seconds: f64) -> Outcome {
    let server = ServerProcess::start(bin, 300, 400);
    let (stop, stopped) = tokio::sync::watch::channel(false);
    let mut idlers = Vec::new();
    for i in 0..CROWD {
        let connected = connect(server.addr, &format!("idle{i}"), (80, 24)).await.expect("an idle player");
        idlers.push(tokio::spawn(load::idle(connected, Arc::default(), stopped.clone())));
    }
    let addr = server.addr;
    let keys: &'static [u8] = Box::leak(vec![b'l'; 1536].into_boxed_slice());
    let (mut outcome, watched) = witnessed(&server, seconds, async move {
        let tasks: Vec<_> = (0..4)
            .map(|_| {
                tokio::spawn(async move {
                    let connected = connect(addr, "watch", (80, 24)).await.ok()?;
                    Some(load::walk(connected, 10.0, seconds, keys).await)
                })
            })
            .collect();
        let mut watched = 0;
        for task in tasks {
            watched += usize::from(task.await.ok().flatten().is_some_and(|s| !s.closed));
        }
        watched
    })
    .await;
    let _ = stop.send(true);
    for idler in idlers {
        let _ = idler.await;
    }
    outcome.note = format!("{CROWD} idle players; {watched} spectators sending `l` at 15 KiB/s each");
    outcome
}

/// Attacker address `n` (0..65,536): 127.1.x.y.
fn attacker(n: u32) -> IpAddr {
    IpAddr::from([127, 1, (n >> 8) as u8, n as u8])
}

/// Opens idle handshakes to `addr` (`SSH-2.0-x`, then nothing) `rate` a second from `addresses`
/// addresses in turn until `stop`; each is held until the server closes it (30 s at most). Returns
/// how many were opened.
async fn idle_flood(addr: SocketAddr, addresses: u32, rate: f64, stop: Arc<AtomicBool>) -> u64 {
    use tokio::io::{AsyncReadExt as _, AsyncWriteExt as _};
    let started = tokio::time::Instant::now();
    let mut opened = 0u64;
    while !stop.load(Ordering::Relaxed) {
        tokio::time::sleep_until(started + Duration::from_secs_f64(opened as f64 / rate)).await;
        let from = attacker((opened % u64::from(addresses)) as u32);
        opened += 1;
        tokio::spawn(async move {
            let socket = tokio::net::TcpSocket::new_v4().ok()?;
            socket.bind(SocketAddr::new(from, 0)).ok()?;
            let mut stream =
                tokio::time::timeout(Duration::from_secs(5), socket.connect(addr)).await.ok()?.ok()?;
            stream.write_all(b"SSH-2.0-x\r\n").await.ok()?;
            let mut sink = [0u8; 2048];
            let held = async {
                while stream.read(&mut sink).await.ok()? > 0 {}
                Some(())
            };
            let _ = tokio::time::timeout(Duration::from_secs(30), held).await;
            Some(())
        });
    }
    opened
}

/// Stock `ssh -tt` (testkit's [`ssh_args`](mazewalk_testkit::ssh_args), to the server on 127.0.0.1)
/// in an 80×24 pty from `from`, as `newcomer`: how long until the game's first frame (the alternate
/// screen) arrives, or `None` if not within `within`. The client is killed after.
fn ssh_newcomer(addr: SocketAddr, from: IpAddr, within: Duration) -> Option<Duration> {
    use std::io::Read as _;
    let started = Instant::now();
    let (mut child, master) =
        mazewalk_testkit::ssh_in_pty(Some(&from.to_string()), addr.port(), None, "newcomer", (80, 24), &[]);
    let (seen, first_frame) = std::sync::mpsc::channel();
    let mut screen = master;
    std::thread::spawn(move || {
        let (mut got, mut buf) = (Vec::new(), [0u8; 4096]);
        while let Ok(n @ 1..) = screen.read(&mut buf) {
            got.extend_from_slice(&buf[..n]);
            if got.windows(8).any(|w| w == b"\x1b[?1049h") {
                let _ = seen.send(());
                return;
            }
        }
    });
    let got_in = first_frame.recv_timeout(within).ok().map(|()| started.elapsed());
    let _ = child.kill();
    let _ = child.wait();
    got_in
}

async fn idle_handshakes(bin: &Path, a: &Args, rate: f64) -> Outcome {
    let (seconds, addresses) = (a.seconds, a.addresses);
    let more: Vec<String> =
        a.max_handshakes.iter().flat_map(|n| ["--max-handshakes".to_string(), n.to_string()]).collect();
    let server = ServerProcess::start_with(bin, 256, 16, &more);
    let addr = server.addr;
    let (mut outcome, (opened, newcomers)) = witnessed(&server, seconds, async move {
        let stop = stop_after(seconds);
        let flood = tokio::spawn(idle_flood(addr, addresses, rate, Arc::clone(&stop)));
        tokio::time::sleep(Duration::from_millis(500)).await; // every slot taken
        let newcomers = tokio::task::spawn_blocking(move || {
            let mut took = Vec::new();
            for k in 0u32.. {
                if stop.load(Ordering::Relaxed) {
                    break;
                }
                let from = IpAddr::from([127, 2, (k / 250) as u8, (k % 250 + 1) as u8]);
                took.push(ssh_newcomer(addr, from, Duration::from_secs(3)));
                std::thread::sleep(Duration::from_millis(200));
            }
            took
        })
        .await
        .expect("the newcomers");
        (flood.await.expect("the flood"), newcomers)
    })
    .await;
    let mut times: Vec<f64> = newcomers.iter().flatten().map(Duration::as_secs_f64).collect();
    let median = if times.is_empty() { f64::NAN } else { quantile(&mut times, 0.5) * 1e3 };
    outcome.note = format!(
        "{opened} idle handshakes ({rate:.0}/s from {addresses} addresses); newcomers (stock ssh) in within 3 s: \
         **{} of {}** ({:.0} %), median {median:.0} ms",
        times.len(),
        newcomers.len(),
        100.0 * times.len() as f64 / newcomers.len().max(1) as f64
    );
    outcome
}

async fn http(bin: &Path, seconds: f64) -> Outcome {
    use std::io::Read as _;
    let more = ["--http".to_string(), "127.0.0.1:0".to_string()];
    let server = ServerProcess::start_with(bin, 256, 16, &more);
    let http = server.http.expect("the --http address");
    let held = Arc::new(std::sync::Mutex::new(std::collections::VecDeque::new()));
    let counts = Arc::new([(); 5].map(|()| AtomicU64::new(0))); // loris, events 200, events other, big 431, big other
    let (held2, counts2) = (Arc::clone(&held), Arc::clone(&counts));
    let (mut outcome, attempts) = witnessed(&server, seconds, async move {
        repeat(3, stop_after(seconds), move |i| {
            let Ok(mut stream) = std::net::TcpStream::connect(http) else { return };
            let _ = stream.set_read_timeout(Some(Duration::from_secs(2)));
            let kind = i % 3;
            let mut status = [0u8; 12];
            match kind {
                0 => {
                    let _ = stream.write_all(b"GET /metrics HTTP/1.1\r\nHost: x\r\nX-Slow: ");
                    counts2[0].fetch_add(1, Ordering::Relaxed);
                }
                1 => {
                    let _ = stream.write_all(b"GET /events HTTP/1.1\r\nHost: x\r\n\r\n");
                    let ok = stream.read_exact(&mut status).is_ok() && &status[9..12] == b"200";
                    counts2[if ok { 1 } else { 2 }].fetch_add(1, Ordering::Relaxed);
                }
                _ => {
                    let head = format!(
                        "GET /metrics HTTP/1.1\r\nHost: x\r\nX-Big: {}\r\n\r\n",
                        "a".repeat(32 * 1024)
                    );
                    let _ = stream.write_all(head.as_bytes());
                    let ok = stream.read_exact(&mut status).is_ok() && &status[9..12] == b"431";
                    counts2[if ok { 3 } else { 4 }].fetch_add(1, Ordering::Relaxed);
                    return;
                }
            }
            let mut held = held2.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
            held.push_back(stream);
            if held.len() > 2000 {
                held.pop_front();
            }
        })
        .await
    })
    .await;
    held.lock().unwrap_or_else(std::sync::PoisonError::into_inner).clear();
    let c: Vec<u64> = counts.iter().map(|n| n.load(Ordering::Relaxed)).collect();
    outcome.note = format!(
        "{attempts} HTTP connections: {} slowloris heads; {} event streams ({} answered 200, the rest refused or closed at the cap); {} 32 KiB headers ({} answered 431)",
        c[0],
        c[1] + c[2],
        c[1],
        c[3] + c[4],
        c[3]
    );
    outcome
}

#[tokio::main]
async fn main() {
    let a = args();
    let mut binaries: Vec<(&str, PathBuf)> = Vec::new();
    if let Some(before) = &a.before {
        binaries.push(("before", before.clone()));
    }
    binaries.push(("after", a.after.clone()));
    for (_, bin) in &binaries {
        assert!(bin.exists(), "{} is missing: build it first (`cargo build --release`)", bin.display());
    }
    println!(
        "| attack | binary | witness p50 / p99 / worst (ms) | keys answered | server CPU (s) | what else |"
    );
    println!("|---|---|---|---|---|---|");
    let mut attacks: Vec<(String, Option<f64>)> =
        ["group18", "junk kex", "held slots", "handshakes", "http", "render", "spectators"]
            .iter()
            .map(|a| ((*a).to_string(), None))
            .collect();
    attacks.extend(a.rates.iter().map(|&rate| (format!("idle handshakes {rate:.0}/s"), Some(rate))));
    for (attack, rate) in &attacks {
        if a.only.as_ref().is_some_and(|only| !attack.starts_with(only.as_str())) {
            continue;
        }
        for (which, bin) in &binaries {
            if attack == "http" && *which == "before" {
                continue; // (a binary without --http)
            }
            let outcome = match (attack.as_str(), rate) {
                (_, Some(rate)) => idle_handshakes(bin, &a, *rate).await,
                ("group18", _) => group18(bin, a.seconds).await,
                ("junk kex", _) => junk_kex(bin, a.seconds).await,
                ("held slots", _) => held_slots(bin, a.seconds).await,
                ("http", _) => http(bin, a.seconds).await,
                ("render", _) => render(bin, a.seconds).await,
                ("spectators", _) => spectators(bin, a.seconds).await,
                _ => handshakes(bin, a.seconds).await,
            };
            println!(
                "| {attack} | {which} | {:.1} / {:.1} / {:.0} | {} of {:.0} | {:.2} | {} |",
                outcome.p50_ms,
                outcome.p99_ms,
                outcome.max_ms,
                outcome.keys,
                a.seconds * 10.0,
                outcome.server_cpu,
                outcome.note
            );
            tokio::time::sleep(Duration::from_millis(500)).await;
        }
    }
}
