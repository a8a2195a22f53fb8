//! The world task: one per server, between the server's own world ([`Host`]) and Redis. It alone
//! talks to Redis, and it never makes anyone wait for it: every command runs on a task of its own
//! and reports back, so a Redis that is slow, gone or silent delays no player's frame — the player
//! tasks touch only the in-process world, as without `--world`.
//!
//! ```text
//! every tick (1/30 s):  the host's players ─▶ Outbox ─▶ PUBLISH (a full one with its presence key)
//!                       finishes ─▶ SET NX winner (the first) · ZADD best (each)
//!                       silent servers expire · labels another server's earlier player shows ─▶ relabel
//! each message heard:   Others ─▶ the host's view of the other servers (within its caps), finishes;
//!                       a winner claimed that is not the one known ─▶ GET winner (once a second
//!                       at most): the winner is only ever what Redis holds, never a message's word
//! Redis lost:           the host hears "offline" (the others freeze); commands reconnect, the
//!                       subscription resubscribes; once back: a full message, the winner
//!                       re-asserted, the finishes and records kept meanwhile sent, the others'
//!                       presence keys read
//! ```

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use redis::aio::MultiplexedConnection;
use redis::{RedisError, RedisResult};
use tokio::sync::{mpsc, watch};
use tokio::task::JoinHandle;
use tracing::{info, warn};

use super::codec::{self, Bounds, Finish, PlayerRecord, ServerId, WinnerRecord, maze_tag};
use super::redis::{self as link, Heard, Link, WorldError};
use super::view::{Caps, Counts, Others, Outbox, TICKS_PER_SECOND};
use crate::limits::RateLimit;
use crate::logs::{ERROR_CHARS, GROUP_BURST, GROUP_INTERVAL, SUMMARY_SECONDS, clip};
use mazewalk_maze::Maze;

/// The server's own world, as the world task sees it (the in-process world implements it).
/// Each call is quick and takes the world's lock for the data only.
pub trait Host: Send + Sync + 'static {
    /// This server's players now, into `players` (cleared first, in id order), and those who
    /// reached the exit since the last call, appended to `finished`.
    fn locals(&self, players: &mut Vec<PlayerRecord>, finished: &mut Vec<LocalFinish>);
    /// The other servers' players changed, or the world went online or offline (`online`: this
    /// server hears Redis and Redis hears it; else the others are as last heard, frozen).
    fn others(&self, others: &Others, online: bool);
    /// The world's winner, first known or corrected.
    fn winner(&self, winner: &WinnerRecord);
    /// Players on another server reached the exit (one call per message heard).
    fn finished(&self, server: ServerId, finishes: &[Finish]);
    /// These players of this server show a label that an earlier player on another server shows:
    /// each should take another label if one is free.
    fn relabel(&self, ids: &[u32]);
}

/// A player of this server reached the exit.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalFinish {
    /// Its id on this server.
    pub id: u32,
    /// Its name.
    pub name: String,
    /// How long its walk took, seconds.
    pub seconds: f64,
}

/// What it takes to join a world.
#[derive(Clone, Debug)]
pub struct WorldConfig {
    /// `redis://[user:pass@]host:port[/db]`, or `rediss://…` for TLS.
    pub url: String,
    /// The maze's content hash (hex): servers of one world walk the same maze.
    pub maze_hash: String,
    /// The maze's bounds, for checking what the others say.
    pub bounds: Bounds,
    /// The maze itself, where known: each other player's position is checked against its cell
    /// ([`Others::with_maze`]).
    pub maze: Option<Arc<Maze>>,
    /// The certificate (PEM) of the CA that signed a `rediss://` Redis's certificate, when it is
    /// not one the system trusts.
    pub ca: Option<Vec<u8>>,
    /// How much of the other servers this one keeps (`--max-remote-servers`, `--max-remote-players`).
    pub caps: Caps,
}

impl WorldConfig {
    /// The world at `url` for the maze hashed `maze_hash` within `bounds`, with no CA of its own and
    /// the default caps.
    #[must_use]
    pub fn new(url: &str, maze_hash: &str, bounds: Bounds) -> WorldConfig {
        WorldConfig {
            url: url.into(),
            maze_hash: maze_hash.into(),
            bounds,
            maze: None,
            ca: None,
            caps: Caps::default(),
        }
    }
}

/// What the world task has done so far, for logs, tests and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Messages published.
    pub published: u64,
    /// Their bytes.
    pub published_bytes: u64,
    /// Redis commands sent (a pipeline counts each of its commands).
    pub commands: u64,
    /// Messages heard, and what became of them.
    pub heard: Counts,
    /// Bytes heard.
    pub heard_bytes: u64,
    /// Messages dropped unread for their size.
    pub too_long: u64,
    /// Messages dropped unread because the world task had more than [`MAX_QUEUED_BYTES`] (or
    /// 1,024 messages) still to read: the world task's queue stays bounded whatever arrives.
    ///
    /// [`MAX_QUEUED_BYTES`]: super::redis::MAX_QUEUED_BYTES
    pub overflow: u64,
    /// Times the winner was read from Redis because a message claimed another.
    pub winner_reads: u64,
    /// Keys named as a server's presence left out when the presence keys were read: a value that is
    /// not a string of at most a message's size (never sent by Redis). Said once in the log. (Names
    /// under the prefix that are not a server's are not sent by Redis, nor counted.)
    pub presences_left_out: u64,
    /// Whether the world is online now.
    pub online: bool,
    /// Times the world went offline.
    pub outages: u64,
}

/// A joined world: its task runs until [`SharedWorld::leave`]. Dropped without it, the task stops
/// at once and says nothing, as when the process is killed: the others notice the silence.
pub struct SharedWorld {
    server: ServerId,
    link: Link,
    stop: watch::Sender<bool>,
    task: JoinHandle<()>,
    listener: JoinHandle<()>,
    stats: Arc<Mutex<Stats>>,
}

/// In-flight publishes at most; beyond, a tick publishes nothing and its changes wait for the next.
const MAX_PUBLISHING: usize = 4;
/// Records of finishes kept while Redis is away, at most (the oldest go first).
const MAX_PENDING: usize = 1024;
/// The longest a stopping server waits to say goodbye.
const BYE_TIMEOUT: Duration = Duration::from_millis(500);
/// At most one log line about dropped messages per this many seconds.
const DROP_LOG_EVERY: f64 = 10.0;
/// Other servers read from their presence keys at most (a world of more is not expected).
const MAX_SERVERS: usize = 1024;
/// Seconds between two reads of the winner from Redis at least, however many messages claim one.
const WINNER_READ_EVERY: f64 = 1.0;
/// Seconds between two reads of the presence keys, sustained, however often the subscription comes
/// back (a read SCANs the whole keyspace: with a million keys of another application, a subscription
/// killed every 100 ms cost Redis 7 s of CPU in 10 s), after a burst of [`PRESENCE_READ_BURST`] (the
/// join's read and a first comeback's, at once). A presence lives 5 s and each server's full message
/// comes every second: reads more often would add little that listening does not.
const PRESENCE_READ_EVERY: f64 = 5.0;
/// Reads of the presence keys at once, before [`PRESENCE_READ_EVERY`] paces them.
const PRESENCE_READ_BURST: u32 = 2;

/// Milliseconds since the Unix epoch.
#[must_use]
pub fn unix_ms() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX))
}

impl SharedWorld {
    /// Joins the world at `config.url` for `host`, on the current tokio runtime: checks that the
    /// world walks this maze (or claims it), learns its winner, then runs the world task.
    ///
    /// # Errors
    /// The URL is bad, Redis does not answer, or the world walks another maze.
    pub async fn join(config: WorldConfig, host: Arc<dyn Host>) -> Result<SharedWorld, WorldError> {
        let link = Link::new(&config.url, &config.maze_hash, config.ca.as_deref())?;
        let unreachable = |source: RedisError| WorldError::Unreachable { url: link.url.clone(), source };
        let mut con = link.connect().await.map_err(unreachable)?;
        let world = link::claim_world(&mut con, &link.keys, &config.maze_hash).await.map_err(unreachable)?;
        if world != config.maze_hash {
            let url_db1 = with_db(&link.url, 1);
            return Err(WorldError::OtherMaze {
                url: link.url.clone(),
                url_db1,
                world,
                ours: config.maze_hash,
            });
        }
        let stored = link::winner(&mut con, &link.keys).await.map_err(unreachable)?;
        let winner = stored.and_then(|bytes| codec::decode_winner(&bytes).ok());
        if let Some(winner) = &winner {
            host.winner(winner);
        }
        let server = ServerId(getrandom::u64().unwrap_or_else(|_| unix_ms() ^ u64::from(std::process::id())));
        let tag = maze_tag(&config.maze_hash);
        let (heard_tx, heard) = mpsc::channel(1024);
        let inbox = link::Inbox::default();
        let listener = tokio::spawn(link.clone().listen(heard_tx, inbox.clone()));
        let (done_tx, done) = mpsc::unbounded_channel();
        let (stop, stopping) = watch::channel(false);
        let stats = Arc::new(Mutex::new(Stats::default()));
        let task = Task {
            link: link.clone(),
            host,
            maze_hash: config.maze_hash,
            server,
            con: Some(con),
            reconnecting: false,
            subscribed: false,
            online: false,
            outbox: Outbox::new(server, tag),
            others: match config.maze {
                Some(maze) => Others::new(server, tag, config.bounds).with_caps(config.caps).with_maze(maze),
                None => Others::new(server, tag, config.bounds).with_caps(config.caps),
            },
            caps: config.caps,
            inbox,
            reading_presences: false,
            presences_due: false,
            presence_reads: RateLimit::new_per_interval(PRESENCE_READ_EVERY, PRESENCE_READ_BURST, 0.0),
            reading_winner: false,
            winner_read_due: false,
            winner_read_at: f64::NEG_INFINITY,
            warnings: Warnings::new(0.0),
            winner,
            claiming: false,
            claims: VecDeque::new(),
            records: VecDeque::new(),
            ready: Vec::new(),
            publishing: 0,
            done_tx,
            clock: Instant::now(),
            stats: Arc::clone(&stats),
            counted: Stats::default(),
            players: Vec::new(),
            finished: Vec::new(),
            others_dirty: false,
            others_told: f64::NEG_INFINITY,
            labels: Vec::new(),
            labels_dirty: true,
            last_drop_log: f64::NEG_INFINITY,
            dropped_logged: 0,
        };
        let task = tokio::spawn(task.run(heard, done, stopping));
        info!(world = %link.url, server = %format!("{:016x}", server.0), "joined the shared world");
        Ok(SharedWorld { server, link, stop, task, listener, stats })
    }

    /// This server's id in the world.
    #[must_use]
    pub fn server(&self) -> ServerId {
        self.server
    }

    /// What the world task has done so far.
    #[must_use]
    pub fn stats(&self) -> Stats {
        *self.stats.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Where [`stats`](Self::stats) are kept, to read them later (`/metrics`).
    pub(crate) fn stats_cell(&self) -> Arc<Mutex<Stats>> {
        Arc::clone(&self.stats)
    }

    /// The `n` best times in the world, best first (name, seconds).
    ///
    /// # Errors
    /// Redis failed.
    pub async fn best(&self, n: usize) -> RedisResult<Vec<(String, f64)>> {
        let mut con = self.link.connect().await?;
        link::best(&mut con, &self.link.keys, n).await
    }

    /// Leaves the world: the others are told at once (a goodbye, if Redis answers within half a
    /// second), and the task stops.
    pub async fn leave(mut self) {
        self.stop.send_replace(true);
        let _ = (&mut self.task).await;
    }
}

impl Drop for SharedWorld {
    fn drop(&mut self) {
        self.task.abort();
        self.listener.abort();
    }
}

/// `url` with database `db` (for a suggestion in a message).
fn with_db(url: &str, db: i64) -> String {
    let Some((scheme, rest)) = url.split_once("://") else { return url.to_owned() };
    let host = rest.split(['/', '?', '#']).next().unwrap_or(rest);
    format!("{scheme}://{host}/{db}")
}

/// What a command reports back to the world task.
enum Done {
    Connected(MultiplexedConnection),
    Published(RedisResult<Option<String>>),
    Claimed(Option<LocalFinish>, RedisResult<Option<Vec<u8>>>, WinnerRecord),
    Recorded((String, f64), RedisResult<()>),
    Presences(RedisResult<link::Presences>),
    Read(RedisResult<Option<Vec<u8>>>),
}

struct Task {
    link: Link,
    host: Arc<dyn Host>,
    maze_hash: String,
    server: ServerId,
    /// The command connection while it works.
    con: Option<MultiplexedConnection>,
    reconnecting: bool,
    /// The subscription is up.
    subscribed: bool,
    /// As last told to the host.
    online: bool,
    outbox: Outbox,
    others: Others,
    caps: Caps,
    /// What the subscribed connection holds for this task, and what it dropped.
    inbox: link::Inbox,
    /// The world's winner as Redis holds it (read, or this server's claim stored): never a
    /// message's word.
    winner: Option<WinnerRecord>,
    /// A read of the presence keys is in flight (one at most).
    reading_presences: bool,
    /// The subscription came back: read the presence keys when [`presence_reads`](Self::presence_reads)
    /// allows.
    presences_due: bool,
    /// The pace of the presence reads ([`PRESENCE_READ_EVERY`], [`PRESENCE_READ_BURST`]).
    presence_reads: RateLimit,
    /// A read of the winner is in flight.
    reading_winner: bool,
    /// A message claimed a winner other than the known one: read it from Redis when allowed.
    winner_read_due: bool,
    /// When the winner was last read.
    winner_read_at: f64,
    /// The budget of warnings.
    warnings: Warnings,
    /// A claim on the winner is in flight.
    claiming: bool,
    /// Finishes waiting to claim the win (while no winner is known).
    claims: VecDeque<LocalFinish>,
    /// Finishes waiting to be recorded.
    records: VecDeque<(String, f64)>,
    /// Finishes to tell the others at the next tick.
    ready: Vec<Finish>,
    publishing: usize,
    done_tx: mpsc::UnboundedSender<Done>,
    clock: Instant,
    stats: Arc<Mutex<Stats>>,
    /// Stats as counted here (copied into `stats` once a tick).
    counted: Stats,
    players: Vec<PlayerRecord>,
    finished: Vec<LocalFinish>,
    /// The others changed since the host last heard (it hears at most once a tick).
    others_dirty: bool,
    /// When the host last heard of the others.
    others_told: f64,
    /// This server's labels at the last tick, and whether the others changed since.
    labels: Vec<(u32, char)>,
    labels_dirty: bool,
    last_drop_log: f64,
    dropped_logged: u64,
}

impl Task {
    async fn run(
        mut self,
        mut heard: mpsc::Receiver<Heard>,
        mut done: mpsc::UnboundedReceiver<Done>,
        mut stopping: watch::Receiver<bool>,
    ) {
        let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / TICKS_PER_SECOND));
        tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
        loop {
            tokio::select! {
                _ = stopping.changed() => break,
                _ = tick.tick() => self.tick(),
                Some(h) = heard.recv() => self.heard(h),
                Some(d) = done.recv() => self.done(d),
            }
        }
        self.bye().await;
    }

    fn now(&self) -> f64 {
        self.clock.elapsed().as_secs_f64()
    }

    fn tick(&mut self) {
        let now = self.now();
        // Silence counts only while this server hears the channel.
        if self.subscribed && self.others.expire(now) {
            self.others_changed(now);
        }
        if self.others_dirty {
            self.tell_others(now);
        }
        self.players.clear();
        self.host.locals(&mut self.players, &mut self.finished);
        for f in std::mem::take(&mut self.finished) {
            push_bounded(&mut self.records, (f.name.clone(), f.seconds));
            match &self.winner {
                Some(_) if self.ready.len() < MAX_PENDING => {
                    self.ready.push(Finish { id: f.id, name: f.name, seconds: f.seconds, won: false });
                }
                Some(_) => {}
                None => push_bounded(&mut self.claims, f),
            }
        }
        // Labels: checked when the others or this server's labels changed.
        let labels: Vec<(u32, char)> = self.players.iter().map(|p| (p.id, p.label)).collect();
        if self.online && (self.labels_dirty || labels != self.labels) {
            self.labels_dirty = false;
            let conflicts = self.others.label_conflicts(&self.players);
            if !conflicts.is_empty() {
                self.host.relabel(&conflicts);
            }
        }
        self.labels = labels;
        if self.con.is_some() {
            self.claim_next();
            while let Some(record) = self.records.pop_front() {
                self.spawn_record(record);
            }
            if self.publishing < MAX_PUBLISHING {
                let ready = std::mem::take(&mut self.ready);
                let message = self.outbox.tick(now, &self.players, ready, self.winner.as_ref(), unix_ms());
                if let Some(message) = message {
                    self.spawn_publish(&message);
                }
            }
        }
        self.read_winner(now);
        self.read_presences(now);
        self.log_drops(now);
        self.share_stats();
    }

    fn share_stats(&self) {
        *self.stats.lock().unwrap_or_else(PoisonError::into_inner) =
            Stats { online: self.online, ..self.counted };
    }

    fn heard(&mut self, heard: Heard) {
        let now = self.now();
        match heard {
            Heard::Up => {
                self.subscribed = true;
                self.others.reconnected(now);
                self.presences_due = true;
                self.read_presences(now);
                self.update_online();
            }
            Heard::Down => {
                self.subscribed = false;
                self.update_online();
            }
            Heard::TooLong(_) => self.counted.too_long += 1,
            Heard::Message(bytes) => {
                self.inbox.taken(bytes.len());
                self.counted.heard_bytes += bytes.len() as u64;
                self.hear(&bytes, now);
            }
        }
        self.counted.heard = self.others.counts();
        self.share_stats();
    }

    /// A message (from the channel, or a presence key) applied to the view.
    fn hear(&mut self, bytes: &[u8], now: f64) {
        let Ok(heard) = self.others.hear(bytes, now) else { return };
        if heard.changed {
            self.others_changed(now);
        }
        let Some(server) = heard.server else { return };
        if !heard.finished.is_empty() {
            self.host.finished(server, &heard.finished);
        }
        // A claim is only a hint (issue #40: anyone who may publish can claim): Redis is asked.
        if heard.winner.is_some() && heard.winner != self.winner {
            self.winner_read_due = true;
            self.read_winner(now);
        }
    }

    /// The view of the others changed at `now`: the host hears of it at once, or at the next tick
    /// if it heard less than a tick ago (with many servers, many messages a tick make one update).
    fn others_changed(&mut self, now: f64) {
        self.labels_dirty = true;
        if now - self.others_told >= 1.0 / TICKS_PER_SECOND {
            self.tell_others(now);
        } else {
            self.others_dirty = true;
        }
    }

    fn tell_others(&mut self, now: f64) {
        (self.others_dirty, self.others_told) = (false, now);
        self.host.others(&self.others, self.online);
    }

    /// The winner's record as Redis holds it (read, or answered to a claim): the world's winner.
    fn stored_winner(&mut self, bytes: &[u8]) {
        match codec::decode_winner(bytes) {
            Ok(stored) => self.adopt(stored),
            Err(err) => {
                if self.warnings.allow(self.now()) {
                    warn!(world = %self.link.url, "the world's winner key holds no winner ({err}); ignored");
                }
            }
        }
    }

    /// The world's winner, as Redis holds it.
    fn adopt(&mut self, winner: WinnerRecord) {
        if self.winner.as_ref() == Some(&winner) {
            return;
        }
        if let Some(known) = &self.winner
            && self.warnings.allow(self.now())
        {
            // Only after Redis lost the key and another claim was stored meanwhile, or a writer
            // set it: Redis decides.
            warn!(world = %self.link.url, known = %known.name, stored = %winner.name, "the world's winner changed in Redis");
        }
        self.winner = Some(winner.clone());
        self.host.winner(&winner);
        // Finishes waiting to claim have lost.
        for f in self.claims.drain(..) {
            self.ready.push(Finish { id: f.id, name: f.name, seconds: f.seconds, won: false });
        }
    }

    /// Reads the winner from Redis if a message asked for it and the last read was
    /// [`WINNER_READ_EVERY`] ago (one in flight at most).
    fn read_winner(&mut self, now: f64) {
        if !self.winner_read_due || self.reading_winner || now - self.winner_read_at < WINNER_READ_EVERY {
            return;
        }
        let Some(mut con) = self.con.clone() else { return }; // when Redis is back
        (self.winner_read_due, self.reading_winner, self.winner_read_at) = (false, true, now);
        self.counted.commands += 1;
        self.counted.winner_reads += 1;
        let (keys, done) = (self.link.keys.clone(), self.done_tx.clone());
        tokio::spawn(async move {
            let _ = done.send(Done::Read(link::winner(&mut con, &keys).await));
        });
    }

    fn done(&mut self, done: Done) {
        match done {
            Done::Connected(con) => {
                self.con = Some(con);
                self.reconnecting = false;
                self.outbox.resync(); // everything, at the next tick
                if let Some(winner) = self.winner.clone() {
                    self.spawn_claim(None, winner); // in case Redis came back empty
                }
                self.update_online();
            }
            Done::Published(result) => {
                self.publishing -= 1;
                match result {
                    Ok(Some(world)) if world != self.maze_hash => {
                        if self.warnings.allow(self.now()) {
                            // (a writer's garbage says what it is: `(a list, not a maze hash)`, a string)
                            let maze_hash = world.len() == 64 && world.bytes().all(|b| b.is_ascii_hexdigit());
                            let world = clip(&world, ERROR_CHARS);
                            if maze_hash {
                                warn!(world = %world, ours = %self.maze_hash, "the world's key names another maze: another maze's server claimed it");
                            } else {
                                warn!(ours = %self.maze_hash, "the world's key holds {world}, not a maze hash: something else wrote it");
                            }
                        }
                    }
                    Ok(_) => {}
                    Err(err) => self.lost(&err),
                }
            }
            Done::Claimed(finish, result, claim) => {
                if finish.is_some() {
                    self.claiming = false;
                }
                match result {
                    Ok(None) => {
                        // Stored: this claim is the winner (or a re-assertion was needed).
                        if let Some(f) = finish {
                            self.winner = Some(claim.clone());
                            self.host.winner(&claim);
                            self.ready.push(Finish { id: f.id, name: f.name, seconds: f.seconds, won: true });
                            let lost: Vec<LocalFinish> = self.claims.drain(..).collect();
                            self.ready.extend(lost.into_iter().map(|f| Finish {
                                id: f.id,
                                name: f.name,
                                seconds: f.seconds,
                                won: false,
                            }));
                        }
                    }
                    Ok(Some(stored)) => {
                        if let Some(f) = finish {
                            self.ready.push(Finish {
                                id: f.id,
                                name: f.name,
                                seconds: f.seconds,
                                won: false,
                            });
                        }
                        self.stored_winner(&stored); // the stored one is the world's
                    }
                    Err(err) => {
                        if let Some(f) = finish {
                            self.claims.push_front(f);
                        }
                        self.lost(&err);
                    }
                }
            }
            Done::Recorded(record, result) => {
                if let Err(err) = result {
                    push_bounded(&mut self.records, record);
                    self.lost(&err);
                }
            }
            Done::Read(result) => {
                self.reading_winner = false;
                match result {
                    Ok(Some(stored)) => self.stored_winner(&stored),
                    // Redis lost the key (restarted empty): the known winner, which came from it,
                    // is stored again; a claim heard meanwhile is not.
                    Ok(None) => {
                        if let Some(known) = self.winner.clone() {
                            self.spawn_claim(None, known);
                        }
                    }
                    Err(err) => {
                        self.winner_read_due = true;
                        self.lost(&err);
                    }
                }
            }
            Done::Presences(result) => {
                self.reading_presences = false;
                match result {
                    Ok(read) => {
                        let now = self.now();
                        if read.left_out > 0 && self.counted.presences_left_out == 0 {
                            warn!(
                                world = %self.link.url,
                                "presence keys that hold no message (a value of another type or size) \
                                 are left out, unread (said once)"
                            );
                        }
                        self.counted.presences_left_out += read.left_out;
                        for bytes in read.messages {
                            self.hear(&bytes, now);
                        }
                        self.counted.heard = self.others.counts();
                    }
                    Err(err) => {
                        self.presences_due = true;
                        self.lost(&err);
                    }
                }
            }
        }
    }

    /// A command failed: the connection is dropped and made again in the background.
    fn lost(&mut self, err: &RedisError) {
        if self.con.take().is_some() && self.warnings.allow(self.now()) {
            warn!(world = %self.link.url, "the world is offline: {}", clip(&err.to_string(), ERROR_CHARS));
        }
        if !self.reconnecting {
            self.reconnecting = true;
            let (link, done) = (self.link.clone(), self.done_tx.clone());
            tokio::spawn(async move {
                let _ = done.send(Done::Connected(link.reconnect().await));
            });
        }
        self.update_online();
    }

    /// Tells the host when the world goes online or offline.
    fn update_online(&mut self) {
        let online = self.con.is_some() && self.subscribed;
        if online != self.online {
            self.online = online;
            self.labels_dirty = true;
            if online {
                if self.warnings.allow(self.now()) {
                    info!(world = %self.link.url, "the world is online");
                }
            } else {
                self.counted.outages += 1;
            }
            self.tell_others(self.now());
        }
    }

    fn claim_next(&mut self) {
        if self.claiming || self.winner.is_some() {
            return;
        }
        if let Some(f) = self.claims.pop_front() {
            self.claiming = true;
            let claim =
                WinnerRecord { server: self.server, id: f.id, seconds: f.seconds, name: f.name.clone() };
            self.spawn_claim(Some(f), claim);
        }
    }

    /// Claims the win for `claim` (a finish of this server's, or the known winner re-asserted).
    fn spawn_claim(&mut self, finish: Option<LocalFinish>, claim: WinnerRecord) {
        let Some(mut con) = self.con.clone() else {
            if let Some(f) = finish {
                self.claiming = false;
                self.claims.push_front(f);
            }
            return;
        };
        self.counted.commands += 1;
        let (keys, done) = (self.link.keys.clone(), self.done_tx.clone());
        tokio::spawn(async move {
            let result = link::claim_winner(&mut con, &keys, &codec::encode_winner(&claim)).await;
            let _ = done.send(Done::Claimed(finish, result, claim));
        });
    }

    fn spawn_record(&mut self, record: (String, f64)) {
        let Some(mut con) = self.con.clone() else {
            self.records.push_front(record);
            return;
        };
        self.counted.commands += 1;
        let (keys, done) = (self.link.keys.clone(), self.done_tx.clone());
        tokio::spawn(async move {
            let result = link::record(&mut con, &keys, &record.0, record.1).await;
            let _ = done.send(Done::Recorded(record, result));
        });
    }

    fn spawn_publish(&mut self, message: &codec::Message) {
        let Some(mut con) = self.con.clone() else { return };
        let mut bytes = Vec::with_capacity(256);
        codec::encode(message, &mut bytes);
        let full = matches!(message.body, codec::Body::Full { .. }).then(|| self.maze_hash.clone());
        self.publishing += 1;
        self.counted.published += 1;
        self.counted.published_bytes += bytes.len() as u64;
        self.counted.commands += if full.is_some() { 3 } else { 1 };
        let (keys, server, done) = (self.link.keys.clone(), self.server, self.done_tx.clone());
        tokio::spawn(async move {
            let result = link::publish(&mut con, &keys, server, &bytes, full.as_deref()).await;
            let _ = done.send(Done::Published(result));
        });
    }

    /// Reads the presence keys if the subscription came back since the last read and the pace allows
    /// ([`PRESENCE_READ_EVERY`] after a burst of [`PRESENCE_READ_BURST`]; one in flight at most).
    fn read_presences(&mut self, now: f64) {
        if !self.presences_due || self.reading_presences {
            return;
        }
        let Some(mut con) = self.con.clone() else { return }; // when Redis is back
        if self.presence_reads.take(1, now) == 0 {
            return; // (still due: a later tick reads them)
        }
        (self.presences_due, self.reading_presences) = (false, true);
        // No more than the view keeps (each up to a message's size: bounded memory).
        let max = self.caps.servers.min(MAX_SERVERS);
        self.counted.commands += 2;
        let (keys, done) = (self.link.keys.clone(), self.done_tx.clone());
        tokio::spawn(async move {
            let _ = done.send(Done::Presences(link::presences(&mut con, &keys, max).await));
        });
    }

    /// Dropped messages, in one line per [`DROP_LOG_EVERY`] seconds at most, and the warnings the
    /// budget left out, summed up every [`SUMMARY_SECONDS`].
    fn log_drops(&mut self, now: f64) {
        self.counted.overflow = self.inbox.dropped();
        let heard = self.counted.heard;
        let dropped = heard.dropped + self.counted.too_long + self.counted.overflow + heard.over_servers;
        if dropped > self.dropped_logged && now - self.last_drop_log >= DROP_LOG_EVERY {
            warn!(
                world = %self.link.url,
                "dropped {} messages from the world (malformed: {}, too long: {}, over the queue: {}, \
                 from servers over --max-remote-servers: {}); players left out over --max-remote-players: {}",
                dropped - self.dropped_logged,
                heard.dropped,
                self.counted.too_long,
                self.counted.overflow,
                heard.over_servers,
                heard.over_players,
            );
            (self.dropped_logged, self.last_drop_log) = (dropped, now);
        }
        if let Some(suppressed) = self.warnings.summary(now) {
            warn!(world = %self.link.url, "{suppressed} more warnings about the world suppressed");
        }
    }

    /// The goodbye: the others drop this server's players at once, and its presence key goes.
    async fn bye(mut self) {
        let Some(mut con) = self.con.take() else { return };
        let message = self.outbox.bye(unix_ms());
        let mut bytes = Vec::new();
        codec::encode(&message, &mut bytes);
        let keys = &self.link.keys;
        let mut pipe = redis::pipe();
        pipe.cmd("PUBLISH").arg(&keys.channel).arg(bytes).ignore();
        pipe.cmd("DEL").arg(keys.server(self.server)).ignore();
        let _ = tokio::time::timeout(BYE_TIMEOUT, pipe.query_async::<()>(&mut con)).await;
    }
}

/// The world task's warnings, rate-limited as the connection log is ([`crate::logs`]): a burst of
/// [`GROUP_BURST`], then one every [`GROUP_INTERVAL`] seconds; what is left out is counted and summed
/// up in one line every [`SUMMARY_SECONDS`] (issue #40: a writer made every message log a line).
#[derive(Debug)]
struct Warnings {
    bucket: RateLimit,
    suppressed: u64,
    summed_at: f64,
}

impl Warnings {
    fn new(now: f64) -> Warnings {
        Warnings {
            bucket: RateLimit::new_per_interval(GROUP_INTERVAL, GROUP_BURST, now),
            suppressed: 0,
            summed_at: now,
        }
    }

    /// Whether a warning may be logged at `now`; if not, it is counted.
    fn allow(&mut self, now: f64) -> bool {
        let allowed = self.bucket.take(1, now) == 1;
        self.suppressed += u64::from(!allowed);
        allowed
    }

    /// The warnings left out since the last summary, when one is due at `now`.
    fn summary(&mut self, now: f64) -> Option<u64> {
        if self.suppressed == 0 || now - self.summed_at < SUMMARY_SECONDS as f64 {
            return None;
        }
        self.summed_at = now;
        Some(std::mem::take(&mut self.suppressed))
    }
}

/// Appends `item`, dropping the oldest beyond [`MAX_PENDING`].
fn push_bounded<T>(queue: &mut VecDeque<T>, item: T) {
    if queue.len() >= MAX_PENDING {
        queue.pop_front();
    }
    queue.push_back(item);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warnings_come_in_a_burst_then_a_trickle_and_the_rest_are_summed_up() {
        let mut warnings = Warnings::new(0.0);
        let allowed = (0..10_000).filter(|i| warnings.allow(f64::from(*i) * 1e-4)).count();
        assert_eq!(allowed, GROUP_BURST as usize, "the burst, in one second");
        assert_eq!(warnings.summary(5.0), None, "not yet due");
        assert!(warnings.allow(1.0 + GROUP_INTERVAL), "one more after the interval");
        let due = SUMMARY_SECONDS as f64;
        assert_eq!(warnings.summary(due), Some(10_000 - GROUP_BURST as u64), "every one left out, counted");
        assert_eq!(warnings.summary(2.0 * due), None, "counts start again");
    }

    #[test]
    fn the_suggested_url_names_database_1() {
        assert_eq!(with_db("redis://***@h:6380/0", 1), "redis://***@h:6380/1");
        assert_eq!(with_db("rediss://h", 1), "rediss://h/1");
    }
}
