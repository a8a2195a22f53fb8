//! What the tests and benches of every mazewalk crate share, in one copy: the proptest configuration
//! of every property, a tolerant comparison, the f64 OKLab oracle ([`oklab`]), the check that a
//! system program a test runs is installed ([`require_tool`]), the `redis-server` they start
//! ([`redis_server`]), the stock `ssh` client's options ([`ssh_args`]; in a pty of its own,
//! `ssh_in_pty`), the release server the measuring examples run ([`server_process`]) and, for the
//! async tests of the server and its world, `eventually` (a wait for a condition, with a deadline),
//! and the process's peak memory (`memory`, Linux).
//! A dev-dependency only.
//!
//! The harnesses that drive a mazewalk crate are behind a feature named after it (`term`, `walk`,
//! `pty`, `serve`, `redis`), so that the math crate's tests, say, build none of them. Only a crate's
//! integration tests and the benches use them: a crate's own unit tests would see a second copy of
//! its types.

use proptest::test_runner::{Config as ProptestConfig, FileFailurePersistence};

#[cfg(all(unix, feature = "pty"))]
pub mod asciinema;
#[cfg(feature = "term")]
pub mod baseline;
#[cfg(feature = "walk")]
pub mod link;
#[cfg(feature = "serve")]
pub mod load;
#[cfg(target_os = "linux")]
pub mod memory;
#[cfg(all(unix, feature = "pty"))]
pub mod pty_link;
#[cfg(feature = "serve")]
pub mod raw_ssh;
#[cfg(feature = "redis")]
pub mod redis_async;
pub mod redis_server;
pub mod scratch;
#[cfg(feature = "walk")]
pub mod screen;
pub mod server_process;
#[cfg(feature = "serve")]
pub mod world_host;

/// The configuration of every property: 1,000 cases ([`config_cases`] for the few that say why they
/// run fewer), or exactly `PROPTEST_CASES` when that is set (more for a long soak, fewer for a quick
/// look).
///
/// Failing seeds go to `proptest-regressions/<test file>.txt` in the crate being tested (a test runs
/// in its crate's directory): proptest's default persistence looks for a `lib.rs` beside the source,
/// which `tests/` lacks, so the file is named after the caller.
#[track_caller]
#[must_use]
pub fn config() -> ProptestConfig {
    config_cases(1000)
}

/// [`config`] with `cases` cases by default, for a property whose cases are expensive (each one
/// generates and validates whole mazes, say): its caller says why in a comment.
#[track_caller]
#[must_use]
pub fn config_cases(cases: u32) -> ProptestConfig {
    let caller = std::path::Path::new(std::panic::Location::caller().file());
    let name = caller.file_stem().and_then(|s| s.to_str()).unwrap_or("tests");
    // Leaked once per property run: `Direct` wants a `&'static str`.
    let path: &'static str = Box::leak(format!("proptest-regressions/{name}.txt").into_boxed_str());
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(cases);
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(path))),
        ..ProptestConfig::default()
    }
}

/// `a ≈ b` relative to `scale`: `|a - b| <= rel · max(scale, |a|, |b|)`. Pass the magnitude the
/// quantities were computed from (e.g. the eye's distance from the origin) as `scale`, because an
/// error of a few ULPs *of the inputs* is what cancellation leaves in a small result.
#[must_use]
pub fn close(a: f32, b: f32, rel: f32, scale: f32) -> bool {
    (a - b).abs() <= rel * scale.max(a.abs()).max(b.abs())
}

/// OKLab (L, a, b) of an 8-bit sRGB colour, in f64 with the library cube root (Björn Ottosson's
/// matrices, <https://bottosson.github.io/posts/oklab/>, at their published precision): the oracle
/// the tests hold the term crate's f32 transform (`mazewalk_term::frame::oklab`, with its fast cube
/// root) to.
#[must_use]
pub fn oklab([r, g, b]: [u8; 3]) -> [f64; 3] {
    let linear = |c: u8| {
        let v = f64::from(c) / 255.0;
        if v <= 0.040_45 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
    };
    let (r, g, b) = (linear(r), linear(g), linear(b));
    let l = (0.412_221_470_8 * r + 0.536_332_536_3 * g + 0.051_445_992_9 * b).cbrt();
    let m = (0.211_903_498_2 * r + 0.680_699_545_1 * g + 0.107_396_956_6 * b).cbrt();
    let s = (0.088_302_461_9 * r + 0.281_718_837_6 * g + 0.629_978_700_5 * b).cbrt();
    [
        0.210_454_255_3 * l + 0.793_617_785 * m - 0.004_072_046_8 * s,
        1.977_998_495_1 * l - 2.428_592_205 * m + 0.450_593_709_9 * s,
        0.025_904_037_1 * l + 0.782_771_766_2 * m - 0.808_675_766 * s,
    ]
}

/// The OKLab distance (ΔE_OK) between two 8-bit sRGB colours, by [`oklab`].
#[must_use]
pub fn oklab_distance(a: [u8; 3], b: [u8; 3]) -> f64 {
    let (p, q) = (oklab(a), oklab(b));
    (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()
}

/// The repository's `mazes/` folder, which every crate's tests read: the example mazes, and in
/// `mazes/cs559/` the original course files (see its README for where they come from).
pub const MAZES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../mazes");

/// The path of `name` in the repository's `mazes/` folder (`"cs559/maze-3x3-50.maze"`, `"tiny.grid"`).
#[must_use]
pub fn maze_path(name: &str) -> String {
    format!("{MAZES}/{name}")
}

/// Waits until `cond` holds, polling every 10 ms, and returns how long that took; panics, saying
/// `what`, when it has not held within `within`. For the async tests of the server and its world.
///
/// # Panics
/// When `cond` does not hold within `within`.
#[cfg(any(feature = "serve", feature = "redis"))]
pub async fn eventually(
    within: std::time::Duration,
    what: &str,
    mut cond: impl FnMut() -> bool,
) -> std::time::Duration {
    let start = std::time::Instant::now();
    loop {
        if cond() {
            return start.elapsed();
        }
        assert!(start.elapsed() < within, "{what}: not within {within:?}");
        tokio::time::sleep(std::time::Duration::from_millis(10)).await;
    }
}

/// A callback that takes lines of text (a records thread's report, say).
pub type Sink = std::sync::Arc<dyn Fn(&str) + Send + Sync>;

/// The lines a [`Sink`] was handed, in order.
pub type Said = std::sync::Arc<std::sync::Mutex<Vec<String>>>;

/// A [`Sink`] that keeps every line it is handed, and the lines it kept, for a test to read.
#[must_use]
pub fn collector() -> (Sink, Said) {
    let said = Said::default();
    let sink = std::sync::Arc::clone(&said);
    let report = std::sync::Arc::new(move |line: &str| {
        sink.lock().unwrap_or_else(std::sync::PoisonError::into_inner).push(line.to_string());
    });
    (report, said)
}

/// The stock OpenSSH client's arguments for `user` at the server on `127.0.0.1:port`, as every test
/// and example runs it: no config files, no known hosts, no prompts, only the given key (none:
/// `/dev/null`). Options such as `-tt` or `-b ADDR` go before them; a remote command after.
#[must_use]
pub fn ssh_args(port: u16, key: Option<&std::path::Path>, user: &str) -> Vec<String> {
    let mut args: Vec<String> = [
        "-F",
        "/dev/null",
        "-p",
        &port.to_string(),
        "-o",
        "StrictHostKeyChecking=no",
        "-o",
        "UserKnownHostsFile=/dev/null",
        "-o",
        "LogLevel=ERROR",
        "-o",
        "BatchMode=yes",
        "-o",
        "IdentitiesOnly=yes",
        "-o",
        "ConnectTimeout=10",
    ]
    .map(String::from)
    .into();
    let key = key.map_or_else(|| "/dev/null".to_string(), |key| key.display().to_string());
    args.extend(["-i".to_string(), key]);
    args.push(format!("{user}@127.0.0.1"));
    args
}

/// Stock `ssh -tt` ([`ssh_args`]; `-b BIND` when given) as `user` in a `cols × rows`
/// pseudo-terminal of its own, the leader of its session (`setsid -c`), with `TERM=xterm-256color`
/// and `env` set and sent to the server (`-o SendEnv=NAME` each): the client, and the terminal's
/// side of the pty to read its screen from and type into.
///
/// # Panics
/// `ssh` or `setsid` is not installed (the message names the package), or the pty cannot be made.
#[cfg(all(unix, feature = "pty"))]
#[must_use]
pub fn ssh_in_pty(
    bind: Option<&str>,
    port: u16,
    key: Option<&std::path::Path>,
    user: &str,
    (cols, rows): (u16, u16),
    env: &[(&str, &str)],
) -> (std::process::Child, std::fs::File) {
    use std::process::{Command, Stdio};
    require_tool("ssh", "openssh-client");
    require_tool("setsid", "util-linux");
    let size = rustix::termios::Winsize { ws_row: rows, ws_col: cols, ws_xpixel: 0, ws_ypixel: 0 };
    let pty = rustix_openpty::openpty(None, Some(&size)).expect("openpty");
    let slave = pty.user;
    let stdio = || Stdio::from(slave.try_clone().expect("dup the pty"));
    let child = Command::new("setsid")
        .args(["-c", "ssh", "-tt"])
        .args(bind.map(|bind| ["-b", bind]).into_iter().flatten())
        .args(env.iter().flat_map(|(name, _)| ["-o".to_string(), format!("SendEnv={name}")]))
        .args(ssh_args(port, key, user))
        .env("TERM", "xterm-256color")
        .envs(env.iter().copied())
        .stdin(stdio())
        .stdout(stdio())
        .stderr(stdio())
        .spawn()
        .expect("spawn setsid -c ssh");
    (child, std::fs::File::from(pty.controller))
}

/// What `scripts/test-all` says about itself, in every missing-tool message: it installs them all.
const INSTALL_ALL: &str = "scripts/test-all installs every tool the tests need";

/// Fails the calling test at once, in one line naming the Debian package to install, unless the
/// program `tool` is on `PATH`. Call it first in a test that runs a system program (`redis-server`,
/// `ssh`, `openssl`…), so a bare `cargo test` on a machine without it says what to install rather
/// than panicking deep in the test, and never passes by skipping.
///
/// # Panics
/// When `tool` is not on `PATH`.
#[track_caller]
pub fn require_tool(tool: &str, package: &str) {
    if find_on_path(tool).is_none() {
        panic!("this test runs `{tool}`, which is not installed: apt-get install {package} ({INSTALL_ALL})");
    }
}

/// [`require_tool`] for a Python 3 module (`paramiko`): `python3` must import it. Returns the
/// interpreter to run (`/usr/bin/python3` first, Debian's own, then `python3` on `PATH`).
///
/// # Panics
/// When no `python3` imports `module`.
#[track_caller]
#[must_use]
pub fn require_python_module(module: &str, package: &str) -> &'static str {
    ["/usr/bin/python3", "python3"]
        .into_iter()
        .find(|python| {
            std::process::Command::new(python)
                .args(["-c", &format!("import {module}")])
                .stdin(std::process::Stdio::null())
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .status()
                .is_ok_and(|status| status.success())
        })
        .unwrap_or_else(|| {
            panic!(
                "this test runs python3 with `{module}`, which is not installed: apt-get install \
                 {package} ({INSTALL_ALL})"
            )
        })
}

/// The first executable file named `tool` in the folders of `PATH` (or `tool` itself, when it is
/// a path).
fn find_on_path(tool: &str) -> Option<std::path::PathBuf> {
    let executable = |path: &std::path::Path| {
        std::fs::metadata(path).is_ok_and(|m| {
            #[cfg(unix)]
            let runnable = std::os::unix::fs::PermissionsExt::mode(&m.permissions()) & 0o111 != 0;
            #[cfg(not(unix))]
            let runnable = true;
            m.is_file() && runnable
        })
    };
    if tool.contains('/') {
        let path = std::path::PathBuf::from(tool);
        return executable(&path).then_some(path);
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path).map(|dir| dir.join(tool)).find(|candidate| executable(candidate))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tool_on_path_is_found_and_a_missing_one_named_with_its_package() {
        require_tool("sh", "dash"); // every Unix has it
        let missing = std::panic::catch_unwind(|| require_tool("mazewalk-no-such-tool", "some-package"));
        let message = *missing.expect_err("a missing tool fails").downcast::<String>().expect("a message");
        assert!(message.contains("`mazewalk-no-such-tool`"), "{message}");
        assert!(message.contains("apt-get install some-package"), "{message}");
        assert!(!message.contains('\n'), "one line: {message}");
    }

    #[test]
    fn a_missing_python_module_is_named_with_its_package() {
        let missing =
            std::panic::catch_unwind(|| require_python_module("mazewalk_no_such_module", "python3-no-such"));
        let message = *missing.expect_err("a missing module fails").downcast::<String>().expect("a message");
        assert!(message.contains("apt-get install python3-no-such"), "{message}");
    }
}
