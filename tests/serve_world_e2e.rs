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
//! exits 1; a world over TLS with `--world-ca`. Two newcomers joining two servers at once (Redis
//! holding every write meanwhile) are put apart once the servers hear each other. Loopback only;
//! every wait has a deadline; every child is killed on drop.
#![cfg(unix)]

mod common;

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{Player, Scratch, Server, hud_row, on_map, playing};
use mazewalk_testkit::redis_server::{Persistence, RedisServer, free_port};

/// `mazewalk serve ARGS` that must refuse to start: its exit code and what it said, within 10 s.
fn refused(scratch: &Scratch, args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .arg("serve")
        .args(["--listen", "127.0.0.1:0", "--open", "--host-key"])
        .arg(scratch.join("host_key_refused"))
        .args(args)
        .env("HOME", scratch.path())
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

/// A player at the server on `port`, without a key, in a 100 × 30 terminal.
fn player(port: u16, user: &str) -> Player {
    Player::connect(port, None, user, 100, 30)
}

/// Three tiles east from the start, the last one the exit.
const SHORT_RUN: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n#####\n#@.E#\n#####\n";

/// Four tiles in a row, the start first and the exit last: a newcomer spawns a cell from another
/// player (the next tile, when the start is taken) and three steps from there are still short of it.
const LONG_RUN: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n######\n#@..E#\n######\n";

/// [`LONG_RUN`] with a tile behind the start, where a second newcomer spawns (a walk from a spot
/// nearer the exit than the start is not kept in the records).
const LONG_RUN_AND_ONE_BEHIND: &str = "mazewalk-grid 1\ntile 4\nfacing east\n\n#######\n#.@..E#\n#######\n";

// issue #35: two servers, one world on Redis, stock ssh clients.
#[test]
fn two_servers_walk_one_world_on_redis() {
    let scratch = Scratch::new("two");
    let mut redis = RedisServer::start(Persistence::None);
    let maze = scratch.maze(LONG_RUN_AND_ONE_BEHIND);
    let server_a = Server::in_world(&scratch, "a", &maze, &redis.url(0), &[]);
    let mut server_b = Server::in_world(&scratch, "b", &maze, &redis.url(0), &[]);

    let alice = player(server_a.port, "alice");
    alice.wait_for("alice's game on server A", playing);
    let mut bob = player(server_b.port, "bob");
    bob.wait_for("bob's game on server B", playing);
    // The HUD counts the world's players. Bob may start at the start (x 10) or a tile west of it (x 6,
    // as server B last heard of alice); he walks 7 steps east (7 units: 3 or more from alice, short
    // of the exit at x 20) and each sees the other, across servers, on the map (on one spot, the map
    // shows only the one in front: the viewer).
    alice.wait_for("2 in on alice's HUD", |s, _| hud_row(s).contains("2 in"));
    bob.wait_for("2 in on bob's HUD", |s, _| hud_row(s).contains("2 in"));
    for _ in 0..7 {
        bob.send(b"w");
        std::thread::sleep(Duration::from_millis(60));
    }
    alice.wait_for("bob (server B) on alice's map", |s, _| on_map(s, 'B'));
    bob.wait_for("alice (server A) on bob's map", |s, _| on_map(s, 'A'));
    assert!(!alice.shows(|s| hud_row(s).contains("world offline")), "Redis is up");

    // Bob holds `w` east into the exit tile; alice, on the other server, is told.
    let announced = |s: &vt100::Screen, _: &[u8]| s.contents().contains("bob reached the exit first");
    assert!(!alice.shows(|s| announced(s, &[])), "nobody has reached the exit yet");
    // (Until his own screen says he is there, not for a time long enough.)
    let deadline = Instant::now() + common::TIMEOUT;
    while !bob.shows(|s| s.contents().contains("You found the exit in")) {
        assert!(Instant::now() < deadline, "bob never reached the exit");
        bob.send(b"w");
        std::thread::sleep(Duration::from_millis(40));
    }
    alice.wait_for("the announcement on alice's screen (server A)", announced);
    bob.wait_for("bob's own exit box", |s, _| s.contents().contains("You found the exit in"));
    // Every finish reaches the other servers: bob's best time is in alice's player list.
    let mut alice = alice;
    alice.send(b"\t");
    alice.wait_for("bob's best time in alice's player list", |s, _| {
        s.contents().lines().any(|line| {
            let best = line.split_whitespace().last().unwrap_or("");
            line.contains("B  bob") && best.contains(':') && best.contains('.') // m:ss.s
        })
    });
    alice.send(b"\t");
    alice.wait_for("the list closed", |s, _| !s.contents().contains("Players: 2"));
    // The best times are the world's, in Redis: bob's exit box ranks him there.
    bob.wait_for("the world's best times in bob's exit box", |s, _| {
        let text = s.contents();
        text.contains("Best times here (1 player)") && text.contains("1. bob")
    });

    // `mazewalk records --world` reads the same table.
    let listed = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .arg("records")
        .arg(&maze)
        .args(["--world", &redis.url(0)])
        .output()
        .expect("mazewalk records --world");
    let text = String::from_utf8_lossy(&listed.stdout);
    assert!(listed.status.success(), "{listed:?}");
    assert!(text.contains("maze.grid") && text.contains("1 player, 1 finish"), "{text}");
    // The world's records are read by every server's host: they name the maze by its file's name,
    // never by the folders it lies in on the server that kept the finish.
    let folder = scratch.path().file_name().expect("the scratch folder's name").to_string_lossy();
    assert!(!text.contains(&*folder), "the host's folders in the world's records: {text}");
    assert!(text.contains("   1. bob"), "{text}");
    let unnamed = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(["records", "--world", &redis.url(0)])
        .output()
        .expect("run");
    assert!(
        unnamed.status.code() == Some(2)
            && String::from_utf8_lossy(&unnamed.stderr).contains("name the maze")
    );

    // Server B dies without a word: bob leaves alice's view within 5 s (3 s of silence).
    assert!(alice.shows(|s| on_map(s, 'B')), "bob still shows before his server dies");
    server_b.child.kill().expect("SIGKILL server B");
    let killed = Instant::now();
    alice.wait_for("bob gone from alice's map", |s, _| !on_map(s, 'B') && hud_row(s).contains("1 in"));
    let gone = killed.elapsed();
    assert!(gone <= Duration::from_secs(5), "bob left alice's view {gone:?} after server B died");

    // Server C stopped by SIGTERM tells its player goodbye, then leaves the world: carol leaves
    // alice's view at once, well before the 3 s of silence a killed server takes.
    let mut server_c = Server::in_world(&scratch, "c", &maze, &redis.url(0), &[]);
    let carol = player(server_c.port, "carol");
    carol.wait_for("carol's game on server C", playing);
    // (Carol starts next to alice, maybe on her map character: the player list shows her.)
    alice.send(b"\t");
    alice.wait_for("carol (server C) in alice's player list", |s, _| {
        s.contents().contains("C  carol") && hud_row(s).contains("2 in")
    });
    let pid = rustix::process::Pid::from_child(&server_c.child);
    rustix::process::kill_process(pid, rustix::process::Signal::TERM).expect("SIGTERM server C");
    let stopped = Instant::now();
    carol.wait_for("carol told the server is shutting down", |s, _| s.contents().contains("shutting down"));
    alice.wait_for("carol gone from alice's list", |s, _| {
        !s.contents().contains("carol") && hud_row(s).contains("1 in")
    });
    let gone = stopped.elapsed();
    assert!(gone < Duration::from_millis(2500), "carol left alice's view {gone:?} after SIGTERM");
    let status = server_c.child.wait().expect("server C's exit");
    assert_eq!(status.code(), Some(143), "SIGTERM's exit code");

    // Redis dies: alice walks on, and her HUD says the world is offline; Redis back (empty), the
    // world is online again.
    alice.send(b"\t"); // (the player list closed)
    alice.wait_for("the list closed", |s, _| !s.contents().contains("Players: 1"));
    redis.stop(); // SIGKILL
    alice.wait_for("world offline on alice's HUD", |s, _| hud_row(s).contains("world offline"));
    let heading = alice.read(hud_row);
    alice.send(b"\x1b[D"); // ← turns her 15°
    alice.wait_for("alice turning while the world is offline", |s, _| {
        let hud = hud_row(s);
        hud.contains("world offline") && hud.contains("heading 15°") && hud != heading
    });
    redis.restart();
    alice.wait_for("the world online again on alice's HUD", |s, _| {
        let hud = hud_row(s);
        !hud.contains("world offline") && hud.contains("1 in")
    });
    let log = server_a.log();
    assert!(log.contains("joined the shared world"), "{log}");
}

/// `redis-cli -u URL ARGS`, which must succeed.
fn redis_cli(url: &str, args: &[&str]) {
    let done = Command::new("redis-cli").args(["-u", url]).args(args).output().expect("run redis-cli");
    assert!(done.status.success() && !String::from_utf8_lossy(&done.stdout).contains("ERR"), "{done:?}");
}

// Two newcomers join two servers at once, neither server yet told of the other's (Redis holds every
// write for 6 s meanwhile, as a slow link would hold the two messages, or as a server that has just
// started has not heard a full message yet): both are put on the start. Once the servers hear each
// other, the later comer moves a cell away without a key pressed, and each sees the other on its
// map (on one spot, a map shows only its own viewer).
#[test]
fn newcomers_racing_on_two_servers_end_up_apart() {
    let scratch = Scratch::new("race");
    let redis = RedisServer::start(Persistence::None);
    let maze = scratch.maze(LONG_RUN);
    let server_a = Server::in_world(&scratch, "a", &maze, &redis.url(0), &[]);
    let server_b = Server::in_world(&scratch, "b", &maze, &redis.url(0), &[]);
    server_a.wait_log("the world is online", 1);
    server_b.wait_log("the world is online", 1);

    redis_cli(&redis.url(0), &["CLIENT", "PAUSE", "6000", "WRITE"]);
    let paused = Instant::now();
    let ada = player(server_a.port, "ada");
    let bob = player(server_b.port, "bob");
    ada.wait_for("ada's game on server A", playing);
    bob.wait_for("bob's game on server B", playing);
    // (Else the race was not run: the second to join may have known of the first.)
    assert!(paused.elapsed() < Duration::from_secs(6), "both joined in the pause: {:?}", paused.elapsed());
    assert!(!ada.shows(|s| on_map(s, 'B')) && !bob.shows(|s| on_map(s, 'A')), "neither knows the other yet");

    ada.wait_for("bob (server B) on ada's map, a spot apart", |s, _| {
        on_map(s, 'B') && hud_row(s).contains("2 in")
    });
    bob.wait_for("ada (server A) on bob's map, a spot apart", |s, _| {
        on_map(s, 'A') && hud_row(s).contains("2 in")
    });
}

// Red-team pass 3: a writer that replaces the world's key with garbage under a running server was
// logged as "the world's maze changed while Redis was away", though Redis was never away: the
// warning says what the key holds.
#[test]
fn garbage_in_the_worlds_key_is_said_for_what_it_is() {
    let scratch = Scratch::new("world-garbage");
    let redis = RedisServer::start(Persistence::None);
    let maze = scratch.maze(LONG_RUN);
    let server = Server::in_world(&scratch, "a", &maze, &redis.url(0), &[]);
    server.wait_log("the world is online", 1);
    redis_cli(&redis.url(0), &["DEL", "mazewalk:world"]);
    redis_cli(&redis.url(0), &["RPUSH", "mazewalk:world", "junk"]);
    server.wait_log("the world's key holds (a list, not a maze hash)", 1);
    let log = server.log();
    assert!(!log.contains("while Redis was away"), "{log}");
}

// issue #35: a server that cannot join the world says why at once and exits 1: Redis away, another
// maze in the world (both hashes named); a CA for a world without TLS is a bad flag value: exit 2.
#[test]
fn a_server_that_cannot_join_the_world_says_why_and_exits_1() {
    let scratch = Scratch::new("refused");
    let away = format!("redis://127.0.0.1:{}/0", free_port());
    let started = Instant::now();
    let (code, said) = refused(&scratch, &["--gen", "4x4", "--world", &away]);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("cannot reach the world at redis://127.0.0.1:"), "{said}");
    assert!(started.elapsed() < Duration::from_secs(5), "bounded: {:?}", started.elapsed());

    let redis = RedisServer::start(Persistence::None);
    let maze = scratch.maze(SHORT_RUN);
    let server = Server::in_world(&scratch, "a", &maze, &redis.url(0), &[]);
    let (code, said) = refused(&scratch, &["--gen", "4x4", "--world", &redis.url(0)]);
    assert_eq!(code, Some(1), "{said}");
    // (both hashes, 64 hex digits each, and different)
    let hashes: Vec<&str> = said.split(|c: char| !c.is_ascii_hexdigit()).filter(|w| w.len() == 64).collect();
    assert_eq!(hashes.len(), 2, "both hashes named: {said}");
    assert_ne!(hashes[0], hashes[1], "{said}");
    assert!(said.contains("walks the maze") && said.contains("/1"), "{said}");
    drop(server);

    let ca = scratch.join("any.pem");
    std::fs::write(&ca, "not a certificate").expect("a file");
    let (code, said) =
        refused(&scratch, &["--gen", "4x4", "--world", &redis.url(0), "--world-ca", ca.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{said}");
    assert!(said.contains("--world-ca is for a world over TLS"), "{said}");
}

// issue #35: rediss:// with --world-ca FILE: two servers share a world over TLS with a Redis whose
// certificate a CA of its own signed; without the CA, the server refuses to start and says why.
#[test]
fn two_servers_share_a_world_over_tls_with_their_own_ca() {
    let scratch = Scratch::new("tls");
    let redis = RedisServer::start_tls();
    assert!(redis.url(0).starts_with("rediss://"));
    let maze = scratch.maze(SHORT_RUN);
    let ca = redis.ca_path().expect("its CA's certificate");
    let ca = ca.to_str().expect("a UTF-8 path");
    let server_a = Server::in_world(&scratch, "a", &maze, &redis.url(0), &["--world-ca", ca]);
    let server_b = Server::in_world(&scratch, "b", &maze, &redis.url(0), &["--world-ca", ca]);
    let mut alice = player(server_a.port, "alice");
    alice.wait_for("alice's game on server A", playing);
    let bob = player(server_b.port, "bob");
    bob.wait_for("bob's game on server B", playing);
    alice.send(b"\t"); // (they may start on one map character: the player list shows both)
    alice.wait_for("bob (server B, over TLS) in alice's player list", |s, _| {
        s.contents().contains("B  bob") && hud_row(s).contains("2 in")
    });
    let (code, said) = refused(&scratch, &[maze.to_str().expect("utf-8"), "--world", &redis.url(0)]);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.to_lowercase().contains("certificate"), "the reason: {said}");
}
