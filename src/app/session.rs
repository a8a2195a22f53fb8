//! One player's walk: bytes from a terminal in, the bytes of the next frame out — pure: no globals,
//! no terminal, no clock (time comes in as seconds on the caller's clock), no exit.
//!
//! ```text
//! bytes ─InputDecoder─▶ Input ─▶ App (keys, drag, tick) ─▶ draw: 3D view + overlays ─▶ Frame ─Encoder─▶ bytes
//! ```
//!
//! The local walkthrough ([`super::run`]) is a `Session` plus the terminal guard plus stdin and
//! stdout; a server runs one `Session` per connection. The host reads its own clock, passes the
//! bytes it got ([`Session::feed`]) and what only it knows ([`Input::Resize`], a stop), sleeps until
//! [`Session::next_wake`], and writes whatever [`Session::frame`] produces.
//!
//! ```
//! use mazewalk::app::{App, Session, SessionOptions};
//! use mazewalk::maze;
//! use mazewalk::render::RenderOptions;
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

use std::time::Instant;

use super::overlay::{self, MapArea};
use super::state::{App, MapMode};
use crate::frame::{Cell, Frame, Region};
use crate::input::{Input, InputDecoder, Key};
use crate::render::{Projection, RenderStats, Renderer};
use crate::term::encoder::{self, Encoder};

/// The most frames per second drawn while something moves.
pub const MAX_FPS: f64 = 60.0;

/// How a session encodes its frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SessionOptions {
    /// The terminal erases with the current background colour ([`Encoder::set_bce`]).
    pub bce: bool,
    /// Colour tolerance in 8-bit steps ([`Encoder::set_tolerance`]).
    pub color_tolerance: u8,
}

impl Default for SessionOptions {
    fn default() -> Self {
        SessionOptions { bce: false, color_tolerance: encoder::DEFAULT_TOLERANCE }
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

/// What the last frame cost, for the HUD.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameCost {
    /// Seconds spent making the previous frame (render + overlays + encode).
    pub seconds: f64,
    /// Bytes the previous frame sent.
    pub bytes: usize,
}

/// The buffers one screen is drawn with, reused from frame to frame.
#[derive(Debug, Default)]
pub struct Screen {
    /// The pipeline and its buffers.
    pub renderer: Renderer,
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
}

impl Session {
    /// A session walking `app` on a `cols × rows` terminal; its first [`frame`](Self::frame) paints
    /// the whole screen.
    #[must_use]
    pub fn new(app: App, cols: u16, rows: u16, options: SessionOptions) -> Session {
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

    /// Bytes from the terminal, arriving at time `now`.
    pub fn feed(&mut self, bytes: &[u8], now: f64) {
        let mut inputs = std::mem::take(&mut self.inputs);
        self.decoder.feed(bytes, now, &mut inputs);
        for input in inputs.drain(..) {
            self.input(input, now);
        }
        self.inputs = inputs;
    }

    /// One input at time `now`: keys and drags move the viewer, `Ctrl-C` quits, `Ctrl-Z` asks the host
    /// for a stop ([`take_suspend`](Self::take_suspend)), a resize redraws, losing focus lets go of
    /// held keys (no release will come).
    pub fn input(&mut self, input: Input, now: f64) {
        match input {
            Input::Key { key: Key::Char('c'), modifiers, .. } if modifiers.ctrl => self.app.quit = true,
            Input::Key { key: Key::Char('z'), modifiers, .. } if modifiers.ctrl => self.suspend = true,
            Input::Key { key, phase, .. } => self.dirty |= self.app.key(key, phase, now),
            Input::MouseDrag { dx, dy, .. } => self.dirty |= self.app.drag(dx, dy),
            Input::Resize { cols, rows } => {
                self.frame.resize(cols.into(), rows.into());
                self.dirty = true;
            }
            Input::FocusLost => self.app.focus_lost(),
            Input::MouseDown { .. }
            | Input::MouseUp { .. }
            | Input::Scroll(_)
            | Input::FocusGained
            | Input::Reply(_) => {}
        }
    }

    /// The terminal's screen was lost (a stop, a reconnect): the next frame paints everything, and
    /// held keys are let go (their releases may have been missed).
    pub fn invalidate(&mut self) {
        self.encoder.invalidate();
        self.app.focus_lost();
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
        let frame_due = self.last_frame + 1.0 / MAX_FPS;
        let drawing = (self.dirty || self.app.is_animating(now)).then_some(frame_due);
        [drawing, self.app.held.next_expiry(), self.decoder.deadline()].into_iter().flatten().reduce(f64::min)
    }

    /// Brings the walk to time `now` and, if the picture changed and a frame is due (at most
    /// [`MAX_FPS`] a second), draws it and appends its bytes to `out`: only what changed since the
    /// last frame. Returns whether a frame was drawn (it may still be 0 bytes).
    pub fn frame(&mut self, now: f64, out: &mut Vec<u8>) -> bool {
        let mut inputs = std::mem::take(&mut self.inputs);
        self.decoder.expire(now, &mut inputs);
        for input in inputs.drain(..) {
            self.input(input, now);
        }
        self.inputs = inputs;
        self.dirty |= self.app.tick(now);
        if !self.dirty || now < self.last_frame + 1.0 / MAX_FPS || self.app.quit {
            return false;
        }
        let started = Instant::now();
        draw(&self.app, &mut self.screen, &mut self.frame, &self.cost);
        let stats = self.encoder.encode(&self.frame, out);
        self.cost = FrameCost { seconds: started.elapsed().as_secs_f64(), bytes: stats.bytes };
        self.outcome.frames += 1;
        self.outcome.bytes += stats.bytes as u64;
        (self.dirty, self.last_frame) = (false, now);
        true
    }
}

/// Draws the whole screen for the current state into `frame` (its size is the terminal's): the 3D
/// view, then the map, the HUD and any box. Pure: no I/O, so screens are tested as text.
pub fn draw(app: &App, screen: &mut Screen, frame: &mut Frame, cost: &FrameCost) -> RenderStats {
    let (cols, rows) = (frame.width(), frame.height());
    if overlay::too_small(cols, rows) {
        overlay::draw_too_small(frame);
        return RenderStats::default();
    }
    // The bottom row is the HUD; the 3D view gets the rest, drawn in place.
    let view = Region { col: 0, row: 0, cols, rows: rows - 1 };
    let stats = match screen.renderer.render(app.maze(), &app.camera, &app.options, frame, view) {
        Ok(stats) => stats,
        Err(err) => {
            frame.fill(Cell::BLANK);
            overlay::draw_box(frame, "Cannot draw", &[err.to_string()]);
            RenderStats::default()
        }
    };
    frame.region_rows_mut(Region { row: rows - 1, rows: 1, ..view }).for_each(|hud| hud.fill(Cell::BLANK));
    let portal = screen.renderer.portal();
    let visited = |c: u32| portal.was_visited(c);
    let area = match app.map {
        MapMode::Off => None,
        MapMode::Corner => Some(MapArea::corner(frame, app.camera.position)),
        MapMode::Full => Some(MapArea::full(frame, app.maze(), app.camera.position)),
    };
    if let Some(area) = area {
        overlay::draw_map(frame, &area, app.maze(), &app.camera, &visited);
    }
    if let Some(seconds) = app.finished {
        let lines = [
            format!("You found the exit in {}.", clock_text(seconds)),
            String::new(),
            "r  walk it again".to_string(),
            "q  quit".to_string(),
        ];
        overlay::draw_box(frame, "Found the exit!", &lines);
    } else if app.help {
        overlay::draw_box(frame, "Keys (? to close)", &overlay::help_lines());
    }
    overlay::draw_hud(frame, &hud_text(app, &stats, cost)); // last: boxes never hide it
    stats
}

/// The HUD line: where, which way, which cell, what the frame cost.
fn hud_text(app: &App, stats: &RenderStats, cost: &FrameCost) -> String {
    let c = &app.camera;
    let ms = cost.seconds * 1e3;
    let fps = if cost.seconds > 0.0 { (1.0 / cost.seconds).min(9999.0) } else { 0.0 };
    let projection = match c.projection {
        Projection::Perspective => "persp",
        Projection::Orthographic => "ortho",
    };
    // Most useful first: a narrow terminal cuts the end off.
    format!(
        " ({:.1}, {:.1}) z{:+.1}  heading {:.0}° pitch {:+.0}°  cell {}  seen {}  {:.1} ms {:.0} fps {} B  \
         fov {:.0}° {projection} {}  ? help",
        c.position.x,
        c.position.y,
        c.eye_z,
        c.yaw_deg,
        c.pitch_deg,
        app.cell,
        stats.portal.distinct_cells,
        ms,
        fps,
        cost.bytes,
        c.hfov_deg,
        app.options.charset,
    )
}

/// `m:ss.s` for the exit screen.
#[must_use]
pub fn clock_text(seconds: f64) -> String {
    let minutes = (seconds / 60.0).floor();
    format!("{}:{:04.1}", minutes as u64, seconds - minutes * 60.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_text_reads_minutes_and_seconds() {
        assert_eq!(clock_text(0.0), "0:00.0");
        assert_eq!(clock_text(75.25), "1:15.2");
    }
}
