//! Where a 256-colour frame's bytes go while turning and walking at 120×40 (issue #42): the bytes by
//! kind (colours, cursor moves, glyphs, markers), and the cells that changed by how far their
//! colours moved in OKLab (each cell's largest sample distance between the frame before and this one),
//! exact (0), at the default tolerance (2) and at two raised ones (4, 6; a slow link raises it to 5 and 8),
//! and how often a changed cell has the colours of the changed cell before it, row by row or column
//! by column.
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example palette_bytes
//! ```

use mazewalk_bench::stream::Kinds;
use mazewalk_maze as maze;
use mazewalk_render::quality::shown;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::encoder::DEFAULT_TOLERANCE;
use mazewalk_term::frame::{ColorDepth, Frame};
use mazewalk_walk::{App, Session, SessionOptions};

const COLS: u16 = 120;
const ROWS: u16 = 40;

/// Holds `key` for 3 s (30 presses a second, a frame each 1/60 s); returns the bytes by kind, the
/// changed cells' histogram by largest sample distance (≤ 0.02, 0.03, 0.04, 0.06, more), and the
/// seconds the viewer moved.
fn run(key: &[u8], tolerance: u8) -> (Kinds, [usize; 5], f64, (usize, usize, usize)) {
    let options = RenderOptions {
        charset: Charset::Half,
        color_depth: ColorDepth::Ansi256,
        ..RenderOptions::default()
    };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("a start cell");
    let mut session = Session::new(
        app,
        COLS,
        ROWS,
        SessionOptions { flow_control: false, color_tolerance: tolerance, ..SessionOptions::default() },
    );
    let mut out = Vec::new();
    session.frame(0.0, &mut out);
    let mut before: Frame = session.screen().clone();
    let (mut kinds, mut hist) = (Kinds::default(), [0usize; 5]);
    let mut shared = (0, 0, 0);
    let mut viewer = (session.app().camera.position, session.app().camera.yaw_deg);
    let mut moved = 0.0;
    for i in 1..=180 {
        let now = f64::from(i) / 60.0;
        if i % 2 == 1 {
            session.feed(key, now);
        }
        out.clear();
        if !session.frame(now, &mut out) {
            continue;
        }
        let now_viewer = (session.app().camera.position, session.app().camera.yaw_deg);
        if now_viewer == viewer {
            continue; // not moving (a wall): not counted
        }
        viewer = now_viewer;
        moved += 1.0 / 60.0;
        kinds.add(&out);
        let after = session.screen();
        let (a, b) = (shown(&before, Charset::Half), shown(after, Charset::Half));
        let cols = usize::from(COLS);
        let changed = |k: usize| before.cells()[k] != after.cells()[k];
        let colours = |k: usize| (after.cells()[k].fg, after.cells()[k].bg);
        let mut last = None;
        for (k, (x, y)) in before.cells().iter().zip(after.cells()).enumerate() {
            if x == y {
                continue;
            }
            // Colours shared with the changed cell written before it (row by row), or with a changed
            // cell right above it (what a column-wise order would write before it).
            shared.0 += usize::from(last.is_some_and(|j| colours(j) == colours(k)));
            shared.1 += usize::from(k >= cols && changed(k - cols) && colours(k - cols) == colours(k));
            shared.2 += 1;
            last = Some(k);
            let (col, row) = (k % usize::from(COLS), k / usize::from(COLS));
            let d = (0..2)
                .map(|s| {
                    let i = (row * 2 + s) * usize::from(COLS) + col;
                    a[i].distance(b[i])
                })
                .fold(0.0f32, f32::max);
            let bucket = [0.02, 0.03, 0.04, 0.06].iter().position(|&t| d <= t).unwrap_or(4);
            hist[bucket] += 1;
        }
        before = after.clone();
    }
    (kinds, hist, moved, shared)
}

fn main() {
    println!("256 colours, 120×40 half blocks, built-in maze, 60 frames/s, 3 s of a held key:\n");
    println!(
        "| key | tolerance | KB/s | SGR | SGRs/frame | moves and erasures | glyphs | markers | cells changed by ≤0.02 / ≤0.03 / ≤0.04 / ≤0.06 / more | colours as the last changed cell / as the changed cell above |"
    );
    println!("|---|---|--:|--:|--:|--:|--:|--:|---|---|");
    for (name, key) in [("turning ←", b"\x1b[D".as_slice()), ("walking W", b"w".as_slice())] {
        for tolerance in [0, DEFAULT_TOLERANCE, 4, 6] {
            let (k, hist, moved, shared) = run(key, tolerance);
            let pct = |n: usize| format!("{:.0} %", 100.0 * n as f64 / k.total().max(1) as f64);
            let frames = (moved * 60.0).round().max(1.0);
            println!(
                "| {name} | {tolerance} | {:.1} | {} | {:.0} | {} | {} | {} | {:?} | {:.0} % / {:.0} % |",
                k.total() as f64 / moved.max(1e-3) / 1e3,
                pct(k.sgr),
                k.sgr_count as f64 / frames,
                pct(k.moves + k.erase),
                pct(k.glyphs),
                pct(k.markers),
                hist,
                100.0 * shared.0 as f64 / shared.2.max(1) as f64,
                100.0 * shared.1 as f64 / shared.2.max(1) as f64,
            );
        }
    }
}
