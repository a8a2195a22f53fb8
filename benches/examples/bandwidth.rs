//! Bytes per second on the wire while walking and turning, and key-to-screen latency on a slow link,
//! in virtual time through the same [`Session`] the walkthrough and the server run (deterministic up
//! to the HUD's frame-time field). Prints the markdown tables of BENCHMARKS.md.
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example bandwidth [--ascii-rep]
//! ```
//!
//! The terminal (vt100) repeats any glyph on REP and says so, as xterm does; `--ascii-rep` has it
//! answer the session's REP probe as tmux does (REP after ASCII glyphs only).

use mazewalk_testkit::link;

use link::{LinkConfig, Sim};
use mazewalk_maze as maze;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::ColorDepth;
use mazewalk_walk::{App, Session, SessionOptions};

/// A link fast enough never to hold a frame back: the session's own output rate.
const UNLIMITED: LinkConfig = LinkConfig { bytes_per_s: 1e12, one_way: 0.0 };
const ONE_MBIT: LinkConfig = LinkConfig { bytes_per_s: 125_000.0, one_way: 0.050 };

fn session(cols: u16, rows: u16, depth: ColorDepth, flow_control: bool) -> Session {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("viewer in a cell");
    Session::new(app, cols, rows, SessionOptions { flow_control, ..SessionOptions::default() })
}

/// Holds `key` from 1 s to 4 s (auto-repeat every 33 ms after 500 ms): bytes per second while the
/// viewer moves (a walk that reaches a wall stops counting there), the latencies of the frames shown
/// meanwhile (sorted), and how long the picture moved on after the release.
fn hold(mut sim: Sim, key: &[u8]) -> (f64, Vec<f64>, f64) {
    let (press, release) = (1.0, 4.0);
    sim.run_until(press, |_| {});
    let before = sim.bytes_sent;
    sim.type_keys(key);
    let mut next = press + 0.5;
    let (mut last, mut changed) = (None, 0.0);
    let one_way = sim.link.one_way;
    let mut viewer = (sim.session.app().camera.position, sim.session.app().camera.yaw_deg);
    let mut moving_until = press;
    sim.run_until(release + 12.0, |sim| {
        let now_viewer = (sim.session.app().camera.position, sim.session.app().camera.yaw_deg);
        if now_viewer != viewer {
            (viewer, moving_until) = (now_viewer, sim.now);
        }
        if sim.now >= next && sim.now <= release {
            sim.type_keys(key);
            next += 0.033;
        }
        if sim.now > release {
            let hud = sim.screen_heading();
            if hud != last {
                (last, changed) = (hud, sim.now);
            }
        }
    });
    let moving = moving_until.min(release);
    let held: usize =
        sim.shown.iter().filter(|f| f.drawn_at > press && f.drawn_at <= moving).map(|f| f.bytes).sum();
    let _ = before;
    let mut lat: Vec<f64> = sim
        .shown
        .iter()
        .filter(|f| f.drawn_at > press + one_way && f.drawn_at < release)
        .map(|f| f.shown_at - (f.drawn_at - one_way))
        .collect();
    lat.sort_by(f64::total_cmp);
    (held as f64 / (moving - press).max(1e-3), lat, (changed - release).max(0.0))
}

fn main() {
    let repeats_blocks = !std::env::args().any(|a| a == "--ascii-rep");
    let sim = |session: Session, rows: u16, cols: u16, link: LinkConfig| {
        let mut sim = Sim::new(session, rows, cols, link);
        sim.repeats_blocks = repeats_blocks;
        sim
    };
    println!(
        "Bytes per second while a key is held (half blocks, built-in maze, 60 frames/s at most; REP after {}):\n",
        if repeats_blocks { "any glyph, as xterm" } else { "ASCII only, as tmux" }
    );
    println!("| size | colours | walking (W) | turning (←) |");
    println!("|---|---|---:|---:|");
    for (cols, rows) in [(80, 24), (120, 40), (200, 60)] {
        for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16, ColorDepth::None] {
            let walk = hold(sim(session(cols, rows, depth, false), rows, cols, UNLIMITED), b"w").0;
            let turn = hold(sim(session(cols, rows, depth, false), rows, cols, UNLIMITED), b"\x1b[D").0;
            println!("| {cols}×{rows} | {depth} | {:.1} KB/s | {:.1} KB/s |", walk / 1e3, turn / 1e3);
        }
    }
    println!(
        "\nTurning at 120×40 over 1 Mbit/s with 50 ms each way (key-to-screen latency of the frames shown):\n"
    );
    println!("| colours | flow control | bytes/s | latency p50 | p95 | max | still turning after release |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        for flow in [true, false] {
            let (bps, lat, tail) = hold(sim(session(120, 40, depth, flow), 40, 120, ONE_MBIT), b"\x1b[D");
            let p = |q: f64| lat[((lat.len() - 1) as f64 * q).round() as usize];
            println!(
                "| {depth} | {} | {:.0} KB/s | {:.0} ms | {:.0} ms | {:.0} ms | {:.2} s |",
                if flow { "on" } else { "off" },
                bps / 1e3,
                p(0.5) * 1e3,
                p(0.95) * 1e3,
                p(1.0) * 1e3,
                tail
            );
        }
    }
}
