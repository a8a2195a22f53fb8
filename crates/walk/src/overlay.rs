//! What is drawn over the 3D view: the map (with the other players of a served maze), the HUD line, the
//! key help, the exit screen, and the message for a terminal too small to draw in. Pure: frames in, frames out; tested as text.
//!
//! The overlays keep to the walk's colour depth and charset ([`Style`]): with no colour they use the
//! terminal's own colours and frame boxes with lines instead of a background; with `ascii` glyphs every
//! character of map, HUD and boxes is ASCII. [`limit_colors`] takes every colour in a frame down to a
//! depth (the overlays' palette indices, a wall's own truecolor on the map).

use glam::Vec2;

use super::controls::{DEVELOPER_KEYS, HELP, LOCAL_ONLY, SERVED};
use mazewalk_maze::{Aabb, Maze};
use mazewalk_render::Charset;
use mazewalk_render::camera::Camera;
use mazewalk_render::palette::{ansi16, quantize_srgb8, xterm_rgb};
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame, Region};

/// The smallest terminal the walkthrough draws in (columns, rows).
pub(crate) const MIN_SIZE: (usize, usize) = (20, 6);

/// The map's scale where it does not show a whole maze: maze units per column (a row is twice as
/// tall). A generated maze's 4-unit cell is then 4 columns by 2 rows: a wall and a passage in each
/// direction, so walls and passages read one character apart (coarser, a cell's walls and its
/// floor fell in the same row).
pub(crate) const MAP_UNITS_PER_COL: f32 = 1.0;

/// The side of a generated maze's cell (and of the built-in maze's tiles), maze units.
const GRID_CELL: f32 = mazewalk_maze::generate::CELL_SIZE;
/// The scales the full map may draw a whole maze at, finest first: columns per [`GRID_CELL`] (a row
/// is twice as tall, so each is even: a cell is a whole number of rows too). The coarsest is
/// [`MAP_UNITS_PER_COL`]'s; a maze that does not fit at it scrolls.
const FULL_MAP_COLS_PER_CELL: [f32; 7] = [16.0, 14.0, 12.0, 10.0, 8.0, 6.0, 4.0];

const HUD_FG: Color = Color::Indexed(252);
const HUD_BG: Color = Color::Indexed(236);
const BOX_FG: Color = Color::Indexed(255);
const BOX_BG: Color = Color::Indexed(24);
const FLOOR_BG: Color = Color::Indexed(235);
const VISITED_BG: Color = Color::Indexed(17);
/// The map's walls: one neutral colour (a maze's own colours made the map unreadable).
const WALL_FG: Color = Color::Indexed(250);
/// The floor the viewer is looking at, on the map.
const WEDGE_BG: Color = Color::Indexed(239);
const LEGEND_FG: Color = Color::Indexed(255);
const VIEWER_FG: Color = Color::Indexed(226);
const EXIT_FG: Color = Color::Indexed(46);

/// How the overlays draw: the walk's colour depth and whether only ASCII may be used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Style {
    /// The colour depth of the whole screen.
    pub depth: ColorDepth,
    /// Only ASCII characters (the `ascii` charset).
    pub ascii: bool,
}

impl Style {
    /// The style for a walk drawn with `charset` at `depth`.
    #[must_use]
    pub fn new(charset: Charset, depth: ColorDepth) -> Style {
        Style { depth, ascii: charset == Charset::Ascii }
    }

    /// `unicode`, or `ascii` when only ASCII may be used.
    fn glyph(self, unicode: char, ascii: char) -> char {
        if self.ascii { ascii } else { unicode }
    }

    /// [`text`](Self::text) of a string of one's own: the same string where no spelling is needed
    /// (no copy: the HUD's fields, every frame).
    #[must_use]
    pub(crate) fn own_text(self, text: String) -> String {
        if self.ascii { self.text(&text) } else { text }
    }

    /// `text` with the non-ASCII characters the overlays use spelled in ASCII, when needed: degrees
    /// as ` deg`, arrows as words, a block glyph shown as an example (`half ▀`) left out.
    #[must_use]
    pub fn text(self, text: &str) -> String {
        if !self.ascii {
            return text.to_string();
        }
        let mut out = String::with_capacity(text.len());
        for c in text.chars() {
            match c {
                '°' => out.push_str(" deg"),
                // block elements and sextants: the glyph itself, nothing to spell
                '\u{2580}'..='\u{259F}' | '\u{1FB00}'..='\u{1FB3B}' => {
                    if out.ends_with(' ') {
                        out.pop();
                    }
                }
                '…' => out.push_str("..."),
                '×' => out.push('x'),
                '←' => out.push_str("Left"),
                '→' => out.push_str("Right"),
                '↑' => out.push_str("Up"),
                '↓' => out.push_str("Down"),
                c if c.is_ascii() => out.push(c),
                _ => out.push('?'),
            }
        }
        out
    }
}

impl Default for Style {
    fn default() -> Self {
        Style { depth: ColorDepth::TrueColor, ascii: false }
    }
}

/// Takes every colour in `frame` down to `depth`: truecolor to the nearest of 256 or 16 colours,
/// palette indices above 15 to the nearest of the 16, and everything to the terminal's default with
/// no colour at all — so not one code of a deeper palette is ever sent.
pub fn limit_colors(frame: &mut Frame, depth: ColorDepth) {
    let region = frame.region();
    limit_colors_in(frame, region, depth);
}

/// [`limit_colors`] in `region` of `frame` only.
pub(crate) fn limit_colors_in(frame: &mut Frame, region: Region, depth: ColorDepth) {
    // A colour already within the depth is left as it is (written back only when it changes). A
    // screen runs this over the map and the HUD's row every frame, and over the whole frame when a
    // box is up: one loop per depth, each with only its own test a colour (in 256 colours, whether
    // it is truecolor: the renderer's colours already are indices).
    fn each_color(frame: &mut Frame, region: Region, limit: impl Fn(Color) -> Option<Color>) {
        for row in frame.region_rows_mut(region) {
            for cell in row {
                for color in [&mut cell.fg, &mut cell.bg] {
                    if let Some(limited) = limit(*color) {
                        *color = limited;
                    }
                }
            }
        }
    }
    match depth {
        ColorDepth::TrueColor => {}
        ColorDepth::None => {
            each_color(frame, region, |color| (color != Color::Default).then_some(Color::Default));
        }
        ColorDepth::Ansi256 => each_color(frame, region, |color| match color {
            Color::Rgb(r, g, b) => Some(quantize_srgb8([r, g, b], depth)),
            Color::Default | Color::Indexed(_) => None,
        }),
        ColorDepth::Ansi16 => each_color(frame, region, |color| match color {
            Color::Rgb(r, g, b) => Some(quantize_srgb8([r, g, b], depth)),
            Color::Indexed(i) if i >= 16 => Some(Color::Indexed(ansi16(xterm_rgb(i)))),
            Color::Default | Color::Indexed(_) => None,
        }),
    }
}

/// True when a `cols × rows` terminal is too small for the walkthrough.
#[must_use]
pub(crate) fn too_small(cols: usize, rows: usize) -> bool {
    cols < MIN_SIZE.0 || rows < MIN_SIZE.1
}

/// Fills `frame` with a short note that the terminal is too small: the longest wording that fits the
/// width, on as many rows as there are (even 1×1 shows something).
pub(crate) fn draw_too_small(frame: &mut Frame, style: Style) {
    frame.fill(Cell::BLANK);
    let (w, h) = (frame.width(), frame.height());
    let need = style.text(&format!("need {}×{}", MIN_SIZE.0, MIN_SIZE.1));
    let title =
        ["terminal too small", "too small", "small", "!"].into_iter().find(|t| t.chars().count() <= w);
    let lines: Vec<&str> = title.into_iter().chain([need.as_str(), "q quits"]).take(h).collect();
    for (i, line) in lines.iter().enumerate() {
        let x = w.saturating_sub(line.chars().count()) / 2;
        frame.put_str(x, i + (h - lines.len()) / 2, line, Color::Default, Color::Default);
    }
}

/// The HUD: one line at the bottom of the frame.
pub(crate) fn draw_hud(frame: &mut Frame, text: &str, style: Style) {
    let Some(y) = frame.height().checked_sub(1) else { return };
    let w = frame.width();
    for x in 0..w {
        frame.set(x, y, Cell { ch: ' ', fg: HUD_FG, bg: HUD_BG });
    }
    let spelled = style.ascii.then(|| style.text(text)); // (a copy only where spelled in ASCII)
    frame.put_str(0, y, spelled.as_deref().unwrap_or(text), HUD_FG, HUD_BG);
}

/// The HUD line of [`hud_line_placed`] alone.
#[must_use]
#[cfg(test)]
pub(crate) fn hud_line(fields: &[(u8, String)], help: &str, width: usize) -> String {
    hud_line_placed(fields, help, width).0
}

/// The HUD line, exactly `width` columns: `fields` as (priority, text), lower numbers more important,
/// shown in their order; each whole or not at all (a cut number reads as a wrong one: `heading 3` for
/// 345°), the least important left out first; `help` at the right end whenever it fits. Also where
/// each field starts in it (a byte offset; `None`: left out).
#[must_use]
pub(crate) fn hud_line_placed(
    fields: &[(u8, String)],
    help: &str,
    width: usize,
) -> (String, Vec<Option<usize>>) {
    let len = |s: &str| s.chars().count();
    let help = if len(help) < width { help } else { "" };
    // A leading space, the fields two apart, and two before the help: each field costs its length
    // and two spaces (the last's pair being the leading space and one before the help), and the
    // help one more.
    let mut room = width.saturating_sub(len(help) + usize::from(!help.is_empty()));
    let mut keep = vec![false; fields.len()];
    let mut by_priority: Vec<usize> = (0..fields.len()).collect();
    by_priority.sort_by_key(|&i| fields[i].0); // stable: of equal priority, the earlier first
    for i in by_priority {
        let need = len(&fields[i].1) + 2;
        if !fields[i].1.is_empty() && need <= room {
            (keep[i], room) = (true, room - need);
        }
    }
    let mut line = String::with_capacity(width + 8);
    let mut at = vec![None; fields.len()];
    for (i, field) in fields.iter().enumerate().filter(|(i, _)| keep[*i]) {
        line.push_str(if line.is_empty() { " " } else { "  " });
        at[i] = Some(line.len());
        line.push_str(&field.1);
    }
    let pad = width.saturating_sub(len(&line) + len(help));
    line.extend(std::iter::repeat_n(' ', pad));
    line.push_str(help);
    (line, at)
}

/// A box of text lines centred above the HUD's row (drawn over boxes), clipped to the frame. Without
/// colour its background would not set it apart from the view: it gets a frame of lines instead.
///
/// Short of room, a box gives up spacing before text: its blank rows, then its padding (or frame);
/// then its last lines, for a `…` row (so a box lists what matters most first). A line too wide loses
/// words from its end, marked `…`, never part of one ([`fit_line`]).
pub(crate) fn draw_box(frame: &mut Frame, title: &str, lines: &[String], style: Style) {
    let (w, h) = (frame.width(), frame.height().saturating_sub(1));
    let inner = lines.iter().map(|l| l.chars().count()).chain([title.chars().count()]).max().unwrap_or(0);
    let side = if inner + 4 <= w { 2 } else { 1 };
    let bw = (inner + 2 * side).min(w);
    let text_width = bw.saturating_sub(2 * side);
    // (rows above and below the text, a blank row under the title, the lines)
    let mut rows: Vec<&str> = lines.iter().map(String::as_str).collect();
    let (mut pad, mut gap) = (1, 1);
    if rows.len() + 2 + 2 * pad > h {
        (gap, pad) = (0, 1);
        rows.retain(|l| !l.trim().is_empty());
    }
    if rows.len() + 1 + 2 * pad > h {
        pad = 0;
    }
    let more = rows.len() + 1 > h;
    rows.truncate(h.saturating_sub(2)); // room for the title and the `…` row
    let bh = (rows.len() + usize::from(more) + 1 + gap + 2 * pad).min(h);
    let (x0, y0) = ((w - bw) / 2, (h - bh) / 2);
    let (fg, bg) =
        if style.depth == ColorDepth::None { (Color::Default, Color::Default) } else { (BOX_FG, BOX_BG) };
    for y in y0..y0 + bh {
        for x in x0..x0 + bw {
            frame.set(x, y, Cell { ch: ' ', fg, bg });
        }
    }
    if style.depth == ColorDepth::None && bw >= 2 && pad == 1 {
        let (x1, y1) = (x0 + bw - 1, y0 + bh - 1);
        let line = |ch| Cell { ch, fg, bg };
        for x in x0..=x1 {
            frame.set(x, y0, line(style.glyph('─', '-')));
            frame.set(x, y1, line(style.glyph('─', '-')));
        }
        for y in y0..=y1 {
            frame.set(x0, y, line(style.glyph('│', '|')));
            frame.set(x1, y, line(style.glyph('│', '|')));
        }
        for (x, y, ch) in [(x0, y0, '┌'), (x1, y0, '┐'), (x0, y1, '└'), (x1, y1, '┘')] {
            frame.set(x, y, line(style.glyph(ch, '+')));
        }
    }
    let ellipsis = if style.ascii { "..." } else { "…" };
    let title = fit_line(&style.text(title), text_width, ellipsis);
    let tx = x0 + bw.saturating_sub(title.chars().count()) / 2;
    frame.put_str(tx, y0 + pad, &title, fg, bg);
    let mut texts: Vec<String> =
        rows.iter().map(|l| fit_line(&style.text(l), text_width, ellipsis)).collect();
    // columns aligned on some rows only read as a jumble: if one row gave up its alignment, all do
    if rows.iter().zip(&texts).any(|(row, text)| row.contains("  ") && !text.contains("  ")) {
        let squeeze = |l: &&str| l.split_whitespace().collect::<Vec<_>>().join(" ");
        texts = rows.iter().map(|l| fit_line(&style.text(&squeeze(l)), text_width, ellipsis)).collect();
    }
    for (i, text) in texts.into_iter().chain(more.then(|| ellipsis.to_string())).enumerate() {
        frame.put_str(x0 + side, y0 + pad + 1 + gap + i, &text, fg, bg);
    }
}

/// `line` in at most `width` columns: whole, or shortened by words from its end with `ellipsis` after
/// them. A line in two columns (a run of spaces between them) gives up its alignment when that keeps
/// more of its second column. Only a first word wider than the box is cut.
#[must_use]
pub(crate) fn fit_line(line: &str, width: usize, ellipsis: &str) -> String {
    let len = |s: &str| s.chars().count();
    if len(line) <= width {
        return line.to_string();
    }
    // the longest prefix ending at a word's end that leaves room for the ellipsis
    let shorten = |line: &str| -> Option<String> {
        let ends = line.char_indices().filter(|&(i, c)| c == ' ' && i > 0 && !line[..i].ends_with(' '));
        let cut = ends.map(|(i, _)| i).rfind(|&i| len(&line[..i]) + len(ellipsis) <= width)?;
        Some(format!("{}{ellipsis}", &line[..cut]))
    };
    let words = |s: &str| s.split_whitespace().count();
    let squeezed = line.split_whitespace().collect::<Vec<_>>().join(" ");
    let candidates = [shorten(line), (len(&squeezed) <= width).then(|| squeezed.clone()), shorten(&squeezed)];
    if let Some(best) =
        candidates.into_iter().flatten().max_by_key(|c| (words(c), usize::from(c.contains("  "))))
    {
        return best;
    }
    let keep = width.saturating_sub(len(ellipsis));
    if keep == 0 {
        return line.chars().take(width).collect();
    }
    format!("{}{ellipsis}", line.chars().take(keep).collect::<String>())
}

/// The help's line about the goal, in a maze with an exit.
pub(crate) const GOAL: (&str, &str) = ("goal", "find the exit: E on the map, a green beacon ahead");

/// The key help as box lines (in ASCII when the style asks for it): how to quit and close it first,
/// then the goal in a maze with an exit, then the keys.
#[must_use]
pub fn help_lines(style: Style, has_exit: bool) -> Vec<String> {
    help_lines_for(style, has_exit, false)
}

/// [`help_lines`] for a walk that is `served` or not: a served player's help has the player list's
/// `Tab` instead of `Ctrl-Z` (which cannot stop a server), and no developer keys
/// ([`DEVELOPER_KEYS`]: they do nothing there).
#[must_use]
pub fn help_lines_for(style: Style, has_exit: bool, served: bool) -> Vec<String> {
    let local_only = |keys: &str| keys == LOCAL_ONLY || DEVELOPER_KEYS.contains(&keys);
    let keys = HELP[2..].iter().copied().filter(|(keys, _)| !served || !local_only(keys));
    let rows: Vec<(&str, &str)> = HELP[..2]
        .iter()
        .copied()
        .chain(has_exit.then_some(GOAL))
        .chain(keys)
        .chain(served.then_some(SERVED))
        .collect();
    let width = rows.iter().map(|(keys, _)| style.text(keys).chars().count()).max().unwrap_or(0);
    rows.iter().map(|(keys, what)| format!("{:<width$} {}", style.text(keys), style.text(what))).collect()
}

/// The last row of page `page` (from 1) of a help in `count` pages: the keys that turn its pages
/// (after the last page Space shows the first again).
#[must_use]
pub fn page_row(page: usize, count: usize) -> String {
    let next = if page >= count { "first" } else { "next" };
    format!("Space / PgDn: {next} page, PgUp: back ({page} of {count})")
}

/// The help's `lines` as pages for a box over a frame `height` rows tall (the HUD's row included):
/// one page when they all fit (with a row above and below the title and lines), else pages of about
/// equal length, each ending in a row that says which page it is and how to see the next (as wide as
/// the widest line where the frame's `width` has room: every page's box the same).
#[must_use]
pub fn help_pages(lines: &[String], (width, height): (usize, usize)) -> Vec<Vec<String>> {
    let h = height.saturating_sub(1);
    if lines.len() + 3 <= h || lines.is_empty() {
        return vec![lines.to_vec()];
    }
    let per = h.saturating_sub(4).max(1); // the title, a row above and below, the page's own row
    let pages = lines.len().div_ceil(per);
    let per = lines.len().div_ceil(pages);
    let count = lines.len().div_ceil(per);
    lines
        .chunks(per)
        .enumerate()
        .map(|(i, page)| {
            let mut page = page.to_vec();
            let row = page_row(i + 1, count);
            let widest = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
            page.push(if widest + 4 <= width { format!("{row:<widest$}") } else { row });
            page
        })
        .collect()
}

/// Where the map goes and how much of the maze one map character shows.
///
/// The map's characters form a lattice over the maze plane, `lattice` columns × rows centred on
/// `centre`, each `units_per_col` wide and twice that tall; the frame shows the part of it from lattice
/// character `from` on, `width` × `height` characters at (`x`, `y`) — all of it, unless the map was
/// fitted to what has been seen ([`MapArea::fit_to_seen`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapArea {
    /// Left column in the frame.
    pub x: usize,
    /// Top row in the frame.
    pub y: usize,
    /// Columns shown.
    pub width: usize,
    /// Rows shown.
    pub height: usize,
    /// Maze units per map column (a row shows twice as much: terminal cells are twice as tall).
    pub units_per_col: f32,
    /// The maze point at the lattice's centre.
    pub centre: Vec2,
    /// The whole lattice, columns and rows.
    lattice: (usize, usize),
    /// The lattice character shown at (`x`, `y`).
    from: (usize, usize),
}

impl MapArea {
    /// A map of `width × height` characters at (`x`, `y`), the whole lattice shown.
    fn whole(x: usize, y: usize, width: usize, height: usize, units_per_col: f32, centre: Vec2) -> MapArea {
        MapArea { x, y, width, height, units_per_col, centre, lattice: (width, height), from: (0, 0) }
    }

    /// A small map in the top-right corner at [`MAP_UNITS_PER_COL`], centred on the viewer (to the
    /// nearest character), a third of the frame's width and height at most, so a ninth of it, and
    /// 40 × 14 characters at most ([`fit_to_seen`](Self::fit_to_seen) draws what has been seen of it).
    #[must_use]
    pub fn corner(frame: &Frame, viewer: Vec2) -> MapArea {
        let width = (frame.width() / 3).clamp(1, 40);
        let height = (frame.height() / 3).clamp(1, 14);
        let u = MAP_UNITS_PER_COL;
        MapArea::whole(frame.width() - width, 0, width, height, u, snap(viewer, u))
    }

    /// The whole frame but the HUD's row: the whole maze if it fits at [`MAP_UNITS_PER_COL`] or
    /// closer, else a window at that scale on the part of the maze round the viewer — the viewer in
    /// it, the window within the maze's outline (and one character round it) rather than centred on
    /// the viewer, which showed half a screen of nothing by the maze's sides.
    ///
    /// The whole maze is drawn at the finest scale that fits (4 to 16 columns a generated cell), its
    /// outline included (issue #39: the east and south walls, each a character past the last cell,
    /// fell off a map scaled to the maze's width and height alone), with the maze's corner on a
    /// character's corner: every generated cell is then the same whole number of characters, its walls
    /// in the same columns and rows as its neighbours'.
    #[must_use]
    pub fn full(frame: &Frame, maze: &Maze, viewer: Vec2) -> MapArea {
        let (width, height) = (frame.width().max(1), frame.height().saturating_sub(1).max(1));
        let (lo, hi) = (maze.extents().min, maze.extents().max);
        let size = hi - lo;
        // characters the maze takes at `u` units a column: its extent, and one for the far outline
        let needs = |u: f32| {
            let chars = |extent: f32, unit: f32| (extent / unit - 1e-3).ceil().max(0.0) as usize + 1;
            (chars(size.x, u), chars(size.y, 2.0 * u))
        };
        let fits = FULL_MAP_COLS_PER_CELL.iter().map(|&k| GRID_CELL / k).find(|&u| {
            let (cols, rows) = needs(u);
            cols <= width && rows <= height
        });
        if let Some(u) = fits {
            // the maze's north-west corner on the corner of character (`left`, `top`), the maze
            // centred within a character
            let (cols, rows) = needs(u);
            let (left, top) = ((width - cols) / 2, (height - rows) / 2);
            let centre = Vec2::new(
                lo.x + (width as f32 / 2.0 - left as f32) * u,
                hi.y + (top as f32 - height as f32 / 2.0) * 2.0 * u,
            );
            return MapArea::whole(0, 0, width, height, u, centre);
        }
        let u = MAP_UNITS_PER_COL;
        // half the window, in maze units; the window may reach a character past the outline
        let half = Vec2::new(width as f32 * u, height as f32 * 2.0 * u) * 0.5;
        let (lo, hi) = (lo - Vec2::splat(u), hi + Vec2::splat(u));
        let axis = |v: f32, lo: f32, hi: f32, half: f32| {
            if hi - lo <= 2.0 * half { (lo + hi) * 0.5 } else { v.clamp(lo + half, hi - half) }
        };
        let centre = Vec2::new(axis(viewer.x, lo.x, hi.x, half.x), axis(viewer.y, lo.y, hi.y, half.y));
        MapArea::whole(0, 0, width, height, u, snap(centre, u))
    }

    /// This map cut down to the characters that show a `seen` cell or one of the points `also` (the
    /// viewer, the other players), kept in the top-right corner of where it was: at the start of a
    /// walk a corner map is the corridor in view, not a box of black; it grows as the walk sees more,
    /// up to the whole area.
    ///
    /// `seen_key`, where given, names `seen` (of the same maze): the characters' box found for it
    /// and this area is kept in `cells`, and taken again while both stay the same.
    #[must_use]
    pub(crate) fn fit_to_seen(
        &self,
        maze: &Maze,
        seen: &(impl Fn(u32) -> bool + ?Sized),
        also: impl IntoIterator<Item = Vec2>,
        cells: &mut MapCells,
        seen_key: Option<(u64, bool)>,
    ) -> MapArea {
        let (mut lo, mut hi) = match (seen_key, cells.fitted) {
            (Some(key), Some((area, kept, found))) if kept == key && area == *self => {
                #[cfg(test)]
                FITS_KEPT.with(|n| n.set(n.get() + 1));
                found
            }
            _ => {
                let probes = cells.for_area(self, maze);
                let (mut lo, mut hi) = ((usize::MAX, usize::MAX), (0, 0));
                for row in self.from.1..self.from.1 + self.height {
                    for col in self.from.0..self.from.0 + self.width {
                        let p = &probes[row * self.lattice.0 + col];
                        if p.iter().any(|&(c, _)| c != NO_CELL && seen(c)) {
                            lo = (lo.0.min(col), lo.1.min(row));
                            hi = (hi.0.max(col), hi.1.max(row));
                        }
                    }
                }
                cells.fitted = seen_key.map(|key| (*self, key, (lo, hi)));
                (lo, hi)
            }
        };
        let mut include = |col: usize, row: usize| {
            lo = (lo.0.min(col), lo.1.min(row));
            hi = (hi.0.max(col), hi.1.max(row));
        };
        for (col, row) in also.into_iter().filter_map(|p| self.lattice_char(p)) {
            include(col, row);
        }
        if lo.0 > hi.0 {
            return *self; // nothing seen here (a viewer outside the maze): the whole area
        }
        let (width, height) = (hi.0 - lo.0 + 1, hi.1 - lo.1 + 1);
        MapArea { x: self.x + self.width - width, width, height, from: lo, ..*self }
    }

    /// The maze-plane box lattice character (`col`, `row`) covers.
    fn world_box(&self, col: usize, row: usize) -> Aabb {
        let (u, v) = (self.units_per_col, 2.0 * self.units_per_col);
        let x0 = self.centre.x + (col as f32 - self.lattice.0 as f32 / 2.0) * u;
        let y1 = self.centre.y - (row as f32 - self.lattice.1 as f32 / 2.0) * v; // north is up
        Aabb::new(Vec2::new(x0, y1 - v), Vec2::new(x0 + u, y1))
    }

    /// Whether maze point `p` shows on the map (a host redraws a player's screen when another player
    /// moves inside it).
    #[must_use]
    pub fn shows(&self, p: Vec2) -> bool {
        self.frame_cell(p).is_some()
    }

    /// The lattice character showing maze point `p`, as floats.
    fn to_map(self, p: Vec2) -> Vec2 {
        Vec2::new(
            (p.x - self.centre.x) / self.units_per_col + self.lattice.0 as f32 / 2.0,
            -(p.y - self.centre.y) / (2.0 * self.units_per_col) + self.lattice.1 as f32 / 2.0,
        )
    }

    /// The lattice character (column, row) showing maze point `p`, if `p` is on the lattice.
    fn lattice_char(&self, p: Vec2) -> Option<(usize, usize)> {
        let m = self.to_map(p);
        let on =
            m.x >= 0.0 && m.y >= 0.0 && (m.x as usize) < self.lattice.0 && (m.y as usize) < self.lattice.1;
        on.then_some((m.x as usize, m.y as usize))
    }

    /// The frame cell (column, row) showing maze point `p`, if the map shows it.
    fn frame_cell(&self, p: Vec2) -> Option<(usize, usize)> {
        let (col, row) = self.lattice_char(p)?;
        let (col, row) = (col.checked_sub(self.from.0)?, row.checked_sub(self.from.1)?);
        (col < self.width && row < self.height).then_some((self.x + col, self.y + row))
    }
}

/// `p` moved to the nearest corner of the map's character lattice (`units_per_col` across, twice
/// that down): a map centred there scrolls a whole character at a time, so its characters cover the
/// same pieces of the maze from frame to frame while the viewer walks within one ([`MapCells`] keeps
/// what they show).
fn snap(p: Vec2, units_per_col: f32) -> Vec2 {
    let step = Vec2::new(units_per_col, 2.0 * units_per_col);
    (p / step).round() * step
}

/// What each character of a map shows of the maze, for one [`MapArea`]: the cells under its probe
/// points (its centre, then points near its corners; for a character outside the maze, the cell
/// just west or north whose wall is its outline) and, for each, whether one of the cell's walls
/// crosses the character. Worked out when the area changes (the map scrolled, the terminal was
/// resized) and kept: a frame's map is then a look-up per character, not five point locations (the
/// map was a sixth of a served frame's cost).
#[derive(Clone, Debug, Default)]
pub struct MapCells {
    /// The area and the maze (its cell and edge counts) the probes are for.
    key: Option<(MapArea, usize, usize)>,
    /// Per character, row by row: per probe, its cell ([`NO_CELL`] if none) and that cell's wall.
    probes: Vec<[(u32, bool); 5]>,
    /// Scratch: the probes of the lattice before, while a moved one takes what it shares with it.
    before: Vec<[(u32, bool); 5]>,
    /// Characters whose probes were worked out, all told (the others were kept).
    worked_out: usize,
    /// The last fit ([`MapArea::fit_to_seen`]): the area, the seen cells' key, and the box of the
    /// characters showing a seen cell (lower and upper corners; empty when the lower is past it).
    fitted: Option<(MapArea, (u64, bool), CharBox)>,
}

/// A box of a map's lattice characters: its lower and upper corners (column, row).
type CharBox = ((usize, usize), (usize, usize));

#[cfg(test)]
thread_local! {
    /// Fits [`MapArea::fit_to_seen`] took again from the one before, on this thread (for the test
    /// that holds them to fits worked out).
    pub(crate) static FITS_KEPT: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// "No cell under this probe" in [`MapCells`].
const NO_CELL: u32 = u32::MAX;

impl MapCells {
    /// The probes of the characters of `area`'s whole lattice, row by row, worked out now if the
    /// lattice is not the one kept (whatever part of it is shown).
    fn for_area(&mut self, area: &MapArea, maze: &Maze) -> &[[(u32, bool); 5]] {
        let lattice =
            MapArea { x: 0, y: 0, width: area.lattice.0, height: area.lattice.1, from: (0, 0), ..*area };
        let key = (lattice, maze.cell_count(), maze.edges().len());
        if self.key != Some(key) {
            // A lattice of the same maze, size and scale moved by whole characters (the corner map
            // following a walker) shares most of its characters with the one before: a character
            // whose box is bit for bit a box of the lattice before takes that one's probes (a
            // function of the box and the maze), the others are worked out.
            let shifted = self.key.filter(|(kept, cells, edges)| {
                (kept.lattice, kept.units_per_col, *cells, *edges)
                    == (lattice.lattice, lattice.units_per_col, key.1, key.2)
            });
            std::mem::swap(&mut self.probes, &mut self.before);
            self.probes.clear();
            let (columns, rows) = area.lattice;
            let offset = shifted.map(|(kept, ..)| {
                // (dx, dy): the characters the lattice moved by, east and south
                let d =
                    (lattice.centre - kept.centre) / Vec2::new(kept.units_per_col, -2.0 * kept.units_per_col);
                ((d.x.round() as i64, d.y.round() as i64), kept)
            });
            for row in 0..rows {
                for col in 0..columns {
                    let world_box = area.world_box(col, row);
                    let kept = offset.and_then(|((dx, dy), kept)| {
                        let (c, r) = (col as i64 + dx, row as i64 + dy);
                        let on = (0..columns as i64).contains(&c) && (0..rows as i64).contains(&r);
                        let (c, r) = (c as usize, r as usize);
                        (on && same_box(kept.world_box(c, r), world_box))
                            .then(|| self.before[r * columns + c])
                    });
                    self.probes.push(kept.unwrap_or_else(|| {
                        self.worked_out += 1;
                        probes(world_box, maze)
                    }));
                }
            }
            self.key = Some(key);
        }
        &self.probes
    }
}

/// Whether two boxes are the same bit for bit (the probes of one are the other's).
fn same_box(a: Aabb, b: Aabb) -> bool {
    let bits = |b: Aabb| [b.min.x, b.min.y, b.max.x, b.max.y].map(f32::to_bits);
    bits(a) == bits(b)
}

/// The cells under a map character covering `world_box`, and whether each has a wall through it.
///
/// A wall on the line between two characters (the usual case: a generated maze's walls lie on
/// multiples of its cell size, and so do the lattice's lines) belongs to the character after it, east
/// or south: the box is half-open, `[min, max)`, so that a wall is drawn one character thick.
fn probes(world_box: Aabb, maze: &Maze) -> [(u32, bool); 5] {
    // [min, max) on x, (min, max] on y (north is up: the southern edge is the one left out), each
    // shifted a thousandth of the box toward the edge it keeps: a lattice line computed a rounding
    // error off a wall (at 0.4 units a column, say) still gives the wall to the same character
    let e = (world_box.max - world_box.min) * 1e-3;
    let half_open = Aabb::new(
        Vec2::new(world_box.min.x - e.x, world_box.min.y + e.y),
        Vec2::new(world_box.max.x - e.x, world_box.max.y + e.y),
    );
    // the character's centre, else a point near a corner (so a wall on the maze's outline, whose
    // character is centred outside, is still drawn)
    let inset = (world_box.max - world_box.min) * 0.1;
    let points = [
        world_box.centre(),
        world_box.min + inset,
        Vec2::new(world_box.max.x - inset.x, world_box.min.y + inset.y),
        Vec2::new(world_box.min.x + inset.x, world_box.max.y - inset.y),
        world_box.max - inset,
    ];
    let probe = |p: Vec2| match maze.cell_at(p) {
        None => (NO_CELL, false),
        Some(c) => {
            let walled = maze.cell_edges(c).iter().any(|&e| {
                let (a, b) = maze.edge_points(e);
                maze.edges().is_opaque(e as usize) && half_open.touches_segment(a, b)
            });
            (c, walled)
        }
    };
    let mut found = points.map(probe);
    if found.iter().all(|&(c, _)| c == NO_CELL) {
        // Outside the maze, a character may still hold its outline: a wall on its west or north edge
        // (or its north-west corner) belongs to it, and the cell it bounds lies just west or north
        // (issue #39: the east and south outline were missing). Only the wall is taken from there,
        // never the floor.
        let outside = [
            Vec2::new(world_box.min.x - inset.x, world_box.centre().y),
            Vec2::new(world_box.centre().x, world_box.max.y + inset.y),
            Vec2::new(world_box.min.x - inset.x, world_box.max.y + inset.y),
        ];
        if let Some(&(c, _)) = outside.map(probe).iter().find(|&&(_, walled)| walled) {
            found[0] = (c, true);
        }
    }
    found
}

/// Draws the map into `area`: the cells the viewer has `seen` (fog of war: nothing else, not even
/// the exit), walls in one neutral colour, the view wedge and the viewer ([`draw_peers`] adds the other
/// players).
/// `tint`, when given, marks the cells the portal pass visited this frame, with a legend.
#[allow(clippy::too_many_arguments)]
pub fn draw_map(
    frame: &mut Frame,
    area: &MapArea,
    maze: &Maze,
    camera: &Camera,
    seen: &(impl Fn(u32) -> bool + ?Sized),
    tint: Option<&dyn Fn(u32) -> bool>,
    style: Style,
    cells: &mut MapCells,
) {
    let wall = Cell { ch: style.glyph('█', '#'), fg: WALL_FG, bg: FLOOR_BG };
    let eye = camera.position;
    // The view wedge: within a dozen columns, and within ±fov/2 of the heading, i.e. the cosine of
    // the angle off the heading at least cos(fov/2) (no angle computed per cell).
    let (reach, heading) = (12.0 * area.units_per_col, Vec2::from_angle(camera.yaw_deg.to_radians()));
    let cos_half_fov = (camera.hfov_deg * 0.5).to_radians().cos();
    let probes = cells.for_area(area, maze);
    for row in 0..area.height {
        for col in 0..area.width {
            let (lattice_col, lattice_row) = (area.from.0 + col, area.from.1 + row);
            let world_box = area.world_box(lattice_col, lattice_row);
            // the first probe on a seen cell
            let probe = probes.get(lattice_row * area.lattice.0 + lattice_col);
            let found = probe.and_then(|p| p.iter().find(|&&(c, _)| c != NO_CELL && seen(c)));
            let cell = match found {
                None => Cell::BLANK, // unseen, or outside the maze
                Some(&(c, walled)) => {
                    let bg = match tint {
                        Some(tint) if tint(c) => VISITED_BG,
                        _ => FLOOR_BG,
                    };
                    if walled {
                        Cell { bg, ..wall }
                    } else {
                        // Floor; inside the view wedge a lighter floor.
                        let to = world_box.centre() - eye;
                        let distance = to.length();
                        let in_wedge = distance < reach && to.dot(heading) >= distance * cos_half_fov;
                        let bg = if in_wedge && bg == FLOOR_BG { WEDGE_BG } else { bg };
                        Cell { ch: ' ', fg: Color::Default, bg }
                    }
                }
            };
            frame.set(area.x + col, area.y + row, cell);
        }
    }
    let put = |frame: &mut Frame, p: Vec2, ch: char, fg: Color| {
        if let Some((x, y)) = area.frame_cell(p) {
            let bg = frame.get(x, y).map_or(Color::Default, |c| c.bg);
            frame.set(x, y, Cell { ch, fg, bg });
        }
    };
    if let Some(exit) = maze.exit().filter(|exit| seen(exit.cell)).and(maze.exit_point()) {
        put(frame, exit, 'E', EXIT_FG);
    }
    let arrow = heading_arrow(camera.yaw_deg);
    let arrow = if style.ascii { ascii_arrow(camera.yaw_deg) } else { arrow };
    put(frame, camera.position, arrow, VIEWER_FG);
    if tint.is_some() && area.height > 1 {
        // The legend, on the map's last row.
        let legend = " portal pass: cells visited now ";
        for (k, ch) in legend.chars().take(area.width).enumerate() {
            frame.set(area.x + k, area.y + area.height - 1, Cell { ch, fg: LEGEND_FG, bg: VISITED_BG });
        }
    }
}

/// Another player walking the same maze (`mazewalk serve`), as the map shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peer {
    /// Where the player stands (maze plane).
    pub position: Vec2,
    /// Which way the player faces, degrees counter-clockwise from +x.
    pub heading_deg: f32,
    /// The first letter of the player's name (ASCII).
    pub initial: char,
    /// The player's colour.
    pub color: Color,
    /// The cell the player stands in, where the caller knows it (the server does); `None`: the
    /// renderer looks it up (a point location per peer per frame).
    pub cell: Option<u32>,
}

/// Draws each peer on the map in `area` as its initial in its colour (over walls and floor alike; the
/// viewer's own arrow, drawn by [`draw_map`] before, stays on top where they meet). Where peers share
/// a character, the one the view shows in front shows: the nearest the viewer, of equally near ones
/// the first (as the renderer draws figures), so a player has one label in the view and on the map.
pub(crate) fn draw_peers(frame: &mut Frame, area: &MapArea, peers: &[Peer], viewer: Vec2, style: Style) {
    let own = area.frame_cell(viewer);
    // farthest first and, of equals, the last first: the one in front is drawn last
    let mut order: Vec<(f32, usize)> =
        peers.iter().enumerate().map(|(i, p)| (p.position.distance_squared(viewer), i)).collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)));
    for peer in order.iter().map(|&(_, i)| &peers[i]) {
        let Some((x, y)) = area.frame_cell(peer.position) else { continue };
        if own == Some((x, y)) {
            continue;
        }
        let bg = frame.get(x, y).map_or(Color::Default, |c| c.bg);
        let initial = if peer.initial.is_ascii_graphic() { peer.initial } else { '?' };
        let fg = if style.depth == ColorDepth::None { Color::Default } else { peer.color };
        frame.set(x, y, Cell { ch: initial, fg, bg });
    }
}

/// The look-ahead lens's range marks (the screen's `range_marks`): a light grey digit on black.
pub(crate) const RANGE_FG: Color = Color::Rgb(220, 220, 220);

/// A ghost's colour on the map and on its caption: a pale blue, no player's.
pub(crate) const GHOST_FG: Color = Color::Rgb(190, 230, 255);

/// Draws a stored run's ghost on the map in `area` at `position`: `◌` (`@` in ASCII), under the
/// viewer's own arrow where they meet.
pub(crate) fn draw_ghost(frame: &mut Frame, area: &MapArea, position: Vec2, viewer: Vec2, style: Style) {
    let Some((x, y)) = area.frame_cell(position) else { return };
    if area.frame_cell(viewer) == Some((x, y)) {
        return;
    }
    let bg = frame.get(x, y).map_or(Color::Default, |c| c.bg);
    let fg = if style.depth == ColorDepth::None { Color::Default } else { GHOST_FG };
    frame.set(x, y, Cell { ch: if style.ascii { '@' } else { '◌' }, fg, bg });
}

/// [`heading_arrow`] in ASCII: `>`, `^`, `<`, `v` by quadrant.
#[must_use]
pub(crate) fn ascii_arrow(yaw_deg: f32) -> char {
    ['>', '^', '<', 'v'][((yaw_deg.rem_euclid(360.0) + 45.0) / 90.0) as usize % 4]
}

/// An arrow glyph pointing along the heading (counter-clockwise from east), in 45° steps.
#[must_use]
pub(crate) fn heading_arrow(yaw_deg: f32) -> char {
    const ARROWS: [char; 8] = ['→', '↗', '↑', '↖', '←', '↙', '↓', '↘'];
    let octant = ((yaw_deg.rem_euclid(360.0) + 22.5) / 45.0) as usize % 8;
    ARROWS[octant]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn too_small_message_fits_any_size_without_panicking() {
        for (w, h) in [(0, 0), (1, 1), (5, 2), (19, 5), (80, 24)] {
            let mut frame = Frame::new(w, h);
            draw_too_small(&mut frame, Style::default());
            assert_eq!((frame.width(), frame.height()), (w, h));
        }
        let mut frame = Frame::new(20, 3);
        draw_too_small(&mut frame, Style::default());
        assert_eq!(frame.lines()[0], " terminal too small ");
        assert!(too_small(19, 24) && too_small(80, 5) && !too_small(20, 6));
    }

    #[test]
    fn a_map_drawn_from_kept_cells_is_the_map_drawn_afresh() {
        let maze = mazewalk_maze::builtin().unwrap();
        let start = maze.viewer().pos;
        let mut kept = MapCells::default();
        let cells = maze.cell_count() as u32;
        // walking east and turning, as more of the maze is seen; the corner map and the full one
        for step in 0..24 {
            let position = start + Vec2::new(0.37 * step as f32, 0.11 * (step % 5) as f32);
            let camera = Camera::new(position, 15.0 * step as f32, 90.0);
            let seen = |c: u32| c % 3 != step as u32 % 3 || c == cells - 1;
            for full in [false, true] {
                let frame = Frame::new(90, 30);
                let area = if full {
                    MapArea::full(&frame, &maze, position)
                } else {
                    MapArea::corner(&frame, position)
                };
                let draw = |cells: &mut MapCells| {
                    let mut frame = frame.clone();
                    draw_map(&mut frame, &area, &maze, &camera, &seen, None, Style::default(), cells);
                    frame
                };
                let from_kept = draw(&mut kept);
                assert_eq!(from_kept, draw(&mut MapCells::default()), "step {step}, full {full}");
                assert!(from_kept.cells().iter().any(|c| c.fg == WALL_FG), "step {step}, full {full}: walls");
            }
        }
    }

    /// The corner map following a walker works out only the characters it did not show before
    /// (issue #42: every character of it was worked out again each time it moved by one), and
    /// draws what it draws afresh.
    #[test]
    fn a_corner_map_moved_by_whole_characters_keeps_what_it_showed() {
        let maze = mazewalk_maze::builtin().unwrap();
        let start = maze.viewer().pos;
        let mut kept = MapCells::default();
        let frame = Frame::new(120, 40);
        let seen = |_| true;
        let mut shifts = 0;
        for step in 0..30 {
            // east, then north (a row is two maze units), by a character or two a step
            let position = start
                + if step < 15 {
                    Vec2::new(step as f32, 0.0)
                } else {
                    Vec2::new(14.0, 1.5 * (step - 14) as f32)
                };
            let camera = Camera::new(position, 0.0, 90.0);
            let area = MapArea::corner(&frame, position);
            let before = kept.worked_out;
            let draw = |cells: &mut MapCells| {
                let mut frame = frame.clone();
                draw_map(&mut frame, &area, &maze, &camera, &seen, None, Style::default(), cells);
                frame
            };
            assert_eq!(draw(&mut kept), draw(&mut MapCells::default()), "step {step}");
            let worked = kept.worked_out - before;
            if step > 0 && worked > 0 {
                // A move of a column works out one column, of a row one row (or two).
                assert!(worked <= 2 * area.lattice.0.max(area.lattice.1), "step {step}: {worked}");
                shifts += 1;
            }
        }
        assert!(shifts > 20, "moves: {shifts}");
    }

    /// The lighter floor is the view wedge: floor within a dozen columns whose direction from the
    /// viewer is within ±fov/2 of the heading (by angles here, by a cosine in `draw_map`), at every
    /// heading, for narrow and wide fields of view; none behind.
    #[test]
    fn the_map_lights_the_floor_in_the_view_wedge() {
        let maze = mazewalk_maze::builtin().unwrap();
        let position = maze.viewer().pos;
        let frame = Frame::new(120, 40);
        let area = MapArea::corner(&frame, position);
        let reach = 12.0 * area.units_per_col;
        let (mut lit, mut checked) = (0, 0);
        for (yaw, hfov) in [(0.0, 90.0), (37.0, 60.0), (180.0, 90.0), (-100.0, 120.0), (271.0, 30.0)] {
            let camera = Camera::new(position, yaw, hfov);
            let mut frame = frame.clone();
            draw_map(
                &mut frame,
                &area,
                &maze,
                &camera,
                &|_| true,
                None,
                Style::default(),
                &mut MapCells::default(),
            );
            for row in 0..area.height {
                for col in 0..area.width {
                    let cell = frame.get(area.x + col, area.y + row).unwrap();
                    if cell.ch != ' ' || !(cell.bg == WEDGE_BG || cell.bg == FLOOR_BG) {
                        continue; // walls, the arrow, outside the maze
                    }
                    let to = area.world_box(col, row).centre() - position;
                    let off = (to.to_angle().to_degrees() - yaw + 540.0).rem_euclid(360.0) - 180.0;
                    let (near_edge, inside) = (
                        (off.abs() - hfov / 2.0).abs() < 0.01 || (to.length() - reach).abs() < 0.01,
                        off.abs() <= hfov / 2.0 && to.length() < reach,
                    );
                    if !near_edge {
                        assert_eq!(cell.bg == WEDGE_BG, inside, "yaw {yaw}, fov {hfov}: {to} is {off}° off");
                        lit += usize::from(inside);
                        checked += 1;
                    }
                }
            }
        }
        assert!(lit > 20 && checked > 2 * lit, "{lit} lit of {checked}");
    }

    #[test]
    fn the_corner_map_scrolls_a_whole_character_at_a_time() {
        let frame = Frame::new(120, 40);
        let at = |x: f32, y: f32| MapArea::corner(&frame, Vec2::new(x, y));
        // 40 columns: 1 unit a column, 2 a row
        assert_eq!(at(10.2, 7.4), at(10.4, 7.9));
        assert_eq!(at(10.2, 7.4).centre, Vec2::new(10.0, 8.0));
        assert_ne!(at(10.2, 7.4), at(10.6, 7.4));
        // the viewer stays within a character of the map's middle
        for (x, y) in [(10.49, 6.99), (3.51, -1.01), (0.0, 0.0)] {
            let area = at(x, y);
            let m = area.to_map(Vec2::new(x, y)) - Vec2::new(area.width as f32, area.height as f32) / 2.0;
            assert!(m.abs().max_element() <= 0.5, "{m}");
        }
    }

    #[test]
    fn peers_show_as_their_initials_where_they_stand_and_nowhere_else() {
        let mut frame = Frame::filled(10, 5, Cell::plain('.'));
        // 1 unit per column, 2 per row, centred on (0, 0): column = x + 5, row = 2.5 - y / 2.
        let area = MapArea::whole(0, 0, 10, 5, 1.0, Vec2::ZERO);
        let peer = |x: f32, y: f32, initial: char| Peer {
            position: Vec2::new(x, y),
            heading_deg: 0.0,
            initial,
            color: Color::Indexed(196),
            cell: None,
        };
        let peers =
            [peer(-4.5, 4.0, 'a'), peer(100.0, 0.0, 'b'), peer(0.5, 0.5, 'c'), peer(2.5, 0.5, '\x1b')];
        draw_peers(&mut frame, &area, &peers, Vec2::new(0.5, 0.5), Style::default());
        // `b` is off the map, `c` stands on the viewer (whose arrow wins), the escape byte is a `?`.
        assert_eq!(frame.lines(), ["a.........", "..........", ".......?..", "..........", ".........."]);
        assert_eq!(frame.get(0, 0).map(|c| c.fg), Some(Color::Indexed(196)));
        assert!(area.shows(Vec2::new(-5.0, -4.9)) && !area.shows(Vec2::new(5.0, 0.0)));
    }

    #[test]
    fn arrows_follow_the_heading() {
        assert_eq!(heading_arrow(0.0), '→');
        assert_eq!(heading_arrow(90.0), '↑');
        assert_eq!(heading_arrow(-90.0), '↓');
        assert_eq!(heading_arrow(200.0), '←');
        assert_eq!(heading_arrow(44.0), '↗');
    }

    /// The HUD's fields as the walk makes them, at their longest.
    fn hud_fields() -> Vec<(u8, String)> {
        [
            (0, "(-116.3, -50.8) z-0.8"),
            (1, "heading 345° pitch -45°"),
            (2, "time 12:34.5"),
            (3, "57 fps 12345 B"),
            (4, "cell 1234 seen 567"),
            (5, "fov 120° persp sextant"),
            (6, "12.3 ms"),
        ]
        .map(|(p, t)| (p, t.to_string()))
        .to_vec()
    }

    // Bug: at narrow widths the HUD cut fields mid-number (`heading 3` for 345°, `z-0` for -0.8).
    #[test]
    fn the_hud_shows_whole_fields_only_the_least_important_left_out_first() {
        let fields = hud_fields();
        for width in 0..=140 {
            let line = hud_line(&fields, "? help ", width);
            assert_eq!(line.chars().count(), width, "{line:?}");
            assert_eq!(line.ends_with("? help "), width > 7, "help at the right end when it fits: {line:?}");
            let shown: Vec<&str> = line
                .trim_end_matches("? help ")
                .split("  ")
                .map(str::trim)
                .filter(|t| !t.is_empty())
                .collect();
            for text in &shown {
                assert!(
                    fields.iter().any(|(_, f)| f == text),
                    "width {width}: a cut field {text:?} in {line:?}"
                );
            }
            // (QA: `look ahead ? help` at 82 columns) the help stands two spaces off the fields
            if width > 7 && !shown.is_empty() {
                assert!(line.trim_end_matches("? help ").ends_with("  "), "width {width}: {line:?}");
            }
            // fields come in their order; one is left out only if it does not fit beside the more
            // important ones shown
            let order: Vec<usize> =
                shown.iter().map(|t| fields.iter().position(|(_, f)| f == t).unwrap()).collect();
            assert!(order.windows(2).all(|w| w[0] < w[1]), "{line:?}");
            let len = |i: usize| fields[i].1.chars().count() + 2;
            for left_out in (0..fields.len()).filter(|i| !order.contains(i)) {
                let before: usize = order.iter().filter(|&&i| i < left_out).map(|&i| len(i)).sum();
                assert!(1 + before + len(left_out) + 8 > width, "width {width}: {left_out} fits in {line:?}");
            }
        }
        assert_eq!(hud_line(&fields, "? help ", 32), " (-116.3, -50.8) z-0.8   ? help ");
        // heading no longer fits: the shorter clock, less important, does
        assert_eq!(hud_line(&fields, "? help ", 45), " (-116.3, -50.8) z-0.8  time 12:34.5  ? help ");
        assert!(hud_line(&fields, "? help ", 140).contains("fov 120° persp sextant  12.3 ms"));
    }

    /// `frame`'s rows, trimmed at the right.
    fn trimmed(frame: &Frame) -> Vec<String> {
        frame.lines().iter().map(|l| l.trim_end().to_string()).collect()
    }

    // Bug: at small sizes the help stopped early without the quit row, descriptions were cut mid-word
    // and the exit box read `You found the ex`, without "q quit".
    #[test]
    fn small_boxes_keep_the_first_lines_whole_words_and_say_what_is_left_out() {
        let style = Style::default();
        let mut frame = Frame::filled(20, 6, Cell::plain('.'));
        draw_box(&mut frame, "Keys (? to close)", &help_lines(style, false), style);
        assert_eq!(
            trimmed(&frame),
            [
                " Keys (? to close)",
                " q / Ctrl-C quit…",
                " ? / h this help…",
                " W / S walk…",
                " …",
                "...................."
            ]
        );
        let exit: Vec<String> =
            ["You found the exit in 0:05.0.", "", "r  walk it again", "q  quit"].map(String::from).to_vec();
        let mut frame = Frame::filled(20, 6, Cell::plain('.'));
        draw_box(&mut frame, "Found the exit!", &exit, style);
        assert_eq!(
            trimmed(&frame),
            [
                "  Found the exit!",
                " You found the…",
                " r  walk it again",
                " q  quit",
                "....................",
                "...................."
            ]
        );
        // every size: no word of a help row is cut, and some row tells of those left out
        for (w, h) in [(60, 15), (40, 12), (30, 8), (20, 6)] {
            let mut frame = Frame::filled(w, h, Cell::plain('.'));
            draw_box(&mut frame, "Keys", &help_lines(style, false), style);
            let words: Vec<&str> = HELP.iter().flat_map(|(k, d)| k.split(' ').chain(d.split(' '))).collect();
            let rows = trimmed(&frame);
            assert!(rows.iter().any(|r| r.trim() == "…"), "{w}×{h}: {rows:?}");
            for row in &rows[2..h - 2] {
                for word in row.split(' ').filter(|w| !w.is_empty()) {
                    let word = word.trim_end_matches('…');
                    assert!(word.is_empty() || words.contains(&word), "{w}×{h}: {word:?} in {row:?}");
                }
            }
        }
    }

    #[test]
    fn a_line_is_shortened_by_whole_words() {
        assert_eq!(fit_line("walk forward / back", 19, "…"), "walk forward / back");
        assert_eq!(fit_line("walk forward / back", 18, "…"), "walk forward /…");
        assert_eq!(fit_line("W / S      walk forward", 17, "…"), "W / S      walk…");
        assert_eq!(fit_line("W / S      walk forward", 15, "…"), "W / S walk…");
        assert_eq!(fit_line("W / S      walk forward", 14, "..."), "W / S walk...");
        assert_eq!(fit_line("Unbreakable", 5, "…"), "Unbr…");
    }

    #[test]
    fn hud_and_box_are_clipped_to_the_frame() {
        let mut frame = Frame::filled(12, 5, Cell::plain('.'));
        draw_hud(&mut frame, "a long heads-up line", Style::default());
        assert_eq!(frame.lines()[4], "a long heads");
        draw_box(&mut frame, "Help", &["one".to_string(), "two".to_string()], Style::default());
        let lines = frame.lines();
        // an 8×4 box (text + 2 padding each side) above the HUD's row: no room for the spacing rows
        assert_eq!(lines[0], "..  Help  ..");
        assert_eq!(lines[1], "..  one   ..");
        assert_eq!(lines[2], "..  two   ..");
        let mut tiny = Frame::new(1, 1);
        draw_box(&mut tiny, "Help", &help_lines(Style::default(), false), Style::default());
        draw_hud(&mut tiny, "x", Style::default());
    }

    #[test]
    fn without_colour_a_box_is_framed_and_with_ascii_everything_is_ascii() {
        let style = Style { depth: ColorDepth::None, ascii: true };
        let mut frame = Frame::filled(14, 6, Cell::plain('.'));
        draw_box(&mut frame, "Keys", &help_lines(style, false)[4..5], style);
        draw_hud(&mut frame, "heading 90° ← ×", style);
        let lines = frame.lines();
        assert_eq!(lines[0], "+------------+");
        assert_eq!(lines[1], "|    Keys    |");
        assert_eq!(lines[3], "|Left /...   |", "whole words, in ASCII");
        assert_eq!(lines[5], "heading 90 deg");
        assert!(lines.iter().all(|l| l.is_ascii()));
        assert!(
            frame.cells().iter().all(|c| c.fg == Color::Default && c.bg == Color::Default || c.bg == HUD_BG)
        );
        limit_colors(&mut frame, ColorDepth::None);
        assert!(frame.cells().iter().all(|c| c.fg == Color::Default && c.bg == Color::Default));
    }

    #[test]
    fn colours_are_limited_to_the_depth() {
        let mut frame = Frame::new(3, 1);
        frame.set(0, 0, Cell { ch: 'a', fg: Color::Rgb(200, 30, 30), bg: Color::Indexed(236) });
        frame.set(1, 0, Cell { ch: 'b', fg: Color::Indexed(9), bg: Color::Default });
        let mut f256 = frame.clone();
        limit_colors(&mut f256, ColorDepth::Ansi256);
        assert!(matches!(f256.cells()[0].fg, Color::Indexed(_)));
        assert_eq!(f256.cells()[0].bg, Color::Indexed(236));
        let mut f16 = frame.clone();
        limit_colors(&mut f16, ColorDepth::Ansi16);
        assert!(
            f16.cells().iter().all(|c| !matches!(c.fg, Color::Rgb(..)) && !matches!(c.bg, Color::Rgb(..)))
        );
        assert!(
            f16.cells()
                .iter()
                .all(|c| !matches!(c.fg, Color::Indexed(16..)) && !matches!(c.bg, Color::Indexed(16..)))
        );
        assert_eq!(f16.cells()[1].fg, Color::Indexed(9));
    }

    #[test]
    fn ascii_arrows_point_by_quadrant() {
        assert_eq!(ascii_arrow(0.0), '>');
        assert_eq!(ascii_arrow(90.0), '^');
        assert_eq!(ascii_arrow(180.0), '<');
        assert_eq!(ascii_arrow(-90.0), 'v');
        assert_eq!(ascii_arrow(44.0), '>');
    }
}
