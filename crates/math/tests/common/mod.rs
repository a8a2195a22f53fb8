//! Shared by the math crate's tests: tolerant comparisons of vectors and matrices, and the named
//! strategies of every property (cameras, frusta, boxes, conventions).

// Each test crate includes this module and uses a different subset of it.
#![allow(dead_code)]

use glam::{Mat4, Vec3, Vec4};
pub use mazewalk_testkit::{close, config};

/// Component-wise [`close`].
pub fn close3(a: Vec3, b: Vec3, rel: f32, scale: f32) -> bool {
    (0..3).all(|i| close(a[i], b[i], rel, scale))
}

/// Component-wise [`close`] for `Vec4`.
pub fn close4(a: Vec4, b: Vec4, rel: f32, scale: f32) -> bool {
    (0..4).all(|i| close(a[i], b[i], rel, scale))
}

/// Two matrices agree column by column, each column relative to its own largest entry (in either
/// matrix). Columns mix quantities of different sizes (a look-at's rotation is <= 1, its translation
/// is about |eye|), and rounding in an entry scales with the column it is computed with.
pub fn mat4_close(a: Mat4, b: Mat4, rel: f32) -> bool {
    (0..4).all(|c| {
        let (ca, cb) = (a.col(c), b.col(c));
        let scale = ca.abs().max_element().max(cb.abs().max_element());
        close4(ca, cb, rel, scale)
    })
}

// ---- Named strategies ------------------------------------------------------------------------
//
// Ranges cover what a maze walkthrough can meet (a few hundred units, near planes from 1 cm) with
// margin, and exclude only what is numerically meaningless in f32: up vectors within ~3° of the view
// direction (the right vector is a cross product of nearly parallel vectors, so its direction is
// mostly rounding), slivers of frusta thinner than 1e-3 of their offset, and far/near ratios beyond
// 1e3 (depth precision is gone long before).

use proptest::prelude::*;

/// A point in the cube `[-extent, extent]³`.
pub fn arb_point(extent: f32) -> impl Strategy<Value = Vec3> {
    (-extent..extent, -extent..extent, -extent..extent).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A unit vector, from a point in the unit cube that is not too short to normalize accurately.
pub fn arb_unit() -> impl Strategy<Value = Vec3> {
    arb_point(1.0)
        .prop_filter("too short to normalize accurately", |v| v.length() > 0.1)
        .prop_map(Vec3::normalize)
}

/// A look-at camera `(eye, target, up)`: eye within 100 units of the origin, target 0.1–100 units
/// away, unit `up` at least ~3° (sine 0.05) from the view direction.
pub fn arb_eye_target_up() -> impl Strategy<Value = (Vec3, Vec3, Vec3)> {
    (arb_point(100.0), arb_unit(), 0.1f32..100.0, arb_unit())
        .prop_filter("up nearly parallel to the view direction", |(_, dir, _, up)| {
            dir.cross(*up).length() > 0.05
        })
        .prop_map(|(eye, dir, distance, up)| (eye, eye + dir * distance, up))
}

/// A look-to camera `(eye, unit dir, unit up)`, same ranges as [`arb_eye_target_up`].
pub fn arb_eye_dir_up() -> impl Strategy<Value = (Vec3, Vec3, Vec3)> {
    (arb_point(100.0), arb_unit(), arb_unit())
        .prop_filter("up nearly parallel to the view direction", |(_, dir, up)| {
            dir.cross(*up).length() > 0.05
        })
}

/// A look-to camera `(eye, unit dir, unit up)` whose up is nearly parallel (or anti-parallel) to the
/// view direction: the sine of their angle is in `[min_sine, max_sine)`, built in f64 and rounded to
/// f32 (which moves the sine by about 1e-7 of its 1e-4, so keep the range 1 % clear of a threshold).
pub fn arb_up_near_parallel(min_sine: f64, max_sine: f64) -> impl Strategy<Value = (Vec3, Vec3, Vec3)> {
    (arb_point(100.0), arb_unit(), arb_unit(), min_sine..max_sine, any::<bool>()).prop_filter_map(
        "the second vector is parallel to the direction",
        |(eye, dir, other, sine, opposite)| {
            let d = dir.as_dvec3().normalize();
            let side = (other.as_dvec3() - d * d.dot(other.as_dvec3())).try_normalize()?; // ⟂ d
            let cosine = (1.0 - sine * sine).sqrt() * if opposite { -1.0 } else { 1.0 };
            Some((eye, dir, (d * cosine + side * sine).as_vec3()))
        },
    )
}

/// A perspective frustum `[left, right, bottom, top, near, far]`: bounds within 10 units, width and
/// height at least 0.01 (so `(r+l)/(r-l)` stays below ~2e3), near in [0.01, 10], far/near in
/// [1.01, 1e3].
pub fn arb_frustum() -> impl Strategy<Value = [f32; 6]> {
    (-10.0f32..10.0, 0.01f32..10.0, -10.0f32..10.0, 0.01f32..10.0, 0.01f32..10.0, 1.01f32..1e3)
        .prop_map(|(l, w, b, h, n, ratio)| [l, l + w, b, b + h, n, n * ratio])
}

/// An orthographic box `[left, right, bottom, top, near, far]`: as [`arb_frustum`] across, near in
/// [-100, 100] (a box may start behind the eye), depth 0.01–1000.
pub fn arb_ortho() -> impl Strategy<Value = [f32; 6]> {
    (-10.0f32..10.0, 0.01f32..10.0, -10.0f32..10.0, 0.01f32..10.0, -100.0f32..100.0, 0.01f32..1e3)
        .prop_map(|(l, w, b, h, n, d)| [l, l + w, b, b + h, n, n + d])
}

/// A symmetric perspective `(fov_y, aspect, near, far)`: fov in [0.01, 3.1] rad (not touching 0 or π,
/// where tan blows up), aspect in [0.05, 20], near and far as in [`arb_frustum`].
pub fn arb_perspective() -> impl Strategy<Value = (f32, f32, f32, f32)> {
    (0.01f32..3.1, 0.05f32..20.0, 0.01f32..10.0, 1.01f32..1e3)
        .prop_map(|(fov, aspect, n, ratio)| (fov, aspect, n, n * ratio))
}

/// A projection convention.
pub fn arb_convention() -> impl Strategy<Value = mazewalk_math::Convention> {
    prop::sample::select(mazewalk_math::Convention::ALL.to_vec())
}
