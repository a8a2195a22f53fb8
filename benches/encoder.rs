//! Bytes on the wire and encode time over a scripted walk at 160×48 (half blocks): forward, a full
//! 360° turn, a strafe, looking up and down, then standing still. Beside our encoder: a naive full
//! repaint of every frame (an SGR per cell) and the lower bound (only the changed cells' glyph bytes).
//! The byte table is printed first (deterministic); criterion then times the encoder per frame.
//!
//! `cargo bench --bench encoder`

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use mazewalk::app::App;
use mazewalk::app::run::{FrameCost, Screen, draw};
use mazewalk::frame::{ColorDepth, Frame};
use mazewalk::maze;
use mazewalk::render::{Charset, Culling, RenderOptions};
use mazewalk::term::encoder::{Encoder, full_repaint};
use mazewalk::term::{Key, KeyAction};

const COLS: usize = 160;
const ROWS: usize = 48;
/// Frames per second of the script (the loop's cap).
const FPS: f64 = 60.0;

/// The script: (key held, seconds). `None` = stand still.
const SCRIPT: &[(Option<Key>, f64)] = &[
    (Some(Key::Char('w')), 1.0),
    (Some(Key::Left), 360.0 / 110.0), // a full turn at the turn speed
    (Some(Key::Char('d')), 0.5),
    (Some(Key::Up), 0.5),
    (Some(Key::Down), 1.0),
    (None, 1.0),
];

/// Every screen of the scripted walk, as the walkthrough draws it (3D view, corner map, HUD).
fn walk_frames(depth: ColorDepth) -> Vec<Frame> {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, culling: Culling::Portal, cell_aspect: 0.5 };
    let mut app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("start");
    app.releases = true; // the kitty protocol: press … release
    let mut screen = Screen::default();
    let mut frames = Vec::new();
    let mut t = 0.0;
    for &(key, seconds) in SCRIPT {
        if let Some(key) = key {
            app.key(key, KeyAction::Press, t);
        }
        let end = t + seconds;
        while t < end {
            t += 1.0 / FPS;
            app.tick(t);
            let mut frame = Frame::new(COLS, ROWS);
            // A constant HUD cost, so the frame-time text does not make every frame differ.
            draw(&app, &mut screen, &mut frame, &FrameCost::default());
            frames.push(frame);
        }
        if let Some(key) = key {
            app.key(key, KeyAction::Release, t);
        }
    }
    frames
}

fn median(mut v: Vec<usize>) -> usize {
    v.sort_unstable();
    v[v.len() / 2]
}

fn bench(c: &mut Criterion) {
    for (name, depth) in [("truecolor", ColorDepth::TrueColor), ("256", ColorDepth::Ansi256)] {
        let frames = walk_frames(depth);
        let mut encoder = Encoder::new();
        let (mut ours, mut naive, mut bound, mut idle) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut out = Vec::new();
        for (i, frame) in frames.iter().enumerate() {
            let lower = encoder.lower_bound(frame);
            out.clear();
            let stats = encoder.encode(frame, &mut out);
            let mut full = Vec::new();
            full_repaint(frame, &mut full);
            if i == 0 {
                continue; // the first frame is a full paint for everyone
            }
            if stats.cells_changed == 0 {
                idle.push(stats.bytes);
            } else {
                ours.push(stats.bytes);
                naive.push(full.len());
                bound.push(lower);
            }
        }
        let (o, n, b) = (median(ours.clone()), median(naive.clone()), median(bound.clone()));
        eprintln!(
            "{name}: {} walking frames: median bytes/frame ours {o}, naive full repaint {n} ({:.1}× ours), \
             lower bound {b} (ours {:.2}× it); mean ours {}; {} idle frames sent {} bytes in all",
            ours.len(),
            n as f64 / o as f64,
            o as f64 / b.max(1) as f64,
            ours.iter().sum::<usize>() / ours.len().max(1),
            idle.len(),
            idle.iter().sum::<usize>()
        );
        let mut group = c.benchmark_group(format!("encode-{name}"));
        group.sample_size(20).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
        group.bench_function("ours, whole walk", |bch| {
            bch.iter(|| {
                let mut encoder = Encoder::new();
                let mut out = Vec::with_capacity(1 << 16);
                for frame in &frames {
                    out.clear();
                    black_box(encoder.encode(frame, &mut out));
                }
            })
        });
        group.bench_function("naive full repaint, whole walk", |bch| {
            bch.iter(|| {
                let mut out = Vec::with_capacity(1 << 18);
                for frame in &frames {
                    out.clear();
                    full_repaint(frame, &mut out);
                    black_box(&out);
                }
            })
        });
        group.finish();
        eprintln!("({} frames per walk)", frames.len());
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
