//! The renderer's back end: samples, rasterization, shading and glyphs — pure data in, pure data out.
//!
//! ```text
//! clipped polygons in grid space ─raster─▶ SampleBuffer (colour, depth, id, outline) ─glyph─▶ Frame
//! ```
//!
//! The grid is measured in samples (origin top-left, y down, sample `(x, y)` centred at
//! `(x + 0.5, y + 0.5)`); a terminal cell holds [`Charset::samples_per_cell`] of them. Colours are linear
//! RGB in 0..1 until [`glyph::to_frame`] encodes them to sRGB and quantizes to the [`ColorDepth`].
//! Depth is in [0, 1], smaller = nearer, tested LESS.
//!
//! # How the pipeline calls it
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

pub use camera::{Camera, CameraError, Eye, Projection};
pub use glyph::to_frame;
pub use line::{draw_line, line_glyph, line_points};
pub use options::{Charset, Culling, Ramp, RenderOptions};
pub use pipeline::{RenderStats, Renderer, Target};
pub use portal::{PortalPass, PortalStats};
pub use raster::{GridVertex, Varying, fill_polygon, fill_triangle};
pub use samples::SampleBuffer;
pub use sprite::Sprite;
