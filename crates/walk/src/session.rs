//! One player's walk: bytes from a terminal in, the bytes of the next frame out — pure: no globals,
//! no terminal, no clock (time comes in as seconds on the caller's clock), no exit.
//!
//! ```text
//! bytes ─InputDecoder─▶ Input ─▶ App (keys, drag, tick) ─▶ screen::draw ─▶ Frame ─Encoder─▶ bytes
//! ```
//!
//! The local walkthrough (the `mazewalk` binary's `run`) is a `Session` plus the terminal guard plus
//! stdin and stdout; a server runs one `Session` per connection. The host reads its own clock, passes
//! the bytes it got ([`Session::feed`]) and what only it knows ([`Input::Resize`], a stop, what the
//! last frame cost it: [`Session::frame_cost`]), sleeps until [`Session::next_wake`], and writes
//! whatever [`Session::frame`] produces.
//!
//! ```
//! use mazewalk_walk::{App, Session, SessionOptions};
//! use mazewalk_maze as maze;
//! use mazewalk_render::RenderOptions;
//!
//! let app = App::new(maze::builtin()?, RenderOptions::default(), 0.0)?;
//! let mut session = Session::new(app, 80, 24, SessionOptions::default());
//! let mut bytes = Vec::new();
//! assert!(session.frame(0.0, &mut bytes)); // the first frame: everything
//! session.feed(b"w", 0.1); // a key press
//! bytes.clear();
//! assert!(session.frame(0.1, &mut bytes) && !bytes.is_empty()); // walked: what changed
//! bytes.clear();
//! session.feed(b"q", 0.2);
//! assert!(session.is_over());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::collections::VecDeque;
use std::sync::Arc;

use crate::clock::clock_text;
use crate::flow::{ACK_TIMEOUT, FlowControl, QUERY};
use crate::overlay::{MapArea, Peer};
use crate::roster;
use crate::run::{Pose, Run};
use crate::screen::{self, FrameCost, Hud, Screen};
use crate::state::App;
use crate::views::SharedViews;
use mazewalk_render::{Charset, Culling};
use mazewalk_term::caps::{REP_PROBE, REP_PROBE_ASCII, RepLevel, RepReport, TRUECOLOR_QUERY, rep_answer};
use mazewalk_term::encoder::{self, Encoder};
use mazewalk_term::frame::{ColorDepth, Frame};
use mazewalk_term::input::{Input, InputDecoder, Key, KeyPhase, Reply};

/// The most frames per second drawn while something moves.
pub(crate) const MAX_FPS: f64 = 60.0;

use mazewalk_term::modes::KEYBOARD_FLAGS_QUERY as KEYBOARD_QUERY;

/// The size drawn when a terminal gives none (a side of zero: some ptys, an SSH pty request without one).
pub const DEFAULT_SIZE: (u16, u16) = (80, 24);

/// The largest picture a session draws, columns and rows: a terminal larger than that shows it in its
/// top-left corner. Beyond any real screen (a 4K monitor at a 6-pixel font is ≈ 640 × 270), and a
/// bound on what a terminal's size can cost: one that claims 65535 × 65535 must not make a 50 GB frame.
pub(crate) const MAX_SIZE: (u16, u16) = (1000, 400);

/// The size a session draws for a terminal of `cols × rows`: a side of zero is unknown, so
/// [`DEFAULT_SIZE`]'s; no side more than `max`'s.
#[must_use]
pub fn fit_size(cols: u32, rows: u32, max: (u16, u16)) -> (u16, u16) {
    let side = |n: u32, default: u16, max: u16| {
        if n == 0 { default } else { u16::try_from(n).unwrap_or(u16::MAX).min(max) }
    };
    (side(cols, DEFAULT_SIZE.0, max.0), side(rows, DEFAULT_SIZE.1, max.1))
}

/// How a session encodes and paces its frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SessionOptions {
    /// The terminal erases with the current background colour ([`Encoder::set_bce`]).
    pub bce: bool,
    /// Colour tolerance in steps of 0.01 in OKLab ([`Encoder::set_tolerance`]); raised while the terminal
    /// answers slowly (see [`adaptive_tolerance`]).
    pub color_tolerance: u8,
    /// End-to-end flow control ([`super::flow`]): a query after each frame, at most
    /// [`MAX_UNACKED`](super::flow::MAX_UNACKED) frames unanswered.
    pub flow_control: bool,
    /// The most samples drawn a second (`None`: no bound but [`MAX_FPS`]): a frame's samples are its
    /// cells × its charset's samples per cell (at least 2), so a larger screen or a finer charset is drawn at a
    /// lower frame rate ([`frame_interval`](Session::frame_interval)). A server's bound on what one
    /// session's drawing can cost.
    pub sample_rate: Option<u32>,
}

impl Default for SessionOptions {
    fn default() -> Self {
        SessionOptions {
            bce: false,
            color_tolerance: encoder::DEFAULT_TOLERANCE,
            flow_control: true,
            sample_rate: None,
        }
    }
}

/// The colour tolerance for a frame when replies take `round_trip` seconds: the base while the link
/// keeps up; more (fewer changed cells, fewer bytes) while frames take longer than a few frame
/// intervals to reach the screen, which is when every byte saved shortens the wait for the next one.
#[must_use]
pub(crate) fn adaptive_tolerance(base: u8, round_trip: Option<f64>) -> u8 {
    let extra = match round_trip {
        Some(rtt) if rtt > 0.3 => 6,
        Some(rtt) if rtt > 0.1 => 3,
        _ => 0,
    };
    base.saturating_add(extra).min(encoder::MAX_TOLERANCE)
}

/// Whether the link counts as slow, from the reply round trip in seconds and whether it counted as
/// slow before: slow above 0.15 s, fast again below 0.08 s (between the two it stays as it was, so
/// it does not flap). On a slow link the walk stops dithering (`--dither`, off by default): a
/// dithered 256- or 16-colour frame costs about 1.5× the bytes of a plain one while walking.
#[must_use]
pub fn slow_link(was_slow: bool, round_trip: Option<f64>) -> bool {
    match round_trip {
        Some(rtt) if rtt > 0.15 => true,
        Some(rtt) if rtt >= 0.08 => was_slow,
        _ => false,
    }
}

/// What the walk cost so far, and how it ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outcome {
    /// Seconds taken to reach the exit, if it was reached.
    pub finished: Option<f64>,
    /// Frames drawn.
    pub frames: u64,
    /// Bytes of all frames together.
    pub bytes: u64,
}

/// One player's walk: app state, renderer, encoder, input decoder and screen.
#[derive(Debug)]
pub struct Session {
    app: App,
    screen: Screen,
    frame: Frame,
    encoder: Encoder,
    decoder: InputDecoder,
    inputs: Vec<Input>,
    dirty: bool,
    last_frame: f64,
    cost: FrameCost,
    suspend: bool,
    outcome: Outcome,
    options: SessionOptions,
    flow: FlowControl,
    /// When the frames of the last second were drawn (for the HUD's frame rate).
    recent_frames: VecDeque<f64>,
    /// A kitty keyboard query (`CSI ? u`) is out and not yet answered: only its answer may turn key
    /// releases on (a pasted or forged `CSI ? 3 u` would leave every key held until a release
    /// that never comes).
    keyboard_query: bool,
    /// The truecolor questions ([`ask_truecolor`](Self::ask_truecolor)) and how far their answers
    /// may still come.
    truecolor_query: TruecolorQuery,
    /// The whole seconds the HUD's exit clock showed last.
    clock_shown: Option<u64>,
    /// The stored run a ghost replays when the player wants it ([`App::ghost`]), and its caption.
    ghost_run: Option<(Arc<Run>, String)>,
    /// Where the questions whether, and after which glyphs, the terminal has REP ([`REP_PROBE`], sent
    /// before the first frame) stand: only their answers, in order, may turn REP on.
    rep_probe: RepProbe,
    /// The screen shows the last frame only within the colour tolerance ([`EncodeStats::approximate`](mazewalk_term::encoder::EncodeStats::approximate)):
    /// once the picture has held still for [`SETTLE_AFTER`], it is sent once more, exactly.
    approximate: bool,
}

/// How long the picture holds still before a frame left within the colour tolerance is sent once
/// more, exactly ([`Session::frame`]). While the view moves, the tolerance saves the bytes of colours
/// that drift by less than a just-noticeable step; at rest, its seams (a patch left a step off its
/// neighbours draws an edge the eye picks out) would stay: settling costs one frame's worth of
/// those cells per stop, none while walking or turning.
pub(crate) const SETTLE_AFTER: f64 = 0.25;

/// Where the REP questions stand ([`REP_PROBE`]: after a space, then after a block glyph).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RepProbe {
    /// Not asked yet: asked before the first frame.
    NotAsked,
    /// Asked; the answer to the space question may come (whenever: a report of row 2 or 3 is never a
    /// key, and a key between the reports changes nothing here). An answer to the block question
    /// before it is not taken (a terminal answers in order; one whose first report was lost or
    /// garbled keeps REP off). `block`: the block question was asked too (not in the ascii charset).
    Asked { block: bool },
    /// The space was repeated (REP after ASCII glyphs is on); the answer to the block question may
    /// come, and turn REP after any glyph on.
    SpaceRepeated,
    /// Answered: no more answers count.
    Done,
}

/// Where the truecolor questions stand: only answers to questions asked, before the terminal has
/// answered the device-attributes query sent after them, count (a pasted or forged answer later
/// must not change the colours of a walk under way).
#[derive(Clone, Copy, Debug, PartialEq)]
enum TruecolorQuery {
    /// Not asked, or no more answers count.
    Closed,
    /// Asked; the clock starts with the next frame.
    Asked,
    /// Asked at this time: answers count until the next device-attributes reply, or for
    /// [`ACK_TIMEOUT`] from a terminal that answers no query at all.
    Open(f64),
}

impl Session {
    /// A session walking `app` on a `cols × rows` terminal; its first [`frame`](Self::frame) paints
    /// the whole screen.
    #[must_use]
    pub fn new(app: App, cols: u16, rows: u16, options: SessionOptions) -> Session {
        let (cols, rows) = fit_size(cols.into(), rows.into(), MAX_SIZE);
        let mut encoder = Encoder::new();
        encoder.set_bce(options.bce);
        encoder.set_tolerance(options.color_tolerance);
        Session {
            app,
            screen: Screen::default(),
            frame: Frame::new(cols.into(), rows.into()),
            encoder,
            decoder: InputDecoder::new(),
            inputs: Vec::new(),
            dirty: true,
            last_frame: f64::NEG_INFINITY,
            cost: FrameCost::default(),
            suspend: false,
            outcome: Outcome::default(),
            options,
            flow: FlowControl::default(),
            recent_frames: VecDeque::new(),
            keyboard_query: false,
            truecolor_query: TruecolorQuery::Closed,
            clock_shown: None,
            ghost_run: None,
            rep_probe: RepProbe::NotAsked,
            approximate: false,
        }
    }

    /// The stored run to race as a ghost (`None`: none): a served maze's best run, the local walk's
    /// `--ghost FILE`. The host checks it belongs to the maze ([`Run::check_maze`]). It shows while
    /// the player wants it ([`App::ghost`], `g`), from the walk's start or the toggle, whichever is
    /// later, labelled with its holder's name and time.
    pub fn set_ghost_run(&mut self, run: Option<Arc<Run>>) {
        let same = match (&self.ghost_run, &run) {
            (Some((a, _)), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if !same {
            self.ghost_run = run.map(|run| {
                let name = if run.holder.is_empty() { String::new() } else { format!("{} ", run.holder) };
                let caption = format!("ghost {name}{}", clock_text(run.seconds()));
                (run, caption)
            });
            self.dirty = true;
        }
    }

    /// The ghost's pose at `now`, if it shows, and whether it is still on its way.
    fn ghost_at(&self, now: f64) -> Option<(Pose, bool)> {
        let (run, _) = self.ghost_run.as_ref()?;
        let t = self.app.ghost_time(now)?;
        Some((run.pose_at(t)?, t < run.seconds()))
    }

    /// The whole seconds the exit clock shows at `now` while it runs (a maze with an exit not found
    /// yet): it ticks once a second, standing still too (a few bytes).
    fn running_clock(&self, now: f64) -> Option<u64> {
        let app = &self.app;
        (app.maze().exit().is_some() && app.finished.is_none() && !app.clock_unknown)
            .then(|| (now - app.started).max(0.0).floor() as u64)
    }

    /// Adds the cells the last frame showed to the map's seen cells: the portal pass's, or with brute
    /// force the cells on both sides of every wall that reached a sample.
    fn note_seen(&mut self) {
        let renderer = &self.screen.renderer;
        if self.app.options.culling == Culling::Portal {
            self.app.mark_seen(renderer.portal().visited.iter().copied());
        } else {
            let maze = self.app.maze();
            let walls = maze.edges().len() as u32;
            let mut cells: Vec<u32> =
                renderer.samples().id().iter().filter(|&&id| id < walls).copied().collect();
            cells.sort_unstable();
            cells.dedup();
            let sides: Vec<u32> =
                cells.iter().flat_map(|&e| [maze.edge(e).left, maze.edge(e).right]).flatten().collect();
            self.app.mark_seen(sides);
        }
    }

    /// The walk's state.
    #[must_use]
    pub fn app(&self) -> &App {
        &self.app
    }

    /// The walk's state, to change settings.
    pub fn app_mut(&mut self) -> &mut App {
        self.dirty = true;
        &mut self.app
    }

    /// The screen as last drawn.
    #[must_use]
    pub fn screen(&self) -> &Frame {
        &self.frame
    }

    /// The other players to draw (a host's view of a shared maze); the next frame is drawn only if
    /// they differ from the ones drawn in what is drawn of them: where they stand, their cells,
    /// initials and colours, in order (a figure and a map label show no heading: another player
    /// turning on the spot changes no picture). Returns whether they did.
    pub fn set_peers(&mut self, peers: &[Peer]) -> bool {
        let drawn = |p: &Peer| (p.position.x.to_bits(), p.position.y.to_bits(), p.cell, p.initial, p.color);
        let changed = self.screen.peers.len() != peers.len()
            || self.screen.peers.iter().zip(peers).any(|(a, b)| drawn(a) != drawn(b));
        self.screen.peers.clear();
        self.screen.peers.extend_from_slice(peers);
        self.dirty |= changed;
        changed
    }

    /// Views this session's renderer drew so far ([`Screen::renders`](crate::screen::Screen::renders)):
    /// a frame whose view is unchanged (only the map, a box or the HUD changed) shows the last one
    /// again without rendering it.
    #[must_use]
    pub fn renders(&self) -> u64 {
        self.screen.renders()
    }

    /// Everyone in a served maze, for the player list (`Tab` opens and closes it; empty: no list, and
    /// `Tab` does nothing). Redraws only if the list is open and changed.
    pub fn set_roster(&mut self, entries: &[roster::Entry]) {
        if self.screen.roster != entries {
            self.screen.roster.clear();
            self.screen.roster.extend_from_slice(entries);
            self.dirty |= self.screen.show_roster;
            self.screen.show_roster &= !entries.is_empty();
        }
    }

    /// How many players walk the maze (a host's count, the HUD shows it as "3 in"; `None`: not
    /// served). The next frame is drawn only if it changed.
    pub fn set_players_in(&mut self, players: Option<usize>) {
        if self.screen.players_in != players {
            self.screen.players_in = players;
            self.dirty = true;
        }
    }

    /// A host's word on its own state for the HUD (`None`: nothing to say), e.g. "world offline". The
    /// next frame is drawn only if it changed.
    pub fn set_status(&mut self, status: Option<&str>) {
        if self.screen.status.as_deref() != status {
            self.screen.status = status.map(str::to_owned);
            self.dirty = true;
        }
    }

    /// A host's own key help, shown by `?` instead of the walk's (a spectator's keys; empty: the
    /// walk's).
    pub fn set_help(&mut self, lines: Vec<String>) {
        if self.screen.help != lines {
            self.screen.help = lines;
            self.dirty |= self.app.help;
        }
    }

    /// What the player list's header says closes it (a host whose key for it is not `Tab`: a
    /// spectator's `p`).
    pub fn set_roster_hint(&mut self, hint: &str) {
        if self.screen.roster_hint != hint {
            self.screen.roster_hint = hint.to_string();
            self.dirty |= self.screen.show_roster;
        }
    }

    /// Opens or closes the player list (a host's key for it: `Tab` is a spectator's next player);
    /// without a list, nothing happens.
    pub fn toggle_roster(&mut self) {
        if !self.screen.roster.is_empty() {
            self.screen.show_roster = !self.screen.show_roster;
            self.dirty = true;
        }
    }

    /// Whether the player list is open.
    #[must_use]
    pub fn roster_open(&self) -> bool {
        self.screen.show_roster
    }

    /// Draws the 3D view through `views`, shared with every other screen drawing the same view
    /// ([`SharedViews`]), instead of rendering its own. A view from the cache was not rendered by this
    /// screen's renderer, so the map learns no cells from it and [`sees_cell`](Self::sees_cell) is
    /// not to be asked: a screen sharing views shows the whole map ([`App::reveal_map`]).
    pub fn share_views(&mut self, views: std::sync::Arc<SharedViews>) {
        self.screen.shared_views = Some(views);
    }

    /// More lines for the exit box: a served maze's best times.
    pub fn set_standings(&mut self, lines: Vec<String>) {
        if self.screen.standings != lines {
            self.screen.standings = lines;
            self.dirty = true;
        }
    }

    /// Shows `notice` in a box over the view (`None` takes it away).
    pub fn set_notice(&mut self, notice: Option<String>) {
        if self.screen.notice != notice {
            self.screen.notice = notice;
            self.dirty = true;
        }
    }

    /// Whether the last frame's portal pass reached `cell`: something moving there may show in the
    /// view, so a host redraws when it does.
    #[must_use]
    pub fn sees_cell(&self, cell: u32) -> bool {
        self.screen.renderer.portal().was_visited(cell)
    }

    /// Where the map is, if it is shown: all the area it may cover (the corner map draws the part of
    /// it that shows what has been seen and the other players in it, so a player anywhere in it
    /// shows: a host draws those).
    #[must_use]
    pub fn map_area(&self) -> Option<MapArea> {
        screen::map_area(&self.app, &self.frame)
    }

    /// Where the last frame's map was drawn: the corner map fitted to what it shows.
    #[must_use]
    pub fn map_drawn(&self) -> Option<MapArea> {
        self.screen.map
    }

    /// What making the last frame cost the host, in seconds of its own clock (render, overlays and
    /// encoding: the host times [`frame`](Self::frame)); the HUD shows it on the next frame.
    pub fn frame_cost(&mut self, seconds: f64) {
        self.cost.seconds = seconds;
    }

    /// Changes [`SessionOptions::sample_rate`] (a server's share of a budget, which changes as
    /// other screens come and go); the next frame is due by the new rate.
    pub fn set_sample_rate(&mut self, rate: Option<u32>) {
        self.options.sample_rate = rate;
    }

    /// Bytes from the terminal, arriving at time `now`.
    pub fn feed(&mut self, bytes: &[u8], now: f64) {
        self.decode(now, |decoder, out| decoder.feed(bytes, now, out));
    }

    /// Bytes from the terminal were dropped after the last [`feed`](Self::feed) (a rate limit): see
    /// [`InputDecoder::gap`].
    pub fn input_gap(&mut self) {
        self.decoder.gap();
        self.flow.resync(); // replies may have been among the bytes dropped
    }

    /// Runs `step` on the decoder and applies the inputs it produces, at time `now`.
    fn decode(&mut self, now: f64, step: impl FnOnce(&mut InputDecoder, &mut Vec<Input>)) {
        let mut inputs = std::mem::take(&mut self.inputs); // reused: no allocation per read
        step(&mut self.decoder, &mut inputs);
        for input in inputs.drain(..) {
            self.input(input, now);
        }
        self.inputs = inputs;
    }

    /// One input at time `now`: keys and drags move the viewer, `Ctrl-C` quits, `Ctrl-Z` asks the host
    /// for a stop ([`take_suspend`](Self::take_suspend)), `Ctrl-L` paints everything again
    /// ([`repaint`](Self::repaint)), a resize redraws, losing focus lets go of
    /// held keys (no release will come).
    pub fn input(&mut self, input: Input, now: f64) {
        match input {
            Input::Key { key: Key::Char('c'), modifiers, .. } if modifiers.ctrl => self.app.quit = true,
            Input::Key { key: Key::Char('z'), modifiers, .. } if modifiers.ctrl => self.suspend = true,
            // Ctrl-L: another program wrote over the picture (a background job, `wall`): paint it all
            // again, as every full-screen program does.
            Input::Key { key: Key::Char('l'), modifiers, phase } if modifiers.ctrl => {
                if phase == KeyPhase::Press {
                    self.repaint();
                }
            }
            // Ctrl or Alt with a letter is not the letter (Ctrl-Q must not quit, Alt-W not walk).
            Input::Key { key: Key::Char(_), modifiers, .. } if modifiers.ctrl || modifiers.alt => {}
            // The player list of a served maze: Tab opens and closes it, Esc closes it (not the walk).
            Input::Key { key: Key::Tab, phase, .. } if !self.screen.roster.is_empty() => {
                if phase == KeyPhase::Press {
                    self.screen.show_roster = !self.screen.show_roster;
                    self.dirty = true;
                }
            }
            Input::Key { key: Key::Esc, .. } if self.screen.show_roster => {
                self.screen.show_roster = false;
                self.dirty = true;
            }
            // The walk's help where it does not fit whole: Space or PgDn shows its next page (after
            // the last, the first again), PgUp the one before.
            Input::Key { key: key @ (Key::Char(' ') | Key::PageDown | Key::PageUp), phase, .. }
                if self.app.help && self.screen.help_pages > 1 =>
            {
                if phase == KeyPhase::Press {
                    let (page, pages) = (self.screen.help_page, self.screen.help_pages);
                    self.screen.help_page =
                        if key == Key::PageUp { (page + pages - 1) % pages } else { (page + 1) % pages };
                    self.dirty = true;
                }
            }
            Input::Key { key, phase, .. } => self.dirty |= self.app.key(key, phase, now),
            Input::MouseDrag { dx, dy, .. } => self.dirty |= self.app.drag(dx, dy),
            Input::Resize { cols, rows } => {
                let (cols, rows) = fit_size(cols.into(), rows.into(), MAX_SIZE);
                self.frame.resize(cols.into(), rows.into());
                self.screen.forget_frame(); // cleared: a view shown again is copied whole
                self.dirty = true;
            }
            Input::FocusLost => self.app.focus_lost(),
            Input::MouseDown { .. } | Input::MouseUp { .. } | Input::Scroll(_) | Input::FocusGained => {}
            // The answers to the REP questions ([`REP_PROBE`]), in order: a terminal that wrote two
            // cells for one space and `CSI b` repeats ASCII glyphs, and frames may send runs of them
            // as REP from now on; one that then wrote three cells for `▀` and `CSI 2 b` repeats
            // block glyphs too (xterm; not tmux), and runs of blocks go as REP as well.
            Input::Reply(Reply::CursorPosition { row, col }) => {
                match (self.rep_probe, rep_answer(row, col)) {
                    (RepProbe::Asked { block }, Some(RepReport::Space(true))) => {
                        self.encoder.set_rep(RepLevel::Ascii);
                        self.rep_probe = if block { RepProbe::SpaceRepeated } else { RepProbe::Done };
                    }
                    (RepProbe::Asked { .. }, Some(RepReport::Space(false)))
                    | (RepProbe::SpaceRepeated, Some(RepReport::Block(false))) => {
                        self.rep_probe = RepProbe::Done;
                    }
                    (RepProbe::SpaceRepeated, Some(RepReport::Block(true))) => {
                        self.encoder.set_rep(RepLevel::Any);
                        self.rep_probe = RepProbe::Done;
                    }
                    _ => {} // not an answer to a question still open
                }
            }
            // The answer to the kitty keyboard query ([`ask_keyboard_flags`](Self::ask_keyboard_flags)):
            // flag 2 (report event types) means key releases will come. Unasked, it is ignored.
            Input::Reply(Reply::KeyboardFlags(flags)) => {
                if std::mem::take(&mut self.keyboard_query) {
                    self.app.releases = flags & 2 != 0;
                }
            }
            Input::Reply(Reply::DeviceAttributes) => {
                // Everything the terminal had to say about the questions before it came before this.
                if matches!(self.truecolor_query, TruecolorQuery::Open(_)) {
                    self.truecolor_query = TruecolorQuery::Closed;
                }

                self.flow.answered(now);
            }
            // An answer to the truecolor questions ([`ask_truecolor`](Self::ask_truecolor)): a yes
            // raises the depth to truecolor, once, with a full repaint; a no changes nothing (the
            // environment's depth stays). Unasked or late, it is ignored.
            Input::Reply(Reply::DirectColor(yes)) => {
                let open = match self.truecolor_query {
                    TruecolorQuery::Asked => true,
                    TruecolorQuery::Open(since) => now - since <= ACK_TIMEOUT,
                    TruecolorQuery::Closed => false,
                };
                if yes && open {
                    self.truecolor_query = TruecolorQuery::Closed;
                    if self.app.options.color_depth != ColorDepth::TrueColor {
                        self.app.options.color_depth = ColorDepth::TrueColor;
                        self.encoder.invalidate();
                        self.dirty = true;
                    }
                }
            }
        }
    }

    /// Appends the truecolor questions ([`TRUECOLOR_QUERY`]), to send before the first frame (after
    /// the host entered game mode), when the colour depth is the environment's guess
    /// ([`plan_color_depth`](mazewalk_term::caps::plan_color_depth) says whether to ask): a terminal
    /// that says it shows 24-bit colour gets it from then on (a full repaint); one that says nothing,
    /// no, or garbage keeps the depth the walk started with. Answers count until the terminal has
    /// answered the device-attributes query that follows the first frame (with flow control off, one
    /// is sent here), or for [`ACK_TIMEOUT`] — never later: a pasted or forged answer cannot change
    /// the colours of a walk under way.
    pub fn ask_truecolor(&mut self, out: &mut Vec<u8>) {
        out.extend_from_slice(TRUECOLOR_QUERY);
        if !self.options.flow_control {
            out.extend_from_slice(QUERY); // the fence the frames would have sent
        }
        self.truecolor_query = TruecolorQuery::Asked;
    }

    /// The colour depth frames are drawn at (the truecolor questions may have raised it).
    #[must_use]
    pub fn color_depth(&self) -> ColorDepth {
        self.app.options.color_depth
    }

    /// Appends the kitty keyboard query (`CSI ? u`, after the host pushed its flags): its answer says
    /// whether key releases will come (terminals without the protocol ignore it).
    pub fn ask_keyboard_flags(&mut self, out: &mut Vec<u8>) {
        out.extend_from_slice(KEYBOARD_QUERY);
        self.keyboard_query = true;
    }

    /// The terminal's screen was lost (a stop, a reconnect): the next frame paints everything, and
    /// held keys are let go (their releases may have been missed).
    pub fn invalidate(&mut self) {
        self.encoder.invalidate();
        self.app.focus_lost();
        self.dirty = true;
    }

    /// The terminal may show something else than the last frame (another program wrote to it; the
    /// `Ctrl-L` key, a SIGWINCH at the same size): the next frame clears the screen and paints
    /// everything from an absolute position, trusting nothing of what it showed or where its cursor
    /// is. Unlike [`invalidate`](Self::invalidate), held keys stay held.
    pub fn repaint(&mut self) {
        self.encoder.invalidate();
        self.dirty = true;
    }

    /// Whether `Ctrl-Z` asked for a stop since the last call (the host decides what a stop is).
    pub fn take_suspend(&mut self) -> bool {
        std::mem::take(&mut self.suspend)
    }

    /// Whether the player quit (q, Esc, Ctrl-C).
    #[must_use]
    pub fn is_over(&self) -> bool {
        self.app.quit
    }

    /// Frames and bytes so far, and the time to the exit if it was reached.
    #[must_use]
    pub fn outcome(&self) -> Outcome {
        Outcome { finished: self.app.finished, ..self.outcome }
    }

    /// When to call [`frame`](Self::frame) next, if nothing arrives before: a frame is due, held keys
    /// move the viewer, a hold runs out, or an unfinished input sequence times out. `None`: nothing
    /// will change until input arrives.
    #[must_use]
    pub fn next_wake(&self, now: f64) -> Option<f64> {
        let interval = self.frame_interval();
        let frame_due = self.last_frame + interval;
        let ghost_moving = self.ghost_at(now).is_some_and(|(_, moving)| moving);
        let animating = self.app.is_animating(now) || ghost_moving;
        let drawing = match self.flow.deadline() {
            // Nothing to draw: no frame is held back, whatever is in flight (a deadline kept after it
            // passed would wake the host at once, again and again, on a stalled link).
            _ if !self.dirty && !animating => None,
            // Held back by flow control: wait for a reply (input) or the timeout, ticking the motion
            // on meanwhile so that the next frame shows where the viewer has got to.
            Some(timeout) if self.options.flow_control => {
                let ticking = animating.then_some(now + interval);
                Some(ticking.map_or(timeout, |t| t.min(timeout)))
            }
            _ => Some(frame_due),
        };
        // The exit clock's next tick (if the frame is held back, the reply that lets it go wakes the
        // host), and the open player list's times, which tick each second too.
        let tick = self.running_clock(now).map(|s| self.app.started + (s + 1) as f64);
        let roster = self.screen.show_roster.then(|| now.floor() + 1.0);
        // The exact frame after a still moment; held back by flow control, the reply or its deadline.
        let settle = self.approximate.then(|| match self.flow.deadline() {
            Some(timeout) if self.options.flow_control => timeout.max(self.last_frame + SETTLE_AFTER),
            _ => self.last_frame + SETTLE_AFTER,
        });
        // Never before `now` (a frame due long ago, a session that has ended): a host sleeps until then.
        let wake = [drawing, tick, roster, settle, self.app.held.next_expiry(), self.decoder.deadline()];
        wake.into_iter().flatten().reduce(f64::min).map(|t| if t.is_nan() { now } else { t.max(now) })
    }

    /// The shortest time between two frames (seconds): [`MAX_FPS`]'s, or longer where the
    /// [`sample_rate`](SessionOptions::sample_rate) bound asks for it (a 400×150 screen in sextants is
    /// 360,000 samples a frame).
    #[must_use]
    pub fn frame_interval(&self) -> f64 {
        // (an ASCII cell, one sample, costs about a half-block cell's two: its glyph and colours)
        let (sx, sy) = self.app.options.charset.samples_per_cell();
        let samples = (self.frame.width() * self.frame.height() * (sx * sy).max(2)) as f64;
        let bound = self.options.sample_rate.map_or(0.0, |rate| samples / f64::from(rate.max(1)));
        bound.max(1.0 / MAX_FPS)
    }

    /// The end-to-end flow control's state (frames in flight, the terminal's reply time).
    #[must_use]
    pub fn flow(&self) -> &FlowControl {
        &self.flow
    }

    /// Brings the walk to time `now` and, if the picture changed and a frame is due (at most
    /// [`MAX_FPS`] a second), draws it and appends its bytes to `out`: only what changed since the
    /// last frame. Returns whether a frame was drawn (it may still be 0 bytes).
    pub fn frame(&mut self, now: f64, out: &mut Vec<u8>) -> bool {
        if self.truecolor_query == TruecolorQuery::Asked {
            self.truecolor_query = TruecolorQuery::Open(now);
        }
        self.decode(now, |decoder, out| decoder.expire(now, out)); // a lone Esc, a stalled sequence
        self.dirty |= self.app.tick(now);
        let ghost =
            self.ghost_at(now).zip(self.ghost_run.as_ref()).map(|((pose, _), (_, caption))| (pose, caption));
        if ghost.map(|(p, c)| (p, c.as_str())) != self.screen.ghost.as_ref().map(|(p, c)| (*p, c.as_str())) {
            self.screen.ghost = ghost.map(|(p, c)| (p, c.clone()));
            self.dirty = true;
        }
        self.dirty |= self.screen.show_roster && now.floor() > self.last_frame.floor(); // its times tick
        let clock = self.running_clock(now);
        let ticked = clock != self.clock_shown; // only the HUD's clock, if nothing else changed
        if self.app.quit {
            return false;
        }
        if !(self.dirty || ticked) {
            return self.settle(now, out);
        }
        if now < self.last_frame + self.frame_interval() {
            return false;
        }
        if self.options.flow_control && !self.flow.may_send(now) {
            return false; // the picture stays dirty: the next frame, once allowed, shows the latest
        }
        while self.recent_frames.front().is_some_and(|&t| t <= now - 1.0) {
            self.recent_frames.pop_front();
        }
        self.recent_frames.push_back(now);
        let hud =
            Hud { cost: self.cost, fps: self.recent_frames.len(), elapsed: now - self.app.started, now };
        let round_trip = self.flow.round_trip().filter(|_| self.options.flow_control);
        // The cells of the frame that may have changed since the last one encoded: the whole frame,
        // or only the HUD's row on a tick of its clock (its digits alone, where nothing else changed).
        let tick = !self.dirty;
        let changed = if self.dirty {
            self.screen.slow_link = slow_link(self.screen.slow_link, round_trip);
            // (the session's frame is kept from frame to frame, changed only here, in the HUD's row
            // and by a resize, which tells the screen)
            screen::draw_kept(&self.app, &mut self.screen, &mut self.frame, &hud);
            self.note_seen();
            0..self.frame.cells().len()
        } else {
            screen::draw_hud(&self.app, &mut self.screen, &mut self.frame, &hud) // the view is as it was
        };
        self.encoder.set_tolerance(adaptive_tolerance(self.options.color_tolerance, round_trip));
        // (the ascii charset is for terminals or fonts without block glyphs: none of its own)
        self.encoder.set_blocks(self.app.options.charset != Charset::Ascii);
        let before = out.len();
        if self.rep_probe == RepProbe::NotAsked {
            // Before the first frame, whose full paint clears the screen over the probe's cells; in
            // the ascii charset only its ASCII question (no block glyph is ever sent, so none is asked).
            let ascii = self.app.options.charset == Charset::Ascii;
            out.extend_from_slice(if ascii { REP_PROBE_ASCII } else { REP_PROBE });
            self.rep_probe = RepProbe::Asked { block: !ascii };
        }
        // (a tick's frame: the clock's cells encoded, not the whole frame scanned for them)
        let stats = self.encoder.encode_cells(&self.frame, changed, out);
        // A tick goes without the query: its few bytes (a digit or two of the clock) need no pacing,
        // and an idle player's terminal answering each second was half a served tick's packets and
        // its second wake (BENCHMARKS, "An idle player's clock tick").
        if self.options.flow_control && !tick {
            out.extend_from_slice(QUERY);
            self.flow.sent(now);
        }
        self.cost = FrameCost { bytes: stats.bytes, ..self.cost }; // the seconds: from the host
        self.outcome.frames += 1;
        self.outcome.bytes += (out.len() - before) as u64;
        (self.dirty, self.last_frame, self.clock_shown) = (false, now, clock);
        self.approximate = stats.approximate;
        true
    }

    /// The last frame again at tolerance 0, once the picture has held still for [`SETTLE_AFTER`], if
    /// the screen shows it only within the tolerance: only the cells left off are sent. Returns
    /// whether it was sent.
    fn settle(&mut self, now: f64, out: &mut Vec<u8>) -> bool {
        if !self.approximate || now < self.last_frame + SETTLE_AFTER {
            return false;
        }
        if self.options.flow_control && !self.flow.may_send(now) {
            return false; // a reply (input) or the flow's deadline wakes the host again
        }
        self.encoder.set_tolerance(0);
        let before = out.len();
        let stats = self.encoder.encode(&self.frame, out);
        if self.options.flow_control && stats.bytes > 0 {
            out.extend_from_slice(QUERY);
            self.flow.sent(now);
        }
        self.outcome.bytes += (out.len() - before) as u64;
        self.approximate = false;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_render::RenderOptions;
    use mazewalk_term::frame::{Cell, Color};

    /// Frames left within the colour tolerance while walking are sent once more, exactly, once the
    /// picture holds still: the screen then shows the frame itself, and nothing more is sent.
    #[test]
    fn a_still_picture_settles_to_the_exact_frame_once() {
        let mut s = no_exit_session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        let mut out = Vec::new();
        s.frame(0.0, &mut out);
        s.feed(b"w", 0.05); // a tap: one step forward, drawn over a few frames
        let mut t = 0.05;
        while t < 0.6 && (t < 0.1 || s.dirty || s.app.is_animating(t)) {
            t += 1.0 / MAX_FPS;
            s.frame(t, &mut out);
        }
        assert!(s.approximate, "the step's last frame is within the tolerance somewhere");
        let last = s.last_frame;
        // Before the settle: the screen is off the frame somewhere (an exact encode would send bytes).
        let mut probe = s.encoder.clone();
        probe.set_tolerance(0);
        assert!(probe.encode(&s.frame, &mut Vec::new()).bytes > 0);
        assert!(!s.frame(last + SETTLE_AFTER / 2.0, &mut out), "not before the picture holds still");
        // The host sleeps from wake to wake (a tap's hold running out, …) until the settle is due.
        let (mut at, mut woken) = (last + SETTLE_AFTER / 2.0, false);
        for _ in 0..10 {
            let wake = s.next_wake(at).expect("the host is woken to settle");
            if wake >= last + SETTLE_AFTER - 1e-9 {
                assert!((wake - (last + SETTLE_AFTER)).abs() < 1e-9, "{wake}");
                woken = true;
                break;
            }
            assert!(!s.frame(wake, &mut out), "nothing to send before the settle, at {wake}");
            at = wake;
        }
        assert!(woken);
        let before = out.len();
        assert!(s.frame(last + SETTLE_AFTER, &mut out), "settled");
        assert!(out.len() > before);
        let mut exact = s.encoder.clone();
        exact.set_tolerance(0);
        assert_eq!(exact.encode(&s.frame, &mut Vec::new()).bytes, 0, "the screen is the frame");
        assert!(!s.frame(last + 2.0, &mut out), "settled once, then quiet");
        assert_eq!(s.next_wake(last + 2.0), None);
    }

    /// Issue #42: a clock tick encodes only the HUD's row, and sends what an encode of the whole
    /// frame would: at a tick while the screen is off the view within the tolerance (the settle
    /// not yet sent), and at one after the settle made it exact.
    #[test]
    fn a_clock_tick_sends_the_bytes_of_the_whole_frame_for_its_hud_row() {
        let app = App::new(mazewalk_maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
        let mut s =
            Session::new(app, 120, 40, SessionOptions { flow_control: false, ..SessionOptions::default() });
        let mut out = Vec::new();
        s.frame(0.0, &mut out);
        s.feed(b"w", 0.05); // a tap: one step forward, drawn over a few frames
        let mut t = 0.05;
        while t < 0.1 || s.dirty || s.app.is_animating(t) {
            t += 1.0 / MAX_FPS;
            s.frame(t, &mut out);
        }
        assert!(s.approximate, "the step's last frame is within the tolerance somewhere");
        let second = t.floor() + 1.0;
        // The first tick before the settle (a host woken late), the second after it.
        for (at, approximate) in [(second, true), (second + 1.0, false)] {
            if !approximate {
                assert!(s.frame(at - 0.5, &mut out), "settled");
                assert!(!s.approximate);
            }
            let (view, mut whole) = (s.frame.clone(), s.encoder.clone());
            out.clear();
            assert!(s.frame(at, &mut out), "a tick at {at}");
            let rows = s.frame.height();
            assert_eq!(s.frame.cells()[..(rows - 1) * 120], view.cells()[..(rows - 1) * 120], "only the HUD");
            assert_ne!(s.frame.row(rows - 1), view.row(rows - 1), "the clock's row changed");
            whole.set_tolerance(adaptive_tolerance(s.options.color_tolerance, None));
            let mut expected = Vec::new();
            let stats = whole.encode(&s.frame, &mut expected);
            assert_eq!(out, expected, "at {at}");
            assert!(!out.is_empty() && out.len() < 120, "a tick's bytes: {}", out.len());
            assert_eq!((s.approximate, stats.approximate), (approximate, approximate), "at {at}");
        }
    }

    /// Issue #42: with flow control, a frame ends with the query and counts as in flight; a tick of
    /// the exit clock (the HUD's row alone) sends no query and leaves the count as it was, so an
    /// idle player's terminal is not asked to answer every second; the next frame asks again.
    #[test]
    fn a_clock_tick_goes_without_the_flow_controls_query() {
        let mut s = session(SessionOptions::default());
        let mut out = Vec::new();
        assert!(s.frame(0.0, &mut out));
        assert!(out.ends_with(QUERY), "a frame ends with the query");
        s.feed(b"\x1b[?62;22c", 0.05); // its answer
        s.frame(0.05, &mut Vec::new());
        assert_eq!(s.flow().in_flight(), 0);
        for second in 1..=3 {
            // (whatever else is due first: the settle's exact frame, its answer)
            s.frame(f64::from(second) - 0.5, &mut Vec::new());
            if s.flow().in_flight() > 0 {
                s.feed(b"\x1b[?62;22c", f64::from(second) - 0.4);
            }
            assert_eq!(s.flow().in_flight(), 0);
            let at = f64::from(second);
            assert_eq!(s.next_wake(at - 0.3), Some(at), "the clock wakes the host");
            out.clear();
            assert!(s.frame(at, &mut out), "the tick at {at}");
            assert!(!out.is_empty(), "the clock's digits");
            let queries = out.windows(QUERY.len()).filter(|w| *w == QUERY).count();
            assert_eq!(queries, 0, "a tick asks nothing: {:?}", String::from_utf8_lossy(&out));
            assert_eq!(s.flow().in_flight(), 0, "a tick is not waited for");
        }
        s.feed(b"\x1b[D", 3.2); // a key: a frame of the view again
        out.clear();
        assert!(s.frame(3.2, &mut out));
        assert!(out.ends_with(QUERY), "the frame after the ticks asks again");
        assert_eq!(s.flow().in_flight(), 1);
    }

    /// The ascii charset is for a terminal or font without block glyphs: its first bytes ask only the
    /// REP probe's ASCII question (a space repeated), so not one byte before the frames is outside
    /// ASCII; the answer still turns REP on after ASCII glyphs, and nothing raises it further.
    #[test]
    fn the_ascii_charset_asks_rep_with_a_space_only() {
        let options = mazewalk_render::RenderOptions {
            charset: mazewalk_render::Charset::Ascii,
            ..mazewalk_render::RenderOptions::default()
        };
        let app = App::new(mazewalk_maze::builtin().unwrap(), options, 0.0).unwrap();
        let mut s =
            Session::new(app, 100, 30, SessionOptions { flow_control: false, ..SessionOptions::default() });
        let mut out = Vec::new();
        assert!(s.frame(0.0, &mut out));
        assert!(out.starts_with(REP_PROBE_ASCII) && !out.starts_with(REP_PROBE), "the space question only");
        assert!(out.is_ascii(), "nothing but ASCII");
        s.feed(b"\x1b[2;3R", 0.1);
        s.feed(b"\x1b[3;4R", 0.2);
        assert_eq!(s.encoder.rep(), RepLevel::Ascii, "the space answered; no block was asked");
    }

    /// Issue #42: the REP probe's two reports, in order, set how far frames use REP: none (no REP),
    /// after ASCII only (tmux: the space repeated, the block not), after any glyph (xterm). Silence,
    /// one report only, reports out of order or of other rows, keys between them, a report arriving
    /// late or answered twice: never more than the terminal said, and a report is never a key.
    #[test]
    fn the_rep_reports_set_the_level_in_order() {
        let report = |row: u16, col: u16| format!("\x1b[{row};{col}R").into_bytes();
        let run = |inputs: &[Vec<u8>]| {
            let mut s = session(SessionOptions { flow_control: false, ..SessionOptions::default() });
            let mut out = Vec::new();
            assert!(s.frame(0.0, &mut out));
            assert!(out.starts_with(REP_PROBE), "asked before the first frame");
            assert_eq!(s.encoder.rep(), RepLevel::None, "off until the terminal answers");
            let (x, y) = (s.app.camera.position, s.app.camera.yaw_deg);
            for (i, bytes) in inputs.iter().enumerate() {
                s.feed(bytes, 0.1 + i as f64 * 0.5);
            }
            let turned = (s.app.camera.position, s.app.camera.yaw_deg) != (x, y);
            assert!(!s.app.quit);
            let mut again = Vec::new();
            s.frame(30.0, &mut again);
            assert!(!again.windows(REP_PROBE.len()).any(|w| w == REP_PROBE), "asked once");
            (s.encoder.rep(), turned)
        };
        let table: &[(&str, Vec<Vec<u8>>, RepLevel)] = &[
            ("silence", vec![], RepLevel::None),
            ("no REP", vec![report(2, 2), report(3, 2)], RepLevel::None),
            ("tmux: ASCII only", vec![report(2, 3), report(3, 2)], RepLevel::Ascii),
            ("xterm: any glyph", vec![report(2, 3), report(3, 4)], RepLevel::Any),
            ("both in one read", vec![[report(2, 3), report(3, 4)].concat()], RepLevel::Any),
            ("only the first answered", vec![report(2, 3)], RepLevel::Ascii),
            ("only the second answered", vec![report(3, 4)], RepLevel::None),
            ("out of order", vec![report(3, 4), report(2, 3)], RepLevel::Ascii),
            ("no REP, then a yes to blocks", vec![report(2, 2), report(3, 4)], RepLevel::None),
            ("a key between the reports", vec![report(2, 3), b"x".to_vec(), report(3, 4)], RepLevel::Any),
            ("an arrow key between", vec![report(2, 3), b"\x1b[1;3C".to_vec(), report(3, 4)], RepLevel::Any),
            ("Alt-F3 (row 1) first", vec![report(1, 3), report(2, 3), report(3, 4)], RepLevel::Any),
            ("Alt-F3 as the block answer", vec![report(2, 3), report(1, 4)], RepLevel::Ascii),
            ("answered twice", vec![report(2, 3), report(3, 2), report(3, 4)], RepLevel::Ascii),
            ("a second probe answer later", vec![report(2, 2), report(2, 3), report(3, 4)], RepLevel::None),
            ("`▀` two cells wide", vec![report(2, 3), report(3, 3)], RepLevel::Ascii),
            (
                "a report split across reads",
                vec![b"\x1b[2;".to_vec(), b"3R\x1b[3".to_vec(), b";4R".to_vec()],
                RepLevel::Any,
            ),
        ];
        for (what, inputs, want) in table {
            // Only the arrow key (Alt-→, `CSI 1 ; 3 C`: a turn) moves the viewer; no report does.
            let arrow = inputs.iter().any(|i| i.ends_with(b"C"));
            assert_eq!(run(inputs), (*want, arrow), "{what}");
        }
    }

    /// Red-team pass 3: a served walk (no developer keys) ignores `b` (culling off: every wall of
    /// the maze drawn), `v` and `i`, which the local walk's keys turn on.
    #[test]
    fn a_walk_without_developer_keys_ignores_b_v_and_i() {
        for developer_keys in [true, false] {
            let mut s = no_exit_session(SessionOptions { flow_control: false, ..SessionOptions::default() });
            s.app_mut().developer_keys = developer_keys;
            s.feed(b"bvi", 0.1);
            let app = s.app();
            assert_eq!(app.options.culling == Culling::None, developer_keys);
            assert_eq!(app.culling_tint, developer_keys);
            assert_eq!(app.figures, developer_keys);
        }
    }

    /// Red-team pass 3: with a sample rate, a screen's frame rate falls with its cells × its
    /// charset's samples per cell (never above [`MAX_FPS`]); frames drawn while turning, in a second.
    #[test]
    fn a_sample_rate_draws_a_large_fine_screen_at_a_lower_frame_rate() {
        let rate = 200 * 60 * 2 * 60;
        let frames_in_a_second = |cols: u16, rows: u16, charset: Charset, sample_rate: Option<u32>| {
            let opts = mazewalk_maze::generate::GenOptions {
                width: 4,
                height: 3,
                exit: false,
                ..Default::default()
            };
            let maze = mazewalk_maze::generate::generate(&opts).unwrap();
            let options = RenderOptions { charset, ..RenderOptions::default() };
            let app = App::new(maze, options, 0.0).unwrap();
            let options = SessionOptions { flow_control: false, sample_rate, ..SessionOptions::default() };
            let mut s = Session::new(app, cols, rows, options);
            let mut out = Vec::new();
            let mut frames = 0;
            for i in 0..1200 {
                let t = f64::from(i) / 1200.0;
                s.input(Input::press(Key::Right), t);
                frames += usize::from(s.frame(t, &mut out));
            }
            frames
        };
        let unbounded = frames_in_a_second(400, 150, Charset::Sextant, None);
        assert!(unbounded >= 55, "{unbounded} frames without a bound");
        for (cols, rows, charset, want) in [
            (120, 40, Charset::Half, 60.0),
            (200, 60, Charset::Half, 60.0),
            (400, 150, Charset::Half, 12.0),
            (400, 150, Charset::Ascii, 12.0), // (counted as 2 samples a cell)
            (400, 150, Charset::Sextant, 4.0),
        ] {
            let frames = frames_in_a_second(cols, rows, charset, Some(rate)) as f64;
            assert!(
                (frames - want).abs() <= 1.0 + want / 20.0,
                "{cols}×{rows} {charset:?}: {frames} frames, not {want}"
            );
        }
    }

    /// A session in a maze without an exit: no clock ticks.
    fn no_exit_session(options: SessionOptions) -> Session {
        let opts =
            mazewalk_maze::generate::GenOptions { width: 4, height: 3, exit: false, ..Default::default() };
        let maze = mazewalk_maze::generate::generate(&opts).unwrap();
        Session::new(App::new(maze, RenderOptions::default(), 0.0).unwrap(), 100, 30, options)
    }

    fn session(options: SessionOptions) -> Session {
        let app = App::new(mazewalk_maze::builtin().unwrap(), mazewalk_render::RenderOptions::default(), 0.0)
            .unwrap();
        Session::new(app, 100, 30, options)
    }

    /// Issue #34: a served maze's player list. Tab opens and closes it, Esc closes it without ending
    /// the walk, its times tick each second while it is open; without a list Tab does nothing.
    #[test]
    fn tab_shows_the_player_list_and_esc_closes_it_not_the_walk() {
        let mut s = session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        let mut out = Vec::new();
        s.frame(0.0, &mut out);
        s.feed(b"\t", 0.1);
        assert!(!s.frame(0.2, &mut out), "no list: Tab does nothing");
        let me = roster::Entry {
            name: "ada".into(),
            label: 'A',
            color: mazewalk_term::frame::Color::Indexed(196),
            joined_at: 0.0,
            best: None,
            me: true,
        };
        s.set_roster(std::slice::from_ref(&me));
        s.set_players_in(Some(1));
        assert!(s.frame(0.3, &mut out));
        assert!(s.screen().lines().last().unwrap().contains("1 in"), "the HUD counts the players");
        s.feed(b"\t", 1.4);
        assert!(s.frame(1.5, &mut out));
        let text = s.screen().lines().join("\n");
        assert!(text.contains("Players: 1") && text.contains("A  ada (you)      0:01"), "{text}");
        assert!(s.next_wake(1.5).is_some_and(|t| t <= 2.0), "its times tick each second");
        assert!(s.frame(2.0, &mut out) && s.screen().lines().join("\n").contains("0:02"));
        s.input(mazewalk_term::input::Input::press(Key::Esc), 2.2);
        assert!(!s.is_over(), "Esc closed the list, not the walk");
        assert!(s.frame(2.3, &mut out));
        assert!(!s.screen().lines().join("\n").contains("Players:"));
    }

    /// A terminal's size, whatever it claims, costs a bounded frame: a side of zero is unknown
    /// (80 × 24), a side past [`MAX_SIZE`] is drawn at it.
    #[test]
    fn any_claimed_size_draws_a_bounded_frame() {
        let mut s = session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        for ((cols, rows), drawn) in [
            ((65535, 65535), MAX_SIZE),
            ((0, 0), DEFAULT_SIZE),
            ((0, 50), (80, 50)),
            ((120, 40), (120, 40)),
            ((1, 1), (1, 1)),
            ((5000, 3), (MAX_SIZE.0, 3)),
        ] {
            s.input(Input::Resize { cols, rows }, 0.0);
            s.frame(0.0, &mut Vec::new());
            let screen = s.screen();
            assert_eq!((screen.width(), screen.height()), (drawn.0.into(), drawn.1.into()), "{cols}×{rows}");
        }
        let huge = Session::new(s.app().clone(), u16::MAX, u16::MAX, SessionOptions::default());
        assert_eq!((huge.screen().width(), huge.screen().height()), (1000, 400));
    }

    #[test]
    fn the_exit_box_also_shows_the_news() {
        let mut s = session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        s.app_mut().finished = Some(83.0);
        s.app_mut().exit_box = true;
        s.set_notice(Some("You reached the exit first, in 1:23.0!".into()));
        s.frame(0.0, &mut Vec::new());
        let text = s.screen().lines().join("\n");
        assert!(text.contains("Found the exit!") && text.contains("You found the exit in 1:23.0."), "{text}");
        assert!(text.contains("You reached the exit first, in 1:23.0!"), "{text}");
    }

    #[test]
    fn with_flow_control_frames_wait_for_replies_and_coalesce() {
        let mut s = session(SessionOptions::default());
        let mut out = Vec::new();
        assert!(s.frame(0.0, &mut out));
        assert!(out.ends_with(QUERY), "each frame ends with the query");
        s.feed(b"\x1b[D", 0.02); // ← tapped: one step
        assert!(s.frame(0.02, &mut out), "a second frame may go before any reply");
        let heading_sent = s.app().camera.yaw_deg;
        // ← held: the terminal's auto-repeat every 30 ms.
        let mut t = 0.05;
        while t < 0.3 {
            s.feed(b"\x1b[D", t);
            assert!(!s.frame(t, &mut out), "two in flight: held back at {t}");
            t += 0.03;
        }
        assert!(s.next_wake(0.3).is_some_and(|t| t > 0.3), "no busy wait while held back");
        assert!(s.app().camera.yaw_deg > heading_sent, "the walk goes on meanwhile");
        s.feed(b"\x1b[?62;22c", 0.4); // the first frame is on screen
        out.clear();
        assert!(s.frame(0.4, &mut out), "a reply lets the latest state out");
        assert_eq!(s.flow().in_flight(), 2);
    }

    #[test]
    fn ctrl_or_alt_letters_are_not_the_letters_and_wake_ups_are_never_in_the_past() {
        use mazewalk_term::input::{Modifiers, Protocol, encode};
        let mut s = session(SessionOptions::default());
        s.frame(0.0, &mut Vec::new());
        for modifiers in [
            Modifiers { ctrl: true, ..Modifiers::default() },
            Modifiers { alt: true, ..Modifiers::default() },
        ] {
            for c in ['q', 'w', 'm'] {
                let key =
                    Input::Key { key: Key::Char(c), phase: mazewalk_term::input::KeyPhase::Press, modifiers };
                if let Some(bytes) = encode(&key, Protocol::Legacy) {
                    s.feed(&bytes, 0.1); // as the bytes a terminal sends
                }
                s.input(key, 0.1);
            }
        }
        assert!(!s.is_over(), "Ctrl-Q and Alt-Q do not quit");
        assert_eq!(s.app().camera.position, s.app().maze().viewer().pos, "Ctrl-W / Alt-W do not walk");
        s.feed(b"q", 0.2);
        assert!(s.is_over());
        assert!(s.next_wake(0.3).is_none_or(|t| t >= 0.3), "{:?}", s.next_wake(0.3));
    }

    /// QA finding 1: another program's output garbles the picture; Ctrl-L paints it all again.
    #[test]
    fn ctrl_l_paints_the_whole_frame_again_from_an_absolute_position() {
        let mut s = no_exit_session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        let mut first = Vec::new();
        assert!(s.frame(0.0, &mut first));
        let mut out = Vec::new();
        assert!(!s.frame(1.0, &mut out) && out.is_empty(), "at rest: nothing to send");
        s.feed(b"\x0c", 1.0); // Ctrl-L, as a terminal sends it
        assert!(!s.is_over());
        assert!(s.frame(1.0, &mut out));
        let text = String::from_utf8_lossy(&out);
        // The screen cleared, then the first move absolute (`CSI row;col H`): no trust in the cursor.
        let after = &text[text.find("\x1b[2J").expect("the screen is cleared") + 4..];
        let cup = after.strip_prefix("\x1b[").map(|rest| rest.split_once('H').map(|(at, _)| at));
        assert!(
            cup.flatten().is_some_and(|at| at.chars().all(|c| c.is_ascii_digit() || c == ';')),
            "{text:?}"
        );
        // The same bytes as the full paint after a stop ends ([`Session::invalidate`]).
        let mut resumed =
            no_exit_session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        resumed.frame(0.0, &mut Vec::new());
        resumed.invalidate();
        let mut full = Vec::new();
        assert!(resumed.frame(1.0, &mut full));
        assert_eq!(out, full);
        assert_eq!(s.app().camera.position, s.app().maze().viewer().pos, "Ctrl-L is no `l`");
        // Its release (kitty's protocol) paints nothing more.
        out.clear();
        s.feed(b"\x1b[108;5:3u", 2.0);
        assert!(!s.frame(2.0, &mut out) && out.is_empty(), "{:?}", String::from_utf8_lossy(&out));
    }

    /// QA finding 6: with bracketed paste on (game mode turns it on), an accidental paste plays
    /// none of its letters: no `r` reset, no `q` quit, no step; keys after it count again.
    #[test]
    fn a_bracketed_paste_plays_no_keys() {
        let mut s = no_exit_session(SessionOptions { flow_control: false, ..SessionOptions::default() });
        s.frame(0.0, &mut Vec::new());
        let start = s.app().camera;
        s.feed(b"\x1b[200~see https://example.org/maze?id=42 wwww", 0.1);
        s.feed(&[b'q'; 100_000], 0.2); // a long one, in several reads: dropped as it comes
        s.feed(b"\x1b[C r q\x1b[201~", 0.3);
        s.frame(0.4, &mut Vec::new());
        assert!(!s.is_over(), "a pasted q does not quit");
        assert_eq!(s.app().camera, start, "nothing pasted moved or turned the viewer");
        s.feed(b"w", 1.0);
        s.frame(1.1, &mut Vec::new());
        assert_ne!(s.app().camera.position, start.position, "a key after the paste walks");
        s.feed(b"q", 1.2);
        assert!(s.is_over());
    }

    #[test]
    fn a_stalled_link_with_nothing_to_draw_sleeps() {
        // Two frames unanswered (the link stalled, or a terminal that never answers), then the
        // picture stops changing: nothing is held back, so nothing is due, before or after the
        // reply timeout (it used to stay due at the timeout: a host waking at once, forever). (A maze
        // with no exit: an exit's clock ticks every second.)
        let mut s = no_exit_session(SessionOptions::default());
        let mut out = Vec::new();
        assert!(s.frame(0.0, &mut out));
        s.feed(b"m", 0.1); // the map: one change, no motion
        assert!(s.frame(0.1, &mut out));
        assert_eq!(s.flow().in_flight(), 2);
        assert!(!s.frame(0.2, &mut out));
        assert!(s.next_wake(0.2).is_some_and(|t| t > 0.2), "the key's hold runs out, later");
        for now in [1.0, 2.5, 10.0] {
            assert!(!s.frame(now, &mut out), "nothing new at {now}");
            assert_eq!(s.next_wake(now), None, "asleep at {now}");
        }
        s.feed(b"m", 11.0); // a change past the timeout goes out at once
        assert!(s.frame(11.0, &mut out));
    }

    #[test]
    fn a_stalled_link_gets_a_frame_a_timeout_not_a_flood() {
        // The terminal answered, then its link stalled while ← was held (auto-repeat keeps coming
        // from a stopped client's buffers, say): frames go one per ACK_TIMEOUT, not 60 a second.
        let mut s = session(SessionOptions::default());
        let mut out = Vec::new();
        s.frame(0.0, &mut out);
        s.feed(b"\x1b[?62;22c", 0.05);
        let (mut drawn, mut t) = (0, 0.1);
        while t < 10.1 {
            s.feed(b"\x1b[D", t);
            drawn += usize::from(s.frame(t, &mut out));
            assert!(s.next_wake(t).is_some_and(|w| w > t), "no busy wait at {t}");
            t += 0.03;
        }
        let probes = (10.0 / crate::flow::ACK_TIMEOUT) as usize;
        assert!((2..=2 + probes + 1).contains(&drawn), "{drawn} frames in 10 s");
        s.feed(b"\x1b[?62;22c", 10.2); // the link is back: frames flow again
        assert!(s.frame(10.2, &mut out));
    }

    #[test]
    fn without_replies_the_walk_goes_on_after_the_timeout() {
        let mut s = session(SessionOptions::default());
        let mut out = Vec::new();
        s.frame(0.0, &mut out);
        s.feed(b"w", 0.1);
        s.frame(0.1, &mut out);
        s.feed(b"w", 0.2);
        assert!(!s.frame(0.2, &mut out));
        assert!(s.frame(0.1 + crate::flow::ACK_TIMEOUT, &mut out));
        assert!(s.flow().silent());
        s.feed(b"w", 3.0);
        assert!(s.frame(3.0, &mut out), "silent: no waiting");
    }

    /// The 3D view's cells (all rows but the HUD) as drawn by a fresh session at 256 colours.
    /// Issue #42: a served player's view is rendered only when what it is drawn from changed.
    /// Another player turning on the spot (a figure and a map label show no heading) draws no frame;
    /// the HUD's count of players changing alone draws a frame without a render, and that frame is,
    /// cell for cell, the one a session drawing it all afresh shows; the other stepping renders.
    #[test]
    fn a_frame_renders_the_view_only_when_the_view_changed() {
        let options = SessionOptions { flow_control: false, ..SessionOptions::default() };
        let mut s = no_exit_session(options);
        let camera = s.app().camera;
        let ahead = camera.position + 0.8 * glam::Vec2::from_angle(camera.yaw_deg.to_radians());
        let peer =
            Peer { position: ahead, heading_deg: 0.0, initial: 'B', color: Color::Indexed(196), cell: None };
        let mut out = Vec::new();
        assert!(s.set_peers(&[peer]));
        assert!(s.frame(0.0, &mut out));
        assert_eq!(s.renders(), 1);
        let mut alone = no_exit_session(options);
        alone.frame(0.0, &mut Vec::new());
        assert_ne!(view_cells(&s), view_cells(&alone), "the other player shows in the view");

        let turned = Peer { heading_deg: 90.0, ..peer };
        assert!(!s.set_peers(&[turned]), "turning on the spot changes no picture");
        assert!(!s.frame(0.1, &mut out), "so no frame is drawn");
        s.set_players_in(Some(2));
        assert!(s.frame(0.2, &mut out), "the HUD's count changed");
        assert_eq!(s.renders(), 1, "the view did not: shown again, not rendered");
        let mut fresh = no_exit_session(options);
        fresh.set_peers(&[turned]);
        fresh.set_players_in(Some(2));
        fresh.frame(0.0, &mut Vec::new());
        assert_eq!(fresh.renders(), 1);
        assert_eq!(s.screen().cells(), fresh.screen().cells(), "what a full render draws");

        let stepped = Peer { position: ahead + glam::Vec2::new(0.05, 0.05), ..turned };
        assert!(s.set_peers(&[stepped]));
        assert!(s.frame(0.3, &mut out));
        assert_eq!(s.renders(), 2, "the view changed: rendered");
        fresh.set_peers(&[stepped]);
        fresh.frame(0.3, &mut Vec::new());
        assert_eq!(s.screen().cells(), fresh.screen().cells());

        // A third player walking where the view does not reach: on the map, not in the view.
        let maze = s.app().maze();
        let away: Vec<(glam::Vec2, u32)> = (0..maze.cell_count() as u32)
            .filter(|&c| !s.sees_cell(c))
            .map(|c| (maze.cell_centroid(c), c))
            .take(2)
            .collect();
        assert_eq!(away.len(), 2, "cells the view does not reach");
        let far =
            |(position, cell): (glam::Vec2, u32)| Peer { position, cell: Some(cell), initial: 'C', ..peer };
        assert!(s.set_peers(&[stepped, far(away[0])]));
        assert!(s.frame(0.4, &mut out));
        let renders = s.renders();
        assert!(s.set_peers(&[stepped, far(away[1])]), "it moved");
        assert!(s.frame(0.5, &mut out));
        assert_eq!(s.renders(), renders, "where the view does not reach: not rendered");
        fresh.set_peers(&[stepped, far(away[1])]);
        fresh.frame(0.5, &mut Vec::new());
        assert_eq!(s.screen().cells(), fresh.screen().cells());
    }

    fn view_cells(s: &Session) -> Vec<Cell> {
        let frame = s.screen();
        frame.cells()[..frame.width() * (frame.height() - 1)].to_vec()
    }

    #[test]
    fn a_slow_link_stops_dithering_and_a_fast_one_brings_it_back() {
        use mazewalk_term::frame::ColorDepth;
        let options = RenderOptions { color_depth: ColorDepth::Ansi256, ..RenderOptions::default() };
        let app =
            |dither| App::new(mazewalk_maze::builtin().unwrap(), RenderOptions { dither, ..options }, 0.0);
        let still = |dither| {
            let mut s = Session::new(app(dither).unwrap(), 100, 30, SessionOptions::default());
            s.frame(0.0, &mut Vec::new());
            view_cells(&s)
        };
        let (dithered, plain) = (still(true), still(false));
        assert_ne!(dithered, plain, "the built-in view has colours between palette entries");

        let mut s = Session::new(app(true).unwrap(), 100, 30, SessionOptions::default());
        let mut out = Vec::new();
        let mut t = 0.0;
        // Each frame answered 0.4 s after it went: the link is slow.
        for _ in 0..4 {
            assert!(s.frame(t, &mut out));
            s.feed(b"\x1b[?62;22c", t + 0.4);
            t += 0.4;
            s.invalidate();
        }
        assert!(s.frame(t, &mut out));
        assert_eq!(view_cells(&s), plain, "slow: nearest entries only");
        // Then answered at once, until the round trip has settled under 0.08 s.
        for _ in 0..20 {
            s.feed(b"\x1b[?62;22c", t + 0.01);
            t += 0.02;
            s.invalidate();
            assert!(s.frame(t, &mut out));
        }
        assert_eq!(view_cells(&s), dithered, "fast again: dithered");
    }

    #[test]
    fn slow_replies_raise_the_colour_tolerance() {
        assert_eq!(adaptive_tolerance(1, None), 1);
        // Slow past 0.15 s, fast again under 0.08 s, as it was in between.
        assert!(!slow_link(false, None) && !slow_link(true, None));
        assert!(slow_link(false, Some(0.2)) && !slow_link(false, Some(0.1)) && slow_link(true, Some(0.1)));
        assert!(!slow_link(true, Some(0.05)));
        assert_eq!(adaptive_tolerance(1, Some(0.05)), 1);
        assert_eq!(adaptive_tolerance(1, Some(0.2)), 4);
        assert_eq!(adaptive_tolerance(1, Some(1.0)), 7);
        assert_eq!(adaptive_tolerance(15, Some(1.0)), encoder::MAX_TOLERANCE);
    }
}
