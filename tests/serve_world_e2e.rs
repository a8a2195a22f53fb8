//! End to end, issue #35: two `mazewalk serve --world redis://…` processes (the built binary) on two
//! ports, one real `redis-server` (Debian's package, started here on a free loopback port), and stock
//! `ssh -tt` clients in pseudo-terminals read by a `vt100` emulator (as tests/serve_e2e.rs does).
//!
//! Checks: bob on server B shows on the map of alice on server A, and the HUD counts both; bob
//! reaches the exit and alice's screen announces it, and bob's exit box ranks him from the world's
//! records in Redis (which `mazewalk records --world` lists too); server B killed (SIGKILL, no
//! goodbye), bob leaves alice's view within 5 s; server C stopped (SIGTERM) tells carol, then
//! leaves the world, and carol leaves alice's view at once; Redis killed, alice turns and her HUD
//! says the world is offline, Redis back, online again. A server that cannot join says why and
//! exits 1; a world over TLS with `--world-ca`. Loopback only; every wait has a deadline; every
//! child is killed on drop.
#![cfg(unix)]

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::num::NonZeroU16;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use rustix::termios::Winsize;

/// Longest wait for anything. Generous for a loaded CI machine; each step takes well under a second.
const TIMEOUT: Duration = Duration::from_secs(20);

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A scratch folder of the test's own, removed on drop.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("mazewalk-world-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A free port on 127.0.0.1 (free when asked; the test's own processes take it at once).
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).expect("a free port").port()
}

/// `redis-server`, without persistence, on a free loopback port; killed on drop.
struct Redis {
    child: Child,
    port: u16,
    tls: bool,
}

impl Redis {
    fn start(dir: &std::path::Path) -> Redis {
        Redis::start_with(dir, &[])
    }

    /// One that speaks TLS only, with a certificate for 127.0.0.1 signed by a CA of its own, made by
    /// `openssl` in `dir` (`ca.pem`).
    fn start_tls(dir: &std::path::Path) -> Redis {
        make_certificates(dir);
        let file = |name: &str| dir.join(name).display().to_string();
        let (cert, key, ca) = (file("redis.pem"), file("redis.key"), file("ca.pem"));
        let mut redis = Redis::start_with(
            dir,
            &[
                "--tls-port",
                "PORT",
                "--port",
                "0",
                "--tls-auth-clients",
                "no",
                "--tls-cert-file",
                &cert,
                "--tls-key-file",
                &key,
                "--tls-ca-cert-file",
                &ca,
            ],
        );
        redis.tls = true;
        redis
    }

    fn start_with(dir: &std::path::Path, tls: &[&str]) -> Redis {
        Redis::start_on(dir, free_port(), tls)
    }

    /// Starts it again (empty) on the same port, after it was killed.
    fn restart(&mut self, dir: &std::path::Path) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        *self = Redis::start_on(dir, self.port, &[]);
    }

    fn start_on(dir: &std::path::Path, port: u16, tls: &[&str]) -> Redis {
        let port_arg = port.to_string();
        let tls: Vec<&str> = tls.iter().map(|&a| if a == "PORT" { port_arg.as_str() } else { a }).collect();
        let plain = ["--port", port_arg.as_str()];
        let child = Command::new("redis-server")
            .args(if tls.is_empty() { &plain[..] } else { &tls[..] })
            .args(["--bind", "127.0.0.1", "--protected-mode", "no"])
            .arg("--dir")
            .arg(dir)
            .args(["--save", "", "--appendonly", "no", "--daemonize", "no"])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|err| {
                panic!("redis-server ({err}): install Debian's redis-server (.ci/run does)")
            });
        let redis = Redis { child, port, tls: !tls.is_empty() };
        let deadline = Instant::now() + Duration::from_secs(10);
        while !redis.listens() {
            assert!(Instant::now() < deadline, "redis-server did not answer within 10 s");
            std::thread::sleep(Duration::from_millis(20));
        }
        redis
    }

    /// Whether it answers a PING (inline command, RESP reply); over TLS, whether it takes connections.
    fn listens(&self) -> bool {
        let Ok(mut stream) = TcpStream::connect(("127.0.0.1", self.port)) else { return false };
        if self.tls {
            return true;
        }
        let _ = stream.set_read_timeout(Some(Duration::from_secs(1)));
        let mut reply = [0u8; 7];
        stream.write_all(b"PING\r\n").is_ok()
            && stream.read_exact(&mut reply).is_ok()
            && &reply == b"+PONG\r\n"
    }

    fn url(&self) -> String {
        let scheme = if self.tls { "rediss" } else { "redis" };
        format!("{scheme}://127.0.0.1:{}/0", self.port)
    }
}

impl Drop for Redis {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A CA, and a certificate for 127.0.0.1 it signed, made by `openssl` in `dir` (`ca.pem`, `redis.pem`,
/// `redis.key`).
fn make_certificates(dir: &std::path::Path) {
    let openssl = |args: &[&str]| {
        let status = Command::new("openssl")
            .args(args)
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap_or_else(|err| panic!("openssl could not be run ({err}): install it (.ci/run does)"));
        assert!(status.success(), "openssl {args:?}");
    };
    let ec = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"];
    let ca = ["-keyout", "ca.key", "-out", "ca.pem", "-days", "2", "-subj", "/CN=mazewalk test CA"];
    openssl(&[&["req", "-x509"][..], &ec, &ca].concat());
    let csr = ["-keyout", "redis.key", "-out", "redis.csr", "-subj", "/CN=127.0.0.1"];
    openssl(&[&["req"][..], &ec, &csr].concat());
    std::fs::write(dir.join("ext.cnf"), "subjectAltName=IP:127.0.0.1\nbasicConstraints=CA:FALSE\n")
        .expect("ext.cnf");
    openssl(&[
        "x509",
        "-req",
        "-in",
        "redis.csr",
        "-CA",
        "ca.pem",
        "-CAkey",
        "ca.key",
        "-CAcreateserial",
        "-out",
        "redis.pem",
        "-days",
        "2",
        "-extfile",
        "ext.cnf",
    ]);
}

/// `mazewalk serve ARGS` that must refuse to start: its exit code and what it said, within 10 s.
fn refused(scratch: &Scratch, args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .arg("serve")
        .args(["--listen", "127.0.0.1:0", "--open", "--host-key"])
        .arg(scratch.0.join("host_key_refused"))
        .args(args)
        .env("HOME", &scratch.0)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mazewalk serve");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > Duration::from_secs(10) {
            let _ = child.kill();
            panic!("mazewalk serve {args:?} did not give up within 10 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut said = String::new();
    child.stderr.take().expect("stderr").read_to_string(&mut said).expect("its stderr");
    (status.code(), said)
}

/// `mazewalk serve`, with its log.
struct Server {
    child: Child,
    port: u16,
    log: Arc<Mutex<String>>,
}

impl Server {
    /// A server of its own host key `name` on `maze`, in the world at `world`.
    fn start(scratch: &Scratch, name: &str, maze: &std::path::Path, world: &str) -> Server {
        Server::start_with(scratch, name, maze, world, &[])
    }

    fn start_with(
        scratch: &Scratch,
        name: &str,
        maze: &std::path::Path,
        world: &str,
        more: &[&str],
    ) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
            .arg("serve")
            .args(["--listen", "127.0.0.1:0", "--open", "--world", world, "--host-key"])
            .arg(scratch.0.join(format!("host_key_{name}")))
            .arg(maze)
            .args(more)
            .env("HOME", &scratch.0)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start mazewalk serve");
        let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
        let log = Arc::new(Mutex::new(String::new()));
        let stderr = child.stderr.take().expect("stderr");
        let sink = Arc::clone(&log);
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                let mut log = lock(&sink);
                log.push_str(&line);
                log.push('\n');
            }
        });
        let mut line = String::new();
        stdout.read_line(&mut line).expect("the first line");
        let port = line
            .trim()
            .split(", ")
            .next()
            .and_then(|first| first.rsplit_once(':'))
            .and_then(|(_, port)| port.parse().ok())
            .unwrap_or_else(|| {
                std::thread::sleep(Duration::from_millis(200));
                panic!("expected `mazewalk: serving on ADDR:PORT`, got {line:?}; log:\n{}", lock(&log))
            });
        std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink())); // the rest
        Server { child, port, log }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// What the reader thread shares with the test.
struct Screen {
    parser: vt100::Parser,
    raw: Vec<u8>,
}

/// `ssh -tt` in a pty (its controlling terminal, through `setsid -c`), read by a `vt100` emulator
/// that answers the device-attributes queries as a terminal would.
struct Player {
    child: Child,
    master: File,
    shared: Arc<Mutex<Screen>>,
}

fn nz(n: u16) -> NonZeroU16 {
    NonZeroU16::new(n).expect("non-zero")
}

impl Player {
    fn connect(port: u16, user: &str) -> Player {
        let (cols, rows) = (100, 30);
        let size = Winsize { ws_row: rows, ws_col: cols, ws_xpixel: 0, ws_ypixel: 0 };
        let pty = rustix_openpty::openpty(None, Some(&size)).expect("openpty");
        let master = File::from(pty.controller);
        let slave = pty.user;
        let stdio = || Stdio::from(slave.try_clone().expect("dup the pty"));
        let child = Command::new("setsid")
            .args(["-c", "ssh", "-tt", "-F", "/dev/null", "-p", &port.to_string()])
            .args(["-o", "StrictHostKeyChecking=no", "-o", "UserKnownHostsFile=/dev/null"])
            .args(["-o", "LogLevel=ERROR", "-o", "BatchMode=yes", "-o", "IdentitiesOnly=yes"])
            .args(["-o", "ConnectTimeout=10", "-i", "/dev/null", &format!("{user}@127.0.0.1")])
            .env("TERM", "xterm-256color")
            .stdin(stdio())
            .stdout(stdio())
            .stderr(stdio())
            .spawn()
            .expect("spawn setsid -c ssh");
        drop(slave);
        let shared = Arc::new(Mutex::new(Screen {
            parser: vt100::Parser::new(nz(rows), nz(cols), 0),
            raw: Vec::new(),
        }));
        let mut input = master.try_clone().expect("dup");
        let mut answer = master.try_clone().expect("dup");
        let sink = Arc::clone(&shared);
        std::thread::spawn(move || {
            let mut buf = vec![0u8; 1 << 16];
            let mut scanned = 0usize;
            loop {
                let n = match input.read(&mut buf) {
                    Ok(0) | Err(_) => break,
                    Ok(n) => n,
                };
                let mut s = lock(&sink);
                s.raw.extend_from_slice(&buf[..n]);
                s.parser.process(&buf[..n]);
                let from = scanned.saturating_sub(2);
                let queries = s.raw[from..].windows(3).filter(|w| *w == b"\x1b[c").count();
                scanned = s.raw.len();
                drop(s);
                for _ in 0..queries {
                    let _ = answer.write_all(b"\x1b[?62;22c");
                }
            }
        });
        Player { child, master, shared }
    }

    fn send(&mut self, bytes: &[u8]) {
        self.master.write_all(bytes).expect("write to the pty");
    }

    /// Polls the screen until `ok` holds; panics with the screen after [`TIMEOUT`].
    fn wait_for(&self, what: &str, ok: impl Fn(&vt100::Screen) -> bool) {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            {
                let s = lock(&self.shared);
                if ok(s.parser.screen()) {
                    return;
                }
                assert!(
                    Instant::now() < deadline,
                    "timed out waiting for {what}; the screen shows:\n{}",
                    s.parser.screen().contents()
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn shows(&self, ok: impl Fn(&vt100::Screen) -> bool) -> bool {
        ok(lock(&self.shared).parser.screen())
    }

    fn read<T>(&self, f: impl Fn(&vt100::Screen) -> T) -> T {
        f(lock(&self.shared).parser.screen())
    }
}

impl Drop for Player {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The HUD's row.
fn hud_row(screen: &vt100::Screen) -> String {
    let rows = screen.size().0.get();
    screen.contents_between(rows - 1, 0, rows - 1, u16::MAX)
}

/// The game is on screen: the HUD's help hint on the bottom row.
fn playing(screen: &vt100::Screen) -> bool {
    screen.alternate_screen() && hud_row(screen).contains("? help")
}

/// Whether `ch` shows in the corner map (the top third of the right third of the screen).
fn on_map(screen: &vt100::Screen, ch: char) -> bool {
    let (rows, cols) = (screen.size().0.get(), screen.size().1.get());
    let width = (cols / 3).min(40);
    (0..rows / 3).any(|row| screen.contents_between(row, cols - width, row, cols).contains(ch))
}

/// Three tiles east from the start, the last one the exit.
const SHORT_RUN: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n#####\n#@.E#\n#####\n";

// issue #35: two servers, one world on Redis, stock ssh clients.
#[test]
fn two_servers_walk_one_world_on_redis() {
    let scratch = Scratch::new("two");
    let mut redis = Redis::start(&scratch.0);
    let maze = scratch.0.join("maze.grid");
    std::fs::write(&maze, SHORT_RUN).expect("write the maze");
    let server_a = Server::start(&scratch, "a", &maze, &redis.url());
    let mut server_b = Server::start(&scratch, "b", &maze, &redis.url());

    let alice = Player::connect(server_a.port, "alice");
    alice.wait_for("alice's game on server A", playing);
    let mut bob = Player::connect(server_b.port, "bob");
    bob.wait_for("bob's game on server B", playing);
    // The HUD counts the world's players. Bob then walks 3 steps east (3 units: a map character or
    // more from wherever he started, short of the exit 6 units away) and each sees the other, across
    // servers, on the map (on one spot, the map shows only the one in front: the viewer).
    alice.wait_for("2 in on alice's HUD", |s| hud_row(s).contains("2 in"));
    bob.wait_for("2 in on bob's HUD", |s| hud_row(s).contains("2 in"));
    for _ in 0..3 {
        bob.send(b"w");
        std::thread::sleep(Duration::from_millis(60));
    }
    alice.wait_for("bob (server B) on alice's map", |s| on_map(s, 'B'));
    bob.wait_for("alice (server A) on bob's map", |s| on_map(s, 'A'));
    assert!(!alice.shows(|s| hud_row(s).contains("world offline")), "Redis is up");

    // Bob holds `w` east into the exit tile; alice, on the other server, is told.
    let announced = |s: &vt100::Screen| s.contents().contains("bob reached the exit first");
    assert!(!alice.shows(announced), "nobody has reached the exit yet");
    for _ in 0..50 {
        bob.send(b"w");
        std::thread::sleep(Duration::from_millis(40));
    }
    alice.wait_for("the announcement on alice's screen (server A)", announced);
    bob.wait_for("bob's own exit box", |s| s.contents().contains("You found the exit in"));
    // Every finish reaches the other servers: bob's best time is in alice's player list.
    let mut alice = alice;
    alice.send(b"\t");
    alice.wait_for("bob's best time in alice's player list", |s| {
        s.contents().lines().any(|line| {
            let best = line.split_whitespace().last().unwrap_or("");
            line.contains("B  bob") && best.contains(':') && best.contains('.') // m:ss.s
        })
    });
    alice.send(b"\t");
    alice.wait_for("the list closed", |s| !s.contents().contains("Players: 2"));
    // The best times are the world's, in Redis: bob's exit box ranks him there.
    bob.wait_for("the world's best times in bob's exit box", |s| {
        let text = s.contents();
        text.contains("Best times here (1 player)") && text.contains("1. bob")
    });

    // `mazewalk records --world` reads the same table.
    let listed = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .arg("records")
        .arg(&maze)
        .args(["--world", &redis.url()])
        .output()
        .expect("mazewalk records --world");
    let text = String::from_utf8_lossy(&listed.stdout);
    assert!(listed.status.success(), "{listed:?}");
    assert!(text.contains("maze.grid") && text.contains("1 player, 1 finish"), "{text}");
    assert!(text.contains("   1. bob"), "{text}");
    let unnamed = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["records", "--world", &redis.url()])
        .output()
        .expect("run");
    assert!(!unnamed.status.success() && String::from_utf8_lossy(&unnamed.stderr).contains("name the maze"));

    // Server B dies without a word: bob leaves alice's view within 5 s (3 s of silence).
    assert!(alice.shows(|s| on_map(s, 'B')), "bob still shows before his server dies");
    server_b.child.kill().expect("SIGKILL server B");
    let killed = Instant::now();
    alice.wait_for("bob gone from alice's map", |s| !on_map(s, 'B') && hud_row(s).contains("1 in"));
    let gone = killed.elapsed();
    assert!(gone <= Duration::from_secs(5), "bob left alice's view {gone:?} after server B died");

    // Server C stopped by SIGTERM tells its player goodbye, then leaves the world: carol leaves
    // alice's view at once, well before the 3 s of silence a killed server takes.
    let mut server_c = Server::start(&scratch, "c", &maze, &redis.url());
    let carol = Player::connect(server_c.port, "carol");
    carol.wait_for("carol's game on server C", playing);
    // (Carol starts next to alice, maybe on her map character: the player list shows her.)
    alice.send(b"\t");
    alice.wait_for("carol (server C) in alice's player list", |s| {
        s.contents().contains("C  carol") && hud_row(s).contains("2 in")
    });
    let pid = rustix::process::Pid::from_child(&server_c.child);
    rustix::process::kill_process(pid, rustix::process::Signal::TERM).expect("SIGTERM server C");
    let stopped = Instant::now();
    carol.wait_for("carol told the server is shutting down", |s| s.contents().contains("shutting down"));
    alice.wait_for("carol gone from alice's list", |s| {
        !s.contents().contains("carol") && hud_row(s).contains("1 in")
    });
    let gone = stopped.elapsed();
    assert!(gone < Duration::from_millis(2500), "carol left alice's view {gone:?} after SIGTERM");
    let status = server_c.child.wait().expect("server C's exit");
    assert_eq!(status.code(), Some(143), "SIGTERM's exit code");

    // Redis dies: alice walks on, and her HUD says the world is offline; Redis back (empty), the
    // world is online again.
    alice.send(b"\t"); // (the player list closed)
    alice.wait_for("the list closed", |s| !s.contents().contains("Players: 1"));
    redis.child.kill().expect("SIGKILL redis-server");
    alice.wait_for("world offline on alice's HUD", |s| hud_row(s).contains("world offline"));
    let heading = alice.read(hud_row);
    alice.send(b"\x1b[D"); // ← turns her 15°
    alice.wait_for("alice turning while the world is offline", |s| {
        let hud = hud_row(s);
        hud.contains("world offline") && hud.contains("heading 15°") && hud != heading
    });
    redis.restart(&scratch.0);
    alice.wait_for("the world online again on alice's HUD", |s| {
        let hud = hud_row(s);
        !hud.contains("world offline") && hud.contains("1 in")
    });
    let log = lock(&server_a.log).clone();
    assert!(log.contains("joined the shared world"), "{log}");
}

// issue #35: a server that cannot join the world says why at once and exits 1: Redis away, another
// maze in the world (both hashes named), a CA for a world without TLS.
#[test]
fn a_server_that_cannot_join_the_world_says_why_and_exits_1() {
    let scratch = Scratch::new("refused");
    let away = format!("redis://127.0.0.1:{}/0", free_port());
    let started = Instant::now();
    let (code, said) = refused(&scratch, &["--gen", "4x4", "--world", &away]);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("cannot reach the world at redis://127.0.0.1:"), "{said}");
    assert!(started.elapsed() < Duration::from_secs(5), "bounded: {:?}", started.elapsed());

    let redis = Redis::start(&scratch.0);
    let maze = scratch.0.join("maze.grid");
    std::fs::write(&maze, SHORT_RUN).expect("write the maze");
    let server = Server::start(&scratch, "a", &maze, &redis.url());
    let (code, said) = refused(&scratch, &["--gen", "4x4", "--world", &redis.url()]);
    assert_eq!(code, Some(1), "{said}");
    // (both hashes, 64 hex digits each, and different)
    let hashes: Vec<&str> = said.split(|c: char| !c.is_ascii_hexdigit()).filter(|w| w.len() == 64).collect();
    assert_eq!(hashes.len(), 2, "both hashes named: {said}");
    assert_ne!(hashes[0], hashes[1], "{said}");
    assert!(said.contains("walks the maze") && said.contains("/1"), "{said}");
    drop(server);

    let ca = scratch.0.join("any.pem");
    std::fs::write(&ca, "not a certificate").expect("a file");
    let (code, said) =
        refused(&scratch, &["--gen", "4x4", "--world", &redis.url(), "--world-ca", ca.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("--world-ca is for a world over TLS"), "{said}");
}

// issue #35: rediss:// with --world-ca FILE: two servers share a world over TLS with a Redis whose
// certificate a CA of its own signed; without the CA, the server refuses to start and says why.
#[test]
fn two_servers_share_a_world_over_tls_with_their_own_ca() {
    let scratch = Scratch::new("tls");
    let redis = Redis::start_tls(&scratch.0);
    assert!(redis.url().starts_with("rediss://"));
    let maze = scratch.0.join("maze.grid");
    std::fs::write(&maze, SHORT_RUN).expect("write the maze");
    let ca = scratch.0.join("ca.pem");
    let ca = ca.to_str().expect("a UTF-8 path");
    let server_a = Server::start_with(&scratch, "a", &maze, &redis.url(), &["--world-ca", ca]);
    let server_b = Server::start_with(&scratch, "b", &maze, &redis.url(), &["--world-ca", ca]);
    let mut alice = Player::connect(server_a.port, "alice");
    alice.wait_for("alice's game on server A", playing);
    let bob = Player::connect(server_b.port, "bob");
    bob.wait_for("bob's game on server B", playing);
    alice.send(b"\t"); // (they may start on one map character: the player list shows both)
    alice.wait_for("bob (server B, over TLS) in alice's player list", |s| {
        s.contents().contains("B  bob") && hud_row(s).contains("2 in")
    });
    let (code, said) = refused(&scratch, &[maze.to_str().expect("utf-8"), "--world", &redis.url()]);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.to_lowercase().contains("certificate"), "the reason: {said}");
}
