//! Infinite far planes and reversed depth, in every convention: what each projection means (where
//! the near and far planes land, which way depth runs), that the infinite forms are the limits of the
//! finite ones as far → ∞ (glam has no OpenGL-range infinite projection to compare with; the [0, 1]
//! forms are also checked against glam in `math_oracle.rs`), that the clip planes keep exactly the
//! depths between near and far whichever way depth runs, and the precision reversed depth is for.
//!
//! Tolerances are stated beside each check, relative to the magnitudes involved (ε = 6e-8).

mod common;

use common::*;
use glam::{Mat4, Vec4};
use mazewalk_math::{ClipPlane, Convention, DepthRange, clip_polygon};
use proptest::prelude::*;

/// The four ways a perspective can map depth.
#[derive(Clone, Copy, Debug)]
enum Mapping {
    Forward,
    Reverse,
    Infinite,
    InfiniteReverse,
}

const MAPPINGS: [Mapping; 4] =
    [Mapping::Forward, Mapping::Reverse, Mapping::Infinite, Mapping::InfiniteReverse];

impl Mapping {
    fn projection(self, conv: Convention, fov: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
        match self {
            Mapping::Forward => conv.perspective(fov, aspect, near, far),
            Mapping::Reverse => conv.perspective_reverse(fov, aspect, near, far),
            Mapping::Infinite => conv.perspective_infinite(fov, aspect, near),
            Mapping::InfiniteReverse => conv.perspective_infinite_reverse(fov, aspect, near),
        }
        .unwrap()
    }

    /// The far plane's distance: `far`, or infinity.
    fn far(self, far: f32) -> f32 {
        match self {
            Mapping::Forward | Mapping::Reverse => far,
            Mapping::Infinite | Mapping::InfiniteReverse => f32::INFINITY,
        }
    }

    /// NDC depth of the near and far planes.
    fn ends(self, range: DepthRange) -> (f32, f32) {
        match self {
            Mapping::Forward | Mapping::Infinite => (range.near(), range.far()),
            Mapping::Reverse | Mapping::InfiniteReverse => (range.far(), range.near()),
        }
    }
}

fn arb_mapping() -> impl Strategy<Value = Mapping> {
    prop::sample::select(MAPPINGS.to_vec())
}

/// NDC depth of the point at `distance` straight ahead.
fn depth(conv: Convention, proj: Mat4, distance: f32) -> f32 {
    proj.project_point3(conv.forward() * distance).z
}

/// `far / near` log-uniform in `[10^lo, 10^hi]`.
fn arb_ratio(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    (lo..hi).prop_map(|e| 10f32.powf(e))
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn near_and_far_land_where_the_mapping_says_and_depth_runs_one_way(
        conv in arb_convention(), mapping in arb_mapping(), (fov, aspect, n, f) in arb_perspective(),
        u in 0.0f32..1.0, v in 0.0f32..1.0,
    ) {
        let proj = mapping.projection(conv, fov, aspect, n, f);
        let (at_near, at_far) = mapping.ends(conv.depth_range());
        // One projective divide of a few roundings: 1e-5 of the depth scale, which for the finite
        // forms is (f+n)/(f-n) <= 200 (f/n >= 1.01).
        let scale = (f + n) / (f - n);
        prop_assert!(close(depth(conv, proj, n), at_near, 1e-5, scale), "near → {}", depth(conv, proj, n));
        let far = mapping.far(f);
        if far.is_finite() {
            prop_assert!(close(depth(conv, proj, far), at_far, 1e-5, scale), "far → {}", depth(conv, proj, far));
        } else {
            // At infinity only the limit: a point 1e6 near planes away is n/d or 2n/d = 1e-6 or 2e-6
            // short of it (checked to 4e-6, room for the rounding near ±1), and not on it.
            let z = depth(conv, proj, n * 1e6);
            prop_assert!(close(z, at_far, 4e-6, 1.0) && z != at_far, "1e6·near → {z}");
        }
        // Monotonic, towards the far end: a point farther away is nearer `at_far` (or equal, once f32
        // runs out of values).
        let span = if far.is_finite() { far - n } else { 1e3 * n };
        let (d1, d2) = (n + span * u.min(v), n + span * u.max(v));
        let (z1, z2) = (depth(conv, proj, d1), depth(conv, proj, d2));
        prop_assert!((z2 - z1) * (at_far - at_near) >= -1e-6, "d {d1} → {z1}, d {d2} → {z2}");
    }

    #[test]
    fn reversed_depth_is_forward_depth_mirrored_in_the_range(
        conv in arb_convention(), (fov, aspect, n, f) in arb_perspective(), u in 0.0f32..1.0,
        p in arb_point(10.0),
    ) {
        // Reversed depth changes z only: z → -z on [-1, 1], z → 1 - z on [0, 1]; x, y and w stay.
        let mirror = |z: f32| conv.depth_range().near() + 1.0 - z;
        let view = p + conv.forward() * (n + (f - n) * u);
        for (forward, reverse) in [
            (conv.perspective(fov, aspect, n, f).unwrap(), conv.perspective_reverse(fov, aspect, n, f).unwrap()),
            (conv.perspective_infinite(fov, aspect, n).unwrap(), conv.perspective_infinite_reverse(fov, aspect, n).unwrap()),
        ] {
            let (a, b) = (forward * view.extend(1.0), reverse * view.extend(1.0));
            // In clip space, relative to the point's largest clip coordinate: a few roundings each.
            let scale = a.abs().max_element();
            prop_assert!(close4(a.with_z(0.0), b.with_z(0.0), 1e-5, scale), "{a} vs {b}");
            prop_assert!(close(mirror(a.z / a.w), b.z / b.w, 1e-5, (f + n) / (f - n)), "{a} vs {b}");
        }
        // A near plane beyond the far one is the same reversed projection.
        let swapped = conv.perspective(fov, aspect, f, n).unwrap();
        prop_assert!(mat4_close(conv.perspective_reverse(fov, aspect, n, f).unwrap(), swapped, 1e-5));
    }

    #[test]
    fn infinite_projections_are_the_limits_of_the_finite_ones(
        conv in arb_convention(), (fov, aspect, n, _) in arb_perspective(), ratio in arb_ratio(2.0, 12.0),
        reverse in any::<bool>(),
    ) {
        let f = n * ratio;
        let (finite, infinite) = if reverse {
            (conv.perspective_reverse(fov, aspect, n, f).unwrap(), conv.perspective_infinite_reverse(fov, aspect, n).unwrap())
        } else {
            (conv.perspective(fov, aspect, n, f).unwrap(), conv.perspective_infinite(fov, aspect, n).unwrap())
        };
        // The depth coefficients differ from their limits by n/(f-n) relative (2n/(f-n) for a on
        // [-1, 1], 2n²/(f-n) against 2n for b): the finite matrix converges to the infinite one at
        // that rate, and reaches it in f32 once n/f is below rounding (1e-5 for the x, y scales the
        // two compute through different formulas).
        let rate = 2.0 * n / (f - n);
        prop_assert!(mat4_close(finite, infinite, rate + 1e-5), "f/n = {ratio}\nfinite   {finite}\ninfinite {infinite}");
    }

    #[test]
    fn the_depth_planes_keep_exactly_the_depths_between_near_and_far(
        conv in arb_convention(), mapping in arb_mapping(), (fov, aspect, n, f) in arb_perspective(),
        before in 0.0f32..1.0, beyond in (1.5f32..3.0, 1.5f32..3.0), lateral in (arb_point(1.0), arb_point(1.0), arb_point(1.0)),
    ) {
        // A view-space triangle from before the near plane (behind the eye, up to -far) to beyond the
        // far plane, clipped by the two depth planes alone.
        let (start, (k1, k2)) = (n / 2.0 - before * f, beyond);
        let corners = [(start, lateral.0), (f * k1, lateral.1), (f * k2, lateral.2)];
        let proj = mapping.projection(conv, fov, aspect, n, f);
        let clip: Vec<Vec4> = corners.iter().map(|&(d, side)| proj * (side.with_z(0.0) + conv.forward() * d).extend(1.0)).collect();
        let (mut out, mut scratch) = (Vec::new(), Vec::new());
        let planes = ClipPlane::Near.bit() | ClipPlane::Far.bit();
        clip_polygon(&clip, planes, conv.depth_range(), &mut out, &mut scratch);
        // w is the distance in front of the eye. A plane's distance at a cut vertex is off by a few
        // ULPs of the clip coordinates (64ε·scale), and it changes by |rate| per unit of distance
        // along the view axis, so the cut's distance is known to 64ε·scale / |rate|. The rate is
        // about 2 (or 1) at the near plane but only n/(f-n) at a finite far plane, forward or
        // reversed: in clip space z and w are nearly equal there (which is the depth-precision
        // problem itself, before the divide).
        let scale = clip.iter().map(|c| c.z.abs().max(c.w.abs())).fold(0.0, f32::max);
        let (near_plane, far_plane) = match mapping {
            Mapping::Forward | Mapping::Infinite => (ClipPlane::Near, ClipPlane::Far),
            Mapping::Reverse | Mapping::InfiniteReverse => (ClipPlane::Far, ClipPlane::Near),
        };
        let tol = |plane: ClipPlane| {
            let rate = plane.distance(proj * conv.forward().extend(0.0), conv.depth_range());
            64.0 * f32::EPSILON * scale / rate.abs()
        };
        let far = mapping.far(f);
        let (lo, hi) = out.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), c| (lo.min(c.w), hi.max(c.w)));
        prop_assert!(!out.is_empty(), "{mapping:?} lost the triangle");
        prop_assert!((lo - n).abs() <= tol(near_plane), "{mapping:?}: nearest kept {lo}, near plane {n} (±{})", tol(near_plane));
        if far.is_finite() {
            prop_assert!((hi - far).abs() <= tol(far_plane), "{mapping:?}: farthest kept {hi}, far plane {far} (±{})", tol(far_plane));
        } else {
            prop_assert_eq!(hi, f * k1.max(k2), "{:?}: the farthest corner is kept", mapping);
        }
    }
}

#[test]
fn reversed_depth_on_zero_to_one_resolves_a_centimetre_a_kilometre_away() {
    // What reversed depth is for (the README's table measures it): with near = 0.1, forward [0, 1]
    // depth is 1 - 0.1/d, whose f32 steps near 1 are 6e-8 apart while 1 cm at 1 km moves it 1e-9; the
    // reversed 0.1/d is near 1e-4, where the steps are 7e-12.
    let (near, far) = (0.1, 1000.0);
    let conv = Convention::RhZo;
    let resolves = |proj: Mat4| depth(conv, proj, 999.99) != depth(conv, proj, 1000.0);
    assert!(!resolves(conv.perspective(1.0, 1.0, near, far).unwrap()));
    assert!(!resolves(conv.perspective_infinite(1.0, 1.0, near).unwrap()));
    assert!(resolves(conv.perspective_reverse(1.0, 1.0, near, far).unwrap()));
    assert!(resolves(conv.perspective_infinite_reverse(1.0, 1.0, near).unwrap()));
}

#[test]
fn new_projections_refuse_what_perspective_refuses() {
    use mazewalk_math::MathError;
    for conv in Convention::ALL {
        assert_eq!(
            conv.perspective_infinite(1.0, 1.0, 0.0),
            Err(MathError::DepthNotPositive { near: 0.0, far: f32::INFINITY })
        );
        assert_eq!(
            conv.perspective_infinite_reverse(0.0, 1.0, 1.0),
            Err(MathError::FovOutOfRange { fov: 0.0 })
        );
        assert_eq!(
            conv.perspective_infinite(1.0, 0.0, 1.0),
            Err(MathError::NotPositive { arg: "aspect", value: 0.0 })
        );
        assert!(matches!(
            conv.perspective_infinite_reverse(1.0, 1.0, f32::NAN),
            Err(MathError::NonFinite { arg: "near", .. })
        ));
        assert_eq!(
            conv.perspective_reverse(1.0, 1.0, 2.0, 2.0),
            Err(MathError::EmptyDepthRange { near: 2.0 })
        );
        assert_eq!(
            conv.perspective_reverse(1.0, 1.0, 1.0, -2.0),
            Err(MathError::DepthNotPositive { near: 1.0, far: -2.0 })
        );
        // 1/tan(fov/2)/aspect overflows for a tiny fov and aspect.
        assert_eq!(
            conv.perspective_infinite_reverse(1e-30, 1e-30, 1.0),
            Err(MathError::Overflow { what: "infinite perspective" })
        );
    }
    // On [-1, 1] the depth term is 2·near, which overflows where [0, 1]'s near does not.
    assert_eq!(
        Convention::RhGl.perspective_infinite(1.0, 1.0, 3e38),
        Err(MathError::Overflow { what: "infinite perspective" })
    );
    assert!(Convention::RhZo.perspective_infinite(1.0, 1.0, 3e38).is_ok());
}
