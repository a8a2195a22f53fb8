//! How a frame in 256 or 16 colours looks beside the truecolor frame of the same view (issue #33):
//! the measures of a picture a player can find the way by, per sample, in OKLab, with no blur.
//!
//! A frame is read back as the terminal shows it, sample by sample ([`shown`]: a half-block cell is
//! two samples, its glyph's ink on the samples it covers and its background on the rest, indexed
//! colours through xterm's default palette). Against the truecolor frame's samples:
//!
//! - **grain** ([`Measures::grain`]): the share of neighbouring sample pairs (right and down) whose
//!   OKLab distance in the frame exceeds the same pair's distance in the truecolor frame by more than
//!   [`GRAIN_STEP`]: the dots and checks a palette adds where the picture is smooth;
//! - **hue error** ([`Measures::hue_error_deg`]): the mean hue-angle difference over the samples whose
//!   truecolor chroma is above [`CHROMATIC`], counting 180° where the frame's sample has lost its chroma
//!   (below [`GREY`]);
//! - **surfaces apart** ([`Measures::surfaces_apart`]): the smallest OKLab distance (×100) between the
//!   frame's mean colours (means of OKLab) over the three largest surfaces of the view (by coverage id:
//!   typically the floor, the ceiling and one wall).
//!
//! Pure functions on frames and coverage ids; the measuring tool (`benches/examples/picture.rs`) and
//! the tests call them.

use glam::Vec3;

use super::options::Charset;
use super::palette::{hue_difference, oklab, xterm_rgb};
use super::picture::glyph_mask;
use super::shade::srgb_to_linear;
use mazewalk_term::frame::{Color, Frame};

/// A pair of neighbouring samples is grain where the frame puts them this much further apart (OKLab)
/// than the truecolor frame does.
pub const GRAIN_STEP: f32 = 0.06;
/// Samples whose truecolor chroma (OKLab) is above this count toward the hue error.
pub const CHROMATIC: f32 = 0.04;
/// A frame's sample with less chroma than this has lost its hue: 180° of hue error.
pub const GREY: f32 = 0.01;

/// The sRGB the terminal is assumed to show for `Color::Default` (as [`picture`](super::picture)).
const DEFAULT_FG: [u8; 3] = [229, 229, 229];
const DEFAULT_BG: [u8; 3] = [0, 0, 0];

/// OKLab of an sRGB colour.
#[must_use]
pub fn oklab_srgb8(rgb: [u8; 3]) -> Vec3 {
    oklab(Vec3::from_array(rgb.map(|v| srgb_to_linear(f32::from(v) / 255.0))))
}

/// What the terminal shows on each sample of `frame` drawn with the block charset `charset`, in OKLab,
/// row-major (`frame.width() · sx` by `frame.height() · sy`). A glyph that is not one of the charset's
/// blocks shows its background.
#[must_use]
pub fn shown(frame: &Frame, charset: Charset) -> Vec<Vec3> {
    let (sx, sy) = charset.samples_per_cell();
    let width = frame.width() * sx;
    let mut out = vec![Vec3::ZERO; width * frame.height() * sy];
    let rgb = |color: Color, default: [u8; 3]| match color {
        Color::Default => default,
        Color::Rgb(r, g, b) => [r, g, b],
        Color::Indexed(i) => xterm_rgb(i),
    };
    for (k, cell) in frame.cells().iter().enumerate() {
        let (col, row) = (k % frame.width(), k / frame.width());
        let (fg, bg) = (oklab_srgb8(rgb(cell.fg, DEFAULT_FG)), oklab_srgb8(rgb(cell.bg, DEFAULT_BG)));
        let mask = glyph_mask(charset, cell.ch).unwrap_or(0);
        for bit in 0..sx * sy {
            let (x, y) = (col * sx + bit % sx, row * sy + bit / sx);
            out[y * width + x] = if mask >> bit & 1 == 1 { fg } else { bg };
        }
    }
    out
}

/// A frame's measures against the truecolor frame of the same view (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measures {
    /// Share (0..1) of neighbouring sample pairs that are grain.
    pub grain: f64,
    /// Mean hue error over the truecolor frame's chromatic samples, degrees; 0 where it has none.
    pub hue_error_deg: f64,
    /// The smallest OKLab distance ×100 between the mean colours of the three largest surfaces; the
    /// distance of two where the view has two, 0 where it has fewer.
    pub surfaces_apart: f64,
}

/// The measures of `frame` against `truth` (both from [`shown`], the same size), with `ids` the
/// samples' coverage ids (the renderer's [`SampleBuffer::id`](super::SampleBuffer::id)) and `width`
/// samples per row.
///
/// # Panics
/// If the three slices differ in length, or `width` does not divide it.
#[must_use]
pub fn measure(frame: &[Vec3], truth: &[Vec3], ids: &[u32], width: usize) -> Measures {
    assert!(frame.len() == truth.len() && truth.len() == ids.len(), "one sample each");
    assert!(width > 0 && frame.len().is_multiple_of(width), "whole rows");
    Measures {
        grain: grain(frame, truth, width),
        hue_error_deg: hue_error_deg(frame, truth),
        surfaces_apart: surfaces_apart(frame, ids),
    }
}

/// The share of neighbouring pairs (right, down) the frame sets [`GRAIN_STEP`] further apart.
fn grain(frame: &[Vec3], truth: &[Vec3], width: usize) -> f64 {
    let height = frame.len() / width;
    let (mut pairs, mut grainy) = (0usize, 0usize);
    let mut pair = |i: usize, j: usize| {
        pairs += 1;
        let excess = frame[i].distance(frame[j]) - truth[i].distance(truth[j]);
        grainy += usize::from(excess > GRAIN_STEP);
    };
    for y in 0..height {
        for x in 0..width {
            let i = y * width + x;
            if x + 1 < width {
                pair(i, i + 1);
            }
            if y + 1 < height {
                pair(i, i + width);
            }
        }
    }
    if pairs == 0 { 0.0 } else { grainy as f64 / pairs as f64 }
}

/// Chroma and hue angle (radians) of an OKLab colour.
fn chroma_hue(lab: Vec3) -> (f32, f32) {
    (lab.y.hypot(lab.z), lab.z.atan2(lab.y))
}

/// The mean hue difference over the truth's chromatic samples (180° where the frame's is grey).
fn hue_error_deg(frame: &[Vec3], truth: &[Vec3]) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (&f, &t) in frame.iter().zip(truth) {
        let (tc, th) = chroma_hue(t);
        if tc <= CHROMATIC {
            continue;
        }
        let (fc, fh) = chroma_hue(f);
        let error = if fc < GREY { 180.0 } else { f64::from(hue_difference(fh, th).to_degrees()) };
        sum += error;
        n += 1;
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The ids of the three largest surfaces (most samples first; ties: the smaller id first).
#[must_use]
pub fn largest_surfaces(ids: &[u32]) -> Vec<u32> {
    let mut counts = std::collections::HashMap::new();
    for &id in ids {
        *counts.entry(id).or_insert(0usize) += 1;
    }
    let mut by_size: Vec<(u32, usize)> = counts.into_iter().collect();
    by_size.sort_unstable_by_key(|&(id, n)| (std::cmp::Reverse(n), id));
    by_size.into_iter().take(3).map(|(id, _)| id).collect()
}

/// The mean OKLab colour of `frame` over the samples of surface `id`.
#[must_use]
pub fn surface_mean(frame: &[Vec3], ids: &[u32], id: u32) -> Vec3 {
    let (sum, n) = frame
        .iter()
        .zip(ids)
        .filter(|&(_, &i)| i == id)
        .fold((Vec3::ZERO, 0usize), |(sum, n), (&lab, _)| (sum + lab, n + 1));
    sum / n.max(1) as f32
}

/// The smallest distance (×100) between the mean colours of the three largest surfaces.
fn surfaces_apart(frame: &[Vec3], ids: &[u32]) -> f64 {
    let means: Vec<Vec3> = largest_surfaces(ids).into_iter().map(|id| surface_mean(frame, ids, id)).collect();
    let mut least = f32::INFINITY;
    for (k, a) in means.iter().enumerate() {
        for b in &means[k + 1..] {
            least = least.min(a.distance(*b));
        }
    }
    if least.is_finite() { f64::from(100.0 * least) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_term::frame::Cell;

    #[test]
    fn a_half_block_cell_shows_its_ink_on_top_and_its_background_below() {
        let mut frame = Frame::new(2, 1);
        frame.set(0, 0, Cell { ch: '▀', fg: Color::Rgb(255, 0, 0), bg: Color::Indexed(21) });
        frame.set(1, 0, Cell { ch: '▄', fg: Color::Rgb(255, 0, 0), bg: Color::Indexed(21) });
        let s = shown(&frame, Charset::Half);
        let (red, blue) = (oklab_srgb8([255, 0, 0]), oklab_srgb8(xterm_rgb(21)));
        assert_eq!(s, [red, blue, blue, red]); // row 0: the top samples, row 1: the bottom ones
    }

    #[test]
    fn a_frame_against_itself_has_no_grain_and_no_hue_error() {
        let truth: Vec<Vec3> =
            (0..40).map(|k| oklab_srgb8([(k * 6) as u8, 100, (250 - k * 5) as u8])).collect();
        let ids: Vec<u32> = (0..40).map(|k| k / 14).collect();
        let m = measure(&truth, &truth, &ids, 8);
        assert_eq!((m.grain, m.hue_error_deg), (0.0, 0.0));
        assert!(m.surfaces_apart > 10.0, "{m:?}");
    }

    #[test]
    fn a_checkerboard_is_grain_and_a_grey_is_half_a_turn_of_hue() {
        let (a, b) = (oklab_srgb8([120, 120, 120]), oklab_srgb8([90, 90, 150]));
        let truth = vec![oklab_srgb8([105, 105, 135]); 16];
        let checks: Vec<Vec3> = (0..16).map(|k| if (k % 4 + k / 4) % 2 == 0 { a } else { b }).collect();
        let m = measure(&checks, &truth, &[0; 16], 4);
        assert_eq!(m.grain, 1.0, "every neighbour differs");
        let bluish = vec![oklab_srgb8([40, 80, 200]); 4];
        let grey = vec![oklab_srgb8([90, 90, 90]); 4];
        assert_eq!(measure(&grey, &bluish, &[0; 4], 2).hue_error_deg, 180.0);
        // A shift of hue with chroma kept: the angle between the two.
        let other = vec![oklab_srgb8([40, 200, 80]); 4];
        let (_, h1) = chroma_hue(bluish[0]);
        let (_, h2) = chroma_hue(other[0]);
        let expected = f64::from((h1 - h2).abs().to_degrees());
        let expected = if expected > 180.0 { 360.0 - expected } else { expected };
        assert!((measure(&other, &bluish, &[0; 4], 2).hue_error_deg - expected).abs() < 1e-3);
    }

    #[test]
    fn surfaces_apart_is_the_closest_pair_of_the_three_largest() {
        // Surfaces 0 (6 samples), 1 (5), 2 (3), 3 (2): the last is left out.
        let ids = [0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 3, 3];
        let colour = |id: u32| match id {
            0 => Vec3::new(0.3, 0.0, 0.0),
            1 => Vec3::new(0.5, 0.0, 0.0),
            2 => Vec3::new(0.55, 0.0, 0.0),
            _ => Vec3::new(0.551, 0.0, 0.0),
        };
        let frame: Vec<Vec3> = ids.iter().map(|&id| colour(id)).collect();
        assert_eq!(largest_surfaces(&ids), [0, 1, 2]);
        let apart = measure(&frame, &frame, &ids, 4).surfaces_apart;
        assert!((apart - 5.0).abs() < 1e-4, "{apart}");
    }
}
