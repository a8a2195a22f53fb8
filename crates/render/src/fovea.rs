//! The foveated viewport (issue #39): the middle of a wide view gets more samples per degree, its
//! edges fewer, so far openings stay several columns wide while the whole field stays on screen.
//!
//! Why: a level view down a generated corridor (cells 4 units, the eye 2 from each side) at 120
//! columns over the walk's ~119° field gives a side opening `k` cells ahead `8f/(16k² − 4)` columns,
//! `f` ≈ 36 columns a unit of tan: half a column at six cells. A narrower field magnifies it but loses
//! the nearest cells and, nose to a wall, the wall's ends. So the field stays wide and the viewport
//! does the magnifying where far things are: in the middle.
//!
//! How: each axis of NDC is cut into bands, and within a band NDC → screen is affine (NVIDIA's
//! multi-resolution viewports). Every band × band tile is then an ordinary viewport of the *same*
//! projection: the pipeline draws each tile with its own NDC → grid matrix ([`Eye::tiles`]), lines stay
//! straight inside a tile and bend only where tiles meet, and depth, the portal pass and clipping are
//! exactly those of the unwarped view. The warp is odd, monotone and fixes −1, 0 and +1, so the
//! frame's edges and centre show what they showed before; both axes use the same bands, so the middle
//! tile is magnified alike across and down, with no stretch.
//!
//! [`Eye::tiles`]: super::Eye::tiles

/// A view this wide (degrees across) or narrower is drawn unwarped: the look-ahead lens (`z`, 30°)
/// magnifies already.
pub const MIN_HFOV_DEG: f32 = 60.0;

/// Fewer samples than this along an axis: no warp (the bands would collapse into single samples).
const MIN_SAMPLES: usize = 24;

/// The warp on the positive half of an axis: band edges as (NDC, screen) pairs between (0, 0) and
/// (1, 1). Sampled from `screen = asinh(a·ndc) / asinh(a)` at a = 12 (a centre magnification of
/// about 3.1, (1/3) ÷ 0.106, after the linear bands): down a generated corridor at 120×40 a side opening 3 cells ahead
/// then spans ~5 columns (2 unwarped), 4 cells ~3.5 (1.1), 6 cells ~1.5 (0.5), and one at one cell
/// keeps ~20 (24).
pub const ACROSS: &[(f32, f32)] = &[(0.106, 1.0 / 3.0), (0.343, 2.0 / 3.0)];

/// The same down the view: its middle band as across (the middle tile magnified alike both ways),
/// the rest one band.
pub const DOWN: &[(f32, f32)] = ACROSS;

/// The most band edges an axis has (−1, the knots on both sides, 1).
const MAX_EDGES: usize = 2 * 2 + 2;

/// The warp of one axis for a grid `samples` long: odd, monotone, piecewise linear, its band edges on
/// whole samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisWarp {
    /// Band edges in NDC, ascending from −1 to 1.
    ndc: [f32; MAX_EDGES],
    /// The same edges on the screen (warped NDC, −1 to 1), each on a whole sample.
    screen: [f32; MAX_EDGES],
    /// How many of `ndc` and `screen` are edges.
    edges: usize,
}

impl AxisWarp {
    /// The warp for an axis of `samples` samples, or `None` where the grid is too small to warp.
    #[must_use]
    pub fn new(samples: usize, knots: &[(f32, f32)]) -> Option<AxisWarp> {
        if samples < MIN_SAMPLES || 2 * knots.len() + 2 > MAX_EDGES {
            return None;
        }
        let n = samples as f32;
        let (mut ndc, mut screen) = ([0.0; MAX_EDGES], [0.0; MAX_EDGES]);
        let edges = 2 * knots.len() + 2;
        let last = edges - 1;
        (ndc[0], screen[0], ndc[last], screen[last]) = (-1.0, -1.0, 1.0, 1.0);
        for (k, &(_, s)) in knots.iter().enumerate() {
            // The knot moved to the nearest sample edge, along the unsnapped warp.
            let snapped = (((s + 1.0) * 0.5 * n).round() / n) * 2.0 - 1.0;
            let at = unsnapped_to_ndc(knots, snapped);
            (ndc[knots.len() + 1 + k], screen[knots.len() + 1 + k]) = (at, snapped);
            (ndc[knots.len() - k], screen[knots.len() - k]) = (-at, -snapped);
        }
        // Odd sample counts: the mirrored knot is off a sample edge by half a sample; snap it too.
        for s in &mut screen[1..last] {
            *s = ((*s + 1.0) * 0.5 * n).round() / n * 2.0 - 1.0;
        }
        let increasing = |v: &[f32]| v[..edges].windows(2).all(|w| w[1] > w[0]);
        (increasing(&screen) && increasing(&ndc)).then_some(AxisWarp { ndc, screen, edges })
    }

    /// NDC → screen (both in [−1, 1]); beyond ±1 the outer bands' lines continue.
    #[must_use]
    pub fn to_screen(&self, ndc: f32) -> f32 {
        let k = band_of(&self.ndc[..self.edges], ndc);
        let t = (ndc - self.ndc[k]) / (self.ndc[k + 1] - self.ndc[k]);
        self.screen[k] + t * (self.screen[k + 1] - self.screen[k])
    }

    /// Screen → NDC: the inverse of [`AxisWarp::to_screen`].
    #[must_use]
    pub fn to_ndc(&self, screen: f32) -> f32 {
        let k = band_of(&self.screen[..self.edges], screen);
        let t = (screen - self.screen[k]) / (self.screen[k + 1] - self.screen[k]);
        self.ndc[k] + t * (self.ndc[k + 1] - self.ndc[k])
    }

    /// The bands, ascending: each one's NDC range and screen range.
    pub fn bands(&self) -> impl Iterator<Item = ([f32; 2], [f32; 2])> + '_ {
        (0..self.edges - 1).map(|k| ([self.ndc[k], self.ndc[k + 1]], [self.screen[k], self.screen[k + 1]]))
    }

    /// The magnification of the middle band: screen per NDC there (1 for no warp).
    #[must_use]
    pub fn centre_magnification(&self) -> f32 {
        let k = self.edges / 2 - 1;
        (self.screen[k + 1] - self.screen[k]) / (self.ndc[k + 1] - self.ndc[k])
    }
}

/// The band `x` falls in (the first or the last for values beyond the ends).
fn band_of(edges: &[f32], x: f32) -> usize {
    let inner = &edges[1..edges.len() - 1];
    inner.iter().take_while(|&&e| x >= e).count()
}

/// The warp's inverse before its knots are snapped to samples.
fn unsnapped_to_ndc(knots: &[(f32, f32)], screen: f32) -> f32 {
    let (mut n0, mut s0) = (0.0, 0.0);
    let a = screen.abs();
    for &(n1, s1) in knots.iter().chain(&[(1.0, 1.0)]) {
        if a <= s1 {
            return (n0 + (a - s0) / (s1 - s0) * (n1 - n0)).copysign(screen);
        }
        (n0, s0) = (n1, s1);
    }
    screen
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn small_grids_are_not_warped() {
        assert_eq!(AxisWarp::new(MIN_SAMPLES - 1, ACROSS), None);
        assert!(AxisWarp::new(MIN_SAMPLES, ACROSS).is_some());
    }

    #[test]
    fn the_middle_is_magnified_and_the_edges_squeezed() {
        let w = AxisWarp::new(120, ACROSS).unwrap();
        assert!(w.centre_magnification() > 2.5, "{}", w.centre_magnification());
        let outer = w.bands().last().unwrap();
        assert!((outer.1[1] - outer.1[0]) < (outer.0[1] - outer.0[0]), "the outer band squeezed");
    }

    proptest! {
        #![proptest_config(mazewalk_testkit::config())]
        /// Odd, monotone, fixing −1, 0 and 1, inverted by `to_ndc`, band edges on whole samples,
        /// for every grid size.
        #[test]
        fn the_warp_is_an_odd_monotone_bijection_with_edges_on_samples(
            samples in MIN_SAMPLES..3000usize,
            a in -1.0f32..1.0,
            b in -1.0f32..1.0,
        ) {
            for knots in [ACROSS, DOWN] {
            let w = AxisWarp::new(samples, knots).unwrap();
            for x in [-1.0f32, 0.0, 1.0] {
                prop_assert!((w.to_screen(x) - x).abs() < 1e-6);
            }
            prop_assert!((w.to_screen(-a) + w.to_screen(a)).abs() < 0.5 / samples as f32 * 2.0 + 1e-5);
            if a < b {
                prop_assert!(w.to_screen(a) < w.to_screen(b));
            }
            prop_assert!((w.to_ndc(w.to_screen(a)) - a).abs() < 1e-5);
            for (_, s) in w.bands() {
                for e in s {
                    let g = (e + 1.0) * 0.5 * samples as f32;
                    prop_assert!((g - g.round()).abs() < 1e-3, "{e} → sample {g}");
                }
            }
            }
        }
    }
}
