//! Figures standing in the maze (the other players): billboards through the walls' own pipeline.
//!
//! ```text
//! model (unit figure, x across, z up) ─TRS─▶ world ─view·projection─▶ clip ─clip─▶ ÷w ─viewport─▶ grid
//!     ─raster, depth LESS against the walls─▶ samples ─glyphs─▶ cells, then the label on the head's cell
//! ```
//!
//! A figure is two convex polygons in model space, a body and a head, on the plane y = 0 with the feet at
//! the origin and the unit box `[-½, ½] × [0, 1]` in x and z. Its model matrix is
//! `T(feet on the floor) · R_z(facing the eye) · S(width, 1, height)`: a billboard, turned about the
//! vertical so that it always faces the viewer (as sprites in classic first-person games do), kept
//! upright whatever the pitch. Culling: a figure is drawn only when its cell is one the portal pass
//! reached (or with no culling); walls the pass left out are not in the depth buffer, so drawing a figure
//! beyond them would show it through them.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::camera::Eye;
use super::raster::{GridVertex, blend_polygon, fill_polygon};
use super::samples::SampleBuffer;
use super::shade::{Fog, srgb_to_linear};
use mazewalk_math::{ClipPlanes, ClipVertex, clip_polygon, model, rotation_z};
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};

/// A figure's width across (maze units): a little less than a viewer's disc ([`WALL_MARGIN`] × 2 is
/// 0.5) would make it a post; this reads as a person in a 4-unit corridor.
///
/// [`WALL_MARGIN`]: mazewalk_maze::geometry::WALL_MARGIN
pub(crate) const SPRITE_WIDTH: f32 = 0.7;
/// A figure's height from the floor (maze units; floor to ceiling is 2): the head just above a
/// standing viewer's eye.
pub(crate) const SPRITE_HEIGHT: f32 = 1.45;
/// At most this many figures are drawn in one frame (the rest are left out, farthest first).
pub(crate) const MAX_SPRITES: usize = 1024;
/// The samples the figures of one frame may cover, as screens' worth: nearest first, a figure is
/// drawn while those drawn before it have covered less (their bounding boxes on the screen). Figures
/// that cover the screen this many times over hide what is behind them; the rest are left out, not
/// rasterized to fail the depth test (red-team pass 8: 1,024 figures a Redis writer put within 0.6
/// units of a player each covered most of its view; the server's CPU for it fell from 0.63 to 0.38 s
/// over 10 s).
pub(crate) const FIGURE_SCREENS: usize = 4;
/// Coverage id of the exit's beacon in the sample buffer (below the floor's and ceiling's ids).
pub(crate) const EXIT_ID: u32 = u32::MAX - 3;
/// Coverage id of figure `k` in the sample buffer: `SPRITE_ID - k` (below the exit's, far above any
/// wall's).
pub const SPRITE_ID: u32 = u32::MAX - 4;
/// The exit's glow (linear RGB): its beacon and the light it casts on the floor.
pub(crate) const EXIT_GLOW: Vec3 = Vec3::new(0.20, 1.0, 0.42);
/// The beacon's width (maze units): a column of light from floor to ceiling over the exit.
pub(crate) const BEACON_WIDTH: f32 = 1.0;
/// The beacon's green bands, each with a white one above it, floor to ceiling.
pub(crate) const BEACON_BANDS: f32 = 3.0;
/// The beacon's white (linear RGB): a touch of its green.
pub(crate) const BEACON_WHITE: Vec3 = Vec3::new(0.85, 1.0, 0.9);

/// Whether a coverage id ([`SampleBuffer::id`](crate::SampleBuffer::id)) is a figure's (or the
/// beacon's).
#[must_use]
pub fn is_figure(id: u32) -> bool {
    (SPRITE_ID - (MAX_SPRITES as u32 - 1)..=EXIT_ID).contains(&id)
}

/// One figure to draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sprite {
    /// Where it stands (world, maze plane).
    pub position: Vec2,
    /// The maze cell it stands in (for the portal culling).
    pub cell: u32,
    /// Its colour, sRGB in 0..1 (as wall colours are).
    pub color: Vec3,
    /// The letter shown on its head (the player's initial).
    pub label: char,
    /// A ghost (a stored run replayed): drawn translucent, [`GHOST_ALPHA`] of it over what is behind,
    /// hiding nothing, after the solid figures.
    pub ghost: bool,
}

/// How much of a ghost's colour covers what is behind it.
pub const GHOST_ALPHA: f32 = 0.5;

/// The body: a tunic widening to the shoulders, in model space (x across, z up, unit box).
const BODY: [Vec2; 6] = [
    Vec2::new(-0.40, 0.0),
    Vec2::new(0.40, 0.0),
    Vec2::new(0.50, 0.46),
    Vec2::new(0.34, 0.68),
    Vec2::new(-0.34, 0.68),
    Vec2::new(-0.50, 0.46),
];

/// The head's centre and half extents in model space: a circle of radius 0.17 maze units once scaled by
/// [`SPRITE_WIDTH`] × [`SPRITE_HEIGHT`].
const HEAD_CENTRE: Vec2 = Vec2::new(0.0, 0.80);
const HEAD_RADIUS: Vec2 = Vec2::new(0.17 / SPRITE_WIDTH, 0.17 / SPRITE_HEIGHT);

/// The head as an octagon (model space).
fn head() -> [Vec2; 8] {
    std::array::from_fn(|k| {
        let angle = (k as f32 + 0.5) * std::f32::consts::FRAC_PI_4;
        HEAD_CENTRE + HEAD_RADIUS * Vec2::new(angle.cos(), angle.sin())
    })
}

/// The model matrix of a billboard standing at `feet` seen from `eye` (world): scale the unit box to
/// `size` (width across × height; a figure's is [`SPRITE_WIDTH`] × [`SPRITE_HEIGHT`]), turn it about z so that its plane faces the eye (model +x goes
/// to the viewer's right, model −y toward the viewer), stand it on the floor at `feet`. `None` when the
/// eye is straight above or below the feet (no way to face it) or a value is not finite.
#[must_use]
pub(crate) fn model_matrix(feet: Vec2, eye: Vec3, size: Vec2) -> Option<Mat4> {
    let to_feet = (feet - eye.truncate()).try_normalize()?; // the line of sight, in the maze plane
    // R_z(θ) takes +x to (cos θ, sin θ); the viewer's right of `to_feet` is (to_feet.y, −to_feet.x).
    let angle = (-to_feet.x).atan2(to_feet.y);
    let m = model(feet.extend(FLOOR_Z), rotation_z(angle), Vec3::new(size.x, 1.0, size.y));
    m.is_finite().then_some(m)
}

/// The box in NDC of a figure's quad (model matrix `model`) seen by `eye`, or `None` where a corner
/// lies behind the eye (then the clipper decides what is left): what [`reaches_tile`] asks of a tile.
/// The same for every tile of a view (they share its projection).
fn ndc_box(eye: &Eye, model: Mat4) -> Option<[Vec2; 2]> {
    let mut ndc = [Vec2::INFINITY, Vec2::NEG_INFINITY];
    for (x, z) in [(-0.5, 0.0), (0.5, 0.0), (-0.5, 1.0), (0.5, 1.0)] {
        let clip = eye.world_to_clip * model.transform_point3(Vec3::new(x, 0.0, z)).extend(1.0);
        if clip.w <= 0.0 {
            return None; // behind the eye: let the clipper decide
        }
        let p = clip.truncate().truncate() / clip.w;
        ndc = [ndc[0].min(p), ndc[1].max(p)];
    }
    Some(ndc)
}

/// Whether a figure whose quad has the NDC box `ndc` ([`ndc_box`]) may cover a sample of `eye`'s
/// grid, when `eye` is one tile of a foveated view (`window`: its [`tile_window`](crate::pipeline::tile_window); a
/// whole view: always). No when its quad's four corners are all in front of the eye and their box
/// misses the tile's window; clipping would leave nothing.
fn reaches_tile(window: Option<[Vec2; 2]>, ndc: Option<[Vec2; 2]>) -> bool {
    match (window, ndc) {
        (Some(window), Some(ndc)) => crate::pipeline::meets(ndc, window),
        _ => true,
    }
}

/// A figure's vertex on its way through the pipeline: clip position plus what its shading needs, both
/// affine in world space (so clipped linearly in clip space, interpolated perspective-correctly).
#[derive(Clone, Copy, Debug, PartialEq)]
struct SpriteVertex {
    clip: Vec4,
    /// `x`: view depth (distance along the view axis, for the fog); `y`: model height in 0..1; `z`:
    /// model x, −½..½ across.
    attrs: Vec3,
}

impl ClipVertex for SpriteVertex {
    fn clip(&self) -> Vec4 {
        self.clip
    }
    fn lerp(&self, other: &Self, t: f32) -> Self {
        SpriteVertex { clip: self.clip.lerp(other.clip, t), attrs: self.attrs.lerp(other.attrs, t) }
    }
}

/// Where a drawn figure's label goes: the sample under its head's centre, if the figure won it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Label {
    /// Sample index (row-major) of the head's centre.
    pub sample: usize,
    /// The figure's coverage id.
    pub id: u32,
    /// The letter.
    pub label: char,
    /// The figure's colour, linear RGB.
    pub color: Vec3,
    /// Which of the sprites passed it is.
    pub sprite: usize,
}

/// The figures' own buffers, reused from frame to frame.
#[derive(Debug, Default)]
pub(crate) struct SpritePass {
    input: Vec<SpriteVertex>,
    output: Vec<SpriteVertex>,
    temp: Vec<SpriteVertex>,
    grid: Vec<GridVertex<Vec3>>,
    order: Vec<(f32, usize)>,
    /// The figures of `order`, as [`SpritePass::prepare`] found them for the view: each one's model
    /// matrix (`None`: it cannot face the eye) and its box in NDC ([`ndc_box`]).
    placed: Vec<Option<(Mat4, Option<[Vec2; 2]>)>>,
    /// The samples the frame's figures have covered so far (their bounding boxes), and the figures
    /// rasterized (on the screen after clipping).
    covered: usize,
    drawn: usize,
    /// The labels of the last frame's figures (those whose head centre is on screen).
    pub labels: Vec<Label>,
}

impl SpritePass {
    /// Before a view's tiles: the `sprites` for which `visible(cell)` holds, in the order they are
    /// drawn (the solid figures nearest first, then the ghosts farthest first), at most
    /// [`MAX_SPRITES`], each with its model matrix and its box in NDC: the same for every tile of
    /// `view`, whose eye position and projection they share.
    pub fn prepare(&mut self, view: &Eye, sprites: &[Sprite], visible: impl Fn(u32) -> bool) {
        self.order.clear();
        for (k, sprite) in sprites.iter().enumerate() {
            let depth = view.view_depth(sprite.position.extend(FLOOR_Z));
            if visible(sprite.cell) && depth >= -SPRITE_WIDTH {
                self.order.push((depth, k));
            }
        }
        // the solid figures nearest first (the depth test hides the rest), then the ghosts farthest
        // first (each blends over what is drawn behind it)
        let key =
            |&(depth, k): &(f32, usize)| (sprites[k].ghost, if sprites[k].ghost { -depth } else { depth });
        self.order.sort_by(|a, b| {
            let (ka, kb) = (key(a), key(b));
            ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
        });
        self.order.truncate(MAX_SPRITES);
        let size = Vec2::new(SPRITE_WIDTH, SPRITE_HEIGHT);
        self.placed.clear();
        self.placed.extend(self.order.iter().map(|&(_, k)| {
            model_matrix(sprites[k].position, view.position, size).map(|model| (model, ndc_box(view, model)))
        }));
    }

    /// Rasterizes the figures [`SpritePass::prepare`] chose for the view (of `sprites`, the same
    /// slice) into `samples`, the view or one of its tiles (`eye`), depth-tested against what is
    /// there (draw the walls first), in that order, while those drawn have covered less than
    /// [`FIGURE_SCREENS`] screens; returns the samples written. Records each drawn figure's
    /// [`Label`] position.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub fn draw(&mut self, samples: &mut SampleBuffer, eye: &Eye, fog: &Fog, sprites: &[Sprite]) -> usize {
        self.labels.clear();
        let window = (!eye.is_whole()).then(|| crate::pipeline::tile_window(eye));
        let mut written = 0;
        (self.covered, self.drawn) = (0, 0);
        for slot in 0..self.order.len() {
            if self.covered >= FIGURE_SCREENS * eye.width * eye.height {
                break; // (what is left stands behind screens of figures)
            }
            let (_, k) = self.order[slot];
            let sprite = &sprites[k];
            let Some((model, ndc)) = self.placed[slot] else { continue };
            if !reaches_tile(window, ndc) {
                continue; // a tile of a foveated view the figure is nowhere near
            }
            let id = SPRITE_ID - slot as u32;
            let albedo = sprite.color.clamp(Vec3::ZERO, Vec3::ONE).map(srgb_to_linear);
            // Shoulders lit, feet in shadow; the head a lighter tint of the same colour.
            let body = |attrs: Vec3| fog.apply(albedo * (0.55 + 0.45 * attrs.y), attrs.x);
            let face = albedo.lerp(Vec3::ONE, 0.45);
            let head_shade = |attrs: Vec3| fog.apply(face, attrs.x);
            let alpha = sprite.ghost.then_some(GHOST_ALPHA);
            let before = self.covered;
            written += self.fill(samples, eye, model, &BODY, id, alpha, body);
            written += self.fill(samples, eye, model, &head(), id, alpha, head_shade);
            self.drawn += usize::from(self.covered > before);

            let centre = model.transform_point3(Vec3::new(HEAD_CENTRE.x, 0.0, HEAD_CENTRE.y));
            let clip = eye.world_to_clip * centre.extend(1.0);
            if clip.w > 0.0 {
                let grid = eye.grid(clip);
                let (x, y) = (grid.x.floor(), grid.y.floor());
                if (0.0..eye.width as f32).contains(&x) && (0.0..eye.height as f32).contains(&y) {
                    let sample = y as usize * eye.width + x as usize;
                    self.labels.push(Label { sample, id, label: sprite.label, color: face, sprite: k });
                }
            }
        }
        written
    }

    /// The exit's beacon at `point`: a column of light from floor to ceiling, a billboard like the
    /// figures ([`BEACON_WIDTH`] wide), brightest along its middle and half as fogged as a wall, so it
    /// shows down a long corridor, banded green and white like a lighthouse ([`BEACON_BANDS`] of
    /// each): a look no wall has in any colour depth, nor in ascii, where the bands are two glyphs
    /// (issue #39: a green wall was chased for the beacon). Depth-tested; returns the samples written.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn draw_beacon(
        &mut self,
        samples: &mut SampleBuffer,
        eye: &Eye,
        fog: &Fog,
        point: Vec2,
    ) -> usize {
        let size = Vec2::new(BEACON_WIDTH, CEILING_Z - FLOOR_Z);
        let Some(model) = model_matrix(point, eye.position, size) else { return 0 };
        let column = [Vec2::new(-0.5, 0.0), Vec2::new(0.5, 0.0), Vec2::new(0.5, 1.0), Vec2::new(-0.5, 1.0)];
        let glow = |attrs: Vec3| {
            let white = (attrs.y * BEACON_BANDS).fract() >= 0.5;
            let colour = if white { BEACON_WHITE } else { EXIT_GLOW };
            fog.apply(colour * (1.0 - 1.2 * attrs.z.abs()), 0.5 * attrs.x)
        };
        self.fill(samples, eye, model, &column, EXIT_ID, None, glow)
    }

    /// One convex model-space polygon of a figure: model → world → clip, clipped against the view volume,
    /// ÷w and viewport, rasterized with `id`, each sample shaded by `shade(attrs)` (with `alpha`, that
    /// much of it blended over what is there: [`blend_polygon`]).
    #[allow(clippy::too_many_arguments)] // (the pipeline's stages, each one value)
    fn fill(
        &mut self,
        samples: &mut SampleBuffer,
        eye: &Eye,
        model: Mat4,
        polygon: &[Vec2],
        id: u32,
        alpha: Option<f32>,
        shade: impl FnMut(Vec3) -> Vec3,
    ) -> usize {
        self.input.clear();
        for &p in polygon {
            let world = model.transform_point3(Vec3::new(p.x, 0.0, p.y)); // model → world
            let clip = eye.world_to_clip * world.extend(1.0); // world → clip
            self.input.push(SpriteVertex { clip, attrs: Vec3::new(eye.view_depth(world), p.y, p.x) });
        }
        let depth = eye.camera.convention.depth_range();
        clip_polygon(&self.input, ClipPlanes::ALL, depth, &mut self.output, &mut self.temp);
        if self.output.len() < 3 {
            return 0;
        }
        self.grid.clear();
        self.grid.extend(self.output.iter().map(|v| eye.grid_vertex(v.clip, v.attrs))); // ÷w → NDC → viewport
        let (lo, hi) = self
            .grid
            .iter()
            .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), v| (lo.min(v.pos), hi.max(v.pos)));
        let size = |lo: f32, hi: f32, n: usize| (hi.min(n as f32) - lo.max(0.0)).max(0.0).ceil() as usize;
        self.covered += size(lo.x, hi.x, eye.width) * size(lo.y, hi.y, eye.height);
        match alpha {
            None => fill_polygon(samples, &self.grid, id, shade),
            Some(alpha) => blend_polygon(samples, &self.grid, id, alpha, shade),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FIGURE: Vec2 = Vec2::new(SPRITE_WIDTH, SPRITE_HEIGHT);

    #[test]
    fn the_model_matrix_stands_the_figure_on_the_floor_facing_the_eye() {
        let eye = Vec3::new(1.0, 2.0, 0.0);
        for feet in [Vec2::new(5.0, 2.0), Vec2::new(-3.0, -1.0), Vec2::new(1.0, 9.0), Vec2::new(0.5, 1.5)] {
            let m = model_matrix(feet, eye, FIGURE).unwrap();
            assert!(m.transform_point3(Vec3::ZERO).abs_diff_eq(feet.extend(FLOOR_Z), 1e-5), "feet");
            let top = m.transform_point3(Vec3::Z);
            assert!(
                (top.z - (FLOOR_Z + SPRITE_HEIGHT)).abs() < 1e-5 && top.truncate().abs_diff_eq(feet, 1e-5)
            );
            // Model x spans the width across the line of sight; model −y points at the eye.
            let across = m.transform_vector3(Vec3::X);
            let to_eye = (eye.truncate() - feet).normalize();
            assert!((across.length() - SPRITE_WIDTH).abs() < 1e-5);
            assert!(across.truncate().dot(to_eye).abs() < 1e-5, "the plane faces the eye");
            let toward = m.transform_vector3(-Vec3::Y).truncate();
            assert!(toward.normalize().dot(to_eye) > 0.9999, "front toward the eye");
            // Seen from the eye, model +x is on the viewer's right.
            let right = Vec2::new(-to_eye.y, to_eye.x); // heading_right of the line of sight, −to_eye
            assert!(across.truncate().normalize().dot(right) > 0.9999);
        }
        assert_eq!(model_matrix(Vec2::new(1.0, 2.0), eye, FIGURE), None, "straight above: no facing");
        assert_eq!(model_matrix(Vec2::new(f32::NAN, 2.0), eye, FIGURE), None);
    }

    #[test]
    fn the_head_is_round_and_sits_on_the_shoulders() {
        for p in head() {
            let world = (p - HEAD_CENTRE) * Vec2::new(SPRITE_WIDTH, SPRITE_HEIGHT);
            assert!((world.length() - 0.17).abs() < 1e-5, "a circle in world units");
        }
        let shoulders = BODY.iter().map(|p| p.y).fold(0.0, f32::max);
        let chin = head().iter().map(|p| p.y).fold(1.0, f32::min);
        assert!(
            chin > shoulders - 0.02 && chin < shoulders + 0.02,
            "chin {chin} at the shoulders {shoulders}"
        );
        assert!(head().iter().all(|p| p.y <= 1.0 && p.x.abs() <= 0.5), "inside the unit box");
    }
    /// Red-team pass 8: a crowd pressed round the eye is drawn only until it has covered a few
    /// screens (the rest stand behind it), while a crowd spread out down the view is drawn whole.
    #[test]
    fn figures_are_drawn_until_they_have_covered_a_few_screens() {
        let camera = crate::Camera::new(Vec2::ZERO, 0.0, 90.0);
        let eye = camera.eye(120, 80, 1.0).unwrap();
        let fog = Fog { color: Vec3::ZERO, half: 8.0, end: 40.0 };
        let figure =
            |position: Vec2| Sprite { position, cell: 0, color: Vec3::ONE, label: 'a', ghost: false };
        let mut pass = SpritePass::default();
        let mut samples = SampleBuffer::new(eye.width, eye.height);
        // 1,024 figures in a ring 0.3–0.6 units round the eye
        let pressed: Vec<Sprite> = (0..1024)
            .map(|k| {
                let angle = k as f32 * 0.37;
                figure((0.3 + 0.3 * (k % 7) as f32 / 6.0) * Vec2::new(angle.cos(), angle.sin()))
            })
            .collect();
        pass.prepare(&eye, &pressed, |_| true);
        assert!(pass.draw(&mut samples, &eye, &fog, &pressed) > 0);
        assert!(pass.drawn < 64, "{} of the pressed crowd drawn", pass.drawn);
        let screen = eye.width * eye.height;
        assert!(pass.covered >= FIGURE_SCREENS * screen, "stopped before the screens were covered");
        // 40 figures in a line across the view, 10 units off: each a few samples, all drawn
        let mut samples = SampleBuffer::new(eye.width, eye.height);
        let spread: Vec<Sprite> = (0..40).map(|k| figure(Vec2::new(10.0, k as f32 * 0.4 - 8.0))).collect();
        pass.prepare(&eye, &spread, |_| true);
        pass.draw(&mut samples, &eye, &fog, &spread);
        assert_eq!(pass.drawn, 40);
    }
}
