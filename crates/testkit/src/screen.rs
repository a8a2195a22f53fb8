//! What a vt100 emulator shows, read back as a [`Frame`]: each cell's first glyph (a space where it
//! has none) and its colours, for tests and benches that compare the terminal's screen with the
//! frame a session drew.

use mazewalk_term::frame::{Cell, Color, Frame};

/// A vt100 colour as a frame's colour.
pub fn color(color: vt100::Color) -> Color {
    match color {
        vt100::Color::Default => Color::Default,
        vt100::Color::Idx(i) => Color::Indexed(i),
        vt100::Color::Rgb(r, g, b) => Color::Rgb(r, g, b),
    }
}

/// The emulator's whole screen as a frame of its size.
pub fn screen_frame(terminal: &vt100::Parser) -> Frame {
    let screen = terminal.screen();
    let (rows, cols) = (screen.size().0.get(), screen.size().1.get());
    let mut frame = Frame::new(cols.into(), rows.into());
    for y in 0..rows {
        for x in 0..cols {
            let Some(cell) = screen.cell(y, x) else { continue };
            let ch = cell.contents().chars().next().unwrap_or(' ');
            frame.set(x.into(), y.into(), Cell { ch, fg: color(cell.fgcolor()), bg: color(cell.bgcolor()) });
        }
    }
    frame
}
