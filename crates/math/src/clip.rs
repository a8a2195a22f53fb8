//! Homogeneous clipping in clip space (before the divide by w): Sutherland–Hodgman of a convex
//! polygon against the planes of the clip volume.
//!
//! The clip volume is `-w <= x <= w`, `-w <= y <= w`, `near(depth)·w <= z <= w`, where the near
//! bound is `-w` for [`DepthRange::NegOneToOne`] and `0` for [`DepthRange::ZeroToOne`]. Each plane has
//! a signed distance that is linear in the clip coordinates and `>= 0` inside, so an edge crosses a
//! plane where that distance, interpolated linearly along the edge, is zero. Clipping in clip space
//! (not NDC) keeps points behind the eye (w < 0) from wrapping round through infinity.
//!
//! The same planes serve every projection of the crate. With reversed depth
//! ([`crate::Convention::perspective_reverse`]) the volume is unchanged and the depth planes swap
//! roles: [`ClipPlane::Near`] cuts at the far plane and [`ClipPlane::Far`] at the near plane. With an
//! infinite far plane the plane at the far end clips nothing in front of the eye.

use glam::Vec4;

use super::DepthRange;

/// A polygon vertex that clipping can read and interpolate: a clip-space position plus any
/// attributes (depth, texture coordinates, shade …), all interpolated linearly **in clip space**.
///
/// ```
/// use glam::Vec4;
/// use mazewalk_math::ClipVertex;
///
/// #[derive(Clone, Debug)]
/// struct Shaded { clip: Vec4, u: f32 }
///
/// impl ClipVertex for Shaded {
///     fn clip(&self) -> Vec4 { self.clip }
///     fn lerp(&self, other: &Self, t: f32) -> Self {
///         Shaded { clip: self.clip.lerp(other.clip, t), u: self.u + (other.u - self.u) * t }
///     }
/// }
/// ```
pub trait ClipVertex: Clone {
    /// The homogeneous clip-space position.
    fn clip(&self) -> Vec4;
    /// The vertex a fraction `t` (in [0, 1]) of the way from `self` to `other`; `t = 0` is `self`.
    #[must_use]
    fn lerp(&self, other: &Self, t: f32) -> Self;
}

impl ClipVertex for Vec4 {
    fn clip(&self) -> Vec4 {
        *self
    }

    fn lerp(&self, other: &Self, t: f32) -> Self {
        Vec4::lerp(*self, *other, t)
    }
}

/// One plane of the clip volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ClipPlane {
    /// `x >= -w`.
    Left,
    /// `x <= w`.
    Right,
    /// `y >= -w`.
    Bottom,
    /// `y <= w`.
    Top,
    /// `z >= -w` (depth [-1, 1]) or `z >= 0` (depth [0, 1]): the depth range's near end, so the
    /// near plane (the far plane, with reversed depth).
    Near,
    /// `z <= w`: the range's far end, so the far plane (the near plane, with reversed depth).
    Far,
}

impl ClipPlane {
    /// All six, in the order clipping visits them.
    pub const ALL: [ClipPlane; 6] = [
        ClipPlane::Left,
        ClipPlane::Right,
        ClipPlane::Bottom,
        ClipPlane::Top,
        ClipPlane::Near,
        ClipPlane::Far,
    ];

    /// Signed distance of `clip` from this plane (scaled, not Euclidean): `>= 0` inside, `< 0` outside.
    /// Linear in `clip`, which is what makes interpolating it along an edge exact.
    ///
    /// ```
    /// use glam::Vec4;
    /// use mazewalk_math::{ClipPlane, DepthRange};
    /// assert_eq!(ClipPlane::Right.distance(Vec4::new(0.5, 0.0, 0.0, 1.0), DepthRange::ZeroToOne), 0.5);
    /// assert_eq!(ClipPlane::Near.distance(Vec4::new(0.0, 0.0, -0.5, 1.0), DepthRange::NegOneToOne), 0.5);
    /// ```
    #[must_use]
    pub fn distance(self, clip: Vec4, depth: DepthRange) -> f32 {
        match self {
            ClipPlane::Left => clip.w + clip.x,
            ClipPlane::Right => clip.w - clip.x,
            ClipPlane::Bottom => clip.w + clip.y,
            ClipPlane::Top => clip.w - clip.y,
            ClipPlane::Near => match depth {
                DepthRange::NegOneToOne => clip.w + clip.z,
                DepthRange::ZeroToOne => clip.z,
            },
            ClipPlane::Far => clip.w - clip.z,
        }
    }

    /// This plane as a one-plane set.
    #[must_use]
    pub const fn bit(self) -> ClipPlanes {
        ClipPlanes(1 << self as u8)
    }
}

/// A set of [`ClipPlane`]s, as a bitmask: which planes to clip against, or (from [`outcode`]) which
/// planes a point is outside of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ClipPlanes(u8);

impl ClipPlanes {
    /// No planes.
    pub const NONE: ClipPlanes = ClipPlanes(0);
    /// All six planes of the clip volume (what the renderer uses).
    pub const ALL: ClipPlanes = ClipPlanes(0b11_1111);
    /// Only the near plane: enough to make the perspective divide safe (w > 0).
    pub const NEAR: ClipPlanes = ClipPlane::Near.bit();

    /// Whether `plane` is in the set.
    #[must_use]
    pub const fn contains(self, plane: ClipPlane) -> bool {
        self.0 & plane.bit().0 != 0
    }

    /// Whether the set is empty.
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The union of two sets.
    #[must_use]
    pub const fn union(self, other: ClipPlanes) -> ClipPlanes {
        ClipPlanes(self.0 | other.0)
    }

    /// The planes in both sets.
    #[must_use]
    pub const fn intersection(self, other: ClipPlanes) -> ClipPlanes {
        ClipPlanes(self.0 & other.0)
    }

    /// The planes in the set, in [`ClipPlane::ALL`] order.
    pub fn iter(self) -> impl Iterator<Item = ClipPlane> {
        ClipPlane::ALL.into_iter().filter(move |&p| self.contains(p))
    }
}

impl std::ops::BitOr for ClipPlanes {
    type Output = ClipPlanes;
    fn bitor(self, rhs: ClipPlanes) -> ClipPlanes {
        self.union(rhs)
    }
}

impl From<ClipPlane> for ClipPlanes {
    fn from(plane: ClipPlane) -> ClipPlanes {
        plane.bit()
    }
}

/// The planes of `planes` that `clip` is strictly outside of (a Cohen–Sutherland outcode).
///
/// ```
/// use glam::Vec4;
/// use mazewalk_math::{ClipPlane, ClipPlanes, DepthRange, outcode};
/// let code = outcode(Vec4::new(2.0, 0.0, 0.5, 1.0), ClipPlanes::ALL, DepthRange::ZeroToOne);
/// assert_eq!(code, ClipPlane::Right.into());
/// ```
#[must_use]
pub fn outcode(clip: Vec4, planes: ClipPlanes, depth: DepthRange) -> ClipPlanes {
    planes.iter().filter(|p| p.distance(clip, depth) < 0.0).fold(ClipPlanes::NONE, |code, p| code | p.bit())
}

/// Where a polygon stands against a set of planes, decided from outcodes alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coverage {
    /// Every vertex is inside every plane: the polygon needs no clipping.
    Inside,
    /// Every vertex is outside one same plane: nothing is visible.
    Outside,
    /// Neither: clip it (the result may still be empty).
    Straddling,
}

/// Classifies a polygon (or any point set) against `planes` without clipping, to skip the work.
///
/// ```
/// use glam::Vec4;
/// use mazewalk_math::{ClipPlanes, Coverage, DepthRange, classify};
/// let behind = [Vec4::new(0.0, 0.0, -2.0, 1.0), Vec4::new(1.0, 0.0, -2.0, 1.0), Vec4::new(0.0, 1.0, -3.0, 1.0)];
/// assert_eq!(classify(&behind, ClipPlanes::ALL, DepthRange::ZeroToOne), Coverage::Outside);
/// ```
#[must_use]
pub fn classify<V: ClipVertex>(polygon: &[V], planes: ClipPlanes, depth: DepthRange) -> Coverage {
    let (mut any, mut all) = (ClipPlanes::NONE, planes);
    for v in polygon {
        let code = outcode(v.clip(), planes, depth);
        any = any | code;
        all = all.intersection(code);
    }
    if polygon.is_empty() || !all.is_empty() {
        Coverage::Outside // an empty polygon shows nothing either
    } else if any.is_empty() {
        Coverage::Inside
    } else {
        Coverage::Straddling
    }
}

/// Clips the convex `polygon` (in clip space, either winding) against `planes`, writing the result to
/// `out`; `scratch` is working space. Both buffers are cleared first and reused, so the hot path does
/// not allocate once they have grown. Fewer than 3 output vertices leave `out` empty.
///
/// New vertices are interpolated from the inside vertex toward the outside one, so an edge shared by
/// two polygons is cut at the identical point whichever polygon it is clipped from. A vertex exactly on
/// a plane counts as inside.
///
/// # Panics
///
/// In debug builds, if a vertex has a non-finite clip position (a caller bug: validate upstream).
///
/// ```
/// use glam::Vec4;
/// use mazewalk_math::{ClipPlanes, DepthRange, clip_polygon};
/// // A triangle poking out through the right side (x <= w) of the volume.
/// let tri = [Vec4::new(0.0, 0.0, 0.5, 1.0), Vec4::new(3.0, 0.0, 0.5, 1.0), Vec4::new(0.0, 0.5, 0.5, 1.0)];
/// let (mut out, mut scratch) = (Vec::new(), Vec::new());
/// clip_polygon(&tri, ClipPlanes::ALL, DepthRange::ZeroToOne, &mut out, &mut scratch);
/// assert_eq!(out.len(), 4); // the tip is cut off
/// assert!(out.iter().all(|v| v.x <= v.w));
/// ```
pub fn clip_polygon<V: ClipVertex>(
    polygon: &[V],
    planes: ClipPlanes,
    depth: DepthRange,
    out: &mut Vec<V>,
    scratch: &mut Vec<V>,
) {
    debug_assert!(polygon.iter().all(|v| v.clip().is_finite()), "non-finite clip coordinates");
    out.clear();
    scratch.clear();
    out.extend_from_slice(polygon);
    for plane in planes.iter() {
        if out.len() < 3 {
            break;
        }
        if out.iter().all(|v| plane.distance(v.clip(), depth) >= 0.0) {
            continue; // wholly inside this plane: skip the copy
        }
        std::mem::swap(out, scratch);
        out.clear();
        clip_against(scratch, plane, depth, out);
    }
    if out.len() < 3 {
        out.clear();
    }
}

/// One Sutherland–Hodgman pass: the part of `input` on the inside of `plane`, appended to `out`.
fn clip_against<V: ClipVertex>(input: &[V], plane: ClipPlane, depth: DepthRange, out: &mut Vec<V>) {
    let Some(last) = input.last() else { return };
    let (mut prev, mut prev_d) = (last, plane.distance(last.clip(), depth));
    for cur in input {
        let cur_d = plane.distance(cur.clip(), depth);
        match (prev_d >= 0.0, cur_d >= 0.0) {
            (true, true) => out.push(cur.clone()),
            (true, false) => out.push(crossing(prev, prev_d, cur, cur_d)), // leaving: keep the crossing
            (false, true) => {
                out.push(crossing(cur, cur_d, prev, prev_d)); // entering: the crossing, then cur
                out.push(cur.clone());
            }
            (false, false) => {}
        }
        (prev, prev_d) = (cur, cur_d);
    }
}

/// The point where the edge from `inside` (distance `d_in >= 0`) to `outside` (`d_out < 0`) meets the
/// plane. Always parameterised from the inside end, so the shared edge of two polygons is cut at
/// bit-identical points whichever way round each polygon walks it.
fn crossing<V: ClipVertex>(inside: &V, d_in: f32, outside: &V, d_out: f32) -> V {
    // The distance is linear along the edge: d(t) = d_in + t·(d_out - d_in) = 0. The denominator is
    // > 0 because d_in >= 0 > d_out, so t is in [0, 1).
    let t = d_in / (d_in - d_out);
    inside.lerp(outside, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(z: f32) -> [Vec4; 4] {
        [
            Vec4::new(-0.5, -0.5, z, 1.0),
            Vec4::new(0.5, -0.5, z, 1.0),
            Vec4::new(0.5, 0.5, z, 1.0),
            Vec4::new(-0.5, 0.5, z, 1.0),
        ]
    }

    #[test]
    fn inside_is_unchanged_and_outside_is_empty() {
        let (mut out, mut scratch) = (Vec::new(), Vec::new());
        clip_polygon(&quad(0.5), ClipPlanes::ALL, DepthRange::ZeroToOne, &mut out, &mut scratch);
        assert_eq!(out, quad(0.5));
        assert_eq!(classify(&quad(0.5), ClipPlanes::ALL, DepthRange::ZeroToOne), Coverage::Inside);
        clip_polygon(&quad(-0.5), ClipPlanes::ALL, DepthRange::ZeroToOne, &mut out, &mut scratch);
        assert!(out.is_empty());
        // z = -0.5 is behind the [0, 1] near plane but inside the [-1, 1] one.
        clip_polygon(&quad(-0.5), ClipPlanes::ALL, DepthRange::NegOneToOne, &mut out, &mut scratch);
        assert_eq!(out, quad(-0.5));
    }

    #[test]
    fn only_the_chosen_planes_clip() {
        let wide =
            [Vec4::new(-3.0, 0.0, 0.5, 1.0), Vec4::new(3.0, 0.0, 0.5, 1.0), Vec4::new(0.0, 0.5, 0.5, 1.0)];
        let (mut out, mut scratch) = (Vec::new(), Vec::new());
        clip_polygon(&wide, ClipPlanes::NEAR, DepthRange::ZeroToOne, &mut out, &mut scratch);
        assert_eq!(out, wide);
        clip_polygon(&wide, ClipPlane::Left.into(), DepthRange::ZeroToOne, &mut out, &mut scratch);
        assert!(out.iter().all(|v| v.x >= -v.w) && out.iter().any(|v| v.x > 1.0));
    }

    #[test]
    fn a_shared_edge_is_cut_at_the_same_point_from_both_sides() {
        let (a, b) = (Vec4::new(0.3, -0.2, 0.4, 1.0), Vec4::new(2.7, 0.9, 0.1, 1.3));
        let left = [a, b, Vec4::new(0.0, 0.9, 0.5, 1.0)];
        let right = [b, a, Vec4::new(0.9, -0.9, 0.5, 1.0)];
        let (mut out1, mut out2, mut scratch) = (Vec::new(), Vec::new(), Vec::new());
        clip_polygon(&left, ClipPlanes::ALL, DepthRange::ZeroToOne, &mut out1, &mut scratch);
        clip_polygon(&right, ClipPlanes::ALL, DepthRange::ZeroToOne, &mut out2, &mut scratch);
        let cut = out1.iter().find(|v| (v.x - v.w).abs() < 1e-6).expect("cut on the right plane");
        assert!(out2.contains(cut), "{cut} not in {out2:?}");
    }
}
