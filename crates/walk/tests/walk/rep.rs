//! Issue #42: runs of one look go as REP (`CSI n b`) to a terminal that has it. The session asks
//! before its first frame ([`REP_PROBE`]); a terminal with REP (vt100, as xterm) answers that the
//! cursor moved two cells and the frames send runs as REP from then on; one without it (answering
//! one cell), or an answer that is not one to the probe (row 1: how xterm sends Alt-F3), leaves it
//! off. Either way the terminal shows every frame exactly.

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

/// How the terminal answers the cursor position query.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Answer {
    /// Where the cursor is: vt100 has REP.
    Truly,
    /// As a terminal without REP would: one cell left of where vt100's cursor is.
    WithoutRep,
    /// Row 1 and the column vt100 says (not an answer to the probe).
    RowOne,
}

/// Walks forward for two seconds in `depth`, exactly (tolerance 0), the terminal answering the
/// probe as `answer`; checks the screen after every frame; returns the bytes and the REPs sent.
fn walk(depth: ColorDepth, answer: Answer) -> (usize, usize) {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("a start cell");
    let session_options =
        SessionOptions { flow_control: false, color_tolerance: 0, ..SessionOptions::default() };
    let mut session = Session::new(app, COLS, ROWS, session_options);
    let nz = |n: u16| std::num::NonZeroU16::new(n).expect("not zero");
    let mut parser = vt100::Parser::new(nz(ROWS), nz(COLS), 0);
    let (mut bytes, mut reps) = (0, 0);
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
            let (row, col) = match answer {
                Answer::Truly => (row + 1, col + 1),
                Answer::WithoutRep => (row + 1, col),
                Answer::RowOne => (1, col + 1),
            };
            session.feed(format!("\x1b[{row};{col}R").as_bytes(), now);
            rest = &rest[at + 4..];
        }
        parser.process(rest);
        assert!(
            shown(&screen_frame(&parser), Charset::Half) == shown(session.screen(), Charset::Half),
            "{depth} {answer:?}: frame {i} not shown exactly"
        );
        bytes += out.len();
        // REP: ESC [ digits b (nothing else the encoder sends ends in `b`), past the probe's own.
        let frame = if i == 0 { &out[REP_PROBE.len()..] } else { &out[..] };
        let is_rep =
            |s: &[u8]| s.first() == Some(&b'[') && s[1..].iter().find(|b| !b.is_ascii_digit()) == Some(&b'b');
        reps += frame.split(|&b| b == 0x1b).filter(|s| is_rep(s)).count();
    }
    (bytes, reps)
}

#[test]
fn runs_go_as_rep_only_to_a_terminal_that_said_it_has_it() {
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let (with, reps) = walk(depth, Answer::Truly);
        let (without, none) = walk(depth, Answer::WithoutRep);
        let (row_one, none_either) = walk(depth, Answer::RowOne);
        eprintln!("{depth}: {with} bytes with REP ({reps} of them), {without} without");
        assert!(reps > 0, "{depth}: REP never used");
        assert!(with < without, "{depth}: REP did not save bytes: {with} vs {without}");
        assert_eq!((none, none_either), (0, 0), "{depth}: REP to a terminal that did not say it has it");
        assert_eq!(without, row_one, "{depth}: an answer of row 1 is no answer");
    }
}
