//! Issue #40, high: idle handshakes from many addresses locked every player out (each address said
//! its version and waited, holding one of the 32 handshake slots; a newcomer could only push out an
//! address holding two more than its own). Now the handshake longest without progress gives its slot
//! to a newcomer, and one that has not exchanged keys within `kex_timeout` is closed. The newcomer is
//! stock OpenSSH `ssh`; the server runs in this process on loopback, and every test stops by itself.
//! (The full attack, with a playing witness and a rate of up to 500 connections a second, is
//! `benches/examples/attacks.rs --only idle`.)
#![cfg(target_os = "linux")]

use mazewalk_testkit::load;
use mazewalk_testkit::raw_ssh as raw;

use std::collections::VecDeque;
use std::net::{IpAddr, SocketAddr, TcpStream};
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use mazewalk_serve::ssh::NO_PTY_MESSAGE;
use mazewalk_serve::{Access, Limits, Server};
use mazewalk_testkit::eventually;

/// Each test's deadline.
const DEADLINE: Duration = Duration::from_secs(90);

async fn server(limits: Limits) -> Server {
    load::loopback_server(Access::Open, limits).await
}

/// Attacker address `n` (0..65,536): 127.1.x.y, one address group each.
fn attacker(n: u32) -> IpAddr {
    IpAddr::from([127, 1, (n >> 8) as u8, n as u8])
}

/// Stock `ssh` from `from`, with no terminal: it logs in (the server lets anyone in), opens the
/// session, and is told the game needs a terminal — which only a client that got in hears. Returns
/// whether it heard it, and how long it took.
fn newcomer(addr: SocketAddr, from: IpAddr) -> (bool, Duration, String) {
    let started = Instant::now();
    let out = Command::new("ssh")
        .args(["-F", "/dev/null", "-b", &from.to_string(), "-p", &addr.port().to_string()])
        .args(["-o", "StrictHostKeyChecking=no", "-o", "UserKnownHostsFile=/dev/null"])
        .args(["-o", "LogLevel=ERROR", "-o", "BatchMode=yes", "-o", "IdentitiesOnly=yes"])
        .args(["-o", "ConnectTimeout=10", "-i", "/dev/null"])
        .arg(format!("newcomer@{}", addr.ip()))
        .stdin(Stdio::null())
        .output()
        .expect("run ssh");
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (said.contains(NO_PTY_MESSAGE), started.elapsed(), said)
}

/// Attackers on `addresses` addresses open idle handshakes (their version, then nothing) `rate` a
/// second until `stop`, each address in turn, keeping the newest 512 open; counts them in `opened`.
fn flood(addr: SocketAddr, addresses: u32, rate: f64, stop: &AtomicBool, count: &AtomicU64) {
    let mut held: VecDeque<TcpStream> = VecDeque::new();
    let started = Instant::now();
    let mut opened = 0u64;
    while !stop.load(Ordering::Relaxed) {
        let due = Duration::from_secs_f64(opened as f64 / rate);
        if let Some(wait) = due.checked_sub(started.elapsed()) {
            std::thread::sleep(wait);
        }
        if let Ok(stream) = raw::connect(Some(attacker((opened % u64::from(addresses)) as u32)), addr) {
            held.push_back(stream);
            if held.len() > 512 {
                held.pop_front();
            }
        }
        opened += 1;
        count.store(opened, Ordering::Relaxed);
    }
}

/// Issue #40: 200 addresses hold every handshake slot with idle handshakes and keep opening more
/// (100 a second: each address every 2 s, under every per-address limit), the handshake timeouts
/// long enough that none would end by itself meanwhile. Stock `ssh` from an address of its own gets
/// in, every time; the flood never holds more than the slots.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_newcomer_gets_in_while_idle_handshakes_from_many_addresses_fill_every_slot() {
    tokio::time::timeout(DEADLINE, async {
        let limits = Limits {
            handshake_timeout: Duration::from_secs(120),
            kex_timeout: Duration::from_secs(120),
            ..Limits::default()
        };
        let server = Arc::new(server(limits).await);
        let addr = server.local_addr();
        let stop = Arc::new(AtomicBool::new(false));
        let opened = Arc::new(AtomicU64::new(0));
        let attack = {
            let (stop, opened) = (Arc::clone(&stop), Arc::clone(&opened));
            std::thread::spawn(move || flood(addr, 200, 100.0, &stop, &opened))
        };
        eventually(Duration::from_secs(20), "the flood holds every handshake slot", || {
            server.handshakes() == limits.max_handshakes
        })
        .await;
        let before = opened.load(Ordering::Relaxed);
        for n in 0..3u8 {
            let (got_in, took, said) =
                tokio::task::spawn_blocking(move || newcomer(addr, IpAddr::from([127, 2, 0, n + 1])))
                    .await
                    .expect("the newcomer");
            assert!(got_in, "newcomer {n} got in during the flood (after {took:?}); ssh said: {said:?}");
            eprintln!("newcomer {n} got in after {:.0} ms", took.as_secs_f64() * 1e3);
            assert!(server.handshakes() <= limits.max_handshakes, "never more handshakes than slots");
        }
        let during = opened.load(Ordering::Relaxed) - before;
        stop.store(true, Ordering::Relaxed);
        attack.join().expect("the flood");
        assert!(during > 0, "the flood went on while the newcomers logged in");
        eprintln!("{during} idle handshakes opened while the newcomers logged in");
        Arc::into_inner(server).expect("the only handle").shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Issue #40: a client that has not exchanged keys within `kex_timeout` gives its slot up, while one
/// that did (and logged in) plays on.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_handshake_without_its_keys_exchanged_in_time_is_closed() {
    tokio::time::timeout(DEADLINE, async {
        let limits = Limits { kex_timeout: Duration::from_millis(500), ..Limits::default() };
        let server = server(limits).await;
        let addr = server.local_addr();
        let player = load::connect(addr, "player", (80, 24)).await.expect("a player logs in");
        let closed = tokio::task::spawn_blocking(move || {
            let mut idle = raw::connect(Some(attacker(1)), addr).expect("connect");
            raw::until_closed(&mut idle, Duration::from_secs(5)) // (the handshake timeout is 20 s)
        })
        .await
        .expect("the idle client");
        let closed = closed.expect("the idle handshake is closed");
        assert!(closed >= Duration::from_millis(400), "not before its time: {closed:?}");
        eventually(Duration::from_secs(10), "its slot free", || server.handshakes() == 0).await;
        tokio::time::sleep(Duration::from_millis(600)).await;
        assert!(!player.handle.is_closed(), "the player who exchanged keys in time plays on");
        assert_eq!(server.players(), 1);
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}
