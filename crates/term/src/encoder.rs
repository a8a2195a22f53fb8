//! The frame encoder: a [`Frame`] in, the fewest bytes that make the terminal show it out.
//!
//! Pure: no I/O, no crossterm. The encoder remembers the frame it last sent (what the terminal shows)
//! and the terminal's cursor and colour state, then writes only what changed, choosing for each step
//! the cheapest of the equivalent escape sequences:
//!
//! - **cursor moves** (`encoder/cursor.rs`): absolute `CUP`, relative `CUF`/`CUB`/`CUD`/`CUU`,
//!   `CHA`/`VPA`, `\r`, `\r\n`, vertical tabs (line feed/new line mode reset by every full
//!   paint), backspace; or (here) simply rewriting a short unchanged gap when that is fewer bytes;
//! - **colours** (`encoder/sgr.rs`): one `SGR` per change, fg and bg combined, in the shortest form
//!   (`30–37`, `90–97`, `38;5;n`, `38;2;r;g;b`, or a reset `\x1b[0;…m` when that is shorter);
//! - **blank tails**: erase-to-end-of-line `\x1b[K` when it is cheaper than writing the blanks;
//! - **columns**: a column of changed cells of one look (a seam or a wall's end sliding, its colours
//!   not its row neighbours') written down the column, one colour change for all of it, where that
//!   is fewer bytes than a colour change in each row ([`columns`]), before the rows;
//! - **runs** of one look along a row as `REP` (`CSI n b`) where the terminal has it
//!   ([`Encoder::set_rep`]);
//! - **detours**: in the rows, before a colour change, the changed cells further on that the pen's
//!   colours draw as they are (a blank in its background, a full block in its ink, a half block of
//!   the two) where their moves cost fewer bytes than the colour change each would need in its own
//!   row ([`detours`]): a wall's edge slanting across the rows goes edge by edge, not row by row;
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

mod cursor;
mod sgr;

use std::collections::HashMap;
use std::ops::Range;

use rustc_hash::FxHashMap;

use crate::blocks::FULL_BLOCK;
use crate::caps::RepLevel;
use crate::frame::{Cell, Frame, PackedCell, PackedColor};
use cursor::{RESET_LNM, digits, find_move, move_bound, move_len, write_found, write_move};
use sgr::{SGR_RESET, Sgr, write_sgr, write_sgr_reset};

/// Begin synchronized update (DEC mode 2026): the terminal holds the screen until the end marker.
pub(crate) const SYNC_BEGIN: &[u8] = b"\x1b[?2026h";
/// End synchronized update.
pub(crate) const SYNC_END: &[u8] = b"\x1b[?2026l";

/// The colour tolerance the walkthrough uses ([`Encoder::set_tolerance`]): two [`TOLERANCE_STEP`]s, an
/// OKLab distance of 0.02, about what an eye can just tell apart side by side; walking and turning
/// in truecolor cost a fraction of the exact bytes (see BENCHMARKS.md).
pub const DEFAULT_TOLERANCE: u8 = 2;

/// The largest colour tolerance accepted, in [`TOLERANCE_STEP`]s (an OKLab distance of 0.16).
pub const MAX_TOLERANCE: u8 = 16;

pub use crate::frame::TOLERANCE_STEP;

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
    /// Whether the screen now differs from the frame: cells left, or drawn, within the
    /// [tolerance](Encoder::set_tolerance) of their colours instead of in them. The same frame
    /// encoded again at tolerance 0 makes the screen exact.
    pub approximate: bool,
}

/// Encodes frames as terminal output, diffing each against the previous one.
///
/// ```
/// use mazewalk_term::frame::Frame;
/// use mazewalk_term::encoder::Encoder;
///
/// let mut encoder = Encoder::new();
/// let mut out = Vec::new();
/// let mut frame = Frame::new(40, 2);
/// encoder.encode(&frame, &mut out); // first frame: a full paint
/// out.clear();
/// encoder.encode(&frame, &mut out);
/// assert!(out.is_empty()); // nothing changed: nothing sent
/// frame.set(30, 1, mazewalk_term::frame::Cell::plain('x'));
/// let stats = encoder.encode(&frame, &mut out);
/// assert_eq!(stats.cells_changed, 1);
/// assert_eq!(out, b"\x1b[?2026h\x1b[2;31Hx\x1b[?2026l"); // sync begin, move, glyph, sync end
/// ```
#[derive(Clone, Debug)]
pub struct Encoder {
    /// What the terminal shows, as far as we know (row-major, `width` × `height`); meaningless while
    /// `valid` is false.
    screen: Vec<PackedCell>,
    width: usize,
    height: usize,
    valid: bool,
    pen: Pen,
    bce: bool,
    /// Cells within this many [`TOLERANCE_STEP`]s (OKLab; truecolor colours and palette entries 16–255)
    /// of what is on screen are left as they are.
    tolerance: u8,
    /// Scratch for a full paint's frame as sent, swapped into `screen` after it (a diff turns
    /// `screen` itself into the frame as sent: `frame` up to `tolerance`, the screen where close,
    /// the pen's colours where close).
    effective: Vec<PackedCell>,
    /// Scratch: which cells of the frame differ from the screen ([`mark_changes`]).
    differs: Vec<bool>,
    /// The cells of `differs` that may be set: those the last [`Memo::scan`] marked (the others
    /// it cleared).
    differs_set: Range<usize>,
    /// The last diff's frame and which of its cells it left as the screen showed them ([`Memo`]).
    memo: Memo,
    /// The tolerance the screen shows the last frame within: the last diff's, 0 after a full paint
    /// ([`Encoder::encode_rows`] relies on the rows it leaves only at this tolerance or above).
    sent_within: u8,
    /// For each row, whether the screen is off the last frame there within the tolerance
    /// ([`EncodeStats::approximate`], kept for the rows [`Encoder::encode_rows`] leaves), where
    /// `approximate_rows_known`: a whole frame's encode finds only whether any is.
    approximate_rows: Vec<bool>,
    approximate_rows_known: bool,
    /// Scratch: the indices of the cells of the frame not equal to the screen's ([`Memo::scan`]).
    unequal: Vec<u32>,
    /// Scratch: each column's first row of a column of changed cells ([`first_columns`]).
    first: Vec<usize>,
    /// Scratch: the changed cells by the colours they show ([`Follow`]).
    follow: Follow,
    /// After which glyphs runs of one look may go as `REP` ([`Encoder::set_rep`]).
    rep: RepLevel,
    /// Whether a blank may go as a full block ([`Encoder::set_blocks`]).
    blocks: bool,
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
            screen: Vec::new(),
            width: 0,
            height: 0,
            valid: false,
            pen: Pen::UNKNOWN,
            bce: true,
            tolerance: 0,
            effective: Vec::new(),
            differs: Vec::new(),
            differs_set: 0..0,
            memo: Memo::default(),
            sent_within: 0,
            approximate_rows: Vec::new(),
            approximate_rows_known: true,
            unequal: Vec::new(),
            first: Vec::new(),
            follow: Follow::default(),
            rep: RepLevel::None,
            blocks: true,
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

    /// Leave a cell as the screen shows it while each of its colours is within `steps`
    /// [`TOLERANCE_STEP`]s of the new frame's: an OKLab distance of `steps` × 0.01 (default 0: exact).
    /// It applies to truecolor colours and to the 256-colour palette's cube and greys (indices 16–255,
    /// by xterm's RGB for them); the 16 ANSI colours and the defaults are the terminal's theme, whose
    /// distances are unknown, and stay exact. The screen then differs from the frame by at most that
    /// much, never more: each frame is compared with what the screen shows.
    pub fn set_tolerance(&mut self, steps: u8) {
        self.tolerance = steps;
    }

    /// After which glyphs the terminal repeats the last one on `CSI n b` (REP, ECMA-48: xterm and tmux
    /// do, GNU screen does not; the walk asks the terminal, [`REP_PROBE`](crate::caps::REP_PROBE)):
    /// then a run of changed cells that go in one look (the same glyph, no colour change) after the
    /// first is sent as `REP` where that is shorter than the glyphs (off by default: a terminal without
    /// it would show the run as missing). At [`RepLevel::Ascii`] only runs of an ASCII glyph (blanks,
    /// the ascii charset): tmux keeps the last character for REP only when it is ASCII, and ignores
    /// REP after a block glyph, leaving the cursor, and every cell written after it, out of place. At
    /// [`RepLevel::Any`] runs of block glyphs too.
    pub fn set_rep(&mut self, rep: RepLevel) {
        self.rep = rep;
    }

    /// After which glyphs runs go as `REP` ([`Encoder::set_rep`]).
    #[must_use]
    pub fn rep(&self) -> RepLevel {
        self.rep
    }

    /// Whether the frames are drawn in block glyphs (the default): then a blank may go as a full
    /// block in the pen's ink where that is fewer bytes. Off for frames of ASCII only (the ascii
    /// charset, for terminals or fonts without the blocks): every glyph sent is then the frame's own.
    pub fn set_blocks(&mut self, blocks: bool) {
        self.blocks = blocks;
    }

    /// Appends to `out` the bytes that turn the previous frame into `frame`: nothing if they are equal,
    /// a full paint if there is no (valid, same-sized) previous frame.
    pub fn encode(&mut self, frame: &Frame, out: &mut Vec<u8>) -> EncodeStats {
        self.encode_rows(frame, 0..frame.height(), out)
    }

    /// [`Encoder::encode`] of a frame that differs from the one last encoded only in `rows` (the
    /// HUD's row on a clock tick): the same bytes and statistics, for the work of those rows. Only
    /// the cells of `rows` are read and compared with the screen; the others keep what the encoder
    /// knew of them (the memo of cells left, whether the screen is off them within the tolerance).
    /// Where the encoder cannot rely on the other rows (a full paint is due, or the tolerance is
    /// below the one the screen was last sent at, so that cells it left may have to go now) it
    /// encodes the whole frame.
    ///
    /// # Panics
    ///
    /// In debug builds, if a cell outside `rows` would be sent (the frame changed there): a bug
    /// of the caller's.
    pub fn encode_rows(&mut self, frame: &Frame, rows: Range<usize>, out: &mut Vec<u8>) -> EncodeStats {
        let width = frame.width();
        self.encode_cells(frame, rows.start.saturating_mul(width)..rows.end.saturating_mul(width), out)
    }

    /// [`Encoder::encode_rows`] of a frame that differs from the one last encoded only in `cells`
    /// (indices into [`Frame::cells`], row by row: the clock's digits of the HUD on a tick): the same
    /// bytes and statistics as [`Encoder::encode`], for the work of those cells.
    ///
    /// # Panics
    ///
    /// In debug builds, if a cell outside `cells` would be sent (the frame changed there): a bug
    /// of the caller's.
    pub fn encode_cells(&mut self, frame: &Frame, cells: Range<usize>, out: &mut Vec<u8>) -> EncodeStats {
        let start = out.len();
        let (width, height) = (frame.width(), frame.height());
        let full_paint = !self.valid || (self.width, self.height) != (width, height);
        let n = frame.cells().len();
        let cells = if full_paint || self.tolerance < self.sent_within {
            0..n
        } else {
            cells.start.min(n)..cells.end.min(n).max(cells.start.min(n))
        };
        // The rows the cells are in (none for no cells).
        let rows = if cells.is_empty() { 0..0 } else { cells.start / width..cells.end.div_ceil(width) };
        out.extend_from_slice(SYNC_BEGIN);
        // `sent`: the frame as it will be on screen, which the tolerance may leave a little off `frame`;
        // packed, as every comparison and price below reads it.
        let cells_changed = if full_paint {
            let sent = &mut self.effective;
            sent.clear();
            sent.extend(frame.cells().iter().map(PackedCell::pack));
            self.pen = paint_full(sent, width, self.bce, self.rep, self.blocks, out);
            self.memo.before.clear(); // (what it remembers was about the screen before)
            std::mem::swap(&mut self.screen, &mut self.effective); // the screen is now what was sent
            self.screen.len()
        } else {
            self.pen.blocks = self.blocks;
            let how = How { bce: self.bce, tolerance: self.tolerance, rep: self.rep };
            self.memo.prepare(frame.cells().len(), self.tolerance);
            #[cfg(debug_assertions)]
            self.assert_unchanged_outside(frame, &cells);
            // In place: the screen's cells become the frame's where they differ (or where within the
            // tolerance stay), packed and compared in one pass, the cells not equal to the screen's
            // listed (`unequal`: only those can the diff change); the diff leaves it what was sent.
            let screen = &mut self.screen;
            let differs = (&mut self.differs, self.differs_set.clone());
            self.memo.scan(frame.cells(), cells.clone(), screen, differs, &mut self.unequal);
            self.differs_set = cells.clone();
            let scratch = (&mut self.first, Some(&mut self.follow));
            diff_marked(screen, width, rows.clone(), how, &mut self.pen, out, &mut self.differs, scratch)
        };
        let body = out.len() - start - SYNC_BEGIN.len();
        if body == 0 {
            out.truncate(start);
        } else {
            out.extend_from_slice(SYNC_END);
        }
        (self.width, self.height) = (width, height);
        self.valid = true;
        self.sent_within = if full_paint { 0 } else { self.tolerance };
        let approximate = self.approximate(frame, rows, cells, full_paint);
        EncodeStats { bytes: out.len() - start, cells_changed, full_paint, approximate }
    }

    /// Whether the screen is off the frame just encoded ([`EncodeStats::approximate`]) after an
    /// encode of `cells` of it, in `rows`. (Out of line, as [`Memo::scan`] is: the encode's loops as
    /// they were.)
    #[inline(never)]
    fn approximate(
        &mut self,
        frame: &Frame,
        rows: Range<usize>,
        scanned: Range<usize>,
        full_paint: bool,
    ) -> bool {
        let (width, height) = (frame.width(), frame.height());
        // Whether a cell on screen now differs in look from the frame's: only a cell the diff changed
        // can (the others were packed from the frame and left so), and it changes only cells that
        // were not equal to the screen's; the rows not scanned are as they were.
        let cells = frame.cells();
        let off = |shown: &PackedCell, k: usize| {
            let cell = PackedCell::pack(&cells[k]);
            *shown != cell && !shown.looks_within(&cell, 0)
        };
        if full_paint {
            self.approximate_rows.clear();
            self.approximate_rows.resize(height, false);
            self.approximate_rows_known = true;
            false
        } else if scanned == (0..cells.len()) {
            // The whole frame: the first cell off is enough; which rows are, only an encode of some
            // rows asks (mostly none does: the settle's exact frame comes first).
            let approximate =
                self.tolerance > 0 && self.unequal.iter().any(|&k| off(&self.screen[k as usize], k as usize));
            self.approximate_rows.fill(false);
            self.approximate_rows_known = !approximate;
            approximate
        } else {
            // The rows scanned whole are off only where the scan finds them so (below); a row scanned
            // in part (a first or last one) has its other cells as they were, off where they were: a
            // row that was off nowhere still is there.
            let known = self.approximate_rows_known;
            for y in rows.clone() {
                let (first, end) = (y * width, (y + 1) * width);
                let was = self.approximate_rows[y];
                self.approximate_rows[y] = !(scanned.start <= first && end <= scanned.end)
                    && (!known || was)
                    && (first..end).filter(|k| !scanned.contains(k)).any(|k| off(&self.screen[k], k));
            }
            if !known {
                // (the rows not scanned are the frame last encoded, the screen as it left them)
                for y in (0..height).filter(|y| !rows.contains(y)) {
                    self.approximate_rows[y] = (y * width..(y + 1) * width).any(|k| off(&self.screen[k], k));
                }
                self.approximate_rows_known = true;
            }
            if self.tolerance > 0 {
                mark_approximate_rows(&self.screen, cells, &self.unequal, width, &mut self.approximate_rows);
            }
            self.approximate_rows.contains(&true)
        }
    }

    /// [`Encoder::encode_cells`]'s precondition: no cell of `frame` outside `scanned` would be sent.
    #[cfg(debug_assertions)]
    fn assert_unchanged_outside(&self, frame: &Frame, scanned: &Range<usize>) {
        let width = frame.width();
        let cells = frame.cells().iter().zip(&self.screen).enumerate();
        for (k, (cell, shown)) in cells.filter(|(k, _)| !scanned.contains(k)) {
            let mut cell = PackedCell::pack(cell);
            assert!(
                *shown == cell || !mark(shown, &mut cell, self.tolerance),
                "encode_cells({scanned:?}): cell {k} (row {}) changed outside the rows or cells told",
                k / width.max(1)
            );
        }
    }
}

/// Marks in `rows` (one flag a row) the rows where a cell of the screen the diff may have changed
/// (`unequal`, in order) differs in look from the frame's (`cells`).
fn mark_approximate_rows(
    screen: &[PackedCell],
    cells: &[Cell],
    unequal: &[u32],
    width: usize,
    rows: &mut [bool],
) {
    let mut i = 0;
    while let Some(&k) = unequal.get(i) {
        let (shown, cell) = (&screen[k as usize], PackedCell::pack(&cells[k as usize]));
        if *shown != cell && !shown.looks_within(&cell, 0) {
            // The row is off: on to the next row's cells.
            let row = k as usize / width.max(1);
            rows[row] = true;
            let next = ((row + 1) * width) as u32;
            i += unequal[i..].partition_point(|&j| j < next);
        } else {
            i += 1;
        }
    }
}

/// `frame` as text lines for a pipe or a file (`mazewalk render`): no cursor moves, each line starts
/// from default colours, sets them only where they change and ends with a reset and `\n`. A frame of
/// default colours gives plain text.
pub fn ansi_lines(frame: &Frame, out: &mut Vec<u8>) {
    for y in 0..frame.height() {
        let mut pen = Pen {
            cursor: None,
            fg: Some(PackedColor::DEFAULT),
            bg: Some(PackedColor::DEFAULT),
            blocks: true,
        };
        for cell in frame.row(y).unwrap_or(&[]).iter().map(PackedCell::pack) {
            let fg = (cell.ch != ' ').then_some(cell.fg);
            write_sgr(out, &mut pen, fg, Some(cell.bg));
            push_char(out, cell.ch);
        }
        if pen.fg != Some(PackedColor::DEFAULT) || pen.bg != Some(PackedColor::DEFAULT) {
            out.extend_from_slice(SGR_RESET);
        }
        out.push(b'\n');
    }
}

/// The terminal state the encoder tracks; `None` means unknown.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pen {
    /// Cursor (column, row); unknown at start and after a glyph in the last column (pending wrap).
    cursor: Option<(usize, usize)>,
    fg: Option<PackedColor>,
    bg: Option<PackedColor>,
    /// Whether the terminal is drawing block glyphs ([`Encoder::set_blocks`]): then a blank may go
    /// as a full block in its colour (and back).
    blocks: bool,
}

impl Pen {
    const UNKNOWN: Pen = Pen { cursor: None, fg: None, bg: None, blocks: true };
}

/// Clears the screen and paints `frame`, choosing the clear colour that gives the fewest bytes.
fn paint_full(
    frame: &[PackedCell],
    width: usize,
    bce: bool,
    rep: RepLevel,
    blocks: bool,
    out: &mut Vec<u8>,
) -> Pen {
    let start = out.len();
    let pen = clear_and_paint(frame, width, PackedColor::DEFAULT, bce, rep, blocks, out);
    // Clearing to the most common blank background saves writing those blanks (needs BCE).
    let Some(bg) = bce.then(|| most_common_blank_bg(frame)).flatten() else { return pen };
    let mut alt = Vec::with_capacity(out.len() - start);
    let alt_pen = clear_and_paint(frame, width, bg, bce, rep, blocks, &mut alt);
    if alt.len() < out.len() - start {
        out.truncate(start);
        out.extend_from_slice(&alt);
        return alt_pen;
    }
    pen
}

/// Resets SGR, sets the background `bg`, clears the screen, then sends `frame` as a diff (with REP
/// as far as `rep` allows).
fn clear_and_paint(
    frame: &[PackedCell],
    width: usize,
    bg: PackedColor,
    bce: bool,
    rep: RepLevel,
    blocks: bool,
    out: &mut Vec<u8>,
) -> Pen {
    let mut pen = Pen { blocks, ..Pen::UNKNOWN };
    // The reset form also clears attributes we don't track (bold…) that someone else may have left.
    write_sgr_reset(out, &mut pen, None, Some(bg));
    out.extend_from_slice(RESET_LNM); // (cursor moves down by vertical tab)
    out.extend_from_slice(b"\x1b[2J");
    let blank = vec![PackedCell { ch: ' ', fg: PackedColor::DEFAULT, bg }; frame.len()];
    // A copy: the diff records the forms it sent, and each trial of `paint_full` starts from the frame.
    let how = How { bce, tolerance: 0, rep };
    diff(&blank, &mut frame.to_vec(), width, how, &mut pen, out, &mut Vec::new());
    pen
}

/// The most common background of space cells, if it is not the default. Ties go to the default, then
/// to the colour met first (row-major), so that a frame always encodes to the same bytes.
fn most_common_blank_bg(frame: &[PackedCell]) -> Option<PackedColor> {
    // Colour -> (blanks, index of its first blank).
    let mut counts: HashMap<PackedColor, (usize, usize)> = HashMap::new();
    for (i, cell) in frame.iter().enumerate().filter(|(_, c)| c.ch == ' ') {
        counts.entry(cell.bg).or_insert((0, i)).0 += 1;
    }
    let (bg, _) = counts
        .into_iter()
        .max_by_key(|&(bg, (n, first))| (n, bg == PackedColor::DEFAULT, std::cmp::Reverse(first)))?;
    (bg != PackedColor::DEFAULT).then_some(bg)
}

/// How a diff may write: BCE ([`Encoder::set_bce`]), the tolerance ([`Encoder::set_tolerance`]),
/// REP ([`Encoder::set_rep`]).
#[derive(Clone, Copy, Debug)]
struct How {
    bce: bool,
    tolerance: u8,
    rep: RepLevel,
}

/// Writes what turns `old` (on screen) into `new` (same size); returns the number of cells changed. A
/// cell of `new` within `how.tolerance` of `old` is left as `old` shows it, and a changed one may
/// take the pen's colour where that is within the tolerance of its own (one SGR less); `new` is updated
/// to what was sent. `differs` is scratch ([`mark_changes`]). (A full paint's diff, against a blank
/// screen; an encoder's diff of a frame against its screen marks with [`Memo::scan`].)
fn diff(
    old: &[PackedCell],
    new: &mut [PackedCell],
    width: usize,
    how: How,
    pen: &mut Pen,
    out: &mut Vec<u8>,
    differs: &mut Vec<bool>,
) -> usize {
    debug_assert_eq!(old.len(), new.len());
    let width = width.max(1);
    differs.clear();
    for (old_row, new_row) in old.chunks_exact(width).zip(new.chunks_exact_mut(width)) {
        mark_changes(old_row, new_row, how.tolerance, differs);
    }
    let rows = 0..new.len() / width;
    diff_marked(new, width, rows, how, pen, out, differs, (&mut Vec::new(), None))
}

/// [`diff`] once `differs` marks which cells of `new` differ from the screen (and `new` is within the
/// tolerance where they do not): the columns, then the rows, with detours to cells of the pen's
/// colours ([`detours`]) where given `follow`. `first` and `follow` are scratch. (A full paint takes
/// no detours: it is one frame, and the detours' search over every cell of it cost 4× its
/// instructions.) Only `rows` are searched for changed cells: none may be marked outside them
/// (then the bytes are those of a search of every row: a row without one writes nothing, and a
/// column or a detour is made of changed cells).
#[allow(clippy::too_many_arguments)]
fn diff_marked(
    new: &mut [PackedCell],
    width: usize,
    rows: Range<usize>,
    how: How,
    pen: &mut Pen,
    out: &mut Vec<u8>,
    differs: &mut [bool],
    (first, mut follow): (&mut Vec<usize>, Option<&mut Follow>),
) -> usize {
    let width = width.max(1);
    debug_assert!(
        !differs[..rows.start * width].contains(&true) && !differs[rows.end * width..].contains(&true)
    );
    // Columns first, where a column of one look goes cheaper down than across; then the rows.
    let mut changed = columns(new, width, rows.clone(), how.tolerance, pen, out, differs, first);
    if let Some(follow) = follow.as_deref_mut() {
        follow.index(new, differs, width, rows.clone(), how);
    }
    for y in rows {
        let tail = erasable_tail(&new[y * width..][..width], how.bce);
        changed += diff_row(pen, out, y, 0, new, width, differs, tail, how, follow.as_deref_mut());
    }
    changed
}

/// The shortest column of changed cells [`columns`] writes downwards.
const MIN_COLUMN: usize = 3;

/// The cursor move from a glyph to the cell under it, as [`columns`] prices it (a vertical tab and
/// a backspace).
const DOWN_ONE: usize = 2;

/// Writes the columns of changed cells of one look (a seam sliding along a wall, a wall's end: the
/// same colours down a column, others beside it) down the column, one colour change for the column
/// and a short move a cell, where that is fewer bytes than writing them row by row (a colour change
/// for each where its row's changed cell before it has other colours); marks them unchanged for
/// the rows that follow. Cells in a run of one look along their row are left to the rows (REP, the
/// pen's colours). Returns the cells written. Only `rows` are searched (none changed outside them).
#[allow(clippy::too_many_arguments)]
fn columns(
    new: &mut [PackedCell],
    width: usize,
    rows: Range<usize>,
    tolerance: u8,
    pen: &mut Pen,
    out: &mut Vec<u8>,
    differs: &mut [bool],
    first: &mut Vec<usize>,
) -> usize {
    if rows.len() < MIN_COLUMN {
        return 0;
    }
    let height = rows.end; // (a column ends at the last row searched at the latest)
    first_columns(new, differs, width, rows, first);
    let mut changed = 0;
    for (x, &first) in first.iter().enumerate() {
        // Changed, and not in a run of its look along the row.
        let alone = |new: &[PackedCell], differs: &[bool], k: usize| {
            differs[k]
                && !(x > 0 && differs[k - 1] && new[k - 1] == new[k])
                && !(x + 1 < width && differs[k + 1] && new[k + 1] == new[k])
        };
        let mut y = first;
        while y < height {
            let k = y * width + x;
            if !alone(new, differs, k) {
                y += 1;
                continue;
            }
            let cell = new[k];
            let run = (y..height)
                .take_while(|&r| new[r * width + x] == cell && alone(new, differs, r * width + x))
                .count();
            if run >= MIN_COLUMN && column_pays(new, differs, width, (x, y, run), tolerance) {
                for r in y..y + run {
                    write_move(out, pen, x, r);
                    new[r * width + x] = write_cell(out, pen, &cell, width, tolerance);
                    differs[r * width + x] = false;
                }
                changed += run;
            }
            y += run;
        }
    }
    changed
}

/// For each column, the first row of `rows` from which [`MIN_COLUMN`] cells down it (in `rows`) are
/// all changed and of one look (`rows.end` where none is): [`columns`] starts there. Exact: a run [`columns`] could write
/// starts at such a row (its cells are changed and of one look, and more besides); a shorter run
/// before the first such row ends at it at the latest (a run over it would have one of at least
/// [`MIN_COLUMN`] cells in it from a row further up), and nothing is written for it. These are
/// the column's own cells, which writing the columns before it does not change. Row by row, eight
/// flags a word, a byte a column: a column with nothing changed, or whose first row is found
/// already, costs next to nothing.
fn first_columns(
    new: &[PackedCell],
    differs: &[bool],
    width: usize,
    rows: Range<usize>,
    first: &mut Vec<usize>,
) {
    let height = rows.end;
    first.clear();
    first.resize(width, height);
    for y in rows.start..height.saturating_sub(MIN_COLUMN - 1) {
        let rows: [&[bool]; MIN_COLUMN] = std::array::from_fn(|i| &differs[(y + i) * width..][..width]);
        // Whether column `x` starts a column here (its first row not found yet).
        let starts = |first: &[usize], x: usize| {
            let k = y * width + x;
            first[x] == height
                && rows.iter().all(|row| row[x])
                && (1..MIN_COLUMN).all(|i| new[k + i * width] == new[k])
        };
        let mut x = 0;
        // Eight columns at a time: a byte each (the first the highest), set where the column has a
        // changed cell in all the rows and its first row is still to find; only those are looked at.
        while x + 8 <= width {
            let word = |row: &[bool]| row[x..x + 8].iter().fold(0u64, |w, &d| w << 8 | u64::from(d));
            let mut open = rows.iter().fold(u64::MAX, |w, row| w & word(row));
            if open != 0 {
                open &= first[x..x + 8].iter().fold(0u64, |w, &f| w << 8 | u64::from(f == height));
            }
            while open != 0 {
                let byte = open.leading_zeros() / 8;
                open &= !(0xff << (56 - 8 * byte));
                let at = x + byte as usize;
                if starts(first, at) {
                    first[at] = y;
                }
            }
            x += 8;
        }
        for x in x..width {
            if starts(first, x) {
                first[x] = y;
            }
        }
    }
}

/// Whether the `run` cells of one look from row `y` down column `x` cost fewer bytes down the
/// column than in the rows: down, one colour change (from nothing known) and a [`DOWN_ONE`] a
/// cell; across, each cell's colour change from its row's changed cell before it (the pen the rows
/// would leave), or from nothing known and a move where that cell did not change. Colours as they
/// would be sent ([`shortest`]).
fn column_pays(
    new: &[PackedCell],
    differs: &[bool],
    width: usize,
    (x, y, run): (usize, usize, usize),
    tolerance: u8,
) -> bool {
    let cell = shortest(&new[y * width + x], tolerance);
    let glyph = cell.ch.len_utf8();
    let down = Sgr::to_cell(&Pen::UNKNOWN, &cell).len() + run * glyph + (run - 1) * DOWN_ONE;
    let across: usize = (y..y + run)
        .map(|r| {
            let k = r * width + x;
            let before = (x > 0 && differs[k - 1]).then(|| shortest(&new[k - 1], tolerance));
            let pen = before.map_or(Pen::UNKNOWN, |b| Pen { fg: Some(b.fg), bg: Some(b.bg), ..Pen::UNKNOWN });
            let colours = Sgr::to_cell(&pen, &cell).len();
            colours + glyph + if before.is_some() { 0 } else { DOWN_ONE }
        })
        .sum();
    down < across
}

/// The last diff's frame (as given, before the tolerance) and which of its cells [`Memo::scan`]
/// left as the screen showed them. A cell left so stays as it was on screen (only changed cells are
/// written), so where the next frame has it again the answer is the same: left, with no colour
/// measured (walking, a wall's cells within the tolerance of the blanks on screen are asked about
/// again every frame). Forgotten on a full paint, a resize and a new tolerance.
#[derive(Clone, Debug, Default)]
struct Memo {
    before: Vec<PackedCell>,
    left: Vec<bool>,
    tolerance: u8,
}

impl Memo {
    /// Ready for a diff of `cells` cells at `tolerance`: what it holds, if about such a diff, else
    /// nothing left.
    fn prepare(&mut self, cells: usize, tolerance: u8) {
        if self.before.len() != cells || self.tolerance != tolerance {
            let blank = PackedCell { ch: ' ', fg: PackedColor::DEFAULT, bg: PackedColor::DEFAULT };
            self.before.clear();
            self.before.resize(cells, blank);
            self.left.clear();
            self.left.resize(cells, false);
            self.tolerance = tolerance;
        }
    }

    /// `cells` in `range` packed and marked in `differs` against the screen ([`Memo::mark`]: the
    /// memo first, then the tolerance), in one pass, each of the screen's cells becoming the frame's
    /// as it is to be sent (the frame's, or the screen's own where within the tolerance: the diff
    /// reads nothing else of the screen); the indices of the cells not equal to the screen's (the
    /// only ones a diff can change) in `unequal`. The cells outside `range` are not read (their
    /// memo and screen stay as they are) and are marked unchanged: of `differs`, only the cells
    /// of `set` may be set (the rest are cleared already). Keeps the buffers' storage. (Out of line:
    /// inlined into [`Encoder::encode_rows`] it called the colours' OKLab lookups out of line, 83,209
    /// calls and 1.07× the encoder's instructions over `turn_frames`' 39 frames of turning.)
    #[inline(never)]
    fn scan(
        &mut self,
        cells: &[Cell],
        range: Range<usize>,
        screen: &mut [PackedCell],
        (differs, set): (&mut Vec<bool>, Range<usize>),
        unequal: &mut Vec<u32>,
    ) {
        let n = cells.len();
        debug_assert_eq!((screen.len(), self.before.len(), self.left.len()), (n, n, n));
        // (Same length frame after frame: no storage and no writes here but the first time.)
        differs.resize(n, false);
        unequal.clear();
        // The flags set before and outside `range` cleared (a tick after a tick: none).
        let set = set.start.min(n)..set.end.min(n);
        differs[set.start..set.end.min(range.start).max(set.start)].fill(false);
        differs[set.start.max(range.end).min(set.end)..set.end].fill(false);
        let start = range.start;
        let (cells, screen, differs) =
            (&cells[range.clone()], &mut screen[range.clone()], &mut differs[range]);
        for i in 0..cells.len() {
            let k = start + i;
            let cell = PackedCell::pack(&cells[i]);
            // The common case, a cell as the screen shows it: nothing to write but its flag.
            differs[i] = screen[i] != cell && {
                unequal.push(k as u32);
                let (shown, mut cell) = (screen[i], cell);
                let differ = self.mark(k, &shown, &mut cell);
                screen[i] = cell;
                differ
            };
        }
    }

    /// [`mark`] of cell `k` (not equal to `shown`), answering from the memo where the frame's cell is
    /// one it measured and left, and remembering those it measures and leaves. A cell equal to the
    /// screen's is not written, nor is one answered from the memo: the screen's cell stays what it
    /// was when remembered. Every other cell is forgotten (it may be written). A cell of the same
    /// look in another spelling (a one-colour `▀` for a blank) leaves the screen's spelling as it is,
    /// so that what the diff reads of the screen (a blank tail to erase, a run to repeat) is the same
    /// whether or not its row was scanned: [`Encoder::encode_rows`] sends what [`Encoder::encode`]
    /// does.
    #[inline(always)]
    fn mark(&mut self, k: usize, shown: &PackedCell, cell: &mut PackedCell) -> bool {
        let tolerance = self.tolerance;
        if tolerance > 0 && cell.may_be_near(tolerance) {
            if self.left[k] && self.before[k] == *cell {
                *cell = *shown;
                return false;
            }
            let within = shown.looks_within(cell, tolerance);
            if within {
                self.before[k] = *cell;
                *cell = *shown;
            }
            self.left[k] = within;
            return !within;
        }
        self.left[k] = false;
        let differs = !shown.looks_within(cell, 0);
        if !differs {
            *cell = *shown; // the same look: the screen keeps its spelling, as a scan of no row would
        }
        differs
    }
}

/// Which cells of row `new` look different from row `old` (one look comparison a cell: the diff's
/// searches read the flags), appended to `differs`. A cell within `tolerance` of `old` is first set
/// to `old`.
fn mark_changes(old: &[PackedCell], new: &mut [PackedCell], tolerance: u8, differs: &mut Vec<bool>) {
    differs.extend(old.iter().zip(new).map(|(shown, cell)| shown != cell && mark(shown, cell, tolerance)));
}

/// Whether `cell` looks different from `shown` (which it is not equal to); set to `shown` where
/// within `tolerance` of it. ([`Memo::mark`] is this with a memo.)
#[inline(always)]
fn mark(shown: &PackedCell, cell: &mut PackedCell, tolerance: u8) -> bool {
    // Only truecolor colours and palette entries past the ANSI 16 with a neighbour that close
    // can be close without being equal; a cell not within the tolerance does not look the same
    // either (one comparison).
    // Against what the screen shows, never the frame before: a slow fade is resent once it has
    // moved the tolerance from what was sent, however small each frame's step.
    if tolerance > 0 && cell.may_be_near(tolerance) {
        let within = shown.looks_within(cell, tolerance);
        if within {
            *cell = *shown;
        }
        return !within;
    }
    let differs = !shown.looks_within(cell, 0);
    if !differs {
        *cell = *shown; // (as [`Memo::mark`]: the same look keeps the screen's spelling)
    }
    differs
}

/// The first of `flags` set from index `from` on: sixteen at a time (one test: a frame's rows are
/// mostly unchanged), then the one.
#[inline]
fn next_set(flags: &[bool], from: usize) -> Option<usize> {
    // (Turning, the cell after one written is mostly changed too.)
    if flags.get(from) == Some(&true) {
        return Some(from);
    }
    let mut i = from;
    while let Some(chunk) = flags.get(i..i + 16) {
        if chunk.iter().fold(false, |any, &set| any | set) {
            break;
        }
        i += 16;
    }
    (i..flags.len()).find(|&k| flags[k])
}

/// Where a row's tail of same-background spaces starts, and that background, if `\x1b[K` may erase it.
fn erasable_tail(row: &[PackedCell], bce: bool) -> Option<(usize, PackedColor)> {
    let last = row.last().filter(|c| c.ch == ' ')?;
    if !bce && last.bg != PackedColor::DEFAULT {
        return None;
    }
    let len = row.iter().rev().take_while(|c| c.ch == ' ' && c.bg == last.bg).count();
    Some((row.len() - len, last.bg))
}

/// Encodes the changes of row `y` of `frame` (rows of `width` cells) from column `from` on (`differs`:
/// which cells differ from the screen); returns the number of cells changed. Changed cells are
/// written within `how.tolerance` of `frame` ([`write_cell`]), runs of one look as `REP` where
/// `how.rep` allows ([`repeat`]), and `frame` records what was sent. With `follow`, before a cell that
/// needs a colour change, the changed cells anywhere below that need none may go first ([`detours`]).
#[allow(clippy::too_many_arguments)]
fn diff_row(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    y: usize,
    from: usize,
    frame: &mut [PackedCell],
    width: usize,
    differs: &mut [bool],
    tail: Option<(usize, PackedColor)>,
    how: How,
    mut follow: Option<&mut Follow>,
) -> usize {
    let tolerance = how.tolerance;
    let row = y * width..(y + 1) * width;
    let mut changed = 0;
    let mut from = from;
    while let Some(x) = next_set(&differs[row.clone()], from) {
        if let Some((start, bg)) = tail
            && x >= start
        {
            // Everything left to change is blank: erase to end of line, or write the cells, whichever is
            // shorter (try both, keep the shorter).
            changed += differs[row.start + x..row.end].iter().filter(|&&d| d).count();
            let mark = out.len();
            let mut erase = *pen;
            reach(&mut erase, out, y, x, &frame[row.clone()], Then::Erase(bg));
            let erase_len = out.len() - mark;
            out.truncate(mark);
            let mut write = *pen;
            // Exact (tolerance 0): a trial, so it must leave `frame` as it is.
            let exact = How { tolerance: 0, ..how };
            diff_row(&mut write, out, y, x, frame, width, differs, None, exact, None);
            if erase_len < out.len() - mark {
                out.truncate(mark);
                reach(pen, out, y, x, &frame[row.clone()], Then::Erase(bg));
            } else {
                *pen = write;
            }
            return changed;
        }
        if let Some(follow) = follow.as_deref_mut() {
            // Again only where the pen's colours changed under the detours ([`detours`]).
            loop {
                let colours = (pen.fg, pen.bg);
                let written = detours(pen, out, frame, width, differs, row.start + x, how, follow);
                changed += written;
                if written == 0 || (pen.fg, pen.bg) == colours {
                    break;
                }
            }
        }
        let new = &mut frame[row.clone()];
        if pen.cursor == Some((x, y)) {
            // The cursor is there (the cell after the last one written): no route to price.
            new[x] = write_cell(out, pen, &new[x], width, tolerance);
        } else if let Some(sent) = reach(pen, out, y, x, new, Then::Cell(new[x], tolerance)) {
            new[x] = sent;
        }
        changed += 1;
        from = x + 1;
        if how.rep != RepLevel::None {
            // (before the erasable tail, which the branch above prices as a whole)
            let end = tail.map_or(width, |(start, _)| start);
            let repeated = repeat(pen, out, new, end, &differs[row.clone()], x, tolerance, how.rep);
            changed += repeated;
            from += repeated;
        }
        // Written: no detour comes back to them. (Mostly the one cell: a store, not a `memset`.)
        differs[row.start + x] = false;
        if from > x + 1 {
            differs[row.start + x + 1..row.start + from].fill(false);
        }
    }
    changed
}

/// The changed cells of a frame (after the columns, before the rows; none in a row's erasable
/// tail) by the colours they show ([`colour_key`]), for [`detours`]: grouped by look, each look's
/// cells in row-major order (a counting sort by the look each key maps to, not a sort by key).
#[derive(Clone, Debug, Default)]
struct Follow {
    /// The cells of every look, look after look.
    cells: Vec<u32>,
    looks: Vec<Look>,
    /// Each key's look (index into `looks`).
    ids: FxHashMap<u64, u32>,
    /// Scratch: `(look, cell)` in row-major order, before the cells are grouped.
    marks: Vec<(u32, u32)>,
    /// Tests: take the detours by the whole search every turn, the fast path's oracle.
    #[cfg(test)]
    whole_search: bool,
    /// Tests: the cells the fast path chose.
    #[cfg(test)]
    fast: usize,
}

/// The cells of one look in [`Follow::cells`]: up to `end`, from `head` on (those before are
/// written: within a frame a cell is only ever written, never marked changed again).
#[derive(Clone, Copy, Debug)]
struct Look {
    head: u32,
    end: u32,
    /// The last candidate of this look [`detours`] priced: the cell, the cell before it where
    /// that was still changed, and what it would cost in its row (a function of those two: the
    /// same for the next candidate of the same cells, and for a candidate not taken, which mostly
    /// comes up again before the next cell).
    priced: Option<(PackedCell, Option<PackedCell>, usize)>,
}

impl Follow {
    /// Indexes the cells `differs` marks in `frame`, but those a row's erasable tail holds (the rows
    /// price that tail as a whole), by the colours they would be sent in ([`shortest`]: those the
    /// pen has after a cell of them). Only `rows` are searched (none marked outside them).
    fn index(&mut self, frame: &[PackedCell], differs: &[bool], width: usize, rows: Range<usize>, how: How) {
        let (bce, tolerance) = (how.bce, how.tolerance);
        self.marks.clear();
        self.looks.clear();
        self.ids.clear();
        // Neighbours along a row mostly show one look: the last key's look is tried before the map;
        // and mostly are one cell, whose key is the last cell's (a key is the cell's alone).
        let mut last: Option<(u64, u32)> = None;
        let mut last_cell: Option<(PackedCell, Option<u64>)> = None;
        let cells = rows.start * width..rows.end * width;
        let searched = frame[cells.clone()].chunks_exact(width).zip(differs[cells].chunks_exact(width));
        for (y, (row, row_differs)) in (rows.start..).zip(searched) {
            let end = erasable_tail(row, bce).map_or(width, |(start, _)| start);
            let mut x = 0;
            while let Some(found) = next_set(&row_differs[..end], x) {
                let cell = row[found];
                let key = match last_cell {
                    Some((held, key)) if held == cell => key,
                    _ => {
                        let key = colour_key(&shortest(&cell, tolerance));
                        last_cell = Some((cell, key));
                        key
                    }
                };
                if let Some(key) = key {
                    let id = match last {
                        Some((last_key, id)) if last_key == key => id,
                        _ => {
                            let fresh = self.looks.len() as u32;
                            let id = *self.ids.entry(key).or_insert(fresh);
                            if id == fresh {
                                self.looks.push(Look { head: 0, end: 0, priced: None });
                            }
                            last = Some((key, id));
                            id
                        }
                    };
                    self.looks[id as usize].end += 1; // a count, until the offsets below
                    self.marks.push((id, (y * width + found) as u32));
                }
                x = found + 1;
            }
        }
        let mut start = 0;
        for look in &mut self.looks {
            let count = look.end;
            (look.head, look.end) = (start, start);
            start += count;
        }
        self.cells.clear();
        self.cells.resize(start as usize, 0);
        for &(id, cell) in &self.marks {
            let look = &mut self.looks[id as usize];
            self.cells[look.end as usize] = cell;
            look.end += 1;
        }
    }

    /// The look of the cells of colours `key`, if any are indexed.
    fn look(&self, key: u64) -> Option<u32> {
        self.ids.get(&key).copied()
    }

    /// What changed cell `k` of look `look` would cost in its row ([`row_cost`]) after the cell
    /// before it there where that is changed (colours unknown where it is not).
    fn later(
        &mut self,
        look: u32,
        k: usize,
        frame: &[PackedCell],
        differs: &[bool],
        width: usize,
        (blocks, tolerance): (bool, u8),
    ) -> usize {
        let (cell, before) = (frame[k], (!k.is_multiple_of(width) && differs[k - 1]).then(|| frame[k - 1]));
        let look = &mut self.looks[look as usize];
        if let Some((held, held_before, later)) = look.priced
            && (held, held_before) == (cell, before)
        {
            return later;
        }
        let later = row_cost(&cell, before.as_ref(), (blocks, tolerance));
        look.priced = Some((cell, before, later));
        later
    }

    /// The first cell of look `look` still changed (`differs`) at or after cell `at` (row-major), or
    /// else the first before it; with its place in [`Follow::cells`].
    fn first(&mut self, look: u32, at: usize, differs: &[bool]) -> Option<(usize, usize)> {
        let look = &mut self.looks[look as usize];
        let (mut head, end) = (look.head as usize, look.end as usize);
        while head < end && !differs[self.cells[head] as usize] {
            head += 1;
        }
        look.head = head as u32;
        let cells = &self.cells[head..end];
        let &first = cells.first()?;
        if first as usize >= at {
            return Some((first as usize, head)); // (mostly: the rows write the cells before the cursor)
        }
        let split = head + cells.partition_point(|&k| (k as usize) < at);
        let later = (split..end).find(|&i| differs[self.cells[i] as usize]);
        Some(later.map_or((first as usize, head), |i| (self.cells[i] as usize, i)))
    }

    /// The first cell of look `look` still changed after its cell at place `place` in
    /// [`Follow::cells`], with its place.
    fn next_after(&self, look: u32, place: usize, differs: &[bool]) -> Option<(usize, usize)> {
        let end = self.looks[look as usize].end as usize;
        (place + 1..end).map(|i| (self.cells[i] as usize, i)).find(|&(k, _)| differs[k])
    }
}

/// What `cell` would cost in its row after changed cell `before` (colours unknown where `None`):
/// its glyph and its colour change, both in the colours they would be sent in ([`shortest`]).
fn row_cost(cell: &PackedCell, before: Option<&PackedCell>, (blocks, tolerance): (bool, u8)) -> usize {
    let shown = before.map(|b| shortest(b, tolerance));
    let row_pen = Pen { cursor: None, fg: shown.map(|b| b.fg), bg: shown.map(|b| b.bg), blocks };
    let sent = shortest(cell, tolerance).canonical();
    Sgr::to_cell(&row_pen, &sent).len() + sent.ch.len_utf8()
}

/// `cell` in the colours of their shortest codes within `tolerance` ([`PackedColor::cheapest`]):
/// what [`cell_form`] sends for it from a pen near neither colour, as the detours' index and prices
/// reckon it.
#[inline]
fn shortest(cell: &PackedCell, tolerance: u8) -> PackedCell {
    PackedCell { ch: cell.ch, fg: cell.fg.cheapest(tolerance), bg: cell.bg.cheapest(tolerance) }
}

/// The colours a blank, a half block or a full block shows, as one word whatever its form (`▀` or
/// `▄`, a blank or a full block): its two halves' colours, the smaller first (a cell of one colour
/// has it twice). `None` for other glyphs and for cells that show a default colour.
fn colour_key(cell: &PackedCell) -> Option<u64> {
    let [top, bottom] = cell.halves()?;
    Some(pair_key(top, bottom))
}

fn pair_key(a: PackedColor, b: PackedColor) -> u64 {
    let (a, b) = (a.word().min(b.word()), a.word().max(b.word()));
    u64::from(a) << 32 | u64::from(b)
}

/// The bytes a [`detours`] must save, by its own reckoning, before it is taken: its prices are
/// estimates (a move's bound, the colour change a cell would need in its row), and detours taken
/// for a byte or none cost as many as they saved (`walk_bytes` in 256 colours: walking 25.7 KB/s
/// with no margin, 25.5 with this one, as without detours; turning 73.3 and 73.1).
const MARGIN: usize = 1;

/// Issue #42: before changed cell `next` (the first still to write, row-major), where it needs a
/// colour change, writes changed cells further on that need none, one at a time while any pays:
/// of the first on or after the cursor (row-major, else the first before it) of each look the
/// pen's colours draw (a blank in its background, a full block in its ink, a half block of the
/// two), the one that saves the most, if any saves more than [`MARGIN`]: the move there and the
/// move on to `next` against the move to `next` it replaces and what that cell would cost in its
/// row (its glyph and its colour change from the changed cell before it there, or from colours
/// unknown). Then the run of its look after it ([`repeat`]).
/// Returns the cells written (0: none). Turning, a wall's edge slants across the rows: row by row
/// the pen changes at each of its cells, where the cells of one look are a short move apart.
///
/// The pen's colours stay while it writes cells of its looks, so what depends only on them (the
/// three looks, whether `next` needs a colour change) is found once for all the detours before
/// `next`; should a cell's writing change them after all, it returns, and the caller asks again.
/// Each look's candidate and what it is worth but for the moves from the cursor carry from one
/// turn to the next ([`Lead`]); along a run of the chosen look, its next cell, at the cursor, is
/// taken without the moves priced where the whole pricing could choose no other (the fast path).
#[allow(clippy::too_many_arguments)]
fn detours(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    frame: &mut [PackedCell],
    width: usize,
    differs: &mut [bool],
    next: usize,
    how: How,
    follow: &mut Follow,
) -> usize {
    #[cfg(test)]
    if follow.whole_search {
        return tests::detours_searched(pen, out, frame, width, differs, next, how, follow);
    }
    let (Some(fg), Some(bg)) = (pen.fg, pen.bg) else { return 0 };
    if Sgr::to_cell(pen, &frame[next]).len() == 0 {
        return 0; // the pen draws it as it is: on along the row
    }
    // (Asked before the looks and their cells: half the time the pen draws it in another form, or
    // within the tolerance. The move to it asks it again, from the memo.)
    if cell_form(pen, &frame[next], how.tolerance).1.len() == 0 {
        return 0; // the pen draws it: on along the row
    }
    // The looks and the glyph each goes in with no colour change: a blank in the pen's paper as a
    // space, one in its ink as a full block (where the frames have blocks), a half block of the two
    // as itself or its inverse. (The same cell may come up under two keys, where the pen's colours
    // are one.)
    let blank = follow.look(pair_key(bg, bg)).map(|look| Lead::new(look, 1, false));
    let block = (pen.blocks && fg != bg).then(|| follow.look(pair_key(fg, fg))).flatten();
    let block = block.map(|look| Lead::new(look, FULL_BLOCK.len_utf8(), true));
    let half =
        (fg != bg).then(|| follow.look(pair_key(fg, bg))).flatten().map(|look| Lead::new(look, 3, false));
    if blank.is_none() && block.is_none() && half.is_none() {
        return 0;
    }
    let mut leads = [blank, block, half];
    let (nx, ny) = (next % width, next / width);
    let margin = MARGIN as isize;
    let mut written = 0;
    // The last cell written and its form: the pen's colours stay while it writes (it returns where
    // they change), and a cell's form is a function of them and the cell.
    let mut written_form = None;
    // The last cell the fast path priced in its row right after written cells, and that price.
    let mut alone: Option<(PackedCell, usize)> = None;
    loop {
        let cursor = pen.cursor.map(|(x, y)| y * width + x);
        let at = cursor.unwrap_or(0);
        let mut found = [None; 3];
        for i in 0..3 {
            if let Some(lead) = &mut leads[i] {
                found[i] = lead.candidate(at, follow, frame, differs);
            }
        }
        if found.iter().flatten().all(|&k| k == next) {
            return written;
        }
        let mut values = [None; 3];
        for i in 0..3 {
            if let (Some(lead), Some(k)) = (&mut leads[i], found[i])
                && k != next
            {
                values[i] = Some((
                    k,
                    lead.value(k, (nx, ny), (frame, differs, width), pen.blocks, how.tolerance, follow),
                ));
            }
        }
        let direct = |pen: &Pen| move_bound(pen.cursor, nx, ny) as isize;
        // The largest saving above `MARGIN` wins, the first of equals.
        //
        // The invariant the fast path rests on: the move from the cursor costs nothing to the cell
        // at the cursor and at least a byte to any other, so a candidate at the cursor whose value
        // is no less than every other's saves strictly more than each, whatever their order: it is
        // the one the whole pricing below chooses, without the moves from the cursor priced. (And
        // as it is not `next`, the move to `next` costs at least a byte: a value of `MARGIN` saves
        // more than it.)
        let best_value = |values: &[Option<(usize, isize)>; 3], skip: usize| {
            (0..3).filter(|&i| i != skip).filter_map(|i| values[i]).map(|(_, v)| v).max()
        };
        let at_cursor = (0..3).find(|&i| values[i].is_some_and(|(k, _)| Some(k) == cursor));
        let best = match at_cursor {
            Some(i) if best_value(&values, i).is_none_or(|v| v <= values[i].unwrap().1) => {
                let value = values[i].unwrap().1;
                if value < margin && value + direct(pen) <= margin {
                    return written;
                }
                i
            }
            _ => {
                let direct = direct(pen);
                let mut best: Option<(isize, usize)> = None;
                for (i, &(k, value)) in values.iter().enumerate().filter_map(|(i, v)| Some((i, v.as_ref()?)))
                {
                    let saving = value + direct - move_bound(pen.cursor, k % width, k / width) as isize;
                    if saving > margin && best.is_none_or(|(most, _)| saving > most) {
                        best = Some((saving, i));
                    }
                }
                let Some((_, i)) = best else { return written };
                i
            }
        };
        let (mut k, _) = values[best].unwrap();
        write_move(out, pen, k % width, k / width);
        // The fast path: the cells written from here on are `at`'s row-major successors up to the
        // cursor (where `at <= k`, and the cells between written or passed), so the other looks'
        // candidates stand, values and all, until the cursor reaches the first of them at or after
        // `at` (`guard`): neither passed nor written nor right after a written cell. The chosen
        // look's next cell, where it is at the cursor and its value no less than theirs, is then
        // the whole turn's choice by the invariant above.
        let others = best_value(&values, best);
        let guard = (0..3)
            .filter(|&i| i != best)
            .filter_map(|i| leads[i].and_then(|other| other.answer()))
            .filter(|&other| other >= at)
            .min()
            .unwrap_or(usize::MAX);
        let lead = leads[best].as_mut().expect("a lead of each value");
        // No move to `next` costs more than this (`move_bound` is `CUP`'s bytes at most, or 3).
        let ceiling = move_bound(None, nx, ny).max(3) as isize;
        loop {
            written += write_detour(pen, out, frame, width, differs, k, how, &mut written_form);
            if (pen.fg, pen.bg) != (Some(fg), Some(bg)) {
                return written;
            }
            let Some(to) = pen.cursor.map(|(x, y)| y * width + x) else { break };
            if at > k || to >= guard {
                break;
            }
            let Some(c) = lead.after(k, to, follow, frame, differs) else { break };
            // Right after a written cell, what it would cost in its row depends on it alone. (Not
            // through the look's memo, [`Follow::later`]: a run's cells would push out its last
            // candidate after a jump, mostly the next jump's too.)
            let later = match alone {
                Some((cell, later)) if cell == frame[c] => later,
                _ => {
                    let later = row_cost(&frame[c], None, (pen.blocks, how.tolerance));
                    alone = Some((frame[c], later));
                    later
                }
            };
            // Its value with the dearest move on to `next`: where that is enough, so is its value.
            let floor = later as isize - lead.glyph as isize - ceiling;
            if floor < margin || others.is_some_and(|v| v > floor) {
                let value =
                    lead.value(c, (nx, ny), (frame, differs, width), pen.blocks, how.tolerance, follow);
                if others.is_some_and(|v| v > value) {
                    break;
                }
                if value < margin && value + direct(pen) <= margin {
                    return written;
                }
            }
            k = c;
            #[cfg(test)]
            {
                follow.fast += 1;
            }
        }
    }
}

/// Writes detour cell `k` at the cursor, and the run of its look after it ([`repeat`]); marks
/// them written. Returns the cells written. `last`: the last cell written from the pen's colours
/// now and its form ([`cell_form`], a function of the two), kept by the caller while they stay.
#[allow(clippy::too_many_arguments)]
fn write_detour(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    frame: &mut [PackedCell],
    width: usize,
    differs: &mut [bool],
    k: usize,
    how: How,
    last: &mut Option<(PackedCell, (PackedCell, Sgr))>,
) -> usize {
    let (x, y) = (k % width, k / width);
    // (The form of a cell equal to the last one written: the pen's colours are the same.)
    let form = match *last {
        Some((cell, form)) if cell == frame[k] => form,
        _ => {
            let form = cell_form(pen, &frame[k], how.tolerance);
            *last = Some((frame[k], form));
            form
        }
    };
    frame[k] = write_form(out, pen, form, width);
    differs[k] = false;
    if how.rep != RepLevel::None
        && may_repeat(&frame[y * width..][..width], &differs[y * width..][..width], x, how.rep)
    {
        let row = &mut frame[y * width..][..width];
        // (The row's erasable tail only where a run may follow: a scan of the row's end.)
        let end = erasable_tail(row, how.bce).map_or(width, |(start, _)| start);
        let repeated = repeat(pen, out, row, end, &differs[y * width..][..width], x, how.tolerance, how.rep);
        differs[k + 1..=k + repeated].fill(false);
        return 1 + repeated;
    }
    1
}

/// One of the looks [`detours`] draws from the pen, carried from one cell to the next (within one
/// call: one `next`): its candidate ([`Follow::first`]) and the candidate's value.
///
/// A candidate saves the move to `next` and what the cell would cost in its row
/// ([`Follow::later`]), less the moves there and on to `next` and its glyph (moves priced by
/// [`move_bound`]: most are not taken). All but the two moves from the cursor is its *value*,
/// which the cursor does not change: `saving = value + move_bound(cursor, next) -
/// move_bound(cursor, candidate)`.
#[derive(Clone, Copy, Debug)]
struct Lead {
    look: u32,
    /// The bytes of the glyph the look goes in.
    glyph: usize,
    /// Whether a text space is no candidate (the full-block look: a text space stays a space).
    no_text: bool,
    /// The cursor's cell (row-major) [`Follow::first`] answered from, and its answer.
    first: Option<(usize, Option<(usize, usize)>)>,
    /// The last candidate valued: the cell, whether the cell before it was changed (all its
    /// value depends on while `next` stays: [`Follow::later`]), and the value.
    valued: Option<(usize, bool, isize)>,
}

impl Lead {
    fn new(look: u32, glyph: usize, no_text: bool) -> Lead {
        Lead { look, glyph, no_text, first: None, valued: None }
    }

    /// [`Follow::first`] of the look from cell `at`, from its last answer where that tells: cells
    /// are only ever written, never marked changed again, so while the cursor has not gone back
    /// and that cell is still changed, it stands (one at or after the cursor then was the first
    /// changed one there, so it is for any cursor up to it; one before it was the first changed at
    /// all, with none after). Where it was at or after the cursor then and is written now with
    /// every cell up to the cursor (the detour's cell, the run after it), the first at or after
    /// the cursor is the look's next changed cell after it, if any.
    fn candidate(
        &mut self,
        at: usize,
        follow: &mut Follow,
        frame: &[PackedCell],
        differs: &[bool],
    ) -> Option<usize> {
        let first = match self.first {
            Some((from, None)) if from <= at => None,
            Some((from, Some((k, place)))) if from <= at => {
                if differs[k] && (k >= at || k < from) {
                    Some((k, place))
                } else if from <= k
                    && k < at
                    && differs[k..at].iter().all(|&d| !d)
                    && let Some(next) = follow.next_after(self.look, place, differs)
                {
                    self.first = Some((at, Some(next)));
                    Some(next)
                } else {
                    self.first = Some((at, follow.first(self.look, at, differs)));
                    self.first.and_then(|(_, first)| first)
                }
            }
            _ => {
                self.first = Some((at, follow.first(self.look, at, differs)));
                self.first.and_then(|(_, first)| first)
            }
        };
        first.map(|(k, _)| k).filter(|&k| !(self.no_text && frame[k].is_text_space()))
    }

    /// Its last [`Follow::first`] answer (before a text space is left out), if any.
    fn answer(&self) -> Option<usize> {
        self.first.and_then(|(_, first)| first).map(|(k, _)| k)
    }

    /// Its candidate from the cursor at `to`, where that is `to` itself, once its last candidate
    /// `k` and every cell up to `to` are written.
    fn after(
        &mut self,
        k: usize,
        to: usize,
        follow: &Follow,
        frame: &[PackedCell],
        differs: &[bool],
    ) -> Option<usize> {
        let Some((_, Some((held, place)))) = self.first else { return None };
        debug_assert_eq!(held, k);
        let (c, place) = follow.next_after(self.look, place, differs).filter(|&(c, _)| c == to)?;
        if self.no_text && frame[c].is_text_space() {
            return None;
        }
        self.first = Some((to, Some((c, place))));
        Some(c)
    }

    /// The value of candidate `k` (see [`Lead`]), on to `next`. (Inlined: mostly remembered.)
    #[inline]
    fn value(
        &mut self,
        k: usize,
        next: (usize, usize),
        (frame, differs, width): (&[PackedCell], &[bool], usize),
        blocks: bool,
        tolerance: u8,
        follow: &mut Follow,
    ) -> isize {
        let before = !k.is_multiple_of(width) && differs[k - 1];
        match self.valued {
            Some((held, held_before, value)) if (held, held_before) == (k, before) => value,
            _ => self.value_missed(k, before, next, (frame, differs, width), (blocks, tolerance), follow),
        }
    }

    /// [`Lead::value`] not remembered: found, and remembered.
    #[inline(never)]
    fn value_missed(
        &mut self,
        k: usize,
        before: bool,
        (nx, ny): (usize, usize),
        (frame, differs, width): (&[PackedCell], &[bool], usize),
        (blocks, tolerance): (bool, u8),
        follow: &mut Follow,
    ) -> isize {
        let (x, y) = (k % width, k / width);
        let after = if x + 1 < width { Some((x + 1, y)) } else { None };
        let later = follow.later(self.look, k, frame, differs, width, (blocks, tolerance));
        let value = later as isize - self.glyph as isize - move_bound(after, nx, ny) as isize;
        self.valued = Some((k, before, value));
        value
    }
}

/// After the glyph just written for column `x` (the last thing in `out`), the changed cells right
/// after it, up to column `end`, that go in the same look from the pen (the same glyph, no colour
/// change) as one `CSI n b` (REP: repeat the last glyph n times), where that is fewer bytes than the
/// glyphs, and the terminal repeats that glyph (`level`); returns how many cells it covered (0:
/// none, nothing written).
#[allow(clippy::too_many_arguments)]
fn repeat(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    new: &mut [PackedCell],
    end: usize,
    differs: &[bool],
    x: usize,
    tolerance: u8,
    level: RepLevel,
) -> usize {
    if !may_repeat(new, differs, x, level) {
        return 0;
    }
    let last = new[x];
    let same = |pen: &Pen, cell: &PackedCell| {
        let (form, sgr) = cell_form(pen, cell, tolerance);
        (sgr.len() == 0 && form.ch == last.ch).then_some(form)
    };
    let end = end.min(new.len());
    if x + least_run(last.ch) >= end {
        return 0;
    }
    let run = (x + 1..end).take_while(|&j| differs[j] && same(pen, &new[j]).is_some()).count();
    if run == 0 || run * last.ch.len_utf8() <= 3 + digits(run) {
        return 0;
    }
    out.extend_from_slice(b"\x1b[");
    push_num(out, run);
    out.push(b'b');
    let width = new.len();
    for cell in &mut new[x + 1..=x + run] {
        *cell = last; // the look on screen: the glyph and colours just written
        advance(pen, width);
    }
    run
}

/// The shortest run of `glyph` that pays as `REP` (`run * glyph > 3 + digits(run)`: five ASCII
/// glyphs, two block glyphs).
#[inline]
fn least_run(glyph: char) -> usize {
    let glyph = glyph.len_utf8();
    (1..5).find(|&n| n * glyph > 3 + digits(n)).unwrap_or(5)
}

/// Whether [`repeat`] after column `x` of row `new` may send a run, by what it checks first: the
/// terminal repeats the glyph there (`level`), and the [`least_run`] cells after it are changed
/// and in the row. Where not, no cell's form is asked (nor the row's erasable tail, by the detours).
#[inline]
fn may_repeat(new: &[PackedCell], differs: &[bool], x: usize, level: RepLevel) -> bool {
    let Some(&last) = new.get(x) else { return false };
    if level < RepLevel::Any && !last.ch.is_ascii() {
        return false; // tmux repeats only an ASCII glyph: after `▀` it ignores REP (see `set_rep`)
    }
    let least = least_run(last.ch);
    x + least < new.len() && differs[x + 1..=x + least].iter().all(|&d| d)
}

/// What [`reach`] does once the cursor is there.
#[derive(Clone, Copy, Debug)]
enum Then {
    /// Write this cell, within this tolerance ([`write_cell`]).
    Cell(PackedCell, u8),
    /// Erase to the end of the line in this background.
    Erase(PackedColor),
}

impl Then {
    /// Does it; returns the cell as sent.
    fn write(self, out: &mut Vec<u8>, pen: &mut Pen, width: usize) -> Option<PackedCell> {
        match self {
            Then::Cell(cell, tolerance) => Some(write_cell(out, pen, &cell, width, tolerance)),
            Then::Erase(bg) => {
                write_sgr(out, pen, None, Some(bg));
                out.extend_from_slice(b"\x1b[K");
                None
            }
        }
    }

    /// The bytes [`Then::write`] would send, leaving `pen` as it would.
    fn price(self, pen: &mut Pen, width: usize) -> usize {
        match self {
            Then::Cell(cell, tolerance) => price_cell(pen, &cell, width, tolerance),
            Then::Erase(bg) => {
                let sgr = Sgr::new(pen, None, Some(bg));
                sgr.apply(pen);
                sgr.len() + 3
            }
        }
    }
}

/// Puts the cursor on column `x` of row `y` and does `then`, by the cheapest route: a cursor move, or
/// a move to an earlier column and a rewrite of the unchanged cells in between (from `row`). Returns
/// the cell sent, if `then` sends one.
fn reach(
    pen: &mut Pen,
    out: &mut Vec<u8>,
    y: usize,
    x: usize,
    row: &[PackedCell],
    then: Then,
) -> Option<PackedCell> {
    let width = row.len();
    let mut starts = [None, None];
    if pen.cursor != Some((x, y)) {
        if let Some((cx, cy)) = pen.cursor
            && cy == y
            && cx < x
            && x - cx <= MAX_REWRITE
        {
            starts[0] = Some(cx);
        }
        if (1..=MAX_REWRITE).contains(&x) {
            starts[1] = Some(0);
        }
    }
    // The routes are priced, not written, and a rewrite stops being priced once it costs more than
    // the best so far. The cheapest wins; of equals, the one starting furthest left (a rewrite beats
    // the plain move on a tie). The plain move leaves the colours as they are: the target's form from
    // the pen now is the one it would be written in, found once.
    let plain_form = match then {
        Then::Cell(cell, tolerance) => Some(cell_form(pen, &cell, tolerance)),
        Then::Erase(_) => None,
    };
    let mut from = x;
    // The plain move, searched for once: priced here, written below if it wins.
    let mut plain_move = None;
    if starts.iter().any(Option::is_some) {
        let found = find_move(pen, x, y);
        plain_move = Some(found);
        let mut moved = Pen { cursor: Some((x, y)), ..*pen };
        let mut best = found.len
            + match plain_form {
                Some((cell, sgr)) => sgr.len() + cell.ch.len_utf8(),
                None => then.price(&mut moved, width),
            };
        for start in starts.into_iter().flatten() {
            if let Some(len) = price_route(pen, y, start, x, row, then, best) {
                (best, from) = (len, start).min((best, from));
            }
        }
    }
    match plain_move {
        Some(found) if from == x => write_found(out, pen, found),
        _ => write_move(out, pen, from, y),
    }
    for cell in &row[from..x] {
        write_cell(out, pen, cell, width, 0); // on screen already: exactly as it is
    }
    match plain_form {
        Some(form) if from == x => Some(write_form(out, pen, form, width)),
        _ => then.write(out, pen, width),
    }
}

/// The bytes of the route to column `x` that moves to column `from` and rewrites the cells between,
/// then does `then`, if at most `limit`.
fn price_route(
    pen: &Pen,
    y: usize,
    from: usize,
    x: usize,
    row: &[PackedCell],
    then: Then,
    limit: usize,
) -> Option<usize> {
    let mut pen = *pen;
    let mut len = move_len(&mut pen, from, y);
    // First a floor from the glyphs alone (each cell's shortest form: one byte where it may go as a
    // blank — a full block, a glyph in one colour — else its glyph's; a blank is one byte anyway).
    let floor: usize = row[from..x]
        .iter()
        .map(|cell| if cell.ch == '█' || cell.fg == cell.bg { 1 } else { cell.ch.len_utf8() })
        .sum();
    if len + floor + 1 > limit {
        return None;
    }
    for cell in &row[from..x] {
        len += price_cell(&mut pen, cell, row.len(), 0);
        if len > limit {
            return None;
        }
    }
    len += then.price(&mut pen, row.len());
    (len <= limit).then_some(len)
}

/// `cell`'s [`PackedCell::inverse`] (the same look), unless it would send a block glyph the frames
/// do not use (a blank as a full block, where the pen says no blocks) or a space in text as a full
/// block ([`PackedCell::is_text_space`]).
fn inverse_of(pen: &Pen, cell: &PackedCell) -> Option<PackedCell> {
    if cell.is_text_space() {
        return None;
    }
    cell.inverse().filter(|inverse| pen.blocks || inverse.ch != FULL_BLOCK || cell.ch == FULL_BLOCK)
}

/// The form `cell` goes in from `pen` and its colour change: of the cell and its [`PackedCell::inverse`]
/// (same look), the one whose colours cost fewer bytes, each with the pen's colours kept where they
/// are within `tolerance` of the cell's; and, where a tolerance applies, a blank or a full block in one colour
/// within `tolerance` of both halves of a half-block cell where that is fewer bytes. The last one
/// found is remembered ([`LAST_FORM`]), and a few hundred before it ([`FORMS`]).
#[inline]
fn cell_form(pen: &Pen, cell: &PackedCell, tolerance: u8) -> (PackedCell, Sgr) {
    let key = FormKey::of(pen, cell, tolerance);
    LAST_FORM.with(|last| {
        if last.key.get() == key { last.form.get() } else { form_missed(last, key, pen, cell, tolerance) }
    })
}

/// [`cell_form`] not remembered: found, and remembered. (Out of line: the memo's hit, the usual
/// answer, inlines where it is asked.)
#[cold]
#[inline(never)]
fn form_missed(
    last: &FormMemo,
    key: FormKey,
    pen: &Pen,
    cell: &PackedCell,
    tolerance: u8,
) -> (PackedCell, Sgr) {
    let form = FORMS.with(|forms| {
        let slot = &forms[key.slot()];
        if slot.key.get() == key {
            return slot.form.get();
        }
        let form = find_form(pen, cell, tolerance, true);
        slot.key.set(key);
        slot.form.set(form);
        form
    });
    last.key.set(key);
    last.form.set(form);
    form
}

/// All that [`find_form`] reads, in two words: the pen's colours, the cell's colours (each
/// [`PackedColor::word`], 0 for `None`, which no colour is), the cell's glyph, whether the pen draws
/// blocks and the tolerance (not the cursor). Equal keys, equal inputs: one comparison of each word.
#[derive(Clone, Copy, PartialEq, Eq)]
struct FormKey(u128, u64);

impl FormKey {
    /// No inputs have it (a glyph's bits are at most 21: its word's top bits are zero).
    const NONE: FormKey = FormKey(0, u64::MAX);

    /// Its slot in [`FORMS`]: a hash of both words.
    #[inline]
    fn slot(self) -> usize {
        let FormKey(colours, rest) = self;
        let mixed = (colours as u64) ^ (colours >> 64) as u64 ^ rest.rotate_left(29);
        (mixed.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - FORM_SLOTS.trailing_zeros())) as usize
    }

    #[inline(always)]
    fn of(pen: &Pen, cell: &PackedCell, tolerance: u8) -> FormKey {
        let word = |c: Option<PackedColor>| u128::from(c.map_or(0, PackedColor::word));
        let colours =
            word(pen.fg) | word(pen.bg) << 32 | word(Some(cell.fg)) << 64 | word(Some(cell.bg)) << 96;
        let rest = u64::from(u32::from(cell.ch)) << 16 | u64::from(pen.blocks) << 8 | u64::from(tolerance);
        FormKey(colours, rest)
    }
}

/// The last form [`cell_form`] found: its inputs ([`FormKey`]) and the form.
struct FormMemo {
    key: std::cell::Cell<FormKey>,
    form: std::cell::Cell<(PackedCell, Sgr)>,
}

thread_local! {
    /// The last form [`cell_form`] found on this thread, by all it read ([`FormKey`]): a pure
    /// function of them, it changes no answer. The diff often asks one cell's form twice or three
    /// times in a row from the same pen: the run after a cell ([`repeat`]) stops at the next changed
    /// cell, whose form the detours ask next ([`detours`]) and then the move to it ([`reach`]).
    static LAST_FORM: FormMemo = const {
        FormMemo {
            key: std::cell::Cell::new(FormKey::NONE),
            form: std::cell::Cell::new((
                PackedCell { ch: ' ', fg: PackedColor::DEFAULT, bg: PackedColor::DEFAULT },
                Sgr::KEEP,
            )),
        }
    };
}

/// Slots of [`FORMS`]: a power of two.
const FORM_SLOTS: usize = 1 << 9;

thread_local! {
    /// The forms [`cell_form`] found lately on this thread past the last one ([`LAST_FORM`]), by a
    /// hash of all they read ([`FormKey::slot`]): each a pure function of its key, so an answer
    /// from here is the one [`find_form`] would find. Turning, a wall's few shades come up again
    /// from a few pens, cell after cell, between other forms. (40 KB a thread: 512 slots of 80 bytes.)
    static FORMS: [FormMemo; FORM_SLOTS] = const {
        [const {
            FormMemo {
                key: std::cell::Cell::new(FormKey::NONE),
                form: std::cell::Cell::new((
                    PackedCell { ch: ' ', fg: PackedColor::DEFAULT, bg: PackedColor::DEFAULT },
                    Sgr::KEEP,
                )),
            }
        }; FORM_SLOTS]
    };
}

/// [`cell_form`]; `shortcut`: skip the inverse forms where they cannot win (false: the whole
/// search, the oracle the tests hold the shortcut to).
fn find_form(pen: &Pen, cell: &PackedCell, tolerance: u8, shortcut: bool) -> (PackedCell, Sgr) {
    let cell = cell.canonical();
    let priced = |cell: PackedCell| (cell, Sgr::to_cell(pen, &cell));
    // (A cell that needs no colour change is never beaten: the searches below start only past it.)
    // Palette cells whose entries have no other entry within the tolerance (232 of 240 at the
    // default) take this path, as all palette cells did before they had a tolerance: with every
    // palette cell in the search below, the encoder's instructions turning in 256 colours were 1.38×.
    if tolerance == 0 || !cell.may_be_near(tolerance) {
        let plain = priced(cell);
        if plain.1.len() > 0
            && let Some(inverse) = inverse_of(pen, &cell).map(priced)
            && inverse.1.len() < plain.1.len()
        {
            return inverse;
        }
        return plain;
    }
    // The pen's colours where close enough, else the colour of the shortest code within the
    // tolerance ([`PackedColor::cheapest`], issue #42); a glyph they leave in one colour may go as
    // a blank.
    let near_pen = |mut cell: PackedCell| {
        let near = |want: PackedColor, pen: Option<PackedColor>| match pen {
            Some(p) if p.within(want, tolerance) => p,
            _ => want.cheapest(tolerance),
        };
        cell.fg = near(cell.fg, pen.fg);
        cell.bg = near(cell.bg, pen.bg);
        cell
    };
    let plain = near_pen(cell);
    let mut best = priced(plain);
    // Two truecolor colours or two palette entries past the ANSI 16 (whose codes are as long as
    // foreground as background), neither near the pen's other one: the inverse changes both colours,
    // at the lengths the plain form's worst case has, so it cannot be shorter; and the plain form's
    // two colours differ (the pen could only merge them by being near both), so it has no blank form.
    let both_far = |pen: &Pen| {
        cell.fg.is_tolerant()
            && cell.bg.is_tolerant()
            && !pen.fg.is_some_and(|p| p.within(cell.bg, tolerance))
            && !pen.bg.is_some_and(|p| p.within(cell.fg, tolerance))
    };
    // A cell of halves within the tolerance of one colour (a blank, a full block, a half block of
    // two near colours, or of two colours a colour between them is near: no further apart than
    // twice the tolerance) may go as a blank in it (below): the shortcut holds only where they are not.
    let halves = cell.halves();
    let one_colour = halves.is_some_and(|[top, bottom]| top.within(bottom, tolerance.saturating_mul(2)));
    // (Nor where the two colours it would send are one: it goes as a blank of it, below.)
    if shortcut && best.1.len() > 0 && both_far(pen) && !one_colour && plain.fg != plain.bg {
        return best;
    }
    if best.1.len() > 0 {
        let inverse = inverse_of(pen, &cell).map(near_pen);
        // The first of the cheapest, in this order (a canonical form only where it differs).
        for candidate in
            [Some(plain.canonical()), inverse, inverse.map(|c| c.canonical())].into_iter().flatten()
        {
            if candidate != best.0 {
                let priced = priced(candidate);
                if priced.1.len() < best.1.len() {
                    best = priced;
                }
            }
        }
    }
    // Issue #42: a blank, a half block or a full block whose two halves are both within the tolerance
    // of one colour — the pen's background or ink, or either half's own — may show that colour alone,
    // as a blank (one byte) or, in the pen's ink, a full block: a wall's gentle vertical gradient then
    // costs one colour a cell, or none. Bytes are glyph and colours together here.
    if let Some([top, bottom]) = halves
        && best.1.len() > 0
    {
        let bytes = |(cell, sgr): &(PackedCell, Sgr)| sgr.len() + cell.ch.len_utf8();
        // (A half's own colour as the colour of its shortest code where that is near both.)
        let both = |c: &PackedColor| c.within(top, tolerance) && c.within(bottom, tolerance);
        let short = |c: PackedColor| Some(c.cheapest(tolerance)).filter(both).unwrap_or(c);
        let colours = [pen.bg, pen.fg, Some(short(top)), Some(short(bottom))];
        for (k, colour) in colours.into_iter().enumerate() {
            let Some(colour) = colour.filter(both) else {
                continue;
            };
            let candidate = if k == 1 {
                if !pen.blocks || cell.is_text_space() {
                    continue; // no block glyphs in these frames; a space in text stays a space
                }
                PackedCell { ch: FULL_BLOCK, fg: colour, bg: cell.bg } // the pen's ink: no background shown
            } else {
                PackedCell { ch: ' ', fg: colour, bg: colour }
            };
            let priced = priced(candidate);
            // (A new colour must also save colour bytes: it changes the pen the cells after it reuse.)
            if bytes(&priced) < bytes(&best) && (k < 2 || priced.1.len() < best.1.len()) {
                best = priced;
            }
        }
    }
    best
}

/// Writes one cell at the cursor in the form [`cell_form`] chooses: colours if needed, then the
/// glyph; returns the cell as sent.
fn write_cell(
    out: &mut Vec<u8>,
    pen: &mut Pen,
    cell: &PackedCell,
    width: usize,
    tolerance: u8,
) -> PackedCell {
    write_form(out, pen, cell_form(pen, cell, tolerance), width)
}

/// Writes a cell in the form [`cell_form`] found from `pen`; returns the cell as sent. (Inlined:
/// a call passed the form through memory, for every cell written.)
#[inline]
fn write_form(out: &mut Vec<u8>, pen: &mut Pen, (cell, sgr): (PackedCell, Sgr), width: usize) -> PackedCell {
    sgr.write(out, pen);
    push_char(out, cell.ch);
    advance(pen, width);
    cell
}

/// The bytes [`write_cell`] would send, leaving `pen` as it would.
fn price_cell(pen: &mut Pen, cell: &PackedCell, width: usize, tolerance: u8) -> usize {
    let (cell, sgr) = cell_form(pen, cell, tolerance);
    sgr.apply(pen);
    advance(pen, width);
    sgr.len() + cell.ch.len_utf8()
}

/// The cursor after a glyph.
fn advance(pen: &mut Pen, width: usize) {
    pen.cursor = match pen.cursor {
        Some((x, y)) if x + 1 < width => Some((x + 1, y)),
        _ => None, // after the last column: pending wrap, position unreliable
    };
}

#[inline]
fn push_char(out: &mut Vec<u8>, ch: char) {
    if ch.is_ascii() {
        return out.push(ch as u8); // (blanks and the ascii charset, without the encoding's cases)
    }
    let mut buf = [0; 4];
    // Copies of a fixed length, without a call to `memcpy`: block glyphs are three bytes.
    match ch.encode_utf8(&mut buf).len() {
        1 => out.push(buf[0]),
        3 => out.extend_from_slice(&buf[..3]),
        len => out.extend_from_slice(&buf[..len]),
    }
}

/// `n` in decimal.
fn push_num(out: &mut Vec<u8>, n: usize) {
    // Colour channels and short moves, the usual numbers, without the loop.
    match n {
        0..=9 => return out.push(b'0' + n as u8),
        10..=99 => return out.extend_from_slice(&[b'0' + (n / 10) as u8, b'0' + (n % 10) as u8]),
        100..=255 => {
            return out.extend_from_slice(&[
                b'0' + (n / 100) as u8,
                b'0' + (n / 10 % 10) as u8,
                b'0' + (n % 10) as u8,
            ]);
        }
        _ => {}
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::{Cell, Color};

    fn packed(frame: &Frame) -> Vec<PackedCell> {
        frame.cells().iter().map(PackedCell::pack).collect()
    }

    /// A pen at `cursor` with these colours.
    fn pen(cursor: Option<(usize, usize)>, fg: Option<Color>, bg: Option<Color>) -> Pen {
        Pen { cursor, fg: fg.map(PackedColor::pack), bg: bg.map(PackedColor::pack), blocks: true }
    }

    /// The column pass starts each column at the first row of [`MIN_COLUMN`] changed cells of one
    /// look down it, found eight columns a word: against a plain search of every column, on grids
    /// of two looks and sparse and dense changes, widths on and off a multiple of eight.
    #[test]
    fn a_column_starts_at_its_first_rows_of_changed_cells_of_one_look() {
        let looks = [Cell::plain('a'), Cell::plain('b')].map(|cell| PackedCell::pack(&cell));
        let mut seed = 0x2545_f491_u32;
        let mut next = move |n: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed % n
        };
        let mut found = 0;
        for (width, height) in [(1_usize, 1_usize), (7, 2), (8, 3), (13, 9), (24, 5), (120, 40)] {
            for percent_changed in [5, 60, 95] {
                let cells = width * height;
                let new: Vec<PackedCell> = (0..cells).map(|_| looks[next(2) as usize]).collect();
                let differs: Vec<bool> = (0..cells).map(|_| next(100) < percent_changed).collect();
                let plain: Vec<usize> = (0..width)
                    .map(|x| {
                        (0..height.saturating_sub(MIN_COLUMN - 1))
                            .find(|&y| {
                                let k = y * width + x;
                                (0..MIN_COLUMN)
                                    .all(|i| differs[k + i * width] && new[k + i * width] == new[k])
                            })
                            .unwrap_or(height)
                    })
                    .collect();
                let mut first = vec![7; 3]; // (scratch left by another frame)
                first_columns(&new, &differs, width, 0..height, &mut first);
                assert_eq!(first, plain, "{width}x{height}");
                found += plain.iter().filter(|&&y| y < height).count();
            }
        }
        assert!(found > 100, "columns with a start: {found}");
    }

    /// The memo of cells left within the tolerance changes no byte: frames of half blocks drifting
    /// by a shade or two (truecolor, near palette entries, the defaults and ANSI colours that switch
    /// spelling), some cells going back to what they were, encoded by one encoder and by one that
    /// forgets its memo before every frame, at tolerances 0, 2 and 5, with REP and without.
    #[test]
    fn the_memo_of_cells_left_changes_no_byte() {
        let mut seed = 0x9e37_79b9_u32;
        let mut next = move |n: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed % n
        };
        let (width, height) = (23, 7);
        let grey = |v: u8| Color::Rgb(v, v, v.saturating_add(1));
        let colours = [grey(100), grey(101), grey(102), grey(140), Color::Indexed(59), Color::Indexed(241)];
        let colours = [&colours[..], &[Color::Default, Color::Indexed(4)]].concat();
        let mut left_alone = 0;
        for tolerance in [0, 2, 5] {
            for rep in [RepLevel::None, RepLevel::Ascii, RepLevel::Any] {
                let (mut with_memo, mut without) = (Encoder::new(), Encoder::new());
                for encoder in [&mut with_memo, &mut without] {
                    encoder.set_tolerance(tolerance);
                    encoder.set_rep(rep);
                }
                let mut frame = Frame::filled(width, height, Cell { ch: '▀', fg: grey(100), bg: grey(101) });
                for _ in 0..60 {
                    for _ in 0..next(40) {
                        let (x, y) = (next(width as u32) as usize, next(height as u32) as usize);
                        let ch = ['▀', '▄', ' ', '█', 'x'][next(5) as usize];
                        let pick = |k: u32| colours[k as usize % colours.len()];
                        frame.set(x, y, Cell { ch, fg: pick(next(8)), bg: pick(next(8)) });
                    }
                    let (mut a, mut b) = (Vec::new(), Vec::new());
                    without.memo.before.clear();
                    let stats = with_memo.encode(&frame, &mut a);
                    assert_eq!(stats, without.encode(&frame, &mut b));
                    assert_eq!(a, b);
                    assert_eq!(with_memo.screen, without.screen);
                    left_alone += with_memo.memo.left.iter().filter(|&&l| l).count();
                }
            }
        }
        assert!(left_alone > 100, "cells answered or remembered: {left_alone}");
    }

    impl Memo {
        /// The encoder's marking before the one-pass scan ([`Memo::scan`]), kept as its oracle:
        /// [`mark_changes`] of the whole frame, answering from the memo where the frame's cell is one
        /// it measured and left, and remembering those it measures and leaves. A cell equal to the
        /// screen's is not written, nor is one answered from the memo: the screen's cell stays what it
        /// was when remembered. Every other cell is forgotten (it may be written); one of the same
        /// look keeps the screen's spelling.
        fn mark_changes(
            &mut self,
            old: &[PackedCell],
            new: &mut [PackedCell],
            tolerance: u8,
            differs: &mut Vec<bool>,
        ) {
            debug_assert_eq!((self.before.len(), self.left.len()), (new.len(), new.len()));
            let (before, left) = (&mut self.before[..], &mut self.left[..]);
            differs.extend(old.iter().zip(new).enumerate().map(|(k, (shown, cell))| {
                if shown == cell {
                    return false; // the common case, inline
                }
                if tolerance > 0 && cell.may_be_near(tolerance) {
                    // As `mark`, the memo first.
                    if left[k] && before[k] == *cell {
                        *cell = *shown;
                        return false;
                    }
                    let within = shown.looks_within(cell, tolerance);
                    if within {
                        before[k] = *cell;
                        *cell = *shown;
                    }
                    left[k] = within;
                    return !within;
                }
                left[k] = false;
                let differs = !shown.looks_within(cell, 0);
                if !differs {
                    *cell = *shown;
                }
                differs
            }));
        }
    }

    /// [`detours`] before its fast path, kept as its oracle: every turn finds each look's first
    /// changed cell from the cursor and prices every candidate's moves and cost in its row.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn detours_searched(
        pen: &mut Pen,
        out: &mut Vec<u8>,
        frame: &mut [PackedCell],
        width: usize,
        differs: &mut [bool],
        next: usize,
        how: How,
        follow: &mut Follow,
    ) -> usize {
        let (Some(fg), Some(bg)) = (pen.fg, pen.bg) else { return 0 };
        if Sgr::to_cell(pen, &frame[next]).len() == 0
            || cell_form(pen, &frame[next], how.tolerance).1.len() == 0
        {
            return 0;
        }
        let blank = follow.look(pair_key(bg, bg));
        let block = (pen.blocks && fg != bg).then(|| follow.look(pair_key(fg, fg))).flatten();
        let half = (fg != bg).then(|| follow.look(pair_key(fg, bg))).flatten();
        if blank.is_none() && block.is_none() && half.is_none() {
            return 0;
        }
        let (nx, ny) = (next % width, next / width);
        let mut written = 0;
        loop {
            let at = pen.cursor.map_or(0, |(x, y)| y * width + x);
            let mut first = |look: u32| follow.first(look, at, differs).map(|(k, _)| k);
            let blank = blank.and_then(|look| Some((look, first(look)?, 1)));
            let block = block.and_then(|look| Some((look, first(look)?, FULL_BLOCK.len_utf8())));
            let block = block.filter(|&(_, k, _)| !frame[k].is_text_space());
            let half = half.and_then(|look| Some((look, first(look)?, 3)));
            let found = [blank, block, half];
            if found.iter().flatten().all(|&(_, k, _)| k == next) {
                return written;
            }
            let direct = move_bound(pen.cursor, nx, ny);
            let mut best: Option<(usize, usize)> = None;
            for candidate in found {
                let Some((look, k, glyph)) = candidate else { continue };
                if k == next {
                    continue;
                }
                let (x, y) = (k % width, k / width);
                let after = if x + 1 < width { Some((x + 1, y)) } else { None };
                let moves = move_bound(pen.cursor, x, y) + move_bound(after, nx, ny) + glyph;
                let later = follow.later(look, k, frame, differs, width, (pen.blocks, how.tolerance));
                let Some(saving) = (later + direct).checked_sub(moves).filter(|&s| s > MARGIN) else {
                    continue;
                };
                if best.is_none_or(|(most, _)| saving > most) {
                    best = Some((saving, k));
                }
            }
            let Some((_, k)) = best else { return written };
            write_move(out, pen, k % width, k / width);
            written += write_detour(pen, out, frame, width, differs, k, how, &mut None);
            if (pen.fg, pen.bg) != (Some(fg), Some(bg)) {
                return written;
            }
        }
    }

    /// Issue #42: the detours' fast path and carried candidates change no byte. Frames of runs of
    /// blanks, blocks and half blocks of two colours and a few others, slanting across the rows
    /// and sliding along them a frame (as turning), with scattered letters, encoded by an encoder
    /// and by one whose detours search every turn ([`detours_searched`]), at tolerances 0 and 2,
    /// every REP level, with and without blocks; and the fast path chose cells.
    #[test]
    fn the_detours_fast_path_changes_no_byte() {
        let mut seed = 0x6c07_8965_u32;
        let mut next = move |n: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed % n
        };
        let others = [Color::Rgb(90, 90, 91), Color::Indexed(241), Color::Indexed(4), Color::Rgb(90, 92, 91)];
        let (width, height) = (41, 13);
        let mut fast = 0;
        // Truecolor, palette and ANSI colours: colour changes dearer and cheaper than moves.
        let pairs = [
            (Color::Rgb(200, 40, 9), Color::Rgb(30, 160, 220)),
            (Color::Indexed(59), Color::Indexed(166)),
            (Color::Indexed(1), Color::Indexed(12)),
        ];
        for ((p, q), tolerance) in pairs.into_iter().flat_map(|pair| [(pair, 0), (pair, 2)]) {
            for rep in [RepLevel::None, RepLevel::Ascii, RepLevel::Any] {
                for blocks in [true, false] {
                    let (mut encoder, mut oracle) = (Encoder::new(), Encoder::new());
                    oracle.follow.whole_search = true;
                    for encoder in [&mut encoder, &mut oracle] {
                        encoder.set_tolerance(tolerance);
                        encoder.set_rep(rep);
                        encoder.set_blocks(blocks);
                    }
                    let (mut pattern, mut slope, mut shift) = (Vec::new(), 0, 0);
                    let mut frame = Frame::new(width, height);
                    for step in 0..80 {
                        if step % 20 == 0 {
                            // A row of runs, each of one look: mostly the two colours' blanks,
                            // blocks and half blocks, some of another colour.
                            pattern.clear();
                            while pattern.len() < width {
                                let other = others[next(4) as usize];
                                let (a, b) = [(p, q), (q, p), (p, p), (q, q), (other, p), (q, other)]
                                    [next(6) as usize];
                                let ch = ['▀', '▄', ' ', '█'][next(4) as usize];
                                pattern.extend(std::iter::repeat_n(
                                    Cell { ch, fg: a, bg: b },
                                    1 + next(7) as usize,
                                ));
                            }
                            slope = 1 + next(3) as usize;
                        }
                        shift += 1 + next(6) as usize;
                        for y in 0..height {
                            for x in 0..width {
                                frame.set(x, y, pattern[(x + y * slope + shift) % width]);
                            }
                        }
                        for _ in 0..next(8) {
                            let (x, y) = (next(width as u32) as usize, next(height as u32) as usize);
                            frame.set(x, y, Cell { ch: 'x', fg: others[next(4) as usize], bg: q });
                        }
                        let (mut a, mut b) = (Vec::new(), Vec::new());
                        assert_eq!(encoder.encode(&frame, &mut a), oracle.encode(&frame, &mut b));
                        assert_eq!(a, b, "tolerance {tolerance}, {rep:?}, blocks {blocks}, step {step}");
                        assert_eq!(encoder.screen, oracle.screen);
                    }
                    fast += encoder.follow.fast;
                }
            }
        }
        assert!(fast > 1000, "cells the fast path chose: {fast}");
    }

    /// [`Encoder::encode`] as it was before the one-pass scan ([`Memo::scan`]): the frame packed,
    /// then marked against the screen by [`Memo::mark_changes`], then every cell of the screen
    /// compared with the frame for [`EncodeStats::approximate`]. The oracle of the scan.
    fn encode_unscanned(encoder: &mut Encoder, frame: &Frame, out: &mut Vec<u8>) -> EncodeStats {
        let start = out.len();
        let (width, height) = (frame.width(), frame.height());
        let full_paint = !encoder.valid || (encoder.width, encoder.height) != (width, height);
        out.extend_from_slice(SYNC_BEGIN);
        let mut sent: Vec<PackedCell> = packed(frame);
        let cells_changed = if full_paint {
            encoder.pen = paint_full(&sent, width, encoder.bce, encoder.rep, encoder.blocks, out);
            encoder.memo.before.clear();
            sent.len()
        } else {
            encoder.pen.blocks = encoder.blocks;
            let how = How { bce: encoder.bce, tolerance: encoder.tolerance, rep: encoder.rep };
            encoder.memo.prepare(sent.len(), encoder.tolerance);
            let mut differs = Vec::new();
            encoder.memo.mark_changes(&encoder.screen, &mut sent, how.tolerance, &mut differs);
            let scratch = (&mut Vec::new(), Some(&mut Follow::default()));
            diff_marked(&mut sent, width, 0..height, how, &mut encoder.pen, out, &mut differs, scratch)
        };
        if out.len() - start == SYNC_BEGIN.len() {
            out.truncate(start);
        } else {
            out.extend_from_slice(SYNC_END);
        }
        encoder.screen = sent;
        (encoder.width, encoder.height) = (width, height);
        encoder.valid = true;
        let approximate = !full_paint
            && encoder.tolerance > 0
            && encoder
                .screen
                .iter()
                .zip(packed(frame))
                .any(|(shown, cell)| *shown != cell && !shown.looks_within(&cell, 0));
        EncodeStats { bytes: out.len() - start, cells_changed, full_paint, approximate }
    }

    /// The one-pass scan of the frame against the screen, and the check of whether the screen is
    /// exact over the cells the diff could change, change no byte and no statistic: frames of half
    /// blocks, blanks, blocks and letters in truecolor, near and far palette entries, ANSI and default
    /// colours, some cells going back to what they were, rows scrolled (a turn), a resize and an
    /// invalidation, encoded by [`Encoder::encode`] and by [`encode_unscanned`], at tolerances 0, 2
    /// and 5, every REP level, with and without BCE and blocks.
    #[test]
    fn the_one_pass_scan_changes_no_byte() {
        let mut seed = 0x2545_f491_u32;
        let mut next = move |n: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed % n
        };
        let grey = |v: u8| Color::Rgb(v, v, v.saturating_add(1));
        let colours = [grey(100), grey(101), grey(103), grey(140), Color::Rgb(200, 40, 9)];
        let palette = [Color::Indexed(59), Color::Indexed(241), Color::Indexed(17), Color::Indexed(231)];
        let colours = [&colours[..], &palette, &[Color::Default, Color::Indexed(4)]].concat();
        let (mut approximate, mut frames) = (0, 0);
        for tolerance in [0, 2, 5] {
            for rep in [RepLevel::None, RepLevel::Ascii, RepLevel::Any] {
                for (bce, blocks) in [(true, true), (false, true), (true, false)] {
                    let (mut scanned, mut oracle) = (Encoder::new(), Encoder::new());
                    for encoder in [&mut scanned, &mut oracle] {
                        encoder.set_tolerance(tolerance);
                        encoder.set_rep(rep);
                        encoder.set_bce(bce);
                        encoder.set_blocks(blocks);
                    }
                    let (mut width, mut height) = (31, 9);
                    let mut frame =
                        Frame::filled(width, height, Cell { ch: '▀', fg: grey(100), bg: grey(101) });
                    for step in 0..40 {
                        if step == 25 {
                            (width, height) = (17, 12);
                            frame.resize(width, height);
                        }
                        if step == 33 {
                            scanned.invalidate();
                            oracle.invalidate();
                        }
                        if next(4) == 0 {
                            // A turn: every row moves a column.
                            for row in frame.cells_mut().chunks_exact_mut(width) {
                                row.rotate_left(1);
                            }
                        }
                        for _ in 0..next(60) {
                            let (x, y) = (next(width as u32) as usize, next(height as u32) as usize);
                            let ch = ['▀', '▄', ' ', '█', 'x', '▘'][next(6) as usize];
                            let pick = |k: u32| colours[k as usize % colours.len()];
                            frame.set(x, y, Cell { ch, fg: pick(next(16)), bg: pick(next(16)) });
                        }
                        let (mut a, mut b) = (b"x".to_vec(), b"x".to_vec());
                        let stats = scanned.encode(&frame, &mut a);
                        assert_eq!(stats, encode_unscanned(&mut oracle, &frame, &mut b), "step {step}");
                        assert_eq!(a, b, "step {step}");
                        assert_eq!(scanned.screen, oracle.screen);
                        approximate += usize::from(stats.approximate);
                        frames += 1;
                    }
                }
            }
        }
        assert!(approximate > 50, "frames left approximate: {approximate} of {frames}");
    }

    /// The first flag set from an index on, sixteen at a time, is the first the plain search finds:
    /// rows of every length up to 70 with flags set nowhere, at their start, end, chunks' edges and
    /// at random, from every index.
    #[test]
    fn the_next_set_flag_is_the_first_from_there() {
        let mut seed = 0x1234_5678_u32;
        for len in 0..70 {
            for pattern in 0..8 {
                let mut flags = vec![false; len];
                for (k, flag) in flags.iter_mut().enumerate() {
                    seed ^= seed << 13;
                    seed ^= seed >> 17;
                    seed ^= seed << 5;
                    *flag = match pattern {
                        0 => false,
                        1 => k == 0,
                        2 => k + 1 == len,
                        3 => k % 16 == 15 || k % 16 == 0,
                        4 => k == 33,
                        _ => seed.is_multiple_of(pattern * 3),
                    };
                }
                for from in 0..=len + 1 {
                    let plain = (from..len).find(|&k| flags[k]);
                    assert_eq!(next_set(&flags, from), plain, "{flags:?} from {from}");
                }
            }
        }
    }

    /// Escape codes carry their numbers in plain decimal: every number the fast paths cover and
    /// their edges, then the loop's (moves across wide screens, and the largest `usize`).
    #[test]
    fn push_num_writes_plain_decimal() {
        let edges = [256, 999, 1000, 4095, 65535, 1 << 20, 1 << 31, usize::MAX / 10, usize::MAX];
        for n in (0..=2000).chain(edges) {
            let mut out = b"x".to_vec();
            push_num(&mut out, n);
            assert_eq!(out, format!("x{n}").into_bytes(), "{n}");
        }
    }

    /// A cell goes as itself or as its inverse, whichever needs fewer colour bytes from the pen:
    /// `▄` in B on A, with the pen at A on B, is `▀` in A on B and needs no colour code — at any
    /// tolerance, in palette colours and in truecolor.
    #[test]
    fn a_cell_goes_as_its_inverse_when_the_pen_already_has_its_colours() {
        for (a, b) in
            [(Color::Indexed(4), Color::Indexed(11)), (Color::Rgb(10, 20, 30), Color::Rgb(200, 100, 0))]
        {
            for tolerance in [0, 1] {
                let mut pen = pen(Some((0, 0)), Some(a), Some(b));
                let mut out = Vec::new();
                let cell = PackedCell::pack(&Cell { ch: '▄', fg: b, bg: a });
                let sent = write_cell(&mut out, &mut pen, &cell, 10, tolerance);
                assert_eq!(String::from_utf8(out).unwrap(), "▀", "{a:?} on {b:?}, tolerance {tolerance}");
                assert_eq!(sent.unpack(), Cell { ch: '▀', fg: a, bg: b });
                let (a, b) = (PackedColor::pack(a), PackedColor::pack(b));
                assert_eq!((pen.fg, pen.bg, pen.cursor), (Some(a), Some(b), Some((1, 0))));
            }
        }
    }

    /// A cell the pen can draw as it is goes exactly as it is, with no colour code, even where a form
    /// within the tolerance would be a shorter glyph: `▀` in two near truecolor colours that are the
    /// pen's own is sent as `▀`, not as a blank in one of them (the tolerance approximates only to
    /// save colour codes).
    #[test]
    fn a_cell_the_pen_draws_as_it_is_goes_exactly() {
        let (a, b) = (Color::Rgb(100, 100, 100), Color::Rgb(101, 101, 101));
        assert!(PackedColor::pack(a).within(PackedColor::pack(b), 1), "near enough for a blank");
        for tolerance in [0, 1, 2, MAX_TOLERANCE] {
            let mut pen = pen(Some((0, 0)), Some(a), Some(b));
            let mut out = Vec::new();
            let cell = PackedCell::pack(&Cell { ch: '▀', fg: a, bg: b });
            let sent = write_cell(&mut out, &mut pen, &cell, 10, tolerance);
            assert_eq!(String::from_utf8(out).unwrap(), "▀", "tolerance {tolerance}");
            assert_eq!(sent, cell, "tolerance {tolerance}");
        }
    }

    /// Routes are chosen by price, so a price must be exactly what writing sends and leave the pen as
    /// writing does: every glyph kind, colour kind and pen (unknown, default, equal, near, far), at
    /// tolerance 0 and 2, the cell in the middle and in the last column.
    #[test]
    fn a_cell_is_priced_at_exactly_the_bytes_it_is_written_in() {
        let colors = [
            Color::Default,
            Color::Indexed(3),
            Color::Indexed(12),
            Color::Indexed(200),
            Color::Indexed(59),
            Color::Indexed(241), // 59's near neighbour: within 2 steps
            Color::Rgb(10, 20, 30),
            Color::Rgb(11, 21, 29),
            Color::Rgb(200, 100, 0),
        ];
        let pens = std::iter::once(None).chain(colors.map(Some));
        let pens: Vec<Option<Color>> = pens.collect();
        let mut checked = 0;
        for ch in [' ', '█', '▀', '▄', '▞', '\u{1FB00}', 'x', '·'] {
            for (fg, bg) in colors.iter().flat_map(|&f| colors.map(|b| (f, b))) {
                for (&pen_fg, &pen_bg) in pens.iter().flat_map(|f| pens.iter().map(move |b| (f, b))) {
                    for (tolerance, x) in [(0, 3), (2, 3), (2, 9)] {
                        let pen = pen(Some((x, 1)), pen_fg, pen_bg);
                        let (mut written, mut priced) = (pen, pen);
                        let mut out = Vec::new();
                        let cell = PackedCell::pack(&Cell { ch, fg, bg });
                        write_cell(&mut out, &mut written, &cell, 10, tolerance);
                        let len = price_cell(&mut priced, &cell, 10, tolerance);
                        assert_eq!((len, priced), (out.len(), written), "{cell:?} from {pen:?}");
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 8 * 81 * 100 * 3);
    }

    /// The shortcut past the inverse forms finds what the whole search finds: truecolor cells and
    /// palette cells of every glyph kind, colours near and far from every pen, tolerances 1 and 3.
    #[test]
    fn the_form_search_shortcut_finds_what_the_whole_search_finds() {
        let (a, b) = (Color::Rgb(100, 50, 200), Color::Rgb(30, 220, 9));
        let truecolor = [a, Color::Rgb(101, 51, 199), b, Color::Rgb(32, 219, 9), Color::Rgb(0, 0, 0)];
        // 59 and 241 are 0.011 apart, 102 and 245 0.010, 254 and 255 0.030; 16 is black, 9 an ANSI colour.
        let (i, n) = (Color::Indexed, Color::Indexed(9));
        let palette = [i(59), i(241), i(102), i(245), i(254), i(255), i(16), n];
        // Colours with shorter codes within the tolerance (issue #42): greys near the cube's 95 and
        // the ramp, channels just over 100 and 10, and two near one entry from either side.
        let rgb = Color::Rgb;
        let short = [
            rgb(100, 100, 100),
            rgb(91, 91, 91),
            rgb(101, 50, 11),
            rgb(96, 134, 176),
            rgb(94, 136, 174),
            i(59),
        ];
        for colors in [&truecolor[..], &palette[..], &short[..]] {
            form_search_cases(colors);
        }
    }

    /// The form remembered ([`LAST_FORM`], [`FORMS`]) is the form found: calls one after another
    /// whose inputs differ in one thing each (the pen's ink, its paper, whether it draws blocks, the
    /// cell's glyph or a colour, the tolerance) or in nothing [`find_form`] reads (the cursor)
    /// answer as [`find_form`] does, and each call leaves its own inputs remembered in both. (The
    /// base inputs come back after each variant: past the last form, from [`FORMS`].)
    #[test]
    fn a_remembered_cell_form_is_the_form_found() {
        let (near, far) = (Color::Rgb(100, 50, 200), Color::Rgb(101, 51, 199));
        let colors =
            [near, far, Color::Rgb(30, 220, 9), Color::Indexed(59), Color::Indexed(241), Color::Default];
        let mut calls = 0;
        for ch in [' ', '█', '▀', 'x'] {
            for (&fg, &bg) in colors.iter().flat_map(|f| colors.iter().map(move |b| (f, b))) {
                let cell = PackedCell::pack(&Cell { ch, fg, bg });
                let base = pen(Some((3, 1)), Some(near), Some(far));
                let variants = [
                    (base, cell, 2),
                    (Pen { cursor: Some((4, 1)), ..base }, cell, 2),
                    (Pen { blocks: false, ..base }, cell, 2),
                    (base, cell, 0),
                    (base, cell, 3),
                    (Pen { fg: Some(PackedColor::pack(bg)), ..base }, cell, 2),
                    (Pen { bg: Some(PackedColor::pack(fg)), ..base }, cell, 2),
                    (Pen { fg: None, ..base }, cell, 2),
                    (base, PackedCell { ch: '▄', ..cell }, 2),
                    (base, PackedCell { fg: cell.bg, ..cell }, 2),
                    (base, PackedCell { bg: cell.fg, ..cell }, 2),
                ];
                // Each variant after the base and the base after it: one input changed each time.
                for (pen, cell, tolerance) in variants.into_iter().flat_map(|v| [variants[0], v]) {
                    let (remembered, found) =
                        (cell_form(&pen, &cell, tolerance), find_form(&pen, &cell, tolerance, true));
                    assert_eq!(format!("{remembered:?}"), format!("{found:?}"), "{cell:?} from {pen:?}");
                    let key = FormKey::of(&pen, &cell, tolerance);
                    assert!(LAST_FORM.with(|last| last.key.get() == key));
                    assert!(FORMS.with(|forms| forms[key.slot()].key.get() == key));
                    calls += 1;
                }
            }
        }
        assert_eq!(calls, 4 * 36 * 22);
    }

    fn form_search_cases(colors: &[Color]) {
        let pens: Vec<Option<Color>> = [None, Some(Color::Default), Some(Color::Indexed(9))]
            .into_iter()
            .chain(colors.iter().copied().map(Some))
            .collect();
        for ch in [' ', '█', '▀', '▞', '\u{1FB05}', 'x'] {
            for (fg, bg) in colors.iter().flat_map(|&f| colors.iter().map(move |&b| (f, b))) {
                for (&pen_fg, &pen_bg) in pens.iter().flat_map(|f| pens.iter().map(move |b| (f, b))) {
                    for tolerance in [1, 3] {
                        let pen = pen(Some((0, 0)), pen_fg, pen_bg);
                        let cell = PackedCell::pack(&Cell { ch, fg, bg });
                        let (fast, whole) = (
                            find_form(&pen, &cell, tolerance, true),
                            find_form(&pen, &cell, tolerance, false),
                        );
                        assert_eq!((fast.0, fast.1.len()), (whole.0, whole.1.len()), "{cell:?} from {pen:?}");
                    }
                }
            }
        }
    }

    /// Rows whose cells cost exactly their glyph floor from a pen in colour 3 on grey (`x` in the
    /// pen's colours, a blank, a full block whose ink is the pen's background and a half block of
    /// one colour, both going as a blank): the cases where a route's price is tight against its
    /// limit; and rows in default colours and rows that change colour, where it is not.
    fn route_cases() -> (Vec<Vec<PackedCell>>, Vec<Pen>, Vec<Then>) {
        let grey = Color::Indexed(8);
        let cell = |ch, fg, bg| PackedCell::pack(&Cell { ch, fg, bg });
        let ink = Color::Indexed(3);
        let tight = [
            cell('x', ink, grey),
            cell(' ', ink, grey),
            cell('█', grey, Color::Indexed(4)),
            cell('▀', grey, grey),
        ];
        let plain = [
            cell('x', Color::Default, Color::Default),
            cell(' ', Color::Default, Color::Default),
            cell('█', Color::Default, Color::Default),
            cell('▀', Color::Default, Color::Default),
        ];
        let colourful = [
            cell('x', Color::Indexed(3), Color::Default),
            cell('▄', grey, Color::Rgb(40, 50, 60)),
            cell(' ', Color::Default, grey),
            cell('█', Color::Rgb(200, 10, 10), grey),
            cell('\u{1FB00}', Color::Indexed(12), Color::Indexed(200)),
        ];
        let mut rows = Vec::new();
        for k in 0..tight.len() {
            rows.push((0..12).map(|i| tight[(i + k) % tight.len()]).collect::<Vec<_>>());
            rows.push((0..12).map(|i| plain[(i + k) % plain.len()]).collect());
            rows.push((0..12).map(|i| colourful[(i * 3 + k) % colourful.len()]).collect());
            rows.push((0..12).map(|i| if i % 3 == k % 3 { colourful[k] } else { plain[i % 4] }).collect());
        }
        let pens = [
            pen(None, None, None),
            pen(Some((0, 1)), Some(Color::Default), Some(Color::Default)),
            pen(Some((2, 1)), Some(Color::Default), Some(Color::Default)),
            pen(Some((5, 1)), Some(ink), Some(grey)),
            pen(Some((0, 1)), Some(ink), Some(grey)),
            pen(Some((9, 2)), Some(ink), Some(grey)),
            pen(Some((1, 0)), Some(Color::Default), Some(Color::Default)),
            pen(Some((7, 3)), Some(Color::Rgb(40, 50, 60)), Some(Color::Default)),
        ];
        let thens = vec![
            Then::Cell(cell('y', Color::Default, Color::Default), 0),
            Then::Cell(cell('y', ink, grey), 0),
            Then::Cell(cell('▞', grey, Color::Rgb(40, 50, 60)), 0),
            Then::Cell(cell('▞', grey, Color::Rgb(41, 50, 60)), 2),
            Then::Erase(PackedColor::DEFAULT),
            Then::Erase(PackedColor::pack(grey)),
        ];
        (rows, pens.to_vec(), thens)
    }

    /// The route that moves to `from`, rewrites the cells up to `x` exactly, then does `then`,
    /// written out: its bytes and the pen it leaves.
    fn written_route(
        pen: &Pen,
        y: usize,
        from: usize,
        x: usize,
        row: &[PackedCell],
        then: Then,
    ) -> (Vec<u8>, Pen) {
        let (mut pen, mut out) = (*pen, Vec::new());
        write_move(&mut out, &mut pen, from, y);
        for cell in &row[from..x] {
            write_cell(&mut out, &mut pen, cell, row.len(), 0);
        }
        then.write(&mut out, &mut pen, row.len());
        (out, pen)
    }

    /// Routes are compared by price, and a route is dropped once it costs more than the best so far:
    /// its price is exactly the bytes writing it sends, and it is dropped only when those exceed the
    /// limit (at the limit it is kept, so that ties are decided by the rule, not by the pruning).
    #[test]
    fn a_route_is_priced_at_exactly_its_bytes_and_dropped_only_above_its_limit() {
        let (rows, pens, thens) = route_cases();
        let mut tight = 0;
        for row in &rows {
            for pen in &pens {
                for &then in &thens {
                    for x in 1..row.len() {
                        for from in 0..x {
                            let (out, _) = written_route(pen, 1, from, x, row, then);
                            let exact = out.len();
                            let case = format!("{then:?} at {x} from {from}, {pen:?}, {row:?}");
                            assert_eq!(
                                price_route(pen, 1, from, x, row, then, usize::MAX),
                                Some(exact),
                                "{case}"
                            );
                            assert_eq!(price_route(pen, 1, from, x, row, then, exact), Some(exact), "{case}");
                            assert_eq!(price_route(pen, 1, from, x, row, then, exact - 1), None, "{case}");
                            let mut moved = *pen;
                            tight += usize::from(move_len(&mut moved, from, 1) + (x - from) + 1 == exact);
                        }
                    }
                }
            }
        }
        assert!(tight > 100, "the glyph floor is met exactly in {tight} routes");
    }

    /// What follows a move is priced at exactly its bytes, leaving the pen as writing it does.
    #[test]
    fn a_cell_or_an_erase_is_priced_at_exactly_its_bytes() {
        let (_, pens, thens) = route_cases();
        for pen in &pens {
            for &then in &thens {
                let (mut written, mut priced, mut out) = (*pen, *pen, Vec::new());
                then.write(&mut out, &mut written, 12);
                assert_eq!(
                    (then.price(&mut priced, 12), priced),
                    (out.len(), written),
                    "{then:?} from {pen:?}"
                );
            }
        }
    }

    /// The cursor gets where it must by the cheapest route: a move, or a move to the cursor's own
    /// column or to the line's start and a rewrite of the unchanged cells from there (at most
    /// [`MAX_REWRITE`] of them); of equal routes, the one starting furthest left.
    #[test]
    fn the_cheapest_route_is_taken_and_of_equals_the_leftmost() {
        let (rows, pens, thens) = route_cases();
        let mut rewrites = 0;
        for row in &rows {
            for pen in &pens {
                for &then in &thens {
                    for x in 0..row.len() {
                        let mut starts = vec![x];
                        if pen.cursor != Some((x, 1)) {
                            if let Some((cx, 1)) = pen.cursor
                                && cx < x
                                && x - cx <= MAX_REWRITE
                            {
                                starts.push(cx);
                            }
                            if (1..=MAX_REWRITE).contains(&x) {
                                starts.push(0);
                            }
                        }
                        let best = starts
                            .iter()
                            .map(|&from| {
                                let (out, pen) = written_route(pen, 1, from, x, row, then);
                                ((out.len(), from), out, pen)
                            })
                            .min_by_key(|(key, _, _)| *key)
                            .unwrap();
                        rewrites += usize::from(best.0.1 < x);
                        let (mut reached, mut out) = (*pen, Vec::new());
                        reach(&mut reached, &mut out, 1, x, row, then);
                        assert_eq!((out, reached), (best.1, best.2), "{then:?} at {x} from {pen:?}, {row:?}");
                    }
                }
            }
        }
        assert!(rewrites > 100, "a rewrite wins in {rewrites} cases");
    }

    /// Nothing changed, nothing sent: not even the synchronized-update brackets.
    #[test]
    fn an_unchanged_frame_sends_nothing() {
        let frame = Frame::from_lines(&["a maze", "walk"]);
        let mut encoder = Encoder::new();
        let mut out = b"earlier bytes".to_vec();
        assert!(encoder.encode(&frame, &mut out).bytes > 0);
        let before = out.len();
        let stats = encoder.encode(&frame, &mut out);
        assert_eq!((stats.bytes, stats.cells_changed, out.len()), (0, 0, before));
    }

    /// When blanking a row's tail, the shorter of erasing to the end of the line and writing the
    /// blanks wins (a tie writes): one blank is a space (1 byte) rather than `\x1b[K` (3), eight
    /// are `\x1b[K`.
    #[test]
    fn a_blank_tail_is_erased_or_written_whichever_is_shorter() {
        let mut encoder = Encoder::new();
        let mut out = Vec::new();
        encoder.encode(&Frame::from_lines(&["ab x  "]), &mut out);
        out.clear();
        encoder.encode(&Frame::from_lines(&["ab    "]), &mut out);
        // the cursor stands just after the `x`: back one (BS) and a space
        assert_eq!(out, b"\x1b[?2026h\x08 \x1b[?2026l");
        encoder.encode(&Frame::from_lines(&["abcdefghij"]), &mut out);
        out.clear();
        encoder.encode(&Frame::from_lines(&["ab        "]), &mut out);
        assert!(out.windows(3).any(|w| w == b"\x1b[K"), "{:?}", String::from_utf8_lossy(&out));
        // three blanks or `\x1b[K`: a tie, and the blanks are written (the cursor ends where a
        // write leaves it, not where the erase began)
        encoder.encode(&Frame::from_lines(&["abxyz "]), &mut out);
        out.clear();
        encoder.encode(&Frame::from_lines(&["ab    "]), &mut out);
        let text = String::from_utf8_lossy(&out);
        assert!(text.contains("   ") && !text.contains("\x1b[K"), "{text:?}");
    }

    /// A full paint is the shorter of its two trials (clear to the default background, or to the
    /// most common blank one), the default on a tie, whatever `out` held before.
    #[test]
    fn a_full_paint_is_the_shorter_trial() {
        let blue = Cell { ch: ' ', fg: Color::Default, bg: Color::Indexed(4) };
        let trial = |frame: &Frame, bg: Color| {
            let mut out = Vec::new();
            clear_and_paint(
                &packed(frame),
                frame.width(),
                PackedColor::pack(bg),
                true,
                RepLevel::None,
                true,
                &mut out,
            );
            out
        };
        let mut ties = 0;
        // Frames row by row: `b` a blue blank, `d` a default blank, `x` a letter. "dbb" and "bbxd"
        // are ties.
        for rows in [
            &["dddddddd", "dddddddx"][..],
            &["bbbddddd", "dddddddx"],
            &["bbbbbbbb", "bddddddx"],
            &["bbbbbbbb", "bbbbbbbx"],
            &["bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb", "bbbbbbbbbbbbbbbbbbbbbbbbbbbbbddddddddddx"],
            &["dbb"],
            &["bbxd"],
        ] {
            let (width, height) = (rows[0].len(), rows.len());
            let mut frame = Frame::filled(width, height, Cell::BLANK);
            for (y, row) in rows.iter().enumerate() {
                for (x, kind) in row.chars().take(width).enumerate() {
                    let cell = match kind {
                        'b' => blue,
                        'x' => Cell::plain('x'),
                        _ => Cell::BLANK,
                    };
                    frame.set(x, y, cell);
                }
            }
            let (default, coloured) = (trial(&frame, Color::Default), trial(&frame, Color::Indexed(4)));
            let blue_is_commonest =
                most_common_blank_bg(&packed(&frame)) == Some(PackedColor::pack(Color::Indexed(4)));
            ties += usize::from(blue_is_commonest && coloured.len() == default.len());
            let best = if blue_is_commonest && coloured.len() < default.len() { coloured } else { default };
            let mut out = vec![b'.'; 100];
            paint_full(&packed(&frame), frame.width(), true, RepLevel::None, true, &mut out);
            assert_eq!(&out[100..], &best[..], "{rows:?}");
        }
        assert_eq!(ties, 2, "the premise: two of the cases are ties");
    }

    /// `ansi_lines`: a frame in default colours is plain text; colours are set where they change
    /// and reset at each line's end, so every line reads on its own.
    #[test]
    fn ansi_lines_are_plain_text_with_colours_where_they_change() {
        let mut out = Vec::new();
        ansi_lines(&Frame::from_lines(&["ab", " c"]), &mut out);
        assert_eq!(out, b"ab\n c\n");
        let red = Cell { ch: 'r', fg: Color::Indexed(1), bg: Color::Default };
        let on_blue = Cell { ch: ' ', fg: Color::Indexed(1), bg: Color::Indexed(4) };
        let mut frame = Frame::from_lines(&["a  ", "b  "]);
        frame.set(1, 0, red);
        frame.set(2, 0, on_blue);
        let mut out = Vec::new();
        ansi_lines(&frame, &mut out);
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.split_inclusive('\n').collect();
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[1], "b  \n", "the second line needs no colour: the first reset its own");
        assert!(lines[0].starts_with('a') && lines[0].ends_with("\x1b[0m\n"), "{:?}", lines[0]);
        // a line ending in a coloured glyph on the default background is reset too
        let mut out = Vec::new();
        let mut frame = Frame::from_lines(&["a ", "b "]);
        frame.set(1, 0, red);
        ansi_lines(&frame, &mut out);
        assert!(String::from_utf8(out).unwrap().starts_with("a\x1b[31mr\x1b[0m\nb \n"));
        // the first line, read back as a terminal would
        let n = |k| std::num::NonZeroU16::new(k).expect("non-zero");
        let mut parser = vt100::Parser::new(n(1), n(3), 0);
        parser.process(lines[0].trim_end_matches('\n').as_bytes());
        let screen = parser.screen();
        let cell = |x| screen.cell(0, x).expect("a cell");
        assert_eq!((cell(0).contents(), cell(0).fgcolor()), ("a", vt100::Color::Default));
        assert_eq!((cell(1).contents(), cell(1).fgcolor()), ("r", vt100::Color::Idx(1)));
        assert_eq!(cell(2).bgcolor(), vt100::Color::Idx(4));
    }

    #[test]
    fn erasable_tail_needs_spaces_of_one_background_and_bce_for_colour() {
        let tail =
            |row: &[Cell], bce| erasable_tail(&row.iter().map(PackedCell::pack).collect::<Vec<_>>(), bce);
        let blue = Cell { ch: ' ', fg: Color::Default, bg: Color::Indexed(4) };
        let row = [Cell::plain('a'), Cell::BLANK, blue, blue];
        assert_eq!(tail(&row, true), Some((2, PackedColor::pack(Color::Indexed(4)))));
        assert_eq!(tail(&row, false), None);
        assert_eq!(
            tail(&[Cell::plain('a'), Cell::BLANK, Cell::BLANK], false),
            Some((1, PackedColor::DEFAULT))
        );
        assert_eq!(tail(&[Cell::BLANK, Cell::plain('a')], true), None);
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
        assert_eq!(out, b"\x1b[?2026h\x1b[0;44m\x1b[20l\x1b[2J\x1b[3;4H\x1b[mx\x1b[?2026l");
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
                // a new hasher seed each time
                assert_eq!(most_common_blank_bg(&packed(&frame)), Some(PackedColor::pack(first)));
            }
        }
        let mut frame = Frame::filled(4, 2, blank(blue));
        (0..4).for_each(|x| frame.set(x, 1, Cell::BLANK));
        assert_eq!(most_common_blank_bg(&packed(&frame)), None, "a tie with the default goes to the default");
    }
}
