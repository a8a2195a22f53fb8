//! The terminal modes of a full-screen walk, as bytes: what enters game mode and what puts the
//! terminal back. Pure; the local walk's guard (the `mazewalk` binary) writes them to its own
//! terminal around raw mode and signals, a server writes them into each player's channel.
//!
//! | mode | on | off |
//! |---|---|---|
//! | alternate screen | `CSI ? 1049 h` | `CSI ? 1049 l` |
//! | cursor | hidden `CSI ? 25 l` | shown `CSI ? 25 h` |
//! | bracketed paste: a paste comes marked, and [`crate::input`] drops it whole (an accidental paste must not play its letters as keys: `r` resets, `q` quits) | `CSI ? 2004 h` | `CSI ? 2004 l` |
//! | mouse: clicks, drags, motion; urxvt and SGR encodings | `CSI ? 1000;1002;1003;1015;1006 h` (one each) | the same with `l`, in reverse |
//! | focus events | `CSI ? 1004 h` | `CSI ? 1004 l` |
//! | kitty keyboard flags 1 (disambiguate) + 2 (report event types) | pushed `CSI > 3 u` | popped `CSI < 1 u` |
//!
//! These are the bytes crossterm 0.29's commands write (the binary's guard tests compare them).
//!
//! And the two questions a walk asks while it runs, whose answers arrive as input
//! ([`crate::input`] decodes them):
//!
//! | question | bytes | answer |
//! |---|---|---|
//! | primary device attributes: after each frame, the flow control's fence | `CSI c` | `CSI ? … c`, once the frame before it is drawn |
//! | the kitty keyboard flags in force | `CSI ? u` | `CSI ? flags u` (kitty-protocol terminals only) |
//! | device status, sent last by a quitting walk: every frame's answer is in | `CSI 5 n` | `CSI 0 n` |

use crate::encoder::SYNC_END;

/// Primary device attributes, `CSI c`: every terminal answers, in order with what it draws.
pub const DEVICE_ATTRIBUTES_QUERY: &[u8] = b"\x1b[c";

/// The kitty keyboard protocol's "which flags are set?", `CSI ? u`.
pub const KEYBOARD_FLAGS_QUERY: &[u8] = b"\x1b[?u";

/// Device status report, `CSI 5 n` ("status?"): every terminal answers [`STATUS_OK`], in order with
/// what came before it.
pub const STATUS_QUERY: &[u8] = b"\x1b[5n";

/// The answer to [`STATUS_QUERY`], `CSI 0 n` ("OK").
pub const STATUS_OK: &[u8] = b"\x1b[0n";

/// Which of the optional modes are on (what [`restore_sequence`] turns off again).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Enabled {
    /// Mouse capture is on.
    pub mouse: bool,
    /// Focus events are on.
    pub focus_events: bool,
    /// Keyboard enhancement flags were pushed: the app gets key release and repeat events.
    pub keyboard_enhancement: bool,
}

impl Enabled {
    /// Every optional mode on.
    pub const ALL: Enabled = Enabled { mouse: true, focus_events: true, keyboard_enhancement: true };

    /// Whether key releases are reported (otherwise the app must time out held keys itself).
    #[must_use]
    pub fn reports_key_releases(&self) -> bool {
        self.keyboard_enhancement
    }
}

const ALTERNATE_SCREEN_ON: &str = "\x1b[?1049h";
const ALTERNATE_SCREEN_OFF: &str = "\x1b[?1049l";
const CURSOR_HIDDEN: &str = "\x1b[?25l";
const CURSOR_SHOWN: &str = "\x1b[?25h";
const BRACKETED_PASTE_ON: &str = "\x1b[?2004h";
const BRACKETED_PASTE_OFF: &str = "\x1b[?2004l";
/// Button events (1000), drags (1002), any motion (1003), then the urxvt (1015) and SGR (1006)
/// encodings, so that columns past 223 are reported.
const MOUSE_ON: &str = "\x1b[?1000h\x1b[?1002h\x1b[?1003h\x1b[?1015h\x1b[?1006h";
const MOUSE_OFF: &str = "\x1b[?1006l\x1b[?1015l\x1b[?1003l\x1b[?1002l\x1b[?1000l";
const FOCUS_ON: &str = "\x1b[?1004h";
const FOCUS_OFF: &str = "\x1b[?1004l";
/// Push kitty keyboard flags DISAMBIGUATE_ESCAPE_CODES (1) | REPORT_EVENT_TYPES (2).
const KEYBOARD_PUSH: &str = "\x1b[>3u";
/// Pop one entry of the kitty keyboard flags' stack.
const KEYBOARD_POP: &str = "\x1b[<1u";
const COLORS_RESET: &str = "\x1b[0m";

/// The bytes that enter game mode: alternate screen, hidden cursor, bracketed paste on, then the
/// optional modes. Keyboard flags are pushed last, on the alternate screen (kitty keeps a stack per
/// screen, and [`restore_sequence`] pops them before leaving it).
///
/// ```
/// use mazewalk_term::modes::{Enabled, enter_sequence};
/// assert_eq!(enter_sequence(Enabled::default()), "\x1b[?1049h\x1b[?25l\x1b[?2004h");
/// assert!(enter_sequence(Enabled::ALL).ends_with("\x1b[?1004h\x1b[>3u"));
/// ```
#[must_use]
pub fn enter_sequence(enabled: Enabled) -> String {
    let mut s = String::with_capacity(96);
    s += ALTERNATE_SCREEN_ON;
    s += CURSOR_HIDDEN;
    s += BRACKETED_PASTE_ON;
    if enabled.mouse {
        s += MOUSE_ON;
    }
    if enabled.focus_events {
        s += FOCUS_ON;
    }
    if enabled.keyboard_enhancement {
        s += KEYBOARD_PUSH;
    }
    s
}

/// The bytes that undo [`enter_sequence`], in reverse: end any half-sent synchronized frame, pop the
/// keyboard flags, mouse and focus reporting off, bracketed paste off, cursor shown, colours reset,
/// main screen back.
/// (A local walk turns raw mode off after writing them.)
#[must_use]
pub fn restore_sequence(enabled: Enabled) -> String {
    let mut s = String::from_utf8_lossy(SYNC_END).into_owned();
    if enabled.keyboard_enhancement {
        s += KEYBOARD_POP;
    }
    if enabled.mouse {
        s += MOUSE_OFF;
    }
    if enabled.focus_events {
        s += FOCUS_OFF;
    }
    s += BRACKETED_PASTE_OFF; // (a shell turns it on again for its prompt, as it likes)
    s += CURSOR_SHOWN;
    s += COLORS_RESET;
    s += ALTERNATE_SCREEN_OFF;
    s
}

/// Home the cursor, then erase the whole screen (terminfo's `clear` for the Linux console and `vt100`).
const CLEAR_SCREEN: &str = "\x1b[H\x1b[2J";

/// [`restore_sequence`] on a terminal with an alternate screen (`alternate_screen`: terminfo's
/// `smcup`, [`crate::caps::terminfo_has_alternate_screen`]) or without one: the Linux console,
/// `vt100`, `vt220`, which ignore `CSI ? 1049`. There the walk's last frame stays on the only
/// screen, with the cursor wherever the last update left it (in the HUD): after the rest, in the
/// default colours, the screen is cleared and the cursor homed, so the shell's prompt lands on a
/// clean screen.
///
/// ```
/// use mazewalk_term::modes::{Enabled, restore_sequence, restore_sequence_for};
/// assert_eq!(restore_sequence_for(Enabled::ALL, true), restore_sequence(Enabled::ALL));
/// assert!(restore_sequence_for(Enabled::ALL, false).ends_with("\x1b[0m\x1b[?1049l\x1b[H\x1b[2J"));
/// ```
#[must_use]
pub fn restore_sequence_for(enabled: Enabled, alternate_screen: bool) -> String {
    let mut s = restore_sequence(enabled);
    if !alternate_screen {
        s += CLEAR_SCREEN;
    }
    s
}

/// The bytes that take the terminal back after a stop that restored nothing (SIGSTOP): the
/// [`enter_sequence`], with our keyboard flags popped just before they are pushed again. They are
/// most likely still on the alternate screen's stack; pushed twice, one would outlive the walk there.
/// (If they are not, the pop of an empty stack only resets the flags.)
#[must_use]
pub fn reenter_sequence(enabled: Enabled) -> String {
    let mut s = enter_sequence(Enabled { keyboard_enhancement: false, ..enabled });
    if enabled.keyboard_enhancement {
        s += KEYBOARD_POP;
        s += KEYBOARD_PUSH;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Human-readable escape sequence, for test messages.
    fn visible(s: &str) -> String {
        s.replace('\x1b', "ESC")
    }

    /// Asserts `haystack` contains each of `needles`, in that order.
    fn assert_in_order(haystack: &str, needles: &[&str]) {
        let mut from = 0;
        for needle in needles {
            let Some(at) = haystack[from..].find(needle) else {
                panic!("{} not found in order in {}", visible(needle), visible(haystack));
            };
            from += at + needle.len();
        }
    }

    #[test]
    fn restore_undoes_everything_in_reverse_order() {
        let restore = restore_sequence(Enabled::ALL);
        assert_in_order(
            &restore,
            &[
                "\x1b[?2026l", // a frame cut short by a panic or signal is ended first
                "\x1b[<1u",    // keyboard flags popped while still on the alternate screen
                "\x1b[?1000l", // mouse off
                "\x1b[?1004l", // focus events off
                "\x1b[?25h",   // cursor shown
                "\x1b[0m",     // colours reset
                "\x1b[?1049l", // main screen back
            ],
        );
    }

    #[test]
    fn restore_only_undoes_what_was_enabled() {
        let restore = restore_sequence(Enabled::default());
        assert!(!restore.contains("\x1b[<"), "{}", visible(&restore));
        assert!(!restore.contains("\x1b[?1000l"));
        assert_in_order(&restore, &["\x1b[?25h", "\x1b[0m", "\x1b[?1049l"]);
    }

    #[test]
    fn enter_pushes_keyboard_flags_last_on_the_alternate_screen() {
        let enter = enter_sequence(Enabled::ALL);
        // REPORT_EVENT_TYPES (2) | DISAMBIGUATE_ESCAPE_CODES (1) = 3.
        assert_in_order(
            &enter,
            &["\x1b[?1049h", "\x1b[?25l", "\x1b[?2004h", "\x1b[?1000h", "\x1b[?1004h", "\x1b[>3u"],
        );
        let plain = enter_sequence(Enabled::default());
        assert!(!plain.contains("\x1b[>") && !plain.contains("\x1b[?1000h"), "{}", visible(&plain));
    }

    #[test]
    fn every_mode_turned_on_is_turned_off() {
        // Each `CSI ? n h` of the enter sequence has its `CSI ? n l` in the restore sequence:
        // bracketed paste too (QA finding 6: on in the walk, so that a paste is dropped whole).
        let enter = enter_sequence(Enabled::ALL);
        let restore = restore_sequence(Enabled::ALL);
        for on in enter.split('\x1b').filter(|s| s.starts_with("[?") && s.ends_with('h')) {
            let off = format!("\x1b{}l", &on[..on.len() - 1]);
            assert!(restore.contains(&off), "{} not undone in {}", visible(on), visible(&restore));
        }
        assert!(enter.contains("\x1b[?25l") && restore.contains("\x1b[?25h"), "the cursor comes back");
    }

    /// QA finding 3: without an alternate screen the last frame is cleared, after the colours are
    /// reset (an erase fills with the current background), and the cursor is left at the top.
    #[test]
    fn without_an_alternate_screen_the_restore_clears_and_homes() {
        for enabled in [Enabled::ALL, Enabled::default()] {
            let kept = restore_sequence_for(enabled, true);
            assert_eq!(kept, restore_sequence(enabled), "with one: today's bytes");
            assert!(!kept.contains("\x1b[2J"), "{}", visible(&kept));
            let cleared = restore_sequence_for(enabled, false);
            assert_eq!(cleared.strip_suffix("\x1b[H\x1b[2J"), Some(kept.as_str()), "{}", visible(&cleared));
            assert_in_order(&cleared, &["\x1b[?25h", "\x1b[0m", "\x1b[H", "\x1b[2J"]);
        }
    }

    #[test]
    fn reenter_pops_the_keyboard_flags_before_pushing_them_again() {
        // After a stop that restored nothing, our flags are likely still on the alternate screen's
        // stack: popped on that screen, then pushed, so the stack holds them once.
        let reenter = reenter_sequence(Enabled::ALL);
        assert_in_order(
            &reenter,
            &["\x1b[?1049h", "\x1b[?25l", "\x1b[?1000h", "\x1b[?1004h", "\x1b[<1u", "\x1b[>3u"],
        );
        assert!(reenter.ends_with("\x1b[>3u"), "{}", visible(&reenter));
        assert_eq!(reenter.replace("\x1b[<1u", ""), enter_sequence(Enabled::ALL));
        // Without keyboard flags there is nothing to pop: the same bytes as entering.
        let plain = Enabled { keyboard_enhancement: false, ..Enabled::ALL };
        assert_eq!(reenter_sequence(plain), enter_sequence(plain));
    }
}
