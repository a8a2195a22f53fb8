//! The best times of a shared world (`--world`), kept in Redis behind the records' [`Store`]: every
//! server of the world writes there, so the exit box ranks a player among every server's players.
//!
//! ```text
//! mazewalk:{H}:best               best time, seconds, by player name (sorted set; ZADD LT: only better)
//! mazewalk:{H}:best:at            when each best was made, Unix seconds, by player name (hash;
//!                                 none for a best only the world task kept, Redis being away
//!                                 from the records: read as 0)
//! mazewalk:{H}:finishes           finishes in all (a counter)
//! mazewalk:{H}:name               what the first server to keep a finish called the maze
//! mazewalk:{H}:runs               the run of each of the best TOP players' bests, by player name
//!                                 (hash; each at most MAX_BYTES, mazewalk_walk::run's format)
//! ```
//!
//! The store runs on the records thread ([`Records`](crate::records::Records)), never on the async
//! workers: it has a runtime of its own, one thread, that only its calls drive. A Redis that does not
//! answer fails the finish at hand ([`Fault::Unreachable`], transient: the next one tries again),
//! within the link's timeouts. What Redis says is untrusted and read as bytes: a name that is not a
//! player name (not UTF-8 either) or a time that is not a time is left out of the table and counted
//! ([`RedisStore::left_out`], said once in the log); a `:at` that is not a number reads as 0, and a
//! `:finishes` that is no count is left as it is (counted too) and read as 0.
//!
//! Every answer is bounded by the request, whatever a writer stored (values of up to 512 MB): the
//! reads are Lua scripts that send no member or `:runs` field longer than a player's name, no `:at`
//! or `:finishes` longer than a number, no run longer than [`MAX_BYTES`], and the first
//! [`MAX_MAZE_NAME_BYTES`] of the name; what they leave out is counted as above (red-team pass 8:
//! 10 members of 40 MB made a server read 400 MB at each read of the best times).

use std::path::PathBuf;

use mazewalk_maze::ContentHash;
use redis::RedisResult;
use redis::aio::MultiplexedConnection;

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use super::redis::{GET_BOUNDED, GET_PREFIX, Keys, Link, MAX_MEMBER_BYTES, WorldError, best_times};
use crate::records::{Best, Fault, Finish, MazeRecords, RecordsError, Standing, Store, StoredRun, TOP};
use mazewalk_walk::run::MAX_BYTES;

/// The best times of one world in its Redis.
pub struct RedisStore {
    link: Link,
    runtime: tokio::runtime::Runtime,
    con: Option<MultiplexedConnection>,
    maze: ContentHash,
    /// Entries of the best times left out so far: not a player's name and a time.
    left_out: Arc<AtomicU64>,
    /// Whether the log has said so.
    said_left_out: bool,
}

impl std::fmt::Debug for RedisStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RedisStore").field("url", &self.link.url).finish_non_exhaustive()
    }
}

/// The keys of the records beside the world's own.
struct RecordKeys {
    /// The world's own.
    world: Keys,
    best: String,
    at: String,
    finishes: String,
    name: String,
    runs: String,
    /// Where [`top`] and the others count the entries they leave out.
    left_out: Arc<AtomicU64>,
}

impl RecordKeys {
    fn of(keys: &Keys, left_out: &Arc<AtomicU64>) -> RecordKeys {
        let tag = keys.best.strip_suffix(":best").unwrap_or(&keys.best);
        RecordKeys {
            world: keys.clone(),
            best: keys.best.clone(),
            at: keys.best_at(),
            finishes: format!("{tag}:finishes"),
            name: format!("{tag}:name"),
            runs: format!("{tag}:runs"),
            left_out: Arc::clone(left_out),
        }
    }
}

impl RedisStore {
    /// The records of the world at `url` (with `ca` for a `rediss://` Redis of its own CA) for the maze
    /// `maze`. Connects to nothing yet: the first finish does.
    ///
    /// # Errors
    /// The URL is not a Redis URL, or `ca` is given without TLS; or the runtime cannot start.
    pub fn new(url: &str, ca: Option<&[u8]>, maze: ContentHash) -> Result<RedisStore, WorldError> {
        let link = Link::new(url, &maze.to_string(), ca)?;
        let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().map_err(|e| {
            WorldError::Unreachable { url: link.url.clone(), source: redis::RedisError::from(e) }
        })?;
        Ok(RedisStore { link, runtime, con: None, maze, left_out: Arc::default(), said_left_out: false })
    }

    /// Entries of the world's best times left out so far (each time they were read): a member that
    /// is not a player's name (or not UTF-8), a score that is not a time.
    #[must_use]
    pub fn left_out(&self) -> u64 {
        self.left_out.load(Ordering::Relaxed)
    }

    fn error(&self, err: &redis::RedisError) -> RecordsError {
        let fault = if err.is_io_error() || err.is_timeout() || err.is_connection_dropped() {
            Fault::Unreachable
        } else {
            Fault::Other
        };
        let detail = crate::logs::clip(&err.to_string(), crate::logs::ERROR_CHARS);
        RecordsError { path: PathBuf::from(&self.link.url), fault, detail }
    }

    /// Runs `f` on a connection (made if there is none; dropped on a failure, to be made again).
    fn with<T>(
        &mut self,
        f: impl AsyncFnOnce(&mut MultiplexedConnection, &RecordKeys) -> RedisResult<T>,
    ) -> Result<T, RecordsError> {
        let keys = RecordKeys::of(&self.link.keys, &self.left_out);
        let (link, con) = (&self.link, &mut self.con);
        let result = self.runtime.block_on(async {
            let result = async {
                if con.is_none() {
                    *con = Some(link.connect().await?);
                }
                let Some(c) = con.as_mut() else { unreachable!("made above") };
                f(c, &keys).await
            }
            .await;
            if result.is_err() {
                // The connection's task (and whatever it had read of a failed reply) ends when this
                // runtime next runs it: now, not at the next finish, which may be an hour away.
                *con = None;
                tokio::task::yield_now().await;
            }
            result
        });
        if !self.said_left_out && self.left_out() > 0 {
            self.said_left_out = true;
            tracing::warn!(
                "records: {}: the world's best times hold entries that are not a player's name and a time; \
                 they are left out (said once)",
                self.link.url
            );
        }
        result.map_err(|err| {
            self.con = None;
            self.error(&err)
        })
    }

    /// [`with`](Self::with) for a read, asked once more on a new connection where the one it had
    /// failed as unreachable: a connection left idle across a Redis restart fails its first command
    /// ("broken pipe"), which said nothing about the Redis now there.
    fn read<T>(
        &mut self,
        f: impl AsyncFn(&mut MultiplexedConnection, &RecordKeys) -> RedisResult<T>,
    ) -> Result<T, RecordsError> {
        let had = self.con.is_some();
        match self.with(&f) {
            Err(err) if had && err.fault == Fault::Unreachable => self.with(&f),
            result => result,
        }
    }
}

/// The best `TOP` of the sorted set at `keys`, best first, with when each was made; entries Redis
/// holds that are not a player's name and a time are left out and counted ([`best_times`]: Redis
/// never sends a member longer than a name, nor a `:at` longer than a date).
async fn top(con: &mut MultiplexedConnection, keys: &RecordKeys) -> RedisResult<Vec<Best>> {
    let (rows, left_out) = best_times(con, &keys.world, TOP).await?;
    keys.left_out.fetch_add(left_out as u64, Ordering::Relaxed);
    Ok(rows
        .into_iter()
        .map(|row| Best { player: row.name, seconds: row.seconds, at: unix_seconds(&row.at) })
        .collect())
}

/// Deletes the fields of the hash `KEYS[1]` that are not among `ARGV[2..]`, and answers how many
/// of them were longer than `ARGV[1]` bytes (no player's name: a writer's, counted). Nothing of
/// what the hash holds is sent.
const KEEP_RUNS: &str = "local keep = {} \
    for i = 2, #ARGV do keep[ARGV[i]] = true end \
    local junk = 0 \
    for _, f in ipairs(redis.call('HKEYS', KEYS[1])) do \
        if not keep[f] then \
            redis.call('HDEL', KEYS[1], f) \
            if #f > tonumber(ARGV[1]) then junk = junk + 1 end \
        end \
    end \
    return junk";

/// The first of the fields `ARGV[2..]` of the hash `KEYS[1]` whose value is 1 to `ARGV[1]` bytes
/// long, as `{its place among them (from 0), the value, how many before it were longer}`, or
/// `{-1, '', how many were longer}` if none is: a longer value is never sent. One script, so the
/// length checked is the length read.
const RUN_BOUNDED: &str = "local max, longer = tonumber(ARGV[1]), 0 \
    for i = 2, #ARGV do \
        local n = redis.call('HSTRLEN', KEYS[1], ARGV[i]) \
        if n >= 1 and n <= max then return {i - 2, redis.call('HGET', KEYS[1], ARGV[i]), longer} end \
        if n > max then longer = longer + 1 end \
    end \
    return {-1, '', longer}";

/// The longest count of finishes read (a count in decimal is 20 bytes at most).
const MAX_COUNT_BYTES: usize = 32;

/// The characters of the maze's name shown.
const MAX_MAZE_NAME_CHARS: usize = 256;

/// The bytes of the maze's name read: enough for [`MAX_MAZE_NAME_CHARS`] characters of UTF-8.
const MAX_MAZE_NAME_BYTES: usize = 4 * MAX_MAZE_NAME_CHARS;

/// A `:at` value as Redis holds it: Unix seconds, or 0 for anything else (an entry written by
/// another program, garbage).
fn unix_seconds(bytes: &[u8]) -> i64 {
    std::str::from_utf8(bytes).ok().and_then(|s| s.trim().parse().ok()).unwrap_or(0)
}

impl Store for RedisStore {
    fn record(&mut self, finish: &Finish) -> Result<Standing, RecordsError> {
        let finish = finish.clone();
        self.with(async move |con, keys| {
            let (improved, _): (i64, Option<String>) = redis::pipe()
                .atomic()
                .cmd("ZADD")
                .arg(&keys.best)
                .arg("LT")
                .arg("CH")
                .arg(finish.seconds)
                .arg(&finish.player)
                .cmd("SET")
                .arg(&keys.name)
                .arg(&finish.maze_name)
                .arg("NX")
                .query_async(con)
                .await?;
            // The count of finishes is only shown: a value there that is no count (another
            // program's, garbage) is left as it is and counted, not a failed finish.
            if let Err(err) = redis::cmd("INCR").arg(&keys.finishes).query_async::<i64>(con).await {
                if err.is_io_error() || err.is_timeout() || err.is_connection_dropped() {
                    return Err(err);
                }
                keys.left_out.fetch_add(1, Ordering::Relaxed);
            }
            let (best, players): (Option<f64>, i64) = redis::pipe()
                .cmd("ZSCORE")
                .arg(&keys.best)
                .arg(&finish.player)
                .cmd("ZCARD")
                .arg(&keys.best)
                .query_async(con)
                .await?;
            let best = best.filter(|b| b.is_finite()).unwrap_or(finish.seconds);
            // When the best was made: this finish, if it is the best (the world task may have put
            // its time in the set first: ZADD then said nothing changed).
            if improved > 0 || best == finish.seconds {
                redis::cmd("HSET")
                    .arg(&keys.at)
                    .arg(&finish.player)
                    .arg(finish.at)
                    .query_async::<i64>(con)
                    .await?;
            }

            let ahead: i64 = redis::cmd("ZCOUNT")
                .arg(&keys.best)
                .arg("-inf")
                .arg(format!("({best}"))
                .query_async(con)
                .await?;
            let top = top(con, keys).await?;
            let players = usize::try_from(players).unwrap_or(0).max(1);
            let rank = usize::try_from(ahead).unwrap_or(0).saturating_add(1).min(players);
            // The run of a best among the best TOP is kept; the runs of those no longer there go.
            if let Some(run) = finish.run.as_ref().filter(|r| r.len() <= MAX_BYTES)
                && best == finish.seconds
                && rank <= TOP
            {
                let held: usize = redis::cmd("HLEN").arg(&keys.runs).query_async(con).await?;
                if held > 2 * TOP {
                    // (more than this server ever leaves: whatever else wrote there goes, unread)
                    redis::cmd("DEL").arg(&keys.runs).query_async::<i64>(con).await?;
                } else if held > 0 {
                    // (in Redis: a field that is not a player's goes too, unread whatever its size)
                    let mut keep = redis::cmd("EVAL");
                    keep.arg(KEEP_RUNS).arg(1).arg(&keys.runs).arg(MAX_MEMBER_BYTES);
                    for b in &top {
                        keep.arg(&b.player);
                    }
                    let junk: u64 = keep.query_async(con).await?;
                    keys.left_out.fetch_add(junk, Ordering::Relaxed);
                }
                redis::cmd("HSET")
                    .arg(&keys.runs)
                    .arg(&finish.player)
                    .arg(run)
                    .query_async::<i64>(con)
                    .await?;
            }
            Ok(Standing { top, best, rank, players })
        })
    }

    fn run(&mut self, maze: &ContentHash, player: Option<&str>) -> Result<Option<StoredRun>, RecordsError> {
        if *maze != self.maze {
            return Ok(None); // one world, one maze
        }
        let player = player.map(str::to_owned);
        self.read(async |con, keys| {
            // whose: the named player's, or the best player's with a run
            let top = top(con, keys).await?;
            let wanted: Vec<&Best> =
                top.iter().filter(|b| player.as_ref().is_none_or(|p| *p == b.player)).collect();
            if wanted.is_empty() {
                return Ok(None);
            }
            // the first kept whose run is of a run's size (Redis may hold anything, of any size)
            let mut first = redis::cmd("EVAL");
            first.arg(RUN_BOUNDED).arg(1).arg(&keys.runs).arg(MAX_BYTES);
            for b in &wanted {
                first.arg(&b.player);
            }
            let (place, bytes, longer): (i64, Vec<u8>, u64) = first.query_async(con).await?;
            keys.left_out.fetch_add(longer, Ordering::Relaxed);
            let Some(best) = usize::try_from(place).ok().and_then(|i| wanted.get(i)) else {
                return Ok(None);
            };
            Ok(Some(StoredRun { player: best.player.clone(), seconds: best.seconds, bytes }))
        })
    }

    fn mazes(&mut self, maze: Option<&ContentHash>) -> Result<Vec<MazeRecords>, RecordsError> {
        if maze.is_some_and(|m| *m != self.maze) {
            return Ok(Vec::new()); // one world, one maze
        }
        let hash = self.maze.to_string();
        self.read(async |con, keys| {
            // (both bounded in Redis: a count longer than a count reads as none, a name is cut)
            let (players, finishes, name): (i64, Option<Vec<u8>>, Option<Vec<u8>>) = redis::pipe()
                .cmd("ZCARD")
                .arg(&keys.best)
                .cmd("EVAL")
                .arg(GET_BOUNDED)
                .arg(1)
                .arg(&keys.finishes)
                .arg(MAX_COUNT_BYTES)
                .cmd("EVAL")
                .arg(GET_PREFIX)
                .arg(1)
                .arg(&keys.name)
                .arg(MAX_MAZE_NAME_BYTES)
                .query_async(con)
                .await?;
            if players == 0 {
                return Ok(Vec::new());
            }
            if finishes.as_ref().is_some_and(Vec::is_empty) {
                keys.left_out.fetch_add(1, Ordering::Relaxed); // (not a string, or longer than a count)
            }
            let top = top(con, keys).await?;
            let name: String = String::from_utf8_lossy(&name.unwrap_or_default())
                .chars()
                .filter(|c| !c.is_control())
                .take(MAX_MAZE_NAME_CHARS)
                .collect();
            let finishes = finishes.as_deref().map_or(0, unix_seconds); // (a count, read as leniently)
            Ok(vec![MazeRecords {
                maze: hash.clone(),
                name,
                players: usize::try_from(players).unwrap_or(0),
                finishes: usize::try_from(finishes).unwrap_or(0),
                top,
            }])
        })
    }
}
