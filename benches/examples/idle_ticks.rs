//! An idle player's session for callgrind (issue #42, 1,000 idle players at ~0 CPU): a first paint,
//! then the player stands still for SECONDS seconds, the session woken only when it asks
//! ([`Session::next_wake`]): the settle after the first paint, then the HUD's exit clock, a tick a
//! second. No link, no flow control: what a tick costs the walk itself.
//!
//! ```sh
//! cargo build --release -p mazewalk-bench --example idle_ticks
//! valgrind --tool=callgrind ./target/release/examples/idle_ticks 256 1     # DEPTH SECONDS COLS ROWS
//! valgrind --tool=callgrind ./target/release/examples/idle_ticks 256 101
//! ```
//!
//! A tick's instructions: (the 101 s run's total − the 1 s run's) ÷ 100. It prints the frames drawn,
//! their bytes and a hash of all the output, first paint included: two builds that print the same
//! line sent the same bytes.

use mazewalk_maze as maze;
use mazewalk_render::RenderOptions;
use mazewalk_term::frame::ColorDepth;
use mazewalk_walk::{App, Session, SessionOptions};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_owned());
    let depth: ColorDepth = arg(0, "256").parse().expect("colour depth");
    let seconds: f64 = arg(1, "101").parse().expect("seconds");
    let (cols, rows): (u16, u16) =
        (arg(2, "120").parse().expect("cols"), arg(3, "40").parse().expect("rows"));
    let options = RenderOptions { color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("a start cell");
    let options = SessionOptions { flow_control: false, ..SessionOptions::default() };
    let mut session = Session::new(app, cols, rows, options);
    // FNV-1a over every byte sent (the first paint included): an A/B of two builds compares it.
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    let (mut out, mut frames, mut bytes, mut now) = (Vec::new(), 0, 0, 0.0);
    while now <= seconds {
        out.clear();
        if session.frame(now, &mut out) {
            frames += 1;
        }
        bytes += out.len();
        for &b in &out {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        let Some(wake) = session.next_wake(now) else { break };
        now = wake.max(now + 1e-3); // (a wake due now: on a little, as a host's sleep would)
    }
    println!("{depth} {cols}x{rows}, idle {seconds} s: {frames} frames, {bytes} bytes, FNV-1a {hash:016x}");
}
