//! Keys → actions, and which actions are held right now (pure: time is passed in, never read).
//!
//! Terminals that speak the kitty keyboard protocol report presses *and releases*, so an action is held
//! exactly from press to release. Elsewhere only presses arrive, repeated by the terminal's auto-repeat
//! after an initial delay (typically 250–600 ms, then every 30–50 ms). Either way a tap takes one step
//! and a hold glides: see [`Held`].

/// Something the viewer can do; each has a key (see [`HELP`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Action {
    /// Walk forward (W).
    Forward,
    /// Walk back (S).
    Back,
    /// Step left (A).
    StrafeLeft,
    /// Step right (D).
    StrafeRight,
    /// Turn left (←).
    TurnLeft,
    /// Turn right (→).
    TurnRight,
    /// Snap turn 90° left (`,` or `<`).
    SnapLeft,
    /// Snap turn 90° right (`.` or `>`).
    SnapRight,
    /// Look up (↑).
    LookUp,
    /// Look down (↓).
    LookDown,
    /// Rise toward the ceiling (]).
    Rise,
    /// Sink toward the floor ([).
    Sink,
    /// Widen the field of view (+).
    FovWider,
    /// Narrow the field of view (-).
    FovNarrower,
    /// The look-ahead lens on / off (z): a narrow field for far openings.
    ToggleLookAhead,
    /// The foveated view on / off (f): the wide field with its middle magnified, or drawn plainly.
    ToggleFovea,
    /// Perspective ↔ orthographic (p).
    ToggleProjection,
    /// Map: off → corner → full screen (m).
    CycleMap,
    /// Next glyph mode (c).
    CycleCharset,
    /// Back to the start (r).
    Reset,
    /// Show or hide the key help (? or h).
    Help,
    /// Portal culling ↔ brute force (b): every wall drawn, for comparison.
    ToggleCulling,
    /// Tint the map's cells the portal pass visited this frame (v), with a legend: culling, seen.
    ToggleCullingTint,
    /// Brick walls and filtered floor tiles on / off (t).
    ToggleTextures,
    /// The chalk marks on the floor of the cells walked on / off (x).
    ToggleChalk,
    /// The developer figures in the HUD on / off (i): frames per second, bytes, cell, cells seen, ms.
    ToggleFigures,
    /// Race a stored run's ghost, on / off (g): a served maze's best run, or the local walk's
    /// `--ghost FILE`.
    ToggleGhost,
    /// Leave (q, or Esc with no box shown: there it closes the box). After a minute of walking it asks
    /// first.
    Quit,
}

impl Action {
    /// The actions that act continuously while held (the rest fire once per press).
    pub(crate) const CONTINUOUS: [Action; 12] = [
        Action::Forward,
        Action::Back,
        Action::StrafeLeft,
        Action::StrafeRight,
        Action::TurnLeft,
        Action::TurnRight,
        Action::LookUp,
        Action::LookDown,
        Action::Rise,
        Action::Sink,
        Action::FovWider,
        Action::FovNarrower,
    ];

    /// Whether the action acts continuously while held ([`CONTINUOUS`](Self::CONTINUOUS)).
    #[must_use]
    pub(crate) fn is_continuous(self) -> bool {
        self.slot().is_some()
    }

    /// Its index in [`CONTINUOUS`](Self::CONTINUOUS).
    fn slot(self) -> Option<usize> {
        Action::CONTINUOUS.iter().position(|&a| a == self)
    }
}

use mazewalk_term::input::Key;

/// The action bound to `key`, if any.
#[must_use]
pub(crate) fn action_for(key: Key) -> Option<Action> {
    Some(match key {
        Key::Char(c) => match c.to_ascii_lowercase() {
            'w' => Action::Forward,
            's' => Action::Back,
            'a' => Action::StrafeLeft,
            'd' => Action::StrafeRight,
            '[' => Action::Sink,
            ']' => Action::Rise,
            '+' | '=' => Action::FovWider,
            '-' | '_' => Action::FovNarrower,
            ',' | '<' => Action::SnapLeft,
            '.' | '>' => Action::SnapRight,
            'z' => Action::ToggleLookAhead,
            'f' => Action::ToggleFovea,
            'p' => Action::ToggleProjection,
            'm' => Action::CycleMap,
            'c' => Action::CycleCharset,
            'r' => Action::Reset,
            'b' => Action::ToggleCulling,
            'v' => Action::ToggleCullingTint,
            't' => Action::ToggleTextures,
            'x' => Action::ToggleChalk,
            'i' => Action::ToggleFigures,
            'g' => Action::ToggleGhost,
            '?' | 'h' => Action::Help,
            'q' => Action::Quit,
            _ => return None,
        },
        Key::Left => Action::TurnLeft,
        Key::Right => Action::TurnRight,
        Key::Up => Action::LookUp,
        Key::Down => Action::LookDown,
        Key::Esc => Action::Quit,
        _ => return None,
    })
}

/// The key help, one line per binding (shown by `?` and in README): how to leave first, as a small
/// box keeps its first lines.
pub(crate) const HELP: &[(&str, &str)] = &[
    ("q / Ctrl-C", "quit (Esc too, with no box shown)"),
    ("? / h", "this help (Esc closes it too)"),
    ("W / S", "walk forward / back (tap: a step, hold: glide)"),
    ("A / D", "step left / right"),
    ("← / →", "turn left / right (tap: 15°)"),
    (", . or < >", "snap turn 90° left / right"),
    ("↑ / ↓", "look up / down"),
    ("[ / ]", "move down / up"),
    ("+ / -", "wider / narrower field of view"),
    ("z / f", "far openings: a 30° lens / the magnified middle off, on"),
    ("drag", "look around with the mouse"),
    ("p", "perspective / orthographic"),
    ("m", "map: corner / full / off (shows what you have seen)"),
    ("v", "map: tint the cells the portal pass visits"),
    ("b", "portal culling / brute force (every wall)"),
    ("c", "glyphs: ascii, half ▀, quad ▚, sextant (2×3)"),
    ("t", "textures: brick walls, floor tiles"),
    ("x", "chalk crosses on the floor where you walked"),
    ("i", "developer figures: fps, bytes, cell, ms"),
    ("g", "ghost: race the best run (served) or --ghost"),
    ("r", "back to the start"),
    ("Ctrl-Z", "suspend (fg to come back)"),
];

/// The key that only the local walk has ([`HELP`]'s last row): a served player's `Ctrl-Z` cannot stop
/// a server, so its help leaves it out.
pub(crate) const LOCAL_ONLY: &str = "Ctrl-Z";

/// The developer toggles, which a served player does not have ([`App::developer_keys`](crate::state::App::developer_keys)):
/// brute force (`b`: every wall of the maze drawn, which made one address's 16 connections cost a
/// server a core), the culling tint (`v`) and the developer figures (`i`: a HUD that changes every
/// frame).
pub const DEVELOPER_ACTIONS: [Action; 3] =
    [Action::ToggleCulling, Action::ToggleCullingTint, Action::ToggleFigures];

/// Their keys in [`HELP`]: a served player's help leaves them out.
pub(crate) const DEVELOPER_KEYS: [&str; 3] = ["b", "v", "i"];

/// A served maze's own key, in its players' help instead of [`LOCAL_ONLY`]: the player list.
pub(crate) const SERVED: (&str, &str) = ("Tab", "who is in the maze, their times");

/// Without releases, a press closer than this (seconds) to the key's previous press is the terminal's
/// auto-repeat: repeats come every 30–50 ms on common settings, and a person taps no faster than every
/// 60 ms. Between the two, with room for a repeat arriving a few ms late and for a tap's gap computed in
/// floating point: a tap 60 ms after the last one still counts.
pub const HOLD_GAP: f64 = 0.058;
/// Presses closer than this (seconds) arrived together (one read, one packet: taps held up on the way)
/// and say nothing about the repeat rate: each is a tap, unless the key is already gliding.
pub(crate) const TOGETHER: f64 = 0.01;
/// How long a link may hold key presses back (seconds) and let them go together: presses that arrive
/// [`TOGETHER`] this soon after the key was last seen repeating are its auto-repeat, bunched.
pub(crate) const STALL: f64 = 0.5;
/// How long a repeat keeps its key held, as a multiple of the repeat interval observed on that key: the
/// next repeat is due after one interval, the other half is room for jitter (an SSH link).
pub const REPEAT_HOLD_INTERVALS: f64 = 1.5;
/// The shortest and longest a repeat keeps its key held (seconds), whatever interval was observed (the
/// interval is at most [`HOLD_GAP`], so the glide stops within 87 ms of the last repeat).
pub const REPEAT_HOLD_RANGE: (f64, f64) = (0.05, REPEAT_HOLD_INTERVALS * HOLD_GAP);
/// The most taps of one key that may take their steps at once, ahead of the time the key's motion
/// takes at full speed (then one more each step's time, as a hold glides): a link stalled for
/// [`STALL`] lets go at most this many taps of a person tapping every 60 ms (0.5 ⁄ 0.058 ≈ 8.6,
/// rounded up). Taps past it — a paste, a script's burst, a person tapping faster than the key
/// glides for long — step nothing, so no way of pressing moves a player further than holding the
/// key does, but for this many steps (a race won by pasting the way; a script tapping every 58 ms
/// walked 3× as fast as a hold and won a served race, red-team pass 6).
pub const TAP_BURST: f64 = 9.0;
/// A press this soon after the key's previous one (seconds) is not an answer to the exit box: the key
/// walked the viewer into the exit and is still held (or tapped faster than anyone reads).
pub(crate) const ANSWER_GAP: f64 = 0.125;

/// One continuous action's key.
#[derive(Clone, Copy, Debug, PartialEq)]
struct KeyState {
    /// When it was last pressed (or repeated).
    last_press: f64,
    /// The auto-repeat interval observed on it (seconds), smoothed.
    interval: Option<f64>,
    /// Continuous motion from `.0` until `.1` (`INFINITY`: until the release).
    glide: Option<(f64, f64)>,
    /// After a step, continuous motion waits until this time: the step stood for it.
    rest_until: f64,
    /// When a press of it was last taken for its auto-repeat.
    repeated_at: f64,
    /// When the key's motion would end had it all been made at full speed: its steps (each its
    /// step's time) and its glides laid end to end, from where it was last still. Kept through a
    /// [`Held::clear`]: a focus report cannot make a burst new.
    paid_until: f64,
    /// The glide's motion up to this time is in `paid_until`.
    glide_paid_to: f64,
}

impl KeyState {
    /// The glide's motion up to `now` laid into `paid_until`.
    fn settle(&mut self, now: f64) {
        if let Some((from, until)) = self.glide {
            let (start, end) = (from.max(self.glide_paid_to), until.min(now));
            if end > start {
                self.paid_until = self.paid_until.max(start) + (end - start);
                self.glide_paid_to = end;
            }
        }
    }
}

/// Whether motion laid on until `paid_until` leaves room at `now` for a tap's step of `pace` seconds:
/// while it is at most [`TAP_BURST`] − 1 steps ahead of `now`.
fn tap_room(paid_until: f64, now: f64, pace: f64) -> bool {
    // (a float's room: nine steps at once are eight paces ahead after eight additions)
    paid_until - now <= (TAP_BURST - 1.0) * pace + 1e-9
}

/// The walking keys' slots in [`Action::CONTINUOUS`]: forward, back and the two strafes. Their taps
/// share a budget as well as each having its own ([`Feet`]).
const FEET: std::ops::Range<usize> = 0..4;

/// The walking keys' shared budget: when their motion together would end at full speed, their taps'
/// steps and their glides laid end to end (two glides at once, a diagonal hold, counted once: it
/// moves no faster than one). Each key's own budget let two keys tapped in turn each step at its
/// full pace, and a player facing 45° off a corridor tapping `w` and `d` in turn walked down it 1.4×
/// as fast as a hold (red-team pass 7).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Feet {
    paid_until: f64,
    /// The glides' motion up to this time is in `paid_until`.
    glides_paid_to: f64,
}

impl Default for Feet {
    fn default() -> Self {
        Feet { paid_until: f64::NEG_INFINITY, glides_paid_to: f64::NEG_INFINITY }
    }
}

impl Default for KeyState {
    fn default() -> Self {
        KeyState {
            last_press: f64::NEG_INFINITY,
            interval: None,
            glide: None,
            rest_until: f64::NEG_INFINITY,
            repeated_at: f64::NEG_INFINITY,
            paid_until: f64::NEG_INFINITY,
            glide_paid_to: f64::NEG_INFINITY,
        }
    }
}

/// Which continuous actions are held, and when they move.
///
/// **Tap = step, hold = glide.** A press takes one discrete step at once (the caller makes it when
/// [`press`](Self::press) says so); motion becomes continuous only while the key is known to be held,
/// and a step stands for the time it would have taken at full speed (the glide waits for it), so a hold
/// moves as far as `speed × time` whichever way it started.
///
/// - With releases (kitty protocol), the key is held from its press to its release: a tap is exactly one
///   step, a longer press glides on after the step's time until the release. Repeats change nothing.
/// - Without releases, only presses arrive. A person taps at most every 60 ms, pausing as long as they
///   like between taps; a terminal's auto-repeat sends its first repeat after an initial delay
///   (250–600 ms), then one every 30–50 ms. The delay cannot tell a held key from taps (a tap may follow
///   any pause), the repeat rate can: so a press is a tap — one whole step, ending any glide, as the key
///   must have been let go — unless it comes within [`HOLD_GAP`] of the key's previous press (or
///   `TOGETHER` with it while gliding or within `STALL` of a repeat: a stalled link let a
///   hold's repeats go at once). Such a press is the auto-repeat: no step, the key glides until
///   [`REPEAT_HOLD_INTERVALS`] × the observed repeat interval (within [`REPEAT_HOLD_RANGE`]) after the
///   latest repeat, so it stops within that of the key being let go. A hold therefore takes two steps
///   (the press, and its first repeat, which looks like a tap after a pause) and glides from its second
///   repeat on; taps are never merged into a hold, whatever their rhythm and pauses (issue #39).
///   What stays ambiguous: a terminal repeating slower than [`HOLD_GAP`] (some repeat every 100 ms) is
///   read as taps, a step per repeat; a repeat that a link delays past [`HOLD_GAP`] takes a step (which
///   stands for its share of the glide); taps that a link lets go together within `STALL` of a hold
///   are taken for its repeats.
/// - Either way, a key's taps step at most [`TAP_BURST`] steps ahead of the time its motion takes at
///   full speed, its glides counted: at most that many at once, then one each step's time (never
///   sooner than [`HOLD_GAP`]). The presses of a paste, or a script's, past that step nothing, and no
///   way of pressing moves further than a hold (bar the burst).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Held {
    keys: [KeyState; Action::CONTINUOUS.len()],
    feet: Feet,
}

impl Held {
    /// The glides up to `now` laid into each key's budget and the walking keys' shared one ([`Feet`]:
    /// the union of their glides).
    fn settle(&mut self, now: f64) {
        let mut spans = [(0.0, 0.0); FEET.end];
        let mut count = 0;
        for key in &self.keys[FEET] {
            if let Some((from, until)) = key.glide {
                let (start, end) = (from.max(self.feet.glides_paid_to), until.min(now));
                if end > start {
                    spans[count] = (start, end);
                    count += 1;
                }
            }
        }
        let spans = &mut spans[..count];
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut laid_to = f64::NEG_INFINITY; // (within the union: each stretch once)
        for &(start, end) in spans.iter() {
            let start = start.max(laid_to);
            if end > start {
                self.feet.paid_until = self.feet.paid_until.max(start) + (end - start);
                laid_to = end;
            }
        }
        self.feet.glides_paid_to = self.feet.glides_paid_to.max(now);
        for key in &mut self.keys {
            key.settle(now);
        }
    }

    /// Whether a tap of the key in `slot` at `now` may take its step (a step taking `step_seconds` at
    /// full speed): while the key's motion, and for a walking key the walking keys' together
    /// ([`Feet`]), is at most [`TAP_BURST`] − 1 steps ahead of the time it takes at full speed (each
    /// step at least [`HOLD_GAP`], a person's fastest tapping). Its step is then laid on. (Settled.)
    fn take_tap(&mut self, slot: usize, now: f64, step_seconds: f64) -> bool {
        let pace = step_seconds.max(HOLD_GAP);
        let walking = FEET.contains(&slot);
        let key = &mut self.keys[slot];
        if !tap_room(key.paid_until, now, pace) || walking && !tap_room(self.feet.paid_until, now, pace) {
            return false;
        }
        key.paid_until = key.paid_until.max(now) + pace;
        if walking {
            self.feet.paid_until = self.feet.paid_until.max(now) + pace;
        }
        true
    }

    /// A key went down at time `now` (seconds); `releases`: the terminal reports releases; `repeat`: the
    /// terminal said this is an auto-repeat; `step_seconds`: how long the action's step takes at full
    /// speed. Returns whether the caller takes one step now.
    pub fn press(
        &mut self,
        action: Action,
        now: f64,
        releases: bool,
        repeat: bool,
        step_seconds: f64,
    ) -> bool {
        let Some(slot) = action.slot() else { return false };
        self.settle(now); // the glides so far, before anything changes them
        let key = &mut self.keys[slot];
        let gap = now - key.last_press;
        key.last_press = now;
        if releases {
            if repeat {
                return false; // already gliding until the release
            }
            let stepped = self.take_tap(slot, now, step_seconds);
            // (past the taps in hand, a burst moves nothing)
            self.keys[slot].glide = stepped.then_some((now + step_seconds, f64::INFINITY));
            return stepped;
        }
        let gliding = key.glide.filter(|&(_, until)| until >= now);
        let repeat_rate = (TOGETHER..HOLD_GAP).contains(&gap);
        // presses that arrive together are taps held up on the way, unless the key was just held:
        // then a stalled link let its repeats go at once (the first of them took a step, as a tap)
        let bunched = gap < TOGETHER && (gliding.is_some() || now - key.repeated_at < STALL);
        if !(repeat || repeat_rate || bunched) {
            // A tap: one step, standing for its time at full speed (if a tap is in hand).
            key.glide = None;
            if !self.take_tap(slot, now, step_seconds) {
                return false;
            }
            self.keys[slot].rest_until = now + step_seconds;
            return true;
        }
        let key = &mut self.keys[slot];
        // Auto-repeat: the key is held.
        key.repeated_at = now;
        if repeat_rate {
            key.interval = Some(key.interval.map_or(gap, |interval| (interval + gap) / 2.0));
        }
        let hold = (REPEAT_HOLD_INTERVALS * key.interval.unwrap_or(HOLD_GAP))
            .clamp(REPEAT_HOLD_RANGE.0, REPEAT_HOLD_RANGE.1);
        key.glide = Some(match gliding {
            Some((from, until)) => (from, until.max(now + hold)),
            None => (now.max(key.rest_until), now + hold),
        });
        false
    }

    /// A key went up at `now`.
    pub fn release(&mut self, action: Action, now: f64) {
        if let Some(slot) = action.slot() {
            self.settle(now);
            self.keys[slot].glide = None;
        }
    }

    /// Lets go of everything at `now` (focus lost, suspend, reset). What the keys' motion has taken
    /// stays ([`TAP_BURST`]): a terminal's focus report, which a served client may send at will, does
    /// not give a new burst.
    pub fn clear(&mut self, now: f64) {
        self.settle(now);
        for key in &mut self.keys {
            *key = KeyState { paid_until: key.paid_until, ..KeyState::default() };
        }
    }

    /// Stops all motion at `now` but remembers when each key was last pressed, so that a key still
    /// held comes on as auto-repeat ([`recently_pressed`](Self::recently_pressed)), not as a fresh tap.
    pub(crate) fn clear_motion(&mut self, now: f64) {
        self.settle(now);
        for key in &mut self.keys {
            key.glide = None;
        }
    }

    /// A press of `action`'s key that moves nothing (a box took it), at `now`.
    pub(crate) fn note_press(&mut self, action: Action, now: f64) {
        if let Some(slot) = action.slot() {
            self.keys[slot].last_press = now;
        }
    }

    /// Whether `action`'s key was pressed within [`ANSWER_GAP`] before `now`: a press now is its
    /// auto-repeat (or a tap too quick to mean anything else).
    #[must_use]
    pub(crate) fn recently_pressed(&self, action: Action, now: f64) -> bool {
        action.slot().is_some_and(|slot| now - self.keys[slot].last_press < ANSWER_GAP)
    }

    /// Drops glides that have run out by `now`.
    pub fn expire(&mut self, now: f64) {
        if self.keys.iter().any(|key| key.glide.is_some_and(|(_, until)| until < now)) {
            self.settle(now);
            for key in &mut self.keys {
                if key.glide.is_some_and(|(_, until)| until < now) {
                    key.glide = None;
                }
            }
        }
    }

    /// Whether `action` is held at `now` (gliding, or about to once its step's time is up).
    #[must_use]
    pub(crate) fn is_held(&self, action: Action, now: f64) -> bool {
        action.slot().is_some_and(|slot| self.keys[slot].glide.is_some_and(|(_, until)| until >= now))
    }

    /// For how many seconds between `from` and `to` `action` moves continuously.
    #[must_use]
    pub(crate) fn moving_time(&self, action: Action, from: f64, to: f64) -> f64 {
        let glide = action.slot().and_then(|slot| self.keys[slot].glide);
        glide.map_or(0.0, |(start, until)| (to.min(until) - from.max(start)).max(0.0))
    }

    /// True while anything is held (the event loop keeps animating).
    #[must_use]
    pub fn any(&self, now: f64) -> bool {
        Action::CONTINUOUS.iter().any(|&action| self.is_held(action, now))
    }

    /// The earliest time a hold runs out, if any hold is timed.
    #[must_use]
    pub fn next_expiry(&self) -> Option<f64> {
        self.keys
            .iter()
            .filter_map(|k| k.glide)
            .map(|(_, until)| until)
            .filter(|t| t.is_finite())
            .reduce(f64::min)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_map_to_the_documented_actions() {
        assert_eq!(action_for(Key::Char('W')), Some(Action::Forward));
        assert_eq!(action_for(Key::Char(']')), Some(Action::Rise));
        assert_eq!(action_for(Key::Char('[')), Some(Action::Sink));
        assert_eq!(action_for(Key::Left), Some(Action::TurnLeft));
        assert_eq!(action_for(Key::Up), Some(Action::LookUp));
        assert_eq!(action_for(Key::Esc), Some(Action::Quit));
        assert_eq!(action_for(Key::Char('<')), Some(Action::SnapLeft));
        assert_eq!(action_for(Key::Char('.')), Some(Action::SnapRight));
        assert_eq!(action_for(Key::Char('u')), None);
        assert_eq!(action_for(Key::Char('y')), None);
        // Every binding of README's keys table, capitals too (a terminal with Shift or Caps Lock).
        let bindings = [
            ("wW", Action::Forward),
            ("sS", Action::Back),
            ("aA", Action::StrafeLeft),
            ("dD", Action::StrafeRight),
            ("[", Action::Sink),
            ("]", Action::Rise),
            ("+=", Action::FovWider),
            ("-_", Action::FovNarrower),
            (",<", Action::SnapLeft),
            (".>", Action::SnapRight),
            ("pP", Action::ToggleProjection),
            ("mM", Action::CycleMap),
            ("cC", Action::CycleCharset),
            ("rR", Action::Reset),
            ("bB", Action::ToggleCulling),
            ("vV", Action::ToggleCullingTint),
            ("tT", Action::ToggleTextures),
            ("xX", Action::ToggleChalk),
            ("iI", Action::ToggleFigures),
            ("gG", Action::ToggleGhost),
            ("zZ", Action::ToggleLookAhead),
            ("?hH", Action::Help),
            ("qQ", Action::Quit),
        ];
        for (keys, action) in bindings {
            for key in keys.chars() {
                assert_eq!(action_for(Key::Char(key)), Some(action), "{key:?}");
            }
        }
        let arrows = [(Key::Right, Action::TurnRight), (Key::Down, Action::LookDown)];
        for (key, action) in arrows {
            assert_eq!(action_for(key), Some(action), "{key:?}");
        }
    }

    #[test]
    fn with_releases_a_press_steps_then_glides_until_released() {
        let mut held = Held::default();
        assert!(held.press(Action::Forward, 1.0, true, false, 0.2), "a press steps at once");
        assert!(!held.press(Action::Forward, 1.5, true, true, 0.2), "a repeat does not");
        assert_eq!(held.moving_time(Action::Forward, 1.0, 1.2), 0.0, "the step stands for its 0.2 s");
        assert!((held.moving_time(Action::Forward, 1.0, 100.0) - 98.8).abs() < 1e-9);
        assert_eq!(held.next_expiry(), None, "a release will tell");
        held.release(Action::Forward, 50.0);
        assert!(!held.is_held(Action::Forward, 100.0));
        assert!(!held.any(100.0));
    }

    #[test]
    fn without_releases_taps_step_and_repeats_glide() {
        let mut held = Held::default();
        assert!(held.press(Action::TurnLeft, 0.0, false, false, 0.1), "a tap steps");
        assert!(!held.any(0.0), "and does not glide");
        assert!(held.press(Action::TurnLeft, 0.15, false, false, 0.1), "so does a tap 150 ms later");
        // Auto-repeat every 33 ms: no more steps, a glide that stops soon after the last repeat.
        let mut t = 0.15;
        for _ in 0..30 {
            t += 0.033;
            assert!(!held.press(Action::TurnLeft, t, false, false, 0.1), "a repeat at {t} stepped");
            assert!(held.is_held(Action::TurnLeft, t));
        }
        let stop = held.next_expiry().unwrap();
        let hold = (REPEAT_HOLD_INTERVALS * 0.033).clamp(REPEAT_HOLD_RANGE.0, REPEAT_HOLD_RANGE.1);
        assert!((stop - t - hold).abs() < 1e-9, "stops {} s after the last repeat", stop - t);
        held.expire(stop + 1e-6);
        assert!(!held.any(stop + 1e-6));
    }

    #[test]
    fn opposing_keys_cancel_on_an_axis() {
        let mut held = Held::default();
        held.press(Action::Forward, 0.0, true, false, 0.0);
        held.press(Action::Back, 0.5, true, false, 0.0);
        let (forward, back) =
            (held.moving_time(Action::Forward, 0.0, 1.0), held.moving_time(Action::Back, 0.0, 1.0));
        assert_eq!(forward - back, 0.5, "they cancel once both are down");
    }

    #[test]
    fn one_shot_actions_are_never_held() {
        let mut held = Held::default();
        assert!(!held.press(Action::Quit, 0.0, true, false, 0.0));
        assert!(!held.any(0.0));
    }

    /// A held key's repeats extend one glide from its first repeat on: the motion between repeats is
    /// all there, not restarted at each.
    #[test]
    fn repeats_extend_one_glide_from_the_first() {
        let mut held = Held::default();
        assert!(held.press(Action::Forward, 0.0, false, false, 0.0), "the press: a step");
        assert!(held.press(Action::Forward, 0.5, false, false, 0.0), "the first repeat: a step");
        for t in [0.53, 0.56, 0.59] {
            assert!(!held.press(Action::Forward, t, false, false, 0.0), "repeats glide");
        }
        let moving = held.moving_time(Action::Forward, 0.53, 0.6);
        assert!((moving - 0.07).abs() < 1e-9, "glided {moving} s of the 0.07 s from 0.53");
    }

    /// Focus lost, suspend or reset: nothing moves on; a box's `clear_motion` stops the glides but a
    /// key still held comes back as a repeat, not as a tap.
    #[test]
    fn clearing_stops_every_glide() {
        let mut held = Held::default();
        held.press(Action::TurnLeft, 0.0, true, false, 0.1);
        held.press(Action::Forward, 0.0, true, false, 0.1);
        assert!(held.any(1.0));
        held.clear_motion(1.0);
        assert!(!held.any(1.0) && held.next_expiry().is_none());
        assert!(held.recently_pressed(Action::Forward, 0.05), "the press is remembered");
        held.press(Action::Back, 2.0, true, false, 0.1);
        held.clear(2.0);
        assert!(!held.any(2.5) && held.next_expiry().is_none());
        assert!(!held.recently_pressed(Action::Back, 2.05), "nothing is remembered");
    }

    /// Steps `action` taps at `times` take (a step taking `step_seconds`), without releases.
    fn taps_stepped(
        held: &mut Held,
        action: Action,
        times: impl IntoIterator<Item = f64>,
        step: f64,
    ) -> usize {
        times.into_iter().filter(|&t| held.press(action, t, false, false, step)).count()
    }

    /// Red-team pass 6: a script tapping every 58 ms walked 3× as far as a hold of the key and won a
    /// served race. Taps now step no further than the key's glide would take it, bar the burst, and a
    /// hold's glide counts: holding first and bursting after gives no more.
    #[test]
    fn no_way_of_tapping_moves_further_than_a_hold_bar_the_burst() {
        let step = 0.2; // walking: 1 unit at 5 units a second
        for gap in [0.06, 0.08, 0.125] {
            let mut held = Held::default();
            let taps = (0..).map(|k| 1.0 + gap * f64::from(k)).take_while(|&t| t < 11.0);
            let stepped = taps_stepped(&mut held, Action::Forward, taps, step);
            // 10 s of gliding is 50 steps; the burst 9 more; at most one more for the taps' phase
            assert!(stepped <= 50 + TAP_BURST as usize + 1, "taps {gap} s apart: {stepped} steps in 10 s");
            assert!(stepped >= 50 + TAP_BURST as usize - 2, "taps {gap} s apart: only {stepped} steps");
        }
        // A person tapping at 5 a second or slower: every tap a step, however long.
        let mut held = Held::default();
        let taps = (0..100).map(|k| 1.0 + 0.2 * f64::from(k));
        assert_eq!(taps_stepped(&mut held, Action::Forward, taps, step), 100);
        // A burst, then a hold of 2 s (repeats every 40 ms after 0.4 s), then, past `STALL` after its
        // last repeat, a burst again: the hold's glide is laid after the first burst's steps, so the
        // second burst finds less room, and all of it moves no further than a hold of the whole time
        // and a burst.
        // A walking key's glide counts in its own budget and in the walking keys' shared one, a
        // turning key's in its own alone.
        for (action, step) in [(Action::Forward, step), (Action::TurnLeft, 0.136)] {
            let mut held = Held::default();
            let first = taps_stepped(&mut held, action, [1.0; 20], step);
            // the press at 1.5 (a tap), its repeats every 40 ms from 1.54 to 3.5
            let hold = std::iter::once(1.5).chain((0..50).map(|k| 1.54 + 0.04 * f64::from(k)));
            let hold_steps = taps_stepped(&mut held, action, hold, step);
            let glided = held.moving_time(action, 1.0, 4.01) / step;
            let second = taps_stepped(&mut held, action, [4.01; 20], step);
            let total = (first + hold_steps + second) as f64 + glided;
            let most = 3.01 / step.max(HOLD_GAP) + TAP_BURST + 1.0;
            assert!(total <= most, "{action:?}: {total} steps in 3 s (at most {most})");
            assert!(second < TAP_BURST as usize, "{action:?}: the hold's glide counted: a burst of {second}");
        }
    }

    /// A burst of presses at one instant (a paste, a stalled link letting taps go) steps exactly
    /// [`TAP_BURST`] times, whatever the step's time: the budget's room is not lost to the rounding
    /// of the steps laid end to end.
    #[test]
    fn a_burst_at_one_instant_steps_exactly_the_burst() {
        for step in [0.2, 0.136, 0.1, 0.3, 1.0 / 3.0, 0.07, 0.0] {
            for action in [Action::Forward, Action::TurnRight] {
                let mut held = Held::default();
                let stepped = taps_stepped(&mut held, action, [2.0; 30], step);
                assert_eq!(stepped, TAP_BURST as usize, "{action:?}, a step of {step} s");
            }
        }
    }

    /// Red-team pass 7: each key's taps had a budget of their own, so `w` and `d` tapped in turn
    /// each stepped at its full pace, and facing 45° off a corridor a player walked down it 1.4× as
    /// fast as a hold (2× for the first seconds). The walking keys' taps now share a budget too, and
    /// a glide of one counts against the taps of another; turning keeps a budget of its own.
    #[test]
    fn walking_keys_tapped_in_turn_step_no_more_than_one_key() {
        let step = 0.2;
        let walking = [Action::Forward, Action::StrafeRight, Action::Back, Action::StrafeLeft];
        for gap in [0.06, 0.1, 0.2] {
            let mut held = Held::default();
            let mut stepped = 0;
            let times = (0..).map(|k| 1.0 + gap * f64::from(k)).take_while(|&t| t < 5.0);
            for (k, t) in times.enumerate() {
                // (two keys in turn, then all four)
                let action = if gap < 0.2 { walking[k % 2] } else { walking[k % 4] };
                stepped += usize::from(held.press(action, t, false, false, step));
            }
            // 4 s at full pace is 20 steps, the burst 9 more, one more for the taps' phase
            assert!(stepped <= 20 + TAP_BURST as usize + 1, "taps {gap} s apart: {stepped} steps in 4 s");
        }
        // A person alternating two keys at a walking pace: every tap a step.
        let mut held = Held::default();
        let taps = (0..40).map(|k| (walking[k % 2], 1.0 + 0.25 * k as f64));
        assert_eq!(taps.filter(|&(action, t)| held.press(action, t, false, false, step)).count(), 40);
        // Holding `w` (releases reported) while tapping `d`: the taps step no more than a burst.
        let mut held = Held::default();
        assert!(held.press(Action::Forward, 1.0, true, false, step));
        let taps = (0..20).map(|k| 1.5 + 0.1 * f64::from(k));
        let stepped = taps.filter(|&t| held.press(Action::StrafeRight, t, true, false, step)).count();
        assert!(stepped <= TAP_BURST as usize, "{stepped} strafe steps over a held walk");
        // Turning has its own: a walk's budget spent, turning taps still turn.
        assert!(held.press(Action::TurnLeft, 3.6, false, false, 0.136));
    }

    /// A lost focus (a report any served client may send) lets go of the keys but gives no new burst.
    #[test]
    fn a_focus_report_gives_no_new_burst() {
        for action in [Action::Forward, Action::TurnLeft] {
            let mut held = Held::default();
            let mut stepped = 0;
            for round in 0..20 {
                let t = 1.0 + 0.01 * f64::from(round);
                stepped += taps_stepped(&mut held, action, (0..20).map(|k| t + 1e-5 * f64::from(k)), 0.2);
                held.clear(t + 0.001);
            }
            let most = TAP_BURST as usize + 1;
            assert!(stepped <= most, "{action:?}: {stepped} steps in 0.2 s, the keys cleared between");
        }
    }

    /// A glide that ran out is dropped by `expire`: the session is not woken for it again.
    #[test]
    fn expired_glides_are_dropped() {
        let mut held = Held::default();
        held.press(Action::Forward, 0.0, false, false, 0.0);
        held.press(Action::Forward, 0.5, false, false, 0.0);
        held.press(Action::Forward, 0.53, false, false, 0.0);
        let until = held.next_expiry().expect("a timed glide");
        held.expire(until);
        assert_eq!(held.next_expiry(), Some(until), "not yet run out at its end");
        held.expire(until + 0.001);
        assert_eq!(held.next_expiry(), None, "run out");
        // Two glides: at the later one's end the earlier, run out, is dropped, the later not yet.
        let mut held = Held::default();
        for t in [0.0, 0.5, 0.53] {
            held.press(Action::Forward, t, false, false, 0.0);
        }
        for t in [0.1, 0.6, 0.63] {
            held.press(Action::TurnLeft, t, false, false, 0.0);
        }
        let turn_end =
            |held: &Held| held.keys[Action::TurnLeft.slot().unwrap()].glide.map(|(_, until)| until);
        let (first, last) = (held.next_expiry().unwrap(), turn_end(&held).unwrap());
        assert!(first < last, "the walk's glide ends first");
        held.expire(last);
        assert_eq!(held.next_expiry(), Some(last), "the turn's glide not yet run out at its end");
        assert!(held.is_held(Action::TurnLeft, last) && !held.is_held(Action::Forward, last));
    }

    /// The bounds of the time windows are exclusive: a press exactly `ANSWER_GAP` after the last is
    /// not recent; presses together exactly `STALL` after the key last repeated are taps.
    #[test]
    fn the_windows_end_where_they_say() {
        let mut held = Held::default();
        held.note_press(Action::Forward, 1.0);
        assert!(held.recently_pressed(Action::Forward, 1.0 + ANSWER_GAP / 2.0));
        assert!(!held.recently_pressed(Action::Forward, 1.0 + ANSWER_GAP));
        // A hold whose last repeat is at 0.25; its glide has run out by 0.745.
        let mut held = Held::default();
        for t in [0.0, 0.2, 0.22, 0.25] {
            held.press(Action::TurnLeft, t, false, false, 0.0);
        }
        held.expire(0.745);
        assert!(held.press(Action::TurnLeft, 0.745, false, false, 0.0), "a tap after a pause");
        assert!(held.press(Action::TurnLeft, 0.75, false, false, 0.0), "STALL after the repeat: a tap");
    }
}
