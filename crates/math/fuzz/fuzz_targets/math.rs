//! Feeds arbitrary floats to every math constructor. Asserts: no panic; each result is an error or a
//! finite matrix; and, where the input is valid, what the matrix means (look-at puts the eye at the
//! origin, a projection maps the near plane to the depth range's near end, clipping stays inside).

#![no_main]

use arbitrary::Arbitrary;
use glam::{Mat4, Vec3, Vec4};
use libfuzzer_sys::fuzz_target;
use mazewalk_math::{self as math, ClipPlane, ClipPlanes, Convention, MathError};

#[derive(Arbitrary, Debug)]
struct Input {
    eye: [f32; 3],
    target: [f32; 3],
    up: [f32; 3],
    bounds: [f32; 6],
    fov: f32,
    aspect: f32,
    grid: (u16, u16),
    polygon: Vec<[f32; 4]>,
}

/// Relative closeness, scaled by the magnitudes the value was computed from.
fn close(a: f32, b: f32, scale: f32) -> bool {
    (a - b).abs() <= 1e-4 * scale.max(1.0)
}

/// A constructor's result must be an error or a finite matrix: never NaN silently.
fn finite(result: &Result<Mat4, MathError>) -> Option<Mat4> {
    let m = *result.as_ref().ok()?;
    assert!(m.is_finite(), "non-finite matrix {m}");
    Some(m)
}

fuzz_target!(|input: Input| {
    let (eye, target, up) = (Vec3::from(input.eye), Vec3::from(input.target), Vec3::from(input.up));
    let [l, r, b, t, n, f] = input.bounds;

    for conv in Convention::ALL {
        if let Some(view) = finite(&conv.look_at(eye, target, up)) {
            // Valid input: the eye goes to the origin, the target onto the forward axis.
            let scale = eye.abs().max_element().max(target.abs().max_element());
            if scale < 1e30 {
                let e = view.transform_point3(eye);
                assert!(e.abs().max_element() <= 1e-4 * scale.max(1.0), "{conv:?}: eye → {e}");
                let on_axis = view.transform_point3(target);
                let offset = target - eye;
                let largest = offset.abs().max_element(); // scaled first: 1e20² overflows
                let distance = largest * (offset / largest).length();
                assert!(close(on_axis.dot(conv.forward()), distance, scale), "{conv:?}: target → {on_axis}");
            }
        }
        finite(&conv.look_to(eye, target, up));
        if let Some(proj) = finite(&conv.frustum(l, r, b, t, n, f)) {
            // Valid frustum: the near plane's centre ray lands on the near end of the depth range.
            // Only where f32 can answer: no subnormal products, and near and far not so close that
            // the depth scale (f+n)/(f-n) amplifies rounding past the tolerance.
            let clip = proj * (conv.forward() * n).extend(1.0);
            let depth_scale = ((f + n) / (f - n)).abs();
            if n > 1e-15 && f < 1e15 && depth_scale < 1e3 {
                assert!(close(clip.z / clip.w, conv.depth_range().near(), depth_scale), "{conv:?}: {clip}");
            }
        }
        finite(&conv.orthographic(l, r, b, t, n, f));
        finite(&conv.perspective(input.fov, input.aspect, n, f));
        finite(&conv.perspective_reverse(input.fov, input.aspect, n, f));
        finite(&conv.perspective_infinite(input.fov, input.aspect, n));
        finite(&conv.perspective_infinite_reverse(input.fov, input.aspect, n));
        finite(&math::perspective_hfov(
            conv,
            input.fov,
            input.grid.0.into(),
            input.grid.1.into(),
            input.aspect,
            n,
            f,
        ));
        finite(&math::orthographic_hwidth(
            conv,
            l,
            input.grid.0.into(),
            input.grid.1.into(),
            input.aspect,
            n,
            f,
        ));
        finite(&math::viewport(l, r, conv.depth_range()));
    }
    finite(&math::camera_to_world_rh(eye, target, up));
    finite(&math::camera_to_world_lh(eye, target, up));
    if let Ok(view) = math::look_at_rh(eye, target, up) {
        let _ = math::rigid_inverse(view);
    }
    let model = math::model(eye, math::rotation_z(input.fov), up);
    if let Ok(normal) = math::normal_matrix(model) {
        assert!(normal.is_finite(), "non-finite normal matrix");
    }
    let _ = (
        math::direction_from_yaw_pitch(input.fov, input.aspect),
        math::vertical_fov(input.fov, input.aspect),
    );
    let _ = math::near_corner_distance(n, input.fov, input.aspect);

    // Clipping: finite, moderate coordinates only (the caller's contract); the output must lie inside
    // the volume, relative to the input's size.
    let polygon: Vec<Vec4> = input.polygon.iter().take(16).map(|&p| Vec4::from(p)).collect();
    let scale = polygon.iter().map(|p| p.abs().max_element()).fold(1.0, f32::max);
    if polygon.iter().all(|p| p.is_finite()) && scale < 1e6 {
        for depth in [math::DepthRange::NegOneToOne, math::DepthRange::ZeroToOne] {
            let (mut out, mut scratch) = (Vec::new(), Vec::new());
            math::clip_polygon(&polygon, ClipPlanes::ALL, depth, &mut out, &mut scratch);
            assert!(out.is_empty() || out.len() >= 3);
            for v in &out {
                assert!(v.is_finite(), "{v}");
                for plane in ClipPlane::ALL {
                    assert!(plane.distance(*v, depth) >= -1e-5 * scale, "{v} outside {plane:?}");
                }
            }
            let _ = math::classify(&polygon, ClipPlanes::ALL, depth);
        }
    }
});
