//! Cursor moves: the shortest sequence from where the cursor is to where the next glyph goes, among
//! absolute `CUP`, relative `CUF`/`CUB`/`CUD`/`CUU`, `CHA`/`VPA`, `\r`, `\r\n`, vertical tabs and
//! backspace. (Rewriting unchanged cells instead of moving is the diff's choice: see `reach` in the
//! encoder.)

use super::{Pen, push_num};

/// Vertical part of a relative move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Vertical {
    Stay,
    /// `\r` (unless already in column 0) then `\n` × k: lands in column 0 whether or not `\n` implies
    /// `\r`. Only downwards, and never from the last row (the move's target is on screen).
    CrLf(usize),
    /// Vertical tabs (`\x0b`) × k: down k rows, same column, one byte each. The tty's output
    /// processing maps only `\n`, and the terminal treats VT as a line feed without a carriage
    /// return while line feed/new line mode (LNM) is reset, which a full paint does
    /// ([`RESET_LNM`]). Only downwards, never from the last row, as `CrLf`.
    Vt(usize),
    Down(usize),
    Up(usize),
    /// `VPA`: absolute row, same column.
    Row(usize),
}

/// Horizontal part of a relative move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Horizontal {
    Stay,
    Cr,
    Right(usize),
    Left(usize),
    /// Backspaces: one byte each.
    Back(usize),
    /// `CHA`: absolute column.
    Column(usize),
}

/// Reset line feed/new line mode (LNM, `CSI 20 l`): then a vertical tab moves down without a
/// carriage return ([`Vertical::Vt`]); sent with every full paint.
pub(super) const RESET_LNM: &[u8] = b"\x1b[20l";

/// Moves the cursor to column `x`, row `y` by the shortest sequence (nothing if it is there).
pub(super) fn write_move(out: &mut Vec<u8>, pen: &mut Pen, x: usize, y: usize) {
    if pen.cursor == Some((x, y)) {
        return; // the diff's usual case: the next changed cell is the one after the last
    }
    write_found(out, pen, find_move(pen, x, y));
}

/// A move [`find_move`] found from a pen: priced, and written by [`write_found`] from that pen
/// without searching again.
#[derive(Clone, Copy)]
pub(super) struct Move {
    x: usize,
    y: usize,
    /// Its bytes.
    pub(super) len: usize,
    route: Option<(Vertical, Horizontal)>,
}

/// The move [`write_move`] would send from `pen` to column `x`, row `y`.
pub(super) fn find_move(pen: &Pen, x: usize, y: usize) -> Move {
    let (len, route) = shortest_move(pen.cursor, x, y);
    Move { x, y, len, route }
}

/// Writes `found` ([`find_move`] from this pen) and updates the pen.
pub(super) fn write_found(out: &mut Vec<u8>, pen: &mut Pen, found: Move) {
    let Move { x, y, len, route } = found;
    let start = out.len();
    match (pen.cursor, route) {
        _ if pen.cursor == Some((x, y)) => {}
        (Some((cx, _)), Some((vertical, horizontal))) => write_relative(out, cx, vertical, horizontal),
        _ => write_cup(out, x, y),
    }
    debug_assert_eq!(out.len() - start, len);
    pen.cursor = Some((x, y));
}

/// The bytes [`write_move`] would send, leaving the pen as it would.
pub(super) fn move_len(pen: &mut Pen, x: usize, y: usize) -> usize {
    let (len, _) = shortest_move(pen.cursor, x, y);
    pen.cursor = Some((x, y));
    len
}

/// A bound on the bytes of the move [`write_move`] would send from `from` to (`x`, `y`), by
/// arithmetic alone: the shortest of `CUP` and a vertical step (vertical tabs, `CUD`, `CUU`) followed
/// by a horizontal one (`CUF`, `CUB`, backspaces, `\r`). [`shortest_move`] prices these routes among
/// others, so the move it finds is never longer. For moves priced and mostly not taken (`detours` in
/// the encoder).
#[inline(always)]
pub(super) fn move_bound(from: Option<(usize, usize)>, x: usize, y: usize) -> usize {
    use std::cmp::Ordering::{Equal, Greater, Less};
    let Some((cx, cy)) = from else { return cup_len(x, y) };
    let vertical = match y.cmp(&cy) {
        Equal => 0,
        Greater if y - cy <= 3 => y - cy,
        Greater => csi_len(y - cy, 1),
        Less => csi_len(cy - y, 1),
    };
    let horizontal = match x.cmp(&cx) {
        Equal => 0,
        Greater => csi_len(x - cx, 1),
        Less if x == 0 => 1,
        Less if cx - x <= 3 => cx - x,
        Less => csi_len(cx - x, 1),
    };
    let relative = vertical + horizontal;
    // (`CUP` is at least 3 bytes: a step that short is the bound without pricing it.)
    if relative <= 3 { relative } else { cup_len(x, y).min(relative) }
}

/// The vertical steps from row `cy` to row `y` a move may begin with, in the order a tie is broken
/// by (the first of the shortest wins); `None` where a step does not apply.
#[cfg(test)]
fn vertical_steps(cy: usize, y: usize) -> [Option<Vertical>; 6] {
    [
        Some(Vertical::Stay).filter(|_| cy == y),
        Some(Vertical::CrLf(y.wrapping_sub(cy))).filter(|_| y > cy),
        Some(Vertical::Vt(y.wrapping_sub(cy))).filter(|_| y > cy && y - cy <= 3),
        Some(Vertical::Down(y.wrapping_sub(cy))).filter(|_| y > cy),
        Some(Vertical::Up(cy.wrapping_sub(y))).filter(|_| y < cy),
        Some(Vertical::Row(y)).filter(|_| y != cy),
    ]
}

/// The shortest move from `from` to (`x`, `y`) and its bytes: a relative move, or `None` for `CUP`
/// (or for nothing, when the cursor is there). Priced by arithmetic; the first of the shortest in
/// this order, `CUP` first.
fn shortest_move(
    from: Option<(usize, usize)>,
    x: usize,
    y: usize,
) -> (usize, Option<(Vertical, Horizontal)>) {
    let Some((cx, cy)) = from else { return (cup_len(x, y), None) };
    if (cx, cy) == (x, y) {
        return (0, None);
    }
    if cy == y && x > cx {
        // The diff's usual move, on along the row: `CUF` is shorter than `CHA` (fewer digits) and `CUP`.
        return (csi_len(x - cx, 1), Some((Vertical::Stay, Horizontal::Right(x - cx))));
    }
    // Every vertical step, each followed by every horizontal one, in this order; the first of the
    // shortest pairs wins (`CUP` before them all). A pair's bytes are its vertical's plus its
    // horizontal's, and the horizontals after a vertical depend only on the column it leaves the
    // cursor in (0 after `\r\n`, else the cursor's): so a vertical's first shortest pair is it
    // with the first shortest horizontal from that column. Of the verticals that leave the column
    // as it is, one is never beaten by those after it: down by one to three, vertical tabs (a byte
    // each: `CUD` is 3–4 bytes, `VPA` at least 4 below the top row); further down, `CUD`, whose
    // distance has no more digits than `VPA`'s row. Up, `CUU` and `VPA` both.
    // (`tests::the_shortest_move_is_the_first_of_the_shortest_of_all_pairs` holds it to the search
    // of all pairs.)
    let from_cursor = shortest_horizontal(cx, x);
    let mut best: (usize, Option<(Vertical, Horizontal)>) = (cup_len(x, y), None);
    let mut consider = |vertical: Vertical, (across, horizontal): (usize, Horizontal)| {
        let len = vertical_len(cx, vertical) + across;
        if len < best.0 {
            best = (len, Some((vertical, horizontal)));
        }
    };
    match y.cmp(&cy) {
        std::cmp::Ordering::Equal => consider(Vertical::Stay, from_cursor),
        std::cmp::Ordering::Greater => {
            let down = y - cy;
            consider(Vertical::CrLf(down), shortest_horizontal(0, x));
            consider(if down <= 3 { Vertical::Vt(down) } else { Vertical::Down(down) }, from_cursor);
        }
        std::cmp::Ordering::Less => {
            consider(Vertical::Up(cy - y), from_cursor);
            consider(Vertical::Row(y), from_cursor);
        }
    }
    best
}

/// The first of the shortest horizontal steps from column `col` to column `x`, in the order
/// [`shortest_move`] searches them (`Stay`, `\r`, `CUF`, `CUB`, backspaces, `CHA`), and its bytes;
/// by cases rather than by pricing each (the tests hold [`shortest_move`] to the search of all
/// steps). Right: `CUF` never has more digits than `CHA` (the distance is below the column). Left to
/// column 0: `\r`, one byte. Left by one to three: as many backspaces, shorter than `CUB` (3–4
/// bytes) and `CHA` (at least 4 past column 0). Further left: `CUB`, unless `CHA` has fewer digits.
#[inline]
fn shortest_horizontal(col: usize, x: usize) -> (usize, Horizontal) {
    use std::cmp::Ordering::{Equal, Greater, Less};
    match x.cmp(&col) {
        Equal => (0, Horizontal::Stay),
        Greater => (csi_len(x - col, 1), Horizontal::Right(x - col)),
        Less if x == 0 => (1, Horizontal::Cr),
        Less if col - x <= 3 => (col - x, Horizontal::Back(col - x)),
        Less => {
            let (left, column) = (csi_len(col - x, 1), csi_len(x + 1, 1));
            if column < left { (column, Horizontal::Column(x)) } else { (left, Horizontal::Left(col - x)) }
        }
    }
}

/// The bytes of [`write_relative`].
#[cfg(test)]
fn relative_len(from_x: usize, vertical: Vertical, horizontal: Horizontal) -> usize {
    vertical_len(from_x, vertical) + horizontal_len(horizontal)
}

/// The bytes of a vertical step from column `from_x` (the first part of a relative move's bytes).
fn vertical_len(from_x: usize, vertical: Vertical) -> usize {
    match vertical {
        Vertical::Stay => 0,
        Vertical::CrLf(k) => usize::from(from_x != 0) + k,
        Vertical::Vt(k) => k,
        Vertical::Down(k) | Vertical::Up(k) => csi_len(k, 1),
        Vertical::Row(y) => csi_len(y + 1, 1),
    }
}

/// The bytes of a horizontal step (the second part of a relative move's bytes).
#[cfg(test)]
fn horizontal_len(horizontal: Horizontal) -> usize {
    match horizontal {
        Horizontal::Stay => 0,
        Horizontal::Cr => 1,
        Horizontal::Right(n) | Horizontal::Left(n) => csi_len(n, 1),
        Horizontal::Back(n) => n,
        Horizontal::Column(x) => csi_len(x + 1, 1),
    }
}

/// The bytes of [`write_csi`].
#[inline(always)]
fn csi_len(n: usize, default: usize) -> usize {
    3 + if n != default { digits(n) } else { 0 }
}

/// The bytes of [`write_cup`].
#[inline(always)]
fn cup_len(x: usize, y: usize) -> usize {
    3 + if x != 0 {
        digits(y + 1) + 1 + digits(x + 1)
    } else if y != 0 {
        digits(y + 1)
    } else {
        0
    }
}

/// The decimal digits of `n`.
#[inline]
pub(super) fn digits(n: usize) -> usize {
    // A screen's rows and columns, the usual numbers, by comparison.
    match n {
        0..=9 => 1,
        10..=99 => 2,
        100..=999 => 3,
        _ => n.ilog10() as usize + 1,
    }
}

fn write_relative(out: &mut Vec<u8>, from_x: usize, vertical: Vertical, horizontal: Horizontal) {
    match vertical {
        Vertical::Stay => {}
        Vertical::CrLf(k) => {
            if from_x != 0 {
                out.push(b'\r');
            }
            out.extend(std::iter::repeat_n(b'\n', k));
        }
        Vertical::Vt(k) => out.extend(std::iter::repeat_n(b'\x0b', k)),
        Vertical::Down(k) => write_csi(out, k, 1, b'B'),
        Vertical::Up(k) => write_csi(out, k, 1, b'A'),
        Vertical::Row(y) => write_csi(out, y + 1, 1, b'd'),
    }
    match horizontal {
        Horizontal::Stay => {}
        Horizontal::Cr => out.push(b'\r'),
        Horizontal::Right(n) => write_csi(out, n, 1, b'C'),
        Horizontal::Left(n) => write_csi(out, n, 1, b'D'),
        Horizontal::Back(n) => out.extend(std::iter::repeat_n(b'\x08', n)),
        Horizontal::Column(x) => write_csi(out, x + 1, 1, b'G'),
    }
}

/// `ESC [ n final`, omitting `n` when it is the default.
fn write_csi(out: &mut Vec<u8>, n: usize, default: usize, final_byte: u8) {
    out.extend_from_slice(b"\x1b[");
    if n != default {
        push_num(out, n);
    }
    out.push(final_byte);
}

/// `CUP` to column `x`, row `y` (0-based), omitting default parameters: `\x1b[H`, `\x1b[5H`, `\x1b[5;9H`.
/// (`\x1b[;9H` would save a byte on the top row, but an empty leading parameter is less portable.)
fn write_cup(out: &mut Vec<u8>, x: usize, y: usize) {
    out.extend_from_slice(b"\x1b[");
    if x != 0 {
        push_num(out, y + 1);
        out.push(b';');
        push_num(out, x + 1);
    } else if y != 0 {
        push_num(out, y + 1);
    }
    out.push(b'H');
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moved(from: Option<(usize, usize)>, x: usize, y: usize) -> String {
        let mut out = Vec::new();
        let mut pen = Pen { cursor: from, ..Pen::UNKNOWN };
        write_move(&mut out, &mut pen, x, y);
        assert_eq!(pen.cursor, Some((x, y)));
        String::from_utf8(out).unwrap()
    }

    /// [`shortest_move`] as it searched before: every vertical step with every horizontal one after
    /// it, the first of the shortest (`CUP` first).
    fn searched_move(
        from: Option<(usize, usize)>,
        x: usize,
        y: usize,
    ) -> (usize, Option<(Vertical, Horizontal)>) {
        let Some((cx, cy)) = from else { return (cup_len(x, y), None) };
        if (cx, cy) == (x, y) {
            return (0, None);
        }
        if cy == y && x > cx {
            // The diff's usual move, on along the row: `CUF` is shorter than `CHA` (fewer digits) and `CUP`.
            return (csi_len(x - cx, 1), Some((Vertical::Stay, Horizontal::Right(x - cx))));
        }
        let verticals = vertical_steps(cy, y);
        let mut best: (usize, Option<(Vertical, Horizontal)>) = (cup_len(x, y), None);
        for vertical in verticals.into_iter().flatten() {
            let col = if matches!(vertical, Vertical::CrLf(_)) { 0 } else { cx };
            let horizontals = [
                Some(Horizontal::Stay).filter(|_| col == x),
                Some(Horizontal::Cr).filter(|_| x == 0 && col != 0),
                Some(Horizontal::Right(x.wrapping_sub(col))).filter(|_| x > col),
                Some(Horizontal::Left(col.wrapping_sub(x))).filter(|_| x < col),
                Some(Horizontal::Back(col.wrapping_sub(x))).filter(|_| x < col && col - x <= 3),
                Some(Horizontal::Column(x)).filter(|_| x != col),
            ];
            for horizontal in horizontals.into_iter().flatten() {
                let len = relative_len(cx, vertical, horizontal);
                if len < best.0 {
                    best = (len, Some((vertical, horizontal)));
                }
            }
        }
        best
    }

    /// The move found with each vertical's shortest horizontal once is the move of the search of all
    /// pairs, route and bytes: from every cursor to every cell of a 130×45 screen near the corners,
    /// edges and middle (the columns and rows where the forms' lengths change), and from nowhere.
    #[test]
    fn the_shortest_move_is_the_first_of_the_shortest_of_all_pairs() {
        let columns: Vec<usize> = (0..14).chain(95..106).chain(125..130).collect();
        let rows: Vec<usize> = (0..14).chain(38..45).collect();
        let mut moves = 0;
        for &cy in &rows {
            for &cx in &columns {
                for &y in &rows {
                    for &x in &columns {
                        let from = Some((cx, cy));
                        assert_eq!(
                            shortest_move(from, x, y),
                            searched_move(from, x, y),
                            "{from:?} to {x},{y}"
                        );
                        moves += 1;
                    }
                }
            }
        }
        for (x, y) in [(0, 0), (5, 0), (0, 7), (120, 44)] {
            assert_eq!(shortest_move(None, x, y), searched_move(None, x, y));
        }
        assert!(moves > 300_000);
    }

    /// `move_bound` is never below the move written, and is that move where the move is one of its
    /// routes (below, 381,089 of 397,530 moves; the test asks nine in ten).
    #[test]
    fn a_move_bound_is_never_below_the_move_and_mostly_is_it() {
        let columns: Vec<usize> = (0..14).chain(95..106).chain(125..130).collect();
        let rows: Vec<usize> = (0..14).chain(38..45).collect();
        let (mut moves, mut equal) = (0, 0);
        for from in rows.iter().flat_map(|&cy| columns.iter().map(move |&cx| Some((cx, cy)))).chain([None]) {
            for &y in &rows {
                for &x in &columns {
                    let (bound, (len, _)) = (move_bound(from, x, y), shortest_move(from, x, y));
                    assert!(bound >= len, "{from:?} to {x},{y}: bound {bound} < {len}");
                    (moves, equal) = (moves + 1, equal + usize::from(bound == len));
                }
            }
        }
        assert!(equal * 10 >= moves * 9, "{equal} of {moves} moves bound exactly");
    }

    /// What the detours' fast path rests on (issue #42): a move's bound is 0 to the cursor's own
    /// cell and at least a byte to any other, and never more than `CUP`'s bytes or 3 (a bound from
    /// nowhere, `None`, is `CUP`'s).
    #[test]
    fn a_move_bound_is_nothing_only_in_place_and_never_above_cup_or_three() {
        let columns: Vec<usize> = (0..14).chain(95..106).chain(125..130).collect();
        let rows: Vec<usize> = (0..14).chain(38..45).collect();
        for from in rows.iter().flat_map(|&cy| columns.iter().map(move |&cx| Some((cx, cy)))).chain([None]) {
            for &y in &rows {
                for &x in &columns {
                    let bound = move_bound(from, x, y);
                    assert_eq!(bound == 0, from == Some((x, y)), "{from:?} to {x},{y}: {bound}");
                    assert!(bound <= move_bound(None, x, y).max(3), "{from:?} to {x},{y}: {bound}");
                }
            }
        }
    }

    #[test]
    fn cursor_moves_pick_the_cheapest_form() {
        assert_eq!(moved(None, 0, 0), "\x1b[H");
        assert_eq!(moved(None, 0, 4), "\x1b[5H");
        assert_eq!(moved(None, 8, 4), "\x1b[5;9H");
        assert_eq!(moved(None, 8, 0), "\x1b[1;9H");
        assert_eq!(moved(Some((3, 3)), 3, 3), "");
        assert_eq!(moved(Some((5, 3)), 0, 3), "\r");
        assert_eq!(moved(Some((5, 3)), 6, 3), "\x1b[C");
        assert_eq!(moved(Some((5, 3)), 20, 3), "\x1b[15C");
        assert_eq!(moved(Some((5, 3)), 4, 3), "\x08");
        assert_eq!(moved(Some((50, 3)), 30, 3), "\x1b[20D");
        assert_eq!(moved(Some((5, 3)), 0, 4), "\r\n");
        assert_eq!(moved(Some((0, 3)), 0, 5), "\n\n");
        // Down in the same column: vertical tabs, a byte each (up to three, then `CUD`).
        assert_eq!(moved(Some((5, 3)), 5, 4), "\x0b");
        assert_eq!(moved(Some((5, 3)), 5, 6), "\x0b\x0b\x0b");
        assert_eq!(moved(Some((5, 3)), 5, 8), "\x1b[5B");
        assert_eq!(moved(Some((5, 3)), 4, 4), "\x0b\x08"); // the cell under the last glyph
        assert_eq!(moved(Some((5, 3)), 1, 4), "\r\n\x1b[C");
        assert_eq!(moved(Some((5, 3)), 2, 4), "\x0b\x08\x08\x08"); // `\x1b[5;3H` and "\r\n\x1b[2C" are 6
        assert_eq!(moved(Some((5, 9)), 5, 2), "\x1b[7A");
        assert_eq!(moved(Some((70, 3)), 40, 30), "\x1b[31;41H");
        // Up to three backspaces (a byte each) beat `CUB`; past three, `CUB` (ties go to it).
        assert_eq!(moved(Some((5, 3)), 2, 3), "\x08\x08\x08");
        assert_eq!(moved(Some((5, 3)), 1, 3), "\x1b[4D");
        // Far back along a row, an absolute column (`CHA`) has fewer digits than the distance.
        assert_eq!(moved(Some((50, 3)), 5, 3), "\x1b[6G");
        // Far up in the same column, an absolute row (`VPA`).
        assert_eq!(moved(Some((5, 40)), 5, 2), "\x1b[3d");
        assert_eq!(moved(Some((0, 3)), 0, 4), "\n");
    }
}
