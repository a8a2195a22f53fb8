//! Homogeneous clipping: the result is inside the input polygon and the clip volume, convex, and
//! stable under clipping again; inside polygons pass unchanged, outside ones vanish; shared edges are
//! cut at identical points. Those properties bound the answer; the exact ones below pin it: every
//! new vertex lies on the plane that cut it, the polygon is an f64 Sutherland–Hodgman reference's
//! vertex for vertex, each input edge keeps exactly its f64 Liang–Barsky segment, and the area is the
//! reference's (so a polygon whose exact clip has area is never lost).
//!
//! Tolerances. The bounding properties: 1e-5 relative to the polygon's largest clip coordinate. A
//! crossing is one lerp with a parameter from one division, a few ULPs of the coordinates it mixes;
//! six planes compound that. The exact properties state theirs from ε = 2⁻²⁴ (f32's unit roundoff,
//! 6e-8) and that same magnitude, next to each (`cut_tolerance`, `EXACT_ULPS`).

mod common;

use glam::{DVec2, DVec4, Vec2, Vec4};
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

// ---- Exact clipping ----------------------------------------------------------------------------
//
// The references below are the textbook algorithms in f64, on the same f32 input (exactly
// representable in f64), so what they compute is the exact clip to 1e-16: the f32 clipper must agree
// with them to its own rounding.

/// f32's unit roundoff, 2⁻²⁴: the largest relative error of one rounding.
const EPS: f32 = f32::EPSILON / 2.0;

/// How far a new vertex may be from the plane that cut it, for an input of largest coordinate
/// `scale`. The distances of the two input vertices are each one rounded sum (relative error ε); they
/// have opposite signs, so `t = d_in / (d_in - d_out)` suffers no cancellation: relative error ≤ 3ε.
/// The lerp `a·(1-t) + b·t` adds ≤ 3ε·scale per coordinate and `t`'s error moves the point ≤ 3ε·2·scale
/// along the edge: ≤ 9ε·scale per coordinate. A plane's distance sums two coordinates and rounds once:
/// ≤ 2·9ε·scale + ε·scale = 19ε·scale. 32ε·scale leaves margin and still reads a cut 10 % along an
/// edge (moving the distance by a tenth of the edge's extent across the plane) as wrong.
fn cut_tolerance(scale: f32) -> f32 {
    32.0 * EPS * scale
}

/// How far the f32 clipper's vertices may be from the exact ones after all six planes: each cut
/// starts from vertices already off by the earlier cuts' rounding, and the parameter of a crossing
/// divides by the drop in distance along the edge, which amplifies that rounding for an edge nearly
/// parallel to the plane, without bound as the edge turns parallel. Measured (commit 1020849, against
/// [`reference_clip`] and [`liang_barsky`]): at most 43ε·scale over 100,000 cases, 115ε·scale over
/// 1,000,000. 1024ε·scale (6e-5 of the polygon's size) leaves a wide margin for that tail and is
/// still a thousand times smaller than a cut moved 10 % along an edge of the polygon's size.
const EXACT_ULPS: f32 = 1024.0;

fn exact_tolerance(scale: f32) -> f32 {
    EXACT_ULPS * EPS * scale
}

/// [`ClipPlane::distance`]'s linear forms, written again in f64 from the volume's definition:
/// `-w <= x, y <= w`, `near·w <= z <= w`, `near` being -1 or 0.
fn distance64(plane: ClipPlane, p: DVec4, depth: DepthRange) -> f64 {
    match plane {
        ClipPlane::Left => p.w + p.x,
        ClipPlane::Right => p.w - p.x,
        ClipPlane::Bottom => p.w + p.y,
        ClipPlane::Top => p.w - p.y,
        ClipPlane::Near => p.z - f64::from(depth.near()) * p.w,
        ClipPlane::Far => p.w - p.z,
    }
}

/// Sutherland–Hodgman in f64, as the textbook writes it (Foley et al., §3.14): walk the edges
/// `prev → cur`; keep `cur` if inside, and the crossing where the edge changes side, computed from
/// `prev`. Planes in [`ClipPlane::ALL`] order; fewer than 3 vertices is nothing.
fn reference_clip(polygon: &[Vec4], depth: DepthRange) -> Vec<DVec4> {
    let mut poly: Vec<DVec4> = polygon.iter().map(|p| p.as_dvec4()).collect();
    for plane in ClipPlane::ALL {
        let input = std::mem::take(&mut poly);
        for (i, &cur) in input.iter().enumerate() {
            let prev = input[(i + input.len() - 1) % input.len()];
            let (dp, dc) = (distance64(plane, prev, depth), distance64(plane, cur, depth));
            if (dp >= 0.0) != (dc >= 0.0) {
                poly.push(prev + (cur - prev) * (dp / (dp - dc)));
            }
            if dc >= 0.0 {
                poly.push(cur);
            }
        }
    }
    if poly.len() < 3 { Vec::new() } else { poly }
}

/// Liang–Barsky in f64 (Liang & Barsky 1984, in homogeneous form): the parameter interval
/// `[t0, t1]` of the segment `a + t·(b - a)`, `t` in [0, 1], inside every plane, or `None`. Each
/// plane's distance is linear in `t`, `d(t) = d_a + t·(d_b - d_a)`: where it falls the plane bounds
/// `t` above, where it rises below.
fn liang_barsky(a: DVec4, b: DVec4, depth: DepthRange) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for plane in ClipPlane::ALL {
        let (da, db) = (distance64(plane, a, depth), distance64(plane, b, depth));
        if da < 0.0 && db < 0.0 {
            return None;
        }
        let t = da / (da - db);
        if da < 0.0 {
            t0 = t0.max(t); // entering
        } else if db < 0.0 {
            t1 = t1.min(t); // leaving
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Consecutive vertices (cyclically) closer than `tol` merged into one: a crossing that lands within
/// rounding of a later plane is kept by one clipper and cut again by the other, which leaves two
/// vertices a rounding apart where the other has one.
fn merge_close(polygon: &[DVec4], tol: f64) -> Vec<DVec4> {
    let mut merged: Vec<DVec4> = Vec::new();
    for &p in polygon {
        if merged.last().is_none_or(|q| (p - *q).abs().max_element() > tol) {
            merged.push(p);
        }
    }
    while merged.len() > 1 && (merged[0] - merged[merged.len() - 1]).abs().max_element() <= tol {
        merged.pop();
    }
    merged
}

/// Whether `a` and `b` are the same loop of vertices within `tol`, starting anywhere.
fn same_loop(a: &[DVec4], b: &[DVec4], tol: f64) -> bool {
    let n = a.len();
    n == b.len()
        && (n == 0 || (0..n).any(|k| (0..n).all(|i| (a[(i + k) % n] - b[i]).abs().max_element() <= tol)))
}

/// The area of a clipped polygon in the input polygon's plane, in f64 (shoelace).
fn area(polygon: &Polygon, vertices: &[DVec4]) -> f64 {
    let (centre, u, v) = (polygon.centre.as_dvec4(), polygon.u.as_dvec4(), polygon.v.as_dvec4());
    let flat: Vec<DVec2> =
        vertices.iter().map(|&p| DVec2::new((p - centre).dot(u), (p - centre).dot(v))).collect();
    let n = flat.len();
    (0..n).map(|i| flat[i].perp_dot(flat[(i + 1) % n])).sum::<f64>().abs() / 2.0
}

fn perimeter(vertices: &[DVec4]) -> f64 {
    let n = vertices.len();
    (0..n).map(|i| (vertices[(i + 1) % n] - vertices[i]).length()).sum()
}

fn to_f64(polygon: &[Vec4]) -> Vec<DVec4> {
    polygon.iter().map(|p| p.as_dvec4()).collect()
}

/// `polygon` moved along `plane`'s normal so that its centroid (the mean of its vertices, inside it)
/// lies on the plane.
fn across(polygon: &Polygon, plane: ClipPlane, depth: DepthRange) -> Vec<Vec4> {
    // The distance is linear, so its normal's components are the distances of the unit vectors.
    let normal = Vec4::from(Vec4::AXES.map(|axis| plane.distance(axis, depth)));
    let centroid = polygon.vertices.iter().sum::<Vec4>() / polygon.vertices.len() as f32;
    let shift = -plane.distance(centroid, depth) / normal.length_squared() * normal;
    polygon.vertices.iter().map(|&p| p + shift).collect()
}

/// Every plane, as a strategy.
fn arb_plane() -> impl Strategy<Value = ClipPlane> {
    prop::sample::select(ClipPlane::ALL.to_vec())
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn a_polygon_across_a_plane_is_cut_at_two_new_vertices_on_it(
        polygon in arb_convex_polygon(), depth in arb_depth(), plane in arb_plane(),
    ) {
        // Moved along the plane's normal so that its centroid is on the plane: its vertices are then on
        // both sides, unless it lies parallel to the plane.
        let input = &across(&polygon, plane, depth);
        let inside = |p: &Vec4| plane.distance(*p, depth) >= 0.0;
        // Only polygons with vertices strictly on both sides and none on the plane: a vertex on the
        // plane is kept, not cut (the crossing from it is itself).
        let distances: Vec<f32> = input.iter().map(|p| plane.distance(*p, depth)).collect();
        prop_assume!(distances.iter().any(|&d| d > 0.0) && distances.iter().any(|&d| d < 0.0));
        prop_assume!(distances.iter().all(|&d| d != 0.0));
        let scale = input.iter().map(|v| v.abs().max_element()).fold(1.0, f32::max);
        let (mut out, mut scratch) = (Vec::new(), Vec::new());
        clip_polygon(input, plane.into(), depth, &mut out, &mut scratch);
        // A convex polygon's boundary crosses a plane exactly twice: the inside vertices stay, as they
        // were, and two new ones appear, each on the plane and on an edge from inside to outside.
        let kept: Vec<Vec4> = input.iter().copied().filter(inside).collect();
        let new: Vec<Vec4> = out.iter().copied().filter(|p| !input.contains(p)).collect();
        prop_assert_eq!(out.len(), kept.len() + 2, "{:?} → {:?}", input, out);
        prop_assert_eq!(new.len(), 2, "new vertices {:?}", new);
        prop_assert!(kept.iter().all(|p| out.contains(p)));
        let tol = cut_tolerance(scale);
        let n = input.len();
        for p in new {
            prop_assert!(plane.distance(p, depth).abs() <= tol, "{p} is {} from {plane:?} (tolerance {tol})", plane.distance(p, depth));
            let on_a_cut_edge = (0..n).any(|i| {
                let (a, b) = (input[i], input[(i + 1) % n]);
                inside(&a) != inside(&b) && segment_distance(p, a, b) <= tol
            });
            prop_assert!(on_a_cut_edge, "{p} is on no edge that crosses {plane:?}");
        }
    }

    #[test]
    fn the_clip_is_the_f64_sutherland_hodgman_vertex_for_vertex(polygon in arb_convex_polygon(), depth in arb_depth()) {
        let tol = exact_tolerance(polygon.scale());
        let ours = merge_close(&to_f64(&clip(&polygon.vertices, depth)), f64::from(tol));
        let exact = merge_close(&reference_clip(&polygon.vertices, depth), f64::from(tol));
        // A degenerate reference (all its vertices within rounding of one another, or of a line) is
        // a polygon of no area, which f32 may keep or drop: the area property covers it.
        if exact.len() < 3 || ours.len() < 3 {
            prop_assert!(area(&polygon, &exact) <= f64::from(tol) * perimeter(&exact).max(f64::from(tol)), "lost {exact:?}");
        } else {
            prop_assert!(same_loop(&ours, &exact, f64::from(tol)), "ours  {ours:?}\nexact {exact:?}");
        }
    }

    #[test]
    fn every_edge_keeps_its_f64_liang_barsky_segment(polygon in arb_convex_polygon(), depth in arb_depth()) {
        let input = &polygon.vertices;
        let ours = to_f64(&clip(input, depth));
        let tol = f64::from(exact_tolerance(polygon.scale()));
        let n = input.len();
        for i in 0..n {
            let (a, b) = (input[i].as_dvec4(), input[(i + 1) % n].as_dvec4());
            let Some((t0, t1)) = liang_barsky(a, b, depth) else { continue };
            let (p0, p1) = (a + (b - a) * t0, a + (b - a) * t1);
            // The part of an edge inside the volume is part of the clipped polygon's boundary, and
            // its two ends are vertices of it (an edge just grazing the volume may be kept or not).
            if (p1 - p0).abs().max_element() <= 4.0 * tol {
                continue;
            }
            for p in [p0, p1] {
                prop_assert!(
                    ours.iter().any(|q| (*q - p).abs().max_element() <= tol),
                    "edge {i} keeps [{t0}, {t1}]: {p} is not a vertex of {ours:?}"
                );
            }
        }
    }

    #[test]
    fn the_clip_has_the_exact_area_so_none_is_lost(polygon in arb_convex_polygon(), depth in arb_depth()) {
        let exact = reference_clip(&polygon.vertices, depth);
        let ours = to_f64(&clip(&polygon.vertices, depth));
        // Moving each vertex by up to `tol` changes the area by at most the perimeter times `tol`:
        // so a clip whose exact area is larger is never lost, and none is clipped to a wrong shape.
        let tol = f64::from(exact_tolerance(polygon.scale()));
        let slack = perimeter(&exact).max(perimeter(&ours)) * tol;
        let (a, b) = (area(&polygon, &ours), area(&polygon, &exact));
        prop_assert!((a - b).abs() <= slack, "area {a} vs exact {b} (slack {slack}): {ours:?} vs {exact:?}");
    }
}
