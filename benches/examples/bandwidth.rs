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
//!
//! Beside the bytes, the picture: the mean OKLab distance, over every sample of every frame shown
//! while the key is held, between what the terminal shows and the exact frame the session drew (0
//! where the colour tolerance left nothing off; issue #42's limit for truecolor is 0.01).

use mazewalk_testkit::link;

use link::{LinkConfig, Sim};
use mazewalk_maze as maze;
use mazewalk_render::quality::shown;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::{ColorDepth, Frame};
use mazewalk_testkit::screen::screen_frame;
use mazewalk_walk::{App, Session, SessionOptions};

/// A link fast enough never to hold a frame back: the session's own output rate.
const UNLIMITED: LinkConfig = LinkConfig { bytes_per_s: 1e12, one_way: 0.0 };
const ONE_MBIT: LinkConfig = LinkConfig { bytes_per_s: 125_000.0, one_way: 0.050 };

fn session(cols: u16, rows: u16, depth: ColorDepth, flow_control: bool) -> Session {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("viewer in a cell");
    Session::new(app, cols, rows, SessionOptions { flow_control, ..SessionOptions::default() })
}

/// The sum of the OKLab distances, sample by sample (half blocks), between what the terminal
/// shows and the exact frame, and the samples.
fn distance(terminal: &vt100::Parser, exact: &Frame) -> (f64, usize) {
    let (got, want) = (shown(&screen_frame(terminal), Charset::Half), shown(exact, Charset::Half));
    (got.iter().zip(&want).map(|(a, b)| f64::from(a.distance(*b))).sum(), got.len())
}

/// What holding a key cost and showed.
struct Held {
    /// Bytes per second while the viewer moves (a walk that reaches a wall stops counting there).
    bytes_per_s: f64,
    /// The latencies of the frames shown meanwhile, sorted.
    latencies: Vec<f64>,
    /// How long the picture moved on after the release.
    tail: f64,
    /// The mean OKLab distance of the screen from the exact frame over the frames shown as soon as
    /// drawn while the key was held (none over a slow link, where the screen lags the session).
    picture: Option<f64>,
}

/// Holds `key` from 1 s to 4 s (auto-repeat every 33 ms after 500 ms).
fn hold(mut sim: Sim, key: &[u8]) -> Held {
    let (press, release) = (1.0, 4.0);
    sim.run_until(press, |_| {});
    let before = sim.bytes_sent;
    sim.type_keys(key);
    let mut next = press + 0.5;
    let (mut last, mut changed) = (None, 0.0);
    let one_way = sim.link.one_way;
    let mut viewer = (sim.session.app().camera.position, sim.session.app().camera.yaw_deg);
    let mut moving_until = press;
    let (mut sum, mut samples, mut seen) = (0.0, 0, 0);
    sim.run_until(release + 12.0, |sim| {
        // A frame shown a step after it was drawn (a link that holds none back; the session draws
        // at most 60 a second, so it is still the last it drew): the screen against it.
        if sim.shown.len() > seen {
            seen = sim.shown.len();
            let last = sim.shown[seen - 1];
            let at_once = sim.link.one_way == 0.0 && last.shown_at - last.drawn_at < 1.5 * link::STEP;
            if at_once && last.drawn_at > press && last.drawn_at <= release {
                let (s, n) = distance(&sim.terminal, sim.session.screen());
                (sum, samples) = (sum + s, samples + n);
            }
        }
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
    Held {
        bytes_per_s: held as f64 / (moving - press).max(1e-3),
        latencies: lat,
        tail: (changed - release).max(0.0),
        picture: (samples > 0).then(|| sum / samples as f64),
    }
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
    println!(
        "| size | colours | walking (W) | turning (←) | picture: mean OKLab distance walking / turning |"
    );
    println!("|---|---|---:|---:|---:|");
    for (cols, rows) in [(80, 24), (120, 40), (200, 60)] {
        for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16, ColorDepth::None] {
            let walk = hold(sim(session(cols, rows, depth, false), rows, cols, UNLIMITED), b"w");
            let turn = hold(sim(session(cols, rows, depth, false), rows, cols, UNLIMITED), b"\x1b[D");
            let picture = |held: &Held| held.picture.map_or("–".into(), |d| format!("{d:.4}"));
            println!(
                "| {cols}×{rows} | {depth} | {:.2} KB/s | {:.2} KB/s | {} / {} |",
                walk.bytes_per_s / 1e3,
                turn.bytes_per_s / 1e3,
                picture(&walk),
                picture(&turn)
            );
        }
    }
    println!(
        "\nTurning at 120×40 over 1 Mbit/s with 50 ms each way (key-to-screen latency of the frames shown):\n"
    );
    println!("| colours | flow control | bytes/s | latency p50 | p95 | max | still turning after release |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        for flow in [true, false] {
            let Held { bytes_per_s: bps, latencies: lat, tail, .. } =
                hold(sim(session(120, 40, depth, flow), 40, 120, ONE_MBIT), b"\x1b[D");
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
