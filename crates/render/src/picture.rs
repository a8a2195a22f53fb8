//! A frame as the terminal shows it, in pixels: for pictures of frames without a terminal or a font
//! (`mazewalk render --png`, the README's images).
//!
//! Exact for the block charsets: every cell is split into its samples (`sx × sy` blocks of pixels) and
//! each block takes the colour the glyph gives it, ink or background, through xterm's default palette
//! for indexed colours. The terminal's default colours are taken as light grey on black. Digits and
//! the look-ahead lens's `|` and `+` are drawn in a small pixel font ([`PIXEL_FONT`]), so that a
//! picture of the lens reads as the terminal does; other glyphs that are not block glyphs (the HUD's
//! letters, a figure's initial) show as their cell's background with a square of ink in the middle,
//! a stand-in for the character.

use super::options::Charset;
use super::palette::xterm_rgb;
use mazewalk_term::blocks::{HALF, QUAD, sextant_glyph};
use mazewalk_term::frame::{Color, Frame};

/// The pixels of one terminal cell in a picture: 12 wide, 24 tall (cells are about half as wide as
/// tall), which every charset's samples divide (half 12×12, quad 6×12, sextant 6×8).
pub(crate) const CELL_PIXELS: (usize, usize) = (12, 24);

/// The default foreground and background the picture assumes (sRGB).
const DEFAULT_FG: [u8; 3] = [229, 229, 229];
const DEFAULT_BG: [u8; 3] = [0, 0, 0];

/// Which samples of a `charset` cell `ch` inks (bit order of [`super::glyph`]: row-major from the
/// top-left), or `None` when `ch` is not one of its block glyphs.
#[must_use]
pub(crate) fn glyph_mask(charset: Charset, ch: char) -> Option<u8> {
    match charset {
        Charset::Ascii => None,
        Charset::Half => HALF.iter().position(|&g| g == ch).map(|m| m as u8),
        Charset::Quad => QUAD.iter().position(|&g| g == ch).map(|m| m as u8),
        Charset::Sextant => (0..64u8).find(|&m| sextant_glyph(m) == ch),
    }
}

/// Digits, `|` and `+` (the look-ahead lens's range marks, `7|`, `9+`) in 3 × 5 pixels, each row's
/// three bits from the left; drawn 3× ([`FONT_SCALE`]) in the middle of their cell.
const PIXEL_FONT: [(char, [u8; 5]); 12] = [
    ('0', [0b111, 0b101, 0b101, 0b101, 0b111]),
    ('1', [0b010, 0b110, 0b010, 0b010, 0b111]),
    ('2', [0b111, 0b001, 0b111, 0b100, 0b111]),
    ('3', [0b111, 0b001, 0b011, 0b001, 0b111]),
    ('4', [0b101, 0b101, 0b111, 0b001, 0b001]),
    ('5', [0b111, 0b100, 0b111, 0b001, 0b111]),
    ('6', [0b111, 0b100, 0b111, 0b101, 0b111]),
    ('7', [0b111, 0b001, 0b010, 0b010, 0b010]),
    ('8', [0b111, 0b101, 0b111, 0b101, 0b111]),
    ('9', [0b111, 0b101, 0b111, 0b001, 0b111]),
    ('|', [0b010, 0b010, 0b010, 0b010, 0b010]),
    ('+', [0b000, 0b010, 0b111, 0b010, 0b000]),
];

/// How many pixels a [`PIXEL_FONT`] pixel takes each way.
const FONT_SCALE: usize = 3;

/// Whether pixel (`px`, `py`) of a cell showing `ch` is ink: `ch`'s [`PIXEL_FONT`] glyph where it
/// has one, else a square in the cell's middle third (none for a space).
fn text_ink(ch: char, px: usize, py: usize) -> bool {
    let (cw, chh) = CELL_PIXELS;
    match PIXEL_FONT.iter().find(|(c, _)| *c == ch) {
        Some((_, rows)) => {
            let (left, top) = ((cw - 3 * FONT_SCALE) / 2, (chh - 5 * FONT_SCALE) / 2);
            let (x, y) = (px.wrapping_sub(left) / FONT_SCALE, py.wrapping_sub(top) / FONT_SCALE);
            x < 3 && y < 5 && rows[y] >> (2 - x) & 1 == 1
        }
        None => ch != ' ' && (cw / 3..2 * cw / 3).contains(&px) && (chh / 3..2 * chh / 3).contains(&py),
    }
}

/// The sRGB a colour shows as (`Default` as the assumed terminal defaults).
fn rgb(color: Color, default: [u8; 3]) -> [u8; 3] {
    match color {
        Color::Default => default,
        Color::Rgb(r, g, b) => [r, g, b],
        Color::Indexed(i) => xterm_rgb(i),
    }
}

/// `frame` drawn with `charset`'s sample layout: `(width, height, RGB bytes)`, [`CELL_PIXELS`] per cell.
#[must_use]
#[cfg(test)]
pub(crate) fn frame_pixels(frame: &Frame, charset: Charset) -> (usize, usize, Vec<u8>) {
    let (width, height) = picture_size(frame);
    let mut pixels = Vec::with_capacity(width * height * 3);
    for_each_band(frame, charset, |band| {
        pixels.extend_from_slice(band);
        Ok::<(), std::convert::Infallible>(())
    })
    .unwrap_or_else(|never| match never {});
    (width, height, pixels)
}

/// The size in pixels of `frame`'s picture.
#[must_use]
pub fn picture_size(frame: &Frame) -> (usize, usize) {
    (frame.width() * CELL_PIXELS.0, frame.height() * CELL_PIXELS.1)
}

/// `frame_pixels` (the tests' whole picture) one row of cells at a time, top to bottom: `band` gets that row's
/// [`CELL_PIXELS`]`.1` lines of RGB pixels (so a picture is written without ever being whole in memory;
/// the first error stops the bands).
pub fn for_each_band<E>(
    frame: &Frame,
    charset: Charset,
    mut band: impl FnMut(&[u8]) -> Result<(), E>,
) -> Result<(), E> {
    let (cw, ch) = CELL_PIXELS;
    let (sx, sy) = if charset == Charset::Ascii { (1, 1) } else { charset.samples_per_cell() };
    let width = picture_size(frame).0;
    let mut pixels = vec![0u8; width * ch * 3];
    for row in frame.cells().chunks(frame.width().max(1)) {
        for (col, cell) in row.iter().enumerate() {
            let (fg, bg) = (rgb(cell.fg, DEFAULT_FG), rgb(cell.bg, DEFAULT_BG));
            let mask = glyph_mask(charset, cell.ch);
            for py in 0..ch {
                for px in 0..cw {
                    let inked = match mask {
                        Some(mask) => mask >> ((px * sx / cw) + sx * (py * sy / ch)) & 1 == 1,
                        // A character: a digit or a mark of the lens as itself, else a stand-in.
                        None => text_ink(cell.ch, px, py),
                    };
                    let at = (py * width + col * cw + px) * 3;
                    pixels[at..at + 3].copy_from_slice(&if inked { fg } else { bg });
                }
            }
        }
        band(&pixels)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_term::frame::Cell;

    #[test]
    fn every_block_glyph_maps_back_to_its_mask() {
        for charset in [Charset::Half, Charset::Quad, Charset::Sextant] {
            let (sx, sy) = charset.samples_per_cell();
            for mask in 0..1u8 << (sx * sy) {
                let glyph = super::super::glyph::block_glyph(charset, mask);
                assert_eq!(glyph_mask(charset, glyph), Some(mask), "{charset} {mask:b}");
            }
        }
        assert_eq!(glyph_mask(Charset::Half, 'A'), None);
    }

    #[test]
    fn each_band_is_one_row_of_cells_in_place() {
        let mut frame = Frame::new(2, 2);
        let colors = [[10, 0, 0], [0, 20, 0], [0, 0, 30], [40, 40, 0]];
        for (k, [r, g, b]) in colors.into_iter().enumerate() {
            frame.set(k % 2, k / 2, Cell { ch: ' ', fg: Color::Default, bg: Color::Rgb(r, g, b) });
        }
        let (mut bands, (w, _)) = (Vec::new(), picture_size(&frame));
        for_each_band(&frame, Charset::Half, |band| {
            bands.push(band.to_vec());
            Ok::<_, ()>(())
        })
        .unwrap();
        assert_eq!(bands.len(), 2);
        let (cw, ch) = CELL_PIXELS;
        for (k, color) in colors.iter().enumerate() {
            let band = &bands[k / 2];
            for (x, y) in [(0, 0), (cw - 1, ch - 1)] {
                let at = (y * w + (k % 2) * cw + x) * 3;
                assert_eq!(&band[at..at + 3], color, "cell {k} pixel ({x}, {y})");
            }
        }
        let stop = for_each_band(&frame, Charset::Half, |_| Err("full"));
        assert_eq!(stop, Err("full"), "the first error stops it");
    }

    /// The lens's marks read in a picture: each digit, `|` and `+` is its own shape, inked within
    /// its cell's middle; other characters keep the stand-in square, a space shows nothing.
    #[test]
    fn digits_and_the_lens_marks_are_drawn_each_as_itself() {
        let shape = |ch: char| {
            let mut frame = Frame::new(1, 1);
            frame.set(0, 0, Cell { ch, fg: Color::Rgb(255, 255, 255), bg: Color::Rgb(0, 0, 0) });
            let (_, _, pixels) = frame_pixels(&frame, Charset::Half);
            pixels.chunks(3).map(|p| p[0] == 255).collect::<Vec<bool>>()
        };
        let marks: Vec<char> = "0123456789|+".chars().collect();
        let shapes: Vec<Vec<bool>> = marks.iter().map(|&c| shape(c)).collect();
        for (i, a) in shapes.iter().enumerate() {
            assert!(a.iter().any(|&ink| ink), "{:?} shows nothing", marks[i]);
            for (j, b) in shapes.iter().enumerate().skip(i + 1) {
                assert_ne!(a, b, "{:?} and {:?} look alike", marks[i], marks[j]);
            }
            assert_ne!(a, &shape('A'), "{:?} looks like the stand-in", marks[i]);
        }
        // '8' has every pixel '0' has and its bar besides
        let (zero, eight) = (&shapes[0], &shapes[8]);
        assert!(zero.iter().zip(eight).all(|(z, e)| !z || *e) && eight != zero);
        assert!(shape(' ').iter().all(|&ink| !ink));
    }

    #[test]
    fn a_half_block_cell_is_its_two_samples() {
        let mut frame = Frame::new(1, 1);
        frame.set(0, 0, Cell { ch: '▀', fg: Color::Rgb(255, 0, 0), bg: Color::Indexed(21) });
        let (w, h, pixels) = frame_pixels(&frame, Charset::Half);
        assert_eq!((w, h), CELL_PIXELS);
        let at = |x: usize, y: usize| &pixels[(y * w + x) * 3..(y * w + x) * 3 + 3];
        assert_eq!(at(0, 0), [255, 0, 0]);
        assert_eq!(at(11, 11), [255, 0, 0]);
        assert_eq!(at(0, 12), xterm_rgb(21));
        assert_eq!(at(11, 23), xterm_rgb(21));
    }
}
