//! A digest of many renders, one line each, to tell that a change to the renderer keeps every frame
//! byte for byte (run it before and after, then `diff` the two outputs):
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example frame_digest > after.txt
//! ```
//!
//! Views: held-out views (`quality::held_out_views`) and views from cells in the exit's light of the
//! built-in maze and of generated mazes (in and out of the glow), level and pitched, at 120 × 40 and
//! 77 × 23, every charset and colour depth, the textures' filter on and off. Each line: the view, and
//! hashes of the samples (colour bits, depths, ids) and of the frame's cells.
//!
//! With `fovea`: the same views foveated, as the walk draws them (`Camera::fovea`).
//!
//! With `ramps`: instead, the 256- and 16-colour entries (`palette::ramp_entry`) of every
//! chromaticity slot's light ramp at 48 intensities, a line per palette and red step.

use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

use glam::Vec3;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::{Maze, builtin};
use mazewalk_render::palette::{Palette, ramp_entry};
use mazewalk_render::quality::held_out_views;
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, Target};
use mazewalk_term::frame::{ColorDepth, Frame};

fn main() {
    if std::env::args().nth(1).as_deref() == Some("ramps") {
        ramps();
        return;
    }
    let mazes: Vec<(&str, Maze)> = vec![
        ("builtin", builtin().expect("built-in maze")),
        ("walk-20x15-71", generate(&GenOptions::walk(20, 15, 71)).expect("maze")),
        ("walk-30x20-5", generate(&GenOptions::walk(30, 20, 5)).expect("maze")),
        (
            "loops-9x7-5",
            generate(&GenOptions {
                width: 9,
                height: 7,
                seed: 5,
                loops: 0.3,
                exit: true,
                ..GenOptions::default()
            })
            .expect("maze"),
        ),
        (
            "plain-12x12-3",
            generate(&GenOptions { width: 12, height: 12, seed: 3, ..GenOptions::default() }).expect("maze"),
        ),
    ];
    let fovea = std::env::args().nth(1).as_deref() == Some("fovea");
    let (mut renderer, mut frames) = (Renderer::new(), 0);
    for (m, (name, maze)) in mazes.iter().enumerate() {
        let light = maze.exit_light();
        let lit: Vec<u32> = (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0).collect();
        let mut cameras: Vec<Camera> =
            held_out_views(maze, 900 + m as u64, 8).into_iter().map(|(_, camera)| camera).collect();
        let v = maze.viewer();
        for &cell in lit.iter().step_by(lit.len().div_ceil(6).max(1)) {
            for heading in [15.0, 100.0, 190.0, 280.0] {
                cameras.push(Camera {
                    eye_z: v.z,
                    min_vfov_deg: maze.min_vfov_deg(),
                    ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
                });
            }
        }
        for (k, camera) in cameras.iter().enumerate() {
            for pitch_deg in [0.0, -12.0] {
                let camera = Camera { pitch_deg, fovea, ..*camera };
                for (c, charset) in Charset::ALL.into_iter().enumerate() {
                    let (cols, rows) = if (k + c) % 3 == 0 { (77, 23) } else { (120, 40) };
                    let textures = (k + c) % 4 == 3;
                    for color_depth in
                        [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16, ColorDepth::None]
                    {
                        let options =
                            RenderOptions { charset, color_depth, textures, ..RenderOptions::default() };
                        let mut frame = Frame::new(cols, rows);
                        let region = frame.region();
                        renderer
                            .render(maze, &camera, &[], &options, Target::Frame(&mut frame, region))
                            .expect("render");
                        let s = renderer.samples();
                        let mut h = DefaultHasher::new();
                        s.color().iter().for_each(|c| c.to_array().map(f32::to_bits).hash(&mut h));
                        s.depth().iter().for_each(|d| d.to_bits().hash(&mut h));
                        s.id().hash(&mut h);
                        let samples = h.finish();
                        let mut h = DefaultHasher::new();
                        frame.cells().hash(&mut h);
                        println!(
                            "{name} view {k} pitch {pitch_deg} {charset:?} {color_depth:?} {cols}x{rows} textures {textures}: samples {samples:016x} frame {:016x}",
                            h.finish()
                        );
                        frames += 1;
                    }
                }
            }
        }
    }
    eprintln!("{frames} frames");
}

/// Every chromaticity slot's ramp (`CHROMA_STEPS` = 96 steps of red and green), read at 48 intensities.
fn ramps() {
    const STEPS: usize = 96;
    for palette in [Palette::Xterm256, Palette::Ansi16] {
        for r in 0..=STEPS {
            let mut h = DefaultHasher::new();
            for g in 0..=STEPS - r {
                let chroma = Vec3::new(r as f32, g as f32, (STEPS - r - g) as f32) / STEPS as f32;
                let brightest = 1.0 / chroma.max_element();
                for k in 1..=48 {
                    ramp_entry(chroma * (brightest * k as f32 / 48.0), palette).hash(&mut h);
                }
            }
            println!("{palette:?} red {r}: {:016x}", h.finish());
        }
    }
}
