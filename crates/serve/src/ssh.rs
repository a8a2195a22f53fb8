//! The SSH side of `mazewalk serve`: the accept loop and its limits, one task per connection (russh's
//! protocol task under it), one task per player that moves bytes between the SSH channel and its
//! [`Player`], the shared [`World`], and the shutdown. All the game logic is in the pure modules; this
//! one only waits, reads, writes and counts.

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use russh::keys::ssh_key::public::KeyData;
use russh::keys::{PrivateKey, PublicKey};
use russh::server::{Auth, ChannelOpenHandle, Handler, Msg, PublicKeyOffer, Session, VerifiedPublicKey};
use russh::{Channel, ChannelId, ChannelMsg, ChannelOpenFailure, ChannelWriteHalf, MethodKind, MethodSet};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::watch;
use tokio::task::JoinSet;
use tracing::{info, warn};

use super::host_key::fingerprint;
use super::limits::Limits;
use super::player::{Player, player_name};
use super::stream::{Cut, CutStream};
use super::world::{PlayerId, World};
use mazewalk_maze::Maze;

/// Who may play.
#[derive(Clone, Debug)]
pub enum Access {
    /// Anyone, with any user name and any key or none (a public game).
    Open,
    /// Only the holders of these keys (an authorized-keys file).
    Keys(Vec<KeyData>),
}

/// Everything a server needs.
#[derive(Clone, Debug)]
pub struct ServeOptions {
    /// The maze everyone walks.
    pub maze: Maze,
    /// Where to listen.
    pub listen: SocketAddr,
    /// The host key.
    pub host_key: PrivateKey,
    /// Who may play.
    pub access: Access,
    /// The limits.
    pub limits: Limits,
}

/// What a player is told when the server shuts down.
pub const SHUTDOWN_MESSAGE: &str = "mazewalk: server shutting down";
/// What a client without a terminal is told.
pub const NO_PTY_MESSAGE: &str =
    "mazewalk: this is a full-screen game and needs a terminal: connect with `ssh -t` (no command)";
/// What a client whose terminal cannot show the game (`TERM=dumb`) is told.
pub const DUMB_TERMINAL_MESSAGE: &str = "mazewalk: this terminal (TERM=dumb) cannot show the full-screen game: it needs cursor movement; connect from a terminal that has it (e.g. TERM=xterm-256color ssh …)";
/// What a client asking to run a command or a subsystem is told.
pub const NO_EXEC_MESSAGE: &str =
    "mazewalk: no commands or subsystems here, only the game: connect with `ssh -t` and no command";
/// How long a shutting-down server waits for its players' goodbyes before cutting them off.
const GOODBYE_GRACE: Duration = Duration::from_secs(2);

/// What all connections share.
struct Shared {
    maze: Arc<Maze>,
    access: Access,
    limits: Limits,
    config: Arc<russh::server::Config>,
    world: Mutex<World>,
    /// The world's version, for the players' tasks to wait on.
    world_version: watch::Sender<u64>,
    shutdown: watch::Receiver<bool>,
    /// The server's clock: every session's time is seconds since this instant.
    clock: Instant,
    connections: Mutex<Connections>,
}

impl Shared {
    fn world(&self) -> MutexGuard<'_, World> {
        self.world.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn now(&self) -> f64 {
        self.clock.elapsed().as_secs_f64()
    }
}

/// Open connections, in all and per address.
#[derive(Default)]
struct Connections {
    total: usize,
    per_address: HashMap<IpAddr, usize>,
}

/// One open connection's place in [`Connections`], given back on drop.
struct Slot {
    shared: Arc<Shared>,
    ip: IpAddr,
}

impl Slot {
    /// A place for a connection from `ip`, if the limits leave one (else why not).
    fn take(shared: &Arc<Shared>, ip: IpAddr) -> Result<Slot, Refusal> {
        let mut c = shared.connections.lock().unwrap_or_else(PoisonError::into_inner);
        if c.total >= shared.limits.max_players {
            return Err(Refusal::Full(shared.limits.max_players));
        }
        let from_ip = c.per_address.entry(ip).or_default();
        if *from_ip >= shared.limits.max_per_address {
            return Err(Refusal::FromThisAddress(shared.limits.max_per_address));
        }
        *from_ip += 1;
        c.total += 1;
        Ok(Slot { shared: Arc::clone(shared), ip })
    }
}

/// Why a connection gets no [`Slot`].
#[derive(Clone, Copy, Debug)]
enum Refusal {
    /// `--max-players`, reached.
    Full(usize),
    /// `--max-per-address`, reached by the client's address.
    FromThisAddress(usize),
}

impl Refusal {
    /// For the log.
    fn reason(self) -> &'static str {
        match self {
            Refusal::Full(_) => "server full",
            Refusal::FromThisAddress(_) => "too many connections from this address",
        }
    }

    /// For the client (its `ssh` prints it).
    fn message(self) -> String {
        match self {
            Refusal::Full(1) => "mazewalk: the server is full (one player at a time); try again later".into(),
            Refusal::Full(n) => format!("mazewalk: the server is full ({n} players); try again later"),
            Refusal::FromThisAddress(n) => {
                let n = if n == 1 { "a connection".to_owned() } else { format!("{n} connections") };
                format!("mazewalk: {n} from your address already; close one, or try again later")
            }
        }
    }
}

/// Refusals being told at once, at most (a flood beyond it is dropped unanswered).
const MAX_REFUSALS_AT_ONCE: usize = 32;
/// How long a refusal waits for the client to read it and hang up.
const REFUSAL_GRACE: Duration = Duration::from_secs(2);

/// Tells a client it was refused, in the only place before a key exchange that OpenSSH shows: an SSH
/// identification, then a disconnect packet (unencrypted, as every packet before the key exchange is;
/// `ssh` prints "Received disconnect from …: <the message>"). The client's own bytes are read until it
/// hangs up: closing with them unread would reset the connection, and could lose ours on the way.
async fn refuse(mut stream: TcpStream, refusal: Refusal) {
    use tokio::io::{AsyncReadExt as _, AsyncWriteExt as _};
    let mut bytes = format!("SSH-2.0-mazewalk_{}\r\n", env!("CARGO_PKG_VERSION")).into_bytes();
    bytes.extend(disconnect_packet(SSH_DISCONNECT_TOO_MANY_CONNECTIONS, &refusal.message()));
    let _ = tokio::time::timeout(REFUSAL_GRACE, async {
        stream.write_all(&bytes).await?;
        stream.shutdown().await?;
        let mut sink = [0; 1024];
        while stream.read(&mut sink).await? > 0 {}
        Ok::<_, std::io::Error>(())
    })
    .await;
}

/// RFC 4253's reason code for a refusal by limits.
const SSH_DISCONNECT_TOO_MANY_CONNECTIONS: u32 = 11;

/// An `SSH_MSG_DISCONNECT` packet in the binary packet protocol before any key exchange (RFC 4253 §6,
/// §11.1): length, padding length, the message (code, description, empty language tag), at least 4
/// bytes of padding to a multiple of 8, no MAC.
fn disconnect_packet(code: u32, description: &str) -> Vec<u8> {
    const SSH_MSG_DISCONNECT: u8 = 1;
    let mut payload = vec![SSH_MSG_DISCONNECT];
    payload.extend(code.to_be_bytes());
    payload.extend((description.len() as u32).to_be_bytes());
    payload.extend(description.as_bytes());
    payload.extend(0u32.to_be_bytes());
    let unpadded = 4 + 1 + payload.len();
    let padding = 4 + (8 - (unpadded + 4) % 8) % 8;
    let mut packet = ((1 + payload.len() + padding) as u32).to_be_bytes().to_vec();
    packet.push(padding as u8);
    packet.extend(payload);
    packet.extend(std::iter::repeat_n(0, padding));
    packet
}

impl Drop for Slot {
    fn drop(&mut self) {
        let mut c = self.shared.connections.lock().unwrap_or_else(PoisonError::into_inner);
        c.total -= 1;
        if let Some(n) = c.per_address.get_mut(&self.ip) {
            *n -= 1;
            if *n == 0 {
                c.per_address.remove(&self.ip);
            }
        }
    }
}

/// What one connection's tasks share: who it is, whether it plays, its stream's cut and counts.
struct Conn {
    peer: SocketAddr,
    cut: Arc<Cut>,
    user: Mutex<Option<String>>,
    key: Mutex<Option<String>>,
    /// The last key offered and refused (its fingerprint), for the log of a login that failed.
    refused: Mutex<Option<String>>,
    playing: AtomicBool,
    /// Why it ended, when the server ended it (else the client did).
    ended: Mutex<Option<&'static str>>,
}

impl Conn {
    fn set<T>(field: &Mutex<T>, value: T) {
        *field.lock().unwrap_or_else(PoisonError::into_inner) = value;
    }

    fn get<T: Clone>(field: &Mutex<T>) -> T {
        field.lock().unwrap_or_else(PoisonError::into_inner).clone()
    }

    /// Records why the server ends the connection, for the log (the first reason is kept).
    fn ending(&self, reason: &'static str) {
        self.ended.lock().unwrap_or_else(PoisonError::into_inner).get_or_insert(reason);
    }

    /// Ends the connection for `reason`: the stream is cut (the first reason is kept).
    fn end(&self, reason: &'static str) {
        self.ending(reason);
        self.cut.cut();
    }
}

/// A running server.
pub struct Server {
    local_addr: SocketAddr,
    shutdown: watch::Sender<bool>,
    shared: Arc<Shared>,
    accept: tokio::task::JoinHandle<()>,
}

impl Server {
    /// Binds `options.listen` and starts accepting players (on the current tokio runtime).
    ///
    /// # Errors
    /// The address cannot be bound.
    pub async fn start(options: ServeOptions) -> std::io::Result<Server> {
        let listener = TcpListener::bind(options.listen).await?;
        let local_addr = listener.local_addr()?;
        let limits = options.limits;
        let mut methods = MethodSet::empty();
        methods.push(MethodKind::PublicKey);
        if matches!(options.access, Access::Open) {
            methods.push(MethodKind::None);
        }
        let config = russh::server::Config {
            server_id: russh::SshId::Standard(
                format!("SSH-2.0-mazewalk_{}", env!("CARGO_PKG_VERSION")).into(),
            ),
            methods,
            keys: vec![options.host_key],
            // OpenSSH tries "none" first to learn the methods: no delay for that one.
            auth_rejection_time: Duration::from_millis(500),
            auth_rejection_time_initial: Some(Duration::ZERO),
            max_auth_attempts: 6,
            // Our receive window and queue: what a client can make us hold before it must wait.
            window_size: 256 * 1024,
            maximum_packet_size: 32 * 1024,
            channel_buffer_size: 16,
            inactivity_timeout: None, // the idle timeout is the player's (input), keepalives the link's
            keepalive_interval: Some(limits.keepalive_interval),
            keepalive_max: limits.keepalive_max,
            nodelay: true,
            ..russh::server::Config::default()
        };
        let (shutdown, shutdown_rx) = watch::channel(false);
        let shared = Arc::new(Shared {
            maze: Arc::new(options.maze),
            access: options.access,
            limits,
            config: Arc::new(config),
            world: Mutex::new(World::new()),
            world_version: watch::Sender::new(0),
            shutdown: shutdown_rx,
            clock: Instant::now(),
            connections: Mutex::new(Connections::default()),
        });
        let accept = tokio::spawn(accept_loop(listener, Arc::clone(&shared)));
        Ok(Server { local_addr, shutdown, shared, accept })
    }

    /// The address it listens on (with the port the system chose for port 0).
    #[must_use]
    pub fn local_addr(&self) -> SocketAddr {
        self.local_addr
    }

    /// Players in the maze now.
    #[must_use]
    pub fn players(&self) -> usize {
        self.shared.world().len()
    }

    /// Open connections now (players and those still connecting).
    #[must_use]
    pub fn connections(&self) -> usize {
        self.shared.connections.lock().unwrap_or_else(PoisonError::into_inner).total
    }

    /// Tells every player the server is shutting down, restores their terminals, closes every
    /// connection and stops listening; returns when all are closed.
    pub async fn shutdown(self) {
        self.shutdown.send_replace(true);
        let _ = self.accept.await;
    }
}

/// Accepts connections until shutdown, then waits for them to close.
async fn accept_loop(listener: TcpListener, shared: Arc<Shared>) {
    let mut connections = JoinSet::new();
    let mut refusals = JoinSet::new();
    let mut shutdown = shared.shutdown.clone();
    loop {
        tokio::select! {
            () = until_shutdown(&mut shutdown) => break,
            Some(_) = connections.join_next(), if !connections.is_empty() => {}
            Some(_) = refusals.join_next(), if !refusals.is_empty() => {}
            accepted = listener.accept() => match accepted {
                Ok((stream, peer)) => match Slot::take(&shared, peer.ip()) {
                    Ok(slot) => {
                        connections.spawn(connection(Arc::clone(&shared), stream, peer, slot));
                    }
                    Err(refusal) => {
                        info!(peer = %peer, "refused: {}", refusal.reason());
                        if refusals.len() < MAX_REFUSALS_AT_ONCE {
                            refusals.spawn(refuse(stream, refusal));
                        }
                    }
                },
                Err(err) => {
                    // Out of file descriptors, say: wait a little rather than spin.
                    warn!("accept failed: {err}");
                    tokio::time::sleep(Duration::from_millis(100)).await;
                }
            },
        }
    }
    drop(listener);
    refusals.abort_all();
    while connections.join_next().await.is_some() {}
}

/// Returns once the server is shutting down (or gone).
async fn until_shutdown(shutdown: &mut watch::Receiver<bool>) {
    let _ = shutdown.wait_for(|&s| s).await.is_ok(); // the guard is dropped here, before any other await
}

/// One connection, from accept to close: russh's task under a cut-able stream, the handshake timeout,
/// the shutdown, and the disconnect log line.
async fn connection(shared: Arc<Shared>, stream: TcpStream, peer: SocketAddr, _slot: Slot) {
    let _ = stream.set_nodelay(true);
    let _ = socket2::SockRef::from(&stream).set_send_buffer_size(shared.limits.send_buffer);
    let (stream, cut) = CutStream::new(stream);
    let conn = Arc::new(Conn {
        peer,
        cut,
        user: Mutex::new(None),
        key: Mutex::new(None),
        refused: Mutex::new(None),
        playing: AtomicBool::new(false),
        ended: Mutex::new(None),
    });
    let started = Instant::now();
    let handler = Handlers { shared: Arc::clone(&shared), conn: Arc::clone(&conn), session_open: false };
    let handshake = tokio::time::sleep(shared.limits.handshake_timeout);
    tokio::pin!(handshake);
    let mut shutdown = shared.shutdown.clone();
    let mut shutting_down = false;
    let mut handshake_over = false;
    let ssh = async {
        match russh::server::run_stream(Arc::clone(&shared.config), stream, handler).await {
            Ok(session) => session.await,
            Err(err) => Err(err),
        }
    };
    tokio::pin!(ssh);
    let result = loop {
        tokio::select! {
            result = &mut ssh => break result,
            // (A branch's condition is read when `select!` starts waiting, so the body looks again.)
            () = &mut handshake, if !handshake_over => {
                handshake_over = true;
                if !conn.playing.load(Ordering::SeqCst) {
                    conn.end("handshake timeout");
                }
            }
            () = until_shutdown(&mut shutdown), if !shutting_down => {
                shutting_down = true;
                if !conn.playing.load(Ordering::SeqCst) {
                    conn.end("server shutting down");
                } else {
                    // The player's task says goodbye and closes; cut whatever is left after a grace.
                    conn.ending("server shutting down");
                    let conn = Arc::clone(&conn);
                    tokio::spawn(async move {
                        tokio::time::sleep(GOODBYE_GRACE).await;
                        conn.end("server shutting down");
                    });
                }
            }
        }
    };
    let error = result.err().map(|e| match e {
        // russh's words, in the log's (lower case, no library jargon)
        russh::Error::KeepaliveTimeout => "keepalive timeout".to_string(),
        russh::Error::IO(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "connection lost".to_string()
        }
        e => e.to_string(),
    });
    // Keys were refused and none let in: the client gave up (it closes, or says nothing more).
    let refused = Conn::get(&conn.key).is_none().then(|| Conn::get(&conn.refused)).flatten();
    let reason = match (Conn::get(&conn.ended), &refused) {
        (Some(ended), _) => ended.to_string(),
        (None, Some(_)) => "authentication failed".to_string(),
        (None, None) => error.unwrap_or_else(|| "closed".into()),
    };
    info!(
        peer = %peer,
        user = %Conn::get(&conn.user).as_deref().unwrap_or("-"),
        key = Conn::get(&conn.key).or(refused).as_deref().unwrap_or("-"),
        seconds = format_args!("{:.1}", started.elapsed().as_secs_f64()),
        bytes_in = conn.cut.bytes_in.load(Ordering::Relaxed),
        bytes_out = conn.cut.bytes_out.load(Ordering::Relaxed),
        reason = %reason,
        "disconnected"
    );
}

/// russh's callbacks for one connection: authentication, and the answers to channel requests. The
/// session channel's bytes go to the player's task ([`play`]).
struct Handlers {
    shared: Arc<Shared>,
    conn: Arc<Conn>,
    session_open: bool,
}

impl Handlers {
    fn may_play(&self, key: Option<&PublicKey>) -> bool {
        match (&self.shared.access, key) {
            (Access::Open, _) => true,
            (Access::Keys(keys), Some(key)) => keys.contains(key.key_data()),
            (Access::Keys(_), None) => false,
        }
    }

    fn accepted(&self, user: &str, key: Option<&PublicKey>) -> Auth {
        let name = player_name(user);
        let fingerprint = key.map(fingerprint);
        info!(
            peer = %self.conn.peer,
            user = %name,
            key = fingerprint.as_deref().unwrap_or("-"),
            "connected"
        );
        Conn::set(&self.conn.user, Some(name));
        Conn::set(&self.conn.key, fingerprint);
        Auth::Accept
    }

    /// Refuses `user`'s key (or no key): the log of the connection will say whose and which.
    fn refused(&self, user: &str, key: Option<&PublicKey>) -> Auth {
        Conn::set(&self.conn.user, Some(player_name(user)));
        if let Some(key) = key {
            Conn::set(&self.conn.refused, Some(fingerprint(key)));
        }
        Handlers::rejected()
    }

    fn rejected() -> Auth {
        let mut methods = MethodSet::empty();
        methods.push(MethodKind::PublicKey);
        Auth::Reject { proceed_with_methods: Some(methods), partial_success: false }
    }

    /// Refuses a command or subsystem on `channel`: the message on its stderr, exit status 1, closed.
    /// (The request itself succeeds: OpenSSH's client would exit on a failure before it prints the
    /// message.)
    fn refuse_command(channel: ChannelId, session: &mut Session) -> Result<(), russh::Error> {
        session.channel_success(channel)?;
        session.extended_data(channel, 1, format!("{NO_EXEC_MESSAGE}\r\n").into_bytes())?;
        session.exit_status_request(channel, 1)?;
        session.eof(channel)?;
        session.close(channel)
    }
}

impl Handler for Handlers {
    type Error = russh::Error;

    async fn auth_none(&mut self, user: &str) -> Result<Auth, Self::Error> {
        Ok(if self.may_play(None) { self.accepted(user, None) } else { self.refused(user, None) })
    }

    async fn auth_publickey_offered(
        &mut self,
        user: &str,
        offer: PublicKeyOffer<'_>,
    ) -> Result<Auth, Self::Error> {
        let key = offer.public_key;
        Ok(if self.may_play(Some(key)) { Auth::Accept } else { self.refused(user, Some(key)) })
    }

    async fn auth_publickey(&mut self, user: &str, key: VerifiedPublicKey<'_>) -> Result<Auth, Self::Error> {
        let key = key.public_key;
        Ok(if self.may_play(Some(key)) {
            self.accepted(user, Some(key))
        } else {
            self.refused(user, Some(key))
        })
    }

    async fn channel_open_session(
        &mut self,
        channel: Channel<Msg>,
        reply: ChannelOpenHandle,
        _: &mut Session,
    ) -> Result<(), Self::Error> {
        if std::mem::replace(&mut self.session_open, true) {
            reply.reject(ChannelOpenFailure::AdministrativelyProhibited).await; // one walk per connection
            return Ok(());
        }
        reply.accept().await;
        tokio::spawn(play(Arc::clone(&self.shared), Arc::clone(&self.conn), channel));
        Ok(())
    }

    async fn channel_open_direct_tcpip(
        &mut self,
        _: Channel<Msg>,
        host: &str,
        port: u32,
        _: &str,
        _: u32,
        reply: ChannelOpenHandle,
        _: &mut Session,
    ) -> Result<(), Self::Error> {
        info!(peer = %self.conn.peer, "refused port forwarding to {}:{port}", player_name(host));
        reply.reject(ChannelOpenFailure::AdministrativelyProhibited).await;
        Ok(())
    }

    async fn pty_request(
        &mut self,
        channel: ChannelId,
        _: &str,
        _: u32,
        _: u32,
        _: u32,
        _: u32,
        _: &[(russh::Pty, u32)],
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        session.channel_success(channel) // the player's task reads the request from the channel
    }

    async fn env_request(
        &mut self,
        channel: ChannelId,
        name: &str,
        _: &str,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        if name == "COLORTERM" { session.channel_success(channel) } else { session.channel_failure(channel) }
    }

    async fn shell_request(&mut self, channel: ChannelId, session: &mut Session) -> Result<(), Self::Error> {
        session.channel_success(channel)
    }

    async fn exec_request(
        &mut self,
        channel: ChannelId,
        _: &[u8],
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        info!(peer = %self.conn.peer, "refused a command");
        Handlers::refuse_command(channel, session)
    }

    async fn subsystem_request(
        &mut self,
        channel: ChannelId,
        name: &str,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        info!(peer = %self.conn.peer, "refused subsystem {}", player_name(name));
        Handlers::refuse_command(channel, session)
    }

    async fn x11_request(
        &mut self,
        channel: ChannelId,
        _: bool,
        _: &str,
        _: &str,
        _: u32,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        session.channel_failure(channel)
    }

    async fn agent_request(&mut self, _: ChannelId, _: &mut Session) -> Result<bool, Self::Error> {
        Ok(false) // agent forwarding refused
    }

    async fn tcpip_forward(&mut self, _: &str, port: &mut u32, _: &mut Session) -> Result<bool, Self::Error> {
        info!(peer = %self.conn.peer, "refused remote port forwarding of port {port}");
        Ok(false)
    }
}

/// How a walk ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum End {
    /// The player quit (q, Esc, Ctrl-C).
    Quit,
    /// The server is shutting down.
    Shutdown,
    /// No input for the idle timeout.
    Idle,
    /// The client closed the channel or the connection went.
    Gone,
    /// A frame could not be written within the write timeout.
    Stalled,
}

/// The terminal a pty request described.
struct Pty {
    term: String,
    size: (u32, u32),
}

/// The longest `TERM` / `COLORTERM` value kept (they only pick a colour depth).
const MAX_TERM: usize = 64;

fn bounded(s: &str) -> String {
    s.chars().take(MAX_TERM).collect()
}

/// One player: waits for the pty and the shell, then walks — input from the channel, frames to it,
/// the others from the world — until the player quits, idles out, stalls, goes, or the server stops.
async fn play(shared: Arc<Shared>, conn: Arc<Conn>, channel: Channel<Msg>) {
    let (mut rx, tx) = channel.split();
    let mut pty: Option<Pty> = None;
    let mut colorterm: Option<String> = None;
    loop {
        match rx.wait().await {
            Some(ChannelMsg::RequestPty { term, col_width, row_height, .. }) => {
                pty = Some(Pty { term: bounded(&term), size: (col_width, row_height) });
            }
            Some(ChannelMsg::WindowChange { col_width, row_height, .. }) => {
                if let Some(pty) = &mut pty {
                    pty.size = (col_width, row_height);
                }
            }
            Some(ChannelMsg::SetEnv { variable_name, variable_value, .. })
                if variable_name == "COLORTERM" =>
            {
                colorterm = Some(bounded(&variable_value));
            }
            Some(ChannelMsg::RequestShell { .. }) => break,
            // Refused by the handler, which closes the channel.
            Some(ChannelMsg::Exec { .. } | ChannelMsg::RequestSubsystem { .. }) => return,
            Some(ChannelMsg::Eof | ChannelMsg::Close) | None => return,
            Some(_) => {}
        }
    }
    let Some(pty) = pty else {
        let _ = tx.data_bytes(format!("{NO_PTY_MESSAGE}\r\n").into_bytes()).await;
        close(&tx, 1).await;
        return;
    };
    if pty.term.eq_ignore_ascii_case("dumb") {
        // As the local walk refuses one: cursor moves and colours would be garbage on it.
        let _ = tx.data_bytes(format!("{DUMB_TERMINAL_MESSAGE}\r\n").into_bytes()).await;
        close(&tx, 1).await;
        return;
    }
    let user = Conn::get(&conn.user).unwrap_or_else(|| "player".into());
    let now = shared.now();
    let mut player = match Player::new(
        Arc::clone(&shared.maze),
        &pty.term,
        colorterm.as_deref(),
        pty.size,
        &shared.limits,
        now,
    ) {
        Ok(player) => player,
        Err(err) => {
            let _ = tx.data_bytes(format!("mazewalk: {err}\r\n").into_bytes()).await;
            close(&tx, 1).await;
            return;
        }
    };
    let (position, heading, cell) = player.whereabouts();
    let id = {
        let mut world = shared.world();
        let id = world.join(&user, position, heading, cell);
        shared.world_version.send_replace(world.version());
        id
    };
    player.joined(id);
    conn.playing.store(true, Ordering::SeqCst);
    let end = walk(&shared, &conn, &tx, &mut rx, &mut player, id).await;
    {
        let mut world = shared.world();
        world.leave(id);
        shared.world_version.send_replace(world.version());
    }
    if end == End::Stalled {
        conn.end("stopped reading");
        return;
    }
    if end == End::Gone {
        return;
    }
    let message = match end {
        End::Shutdown => SHUTDOWN_MESSAGE.to_string(),
        End::Idle => {
            conn.ending("idle timeout");
            format!("mazewalk: disconnected after {} s without a key", shared.limits.idle_timeout.as_secs())
        }
        _ => {
            conn.ending("quit");
            match player.session().outcome().finished {
                Some(seconds) => format!("You found the exit in {seconds:.1} s."),
                None => "Thanks for walking.".to_string(),
            }
        }
    };
    let mut out = Vec::new();
    player.leave(Some(&message), &mut out);
    let write = tokio::time::timeout(shared.limits.write_timeout, tx.data_bytes(out));
    if !matches!(write.await, Ok(Ok(()))) {
        conn.end("stopped reading");
        return;
    }
    drain_answers(&mut rx, &mut player, &shared).await;
    close(&tx, if end == End::Quit { 0 } else { 1 }).await;
}

/// Waits for the terminal's answers to the last frames' queries, reading and dropping whatever else
/// comes, for at most two round trips (0.25–1 s). A channel closed before they arrive leaves them to
/// the player's shell, typed at its prompt (`1;2c`). Gives up at once on a terminal that does not answer.
async fn drain_answers(rx: &mut russh::ChannelReadHalf, player: &mut Player, shared: &Shared) {
    let waiting =
        |player: &Player| player.session().flow().in_flight() > 0 && !player.session().flow().silent();
    let round_trip = player.session().flow().round_trip().unwrap_or(0.5);
    let deadline = tokio::time::Instant::now() + Duration::from_secs_f64((2.0 * round_trip).clamp(0.25, 1.0));
    while waiting(player) {
        match tokio::time::timeout_at(deadline, rx.wait()).await {
            Ok(Some(ChannelMsg::Data { data })) => {
                player.feed(&data, shared.now());
            }
            Ok(Some(ChannelMsg::Eof | ChannelMsg::Close) | None) | Err(_) => break,
            Ok(Some(_)) => {}
        }
    }
}

/// Sends the exit status, end of file and close on the channel.
async fn close(tx: &ChannelWriteHalf<Msg>, status: u32) {
    let _ = tx.exit_status(status).await;
    let _ = tx.eof().await;
    let _ = tx.close().await;
}

/// The walk itself (see [`play`]).
async fn walk(
    shared: &Shared,
    conn: &Conn,
    tx: &ChannelWriteHalf<Msg>,
    rx: &mut russh::ChannelReadHalf,
    player: &mut Player,
    id: PlayerId,
) -> End {
    let mut out = Vec::with_capacity(16 * 1024);
    player.enter(&mut out);
    let mut versions = shared.world_version.subscribe();
    let mut shutdown = shared.shutdown.clone();
    let mut last_input = Instant::now();
    loop {
        if *shutdown.borrow_and_update() {
            return End::Shutdown;
        }
        if player.is_over() {
            return End::Quit;
        }
        let now = shared.now();
        if player.look_due(now) {
            let look = shared.world().look(); // the lock: for the snapshot's two `Arc`s only
            player.look(&look, now);
        }
        let started = Instant::now();
        if player.frame(now, &mut out) {
            player.session_mut().frame_cost(started.elapsed().as_secs_f64());
        }
        if !out.is_empty() {
            let bytes = std::mem::take(&mut out);
            match tokio::time::timeout(shared.limits.write_timeout, tx.data_bytes(bytes)).await {
                Ok(Ok(())) => {}
                Ok(Err(_)) => return End::Gone,
                Err(_) => return End::Stalled,
            }
        }
        // Tell the others where this player is now, and whether it won.
        let news = player.news();
        {
            let mut world = shared.world();
            let mut changed = world.moved(id, news.position, news.heading_deg, news.cell);
            if let Some(seconds) = news.finished {
                changed |= world.finished(id, seconds).is_some();
            }
            if changed {
                shared.world_version.send_replace(world.version());
            }
        }
        // Sleep until input, the session's next deadline, a change in the world, the idle timeout or
        // the shutdown: nothing at all happens for a player who stands still among others who do.
        let now = shared.now();
        let wake = player.next_wake(now);
        let sleep = wake.map(|at| tokio::time::sleep(Duration::from_secs_f64((at - now).clamp(0.0, 3600.0))));
        let idle = tokio::time::sleep_until((last_input + shared.limits.idle_timeout).into());
        tokio::select! {
            message = rx.wait() => match message {
                Some(ChannelMsg::Data { data }) => {
                    if player.feed(&data, shared.now()) {
                        last_input = Instant::now(); // a key, not just the terminal answering
                    }
                }
                Some(ChannelMsg::WindowChange { col_width, row_height, .. }) => {
                    player.resize(col_width, row_height, shared.now());
                }
                Some(ChannelMsg::Eof | ChannelMsg::Close) | None => return End::Gone,
                Some(_) => {}
            },
            () = async { if let Some(sleep) = sleep { sleep.await } else { std::future::pending().await } } => {}
            changed = versions.changed(), if !player.look_scheduled() => {
                if changed.is_err() {
                    return End::Shutdown; // the server is gone
                }
                versions.borrow_and_update();
                player.world_changed(shared.now());
            }
            () = idle => return End::Idle,
            _ = shutdown.changed() => {}
        }
        if conn.cut.is_cut() {
            return End::Gone;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every description gives a packet RFC 4253 allows: its length field is the rest, the whole a
    /// multiple of 8 with 4 to 11 bytes of padding, and the message readable back.
    #[test]
    fn a_disconnect_packet_is_padded_to_the_block_and_reads_back() {
        for len in 0..40 {
            let description = "x".repeat(len);
            let packet = disconnect_packet(SSH_DISCONNECT_TOO_MANY_CONNECTIONS, &description);
            let length = u32::from_be_bytes(packet[..4].try_into().unwrap()) as usize;
            assert_eq!(length + 4, packet.len());
            assert_eq!(packet.len() % 8, 0, "{len}");
            let padding = usize::from(packet[4]);
            assert!((4..12).contains(&padding), "{padding}");
            let payload = &packet[5..packet.len() - padding];
            assert_eq!(payload[0], 1, "SSH_MSG_DISCONNECT");
            assert_eq!(u32::from_be_bytes(payload[1..5].try_into().unwrap()), 11);
            let text_len = u32::from_be_bytes(payload[5..9].try_into().unwrap()) as usize;
            assert_eq!(&payload[9..9 + text_len], description.as_bytes());
            assert_eq!(&payload[9 + text_len..], &[0, 0, 0, 0], "an empty language tag");
        }
    }
}
