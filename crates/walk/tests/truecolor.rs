//! Truecolor wherever the terminal can show it (issue #33): fake terminals answer the session's
//! questions ([`Session::ask_truecolor`]) through its bytes, as they would over a pty or an SSH
//! channel. The first frame goes out at the environment's depth; a yes switches to truecolor with one
//! full repaint; no, silence, garbage, or an answer after the questions are over change nothing.

use mazewalk_maze as maze;
use mazewalk_render::RenderOptions;
use mazewalk_term::caps::TRUECOLOR_QUERY;
use mazewalk_term::frame::ColorDepth;
use mazewalk_walk::flow::QUERY;
use mazewalk_walk::{App, Session, SessionOptions};

const DA_ANSWER: &[u8] = b"\x1b[?62;22c";
/// xterm's answers: DECRQSS with the RGB pen, XTGETTCAP with RGB = 8.
const XTERM_DECRQSS: &[u8] = b"\x1bP1$r0;48:2::1:2:3m\x1b\\";
const XTERM_XTGETTCAP: &[u8] = b"\x1bP1+r524742=38\x1b\\";
/// kitty's: RGB unknown, Tc known, and the pen.
const KITTY: &[u8] = b"\x1bP0+r524742\x1b\\\x1bP1+r5463\x1b\\\x1bP1$r0;48:2:1:2:3m\x1b\\";

fn session(depth: ColorDepth, flow_control: bool) -> Session {
    let options = RenderOptions { color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().unwrap(), options, 0.0).unwrap();
    Session::new(app, 60, 20, SessionOptions { flow_control, ..SessionOptions::default() })
}

/// A session at 256 colours that asked, and its first frame: the bytes sent so far.
fn asked() -> (Session, Vec<u8>) {
    let mut s = session(ColorDepth::Ansi256, true);
    let mut out = Vec::new();
    s.ask_truecolor(&mut out);
    assert!(s.frame(0.0, &mut out), "the first frame does not wait for an answer");
    (s, out)
}

/// Whether `bytes` hold 24-bit colour codes.
fn has_rgb(bytes: &[u8]) -> bool {
    bytes.windows(5).any(|w| w == b"38;2;" || w == b"48;2;")
}

/// Whether `bytes` hold a full repaint (the encoder clears the screen first).
fn repaints(bytes: &[u8]) -> bool {
    bytes.windows(4).any(|w| w == b"\x1b[2J")
}

/// The next frame at `now`, its bytes.
fn next(s: &mut Session, now: f64) -> Vec<u8> {
    let mut out = Vec::new();
    s.frame(now, &mut out);
    out
}

#[test]
fn the_questions_go_before_the_first_frame_which_keeps_the_environments_depth() {
    let (s, out) = asked();
    assert!(out.starts_with(TRUECOLOR_QUERY), "{:?}", String::from_utf8_lossy(&out[..40]));
    assert!(!has_rgb(&out[TRUECOLOR_QUERY.len()..]), "the first frame is in 256 colours");
    assert_eq!(s.color_depth(), ColorDepth::Ansi256);
    // Without flow control, the questions carry their own fence (the frames send none).
    let mut s = session(ColorDepth::Ansi256, false);
    let mut out = Vec::new();
    s.ask_truecolor(&mut out);
    assert_eq!(out, [TRUECOLOR_QUERY, QUERY].concat());
}

#[test]
fn a_yes_switches_to_truecolor_with_one_full_repaint() {
    for (terminal, answer) in
        [("xterm, DECRQSS", XTERM_DECRQSS), ("xterm, XTGETTCAP", XTERM_XTGETTCAP), ("kitty", KITTY)]
    {
        let (mut s, _) = asked();
        s.feed(answer, 0.1);
        assert_eq!(s.color_depth(), ColorDepth::TrueColor, "{terminal}");
        let repaint = next(&mut s, 0.1);
        assert!(repaints(&repaint) && has_rgb(&repaint), "{terminal}: a full repaint in truecolor");
        // Both questions answered yes (xterm answers both): still one repaint.
        s.feed(XTERM_XTGETTCAP, 0.12);
        s.feed(DA_ANSWER, 0.15);
        s.feed(DA_ANSWER, 0.2);
        assert!(!repaints(&next(&mut s, 0.3)), "{terminal}: once");
    }
}

#[test]
fn no_silence_and_garbage_keep_the_environments_depth() {
    let long = [b"\x1bP1$r0;" as &[u8], &[b'1'; 600], b";48:2::1:2:3m\x1b\\"].concat();
    let answers: [(&str, &[u8]); 7] = [
        ("xterm without direct colour", b"\x1bP1$r0;48:5:16m\x1b\\\x1bP1+r524742=2D31\x1b\\"),
        ("silence (tmux, Alacritty)", b""),
        ("invalid (WezTerm's DECRQSS, xterm's unknown name)", b"\x1bP0$r\x1b\\\x1bP0+r\x1b\\"),
        ("not hex", b"\x1bP1+rRGB=8\x1b\\"),
        ("another colour", b"\x1bP1$r0;48:2::7:7:7m\x1b\\"),
        ("cancelled", b"\x1bP1$r0;48:2::1:2:3m\x18"),
        ("too long", &long),
    ];
    for (terminal, answer) in answers {
        let (mut s, _) = asked();
        s.feed(answer, 0.1);
        s.feed(DA_ANSWER, 0.15); // the first frame is on screen: the questions are over
        assert_eq!(s.color_depth(), ColorDepth::Ansi256, "{terminal}");
        let out = next(&mut s, 0.2);
        assert!(!repaints(&out) && !has_rgb(&out), "{terminal}: nothing changes");
        assert!(!s.is_over(), "{terminal}: no key came of it");
    }
}

#[test]
fn an_answer_split_across_reads_counts() {
    for answer in [XTERM_DECRQSS, KITTY] {
        for cut in 1..answer.len() {
            let (mut s, _) = asked();
            s.feed(&answer[..cut], 0.1);
            s.feed(&answer[cut..], 0.12);
            assert_eq!(s.color_depth(), ColorDepth::TrueColor, "cut at {cut}");
        }
        // one byte a read, a pause before the terminator's last byte: no Esc key (it would quit)
        let (mut s, _) = asked();
        let (body, last) = answer.split_at(answer.len() - 1);
        for (i, byte) in body.iter().enumerate() {
            s.feed(&[*byte], 0.1 + 0.001 * i as f64);
        }
        next(&mut s, 1.0);
        s.feed(last, 1.0);
        assert_eq!(s.color_depth(), ColorDepth::TrueColor);
        assert!(!s.is_over(), "the terminator's ESC is not the Esc key");
    }
}

#[test]
fn answers_after_the_start_or_unasked_change_nothing() {
    // after the first frame's device attributes: a pasted or forged answer
    let (mut s, _) = asked();
    s.feed(DA_ANSWER, 0.1);
    s.feed(XTERM_DECRQSS, 0.2);
    s.feed(XTERM_XTGETTCAP, 5.0);
    assert_eq!(s.color_depth(), ColorDepth::Ansi256);
    // a terminal that answers no query at all: the questions close after the reply timeout
    let (mut s, _) = asked();
    next(&mut s, 0.5);
    s.feed(XTERM_DECRQSS, 0.1 + mazewalk_walk::flow::ACK_TIMEOUT + 0.01);
    assert_eq!(s.color_depth(), ColorDepth::Ansi256);
    // never asked (a forced depth, or the environment said): never switched
    let mut s = session(ColorDepth::Ansi16, true);
    next(&mut s, 0.0);
    s.feed(XTERM_DECRQSS, 0.05);
    assert_eq!(s.color_depth(), ColorDepth::Ansi16);
}
