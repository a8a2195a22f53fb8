//! The frame encoder: a [`Frame`] in, the fewest bytes that make the terminal show it out.
//!
//! Pure: no I/O, no crossterm. The encoder remembers the frame it last sent (what the terminal shows)
//! and the terminal's cursor and colour state, then writes only what changed, choosing for each step
//! the cheapest of the equivalent escape sequences:
//!
//! - **cursor moves**: absolute `CUP`, relative `CUF`/`CUB`/`CUD`/`CUU`, `CHA`/`VPA`, `\r`, `\r\n`,
//!   backspace, or simply rewriting a short unchanged gap when that is fewer bytes;
//! - **colours**: one `SGR` per change, fg and bg combined, in the shortest form (`30–37`, `90–97`,
//!   `38;5;n`, `38;2;r;g;b`, or a reset `\x1b[0;…m` when that is shorter);
//! - **blank tails**: erase-to-end-of-line `\x1b[K` when it is cheaper than writing the blanks;
//! - **full paints** (first frame, resize, [`Encoder::invalidate`]): clear the screen to the background
//!   that saves the most, then send the frame as a diff against that blank screen.
//!
//! A frame is one buffer wrapped in synchronized output (`\x1b[?2026h` … `\x1b[?2026l`, ignored by
//! terminals without it); an unchanged frame is zero bytes.
//!
//! Two facts about cells the encoder relies on: every glyph is one column wide (the [`Frame`]
//! guarantees it), and a space shows only its background, so a space's foreground is neither sent nor
//! compared.
//!
//! Terminal behaviour assumed (xterm and everything that imitates it): after a glyph in the last column
//! the cursor is in the "pending wrap" state, whose position terminals disagree on, so the next move is
//! absolute; `\n` may or may not imply `\r` (raw mode clears `OPOST`, but who knows), so it is only sent
//! where both readings agree; erasures fill with the current background ("BCE"), which
//! [`Encoder::set_bce`] can turn off for terminals that don't (GNU screen).

use std::collections::HashMap;

use crate::frame::{Cell, Color, Frame};

/// Begin synchronized update (DEC mode 2026): the terminal holds the screen until the end marker.
pub const SYNC_BEGIN: &[u8] = b"\x1b[?2026h";
/// End synchronized update.
pub const SYNC_END: &[u8] = b"\x1b[?2026l";
/// Reset all SGR attributes (colours back to the terminal's defaults).
pub const SGR_RESET: &[u8] = b"\x1b[0m";

/// The colour tolerance the walkthrough uses ([`Encoder::set_tolerance`]): one 8-bit step per channel,
/// below what anyone can see, and a sixth fewer bytes while walking in truecolor (see BENCHMARKS.md).
pub const DEFAULT_TOLERANCE: u8 = 1;

/// A rewrite of unchanged cells longer than this never beats a cursor move (`CUP` is at most ~12 bytes).
const MAX_REWRITE: usize = 12;

/// What one [`Encoder::encode`] call did, for the HUD and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EncodeStats {
    /// Bytes appended to the output buffer (0 when nothing changed).
    pub bytes: usize,
    /// Cells whose look changed; every cell on a full paint.
    pub cells_changed: usize,
    /// Whether this was a full paint (first frame, resize or after [`Encoder::invalidate`]).
    pub full_paint: bool,
}

/// Encodes frames as terminal output, diffing each against the previous one.
///
/// ```
/// use mazewalk::frame::Frame;
/// use mazewalk::term::encoder::Encoder;
///
/// let mut encoder = Encoder::new();
/// let mut out = Vec::new();
/// let mut frame = Frame::new(40, 2);
/// encoder.encode(&frame, &mut out); // first frame: a full paint
/// out.clear();
/// encoder.encode(&frame, &mut out);
/// assert!(out.is_empty()); // nothing changed: nothing sent
/// frame.set(30, 1, mazewalk::frame::Cell::plain('x'));
/// let stats = encoder.encode(&frame, &mut out);
/// assert_eq!(stats.cells_changed, 1);
/// assert_eq!(out, b"\x1b[?2026h\x1b[2;31Hx\x1b[?2026l"); // sync begin, move, glyph, sync end
/// ```
#[derive(Clone, Debug)]
pub struct Encoder {
    /// What the terminal shows, as far as we know; meaningless while `valid` is false.
    screen: Frame,
    valid: bool,
    pen: Pen,
    bce: bool,
    sync_threshold: usize,
    /// Truecolor cells within this many 8-bit steps per channel of what is on screen are left as they are.
    tolerance: u8,
    /// Scratch for the frame as sent: `frame` up to `tolerance` (the screen where close, the pen's
    /// colours where close); swapped into `screen` after each encode.
    effective: Frame,
    last: EncodeStats,
}

impl Default for Encoder {
    fn default() -> Self {
        Encoder::new()
    }
}

impl Encoder {
    /// An encoder whose first frame will be a full paint. Assumes BCE (see [`Encoder::set_bce`]).
    #[must_use]
    pub fn new() -> Encoder {
        Encoder {
            screen: Frame::default(),
            valid: false,
            pen: Pen::UNKNOWN,
            bce: true,
            sync_threshold: 0,
            tolerance: 0,
            effective: Frame::default(),
            last: EncodeStats::default(),
        }
    }

    /// Forget what the terminal shows: the next frame is a full paint (after resume, a reset, a resize).
    pub fn invalidate(&mut self) {
        self.valid = false;
        self.pen = Pen::UNKNOWN;
    }

    /// Whether erasures fill with the current background (true for xterm, VTE, kitty, tmux…; false for
    /// GNU screen without `defbce on`). Without BCE only default-background blanks are erased.
    pub fn set_bce(&mut self, bce: bool) {
        self.bce = bce;
        self.invalidate();
    }

    /// Wrap a frame in synchronized output only when its body is longer than `bytes` (default 0:
    /// always). A tiny update arrives in one read and cannot tear, so 16 bytes of markers can be saved.
    pub fn set_sync_threshold(&mut self, bytes: usize) {
        self.sync_threshold = bytes;
    }

    /// Leave a truecolor cell as the screen shows it while each of its colours is within `steps` 8-bit
    /// steps per channel of the new frame's (default 0: exact). The screen then differs from the frame by
    /// at most that much, never more: each frame is compared with what the screen shows.
    pub fn set_tolerance(&mut self, steps: u8) {
        self.tolerance = steps;
    }

    /// What the last [`Encoder::encode`] did.
    #[must_use]
    pub fn last_stats(&self) -> EncodeStats {
        self.last
    }

    /// Appends to `out` the bytes that turn the previous frame into `frame`: nothing if they are equal,
    /// a full paint if there is no (valid, same-sized) previous frame.
    pub fn encode(&mut self, frame: &Frame, out: &mut Vec<u8>) -> EncodeStats {
        let start = out.len();
        let full_paint =
            !self.valid || self.screen.width() != frame.width() || self.screen.height() != frame.height();
        out.extend_from_slice(SYNC_BEGIN);
        // `sent`: the frame as it will be on screen, which the tolerance may leave a little off `frame`.
        let sent = &mut self.effective;
        sent.clone_from(frame);
        let cells_changed = if full_paint {
            self.pen = paint_full(sent, self.bce, out);
            sent.cells().len()
        } else {
            if self.tolerance > 0 {
                for (shown, cell) in self.screen.cells().iter().zip(sent.cells_mut()) {
                    // Only truecolor colours can be close without being equal; the diff finds the rest.
                    if has_rgb(cell) && shown.looks_within(cell, self.tolerance) {
                        *cell = *shown;
                    }
                }
            }
            diff(&self.screen, sent, self.bce, self.tolerance, &mut self.pen, out)
        };
        let body = out.len() - start - SYNC_BEGIN.len();
        if body == 0 {
            out.truncate(start);
        } else if body <= self.sync_threshold {
            out.drain(start..start + SYNC_BEGIN.len()); // cheap: the body is short
        } else {
            out.extend_from_slice(SYNC_END);
        }
        std::mem::swap(&mut self.screen, &mut self.effective); // the screen is now what was sent
        self.valid = true;
        self.last = EncodeStats { bytes: out.len() - start, cells_changed, full_paint };
        self.last
    }

    /// The bytes that reset what the encoder may have left set (colours); the guard sends them on exit.
    #[must_use]
    pub fn reset_sequence() -> &'static [u8] {
        SGR_RESET
    }

    /// A lower bound for the next frame: the UTF-8 bytes of just the non-blank glyphs that must change
    /// (all of them if a full paint is due; blanks are left out, an erasure may cover any number of
    /// them). No encoding can send less; benchmarks report it beside [`EncodeStats::bytes`].
    #[must_use]
    pub fn lower_bound(&self, frame: &Frame) -> usize {
        let full =
            !self.valid || self.screen.width() != frame.width() || self.screen.height() != frame.height();
        // The cheaper of the cell and its inverse; a blank may be erased, so it costs nothing.
        let bytes = |c: &Cell| if c.ch == ' ' { 0 } else { c.ch.len_utf8() };
        let glyph_bytes = |c: &Cell| {
            let c = c.canonical();
            c.inverse().map_or(bytes(&c), |inverse| bytes(&c).min(bytes(&inverse)))
        };
        if full {
            frame.cells().iter().map(glyph_bytes).sum()
        } else {
            (self.screen.cells().iter().zip(frame.cells()))
                .filter(|(old, new)| !same_look(old, new))
                .map(|(_, new)| glyph_bytes(new))
                .sum()
        }
    }
}

/// The naive baseline for benchmarks: every cell with its full SGR, every row positioned absolutely.
pub fn full_repaint(frame: &Frame, out: &mut Vec<u8>) {
    for y in 0..frame.height() {
        write_cup(out, 0, y);
        for cell in frame.row(y).unwrap_or(&[]) {
            out.extend_from_slice(b"\x1b[");
            push_color(out, cell.fg, Layer::Fg);
            out.push(b';');
            push_color(out, cell.bg, Layer::Bg);
            out.push(b'm');
            push_char(out, cell.ch);
        }
    }
    out.extend_from_slice(SGR_RESET);
}

/// `frame` as text lines for a pipe or a file (`mazewalk render`): no cursor moves, each line starts
/// from default colours, sets them only where they change and ends with a reset and `\n`. A frame of
/// default colours gives plain text.
pub fn ansi_lines(frame: &Frame, out: &mut Vec<u8>) {
    for y in 0..frame.height() {
        let mut pen = Pen { cursor: None, fg: Some(Color::Default), bg: Some(Color::Default) };
        for cell in frame.row(y).unwrap_or(&[]) {
            let fg = (cell.ch != ' ').then_some(cell.fg);
            write_sgr(out, &mut pen, fg, Some(cell.bg));
            push_char(out, cell.ch);
        }
        if pen.fg != Some(Color::Default) || pen.bg != Some(Color::Default) {
            out.extend_from_slice(SGR_RESET);
        }
        out.push(b'\n');
    }
}

/// Whether two cells look the same on screen ([`Cell::same_look`]): what the diff compares.
#[must_use]
pub fn same_look(a: &Cell, b: &Cell) -> bool {
    a.same_look(b)
}

/// The terminal state the encoder tracks; `None` means unknown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pen {
    /// Cursor (column, row); unknown at start and after a glyph in the last column (pending wrap).
    cursor: Option<(usize, usize)>,
    fg: Option<Color>,
    bg: Option<Color>,
}

impl Pen {
    const UNKNOWN: Pen = Pen { cursor: None, fg: None, bg: None };
}

/// Clears the screen and paints `frame`, choosing the clear colour that gives the fewest bytes.
fn paint_full(frame: &Frame, bce: bool, out: &mut Vec<u8>) -> Pen {
    let start = out.len();
    let pen = clear_and_paint(frame, Color::Default, bce, out);
    // Clearing to the most common blank background saves writing those blanks (needs BCE).
    let Some(bg) = bce.then(|| most_common_blank_bg(frame)).flatten() else { return pen };
    let mut alt = Vec::with_capacity(out.len() - start);
    let alt_pen = clear_and_paint(frame, bg, bce, &mut alt);
    if alt.len() < out.len() - start {
        out.truncate(start);
        out.extend_from_slice(&alt);
        return alt_pen;
    }
    pen
}

/// Resets SGR, sets the background `bg`, clears the screen, then sends `frame` as a diff.
fn clear_and_paint(frame: &Frame, bg: Color, bce: bool, out: &mut Vec<u8>) -> Pen {
    let mut pen = Pen::UNKNOWN;
    // The reset form also clears attributes we don't track (bold…) that someone else may have left.
    write_sgr_reset(out, &mut pen, None, Some(bg));
    out.extend_from_slice(b"\x1b[2J");
    let blank = Frame::filled(frame.width(), frame.height(), Cell { ch: ' ', fg: Color::Default, bg });
    // A copy: the diff records the forms it sent, and each trial of `paint_full` starts from the frame.
    diff(&blank, &mut frame.clone(), bce, 0, &mut pen, out);
    pen
}

/// The most common background of space cells, if it is not the default. Ties go to the default, then
/// to the colour met first (row-major), so that a frame always encodes to the same bytes.
fn most_common_blank_bg(frame: &Frame) -> Option<Color> {
    // Colour -> (blanks, index of its first blank).
    let mut counts: HashMap<Color, (usize, usize)> = HashMap::new();
    for (i, cell) in frame.cells().iter().enumerate().filter(|(_, c)| c.ch == ' ') {
        counts.entry(cell.bg).or_insert((0, i)).0 += 1;
    }
    let (bg, _) = counts
        .into_iter()
        .max_by_key(|&(bg, (n, first))| (n, bg == Color::Default, std::cmp::Reverse(first)))?;
    (bg != Color::Default).then_some(bg)
}

/// Writes what turns `old` into `new` (same size); returns the number of cells changed. A changed
/// truecolor cell may take the pen's colour where that is within `tolerance` of its own (one SGR less);
/// `new` is updated to what was sent.
fn diff(old: &Frame, new: &mut Frame, bce: bool, tolerance: u8, pen: &mut Pen, out: &mut Vec<u8>) -> usize {
    debug_assert_eq!((old.width(), old.height()), (new.width(), new.height()));
    let width = new.width().max(1);
    let mut changed = 0;
    for (y, (old_row, new_row)) in
        old.cells().chunks_exact(width).zip(new.cells_mut().chunks_exact_mut(width)).enumerate()
    {
        let tail = erasable_tail(new_row, bce);
        changed += diff_row(pen, out, y, 0, old_row, new_row, tail, tolerance);
    }
    changed
}

/// Where a row's tail of same-background spaces starts, and that background, if `\x1b[K` may erase it.
fn erasable_tail(row: &[Cell], bce: bool) -> Option<(usize, Color)> {
    let last = row.last().filter(|c| c.ch == ' ')?;
    if !bce && last.bg != Color::Default {
        return None;
    }
    let len = row.iter().rev().take_while(|c| c.ch == ' ' && c.bg == last.bg).count();
    Some((row.len() - len, last.bg))
}

/// Encodes the changes of row `y` from column `from` on; returns the number of cells changed. Changed
/// cells are written within `tolerance` of `new` ([`write_cell`]) and `new` records what was sent.
#[allow(clippy::too_many_arguments)]
fn diff_row(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    y: usize,
    from: usize,
    old: &[Cell],
    new: &mut [Cell],
    tail: Option<(usize, Color)>,
    tolerance: u8,
) -> usize {
    let width = new.len();
    let mut changed = 0;
    let mut from = from;
    while let Some(x) = (from..width).find(|&i| !same_look(&old[i], &new[i])) {
        if let Some((start, bg)) = tail
            && x >= start
        {
            // Everything left to change is blank: erase to end of line, or write the cells, whichever is
            // shorter (try both, keep the shorter).
            changed += (x..width).filter(|&i| !same_look(&old[i], &new[i])).count();
            let mark = out.len();
            let mut erase = *pen;
            reach(&mut erase, out, y, x, new, |pen, out| {
                write_sgr(out, pen, None, Some(bg));
                out.extend_from_slice(b"\x1b[K");
            });
            let erase_len = out.len() - mark;
            out.truncate(mark);
            let mut write = *pen;
            // Exact (tolerance 0): a trial, so it must leave `new` as it is.
            diff_row(&mut write, out, y, x, old, new, None, 0);
            if erase_len < out.len() - mark {
                out.truncate(mark);
                reach(pen, out, y, x, new, |pen, out| {
                    write_sgr(out, pen, None, Some(bg));
                    out.extend_from_slice(b"\x1b[K");
                });
            } else {
                *pen = write;
            }
            return changed;
        }
        let (cell, mut sent) = (new[x], new[x]);
        // `reach` tries routes and ends with the one it keeps: the last cell written is the one sent.
        reach(pen, out, y, x, new, |pen, out| sent = write_cell(out, pen, &cell, width, tolerance));
        new[x] = sent;
        changed += 1;
        from = x + 1;
    }
    changed
}

/// Puts the cursor on column `x` of row `y` and runs `then`, by the cheapest route: a cursor move, or
/// a move to an earlier column and a rewrite of the unchanged cells in between (from `row`).
fn reach(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    y: usize,
    x: usize,
    row: &[Cell],
    mut then: impl FnMut(&mut Pen, &mut Vec<u8>),
) {
    let width = row.len();
    let mut route = |pen: &mut Pen, out: &mut Vec<u8>, from: usize| {
        write_move(out, pen, from, y);
        for cell in &row[from..x] {
            write_cell(out, pen, cell, width, 0); // on screen already: exactly as it is
        }
        then(pen, out);
    };
    let mut starts = [Some(x), None, None];
    if pen.cursor != Some((x, y)) {
        if let Some((cx, cy)) = pen.cursor
            && cy == y
            && cx < x
            && x - cx <= MAX_REWRITE
        {
            starts[1] = Some(cx);
        }
        if x > 0 && x <= MAX_REWRITE {
            starts[2] = Some(0);
        }
    }
    let mark = out.len();
    let mut best = (usize::MAX, x);
    for from in starts.into_iter().flatten() {
        let mut trial = *pen;
        route(&mut trial, out, from);
        best = best.min((out.len() - mark, from));
        out.truncate(mark);
    }
    route(pen, out, best.1);
}

/// Writes one cell at the cursor: colours if needed, then the glyph; returns the cell as sent. Of the
/// cell and its [`Cell::inverse`] (same look), the one whose colours cost fewer bytes from the current
/// pen, each with the pen's colours kept where they are within `tolerance` of the cell's.
fn write_cell(out: &mut Vec<u8>, pen: &mut Pen, cell: &Cell, width: usize, tolerance: u8) -> Cell {
    let cell = cell.canonical();
    let near_pen = |mut cell: Cell| {
        let keep = |want: Color, pen: Option<Color>| pen.filter(|p| p.within(want, tolerance));
        cell.fg = keep(cell.fg, pen.fg).unwrap_or(cell.fg);
        cell.bg = keep(cell.bg, pen.bg).unwrap_or(cell.bg);
        cell
    };
    let cell = if tolerance == 0 || !has_rgb(&cell) {
        match cell.inverse() {
            Some(inverse) if sgr_len(pen, &inverse) < sgr_len(pen, &cell) => inverse,
            _ => cell,
        }
    } else {
        // The pen's colours where close enough; a glyph they leave in one colour may go as a blank.
        let (plain, inverse) = (near_pen(cell), cell.inverse().map(near_pen));
        [Some(plain), Some(plain.canonical()), inverse, inverse.map(|c| c.canonical())]
            .into_iter()
            .flatten()
            .min_by_key(|c| sgr_len(pen, c))
            .unwrap_or(plain)
    };
    let (fg, bg) = shown_colors(&cell);
    write_sgr(out, pen, fg, bg);
    push_char(out, cell.ch);
    pen.cursor = match pen.cursor {
        Some((x, y)) if x + 1 < width => Some((x + 1, y)),
        _ => None, // after the last column: pending wrap, position unreliable
    };
    cell
}

/// Whether a cell has a truecolor colour, the only kind a tolerance applies to.
fn has_rgb(cell: &Cell) -> bool {
    matches!(cell.fg, Color::Rgb(..)) || matches!(cell.bg, Color::Rgb(..))
}

fn push_char(out: &mut Vec<u8>, ch: char) {
    let mut buf = [0; 4];
    out.extend_from_slice(ch.encode_utf8(&mut buf).as_bytes());
}

// ---------------------------------------------------------------------------------------------------
// Colours (SGR)

#[derive(Clone, Copy, PartialEq, Eq)]
enum Layer {
    Fg,
    Bg,
}

/// The colours a cell needs on screen: no foreground for a space, no background for a full block.
fn shown_colors(cell: &Cell) -> (Option<Color>, Option<Color>) {
    ((cell.ch != ' ').then_some(cell.fg), (cell.ch != '█').then_some(cell.bg))
}

/// The bytes [`write_sgr`] would send to show `cell`'s colours from `pen`.
fn sgr_len(pen: &Pen, cell: &Cell) -> usize {
    let (fg, bg) = shown_colors(cell);
    sgr_forms(pen, fg, bg).map_or(0, |(plain, reset)| plain.min(reset))
}

/// The lengths of the two ways to set `fg` and `bg` (`None`: don't care) from `pen`: just the changed
/// colours, or a reset followed by the non-default ones; `None` when nothing changes.
fn sgr_forms(pen: &Pen, fg: Option<Color>, bg: Option<Color>) -> Option<(usize, usize)> {
    let changes = sgr_changes(pen, fg, bg);
    let n = changes.iter().flatten().count();
    if n == 0 {
        return None;
    }
    // ESC [ p;p m: codes joined by `;`.
    let plain = 3 + n - 1 + changes.iter().flatten().map(|&(c, layer)| color_len(c, layer)).sum::<usize>();
    // ESC [ 0;p;p m, or ESC [ m when both are the defaults.
    let params: usize = [(fg, Layer::Fg), (bg, Layer::Bg)]
        .into_iter()
        .filter_map(|(c, layer)| Some((c.filter(|&c| c != Color::Default)?, layer)))
        .map(|(c, layer)| 1 + color_len(c, layer))
        .sum();
    let reset = 3 + if params > 0 { 1 + params } else { 0 };
    Some((plain, reset))
}

/// The colours that differ from the pen's, with their layer: foreground, then background.
fn sgr_changes(pen: &Pen, fg: Option<Color>, bg: Option<Color>) -> [Option<(Color, Layer)>; 2] {
    [
        fg.filter(|&c| pen.fg != Some(c)).map(|c| (c, Layer::Fg)),
        bg.filter(|&c| pen.bg != Some(c)).map(|c| (c, Layer::Bg)),
    ]
}

/// Sets the colours to `fg` and `bg` (`None`: don't care) in the shortest form, if they changed.
fn write_sgr(out: &mut Vec<u8>, pen: &mut Pen, fg: Option<Color>, bg: Option<Color>) {
    let Some((plain, reset)) = sgr_forms(pen, fg, bg) else { return };
    if reset < plain {
        return write_sgr_reset(out, pen, fg, bg);
    }
    let start = out.len();
    out.extend_from_slice(b"\x1b[");
    for (i, (color, layer)) in sgr_changes(pen, fg, bg).into_iter().flatten().enumerate() {
        if i > 0 {
            out.push(b';');
        }
        push_color(out, color, layer);
    }
    out.push(b'm');
    debug_assert_eq!(out.len() - start, plain);
    pen.fg = fg.or(pen.fg);
    pen.bg = bg.or(pen.bg);
}

/// Resets SGR and sets `fg` and `bg` (`None`: leave default) in one sequence: `\x1b[m`, `\x1b[0;41m`…
fn write_sgr_reset(out: &mut Vec<u8>, pen: &mut Pen, fg: Option<Color>, bg: Option<Color>) {
    let (fg, bg) = (fg.unwrap_or(Color::Default), bg.unwrap_or(Color::Default));
    out.extend_from_slice(b"\x1b[");
    let colors = [(fg, Layer::Fg), (bg, Layer::Bg)];
    let mut non_default = colors.iter().filter(|(c, _)| *c != Color::Default).peekable();
    if non_default.peek().is_some() {
        out.push(b'0');
        for &(color, layer) in non_default {
            out.push(b';');
            push_color(out, color, layer);
        }
    }
    out.push(b'm');
    pen.fg = Some(fg);
    pen.bg = Some(bg);
}

/// The shortest SGR parameters for `color` as foreground or background.
fn push_color(out: &mut Vec<u8>, color: Color, layer: Layer) {
    let base = if layer == Layer::Fg { 30 } else { 40 };
    match color {
        Color::Default => push_num(out, base + 9),
        Color::Indexed(n @ 0..=7) => push_num(out, base + usize::from(n)),
        Color::Indexed(n @ 8..=15) => push_num(out, base + 60 + usize::from(n - 8)),
        Color::Indexed(n) => {
            push_num(out, base + 8);
            out.extend_from_slice(b";5;");
            push_num(out, n.into());
        }
        Color::Rgb(r, g, b) => {
            push_num(out, base + 8);
            out.extend_from_slice(b";2;");
            for (i, c) in [r, g, b].into_iter().enumerate() {
                if i > 0 {
                    out.push(b';');
                }
                push_num(out, c.into());
            }
        }
    }
}

/// The length of [`push_color`]'s parameters for `color`.
fn color_len(color: Color, layer: Layer) -> usize {
    let digits = |n: u8| 1 + usize::from(n >= 10) + usize::from(n >= 100);
    match color {
        Color::Default | Color::Indexed(0..=7) => 2,
        Color::Indexed(8..=15) => 2 + usize::from(layer == Layer::Bg), // 90–97, 100–107
        Color::Indexed(n) => 5 + digits(n),                            // 38;5;n
        Color::Rgb(r, g, b) => 7 + digits(r) + digits(g) + digits(b),  // 38;2;r;g;b
    }
}

fn push_num(out: &mut Vec<u8>, n: usize) {
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    let mut n = n;
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.extend_from_slice(&digits[i..]);
}

// ---------------------------------------------------------------------------------------------------
// Cursor moves

/// Vertical part of a relative move.
#[derive(Clone, Copy)]
enum Vertical {
    Stay,
    /// `\r` (unless already in column 0) then `\n` × k: lands in column 0 whether or not `\n` implies
    /// `\r`. Only downwards, and never from the last row (the move's target is on screen).
    CrLf(usize),
    Down(usize),
    Up(usize),
    /// `VPA`: absolute row, same column.
    Row(usize),
}

/// Horizontal part of a relative move.
#[derive(Clone, Copy)]
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

/// Moves the cursor to column `x`, row `y` by the shortest sequence (nothing if it is there).
fn write_move(out: &mut Vec<u8>, pen: &mut Pen, x: usize, y: usize) {
    let from = pen.cursor;
    pen.cursor = Some((x, y));
    let Some((cx, cy)) = from else { return write_cup(out, x, y) };
    if (cx, cy) == (x, y) {
        return;
    }
    let verticals = [
        Some(Vertical::Stay).filter(|_| cy == y),
        Some(Vertical::CrLf(y.wrapping_sub(cy))).filter(|_| y > cy),
        Some(Vertical::Down(y.wrapping_sub(cy))).filter(|_| y > cy),
        Some(Vertical::Up(cy.wrapping_sub(y))).filter(|_| y < cy),
        Some(Vertical::Row(y)).filter(|_| y != cy),
    ];
    let mark = out.len();
    write_cup(out, x, y);
    let mut best: (usize, Option<(Vertical, Horizontal)>) = (out.len() - mark, None);
    out.truncate(mark);
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
            write_relative(out, cx, vertical, horizontal);
            if out.len() - mark < best.0 {
                best = (out.len() - mark, Some((vertical, horizontal)));
            }
            out.truncate(mark);
        }
    }
    match best.1 {
        Some((vertical, horizontal)) => write_relative(out, cx, vertical, horizontal),
        None => write_cup(out, x, y),
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
        assert_eq!(moved(Some((5, 3)), 5, 4), "\x1b[B");
        assert_eq!(moved(Some((5, 3)), 1, 4), "\r\n\x1b[C");
        assert_eq!(moved(Some((5, 3)), 2, 4), "\x1b[5;3H"); // ties with "\r\n\x1b[2C": absolute wins
        assert_eq!(moved(Some((5, 9)), 5, 2), "\x1b[7A");
        assert_eq!(moved(Some((70, 3)), 40, 30), "\x1b[31;41H");
    }

    fn sgr(from: (Option<Color>, Option<Color>), fg: Option<Color>, bg: Color) -> (String, Pen) {
        let mut out = Vec::new();
        let mut pen = Pen { cursor: None, fg: from.0, bg: from.1 };
        write_sgr(&mut out, &mut pen, fg, Some(bg));
        (String::from_utf8(out).unwrap(), pen)
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
        assert_eq!((pen.fg, pen.bg), (Some(Color::Default), Some(Color::Default)));
        assert_eq!(sgr((rgb, rgb), Some(Color::Default), Color::Indexed(1)).0, "\x1b[0;41m");
        // Unknown state: everything is sent.
        assert_eq!(sgr((None, None), red, Color::Default).0, "\x1b[0;31m");
    }

    #[test]
    fn erasable_tail_needs_spaces_of_one_background_and_bce_for_colour() {
        let blue = Cell { ch: ' ', fg: Color::Default, bg: Color::Indexed(4) };
        let row = [Cell::plain('a'), Cell::BLANK, blue, blue];
        assert_eq!(erasable_tail(&row, true), Some((2, Color::Indexed(4))));
        assert_eq!(erasable_tail(&row, false), None);
        assert_eq!(
            erasable_tail(&[Cell::plain('a'), Cell::BLANK, Cell::BLANK], false),
            Some((1, Color::Default))
        );
        assert_eq!(erasable_tail(&[Cell::BLANK, Cell::plain('a')], true), None);
    }

    #[test]
    fn a_blank_tail_is_erased_when_that_is_cheaper() {
        let mut encoder = Encoder::new();
        let mut out = Vec::new();
        encoder.encode(&Frame::from_lines(&["abcdefghij", "x"]), &mut out);
        out.clear();
        encoder.encode(&Frame::from_lines(&["ab        ", "x"]), &mut out);
        // `\x1b[H` + rewriting "ab" (5 bytes) beats `\x1b[1;3H` (6 bytes).
        assert_eq!(String::from_utf8(out).unwrap(), "\x1b[?2026h\x1b[Hab\x1b[K\x1b[?2026l");
    }

    #[test]
    fn a_short_unchanged_gap_is_rewritten_instead_of_jumped() {
        let mut encoder = Encoder::new();
        let mut out = Vec::new();
        encoder.encode(&Frame::from_lines(&["aaaaaaaaaa"]), &mut out);
        out.clear();
        encoder.encode(&Frame::from_lines(&["abab      "]), &mut out);
        // Rewriting the unchanged 'a's at columns 0 and 2 (1 byte each) beats `\x1b[1;2H` and `\x1b[C`.
        assert_eq!(out, b"\x1b[?2026h\x1b[Habab\x1b[K\x1b[?2026l");
    }

    #[test]
    fn full_paint_clears_to_the_most_common_blank_background() {
        let blue = Cell { ch: ' ', fg: Color::Default, bg: Color::Indexed(4) };
        let mut frame = Frame::filled(20, 5, blue);
        frame.set(3, 2, Cell::plain('x'));
        let mut out = Vec::new();
        let stats = Encoder::new().encode(&frame, &mut out);
        assert!(stats.full_paint);
        assert_eq!(out, b"\x1b[?2026h\x1b[0;44m\x1b[2J\x1b[3;4H\x1b[mx\x1b[?2026l");
        let mut encoder = Encoder::new();
        encoder.set_bce(false);
        out.clear();
        encoder.encode(&frame, &mut out);
        assert!(out.len() > 100, "without BCE the blue blanks are written");
    }

    // issue #11: the clear colour of a full paint depended on `HashMap` order when two tied.
    #[test]
    fn full_paint_breaks_a_tie_of_blank_backgrounds_by_the_first_met() {
        let (blue, red) = (Color::Indexed(4), Color::Indexed(1));
        let blank = |bg| Cell { ch: ' ', fg: Color::Default, bg };
        for (first, second) in [(blue, red), (red, blue)] {
            let mut frame = Frame::filled(4, 2, blank(first));
            (0..4).for_each(|x| frame.set(x, 1, blank(second)));
            for _ in 0..20 {
                assert_eq!(most_common_blank_bg(&frame), Some(first)); // a new hasher seed each time
            }
        }
        let mut frame = Frame::filled(4, 2, blank(blue));
        (0..4).for_each(|x| frame.set(x, 1, Cell::BLANK));
        assert_eq!(most_common_blank_bg(&frame), None, "a tie with the default goes to the default");
    }

    #[test]
    fn sync_threshold_drops_the_markers_for_tiny_updates() {
        let mut encoder = Encoder::new();
        encoder.set_sync_threshold(64);
        let mut out = Vec::new();
        encoder.encode(&Frame::from_lines(&["ab"]), &mut out);
        out.clear();
        encoder.encode(&Frame::from_lines(&["ax"]), &mut out);
        assert_eq!(out, b"\x1b[Hax");
    }
}
