//! The server under load, at a small scale (the full scale is `examples/load.rs`): an in-process server
//! on loopback, scripted russh clients. 50 players stand still while 10 walk at 30 keys a second, and
//! four bad clients try their luck meanwhile: one claims a 65535×65535 pty, one sends 800 KB/s of
//! garbage after logging in, one never reads (a tiny SSH window it never reopens), one opens a TCP
//! connection and says nothing. Checks: idle players get 0 bytes and cost next to no CPU; walkers get
//! a frame for their keys quickly; the one that never reads and the silent one are dropped after
//! their timeouts; the others are unaffected. Bounded in count and time.
#![cfg(target_os = "linux")]

use mazewalk_testkit::load;

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use load::{Connected, connect, quantile};
use mazewalk_serve::{Access, Limits, Server};
use tokio::sync::watch;

/// The whole test's deadline.
const DEADLINE: Duration = Duration::from_secs(180);

fn limits() -> Limits {
    Limits {
        max_players: 200,
        max_per_address: 200,
        handshake_timeout: Duration::from_secs(3), // a loaded CI machine's handshakes take their time
        write_timeout: Duration::from_secs(1),
        ..Limits::default()
    }
}

/// Waits until `server` has `n` connections, or panics after `within`.
async fn connections_become(server: &Server, n: usize, within: Duration, what: &str) {
    let deadline = Instant::now() + within;
    while server.connections() != n {
        assert!(Instant::now() < deadline, "{what}: {} connections, expected {n}", server.connections());
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn walkers_keep_their_frame_rate_while_idle_players_cost_nothing_and_abusers_are_dropped() {
    tokio::time::timeout(DEADLINE, scenario()).await.expect("the load test ran over its deadline");
}

async fn scenario() {
    if std::env::var_os("MAZEWALK_LOG").is_some() {
        let _ = tracing_subscriber::fmt().with_writer(std::io::stderr).try_init(); // the server's log lines
    }
    let server = server_with(limits()).await;
    let addr = server.local_addr();

    // 50 players stand still.
    let (stop, stopped) = watch::channel(false);
    let mut idle = Vec::new();
    let idle_bytes = Arc::new(AtomicU64::new(0));
    for i in 0..50 {
        let connected = connect(addr, &format!("idle{i}"), (80, 24)).await.expect("connect an idle player");
        idle.push(tokio::spawn(load::idle(connected, Arc::clone(&idle_bytes), stopped.clone())));
    }
    connections_become(&server, 50, Duration::from_secs(60), "idle players").await;
    // Let the joins' redraws (each newcomer shows on the others' maps) and the flow-control replies
    // settle, then measure a quiet second and a half.
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let bytes_before = idle_bytes.load(Ordering::Relaxed);
    let cpu_before = load::cpu_seconds(None);
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let idle_cpu = load::cpu_seconds(None) - cpu_before;
    let quiet_bytes = idle_bytes.load(Ordering::Relaxed) - bytes_before;
    // nothing but the exit clock on the HUD (issue #33: it ticks once a second; the built-in maze
    // has an exit): at most two ticks of a few bytes each in the second and a half
    assert!(quiet_bytes <= 50 * 2 * 40, "50 players standing still are sent {quiet_bytes} bytes");
    assert!(idle_cpu < 0.15, "50 players standing still cost {idle_cpu:.3} s of CPU in 1.5 s");

    // The bad clients.
    let huge = connect(addr, "huge", (65535, 65535)).await.expect("connect the huge pty");
    let huge = tokio::spawn(load::walk(huge, 5.0, 3.0, b"\x1b[D"));
    let garbage = connect(addr, "garbage", (80, 24)).await.expect("connect the garbage sender");
    let garbage = tokio::spawn(async move {
        let Connected { handle, channel } = garbage;
        // It reads what it is sent (a client that does not is another test).
        let (mut rx, channel) = channel.split();
        let drain = tokio::spawn(async move { while rx.wait().await.is_some() {} });
        // Printable noise but `q`, which quits (so do Esc, Ctrl-C and Ctrl-Q): this client is to stay
        // and keep sending. (Any bytes at all go through the `serve` fuzz target.)
        let noise: Vec<u8> = (0..8192u32)
            .map(|i| 0x20 + ((i.wrapping_mul(2_654_435_761) >> 13) % 95) as u8)
            .map(|b| if matches!(b, b'q' | b'Q') { b'x' } else { b })
            .collect();
        let until = Instant::now() + Duration::from_secs(3);
        while Instant::now() < until {
            let sent = tokio::time::timeout(Duration::from_secs(2), channel.data_bytes(noise.clone())).await;
            assert!(matches!(sent, Ok(Ok(()))), "the server keeps taking the garbage sender's bytes");
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
        (handle, channel, drain)
    });
    // The deaf one: stops reading after its first frame and keeps turning (its picture changes
    // every frame) until the server gives up on it.
    let (slow, deaf) = load::connect_deaf(addr, "slow", (120, 40)).await.expect("connect the slow reader");
    let slow_keys = tokio::spawn(async move {
        let Connected { handle, channel } = slow;
        deaf.store(true, Ordering::SeqCst);
        for _ in 0..200 {
            let key = channel.data_bytes(b"\x1b[D".to_vec());
            if !matches!(tokio::time::timeout(Duration::from_millis(500), key).await, Ok(Ok(()))) {
                break;
            }
            tokio::time::sleep(Duration::from_millis(30)).await;
        }
        (handle, channel)
    });
    let silent = tokio::net::TcpStream::connect(addr).await.expect("connect the silent one");

    // 10 players walk (turning, which changes every frame) at 30 keys a second for 3 s.
    let mut walkers = Vec::new();
    for i in 0..10 {
        let connected = connect(addr, &format!("walker{i}"), (80, 24)).await.expect("connect a walker");
        walkers.push(tokio::spawn(load::walk(connected, 30.0, 3.0, b"\x1b[D")));
    }
    let mut latencies = Vec::new();
    let mut frames = Vec::new();
    for walker in walkers {
        let stats = walker.await.expect("walker");
        assert!(!stats.closed, "a walker was dropped");
        frames.push(stats.frames);
        latencies.extend(stats.latencies);
    }
    let (p50, p99) = (quantile(&mut latencies, 0.5), quantile(&mut latencies, 0.99));
    eprintln!("walkers: frames {frames:?}, key-to-frame p50 {:.1} ms p99 {:.1} ms", p50 * 1e3, p99 * 1e3);
    // 90 keys each: allow for a loaded CI machine, but a frame per few keys at least, and quickly.
    assert!(frames.iter().all(|&f| f >= 20), "every walker gets frames: {frames:?}");
    assert!(p50 < 0.2, "p50 key-to-frame {p50:.3} s");
    assert!(p99 < 1.0, "p99 key-to-frame {p99:.3} s");
    let huge = huge.await.expect("huge");
    assert!(!huge.closed && huge.frames > 0, "the huge pty is drawn (clamped)");
    let _garbage = garbage.await.expect("garbage");

    // The silent connection and the one that never reads are gone; everyone else is still here.
    let _slow = slow_keys.await.expect("slow");
    // 50 idle players and the garbage sender (the walkers and the huge pty quit with q).
    connections_become(&server, 50 + 1, Duration::from_secs(10), "after the timeouts").await;
    drop(silent);

    stop.send_replace(true);
    for handle in idle {
        let stats = handle.await.expect("idle player");
        assert!(!stats.closed && stats.frames >= 1, "idle players keep their connection");
    }
    server.shutdown().await;
}

/// A server on loopback with `limits`, open to all.
async fn server_with(limits: Limits) -> Server {
    load::loopback_server(Access::Open, limits).await
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_idle_player_is_told_and_let_go_and_the_connection_limits_hold() {
    tokio::time::timeout(DEADLINE, async {
        let limits = Limits {
            idle_timeout: Duration::from_secs(1),
            max_players: 3,
            max_per_address: 2,
            ..Limits::default()
        };
        let server = server_with(limits).await;
        let addr = server.local_addr();
        let first = connect(addr, "first", (80, 24)).await.expect("the first player");
        let _second = connect(addr, "second", (80, 24)).await.expect("the second player");
        assert!(connect(addr, "third", (80, 24)).await.is_err(), "a third from the same address is refused");
        connections_become(&server, 2, Duration::from_secs(10), "two from one address").await;

        // The first says nothing: after the idle timeout it is told why, its terminal restored.
        let Connected { handle: _handle, mut channel } = first;
        let mut seen = Vec::new();
        let started = Instant::now();
        let status = loop {
            match channel.wait().await {
                Some(russh::ChannelMsg::Data { data }) => seen.extend_from_slice(&data),
                Some(russh::ChannelMsg::ExitStatus { exit_status }) => break exit_status,
                Some(_) => {}
                None => panic!("closed without an exit status"),
            }
        };
        let text = String::from_utf8_lossy(&seen);
        assert!(started.elapsed() >= Duration::from_millis(900), "not before the timeout");
        assert!(text.contains("without a key") && text.contains("\x1b[?1049l"), "{text:?}");
        assert_eq!(status, 1);
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}
