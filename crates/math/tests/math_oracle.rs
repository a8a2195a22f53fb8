//! Every hand-written matrix against its `glam` counterpart (the oracle), over random valid input.
//! Projections go through the crate's one projection API, the [`Convention`] methods, for all three
//! conventions (`arb_convention`), each against the matching `glam::camera` module.
//!
//! Tolerance: 1e-5 relative, per matrix column (see `common::mat4_close`). The two sides compute the
//! same quantities through different but equivalent formulas (tan vs cos/sin, normalize order), so
//! they differ by a few ULPs (1 ULP = 6e-8 relative); 1e-5 leaves room for the ~20× amplification
//! from normalizing a right vector at the 3° limit of `arb_eye_target_up`.

mod common;

use common::*;
use glam::{Mat4, Quat, Vec3, camera};
use mazewalk_math::{self as math, Convention};
use proptest::prelude::*;

const REL: f32 = 1e-5;

/// View matrices: rotation entries (<= 1) to `REL` absolute; translation relative to `|eye| + 1`,
/// because `-right·eye` cancels and keeps only the absolute error of the dot product.
fn view_close(a: Mat4, b: Mat4, eye: Vec3) -> bool {
    let rotation_ok = (0..3).all(|c| close4(a.col(c), b.col(c), REL, 1.0));
    rotation_ok && close4(a.w_axis, b.w_axis, REL, eye.abs().max_element() + 1.0)
}

/// glam's perspective, frustum and orthographic for a convention.
fn glam_perspective(conv: Convention) -> fn(f32, f32, f32, f32) -> Mat4 {
    match conv {
        Convention::RhGl => camera::rh::proj::opengl::perspective,
        Convention::RhZo => camera::rh::proj::directx::perspective,
        Convention::LhZo => camera::lh::proj::directx::perspective,
    }
}

type Infinite = fn(f32, f32, f32) -> Mat4;

/// glam's infinite perspectives, forward and reversed, where it has them: for the [0, 1] conventions
/// (`directx`); its `opengl` modules have none, and `math_depth.rs` checks RhGl's against the limit.
fn glam_perspective_infinite(conv: Convention) -> Option<(Infinite, Infinite)> {
    match conv {
        Convention::RhGl => None,
        Convention::RhZo => Some((
            camera::rh::proj::directx::perspective_infinite,
            camera::rh::proj::directx::perspective_infinite_reverse,
        )),
        Convention::LhZo => Some((
            camera::lh::proj::directx::perspective_infinite,
            camera::lh::proj::directx::perspective_infinite_reverse,
        )),
    }
}

type Box6 = fn(f32, f32, f32, f32, f32, f32) -> Mat4;

fn glam_frustum(conv: Convention) -> Box6 {
    match conv {
        Convention::RhGl => camera::rh::proj::opengl::frustum,
        Convention::RhZo => camera::rh::proj::directx::frustum,
        Convention::LhZo => camera::lh::proj::directx::frustum,
    }
}

fn glam_orthographic(conv: Convention) -> Box6 {
    match conv {
        Convention::RhGl => camera::rh::proj::opengl::orthographic,
        Convention::RhZo => camera::rh::proj::directx::orthographic,
        Convention::LhZo => camera::lh::proj::directx::orthographic,
    }
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn perspective_matches_glam(conv in arb_convention(), (fov, aspect, n, f) in arb_perspective()) {
        let ours = conv.perspective(fov, aspect, n, f).unwrap();
        let theirs = glam_perspective(conv)(fov, aspect, n, f);
        prop_assert!(mat4_close(ours, theirs, REL), "{conv:?}\nours   {ours}\ntheirs {theirs}");
    }

    #[test]
    fn frustum_matches_glam(conv in arb_convention(), [l, r, b, t, n, f] in arb_frustum()) {
        let ours = conv.frustum(l, r, b, t, n, f).unwrap();
        let theirs = glam_frustum(conv)(l, r, b, t, n, f);
        prop_assert!(mat4_close(ours, theirs, REL), "{conv:?}\nours   {ours}\ntheirs {theirs}");
    }

    #[test]
    fn orthographic_matches_glam(conv in arb_convention(), [l, r, b, t, n, f] in arb_ortho()) {
        let ours = conv.orthographic(l, r, b, t, n, f).unwrap();
        let theirs = glam_orthographic(conv)(l, r, b, t, n, f);
        prop_assert!(mat4_close(ours, theirs, REL), "{conv:?}\nours   {ours}\ntheirs {theirs}");
    }

    #[test]
    fn look_at_matches_glam((eye, target, up) in arb_eye_target_up()) {
        let rh = math::look_at_rh(eye, target, up).unwrap();
        let glam_rh = camera::rh::view::look_at_mat4(eye, target, up);
        prop_assert!(view_close(rh, glam_rh, eye), "rh\nours   {rh}\ntheirs {glam_rh}");
        let lh = math::look_at_lh(eye, target, up).unwrap();
        let glam_lh = camera::lh::view::look_at_mat4(eye, target, up);
        prop_assert!(view_close(lh, glam_lh, eye), "lh\nours   {lh}\ntheirs {glam_lh}");
    }

    #[test]
    fn look_to_matches_glam((eye, dir, up) in arb_eye_dir_up()) {
        let rh = math::look_to_rh(eye, dir, up).unwrap();
        let glam_rh = camera::rh::view::look_to_mat4(eye, dir, up);
        prop_assert!(view_close(rh, glam_rh, eye), "rh\nours   {rh}\ntheirs {glam_rh}");
        let lh = math::look_to_lh(eye, dir, up).unwrap();
        let glam_lh = camera::lh::view::look_to_mat4(eye, dir, up);
        prop_assert!(view_close(lh, glam_lh, eye), "lh\nours   {lh}\ntheirs {glam_lh}");
    }

    #[test]
    fn infinite_perspectives_match_glam(
        conv in arb_convention().prop_filter("glam has no OpenGL-range infinite perspective", |c| *c != Convention::RhGl),
        (fov, aspect, n, _) in arb_perspective(),
    ) {
        let (forward, reverse) = glam_perspective_infinite(conv).unwrap();
        let ours = conv.perspective_infinite(fov, aspect, n).unwrap();
        let theirs = forward(fov, aspect, n);
        prop_assert!(mat4_close(ours, theirs, REL), "{conv:?}\nours   {ours}\ntheirs {theirs}");
        let ours = conv.perspective_infinite_reverse(fov, aspect, n).unwrap();
        let theirs = reverse(fov, aspect, n);
        prop_assert!(mat4_close(ours, theirs, REL), "{conv:?} reversed\nours   {ours}\ntheirs {theirs}");
    }

    #[test]
    fn elementary_transforms_match_glam(offset in arb_point(100.0), factors in arb_point(10.0), angle in -10.0f32..10.0) {
        prop_assert_eq!(math::translation(offset), Mat4::from_translation(offset));
        prop_assert_eq!(math::scaling(factors), Mat4::from_scale(factors));
        // sin/cos are the same calls on both sides, but glam may build the matrix through a quaternion.
        prop_assert!(mat4_close(math::rotation_x(angle), Mat4::from_rotation_x(angle), REL));
        prop_assert!(mat4_close(math::rotation_y(angle), Mat4::from_rotation_y(angle), REL));
        prop_assert!(mat4_close(math::rotation_z(angle), Mat4::from_rotation_z(angle), REL));
    }

    #[test]
    fn model_matches_glam_scale_rotation_translation(t in arb_point(100.0), s in arb_point(10.0), axis in arb_unit(), angle in -4.0f32..4.0) {
        let rotation = Quat::from_axis_angle(axis, angle);
        let ours = math::model(t, Mat4::from_quat(rotation), s);
        let theirs = Mat4::from_scale_rotation_translation(s, rotation, t);
        prop_assert!(mat4_close(ours, theirs, REL), "ours   {ours}\ntheirs {theirs}");
    }
}
