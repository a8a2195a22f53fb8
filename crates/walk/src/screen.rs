//! One screen of the walk, composed: the 3D view, then the map, the boxes and the HUD over it, with
//! colours limited to the terminal's depth. Pure: the walk's state, what the host shows besides it
//! (other players, a notice) and the HUD's numbers in, a [`Frame`] out, so whole screens are tested
//! as text.
//!
//! ```text
//! App + Screen (peers, notice) + Hud ─draw─▶ Frame: view rows (Renderer) · map · box · HUD row
//! ```

use std::ops::Range;
use std::sync::Arc;

use glam::Vec3;

use crate::clock::{clock_text, running_clock_text};
use crate::overlay::{self, MapArea, MapCells, Peer, Style};
use crate::roster;
use crate::run::Pose;
use crate::state::{App, MapMode};
use crate::views::{SharedViews, ViewKey};
use mazewalk_render::palette::xterm_rgb;
use mazewalk_render::portal::PortalPass;
use mazewalk_render::{
    Camera, Charset, Culling, Projection, RenderOptions, RenderStats, Renderer, Sprite, Target,
};
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame, Region};

/// What the last frame cost, for the HUD.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameCost {
    /// Seconds the host measured making the previous frame (render + overlays + encode).
    pub seconds: f64,
    /// Bytes the previous frame sent.
    pub bytes: usize,
}

/// The numbers the HUD shows besides the viewer's own.
#[derive(Clone, Copy, Debug, Default)]
pub struct Hud {
    /// What the previous frame cost.
    pub cost: FrameCost,
    /// Frames actually drawn over the last second (this one included).
    pub fps: usize,
    /// Seconds since the walk (re)started, for the clock of a maze with an exit.
    pub elapsed: f64,
    /// The host's time now (seconds), for the player list's times.
    pub now: f64,
}

/// The buffers one screen is drawn with, reused from frame to frame, and what a host shows besides the
/// walk itself.
#[derive(Debug, Default)]
pub struct Screen {
    /// The pipeline and its buffers.
    pub renderer: Renderer,
    /// The link is slow ([`slow_link`](crate::session::slow_link)): no dithering, whatever the options
    /// say.
    pub slow_link: bool,
    /// Other players in the same maze (`mazewalk serve`), drawn in the view and on the map.
    pub peers: Vec<Peer>,
    /// A message for everyone (e.g. who reached the exit first), shown in a box until taken away.
    pub notice: Option<String>,
    /// Everyone in a served maze, for the player list (`Tab`); empty when not served.
    pub roster: Vec<roster::Entry>,
    /// The player list is open.
    pub show_roster: bool,
    /// How many players walk the maze (`mazewalk serve`), for the HUD ("3 in").
    pub players_in: Option<usize>,
    /// A host's word on its own state for the HUD, right after the heading (e.g. "world offline"
    /// while a shared world's Redis is away).
    pub status: Option<String>,
    /// More lines for the exit box (a served maze's best times).
    pub standings: Vec<String>,
    /// Where the last frame's map was drawn.
    pub map: Option<MapArea>,
    /// A host's own key help, shown by `?` instead of the walk's (a spectator's keys); empty: the
    /// walk's.
    pub help: Vec<String>,
    /// The page of the walk's own help shown ([`overlay::help_pages`]: where it does not fit whole).
    pub help_page: usize,
    /// How many pages the walk's help had in the last frame (1 when it fit whole, or did not show).
    pub help_pages: usize,
    /// What the player list's header says closes it; empty: [`roster::CLOSE_HINT`] (a player's `Tab`).
    pub roster_hint: String,
    /// Views shared with other screens ([`SharedViews`]: a server's spectators of one player); `None`:
    /// this screen renders its own.
    pub shared_views: Option<Arc<SharedViews>>,
    /// A stored run's ghost where it is now (`None`: none shown), and its label ("ghost ada 1:40.4").
    pub ghost: Option<(Pose, String)>,
    /// What the last frame's render did (the HUD's developer figures).
    stats: RenderStats,
    /// The peers as the renderer's figures (reused from frame to frame).
    sprites: Vec<Sprite>,
    /// What the map's characters show, kept while the map stays put.
    map_cells: MapCells,
    /// What the open exit box shows besides the time, held until it closes.
    exit_news: ExitNews,
    /// The last view this screen's own renderer drew, kept to be shown again while nothing it is
    /// drawn from changed.
    last_view: Option<LastView>,
    /// Views this screen's own renderer drew (a view shown again from `last_view` is not one).
    renders: u64,
    /// The frame last drawn into by [`draw_kept`] still holds `last_view` but under its patch.
    kept: bool,
    /// What the HUD's row shows and what it was made of, for a clock tick ([`draw_hud`]).
    hud: HudMemo,
}

/// The HUD's row as [`draw_hud`] last drew it: its text, what it was made of but the clock, and where
/// the clock's field stands in it. A clock tick with nothing else changed (an idle player's each
/// second) writes the clock's new digits over the old instead of formatting and fitting the whole
/// line again (BENCHMARKS, "An idle player's clock tick").
#[derive(Debug, Default)]
struct HudMemo {
    /// What the line was made of, but the clock (`None`: nothing to go by).
    key: Option<HudKey>,
    /// The line as drawn, `width` columns.
    line: String,
    /// The clock's field: its first column in the row and its text (`time 1:23`); `None` where the
    /// line has no clock (no exit, or no room for it).
    clock: Option<(usize, String)>,
}

/// Everything the HUD's line is made of but the clock's text ([`hud_text_placed`]'s inputs), compared
/// whole: equal keys and clock texts of one length make lines alike but for the clock's digits.
/// (Without the developer figures, which change every frame: with them, no key is made.)
#[derive(Debug, PartialEq)]
struct HudKey {
    /// Heading, position x and y, eye height, pitch and field of view, as bits.
    camera: [u32; 6],
    projection: Projection,
    charset: Charset,
    look_ahead: bool,
    /// The finish time (bits) or none, whether the clock is unknown, whether the maze has an exit.
    clock: (Option<u64>, bool, bool),
    players_in: Option<usize>,
    status: Option<String>,
    ghost: Option<String>,
    own_keys: bool,
    style: Style,
    /// The frame's width and height.
    size: (usize, usize),
}

/// A view as this screen's renderer drew it, before anything was drawn over it: a pure function of
/// its key (see [`crate::views`]), so while the key stays the same, bit for bit, its cells are the
/// render's (the map, a box or the HUD changing alone renders nothing). The renderer's own state (its
/// portal pass, samples and figures' heads, read by the map and the ghost's caption) is still this
/// render's: nothing else renders with it meanwhile.
///
/// Of the figures, only those in a cell the render's portal pass reached (all, without culling) are
/// drawn ([`Renderer::render`]), and with the camera the same so is the pass: the key holds no
/// figures, `figures` those (with their places in the list, which the heads name) and `sprites` how
/// many there were. Another player walking where the view does not reach moves on the map only.
///
/// Its cells are kept whole (`whole`), or, drawn with [`draw_kept`] (a frame kept between frames: a
/// session's), only those under what was drawn over the view (`patch`, the map's box): the frame's
/// other view cells are still the render's.
#[derive(Debug)]
struct LastView {
    key: ViewKey,
    figures: Vec<(usize, Sprite)>,
    sprites: usize,
    cells: Vec<Cell>,
    /// `cells` is the whole view; else the cells of `patch`, row by row (none without a patch).
    whole: bool,
    /// The part of the view drawn over (the map), whose cells `cells` holds when not `whole`.
    patch: Option<Region>,
    stats: RenderStats,
}

impl LastView {
    /// Whether `sprites` draw in this view what its own did: as many, and the same ones, bit for bit,
    /// where `visible` (the render's portal pass) says a figure shows.
    fn same_figures(&self, sprites: &[Sprite], visible: impl Fn(u32) -> bool) -> bool {
        let bits =
            |s: &Sprite| [s.position.x, s.position.y, s.color.x, s.color.y, s.color.z].map(f32::to_bits);
        let mut shown = sprites.iter().enumerate().filter(|(_, s)| visible(s.cell));
        self.sprites == sprites.len()
            && self
                .figures
                .iter()
                .all(|(k, a)| shown.next().is_some_and(|(j, b)| *k == j && a == b && bits(a) == bits(b)))
            && shown.next().is_none()
    }
}

/// The host's lines in the exit box, held from when the box opens until it closes (issue #39: the box
/// lost its "first" line when the host took the notice away, mid-read): the notice and the standings
/// as each first came while the box was open, whatever the host says later.
#[derive(Debug, Default)]
struct ExitNews {
    notice: Option<String>,
    standings: Vec<String>,
}

impl ExitNews {
    /// Takes what the host shows now where nothing is held yet; `open`: whether the exit box is open
    /// (closed, nothing is held).
    fn update(&mut self, open: bool, notice: Option<&String>, standings: &[String]) {
        if !open {
            *self = ExitNews::default();
            return;
        }
        if self.notice.is_none() {
            self.notice = notice.cloned();
        }
        if self.standings.is_empty() {
            self.standings = standings.to_vec();
        }
    }
}

/// A peer as the renderer draws it: a figure in the peer's colour with its initial, standing in its
/// cell (the one the peer says, else the one under it; `None` when it stands in no cell).
fn figure(maze: &mazewalk_maze::Maze, peer: &Peer) -> Option<Sprite> {
    let cell =
        peer.cell.filter(|&c| (c as usize) < maze.cell_count()).or_else(|| maze.cell_at(peer.position))?;
    let rgb = match peer.color {
        Color::Rgb(r, g, b) => [r, g, b],
        Color::Indexed(i) => xterm_rgb(i),
        Color::Default => [200, 200, 200],
    };
    let color = Vec3::from_array(rgb.map(|c| f32::from(c) / 255.0));
    Some(Sprite { position: peer.position, cell, color, label: peer.initial, ghost: false })
}

/// Draws the whole screen for the current state into `frame` (its size is the terminal's): the 3D
/// view, then the map, the HUD and any box. Pure: no I/O, so screens are tested as text.
pub fn draw(app: &App, screen: &mut Screen, frame: &mut Frame, hud: &Hud) -> RenderStats {
    draw_into(app, screen, frame, hud, false)
}

/// [`draw`] into the frame drawn into last time, which its owner kept as it was left but for its HUD
/// row (a session's own frame; after anything else, [`Screen::forget_frame`]): a view shown again
/// restores only what was drawn over it, and a view rendered keeps only the cells the map covers,
/// not a copy of the whole view (56 KB at 120×40).
pub(crate) fn draw_kept(app: &App, screen: &mut Screen, frame: &mut Frame, hud: &Hud) -> RenderStats {
    draw_into(app, screen, frame, hud, true)
}

fn draw_into(app: &App, screen: &mut Screen, frame: &mut Frame, hud: &Hud, keep: bool) -> RenderStats {
    // the frame holds the last view but under its patch (cleared now: set again at the end)
    let kept = keep && std::mem::take(&mut screen.kept);
    // the view drawn by this screen's own renderer (not a shared one): `last_view` is the frame's
    let own = screen.shared_views.is_none();
    let (cols, rows) = (frame.width(), frame.height());
    let style = Style::new(app.options.charset, app.options.color_depth);
    if overlay::too_small(cols, rows) {
        (screen.map, screen.stats, screen.help_pages) = (None, RenderStats::default(), 1);
        overlay::draw_too_small(frame, style);
        return RenderStats::default();
    }
    // The bottom row is the HUD; the 3D view gets the rest, drawn in place.
    let view = Region { col: 0, row: 0, cols, rows: rows - 1 };
    let options = RenderOptions { dither: app.options.dither && !screen.slow_link, ..app.options };
    // The other players, as figures standing in the maze.
    screen.sprites.clear();
    screen.sprites.extend(screen.peers.iter().filter_map(|peer| figure(app.maze(), peer)));
    let ghost_sprite = screen.sprites.len();
    if let Some((pose, caption)) = &screen.ghost
        && let Some(cell) = app.maze().cell_at(pose.position)
    {
        let label = caption.strip_prefix("ghost ").and_then(|c| c.chars().next()).unwrap_or('?');
        let color = Vec3::new(0.78, 0.92, 1.0); // a pale blue: no player's colour
        screen.sprites.push(Sprite { position: pose.position, cell, color, label, ghost: true });
    }
    let drawn = match &screen.shared_views {
        // drawn once for every screen with the same key, copied into this one's view rows
        Some(views) => {
            let key = ViewKey::new(app.maze(), &app.camera, &screen.sprites, &options, (cols, view.rows))
                .with_chalk(app.chalked());
            views.view(app.maze(), &key, &mut screen.renderer).map(|shared| {
                frame.cells_mut()[..cols * view.rows].copy_from_slice(shared.frame.cells());
                shared.stats
            })
        }
        None => {
            let size = (cols, view.rows);
            let cells = cols * view.rows;
            let portal = screen.renderer.portal();
            let visible = |cell: u32| options.culling == Culling::None || portal.was_visited(cell);
            match &screen.last_view {
                Some(last)
                    if last.key.is(app.maze(), &app.camera, &[], &options, size, app.chalked())
                        && last.same_figures(&screen.sprites, visible)
                        && (last.whole || kept) =>
                {
                    if last.whole {
                        frame.cells_mut()[..cells].copy_from_slice(&last.cells);
                    } else if let Some(patch) = last.patch {
                        let under = last.cells.chunks_exact(patch.cols);
                        frame
                            .region_rows_mut(patch)
                            .zip(under)
                            .for_each(|(row, kept)| row.copy_from_slice(kept));
                    }
                    Ok(last.stats)
                }
                _ => {
                    screen.renders += 1;
                    screen.renderer.set_chalk(app.chalked());
                    let drawn = screen.renderer.render(
                        app.maze(),
                        &app.camera,
                        &screen.sprites,
                        &options,
                        Target::Frame(frame, view),
                    );
                    screen.last_view = drawn.as_ref().ok().map(|&stats| {
                        let mut last = screen.last_view.take().unwrap_or(LastView {
                            key: ViewKey::new(app.maze(), &app.camera, &[], &options, size),
                            figures: Vec::new(),
                            sprites: 0,
                            cells: Vec::new(),
                            whole: false,
                            patch: None,
                            stats,
                        });
                        let portal = screen.renderer.portal();
                        let visible =
                            |cell: u32| options.culling == Culling::None || portal.was_visited(cell);
                        last.key = ViewKey::new(app.maze(), &app.camera, &[], &options, size)
                            .with_chalk(app.chalked());
                        last.figures.clear();
                        last.figures.extend(
                            screen.sprites.iter().copied().enumerate().filter(|(_, s)| visible(s.cell)),
                        );
                        last.sprites = screen.sprites.len();
                        last.cells.clear();
                        if !keep {
                            last.cells.extend_from_slice(&frame.cells()[..cells]);
                        }
                        (last.whole, last.patch) = (!keep, None);
                        last.stats = stats;
                        last
                    });
                    drawn
                }
            }
        }
    };
    // Whether anything but the map and the HUD was drawn over the view (a box, a caption, the
    // player list): the view as rendered is within the terminal's depth already (the renderer
    // draws to it), so only what is drawn over it needs its colours limited.
    let mut over_view = false;
    let stats = match drawn {
        Ok(stats) => stats,
        Err(err) => {
            frame.fill(Cell::BLANK);
            overlay::draw_box(frame, "Cannot draw", &[err.to_string()], style);
            over_view = true;
            RenderStats::default()
        }
    };
    let exit_box = app.finished.filter(|_| app.exit_box);
    let roster_open = screen.show_roster && !screen.roster.is_empty() && !app.confirm_quit;
    let caption = screen.ghost.is_some() && screen.renderer.heads().iter().any(|h| h.0 == ghost_sprite);
    let boxed = exit_box.is_some() || app.confirm_quit || app.help || screen.notice.is_some() || roster_open;
    let marks = if app.look_ahead() {
        range_marks(app.maze(), &app.camera, app.cell, &options, view)
    } else {
        Vec::new()
    };
    let marked = !marks.is_empty();
    if let Some(last) =
        screen.last_view.as_mut().filter(|last| own && !last.whole && (caption || boxed || marked))
    {
        // drawn over more than the map: the whole view is kept (the frame holds it, as rendered)
        last.cells.clear();
        last.cells.extend_from_slice(&frame.cells()[..cols * view.rows]);
        (last.whole, last.patch) = (true, None);
    }
    if let Some((_, caption)) = &screen.ghost
        && let Some(&(_, col, row)) = screen.renderer.heads().iter().find(|h| h.0 == ghost_sprite)
    {
        draw_caption(frame, view, col, row, &style.text(caption));
        over_view = true;
    }
    over_view |= marked;
    put_range_marks(frame, &marks, view, style.depth);
    frame.region_rows_mut(Region { row: rows - 1, rows: 1, ..view }).for_each(|hud| hud.fill(Cell::BLANK));
    // Cells visible in this frame: the portal pass's (with brute force it did not run: none new).
    let portal = screen.renderer.portal();
    let visible_now = |c: u32| app.options.culling == Culling::Portal && portal.was_visited(c);
    let seen = seen_now(app, portal);
    let tint: Option<&dyn Fn(u32) -> bool> = app.culling_tint.then_some(&visible_now);
    screen.map = map_area(app, frame).map(|area| match app.map {
        // the corner map: what has been seen, not a box of black over the view
        MapMode::Corner => {
            let also = std::iter::once(app.camera.position).chain(screen.peers.iter().map(|p| p.position));
            // (kept while the seen cells and the area stay: none in view but seen already)
            let key = (!fresh_in_view(app, portal)).then(|| (app.seen_id(), app.reveal_map));
            area.fit_to_seen(app.maze(), &seen, also, &mut screen.map_cells, key)
        }
        _ => area,
    });
    if let Some(last) = screen.last_view.as_mut().filter(|last| own && !last.whole) {
        // only the map over the view: the cells under it are kept (the frame holds the others)
        let patch = screen.map.map(|area| Region {
            col: area.x,
            row: area.y,
            cols: area.width.min(cols.saturating_sub(area.x)),
            rows: area.height.min(view.rows.saturating_sub(area.y)),
        });
        let patch = patch.filter(|p| p.cols > 0 && p.rows > 0);
        last.cells.clear();
        if let Some(patch) = patch {
            frame.region_rows_mut(patch).for_each(|row| last.cells.extend_from_slice(row));
        }
        last.patch = patch;
    }
    if let Some(area) = &screen.map {
        // the view's wedge as wide as the view drawn (a generated maze's widens on a wide screen)
        let shown = Camera { hfov_deg: app.shown_hfov_deg(cols, rows - 1), ..app.camera };
        overlay::draw_map(frame, area, app.maze(), &shown, &seen, tint, style, &mut screen.map_cells);
        overlay::draw_peers(frame, area, &screen.peers, app.camera.position, style);
        if let Some((pose, _)) = &screen.ghost {
            overlay::draw_ghost(frame, area, pose.position, app.camera.position, style);
        }
    }
    screen.exit_news.update(exit_box.is_some(), screen.notice.as_ref(), &screen.standings);
    over_view |= boxed;
    let mut help_pages = 1;
    if let Some(seconds) = exit_box {
        // in a served maze, the news (who was first) shows in the box too, not hidden behind it
        let news = &screen.exit_news;
        let lines: Vec<String> = [format!("You found the exit in {}.", clock_text(seconds))]
            .into_iter()
            .chain(news.notice.clone())
            .chain(news.standings.iter().cloned())
            .chain([
                String::new(),
                "r    walk it again".to_string(),
                "q    quit".to_string(),
                "any  walk on".to_string(),
            ])
            .collect();
        overlay::draw_box(frame, "Found the exit!", &lines, style);
    } else if app.confirm_quit {
        let lines = ["q    quit".to_string(), "any  walk on".to_string()];
        overlay::draw_box(frame, "Quit?", &lines, style);
    } else if roster_open {
        // asked for: instead of the other boxes (drawn over one, the wider box's edges showed on
        // either side of it as stray characters), which come back when it closes
        let hint = if screen.roster_hint.is_empty() { roster::CLOSE_HINT } else { &screen.roster_hint };
        roster::draw(frame, &screen.roster, hud.now, hint, style);
    } else if app.help {
        let title = "Keys (? or Esc to close)";
        if screen.help.is_empty() {
            // a served player (with a player list) has the list's key, and no Ctrl-Z nor developer keys
            let served = !screen.roster.is_empty() || !app.developer_keys;
            let lines = overlay::help_lines_for(style, app.maze().exit().is_some(), served);
            let pages = overlay::help_pages(&lines, (cols, rows));
            help_pages = pages.len();
            screen.help_page = screen.help_page.min(pages.len() - 1);
            overlay::draw_box(frame, title, &pages[screen.help_page], style);
        } else {
            overlay::draw_box(frame, title, &screen.help, style);
        }
    } else if let Some(notice) = &screen.notice {
        overlay::draw_box(frame, "News", std::slice::from_ref(notice), style);
    }
    // Space and PgDn turn its pages only while it shows (under another box, they are that box's)
    screen.help_pages = help_pages;
    if !app.help {
        screen.help_page = 0; // opened again, it starts at its first page
    }
    screen.stats = stats;
    drop(seen); // (it reads the renderer's portal pass: done with before the HUD's memo is written)
    let _ = draw_hud(app, screen, frame, hud); // last: boxes never hide it (its row's colours limited there)
    // Not one code deeper than the terminal's depth: of what was drawn over the view, or of the map
    // alone (its walls, wedge and arrow change as the player turns; the view's cells need no look).
    if over_view {
        overlay::limit_colors(frame, style.depth);
    } else if let Some(area) = &screen.map {
        let map = Region { col: area.x, row: area.y, cols: area.width, rows: area.height };
        overlay::limit_colors_in(frame, map, style.depth);
    }
    screen.kept = keep && own;
    stats
}

impl Screen {
    /// The frame [`draw_kept`] drew into last was changed otherwise (resized, cleared): the next
    /// draw takes nothing from it.
    pub(crate) fn forget_frame(&mut self) {
        self.kept = false;
    }

    /// Views this screen's own renderer drew so far: frames whose view was shown again unchanged
    /// (only the map, a box or the HUD changed) and views shared with other screens are not counted.
    #[must_use]
    pub fn renders(&self) -> u64 {
        self.renders
    }
}

/// A ghost's caption over its head at (`col`, `row`) of the frame: on the row above, centred, kept
/// inside the view (on the head's row when the head is on the view's top row).
fn draw_caption(frame: &mut Frame, view: Region, col: usize, row: usize, caption: &str) {
    let width = caption.chars().count().min(view.cols);
    let row = if row > view.row { row - 1 } else { row + 1 };
    if row >= view.row + view.rows || width == 0 {
        return;
    }
    let left = col.saturating_sub(width / 2).clamp(view.col, view.col + view.cols - width);
    for (k, ch) in caption.chars().take(width).enumerate() {
        frame.set(left + k, row, Cell { ch, fg: overlay::GHOST_FG, bg: Color::Indexed(0) });
    }
}

/// The look-ahead lens's range marks ([`range_marks`]) of the view `camera` has from `cell` of
/// `maze`, drawn over `view` of `frame` as the walk draws them with the lens on (`z`): for `mazewalk
/// render --look-ahead`. Returns whether any was drawn.
pub fn draw_range_marks(
    frame: &mut Frame,
    (maze, camera, cell): (&mazewalk_maze::Maze, &Camera, u32),
    options: &RenderOptions,
    view: Region,
) -> bool {
    let marks = range_marks(maze, camera, cell, options, view);
    put_range_marks(frame, &marks, view, options.color_depth);
    // (their colour within the frame's depth, as the walk limits what it draws over the view)
    overlay::limit_colors_in(frame, view, options.color_depth);
    !marks.is_empty()
}

/// `marks` (text, row) on `view`'s left edge, each on its floor cell line's row: a rangefinder's
/// scale, light on black (the terminal's own colours without colour).
fn put_range_marks(frame: &mut Frame, marks: &[(String, usize)], view: Region, depth: ColorDepth) {
    let (fg, bg) = if depth == ColorDepth::None {
        (Color::Default, Color::Default)
    } else {
        (overlay::RANGE_FG, Color::Indexed(0))
    };
    for (text, row) in marks {
        for (x, ch) in (view.col..view.col + view.cols).zip(text.chars()) {
            frame.set(x, *row, Cell { ch, fg, bg });
        }
    }
}

/// Cells a line's range mark counts at most: one digit.
const RANGE_MARKS: usize = 9;

/// Cells the ray of the range marks crosses at most, looking for the wall that ends it.
const RANGE_CELLS: usize = 99;

/// The look-ahead lens's range marks (issue #39: a new player through the lens counted corridors a
/// cell short, as the nearest cell line it shows lies on the frame's edge), as (text, row of
/// `view`): where the floor straight ahead crosses into the k-th cell ahead (the cell line drawn
/// there), the digit k on that line's row, up to [`RANGE_MARKS`], for lines in the view, until one
/// would share the row of the one before (lines crowd toward the horizon); then, where a wall ends
/// the way straight ahead with its foot in the view, `n|` on that row, n the cells crossed to it:
/// the corridor's length beyond the viewer's cell (it takes the row of a line's digit it falls on;
/// a wall so near its foot is below the view, nose to it, marks the bottom row: `0|` in the viewer's
/// own cell). Without that end in view, a last digit with more lines beyond it reads `k+`.
fn range_marks(
    maze: &mazewalk_maze::Maze,
    camera: &Camera,
    cell: u32,
    options: &RenderOptions,
    view: Region,
) -> Vec<(String, usize)> {
    use mazewalk_maze::geometry::{FLOOR_Z, heading_dir};
    let (per_col, per_row) = options.charset.samples_per_cell();
    let aspect = options.charset.sample_aspect(options.cell_aspect);
    let Ok(eye) = camera.eye(view.cols * per_col, view.rows * per_row, aspect) else { return Vec::new() };
    // the view's row of a point on the floor, if it is in the view
    let row_of = |at: glam::Vec2| {
        let clip = eye.clip(at.extend(FLOOR_Z));
        let y = eye.grid(clip).y;
        (clip.w > eye.near && (0.0..(view.rows * per_row) as f32).contains(&y))
            .then(|| view.row + y as usize / per_row)
    };
    let dir = heading_dir(camera.yaw_deg.to_radians());
    let (crossings, end) = cells_ahead(maze, cell, camera.position, dir);
    let mut marks: Vec<(String, usize)> = Vec::new();
    let mut more = false;
    for (k, &at) in crossings.iter().enumerate().map(|(k, at)| (k + 1, at)) {
        let Some(row) = row_of(at) else { continue }; // below the view (the nearest lines)
        if k > RANGE_MARKS || marks.last().is_some_and(|&(_, last)| row >= last) {
            more = true; // crowded toward the horizon: the rest would share rows
            break;
        }
        marks.push((k.to_string(), row));
    }
    // (an end wall nearer than the lowest floor the lens shows, its foot below the view or behind
    // the eye's near plane: its mark on the view's bottom row, where no line's can be)
    let below = |at: glam::Vec2| {
        let clip = eye.clip(at.extend(FLOOR_Z));
        (clip.w <= eye.near || eye.grid(clip).y >= (view.rows * per_row) as f32)
            .then_some(view.row + view.rows - 1)
    };
    match end.and_then(|at| row_of(at).or_else(|| below(at))) {
        Some(row) => {
            marks.retain(|&(_, r)| r > row);
            marks.push((format!("{}|", crossings.len()), row));
        }
        None if more => {
            if let Some((text, _)) = marks.last_mut() {
                text.push('+');
            }
        }
        None => {}
    }
    marks
}

/// Where a ray on the floor from `at` (in `cell`) along `dir` crosses into each next cell through an
/// opening, nearest first ([`RANGE_CELLS`] at most), and where it meets the wall that ends it (`None`
/// where it leaves the maze, or past those cells).
fn cells_ahead(
    maze: &mazewalk_maze::Maze,
    mut cell: u32,
    at: glam::Vec2,
    dir: glam::Vec2,
) -> (Vec<glam::Vec2>, Option<glam::Vec2>) {
    let mut out = Vec::new();
    let mut from = 0.0f32;
    while out.len() < RANGE_CELLS {
        // the edge of this cell the ray leaves by: the nearest crossing past the last one
        let leave = maze
            .cell_edges(cell)
            .iter()
            .filter_map(|&e| {
                let (a, b) = maze.edge_points(e);
                let (side, denom) = (b - a, dir.perp_dot(b - a));
                if denom.abs() < 1e-9 {
                    return None; // along the edge
                }
                let t = (a - at).perp_dot(side) / denom; // along the ray
                let s = (a - at).perp_dot(dir) / denom; // along the edge
                (t > from + 1e-4 && (-1e-4..=1.0 + 1e-4).contains(&s)).then_some((t, e))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let Some((t, e)) = leave else { break };
        let edge = maze.edge(e);
        if edge.opaque {
            return (out, Some(at + dir * t));
        }
        let Some(next) = edge.other_side(cell) else { break };
        out.push(at + dir * t);
        (cell, from) = (next, t);
    }
    (out, None)
}

/// Draws the HUD's row of `frame` only, over what [`draw`] drew last: when nothing but the HUD's
/// numbers changed (the exit clock ticked), the view need not be rendered again. Returns the cells
/// it drew (indices into [`Frame::cells`]: the row, the clock's digits alone on a tick, none on a
/// screen too small for a HUD): the only ones of `frame` it changes.
pub(crate) fn draw_hud(app: &App, screen: &mut Screen, frame: &mut Frame, hud: &Hud) -> Range<usize> {
    let (cols, rows) = (frame.width(), frame.height());
    if overlay::too_small(cols, rows) {
        screen.hud = HudMemo::default();
        return 0..0; // the too-small note has no HUD
    }
    let style = Style::new(app.options.charset, app.options.color_depth);
    // the ghost raced, or that there is none to race: yet (served: the first finish makes one), or
    // without a run to race (the local walk: `--ghost FILE` names one)
    let none = if screen.players_in.is_some() { "no ghost yet" } else { "no ghost (--ghost FILE)" };
    let ghost = match &screen.ghost {
        Some((_, caption)) => Some(caption.as_str()),
        None => app.ghost.then_some(none),
    };
    let fov = app.shown_hfov_deg(cols, rows - 1);
    let host = (screen.players_in, screen.status.as_deref(), ghost, screen.help.is_empty());
    let clock = clock_field(app, hud);
    let row = Region { col: 0, row: rows - 1, cols, rows: 1 };
    // A tick of the clock alone: its digits written over the old ones, the rest of the row as it is.
    // (without the developer figures, which change every frame: with them, no key is kept)
    let key = (!app.figures).then(|| hud_key(app, host, fov, style, (cols, rows)));
    let memo = &mut screen.hud;
    if let (Some(_), Some((column, shown)), Some(clock)) = (&key, &mut memo.clock, &clock)
        && shown.len() == clock.len()
        && memo.key == key
        && frame.row(rows - 1).is_some_and(|cells| cells.iter().map(|c| c.ch).eq(memo.line.chars()))
    {
        for (x, ch) in (*column..).zip(clock.chars()) {
            if let Some(cell) = frame.get_mut(x, rows - 1) {
                cell.ch = ch; // (its colours: the HUD's, limited to the depth when the line was drawn)
            }
        }
        let at = memo.line.char_indices().nth(*column).map_or(memo.line.len(), |(i, _)| i);
        memo.line.replace_range(at..at + shown.len(), clock);
        shown.clone_from(clock);
        let first = (rows - 1) * cols + *column;
        return first..(first + clock.chars().count()).min(rows * cols);
    }
    let (line, clock_at) = hud_text_placed(app, &screen.stats, hud, host, fov, style, cols);
    #[cfg(test)]
    HUD_LINES_MADE.with(|n| n.set(n.get() + 1));
    overlay::draw_hud(frame, &line, style);
    overlay::limit_colors_in(frame, row, style.depth);
    screen.hud = HudMemo {
        key,
        clock: clock_at.zip(clock).map(|(at, text)| (line[..at].chars().count(), text)),
        line,
    };
    (rows - 1) * cols..rows * cols
}

#[cfg(test)]
thread_local! {
    /// HUD lines [`draw_hud`] made whole on this thread (not a clock's digits written in place).
    static HUD_LINES_MADE: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The HUD's inputs but the clock, as [`HudKey`] holds them.
type HudHost<'a> = (Option<usize>, Option<&'a str>, Option<&'a str>, bool);

/// The [`HudKey`] of a HUD line drawn of these.
fn hud_key(app: &App, host: HudHost, fov: f32, style: Style, size: (usize, usize)) -> HudKey {
    let c = &app.camera;
    let (players_in, status, ghost, own_keys) = host;
    HudKey {
        camera: [c.yaw_deg, c.position.x, c.position.y, c.eye_z, c.pitch_deg, fov].map(f32::to_bits),
        projection: c.projection,
        charset: app.options.charset,
        look_ahead: app.look_ahead(),
        clock: (app.finished.map(f64::to_bits), app.clock_unknown, app.maze().exit().is_some()),
        players_in,
        status: status.map(str::to_string),
        ghost: ghost.map(str::to_string),
        own_keys,
        style,
        size,
    }
}

/// Whether a cell has been seen, the cells `portal` (the last render's pass) visited counted: a
/// cell seen before or in view now. The map's probes ask this of ~3,000 cells a frame, mostly seen
/// or far; the pass's cells are looked up only when one of them was not seen before (after a frame
/// the session marks them seen: a walker turning where it has looked already has none).
fn seen_now<'a>(app: &'a App, portal: &'a PortalPass) -> impl Fn(u32) -> bool + 'a {
    let fresh = fresh_in_view(app, portal);
    move |c: u32| app.has_seen(c) || (fresh && portal.was_visited(c))
}

/// Whether a cell `portal` visited (in view now) was not seen before.
fn fresh_in_view(app: &App, portal: &PortalPass) -> bool {
    app.options.culling == Culling::Portal && portal.visited.iter().any(|&c| !app.has_seen(c))
}

/// Where the map goes on `frame` for the walk's map mode (`None`: no map): the whole area, before the
/// corner map is fitted to what it shows.
pub(crate) fn map_area(app: &App, frame: &Frame) -> Option<MapArea> {
    if overlay::too_small(frame.width(), frame.height()) {
        return None; // only the too-small message is drawn
    }
    match app.map {
        MapMode::Off => None,
        MapMode::Corner => Some(MapArea::corner(frame, app.camera.position)),
        MapMode::Full => Some(MapArea::full(frame, app.maze(), app.camera.position)),
    }
}

/// The HUD line without a host's status (the tests' shorthand).
#[cfg(test)]
fn hud_text(
    app: &App,
    stats: &RenderStats,
    hud: &Hud,
    players_in: Option<usize>,
    style: Style,
    width: usize,
) -> String {
    hud_text_with(app, stats, hud, (players_in, None, None, true), app.camera.hfov_deg, style, width)
}

/// The HUD line (see [`hud_text_placed`]).
#[cfg(test)]
fn hud_text_with(
    app: &App,
    stats: &RenderStats,
    hud: &Hud,
    host: HudHost,
    fov_deg: f32,
    style: Style,
    width: usize,
) -> String {
    hud_text_placed(app, stats, hud, host, fov_deg, style, width).0
}

/// The HUD's clock field: the time since the start (`time 1:23`), or the finish (`exit in 1:40.4`);
/// none without an exit, or with the start unknown.
fn clock_field(app: &App, hud: &Hud) -> Option<String> {
    match (app.maze().exit(), app.finished) {
        (None, _) => None,
        _ if app.clock_unknown => None,
        (Some(_), Some(took)) => Some(format!("exit in {}", clock_text(took))),
        (Some(_), None) => Some(format!("time {}", running_clock_text(hud.elapsed))),
    }
}

/// The HUD line, `width` columns at most: what a player needs first — a host's status when it has
/// one ("world offline"), which way they face (heading and compass point), the exit clock, how many
/// players are in (a served maze) —, then where they are, the view settings and, with [`App::figures`], the developer figures (frames per second,
/// bytes, cell, cells seen, ms): each only if it fits whole, and "? help" always at the right end.
/// Also where the clock's field ([`clock_field`]) starts in it (a byte offset), where it is shown.
fn hud_text_placed(
    app: &App,
    stats: &RenderStats,
    hud: &Hud,
    (players_in, status, ghost, own_keys): HudHost,
    fov_deg: f32,
    style: Style,
    width: usize,
) -> (String, Option<usize>) {
    const HELP: &str = "? help ";
    let c = &app.camera;
    let projection = match c.projection {
        Projection::Perspective => "persp",
        Projection::Orthographic => "ortho",
    };
    // (formatted only when shown: most frames do not show them)
    let dev = |text: &dyn Fn() -> String| if app.figures { text() } else { String::new() };
    let charset = app.options.charset;
    // the look-ahead lens (`z`) is said early: a player who forgets it is on sees a far narrower view
    let (lens, view) = if app.look_ahead() {
        (format!("fov {fov_deg:.0}° look ahead"), format!("{projection} {charset}"))
    } else {
        (String::new(), format!("fov {fov_deg:.0}° {projection} {charset}"))
    };
    // (priority, text): lower numbers are kept first when the line is short of room
    let fields = [
        (0, status.unwrap_or_default().to_string()),
        (0, format!("heading {:.0}° {}", c.yaw_deg, compass_point(c.yaw_deg))),
        (1, clock_field(app, hud).unwrap_or_default()),
        (2, players_in.map(|n| format!("{n} in")).unwrap_or_default()),
        (2, ghost.unwrap_or_default().to_string()),
        // (position, height and pitch apart: each fits where they together would not)
        (3, format!("({:.1}, {:.1})", c.position.x, c.position.y)),
        (5, format!("z{:+.1}", c.eye_z)),
        (6, format!("pitch {:+.0}°", c.pitch_deg)),
        (2, lens),
        (7, view),
        (4, dev(&|| format!("{} fps {} B", hud.fps, hud.cost.bytes))),
        (8, dev(&|| format!("cell {} seen {}", app.cell, stats.portal.distinct_cells))),
        (9, dev(&|| format!("{:.1} ms", hud.cost.seconds * 1e3))),
    ];
    // fitted as shown (in ASCII a degree sign takes four columns)
    let (line, at) = overlay::hud_line_placed(
        &fields.map(|(priority, text)| (priority, style.own_text(text))),
        HELP,
        width,
    );
    let clock_at = at[2]; // (the clock's field)
    // The lens's key beside the help's, where the line has room to spare after every field: far
    // openings are read through it (issue #39), and a new player does not find it in the help alone.
    const LENS_KEY: &str = "z look ahead  ";
    match line.strip_suffix(HELP) {
        // (only where the walk's own keys apply: a spectator's `z` does nothing)
        Some(fields)
            if own_keys
                && !app.look_ahead()
                && fields.len() - fields.trim_end().len() >= LENS_KEY.len() + 2 =>
        {
            let cut = fields.len() - LENS_KEY.len(); // (spaces: one byte a column)
            (format!("{}{LENS_KEY}{HELP}", &fields[..cut]), clock_at)
        }
        _ => (line, clock_at),
    }
}

/// The compass point of a heading (degrees counter-clockwise from east, +x; north, +y, is up on the
/// map), to the nearest of eight.
#[must_use]
pub(crate) fn compass_point(yaw_deg: f32) -> &'static str {
    const POINTS: [&str; 8] = ["E", "NE", "N", "NW", "W", "SW", "S", "SE"];
    POINTS[((yaw_deg.rem_euclid(360.0) + 22.5) / 45.0) as usize % 8]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A clock tick with nothing else changed writes the clock's new digits over the old: the row
    /// is the one a screen that never drew a HUD draws, cell for cell, in each charset and depth; the
    /// line is made whole again only where the clock's text changes length, or anything else changed
    /// (the players in, the row drawn over).
    #[test]
    fn a_clock_tick_writes_the_clocks_digits_as_the_whole_line_would() {
        use mazewalk_render::Charset;
        let made = || HUD_LINES_MADE.with(std::cell::Cell::get);
        for (charset, depth) in [
            (Charset::Half, ColorDepth::TrueColor),
            (Charset::Ascii, ColorDepth::Ansi16),
            (Charset::Half, ColorDepth::None),
        ] {
            let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
            let app = App::new(mazewalk_maze::builtin().unwrap(), options, 0.0).unwrap();
            let (cols, rows) = (100, 30);
            let (mut screen, mut frame) = (Screen::default(), Frame::new(cols, rows));
            screen.players_in = Some(2);
            draw_kept(&app, &mut screen, &mut frame, &Hud::default());
            let hud_row = |frame: &Frame| frame.row(rows - 1).unwrap().to_vec();
            let alike = |screen: &Screen, frame: &Frame, hud: &Hud| {
                let (mut fresh, mut again) = (Screen::default(), frame.clone());
                fresh.players_in = screen.players_in;
                draw_hud(&app, &mut fresh, &mut again, hud);
                hud_row(frame) == hud_row(&again)
            };
            // (the HUD lines the screen's own draws made whole: `alike` makes some of its own)
            let whole = std::cell::Cell::new(0);
            let draw = |screen: &mut Screen, frame: &mut Frame, hud: &Hud| {
                let before = made();
                let drawn = draw_hud(&app, screen, frame, hud);
                whole.set(whole.get() + made() - before);
                drawn
            };
            // 0:00 → 0:01 … 9:59 → 10:00 (a column longer) → 10:01 … 59:59 → 60:00 → 600:00 (longer)
            for elapsed in [1.0, 2.0, 59.5, 60.0, 599.0, 600.0, 601.0, 3599.0, 3600.0, 36000.0] {
                let hud = Hud { elapsed, ..Hud::default() };
                let made_before = whole.get();
                let drawn = draw(&mut screen, &mut frame, &hud);
                let text: String = hud_row(&frame).iter().map(|c| c.ch).collect();
                let clock = format!("time {}", running_clock_text(elapsed));
                assert!(text.contains(&clock), "{text:?}");
                // the cells drawn: the row where the line was made whole, else the clock's alone
                let cells: String = frame.cells()[drawn.clone()].iter().map(|c| c.ch).collect();
                if whole.get() == made_before {
                    assert_eq!(cells, clock, "{drawn:?}");
                } else {
                    assert_eq!(drawn, (rows - 1) * cols..rows * cols);
                }
                assert!(alike(&screen, &frame, &hud), "{charset:?} {depth:?} at {elapsed}: {text:?}");
            }
            assert_eq!(whole.get(), 2, "{charset:?} {depth:?}: made whole at 10:00 and 600:00 only");
            // anything else changed: made whole, and right
            screen.players_in = Some(3);
            let hud = Hud { elapsed: 36001.0, ..Hud::default() };
            draw(&mut screen, &mut frame, &hud);
            assert!(
                alike(&screen, &frame, &hud) && whole.get() == 3,
                "{charset:?} {depth:?}: the players in"
            );
            (0..cols).for_each(|x| frame.set(x, rows - 1, Cell::BLANK));
            let hud = Hud { elapsed: 36002.0, ..Hud::default() };
            draw(&mut screen, &mut frame, &hud);
            assert!(
                alike(&screen, &frame, &hud) && whole.get() == 4,
                "{charset:?} {depth:?}: the row drawn over"
            );
        }
    }

    #[test]
    fn the_hud_fits_any_width_by_priority_and_always_offers_help() {
        let app = App::new(mazewalk_maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
        let stats = RenderStats::default();
        let hud = Hud { fps: 57, elapsed: 83.4, ..Hud::default() };
        for width in [20, 40, 60, 80, 120, 200] {
            let line = hud_text(&app, &stats, &hud, Some(3), Style::default(), width);
            assert_eq!(line.chars().count(), width, "{line:?}");
            assert!(line.ends_with("? help "), "{line:?}");
            // where the player faces first (at 20 columns only the shorter clock fits beside the help)
            assert!(line.starts_with(if width > 20 { " heading 0° E" } else { " time 1:23" }), "{line:?}");
        }
        let at40 = hud_text(&app, &stats, &hud, Some(3), Style::default(), 40);
        assert_eq!(at40, " heading 0° E  time 1:23  3 in   ? help ");
        let at80 = hud_text(&app, &stats, &hud, None, Style::default(), 80);
        assert!(
            at80.contains("time 1:23") && at80.contains("(6.0, 50.0)") && !at80.contains(" in "),
            "{at80:?}"
        );
        let wide = hud_text(&app, &stats, &hud, None, Style::default(), 200);
        assert!(wide.contains("fov 90° persp half"), "{wide:?}");
        // the lens's key offered beside the help where there is room, and only then
        assert!(wide.ends_with("    z look ahead  ? help ") && wide.chars().count() == 200, "{wide:?}");
        // not where the keys are another's (a spectator's: `z` does nothing there)
        let theirs =
            hud_text_with(&app, &stats, &hud, (None, None, None, false), 90.0, Style::default(), 200);
        assert!(!theirs.contains("look ahead") && theirs.ends_with("? help "), "{theirs:?}");
        let at60 = hud_text(&app, &stats, &hud, None, Style::default(), 60);
        assert!(!at60.contains("look ahead") && at60.contains("z+0.0"), "fields first: {at60:?}");
        // in ASCII, fitted as shown: degrees spelled out, the help still at the right end
        let ascii = Style { ascii: true, ..Style::default() };
        for width in 20..60 {
            let line = hud_text(&app, &stats, &hud, Some(3), ascii, width);
            assert!(line.is_ascii() && line.len() == width && line.ends_with("? help "), "{line:?}");
        }
    }

    // issue #35: a shared world's Redis away shows first in the HUD, before the heading.
    #[test]
    fn a_hosts_status_comes_first_in_the_hud() {
        let app = App::new(mazewalk_maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
        let (stats, hud) = (RenderStats::default(), Hud { elapsed: 83.4, ..Hud::default() });
        let line = |width| {
            let host = (Some(3), Some("world offline"), None, true);
            hud_text_with(&app, &stats, &hud, host, 90.0, Style::default(), width)
        };
        assert!(line(60).starts_with(" world offline  heading 0° E  time 1:23  3 in"), "{:?}", line(60));
        assert!(line(30).starts_with(" world offline "), "kept before the rest: {:?}", line(30));
    }

    // issue #33: the developer figures (fps, bytes, cell, seen, ms) are behind `i`.
    #[test]
    fn the_developer_figures_show_only_when_asked_for() {
        let mut app = App::new(mazewalk_maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
        let (stats, hud) = (RenderStats::default(), Hud { fps: 57, elapsed: 1.0, ..Hud::default() });
        let plain = hud_text(&app, &stats, &hud, None, Style::default(), 200);
        for figure in [" fps ", " B ", "cell ", "seen ", " ms"] {
            assert!(!plain.contains(figure), "{figure:?} in {plain:?}");
        }
        app.figures = true;
        let dev = hud_text(&app, &stats, &hud, None, Style::default(), 200);
        assert!(dev.contains("57 fps 0 B") && dev.contains("cell ") && dev.contains(" ms"), "{dev:?}");
    }

    // issue #39: the look-ahead lens (`z`) says so in the HUD, kept before the position and the view
    // settings: a player who forgot it is on would take the narrow view for the maze.
    #[test]
    fn the_hud_says_when_the_look_ahead_lens_is_on() {
        let mut app = App::new(mazewalk_maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
        let (stats, hud) = (RenderStats::default(), Hud { elapsed: 83.4, ..Hud::default() });
        let line = |app: &App, width| {
            let fov = app.shown_hfov_deg(120, 39);
            hud_text_with(app, &stats, &hud, (Some(3), None, None, true), fov, Style::default(), width)
        };
        for width in [60, 80, 120, 200] {
            // (off, only the key offered where there is room: `z look ahead`)
            assert!(!line(&app, width).contains("° look ahead"), "{:?}", line(&app, width));
        }
        app.set_look_ahead(true);
        for width in [60, 80, 120, 200] {
            let text = line(&app, width);
            assert!(text.contains("  fov 30° look ahead  ") && text.ends_with("? help "), "{text:?}");
            assert!(!text.contains("z look ahead"), "no key offered for what is on: {text:?}");
        }
        assert!(line(&app, 200).contains("fov 30° look ahead  persp half"), "{:?}", line(&app, 200));
        assert!(!line(&app, 60).contains("(6.0, 50.0)"), "the lens before the position");
        app.set_look_ahead(false);
        assert!(line(&app, 200).contains("fov 90° persp half"), "{:?}", line(&app, 200));
    }

    /// Issue #39: through the lens a new player counted every corridor a cell short, the nearest
    /// cell line in view lying on the frame's bottom edge. The lens numbers the floor's cell lines
    /// straight ahead at the view's left edge, and marks the wall that ends the way with the cells to
    /// it. Down a corridor of eight cells from the first's centre (and from a little past it), in
    /// every charset: line digits 2 (3), 3, … bottom to top with none skipped, every cell line ascii
    /// draws on the floor numbered (on its row, within one), and `7|` at the end wall's foot, above
    /// them (`12|` down one of thirteen; `0|` and `1|` on the bottom row in a corridor of one and of
    /// two cells, whose end walls' feet lie below the lens's view); none of it without the lens.
    #[test]
    fn the_lens_numbers_the_cell_lines_ahead_and_the_walls_end() {
        use mazewalk_render::Charset;
        let corridor = |cells: usize| {
            let wall = "#".repeat(cells + 2);
            let text = format!(
                "mazewalk-grid 1\ntile 4\nfacing east\n\n{wall}\n#@{}#\n{wall}\n",
                ".".repeat(cells - 1)
            );
            mazewalk_maze::parse("corridor.grid", text.as_bytes()).unwrap()
        };
        for charset in [Charset::Ascii, Charset::Half, Charset::Quad, Charset::Sextant] {
            for (cells, past) in [(8, 0.0), (8, 0.4), (13, 0.0), (1, 0.4), (2, 0.0)] {
                let maze = corridor(cells);
                let options = RenderOptions { charset, ..RenderOptions::default() };
                let mut app = App::new(maze.clone(), options, 0.0).unwrap();
                app.camera.position.x += past;
                let mut screen = Screen::default();
                let mut frame = Frame::new(120, 40);
                // the marks: (text, row), bottom to top
                let marks = |frame: &Frame| -> Vec<(String, usize)> {
                    (0..39)
                        .rev()
                        .filter(|&y| frame.get(0, y).unwrap().ch.is_ascii_digit())
                        .map(|y| {
                            let text = (0..4)
                                .map(|x| frame.get(x, y).unwrap())
                                .take_while(|c| c.fg == overlay::RANGE_FG)
                                .map(|c| c.ch)
                                .collect();
                            (text, y)
                        })
                        .collect()
                };
                draw(&app, &mut screen, &mut frame, &Hud::default());
                assert!(marks(&frame).is_empty(), "no marks without the lens");
                app.set_look_ahead(true);
                draw(&app, &mut screen, &mut frame, &Hud::default());
                let marks = marks(&frame);
                let (end, lines) = marks.split_last().expect("marks");
                assert_eq!(end.0, format!("{}|", cells - 1), "{charset:?} {past}: the end wall: {marks:?}");
                if cells <= 2 {
                    // nose to the wall, or one cell off: its foot below the lens's view, marked on
                    // the bottom row, no line in view
                    assert_eq!((end.1, lines.len()), (38, 0), "{charset:?} {cells}: {marks:?}");
                    continue;
                }
                let digits: Vec<u32> = lines.iter().map(|(t, _)| t.parse().unwrap()).collect();
                // (from a little past the centre cell 2's line lies below the view)
                let first = if past == 0.0 { 2 } else { 3 };
                assert!(digits.len() >= 3 && digits[0] == first, "{charset:?} {past}: {marks:?}");
                assert!(digits.windows(2).all(|w| w[1] == w[0] + 1), "none skipped: {marks:?}");
                assert!(marks.windows(2).all(|w| w[1].1 < w[0].1), "bottom to top: {marks:?}");
                if charset == Charset::Ascii {
                    // every floor line drawn (the middle column's `~` below the end wall) is numbered
                    for y in end.1 + 1..39 {
                        if frame.get(60, y).unwrap().ch == '~' {
                            assert!(lines.iter().any(|m| m.1.abs_diff(y) <= 1), "line at {y}: {marks:?}");
                        }
                    }
                }
            }
        }
    }

    /// A screen drawn into a kept frame ([`draw_kept`]: only the cells under the map kept of a
    /// rendered view, only those restored when it is shown again) draws each frame bit for bit as
    /// [`draw`] does into a fresh frame: over two mazes and every charset, through turns, steps and
    /// frames where only the map, a box or the HUD changes (a peer walking behind the viewer, the
    /// help, a notice, the player list, a ghost and its caption, the exit box, the map's modes) and
    /// a resize to the same size (the frame cleared, the screen told). It fails if the patch is not
    /// restored, if what a box or caption covers is taken for the view, or if the screen is not told
    /// of the resize (each tried), and if views are never shown again or never by their patch.
    #[test]
    fn a_kept_frame_draws_what_a_fresh_one_does() {
        use glam::Vec2;
        use mazewalk_render::Charset;
        let generated = mazewalk_maze::generate::generate(&mazewalk_maze::generate::GenOptions {
            width: 9,
            height: 7,
            seed: 6,
            loops: 0.3,
            exit: true,
            ..mazewalk_maze::generate::GenOptions::default()
        })
        .expect("maze");
        let (mut frames, mut shown_again, mut patched) = (0, 0, 0);
        for maze in [mazewalk_maze::builtin().unwrap(), generated] {
            for charset in [Charset::Half, Charset::Quad, Charset::Sextant, Charset::Ascii] {
                let options = RenderOptions { charset, ..RenderOptions::default() };
                let mut app = App::new(maze.clone(), options, 0.0).unwrap();
                let (mut kept, mut fresh) = (Screen::default(), Screen::default());
                let mut frame = Frame::new(100, 30);
                for k in 0..60 {
                    // every third frame the view changes (a turn, or a step); else something else
                    match k % 3 {
                        0 if k % 12 == 9 => {
                            let ahead = Vec2::from_angle(app.camera.yaw_deg.to_radians()) * 0.4;
                            if maze.cell_at(app.camera.position + ahead).is_some() {
                                app.camera.position += ahead;
                            }
                        }
                        0 => app.camera.yaw_deg = (app.camera.yaw_deg + 31.0).rem_euclid(360.0),
                        _ => {}
                    }
                    // (the map changes while the view stays: the full map's cells must go when it is off)
                    app.map = match k {
                        0..=16 => MapMode::Corner,
                        17..=31 => MapMode::Full,
                        32..=46 => MapMode::Off,
                        _ => MapMode::Corner,
                    };
                    app.help = k % 17 == 4;
                    app.set_look_ahead(k % 20 < 3); // (its range marks over the view: three frames in twenty)
                    app.finished = (k % 23 == 7).then_some(12.5);
                    app.exit_box = app.finished.is_some();
                    let behind = Vec2::from_angle(app.camera.yaw_deg.to_radians()) * -(0.2 + 0.05 * k as f32);
                    let ahead = Vec2::from_angle(app.camera.yaw_deg.to_radians()) * 1.2;
                    for screen in [&mut kept, &mut fresh] {
                        screen.notice = (k % 19 == 11).then(|| "news".to_string());
                        screen.roster = vec![roster::Entry {
                            name: "ada".to_string(),
                            label: 'a',
                            color: Color::Indexed(9),
                            joined_at: 0.0,
                            best: None,
                            me: false,
                        }];
                        screen.show_roster = k % 13 == 6;
                        screen.peers = vec![Peer {
                            position: app.camera.position + behind,
                            heading_deg: 0.0,
                            initial: 'b',
                            color: Color::Rgb(250, 120, 10),
                            cell: None,
                        }];
                        screen.ghost = (k % 11 == 8).then(|| {
                            let pose =
                                Pose { position: app.camera.position + ahead, yaw_deg: 0.0, pitch_deg: 0.0 };
                            (pose, "ghost ada 1:40.4".to_string())
                        });
                    }
                    if k == 40 {
                        frame.resize(100, 30); // cleared
                        kept.forget_frame();
                    }
                    let renders = kept.renders();
                    let patch = kept.last_view.as_ref().and_then(|l| (!l.whole).then_some(l.patch).flatten());
                    draw_kept(&app, &mut kept, &mut frame, &Hud::default());
                    let mut expected = Frame::new(100, 30);
                    draw(&app, &mut fresh, &mut expected, &Hud::default());
                    assert!(frame == expected, "{charset:?}, frame {k}: not the fresh screen's");
                    if kept.renders() == renders {
                        shown_again += 1;
                        patched += usize::from(patch.is_some());
                    }
                    frames += 1;
                }
            }
        }
        assert_eq!(frames, 2 * 4 * 60);
        assert!(
            shown_again > 50 && patched > 16,
            "{shown_again} views shown again, {patched} by their patch"
        );
    }

    /// The map's `seen` with the pass's cells looked up only when one is new is the cell seen before
    /// or visible now, for every cell of two mazes over turning and walking frames, portal culling
    /// and brute force, with the cells in view marked seen after some frames and not others (as a
    /// session does after each); and the corner map fitted to it, kept from frame to frame while the
    /// seen cells and the area stay, is the map fitted afresh. It fails if a cell in view now but not
    /// seen before is left out, or if one not in view counts (tried: `fresh` always false), if a fit
    /// is kept across a newly seen cell (tried: the key without the seen cells' id), or if none is
    /// kept.
    #[test]
    fn seen_now_is_seen_before_or_visible_now() {
        let generated = mazewalk_maze::generate::generate(&mazewalk_maze::generate::GenOptions {
            width: 9,
            height: 7,
            seed: 5,
            loops: 0.3,
            exit: true,
            ..mazewalk_maze::generate::GenOptions::default()
        })
        .expect("maze");
        let (mut fresh_frames, mut known_frames) = (0, 0);
        for maze in [mazewalk_maze::builtin().unwrap(), generated] {
            for culling in [Culling::Portal, Culling::None] {
                let options = RenderOptions { culling, ..RenderOptions::default() };
                let mut app = App::new(maze.clone(), options, 0.0).unwrap();
                app.map = MapMode::Corner;
                let mut screen = Screen::default();
                let mut frame = Frame::new(100, 30);
                for k in 0..24 {
                    app.camera.yaw_deg = (app.camera.yaw_deg + 23.0).rem_euclid(360.0);
                    if k % 6 == 5 {
                        let ahead = glam::Vec2::from_angle(app.camera.yaw_deg.to_radians()) * 0.4;
                        if maze.cell_at(app.camera.position + ahead).is_some() {
                            app.camera.position += ahead;
                        }
                    }
                    draw(&app, &mut screen, &mut frame, &Hud::default());
                    let new_in_view = {
                        let portal = screen.renderer.portal();
                        let seen = seen_now(&app, portal);
                        // the corner map as fitted now, without the fit kept from frame to frame
                        let also = [app.camera.position];
                        let fitted = map_area(&app, &frame)
                            .map(|area| area.fit_to_seen(&maze, &seen, also, &mut MapCells::default(), None));
                        assert_eq!(screen.map, fitted, "frame {k}, {culling:?}");
                        let mut new_in_view = false;
                        for c in 0..maze.cell_count() as u32 {
                            let visible = culling == Culling::Portal && portal.was_visited(c);
                            new_in_view |= visible && !app.has_seen(c);
                            assert_eq!(
                                seen(c),
                                app.has_seen(c) || visible,
                                "cell {c}, frame {k}, {culling:?}"
                            );
                        }
                        new_in_view
                    };
                    if culling == Culling::Portal {
                        *(if new_in_view { &mut fresh_frames } else { &mut known_frames }) += 1;
                    }
                    if k % 4 == 3 {
                        let visited = screen.renderer.portal().visited.clone();
                        app.mark_seen(visited);
                    }
                    if k % 4 == 1 {
                        // cells seen otherwise (brute force's: by the samples' walls), not in view now
                        let cells = maze.cell_count() as u32;
                        app.mark_seen([(7 * k as u32) % cells, (7 * k as u32 + 3) % cells]);
                    }
                }
            }
        }
        assert!(
            fresh_frames > 5 && known_frames > 5,
            "{fresh_frames} frames with new cells, {known_frames} without"
        );
        assert!(overlay::FITS_KEPT.with(std::cell::Cell::get) > 20, "the map's fit never kept");
    }

    /// A screen limits the colours of what is drawn over the view (the map, boxes, a caption, the
    /// player list; the HUD's row by itself), not the view's own: it must come out as if the whole
    /// frame had been limited. On turning views of the built-in maze and a generated one, in every
    /// charset and depth, with a player in truecolour in view and on the corner map, with and
    /// without the help box, a notice, a ghost and its caption: each frame is its own limit. It
    /// fails if the renderer draws a colour beyond the depth, or if an overlay's colours are left
    /// as drawn (the map's peer, a box, the caption).
    #[test]
    fn a_screen_is_within_its_depth_though_only_the_overlays_are_limited() {
        use glam::Vec2;
        use mazewalk_render::Charset;
        use mazewalk_term::frame::ColorDepth;
        let generated = mazewalk_maze::generate::generate(&mazewalk_maze::generate::GenOptions {
            width: 9,
            height: 7,
            seed: 4,
            loops: 0.3,
            exit: true,
            ..mazewalk_maze::generate::GenOptions::default()
        })
        .expect("maze");
        let (mut frames, mut peers_shown) = (0, 0);
        for maze in [mazewalk_maze::builtin().unwrap(), generated] {
            for charset in [Charset::Half, Charset::Quad, Charset::Sextant, Charset::Ascii] {
                for depth in
                    [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16, ColorDepth::None]
                {
                    let options = RenderOptions { charset, color_depth: depth, ..RenderOptions::default() };
                    let mut app = App::new(maze.clone(), options, 0.0).unwrap();
                    app.map = MapMode::Corner;
                    let mut screen = Screen::default();
                    for k in 0..8 {
                        app.camera.yaw_deg = (app.camera.yaw_deg + 47.0).rem_euclid(360.0);
                        app.help = k == 5;
                        screen.notice = (k == 6).then(|| "news".to_string());
                        let ahead = Vec2::from_angle(app.camera.yaw_deg.to_radians()) * 1.5;
                        screen.peers = vec![Peer {
                            position: app.camera.position + ahead,
                            heading_deg: 0.0,
                            initial: 'b',
                            color: Color::Rgb(250, 120, 10),
                            cell: None,
                        }];
                        screen.ghost = (k == 7).then(|| {
                            let position = app.camera.position + ahead * 0.8;
                            let pose = Pose { position, yaw_deg: 0.0, pitch_deg: 0.0 };
                            (pose, "ghost ada 1:40.4".to_string())
                        });
                        let mut frame = Frame::new(100, 30);
                        draw(&app, &mut screen, &mut frame, &Hud::default());
                        let mut limited = frame.clone();
                        overlay::limit_colors(&mut limited, depth);
                        assert!(
                            frame == limited,
                            "{charset:?}, {depth:?}, frame {k}: a colour beyond the depth"
                        );
                        let on_map = frame.cells().iter().any(|c| c.ch == 'b' && c.fg != Color::Default);
                        peers_shown += usize::from(on_map && depth != ColorDepth::TrueColor);
                        frames += 1;
                    }
                }
            }
        }
        assert_eq!(frames, 2 * 4 * 4 * 8);
        assert!(peers_shown > 20, "the peer showed in colour in {peers_shown} limited frames");
    }

    #[test]
    fn compass_points_follow_the_heading_with_north_up_on_the_map() {
        // 0° is east (+x), counter-clockwise: 90° north (+y, up on the map)
        let points = [(0.0, "E"), (44.0, "NE"), (90.0, "N"), (135.0, "NW"), (180.0, "W"), (225.0, "SW")];
        for (yaw, point) in points.into_iter().chain([(270.0, "S"), (337.6, "E"), (-90.0, "S"), (360.0, "E")])
        {
            assert_eq!(compass_point(yaw), point, "{yaw}°");
        }
    }
}
