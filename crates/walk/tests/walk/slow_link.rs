//! End-to-end flow control on a slow link (issue #14): turning at 120×40 in truecolor over 1 Mbit/s
//! with 50 ms each way. With flow control the picture stays within a couple of frame transmissions
//! and a round trip of the keys; without it, on a link slower than the frames (a third of a megabit),
//! frames queue in the link and the picture falls behind and keeps turning long after the key is
//! let go. Virtual time: the figures are deterministic.

use crate::common;

use common::link::{LinkConfig, Sim};
use mazewalk_maze as maze;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::ColorDepth;
use mazewalk_walk::{App, Session, SessionOptions};

const ONE_MBIT: LinkConfig = LinkConfig { bytes_per_s: 125_000.0, one_way: 0.050 };
/// Slower than the frames while turning (about 68 KB/s unthrottled): there they queue.
const THIRD_MBIT: LinkConfig = LinkConfig { bytes_per_s: 41_667.0, one_way: 0.050 };
/// The key goes down here and is held (auto-repeat every 33 ms after 500 ms) until [`RELEASE`].
const PRESS: f64 = 1.0;
const RELEASE: f64 = 3.0;

/// What a player on the link sees while turning.
#[derive(Debug)]
struct Turning {
    /// Key-to-screen latency of each frame shown while the key is held: from the moment the state
    /// it shows was typed (drawn − one way) to the moment it is on screen. Sorted.
    latencies: Vec<f64>,
    /// How long after the key is let go the picture still turns.
    tail: f64,
    /// Bytes per second over the link while turning.
    bytes_per_s: f64,
}

impl Turning {
    fn percentile(&self, p: f64) -> f64 {
        self.latencies[((self.latencies.len() - 1) as f64 * p).round() as usize]
    }
}

fn turn(link: LinkConfig, flow_control: bool) -> Turning {
    let options = RenderOptions {
        charset: Charset::Half,
        color_depth: ColorDepth::TrueColor,
        ..RenderOptions::default()
    };
    let app = App::new(maze::builtin().unwrap(), options, 0.0).unwrap();
    let session = Session::new(app, 120, 40, SessionOptions { flow_control, ..SessionOptions::default() });
    let mut sim = Sim::new(session, 40, 120, link);
    sim.run_until(PRESS, |_| {});
    sim.type_keys(b"\x1b[D");
    let mut next_repeat = PRESS + 0.5;
    let (mut last_heading, mut last_change) = (None, 0.0);
    let sent_before = sim.bytes_sent;
    sim.run_until(RELEASE + 10.0, |sim| {
        if sim.now >= next_repeat && sim.now <= RELEASE {
            sim.type_keys(b"\x1b[D");
            next_repeat += 0.033;
        }
        let heading = sim.screen_heading();
        if heading != last_heading {
            (last_heading, last_change) = (heading, sim.now);
        }
    });
    let mut latencies: Vec<f64> = sim
        .shown
        .iter()
        .filter(|f| f.drawn_at > PRESS + link.one_way && f.drawn_at < RELEASE)
        .map(|f| f.shown_at - (f.drawn_at - link.one_way))
        .collect();
    latencies.sort_by(f64::total_cmp);
    let held_bytes: usize =
        sim.shown.iter().filter(|f| f.drawn_at > PRESS && f.drawn_at < RELEASE).map(|f| f.bytes).sum();
    let _ = sent_before;
    Turning { latencies, tail: last_change - RELEASE, bytes_per_s: held_bytes as f64 / (RELEASE - PRESS) }
}

#[test]
fn with_flow_control_the_picture_keeps_up_with_the_keys_on_a_slow_link() {
    let show = |name: &str, t: &Turning| {
        println!(
            "{name}: p50 {:.3} s, max {:.3} s, tail {:.3} s, {:.0} B/s",
            t.percentile(0.5),
            t.percentile(1.0),
            t.tail,
            t.bytes_per_s
        );
    };
    let with = turn(ONE_MBIT, true);
    show("1 Mbit/s, with flow control", &with);
    assert!(with.latencies.len() >= 5, "frames were shown while turning: {with:?}");
    assert!(with.percentile(1.0) <= 0.6, "{with:?}");
    assert!(with.tail <= 0.6, "the picture stops soon after the key: {with:?}");
    // Without it a link slower than the frames queues them: the picture lags more and more, and goes
    // on turning. (Since the encoder writes columns and REP, turning in truecolor takes less than
    // 1 Mbit/s: a third of it shows the queue.)
    let (slow_with, without) = (turn(THIRD_MBIT, true), turn(THIRD_MBIT, false));
    show("1/3 Mbit/s, with flow control", &slow_with);
    show("1/3 Mbit/s, without", &without);
    assert!(slow_with.percentile(1.0) <= 0.6 && slow_with.tail <= 0.6, "{slow_with:?}");
    assert!(without.percentile(1.0) > 2.0 * slow_with.percentile(1.0), "{without:?}");
    assert!(without.tail > 1.0, "{without:?}");
}
