//! Issue #34's attacks, each as a quick bounded test against an in-process server on loopback (the
//! full reproductions, with a witness player's latency before and after, are
//! `benches/examples/attacks.rs`): a key exchange that costs the server a second of CPU, an `ssh-rsa`
//! (SHA-1) signature, a connection kept after its game, and a flood of handshakes; and the red-team
//! pass's: a flood of window changes, one address's spectators, a command asked for mid-game. (A player that
//! types but never reads at shutdown is `tests/serve_e2e.rs`'s: it takes a client that stops
//! adjusting its window, as OpenSSH does when its terminal is not read; russh's client never stops.)
#![cfg(target_os = "linux")]

use mazewalk_testkit::load;
use mazewalk_testkit::raw_ssh as raw;

use std::net::{IpAddr, SocketAddr};
use std::sync::Arc;
use std::time::{Duration, Instant};

use load::{Connected, connect, quantile};
use mazewalk_serve::{Access, Limits, Server};
use mazewalk_testkit::eventually;
use russh::keys::{HashAlg, PrivateKeyWithHashAlg};

/// Each test's deadline.
const DEADLINE: Duration = Duration::from_secs(60);

async fn server(access: Access, limits: Limits) -> Server {
    load::loopback_server(access, limits).await
}

/// Issue #34, high 1: a client offering only `diffie-hellman-group18-sha512` and sending its half
/// uncomputed cost the server 0.9 s of CPU a handshake (release build). Now the server does not offer
/// it: each such connection is closed in milliseconds, before any exponentiation.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_offering_only_finite_field_diffie_hellman_is_refused_at_once() {
    tokio::time::timeout(DEADLINE, async {
        let server = server(Access::Open, Limits::default()).await;
        let addr = server.local_addr();
        let took = tokio::task::spawn_blocking(move || {
            let started = Instant::now();
            for i in 0..10 {
                let mut stream = raw::connect(None, addr).expect("connect");
                use std::io::Write as _;
                let _ = stream.write_all(&raw::kexinit("diffie-hellman-group18-sha512"));
                let _ = stream.write_all(&raw::kexdh_init(8192, i));
                let closed = raw::until_closed(&mut stream, Duration::from_secs(5));
                assert!(closed.is_some(), "connection {i} still open after 5 s");
            }
            started.elapsed()
        })
        .await
        .expect("the attacker");
        // (Ten group18 handshakes took ≥ 9 s of server CPU before; milliseconds each now.)
        assert!(took < Duration::from_secs(3), "10 refusals took {took:?}");
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// A key pair made by ssh-keygen (as a player's would be) with `args` (`-t rsa -b 2048`), read back
/// by russh; in a scratch folder named `name`.
fn keygen(name: &str, args: &[&str]) -> (russh::keys::PrivateKey, tempdir::Dir) {
    let dir = tempdir::Dir::new(name);
    let path = dir.0.join("id");
    mazewalk_testkit::require_tool("ssh-keygen", "openssh-client");
    let status = std::process::Command::new("ssh-keygen")
        .args(["-q", "-N", ""])
        .args(args)
        .arg("-f")
        .arg(&path)
        .stdin(std::process::Stdio::null())
        .status()
        .expect("ssh-keygen");
    assert!(status.success());
    (russh::keys::load_secret_key(&path, None).expect("read the key"), dir)
}

/// An RSA key pair made by ssh-keygen.
fn rsa_key() -> (russh::keys::PrivateKey, tempdir::Dir) {
    keygen("rsa", &["-t", "rsa", "-b", "2048"])
}

mod tempdir {
    /// A scratch folder, removed on drop.
    pub struct Dir(pub std::path::PathBuf);

    impl Dir {
        pub fn new(name: &str) -> Dir {
            let dir = std::env::temp_dir().join(format!("mazewalk-attacks-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).expect("scratch folder");
            Dir(dir)
        }
    }

    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// Issue #34, low: `ssh-rsa` signatures (RSA over SHA-1) were accepted; OpenSSH 8.8 and later refuse
/// them. The same key signing with SHA-256 or SHA-512 is let in.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_rsa_key_logs_in_with_sha2_but_not_with_sha1() {
    tokio::time::timeout(DEADLINE, async {
        let (key, _dir) = rsa_key();
        let key = Arc::new(key);
        let access = Access::Keys(vec![key.public_key().key_data().clone()]);
        let server = server(access, Limits::default()).await;
        let addr = server.local_addr();
        for (hash, let_in) in [(None, false), (Some(HashAlg::Sha256), true), (Some(HashAlg::Sha512), true)] {
            let config = Arc::new(russh::client::Config::default());
            let mut handle =
                russh::client::connect(config, addr, load::Client).await.expect("the key exchange");
            let auth = handle
                .authenticate_publickey("rosa", PrivateKeyWithHashAlg::new(Arc::clone(&key), hash))
                .await
                .expect("an answer");
            assert_eq!(auth.success(), let_in, "{hash:?}");
        }
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Issue #34, medium 4: when the game ended (`q`, or the client closing the channel) the connection
/// stayed open, holding a slot for good (`ssh -o ControlPersist=yes`, paramiko). Now the server
/// closes it after `after_game`.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_connection_closes_when_its_game_ends() {
    tokio::time::timeout(DEADLINE, async {
        let limits = Limits { after_game: Duration::from_millis(300), ..Limits::default() };
        let server = server(Access::Open, limits).await;
        let addr = server.local_addr();
        // One quits with q, the other closes its channel; neither closes its connection.
        let quitter = connect(addr, "quitter", (80, 24)).await.expect("connect");
        let closer = connect(addr, "closer", (80, 24)).await.expect("connect");
        eventually(Duration::from_secs(10), "both playing", || server.players() == 2).await;
        let Connected { handle: quitter, channel } = quitter;
        channel.data(&b"q"[..]).await.expect("q");
        let Connected { handle: closer, channel } = closer;
        channel.close().await.expect("close the channel");
        eventually(Duration::from_secs(10), "both games over", || server.players() == 0).await;
        let ended = Instant::now();
        eventually(Duration::from_secs(10), "the server closes both connections", || {
            quitter.is_closed() && closer.is_closed()
        })
        .await;
        assert_eq!(server.connections(), 0, "both slots are free");
        assert!(ended.elapsed() < Duration::from_secs(5), "{:?}", ended.elapsed());
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// A loopback address of its own (Linux routes all of 127/8 to loopback): address group `n`.
fn address(n: u8) -> IpAddr {
    IpAddr::from([127, 0, 0, n])
}

/// Issue #34, medium 5: connections still in the handshake took players' slots (16 addresses × 16
/// connections locked every player out). Now: a witness already playing keeps its latency, a newcomer
/// from another address gets in while the flood holds every handshake slot, and the flood never holds
/// more than its slots.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flood_of_handshakes_neither_slows_players_nor_keeps_newcomers_out() {
    tokio::time::timeout(DEADLINE, async {
        let limits = Limits {
            max_players: 4,
            max_handshakes: 8,
            max_per_address: 16,
            handshake_timeout: Duration::from_secs(30), // the flood holds its slots throughout
            ..Limits::default()
        };
        let server = server(Access::Open, limits).await;
        let addr = server.local_addr();
        let witness = connect(addr, "witness", (80, 24)).await.expect("the witness");
        let witness = tokio::spawn(load::walk(witness, 10.0, 4.0, b"\x1b[D"));
        // Four addresses open 12 silent connections each, as fast as they can, and keep them.
        let flood = tokio::task::spawn_blocking(move || {
            let mut held = Vec::new();
            for n in 2..6 {
                for _ in 0..12 {
                    if let Ok(stream) = raw::connect(Some(address(n)), addr) {
                        held.push(stream);
                    }
                }
            }
            held
        })
        .await
        .expect("the flood");
        eventually(Duration::from_secs(10), "the flood holds every handshake slot", || {
            server.handshakes() == 8
        })
        .await;
        // A newcomer from an address of its own pushes out one of the flood's and logs in.
        let stream = tokio::net::TcpSocket::new_v4().expect("socket");
        stream.bind(SocketAddr::new(address(9), 0)).expect("bind");
        let stream = stream.connect(addr).await.expect("connect the newcomer");
        let newcomer = load::connect_over(stream, "newcomer", (80, 24)).await;
        assert!(newcomer.is_ok(), "a newcomer gets in during the flood: {:?}", newcomer.err());
        eventually(Duration::from_secs(10), "the newcomer playing", || server.players() == 2).await;
        assert!(server.handshakes() <= 8, "the flood holds no more than its slots");
        let stats = witness.await.expect("the witness");
        assert!(!stats.closed, "the witness keeps playing");
        let mut latencies = stats.latencies;
        let p99 = quantile(&mut latencies, 0.99);
        eprintln!("witness during the flood: {} keys, p99 {:.1} ms", latencies.len(), p99 * 1e3);
        assert!(latencies.len() >= 20, "the witness's keys were answered: {}", latencies.len());
        assert!(p99 < 0.5, "p99 key-to-frame {p99:.3} s during the flood");
        drop(flood);
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Red-team pass: a flood of window changes alternating two sizes (400×150 and 399×150, 15,000 a
/// second from one paramiko client) made the server reallocate a 60,000-cell screen for each, half a
/// core for one connection (`Frame::resize` 60 % of the profile). Now a screen follows at most
/// `resize_rate` window changes a second: one that comes sooner waits its turn, and of a flood only
/// the size asked for last is drawn.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flood_of_window_changes_is_followed_a_few_times_a_second() {
    use russh::ChannelMsg;
    use std::sync::Mutex;
    const QUERY: &[u8] = b"\x1b[c";
    let count = |bytes: &[u8], what: &[u8]| bytes.windows(what.len()).filter(|w| *w == what).count();
    tokio::time::timeout(DEADLINE, async {
        // One window change every 2 s at most.
        let limits = Limits { resize_rate: 0.5, ..Limits::default() };
        let server = server(Access::Open, limits).await;
        let Connected { handle: _handle, channel } =
            connect(server.local_addr(), "resizer", (400, 150)).await.expect("connect");
        let (mut rx, tx) = channel.split();
        let tx = Arc::new(tx);
        // Everything received, every frame's query answered at once (so that frames keep coming).
        let received = Arc::new(Mutex::new(Vec::<u8>::new()));
        let reader = {
            let (received, tx) = (Arc::clone(&received), Arc::clone(&tx));
            tokio::spawn(async move {
                while let Some(message) = rx.wait().await {
                    if let ChannelMsg::Data { data } = message {
                        // (a query may straddle two messages: counted where it ends)
                        let (before, queries) = {
                            let mut all = received.lock().expect("the bytes");
                            let before = count(&all[all.len().saturating_sub(2)..], QUERY);
                            all.extend_from_slice(&data);
                            (before, count(&all[all.len().saturating_sub(data.len() + 2)..], QUERY))
                        };
                        for _ in before..queries {
                            let _ = tx.data(&b"\x1b[?62;22c"[..]).await;
                        }
                    }
                }
            })
        };
        // The screen as a 400×150 terminal shows it: whether it is drawn at `cols × rows` (its HUD
        // on the last row, nothing beyond).
        let drawn_at = |cols: u16, rows: u16| {
            let size = |n: u16| std::num::NonZeroU16::new(n).expect("non-zero");
            let mut parser = vt100::Parser::new(size(150), size(400), 0);
            parser.process(&received.lock().expect("the bytes"));
            let screen = parser.screen();
            let beyond_rows = screen.contents_between(rows, 0, 149, 399);
            let beyond_cols = screen.rows(cols, 400 - cols).take(rows.into()).collect::<String>();
            let hud = screen.contents_between(rows - 1, 0, rows - 1, cols - 1);
            beyond_rows.trim().is_empty() && beyond_cols.trim().is_empty() && hud.contains("heading")
        };
        eventually(Duration::from_secs(10), "the first frame", || drawn_at(400, 150)).await;
        // The first window change is followed at once …
        tx.window_change(120, 40, 0, 0).await.expect("a window change");
        eventually(Duration::from_secs(10), "drawn at 120×40", || drawn_at(120, 40)).await;
        // … the next waits its turn (2 s after the first) …
        tx.window_change(100, 30, 0, 0).await.expect("a window change");
        tokio::time::sleep(Duration::from_millis(300)).await;
        assert!(drawn_at(120, 40), "a second window change within 2 s was drawn at once");
        eventually(Duration::from_secs(10), "drawn at 100×30 in its turn", || drawn_at(100, 30)).await;
        // … and of a flood, the last size is drawn.
        let flooding = Instant::now();
        let mut sent = 0u32;
        while flooding.elapsed() < Duration::from_secs(1) {
            let cols = if sent.is_multiple_of(2) { 399 } else { 400 };
            tx.window_change(cols, 150, 0, 0).await.expect("a window change");
            sent += 1;
        }
        tx.window_change(90, 25, 0, 0).await.expect("the last window change");
        eprintln!("{sent} window changes in 1 s");
        assert!(sent >= 1000, "the premise: a flood ({sent} window changes)");
        eventually(Duration::from_secs(10), "drawn at the last size, 90×25", || drawn_at(90, 25)).await;
        reader.abort();
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Red-team pass: one address logged in 16 `watch` connections (its `--max-per-address`) and held
/// every spectator's place for good (a spectator has no idle timeout); a spectator from anywhere else
/// was refused. Now one address holds at most `max_spectators_per_address` of them: its next one is
/// refused, while a spectator from another address, and a player from the same one, get in.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn one_address_cannot_hold_every_spectators_place() {
    async fn from(n: u8, user: &str, addr: SocketAddr) -> Result<Connected, russh::Error> {
        let stream = tokio::net::TcpSocket::new_v4().expect("socket");
        stream.bind(SocketAddr::new(address(n), 0)).expect("bind");
        let stream = stream.connect(addr).await.expect("connect");
        load::connect_over(stream, user, (80, 24)).await
    }
    tokio::time::timeout(DEADLINE, async {
        let limits = Limits::default();
        let server = server(Access::Open, limits).await;
        let addr = server.local_addr();
        let share = limits.max_spectators_per_address;
        assert!(share < limits.max_spectators && limits.max_spectators <= limits.max_per_address);
        let mut held = Vec::new();
        for _ in 0..share {
            held.push(from(20, "watch", addr).await.expect("a spectator within the address's share"));
        }
        eventually(Duration::from_secs(10), "its share watching", || server.spectators() == share).await;
        let over = from(20, "watch", addr).await;
        if let Ok(over) = &over {
            let closed = || over.handle.is_closed();
            eventually(Duration::from_secs(10), "the one over its share closed", closed).await;
        }
        assert_eq!(server.spectators(), share, "one more from the same address");
        let elsewhere = from(21, "watch", addr).await.expect("a spectator from another address");
        eventually(Duration::from_secs(10), "the other address's spectator", || {
            server.spectators() == share + 1
        })
        .await;
        let player = from(20, "ada", addr).await.expect("a player from the first address");
        eventually(Duration::from_secs(10), "its player", || server.players() == 1).await;
        drop((held, elsewhere, player));
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Red-team pass: a command (or subsystem) asked for on the channel whose game runs made the server
/// close that channel under the game: the player stayed in the maze, drawn for no one and counted,
/// until its view changed. Now the request fails and the game goes on.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_command_asked_for_during_the_game_fails_and_the_game_goes_on() {
    use russh::ChannelMsg;
    tokio::time::timeout(DEADLINE, async {
        let server = server(Access::Open, Limits::default()).await;
        let Connected { handle: _handle, mut channel } =
            connect(server.local_addr(), "exec", (80, 24)).await.expect("connect");
        eventually(Duration::from_secs(10), "playing", || server.players() == 1).await;
        // Reads until `done` says so; panics on the channel's end.
        async fn until(channel: &mut russh::Channel<russh::client::Msg>, done: impl Fn(&ChannelMsg) -> bool) {
            loop {
                let message = channel.wait().await;
                match &message {
                    Some(ChannelMsg::Eof | ChannelMsg::Close | ChannelMsg::ExitStatus { .. }) | None => {
                        panic!("the game's channel ended: {message:?}")
                    }
                    Some(message) if done(message) => return,
                    Some(_) => {}
                }
            }
        }
        channel.exec(true, "id").await.expect("ask for a command");
        until(&mut channel, |m| matches!(m, ChannelMsg::Failure)).await;
        channel.request_subsystem(true, "sftp").await.expect("ask for a subsystem");
        until(&mut channel, |m| matches!(m, ChannelMsg::Failure)).await;
        // The game goes on: a key turns the view, and a frame comes.
        channel.data(&b"\x1b[D"[..]).await.expect("a key");
        until(&mut channel, |m| matches!(m, ChannelMsg::Data { data } if data.len() > 100)).await;
        assert_eq!(server.players(), 1);
        channel.data(&b"q"[..]).await.expect("q");
        eventually(Duration::from_secs(10), "the player quit", || server.players() == 0).await;
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Red-team pass 6, medium: a client asking for packets of 1 byte of channel data had every byte of
/// every frame sealed and sent on its own (11× the server's CPU per frame byte). Now a session whose
/// packets (or opening window) are under `MIN_CHANNEL_PACKET` bytes is refused and its connection
/// closed; a client at the floor plays.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_asking_for_tiny_packets_gets_no_game() {
    tokio::time::timeout(DEADLINE, async {
        let server = server(Access::Open, Limits::default()).await;
        let addr = server.local_addr();
        for packet in [1, 512, mazewalk_serve::MIN_CHANNEL_PACKET as u32 - 1] {
            let refused = load::connect_with_packet(addr, "tiny", (80, 24), packet).await;
            assert!(refused.is_err(), "a session with {packet}-byte packets was opened");
        }
        eventually(Duration::from_secs(10), "the refused connections closed", || server.connections() == 0)
            .await;
        assert_eq!(server.players(), 0);
        let floor = mazewalk_serve::MIN_CHANNEL_PACKET as u32;
        let Connected { channel, .. } =
            load::connect_with_packet(addr, "floor", (80, 24), floor).await.expect("a player at the floor");
        eventually(Duration::from_secs(10), "the player at the floor plays", || server.players() == 1).await;
        let mut channel = channel;
        let mut bytes = 0;
        while bytes < 1000 {
            match tokio::time::timeout(Duration::from_secs(10), channel.wait()).await {
                Ok(Some(russh::ChannelMsg::Data { data })) => {
                    assert!(data.len() <= floor as usize, "a packet of {} bytes", data.len());
                    bytes += data.len();
                }
                Ok(Some(_)) => {}
                other => panic!("no first frame: {other:?}"),
            }
        }
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Red-team pass 14: the packet floor above was checked when the channel opened, but a client may
/// send `SSH_MSG_CHANNEL_OPEN_CONFIRMATION` for its own channel mid-game, and russh took the
/// confirmation's packet size as the channel's: a packet size of 1 had every byte of every frame
/// sealed as a packet of its own again (a paramiko player pressing Ctrl-L got 49,814 packets of one
/// byte in 4 s). The server opens no channel, so such a confirmation now ends the connection. The
/// client (the repository's `tests/clients/reconfirmer.py`) counts the packets under 64 bytes after
/// it.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_channel_confirmed_again_with_tiny_packets_ends_the_connection() {
    tokio::time::timeout(DEADLINE, async {
        let server = server(Access::Open, Limits::default()).await;
        let port = server.local_addr().port();
        let python = mazewalk_testkit::require_python_module("paramiko", "python3-paramiko");
        let script =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/clients/reconfirmer.py");
        let out = tokio::task::spawn_blocking(move || {
            std::process::Command::new(python)
                .arg(&script)
                .args([&port.to_string(), "2"])
                .stdin(std::process::Stdio::null())
                .output()
                .expect("run the reconfirmer")
        })
        .await
        .expect("the reconfirmer");
        let said = String::from_utf8_lossy(&out.stdout);
        let figure = |name: &str| -> Option<usize> {
            said.split_whitespace().skip_while(|w| *w != name).nth(1).and_then(|v| v.parse().ok())
        };
        let (tiny, open) = (figure("tiny"), figure("open"));
        assert!(tiny.is_some(), "{said} {}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(tiny, Some(0), "packets under 64 bytes after the confirmation: {said}");
        assert_eq!(open, Some(0), "the connection stayed open: {said}");
        eventually(Duration::from_secs(10), "the player left", || server.players() == 0).await;
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// An ed25519 key pair made by ssh-keygen, in a scratch folder named `name`.
fn ed25519_key(name: &str) -> (russh::keys::PrivateKey, tempdir::Dir) {
    keygen(name, &["-t", "ed25519"])
}

/// A signer that never signs: each public-key attempt through it sends a probe (the key offered
/// without a signature) and, where the server accepts the probe, is asked to sign and declines.
/// Counts the probes accepted (the times it was asked).
struct Declines(Arc<std::sync::atomic::AtomicUsize>);

#[derive(Debug)]
enum Declined {
    Sign,
    Send,
}

impl From<russh::SendError> for Declined {
    fn from(_: russh::SendError) -> Declined {
        Declined::Send
    }
}

impl russh::Signer for Declines {
    type Error = Declined;

    fn auth_sign(
        &mut self,
        _: &russh::keys::agent::AgentIdentity,
        _: Option<HashAlg>,
        _: Vec<u8>,
    ) -> impl std::future::Future<Output = Result<Vec<u8>, Declined>> + Send {
        self.0.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        std::future::ready(Err(Declined::Sign))
    }
}

/// Offers `key` up to `tries` times on `handle`, `pause` apart, declining to sign; ends early when
/// the connection closes. Returns the attempts made.
async fn probe(
    handle: &mut russh::client::Handle<load::Client>,
    key: &russh::keys::PrivateKey,
    (tries, pause): (usize, Duration),
    signer: &mut Declines,
) -> usize {
    for attempt in 0..tries {
        let answer =
            handle.authenticate_publickey_with("prober", key.public_key().clone(), None, signer).await;
        if matches!(answer, Err(Declined::Send)) || handle.is_closed() {
            return attempt + 1;
        }
        tokio::time::sleep(pause).await;
    }
    tries
}

/// Red-team pass 7, high: a probe (a key offered without a signature) was accepted as often as a
/// client sent one, at once, and russh checks a certificate's CA signature on each before the server
/// is asked: one connection pipelining probes of a certificate under an 8192-bit RSA CA took 0.74 of
/// a core. Now a connection has at most `MAX_ACCEPTED_PROBES` probes accepted; later ones are
/// refused (each waits out the refusal's half second, and russh closes the connection after a few).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_connection_gets_only_a_few_probes_answered() {
    tokio::time::timeout(DEADLINE, async {
        let (key, _dir) = ed25519_key("probes");
        let server = server(Access::Open, Limits::default()).await;
        let config = Arc::new(russh::client::Config::default());
        let mut handle = russh::client::connect(config, server.local_addr(), load::Client)
            .await
            .expect("the key exchange");
        let accepted = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let mut signer = Declines(Arc::clone(&accepted));
        let attempts = probe(&mut handle, &key, (30, Duration::ZERO), &mut signer).await;
        let accepted = accepted.load(std::sync::atomic::Ordering::SeqCst);
        assert_eq!(accepted, mazewalk_serve::MAX_ACCEPTED_PROBES, "probes accepted of {attempts} made");
        assert!(attempts < 30 && handle.is_closed(), "the connection closed after the refusals: {attempts}");
        // The key still logs in on a connection of its own: one probe, then its signature.
        let config = Arc::new(russh::client::Config::default());
        let mut handle = russh::client::connect(config, server.local_addr(), load::Client)
            .await
            .expect("the key exchange");
        assert!(signs_in(&mut handle, "prober", key).await, "the key logs in");
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}

/// Whether `key` logs `user` in on `handle` (its signature sent after the probe).
async fn signs_in(
    handle: &mut russh::client::Handle<load::Client>,
    user: &str,
    key: russh::keys::PrivateKey,
) -> bool {
    let key = PrivateKeyWithHashAlg::new(Arc::new(key), None);
    handle.authenticate_publickey(user, key).await.expect("an answer").success()
}

/// A client's key exchange with the server at `addr`, from `from`.
async fn connect_from(from: IpAddr, addr: SocketAddr) -> russh::client::Handle<load::Client> {
    let socket = tokio::net::TcpSocket::new_v4().expect("socket");
    socket.bind(SocketAddr::new(from, 0)).expect("bind");
    let stream = socket.connect(addr).await.expect("connect");
    let config = Arc::new(russh::client::Config::default());
    russh::client::connect_stream(config, stream, load::Client).await.expect("the key exchange")
}

/// Red-team pass 7, high: every authentication request counted as a handshake's progress, so
/// connections probing every few milliseconds never looked stalled, and a newcomer (all handshake
/// slots taken) pushed out an honest client waiting a round trip between its steps instead: from a
/// few addresses of one /24, 0 of 15 logins got in. Now a handshake moves on at its milestones only
/// (keys exchanged, its first request): a prober that began first is pushed out first, however
/// busy it keeps.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_prober_does_not_keep_its_slot_by_probing() {
    tokio::time::timeout(DEADLINE, async {
        let (key, _dir) = ed25519_key("slots");
        let limits = Limits { max_handshakes: 2, ..Limits::default() };
        let server = server(Access::Open, limits).await;
        let addr = server.local_addr();
        // The prober: a probe every 50 ms, or as soon as it is answered where the answer is slower
        // (its first few accepted, then refused, each refusal half a second), from the start.
        let accepted = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let mut prober = connect_from(address(2), addr).await;
        let prober = {
            let (key, accepted) = (key.clone(), Arc::clone(&accepted));
            tokio::spawn(async move {
                let mut signer = Declines(accepted);
                probe(&mut prober, &key, (60, Duration::from_millis(50)), &mut signer).await;
                prober.is_closed()
            })
        };
        eventually(Duration::from_secs(10), "the prober's first answer", || {
            accepted.load(std::sync::atomic::Ordering::SeqCst) > 0
        })
        .await;
        tokio::time::sleep(Duration::from_millis(200)).await;
        // The honest client: its key offered once and answered, then waiting (a round trip, a
        // passphrase): the later of the two handshakes to reach a milestone.
        let mut honest = connect_from(address(3), addr).await;
        let asked = Arc::new(std::sync::atomic::AtomicUsize::new(0));
        probe(&mut honest, &key, (1, Duration::ZERO), &mut Declines(Arc::clone(&asked))).await;
        assert_eq!(asked.load(std::sync::atomic::Ordering::SeqCst), 1, "the honest probe answered");
        tokio::time::sleep(Duration::from_millis(600)).await; // the prober's requests go on
        assert_eq!(server.handshakes(), 2, "both slots taken");
        // A newcomer: every slot taken, one is pushed out for it.
        let _newcomer = raw::connect(Some(address(4)), addr).expect("the newcomer");
        tokio::time::sleep(Duration::from_millis(800)).await;
        assert!(!honest.is_closed(), "the honest handshake was pushed out for the newcomer");
        assert!(prober.await.expect("the prober"), "the prober's connection ended");
        // The honest client logs in.
        assert!(signs_in(&mut honest, "honest", key).await, "the honest client logs in");
        server.shutdown().await;
    })
    .await
    .expect("ran over its deadline");
}
