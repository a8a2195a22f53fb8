//! The event loop: the one place where the pure app state meets the terminal.
//!
//! ```text
//! input ─decode─▶ App::key / drag / tick ─▶ Renderer (3D) + overlays ─▶ Frame ─Encoder─▶ one write
//! ```
//!
//! Event-driven: while nothing moves it blocks in `poll` and sends nothing at all; while keys are held
//! it draws at most [`MAX_FPS`] frames a second, with motion measured in units per second.

use std::io;
use std::time::{Duration, Instant};

use super::overlay::{self, MapArea};
use super::state::{App, MapMode};
use crate::frame::{Cell, Frame};
use crate::render::{Projection, RenderStats, Renderer};
use crate::term::{Encoder, GuardOptions, Input, InputReader, Key, TerminalGuard, guard};

/// The most frames per second drawn while something moves.
pub const MAX_FPS: f64 = 60.0;
/// How long the loop sleeps when nothing moves and no key is held (it wakes on input anyway).
const IDLE_WAIT: Duration = Duration::from_secs(3600);

/// How the walk ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Seconds taken to reach the exit, if it was reached.
    pub finished: Option<f64>,
    /// Frames drawn.
    pub frames: u64,
    /// Bytes written to the terminal, all frames together.
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
    /// The 3D view (all rows but the HUD's).
    view: Frame,
}

/// Runs the walkthrough until the user quits. The terminal is restored on return, on error, on panic,
/// on SIGTERM / SIGHUP / SIGINT or a hang-up, and around a stop (Ctrl-Z, SIGTSTP; taken back after
/// SIGSTOP) (the guard). `bce` and `color_tolerance` set up the encoder ([`Encoder::set_bce`],
/// [`Encoder::set_tolerance`]).
///
/// # Errors
/// The terminal could not be set up, read or written.
pub fn run(app: &mut App, bce: bool, color_tolerance: u8) -> io::Result<Outcome> {
    let mut terminal = TerminalGuard::enter(GuardOptions::default())?;
    app.releases = terminal.enabled().reports_key_releases();
    let mut encoder = Encoder::new();
    encoder.set_bce(bce);
    encoder.set_tolerance(color_tolerance);
    let mut input = InputReader::new();
    let (cols, rows) = guard::size()?;
    let mut frame = Frame::new(cols.into(), rows.into());
    let mut screen = Screen::default();
    let mut bytes = Vec::new();
    let clock = Instant::now();
    let now = |clock: &Instant| clock.elapsed().as_secs_f64();
    let (mut dirty, mut last_frame) = (true, f64::NEG_INFINITY);
    let mut cost = FrameCost::default();
    let mut outcome = Outcome { finished: None, frames: 0, bytes: 0 };

    while !app.quit {
        // Wait for input: not at all when a frame is due, until the next frame while keys are held,
        // and until something happens (or a held key times out) otherwise.
        let t = now(&clock);
        let timeout = if dirty {
            (last_frame + 1.0 / MAX_FPS - t).max(0.0)
        } else if app.is_animating(t) {
            (last_frame + 1.0 / MAX_FPS - t).max(0.001)
        } else {
            app.held.next_expiry().map_or(IDLE_WAIT.as_secs_f64(), |at| (at - t).max(0.001))
        };
        let mut first = Some(Duration::from_secs_f64(timeout.min(IDLE_WAIT.as_secs_f64())));
        // Drain everything that is pending, so a burst of key repeats costs one frame.
        while let Some(event) = input.next_input(first.take().unwrap_or(Duration::ZERO))? {
            let t = now(&clock);
            match event {
                Input::Key { key: Key::Char('c'), modifiers, .. } if modifiers.ctrl => app.quit = true,
                Input::Key { key: Key::Char('z'), modifiers, .. } if modifiers.ctrl => terminal.suspend()?,
                Input::Key { key, action, .. } => dirty |= app.key(key, action, t),
                Input::MouseDrag { dx, dy, .. } => dirty |= app.drag(dx, dy),
                Input::Resize { cols, rows } => {
                    frame.resize(cols.into(), rows.into());
                    dirty = true;
                }
                Input::FocusLost => app.focus_lost(),
                _ => {}
            }
            if app.quit {
                break;
            }
        }
        if app.quit {
            break;
        }
        if terminal.take_resumed() {
            // Back from a stop (Ctrl-Z above, or SIGTSTP or a SIGCONT after SIGSTOP on the guard's
            // signal thread, which wakes this loop): releases may have been missed, the screen was
            // cleared and its size may have changed meanwhile.
            app.focus_lost();
            encoder.invalidate();
            let (cols, rows) = guard::size()?;
            frame.resize(cols.into(), rows.into());
            dirty = true;
        }
        let t = now(&clock);
        dirty |= app.tick(t);
        if !dirty || t < last_frame + 1.0 / MAX_FPS {
            continue;
        }
        let started = Instant::now();
        draw(app, &mut screen, &mut frame, &cost);
        bytes.clear();
        let stats = encoder.encode(&frame, &mut bytes);
        terminal.write_frame(&bytes)?;
        cost.seconds = started.elapsed().as_secs_f64();
        cost.bytes = stats.bytes;
        outcome.frames += 1;
        outcome.bytes += stats.bytes as u64;
        (dirty, last_frame) = (false, t);
    }
    terminal.restore()?;
    outcome.finished = app.finished;
    Ok(outcome)
}

/// Draws the whole screen for the current state into `frame` (its size is the terminal's): the 3D
/// view, then the map, the HUD and any box. Pure: no I/O, so screens are tested as text.
pub fn draw(app: &App, screen: &mut Screen, frame: &mut Frame, cost: &FrameCost) -> RenderStats {
    let (cols, rows) = (frame.width(), frame.height());
    if overlay::too_small(cols, rows) {
        overlay::draw_too_small(frame);
        return RenderStats::default();
    }
    // The bottom row is the HUD; the 3D view gets the rest.
    let view_rows = rows - 1;
    let stats = match screen.renderer.render(
        app.maze(),
        &app.camera,
        &app.options,
        cols,
        view_rows,
        &mut screen.view,
    ) {
        Ok(stats) => stats,
        Err(err) => {
            screen.view.resize(cols, view_rows);
            overlay::draw_box(&mut screen.view, "Cannot draw", &[err.to_string()]);
            RenderStats::default()
        }
    };
    frame.fill(Cell::BLANK);
    frame.cells_mut()[..screen.view.cells().len()].copy_from_slice(screen.view.cells());
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
        app.options.charset.name(),
    )
}

/// `m:ss.s` for the exit screen.
fn clock_text(seconds: f64) -> String {
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
