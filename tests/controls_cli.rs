//! The speed and step flags of the walk (issue #14): values outside their documented ranges are usage
//! errors (exit 2) before any terminal is touched; good ones get as far as needing a terminal (exit 1
//! here, where stdin is not one).

use std::process::{Command, Output, Stdio};

fn mazewalk(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mazewalk"))
        .args(args)
        .stdin(Stdio::null())
        .env("TERM", "xterm-256color")
        .output()
        .expect("run mazewalk")
}

#[test]
fn speeds_and_steps_outside_their_ranges_are_usage_errors() {
    for args in [
        ["--turn-speed", "5"],
        ["--turn-speed", "721"],
        ["--walk-speed", "0"],
        ["--walk-speed", "nan"],
        ["--walk-speed=-3", ""],
        ["--turn-step", "91"],
        ["--turn-step", "inf"],
        ["--walk-step", "4.5"],
    ] {
        let args: Vec<&str> = args.into_iter().filter(|a| !a.is_empty()).collect();
        let out = mazewalk(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(args[0].split('=').next().unwrap()), "{args:?}: {stderr}");
    }
}

#[test]
fn speeds_and_steps_inside_their_ranges_are_accepted() {
    let out =
        mazewalk(&["--turn-speed", "720", "--walk-speed", "0.5", "--turn-step", "90", "--walk-step", "0.25"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("needs a terminal"), "{stderr}");
}
