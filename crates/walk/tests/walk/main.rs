//! The walk crate's integration tests, one binary (one link) for all of them: controls (taps and
//! holds), the map's fog, overlays, frames at every size, sessions through a vt100 screen, flow control
//! on a slow link, the colour-depth questions.

mod chalk;
mod common;
mod controls;
mod ghost;
mod look_ahead;
mod map_fog;
mod overlays;
mod render_frames;
mod rep;
mod run_codec;
mod sessions;
mod slow_link;
mod tolerance_picture;
mod truecolor;
