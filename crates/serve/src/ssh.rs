//! The SSH side of `mazewalk serve`: the accept loop and its limits, one task per connection (russh's
//! protocol task under it), one task per player that moves bytes between the SSH channel and its
//! [`Player`], the shared [`World`], and the shutdown. All the game logic is in the pure modules; this
//! one only waits, reads, writes and counts.

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use mazewalk_walk::flow::{LAST_QUERY, LastAnswer};
use russh::keys::ssh_key::public::KeyData;
use russh::keys::{PrivateKey, PublicKey};
use russh::server::{
    Auth, ChannelOpenHandle, Handle, Handler, Msg, PublicKeyOffer, Session, VerifiedPublicKey,
};
use russh::{
    Channel, ChannelId, ChannelMsg, ChannelOpenFailure, ChannelWriteHalf, Disconnect, MethodKind, MethodSet,
};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{mpsc, watch};
use tokio::task::JoinSet;
use tracing::{info, warn};

use super::algorithms;
use super::host_key::fingerprint;
use super::identity::player_name;
use super::limits::{DrawMeter, Limits, drawing_share};
use super::logs::{self, LogLimit, tenths};
use super::metrics::Metrics;
use super::player::{ClientTerminal, News, Player};
use super::recording::{RecordOptions, Recordings, Tap};
use super::records::{Keeper, Standing, standing_lines};
use super::shared::codec::{Finish, PlayerRecord, WinnerRecord};
use super::shared::view::Others;
use super::shared::{Host, LocalFinish, ServerId, SharedWorld, WorldConfig};
use super::slots::{ConnId, Refusal, Role, Slots, address_group};
use super::spawn::{Arrival, SPACING, Spawns};
use super::spectator::{Audience, Spectator, WATCH_USER};
use super::stream::{Cut, CutStream};
use super::world::{Look, PlayerId, World};
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
    /// Where to listen: every address is bound (a host name's addresses, say); port 0 on the first
    /// picks a free port, which the others then use too.
    pub listen: Vec<SocketAddr>,
    /// The host key.
    pub host_key: PrivateKey,
    /// Who may play.
    pub access: Access,
    /// The limits.
    pub limits: Limits,
    /// Where the best times go (`None`: not kept).
    pub records: Option<Keeper>,
    /// Where each player's session is recorded as an asciicast (`None`: not recorded).
    pub record: Option<RecordOptions>,
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
/// What a player or spectator pushed out of its place by a newcomer is told (a full server's fair
/// share: [`Slots::promote`]).
pub const PUSHED_OUT_MESSAGE: &str = "mazewalk: the server was full and your address held the most places; yours went to a newcomer from another address";
/// Why a connection pushed out of its place ended, for the log.
const PUSHED_OUT_REASON: &str = "pushed out: server full, its address held the most places";
/// Why a connection that confirmed a channel the server never opened ended, for the log.
const CONFIRMED_REASON: &str = "protocol violation: confirmed a channel the server never opened";
/// What a client still connected after its game is told as the server closes the connection.
pub(crate) const GAME_OVER_MESSAGE: &str = "mazewalk: the game is over; one game per connection";
/// What a client whose input ended is told as the server closes its connection.
pub const INPUT_ENDED_MESSAGE: &str = "mazewalk: your input ended; goodbye";
/// Views the spectators share, kept at most: a few followed players at a few sizes.
const SHARED_VIEWS: usize = 16;
/// How long a shutting-down server waits for its players' goodbyes before cutting them off.
const GOODBYE_GRACE: Duration = Duration::from_secs(2);
/// The smallest packet (bytes of channel data) a client may ask the game's frames to be cut into, and
/// the smallest window it may open with: OpenSSH, PuTTY and paramiko offer 16–32 KiB and windows of
/// megabytes. A client asking for 1-byte packets had every byte of every frame sent as a packet of
/// its own, sealed on its own: ~40 bytes on the wire and 11× the server's CPU per frame byte
/// (red-team pass 6). At this floor a packet's header and seal are a few percent of it.
pub const MIN_CHANNEL_PACKET: usize = 1024;
/// Failed authentication attempts per connection, as sshd's default `MaxAuthTries`. The `none`
/// request a client sends first to learn the methods is not one of them (as in sshd).
pub(crate) const MAX_AUTH_TRIES: usize = 6;
/// Public-key probes (a key offered without a signature) a connection may have accepted; later ones
/// are refused, and so count among the [`MAX_AUTH_TRIES`] and wait out the refusal's half second. A
/// client needs one accepted probe for the key it signs with (OpenSSH's `ssh` offers a key, then
/// signs with it); russh checks a certificate's CA signature on every probe before the server is
/// asked, and an accepted probe was answered at once, without limit: one connection pipelining
/// probes of a certificate under an 8192-bit RSA CA with e = 2³³−1 took 0.74 of a core, four took
/// 1.45 cores (red-team pass 7). Each probe is asked of the server with the certificate's own key,
/// so a certificate cannot be told from a key here: the cap bounds them alike.
pub const MAX_ACCEPTED_PROBES: usize = 3;

/// What all connections share.
struct Shared {
    maze: Arc<Maze>,
    access: Access,
    limits: Limits,
    config: Arc<russh::server::Config>,
    /// The world and its version (shared with the world task of a `--world` server).
    world: Arc<WorldCell>,
    shutdown: watch::Receiver<bool>,
    /// The server's clock: every session's time is seconds since this instant.
    clock: Instant,
    /// Where newcomers start.
    spawns: Spawns,
    /// Where the best times go.
    records: Option<Keeper>,
    slots: Mutex<Slots>,
    /// The screens drawing now, which share [`Limits::render_total`].
    drawing: Mutex<DrawMeter>,
    /// Every open connection, by its slot's id (to close one pushed out of its slot).
    conns: Mutex<HashMap<ConnId, Arc<Conn>>>,
    /// Which lines about connections are logged.
    log_limit: Mutex<LogLimit>,
    /// What `/metrics` counts (`--http`).
    metrics: Metrics,
    /// What the spectators share: the way to the exit (for the leader) and the views they draw.
    audience: Audience,
    /// The players' recordings (`--record-dir`).
    recordings: Option<Recordings>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The world, and its version for the players' tasks to wait on.
struct WorldCell {
    world: Mutex<World>,
    version: watch::Sender<u64>,
    /// The server's clock (as [`Shared::clock`]).
    clock: Instant,
    /// The records, whose best run is read again when another server's player finishes.
    records: Option<crate::records::Records>,
}

impl WorldCell {
    /// Changes the world with `change` under its lock, and publishes its version if it changed.
    fn change<R>(&self, change: impl FnOnce(&mut World) -> R) -> R {
        let mut world = lock(&self.world);
        let before = world.version();
        let result = change(&mut world);
        if world.version() != before {
            self.version.send_replace(world.version());
        }
        result
    }

    /// A look at the world for a player whose subscription to the version is `seen`, which then
    /// counts every version the look shows as seen (under the lock, where versions are published): a
    /// change the player has looked at does not wake it again.
    fn look(&self, seen: &mut watch::Receiver<u64>) -> Look {
        let mut world = lock(&self.world);
        seen.borrow_and_update();
        world.look() // the snapshot's two `Arc`s
    }

    /// Tells the world a player's news under its lock, and publishes the version if that changed it.
    /// A player is not woken by its own move (issue #42): where its subscription `seen` had seen
    /// every version before, it counts the new one as seen too. A finish still wakes it (its best
    /// time is in the player list). Returns whether the finish is the world's first. A finish
    /// from a head start ([`News::whole_way`] false) is no best time and no winner's.
    fn tell(&self, id: PlayerId, news: &News, seen: &mut watch::Receiver<u64>) -> bool {
        let mut world = lock(&self.world);
        let up_to_date = seen.has_changed().is_ok_and(|changed| !changed);
        let before = world.version();
        world.moved(id, news.position, news.heading_deg, news.cell);
        world.pitched(id, news.pitch_deg);
        world.clocked(id, news.clock);
        let finished = news.finished.filter(|_| news.whole_way);
        let first = finished.and_then(|seconds| world.finished(id, seconds)).is_some();
        if world.version() != before {
            self.version.send_replace(world.version());
            if up_to_date && news.finished.is_none() {
                seen.borrow_and_update();
            }
        }
        first
    }
}

/// The world task's view of this server's world (`--world`): it takes the players and their
/// finishes, and brings the others, the winner, their finishes and relabels. Each call holds the
/// world's lock for data only.
impl Host for WorldCell {
    fn locals(&self, players: &mut Vec<PlayerRecord>, finished: &mut Vec<LocalFinish>) {
        lock(&self.world).locals(players, finished);
    }

    fn others(&self, others: &Others, online: bool) {
        let now = self.clock.elapsed().as_secs_f64();
        self.change(|world| world.set_others(others, online, now));
    }

    fn winner(&self, winner: &WinnerRecord) {
        if self.change(|world| world.set_winner(winner)) {
            info!(player = %winner.name, seconds = tenths(winner.seconds), "the world's winner");
        }
    }

    fn finished(&self, server: ServerId, finishes: &[Finish]) {
        self.change(|world| world.remote_finished(server, finishes));
        // Its run may be the maze's best: the ghost (`g`) here too, within seconds (issue #43).
        if let (Some(records), false) = (&self.records, finishes.is_empty()) {
            records.reread_best_run();
        }
    }

    fn relabel(&self, ids: &[u32]) {
        self.change(|world| world.relabel(ids));
    }
}

impl Shared {
    fn world(&self) -> MutexGuard<'_, World> {
        lock(&self.world.world)
    }

    /// Publishes the world's version (after a change under [`world`](Self::world)'s lock).
    fn world_changed(&self, world: &World) {
        self.world.version.send_replace(world.version());
    }

    fn now(&self) -> f64 {
        self.clock.elapsed().as_secs_f64()
    }

    /// The samples a second `conn`'s screen may draw at `now`: its share of its address group's
    /// budget ([`Limits::render_rate`] over the group's screens now, [`screen_share`](crate::limits::screen_share)), so that the
    /// screens of one address together draw about one budget, and a lone one draws at the whole; no
    /// more than an equal share of the server's ([`Limits::render_total`]) among the screens drawing
    /// ([`drawing_share`]).
    fn render_share(&self, conn: &Conn, now: f64) -> u32 {
        let screens = lock(&self.slots).screens_from(conn.peer.ip());
        let drawing = lock(&self.drawing).drawing(now);
        drawing_share(self.limits.render_rate, screens, self.limits.render_total, drawing)
    }

    /// A screen that last counted itself drawing in second `counted` drew a frame at `now`
    /// ([`DrawMeter::drew`]).
    fn drew(&self, counted: &mut Option<u64>, now: f64) {
        *counted = Some(lock(&self.drawing).drew(*counted, now));
    }

    /// Whether a line about a connection from `group` may be logged now ([`LogLimit`]).
    fn log_ok(&self, group: IpAddr) -> bool {
        lock(&self.log_limit).allow(group, self.now())
    }

    /// Logs what the log limit left out since the last summary.
    fn log_suppressed(&self) {
        let summary = lock(&self.log_limit).take_suppressed(self.now());
        for (group, lines) in &summary.groups {
            info!(addresses = %group, lines, "log lines suppressed (rate limit)");
        }
        if summary.others.1 > 0 {
            let (groups, lines) = summary.others;
            info!(addresses = groups, lines, "log lines suppressed from other addresses (rate limit)");
        }
    }
}

/// An open connection's slot ([`Slots`]), given back on drop.
struct Slot {
    shared: Arc<Shared>,
    id: ConnId,
}

impl Drop for Slot {
    fn drop(&mut self) {
        lock(&self.shared.slots).release(self.id);
        lock(&self.shared.conns).remove(&self.id);
    }
}

/// Refusals being told at once, at most (a flood beyond it is dropped unanswered).
const MAX_REFUSALS_AT_ONCE: usize = 32;
/// How long a refusal waits for the client to read it and hang up.
const REFUSAL_GRACE: Duration = Duration::from_secs(2);

/// Tells a client it was refused, in the only place before a key exchange that OpenSSH shows: an SSH
/// identification, then a disconnect packet (unencrypted, as every packet before the key exchange is;
/// `ssh` prints "Received disconnect from …: \<the message\>"). The client's own bytes are read until it
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

/// What one connection's tasks share: who it is, whether it plays, its stream's cut and counts.
struct Conn {
    id: ConnId,
    peer: SocketAddr,
    /// The address group it is counted and logged in ([`address_group`]).
    group: IpAddr,
    cut: Arc<Cut>,
    user: Mutex<Option<String>>,
    key: Mutex<Option<String>>,
    /// The last key offered and refused (its fingerprint), for the log of a login that failed.
    refused: Mutex<Option<String>>,
    /// The authentication methods tried and refused (`none`, `password`, …), in order, each once.
    methods_refused: Mutex<Vec<&'static str>>,
    /// Authentication requests so far.
    auth_requests: AtomicUsize,
    /// Public-key probes accepted so far ([`MAX_ACCEPTED_PROBES`]).
    probes_accepted: AtomicUsize,
    /// Keys exchanged (the client asked for authentication, encrypted).
    keys: AtomicBool,
    /// Logged in.
    authenticated: AtomicBool,
    playing: AtomicBool,
    /// It logged in as a spectator ([`WATCH_USER`]).
    spectator: AtomicBool,
    /// Why it ended, when the server ended it (else the client did).
    ended: Mutex<Option<&'static str>>,
    /// The session's handle once the SSH session runs (to send a disconnect).
    handle: Mutex<Option<Handle>>,
    /// Its "connected" line was logged (so its "disconnected" line is too, whatever the log limit).
    logged: AtomicBool,
    /// A newcomer took its place ([`Conn::push_out`]).
    pushed_out: AtomicBool,
    /// Wakes its game to say goodbye when it is pushed out.
    push: tokio::sync::Notify,
}

impl Conn {
    fn new(id: ConnId, peer: SocketAddr, cut: Arc<Cut>) -> Conn {
        Conn {
            id,
            peer,
            group: address_group(peer.ip()),
            cut,
            user: Mutex::new(None),
            key: Mutex::new(None),
            refused: Mutex::new(None),
            methods_refused: Mutex::new(Vec::new()),
            auth_requests: AtomicUsize::new(0),
            probes_accepted: AtomicUsize::new(0),
            keys: AtomicBool::new(false),
            authenticated: AtomicBool::new(false),
            playing: AtomicBool::new(false),
            spectator: AtomicBool::new(false),
            ended: Mutex::new(None),
            handle: Mutex::new(None),
            logged: AtomicBool::new(false),
            pushed_out: AtomicBool::new(false),
            push: tokio::sync::Notify::new(),
        }
    }

    fn set<T>(field: &Mutex<T>, value: T) {
        *lock(field) = value;
    }

    fn get<T: Clone>(field: &Mutex<T>) -> T {
        lock(field).clone()
    }

    /// Records why the server ends the connection, for the log (the first reason is kept).
    fn ending(&self, reason: &'static str) {
        lock(&self.ended).get_or_insert(reason);
    }

    /// Ends the connection for `reason`: the stream is cut (the first reason is kept).
    fn end(&self, reason: &'static str) {
        self.ending(reason);
        self.cut.cut();
    }

    /// A newcomer took this player's (or spectator's) place: its game says goodbye
    /// ([`PUSHED_OUT_MESSAGE`]) and ends; the stream is cut after `grace` whatever the client does.
    fn push_out(self: &Arc<Self>, grace: Duration) {
        self.ending(PUSHED_OUT_REASON);
        self.pushed_out.store(true, Ordering::SeqCst);
        self.push.notify_one(); // (kept for the game's next wait if it is not waiting now)
        let conn = Arc::clone(self);
        tokio::spawn(async move {
            tokio::select! {
                () = tokio::time::sleep(grace) => conn.end(PUSHED_OUT_REASON),
                () = conn.cut.cut_off() => {}
            }
        });
    }

    /// Whether a newcomer took its place.
    fn is_pushed_out(&self) -> bool {
        self.pushed_out.load(Ordering::SeqCst)
    }

    /// Ends the connection for `reason` as politely as a client lets it: a disconnect message (the
    /// client's `ssh` prints `description`), and the stream cut after `grace` whatever the client does.
    async fn close(&self, reason: &'static str, description: &str, grace: Duration) {
        self.ending(reason);
        if let Some(handle) = Conn::get(&self.handle) {
            let sent = handle.disconnect(Disconnect::ByApplication, description.into(), String::new());
            let _ = tokio::time::timeout(grace, sent).await;
            let _ = tokio::time::timeout(grace, self.cut.cut_off()).await;
        }
        self.cut.cut();
    }
}

/// A running server.
pub struct Server {
    local_addrs: Vec<SocketAddr>,
    shutdown: watch::Sender<bool>,
    shared: Arc<Shared>,
    accept: tokio::task::JoinHandle<()>,
    /// The shared world it is part of (`--world`).
    world: Option<SharedWorld>,
}

/// Binds every address of `listen` (see [`ServeOptions::listen`]); an address that cannot be bound is
/// warned of and left out, as sshd does, unless none can be.
async fn bind(listen: &[SocketAddr]) -> std::io::Result<Vec<TcpListener>> {
    let mut listeners: Vec<TcpListener> = Vec::new();
    let mut first_error = None;
    for &addr in listen {
        // Port 0 asks for a free port: the first address's, then the same one on the others.
        let addr = match listeners.first().map(TcpListener::local_addr) {
            Some(Ok(first)) if addr.port() == 0 => SocketAddr::new(addr.ip(), first.port()),
            _ => addr,
        };
        match TcpListener::bind(addr).await {
            Ok(listener) => listeners.push(listener),
            Err(err) => {
                let err = std::io::Error::new(err.kind(), format!("cannot listen on {addr}: {err}"));
                if listen.len() > 1 {
                    warn!("{err}");
                }
                first_error.get_or_insert(err);
            }
        }
    }
    match first_error {
        Some(err) if listeners.is_empty() => Err(err),
        None if listeners.is_empty() => {
            Err(std::io::Error::new(std::io::ErrorKind::InvalidInput, "no address to listen on"))
        }
        _ => Ok(listeners),
    }
}

impl Server {
    /// Binds `options.listen` and starts accepting players (on the current tokio runtime).
    ///
    /// # Errors
    /// No address can be bound (the message names it: "cannot listen on ADDR: …").
    pub async fn start(options: ServeOptions) -> std::io::Result<Server> {
        Server::start_in(options, None).await
    }

    /// [`start`](Self::start), with the world shared on Redis when `world` is given (`--world`):
    /// the world is joined (its maze checked) after binding and before the first player is let in.
    ///
    /// # Errors
    /// As [`start`](Self::start); and Redis does not answer, or its world walks another maze (the
    /// message, a [`WorldError`](crate::shared::WorldError)'s, names both hashes).
    pub async fn start_in(options: ServeOptions, world: Option<WorldConfig>) -> std::io::Result<Server> {
        let spawns = Spawns::new(&options.maze).ok_or_else(|| {
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "the maze's start is in no cell")
        })?;
        let listeners = bind(&options.listen).await?;
        let local_addrs =
            listeners.iter().map(TcpListener::local_addr).collect::<std::io::Result<Vec<_>>>()?;
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
            preferred: algorithms::preferred(),
            // OpenSSH tries "none" first to learn the methods: no delay for that one.
            auth_rejection_time: Duration::from_millis(500),
            auth_rejection_time_initial: Some(Duration::ZERO),
            // russh counts every refusal, the first `none` too; sshd does not count that one.
            max_auth_attempts: MAX_AUTH_TRIES + 1,
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
        let clock = Instant::now();
        let in_world = match &world {
            None => World::new(),
            Some(_) => {
                let since = u64::try_from(clock.elapsed().as_millis()).unwrap_or(0);
                World::shared(crate::shared::task::unix_ms().saturating_sub(since))
            }
        };
        let records = options.records.as_ref().map(|keeper| keeper.records.clone());
        let cell = Arc::new(WorldCell {
            world: Mutex::new(in_world),
            version: watch::Sender::new(0),
            clock,
            records,
        });
        let maze = Arc::new(options.maze);
        let joined = match world {
            None => None,
            Some(config) => {
                // (the others' players checked against the maze's cells, not only its extents)
                let config = WorldConfig { maze: Some(Arc::clone(&maze)), ..config };
                let host: Arc<dyn Host> = Arc::clone(&cell) as Arc<dyn Host>;
                // (Its message says it all; its sources would repeat it.)
                let joined = SharedWorld::join(config, host)
                    .await
                    .map_err(|e| std::io::Error::other(e.to_string()))?;
                cell.change(|w| w.set_server(joined.server()));
                Some(joined)
            }
        };
        let audience = Audience::new(&maze, SHARED_VIEWS);
        let metrics = Metrics::default();
        let recordings = options.record.map(|record| Recordings::new(record, metrics.clone()));
        let shared = Arc::new(Shared {
            maze,
            access: options.access,
            limits,
            config: Arc::new(config),
            world: cell,
            shutdown: shutdown_rx,
            clock,
            spawns,
            records: options.records,
            slots: Mutex::new(Slots::new(&limits)),
            drawing: Mutex::new(DrawMeter::default()),
            conns: Mutex::new(HashMap::new()),
            log_limit: Mutex::new(LogLimit::new(0.0)),
            metrics,
            audience,
            recordings,
        });
        let accept = tokio::spawn(accept_loop(listeners, Arc::clone(&shared)));
        Ok(Server { local_addrs, shutdown, shared, accept, world: joined })
    }

    /// The first address it listens on (with the port the system chose for port 0).
    #[must_use]
    pub fn local_addr(&self) -> SocketAddr {
        self.local_addrs[0]
    }

    /// Every address it listens on.
    #[must_use]
    pub(crate) fn local_addrs(&self) -> &[SocketAddr] {
        &self.local_addrs
    }

    /// Players in the maze now.
    #[must_use]
    pub fn players(&self) -> usize {
        self.shared.world().len()
    }

    /// Open connections now (players, spectators and those still connecting).
    #[must_use]
    pub fn connections(&self) -> usize {
        let slots = lock(&self.shared.slots);
        slots.players() + slots.spectators() + slots.handshakes()
    }

    /// Spectators watching now.
    #[must_use]
    pub fn spectators(&self) -> usize {
        lock(&self.shared.slots).spectators()
    }

    /// Views the spectators rendered, and those they took from another's render, so far
    /// ([`SharedViews::counts`](mazewalk_walk::views::SharedViews::counts)).
    #[must_use]
    pub fn shared_views(&self) -> (u64, u64) {
        self.shared.audience.views.counts()
    }

    /// Connections still in the handshake now (key exchange and authentication).
    #[must_use]
    pub fn handshakes(&self) -> usize {
        lock(&self.shared.slots).handshakes()
    }

    /// Tells every player the server is shutting down, restores their terminals, closes every
    /// connection and stops listening; then leaves the shared world, if any (the other servers are
    /// told at once); returns when all are closed.
    pub async fn shutdown(self) {
        self.shutdown.send_replace(true);
        let _ = self.accept.await;
        if let Some(world) = self.world {
            world.leave().await;
        }
    }

    /// Serves `/metrics` and the status page (of the maze called `maze_name`) over HTTP on `addr` until
    /// the shutdown ([`crate::http`]); returns the address
    /// bound (port 0 picks one).
    ///
    /// # Errors
    /// The address cannot be bound.
    pub async fn serve_http(&self, addr: SocketAddr, maze_name: &str) -> std::io::Result<SocketAddr> {
        let shared = Arc::clone(&self.shared);
        let world = self.world.as_ref().map(SharedWorld::stats_cell);
        let live = crate::metrics::Live(Box::new(move || crate::metrics::Snapshot {
            players: shared.world().len(),
            handshakes: lock(&shared.slots).handshakes(),
            records: shared.records.as_ref().map(|keeper| {
                let (written, failed) = keeper.records.written_failed();
                (written, failed, keeper.records.dropped())
            }),
            world: world.as_ref().map(|stats| *lock(stats)),
        }));
        let registry = crate::metrics::registry(&self.shared.metrics, live);
        let shared = Arc::clone(&self.shared);
        // the player list's JSON and the world's version and whether it was online, when built
        let players: Mutex<Option<(WorldState, String)>> = Mutex::new(None);
        let records = self.shared.records.as_ref().map(|keeper| keeper.records.clone());
        let site = crate::http::Site {
            registry,
            maze: crate::http::maze_json(&self.shared.maze, maze_name, &self.joining()).into(),
            versions: self.shared.world.version.subscribe(),
            players: Box::new(move || {
                // Built once a change of the world (every stream asks at each), outside its lock.
                let look = shared.world().look();
                let mut cached = lock(&players);
                let key = (look.version, look.online);
                if cached.as_ref().is_none_or(|(at, _)| *at != key) {
                    *cached = Some((key, crate::http::players_json(&look)));
                }
                cached.as_ref().map(|(_, json)| json.clone()).unwrap_or_default()
            }),
            best_run: Box::new(move || {
                crate::http::best_run_json(records.as_ref().and_then(|r| r.best_run()).as_deref())
            }),
            streams: Arc::default(),
            requests: std::sync::Mutex::default(),
            shutdown: self.shared.shutdown.clone(),
        };
        let (local, _task) = crate::http::start(addr, site).await?;
        Ok(local)
    }

    /// How a player joins, for the status page: this server's SSH port and its host key's
    /// fingerprint (SHA-256, as `ssh` shows it when it first meets the host).
    fn joining(&self) -> crate::http::Joining {
        crate::http::Joining {
            ssh_port: self.local_addrs.first().map(SocketAddr::port),
            host_key: self.shared.config.keys.first().map(|key| fingerprint(key.public_key())),
        }
    }

    /// What `/metrics` counts as it happens.
    #[must_use]
    pub fn metrics(&self) -> &Metrics {
        &self.shared.metrics
    }

    /// What the world task has done so far (`None`: the world is this server's alone).
    #[must_use]
    pub fn world_stats(&self) -> Option<crate::shared::Stats> {
        self.world.as_ref().map(SharedWorld::stats)
    }
}

/// Accepts connections until shutdown, then waits for them to close.
async fn accept_loop(listeners: Vec<TcpListener>, shared: Arc<Shared>) {
    // One task per listener hands its connections over, one at a time.
    let (accepted_tx, mut accepted) = mpsc::channel::<(TcpStream, SocketAddr)>(1);
    let mut acceptors = JoinSet::new();
    for listener in listeners {
        acceptors.spawn(accept(listener, accepted_tx.clone(), shared.shutdown.clone()));
    }
    drop(accepted_tx);
    let mut connections = JoinSet::new();
    let mut refusals = JoinSet::new();
    let mut shutdown = shared.shutdown.clone();
    let mut summary = tokio::time::interval(Duration::from_secs(logs::SUMMARY_SECONDS));
    summary.tick().await; // (the first tick is at once)
    loop {
        tokio::select! {
            () = until_shutdown(&mut shutdown) => break,
            Some(_) = connections.join_next(), if !connections.is_empty() => {}
            Some(_) = refusals.join_next(), if !refusals.is_empty() => {}
            _ = summary.tick() => shared.log_suppressed(),
            Some((stream, peer)) = accepted.recv() => admit(&shared, stream, peer, &mut connections, &mut refusals),
        }
    }
    acceptors.abort_all();
    refusals.abort_all();
    while connections.join_next().await.is_some() {}
    shared.log_suppressed();
}

/// Accepts connections on `listener` into `accepted` until shutdown.
async fn accept(
    listener: TcpListener,
    accepted: mpsc::Sender<(TcpStream, SocketAddr)>,
    mut shutdown: watch::Receiver<bool>,
) {
    let mut warned = None::<Instant>;
    loop {
        tokio::select! {
            () = until_shutdown(&mut shutdown) => return,
            result = listener.accept() => match result {
                Ok(connection) => {
                    if accepted.send(connection).await.is_err() {
                        return;
                    }
                }
                Err(err) => {
                    // Out of file descriptors, say: wait a little rather than spin, and say so
                    // once a minute at most.
                    if warned.is_none_or(|at| at.elapsed() > Duration::from_secs(60)) {
                        warn!("accept failed: {err}");
                        warned = Some(Instant::now());
                    }
                    tokio::time::sleep(Duration::from_millis(100)).await;
                }
            },
        }
    }
}

/// A new connection: a slot for it (pushing out another's handshake, perhaps), or a refusal.
fn admit(
    shared: &Arc<Shared>,
    stream: TcpStream,
    peer: SocketAddr,
    connections: &mut JoinSet<()>,
    refusals: &mut JoinSet<()>,
) {
    let admitted = lock(&shared.slots).admit(peer.ip(), shared.now());
    match admitted {
        Ok(admitted) => {
            if let Some(conn) = admitted.evicted.and_then(|id| lock(&shared.conns).get(&id).cloned()) {
                conn.end("pushed out: every handshake slot taken");
            }
            let _ = stream.set_nodelay(true);
            let _ = socket2::SockRef::from(&stream).set_send_buffer_size(shared.limits.send_buffer);
            let (stream, cut) = CutStream::new(stream);
            let conn = Arc::new(Conn::new(admitted.id, peer, cut));
            lock(&shared.conns).insert(admitted.id, Arc::clone(&conn));
            let slot = Slot { shared: Arc::clone(shared), id: admitted.id };
            connections.spawn(connection(Arc::clone(shared), stream, conn, slot));
        }
        Err(refusal) => {
            shared.metrics.refused(&refusal);
            if shared.log_ok(address_group(peer.ip())) {
                info!(peer = %peer, "refused: {}", refusal.reason());
            }
            if refusals.len() < MAX_REFUSALS_AT_ONCE {
                refusals.spawn(refuse(stream, refusal));
            }
        }
    }
}

/// Returns once the server is shutting down (or gone).
async fn until_shutdown(shutdown: &mut watch::Receiver<bool>) {
    let _ = shutdown.wait_for(|&s| s).await.is_ok(); // the guard is dropped here, before any other await
}

/// One connection, from accept to close: russh's task under a cut-able stream, the handshake timeout,
/// the shutdown, and the disconnect log line.
async fn connection(shared: Arc<Shared>, stream: CutStream<TcpStream>, conn: Arc<Conn>, _slot: Slot) {
    let started = Instant::now();
    let handler =
        Handlers { shared: Arc::clone(&shared), conn: Arc::clone(&conn), session_open: false, shell: false };
    let handshake = tokio::time::sleep(shared.limits.handshake_timeout);
    tokio::pin!(handshake);
    let kex = tokio::time::sleep(shared.limits.kex_timeout);
    tokio::pin!(kex);
    let mut kex_over = false;
    let mut shutdown = shared.shutdown.clone();
    let mut shutting_down = false;
    let mut handshake_over = false;
    let ssh = async {
        match russh::server::run_stream(Arc::clone(&shared.config), stream, handler).await {
            Ok(session) => {
                Conn::set(&conn.handle, Some(session.handle()));
                session.await
            }
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
            () = &mut kex, if !kex_over => {
                kex_over = true;
                if !conn.keys.load(Ordering::SeqCst) {
                    conn.end("key exchange timeout");
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
    Conn::set(&conn.handle, None);
    if let Some(cpu) = conn.cut.kex_finished() {
        shared.metrics.key_exchange(cpu); // closed before its keys were exchanged
    }
    let error = result.err().map(|e| logs::error_reason(&e));
    let logged_in = conn.authenticated.load(Ordering::SeqCst);
    let methods = Conn::get(&conn.methods_refused);
    let refused = Conn::get(&conn.refused);
    let reason = match (Conn::get(&conn.ended), logged_in || methods.is_empty()) {
        (Some(ended), _) => ended.to_string(),
        // Refused and never let in: the client gave up (it closes, or says nothing more).
        (None, false) => format!("authentication failed ({})", methods.join(", ")),
        (None, true) => error.unwrap_or_else(|| "closed".into()),
    };
    if conn.logged.load(Ordering::SeqCst) || shared.log_ok(conn.group) {
        info!(
            peer = %conn.peer,
            user = %Conn::get(&conn.user).as_deref().unwrap_or("-"),
            key = Conn::get(&conn.key).or(refused).as_deref().unwrap_or("-"),
            seconds = tenths(started.elapsed().as_secs_f64()),
            bytes_in = conn.cut.bytes_in.load(Ordering::Relaxed),
            bytes_out = conn.cut.bytes_out.load(Ordering::Relaxed),
            // (quoted, as `key`: a reason is words, `reason="authentication failed (none)"`)
            reason = reason.as_str(),
            "disconnected"
        );
    }
}

/// russh's callbacks for one connection: authentication, and the answers to channel requests. The
/// session channel's bytes go to the player's task ([`play`]).
struct Handlers {
    shared: Arc<Shared>,
    conn: Arc<Conn>,
    session_open: bool,
    /// The session channel's shell was asked for: the game runs on it, and a command or subsystem
    /// asked for afterwards is refused without closing it.
    shell: bool,
}

impl Handlers {
    fn may_play(&self, key: Option<&PublicKey>) -> bool {
        match (&self.shared.access, key) {
            (Access::Open, _) => true,
            (Access::Keys(keys), Some(key)) => keys.contains(key.key_data()),
            (Access::Keys(_), None) => false,
        }
    }

    /// A request for `user` arrived: the name is kept for the log whatever comes of it. The first
    /// moves the handshake on ([`Slots::progress`]); later ones do not: a client sending requests
    /// as fast as it can (probes, refused tries) would otherwise never look stalled, and newcomers
    /// pushed out the honest handshakes waiting a round trip between their steps instead (red-team
    /// pass 7: with a few addresses of one /24 probing every few milliseconds, 0 of 15 logins got
    /// in). A handshake's milestones are the keys exchanged and its first request; it is pushed out
    /// after those that have reached neither since.
    fn request(&self, user: &str) {
        let earlier = self.conn.auth_requests.fetch_add(1, Ordering::SeqCst);
        Conn::set(&self.conn.user, Some(player_name(user)));
        if earlier == 0 {
            self.progress();
        }
    }

    /// The handshake moved on: it keeps its slot longer than those that did not.
    fn progress(&self) {
        lock(&self.shared.slots).progress(self.conn.id, self.shared.now());
    }

    fn accepted(&self, user: &str, key: Option<&PublicKey>) -> Auth {
        let name = player_name(user);
        let fingerprint = key.map(fingerprint);
        self.conn.authenticated.store(true, Ordering::SeqCst);
        if self.shared.log_ok(self.conn.group) {
            self.conn.logged.store(true, Ordering::SeqCst);
            info!(
                peer = %self.conn.peer,
                user = %name,
                key = fingerprint.as_deref().unwrap_or("-"),
                "connected"
            );
        }
        Conn::set(&self.conn.user, Some(name));
        Conn::set(&self.conn.key, fingerprint);
        Auth::Accept
    }

    /// Refuses a request by `method` (with `key`, if one): the log of the connection will say whose
    /// and which.
    fn refused(&self, method: &'static str, key: Option<&PublicKey>) -> Auth {
        let mut methods = lock(&self.conn.methods_refused);
        if !methods.contains(&method) {
            methods.push(method);
        }
        if let Some(key) = key {
            Conn::set(&self.conn.refused, Some(fingerprint(key)));
        }
        let mut methods = MethodSet::empty();
        methods.push(MethodKind::PublicKey);
        Auth::Reject { proceed_with_methods: Some(methods), partial_success: false }
    }

    /// Refuses a command or subsystem on `channel`: the message on its stderr, exit status 1, closed.
    /// (The request itself succeeds: OpenSSH's client would exit on a failure before it prints the
    /// message.) On a channel whose game runs already (its shell was asked for), the request fails
    /// and the game goes on: closing the channel under it left the player in the maze, drawn for no
    /// one, until its view changed.
    fn refuse_command(&self, channel: ChannelId, session: &mut Session) -> Result<(), russh::Error> {
        if self.shell {
            return session.channel_failure(channel);
        }
        session.channel_success(channel)?;
        session.extended_data(channel, 1, format!("{NO_EXEC_MESSAGE}\r\n").into_bytes())?;
        session.exit_status_request(channel, 1)?;
        session.eof(channel)?;
        session.close(channel)
    }

    /// Logs `line` about this connection, within the log limit.
    fn log(&self, line: std::fmt::Arguments<'_>) {
        if self.shared.log_ok(self.conn.group) {
            // the name asked for, once a request came (`player` in JSON lines), so a host can tell whose
            match Conn::get(&self.conn.user) {
                Some(user) => info!(peer = %self.conn.peer, user = %user, "{line}"),
                None => info!(peer = %self.conn.peer, "{line}"),
            }
        }
    }
}

impl Handler for Handlers {
    type Error = russh::Error;

    /// The keys are exchanged: the client's first encrypted request (for authentication) is here.
    async fn authentication_banner(&mut self) -> Result<Option<String>, Self::Error> {
        self.conn.keys.store(true, Ordering::SeqCst);
        if let Some(cpu) = self.conn.cut.kex_finished() {
            self.shared.metrics.key_exchange(cpu);
        }
        self.progress();
        Ok(None)
    }

    async fn auth_none(&mut self, user: &str) -> Result<Auth, Self::Error> {
        self.request(user);
        Ok(if self.may_play(None) { self.accepted(user, None) } else { self.refused("none", None) })
    }

    async fn auth_password(&mut self, user: &str, _: &str) -> Result<Auth, Self::Error> {
        self.request(user);
        Ok(self.refused("password", None))
    }

    async fn auth_keyboard_interactive<'a>(
        &'a mut self,
        user: &str,
        _: &str,
        _: Option<russh::server::Response<'a>>,
    ) -> Result<Auth, Self::Error> {
        self.request(user);
        Ok(self.refused("keyboard-interactive", None))
    }

    async fn auth_publickey_offered(
        &mut self,
        user: &str,
        offer: PublicKeyOffer<'_>,
    ) -> Result<Auth, Self::Error> {
        self.request(user);
        let key = offer.public_key;
        // (russh asks this before it checks a signature whose key was not offered first)
        let refused = algorithms::refused_signature(offer.algorithm) || algorithms::refused_key(key);
        // (counted only where it would be accepted: refused probes are russh's to count and delay)
        let accept = !refused
            && self.may_play(Some(key))
            && self.conn.probes_accepted.fetch_add(1, Ordering::SeqCst) < MAX_ACCEPTED_PROBES;
        Ok(if accept {
            Auth::Accept // a probe: the client signs next
        } else {
            self.refused("publickey", Some(key))
        })
    }

    async fn auth_publickey(&mut self, user: &str, key: VerifiedPublicKey<'_>) -> Result<Auth, Self::Error> {
        // (A signed request that follows an accepted probe is not counted twice.)
        Conn::set(&self.conn.user, Some(player_name(user)));
        let (algorithm, key) = (key.algorithm, key.public_key);
        Ok(if !algorithms::refused_signature(algorithm) && self.may_play(Some(key)) {
            self.accepted(user, Some(key))
        } else {
            self.refused("publickey", Some(key))
        })
    }

    async fn auth_succeeded(&mut self, session: &mut Session) -> Result<(), Self::Error> {
        let spectator = Conn::get(&self.conn.user).as_deref() == Some(WATCH_USER);
        let role = if spectator { Role::Spectator } else { Role::Player };
        self.conn.spectator.store(spectator, Ordering::SeqCst);
        let promoted = lock(&self.shared.slots).promote(self.conn.id, role, self.shared.now());
        if let Ok(Some(victim)) = promoted {
            // The server was full: a place of the address holding the most is this one's now.
            self.shared.metrics.pushed_out(role);
            if let Some(victim) = lock(&self.shared.conns).get(&victim).cloned() {
                victim.push_out(self.shared.limits.write_timeout + GOODBYE_GRACE);
            }
        }
        if let Err(refusal) = promoted {
            // Every player's (or spectator's) slot was taken while this one logged in.
            self.shared.metrics.refused(&refusal);
            self.log(format_args!("refused: {}", refusal.reason()));
            self.conn.ending(refusal.reason());
            session.disconnect(Disconnect::TooManyConnections, &refusal.message(), "")?;
        }
        Ok(())
    }

    async fn channel_open_session(
        &mut self,
        channel: Channel<Msg>,
        reply: ChannelOpenHandle,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        if std::mem::replace(&mut self.session_open, true) {
            reply.reject(ChannelOpenFailure::AdministrativelyProhibited).await; // one walk per connection
            return Ok(());
        }
        let packet = channel.writable_packet_size().await; // the client's packet size, or window if less
        if packet < MIN_CHANNEL_PACKET {
            self.log(format_args!(
                "refused a session: a packet size of {packet} (under {MIN_CHANNEL_PACKET} bytes)"
            ));
            self.conn.ending("packets too small");
            reply.reject(ChannelOpenFailure::AdministrativelyProhibited).await;
            let message = format!(
                "mazewalk: a packet size of {packet} is too small (at least {MIN_CHANNEL_PACKET} bytes)"
            );
            session.disconnect(Disconnect::ByApplication, &message, "")?;
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
        self.log(format_args!("refused port forwarding: {}:{port}", player_name(host)));
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
        // the ones that choose the picture (the player's task reads them from the channel)
        if ClientTerminal::ENV.contains(&name) {
            session.channel_success(channel)
        } else {
            session.channel_failure(channel)
        }
    }

    async fn shell_request(&mut self, channel: ChannelId, session: &mut Session) -> Result<(), Self::Error> {
        self.shell = true;
        session.channel_success(channel)
    }

    async fn exec_request(
        &mut self,
        channel: ChannelId,
        _: &[u8],
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        self.log(format_args!("refused a command"));
        self.refuse_command(channel, session)
    }

    async fn subsystem_request(
        &mut self,
        channel: ChannelId,
        name: &str,
        session: &mut Session,
    ) -> Result<(), Self::Error> {
        self.log(format_args!("refused subsystem: {}", player_name(name)));
        self.refuse_command(channel, session)
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

    /// The server opens no channel, so a client's confirmation can only name one the client opened:
    /// russh takes its window and packet size as that channel's before asking here, so a player that
    /// confirmed its own game's channel with a packet size of 1 had every byte of every frame sealed
    /// as a packet of its own again, past the floor checked at the open (red-team pass 14). The
    /// connection ends here, before anything more is sent on it.
    async fn channel_open_confirmation(
        &mut self,
        _: ChannelId,
        packet: u32,
        _: u32,
        _: &mut Session,
    ) -> Result<(), Self::Error> {
        self.log(format_args!(
            "closed: it confirmed a channel the server never opened (packet size {packet})"
        ));
        self.conn.end(CONFIRMED_REASON);
        Err(russh::Error::Inconsistent)
    }

    async fn agent_request(&mut self, _: ChannelId, _: &mut Session) -> Result<bool, Self::Error> {
        Ok(false) // agent forwarding refused
    }

    async fn tcpip_forward(&mut self, _: &str, port: &mut u32, _: &mut Session) -> Result<bool, Self::Error> {
        self.log(format_args!("refused remote port forwarding: port {port}"));
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
    /// A newcomer took its place: the server was full and its address held the most.
    PushedOut,
}

/// The terminal a pty request described, with the environment the client sent.
struct Pty {
    terminal: ClientTerminal,
    size: (u32, u32),
}

/// The connection's one session channel: the game, then — if the client keeps the connection open
/// after it (a multiplexing master, a client that never hangs up) — the connection closed after
/// [`Limits::after_game`], so that it gives its slot back.
async fn play(shared: Arc<Shared>, conn: Arc<Conn>, channel: Channel<Msg>) {
    game(&shared, &conn, channel).await;
    if Conn::get(&conn.ended) == Some("closed") {
        // The client's input ended (`ssh < /dev/null`, a closed pipe): nothing more will come.
        conn.close("closed", INPUT_ENDED_MESSAGE, Duration::from_secs(1)).await;
        return;
    }
    let after = tokio::time::timeout(shared.limits.after_game, conn.cut.cut_off());
    if after.await.is_err() {
        conn.close("game over", GAME_OVER_MESSAGE, Duration::from_secs(1)).await;
    }
}

/// One player: waits for the pty and the shell, then walks — input from the channel, frames to it,
/// the others from the world — until the player quits, idles out, stalls, goes, or the server stops.
async fn game(shared: &Arc<Shared>, conn: &Arc<Conn>, channel: Channel<Msg>) {
    let (mut rx, tx) = channel.split();
    let mut pty: Option<Pty> = None;
    let mut env = ClientTerminal::default(); // (sent before or after the pty request)
    loop {
        match rx.wait().await {
            Some(ChannelMsg::RequestPty { term, col_width, row_height, .. }) => {
                pty = Some(Pty { terminal: ClientTerminal::new(&term), size: (col_width, row_height) });
            }
            Some(ChannelMsg::WindowChange { col_width, row_height, .. }) => {
                if let Some(pty) = &mut pty {
                    pty.size = (col_width, row_height);
                }
            }
            Some(ChannelMsg::SetEnv { variable_name, variable_value, .. }) => {
                env.set(&variable_name, &variable_value);
            }
            Some(ChannelMsg::RequestShell { .. }) => break,
            // Refused by the handler, which closes the channel.
            Some(ChannelMsg::Exec { .. } | ChannelMsg::RequestSubsystem { .. }) => return,
            Some(ChannelMsg::Eof | ChannelMsg::Close) | None => return,
            Some(_) => {}
        }
    }
    let Some(mut pty) = pty else {
        let _ = tx.data_bytes(format!("{NO_PTY_MESSAGE}\r\n").into_bytes()).await;
        close(&tx, 1).await;
        return;
    };
    for name in ClientTerminal::ENV {
        if let Some(value) = env.get(name) {
            pty.terminal.set(name, value);
        }
    }
    if pty.terminal.term().eq_ignore_ascii_case("dumb") {
        // As the local walk refuses one: cursor moves and colours would be garbage on it.
        let _ = tx.data_bytes(format!("{DUMB_TERMINAL_MESSAGE}\r\n").into_bytes()).await;
        close(&tx, 1).await;
        return;
    }
    if conn.spectator.load(Ordering::SeqCst) {
        watch(shared, conn, tx, rx, &pty).await;
        return;
    }
    let user = Conn::get(&conn.user).unwrap_or_else(|| "player".into());
    let now = shared.now();
    let mut player = match Player::new(Arc::clone(&shared.maze), &pty.terminal, pty.size, &shared.limits, now)
    {
        Ok(player) => player,
        Err(err) => {
            let _ = tx.data_bytes(format!("mazewalk: {err}\r\n").into_bytes()).await;
            close(&tx, 1).await;
            return;
        }
    };
    let id = {
        // A spot of its own, chosen and taken under one lock (two newcomers never get the same).
        let mut world = shared.world();
        let spot = shared.spawns.pick(&world.positions());
        player.place(&spot, now);
        let (position, heading, cell) = player.whereabouts();
        let id = world.join(&user, position, heading, cell, now);
        shared.world_changed(&world);
        id
    };
    player.joined(id);
    shared.metrics.joined();
    conn.playing.store(true, Ordering::SeqCst);
    // `--record-dir`: everything sent from here on, game mode on to the goodbye (its HUD says so).
    let mut tap = match &shared.recordings {
        Some(recordings) => {
            let timestamp =
                std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).ok().map(|d| d.as_secs());
            let title = format!("mazewalk serve: {}", player_name(&user));
            let header = player.cast_header(&pty.terminal, title, timestamp);
            recordings.start(&user, conn.group, header, shared.now()).await
        }
        None => None,
    };
    player.set_recorded(tap.is_some());
    let end = walk(shared, conn, &tx, &mut rx, &mut player, id, &mut tap).await;
    {
        let mut world = shared.world();
        world.leave(id);
        shared.world_changed(&world);
    }
    let quit = match player.session().outcome().finished {
        Some(seconds) if shared.records.is_some() && player.head_start() > 0 => format!(
            "You found the exit in {seconds:.1} s, from {} cells nearer it than the start (a crowd took the \
             cells behind it): not kept in the records.",
            player.head_start()
        ),
        Some(seconds) => format!("You found the exit in {seconds:.1} s."),
        None => "Thanks for walking.".to_string(),
    };
    goodbye(shared, conn, &tx, &mut rx, &mut player, end, quit, tap.as_mut()).await;
}

/// The end of a game or a watch: the terminal restored and a line saying why (quit: `quit`), or the
/// connection cut (stalled, gone). A player's recording (`tap`) gets the goodbye too.
#[allow(clippy::too_many_arguments)] // (the eighth, the recording, is a player's only)
async fn goodbye(
    shared: &Shared,
    conn: &Conn,
    tx: &ChannelWriteHalf<Msg>,
    rx: &mut russh::ChannelReadHalf,
    player: &mut impl Remote,
    end: End,
    quit: String,
    tap: Option<&mut Tap>,
) {
    if end == End::Stalled {
        conn.end("stopped reading");
        return;
    }
    if end == End::Gone {
        conn.ending("closed"); // the client closed its input or the connection went
        return;
    }
    let message = match end {
        End::Shutdown => SHUTDOWN_MESSAGE.to_string(),
        End::PushedOut => PUSHED_OUT_MESSAGE.to_string(),
        End::Idle => {
            conn.ending("idle timeout");
            format!("mazewalk: disconnected after {} s without a key", shared.limits.idle_timeout.as_secs())
        }
        _ => {
            conn.ending("quit");
            quit
        }
    };
    // Asked first, so that its answer comes before the goodbye's: that answer says every frame's
    // answer is in ([`drain_answers`]). Not asked of a terminal that never answered. (Recorded, as
    // the frames' own queries are: a cast is what the player's terminal received.)
    let asked = player.session().flow().round_trip().is_some();
    let mut out = if asked { LAST_QUERY.to_vec() } else { Vec::new() };
    player.leave(Some(&message), &mut out);
    if let Some(tap) = tap {
        tap.output(shared.now(), &out);
    }
    // A shutting-down server waits for the goodbye no longer than its grace; either way a cut ends
    // the wait (a client that types but never reads fills the channel's queue, and russh's task,
    // waiting to hand it over, would not see the cut until this write gave up).
    let patience = if end == End::Shutdown {
        GOODBYE_GRACE.min(shared.limits.write_timeout)
    } else {
        shared.limits.write_timeout
    };
    let written = tokio::select! {
        written = tokio::time::timeout(patience, send_packets(tx, out)) => matches!(written, Ok(Ok(()))),
        () = conn.cut.cut_off() => false,
    };
    if !written {
        conn.end("stopped reading");
        return;
    }
    tokio::select! {
        () = drain_answers(rx, player, shared, asked) => close(tx, if end == End::Quit { 0 } else { 1 }).await,
        () = conn.cut.cut_off() => {}
    }
}

/// One spectator: its screen follows the players until it stops watching, idles… never: a big screen
/// presses no keys (a dead link goes by keepalives and the write timeout), goes, or the server stops.
async fn watch(
    shared: &Arc<Shared>,
    conn: &Arc<Conn>,
    tx: ChannelWriteHalf<Msg>,
    mut rx: russh::ChannelReadHalf,
    pty: &Pty,
) {
    let now = shared.now();
    let mut spectator = match Spectator::new(
        Arc::clone(&shared.maze),
        &pty.terminal,
        pty.size,
        &shared.limits,
        &shared.audience,
        now,
    ) {
        Ok(spectator) => spectator,
        Err(err) => {
            let _ = tx.data_bytes(format!("mazewalk: {err}\r\n").into_bytes()).await;
            close(&tx, 1).await;
            return;
        }
    };
    shared.metrics.spectator_joined();
    conn.playing.store(true, Ordering::SeqCst);
    let end = watching(shared, conn, &tx, &mut rx, &mut spectator).await;
    shared.metrics.spectator_left();
    // (not recorded: a spectator sees what a player sees, and that player's cast has it)
    goodbye(shared, conn, &tx, &mut rx, &mut spectator, end, "Thanks for watching.".into(), None).await;
}

/// The watch itself: as [`walk`], with a spectator's screen and nothing told to the world.
async fn watching(
    shared: &Shared,
    conn: &Conn,
    tx: &ChannelWriteHalf<Msg>,
    rx: &mut russh::ChannelReadHalf,
    spectator: &mut Spectator,
) -> End {
    let mut out = Vec::with_capacity(16 * 1024);
    spectator.enter(&mut out);
    let mut versions = shared.world.version.subscribe();
    let mut counted: Option<u64> = None; // the second this screen last counted itself drawing
    let mut shutdown = shared.shutdown.clone();
    loop {
        if *shutdown.borrow_and_update() {
            return End::Shutdown;
        }
        if spectator.is_over() {
            return End::Quit;
        }
        if conn.is_pushed_out() {
            return End::PushedOut;
        }
        let now = shared.now();
        if spectator.look_due(now) {
            let look = shared.world.look(&mut versions);
            spectator.look(look, now);
        }
        spectator.session_mut().set_sample_rate(Some(shared.render_share(conn, now)));
        let started = Instant::now();
        if spectator.frame(now, &mut out) {
            spectator.session_mut().frame_cost(started.elapsed().as_secs_f64());
            shared.drew(&mut counted, now);
        }
        if !out.is_empty() {
            // (Not in the players' frames and bytes sent: /metrics counts those.)
            let write =
                tokio::time::timeout(shared.limits.write_timeout, send_packets(tx, std::mem::take(&mut out)));
            tokio::select! {
                written = write => match written {
                    Ok(Ok(())) => {}
                    Ok(Err(_)) => return End::Gone,
                    Err(_) => return End::Stalled,
                },
                () = conn.cut.cut_off() => return End::Gone,
                () = until_shutdown(&mut shutdown) => return End::Shutdown,
            }
        }
        let now = shared.now();
        let wake = spectator.next_wake(now);
        let sleep = wake.map(|at| tokio::time::sleep(Duration::from_secs_f64((at - now).clamp(0.0, 3600.0))));
        tokio::select! {
            message = rx.wait() => match message {
                Some(ChannelMsg::Data { data }) => {
                    if spectator.feed(&data, shared.now()) {
                        lock(&shared.slots).active(conn.id, shared.now()); // a key: pushed out after the idler
                    }
                }
                Some(ChannelMsg::WindowChange { col_width, row_height, .. }) => {
                    spectator.resize(col_width, row_height, shared.now());
                }
                Some(ChannelMsg::Eof | ChannelMsg::Close) | None => return End::Gone,
                Some(_) => {}
            },
            () = async { if let Some(sleep) = sleep { sleep.await } else { std::future::pending().await } } => {}
            changed = versions.changed(), if !spectator.look_scheduled() => {
                if changed.is_err() {
                    return End::Shutdown;
                }
                versions.borrow_and_update();
                spectator.world_changed(shared.now());
            }
            _ = shutdown.changed() => {}
            () = conn.cut.cut_off() => return End::Gone,
            () = conn.push.notified() => return End::PushedOut,
        }
        if conn.cut.is_cut() {
            return End::Gone;
        }
    }
}

/// Waits for the terminal's answers to the last frames' queries, reading and dropping whatever else
/// comes, for at most two round trips (0.25–1 s): when `asked` ([`LAST_QUERY`] went before the
/// goodbye), until its answer comes (the frames' own count is not enough: after a terminal stopped
/// reading for a while, the frames sent meanwhile were counted lost, and their answers came after
/// the close); else while frames are counted in flight. A channel closed before they arrive leaves
/// them to the player's shell, typed at its prompt (`1;2c`). Gives up at once on a terminal that
/// does not answer.
async fn drain_answers(
    rx: &mut russh::ChannelReadHalf,
    player: &mut impl Remote,
    shared: &Shared,
    asked: bool,
) {
    let counted =
        |player: &dyn Remote| player.session().flow().in_flight() > 0 && !player.session().flow().silent();
    let round_trip = player.session().flow().round_trip().unwrap_or(0.5);
    let deadline = tokio::time::Instant::now() + Duration::from_secs_f64((2.0 * round_trip).clamp(0.25, 1.0));
    let (mut last, mut answered) = (LastAnswer::default(), false);
    while if asked { !answered } else { counted(player) } {
        match tokio::time::timeout_at(deadline, rx.wait()).await {
            Ok(Some(ChannelMsg::Data { data })) => {
                player.feed(&data, shared.now());
                answered = last.read(&data);
            }
            Ok(Some(ChannelMsg::Eof | ChannelMsg::Close) | None) | Err(_) => break,
            Ok(Some(_)) => {}
        }
    }
}

/// What the goodbye needs of a player's or a spectator's screen.
trait Remote {
    /// Bytes from its terminal ([`Player::feed`]).
    fn feed(&mut self, bytes: &[u8], now: f64) -> bool;
    /// Its session.
    fn session(&self) -> &mazewalk_walk::Session;
    /// The bytes that give its terminal back, and a line ([`Player::leave`]).
    fn leave(&self, message: Option<&str>, out: &mut Vec<u8>);
}

impl Remote for Player {
    fn feed(&mut self, bytes: &[u8], now: f64) -> bool {
        Player::feed(self, bytes, now)
    }
    fn session(&self) -> &mazewalk_walk::Session {
        Player::session(self)
    }
    fn leave(&self, message: Option<&str>, out: &mut Vec<u8>) {
        Player::leave(self, message, out);
    }
}

impl Remote for Spectator {
    fn feed(&mut self, bytes: &[u8], now: f64) -> bool {
        Spectator::feed(self, bytes, now)
    }
    fn session(&self) -> &mazewalk_walk::Session {
        Spectator::session(self)
    }
    fn leave(&self, message: Option<&str>, out: &mut Vec<u8>) {
        Spectator::leave(self, message, out);
    }
}

/// Sends the exit status, end of file and close on the channel.
/// The least channel data the game's output is cut into a packet of, unless less is left to send:
/// half [`MIN_CHANNEL_PACKET`]. A client that opened with a window of at least the floor and hands
/// it back as it reads (OpenSSH, PuTTY and paramiko hand back at half the window consumed) never
/// waits on it; one that hands back a byte at a time waits here for a packet's worth, instead of
/// having every byte sent and sealed as a packet of its own (red-team pass 7).
const LEAST_PACKET: usize = MIN_CHANNEL_PACKET / 2;

/// Sends `bytes` on the channel in packets of at least [`LEAST_PACKET`] (the last may be less):
/// each packet waits for the client's window to hold that much, looking again at growing intervals
/// up to 50 ms (russh wakes a writer on any window growth, and would send what the window holds).
/// The caller bounds the wait (the write timeout).
async fn send_packets(tx: &ChannelWriteHalf<Msg>, bytes: Vec<u8>) -> Result<(), russh::Error> {
    let bytes = bytes::Bytes::from(bytes);
    let mut sent = 0;
    while sent < bytes.len() {
        let want = (bytes.len() - sent).min(LEAST_PACKET);
        let mut pause = Duration::from_millis(1);
        let writable = loop {
            let writable = tx.writable_packet_size().await;
            if writable >= want {
                break writable;
            }
            tokio::time::sleep(pause).await;
            pause = (pause * 2).min(Duration::from_millis(50));
        };
        let end = (sent + writable).min(bytes.len());
        tx.data_bytes(bytes.slice(sent..end)).await?; // within the window: one packet
        sent = end;
    }
    Ok(())
}

async fn close(tx: &ChannelWriteHalf<Msg>, status: u32) {
    let _ = tx.exit_status(status).await;
    let _ = tx.eof().await;
    let _ = tx.close().await;
}

/// A world's version and whether a shared one was online (`Look::version`, `Look::online`): what the
/// status page's player list was built for.
type WorldState = (u64, Option<bool>);

/// A shared world's newcomer standing where another server's earlier player stands (the two joined
/// within a message's way of each other, or this server had not heard of the other yet: a spot is
/// picked from what this server knows) moves to a free spot, as if it had known: exactly one of the
/// two moves (the later comer, by the order every server computes alike), and only while its
/// [`Arrival`] says so. Checked at each look under the world's lock (O(other servers' players))
/// until then.
fn settle(shared: &Shared, player: &mut Player, id: PlayerId, arriving: &mut Option<Arrival>, now: f64) {
    let Some(arrival) = arriving.as_mut() else { return };
    if !arrival.settling(player.whereabouts().0, now) {
        *arriving = None; // for good
        return;
    }
    let mut world = shared.world();
    if !world.came_first_near(id, SPACING) {
        return;
    }
    let Some(spot) = arrival.crowded(&shared.spawns, &world.positions_but(id)) else { return };
    player.place(&spot, now);
    let (position, heading, cell) = player.whereabouts();
    world.moved(id, position, heading, cell);
    shared.world_changed(&world);
    arrival.placed(position);
}

/// The walk itself (see [`play`]).
async fn walk(
    shared: &Shared,
    conn: &Conn,
    tx: &ChannelWriteHalf<Msg>,
    rx: &mut russh::ChannelReadHalf,
    player: &mut Player,
    id: PlayerId,
    tap: &mut Option<Tap>,
) -> End {
    let mut out = Vec::with_capacity(16 * 1024);
    player.enter(&mut out);
    let mut versions = shared.world.version.subscribe();
    let mut counted: Option<u64> = None; // the second this screen last counted itself drawing
    let mut shutdown = shared.shutdown.clone();
    let mut last_input = Instant::now();
    // The first key the next frame answers (for /metrics).
    let mut key_at: Option<Instant> = None;
    // The records' answer to the last finish (the maze's best times for the exit box), on its way.
    let mut standing: Option<tokio::sync::oneshot::Receiver<Option<Standing>>> = None;
    let user = Conn::get(&conn.user).unwrap_or_default();
    // The size its recording was told (the cast's header has the first).
    let mut recorded_size = (player.session().screen().width(), player.session().screen().height());
    // (In a world of this server's alone, spots are picked under one lock: nothing to settle.)
    let in_world = shared.world().is_shared();
    let mut arriving = in_world.then(|| Arrival::new(player.whereabouts().0, shared.now()));
    loop {
        if *shutdown.borrow_and_update() {
            return End::Shutdown;
        }
        if player.is_over() {
            return End::Quit;
        }
        if conn.is_pushed_out() {
            return End::PushedOut;
        }
        let now = shared.now();
        if let Some(keeper) = &shared.records {
            // the maze's best run, for the ghost (`g`): the records thread's latest, checked
            player.session_mut().set_ghost_run(keeper.records.best_run());
        }
        if player.look_due(now) {
            // Under the lock: the snapshot's two `Arc`s cloned, after rebuilding it if the world
            // changed since the last look (World::look); every version it shows counts as seen.
            let look = shared.world.look(&mut versions);
            player.look(&look, now);
            settle(shared, player, id, &mut arriving, now);
        }
        player.session_mut().set_sample_rate(Some(shared.render_share(conn, now)));
        let started = Instant::now();
        let drew = player.frame(now, &mut out);
        if drew {
            player.session_mut().frame_cost(started.elapsed().as_secs_f64());
            shared.drew(&mut counted, now);
        }
        let screen = player.session().screen(); // the size drawn: within the limits
        if (screen.width(), screen.height()) != recorded_size {
            recorded_size = (screen.width(), screen.height());
            if let Some(tap) = tap.as_mut() {
                let size = |n: usize| u16::try_from(n).unwrap_or(u16::MAX);
                tap.resize(now, size(recorded_size.0), size(recorded_size.1));
            }
        }
        if !out.is_empty() {
            let bytes = std::mem::take(&mut out);
            let len = bytes.len();
            if let Some(tap) = tap.as_mut() {
                tap.depth(now, player.session().color_depth()); // the terminal said truecolor: marked
                tap.output(now, &bytes);
            }
            let write = tokio::time::timeout(shared.limits.write_timeout, send_packets(tx, bytes));
            tokio::select! {
                written = write => match written {
                    Ok(Ok(())) => {
                        let key = if drew { key_at.take().map(|at| at.elapsed().as_secs_f64()) } else { None };
                        shared.metrics.sent(len, drew, key);
                    }
                    Ok(Err(_)) => return End::Gone,
                    Err(_) => return End::Stalled,
                },
                () = conn.cut.cut_off() => return End::Gone,
                // (At shutdown a frame stuck in a full window gives way to the goodbye.)
                () = until_shutdown(&mut shutdown) => return End::Shutdown,
            }
        }
        // Tell the others where this player is now, and whether it won (a walk from a head start
        // back as far from the exit as the start starts again there, for the records).
        player.start_line(|cell| shared.spawns.fair(cell), shared.now());
        let news = player.news();
        let first = shared.world.tell(id, &news, &mut versions);
        if let Some(seconds) = news.finished {
            // The winner always; every other finish within the log limit.
            if first || shared.log_ok(conn.group) {
                let what = if first { "reached the exit first" } else { "reached the exit" };
                info!(peer = %conn.peer, user = %user, seconds = tenths(seconds), "{what}");
            }
            // Kept, without waiting: the standing comes back while the player plays on. Not a walk
            // from a spot nearer the exit than the start (a crowd took those behind it): no head
            // start on a record.
            if let Some(keeper) = shared.records.as_ref().filter(|_| player.head_start() == 0) {
                player.session_mut().set_standings(Vec::new());
                let holder = crate::identity::player_name(&user);
                let run = player.session().app().run(keeper.maze, &holder).and_then(|run| run.encode().ok());
                standing = keeper.finish(&user, seconds, run);
            } else if shared.records.is_some() {
                // (the exit box says so at once, where the best times would stand)
                let lines = crate::records::head_start_lines(player.head_start());
                player.session_mut().set_standings(lines);
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
                        lock(&shared.slots).active(conn.id, shared.now()); // pushed out after the idler
                        key_at.get_or_insert(last_input);
                    }
                }
                Some(ChannelMsg::WindowChange { col_width, row_height, .. }) => {
                    player.resize(col_width, row_height, shared.now()); // now, or when its turn comes
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
            answer = async { standing.as_mut().expect("checked").await }, if standing.is_some() => {
                standing = None;
                if let Ok(Some(answer)) = answer {
                    player.session_mut().set_standings(standing_lines(&answer, &user));
                }
            }
            () = idle => return End::Idle,
            _ = shutdown.changed() => {}
            () = conn.cut.cut_off() => return End::Gone,
            () = conn.push.notified() => return End::PushedOut,
        }
        if conn.cut.is_cut() {
            return End::Gone;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    /// Issue #42: a player's own move does not wake its task to look at the world; another's move
    /// does, until a look shows it; a move made while another's is still unseen leaves it to be seen;
    /// standing still changes nothing; a finish wakes even the finisher (its best time is listed).
    #[test]
    fn a_player_is_not_woken_by_its_own_move() {
        let cell = WorldCell {
            world: Mutex::new(World::new()),
            version: watch::Sender::new(0),
            clock: Instant::now(),
            records: None,
        };
        let (a, b) = cell.change(|world| {
            (
                world.join("alice", Vec2::ZERO, 0.0, 0, 0.0),
                world.join("bob", Vec2::new(4.0, 0.0), 0.0, 1, 0.0),
            )
        });
        let (mut seen_a, mut seen_b) = (cell.version.subscribe(), cell.version.subscribe());
        let woken = |seen: &watch::Receiver<u64>| seen.has_changed().expect("the world is there");
        let at = |x: f32| News {
            position: Vec2::new(x, 0.0),
            heading_deg: 0.0,
            cell: 0,
            pitch_deg: 0.0,
            finished: None,
            clock: crate::world::WalkClock { started: 0.0, took: None },
            whole_way: true,
        };
        cell.tell(a, &at(0.5), &mut seen_a);
        assert!(!woken(&seen_a), "alice's own move");
        assert!(woken(&seen_b), "bob is told alice moved");
        let look = cell.look(&mut seen_b);
        assert!(!woken(&seen_b), "bob's look showed it");
        assert_eq!(look.players.len(), 2);
        cell.tell(b, &at(4.5), &mut seen_b);
        assert!(woken(&seen_a) && !woken(&seen_b), "bob's move wakes alice, not bob");
        cell.tell(a, &at(0.7), &mut seen_a);
        assert!(woken(&seen_a), "bob's move is still to be seen by alice");
        cell.look(&mut seen_a);
        let version = *cell.version.borrow();
        cell.tell(a, &at(0.7), &mut seen_a);
        assert_eq!(*cell.version.borrow(), version, "standing still changes nothing");
        assert!(!woken(&seen_a));
        // red-team pass 5: a walk from a head start (a crowd put bob nearer the exit) is no best
        // time and no winner's; alice's whole way, later and slower, is the world's first
        let head_start = News { finished: Some(5.0), whole_way: false, ..at(4.9) };
        assert!(!cell.tell(b, &head_start, &mut seen_b), "not crowned");
        cell.look(&mut seen_b);
        assert!(cell.look(&mut seen_a).players.iter().all(|(_, p)| p.best.is_none()), "no best time shown");
        assert!(cell.tell(a, &News { finished: Some(12.0), ..at(0.9) }, &mut seen_a), "the first");
        assert!(woken(&seen_a) && woken(&seen_b), "a finish wakes everyone");
    }

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
