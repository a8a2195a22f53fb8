//! Terminal input as a byte stream: keys, mouse, focus and the terminal's replies — pure, no I/O.
//!
//! A terminal (a local tty, an SSH channel) sends bytes; [`InputDecoder::feed`] turns any chunk of
//! them into [`Input`]s, keeping whatever sequence a chunk ends in the middle of for the next one. It
//! understands
//!
//! - legacy xterm keys: text (UTF-8), C0 controls (`Ctrl-C` is `0x03`), `CSI`/`SS3` cursor and
//!   function keys with xterm's modifier parameter (`ESC [ 1 ; 5 D` is Ctrl-←), `ESC x` as Alt-x;
//! - the kitty keyboard protocol (`CSI code ; mods : event u` and the functional keys with an event
//!   field), which reports key presses, repeats and **releases**;
//! - SGR mouse reports (`CSI < b ; x ; y M/m`), and urxvt's (`CSI b+32 ; x ; y M`), turned into
//!   presses, releases, drags (as deltas) and wheel notches; legacy X10 reports are skipped whole, so
//!   their coordinate bytes never become keys;
//! - focus in/out (`CSI I`/`CSI O`); bracketed paste (`CSI 200~ … CSI 201~`) is dropped whole, so
//!   pasted text never walks the viewer;
//! - the terminal's **replies**: primary device attributes (`CSI ? … c`), a cursor position report
//!   (`CSI row ; col R`), the kitty keyboard flags (`CSI ? flags u`) and the answers about 24-bit
//!   colour ([`Reply::DirectColor`]: DECRQSS and XTGETTCAP strings, `DCS … ST`), surfaced as
//!   [`Input::Reply`] (a reply arrives only after the terminal has processed everything sent before
//!   the query: the basis of end-to-end flow control). A string's terminator `ESC \` is never the
//!   Esc key, even when a read ends between its two bytes.
//!
//! A lone `Esc` is ambiguous with the start of a sequence: it is resolved as the Esc key when no
//! byte follows within [`ESC_TIMEOUT`] (ask [`InputDecoder::deadline`] when, and call
//! [`InputDecoder::expire`] then). A partial sequence that never completes is dropped the same way,
//! and one longer than [`MAX_SEQUENCE`] bytes is dropped at once: memory stays bounded whatever
//! arrives.
//!
//! Tokenizing escape sequences is the `vte` crate's job (alacritty's parser, the DEC VT500 state
//! machine: parameters, sub-parameters, intermediates, UTF-8, strings, all bounded); this module gives
//! the tokens their meaning as input. Time is passed in (seconds, the caller's clock), never read.
//!
//! ```
//! use mazewalk_term::input::{Input, InputDecoder, Key, KeyPhase, Modifiers};
//! let mut decoder = InputDecoder::new();
//! let mut inputs = Vec::new();
//! decoder.feed(b"w\x1b[1;5", 0.0, &mut inputs); // a key, then half of Ctrl-←
//! decoder.feed(b"D", 0.001, &mut inputs);
//! let ctrl = Modifiers { ctrl: true, ..Modifiers::NONE };
//! assert_eq!(inputs, [Input::press(Key::Char('w')), Input::Key { key: Key::Left, phase: KeyPhase::Press, modifiers: ctrl }]);
//! ```

use vte::{Params, Parser, Perform};

/// How long a lone `Esc` (or any unfinished sequence) waits for the rest before it is resolved, in
/// seconds. Long enough for a sequence split across two reads on a slow SSH link; short enough that
/// the Esc key feels immediate.
pub const ESC_TIMEOUT: f64 = 0.15;

/// How long a paste may pause before it is taken as over, in seconds (its end marker lost).
pub const PASTE_IDLE: f64 = 0.5;

/// The longest escape sequence kept while waiting for its end (bytes); longer ones are dropped (no
/// input mazewalk understands comes close; an OSC or DCS string from a confused terminal might).
pub const MAX_SEQUENCE: usize = 4096;

/// A key. ASCII letters are always lowercase, with shift in [`Modifiers`]: a press of `W` and the
/// release of `w` that follows when shift goes up first are the same key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    /// A character key (ASCII letters lowercase).
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
    /// Insert.
    Insert,
    /// Delete.
    Delete,
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
    /// Anything else (keypad and media keys, lone modifiers in the kitty protocol…).
    Other,
}

/// Whether a key went down, auto-repeated or came up. Terminals without the kitty protocol report
/// only `Press` (their auto-repeat looks like more presses).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KeyPhase {
    /// The key went down (or, without the kitty protocol, any key event).
    Press,
    /// Auto-repeat while held (kitty protocol).
    Repeat,
    /// The key came up (kitty protocol).
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

impl Modifiers {
    /// No modifier.
    pub const NONE: Modifiers = Modifiers { shift: false, ctrl: false, alt: false };

    /// From xterm's and kitty's modifier parameter: 1 + a bit set (shift 1, alt 2, ctrl 4; the rest —
    /// super, hyper, meta, caps and num lock — are not ours).
    fn from_param(param: u16) -> Modifiers {
        let bits = param.saturating_sub(1);
        Modifiers { shift: bits & 1 != 0, alt: bits & 2 != 0, ctrl: bits & 4 != 0 }
    }

    /// The parameter [`from_param`](Self::from_param) reads.
    fn param(self) -> u16 {
        1 + u16::from(self.shift) + 2 * u16::from(self.alt) + 4 * u16::from(self.ctrl)
    }
}

/// A mouse button.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MouseButton {
    /// Left (primary).
    Left,
    /// Middle (wheel click).
    Middle,
    /// Right (secondary).
    Right,
}

/// A reply the terminal sends to a query.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Reply {
    /// Primary device attributes (`CSI ? … c`, the answer to `CSI c`): every terminal answers it, and
    /// only after everything sent before the query.
    DeviceAttributes,
    /// Cursor position report (the answer to `CSI 6 n`), 1-based.
    CursorPosition {
        /// Row, from 1 at the top.
        row: u16,
        /// Column, from 1 at the left.
        col: u16,
    },
    /// The kitty keyboard protocol's flags (the answer to `CSI ? u`): the terminal speaks it.
    KeyboardFlags(u16),
    /// An answer to [`TRUECOLOR_QUERY`](crate::caps::TRUECOLOR_QUERY): `true` when it says the
    /// terminal shows 24-bit colour (DECRQSS gives back the pen `48:2…:1:2:3`; XTGETTCAP knows `RGB`
    /// or `Tc`), `false` when it says it does not (the pen came back as a palette colour; `RGB` is
    /// `-1`). Answers that prove nothing (`DCS 0 $ r`, `DCS 0 + r`, other capabilities) and garbage
    /// are no reply at all.
    DirectColor(bool),
}

/// One input event. Grid coordinates are 0-based columns and rows from the top-left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Input {
    /// A key event.
    Key {
        /// Which key.
        key: Key,
        /// Down, repeat or up.
        phase: KeyPhase,
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
    /// The terminal window got focus.
    FocusGained,
    /// The terminal window lost focus: held keys will get no release, so forget them.
    FocusLost,
    /// The terminal now has `cols` × `rows` cells. Not in the byte stream: the host reports it
    /// (SIGWINCH locally, a window-change request over SSH).
    Resize {
        /// Columns.
        cols: u16,
        /// Rows.
        rows: u16,
    },
    /// The terminal answered a query.
    Reply(Reply),
}

impl Input {
    /// A key press without modifiers.
    #[must_use]
    pub const fn press(key: Key) -> Input {
        Input::Key { key, phase: KeyPhase::Press, modifiers: Modifiers::NONE }
    }
}

/// The byte-stream decoder. Feed it chunks as they arrive; it keeps an unfinished sequence between
/// chunks, and the last mouse position (drags become deltas).
pub struct InputDecoder {
    parser: Parser,
    state: State,
}

impl std::fmt::Debug for InputDecoder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InputDecoder").field("state", &self.state).finish_non_exhaustive()
    }
}

impl Default for InputDecoder {
    fn default() -> Self {
        InputDecoder::new()
    }
}

/// What the decoder remembers besides the tokenizer's own state.
#[derive(Clone, Debug, Default)]
struct State {
    /// Bytes fed since the last complete token (0: between tokens).
    pending: usize,
    /// The first of those bytes.
    pending_first: u8,
    /// Bytes fed since the tokenizer last completed a token. Unlike `pending`, a UTF-8 lead byte
    /// does not start it again: inside an OSC string, which the tokenizer keeps whole until its
    /// end, `é` after `é` would otherwise never reach [`MAX_SEQUENCE`].
    unfinished: usize,
    /// When the last byte arrived.
    last_byte_at: f64,
    /// Set by every token the tokenizer completes (a print, a control, a sequence).
    completed: bool,
    /// `ESC O` arrived: the next character is an SS3 key (application cursor keys, F1–F4).
    ss3: bool,
    /// Raw bytes still to skip (the three coordinate bytes of a legacy X10 mouse report).
    skip: u8,
    /// Inside a bracketed paste: everything is dropped until its end marker.
    in_paste: bool,
    /// Bytes arrived since the stream last paused: the tokenizer may be inside a sequence (its own
    /// state is not observable, so a pause resets it: [`InputDecoder::expire`]).
    unsettled: bool,
    /// Where the mouse was last reported.
    last_mouse: Option<(u16, u16)>,
    /// Which button a drag holds.
    drag_button: Option<MouseButton>,
    /// Bytes were dropped ([`InputDecoder::gap`]): skip to the next ESC or pause.
    after_gap: bool,
    /// The DCS string being read, if it is one of the answers mazewalk asks for.
    dcs: Option<DcsAnswer>,
    /// Its bytes so far (at most [`MAX_DCS`]).
    dcs_data: Vec<u8>,
    /// What the DCS string that just ended answered, emitted unless it was cancelled (CAN, SUB).
    dcs_answer: Option<bool>,
    /// Set by the tokenizer when a string (OSC, DCS) ends.
    string_ended: bool,
    /// The last byte was an ESC that ended a string: the first half of its terminator `ESC \`, not
    /// the Esc key, even if the `\` is late.
    terminator: bool,
    /// A pause came after such an ESC: a `\` next is the rest of the terminator, not the key.
    late_terminator: bool,
}

/// The DCS answers [`InputDecoder`] reads ([`Reply::DirectColor`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DcsAnswer {
    /// `DCS 1 $ r … ST`: DECRQSS's valid answer.
    Decrqss,
    /// `DCS 1 + r … ST`: XTGETTCAP's answer for capabilities it knows.
    Xtgettcap,
}

/// The longest DCS answer kept (bytes): a pen or a few capabilities. Longer ones are garbage.
const MAX_DCS: usize = 256;

impl InputDecoder {
    /// A decoder between sequences, that has seen no mouse yet.
    #[must_use]
    pub fn new() -> InputDecoder {
        InputDecoder { parser: Parser::new(), state: State::default() }
    }

    /// Decodes `bytes` (arriving at time `now`, seconds) and appends the inputs they complete to
    /// `out`. Never fails: bytes that mean nothing are skipped.
    pub fn feed(&mut self, bytes: &[u8], now: f64, out: &mut Vec<Input>) {
        if self.state.after_gap && self.deadline().is_some_and(|at| now >= at) {
            self.state.after_gap = false; // a pause since the gap: a fresh start
        }
        if !bytes.is_empty() {
            (self.state.last_byte_at, self.state.unsettled) = (now, true);
        }
        for &byte in bytes {
            let state = &mut self.state;
            if std::mem::take(&mut state.late_terminator) && byte == b'\\' {
                continue;
            }
            if state.after_gap {
                if byte != 0x1B {
                    continue;
                }
                state.after_gap = false;
            }
            if state.skip > 0 {
                state.skip -= 1;
                continue;
            }
            if state.pending == 0 && byte == 0x7F {
                // DEL is Backspace on every current terminal; the VT500 tokenizer ignores it.
                if !state.in_paste {
                    out.push(Input::press(Key::Backspace));
                }
                continue;
            }
            if state.pending == 1 && state.pending_first == 0x1B && byte == 0x1B {
                // Esc, Esc: the first was the key (the tokenizer would restart the sequence) — unless
                // it ended a string.
                if !state.in_paste && !state.terminator {
                    out.push(Input::press(Key::Esc));
                }
                state.pending = 0;
            }
            (state.completed, state.string_ended) = (false, false);
            let mut performer = Performer { state, out };
            self.parser.advance(&mut performer, &[byte]);
            let state = &mut self.state;
            if byte == 0x1B {
                state.terminator = state.string_ended;
            } else if state.completed {
                state.terminator = false;
            }
            if let Some(direct) = state.dcs_answer.take()
                && !matches!(byte, 0x18 | 0x1A) // CAN and SUB cancel a string
                && !state.in_paste
            {
                out.push(Input::Reply(Reply::DirectColor(direct)));
            }
            state.unfinished = if state.completed { 0 } else { state.unfinished + 1 };
            if byte == 0x1B || (0xC2..=0xF4).contains(&byte) {
                // Starts a sequence or a character, even when it also ended an invalid one.
                (state.pending, state.pending_first) = (1, byte);
            } else if state.completed {
                state.pending = 0;
            } else {
                if state.pending == 0 {
                    state.pending_first = byte;
                }
                state.pending += 1;
            }
            if state.pending > MAX_SEQUENCE || state.unfinished > MAX_SEQUENCE {
                self.reset();
            }
        }
    }

    /// When the stream counts as paused ([`expire`](Self::expire)): [`ESC_TIMEOUT`] after the last
    /// byte ([`PASTE_IDLE`] inside a paste); `None` once a pause has been taken.
    #[must_use]
    pub fn deadline(&self) -> Option<f64> {
        let s = &self.state;
        s.unsettled.then_some(s.last_byte_at + if s.in_paste { PASTE_IDLE } else { ESC_TIMEOUT })
    }

    /// Takes the pause at the [`deadline`](Self::deadline) if `now` is past it: a lone `Esc` becomes
    /// the Esc key; an unfinished sequence is dropped; a paste whose end never came is over (so a
    /// stray paste marker cannot swallow the keys after it).
    pub fn expire(&mut self, now: f64, out: &mut Vec<Input>) {
        if self.deadline().is_none_or(|at| now < at) {
            return;
        }
        let state = &self.state;
        let lone_esc = state.pending == 1 && state.pending_first == 0x1B && !state.in_paste;
        let terminator = lone_esc && state.terminator;
        if lone_esc && !terminator {
            out.push(Input::press(Key::Esc));
        }
        self.reset();
        self.state.late_terminator = terminator;
        (self.state.in_paste, self.state.unsettled, self.state.after_gap) = (false, false, false);
    }

    /// Bytes were dropped here (a rate limit): the sequence they cut is dropped, an ESC waiting
    /// for the rest of its sequence included (taken for the Esc key, it would quit), and so is
    /// everything up to the next ESC or the next pause, which may be the cut sequence's end (`[C`
    /// would be the keys `[` and `C`).
    pub fn gap(&mut self) {
        self.reset();
        self.state.after_gap = true;
    }

    /// Drops whatever sequence is unfinished.
    fn reset(&mut self) {
        self.parser = Parser::new();
        let state = &mut self.state;
        (state.pending, state.unfinished, state.ss3, state.skip, state.terminator) = (0, 0, false, 0, false);
        state.dcs = None;
        state.dcs_data.clear();
    }
}

/// The tokenizer's callbacks: each token becomes zero or one [`Input`].
struct Performer<'a> {
    state: &'a mut State,
    out: &'a mut Vec<Input>,
}

impl Performer<'_> {
    fn emit(&mut self, input: Input) {
        if !self.state.in_paste {
            self.out.push(input);
        }
    }

    fn key(&mut self, key: Key, modifiers: Modifiers, phase: KeyPhase) {
        let (key, modifiers) = fold_case(key, modifiers);
        self.emit(Input::Key { key, phase, modifiers });
    }

    /// An SGR mouse report: button code `b` (low bits the button, +32 motion, +64 wheel), 1-based
    /// (`x`, `y`), `release` for the final `m`.
    fn mouse(&mut self, b: u16, x: u16, y: u16, release: bool) {
        let at = (x.saturating_sub(1), y.saturating_sub(1));
        let last = self.state.last_mouse.replace(at).unwrap_or(at);
        let button = match b & 3 {
            0 => Some(MouseButton::Left),
            1 => Some(MouseButton::Middle),
            2 => Some(MouseButton::Right),
            _ => None,
        };
        let input = if b & 64 != 0 {
            match b & 3 {
                0 => Input::Scroll(1),
                1 => Input::Scroll(-1),
                _ => return, // horizontal wheel
            }
        } else if b & 32 != 0 {
            // Motion: a drag while a button is down (the report's own button may be "none").
            let Some(button) = button.or(self.state.drag_button) else { return };
            let (dx, dy) = (i32::from(at.0) - i32::from(last.0), i32::from(at.1) - i32::from(last.1));
            Input::MouseDrag { button, dx, dy }
        } else if let Some(button) = button {
            if release {
                self.state.drag_button = None;
                Input::MouseUp { button }
            } else {
                self.state.drag_button = Some(button);
                Input::MouseDown { button, col: at.0, row: at.1 }
            }
        } else {
            return;
        };
        self.emit(input);
    }
}

/// ASCII uppercase folds to lowercase with shift (see [`Key`]).
fn fold_case(key: Key, mut modifiers: Modifiers) -> (Key, Modifiers) {
    match key {
        Key::Char(c) if c.is_ascii_uppercase() => {
            modifiers.shift = true;
            (Key::Char(c.to_ascii_lowercase()), modifiers)
        }
        _ => (key, modifiers),
    }
}

/// The key a C0 control byte stands for (`0x01`–`0x1A` are Ctrl-A–Ctrl-Z).
fn control_key(byte: u8) -> Option<(Key, Modifiers)> {
    let ctrl = Modifiers { ctrl: true, ..Modifiers::NONE };
    Some(match byte {
        b'\r' | b'\n' => (Key::Enter, Modifiers::NONE),
        b'\t' => (Key::Tab, Modifiers::NONE),
        0x08 => (Key::Backspace, Modifiers::NONE),
        0x00 => (Key::Char(' '), ctrl),
        0x01..=0x1A => (Key::Char(char::from(b'a' + byte - 1)), ctrl),
        0x1C..=0x1F => (Key::Char(char::from(b'4' + byte - 0x1C)), ctrl),
        _ => return None,
    })
}

/// The key of a `CSI … ~` sequence's first parameter (xterm and kitty agree).
fn tilde_key(n: u16) -> Option<Key> {
    Some(match n {
        1 | 7 => Key::Home,
        2 => Key::Insert,
        3 => Key::Delete,
        4 | 8 => Key::End,
        5 => Key::PageUp,
        6 => Key::PageDown,
        _ => return (1..=20).map(Key::F).find(|&k| function_key_number(k) == Some(n)),
    })
}

/// The `CSI n ~` number of F1–F20 (xterm: F1–F5 are 11–15, then gaps at 16, 22, 27 and 30).
fn function_key_number(key: Key) -> Option<u16> {
    let Key::F(f) = key else { return None };
    let f = u16::from(f);
    Some(match f {
        1..=5 => f + 10,
        6..=10 => f + 11,
        11..=14 => f + 12,
        15..=16 => f + 13,
        17..=20 => f + 14,
        _ => return None,
    })
}

/// The key of a `CSI`/`SS3` sequence's final letter.
fn letter_key(action: char) -> Option<Key> {
    Some(match action {
        'A' => Key::Up,
        'B' => Key::Down,
        'C' => Key::Right,
        'D' => Key::Left,
        'H' => Key::Home,
        'F' => Key::End,
        'P' => Key::F(1),
        'Q' => Key::F(2),
        'S' => Key::F(4),
        _ => return None,
    })
}

/// The key of a kitty `CSI code … u` key code (a Unicode code point, or one of the C0 codes kitty
/// keeps for Enter, Tab, Backspace and Esc; its private-use codes are keypad and media keys).
fn kitty_key(code: u16) -> Key {
    match code {
        13 => Key::Enter,
        9 => Key::Tab,
        127 | 8 => Key::Backspace,
        27 => Key::Esc,
        0xE000..=0xF8FF => Key::Other,
        c => char::from_u32(u32::from(c)).filter(|c| !c.is_control()).map_or(Key::Other, Key::Char),
    }
}

/// The phase in a kitty event field (1 press, 2 repeat, 3 release; absent means press).
fn phase(event: Option<u16>) -> KeyPhase {
    match event {
        Some(2) => KeyPhase::Repeat,
        Some(3) => KeyPhase::Release,
        _ => KeyPhase::Press,
    }
}

impl Perform for Performer<'_> {
    fn print(&mut self, c: char) {
        self.state.completed = true;
        if c == char::REPLACEMENT_CHARACTER {
            return; // invalid UTF-8
        }
        if std::mem::take(&mut self.state.ss3) {
            if let Some(key) = letter_key(c).or((c == 'R').then_some(Key::F(3))) {
                self.key(key, Modifiers::NONE, KeyPhase::Press);
            }
            return;
        }
        self.key(Key::Char(c), Modifiers::NONE, KeyPhase::Press);
    }

    fn execute(&mut self, byte: u8) {
        self.state.completed = true;
        self.state.ss3 = false;
        if let Some((key, modifiers)) = control_key(byte) {
            self.key(key, modifiers, KeyPhase::Press);
        }
    }

    fn esc_dispatch(&mut self, intermediates: &[u8], _ignore: bool, byte: u8) {
        self.state.completed = true;
        match (intermediates, byte) {
            ([], b'O') => self.state.ss3 = true,
            ([], b'\\') => {} // ST, the end of a string: never Alt-\
            // Alt-x arrives as ESC x.
            ([], 0x20..=0x7E) => {
                self.key(
                    Key::Char(char::from(byte)),
                    Modifiers { alt: true, ..Modifiers::NONE },
                    KeyPhase::Press,
                );
            }
            _ => {}
        }
    }

    fn csi_dispatch(&mut self, params: &Params, intermediates: &[u8], ignore: bool, action: char) {
        self.state.completed = true;
        self.state.ss3 = false;
        if ignore {
            return; // too many parameters: not input we know
        }
        // Each parameter with its sub-parameters (kitty: `code:shifted:base;mods:event;text`).
        let field = |i: usize| params.iter().nth(i);
        let first = |i: usize| field(i).and_then(|f| f.first().copied());
        let sub = |i: usize, j: usize| field(i).and_then(|f| f.get(j).copied());
        let mods = Modifiers::from_param(first(1).unwrap_or(1));
        let event = sub(1, 1);
        match (intermediates, action) {
            ([b'<'], 'M' | 'm') => {
                let (b, x, y) = (first(0).unwrap_or(0), first(1).unwrap_or(1), first(2).unwrap_or(1));
                self.mouse(b, x, y, action == 'm');
            }
            ([b'?'], 'c') => self.emit(Input::Reply(Reply::DeviceAttributes)),
            ([b'?'], 'u') => self.emit(Input::Reply(Reply::KeyboardFlags(first(0).unwrap_or(0)))),
            ([], 'R') => {
                let (row, col) = (first(0).unwrap_or(1), first(1).unwrap_or(1));
                self.emit(Input::Reply(Reply::CursorPosition { row, col }));
            }
            ([], 'I') => self.emit(Input::FocusGained),
            ([], 'O') => self.emit(Input::FocusLost),
            ([], 'M') if params.len() <= 1 && first(0).unwrap_or(0) == 0 => self.state.skip = 3, // X10 mouse: 3 raw bytes follow
            // urxvt's mouse report (mode 1015, for a terminal that has it and not SGR's): `CSI b+32 ;
            // x ; y M`, a release as button 3, which does not say which button was let go.
            ([], 'M') if params.len() == 3 => {
                let Some(b) = first(0).and_then(|b| b.checked_sub(32)) else { return };
                let (x, y) = (first(1).unwrap_or(1), first(2).unwrap_or(1));
                if b & (3 | 32 | 64) == 3 {
                    let code = self.state.drag_button.map(|button| match button {
                        MouseButton::Left => 0,
                        MouseButton::Middle => 1,
                        MouseButton::Right => 2,
                    });
                    if let Some(code) = code {
                        self.mouse(code, x, y, true);
                    }
                } else {
                    self.mouse(b, x, y, false);
                }
            }
            ([], 'Z') => self.key(Key::Tab, Modifiers { shift: true, ..mods }, KeyPhase::Press),
            ([], 'u') => self.key(kitty_key(first(0).unwrap_or(0)), mods, phase(event)),
            ([], '~') => match first(0) {
                Some(200) => self.state.in_paste = true,
                Some(201) => self.state.in_paste = false,
                Some(n) => {
                    if let Some(key) = tilde_key(n) {
                        self.key(key, mods, phase(event));
                    }
                }
                None => {}
            },
            ([], letter) => {
                if let Some(key) = letter_key(letter) {
                    self.key(key, mods, phase(event));
                }
            }
            _ => {}
        }
    }

    fn osc_dispatch(&mut self, _params: &[&[u8]], _bell_terminated: bool) {
        (self.state.completed, self.state.string_ended) = (true, true);
    }

    fn hook(&mut self, params: &Params, intermediates: &[u8], ignore: bool, action: char) {
        let valid = !ignore && params.len() == 1 && params.iter().next() == Some(&[1][..]);
        self.state.dcs = match (intermediates, action) {
            ([b'$'], 'r') if valid => Some(DcsAnswer::Decrqss),
            ([b'+'], 'r') if valid => Some(DcsAnswer::Xtgettcap),
            _ => None,
        };
        self.state.dcs_data.clear();
    }

    fn put(&mut self, byte: u8) {
        let state = &mut *self.state;
        if state.dcs.is_some() {
            if state.dcs_data.len() < MAX_DCS {
                state.dcs_data.push(byte);
            } else {
                state.dcs = None; // too long for an answer of ours: garbage
            }
        }
    }

    fn unhook(&mut self) {
        (self.state.completed, self.state.string_ended) = (true, true);
        // (emitted by `feed` once it knows the string was ended, not cancelled)
        self.state.dcs_answer = match self.state.dcs.take() {
            Some(DcsAnswer::Decrqss) => decrqss_direct_color(&self.state.dcs_data),
            Some(DcsAnswer::Xtgettcap) => xtgettcap_direct_color(&self.state.dcs_data),
            None => None,
        };
        self.state.dcs_data.clear();
    }
}

/// What DECRQSS's answer for the pen (`Pt` of `DCS 1 $ r Pt ST`, e.g. `0;48:2::1:2:3m`) says about
/// 24-bit colour after `CSI 48;2;1;2;3 m`: `Some(true)` when the background came back as RGB
/// (1, 2, 3) — in any of the colon forms terminals use (`48:2:1:2:3` kitty, `48:2::1:2:3` xterm,
/// `48:2:1:1:2:3` iTerm2) or the semicolon form —, `Some(false)` when it came back as another
/// background (a palette entry), `None` when it names none (not an answer to our question).
fn decrqss_direct_color(pt: &[u8]) -> Option<bool> {
    let sgr = std::str::from_utf8(pt.strip_suffix(b"m")?).ok()?;
    let params: Vec<&str> = sgr.split(';').collect();
    let number = |s: &str| s.parse::<u32>().ok();
    for (i, param) in params.iter().enumerate() {
        let sub: Vec<&str> = param.split(':').collect();
        let rgb = match sub[..] {
            ["48", "2", .., r, g, b] if sub.len() <= 6 => [number(r), number(g), number(b)],
            ["48", "5", _] => return Some(false),
            // the semicolon form: 48;2;r;g;b or 48;5;n
            ["48"] => match params.get(i + 1..i + 5) {
                Some(&["2", r, g, b]) => [number(r), number(g), number(b)],
                _ if params.get(i + 1) == Some(&"5") => return Some(false),
                _ => continue,
            },
            _ => continue,
        };
        return Some(rgb == [Some(1), Some(2), Some(3)]);
    }
    None
}

/// What XTGETTCAP's answer (`Pt` of `DCS 1 + r Pt ST`: `name[=value]` pairs in hex, `;`-separated)
/// says about 24-bit colour: `Some(true)` for `Tc`, or `RGB` with no value or a positive one (`8`,
/// `8/8/8`); `Some(false)` for `RGB` = `-1` (xterm without direct colour); `None` when it names
/// neither, or is not hex.
fn xtgettcap_direct_color(pt: &[u8]) -> Option<bool> {
    let hex = |s: &[u8]| -> Option<Vec<u8>> {
        s.len().is_multiple_of(2).then_some(())?;
        s.chunks(2).map(|pair| u8::from_str_radix(std::str::from_utf8(pair).ok()?, 16).ok()).collect()
    };
    let mut said = None;
    for pair in pt.split(|&b| b == b';') {
        let mut parts = pair.splitn(2, |&b| b == b'=');
        let name = hex(parts.next()?)?;
        let value = parts.next().map(hex).map(|v| v.and_then(|v| String::from_utf8(v).ok()));
        let yes = match (&name[..], value) {
            (b"Tc", _) => true,
            (b"RGB", None) => true,
            (b"RGB", Some(Some(v))) => v.split('/').next().and_then(|n| n.trim().parse::<i32>().ok())? > 0,
            _ => continue,
        };
        said = Some(said.unwrap_or(false) || yes);
    }
    said
}

/// How [`encode`] writes keys: as a terminal without the kitty protocol, or with it (flags 1 | 2:
/// disambiguate escape codes, report event types).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Protocol {
    /// xterm's legacy encoding (presses only).
    Legacy,
    /// The kitty keyboard protocol with press, repeat and release events.
    Kitty,
}

/// The bytes a terminal sends for `input` (keys, SGR mouse, focus, replies; `Resize` has none) — the
/// inverse of [`InputDecoder`], for tests and scripted clients. A mouse drag is written as motion to
/// (`dx`, `dy`) from (0, 0). `None` when the protocol cannot express it (a repeat or release in
/// legacy mode, a key with no encoding).
#[must_use]
pub fn encode(input: &Input, protocol: Protocol) -> Option<Vec<u8>> {
    match *input {
        Input::Key { key, phase, modifiers } => encode_key(key, phase, modifiers, protocol),
        Input::MouseDown { button, col, row } => {
            Some(format!("\x1b[<{};{};{}M", button_code(button), col + 1, row + 1).into_bytes())
        }
        Input::MouseUp { button } => Some(format!("\x1b[<{};1;1m", button_code(button)).into_bytes()),
        Input::MouseDrag { button, dx, dy } => {
            let (x, y) = (u16::try_from(dx + 1).ok()?, u16::try_from(dy + 1).ok()?);
            Some(format!("\x1b[<{};{x};{y}M", button_code(button) + 32).into_bytes())
        }
        Input::Scroll(1) => Some(b"\x1b[<64;1;1M".to_vec()),
        Input::Scroll(-1) => Some(b"\x1b[<65;1;1M".to_vec()),
        Input::Scroll(_) | Input::Resize { .. } => None,
        Input::FocusGained => Some(b"\x1b[I".to_vec()),
        Input::FocusLost => Some(b"\x1b[O".to_vec()),
        Input::Reply(Reply::DeviceAttributes) => Some(b"\x1b[?62;22c".to_vec()),
        Input::Reply(Reply::CursorPosition { row, col }) => Some(format!("\x1b[{row};{col}R").into_bytes()),
        Input::Reply(Reply::KeyboardFlags(flags)) => Some(format!("\x1b[?{flags}u").into_bytes()),
        // (xterm's answers to DECRQSS for the pen)
        Input::Reply(Reply::DirectColor(true)) => Some(b"\x1bP1$r0;48:2::1:2:3m\x1b\\".to_vec()),
        Input::Reply(Reply::DirectColor(false)) => Some(b"\x1bP1$r0;48:5:16m\x1b\\".to_vec()),
    }
}

fn button_code(button: MouseButton) -> u16 {
    match button {
        MouseButton::Left => 0,
        MouseButton::Middle => 1,
        MouseButton::Right => 2,
    }
}

fn encode_key(key: Key, phase: KeyPhase, modifiers: Modifiers, protocol: Protocol) -> Option<Vec<u8>> {
    let m = modifiers.param();
    // Cursor and function keys: a letter or a `~` number, the same in both protocols but for the
    // event field.
    let functional = match key {
        Key::Up => Some((1, 'A')),
        Key::Down => Some((1, 'B')),
        Key::Right => Some((1, 'C')),
        Key::Left => Some((1, 'D')),
        Key::Home => Some((1, 'H')),
        Key::End => Some((1, 'F')),
        Key::Insert => Some((2, '~')),
        Key::Delete => Some((3, '~')),
        Key::PageUp => Some((5, '~')),
        Key::PageDown => Some((6, '~')),
        Key::F(n @ 1..=4) if protocol == Protocol::Legacy || n != 3 => Some((1, (b'P' + n - 1) as char)),
        Key::F(3) => Some((13, '~')),
        Key::F(5..=20) => Some((function_key_number(key)?, '~')),
        _ => None,
    };
    match protocol {
        Protocol::Legacy => {
            if phase != KeyPhase::Press {
                return None;
            }
            if let Some((n, last)) = functional {
                return Some(
                    match (m, last) {
                        (1, '~') => format!("\x1b[{n}~"),
                        (1, 'P'..='S') => format!("\x1bO{last}"), // F1–F4 unmodified are SS3
                        (_, 'R') => return None,                  // `CSI 1;m R` is a cursor position report
                        (1, _) => format!("\x1b[{last}"),
                        (_, _) => format!("\x1b[{n};{m}{last}"),
                    }
                    .into_bytes(),
                );
            }
            let mut bytes = Vec::new();
            if modifiers.alt {
                bytes.push(0x1B);
            }
            match key {
                Key::Char(c) if modifiers.ctrl => match c {
                    'a'..='z' => bytes.push(c as u8 - b'a' + 1),
                    ' ' => bytes.push(0),
                    _ => return None,
                },
                Key::Char(c) => {
                    let c = if modifiers.shift { c.to_ascii_uppercase() } else { c };
                    bytes.extend_from_slice(c.encode_utf8(&mut [0; 4]).as_bytes());
                }
                Key::Enter => bytes.push(b'\r'),
                Key::Tab if modifiers.shift => bytes.extend_from_slice(b"\x1b[Z"),
                Key::Tab => bytes.push(b'\t'),
                Key::Backspace => bytes.push(0x7F),
                Key::Esc => bytes.push(0x1B),
                _ => return None,
            }
            Some(bytes)
        }
        Protocol::Kitty => {
            let event = match phase {
                KeyPhase::Press => 1,
                KeyPhase::Repeat => 2,
                KeyPhase::Release => 3,
            };
            let (n, last) = functional.or_else(|| {
                let code = match key {
                    Key::Char(c) => u32::from(c),
                    Key::Enter => 13,
                    Key::Tab => 9,
                    Key::Backspace => 127,
                    Key::Esc => 27,
                    _ => return None,
                };
                Some((u16::try_from(code).ok()?, 'u'))
            })?;
            Some(format!("\x1b[{n};{m}:{event}{last}").into_bytes())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(chunks: &[&[u8]]) -> Vec<Input> {
        let mut d = InputDecoder::new();
        let mut out = Vec::new();
        for chunk in chunks {
            d.feed(chunk, 0.0, &mut out);
        }
        out
    }

    fn with(key: Key, phase: KeyPhase, shift: bool, ctrl: bool, alt: bool) -> Input {
        Input::Key { key, phase, modifiers: Modifiers { shift, ctrl, alt } }
    }

    #[test]
    fn legacy_keys_text_controls_and_modified_arrows() {
        use Key::*;
        use KeyPhase::Press;
        assert_eq!(
            decode(&[b"wA\x03\x1a\r\t\x7f\x1b[D\x1bOA\x1b[1;5C\x1b[5~\x1b[Z"]),
            [
                Input::press(Char('w')),
                with(Char('a'), Press, true, false, false),
                with(Char('c'), Press, false, true, false),
                with(Char('z'), Press, false, true, false),
                Input::press(Enter),
                Input::press(Tab),
                Input::press(Backspace),
                Input::press(Left),
                Input::press(Up),
                with(Right, Press, false, true, false),
                Input::press(PageUp),
                with(Tab, Press, true, false, false),
            ]
        );
    }

    #[test]
    fn kitty_reports_press_repeat_and_release() {
        use KeyPhase::*;
        assert_eq!(
            decode(&[b"\x1b[119u\x1b[119;1:2u\x1b[119;2:3u\x1b[1;1:3D\x1b[27u"]),
            [
                Input::press(Key::Char('w')),
                with(Key::Char('w'), Repeat, false, false, false),
                with(Key::Char('w'), Release, true, false, false),
                with(Key::Left, Release, false, false, false),
                Input::press(Key::Esc),
            ]
        );
    }

    #[test]
    fn a_sequence_split_anywhere_decodes_the_same() {
        let whole: &[u8] = b"\x1b[1;5D\x1b[<0;10;5M\x1b[119;1:3uq";
        let expected = decode(&[whole]);
        assert_eq!(expected.len(), 4);
        for cut in 0..=whole.len() {
            assert_eq!(decode(&[&whole[..cut], &whole[cut..]]), expected, "cut at {cut}");
        }
    }

    #[test]
    fn a_lone_esc_resolves_after_the_timeout_and_not_before() {
        let mut d = InputDecoder::new();
        let mut out = Vec::new();
        d.feed(b"\x1b", 1.0, &mut out);
        assert!(out.is_empty());
        assert_eq!(d.deadline(), Some(1.0 + ESC_TIMEOUT));
        d.expire(1.0 + ESC_TIMEOUT / 2.0, &mut out);
        assert!(out.is_empty());
        d.expire(1.0 + ESC_TIMEOUT, &mut out);
        assert_eq!(out, [Input::press(Key::Esc)]);
        assert_eq!(d.deadline(), None);
        // Esc Esc: the first is a key at once.
        out.clear();
        d.feed(b"\x1b\x1b", 2.0, &mut out);
        assert_eq!(out, [Input::press(Key::Esc)]);
    }

    #[test]
    fn a_stale_partial_sequence_is_dropped_and_later_keys_still_arrive() {
        let mut d = InputDecoder::new();
        let mut out = Vec::new();
        d.feed(b"\x1b[1;", 0.0, &mut out);
        d.expire(1.0, &mut out);
        d.feed(b"w", 1.0, &mut out);
        assert_eq!(out, [Input::press(Key::Char('w'))]);
    }

    #[test]
    fn sgr_mouse_press_drag_release_and_wheel() {
        assert_eq!(
            decode(&[b"\x1b[<0;10;5M\x1b[<32;13;4M\x1b[<32;11;4M\x1b[<0;11;4m\x1b[<64;1;1M\x1b[<65;1;1M"]),
            [
                Input::MouseDown { button: MouseButton::Left, col: 9, row: 4 },
                Input::MouseDrag { button: MouseButton::Left, dx: 3, dy: -1 },
                Input::MouseDrag { button: MouseButton::Left, dx: -2, dy: 0 },
                Input::MouseUp { button: MouseButton::Left },
                Input::Scroll(1),
                Input::Scroll(-1),
            ]
        );
    }

    /// QA finding 7: urxvt's encoding (mode 1015, which game mode turns on) is decoded as SGR's is.
    #[test]
    fn urxvt_mouse_press_drag_release_and_wheel() {
        assert_eq!(
            decode(&[b"\x1b[32;50;15M\x1b[64;60;15M\x1b[64;58;14M\x1b[35;70;15M\x1b[96;1;1M\x1b[97;1;1M"]),
            [
                Input::MouseDown { button: MouseButton::Left, col: 49, row: 14 },
                Input::MouseDrag { button: MouseButton::Left, dx: 10, dy: 0 },
                Input::MouseDrag { button: MouseButton::Left, dx: -2, dy: -1 },
                Input::MouseUp { button: MouseButton::Left },
                Input::Scroll(1),
                Input::Scroll(-1),
            ]
        );
        // the right button; a release with no button down, a code under 32 and motion with no button
        // down are nothing
        assert_eq!(
            decode(&[b"\x1b[35;1;1M\x1b[34;5;5M\x1b[35;6;6M\x1b[2;1;1M\x1b[67;3;3M"]),
            [
                Input::MouseDown { button: MouseButton::Right, col: 4, row: 4 },
                Input::MouseUp { button: MouseButton::Right }
            ]
        );
    }

    #[test]
    fn replies_focus_paste_and_x10_mouse() {
        assert_eq!(
            decode(&[b"\x1b[?62;22c\x1b[12;40R\x1b[?3u\x1b[I\x1b[O\x1b[200~wasd\x1b[D\x1b[201~\x1b[Mwww"]),
            [
                Input::Reply(Reply::DeviceAttributes),
                Input::Reply(Reply::CursorPosition { row: 12, col: 40 }),
                Input::Reply(Reply::KeyboardFlags(3)),
                Input::FocusGained,
                Input::FocusLost,
            ],
            "nothing pasted and no X10 coordinate byte becomes a key"
        );
    }

    // issue #33: the answers real terminals give to the truecolor questions (caps::TRUECOLOR_QUERY).
    #[test]
    fn truecolor_answers_of_real_terminals() {
        let yes = Input::Reply(Reply::DirectColor(true));
        let no = Input::Reply(Reply::DirectColor(false));
        let table: &[(&str, &[u8], &[Input])] = &[
            // DECRQSS for the pen after 48;2;1;2;3
            ("xterm", b"\x1bP1$r0;48:2::1:2:3m\x1b\\", &[yes]),
            ("kitty", b"\x1bP1$r0;48:2:1:2:3m\x1b\\", &[yes]),
            ("iTerm2", b"\x1bP1$r0;48:2:1:1:2:3m\x1b\\", &[yes]),
            ("semicolons", b"\x1bP1$r0;48;2;1;2;3m\x1b\\", &[yes]),
            ("xterm, no direct colour", b"\x1bP1$r0;48:5:16m\x1b\\", &[no]),
            ("another colour", b"\x1bP1$r0;48:2::9:9:9m\x1b\\", &[no]),
            ("WezTerm, tmux 3.6", b"\x1bP0$r\x1b\\", &[]),
            ("no background", b"\x1bP1$r0m\x1b\\", &[]),
            // XTGETTCAP for RGB, then Tc
            ("xterm RGB", b"\x1bP1+r524742=38\x1b\\\x1bP0+r\x1b\\", &[yes]),
            ("WezTerm", b"\x1bP1+r524742=382F382F38\x1b\\\x1bP1+r5463=31\x1b\\", &[yes, yes]),
            ("kitty", b"\x1bP0+r524742\x1b\\\x1bP1+r5463\x1b\\", &[yes]),
            ("kitty, lower-case hex", b"\x1bP1+r5463=3f\x1b\\", &[yes]),
            ("iTerm2, one string", b"\x1bP1+r524742=38;5463\x1b\\", &[yes]),
            ("xterm, no direct colour", b"\x1bP1+r524742=2D31\x1b\\", &[no]),
            ("other capability", b"\x1bP1+r636F6C6F7273=323536\x1b\\", &[]),
            // 8-bit ST
            ("8-bit ST", b"\x1bP1$r0;48:2::1:2:3m\x9c", &[yes]),
            // garbage
            ("not hex", b"\x1bP1+rRGB\x1b\\", &[]),
            ("odd hex", b"\x1bP1+r52474\x1b\\", &[]),
            ("bad value", b"\x1bP1+r524742=zz\x1b\\", &[]),
            (
                "cancelled (CAN)",
                b"\x1bP1$r0;48:2::1:2:3m\x18",
                &[Input::Key {
                    key: Key::Char('x'),
                    phase: KeyPhase::Press,
                    modifiers: Modifiers { ctrl: true, ..Modifiers::NONE },
                }],
            ),
            ("other DCS", b"\x1bP>|xterm(390)\x1b\\", &[]),
            ("two parameters", b"\x1bP1;1$r0;48:2::1:2:3m\x1b\\", &[]),
        ];
        for (terminal, bytes, want) in table {
            let mut bytes = bytes.to_vec();
            bytes.push(b'w'); // a key after it still arrives, and nothing else does
            let mut want = want.to_vec();
            want.push(Input::press(Key::Char('w')));
            for cut in 0..=bytes.len() {
                assert_eq!(decode(&[&bytes[..cut], &bytes[cut..]]), want, "{terminal}, cut at {cut}");
            }
        }
        let long = [&b"\x1bP1$r0;"[..], &b"1;".repeat(MAX_DCS), b"48:2::1:2:3m\x1b\\q"].concat();
        assert_eq!(decode(&[&long]), [Input::press(Key::Char('q'))], "too long for an answer");
    }

    // issue #33: over SSH a read can end between a string's ESC and its `\`: the ESC is not the Esc
    // key (which quits), however late the `\`; and `ESC \` is never Alt-\.
    #[test]
    fn a_string_terminator_split_across_reads_is_not_the_esc_key() {
        for string in [&b"\x1bP1$r0;48:2::1:2:3m"[..], b"\x1bP0+r", b"\x1b]11;rgb:0000/0000/0000"] {
            let mut d = InputDecoder::new();
            let mut out = Vec::new();
            d.feed(string, 0.0, &mut out);
            d.feed(b"\x1b", 0.01, &mut out);
            d.expire(1.0, &mut out); // the `\` is late
            d.feed(b"\\w", 1.0, &mut out);
            d.expire(2.0, &mut out);
            assert!(!out.contains(&Input::press(Key::Esc)), "{out:?}");
            assert_eq!(out.last(), Some(&Input::press(Key::Char('w'))), "{out:?}");
            assert!(out.iter().all(|i| !matches!(i, Input::Key { key: Key::Char('\\'), .. })), "{out:?}");
        }
        // A real Esc after a string still counts.
        let mut d = InputDecoder::new();
        let mut out = Vec::new();
        d.feed(b"\x1bP0+r\x1b\\", 0.0, &mut out);
        d.feed(b"\x1b", 0.5, &mut out);
        d.expire(1.0, &mut out);
        assert_eq!(out, [Input::press(Key::Esc)]);
    }

    #[test]
    fn an_endless_string_is_dropped_in_bounded_memory() {
        let mut d = InputDecoder::new();
        let mut out = Vec::new();
        d.feed(b"\x1b]0;", 0.0, &mut out);
        d.feed(&vec![b'x'; 3 * MAX_SEQUENCE], 0.0, &mut out);
        assert!(d.state.pending <= MAX_SEQUENCE);
        d.feed(b"\x07q", 0.0, &mut out);
        assert_eq!(out.last(), Some(&Input::press(Key::Char('q'))));
    }

    #[test]
    fn every_key_round_trips_in_both_protocols() {
        let keys = [
            Key::Char('w'),
            Key::Char('['),
            Key::Char('?'),
            Key::Char('é'),
            Key::Up,
            Key::Down,
            Key::Left,
            Key::Right,
            Key::Enter,
            Key::Tab,
            Key::Backspace,
            Key::Home,
            Key::End,
            Key::Insert,
            Key::Delete,
            Key::PageUp,
            Key::PageDown,
            Key::F(1),
            Key::F(3),
            Key::F(5),
            Key::F(12),
        ];
        for key in keys {
            for protocol in [Protocol::Legacy, Protocol::Kitty] {
                let input = Input::press(key);
                let bytes = encode(&input, protocol).unwrap();
                assert_eq!(decode(&[&bytes]), [input], "{key:?} {protocol:?} {bytes:?}");
            }
        }
        for reply in [Reply::DirectColor(true), Reply::DirectColor(false), Reply::KeyboardFlags(3)] {
            let bytes = encode(&Input::Reply(reply), Protocol::Legacy).unwrap();
            assert_eq!(decode(&[&bytes]), [Input::Reply(reply)]);
        }
    }
}
