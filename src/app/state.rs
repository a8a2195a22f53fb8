//! The walkthrough's state and what each input does to it — pure: no terminal, no clock (time comes in
//! as seconds), so every handler is unit-tested without a terminal.

use glam::Vec2;

use super::controls::{Action, Held, action_for};
use crate::input::{Key, KeyPhase};
use crate::maze::Maze;
use crate::maze::geometry::{WALL_MARGIN, clamp_eye_height, heading_dir, heading_right};
use crate::maze::movement::{Position, step};
use crate::render::camera::{Camera, FOV_RANGE_DEG, PITCH_LIMIT_DEG, Projection};
use crate::render::{Charset, RenderOptions};

/// Walking speed, maze units per second (a generated cell is 4 units).
pub const WALK_SPEED: f32 = 5.0;
/// Turning speed, degrees per second.
pub const TURN_SPEED: f32 = 110.0;
/// Looking up/down, degrees per second.
pub const LOOK_SPEED: f32 = 70.0;
/// Rising/sinking, maze units per second (floor to ceiling is 2).
pub const RISE_SPEED: f32 = 1.0;
/// Field of view change, degrees per second.
pub const FOV_SPEED: f32 = 45.0;
/// Degrees of look per cell of mouse drag.
pub const DRAG_DEGREES_PER_CELL: f32 = 2.0;
/// A frame longer than this (a stall, a suspend) advances the motion by this much only.
pub const MAX_STEP: f64 = 0.1;

/// Where the map is shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MapMode {
    /// No map.
    Off,
    /// A small map in the top-right corner.
    #[default]
    Corner,
    /// The map fills the screen.
    Full,
}

/// The walkthrough.
#[derive(Clone, Debug)]
pub struct App {
    maze: Maze,
    /// The viewer.
    pub camera: Camera,
    /// The cell the viewer is in.
    pub cell: u32,
    start: (Camera, u32),
    /// How frames are drawn.
    pub options: RenderOptions,
    /// The map overlay.
    pub map: MapMode,
    /// The key help overlay.
    pub help: bool,
    /// Held keys.
    pub held: Held,
    /// Whether the terminal reports key releases (kitty protocol).
    pub releases: bool,
    /// When the walk started (seconds, the caller's clock).
    pub started: f64,
    /// Seconds it took to reach the exit, once reached.
    pub finished: Option<f64>,
    /// Set by q / Esc.
    pub quit: bool,
    last_tick: f64,
}

/// The viewer's start is not inside any cell.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the viewer's start ({x}, {y}) is not inside any cell of the maze")]
pub struct StartOutsideMaze {
    /// Start x.
    pub x: f32,
    /// Start y.
    pub y: f32,
}

impl App {
    /// A walkthrough of `maze` from its viewer, starting at time `now`.
    ///
    /// # Errors
    /// [`StartOutsideMaze`] when the maze's viewer is not in a cell.
    pub fn new(maze: Maze, options: RenderOptions, now: f64) -> Result<App, StartOutsideMaze> {
        let viewer = maze.viewer();
        let mut camera =
            Camera::new(viewer.pos, viewer.dir_deg, viewer.fov_deg.clamp(FOV_RANGE_DEG.0, FOV_RANGE_DEG.1));
        camera.eye_z = clamp_eye_height(viewer.z);
        let cell = maze.cell_at(viewer.pos).ok_or(StartOutsideMaze { x: viewer.pos.x, y: viewer.pos.y })?;
        Ok(App {
            maze,
            camera,
            cell,
            start: (camera, cell),
            options,
            map: MapMode::Corner,
            help: false,
            held: Held::default(),
            releases: false,
            started: now,
            finished: None,
            quit: false,
            last_tick: now,
        })
    }

    /// The maze being walked.
    #[must_use]
    pub fn maze(&self) -> &Maze {
        &self.maze
    }

    /// A key event at time `now`. Returns true when the picture may have changed.
    pub fn key(&mut self, key: Key, phase: KeyPhase, now: f64) -> bool {
        let Some(action) = action_for(key) else { return false };
        if action.is_continuous() {
            match phase {
                KeyPhase::Release => self.held.release(action),
                KeyPhase::Press | KeyPhase::Repeat => {
                    // Bring the motion up to date before the set of held keys changes.
                    self.tick(now);
                    self.held.press(action, now, self.releases, phase == KeyPhase::Repeat);
                }
            }
            return true;
        }
        if phase == KeyPhase::Release {
            return false;
        }
        match action {
            Action::ToggleProjection => {
                self.camera.projection = match self.camera.projection {
                    Projection::Perspective => Projection::Orthographic,
                    Projection::Orthographic => Projection::Perspective,
                };
            }
            Action::CycleMap => {
                self.map = match self.map {
                    MapMode::Off => MapMode::Corner,
                    MapMode::Corner => MapMode::Full,
                    MapMode::Full => MapMode::Off,
                };
            }
            Action::CycleCharset => {
                let all = Charset::ALL;
                let i = all.iter().position(|&c| c == self.options.charset).unwrap_or(0);
                self.options.charset = all[(i + 1) % all.len()];
            }
            Action::Reset => {
                (self.camera, self.cell) = self.start;
                self.held.clear();
                (self.started, self.finished) = (now, None);
            }
            Action::Help => self.help = !self.help,
            Action::Quit => self.quit = true,
            _ => {}
        }
        true
    }

    /// A mouse drag by (`dx`, `dy`) terminal cells: look around.
    pub fn drag(&mut self, dx: i32, dy: i32) -> bool {
        if dx == 0 && dy == 0 {
            return false;
        }
        self.turn(-(dx as f32) * DRAG_DEGREES_PER_CELL, -(dy as f32) * DRAG_DEGREES_PER_CELL);
        true
    }

    /// The terminal lost focus: releases will not arrive, so let go of every key.
    pub fn focus_lost(&mut self) {
        self.held.clear();
    }

    fn turn(&mut self, yaw_deg: f32, pitch_deg: f32) {
        self.camera.yaw_deg = (self.camera.yaw_deg + yaw_deg).rem_euclid(360.0);
        self.camera.pitch_deg = (self.camera.pitch_deg + pitch_deg).clamp(-PITCH_LIMIT_DEG, PITCH_LIMIT_DEG);
    }

    /// True while something moves by itself (held keys), so the loop keeps drawing frames.
    #[must_use]
    pub fn is_animating(&self, now: f64) -> bool {
        self.held.any(now)
    }

    /// Advances held-key motion to time `now` at speeds independent of the frame rate. Returns true when
    /// the viewer moved.
    pub fn tick(&mut self, now: f64) -> bool {
        let dt = (now - self.last_tick).clamp(0.0, MAX_STEP) as f32;
        self.last_tick = now;
        let h = &self.held;
        let walk = Vec2::new(
            h.axis(Action::Forward, Action::Back, now),
            h.axis(Action::StrafeRight, Action::StrafeLeft, now),
        );
        let turn = h.axis(Action::TurnLeft, Action::TurnRight, now);
        let look = h.axis(Action::LookUp, Action::LookDown, now);
        let rise = h.axis(Action::Rise, Action::Sink, now);
        let zoom = h.axis(Action::FovWider, Action::FovNarrower, now);
        self.held.expire(now);
        if dt == 0.0 || (walk == Vec2::ZERO && turn == 0.0 && look == 0.0 && rise == 0.0 && zoom == 0.0) {
            return false;
        }
        let before = (self.camera, self.cell);
        self.turn(turn * TURN_SPEED * dt, look * LOOK_SPEED * dt);
        self.camera.eye_z = clamp_eye_height(self.camera.eye_z + rise * RISE_SPEED * dt);
        self.camera.hfov_deg =
            (self.camera.hfov_deg + zoom * FOV_SPEED * dt).clamp(FOV_RANGE_DEG.0, FOV_RANGE_DEG.1);
        if walk != Vec2::ZERO {
            // Walking stays level whatever the pitch: forward is the heading in the maze plane.
            let heading = self.camera.yaw_deg.to_radians();
            let (forward, right) = (heading_dir(heading), heading_right(heading));
            let delta = (forward * walk.x + right * walk.y).normalize_or_zero() * WALK_SPEED * dt;
            let to =
                step(&self.maze, Position { cell: self.cell, pos: self.camera.position }, delta, WALL_MARGIN);
            self.camera.position = to.pos;
            self.cell = to.cell;
        }
        if self.finished.is_none() && self.maze.exit().is_some_and(|exit| exit.cell == self.cell) {
            self.finished = Some(now - self.started);
        }
        (self.camera, self.cell) != before
    }
}
