//! `contrib/mazewalk.service`, the systemd unit a host copies: its command line runs as written (the
//! binary, %S made a scratch folder, the two ports made free ones), makes the host key and the records
//! in its state folder, and stops on SIGTERM within `TimeoutStopSec=` with an exit status the unit
//! counts as clean (`SuccessExitStatus=`). `systemd-analyze verify` accepts it when systemd-analyze is
//! on PATH (with ExecStart pointing at the built binary, which it checks exists).
#![cfg(unix)]

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use rustix::process::{Pid, Signal};

const UNIT: &str = include_str!("../contrib/mazewalk.service");
const INSTALLED: &str = "/usr/local/bin/mazewalk";

/// The value of `key=` in the unit (continued lines joined; the last one when repeated).
fn setting(key: &str) -> String {
    let joined = UNIT.replace("\\\n", " ");
    joined
        .lines()
        .rev()
        .find_map(|l| l.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no {key}= in the unit"))
        .to_string()
}

#[test]
fn the_units_command_serves_keeps_its_state_and_stops_cleanly_in_time() {
    let scratch = std::env::temp_dir().join(format!("mazewalk-unit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(scratch.join("mazewalk")).expect("the state folder");
    let state = scratch.to_str().expect("a UTF-8 path");
    let exec = setting("ExecStart");
    let mut words: Vec<String> = exec.split_whitespace().map(|w| w.replace("%S", state)).collect();
    assert_eq!(words[0], INSTALLED);
    for flag in ["--listen", "--http"] {
        let at = words.iter().position(|w| w == flag).unwrap_or_else(|| panic!("{flag} in ExecStart"));
        words[at + 1] = "127.0.0.1:0".into(); // (free ports: the test may run beside a real one)
    }
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(&words[1..])
        .env_clear() // as systemd starts it: no HOME, no XDG folders
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("start the unit's command");
    let stdout = BufReader::new(child.stdout.take().expect("stdout"));
    let lines: Vec<String> =
        stdout.lines().map_while(Result::ok).take_while(|l| !l.starts_with("metrics at")).collect();
    assert!(lines.iter().any(|l| l.starts_with("mazewalk: serving on")), "{lines:?}");
    assert!(Path::new(state).join("mazewalk/host_ed25519_key").is_file(), "the host key in the state folder");
    // The records database is opened at start.
    assert!(Path::new(state).join("mazewalk/records.sqlite").is_file(), "the records in the state folder");

    let stop = Instant::now();
    rustix::process::kill_process(Pid::from_child(&child), Signal::TERM).expect("SIGTERM");
    let timeout: u64 = setting("TimeoutStopSec").parse().expect("TimeoutStopSec in seconds");
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        assert!(stop.elapsed() < Duration::from_secs(timeout), "still running after TimeoutStopSec");
        std::thread::sleep(Duration::from_millis(20));
    };
    let code = status.code().expect("an exit code, not a signal");
    let clean: Vec<i32> =
        setting("SuccessExitStatus").split_whitespace().map(|c| c.parse().expect("a code")).collect();
    assert!(code == 0 || clean.contains(&code), "exit {code}, not clean for the unit ({clean:?})");
    eprintln!("started and stopped in {:?}", started.elapsed());

    if let Ok(out) = Command::new("systemd-analyze").arg("--version").output() {
        if out.status.success() {
            let unit = scratch.join("mazewalk.service");
            std::fs::write(&unit, UNIT.replace(INSTALLED, env!("CARGO_BIN_EXE_mazewalk"))).expect("a copy");
            let verify = Command::new("systemd-analyze").arg("verify").arg(&unit).output().expect("verify");
            assert!(
                verify.status.success() && verify.stderr.is_empty(),
                "systemd-analyze verify: {}",
                String::from_utf8_lossy(&verify.stderr)
            );
        }
    } else {
        eprintln!("systemd-analyze not on PATH: the unit was not verified");
    }
    let _ = std::fs::remove_dir_all(&scratch);
}
