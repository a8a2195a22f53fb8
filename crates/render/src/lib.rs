//! The CPU renderer: a maze and a camera in, a character [`Frame`](mazewalk_term::Frame) out — pure
//! data in, pure data out. The whole pipeline is the three functions at the end of this file, one stage
//! a line; each stage is a method of [`Renderer`] in [`pipeline`], the matrices are `mazewalk_math`'s.
//!
//! ```text
//! maze + camera
//!   ─eye()───────▶ world→view (look-at), view→clip (projection), NDC→grid (viewport): Eye   camera.rs
//!   ─portal pass─▶ the walls that can be seen, cell to cell through openings              portal.rs
//!   each wall: quad (world) ─view─▶ view ─projection─▶ clip ─clip─▶ clip ─÷w─▶ NDC ─viewport─▶ grid
//!              ─raster (top-left rule, depth LESS)─▶ samples, shaded: sun and headlight through the
//!              normal matrix, fog by depth                                      wall.rs, raster.rs, shade.rs
//!   floor, ceiling: each sample's ray meets z = ∓1 where no wall is nearer                 pipeline.rs
//!   figures, the exit's beacon: billboards through the same chain                          sprite.rs
//!   edges, seams, cell lines, door jambs, chalk marks; ascii outlines (Bresenham)           pipeline.rs
//!   ─glyphs──────▶ half blocks, quadrants, sextants or ascii, colours to the depth ─▶ Frame glyph.rs, palette.rs
//! ```
//!
//! The grid is measured in samples (origin top-left, y down, sample `(x, y)` centred at
//! `(x + 0.5, y + 0.5)`); a terminal cell holds [`Charset::samples_per_cell`] of them. Colours are linear
//! RGB in 0..1 until [`glyph::to_frame`] encodes them to sRGB and quantizes to the [`ColorDepth`].
//! Depth is in [0, 1], smaller = nearer, tested LESS. The conventions (handedness, depth range, column
//! vectors) are the math crate's, stated once in its README.
//!
//! # The pieces, called by hand
//!
//! ```
//! use glam::{Vec2, Vec3};
//! use mazewalk_term::frame::{ColorDepth, Frame};
//! use mazewalk_render::shade::{Fog, headlight, lit};
//! use mazewalk_render::{Charset, RenderOptions, SampleBuffer, GridVertex, draw_line, fill_polygon, to_frame};
//!
//! let (cols, rows, charset) = (8, 3, Charset::Half);
//! let (sx, sy) = charset.samples_per_cell();
//! let mut samples = SampleBuffer::new(cols * sx, rows * sy);
//! samples.clear(Vec3::ZERO);
//! // One wall polygon after clipping, divide by w and viewport; attrs = view-space position here.
//! let wall = [(1.0, 1.0, -2.0), (7.0, 1.0, -2.0), (7.0, 5.0, -2.0), (1.0, 5.0, -2.0)].map(|(x, y, z)| {
//!     GridVertex { pos: Vec2::new(x, y), depth: 0.5, inv_w: 1.0 / 2.0, attrs: Vec3::new(0.0, 0.0, z) }
//! });
//! let fog = Fog { color: Vec3::ZERO, half: 8.0, end: 20.0 };
//! let (albedo, normal_view) = (Vec3::new(0.6, 0.3, 0.3), Vec3::Z);
//! let wall_id = 7;
//! let written = fill_polygon(&mut samples, &wall, wall_id, |view: Vec3| {
//!     fog.apply(lit(albedo, headlight(normal_view), 0.2), view.z.abs()) // Lambert + fog by depth
//! });
//! assert_eq!(written, 6 * 4);
//! // Ascii outlines: an edge at the wall's depth (sample aspect from the cell aspect).
//! draw_line(&mut samples, Vec3::new(1.0, 1.0, 0.5), Vec3::new(7.0, 1.0, 0.5), charset.sample_aspect(0.5), 1e-4);
//! let mut frame = Frame::new(cols, rows);
//! let region = frame.region(); // the whole frame
//! let options = RenderOptions { charset, color_depth: ColorDepth::TrueColor, ..RenderOptions::default() };
//! to_frame(&samples, &options, &mut frame, region);
//! // Half blocks: `▀` inks the top sample over the bottom one; a cell of one colour is a blank in it.
//! assert_eq!(frame.lines(), [" ▀▀▀▀▀▀ ", "        ", " ▀▀▀▀▀▀ "]);
//! ```
//!
//! [`ColorDepth`]: mazewalk_term::frame::ColorDepth

#![forbid(unsafe_code)]

pub mod camera;
pub mod fovea;
pub mod glyph;
pub mod line;
pub mod options;
pub mod oracle;
pub mod palette;
pub mod picture;
pub mod pipeline;
pub mod portal;
pub mod quality;
pub mod raster;
pub mod samples;
pub mod shade;
pub mod sprite;
pub mod wall;

pub use camera::{Camera, CameraError, Eye, Projection, Tile};
pub use glyph::to_frame;
pub use line::{draw_line, line_glyph, line_points};
pub use options::{Charset, Culling, Ramp, RenderOptions};
pub use pipeline::{RenderStats, Renderer, Target};
pub use portal::{PortalPass, PortalStats};
pub use raster::{GridVertex, Varying, fill_polygon, fill_triangle};
pub use samples::SampleBuffer;
pub use sprite::Sprite;

use pipeline::{Light, Shading, fog_of};

/// The pipeline in one screen.
impl Renderer {
    /// The pipeline up to the samples (no glyphs): what the frame is made of, sample by sample.
    ///
    /// The whole chain in order, one stage a line (tinyrenderer's `our_gl` in spirit); every stage is
    /// a method below, and the matrices are the math crate's. A foveated view ([`fovea`]) runs the
    /// stages once per tile, each tile an eye with a plain viewport over its band of NDC.
    #[allow(clippy::too_many_arguments)]
    fn samples_with(
        &mut self,
        maze: &mazewalk_maze::Maze,
        camera: &Camera,
        charset: Charset,
        cell_aspect: f32,
        culling: Culling,
        cols: usize,
        rows: usize,
        sprites: &[Sprite],
        textures: bool,
    ) -> Result<RenderStats, CameraError> {
        let (sx, sy) = charset.samples_per_cell();
        let view = camera.eye(cols * sx, rows * sy, charset.sample_aspect(cell_aspect))?; // look-at, projection, viewport
        self.begin_view(maze); // what the tiles of one view share, forgotten
        let mut stats = self.choose_walls(maze, &view, culling); // portal pass: cell to cell through openings
        self.ascii_lines = charset == Charset::Ascii;
        self.faced.clear(); // ascii: which walls are seen square on, set by the outlines
        let tiles = view.tiles();
        let flat = !textures && !self.reference_shading; // walls drawn flat, one colour a wall
        self.wall_boxes(maze, &view, tiles.len(), flat); // a foveated view: each wall's box on the screen
        self.choose_cell_lines(maze, &view, culling); // the openings' lines, the way's
        let visible = |cell: u32| culling == Culling::None || self.portal.was_visited(cell);
        self.sprites.prepare(&view, sprites, visible); // the figures in view, nearest first
        let tiled = tiles.len() > 1;
        for (k, tile) in tiles.iter().enumerate() {
            let eye = &tile.eye; // the whole view, or one tile of a foveated view
            self.enter_tile(&view, tile, k); // a foveated view's tile: drawn in its place in the picture
            self.walls_in(eye); // a foveated view's tile: the walls that reach it
            stats.add(self.draw(maze, eye, Shading::Color, textures)); // walls, floor, ceiling
            let visible = |cell: u32| culling == Culling::None || self.portal.was_visited(cell);
            let fog = fog_of(eye);
            stats.samples_written += self.sprites.draw(&mut self.samples, eye, &fog, sprites); // figures
            if let Some(point) = maze.exit().filter(|exit| visible(exit.cell)).and(maze.exit_point()) {
                stats.samples_written += self.sprites.draw_beacon(&mut self.samples, eye, &fog, point); // the exit
            }
            if !tiled && !self.no_edges {
                self.draw_edges(maze, eye); // where surfaces meet: edges; where cells meet along a wall: seams
            }
            self.place_tile(&view, tile); // a foveated view: the tile's figures' labels into the view's
        }
        if tiled && !self.no_edges {
            self.picture_edges(maze, &tiles); // the edges, once over the whole picture
        }
        self.finish_tiles(&view); // a foveated view: its picture becomes the samples
        self.draw_lines(maze, &view, &tiles, culling, charset, cell_aspect); // cell lines, jambs, chalk, outlines
        stats.walls_drawn = self.wall_count();
        Ok(stats)
    }

    /// What is drawn over the surfaces once their edges are, over the whole picture: the cell lines
    /// on floor and ceiling, the jambs, the chalk crosses and, in ascii, the walls' outlines. Each
    /// segment is clipped once against `view`'s volume and drawn through every tile it reaches (a
    /// view drawn whole: its one tile), so that what a line looks at beside it is the picture's.
    fn draw_lines(
        &mut self,
        maze: &mazewalk_maze::Maze,
        view: &Eye,
        tiles: &[Tile],
        culling: Culling,
        charset: Charset,
        cell_aspect: f32,
    ) {
        let mut windows = std::mem::take(&mut self.tile_windows);
        windows.clear();
        windows.extend(tiles.iter().map(|tile| pipeline::tile_window(&tile.eye)));
        let tiling = pipeline::Tiling { view, tiles, windows: &windows };
        if !self.no_edges {
            self.draw_cell_bounds(maze, &tiling); // cell boundaries on floor and ceiling: fainter lines
            self.draw_jambs(maze, &tiling); // where a wall ends at an opening: a light line, seen from afar
            self.draw_chalk(maze, &tiling, culling); // the walked cells' chalk crosses on the floor
        }
        if charset == Charset::Ascii {
            let aspect = charset.sample_aspect(cell_aspect);
            self.outline_visible_walls(maze, &tiling, aspect); // Bresenham edges
        }
        self.tile_windows = windows;
    }

    /// The 3D part of the pipeline for `eye`, once its walls are chosen ([`Renderer::choose_walls`]):
    /// draw each wall through the whole chain, then floor and ceiling where no wall is nearer.
    fn draw(
        &mut self,
        maze: &mazewalk_maze::Maze,
        eye: &Eye,
        shading: Shading,
        textures: bool,
    ) -> RenderStats {
        self.begin(maze, eye); // every sample uncovered, the buffer sized to the grid
        let mut stats = RenderStats::default();
        let light = Light::of(eye, maze, true); // the fog, the sun and the headlight of this view
        for k in 0..self.walls.len() {
            let e = self.walls[k]; // model → world → view → clip → clip → ÷w → NDC → viewport → raster
            let (triangles, written) = self.draw_wall(maze, eye, &light, e, shading, textures);
            (stats.triangles, stats.samples_written) =
                (stats.triangles + triangles, stats.samples_written + written);
        }
        let filter = textures.then_some(light.per_sample); // floor and ceiling: each ray meets z = ∓1
        let glow = light.exit_light.filter(|_| !self.no_plane_tint).map(|exit_light| (maze, exit_light));
        self.fill_floor_and_ceiling(eye, &light.fog, shading, maze.exit_point(), filter, glow); // tinted by the exit's light
        stats
    }
}
