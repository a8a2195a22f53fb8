//! Issue #39: the walk's foveated view (`mazewalk_render::fovea`) draws what its warp says: every
//! sample of a wall, the floor or the ceiling shows the surface its own ray meets first, the ray
//! through the sample's centre by `Eye::ray` (which undoes the warp), found here by casting it
//! against every wall of the maze in the plane: no tile misplaced, no band's window off, nothing
//! drawn twice or left out where tiles meet. A sample may differ only beside a boundary of what the
//! rays see (the raster snaps vertices to 1/256 of a sample): where one of the eight samples around
//! it shows the surface, or at a junction of edges on the screen through the sample's centre (the
//! ray passes walls' ends: [`at_a_junction`]).

use crate::draw;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};
use mazewalk_render::samples::{CEILING, FLOOR};
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer};
use proptest::prelude::*;

/// What the ray from `start` along `dir` meets first: the nearest opaque wall it crosses between
/// floor and ceiling, else the floor or the ceiling (a level ray: the nearest wall, or nothing).
fn first_hit(maze: &Maze, start: glam::Vec3, dir: glam::Vec3) -> Option<u32> {
    first_hit_but(maze, start, dir, |_| false)
}

/// [`first_hit`], the walls `passed` says left out.
fn first_hit_but(
    maze: &Maze,
    start: glam::Vec3,
    dir: glam::Vec3,
    passed: impl Fn(u32) -> bool,
) -> Option<u32> {
    let (o, d) = (start.truncate(), dir.truncate());
    let mut best: Option<(f32, u32)> = None;
    for e in 0..maze.edges().len() as u32 {
        if !maze.edge(e).opaque || passed(e) {
            continue;
        }
        let (a, b) = maze.edge_points(e);
        let ab = b - a;
        let denom = d.perp_dot(ab);
        if denom.abs() < 1e-12 {
            continue;
        }
        let t = (a - o).perp_dot(ab) / denom;
        let u = (a - o).perp_dot(d) / denom;
        if t > 0.0 && (0.0..=1.0).contains(&u) && best.is_none_or(|(bt, _)| t < bt) {
            best = Some((t, e));
        }
    }
    let plane = if dir.z < 0.0 { FLOOR } else { CEILING };
    match best {
        Some((t, e)) => {
            let z = start.z + t * dir.z;
            Some(if z > FLOOR_Z && z < CEILING_Z { e } else { plane })
        }
        None if dir.z != 0.0 => Some(plane),
        None => None,
    }
}

/// How far (in the plane) the ray from `start` along `dir` runs to pass an end of wall `e`, where
/// it passes one between floor and ceiling within a thousandth of the end's distance.
fn end_on_ray(maze: &Maze, (start, dir): (glam::Vec3, glam::Vec3), e: u32) -> Option<f32> {
    let (o, d) = (start.truncate(), dir.truncate());
    let (p, q) = maze.edge_points(e);
    let on = |end: glam::Vec2| {
        let t = (end - o).dot(d) / d.length_squared(); // the ray's point nearest the end
        let z = start.z + t * dir.z;
        (t > 0.0 && (FLOOR_Z..=CEILING_Z).contains(&z) && end.distance(o + d * t) <= 1e-3 * (d * t).length())
            .then_some(t)
    };
    on(p).into_iter().chain(on(q)).reduce(f32::min)
}

/// How far (in the plane) the ray from `start` along `dir` runs to meet `surface` (a wall's line,
/// the floor or the ceiling).
fn reach(maze: &Maze, (start, dir): (glam::Vec3, glam::Vec3), surface: u32) -> Option<f32> {
    let (o, d) = (start.truncate(), dir.truncate());
    if surface < maze.edges().len() as u32 {
        let (a, b) = maze.edge_points(surface);
        let denom = d.perp_dot(b - a);
        (denom.abs() >= 1e-12).then(|| (a - o).perp_dot(b - a) / denom)
    } else {
        let z = if surface == FLOOR { FLOOR_Z } else { CEILING_Z };
        (dir.z != 0.0).then(|| (z - start.z) / dir.z)
    }
}

/// Whether `shown` may stand where the ray from `start` along `dir` meets `first` because the
/// sample's centre is on a junction of edges on the screen: the ray passes walls' ends there (a
/// corner; walls' ends on one line of sight from a viewer at a cell's centre), `first` among them or
/// beyond them all. Then the raster's snap decides between the walls whose ends the ray passes
/// before what lies beyond them, and that.
fn at_a_junction(maze: &Maze, ray: (glam::Vec3, glam::Vec3), first: u32, shown: u32) -> bool {
    let walls = maze.edges().len() as u32;
    let passed = |e: u32| end_on_ray(maze, ray, e).is_some();
    let beyond = first_hit_but(maze, ray.0, ray.1, passed);
    let far = beyond.and_then(|b| reach(maze, ray, b)).unwrap_or(f32::INFINITY) * (1.0 + 1e-3);
    let before_beyond = |e: u32| e < walls && end_on_ray(maze, ray, e).is_some_and(|t| t <= far);
    let junction = before_beyond(first) || (beyond == Some(first) && (0..walls).any(before_beyond));
    junction && (beyond == Some(shown) || before_beyond(shown))
}

/// `drawn`'s view at `cols × rows` in `charset`, judged by the rays of `camera`'s (foveated) view:
/// the samples whose id disagrees with their ray's first hit and have no neighbour that agrees, and
/// the samples judged.
fn disagreements(
    maze: &Maze,
    (drawn, camera): (&Camera, &Camera),
    charset: Charset,
    cols: usize,
    rows: usize,
) -> (Vec<String>, usize) {
    let options = RenderOptions { charset, ..RenderOptions::default() };
    let mut renderer = Renderer::new();
    draw(&mut renderer, maze, drawn, &options, cols, rows);
    let (sx, sy) = charset.samples_per_cell();
    let view = camera.eye(cols * sx, rows * sy, charset.sample_aspect(options.cell_aspect)).expect("eye");
    assert!(view.warp.is_some(), "the view is foveated");
    let (ids, width, height) = (renderer.samples().id(), view.width, view.height);
    let walls = maze.edges().len() as u32;
    let expected: Vec<Option<u32>> = (0..width * height)
        .map(|k| {
            let (start, dir) = view.ray((k % width) as f32 + 0.5, (k / width) as f32 + 0.5);
            first_hit(maze, start, dir)
        })
        .collect();
    let mut judged = 0;
    let mut wrong = Vec::new();
    for k in 0..width * height {
        let shown = ids[k];
        if !(shown < walls || shown == FLOOR || shown == CEILING) {
            continue; // the exit's beacon, or nothing
        }
        judged += 1;
        if expected[k] == Some(shown) {
            continue;
        }
        let (x, y) = (k % width, k / width);
        let ray = view.ray(x as f32 + 0.5, y as f32 + 0.5);
        if expected[k].is_some_and(|first| at_a_junction(maze, ray, first, shown)) {
            continue;
        }
        // (the eight around it: where three surfaces meet at a point by the sample's centre, the
        // one shown may touch it only at a corner)
        let (xs, ys) =
            (x.saturating_sub(1)..=(x + 1).min(width - 1), y.saturating_sub(1)..=(y + 1).min(height - 1));
        let beside =
            ys.flat_map(|ny| xs.clone().map(move |nx| ny * width + nx)).any(|n| expected[n] == Some(shown));
        if !beside {
            wrong.push(format!("sample ({x}, {y}): shows {shown}, its ray meets {:?}", expected[k]));
        }
    }
    (wrong, judged)
}

proptest! {
    #![proptest_config(mazewalk_testkit::config_cases(8))]

    /// Over generated mazes, every cell's centre, headings and a little pitch, in half blocks and
    /// ascii at 120×40 and 80×24: every sample shows what its ray meets, up to the boundaries.
    #[test]
    fn every_sample_of_the_foveated_view_shows_what_its_ray_meets(
        seed in any::<u64>(),
        pick in 0.0f32..1.0,
        heading in 0.0f32..360.0,
        pitch in -20.0f32..20.0,
        ascii in any::<bool>(),
        small in any::<bool>(),
    ) {
        let maze = generate(&GenOptions::walk(8, 6, seed)).expect("maze");
        let cell = ((pick * maze.cell_count() as f32) as u32).min(maze.cell_count() as u32 - 1);
        let v = maze.viewer();
        let camera = Camera {
            eye_z: v.z,
            pitch_deg: pitch,
            min_vfov_deg: maze.min_vfov_deg(),
            fovea: true,
            ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
        };
        let charset = if ascii { Charset::Ascii } else { Charset::Half };
        let (cols, rows) = if small { (80, 24) } else { (120, 40) };
        let (wrong, judged) = disagreements(&maze, (&camera, &camera), charset, cols, rows);
        prop_assert!(judged > cols * rows / 2, "{judged} judged");
        prop_assert!(wrong.is_empty(), "{} of {judged}: {:?}", wrong.len(), &wrong[..wrong.len().min(5)]);
    }
}

/// The judge can fail: the plain view's samples, judged by the foveated view's rays, disagree
/// wherever the warp moved a boundary.
#[test]
fn the_plain_view_fails_the_foveated_views_rays() {
    let maze = generate(&GenOptions::walk(8, 6, 7)).expect("maze");
    let v = maze.viewer();
    let foveated = Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(maze.cell_centroid(0), 0.0, v.fov_deg)
    };
    let plain = Camera { fovea: false, ..foveated };
    let (wrong, judged) = disagreements(&maze, (&plain, &foveated), Charset::Half, 120, 40);
    assert!(wrong.len() > judged / 50, "{} of {judged}", wrong.len());
    let (wrong, _) = disagreements(&maze, (&foveated, &foveated), Charset::Half, 120, 40);
    assert!(wrong.is_empty(), "{wrong:?}");
}
