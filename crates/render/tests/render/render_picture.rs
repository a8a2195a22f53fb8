//! The picture (issue #15): edges where surfaces meet, light by orientation, walls never black, the
//! exit visible from down a corridor.

use crate::draw;
use glam::{Vec2, Vec3};
use mazewalk_maze::{Maze, grid};
use mazewalk_render::shade::luminance;
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, Renderer, Target};
use mazewalk_term::frame::{Color, ColorDepth, Frame};

fn maze(text: &str) -> Maze {
    grid::parse_str("test.grid", text).unwrap()
}

fn samples(maze: &Maze, camera: &Camera, cols: usize, rows: usize) -> Renderer {
    let mut renderer = Renderer::new();
    renderer
        .render(
            maze,
            camera,
            &[],
            &RenderOptions { charset: Charset::Ascii, culling: Culling::Portal, ..RenderOptions::default() },
            Target::Samples { cols, rows },
        )
        .unwrap();
    renderer
}

/// A room whose walls all have one colour; looking into its north-east corner from inside.
const ROOM: &str = "mazewalk-grid 1
# = #8080c0
######
#....#
#....#
#@...#
######
";

#[test]
fn two_walls_of_one_colour_meeting_at_a_corner_stay_distinct() {
    let maze = maze(ROOM);
    // From the middle of the room, facing the north-east corner (45°), 7 units from it.
    let camera = Camera::new(Vec2::new(15.0, 11.0), 45.0, 90.0);
    let (cols, rows) = (81, 40);
    let renderer = samples(&maze, &camera, cols, rows);
    let s = renderer.samples();
    let y = rows / 2 - 1; // eye level: the corner is a vertical line through the middle
    let row: Vec<(u32, Vec3)> = (0..cols).map(|x| (s.id()[y * cols + x], s.color()[y * cols + x])).collect();
    let walls = maze.edges().len() as u32;
    // Where a wall running east-west meets one running north-south (not a seam between two tiles' edges
    // of one straight wall).
    let direction = |id: u32| {
        let (a, b) = maze.edge_points(id);
        (b - a).normalize().abs()
    };
    let corner = (1..cols).find(|&x| {
        row[x - 1].0 < walls && row[x].0 < walls && direction(row[x - 1].0).dot(direction(row[x].0)) < 0.5
    });
    let x = corner.expect("two walls meet in the view");
    let (left, right) = (row[x - 4].1, row[x + 3].1); // inside each wall, off the edge
    let edge = [row[x - 1].1, row[x].1];
    // The walls face different ways: the sun lights them differently, faintly since issue #39 (its
    // span 0.95–1.0, so that lightness tells the headlight's geometry, not the compass; at 0.7–1.2
    // these two differed by over 10 %). The edge below is what marks the corner.
    let (l, r) = (luminance(left), luminance(right));
    assert!((l - r).abs() > 0.01 * l.max(r), "{left} vs {right}");
    // The corner itself is drawn as an edge: darker than both walls beside it.
    let darkest = luminance(edge[0]).min(luminance(edge[1]));
    assert!(darkest < 0.8 * luminance(left).min(luminance(right)), "edge {edge:?}, walls {left} {right}");
}

#[test]
fn a_black_wall_is_never_the_fog() {
    let text = "mazewalk-grid 1
K = #000000
KKKKK
K@..K
KKKKK
";
    let maze = maze(text);
    let camera = Camera::new(Vec2::new(2.0, 6.0), 0.0, 90.0); // facing the black east wall, 8 units off
    let (cols, rows) = (40, 20);
    let renderer = samples(&maze, &camera, cols, rows);
    let s = renderer.samples();
    let walls = maze.edges().len() as u32;
    let i = (rows / 2) * cols + cols / 2;
    assert!(s.id()[i] < walls, "a wall straight ahead");
    // Far from the fog colour: several 8-bit steps apart once encoded.
    let fog_free = luminance(s.color()[i]);
    assert!(fog_free > 0.004, "wall luminance {fog_free}");
    // And in every colour depth the wall's cells differ from the empty space beyond the far plane.
    // (Without colour the shade glyphs can coincide; the wall's edges still draw it.)
    for depth in [ColorDepth::Ansi16, ColorDepth::Ansi256, ColorDepth::TrueColor] {
        let mut near = Frame::new(cols, rows);
        let options =
            RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
        let region = near.region();
        Renderer::new().render(&maze, &camera, &[], &options, Target::Frame(&mut near, region)).unwrap();
        // The same view seeing only 2 units far: the wall is beyond the far plane, the middle is fog.
        let mut nothing = Frame::new(cols, rows);
        let short = Camera { view_distance: 2.0, ..camera };
        Renderer::new().render(&maze, &short, &[], &options, Target::Frame(&mut nothing, region)).unwrap();
        let middle = |f: &Frame| *f.get(cols / 2, rows / 2).unwrap();
        assert_ne!(middle(&near), middle(&nothing), "{depth:?}: the black wall looks like empty space");
    }
}

/// A straight corridor, the exit three cells ahead of the start (or plain floor there).
fn corridor(exit: bool) -> Maze {
    let tile = if exit { 'E' } else { '.' };
    maze(&format!("mazewalk-grid 1\n#######\n#>..{tile}.#\n#######\n"))
}

#[test]
fn the_exit_shows_three_cells_down_a_corridor_in_every_charset_and_colour_depth() {
    let camera = Camera::new(Vec2::new(6.0, 6.0), 0.0, 90.0);
    for charset in Charset::ALL {
        for depth in [ColorDepth::None, ColorDepth::Ansi16, ColorDepth::Ansi256, ColorDepth::TrueColor] {
            let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
            let frame = |maze: &Maze| draw(&mut Renderer::new(), maze, &camera, &options, 80, 24);
            let (with, without) = (frame(&corridor(true)), frame(&corridor(false)));
            let differing = with.cells().iter().zip(without.cells()).filter(|(a, b)| a != b).count();
            // A beacon across a few columns and the floor's glow: dozens of cells, not a speck.
            assert!(differing >= 8, "{charset} {depth:?}: {differing} cells show the exit");
            if depth == ColorDepth::TrueColor {
                let green = with.cells().iter().any(|c| {
                    [c.fg, c.bg]
                        .iter()
                        .any(|&k| matches!(k, Color::Rgb(r, g, b) if g > 150 && u16::from(g) > u16::from(r) + 60 && u16::from(g) > u16::from(b) + 40))
                });
                assert!(green, "{charset}: the exit glows green");
            }
        }
    }
}

/// Without colour, shade glyphs carry the picture: the walls' usual glyph is neither the floor's nor
/// the ceiling's, in every block charset; the long ascii ramp uses many more characters than the short.
#[test]
fn without_colour_walls_floor_and_ceiling_take_different_glyphs() {
    use mazewalk_render::Ramp;
    use mazewalk_render::samples::{CEILING, FLOOR};
    use std::collections::HashMap;
    let maze = mazewalk_maze::builtin().unwrap();
    let viewer = maze.viewer();
    let camera = Camera::new(viewer.pos, viewer.dir_deg, 90.0);
    let walls = maze.edges().len() as u32;
    for charset in [Charset::Half, Charset::Quad, Charset::Sextant] {
        let options = RenderOptions { charset, color_depth: ColorDepth::None, ..RenderOptions::default() };
        let mut renderer = Renderer::new();
        let frame = draw(&mut renderer, &maze, &camera, &options, 100, 30);
        let (sx, sy) = charset.samples_per_cell();
        let s = renderer.samples();
        // Each cell by what all its samples show: a wall, the floor or the ceiling.
        let mut glyphs: HashMap<&str, HashMap<char, usize>> = HashMap::new();
        for row in 0..30 {
            for col in 0..100 {
                let ids: Vec<u32> = (0..sy)
                    .flat_map(|dy| (0..sx).map(move |dx| (row * sy + dy) * s.width() + col * sx + dx))
                    .map(|i| s.id()[i])
                    .collect();
                let kind = match ids[0] {
                    id if ids.iter().all(|&i| i == id) && id < walls => "wall",
                    FLOOR if ids.iter().all(|&i| i == FLOOR) => "floor",
                    CEILING if ids.iter().all(|&i| i == CEILING) => "ceiling",
                    _ => continue,
                };
                *glyphs.entry(kind).or_default().entry(frame.get(col, row).unwrap().ch).or_default() += 1;
            }
        }
        let usual = |kind: &str| glyphs[kind].iter().max_by_key(|(_, n)| **n).map(|(c, _)| *c).unwrap();
        let (wall, floor, ceiling) = (usual("wall"), usual("floor"), usual("ceiling"));
        assert!(
            wall != floor && wall != ceiling,
            "{charset}: wall {wall:?}, floor {floor:?}, ceiling {ceiling:?}"
        );
    }
    // Over the viewer's view turned about (each wall is one flat shade, so one view shows a few of
    // the walls' shades; the floor's and ceiling's run on with depth).
    let distinct = |ramp| {
        let options = RenderOptions {
            charset: Charset::Ascii,
            color_depth: ColorDepth::None,
            ramp,
            ..RenderOptions::default()
        };
        let mut chars: Vec<char> = Vec::new();
        for turn in [0.0, 90.0, 180.0, 270.0] {
            let camera = Camera::new(viewer.pos, viewer.dir_deg + turn, 90.0);
            let frame = draw(&mut Renderer::new(), &maze, &camera, &options, 100, 30);
            chars.extend(frame.cells().iter().map(|c| c.ch));
        }
        chars.sort_unstable();
        chars.dedup();
        chars.len()
    };
    let (short, long) = (distinct(Ramp::Short), distinct(Ramp::Long));
    assert!(long > short + 10, "long ramp {long} characters, short {short}");
}

/// Textures draw mortar joints on near walls (a spread of shades where the plain wall is smooth) and
/// keep the wall's overall brightness.
#[test]
fn textured_walls_show_joints_up_close_and_keep_their_brightness() {
    let maze = maze("mazewalk-grid 1\n#########\n#>......#\n#########\n");
    let camera = Camera::new(Vec2::new(6.0, 6.0), 30.0, 90.0); // the north wall fills the left half
    let walls = maze.edges().len() as u32;
    let shades = |textures: bool| {
        let mut renderer = Renderer::new();
        let options = RenderOptions {
            charset: Charset::Ascii,
            color_depth: ColorDepth::TrueColor,
            textures,
            ..RenderOptions::default()
        };
        draw(&mut renderer, &maze, &camera, &options, 80, 40);
        let s = renderer.samples();
        (0..s.width() * s.height())
            .filter(|&i| s.id()[i] < walls)
            .map(|i| luminance(s.color()[i]))
            .collect::<Vec<f32>>()
    };
    let (plain, textured) = (shades(false), shades(true));
    assert_eq!(plain.len(), textured.len(), "the same walls cover the same samples");
    let darker = plain.iter().zip(&textured).filter(|(p, t)| **t < 0.75 * **p).count();
    assert!(darker > textured.len() / 20, "mortar on {darker} of {} wall samples", textured.len());
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    assert!((mean(&textured) / mean(&plain) - 0.92).abs() < 0.08, "{} vs {}", mean(&textured), mean(&plain));
}

// issue #39: openings 4+ cells down a corridor were lost (a wall there is a few rows tall; the gap
// of a side opening narrower than a column). Each end of a wall at an opening is a light jamb one
// sample wide, so every side opening up to six cells away shows, in truecolor and in 256 colours.
#[test]
fn side_openings_show_as_light_jambs_as_far_as_six_cells() {
    // A corridor along y = 8..12 (tile 4), a side opening to the north every other cell.
    let corridor = maze(
        "mazewalk-grid 1\ntile 4\nfacing east\n\n###############\n###.#.#.#.#.###\n#>...........##\n###############\n",
    );
    let camera = Camera::new(Vec2::new(6.0, 6.0), 0.0, 90.0);
    let (cols, rows) = (120, 40);
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let options =
            RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
        let mut renderer = Renderer::new();
        draw(&mut renderer, &corridor, &camera, &options, cols, rows);
        let samples = renderer.samples();
        let (width, ids, colors) = (samples.width(), samples.id(), samples.color());
        let eye = camera.eye(cols, rows * 2, Charset::Half.sample_aspect(0.5)).unwrap();
        // The openings' ends on the north wall (y = 8 in the file's rows, 4-unit tiles; x = 12, 16,
        // … 28 for the openings 1.5 to 5.5 cells ahead of the eye at x = 6).
        for x_end in [12.0f32, 16.0, 20.0, 24.0, 28.0, 32.0] {
            let grid = eye.grid(eye.clip(Vec3::new(x_end, 8.0, 0.5)));
            let (gx, gy) = (grid.x.floor() as usize, grid.y.floor() as usize);
            // Along the row through the jamb's upper half, a wall sample lighter than the wall
            // samples two further out on either side.
            let lighter = (gx.saturating_sub(1)..=gx + 1).any(|x| {
                let i = gy * width + x;
                let wall = |j: usize| ids[j] == ids[i];
                let l = luminance(colors[i]);
                ids[i] < corridor.edges().len() as u32
                    && [i - 3, i + 3].iter().all(|&j| !wall(j) || luminance(colors[j]) + 0.01 < l)
            });
            assert!(lighter, "{depth:?}: no jamb where the wall ends at x = {x_end} (sample {gx}, {gy})");
        }
    }
}

// issue #39: in a dead end, a jamb was drawn where the end wall meets a side wall, for an opening
// round the corner behind the end wall (on its far side, out of sight), and was read as a way on.
// `mazewalk --gen 20x15 --seed 58` at (62, 46) facing east: the cell ahead is a dead end whose end
// wall (x = 68, y 44..48) has an opening of its own line only beyond it.
#[test]
fn a_dead_end_shows_no_jamb_for_an_opening_behind_its_end_wall() {
    use mazewalk_maze::generate::{GenOptions, generate};
    let opts = GenOptions::walk(20, 15, 58);
    let maze = generate(&opts).unwrap();
    let end = (0..maze.edges().len() as u32)
        .find(|&e| {
            let (a, b) = maze.edge_points(e);
            a.x == 68.0 && b.x == 68.0 && a.y.min(b.y) == 44.0 && a.y.max(b.y) == 48.0
        })
        .expect("the end wall");
    assert!(maze.edge(end).opaque);
    let v = maze.viewer();
    let camera = Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(Vec2::new(62.0, 46.0), 0.0, v.fov_deg)
    };
    let (cols, rows) = (120, 40);
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let options =
            RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
        let mut renderer = Renderer::new();
        draw(&mut renderer, &maze, &camera, &options, cols, rows);
        let samples = renderer.samples();
        let (width, ids, colors) = (samples.width(), samples.id(), samples.color());
        let eye = camera.eye(cols, rows * 2, Charset::Half.sample_aspect(0.5)).unwrap();
        let row = eye.grid(eye.clip(Vec3::new(68.0, 46.0, 0.5))).y.floor() as usize;
        let on_wall: Vec<f32> = (0..width)
            .map(|x| row * width + x)
            .filter(|&i| ids[i] == end)
            .map(|i| luminance(colors[i]))
            .collect();
        assert!(on_wall.len() > 20, "{depth:?}: the end wall shows");
        let plain = on_wall[on_wall.len() / 2];
        assert!(
            on_wall.iter().all(|&l| (l - plain).abs() < 0.01),
            "{depth:?}: a light jamb on the dead end's wall: {on_wall:?}"
        );
    }
}
