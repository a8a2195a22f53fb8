//! A terminal's last screen, from the bytes it was sent: `screen_dump COLSxROWS < bytes` feeds them
//! to the `vt100` emulator (the one the end-to-end tests read screens with) and prints the screen
//! as text with an SGR colour sequence before every cell — every cell, blank or not, in its own
//! colours, so a picture can be drawn from it exactly (`scripts/screen_png.py`; `tmux capture-pane
//! -e` leaves out the background of erased cells). For the README's whole-screen pictures
//! (`scripts/serve_pictures.py`).
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example screen_dump 100x30 < session.bytes > screen.txt
//! ```

use std::io::{Read, Write};

fn sgr(color: vt100::Color, fg: bool) -> String {
    let (base, ext) = if fg { (39, 38) } else { (49, 48) };
    match color {
        vt100::Color::Default => format!("{base}"),
        vt100::Color::Idx(n) => format!("{ext};5;{n}"),
        vt100::Color::Rgb(r, g, b) => format!("{ext};2;{r};{g};{b}"),
    }
}

fn main() -> std::io::Result<()> {
    let size = std::env::args().nth(1).unwrap_or_else(|| "100x30".into());
    let (cols, rows) = size
        .split_once('x')
        .and_then(|(c, r)| Some((c.parse::<u16>().ok()?, r.parse::<u16>().ok()?)))
        .filter(|&(c, r)| c > 0 && r > 0)
        .expect("COLSxROWS, e.g. 100x30");
    let mut bytes = Vec::new();
    std::io::stdin().read_to_end(&mut bytes)?;
    let nz = |n: u16| std::num::NonZeroU16::new(n).expect("checked");
    let mut parser = vt100::Parser::new(nz(rows), nz(cols), 0);
    parser.process(&bytes);
    let screen = parser.screen();
    let mut out = String::new();
    for row in 0..rows {
        for col in 0..cols {
            let Some(cell) = screen.cell(row, col) else { continue };
            let (mut fg, mut bg) = (cell.fgcolor(), cell.bgcolor());
            if cell.inverse() {
                std::mem::swap(&mut fg, &mut bg);
            }
            let text = cell.contents();
            let text = if text.is_empty() { " " } else { text };
            out += &format!("\x1b[{};{}m{text}", sgr(fg, true), sgr(bg, false));
        }
        out += "\x1b[0m\n";
    }
    std::io::stdout().write_all(out.as_bytes())
}
