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
//! [`ColorDepth`]: crate::frame::ColorDepth

pub mod glyph;
pub mod line;
pub mod palette;
pub mod raster;
pub mod samples;
pub mod shade;

pub use glyph::{Charset, to_frame};
pub use line::{draw_line, line_glyph, line_points};
pub use raster::{ScreenVertex, Varying, fill_polygon, fill_triangle};
pub use samples::SampleBuffer;
