//! A slow link between a [`Session`] and a terminal, in virtual time: what the session writes goes
//! into an unbounded queue drained at `bytes_per_s` (the link's bottleneck), then arrives after
//! `one_way` seconds at a vt100 emulator, which answers every device-attributes query back through
//! the same delay, and every cursor position query with where its cursor is, as a real terminal at
//! the end of an SSH connection would. Keys typed at the terminal reach the session after `one_way`
//! too. Deterministic: no clock, no threads.
#![allow(missing_docs)] // moved from the tests that share it, whose items were not documented one by one

use std::collections::VecDeque;

use mazewalk_walk::Session;

/// The link: a bottleneck rate and a one-way delay.
#[derive(Clone, Copy, Debug)]
pub struct LinkConfig {
    /// Bytes per second through the bottleneck (125,000 = 1 Mbit/s).
    pub bytes_per_s: f64,
    /// One-way delay, seconds.
    pub one_way: f64,
}

/// One frame on its way to the terminal.
struct InFlight {
    arrives: f64,
    drawn_at: f64,
    bytes: Vec<u8>,
}

/// A frame as it reached the screen.
#[derive(Clone, Copy, Debug)]
pub struct Shown {
    /// When the session drew it.
    pub drawn_at: f64,
    /// When the terminal had all of it.
    pub shown_at: f64,
    /// Its size in bytes.
    pub bytes: usize,
}

/// The session, the link and the terminal, stepped together.
pub struct Sim {
    pub session: Session,
    pub terminal: vt100::Parser,
    pub link: LinkConfig,
    pub now: f64,
    up: VecDeque<(f64, Vec<u8>)>,
    down: VecDeque<InFlight>,
    link_free_at: f64,
    pub shown: Vec<Shown>,
    pub bytes_sent: u64,
    /// Whether the terminal says it repeats a block glyph on REP, as vt100 and xterm do (true, the
    /// default), or answers the session's second REP question (row 3) as tmux does, one cell in:
    /// REP after ASCII glyphs only.
    pub repeats_blocks: bool,
}

/// The cursor position query (`CSI 6 n`), answered with where the terminal's cursor is.
const CPR_QUERY: &[u8] = b"\x1b[6n";

/// The simulation's time step, seconds.
pub const STEP: f64 = 0.001;

impl Sim {
    pub fn new(session: Session, rows: u16, cols: u16, link: LinkConfig) -> Sim {
        let nz = |n: u16| std::num::NonZeroU16::new(n).expect("a terminal is at least 1×1");
        Sim {
            session,
            terminal: vt100::Parser::new(nz(rows), nz(cols), 0),
            link,
            now: 0.0,
            up: VecDeque::new(),
            down: VecDeque::new(),
            link_free_at: 0.0,
            shown: Vec::new(),
            bytes_sent: 0,
            repeats_blocks: true,
        }
    }

    /// The user types `bytes` now; the session gets them one delay later.
    pub fn type_keys(&mut self, bytes: &[u8]) {
        self.up.push_back((self.now + self.link.one_way, bytes.to_vec()));
    }

    /// Runs until `until`, calling `each_step` after every step (to type keys, watch the screen).
    pub fn run_until(&mut self, until: f64, mut each_step: impl FnMut(&mut Sim)) {
        let mut out = Vec::new();
        while self.now < until {
            self.now += STEP;
            let now = self.now;
            while self.up.front().is_some_and(|(at, _)| *at <= now) {
                let (_, bytes) = self.up.pop_front().expect("checked");
                self.session.feed(&bytes, now);
            }
            out.clear();
            if self.session.frame(now, &mut out) && !out.is_empty() {
                let start = self.link_free_at.max(now);
                self.link_free_at = start + out.len() as f64 / self.link.bytes_per_s;
                let arrives = self.link_free_at + self.link.one_way;
                self.bytes_sent += out.len() as u64;
                self.down.push_back(InFlight { arrives, drawn_at: now, bytes: out.clone() });
            }
            while self.down.front().is_some_and(|f| f.arrives <= now) {
                let frame = self.down.pop_front().expect("checked");
                // Up to each cursor position query, then its answer (where the cursor is then).
                let mut rest = &frame.bytes[..];
                while let Some(at) = rest.windows(4).position(|w| w == CPR_QUERY) {
                    self.terminal.process(&rest[..at + CPR_QUERY.len()]);
                    let (row, col) = self.terminal.screen().cursor_position();
                    let col = if row + 1 == 3 && !self.repeats_blocks { 1 } else { col };
                    let answer = format!("\x1b[{};{}R", row + 1, col + 1).into_bytes();
                    self.up.push_back((now + self.link.one_way, answer));
                    rest = &rest[at + CPR_QUERY.len()..];
                }
                self.terminal.process(rest);
                let queries = frame.bytes.windows(3).filter(|w| *w == b"\x1b[c").count();
                for _ in 0..queries {
                    self.up.push_back((now + self.link.one_way, b"\x1b[?62;22c".to_vec()));
                }
                self.shown.push(Shown { drawn_at: frame.drawn_at, shown_at: now, bytes: frame.bytes.len() });
            }
            each_step(self);
        }
    }

    /// The heading the HUD on the terminal's screen shows, in degrees.
    pub fn screen_heading(&self) -> Option<f32> {
        let (rows, cols) = self.terminal.screen().size();
        let hud = self.terminal.screen().rows(0, cols.get()).nth(usize::from(rows.get()) - 1)?;
        hud.split("heading ").nth(1)?.split('°').next()?.trim().parse().ok()
    }
}
