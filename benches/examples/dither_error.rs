//! Issue #14: how far 256- and 16-colour frames are from the truecolor frame, and what they cost on the
//! wire, with the renderer's quantization beside plain nearest-colour quantization in the same run.
//!
//! ```sh
//! nice cargo run --release --example dither_error [out-dir]   # default out-dir: target/dither-images
//! ```
//!
//! **Error.** Fixed views (the built-in maze from its start and turned, generated 40×25 mazes from
//! theirs) rendered in half blocks at 160×48 cells. Each frame's cells are turned back into what the
//! terminal shows per sample (`▀`: ink on the top sample, background on the bottom; shade glyphs `░▒▓`
//! as their ink coverage mixed in linear light; indexed colours through xterm's defaults,
//! [`xterm_rgb`]). Both that and the truecolor frame are box-blurred over every 2×2 window of samples
//! in linear light (what the eye does to a fine pattern), and the error is the mean OKLab ΔE (Euclidean,
//! L in 0..100) over the windows. The OKLab conversion is written out here, independently of the
//! renderer's. "sample" is the same without the blur.
//!
//! **Bytes.** The encoder's walk (`benches/encoder.rs`: forward, a full turn, strafe, look up and down,
//! stand still; 60 frames a second through the app's own key handlers) at 160×48, encoded exactly
//! (tolerance 0) frame after frame; mean bytes per walking frame.
//!
//! "plain" is every sample quantized on its own to the nearest colour in sRGB
//! ([`palette::quantize`]), cells built from those as half blocks do; "renderer" is `to_frame`.
//!
//! Writes `<out-dir>/<view>.png` (or `.ppm` without ImageMagick): truecolor, 256 plain, 256 renderer,
//! 16 plain, 16 renderer side by side, each sample a 4×4 block of pixels.

#[path = "../common/mod.rs"]
mod common;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{Algorithm, GenOptions, generate};
use mazewalk_render::palette::{self, xterm_rgb};
use mazewalk_render::shade::srgb_to_linear;
use mazewalk_render::{Camera, Charset, Culling, RenderOptions, Renderer, Target};
use mazewalk_term::encoder::Encoder;
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame, Region};
use mazewalk_walk::App;

const COLS: usize = 160;
const ROWS: usize = 48;
/// Pixels per sample side in the images.
const SCALE: usize = 4;

/// How a frame was quantized.
#[derive(Clone, Copy, PartialEq)]
enum Method {
    /// `to_frame` at the depth.
    Renderer,
    /// Each sample to its nearest colour alone (sRGB distance), as half blocks.
    Plain,
}

fn options(depth: ColorDepth) -> RenderOptions {
    RenderOptions {
        charset: Charset::Half,
        color_depth: depth,
        culling: Culling::Portal,
        ..RenderOptions::default()
    }
}

/// The frame of `camera` in `maze` at `depth` by `method`.
fn frame_of(
    renderer: &mut Renderer,
    maze: &Maze,
    camera: &Camera,
    depth: ColorDepth,
    method: Method,
) -> Frame {
    let mut frame = Frame::new(COLS, ROWS);
    let region = Region { col: 0, row: 0, cols: COLS, rows: ROWS };
    renderer.render(maze, camera, &[], &options(depth), Target::Frame(&mut frame, region)).expect("camera");
    if method == Method::Plain {
        let samples = renderer.samples();
        let w = samples.width();
        for row in 0..ROWS {
            for col in 0..COLS {
                let q = |y: usize| palette::quantize(samples.color()[y * w + col], depth);
                let (top, bottom) = (q(2 * row), q(2 * row + 1));
                let cell = if top == bottom {
                    Cell { ch: ' ', fg: bottom, bg: bottom }
                } else {
                    Cell { ch: '▀', fg: top, bg: bottom }
                };
                frame.set(col, row, cell);
            }
        }
    }
    frame
}

/// Bytes of `out` in colour codes (`ESC [ … m`), other escape sequences (cursor moves, sync) and text.
fn byte_kinds(out: &[u8]) -> [usize; 3] {
    let (mut kinds, mut i) = ([0; 3], 0);
    while i < out.len() {
        if out[i] == 0x1b {
            // ESC [ parameters … final byte (0x40–0x7e).
            let end = (i + 2..out.len()).find(|&j| (0x40..=0x7e).contains(&out[j])).unwrap_or(out.len() - 1);
            kinds[usize::from(out[end] != b'm')] += end + 1 - i;
            i = end + 1;
        } else {
            kinds[2] += 1;
            i += 1;
        }
    }
    kinds
}

fn linear_of(color: Color) -> Vec3 {
    let rgb = match color {
        Color::Rgb(r, g, b) => [r, g, b],
        Color::Indexed(i) => xterm_rgb(i),
        Color::Default => [0, 0, 0],
    };
    Vec3::from_array(rgb.map(|v| srgb_to_linear(f32::from(v) / 255.0)))
}

/// What the terminal shows on each sample of a half-block frame (linear RGB, row-major).
fn shown(frame: &Frame) -> Vec<Vec3> {
    let mut out = vec![Vec3::ZERO; COLS * ROWS * 2];
    for row in 0..ROWS {
        for col in 0..COLS {
            let cell = frame.get(col, row).expect("in the frame");
            let (fg, bg) = (linear_of(cell.fg), linear_of(cell.bg));
            let (top, bottom) = match cell.ch {
                '▀' => (fg, bg),
                '▄' => (bg, fg),
                '█' => (fg, fg),
                '░' => (bg.lerp(fg, 0.25), bg.lerp(fg, 0.25)),
                '▒' => (bg.lerp(fg, 0.5), bg.lerp(fg, 0.5)),
                '▓' => (bg.lerp(fg, 0.75), bg.lerp(fg, 0.75)),
                ' ' => (bg, bg),
                other => panic!("glyph {other:?} in a half-block frame"),
            };
            out[2 * row * COLS + col] = top;
            out[(2 * row + 1) * COLS + col] = bottom;
        }
    }
    out
}

/// OKLab of a linear sRGB colour (Björn Ottosson, <https://bottosson.github.io/posts/oklab/>), ×100.
fn oklab(c: Vec3) -> Vec3 {
    let l = 0.412_221_46 * c.x + 0.536_332_55 * c.y + 0.051_445_995 * c.z;
    let m = 0.211_903_5 * c.x + 0.680_699_5 * c.y + 0.107_396_96 * c.z;
    let s = 0.088_302_46 * c.x + 0.281_718_85 * c.y + 0.629_978_7 * c.z;
    let (l, m, s) = (l.max(0.0).cbrt(), m.max(0.0).cbrt(), s.max(0.0).cbrt());
    100.0
        * Vec3::new(
            0.210_454_26 * l + 0.793_617_8 * m - 0.004_072_047 * s,
            1.977_998_5 * l - 2.428_592_2 * m + 0.450_593_7 * s,
            0.025_904_037 * l + 0.782_771_77 * m - 0.808_675_77 * s,
        )
}

/// Every 2×2 window's mean (linear light), `(w-1) × (h-1)` of them.
fn blur2(c: &[Vec3], w: usize, h: usize) -> Vec<Vec3> {
    let mut out = Vec::with_capacity((w - 1) * (h - 1));
    for y in 0..h - 1 {
        for x in 0..w - 1 {
            let i = y * w + x;
            out.push((c[i] + c[i + 1] + c[i + w] + c[i + w + 1]) * 0.25);
        }
    }
    out
}

fn mean_delta_e(a: &[Vec3], b: &[Vec3]) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(&x, &y)| f64::from(oklab(x).distance(oklab(y)))).sum();
    sum / a.len() as f64
}

/// (blurred, per sample) error of `frame` against `truth`.
fn errors(truth: &[Vec3], frame: &Frame) -> (f64, f64) {
    let s = shown(frame);
    let (w, h) = (COLS, 2 * ROWS);
    (mean_delta_e(&blur2(truth, w, h), &blur2(&s, w, h)), mean_delta_e(truth, &s))
}

fn write_image(dir: &Path, name: &str, panels: &[Vec<Vec3>]) -> PathBuf {
    let (w, h) = (COLS * SCALE, 2 * ROWS * SCALE);
    let gap = 8;
    let width = panels.len() * (w + gap) - gap;
    let mut ppm = format!("P6\n{width} {h}\n255\n").into_bytes();
    for y in 0..h {
        for (k, panel) in panels.iter().enumerate() {
            for x in 0..w {
                let c = panel[(y / SCALE) * COLS + x / SCALE];
                ppm.extend(palette::to_srgb8(c));
            }
            if k + 1 < panels.len() {
                ppm.extend(std::iter::repeat_n(255u8, 3 * gap));
            }
        }
    }
    let path = dir.join(format!("{name}.ppm"));
    std::fs::write(&path, ppm).expect("write the image");
    let png = dir.join(format!("{name}.png"));
    let converted = std::process::Command::new("convert").arg(&path).arg(&png).status();
    if converted.is_ok_and(|s| s.success()) {
        let _ = std::fs::remove_file(&path);
        png
    } else {
        path
    }
}

/// The fixed views: a name, the maze and the camera.
fn views() -> Vec<(String, Maze, Camera)> {
    let mut out = Vec::new();
    let builtin = mazewalk_maze::builtin().expect("built-in maze");
    let v = *builtin.viewer();
    for (k, turn) in [0.0, -90.0, 180.0].into_iter().enumerate() {
        let camera = Camera::new(v.pos, v.dir_deg + turn, v.fov_deg);
        out.push((format!("builtin-{k}"), builtin.clone(), camera));
    }
    for (seed, algorithm) in [(1, Algorithm::Backtracker), (2, Algorithm::Prim), (3, Algorithm::Wilson)] {
        let maze = generate(&GenOptions { width: 40, height: 25, seed, algorithm, ..GenOptions::default() })
            .expect("generated maze");
        let v = *maze.viewer();
        let camera = Camera::new(v.pos, v.dir_deg, v.fov_deg);
        out.push((format!("gen40x25-seed{seed}"), maze, camera));
    }
    // Looking down a little from the open-area benchmark view: much floor, far walls.
    let scene = common::scene(common::View::Open, 100);
    let camera = Camera { pitch_deg: -20.0, ..scene.camera };
    out.push(("open-100-down".into(), scene.maze, camera));
    out
}

/// The encoder bench's walk: every frame's camera.
fn walk_cameras() -> (Maze, Vec<(bool, Camera)>) {
    let scene = common::scene(common::View::Open, 100);
    let mut app = App::new(scene.maze.clone(), options(ColorDepth::TrueColor), 0.0).expect("viewer");
    app.camera = scene.camera;
    app.cell = app.maze().cell_at(scene.camera.position).expect("camera in the maze");
    app.releases = true;
    let mut cameras = Vec::new();
    common::play_walk(&mut app, &common::walk_script(), |app, _, moved| cameras.push((moved, app.camera)));
    (scene.maze, cameras)
}

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "target/dither-images".into()));
    std::fs::create_dir_all(&dir).expect("output directory");
    let mut renderer = Renderer::new();
    let runs = [
        ("256 plain", ColorDepth::Ansi256, Method::Plain),
        ("256 renderer", ColorDepth::Ansi256, Method::Renderer),
        ("16 plain", ColorDepth::Ansi16, Method::Plain),
        ("16 renderer", ColorDepth::Ansi16, Method::Renderer),
    ];
    let mut md = String::from("| view | ");
    for (name, ..) in runs {
        let _ = write!(md, "{name}, 2×2 / sample | ");
    }
    md.push_str("\n|---|");
    md.push_str(&"--:|".repeat(runs.len()));
    md.push('\n');
    let mut totals = [(0.0, 0.0); 4];
    let mut images = Vec::new();
    let views = views();
    // The pair search is memoized per colour bucket: the first frame pays for its buckets (issue #16).
    for depth in [ColorDepth::Ansi256, ColorDepth::Ansi16] {
        let (_, maze, camera) = &views[0];
        let ms = |renderer: &mut Renderer| {
            let start = std::time::Instant::now();
            let _ = frame_of(renderer, maze, camera, depth, Method::Renderer);
            start.elapsed().as_secs_f64() * 1e3
        };
        let (first, again) = (ms(&mut renderer), ms(&mut renderer));
        println!("{depth:?}: first frame {first:.2} ms, the same frame again {again:.2} ms");
    }
    for (name, maze, camera) in &views {
        let truth_frame = frame_of(&mut renderer, maze, camera, ColorDepth::TrueColor, Method::Renderer);
        let truth = shown(&truth_frame);
        let _ = write!(md, "| {name} | ");
        let mut panels = vec![truth.clone()];
        for (k, &(_, depth, method)) in runs.iter().enumerate() {
            let frame = frame_of(&mut renderer, maze, camera, depth, method);
            let (blurred, sample) = errors(&truth, &frame);
            totals[k].0 += blurred;
            totals[k].1 += sample;
            let _ = write!(md, "{blurred:.2} / {sample:.2} | ");
            panels.push(shown(&frame));
        }
        md.push('\n');
        images.push(write_image(&dir, name, &panels));
    }
    let n = views.len() as f64;
    md.push_str("| **mean** | ");
    for (b, s) in totals {
        let _ = write!(md, "**{:.2}** / {:.2} | ", b / n, s / n);
    }
    md.push('\n');
    println!(
        "Mean OKLab ΔE (×100) against truecolor, 2×2 box blur / per sample, half blocks {COLS}×{ROWS}:\n"
    );
    println!("{md}");

    let (maze, cameras) = walk_cameras();
    println!("Bytes per frame over the encoder walk ({} frames, exact encoder):\n", cameras.len());
    println!(
        "| depth, method | walking mean | walking median | cells changed, walking mean | colour / cursor / text bytes, walking mean | idle mean | first frame |"
    );
    println!("|---|--:|--:|--:|--:|--:|--:|");
    for (name, depth, method) in runs {
        let mut encoder = Encoder::new();
        let mut out = Vec::new();
        let (mut walking, mut idle, mut first) = (Vec::new(), Vec::new(), 0);
        let mut cells = Vec::new();
        let mut breakdown = [0usize; 3];
        for (k, &(moved, camera)) in cameras.iter().enumerate() {
            let frame = frame_of(&mut renderer, &maze, &camera, depth, method);
            out.clear();
            let stats = encoder.encode(&frame, &mut out);
            let bytes = stats.bytes;
            if moved && k > 0 {
                let [sgr, cursor, text] = byte_kinds(&out);
                breakdown = [breakdown[0] + sgr, breakdown[1] + cursor, breakdown[2] + text];
            }
            match (k, moved) {
                (0, _) => first = bytes,
                (_, true) => {
                    walking.push(bytes);
                    cells.push(stats.cells_changed);
                }
                (_, false) => idle.push(bytes),
            }
        }
        let mean = |v: &[usize]| v.iter().sum::<usize>() as f64 / v.len().max(1) as f64;
        let mut sorted = walking.clone();
        sorted.sort_unstable();
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0);
        let n = walking.len().max(1) as f64;
        println!(
            "| {name} | {:.0} | {median} | {:.0} | {:.0} / {:.0} / {:.0} | {:.0} | {first} |",
            mean(&walking),
            mean(&cells),
            breakdown[0] as f64 / n,
            breakdown[1] as f64 / n,
            breakdown[2] as f64 / n,
            mean(&idle)
        );
    }
    println!("\nImages (truecolor | 256 plain | 256 renderer | 16 plain | 16 renderer):");
    for path in images {
        println!("- {}", path.display());
    }
}
