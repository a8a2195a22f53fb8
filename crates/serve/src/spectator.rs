//! One spectator (`ssh -p PORT watch@HOST`), without the connection: the first-person view of a
//! player it follows, the map of everyone (the whole maze shown), the player list and the news, on
//! its own terminal at its own size and colour depth. It is in no one's world: no figure in the
//! maze, not in the player list or the count, no records; its keys change only its own screen.
//!
//! Whom it follows: the **leader** by default — the player nearest the exit by path (portal steps
//! from its cell to the exit's cell), of equals the first to join; in a maze without an exit, the
//! first to join ([`leader`]). `Tab` or `→` follows the next player in the list's order, `Shift-Tab`
//! or `←` the one before ([`cycle`]), `l` the leader again; a followed player who leaves gives the
//! view back to the leader. With `--world` the others' servers' players are in the list too: their
//! view is drawn here, from where the world says they stand and look.
//!
//! Pure, as [`Player`](crate::player::Player) is: bytes, sizes and looks at the world in, bytes out,
//! time as seconds. Spectators of one player at one size, depth and charset share one render per
//! frame ([`SharedViews`]).

use std::sync::Arc;

use super::limits::{Limits, RateLimit};
use super::player::{
    ClientTerminal, NOTICE_SECONDS, Resizes, WORLD_LOOKS_PER_SECOND, apply_resize, enter_game, leave_game,
    only_replies, served_app, served_session,
};
use super::world::{Look, PlayerId, Seen};
use mazewalk_maze::Maze;
use mazewalk_term::input::{Input, InputDecoder, Key, KeyPhase, Modifiers};
use mazewalk_walk::overlay::Peer;
use mazewalk_walk::roster;
use mazewalk_walk::state::StartOutsideMaze;
use mazewalk_walk::views::SharedViews;
use mazewalk_walk::{MapMode, Session};

/// The SSH user name that watches instead of playing.
pub const WATCH_USER: &str = "watch";

/// What the screen says while nobody plays.
pub const WAITING: &str = "Waiting for a player…";

/// A spectator's keys (its `?` box).
pub const HELP: [&str; 7] = [
    "Tab  →       next player",
    "Shift-Tab ←  previous player",
    "l            follow the leader (nearest the exit)",
    "p            who is in the maze, their times",
    "m            map: corner, full, off",
    "?            these keys",
    "q  Esc       stop watching",
];

/// What the player list's header says closes it: a spectator's `Tab` is the next player.
pub const ROSTER_HINT: &str = "p or Esc closes";

/// What a server's spectators share: the maze's portal steps from the exit's cell to each cell (for
/// the leader; `None`: no exit) and the views they draw ([`SharedViews`]).
#[derive(Clone, Debug)]
pub struct Audience {
    /// [`Maze::portal_distances`] from the exit's cell.
    pub distances: Option<Arc<[u32]>>,
    /// The views shared.
    pub views: Arc<SharedViews>,
}

impl Audience {
    /// The audience of `maze`, sharing up to `views` views.
    #[must_use]
    pub fn new(maze: &Maze, views: usize) -> Audience {
        let distances = maze.exit().map(|exit| maze.portal_distances(exit.cell).into());
        Audience { distances, views: Arc::new(SharedViews::new(views)) }
    }
}

/// Whom a spectator follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Follow {
    /// The leader ([`leader`]), whoever it is at each look.
    Leader,
    /// This player, while it is in the maze.
    Player(PlayerId),
}

/// The leader among `players` (in order of arrival): the one nearest the exit by path — the fewest
/// portal steps from its cell in `distances` (steps from the exit's cell to each cell; a cell out
/// of range or unreachable counts as farthest) — of equals the first; with no `distances` (no
/// exit), the first. `None` when nobody plays.
#[must_use]
pub fn leader(players: &[(PlayerId, Seen)], distances: Option<&[u32]>) -> Option<PlayerId> {
    let steps = |seen: &Seen| distances.map_or(0, |d| d.get(seen.cell as usize).copied().unwrap_or(u32::MAX));
    // (min_by_key keeps the first of equals)
    players.iter().min_by_key(|(_, seen)| steps(seen)).map(|(id, _)| *id)
}

/// The player after `current` among `players` (in order of arrival, wrapping round), or before it
/// when not `forward`; from no one (or one who left), the first (or the last).
#[must_use]
pub fn cycle(players: &[(PlayerId, Seen)], current: Option<PlayerId>, forward: bool) -> Option<PlayerId> {
    cycle_by(players, current, if forward { 1 } else { -1 })
}

/// The player `steps` places after `current` among `players` (before it for a negative count),
/// wrapping round: [`cycle`] that many times over, in one look at the list. From no one (or one who
/// left), the first step goes to the first (or the last).
#[must_use]
pub fn cycle_by(players: &[(PlayerId, Seen)], current: Option<PlayerId>, steps: i64) -> Option<PlayerId> {
    let n = i64::try_from(players.len()).ok().filter(|&n| n > 0)?;
    let at = current.and_then(|c| players.iter().position(|(id, _)| *id == c));
    let next = match at {
        Some(i) => (i as i64).saturating_add(steps).rem_euclid(n),
        None if steps > 0 => (steps - 1).rem_euclid(n),
        None => steps.rem_euclid(n),
    };
    Some(players[next as usize].0)
}

/// Follow keys (`Tab`, the arrows, `l`) a spectator's screen shows at once, at most …
pub const KEY_SHOWS_BURST: u32 = 8;
/// … and then this many a second: the keys past it are shown together when the next show is due.
/// (Red-team pass 12: each key showed its change at once, the player list rebuilt — every name
/// copied — for each: a spectator sending `l` at the input rate in a world of 1,280 players took
/// 0.6 of a core, and the 64 KiB burst blocked a worker of the game's runtime for 2.5 s.)
pub const KEY_SHOWS_PER_SECOND: u32 = 30;

/// One spectator's screen on a remote terminal.
#[derive(Debug)]
pub struct Spectator {
    session: Session,
    /// Its own decoder: its keys are its own, never the walk's (no key moves the camera).
    decoder: InputDecoder,
    inputs: Vec<Input>,
    input: RateLimit,
    limits: Limits,
    /// The window changes it follows.
    resizes: Resizes,
    dropped: u64,
    over: bool,
    follow: Follow,
    /// The player shown now.
    shown: Option<PlayerId>,
    /// Portal steps from the exit's cell to each cell (`None`: no exit).
    distances: Option<Arc<[u32]>>,
    look_at: Option<f64>,
    last_look: f64,
    /// The last look at the world (cycling shows another player without waiting for the world).
    look: Option<Look>,
    /// Places along the list the follow keys moved since the last show (`Tab` and `→` +1, `←` −1),
    /// from the player `follow` names then: a key only counts, the list is looked at by the show.
    steps: i64,
    /// The follow keys changed whom it follows since the last show.
    keys_unshown: bool,
    /// When those keys are shown, if they came faster than [`KEY_SHOWS_PER_SECOND`].
    show_at: Option<f64>,
    /// The key shows' budget.
    key_shows: RateLimit,
    peers: Vec<Peer>,
    roster: Vec<roster::Entry>,
    /// The winner's announcement and until when it shows.
    news: Option<(String, f64)>,
    seen_winner: bool,
    ask_truecolor: bool,
    /// Shows so far (each looks at the whole list: what a flood of keys must not multiply).
    #[cfg(test)]
    shows: usize,
}

impl Spectator {
    /// A spectator of `maze` on a `cols × rows` `terminal`, at time `now`, one of
    /// `audience`.
    ///
    /// # Errors
    /// The maze's start is in no cell.
    pub fn new(
        maze: impl Into<Arc<Maze>>,
        terminal: &ClientTerminal,
        (cols, rows): (u32, u32),
        limits: &Limits,
        audience: &Audience,
        now: f64,
    ) -> Result<Spectator, StartOutsideMaze> {
        let (mut app, plan) = served_app(maze, terminal, now)?;
        app.reveal_map = true; // everyone on the whole map
        // no chalk marks: the followed player's are not shared, and the spectator walks nowhere
        app.chalk = false;
        let mut session = served_session(app, terminal, (cols, rows), limits);
        session.set_help(HELP.iter().map(|line| (*line).to_string()).collect());
        session.set_roster_hint(ROSTER_HINT);
        session.share_views(Arc::clone(&audience.views));
        session.set_notice(Some(WAITING.into()));
        session.set_players_in(Some(0));
        Ok(Spectator {
            session,
            decoder: InputDecoder::new(),
            inputs: Vec::new(),
            input: RateLimit::new(limits.input_rate, limits.input_burst, now),
            limits: *limits,
            resizes: Resizes::new(limits),
            dropped: 0,
            over: false,
            follow: Follow::Leader,
            shown: None,
            distances: audience.distances.clone(),
            look_at: Some(now),
            last_look: f64::NEG_INFINITY,
            look: None,
            steps: 0,
            keys_unshown: false,
            show_at: None,
            key_shows: RateLimit::new(KEY_SHOWS_PER_SECOND, KEY_SHOWS_BURST, now),
            peers: Vec::new(),
            roster: Vec::new(),
            news: None,
            seen_winner: false,
            ask_truecolor: plan.ask,
            #[cfg(test)]
            shows: 0,
        })
    }

    /// The bytes that put the remote terminal into game mode (as a player's).
    pub fn enter(&mut self, out: &mut Vec<u8>) {
        enter_game(&mut self.session, self.ask_truecolor, out);
    }

    /// The bytes that give the terminal back, then `message` on a line of its own.
    pub fn leave(&self, message: Option<&str>, out: &mut Vec<u8>) {
        leave_game(message, out);
    }

    /// Bytes from the spectator's terminal at `now` (beyond the input rate, dropped). Returns whether
    /// they held anything but the terminal's own answers.
    pub fn feed(&mut self, bytes: &[u8], now: f64) -> bool {
        let allowed = self.input.take(bytes.len(), now);
        let mut inputs = std::mem::take(&mut self.inputs);
        self.decoder.feed(&bytes[..allowed], now, &mut inputs);
        if allowed < bytes.len() {
            // The cut may fall inside an escape sequence: its ESC must not become the Esc key.
            self.dropped += (bytes.len() - allowed) as u64;
            self.decoder.gap();
            self.session.input_gap();
        }
        for input in inputs.drain(..) {
            self.input(input, now);
        }
        self.inputs = inputs;
        self.show_keys(now);
        !only_replies(bytes)
    }

    /// Shows what the follow keys changed, once for all of them: now, within the key shows' budget
    /// ([`KEY_SHOWS_PER_SECOND`]), else at the first [`frame`](Self::frame) after it allows (a
    /// [`next_wake`](Self::next_wake)).
    fn show_keys(&mut self, now: f64) {
        if !std::mem::take(&mut self.keys_unshown) {
            return;
        }
        if self.key_shows.take(1, now) == 1 {
            self.show(now);
        } else if self.show_at.is_none() {
            self.show_at = Some(now + 1.0 / f64::from(KEY_SHOWS_PER_SECOND));
        }
    }

    /// One input: the spectator's keys; the terminal's answers, size and focus go to the session;
    /// nothing else (a drag would turn the view).
    fn input(&mut self, input: Input, now: f64) {
        let Input::Key { key, phase, modifiers } = input else {
            if matches!(input, Input::Resize { .. } | Input::Reply(_) | Input::FocusLost | Input::FocusGained)
            {
                self.session.input(input, now);
            }
            return;
        };
        if phase == KeyPhase::Release {
            return;
        }
        let Modifiers { shift, ctrl, alt } = modifiers;
        let help = self.session.app().help;
        match key {
            Key::Char('c') if ctrl => self.over = true,
            Key::Char(_) if ctrl || alt => {}
            // (Counted here, shown once for all the keys of a read: see `show_keys`.)
            Key::Tab | Key::Right | Key::Left => {
                let forward = key == Key::Right || (key == Key::Tab && !shift);
                if self.look.as_ref().is_some_and(|look| !look.players.is_empty()) {
                    self.steps = self.steps.saturating_add(if forward { 1 } else { -1 });
                    self.keys_unshown = true;
                }
            }
            Key::Char('l') => {
                (self.follow, self.steps, self.keys_unshown) = (Follow::Leader, 0, true);
            }
            Key::Char('p') => self.session.toggle_roster(),
            Key::Char('m') => {
                let app = self.session.app_mut();
                app.map = match app.map {
                    MapMode::Corner => MapMode::Full,
                    MapMode::Full => MapMode::Off,
                    MapMode::Off => MapMode::Corner,
                };
            }
            Key::Char('?') => self.session.app_mut().help = !help,
            Key::Esc if help => self.session.app_mut().help = false,
            Key::Esc if self.session.roster_open() => self.session.toggle_roster(),
            Key::Esc | Key::Char('q') if phase == KeyPhase::Press => self.over = true,
            _ => {}
        }
    }

    /// The client's window changed.
    pub fn resize(&mut self, cols: u32, rows: u32, now: f64) {
        self.resizes.ask(cols, rows, &self.limits);
        apply_resize(&mut self.resizes, &mut self.session, now);
    }

    /// The world changed at `now`: look again, no sooner than [`WORLD_LOOKS_PER_SECOND`] allows.
    pub fn world_changed(&mut self, now: f64) {
        if self.look_at.is_none() {
            self.look_at = Some((self.last_look + 1.0 / WORLD_LOOKS_PER_SECOND).max(now));
        }
    }

    /// Whether a look at the world is scheduled.
    #[must_use]
    pub fn look_scheduled(&self) -> bool {
        self.look_at.is_some()
    }

    /// Whether a look at the world is due at `now`.
    #[must_use]
    pub fn look_due(&self, now: f64) -> bool {
        self.look_at.is_some_and(|at| now >= at)
    }

    /// What the world looks like at `now`: the followed player's view, everyone else as figures and
    /// on the map, the list, the count, the winner's news once.
    pub fn look(&mut self, look: Look, now: f64) {
        (self.look_at, self.last_look) = (None, now);
        if let (Some(winner), false) = (&look.winner, self.seen_winner) {
            self.seen_winner = true;
            self.news = Some((winner.announcement(), now + NOTICE_SECONDS));
        }
        self.look = Some(look);
        self.show(now);
    }

    /// Puts the last look on the screen.
    fn show(&mut self, now: f64) {
        #[cfg(test)]
        {
            self.shows += 1;
        }
        self.show_at = None; // the keys waiting, if any, are shown here
        let steps = std::mem::take(&mut self.steps);
        let Some(look) = &self.look else { return };
        let players = &look.players[..];
        let present = |id: PlayerId| players.iter().any(|(p, _)| *p == id);
        if let Follow::Player(id) = self.follow
            && !present(id)
        {
            self.follow = Follow::Leader; // it left: back to the leader
        }
        self.shown = match self.follow {
            Follow::Player(id) => Some(id),
            Follow::Leader => leader(players, self.distances.as_deref()),
        };
        // the follow keys since the last show, from whom it showed then (or the leader, after `l`)
        if steps != 0
            && let Some(next) = cycle_by(players, self.shown, steps)
        {
            (self.follow, self.shown) = (Follow::Player(next), Some(next));
        }
        let shown = self.shown.and_then(|id| players.iter().find(|(p, _)| *p == id));
        let mut peers = std::mem::take(&mut self.peers);
        look.peers_of(self.shown.unwrap_or(PlayerId(u64::MAX)), |_, _| true, &mut peers);
        self.session.set_peers(&peers);
        self.peers = peers;
        let status = match shown {
            Some((_, seen)) => {
                let (camera, cell) = (self.session.app().camera, self.session.app().cell);
                let at = mazewalk_render::Camera {
                    position: seen.position,
                    yaw_deg: seen.heading_deg,
                    pitch_deg: seen.pitch_deg,
                    ..camera
                };
                if at != camera || cell != seen.cell {
                    let app = self.session.app_mut();
                    (app.camera, app.cell) = (at, seen.cell);
                }
                // the followed player's exit clock as it sees it (another server's is not known:
                // none shown, rather than a time that is not the player's)
                let clock = seen.clock.map(|c| (c.started, c.took));
                let app = self.session.app();
                if clock.is_none() != app.clock_unknown
                    || clock.is_some_and(|c| c != (app.started, app.finished))
                {
                    let app = self.session.app_mut();
                    app.clock_unknown = clock.is_none();
                    (app.started, app.finished) = clock.unwrap_or((seen.joined_at, None));
                }
                format!("watching {}  ← →", seen.name)
            }
            None => "watching".to_string(),
        };
        self.session.set_status(Some(&status));
        self.roster.clear();
        self.roster.extend(players.iter().map(|(_, seen)| roster::Entry {
            name: seen.name.clone(),
            label: seen.label,
            color: seen.color,
            joined_at: seen.joined_at,
            best: seen.best,
            me: false,
        }));
        self.session.set_roster(&self.roster);
        self.session.set_players_in(Some(players.len()));
        let news = self.news.as_ref().filter(|(_, until)| now < *until).map(|(text, _)| text.clone());
        let waiting = shown.is_none().then(|| WAITING.to_string());
        self.session.set_notice(waiting.or(news));
    }

    /// Draws a frame if one is due, appending its bytes to `out`; news whose time is up goes first.
    pub fn frame(&mut self, now: f64, out: &mut Vec<u8>) -> bool {
        apply_resize(&mut self.resizes, &mut self.session, now); // a window change that waited
        let mut inputs = std::mem::take(&mut self.inputs);
        self.decoder.expire(now, &mut inputs); // a lone Esc
        for input in inputs.drain(..) {
            self.input(input, now);
        }
        self.inputs = inputs;
        self.show_keys(now);
        if self.show_at.is_some_and(|at| now >= at) {
            self.key_shows.take(1, now);
            self.show(now); // the follow keys that came too fast, all at once
        }
        if self.news.as_ref().is_some_and(|(_, until)| now >= *until) {
            self.news = None;
            self.show(now);
        }
        let _ = self.session.take_suspend();
        self.session.frame(now, out)
    }

    /// When [`frame`](Self::frame) or a look is due next if nothing arrives.
    #[must_use]
    pub fn next_wake(&self, now: f64) -> Option<f64> {
        let news = self.news.as_ref().map(|(_, until)| *until);
        [
            self.session.next_wake(now),
            self.look_at,
            news,
            self.decoder.deadline(),
            self.resizes.due(),
            self.show_at,
        ]
        .into_iter()
        .flatten()
        .reduce(f64::min)
        .map(|at| at.max(now))
    }

    /// Whom it follows.
    #[must_use]
    pub fn follow(&self) -> Follow {
        self.follow
    }

    /// The player shown now.
    #[must_use]
    pub fn shown(&self) -> Option<PlayerId> {
        self.shown
    }

    /// Whether the spectator stopped watching (q, Esc, Ctrl-C).
    #[must_use]
    pub fn is_over(&self) -> bool {
        self.over
    }

    /// Input bytes dropped by the rate limit so far.
    #[must_use]
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// The session, to read.
    #[must_use]
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// The session, to change (what a frame cost).
    pub(crate) fn session_mut(&mut self) -> &mut Session {
        &mut self.session
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::player::clamp_size;
    use crate::world::{WalkClock, World};
    use glam::Vec2;

    fn seen(name: &str, cell: u32) -> Seen {
        Seen {
            name: name.into(),
            position: Vec2::ZERO,
            heading_deg: 0.0,
            pitch_deg: 0.0,
            cell,
            color: mazewalk_term::frame::Color::Indexed(196),
            label: name.chars().next().unwrap().to_ascii_uppercase(),
            joined_at: 0.0,
            best: None,
            clock: None,
        }
    }

    #[test]
    fn the_leader_is_nearest_the_exit_by_path_of_equals_the_first() {
        let players = [
            (PlayerId(0), seen("ada", 0)),
            (PlayerId(1), seen("bob", 2)),
            (PlayerId(2), seen("cy", 1)),
            (PlayerId(3), seen("di", 2)),
        ];
        let distances = [5, 3, 1];
        assert_eq!(leader(&players, Some(&distances)), Some(PlayerId(1)), "bob and di: bob came first");
        assert_eq!(leader(&players[2..], Some(&distances)), Some(PlayerId(3)));
        assert_eq!(leader(&players, None), Some(PlayerId(0)), "no exit: the first to join");
        let lost = [(PlayerId(7), seen("ed", 99)), (PlayerId(8), seen("fy", 0))];
        assert_eq!(leader(&lost, Some(&distances)), Some(PlayerId(8)), "a cell out of range is farthest");
        let cut_off = [(PlayerId(7), seen("ed", 0)), (PlayerId(8), seen("fy", 1))];
        assert_eq!(leader(&cut_off, Some(&[u32::MAX, 9])), Some(PlayerId(8)), "unreachable is farthest");
        assert_eq!(leader(&[], Some(&distances)), None);
    }

    #[test]
    fn cycling_goes_round_the_list_both_ways() {
        let players =
            [(PlayerId(0), seen("ada", 0)), (PlayerId(4), seen("bob", 0)), (PlayerId(9), seen("cy", 0))];
        let next = |from, forward| cycle(&players, from, forward);
        assert_eq!(next(Some(PlayerId(0)), true), Some(PlayerId(4)));
        assert_eq!(next(Some(PlayerId(9)), true), Some(PlayerId(0)), "wraps round");
        assert_eq!(next(Some(PlayerId(0)), false), Some(PlayerId(9)), "back, wrapping round");
        assert_eq!(next(None, true), Some(PlayerId(0)));
        assert_eq!(next(None, false), Some(PlayerId(9)));
        assert_eq!(next(Some(PlayerId(5)), true), Some(PlayerId(0)), "from one who left: the first");
        assert_eq!(cycle(&[], Some(PlayerId(0)), true), None);
    }

    fn spectator(maze: &Arc<Maze>) -> Spectator {
        let audience = Audience::new(maze, 4);
        Spectator::new(
            Arc::clone(maze),
            &ClientTerminal::new("xterm-256color"),
            (100, 30),
            &Limits::default(),
            &audience,
            0.0,
        )
        .unwrap()
    }

    fn text(s: &Spectator) -> String {
        s.session().screen().lines().join("\n")
    }

    /// The QA report: the spectator's HUD read `time 7:10`, the followed player's time since it
    /// joined, while the player's own read `exit in 3:51.7`. Now it shows the player's exit clock: its
    /// walk's time (from its last `r`), and its finish once it reached the exit.
    #[test]
    fn a_spectator_shows_the_followed_players_exit_clock() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        assert!(maze.exit().is_some(), "a maze with an exit: a clock");
        let mut s = spectator(&maze);
        let mut world = World::new();
        let mut out = Vec::new();
        let start = maze.viewer().pos;
        let ada = world.join("ada", start, 0.0, maze.cell_at(start).unwrap(), 0.0);
        let hud = |s: &Spectator| s.session().screen().lines().last().cloned().unwrap_or_default();
        // ada walks again (`r`) at 200 s; at 430 s her clock reads 3:50, not her 7:10 in the maze
        world.clocked(ada, WalkClock { started: 200.0, took: None });
        s.look(world.look(), 430.0);
        s.feed(b"\x1b[?62;22c", 430.0);
        assert!(s.frame(430.0, &mut out));
        assert!(hud(&s).contains("time 3:50") && !hud(&s).contains("7:10"), "{}", hud(&s));
        // she reaches the exit in 3:51.7: so it reads, and stays
        world.clocked(ada, WalkClock { started: 200.0, took: Some(231.7) });
        s.world_changed(431.8);
        s.look(world.look(), 432.0);
        s.frame(432.0, &mut out);
        assert!(hud(&s).contains("exit in 3:51.7"), "{}", hud(&s));
        s.frame(500.0, &mut out);
        assert!(hud(&s).contains("exit in 3:51.7"), "{}", hud(&s));
    }

    /// Nobody plays: a calm screen that says so. Two join: the view is the leader's, from where it
    /// stands and looks; the spectator's keys cycle and never move the view; the followed player's
    /// turn does; one who leaves gives the view back to the leader.
    #[test]
    fn a_spectator_follows_players_and_its_keys_never_move_the_view() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let mut s = spectator(&maze);
        let mut world = World::new();
        let mut out = Vec::new();
        s.look(world.look(), 0.0);
        assert!(s.frame(0.0, &mut out));
        assert!(text(&s).contains(WAITING) && text(&s).contains("0 in"), "{}", text(&s));
        assert_eq!(s.shown(), None);

        let start = maze.viewer().pos;
        let ada = world.join("ada", start, 0.0, maze.cell_at(start).unwrap(), 0.0);
        let ahead = start + Vec2::new(2.0, 0.0);
        let bob = world.join("bob", ahead, 90.0, maze.cell_at(ahead).unwrap(), 0.0);
        s.world_changed(0.1);
        assert!(s.look_due(0.1));
        s.look(world.look(), 0.1);
        let leader = leader(&world.look().players, s.distances.as_deref()).unwrap();
        assert_eq!(s.shown(), Some(leader));
        assert_eq!(s.follow(), Follow::Leader);
        s.feed(b"\x1b[?62;22c", 0.15);
        assert!(s.frame(0.2, &mut out));
        let shown = world.get(leader).unwrap().clone();
        assert_eq!(s.session().app().camera.position, shown.position);
        assert_eq!(s.session().app().camera.yaw_deg, shown.heading_deg);
        assert!(text(&s).contains(&format!("watching {}", shown.name)) && text(&s).contains("2 in"));
        assert!(!text(&s).contains(WAITING));

        // Tab: the other one; ← back; l: the leader again.
        s.feed(b"\t", 0.3);
        let other = if leader == ada { bob } else { ada };
        assert_eq!((s.shown(), s.follow()), (Some(other), Follow::Player(other)));
        assert_eq!(s.session().app().camera.position, world.get(other).unwrap().position);
        s.feed(b"\x1b[D", 0.35);
        assert_eq!(s.shown(), Some(leader));
        s.feed(b"\x1b[C", 0.36);
        assert_eq!(s.shown(), Some(other));
        // A walker's keys do nothing to the view.
        let camera = s.session().app().camera;
        s.feed(b"wwaasd\x1b[A\x1b[B  ", 0.4);
        s.frame(0.5, &mut out);
        s.frame(1.0, &mut out);
        assert_eq!(s.session().app().camera, camera);
        // The followed player turns: the view turns.
        world.moved(other, world.get(other).unwrap().position, 200.0, world.get(other).unwrap().cell);
        s.world_changed(1.1);
        s.look(world.look(), 1.1);
        assert_eq!(s.session().app().camera.yaw_deg, 200.0);
        let version = world.version();
        world.pitched(other, -20.0); // it looks down: a change the spectator hears of, and shows
        assert!(world.version() > version);
        s.look(world.look(), 1.15);
        assert_eq!(s.session().app().camera.pitch_deg, -20.0);
        // p opens the player list (Tab is the next player here), without the spectator in it.
        s.feed(b"p", 1.2);
        s.feed(b"\x1b[?62;22c\x1b[?62;22c", 1.25);
        assert!(s.frame(1.3, &mut out));
        assert!(text(&s).contains("Players: 2"), "{}", text(&s));
        s.feed(b"\x1b", 1.4);
        s.frame(2.0, &mut out); // a lone Esc, expired: closes the list, not the watch
        assert!(!s.is_over() && !s.session().roster_open());
        // ? shows the spectator's keys.
        s.feed(b"?", 2.1);
        s.feed(b"\x1b[?62;22c\x1b[?62;22c", 2.15);
        s.frame(2.2, &mut out);
        assert!(text(&s).contains("next player") && text(&s).contains("stop watching"), "{}", text(&s));
        // The followed player leaves: back to the leader.
        world.leave(other);
        s.world_changed(2.5);
        s.look(world.look(), 2.5);
        assert_eq!((s.shown(), s.follow()), (Some(leader), Follow::Leader));
        s.feed(b"q", 2.6);
        assert!(s.is_over());
    }

    // Bug: the spectator's player list said "Tab closes", but a spectator's Tab follows the next
    // player and leaves the list open; `p` (and Esc) close it. The header says so, and does it.
    #[test]
    fn a_spectators_player_list_says_the_keys_that_close_it() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let mut s = spectator(&maze);
        let mut world = World::new();
        let start = maze.viewer().pos;
        let ada = world.join("ada", start, 0.0, maze.cell_at(start).unwrap(), 0.0);
        let ahead = start + Vec2::new(2.0, 0.0);
        let bob = world.join("bob", ahead, 90.0, maze.cell_at(ahead).unwrap(), 0.0);
        s.look(world.look(), 0.0);
        let mut out = Vec::new();
        let mut frame_at = |s: &mut Spectator, now: f64| {
            s.feed(b"\x1b[?62;22c\x1b[?62;22c", now); // the terminal answered: frames may go
            assert!(s.frame(now + 0.05, &mut out));
            text(s)
        };
        s.feed(b"p", 0.1);
        let open = frame_at(&mut s, 0.1);
        assert!(open.contains("Players: 2") && open.contains(ROSTER_HINT), "{open}");
        assert!(!open.contains("Tab closes"), "{open}");
        // Tab: the next player, the list still open (as its header promises)
        let before = s.shown();
        s.feed(b"\t", 0.3);
        assert_ne!(s.shown(), before);
        assert!(s.shown() == Some(ada) || s.shown() == Some(bob));
        let after_tab = frame_at(&mut s, 0.3);
        assert!(s.session().roster_open() && after_tab.contains("Players: 2"), "{after_tab}");
        // p closes it, as the header says; p again opens it, and Esc closes it too
        s.feed(b"p", 0.5);
        assert!(!s.session().roster_open());
        assert!(!frame_at(&mut s, 0.5).contains("Players: 2"));
        s.feed(b"p", 0.7);
        assert!(s.session().roster_open());
        s.feed(b"\x1b", 0.8);
        s.frame(1.5, &mut Vec::new()); // a lone Esc, expired
        assert!(!s.session().roster_open() && !s.is_over());
    }

    /// A spectator watching `n` players who joined at the maze's start, at time 0.
    fn watching(maze: &Arc<Maze>, n: usize) -> (Spectator, Vec<PlayerId>) {
        let mut s = spectator(maze);
        let mut world = World::new();
        let start = maze.viewer().pos;
        let cell = maze.cell_at(start).unwrap();
        let ids = (0..n).map(|i| world.join(&format!("player{i}"), start, 0.0, cell, 0.0)).collect();
        s.look(world.look(), 0.0);
        (s, ids)
    }

    /// Red-team pass 12: each follow key (`l`, `Tab`, an arrow) showed its change at once, the
    /// player list rebuilt for it, every name copied: a spectator sending `l` at the input rate
    /// (16 KiB a second) in a world of 1,280 players (the default 256 here and 1,024 of other
    /// servers') took 0.6 of a core, its 64 KiB burst a worker of the game's runtime for 2.5 s. Now
    /// a key is counted and a read's keys shown once: a second of keys costs the same in a crowd
    /// as with one player, and lands on the same player as one key at a time would.
    #[test]
    fn a_flood_of_follow_keys_costs_the_same_whatever_the_crowd() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let crowd = Limits::default().max_players + 1024;
        // A second of keys at the input rate, in one read, and the frame after: the shows it made
        // (each looks at the whole list of players) and the presses.
        let second_of_keys = |s: &mut Spectator, key: &[u8], at: f64| {
            let keys = key.repeat(Limits::default().input_rate as usize / key.len());
            let before = s.shows;
            s.feed(&keys, at);
            s.frame(at + 0.5, &mut Vec::new());
            (s.shows - before, keys.len() / key.len())
        };
        let (mut alone, _) = watching(&maze, 1);
        let (mut crowded, ids) = watching(&maze, crowd);
        let mut place = 0;
        for (k, key) in [&b"l"[..], b"\t", b"\x1b[C"].into_iter().enumerate() {
            let at = 2.0 * k as f64 + 1.0;
            let (shows_alone, _) = second_of_keys(&mut alone, key, at);
            let (shows, presses) = second_of_keys(&mut crowded, key, at);
            // the leader (the first to join, of equals), then `presses` places on each time
            place = if key == b"l" { 0 } else { (place + presses) % crowd };
            assert_eq!(crowded.shown(), Some(ids[place]), "after {presses} of {key:?}");
            // one show for the read's thousands of keys, whatever the crowd (a show a key before)
            assert!(
                shows <= 1 && shows == shows_alone,
                "{presses} of {key:?}: {shows} shows, {shows_alone} alone"
            );
        }
    }

    /// The keys past the key shows' budget wait, counted, for one show at the next frame it allows
    /// (the host is woken for it), and land where one show a key would have.
    #[test]
    fn follow_keys_past_their_budget_are_shown_together_at_the_next_frame() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let (mut s, ids) = watching(&maze, 5);
        assert_eq!(s.shown(), Some(ids[0]));
        let burst = KEY_SHOWS_BURST as usize;
        for press in 1..=21 {
            s.feed(b"\t", 1.0); // each its own read, as each key of a typist is
            let shown_now = ids[press.min(burst) % 5];
            assert_eq!(s.shown(), Some(shown_now), "after press {press}");
        }
        let due = 1.0 + 1.0 / f64::from(KEY_SHOWS_PER_SECOND);
        assert!(s.next_wake(1.0).is_some_and(|at| at <= due), "woken for the keys waiting");
        s.frame(due - 0.01, &mut Vec::new());
        assert_eq!(s.shown(), Some(ids[burst % 5]), "not yet");
        s.frame(due, &mut Vec::new());
        assert_eq!((s.shown(), s.follow()), (Some(ids[21 % 5]), Follow::Player(ids[21 % 5])));
        s.feed(b"\x1b[D\x1b[D\x1b[Dl\x1b[D", 3.0); // back three, the leader, back one: in one read
        assert_eq!(s.shown(), Some(ids[4]));
    }

    #[test]
    fn a_winner_is_news_for_a_while_and_a_flood_of_keys_is_cut() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let mut s = spectator(&maze);
        let mut world = World::new();
        let start = maze.viewer().pos;
        let ada = world.join("ada", start, 0.0, maze.cell_at(start).unwrap(), 0.0);
        world.finished(ada, 83.0);
        s.look(world.look(), 1.0);
        s.frame(1.0, &mut Vec::new());
        assert!(text(&s).contains("ada reached the exit first, in 1:23.0!"), "{}", text(&s));
        assert!(s.next_wake(1.0).is_some_and(|t| t <= 1.0 + NOTICE_SECONDS));
        s.feed(b"\x1b[?62;22c", 1.1);
        s.frame(1.0 + NOTICE_SECONDS, &mut Vec::new());
        assert!(!text(&s).contains("reached the exit first"));
        s.feed(&vec![b'x'; 200_000], 20.0);
        assert!(s.dropped() > 0 && !s.is_over());
    }

    /// Every size and colour depth a walk is drawn at: the spectator's own terminal's, clamped as a
    /// player's, the view its player's from there.
    #[test]
    fn a_spectator_draws_at_its_own_size_and_depth() {
        use mazewalk_term::frame::ColorDepth;
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let audience = Audience::new(&maze, 4);
        let limits = Limits::default();
        let mut world = World::new();
        let start = maze.viewer().pos;
        world.join("ada", start, 0.0, maze.cell_at(start).unwrap(), 0.0);
        let terminals = [
            (ClientTerminal::new("xterm-256color"), ColorDepth::Ansi256),
            (ClientTerminal::new("xterm-256color").with("COLORTERM", "truecolor"), ColorDepth::TrueColor),
            (ClientTerminal::new("xterm"), ColorDepth::Ansi16),
            (ClientTerminal::new(""), ColorDepth::Ansi16),
        ];
        for (terminal, depth) in terminals {
            let term = terminal.term();
            for size in [(0, 0), (1, 1), (20, 6), (80, 24), (150, 50), (65535, 65535)] {
                let mut s =
                    Spectator::new(Arc::clone(&maze), &terminal, size, &limits, &audience, 0.0).unwrap();
                s.look(world.look(), 0.0);
                assert!(s.frame(0.0, &mut Vec::new()), "{term} {size:?}");
                let screen = s.session().screen();
                let want = clamp_size(size.0, size.1, &limits);
                assert_eq!((screen.width() as u16, screen.height() as u16), want, "{term} {size:?}");
                assert_eq!(s.session().color_depth(), depth, "{terminal:?}");
                if want.0 >= 80 {
                    assert!(text(&s).contains("watching ada"), "{term} {size:?}:\n{}", text(&s));
                    // (no lens to offer: a spectator's `z` does nothing)
                    assert!(!text(&s).contains("look ahead"), "{term} {size:?}:\n{}", text(&s));
                }
            }
        }
    }
}
