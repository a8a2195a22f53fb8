//! Scripted SSH players (russh's client) for the load test (`tests/serve_load.rs`, small) and the load
//! example (`examples/load.rs`, full scale): each connects with a pty of its size, answers the
//! device-attributes query after every frame as a terminal would (so the server's flow control sees a
//! live terminal), and either walks — a key every 1/rate s, measuring how long each key waits for the
//! next frame — or stands still, counting the bytes it gets.
#![allow(missing_docs)] // moved from the tests that share it, whose items were not documented one by one

use std::collections::VecDeque;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use mazewalk_serve::{Access, Limits, ServeOptions, Server};
use russh::client::{self, Handle, Msg};
use russh::keys::PublicKeyOrCertificate;
use russh::keys::ssh_key::private::Ed25519Keypair;
use russh::{Channel, ChannelMsg, ChannelWriteHalf};
use tokio::sync::watch;

/// The device-attributes query the server sends after each frame, and a terminal's answer.
const QUERY: &[u8] = b"\x1b[c";
const ANSWER: &[u8] = b"\x1b[?62;22c";

/// A host key for an in-process server (fixed: tests need no randomness).
#[must_use]
pub fn host_key() -> russh::keys::PrivateKey {
    russh::keys::PrivateKey::from(Ed25519Keypair::from_seed(&[7; 32]))
}

/// The options of an in-process server of `maze` on a free loopback port ([`host_key`], no records,
/// no recordings).
#[must_use]
pub fn loopback_options(maze: mazewalk_maze::Maze, access: Access, limits: Limits) -> ServeOptions {
    let listen: SocketAddr = "127.0.0.1:0".parse().expect("the loopback address");
    ServeOptions {
        maze,
        listen: vec![listen],
        host_key: host_key(),
        access,
        limits,
        records: None,
        record: None,
    }
}

/// An in-process server of the built-in maze on a free loopback port ([`loopback_options`]).
pub async fn loopback_server(access: Access, limits: Limits) -> Server {
    let maze = mazewalk_maze::builtin().expect("built-in maze");
    Server::start(loopback_options(maze, access, limits)).await.expect("start the server")
}

/// The client side: trusts any host key (loopback tests only).
pub struct Client;

impl client::Handler for Client {
    type Error = russh::Error;

    async fn check_server_key(&mut self, _: &PublicKeyOrCertificate) -> Result<bool, Self::Error> {
        Ok(true)
    }
}

/// A connected player: the connection and its session channel, pty and shell requested.
pub struct Connected {
    pub handle: Handle<Client>,
    pub channel: Channel<Msg>,
}

/// Connects as `user` (no key: the server must be open), asks for a `cols × rows` pty and a shell.
///
/// # Errors
/// Anything russh reports, or a refused authentication.
pub async fn connect(addr: SocketAddr, user: &str, size: (u32, u32)) -> Result<Connected, russh::Error> {
    connect_with_window(addr, user, size, client::Config::default().window_size).await
}

/// [`connect`] with the client's receive window for the channel: how many bytes the server may send
/// before the client reads and reopens it (a client that never reads stops the server there).
///
/// # Errors
/// As [`connect`].
pub async fn connect_with_window(
    addr: SocketAddr,
    user: &str,
    size: (u32, u32),
    window_size: u32,
) -> Result<Connected, russh::Error> {
    connect_with(addr, user, size, client::Config { window_size, ..client::Config::default() }).await
}

/// [`connect`] with the largest packet of channel data the client takes (`maximum_packet_size`; a
/// stock client offers 32 KiB): each frame the server sends comes cut into packets of at most this.
///
/// # Errors
/// As [`connect`]: a server that refuses such packets refuses the session channel.
pub async fn connect_with_packet(
    addr: SocketAddr,
    user: &str,
    size: (u32, u32),
    maximum_packet_size: u32,
) -> Result<Connected, russh::Error> {
    connect_with(addr, user, size, client::Config { maximum_packet_size, ..client::Config::default() }).await
}

/// [`connect`] with the client's `config` (a new TCP connection, `nodelay`).
async fn connect_with(
    addr: SocketAddr,
    user: &str,
    size: (u32, u32),
    config: client::Config,
) -> Result<Connected, russh::Error> {
    let stream = tokio::net::TcpStream::connect(addr).await?;
    stream.set_nodelay(true)?;
    connect_stream(stream, user, size, config, false).await
}

/// [`connect`] over a TCP connection already made (from an address of the caller's choice, say).
///
/// # Errors
/// As [`connect`].
pub async fn connect_over(
    stream: tokio::net::TcpStream,
    user: &str,
    size: (u32, u32),
) -> Result<Connected, russh::Error> {
    stream.set_nodelay(true)?;
    connect_stream(stream, user, size, client::Config::default(), false).await
}

/// [`connect`] over `stream`.
async fn connect_stream<S>(
    stream: S,
    user: &str,
    (cols, rows): (u32, u32),
    config: client::Config,
    truecolor: bool,
) -> Result<Connected, russh::Error>
where
    S: tokio::io::AsyncRead + tokio::io::AsyncWrite + Unpin + Send + 'static,
{
    let config = Arc::new(client::Config { nodelay: true, ..config });
    let mut handle = client::connect_stream(config, stream, Client).await?;
    if !handle.authenticate_none(user).await?.success() {
        return Err(russh::Error::NotAuthenticated);
    }
    let channel = handle.channel_open_session().await?;
    if truecolor {
        channel.set_env(true, "COLORTERM", "truecolor").await?;
    }
    channel.request_pty(true, "xterm-256color", cols, rows, 0, 0, &[]).await?;
    channel.request_shell(true).await?;
    Ok(Connected { handle, channel })
}

/// Connects as [`connect`] does, over a stream that stops reading once the returned flag is set:
/// a client that stops reading (its keys still go out). It asks for truecolor (`COLORTERM`), whose
/// frames are the largest, so that what the server sends piles up soonest.
///
/// # Errors
/// As [`connect`].
pub async fn connect_deaf(
    addr: SocketAddr,
    user: &str,
    size: (u32, u32),
) -> Result<(Connected, Arc<AtomicBool>), russh::Error> {
    // A small receive buffer, so that what the server sends piles up on its side soon.
    let socket =
        if addr.is_ipv4() { tokio::net::TcpSocket::new_v4()? } else { tokio::net::TcpSocket::new_v6()? };
    socket.set_recv_buffer_size(16 * 1024)?;
    let stream = socket.connect(addr).await?;
    let deaf = Arc::new(AtomicBool::new(false));
    let connected = connect_stream(
        Deaf { inner: stream, deaf: Arc::clone(&deaf) },
        user,
        size,
        client::Config::default(),
        true, // the largest frames: what the server sends piles up soonest
    )
    .await?;
    Ok((connected, deaf))
}

/// A stream whose reads never complete once `deaf` is set (writes go on).
struct Deaf<S> {
    inner: S,
    deaf: Arc<AtomicBool>,
}

impl<S: tokio::io::AsyncRead + Unpin> tokio::io::AsyncRead for Deaf<S> {
    fn poll_read(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        buf: &mut tokio::io::ReadBuf<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        if self.deaf.load(Ordering::SeqCst) {
            return std::task::Poll::Pending; // never woken: this client reads nothing more
        }
        std::pin::Pin::new(&mut self.inner).poll_read(cx, buf)
    }
}

impl<S: tokio::io::AsyncWrite + Unpin> tokio::io::AsyncWrite for Deaf<S> {
    fn poll_write(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
        buf: &[u8],
    ) -> std::task::Poll<std::io::Result<usize>> {
        std::pin::Pin::new(&mut self.inner).poll_write(cx, buf)
    }

    fn poll_flush(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(
        mut self: std::pin::Pin<&mut Self>,
        cx: &mut std::task::Context<'_>,
    ) -> std::task::Poll<std::io::Result<()>> {
        std::pin::Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

/// What one scripted player saw.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Frames received (one device-attributes query each).
    pub frames: u64,
    /// Bytes received.
    pub bytes: u64,
    /// Bytes received after the first frame (for a player standing still: what idling costs).
    pub bytes_after_first: u64,
    /// Seconds from each key to the first bytes of a frame after it.
    pub latencies: Vec<f64>,
    /// Whether the server closed the channel.
    pub closed: bool,
}

/// Counts the queries in `data`, one whose bytes straddle two messages included (`carry` keeps the
/// last two bytes).
fn count_queries(carry: &mut Vec<u8>, data: &[u8]) -> usize {
    carry.extend_from_slice(data);
    let n = carry.windows(QUERY.len()).filter(|w| *w == QUERY).count();
    let keep = carry.len().min(QUERY.len() - 1);
    carry.drain(..carry.len() - keep);
    n
}

/// Counts the frames in `data` into `stats` (one query each: [`count_queries`]) and answers each
/// query, as a terminal does.
async fn answer_frames(tx: &ChannelWriteHalf<Msg>, carry: &mut Vec<u8>, data: &[u8], stats: &mut Stats) {
    let n = count_queries(carry, data);
    stats.frames += n as u64;
    for _ in 0..n {
        let _ = tx.data_bytes(ANSWER.to_vec()).await;
    }
}

/// Walks for `seconds`: a key every `1 / rate` s (turning left, with a step forward now and then, so
/// that every key changes the view), answering every frame's query; returns what it measured.
pub async fn walk(connected: Connected, rate: f64, seconds: f64, key: &'static [u8]) -> Stats {
    let Connected { handle: _handle, channel } = connected;
    let (mut rx, tx) = channel.split();
    let mut stats = Stats::default();
    let mut carry = Vec::new();
    // Wait for the first frame before the clock starts.
    while stats.frames == 0 {
        match rx.wait().await {
            Some(ChannelMsg::Data { data }) => {
                stats.bytes += data.len() as u64;
                answer_frames(&tx, &mut carry, &data, &mut stats).await;
            }
            Some(ChannelMsg::Eof | ChannelMsg::Close) | None => {
                stats.closed = true;
                return stats;
            }
            _ => {}
        }
    }
    let start = Instant::now();
    let end = start + Duration::from_secs_f64(seconds);
    let mut ticker = tokio::time::interval(Duration::from_secs_f64(1.0 / rate));
    ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut pending: VecDeque<Instant> = VecDeque::new();
    loop {
        tokio::select! {
            _ = ticker.tick() => {
                if Instant::now() >= end {
                    break;
                }
                pending.push_back(Instant::now());
                if tx.data_bytes(key.to_vec()).await.is_err() {
                    stats.closed = true;
                    break;
                }
            }
            message = rx.wait() => match message {
                Some(ChannelMsg::Data { data }) => {
                    let now = Instant::now();
                    stats.latencies.extend(pending.drain(..).map(|sent| (now - sent).as_secs_f64()));
                    stats.bytes += data.len() as u64;
                    stats.bytes_after_first += data.len() as u64;
                    answer_frames(&tx, &mut carry, &data, &mut stats).await;
                }
                Some(ChannelMsg::Eof | ChannelMsg::Close) | None => {
                    stats.closed = true;
                    break;
                }
                _ => {}
            }
        }
    }
    let _ = tx.data_bytes(b"q".to_vec()).await;
    stats
}

/// Stands still, answering queries, until `stop` turns true; counts what arrives, also into `bytes`
/// as it arrives (for a caller measuring a quiet spell).
pub async fn idle(connected: Connected, bytes: Arc<AtomicU64>, mut stop: watch::Receiver<bool>) -> Stats {
    let Connected { handle: _handle, channel } = connected;
    let (mut rx, tx) = channel.split();
    let mut stats = Stats::default();
    let mut carry = Vec::new();
    loop {
        tokio::select! {
            () = until(&mut stop) => break,
            message = rx.wait() => match message {
                Some(ChannelMsg::Data { data }) => {
                    if stats.frames > 0 {
                        stats.bytes_after_first += data.len() as u64;
                    }
                    stats.bytes += data.len() as u64;
                    bytes.fetch_add(data.len() as u64, Ordering::Relaxed);
                    answer_frames(&tx, &mut carry, &data, &mut stats).await;
                }
                Some(ChannelMsg::Eof | ChannelMsg::Close) | None => {
                    stats.closed = true;
                    break;
                }
                _ => {}
            }
        }
    }
    stats
}

/// Returns once `stop` is true (or its sender is gone).
async fn until(stop: &mut watch::Receiver<bool>) {
    let _ = stop.wait_for(|&s| s).await.is_ok(); // the guard is dropped here, before any other await
}

/// The `p`-quantile (0..=1) of `values` (sorted here), 0 for none.
#[must_use]
pub fn quantile(values: &mut [f64], p: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let i = ((values.len() - 1) as f64 * p).round() as usize;
    values[i.min(values.len() - 1)]
}

/// This process's CPU time so far, seconds (user + system), from /proc (Linux).
#[must_use]
pub fn cpu_seconds(pid: Option<u32>) -> f64 {
    let path = pid.map_or_else(|| "/proc/self/stat".to_string(), |p| format!("/proc/{p}/stat"));
    let Ok(stat) = std::fs::read_to_string(path) else { return 0.0 };
    // Fields after the command name (which may hold spaces) start after the last ')'.
    let fields: Vec<&str> = stat.rsplit_once(')').map_or("", |(_, rest)| rest).split_whitespace().collect();
    let ticks = |i: usize| fields.get(i).and_then(|f| f.parse::<f64>().ok()).unwrap_or(0.0);
    (ticks(11) + ticks(12)) / 100.0 // utime, stime: fields 14 and 15, in clock ticks of 1/100 s
}

/// Resident memory, bytes, from /proc (Linux).
#[must_use]
pub fn rss_bytes(pid: Option<u32>) -> u64 {
    let path = pid.map_or_else(|| "/proc/self/status".to_string(), |p| format!("/proc/{p}/status"));
    std::fs::read_to_string(path)
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmRSS:")).map(str::to_string))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|kb| kb.parse::<u64>().ok()))
        .map_or(0, |kb| kb * 1024)
}
