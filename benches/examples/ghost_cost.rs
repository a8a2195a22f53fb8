//! Issue #43: what a ghost costs — the size of a run (a ghost's data) against its 64 KiB cap, the
//! time to encode and decode one, and a frame's render time with a ghost in view beside one with a
//! live player's figure in the same place and one with nobody, in the same run.
//!
//! ```sh
//! nice cargo run --release -p mazewalk-bench --example ghost_cost
//! ```
//!
//! Runs: a walker through the app's own key handlers at 60 ticks a second in a generated 40×25 maze
//! (`W` held, a random turn of 15–180° every 0.5–3 s, looking up or down now and then), its poses kept
//! by the run's recorder for 1, 5 and 10 minutes. Frames: the walk script of the other benches in
//! the built-in maze at 120×40 half blocks, truecolor, the figure 3 units ahead of the viewer
//! wherever that is in a cell; render time per frame, median.

use mazewalk_bench::common;

use std::time::Instant;

use glam::{Vec2, Vec3};
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::geometry::heading_dir;
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, Sprite, Target};
use mazewalk_term::frame::{ColorDepth, Frame};
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::App;
use mazewalk_walk::run::{MAX_BYTES, Recorder, Run};

/// A small deterministic generator (the walker's choices).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The run of `minutes` of the random walker.
fn walker_run(minutes: f64) -> Run {
    let maze = generate(&GenOptions { width: 40, height: 25, seed: 3, loops: 0.1, ..GenOptions::default() })
        .expect("generated maze");
    let hash = maze.content_hash();
    let mut app = App::new(maze, RenderOptions::default(), 0.0).expect("viewer in the maze");
    app.releases = true;
    let (mut rng, mut recorder) = (Lcg(7), Recorder::default());
    app.key(Key::Char('w'), KeyPhase::Press, 0.0);
    let (mut next_turn, mut turning): (f64, Option<(Key, f64)>) = (1.0, None);
    let ticks = (minutes * 60.0 * 60.0) as u32;
    for tick in 1..=ticks {
        let now = f64::from(tick) / 60.0;
        if let Some((key, until)) = turning
            && now >= until
        {
            app.key(key, KeyPhase::Release, now);
            turning = None;
        }
        if turning.is_none() && now >= next_turn {
            let key = [Key::Left, Key::Right, Key::Left, Key::Right, Key::Up, Key::Down]
                [(rng.next() * 6.0) as usize];
            let hold = 0.1 + rng.next() * 1.5;
            app.key(key, KeyPhase::Press, now);
            turning = Some((key, now + hold));
            next_turn = now + hold + 0.5 + rng.next() * 2.5;
        }
        app.tick(now);
        recorder.note(now, app.pose());
    }
    let seconds = f64::from(ticks) / 60.0;
    recorder.finish(hash, "walker", seconds, app.pose()).expect("a run within the cap")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    println!("| run | samples | bytes | bytes per sample | of the cap | encode µs | decode µs |");
    println!("|---|--:|--:|--:|--:|--:|--:|");
    for minutes in [1.0, 5.0, 10.0] {
        let run = walker_run(minutes);
        let bytes = run.encode().expect("encode");
        let encode = median(
            (0..101)
                .map(|_| {
                    let t = Instant::now();
                    std::hint::black_box(run.encode().expect("encode"));
                    t.elapsed().as_secs_f64() * 1e6
                })
                .collect(),
        );
        let decode = median(
            (0..101)
                .map(|_| {
                    let t = Instant::now();
                    std::hint::black_box(Run::decode(&bytes).expect("decode"));
                    t.elapsed().as_secs_f64() * 1e6
                })
                .collect(),
        );
        println!(
            "| {minutes} min | {} | {} | {:.2} | {:.0} % | {encode:.0} | {decode:.0} |",
            run.samples.len(),
            bytes.len(),
            bytes.len() as f64 / run.samples.len() as f64,
            100.0 * bytes.len() as f64 / MAX_BYTES as f64
        );
    }

    let maze = mazewalk_maze::builtin().expect("built-in maze");
    let mut app = App::new(maze.clone(), RenderOptions::default(), 0.0).expect("viewer in the maze");
    app.releases = true;
    let mut cameras: Vec<Camera> = Vec::new();
    common::play_walk(&mut app, &common::walk_script(), |app, _, _| cameras.push(app.camera));
    let options = RenderOptions {
        charset: Charset::Half,
        color_depth: ColorDepth::TrueColor,
        ..RenderOptions::default()
    };
    let figure = |camera: &Camera, ghost: bool| {
        let position: Vec2 = camera.position + heading_dir(camera.yaw_deg.to_radians()) * 3.0;
        let cell = maze.cell_at(position)?;
        let color = if ghost { Vec3::new(0.78, 0.92, 1.0) } else { Vec3::new(0.9, 0.2, 0.2) };
        Some(Sprite { position, cell, color, label: 'a', ghost })
    };
    println!();
    println!("| 120×40 half, truecolor | frames | render ms (median) | ratio to nobody |");
    println!("|---|--:|--:|--:|");
    let mut times: [Vec<f64>; 3] = Default::default();
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(120, 40);
    // alternated frame by frame, so that the three see the same machine
    for _ in 0..5 {
        for camera in &cameras {
            let (Some(solid), Some(ghost)) = (figure(camera, false), figure(camera, true)) else { continue };
            for (k, sprites) in [&[][..], &[solid][..], &[ghost][..]].into_iter().enumerate() {
                let region = frame.region();
                let t = Instant::now();
                renderer
                    .render(&maze, camera, sprites, &options, Target::Frame(&mut frame, region))
                    .expect("camera");
                times[k].push(t.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    let frames = times[0].len();
    let [nobody, player, ghost] = times.map(median);
    for (name, ms) in [("nobody", nobody), ("a player's figure", player), ("a ghost", ghost)] {
        println!("| {name} | {frames} | {ms:.3} | {:.3} |", ms / nobody);
    }
}
