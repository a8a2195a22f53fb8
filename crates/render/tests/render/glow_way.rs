//! Issue #39: inside the exit's glow, the way on in one look. The line across the opening the exit's
//! light comes through toward the eye (a lit cell's way one step nearer the exit:
//! `ExitLight::lit_through`) is drawn in the way's light, on the floor and the ceiling: the
//! 256-colour cube's (95, 135, 0) in truecolor and 256 colours, the bright yellow in 16, `^` in
//! ascii; every other opening's line stays the ordinary cell line's.
//!
//! The measure (`cargo test -p mazewalk-render --test render glow_way -- --nocapture` prints it):
//! held-out generated mazes (20×15, the seeds below), poses at every junction inside the glow facing
//! each of its openings and 1–4 cells before it facing it; in each 120×40 frame (half blocks in
//! truecolor, 256 and 16 colours; ascii without colour) the samples showing the way's look at the
//! projected line (±1 sample) of each toward-exit opening, by its distance from the eye, and every
//! sample showing that look anywhere.

use crate::draw;
use glam::{Vec2, Vec3};
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};
use mazewalk_render::samples::{CEILING, FLOOR};
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, quality};
use mazewalk_term::frame::{ColorDepth, xterm_rgb};

/// Held-out mazes: none of the seeds the glow was tuned on.
const SEEDS: [u64; 4] = [5_501, 7_723, 31_337, 60_013];
/// The beacon's sample id (`sprite::EXIT_ID`).
const BEACON: u32 = u32::MAX - 3;
/// A toward-exit opening counts as shown with at least this many samples of the way's look.
const SHOWN: usize = 3;

/// The maze viewer's camera at `at`, facing `heading` (degrees).
fn camera(maze: &Maze, at: Vec2, heading: f32) -> Camera {
    let v = maze.viewer();
    Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(at, heading, v.fov_deg)
    }
}

/// Every pose: at each junction (3+ openings) inside the glow facing each opening, and 1–4 cells
/// before it, in a straight corridor, facing it. (position, heading)
fn poses(maze: &Maze) -> Vec<(Vec2, f32)> {
    let light = maze.exit_light();
    let heading = |d: Vec2| d.y.atan2(d.x).to_degrees();
    let next = |cell: u32, dir: Vec2| {
        maze.cell_edges(cell).iter().find_map(|&e| {
            let edge = maze.edge(e);
            let other = edge.other_side(cell).filter(|_| !edge.opaque)?;
            let d = maze.cell_centroid(other) - maze.cell_centroid(cell);
            (d.normalize().dot(dir) > 0.99).then_some(other)
        })
    };
    let mut out = Vec::new();
    for cell in 0..maze.cell_count() as u32 {
        let ways: Vec<u32> = maze
            .cell_edges(cell)
            .iter()
            .filter_map(|&e| maze.edge(e).other_side(cell).filter(|_| !maze.edge(e).opaque))
            .collect();
        if ways.len() < 3 || light.level(cell) == 0 {
            continue;
        }
        let here = maze.cell_centroid(cell);
        for &n in &ways {
            let dir = (maze.cell_centroid(n) - here).normalize();
            out.push((here, heading(dir)));
            // back along the corridor that opening leads into, facing the junction
            let mut at = cell;
            for _ in 0..4 {
                let Some(back) = next(at, dir) else { break };
                out.push((maze.cell_centroid(back), heading(-dir)));
                at = back;
            }
        }
    }
    out
}

/// The samples (index in a `width × height` grid) within one sample of the projection of the world
/// segment `p`–`q` where it lies in front of the eye.
pub(crate) fn near_line(eye: &mazewalk_render::Eye, p: Vec3, q: Vec3, out: &mut Vec<usize>) {
    let (w, h) = (eye.width as i64, eye.height as i64);
    for k in 0..=256 {
        let point = p.lerp(q, k as f32 / 256.0);
        let clip = eye.clip(point);
        if clip.w <= eye.near {
            continue;
        }
        let g = eye.grid(clip);
        let (x, y) = (g.x.floor() as i64, g.y.floor() as i64);
        for (dx, dy) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (0, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (x, y) = (x + dx, y + dy);
            if (0..w).contains(&x) && (0..h).contains(&y) {
                out.push((y * w + x) as usize);
            }
        }
    }
}

/// The samples (index in a `width × height` grid, each once) the projection of the world segment
/// `p`–`q` passes through where it lies in front of the eye: the line's own samples.
pub(crate) fn on_line(eye: &mazewalk_render::Eye, p: Vec3, q: Vec3) -> Vec<usize> {
    let mut own = Vec::new();
    for k in 0..=64 {
        let clip = eye.clip(p.lerp(q, k as f32 / 64.0));
        if clip.w > eye.near {
            let g = eye.grid(clip);
            if g.x >= 0.0 && g.y >= 0.0 && (g.x as usize) < eye.width && (g.y as usize) < eye.height {
                own.push(g.y as usize * eye.width + g.x as usize);
            }
        }
    }
    own.sort_unstable();
    own.dedup();
    own
}

/// One mode of the measure: a colour depth with half blocks, or ascii without colour.
#[derive(Clone, Copy, Debug)]
enum Mode {
    Half(ColorDepth),
    Ascii,
}

/// OKLab of an sRGB colour.
pub(crate) fn lab(rgb: [u8; 3]) -> Vec3 {
    let linear = rgb.map(|c| mazewalk_render::shade::srgb_to_linear(f32::from(c) / 255.0));
    Vec3::from_array(mazewalk_term::frame::oklab(linear, f32::cbrt))
}

/// How the way's line shows in `depth` (OKLab).
pub(crate) fn way_look(depth: ColorDepth) -> Vec3 {
    match depth {
        ColorDepth::Ansi16 => lab(xterm_rgb(3)),
        _ => lab(xterm_rgb(64)), // (95, 135, 0), truecolor's own
    }
}

/// The tally of one mode over every view.
#[derive(Default, Debug)]
struct Tally {
    /// Toward-exit openings in view (at least SHOWN samples of their line show floor or ceiling),
    /// by distance band: 0–1, 2, 3, 4–6 cells.
    in_view: [usize; 4],
    /// Of those, the ones whose line shows the way's look on at least SHOWN samples.
    shown: [usize; 4],
    /// Samples of the way's look.
    way_samples: usize,
    /// Samples of the way's look not within a sample of a toward-exit opening's line, or not on the
    /// floor or the ceiling (a wall, the beacon): each a failure.
    stray: Vec<String>,
    /// Beacon samples showing the way's look.
    beacon_taken: usize,
    /// 16 colours: samples of walls of a dark cell (beyond the glow) that show the dark yellow, as a
    /// brown or olive wall's ramp may there (no entry of the 16 is left that no wall or the beacon
    /// shows).
    dark_walls: usize,
    /// 16 colours: floor samples round the exit's point showing the dark yellow (the exit's own
    /// light on the floor, as before the way's lines).
    round_exit: usize,
    views: usize,
}

fn measure(mode: Mode, seeds: &[u64], every: usize) -> Tally {
    let (charset, depth) = match mode {
        Mode::Half(depth) => (Charset::Half, depth),
        Mode::Ascii => (Charset::Ascii, ColorDepth::None),
    };
    let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
    let mut tally = Tally::default();
    let mut renderer = Renderer::new();
    for &seed in seeds {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let light = maze.exit_light();
        for (at, heading) in poses(&maze).into_iter().step_by(every) {
            let camera = camera(&maze, at, heading);
            let frame = draw(&mut renderer, &maze, &camera, &options, 120, 40);
            tally.views += 1;
            let (sx, sy) = charset.samples_per_cell();
            let eye = camera.eye(120 * sx, 40 * sy, charset.sample_aspect(options.cell_aspect)).expect("eye");
            let ids = renderer.samples().id().to_vec();
            let is_way: Vec<bool> = match mode {
                Mode::Half(depth) => {
                    let look = way_look(depth);
                    quality::shown(&frame, Charset::Half).iter().map(|c| c.distance(look) < 1e-3).collect()
                }
                Mode::Ascii => frame.cells().iter().map(|c| c.ch == '^').collect(),
            };
            // the toward-exit openings seen from the eye's side: their lines' samples
            let mut toward_samples = Vec::new();
            for e in 0..maze.edges().len() as u32 {
                let Some(dim) = light.lit_through(&maze, e) else { continue };
                let (a, b) = maze.edge_points(e);
                let side = |p: Vec2| (b - a).perp_dot(p - a);
                if side(at) * side(maze.cell_centroid(dim)) <= 0.0 {
                    continue; // seen from the brighter side: the way back, an ordinary line
                }
                let mut line = Vec::new();
                near_line(&eye, a.extend(FLOOR_Z), b.extend(FLOOR_Z), &mut line);
                near_line(&eye, a.extend(CEILING_Z), b.extend(CEILING_Z), &mut line);
                line.sort_unstable();
                line.dedup();
                toward_samples.extend_from_slice(&line);
                // in view: the line's own samples (not the band round it) showing floor or ceiling
                let mut own = on_line(&eye, a.extend(FLOOR_Z), b.extend(FLOOR_Z));
                own.extend(on_line(&eye, a.extend(CEILING_Z), b.extend(CEILING_Z)));
                own.sort_unstable();
                own.dedup();
                let open = own.iter().filter(|&&i| ids[i] == FLOOR || ids[i] == CEILING).count();
                if open < SHOWN {
                    continue;
                }
                let cells = Vec2::new(a.distance(at), b.distance(at)).min_element().min(
                    // the nearest point of the opening
                    at.distance(
                        a + (b - a) * ((at - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0),
                    ),
                ) / mazewalk_maze::generate::CELL_SIZE;
                let band = match cells as usize {
                    0 | 1 => 0,
                    2 => 1,
                    3 => 2,
                    4..=6 => 3,
                    _ => continue,
                };
                tally.in_view[band] += 1;
                let glowing = line.iter().filter(|&&i| is_way[i]).count();
                if glowing >= SHOWN {
                    tally.shown[band] += 1;
                }
            }
            toward_samples.sort_unstable();
            for (i, &way) in is_way.iter().enumerate() {
                if !way {
                    continue;
                }
                tally.way_samples += 1;
                tally.beacon_taken += usize::from(ids[i] == BEACON);
                let on_plane = ids[i] == FLOOR || ids[i] == CEILING;
                let dark_wall = (ids[i] as usize) < maze.edges().len() && {
                    let edge = maze.edge(ids[i]);
                    [edge.left, edge.right].iter().flatten().any(|&c| light.level(c) == 0)
                };
                if matches!(mode, Mode::Half(ColorDepth::Ansi16)) && dark_wall {
                    tally.dark_walls += 1;
                    continue;
                }
                // 16 colours: the floor round the beacon, the exit's own light on it (within 2 units
                // of the exit's point), shows the dark yellow as it did before the way's lines
                let (start, dir) = eye.ray((i % eye.width) as f32 + 0.5, (i / eye.width) as f32 + 0.5);
                let on_floor = start + dir * ((FLOOR_Z - start.z) / dir.z);
                let round_exit = ids[i] == FLOOR
                    && maze.exit_point().is_some_and(|x| x.distance(on_floor.truncate()) < 2.5);
                if matches!(mode, Mode::Half(ColorDepth::Ansi16)) && round_exit {
                    tally.round_exit += 1;
                    continue;
                }
                if !on_plane || toward_samples.binary_search(&i).is_err() {
                    tally.stray.push(format!(
                        "{mode:?} seed {seed} at {at} heading {heading}: sample {i} (id {})",
                        ids[i]
                    ));
                }
            }
        }
    }
    tally
}

const MODES: [Mode; 4] = [
    Mode::Half(ColorDepth::TrueColor),
    Mode::Half(ColorDepth::Ansi256),
    Mode::Half(ColorDepth::Ansi16),
    Mode::Ascii,
];

/// One line of the measure for `mode`.
fn report(mode: Mode, tally: &Tally) {
    let band = |k: usize| {
        format!(
            "{}/{} ({:.2})",
            tally.shown[k],
            tally.in_view[k],
            tally.shown[k] as f64 / tally.in_view[k].max(1) as f64
        )
    };
    eprintln!(
        "{mode:?}: {} views; toward-exit openings shown / in view: 0–1 cells {}, 2 cells {}, 3 cells {}, \
         4–6 cells {}; way samples {}, off its lines {}, on the beacon {}, on dark walls (16) {}, round the exit (16) {}",
        tally.views,
        band(0),
        band(1),
        band(2),
        band(3),
        tally.way_samples,
        tally.stray.len(),
        tally.beacon_taken,
        tally.dark_walls,
        tally.round_exit,
    );
}

/// In every mode, over junction views inside the glow (two of the held-out mazes, every third pose):
/// the way's look shows only on the lines of openings the light comes through toward the eye (never
/// on another opening's line, a lit wall or the beacon), and the toward-exit openings within a cell
/// or so show it.
#[test]
fn inside_the_glow_the_line_the_light_comes_through_glows_and_no_other_does() {
    let tallies: Vec<(Mode, Tally)> =
        MODES.iter().map(|&mode| (mode, measure(mode, &[SEEDS[0], SEEDS[3]], 3))).collect();
    for (mode, tally) in &tallies {
        report(*mode, tally);
    }
    for (mode, tally) in tallies {
        let share = |k: usize| tally.shown[k] as f64 / tally.in_view[k].max(1) as f64;
        assert!(tally.views > 150, "{mode:?}: {} views", tally.views);
        crate::none_failed(tally.way_samples, 1000, &tally.stray, "samples of the way's look off its lines");
        assert_eq!(tally.beacon_taken, 0, "{mode:?}");
        assert!(tally.in_view[0] > 100, "{mode:?}: {:?}", tally.in_view);
        assert!(
            share(0) >= 0.9,
            "{mode:?}: near toward-exit openings shown {:?} of {:?}",
            tally.shown,
            tally.in_view
        );
    }
}

/// The whole measure, every held-out maze and pose, for BENCHMARKS.md (2,752 views a mode; about five
/// minutes on a loaded two-core machine):
/// `cargo test -p mazewalk-render --test render glow_way_measure -- --ignored --nocapture`.
#[test]
#[ignore]
fn glow_way_measure() {
    for mode in MODES {
        report(mode, &measure(mode, &SEEDS, 1));
    }
}
