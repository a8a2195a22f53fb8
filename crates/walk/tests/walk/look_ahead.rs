//! Issue #39, far openings: a look-ahead lens (`z`). A generated maze's walk keeps a vertical field
//! of 96° (a player 1.6 from a wall still sees its ends and the floor), which at 120×40 half blocks is
//! a horizontal field of ~118°, ~36 columns a unit of tan: a side opening k cells down a corridor
//! spans 8f/(16k²−4) columns, 0.7 at k = 5 and 0.5 at k = 6, narrower than anything a column shows.
//! The walk's view is foveated (`mazewalk_render::fovea`): the same field, its middle magnified,
//! so those openings span 2.3–3.1 times the columns (1.6 at k = 6, 5.0 at k = 3). The lens is a
//! horizontal field of 30° with no widening (f ≈ 224: 3.1 columns at k = 6), the camera `mazewalk
//! render --fov 30` draws; `z` again brings back the field the player had.

use glam::Vec2;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::grid;
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, Target};
use mazewalk_term::frame::Frame;
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::App;
use mazewalk_walk::state::LOOK_AHEAD_FOV_DEG;

const COLS: usize = 120;
const ROWS: usize = 40;

fn press(app: &mut App, c: char, now: f64) {
    app.key(Key::Char(c), KeyPhase::Press, now);
    app.tick(now + 0.02);
}

/// The camera without its fields of view: what the lens must leave alone.
fn pose(c: &Camera) -> Camera {
    Camera { hfov_deg: 0.0, min_vfov_deg: 0.0, ..*c }
}

#[test]
fn z_turns_a_30_degree_lens_on_and_off_brings_back_the_exact_field() {
    let maze = generate(&GenOptions::walk(20, 15, 5)).expect("maze");
    let mut app = App::new(maze, RenderOptions::default(), 0.0).unwrap();
    assert!(app.camera.min_vfov_deg > 90.0, "a generated maze widens its view on a wide screen");
    // a field the player chose with `+` (both fields wider): what `z` must bring back
    press(&mut app, '+', 1.0);
    let wide = app.camera;
    assert!(app.shown_hfov_deg(COLS, ROWS - 1) > 110.0, "{}", app.shown_hfov_deg(COLS, ROWS - 1));
    assert!(!app.look_ahead());

    press(&mut app, 'z', 2.0);
    assert!(app.look_ahead());
    assert_eq!((app.camera.hfov_deg, app.camera.min_vfov_deg), (LOOK_AHEAD_FOV_DEG, 0.0));
    assert_eq!(LOOK_AHEAD_FOV_DEG, 30.0);
    // no widening, whatever the screen's shape
    for (cols, rows) in [(COLS, ROWS - 1), (80, 23), (200, 59), (40, 40)] {
        assert_eq!(app.shown_hfov_deg(cols, rows), 30.0, "{cols}×{rows}");
    }
    assert_eq!(pose(&app.camera), pose(&wide), "the lens changes the field only");
    // a release of `z` (kitty protocol) does nothing
    app.key(Key::Char('z'), KeyPhase::Release, 2.05);
    assert!(app.look_ahead());
    // off: exactly the field the player had
    press(&mut app, 'z', 3.0);
    assert!(!app.look_ahead());
    assert_eq!(app.camera, wide);

    // walking and turning with the lens on work as usual, and off keeps where they went
    press(&mut app, 'z', 4.0);
    press(&mut app, 'w', 5.0);
    app.key(Key::Left, KeyPhase::Press, 6.0);
    app.tick(6.02);
    app.key(Key::Up, KeyPhase::Press, 7.0);
    app.tick(7.02);
    assert_ne!(app.camera.position, wide.position, "walked");
    assert_eq!(app.camera.yaw_deg, (wide.yaw_deg + 15.0).rem_euclid(360.0), "turned a tap");
    assert_eq!(app.camera.pitch_deg, 10.0, "looked up a tap");
    assert_eq!(app.camera.hfov_deg, 30.0);
    let moved = pose(&app.camera);
    press(&mut app, 'z', 8.0);
    assert_eq!(app.camera, Camera { hfov_deg: wide.hfov_deg, min_vfov_deg: wide.min_vfov_deg, ..moved });

    // `+` / `-` with the lens on widen or narrow the lens (still no widening); `z` brings back the
    // field from before the lens, not the lens's
    press(&mut app, 'z', 9.0);
    press(&mut app, '-', 10.0);
    assert!(app.look_ahead());
    assert_eq!((app.camera.hfov_deg, app.camera.min_vfov_deg), (25.0, 0.0));
    assert_eq!(app.shown_hfov_deg(COLS, ROWS - 1), 25.0);
    press(&mut app, '+', 11.0);
    press(&mut app, '+', 12.0);
    assert_eq!((app.camera.hfov_deg, app.camera.min_vfov_deg), (35.0, 0.0));
    press(&mut app, 'z', 13.0);
    assert_eq!((app.camera.hfov_deg, app.camera.min_vfov_deg), (wide.hfov_deg, wide.min_vfov_deg));

    // `r`, back to the start: the start's field, the lens off
    press(&mut app, 'z', 14.0);
    press(&mut app, 'r', 15.0);
    assert!(!app.look_ahead());
    assert!(app.camera.min_vfov_deg > 90.0 && app.camera.hfov_deg != 30.0, "{:?}", app.camera);
}

/// A straight corridor of tiles 4 units wide (the generated mazes' cells) running east from the start
/// (`@`), side openings 1..6 cells ahead on alternating sides (north at 1, 3, 5; south at 2, 4, 6),
/// each one tile deep, the end wall 7 cells ahead; the generated mazes' fields (90° widened to a
/// vertical 96°).
const CORRIDOR: &str = "mazewalk-grid 1
tile 4
vfov 96.02558

#########
##.#.#.##
#@......#
###.#.#.#
#########
";

/// For each opening 1..=6 cells ahead, in the view `camera` sees at 120×40 half blocks: the sample
/// columns whose sample on the horizon row shows one of the opening's side cell's walls (the wall
/// faced through it or the cell's far side), not the corridor's side wall; and the columns it spans
/// by the projection of its two ends.
fn opening_columns(maze: &mazewalk_maze::Maze, camera: &Camera) -> Vec<(usize, f32)> {
    let options = RenderOptions { charset: Charset::Half, ..RenderOptions::default() };
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(COLS, ROWS);
    let region = frame.region();
    renderer.render(maze, camera, &[], &options, Target::Frame(&mut frame, region)).expect("render");
    let samples = renderer.samples();
    let (width, height) = (samples.width(), samples.height());
    assert_eq!(width, COLS);
    let eye = camera.eye(width, height, Charset::Half.sample_aspect(options.cell_aspect)).expect("eye");
    let z = camera.eye_z;
    let at = camera.position; // the start tile's centre, facing +x
    let horizon = eye.grid(eye.clip((at + Vec2::X * 1000.0).extend(z))).y.floor() as usize;
    let edges = maze.edges().len() as u32;
    (1..=6)
        .map(|k| {
            let side = if k % 2 == 1 { 1.0 } else { -1.0 }; // north (+y) at odd k
            // the side cell: a tile k ahead and one to the side
            let centre = at + Vec2::new(4.0 * k as f32, 4.0 * side);
            let cell = maze.cell_at(centre).expect("the side cell");
            let its_walls: Vec<u32> = maze.cell_edges(cell).to_vec();
            let row = &samples.id()[horizon * width..(horizon + 1) * width];
            let shown = row.iter().filter(|&&id| id < edges && its_walls.contains(&id)).count();
            // the opening's ends, on the corridor's side line 2 units off its axis
            let end = |along: f32| {
                let p = at + Vec2::new(along, 2.0 * side);
                eye.grid(eye.clip(p.extend(z))).x
            };
            let span = (end(4.0 * k as f32 - 2.0) - end(4.0 * k as f32 + 2.0)).abs();
            (shown, span)
        })
        .collect()
}

#[test]
fn the_foveated_view_and_the_lens_widen_openings_three_to_six_cells_ahead() {
    let maze = grid::parse_str("corridor.grid", CORRIDOR).expect("the corridor");
    let mut app = App::new(maze, RenderOptions::default(), 0.0).unwrap();
    assert_eq!(app.camera.yaw_deg, 0.0);
    // the walk's own field: ~118° at 120×40; drawn plainly, far openings are narrower than a column
    let wide_deg = app.shown_hfov_deg(COLS, ROWS);
    assert!((110.0..125.0).contains(&wide_deg), "{wide_deg}");
    assert!(app.camera.fovea, "the walk's view is foveated");
    let plain = opening_columns(app.maze(), &Camera { fovea: false, ..app.camera });
    for k in [5, 6] {
        let (shown, span) = plain[k - 1];
        assert!(span < 1.0 && shown <= 1, "plain wide field, {k} cells: {shown} columns, span {span:.2}");
    }
    assert!(plain[2].1 < 2.5 && plain[3].1 < 1.5, "plain wide field, 3 and 4 cells: {plain:?}");

    // the walk's foveated view: the same field, far openings several times as wide
    let fovea = opening_columns(app.maze(), &app.camera);
    for k in 3..=6 {
        let (shown, span) = fovea[k - 1];
        assert!(span >= 2.3 * plain[k - 1].1, "foveated, {k} cells: span {span:.2} against {plain:?}");
        let least = if k < 6 { 2 } else { 1 }; // (at 6 cells 1.6 columns: one whole one)
        assert!(shown >= least, "foveated, {k} cells: {shown} columns");
    }

    press(&mut app, 'z', 1.0);
    assert_eq!(app.shown_hfov_deg(COLS, ROWS), 30.0);
    let lens = opening_columns(app.maze(), &app.camera);
    for k in 3..=6 {
        let (shown, span) = lens[k - 1];
        assert!(shown >= 3 && span >= 3.0, "look ahead, {k} cells: {shown} columns, span {span:.2}");
        assert!(shown > plain[k - 1].0, "look ahead, {k} cells: {shown} against {plain:?}");
    }
    eprintln!("columns (shown, span) for k = 1..6: plain {plain:?}, foveated {fovea:?}, look ahead {lens:?}");
}

/// `f` turns the foveated view off and on: the same field and pose, drawn plainly (the far openings
/// back to their unmagnified widths) or magnified in the middle; `r` brings back the start's.
#[test]
fn f_turns_the_magnified_middle_off_and_on() {
    let maze = grid::parse_str("corridor.grid", CORRIDOR).expect("the corridor");
    let mut app = App::new(maze, RenderOptions::default(), 0.0).unwrap();
    assert!(app.camera.fovea);
    let foveated = opening_columns(app.maze(), &app.camera);
    press(&mut app, 'f', 1.0);
    assert!(!app.camera.fovea);
    let plain = opening_columns(app.maze(), &app.camera);
    assert!(plain[5].1 < 1.0 && foveated[5].1 > 1.5, "6 cells: plain {plain:?}, foveated {foveated:?}");
    press(&mut app, 'f', 2.0);
    assert!(app.camera.fovea);
    press(&mut app, 'f', 3.0);
    press(&mut app, 'r', 4.0);
    assert!(app.camera.fovea, "back to the start: the start's view");
}
