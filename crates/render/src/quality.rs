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
//!   typically the floor, the ceiling and one wall);
//! - **error** ([`Measures::mean_error`], [`Measures::p95_error`]): the OKLab distance of each sample to
//!   the truecolor frame's, its mean and its 95th percentile over the frame (issue #39);
//! - **chroma ratio** ([`Measures::chroma_ratio`]): over the truecolor frame's chromatic samples, the
//!   median chroma the frame shows ÷ the median chroma of truecolor: above 1, the palette paints the
//!   scene more vivid than it is; below, greyer.
//!
//! Pure functions on frames and coverage ids; the measuring tool (`benches/examples/picture.rs`) and
//! the tests call them.

use glam::{Vec2, Vec3};

use super::camera::Camera;
use super::options::Charset;
use super::palette::{hue_difference, oklab, xterm_rgb};
use super::picture::glyph_mask;
use super::shade::srgb_to_linear;
use mazewalk_maze::Maze;
use mazewalk_maze::movement::{Position, settle};
use mazewalk_term::frame::{Color, Frame};

/// What [`held_out_views`] makes of a view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewKind {
    /// Anywhere in a cell (at least a fifth of the way from its walls), any heading.
    InCell,
    /// The maze's clearance from one of a cell's walls (the closest the walk lets a player stand:
    /// [`Maze::clearance`]), facing it within ±60°.
    NoseToWall,
    /// From a cell's centroid through one of its openings: down a corridor.
    Corridor,
}

/// `n` views of `maze` drawn from `seed` (the same seed, the same views): the kinds of [`ViewKind`] in
/// turn, each with the maze viewer's eye height and field of view. The views the colour measures of
/// issue #39 are taken over, so that no one frame stands for the picture.
#[must_use]
pub fn held_out_views(maze: &Maze, seed: u64, n: usize) -> Vec<(ViewKind, Camera)> {
    let mut state = seed ^ 0x9E37_79B9_7F4A_7C15;
    // SplitMix64, as the maze generator: a uniform float in 0..1.
    let mut unit = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    };
    let viewer = maze.viewer();
    let camera = |position: Vec2, yaw: f32| Camera {
        eye_z: viewer.z,
        min_vfov_deg: maze.min_vfov_deg(),
        ..Camera::new(position, yaw.to_degrees().rem_euclid(360.0), viewer.fov_deg)
    };
    let clearance = maze.clearance();
    let cells = maze.cell_count();
    let mut out = Vec::with_capacity(n);
    let kinds = [ViewKind::InCell, ViewKind::NoseToWall, ViewKind::Corridor];
    // Bounded: a maze with no cell a view fits in gives fewer views, not a hang.
    for _ in 0..n.saturating_mul(50) {
        if out.len() == n || cells == 0 {
            break;
        }
        let kind = kinds[out.len() % kinds.len()];
        let cell = ((unit() * cells as f32) as usize).min(cells - 1) as u32;
        let edges = maze.cell_edges(cell);
        if edges.is_empty() {
            continue;
        }
        let e = edges[((unit() * edges.len() as f32) as usize).min(edges.len() - 1)];
        let (a, b) = maze.edge_points_ccw(e, cell);
        let centroid = maze.cell_centroid(cell);
        let view = match kind {
            ViewKind::InCell => {
                let on_edge = a.lerp(b, unit());
                Some(camera(centroid.lerp(on_edge, 0.8 * unit()), unit() * std::f32::consts::TAU))
            }
            ViewKind::NoseToWall if maze.edge(e).opaque && a.distance(b) > 2.4 * clearance => {
                let inward = (b - a).perp().normalize_or_zero(); // the cell is left of its ccw edges
                let at = a.lerp(b, 0.2 + 0.6 * unit()) + clearance * inward;
                let facing = (-inward).y.atan2((-inward).x) + (unit() - 0.5) * 120f32.to_radians();
                // where the walk would have the player stand there (out of a corner), as close as it lets
                let stands =
                    maze.cell_contains(cell, at).then(|| settle(maze, Position { cell, pos: at }, clearance));
                stands.filter(|s| s.cell == cell).map(|s| camera(s.pos, facing))
            }
            ViewKind::Corridor if !maze.edge(e).opaque => {
                let through = a.lerp(b, 0.5) - centroid;
                Some(camera(centroid, through.y.atan2(through.x)))
            }
            _ => None,
        };
        if let Some(view) = view {
            out.push((kind, view));
        }
    }
    out
}

/// A pair of neighbouring samples is grain where the frame puts them this much further apart (OKLab)
/// than the truecolor frame does.
pub(crate) const GRAIN_STEP: f32 = 0.06;
/// Samples whose truecolor chroma (OKLab) is above this count toward the hue error.
pub(crate) const CHROMATIC: f32 = 0.04;
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
    /// Mean OKLab distance of a sample to the truecolor frame's.
    pub mean_error: f64,
    /// 95th percentile of that distance.
    pub p95_error: f64,
    /// Median chroma of the frame over the truecolor frame's chromatic samples ÷ truecolor's median
    /// there; 1 where truecolor has no chromatic sample.
    pub chroma_ratio: f64,
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
    let mut errors: Vec<f32> = frame.iter().zip(truth).map(|(f, t)| f.distance(*t)).collect();
    Measures {
        grain: grain(frame, truth, width),
        hue_error_deg: hue_error_deg(frame, truth),
        surfaces_apart: surfaces_apart(frame, ids),
        mean_error: errors.iter().map(|&e| f64::from(e)).sum::<f64>() / errors.len().max(1) as f64,
        p95_error: percentile(&mut errors, 0.95),
        chroma_ratio: chroma_ratio(frame, truth),
    }
}

/// The `q` quantile (0..=1, nearest rank) of `values` (reordered); 0 for none.
fn percentile(values: &mut [f32], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((q * values.len() as f64).ceil() as usize).clamp(1, values.len()) - 1;
    let (_, value, _) = values.select_nth_unstable_by(rank, f32::total_cmp);
    f64::from(*value)
}

/// Median chroma of `frame` ÷ median chroma of `truth`, both over the truth's chromatic samples.
fn chroma_ratio(frame: &[Vec3], truth: &[Vec3]) -> f64 {
    let (mut shown, mut true_chroma): (Vec<f32>, Vec<f32>) = frame
        .iter()
        .zip(truth)
        .map(|(&f, &t)| (chroma_hue(f).0, chroma_hue(t).0))
        .filter(|&(_, t)| t > CHROMATIC)
        .unzip();
    let truth_median = percentile(&mut true_chroma, 0.5);
    if truth_median > 0.0 { percentile(&mut shown, 0.5) / truth_median } else { 1.0 }
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
pub(crate) fn largest_surfaces(ids: &[u32]) -> Vec<u32> {
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
pub(crate) fn surface_mean(frame: &[Vec3], ids: &[u32], id: u32) -> Vec3 {
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
        assert_eq!((m.grain, m.hue_error_deg, m.mean_error, m.p95_error), (0.0, 0.0, 0.0, 0.0));
        assert_eq!(m.chroma_ratio, 1.0);
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
    fn errors_are_per_sample_distances_and_chroma_is_compared_by_medians() {
        let truth = vec![Vec3::new(0.5, 0.1, 0.0); 20];
        // Nineteen samples off by 0.01 in lightness, one off by 0.2: the mean sees both, the 95th
        // percentile (the 19th of 20) only the small one.
        let mut frame = vec![Vec3::new(0.51, 0.1, 0.0); 20];
        frame[7] = Vec3::new(0.7, 0.1, 0.0);
        let m = measure(&frame, &truth, &[0; 20], 5);
        assert!((m.mean_error - (19.0 * 0.01 + 0.2) / 20.0).abs() < 1e-5, "{m:?}");
        assert!((m.p95_error - 0.01).abs() < 1e-5, "{m:?}");
        assert!((m.chroma_ratio - 1.0).abs() < 1e-6);
        // Twice as saturated, then grey.
        let vivid = vec![Vec3::new(0.5, 0.2, 0.0); 20];
        assert!((measure(&vivid, &truth, &[0; 20], 5).chroma_ratio - 2.0).abs() < 1e-5);
        let grey = vec![Vec3::new(0.5, 0.0, 0.0); 20];
        assert_eq!(measure(&grey, &truth, &[0; 20], 5).chroma_ratio, 0.0);
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
