//! The pipeline in one place: maze + camera → samples → [`Frame`].
//!
//! ```text
//! camera ─eye()─▶ world→view, view→clip, NDC→grid matrices
//! walls  ─portal pass (or all)─▶ wall ids, ascending
//!   each wall: extrude (world) ─view─▶ view ─projection─▶ clip ─clip─▶ clip ─÷w─▶ NDC ─viewport─▶ grid
//!              ─raster (top-left rule, depth LESS, Lambert via the normal matrix + fog)─▶ samples
//! floor / ceiling: per sample, the camera ray meets z = -1 / +1 (where no wall is nearer)
//! ascii: outlines of the visible walls (Bresenham), then glyphs ─▶ Frame
//! ```

use std::ops::Range;

use glam::{Vec2, Vec3, Vec4};
use wide::bytemuck::cast;
use wide::{f32x8, i32x8, u32x8};

use super::camera::{Camera, CameraError, Eye, Projection, Tile};
use super::glyph;
use super::line::{CentrePoints, LinePoints, centre_points, line_glyph, line_points};
use super::options::{Charset, Culling, RenderOptions};
use super::palette;
use super::portal::{PortalPass, PortalStats};
use super::raster::{GridVertex, LANES, fill_polygon, fill_polygon_x8};
use super::samples::{CEILING, FLOOR, NONE, SampleBuffer};
use super::shade::{
    CEILING_EXIT_TINT, FLOOR_EXIT_TINT, Fog, SUN_WORLD, apart_from_floor, bricks, chalk_color, checker,
    checker_filtered, edge_color, exit_lit_wall, exit_lit_wall_16, exit_tinted, headlight, jamb_color,
    jamb_grey, line_color, lit, luminance, seam_color, slant_cosine, srgb_to_linear, sun_factor, wall_albedo,
    way_light, way_light_16,
};
use super::sprite::{EXIT_GLOW, Label, Sprite, SpritePass, is_figure};
use super::wall::{ClipScratch, WallVertex, clip_segment, clip_wall, wall_quad_world};
use mazewalk_math::rigid_inverse;
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};
use mazewalk_maze::light::{EXIT_LIGHT, ExitLight};
use mazewalk_maze::{Aabb, Maze};
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame, Region};

/// Light that reaches a wall whatever its angle to the headlight: the share of its colour a wall seen
/// edge-on (a corridor's side wall) keeps, against all of it for a wall faced squarely.
const AMBIENT: f32 = 0.65;
/// The same for the floor and the ceiling, seen edge-on when the view is level: below the walls', so
/// walls, what a player finds the way by, stand out from both.
const FLOOR_AMBIENT: f32 = 0.5;
/// See [`FLOOR_AMBIENT`].
const CEILING_AMBIENT: f32 = 0.45;
/// Where nothing is hit: the fog's colour (linear RGB).
const FOG_COLOR: Vec3 = Vec3::ZERO;
/// Floor and ceiling base colours (sRGB, like the maze files' wall colours).
pub(crate) const FLOOR_SRGB: Vec3 = Vec3::new(0.49, 0.46, 0.41);
pub(crate) const CEILING_SRGB: Vec3 = Vec3::new(0.23, 0.24, 0.27);
/// The floor/ceiling checker: one square per generated maze cell, a gentle contrast to show motion.
const CHECKER_PERIOD: f32 = 4.0;
const CHECKER_CONTRAST: f32 = 0.18;
/// How far (maze units) the exit's light reaches on the floor round it.
const EXIT_GLOW_RADIUS: f32 = 2.0;

/// What one frame cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// The portal pass's counts (zero for brute force).
    pub portal: PortalStats,
    /// Walls sent to the raster.
    pub walls_drawn: usize,
    /// Triangles rasterized (a clipped wall polygon of n vertices is n - 2 triangles).
    pub triangles: usize,
    /// Samples written by walls (after the depth test).
    pub samples_written: usize,
}

impl RenderStats {
    /// Adds a tile's raster counts (the portal pass's stay the view's).
    pub(crate) fn add(&mut self, tile: RenderStats) {
        self.triangles += tile.triangles;
        self.samples_written += tile.samples_written;
    }
}

/// What the shading closure computes per sample: a colour, or the view depth (for `--depth-out`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shading {
    Color,
    ViewDepth,
}

/// What lights a view, the same for all its walls.
pub(crate) struct Light<'m> {
    pub(crate) fog: Fog,
    /// The sun's direction in view space (a direction: it turns as normals do).
    sun_view: Vec3,
    /// Orthographic: the headlight's rays are parallel, footprints the same at every depth.
    ortho: bool,
    /// View → world, for texture coordinates on the walls.
    view_to_world: glam::Mat4,
    /// Maze units one sample covers per unit of view depth (perspective), or in all (orthographic).
    pub(crate) per_sample: f32,
    /// The exit's light through the maze's cells ([`ExitLight`], kept by the maze: searched once):
    /// what tints walls, floor and ceiling toward the exit; `None` when this frame draws no tint.
    pub(crate) exit_light: Option<&'m ExitLight>,
}

impl<'m> Light<'m> {
    pub(crate) fn of(eye: &Eye, maze: &'m Maze, exit_tint: bool) -> Light<'m> {
        Light {
            exit_light: exit_tint.then(|| maze.exit_light()),
            fog: fog_of(eye),
            sun_view: (eye.normal_to_view * SUN_WORLD).normalize_or_zero(),
            ortho: eye.camera.projection == Projection::Orthographic,
            view_to_world: rigid_inverse(eye.world_to_view),
            per_sample: eye.tan_extent().x / eye.width.max(1) as f32,
        }
    }
}

/// A wall's light, one for the whole wall ([`Renderer::wall_shade`]).
struct WallShade {
    /// Its albedo lit by the sun, the headlight and the exit's light (linear RGB), before fog.
    lit_albedo: Vec3,
    /// The view depth its fog is taken at ([`flat_fog_depth`]).
    fog_depth: f32,
    /// Its normal in view space, as the normal matrix takes it (not turned toward the eye).
    normal_view: Vec3,
}

/// A wall of a view drawn in tiles, worked out once for all of them ([`Renderer::wall_boxes`]).
#[derive(Clone, Debug)]
struct ViewWall {
    e: u32,
    /// The box its clipped polygon covers in NDC.
    ndc_box: [Vec2; 2],
    /// Its polygon clipped to the view volume (clip space), in `Renderer::view_wall_vertices`.
    vertices: Range<usize>,
    /// Its one colour where the frame draws walls flat, as [`Renderer::draw_wall`] gives it.
    flat: Option<Vec3>,
}

/// A tile draws the walls whose boxes come this many samples near it: a wall's edge is drawn on the
/// sample beside the wall.
const TILE_MARGIN: f32 = 2.0;

/// A wall shorter than this many samples on the picture draws no edge against the ceiling and floor,
/// so it shows its whole height and no more ([`Renderer::draw_edges`]): six rows of half blocks.
const FAR_WALL_SAMPLES: f32 = 12.0;

/// A cell line on the floor (ceiling) within this angle of a wall runs along the wall's foot (top),
/// and is left out beside it (`draw_cell_bounds`); one at a larger angle meets the wall, and is drawn
/// up to it. A grid maze's lines are at 0° or 90° to every wall.
const FOOT_ANGLE: f32 = std::f32::consts::FRAC_PI_6;

/// The fog of a view: half the light left at a fifth of the far distance (19 maze units, about five
/// generated cells, at the default view distance), all fog at the far plane.
pub(crate) fn fog_of(eye: &Eye) -> Fog {
    Fog { color: FOG_COLOR, half: eye.far * 0.2, end: eye.far }
}

/// The renderer: the pipeline plus every buffer it reuses from frame to frame.
#[derive(Debug, Default)]
pub struct Renderer {
    pub(crate) samples: SampleBuffer,
    /// A foveated view's picture, each tile drawn in its place in it ([`Renderer::enter_tile`]);
    /// then swapped into `samples` (`showing_picture`) until the next foveated view.
    picture: SampleBuffer,
    showing_picture: bool,
    /// The figures' labels of a foveated view's tiles, at their samples in the whole view.
    tile_labels: Vec<Label>,
    pub(crate) portal: PortalPass,
    pub(crate) walls: Vec<u32>,
    /// A view drawn in tiles: its chosen walls, each worked out once for all its tiles, by id.
    view_walls: Vec<ViewWall>,
    /// The clipped polygons of `view_walls`.
    view_wall_vertices: Vec<WallVertex>,
    /// A view drawn in tiles: each row's short-wall depth ([`Renderer::picture_edges`]).
    short_rows: Vec<f32>,
    /// The tiles' NDC windows as their lines reach them ([`Tiling`]), reused.
    pub(crate) tile_windows: Vec<[Vec2; 2]>,
    scratch: ClipScratch,
    polygon_grid: Vec<GridVertex<Vec3>>,
    /// The walls' fill's depths a column (`raster::fill_polygon_x8`), reused.
    column_depths: Vec<f32>,
    seen: Vec<u32>,
    pub(crate) sprites: SpritePass,
    /// Which samples are edges or seams: all `None` between frames (each frame unmarks what it marked).
    edge_marks: Vec<Mark>,
    /// The samples marked this frame, each once.
    edge_list: Vec<u32>,
    plane_row: PlaneRow,
    /// The sides of the cells the floor and ceiling rows cross, for the exit's light: worked out once a
    /// view ([`Renderer::begin_view`]), whatever its tiles.
    cell_sides: CellSides,
    /// Each plane's colour tinted at every level of the exit's light, by (colour, strength).
    plane_tints: Vec<((Vec3, f32), [Vec3; EXIT_LIGHT as usize + 1])>,
    /// Skip the edge pass (the portal oracle compares visibility, not the picture's edges).
    pub(crate) no_edges: bool,
    /// Shade every sample by the scalar reference paths (the oracle of the SIMD ones).
    pub(crate) reference_shading: bool,
    /// Tests: the exit's light levels of a lit row worked out for every sample, walls' too (as
    /// before they were left out), to hold the rows that skip them to the same samples.
    #[cfg(test)]
    pub(crate) levels_everywhere: bool,
    /// Tests: level rows' checker paints by groups only, never by runs ([`RowShade::paints_by_runs`]).
    #[cfg(test)]
    pub(crate) plane_runs_off: bool,
    /// Ids below this are walls (the last frame's maze's edge count).
    wall_ids: u32,
    /// The last frame's figures whose head shows: (index in the sprites passed, column, row of the
    /// frame).
    heads: Vec<(usize, usize, usize)>,
    /// The cells whose floors carry a chalk mark ([`Renderer::set_chalk`]), sorted, each once.
    chalk: Vec<u32>,
    /// The last frame's openings whose lines are drawn in the way's light ([`way_light`]).
    way: Vec<u32>,
    /// The last frame's openings whose lines are drawn on the floor and ceiling (`draw_cell_bounds`).
    lines: Vec<u32>,
    /// This frame tints no floor or ceiling by the exit's light: in 16 colours (the floor and the
    /// ceiling show one entry each there, and a green one would be a wall's; walls show the glow's
    /// dark green, `palette::GLOW_16`) and without colour (ascii shows lightness only: the frame stays
    /// exactly as without the tint).
    pub(crate) no_plane_tint: bool,
    /// Tests: draw floor and ceiling as if the maze had no exit's light (walls as ever).
    #[cfg(test)]
    pub(crate) plane_tint_off: bool,
    /// This frame keeps walls lit apart from the floor ([`apart_from_floor`]): in colour. Without
    /// colour the ascii charset tells floor and ceiling by their own glyphs, and its wall glyphs by
    /// lightness alone; raised walls would all take the ramp's top glyphs and lose their distance.
    pub(crate) walls_apart: bool,
    /// Ascii, by wall id: whether the last frame saw the wall square on (`|n · axis|` at least ½√2)
    /// rather than along the view; the glyph pass draws the two with glyphs of their own (issue #39).
    /// Set for the walls [`Renderer::outline_visible_walls`] outlines.
    pub(crate) faced: Vec<bool>,
    /// This frame draws the floor's cell lines off the floor's tint ([`FLOOR_BOUND_16`]): in 16
    /// colours, where the floor shows one entry and a darker grey of its own is that entry again.
    pub(crate) floor_bounds_apart: bool,
    /// This frame is ascii: the floor's and the ceiling's cell lines are also drawn as
    /// [`CELL_LINE_GLYPH`] (shading glyphs are by distance, not by cell: without a glyph of their own
    /// the cells down a corridor cannot be counted, issue #39), thinned by [`LINE_GAP_ASCII`].
    pub(crate) ascii_lines: bool,
}

/// Where [`Renderer::render`] puts the picture.
#[derive(Debug)]
pub enum Target<'a> {
    /// Glyphs into a region of a frame; the rest of the frame is left alone (the walk, `mazewalk
    /// render`).
    Frame(&'a mut Frame, Region),
    /// Only the samples of a `cols × rows`-cell picture, no glyphs: what a frame is made of, sample by
    /// sample, read back with [`Renderer::samples`] (the portal oracle, the benches).
    Samples {
        /// Cells across.
        cols: usize,
        /// Cells down.
        rows: usize,
    },
    /// The view-space depth of the wall through each cell's centre of a `cols × rows` picture, read
    /// back with [`Renderer::cell_depths`]; figures and glyphs play no part.
    Depths {
        /// Cells across.
        cols: usize,
        /// Cells down.
        rows: usize,
    },
}

impl Renderer {
    /// A renderer with empty buffers (they grow on first use).
    #[must_use]
    pub fn new() -> Renderer {
        Renderer::default()
    }

    /// Chalk marks from now on: a pale cross on the floor at the centre of each cell of `cells` (the
    /// cells a player has walked: Trémaux's marks, the classic aid to finding the way without a map).
    /// Drawn through the same chain as the floor's cell lines, in every charset and colour depth; with
    /// none (the default) the picture is as without marks. What a view is drawn from, with the maze,
    /// the camera, the figures and the options.
    pub fn set_chalk(&mut self, cells: &[u32]) {
        self.chalk.clear();
        self.chalk.extend_from_slice(cells);
        self.chalk.sort_unstable();
        self.chalk.dedup();
    }

    /// The samples of the last frame (colour, depth, id per sample).
    #[must_use]
    pub fn samples(&self) -> &SampleBuffer {
        &self.samples
    }

    /// The portal pass of the last frame (walls found, cells visited).
    #[must_use]
    pub fn portal(&self) -> &PortalPass {
        &self.portal
    }

    /// Renders `maze` from `camera`, with figures standing in it ([`Sprite`]s: the other players,
    /// depth-tested against the walls, each with its label on its head's cell), into `target`: the
    /// one entry point of the pipeline, whatever the picture is for.
    ///
    /// ```
    /// use mazewalk_render::{Camera, RenderOptions, Renderer, Target};
    /// use mazewalk_term::Frame;
    ///
    /// let maze = mazewalk_maze::builtin()?;
    /// let v = maze.viewer();
    /// let camera = Camera { eye_z: v.z, ..Camera::new(v.pos, v.dir_deg, v.fov_deg) };
    /// let mut frame = Frame::new(40, 12);
    /// let region = frame.region();
    /// let options = RenderOptions::default(); // half blocks, truecolor, portal culling
    /// let target = Target::Frame(&mut frame, region);
    /// let stats = Renderer::new().render(&maze, &camera, &[], &options, target)?; // no figures
    /// assert!(stats.walls_drawn > 0);
    /// assert!(frame.cells().iter().any(|c| c.ch == '▀'));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// [`CameraError`] when the camera or the grid is unusable.
    ///
    /// # Panics
    /// If a [`Target::Frame`]'s region is not inside its frame.
    pub fn render(
        &mut self,
        maze: &Maze,
        camera: &Camera,
        sprites: &[Sprite],
        options: &RenderOptions,
        target: Target<'_>,
    ) -> Result<RenderStats, CameraError> {
        let RenderOptions { charset, color_depth, culling, cell_aspect, textures, .. } = *options;
        self.no_plane_tint = matches!(color_depth, ColorDepth::Ansi16 | ColorDepth::None);
        #[cfg(test)]
        {
            self.no_plane_tint |= self.plane_tint_off;
        }
        self.walls_apart = color_depth != ColorDepth::None;
        self.floor_bounds_apart = color_depth == ColorDepth::Ansi16;
        match target {
            Target::Frame(frame, region) => {
                let (cols, rows) = (region.cols, region.rows);
                let stats = self.samples_with(
                    maze,
                    camera,
                    charset,
                    cell_aspect,
                    culling,
                    cols,
                    rows,
                    sprites,
                    textures,
                )?;
                let faced: &[bool] = if charset == Charset::Ascii { &self.faced } else { &[] };
                glyph::to_frame_faced(&self.samples, options, frame, region, faced);
                self.label_sprites(charset, color_depth, frame, region);
                Ok(stats)
            }
            Target::Samples { cols, rows } => {
                self.samples_with(maze, camera, charset, cell_aspect, culling, cols, rows, sprites, textures)
            }
            Target::Depths { cols, rows } => {
                // One sample per cell, centred in the cell: exactly the ascii sampling.
                let view = camera.eye(cols, rows, Charset::Ascii.sample_aspect(cell_aspect))?;
                self.begin_view(maze);
                let mut stats = self.choose_walls(maze, &view, culling);
                let tiles = view.tiles();
                self.wall_boxes(maze, &view, tiles.len(), false);
                for (k, tile) in tiles.iter().enumerate() {
                    self.enter_tile(&view, tile, k);
                    self.walls_in(&tile.eye);
                    stats.add(self.draw(maze, &tile.eye, Shading::ViewDepth, false));
                    self.place_tile(&view, tile);
                }
                self.finish_tiles(&view);
                Ok(stats)
            }
        }
    }

    /// After a [`Target::Depths`] render, for each terminal cell (row by row) the view-space depth of
    /// the wall seen through the cell's centre (maze units along the view direction), or `None` where
    /// no wall is seen: the `--depth-out` hook.
    pub fn cell_depths(&self) -> impl Iterator<Item = Option<f32>> + '_ {
        let s = &self.samples;
        s.id().iter().zip(s.color()).map(|(&id, c)| (id < self.wall_ids).then_some(c.x))
    }

    /// Each drawn figure's label on the cell of its head's centre, if the figure is what shows there.
    fn label_sprites(&mut self, charset: Charset, depth: ColorDepth, frame: &mut Frame, region: Region) {
        let (sx, sy) = charset.samples_per_cell();
        let width = self.samples.width();
        self.heads.clear();
        for label in &self.sprites.labels {
            if self.samples.id()[label.sample] != label.id {
                continue; // hidden there (a wall, a nearer figure)
            }
            let (x, y) = (label.sample % width / sx, label.sample / width / sy);
            let bg = palette::picture_color(label.color, depth); // as the head it stands on
            // Dark ink on a light head (the head is a light tint of the figure's colour).
            let fg = if depth == ColorDepth::None { Color::Default } else { Color::Indexed(0) };
            // One printable ASCII character, whatever the caller passed (a name may hold anything).
            let ch = if label.label.is_ascii_graphic() { label.label } else { '?' };
            let cell = if depth == ColorDepth::None { Cell::plain(ch) } else { Cell { ch, fg, bg } };
            frame.set(region.col + x, region.row + y, cell);
            self.heads.push((label.sprite, region.col + x, region.row + y));
        }
    }

    /// Where the last frame drawn into a [`Target::Frame`] shows each figure's head (those hidden or
    /// off the view are left out): the figure's index in the sprites passed, and the frame's column
    /// and row of its label. A caller labels a figure further there (a ghost's name and time).
    #[must_use]
    pub fn heads(&self) -> &[(usize, usize, usize)] {
        &self.heads
    }

    /// Before tile `k` of a view: a foveated view's tile draws in its place in the view's picture
    /// (`samples` is the picture's window of the tile, its samples where they are in the picture:
    /// nothing to copy after). Nothing to do for a view drawn whole (its one tile is the view).
    pub(crate) fn enter_tile(&mut self, view: &Eye, tile: &Tile, k: usize) {
        if view.warp.is_none() {
            return;
        }
        if std::mem::take(&mut self.showing_picture) {
            std::mem::swap(&mut self.samples, &mut self.picture);
        }
        if k == 0 {
            if self.picture.width() != view.width || self.picture.height() != view.height {
                self.picture.resize(view.width, view.height);
            }
            // Every tile's samples uncovered at once, not window by window (the tiles' rows are
            // short: a clear a row cost more than its samples). The last view's outlines too: the
            // tiles draw none.
            self.picture.clear_coverage();
        }
        std::mem::swap(&mut self.samples, &mut self.picture);
        let (x0, y0) = tile.at;
        self.samples.window(x0, y0, tile.eye.width, tile.eye.height);
    }

    /// After a foveated view's tile: its figures' labels into the view's, and the picture whole again.
    pub(crate) fn place_tile(&mut self, view: &Eye, tile: &Tile) {
        if view.warp.is_none() {
            return;
        }
        self.samples.end_window(); // (the tile's samples are in the picture already)
        // (its figures' labels: drawn now, with the figures)
        let ((x0, y0), tile_width) = (tile.at, tile.eye.width);
        self.tile_labels.extend(self.sprites.labels.iter().map(|label| Label {
            sample: (label.sample / tile_width + y0) * view.width + label.sample % tile_width + x0,
            ..*label
        }));
        std::mem::swap(&mut self.samples, &mut self.picture);
    }

    /// After the last tile of a foveated view: its picture becomes the samples, its labels the
    /// figures' labels, and its walls those of the whole view.
    pub(crate) fn finish_tiles(&mut self, view: &Eye) {
        if view.warp.is_none() {
            return;
        }
        std::mem::swap(&mut self.samples, &mut self.picture);
        self.showing_picture = true;
        std::mem::swap(&mut self.sprites.labels, &mut self.tile_labels);
        self.tile_labels.clear();
        // (the walls of the whole view again, for the lines drawn over it: its last tile's were kept)
        if !self.view_walls.is_empty() {
            self.walls.clear();
            self.walls.extend(self.view_walls.iter().map(|wall| wall.e));
        }
    }

    /// A view drawn in several tiles: each chosen wall clipped to the view volume once, with the box
    /// it covers in NDC and, where walls are drawn flat (`flat`: [`Renderer::draw_wall`]'s fast
    /// path), its one colour, into `view_walls`; walls wholly clipped away are left out. Nothing for
    /// one tile. (What a wall's tiles share: only the viewport differs from tile to tile.)
    pub(crate) fn wall_boxes(&mut self, maze: &Maze, view: &Eye, tiles: usize, flat: bool) {
        self.view_walls.clear();
        self.view_wall_vertices.clear();
        if tiles <= 1 {
            return;
        }
        let light = Light::of(view, maze, true);
        for k in 0..self.walls.len() {
            let e = self.walls[k];
            let Some(poly) = clip_wall(maze, view, e, &mut self.scratch) else { continue };
            let ndc = |v: &WallVertex| v.clip.truncate().truncate() / v.clip.w;
            let (lo, hi) = poly
                .iter()
                .fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), v| (lo.min(ndc(v)), hi.max(ndc(v))));
            let start = self.view_wall_vertices.len();
            self.view_wall_vertices.extend_from_slice(poly);
            let first_view = poly[0].view;
            let flat = (flat && maze.edge(e).opaque).then(|| {
                let shade = self.wall_shade(maze, view, &light, e, first_view);
                light.fog.apply(shade.lit_albedo, shade.fog_depth)
            });
            let vertices = start..self.view_wall_vertices.len();
            self.view_walls.push(ViewWall { e, ndc_box: [lo, hi], vertices, flat });
        }
    }

    /// A tile of a view drawn in several: `walls` becomes the chosen walls whose box
    /// ([`Renderer::wall_boxes`]) comes within [`TILE_MARGIN`] samples of the tile (a wall's edges are
    /// drawn on the samples beside it). Nothing for a view drawn whole.
    pub(crate) fn walls_in(&mut self, tile: &Eye) {
        if self.view_walls.is_empty() {
            return; // a view drawn whole (or one whose walls are all clipped away)
        }
        let window = tile_window(tile);
        self.walls.clear();
        self.walls.extend(self.view_walls.iter().filter(|w| meets(w.ndc_box, window)).map(|w| w.e));
    }

    /// The walls of the whole view: chosen ([`Renderer::choose_walls`]), or those seen through its
    /// tiles.
    pub(crate) fn wall_count(&self) -> usize {
        if self.view_walls.is_empty() { self.walls.len() } else { self.view_walls.len() }
    }

    /// A new frame's samples: sized to the grid, none covered.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn begin(&mut self, maze: &Maze, eye: &Eye) {
        // (a foveated view's tile: its samples were uncovered with the picture's, `enter_tile`)
        if !self.samples.is_window() {
            if self.samples.width() != eye.width || self.samples.height() != eye.height {
                self.samples.reshape(eye.width, eye.height);
            }
            self.samples.clear_coverage(); // colours: every sample gets a wall's, a plane's or the fog's
        }
        self.wall_ids = maze.edges().len() as u32;
    }

    /// A new view, before its tiles: the cells' sides the floor's rows look up forgotten (the maze
    /// may be another).
    pub(crate) fn begin_view(&mut self, maze: &Maze) {
        self.cell_sides.begin(maze.cell_count());
    }

    /// The walls to draw, into `self.walls`: the portal pass's (or every wall, brute force), ascending
    /// so that depth ties resolve the same way whichever pass chose them.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn choose_walls(&mut self, maze: &Maze, eye: &Eye, culling: Culling) -> RenderStats {
        let mut stats = RenderStats::default();
        self.walls.clear();
        match culling {
            // (only the walls: a portal is never drawn, and an open floor of tiny tiles has millions)
            Culling::None => self.walls.extend(maze.edges().opaque_ids()),
            Culling::Portal => {
                stats.portal = self.portal.run(maze, eye);
                self.walls.extend_from_slice(&self.portal.walls);
            }
        }
        self.walls.sort_unstable();
        stats
    }

    /// One wall through the whole chain: its quad extruded in world space (the model is the world:
    /// walls stand where the maze puts them), to view and clip space, clipped against the view volume,
    /// divided by w to NDC and mapped to the grid by the viewport, then rasterized (top-left rule,
    /// depth LESS), each sample shaded: Lambert from the headlight and the sun through the normal
    /// matrix, then fog, one fog for the whole wall ([`flat_fog_depth`]): a wall is one flat colour
    /// (bricks aside). Returns the triangles rasterized and the samples written.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn draw_wall(
        &mut self,
        maze: &Maze,
        eye: &Eye,
        light: &Light,
        e: u32,
        shading: Shading,
        textures: bool,
    ) -> (usize, usize) {
        let edge = maze.edge(e);
        if !edge.opaque {
            return (0, 0); // portals are invisible
        }
        // A view drawn in tiles: the wall clipped and its colour worked out once, for all its tiles.
        let shared = self.view_walls.binary_search_by_key(&e, |wall| wall.e).ok();
        if let Some((vertices, flat)) = shared
            .map(|i| &self.view_walls[i])
            .and_then(|wall| Some((wall.vertices.clone(), wall.flat?)))
            .filter(|_| shading == Shading::Color)
        {
            let poly = &self.view_wall_vertices[vertices];
            self.polygon_grid.clear();
            self.polygon_grid.extend(poly.iter().map(|v| eye.grid_vertex(v.clip, v.view))); // ÷w → NDC → viewport
            let (triangles, columns) = (self.polygon_grid.len() - 2, &mut self.column_depths);
            return (triangles, fill_polygon_x8(&mut self.samples, &self.polygon_grid, e, flat, columns));
        }
        let Some(poly) = clip_wall(maze, eye, e, &mut self.scratch) else { return (0, 0) }; // world → clip, clipped
        self.polygon_grid.clear();
        self.polygon_grid.extend(poly.iter().map(|v| eye.grid_vertex(v.clip, v.view))); // ÷w → NDC → viewport
        let (a, b) = maze.edge_points(e);
        let along = (b - a).normalize_or_zero();
        let WallShade { lit_albedo, fog_depth, normal_view } =
            self.wall_shade(maze, eye, light, e, self.polygon_grid[0].attrs);
        let triangles = self.polygon_grid.len() - 2;
        let fog = &light.fog;
        if shading == Shading::Color && !textures && !self.reference_shading {
            // The same colour as below (the same call), eight samples at a time.
            let flat = fog.apply(lit_albedo, fog_depth);
            let columns = &mut self.column_depths;
            return (triangles, fill_polygon_x8(&mut self.samples, &self.polygon_grid, e, flat, columns));
        }
        let (ortho, per_sample, view_to_world) = (light.ortho, light.per_sample, light.view_to_world);
        let written = fill_polygon(&mut self.samples, &self.polygon_grid, e, |view: Vec3| {
            let depth = view.z.abs(); // distance along the view axis (RH: -z, LH: +z)
            match shading {
                Shading::ViewDepth => Vec3::splat(depth),
                Shading::Color => {
                    let mut color = lit_albedo;
                    if textures {
                        // Texture coordinates: along the wall from its start, and height.
                        let world = view_to_world.transform_point3(view);
                        let u = (world.truncate() - a).dot(along);
                        // A sample's footprint on the wall: wider where the wall is seen edge-on
                        // (the slant of the ray from the eye, or of the view axis, to the wall).
                        let ray = if ortho { Vec3::new(0.0, 0.0, view.z) } else { view };
                        let reach = if ortho { per_sample } else { per_sample * depth };
                        color *= bricks(u, world.z, reach / slant_cosine(normal_view, ray).max(0.25));
                    }
                    fog.apply(color, fog_depth)
                }
            }
        });
        (triangles, written)
    }

    /// Wall `e`'s light, one for the whole wall: its albedo lit (sun, headlight, the exit's light in
    /// the cell on the eye's side) and the depth its fog is taken at. `first_view`: a view-space
    /// point of the wall as drawn (the sun's side is the one facing it).
    fn wall_shade(&self, maze: &Maze, eye: &Eye, light: &Light, e: u32, first_view: Vec3) -> WallShade {
        let edge = maze.edge(e);
        let (a, b) = maze.edge_points(e);
        let normal_world = (b - a).perp().normalize_or_zero().extend(0.0);
        // Normals by the inverse transpose, normalized once per wall; turned toward the eye (walls
        // are seen from both sides) for the sun, whose factor is then the wall's.
        let normal_view = (eye.normal_to_view * normal_world).normalize_or_zero();
        let facing = if normal_view.dot(first_view) > 0.0 { -normal_view } else { normal_view };
        // Never near the floor's lightness ([`apart_from_floor`]: the rule that keeps walls apart),
        // applied to the wall's colour before the sun and the headlight, so both keep their ratios.
        let floor_luminance = luminance(FLOOR_SRGB.map(srgb_to_linear)) * plane_lights(eye).0;
        let albedo = wall_albedo(edge.color.map(srgb_to_linear));
        let albedo =
            if self.walls_apart { apart_from_floor(albedo, floor_luminance, AMBIENT) } else { albedo };
        let albedo = albedo * sun_factor(facing, light.sun_view);
        // The headlight along the view axis: one light for the whole wall.
        // (off the floor's and ceiling's tints: in 16 colours those show as floor and ceiling)
        // The exit's light in the cell on the eye's side of the wall (the side the eye sees): walls
        // stop it, so the far side of a wall keeps its own cell's level.
        let eye_left = (eye.camera.position - a).perp_dot(b - a) < 0.0;
        let side = if eye_left { edge.left } else { edge.right };
        // (in colour only: the glow lifts a wall's luminance, which ascii would draw as nearness)
        let level = side
            .zip(light.exit_light)
            .filter(|_| self.walls_apart)
            .map_or(0, |(cell, exit_light)| exit_light.level(cell));
        // (16 colours: one dark green with its own seam lines; else the wall's own colour tinted)
        let lit_wall = if self.floor_bounds_apart { exit_lit_wall_16 } else { exit_lit_wall };
        let lit_albedo =
            palette::off_floor_and_ceiling(lit_wall(lit(albedo, headlight(normal_view), AMBIENT), level));
        // One fog for the whole wall, at its point nearest the eye: each wall (in a generated maze,
        // one cell's side) is one flat colour, so a colour step on a wall is a cell seam (issue #39).
        let fog_depth = flat_fog_depth(eye, e, maze);
        WallShade { lit_albedo, fog_depth, normal_view }
    }

    /// Floor and ceiling, per sample: where the sample's ray meets z = -1 or z = +1 before any wall.
    ///
    /// Floor and ceiling are solid: a ray that starts beyond them (an orthographic view cutting through
    /// the floor, a near plane poking through it) shows that plane and nothing else, and a wall sample
    /// whose ray meets the floor or ceiling first shows the floor or ceiling. So no wall is ever seen
    /// from under the floor, which also keeps the portal pass (which follows rays inside the
    /// floor-to-ceiling slab) exact against brute force.
    /// With `filter` (maze units a sample covers per unit of distance), the tiles fade to their mean as
    /// they shrink below a sample ([`checker_filtered`]).
    /// With `glow` (the maze and its exit's light), a sample in a lit cell turns toward the exit's
    /// colour by its cell's level as a wall does ([`exit_tinted`], the floor by [`FLOOR_EXIT_TINT`],
    /// the ceiling by [`CEILING_EXIT_TINT`]), its luminance kept: rows that come near no lit cell take
    /// the fast path.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn fill_floor_and_ceiling(
        &mut self,
        eye: &Eye,
        fog: &Fog,
        shading: Shading,
        exit: Option<Vec2>,
        filter: Option<f32>,
        glow: Option<(&Maze, &ExitLight)>,
    ) {
        let glow = glow.filter(|(_, light)| light.lit_cells() > 0);
        let floor = (FLOOR_Z, FLOOR, FLOOR_SRGB.map(srgb_to_linear));
        let ceiling = (CEILING_Z, CEILING, CEILING_SRGB.map(srgb_to_linear));
        let perspective = eye.camera.projection == Projection::Perspective;
        let start_depth = if perspective { eye.near } else { 0.0 };
        let (floor_light, ceiling_light) = plane_lights(eye);
        let plane_light = |plane: u32| if plane == FLOOR { floor_light } else { ceiling_light };
        let depth_at = eye.depth_by_distance();
        // Where a ray of height `start_z` and slope `dir_z` ends: which plane, how far along it (`t`;
        // `None` when it starts inside the ground or the roof and shows that plane right there), the grid
        // depth a wall must beat to stay, and the fog there. `None`: it meets neither.
        let meet = |start_z: f32, dir_z: f32| {
            let inside = match start_z {
                z if z < FLOOR_Z => Some(floor),
                z if z > CEILING_Z => Some(ceiling),
                _ => None,
            };
            if let Some(plane) = inside {
                return Some(PlaneHit {
                    plane,
                    t: None,
                    wall_stays_at: f32::NEG_INFINITY,
                    fog: fog.amount(start_depth),
                });
            }
            let plane = match dir_z {
                z if z < 0.0 => floor,
                z if z > 0.0 => ceiling,
                _ => return None, // level: never meets either
            };
            let t = (plane.0 - start_z) / dir_z;
            let depth = start_depth + t;
            (t >= 0.0 && depth <= eye.far).then(|| PlaneHit {
                plane,
                t: Some(t),
                wall_stays_at: depth_at.grid_depth(depth),
                fog: fog.amount(depth),
            })
        };
        // The colour of a plane at `hit`, seen along `dir`: the reference, sample by sample.
        let mut cursor = glow.map(|glow| CellCursor::new(glow, &mut self.cell_sides));
        // Each plane's colour tinted at every level of the exit's light, worked out once a renderer (the
        // rows of a plane share its colour and strength: a row asked all levels, 29 OKLab inversions;
        // and the tiles of a foveated view, 25 times a frame).
        let mut tint_tables = std::mem::take(&mut self.plane_tints);
        let color_at =
            |hit: &PlaneHit, point: Vec3, dir: Vec3, cursor: &mut Option<CellCursor<'_, '_>>| -> Vec3 {
                if shading == Shading::ViewDepth {
                    return Vec3::ZERO;
                }
                let on_plane = Vec2::new(point.x, point.y);
                let mut base = match filter {
                    // The footprint grows with the distance along the ray and the slant it meets the plane
                    // at (1 / |dir.z| per unit of ray).
                    Some(per) => {
                        let slant = dir.length() / dir.z.abs().max(1e-3);
                        let reach = per * hit.t.unwrap_or(0.0) * slant.min(8.0);
                        checker_filtered(hit.plane.2, on_plane, CHECKER_PERIOD, CHECKER_CONTRAST, reach)
                    }
                    None => checker(hit.plane.2, on_plane, CHECKER_PERIOD, CHECKER_CONTRAST),
                };
                if let Some(cursor) = cursor {
                    base = cursor.tint(on_plane, hit.plane.1, base);
                }
                if let Some(exit) = exit.filter(|_| hit.plane.1 == FLOOR) {
                    // The exit's light on the floor round it, fading out over EXIT_GLOW_RADIUS.
                    let d2 = on_plane.distance_squared(exit);
                    if d2 < EXIT_GLOW_RADIUS * EXIT_GLOW_RADIUS {
                        let glow = 1.0 - d2.sqrt() / EXIT_GLOW_RADIUS;
                        base = base.lerp(EXIT_GLOW, 0.8 * glow);
                    }
                }
                (base * plane_light(hit.plane.1)).lerp(fog.color, hit.fog)
            };
        let (width, pitch) = (eye.width, self.samples.pitch());
        let (colors, depths, ids) = self.samples.parts_mut();
        let rays = eye.row_rays(); // (each row's first two rays, their columns' share worked out once)
        for y in 0..eye.height {
            // `Eye::ray` is affine in the grid x: along a row, start and direction step by constants.
            let [(start0, dir0), (start1, dir1)] = rays.at(y as f32 + 0.5);
            let (start_step, dir_step) = (start1 - start0, dir1 - dir0);
            let at = |x: usize| (start0 + start_step * x as f32, dir0 + dir_step * x as f32);
            let row = y * pitch..y * pitch + width; // (a window's rows: its picture's apart)
            let (colors, depths, ids) = (&mut colors[row.clone()], &mut depths[row.clone()], &mut ids[row]);
            // The camera's right vector is level, so along a row the rays keep their height and slope:
            // where they end, how far, and the fog there are the row's (exactly what each ray would find).
            if start_step.z == 0.0 && dir_step.z == 0.0 {
                let Some(hit) = meet(start0.z, dir0.z) else {
                    // The whole row sees neither plane (a level row, or beyond the far plane): fog.
                    for (color, _) in colors.iter_mut().zip(&*ids).filter(|(_, id)| **id == NONE) {
                        *color = FOG_COLOR;
                    }
                    continue;
                };
                // A wall stays where it is at least as near as the plane along this ray (none can
                // where the ray starts inside the plane's solid side): every path below leaves such
                // samples be, so a row walls keep whole is done (a wall faced up close, a tile of walls).
                let stays_at = if hit.t.is_some() { hit.wall_stays_at } else { f32::NEG_INFINITY };
                if first_shown((ids, depths), stays_at, 0) == width {
                    continue;
                }
                let (first, last) = (at(0), at(width.saturating_sub(1)));
                let t = hit.t.unwrap_or(0.0);
                let (a, b) = ((first.0 + first.1 * t).truncate(), (last.0 + last.1 * t).truncate());
                let glows = exit.is_some_and(|exit| {
                    hit.plane.1 == FLOOR && segment_distance(exit, a, b) <= EXIT_GLOW_RADIUS * 1.001
                });
                // The exit's light, when the row's box meets the lit cells' (some samples may be lit).
                let lit_row =
                    glow.is_some_and(|(_, light)| Aabb::new(a.min(b), a.max(b)).intersects(&light.bounds()));
                if shading == Shading::Color && !glows && !self.reference_shading {
                    let shade = RowShade::new(
                        &hit,
                        (start0, start_step),
                        (dir0, dir_step),
                        filter,
                        plane_light(hit.plane.1),
                    );
                    let base = hit.plane.2;
                    let fog_term = fog.color * hit.fog;
                    #[cfg(not(test))]
                    let by_runs = true;
                    #[cfg(test)]
                    let by_runs = !self.plane_runs_off;
                    if let Some(cursor) = cursor.as_mut().filter(|_| lit_row) {
                        // The tint is linear in the colour: the plane's colour tinted by the sample's
                        // level (one of `EXIT_LIGHT` + 1, for the row), times its checker, light and
                        // fog, is the tinted sample.
                        let strength = if hit.plane.1 == FLOOR { FLOOR_EXIT_TINT } else { CEILING_EXIT_TINT };
                        let tinted = match tint_tables.iter().find(|(key, _)| *key == (base, strength)) {
                            Some((_, table)) => *table,
                            None => {
                                let table: [Vec3; EXIT_LIGHT as usize + 1] =
                                    std::array::from_fn(|level| exit_tinted(base, level as u8, strength));
                                tint_tables.push(((base, strength), table));
                                table
                            }
                        };
                        let point_at = |x: usize| {
                            let (start, dir) = at(x);
                            (start + dir * t).truncate() // as the per-sample path finds it
                        };
                        let step = (start_step + dir_step * t).truncate();
                        // Only the samples the plane shows need a level: a wall's stay (below) needs none.
                        #[cfg(not(test))]
                        let everywhere = false;
                        #[cfg(test)]
                        let everywhere = self.levels_everywhere;
                        let shown_from =
                            |x: usize| if everywhere { x } else { first_shown((ids, depths), stays_at, x) };
                        let level_runs = &mut self.plane_row.level_runs;
                        cursor.row_levels(point_at, (point_at(0), step), width, shown_from, level_runs);
                        let square_runs = &mut self.plane_row.square_runs;
                        if by_runs && shade.square_runs(square_runs, width) {
                            // Runs of one level and one checker square: one colour each, worked out
                            // once (the same operations as on each sample: the same bits).
                            let (mut x, mut squares, mut levels) =
                                (0, square_runs.iter().peekable(), level_runs.iter().peekable());
                            while let (Some(&&(square_end, paint)), Some(&&(level_end, level))) =
                                (squares.peek(), levels.peek())
                            {
                                let end = square_end.min(level_end);
                                let color = tinted[usize::from(level)] * paint + fog_term;
                                let run = x..end;
                                fill_run(
                                    (&mut colors[run.clone()], &mut depths[run.clone()], &mut ids[run]),
                                    (color, hit.plane.1),
                                    stays_at,
                                );
                                x = end;
                                if square_end == end {
                                    squares.next();
                                }
                                if level_end == end {
                                    levels.next();
                                }
                            }
                            continue;
                        }
                        let paint = &mut self.plane_row.shade;
                        shade.fill_paints(paint, width);
                        let mut x = 0;
                        for &(end, level) in level_runs.iter() {
                            let base = tinted[usize::from(level)];
                            while x < end {
                                // the samples a wall keeps skipped eight at a time, then the plane's
                                x = first_shown((&ids[..end], &depths[..end]), stays_at, x);
                                while x < end && !(ids[x] != NONE && depths[x] <= stays_at) {
                                    (colors[x], depths[x], ids[x]) =
                                        (base * paint[x] + fog_term, f32::INFINITY, hit.plane.1);
                                    x += 1;
                                }
                            }
                        }
                        continue;
                    }
                    if by_runs && shade.square_runs(&mut self.plane_row.square_runs, width) {
                        let mut x = 0;
                        for &(end, paint) in &self.plane_row.square_runs {
                            let run = x..end;
                            fill_run(
                                (&mut colors[run.clone()], &mut depths[run.clone()], &mut ids[run]),
                                (base * paint + fog_term, hit.plane.1),
                                stays_at,
                            );
                            x = end;
                        }
                        continue;
                    }
                    plane_run(
                        (&mut colors[..width], &mut depths[..width], &mut ids[..width]),
                        |g| shade.group(g),
                        (base, fog_term, hit.plane.1),
                        stays_at,
                        shade.squares(),
                    );
                    continue;
                }
            }
            for x in 0..width {
                let (start, dir) = at(x);
                let Some(hit) = meet(start.z, dir.z) else {
                    if ids[x] == NONE {
                        colors[x] = FOG_COLOR; // neither plane, no wall: fog
                    }
                    continue;
                };
                let point = match hit.t {
                    // Inside the ground or the roof: that plane, seen where the ray starts.
                    None => start,
                    Some(t) => {
                        if ids[x] != NONE && depths[x] <= hit.wall_stays_at {
                            continue; // a wall at least as near as the plane along this ray stays
                        }
                        start + dir * t
                    }
                };
                colors[x] = color_at(&hit, point, dir, &mut cursor);
                depths[x] = f32::INFINITY;
                ids[x] = hit.plane.1;
            }
        }
        self.plane_tints = tint_tables;
    }

    /// Edges: where two neighbouring samples (right or below) belong to different surfaces, the nearer
    /// one is drawn as an edge ([`edge_color`]): wall ends, corners, the seams with floor and ceiling,
    /// the outlines of figures. One sample wide, so it survives at any size. Two walls on one line
    /// (a long wall made of several edges, one a cell) meet at a cell boundary: a seam, fainter than an
    /// edge ([`seam_color`]), so a player counts the cells a wall runs along (issue #39).
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn draw_edges(&mut self, maze: &Maze, eye: &Eye) {
        let short_from = short_wall_depth(eye);
        self.edges_of(maze, &|_| short_from);
    }

    /// A view drawn in tiles, once their surfaces are placed in its picture: the edges and seams over
    /// the whole picture, each sample compared with its neighbours whichever tile they came from (a
    /// row of the picture takes its tiles' short-wall depth). Then the tiles' lines are drawn over
    /// them, as in a view drawn whole.
    pub(crate) fn picture_edges(&mut self, maze: &Maze, tiles: &[Tile]) {
        let mut short_rows = std::mem::take(&mut self.short_rows);
        short_rows.clear();
        short_rows.resize(self.picture.height(), f32::INFINITY);
        for tile in tiles {
            let y = tile.at.1;
            short_rows[y..y + tile.eye.height].fill(short_wall_depth(&tile.eye));
        }
        std::mem::swap(&mut self.samples, &mut self.picture);
        let width = self.samples.width();
        self.edges_of(maze, &|k| short_rows[k / width]);
        std::mem::swap(&mut self.samples, &mut self.picture);
        self.short_rows = short_rows;
    }

    /// Marks and paints the edges and seams between neighbouring samples; a wall at sample `k` as deep
    /// as `short_from(k)` or deeper is short ([`FAR_WALL_SAMPLES`]).
    fn edges_of(&mut self, maze: &Maze, short_from: &dyn Fn(usize) -> f32) {
        let (width, height) = (self.samples.width(), self.samples.height());
        if self.edge_marks.len() < width * height {
            self.edge_marks.resize(width * height, Mark::None); // (all None: a tile uses the first ones)
        }
        self.edge_list.clear();
        let walls = maze.edges().len() as u32;
        let mut last = (NONE, NONE, Mark::None); // the last pair of walls compared, and what they make
        let mut differ = |a: u32, b: u32| match (a < walls, b < walls) {
            (true, true) => {
                if (last.0, last.1) != (a, b) {
                    last = (a, b, if collinear(maze, a, b) { Mark::Seam } else { Mark::Edge });
                }
                last.2
            }
            (false, false) if is_figure(a) || is_figure(b) => Mark::Edge,
            (false, false) => Mark::None, // floor, ceiling, nothing: no edge
            _ => Mark::Edge,
        };
        let (ids, depth) = (self.samples.id(), self.samples.depth());
        let planes_apart = self.walls_apart;
        let (marks, list) = (&mut self.edge_marks, &mut self.edge_list);
        let mut mark = |i: usize, j: usize, what: Mark| {
            if what == Mark::None {
                return;
            }
            // An edge on the nearer sample, except where a short (far) wall meets floor or ceiling:
            // there no edge at all, so the wall shows its whole height in its own colour and no more.
            // Its top and bottom darkened, a far wall two rows tall read as one, twice as far; its
            // edges drawn on the floor and ceiling beside it, it read 1.5–2× nearer (issue #39, two
            // new players). Its colour stands apart from the planes' (`apart_from_floor`). Near walls
            // keep their edges. In colour only: without colour the glyphs are the only line there
            // is. A seam on the sample left of (or above) the boundary, so a seam seen square-on is
            // one sample wide whichever wall is nearer.
            let plane = |k: usize| planes_apart && (ids[k] == FLOOR || ids[k] == CEILING);
            let short = |k: usize| ids[k] < walls && depth[k] >= short_from(k);
            if what == Mark::Edge && ((plane(i) && short(j)) || (plane(j) && short(i))) {
                return;
            }
            let at = match what {
                Mark::Edge => {
                    if depth[j] < depth[i] {
                        j
                    } else {
                        i
                    }
                }
                _ => i,
            };
            if marks[at] == Mark::None {
                list.push(at as u32);
            }
            marks[at] = marks[at].max(what);
        };
        // Neighbours to the right, then below; most pairs are one surface, skipped eight at a time.
        for y in 0..height {
            let row = y * width;
            let here = &ids[row..row + width];
            for_each_difference(here, &here[1.min(width)..], |x| {
                mark(row + x, row + x + 1, differ(here[x], here[x + 1]));
            });
            if y + 1 < height {
                let below = &ids[row + width..row + 2 * width];
                for_each_difference(here, below, |x| {
                    mark(row + x, row + width + x, differ(here[x], below[x]));
                });
            }
        }
        // In 16 colours a lit wall's seams and corners (where it meets another wall beside it: its
        // lines along floor and ceiling keep their look) are dark cyan lines: its own darker shades
        // are the same dark green (`palette::glow_line_16`).
        let glow_lines = self.floor_bounds_apart;
        let (ids, colors) = self.samples.id_and_color_mut();
        let wall_beside = |i: usize| {
            let other = |j: usize| ids[j] < walls && ids[j] != ids[i];
            let x = i % width;
            (x > 0 && other(i - 1)) || (x + 1 < width && other(i + 1))
        };
        for &i in &self.edge_list {
            let i = i as usize;
            let glow_line = glow_lines && ids[i] < walls && wall_beside(i) && palette::glow_lit_16(colors[i]);
            colors[i] = match self.edge_marks[i] {
                _ if glow_line => palette::glow_line_16(),
                Mark::Edge => edge_color(colors[i]),
                _ => seam_color(colors[i]),
            };
            self.edge_marks[i] = Mark::None;
        }
    }

    /// The openings whose lines [`Renderer::draw_cell_bounds`] draws, once a view: those of the
    /// cells the pass visited (every one, brute force or past the pass's cap) within the view's
    /// reach ([`Eye::reach`]: no farther opening can show), and of those, the ones the exit's light
    /// comes through toward the eye.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn choose_cell_lines(&mut self, maze: &Maze, view: &Eye, culling: Culling) {
        self.lines.clear();
        match culling {
            Culling::Portal if self.portal.fell_back() => self.lines.extend(0..maze.edges().len() as u32),
            Culling::None => self.lines.extend(0..maze.edges().len() as u32),
            Culling::Portal => {
                for &cell in &self.portal.visited {
                    self.lines.extend_from_slice(maze.cell_edges(cell));
                }
            }
        }
        // Openings only, and of those only the ones within the view's reach: brute force (and the
        // portal pass past its cap) lists every edge, and an open floor of tiny tiles has millions,
        // nearly all farther than the far plane (red-team pass 9: 2046 × 2046 half-unit tiles, each
        // of its 8 million openings clipped to the view every frame, 0.2 s a frame). (A line lies on
        // the floor or the ceiling: its distance from the eye is at least its distance in the plan.)
        let (at, reach) = (view.position.truncate(), view.reach() * 1.001);
        self.lines.retain(|&e| {
            !maze.edges().is_opaque(e as usize) && {
                let (a, b) = maze.edge_points(e);
                segment_distance(at, a, b) <= reach
            }
        });
        self.lines.sort_unstable();
        self.lines.dedup();
        // The openings the exit's light comes through toward the eye: each lit cell's way one step
        // nearer the exit, seen from the cell's side (`ExitLight::lit_through`); their lines are
        // drawn in the way's light ([`way_light`], [`WAY_GLYPH`]) after the others (issue #39).
        let light = maze.exit_light();
        let toward = |e: u32| {
            light.lit_through(maze, e).is_some_and(|dim| {
                let (a, b) = maze.edge_points(e);
                let side = |p: Vec2| (b - a).perp_dot(p - a);
                side(at) * side(maze.cell_centroid(dim)) > 0.0
            })
        };
        self.way.clear();
        self.way.extend(self.lines.iter().copied().filter(|&e| toward(e)));
    }

    /// Cell boundaries on floor and ceiling: each opening of a cell the pass visited (of every cell,
    /// brute force), as a line one sample wide where it lies on the floor (and on the ceiling) in view,
    /// lighter than the plane ([`line_color`]; in 16 colours the light grey, `FLOOR_BOUND_16`), and
    /// left out on the plane beside a wall (in truecolor and 256 colours also two samples off it). With the seams on the walls, a corridor reads as a row of cells a player can
    /// count, and a side opening as a break in the wall with its own boundary line (issue #39). Exact:
    /// a ray meets the floor once, so where a sample shows the floor and the boundary projects onto
    /// it, the boundary is what the sample shows.
    ///
    /// Inside the exit's light, the line across each opening the light comes through toward the eye
    /// (a lit cell's way one step nearer the exit, `ExitLight::lit_through`, seen from that cell's
    /// side) is drawn in the way's light instead ([`way_light`], `way_light_16` in 16 colours,
    /// [`WAY_GLYPH`] in ascii): at a junction the glowing line is the way on (issue #39).
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn draw_cell_bounds(&mut self, maze: &Maze, tiling: &Tiling<'_>) {
        let view = tiling.view;
        let w = self.samples.width();
        self.edge_list.clear();
        // The lines' colour on the floor and on the ceiling: in truecolor and 256 colours the plane a
        // step lighter (line_color); in 16 colours, where the floor shows one entry, FLOOR_BOUND_16,
        // and on the ceiling the seam's colour, which its ramp shows light grey.
        let paint: [fn(Vec3) -> Vec3; 2] =
            if self.floor_bounds_apart { [FLOOR_BOUND_16, seam_color] } else { [line_color, line_color] };
        // In 16 colours the lines are light grey, as a door jamb is: where a cell's line would lie
        // under LINE_GAP_16 samples from the line a cell nearer (a corridor's far cells), the lines
        // make one pale band with the far walls' jambs (issue #39), and are left out.
        // The way's lines likewise in truecolor and 256 colours, at least WAY_LINE_GAP apart: drawn on
        // every sample down a long corridor they made one bright band past which a far wall looked
        // taller (`far_wall_height`), and the cells could not be counted. (The ordinary lines there,
        // lighter than their plane but less than the way's light is, are drawn at every distance:
        // thinned, a line 1–2 cells off on the ceiling, nearer the eye's height, was left out.)
        // In ascii (a sample a cell) the lines are glyphs: where they lie under LINE_GAP_ASCII rows
        // apart they make a block of `~`, and the farther ones are left out the same way.
        let gap = if self.ascii_lines { LINE_GAP_ASCII } else { LINE_GAP_16 };
        let colour_lines = !(self.floor_bounds_apart || self.ascii_lines);
        let perspective = view.camera.projection == Projection::Perspective;
        let walls = maze.edges().len() as u32;
        let seen = std::mem::take(&mut self.lines);
        let way = std::mem::take(&mut self.way);
        let way_paint = if self.floor_bounds_apart { way_light_16 } else { way_light };
        for (z, plane, paint) in [(FLOOR_Z, FLOOR, paint[0]), (CEILING_Z, CEILING, paint[1])] {
            for (edges, paint, glyph, is_way) in
                [(&seen, paint, CELL_LINE_GLYPH, false), (&way, way_paint, WAY_GLYPH, true)]
            {
                self.edge_list.clear();
                let below = (view.position.z - z).abs(); // the plane's distance from the eye's height
                for &e in edges {
                    let (a, b) = maze.edge_points(e);
                    let Some(clipped) = clip_segment(view, a.extend(z), b.extend(z)) else { continue };
                    let gap = if is_way && colour_lines { WAY_LINE_GAP } else { gap };
                    // a line at depth d and the one a cell (its length) nearer are `per_unit · below ·
                    // c / (d (d − c))` samples apart: up to the depth where that is LINE_GAP_16 on
                    // the tile's scale, so the last line drawn still stands apart from the one before
                    let thinned = perspective && (is_way || !colour_lines);
                    let c = a.distance(b);
                    let depth = |p: Vec2| (p.extend(z) - view.position).dot(view.forward);
                    let nearest = depth(a).min(depth(b));
                    // A wall whose foot (top) this line runs along: within FOOT_ANGLE of it (below).
                    let line = (b - a).normalize_or_zero();
                    let along_foot = |id: u32| {
                        id < walls && {
                            let (c, d) = maze.edge_points(id);
                            line.perp_dot((d - c).normalize_or_zero()).abs() < FOOT_ANGLE.sin()
                        }
                    };
                    for tile in tiling.reached(clipped) {
                        if thinned {
                            let per_unit = tile.eye.height as f32 / tile.eye.tan_extent().y; // at depth 1
                            let room = per_unit * below * c / gap;
                            if nearest > 0.5 * ((c * c + 4.0 * room).sqrt() + c) {
                                continue;
                            }
                        }
                        for (x, y) in tile_samples(tile, clipped) {
                            let i = y * w + x;
                            // Not on the plane's sample just beside a wall (the floor's below it, the
                            // ceiling's above): a light line there reads as a pale far wall's own foot or
                            // top, a row taller than it is (issue #39, `far_wall_height`). Every line but
                            // ascii's glyphs is lighter than its plane (16 colours' light grey, line_color,
                            // the way's light): each is left out there.
                            let off = |k: usize| {
                                if plane == FLOOR { i.checked_sub(k * w) } else { Some(i + k * w) }
                            };
                            let wall_at = |j: Option<usize>, along: bool| {
                                j.and_then(|j| self.samples.id().get(j))
                                    .is_some_and(|&id| id < walls && (!along || along_foot(id)))
                            };
                            let light = colour_lines || self.floor_bounds_apart || is_way;
                            // (in truecolor and 256 colours, whose lines are near a wall's lightness, not
                            // two samples off a wall either: there a wall's foot is told from the floor a
                            // little way off it, `wall_floor`; nor, but the way's, three off a far wall, one
                            // under FAR_WALL_SAMPLES tall, which fades to a line's grey: a grey line there
                            // read as the wall again, a row taller, `far_wall_height`; those two only for a
                            // wall the line runs along: one that meets a wall at an angle, down a side
                            // opening to the wall faced across it, reaches the sample beside the wall, and
                            // that it reaches the wall tells the opening from a wall in line with an end
                            // wall, issue #39)
                            let far_wall_at = |k: usize| {
                                off(k).and_then(|j| self.samples.id().get(j)).is_some_and(|&id| {
                                    along_foot(id)
                                        && off(k + FAR_WALL_SAMPLES as usize)
                                            .and_then(|j| self.samples.id().get(j))
                                            .is_none_or(|&top| top != id)
                                })
                            };
                            let beside_wall = light
                                && (wall_at(off(1), false)
                                    || colour_lines && wall_at(off(2), true)
                                    || colour_lines && !is_way && far_wall_at(3));
                            if self.samples.id()[i] == plane
                                && self.edge_marks[i] == Mark::None
                                && !beside_wall
                            {
                                self.edge_marks[i] = Mark::Seam;
                                self.edge_list.push(i as u32);
                            }
                        }
                    }
                }
                if self.ascii_lines {
                    for &i in &self.edge_list {
                        let i = i as usize;
                        self.samples.put_outline(i % w, i / w, Some(glyph));
                    }
                }
                self.paint_marked(paint);
            }
        }
        (self.lines, self.way) = (seen, way);
    }

    /// Door jambs: where a wall ends at an opening of its own line (a side opening, a turn) on the
    /// eye's side of the wall, a light line one sample wide from floor to ceiling on the wall's last
    /// samples ([`jamb_color`]). An
    /// opening six cells down a corridor is narrower than a column, but its jambs stay a sample wide,
    /// so a player sees where the side openings are as far as the view reaches (issue #39).
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn draw_jambs(&mut self, maze: &Maze, tiling: &Tiling<'_>) {
        let view = tiling.view;
        let w = self.samples.width();
        let (eye_at, forward) = (view.camera.position, ground_forward(view));
        self.edge_list.clear();
        for &e in &self.walls {
            let edge = maze.edge(e);
            if !edge.opaque {
                continue;
            }
            for v in [edge.start, edge.end] {
                // Only an opening on the eye's side of the wall: one beyond it (round the corner of a
                // dead end, behind the wall the eye faces) cannot be seen from here, and a jamb for
                // it reads as a way on where there is none (issue #39).
                if wall_end(maze, e, v, eye_at, forward) != WallEnd::Jamb {
                    continue;
                }
                let at = maze.vertex(v);
                let Some(clipped) = clip_segment(view, at.extend(FLOOR_Z), at.extend(CEILING_Z)) else {
                    continue;
                };
                for (x, y) in tiling.reached(clipped).flat_map(|tile| tile_samples(tile, clipped)) {
                    // The wall's own sample on the line, or beside it (the line runs along the
                    // wall's end, which rounds to either side).
                    let row = y * w;
                    let on_wall = [x, x.wrapping_sub(1), x + 1].into_iter().filter(|&x| x < w);
                    if let Some(i) = on_wall.map(|x| row + x).find(|&i| self.samples.id()[i] == e)
                        && self.edge_marks[i] == Mark::None
                    {
                        self.edge_marks[i] = Mark::Seam;
                        self.edge_list.push(i as u32);
                    }
                }
            }
        }
        // (a jamb is paler than its wall: off the floor's and ceiling's tints, as the wall is)
        // (in 16 colours a grey: a coloured wall never shows the light grey or white there, so the
        // jamb stands out from every wall, far walls too)
        if self.floor_bounds_apart {
            self.paint_marked(jamb_grey);
        } else {
            self.paint_marked(|color| palette::off_floor_and_ceiling(jamb_color(color)));
        }
    }

    /// Chalk marks ([`Renderer::set_chalk`]): on the floor of each marked cell the view shows, a cross
    /// through the cell's centroid, its arms a fifth of the cell's smaller side from the centre, one
    /// sample wide, in [`chalk_color`] of the floor under it (so a far mark fades as the floor does),
    /// moved off the floor's tint ([`palette::off_floor_and_ceiling`]).
    /// Exact as the cell lines are: a ray meets the floor once.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn draw_chalk(&mut self, maze: &Maze, tiling: &Tiling<'_>, culling: Culling) {
        let view = tiling.view;
        let w = self.samples.width();
        self.edge_list.clear();
        for &cell in &self.chalk {
            if cell as usize >= maze.cell_count()
                || culling == Culling::Portal && !self.portal.fell_back() && !self.portal.was_visited(cell)
            {
                continue;
            }
            let centre = maze.cell_centroid(cell);
            let size = maze.cell_aabb(cell);
            let arm = 0.2 * (size.max - size.min).min_element();
            for d in [Vec2::new(arm, arm), Vec2::new(arm, -arm)] {
                let (a, b) = ((centre - d).extend(FLOOR_Z), (centre + d).extend(FLOOR_Z));
                let Some(clipped) = clip_segment(view, a, b) else { continue };
                for (x, y) in tiling.reached(clipped).flat_map(|tile| tile_samples(tile, clipped)) {
                    let i = y * w + x;
                    if self.samples.id()[i] == FLOOR && self.edge_marks[i] == Mark::None {
                        self.edge_marks[i] = Mark::Seam;
                        self.edge_list.push(i as u32);
                    }
                }
            }
        }
        // (in ascii a glyph of its own: by lightness alone a mark on the floor's lightest glyph, or
        // under a cell line's `~`, would not show)
        if self.ascii_lines {
            for &i in &self.edge_list {
                let i = i as usize;
                self.samples.put_outline(i % w, i / w, Some(CHALK_GLYPH));
            }
        }
        // (off the floor's tint, as a jamb is off its wall's: in 16 colours the floor's tint shows only
        // the floor's entry, and a mark must show)
        self.paint_marked(|color| palette::off_floor_and_ceiling(chalk_color(color)));
    }

    /// The samples listed in `edge_list` drawn in `paint` of their colour, and unmarked. A sample with
    /// the bits of the one painted before it takes that one's paint (a line across a floor row, a
    /// seam down a level wall: one colour along it), without `paint`'s cube roots again.
    fn paint_marked(&mut self, paint: fn(Vec3) -> Vec3) {
        let colors = self.samples.color_mut();
        let mut last: Option<(Vec3, Vec3)> = None;
        for &i in &self.edge_list {
            let color = colors[i as usize];
            let painted = match last {
                Some((before, painted))
                    if before.to_array().map(f32::to_bits) == color.to_array().map(f32::to_bits) =>
                {
                    painted
                }
                _ => paint(color),
            };
            last = Some((color, painted));
            colors[i as usize] = painted;
            self.edge_marks[i as usize] = Mark::None;
        }
    }

    /// Ascii: the edges of every wall that won at least one sample, as line glyphs on that wall's samples.
    /// A wall's end is `|` where the wall stops (a door jamb, a corner, a free end) and
    /// [`SEAM_GLYPH`] where the next wall of its line goes on (a cell boundary along a straight
    /// wall): issue #39, an opening 4–6 cells away is a column or less wide, and what marks it is the
    /// two ends beside it; drawn alike, every seam read as one. Ends win over the top and bottom lines
    /// (a far wall two rows tall is all ends and lines), and the top and bottom lines are left out
    /// where the wall stands under [`SHORT_ASCII_WALL`] samples tall, so a far wall shows its glyphs:
    /// which way it faces ([`Renderer::faced`]), not a row of `-`.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    pub(crate) fn outline_visible_walls(&mut self, maze: &Maze, tiling: &Tiling<'_>, sample_aspect: f32) {
        let view = tiling.view;
        let edges = maze.edges().len() as u32;
        self.seen.clear();
        // One id per run of equal samples (a wall covers runs of a row), so the sort is of a few.
        let runs = self.samples.id().chunk_by(|a, b| a == b).map(|run| run[0]);
        self.seen.extend(runs.filter(|&id| id < edges));
        self.seen.sort_unstable();
        self.seen.dedup();
        self.faced.resize(edges as usize, false); // cleared once a view: its tiles set their walls
        let (w, h) = (self.samples.width(), self.samples.height());
        let (eye_at, forward) = (view.camera.position, ground_forward(view));
        for &e in &self.seen {
            let (a, b) = maze.edge_points(e);
            let normal_view =
                (view.normal_to_view * (b - a).perp().normalize_or_zero().extend(0.0)).normalize_or_zero();
            self.faced[e as usize] = normal_view.z.abs() >= std::f32::consts::FRAC_1_SQRT_2;
            let edge = maze.edge(e);
            let quad = wall_quad_world(maze, e);
            // The quad's sides: 0 the foot, 1 the end at `edge.end`, 2 the top, 3 the end at `edge.start`;
            // lines first, then seams, then the ends that stop, each over what came before.
            let end = |v: u32| wall_end(maze, e, v, eye_at, forward);
            let ends = [(1, end(edge.end)), (3, end(edge.start))];
            let order = [(0, WallEnd::Corner), (2, WallEnd::Corner)].into_iter();
            let order = order
                .chain(ends.into_iter().filter(|end| end.1 == WallEnd::Seam))
                .chain(ends.into_iter().filter(|end| end.1 != WallEnd::Seam));
            for (k, what) in order {
                let Some(clipped) = clip_segment(view, quad[k], quad[(k + 1) % 4]) else { continue };
                for tile in tiling.reached(clipped) {
                    let (gp, gq) = (tile.eye.grid(clipped.0), tile.eye.grid(clipped.1));
                    let glyph = match (line_glyph(gq.x - gp.x, gq.y - gp.y, sample_aspect), what) {
                        ('|', WallEnd::Seam) if k % 2 == 1 => SEAM_GLYPH,
                        ('|', WallEnd::Jamb) if k % 2 == 1 => {
                            // which hand the wall lies on, seen from the eye: the bracket's back to the
                            // opening (`]` a wall on the left stops, `[` one on the right starts)
                            let (here, there) = if k == 1 { (b, a) } else { (a, b) };
                            jamb_glyph((here - eye_at).perp_dot(there - here) > 0.0)
                        }
                        (glyph, _) => glyph,
                    };
                    let (tx, ty) = tile.at; // (the tile's part of the picture)
                    let points = tile_line(tile, gp.truncate(), gq.truncate());
                    for (x, y) in points.map(|(x, y)| (x + tx, y + ty)) {
                        // Only on this wall's own samples: exact, and the same in every culling mode. An
                        // end runs along the wall's last samples, which round to either side of it: a
                        // sample beside the line where the line's own shows no other wall of that vertex
                        // (that one draws the line: one line where two walls meet).
                        let ids = self.samples.id();
                        let v = if k == 1 { edge.end } else { edge.start };
                        let meets = |f: u32| f < edges && (maze.edge(f).start == v || maze.edge(f).end == v);
                        let beside = if k % 2 == 1 && !meets(ids[y * w + x]) {
                            [x, x.wrapping_sub(1), x + 1]
                        } else {
                            [x; 3]
                        };
                        let Some(x) = beside.into_iter().find(|&x| x < w && ids[y * w + x] == e) else {
                            continue;
                        };
                        if k % 2 == 0 {
                            // a top or bottom line where the wall stands tall enough in this column
                            let tall = (1..SHORT_ASCII_WALL).all(|d| {
                                let row =
                                    if k == 0 { y.checked_sub(d) } else { Some(y + d).filter(|&r| r < h) };
                                row.is_some_and(|r| ids[r * w + x] == e)
                            });
                            if !tall {
                                continue;
                            }
                        }
                        self.samples.put_outline(x, y, Some(glyph));
                    }
                }
            }
        }
    }
}

/// The ascii glyph of a seam: where a wall's line goes on into the next wall (a cell boundary along a
/// straight wall), dotted, where a wall that stops (a jamb, a corner) ends in `|`.
pub(crate) const SEAM_GLYPH: char = ':';

/// The ascii glyph of a door jamb or a post ([`WallEnd::Jamb`]: a wall stops at an opening), apart
/// from a corner's `|`: `]` where the wall lies to the left of its end on the picture (`wall_left`),
/// `[` where it lies to the right, so the bracket's back faces the opening (issue #39: a jamb where
/// a side wall starts read as one where it ends, and the opening was given to the wrong cell).
pub(crate) const fn jamb_glyph(wall_left: bool) -> char {
    if wall_left { ']' } else { '[' }
}

/// In ascii, a wall shorter than this many samples in a column draws no top or bottom line there:
/// the lines would be all of it.
pub(crate) const SHORT_ASCII_WALL: usize = 3;

/// What happens at a wall's end, seen from the eye's side of the wall ([`wall_end`]): the one
/// reading of a vertex's neighbourhood that the door jambs ([`Renderer::draw_jambs`]) and the ascii
/// ends ([`Renderer::outline_visible_walls`]) both draw from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum WallEnd {
    /// The wall stops at an opening: its line goes on as an opening (a side opening's jamb, a turn),
    /// or, on a wall seen square on, the line goes on as another wall across an opening that runs
    /// from this end toward the eye (a post: the wall seen through a side opening beside the end
    /// wall, issue #39). A vertical edge with depth or an opening behind it.
    Jamb,
    /// Two walls of one line meet with no opening between them and the eye: a cell boundary.
    Seam,
    /// Another wall meets at an angle on the eye's side, or nothing goes on: the wall stops.
    Corner,
}

/// What wall `e`'s end at its vertex `v` is, seen from `eye` (`forward`, the view's direction on the
/// ground): in the wall's cell on the eye's side, another wall of its line at `v` is a seam and an
/// opening of its line a jamb; another wall at an angle a corner; an opening at an angle leads to
/// the cell across it, whose edge of the line at `v` says the same (an opening: a jamb; a wall: a
/// seam, or a post ([`WallEnd::Jamb`]) where the wall is seen square on and the opening lies on the
/// eye's side of the wall's cell).
pub(crate) fn wall_end(maze: &Maze, e: u32, v: u32, eye: Vec2, forward: Vec2) -> WallEnd {
    let edge = maze.edge(e);
    let (a, b) = maze.edge_points(e);
    let eye_left = (b - a).perp_dot(eye - a) > 0.0;
    let Some(near) = (if eye_left { edge.left } else { edge.right }) else { return WallEnd::Corner };
    let at_v = |f: u32| f != e && (maze.edge(f).start == v || maze.edge(f).end == v);
    let along = |f: u32| at_v(f) && collinear(maze, e, f);
    let mut across = None;
    for &g in maze.cell_edges(near).iter().filter(|&&g| at_v(g)) {
        match (maze.edge(g).opaque, collinear(maze, e, g)) {
            (true, true) => return WallEnd::Seam, // the next wall of the line, in the same cell
            (false, true) => return WallEnd::Jamb, // the line goes on as an opening
            (true, false) => return WallEnd::Corner, // a wall at an angle on the eye's side
            (false, false) => across = Some(g),   // an opening at an angle: see across it
        }
    }
    let Some((g, next)) = across.and_then(|g| Some((g, maze.edge(g).other_side(near)?))) else {
        return WallEnd::Corner;
    };
    let Some(f) = maze.cell_edges(next).iter().copied().find(|&f| along(f)) else { return WallEnd::Corner };
    if !maze.edge(f).opaque {
        return WallEnd::Jamb;
    }
    // The line goes on as a wall across the opening `g`. Seen square on, with the eye on the wall's
    // own cell's side of the opening, and the opening a doorway (a wall of its line stops at its
    // other end), the wall beyond is seen through a side opening beside this one, coplanar and as
    // tall: one wall of two colours to a player (issue #39, the last cell's side openings beside the
    // end wall), so its end is a post. Along the view, or across open floor, it is a seam.
    let (p, q) = maze.edge_points(g);
    let side = |point: Vec2| (q - p).perp_dot(point - p) > 0.0;
    let faced = (b - a).perp().normalize_or_zero().dot(forward).abs() >= std::f32::consts::FRAC_1_SQRT_2;
    if faced && side(eye) == side(maze.cell_centroid(near)) && doorway(maze, g, v, near, eye) {
        WallEnd::Jamb
    } else {
        WallEnd::Seam
    }
}

/// Whether opening `g` (at vertex `v` of a wall, in `cell`, a cell on the eye's side) is a doorway
/// seen from `eye`: along `g`'s line from `v` toward the eye, past `g` and any openings in line after
/// it (cell by cell, in the cell or across its opening at each vertex), a wall of the line stops it
/// before the eye's own place along the line. Not a doorway: open floor beside the eye all the way.
fn doorway(maze: &Maze, g: u32, v: u32, cell: u32, eye: Vec2) -> bool {
    let (mut g, mut from, mut cell) = (g, v, cell);
    let origin = maze.vertex(v);
    let toward = |u: u32| maze.vertex(u) - origin;
    // (a few cells at most: a doorway's wall is within the view's reach of the wall's end)
    for _ in 0..8 {
        let u = if maze.edge(g).start == from { maze.edge(g).end } else { maze.edge(g).start };
        let dir = toward(u);
        if dir.dot(toward(u)) >= dir.dot(eye - origin) {
            return false; // the line passes the eye open
        }
        let at_u = |f: u32| f != g && (maze.edge(f).start == u || maze.edge(f).end == u);
        let next_in = |c: u32| maze.cell_edges(c).iter().copied().find(|&f| at_u(f) && collinear(maze, g, f));
        let found = next_in(cell).map(|f| (f, cell)).or_else(|| {
            maze.cell_edges(cell).iter().find_map(|&f| {
                let across = maze.edge(f).other_side(cell).filter(|_| at_u(f) && !maze.edge(f).opaque)?;
                next_in(across).map(|f| (f, across))
            })
        });
        match found {
            Some((f, _)) if maze.edge(f).opaque => return true,
            Some((f, c)) => (g, from, cell) = (f, u, c),
            None => return false,
        }
    }
    false
}

/// The floor's cell lines in 16 colours: a seam moved off the floor's chromaticity
/// ([`palette::off_floor_and_ceiling`]), as a jamb is off its wall's: there the floor shows one entry
/// (`palette::FLOOR_16`), and a darker grey of the floor's own tint is that entry again (no line at
/// all). Off it, the line takes the nearest other entry, lighter than the floor's dark grey, as the
/// ceiling's lines are lighter than its blue; black stays for what is black.
const FLOOR_BOUND_16: fn(Vec3) -> Vec3 = |c| palette::off_floor_and_ceiling(seam_color(c));

/// In ascii, the least gap (rows: a sample a cell) between a floor's (ceiling's) cell line and the one
/// a cell nearer for the line to be drawn: lines a row apart make a block ([`Renderer::draw_cell_bounds`]).
const LINE_GAP_ASCII: f32 = 2.0;

/// The ascii glyph of the floor's and the ceiling's cell lines: a cell boundary on open floor, none of
/// the walls' glyphs (faced, along the view, outlines, seams), nor the floor's, the ceiling's or the
/// beacon's (issue #39: cells a player can count).
pub(crate) const CELL_LINE_GLYPH: char = '~';

/// The ascii glyph of the line across an opening the exit's light comes through toward the eye (a lit
/// cell's way one step nearer the exit, issue #39): none of the walls', the floor's, the ceiling's,
/// the other cell lines' (`~`), a chalk mark's or the beacon's; a row of them points the way on.
pub(crate) const WAY_GLYPH: char = '^';

/// In truecolor and 256 colours, the least gap (samples) between a line across an opening the exit's
/// light comes through and the one a cell nearer for it to be drawn ([`Renderer::draw_cell_bounds`]):
/// every other row at most, so far down a corridor toward the exit the lines stay lines.
const WAY_LINE_GAP: f32 = 2.0;

/// The ascii glyph of a chalk mark's cross ([`Renderer::set_chalk`]): none of the walls', the floor's,
/// the ceiling's, the cell lines' or the beacon's.
pub(crate) const CHALK_GLYPH: char = 'x';

/// In 16 colours, the least gap (samples) between a floor's (ceiling's) cell line and the one a cell
/// nearer for the line to be drawn ([`Renderer::draw_cell_bounds`]).
const LINE_GAP_16: f32 = 3.0;

/// The view's direction on the ground (unit; the x axis where the eye looks straight up or down).
fn ground_forward(eye: &Eye) -> Vec2 {
    eye.forward.truncate().try_normalize().unwrap_or(Vec2::X)
}

/// What a sample on a boundary between surfaces is drawn as (the stronger wins).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
enum Mark {
    /// Not on a boundary.
    #[default]
    None,
    /// A cell boundary: two walls on one line, or an opening on the floor or ceiling.
    Seam,
    /// Where two surfaces meet: a corner, a wall's end, the floor, a figure.
    Edge,
}

/// A row of floor or ceiling samples where no cell is lit: each sample that no wall at least as
/// near as the plane holds (`id` NONE, or its depth past `stays_at`) becomes the plane, its colour
/// `base × paint + fog_term`, `shade(g)` the paints of group `g` (samples `8g..8g + 8`), asked only of
/// groups the plane shows in. Eight samples at a time: a group all wall is skipped with one test, a
/// group all plane is written in lanes (the same products and sums as the scalar path, lane by
/// lane: the same bits), a mixed group sample by sample. A group all plane whose eight paints are
/// one of `common`'s, bit for bit (a checker square's: the two a row without the textures' filter
/// takes), is that paint's colour eight times, worked out once a row by the same operations.
/// Returns how many groups took a common paint's colour.
fn plane_run(
    (colors, depths, ids): (&mut [Vec3], &mut [f32], &mut [u32]),
    shade: impl Fn(usize) -> f32x8,
    (base, fog_term, plane): (Vec3, Vec3, u32),
    stays_at: f32,
    common: [f32; 2],
) -> usize {
    let scalar = |x: usize, paint: f32, colors: &mut [Vec3], depths: &mut [f32], ids: &mut [u32]| {
        if ids[x] != NONE && depths[x] <= stays_at {
            return;
        }
        (colors[x], depths[x], ids[x]) = (base * paint + fog_term, f32::INFINITY, plane);
    };
    let s = f32x8::splat;
    let (none, stays) = (u32x8::splat(NONE), s(stays_at));
    let (rgb, fog) = (base.to_array().map(s), fog_term.to_array().map(s));
    let common = common.map(|paint| (u32x8::splat(paint.to_bits()), base * paint + fog_term));
    let mut by_common = 0;
    let groups = colors.len() / LANES;
    for g in 0..groups {
        let at = g * LANES..(g + 1) * LANES;
        let id = u32x8::from(<[u32; LANES]>::try_from(&ids[at.clone()]).expect("eight"));
        let depth = f32x8::from(<[f32; LANES]>::try_from(&depths[at.clone()]).expect("eight"));
        // Lanes a wall keeps: not NONE, and at least as near as the plane (NaN depths: not kept).
        let empty = cast::<u32x8, f32x8>(id.simd_eq(none)).to_bitmask();
        let kept = !empty & depth.simd_le(stays).to_bitmask() & 0xff;
        if kept == 0xff {
            continue; // (its paints are not worked out)
        }
        let paint = shade(g);
        if kept != 0 {
            for (x, paint) in at.zip(paint.to_array()) {
                scalar(x, paint, colors, depths, ids);
            }
            continue;
        }
        let bits = cast::<f32x8, u32x8>(paint);
        if let Some(&(_, color)) = common.iter().find(|(one, _)| bits.simd_eq(*one).all()) {
            colors[at.clone()].fill(color);
            by_common += 1;
        } else {
            let [r, gr, b] = [0, 1, 2].map(|c| (rgb[c] * paint + fog[c]).to_array());
            for (k, color) in colors[at.clone()].iter_mut().enumerate() {
                *color = Vec3::new(r[k], gr[k], b[k]);
            }
        }
        depths[at.clone()].fill(f32::INFINITY);
        ids[at].fill(plane);
    }
    if groups * LANES < colors.len() {
        let paint = shade(groups).to_array();
        for (x, paint) in (groups * LANES..colors.len()).zip(paint) {
            scalar(x, paint, colors, depths, ids);
        }
    }
    by_common
}

/// A run of floor or ceiling samples of one colour: each sample that no wall at least as near as the
/// plane holds (`id` NONE, or its depth past `stays_at`) becomes the plane (`color`, depth infinite,
/// id `plane`). Eight samples at a time: eight all wall are skipped with one test, eight all plane
/// filled, a mix sample by sample (as [`plane_run`] tests them).
fn fill_run(
    (colors, depths, ids): (&mut [Vec3], &mut [f32], &mut [u32]),
    (color, plane): (Vec3, u32),
    stays_at: f32,
) {
    let n = colors.len().min(depths.len()).min(ids.len());
    let one = |x: usize, colors: &mut [Vec3], depths: &mut [f32], ids: &mut [u32]| {
        if ids[x] != NONE && depths[x] <= stays_at {
            return;
        }
        (colors[x], depths[x], ids[x]) = (color, f32::INFINITY, plane);
    };
    let (none, stays) = (u32x8::splat(NONE), f32x8::splat(stays_at));
    let eight = [color; LANES];
    let mut x = 0;
    while x + LANES <= n {
        let at = x..x + LANES;
        let id = u32x8::from(<[u32; LANES]>::try_from(&ids[at.clone()]).expect("eight"));
        let depth = f32x8::from(<[f32; LANES]>::try_from(&depths[at.clone()]).expect("eight"));
        // Lanes a wall keeps: not NONE, and at least as near as the plane (NaN depths: not kept).
        let empty = cast::<u32x8, f32x8>(id.simd_eq(none)).to_bitmask();
        let kept = !empty & depth.simd_le(stays).to_bitmask() & 0xff;
        if kept == 0 {
            colors[at.clone()].copy_from_slice(&eight); // (a copy of 96 bytes: no loop)
            depths[at.clone()].fill(f32::INFINITY);
            ids[at].fill(plane);
        } else if kept != 0xff {
            for x in at {
                one(x, colors, depths, ids);
            }
        }
        x += LANES;
    }
    for x in x..n {
        one(x, colors, depths, ids);
    }
}

/// From `x`, the first sample of a row that no wall at least as near as the plane holds (`id` NONE,
/// or its depth past `stays_at`, as [`fill_run`] tells them), or the row's length. Eight at a time.
fn first_shown((ids, depths): (&[u32], &[f32]), stays_at: f32, mut x: usize) -> usize {
    let n = ids.len().min(depths.len());
    let (none, stays) = (u32x8::splat(NONE), f32x8::splat(stays_at));
    while x + LANES <= n {
        let at = x..x + LANES;
        let id = u32x8::from(<[u32; LANES]>::try_from(&ids[at.clone()]).expect("eight"));
        let depth = f32x8::from(<[f32; LANES]>::try_from(&depths[at]).expect("eight"));
        let empty = cast::<u32x8, f32x8>(id.simd_eq(none)).to_bitmask();
        let kept = !empty & depth.simd_le(stays).to_bitmask() & 0xff;
        if kept != 0xff {
            return x + kept.trailing_ones() as usize;
        }
        x += LANES;
    }
    while x < n && ids[x] != NONE && depths[x] <= stays_at {
        x += 1;
    }
    x
}

/// The headlight on floor and ceiling (factors on their colours): one light for each plane (both face
/// the same way); the floor, under the lamp the viewer carries, keeps more of its colour than the
/// ceiling.
fn plane_lights(eye: &Eye) -> (f32, f32) {
    let facing_planes = headlight((eye.normal_to_view * Vec3::Z).normalize_or_zero());
    (
        FLOOR_AMBIENT + (1.0 - FLOOR_AMBIENT) * facing_planes,
        CEILING_AMBIENT + (1.0 - CEILING_AMBIENT) * facing_planes,
    )
}

/// How far inside a cell (maze units) a point must be for [`CellCursor`] to take the last cell's
/// level without asking the maze: well beyond the maze's on-edge tolerance (1e-4) and f32 rounding.
const INSIDE_MARGIN: f32 = 1e-3;

/// Which cell floor and ceiling samples lie in, for the exit's light: the last cell found, kept
/// while the samples stay in it (a row's samples cross a few cells), so most samples cost a test
/// against the cell's sides instead of a search of the maze's cell index.
struct CellCursor<'m, 's> {
    maze: &'m Maze,
    light: &'m ExitLight,
    /// The sides of the cells crossed this frame ([`CellSides`]): each worked out once a frame.
    sides: &'s mut CellSides,
    /// The last cell found and its level.
    cell: Option<(u32, u8)>,
    /// That cell's sides in `sides`.
    edges: Range<usize>,
}

impl<'m, 's> CellCursor<'m, 's> {
    fn new((maze, light): (&'m Maze, &'m ExitLight), sides: &'s mut CellSides) -> CellCursor<'m, 's> {
        CellCursor { maze, light, sides, cell: None, edges: 0..0 }
    }

    /// The exit's light level at `point` (0 outside the lit cells' box or the maze). The same for a
    /// point whatever the cursor's state: the last cell answers only for a point well inside it (by
    /// [`INSIDE_MARGIN`], where no other cell holds it), a point near a boundary asks the maze.
    fn level(&mut self, point: Vec2) -> u8 {
        let bounds = self.light.bounds();
        if !(point.cmpge(bounds.min).all() && point.cmple(bounds.max).all()) {
            self.cell = None;
            return 0;
        }
        if let Some((_, level)) = self.cell
            && self.well_inside(point)
        {
            return level; // still in the last cell
        }
        if let Some((last, _)) = self.cell {
            // Most often the point has crossed into a cell beside the last one: a cell across an edge
            // it lies beyond that holds it well inside is the one the maze would find.
            let maze = self.maze;
            for (&e, k) in maze.cell_edges(last).iter().zip(self.edges.clone()) {
                if self.sides.sides[k].holds(point) {
                    continue; // not beyond this edge
                }
                let Some(next) = maze.edge(e).other_side(last) else { continue };
                let beside = self.sides.of(maze, next);
                if self.sides.sides[beside.clone()].iter().all(|side| side.holds(point)) {
                    let level = self.light.level(next);
                    (self.cell, self.edges) = (Some((next, level)), beside);
                    return level;
                }
            }
        }
        let Some(cell) = self.maze.cell_at(point) else {
            self.cell = None;
            return 0;
        };
        let level = self.light.level(cell);
        (self.cell, self.edges) = (Some((cell, level)), self.sides.of(self.maze, cell));
        level
    }

    /// `point` is inside the last cell by at least [`INSIDE_MARGIN`] from every edge.
    fn well_inside(&self, point: Vec2) -> bool {
        self.sides.sides[self.edges.clone()].iter().all(|side| side.holds(point))
    }

    /// The levels of a row's points `point_at(x)` (`start + step × x`, up to rounding), x in
    /// 0..`width`, by runs into `runs` ((end, level), in order from 0, the last ending at `width`):
    /// each sample not `hidden` lies in a run of [`CellCursor::level`] of its point, but each cell
    /// the row crosses is found once and the run of samples well inside it follows from its edges
    /// (each bounds x by a linear inequality, its ends checked point by point), so a row costs a
    /// search per cell crossed, not per sample. Hidden samples (a wall in front of the plane; from x,
    /// the next sample not hidden is `shown_from(x)`, at most `width`) are not looked at: they join
    /// the run before them (the first run, if they begin the row). A
    /// point's level does not depend on the cursor's state, so those that are looked at are the same
    /// either way.
    #[cfg_attr(feature = "stage-profile", inline(never))]
    fn row_levels(
        &mut self,
        point_at: impl Fn(usize) -> Vec2,
        (start, step): (Vec2, Vec2),
        width: usize,
        shown_from: impl Fn(usize) -> usize,
        runs: &mut Vec<(usize, u8)>,
    ) {
        runs.clear();
        // samples up to `end` at `level`: the last run grows where it has that level
        let push = |runs: &mut Vec<(usize, u8)>, end: usize, level: u8| match runs.last_mut() {
            Some(last) if last.1 == level => last.0 = end,
            _ => runs.push((end, level)),
        };
        let (mut x, mut hidden_lead) = (0, true);
        while x < width {
            let end = shown_from(x).min(width);
            if end > x {
                match runs.last_mut() {
                    Some(last) => last.0 = end,
                    None => runs.push((end, 0)), // (its level is the next run's, if one follows)
                }
                x = end;
                continue;
            }
            let point = point_at(x);
            let level = self.level(point).min(EXIT_LIGHT);
            if std::mem::take(&mut hidden_lead)
                && let Some(lead) = runs.first_mut()
            {
                lead.1 = level; // the row began with hidden samples: they take the first shown's level
            }
            if self.cell.is_none() {
                // Outside the lit cells' box (or the maze): dark up to where the row enters the box.
                let next = self.enters_box(start, step, x).clamp(x + 1, width);
                push(runs, next, 0);
                x = next;
                continue;
            }
            if !self.well_inside(point) {
                push(runs, x + 1, level); // near a boundary: this sample alone
                x += 1;
                continue;
            }
            // The last x still inside the cell: each edge's side `c0 + c1·x ≥ margin` ends at
            // (margin − c0) ⁄ c1 where c1 < 0; then checked against the points themselves.
            let mut last = (width - 1) as f32;
            for &Side { start: a, along, margin } in &self.sides.sides[self.edges.clone()] {
                let (c0, c1) = (along.perp_dot(start - a), along.perp_dot(step));
                if c1 < 0.0 {
                    last = last.min((margin - c0) / c1);
                }
            }
            let mut end =
                if last.is_finite() && last >= x as f32 { (last as usize).min(width - 1) } else { x };
            while end > x && !self.well_inside(point_at(end)) {
                end -= 1;
            }
            while end + 1 < width && self.well_inside(point_at(end + 1)) {
                end += 1;
            }
            push(runs, end + 1, level);
            x = end + 1;
        }
    }

    /// The first x after `x` at which the row `start + step × x` may be inside the lit cells' box
    /// (`usize::MAX` if never).
    fn enters_box(&self, start: Vec2, step: Vec2, x: usize) -> usize {
        let bounds = self.light.bounds();
        let (mut enter, mut leave) = (f32::NEG_INFINITY, f32::INFINITY);
        for (p, d, lo, hi) in
            [(start.x, step.x, bounds.min.x, bounds.max.x), (start.y, step.y, bounds.min.y, bounds.max.y)]
        {
            if d == 0.0 {
                if !(lo..=hi).contains(&p) {
                    return usize::MAX;
                }
                continue;
            }
            let (a, b) = ((lo - p) / d, (hi - p) / d);
            (enter, leave) = (enter.max(a.min(b)), leave.min(a.max(b)));
        }
        if enter > leave || enter.is_nan() || leave.is_nan() || leave < x as f32 {
            return usize::MAX; // never, or only behind x
        }
        // a sample before `enter` lies outside (one sample early, against rounding)
        // two samples early, against rounding: every sample before lies outside
        if enter > x as f32 + 2.0 { (enter.floor() as usize - 1).max(x + 1) } else { x + 1 }
    }

    /// `color` of floor or ceiling (`plane`) at `point` in the exit's light: tinted by the level of
    /// the cell `point` lies in ([`exit_tinted`]; the floor by [`FLOOR_EXIT_TINT`], the ceiling by
    /// [`CEILING_EXIT_TINT`]).
    fn tint(&mut self, point: Vec2, plane: u32, color: Vec3) -> Vec3 {
        let level = self.level(point);
        exit_tinted(color, level, if plane == FLOOR { FLOOR_EXIT_TINT } else { CEILING_EXIT_TINT })
    }
}

/// One side of a cell for [`CellCursor`]: an edge counter-clockwise round the cell (its start, and
/// start → end: inside is on its left), and how far to its left a point well inside lies
/// ([`INSIDE_MARGIN`] times its length).
#[derive(Clone, Copy, Debug)]
struct Side {
    start: Vec2,
    along: Vec2,
    margin: f32,
}

impl Side {
    /// Whether `point` is on the inside of this side by at least its margin.
    fn holds(&self, point: Vec2) -> bool {
        self.along.perp_dot(point - self.start) >= self.margin
    }
}

/// The sides of the cells a frame's floor and ceiling rows cross, each cell's worked out once a frame
/// (row after row crosses the same few cells) and forgotten at the next frame (the maze may differ).
#[derive(Debug, Default)]
pub(crate) struct CellSides {
    /// Per cell: where its sides start in `sides`, or `usize::MAX` when not worked out this frame.
    first: Vec<usize>,
    sides: Vec<Side>,
    /// The cells worked out this frame.
    cells: Vec<u32>,
}

impl CellSides {
    /// Forgets the frame before's cells, for a maze of `cells` cells.
    fn begin(&mut self, cells: usize) {
        for c in self.cells.drain(..) {
            self.first[c as usize] = usize::MAX;
        }
        self.first.resize(cells, usize::MAX);
        self.sides.clear();
    }

    /// Where cell `c`'s sides are in `sides` (in the order of `maze.cell_edges(c)`), worked out on
    /// its first use this frame.
    fn of(&mut self, maze: &Maze, c: u32) -> Range<usize> {
        let (first, n) = (self.first[c as usize], maze.cell_edges(c).len());
        if first != usize::MAX {
            return first..first + n;
        }
        let first = self.sides.len();
        self.sides.extend(maze.cell_edges(c).iter().map(|&e| {
            let (a, b) = maze.edge_points_ccw(e, c);
            let along = b - a;
            Side { start: a, along, margin: INSIDE_MARGIN * along.length() }
        }));
        self.first[c as usize] = first;
        self.cells.push(c);
        first..first + n
    }
}

/// Where a ray meets the floor or the ceiling (see `Renderer::fill_floor_and_ceiling`).
#[derive(Clone, Copy, Debug)]
struct PlaneHit {
    /// The plane: its height, coverage id and linear colour.
    plane: (f32, u32, Vec3),
    /// How far along the ray; `None` when the ray starts inside the plane's solid side.
    t: Option<f32>,
    /// The grid depth a wall sample must reach (or beat) to stay in front of the plane.
    wall_stays_at: f32,
    /// The fog there (0..1).
    fog: f32,
}

/// The floor and ceiling pass's scratch for one level row: the factor each sample multiplies its
/// plane's colour by (checker, headlight, fog), computed in a straight loop over an array that the
/// compiler vectorizes, where the per-sample reference (`color_at`) branches on every option.
#[derive(Debug, Default)]
struct PlaneRow {
    shade: Vec<f32>,
    /// The exit's light levels of a row that comes near a lit cell, by runs: (end, level), the
    /// runs in order from sample 0 ([`CellCursor::row_levels`]).
    level_runs: Vec<(usize, u8)>,
    /// A row's checker paints by runs: (end, paint), in order from sample 0
    /// ([`RowShade::square_runs`]).
    square_runs: Vec<(usize, f32)>,
}

/// What a level row's samples multiply their plane's colour by (checker, headlight, fog), eight at a
/// time: for the samples whose rays start at `start0 + start_step · x` and go along
/// `dir0 + dir_step · x` (both level steps), all ending on `hit`'s plane, the plane's colour times
/// the paint, plus the fog's colour times `hit.fog`, is the reference colour without glow.
#[derive(Clone, Copy, Debug)]
struct RowShade {
    t: f32x8,
    dz: f32,
    dz2: f32x8,
    lit_kept: f32x8,
    reach_per_slant: f32x8,
    filtered: bool,
    start: (Vec3, Vec3),
    dir: (Vec3, Vec3),
}

impl RowShade {
    fn new(
        hit: &PlaneHit,
        (start0, start_step): (Vec3, Vec3),
        (dir0, dir_step): (Vec3, Vec3),
        filter: Option<f32>,
        light: f32,
    ) -> RowShade {
        let s = f32x8::splat;
        RowShade {
            t: s(hit.t.unwrap_or(0.0)),
            dz: dir0.z.abs(), // the same for the whole row
            dz2: s(dir0.z * dir0.z),
            // The plane's light, then what the fog leaves of it.
            lit_kept: s(light * (1.0 - hit.fog)),
            reach_per_slant: s(filter.unwrap_or(0.0) * hit.t.unwrap_or(0.0)),
            filtered: filter.is_some(),
            start: (start0, start_step),
            dir: (dir0, dir_step),
        }
    }

    /// The two paints of the row's checker squares (light, dark) before any filter: what most
    /// groups of a row without the textures' filter are.
    fn squares(&self) -> [f32; 2] {
        let dark = f32x8::splat(1.0 - CHECKER_CONTRAST);
        [f32x8::splat(1.0) * self.lit_kept, dark * self.lit_kept].map(|paint| paint.to_array()[0])
    }

    /// Sample `x`'s point in checker squares (before [`RowShade::group`]'s `floor`s), by the scalar
    /// twins of its lane operations, in the same order: the same bits (`f32` arithmetic is IEEE in a
    /// lane or alone, and nothing is fused).
    fn squares_at(&self, x: usize) -> (f32, f32) {
        let ((start0, start_step), (dir0, dir_step)) = (self.start, self.dir);
        let (t, x) = (self.t.to_array()[0], x as f32);
        let (dx, dy) = (dir0.x + dir_step.x * x, dir0.y + dir_step.y * x);
        let px = start0.x + start_step.x * x + dx * t;
        let py = start0.y + start_step.y * x + dy * t;
        let per_square = 1.0 / CHECKER_PERIOD;
        (px * per_square, py * per_square)
    }

    /// Sample `x`'s checker square: the two floors of [`RowShade::squares_at`], as [`floor_int`]
    /// takes them (for |v| < 2^31).
    fn square_at(&self, x: usize) -> (i32, i32) {
        square_of(self.squares_at(x))
    }

    /// Fills `out` with the paints of samples `0..width` (and the last group's lanes past it), as
    /// [`RowShade::group`] gives them, from [`RowShade::square_runs`]: `false` (and `out` untouched)
    /// where that gives none.
    #[cfg(test)]
    fn paints_by_runs(&self, out: &mut Vec<f32>, width: usize) -> bool {
        let n = width.div_ceil(LANES) * LANES;
        let mut runs = Vec::new();
        if !self.square_runs(&mut runs, n) {
            return false;
        }
        out.resize(n, 0.0);
        let mut x = 0;
        for (end, paint) in runs {
            out[x..end].fill(paint);
            x = end;
        }
        assert_eq!(x, n, "the runs cover the row");
        true
    }

    /// The paints of samples `0..n`, as [`RowShade::group`] gives them, by runs of one checker
    /// square into `runs` ((end, paint), in order from 0, the last ending at `n`): `false` where
    /// that is not sure to be the same or not cheaper. Without the textures' filter a sample's
    /// paint is its square's; each of the ray's operations is monotonic in `x` (a product with a
    /// fixed factor, a sum with a fixed term, rounded to nearest), so where a row's start and
    /// direction step the same way along each axis (or one of them does not move) and the ray's
    /// length `t` is not negative, each of the two `floor`s is monotonic along the row, and a square's
    /// samples are one run: found from its first sample, an estimate of where it ends, and the exact
    /// floors checked there. Rows crossing squares every few samples keep the groups.
    fn square_runs(&self, runs: &mut Vec<(usize, f32)>, n: usize) -> bool {
        let t = self.t.to_array()[0];
        let ((_, start_step), (_, dir_step)) = (self.start, self.dir);
        let opposite = |a: f32, b: f32| (a > 0.0 && b < 0.0) || (a < 0.0 && b > 0.0);
        if self.filtered
            || n == 0
            || t.is_nan()
            || t < 0.0
            || opposite(start_step.x, dir_step.x)
            || opposite(start_step.y, dir_step.y)
        {
            return false;
        }
        let (start, end) = (self.squares_at(0), self.squares_at(n - 1));
        // floor_int's floors are these where they are well inside i32 (and every sample's lies
        // between the ends')
        let sane = |v: f32| v.abs() < 16_777_216.0; // false for NaN
        if ![start.0, start.1, end.0, end.1].into_iter().all(sane) {
            return false;
        }
        let (first, last) = (square_of(start), square_of(end));
        let crossings = first.0.abs_diff(last.0) + first.1.abs_diff(last.1);
        if crossings as usize * RUN_AT_LEAST > n {
            return false; // short runs on average: the groups are cheaper
        }
        let [light, dark] = self.squares();
        let paint = |(u, v): (i32, i32)| if (u ^ v) & 1 == 1 { dark } else { light };
        runs.clear();
        if crossings == 0 {
            // The row's ends in one square: so is every sample between them (the floors are
            // monotonic), the whole row one run (as a foveated view's tiles' rows most often are).
            runs.push((n, paint(first)));
            return true;
        }
        // where the row crosses each axis's next square, estimated as a straight line in x
        let span = (n - 1).max(1) as f64;
        // (u at 0, samples a unit of u)
        let along = |a: f32, b: f32| (f64::from(a), span / f64::from(b - a));
        let (ux, vx) = (along(start.0, end.0), along(start.1, end.1));
        // about the last sample before the line of `u` reaches the next square (checked below)
        let ends_at = |(u0, per): (f64, f64), here: i32| {
            if !per.is_finite() {
                return f64::INFINITY;
            }
            let next = if per > 0.0 { f64::from(here) + 1.0 } else { f64::from(here) };
            (next - u0) * per
        };
        let mut x = 0;
        let mut here = first;
        while x < n {
            let guess = ends_at(ux, here.0).min(ends_at(vx, here.1));
            // (`as` saturates: below x, or NaN, gives x; at or past the row's end, its last sample)
            let mut end = (guess as usize).clamp(x, n - 1);
            if end > x && self.square_at(end) != here {
                end = self.run_back(x, end, here);
            }
            let (end, next) = match (end + 1 < n).then(|| self.square_at(end + 1)) {
                Some(square) if square == here => self.run_on(end + 1, n, here),
                next => (end, next),
            };
            runs.push((end + 1, paint(here)));
            x = end + 1;
            here = next.unwrap_or(here);
        }
        true
    }

    /// The last sample before `end` (down to `x`) in square `here`: the estimate went past the run.
    /// (Not inlined: the estimate is nearly always right, and a loop inlined is vectorized at a
    /// cost every run pays.)
    #[inline(never)]
    fn run_back(&self, x: usize, mut end: usize, here: (i32, i32)) -> usize {
        while end > x && self.square_at(end) != here {
            end -= 1;
        }
        end
    }

    /// From `end`, in square `here`, the run's last sample before `n` and the next square: the
    /// estimate stopped short of the run's end.
    #[inline(never)]
    fn run_on(&self, mut end: usize, n: usize, here: (i32, i32)) -> (usize, Option<(i32, i32)>) {
        while end + 1 < n {
            let square = self.square_at(end + 1);
            if square != here {
                return (end, Some(square));
            }
            end += 1;
        }
        (end, None)
    }

    /// Fills `out` with the paints of samples `0..width` (and the last group's lanes past it), group
    /// by group.
    fn fill_paints(&self, out: &mut Vec<f32>, width: usize) {
        out.resize(width.div_ceil(LANES) * LANES, 0.0);
        for (k, out) in out.chunks_exact_mut(LANES).enumerate() {
            out.copy_from_slice(&cast::<f32x8, [f32; LANES]>(self.group(k)));
        }
    }

    /// The paints of samples `8k..8k + 8`.
    #[inline(always)]
    fn group(&self, k: usize) -> f32x8 {
        let s = f32x8::splat;
        let ((start0, start_step), (dir0, dir_step), t) = (self.start, self.dir, self.t);
        let (dark, mean) = (s(1.0 - CHECKER_CONTRAST), s(1.0 - 0.5 * CHECKER_CONTRAST));
        let per_square = s(1.0 / CHECKER_PERIOD);
        let lane = f32x8::from([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        // The same operations, in the same order, as the reference on each sample.
        let x = s((k * LANES) as f32) + lane;
        let (dx, dy) = (s(dir0.x) + s(dir_step.x) * x, s(dir0.y) + s(dir_step.y) * x);
        let px = s(start0.x) + s(start_step.x) * x + dx * t;
        let py = s(start0.y) + s(start_step.y) * x + dy * t;
        let odd = (floor_int(px * per_square) ^ floor_int(py * per_square)) & i32x8::splat(1);
        let mut square = cast::<i32x8, f32x8>(odd.simd_eq(i32x8::splat(1))).select(dark, s(1.0));
        if self.filtered {
            // checker_filtered(): the squares fade to their mean as the footprint grows.
            let length = (dx * dx + dy * dy + self.dz2).sqrt();
            let reach = self.reach_per_slant * (length / s(self.dz.max(1e-3))).min(s(8.0));
            let fade = ((reach * per_square - s(0.1)) / s(0.4)).clamp(s(0.0), s(1.0));
            square += (mean - square) * fade;
        }
        square * self.lit_kept
    }
}

/// A point's checker square, from its coordinates in squares ([`RowShade::squares_at`]): their two
/// floors, as [`floor_int`] takes them (for |v| < 2^31).
fn square_of((u, v): (f32, f32)) -> (i32, i32) {
    let floor = |v: f32| {
        let t = v as i32;
        t - i32::from(t as f32 > v)
    };
    (floor(u), floor(v))
}

/// A level row's checker squares are filled by runs ([`RowShade::square_runs`]) where they
/// average at least this many samples (a run costs about three groups' paints).
const RUN_AT_LEAST: usize = 24;

/// `floor(v)` as integers, lane by lane: truncate, then one less where that rounded up (negative
/// non-integers). Exact for |v| < 2^31 (a checker square 2^33 units from the origin is beyond any
/// maze); NaN and larger values give `i32::MIN`.
fn floor_int(v: f32x8) -> i32x8 {
    let t = v.fast_trunc_int();
    t + cast::<f32x8, i32x8>(f32x8::from_i32x8(t).simd_gt(v)) // the mask is -1 where t > v
}

/// Calls `f(x)` for each `x` where `a[x] != b[x]` (up to the shorter's length), in ascending order.
/// Eight comparisons at a time: in a frame nearly every neighbour is the same surface.
fn for_each_difference(a: &[u32], b: &[u32], mut f: impl FnMut(usize)) {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let whole = n - n % LANES;
    for (start, (a8, b8)) in (0..).step_by(LANES).zip(a.chunks_exact(LANES).zip(b.chunks_exact(LANES))) {
        let lanes = |v: &[u32]| u32x8::new(v.try_into().expect("eight"));
        let mut differing = !lanes(a8).simd_eq(lanes(b8)).to_bitmask() & 0xff;
        while differing != 0 {
            f(start + differing.trailing_zeros() as usize);
            differing &= differing - 1;
        }
    }
    for x in whole..n {
        if a[x] != b[x] {
            f(x);
        }
    }
}

/// The grid depth from which a wall stands shorter on `eye`'s picture than [`FAR_WALL_SAMPLES`]: a
/// wall spans `height · (CEILING_Z − FLOOR_Z) / (tan_extent · depth)` samples in perspective, the
/// same at every depth in orthographic (as the depth buffer holds it: grid depth, growing with the
/// distance, depth LESS).
fn short_wall_depth(eye: &Eye) -> f32 {
    let span_at_unit_depth = eye.height as f32 * (CEILING_Z - FLOOR_Z) / eye.tan_extent().y;
    match eye.camera.projection {
        Projection::Perspective => eye.depth_by_distance().grid_depth(span_at_unit_depth / FAR_WALL_SAMPLES),
        Projection::Orthographic if span_at_unit_depth < FAR_WALL_SAMPLES => f32::NEG_INFINITY,
        Projection::Orthographic => f32::INFINITY,
    }
}

/// A tile's NDC window grown by [`TILE_MARGIN`] samples: what may draw into it.
pub(crate) fn tile_window(tile: &Eye) -> [Vec2; 2] {
    let [lo, hi] = tile.window;
    let margin = TILE_MARGIN * (hi - lo) / Vec2::new(tile.width as f32, tile.height as f32);
    [lo - margin, hi + margin]
}

/// Whether two NDC boxes overlap.
pub(crate) fn meets([a, b]: [Vec2; 2], [lo, hi]: [Vec2; 2]) -> bool {
    a.x <= hi.x && b.x >= lo.x && a.y <= hi.y && b.y >= lo.y
}

/// A view as its lines are drawn over its picture ([`Renderer::draw_cell_bounds`] and the others):
/// the whole view's eye, which clips each segment once, and its tiles (a view drawn whole: its one
/// tile), each with its NDC window grown by [`TILE_MARGIN`] samples ([`tile_window`]).
pub(crate) struct Tiling<'a> {
    pub(crate) view: &'a Eye,
    pub(crate) tiles: &'a [Tile],
    pub(crate) windows: &'a [[Vec2; 2]],
}

impl Tiling<'_> {
    /// The tiles a segment clipped to the view volume (`clipped`, clip space) comes near.
    fn reached(&self, clipped: (Vec4, Vec4)) -> impl Iterator<Item = &Tile> {
        let ndc = |c: Vec4| c.truncate().truncate() / c.w;
        let (p, q) = (ndc(clipped.0), ndc(clipped.1));
        let whole = self.tiles.len() == 1;
        let near = move |window: &[Vec2; 2]| whole || meets([p.min(q), p.max(q)], *window);
        self.tiles.iter().zip(self.windows).filter(move |(_, window)| near(window)).map(|(tile, _)| tile)
    }
}

/// The samples of the picture a segment clipped to the view volume (`clipped`, clip space) passes
/// over in `tile`'s part of it, each in the picture's coordinates: projected to the tile's grid,
/// then Bresenham between the samples of its ends where the tile is the whole view, and sampled at
/// the samples' centres ([`centre_points`]) where it is one of several, so that a line crossing
/// from tile to tile, each rounding it on its own grid, leaves no gap where they meet.
fn tile_samples(tile: &Tile, (p, q): (Vec4, Vec4)) -> impl Iterator<Item = (usize, usize)> + use<> {
    let eye = &tile.eye;
    let (gp, mut gq) = (eye.grid(p), eye.grid(q));
    // A segment upright (or level) on the grid up to rounding, a vertical in a level view, stays
    // in one column (row) of samples rather than stepping at a rounding's whim.
    if (gq.x - gp.x).abs() < 1e-3 {
        gq.x = gp.x;
    }
    if (gq.y - gp.y).abs() < 1e-3 {
        gq.y = gp.y;
    }
    let (tx, ty) = tile.at;
    tile_line(tile, gp.truncate(), gq.truncate()).map(move |(x, y)| (x + tx, y + ty))
}

/// The samples of `tile`'s grid the segment `p`–`q` (on that grid) passes over: see [`tile_samples`].
fn tile_line(tile: &Tile, p: Vec2, q: Vec2) -> TileLine {
    let (w, h) = (tile.eye.width, tile.eye.height);
    if tile.eye.is_whole() {
        let (x0, y0) = (p.x.floor() as i64, p.y.floor() as i64);
        let (x1, y1) = (q.x.floor() as i64, q.y.floor() as i64);
        TileLine::Whole(line_points(x0, y0, x1, y1, w, h))
    } else {
        TileLine::Part(centre_points(p, q, w, h))
    }
}

/// The samples of a line on a tile ([`tile_line`]).
enum TileLine {
    Whole(LinePoints),
    Part(CentrePoints),
}

impl Iterator for TileLine {
    type Item = (usize, usize);

    #[inline]
    fn next(&mut self) -> Option<(usize, usize)> {
        match self {
            TileLine::Whole(points) => points.next(),
            TileLine::Part(points) => points.next(),
        }
    }
}

/// The depth a wall's fog is taken at: the least view depth (along the view direction) of its quad,
/// not below 0 (a wall reaching past the eye's plane is at the eye), so every sample of the wall takes
/// one colour. Its point nearest the eye, for two reasons: the cue stays monotone (of two walls of one
/// colour facing one way, the one whose nearest point is farther is never the lighter: fog only
/// darkens with depth), and no wall flashes as it is passed (walking straight on, every wall's nearest
/// point comes nearer, or stays at 0 once level with the eye, so no wall ever darkens; the distance to
/// a wall's middle would grow again once the eye passed it). Of the whole quad, not only its part in
/// the view: the view's edges play no part. A generated maze's walls are one cell's side each, as the
/// course files' (4 to 10 units): every colour step along a wall is a seam.
fn flat_fog_depth(eye: &Eye, e: u32, maze: &Maze) -> f32 {
    let depth = |corner: Vec3| (corner - eye.position).dot(eye.forward);
    wall_quad_world(maze, e).into_iter().map(depth).fold(f32::INFINITY, f32::min).max(0.0)
}

/// The distance from `p` to the segment `a`–`b`.
fn segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let t =
        if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + ab * t)
}

/// Whether walls `a` and `b` lie on one line (within a ten-thousandth of the longer one's length).
fn collinear(maze: &Maze, a: u32, b: u32) -> bool {
    let ((p, q), (r, s)) = (maze.edge_points(a), maze.edge_points(b));
    let (d, e) = (q - p, s - r);
    let tolerance = 1e-4 * d.length().max(e.length());
    let off_line = |point: Vec2| d.perp_dot(point - p).abs() / d.length().max(f32::MIN_POSITIVE);
    d.length() > 0.0 && off_line(r) <= tolerance && off_line(s) <= tolerance
}

#[cfg(test)]
mod tests {
    use super::*;
    use mazewalk_maze::generate::{GenOptions, generate};

    /// `r`'s samples of `camera`'s view in `charset` at `cols × rows` cells (cell aspect 0.5, the
    /// portal pass, no figures): the tests' one way to render without a frame.
    fn render_samples(
        r: &mut Renderer,
        maze: &Maze,
        camera: &Camera,
        charset: Charset,
        (cols, rows): (usize, usize),
        textures: bool,
    ) -> RenderStats {
        r.samples_with(maze, camera, charset, 0.5, Culling::Portal, cols, rows, &[], textures)
            .expect("camera")
    }

    /// A renderer reused from frame to frame (colours not cleared: each pass writes its own) gives a
    /// fresh renderer's samples, including where nothing is seen (the fog beyond the view distance).
    #[test]
    fn a_reused_renderer_leaves_nothing_of_the_last_frame() {
        let maze =
            generate(&GenOptions { width: 12, height: 12, seed: 3, loops: 0.5, ..GenOptions::default() })
                .expect("maze");
        let viewer = maze.viewer();
        let cameras = [
            // Short sight: the far ends of corridors and the horizon are beyond it.
            Camera { view_distance: 3.0, ..Camera::new(viewer.pos, viewer.dir_deg, 90.0) },
            Camera { pitch_deg: -60.0, ..Camera::new(viewer.pos, viewer.dir_deg + 90.0, 70.0) },
            Camera {
                view_distance: 2.0,
                pitch_deg: 25.0,
                ..Camera::new(viewer.pos, viewer.dir_deg + 180.0, 100.0)
            },
            Camera { projection: Projection::Orthographic, ..Camera::new(viewer.pos, 30.0, 90.0) },
        ];
        let mut reused = Renderer::new();
        let mut fog = 0;
        for charset in [Charset::Half, Charset::Ascii] {
            for camera in cameras.iter().chain(cameras.iter().rev()) {
                let render = |r: &mut Renderer| {
                    r.render(
                        &maze,
                        camera,
                        &[],
                        &RenderOptions { charset, culling: Culling::Portal, ..RenderOptions::default() },
                        Target::Samples { cols: 41, rows: 13 },
                    )
                    .expect("camera");
                };
                let mut fresh = Renderer::new();
                render(&mut fresh);
                render(&mut reused);
                assert_eq!(reused.samples(), fresh.samples(), "{charset:?} {camera:?}");
                fog += fresh.samples().id().iter().filter(|&&id| id == NONE).count();
            }
        }
        assert!(fog > 0, "no view saw the fog");
    }

    /// The lane scan finds exactly the positions a plain comparison does, at every length and offset.
    #[test]
    fn for_each_difference_finds_every_differing_position() {
        let mut seed = 1u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            seed >> 29 // 0..8: many equal neighbours, some runs of differences
        };
        for len in 0..40 {
            let a: Vec<u32> = (0..len).map(|_| next()).collect();
            let b: Vec<u32> = (0..len + 3).map(|_| next()).collect();
            for (a, b) in [(&a[..], &b[..]), (&b[..], &a[..]), (&a[..], &a[1.min(len)..])] {
                let mut found = Vec::new();
                for_each_difference(a, b, |x| found.push(x));
                let expected: Vec<usize> = (0..a.len().min(b.len())).filter(|&x| a[x] != b[x]).collect();
                assert_eq!(found, expected, "{a:?} {b:?}");
            }
        }
    }

    /// The depths of `samples`, bit for bit (a −0 is not a +0).
    fn depth_bits(samples: &SampleBuffer) -> Vec<u32> {
        samples.depth().iter().map(|d| d.to_bits()).collect()
    }

    /// The SIMD paths (walls eight samples at a time, floor and ceiling by rows) give the scalar
    /// reference's samples, in level, pitched, low, orthographic and textured views, with the exit's
    /// glow in sight.
    #[test]
    fn the_simd_paths_match_the_scalar_reference() {
        let maze =
            generate(&GenOptions { width: 6, height: 6, seed: 7, exit: true, ..GenOptions::default() })
                .expect("maze");
        let viewer = maze.viewer();
        let exit = maze.exit_point().expect("a generated maze has an exit");
        let cameras = [
            Camera::new(viewer.pos, viewer.dir_deg, 90.0),
            Camera { pitch_deg: 40.0, ..Camera::new(viewer.pos, viewer.dir_deg + 30.0, 70.0) },
            Camera { pitch_deg: -75.0, eye_z: -0.9, ..Camera::new(viewer.pos, viewer.dir_deg, 100.0) },
            Camera {
                projection: Projection::Orthographic,
                pitch_deg: -20.0,
                ..Camera::new(viewer.pos, 10.0, 90.0)
            },
            Camera { projection: Projection::Orthographic, ..Camera::new(viewer.pos, 100.0, 90.0) },
            // Standing near the exit, looking at its glow on the floor.
            Camera { pitch_deg: -30.0, ..Camera::new(exit - Vec2::new(1.5, 0.0), 0.0, 90.0) },
        ];
        let (mut glowing, mut walls, mut ortho_by_column) = (0, 0, 0);
        for camera in cameras {
            let Some(_) = maze.cell_at(camera.position) else { continue };
            for textures in [false, true] {
                let (mut fast, mut reference) = (Renderer::new(), Renderer::new());
                reference.reference_shading = true;
                let before = crate::raster::FILLED_BY_COLUMN.with(std::cell::Cell::get);
                for r in [&mut fast, &mut reference] {
                    render_samples(r, &maze, &camera, Charset::Half, (53, 17), textures);
                }
                if camera.projection == Projection::Orthographic && camera.pitch_deg == 0.0 && !textures {
                    // the level orthographic view's walls take their depths a column too
                    ortho_by_column += crate::raster::FILLED_BY_COLUMN.with(std::cell::Cell::get) - before;
                }
                let (f, r) = (fast.samples(), reference.samples());
                assert_eq!(f.id(), r.id(), "{camera:?}");
                assert_eq!(depth_bits(f), depth_bits(r), "{camera:?}");
                for (i, (a, b)) in f.color().iter().zip(r.color()).enumerate() {
                    let plane = [FLOOR, CEILING].contains(&f.id()[i]);
                    // Walls: the same operations in the same order, so the same bits; planes: the row
                    // path factors the shading differently (a few ulps).
                    let tolerance = if plane { 1e-5 } else { 0.0 };
                    assert!(
                        (*a - *b).abs().max_element() <= tolerance,
                        "{camera:?} textures {textures}: sample {i}: {a} vs {b}"
                    );
                    glowing += usize::from(b.y > b.x * 1.5 && f.id()[i] == FLOOR);
                    walls += usize::from(f.id()[i] < maze.edges().len() as u32);
                }
            }
        }
        assert!(glowing > 0, "no view saw the exit's glow on the floor");
        assert!(walls > 1000, "the views show few walls: {walls} samples");
        assert!(ortho_by_column > 0, "the level orthographic view filled no triangle by column");
    }

    /// [`plane_run`] (eight samples at a time) is the scalar row loop it replaced, bit for bit: on
    /// the walls, depths and ids of held-out views (before the planes are drawn, so groups all wall,
    /// all empty and mixed), at widths that leave tails, with a NaN depth, a wall at the plane's own
    /// depth, and the plane seen from inside it (`stays_at` −∞).
    #[test]
    fn the_plane_rows_in_lanes_are_the_scalar_loop() {
        let scalar = |(colors, depths, ids): (&mut [Vec3], &mut [f32], &mut [u32]),
                      paint: &[f32],
                      (base, fog_term, plane): (Vec3, Vec3, u32),
                      stays_at: f32| {
            for (((color, depth), id), &paint) in
                colors.iter_mut().zip(depths.iter_mut()).zip(ids.iter_mut()).zip(paint)
            {
                if *id != NONE && *depth <= stays_at {
                    continue;
                }
                (*color, *depth, *id) = (base * paint + fog_term, f32::INFINITY, plane);
            }
        };
        let (mut rows, mut mixed, mut commons) = (0, 0, 0);
        for seed in [21, 22] {
            let opts =
                GenOptions { width: 9, height: 7, seed, loops: 0.3, exit: true, ..GenOptions::default() };
            let maze = generate(&opts).expect("maze");
            for (k, (_, camera)) in crate::quality::held_out_views(&maze, seed, 8).into_iter().enumerate() {
                let mut renderer = Renderer::new();
                let width = [120, 61, 37, 5][k % 4];
                render_samples(&mut renderer, &maze, &camera, Charset::Half, (width, 20), false);
                let samples = renderer.samples();
                for y in 0..samples.height() {
                    let row = y * width..(y + 1) * width;
                    let mut depths = samples.depth()[row.clone()].to_vec();
                    let mut ids = samples.id()[row.clone()].to_vec();
                    // Walls as the planes find them: ids below NONE; anything else empty.
                    for (id, depth) in ids.iter_mut().zip(&mut depths) {
                        if [FLOOR, CEILING].contains(id) {
                            (*id, *depth) = (NONE, f32::INFINITY);
                        }
                    }
                    if y == 3 {
                        depths[width / 2] = f32::NAN;
                    }
                    let colors = samples.color()[row].to_vec();
                    // Paints all different, or a checker's two in runs of 3 to 19 (groups of one
                    // of them, of both, and of another value beside them).
                    let common = [0.43, 0.43 * (1.0 - CHECKER_CONTRAST)];
                    let paint: Vec<f32> = match y % 3 {
                        0 => (0..width).map(|x| 0.3 + (x % 7) as f32 * 0.071).collect(),
                        1 => (0..width).map(|x| common[x / (3 + y % 17) % 2]).collect(),
                        _ => (0..width).map(|x| if x % 29 == 5 { 0.5 } else { common[x / 11 % 2] }).collect(),
                    };
                    let base = Vec3::new(0.21, 0.17 + y as f32 * 0.01, 0.093);
                    let fog_term = Vec3::new(0.0131, 0.0117, 0.029);
                    let finite = depths.iter().copied().filter(|d| d.is_finite());
                    let middle = finite.clone().sum::<f32>() / finite.count().max(1) as f32;
                    for stays_at in [middle, depths[0], f32::NEG_INFINITY] {
                        let mut a = (colors.clone(), depths.clone(), ids.clone());
                        let mut b = a.clone();
                        let run = (&mut a.0[..], &mut a.1[..], &mut a.2[..]);
                        let paints = (base, fog_term, FLOOR);
                        let mut padded = paint.clone();
                        padded.resize(width.div_ceil(LANES) * LANES, f32::NAN);
                        let shade = |g: usize| {
                            f32x8::from(<[f32; LANES]>::try_from(&padded[g * LANES..][..LANES]).expect("8"))
                        };
                        commons += plane_run(run, shade, paints, stays_at, common);
                        scalar((&mut b.0, &mut b.1, &mut b.2), &paint, (base, fog_term, FLOOR), stays_at);
                        let bits =
                            |c: &[Vec3]| c.iter().map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>();
                        assert_eq!(bits(&a.0), bits(&b.0), "seed {seed}, view {k}, row {y}");
                        assert_eq!(
                            a.1.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
                            b.1.iter().map(|d| d.to_bits()).collect::<Vec<_>>()
                        );
                        assert_eq!(a.2, b.2);
                        rows += 1;
                        let walls = ids.iter().filter(|&&id| id != NONE).count();
                        mixed += usize::from(walls > 0 && walls < width && stays_at.is_finite());
                    }
                }
            }
        }
        assert!(rows > 500 && mixed > 50, "{rows} rows, {mixed} of them part wall");
        assert!(commons > 1000, "{commons} groups of one common paint");
    }

    /// The eight-lane wall fill gives the scalar reference's wall samples bit for bit (ids, depths,
    /// colours) over held-out views of generated mazes (in a cell, nose to a wall, down a corridor;
    /// level as the walk draws them, a hair off level either way, and pitched), every charset at
    /// 120×40: so the frames built from them are the reference's. Level views take their depths a
    /// column in most of their triangles (`raster::column_depths`). Planes, drawn by rows, stay
    /// within the few ulps `the_simd_paths_match_the_scalar_reference` allows them.
    #[test]
    fn the_eight_lane_walls_are_the_reference_on_held_out_views() {
        let mut wall_samples = 0;
        // triangles filled by column / all triangles the fast renders drew, level views and others
        let (mut level, mut other) = ((0, 0), (0, 0));
        for seed in [11, 12, 13] {
            let maze = generate(&GenOptions {
                width: 9,
                height: 7,
                seed,
                loops: 0.3,
                exit: true,
                ..GenOptions::default()
            })
            .expect("maze");
            for (_, camera) in crate::quality::held_out_views(&maze, seed, 15) {
                for pitch_deg in [0.0, 1e-3, -1e-4, 0.3, 12.0, -25.0] {
                    let camera = Camera { pitch_deg, ..camera };
                    for charset in Charset::ALL {
                        let (mut fast, mut reference) = (Renderer::new(), Renderer::new());
                        reference.reference_shading = true;
                        for (k, r) in [&mut fast, &mut reference].into_iter().enumerate() {
                            let before = crate::raster::FILLED_BY_COLUMN.with(std::cell::Cell::get);
                            let stats = render_samples(r, &maze, &camera, charset, (120, 40), false);
                            if k == 0 {
                                let now = crate::raster::FILLED_BY_COLUMN.with(std::cell::Cell::get);
                                let count = if pitch_deg == 0.0 { &mut level } else { &mut other };
                                (count.0, count.1) = (count.0 + now - before, count.1 + stats.triangles);
                            }
                        }
                        let (f, r) = (fast.samples(), reference.samples());
                        let what = format!("seed {seed}, {charset:?}, {camera:?}");
                        assert_eq!(f.id(), r.id(), "{what}");
                        assert_eq!(depth_bits(f), depth_bits(r), "{what}");
                        for (i, (a, b)) in f.color().iter().zip(r.color()).enumerate() {
                            if f.id()[i] < maze.edges().len() as u32 {
                                assert_eq!(
                                    a.to_array().map(f32::to_bits),
                                    b.to_array().map(f32::to_bits),
                                    "{what}: {i}"
                                );
                                wall_samples += 1;
                            } else {
                                assert!((*a - *b).abs().max_element() <= 1e-5, "{what}: {i}: {a} vs {b}");
                            }
                        }
                    }
                }
            }
        }
        assert!(wall_samples > 1_000_000, "the views show few walls: {wall_samples} samples");
        assert!(level.0 * 2 > level.1, "level views: {} of {} triangles by column", level.0, level.1);
    }

    /// A lit row works out the exit's light levels only for the samples the plane shows (not those a
    /// wall in front keeps): the samples are bit for bit those of rows that work out every sample's
    /// level, over views from lit cells of three mazes at four headings, level and pitched, and
    /// held-out views; the tint shows in many of them, beside walls.
    #[test]
    fn lit_rows_level_only_the_samples_they_show() {
        let mazes = [
            seed_71(),
            small_loops(),
            generate(&GenOptions {
                width: 12,
                height: 6,
                seed: 8,
                loops: 0.1,
                exit: true,
                ..GenOptions::default()
            })
            .expect("maze"),
        ];
        let (mut views, mut tinted, mut tinted_beside_walls) = (0, 0, 0);
        for (m, maze) in mazes.iter().enumerate() {
            let light = maze.exit_light();
            let lit: Vec<u32> = (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0).collect();
            let mut cameras: Vec<Camera> = lit
                .iter()
                .step_by(lit.len().div_ceil(12).max(1))
                .flat_map(|&cell| [20.0, 110.0, 200.0, 290.0].map(|heading| standing(maze, cell, heading)))
                .collect();
            cameras
                .extend(crate::quality::held_out_views(maze, 40 + m as u64, 6).into_iter().map(|(_, c)| c));
            for camera in cameras {
                for pitch_deg in [0.0, -20.0] {
                    let camera = Camera { pitch_deg, ..camera };
                    let mut renders = [true, false, false]
                        .map(|everywhere| Renderer { levels_everywhere: everywhere, ..Renderer::new() });
                    renders[2].no_plane_tint = true; // no exit's light on floor and ceiling
                    for r in &mut renders {
                        render_samples(r, maze, &camera, Charset::Half, (120, 40), false);
                    }
                    let [every, shown, untinted] = renders.each_ref().map(Renderer::samples);
                    let what = format!("maze {m}, {camera:?}");
                    assert_eq!(every.id(), shown.id(), "{what}");
                    assert_eq!(depth_bits(every), depth_bits(shown), "{what}");
                    let bits = |s: &SampleBuffer| -> Vec<[u32; 3]> {
                        s.color().iter().map(|c| c.to_array().map(f32::to_bits)).collect()
                    };
                    assert!(bits(every) == bits(shown), "{what}: a shown sample's colour differs");
                    let walls = maze.edges().len() as u32;
                    for (i, (a, b)) in shown.color().iter().zip(untinted.color()).enumerate() {
                        if a != b && [FLOOR, CEILING].contains(&shown.id()[i]) {
                            tinted += 1;
                            let beside = [i.wrapping_sub(1), i + 1]
                                .iter()
                                .any(|&j| shown.id().get(j).is_some_and(|&id| id < walls));
                            tinted_beside_walls += usize::from(beside);
                        }
                    }
                    views += 1;
                }
            }
        }
        assert!(views >= 100, "{views} views");
        assert!(
            tinted > 20_000 && tinted_beside_walls > 200,
            "tinted samples {tinted}, beside walls {tinted_beside_walls}"
        );
    }

    /// A level row's checker paints by runs are its groups' paints, lane for lane, bit for bit: rows
    /// of level views (perspective and orthographic) of two mazes at several widths, floor and
    /// ceiling, and made-up rows: steps either way, a row far from the origin, one on square
    /// boundaries at −0, widths 0 to 333. A row whose start and direction step apart is not taken
    /// (its floors are not sure to be monotonic), nor one with the textures' filter. Fails if the
    /// steps' test is dropped, or if the floors are off at an integer (both tried).
    #[test]
    fn plane_paints_by_runs_are_the_groups_paints() {
        let (mut rows, mut by_runs) = (0, 0);
        let one_square = std::cell::Cell::new(0); // rows of one square: one run, found from the ends alone
        let check = |shade: &RowShade, width: usize| -> bool {
            let mut out = vec![f32::NAN; 3];
            if !shade.paints_by_runs(&mut out, width) {
                assert_eq!(out.len(), 3, "left untouched");
                return false;
            }
            let n = width.div_ceil(LANES) * LANES;
            let groups: Vec<u32> =
                (0..n / LANES).flat_map(|g| shade.group(g).to_array()).map(f32::to_bits).collect();
            let runs: Vec<u32> = out.iter().map(|p| p.to_bits()).collect();
            assert_eq!(runs, groups, "{shade:?}, width {width}");
            if n > 0 && shade.square_at(0) == shade.square_at(n - 1) {
                one_square.set(one_square.get() + 1);
            }
            true
        };
        let hit = |t: f32| PlaneHit {
            plane: (FLOOR_Z, FLOOR, Vec3::ONE),
            t: Some(t),
            wall_stays_at: 0.0,
            fog: 0.3,
        };
        let mazes = [
            seed_71(),
            generate(&GenOptions { width: 9, height: 7, seed: 5, ..GenOptions::default() }).expect("maze"),
        ];
        for (m, maze) in mazes.iter().enumerate() {
            for (k, (_, camera)) in
                crate::quality::held_out_views(maze, 60 + m as u64, 8).into_iter().enumerate()
            {
                for projection in [Projection::Perspective, Projection::Orthographic] {
                    let camera = Camera { pitch_deg: 0.0, projection, ..camera };
                    let width = [120, 61, 37, 5, 200, 1][k % 6];
                    let aspect = Charset::Half.sample_aspect(0.5);
                    let eye = camera.eye(width, 40, aspect).expect("eye");
                    // and the tiles of the view foveated, 20 to 40 samples wide: most of their rows
                    // lie in one square
                    let view = Camera { fovea: true, ..camera }.eye(120, 80, aspect).expect("eye");
                    for eye in std::iter::once(eye).chain(view.tiles().into_iter().map(|tile| tile.eye)) {
                        for y in 0..eye.height {
                            let gy = y as f32 + 0.5;
                            let (start0, dir0) = eye.ray(0.5, gy);
                            let (start1, dir1) = eye.ray(1.5, gy);
                            let (start_step, dir_step) = (start1 - start0, dir1 - dir0);
                            let z = if dir0.z < 0.0 { FLOOR_Z } else { CEILING_Z };
                            let t = if dir0.z == 0.0 { 0.0 } else { (z - start0.z) / dir0.z };
                            if t.is_nan() || t < 0.0 {
                                continue;
                            }
                            let shade =
                                RowShade::new(&hit(t), (start0, start_step), (dir0, dir_step), None, 0.7);
                            rows += 1;
                            by_runs += usize::from(check(&shade, eye.width));
                        }
                    }
                }
            }
        }
        // made-up rows: steps either way, against each other, tiny, far out
        let mut runs_before = by_runs;
        for (i, (s0, ss, d0, ds, t)) in [
            (
                Vec3::new(3.0, 7.0, 0.0),
                Vec3::new(0.01, -0.02, 0.0),
                Vec3::new(1.0, 0.5, -0.5),
                Vec3::new(0.02, -0.03, 0.0),
                4.0,
            ),
            (
                Vec3::new(-3.0, 1.0, 0.0),
                Vec3::new(-0.1, 0.0, 0.0),
                Vec3::new(-1.0, 0.2, -0.5),
                Vec3::new(-0.01, 0.0, 0.0),
                0.0,
            ),
            (
                Vec3::new(1e6, -2e6, 0.0),
                Vec3::new(0.001, 0.001, 0.0),
                Vec3::new(0.3, 1.0, -0.5),
                Vec3::new(0.001, 0.0, 0.0),
                9.0,
            ),
            (
                Vec3::new(0.5, 0.5, 0.0),
                Vec3::new(0.01, 0.0, 0.0),
                Vec3::new(0.3, 1.0, -0.5),
                Vec3::new(-0.001, 0.0005, 0.0),
                9.0,
            ),
            (Vec3::new(-0.0, 0.0, 0.0), Vec3::ZERO, Vec3::new(0.0, -0.0, -0.5), Vec3::ZERO, 2.0),
        ]
        .into_iter()
        .enumerate()
        {
            for width in [0, 1, 8, 9, 120, 333] {
                let shade = RowShade::new(&hit(t), (s0, ss), (d0, ds), None, 0.9);
                let taken = check(&shade, width);
                (rows, by_runs) = (rows + 1, by_runs + usize::from(taken));
                if i == 3 && width > 8 {
                    // x steps +0.01 by the start and −0.001·9 by the direction: not sure to be monotonic
                    assert_eq!(by_runs, runs_before, "row {i}, width {width}: runs across steps apart");
                }
                runs_before = by_runs;
            }
        }
        // the textures' filter: never by runs
        let filtered = RowShade::new(
            &hit(2.0),
            (Vec3::ZERO, Vec3::X * 0.01),
            (Vec3::NEG_Z, Vec3::X * 0.01),
            Some(0.01),
            0.9,
        );
        assert!(!filtered.paints_by_runs(&mut Vec::new(), 120));
        let one_square = one_square.get();
        assert!(rows > 1000 && by_runs > rows / 4, "{by_runs} of {rows} rows by runs");
        assert!(one_square > by_runs / 4, "{one_square} of {by_runs} rows by runs in one square");
    }

    /// Whole renders with level rows' paints by runs are those by groups, bit for bit (ids, depths,
    /// colours), and so are their frames in every colour depth: held-out views of three mazes (two
    /// generated, the built-in one), level, a hair off level and pitched, every charset, the
    /// textures' filter on and off.
    #[test]
    fn renders_with_plane_runs_are_those_by_groups() {
        let mazes = [seed_71(), small_loops(), mazewalk_maze::builtin().expect("built-in maze")];
        let (mut views, mut frames_compared) = (0, 0);
        for (m, maze) in mazes.iter().enumerate() {
            for (k, (_, camera)) in
                crate::quality::held_out_views(maze, 80 + m as u64, 6).into_iter().enumerate()
            {
                for pitch_deg in [0.0, 0.001, -15.0] {
                    let camera = Camera { pitch_deg, ..camera };
                    let charset = Charset::ALL[k % 4];
                    let textures = k % 3 == 2;
                    let mut renders =
                        [false, true].map(|off| Renderer { plane_runs_off: off, ..Renderer::new() });
                    for r in &mut renders {
                        render_samples(r, maze, &camera, charset, (120, 40), textures);
                    }
                    let [runs, groups] = renders.each_ref().map(Renderer::samples);
                    let what = format!("maze {m}, view {k}, {camera:?}");
                    assert_eq!(runs.id(), groups.id(), "{what}");
                    assert_eq!(depth_bits(runs), depth_bits(groups), "{what}");
                    let bits = |s: &SampleBuffer| -> Vec<[u32; 3]> {
                        s.color().iter().map(|c| c.to_array().map(f32::to_bits)).collect()
                    };
                    assert!(bits(runs) == bits(groups), "{what}: colours differ");
                    // and the frames, in every colour depth (which sets the exit's light on the planes)
                    for color_depth in
                        [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16, ColorDepth::None]
                    {
                        let options =
                            RenderOptions { charset, color_depth, textures, ..RenderOptions::default() };
                        let frames = renders.each_mut().map(|r| {
                            let mut frame = Frame::new(120, 40);
                            let region = frame.region();
                            r.render(maze, &camera, &[], &options, Target::Frame(&mut frame, region))
                                .expect("render");
                            frame
                        });
                        assert!(
                            frames[0].cells() == frames[1].cells(),
                            "{what}, {color_depth:?}: frames differ"
                        );
                        frames_compared += 1;
                    }
                    views += 1;
                }
            }
        }
        assert!(views >= 50 && frames_compared >= 200, "{views} views, {frames_compared} frames");
    }

    /// Seed 71's 20 × 15 maze (as the exit-light tests and the pictures use it).
    fn seed_71() -> Maze {
        generate(&GenOptions::walk(20, 15, 71)).expect("maze")
    }

    /// A small generated maze with loops and an exit (9 × 7, seed 5, loops 0.3).
    fn small_loops() -> Maze {
        generate(&GenOptions {
            width: 9,
            height: 7,
            seed: 5,
            loops: 0.3,
            exit: true,
            ..GenOptions::default()
        })
        .expect("maze")
    }

    /// `camera`'s view at 120 × 40 in `color_depth`, floor and ceiling in the exit's light or not:
    /// the samples' colours and ids, the frame, and the cells the portal pass visited.
    fn view(
        maze: &Maze,
        camera: &Camera,
        color_depth: ColorDepth,
        plane_tint_off: bool,
    ) -> (Vec<Vec3>, Vec<u32>, Frame, Vec<u32>) {
        let mut frame = Frame::new(120, 40);
        let region = frame.region();
        let mut renderer = Renderer { plane_tint_off, ..Renderer::new() };
        let options = RenderOptions { color_depth, ..RenderOptions::default() };
        renderer.render(maze, camera, &[], &options, Target::Frame(&mut frame, region)).expect("camera");
        let samples = renderer.samples();
        (samples.color().to_vec(), samples.id().to_vec(), frame, renderer.portal.visited.clone())
    }

    /// The camera at cell `cell`'s centre facing `heading`, as the walk stands there.
    fn standing(maze: &Maze, cell: u32, heading: f32) -> Camera {
        let v = maze.viewer();
        Camera {
            eye_z: v.z,
            min_vfov_deg: maze.min_vfov_deg(),
            ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
        }
    }

    /// How far a colour's chromaticity is from the exit's light's.
    fn off_exit_hue(c: Vec3) -> f32 {
        let chromaticity = |c: Vec3| c / (c.x + c.y + c.z).max(1e-6);
        chromaticity(c).distance(chromaticity(EXIT_GLOW))
    }

    /// Issue #39: a floor or ceiling sample lying in a lit cell turns toward the exit's hue, its
    /// luminance kept; one in a dark cell is drawn exactly as without the exit's light. In 256
    /// colours the tint shows in the frame.
    #[test]
    fn floor_and_ceiling_in_lit_cells_lean_toward_the_exit_and_dark_ones_do_not() {
        let maze = seed_71();
        let light = maze.exit_light();
        let (mut changed, mut unchanged, mut frames_changed) = ([0usize; 2], 0usize, 0usize);
        let level_at = |p: Vec2| maze.cell_at(p).map_or(0, |c| light.level(c));
        for cell in 0..maze.cell_count() as u32 {
            for heading in [0.0, 90.0, 180.0, 270.0] {
                let camera = standing(&maze, cell, heading);
                let eye = camera.eye(120, 80, Charset::Half.sample_aspect(0.5)).expect("camera");
                let (lit, ids, ..) = view(&maze, &camera, ColorDepth::TrueColor, false);
                let (unlit, unlit_ids, ..) = view(&maze, &camera, ColorDepth::TrueColor, true);
                assert_eq!(ids, unlit_ids);
                for (k, (&a, &b)) in lit.iter().zip(&unlit).enumerate() {
                    let (plane, z) = match ids[k] {
                        FLOOR => (0, FLOOR_Z),
                        CEILING => (1, CEILING_Z),
                        _ => {
                            assert_eq!(a, b, "cell {cell} heading {heading}: wall sample {k}");
                            continue;
                        }
                    };
                    // A floor or ceiling sample beside a wall may carry that wall's edge.
                    if [k.wrapping_sub(120), k + 120, k.wrapping_sub(1), k + 1]
                        .iter()
                        .any(|&n| ids.get(n).is_some_and(|&id| id < CEILING))
                    {
                        continue;
                    }
                    // A line across an opening the light comes through is the light itself, not
                    // the plane tinted ([`way_light`]: `glow_way` tests it).
                    if a == way_light(a) {
                        continue;
                    }
                    // Where the sample's ray meets its plane, and the levels there and just round it
                    // (a sample on a boundary between cells of two levels is left out).
                    let (start, dir) = eye.ray((k % 120) as f32 + 0.5, (k / 120) as f32 + 0.5);
                    let p = (start + dir * ((z - start.z) / dir.z)).truncate();
                    let near =
                        [Vec2::ZERO, Vec2::X, -Vec2::X, Vec2::Y, -Vec2::Y].map(|d| level_at(p + d * 0.01));
                    let what = format!("cell {cell} heading {heading} sample {k} at {p}: {a} lit, {b} unlit");
                    if near.iter().all(|&l| l == 0) {
                        assert_eq!(a, b, "{what}: dark, yet tinted");
                        unchanged += 1;
                    } else if near.iter().all(|&l| l > 0) {
                        assert!(off_exit_hue(a) < off_exit_hue(b), "{what}: lit, not nearer the exit's hue");
                        assert!(
                            (luminance(a) - luminance(b)).abs() <= 1e-3 * luminance(b) + 1e-6,
                            "{what}: luminance not kept"
                        );
                        changed[plane] += 1;
                    }
                }
                if light.level(cell) > 0 && heading == 0.0 {
                    let (_, _, with, _) = view(&maze, &camera, ColorDepth::Ansi256, false);
                    let (_, _, without, _) = view(&maze, &camera, ColorDepth::Ansi256, true);
                    frames_changed += usize::from(with != without);
                }
            }
        }
        eprintln!(
            "tinted floor, ceiling {changed:?}, unchanged {unchanged}, 256-colour frames changed {frames_changed}"
        );
        assert!(changed[0] > 5_000 && changed[1] > 2_000, "tinted floor, ceiling samples: {changed:?}");
        assert!(unchanged > 500_000, "samples beyond the light: {unchanged}");
        assert!(frames_changed >= 5, "256-colour frames the tint shows in: {frames_changed}");
    }

    /// Issue #39: where the exit's light is brighter its tint on the floor is stronger: at the centre
    /// of each lit cell, the floor at the viewer's feet (looking straight down) is further toward the
    /// exit's hue the higher the cell's level, and the exit cell's floor the furthest.
    #[test]
    fn the_floor_glow_grows_toward_the_exit() {
        let maze = seed_71();
        let light = maze.exit_light();
        let exit = maze.exit().expect("exit").cell;
        let mut by_level: Vec<(u8, f32)> = Vec::new();
        for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0 && c != exit) {
            let camera = Camera { pitch_deg: -89.0, ..standing(&maze, cell, 0.0) };
            let (lit, ids, ..) = view(&maze, &camera, ColorDepth::TrueColor, false);
            let (unlit, ..) = view(&maze, &camera, ColorDepth::TrueColor, true);
            let middle = 20 * 2 / 2 * 120 + 60; // the middle sample of the 120 × 80 half-block grid
            assert_eq!(ids[middle], FLOOR, "cell {cell}: looking down");
            by_level.push((light.level(cell), off_exit_hue(unlit[middle]) - off_exit_hue(lit[middle])));
        }
        by_level.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        assert!(by_level.len() >= 8, "{by_level:?}");
        for pair in by_level.windows(2) {
            let ((la, da), (lb, db)) = (pair[0], pair[1]);
            assert!(da > 0.0, "level {la}: no tint at the feet");
            if la < lb {
                assert!(db > da, "level {lb} ({db}) not further toward the exit than level {la} ({da})");
            }
        }
    }

    /// Issue #39: in 16 colours (a tinted floor's nearest entry could be the beacon's green) and
    /// without colour (ascii shows lightness only) the exit's light draws nothing on floor or ceiling:
    /// every lit cell's four views give the same frame and samples as with it off.
    #[test]
    fn sixteen_colours_and_no_colour_draw_no_tint_on_floor_or_ceiling() {
        let maze = seed_71();
        let light = maze.exit_light();
        let mut views = 0;
        for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0) {
            for heading in [0.0, 90.0, 180.0, 270.0] {
                let camera = standing(&maze, cell, heading);
                for depth in [ColorDepth::Ansi16, ColorDepth::None] {
                    let (a, _, frame_a, _) = view(&maze, &camera, depth, false);
                    let (b, _, frame_b, _) = view(&maze, &camera, depth, true);
                    assert!(a == b && frame_a == frame_b, "cell {cell} heading {heading} {depth:?}");
                    views += 1;
                }
            }
        }
        assert!(views >= 64, "{views}");
    }

    /// Red-team pass 9: brute force (and the portal pass past its cap) listed every opening of the
    /// maze for the floor's and ceiling's cell lines, and clipped each to the view every frame: 8
    /// million on a 2046 × 2046 floor of half-unit tiles, nearly all beyond the far plane. Now only
    /// those within the view's reach ([`Eye::reach`]) are listed, and still every one of which any
    /// part is in view, on the floor or the ceiling, perspective or orthographic, whatever the pitch.
    #[test]
    fn brute_forces_cell_lines_are_the_openings_the_view_can_reach() {
        let n = 120; // 4-unit tiles: 480 units across, far more than the view reaches
        let row = |r: usize| format!("#{}{}#", if r == n / 2 { '@' } else { '.' }, ".".repeat(n - 1));
        let rows: Vec<String> = (0..n).map(row).collect();
        let wall = "#".repeat(n + 2);
        let text = format!("mazewalk-grid 1\ntile 4\nfacing east\n\n{wall}\n{}\n{wall}\n", rows.join("\n"));
        let floor = mazewalk_maze::grid::parse_str("floor.grid", &text).unwrap();
        let centre = Vec2::splat(n as f32 * 2.0);
        // (at 170° the view reaches past the floor's corners: every opening stays)
        for (projection, fov, pitch, fewer) in [
            (Projection::Perspective, 90.0, 0.0, true),
            (Projection::Perspective, 170.0, -60.0, false),
            (Projection::Orthographic, 90.0, 45.0, true),
        ] {
            let camera = Camera { projection, pitch_deg: pitch, ..Camera::new(centre, 30.0, fov) };
            let eye = camera.eye(120, 40, 0.5).unwrap();
            let mut renderer = Renderer::new();
            renderer.choose_cell_lines(&floor, &eye, Culling::None);
            let chosen = &renderer.lines;
            let openings = floor.portal_count();
            let count = chosen.len();
            assert!(!fewer || count < openings / 2, "{projection:?} {fov}°: {count} of {openings} openings");
            for e in 0..floor.edges().len() as u32 {
                let (a, b) = floor.edge_points(e);
                let seen = [FLOOR_Z, CEILING_Z]
                    .iter()
                    .any(|&z| clip_segment(&eye, a.extend(z), b.extend(z)).is_some());
                if seen && !floor.edge(e).opaque {
                    assert!(
                        chosen.binary_search(&e).is_ok(),
                        "{projection:?} {fov}°: opening {e} in view, not chosen"
                    );
                }
            }
        }
    }
}
