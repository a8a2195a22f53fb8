//! What the served fuzz targets (`serve`: a player, `watch`: a spectator) share: how their input
//! bytes become steps, and what must hold of every frame, every wake and the goodbye.

use mazewalk_serve::Limits;
use mazewalk_serve::player::REMOTE;
use mazewalk_term::frame::Frame;
use mazewalk_term::modes::restore_sequence;

/// Generous upper bound of a frame's bytes per screen cell (glyph, colours, cursor moves), plus the
/// fixed part (synchronized output, the query).
const MAX_BYTES_PER_CELL: usize = 64;

/// The size limits both targets serve under: small, which keeps runs quick.
pub fn limits() -> Limits {
    Limits { max_cols: 160, max_rows: 60, ..Limits::default() }
}

/// One step of a fuzz input.
pub enum Step<'a> {
    /// Bytes typed (keys, mouse, terminal answers, garbage), in one chunk.
    Keys(&'a [u8]),
    /// A window change to any size, absurd ones included.
    Resize(u32, u32),
    /// Time passes, seconds.
    Wait(f64),
    /// The others in the world do something; how much is the number.
    World(usize),
}

/// The input's first byte picks the first window size; then each step's first byte says what in its
/// low 2 bits and how much in the rest.
pub fn steps(bytes: &[u8]) -> Option<((u32, u32), impl Iterator<Item = Step<'_>>)> {
    let (&size, mut rest) = bytes.split_first()?;
    let window = (u32::from(size & 0x0f) * 13, u32::from(size >> 4) * 5);
    let steps = std::iter::from_fn(move || {
        let (&op, tail) = rest.split_first()?;
        rest = tail;
        let n = usize::from(op >> 2);
        Some(match op & 3 {
            0 => {
                let (chunk, tail) = rest.split_at(n.min(rest.len()));
                rest = tail;
                Step::Keys(chunk)
            }
            1 => {
                let (dims, tail) = rest.split_at(8.min(rest.len()));
                rest = tail;
                let mut b = [0u8; 8];
                b[..dims.len()].copy_from_slice(dims);
                Step::Resize(
                    u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                    u32::from_le_bytes([b[4], b[5], b[6], b[7]]),
                )
            }
            2 => Step::Wait(n as f64 / 20.0),
            _ => Step::World(n),
        })
    });
    Some((window, steps))
}

/// A frame's screen stays within the limits, and its bytes within a fixed bound per cell.
pub fn check_frame(screen: &Frame, out: &[u8], limits: &Limits) {
    assert!(
        screen.width() <= usize::from(limits.max_cols) && screen.height() <= usize::from(limits.max_rows)
    );
    assert!(out.len() <= 256 + screen.width() * screen.height() * MAX_BYTES_PER_CELL, "{} bytes", out.len());
}

/// A wake before now (even -inf: "a frame is due") means at once, and the server clamps the wait; but
/// never NaN and never +inf.
pub fn check_wake(wake: Option<f64>) {
    if let Some(wake) = wake {
        assert!(!wake.is_nan() && wake < f64::INFINITY);
    }
}

/// Leaving ends with the full restore sequence, then the goodbye.
pub fn check_goodbye(out: &[u8]) {
    let restore = restore_sequence(REMOTE);
    assert!(out.starts_with(restore.as_bytes()) && out.ends_with(b"bye\r\n"));
}
