//! Model transforms: translation, scaling, rotation, `T·R·S`, and the normal matrix.
//!
//! Column vectors: `M * p`. These are infallible; non-finite input propagates into the matrix.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::MathError;

/// Moves points by `offset`. Column vectors: the offset sits in the fourth column.
///
/// ```
/// # use glam::Vec3;
/// let m = mazewalk_math::translation(Vec3::new(1.0, 2.0, 3.0));
/// assert_eq!(m.transform_point3(Vec3::ZERO), Vec3::new(1.0, 2.0, 3.0));
/// assert_eq!(m.transform_vector3(Vec3::X), Vec3::X); // directions do not move
/// ```
#[must_use]
pub fn translation(offset: Vec3) -> Mat4 {
    Mat4::from_cols(Vec4::X, Vec4::Y, Vec4::Z, offset.extend(1.0))
}

/// Scales each axis by the matching component of `factors`, about the origin.
///
/// ```
/// # use glam::Vec3;
/// let m = mazewalk_math::scaling(Vec3::new(2.0, 3.0, 4.0));
/// assert_eq!(m.transform_point3(Vec3::ONE), Vec3::new(2.0, 3.0, 4.0));
/// ```
#[must_use]
pub fn scaling(factors: Vec3) -> Mat4 {
    Mat4::from_diagonal(factors.extend(1.0))
}

/// Rotates by `angle` radians about +x, counter-clockwise looking down the axis towards the origin
/// (right-hand rule): +y turns towards +z.
///
/// ```
/// # use glam::Vec3;
/// let m = mazewalk_math::rotation_x(std::f32::consts::FRAC_PI_2);
/// assert!(m.transform_vector3(Vec3::Y).abs_diff_eq(Vec3::Z, 1e-6));
/// ```
#[must_use]
pub fn rotation_x(angle: f32) -> Mat4 {
    let (s, c) = angle.sin_cos();
    // Columns are the images of the basis vectors: x stays, y → (0, c, s), z → (0, -s, c).
    Mat4::from_cols(Vec4::X, Vec4::new(0.0, c, s, 0.0), Vec4::new(0.0, -s, c, 0.0), Vec4::W)
}

/// Rotates by `angle` radians about +y (right-hand rule): +z turns towards +x.
///
/// ```
/// # use glam::Vec3;
/// let m = mazewalk_math::rotation_y(std::f32::consts::FRAC_PI_2);
/// assert!(m.transform_vector3(Vec3::Z).abs_diff_eq(Vec3::X, 1e-6));
/// ```
#[must_use]
pub fn rotation_y(angle: f32) -> Mat4 {
    let (s, c) = angle.sin_cos();
    // x → (c, 0, -s), z → (s, 0, c): the cyclic order is z → x → y, hence the sign swap.
    Mat4::from_cols(Vec4::new(c, 0.0, -s, 0.0), Vec4::Y, Vec4::new(s, 0.0, c, 0.0), Vec4::W)
}

/// Rotates by `angle` radians about +z (right-hand rule): +x turns towards +y. With the world's z up
/// this is a turn counter-clockwise in the maze plane, the direction yaw is measured in.
///
/// ```
/// # use glam::Vec3;
/// let m = mazewalk_math::rotation_z(std::f32::consts::FRAC_PI_2);
/// assert!(m.transform_vector3(Vec3::X).abs_diff_eq(Vec3::Y, 1e-6));
/// ```
#[must_use]
pub fn rotation_z(angle: f32) -> Mat4 {
    let (s, c) = angle.sin_cos();
    Mat4::from_cols(Vec4::new(c, s, 0.0, 0.0), Vec4::new(-s, c, 0.0, 0.0), Vec4::Z, Vec4::W)
}

/// The model matrix `T · R · S`: scale first, then rotate, then translate (column vectors).
///
/// `rotation` is a linear transform with no translation, usually from [`rotation_x`]/`y`/`z`.
///
/// # Panics
///
/// In debug builds, if `rotation` has a translation or projective part (a caller bug).
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{model, rotation_z};
/// let m = model(Vec3::new(10.0, 0.0, 0.0), rotation_z(std::f32::consts::FRAC_PI_2), Vec3::new(2.0, 1.0, 1.0));
/// // (1, 0, 0) → scaled (2, 0, 0) → rotated (0, 2, 0) → translated (10, 2, 0).
/// assert!(m.transform_point3(Vec3::X).abs_diff_eq(Vec3::new(10.0, 2.0, 0.0), 1e-5));
/// ```
#[must_use]
pub fn model(translation: Vec3, rotation: Mat4, scale: Vec3) -> Mat4 {
    debug_assert!(rotation.w_axis == Vec4::W && rotation.row(3) == Vec4::W, "rotation must be linear");
    self::translation(translation) * rotation * scaling(scale)
}

/// The normal matrix of `model`: the inverse transpose of its upper 3×3.
///
/// Normals transform with it so they stay perpendicular to transformed tangents, even under
/// non-uniform scale (where the plain 3×3 would tilt them). The result is not normalized.
///
/// Works at any magnitude: a rotation times a uniform scale of 1e-30 or 1e30 has a normal matrix
/// (the inverse is taken of the columns scaled to unit size, then scaled back), and a singular 3×3
/// is refused however large or small its columns are.
///
/// # Errors
///
/// [`MathError::NonFinite`] for a non-finite 3×3 part; [`MathError::Singular`] when the 3×3 part is
/// singular or so ill-conditioned that its inverse is meaningless in `f32`: a zero column, or columns
/// whose directions span a parallelepiped of volume at most 1e-6 (the unit cube's is 1);
/// [`MathError::Overflow`] when the inverse is well defined but too large for `f32` (a column shorter
/// than about 3e-39, the reciprocal of `f32::MAX`).
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{normal_matrix, scaling};
/// let n = normal_matrix(scaling(Vec3::new(2.0, 1.0, 1.0)))?;
/// // A plane x + y = c, stretched 2× along x, has normal (1/2, 1, 0) (up to length).
/// assert!((n * Vec3::new(1.0, 1.0, 0.0)).abs_diff_eq(Vec3::new(0.5, 1.0, 0.0), 1e-6));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn normal_matrix(model: Mat4) -> Result<Mat3, MathError> {
    let m = Mat3::from_mat4(model);
    let columns = [m.x_axis, m.y_axis, m.z_axis];
    for col in columns {
        super::check_finite3("model", col)?;
    }
    let singular = || MathError::Singular { determinant: m.determinant() }; // reported, never tested
    // M = U · diag(size): each column divided by its largest |entry|, so U's entries are at most 1
    // and nothing below can overflow or underflow, whatever M's magnitude (issue #12).
    let size = Vec3::from_array(columns.map(|col| col.abs().max_element()));
    if size.min_element() == 0.0 {
        return Err(singular()); // a zero column
    }
    let u = Mat3::from_cols(m.x_axis / size.x, m.y_axis / size.y, m.z_axis / size.z);
    // Scale-free conditioning: |det| of the unit-length columns, the volume of the parallelepiped they
    // span, is 1 for orthogonal columns and 0 for dependent ones (Hadamard's inequality). U's entries
    // are at most 1, so this cannot be NaN; if it ever were, it would refuse.
    let lengths = u.x_axis.length() * u.y_axis.length() * u.z_axis.length(); // each in [1, √3]
    let volume = u.determinant().abs() / lengths;
    if !volume.is_finite() || volume <= SINGULAR_VOLUME {
        return Err(singular());
    }
    // M⁻ᵀ = (U · D)⁻ᵀ = U⁻ᵀ · D⁻¹: column j of U's normal matrix divided by size j.
    let n = u.inverse().transpose();
    let n = Mat3::from_cols(n.x_axis / size.x, n.y_axis / size.y, n.z_axis / size.z);
    if n.is_finite() { Ok(n) } else { Err(MathError::Overflow { what: "normal matrix" }) }
}

/// At or below this volume spanned by the unit columns, [`normal_matrix`] calls a 3×3 singular: its
/// inverse would amplify the columns' rounding (6e-8) past 6 %.
const SINGULAR_VOLUME: f32 = 1e-6;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn singular_model_has_no_normal_matrix() {
        let flat = scaling(Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(normal_matrix(flat), Err(MathError::Singular { determinant: 0.0 }));
    }

    #[test]
    fn non_finite_model_is_rejected() {
        let bad = translation(Vec3::ZERO) * scaling(Vec3::new(f32::NAN, 1.0, 1.0));
        assert!(matches!(normal_matrix(bad), Err(MathError::NonFinite { arg: "model", .. })));
    }
}
