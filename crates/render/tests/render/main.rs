//! The render crate's integration tests, one binary (one link) for all of them: frames as text, the
//! rasterizer and lines, golden frames, the picture and its quality measures, the portal pass against
//! brute force, figures.

mod cell_lines;
mod chalk;
mod exit_light;
mod far_wall_height;
mod flat_walls;
mod glyph_frames;
mod nose_to_wall;
mod openings;
mod picture_quality;
mod raster_fill;
mod raster_lines;
mod render_golden;
mod render_picture;
mod render_portal;
mod render_sprites;
mod tone;
mod wall_floor;
