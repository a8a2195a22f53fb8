//! The slow link in real time (issue #33), short: the real binary in a pty behind a 125,000 B/s link
//! with 50 ms each way ([`pty_link`]), ← held for 1.5 s at 120×40 in truecolor, and two of the far
//! terminal's answers lost on the way back. Flow control used to count every frame whose answer was
//! lost as still on its way: two lost answers stalled the walk for the whole 2 s reply timeout, and
//! the far screen went on turning for 1.3–1.5 s after the key was let go. Now a lost answer is given
//! up after a couple of round trips. The full measurement, with and without lost answers and against
//! another binary, is `benches/examples/slow_link_pty.rs` (BENCHMARKS.md).
#![cfg(unix)]

use std::path::Path;

use mazewalk_testkit::pty_link::{Hold, Link, measure};

#[test]
fn the_picture_stops_soon_after_the_key_even_when_answers_are_lost() {
    let link = Link { bytes_per_s: 125_000.0, one_way: 0.050, lost_answers: &[0.6, 1.0] };
    let hold = Hold { key: b"\x1b[D", hold: 1.5, repeat_delay: 0.5, repeat_every: 1.0 / 33.0 };
    let env = [("TERM", "xterm-256color"), ("LANG", "C.UTF-8")];
    let binary = Path::new(env!("CARGO_BIN_EXE_mazewalk"));
    let outcome = measure(binary, &["--color", "truecolor"], &env, 120, 40, link, hold);
    assert!(outcome.degrees_turned() > 90.0, "it turned: {outcome:?}");
    // 0.3 s here on a quiet machine; the stall this guards against took 1.3 s and more. Generous for a
    // loaded one: the walk in a test build, the link and the emulator all run on the same cores.
    assert!(outcome.tail() < 0.9, "still turning {:.2} s after the release: {outcome:?}", outcome.tail());
    assert!(outcome.last_gap() < 0.9, "the last change waited {:.2} s: {outcome:?}", outcome.last_gap());
}
