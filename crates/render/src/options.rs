//! What a picture is drawn with: the options of one frame ([`RenderOptions`]) and the choices they
//! are made of, each named as the command line spells it ([`Charset`], [`Ramp`], [`Culling`]).
//! Colour depth is the terminal's ([`ColorDepth`], mazewalk-term).

use mazewalk_term::frame::ColorDepth;

/// How cells are drawn, and so how many samples each covers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Charset {
    /// One sample per cell: a luminance ramp plus line outlines; readable without colour.
    Ascii,
    /// 1×2 samples: `▀` with the top sample as ink, the bottom one as background.
    #[default]
    Half,
    /// 2×2 samples: the quadrant blocks `▘▝▀▖▌▞▛▗▚▐▜▄▙▟█`.
    Quad,
    /// 2×3 samples: the sextant blocks U+1FB00–U+1FB3B plus ` `, `▌`, `▐`, `█`.
    Sextant,
}

impl Charset {
    /// Every charset, in the order of their names.
    pub const ALL: [Charset; 4] = [Charset::Ascii, Charset::Half, Charset::Quad, Charset::Sextant];

    /// Samples per cell `(sx, sy)`; the pipeline sizes the buffer `cols·sx × rows·sy`.
    #[must_use]
    pub const fn samples_per_cell(self) -> (usize, usize) {
        match self {
            Charset::Ascii => (1, 1),
            Charset::Half => (1, 2),
            Charset::Quad => (2, 2),
            Charset::Sextant => (2, 3),
        }
    }

    /// A sample's width / height on screen, from the cell's (about 0.5): `cell_aspect · sy / sx`.
    #[must_use]
    pub fn sample_aspect(self, cell_aspect: f32) -> f32 {
        let (sx, sy) = self.samples_per_cell();
        cell_aspect * sy as f32 / sx as f32
    }
}

mazewalk_names::named!(
    Charset,
    "charset",
    [
        ("ascii", Charset::Ascii),
        ("half", Charset::Half),
        ("quad", Charset::Quad),
        ("sextant", Charset::Sextant),
    ]
);

/// The ascii shading ramp, darkest first.
pub const ASCII_RAMP: [char; 10] = [' ', '.', ':', '-', '=', '+', '*', '#', '%', '@'];

/// The long ascii ramp, darkest first: 70 characters by how much of the cell they ink (Paul Bourke's
/// "character representation of grey scale images").
pub const ASCII_RAMP_LONG: [char; 70] = [
    ' ', '.', '\'', '`', '^', '"', ',', ':', ';', 'I', 'l', '!', 'i', '>', '<', '~', '+', '_', '-', '?', ']',
    '[', '}', '{', '1', ')', '(', '|', '\\', '/', 't', 'f', 'j', 'r', 'x', 'n', 'u', 'v', 'c', 'z', 'X', 'Y',
    'U', 'J', 'C', 'L', 'Q', '0', 'O', 'Z', 'm', 'w', 'q', 'p', 'd', 'b', 'k', 'h', 'a', 'o', '*', '#', 'M',
    'W', '&', '8', '%', 'B', '@', '$',
];

/// The ascii glyphs of the floor, darkest first: marks low in the cell, none of them a wall's ([`ASCII_RAMP`]),
/// so that floor and walls are told apart without colour (issue #33). The long ramp leaves them out
/// for walls.
pub const ASCII_FLOOR: [char; 3] = [' ', ',', '_'];
/// The ascii glyphs of the ceiling, darkest first: marks high in the cell (see [`ASCII_FLOOR`]).
pub const ASCII_CEILING: [char; 3] = [' ', '`', '"'];

/// Which ascii shading ramp: the 10 characters of [`ASCII_RAMP`] or the 70 of [`ASCII_RAMP_LONG`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Ramp {
    /// 10 characters, bold steps.
    #[default]
    Short,
    /// 70 characters, fine steps.
    Long,
}

impl Ramp {
    /// The ramp's characters, darkest first.
    #[must_use]
    pub fn glyphs(self) -> &'static [char] {
        match self {
            Ramp::Short => &ASCII_RAMP,
            Ramp::Long => &ASCII_RAMP_LONG,
        }
    }
}

mazewalk_names::named!(Ramp, "ramp", [("short", Ramp::Short), ("long", Ramp::Long)]);

/// Which walls go into the raster.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Culling {
    /// Only walls the cell-and-portal walk can see (the default).
    #[default]
    Portal,
    /// Every wall of the maze (brute force, the reference).
    None,
}

mazewalk_names::named!(Culling, "culling", [("portal", Culling::Portal), ("none", Culling::None)]);

/// How to turn samples into a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Glyph mode (and so samples per cell).
    pub charset: Charset,
    /// Colour depth to quantize to.
    pub color_depth: ColorDepth,
    /// Portal pass or brute force.
    pub culling: Culling,
    /// Terminal cell width / height (about 0.5).
    pub cell_aspect: f32,
    /// In 256 and 16 colours, block charsets only: where a sample lies between two neighbouring
    /// entries of its light ramp that are perceptually close, a 2×2 ordered mix of the two
    /// ([`LightRamp::entry_dithered`](crate::palette::LightRamp::entry_dithered)): smoother shading,
    /// no grain, more bytes. Off (the default), each sample takes its ramp's entry: calm bands.
    pub dither: bool,
    /// The ascii charset's shading ramp.
    pub ramp: Ramp,
    /// Brick walls and filtered floor and ceiling tiles ([`bricks`](crate::shade::bricks),
    /// [`checker_filtered`](crate::shade::checker_filtered)); off, walls
    /// are plain and the tiles unfiltered.
    pub textures: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            charset: Charset::Half,
            color_depth: ColorDepth::TrueColor,
            culling: Culling::Portal,
            cell_aspect: 0.5,
            dither: false,
            ramp: Ramp::Short,
            textures: false,
        }
    }
}
