// The crate's documentation is its README (what docs.rs and the repository show alike): the
// conventions table, the matrices written out, how each is checked. Its Rust examples run as doctests.
#![doc = include_str!("../README.md")]
#![forbid(unsafe_code)]

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
