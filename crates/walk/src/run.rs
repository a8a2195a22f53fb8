//! A walk's run: where the viewer stood and looked over time, from the start to the exit — what a
//! ghost replays (`mazewalk --ghost FILE`, a served maze's best run) and `mazewalk replay` plays back.
//! Pure: a [`Recorder`] fed poses with the walk's own clock, a [`Run`] that says where its viewer was
//! at any time ([`Run::pose_at`]), and its binary form ([`Run::encode`], [`Run::decode`]).
//!
//! # The format, version 1
//!
//! Integers are LEB128 varints (signed ones zigzag-coded first); nothing is padded.
//!
//! ```text
//! "MZRUN" 0x01                        magic and version
//! 32 bytes                            the maze's content hash (Maze::content_hash)
//! u8 rate                             samples per second: RATE (10)
//! varint millis                       the finish time, ms: 1..=MAX_SECONDS × 1000
//! u8 length, ASCII                   the holder's name: ≤ MAX_NAME printable ASCII characters, no
//!                                     space (it is drawn on screens: no escape, no wide or bidi text)
//! varint count                        samples: millis / 100 + 1 (one at every tenth of a second,
//!                                     from 0 to the finish); so at most MAX_SAMPLES
//! x, y, yaw, pitch                    the first sample: zigzag x, y in 1/256 maze units; yaw in
//!                                     1/16° (0..5760); zigzag pitch in 1/16° (±90°)
//! dx, dy, dyaw, dpitch  × (count − 1)  each next sample from the one before, zigzag (dyaw the short
//!                                     way round, in −180°..180°: a half turn is −180°)
//! ```
//!
//! **Limits.** A run is at most [`MAX_SECONDS`] long (ten minutes: a longer walk keeps no run), its
//! positions within ±65,536 maze units ([`POSITION_LIMIT`]), and
//! its encoding at most [`MAX_BYTES`] (64 KiB; at a walk's top speeds a sample takes at most 8 bytes,
//! so a ten-minute run fits in about 48 KB). A run read from a file, a database or Redis is
//! untrusted: [`Run::decode`] checks the length before anything, the count against the finish time
//! and the bytes left before allocating, every value's range, and that nothing trails;
//! [`Run::check_maze`] that it belongs to the maze and stays inside it. Times are monotonic by
//! construction (a sample per tenth of a second). Every fault is a [`RunError`], never a panic.

use glam::Vec2;
#[cfg(doc)]
use mazewalk_maze::Maze;
use mazewalk_maze::{Aabb, ContentHash};

/// Samples per second.
pub const RATE: u32 = 10;
/// The longest run kept, seconds: a walk that takes longer keeps none.
pub const MAX_SECONDS: u32 = 600;
/// The most samples a run has (one per tenth of a second over [`MAX_SECONDS`], both ends counted).
pub const MAX_SAMPLES: usize = (MAX_SECONDS * RATE) as usize + 1;
/// The longest encoding read or written, bytes.
pub const MAX_BYTES: usize = 64 * 1024;
/// The longest holder's name, bytes of UTF-8.
pub const MAX_NAME: usize = 32;

const MAGIC: &[u8; 6] = b"MZRUN\x01";
/// Fixed-point steps per maze unit (positions) and per degree (angles).
const POSITION_STEPS: f32 = 256.0;
const ANGLE_STEPS: f32 = 16.0;
const FULL_TURN: i64 = 360 * 16;
const PITCH_MAX: i64 = 90 * 16;
/// The fewest bytes a sample after the first takes (four one-byte varints).
const MIN_SAMPLE_BYTES: usize = 4;
/// Milliseconds between samples.
const STEP_MS: u32 = 1000 / RATE;

/// Where the viewer stood and looked at one time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    /// Where (maze plane).
    pub position: Vec2,
    /// Heading, degrees counter-clockwise from +x, in 0..360.
    pub yaw_deg: f32,
    /// Pitch, degrees, ±90.
    pub pitch_deg: f32,
}

impl Pose {
    /// The pose as the format keeps it: each value rounded to its fixed-point step.
    #[must_use]
    pub fn quantized(self) -> Pose {
        let (x, y, yaw, pitch) = self.fixed();
        Pose::from_fixed(x, y, yaw, pitch)
    }

    /// Fixed point: x, y in 1/256 units, yaw in 1/16° (0..5760), pitch in 1/16° (±1440). Values out
    /// of range saturate (a NaN is 0).
    fn fixed(self) -> (i64, i64, i64, i64) {
        let steps = |v: f32, per: f32| i64::from((v * per).round() as i32);
        let yaw = steps(self.yaw_deg, ANGLE_STEPS).rem_euclid(FULL_TURN);
        let pitch = steps(self.pitch_deg, ANGLE_STEPS).clamp(-PITCH_MAX, PITCH_MAX);
        (steps(self.position.x, POSITION_STEPS), steps(self.position.y, POSITION_STEPS), yaw, pitch)
    }

    fn from_fixed(x: i64, y: i64, yaw: i64, pitch: i64) -> Pose {
        Pose {
            position: Vec2::new(x as f32 / POSITION_STEPS, y as f32 / POSITION_STEPS),
            yaw_deg: yaw as f32 / ANGLE_STEPS,
            pitch_deg: pitch as f32 / ANGLE_STEPS,
        }
    }
}

/// One finished walk through a maze: who, how long, and a [`Pose`] every tenth of a second.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// The maze walked ([`Maze::content_hash`]).
    pub maze: ContentHash,
    /// Who walked it (a served player's name; empty when nobody said).
    pub holder: String,
    /// The finish time, whole milliseconds (1..=[`MAX_SECONDS`] × 1000).
    pub millis: u32,
    /// The pose at 0, 0.1, 0.2 … seconds: `millis / 100 + 1` of them.
    pub samples: Vec<Pose>,
}

/// What is wrong with a run's bytes, or with a run for a maze.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RunError {
    /// Longer than [`MAX_BYTES`].
    #[error("a run of {0} bytes is longer than the {MAX_BYTES} allowed")]
    TooLarge(usize),
    /// Not a run file (the magic is missing).
    #[error("not a mazewalk run (no MZRUN header)")]
    NotARun,
    /// A version this mazewalk does not read.
    #[error("run format version {0} is not one this mazewalk reads (1)")]
    Version(u8),
    /// The bytes end inside a field.
    #[error("the run ends early, in its {0}")]
    Truncated(&'static str),
    /// A field's value is out of its range.
    #[error("the run's {0} is out of range")]
    OutOfRange(&'static str),
    /// The holder's name is not short printable ASCII.
    #[error("the run's holder name is not at most {MAX_NAME} printable ASCII characters")]
    BadName,
    /// Bytes after the last sample.
    #[error("{0} bytes after the run's end")]
    Trailing(usize),
    /// Longer than [`MAX_SECONDS`] (or no time at all).
    #[error("a run must take between 0.001 and {MAX_SECONDS} seconds")]
    Duration,
    /// The run is of another maze.
    #[error("the run is of another maze (hash {run}, this one is {maze})")]
    OtherMaze {
        /// The run's maze.
        run: ContentHash,
        /// The maze at hand.
        maze: ContentHash,
    },
    /// A sample stands outside the maze's extents.
    #[error("the run's sample {0} stands outside the maze")]
    OutsideMaze(usize),
}

/// Appends `v` as a LEB128 varint.
fn put_varint(out: &mut Vec<u8>, mut v: u64) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

fn zigzag(v: i64) -> u64 {
    ((v << 1) ^ (v >> 63)) as u64
}

fn unzigzag(v: u64) -> i64 {
    (v >> 1) as i64 ^ -((v & 1) as i64)
}

/// A cursor over untrusted bytes.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &'static str) -> Result<&'a [u8], RunError> {
        if self.bytes.len() < n {
            return Err(RunError::Truncated(what));
        }
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Ok(head)
    }

    /// A varint of at most 10 bytes whose value fits in 64 bits, in its shortest form (one encoding
    /// per run).
    fn varint(&mut self, what: &'static str) -> Result<u64, RunError> {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let [b] = self.take(1, what)?.try_into().map_err(|_| RunError::Truncated(what))?;
            let bits = u64::from(b & 0x7f);
            if shift == 63 && bits > 1 {
                return Err(RunError::OutOfRange(what));
            }
            v |= bits << shift;
            if b & 0x80 == 0 {
                if b == 0 && shift > 0 {
                    return Err(RunError::OutOfRange(what)); // an overlong form
                }
                return Ok(v);
            }
        }
        Err(RunError::OutOfRange(what))
    }

    /// A zigzag varint within ±`limit`.
    fn signed(&mut self, what: &'static str, limit: i64) -> Result<i64, RunError> {
        let v = unzigzag(self.varint(what)?);
        if v.unsigned_abs() > limit.unsigned_abs() {
            return Err(RunError::OutOfRange(what));
        }
        Ok(v)
    }
}

/// The samples a run of `millis` has.
fn sample_count(millis: u32) -> usize {
    (millis / STEP_MS) as usize + 1
}

/// Whether a holder's name is one the format keeps.
fn good_name(name: &str) -> bool {
    name.len() <= MAX_NAME && name.bytes().all(|b| b.is_ascii_graphic())
}

/// The largest fixed-point position, in 1/256 steps: ±2^24 of them, ±65,536 maze units (a generated
/// 1000 × 1000 maze spans 4000), where an `f32` still holds every step exactly, so that a decoded run
/// encodes back to its bytes. A walk outside keeps no run.
pub const POSITION_LIMIT: i64 = 1 << 24;

impl Run {
    /// The finish time, seconds.
    #[must_use]
    pub fn seconds(&self) -> f64 {
        f64::from(self.millis) / 1000.0
    }

    /// Where the run's viewer was `t` seconds after its start: between samples, the straight line
    /// from one to the next (the heading the short way round); before the start, the first sample;
    /// after the finish, the last. `None` for a run without samples.
    #[must_use]
    pub fn pose_at(&self, t: f64) -> Option<Pose> {
        let last = self.samples.len().checked_sub(1)?;
        let at = (t.max(0.0) * f64::from(RATE)).min(last as f64);
        let i = at.floor() as usize;
        let (a, b) = (self.samples[i], self.samples[(i + 1).min(last)]);
        let f = (at - i as f64) as f32;
        let turn = (b.yaw_deg - a.yaw_deg + 180.0).rem_euclid(360.0) - 180.0;
        Some(Pose {
            position: a.position.lerp(b.position, f),
            yaw_deg: (a.yaw_deg + turn * f).rem_euclid(360.0),
            pitch_deg: a.pitch_deg + (b.pitch_deg - a.pitch_deg) * f,
        })
    }

    /// The run in the format above.
    ///
    /// # Errors
    /// [`RunError::Duration`] for a run longer than [`MAX_SECONDS`] or of no time,
    /// [`RunError::OutOfRange`] when the samples are not `millis / 100 + 1` or a position is beyond
    /// the format's range, [`RunError::BadName`] for a holder's name the format does not keep,
    /// [`RunError::TooLarge`] past [`MAX_BYTES`].
    pub fn encode(&self) -> Result<Vec<u8>, RunError> {
        if self.millis == 0 || self.millis > MAX_SECONDS * 1000 {
            return Err(RunError::Duration);
        }
        if self.samples.len() != sample_count(self.millis) {
            return Err(RunError::OutOfRange("sample count"));
        }
        if !good_name(&self.holder) {
            return Err(RunError::BadName);
        }
        let mut out = Vec::with_capacity(64 + self.samples.len() * 5);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&self.maze.0);
        out.push(RATE as u8);
        put_varint(&mut out, u64::from(self.millis));
        out.push(self.holder.len() as u8);
        out.extend_from_slice(self.holder.as_bytes());
        put_varint(&mut out, self.samples.len() as u64);
        let mut before = (0, 0, 0, 0);
        for (k, pose) in self.samples.iter().enumerate() {
            let (x, y, yaw, pitch) = pose.fixed();
            if x.abs() > POSITION_LIMIT || y.abs() > POSITION_LIMIT {
                return Err(RunError::OutOfRange("position"));
            }
            if k == 0 {
                put_varint(&mut out, zigzag(x));
                put_varint(&mut out, zigzag(y));
                put_varint(&mut out, yaw as u64);
                put_varint(&mut out, zigzag(pitch));
            } else {
                let turn = (yaw - before.2 + FULL_TURN / 2).rem_euclid(FULL_TURN) - FULL_TURN / 2;
                put_varint(&mut out, zigzag(x - before.0));
                put_varint(&mut out, zigzag(y - before.1));
                put_varint(&mut out, zigzag(turn));
                put_varint(&mut out, zigzag(pitch - before.3));
            }
            before = (x, y, yaw, pitch);
            if out.len() > MAX_BYTES {
                return Err(RunError::TooLarge(out.len()));
            }
        }
        Ok(out)
    }

    /// Reads a run from untrusted bytes (see the module's doc for what is checked).
    ///
    /// # Errors
    /// A [`RunError`] naming the first fault found.
    pub fn decode(bytes: &[u8]) -> Result<Run, RunError> {
        if bytes.len() > MAX_BYTES {
            return Err(RunError::TooLarge(bytes.len()));
        }
        let mut r = Reader { bytes };
        let magic = r.take(MAGIC.len(), "header").map_err(|_| RunError::NotARun)?;
        if magic[..5] != MAGIC[..5] {
            return Err(RunError::NotARun);
        }
        if magic[5] != MAGIC[5] {
            return Err(RunError::Version(magic[5]));
        }
        let maze =
            ContentHash(r.take(32, "maze hash")?.try_into().map_err(|_| RunError::Truncated("maze hash"))?);
        if r.take(1, "rate")? != [RATE as u8] {
            return Err(RunError::OutOfRange("rate"));
        }
        let millis = r.varint("finish time")?;
        if millis == 0 || millis > u64::from(MAX_SECONDS) * 1000 {
            return Err(RunError::Duration);
        }
        let millis = millis as u32;
        let length = usize::from(r.take(1, "holder name")?[0]);
        if length > MAX_NAME {
            return Err(RunError::BadName);
        }
        let holder = std::str::from_utf8(r.take(length, "holder name")?).map_err(|_| RunError::BadName)?;
        if !good_name(holder) {
            return Err(RunError::BadName);
        }
        let count = r.varint("sample count")?;
        if count != sample_count(millis) as u64 {
            return Err(RunError::OutOfRange("sample count"));
        }
        let count = count as usize; // ≤ MAX_SAMPLES: the finish time was checked
        if r.bytes.len() < count * MIN_SAMPLE_BYTES {
            return Err(RunError::Truncated("samples"));
        }
        let mut samples = Vec::with_capacity(count);
        let mut at = (0, 0, 0, 0);
        for k in 0..count {
            if k == 0 {
                at.0 = r.signed("position", POSITION_LIMIT)?;
                at.1 = r.signed("position", POSITION_LIMIT)?;
                let yaw = r.varint("heading")?;
                if yaw >= FULL_TURN as u64 {
                    return Err(RunError::OutOfRange("heading"));
                }
                at.2 = yaw as i64;
                at.3 = r.signed("pitch", PITCH_MAX)?;
            } else {
                let dx = r.signed("position", 2 * POSITION_LIMIT)?;
                let dy = r.signed("position", 2 * POSITION_LIMIT)?;
                let turn = r.signed("heading", FULL_TURN / 2)?;
                if turn == FULL_TURN / 2 {
                    return Err(RunError::OutOfRange("heading")); // a half turn is written −180° (one form)
                }
                let dpitch = r.signed("pitch", 2 * PITCH_MAX)?;
                at.0 += dx;
                at.1 += dy;
                at.2 = (at.2 + turn).rem_euclid(FULL_TURN);
                at.3 += dpitch;
                if at.0.abs() > POSITION_LIMIT || at.1.abs() > POSITION_LIMIT {
                    return Err(RunError::OutOfRange("position"));
                }
                if at.3.abs() > PITCH_MAX {
                    return Err(RunError::OutOfRange("pitch"));
                }
            }
            samples.push(Pose::from_fixed(at.0, at.1, at.2, at.3));
        }
        if !r.bytes.is_empty() {
            return Err(RunError::Trailing(r.bytes.len()));
        }
        Ok(Run { maze, holder: holder.to_string(), millis, samples })
    }

    /// Whether the run belongs to the maze of hash `hash` (its [`Maze::content_hash`], which the
    /// caller computes once) and every sample stands within its `extents` ([`Maze::extents`]).
    ///
    /// # Errors
    /// [`RunError::OtherMaze`], or [`RunError::OutsideMaze`] with the first sample outside.
    pub fn check_maze(&self, hash: ContentHash, extents: Aabb) -> Result<(), RunError> {
        if self.maze != hash {
            return Err(RunError::OtherMaze { run: self.maze, maze: hash });
        }
        // (a position is rounded to 1/256: within one step of the extents is inside)
        let extents = extents.expand(1.0 / POSITION_STEPS);
        let inside = |p: Vec2| extents.min.cmple(p).all() && p.cmple(extents.max).all();
        match self.samples.iter().position(|s| !inside(s.position)) {
            Some(k) => Err(RunError::OutsideMaze(k)),
            None => Ok(()),
        }
    }
}

/// Keeps a walk's poses as it goes, one per tenth of a second of the walk's clock, until the finish
/// or [`MAX_SECONDS`] (past which it keeps nothing more, and the walk has no run). Between two poses
/// it is told, the viewer stood still (a walk moves only when told a key or a tick), so a gap is
/// filled with the pose before.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recorder {
    samples: Vec<Pose>,
    /// Past [`MAX_SECONDS`]: nothing is kept.
    over: bool,
}

impl Recorder {
    /// Starts again from nothing (the walk was reset).
    pub fn restart(&mut self) {
        self.samples.clear();
        self.over = false;
    }

    /// The viewer's pose `t` seconds into the walk. The first pose told counts from 0; a pose for a
    /// tenth of a second already kept is dropped (the first one there is nearest its time).
    pub fn note(&mut self, t: f64, pose: Pose) {
        if self.over || !t.is_finite() {
            return;
        }
        let slot = (t.max(0.0) * f64::from(RATE)).floor();
        if slot >= MAX_SAMPLES as f64 {
            self.over = true;
            self.samples = Vec::new();
            return;
        }
        let slot = slot as usize;
        let pose = pose.quantized();
        let held = self.samples.last().copied().unwrap_or(pose);
        while self.samples.len() < slot {
            self.samples.push(held);
        }
        if self.samples.len() == slot {
            self.samples.push(pose);
        }
    }

    /// The run of a walk that finished `seconds` in, standing at `last`: `None` when it took longer
    /// than [`MAX_SECONDS`] (or no time) or a name is not one the format keeps.
    #[must_use]
    pub fn finish(&self, maze: ContentHash, holder: &str, seconds: f64, last: Pose) -> Option<Run> {
        let millis = (seconds * 1000.0).round();
        if self.over || !(1.0..=f64::from(MAX_SECONDS) * 1000.0).contains(&millis) || !good_name(holder) {
            return None;
        }
        let millis = millis as u32;
        let count = sample_count(millis);
        let mut samples = self.samples.clone();
        let held = samples.last().copied().unwrap_or(last.quantized());
        samples.resize(count, held);
        samples[count - 1] = last.quantized(); // the finish itself: at the exit
        Some(Run { maze, holder: holder.to_string(), millis, samples })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x: f32, y: f32, yaw: f32) -> Pose {
        Pose { position: Vec2::new(x, y), yaw_deg: yaw, pitch_deg: 0.0 }
    }

    fn walk_east(seconds: f64) -> Run {
        let mut rec = Recorder::default();
        let mut t = 0.0;
        while t < seconds {
            rec.note(t, pose(2.0 + 5.0 * t as f32, 6.0, 0.0));
            t += 1.0 / 60.0;
        }
        rec.finish(ContentHash([7; 32]), "ada", seconds, pose(2.0 + 5.0 * seconds as f32, 6.0, 0.0)).unwrap()
    }

    #[test]
    fn a_run_round_trips_and_is_small() {
        let run = walk_east(12.34);
        assert_eq!(run.samples.len(), 124);
        let bytes = run.encode().unwrap();
        assert!(bytes.len() < 80 + 124 * 5, "{} bytes", bytes.len());
        assert_eq!(Run::decode(&bytes), Ok(run));
    }

    #[test]
    fn a_ten_minute_run_at_top_speeds_fits_the_cap() {
        // the worst a walk can do: top walking speed (40 units/s) zigzagging, turning and looking
        // as fast as the keys go, every sample different
        let samples: Vec<Pose> = (0..MAX_SAMPLES)
            .map(|k| {
                let s = if k % 2 == 0 { 1.0 } else { -1.0 };
                Pose {
                    position: Vec2::new(2000.0 + s * 2.0, 2000.0 - s * 2.0),
                    yaw_deg: (k as f32 * 72.0).rem_euclid(360.0),
                    pitch_deg: s * 7.0,
                }
            })
            .collect();
        let run = Run { maze: ContentHash([1; 32]), holder: "x".repeat(MAX_NAME), millis: 600_000, samples };
        let bytes = run.encode().unwrap();
        assert!(bytes.len() <= MAX_BYTES, "{} bytes", bytes.len());
        assert_eq!(Run::decode(&bytes).unwrap().samples.len(), MAX_SAMPLES);
    }

    #[test]
    fn a_walk_past_ten_minutes_keeps_no_run() {
        let mut rec = Recorder::default();
        rec.note(0.0, pose(1.0, 1.0, 0.0));
        rec.note(f64::from(MAX_SECONDS) + 0.2, pose(2.0, 1.0, 0.0));
        assert_eq!(rec.finish(ContentHash([0; 32]), "", 601.0, pose(2.0, 1.0, 0.0)), None);
        assert!(rec.samples.is_empty(), "nothing kept past the cap");
        rec.restart();
        rec.note(0.0, pose(1.0, 1.0, 0.0));
        assert!(rec.finish(ContentHash([0; 32]), "", 3.0, pose(2.0, 1.0, 0.0)).is_some());
    }

    #[test]
    fn the_ghost_moves_between_samples_and_stays_at_the_exit() {
        let run = walk_east(2.0);
        let at = |t| run.pose_at(t).unwrap().position.x;
        assert!((at(0.0) - 2.0).abs() < 0.01);
        assert!((at(1.05) - 7.25).abs() < 0.01, "{}", at(1.05));
        assert!((at(99.0) - 12.0).abs() < 0.01, "at the finish after it");
        let turning =
            Run { samples: vec![pose(0.0, 0.0, 350.0), pose(0.0, 0.0, 10.0)], millis: 100, ..run.clone() };
        assert!((turning.pose_at(0.05).unwrap().yaw_deg - 0.0).abs() < 0.01, "the short way round");
    }

    #[test]
    fn bad_runs_are_refused_with_a_reason() {
        let good = walk_east(1.0).encode().unwrap();
        assert_eq!(Run::decode(b"hello"), Err(RunError::NotARun));
        assert_eq!(Run::decode(&vec![0; MAX_BYTES + 1]), Err(RunError::TooLarge(MAX_BYTES + 1)));
        let mut v2 = good.clone();
        v2[5] = 2;
        assert_eq!(Run::decode(&v2), Err(RunError::Version(2)));
        assert!(matches!(Run::decode(&good[..good.len() - 1]), Err(RunError::Truncated(_))));
        let mut trailing = good.clone();
        trailing.push(0);
        assert_eq!(Run::decode(&trailing), Err(RunError::Trailing(1)));
        // a count that does not match the time, and one that would ask for a huge allocation
        let count_at = MAGIC.len() + 32 + 1 + 2 + 1 + 3; // millis 1000 is two bytes; "ada"
        let mut wrong = good.clone();
        wrong[count_at] += 1;
        assert_eq!(Run::decode(&wrong), Err(RunError::OutOfRange("sample count")));
        let header = MAGIC.len() + 32 + 1; // up to the finish time
        let mut long = good[..header].to_vec();
        put_varint(&mut long, 599_999);
        long.push(0); // no name
        put_varint(&mut long, 6000);
        long.extend_from_slice(&[0, 0, 0, 0]);
        assert_eq!(Run::decode(&long), Err(RunError::Truncated("samples")));
        // one sample (a run under 0.1 s) looking 91° up
        let one = |x: i64, yaw: u64, pitch: i64| {
            let mut b = good[..header].to_vec();
            b.extend_from_slice(&[50, 0, 1]); // 50 ms, no name, one sample
            for v in [zigzag(x), zigzag(0), yaw, zigzag(pitch)] {
                put_varint(&mut b, v);
            }
            b
        };
        assert!(Run::decode(&one(0, 0, 0)).is_ok());
        assert_eq!(Run::decode(&one(0, 0, 91 * 16)), Err(RunError::OutOfRange("pitch")));
        assert_eq!(Run::decode(&one(0, 5760, 0)), Err(RunError::OutOfRange("heading")));
        assert_eq!(Run::decode(&one(1 << 40, 0, 0)), Err(RunError::OutOfRange("position")));
        // (found by the fuzzer: far out, an f32 cannot hold every 1/256 step, and the run would not
        // encode back to its bytes)
        let edge = one(POSITION_LIMIT, 0, 0);
        assert_eq!(Run::decode(&edge).unwrap().encode().unwrap(), edge);
        assert_eq!(Run::decode(&one(POSITION_LIMIT + 1, 0, 0)), Err(RunError::OutOfRange("position")));
        // (found by the fuzzer too: a half turn has one form, −180°)
        let half_turn = Run {
            samples: vec![Pose::default(), Pose { yaw_deg: 180.0, ..Pose::default() }],
            millis: 100,
            ..walk_east(1.0)
        };
        let bytes = half_turn.encode().unwrap();
        assert_eq!(Run::decode(&bytes).unwrap().encode().unwrap(), bytes);
        let mut plus = bytes.clone();
        let at = bytes.len() - 2; // the second sample's dyaw: zigzag(−2880) = 5759, two bytes
        assert_eq!(&bytes[at - 1..at + 1], &[0xff, 0x2c]);
        plus[at - 1..at + 1].copy_from_slice(&[0x80, 0x2d]); // zigzag(+2880)
        assert_eq!(Run::decode(&plus), Err(RunError::OutOfRange("heading")));
        // a name that would turn a screen's text around (U+202E), or hold a space: refused
        let mut bidi = good.clone();
        bidi[header + 3..header + 6].copy_from_slice("\u{202e}".as_bytes());
        assert_eq!(Run::decode(&bidi), Err(RunError::BadName));
        bidi[header + 3..header + 6].copy_from_slice(b"a d");
        assert_eq!(Run::decode(&bidi), Err(RunError::BadName));
        // (found by the fuzzer: the most negative zigzag value, whose absolute value overflows)
        let mut b = good[..header].to_vec();
        b.extend_from_slice(&[50, 0, 1]);
        b.extend_from_slice(&[0xff; 9]);
        b.push(0x01); // zigzag u64::MAX: i64::MIN
        b.extend_from_slice(&[0, 0, 0]);
        assert_eq!(Run::decode(&b), Err(RunError::OutOfRange("position")));
        let mut huge = good[..header].to_vec();
        huge.extend_from_slice(&[0xff; 11]);
        assert_eq!(Run::decode(&huge), Err(RunError::OutOfRange("finish time")));
    }

    #[test]
    fn a_run_is_checked_against_its_maze() {
        let maze = mazewalk_maze::builtin().unwrap();
        let hash = maze.content_hash();
        let mut run = walk_east(1.0);
        assert!(matches!(run.check_maze(hash, maze.extents()), Err(RunError::OtherMaze { .. })));
        run.maze = hash;
        for s in &mut run.samples {
            s.position = maze.viewer().pos;
        }
        assert_eq!(run.check_maze(hash, maze.extents()), Ok(()));
        run.samples[3].position.x = -1e6;
        assert_eq!(run.check_maze(hash, maze.extents()), Err(RunError::OutsideMaze(3)));
    }
}
