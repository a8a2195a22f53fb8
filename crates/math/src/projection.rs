//! Projections: view → clip space. Perspective (through the frustum) and orthographic, in the three
//! [`Convention`]s, plus the grid-aware helpers the renderer uses (horizontal fov, cell aspect).
//!
//! Bounds `left, right, bottom, top` are on the near plane (perspective) or the box sides
//! (orthographic); `near` and `far` are **distances** along the forward axis (-Z right-handed, +Z
//! left-handed), as in `glFrustum` and glam. Clip w is that distance for a perspective projection.

use glam::{Mat4, Vec4};

use super::{Convention, DepthRange, MathError, check_finite, finite_or_overflow};

/// `+1` if view-space z grows forward (left-handed), `-1` if it shrinks (right-handed): the distance in
/// front of the eye is `sign * z`.
fn forward_sign(conv: Convention) -> f32 {
    if conv.is_right_handed() { -1.0 } else { 1.0 }
}

/// The widths `right - left`, `top - bottom`, `far - near` after checking the bounds are finite, the
/// box is not flat and no difference overflows.
fn box_extent(
    left: f32,
    right: f32,
    bottom: f32,
    top: f32,
    near: f32,
    far: f32,
) -> Result<(f32, f32, f32), MathError> {
    let args =
        [("left", left), ("right", right), ("bottom", bottom), ("top", top), ("near", near), ("far", far)];
    args.into_iter().try_for_each(|(arg, value)| check_finite(arg, value))?;
    if left == right {
        return Err(MathError::ZeroWidth { left });
    }
    if bottom == top {
        return Err(MathError::ZeroHeight { bottom });
    }
    if near == far {
        return Err(MathError::EmptyDepthRange { near });
    }
    let extent = (right - left, top - bottom, far - near);
    if !(extent.0.is_finite() && extent.1.is_finite() && extent.2.is_finite()) {
        return Err(MathError::Overflow { what: "projection bounds" });
    }
    Ok(extent)
}

/// [`Convention::frustum`]: see there for the contract.
pub(super) fn frustum(
    conv: Convention,
    left: f32,
    right: f32,
    bottom: f32,
    top: f32,
    near: f32,
    far: f32,
) -> Result<Mat4, MathError> {
    frustum_depth(conv, left, right, bottom, top, near, far, Depth::Forward)
}

/// Which way depth runs: forward (the near plane at the range's near end, the far plane at 1) or
/// reversed (the near plane at 1, the far plane at the near end).
#[derive(Clone, Copy)]
pub(super) enum Depth {
    Forward,
    Reverse,
}

/// A frustum whose depth runs `order`: [`frustum`], and [`perspective`] (both orders) through it.
#[expect(clippy::too_many_arguments, reason = "glFrustum's six numbers, and the depth order")]
fn frustum_depth(
    conv: Convention,
    left: f32,
    right: f32,
    bottom: f32,
    top: f32,
    near: f32,
    far: f32,
    order: Depth,
) -> Result<Mat4, MathError> {
    let (width, height, depth) = box_extent(left, right, bottom, top, near, far)?;
    if !(near > 0.0 && far > 0.0) {
        return Err(MathError::DepthNotPositive { near, far });
    }
    // x on the near plane is n·x/d; mapping [l, r] to [-1, 1] and multiplying through by d gives
    // x_clip = 2n/(r-l)·x - (r+l)/(r-l)·d. Likewise for y.
    let (xx, yy) = (2.0 * near / width, 2.0 * near / height);
    let (zx, zy) = (-(right + left) / width, -(top + bottom) / height);
    // z_ndc = a + b/d, with a and b solved so that d = near and d = far give the range's ends. Reversed,
    // z_ndc becomes -z_ndc on [-1, 1] and 1 - z_ndc on [0, 1]: written out rather than subtracted, so
    // that -n/(f-n) keeps its digits (1 - f/(f-n) would cancel them when f ≫ n).
    let (a, b) = match (conv.depth_range(), order) {
        (DepthRange::NegOneToOne, Depth::Forward) => ((far + near) / depth, -2.0 * far * near / depth),
        (DepthRange::ZeroToOne, Depth::Forward) => (far / depth, -far * near / depth),
        (DepthRange::NegOneToOne, Depth::Reverse) => (-(far + near) / depth, 2.0 * far * near / depth),
        (DepthRange::ZeroToOne, Depth::Reverse) => (-near / depth, far * near / depth),
    };
    finite_or_overflow("frustum", perspective_matrix(conv, xx, yy, zx, zy, a, b))
}

/// The perspective matrix with `w_clip = d`, the distance in front of the eye (`s·z`), so that
/// dividing by w is the perspective divide: `x_clip = xx·x + zx·d`, `y_clip = yy·y + zy·d`,
/// `z_clip = a·d + b` (so `z_ndc = a + b/d`).
fn perspective_matrix(conv: Convention, xx: f32, yy: f32, zx: f32, zy: f32, a: f32, b: f32) -> Mat4 {
    let s = forward_sign(conv);
    Mat4::from_cols(
        Vec4::new(xx, 0.0, 0.0, 0.0),
        Vec4::new(0.0, yy, 0.0, 0.0),
        Vec4::new(s * zx, s * zy, s * a, s), // the coefficients of d = s·z
        Vec4::new(0.0, 0.0, b, 0.0),
    )
}

/// [`Convention::orthographic`]: see there for the contract.
pub(super) fn orthographic(
    conv: Convention,
    left: f32,
    right: f32,
    bottom: f32,
    top: f32,
    near: f32,
    far: f32,
) -> Result<Mat4, MathError> {
    let (width, height, depth) = box_extent(left, right, bottom, top, near, far)?;
    let s = forward_sign(conv);
    // An affine map of the box onto the NDC cube: x_ndc = (2x - (r+l))/(r-l), same for y; depth is
    // linear in the distance d = s·z, from the range's near end at d = near to 1 at d = far.
    let (zz, tz) = match conv.depth_range() {
        DepthRange::NegOneToOne => (2.0 / depth, -(far + near) / depth),
        DepthRange::ZeroToOne => (1.0 / depth, -near / depth),
    };
    finite_or_overflow(
        "orthographic",
        Mat4::from_cols(
            Vec4::new(2.0 / width, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 2.0 / height, 0.0, 0.0),
            Vec4::new(0.0, 0.0, s * zz, 0.0),
            Vec4::new(-(right + left) / width, -(top + bottom) / height, tz, 1.0), // w stays 1
        ),
    )
}

/// [`Convention::perspective`] (forward) and [`Convention::perspective_reverse`]: see there for the
/// contract.
pub(super) fn perspective(
    conv: Convention,
    fov_y: f32,
    aspect: f32,
    near: f32,
    far: f32,
    order: Depth,
) -> Result<Mat4, MathError> {
    check_fov(fov_y)?;
    check_positive("aspect", aspect)?;
    check_near(near, far)?;
    // The symmetric frustum whose near-plane rectangle subtends fov_y vertically.
    let top = near * (0.5 * fov_y).tan();
    let right = top * aspect;
    frustum_depth(conv, -right, right, -top, top, near, far, order)
}

/// [`Convention::perspective_infinite`] (forward) and [`Convention::perspective_infinite_reverse`].
pub(super) fn perspective_infinite(
    conv: Convention,
    fov_y: f32,
    aspect: f32,
    near: f32,
    order: Depth,
) -> Result<Mat4, MathError> {
    check_fov(fov_y)?;
    check_positive("aspect", aspect)?;
    check_near(near, f32::INFINITY)?;
    // The symmetric frustum's 2n/(r-l) and 2n/(t-b), with r = n·tan(fov/2)·aspect and t = n·tan(fov/2):
    // n cancels, so they need no near-plane rectangle.
    let yy = 1.0 / (0.5 * fov_y).tan();
    // The finite depth coefficients as far → ∞: a → the far end's value, b → its near·(range) term.
    let (a, b) = match (conv.depth_range(), order) {
        (DepthRange::NegOneToOne, Depth::Forward) => (1.0, -2.0 * near),
        (DepthRange::ZeroToOne, Depth::Forward) => (1.0, -near),
        (DepthRange::NegOneToOne, Depth::Reverse) => (-1.0, 2.0 * near),
        (DepthRange::ZeroToOne, Depth::Reverse) => (0.0, near),
    };
    finite_or_overflow("infinite perspective", perspective_matrix(conv, yy / aspect, yy, 0.0, 0.0, a, b))
}

/// `Err` unless `near` is finite and `> 0`, checked before `near` scales the frustum's bounds (a zero
/// `near` would otherwise be reported as a zero width). [`frustum`] checks `far`, and `near` again.
fn check_near(near: f32, far: f32) -> Result<(), MathError> {
    check_finite("near", near)?;
    if near > 0.0 { Ok(()) } else { Err(MathError::DepthNotPositive { near, far }) }
}

/// `Err` unless `fov` is a finite angle in the open interval (0, π).
fn check_fov(fov: f32) -> Result<(), MathError> {
    check_finite("fov", fov)?;
    if fov > 0.0 && fov < std::f32::consts::PI { Ok(()) } else { Err(MathError::FovOutOfRange { fov }) }
}

/// `Err` unless `value` is finite and strictly positive.
fn check_positive(arg: &'static str, value: f32) -> Result<(), MathError> {
    check_finite(arg, value)?;
    if value > 0.0 { Ok(()) } else { Err(MathError::NotPositive { arg, value }) }
}

/// The physical aspect (width / height) of a grid of `cols × rows` samples, each `sample_aspect` wide
/// per unit of height (terminal cells: about 0.5): `cols · sample_aspect / rows`.
///
/// # Errors
///
/// [`MathError::EmptyGrid`] for zero columns or rows; [`MathError::NotPositive`] (or
/// [`MathError::NonFinite`]) for a bad `sample_aspect`.
///
/// ```
/// assert_eq!(mazewalk_math::physical_aspect(80, 20, 0.5)?, 2.0);
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn physical_aspect(cols: usize, rows: usize, sample_aspect: f32) -> Result<f32, MathError> {
    if cols == 0 || rows == 0 {
        return Err(MathError::EmptyGrid { width: cols as f32, height: rows as f32 });
    }
    check_positive("sample_aspect", sample_aspect)?;
    let aspect = cols as f32 * sample_aspect / rows as f32;
    check_positive("aspect", aspect)?; // an extreme sample_aspect can overflow or underflow
    Ok(aspect)
}

/// The vertical fov (radians) matching a horizontal fov across a view of physical `aspect`
/// (width / height): `2·atan(tan(hfov/2) / aspect)`. In (0, π) for `hfov` in (0, π) and `aspect > 0`.
///
/// ```
/// let v = mazewalk_math::vertical_fov(std::f32::consts::FRAC_PI_2, 1.0);
/// assert!((v - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
/// ```
#[must_use]
pub fn vertical_fov(horizontal_fov: f32, aspect: f32) -> f32 {
    // Both fovs subtend the same near-plane rectangle: half-height = half-width / aspect.
    2.0 * ((0.5 * horizontal_fov).tan() / aspect).atan()
}

/// Perspective for a grid: the horizontal fov (radians) spans the whole grid width, whose physical
/// aspect is [`physical_aspect`]`(cols, rows, sample_aspect)`. In `conv`'s handedness and depth range.
/// Equal to `conv.perspective(vertical_fov(hfov, aspect), aspect, near, far)`.
///
/// # Errors
///
/// Those of [`physical_aspect`]; [`MathError::FovOutOfRange`] unless `0 < hfov < π`; and those of
/// [`Convention::perspective`].
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{Convention, perspective_hfov};
/// let proj = perspective_hfov(Convention::RhGl, 90f32.to_radians(), 80, 20, 0.5, 0.1, 10.0)?;
/// // 45° to the right of the view axis lands on the right edge of the grid.
/// assert!((proj.project_point3(Vec3::new(1.0, 0.0, -1.0)).x - 1.0).abs() < 1e-5);
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn perspective_hfov(
    conv: Convention,
    hfov: f32,
    cols: usize,
    rows: usize,
    sample_aspect: f32,
    near: f32,
    far: f32,
) -> Result<Mat4, MathError> {
    let aspect = physical_aspect(cols, rows, sample_aspect)?;
    check_fov(hfov)?;
    check_near(near, far)?;
    // Straight to the frustum: half-width from the hfov, half-height through the aspect. Going via
    // vertical_fov would round-trip through atan and tan for nothing.
    let right = near * (0.5 * hfov).tan();
    let top = right / aspect;
    frustum(conv, -right, right, -top, top, near, far)
}

/// Orthographic for a grid: `half_width` world units either side of the view axis across the grid
/// width, the height following the grid's [`physical_aspect`]. In `conv`'s handedness and depth range.
///
/// # Errors
///
/// Those of [`physical_aspect`]; [`MathError::NotPositive`] for `half_width <= 0`; those of
/// [`Convention::orthographic`].
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{Convention, orthographic_hwidth};
/// let proj = orthographic_hwidth(Convention::RhZo, 4.0, 80, 20, 0.5, 0.0, 10.0)?; // aspect 2
/// assert!(proj.project_point3(Vec3::new(4.0, 2.0, -10.0)).abs_diff_eq(Vec3::ONE, 1e-6));
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn orthographic_hwidth(
    conv: Convention,
    half_width: f32,
    cols: usize,
    rows: usize,
    sample_aspect: f32,
    near: f32,
    far: f32,
) -> Result<Mat4, MathError> {
    let aspect = physical_aspect(cols, rows, sample_aspect)?;
    check_positive("half_width", half_width)?;
    let half_height = half_width / aspect;
    orthographic(conv, -half_width, half_width, -half_height, half_height, near, far)
}

/// The distance from the eye to a corner of the near plane, for a horizontal fov (radians) and
/// physical aspect: the radius a camera must keep from walls so the near plane never pokes through.
/// `sqrt(near² + half_width² + half_height²)`; garbage in (non-positive or non-finite), garbage out.
///
/// ```
/// let d = mazewalk_math::near_corner_distance(1.0, std::f32::consts::FRAC_PI_2, 1.0);
/// assert!((d - 3f32.sqrt()).abs() < 1e-6); // corner (1, 1, 1)
/// ```
#[must_use]
pub fn near_corner_distance(near: f32, hfov: f32, aspect: f32) -> f32 {
    let half_width = near * (0.5 * hfov).tan();
    let half_height = half_width / aspect;
    glam::Vec3::new(near, half_width, half_height).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_frusta_are_errors() {
        assert_eq!(
            Convention::RhGl.frustum(1.0, 1.0, -1.0, 1.0, 1.0, 2.0),
            Err(MathError::ZeroWidth { left: 1.0 })
        );
        assert_eq!(
            Convention::RhZo.frustum(-1.0, 1.0, 2.0, 2.0, 1.0, 2.0),
            Err(MathError::ZeroHeight { bottom: 2.0 })
        );
        assert_eq!(
            Convention::LhZo.orthographic(-1.0, 1.0, -1.0, 1.0, 3.0, 3.0),
            Err(MathError::EmptyDepthRange { near: 3.0 })
        );
        assert_eq!(
            Convention::RhGl.perspective(1.0, 1.0, 2.0, 2.0),
            Err(MathError::EmptyDepthRange { near: 2.0 })
        );
    }

    #[test]
    fn perspective_needs_positive_near_and_far() {
        assert_eq!(
            Convention::RhGl.perspective(1.0, 1.0, 0.0, 2.0),
            Err(MathError::DepthNotPositive { near: 0.0, far: 2.0 })
        );
        assert_eq!(
            Convention::LhZo.frustum(-1.0, 1.0, -1.0, 1.0, 1.0, -2.0),
            Err(MathError::DepthNotPositive { near: 1.0, far: -2.0 })
        );
    }

    #[test]
    fn fov_and_aspect_are_checked() {
        assert_eq!(
            Convention::RhZo.perspective(0.0, 1.0, 1.0, 2.0),
            Err(MathError::FovOutOfRange { fov: 0.0 })
        );
        let pi = std::f32::consts::PI;
        assert_eq!(
            Convention::LhZo.perspective(pi, 1.0, 1.0, 2.0),
            Err(MathError::FovOutOfRange { fov: pi })
        );
        assert_eq!(
            Convention::RhGl.perspective(1.0, -1.0, 1.0, 2.0),
            Err(MathError::NotPositive { arg: "aspect", value: -1.0 })
        );
        assert_eq!(
            orthographic_hwidth(Convention::RhGl, 0.0, 10, 10, 0.5, 0.0, 1.0),
            Err(MathError::NotPositive { arg: "half_width", value: 0.0 })
        );
    }

    #[test]
    fn empty_grid_is_an_error() {
        assert_eq!(physical_aspect(0, 10, 0.5), Err(MathError::EmptyGrid { width: 0.0, height: 10.0 }));
        assert!(matches!(
            perspective_hfov(Convention::LhZo, 1.0, 10, 0, 0.5, 0.1, 1.0),
            Err(MathError::EmptyGrid { .. })
        ));
    }

    #[test]
    fn non_finite_bounds_are_errors() {
        assert_eq!(
            Convention::RhGl.frustum(f32::NEG_INFINITY, 1.0, -1.0, 1.0, 1.0, 2.0),
            Err(MathError::NonFinite { arg: "left", value: f32::NEG_INFINITY })
        );
        assert!(matches!(
            Convention::RhGl.perspective(1.0, 1.0, 1.0, f32::NAN),
            Err(MathError::NonFinite { arg: "far", .. })
        ));
    }

    #[test]
    fn overflowing_bounds_are_errors() {
        assert_eq!(
            Convention::RhGl.orthographic(-3e38, 3e38, -1.0, 1.0, 0.0, 1.0),
            Err(MathError::Overflow { what: "projection bounds" })
        );
        // 1 / (right - left) overflows for bounds one subnormal step apart.
        assert_eq!(
            Convention::RhZo.frustum(0.0, 1e-45, -1.0, 1.0, 1.0, 2.0),
            Err(MathError::Overflow { what: "frustum" })
        );
    }

    #[test]
    fn zero_near_or_far_is_an_error() {
        // Both planes strictly in front of the eye: zero is as invalid as negative (issue #12).
        for conv in Convention::ALL {
            assert_eq!(
                conv.frustum(-1.0, 1.0, -1.0, 1.0, 0.0, 2.0),
                Err(MathError::DepthNotPositive { near: 0.0, far: 2.0 })
            );
            assert_eq!(
                conv.frustum(-1.0, 1.0, -1.0, 1.0, 1.0, 0.0),
                Err(MathError::DepthNotPositive { near: 1.0, far: 0.0 })
            );
            assert_eq!(
                conv.perspective(1.0, 1.0, 1.0, 0.0),
                Err(MathError::DepthNotPositive { near: 1.0, far: 0.0 })
            );
            assert_eq!(
                perspective_hfov(conv, 1.0, 10, 10, 0.5, 0.0, 2.0),
                Err(MathError::DepthNotPositive { near: 0.0, far: 2.0 })
            );
            assert_eq!(
                perspective_hfov(conv, 1.0, 10, 10, 0.5, 1.0, 0.0),
                Err(MathError::DepthNotPositive { near: 1.0, far: 0.0 })
            );
        }
    }

    #[test]
    fn a_non_finite_near_is_named() {
        // `near` scales the bounds, so it is checked (and named) before they are built.
        assert!(matches!(
            Convention::RhZo.perspective(1.0, 1.0, f32::NAN, 2.0),
            Err(MathError::NonFinite { arg: "near", .. })
        ));
        assert!(matches!(
            perspective_hfov(Convention::LhZo, 1.0, 10, 10, 0.5, f32::INFINITY, 2.0),
            Err(MathError::NonFinite { arg: "near", .. })
        ));
    }

    #[test]
    fn physical_aspect_is_columns_times_sample_aspect_over_rows() {
        assert_eq!(physical_aspect(80, 20, 0.5), Ok(2.0));
        assert_eq!(physical_aspect(3, 4, 1.0), Ok(0.75));
        assert_eq!(physical_aspect(7, 2, 0.25), Ok(0.875));
        assert_eq!(physical_aspect(10, 0, 0.5), Err(MathError::EmptyGrid { width: 10.0, height: 0.0 }));
        assert_eq!(
            physical_aspect(10, 10, 0.0),
            Err(MathError::NotPositive { arg: "sample_aspect", value: 0.0 })
        );
        // A valid but extreme sample aspect whose product underflows to 0 or overflows to inf.
        assert_eq!(
            physical_aspect(1, 1 << 20, 1e-40),
            Err(MathError::NotPositive { arg: "aspect", value: 0.0 })
        );
        assert!(matches!(
            physical_aspect(usize::MAX, 1, 3e38),
            Err(MathError::NonFinite { arg: "aspect", .. })
        ));
    }

    #[test]
    fn orthographic_hwidth_is_the_box_of_the_grid_aspect() {
        for conv in Convention::ALL {
            // 80 × 20 samples of aspect 0.5: physical aspect 2, so half-height = 4 / 2.
            assert_eq!(
                orthographic_hwidth(conv, 4.0, 80, 20, 0.5, 0.0, 10.0),
                conv.orthographic(-4.0, 4.0, -2.0, 2.0, 0.0, 10.0)
            );
            assert_eq!(
                orthographic_hwidth(conv, 3.0, 10, 20, 1.0, -1.0, 5.0),
                conv.orthographic(-3.0, 3.0, -6.0, 6.0, -1.0, 5.0)
            );
        }
    }
}
