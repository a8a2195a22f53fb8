//! What the tests of every mazewalk crate share: the proptest configuration of every property and a
//! tolerant comparison. A dev-dependency only; it depends on no mazewalk crate (so a crate's tests and
//! its library never see two copies of one type).

use proptest::test_runner::{Config as ProptestConfig, FileFailurePersistence};

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

/// The repository's `mazes/` folder, which every crate's tests read: the example mazes, and in
/// `mazes/cs559/` the original course files (see its README for where they come from).
pub const MAZES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../mazes");

/// The path of `name` in the repository's `mazes/` folder (`"cs559/maze-3x3-50.maze"`, `"tiny.grid"`).
#[must_use]
pub fn maze_path(name: &str) -> String {
    format!("{MAZES}/{name}")
}
