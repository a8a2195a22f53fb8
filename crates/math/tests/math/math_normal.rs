//! The normal matrix, from its textbook definition: `N = (M₃ₓ₃)⁻ᵀ`, so `Nᵀ · M = I`, for any
//! invertible 3×3 part whatever its magnitude; and `Singular` for every singular one.
//!
//! Tolerance: `Nᵀ · M` against `I` to 1e-4 absolute. A rotation times a scale is perfectly
//! conditioned, so the product is a few ULPs (6e-8 each) from the identity at any scale; 1e-4 leaves a
//! wide margin while still catching any wrong column (an error of order 1).

use crate::common;

use common::*;
use glam::{Mat3, Mat4, Quat, Vec3};
use mazewalk_math::{self as math, MathError};
use proptest::prelude::*;

/// `Nᵀ · M`, the product that is the identity exactly when `N` is `M`'s normal matrix.
fn check(model: Mat4, normal: Mat3) -> Mat3 {
    normal.transpose() * Mat3::from_mat4(model)
}

/// A 3×3 part from three columns, as a model matrix.
fn from_cols(x: Vec3, y: Vec3, z: Vec3) -> Mat4 {
    Mat4::from_mat3(Mat3::from_cols(x, y, z))
}

#[test]
fn a_singular_matrix_is_refused_whatever_its_magnitude() {
    // issue #12: |x| overflows to inf and |z| underflows to 0, so the old guard's "volume" was
    // inf·inf·0 = NaN, `det <= 1e-6 · NaN` was false, and this exactly singular matrix came back Ok.
    let x = Vec3::new(1e20, 1.0, 1.0);
    let model = from_cols(x, 2.0 * x, Vec3::new(1e-30, 0.0, 1e-30));
    assert!(
        matches!(math::normal_matrix(model), Err(MathError::Singular { .. })),
        "{:?}",
        math::normal_matrix(model)
    );
    // The same shapes at ordinary and extreme magnitudes: dependent columns, a zero column.
    for scale in [1e-30, 1e-10, 1.0, 1e10, 1e30] {
        let x = Vec3::new(1.0, 2.0, 3.0) * scale;
        for model in [
            from_cols(x, 2.0 * x, Vec3::Z * scale),
            from_cols(x, Vec3::Y * scale, x + Vec3::Y * scale),
            from_cols(x, Vec3::ZERO, Vec3::Z),
            math::scaling(Vec3::new(scale, scale, 0.0)),
        ] {
            let got = math::normal_matrix(model);
            assert!(matches!(got, Err(MathError::Singular { .. })), "scale {scale}: {model} → {got:?}");
        }
    }
}

#[test]
fn uniform_scales_of_any_magnitude_have_a_normal_matrix() {
    // issue #12: 1e13 and 1e-13 are perfectly conditioned but were refused as Singular because the
    // determinant (1e39) or the inverse overflowed in f32.
    for scale in [1e-30f32, 1e-13, 0.01, 1.0, 100.0, 1e13, 1e30] {
        let model = math::scaling(Vec3::splat(scale));
        let normal = math::normal_matrix(model).unwrap_or_else(|e| panic!("scale {scale}: {e}"));
        let product = check(model, normal);
        assert!(product.abs_diff_eq(Mat3::IDENTITY, 1e-4), "scale {scale}: Nᵀ·M = {product}");
    }
}

#[test]
fn an_inverse_too_large_for_f32_is_an_overflow() {
    // The inverse of a 1e-39 scale is 1e39 > f32::MAX: not singular, not representable either.
    let model = math::scaling(Vec3::splat(1e-39));
    assert_eq!(math::normal_matrix(model), Err(MathError::Overflow { what: "normal matrix" }));
}

#[test]
fn conditioning_at_the_threshold_is_singular() {
    // Unit columns x, y and z = (1, 0, 1e-6): the sine of z's angle to the x–y plane, |det| over the
    // column lengths, is exactly 1e-6 in f32 (1 + 1e-12 rounds to 1). At or below 1e-6 is singular;
    // just above is not.
    let at = from_cols(Vec3::X, Vec3::Y, Vec3::new(1.0, 0.0, 1e-6));
    assert!(matches!(math::normal_matrix(at), Err(MathError::Singular { .. })));
    let above = from_cols(Vec3::X, Vec3::Y, Vec3::new(1.0, 0.0, 2e-6));
    assert!(math::normal_matrix(above).is_ok());
}

#[test]
fn conditioning_is_measured_on_normalised_columns() {
    // x = (1, 1, 1) and y = (1, -1, 1) (sine of their angle 0.94), and z tilted out of their plane by a
    // small angle from x's direction. Every column's largest entry is 1 but its length is √3, so
    // |det| alone is 5.2 times the volume of the unit columns: only dividing by the lengths puts a
    // 5e-7 tilt (volume 4.7e-7) below the 1e-6 threshold and a 4e-6 tilt (3.8e-6) above it.
    let (x, y) = (Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, -1.0, 1.0));
    let normal = x.cross(y).normalize(); // unit, perpendicular to both
    let tilt = |sine: f32| from_cols(x, y, x.normalize() * (1.0 - sine * sine).sqrt() + normal * sine);
    assert!(matches!(math::normal_matrix(tilt(5e-7)), Err(MathError::Singular { .. })));
    let model = tilt(4e-6);
    let n = math::normal_matrix(model).unwrap();
    // Conditioned about 1e-6: rounding (6e-8) in the columns is amplified about 1e6/4 times.
    assert!(check(model, n).abs_diff_eq(Mat3::IDENTITY, 0.1), "{}", check(model, n));
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn normal_matrix_inverts_any_rotation_at_any_uniform_scale(
        axis in arb_unit(), angle in -4.0f32..4.0, exponent in -30i32..=30, mantissa in 1.0f32..10.0,
    ) {
        // issue #12: the conditioning test must be scale-free, and so must the inverse.
        let scale = mantissa * 10f32.powi(exponent);
        let model = Mat4::from_quat(Quat::from_axis_angle(axis, angle)) * math::scaling(Vec3::splat(scale));
        let normal = math::normal_matrix(model).unwrap();
        let product = check(model, normal);
        prop_assert!(product.abs_diff_eq(Mat3::IDENTITY, 1e-4), "scale {scale}: Nᵀ·M = {product}");
    }

    #[test]
    fn normal_matrix_refuses_dependent_columns_at_any_magnitude(
        (a, b) in (arb_eighths(), arb_eighths()), (s, t) in (-4i8..=4, -4i8..=4),
        (ex, ey, ez) in (-90i32..=90, -90i32..=90, -90i32..=90),
    ) {
        // issue #12: a third column in the span of the first two is singular whatever the columns'
        // magnitudes, including ones whose squared lengths overflow (above 2^64) or underflow (below
        // 2^-63). Built nearly exactly: entries are eighths times powers of two and s, t small
        // integers, so `w` is in the span up to one rounding per sum, and rescaling it to 2^ez (at
        // least 2^-93, a normal f32) one more: relative 1e-7, far below the 1e-6 threshold.
        let (x, y) = (a * 2f32.powi(ex), b * 2f32.powi(ey));
        let w = f32::from(s) * x + f32::from(t) * y;
        let largest = w.abs().max_element();
        let z = if largest > 0.0 { w / largest * 2f32.powi(ez) } else { w };
        let got = math::normal_matrix(from_cols(x, y, z));
        prop_assert!(matches!(got, Err(MathError::Singular { .. })), "{x} {y} {z} → {got:?}");
    }
}

/// A vector whose components are eighths in [-1, 1]: exact in f32, and so are small multiples and
/// power-of-two scalings of it.
fn arb_eighths() -> impl Strategy<Value = Vec3> {
    (-8i8..=8, -8i8..=8, -8i8..=8).prop_map(|(x, y, z)| Vec3::new(x.into(), y.into(), z.into()) / 8.0)
}
