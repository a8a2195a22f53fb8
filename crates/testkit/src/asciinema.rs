//! The real `asciinema cat FILE`, for the tests that check a recording prints as it was written
//! (`tests/e2e_tui.rs` for the walk's `--record`, `tests/serve_record_e2e.rs` for `serve
//! --record-dir`).

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use rustix::termios::Winsize;

use crate::pty_link::own_session_on_stdin;

/// How long `asciinema cat` may take before the test fails.
pub const TIMEOUT: Duration = Duration::from_secs(10);

/// What `asciinema cat path` prints, run with a 100 × 30 pty of its own as its controlling terminal
/// (it opens /dev/tty); `None`, said loudly on stderr, where asciinema is not installed.
///
/// # Panics
/// When it cannot start for another reason, does not exit within [`TIMEOUT`] (killed), or exits
/// non-zero (with what it said on stderr).
#[must_use]
pub fn cat(path: &Path) -> Option<Vec<u8>> {
    let size = Winsize { ws_row: 30, ws_col: 100, ws_xpixel: 0, ws_ypixel: 0 };
    let pty = rustix_openpty::openpty(None, Some(&size)).expect("openpty");
    let mut command = Command::new("asciinema");
    command
        .arg("cat")
        .arg(path)
        .stdin(Stdio::from(pty.user.try_clone().expect("dup the pty")))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    own_session_on_stdin(&mut command);
    let mut child = match command.spawn() {
        Ok(child) => child,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            eprintln!("SKIPPED: `asciinema cat` (asciinema is not installed; Debian package `asciinema`)");
            return None;
        }
        Err(e) => panic!("cannot start asciinema: {e}"),
    };
    drop(command);
    drop(pty.user);
    let mut stdout = child.stdout.take().expect("stdout");
    let mut stderr = child.stderr.take().expect("stderr");
    let out = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        stdout.read_to_end(&mut bytes).map(|_| bytes)
    });
    let err = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = stderr.read_to_end(&mut bytes);
        bytes
    });
    let deadline = Instant::now() + TIMEOUT;
    let status = loop {
        if let Some(status) = child.try_wait().expect("try_wait") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("asciinema cat did not exit within {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    drop(pty.controller);
    let printed = out.join().expect("the stdout reader").expect("read asciinema's output");
    let err = err.join().expect("the stderr reader");
    assert!(status.success(), "asciinema cat: {status:?}: {}", String::from_utf8_lossy(&err));
    Some(printed)
}
