//! The three projection conventions the renderer can run in, and the NDC depth range each one uses.

use glam::{Mat4, Vec3, Vec4};

use super::{MathError, projection, view};

/// The NDC depth range a projection produces. Reversed depth
/// ([`Convention::perspective_reverse`]) keeps the range and swaps which plane lands on which end.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DepthRange {
    /// z in [-1, 1], near plane at -1 (OpenGL).
    NegOneToOne,
    /// z in [0, 1], near plane at 0 (Direct3D, Vulkan, WebGPU).
    ZeroToOne,
}

impl DepthRange {
    /// The range's near end, -1 or 0: NDC z of the near plane (of the far plane, with reversed depth).
    #[must_use]
    pub const fn near(self) -> f32 {
        match self {
            DepthRange::NegOneToOne => -1.0,
            DepthRange::ZeroToOne => 0.0,
        }
    }

    /// The range's far end, always 1: NDC z of the far plane (of the near plane, with reversed depth).
    #[must_use]
    pub const fn far(self) -> f32 {
        1.0
    }
}

/// A view-space handedness plus an NDC depth range, named like glam's `camera` modules.
///
/// The renderer draws the same scene in every convention and checks the frames agree, so the
/// view constructors here ([`Convention::look_at`], [`Convention::look_to`]) take the crate's
/// **right-handed world** and, for the left-handed convention, mirror it first (see
/// [`Convention::world_mirror`]). The projections ([`Convention::perspective`],
/// [`Convention::frustum`], [`Convention::orthographic`], [`Convention::perspective_infinite`],
/// [`Convention::perspective_reverse`], [`Convention::perspective_infinite_reverse`]) are the crate's
/// only projection API; each mirrors the glam function of the same name in the matching
/// `glam::camera` module, where glam has one.
///
/// ```
/// use glam::{Vec3, Vec4};
/// use mazewalk_math::Convention;
/// let world = Vec4::new(4.0, 1.0, 0.5, 1.0);
/// let ndc: Vec<Vec3> = Convention::ALL
///     .iter()
///     .map(|conv| {
///         let view = conv.look_at(Vec3::ZERO, Vec3::X, Vec3::Z).unwrap();
///         let proj = conv.perspective(1.0, 2.0, 0.1, 10.0).unwrap();
///         let clip = proj * view * world;
///         clip.truncate() / clip.w
///     })
///     .collect();
/// // The same screen point in all three; only the depth values differ by range.
/// assert!(ndc[0].truncate().abs_diff_eq(ndc[1].truncate(), 1e-5));
/// assert!(ndc[1].abs_diff_eq(ndc[2], 1e-5)); // both [0, 1]
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Convention {
    /// Right-handed, -Z forward. NDC z in [-1, 1] (OpenGL).
    RhGl,
    /// Right-handed, -Z forward. NDC z in [0, 1] (glam's `rh::proj::directx`).
    RhZo,
    /// Left-handed, +Z forward. NDC z in [0, 1] (Direct3D; glam's `lh::proj::directx`).
    LhZo,
}

impl Convention {
    /// Every convention, for rendering (and testing) in all of them.
    pub const ALL: [Convention; 3] = [Convention::RhGl, Convention::RhZo, Convention::LhZo];

    /// The NDC depth range this convention's projections produce.
    #[must_use]
    pub const fn depth_range(self) -> DepthRange {
        match self {
            Convention::RhGl => DepthRange::NegOneToOne,
            Convention::RhZo | Convention::LhZo => DepthRange::ZeroToOne,
        }
    }

    /// Whether view space is right-handed (-Z forward).
    #[must_use]
    pub const fn is_right_handed(self) -> bool {
        matches!(self, Convention::RhGl | Convention::RhZo)
    }

    /// The view-space forward axis: -Z (right-handed) or +Z (left-handed).
    #[must_use]
    pub const fn forward(self) -> Vec3 {
        if self.is_right_handed() { Vec3::NEG_Z } else { Vec3::Z }
    }

    /// The reflection taking the crate's right-handed world into this convention's world: identity for
    /// the right-handed conventions, `z → -z` for the left-handed one. A reflection flips handedness,
    /// which is what keeps the image the same way round.
    ///
    /// ```
    /// use glam::Vec3;
    /// use mazewalk_math::Convention;
    /// assert_eq!(Convention::RhZo.world_mirror().transform_point3(Vec3::ONE), Vec3::ONE);
    /// assert_eq!(Convention::LhZo.world_mirror().transform_point3(Vec3::ONE), Vec3::new(1.0, 1.0, -1.0));
    /// ```
    #[must_use]
    pub fn world_mirror(self) -> Mat4 {
        if self.is_right_handed() {
            Mat4::IDENTITY
        } else {
            Mat4::from_diagonal(Vec4::new(1.0, 1.0, -1.0, 1.0))
        }
    }

    /// World (right-handed, z up) → this convention's view space, camera at `eye` looking at `target`.
    /// Right-handed: [`super::look_at_rh`]. Left-handed: `look_at_lh` of the mirrored world, times the
    /// mirror, which equals `look_at_rh` with view z negated.
    ///
    /// # Errors
    ///
    /// As [`super::look_at_rh`].
    ///
    /// ```
    /// use glam::Vec3;
    /// use mazewalk_math::Convention;
    /// let (eye, target) = (Vec3::new(1.0, 1.0, 0.5), Vec3::new(1.0, 4.0, 0.5)); // looking north
    /// for conv in Convention::ALL {
    ///     let view = conv.look_at(eye, target, Vec3::Z)?;
    ///     // The target 3 units down the forward axis (-Z or +Z), east (+x in the world) on the right.
    ///     assert!(view.transform_point3(target).abs_diff_eq(conv.forward() * 3.0, 1e-6));
    ///     assert!(view.transform_point3(target + Vec3::X).x > 0.0);
    /// }
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn look_at(self, eye: Vec3, target: Vec3, up: Vec3) -> Result<Mat4, MathError> {
        if self.is_right_handed() {
            view::look_at_rh(eye, target, up)
        } else {
            let mirror = self.world_mirror();
            let m = |v: Vec3| mirror.transform_vector3(v);
            Ok(view::look_at_lh(m(eye), m(target), m(up))? * mirror)
        }
    }

    /// World (right-handed, z up) → this convention's view space, camera at `eye` looking along `dir`.
    /// The left-handed convention mirrors the world first, as in [`Convention::look_at`].
    ///
    /// # Errors
    ///
    /// As [`super::look_to_rh`].
    ///
    /// ```
    /// use glam::Vec3;
    /// use mazewalk_math::Convention;
    /// let view = Convention::LhZo.look_to(Vec3::ZERO, Vec3::Y, Vec3::Z)?; // looking north
    /// assert!(view.transform_point3(Vec3::new(0.0, 2.0, 1.0)).abs_diff_eq(Vec3::new(0.0, 1.0, 2.0), 1e-6));
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn look_to(self, eye: Vec3, dir: Vec3, up: Vec3) -> Result<Mat4, MathError> {
        if self.is_right_handed() {
            view::look_to_rh(eye, dir, up)
        } else {
            let mirror = self.world_mirror();
            let m = |v: Vec3| mirror.transform_vector3(v);
            Ok(view::look_to_lh(m(eye), m(dir), m(up))? * mirror)
        }
    }

    /// This convention's perspective projection from a vertical field of view `fov_y` (radians) and
    /// `aspect` (width / height), through the symmetric [`Convention::frustum`]. Mirrors glam's
    /// `perspective` in `rh::proj::opengl` (RhGl), `rh::proj::directx` (RhZo) and `lh::proj::directx`
    /// (LhZo).
    ///
    /// # Errors
    ///
    /// [`MathError::NonFinite`]; [`MathError::FovOutOfRange`] unless `0 < fov_y < π`;
    /// [`MathError::NotPositive`] for `aspect <= 0`; [`MathError::DepthNotPositive`] unless
    /// `near, far > 0`; [`MathError::EmptyDepthRange`] for `near == far`; [`MathError::Overflow`].
    ///
    /// ```
    /// use glam::Vec3;
    /// use mazewalk_math::Convention;
    /// for conv in Convention::ALL {
    ///     let proj = conv.perspective(1.2, 2.0, 0.5, 50.0)?;
    ///     let range = conv.depth_range();
    ///     // The near plane lands on the range's near end (-1 or 0), the far plane on 1.
    ///     assert!((proj.project_point3(conv.forward() * 0.5).z - range.near()).abs() < 1e-5);
    ///     assert!((proj.project_point3(conv.forward() * 50.0).z - range.far()).abs() < 1e-5);
    /// }
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn perspective(self, fov_y: f32, aspect: f32, near: f32, far: f32) -> Result<Mat4, MathError> {
        projection::perspective(self, fov_y, aspect, near, far, projection::Depth::Forward)
    }

    /// [`Convention::perspective`] with the far plane at infinity (`far → ∞`): the near plane lands
    /// on the range's near end (-1 or 0) and depth approaches 1 with distance. The far clip plane
    /// (`z <= w`) then holds for every point, so depth clips at the near plane only. Mirrors glam's
    /// `perspective_infinite` in `rh::proj::directx` (RhZo) and `lh::proj::directx` (LhZo); RhGl is
    /// its limit (glam's opengl module has none): `z_ndc = 1 - 2·near/d`.
    ///
    /// # Errors
    ///
    /// [`MathError::NonFinite`]; [`MathError::FovOutOfRange`] unless `0 < fov_y < π`;
    /// [`MathError::NotPositive`] for `aspect <= 0`; [`MathError::DepthNotPositive`] (with `far`
    /// infinite) unless `near > 0`; [`MathError::Overflow`].
    ///
    /// ```
    /// use mazewalk_math::Convention;
    /// for conv in Convention::ALL {
    ///     let proj = conv.perspective_infinite(1.2, 2.0, 0.5)?;
    ///     let depth = |d: f32| proj.project_point3(conv.forward() * d).z;
    ///     assert!((depth(0.5) - conv.depth_range().near()).abs() < 1e-6); // the near plane
    ///     assert!(depth(1e6) < 1.0 && 1.0 - depth(1e6) < 1e-5); // far away: just short of 1
    /// }
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn perspective_infinite(self, fov_y: f32, aspect: f32, near: f32) -> Result<Mat4, MathError> {
        projection::perspective_infinite(self, fov_y, aspect, near, projection::Depth::Forward)
    }

    /// [`Convention::perspective`] with reversed depth: the near plane lands on 1, the far plane on
    /// the range's near end (-1 or 0). The same as `perspective(fov_y, aspect, far, near)` (a near
    /// plane beyond the far one is reversed depth), named so that it reads as meant. On [0, 1] a
    /// float depth buffer then keeps its precision far away (see the crate's README); on [-1, 1] the
    /// values near -1 and the viewport's `(z + 1) / 2` round most of that away again. glam has no
    /// finite reversed perspective; its limit (`far → ∞`) is
    /// [`Convention::perspective_infinite_reverse`].
    ///
    /// The clip volume is the same one (`-w <= x, y <= w`, `near(depth)·w <= z <= w`) and
    /// [`crate::ClipPlanes::ALL`] clips it as before, with the planes' depth roles swapped:
    /// [`crate::ClipPlane::Near`] (`z >= near(depth)·w`) is then the far plane and
    /// [`crate::ClipPlane::Far`] (`z <= w`) the near one. A depth test keeps the *larger* depth.
    ///
    /// # Errors
    ///
    /// As [`Convention::perspective`].
    ///
    /// ```
    /// use mazewalk_math::Convention;
    /// for conv in Convention::ALL {
    ///     let proj = conv.perspective_reverse(1.2, 2.0, 0.5, 50.0)?;
    ///     let depth = |d: f32| proj.project_point3(conv.forward() * d).z;
    ///     assert!((depth(0.5) - 1.0).abs() < 1e-5); // near → 1
    ///     assert!((depth(50.0) - conv.depth_range().near()).abs() < 1e-5); // far → -1 or 0
    ///     assert!(depth(2.0) > depth(3.0)); // nearer is larger
    /// }
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn perspective_reverse(
        self,
        fov_y: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Result<Mat4, MathError> {
        projection::perspective(self, fov_y, aspect, near, far, projection::Depth::Reverse)
    }

    /// [`Convention::perspective_reverse`] with the far plane at infinity: the near plane lands on 1
    /// and depth approaches the range's near end (-1 or 0) with distance. The standard projection of
    /// engines with a float depth buffer on [0, 1]: `z_ndc = near/d`, a value that keeps every digit
    /// however far away. Mirrors glam's `perspective_infinite_reverse` in `rh::proj::directx` (RhZo)
    /// and `lh::proj::directx` (LhZo); RhGl is the limit of its finite reversed form,
    /// `z_ndc = 2·near/d - 1`. Clipping as in [`Convention::perspective_reverse`]:
    /// [`crate::ClipPlane::Far`] is the near plane; [`crate::ClipPlane::Near`] clips nothing in front.
    ///
    /// # Errors
    ///
    /// As [`Convention::perspective_infinite`].
    ///
    /// ```
    /// use mazewalk_math::Convention;
    /// let proj = Convention::RhZo.perspective_infinite_reverse(1.2, 2.0, 0.5)?;
    /// let depth = |d: f32| proj.project_point3(Convention::RhZo.forward() * d).z;
    /// assert_eq!(depth(0.5), 1.0); // near → 1
    /// assert!((depth(5e5) - 1e-6).abs() < 1e-12); // near / d, to the last digit
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn perspective_infinite_reverse(self, fov_y: f32, aspect: f32, near: f32) -> Result<Mat4, MathError> {
        projection::perspective_infinite(self, fov_y, aspect, near, projection::Depth::Reverse)
    }

    /// This convention's off-centre perspective frustum whose near-plane rectangle is
    /// `[left, right] × [bottom, top]` (`glFrustum`); `near` and `far` are distances along the forward
    /// axis. Mirrors glam's `frustum` in the matching module (see [`Convention::perspective`]).
    ///
    /// # Errors
    ///
    /// [`MathError::NonFinite`]; [`MathError::ZeroWidth`] (`left == right`); [`MathError::ZeroHeight`]
    /// (`bottom == top`); [`MathError::EmptyDepthRange`] (`near == far`);
    /// [`MathError::DepthNotPositive`] unless `near, far > 0` (zero included); [`MathError::Overflow`]
    /// when the bounds are too close or too large for `f32`.
    ///
    /// ```
    /// use glam::Vec3;
    /// use mazewalk_math::Convention;
    /// let proj = Convention::RhGl.frustum(-1.0, 3.0, -1.0, 1.0, 1.0, 10.0)?;
    /// // The near-plane corner (3, 1) maps to the NDC corner (1, 1, -1).
    /// assert!(proj.project_point3(Vec3::new(3.0, 1.0, -1.0)).abs_diff_eq(Vec3::new(1.0, 1.0, -1.0), 1e-5));
    /// let proj = Convention::LhZo.frustum(-1.0, 1.0, -1.0, 1.0, 1.0, 10.0)?;
    /// assert!(proj.project_point3(Vec3::new(1.0, 1.0, 1.0)).abs_diff_eq(Vec3::new(1.0, 1.0, 0.0), 1e-5));
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn frustum(
        self,
        left: f32,
        right: f32,
        bottom: f32,
        top: f32,
        near: f32,
        far: f32,
    ) -> Result<Mat4, MathError> {
        projection::frustum(self, left, right, bottom, top, near, far)
    }

    /// This convention's orthographic projection of the box `[left, right] × [bottom, top]` × distances
    /// `[near, far]` onto the NDC cube (`glOrtho`; `near` may be <= 0). Mirrors glam's `orthographic`
    /// in the matching module (see [`Convention::perspective`]).
    ///
    /// # Errors
    ///
    /// [`MathError::NonFinite`], [`MathError::ZeroWidth`], [`MathError::ZeroHeight`],
    /// [`MathError::EmptyDepthRange`], [`MathError::Overflow`].
    ///
    /// ```
    /// use glam::Vec3;
    /// use mazewalk_math::Convention;
    /// let proj = Convention::RhZo.orthographic(-2.0, 2.0, -1.0, 1.0, 0.0, 10.0)?;
    /// assert!(proj.project_point3(Vec3::new(2.0, 1.0, -10.0)).abs_diff_eq(Vec3::ONE, 1e-6));
    /// assert!(proj.project_point3(Vec3::new(-2.0, -1.0, 0.0)).abs_diff_eq(Vec3::new(-1.0, -1.0, 0.0), 1e-6));
    /// # Ok::<(), mazewalk_math::MathError>(())
    /// ```
    pub fn orthographic(
        self,
        left: f32,
        right: f32,
        bottom: f32,
        top: f32,
        near: f32,
        far: f32,
    ) -> Result<Mat4, MathError> {
        projection::orthographic(self, left, right, bottom, top, near, far)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_ranges_and_axes() {
        assert_eq!(Convention::RhGl.depth_range().near(), -1.0);
        assert_eq!(Convention::LhZo.depth_range().near(), 0.0);
        assert_eq!(Convention::RhZo.forward(), Vec3::NEG_Z);
        assert_eq!(Convention::LhZo.forward(), Vec3::Z);
    }

    #[test]
    fn left_handed_view_is_the_right_handed_one_with_z_negated() {
        let (eye, target) = (Vec3::new(1.0, 2.0, 0.5), Vec3::new(-3.0, 4.0, 0.0));
        let lh = Convention::LhZo.look_at(eye, target, Vec3::Z).unwrap();
        let rh = view::look_at_rh(eye, target, Vec3::Z).unwrap();
        let flip = Mat4::from_diagonal(Vec4::new(1.0, 1.0, -1.0, 1.0));
        assert!(lh.abs_diff_eq(flip * rh, 1e-5), "{lh} vs {}", flip * rh);
    }
}
