//! The Unicode block elements a cell can show, as masks of the cell's parts: half blocks (2 rows),
//! quadrants (2 × 2), sextants (2 × 3, Unicode 13's "Symbols for Legacy Computing"), and what a glyph
//! inks on a common 2 × 6 grid so that any two can be compared ([`ink_mask`]) or swapped for their
//! complement in swapped colours ([`complement_glyph`]).
//!
//! ```
//! use mazewalk_term::blocks::{HALF, QUAD, complement_glyph, sextant_glyph};
//! assert_eq!(HALF[0b01], '▀'); // bit 0 top, bit 1 bottom
//! assert_eq!(QUAD[0b0110], '▞'); // bits: top-left, top-right, bottom-left, bottom-right
//! assert_eq!(sextant_glyph(0b000001), '🬀'); // bit 0 top-left … bit 5 bottom-right
//! assert_eq!(complement_glyph('▘'), Some('▟'));
//! ```

/// Quadrant glyphs by mask (bit 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right).
pub const QUAD: [char; 16] = [' ', '▘', '▝', '▀', '▖', '▌', '▞', '▛', '▗', '▚', '▐', '▜', '▄', '▙', '▟', '█'];

/// The half-block glyphs by mask (bit 0 top, bit 1 bottom).
pub const HALF: [char; 4] = [' ', '▀', '▄', '█'];

/// The sextant glyph for a 6-bit mask (bit 0 top-left, 1 top-right, 2 middle-left, … 5 bottom-right).
///
/// U+1FB00 `BLOCK SEXTANT-1` … U+1FB3B `BLOCK SEXTANT-23456` list the masks 1–62 in order, leaving out
/// the two half blocks that already exist (left column `▌` = 21, right column `▐` = 42).
#[must_use]
pub fn sextant_glyph(mask: u8) -> char {
    let mask = u32::from(mask & 63);
    match mask {
        0 => ' ',
        21 => '▌',
        42 => '▐',
        63 => '█',
        _ => {
            let skipped = u32::from(mask > 21) + u32::from(mask > 42);
            char::from_u32(0x1FB00 + mask - 1 - skipped).unwrap_or('?')
        }
    }
}

/// `█`: every part of the cell inked.
pub(crate) const FULL_BLOCK: char = '█';

/// Every sub-cell of the 2×6 grid [`ink_mask`] works on.
pub(crate) const ALL_SUBCELLS: u16 = 0xFFF;

/// The sub-cells a block glyph inks, on a 2×6 grid (bit `x + 2·y`, y down): a half block is 3 sub-rows
/// high, a quadrant 1 column × 3 sub-rows, a sextant 1 column × 2 sub-rows. `None` for other glyphs.
pub(crate) fn ink_mask(ch: char) -> Option<u16> {
    // Quadrants of the 2×6 grid: top-left, top-right, bottom-left, bottom-right.
    const TL: u16 = 0x015;
    const TR: u16 = 0x02A;
    const BL: u16 = 0x540;
    const BR: u16 = 0xA80;
    Some(match ch {
        ' ' => 0,
        FULL_BLOCK => ALL_SUBCELLS,
        '▀' => TL | TR,
        '▄' => BL | BR,
        '▌' => TL | BL,
        '▐' => TR | BR,
        '▘' => TL,
        '▝' => TR,
        '▖' => BL,
        '▗' => BR,
        '▞' => TR | BL,
        '▚' => TL | BR,
        '▛' => TL | TR | BL,
        '▜' => TL | TR | BR,
        '▙' => TL | BL | BR,
        '▟' => TR | BL | BR,
        _ => {
            // Sextant bit k is column k % 2 of sextant row k / 2, i.e. sub-rows 2·(k / 2) and the next.
            let sextant = sextant_mask(ch)?;
            (0..6).filter(|k| sextant & (1 << k) != 0).map(|k| 0b101 << (k % 2 + 4 * (k / 2))).sum()
        }
    })
}

/// The 6-bit mask of a sextant glyph (bit 0 top-left, 1 top-right, 2 middle-left, … 5 bottom-right):
/// U+1FB00–U+1FB3B list the masks 1–62 in order without 21 (`▌`) and 42 (`▐`).
pub(crate) fn sextant_mask(ch: char) -> Option<u32> {
    let index = u32::from(ch).checked_sub(0x1FB00).filter(|&i| i < 60)?;
    let mask = index + 1 + u32::from(index + 1 >= 21);
    Some(mask + u32::from(mask >= 42))
}

/// The block glyph covering exactly the part of the cell `ch` leaves empty, for the block glyphs whose
/// complement is also one: space and full block, the halves, the quadrants and the sextants.
pub fn complement_glyph(ch: char) -> Option<char> {
    Some(match ch {
        ' ' => FULL_BLOCK,
        FULL_BLOCK => ' ',
        '▀' => '▄',
        '▄' => '▀',
        '▌' => '▐',
        '▐' => '▌',
        '▘' => '▟',
        '▟' => '▘',
        '▝' => '▙',
        '▙' => '▝',
        '▖' => '▜',
        '▜' => '▖',
        '▗' => '▛',
        '▛' => '▗',
        '▞' => '▚',
        '▚' => '▞',
        // Sextants: the complement of mask m is 63 − m.
        _ => sextant_glyph(63 - sextant_mask(ch)? as u8),
    })
}
