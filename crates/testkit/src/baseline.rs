//! Yardsticks for the frame encoder, shared by `benches/encoder.rs` and the term crate's
//! `tests/term_encoder.rs`: a naive full repaint and a lower bound on what any encoding must send.
//! Neither is part of the product.

use std::io::Write as _;

use mazewalk_term::frame::{Cell, Color, Frame};

/// The naive baseline: every row positioned absolutely (`CUP`), every cell with its full SGR (foreground
/// and background, each in its shortest code), then a reset.
pub fn full_repaint(frame: &Frame, out: &mut Vec<u8>) {
    for y in 0..frame.height() {
        if y == 0 {
            out.extend_from_slice(b"\x1b[H");
        } else {
            write!(out, "\x1b[{}H", y + 1).expect("writing to a Vec");
        }
        for cell in frame.row(y).unwrap_or(&[]) {
            out.extend_from_slice(b"\x1b[");
            push_color(out, cell.fg, 30);
            out.push(b';');
            push_color(out, cell.bg, 40);
            out.push(b'm');
            out.extend_from_slice(cell.ch.encode_utf8(&mut [0; 4]).as_bytes());
        }
    }
    out.extend_from_slice(b"\x1b[0m");
}

/// The SGR parameters of `color` as a foreground (`base` 30) or a background (`base` 40).
fn push_color(out: &mut Vec<u8>, color: Color, base: u8) {
    match color {
        Color::Default => push_u8(out, base + 9),
        Color::Indexed(n @ 0..=7) => push_u8(out, base + n),
        Color::Indexed(n @ 8..=15) => push_u8(out, base + 60 + (n - 8)),
        Color::Indexed(n) => {
            push_u8(out, base + 8);
            out.extend_from_slice(b";5;");
            push_u8(out, n);
        }
        Color::Rgb(r, g, b) => {
            push_u8(out, base + 8);
            out.extend_from_slice(b";2");
            for c in [r, g, b] {
                out.push(b';');
                push_u8(out, c);
            }
        }
    }
}

/// `n` in decimal, without `write!`'s formatting machinery (this runs per cell in a timed benchmark).
fn push_u8(out: &mut Vec<u8>, n: u8) {
    if n >= 100 {
        out.push(b'0' + n / 100);
    }
    if n >= 10 {
        out.push(b'0' + n / 10 % 10);
    }
    out.push(b'0' + n % 10);
}

/// A lower bound for the bytes of any encoding that turns a screen showing `shown` into one showing
/// `frame`, each cell within `tolerance` steps of 0.01 in OKLab between truecolor colours
/// ([`Cell::looks_within`]): the UTF-8 bytes of the non-blank glyphs that must change. `None` (an unknown screen, or one of
/// another size) means a full paint: every glyph. Blanks count nothing (an erasure may cover any number
/// of them), and a block glyph counts the cheaper of itself and its [`Cell::inverse`].
pub fn lower_bound(shown: Option<&Frame>, frame: &Frame, tolerance: u8) -> usize {
    let bytes = |c: &Cell| if c.ch == ' ' { 0 } else { c.ch.len_utf8() };
    let glyph_bytes = |c: &Cell| {
        let c = c.canonical();
        c.inverse().map_or(bytes(&c), |inverse| bytes(&c).min(bytes(&inverse)))
    };
    let same_size = |s: &&Frame| (s.width(), s.height()) == (frame.width(), frame.height());
    match shown.filter(same_size) {
        None => frame.cells().iter().map(glyph_bytes).sum(),
        Some(shown) => (shown.cells().iter().zip(frame.cells()))
            .filter(|(shown, cell)| !shown.looks_within(cell, tolerance))
            .map(|(_, cell)| glyph_bytes(cell))
            .sum(),
    }
}
