//! Input: crossterm events mapped to mazewalk's own [`Input`], so the app never sees crossterm types.
//!
//! [`InputDecoder`] is the pure mapping (it remembers the last mouse position, to turn drags into
//! deltas); [`InputReader::next_input`] is the blocking wrapper around `crossterm::event::{poll, read}`.

use std::io;
use std::time::{Duration, Instant};

use crossterm::event::{self, Event, KeyCode, KeyEventKind, KeyModifiers, MouseEventKind};

/// A key, independent of crossterm.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    /// A character key. ASCII letters are always lowercase (shift is in [`Modifiers`]), so a press of
    /// `W` and the release of `w` that follows when shift goes up first are the same key.
    Char(char),
    /// Arrow up.
    Up,
    /// Arrow down.
    Down,
    /// Arrow left.
    Left,
    /// Arrow right.
    Right,
    /// Enter / Return.
    Enter,
    /// Escape.
    Esc,
    /// Tab (shift-tab is `Tab` with shift).
    Tab,
    /// Backspace.
    Backspace,
    /// Home.
    Home,
    /// End.
    End,
    /// Page up.
    PageUp,
    /// Page down.
    PageDown,
    /// A function key, `F(1)` to `F(24)`.
    F(u8),
    /// Anything else (media keys, lone modifiers…).
    Other,
}

/// Whether a key went down, auto-repeated or came up. Terminals without the kitty protocol only
/// report `Press` (repeats look like presses).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KeyAction {
    /// The key went down (or, without the kitty protocol, any key event).
    Press,
    /// Auto-repeat while held.
    Repeat,
    /// The key came up.
    Release,
}

/// Modifier keys held with a key or mouse event.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Modifiers {
    /// Shift.
    pub shift: bool,
    /// Control.
    pub ctrl: bool,
    /// Alt / Option / Meta.
    pub alt: bool,
}

/// A mouse button.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MouseButton {
    /// Left (primary).
    Left,
    /// Right (secondary).
    Right,
    /// Middle (wheel click).
    Middle,
}

/// One input event for the app. Grid coordinates: column, row from the top-left, 0-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Input {
    /// A key event.
    Key {
        /// Which key.
        key: Key,
        /// Down, repeat or up.
        action: KeyAction,
        /// Modifiers held.
        modifiers: Modifiers,
    },
    /// A mouse button went down at (`col`, `row`).
    MouseDown {
        /// Which button.
        button: MouseButton,
        /// Column.
        col: u16,
        /// Row.
        row: u16,
    },
    /// A mouse button came up.
    MouseUp {
        /// Which button.
        button: MouseButton,
    },
    /// The mouse moved by (`dx`, `dy`) cells with `button` held (drag to look around).
    MouseDrag {
        /// Which button is held.
        button: MouseButton,
        /// Columns moved, positive to the right.
        dx: i32,
        /// Rows moved, positive downwards.
        dy: i32,
    },
    /// The wheel turned: +1 per notch up (away from the user), -1 down.
    Scroll(i32),
    /// The terminal now has `cols` × `rows` cells.
    Resize {
        /// Columns.
        cols: u16,
        /// Rows.
        rows: u16,
    },
    /// The terminal window got focus.
    FocusGained,
    /// The terminal window lost focus: held keys will get no release, so forget them.
    FocusLost,
}

/// Maps crossterm events to [`Input`]; remembers the last mouse position for drag deltas.
#[derive(Clone, Debug, Default)]
pub struct InputDecoder {
    last_mouse: Option<(u16, u16)>,
}

impl InputDecoder {
    /// A decoder that has seen no mouse yet.
    #[must_use]
    pub fn new() -> InputDecoder {
        InputDecoder::default()
    }

    /// The [`Input`] for `event`, or `None` for events the app doesn't use (mouse moves without a
    /// button, paste, horizontal scroll).
    pub fn decode(&mut self, event: &Event) -> Option<Input> {
        match event {
            Event::Key(key) => {
                let (key_code, shifted) = key_from(key.code);
                let mut modifiers = modifiers_from(key.modifiers);
                modifiers.shift |= shifted;
                let action = match key.kind {
                    KeyEventKind::Press => KeyAction::Press,
                    KeyEventKind::Repeat => KeyAction::Repeat,
                    KeyEventKind::Release => KeyAction::Release,
                };
                Some(Input::Key { key: key_code, action, modifiers })
            }
            Event::Mouse(mouse) => {
                let at = (mouse.column, mouse.row);
                let last = self.last_mouse.replace(at).unwrap_or(at);
                match mouse.kind {
                    MouseEventKind::Down(b) => {
                        Some(Input::MouseDown { button: button_from(b), col: at.0, row: at.1 })
                    }
                    MouseEventKind::Up(b) => Some(Input::MouseUp { button: button_from(b) }),
                    MouseEventKind::Drag(b) => Some(Input::MouseDrag {
                        button: button_from(b),
                        dx: i32::from(at.0) - i32::from(last.0),
                        dy: i32::from(at.1) - i32::from(last.1),
                    }),
                    MouseEventKind::ScrollUp => Some(Input::Scroll(1)),
                    MouseEventKind::ScrollDown => Some(Input::Scroll(-1)),
                    MouseEventKind::Moved | MouseEventKind::ScrollLeft | MouseEventKind::ScrollRight => None,
                }
            }
            Event::Resize(cols, rows) => Some(Input::Resize { cols: *cols, rows: *rows }),
            Event::FocusGained => Some(Input::FocusGained),
            Event::FocusLost => Some(Input::FocusLost),
            Event::Paste(_) => None,
        }
    }
}

/// The key, and whether it was an uppercase ASCII letter (folded to lowercase, shift implied).
fn key_from(code: KeyCode) -> (Key, bool) {
    let key = match code {
        KeyCode::Char(c) if c.is_ascii_uppercase() => return (Key::Char(c.to_ascii_lowercase()), true),
        KeyCode::Char(c) => Key::Char(c),
        KeyCode::Up => Key::Up,
        KeyCode::Down => Key::Down,
        KeyCode::Left => Key::Left,
        KeyCode::Right => Key::Right,
        KeyCode::Enter => Key::Enter,
        KeyCode::Esc => Key::Esc,
        KeyCode::Tab => Key::Tab,
        KeyCode::BackTab => return (Key::Tab, true),
        KeyCode::Backspace => Key::Backspace,
        KeyCode::Home => Key::Home,
        KeyCode::End => Key::End,
        KeyCode::PageUp => Key::PageUp,
        KeyCode::PageDown => Key::PageDown,
        KeyCode::F(n) => Key::F(n),
        _ => Key::Other,
    };
    (key, false)
}

fn modifiers_from(m: KeyModifiers) -> Modifiers {
    Modifiers {
        shift: m.contains(KeyModifiers::SHIFT),
        ctrl: m.contains(KeyModifiers::CONTROL),
        alt: m.contains(KeyModifiers::ALT),
    }
}

fn button_from(b: event::MouseButton) -> MouseButton {
    match b {
        event::MouseButton::Left => MouseButton::Left,
        event::MouseButton::Right => MouseButton::Right,
        event::MouseButton::Middle => MouseButton::Middle,
    }
}

/// Reads terminal input (needs the terminal in raw mode, i.e. a live
/// [`TerminalGuard`](super::guard::TerminalGuard)).
#[derive(Debug, Default)]
pub struct InputReader {
    decoder: InputDecoder,
}

impl InputReader {
    /// A reader with a fresh [`InputDecoder`].
    #[must_use]
    pub fn new() -> InputReader {
        InputReader::default()
    }

    /// The next input, waiting at most `timeout`; `Ok(None)` if none came in time (`Duration::ZERO`:
    /// don't wait, for draining what is queued). Events the app doesn't use are skipped.
    ///
    /// # Errors
    /// Reading the terminal failed.
    pub fn next_input(&mut self, timeout: Duration) -> io::Result<Option<Input>> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if !event::poll(left)? {
                return Ok(None);
            }
            if let Some(input) = self.decoder.decode(&event::read()?) {
                return Ok(Some(input));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crossterm::event::{KeyEvent, KeyEventState, MouseEvent};

    fn key(code: KeyCode, modifiers: KeyModifiers, kind: KeyEventKind) -> Event {
        Event::Key(KeyEvent { code, modifiers, kind, state: KeyEventState::NONE })
    }

    fn mouse(kind: MouseEventKind, column: u16, row: u16) -> Event {
        Event::Mouse(MouseEvent { kind, column, row, modifiers: KeyModifiers::NONE })
    }

    #[test]
    fn keys_map_with_action_and_modifiers_and_letters_fold_to_lowercase() {
        let mut d = InputDecoder::new();
        let shift = Modifiers { shift: true, ..Modifiers::default() };
        assert_eq!(
            d.decode(&key(KeyCode::Char('W'), KeyModifiers::SHIFT, KeyEventKind::Press)),
            Some(Input::Key { key: Key::Char('w'), action: KeyAction::Press, modifiers: shift })
        );
        assert_eq!(
            d.decode(&key(KeyCode::Char('w'), KeyModifiers::NONE, KeyEventKind::Release)),
            Some(Input::Key {
                key: Key::Char('w'),
                action: KeyAction::Release,
                modifiers: Modifiers::default()
            })
        );
        let ctrl = Modifiers { ctrl: true, ..Modifiers::default() };
        assert_eq!(
            d.decode(&key(KeyCode::Char('c'), KeyModifiers::CONTROL, KeyEventKind::Press)),
            Some(Input::Key { key: Key::Char('c'), action: KeyAction::Press, modifiers: ctrl })
        );
        assert_eq!(
            d.decode(&key(KeyCode::Left, KeyModifiers::NONE, KeyEventKind::Repeat)),
            Some(Input::Key { key: Key::Left, action: KeyAction::Repeat, modifiers: Modifiers::default() })
        );
    }

    #[test]
    fn drags_become_deltas_from_the_last_mouse_position() {
        let mut d = InputDecoder::new();
        use event::MouseButton::Left;
        assert_eq!(
            d.decode(&mouse(MouseEventKind::Down(Left), 10, 5)),
            Some(Input::MouseDown { button: MouseButton::Left, col: 10, row: 5 })
        );
        assert_eq!(
            d.decode(&mouse(MouseEventKind::Drag(Left), 13, 4)),
            Some(Input::MouseDrag { button: MouseButton::Left, dx: 3, dy: -1 })
        );
        assert_eq!(
            d.decode(&mouse(MouseEventKind::Drag(Left), 11, 4)),
            Some(Input::MouseDrag { button: MouseButton::Left, dx: -2, dy: 0 })
        );
        assert_eq!(d.decode(&mouse(MouseEventKind::Moved, 0, 0)), None);
        assert_eq!(d.decode(&mouse(MouseEventKind::ScrollUp, 0, 0)), Some(Input::Scroll(1)));
    }

    #[test]
    fn resize_and_focus_pass_through() {
        let mut d = InputDecoder::new();
        assert_eq!(d.decode(&Event::Resize(80, 24)), Some(Input::Resize { cols: 80, rows: 24 }));
        assert_eq!(d.decode(&Event::FocusLost), Some(Input::FocusLost));
        assert_eq!(d.decode(&Event::Paste("x".into())), None);
    }
}
