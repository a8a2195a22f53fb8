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
    /// truecolor colours that close, or two palette entries 16–255 whose xterm RGB are), or equal (any
    /// colours).
    #[inline]
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
            _ => return false,
        };
        distance2(p, q) <= limit * limit
    }
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
    /// What it holds is a pure function of the word: it changes no answer.
    static MEMO: std::cell::RefCell<[(u32, [f32; 3]); MEMO_SLOTS]> =
        const { std::cell::RefCell::new([(0, [0.0; 3]); MEMO_SLOTS]) };
}

/// [`convert`] of the words, remembered ([`MEMO`]; one visit to the thread's memo for them all).
#[inline]
fn oklab<const N: usize>(words: [u32; N]) -> [[f32; 3]; N] {
    MEMO.with_borrow_mut(|memo| {
        words.map(|word| {
            let entry =
                &mut memo[(word.wrapping_mul(0x9E37_79B1) >> (32 - MEMO_SLOTS.trailing_zeros())) as usize];
            if entry.0 != word {
                *entry = (word, convert(word));
            }
            entry.1
        })
    })
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
        self.looks_within_other_glyph(other, tolerance)
    }

    /// [`PackedCell::looks_within`] for two different glyphs (out of line: the diff's inlined loop
    /// stays small).
    #[inline(never)]
    fn looks_within_other_glyph(&self, other: &PackedCell, tolerance: u8) -> bool {
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

    /// Every colour has one spelling: packing is one-to-one and unpacking gives the colour back; the
    /// tolerance applies to truecolor colours alone, as an OKLab distance (against an f64 oracle; pairs
    /// within 1e-5 of the limit, where f32 rounding may go either way, are not held to it).
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
                    // Truecolor colours, and palette entries past the 16 ANSI colours by their xterm RGB.
                    let rgb = |c: Color| match c {
                        Color::Rgb(r, g, b) => Some((0, [r, g, b])),
                        Color::Indexed(n @ 16..) => Some((1, crate::frame::xterm_rgb(n))),
                        _ => None,
                    };
                    let within = match (rgb(a), rgb(b)) {
                        _ if a == b => Some(true),
                        (Some((kind, p)), Some((kind2, q))) if tolerance > 0 && kind == kind2 => {
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
