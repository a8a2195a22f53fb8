//! Homogeneous clipping: the result is inside the input polygon and the clip volume, convex, and
//! stable under clipping again; inside polygons pass unchanged, outside ones vanish; shared edges are
//! cut at identical points.
//!
//! Tolerance: 1e-5 relative to the polygon's largest clip coordinate. A crossing is one lerp with a
//! parameter from one division, a few ULPs of the coordinates it mixes; six planes compound that.

mod common;

use glam::{Vec2, Vec4};
use mazewalk_math::{
    ClipPlane, ClipPlanes, ClipVertex, Coverage, DepthRange, classify, clip_polygon, outcode,
};
use proptest::prelude::*;

const REL: f32 = 1e-5;

/// A convex polygon in clip space, planar in 4D: `centre + a·cos θ·u + b·sin θ·v` for sorted angles,
/// with `u`, `v` orthonormal in R⁴, so it is strictly convex (points on an ellipse). Kept with its frame
/// so tests can map vertices back to 2D.
#[derive(Clone, Debug)]
struct Polygon {
    centre: Vec4,
    u: Vec4,
    v: Vec4,
    vertices: Vec<Vec4>,
}

impl Polygon {
    /// In-plane coordinates of `p`, and how far `p` is from the plane.
    fn to_plane(&self, p: Vec4) -> (Vec2, f32) {
        let d = p - self.centre;
        let (a, b) = (d.dot(self.u), d.dot(self.v));
        (Vec2::new(a, b), (d - a * self.u - b * self.v).length())
    }

    fn scale(&self) -> f32 {
        self.vertices.iter().map(|v| v.abs().max_element()).fold(1.0, f32::max)
    }
}

/// Coordinates within ±3 (the volume is ±w with w up to 3): polygons inside, outside and straddling.
/// Frames whose `u` and `v` are nearly dependent are rejected: their orthonormalized `v` is noise.
fn arb_convex_polygon() -> impl Strategy<Value = Polygon> {
    let vec4 = || (-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0).prop_map(Vec4::from);
    (
        vec4(),
        vec4(),
        vec4(),
        0.05f32..3.0,
        0.05f32..3.0,
        prop::collection::vec(0.0f32..std::f32::consts::TAU, 3..9),
    )
        .prop_filter_map("degenerate frame", |(centre, u, v, a, b, mut angles)| {
            let u = u.try_normalize()?;
            let v = (v - v.dot(u) * u).try_normalize()?;
            angles.sort_by(f32::total_cmp);
            angles.dedup_by(|x, y| (*x - *y).abs() < 1e-3); // coincident vertices are not a polygon
            (angles.len() >= 3).then_some(())?;
            let vertices = angles.iter().map(|t| centre + a * t.cos() * u + b * t.sin() * v).collect();
            Some(Polygon { centre, u, v, vertices })
        })
}

fn arb_depth() -> impl Strategy<Value = DepthRange> {
    prop::sample::select(vec![DepthRange::NegOneToOne, DepthRange::ZeroToOne])
}

fn clip(polygon: &[Vec4], depth: DepthRange) -> Vec<Vec4> {
    let (mut out, mut scratch) = (Vec::new(), Vec::new());
    clip_polygon(polygon, ClipPlanes::ALL, depth, &mut out, &mut scratch);
    out
}

/// 2D cross product of `b - a` and `c - a`: its sign says on which side of line `ab` point `c` lies.
fn cross(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    (b - a).perp_dot(c - a)
}

/// Whether the 2D polygon turns the same way at every vertex (within `tol`).
fn is_convex(points: &[Vec2], tol: f32) -> bool {
    let n = points.len();
    let turns: Vec<f32> =
        (0..n).map(|i| cross(points[i], points[(i + 1) % n], points[(i + 2) % n])).collect();
    turns.iter().all(|&t| t >= -tol) || turns.iter().all(|&t| t <= tol)
}

/// Distance from `p` to the segment `ab` (in R⁴).
fn segment_distance(p: Vec4, a: Vec4, b: Vec4) -> f32 {
    let ab = b - a;
    let t =
        if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + t * ab)).length()
}

/// Every vertex of `a` lies within `tol` of the boundary of polygon `b`.
fn on_boundary(a: &[Vec4], b: &[Vec4], tol: f32) -> bool {
    a.iter().all(|&p| (0..b.len()).any(|i| segment_distance(p, b[i], b[(i + 1) % b.len()]) <= tol))
}

/// A vertex with an attribute: its barycentric weights over the triangle it came from.
#[derive(Clone, Debug, PartialEq)]
struct Tagged {
    clip: Vec4,
    weights: glam::Vec3,
}

impl ClipVertex for Tagged {
    fn clip(&self) -> Vec4 {
        self.clip
    }
    fn lerp(&self, other: &Self, t: f32) -> Self {
        Tagged { clip: self.clip.lerp(other.clip, t), weights: self.weights.lerp(other.weights, t) }
    }
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn output_is_inside_the_input_and_the_volume_and_convex(polygon in arb_convex_polygon(), depth in arb_depth()) {
        let out = clip(&polygon.vertices, depth);
        let tol = REL * polygon.scale();
        let input_2d: Vec<Vec2> = polygon.vertices.iter().map(|&p| polygon.to_plane(p).0).collect();
        let out_2d: Vec<Vec2> = out.iter().map(|&p| polygon.to_plane(p).0).collect();
        for (&p, &p2) in out.iter().zip(&out_2d) {
            for plane in ClipPlane::ALL {
                prop_assert!(plane.distance(p, depth) >= -tol, "{p} outside {plane:?}");
            }
            prop_assert!(polygon.to_plane(p).1 <= tol, "{p} left the polygon's plane");
            // Inside every edge of the (counter-clockwise, by sorted angles) input polygon.
            let n = input_2d.len();
            for i in 0..n {
                prop_assert!(cross(input_2d[i], input_2d[(i + 1) % n], p2) >= -tol * polygon.scale(), "{p} outside the input");
            }
        }
        prop_assert!(out.is_empty() || out.len() >= 3);
        prop_assert!(is_convex(&out_2d, tol * polygon.scale()), "not convex: {out_2d:?}");
        prop_assert!(out.len() <= polygon.vertices.len() + 6); // each plane adds at most one vertex
    }

    #[test]
    fn clipping_twice_changes_nothing(polygon in arb_convex_polygon(), depth in arb_depth()) {
        let once = clip(&polygon.vertices, depth);
        let twice = clip(&once, depth);
        // A crossing can land a rounding error outside its plane and be cut again, adding a vertex on
        // an existing edge (anywhere along it, for a sliver), so compare the outlines: every vertex of
        // each lies on the other's boundary.
        let tol = 10.0 * REL * polygon.scale();
        prop_assert_eq!(once.is_empty(), twice.is_empty());
        prop_assert!(on_boundary(&once, &twice, tol) && on_boundary(&twice, &once, tol), "{once:?}\n{twice:?}");
    }

    #[test]
    fn inside_is_unchanged_and_outside_is_empty(
        polygon in arb_convex_polygon(), depth in arb_depth(), plane in prop::sample::select(ClipPlane::ALL.to_vec()),
    ) {
        let coverage = classify(&polygon.vertices, ClipPlanes::ALL, depth);
        let out = clip(&polygon.vertices, depth);
        match coverage {
            Coverage::Inside => prop_assert_eq!(&out, &polygon.vertices),
            Coverage::Outside => prop_assert!(out.is_empty()),
            Coverage::Straddling => {}
        }
        // Squeeze the polygon into the volume's middle (w = 1, |x|, |y| < 0.5, z in [0.25, 0.75]) …
        let inside: Vec<Vec4> = polygon.vertices.iter()
            .map(|p| Vec4::new(p.x / 7.0, p.y / 7.0, 0.5 + p.z / 13.0, 1.0)).collect();
        prop_assert_eq!(classify(&inside, ClipPlanes::ALL, depth), Coverage::Inside);
        prop_assert_eq!(clip(&inside, depth), inside.clone());
        // … then push it wholly past one plane.
        let shift = match plane {
            ClipPlane::Left => Vec4::new(-2.0, 0.0, 0.0, 0.0),
            ClipPlane::Right => Vec4::new(2.0, 0.0, 0.0, 0.0),
            ClipPlane::Bottom => Vec4::new(0.0, -2.0, 0.0, 0.0),
            ClipPlane::Top => Vec4::new(0.0, 2.0, 0.0, 0.0),
            ClipPlane::Near => Vec4::new(0.0, 0.0, -2.0, 0.0),
            ClipPlane::Far => Vec4::new(0.0, 0.0, 2.0, 0.0),
        };
        let outside: Vec<Vec4> = inside.iter().map(|p| *p + shift).collect();
        prop_assert_eq!(classify(&outside, ClipPlanes::ALL, depth), Coverage::Outside);
        prop_assert!(clip(&outside, depth).is_empty());
    }

    #[test]
    fn a_shared_edge_is_cut_identically_from_both_polygons(
        polygon in arb_convex_polygon(), other in (-3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0, -3.0f32..3.0), depth in arb_depth(),
    ) {
        // Two triangles sharing the edge ab, walked a→b in one and b→a in the other.
        let (a, b, c) = (polygon.vertices[0], polygon.vertices[1], polygon.vertices[2]);
        let d = Vec4::from(other);
        let tag = |clip, weights| Tagged { clip, weights };
        let first = [tag(a, glam::Vec3::X), tag(b, glam::Vec3::Y), tag(c, glam::Vec3::Z)];
        let second = [tag(b, glam::Vec3::Y), tag(a, glam::Vec3::X), tag(d, glam::Vec3::Z)];
        let (mut out1, mut out2, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
        clip_polygon(&first, ClipPlanes::ALL, depth, &mut out1, &mut scratch);
        clip_polygon(&second, ClipPlanes::ALL, depth, &mut out2, &mut scratch);
        // Points on edge ab have exactly zero weight on the third vertex (lerps of zeros are zero).
        let on_edge = |out: &[Tagged]| out.iter().filter(|v| v.weights.z == 0.0).map(|v| v.clip).collect::<Vec<_>>();
        let (edge1, edge2) = (on_edge(&out1), on_edge(&out2));
        // Either triangle may vanish entirely (or degenerate to < 3 vertices) by its third vertex alone.
        if !out1.is_empty() && !out2.is_empty() {
            for p in &edge1 {
                prop_assert!(edge2.contains(p), "{p} cut differently: {edge1:?} vs {edge2:?}");
            }
        }
    }

    #[test]
    fn a_polygon_lying_in_a_boundary_plane_is_inside(
        depth in arb_depth(), plane in prop::sample::select(ClipPlane::ALL.to_vec()),
        w in 0.1f32..3.0, points in prop::collection::vec((-0.99f32..0.99, -0.99f32..0.99, 0.01f32..0.99), 3..7),
    ) {
        // issue #12: a vertex on a plane counts as inside, so a polygon lying in a face of the clip
        // volume is Inside (no clipping, passed through unchanged), never Outside. Each point is put
        // exactly on `plane` (x = ±w, y = ±w, z = near end or w): the plane's distance is then exactly 0.
        let near = match depth { DepthRange::NegOneToOne => -w, DepthRange::ZeroToOne => 0.0 };
        let on_plane: Vec<Vec4> = points.iter().map(|&(a, b, c)| {
            let (x, y, z) = (a * w, b * w, near + c * (w - near));
            match plane {
                ClipPlane::Left => Vec4::new(-w, y, z, w),
                ClipPlane::Right => Vec4::new(w, y, z, w),
                ClipPlane::Bottom => Vec4::new(x, -w, z, w),
                ClipPlane::Top => Vec4::new(x, w, z, w),
                ClipPlane::Near => Vec4::new(x, y, near, w),
                ClipPlane::Far => Vec4::new(x, y, w, w),
            }
        }).collect();
        for p in &on_plane {
            prop_assert_eq!(plane.distance(*p, depth), 0.0);
            prop_assert_eq!(outcode(*p, ClipPlanes::ALL, depth), ClipPlanes::NONE, "{}", p);
        }
        prop_assert_eq!(classify(&on_plane, ClipPlanes::ALL, depth), Coverage::Inside);
        prop_assert_eq!(classify(&on_plane, plane.into(), depth), Coverage::Inside);
        prop_assert_eq!(clip(&on_plane, depth), on_plane);
    }
}
