//! Colours: the SGR (`ESC [ … m`) sequences that set the foreground and background, each colour in its
//! shortest code (`30–37`/`40–47` and `90–97`/`100–107` for the 16 ANSI colours, `38;5;n` for the
//! 256-colour palette, `38;2;r;g;b` for truecolor, `39`/`49` for the default), both changes in one
//! sequence, or a reset (`\x1b[0;…m`) when that is shorter.

use super::Pen;
use crate::frame::{Color, PackedCell, PackedColor, code_len};

/// Reset all SGR attributes (colours back to the terminal's defaults).
pub(super) const SGR_RESET: &[u8] = b"\x1b[0m";

/// Which of a cell's colours an SGR code sets.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layer {
    Fg,
    Bg,
}

/// The colours a cell needs on screen: no foreground for a space, no background for a full block.
fn shown_colors(cell: &PackedCell) -> (Option<PackedColor>, Option<PackedColor>) {
    ((cell.ch != ' ').then_some(cell.fg), (cell.ch != '█').then_some(cell.bg))
}

/// A colour change from a pen, priced: setting `fg` and `bg` (`None`: don't care) in the shorter of
/// the two forms, just the changed colours or a reset followed by the non-default ones. The encoder
/// prices candidate cells and routes with it and writes only the one it keeps.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sgr {
    fg: Option<PackedColor>,
    bg: Option<PackedColor>,
    form: Form,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Form {
    /// Nothing changes.
    Keep,
    /// `ESC [ p;p m` with the changed colours, this many bytes.
    Plain(usize),
    /// `ESC [ 0;p;p m` (or `ESC [ m`), this many bytes.
    Reset(usize),
}

impl Sgr {
    /// No change.
    pub(super) const KEEP: Sgr = Sgr { fg: None, bg: None, form: Form::Keep };

    /// The change from `pen` to `fg` and `bg`.
    #[inline(always)]
    pub(super) fn new(pen: &Pen, fg: Option<PackedColor>, bg: Option<PackedColor>) -> Sgr {
        // Straight-line: the encoder prices several of these for every changed cell.
        let change = |want: Option<PackedColor>, pen: Option<PackedColor>, layer| match want {
            Some(c) if pen != Some(c) => (1, color_len(c, layer)),
            _ => (0, 0),
        };
        let ((n_fg, len_fg), (n_bg, len_bg)) = (change(fg, pen.fg, Layer::Fg), change(bg, pen.bg, Layer::Bg));
        let n = n_fg + n_bg;
        let form = if n == 0 {
            Form::Keep
        } else {
            // ESC [ p;p m: codes joined by `;`.
            let plain = 3 + n - 1 + len_fg + len_bg;
            let is_default = |c: Option<PackedColor>| c.is_none_or(|c| c == PackedColor::DEFAULT);
            if !is_default(fg) && !is_default(bg) {
                // Both colours non-default: the reset form repeats both and adds `0;`, never shorter.
                Form::Plain(plain)
            } else {
                // ESC [ 0;p;p m, or ESC [ m when both are the defaults.
                let param = |c: Option<PackedColor>, layer| match c {
                    Some(c) if c != PackedColor::DEFAULT => 1 + color_len(c, layer),
                    _ => 0,
                };
                let params = param(fg, Layer::Fg) + param(bg, Layer::Bg);
                let reset = 3 + if params > 0 { 1 + params } else { 0 };
                if reset < plain { Form::Reset(reset) } else { Form::Plain(plain) }
            }
        };
        Sgr { fg, bg, form }
    }

    /// The change to `cell`'s shown colours.
    #[inline]
    pub(super) fn to_cell(pen: &Pen, cell: &PackedCell) -> Sgr {
        let (fg, bg) = shown_colors(cell);
        Sgr::new(pen, fg, bg)
    }

    /// Its bytes.
    #[inline]
    pub(super) fn len(&self) -> usize {
        match self.form {
            Form::Keep => 0,
            Form::Plain(len) | Form::Reset(len) => len,
        }
    }

    /// The pen after it, without writing it (for pricing).
    #[inline]
    pub(super) fn apply(&self, pen: &mut Pen) {
        match self.form {
            Form::Keep | Form::Plain(_) => {
                pen.fg = self.fg.or(pen.fg);
                pen.bg = self.bg.or(pen.bg);
            }
            Form::Reset(_) => {
                pen.fg = Some(self.fg.unwrap_or(PackedColor::DEFAULT));
                pen.bg = Some(self.bg.unwrap_or(PackedColor::DEFAULT));
            }
        }
    }

    /// Writes it (the pen must be the one it was priced from) and updates the pen. No change, the
    /// usual case (most cells a diff writes keep the pen's colours), inlined; a sequence out of line.
    #[inline]
    pub(super) fn write(&self, out: &mut Vec<u8>, pen: &mut Pen) {
        if self.form != Form::Keep {
            self.write_change(out, pen);
        }
    }

    /// [`Sgr::write`] of a change.
    #[inline(never)]
    fn write_change(&self, out: &mut Vec<u8>, pen: &mut Pen) {
        match self.form {
            Form::Keep => {}
            Form::Reset(_) => write_sgr_reset(out, pen, self.fg, self.bg),
            Form::Plain(len) => {
                let mut seq = Seq::start();
                let fg = self.fg.filter(|&c| pen.fg != Some(c));
                if let Some(c) = fg {
                    seq.color(c, Layer::Fg);
                }
                if let Some(c) = self.bg.filter(|&c| pen.bg != Some(c)) {
                    if fg.is_some() {
                        seq.push(b";");
                    }
                    seq.color(c, Layer::Bg);
                }
                seq.push(b"m");
                debug_assert_eq!(seq.len, len);
                out.extend_from_slice(seq.bytes());
                self.apply(pen);
            }
        }
    }
}

/// Sets the colours to `fg` and `bg` (`None`: don't care) in the shortest form, if they changed.
pub(super) fn write_sgr(out: &mut Vec<u8>, pen: &mut Pen, fg: Option<PackedColor>, bg: Option<PackedColor>) {
    Sgr::new(pen, fg, bg).write(out, pen);
}

/// Resets SGR and sets `fg` and `bg` (`None`: leave default) in one sequence: `\x1b[m`, `\x1b[0;41m`…
pub(super) fn write_sgr_reset(
    out: &mut Vec<u8>,
    pen: &mut Pen,
    fg: Option<PackedColor>,
    bg: Option<PackedColor>,
) {
    let (fg, bg) = (fg.unwrap_or(PackedColor::DEFAULT), bg.unwrap_or(PackedColor::DEFAULT));
    let mut seq = Seq::start();
    let colors = [(fg, Layer::Fg), (bg, Layer::Bg)];
    let mut non_default = colors.iter().filter(|(c, _)| *c != PackedColor::DEFAULT).peekable();
    if non_default.peek().is_some() {
        seq.push(b"0");
        for &(color, layer) in non_default {
            seq.push(b";");
            seq.color(color, layer);
        }
    }
    seq.push(b"m");
    out.extend_from_slice(seq.bytes());
    pen.fg = Some(fg);
    pen.bg = Some(bg);
}

/// An SGR sequence assembled on the stack and appended in one copy: one capacity check a sequence,
/// not one a digit (the encoder writes one for most changed cells of a truecolor frame).
struct Seq {
    /// The longest, `ESC [ 0 ; 38;2;r;g;b ; 48;2;r;g;b m`, is 38 bytes.
    buf: [u8; 40],
    len: usize,
}

impl Seq {
    fn start() -> Seq {
        let mut buf = [0; 40];
        buf[..2].copy_from_slice(b"\x1b[");
        Seq { buf, len: 2 }
    }

    fn push(&mut self, bytes: &[u8]) {
        self.buf[self.len..self.len + bytes.len()].copy_from_slice(bytes);
        self.len += bytes.len();
    }

    /// `n` in decimal: three bytes copied from [`DECIMAL`], of which `n`'s digits count.
    fn num(&mut self, n: u8) {
        let [digits @ .., count] = DECIMAL[usize::from(n)];
        self.buf[self.len..self.len + 3].copy_from_slice(&digits);
        self.len += usize::from(count);
    }

    /// The shortest SGR parameters for `color` as foreground or background.
    fn color(&mut self, color: PackedColor, layer: Layer) {
        let base = if layer == Layer::Fg { 30 } else { 40 };
        match color.unpack() {
            Color::Default => self.num(base + 9),
            Color::Indexed(n @ 0..=7) => self.num(base + n),
            Color::Indexed(n @ 8..=15) => self.num(base + 60 + (n - 8)),
            Color::Indexed(n) => {
                self.num(base + 8);
                self.push(b";5;");
                self.num(n);
            }
            Color::Rgb(r, g, b) => {
                self.num(base + 8);
                self.push(b";2;");
                self.num(r);
                self.push(b";");
                self.num(g);
                self.push(b";");
                self.num(b);
            }
        }
    }

    fn bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
}

/// The decimal digits of 0–255, padded to three bytes, then their count.
const DECIMAL: [[u8; 4]; 256] = {
    let mut table = [[0; 4]; 256];
    let mut n = 0;
    while n < 256 {
        let (hundreds, tens, ones) =
            (b'0' + (n / 100) as u8, b'0' + (n / 10 % 10) as u8, b'0' + (n % 10) as u8);
        table[n] = match n {
            0..=9 => [ones, 0, 0, 1],
            10..=99 => [tens, ones, 0, 2],
            _ => [hundreds, tens, ones, 3],
        };
        n += 1;
    }
    table
};

/// The length of [`Seq::color`]'s parameters for `color`.
#[inline]
fn color_len(color: PackedColor, layer: Layer) -> usize {
    match color.unpack() {
        Color::Default | Color::Indexed(0..=7) => 2,
        Color::Indexed(8..=15) => 2 + usize::from(layer == Layer::Bg), // 90–97, 100–107
        // 38;5;n and 38;2;r;g;b: as the search for the shortest code within the tolerance counts
        _ => code_len(color),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sgr(from: (Option<Color>, Option<Color>), fg: Option<Color>, bg: Color) -> (String, Pen) {
        let mut out = Vec::new();
        let mut pen = Pen {
            cursor: None,
            fg: from.0.map(PackedColor::pack),
            bg: from.1.map(PackedColor::pack),
            blocks: true,
        };
        write_sgr(&mut out, &mut pen, fg.map(PackedColor::pack), Some(PackedColor::pack(bg)));
        (String::from_utf8(out).unwrap(), pen)
    }

    /// The price of a colour change is the length of what is written, for every palette entry and
    /// truecolor colours of every count of digits, as ink and as paper (the search for the shortest
    /// code within the tolerance counts by the same lengths).
    #[test]
    fn a_colour_is_priced_at_the_bytes_it_is_written_in() {
        let values = [0u8, 9, 10, 99, 100, 255];
        let rgb = values
            .iter()
            .flat_map(|&r| values.iter().flat_map(move |&g| values.map(|b| Color::Rgb(r, g, b))));
        for color in (0..=255).map(Color::Indexed).chain(rgb).chain([Color::Default]) {
            for layer in [Layer::Fg, Layer::Bg] {
                let mut seq = Seq::start();
                seq.color(PackedColor::pack(color), layer);
                assert_eq!(seq.len - 2, color_len(PackedColor::pack(color), layer), "{color:?}");
            }
        }
    }

    #[test]
    fn a_sequence_spells_every_channel_value_and_holds_the_longest_reset() {
        for n in 0..=255u8 {
            let mut seq = Seq::start();
            seq.num(n);
            assert_eq!(seq.bytes(), format!("\x1b[{n}").as_bytes());
        }
        let white = Some(PackedColor::pack(Color::Rgb(255, 255, 255)));
        let (mut out, mut pen) = (Vec::new(), Pen::UNKNOWN);
        write_sgr_reset(&mut out, &mut pen, white, Some(PackedColor::pack(Color::Rgb(100, 200, 255))));
        assert_eq!(out, b"\x1b[0;38;2;255;255;255;48;2;100;200;255m");
    }

    #[test]
    fn sgr_uses_the_shortest_code_for_each_colour_kind() {
        let d = Some(Color::Default);
        let cases = [
            (Color::Indexed(1), "\x1b[31m"),
            (Color::Indexed(9), "\x1b[91m"),
            (Color::Indexed(100), "\x1b[38;5;100m"),
            (Color::Rgb(1, 2, 3), "\x1b[38;2;1;2;3m"),
        ];
        for (color, want) in cases {
            assert_eq!(sgr((d, d), Some(color), Color::Default).0, want);
        }
        assert_eq!(sgr((d, d), None, Color::Indexed(2)).0, "\x1b[42m");
        assert_eq!(sgr((d, d), None, Color::Indexed(10)).0, "\x1b[102m");
        assert_eq!(sgr((d, d), None, Color::Indexed(200)).0, "\x1b[48;5;200m");
        assert_eq!(sgr((d, d), None, Color::Rgb(9, 8, 7)).0, "\x1b[48;2;9;8;7m");
    }

    #[test]
    fn sgr_combines_changes_sends_nothing_when_unchanged_and_prefers_a_short_reset() {
        let red = Some(Color::Indexed(1));
        let rgb = Some(Color::Rgb(10, 20, 30));
        assert_eq!(sgr((red, red), red, Color::Indexed(1)).0, "");
        // A space doesn't care about the foreground: only the background is sent.
        assert_eq!(sgr((red, red), None, Color::Indexed(4)).0, "\x1b[44m");
        assert_eq!(sgr((red, red), Some(Color::Indexed(2)), Color::Indexed(4)).0, "\x1b[32;44m");
        // Both back to default: the reset is shorter than 39;49.
        let (bytes, pen) = sgr((rgb, rgb), Some(Color::Default), Color::Default);
        assert_eq!(bytes, "\x1b[m");
        assert_eq!((pen.fg, pen.bg), (Some(PackedColor::DEFAULT), Some(PackedColor::DEFAULT)));
        assert_eq!(sgr((rgb, rgb), Some(Color::Default), Color::Indexed(1)).0, "\x1b[0;41m");
        // Unknown state: everything is sent.
        assert_eq!(sgr((None, None), red, Color::Default).0, "\x1b[0;31m");
    }
}
