//! Properties of the model, the readers and movement, on generated and real mazes.

use mazewalk_testkit as common;

use glam::{Vec2, vec2};
use mazewalk_maze::generate::{Algorithm, GenOptions, generate};
use mazewalk_maze::movement::{Position, step_traced};
use mazewalk_maze::{self as maze, Format, Maze};
use proptest::prelude::*;

fn arb_algorithm() -> impl Strategy<Value = Algorithm> {
    prop_oneof![Just(Algorithm::Prim), Just(Algorithm::Backtracker), Just(Algorithm::Wilson)]
}

/// Small generated mazes, with and without cycles.
fn arb_maze() -> impl Strategy<Value = Maze> {
    (1u32..12, 1u32..12, any::<u64>(), arb_algorithm(), prop_oneof![Just(0.0f32), 0.0f32..=1.0]).prop_map(
        |(width, height, seed, algorithm, loops)| {
            generate(&GenOptions { width, height, seed, algorithm, loops, ..GenOptions::default() }).unwrap()
        },
    )
}

fn real(name: &str) -> Maze {
    maze::load(common::maze_path(&format!("cs559/{name}"))).unwrap().maze
}

/// Signed area test in f64: > 0 when c is left of a → b.
fn orient(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    (b - a).as_dvec2().perp_dot((c - a).as_dvec2())
}

/// `true` when segments p and q properly cross (each strictly separates the other's end points).
fn crosses(p: (Vec2, Vec2), q: (Vec2, Vec2)) -> bool {
    orient(q.0, q.1, p.0) * orient(q.0, q.1, p.1) < 0.0 && orient(p.0, p.1, q.0) * orient(p.0, p.1, q.1) < 0.0
}

fn distance_to_segment(p: Vec2, (a, b): (Vec2, Vec2)) -> f32 {
    let e = b - a;
    let t = ((p - a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
    p.distance(a + e * t)
}

fn opaque_walls(m: &Maze) -> Vec<(Vec2, Vec2)> {
    (0..m.edges().len() as u32).filter(|&e| m.edge(e).opaque).map(|e| m.edge_points(e)).collect()
}

/// Walks `steps` random steps (mostly short, some long, some axis-aligned so the viewer lands
/// exactly on edge lines) and checks every invariant after each.
fn random_walk(m: &Maze, seed: u64, steps: usize, radius: f32) {
    let walls = opaque_walls(m);
    let mut rng = maze::generate::SplitMix64::new(seed);
    let mut unit = || rng.unit_f32();
    let mut at = Position::of_viewer(m);
    for i in 0..steps {
        let (a, b, c) = (unit(), unit(), unit());
        let len = if c < 0.9 { c * 1.5 } else { c * 30.0 };
        let delta = match (a * 8.0) as u32 {
            0 => vec2(len, 0.0),
            1 => vec2(0.0, -len),
            _ => Vec2::from_angle(b * std::f32::consts::TAU) * len,
        };
        let (next, path) = step_traced(m, at, delta, radius);
        assert!(m.cell_contains(next.cell, next.pos), "step {i}: {next:?} not in its cell");
        assert!(m.cell_at(next.pos).is_some(), "step {i}: left the maze at {next:?}");
        assert_eq!((path[0], path[path.len() - 1]), (at.pos, next.pos));
        for (w, &wall) in walls.iter().enumerate() {
            // each straight leg of the path (a slide turns at a wall)
            for leg in path.windows(2) {
                assert!(!crosses((leg[0], leg[1]), wall), "step {i}: {at:?} → {next:?} crossed wall {w}");
            }
            // tolerance: positions are rounded to f32 after an f64 sweep that stops 1e-4 short
            assert!(
                distance_to_segment(next.pos, wall) >= radius - 1e-3,
                "step {i}: {next:?} too close to wall {w}"
            );
        }
        at = next;
    }
}

proptest! {
    #![proptest_config(common::config())]

    /// `Edges::opaque_ids` lists exactly the walls, ascending: those `is_opaque` says, one by one.
    #[test]
    fn opaque_ids_are_the_walls_in_order(m in arb_maze()) {
        let walls: Vec<u32> = (0..m.edges().len() as u32).filter(|&e| m.edge(e).opaque).collect();
        prop_assert_eq!(m.edges().opaque_ids().collect::<Vec<_>>(), walls);
    }

    #[test]
    fn cs559_write_then_read_is_the_identity(m in arb_maze()) {
        let text = maze::write(&m, Format::Cs559).unwrap();
        prop_assert_eq!(maze::parse("gen", text.as_bytes()).unwrap(), m);
    }

    /// The bucket index agrees with a scan over all cells, boundaries included.
    #[test]
    fn cell_at_finds_a_containing_cell_exactly_when_one_exists(m in arb_maze(), u in 0.0f32..1.0, v in 0.0f32..1.0, snap in 0u8..4) {
        let e = m.extents();
        let mut p = e.min + (e.max - e.min) * vec2(u, v);
        // snap onto the lattice lines of the 4-unit cells: exactly on edges and vertices
        if snap & 1 == 1 { p.x = (p.x / 4.0).round() * 4.0; }
        if snap & 2 == 2 { p.y = (p.y / 4.0).round() * 4.0; }
        let any = (0..m.cell_count() as u32).find(|&c| m.cell_contains(c, p));
        match m.cell_at(p) {
            Some(c) => prop_assert!(m.cell_contains(c, p)),
            None => prop_assert_eq!(any, None),
        }
        prop_assert!(any.is_some(), "generated mazes fill their extents: {:?}", p);
    }

    /// Whatever bytes replace part of a real file, reading returns (never panics), and an error
    /// points inside the file.
    #[test]
    fn mangled_files_never_panic(at in 0usize..1200, len in 0usize..8, junk in proptest::collection::vec(any::<u8>(), 0..8)) {
        let text = std::fs::read(common::maze_path("cs559/maze-3x3-50.maze")).unwrap();
        let at = at.min(text.len());
        let end = (at + len).min(text.len());
        let bytes = [&text[..at], &junk[..], &text[end..]].concat();
        if let Err(e) = maze::parse("m", &bytes) {
            let lines = bytes.split(|&b| b == b'\n').count() as u32;
            prop_assert!(e.line >= 1 && e.line <= lines && e.col >= 1, "{}", e);
        }
    }
}

proptest! {
    // Each case generates a maze and walks thousands of random steps through it.
    #![proptest_config(common::config_cases(8))]

    /// 8 mazes × 12,500 steps = 100,000 steps by default.
    #[test]
    fn random_walks_never_pass_a_wall(m in arb_maze(), seed in any::<u64>(), radius in prop_oneof![Just(0.0f32), 0.01f32..1.5]) {
        random_walk(&m, seed, 12_500, radius);
    }
}

#[test]
fn random_walks_in_the_real_files_never_pass_a_wall() {
    for name in ["maze-1x1-45.maze", "maze-3x3-50.maze", "maze-10x10-100.maze"] {
        random_walk(&real(name), 7, 10_000, 0.2);
    }
}

#[test]
fn a_long_walk_in_a_maze_with_loops() {
    let m = generate(&GenOptions { width: 15, height: 15, seed: 3, loops: 0.3, ..GenOptions::default() })
        .unwrap();
    random_walk(&m, 11, 100_000, 0.25);
}

#[test]
fn points_on_edges_and_vertices_are_in_a_cell() {
    let m = real("maze-10x10-100.maze");
    for v in m.vertices() {
        assert!(m.cell_at(*v).is_some(), "vertex {v}");
    }
    for e in 0..m.edges().len() as u32 {
        let (a, b) = m.edge_points(e);
        let mid = (a + b) * 0.5;
        let c = m.cell_at(mid).unwrap();
        let edge = m.edge(e);
        assert!(edge.left == Some(c) || edge.right == Some(c), "edge {e} midpoint in cell {c}");
    }
}

#[test]
fn perfect_and_counts_of_the_real_files() {
    let m = real("maze-10x10-100.maze");
    assert_eq!(m.portal_count() + m.wall_count(), 220);
    assert!(m.is_connected());
    let one = real("maze-1x1-45.maze");
    assert!(one.is_perfect()); // one cell, no portals
    assert_eq!(one.extents().max, vec2(10.0, 6.0));
}

#[test]
fn other_side_and_cell_edges_agree() {
    let m = real("maze-3x3-50.maze");
    for c in 0..m.cell_count() as u32 {
        for &e in m.cell_edges(c) {
            let edge = m.edge(e);
            let other = edge.other_side(c);
            assert!(other != Some(c));
            if edge.is_portal() {
                assert!(m.cell_edges(other.unwrap()).contains(&e));
            }
            // the cell lies on the left of its edges taken counter-clockwise
            let (a, b) = m.edge_points_ccw(e, c);
            assert!(orient(a, b, m.cell_centroid(c)) > 0.0);
        }
    }
}
