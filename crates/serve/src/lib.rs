//! `mazewalk serve`: many players walk one maze over plain SSH, each with the stock `ssh` client, and
//! see each other on the map.
//!
//! ```text
//! TCP accept ─ slots (handshakes apart from players, per address group, connection rate)
//!   ─▶ connection task: russh over a CutStream (curve25519 / ML-KEM only)
//!   handshake + auth (timeout; --open, or the authorized keys) ─▶ session channel ─▶ player task:
//!     pty-req (TERM, size) · env (colour, locale) · shell ─▶ Player (pure: a Session + enter/leave bytes,
//!     clamped size, rate-limited input)
//!     loop: channel data ─▶ Player::feed · window-change ─▶ resize · world version ─▶ peers
//!           Player::frame ─▶ channel (write timeout) · whereabouts ─▶ World ─▶ version bump
//!           sleep until input, Session::next_wake, a change in the world, idle timeout, shutdown
//!   game over ─▶ the connection closed (one game per connection)
//! ```
//!
//! The pure parts — [`player`] (one player without the connection), [`spectator`] (one spectator,
//! `ssh watch@HOST`), [`world`] (who is where, who
//! won), [`spawn`] (where newcomers start), [`limits`], [`slots`] (who may hold a connection), [`logs`] (what is logged) and
//! [`algorithms`] (what is offered) — are tested without sockets; [`ssh`] is the I/O around them,
//! [`host_key`] the key files, [`authorized_keys`] who may play, [`records`] the best times
//! (SQLite, on a thread of its own), [`http`] the `--http` listener and [`metrics`] what its
//! `/metrics` shows. One world clock: every session's time is seconds since the server
//! started.

#![forbid(unsafe_code)]

pub mod algorithms;
pub mod authorized_keys;
pub mod host_key;
pub mod http;
pub mod identity;
pub mod limits;
pub mod logs;
pub mod metrics;
pub mod player;
pub mod recording;
pub mod records;
pub mod shared;
pub mod slots;
pub mod spawn;
pub mod spectator;
pub mod ssh;
pub mod stream;
pub mod world;

pub use limits::Limits;
pub use ssh::{Access, MAX_ACCEPTED_PROBES, MIN_CHANNEL_PACKET, ServeOptions, Server};

/// Runs a server on a fresh tokio runtime until SIGINT, SIGTERM or SIGHUP (the terminal it ran in
/// closed), then tells every player it is
/// shutting down, restores their terminals and closes. `ready` is called once listening, with the
/// addresses. Returns the signal that ended it.
///
/// # Errors
/// The runtime cannot start, the address cannot be bound, or the signals cannot be watched.
pub fn run(options: ServeOptions, ready: impl FnOnce(&[std::net::SocketAddr])) -> std::io::Result<i32> {
    run_in(options, None, ready)
}

/// [`run`], with the world shared on Redis when `world` is given (`--world`): joined before the
/// first player is let in, left after the players were told of the shutdown.
///
/// # Errors
/// As [`run`]; and the shared world cannot be joined ([`Server::start_in`]).
pub fn run_in(
    options: ServeOptions,
    world: Option<shared::WorldConfig>,
    ready: impl FnOnce(&[std::net::SocketAddr]),
) -> std::io::Result<i32> {
    run_with(options, world, None, |addrs, _| ready(addrs))
}

/// [`run_in`], with `/metrics` and the status page served over HTTP when `http` is given (`--http`,
/// [`http`]): the address, and the maze's name as the page shows it; `ready` gets the HTTP address
/// bound too.
///
/// # Errors
/// As [`run_in`]; and the HTTP address cannot be bound.
pub fn run_with(
    options: ServeOptions,
    world: Option<shared::WorldConfig>,
    http: Option<(std::net::SocketAddr, String)>,
    ready: impl FnOnce(&[std::net::SocketAddr], Option<std::net::SocketAddr>),
) -> std::io::Result<i32> {
    let runtime = tokio::runtime::Builder::new_multi_thread().enable_all().build()?;
    runtime.block_on(async {
        use tokio::signal::unix::{SignalKind, signal};
        let mut interrupt = signal(SignalKind::interrupt())?;
        let mut terminate = signal(SignalKind::terminate())?;
        let mut hangup = signal(SignalKind::hangup())?;
        let server = Server::start_in(options, world).await?;
        let http = match http {
            Some((addr, name)) => Some(server.serve_http(addr, &name).await?),
            None => None,
        };
        ready(server.local_addrs(), http);
        let signal = tokio::select! {
            _ = interrupt.recv() => SignalKind::interrupt(),
            _ = terminate.recv() => SignalKind::terminate(),
            _ = hangup.recv() => SignalKind::hangup(),
        };
        tracing::info!(players = server.players(), "shutting down");
        server.shutdown().await;
        Ok(signal.as_raw_value())
    })
}
