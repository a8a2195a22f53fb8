//! The rasterizer: watertight top-left coverage, depth test, perspective-correct attributes, robustness.

use mazewalk_testkit as common;

use glam::{Vec2, Vec3};
use mazewalk_render::SampleBuffer;
use mazewalk_render::raster::{GridVertex, fill_polygon, fill_triangle, for_each_sample, polygon_coverage};
use mazewalk_render::samples::{FAR, NONE};
use proptest::prelude::*;

const W: usize = 16;
const H: usize = 12;

/// Coordinates around a 16×12 buffer, often on the half-sample grid so edges pass through sample
/// centres and the top-left rule is what decides. All lie on the rasterizer's 1/256 fixed-point grid, so
/// the geometry the tests reason about (in exact f64 arithmetic) is the geometry rasterized.
fn arb_coord(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    prop_oneof![
        ((lo * 2.0) as i32..=(hi * 2.0) as i32).prop_map(|v| v as f32 * 0.5),
        ((lo * 4.0) as i32..=(hi * 4.0) as i32).prop_map(|v| v as f32 * 0.25),
        (lo..hi).prop_map(|v| (v * 256.0).round() / 256.0),
    ]
}

fn arb_point() -> impl Strategy<Value = Vec2> {
    (arb_coord(-4.0, W as f32 + 4.0), arb_coord(-4.0, H as f32 + 4.0)).prop_map(|(x, y)| Vec2::new(x, y))
}

fn cross(o: Vec2, a: Vec2, b: Vec2) -> f64 {
    let (o, a, b) = (o.as_dvec2(), a.as_dvec2(), b.as_dvec2());
    (a - o).perp_dot(b - o)
}

/// Convex hull, counter-clockwise in a y-up sense (Andrew's monotone chain), without collinear points.
fn convex_hull(mut points: Vec<Vec2>) -> Vec<Vec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let mut hull: Vec<Vec2> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec2>> =
            if pass == 0 { Box::new(points.iter()) } else { Box::new(points.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// A convex polygon of at least `min` vertices: the hull of random points.
fn arb_convex_polygon(min: usize) -> impl Strategy<Value = Vec<Vec2>> {
    prop::collection::vec(arb_point(), min..12)
        .prop_map(convex_hull)
        .prop_filter("too few hull points", move |h| h.len() >= min)
}

fn centre(x: usize, y: usize) -> Vec2 {
    Vec2::new(x as f32 + 0.5, y as f32 + 0.5)
}

proptest! {
    #![proptest_config(common::config())]

    /// Both diagonals of a convex quad: no sample twice, the same union, and the union matches the quad.
    #[test]
    fn two_triangles_sharing_an_edge_are_watertight(quad in arb_convex_polygon(4).prop_map(|h| h[..4].to_vec())) {
        let quad = convex_hull(quad);
        prop_assume!(quad.len() == 4);
        let by_ac = polygon_coverage(W, H, &quad);
        let by_bd = polygon_coverage(W, H, &[quad[1], quad[2], quad[3], quad[0]]);
        prop_assert!(by_ac.iter().all(|&c| c <= 1), "double coverage along a-c");
        prop_assert_eq!(&by_ac, &by_bd);
        for y in 0..H {
            for x in 0..W {
                // Exact in f64: every coordinate is a multiple of 1/256 below 2^6. Positive = inside (CCW hull).
                let d = (0..4).map(|k| cross(quad[k], quad[(k + 1) % 4], centre(x, y))).fold(f64::INFINITY, f64::min);
                let count = by_ac[y * W + x];
                if d > 0.0 { prop_assert_eq!(count, 1, "crack at {:?}", (x, y)); }
                if d < 0.0 { prop_assert_eq!(count, 0, "spill at {:?}", (x, y)); }
            }
        }
    }

    /// Any two triangles on opposite sides of a shared edge: no sample twice, and every sample centre
    /// lying exactly on the shared edge (strictly between its ends) is covered once.
    #[test]
    fn a_shared_edge_through_sample_centres_has_no_cracks(a in arb_point(), c in arb_point(), b in arb_point(), d in arb_point()) {
        // Put d on the other side of a–c by reflecting it through the edge's midpoint (stays on the grid).
        let d = if cross(a, c, b) * cross(a, c, d) > 0.0 { a + c - d } else { d };
        prop_assume!(cross(a, c, b) * cross(a, c, d) < 0.0);
        let mut count = vec![0u32; W * H];
        for tri in [[a, b, c], [a, c, d]] {
            for_each_sample(W, H, tri, |x, y, _| count[y * W + x] += 1);
        }
        prop_assert!(count.iter().all(|&n| n <= 1));
        for y in 0..H {
            for x in 0..W {
                let p = centre(x, y);
                let along = (p - a).as_dvec2().dot((c - a).as_dvec2()) / (c - a).as_dvec2().length_squared();
                if cross(a, c, p) == 0.0 && along > 0.0 && along < 1.0 {
                    prop_assert_eq!(count[y * W + x], 1, "crack on the shared edge at {:?}", (x, y));
                }
            }
        }
    }

    #[test]
    fn a_convex_polygon_covers_the_same_samples_whichever_vertex_the_fan_starts_at(
        polygon in arb_convex_polygon(3), shift in 1usize..12,
    ) {
        let mut rotated = polygon.clone();
        rotated.rotate_left(shift % polygon.len());
        let coverage = polygon_coverage(W, H, &polygon);
        prop_assert!(coverage.iter().all(|&c| c <= 1));
        prop_assert_eq!(&coverage, &polygon_coverage(W, H, &rotated));
        let reversed: Vec<Vec2> = polygon.iter().rev().copied().collect();
        prop_assert_eq!(&coverage, &polygon_coverage(W, H, &reversed));
    }

    #[test]
    fn clockwise_and_counter_clockwise_cover_the_same_samples(a in arb_point(), b in arb_point(), c in arb_point()) {
        prop_assert_eq!(polygon_coverage(W, H, &[a, b, c]), polygon_coverage(W, H, &[a, c, b]));
    }

    /// Coverage by definition, sample by sample over the whole buffer (the rasterizer solves each row's
    /// span instead): a centre strictly inside the triangle, or on an edge that is a top or a left edge
    /// (y down: an edge going up, or a horizontal one going right, once the winding puts the interior on
    /// the positive side) and inside the others. Each sample once, row by row.
    #[test]
    fn a_triangle_covers_exactly_the_centres_inside_it_by_the_top_left_rule(
        a in arb_point(), b in arb_point(), c in arb_point(),
    ) {
        let (b, c) = if cross(a, b, c) < 0.0 { (c, b) } else { (b, c) };
        let inside = |p: Vec2| {
            cross(a, b, c) != 0.0
                && [(a, b), (b, c), (c, a)].into_iter().all(|(s, t)| {
                    let (e, d) = (cross(s, t, p), t - s);
                    e > 0.0 || (e == 0.0 && (d.y < 0.0 || (d.y == 0.0 && d.x > 0.0)))
                })
        };
        let expected: Vec<(usize, usize)> =
            (0..H).flat_map(|y| (0..W).map(move |x| (x, y))).filter(|&(x, y)| inside(centre(x, y))).collect();
        let mut got = Vec::new();
        for_each_sample(W, H, [a, b, c], |x, y, _| got.push((x, y)));
        prop_assert_eq!(got, expected);
    }

    /// Top-left rule on an axis-aligned rectangle: centre (i + 0.5) is in iff x0 <= i + 0.5 < x1.
    #[test]
    fn an_axis_aligned_rectangle_covers_exactly_the_predicted_samples(
        xs in (arb_coord(-2.0, 18.0), arb_coord(-2.0, 18.0)), ys in (arb_coord(-2.0, 14.0), arb_coord(-2.0, 14.0)),
    ) {
        let (x0, x1) = (xs.0.min(xs.1), xs.0.max(xs.1));
        let (y0, y1) = (ys.0.min(ys.1), ys.0.max(ys.1));
        let rect = [Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)];
        let expected: Vec<u32> = (0..W * H)
            .map(|i| {
                let p = centre(i % W, i / W);
                u32::from(x0 <= p.x && p.x < x1 && y0 <= p.y && p.y < y1)
            })
            .collect();
        prop_assert_eq!(&polygon_coverage(W, H, &rect), &expected);
        let clockwise = [rect[0], rect[3], rect[2], rect[1]];
        prop_assert_eq!(&polygon_coverage(W, H, &clockwise), &expected);
    }

    /// Anything finite or not, huge or inverted: no panic, nothing but sample writes inside the buffer.
    #[test]
    fn wild_vertices_never_panic(
        coords in prop::array::uniform6(prop_oneof![any::<f32>(), -3e6f32..3e6, Just(f32::NAN), Just(1.0e20)]),
        depths in prop::array::uniform3(any::<f32>()),
        inv_w in prop::array::uniform3(any::<f32>()),
        size in (0usize..9, 0usize..9),
    ) {
        let mut buffer = SampleBuffer::new(size.0, size.1);
        let tri: [GridVertex<f32>; 3] = std::array::from_fn(|k| GridVertex {
            pos: Vec2::new(coords[2 * k], coords[2 * k + 1]),
            depth: depths[k],
            inv_w: inv_w[k],
            attrs: 1.0,
        });
        let written = fill_polygon(&mut buffer, &tri, 3, Vec3::splat);
        prop_assert!(written <= size.0 * size.1);
        prop_assert_eq!(buffer.id().iter().filter(|&&id| id == 3).count(), written);
    }
}

fn flat(pos: [Vec2; 3], depth: f32) -> [GridVertex<()>; 3] {
    pos.map(|pos| GridVertex { pos, depth, inv_w: 1.0, attrs: () })
}

#[test]
fn the_nearer_triangle_wins_whatever_the_draw_order() {
    let near = flat([Vec2::new(0.0, 0.0), Vec2::new(12.0, 0.0), Vec2::new(0.0, 12.0)], 0.3);
    let far = flat([Vec2::new(2.0, 2.0), Vec2::new(16.0, 2.0), Vec2::new(2.0, 12.0)], 0.6);
    let draw = |order: [(&[GridVertex<()>; 3], u32); 2]| {
        let mut buffer = SampleBuffer::new(W, H);
        for (tri, id) in order {
            fill_triangle(&mut buffer, [&tri[0], &tri[1], &tri[2]], id, |()| Vec3::splat(id as f32));
        }
        buffer
    };
    let near_first = draw([(&near, 1), (&far, 2)]);
    let far_first = draw([(&far, 2), (&near, 1)]);
    assert_eq!(near_first, far_first);
    let both = polygon_coverage(W, H, &near.map(|v| v.pos))
        .iter()
        .zip(polygon_coverage(W, H, &far.map(|v| v.pos)))
        .filter(|(a, b)| **a == 1 && *b == 1)
        .count();
    assert!(both > 10, "the triangles should overlap");
    for (i, &id) in near_first.id().iter().enumerate() {
        let in_near = polygon_coverage(W, H, &near.map(|v| v.pos))[i] == 1;
        if in_near {
            assert_eq!((id, near_first.depth()[i]), (1, 0.3));
        }
    }
}

#[test]
fn equal_depth_keeps_the_first_drawn() {
    // LESS, not LEQUAL: a coplanar redraw does not overwrite (and does not count as written).
    let tri = flat([Vec2::new(0.0, 0.0), Vec2::new(8.0, 0.0), Vec2::new(0.0, 8.0)], 0.5);
    let mut buffer = SampleBuffer::new(W, H);
    let first = fill_triangle(&mut buffer, [&tri[0], &tri[1], &tri[2]], 1, |()| Vec3::ONE);
    assert!(first > 0);
    assert_eq!(fill_triangle(&mut buffer, [&tri[0], &tri[1], &tri[2]], 2, |()| Vec3::ONE), 0);
    assert!(buffer.id().iter().all(|&id| id == 1 || id == NONE));
}

#[test]
fn a_huge_but_valid_triangle_covers_the_whole_buffer() {
    let tri = flat([Vec2::new(-1.0e6, -1.0e6), Vec2::new(1.0e6, -1.0e6), Vec2::new(0.0, 1.0e6)], 0.5);
    let mut buffer = SampleBuffer::new(W, H);
    assert_eq!(fill_triangle(&mut buffer, [&tri[0], &tri[1], &tri[2]], 0, |()| Vec3::ONE), W * H);
}

/// A floor strip y = -1 from z = -2 to z = -10 in view space, seen through a pinhole: the interpolated
/// view-space z (an attribute) and the depth must match the ray–plane intersection at every sample.
#[test]
fn attributes_are_perspective_correct_and_depth_is_ndc_z() {
    let (width, height) = (40usize, 30usize);
    let (near, far, focal) = (0.5f32, 20.0f32, 1.5f32);
    let project = |view: Vec3| {
        let w = -view.z;
        let ndc = Vec3::new(
            focal * view.x / w,
            focal * view.y / w,
            ((far + near) * -view.z - 2.0 * far * near) / (far - near) / w,
        );
        GridVertex {
            pos: Vec2::new((ndc.x + 1.0) * 0.5 * width as f32, (1.0 - ndc.y) * 0.5 * height as f32),
            depth: (ndc.z + 1.0) * 0.5,
            inv_w: 1.0 / w,
            attrs: view.z,
        }
    };
    let corners = [
        Vec3::new(-1.0, -1.0, -2.0),
        Vec3::new(1.0, -1.0, -2.0),
        Vec3::new(1.0, -1.0, -10.0),
        Vec3::new(-1.0, -1.0, -10.0),
    ];
    let polygon = corners.map(project);
    let mut buffer = SampleBuffer::new(width, height);
    let written = fill_polygon(&mut buffer, &polygon, 0, Vec3::splat); // keep the attribute as colour
    assert!(written > 50, "the strip should cover a good part of the grid ({written})");
    for y in 0..height {
        for x in 0..width {
            let i = y * width + x;
            if buffer.depth()[i] == FAR {
                continue;
            }
            // Ray t·(ndc.x / focal, ndc.y / focal, -1) through the sample centre meets y = -1 at
            // t = -focal / ndc.y, so view z = -t = focal / ndc.y.
            let ndc_y = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
            let z = focal / ndc_y;
            let expected_depth = (((far + near) * -z - 2.0 * far * near) / (far - near) / -z + 1.0) * 0.5;
            let interpolated = buffer.color()[i].x;
            assert!((interpolated - z).abs() <= 1e-3 * z.abs(), "({x}, {y}): {interpolated} vs {z}");
            assert!((buffer.depth()[i] - expected_depth).abs() < 1e-5, "depth at ({x}, {y})");
        }
    }
}
