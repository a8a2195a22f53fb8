//! Issue #42: runs of one look go as REP (`CSI n b`) to a terminal that has it. The session asks
//! before its first frame ([`REP_PROBE`]), after a space and after `▀`; a terminal that repeats any
//! glyph (vt100, as xterm) answers that the cursor moved two cells, then three, and the frames send
//! runs of any glyph as REP from then on; one that repeats only ASCII (tmux: its second answer one
//! cell) gets REP after ASCII glyphs only, never after a block; one without it (one cell each), or
//! an answer that is not one to the probe (row 1: how xterm sends Alt-F3), leaves it off. Either way
//! the terminal shows every frame exactly.

use mazewalk_maze as maze;
use mazewalk_render::quality::shown;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::caps::REP_PROBE;
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame};
use mazewalk_walk::{App, Session, SessionOptions};

const COLS: u16 = 120;
const ROWS: u16 = 40;

/// The vt100 screen as a frame (its glyphs and colours).
fn screen_frame(parser: &vt100::Parser) -> Frame {
    let color = |c: vt100::Color| match c {
        vt100::Color::Default => Color::Default,
        vt100::Color::Idx(i) => Color::Indexed(i),
        vt100::Color::Rgb(r, g, b) => Color::Rgb(r, g, b),
    };
    let screen = parser.screen();
    let mut frame = Frame::new(COLS.into(), ROWS.into());
    for y in 0..ROWS {
        for x in 0..COLS {
            let cell = screen.cell(y, x).expect("on screen");
            let ch = cell.contents().chars().next().unwrap_or(' ');
            frame.set(x.into(), y.into(), Cell { ch, fg: color(cell.fgcolor()), bg: color(cell.bgcolor()) });
        }
    }
    frame
}

/// How the terminal answers the cursor position queries.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Answer {
    /// Where the cursor is: vt100 repeats any glyph.
    Truly,
    /// As tmux: the space repeated (where vt100's cursor is), the block not (column 2).
    AsciiOnly,
    /// As a terminal without REP would: one cell written for each question (column 2).
    WithoutRep,
    /// Row 1 and the column vt100 says (not an answer to the probe).
    RowOne,
}

impl Answer {
    /// The report for vt100's cursor at 1-based (`row`, `col`).
    fn report(self, row: u16, col: u16) -> (u16, u16) {
        match self {
            Answer::Truly => (row, col),
            Answer::AsciiOnly if row == 3 => (row, 2),
            Answer::AsciiOnly => (row, col),
            Answer::WithoutRep => (row, 2),
            Answer::RowOne => (1, col),
        }
    }
}

/// What a walk sent: bytes, REPs, and REPs right after a glyph that is not ASCII.
#[derive(Clone, Copy, Debug, Default)]
struct Sent {
    bytes: usize,
    reps: usize,
    block_reps: usize,
}

/// Walks forward for two seconds in `depth`, exactly (tolerance 0), the terminal answering the
/// probe as `answer`; checks the screen after every frame; returns what was sent.
fn walk(depth: ColorDepth, answer: Answer) -> Sent {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("a start cell");
    let session_options =
        SessionOptions { flow_control: false, color_tolerance: 0, ..SessionOptions::default() };
    let mut session = Session::new(app, COLS, ROWS, session_options);
    let nz = |n: u16| std::num::NonZeroU16::new(n).expect("not zero");
    let mut parser = vt100::Parser::new(nz(ROWS), nz(COLS), 0);
    let mut sent = Sent::default();
    let mut out = Vec::new();
    for i in 0..60 {
        let now = f64::from(i) / 30.0;
        session.feed(b"w", now);
        out.clear();
        if !session.frame(now, &mut out) {
            continue;
        }
        if i == 0 {
            assert!(out.starts_with(REP_PROBE), "the probe goes before the first frame");
        }
        let mut rest = &out[..];
        while let Some(at) = rest.windows(4).position(|w| w == b"\x1b[6n") {
            parser.process(&rest[..at + 4]);
            let (row, col) = parser.screen().cursor_position();
            let (row, col) = answer.report(row + 1, col + 1);
            session.feed(format!("\x1b[{row};{col}R").as_bytes(), now);
            rest = &rest[at + 4..];
        }
        parser.process(rest);
        assert!(
            shown(&screen_frame(&parser), Charset::Half) == shown(session.screen(), Charset::Half),
            "{depth} {answer:?}: frame {i} not shown exactly"
        );
        sent.bytes += out.len();
        // REP: ESC [ digits b (nothing else the encoder sends ends in `b`), past the probe's own.
        let frame = if i == 0 { &out[REP_PROBE.len()..] } else { &out[..] };
        let is_rep =
            |s: &[u8]| s.first() == Some(&b'[') && s[1..].iter().find(|b| !b.is_ascii_digit()) == Some(&b'b');
        for (at, _) in frame.iter().enumerate().filter(|&(at, &b)| b == 0x1b && is_rep(&frame[at + 1..])) {
            sent.reps += 1;
            // The glyph REP repeats is what comes just before it: a UTF-8 sequence ends in a byte ≥ 0x80.
            assert!(at > 0, "REP first in a frame");
            sent.block_reps += usize::from(frame[at - 1] >= 0x80);
        }
    }
    sent
}

#[test]
fn runs_go_as_rep_only_to_a_terminal_that_said_it_has_it() {
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let any = walk(depth, Answer::Truly);
        let ascii = walk(depth, Answer::AsciiOnly);
        let without = walk(depth, Answer::WithoutRep);
        let row_one = walk(depth, Answer::RowOne);
        eprintln!(
            "{depth}: {} bytes with REP after any glyph ({} REPs, {} after a block), {} after ASCII only ({} REPs), {} without",
            any.bytes, any.reps, any.block_reps, ascii.bytes, ascii.reps, without.bytes
        );
        assert!(any.block_reps > 0, "{depth}: REP never used after a block: {any:?}");
        assert!(ascii.reps > 0, "{depth}: REP never used after ASCII: {ascii:?}");
        assert_eq!(ascii.block_reps, 0, "{depth}: REP after a block to a terminal that repeats only ASCII");
        assert!(any.bytes < ascii.bytes, "{depth}: block REP did not save bytes: {any:?} vs {ascii:?}");
        assert!(ascii.bytes < without.bytes, "{depth}: REP did not save bytes: {ascii:?} vs {without:?}");
        assert_eq!(
            (without.reps, row_one.reps),
            (0, 0),
            "{depth}: REP to a terminal that did not say it has it"
        );
        assert_eq!(without.bytes, row_one.bytes, "{depth}: an answer of row 1 is no answer");
    }
}
