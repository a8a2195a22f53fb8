//! The walkthrough's state and what each input does to it — pure: no terminal, no clock (time comes in
//! as seconds), so every handler is unit-tested without a terminal.

use std::sync::Arc;

use glam::Vec2;

use super::controls::{Action, DEVELOPER_ACTIONS, Held, action_for};
use super::run::{Pose, Recorder, Run};
use mazewalk_maze::Maze;
use mazewalk_maze::geometry::{clamp_eye_height, heading_dir, heading_right};
use mazewalk_maze::movement::{Position, settle, step};
use mazewalk_render::camera::{Camera, FOV_RANGE_DEG, PITCH_LIMIT_DEG, Projection};
use mazewalk_render::{Charset, Culling, RenderOptions};
use mazewalk_term::input::{Key, KeyPhase};

/// Walking speed by default, maze units per second (a generated cell is 4 units); see [`Motion`].
pub const WALK_SPEED: f32 = 5.0;
/// Turning speed by default, degrees per second; see [`Motion`].
pub const TURN_SPEED: f32 = 110.0;
/// How far one tap of W/S/A/D walks by default, maze units: a quarter of a generated cell.
pub const WALK_STEP: f32 = 1.0;
/// How far one tap of ←/→ turns by default, degrees: six taps make a right angle.
pub const TURN_STEP_DEG: f32 = 15.0;
/// The walking speeds `--walk-speed` accepts, maze units per second.
pub const WALK_SPEED_RANGE: (f32, f32) = (0.5, 40.0);
/// The turning speeds `--turn-speed` accepts, degrees per second.
pub const TURN_SPEED_RANGE: (f32, f32) = (10.0, 720.0);
/// The walk steps `--walk-step` accepts, maze units (at most a generated cell).
pub const WALK_STEP_RANGE: (f32, f32) = (0.05, 4.0);
/// The turn steps `--turn-step` accepts, degrees.
pub const TURN_STEP_RANGE_DEG: (f32, f32) = (1.0, 90.0);
/// Looking up/down, degrees per second.
pub(crate) const LOOK_SPEED: f32 = 70.0;
/// How far one tap of ↑/↓ looks, degrees.
pub(crate) const LOOK_STEP_DEG: f32 = 10.0;
/// Rising/sinking, maze units per second (floor to ceiling is 2).
pub(crate) const RISE_SPEED: f32 = 1.0;
/// How far one tap of `[`/`]` rises or sinks, maze units.
pub(crate) const RISE_STEP: f32 = 0.1;
/// The look-ahead lens's horizontal field (`z`), degrees, with no vertical widening: narrow enough that
/// a side opening 6 cells down a generated corridor spans three columns at 120×40 (it spans half a
/// column in the walk's own field there, ~118°; a new player through a 40° lens, 2.3 columns, read
/// openings at 3–5 cells right but took 6-cell ones for side walls).
pub const LOOK_AHEAD_FOV_DEG: f32 = 30.0;
/// Field of view change, degrees per second.
pub(crate) const FOV_SPEED: f32 = 45.0;
/// How much one tap of `+`/`-` changes the field of view, degrees.
pub(crate) const FOV_STEP_DEG: f32 = 5.0;
/// How long a snap turn (`,` `.`) takes, seconds.
pub const SNAP_SECONDS: f64 = 0.15;
/// A snap turn lands on a multiple of 90° when it would land within this many degrees of one, so
/// repeated snaps stay on the maze's grid after a little drift; further off, it turns exactly 90°.
pub const SNAP_ALIGN_DEG: f32 = 10.0;
/// Degrees of look per cell of mouse drag.
pub(crate) const DRAG_DEGREES_PER_CELL: f32 = 2.0;
/// A frame longer than this (a stall, a suspend) advances the motion by this much only.
pub(crate) const MAX_STEP: f64 = 0.1;
/// After walking this long (seconds), `q` asks before it quits: a stray key must not throw a long
/// walk away.
pub const CONFIRM_QUIT_AFTER: f64 = 60.0;
/// For this long after the exit box opens (seconds), keys do not close it: one pressed or held to
/// walk into the exit must not hide the box before it is seen.
pub const EXIT_BOX_GRACE: f64 = 0.5;

/// How far a tap moves and how fast a held key moves: one player's settings (a server may give each
/// player its own). Steps and speeds are positive; the binary takes them from flags within the `*_RANGE`
/// constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Walking speed, maze units per second.
    pub walk_speed: f32,
    /// Turning speed, degrees per second.
    pub turn_speed_deg: f32,
    /// How far one tap walks, maze units.
    pub walk_step: f32,
    /// How far one tap turns, degrees.
    pub turn_step_deg: f32,
}

impl Default for Motion {
    fn default() -> Self {
        Motion {
            walk_speed: WALK_SPEED,
            turn_speed_deg: TURN_SPEED,
            walk_step: WALK_STEP,
            turn_step_deg: TURN_STEP_DEG,
        }
    }
}

impl Motion {
    /// For a continuous action: its step (degrees or maze units) and its speed (the same per second).
    fn step_and_speed(&self, action: Action) -> (f32, f32) {
        match action {
            Action::Forward | Action::Back | Action::StrafeLeft | Action::StrafeRight => {
                (self.walk_step, self.walk_speed)
            }
            Action::TurnLeft | Action::TurnRight => (self.turn_step_deg, self.turn_speed_deg),
            Action::LookUp | Action::LookDown => (LOOK_STEP_DEG, LOOK_SPEED),
            Action::Rise | Action::Sink => (RISE_STEP, RISE_SPEED),
            _ => (FOV_STEP_DEG, FOV_SPEED),
        }
    }
}

/// A snap turn under way: the heading eases from `from_deg` to `to_deg` (not wrapped to 0..360) over
/// [`SNAP_SECONDS`] from `start`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Snap {
    from_deg: f32,
    to_deg: f32,
    start: f64,
}

impl Snap {
    /// The heading at `now`, not wrapped; `None` once the snap is over.
    fn heading_at(&self, now: f64) -> Option<f32> {
        let t = ((now - self.start) / SNAP_SECONDS) as f32;
        if t >= 1.0 {
            return None;
        }
        let t = t.max(0.0);
        let eased = t * t * (3.0 - 2.0 * t); // smoothstep: starts and stops gently
        Some(self.from_deg + (self.to_deg - self.from_deg) * eased)
    }
}

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

/// The next of the numbers that name sets of seen cells ([`App::seen_id`]), unique in the process.
fn next_seen_id() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// The walkthrough.
#[derive(Clone, Debug)]
pub struct App {
    /// Shared: a server's players all walk one maze (a 1000 × 1000 one is ~75 MB).
    maze: Arc<Maze>,
    /// The viewer.
    pub camera: Camera,
    /// The cell the viewer is in.
    pub cell: u32,
    start: (Camera, u32),
    /// How frames are drawn.
    pub options: RenderOptions,
    /// The map overlay.
    pub map: MapMode,
    /// The look-ahead lens (`z`) is on: the fields of view (horizontal, least vertical) it replaced,
    /// which turning it off brings back.
    look_ahead: Option<(f32, f32)>,
    /// The key help overlay (never under the exit box: `?` does nothing there).
    pub help: bool,
    /// Held keys.
    pub held: Held,
    /// Whether the terminal reports key releases (kitty protocol).
    pub releases: bool,
    /// Tap steps and glide speeds.
    pub motion: Motion,
    snap: Option<Snap>,
    /// When the walk started (seconds, the caller's clock).
    pub started: f64,
    /// Seconds it took to reach the exit, once reached.
    pub finished: Option<f64>,
    /// The HUD shows no exit clock: a host's spectator follows a player whose clock it does not know.
    pub clock_unknown: bool,
    /// Set by q, or by Esc with no box shown (after [`CONFIRM_QUIT_AFTER`], by a second q).
    pub quit: bool,
    /// The box that asks whether to quit, after a q late in a walk.
    pub confirm_quit: bool,
    /// The box that says the exit was found is shown (from reaching it until a key closes it).
    pub exit_box: bool,
    /// When the exit box opened (seconds).
    exit_box_since: f64,
    /// The HUD shows the developer figures (`i`, `--dev-figures`): frames per second, bytes, cell,
    /// cells seen, ms per frame.
    pub figures: bool,
    /// The map shows every cell and the exit from the start (`--reveal-map`), not only those seen.
    pub reveal_map: bool,
    /// The map tints the cells the portal pass visited this frame (`v`), a lesson in culling.
    pub culling_tint: bool,
    /// The developer keys work ([`DEVELOPER_ACTIONS`]: `b`, `v`, `i`): in the local walk, not for a
    /// served player, whose culling off would make the server draw every wall of the maze.
    pub developer_keys: bool,
    /// The ghost is wanted (`g`, `--ghost`): a stored run, replayed from the walk's start or from
    /// [`ghost_since`](Self::ghost_since), whichever is later, where the host has one.
    pub ghost: bool,
    /// When the ghost was last turned on (seconds).
    pub ghost_since: f64,
    /// Cells seen so far, one bit each (the map's fog of war).
    seen: Vec<u64>,
    /// A number no other set of seen cells of any walk had ([`App::seen_id`]).
    seen_id: u64,
    /// The view shows a chalk cross on the floor of each cell walked (`x`; on by default).
    pub chalk: bool,
    /// The cells walked since the start (or the last `r`), in the order first entered, each once.
    walked: Vec<u32>,
    /// The same cells, one bit each.
    walked_bits: Vec<u64>,
    last_tick: f64,
    /// The walk's poses since its start, until the finish (the run a ghost replays).
    recorder: Recorder,
    /// The pose at the finish, once reached.
    finish_pose: Option<Pose>,
    /// A stored run that moves the viewer instead of the keys (`mazewalk replay`).
    replay: Option<Arc<Run>>,
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

/// The camera a maze's viewer asks for, made usable: its field of view clamped to [`FOV_RANGE_DEG`] and
/// its eye between floor and ceiling ([`clamp_eye_height`]), as a file may ask for anything in range of
/// a number; with the maze's least vertical field of view ([`Maze::min_vfov_deg`]: a generated maze's
/// widens the view on a wide screen). The walk starts from it and `mazewalk render` renders from it,
/// so a file that loads is a file both show.
#[must_use]
pub fn viewer_camera(maze: &Maze) -> Camera {
    let viewer = maze.viewer();
    let fov = viewer.fov_deg.clamp(FOV_RANGE_DEG.0, FOV_RANGE_DEG.1);
    Camera {
        eye_z: clamp_eye_height(viewer.z),
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(viewer.pos, viewer.dir_deg, fov)
    }
}

/// Where a viewer put at `pos` stands, and the cell holding it: at least the maze's clearance
/// ([`Maze::clearance`], never less than [`WALL_MARGIN`](mazewalk_maze::geometry::WALL_MARGIN)) from
/// every wall, as the walk keeps it ([`settle`]: the renderer's near plane lies inside the margin, so
/// an eye closer would see through the wall). `None` when `pos` is in no cell. The walk starts there,
/// and `mazewalk render` renders from there.
#[must_use]
pub fn stand(maze: &Maze, pos: Vec2) -> Option<Position> {
    let cell = maze.cell_at(pos)?;
    Some(settle(maze, Position { cell, pos }, maze.clearance()))
}

impl App {
    /// A walkthrough of `maze` from its viewer (where it [`stand`]s), starting at time `now`.
    ///
    /// # Errors
    /// [`StartOutsideMaze`] when the maze's viewer is not in a cell.
    pub fn new(
        maze: impl Into<Arc<Maze>>,
        options: RenderOptions,
        now: f64,
    ) -> Result<App, StartOutsideMaze> {
        let maze = maze.into();
        let viewer = maze.viewer();
        let Position { cell, pos } =
            stand(&maze, viewer.pos).ok_or(StartOutsideMaze { x: viewer.pos.x, y: viewer.pos.y })?;
        let camera = Camera { position: pos, ..viewer_camera(&maze) };
        let cells = maze.cell_count();
        Ok(App {
            maze,
            camera,
            cell,
            start: (camera, cell),
            options,
            map: MapMode::Corner,
            look_ahead: None,
            help: false,
            held: Held::default(),
            releases: false,
            motion: Motion::default(),
            snap: None,
            started: now,
            finished: None,
            clock_unknown: false,
            quit: false,
            confirm_quit: false,
            exit_box: false,
            exit_box_since: f64::NEG_INFINITY,
            figures: false,
            reveal_map: false,
            culling_tint: false,
            developer_keys: true,
            ghost: false,
            ghost_since: now,
            seen: vec![0; cells.div_ceil(64)],
            seen_id: next_seen_id(),
            chalk: true,
            walked: vec![cell],
            walked_bits: {
                let mut bits = vec![0; cells.div_ceil(64)];
                bits[cell as usize / 64] |= 1 << (cell % 64);
                bits
            },
            last_tick: now,
            recorder: Recorder::default(),
            finish_pose: None,
            replay: None,
        })
    }

    /// Plays `run` back: from now on the viewer goes where the run went, at its times from the walk's
    /// start (`r` starts it again); the keys that walk, turn and look do nothing, the others (map,
    /// glyphs, help, quit) work as in a walk. At the run's end the viewer stands at its finish and
    /// the HUD shows its time. The caller checks the run is of this maze ([`Run::check_maze`]).
    pub fn set_replay(&mut self, run: Arc<Run>) {
        self.replay = Some(run);
    }

    /// Brings a replay's viewer to its pose at `now`.
    fn follow_replay(&mut self, now: f64) {
        let Some(run) = &self.replay else { return };
        let t = now - self.started;
        let Some(pose) = run.pose_at(t) else { return };
        let done = t >= run.seconds();
        self.camera.position = pose.position;
        self.camera.yaw_deg = pose.yaw_deg;
        self.camera.pitch_deg = pose.pitch_deg;
        if let Some(cell) = self.maze.cell_at(pose.position) {
            self.cell = cell;
        }
        if done && self.finished.is_none() {
            self.finished = Some(run.seconds());
        }
    }

    /// The viewer's pose now.
    #[must_use]
    pub fn pose(&self) -> Pose {
        let c = &self.camera;
        Pose { position: c.position, yaw_deg: c.yaw_deg, pitch_deg: c.pitch_deg }
    }

    /// Seconds into the ghost's run at `now`: from the walk's start, or from when the ghost was
    /// turned on if later (`None`: not wanted).
    #[must_use]
    pub fn ghost_time(&self, now: f64) -> Option<f64> {
        self.ghost.then(|| now - self.started.max(self.ghost_since))
    }

    /// Adds the viewer's cell to the cells walked (the chalk marks), once.
    fn mark_walked(&mut self) {
        if let Some(word) = self.walked_bits.get_mut(self.cell as usize / 64)
            && *word >> (self.cell % 64) & 1 == 0
        {
            *word |= 1 << (self.cell % 64);
            self.walked.push(self.cell);
        }
    }

    /// Notes the viewer's pose at `now` in the walk's run (until the finish).
    fn track(&mut self, now: f64) {
        self.mark_walked();
        if self.finished.is_none() {
            let pose = self.pose();
            self.recorder.note(now - self.started, pose);
        }
    }

    /// The run of this walk's finish, as walked by `holder` through the maze of hash `maze` (its
    /// [`Maze::content_hash`](mazewalk_maze::Maze::content_hash), which the host knows): `None`
    /// before the finish, or for a walk past [`MAX_SECONDS`](crate::run::MAX_SECONDS).
    #[must_use]
    pub fn run(&self, maze: mazewalk_maze::ContentHash, holder: &str) -> Option<Run> {
        self.recorder.finish(maze, holder, self.finished?, self.finish_pose?)
    }

    /// Makes where a viewer put at `position` stands ([`stand`]) the walk's start — the viewer goes
    /// there, facing as the maze's viewer does, and `r` comes back there — for a host that gives each
    /// of its players a spot of its own (`mazewalk serve`). `false`, and nothing changed, when
    /// `position` is in no cell.
    pub fn set_start(&mut self, position: Vec2) -> bool {
        let Some(Position { cell, pos }) = stand(&self.maze, position) else { return false };
        self.start = (Camera { position: pos, ..self.start.0 }, cell);
        (self.camera, self.cell) = self.start;
        self.look_ahead = None;
        // walked from here: the viewer was never where it stood before
        self.walked.clear();
        self.walked_bits.fill(0);
        self.mark_walked();
        true
    }

    /// Where this walk starts faces `yaw_deg` (degrees counter-clockwise from +x; a served newcomer
    /// looks down its cell's longest way, not at a wall or another player's back); the viewer is put
    /// back on the start.
    pub fn set_start_heading(&mut self, yaw_deg: f32) {
        if yaw_deg.is_finite() {
            self.start.0.yaw_deg = yaw_deg.rem_euclid(360.0);
            (self.camera, self.cell) = self.start;
            self.look_ahead = None;
        }
    }

    /// Whether cell `c` shows on the map: seen at some time in the walk, or every cell with
    /// [`reveal_map`](Self::reveal_map).
    #[must_use]
    pub fn has_seen(&self, c: u32) -> bool {
        self.reveal_map || self.seen.get(c as usize / 64).is_some_and(|w| w >> (c % 64) & 1 == 1)
    }

    /// The cells whose floors the view marks in chalk: those walked since the start (or the last
    /// `r`), in the order first entered; none with the marks off (`x`).
    #[must_use]
    pub fn chalked(&self) -> &[u32] {
        if self.chalk { &self.walked } else { &[] }
    }

    /// Records cells as seen (the renderer's visible cells of a frame); ids outside the maze are ignored.
    pub(crate) fn mark_seen(&mut self, cells: impl IntoIterator<Item = u32>) {
        let mut changed = false;
        for c in cells {
            if let Some(word) = self.seen.get_mut(c as usize / 64) {
                changed |= *word >> (c % 64) & 1 == 0;
                *word |= 1 << (c % 64);
            }
        }
        if changed {
            self.seen_id = next_seen_id();
        }
    }

    /// Names the cells seen so far ([`has_seen`](Self::has_seen), but for [`reveal_map`](Self::reveal_map)):
    /// a number no other walk's seen cells, nor these before a cell was first seen, had. A map fitted
    /// to them is kept while it stays.
    #[must_use]
    pub(crate) fn seen_id(&self) -> u64 {
        self.seen_id
    }

    /// The maze being walked.
    #[must_use]
    pub fn maze(&self) -> &Maze {
        &self.maze
    }

    /// A key event at time `now`. Returns true when the picture may have changed.
    ///
    /// A box that asks for a key takes the next one: the exit box closes with any key (`r` walks
    /// again and `q` quits, as it says; Esc only closes it), the question whether to quit quits with
    /// `q` and closes with any other key.
    pub fn key(&mut self, key: Key, phase: KeyPhase, now: f64) -> bool {
        let changed = self.key_at(key, phase, now);
        self.track(now);
        changed
    }

    fn key_at(&mut self, key: Key, phase: KeyPhase, now: f64) -> bool {
        let action = action_for(key);
        if phase == KeyPhase::Press && self.exit_box {
            // a key held or pressed to walk into the exit is not an answer (its auto-repeat comes as
            // presses without the kitty protocol): only a fresh press after the grace
            let repeating = action.is_some_and(|a| self.held.recently_pressed(a, now));
            if let Some(a) = action {
                self.held.note_press(a, now);
            }
            if now - self.exit_box_since < EXIT_BOX_GRACE || repeating {
                return false;
            }
            self.exit_box = false;
            match action {
                Some(Action::Reset) => self.reset(now),
                Some(Action::Quit) if key != Key::Esc => self.quit = true,
                _ => {}
            }
            return true;
        }
        if phase == KeyPhase::Press && self.confirm_quit {
            self.confirm_quit = false;
            self.quit = action == Some(Action::Quit) && key != Key::Esc;
            return true;
        }
        let Some(action) = action else { return false };
        if !self.developer_keys && DEVELOPER_ACTIONS.contains(&action) {
            return false;
        }
        let moves = matches!(action, Action::SnapLeft | Action::SnapRight)
            || action.is_continuous() && !matches!(action, Action::FovWider | Action::FovNarrower);
        if self.replay.is_some() && moves {
            return false; // the run moves the viewer
        }
        if action.is_continuous() {
            match phase {
                KeyPhase::Release => {
                    self.tick(now); // the key moved until now
                    self.held.release(action, now);
                }
                KeyPhase::Press | KeyPhase::Repeat => {
                    // Bring the motion up to date before the set of held keys changes.
                    self.tick(now);
                    let (step, speed) = self.motion.step_and_speed(action);
                    let step_seconds = f64::from(step / speed);
                    if self.held.press(action, now, self.releases, phase == KeyPhase::Repeat, step_seconds) {
                        self.take_step(action, step, now);
                    }
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
            Action::SnapLeft | Action::SnapRight => {
                self.tick(now); // the snap starts from where the viewer is now
                self.snap_turn(if action == Action::SnapLeft { 90.0 } else { -90.0 }, now);
            }
            Action::Reset => self.reset(now),
            Action::ToggleFovea => self.camera.fovea = !self.camera.fovea,
            Action::ToggleLookAhead => self.set_look_ahead(self.look_ahead.is_none()),
            // the exit box shows instead of the help: a toggle there would pop up unseen after it
            Action::Help if self.exit_box => return false,
            Action::Help => self.help = !self.help,
            Action::ToggleCulling => {
                self.options.culling = match self.options.culling {
                    Culling::Portal => Culling::None,
                    Culling::None => Culling::Portal,
                };
            }
            Action::ToggleCullingTint => self.culling_tint = !self.culling_tint,
            Action::ToggleTextures => self.options.textures = !self.options.textures,
            Action::ToggleChalk => self.chalk = !self.chalk,
            Action::ToggleFigures => self.figures = !self.figures,
            Action::ToggleGhost => (self.ghost, self.ghost_since) = (!self.ghost, now),
            Action::Quit if key == Key::Esc && self.help => self.help = false, // Esc closes the box first
            // and the full-screen map, which looks like one: back to its corner
            Action::Quit if key == Key::Esc && self.map == MapMode::Full => self.map = MapMode::Corner,
            // a stray q late in a walk asks first (a finished walk's box says q quits: it does)
            Action::Quit if now - self.started > CONFIRM_QUIT_AFTER && self.finished.is_none() => {
                self.help = false;
                self.confirm_quit = true;
            }
            Action::Quit => self.quit = true,
            _ => {}
        }
        true
    }

    /// Whether the look-ahead lens (`z`) is on.
    #[must_use]
    pub fn look_ahead(&self) -> bool {
        self.look_ahead.is_some()
    }

    /// Turns the look-ahead lens (`z`) on or off. On: the view's horizontal field is
    /// [`LOOK_AHEAD_FOV_DEG`] whatever the screen's shape (no least vertical field), as `mazewalk
    /// render --fov 30` draws it; `+`/`-` then widen or narrow the lens. Off: the fields the viewer had
    /// before it, exactly. Nothing else changes.
    pub fn set_look_ahead(&mut self, on: bool) {
        match (on, self.look_ahead) {
            (true, None) => {
                self.look_ahead = Some((self.camera.hfov_deg, self.camera.min_vfov_deg));
                (self.camera.hfov_deg, self.camera.min_vfov_deg) = (LOOK_AHEAD_FOV_DEG, 0.0);
            }
            (false, Some((hfov_deg, min_vfov_deg))) => {
                self.look_ahead = None;
                (self.camera.hfov_deg, self.camera.min_vfov_deg) = (hfov_deg, min_vfov_deg);
            }
            _ => {}
        }
    }

    /// The clock from zero where the viewer stands: a new walk from here, the floor's chalk kept (a
    /// served player put nearer the exit than the start by a crowd there, back as far from the exit
    /// as the start: `serve`'s start line). `r` still brings it back to its start.
    pub fn restart_clock(&mut self, now: f64) {
        (self.started, self.finished) = (now, None);
        self.exit_box = false;
        self.recorder.restart();
        self.finish_pose = None;
        self.track(now);
    }

    /// Back to the start, the clock from zero (the start's field of view: the lens off).
    fn reset(&mut self, now: f64) {
        (self.camera, self.cell) = self.start;
        self.look_ahead = None;
        self.held.clear(now);
        self.snap = None;
        (self.started, self.finished) = (now, None);
        (self.exit_box, self.confirm_quit) = (false, false);
        self.recorder.restart();
        self.finish_pose = None;
        // a new walk: the floor wiped clean
        self.walked.clear();
        self.walked_bits.fill(0);
        self.track(now);
    }

    /// A mouse drag by (`dx`, `dy`) terminal cells: look around.
    pub fn drag(&mut self, dx: i32, dy: i32) -> bool {
        if dx == 0 && dy == 0 || self.replay.is_some() {
            return false;
        }
        self.turn(-(dx as f32) * DRAG_DEGREES_PER_CELL, -(dy as f32) * DRAG_DEGREES_PER_CELL);
        true
    }

    /// The terminal lost focus: releases will not arrive, so let go of every key.
    pub(crate) fn focus_lost(&mut self) {
        self.held.clear(self.last_tick); // (the motion made so far: to the last tick)
    }

    /// One discrete step of a continuous action (a tap): `amount` degrees or maze units.
    fn take_step(&mut self, action: Action, amount: f32, now: f64) {
        match action {
            Action::TurnLeft => self.turn(amount, 0.0),
            Action::TurnRight => self.turn(-amount, 0.0),
            Action::LookUp => self.turn(0.0, amount),
            Action::LookDown => self.turn(0.0, -amount),
            Action::Rise => self.rise(amount),
            Action::Sink => self.rise(-amount),
            Action::FovWider => self.zoom(amount),
            Action::FovNarrower => self.zoom(-amount),
            Action::Forward => self.walk(Vec2::new(amount, 0.0), now),
            Action::Back => self.walk(Vec2::new(-amount, 0.0), now),
            Action::StrafeRight => self.walk(Vec2::new(0.0, amount), now),
            Action::StrafeLeft => self.walk(Vec2::new(0.0, -amount), now),
            _ => {}
        }
    }

    /// Starts a snap turn by `deg` (±90, counter-clockwise positive), after any snap under way. It lands
    /// on a multiple of 90° when within [`SNAP_ALIGN_DEG`] of one, and never more than 180° ahead of the
    /// heading (a held snap key turns in right angles, not ever faster).
    fn snap_turn(&mut self, deg: f32, now: f64) {
        let heading = self.snap.and_then(|s| s.heading_at(now)).unwrap_or(self.camera.yaw_deg);
        let target = self.snap.map_or(self.camera.yaw_deg, |s| s.to_deg) + deg;
        let aligned = (target / 90.0).round() * 90.0;
        let to_deg = if (target - aligned).abs() <= SNAP_ALIGN_DEG { aligned } else { target };
        if (to_deg - heading).abs() > 180.0 + SNAP_ALIGN_DEG {
            return;
        }
        self.snap = Some(Snap { from_deg: heading, to_deg, start: now });
    }

    fn turn(&mut self, yaw_deg: f32, pitch_deg: f32) {
        if let Some(snap) = &mut self.snap {
            // Turning during a snap carries the snap along.
            snap.from_deg += yaw_deg;
            snap.to_deg += yaw_deg;
        }
        self.camera.yaw_deg = (self.camera.yaw_deg + yaw_deg).rem_euclid(360.0);
        self.camera.pitch_deg = (self.camera.pitch_deg + pitch_deg).clamp(-PITCH_LIMIT_DEG, PITCH_LIMIT_DEG);
    }

    fn rise(&mut self, dz: f32) {
        self.camera.eye_z = clamp_eye_height(self.camera.eye_z + dz);
    }

    /// The horizontal field of view (degrees) of the view drawn `cols × rows` cells: the camera's, or
    /// wider where it keeps the maze's least vertical field ([`Camera::hfov_for`]).
    #[must_use]
    pub fn shown_hfov_deg(&self, cols: usize, rows: usize) -> f32 {
        let aspect = cols as f32 * self.options.cell_aspect / rows.max(1) as f32;
        if aspect.is_finite() && aspect > 0.0 { self.camera.hfov_for(aspect) } else { self.camera.hfov_deg }
    }

    fn zoom(&mut self, deg: f32) {
        self.camera.hfov_deg = (self.camera.hfov_deg + deg).clamp(FOV_RANGE_DEG.0, FOV_RANGE_DEG.1);
        if self.camera.min_vfov_deg > 0.0 {
            // a generated maze's least vertical field zooms too, or a wide screen would not show it
            self.camera.min_vfov_deg = (self.camera.min_vfov_deg + deg).clamp(FOV_RANGE_DEG.0, 150.0);
        }
    }

    /// Walks by `by` maze units (x forward, y right; level whatever the pitch) as far as the walls let.
    fn walk(&mut self, by: Vec2, now: f64) {
        let heading = self.camera.yaw_deg.to_radians();
        let delta = heading_dir(heading) * by.x + heading_right(heading) * by.y;
        let to = step(
            &self.maze,
            Position { cell: self.cell, pos: self.camera.position },
            delta,
            self.maze.clearance(),
        );
        self.camera.position = to.pos;
        self.cell = to.cell;
        if self.finished.is_none() && self.maze.exit().is_some_and(|exit| exit.cell == self.cell) {
            self.finish_pose = Some(self.pose());
            self.finished = Some(now - self.started);
            // the exit box takes the help's place (after `r` the walk starts with none); the keys
            // that walked here let go, so that the box is seen
            (self.help, self.confirm_quit) = (false, false);
            (self.exit_box, self.exit_box_since) = (true, now);
            self.held.clear_motion(now);
        }
    }

    /// True while something moves by itself (held keys, a snap turn), so the loop keeps drawing frames.
    #[must_use]
    pub fn is_animating(&self, now: f64) -> bool {
        self.held.any(now) || self.snap.is_some() || self.replay.is_some() && self.finished.is_none()
    }

    /// Advances held-key motion and any snap turn to time `now` at speeds independent of the frame rate.
    /// Returns true when the viewer moved.
    pub fn tick(&mut self, now: f64) -> bool {
        // A frame longer than MAX_STEP (a stall, a suspend) moves by MAX_STEP's worth only.
        let from = self.last_tick.max(now - MAX_STEP);
        self.last_tick = now;
        let t = |action| self.held.moving_time(action, from, now) as f32;
        let axis = |plus, minus| t(plus) - t(minus); // seconds of motion, signed
        let walk =
            Vec2::new(axis(Action::Forward, Action::Back), axis(Action::StrafeRight, Action::StrafeLeft));
        let turn = axis(Action::TurnLeft, Action::TurnRight);
        let look = axis(Action::LookUp, Action::LookDown);
        let rise = axis(Action::Rise, Action::Sink);
        let zoom = axis(Action::FovWider, Action::FovNarrower);
        self.held.expire(now);
        let before = (self.camera, self.cell);
        if turn != 0.0 || look != 0.0 {
            self.turn(turn * self.motion.turn_speed_deg, look * LOOK_SPEED);
        }
        if rise != 0.0 {
            self.rise(rise * RISE_SPEED);
        }
        if zoom != 0.0 {
            self.zoom(zoom * FOV_SPEED);
        }
        if walk != Vec2::ZERO {
            // Diagonally no faster than straight: the longer of the two, in the combined direction.
            let seconds = walk.x.abs().max(walk.y.abs());
            self.walk(walk.normalize_or_zero() * seconds * self.motion.walk_speed, now);
        }
        if let Some(snap) = self.snap {
            let heading = snap.heading_at(now);
            self.camera.yaw_deg = heading.unwrap_or(snap.to_deg).rem_euclid(360.0);
            if heading.is_none() {
                self.snap = None;
            }
        }
        self.follow_replay(now);
        self.track(now);
        (self.camera, self.cell) != before
    }
}
