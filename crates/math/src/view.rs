//! View matrices: world → view space, built as `rotation · translation(-eye)`.
//!
//! Right-handed view space looks down -Z, left-handed down +Z; both have +Y up and +X right.
//!
//! The view rotation is orthonormal, so its inverse is its transpose: the "fast" look-at writes the
//! camera's basis vectors as **rows** instead of inverting the camera-to-world matrix (whose
//! **columns** they are). [`camera_to_world_rh`] builds that matrix so the tests can check
//! `look_at == camera_to_world.inverse()`.

use glam::{Mat4, Vec3, Vec4};

use super::{MathError, check_finite3, finite_or_overflow};

/// Below this sine of the angle between the view direction and up, "right" (their cross product) is
/// too short to normalize meaningfully in `f32` (about 0.006°), so the up vector counts as parallel.
const PARALLEL_SINE: f32 = 1e-4;

/// `v` scaled to unit length, or `None` for the zero vector. `v` must be finite.
fn unit(v: Vec3) -> Option<Vec3> {
    let largest = v.abs().max_element();
    // Divide by the largest component first so the squared length can neither overflow (1e20²) nor
    // underflow (1e-30²) before the square root.
    (largest > 0.0).then(|| (v / largest).normalize())
}

/// The camera's axes in world space, `[right, up, forward]`, for a right- or left-handed view space.
fn camera_axes(dir: Vec3, up: Vec3, right_handed: bool) -> Result<[Vec3; 3], MathError> {
    check_finite3("dir", dir)?;
    check_finite3("up", up)?;
    let forward = unit(dir).ok_or(MathError::ZeroVector { arg: "dir" })?;
    let up_unit = unit(up).ok_or(MathError::ZeroVector { arg: "up" })?;
    // Right-handed: right = forward × up. Left-handed keeps +X on the right while +Z points forward,
    // which flips the cross product: right = up × forward.
    let right = if right_handed { forward.cross(up_unit) } else { up_unit.cross(forward) };
    let sine = right.length(); // |f × u| = sin(angle) for unit vectors
    if sine < PARALLEL_SINE {
        return Err(MathError::UpParallel { dir, up });
    }
    // Re-orthogonalised (one Gram–Schmidt step): the cross product of nearly parallel unit vectors
    // keeps its absolute rounding (a few ULPs of 1) while its length shrinks to the sine, so near the
    // threshold `right` leans towards `forward` by up to ε / sine (4e-4 at 1e-4). Removing its
    // component along `forward` leaves an error of a few ULPs whatever the angle.
    let right = (right - right.dot(forward) * forward).normalize();
    // The camera's true up: perpendicular to both, unit length (right ⟂ forward, both unit).
    let true_up = if right_handed { right.cross(forward) } else { forward.cross(right) };
    Ok([right, true_up, forward])
}

/// The view matrix from the camera axes: rows are the view axes in world space (the transpose of the
/// orthonormal camera-to-world rotation), then `translation(-eye)` folded into the last column.
fn view_from_axes(eye: Vec3, x: Vec3, y: Vec3, z: Vec3) -> Result<Mat4, MathError> {
    // Column j of the rotation holds component j of each row vector: the transpose, written out.
    let rotation = Mat4::from_cols(
        Vec4::new(x.x, y.x, z.x, 0.0),
        Vec4::new(x.y, y.y, z.y, 0.0),
        Vec4::new(x.z, y.z, z.z, 0.0),
        Vec4::W,
    );
    // R · T(-eye) has last column (-R·eye, 1): rotate the eye's offset, no general inverse needed.
    let last = Vec4::new(-x.dot(eye), -y.dot(eye), -z.dot(eye), 1.0);
    finite_or_overflow(
        "view matrix",
        Mat4::from_cols(rotation.x_axis, rotation.y_axis, rotation.z_axis, last),
    )
}

/// The camera-to-world matrix: columns are the view axes in world space, then the eye.
fn world_from_axes(eye: Vec3, x: Vec3, y: Vec3, z: Vec3) -> Mat4 {
    Mat4::from_cols(x.extend(0.0), y.extend(0.0), z.extend(0.0), eye.extend(1.0))
}

/// Right-handed, -Z forward. World → view for a camera at `eye` looking along `dir` with `up` roughly
/// up; `dir` and `up` need not be unit length. Mirrors `glam::camera::rh::view::look_to_mat4`.
///
/// # Errors
///
/// [`MathError::NonFinite`], [`MathError::ZeroVector`] (`dir` or `up`), [`MathError::UpParallel`],
/// [`MathError::Overflow`] (an eye so far away that `-R·eye` overflows).
///
/// ```
/// # use glam::Vec3;
/// let view = mazewalk_math::look_to_rh(Vec3::ZERO, Vec3::X, Vec3::Z)?;
/// assert!(view.transform_point3(Vec3::new(2.0, 0.0, 0.0)).abs_diff_eq(Vec3::new(0.0, 0.0, -2.0), 1e-6));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn look_to_rh(eye: Vec3, dir: Vec3, up: Vec3) -> Result<Mat4, MathError> {
    check_finite3("eye", eye)?;
    let [right, true_up, forward] = camera_axes(dir, up, true)?;
    view_from_axes(eye, right, true_up, -forward) // view +Z points backwards
}

/// Left-handed, +Z forward. World → view for a camera at `eye` looking along `dir`.
/// Mirrors `glam::camera::lh::view::look_to_mat4`.
///
/// # Errors
///
/// As [`look_to_rh`].
///
/// ```
/// # use glam::Vec3;
/// let view = mazewalk_math::look_to_lh(Vec3::ZERO, Vec3::X, Vec3::Z)?;
/// assert!(view.transform_point3(Vec3::new(2.0, 0.0, 0.0)).abs_diff_eq(Vec3::new(0.0, 0.0, 2.0), 1e-6));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn look_to_lh(eye: Vec3, dir: Vec3, up: Vec3) -> Result<Mat4, MathError> {
    check_finite3("eye", eye)?;
    let [right, true_up, forward] = camera_axes(dir, up, false)?;
    view_from_axes(eye, right, true_up, forward)
}

/// `target - eye`, refusing a zero or overflowing difference.
fn look_direction(eye: Vec3, target: Vec3) -> Result<Vec3, MathError> {
    check_finite3("eye", eye)?;
    check_finite3("target", target)?;
    let dir = target - eye;
    if dir == Vec3::ZERO {
        return Err(MathError::EyeAtTarget { eye });
    }
    if !dir.is_finite() {
        return Err(MathError::Overflow { what: "look-at direction" });
    }
    Ok(dir)
}

/// Right-handed, -Z forward. World → view for a camera at `eye` looking at `target`: the eye goes to the
/// origin and the target onto -Z at distance `|target - eye|`. Mirrors
/// `glam::camera::rh::view::look_at_mat4`.
///
/// # Errors
///
/// [`MathError::EyeAtTarget`], and those of [`look_to_rh`].
///
/// ```
/// # use glam::Vec3;
/// let eye = Vec3::new(1.0, 2.0, 0.0);
/// let view = mazewalk_math::look_at_rh(eye, Vec3::new(1.0, 5.0, 0.0), Vec3::Z)?;
/// assert!(view.transform_point3(eye).abs_diff_eq(Vec3::ZERO, 1e-6));
/// assert!(view.transform_point3(Vec3::new(1.0, 5.0, 0.0)).abs_diff_eq(Vec3::new(0.0, 0.0, -3.0), 1e-6));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn look_at_rh(eye: Vec3, target: Vec3, up: Vec3) -> Result<Mat4, MathError> {
    look_to_rh(eye, look_direction(eye, target)?, up)
}

/// Left-handed, +Z forward. World → view for a camera at `eye` looking at `target` (which lands on +Z).
/// Mirrors `glam::camera::lh::view::look_at_mat4`.
///
/// # Errors
///
/// As [`look_at_rh`].
///
/// ```
/// # use glam::Vec3;
/// let view = mazewalk_math::look_at_lh(Vec3::ZERO, Vec3::new(0.0, 3.0, 0.0), Vec3::Z)?;
/// assert!(view.transform_point3(Vec3::new(0.0, 3.0, 0.0)).abs_diff_eq(Vec3::new(0.0, 0.0, 3.0), 1e-6));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn look_at_lh(eye: Vec3, target: Vec3, up: Vec3) -> Result<Mat4, MathError> {
    look_to_lh(eye, look_direction(eye, target)?, up)
}

/// Right-handed, -Z forward. View → world for a camera at `eye` looking along `dir`: the inverse of
/// [`look_to_rh`], built directly (columns = camera axes, then the eye).
///
/// # Errors
///
/// As [`look_to_rh`].
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{camera_to_world_rh, look_to_rh};
/// let (eye, dir) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 1.0, 0.0));
/// let product = camera_to_world_rh(eye, dir, Vec3::Z)? * look_to_rh(eye, dir, Vec3::Z)?;
/// assert!(product.abs_diff_eq(glam::Mat4::IDENTITY, 1e-5));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn camera_to_world_rh(eye: Vec3, dir: Vec3, up: Vec3) -> Result<Mat4, MathError> {
    check_finite3("eye", eye)?;
    let [right, true_up, forward] = camera_axes(dir, up, true)?;
    Ok(world_from_axes(eye, right, true_up, -forward))
}

/// Left-handed, +Z forward. View → world for a camera at `eye` looking along `dir`: the inverse of
/// [`look_to_lh`].
///
/// # Errors
///
/// As [`look_to_lh`].
///
/// ```
/// # use glam::Vec3;
/// let m = mazewalk_math::camera_to_world_lh(Vec3::ZERO, Vec3::X, Vec3::Z)?;
/// assert!(m.transform_vector3(Vec3::Z).abs_diff_eq(Vec3::X, 1e-6)); // view +Z is the world direction
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn camera_to_world_lh(eye: Vec3, dir: Vec3, up: Vec3) -> Result<Mat4, MathError> {
    check_finite3("eye", eye)?;
    let [right, true_up, forward] = camera_axes(dir, up, false)?;
    Ok(world_from_axes(eye, right, true_up, forward))
}

/// World z up, yaw counter-clockwise from +x, pitch positive up (radians). The unit view direction.
///
/// ```
/// # use glam::Vec3;
/// use std::f32::consts::FRAC_PI_2;
/// let north = mazewalk_math::direction_from_yaw_pitch(FRAC_PI_2, 0.0);
/// assert!(north.abs_diff_eq(Vec3::Y, 1e-6));
/// ```
#[must_use]
pub fn direction_from_yaw_pitch(yaw: f32, pitch: f32) -> Vec3 {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    // Spherical coordinates with the elevation measured from the maze plane.
    Vec3::new(cp * cy, cp * sy, sp)
}

/// World z up. The camera's unit up vector for a yaw and pitch (radians): perpendicular to
/// [`direction_from_yaw_pitch`], it is the direction tilted up by a further 90°, so a camera built from
/// the pair never meets [`MathError::UpParallel`] and never flips, even at pitch ±90°.
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{direction_from_yaw_pitch, up_from_yaw_pitch};
/// assert!(up_from_yaw_pitch(0.3, 0.0).abs_diff_eq(Vec3::Z, 1e-6));
/// assert!(up_from_yaw_pitch(0.3, 1.0).dot(direction_from_yaw_pitch(0.3, 1.0)).abs() < 1e-6);
/// ```
#[must_use]
pub fn up_from_yaw_pitch(yaw: f32, pitch: f32) -> Vec3 {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    // d/d(pitch) of the direction: the same spherical formula at pitch + 90°.
    Vec3::new(-sp * cy, -sp * sy, cp)
}

/// The inverse of a rigid transform (rotation + translation, e.g. any view matrix from this module),
/// without a general 4×4 inverse: `[R | t]⁻¹ = [Rᵀ | -Rᵀ·t]`.
///
/// # Panics
///
/// In debug builds, if the upper 3×3 is not orthonormal (within 1e-3) or the bottom row is not
/// `(0, 0, 0, 1)`: passing a scaled or projective matrix is a caller bug.
///
/// ```
/// # use glam::{Mat4, Vec3};
/// use mazewalk_math::{look_at_rh, rigid_inverse};
/// let view = look_at_rh(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Z)?;
/// assert!((rigid_inverse(view) * view).abs_diff_eq(Mat4::IDENTITY, 1e-5));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
#[must_use]
pub fn rigid_inverse(m: Mat4) -> Mat4 {
    let r = glam::Mat3::from_mat4(m);
    debug_assert!((r * r.transpose()).abs_diff_eq(glam::Mat3::IDENTITY, 1e-3), "not a rotation: {m}");
    debug_assert!(m.row(3) == Vec4::W, "not affine: {m}");
    let rt = r.transpose(); // orthonormal: transpose == inverse
    let t = m.w_axis.truncate();
    Mat4::from_cols(
        rt.x_axis.extend(0.0),
        rt.y_axis.extend(0.0),
        rt.z_axis.extend(0.0),
        (-(rt * t)).extend(1.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eye_at_target_is_an_error() {
        let eye = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(look_at_rh(eye, eye, Vec3::Z), Err(MathError::EyeAtTarget { eye }));
        assert_eq!(look_at_lh(eye, eye, Vec3::Z), Err(MathError::EyeAtTarget { eye }));
    }

    #[test]
    fn zero_direction_or_up_is_an_error() {
        assert_eq!(look_to_rh(Vec3::ZERO, Vec3::ZERO, Vec3::Z), Err(MathError::ZeroVector { arg: "dir" }));
        assert_eq!(look_to_lh(Vec3::ZERO, Vec3::X, Vec3::ZERO), Err(MathError::ZeroVector { arg: "up" }));
    }

    #[test]
    fn up_parallel_to_the_view_direction_is_an_error() {
        let (dir, up) = (Vec3::new(0.0, 0.0, -2.0), Vec3::Z);
        assert_eq!(look_to_rh(Vec3::ZERO, dir, up), Err(MathError::UpParallel { dir, up }));
        assert_eq!(camera_to_world_lh(Vec3::ZERO, dir, up), Err(MathError::UpParallel { dir, up }));
    }

    #[test]
    fn non_finite_input_is_an_error() {
        let nan = Vec3::new(0.0, f32::NAN, 0.0);
        assert!(matches!(look_at_rh(nan, Vec3::X, Vec3::Z), Err(MathError::NonFinite { arg: "eye", .. })));
        assert!(matches!(
            look_at_rh(Vec3::ZERO, nan, Vec3::Z),
            Err(MathError::NonFinite { arg: "target", .. })
        ));
        assert!(matches!(look_to_lh(Vec3::ZERO, Vec3::X, nan), Err(MathError::NonFinite { arg: "up", .. })));
    }

    #[test]
    fn overflowing_look_at_is_an_error() {
        let (eye, target) = (Vec3::splat(-3e38), Vec3::splat(3e38));
        assert_eq!(look_at_rh(eye, target, Vec3::Z), Err(MathError::Overflow { what: "look-at direction" }));
        // right = (1, -1, 0)/√2, so right·eye = 6e38/√2 > f32::MAX.
        let far_eye = Vec3::new(3e38, -3e38, 0.0);
        assert_eq!(
            look_to_rh(far_eye, Vec3::new(1.0, 1.0, 0.0), Vec3::Z),
            Err(MathError::Overflow { what: "view matrix" })
        );
    }

    #[test]
    fn tiny_and_huge_directions_still_normalize() {
        for scale in [1e-30, 1e30] {
            let view = look_to_rh(Vec3::ZERO, Vec3::X * scale, Vec3::Z * scale).unwrap();
            assert!(view.transform_point3(Vec3::X).abs_diff_eq(-Vec3::Z, 1e-6));
        }
    }

    #[test]
    fn up_exactly_at_the_parallel_threshold_is_not_parallel() {
        // up = (1, 1e-4, 0) normalizes to itself (1 + 1e-8 rounds to 1), so the sine of its angle to
        // +x is exactly PARALLEL_SINE: the rule is "below counts as parallel", at the threshold is not.
        let at = Vec3::new(1.0, PARALLEL_SINE, 0.0);
        assert!(look_to_rh(Vec3::ZERO, Vec3::X, at).is_ok());
        assert!(look_to_lh(Vec3::ZERO, Vec3::X, at).is_ok());
        let below = Vec3::new(1.0, 0.99 * PARALLEL_SINE, 0.0);
        assert_eq!(
            look_to_rh(Vec3::ZERO, Vec3::X, below),
            Err(MathError::UpParallel { dir: Vec3::X, up: below })
        );
    }
}
