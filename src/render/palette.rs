//! Colour quantization: linear RGB → sRGB → the terminal's [`ColorDepth`].
//!
//! The renderer works in linear RGB; colours are sRGB-encoded here, once, when quantized (colours from
//! files that are meant as display colours should go through [`srgb_to_linear`]
//! first). Nearest colours are by squared distance in sRGB 0..255. The palettes are xterm's defaults.

use std::sync::OnceLock;

use glam::Vec3;

use super::shade::{Srgb8Tables, linear_to_srgb, srgb_to_linear};
use crate::frame::{Color, ColorDepth};

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
    let tables = Srgb8Tables::get();
    linear.to_array().map(|c| tables.encode(c))
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
pub fn quantize_srgb8(rgb: [u8; 3], depth: ColorDepth) -> Color {
    match depth {
        ColorDepth::None => Color::Default,
        ColorDepth::Ansi16 => Color::Indexed(ansi16(rgb)),
        ColorDepth::Ansi256 => Color::Indexed(xterm256(rgb)),
        ColorDepth::TrueColor => Color::Rgb(rgb[0], rgb[1], rgb[2]),
    }
}

/// A colour shown as a shade glyph mixing two ANSI colours: `glyph` in `fg` over `bg`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Dither {
    /// `' '` (bg only), `'░'` (¼ fg), `'▒'` (½) or `'▓'` (¾).
    pub glyph: char,
    /// ANSI index 0–15 of the ink.
    pub fg: u8,
    /// ANSI index 0–15 of the background.
    pub bg: u8,
}

/// The shade glyphs by the fraction of ink they show (0, ¼, ½, ¾).
pub const SHADES: [char; 4] = [' ', '░', '▒', '▓'];

/// The ANSI-16 mix of two colours and a shade glyph that comes nearest to an sRGB colour.
///
/// Mixes are averaged in linear light (what the eye does with a fine pattern) and compared in sRGB.
/// Looked up at 32 levels per channel; each level's answer is searched the first time a frame needs
/// it and kept (searching all 32,768 up front took ~45 ms, a first frame's whole budget many times
/// over; a frame needs a few hundred). The 16 colours themselves are exact.
#[must_use]
pub fn ansi16_dither(rgb: [u8; 3]) -> Dither {
    use std::sync::atomic::{AtomicU16, Ordering};
    /// Per level: 0 = not searched yet, else 1 + glyph index · 256 + fg · 16 + bg.
    static MEMO: OnceLock<Box<[AtomicU16]>> = OnceLock::new();
    static CANDIDATES: OnceLock<Vec<(Dither, [f32; 3])>> = OnceLock::new();
    if let Some(exact) = ANSI16.iter().position(|&c| c == rgb) {
        return Dither { glyph: ' ', fg: exact as u8, bg: exact as u8 }; // the levels are coarser
    }
    let [r, g, b] = rgb.map(|v| usize::from(v >> 3));
    let key = (r << 10) | (g << 5) | b;
    let memo = MEMO.get_or_init(|| (0..32 * 32 * 32).map(|_| AtomicU16::new(0)).collect());
    let unpack = |packed: u16| {
        let packed = packed - 1;
        Dither {
            glyph: SHADES[usize::from(packed >> 8)],
            fg: ((packed >> 4) & 15) as u8,
            bg: (packed & 15) as u8,
        }
    };
    match memo[key].load(Ordering::Relaxed) {
        0 => {}
        packed => return unpack(packed),
    }
    let candidates = CANDIDATES.get_or_init(dither_candidates);
    let target = [r, g, b].map(|v| ((v << 3) + 4) as f32);
    let d2 = |c: &[f32; 3]| (0..3).map(|k| (c[k] - target[k]).powi(2)).sum::<f32>();
    let best = candidates
        .iter()
        .min_by(|a, b| d2(&a.1).total_cmp(&d2(&b.1)))
        .map_or(Dither { glyph: ' ', fg: 0, bg: 0 }, |c| c.0);
    let glyph = SHADES.iter().position(|&g| g == best.glyph).unwrap_or(0) as u16;
    memo[key].store(1 + (glyph << 8) + (u16::from(best.fg) << 4) + u16::from(best.bg), Ordering::Relaxed);
    best
}

/// Every solid ANSI colour and every ¼, ½, ¾ mix of two different ones, with its sRGB appearance.
fn dither_candidates() -> Vec<(Dither, [f32; 3])> {
    let linear = ANSI16.map(|c| Vec3::from_array(c.map(|v| srgb_to_linear(f32::from(v) / 255.0))));
    let mut out = Vec::new();
    for bg in 0..16u8 {
        out.push((Dither { glyph: ' ', fg: bg, bg }, ANSI16[usize::from(bg)].map(f32::from)));
        for fg in bg + 1..16 {
            for (k, &glyph) in SHADES.iter().enumerate().skip(1) {
                let ink = k as f32 / 4.0;
                let mix = linear[usize::from(bg)].lerp(linear[usize::from(fg)], ink);
                out.push((Dither { glyph, fg, bg }, mix.to_array().map(|c| linear_to_srgb(c) * 255.0)));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_remembered_16_colour_mix_is_the_one_searched() {
        let candidates = dither_candidates();
        for key in (0..32 * 32 * 32).step_by(97) {
            let rgb = [key >> 10, (key >> 5) & 31, key & 31].map(|v| ((v << 3) + 4) as u8);
            if ANSI16.contains(&rgb) {
                continue;
            }
            let d2 = |c: &[f32; 3]| (0..3).map(|k| (c[k] - f32::from(rgb[k])).powi(2)).sum::<f32>();
            let best = candidates.iter().min_by(|a, b| d2(&a.1).total_cmp(&d2(&b.1))).unwrap().0;
            assert_eq!(ansi16_dither(rgb), best, "{rgb:?} searched");
            assert_eq!(ansi16_dither(rgb), best, "{rgb:?} remembered");
        }
    }

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
            let d = ansi16_dither(rgb);
            assert_eq!(d.glyph, ' ', "solid {index}: {d:?}");
        }
    }
}
