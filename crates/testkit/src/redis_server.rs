//! A real `redis-server` (Debian's package) for a test: started on a free loopback port in a
//! directory of its own, stopped (SIGKILL) and started again on the same port and directory as a
//! fault needs, killed and its directory removed on drop. Never a mock. Over TLS, with a CA and a
//! certificate for 127.0.0.1 made by `openssl` for it, when asked.
//!
//! The one copy: the end-to-end tests at the root, `mazewalk-serve`'s tests (through a thin async
//! wrapper) and the benches' examples all start Redis here. Blocking, std only: readiness is Redis's
//! own "Ready to accept connections" log line (written after an append-only file is loaded back),
//! read from its stdout as it comes — an event, not a poll.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use crate::require_tool;

/// How long Redis may take to say it is ready.
const READY_WITHIN: Duration = Duration::from_secs(10);

/// How Redis keeps its data across a restart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Persistence {
    /// Not at all: a restart is empty (`--save "" --appendonly no`).
    None,
    /// Every write in the append-only file, synced at once (`--appendonly yes --appendfsync always`).
    AppendOnly,
}

/// One `redis-server` process.
#[derive(Debug)]
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
    /// Starts one and waits until it is ready.
    ///
    /// # Panics
    /// `redis-server` is not installed (the message names the package), or is not ready within 10 s.
    #[must_use]
    pub fn start(persistence: Persistence) -> RedisServer {
        RedisServer::start_with(persistence, false)
    }

    /// Starts one that speaks TLS only, with a certificate for 127.0.0.1 signed by a CA of its own
    /// ([`ca`](Self::ca)).
    ///
    /// # Panics
    /// As [`start`](Self::start), or `openssl` is missing.
    #[must_use]
    pub fn start_tls() -> RedisServer {
        RedisServer::start_with(Persistence::None, true)
    }

    fn start_with(persistence: Persistence, tls: bool) -> RedisServer {
        require_tool("redis-server", "redis-server");
        if tls {
            require_tool("openssl", "openssl");
        }
        let port = free_port();
        let dir = std::env::temp_dir().join(format!("mazewalk-redis-{}-{port}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a directory for redis-server");
        let ca = tls.then(|| make_certificates(&dir));
        let mut server = RedisServer { port, dir, persistence, ca, child: None };
        server.restart();
        server
    }

    /// The world's URL for database `db` (`redis://` or, over TLS, `rediss://`).
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

    /// The file of the CA's certificate of one that speaks TLS (for `mazewalk serve --world-ca`).
    #[must_use]
    pub fn ca_path(&self) -> Option<PathBuf> {
        self.ca.as_ref().map(|_| self.dir.join("ca.pem"))
    }

    /// Kills it (SIGKILL: no goodbye, no last save).
    pub fn stop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }

    /// Starts it again, on the same port and directory (the data as its persistence kept it), and
    /// waits until it is ready.
    ///
    /// # Panics
    /// As [`start`](Self::start).
    pub fn restart(&mut self) {
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
        // The log on stdout (`--logfile ""`), read below for the ready line.
        command.args(["--bind", "127.0.0.1", "--protected-mode", "no"]).arg("--dir").arg(&self.dir).args([
            "--logfile",
            "",
            "--daemonize",
            "no",
            "--save",
            "",
        ]);
        match self.persistence {
            Persistence::None => command.args(["--appendonly", "no"]),
            Persistence::AppendOnly => command.args(["--appendonly", "yes", "--appendfsync", "always"]),
        };
        let mut child = command
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|err| panic!("redis-server could not be started ({err})"));
        let stdout = child.stdout.take().expect("redis-server's stdout");
        self.child = Some(child);
        let (ready, said_ready) = mpsc::channel();
        // Reads the log to its end (so Redis never blocks on a full pipe), keeping the last lines to
        // show if it never gets ready.
        std::thread::spawn(move || {
            let mut last = Vec::new();
            for line in BufReader::new(stdout).lines() {
                let Ok(line) = line else { break };
                if line.contains("Ready to accept connections") {
                    let _ = ready.send(Ok(()));
                }
                last.push(line);
                if last.len() > 20 {
                    last.remove(0);
                }
            }
            let _ = ready.send(Err(last.join("\n")));
        });
        match said_ready.recv_timeout(READY_WITHIN) {
            Ok(Ok(())) => {}
            Ok(Err(log)) => panic!("redis-server on port {} ended before it was ready:\n{log}", self.port),
            Err(_) => panic!("redis-server on port {} was not ready within {READY_WITHIN:?}", self.port),
        }
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
fn make_certificates(dir: &Path) -> Vec<u8> {
    let openssl = |args: &[&str]| {
        let status = Command::new("openssl")
            .args(args)
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap_or_else(|err| panic!("openssl could not be run ({err})"));
        assert!(status.success(), "openssl {args:?}");
    };
    let ec = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"];
    let ca = ["-keyout", "ca.key", "-out", "ca.pem", "-days", "2", "-subj", "/CN=mazewalk test CA"];
    openssl(&[&["req", "-x509"][..], &ec, &ca].concat());
    let csr = ["-keyout", "redis.key", "-out", "redis.csr", "-subj", "/CN=127.0.0.1"];
    openssl(&[&["req"][..], &ec, &csr].concat());
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

/// A port free on 127.0.0.1 now (the test's own processes take it at once).
#[must_use]
pub fn free_port() -> u16 {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("a loopback port");
    listener.local_addr().expect("its address").port()
}
