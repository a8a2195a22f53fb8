//! A [`Frame`]: the character grid the renderer produces and the terminal encoder sends.
//!
//! Pure data, no terminal types: a row-major grid of [`Cell`]s, each one glyph with a foreground and a
//! background [`Color`]. Grid coordinates: origin top-left, x (column) right, y (row) down.
//!
//! Every glyph stored in a frame must occupy exactly one terminal column (ASCII, box drawing, block and
//! sextant glyphs all do); [`Frame::put_str`] replaces anything else with `?` so the grid and the
//! terminal never disagree about where a column is.

mod packed;

pub use packed::TOLERANCE_STEP;

/// OKLab (L, a, b) of a linear sRGB colour (Björn Ottosson's matrices,
/// <https://bottosson.github.io/posts/oklab/>), with `cbrt` the cube root to apply to the cone
/// responses (each at least 0 for a colour in gamut): Euclidean distance there is close to the
/// difference a person sees. The one transform both the encoder's tolerance (with a fast root) and the
/// renderer's palette (with the library's) use.
#[must_use]
#[inline]
pub fn oklab([r, g, b]: [f32; 3], cbrt: impl Fn(f32) -> f32) -> [f32; 3] {
    let l = 0.412_221_46 * r + 0.536_332_55 * g + 0.051_445_995 * b;
    let m = 0.211_903_5 * r + 0.680_699_5 * g + 0.107_396_96 * b;
    let s = 0.088_302_46 * r + 0.281_718_85 * g + 0.629_978_7 * b;
    let [l, m, s] = [l, m, s].map(cbrt);
    [
        0.210_454_26 * l + 0.793_617_8 * m - 0.004_072_047 * s,
        1.977_998_5 * l - 2.428_592_2 * m + 0.450_593_7 * s,
        0.025_904_037 * l + 0.782_771_77 * m - 0.808_675_77 * s,
    ]
}
pub(crate) use packed::{PackedCell, PackedColor, code_len};

/// xterm's default RGB for the 16 ANSI colours (black, red, green, yellow, blue, magenta, cyan, white,
/// then the bright eight). Terminals' themes change them.
pub const ANSI16: [[u8; 3]; 16] = [
    [0, 0, 0],
    [205, 0, 0],
    [0, 205, 0],
    [205, 205, 0],
    [0, 0, 238],
    [205, 0, 205],
    [0, 205, 205],
    [229, 229, 229],
    [127, 127, 127],
    [255, 0, 0],
    [0, 255, 0],
    [255, 255, 0],
    [92, 92, 255],
    [255, 0, 255],
    [0, 255, 255],
    [255, 255, 255],
];

/// The levels of each axis of xterm's 6×6×6 colour cube (indices 16–231).
pub const CUBE_LEVELS: [u8; 6] = [0, 95, 135, 175, 215, 255];

/// The RGB xterm shows for palette `index` (ANSI 16, cube, grey ramp): the renderer's palette and the
/// encoder's tolerance for palette colours ([`Color::within`]) both read it.
#[must_use]
pub fn xterm_rgb(index: u8) -> [u8; 3] {
    match index {
        0..=15 => ANSI16[usize::from(index)],
        16..=231 => {
            let i = usize::from(index - 16);
            [CUBE_LEVELS[i / 36], CUBE_LEVELS[i / 6 % 6], CUBE_LEVELS[i % 6]]
        }
        _ => [8 + 10 * (index - 232); 3],
    }
}

/// A colour as the terminal is asked to show it; the renderer quantizes to the depth in use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Color {
    /// The terminal's own default colour (what `--color none` produces everywhere).
    #[default]
    Default,
    /// A palette index: 0–15 are the 16 ANSI colours, 16–231 the 6×6×6 cube, 232–255 the grey ramp.
    Indexed(u8),
    /// 24-bit truecolor.
    Rgb(u8, u8, u8),
}

impl Color {
    /// Whether two colours are within `tolerance` [`TOLERANCE_STEP`]s (an OKLab distance of
    /// `tolerance` × 0.01): truecolor colours that close, palette entries 16–255 whose xterm RGB
    /// ([`xterm_rgb`]) are, or any colours that are equal. The 16 ANSI colours are the terminal theme's
    /// (unknown distances): exact.
    #[must_use]
    #[inline]
    pub fn within(self, other: Color, tolerance: u8) -> bool {
        PackedColor::pack(self).within(PackedColor::pack(other), tolerance)
    }
}

/// How many colours the terminal can show; the renderer quantizes to it, the encoder emits its codes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorDepth {
    /// No colour at all: every cell uses [`Color::Default`]; shape and shading come from glyphs alone.
    None,
    /// The 16 ANSI colours ([`Color::Indexed`] 0–15).
    Ansi16,
    /// The xterm 256-colour palette ([`Color::Indexed`] 16–255 for the cube and greys).
    Ansi256,
    /// 24-bit colour ([`Color::Rgb`]).
    #[default]
    TrueColor,
}

mazewalk_names::named!(
    ColorDepth,
    "colour depth",
    [
        ("none", ColorDepth::None),
        ("16", ColorDepth::Ansi16),
        ("256", ColorDepth::Ansi256),
        ("truecolor", ColorDepth::TrueColor),
        ("0", ColorDepth::None),
        ("mono", ColorDepth::None),
        ("ansi", ColorDepth::Ansi16),
        ("24bit", ColorDepth::TrueColor),
        ("rgb", ColorDepth::TrueColor),
    ]
);

/// A rectangle of cells in a frame: columns `col..col + cols`, rows `row..row + rows` (0-based from
/// the top-left). The renderer draws the 3D view into one, the overlays go around and over it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Region {
    /// Leftmost column.
    pub col: usize,
    /// Top row.
    pub row: usize,
    /// Width in cells.
    pub cols: usize,
    /// Height in cells.
    pub rows: usize,
}

/// One character cell of a frame.
///
/// A space shows no ink, but its ink tells what it is: a space in text (ink not its paper, as
/// [`Frame::put_str`] writes them) goes to the terminal as a space; a blank of the picture (ink and
/// paper equal) may go as a full block in the same colour where that is fewer bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cell {
    /// The glyph; always a single-column character.
    pub ch: char,
    /// Foreground colour (the glyph's ink).
    pub fg: Color,
    /// Background colour (the rest of the cell).
    pub bg: Color,
}

impl Cell {
    /// A blank cell in the terminal's default colours.
    pub const BLANK: Cell = Cell { ch: ' ', fg: Color::Default, bg: Color::Default };

    /// A cell with `ch` in the default colours.
    #[must_use]
    pub const fn plain(ch: char) -> Cell {
        Cell { ch, fg: Color::Default, bg: Color::Default }
    }

    /// The same look drawn the other way round, for a block glyph whose complement exists: `▀` in A on B
    /// is `▄` in B on A, a blank on B is `█` in B, a quadrant or sextant is its complement with the
    /// colours swapped. The encoder uses whichever form the terminal's current colours make cheaper.
    ///
    /// None where a colour the cell shows is [`Color::Default`]: the default foreground and the default
    /// background are different colours, so that one cannot change sides.
    #[must_use]
    pub fn inverse(&self) -> Option<Cell> {
        PackedCell::pack(self).inverse().map(PackedCell::unpack)
    }

    /// Whether two cells look the same on screen: the same glyph in the same colours, where a space
    /// shows no foreground and a full block no background; or one is the other's [`Cell::inverse`]; a
    /// block glyph whose two colours are equal looks like a blank of that colour.
    #[must_use]
    pub fn same_look(&self, other: &Cell) -> bool {
        self.looks_within(other, 0)
    }

    /// [`Cell::same_look`] up to `tolerance` [`TOLERANCE_STEP`]s (OKLab) between truecolor colours or
    /// between palette entries 16–255 ([`Color::within`]; other colours must be equal): what the encoder's [`set_tolerance`](crate::encoder::Encoder::set_tolerance) leaves alone.
    ///
    /// Block glyphs (space, full block, halves, quadrants, sextants) are compared by what each part of
    /// the cell shows: on a 2×6 grid of sub-cells (fine enough for all of them), every sub-cell's colour
    /// in one is within `tolerance` of its colour in the other. So `▀` in A on B looks like `▄` in B on
    /// A, and a `▀` whose two colours are within the tolerance of C looks like a blank on C. Other
    /// glyphs must be the same, in colours within the tolerance.
    #[must_use]
    pub fn looks_within(&self, other: &Cell, tolerance: u8) -> bool {
        PackedCell::pack(self).looks_within(&PackedCell::pack(other), tolerance)
    }

    /// The cell itself, or a blank where a block glyph is drawn in one colour (it looks like one).
    #[must_use]
    pub fn canonical(&self) -> Cell {
        PackedCell::pack(self).canonical().unpack()
    }
}

impl Default for Cell {
    fn default() -> Self {
        Cell::BLANK
    }
}

/// A `width × height` grid of cells, row-major, origin top-left.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Frame {
    width: usize,
    height: usize,
    cells: Vec<Cell>,
}

impl Frame {
    /// A frame of blank cells. Callers validate untrusted sizes before calling (see the CLI limits).
    #[must_use]
    pub fn new(width: usize, height: usize) -> Frame {
        Frame::filled(width, height, Cell::BLANK)
    }

    /// A frame with every cell set to `cell`.
    #[must_use]
    pub fn filled(width: usize, height: usize, cell: Cell) -> Frame {
        Frame { width, height, cells: vec![cell; width * height] }
    }

    /// A colourless frame from text lines: one cell per char, short lines padded with blanks. For the
    /// crate's unit tests only.
    #[cfg(test)]
    #[must_use]
    pub(crate) fn from_lines<S: AsRef<str>>(lines: &[S]) -> Frame {
        let height = lines.len();
        let width = lines.iter().map(|l| l.as_ref().chars().count()).max().unwrap_or(0);
        let mut frame = Frame::new(width, height);
        for (y, line) in lines.iter().enumerate() {
            frame.put_str(0, y, line.as_ref(), Color::Default, Color::Default);
        }
        frame
    }

    /// Columns.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// All cells, row-major.
    #[must_use]
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// All cells, row-major, mutable.
    pub fn cells_mut(&mut self) -> &mut [Cell] {
        &mut self.cells
    }

    /// The whole frame as a [`Region`].
    #[must_use]
    pub fn region(&self) -> Region {
        Region { col: 0, row: 0, cols: self.width, rows: self.height }
    }

    /// The rows of `region`, top to bottom, each the region's `cols` cells.
    ///
    /// # Panics
    /// If `region` is not inside the frame.
    pub fn region_rows_mut(&mut self, region: Region) -> impl Iterator<Item = &mut [Cell]> {
        assert!(
            region.col + region.cols <= self.width && region.row + region.rows <= self.height,
            "{region:?} is not inside a {}×{} frame",
            self.width,
            self.height
        );
        let width = self.width.max(1);
        self.cells
            .chunks_exact_mut(width)
            .skip(region.row)
            .take(region.rows)
            .map(move |line| &mut line[region.col..region.col + region.cols])
    }

    /// Row `y` as a slice of `width` cells, or `None` past the bottom.
    #[must_use]
    pub fn row(&self, y: usize) -> Option<&[Cell]> {
        (y < self.height).then(|| &self.cells[y * self.width..(y + 1) * self.width])
    }

    /// The cell at column `x`, row `y`, or `None` outside the grid.
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> Option<&Cell> {
        (x < self.width && y < self.height).then(|| &self.cells[y * self.width + x])
    }

    /// The cell at column `x`, row `y`, mutable, or `None` outside the grid.
    pub fn get_mut(&mut self, x: usize, y: usize) -> Option<&mut Cell> {
        (x < self.width && y < self.height).then(|| &mut self.cells[y * self.width + x])
    }

    /// Sets one cell; writes outside the grid are ignored (overlays clip at the frame's edge).
    pub fn set(&mut self, x: usize, y: usize, cell: Cell) {
        if let Some(c) = self.get_mut(x, y) {
            *c = cell;
        }
    }

    /// Sets every cell to `cell`.
    pub fn fill(&mut self, cell: Cell) {
        self.cells.fill(cell);
    }

    /// Changes the size, keeping nothing: every cell becomes `Cell::BLANK`. Reuses the allocation.
    pub fn resize(&mut self, width: usize, height: usize) {
        self.width = width;
        self.height = height;
        self.cells.clear();
        self.cells.resize(width * height, Cell::BLANK);
    }

    /// Writes `text` from column `x` of row `y`, clipped at the right edge; returns the columns written.
    /// Control and wide characters are replaced by `?` (every glyph must be one column wide).
    pub fn put_str(&mut self, x: usize, y: usize, text: &str, fg: Color, bg: Color) -> usize {
        let mut written = 0;
        for (i, ch) in text.chars().enumerate() {
            let Some(cell) = self.get_mut(x.saturating_add(i), y) else { break };
            *cell = Cell { ch: single_column(ch), fg, bg };
            written += 1;
        }
        written
    }

    /// The glyphs as text lines, colours dropped (how frames are compared in tests and `--color none`).
    #[must_use]
    pub fn lines(&self) -> Vec<String> {
        (0..self.height).map(|y| self.row(y).unwrap_or(&[]).iter().map(|c| c.ch).collect()).collect()
    }
}

/// `ch` if it takes exactly one terminal column, else `?`.
///
/// Conservative: accepts printable ASCII and the Latin-1 to block/sextant ranges mazewalk draws with
/// (U+00A0–U+2FFF minus combining marks, U+1FB00–U+1FBFF legacy computing), nothing East-Asian-wide.
#[must_use]
pub(crate) fn single_column(ch: char) -> char {
    let c = ch as u32;
    let ok = (0x20..0x7F).contains(&c)
        || ((0xA0..0x3000).contains(&c) && !(0x0300..0x0370).contains(&c) && !(0x1100..0x1160).contains(&c))
        || (0x1FB00..0x1FC00).contains(&c);
    if ok { ch } else { '?' }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_foreground_and_background_are_two_colours() {
        // What `--color none` draws: shades in the terminal's own colours, `█` the brightest.
        let (full, blank) = (Cell::plain('█'), Cell::BLANK);
        assert!(!full.same_look(&blank), "a full block in the default foreground is not a blank");
        assert!(!Cell::plain('▌').same_look(&Cell::plain('▐')));
        assert_eq!(Cell::plain('▀').canonical(), Cell::plain('▀'), "two colours, not one");
        assert_eq!(blank.inverse(), None, "the default background cannot become a foreground");
        assert_eq!(Cell::plain('▄').inverse(), None);
        let blue = Color::Indexed(4);
        let on_blue = Cell { ch: ' ', fg: Color::Default, bg: blue }; // the foreground is not shown
        assert_eq!(on_blue.inverse(), Some(Cell { ch: '█', fg: blue, bg: Color::Default }));
        assert!(Cell { ch: '▀', fg: Color::Default, bg: blue }.same_look(&Cell {
            ch: '▀',
            fg: Color::Default,
            bg: blue
        }));
    }

    #[test]
    fn put_str_clips_at_the_right_edge_and_replaces_wide_glyphs() {
        let mut frame = Frame::filled(5, 2, Cell::plain('.'));
        assert_eq!(frame.put_str(3, 0, "abc", Color::Default, Color::Default), 2);
        assert_eq!(frame.put_str(0, 1, "a\tあ", Color::Default, Color::Default), 3);
        assert_eq!(frame.put_str(0, 7, "zz", Color::Default, Color::Default), 0);
        assert_eq!(frame.lines(), ["...ab", "a??.."]);
    }

    #[test]
    fn out_of_grid_access_is_none_and_set_ignores_it() {
        let mut frame = Frame::new(3, 2);
        assert!(frame.get(3, 0).is_none());
        assert!(frame.get(0, 2).is_none());
        frame.set(9, 9, Cell::plain('x'));
        assert_eq!(frame.lines(), ["   ", "   "]);
        frame.set(2, 1, Cell::plain('x'));
        assert_eq!(frame.lines(), ["   ", "  x"]);
    }

    #[test]
    fn from_lines_pads_short_lines_and_resize_blanks() {
        let mut frame = Frame::from_lines(&["ab", "c"]);
        assert_eq!((frame.width(), frame.height()), (2, 2));
        assert_eq!(frame.lines(), ["ab", "c "]);
        frame.resize(1, 3);
        assert_eq!(frame.lines(), [" ", " ", " "]);
        let empty = Frame::new(0, 0);
        assert!(empty.lines().is_empty());
    }
}
