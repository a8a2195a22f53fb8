//! One connected player, without the connection: a [`Session`] plus what a remote terminal needs that
//! a local one gets from the guard — entering and leaving game mode in bytes, the pty's size clamped,
//! colour depth and glyphs from the pty's `TERM` and what the client's environment said
//! ([`ClientTerminal`]), the input rate limited —
//! and the game's rules for one player in a shared world: how often it looks at the others
//! ([`Player::look_due`], at most [`WORLD_LOOKS_PER_SECOND`]), which of them it draws, the winner's
//! notice (shown once, for [`NOTICE_SECONDS`]), and what the world learns from it ([`Player::news`]:
//! where it is, and each walk's finish, once: `r` walks it again, and that finish counts too).
//!
//! Pure: bytes, sizes and looks at the world in, bytes and news out, time as seconds; the SSH side
//! ([`super::ssh`]) moves bytes and holds the world's lock for the data only, and the `serve` fuzz
//! target drives this type with any bytes and window changes.

use std::sync::Arc;

use glam::Vec2;

use super::limits::{Limits, RateLimit};
use super::spawn::Spot;
use super::world::{Look, PlayerId, WalkClock};
use mazewalk_maze::Maze;
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::caps;
use mazewalk_term::frame::ColorDepth;
use mazewalk_term::input::Input;
use mazewalk_term::modes::{Enabled, enter_sequence, restore_sequence};
use mazewalk_walk::overlay::Peer;
use mazewalk_walk::roster;
use mazewalk_walk::session::fit_size;

use mazewalk_walk::state::StartOutsideMaze;
use mazewalk_walk::{App, Session, SessionOptions};

/// What a remote terminal is asked to turn on: everything the local walk uses. The kitty keyboard
/// flags are pushed blind (terminals without the protocol ignore the push and the pop) and then
/// queried: only a terminal whose answer says so is trusted to report key releases.
pub const REMOTE: Enabled = Enabled { mouse: true, focus_events: true, keyboard_enhancement: true };

/// How long the announcement of the first player at the exit stays on screen, seconds.
pub(crate) const NOTICE_SECONDS: f64 = 8.0;

/// A player looks at the others at most this often a second (their moves coalesce meanwhile).
pub(crate) const WORLD_LOOKS_PER_SECOND: f64 = 30.0;

/// What the HUD says while a shared world's Redis is away (`--world`).
pub(crate) const WORLD_OFFLINE: &str = "world offline";

/// What the HUD says while the host records the player's session (`serve --record-dir`).
pub const RECORDED: &str = "recorded";

/// A terminal size from a pty request or window change: zero means "not given" (RFC 4254 §6.2), the
/// rest is clamped to the limits (the picture is drawn at most that large, in the top-left corner).
#[must_use]
pub(crate) fn clamp_size(cols: u32, rows: u32, limits: &Limits) -> (u16, u16) {
    fit_size(cols, rows, (limits.max_cols, limits.max_rows))
}

/// The window changes a served screen follows: at most [`Limits::resize_rate`] a second, the latest
/// size winning among those that came sooner (a window dragged to a new size ends at that size; a
/// flood of window changes costs one screen's reallocation per turn, not one per change).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Resizes {
    /// The size asked for last and not yet drawn.
    pending: Option<(u16, u16)>,
    /// When a size was last taken to be drawn.
    last: f64,
    /// Seconds between two sizes drawn.
    interval: f64,
}

impl Resizes {
    pub(crate) fn new(limits: &Limits) -> Resizes {
        let rate = if limits.resize_rate > 0.0 { limits.resize_rate } else { f64::INFINITY };
        Resizes { pending: None, last: f64::NEG_INFINITY, interval: 1.0 / rate }
    }

    /// The client asked for a `cols × rows` window (as its request gave them) at `now`: clamped to
    /// `limits`, it waits its turn.
    pub(crate) fn ask(&mut self, cols: u32, rows: u32, limits: &Limits) {
        self.pending = Some(clamp_size(cols, rows, limits));
    }

    /// The size to draw from `now`, if one waits and its turn has come (it is taken).
    pub(crate) fn take(&mut self, now: f64) -> Option<(u16, u16)> {
        let due = self.due()?;
        if now < due {
            return None;
        }
        self.last = now;
        self.pending.take()
    }

    /// When the size waiting is to be drawn (`None`: none waits).
    #[must_use]
    pub(crate) fn due(&self) -> Option<f64> {
        self.pending.map(|_| self.last + self.interval)
    }
}

/// Applies the size `resizes` lets through at `now` to `session` (nothing if it is the size drawn).
pub(crate) fn apply_resize(resizes: &mut Resizes, session: &mut Session, now: f64) {
    if let Some((cols, rows)) = resizes.take(now) {
        let screen = session.screen();
        if (cols, rows) != (screen.width() as u16, screen.height() as u16) {
            session.input(Input::Resize { cols, rows }, now);
        }
    }
}

/// A served terminal as its SSH client described it: the pty request's `TERM` and the environment
/// variables sent with the session (`SendEnv`: Debian's and macOS's `ssh` send `LANG` and `LC_*` by
/// default) that choose the picture as they do locally: `COLORTERM` and `NO_COLOR` the colour depth
/// ([`caps::plan_color_depth`]), the locale (`LC_ALL`, `LC_CTYPE`, `LANG`, by tmux's rule:
/// [`caps::locale_is_utf8`]) whether block glyphs show or ASCII is drawn. Each value is cut at
/// [`MAX_CLIENT_VALUE`] characters; other variables are refused and not kept.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ClientTerminal {
    term: String,
    env: [Option<String>; ClientTerminal::ENV.len()],
}

/// The longest `TERM` or environment value a [`ClientTerminal`] keeps (they only pick the picture).
pub const MAX_CLIENT_VALUE: usize = 64;

impl ClientTerminal {
    /// The environment variables kept: the ones that choose the picture.
    pub const ENV: [&'static str; 5] = ["COLORTERM", "NO_COLOR", "LC_ALL", "LC_CTYPE", "LANG"];

    /// A terminal of type `term` (the pty request's), with no environment sent.
    #[must_use]
    pub fn new(term: &str) -> ClientTerminal {
        ClientTerminal { term: bounded(term), env: Default::default() }
    }

    /// The same, with `name` set to `value` (where [`ENV`](Self::ENV) names it).
    #[must_use]
    pub fn with(mut self, name: &str, value: &str) -> ClientTerminal {
        self.set(name, value);
        self
    }

    /// Keeps `name`'s `value` if it is one of [`ENV`](Self::ENV) (the last one sent wins); whether
    /// it was.
    pub fn set(&mut self, name: &str, value: &str) -> bool {
        let slot = Self::ENV.iter().position(|&known| known == name);
        if let Some(k) = slot {
            self.env[k] = Some(bounded(value));
        }
        slot.is_some()
    }

    /// The pty's `TERM`.
    #[must_use]
    pub fn term(&self) -> &str {
        &self.term
    }

    /// `TERM`, or a kept variable's value as the client sent it.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&str> {
        if name == "TERM" {
            return Some(&self.term);
        }
        let k = Self::ENV.iter().position(|&known| known == name)?;
        self.env[k].as_deref()
    }

    /// [`get`](Self::get) as the terminal-detection functions of [`caps`] ask.
    fn lookup(&self) -> impl Fn(&str) -> Option<String> + '_ {
        |name| self.get(name).map(str::to_string)
    }
}

fn bounded(s: &str) -> String {
    s.chars().take(MAX_CLIENT_VALUE).collect()
}

/// The colour depth for a remote terminal: as locally, from its `TERM`, `COLORTERM` and `NO_COLOR`.
#[must_use]
pub fn color_depth(terminal: &ClientTerminal) -> ColorDepth {
    color_plan(terminal).depth
}

/// The walk of a served screen (a player's or a spectator's) on `maze` for `terminal`: half blocks
/// (ASCII on a DEC terminal or in a locale that is not UTF-8: [`caps::detect_block_glyphs`]) in the
/// colour depth it gives ([`color_plan`]), without the developer keys ([`App::developer_keys`]), at
/// time `now`;
/// with the plan, whose question about truecolor the caller asks.
///
/// # Errors
/// The maze's start is in no cell.
pub(crate) fn served_app(
    maze: impl Into<Arc<Maze>>,
    terminal: &ClientTerminal,
    now: f64,
) -> Result<(App, caps::ColorPlan), StartOutsideMaze> {
    let plan = color_plan(terminal);
    let blocks = caps::detect_block_glyphs(terminal.lookup());
    let charset = if blocks { Charset::Half } else { Charset::Ascii };
    let options = RenderOptions { charset, color_depth: plan.depth, ..RenderOptions::default() };
    let mut app = App::new(maze, options, now)?;
    app.developer_keys = false; // culling off (`b`) would draw every wall of the maze, for each of them
    Ok((app, plan))
}

/// The screen of `app` on a `cols × rows` `terminal` (as the pty request gave them, clamped to
/// `limits`).
pub(crate) fn served_session(
    app: App,
    terminal: &ClientTerminal,
    (cols, rows): (u32, u32),
    limits: &Limits,
) -> Session {
    let session_options = SessionOptions {
        bce: caps::detect_bce(terminal.lookup()),
        sample_rate: Some(limits.render_rate),
        ..SessionOptions::default()
    };
    let (cols, rows) = clamp_size(cols, rows, limits);
    Session::new(app, cols, rows, session_options)
}

/// The bytes that put a served terminal (a player's or a spectator's, showing `session`) into game
/// mode before the first frame, with the questions for its truecolor (if `ask_truecolor`; the
/// answer, if any, lives in the session) and its keyboard flags.
pub(crate) fn enter_game(session: &mut Session, ask_truecolor: bool, out: &mut Vec<u8>) {
    out.extend_from_slice(enter_sequence(REMOTE).as_bytes());
    if ask_truecolor {
        session.ask_truecolor(out);
    }
    session.ask_keyboard_flags(out);
}

/// The bytes that give a served terminal back (main screen, cursor shown, keyboard flags popped,
/// mouse and focus reports off), then `message` on a line of its own, if any.
pub(crate) fn leave_game(message: Option<&str>, out: &mut Vec<u8>) {
    out.extend_from_slice(restore_sequence(REMOTE).as_bytes());
    if let Some(message) = message {
        out.extend_from_slice(message.as_bytes());
        out.extend_from_slice(b"\r\n");
    }
}

/// The colour depth a remote terminal starts with and whether to ask it for truecolor
/// ([`caps::plan_color_depth`] with what the client sent: the server knows nothing of the
/// player's terminfo or tmux).
#[must_use]
pub(crate) fn color_plan(terminal: &ClientTerminal) -> caps::ColorPlan {
    caps::plan_color_depth(terminal.lookup(), caps::ColorFacts::default())
}

/// Whether `bytes` are nothing but whole answers a terminal sends by itself: `CSI ? … c` (device
/// attributes, after every frame), `CSI ? … u` (keyboard flags) and `DCS … ST` (the truecolor
/// questions' answers).
#[must_use]
pub(crate) fn only_replies(mut bytes: &[u8]) -> bool {
    while !bytes.is_empty() {
        if let Some(string) = bytes.strip_prefix(b"\x1bP") {
            let Some(end) = string.windows(2).position(|w| w == b"\x1b\\") else { return false };
            bytes = &string[end + 2..];
            continue;
        }
        let Some(rest) = bytes.strip_prefix(b"\x1b[?") else { return false };
        let params = rest.iter().take_while(|b| b.is_ascii_digit() || **b == b';').count();
        match rest.get(params) {
            Some(b'c' | b'u') => bytes = &rest[params + 1..],
            _ => return false,
        }
    }
    true
}

/// One player's walk on a remote terminal.
#[derive(Debug)]
pub struct Player {
    session: Session,
    input: RateLimit,
    limits: Limits,
    /// The window changes it follows.
    resizes: Resizes,
    dropped: u64,
    /// Its id in the world, once it has joined.
    id: Option<PlayerId>,
    /// When to look at the world next (`None`: not until it changes).
    look_at: Option<f64>,
    /// When it last looked.
    last_look: f64,
    /// The others it draws, as of its last look (reused).
    peers: Vec<Peer>,
    /// Everyone, for the player list, as of its last look (reused).
    roster: Vec<roster::Entry>,
    /// When the notice on screen goes away.
    notice_until: Option<f64>,
    /// The winner has been announced to it.
    seen_winner: bool,
    /// The last finish told to the world: the walk's start and its time (after `r` a new walk
    /// starts, and its finish is told too).
    reported_finish: Option<(f64, f64)>,
    /// Its terminal is to be asked for truecolor ([`color_plan`]).
    ask_truecolor: bool,
    /// The host records its session (its HUD says so).
    recorded: bool,
    /// The shared world's Redis is away, as of its last look.
    offline: bool,
    /// How many cells' steps nearer the exit than the maze's start its spot is ([`Spot::ahead`]).
    spot_ahead: u32,
    /// The same for this walk: its spot's, or 0 once it came back as far from the exit as the start
    /// ([`Player::start_line`]).
    ahead: u32,
    /// When this walk's clock started (the app's `started`): another value means `r` started a walk
    /// again from the spot.
    walk_started: f64,
}

/// What the world learns from a player after a frame ([`Player::news`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct News {
    /// Where the player stands.
    pub position: Vec2,
    /// Which way it faces, degrees counter-clockwise from +x.
    pub heading_deg: f32,
    /// The cell it stands in.
    pub cell: u32,
    /// How far it looks up (+) or down (−), degrees.
    pub pitch_deg: f32,
    /// It reached the exit after this many seconds: told once.
    pub finished: Option<f64>,
    /// Its walks are the maze's whole way: it started no nearer the exit than the start
    /// ([`Player::head_start`] 0). A walk with a head start is kept from the records, the player
    /// list's best times and the world's first at the exit (red-team pass 5: a crowd's newcomer,
    /// put nearer the exit, was crowned the world's winner).
    pub whole_way: bool,
    /// Its exit clock as it sees it (for the spectators).
    pub clock: WalkClock,
}

impl Player {
    /// A player walking `maze` from its start on a `cols × rows` `terminal` (as the pty request
    /// gave them), at time `now`.
    ///
    /// # Errors
    /// The maze's start is in no cell.
    pub fn new(
        maze: impl Into<Arc<Maze>>,
        terminal: &ClientTerminal,
        (cols, rows): (u32, u32),
        limits: &Limits,
        now: f64,
    ) -> Result<Player, StartOutsideMaze> {
        let (app, plan) = served_app(maze, terminal, now)?;
        Ok(Player {
            session: served_session(app, terminal, (cols, rows), limits),
            input: RateLimit::new(limits.input_rate, limits.input_burst, now),
            limits: *limits,
            resizes: Resizes::new(limits),
            dropped: 0,
            id: None,
            look_at: Some(now), // look at the world at once
            last_look: f64::NEG_INFINITY,
            peers: Vec::new(),
            roster: Vec::new(),
            notice_until: None,
            seen_winner: false,
            reported_finish: None,
            ask_truecolor: plan.ask,
            recorded: false,
            offline: false,
            spot_ahead: 0,
            ahead: 0,
            walk_started: now,
        })
    }

    /// The host records this player's session (`serve --record-dir`): its HUD says so, always first.
    pub fn set_recorded(&mut self, recorded: bool) {
        self.recorded = recorded;
        self.show_status();
    }

    /// The HUD's word from the host: recorded, the world offline, both or nothing.
    fn show_status(&mut self) {
        let status = match (self.recorded, self.offline) {
            (true, true) => Some(format!("{RECORDED} · {WORLD_OFFLINE}")),
            (true, false) => Some(RECORDED.to_string()),
            (false, true) => Some(WORLD_OFFLINE.to_string()),
            (false, false) => None,
        };
        self.session.set_status(status.as_deref());
    }

    /// The header of an asciicast of this player's screen (`serve --record-dir`): its size as
    /// drawn, `TERM` and `COLORTERM` as the client sent them (`terminal`), its colour depth and
    /// glyphs now; `timestamp`, seconds since the Unix epoch.
    #[must_use]
    pub fn cast_header(
        &self,
        terminal: &ClientTerminal,
        title: String,
        timestamp: Option<u64>,
    ) -> mazewalk_walk::cast::Header {
        let screen = self.session.screen();
        mazewalk_walk::cast::Header {
            width: u16::try_from(screen.width()).unwrap_or(u16::MAX),
            height: u16::try_from(screen.height()).unwrap_or(u16::MAX),
            timestamp,
            title,
            term: Some(terminal.term().to_string()),
            colorterm: terminal.get("COLORTERM").map(str::to_string),
            color_depth: self.session.color_depth(),
            charset: self.session.app().options.charset,
            asked_truecolor: self.ask_truecolor,
        }
    }

    /// The bytes that put the remote terminal into game mode (before the first frame).
    pub fn enter(&mut self, out: &mut Vec<u8>) {
        enter_game(&mut self.session, self.ask_truecolor, out);
    }

    /// The bytes that give the terminal back — main screen, cursor shown, keyboard flags popped, mouse
    /// and focus reports off — then `message` on a line of its own, if any.
    pub fn leave(&self, message: Option<&str>, out: &mut Vec<u8>) {
        leave_game(message, out);
    }

    /// Bytes from the player's terminal, arriving at `now`; beyond the input rate they are dropped.
    /// Returns whether they held anything but the terminal's own answers (device attributes, keyboard
    /// flags), which come without a key pressed: only the rest keeps a player from being idle.
    pub fn feed(&mut self, bytes: &[u8], now: f64) -> bool {
        let allowed = self.input.take(bytes.len(), now);
        if allowed > 0 {
            self.session.feed(&bytes[..allowed], now);
        }
        if allowed < bytes.len() {
            // The cut may fall inside an escape sequence: its ESC must not become the Esc key.
            self.dropped += (bytes.len() - allowed) as u64;
            self.session.input_gap();
        }
        !only_replies(bytes)
    }

    /// The client's window changed: the screen follows at once, or when its turn comes
    /// ([`Limits::resize_rate`]; [`next_wake`](Self::next_wake) says when).
    pub fn resize(&mut self, cols: u32, rows: u32, now: f64) {
        self.resizes.ask(cols, rows, &self.limits);
        apply_resize(&mut self.resizes, &mut self.session, now);
    }

    /// Draws a frame if one is due ([`Session::frame`]), appending its bytes to `out`; a notice whose
    /// time is up goes first.
    pub fn frame(&mut self, now: f64, out: &mut Vec<u8>) -> bool {
        apply_resize(&mut self.resizes, &mut self.session, now); // a window change that waited
        let _ = self.session.take_suspend(); // Ctrl-Z cannot stop a server: ignored
        if self.notice_until.is_some_and(|until| now >= until) {
            self.notice_until = None;
            self.session.set_notice(None);
        }
        // The best times in the exit box are those the records answered to the finish last told:
        // gone once `r` starts a new walk, and not shown in the box of a finish not told yet.
        let app = self.session.app();
        if app
            .finished
            .map(|seconds| (app.started, seconds))
            .is_none_or(|walk| Some(walk) != self.reported_finish)
        {
            self.session.set_standings(Vec::new());
        }
        self.session.frame(now, out)
    }

    /// When [`frame`](Self::frame) or a look at the world is due next if nothing arrives: the
    /// session's next wake ([`Session::next_wake`]), a look, the notice's end, or a window change's
    /// turn.
    #[must_use]
    pub fn next_wake(&self, now: f64) -> Option<f64> {
        [self.session.next_wake(now), self.look_at, self.notice_until, self.resizes.due()]
            .into_iter()
            .flatten()
            .reduce(f64::min)
            .map(|at| at.max(now))
    }

    /// The player starts on `spot` (where a viewer stands there) instead of the maze's start,
    /// facing its heading (the maze's heading when `None`), and `r` brings it back there: its own
    /// spot in a shared maze ([`crate::spawn`]), at time `now`.
    pub(crate) fn place(&mut self, spot: &Spot, now: f64) {
        let app = self.session.app_mut();
        app.set_start(spot.at.pos);
        if let Some(heading) = spot.heading {
            app.set_start_heading(heading);
        }
        self.walk_started = app.started;
        (self.spot_ahead, self.ahead) = (spot.ahead, spot.ahead);
        if spot.ahead > 0 {
            // (back at the start, or any cell as far from the exit: `start_line`)
            self.notice("A crowd at the start: walk back there for a walk the records keep.".into(), now);
        }
    }

    /// How many cells' steps nearer the exit than the maze's start this player's walk started
    /// ([`Spot::ahead`]): 0, or its finish is not the maze's whole way and is not kept in the records
    /// (a crowd must not give a newcomer a head start on a record: red-team pass 4).
    #[must_use]
    pub fn head_start(&self) -> u32 {
        self.ahead
    }

    /// The start line: a walk from a head start (a crowd stood at the start, [`Player::place`]) that
    /// comes back to a cell no nearer the exit than the start (`fair`, [`Spawns::fair`]) starts
    /// again there at `now`, its clock from zero, a walk the records keep; one idle player on the
    /// start no longer keeps every newcomer's walk from the records (red-team pass 5); after a
    /// finish too (its exit box says so). `r` walks from the spot again, with its head start.
    /// Returns whether the walk started again.
    ///
    /// [`Spawns::fair`]: crate::spawn::Spawns::fair
    pub fn start_line(&mut self, fair: impl Fn(u32) -> bool, now: f64) -> bool {
        let app = self.session.app();
        if app.started != self.walk_started {
            (self.walk_started, self.ahead) = (app.started, self.spot_ahead); // `r`: from the spot
        }
        if self.ahead == 0 || !fair(app.cell) {
            return false;
        }
        self.session.app_mut().restart_clock(now);
        (self.walk_started, self.ahead) = (now, 0);
        let text = "As far from the exit as the start: the clock starts again, for records.";
        self.notice(text.to_string(), now);
        true
    }

    /// Shows `text` in the notice box from `now` for [`NOTICE_SECONDS`].
    fn notice(&mut self, text: String, now: f64) {
        self.session.set_notice(Some(text));
        self.notice_until = Some(now + NOTICE_SECONDS);
    }

    /// The player joined the world as `id`.
    pub fn joined(&mut self, id: PlayerId) {
        self.id = Some(id);
    }

    /// The world changed at `now`: look again, but no sooner than [`WORLD_LOOKS_PER_SECOND`] allows
    /// after the last look.
    pub fn world_changed(&mut self, now: f64) {
        if self.look_at.is_none() {
            self.look_at = Some((self.last_look + 1.0 / WORLD_LOOKS_PER_SECOND).max(now));
        }
    }

    /// Whether a look at the world is scheduled (then a change to the world need not be heard of: the
    /// look will see it).
    #[must_use]
    pub(crate) fn look_scheduled(&self) -> bool {
        self.look_at.is_some()
    }

    /// Whether a look at the world is due at `now` (take one with [`World::look`](super::world::World::look)
    /// and hand it to [`look`](Self::look)).
    #[must_use]
    pub fn look_due(&self, now: f64) -> bool {
        self.look_at.is_some_and(|at| now >= at)
    }

    /// What the world looks like at `now`: the others this player shows (in a cell its last frame's
    /// portal pass reached, or on its map) are drawn, and a winner it has not been told of is announced
    /// for [`NOTICE_SECONDS`]. Returns whether the picture changed.
    pub fn look(&mut self, look: &Look, now: f64) -> bool {
        (self.look_at, self.last_look) = (None, now);
        let me = self.id.unwrap_or(PlayerId(u64::MAX));
        let mut peers = std::mem::take(&mut self.peers);
        look.peers_of(me, |position, cell| self.shows(position, cell), &mut peers);
        let mut changed = self.session.set_peers(&peers);
        self.peers = peers;
        // The player list (everyone, itself too) and the HUD's count.
        self.roster.clear();
        self.roster.extend(look.players.iter().map(|(id, seen)| roster::Entry {
            name: seen.name.clone(),
            label: seen.label,
            color: seen.color,
            joined_at: seen.joined_at,
            best: seen.best,
            me: *id == me,
        }));
        self.session.set_roster(&self.roster);
        self.session.set_players_in(Some(look.players.len()));
        // A shared world whose Redis is away: the others stand frozen where last heard.
        self.offline = look.online == Some(false);
        self.show_status();
        if let (Some(winner), false) = (&look.winner, self.seen_winner) {
            self.seen_winner = true;
            self.notice(winner.announcement_for(me), now);
            changed = true;
        }
        changed
    }

    /// What the world should learn after a frame: where the player is, and its finish the first time
    /// it is asked after the player reached the exit — each walk's finish (`r` walks it again).
    pub fn news(&mut self) -> News {
        let (position, heading_deg, cell) = self.whereabouts();
        let app = self.session.app();
        let walk = app.finished.map(|seconds| (app.started, seconds));
        let finished = walk.filter(|walk| self.reported_finish != Some(*walk)).map(|(_, seconds)| seconds);
        if walk.is_some() {
            self.reported_finish = walk;
        }
        let pitch_deg = app.camera.pitch_deg;
        let clock = WalkClock { started: app.started, took: app.finished };
        News { position, heading_deg, cell, pitch_deg, finished, clock, whole_way: self.ahead == 0 }
    }

    /// Whether the player quit (q, Esc, Ctrl-C).
    #[must_use]
    pub fn is_over(&self) -> bool {
        self.session.is_over()
    }

    /// Input bytes dropped by the rate limit so far.
    #[must_use]
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// Where the player stands, which way it faces (degrees) and in which cell.
    #[must_use]
    pub fn whereabouts(&self) -> (Vec2, f32, u32) {
        let app = self.session.app();
        (app.camera.position, app.camera.yaw_deg, app.cell)
    }

    /// Whether another player at `position` in `cell` shows on this player's screen: in a cell the
    /// last frame's portal pass reached, or on its map.
    #[must_use]
    pub fn shows(&self, position: Vec2, cell: u32) -> bool {
        self.session.sees_cell(cell) || self.session.map_area().is_some_and(|area| area.shows(position))
    }

    /// The session, to read.
    #[must_use]
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// The session, to change (a notice, say).
    pub(crate) fn session_mut(&mut self) -> &mut Session {
        &mut self.session
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::World;

    fn player(cols: u32, rows: u32) -> Player {
        Player::new(
            mazewalk_maze::builtin().unwrap(),
            &ClientTerminal::new("xterm-256color"),
            (cols, rows),
            &Limits::default(),
            0.0,
        )
        .unwrap()
    }

    /// Red-team pass 5: one idle player on the start of a maze whose start is the only cell that far
    /// from the exit put every newcomer nearer the exit, and no newcomer's walk was kept. Now a walk
    /// from a head start that comes back as far from the exit as the start starts again there (the
    /// start line): its clock from zero, no head start, the notice saying so; `r` walks from the
    /// spot again, with its head start.
    #[test]
    fn a_head_start_walked_back_to_the_starts_distance_is_a_walk_the_records_keep() {
        use crate::spawn::Spawns;
        use mazewalk_maze::generate::{GenOptions, generate};
        // a generated maze's start is the cell farthest from its exit: with someone there, a
        // newcomer is put nearer the exit
        let maze = Arc::new(generate(&GenOptions::walk(8, 6, 3)).unwrap());
        let spawns = Spawns::new(&maze).unwrap();
        let start = mazewalk_walk::state::stand(&maze, maze.viewer().pos).unwrap();
        let spot = spawns.pick(&[start.pos]);
        assert!(spot.ahead > 0, "the squatter's newcomer starts nearer the exit");
        assert!(spawns.fair(start.cell) && !spawns.fair(spot.at.cell));
        let terminal = ClientTerminal::new("xterm-256color");
        let mut p = Player::new(Arc::clone(&maze), &terminal, (80, 24), &Limits::default(), 0.0).unwrap();
        p.place(&spot, 0.0);
        assert_eq!(p.head_start(), spot.ahead);
        let mut out = Vec::new();
        p.frame(0.0, &mut out);
        assert!(String::from_utf8_lossy(&out).contains("walk back"), "the newcomer is told how to race");
        // on its spot's cell, or any other nearer the exit: nothing changes
        assert!(!p.start_line(|c| spawns.fair(c), 5.0));
        assert_eq!((p.head_start(), p.session().app().started), (spot.ahead, 0.0));
        // back in the start's cell (moved there as a walk would)
        let app = p.session_mut().app_mut();
        (app.camera.position, app.cell) = (start.pos, start.cell);
        assert!(p.start_line(|c| spawns.fair(c), 12.0));
        assert_eq!((p.head_start(), p.session().app().started), (0, 12.0), "a walk from here, no head start");
        assert!(p.news().whole_way);
        out.clear();
        p.frame(12.5, &mut out);
        assert!(String::from_utf8_lossy(&out).contains("clock starts again"));
        assert!(!p.start_line(|c| spawns.fair(c), 13.0), "once");
        // `r`: a new walk from the spot, with its head start
        p.feed(b"r", 14.0);
        assert!(!p.start_line(|c| spawns.fair(c), 14.1));
        assert_eq!(p.head_start(), spot.ahead);
        assert_eq!(p.whereabouts().2, spot.at.cell);
        assert!(!p.news().whole_way);
    }

    /// A window change within the interval waits its turn, the latest of those waiting wins, and
    /// the wake says when.
    #[test]
    fn window_changes_are_followed_at_most_at_the_rate_the_latest_winning() {
        let limits = Limits { resize_rate: 10.0, ..Limits::default() };
        let mut p = player(80, 24);
        let size = |p: &Player| (p.session().screen().width(), p.session().screen().height());
        p.resize(100, 30, 1.0);
        assert_eq!(size(&p), (100, 30), "the first at once");
        for i in 0..1000 {
            p.resize(120 + i % 2, 40, 1.01);
        }
        p.resize(90, 25, 1.02);
        assert_eq!(size(&p), (100, 30), "the rest wait");
        let turn = 1.0 + 1.0 / limits.resize_rate;
        assert!(p.resizes.due().is_some_and(|t| (t - turn).abs() < 1e-9), "{:?}", p.resizes.due());
        assert!(p.next_wake(1.02).is_some_and(|t| t <= turn), "the host wakes for it");
        p.frame(1.05, &mut Vec::new());
        assert_eq!(size(&p), (100, 30), "not before its turn");
        p.frame(1.1, &mut Vec::new());
        assert_eq!(size(&p), (90, 25), "the last asked for, in its turn");
        p.resize(65535, 65535, 1.15);
        p.frame(1.25, &mut Vec::new());
        assert_eq!(size(&p), (usize::from(limits.max_cols), usize::from(limits.max_rows)), "clamped");
    }

    #[test]
    fn sizes_are_clamped_and_zero_means_unknown() {
        let limits = Limits::default();
        assert_eq!(clamp_size(0, 0, &limits), mazewalk_walk::session::DEFAULT_SIZE);
        assert_eq!(clamp_size(65535, 65535, &limits), (limits.max_cols, limits.max_rows));
        assert_eq!(clamp_size(u32::MAX, 1, &limits), (limits.max_cols, 1));
        let p = player(65535, 65535);
        assert_eq!((p.session().screen().width(), p.session().screen().height()), (400, 150));
    }

    #[test]
    fn colour_depth_follows_term_and_colorterm() {
        let term = ClientTerminal::new;
        assert_eq!(color_depth(&term("xterm-256color")), ColorDepth::Ansi256);
        assert_eq!(
            color_depth(&term("xterm-256color").with("COLORTERM", "truecolor")),
            ColorDepth::TrueColor
        );
        assert_eq!(color_depth(&term("dumb")), ColorDepth::None);
        assert_eq!(color_depth(&term("")), ColorDepth::Ansi16);
        // NO_COLOR (no-color.org), when the client sends it (`SendEnv NO_COLOR`), as locally
        assert_eq!(color_depth(&term("xterm-256color").with("NO_COLOR", "1")), ColorDepth::None);
        assert_eq!(color_depth(&term("xterm-256color").with("NO_COLOR", "")), ColorDepth::Ansi256);
    }

    // QA: a DEC terminal (no colour in its terminfo, no Unicode blocks in its font) is drawn in
    // ASCII without colour; `linux`, `screen` and xterms keep half blocks.
    #[test]
    fn a_dec_terminal_gets_ascii_without_colour() {
        let limits = Limits::default();
        let maze = || mazewalk_maze::builtin().unwrap();
        for (term, charset, depth) in [
            ("vt100", Charset::Ascii, ColorDepth::None),
            ("vt220", Charset::Ascii, ColorDepth::None),
            ("linux", Charset::Half, ColorDepth::Ansi16),
            ("screen", Charset::Half, ColorDepth::Ansi16),
            ("xterm-mono", Charset::Half, ColorDepth::None),
            ("xterm-256color", Charset::Half, ColorDepth::Ansi256),
        ] {
            let mut p = Player::new(maze(), &ClientTerminal::new(term), (80, 24), &limits, 0.0).unwrap();
            assert_eq!(p.session().app().options.charset, charset, "{term}");
            assert_eq!(p.session().color_depth(), depth, "{term}");
            let mut out = Vec::new();
            p.enter(&mut out);
            p.frame(0.0, &mut out);
            let blocks = String::from_utf8_lossy(&out).contains('\u{2580}');
            assert_eq!(blocks, charset == Charset::Half, "{term}: a half block sent");
        }
    }

    // QA: a locale that names no UTF-8 codeset, as the client sent it, is drawn in ASCII (its
    // terminal would show each block glyph as three bytes of mojibake); tmux's rule picks which of
    // LC_ALL, LC_CTYPE and LANG decides. Only the variables that choose the picture are kept, each
    // bounded.
    #[test]
    fn the_clients_locale_chooses_the_glyphs() {
        let limits = Limits::default();
        let xterm = || ClientTerminal::new("xterm-256color");
        for (terminal, charset) in [
            (xterm(), Charset::Half),
            (xterm().with("LANG", "C"), Charset::Ascii),
            (xterm().with("LANG", "en_GB.ISO-8859-1"), Charset::Ascii),
            (xterm().with("LANG", "C").with("LC_CTYPE", "C.UTF-8"), Charset::Half),
            (xterm().with("LANG", "en_US.UTF-8").with("LC_ALL", "POSIX"), Charset::Ascii),
            (xterm().with("LC_ALL", "").with("LANG", "C.utf8"), Charset::Half),
        ] {
            let p =
                Player::new(mazewalk_maze::builtin().unwrap(), &terminal, (80, 24), &limits, 0.0).unwrap();
            assert_eq!(p.session().app().options.charset, charset, "{terminal:?}");
        }
        let mut terminal = ClientTerminal::new(&"x".repeat(10_000));
        assert!(!terminal.set("LD_PRELOAD", "/tmp/evil.so") && terminal.get("LD_PRELOAD").is_none());
        assert!(terminal.set("LANG", &"é".repeat(10_000)));
        assert_eq!(terminal.get("LANG").map(|v| v.chars().count()), Some(MAX_CLIENT_VALUE));
        assert_eq!(terminal.term().len(), MAX_CLIENT_VALUE);
    }

    // issue #33: every player's terminal is asked for truecolor (through its session), unless what the
    // client sent decides; a yes raises the player's depth, a forged yes later does not.
    #[test]
    fn a_players_terminal_is_asked_for_truecolor() {
        use mazewalk_term::caps::TRUECOLOR_QUERY;
        let asked = |p: &mut Player| {
            let mut enter = Vec::new();
            p.enter(&mut enter);
            enter.windows(TRUECOLOR_QUERY.len()).any(|w| w == TRUECOLOR_QUERY)
        };
        let mut p = player(80, 24);
        assert!(asked(&mut p));
        assert!(p.frame(0.0, &mut Vec::new()));
        assert!(!p.feed(b"\x1bP1$r0;48:2::1:2:3m\x1b\\", 0.1), "an answer is not activity");
        assert_eq!(p.session().color_depth(), ColorDepth::TrueColor);
        let mut other = player(80, 24);
        asked(&mut other);
        other.frame(0.0, &mut Vec::new());
        other.feed(b"\x1b[?62;22c", 0.1); // the first frame's answer: the questions are over
        other.feed(b"\x1bP1$r0;48:2::1:2:3m\x1b\\", 0.2);
        assert_eq!(other.session().color_depth(), ColorDepth::Ansi256);
        let limits = Limits::default();
        let maze = || mazewalk_maze::builtin().unwrap();
        let truecolor = ClientTerminal::new("xterm-256color").with("COLORTERM", "truecolor");
        let mut told = Player::new(maze(), &truecolor, (80, 24), &limits, 0.0).unwrap();
        assert!(!asked(&mut told));
        let tmux = ClientTerminal::new("tmux-256color");
        let mut tmux = Player::new(maze(), &tmux, (80, 24), &limits, 0.0).unwrap();
        assert!(!asked(&mut tmux), "a tmux on the player's side answers nothing (and 3.4 may crash)");
    }

    #[test]
    fn leaving_restores_everything_entering_turned_on() {
        let mut p = player(80, 24);
        let (mut enter, mut leave) = (Vec::new(), Vec::new());
        p.enter(&mut enter);
        p.leave(Some("bye"), &mut leave);
        let (enter, leave) = (String::from_utf8(enter).unwrap(), String::from_utf8(leave).unwrap());
        assert!(enter.contains("\x1b[?1049h") && enter.contains("\x1b[>") && enter.ends_with("\x1b[?u"));
        for undo in ["\x1b[<1u", "\x1b[?1000l", "\x1b[?25h", "\x1b[?1049l"] {
            assert!(leave.contains(undo), "{undo:?} in {leave:?}");
        }
        assert!(leave.ends_with("bye\r\n"));
    }

    #[test]
    fn input_beyond_the_rate_is_dropped_and_q_still_quits_later() {
        let mut p = player(80, 24);
        let flood = vec![b'x'; 200_000];
        p.feed(&flood, 0.0);
        assert_eq!(p.dropped(), 200_000 - u64::from(Limits::default().input_burst));
        p.feed(b"q", 5.0);
        assert!(p.is_over());
    }

    /// A paste of 30,000 arrow keys (90 KB) through the rate limit, at once and in ssh's 16 KB
    /// reads: cuts fell inside sequences, and a cut right after an ESC (the 64 KiB burst is 21,845
    /// arrows and one byte) left the Esc key once the paste paused, which quit. The arrows let through
    /// turn; nothing else happens; after a pause `q` quits.
    #[test]
    fn a_flood_of_arrow_keys_cut_by_the_rate_limit_only_turns() {
        let arrows = b"\x1b[C".repeat(30_000);
        assert_eq!(Limits::default().input_burst % 3, 1, "the premise: the burst ends after an ESC");
        for chunk in [arrows.len(), 16 * 1024 + 1] {
            let mut p = player(80, 24);
            let heading = p.session.app().camera.yaw_deg;
            for (i, part) in arrows.chunks(chunk).enumerate() {
                p.feed(part, i as f64 * 0.01);
                let mut out = Vec::new();
                p.frame(i as f64 * 0.01 + 0.005, &mut out);
            }
            assert!(p.dropped() > 0, "the premise: the rate limit cut");
            let mut out = Vec::new();
            p.frame(1.0, &mut out);
            assert!(!p.is_over(), "{chunk}-byte reads: quit");
            assert_ne!(p.session.app().camera.yaw_deg, heading, "the arrows let through turn");
            p.feed(b"q", 2.0);
            assert!(p.is_over());
        }
    }

    #[test]
    fn only_keys_count_as_input_not_the_terminals_answers() {
        assert!(only_replies(b"\x1b[?62;22c"));
        assert!(only_replies(b"\x1b[?62;22c\x1b[?1u\x1b[?1;2c"));
        assert!(!only_replies(b"\x1b[?62;22cw"));
        assert!(!only_replies(b"w"));
        assert!(!only_replies(b"\x1b[?62;22"), "a cut answer may be anything");
        assert!(!only_replies(b"\x1b[D"));
        // issue #33: the answers to the truecolor questions are answers too
        assert!(only_replies(b"\x1bP1$r0;48:2::1:2:3m\x1b\\\x1bP1+r524742=38\x1b\\\x1b[?62;22c"));
        assert!(!only_replies(b"\x1bP1$r0;48:2::1:2:3m"), "an unfinished string may be anything");
        let mut p = player(80, 24);
        assert!(!p.feed(b"\x1b[?62;22c", 0.0));
        assert!(p.feed(b"w", 0.1));
    }

    #[test]
    fn a_kitty_answer_with_event_types_turns_releases_on() {
        let mut p = player(80, 24);
        assert!(!p.session().app().releases);
        p.enter(&mut Vec::new());
        p.feed(b"\x1b[?3u", 0.0);
        assert!(p.session().app().releases);
    }

    /// Only the answer to the query counts: the same bytes unasked (pasted, forged), or a second
    /// answer, leave releases as they are, so taps stay taps.
    #[test]
    fn an_unasked_kitty_answer_changes_nothing() {
        let mut p = player(80, 24);
        p.feed(b"\x1b[?3u", 0.0);
        assert!(!p.session().app().releases, "unasked");
        p.enter(&mut Vec::new());
        p.feed(b"\x1b[?1u", 0.1); // the answer: no event types
        p.feed(b"\x1b[?3u", 0.2); // a second one, unasked
        assert!(!p.session().app().releases, "only the first answer counts");
    }

    #[test]
    fn peers_redraw_only_when_they_change() {
        let mut p = player(80, 24);
        let mut world = World::new();
        let (position, heading, cell) = p.whereabouts();
        p.joined(world.join("alice", position, heading, cell, 0.0));
        let mut out = Vec::new();
        assert!(p.frame(0.0, &mut out));
        assert!(p.shows(position, cell), "the player's own cell is in view");
        world.join("bob", position + Vec2::X, 0.0, cell, 0.0);
        assert!(p.look(&world.look(), 0.1), "bob came into view");
        assert!(!p.look(&world.look(), 0.2), "the same peers: nothing to redraw");
        p.feed(b"\x1b[?62;22c", 0.5);
        assert!(p.frame(0.5, &mut out));
        // (within the same second: at 1.0 the built-in maze's exit clock ticks; from 0.75 the frame
        // may settle, once, to its exact colours)
        assert!(!p.frame(0.7, &mut out), "nothing changed since");
        p.frame(0.8, &mut out);
        assert!(!p.frame(0.9, &mut out), "nothing changed since, settled");
    }

    /// Issue #18's game rules, now in the pure player: looks at the world come at most
    /// WORLD_LOOKS_PER_SECOND a second however often it changes, the winner is announced once and for
    /// NOTICE_SECONDS, and the world hears of each walk's finish once.
    #[test]
    fn looks_are_paced_the_winner_is_told_once_and_a_finish_reported_once() {
        let mut p = player(80, 24);
        let mut world = World::new();
        let (position, heading, cell) = p.whereabouts();
        let me = world.join("alice", position, heading, cell, 0.0);
        p.joined(me);
        assert!(p.look_due(0.0), "a newcomer looks at once");
        p.look(&world.look(), 0.0);
        assert!(!p.look_due(0.0));
        p.world_changed(0.001);
        assert!(!p.look_due(0.01) && p.look_due(1.0 / WORLD_LOOKS_PER_SECOND), "paced");
        assert_eq!(p.next_wake(0.01).map(|t| t <= 1.0 / WORLD_LOOKS_PER_SECOND), Some(true));

        let bob = world.join("bob", position, 0.0, cell, 0.0);
        world.finished(bob, 83.0);
        p.look(&world.look(), 1.0);
        let mut out = Vec::new();
        p.frame(1.0, &mut out);
        let text = p.session().screen().lines().join("\n");
        assert!(text.contains("bob reached the exit first, in 1:23.0!"), "{text}");
        p.world_changed(1.5);
        p.look(&world.look(), 1.5);
        p.frame(1.0 + NOTICE_SECONDS + 0.1, &mut out);
        let text = p.session().screen().lines().join("\n");
        assert!(!text.contains("reached the exit first"), "gone after {NOTICE_SECONDS} s, not shown again");

        assert_eq!(p.news().finished, None, "not at the exit");
        p.session_mut().app_mut().finished = Some(90.0);
        assert_eq!(p.news().finished, Some(90.0));
        assert_eq!(p.news().finished, None, "told once");
        // `r` walks it again: that walk's finish is told too (the QA report: only the first was)
        p.feed(b"r", 100.0);
        p.frame(100.0, &mut out);
        assert_eq!(p.session().app().finished, None, "r started a new walk");
        assert_eq!(p.news().finished, None, "not at the exit");
        p.session_mut().app_mut().finished = Some(40.0);
        assert_eq!(p.news().finished, Some(40.0), "the second walk's finish");
        assert_eq!(p.news().finished, None, "told once");
    }

    /// Issue #34: two players on one spot showed as `B` in the view and `C` on the map. The one in
    /// front (the nearer, of equals the first) is the one both show.
    #[test]
    fn a_player_has_one_label_in_the_view_and_on_the_map() {
        let mut p = player(100, 30);
        let mut world = World::new();
        let (position, heading, cell) = p.whereabouts();
        p.joined(world.join("alice", position, heading, cell, 0.0));
        let ahead = position + 2.0 * mazewalk_maze::geometry::heading_dir(heading);
        let bob = world.join("bob", ahead, 0.0, cell, 0.0);
        let carol = world.join("carol", ahead, 0.0, cell, 0.0);
        let mut out = Vec::new();
        p.frame(0.0, &mut out);
        p.look(&world.look(), 0.1);
        p.frame(0.2, &mut out);
        let area = p.session().map_area().expect("the corner map");
        let lines = p.session().screen().lines();
        let in_map = |ch: char| {
            lines.iter().enumerate().any(|(y, l)| {
                l.chars().enumerate().any(|(x, c)| {
                    c == ch
                        && (area.x..area.x + area.width).contains(&x)
                        && (area.y..area.y + area.height).contains(&y)
                })
            })
        };
        let in_view = |ch: char| {
            lines.iter().enumerate().any(|(y, l)| {
                y + 1 < lines.len()
                    && l.chars().enumerate().any(|(x, c)| {
                        c == ch
                            && !((area.x..area.x + area.width).contains(&x)
                                && (area.y..area.y + area.height).contains(&y))
                    })
            })
        };
        let (b, c) = (world.get(bob).unwrap().label, world.get(carol).unwrap().label);
        assert_eq!((b, c), ('B', 'C'));
        assert!(in_view('B') && in_map('B'), "bob, the first, in front in both:\n{}", lines.join("\n"));
        assert!(!in_view('C') && !in_map('C'), "carol behind him in both:\n{}", lines.join("\n"));
    }
}
