//! Samples → [`Frame`] cells: ascii shading ramp, half blocks, quadrants and sextants.
//!
//! Each terminal cell covers `sx × sy` samples ([`Charset::samples_per_cell`]). The block charsets pick,
//! per cell, the 2-colour partition of its samples that fits best (least squared error in sRGB) and the
//! block glyph drawing it; ascii maps luminance to a ramp and overlays the outline layer. Sample bits within
//! a cell are numbered row-major from the top-left: bit `x + sx·y`.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use super::palette::{Dither, ansi16, ansi16_dither, quantize_srgb8};
use super::samples::SampleBuffer;
use super::shade::{linear_to_srgb_fast, luminance};
use crate::frame::{Cell, Color, ColorDepth, Frame};

/// How cells are drawn, and so how many samples each covers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Charset {
    /// One sample per cell: a luminance ramp plus line outlines; readable without colour.
    Ascii,
    /// 1×2 samples: `▀` with the top sample as ink, the bottom one as background.
    #[default]
    Half,
    /// 2×2 samples: the quadrant blocks `▘▝▀▖▌▞▛▗▚▐▜▄▙▟█`.
    Quad,
    /// 2×3 samples: the sextant blocks U+1FB00–U+1FB3B plus ` `, `▌`, `▐`, `█`.
    Sextant,
}

impl Charset {
    /// Every charset, in the order of their names.
    pub const ALL: [Charset; 4] = [Charset::Ascii, Charset::Half, Charset::Quad, Charset::Sextant];

    /// Samples per cell `(sx, sy)`; the pipeline sizes the buffer `cols·sx × rows·sy`.
    #[must_use]
    pub const fn samples_per_cell(self) -> (usize, usize) {
        match self {
            Charset::Ascii => (1, 1),
            Charset::Half => (1, 2),
            Charset::Quad => (2, 2),
            Charset::Sextant => (2, 3),
        }
    }

    /// A sample's width / height on screen, from the cell's (about 0.5): `cell_aspect · sy / sx`.
    #[must_use]
    pub fn sample_aspect(self, cell_aspect: f32) -> f32 {
        let (sx, sy) = self.samples_per_cell();
        cell_aspect * sy as f32 / sx as f32
    }

    /// The name used on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Charset::Ascii => "ascii",
            Charset::Half => "half",
            Charset::Quad => "quad",
            Charset::Sextant => "sextant",
        }
    }
}

impl fmt::Display for Charset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A charset name that is none of `ascii|half|quad|sextant`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown charset {0:?} (expected ascii, half, quad or sextant)")]
pub struct UnknownCharset(pub String);

impl FromStr for Charset {
    type Err = UnknownCharset;

    fn from_str(s: &str) -> Result<Charset, UnknownCharset> {
        Charset::ALL.into_iter().find(|c| c.name() == s).ok_or_else(|| UnknownCharset(s.to_owned()))
    }
}

/// The ascii shading ramp, darkest first.
pub const ASCII_RAMP: [char; 10] = [' ', '.', ':', '-', '=', '+', '*', '#', '%', '@'];

/// The colourless block-mode ramp, darkest first.
pub const BLOCK_RAMP: [char; 5] = [' ', '░', '▒', '▓', '█'];

/// Quadrant glyphs by mask (bit 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right).
pub const QUAD: [char; 16] = [' ', '▘', '▝', '▀', '▖', '▌', '▞', '▛', '▗', '▚', '▐', '▜', '▄', '▙', '▟', '█'];

/// The half-block glyphs by mask (bit 0 top, bit 1 bottom).
pub const HALF: [char; 4] = [' ', '▀', '▄', '█'];

/// The sextant glyph for a 6-bit mask (bit 0 top-left, 1 top-right, 2 middle-left, … 5 bottom-right).
///
/// U+1FB00 `BLOCK SEXTANT-1` … U+1FB3B `BLOCK SEXTANT-23456` list the masks 1–62 in order, leaving out
/// the two half blocks that already exist (left column `▌` = 21, right column `▐` = 42).
#[must_use]
pub fn sextant_glyph(mask: u8) -> char {
    let mask = u32::from(mask & 63);
    match mask {
        0 => ' ',
        21 => '▌',
        42 => '▐',
        63 => '█',
        _ => {
            let skipped = u32::from(mask > 21) + u32::from(mask > 42);
            char::from_u32(0x1FB00 + mask - 1 - skipped).unwrap_or('?')
        }
    }
}

/// The block glyph of `charset` for a sample mask (see the bit order in the module docs); `ascii` has
/// none and gives `█` or ` `.
#[must_use]
pub fn block_glyph(charset: Charset, mask: u8) -> char {
    match charset {
        Charset::Ascii => HALF[usize::from(mask & 1) * 3],
        Charset::Half => HALF[usize::from(mask & 3)],
        Charset::Quad => QUAD[usize::from(mask & 15)],
        Charset::Sextant => sextant_glyph(mask),
    }
}

/// Converts `samples` to cells of `frame` (resized to `cols × rows` = the whole cells the samples fill).
///
/// `outlines` overlays the outline layer (ascii only; the block charsets draw edges with their shapes).
/// With [`ColorDepth::None`] every colour is [`Color::Default`] and shading comes from [`ASCII_RAMP`] or
/// [`BLOCK_RAMP`]; with [`ColorDepth::Ansi16`] flat cells are dithered with [`SHADES`](super::palette::SHADES) mixes.
pub fn to_frame(
    samples: &SampleBuffer,
    charset: Charset,
    depth: ColorDepth,
    outlines: bool,
    frame: &mut Frame,
) {
    let (sx, sy) = charset.samples_per_cell();
    let (cols, rows) = (samples.width() / sx, samples.height() / sy);
    if frame.width() != cols || frame.height() != rows {
        frame.resize(cols, rows);
    }
    let width = samples.width();
    let mut cell_samples = [Vec3::ZERO; 6];
    for row in 0..rows {
        for col in 0..cols {
            let base = row * sy * width + col * sx;
            let cell = if charset == Charset::Ascii {
                let outline = if outlines { samples.outline()[base] } else { None };
                ascii_cell(samples.color()[base], outline, depth)
            } else {
                // Bit order: row-major from the top-left (sample k is at (k % sx, k / sx)).
                let mut k = 0;
                for dy in 0..sy {
                    for dx in 0..sx {
                        cell_samples[k] = samples.color()[base + dy * width + dx];
                        k += 1;
                    }
                }
                block_cell(&cell_samples[..sx * sy], charset, depth)
            };
            frame.set(col, row, cell);
        }
    }
}

/// The index into a `len`-step ramp for a linear colour's lightness (sRGB-encoded luminance).
fn ramp_index(color: Vec3, len: usize) -> usize {
    ((linear_to_srgb_fast(luminance(color)) * (len - 1) as f32).round() as usize).min(len - 1)
}

/// One ascii cell: the outline glyph if any, else the ramp glyph; ink in the sample's colour.
fn ascii_cell(color: Vec3, outline: Option<char>, depth: ColorDepth) -> Cell {
    let ch = outline.unwrap_or(ASCII_RAMP[ramp_index(color, ASCII_RAMP.len())]);
    let fg =
        if ch == ' ' { Color::Default } else { quantize_srgb8(srgb8(color.map(linear_to_srgb_fast)), depth) };
    Cell { ch, fg, bg: Color::Default }
}

/// The best 2-colour partition of a cell's sRGB samples: `(mask, ink mean, background mean)`; samples in
/// `mask` are ink. Only masks without the last sample are tried (a mask and its complement are the same
/// split), so the last sample is always background and mask 0 means one colour.
fn best_partition(srgb: &[Vec3]) -> (u8, Vec3, Vec3) {
    if let [a, b] = *srgb {
        // Half blocks: the loop below for two samples, unrolled (same arithmetic, so the same choice).
        // Mask 0 is one colour, the mean; mask 1 puts `a` over `b` with no error, and wins unless
        // mask 0's error is within the tie margin.
        let mean = (a + b) / 2.0;
        let error = a.distance_squared(mean) + b.distance_squared(mean);
        return if 0.0 < error - 1e-9 { (1, a, b) } else { (0, Vec3::ZERO, mean) };
    }
    let n = srgb.len();
    let mut best = (0u8, Vec3::ZERO, Vec3::ZERO, f32::INFINITY);
    for mask in 0..1u8 << (n - 1) {
        let (mut ink_n, mut ink_sum, mut paper_sum) = (0, Vec3::ZERO, Vec3::ZERO);
        for (k, v) in srgb.iter().enumerate() {
            if mask >> k & 1 == 1 {
                (ink_n, ink_sum) = (ink_n + 1, ink_sum + *v);
            } else {
                paper_sum += *v;
            }
        }
        let ink = if ink_n > 0 { ink_sum / ink_n as f32 } else { Vec3::ZERO };
        let paper = paper_sum / (n - ink_n) as f32;
        let error: f32 = srgb
            .iter()
            .enumerate()
            .map(|(k, v)| v.distance_squared(if mask >> k & 1 == 1 { ink } else { paper }))
            .sum();
        if error < best.3 - 1e-9 {
            best = (mask, ink, paper, error); // strictly better only: ties keep the simpler, earlier mask
        }
    }
    (best.0, best.1, best.2)
}

/// sRGB 0..1 → 0..255, rounded to nearest (halves up).
fn srgb8(srgb: Vec3) -> [u8; 3] {
    srgb.to_array().map(|c| round_u8(c.clamp(0.0, 1.0) * 255.0))
}

/// `v.round() as u8` for `v` in 0..=255, without the libm call `round` is on baseline x86-64: truncate,
/// then add one if the dropped fraction is at least a half (`v - t` is exact for `v` below 2^23).
fn round_u8(v: f32) -> u8 {
    let t = v as u8;
    t + u8::from(v - f32::from(t) >= 0.5)
}

fn solid(color: Color) -> Cell {
    Cell { ch: ' ', fg: color, bg: color } // ink unused: same as the background so equal cells compare equal
}

fn dithered(d: Dither) -> Cell {
    if d.glyph == ' ' {
        solid(Color::Indexed(d.bg))
    } else {
        Cell { ch: d.glyph, fg: Color::Indexed(d.fg), bg: Color::Indexed(d.bg) }
    }
}

/// One block cell from its samples (linear), in bit order.
fn block_cell(samples: &[Vec3], charset: Charset, depth: ColorDepth) -> Cell {
    if depth == ColorDepth::None {
        let mean = samples.iter().sum::<Vec3>() / samples.len() as f32;
        return Cell::plain(BLOCK_RAMP[ramp_index(mean, BLOCK_RAMP.len())]);
    }
    let mut srgb = [Vec3::ZERO; 6];
    for (s, c) in srgb.iter_mut().zip(samples) {
        *s = c.map(linear_to_srgb_fast);
    }
    let srgb = &srgb[..samples.len()];
    let all = srgb8(srgb.iter().sum::<Vec3>() / srgb.len() as f32);
    let first = srgb8(srgb[0]);
    if srgb[1..].iter().all(|s| srgb8(*s) == first) {
        // Fast path, and what keeps flat areas stable: one colour.
        return if depth == ColorDepth::Ansi16 {
            dithered(ansi16_dither(all))
        } else {
            solid(quantize_srgb8(all, depth))
        };
    }
    let (mask, ink, paper) = best_partition(srgb);
    let (ink, paper) = (srgb8(ink), srgb8(paper));
    let (fg, bg) = match depth {
        // 16 colours: keep the shape where the two sides differ in ANSI, else dither the cell's mean.
        ColorDepth::Ansi16 => match (ansi16(ink), ansi16(paper)) {
            (i, p) if mask == 0 || i == p => return dithered(ansi16_dither(all)),
            (i, p) => (Color::Indexed(i), Color::Indexed(p)),
        },
        _ => (quantize_srgb8(ink, depth), quantize_srgb8(paper, depth)),
    };
    if mask == 0 || fg == bg {
        return solid(bg);
    }
    Cell { ch: block_glyph(charset, mask), fg, bg }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charset_names_round_trip() {
        for c in Charset::ALL {
            assert_eq!(c.to_string().parse::<Charset>(), Ok(c));
        }
        assert!("braille".parse::<Charset>().is_err());
        assert_eq!(Charset::Half.sample_aspect(0.5), 1.0);
        assert_eq!(Charset::Sextant.sample_aspect(0.5), 0.75);
    }

    #[test]
    fn best_partition_splits_two_colours() {
        let (a, b) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.1, 0.9));
        let (mask, ink, paper) = best_partition(&[a, b, a, b, a, a]);
        assert_eq!(mask, 0b00_1010); // the last sample is always background
        assert!(ink.abs_diff_eq(b, 1e-6) && paper.abs_diff_eq(a, 1e-6), "{ink} {paper}");
        assert_eq!(best_partition(&[a, a, a, a]).0, 0);
    }

    #[test]
    fn round_u8_rounds_like_round() {
        for v in (0..=255 * 64).map(|k| k as f32 / 64.0).chain([0.499_999_97, 254.499_98, 254.5, 255.0]) {
            assert_eq!(round_u8(v), v.round() as u8, "{v}");
        }
    }
}
