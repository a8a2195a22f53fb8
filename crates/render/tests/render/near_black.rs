//! Issue #39: in 16 colours "no surface is drawn black unless it is black". A player reported a black
//! strip across the far end of a corridor, above the last wall, where truecolor shows sRGB
//! (44,45,46), OKLab L ≈ 0.30: the ceiling's far cell line. 16 colours leave out the far lines that
//! would crowd toward the horizon (`LINE_GAP_16`), and there the ceiling's own light, fogged to
//! L ≈ 0.19, took the black of its ramp. Over many views (generated mazes, poses anywhere in a
//! cell, nose to a wall and down corridors, every heading, pitched up and down, 120×40 and 80×24,
//! half blocks and ascii): no sample whose truecolor colour is at least `NEAR_BLACK` light is shown
//! black in 16 colours, and no ceiling sample is black unless its colour is.

use glam::{Vec2, Vec3};
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::palette::NEAR_BLACK;
use mazewalk_render::quality::{self, held_out_views};
use mazewalk_render::samples::{CEILING, FLOOR, NONE};
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer};
use mazewalk_term::frame::{Color, ColorDepth};

use super::none_failed;
use crate::draw;

/// What a sample's OKLab lightness is taken as black below (the 16 colours' black is L 0).
const SHOWN_BLACK: f32 = 0.01;

/// A sample's colour as the terminal shows it (OKLab), its ink (ascii: the colour its glyph is drawn
/// in, a blank too), its renderer colour (linear) and coverage id.
struct Shown {
    lab: Vec<Vec3>,
    ink: Vec<Vec3>,
    linear: Vec<Vec3>,
    ids: Vec<u32>,
}

/// What the terminal shows of `camera`'s view at `cols × rows` in `charset` and `depth`. In ascii a
/// cell is one sample, shown in its glyph's ink (a blank: nothing, taken as black).
fn shown(
    maze: &Maze,
    camera: &Camera,
    (cols, rows): (usize, usize),
    charset: Charset,
    depth: ColorDepth,
) -> Shown {
    let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
    let mut renderer = Renderer::new();
    let frame = draw(&mut renderer, maze, camera, &options, cols, rows);
    let (lab, ink) = match charset {
        Charset::Ascii => {
            let ink: Vec<Vec3> = frame
                .cells()
                .iter()
                .map(|cell| match cell.fg {
                    Color::Rgb(r, g, b) => quality::oklab_srgb8([r, g, b]),
                    Color::Indexed(i) => quality::oklab_srgb8(mazewalk_render::palette::xterm_rgb(i)),
                    Color::Default => Vec3::ONE,
                })
                .collect();
            let lab =
                frame.cells().iter().zip(&ink).map(|(c, &ink)| if c.ch == ' ' { Vec3::ZERO } else { ink });
            (lab.collect(), ink)
        }
        _ => {
            let lab = quality::shown(&frame, charset);
            (lab.clone(), lab)
        }
    };
    let samples = renderer.samples();
    Shown { lab, ink, linear: samples.color().to_vec(), ids: samples.id().to_vec() }
}

/// A sample's coverage id in words.
fn surface(id: u32) -> String {
    match id {
        FLOOR => "floor".into(),
        CEILING => "ceiling".into(),
        NONE => "nothing".into(),
        wall => format!("wall {wall}"),
    }
}

/// What the 16 colours' frame shows black though it is not: a sample whose truecolor colour is at
/// least `NEAR_BLACK` light, or a ceiling sample whose colour (in the 16 colours' own scene) is not
/// black: the ceiling shows its own entry (or its lines'), near and far. Returns how many samples were judged and the failures, described.
fn blackened(maze: &Maze, camera: &Camera, size: (usize, usize), charset: Charset) -> (usize, Vec<String>) {
    let truth = shown(maze, camera, size, charset, ColorDepth::TrueColor);
    let sixteen = shown(maze, camera, size, charset, ColorDepth::Ansi16);
    let width = size.0 * charset.samples_per_cell().0;
    let mut failures = Vec::new();
    let mut judged = 0;
    for (i, (t, s)) in truth.lab.iter().zip(&sixteen.lab).enumerate() {
        let lit = t.x >= NEAR_BLACK;
        // (in ascii the ceiling's glyph is a blank where it is darkest, in every depth: its ink counts)
        let sky = sixteen.ids[i] == CEILING && sixteen.linear[i].element_sum() >= 1e-5;
        judged += usize::from(lit || sky);
        if lit && s.x < SHOWN_BLACK || sky && sixteen.ink[i].x < SHOWN_BLACK {
            failures.push(format!(
                "{charset:?} {}x{} at {:?} heading {:.1} pitch {:.1}: sample ({}, {}) shown black, truecolor L \
                 {:.3}; {} (truecolor: {}), linear {} (truecolor {})",
                size.0,
                size.1,
                camera.position,
                camera.yaw_deg,
                camera.pitch_deg,
                i % width,
                i / width,
                t.x,
                surface(sixteen.ids[i]),
                surface(truth.ids[i]),
                sixteen.linear[i],
                truth.linear[i],
            ));
        }
    }
    (judged, failures)
}

/// Poses of the player's report and of the views found with the same black strip.
fn reported() -> Vec<(Maze, Camera)> {
    let places = [
        (60374, (22.0, 58.0), 270.0),
        (71, (14.0, 10.0), 90.0),
        (71, (2.0, 30.0), 0.0),
        (9, (42.0, 42.0), 90.0),
    ];
    places
        .into_iter()
        .map(|(seed, (x, y), heading)| {
            let maze = generate(&GenOptions::walk(20, 15, seed)).expect("generated maze");
            let v = maze.viewer();
            let camera = Camera {
                eye_z: v.z,
                min_vfov_deg: maze.min_vfov_deg(),
                fovea: true,
                ..Camera::new(Vec2::new(x, y), heading, v.fov_deg)
            };
            (maze, camera)
        })
        .collect()
}

/// The charsets and sizes each view is drawn at, and the pitches it is seen at (level, up, down).
const CHARSETS: [Charset; 2] = [Charset::Half, Charset::Ascii];
const SIZES: [(usize, usize); 2] = [(120, 40), (80, 24)];
const PITCHES: [f32; 3] = [0.0, 20.0, -25.0];

/// Over `n` held-out views of `maze` (from `seed`), each at every size and charset, the view's
/// `k`-th pitch in turn: samples judged, and the samples shown black though not near black.
fn sweep(maze: &Maze, seed: u64, n: usize) -> (usize, usize, Vec<String>) {
    let (mut views, mut judged, mut failures) = (0, 0, Vec::new());
    for (k, (_, camera)) in held_out_views(maze, seed, n).into_iter().enumerate() {
        let camera = Camera { pitch_deg: PITCHES[k % PITCHES.len()], ..camera };
        for size in SIZES {
            for charset in CHARSETS {
                let (j, f) = blackened(maze, &camera, size, charset);
                (views, judged) = (views + 1, judged + j);
                failures.extend(f);
            }
        }
    }
    (views, judged, failures)
}

/// The player's report and the three views found like it: the ceiling's far band above the end
/// wall was black in 16 colours (11 samples in all at 120×40 half blocks before the fix).
#[test]
fn the_reported_views_show_no_black_strip() {
    let (mut judged, mut failures) = (0, Vec::new());
    for (maze, camera) in reported() {
        for size in SIZES {
            for charset in CHARSETS {
                let (j, f) = blackened(&maze, &camera, size, charset);
                judged += j;
                failures.extend(f);
            }
        }
    }
    none_failed(judged, 10_000, &failures, "samples lighter than NEAR_BLACK shown black in 16 colours");
}

/// Thirty held-out views of each of five generated 20×15 mazes (the report's three seeds and two
/// more), at both sizes, in half blocks and ascii, level and pitched: none shows such a sample.
#[test]
fn held_out_views_of_generated_mazes_show_nothing_black_that_is_not() {
    let (mut views, mut judged, mut failures) = (0, 0, Vec::new());
    for seed in [60374, 71, 9, 3, 202] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("generated maze");
        let (v, j, f) = sweep(&maze, seed, 30);
        (views, judged) = (views + v, judged + j);
        failures.extend(f);
    }
    eprintln!("{views} frames, {judged} samples judged, {} shown black", failures.len());
    none_failed(judged, 500_000, &failures, "samples lighter than NEAR_BLACK shown black in 16 colours");
}

proptest::proptest! {
    #![proptest_config(mazewalk_testkit::config_cases(6))]

    /// Any generated maze, views anywhere (in a cell, nose to a wall, down a corridor), at both sizes
    /// and charsets, level and pitched.
    #[test]
    fn no_sample_lighter_than_near_black_is_shown_black(
        seed in proptest::prelude::any::<u64>(),
        width in 6u32..24,
        height in 6u32..18,
    ) {
        let maze = generate(&GenOptions::walk(width, height, seed)).expect("generated maze");
        let (views, judged, failures) = sweep(&maze, seed, 9);
        proptest::prop_assert!(views >= 9 * SIZES.len() * CHARSETS.len() && judged > 20_000, "{views} frames, {judged} samples");
        proptest::prop_assert!(failures.is_empty(), "{} of {judged}; first: {:#?}", failures.len(), &failures[..failures.len().min(5)]);
    }
}
