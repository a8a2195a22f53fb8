//! Issue #33: how the picture reads in 256 and 16 colours beside truecolor, how far you can see depth
//! in it, how apart its surfaces are, and what it costs on the wire.
//!
//! ```sh
//! nice cargo run --release -p mazewalk-bench --example picture
//! ```
//!
//! `-- --held-out` gives the held-out views' measures alone; `-- --breakdown [VIEW]` which samples
//! carry the 256-colour error on them (by kind of surface, by colour, and per surface on the worst
//! views or those whose label holds VIEW, beside each sample's nearest entry).
//!
//! **Measures** ([`mazewalk_render::quality`]: grain, hue error, surfaces apart; OKLab, per sample, no
//! blur) of nine views of three mazes (the built-in maze, the course file
//! `mazes/cs559/maze-10x10-100.maze`, and `--gen 20x15 --seed 3`, each from its viewer and turned 90°
//! and 180°) at 120×40 half blocks, each colour frame against the truecolor frame of the same view.
//! Every depth is rendered with dithering on and off (`RenderOptions::dither`); the default is marked.
//!
//! **Depth**: the same wall face straight ahead at 4 and at 24 maze units (1 and 6 cells of a generated
//! maze or a 4-unit grid tile) down a corridor of the built-in maze's colours: the OKLab lightness of
//! the frame's samples in the middle of the face, near minus far, at every depth.
//!
//! **No colour**: the distinct glyphs of the built-in view in half blocks, and the glyph ascii draws
//! most on its floor and on its ceiling.
//!
//! **Bytes**: the encoder bench's walk (`benches/common`: forward, a full turn, strafe, look up and
//! down, stand still; 60 frames a second through the app's own key handlers) at 120×40, encoded
//! exactly frame after frame; mean bytes per walking frame.

use mazewalk_bench::common;

use std::collections::BTreeMap;

use glam::Vec3;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::quality::{self, Measures};
use mazewalk_render::samples::{CEILING, FLOOR};
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, Renderer, Target};
use mazewalk_term::encoder::Encoder;
use mazewalk_term::frame::{ColorDepth, Frame, Region};
use mazewalk_walk::state::{stand, viewer_camera};

const COLS: usize = 120;
const ROWS: usize = 40;

/// The frames compared with truecolor: a name, the depth, dithering.
const MODES: [(&str, ColorDepth, bool); 4] = [
    ("256, dithered", ColorDepth::Ansi256, true),
    ("256, undithered", ColorDepth::Ansi256, false),
    ("16, dithered", ColorDepth::Ansi16, true),
    ("16, undithered", ColorDepth::Ansi16, false),
];

fn options(charset: Charset, color_depth: ColorDepth, dither: bool) -> RenderOptions {
    RenderOptions { charset, color_depth, culling: Culling::Portal, dither, ..RenderOptions::default() }
}

fn render(renderer: &mut Renderer, maze: &Maze, camera: &Camera, options: &RenderOptions) -> Frame {
    let mut frame = Frame::new(COLS, ROWS);
    let region = Region { col: 0, row: 0, cols: COLS, rows: ROWS };
    renderer.render(maze, camera, &[], options, Target::Frame(&mut frame, region)).expect("camera");
    frame
}

/// The camera of `maze`'s viewer as `mazewalk render` makes it, turned by `turn_deg`.
fn turned(maze: &Maze, turn_deg: f32) -> Camera {
    let viewer = maze.viewer();
    let from_file = viewer_camera(maze);
    let stands = stand(maze, viewer.pos).expect("the viewer stands in the maze");
    Camera { position: stands.pos, yaw_deg: from_file.yaw_deg + turn_deg, ..from_file }
}

/// The nine views: a name, the maze and the camera.
fn views() -> Vec<(String, Maze, Camera)> {
    let course = concat!(env!("CARGO_MANIFEST_DIR"), "/../mazes/cs559/maze-10x10-100.maze");
    let mazes = [
        ("built-in", mazewalk_maze::builtin().expect("built-in maze")),
        ("cs559 10x10", mazewalk_maze::load(course).expect("course file").maze),
        (
            "gen 20x15 seed 3",
            // As `mazewalk --gen 20x15 --seed 3` makes it.
            generate(&GenOptions::walk(20, 15, 3)).expect("generated maze"),
        ),
    ];
    let mut out = Vec::new();
    for (name, maze) in mazes {
        for turn in [0.0, 90.0, 180.0] {
            out.push((format!("{name}, turned {turn}°"), maze.clone(), turned(&maze, turn)));
        }
    }
    out
}

/// The lightness (OKLab L) of the frame's samples in the middle fifth of the picture that show the
/// wall the middle sample shows.
fn middle_lightness(shown: &[Vec3], ids: &[u32], width: usize) -> f32 {
    let height = shown.len() / width;
    let wall = ids[height / 2 * width + width / 2];
    let (mut sum, mut n) = (0.0, 0);
    for y in height * 2 / 5..height * 3 / 5 {
        for x in width * 2 / 5..width * 3 / 5 {
            if ids[y * width + x] == wall {
                sum += shown[y * width + x].x;
                n += 1;
            }
        }
    }
    sum / n.max(1) as f32
}

/// A corridor nine tiles long ending in a wall of `color` (sRGB hex), facing east down it.
fn corridor(color: &str) -> Maze {
    let text = format!(
        "mazewalk-grid 1\ntile 4\nfacing east\nW = {color}\n\n###########\n#@........W\n###########\n"
    );
    mazewalk_maze::parse("corridor", text.as_bytes()).expect("corridor maze")
}

/// The mazes of the held-out views: generated mazes the other measures never see, a course file, the
/// built-in maze.
fn held_out_mazes() -> Vec<(String, Maze)> {
    let mut mazes: Vec<(String, Maze)> = [(12, 8, 101), (20, 15, 202), (30, 20, 303)]
        .into_iter()
        .map(|(width, height, seed)| {
            let opts = GenOptions::walk(width, height, seed);
            (format!("gen {width}x{height} seed {seed}"), generate(&opts).expect("generated maze"))
        })
        .collect();
    let course = concat!(env!("CARGO_MANIFEST_DIR"), "/../mazes/cs559/maze-10x10-100.maze");
    mazes.push(("cs559 10x10".into(), mazewalk_maze::load(course).expect("course file").maze));
    mazes.push(("built-in".into(), mazewalk_maze::builtin().expect("built-in maze")));
    mazes
}

/// The bounds beside the 256-colour frames: each sample of the truecolor frame shown as its nearest
/// entry (16–255) in OKLab, as no mapping of a sample to one entry can beat on the mean or the 95th
/// percentile; and the same among the entries that keep its hue (for a sample of chroma above 0.04,
/// where the hue error counts it: a coloured entry within 30° of its hue).
const NEAREST: &str = "256 bound: nearest entry";
const NEAREST_HUE: &str = "256 bound: nearest entry keeping the hue";

/// [`NEAREST`] and [`NEAREST_HUE`], remembered per colour (a frame has a few thousand).
struct Nearest {
    entries: Vec<Vec3>,
    known: std::collections::HashMap<([u32; 3], bool), Vec3>,
}

impl Nearest {
    fn new() -> Nearest {
        let lab = |rgb: [u8; 3]| {
            let linear = rgb.map(|v| mazewalk_render::shade::srgb_to_linear(f32::from(v) / 255.0));
            Vec3::from_array(mazewalk_term::frame::oklab(linear, f32::cbrt))
        };
        let entries = (16..=255u8).map(|i| lab(mazewalk_render::palette::xterm_rgb(i))).collect();
        Nearest { entries, known: std::collections::HashMap::new() }
    }

    fn of(&mut self, lab: Vec3, keep_hue: bool) -> Vec3 {
        let (chroma, hue) = (lab.y.hypot(lab.z), lab.z.atan2(lab.y));
        let coloured = keep_hue && chroma > 0.04;
        let entries = &self.entries;
        *self.known.entry((lab.to_array().map(f32::to_bits), keep_hue)).or_insert_with(|| {
            entries
                .iter()
                .filter(|e| {
                    let turn = (e.z.atan2(e.y) - hue).abs() % std::f32::consts::TAU;
                    !coloured
                        || (e.y.hypot(e.z) >= quality::GREY
                            && turn.min(std::f32::consts::TAU - turn) <= 30f32.to_radians())
                })
                .copied()
                .min_by(|a, b| a.distance(lab).total_cmp(&b.distance(lab)))
                .unwrap_or(lab)
        })
    }
}

/// Issue #39's measures over held-out views ([`quality::held_out_views`]: in cells, nose to a wall,
/// down corridors), as the walk shows them (foveated), every depth against truecolor: the median
/// view and the worst.
fn held_out(renderer: &mut Renderer) {
    const PER_MAZE: usize = 30;
    let mut rows: BTreeMap<&str, Vec<Measures>> = BTreeMap::new();
    // Per mode and measure: the worst view's figure and its label (the least for the chroma ratio's
    // low end, the most for the rest).
    let mut worst: BTreeMap<(&str, &str), (f64, String)> = BTreeMap::new();
    let mut merged: BTreeMap<&str, usize> = BTreeMap::new();
    let mut nearest = Nearest::new();
    for (name, maze) in held_out_mazes() {
        for (k, (kind, camera)) in quality::held_out_views(&maze, 39, PER_MAZE).into_iter().enumerate() {
            let camera = Camera { fovea: true, ..camera }; // the walk's view
            let truth_frame =
                render(renderer, &maze, &camera, &options(Charset::Half, ColorDepth::TrueColor, false));
            let truth = quality::shown(&truth_frame, Charset::Half);
            let ids = renderer.samples().id().to_vec();
            let width = renderer.samples().width();
            let apart = quality::measure(&truth, &truth, &ids, width).surfaces_apart;
            let mut shown: Vec<(&str, Vec<Vec3>)> = MODES
                .into_iter()
                .filter(|m| !m.2)
                .map(|(mode, depth, dither)| {
                    let frame = render(renderer, &maze, &camera, &options(Charset::Half, depth, dither));
                    (mode, quality::shown(&frame, Charset::Half))
                })
                .collect();
            shown.push((NEAREST, truth.iter().map(|&t| nearest.of(t, false)).collect()));
            shown.push((NEAREST_HUE, truth.iter().map(|&t| nearest.of(t, true)).collect()));
            for (mode, shown) in shown {
                let m = quality::measure(&shown, &truth, &ids, width);
                let label = format!(
                    "{name} #{k} {kind:?} at ({:.2}, {:.2}) heading {:.0}°",
                    camera.position.x, camera.position.y, camera.yaw_deg
                );
                for (measure, value) in [
                    ("mean error", m.mean_error),
                    ("p95 error", m.p95_error),
                    ("hue error °", m.hue_error_deg),
                    ("grain", m.grain),
                    ("chroma ratio, most", m.chroma_ratio),
                    ("chroma ratio, least", -m.chroma_ratio),
                ] {
                    let entry = worst.entry((mode, measure)).or_insert((f64::NEG_INFINITY, String::new()));
                    if value > entry.0 {
                        *entry = (value, label.clone());
                    }
                }
                // Issue #33: the largest surfaces at least 0.8× as far apart as in truecolor.
                let merged = merged.entry(mode).or_insert(0);
                *merged += usize::from(m.surfaces_apart < 0.8 * apart);
                rows.entry(mode).or_default().push(m);
            }
        }
    }
    println!(
        "\nHeld-out views (issue #39): {PER_MAZE} views of each of {} mazes, half blocks {COLS}×{ROWS}, median view / worst view:\n",
        held_out_mazes().len()
    );
    println!("| frame | mean OKLab error | p95 error | chroma ratio | hue error ° | grain % |");
    println!("|---|--:|--:|--:|--:|--:|");
    for (mode, m) in &rows {
        let stat = |f: &dyn Fn(&Measures) -> f64| {
            let mut v: Vec<f64> = m.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            (v[v.len() / 2], v[0], v[v.len() - 1])
        };
        let (e, _, e1) = stat(&|m| m.mean_error);
        let (p, _, p1) = stat(&|m| m.p95_error);
        let (c, c0, c1) = stat(&|m| m.chroma_ratio);
        let (h, _, h1) = stat(&|m| m.hue_error_deg);
        let (g, _, g1) = stat(&|m| 100.0 * m.grain);
        println!(
            "| {mode} | {e:.3} / {e1:.3} | {p:.3} / {p1:.3} | {c:.2} ({c0:.2}–{c1:.2}) | {h:.1} / {h1:.1} | {g:.2} / {g1:.2} |"
        );
    }
    for (mode, n) in merged {
        let views = rows[mode].len();
        println!(
            "- in {mode}: {n} of {views} views with surfaces less than 0.8× as far apart as in truecolor"
        );
    }
    for ((mode, measure), (value, label)) in worst {
        println!("- worst {measure} in {mode}: {label} ({:.3})", value.abs());
    }
}

fn main() {
    let mut renderer = Renderer::new();
    let args: Vec<String> = std::env::args().collect();
    if let Some(at) = args.iter().position(|a| a == "--breakdown") {
        breakdown(&mut renderer, args.get(at + 1).map(String::as_str));
        return;
    }
    held_out(&mut renderer);
    if std::env::args().any(|a| a == "--held-out") {
        return;
    }
    let views = views();
    // Per mode: the measures of every view.
    let mut all: BTreeMap<&str, Vec<Measures>> = BTreeMap::new();
    println!(
        "Measures against the truecolor frame, half blocks {COLS}×{ROWS} (grain % / hue error ° / surfaces apart ×100):\n"
    );
    print!("| view | truecolor, surfaces apart |");
    for (name, ..) in MODES {
        print!(" {name} |");
    }
    println!("\n|---|--:|{}", "--:|".repeat(MODES.len()));
    let default_dither = RenderOptions::default().dither;
    for (name, maze, camera) in &views {
        let truth_frame =
            render(&mut renderer, maze, camera, &options(Charset::Half, ColorDepth::TrueColor, true));
        let truth = quality::shown(&truth_frame, Charset::Half);
        let ids = renderer.samples().id().to_vec();
        let width = renderer.samples().width();
        let t = quality::measure(&truth, &truth, &ids, width);
        all.entry("truecolor").or_default().push(t);
        print!("| {name} | {:.1} |", t.surfaces_apart);
        for (mode, depth, dither) in MODES {
            let frame = render(&mut renderer, maze, camera, &options(Charset::Half, depth, dither));
            let shown = quality::shown(&frame, Charset::Half);
            let m = quality::measure(&shown, &truth, &ids, width);
            all.entry(mode).or_default().push(m);
            print!(" {:.2} / {:.1} / {:.1} |", 100.0 * m.grain, m.hue_error_deg, m.surfaces_apart);
        }
        println!();
    }
    println!(
        "\nOver the {} views (min–max; surfaces apart also as a share of truecolor's, least):\n",
        views.len()
    );
    println!("| frame | default | grain % | hue error ° | surfaces apart | ÷ truecolor's |");
    println!("|---|---|--:|--:|--:|--:|");
    let truecolor = all["truecolor"].clone();
    let range = |v: &[f64]| {
        let (lo, hi) =
            v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| (lo.min(x), hi.max(x)));
        (lo, hi)
    };
    for (mode, depth, dither) in
        std::iter::once(("truecolor", ColorDepth::TrueColor, default_dither)).chain(MODES)
    {
        let m = &all[mode];
        let (g0, g1) = range(&m.iter().map(|m| 100.0 * m.grain).collect::<Vec<_>>());
        let (h0, h1) = range(&m.iter().map(|m| m.hue_error_deg).collect::<Vec<_>>());
        let (s0, s1) = range(&m.iter().map(|m| m.surfaces_apart).collect::<Vec<_>>());
        let ratio = m
            .iter()
            .zip(&truecolor)
            .map(|(m, t)| m.surfaces_apart / t.surfaces_apart)
            .fold(f64::INFINITY, f64::min);
        let default = if depth == ColorDepth::TrueColor || dither == default_dither { "yes" } else { "" };
        println!("| {mode} | {default} | {g0:.1}–{g1:.1} | {h0:.0}–{h1:.0} | {s0:.1}–{s1:.1} | {ratio:.2} |");
    }

    println!("\nDepth: OKLab lightness of the middle of a wall face at 4 and 24 units, near − far:\n");
    println!("| wall | truecolor | 256 | 16 |");
    println!("|---|--:|--:|--:|");
    for (name, color) in [
        ("#4477aa (blue)", "#4477aa"),
        ("#808080 (grey)", "#808080"),
        ("#cc8844 (orange)", "#cc8844"),
        ("#66aa55 (green)", "#66aa55"),
    ] {
        let maze = corridor(color);
        let camera = turned(&maze, 0.0);
        print!("| {name} |");
        for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16] {
            let at = |x: f32, renderer: &mut Renderer| {
                let camera = Camera { position: glam::Vec2::new(x, camera.position.y), ..camera };
                let frame = render(renderer, &maze, &camera, &options(Charset::Half, depth, default_dither));
                let ids = renderer.samples().id().to_vec();
                middle_lightness(&quality::shown(&frame, Charset::Half), &ids, renderer.samples().width())
            };
            // The wall's face is at x = 40 (ten 4-unit tiles from the west edge).
            let (near, far) = (at(36.0, &mut renderer), at(16.0, &mut renderer));
            print!(" {near:.2} − {far:.2} = **{:.2}** |", near - far);
        }
        println!();
    }

    println!("\nNo colour, the built-in view:\n");
    let (_, builtin, camera) = &views[0];
    let half = render(&mut renderer, builtin, camera, &options(Charset::Half, ColorDepth::None, false));
    let mut glyphs: BTreeMap<char, usize> = BTreeMap::new();
    for cell in half.cells() {
        *glyphs.entry(cell.ch).or_default() += 1;
    }
    let listed: Vec<String> = glyphs.iter().map(|(g, n)| format!("`{g}` {n}")).collect();
    println!("- half blocks: {} distinct glyphs ({})", glyphs.len(), listed.join(", "));
    let ascii = render(&mut renderer, builtin, camera, &options(Charset::Ascii, ColorDepth::None, false));
    let ids = renderer.samples().id();
    let most = |surface: u32| {
        let mut counts: BTreeMap<char, usize> = BTreeMap::new();
        for (cell, &id) in ascii.cells().iter().zip(ids) {
            if id == surface {
                *counts.entry(cell.ch).or_default() += 1;
            }
        }
        counts.into_iter().max_by_key(|&(_, n)| n).map_or(' ', |(g, _)| g)
    };
    println!("- ascii: floor mostly `{}`, ceiling mostly `{}`", most(FLOOR), most(CEILING));

    let (walk_maze, cameras) = {
        let mut app = common::walk_app(100, Charset::Half, ColorDepth::Ansi256);
        let mut cameras = Vec::new();
        common::play_walk(&mut app, &common::walk_script(), |app, _, moved| {
            cameras.push((moved, app.camera))
        });
        (app.maze().clone(), cameras)
    };
    println!(
        "\nBytes per walking frame, {COLS}×{ROWS} half blocks, the encoder walk ({} frames, exact encoder):\n",
        cameras.len()
    );
    println!("| frame | walking mean | walking median |");
    println!("|---|--:|--:|");
    for (mode, depth, dither) in MODES {
        let mut encoder = Encoder::new();
        let mut out = Vec::new();
        let mut walking = Vec::new();
        for (k, &(moved, camera)) in cameras.iter().enumerate() {
            let frame = render(&mut renderer, &walk_maze, &camera, &options(Charset::Half, depth, dither));
            out.clear();
            let bytes = encoder.encode(&frame, &mut out).bytes;
            if moved && k > 0 {
                walking.push(bytes);
            }
        }
        walking.sort_unstable();
        let mean = walking.iter().sum::<usize>() as f64 / walking.len().max(1) as f64;
        println!("| {mode} | {mean:.0} | {} |", walking.get(walking.len() / 2).copied().unwrap_or(0));
    }
}

/// The sRGB of every colour a frame's cells use, by its OKLab (as [`quality::shown`] gives it).
fn rgb_of(frame: &Frame) -> std::collections::HashMap<[u32; 3], [u8; 3]> {
    use mazewalk_term::frame::Color;
    let mut out = std::collections::HashMap::new();
    for cell in frame.cells() {
        for color in [cell.fg, cell.bg] {
            let rgb = match color {
                Color::Rgb(r, g, b) => [r, g, b],
                Color::Indexed(i) => mazewalk_render::palette::xterm_rgb(i),
                Color::Default => continue,
            };
            out.insert(quality::oklab_srgb8(rgb).to_array().map(f32::to_bits), rgb);
        }
    }
    out
}

/// A colour of the truecolor frame (sRGB), the entry shown for it and the kind of surface.
type Costly = ([u8; 3], u8, &'static str);
/// Over one surface's samples that show one entry: how many, their truecolor sRGB summed, their
/// error summed, the nearest entry's error summed, and how often each entry is the nearest.
type Group = (usize, [f64; 3], f64, f64, BTreeMap<u8, usize>);

/// `--breakdown [VIEW]`: the held-out views with the largest mean error in 256 colours; over all of
/// them, the error by kind of surface (walls in the exit's light, other walls, floor, ceiling) against
/// the nearest entry's, and the colours whose entries cost most beyond the nearest; and for the worst
/// few views (or those whose label holds VIEW), which samples carry it: per surface and entry shown,
/// the truecolor colour (mean sRGB), the entry, the nearest entry (the commonest over the group) and
/// the error.
fn breakdown(renderer: &mut Renderer, only: Option<&str>) {
    use mazewalk_maze::light::ExitLight;
    let entries: Vec<(u8, Vec3)> =
        (16..=255u8).map(|i| (i, quality::oklab_srgb8(mazewalk_render::palette::xterm_rgb(i)))).collect();
    let nearest = |lab: Vec3| {
        entries.iter().min_by(|a, b| a.1.distance(lab).total_cmp(&b.1.distance(lab))).map_or(0, |e| e.0)
    };
    let mut index_of: std::collections::HashMap<[u8; 3], u8> = std::collections::HashMap::new();
    for (i, rgb) in (16..=255u8).map(|i| (i, mazewalk_render::palette::xterm_rgb(i))).rev() {
        index_of.insert(rgb, i);
    }
    let key = |lab: &Vec3| lab.to_array().map(f32::to_bits);
    // Per kind: samples, error shown, error of the nearest entry.
    let mut kinds: BTreeMap<&str, (usize, f64, f64)> = BTreeMap::new();
    // Per (truecolor sRGB, entry shown, kind): samples, excess error over the nearest entry, nearest.
    let mut costly: std::collections::HashMap<Costly, (usize, f64, u8)> = std::collections::HashMap::new();
    let mut views = Vec::new();
    for (name, maze) in held_out_mazes() {
        let light = ExitLight::of(&maze);
        let walls = maze.edges().len() as u32;
        let lit = |e: u32| {
            let edge = maze.edge(e);
            [edge.left, edge.right].iter().flatten().any(|&c| light.level(c) > 0)
        };
        for (k, (kind, camera)) in quality::held_out_views(&maze, 39, 30).into_iter().enumerate() {
            let camera = Camera { fovea: true, ..camera }; // as `held_out` measures them
            let truth_frame =
                render(renderer, &maze, &camera, &options(Charset::Half, ColorDepth::TrueColor, false));
            let truth = quality::shown(&truth_frame, Charset::Half);
            let ids = renderer.samples().id().to_vec();
            let width = renderer.samples().width();
            let frame = render(renderer, &maze, &camera, &options(Charset::Half, ColorDepth::Ansi256, false));
            let shown = quality::shown(&frame, Charset::Half);
            let m = quality::measure(&shown, &truth, &ids, width);
            let label = format!(
                "{name} #{k} {kind:?} at ({:.2}, {:.2}) heading {:.0}°",
                camera.position.x, camera.position.y, camera.yaw_deg
            );
            let (truth_rgb, shown_rgb) = (rgb_of(&truth_frame), rgb_of(&frame));
            // Per (surface, kind, entry shown): samples, summed truecolor sRGB, summed error, nearest's.
            let mut groups: BTreeMap<(u32, &str, u8), Group> = BTreeMap::new();
            for ((t, s), &id) in truth.iter().zip(&shown).zip(&ids) {
                let entry = shown_rgb.get(&key(s)).and_then(|rgb| index_of.get(rgb)).copied().unwrap_or(0);
                let rgb = truth_rgb.get(&key(t)).copied().unwrap_or([0; 3]);
                let surface = match id {
                    FLOOR => "floor",
                    CEILING => "ceiling",
                    id if id < walls && lit(id) => "lit wall",
                    id if id < walls => "wall",
                    _ => "other",
                };
                let near = nearest(*t);
                let (err, near_err) =
                    (f64::from(t.distance(*s)), f64::from(t.distance(entries[usize::from(near - 16)].1)));
                let kind = kinds.entry(surface).or_default();
                kind.0 += 1;
                kind.1 += err;
                kind.2 += near_err;
                let c = costly.entry((rgb, entry, surface)).or_insert((0, 0.0, near));
                c.0 += 1;
                c.1 += err - near_err;
                let g = groups.entry((id, surface, entry)).or_default();
                g.0 += 1;
                for (sum, v) in g.1.iter_mut().zip(rgb) {
                    *sum += f64::from(v);
                }
                g.2 += err;
                g.3 += near_err;
                *g.4.entry(near).or_default() += 1;
            }
            views.push((m.mean_error, m.p95_error, label, groups));
        }
    }
    views.sort_by(|a, b| b.0.total_cmp(&a.0));
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "\n256 colours, median view: mean error {:.4}, p95 {:.4}",
        median(&mut views.iter().map(|v| v.0).collect()),
        median(&mut views.iter().map(|v| v.1).collect())
    );
    println!("\nThe held-out views of largest mean error in 256 colours (mean / p95):\n");
    for v in views.iter().take(12) {
        println!("- {:.3} / {:.3} {}", v.0, v.1, v.2);
    }
    println!(
        "\nOver every held-out view, per kind of surface: samples, mean error shown / of the nearest entry:\n"
    );
    for (kind, (n, err, near)) in &kinds {
        println!("- {kind}: {n}, {:.4} / {:.4}", err / *n as f64, near / *n as f64);
    }
    println!("\nThe colours costing most beyond their nearest entry (summed over every view):\n");
    let mut costly: Vec<_> = costly.into_iter().collect();
    costly.sort_by(|a, b| b.1.1.total_cmp(&a.1.1));
    for ((rgb, entry, kind), (n, excess, near)) in costly.into_iter().take(25) {
        println!(
            "- {kind} {rgb:?} as {entry} {:?} (nearest {near} {:?}): {n} samples, excess {:.1}",
            mazewalk_render::palette::xterm_rgb(entry),
            mazewalk_render::palette::xterm_rgb(near),
            excess
        );
    }
    let chosen: Vec<_> = match only {
        Some(only) => views.iter().filter(|v| v.2.contains(only)).collect(),
        None => views.iter().take(3).collect(),
    };
    for (mean, p95, label, groups) in chosen {
        let total: f64 = groups.values().map(|g| g.2).sum();
        println!("\n{label}: mean {mean:.3}, p95 {p95:.3}; per surface and entry, by share of the error:\n");
        println!(
            "| surface | samples | truecolor (mean sRGB) | entry shown | its error | nearest entry (commonest) | nearest's error | share of the view's error |"
        );
        println!("|---|--:|---|---|--:|---|--:|--:|");
        let mut rows: Vec<_> = groups.iter().collect();
        rows.sort_by(|a, b| b.1.2.total_cmp(&a.1.2));
        for ((id, kind, entry), (n, sum, err, near_err, nears)) in rows.into_iter().take(10) {
            let surface = if *id < FLOOR - 1 { format!("{kind} #{id}") } else { kind.to_string() };
            let mean_rgb = sum.map(|v| (v / *n as f64).round() as u8);
            let near = nears.iter().max_by_key(|&(_, c)| c).map_or(0, |(&e, _)| e);
            println!(
                "| {surface} | {n} | {mean_rgb:?} | {entry} {:?} | {:.3} | {near} {:?} | {:.3} | {:.0} % |",
                mazewalk_render::palette::xterm_rgb(*entry),
                err / *n as f64,
                mazewalk_render::palette::xterm_rgb(near),
                near_err / *n as f64,
                100.0 * err / total
            );
        }
    }
}
