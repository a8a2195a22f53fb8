//! The whole frame as a player gets it: a [`Session`] walking the scripted walk (see `common`) draws
//! each frame — 3D view, figures, HUD — and encodes it for the terminal (the diff against the frame
//! before, truecolor, at the walk's default tolerance, `encoder::DEFAULT_TOLERANCE`). One criterion
//! iteration is the whole walk; the time per drawn frame and the frames a second one core keeps up
//! are printed after the run from the medians in `target/criterion` (see `scripts/bench_table.py`),
//! at 80×24, 120×40 and 200×60 in every charset.
//!
//! The camera is the walk's own (`viewer_camera`: the maze's field of view, the foveated view) at the
//! benchmark's pose; `frame-plain/120x40/CHARSET` draws the same walk with one scale across (`f`
//! off), the view this bench drew before the foveated one.
//!
//! ```sh
//! nice cargo bench -p mazewalk-bench --bench frame -- --warm-up-time 1 --measurement-time 3 --sample-size 10
//! ```

use mazewalk_bench::common;

use std::hint::black_box;

use criterion::{Criterion, Throughput};
use mazewalk_render::Camera;
use mazewalk_render::Charset;
use mazewalk_term::frame::ColorDepth;
use mazewalk_term::input::KeyPhase;
use mazewalk_walk::state::viewer_camera;
use mazewalk_walk::{Session, SessionOptions};

const SIZES: [(u16, u16); 3] = [(80, 24), (120, 40), (200, 60)];

/// A session at the open view of the 100×100 maze with loops, its first frame (the full paint) sent:
/// the walk's camera there, foveated or (`plain`) not.
fn session(charset: Charset, cols: u16, rows: u16, plain: bool) -> Session {
    let mut app = common::walk_app(100, charset, ColorDepth::TrueColor);
    let (position, yaw_deg) = (app.camera.position, app.camera.yaw_deg);
    app.camera = Camera { position, yaw_deg, ..viewer_camera(app.maze()) };
    app.camera.fovea = !plain;
    let options = SessionOptions { flow_control: false, ..SessionOptions::default() }; // no terminal answers
    let mut session = Session::new(app, cols, rows, options);
    let mut out = Vec::new();
    session.frame(0.0, &mut out);
    session
}

/// Plays the walk script through `session` at [`common::WALK_FPS`]; returns the frames drawn.
fn walk(session: &mut Session, out: &mut Vec<u8>) -> usize {
    let (mut now, mut drawn) = (0.0, 0);
    for (_, key, seconds) in common::walk_script() {
        if let Some(key) = key {
            session.app_mut().key(key, KeyPhase::Press, now);
        }
        for _ in 0..(seconds * common::WALK_FPS).round() as u32 {
            now += 1.0 / common::WALK_FPS;
            out.clear();
            drawn += usize::from(session.frame(now, out));
        }
        if let Some(key) = key {
            session.app_mut().key(key, KeyPhase::Release, now);
        }
    }
    drawn
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    // The script decides which ticks draw (the camera moved), whatever the size or charset.
    let drawn = walk(&mut session(Charset::Ascii, 80, 24, false), &mut Vec::new());
    eprintln!("{drawn} frames drawn per walk");
    let cases = SIZES.iter().map(|&(cols, rows)| ("frame", cols, rows, false)).chain([(
        "frame-plain",
        120,
        40,
        true,
    )]);
    for (name, cols, rows, plain) in cases {
        let mut group = c.benchmark_group(format!("{name}/{cols}x{rows}"));
        group.throughput(Throughput::Elements(drawn as u64));
        for charset in Charset::ALL {
            group.bench_function(charset.to_string(), |b| {
                let mut out = Vec::with_capacity(1 << 20);
                b.iter_batched_ref(
                    || session(charset, cols, rows, plain),
                    |session| black_box(walk(session, &mut out)),
                    criterion::BatchSize::LargeInput,
                );
            });
        }
        group.finish();
    }
    c.final_summary();
}
