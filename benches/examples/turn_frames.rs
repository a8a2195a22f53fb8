//! A first paint and 39 frames of turning (`←` 30 times a second) through the walk's session, for
//! callgrind's count of what the encoder spends on them (issue #42): no link, no clock.
//!
//! ```sh
//! cargo build --release -p mazewalk-bench --example turn_frames
//! valgrind --tool=callgrind ./target/release/examples/turn_frames truecolor   # COLS ROWS TOLERANCE REP KEY optional
//! callgrind_annotate --inclusive=yes callgrind.out.* | grep 'Encoder::encode \['
//! ```
//!
//! REP: `rep` answers the session's question as a terminal with REP does (runs go as `CSI n b`),
//! `norep` (the default) as one without. KEY: `turn` (the default, `←`) or `walk` (`W`). It prints
//! the bytes of the 39 frames and a hash of all the output, first paint included: two builds that
//! print the same line sent the same bytes.

use mazewalk_maze as maze;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::ColorDepth;
use mazewalk_walk::{App, Session, SessionOptions};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or_else(|| default.to_owned());
    let depth: ColorDepth = arg(0, "truecolor").parse().expect("colour depth");
    let (cols, rows): (u16, u16) =
        (arg(1, "120").parse().expect("cols"), arg(2, "40").parse().expect("rows"));
    let tolerance: u8 =
        arg(3, &mazewalk_term::encoder::DEFAULT_TOLERANCE.to_string()).parse().expect("tolerance");
    let rep = arg(4, "norep") == "rep";
    let key: &[u8] = if arg(5, "turn") == "walk" { b"w" } else { b"\x1b[D" };
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("a start cell");
    let mut session = Session::new(
        app,
        cols,
        rows,
        SessionOptions { flow_control: false, color_tolerance: tolerance, ..SessionOptions::default() },
    );
    let (mut out, mut bytes) = (Vec::new(), 0);
    session.frame(0.0, &mut out);
    // FNV-1a over every byte sent (the first paint included): an A/B of two encoders compares it.
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    let mut fold = |bytes: &[u8]| {
        for &b in bytes {
            hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    fold(&out);
    // The answer to the REP probe before the first frame: two cells written (REP), or one.
    session.feed(if rep { b"\x1b[2;3R" } else { b"\x1b[2;2R" }, 0.0);
    for i in 1..40 {
        let now = f64::from(i) / 30.0;
        session.feed(key, now);
        out.clear();
        session.frame(now, &mut out);
        bytes += out.len();
        fold(&out);
    }
    let what = if key == b"w" { "walking" } else { "turning" };
    let rep = if rep { "REP" } else { "no REP" };
    println!(
        "{depth} {cols}x{rows}, tolerance {tolerance}, {rep}: {bytes} bytes in 39 frames of {what}, FNV-1a {hash:016x}"
    );
}
