//! mazewalk: a first-person 3D maze walkthrough for the terminal.
//!
//! The library holds everything testable; the `mazewalk` binary only wires it to the command line and
//! the terminal. Everything is pure — data in, data out, time passed in as seconds — but four edges:
//! [`term`] (this process's terminal), [`app::run`] (the local walk's loop), [`maze::load`] (reading a
//! file) and `serve::ssh` (the SSH server that runs many players' sessions, Unix only). One player's
//! walk is an [`app::Session`]: terminal bytes in ([`input`]), frame bytes out.
//!
//! # The pipeline
//!
//! ```text
//! maze (2D plan) ─extrude─▶ world ─view─▶ view ─projection─▶ clip ─clip polygons─▶ clip
//!     ─divide by w─▶ NDC ─viewport─▶ grid samples (depth-tested) ─glyphs─▶ Frame ─encoder─▶ bytes
//! ```
//!
//! # Conventions
//!
//! Stated once here (and in ARCHITECTURE.md); every function repeats the part it relies on in one line.
//!
//! | what | convention |
//! |---|---|
//! | vectors | column vectors; a matrix transforms a point as `M * p`, so `T * R * S` scales first |
//! | storage | column-major (glam's `Mat4` stores `x_axis, y_axis, z_axis, w_axis` columns) |
//! | world axes | maze plane is x (east) / y (north); z is up; floor z = -1, ceiling z = +1 ([`maze::geometry`]); right-handed |
//! | angles | radians inside the math; degrees only at the edges (maze files, CLI, HUD) |
//! | heading (yaw) | counter-clockwise from +x in the maze plane (the maze files' `dir`); [`maze::geometry::heading_dir`] turns it into a direction |
//! | pitch | positive looks up, clamped to ±90° exactly (the basis is built from yaw and pitch: no flip) |
//! | view space, right-handed | camera at the origin looking down -Z, +Y up, +X right (OpenGL) |
//! | view space, left-handed | camera at the origin looking down +Z, +Y up, +X right (Direct3D) |
//! | clip / NDC | x, y in [-1, 1] with +y up; z in [-1, 1] (OpenGL, `Convention::RhGl`) or [0, 1] (Direct3D, `RhZo`/`LhZo`); visible iff -w <= x, y <= w and the z range times w |
//! | viewport / grid | origin top-left, x right, y down; sample (i, j) covers [i, i+1) × [j, j+1) with its centre at (i + 0.5, j + 0.5); depth mapped to [0, 1] |
//! | field of view | the CLI and files give the **horizontal** fov across the whole grid width, in degrees |
//! | terminal cells | about twice as tall as wide: cell aspect (width / height) defaults to 0.5 |
//! | colours | linear-ish RGB in `f32` 0..1 inside the renderer; quantized to the terminal's colour depth at the end |

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod app;
pub mod cli;
mod files;
pub mod frame;
pub mod input;
pub mod math;
pub mod maze;
pub mod names;
pub mod render;
#[cfg(unix)]
pub mod serve;
pub mod term;
