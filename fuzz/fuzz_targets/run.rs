//! Issue #43: a run (a ghost's data) from a file, the records database or Redis is untrusted input.
//! Feeds arbitrary bytes to `mazewalk_walk::run::Run::decode`. Asserts: no panic, no hang, no
//! allocation beyond the input's worth; a run that decodes is within the format's limits, encodes
//! back to the same bytes (one encoding per run), says a pose at any time, and checks against the
//! built-in maze without panicking.

#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use mazewalk_maze::{ContentHash, Maze};
use mazewalk_walk::run::{MAX_BYTES, MAX_NAME, MAX_SAMPLES, Run};

/// The built-in maze and its hash (made once: the maze is not what is fuzzed here).
fn maze() -> &'static (Maze, ContentHash) {
    static MAZE: OnceLock<(Maze, ContentHash)> = OnceLock::new();
    MAZE.get_or_init(|| {
        let maze = mazewalk_maze::builtin().expect("built-in maze");
        let hash = maze.content_hash();
        (maze, hash)
    })
}

fuzz_target!(|bytes: &[u8]| {
    let Ok(run) = Run::decode(bytes) else { return };
    assert!(bytes.len() <= MAX_BYTES);
    assert!(run.samples.len() <= MAX_SAMPLES && run.holder.len() <= MAX_NAME);
    assert!(run.samples.iter().all(|s| s.position.is_finite() && (0.0..360.0).contains(&s.yaw_deg)));
    assert_eq!(run.encode().as_deref(), Ok(bytes), "a round trip");
    for t in [-1.0, 0.0, 0.05, run.seconds() / 2.0, run.seconds(), 1e9, f64::NAN] {
        let pose = run.pose_at(t).expect("a run has samples");
        assert!(pose.position.is_finite() && pose.pitch_deg.abs() <= 90.0, "{pose:?} at {t}");
    }
    let (maze, hash) = maze();
    let _ = run.check_maze(*hash, maze.extents());
});
