//! Bresenham lines: endpoints, 8-connectivity, symmetry, clipping, and the depth-tested outline layer.

use mazewalk_testkit as common;

use glam::Vec3;
use mazewalk_render::raster::{GridVertex, fill_polygon};
use mazewalk_render::{Charset, RenderOptions, SampleBuffer, draw_line, line_points, to_frame};
use mazewalk_term::frame::{ColorDepth, Frame};
use proptest::prelude::*;

fn arb_endpoint(range: i64) -> impl Strategy<Value = (i64, i64)> {
    (-range..range, -range..range)
}

/// The whole unclipped line: drawn in a grid big enough to hold it, shifted back.
fn unclipped(p0: (i64, i64), p1: (i64, i64)) -> Vec<(i64, i64)> {
    const SHIFT: i64 = 1000;
    line_points(p0.0 + SHIFT, p0.1 + SHIFT, p1.0 + SHIFT, p1.1 + SHIFT, 3000, 3000)
        .map(|(x, y)| (x as i64 - SHIFT, y as i64 - SHIFT))
        .collect()
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn a_line_includes_both_endpoints_and_is_8_connected(p0 in arb_endpoint(200), p1 in arb_endpoint(200)) {
        let points = unclipped(p0, p1);
        prop_assert_eq!(points.first(), Some(&p0));
        prop_assert_eq!(points.last(), Some(&p1));
        let n = (p1.0 - p0.0).abs().max((p1.1 - p0.1).abs());
        prop_assert_eq!(points.len() as i64, n + 1, "one point per step of the major axis");
        for pair in points.windows(2) {
            let (dx, dy) = (pair[1].0 - pair[0].0, pair[1].1 - pair[0].1);
            prop_assert!(dx.abs() <= 1 && dy.abs() <= 1 && (dx, dy) != (0, 0), "{:?}", pair);
        }
    }

    #[test]
    fn a_line_covers_the_same_points_from_either_end(p0 in arb_endpoint(200), p1 in arb_endpoint(200)) {
        let mut back = unclipped(p1, p0);
        back.reverse();
        prop_assert_eq!(unclipped(p0, p1), back);
    }

    /// Clipping first visits exactly the visible points of the unclipped line, in the same order.
    #[test]
    fn clipping_keeps_exactly_the_visible_points(p0 in arb_endpoint(120), p1 in arb_endpoint(120), w in 0usize..50, h in 0usize..40) {
        let visible: Vec<(i64, i64)> = unclipped(p0, p1)
            .into_iter()
            .filter(|&(x, y)| x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h)
            .collect();
        let clipped: Vec<(i64, i64)> =
            line_points(p0.0, p0.1, p1.0, p1.1, w, h).map(|(x, y)| (x as i64, y as i64)).collect();
        prop_assert_eq!(clipped, visible);
    }

    #[test]
    fn huge_segments_cost_only_their_visible_part(
        p0 in arb_endpoint(2_000_000_000), p1 in arb_endpoint(2_000_000_000),
    ) {
        let (w, h) = (80, 24);
        let count = line_points(p0.0, p0.1, p1.0, p1.1, w, h).take(w + h + 1).count();
        prop_assert!(count <= w.max(h), "a line crosses at most max(w, h) samples of an 8-connected grid");
    }
}

#[test]
fn a_line_from_minus_to_plus_a_billion_crosses_the_grid_once() {
    let points: Vec<_> = line_points(-1_000_000_000, 12, 1_000_000_000, 12, 80, 24).collect();
    assert_eq!(points.len(), 80);
    assert_eq!((points[0], points[79]), ((0, 12), (79, 12)));
    assert_eq!(line_points(i64::MIN, i64::MIN, i64::MAX, i64::MAX, 5, 5).count(), 5);
}

/// A wall at depth 0.2 hides the middle of a line at depth 0.5; the outline shows on either side.
#[test]
fn outlines_are_hidden_behind_nearer_geometry() {
    let mut samples = SampleBuffer::new(9, 3);
    let wall = [(3.0, 0.0), (6.0, 0.0), (6.0, 3.0), (3.0, 3.0)].map(|(x, y)| GridVertex {
        pos: glam::Vec2::new(x, y),
        depth: 0.2,
        inv_w: 1.0,
        attrs: (),
    });
    fill_polygon(&mut samples, &wall, 1, |()| Vec3::splat(0.3));
    assert_eq!(draw_line(&mut samples, Vec3::new(0.5, 1.5, 0.5), Vec3::new(8.5, 1.5, 0.5), 1.0, 1e-4), 6);
    // On the wall's own depth the line shows (edges of a face are drawn at that face's depth).
    draw_line(&mut samples, Vec3::new(3.5, 0.5, 0.2), Vec3::new(3.5, 2.5, 0.2), 1.0, 1e-4);
    let mut frame = Frame::new(9, 3);
    let region = frame.region();
    let options =
        RenderOptions { charset: Charset::Ascii, color_depth: ColorDepth::None, ..RenderOptions::default() };
    to_frame(&samples, &options, &mut frame, region);
    // Grey 0.3 linear: lightness 0.58, stretched over the walls' range (0.05–0.6): step 9 of 9.
    assert_eq!(frame.lines(), ["   |@@   ", "---|@@---", "   |@@   "]);
}
