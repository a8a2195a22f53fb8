//! Issue #39: the exit's light spills down the corridors (block light, `mazewalk_maze::light`): walls
//! within a few cells' path of the exit take a faint tint of the exit's green, stronger closer; walls
//! beyond its reach, or behind a wall from it, are drawn as in a maze without an exit.

use glam::Vec3;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::light::ExitLight;
use mazewalk_render::{Camera, RenderOptions, Renderer, Target};
use mazewalk_term::frame::{ColorDepth, Frame};

/// The maze without its exit: the same walls, no light.
fn without_exit(maze: &Maze) -> Maze {
    let mut edges = mazewalk_maze::Edges::new();
    for e in 0..maze.edges().len() {
        edges.push(maze.edge(e as u32));
    }
    Maze::new(maze.vertices().to_vec(), edges, maze.cells().clone(), *maze.viewer(), None).expect("maze")
}

/// Linear colours and ids of the samples of `camera`'s view (truecolor, half blocks, 120×40).
fn samples(maze: &Maze, camera: &Camera) -> (Vec<Vec3>, Vec<u32>) {
    let mut frame = Frame::new(120, 40);
    let region = frame.region();
    let mut renderer = Renderer::new();
    let options = RenderOptions { color_depth: ColorDepth::TrueColor, ..RenderOptions::default() };
    renderer.render(maze, camera, &[], &options, Target::Frame(&mut frame, region)).expect("camera");
    (renderer.samples().color().to_vec(), renderer.samples().id().to_vec())
}

/// The exit's light (linear RGB, as the beacon's glow).
const EXIT_GLOW: Vec3 = Vec3::new(0.20, 1.0, 0.42);

/// How far a colour's chromaticity (its shares of red, green and blue) is from the exit's light's.
fn off_exit_hue(c: Vec3) -> f32 {
    let chromaticity = |c: Vec3| c / (c.x + c.y + c.z).max(1e-6);
    chromaticity(c).distance(chromaticity(EXIT_GLOW))
}

#[test]
fn walls_near_the_exit_lean_green_and_walls_out_of_its_reach_do_not() {
    let maze = generate(&GenOptions::walk(20, 15, 71)).expect("maze");
    let dark = without_exit(&maze);
    let light = ExitLight::of(&maze);
    let v = maze.viewer();
    let mut near_walls = 0;
    let mut far_walls = 0;
    for cell in 0..maze.cell_count() as u32 {
        let level = light.level(cell);
        for heading in [0.0, 90.0, 180.0, 270.0] {
            let camera = Camera {
                eye_z: v.z,
                min_vfov_deg: maze.min_vfov_deg(),
                ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
            };
            let ((lit, ids), (unlit, _)) = (samples(&maze, &camera), samples(&dark, &camera));
            // The wall straight ahead, in the middle of the view, if it belongs to this cell.
            let middle = (ids.len() / 120 / 2) * 120 + 60;
            let id = ids[middle];
            let Some(&e) = maze.cell_edges(cell).iter().find(|&&e| e == id) else { continue };
            assert!(maze.edge(e).opaque);
            let (a, b) = (lit[middle], unlit[middle]);
            if level == 0 {
                assert_eq!(a, b, "cell {cell} (no light) heading {heading}: wall {e} changed");
                far_walls += 1;
            } else {
                let (da, db) = (off_exit_hue(a), off_exit_hue(b));
                // nearer the exit's hue, by more the nearer the exit (the tint is 5 % of the way per
                // level in colour, less in chromaticity, which moves less than the colour: 2 % asked)
                assert!(
                    da < db * (1.0 - 0.02 * f32::from(level)),
                    "cell {cell} level {level} heading {heading}: {da} off the exit's hue lit, {db} unlit"
                );
                let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
                assert!(
                    (luminance(a) - luminance(b)).abs() < 0.02 * luminance(b) + 1e-3,
                    "the tint keeps a wall's luminance: {a} against {b}"
                );
                near_walls += 1;
            }
        }
    }
    assert!(near_walls >= 8, "walls faced within the light's reach: {near_walls}");
    assert!(far_walls >= 100, "walls faced beyond it: {far_walls}");
}

// In 16 colours a tinted green wall's nearest entry is the beacon's bright green: no tint there.
#[test]
fn sixteen_colours_draw_no_tint() {
    let maze = generate(&GenOptions::walk(20, 15, 71)).expect("maze");
    let dark = without_exit(&maze);
    let light = ExitLight::of(&maze);
    let v = maze.viewer();
    let walls = maze.edges().len() as u32;
    let render = |maze: &Maze, camera: &Camera| {
        let mut frame = Frame::new(120, 40);
        let region = frame.region();
        let mut renderer = Renderer::new();
        let options = RenderOptions { color_depth: ColorDepth::Ansi16, ..RenderOptions::default() };
        renderer.render(maze, camera, &[], &options, Target::Frame(&mut frame, region)).expect("camera");
        (renderer.samples().color().to_vec(), renderer.samples().id().to_vec())
    };
    let mut compared = 0;
    for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0) {
        for heading in [0.0, 90.0, 180.0, 270.0] {
            let camera = Camera {
                eye_z: v.z,
                min_vfov_deg: maze.min_vfov_deg(),
                ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
            };
            let ((lit, ids), (unlit, _)) = (render(&maze, &camera), render(&dark, &camera));
            // Inside walls: an edge sample depends on its neighbours, and the beacon, drawn only in
            // the lit maze, puts edges on the walls beside it.
            let width = 120;
            let inside = |k: usize| {
                [k.wrapping_sub(1), k + 1, k.wrapping_sub(width), k + width]
                    .iter()
                    .all(|&n| ids.get(n).is_none_or(|&id| id == ids[k]))
            };
            for k in (0..ids.len()).filter(|&k| ids[k] < walls && inside(k)) {
                assert_eq!(lit[k], unlit[k], "cell {cell} heading {heading} sample {k}");
                compared += 1;
            }
        }
    }
    assert!(compared > 1000, "{compared}");
}
