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

    /// Whether it is a truecolor colour, the only kind a tolerance applies to.
    #[inline]
    #[must_use]
    pub(crate) fn is_rgb(self) -> bool {
        self.0.get() >> 24 == RGB
    }

    /// Whether two colours are within `tolerance` 8-bit steps per channel: truecolor colours that
    /// close, or any colours that are equal.
    #[inline]
    #[must_use]
    pub(crate) fn within(self, other: PackedColor, tolerance: u8) -> bool {
        let (a, b) = (self.0.get(), other.0.get());
        if a == b {
            return true;
        }
        // Both truecolor: the kinds are 1, 2 and 3, and only 1 | 1 is 1.
        let channel = |shift: u32| ((a >> shift) as u8).abs_diff((b >> shift) as u8) <= tolerance;
        (a | b) >> 24 == RGB && channel(16) && channel(8) && channel(0)
    }
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

    /// Whether the cell shows the terminal's default foreground or background (a space shows no
    /// foreground, a full block no background).
    #[inline]
    fn shows_a_default(&self) -> bool {
        (self.ch != ' ' && self.fg == PackedColor::DEFAULT)
            || (self.ch != FULL_BLOCK && self.bg == PackedColor::DEFAULT)
    }

    /// Whether it has a truecolor colour, the only kind a tolerance applies to.
    #[inline]
    #[must_use]
    pub(crate) fn has_rgb(&self) -> bool {
        self.fg.is_rgb() || self.bg.is_rgb()
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
            return (self.ch == ' ' || self.fg.within(other.fg, tolerance))
                && (self.ch == FULL_BLOCK || self.bg.within(other.bg, tolerance));
        }
        self.looks_within_other_glyph(other, tolerance)
    }

    /// [`PackedCell::looks_within`] for two different glyphs (out of line: the diff's inlined loop
    /// stays small).
    #[inline(never)]
    fn looks_within_other_glyph(&self, other: &PackedCell, tolerance: u8) -> bool {
        // Half blocks (the default charset) and blanks: a top and a bottom half to compare.
        if let (Some(a), Some(b)) = (self.halves(), other.halves()) {
            return a[0].within(b[0], tolerance) && a[1].within(b[1], tolerance);
        }
        self.looks_within_by_regions(other, tolerance)
    }

    /// The colours of the top and bottom halves of a blank, a half block or a full block; `None` for
    /// other glyphs, and where a half shows a default colour (compared by layers instead).
    #[inline]
    fn halves(&self) -> Option<[PackedColor; 2]> {
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

    /// Every colour has one spelling: packing is one-to-one and unpacking gives the colour back, and
    /// the tolerance applies to truecolor channels alone.
    #[test]
    fn a_packed_colour_is_the_colour_and_equal_words_are_equal_colours() {
        let mut colors = vec![Color::Default];
        colors.extend((0..=255).map(Color::Indexed));
        colors.extend(
            [0, 1, 2, 127, 128, 254, 255].iter().flat_map(|&r| {
                [0, 7, 255].iter().flat_map(move |&g| [0, 9, 255].map(|b| Color::Rgb(r, g, b)))
            }),
        );
        for &a in &colors {
            assert_eq!(PackedColor::pack(a).unpack(), a);
            assert_eq!(PackedColor::pack(a).is_rgb(), matches!(a, Color::Rgb(..)));
            for &b in &colors {
                assert_eq!(PackedColor::pack(a) == PackedColor::pack(b), a == b, "{a:?} {b:?}");
                for tolerance in [0, 1, 2, 200] {
                    let within = match (a, b) {
                        (Color::Rgb(r, g, b), Color::Rgb(r2, g2, b2)) => [(r, r2), (g, g2), (b, b2)]
                            .iter()
                            .all(|&(x, y)| i32::from(x).abs_diff(i32::from(y)) <= u32::from(tolerance)),
                        _ => a == b,
                    };
                    assert_eq!(PackedColor::pack(a).within(PackedColor::pack(b), tolerance), within);
                }
            }
        }
        assert_eq!(std::mem::size_of::<Option<PackedColor>>(), 4);
    }
}
