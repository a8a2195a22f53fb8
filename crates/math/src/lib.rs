//! The graphics math core: transforms, view, projection, viewport and clipping, written by hand on
//! glam's `Vec`/`Mat` types (glam's own `camera` module is the oracle in the tests, never used here).
//!
//! # Conventions
//!
//! The crate-wide table lives in the crate docs; this module relies on these parts of it:
//!
//! * **Column vectors, column-major.** A matrix transforms a point as `M * p`, so in `T * R * S` the
//!   scale applies first. glam stores `Mat4` as four columns `x_axis, y_axis, z_axis, w_axis`.
//! * **Radians** everywhere in this module.
//! * **World**: right-handed, z up; yaw counter-clockwise from +x, pitch positive up.
//! * **View space**: right-handed looks down **-Z** (OpenGL), left-handed looks down **+Z**
//!   (Direct3D); both have +Y up and +X right.
//! * **Clip / NDC**: x, y in [-1, 1] with +y up; z in [-1, 1] ([`DepthRange::NegOneToOne`], OpenGL) or
//!   [0, 1] ([`DepthRange::ZeroToOne`], Direct3D). A clip-space point is visible iff
//!   `-w <= x, y <= w` and `near(depth) * w <= z <= w`. Depth runs forward (the near plane at the
//!   range's near end, the far plane at 1) except in the `*_reverse` projections, where it runs from
//!   1 at the near plane to the near end at the far plane; the clip volume is the same either way.
//! * **Grid** (viewport output): origin top-left, x right, y down, depth in [0, 1].
//!
//! Three projection conventions are provided, named like glam's modules: [`Convention::RhGl`]
//! (right-handed, depth [-1, 1]; `glam::camera::rh::proj::opengl`), [`Convention::RhZo`] (right-handed,
//! depth [0, 1]; `rh::proj::directx`) and [`Convention::LhZo`] (left-handed, depth [0, 1];
//! `lh::proj::directx`). Projections are methods of [`Convention`]: `conv.perspective(..)`,
//! `conv.frustum(..)`, `conv.orthographic(..)`, and the perspective with an infinite far plane and
//! with reversed depth, `conv.perspective_infinite(..)`, `conv.perspective_reverse(..)` and
//! `conv.perspective_infinite_reverse(..)`.
//!
//! # Errors
//!
//! Every constructor that can be handed degenerate input (eye on the target, up parallel to the view
//! direction, an empty frustum, a non-positive near plane, non-finite numbers, a result that overflows)
//! returns `Result<_, MathError>`: it never yields a NaN or infinite matrix silently. The elementary
//! transforms ([`translation`], [`scaling`], [`rotation_x`], …) cannot fail for finite input and are
//! infallible; non-finite input propagates into the matrix, as it does in glam.
//!
//! # The pipeline in a few lines
//!
//! ```
//! use glam::{Vec3, Vec4};
//! use mazewalk_math::{self as math, Convention};
//!
//! let conv = Convention::RhGl;
//! let view = conv.look_at(Vec3::ZERO, Vec3::X, Vec3::Z)?; // world → view: stand at the origin, face east
//! let proj = math::perspective_hfov(conv, 90f32.to_radians(), 80, 24, 0.5, 0.1, 100.0)?; // view → clip
//! let viewport = math::viewport(80.0, 24.0, conv.depth_range())?; // NDC → grid
//!
//! let world = Vec4::new(5.0, 0.0, 0.0, 1.0); // straight ahead
//! let clip = proj * view * world;
//! let ndc = clip.truncate() / clip.w; // perspective divide
//! let grid = viewport.transform_point3(ndc);
//! assert!((grid.x - 40.0).abs() < 1e-4 && (grid.y - 12.0).abs() < 1e-4); // the centre of the grid
//! # Ok::<(), math::MathError>(())
//! ```

#![forbid(unsafe_code)]

/// The README's Rust examples, run as doctests (the README is the crate's page on its own).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

mod clip;
mod convention;
mod projection;
mod transform;
mod view;
mod viewport;

use glam::Vec3;

pub use clip::{ClipPlane, ClipPlanes, ClipVertex, Coverage, classify, clip_polygon, outcode};
pub use convention::{Convention, DepthRange};
pub use projection::{
    near_corner_distance, orthographic_hwidth, perspective_hfov, physical_aspect, vertical_fov,
};
pub use transform::{model, normal_matrix, rotation_x, rotation_y, rotation_z, scaling, translation};
pub use view::{
    camera_to_world_lh, camera_to_world_rh, direction_from_yaw_pitch, look_at_lh, look_at_rh, look_to_lh,
    look_to_rh, rigid_inverse, up_from_yaw_pitch,
};
pub use viewport::viewport;

/// Why a math constructor refused its input. Each variant carries the offending values.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum MathError {
    /// An argument was NaN or infinite (`value` is the first offending component).
    #[error("{arg} is not finite ({value})")]
    NonFinite {
        /// The argument's name, as in the function signature.
        arg: &'static str,
        /// The offending (component) value.
        value: f32,
    },
    /// The inputs were finite but the result is not (for example `1 / (right - left)` overflowed).
    #[error("{what} overflowed: the inputs are too large or too close together")]
    Overflow {
        /// What was being built.
        what: &'static str,
    },
    /// Look-at with the eye on the target: there is no view direction.
    #[error("eye {eye} is on the target: no view direction")]
    EyeAtTarget {
        /// The eye, equal to the target.
        eye: Vec3,
    },
    /// A direction (look-to `dir`, or `up`) of zero length.
    #[error("{arg} is the zero vector")]
    ZeroVector {
        /// Which argument.
        arg: &'static str,
    },
    /// The up vector is (nearly) parallel to the view direction, so "right" is undefined.
    #[error("up {up} is parallel to the view direction {dir}")]
    UpParallel {
        /// The view direction.
        dir: Vec3,
        /// The up vector.
        up: Vec3,
    },
    /// A perspective projection needs both clip planes strictly in front of the eye.
    #[error("near ({near}) and far ({far}) must both be > 0 for a perspective projection")]
    DepthNotPositive {
        /// The near plane distance.
        near: f32,
        /// The far plane distance.
        far: f32,
    },
    /// `near == far`: the depth range is empty.
    #[error("near and far are equal ({near}): empty depth range")]
    EmptyDepthRange {
        /// Both plane distances.
        near: f32,
    },
    /// `left == right`: the frustum or box has no width.
    #[error("left and right are equal ({left}): zero width")]
    ZeroWidth {
        /// Both bounds.
        left: f32,
    },
    /// `bottom == top`: the frustum or box has no height.
    #[error("bottom and top are equal ({bottom}): zero height")]
    ZeroHeight {
        /// Both bounds.
        bottom: f32,
    },
    /// A field of view outside the open interval (0, π).
    #[error("field of view {fov} rad is outside (0, π)")]
    FovOutOfRange {
        /// The field of view, radians.
        fov: f32,
    },
    /// An aspect ratio, sample aspect or half-width that is not strictly positive.
    #[error("{arg} must be > 0, got {value}")]
    NotPositive {
        /// Which argument.
        arg: &'static str,
        /// Its value.
        value: f32,
    },
    /// A grid or viewport with no columns or no rows.
    #[error("empty grid: {width} × {height}")]
    EmptyGrid {
        /// Width (columns).
        width: f32,
        /// Height (rows).
        height: f32,
    },
    /// The upper 3×3 of a matrix is singular (or so close that its inverse is meaningless).
    #[error("the 3×3 part is singular (determinant {determinant})")]
    Singular {
        /// Its determinant.
        determinant: f32,
    },
}

/// `Err(NonFinite)` unless `value` is finite.
fn check_finite(arg: &'static str, value: f32) -> Result<(), MathError> {
    if value.is_finite() { Ok(()) } else { Err(MathError::NonFinite { arg, value }) }
}

/// `Err(NonFinite)` naming the first non-finite component, unless all of `v` is finite.
fn check_finite3(arg: &'static str, v: Vec3) -> Result<(), MathError> {
    v.to_array().into_iter().try_for_each(|c| check_finite(arg, c))
}

/// `Ok(m)` if every entry is finite, else `Err(Overflow)`: the last line of defence against NaN.
fn finite_or_overflow(what: &'static str, m: glam::Mat4) -> Result<glam::Mat4, MathError> {
    if m.is_finite() { Ok(m) } else { Err(MathError::Overflow { what }) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finite_checks_name_the_offending_component() {
        assert_eq!(
            check_finite3("eye", Vec3::new(1.0, f32::INFINITY, 2.0)),
            Err(MathError::NonFinite { arg: "eye", value: f32::INFINITY })
        );
        assert_eq!(check_finite3("eye", Vec3::ONE), Ok(()));
    }

    #[test]
    fn errors_display_their_values() {
        let e = MathError::ZeroWidth { left: 2.0 };
        assert_eq!(e.to_string(), "left and right are equal (2): zero width");
    }
}
