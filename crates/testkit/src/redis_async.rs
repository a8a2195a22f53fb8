//! The tests' `redis-server` ([`redis_server`](crate::redis_server), the one copy) for async tests
//! and benches: the blocking start and restart on tokio's blocking threads, so that a test's runtime
//! keeps running the server under test meanwhile, and a `redis` client of the test's own.

pub use crate::redis_server::Persistence;
use crate::redis_server::RedisServer as Blocking;

/// One `redis-server` process.
pub struct RedisServer {
    /// Its port on 127.0.0.1.
    pub port: u16,
    inner: Option<Blocking>,
}

impl RedisServer {
    /// Starts one and waits until it is ready.
    ///
    /// # Panics
    /// `redis-server` is not installed (the message names the package), or is not ready within 10 s.
    pub async fn start(persistence: Persistence) -> RedisServer {
        RedisServer::from(tokio::task::spawn_blocking(move || Blocking::start(persistence)).await)
    }

    /// Starts one that speaks TLS only, with a certificate for 127.0.0.1 signed by a CA of its own
    /// ([`ca`](Self::ca)).
    ///
    /// # Panics
    /// As [`start`](Self::start), or `openssl` is missing.
    pub async fn start_tls() -> RedisServer {
        RedisServer::from(tokio::task::spawn_blocking(Blocking::start_tls).await)
    }

    fn from(started: Result<Blocking, tokio::task::JoinError>) -> RedisServer {
        let inner = started.unwrap_or_else(|err| std::panic::resume_unwind(err.into_panic()));
        RedisServer { port: inner.port, inner: Some(inner) }
    }

    fn inner(&self) -> &Blocking {
        self.inner.as_ref().expect("a redis-server")
    }

    /// The world's URL for database `db`.
    #[must_use]
    pub fn url(&self, db: u32) -> String {
        self.inner().url(db)
    }

    /// The CA's certificate (PEM) of one that speaks TLS.
    #[must_use]
    pub fn ca(&self) -> Option<Vec<u8>> {
        self.inner().ca()
    }

    fn client(&self, db: u32) -> redis::RedisResult<redis::Client> {
        match self.ca() {
            None => redis::Client::open(self.url(db)),
            Some(ca) => redis::Client::build_with_tls(
                self.url(db),
                redis::TlsCertificates { client_tls: None, root_cert: Some(ca) },
            ),
        }
    }

    /// Kills it (SIGKILL: no goodbye, no last save).
    pub fn stop(&mut self) {
        if let Some(inner) = &mut self.inner {
            inner.stop();
        }
    }

    /// Starts it again, on the same port and directory (the data as its persistence kept it), and
    /// waits until it is ready.
    pub async fn restart(&mut self) {
        let mut inner = self.inner.take().expect("a redis-server");
        let restarted = tokio::task::spawn_blocking(move || {
            inner.restart();
            inner
        })
        .await;
        *self = RedisServer::from(restarted);
    }

    /// A plain connection to database `db`, for a test's own commands.
    pub async fn connection(&self, db: u32) -> redis::aio::MultiplexedConnection {
        let client = self.client(db).expect("a Redis URL");
        client.get_multiplexed_async_connection().await.expect("Redis answers")
    }
}

/// Redis's own count of calls of `command` (lower case, e.g. `set`) so far (`INFO commandstats`):
/// 0 for a command not yet called.
///
/// # Errors
/// Redis does not answer `INFO`.
pub async fn command_calls(
    con: &mut redis::aio::MultiplexedConnection,
    command: &str,
) -> redis::RedisResult<u64> {
    let info: String = redis::cmd("INFO").arg("commandstats").query_async(con).await?;
    let prefix = format!("cmdstat_{command}:calls=");
    Ok(info
        .lines()
        .find_map(|l| l.strip_prefix(&prefix))
        .and_then(|rest| rest.split(',').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or(0))
}

/// The bytes Redis has sent its clients so far (`INFO stats`, `total_net_output_bytes`): what a
/// server under test read from it, between two calls (and the first call's own answer, about
/// 2 KB).
///
/// # Errors
/// Redis does not answer `INFO`.
pub async fn net_output_bytes(con: &mut redis::aio::MultiplexedConnection) -> redis::RedisResult<u64> {
    let info: String = redis::cmd("INFO").arg("stats").query_async(con).await?;
    Ok(info
        .lines()
        .find_map(|l| l.strip_prefix("total_net_output_bytes:"))
        .and_then(|n| n.trim().parse().ok())
        .unwrap_or(0))
}
