//! A real `redis-server` (Debian's package) for a test: started on a free loopback port in a
//! directory of its own, stopped (SIGKILL) and started again on the same port and directory as a
//! fault needs, killed and its directory removed on drop. Never a mock. Over TLS, with a CA and a
//! certificate for 127.0.0.1 made by `openssl` for it, when asked.
#![allow(dead_code)] // each includer uses a part

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How Redis keeps its data across a restart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Persistence {
    /// Not at all: a restart is empty (`--save "" --appendonly no`).
    None,
    /// Every write in the append-only file, synced at once (`--appendonly yes --appendfsync always`).
    AppendOnly,
}

/// One `redis-server` process.
pub struct RedisServer {
    /// Its port on 127.0.0.1.
    pub port: u16,
    dir: PathBuf,
    persistence: Persistence,
    /// The CA's certificate (PEM), when it speaks TLS only.
    ca: Option<Vec<u8>>,
    child: Option<Child>,
}

impl RedisServer {
    /// Starts one and waits until it answers.
    ///
    /// # Panics
    /// `redis-server` is not installed (`.ci/run` installs it), or does not answer within 10 s.
    pub async fn start(persistence: Persistence) -> RedisServer {
        RedisServer::start_with(persistence, false).await
    }

    /// Starts one that speaks TLS only, with a certificate for 127.0.0.1 signed by a CA of its own
    /// ([`ca`](Self::ca)).
    ///
    /// # Panics
    /// As [`start`](Self::start), or `openssl` is missing.
    pub async fn start_tls() -> RedisServer {
        RedisServer::start_with(Persistence::None, true).await
    }

    async fn start_with(persistence: Persistence, tls: bool) -> RedisServer {
        let port = free_port();
        let dir = std::env::temp_dir().join(format!("mazewalk-redis-{}-{port}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a directory for redis-server");
        let ca = tls.then(|| make_certificates(&dir));
        let mut server = RedisServer { port, dir, persistence, ca, child: None };
        server.restart().await;
        server
    }

    /// The world's URL for database `db`.
    #[must_use]
    pub fn url(&self, db: u32) -> String {
        let scheme = if self.ca.is_some() { "rediss" } else { "redis" };
        format!("{scheme}://127.0.0.1:{}/{db}", self.port)
    }

    /// The CA's certificate (PEM) of one that speaks TLS.
    #[must_use]
    pub fn ca(&self) -> Option<Vec<u8>> {
        self.ca.clone()
    }

    fn client(&self, db: u32) -> redis::RedisResult<redis::Client> {
        match &self.ca {
            None => redis::Client::open(self.url(db)),
            Some(ca) => redis::Client::build_with_tls(
                self.url(db),
                redis::TlsCertificates { client_tls: None, root_cert: Some(ca.clone()) },
            ),
        }
    }

    /// Kills it (SIGKILL: no goodbye, no last save).
    pub fn stop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    /// Starts it again, on the same port and directory (the data as its persistence kept it), and
    /// waits until it answers.
    pub async fn restart(&mut self) {
        self.stop();
        let mut command = Command::new("redis-server");
        let port = self.port.to_string();
        if self.ca.is_some() {
            command.args(["--port", "0", "--tls-port", &port, "--tls-auth-clients", "no"]);
            for (option, file) in [
                ("--tls-cert-file", "redis.pem"),
                ("--tls-key-file", "redis.key"),
                ("--tls-ca-cert-file", "ca.pem"),
            ] {
                command.arg(option).arg(self.dir.join(file));
            }
        } else {
            command.args(["--port", &port]);
        }
        command.args(["--bind", "127.0.0.1", "--protected-mode", "no"]).arg("--dir").arg(&self.dir).args([
            "--logfile",
            "redis.log",
            "--daemonize",
            "no",
            "--save",
            "",
        ]);
        match self.persistence {
            Persistence::None => command.args(["--appendonly", "no"]),
            Persistence::AppendOnly => command.args(["--appendonly", "yes", "--appendfsync", "always"]),
        };
        let child = command.stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::null()).spawn();
        let child = child.unwrap_or_else(|err| {
            panic!(
                "redis-server could not be started ({err}): install Debian's redis-server (`.ci/run` does)"
            )
        });
        self.child = Some(child);
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            if self.ping().await {
                return;
            }
            assert!(
                Instant::now() < deadline,
                "redis-server on port {} did not answer within 10 s",
                self.port
            );
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    }

    async fn ping(&self) -> bool {
        let Ok(client) = self.client(0) else { return false };
        let Ok(Ok(mut con)) =
            tokio::time::timeout(Duration::from_secs(1), client.get_multiplexed_async_connection()).await
        else {
            return false;
        };
        // A restarted Redis answers LOADING until its data is read back.
        matches!(redis::cmd("PING").query_async::<String>(&mut con).await, Ok(pong) if pong == "PONG")
    }

    /// A plain connection to database `db`, for a test's own commands.
    pub async fn connection(&self, db: u32) -> redis::aio::MultiplexedConnection {
        let client = self.client(db).expect("a Redis URL");
        client.get_multiplexed_async_connection().await.expect("Redis answers")
    }
}

impl Drop for RedisServer {
    fn drop(&mut self) {
        self.stop();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A CA, and a certificate for 127.0.0.1 it signed, made by `openssl` in `dir` (`ca.pem`,
/// `redis.pem`, `redis.key`); returns the CA's certificate.
fn make_certificates(dir: &std::path::Path) -> Vec<u8> {
    let openssl = |args: &[&str]| {
        let status = Command::new("openssl")
            .args(args)
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap_or_else(|err| panic!("openssl could not be run ({err}): install it (`.ci/run` does)"));
        assert!(status.success(), "openssl {args:?}");
    };
    let ec = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"];
    openssl(
        &[
            &["req", "-x509"][..],
            &ec,
            &["-keyout", "ca.key", "-out", "ca.pem", "-days", "2", "-subj", "/CN=mazewalk test CA"],
        ]
        .concat(),
    );
    openssl(
        &[&["req"][..], &ec, &["-keyout", "redis.key", "-out", "redis.csr", "-subj", "/CN=127.0.0.1"]]
            .concat(),
    );
    std::fs::write(dir.join("ext.cnf"), "subjectAltName=IP:127.0.0.1\nbasicConstraints=CA:FALSE\n")
        .expect("ext.cnf");
    openssl(&[
        "x509",
        "-req",
        "-in",
        "redis.csr",
        "-CA",
        "ca.pem",
        "-CAkey",
        "ca.key",
        "-CAcreateserial",
        "-out",
        "redis.pem",
        "-days",
        "2",
        "-extfile",
        "ext.cnf",
    ]);
    std::fs::read(dir.join("ca.pem")).expect("ca.pem")
}

/// A port free on 127.0.0.1 now.
fn free_port() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("a loopback port");
    listener.local_addr().expect("its address").port()
}
