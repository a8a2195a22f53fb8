//! Colour quantization: linear RGB → sRGB → the terminal's [`ColorDepth`].
//!
//! The renderer works in linear RGB; colours are sRGB-encoded here, once, when quantized (colours from
//! files that are meant as display colours should go through [`srgb_to_linear`]
//! first). The palettes are xterm's defaults.
//!
//! The renderer dithers ([`dither`]): each sample shows one of two palette entries chosen in OKLab, by a
//! screen-anchored ordered threshold ([`threshold`]). [`quantize`] is plain nearest colour by squared
//! distance in sRGB 0..255, undithered: truecolor, and the reference the dithering is measured against.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU32, Ordering};

use glam::Vec3;

use super::shade::{Srgb8Tables, srgb_to_linear};
use mazewalk_term::frame::{Color, ColorDepth};

/// xterm's default RGB for the 16 ANSI colours (black, red, green, yellow, blue, magenta, cyan, white,
/// then the bright eight).
pub const ANSI16: [[u8; 3]; 16] = [
    [0, 0, 0],
    [205, 0, 0],
    [0, 205, 0],
    [205, 205, 0],
    [0, 0, 238],
    [205, 0, 205],
    [0, 205, 205],
    [229, 229, 229],
    [127, 127, 127],
    [255, 0, 0],
    [0, 255, 0],
    [255, 255, 0],
    [92, 92, 255],
    [255, 0, 255],
    [0, 255, 255],
    [255, 255, 255],
];

/// The levels of each axis of xterm's 6×6×6 colour cube (indices 16–231).
pub const CUBE_LEVELS: [u8; 6] = [0, 95, 135, 175, 215, 255];

/// A linear colour as sRGB bytes (clamped to 0..1 first; NaN → 0).
#[must_use]
#[inline]
pub fn to_srgb8(linear: Vec3) -> [u8; 3] {
    Srgb8Tables::get().encode3(linear)
}

/// The RGB xterm shows for palette `index` (ANSI 16, cube, grey ramp).
#[must_use]
pub fn xterm_rgb(index: u8) -> [u8; 3] {
    match index {
        0..=15 => ANSI16[usize::from(index)],
        16..=231 => {
            let i = usize::from(index - 16);
            [CUBE_LEVELS[i / 36], CUBE_LEVELS[i / 6 % 6], CUBE_LEVELS[i % 6]]
        }
        _ => [8 + 10 * (index - 232); 3],
    }
}

fn distance2(a: [u8; 3], b: [u8; 3]) -> u32 {
    (0..3).map(|k| u32::from(a[k].abs_diff(b[k])).pow(2)).sum()
}

/// The nearest xterm-256 index in 16–231 (cube) or 232–255 (greys) to an sRGB colour.
#[must_use]
pub fn xterm256(rgb: [u8; 3]) -> u8 {
    // Both candidates come from small tables of `cube_level` and `grey_index` (built on first use), as
    // this runs twice per cell in 256 colours.
    static TABLES: OnceLock<([u8; 256], [u8; 766])> = OnceLock::new();
    let (level, grey) = TABLES.get_or_init(|| {
        (std::array::from_fn(|v| cube_level(v as u8)), std::array::from_fn(|sum| grey_index(sum as u32)))
    });
    let [r, g, b] = rgb.map(|v| level[usize::from(v)]);
    let cube = 16 + 36 * r + 6 * g + b;
    let grey = grey[usize::from(rgb[0]) + usize::from(rgb[1]) + usize::from(rgb[2])];
    if distance2(xterm_rgb(grey), rgb) < distance2(xterm_rgb(cube), rgb) { grey } else { cube }
}

/// The index (0–5) of the cube level nearest to `v` (the lower one on a tie).
fn cube_level(v: u8) -> u8 {
    (0..6).min_by_key(|&k| CUBE_LEVELS[usize::from(k)].abs_diff(v)).unwrap_or(0)
}

/// The grey ramp entry (232–255) nearest to the mean of three channels summing to `sum`.
fn grey_index(sum: u32) -> u8 {
    let mean = sum as f32 / 3.0;
    232 + ((mean - 8.0) / 10.0).round().clamp(0.0, 23.0) as u8
}

/// The nearest of the 16 ANSI colours to an sRGB colour.
#[must_use]
pub fn ansi16(rgb: [u8; 3]) -> u8 {
    (0..16u8).min_by_key(|&i| distance2(ANSI16[usize::from(i)], rgb)).unwrap_or(0)
}

/// A linear colour quantized to `depth` (no dithering; [`ColorDepth::None`] gives [`Color::Default`]).
#[must_use]
pub fn quantize(linear: Vec3, depth: ColorDepth) -> Color {
    quantize_srgb8(to_srgb8(linear), depth)
}

/// An sRGB colour quantized to `depth` (no dithering; [`ColorDepth::None`] gives [`Color::Default`]).
#[must_use]
#[inline] // truecolor, every cell of the block charsets: a wrapping, not a call
pub fn quantize_srgb8(rgb: [u8; 3], depth: ColorDepth) -> Color {
    match depth {
        ColorDepth::None => Color::Default,
        ColorDepth::Ansi16 => Color::Indexed(ansi16(rgb)),
        ColorDepth::Ansi256 => Color::Indexed(xterm256(rgb)),
        ColorDepth::TrueColor => Color::Rgb(rgb[0], rgb[1], rgb[2]),
    }
}

/// The ordered-dither threshold of sample `(x, y)` (sample grid, origin top-left), in (0, 1).
///
/// The 2×2 Bayer matrix tiled over the sample grid: anchored to the screen, so a still picture keeps its
/// pattern and the diff encoder sends nothing for it. Every 2×2 window of samples, aligned or not, holds
/// one threshold from each quarter of (0, 1), so a mix averages out over any 2×2 samples to within ⅛.
/// Not 4×4: that is no finer over 2×2 windows, and its sixteen levels flip scattered single samples
/// as colours drift while walking, where 2×2 flips every other sample of a run (measured: 0.49× the
/// plain error at 0.94× the bytes of 4×4, in 256 colours; BENCHMARKS.md).
#[must_use]
#[inline]
pub fn threshold(x: usize, y: usize) -> f32 {
    const BAYER2: [[u8; 2]; 2] = [[0, 2], [3, 1]];
    (f32::from(BAYER2[y % 2][x % 2]) + 0.5) / 4.0
}

/// A linear colour quantized to `depth` with ordered dithering: the palette entry shown on a sample
/// whose [`threshold`] is `threshold`. Truecolor and [`ColorDepth::None`] are as [`quantize`].
///
/// Each colour is shown as a mix of two palette entries `a` and `b` (a solid entry is a mix with itself):
/// `b` on the samples whose threshold is below the ratio, `a` on the rest, so over a few samples the eye
/// sees `a + (b − a)·ratio` in linear light. The pair is the one whose best mix comes nearest the colour
/// in OKLab, with a penalty on the pair's own distance (a mix of far-apart colours is seen as grain, not
/// as the mean: black and white dashes along a wall edge); it is looked up per 8-step sRGB bucket
/// ([`mix_pair`]). The ratio is then exact for the sample's colour: its projection onto the pair's segment
/// in linear RGB, so gradients stay smooth inside a bucket.
#[must_use]
#[inline]
pub fn dither(linear: Vec3, rgb: [u8; 3], depth: ColorDepth, threshold: f32) -> Color {
    match Mix::of(rgb, depth) {
        Some(mix) => Color::Indexed(mix.pick(linear, threshold)),
        None => quantize_srgb8(rgb, depth),
    }
}

/// A colour's bucket (its sRGB bytes over 8) and the bucket's pair, kept by [`Mix::of_near`].
pub(crate) type KeptPair = Option<([u8; 3], (u8, u8))>;

/// What [`dither`] shows for one 8-bit sRGB colour: an entry that is exactly it, or a pair to mix. A
/// function of the colour alone, so a caller may keep it for the next sample of the same colour (the
/// glyph pass does, per sub-cell position: neighbours along a row often share their colour).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Mix {
    /// A palette entry shows as itself: its bucket's pair need not pass through it.
    Exact(u8),
    /// The bucket's pair `(a, b)` ([`mix_pair`]).
    Pair(u8, u8),
}

impl Mix {
    /// The mix for `rgb` at `depth`; `None` at the depths that do not dither (truecolor, none).
    #[inline]
    pub(crate) fn of(rgb: [u8; 3], depth: ColorDepth) -> Option<Mix> {
        Mix::of_near(rgb, depth, &mut None)
    }

    /// [`Mix::of`], given the bucket and pair of a colour looked up before (`last`, updated): the
    /// pair is a function of the bucket, and the next sample's colour is often in the same one,
    /// where the pair table (256 KB, read at random) need not be read again.
    #[inline]
    pub(crate) fn of_near(rgb: [u8; 3], depth: ColorDepth, last: &mut KeptPair) -> Option<Mix> {
        let palette = match depth {
            ColorDepth::None | ColorDepth::TrueColor => return None,
            ColorDepth::Ansi16 => Palette::Ansi16,
            ColorDepth::Ansi256 => Palette::Xterm256,
        };
        let exact = match palette {
            Palette::Ansi16 => ANSI16.iter().position(|&c| c == rgb).map(|i| i as u8),
            Palette::Xterm256 => exact256(rgb),
        };
        Some(match exact {
            Some(index) => Mix::Exact(index),
            None => {
                let bucket = rgb.map(|v| v >> 3);
                let (a, b) = match *last {
                    Some((seen, pair)) if seen == bucket => pair,
                    _ => {
                        let pair = mix_pair(rgb, palette);
                        *last = Some((bucket, pair));
                        pair
                    }
                };
                Mix::Pair(a, b)
            }
        })
    }

    /// The entry shown on a sample of linear colour `linear` (of this mix's sRGB colour) whose
    /// [`threshold`] is `threshold`.
    #[inline]
    pub(crate) fn pick(self, linear: Vec3, threshold: f32) -> u8 {
        match self {
            Mix::Exact(index) => index,
            Mix::Pair(a, b) => {
                let ratio = mix_ratio(linear.clamp(Vec3::ZERO, Vec3::ONE), a, b);
                if ratio > threshold { b } else { a }
            }
        }
    }
}

/// The xterm-256 index (16–255) showing exactly `rgb`, if one does.
#[inline]
fn exact256(rgb: [u8; 3]) -> Option<u8> {
    /// Each byte's cube level (0–5), or 6 where it is none.
    const LEVEL: [u8; 256] = {
        let mut table = [6u8; 256];
        let mut k = 0;
        while k < 6 {
            table[CUBE_LEVELS[k] as usize] = k as u8;
            k += 1;
        }
        table
    };
    let [r, g, b] = rgb.map(|v| LEVEL[usize::from(v)]);
    if r < 6 && g < 6 && b < 6 {
        return Some(16 + 36 * r + 6 * g + b);
    }
    let grey = rgb[0].wrapping_sub(8);
    (rgb[0] == rgb[1] && rgb[1] == rgb[2] && grey.is_multiple_of(10) && grey <= 230).then(|| 232 + grey / 10)
}

/// Which palette [`dither`] mixes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Palette {
    /// The 16 ANSI colours (xterm's defaults; terminals differ, so nothing finer is assumed).
    Ansi16,
    /// Indices 16–255 of xterm's 256 colours (the cube and the greys, the same on every terminal).
    Xterm256,
}

/// The palette's 256 entries in linear RGB and in OKLab.
struct Entries {
    linear: [Vec3; 256],
    oklab: [Vec3; 256],
}

/// [`Entries`], built on first use (768 `powf` and cube roots: a few µs).
fn entries() -> &'static Entries {
    static ENTRIES: OnceLock<Entries> = OnceLock::new();
    ENTRIES.get_or_init(|| {
        let linear: [Vec3; 256] = std::array::from_fn(|i| {
            Vec3::from_array(xterm_rgb(i as u8).map(|v| srgb_to_linear(f32::from(v) / 255.0)))
        });
        Entries { linear, oklab: linear.map(oklab) }
    })
}

/// OKLab of a linear sRGB colour (Björn Ottosson, <https://bottosson.github.io/posts/oklab/>): L in 0..1,
/// Euclidean distance ≈ perceived difference.
#[must_use]
pub fn oklab(linear: Vec3) -> Vec3 {
    let l = 0.412_221_46 * linear.x + 0.536_332_55 * linear.y + 0.051_445_995 * linear.z;
    let m = 0.211_903_5 * linear.x + 0.680_699_5 * linear.y + 0.107_396_96 * linear.z;
    let s = 0.088_302_46 * linear.x + 0.281_718_85 * linear.y + 0.629_978_7 * linear.z;
    let [l, m, s] = [l, m, s].map(|v| v.max(0.0).cbrt());
    Vec3::new(
        0.210_454_26 * l + 0.793_617_8 * m - 0.004_072_047 * s,
        1.977_998_5 * l - 2.428_592_2 * m + 0.450_593_7 * s,
        0.025_904_037 * l + 0.782_771_77 * m - 0.808_675_77 * s,
    )
}

/// The thresholds of every 2×2 window of samples within the repeating 2×2 tile of [`threshold`] (4
/// windows, wrapping round): what the eye averages a mix over at the least.
fn windows() -> [[f32; 4]; 4] {
    std::array::from_fn(|w| {
        let (x, y) = (w % 2, w / 2);
        [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| threshold(x + dx, y + dy))
    })
}

/// The ratio of `b` in the mix of entries `a` and `b` nearest to `linear` (least squares in linear RGB).
#[inline]
fn mix_ratio(linear: Vec3, a: u8, b: u8) -> f32 {
    let linear_of = &entries().linear;
    let (pa, d) = (linear_of[usize::from(a)], linear_of[usize::from(b)] - linear_of[usize::from(a)]);
    let d2 = d.length_squared();
    if d2 > 0.0 { ((linear - pa).dot(d) / d2).clamp(0.0, 1.0) } else { 0.0 }
}

/// The pair of entries `(a, b)` [`dither`] mixes for sRGB colours in `rgb`'s bucket (8 steps a channel).
///
/// Memoized per bucket: each is searched the first time a frame shows it (a few µs), so a frame pays only
/// for its own colours and no table is built up front (issue #16). Racing threads compute the same pair.
fn mix_pair(rgb: [u8; 3], palette: Palette) -> (u8, u8) {
    const BUCKETS: usize = 32 * 32 * 32;
    // 0 is "not searched yet": a searched pair has bit 16 set.
    static PAIRS: [[AtomicU32; BUCKETS]; 2] = [const { [const { AtomicU32::new(0) }; BUCKETS] }; 2];
    let key = rgb.map(|v| usize::from(v >> 3));
    let slot = &PAIRS[palette as usize][(key[0] << 10) | (key[1] << 5) | key[2]];
    let mut packed = slot.load(Ordering::Relaxed);
    if packed == 0 {
        let centre = key.map(|v| ((v << 3) + 4) as u8); // the bucket's, so the pair is the same whoever asks
        let (a, b) = search_pair(centre, palette);
        packed = 1 << 16 | u32::from(b) << 8 | u32::from(a);
        slot.store(packed, Ordering::Relaxed);
    }
    (packed as u8, (packed >> 8) as u8)
}

/// The OKLab colour of every 16-colour mix of 1, 2 and 3 quarters (`[a][b][k − 1]`, `b` in `k` of 4
/// samples), built on first use: every bucket's search scores all 136 pairs, and the cube roots were
/// most of a 16-colour first frame (issue #16). Entries 0–15 of [`entries`].
fn ansi16_mixes() -> &'static [[[Vec3; 3]; 16]; 16] {
    static MIXES: OnceLock<[[[Vec3; 3]; 16]; 16]> = OnceLock::new();
    MIXES.get_or_init(|| {
        let linear_of = &entries().linear;
        std::array::from_fn(|a| {
            std::array::from_fn(|b| {
                std::array::from_fn(|k| oklab(linear_of[a].lerp(linear_of[b], (k + 1) as f32 / 4.0)))
            })
        })
    })
}

/// The best pair for `rgb` among the palette's candidates (see [`dither`]); the nearer entry first.
fn search_pair(rgb: [u8; 3], palette: Palette) -> (u8, u8) {
    let Entries { linear: linear_of, oklab: oklab_of } = entries();
    let target_linear = Vec3::from_array(rgb.map(|v| srgb_to_linear(f32::from(v) / 255.0)));
    let target = oklab(target_linear);
    let mut candidates = [0u8; 16];
    let n = match palette {
        Palette::Ansi16 => {
            candidates = std::array::from_fn(|i| i as u8);
            16
        }
        Palette::Xterm256 => {
            // The corners of the cube cell around the colour and the two greys around its mean: the
            // entries within one palette step of it, where every useful mix lies.
            let lo = rgb.map(|v| CUBE_LEVELS.iter().rposition(|&l| l <= v).unwrap_or(0));
            let mut n = 0;
            for corner in 0..8 {
                let [r, g, b] = [0, 1, 2].map(|k| (lo[k] + (corner >> k & 1)).min(5) as u8);
                let index = 16 + 36 * r + 6 * g + b;
                if !candidates[..n].contains(&index) {
                    candidates[n] = index;
                    n += 1;
                }
            }
            let mean = rgb.iter().map(|&v| f32::from(v)).sum::<f32>() / 3.0;
            let below = ((mean - 8.0) / 10.0).floor().clamp(0.0, 23.0) as u8;
            candidates[n] = 232 + below;
            candidates[n + 1] = 232 + (below + 1).min(23);
            n + 2
        }
    };
    let candidates = &candidates[..n];
    let windows = windows();
    let mut best = (f32::INFINITY, 0u8, 0u8);
    for (i, &a) in candidates.iter().enumerate() {
        for &b in &candidates[i..] {
            let r = mix_ratio(target_linear, a, b);
            // Scored as the eye sees it at the least: each 2×2 window of the pattern shows the mean of its
            // samples, k of 4 of them `b`. The OKLab error summed over the windows counts both the mix's
            // own error and its grain (sparse far-apart dots miss in most windows).
            let mut windows_with = [0u32; 5];
            for window in &windows {
                windows_with[window.iter().filter(|&&t| r > t).count()] += 1;
            }
            let (pa, pb) = (linear_of[usize::from(a)], linear_of[usize::from(b)]);
            let seen = |k: usize| match k {
                0 => oklab_of[usize::from(a)],
                4 => oklab_of[usize::from(b)],
                _ if palette == Palette::Ansi16 => ansi16_mixes()[usize::from(a)][usize::from(b)][k - 1],
                _ => oklab(pa.lerp(pb, k as f32 / 4.0)),
            };
            let score = (0..5)
                .filter(|&k| windows_with[k] > 0)
                .map(|k| windows_with[k] as f32 * seen(k).distance(target))
                .sum::<f32>();
            if score < best.0 {
                best = if r <= 0.5 { (score, a, b) } else { (score, b, a) };
            }
        }
    }
    (best.1, best.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pure_colours_map_to_their_obvious_indices() {
        assert_eq!(xterm256([255, 0, 0]), 196);
        assert_eq!(xterm256([0, 255, 0]), 46);
        assert_eq!(xterm256([0, 0, 255]), 21);
        assert_eq!(xterm256([0, 0, 0]), 16);
        assert_eq!(xterm256([255, 255, 255]), 231);
        assert_eq!(ansi16([255, 0, 0]), 9);
        assert_eq!(ansi16([0, 0, 0]), 0);
        assert_eq!(ansi16([200, 200, 200]), 7);
        assert_eq!(quantize(Vec3::new(1.0, 0.0, 0.0), ColorDepth::TrueColor), Color::Rgb(255, 0, 0));
        assert_eq!(quantize(Vec3::ONE, ColorDepth::None), Color::Default);
    }

    #[test]
    fn xterm256_tables_match_the_direct_search() {
        // The search the tables are built from, written out per colour.
        let reference = |rgb: [u8; 3]| {
            let level = |v: u8| (0..6).min_by_key(|&k| CUBE_LEVELS[k].abs_diff(v)).unwrap_or(0);
            let [r, g, b] = rgb.map(level);
            let cube = (16 + 36 * r + 6 * g + b) as u8;
            let mean = (u32::from(rgb[0]) + u32::from(rgb[1]) + u32::from(rgb[2])) as f32 / 3.0;
            let grey = 232 + ((mean - 8.0) / 10.0).round().clamp(0.0, 23.0) as u8;
            if distance2(xterm_rgb(grey), rgb) < distance2(xterm_rgb(cube), rgb) { grey } else { cube }
        };
        // Every 13th colour (checked exhaustively once; all 2^24 take a while in the test profile).
        for key in (0..1u32 << 24).step_by(13) {
            let rgb = [(key >> 16) as u8, (key >> 8) as u8, key as u8];
            assert_eq!(xterm256(rgb), reference(rgb), "{rgb:?}");
        }
    }

    #[test]
    fn greys_go_to_the_grey_ramp() {
        for (v, index) in [(8, 232), (128, 244), (238, 255), (100, 241)] {
            assert_eq!(xterm256([v, v, v]), index, "grey {v}");
        }
        // Cube greys that are exact stay in the cube.
        assert_eq!(xterm256([95, 95, 95]), 59);
    }

    #[test]
    fn every_palette_entry_round_trips() {
        for index in 16..=255u8 {
            let rgb = xterm_rgb(index);
            assert_eq!(xterm_rgb(xterm256(rgb)), rgb, "index {index}");
        }
        for (index, &rgb) in ANSI16.iter().enumerate() {
            assert_eq!(usize::from(ansi16(rgb)), index);
        }
    }

    fn linear(rgb: [u8; 3]) -> Vec3 {
        Vec3::from_array(rgb.map(|v| srgb_to_linear(f32::from(v) / 255.0)))
    }

    /// A palette entry is shown as itself on every sample: no grain where none is needed.
    #[test]
    fn palette_entries_dither_to_themselves() {
        let all = |rgb: [u8; 3], depth| {
            (0..4)
                .flat_map(|y| (0..4).map(move |x| threshold(x, y)))
                .map(move |t| dither(linear(rgb), rgb, depth, t))
        };
        for index in 16..=255u8 {
            let rgb = xterm_rgb(index);
            assert!(all(rgb, ColorDepth::Ansi256).all(|c| c == Color::Indexed(index)), "index {index}");
        }
        for index in 0..16u8 {
            let rgb = xterm_rgb(index);
            assert!(all(rgb, ColorDepth::Ansi16).all(|c| c == Color::Indexed(index)), "index {index}");
        }
    }

    /// Over a 4×4 block of thresholds the mix averages (linear light) to the colour, within what the
    /// palette can reach: the mean of a tile is nearer the colour than plain nearest quantization is.
    #[test]
    fn a_tile_of_dithered_samples_averages_to_the_colour() {
        let mut seed = 0x1234_5678_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed >> 24) as u8
        };
        for depth in [ColorDepth::Ansi256, ColorDepth::Ansi16] {
            let (mut dithered, mut plain) = (0.0, 0.0);
            for _ in 0..500 {
                let rgb = [next(), next(), next()];
                let target = linear(rgb);
                let shown = |c: Color| match c {
                    Color::Indexed(i) => linear(xterm_rgb(i)),
                    other => panic!("{other:?}"),
                };
                let mean =
                    (0..16).map(|k| shown(dither(target, rgb, depth, threshold(k % 4, k / 4)))).sum::<Vec3>()
                        / 16.0;
                dithered += oklab(mean).distance(oklab(target));
                plain += oklab(shown(quantize_srgb8(rgb, depth))).distance(oklab(target));
            }
            assert!(dithered < 0.5 * plain, "{depth:?}: dithered {dithered}, plain {plain}");
        }
    }

    #[test]
    fn a_mix_found_from_the_last_bucket_is_the_mix() {
        // colours walking through buckets and back, in both palettes: the kept pair is used only
        // within its bucket
        for depth in [ColorDepth::Ansi256, ColorDepth::Ansi16] {
            let mut last = None;
            let mut kept = 0;
            for k in 0..3000u32 {
                let rgb = [(k / 5 % 256) as u8, (k / 11 % 256) as u8, (k * 3 % 256) as u8];
                let before = last;
                assert_eq!(Mix::of_near(rgb, depth, &mut last), Mix::of(rgb, depth), "{rgb:?} {depth:?}");
                kept += usize::from(before.is_some() && before == last);
            }
            assert!(kept > 100, "the pair is kept along a bucket: {kept}");
        }
    }

    #[test]
    fn thresholds_cover_every_2x2_window_evenly() {
        for (x0, y0) in [(0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (3, 5), (4, 6)] {
            let mut quarters =
                [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(dx, dy)| (threshold(x0 + dx, y0 + dy) * 4.0) as usize);
            quarters.sort_unstable();
            assert_eq!(quarters, [0, 1, 2, 3], "block at ({x0}, {y0})");
        }
    }
}
