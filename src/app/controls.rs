//! Keys → actions, and which actions are held right now (pure: time is passed in, never read).
//!
//! Terminals that speak the kitty keyboard protocol report presses *and releases*, so an action is held
//! exactly from press to release. Elsewhere only presses arrive, repeated by the terminal's auto-repeat
//! after an initial delay (typically 250–600 ms, then 25–40 per second); there a press holds its action
//! for [`FIRST_PRESS_HOLD`] and each repeat extends it by [`REPEAT_HOLD`], which bridges both the initial
//! delay and the gaps between repeats without a visible stutter, and stops soon after the key is let go.

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
    /// Perspective ↔ orthographic (p).
    ToggleProjection,
    /// Map: off → corner → full screen (m).
    CycleMap,
    /// Next glyph mode (c).
    CycleCharset,
    /// Back to the start (r).
    Reset,
    /// Show or hide the key help (?).
    Help,
    /// Leave (q, Esc).
    Quit,
}

impl Action {
    /// The actions that act continuously while held (the rest fire once per press).
    pub const CONTINUOUS: [Action; 12] = [
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
    pub fn is_continuous(self) -> bool {
        self.slot().is_some()
    }

    /// Its index in [`CONTINUOUS`](Self::CONTINUOUS).
    fn slot(self) -> Option<usize> {
        Action::CONTINUOUS.iter().position(|&a| a == self)
    }
}

use crate::input::Key;

/// The action bound to `key`, if any.
#[must_use]
pub fn action_for(key: Key) -> Option<Action> {
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
            'p' => Action::ToggleProjection,
            'm' => Action::CycleMap,
            'c' => Action::CycleCharset,
            'r' => Action::Reset,
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

/// The key help, one line per binding (shown by `?` and in README).
pub const HELP: &[(&str, &str)] = &[
    ("W / S", "walk forward / back"),
    ("A / D", "step left / right"),
    ("← / →", "turn left / right"),
    ("↑ / ↓", "look up / down"),
    ("[ / ]", "move down / up"),
    ("+ / -", "wider / narrower field of view"),
    ("drag", "look around with the mouse"),
    ("p", "perspective / orthographic"),
    ("m", "map: corner / full / off"),
    ("c", "next glyph mode"),
    ("r", "back to the start"),
    ("?", "this help"),
    ("q / Esc", "quit"),
];

/// How long a press holds its action when the terminal reports no releases (seconds): long enough to
/// bridge a typical auto-repeat delay.
pub const FIRST_PRESS_HOLD: f64 = 0.55;
/// How long each auto-repeat extends the hold (seconds): longer than the gap between repeats.
pub const REPEAT_HOLD: f64 = 0.12;

/// Which continuous actions are held, and until when.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Held {
    /// Per continuous action: `Some(until)` while held; `until = INFINITY` when a release will tell.
    until: [Option<f64>; Action::CONTINUOUS.len()],
}

impl Held {
    /// A key went down at time `now` (seconds). `releases` says whether the terminal reports releases.
    pub fn press(&mut self, action: Action, now: f64, releases: bool, repeat: bool) {
        let Some(slot) = action.slot() else { return };
        let slot = &mut self.until[slot];
        let until = if releases {
            f64::INFINITY
        } else {
            let still_held = slot.is_some_and(|t| t >= now);
            let hold = if repeat || still_held { REPEAT_HOLD } else { FIRST_PRESS_HOLD };
            // A repeat never shortens the first press's hold.
            (now + hold).max(slot.unwrap_or(f64::NEG_INFINITY))
        };
        *slot = Some(until);
    }

    /// A key went up.
    pub fn release(&mut self, action: Action) {
        if let Some(slot) = action.slot() {
            self.until[slot] = None;
        }
    }

    /// Lets go of everything (focus lost, suspend, reset).
    pub fn clear(&mut self) {
        self.until = [None; Action::CONTINUOUS.len()];
    }

    /// Drops holds that have run out by `now`.
    pub fn expire(&mut self, now: f64) {
        for slot in &mut self.until {
            if slot.is_some_and(|t| t < now) {
                *slot = None;
            }
        }
    }

    /// Whether `action` is held at `now`.
    #[must_use]
    pub fn is_held(&self, action: Action, now: f64) -> bool {
        action.slot().is_some_and(|slot| self.until[slot].is_some_and(|t| t >= now))
    }

    /// +1, -1 or 0 from a pair of opposing actions.
    #[must_use]
    pub fn axis(&self, plus: Action, minus: Action, now: f64) -> f32 {
        f32::from(u8::from(self.is_held(plus, now))) - f32::from(u8::from(self.is_held(minus, now)))
    }

    /// True while anything is held (the event loop keeps animating).
    #[must_use]
    pub fn any(&self, now: f64) -> bool {
        self.until.iter().any(|s| s.is_some_and(|t| t >= now))
    }

    /// The earliest time a hold runs out, if any hold is timed.
    #[must_use]
    pub fn next_expiry(&self) -> Option<f64> {
        self.until.iter().flatten().copied().filter(|t| t.is_finite()).reduce(f64::min)
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
        assert_eq!(action_for(Key::Char('z')), None);
    }

    #[test]
    fn with_releases_a_key_is_held_until_released() {
        let mut held = Held::default();
        held.press(Action::Forward, 1.0, true, false);
        assert!(held.is_held(Action::Forward, 100.0));
        held.release(Action::Forward);
        assert!(!held.is_held(Action::Forward, 100.0));
        assert!(!held.any(100.0));
    }

    #[test]
    fn without_releases_a_press_bridges_the_repeat_delay_and_then_stops() {
        let mut held = Held::default();
        held.press(Action::TurnLeft, 0.0, false, false);
        assert!(held.is_held(Action::TurnLeft, 0.5), "bridges a 500 ms auto-repeat delay");
        assert!(!held.is_held(Action::TurnLeft, 0.6), "stops soon after a single tap");
        // Auto-repeat every 33 ms keeps it held; after the last repeat it stops within REPEAT_HOLD.
        let mut t = 0.5;
        while t < 2.0 {
            held.press(Action::TurnLeft, t, false, true);
            t += 0.033;
        }
        assert!(held.is_held(Action::TurnLeft, t));
        held.expire(t + REPEAT_HOLD + 0.01);
        assert!(!held.any(t + REPEAT_HOLD + 0.01));
    }

    #[test]
    fn opposing_keys_cancel_on_an_axis() {
        let mut held = Held::default();
        held.press(Action::Forward, 0.0, true, false);
        assert_eq!(held.axis(Action::Forward, Action::Back, 0.0), 1.0);
        held.press(Action::Back, 0.0, true, false);
        assert_eq!(held.axis(Action::Forward, Action::Back, 0.0), 0.0);
    }

    #[test]
    fn one_shot_actions_are_never_held() {
        let mut held = Held::default();
        held.press(Action::Quit, 0.0, true, false);
        assert!(!held.any(0.0));
    }
}
