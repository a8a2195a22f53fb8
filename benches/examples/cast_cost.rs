//! What `--record` adds to a frame: the time to write a frame's bytes as an asciicast event (JSON
//! escaping through a `BufWriter` into a file, as the walk does) beside the time to make the frame
//! (`Session::frame`: render and encode), per frame, medians over a held turn (the most bytes a
//! second) and a held walk, with the cast's size per byte sent.
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example cast_cost
//! ```

use std::io::BufWriter;
use std::time::Instant;

use mazewalk_maze as maze;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::ColorDepth;
use mazewalk_term::input::Input;
use mazewalk_walk::cast::{CastWriter, Header};
use mazewalk_walk::{App, Session, SessionOptions};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Holds `key` for 6 s of virtual time at 60 frames a second; returns the medians of (frame µs,
/// cast µs), the bytes sent and the bytes of the cast.
fn measure(cols: u16, rows: u16, depth: ColorDepth, key: &[u8]) -> (f64, f64, u64, u64) {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("viewer in a cell");
    let mut session =
        Session::new(app, cols, rows, SessionOptions { flow_control: false, ..SessionOptions::default() });
    session.input(Input::Resize { cols, rows }, 0.0);
    let header = Header {
        width: cols,
        height: rows,
        timestamp: None,
        title: "cast_cost".into(),
        term: Some("xterm-256color".into()),
        colorterm: None,
        color_depth: depth,
        charset: Charset::Half,
        asked_truecolor: false,
    };
    let path = std::env::temp_dir().join(format!("mazewalk-cast-cost-{}.cast", std::process::id()));
    let file = std::fs::File::create(&path).expect("a temporary file");
    let mut cast = CastWriter::new(BufWriter::new(file), &header).expect("header");
    let (mut frame_us, mut cast_us, mut sent) = (Vec::new(), Vec::new(), 0u64);
    let mut bytes = Vec::new();
    let mut next_key = 0.0;
    for step in 0..360 {
        let now = f64::from(step) / 60.0;
        if now >= next_key {
            session.feed(key, now); // a held key's auto-repeat, every 33 ms
            next_key += 0.033;
        }
        bytes.clear();
        let started = Instant::now();
        if !session.frame(now, &mut bytes) || bytes.is_empty() {
            continue;
        }
        frame_us.push(started.elapsed().as_secs_f64() * 1e6);
        let started = Instant::now();
        cast.output(now, &bytes);
        cast_us.push(started.elapsed().as_secs_f64() * 1e6);
        sent += bytes.len() as u64;
    }
    cast.finish().expect("the cast written");
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    let _ = std::fs::remove_file(&path);
    (median(frame_us), median(cast_us), sent, size)
}

fn main() {
    println!("Recording's cost per frame (half blocks, built-in maze, a key held 6 s, medians):\n");
    println!(
        "| size | colours | key | bytes sent | frame (render + encode) | cast event | cast / frame | cast bytes / bytes sent |"
    );
    println!("|---|---|---|---:|---:|---:|---:|---:|");
    for (cols, rows) in [(80, 24), (120, 40), (200, 60)] {
        for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
            for (name, key) in [("turn ←", &b"\x1b[D"[..]), ("walk W", b"w")] {
                let (frame, cast, sent, size) = measure(cols, rows, depth, key);
                println!(
                    "| {cols}×{rows} | {depth} | {name} | {:.0} KB | {frame:.0} µs | {cast:.0} µs | {:.1} % | {:.2} |",
                    sent as f64 / 1e3,
                    100.0 * cast / frame,
                    size as f64 / sent as f64
                );
            }
        }
    }
}
