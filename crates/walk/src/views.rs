//! 3D views drawn once and shown by several screens: a server's spectators who follow one player at
//! one size, colour depth and charset see the same view, so the first screen to draw it renders it
//! and the others copy its cells.
//!
//! A view is a pure function of what [`ViewKey`] holds — the maze, the camera, the figures, the
//! render options, the size and the chalk marks (the renderer's buffers are caches, and
//! [`Renderer::render`] reads nothing else but the marks, set from the key before each render) — so two screens whose keys are equal draw equal cells, whoever drew them. The
//! cache keeps the last [`SharedViews::capacity`] views, each in a [`OnceLock`] taken under the
//! cache's lock and filled after it: spectators woken together by one move wait for the first one's
//! render of their view instead of each making their own, and views with different keys render at
//! once on different threads.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use mazewalk_maze::Maze;
use mazewalk_render::{Camera, CameraError, RenderOptions, RenderStats, Renderer, Sprite, Target};
use mazewalk_term::frame::Frame;

/// Everything a 3D view is drawn from.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewKey {
    /// The maze, by address (a server serves one).
    maze: usize,
    camera: Camera,
    sprites: Vec<Sprite>,
    options: RenderOptions,
    size: (usize, usize),
    /// The cells marked in chalk ([`Renderer::set_chalk`]).
    chalk: Vec<u32>,
}

impl ViewKey {
    /// The key of the view of `maze` from `camera` with `sprites`, drawn with `options` at `size`
    /// (columns, rows).
    #[must_use]
    pub fn new(
        maze: &Maze,
        camera: &Camera,
        sprites: &[Sprite],
        options: &RenderOptions,
        size: (usize, usize),
    ) -> ViewKey {
        ViewKey {
            maze: std::ptr::from_ref(maze) as usize,
            camera: *camera,
            sprites: sprites.to_vec(),
            options: *options,
            size,
            chalk: Vec::new(),
        }
    }

    /// The same view with chalk marks on the floors of `cells` ([`Renderer::set_chalk`]).
    #[must_use]
    pub fn with_chalk(mut self, cells: &[u32]) -> ViewKey {
        self.chalk = cells.to_vec();
        self
    }

    /// Whether this is the key [`new`](Self::new) and [`with_chalk`](Self::with_chalk) would make of
    /// these, bit for bit: its numbers' bits, not only their values, so that a `-0.0` where `0.0`
    /// was (equal as numbers, not always in what a render makes of them) is another view. Allocates
    /// nothing (a screen asks it before each frame).
    #[must_use]
    pub fn is(
        &self,
        maze: &Maze,
        camera: &Camera,
        sprites: &[Sprite],
        options: &RenderOptions,
        size: (usize, usize),
        chalk: &[u32],
    ) -> bool {
        let camera_bits = |c: &Camera| {
            [
                c.position.x,
                c.position.y,
                c.eye_z,
                c.yaw_deg,
                c.pitch_deg,
                c.hfov_deg,
                c.min_vfov_deg,
                c.view_distance,
            ]
            .map(f32::to_bits)
        };
        let sprite_bits =
            |s: &Sprite| [s.position.x, s.position.y, s.color.x, s.color.y, s.color.z].map(f32::to_bits);
        self.maze == std::ptr::from_ref(maze) as usize
            && self.size == size
            && self.camera == *camera
            && camera_bits(&self.camera) == camera_bits(camera)
            && self.options == *options
            && self.options.cell_aspect.to_bits() == options.cell_aspect.to_bits()
            && self.sprites.len() == sprites.len()
            && self.sprites.iter().zip(sprites).all(|(a, b)| a == b && sprite_bits(a) == sprite_bits(b))
            && self.chalk == chalk
    }
}

/// A view as drawn: its cells and what drawing it did.
#[derive(Debug)]
pub struct View {
    /// The view's cells (its size is the key's).
    pub frame: Frame,
    /// What the render did.
    pub stats: RenderStats,
}

/// A view being drawn or drawn: what the first screen to ask for it rendered.
type Drawn = Arc<OnceLock<Result<Arc<View>, CameraError>>>;

/// The views drawn lately, shared by the screens that may show them (see the module's doc).
#[derive(Debug)]
pub struct SharedViews {
    views: Mutex<VecDeque<(ViewKey, Drawn)>>,
    capacity: usize,
    counts: Mutex<(u64, u64)>,
}

impl SharedViews {
    /// A cache of the last `capacity` views (at least 1).
    #[must_use]
    pub fn new(capacity: usize) -> SharedViews {
        SharedViews {
            views: Mutex::new(VecDeque::new()),
            capacity: capacity.max(1),
            counts: Mutex::new((0, 0)),
        }
    }

    /// How many views it keeps.
    #[must_use]
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// The view for `key`: the one kept, or one rendered now with `renderer` and kept.
    ///
    /// # Errors
    /// The camera cannot be drawn from ([`Renderer::render`]).
    pub fn view(
        &self,
        maze: &Maze,
        key: &ViewKey,
        renderer: &mut Renderer,
    ) -> Result<Arc<View>, CameraError> {
        let (drawn, first) = {
            let mut views = self.views.lock().unwrap_or_else(PoisonError::into_inner);
            match views.iter().find(|(k, _)| k == key) {
                Some((_, drawn)) => (Arc::clone(drawn), false),
                None => {
                    if views.len() == self.capacity {
                        views.pop_front(); // the oldest
                    }
                    let drawn = Drawn::default();
                    views.push_back((key.clone(), Arc::clone(&drawn)));
                    (drawn, true)
                }
            }
        };
        self.count(first);
        // (Another screen asking meanwhile waits here for this render, not for the cache's lock.)
        let view = drawn.get_or_init(|| {
            let mut frame = Frame::new(key.size.0, key.size.1);
            let region = frame.region();
            let target = Target::Frame(&mut frame, region);
            renderer.set_chalk(&key.chalk);
            let stats = renderer.render(maze, &key.camera, &key.sprites, &key.options, target)?;
            Ok(Arc::new(View { frame, stats }))
        });
        view.clone()
    }

    fn count(&self, rendered: bool) {
        let mut counts = self.counts.lock().unwrap_or_else(PoisonError::into_inner);
        if rendered {
            counts.0 += 1;
        } else {
            counts.1 += 1;
        }
    }

    /// Views rendered and views shown from the cache, so far.
    #[must_use]
    pub fn counts(&self) -> (u64, u64) {
        *self.counts.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{App, Session, SessionOptions};

    fn session(cols: u16, rows: u16) -> Session {
        let app = App::new(mazewalk_maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
        Session::new(app, cols, rows, SessionOptions { flow_control: false, ..SessionOptions::default() })
    }

    /// Three screens of one maze from one camera at one size share one render, and show what a
    /// screen rendering its own shows; another size or another camera is a render of its own.
    #[test]
    fn equal_views_are_rendered_once_and_look_as_if_each_drew_its_own() {
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let views = Arc::new(SharedViews::new(4));
        let make = |cols, rows| {
            let mut app = App::new(Arc::clone(&maze), RenderOptions::default(), 0.0).unwrap();
            app.reveal_map = true;
            let mut s = Session::new(
                app,
                cols,
                rows,
                SessionOptions { flow_control: false, ..SessionOptions::default() },
            );
            s.share_views(Arc::clone(&views));
            s
        };
        let mut shared: Vec<Session> = (0..3).map(|_| make(100, 30)).collect();
        for s in &mut shared {
            assert!(s.frame(0.0, &mut Vec::new()));
        }
        assert_eq!(views.counts(), (1, 2), "rendered once, shown twice from the cache");
        let mut own = session(100, 30);
        own.app_mut().reveal_map = true;
        own.frame(0.0, &mut Vec::new());
        for s in &shared {
            assert_eq!(s.screen().lines(), own.screen().lines());
        }
        let mut other_size = make(90, 30);
        other_size.frame(0.0, &mut Vec::new());
        shared[0].feed(b"\x1b[D", 0.1); // ← turns this one's camera
        shared[0].frame(0.1, &mut Vec::new());
        assert_eq!(views.counts(), (3, 2));
        assert_ne!(shared[0].screen().lines(), shared[1].screen().lines());
    }

    #[test]
    fn the_cache_keeps_its_capacity_the_oldest_going_first() {
        let views = SharedViews::new(2);
        let maze = mazewalk_maze::builtin().unwrap();
        let mut renderer = Renderer::default();
        let camera = crate::state::viewer_camera(&maze);
        let key = |cols| ViewKey::new(&maze, &camera, &[], &RenderOptions::default(), (cols, 10));
        for cols in [10, 20, 30, 10] {
            views.view(&maze, &key(cols), &mut renderer).unwrap();
        }
        assert_eq!(views.counts(), (4, 0), "10 was the oldest of three: gone");
        views.view(&maze, &key(30), &mut renderer).unwrap();
        assert_eq!(views.counts(), (4, 1));
        assert_eq!(views.views.lock().unwrap().len(), 2);
    }

    /// Screens asking for one view at once (a server's spectators woken by one move, each on its own
    /// thread) get one render between them, all the same cells.
    #[test]
    fn screens_asking_at_once_share_one_render() {
        let views = Arc::new(SharedViews::new(4));
        let maze = Arc::new(mazewalk_maze::builtin().unwrap());
        let barrier = Arc::new(std::sync::Barrier::new(4));
        let drawn: Vec<Arc<View>> = (0..4)
            .map(|_| {
                let (views, maze, barrier) = (Arc::clone(&views), Arc::clone(&maze), Arc::clone(&barrier));
                std::thread::spawn(move || {
                    let camera = crate::state::viewer_camera(&maze);
                    let key = ViewKey::new(&maze, &camera, &[], &RenderOptions::default(), (120, 40));
                    barrier.wait();
                    views.view(&maze, &key, &mut Renderer::default()).unwrap()
                })
            })
            .collect::<Vec<_>>()
            .into_iter()
            .map(|thread| thread.join().unwrap())
            .collect();
        assert_eq!(views.counts(), (1, 3));
        assert!(drawn.iter().all(|view| Arc::ptr_eq(view, &drawn[0])), "one view, shared");
    }
}
