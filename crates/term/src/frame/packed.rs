//! Colours and cells packed into words: what the encoder compares and prices, a few hundred times a
//! cell of every frame.
//!
//! A [`Color`] is an enum of three shapes, so comparing two means comparing tags, then fields, and a
//! palette index leaves three bytes undefined. A [`PackedColor`] is one word in which every colour has
//! exactly one spelling: equal colours are equal words (one comparison), and `Option<PackedColor>` is a
//! word too. The look rules ([`PackedCell::looks_within`], [`PackedCell::inverse`],
//! [`PackedCell::canonical`]) are written here once; [`Cell`]'s methods of those names pack and call them.

use std::num::NonZeroU32;

use super::{Cell, Color};
use crate::blocks::{ALL_SUBCELLS, FULL_BLOCK, complement_glyph, ink_mask};

/// A [`Color`] in one word: its kind in the top byte, its value below. Truecolor is `0x01RRGGBB`, a
/// palette index `n` is `0x0200_00nn`, the default `0x0300_0000`. Never zero, so `None` is zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PackedColor(NonZeroU32);

/// The kinds, in the top byte.
const RGB: u32 = 1;
const INDEXED: u32 = 2;
const DEFAULT: u32 = 3;

impl PackedColor {
    /// The terminal's default colour.
    pub(crate) const DEFAULT: PackedColor = PackedColor::new(DEFAULT, 0);

    const fn new(kind: u32, value: u32) -> PackedColor {
        // Never zero: every kind is.
        match NonZeroU32::new(kind << 24 | value) {
            Some(word) => PackedColor(word),
            None => panic!("a colour's kind is never zero"),
        }
    }

    /// `color`, packed.
    #[inline]
    #[must_use]
    pub(crate) fn pack(color: Color) -> PackedColor {
        match color {
            Color::Rgb(r, g, b) => PackedColor::new(RGB, u32::from_be_bytes([0, r, g, b])),
            Color::Indexed(n) => PackedColor::new(INDEXED, u32::from(n)),
            Color::Default => PackedColor::DEFAULT,
        }
    }

    /// The colour it packs.
    #[inline]
    #[must_use]
    pub(crate) fn unpack(self) -> Color {
        let [kind, r, g, b] = self.0.get().to_be_bytes();
        match u32::from(kind) {
            RGB => Color::Rgb(r, g, b),
            INDEXED => Color::Indexed(b),
            _ => Color::Default,
        }
    }

    /// Its word (kind and value): equal words, equal colours.
    #[inline]
    #[must_use]
    pub(crate) fn word(self) -> u32 {
        self.0.get()
    }

    /// Whether a tolerance applies to it: a truecolor colour, or an entry of xterm's 256-colour
    /// palette past the 16 ANSI colours (the cube and the greys, whose RGB every terminal shares). The
    /// 16 ANSI colours are the user's theme, whose distances nobody here knows, and the default
    /// colours likewise: those are exact.
    #[inline]
    #[must_use]
    pub(crate) fn is_tolerant(self) -> bool {
        let word = self.0.get();
        word >> 24 == RGB || (word >> 24 == INDEXED && word & 0xff >= 16)
    }

    /// Whether some other colour may be within `tolerance` [`TOLERANCE_STEP`]s of it: any truecolor
    /// colour (above 0), a palette entry 16–255 whose nearest other entry is that close (at the default
    /// of 2, 8 of the 240), nothing else. Where it is false, [`PackedColor::within`] of it and anything
    /// is equality: the encoder takes its exact path, as fast as at tolerance 0.
    #[inline]
    #[must_use]
    pub(crate) fn may_be_near(self, tolerance: u8) -> bool {
        let word = self.0.get();
        match word >> 24 {
            RGB => tolerance > 0,
            INDEXED if word & 0xff >= 16 => {
                let limit = f32::from(tolerance) * TOLERANCE_STEP;
                PALETTE.nearest[(word & 0xff) as usize] <= limit * limit
            }
            _ => false,
        }
    }

    /// Whether two colours are within `tolerance` [`TOLERANCE_STEP`]s of each other in OKLab (two
    /// truecolor colours that close, two palette entries 16–255 whose xterm RGB are, or a truecolor
    /// colour and an entry 16–255 whose xterm RGB is: the encoder may send an entry for a truecolor
    /// colour, [`PackedColor::cheapest`]), or equal (any colours).
    #[inline(always)] // (in the encoder's loops, as it was before it had a third case out of line)
    #[must_use]
    pub(crate) fn within(self, other: PackedColor, tolerance: u8) -> bool {
        let (a, b) = (self.0.get(), other.0.get());
        if a == b {
            return true;
        }
        if tolerance == 0 {
            return false;
        }
        let limit = f32::from(tolerance) * TOLERANCE_STEP;
        let [p, q] = match (a >> 24, b >> 24) {
            (RGB, RGB) => oklab([a, b]),
            (INDEXED, INDEXED) if a & 0xff >= 16 && b & 0xff >= 16 => {
                let entries = &PALETTE.oklab;
                [entries[(a & 0xff) as usize], entries[(b & 0xff) as usize]]
            }
            (RGB, INDEXED) | (INDEXED, RGB) => return rgb_within_entry(a, b, limit),
            _ => return false,
        };
        distance2(p, q) <= limit * limit
    }

    /// Issue #42: of the colours near this one (within [`SHORT_CODE_REACH`] of `tolerance`: within
    /// the tolerance, with some to spare), the one whose SGR code is the shortest ([`code_len`]): a palette entry 16–255 (`38;5;n`, 7–8 bytes: the cube and the greys,
    /// the same on every xterm-like terminal; never 0–15, the theme's), else a truecolor colour with
    /// fewer digits (a channel of 100–104 as 99, of 10–12 as 9), else itself. Of equal lengths the
    /// nearest, then the lowest word: one answer for a colour, whatever asks. Only a truecolor
    /// colour has others so chosen; any other colour, or a tolerance of 0, is itself. Remembered
    /// per thread ([`CHEAPEST`]): the encoder asks it of each colour it prices.
    #[inline(always)] // (the encoder asks it of palette colours too: those return at once)
    #[must_use]
    pub(crate) fn cheapest(self, tolerance: u8) -> PackedColor {
        if self.0.get() >> 24 != RGB || tolerance == 0 {
            return self;
        }
        self.cheapest_truecolor(tolerance)
    }

    /// [`PackedColor::cheapest`] of a truecolor colour, from the thread's memo or searched. Inlined,
    /// the search out of line ([`search_into`]): with the memo in [`Cell`](std::cell::Cell)s a hit
    /// is a few instructions (`turn_frames truecolor 120 40 2 rep turn`: the encoder's instructions
    /// 0.96× those with it out of line; 256 colours 1.00×).
    #[inline]
    fn cheapest_truecolor(self, tolerance: u8) -> PackedColor {
        let word = self.0.get();
        // (An RGB word with the tolerance in its kind byte: never zero, the empty slot.)
        let key = word & 0x00ff_ffff | u32::from(tolerance) << 24;
        let slot = (key.wrapping_mul(0x9E37_79B1) >> (32 - CHEAPEST_SLOTS.trailing_zeros())) as usize;
        let found = CHEAPEST.with(|memo| {
            let (held, found) = memo[slot].get();
            if held == key { found } else { search_into(&memo[slot], key, word, tolerance) }
        });
        PackedColor(NonZeroU32::new(found).unwrap_or(self.0))
    }
}

/// [`PackedColor::within`] of a truecolor colour and a palette entry (either way round): the entry
/// by xterm's RGB for it, if it is past the 16 ANSI colours. Out of line, the rare case: `within`
/// stays small enough to inline in the encoder's loops (called, a served frame's encoder took 1.05×
/// `74feba5`'s instructions, inlined 1.03×: `load --callgrind`).
#[inline(never)]
fn rgb_within_entry(a: u32, b: u32, limit: f32) -> bool {
    let (rgb, entry) = if a >> 24 == RGB { (a, b) } else { (b, a) };
    entry & 0xff >= 16 && distance2(oklab([rgb])[0], PALETTE.oklab[(entry & 0xff) as usize]) <= limit * limit
}

/// The bytes of the SGR parameters of a truecolor colour (`38;2;r;g;b`) or a palette entry 16–255
/// (`38;5;n`), as the encoder writes them and prices them (its SGR writer reads it); 2 for any
/// other colour (`3x`, `9x`: [`PackedColor::cheapest`] never chooses one).
#[inline]
#[must_use]
pub(crate) fn code_len(color: PackedColor) -> usize {
    let digits = |n: u8| 1 + usize::from(n >= 10) + usize::from(n >= 100);
    let [kind, r, g, b] = color.0.get().to_be_bytes();
    match u32::from(kind) {
        RGB => 7 + digits(r) + digits(g) + digits(b),
        INDEXED if b >= 16 => 5 + digits(b),
        _ => 2,
    }
}

/// [`PackedColor::cheapest`] of truecolor `word`, searched among a few candidates (not every colour
/// within the reach: those nearest the colour, where the short codes are; up to a tolerance of 3,
/// every palette entry within the reach is among them, a test finds): the eight cube
/// entries of each channel's levels either side of it, the three greys of the ramp nearest the
/// channels' mean; then, where no entry is within the reach, the colour with each channel of
/// 100 or more taken to 99, of 10–99 to 9, in every combination.
fn search_cheapest(word: u32, tolerance: u8) -> u32 {
    let limit = f32::from(tolerance) * TOLERANCE_STEP * SHORT_CODE_REACH;
    let limit2 = limit * limit;
    let here = convert(word);
    let [_, r, g, b] = word.to_be_bytes();
    // (length, squared distance, word): the smallest wins.
    let mut best = (code_len(PackedColor(NonZeroU32::new(word).unwrap_or(NonZeroU32::MIN))), 0.0f32, word);
    let consider = |best: &mut (usize, f32, u32), candidate: u32, there: [f32; 3]| {
        let len = code_len(PackedColor(NonZeroU32::new(candidate).unwrap_or(NonZeroU32::MIN)));
        if len > best.0 {
            return;
        }
        let d = distance2(here, there);
        if d <= limit2 && (len, d, candidate) < *best {
            *best = (len, d, candidate);
        }
    };
    // Each channel's cube levels at or below it and at or above it (one where it is a level).
    let levels = |v: u8| {
        let above = super::CUBE_LEVELS.iter().position(|&l| l >= v).unwrap_or(5);
        [above.saturating_sub(usize::from(super::CUBE_LEVELS[above] > v)), above]
    };
    let ([r0, r1], [g0, g1], [b0, b1]) = (levels(r), levels(g), levels(b));
    for (i, j, k) in [r0, r1]
        .into_iter()
        .flat_map(|i| [g0, g1].into_iter().flat_map(move |j| [b0, b1].into_iter().map(move |k| (i, j, k))))
    {
        let n = 16 + 36 * i + 6 * j + k;
        consider(&mut best, INDEXED << 24 | n as u32, PALETTE.oklab[n]);
    }
    let mean = (u32::from(r) + u32::from(g) + u32::from(b)) / 3;
    let grey = (mean.saturating_sub(3) / 10).min(23) as usize; // the ramp's 8 + 10k nearest the mean
    for n in [232 + grey.saturating_sub(1), 232 + grey, 232 + (grey + 1).min(23)] {
        consider(&mut best, INDEXED << 24 | n as u32, PALETTE.oklab[n]);
    }
    if best.0 <= 8 {
        return best.2; // an entry: no truecolor code is as short
    }
    let fewer = |v: u8| match v {
        100.. => Some(99),
        10..=99 => Some(9),
        _ => None,
    };
    for mask in 1..8u8 {
        let channel = |i: u8, v: u8| if mask >> i & 1 == 1 { fewer(v) } else { Some(v) };
        let (Some(r), Some(g), Some(b)) = (channel(0, r), channel(1, g), channel(2, b)) else { continue };
        let candidate = u32::from_be_bytes([RGB as u8, r, g, b]);
        consider(&mut best, candidate, convert(candidate));
    }
    best.2
}

/// How far off its colour [`PackedColor::cheapest`] may choose a colour, as a share of the
/// tolerance (1.4 steps, an OKLab distance of 0.014, at the default of 2). Not all of it: a colour
/// sent that far off leaves the cell less of the tolerance to drift in before it is sent again
/// (walking, the floor's and ceiling's slow shades), and the picture strays further. `bandwidth`
/// at 120×40 against the whole tolerance (1.0) and none (0): walking 29.4 KB/s (29.8, 31.1), in
/// tmux 48.0 (49.5, 49.7), turning 121.6 (106.6, 131.8), the picture's mean distance 0.0049
/// (0.0075, 0.0044) while walking.
pub(crate) const SHORT_CODE_REACH: f32 = 0.7;

/// Slots of [`CHEAPEST`]: a power of two.
const CHEAPEST_SLOTS: usize = 1 << 12;

thread_local! {
    /// [`PackedColor::cheapest`]'s answers lately on this thread, by a hash of the colour and the
    /// tolerance (0: empty). A pure function of them: it changes no answer.
    static CHEAPEST: [std::cell::Cell<(u32, u32)>; CHEAPEST_SLOTS] =
        const { [const { std::cell::Cell::new((0, 0)) }; CHEAPEST_SLOTS] };
}

/// [`search_cheapest`] of `word`, put in [`CHEAPEST`]'s `entry` under `key` (the memo's miss: out
/// of line, so that its hit stays small).
#[cold]
#[inline(never)]
fn search_into(entry: &std::cell::Cell<(u32, u32)>, key: u32, word: u32, tolerance: u8) -> u32 {
    let found = search_cheapest(word, tolerance);
    entry.set((key, found));
    found
}

/// Whether `a[0]` is within `tolerance` of `b[0]` and `a[1]` of `b[1]` ([`PackedColor::within`]),
/// with one visit to the memo where both pairs are two different truecolor colours (the diff's
/// usual question of a cell whose shade moved: ink against ink, paper against paper).
#[inline]
fn both_within(a: [PackedColor; 2], b: [PackedColor; 2], tolerance: u8) -> bool {
    let rgb = |c: &PackedColor| c.0.get() >> 24 == RGB;
    if tolerance > 0 && a[0] != b[0] && a[1] != b[1] && a.iter().chain(&b).all(rgb) {
        let limit = f32::from(tolerance) * TOLERANCE_STEP;
        let [p0, p1, q0, q1] = oklab([a[0], a[1], b[0], b[1]].map(|c| c.0.get()));
        return distance2(p0, q0) <= limit * limit && distance2(p1, q1) <= limit * limit;
    }
    a[0].within(b[0], tolerance) && a[1].within(b[1], tolerance)
}

/// One step of the truecolor tolerance: an OKLab distance (ΔE_OK) of 0.01, about half of what an eye
/// can tell apart side by side (a just-noticeable difference is about 0.02). Perceptual rather than
/// per channel: an 8-bit step is a bigger change in a dark colour than in a light one, so a wall's
/// slow falloff with distance stays within a step or two of what was sent where the eye cannot see
/// it, and is resent where it can.
pub const TOLERANCE_STEP: f32 = 0.01;

/// The 8-bit sRGB codes' linear values (the sRGB transfer function), built once.
static LINEAR: std::sync::LazyLock<[f32; 256]> = std::sync::LazyLock::new(|| {
    std::array::from_fn(|code| {
        let v = code as f64 / 255.0;
        (if v <= 0.040_45 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }) as f32
    })
});

/// The squared OKLab distance of two colours.
#[inline]
fn distance2(p: [f32; 3], q: [f32; 3]) -> f32 {
    let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

/// xterm's 256 palette entries as the tolerance sees them.
struct Palette {
    /// The OKLab of each entry's RGB ([`super::xterm_rgb`]), by the same conversion as a truecolor
    /// colour's: an entry and its RGB as a truecolor colour are the same distance from anything.
    oklab: [[f32; 3]; 256],
    /// For entries 16–255, the squared distance ([`distance2`], as [`PackedColor::within`] computes it)
    /// to the nearest other entry 16–255; infinite for the 16 ANSI colours.
    nearest: [f32; 256],
}

/// [`Palette`], built on first use (256 conversions and 240² distances: some µs).
static PALETTE: std::sync::LazyLock<Palette> = std::sync::LazyLock::new(|| {
    let oklab: [[f32; 3]; 256] = std::array::from_fn(|index| {
        let [r, g, b] = super::xterm_rgb(index as u8);
        convert(u32::from_be_bytes([RGB as u8, r, g, b]))
    });
    let nearest = std::array::from_fn(|i| {
        (16..256)
            .filter(|&j| i >= 16 && j != i)
            .map(|j| distance2(oklab[i], oklab[j]))
            .fold(f32::INFINITY, f32::min)
    });
    Palette { oklab, nearest }
});

/// Slots of [`MEMO`]: a power of two.
const MEMO_SLOTS: usize = 1 << 12;

thread_local! {
    /// The OKLab of the colours met lately on this thread, by a hash of the word (0: empty; no
    /// truecolor word is 0). A frame has a few thousand colours and the encoder asks about each
    /// several times (against the screen, the pen, its other half), at a fifth of a conversion's cost.
    /// What it holds is a pure function of the word: it changes no answer. Cells rather than a
    /// `RefCell`: a lookup checks and sets no borrow flag, and with the conversion out of line
    /// ([`convert_into`]) the visit is small enough to inline at most of the encoder's calls.
    static MEMO: [std::cell::Cell<(u32, [f32; 3])>; MEMO_SLOTS] =
        const { [const { std::cell::Cell::new((0, [0.0; 3])) }; MEMO_SLOTS] };
}

/// [`convert`] of the words, remembered ([`MEMO`]; one visit to the thread's memo for them all).
#[inline]
fn oklab<const N: usize>(words: [u32; N]) -> [[f32; 3]; N] {
    MEMO.with(|memo| {
        words.map(|word| {
            let entry =
                &memo[(word.wrapping_mul(0x9E37_79B1) >> (32 - MEMO_SLOTS.trailing_zeros())) as usize];
            let (held, lab) = entry.get();
            if held == word { lab } else { convert_into(entry, word) }
        })
    })
}

/// [`convert`] of `word`, put in the memo's `entry` (the memo's miss: out of line, so that its hit
/// stays small).
#[cold]
#[inline(never)]
fn convert_into(entry: &std::cell::Cell<(u32, [f32; 3])>, word: u32) -> [f32; 3] {
    let lab = convert(word);
    entry.set((word, lab));
    lab
}

/// The OKLab coordinates (L, a, b) of a truecolor word `0x01RRGGBB` (Björn Ottosson's matrices,
/// <https://bottosson.github.io/posts/oklab/>).
#[inline]
fn convert(word: u32) -> [f32; 3] {
    let table = &*LINEAR;
    let [_, r, g, b] = word.to_be_bytes().map(|c| table[usize::from(c)]);
    super::oklab([r, g, b], cbrt)
}

/// The cube root of `x` in [0, 1] (a linear colour's cone response), to 2e-6 of it: a first guess
/// from the float's bits (a third of the exponent and mantissa), then two Newton steps, with no call
/// or branch.
#[inline]
fn cbrt(x: f32) -> f32 {
    let x = x.max(1e-12); // black: its root is 1e-4, as near 0 as an OKLab distance can tell
    let mut y = f32::from_bits(x.to_bits() / 3 + 0x2a50_8935);
    for _ in 0..2 {
        y = (2.0 * y + x / (y * y)) * (1.0 / 3.0);
    }
    y
}

/// A [`Cell`] with [`PackedColor`]s: comparing two is comparing three words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PackedCell {
    /// The glyph.
    pub(crate) ch: char,
    /// Foreground colour (the glyph's ink).
    pub(crate) fg: PackedColor,
    /// Background colour (the rest of the cell).
    pub(crate) bg: PackedColor,
}

impl PackedCell {
    /// `cell`, packed.
    #[inline]
    #[must_use]
    pub(crate) fn pack(cell: &Cell) -> PackedCell {
        PackedCell { ch: cell.ch, fg: PackedColor::pack(cell.fg), bg: PackedColor::pack(cell.bg) }
    }

    /// The cell it packs.
    #[inline]
    #[must_use]
    pub(crate) fn unpack(self) -> Cell {
        Cell { ch: self.ch, fg: self.fg.unpack(), bg: self.bg.unpack() }
    }

    /// [`Cell::inverse`].
    #[must_use]
    pub(crate) fn inverse(&self) -> Option<PackedCell> {
        if self.shows_a_default() {
            return None;
        }
        complement_glyph(self.ch).map(|ch| PackedCell { ch, fg: self.bg, bg: self.fg })
    }

    /// Whether the cell is a space in text: a blank whose ink is not its paper, as
    /// [`Frame::put_str`](crate::frame::Frame::put_str) and the overlays write them (a blank of the
    /// picture has ink and paper equal: [`PackedCell::canonical`]). The encoder sends it as a space,
    /// never as a full block in its paper that looks the same: text reads back as written.
    #[inline]
    #[must_use]
    pub(crate) fn is_text_space(&self) -> bool {
        self.ch == ' ' && self.fg != self.bg
    }

    /// Whether the cell shows the terminal's default foreground or background (a space shows no
    /// foreground, a full block no background).
    #[inline]
    fn shows_a_default(&self) -> bool {
        (self.ch != ' ' && self.fg == PackedColor::DEFAULT)
            || (self.ch != FULL_BLOCK && self.bg == PackedColor::DEFAULT)
    }

    /// Whether another colour may be within `tolerance` of one of its colours
    /// ([`PackedColor::may_be_near`]); where not, it looks within the tolerance only of cells that
    /// look the same.
    #[inline]
    #[must_use]
    pub(crate) fn may_be_near(&self, tolerance: u8) -> bool {
        self.fg.may_be_near(tolerance) || self.bg.may_be_near(tolerance)
    }

    /// [`Cell::looks_within`].
    #[must_use]
    #[inline] // the diff calls it on every cell of every frame: the common cases without a call
    pub(crate) fn looks_within(&self, other: &PackedCell, tolerance: u8) -> bool {
        // The diff's common case first, then the next most common (a shade drifting by a step).
        if self == other {
            return true;
        }
        if self.ch == other.ch {
            // The same glyph: ink against ink, paper against paper (what the regions come to when the
            // masks are equal; a space has no ink, a full block no paper).
            return match self.ch {
                ' ' => self.bg.within(other.bg, tolerance),
                FULL_BLOCK => self.fg.within(other.fg, tolerance),
                _ => both_within([self.fg, self.bg], [other.fg, other.bg], tolerance),
            };
        }
        if tolerance == 0 {
            return self.looks_same_other_glyph(other);
        }
        self.looks_within_other_glyph(other, tolerance)
    }

    /// [`PackedCell::looks_within_other_glyph`] at tolerance 0, where every colour comparison is
    /// equality (the exact path's question, and the end of an encode's: two spellings of one look).
    #[inline(never)]
    fn looks_same_other_glyph(&self, other: &PackedCell) -> bool {
        self.looks_within_other_glyph_inline(other, 0)
    }

    /// [`PackedCell::looks_within`] for two different glyphs (out of line: the diff's inlined loop
    /// stays small).
    #[inline(never)]
    fn looks_within_other_glyph(&self, other: &PackedCell, tolerance: u8) -> bool {
        self.looks_within_other_glyph_inline(other, tolerance)
    }

    /// [`PackedCell::looks_within_other_glyph`]'s body, inlined into it and its tolerance 0 form.
    #[inline(always)]
    fn looks_within_other_glyph_inline(&self, other: &PackedCell, tolerance: u8) -> bool {
        // Half blocks (the default charset) and blanks: a top and a bottom half to compare.
        if let (Some(a), Some(b)) = (self.halves(), other.halves()) {
            return both_within(a, b, tolerance);
        }
        self.looks_within_by_regions(other, tolerance)
    }

    /// The colours of the top and bottom halves of a blank, a half block or a full block; `None` for
    /// other glyphs, and where a half shows a default colour (compared by layers instead).
    #[inline]
    pub(crate) fn halves(&self) -> Option<[PackedColor; 2]> {
        if self.shows_a_default() {
            return None;
        }
        match self.ch {
            ' ' => Some([self.bg; 2]),
            FULL_BLOCK => Some([self.fg; 2]),
            '▀' => Some([self.fg, self.bg]),
            '▄' => Some([self.bg, self.fg]),
            _ => None,
        }
    }

    /// [`PackedCell::looks_within`] region by region.
    fn looks_within_by_regions(&self, other: &PackedCell, tolerance: u8) -> bool {
        let (Some(ink_a), Some(ink_b)) = (ink_mask(self.ch), ink_mask(other.ch)) else {
            return self.ch == other.ch
                && self.fg.within(other.fg, tolerance)
                && self.bg.within(other.bg, tolerance);
        };
        // The (up to) four regions where each cell shows its ink or its paper.
        [(true, true), (true, false), (false, true), (false, false)].into_iter().all(|(in_a, in_b)| {
            let side = |ink: u16, inside: bool| if inside { ink } else { !ink & ALL_SUBCELLS };
            let color = |cell: &PackedCell, inside: bool| if inside { cell.fg } else { cell.bg };
            let (a, b) = (color(self, in_a), color(other, in_b));
            // The default foreground and the default background are two colours.
            let defaults_agree = (a != PackedColor::DEFAULT && b != PackedColor::DEFAULT) || in_a == in_b;
            side(ink_a, in_a) & side(ink_b, in_b) == 0 || (defaults_agree && a.within(b, tolerance))
        })
    }

    /// [`Cell::canonical`].
    #[inline]
    #[must_use]
    pub(crate) fn canonical(&self) -> PackedCell {
        // (Not in the defaults: a glyph in the default foreground on the default background shows two.)
        if self.fg == self.bg && self.fg != PackedColor::DEFAULT && complement_glyph(self.ch).is_some() {
            PackedCell { ch: ' ', ..*self }
        } else {
            *self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_testkit::{oklab as oklab_f64, oklab_distance};

    /// Issue #42: the colour of the shortest code within the tolerance is within it (by an f64
    /// oracle, a hair of slack), its code no longer than the colour's own, never an ANSI colour
    /// (0–15, the theme's); where any palette entry 16–255 is within the tolerance, it is one of the
    /// shortest such (against a search of all 240, at tolerances up to 3: the search looks near the
    /// colour only); itself at tolerance 0 and for colours other
    /// than truecolor; the same answer asked again, and asked first at another tolerance.
    #[test]
    fn the_cheapest_colour_within_the_tolerance_is_within_it_and_no_longer() {
        let mut seed = 0x1234_5678_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        let mut colours: Vec<[u8; 3]> =
            (0..4000).map(|_| next().to_be_bytes()).map(|[_, r, g, b]| [r, g, b]).collect();
        // Near the short codes: the cube's levels and the greys, channels about 100 and 10.
        for v in [0u8, 8, 9, 10, 11, 12, 18, 93, 95, 97, 99, 100, 101, 103, 104, 118, 135, 136, 178, 255] {
            colours.extend([[v, v, v], [v, 95, 135], [100, v, 12], [v, v.wrapping_add(1), v]]);
        }
        let entry_len = |n: u8| 5 + if n >= 100 { 3 } else { 2 };
        let (mut entries, mut fewer_digits) = (0, 0);
        for tolerance in [0u8, 1, 2, 3, 5] {
            let limit = f64::from(tolerance) * f64::from(TOLERANCE_STEP) + 1e-5;
            for &[r, g, b] in &colours {
                let colour = PackedColor::pack(Color::Rgb(r, g, b));
                let cheap = colour.cheapest(tolerance);
                assert_eq!(cheap, colour.cheapest(tolerance));
                assert!(code_len(cheap) <= code_len(colour), "{colour:?} {cheap:?}");
                assert!(cheap.within(colour, tolerance) && colour.within(cheap, tolerance));
                let shown = match cheap.unpack() {
                    Color::Rgb(r, g, b) => [r, g, b],
                    Color::Indexed(n) => {
                        assert!(n >= 16, "{colour:?} as ANSI colour {n}");
                        entries += 1;
                        crate::frame::xterm_rgb(n)
                    }
                    Color::Default => panic!("{colour:?} as the default"),
                };
                assert!(oklab_distance([r, g, b], shown) <= limit, "{colour:?} {cheap:?} at {tolerance}");
                if tolerance == 0 {
                    assert_eq!(cheap, colour);
                }
                if matches!(cheap.unpack(), Color::Rgb(..)) && cheap != colour {
                    fewer_digits += 1;
                }
                // Every entry within its reach, by the same arithmetic as `within`.
                let reach = f32::from(tolerance) * TOLERANCE_STEP * SHORT_CODE_REACH;
                let here = convert(colour.word());
                let shortest_entry = (16..=255u8)
                    .filter(|&n| distance2(here, PALETTE.oklab[usize::from(n)]) <= reach * reach)
                    .map(entry_len)
                    .min();
                if let Some(len) = shortest_entry.filter(|_| (1..=3).contains(&tolerance)) {
                    assert_eq!(code_len(cheap), len, "{colour:?} {cheap:?} at {tolerance}");
                }
            }
        }
        for other in [Color::Default, Color::Indexed(3), Color::Indexed(100), Color::Indexed(244)] {
            assert_eq!(PackedColor::pack(other).cheapest(2), PackedColor::pack(other));
        }
        assert!(entries > 200 && fewer_digits > 20, "entries {entries}, fewer digits {fewer_digits}");
        let grey = PackedColor::pack(Color::Rgb(100, 100, 100));
        // The ramp's 98 grey (`38;5;241`, 0.007 off); the cube's 95 (`38;5;59`, a byte shorter) is
        // 0.018 off, beyond the reach (0.014).
        assert_eq!(grey.cheapest(2).unpack(), Color::Indexed(241));
        assert_eq!(grey.cheapest(0), grey);
    }

    /// Every colour has one spelling: packing is one-to-one and unpacking gives the colour back; the
    /// tolerance applies to truecolor colours and palette entries 16–255 (by xterm's RGB, either
    /// against either), as an OKLab distance (against an f64 oracle; pairs within 1e-5 of the limit,
    /// where f32 rounding may go either way, are not held to it).
    #[test]
    fn a_packed_colour_is_the_colour_and_equal_words_are_equal_colours() {
        let mut colors = vec![Color::Default];
        colors.extend((0..=255).map(Color::Indexed));
        colors.extend([0, 1, 2, 3, 20, 21, 127, 128, 130, 254, 255].iter().flat_map(|&r| {
            [0, 7, 8, 250, 255].iter().flat_map(move |&g| [0, 9, 12, 255].map(|b| Color::Rgb(r, g, b)))
        }));
        let mut near_limit = 0;
        for &a in &colors {
            assert_eq!(PackedColor::pack(a).unpack(), a);
            assert_eq!(
                PackedColor::pack(a).is_tolerant(),
                matches!(a, Color::Rgb(..) | Color::Indexed(16..))
            );
            for &b in &colors {
                assert_eq!(PackedColor::pack(a) == PackedColor::pack(b), a == b, "{a:?} {b:?}");
                for tolerance in [0, 1, 2, 5, 16, 200] {
                    // Truecolor colours, and palette entries past the 16 ANSI colours by their xterm RGB
                    // (either against either).
                    let rgb = |c: Color| match c {
                        Color::Rgb(r, g, b) => Some([r, g, b]),
                        Color::Indexed(n @ 16..) => Some(crate::frame::xterm_rgb(n)),
                        _ => None,
                    };
                    let within = match (rgb(a), rgb(b)) {
                        _ if a == b => Some(true),
                        (Some(p), Some(q)) if tolerance > 0 => {
                            let d = oklab_distance(p, q);
                            let limit = f64::from(tolerance) * f64::from(TOLERANCE_STEP);
                            ((d - limit).abs() > 1e-5).then_some(d <= limit)
                        }
                        _ => Some(false),
                    };
                    match within {
                        Some(within) => assert_eq!(
                            PackedColor::pack(a).within(PackedColor::pack(b), tolerance),
                            within,
                            "{a:?} {b:?} within {tolerance}"
                        ),
                        None => near_limit += 1,
                    }
                }
            }
        }
        assert!(near_limit < 50, "{near_limit} pairs too near the limit to tell");
        // The palette's closest pairs are a cube grey and a ramp grey (95 and 98): within a step and a
        // half. Its neighbouring greys are 0.03–0.05 apart.
        let entry = |n: u8| PackedColor::pack(Color::Indexed(n));
        assert!(entry(59).within(entry(241), 2) && !entry(59).within(entry(241), 1));
        assert!(!entry(254).within(entry(255), 2) && entry(254).within(entry(255), 4));
        // Whether an entry may be near another is exactly whether one is within the tolerance of it
        // (the encoder's exact path is taken for cells of entries that are not).
        for tolerance in 0..=16 {
            let mut near = 0;
            for a in 0..=255 {
                let partner = (16..=255).any(|b| a != b && entry(a).within(entry(b), tolerance));
                assert_eq!(entry(a).may_be_near(tolerance), partner, "{a} at {tolerance}");
                near += usize::from(partner);
            }
            if tolerance == 2 {
                assert_eq!(near, 8, "the four close pairs");
            }
        }
        assert!(
            PackedColor::pack(Color::Rgb(1, 2, 3)).may_be_near(1) && !PackedColor::DEFAULT.may_be_near(16)
        );
        // The 16 ANSI colours are the theme's: exact, even where xterm's defaults coincide with an entry.
        assert!(!entry(0).within(entry(16), 16) && !entry(15).within(entry(231), 16));
        // One 8-bit step is a bigger change in a dark colour than in a light one.
        let step = |v: u8| oklab_f64([v + 1; 3])[0] - oklab_f64([v; 3])[0];
        assert!(step(2) > 0.012 && step(250) < 0.003, "{} {}", step(2), step(250));
        let (dark, light) = ((2, 3), (250, 251));
        let grey = |v: u8| PackedColor::pack(Color::Rgb(v, v, v));
        assert!(!grey(dark.0).within(grey(dark.1), 1) && grey(light.0).within(grey(light.1), 1));
        assert_eq!(std::mem::size_of::<Option<PackedColor>>(), 4);
    }
}
