//! The Redis side of the shared world: the URL, the keys and channel of a world, the connections
//! (one for commands, one subscribed; each reconnects by itself), and the few commands the world
//! task sends. Nothing here decides anything: [`super::task`] does.
//!
//! Whatever a writer stored in the world's keys, each answer Redis sends to a read is bounded by the
//! request: keys are read through Lua scripts that check a value's type and size before they send
//! it ([`GET_BOUNDED`], [`best_times`], [`presences`]), and what they leave out is counted; the
//! presence keys' names are matched by Redis against a server's ([`server_pattern`]).
//!
//! Keys, all of one maze under the hash tag `{H}` (the maze hash's first 16 hex digits) so that in
//! Redis Cluster a world's keys share one slot:
//!
//! ```text
//! mazewalk:world                  the world's maze hash (TTL 30 s, refreshed by every server)
//! mazewalk:{H}:winner             the first at the exit (SET NX; no TTL)
//! mazewalk:{H}:best               best times, seconds by player name (a sorted set; ZADD LT)
//! mazewalk:{H}:best:at, :finishes, :name, :runs   the rest of the records (super::records)
//! mazewalk:{H}:server:<id>        each server's last full message (TTL 5 s, refreshed every second)
//! mazewalk:{H}:<db>:news          the channel (Redis channels ignore the database: it is named in)
//! ```

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Duration;

use redis::aio::{AsyncPushSender, MultiplexedConnection, SendError};
use redis::{
    AsyncConnectionConfig, Client, ProtocolVersion, PushInfo, PushKind, RedisError, RedisResult, Value,
};
use thiserror::Error;
use tokio::sync::mpsc;

use super::codec::{MAX_MESSAGE_BYTES, ServerId};
use crate::identity::{MAX_NAME, player_name};
use crate::logs::{ERROR_CHARS, clip};

/// How long a connection attempt may take.
pub(crate) const CONNECT_TIMEOUT: Duration = Duration::from_secs(1);
/// How long a command may wait for its answer before the connection counts as lost.
pub(crate) const RESPONSE_TIMEOUT: Duration = Duration::from_millis(500);
/// How often the subscribed connection is checked with a PING (a Redis that vanished without
/// closing the connection never ends the stream).
pub(crate) const PING_EVERY: Duration = Duration::from_secs(1);
/// Waits between reconnection attempts: from the first to the last, then the last again (Redis back
/// is heard within this much).
const BACKOFF: [Duration; 4] = [
    Duration::from_millis(50),
    Duration::from_millis(100),
    Duration::from_millis(200),
    Duration::from_millis(400),
];
/// A server's presence key lives this long unless refreshed (it is, every second).
pub(crate) const PRESENCE_TTL_SECONDS: u64 = 5;
/// The world's maze key lives this long unless refreshed: a world no server walked for this long
/// takes the next server's maze.
pub(crate) const WORLD_TTL_SECONDS: u64 = 30;
/// The bytes of messages the subscribed connection holds for the world task at most; beyond, what
/// arrives is dropped unread and counted (issue #40: a flood of 36,000 messages grew a server by
/// 360 MB). A second of a busy world's traffic is far less.
pub const MAX_QUEUED_BYTES: usize = 8 << 20;

/// Why the world could not be joined.
#[derive(Debug, Error)]
pub enum WorldError {
    /// The URL is not a Redis URL.
    #[error("--world {url}: {source}")]
    Url {
        /// The URL, without its password.
        url: String,
        /// What the client said.
        source: RedisError,
    },
    /// A CA was given for a world without TLS.
    #[error("--world-ca is for a world over TLS (rediss://…), not {url}")]
    CaWithoutTls {
        /// The URL, without its password.
        url: String,
    },
    /// Redis did not answer. (Its text is Redis's, or the network's: clipped and escaped.)
    #[error("cannot reach the world at {url}: {}", clip(&source.to_string(), ERROR_CHARS))]
    Unreachable {
        /// The URL, without its password.
        url: String,
        /// What the client said.
        source: RedisError,
    },
    /// The world walks another maze. (The world's hash is Redis's word: clipped and escaped.)
    #[error(
        "the world at {url} walks the maze {}, and this server's maze is {ours}: start it with \
         the world's maze, or give it a world of its own (another Redis database, e.g. {url_db1})",
        clip(world, ERROR_CHARS)
    )]
    OtherMaze {
        /// The URL, without its password.
        url: String,
        /// The same with database 1 (a suggestion).
        url_db1: String,
        /// The world's maze hash.
        world: String,
        /// This server's.
        ours: String,
    },
}

/// `url` without its user name and password, for messages and logs.
#[must_use]
pub fn redacted(url: &str) -> String {
    let Some((scheme, rest)) = url.split_once("://") else { return url.to_owned() };
    let authority_end = rest.find(['/', '?', '#']).unwrap_or(rest.len());
    let (authority, path) = rest.split_at(authority_end);
    match authority.rsplit_once('@') {
        Some((_, host)) => format!("{scheme}://***@{host}{path}"),
        None => url.to_owned(),
    }
}

/// The names of one world's keys and channel.
#[derive(Clone, Debug)]
pub struct Keys {
    /// The world's maze hash.
    pub world: String,
    /// The winner.
    pub winner: String,
    /// The best times.
    pub best: String,
    /// Every server's presence key starts with this.
    pub servers: String,
    /// The channel.
    pub channel: String,
}

impl Keys {
    /// The keys of the world of the maze whose content hash is `maze_hash` in database `db`.
    #[must_use]
    pub fn new(maze_hash: &str, db: i64) -> Keys {
        let tag: String = maze_hash.chars().take(16).collect();
        Keys {
            world: "mazewalk:world".into(),
            winner: format!("mazewalk:{{{tag}}}:winner"),
            best: format!("mazewalk:{{{tag}}}:best"),
            servers: format!("mazewalk:{{{tag}}}:server:"),
            channel: format!("mazewalk:{{{tag}}}:{db}:news"),
        }
    }

    /// When each best time was made (a hash, by player name).
    #[must_use]
    pub fn best_at(&self) -> String {
        format!("{}:at", self.best)
    }

    /// Server `server`'s presence key.
    #[must_use]
    pub fn server(&self, server: ServerId) -> String {
        format!("{}{:016x}", self.servers, server.0)
    }
}

/// One world's Redis: its client and keys.
#[derive(Clone, Debug)]
pub struct Link {
    client: Client,
    /// The same, speaking RESP3, for the subscribed connection: its messages come to
    /// [`Deliver`] as the connection reads them, with no queue of the client's own between.
    subscriber: Client,
    /// The URL without its password.
    pub url: String,
    /// The keys.
    pub keys: Keys,
}

impl Link {
    /// The link to the world at `url` (`redis://[user:pass@]host:port[/db]`, `rediss://` for TLS,
    /// `redis+unix:///path` for a socket) for the maze hashed `maze_hash`. Connects to nothing yet.
    /// A `rediss://` server's certificate is checked against the system's roots, or against `ca`
    /// (PEM) when given (redis-cli's `--cacert`: a Redis with a certificate of its own CA).
    ///
    /// # Errors
    /// The URL is not a Redis URL, or `ca` is given for a URL without TLS.
    pub fn new(url: &str, maze_hash: &str, ca: Option<&[u8]>) -> Result<Link, WorldError> {
        // rustls asks for a process-wide crypto provider; ring is russh's too. Installing it twice is
        // refused harmlessly.
        let _ = rustls::crypto::ring::default_provider().install_default();
        let shown = redacted(url);
        let bad_url = |source| WorldError::Url { url: shown.clone(), source };
        let client = match ca {
            None => Client::open(url).map_err(bad_url)?,
            Some(_) if !url.starts_with("rediss://") => return Err(WorldError::CaWithoutTls { url: shown }),
            Some(pem) => {
                let certificates = redis::TlsCertificates { client_tls: None, root_cert: Some(pem.to_vec()) };
                Client::build_with_tls(url, certificates).map_err(bad_url)?
            }
        };
        let info = client.get_connection_info();
        let db = info.redis_settings().db();
        let resp3 = info.redis_settings().clone().set_protocol(ProtocolVersion::RESP3);
        let subscriber = Client::open(info.clone().set_redis_settings(resp3)).map_err(bad_url)?;
        Ok(Link { client, subscriber, url: shown, keys: Keys::new(maze_hash, db) })
    }

    /// A connection for commands (pipelined: clones share it), with the timeouts above.
    ///
    /// # Errors
    /// Redis cannot be reached in [`CONNECT_TIMEOUT`], or refuses.
    pub async fn connect(&self) -> RedisResult<MultiplexedConnection> {
        let config = AsyncConnectionConfig::new()
            .set_connection_timeout(Some(CONNECT_TIMEOUT))
            .set_response_timeout(Some(RESPONSE_TIMEOUT));
        let mut con = self.client.get_multiplexed_async_connection_with_config(&config).await?;
        let _: String = redis::cmd("PING").query_async(&mut con).await?; // answers, and has loaded its data
        Ok(con)
    }

    /// A connection subscribed to the world's channel (RESP3), its messages handed to `deliver`.
    async fn subscribe(&self, deliver: Deliver) -> RedisResult<MultiplexedConnection> {
        let config = AsyncConnectionConfig::new()
            .set_connection_timeout(Some(CONNECT_TIMEOUT))
            .set_response_timeout(Some(RESPONSE_TIMEOUT))
            .set_push_sender(deliver);
        let mut con = self.subscriber.get_multiplexed_async_connection_with_config(&config).await?;
        con.subscribe(&self.keys.channel).await?;
        Ok(con)
    }

    /// Connects for commands, again and again until Redis answers (backing off up to 400 ms).
    pub async fn reconnect(&self) -> MultiplexedConnection {
        let mut attempt = 0;
        loop {
            if let Ok(con) = self.connect().await {
                return con;
            }
            tokio::time::sleep(BACKOFF[attempt.min(BACKOFF.len() - 1)]).await;
            attempt += 1;
        }
    }

    /// Listens to the world's channel for good: subscribes, hands every message to `to` while
    /// `inbox` holds less than [`MAX_QUEUED_BYTES`] and `to` has room (else drops it, counted in
    /// `inbox`), as the connection reads it ([`Deliver`]: never waiting, and with no queue between,
    /// so neither Redis's buffer nor this process's grows whatever is published); checks the
    /// connection with a PING every [`PING_EVERY`], and on any failure says so and subscribes again
    /// (backing off up to 400 ms). Ends when `to` is closed.
    pub async fn listen(self, to: mpsc::Sender<Heard>, inbox: Inbox) {
        let mut attempt = 0;
        loop {
            let down = Arc::new(tokio::sync::Notify::new());
            let deliver = Deliver { to: to.clone(), inbox: inbox.clone(), down: Arc::clone(&down) };
            if let Ok(mut con) = self.subscribe(deliver).await {
                attempt = 0;
                if to.send(Heard::Up).await.is_err() {
                    return;
                }
                let mut ping = tokio::time::interval(PING_EVERY);
                ping.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
                loop {
                    tokio::select! {
                        () = down.notified() => break, // the connection closed
                        () = to.closed() => return,
                        _ = ping.tick() => {
                            let cmd = redis::cmd("PING");
                            let pong = tokio::time::timeout(RESPONSE_TIMEOUT, cmd.query_async::<Value>(&mut con)).await;
                            if !matches!(pong, Ok(Ok(_))) {
                                break;
                            }
                        }
                    }
                }
                drop(con);
                if to.send(Heard::Down).await.is_err() {
                    return;
                }
            }
            tokio::time::sleep(BACKOFF[attempt.min(BACKOFF.len() - 1)]).await;
            attempt += 1;
        }
    }
}

/// What the subscribed connection reads, handed on as it is read (on the connection's own task:
/// quick, and never waiting): a message to the world task if it is not too long and there is room,
/// else dropped and counted; the connection's end to [`Link::listen`].
struct Deliver {
    to: mpsc::Sender<Heard>,
    inbox: Inbox,
    down: Arc<tokio::sync::Notify>,
}

impl AsyncPushSender for Deliver {
    fn send(&self, info: PushInfo) -> Result<(), SendError> {
        match info.kind {
            PushKind::Message => {
                // [channel, payload]: the payload is moved, not copied.
                let Some(Value::BulkString(bytes)) = info.data.into_iter().nth(1) else { return Ok(()) };
                let len = bytes.len();
                // Checked before it is queued: the decoder checks again.
                let heard = if len > MAX_MESSAGE_BYTES {
                    Heard::TooLong(len)
                } else if self.inbox.reserve(len) {
                    Heard::Message(bytes)
                } else {
                    self.inbox.drop_one();
                    return Ok(());
                };
                let queued = if matches!(heard, Heard::Message(_)) { len } else { 0 };
                if self.to.try_send(heard).is_err() {
                    self.inbox.taken(queued);
                    self.inbox.drop_one();
                }
            }
            PushKind::Disconnection => self.down.notify_one(),
            _ => {}
        }
        Ok(())
    }
}

/// The bytes the subscribed connection holds for the world task, and the messages it dropped for
/// want of room ([`MAX_QUEUED_BYTES`]). Shared by the two.
#[derive(Clone, Debug, Default)]
pub struct Inbox {
    queued: Arc<AtomicUsize>,
    dropped: Arc<AtomicU64>,
}

impl Inbox {
    /// Room for `len` more bytes: reserved if there is.
    fn reserve(&self, len: usize) -> bool {
        self.queued
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |q| {
                (q + len <= MAX_QUEUED_BYTES).then_some(q + len)
            })
            .is_ok()
    }

    fn drop_one(&self) {
        self.dropped.fetch_add(1, Ordering::Relaxed);
    }

    /// A message of `len` bytes was taken (read by the world task, or dropped after all).
    pub fn taken(&self, len: usize) {
        self.queued.fetch_sub(len, Ordering::AcqRel);
    }

    /// Messages dropped so far.
    #[must_use]
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}

/// What the subscribed connection hears.
#[derive(Debug)]
pub enum Heard {
    /// Subscribed (again).
    Up,
    /// A message on the world's channel.
    Message(Vec<u8>),
    /// A message longer than [`MAX_MESSAGE_BYTES`] (dropped unread).
    TooLong(usize),
    /// The subscription is lost (Redis gone, or silent): reconnecting.
    Down,
}

/// The world's maze, claimed for `maze_hash` if nobody walks it, its TTL refreshed if it is
/// `maze_hash`; returns the world's maze hash (another one: this server must not join).
/// Whatever a writer left there, the answer is short: a value that is not a string, or its first
/// [`MAX_HASH_BYTES`] bytes.
const CLAIM_WORLD: &str = "local t = redis.call('TYPE', KEYS[1]).ok \
    if t == 'none' then redis.call('SET', KEYS[1], ARGV[1], 'EX', ARGV[2]) return ARGV[1] end \
    if t ~= 'string' then return '(a ' .. t .. ', not a maze hash)' end \
    local v = redis.call('GET', KEYS[1]) \
    if v == ARGV[1] then redis.call('EXPIRE', KEYS[1], ARGV[2]) end \
    return string.sub(v, 1, 128)";

/// The longest maze hash read back from the world's key (a SHA-256 in hex is 64).
const MAX_HASH_BYTES: usize = 128;

/// The value at `KEYS[1]` if it is a string of at most `ARGV[1]` bytes, `""` if it is anything
/// else (a writer's: the caller's decoder refuses it), nil if there is none. Redis answers no more
/// than the limit, whatever the key holds, and never a type error.
pub(crate) const GET_BOUNDED: &str = "local t = redis.call('TYPE', KEYS[1]).ok \
    if t == 'none' then return false end \
    if t ~= 'string' or redis.call('STRLEN', KEYS[1]) > tonumber(ARGV[1]) then return '' end \
    return redis.call('GET', KEYS[1])";

/// The first `ARGV[1]` (at least 1) bytes of the value at `KEYS[1]` if it is a string, `""` if it
/// is anything else, nil if there is none: a value read cut, never whole.
pub(crate) const GET_PREFIX: &str = "local t = redis.call('TYPE', KEYS[1]).ok \
    if t == 'none' then return false end \
    if t ~= 'string' then return '' end \
    return redis.call('GETRANGE', KEYS[1], 0, tonumber(ARGV[1]) - 1)";

/// SET NX GET, bounded as [`GET_BOUNDED`]: stores `ARGV[1]` at `KEYS[1]` if there is nothing
/// there (answering nil), else answers what is there.
const CLAIM_BOUNDED: &str = "local t = redis.call('TYPE', KEYS[1]).ok \
    if t == 'none' then redis.call('SET', KEYS[1], ARGV[1]) return false end \
    if t ~= 'string' or redis.call('STRLEN', KEYS[1]) > tonumber(ARGV[2]) then return '' end \
    return redis.call('GET', KEYS[1])";

/// The longest winner record read (a name is at most 16 bytes: far less).
const MAX_WINNER_BYTES: usize = 4096;

/// The world's maze hash as Redis answered it (bytes a writer may have chosen: made text here, and
/// shown clipped and escaped).
fn hash_text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(&bytes[..bytes.len().min(MAX_HASH_BYTES)]).into_owned()
}

/// Claims (or keeps) the world for the maze `maze_hash`; returns the world's maze hash.
///
/// # Errors
/// Redis failed.
pub async fn claim_world(
    con: &mut MultiplexedConnection,
    keys: &Keys,
    maze_hash: &str,
) -> RedisResult<String> {
    redis::cmd("EVAL")
        .arg(CLAIM_WORLD)
        .arg(1)
        .arg(&keys.world)
        .arg(maze_hash)
        .arg(WORLD_TTL_SECONDS)
        .query_async::<Vec<u8>>(con)
        .await
        .map(|bytes| hash_text(&bytes))
}

/// Publishes `message`; a full one also becomes the server's presence (with its TTL) and keeps the
/// world's maze claimed. One round trip. Returns the world's maze hash when it was checked.
///
/// # Errors
/// Redis failed.
pub async fn publish(
    con: &mut MultiplexedConnection,
    keys: &Keys,
    server: ServerId,
    message: &[u8],
    full: Option<&str>,
) -> RedisResult<Option<String>> {
    let mut pipe = redis::pipe();
    pipe.cmd("PUBLISH").arg(&keys.channel).arg(message).ignore();
    if let Some(maze_hash) = full {
        pipe.cmd("SET").arg(keys.server(server)).arg(message).arg("EX").arg(PRESENCE_TTL_SECONDS).ignore();
        pipe.cmd("EVAL").arg(CLAIM_WORLD).arg(1).arg(&keys.world).arg(maze_hash).arg(WORLD_TTL_SECONDS);
        let (world,): (Vec<u8>,) = pipe.query_async(con).await?;
        Ok(Some(hash_text(&world)))
    } else {
        pipe.query_async::<()>(con).await?;
        Ok(None)
    }
}

/// Claims the win for `record` (the encoded winner) unless someone has it: `None` if the claim is
/// this one's, else the winner's record as stored.
///
/// # Errors
/// Redis failed.
pub async fn claim_winner(
    con: &mut MultiplexedConnection,
    keys: &Keys,
    record: &[u8],
) -> RedisResult<Option<Vec<u8>>> {
    // SET NX GET (Redis 7), in a script that answers no more than MAX_WINNER_BYTES.
    redis::cmd("EVAL")
        .arg(CLAIM_BOUNDED)
        .arg(1)
        .arg(&keys.winner)
        .arg(record)
        .arg(MAX_WINNER_BYTES)
        .query_async(con)
        .await
}

/// The winner's record as stored, if any.
///
/// # Errors
/// Redis failed.
pub async fn winner(con: &mut MultiplexedConnection, keys: &Keys) -> RedisResult<Option<Vec<u8>>> {
    redis::cmd("EVAL").arg(GET_BOUNDED).arg(1).arg(&keys.winner).arg(MAX_WINNER_BYTES).query_async(con).await
}

/// Records a walk of `seconds` by `name`: kept if it is the player's best.
///
/// # Errors
/// Redis failed.
pub async fn record(
    con: &mut MultiplexedConnection,
    keys: &Keys,
    name: &str,
    seconds: f64,
) -> RedisResult<()> {
    redis::cmd("ZADD")
        .arg(&keys.best)
        .arg("LT")
        .arg(seconds)
        .arg(name)
        .query_async::<i64>(con)
        .await
        .map(drop)
}

/// The `n` best times, best first: (name, seconds); what Redis holds there that is not a player's
/// name and a time is left out ([`best_times`]).
///
/// # Errors
/// Redis failed.
pub async fn best(con: &mut MultiplexedConnection, keys: &Keys, n: usize) -> RedisResult<Vec<(String, f64)>> {
    let (rows, _) = best_times(con, keys, n).await?;
    Ok(rows.into_iter().map(|row| (row.name, row.seconds)).collect())
}

/// One of the world's best times, as [`best_times`] reads it.
#[derive(Clone, Debug, PartialEq)]
pub struct BestTime {
    /// The player's name (as [`player_name`] makes it).
    pub name: String,
    /// The time, seconds (finite, not negative).
    pub seconds: f64,
    /// When it was made, as `:at` holds it: at most [`MAX_AT_BYTES`] bytes, empty if there is
    /// none or it is longer.
    pub at: Vec<u8>,
}

/// The longest member of the best times read: a player's name is at most [`MAX_NAME`] ASCII
/// characters (bytes), so a longer member is none, and Redis does not send it.
pub const MAX_MEMBER_BYTES: usize = MAX_NAME;

/// The longest `:at` value read (Unix seconds: 20 bytes at most).
pub const MAX_AT_BYTES: usize = 32;

/// The first `ARGV[1]` entries of the sorted set `KEYS[1]`, best first, each with its value in
/// the hash `KEYS[2]`, as `{left out, {{member, score, at}, …}}`. Whatever a writer stored (members
/// and values of up to 512 MB), the answer is short: a member longer than `ARGV[2]` bytes is left
/// out and counted, an `at` longer than `ARGV[3]` bytes is `""` and counted (as is one in a
/// `KEYS[2]` that is no hash). Members are read one rank at a time, so the script holds one long
/// member at most.
const BEST_BOUNDED: &str = "local n, name_max, at_max = tonumber(ARGV[1]), tonumber(ARGV[2]), tonumber(ARGV[3]) \
    local hash = redis.call('TYPE', KEYS[2]).ok \
    local rows, left_out = {}, 0 \
    for i = 0, n - 1 do \
        local r = redis.call('ZRANGE', KEYS[1], i, i, 'WITHSCORES') \
        if #r == 0 then break end \
        if #r[1] > name_max then left_out = left_out + 1 else \
            local at = '' \
            if hash == 'hash' then \
                if redis.call('HSTRLEN', KEYS[2], r[1]) > at_max then left_out = left_out + 1 \
                else at = redis.call('HGET', KEYS[2], r[1]) or '' end \
            elseif hash ~= 'none' then left_out = left_out + 1 end \
            rows[#rows + 1] = {r[1], r[2], at} \
        end \
    end \
    return {left_out, rows}";

/// The `n` best times, best first, with how many entries of the first `n` were left out: a member
/// that is not a player's name (longer than [`MAX_MEMBER_BYTES`]: never sent by Redis; not UTF-8,
/// or not as [`player_name`] makes it), a score that is not a time, an `at` longer than
/// [`MAX_AT_BYTES`] (read as none). Redis's answer is at most `n` × ([`MAX_MEMBER_BYTES`] + a
/// score + [`MAX_AT_BYTES`]), whatever it holds.
///
/// # Errors
/// Redis failed (or the best times are not a sorted set).
pub async fn best_times(
    con: &mut MultiplexedConnection,
    keys: &Keys,
    n: usize,
) -> RedisResult<(Vec<BestTime>, usize)> {
    if n == 0 {
        return Ok((Vec::new(), 0));
    }
    // (member, score, at), as bytes: one member that is not UTF-8 must not fail the whole answer
    type Row = (Vec<u8>, Vec<u8>, Vec<u8>);
    let (left_out, rows): (usize, Vec<Row>) = redis::cmd("EVAL")
        .arg(BEST_BOUNDED)
        .arg(2)
        .arg(&keys.best)
        .arg(keys.best_at())
        .arg(n)
        .arg(MAX_MEMBER_BYTES)
        .arg(MAX_AT_BYTES)
        .query_async(con)
        .await?;
    let all = rows.len();
    let kept: Vec<BestTime> = rows
        .into_iter()
        .filter_map(|(name, score, at)| {
            let name = String::from_utf8(name).ok()?;
            let seconds: f64 = std::str::from_utf8(&score).ok()?.parse().ok()?;
            (player_name(&name) == name && seconds.is_finite() && seconds >= 0.0).then_some(BestTime {
                name,
                seconds,
                at,
            })
        })
        .collect();
    let left_out = left_out + (all - kept.len());
    Ok((kept, left_out))
}

/// The servers present, as [`presences`] reads them.
#[derive(Debug, Default)]
pub struct Presences {
    /// Their last full messages (at most the `max` asked for, each checked by the caller).
    pub messages: Vec<Vec<u8>>,
    /// Keys named as a server's presence left out: a value that is not a string of at most
    /// [`MAX_MESSAGE_BYTES`] (never sent by Redis).
    pub left_out: u64,
}

/// The servers present: their last full messages (at most `max` of them, each checked by the
/// caller), and how many keys named as a presence were left out. Each of Redis's answers is
/// bounded whatever it holds: a SCAN page of about [`SCAN_COUNT`] names, each a server's
/// ([`server_pattern`]: Redis sends no other name under the prefix, whatever its length), then
/// `max` values of at most [`MAX_MESSAGE_BYTES`].
///
/// # Errors
/// Redis failed.
pub async fn presences(con: &mut MultiplexedConnection, keys: &Keys, max: usize) -> RedisResult<Presences> {
    let pattern = server_pattern(&keys.servers);
    let mut names: Vec<Vec<u8>> = Vec::new();
    let mut cursor: u64 = 0;
    for _ in 0..MAX_SCANS {
        let (next, batch): (u64, Vec<Vec<u8>>) = redis::cmd("SCAN")
            .arg(cursor)
            .arg("MATCH")
            .arg(&pattern)
            .arg("COUNT")
            .arg(SCAN_COUNT)
            .query_async(con)
            .await?;
        names.extend(batch);
        cursor = next;
        if cursor == 0 || names.len() >= max {
            break;
        }
    }
    names.truncate(max);
    if names.is_empty() {
        return Ok(Presences::default());
    }
    let mut get = redis::cmd("EVAL");
    get.arg(GET_PRESENCES).arg(names.len()).arg(&names).arg(MAX_MESSAGE_BYTES);
    let (left_out, messages): (u64, Vec<Vec<u8>>) = get.query_async(con).await?;
    Ok(Presences { messages, left_out })
}

/// SCAN calls at most when reading the presence keys ([`SCAN_COUNT`] keys each: a million keys).
const MAX_SCANS: usize = 10_000;

/// The keys one SCAN call looks at, about.
const SCAN_COUNT: usize = 100;

/// The SCAN pattern of the presence keys under `prefix`: the prefix and 16 lowercase hex digits
/// ([`Keys::server`]), so that Redis matches each name inside and sends none of another length
/// (a writer's keys of 20 MB names under the prefix had made a read of 320 MB). Braces are not
/// special in a SCAN pattern; the prefix holds no other glob character. (Not a script that looks
/// at every name under the prefix to count the others: copying them into Lua took Redis 4.1 s
/// for 16 names of 20 MB, against 0.58 s to match them.)
fn server_pattern(prefix: &str) -> String {
    format!("{prefix}{}", "[0-9a-f]".repeat(16))
}

/// The values of `KEYS` that are strings of at most `ARGV[1]` bytes, as `{left out, {values}}`
/// (presence keys a writer set to anything else are counted, and Redis never answers more than the
/// keys × the limit).
const GET_PRESENCES: &str = "local out, left_out = {}, 0 \
    for _, k in ipairs(KEYS) do \
        local t = redis.call('TYPE', k).ok \
        if t == 'string' and redis.call('STRLEN', k) <= tonumber(ARGV[1]) then \
            out[#out + 1] = redis.call('GET', k) \
        elseif t ~= 'none' then \
            left_out = left_out + 1 \
        end \
    end \
    return {left_out, out}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passwords_are_left_out_of_messages() {
        assert_eq!(redacted("redis://u:secret@example.org:6380/2"), "redis://***@example.org:6380/2");
        assert_eq!(redacted("rediss://:p@h/"), "rediss://***@h/");
        assert_eq!(redacted("redis://h:6379"), "redis://h:6379");
        assert_eq!(redacted("redis://h/0?x=a@b"), "redis://h/0?x=a@b");
        assert_eq!(redacted("nonsense"), "nonsense");
    }

    /// A world's keys share one hash tag (one Cluster slot); its channel names the database.
    #[test]
    fn a_worlds_keys_share_a_hash_tag() {
        let keys = Keys::new("0123456789abcdef0123", 3);
        for key in [&keys.winner, &keys.best, &keys.channel, &keys.server(ServerId(255))] {
            assert!(key.contains("{0123456789abcdef}"), "{key}");
        }
        assert_eq!(keys.channel, "mazewalk:{0123456789abcdef}:3:news");
        assert_eq!(keys.server(ServerId(255)), "mazewalk:{0123456789abcdef}:server:00000000000000ff");
    }

    // issue #40: a hostile Redis's texts reach the host's terminal escaped.
    #[test]
    fn redis_texts_in_errors_are_escaped() {
        let source =
            RedisError::from((redis::ErrorKind::Io, "refused", "\x1b]0;owned\x07\x1b[2J".to_string()));
        let err = WorldError::Unreachable { url: "redis://h/".into(), source };
        let text = err.to_string();
        assert!(!text.contains('\x1b') && !text.contains('\x07'), "{text:?}");
        assert!(text.contains("\\u{1b}]0;owned"), "{text}");
        let err = WorldError::OtherMaze {
            url: "redis://h/".into(),
            url_db1: "redis://h/1".into(),
            world: format!("\u{202e}{}", "x".repeat(10_000)),
            ours: "abc".into(),
        };
        let text = err.to_string();
        assert!(!text.contains('\u{202e}') && text.len() < 1000, "{} bytes", text.len());
    }

    #[test]
    fn a_bad_url_is_told_without_its_password() {
        let err = Link::new("http://u:secret@h/", "abc", None).unwrap_err();
        let text = err.to_string();
        assert!(text.starts_with("--world http://***@h/:"), "{text}");
        assert!(!text.contains("secret"));
        let err = Link::new("redis://u:secret@h/", "abc", Some(b"pem")).unwrap_err();
        assert_eq!(err.to_string(), "--world-ca is for a world over TLS (rediss://…), not redis://***@h/");
    }
}
