//! Shading: a headlight at the eye (Lambert plus ambient), distance fog, floor and ceiling colours.
//!
//! Small pure functions on linear RGB in 0..1, called per sample by the pipeline's shading closure.
//! Positions and normals are in view space (the eye at the origin); normals come through the normal
//! matrix and need not be unit length.

use glam::{Vec2, Vec3};

/// Lambert with a light at the eye, two-sided (walls are seen from both sides): `|n · l|` with `l` the
/// unit direction from the surface point `view` to the eye, in [0, 1]. 1.0 at the eye itself.
#[must_use]
pub fn headlight(normal_view: Vec3, view: Vec3) -> f32 {
    let (n, l) = (normal_view.normalize_or_zero(), (-view).normalize_or_zero());
    if l == Vec3::ZERO { 1.0 } else { n.dot(l).abs().min(1.0) }
}

/// Light reaching the eye from a surface: `ambient + (1 - ambient) · diffuse`, so unlit faces keep the
/// `ambient` fraction (0..1) of their colour and faces turned to the headlight get all of it.
#[must_use]
pub fn lit(albedo: Vec3, diffuse: f32, ambient: f32) -> Vec3 {
    albedo * (ambient + (1.0 - ambient) * diffuse.clamp(0.0, 1.0))
}

/// Linear distance fog: nothing before `start`, everything from `end` on, linear in between.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    /// The colour distant things fade to (linear RGB).
    pub color: Vec3,
    /// Distance (world units) where fog begins.
    pub start: f32,
    /// Distance where the fog is complete; `end <= start` means a hard cut at `start`.
    pub end: f32,
}

impl Fog {
    /// How much fog at `distance`: `clamp((distance - start) / (end - start), 0, 1)`.
    #[must_use]
    pub fn amount(&self, distance: f32) -> f32 {
        if self.end <= self.start {
            return if distance >= self.start { 1.0 } else { 0.0 };
        }
        ((distance - self.start) / (self.end - self.start)).clamp(0.0, 1.0)
    }

    /// `color` seen through the fog at `distance`.
    #[must_use]
    pub fn apply(&self, color: Vec3, distance: f32) -> Vec3 {
        color.lerp(self.color, self.amount(distance))
    }
}

/// A floor or ceiling colour with a faint checker on the maze plane, so sliding and turning show.
///
/// `world` is the point on the plane (x east, y north); squares are `period` world units wide; one square
/// colour is `base`, the other `base · (1 - contrast)` (contrast 0..1, about 0.15 reads as subtle).
#[must_use]
pub fn checker(base: Vec3, world: Vec2, period: f32, contrast: f32) -> Vec3 {
    // The square's parity in integers: `floor` and `rem_euclid` on floats are libm calls on baseline
    // x86-64, and this runs for every floor and ceiling sample.
    let cell = world / period;
    let odd = floor_is_odd(cell.x) != floor_is_odd(cell.y);
    if odd { base * (1.0 - contrast.clamp(0.0, 1.0)) } else { base }
}

/// Whether `v.floor()` is odd, in integers (exact for |v| < 2^63; NaN counts as even, like 0).
fn floor_is_odd(v: f32) -> bool {
    let t = v as i64; // truncates toward zero, saturating
    let floor = if (t as f32) > v { t.wrapping_sub(1) } else { t };
    floor & 1 == 1
}

/// The linear value of an sRGB-encoded channel (for colours read from files or the CLI).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// The sRGB encoding of a linear channel in 0..1 (clamped; NaN → 0).
#[must_use]
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    if c <= 0.003_130_8 { c * 12.92 } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// [`linear_to_srgb`] by table, for the per-sample hot path (glyphs): within 2e-7 of it (a 20 000th of
/// an 8-bit step) everywhere in 0..1, several times faster than its `powf`.
///
/// Below the sRGB curve's linear toe (≤ 0.0031308) it is the same multiply. Above, the table holds the
/// exact curve at 512 points per octave of the input (read off the float's exponent and top 9 mantissa
/// bits, so the points crowd where the curve bends most) and interpolates linearly between them.
#[must_use]
pub fn linear_to_srgb_fast(c: f32) -> f32 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    if c <= 0.003_130_8 {
        return c * 12.92;
    }
    let table = SRGB_TABLE.get_or_init(srgb_table);
    // c in (2^-9, 1]: biased exponent 118..=127; index = octave · 512 + top 9 mantissa bits.
    let bits = c.to_bits();
    let i = ((bits >> SRGB_FRACTION_BITS) - SRGB_FIRST_KEY) as usize;
    let t = (bits & ((1 << SRGB_FRACTION_BITS) - 1)) as f32 * (1.0 / (1 << SRGB_FRACTION_BITS) as f32);
    let (a, b) = (table[i], table[i + 1]);
    a + (b - a) * t
}

/// Mantissa bits below the table index (23 - 9: 512 points per octave).
const SRGB_FRACTION_BITS: u32 = 14;
/// The table key of 2^-9 (biased exponent 118), the octave holding the toe's end 0.0031308.
const SRGB_FIRST_KEY: u32 = 118 << (23 - SRGB_FRACTION_BITS);
/// Keys from 2^-9 to 1.0 (biased exponent 127, mantissa 0) inclusive, plus one to interpolate towards.
const SRGB_TABLE_LEN: usize = 9 * 512 + 2;

static SRGB_TABLE: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();

fn srgb_table() -> Vec<f32> {
    (0..SRGB_TABLE_LEN as u32)
        .map(|k| linear_to_srgb(f32::from_bits((SRGB_FIRST_KEY + k) << SRGB_FRACTION_BITS)))
        .collect()
}

/// Relative luminance (Rec. 709 weights) of a linear colour.
#[must_use]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headlight_is_full_face_on_and_zero_edge_on_from_either_side() {
        let wall = Vec3::new(0.0, 0.0, -3.0);
        assert!((headlight(Vec3::Z, wall) - 1.0).abs() < 1e-6);
        assert!((headlight(-Vec3::Z * 5.0, wall) - 1.0).abs() < 1e-6); // back face, unnormalised
        assert!(headlight(Vec3::X, wall).abs() < 1e-6);
        assert_eq!(lit(Vec3::ONE, 0.0, 0.25), Vec3::splat(0.25));
    }

    #[test]
    fn fog_is_linear_between_start_and_end() {
        let fog = Fog { color: Vec3::ONE, start: 2.0, end: 6.0 };
        assert_eq!(fog.amount(1.0), 0.0);
        assert_eq!(fog.amount(4.0), 0.5);
        assert_eq!(fog.amount(9.0), 1.0);
        assert_eq!(fog.apply(Vec3::ZERO, 4.0), Vec3::splat(0.5));
    }

    #[test]
    fn the_srgb_table_matches_the_curve() {
        // Every 61st float in 0..=1 (about 17 million), the ends, the toe and NaN.
        let step = 61;
        let mut worst = 0.0f32;
        for bits in (0..=1.0f32.to_bits()).step_by(step).chain([1.0f32.to_bits(), 0.003_130_8f32.to_bits()]) {
            let c = f32::from_bits(bits);
            worst = worst.max((linear_to_srgb_fast(c) - linear_to_srgb(c)).abs());
        }
        assert!(worst < 2e-7, "worst error {worst}");
        for c in [-1.0, 0.0, 1.0, 2.0, f32::NAN, f32::INFINITY] {
            assert_eq!(linear_to_srgb_fast(c), linear_to_srgb(c), "{c}");
        }
    }

    #[test]
    fn checker_alternates_by_square_and_srgb_round_trips() {
        let base = Vec3::splat(0.5);
        assert_eq!(checker(base, Vec2::new(0.5, 0.5), 1.0, 0.2), base);
        assert_eq!(checker(base, Vec2::new(1.5, 0.5), 1.0, 0.2), base * 0.8);
        assert_eq!(checker(base, Vec2::new(-0.5, 0.5), 1.0, 0.2), base * 0.8);
        for v in [-3.5f32, -2.0, -1.0, -0.5, -0.0, 0.0, 0.25, 1.0, 1.5, 2.999, 1.0e7 + 1.0, -1.0e9, 1.0e18] {
            let float_way = v.floor().rem_euclid(2.0) >= 1.0;
            assert_eq!(floor_is_odd(v), float_way, "{v}");
        }
        for c in [0.0, 0.002, 0.2, 0.5, 1.0] {
            assert!((srgb_to_linear(linear_to_srgb(c)) - c).abs() < 1e-5);
        }
    }
}
