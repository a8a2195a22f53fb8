//! What the matrices mean, checked without glam's camera module: where points land, not entries.
//!
//! Tolerances are relative to the magnitudes involved (see `common::close`): 1e-5 for a handful of
//! roundings (1 ULP = 6e-8), 1e-4 where a projective divide or a general 4×4 inverse amplifies them.

mod common;

use common::*;
use glam::{Mat3, Mat4, Quat, Vec3, Vec4};
use mazewalk_math::{self as math, Convention, DepthRange, MathError};
use proptest::prelude::*;

/// Projects a view-space point to NDC.
fn ndc(proj: Mat4, view: Vec3) -> Vec3 {
    let clip = proj * view.extend(1.0);
    clip.truncate() / clip.w
}

/// A view-space point at `distance` in front of the eye, with lateral offsets `x`, `y`.
fn ahead(conv: Convention, x: f32, y: f32, distance: f32) -> Vec3 {
    Vec3::new(x, y, 0.0) + conv.forward() * distance
}

proptest! {
    #![proptest_config(common::config())]

    #[test]
    fn view_rotation_is_orthonormal_with_determinant_one((eye, target, up) in arb_eye_target_up()) {
        for view in [math::look_at_rh(eye, target, up).unwrap(), math::look_at_lh(eye, target, up).unwrap()] {
            let r = Mat3::from_mat4(view);
            prop_assert!((r * r.transpose()).abs_diff_eq(Mat3::IDENTITY, 1e-5), "{r}");
            prop_assert!(close(r.determinant(), 1.0, 1e-5, 1.0));
            prop_assert_eq!(view.row(3), Vec4::W); // affine: no projective part
        }
    }

    #[test]
    fn cameras_just_above_the_up_parallel_threshold_are_orthonormal(
        (eye, dir, up) in arb_up_near_parallel(1.01e-4, 3e-4), scale in prop::sample::select(vec![1e-3f32, 1.0, 1e3]),
    ) {
        // The view's rotation and the camera-to-world basis are orthonormal to 1e-6 (a few ULPs of
        // rounding in each product entry, 6e-8 each, with margin), however nearly parallel the
        // accepted up is; before the re-orthogonalisation they were off by up to 4.2e-4 here.
        let (dir, up) = (dir * scale, up / scale); // lengths play no part
        for (view, to_world) in [
            (math::look_to_rh(eye, dir, up).unwrap(), math::camera_to_world_rh(eye, dir, up).unwrap()),
            (math::look_to_lh(eye, dir, up).unwrap(), math::camera_to_world_lh(eye, dir, up).unwrap()),
        ] {
            for r in [Mat3::from_mat4(view), Mat3::from_mat4(to_world)] {
                let off = (r * r.transpose() - Mat3::IDENTITY).to_cols_array().map(f32::abs);
                prop_assert!(off.iter().all(|&e| e <= 1e-6), "R·Rᵀ - I = {off:?}");
                prop_assert!(close(r.determinant(), 1.0, 1e-6, 1.0), "det {}", r.determinant());
            }
        }
    }

    #[test]
    fn up_just_below_the_threshold_is_parallel((eye, dir, up) in arb_up_near_parallel(0.0, 0.99e-4)) {
        // The other side of the rule: a sine below 1e-4 (by more than its ~1e-7 rounding) is refused.
        prop_assert_eq!(math::look_to_rh(eye, dir, up), Err(MathError::UpParallel { dir, up }));
        prop_assert_eq!(math::look_to_lh(eye, dir, up), Err(MathError::UpParallel { dir, up }));
    }

    #[test]
    fn look_at_puts_eye_at_origin_and_target_on_the_forward_axis((eye, target, up) in arb_eye_target_up()) {
        let scale = eye.abs().max_element().max(target.abs().max_element());
        let distance = (target - eye).length();
        for (view, forward) in [
            (math::look_at_rh(eye, target, up).unwrap(), Vec3::NEG_Z),
            (math::look_at_lh(eye, target, up).unwrap(), Vec3::Z),
        ] {
            // Translations cancel |eye|-sized terms: the error is relative to the inputs' size.
            prop_assert!(close3(view.transform_point3(eye), Vec3::ZERO, 1e-5, scale));
            prop_assert!(close3(view.transform_point3(target), forward * distance, 1e-5, scale));
            let up_view = view.transform_vector3(up);
            prop_assert!(up_view.y > 0.0, "up lands below the horizon: {up_view}");
            prop_assert!(up_view.x.abs() < 1e-5, "up is tilted sideways: {up_view}");
        }
    }

    #[test]
    fn fast_look_at_is_the_inverse_of_camera_to_world((eye, target, up) in arb_eye_target_up()) {
        let dir = target - eye;
        for (view, to_world) in [
            (math::look_at_rh(eye, target, up).unwrap(), math::camera_to_world_rh(eye, dir, up).unwrap()),
            (math::look_at_lh(eye, target, up).unwrap(), math::camera_to_world_lh(eye, dir, up).unwrap()),
        ] {
            let general = to_world.inverse();
            // General inverse of a matrix with |eye|-sized entries: 1e-4 per column.
            prop_assert!(mat4_close(view, general, 1e-4), "fast {view}\ngeneral {general}");
            prop_assert!(mat4_close(math::rigid_inverse(view), to_world, 1e-4));
        }
    }

    #[test]
    fn near_and_far_planes_map_to_the_depth_range_ends_monotonically(
        conv in arb_convention(), [l, r, b, t, n, f] in arb_frustum(), u in 0.0f32..1.0, v in 0.0f32..1.0,
    ) {
        let proj = conv.frustum(l, r, b, t, n, f).unwrap();
        let range = conv.depth_range();
        prop_assert!(close(ndc(proj, ahead(conv, 0.3, -0.2, n)).z, range.near(), 1e-4, 1.0));
        prop_assert!(close(ndc(proj, ahead(conv, 0.3, -0.2, f)).z, range.far(), 1e-4, 1.0));
        let (d1, d2) = (n + (f - n) * u.min(v), n + (f - n) * u.max(v));
        let (z1, z2) = (ndc(proj, ahead(conv, 0.0, 0.0, d1)).z, ndc(proj, ahead(conv, 0.0, 0.0, d2)).z);
        prop_assert!(z1 <= z2 + 1e-6, "depth not monotonic: d {d1} → {z1}, d {d2} → {z2}");
    }

    #[test]
    fn frustum_corners_map_to_ndc_cube_corners(conv in arb_convention(), [l, r, b, t, n, f] in arb_frustum()) {
        let proj = conv.frustum(l, r, b, t, n, f).unwrap();
        let range = conv.depth_range();
        // An off-centre sliver subtracts (r+l) from a value of about the same size and divides by
        // (r-l): rounding grows by the condition number |r+l|/(r-l) (up to ~2e3 in arb_frustum).
        let condition = 1.0 + (r + l).abs() / (r - l) + (t + b).abs() / (t - b);
        for (x, nx) in [(l, -1.0), (r, 1.0)] {
            for (y, ny) in [(b, -1.0), (t, 1.0)] {
                // Near corners as given; far corners scaled out along the same ray (similar triangles).
                let near = ndc(proj, ahead(conv, x, y, n));
                let far = ndc(proj, ahead(conv, x * f / n, y * f / n, f));
                prop_assert!(close3(near, Vec3::new(nx, ny, range.near()), 1e-5, condition), "{near}");
                prop_assert!(close3(far, Vec3::new(nx, ny, range.far()), 1e-5, condition), "{far}");
            }
        }
    }

    #[test]
    fn ortho_corners_map_to_ndc_cube_corners(conv in arb_convention(), [l, r, b, t, n, f] in arb_ortho()) {
        let proj = conv.orthographic(l, r, b, t, n, f).unwrap();
        let range = conv.depth_range();
        let scale = n.abs().max(f.abs()) / (f - n); // depth cancellation grows with |near| / depth
        for (x, nx) in [(l, -1.0), (r, 1.0)] {
            for (y, ny) in [(b, -1.0), (t, 1.0)] {
                for (d, nz) in [(n, range.near()), (f, range.far())] {
                    let p = proj.transform_point3(ahead(conv, x, y, d));
                    prop_assert!(close3(p, Vec3::new(nx, ny, nz), 1e-4, 1.0 + scale), "{p}");
                }
            }
        }
    }

    #[test]
    fn perspective_puts_the_field_of_view_on_the_ndc_edges(
        conv in arb_convention(), (fov, aspect, n, f) in arb_perspective(), u in 0.0f32..1.0,
    ) {
        // A ray fov/2 above the view axis meets the top edge of NDC at every distance, and the ray
        // whose slope is aspect times as wide meets the right edge: the view's height and width.
        let proj = conv.perspective(fov, aspect, n, f).unwrap();
        let d = n + (f - n) * u;
        let slope = (fov / 2.0).tan(); // height / distance
        let top = ndc(proj, ahead(conv, 0.0, d * slope, d));
        let right = ndc(proj, ahead(conv, d * slope * aspect, 0.0, d));
        // x_ndc = (2n/(r-l))·x/d: a handful of roundings, relative.
        prop_assert!(close(top.y, 1.0, 1e-5, 1.0) && close(top.x, 0.0, 1e-5, 1.0), "top edge: {top}");
        prop_assert!(close(right.x, 1.0, 1e-5, 1.0) && close(right.y, 0.0, 1e-5, 1.0), "right edge: {right}");
    }

    #[test]
    fn every_convention_sees_the_world_the_same_way_round(
        conv in arb_convention(), (eye, target, up) in arb_eye_target_up(), along in 0.1f32..10.0, side in 0.1f32..10.0, lift in 0.1f32..10.0,
    ) {
        // World right-handed: looking along dir with up roughly up, dir × up points to the right.
        // Every convention's view puts what is ahead on its forward axis, what is to the right at
        // +x and what is above at +y, whichever handedness its view space has.
        let dir = (target - eye).normalize();
        let right = dir.cross(up).normalize();
        let above = right.cross(dir);
        let view = conv.look_at(eye, target, up).unwrap();
        let scale = eye.abs().max_element() + 20.0; // translations cancel |eye|-sized terms
        let ahead = view.transform_point3(eye + dir * along);
        prop_assert!(close3(ahead, conv.forward() * along, 1e-5, scale), "{conv:?}: ahead → {ahead}");
        let to_the_right = view.transform_point3(eye + dir * along + right * side);
        prop_assert!(close(to_the_right.x, side, 1e-5, scale) && close(to_the_right.y, 0.0, 1e-5, scale), "{conv:?}: right → {to_the_right}");
        let up_there = view.transform_point3(eye + dir * along + above * lift);
        prop_assert!(close(up_there.y, lift, 1e-5, scale) && close(up_there.x, 0.0, 1e-5, scale), "{conv:?}: above → {up_there}");
    }

    #[test]
    fn inverse_undoes_model_and_projection(
        conv in arb_convention(), (fov, aspect, n, f) in arb_perspective(),
        t in arb_point(100.0), axis in arb_unit(), angle in -4.0f32..4.0,
        s in arb_point(10.0).prop_filter("a scale near 0 is (nearly) singular", |s| s.abs().min_element() > 0.1),
    ) {
        let model = math::model(t, Mat4::from_quat(Quat::from_axis_angle(axis, angle)), s);
        // Conditioned by the scale ratio (<= 100) and |t| (<= 100 × 1.7): 1e-4 relative to |t|.
        prop_assert!(mat4_close(model.inverse() * model, Mat4::IDENTITY, 1e-4 * (1.0 + t.length())));
        // A projection's condition number grows with far/near and 1/tan(fov); check the round trip of
        // a point instead of entries: view → clip → view.
        let proj = conv.perspective(fov, aspect, n, f).unwrap();
        let view = ahead(conv, 0.1 * n, -0.1 * n, (n + f) / 2.0);
        let back = proj.inverse().project_point3(proj.project_point3(view));
        prop_assert!(close3(back, view, 1e-3, view.length()), "{view} → {back}");
    }

    #[test]
    fn model_scales_then_rotates_then_translates(
        t in arb_point(100.0), s in arb_point(10.0), angle in -4.0f32..4.0, p in arb_point(10.0),
    ) {
        let rotation = math::rotation_z(angle);
        let expected = t + rotation.transform_vector3(s * p);
        let got = math::model(t, rotation, s).transform_point3(p);
        prop_assert!(close3(got, expected, 1e-5, t.length() + 100.0), "{got} vs {expected}");
    }

    #[test]
    fn normal_matrix_keeps_normals_perpendicular(
        axis in arb_unit(), angle in -4.0f32..4.0,
        s in arb_point(10.0).prop_filter("a scale near 0 is (nearly) singular", |s| s.abs().min_element() > 0.1),
        a in arb_unit(), b in arb_unit(),
    ) {
        prop_assume!(a.cross(b).length() > 0.1); // two tangents spanning a surface
        let model = math::model(Vec3::ZERO, Mat4::from_quat(Quat::from_axis_angle(axis, angle)), s);
        let normal = math::normal_matrix(model).unwrap() * a.cross(b);
        for tangent in [model.transform_vector3(a), model.transform_vector3(b)] {
            // Cosine of the angle between them, so the test is scale-free.
            let cosine = normal.dot(tangent) / (normal.length() * tangent.length());
            prop_assert!(cosine.abs() < 1e-5, "cos = {cosine}");
        }
    }

    #[test]
    fn viewport_maps_ndc_corners_to_grid_corners(
        width in 1.0f32..500.0, height in 1.0f32..500.0,
        depth in prop::sample::select(vec![DepthRange::NegOneToOne, DepthRange::ZeroToOne]),
    ) {
        let vp = math::viewport(width, height, depth).unwrap();
        let scale = width.max(height);
        let cases = [
            (Vec3::new(-1.0, 1.0, depth.near()), Vec3::new(0.0, 0.0, 0.0)),
            (Vec3::new(1.0, 1.0, depth.near()), Vec3::new(width, 0.0, 0.0)),
            (Vec3::new(-1.0, -1.0, depth.far()), Vec3::new(0.0, height, 1.0)),
            (Vec3::new(1.0, -1.0, depth.far()), Vec3::new(width, height, 1.0)),
            (Vec3::new(0.0, 0.0, (depth.near() + 1.0) / 2.0), Vec3::new(width / 2.0, height / 2.0, 0.5)),
        ];
        for (ndc, grid) in cases {
            prop_assert!(close3(vp.transform_point3(ndc), grid, 1e-6, scale), "{ndc} → {}", vp.transform_point3(ndc));
        }
    }

    #[test]
    fn mirrored_scenes_land_on_the_same_screen_point(
        (eye, target, up) in arb_eye_target_up(), (fov, aspect, n, f) in arb_perspective(), p in arb_point(100.0),
    ) {
        // A reflection of the whole world (eye, target, up and the point) through the plane z = 0.
        let mirror = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
        let rh = Convention::RhZo.perspective(fov, aspect, n, f).unwrap() * math::look_at_rh(eye, target, up).unwrap();
        let lh = Convention::LhZo.perspective(fov, aspect, n, f).unwrap()
            * math::look_at_lh(mirror(eye), mirror(target), mirror(up)).unwrap();
        let (clip_rh, clip_lh) = (rh * p.extend(1.0), lh * mirror(p).extend(1.0));
        // Compare in clip space (no divide), relative to the scene's size.
        prop_assert!(close4(clip_rh, clip_lh, 1e-4, 200.0 / n), "{clip_rh} vs {clip_lh}");
    }

    #[test]
    fn every_convention_renders_the_same_frame(
        (eye, target, up) in arb_eye_target_up(), (fov, aspect, n, f) in arb_perspective(), p in arb_point(100.0),
    ) {
        let grid = |conv: Convention| {
            let view = conv.look_at(eye, target, up).unwrap();
            let proj = conv.perspective(fov, aspect, n, f).unwrap();
            let vp = math::viewport(80.0, 24.0, conv.depth_range()).unwrap();
            vp * proj * view * p.extend(1.0) // grid coordinates, still homogeneous
        };
        // Homogeneous grid coordinates (before the divide) agree for every point, in front or behind,
        // so no point is excluded; rounding is relative to the largest component.
        let first = grid(Convention::RhGl);
        for conv in [Convention::RhZo, Convention::LhZo] {
            let other = grid(conv);
            let scale = first.abs().max_element();
            prop_assert!(close4(first, other, 1e-4, scale), "{conv:?}: {first} vs {other}");
        }
    }

    #[test]
    fn horizontal_fov_reaches_the_grid_edges(
        conv in arb_convention(), hfov in 0.1f32..3.0, cols in 1usize..400, rows in 1usize..200,
        sample_aspect in 0.2f32..2.0, yaw in -4.0f32..4.0, distance in 0.2f32..50.0, eye in arb_point(50.0),
    ) {
        let (n, f) = (0.1, 100.0);
        let proj = math::perspective_hfov(conv, hfov, cols, rows, sample_aspect, n, f).unwrap();
        let aspect = math::physical_aspect(cols, rows, sample_aspect).unwrap();
        let vfov = math::vertical_fov(hfov, aspect);
        let via_vfov = conv.perspective(vfov, aspect, n, f).unwrap();
        // The atan/tan round trip through vfov (which perspective_hfov skips) loses 1/cos(vfov/2) ULPs
        // of tan as vfov nears π (a tall thin grid).
        let round_trip = 1e-5 / (vfov / 2.0).cos();
        prop_assert!(mat4_close(proj, via_vfov, round_trip), "{proj}\n{via_vfov}");
        let view = conv.look_to(eye, math::direction_from_yaw_pitch(yaw, 0.0), Vec3::Z).unwrap();
        let vp = math::viewport(cols as f32, rows as f32, conv.depth_range()).unwrap();
        // Yaw is counter-clockwise, so the right edge is at yaw - hfov/2.
        for (side, edge) in [(1.0f32, 0.0f32), (-1.0, cols as f32)] {
            let world = eye + math::direction_from_yaw_pitch(yaw + side * hfov / 2.0, 0.0) * distance;
            let grid = vp.project_point3((proj * view).project_point3(world));
            // Off-axis angles near ±90° lose digits in tan: 1e-3 of the grid width.
            prop_assert!(close(grid.x, edge, 1e-3, cols as f32), "{grid} vs x = {edge}");
            prop_assert!(close(grid.y, rows as f32 / 2.0, 1e-3, cols as f32), "{grid}");
        }
    }

    #[test]
    fn near_corner_distance_reaches_the_near_plane_corner(
        conv in arb_convention(), hfov in 0.1f32..3.0, cols in 1usize..400, rows in 1usize..200, n in 0.01f32..1.0,
    ) {
        let proj = math::perspective_hfov(conv, hfov, cols, rows, 0.5, n, 100.0).unwrap();
        let aspect = math::physical_aspect(cols, rows, 0.5).unwrap();
        let corner = proj.inverse().project_point3(Vec3::new(1.0, 1.0, conv.depth_range().near()));
        let d = math::near_corner_distance(n, hfov, aspect);
        prop_assert!(close(corner.length(), d, 1e-3, d), "{} vs {d}", corner.length());
    }

    #[test]
    fn yaw_pitch_cameras_never_flip(yaw in -7.0f32..7.0, pitch in -std::f32::consts::FRAC_PI_2..=std::f32::consts::FRAC_PI_2, eye in arb_point(50.0)) {
        let (dir, up) = (math::direction_from_yaw_pitch(yaw, pitch), math::up_from_yaw_pitch(yaw, pitch));
        prop_assert!(close(dir.length(), 1.0, 1e-6, 1.0) && close(up.length(), 1.0, 1e-6, 1.0));
        prop_assert!(dir.dot(up).abs() < 1e-6);
        for to_world in [math::camera_to_world_rh(eye, dir, up).unwrap(), math::camera_to_world_lh(eye, dir, up).unwrap()] {
            // The camera's right stays level (no roll) and its up never points below the horizon.
            prop_assert!(to_world.x_axis.z.abs() < 1e-5, "rolled: right = {}", to_world.x_axis);
            prop_assert!(to_world.y_axis.z > -1e-6, "flipped: up = {}", to_world.y_axis);
        }
    }
}
