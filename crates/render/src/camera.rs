//! The camera: where the viewer stands and looks, and the matrices that follow from it.
//!
//! A [`Camera`] speaks the maze files' language (position in the maze plane, eye height, heading and a
//! **horizontal** field of view in degrees); [`Camera::eye`] turns it into an [`Eye`]: the world → view,
//! view → clip and NDC → grid matrices for one sample grid, built with the hand-written math core, plus
//! the world-space basis the per-sample floor/ceiling rays use.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use thiserror::Error;

use super::fovea::{self, AxisWarp};
use super::raster::GridVertex;
use mazewalk_math::{self as math, Convention, MathError};
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z, WALL_MARGIN, heading_right};

/// Perspective or orthographic projection.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Projection {
    /// Rays from the eye through the grid: far things look smaller.
    #[default]
    Perspective,
    /// Parallel rays along the view direction: a blueprint-like view; fov sets the zoom.
    Orthographic,
}

mazewalk_names::named!(
    Projection,
    "projection",
    [
        ("perspective", Projection::Perspective),
        ("orthographic", Projection::Orthographic),
        ("persp", Projection::Perspective),
        ("ortho", Projection::Orthographic),
    ]
);

/// The narrowest and widest horizontal field of view, in degrees.
pub const FOV_RANGE_DEG: (f32, f32) = (10.0, 170.0);
/// Pitch is clamped to ±90°: straight up or down, never over the top.
pub const PITCH_LIMIT_DEG: f32 = 90.0;
/// Half the width of the orthographic view at fov 90°, in maze units (one cell of the generated mazes).
pub(crate) const ORTHO_HALF_WIDTH_AT_90: f32 = 8.0;
/// How far the viewer sees, in maze units; fog reaches full strength there.
pub(crate) const DEFAULT_VIEW_DISTANCE: f32 = 96.0;
/// The near plane never exceeds this distance from the eye (maze units).
pub(crate) const MAX_NEAR: f32 = 0.05;

/// What is wrong with a camera or the grid it renders into.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CameraError {
    /// A camera parameter is NaN or infinite.
    #[error("camera {what} is not a finite number ({value})")]
    NotFinite {
        /// Which parameter.
        what: &'static str,
        /// Its value.
        value: f32,
    },
    /// The field of view is outside [`FOV_RANGE_DEG`].
    #[error("field of view {0}° is outside {min}..={max}°", min = FOV_RANGE_DEG.0, max = FOV_RANGE_DEG.1)]
    FovOutOfRange(f32),
    /// The eye is not strictly between floor and ceiling.
    #[error("eye height {0} is not strictly between the floor (-1) and the ceiling (+1)")]
    EyeHeightOutOfRange(f32),
    /// The sample grid has no area, or the cell aspect is unusable.
    #[error("cannot render into a {width}×{height} sample grid with cell aspect {aspect}")]
    BadGrid {
        /// Samples across.
        width: usize,
        /// Samples down.
        height: usize,
        /// Sample width / sample height.
        aspect: f32,
    },
    /// The math core refused the matrices (should not happen once the checks above pass).
    #[error(transparent)]
    Math(#[from] MathError),
}

/// A viewer in the maze, as the files and the CLI describe it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position in the maze plane (world x, y).
    pub position: Vec2,
    /// Eye height: world z, strictly between the floor (-1) and the ceiling (+1).
    pub eye_z: f32,
    /// Heading in degrees, counter-clockwise from +x (the files' `dir`).
    pub yaw_deg: f32,
    /// Degrees above the horizon (negative looks down); clamped to ±90°.
    pub pitch_deg: f32,
    /// Horizontal field of view across the whole grid width, in degrees (the files' `fov`).
    pub hfov_deg: f32,
    /// The least vertical field of view, degrees (0 = none): where `hfov_deg` across the grid's
    /// aspect gives less, the horizontal field widens to keep it (Hor+, up to [`FOV_RANGE_DEG`]'s top).
    /// A generated maze asks for one ([`Maze::min_vfov_deg`](mazewalk_maze::Maze::min_vfov_deg)).
    pub min_vfov_deg: f32,
    /// Perspective or orthographic.
    pub projection: Projection,
    /// Which handedness/depth convention the matrices use (the frame is the same for all three).
    pub convention: Convention,
    /// How far the viewer sees (the far plane), in maze units.
    pub view_distance: f32,
    /// A wide perspective view (over [`fovea::MIN_HFOV_DEG`]) is drawn through the foveated
    /// viewport: its middle magnified, its edges squeezed ([`fovea`]). Off in [`Camera::new`]; the
    /// walk and `mazewalk render` turn it on.
    pub fovea: bool,
}

impl Camera {
    /// A level perspective camera at `position`, eye height 0, looking along `yaw_deg` with `hfov_deg`.
    #[must_use]
    pub fn new(position: Vec2, yaw_deg: f32, hfov_deg: f32) -> Camera {
        Camera {
            position,
            eye_z: 0.0,
            yaw_deg,
            pitch_deg: 0.0,
            hfov_deg,
            min_vfov_deg: 0.0,
            projection: Projection::Perspective,
            convention: Convention::RhGl,
            view_distance: DEFAULT_VIEW_DISTANCE,
            fovea: false,
        }
    }

    /// Checks the parameters that come from outside (files, CLI, keys).
    ///
    /// # Errors
    /// [`CameraError`] naming the first bad parameter.
    pub fn validate(&self) -> Result<(), CameraError> {
        let finite = [
            ("x", self.position.x),
            ("y", self.position.y),
            ("height", self.eye_z),
            ("heading", self.yaw_deg),
            ("pitch", self.pitch_deg),
            ("fov", self.hfov_deg),
            ("vertical fov", self.min_vfov_deg),
            ("view distance", self.view_distance),
        ];
        if let Some(&(what, value)) = finite.iter().find(|(_, v)| !v.is_finite()) {
            return Err(CameraError::NotFinite { what, value });
        }
        if !(FOV_RANGE_DEG.0..=FOV_RANGE_DEG.1).contains(&self.hfov_deg) {
            return Err(CameraError::FovOutOfRange(self.hfov_deg));
        }
        if !(0.0..FOV_RANGE_DEG.1).contains(&self.min_vfov_deg) {
            return Err(CameraError::FovOutOfRange(self.min_vfov_deg));
        }
        if !(self.eye_z > FLOOR_Z && self.eye_z < CEILING_Z) {
            return Err(CameraError::EyeHeightOutOfRange(self.eye_z));
        }
        if self.view_distance <= 1.0 {
            return Err(CameraError::NotFinite { what: "view distance", value: self.view_distance });
        }
        Ok(())
    }

    /// The horizontal field of view (degrees) across a view `aspect` wide to 1 high: `hfov_deg`, or
    /// wider where that gives less than `min_vfov_deg` vertically (at most [`FOV_RANGE_DEG`]'s top).
    #[must_use]
    pub fn hfov_for(&self, aspect: f32) -> f32 {
        let keeps_vfov = 2.0 * ((0.5 * self.min_vfov_deg).to_radians().tan() * aspect).atan().to_degrees();
        if keeps_vfov.is_finite() {
            self.hfov_deg.max(keeps_vfov).min(FOV_RANGE_DEG.1)
        } else {
            self.hfov_deg
        }
    }

    /// The eye in world space.
    #[must_use]
    pub(crate) fn eye_world(&self) -> Vec3 {
        self.position.extend(self.eye_z)
    }

    /// The matrices for a `width × height` sample grid whose samples are `sample_aspect` (w / h) wide.
    ///
    /// # Errors
    /// [`CameraError`] for a bad camera or an empty grid.
    pub fn eye(&self, width: usize, height: usize, sample_aspect: f32) -> Result<Eye, CameraError> {
        self.validate()?;
        if width == 0 || height == 0 || !(sample_aspect.is_finite() && sample_aspect > 0.0) {
            return Err(CameraError::BadGrid { width, height, aspect: sample_aspect });
        }
        let yaw = self.yaw_deg.to_radians();
        let pitch = self.pitch_deg.clamp(-PITCH_LIMIT_DEG, PITCH_LIMIT_DEG).to_radians();
        let position = self.eye_world();
        // The basis comes from yaw and pitch directly: `up` tilts with the view, so looking straight up
        // or down never meets the degenerate "up parallel to forward" case and never flips.
        let forward = math::direction_from_yaw_pitch(yaw, pitch);
        let up = math::up_from_yaw_pitch(yaw, pitch);
        // forward × up, which is level for every pitch: the heading's right. Built in the plane so its z is
        // exactly 0, and a row of samples keeps one ray height and slope (the floor pass's row constants).
        let right = heading_right(yaw).extend(0.0);
        debug_assert!(right.distance(forward.cross(up)) < 1e-5, "right = forward × up");
        let world_to_view = self.convention.look_to(position, forward, up)?;

        // Horizontal fov across the whole grid; the physical aspect counts the samples' shape.
        let conv = self.convention;
        let aspect = math::physical_aspect(width, height, sample_aspect)?;
        let hfov = self.hfov_for(aspect).to_radians();
        let far = self.view_distance;
        let (view_to_clip, near, half_w) = match self.projection {
            Projection::Perspective => {
                // Keep the near plane's farthest corner inside the wall margin, so a viewer standing
                // against a wall never sees through it.
                let near = MAX_NEAR.min(0.9 * WALL_MARGIN / math::near_corner_distance(1.0, hfov, aspect));
                let proj = math::perspective_hfov(conv, hfov, width, height, sample_aspect, near, far)?;
                (proj, near, (0.5 * hfov).tan())
            }
            Projection::Orthographic => {
                // The fov zooms: 90° shows ORTHO_HALF_WIDTH_AT_90 units either side of the view axis.
                let r = ORTHO_HALF_WIDTH_AT_90 * (0.5 * hfov).tan();
                (math::orthographic_hwidth(conv, r, width, height, sample_aspect, 0.0, far)?, 0.0, r)
            }
        };
        let half_h = half_w / aspect;
        let ndc_to_grid = math::viewport(width as f32, height as f32, conv.depth_range())?;
        let world_to_clip = view_to_clip * world_to_view;
        let foveated = self.fovea
            && self.projection == Projection::Perspective
            && hfov.to_degrees() > fovea::MIN_HFOV_DEG;
        let warp = match (AxisWarp::new(width, fovea::ACROSS), AxisWarp::new(height, fovea::DOWN)) {
            (Some(x), Some(y)) if foveated => Some([x, y]),
            _ => None,
        };
        Ok(Eye {
            camera: *self,
            width,
            height,
            world_to_view,
            world_to_clip,
            ndc_to_grid,
            normal_to_view: math::normal_matrix(world_to_view)?,
            position,
            forward,
            right,
            up,
            near,
            far,
            half_w,
            half_h,
            window: [Vec2::NEG_ONE, Vec2::ONE],
            warp,
        })
    }
}

/// A camera set up for one sample grid: every matrix of the pipeline, in the camera's convention.
#[derive(Clone, Copy, Debug)]
pub struct Eye {
    /// The camera this came from.
    pub camera: Camera,
    /// Samples across.
    pub width: usize,
    /// Samples down.
    pub height: usize,
    /// World → view (the look-at).
    pub world_to_view: Mat4,
    /// World → clip (projection · view).
    pub world_to_clip: Mat4,
    /// NDC → grid (the viewport), applied after the divide by w.
    pub ndc_to_grid: Mat4,
    /// World normals → view normals (inverse transpose of the view's upper 3×3).
    pub normal_to_view: Mat3,
    /// The eye's position, world space.
    pub position: Vec3,
    /// Unit view direction, world space.
    pub forward: Vec3,
    /// Unit screen-right, world space.
    pub right: Vec3,
    /// Unit screen-up, world space.
    pub up: Vec3,
    /// Near plane distance (0 for orthographic).
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
    /// Perspective: tan(hfov/2); orthographic: half the view width in maze units.
    pub half_w: f32,
    /// Perspective: tan(vfov/2); orthographic: half the view height in maze units.
    pub half_h: f32,
    /// The part of NDC this grid shows, (min x, min y) and (max x, max y): all of it, or one tile's
    /// band of a foveated view ([`Eye::tiles`]).
    pub window: [Vec2; 2],
    /// The foveated viewport's warp across and down ([`fovea`]), or `None`: NDC → screen before the
    /// viewport. Only a whole view's eye has one; its tiles' eyes are each plain viewports.
    pub warp: Option<[AxisWarp; 2]>,
}

/// One tile of a view ([`Eye::tiles`]): an eye for its samples, and where they go in the view's grid.
#[derive(Clone, Copy, Debug)]
pub struct Tile {
    /// The tile's own eye: the view's projection, a viewport over the tile's NDC window.
    pub eye: Eye,
    /// The tile's first column and row in the view's grid.
    pub at: (usize, usize),
}

impl Eye {
    /// World → clip for one point.
    #[must_use]
    pub fn clip(&self, world: Vec3) -> Vec4 {
        self.world_to_clip * world.extend(1.0)
    }

    /// Clip → grid: divide by w (clip → NDC), the fovea's warp if any, then the viewport (NDC → grid
    /// x, y, depth in [0, 1]).
    #[must_use]
    pub fn grid(&self, clip: Vec4) -> Vec3 {
        let mut ndc = clip.truncate() / clip.w;
        if let Some([across, down]) = &self.warp {
            ndc = Vec3::new(across.to_screen(ndc.x), down.to_screen(ndc.y), ndc.z);
        }
        self.ndc_to_grid.transform_point3(ndc)
    }

    /// The tiles this view is drawn in: the view itself unless it is foveated, else one tile per
    /// band across × band down of its warp, each an eye whose plain viewport maps its band of NDC
    /// onto its samples, covering the view's grid once.
    #[must_use]
    pub fn tiles(&self) -> Vec<Tile> {
        let Some([across, down]) = &self.warp else { return vec![Tile { eye: *self, at: (0, 0) }] };
        let (w, h) = (self.width as f32, self.height as f32);
        let col = |s: f32| ((s + 1.0) * 0.5 * w).round() as usize;
        let row = |s: f32| ((1.0 - s) * 0.5 * h).round() as usize;
        let mut tiles = Vec::new();
        for (ndc_y, screen_y) in down.bands().collect::<Vec<_>>().into_iter().rev() {
            for (ndc_x, screen_x) in across.bands() {
                let (x0, x1, y0, y1) =
                    (col(screen_x[0]), col(screen_x[1]), row(screen_y[1]), row(screen_y[0]));
                let (width, height) = (x1 - x0, y1 - y0);
                // The band's NDC onto [-1, 1], then the plain viewport onto the tile's samples.
                let centre = Vec2::new(ndc_x[0] + ndc_x[1], ndc_y[0] + ndc_y[1]) * 0.5;
                let scale = Vec2::new(2.0 / (ndc_x[1] - ndc_x[0]), 2.0 / (ndc_y[1] - ndc_y[0]));
                let to_band =
                    Mat4::from_scale(scale.extend(1.0)) * Mat4::from_translation((-centre).extend(0.0));
                let Ok(viewport) =
                    math::viewport(width as f32, height as f32, self.camera.convention.depth_range())
                else {
                    continue; // an empty band (none: knots are strictly apart)
                };
                let eye = Eye {
                    width,
                    height,
                    ndc_to_grid: viewport * to_band,
                    window: [Vec2::new(ndc_x[0], ndc_y[0]), Vec2::new(ndc_x[1], ndc_y[1])],
                    warp: None,
                    ..*self
                };
                tiles.push(Tile { eye, at: (x0, y0) });
            }
        }
        tiles
    }

    /// How far from the eye a point it sees can be, at most, maze units: the view volume is convex, so
    /// none of it is farther than its farthest corner, on the far plane (`far` along the view axis;
    /// across and down `far` × the tangents in perspective, the half sizes in orthographic).
    #[must_use]
    pub fn reach(&self) -> f32 {
        let (w, h) = (self.half_w, self.half_h);
        match self.camera.projection {
            Projection::Perspective => self.far * (1.0 + w * w + h * h).sqrt(),
            Projection::Orthographic => (self.far * self.far + w * w + h * h).sqrt(),
        }
    }

    /// Whether this eye draws a whole view through one viewport: neither a foveated view (its warp)
    /// nor one tile of one (a band of NDC).
    #[must_use]
    pub fn is_whole(&self) -> bool {
        self.warp.is_none() && self.window == [Vec2::NEG_ONE, Vec2::ONE]
    }

    /// What this grid spans across and down: in tan of the angle off the view axis (perspective) or
    /// maze units (orthographic); a tile, its band's share. `width / tan_extent().x` samples a unit.
    #[must_use]
    pub fn tan_extent(&self) -> Vec2 {
        let extent = self.window[1] - self.window[0];
        Vec2::new(extent.x * self.half_w, extent.y * self.half_h)
    }

    /// A clipped vertex taken to the raster: ÷w → NDC → viewport, with `1/w` kept for perspective-correct
    /// interpolation of `attrs`.
    #[must_use]
    pub(crate) fn grid_vertex<A>(&self, clip: Vec4, attrs: A) -> GridVertex<A> {
        let grid = self.grid(clip);
        GridVertex { pos: grid.truncate(), depth: grid.z, inv_w: 1.0 / clip.w, attrs }
    }

    /// View-space depth (distance along the view direction) of a world point.
    #[must_use]
    pub(crate) fn view_depth(&self, world: Vec3) -> f32 {
        (world - self.position).dot(self.forward)
    }

    /// Grid depth as a function of view depth, for comparing a distance with the depth buffer.
    #[must_use]
    pub(crate) fn depth_by_distance(&self) -> DepthByDistance {
        let (at_eye, per_unit) = (self.clip(self.position), self.world_to_clip * self.forward.extend(0.0));
        DepthByDistance {
            clip_z: Vec2::new(at_eye.z, per_unit.z),
            clip_w: Vec2::new(at_eye.w, per_unit.w),
            scale: self.ndc_to_grid.z_axis.z,
            offset: self.ndc_to_grid.w_axis.z,
        }
    }

    /// The ray through grid point (`gx`, `gy`): where it starts (on the near plane) and its unit-free
    /// direction in world space, such that `start + t·dir` has view depth `near + t` (perspective) or
    /// `t` (orthographic). Built from the camera basis, not the matrices, so all conventions agree.
    #[must_use]
    pub fn ray(&self, gx: f32, gy: f32) -> (Vec3, Vec3) {
        self.ray_from(self.across(gx), self.down(gy))
    }

    /// The rays through grid points (0.5, `gy`) and (1.5, `gy`) for any row `gy`, as [`Eye::ray`]
    /// gives them: a pass over rows asks them twice a row, and their columns' share of the work is
    /// the same on every row, so it is done once here ([`RowRays`]).
    #[must_use]
    pub(crate) fn row_rays(&self) -> RowRays<'_> {
        RowRays { eye: self, across: [self.across(0.5), self.across(1.5)] }
    }

    /// What column `gx` adds to its rays, whatever the row: the part of [`Eye::ray`]'s sums before
    /// the row's term (`forward + right·x` in perspective, `position + right·x` in orthographic).
    fn across(&self, gx: f32) -> Vec3 {
        let [lo, hi] = self.window;
        let mut ndc_x = lo.x + gx / self.width as f32 * (hi.x - lo.x);
        if let Some([across, _]) = &self.warp {
            ndc_x = across.to_ndc(ndc_x);
        }
        match self.camera.projection {
            Projection::Perspective => self.forward + self.right * (ndc_x * self.half_w),
            Projection::Orthographic => self.position + self.right * (ndc_x * self.half_w),
        }
    }

    /// What row `gy` adds to its rays, whatever the column: the last term of [`Eye::ray`]'s sums.
    #[inline]
    fn down(&self, gy: f32) -> Vec3 {
        let [lo, hi] = self.window;
        let mut ndc_y = hi.y - gy / self.height as f32 * (hi.y - lo.y); // grid y down, NDC y up
        if let Some([_, down]) = &self.warp {
            ndc_y = down.to_ndc(ndc_y);
        }
        self.up * (ndc_y * self.half_h)
    }

    /// [`Eye::ray`] from its column's share ([`Eye::across`]) and its row's ([`Eye::down`]): the
    /// same operations in the same order, so the same bits.
    #[inline]
    fn ray_from(&self, across: Vec3, down: Vec3) -> (Vec3, Vec3) {
        match self.camera.projection {
            Projection::Perspective => {
                let dir = across + down;
                (self.position + dir * self.near, dir)
            }
            Projection::Orthographic => (across + down, self.forward),
        }
    }
}

/// The rays of a row's first two samples, row after row ([`Eye::row_rays`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowRays<'e> {
    eye: &'e Eye,
    /// What columns 0.5 and 1.5 add to their rays ([`Eye::across`]).
    across: [Vec3; 2],
}

impl RowRays<'_> {
    /// The rays through (0.5, `gy`) and (1.5, `gy`): `Eye::ray`'s, bit for bit.
    #[inline]
    pub(crate) fn at(&self, gy: f32) -> [(Vec3, Vec3); 2] {
        let down = self.eye.down(gy); // (the row's share, the same for both)
        let [first, second] = self.across;
        [self.eye.ray_from(first, down), self.eye.ray_from(second, down)]
    }
}

/// The grid depth of any point at a given view depth (distance along the view direction): a projection's
/// clip z and w rows have no x or y terms, so both are affine in the view depth, and the viewport maps
/// NDC z to grid depth by a scale and an offset. Two multiply-adds and a divide, where the full path
/// (`Eye::grid(Eye::clip(p))`) is a 4×4 and a 3×4 product: the floor pass's depth test per sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DepthByDistance {
    /// Clip z at view depth 0 and per unit of view depth.
    clip_z: Vec2,
    /// Clip w, likewise.
    clip_w: Vec2,
    /// The viewport's NDC z → grid depth.
    scale: f32,
    offset: f32,
}

impl DepthByDistance {
    /// The grid depth at view depth `d`.
    #[must_use]
    pub(crate) fn grid_depth(&self, d: f32) -> f32 {
        let (z, w) = (self.clip_z.x + self.clip_z.y * d, self.clip_w.x + self.clip_w.y * d);
        self.scale * (z / w) + self.offset
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A foveated view's tiles cover its grid exactly once, each tile's viewport maps its NDC window
    /// onto its samples, and a point's grid position through the view's warp is its position through
    /// the tile that holds it; a view that is not foveated is its own one tile.
    #[test]
    fn tiles_cover_the_grid_once_and_agree_with_the_warp() {
        for (cols, rows, fovea, hfov) in
            [(120, 80, true, 119.0), (80, 48, true, 120.0), (201, 61, true, 90.0), (120, 80, false, 119.0)]
        {
            let camera = Camera { fovea, ..Camera::new(Vec2::new(2.0, -1.0), 30.0, hfov) };
            let view = camera.eye(cols, rows, 1.0).expect("eye");
            let tiles = view.tiles();
            assert_eq!(tiles.len(), if fovea { 25 } else { 1 }, "{cols}×{rows}");
            let mut covered = vec![0u8; cols * rows];
            for tile in &tiles {
                let (x0, y0) = tile.at;
                for y in y0..y0 + tile.eye.height {
                    for x in x0..x0 + tile.eye.width {
                        covered[y * cols + x] += 1;
                    }
                }
                // points inside the tile's window: the same grid position both ways
                let [lo, hi] = tile.eye.window;
                for t in [0.1f32, 0.5, 0.9] {
                    let ndc = lo.lerp(hi, t).extend(0.3);
                    let clip = ndc.extend(1.0) * 2.5; // any w: the divide brings back `ndc`
                    let (whole, own) = (view.grid(clip), tile.eye.grid(clip));
                    let own = own + Vec3::new(x0 as f32, y0 as f32, 0.0);
                    assert!(whole.distance(own) < 1e-3, "{cols}×{rows} {ndc}: {whole} vs {own}");
                    // and the ray through that grid point is the same ray
                    let (a, b) =
                        (view.ray(whole.x, whole.y).1, tile.eye.ray(own.x - x0 as f32, own.y - y0 as f32).1);
                    assert!(a.distance(b) < 1e-4, "{a} vs {b}");
                }
            }
            assert!(covered.iter().all(|&c| c == 1), "{cols}×{rows}: every sample in one tile");
        }
    }

    /// A row's first two rays by [`Eye::row_rays`] are [`Eye::ray`]'s, bit for bit, on every row of
    /// views whole and foveated (the whole view's warp, and each tile), level and pitched, in both
    /// projections.
    #[test]
    fn row_rays_are_the_rays_bit_for_bit() {
        let bits =
            |(start, dir): (Vec3, Vec3)| [start.to_array(), dir.to_array()].map(|v| v.map(f32::to_bits));
        for projection in [Projection::Perspective, Projection::Orthographic] {
            for (pitch_deg, fovea) in [(0.0, true), (-12.0, true), (35.0, false)] {
                let camera = Camera {
                    projection,
                    pitch_deg,
                    fovea,
                    eye_z: 0.2,
                    ..Camera::new(Vec2::new(2.3, -1.7), 37.0, 119.0)
                };
                let view = camera.eye(120, 80, 1.0).expect("eye");
                for eye in std::iter::once(view).chain(view.tiles().into_iter().map(|tile| tile.eye)) {
                    let rays = eye.row_rays();
                    for y in 0..eye.height {
                        let gy = y as f32 + 0.5;
                        let [first, second] = rays.at(gy);
                        assert_eq!(bits(first), bits(eye.ray(0.5, gy)), "{projection:?} {pitch_deg} row {y}");
                        assert_eq!(
                            bits(second),
                            bits(eye.ray(1.5, gy)),
                            "{projection:?} {pitch_deg} row {y}"
                        );
                    }
                }
            }
        }
    }

    /// `DepthByDistance` agrees with the full clip → grid path for points all over the view volume, in
    /// every projection and convention, pitched or level.
    #[test]
    fn depth_by_distance_matches_the_full_path() {
        for convention in Convention::ALL {
            for projection in [Projection::Perspective, Projection::Orthographic] {
                for pitch_deg in [0.0, 35.0, -80.0] {
                    let camera = Camera {
                        convention,
                        projection,
                        pitch_deg,
                        eye_z: 0.3,
                        ..Camera::new(Vec2::new(2.0, -1.0), 30.0, 75.0)
                    };
                    let eye = camera.eye(120, 40, 1.0).expect("camera");
                    let depth = eye.depth_by_distance();
                    for (gx, gy, t) in
                        [(0.5, 0.5, 0.0), (60.0, 20.0, 3.0), (119.5, 39.5, 40.0), (10.0, 33.0, 90.0)]
                    {
                        let (start, dir) = eye.ray(gx, gy);
                        let p = start + dir * t;
                        let full = eye.grid(eye.clip(p)).z;
                        let fast = depth.grid_depth(eye.view_depth(p));
                        assert!(
                            (full - fast).abs() < 1e-5,
                            "{convention:?} {projection:?} {pitch_deg}: {full} vs {fast}"
                        );
                    }
                }
            }
        }
    }
}
