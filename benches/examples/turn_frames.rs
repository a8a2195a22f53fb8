//! A first paint and 39 frames of turning (`←` 30 times a second) through the walk's session, for
//! callgrind's count of what the encoder spends on them (issue #42): no link, no clock.
//!
//! ```sh
//! cargo build --release -p mazewalk-bench --example turn_frames
//! valgrind --tool=callgrind ./target/release/examples/turn_frames truecolor   # COLS ROWS TOLERANCE REP KEY CHARSET optional
//! callgrind_annotate --inclusive=yes callgrind.out.* | grep 'Encoder::encode \['
//! ```
//!
//! REP: `rep` answers the session's questions as a terminal that repeats only ASCII glyphs does
//! (tmux: runs of blanks go as `CSI n b`), `anyrep` as one that repeats any glyph (xterm: runs of
//! blocks too), `norep` (the default) as one without. KEY: `turn` (the default, `←`) or `walk` (`W`). It prints
//! the bytes of the 39 frames and a hash of all the output, first paint included: two builds that
//! print the same line sent the same bytes. CHARSET: `half` (the default), `quad`, `sextant` or `ascii`
//! (which the walk sends without block glyphs).

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
    let rep = arg(4, "norep");
    let key: &[u8] = if arg(5, "turn") == "walk" { b"w" } else { b"\x1b[D" };
    let charset: Charset = arg(6, "half").parse().expect("charset");
    let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
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
    // The answers to the REP probe before the first frame: after a space two cells written (REP)
    // or one; after `▀` and two repeats three cells (REP after any glyph) or one.
    session.feed(
        match rep.as_str() {
            "anyrep" => b"\x1b[2;3R\x1b[3;4R",
            "rep" => b"\x1b[2;3R\x1b[3;2R",
            _ => b"\x1b[2;2R\x1b[3;2R",
        },
        0.0,
    );
    for i in 1..40 {
        let now = f64::from(i) / 30.0;
        session.feed(key, now);
        out.clear();
        session.frame(now, &mut out);
        bytes += out.len();
        fold(&out);
    }
    let what = if key == b"w" { "walking" } else { "turning" };
    let rep = match rep.as_str() {
        "anyrep" => "REP after any glyph",
        "rep" => "REP after ASCII",
        _ => "no REP",
    };
    println!(
        "{depth} {cols}x{rows} {charset}, tolerance {tolerance}, {rep}: {bytes} bytes in 39 frames of {what}, FNV-1a {hash:016x}"
    );
}
