//! The viewport transform: NDC → grid coordinates.

use glam::{Mat4, Vec4};

use super::{DepthRange, MathError, check_finite};

/// NDC → grid: origin top-left, x right, y down, depth to [0, 1]. NDC x = -1 → 0, x = +1 → `width`;
/// NDC y = +1 → 0, y = -1 → `height`; NDC z from `depth`'s range → [0, 1] (0 at the range's near
/// end: the near plane, or the far plane with reversed depth).
///
/// # Errors
///
/// [`MathError::NonFinite`]; [`MathError::EmptyGrid`] unless `width, height > 0`.
///
/// ```
/// # use glam::Vec3;
/// use mazewalk_math::{DepthRange, viewport};
/// let vp = viewport(80.0, 24.0, DepthRange::NegOneToOne)?;
/// assert_eq!(vp.transform_point3(Vec3::new(-1.0, 1.0, -1.0)), Vec3::new(0.0, 0.0, 0.0)); // top-left, near
/// assert_eq!(vp.transform_point3(Vec3::new(1.0, -1.0, 1.0)), Vec3::new(80.0, 24.0, 1.0)); // bottom-right, far
/// # Ok::<(), mazewalk_math::MathError>(())
/// ```
pub fn viewport(width: f32, height: f32, depth: DepthRange) -> Result<Mat4, MathError> {
    check_finite("width", width)?;
    check_finite("height", height)?;
    if !(width > 0.0 && height > 0.0) {
        return Err(MathError::EmptyGrid { width, height });
    }
    let (half_w, half_h) = (0.5 * width, 0.5 * height);
    let depth_scale = 1.0 / (depth.far() - depth.near()); // 1/2 for [-1, 1], 1 for [0, 1]
    Ok(Mat4::from_cols(
        Vec4::new(half_w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, -half_h, 0.0, 0.0), // NDC +y is up, grid +y is down
        Vec4::new(0.0, 0.0, depth_scale, 0.0),
        Vec4::new(half_w, half_h, -depth.near() * depth_scale, 1.0), // NDC (0, 0) → the grid's centre
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_viewport_is_an_error() {
        assert_eq!(
            viewport(0.0, 10.0, DepthRange::ZeroToOne),
            Err(MathError::EmptyGrid { width: 0.0, height: 10.0 })
        );
        assert!(matches!(viewport(f32::NAN, 1.0, DepthRange::ZeroToOne), Err(MathError::NonFinite { .. })));
    }

    #[test]
    fn a_grid_with_no_rows_or_no_columns_is_empty() {
        // issue #12: zero height is refused as zero width is, whichever side is zero.
        for (width, height) in [(10.0, 0.0), (0.0, 0.0), (-1.0, 5.0), (5.0, -1.0)] {
            assert_eq!(
                viewport(width, height, DepthRange::NegOneToOne),
                Err(MathError::EmptyGrid { width, height })
            );
        }
    }
}
