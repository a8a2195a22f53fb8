//! The math core against two oracles nobody here wrote: nalgebra, in f64, and cgmath, in f64. glam
//! (`crates/math/tests/math_oracle.rs`) is the first oracle; a bug shared with glam's conventions
//! would pass there and must fail here. Each property also checks the two oracles against each other
//! (to 1e-12, f64 rounding), so a disagreement between them cannot hide behind our tolerance.
//!
//! # What each library provides, and how the other conventions are derived
//!
//! Both libraries write look-at right- and left-handed (nalgebra `Matrix4::look_at_rh`/`_lh`, cgmath
//! `Matrix4::look_at_rh`/`_lh`), and projections only right-handed with depth in [-1, 1] (OpenGL):
//! perspective (nalgebra `Matrix4::new_perspective`, cgmath `perspective`), orthographic (nalgebra
//! `Matrix4::new_orthographic`, cgmath `ortho`) and, in cgmath only, the off-centre frustum
//! (`frustum`; nalgebra has none). The crate's other conventions are derived from those exactly,
//! by two matrices whose entries are 0, ±1 and ½:
//!
//! * **Depth [0, 1] from [-1, 1]**, same handedness: `z₀₁ = (z₋₁₁ + 1) / 2` in NDC, so in clip space
//!   `z' = (z + w) / 2`: `P_zo = Z · P_gl` with `Z` the identity but for row 3 = `(0, 0, ½, ½)`. In f64
//!   the halving is exact and the sum rounds once.
//! * **Left-handed from right-handed**, same depth range: left-handed view space is right-handed view
//!   space with z negated, `p_rh = F · p_lh` with `F = diag(1, 1, -1, 1)`, so `P_lh = P_rh · F`: the
//!   third column negated, exactly.
//! * **Reversed depth** (near → 1, far → the range's near end): `z → -z` on [-1, 1] (`R_gl =
//!   diag(1, 1, -1, 1)` on the left) and `z → w - z` on [0, 1] (`R_zo`, row 3 = `(0, 0, -1, 1)`).
//! * **Infinite far plane**: the finite projection at `far = 1e15 · near`, whose distance from the
//!   limit (relative `near/far`) is below f64's rounding of f32's.
//!
//! So RhGl is the library's matrix, RhZo is `Z · P`, LhZo is `Z · P · F`.
//!
//! The viewport is in neither library; it is the inverse of the orthographic projection of the grid's
//! box, `[0, width] × [height, 0]` (grid y down) with depth 0 → the range's near end, 1 → 1, which is
//! what a viewport is: NDC back to the box. That inverse is nalgebra's (`try_inverse`) and cgmath's
//! (`invert`) of their own `ortho`, depth-derived as above.
//!
//! The normal matrix is checked against nalgebra's f64 inverse transpose, to a tolerance that grows
//! with the matrix's condition number (nalgebra's SVD), as the error of any inverse does.
//!
//! # Tolerances
//!
//! The oracles are exact to 1e-16; the tolerances are our f32 error. Projections and viewports: 1e-5
//! relative per column (a few roundings, 6e-8 each, times the conditioning of off-centre frusta that
//! `arb_frustum` bounds). Views: 1e-5 on the rotation (the right axis of `arb_eye_target_up` may be a
//! cross product of vectors 3° apart, amplifying ε about 20×), translation relative to `|eye| + 1`.

#[path = "../../math/tests/common/mod.rs"]
mod common;

use cgmath::SquareMatrix;
use common::*;
use glam::{Mat3, Mat4, Vec3};
use mazewalk_math::{self as math, Convention, DepthRange};
use nalgebra::{Matrix3, Matrix4, Point3, Vector3};
use proptest::prelude::*;

type M4 = Matrix4<f64>;

const REL: f64 = 1e-5;

/// Agreement of the two oracles: f64 rounding of the same quantities, through different formulas.
const ORACLES_AGREE: f64 = 1e-12;

fn na(m: Mat4) -> M4 {
    M4::from_column_slice(&m.to_cols_array().map(f64::from))
}

fn from_cg(m: cgmath::Matrix4<f64>) -> M4 {
    let cols: &[[f64; 4]; 4] = m.as_ref();
    M4::from_column_slice(cols.as_flattened())
}

fn p3(v: Vec3) -> Point3<f64> {
    Point3::new(v.x.into(), v.y.into(), v.z.into())
}

fn v3(v: Vec3) -> Vector3<f64> {
    Vector3::new(v.x.into(), v.y.into(), v.z.into())
}

fn cg_p3(v: Vec3) -> cgmath::Point3<f64> {
    cgmath::Point3::new(v.x.into(), v.y.into(), v.z.into())
}

fn cg_v3(v: Vec3) -> cgmath::Vector3<f64> {
    cgmath::Vector3::new(v.x.into(), v.y.into(), v.z.into())
}

/// Column by column, each relative to its own largest entry in either matrix (and to `floor`).
fn columns_close(a: &M4, b: &M4, rel: f64, floor: f64) -> bool {
    (0..4).all(|c| {
        let scale = a.column(c).amax().max(b.column(c).amax()).max(floor);
        (a.column(c) - b.column(c)).amax() <= rel * scale
    })
}

/// A view matrix: the rotation (entries <= 1) to `REL`, the translation relative to `|eye| + 1`
/// (`-right·eye` cancels and keeps only the dot product's absolute error).
fn view_close(ours: &M4, exact: &M4, eye: Vec3) -> bool {
    let rotation = (0..3).all(|c| (ours.column(c) - exact.column(c)).amax() <= REL);
    let translation =
        (ours.column(3) - exact.column(3)).amax() <= REL * f64::from(eye.abs().max_element() + 1.0);
    rotation && translation
}

/// `Z`: clip z → (z + w) / 2, depth [-1, 1] → [0, 1].
fn zero_to_one() -> M4 {
    let mut z = M4::identity();
    z[(2, 2)] = 0.5;
    z[(2, 3)] = 0.5;
    z
}

/// `F`: view z → -z, right-handed view space ↔ left-handed.
fn flip_z() -> M4 {
    M4::from_diagonal(&nalgebra::Vector4::new(1.0, 1.0, -1.0, 1.0))
}

/// An OpenGL-convention (right-handed, [-1, 1]) projection carried into `conv`.
fn in_convention(conv: Convention, gl: M4) -> M4 {
    match conv {
        Convention::RhGl => gl,
        Convention::RhZo => zero_to_one() * gl,
        Convention::LhZo => zero_to_one() * gl * flip_z(),
    }
}

/// `R`: depth reversed within `range`: z → -z on [-1, 1], z → w - z on [0, 1].
fn reverse(range: DepthRange) -> M4 {
    let mut r = M4::identity();
    r[(2, 2)] = -1.0;
    if range == DepthRange::ZeroToOne {
        r[(2, 3)] = 1.0;
    }
    r
}

/// Both oracles' OpenGL perspective, checked against each other.
fn oracle_perspective(fov: f32, aspect: f32, near: f64, far: f64) -> Result<M4, TestCaseError> {
    let (fov, aspect) = (f64::from(fov), f64::from(aspect));
    let nalgebra = M4::new_perspective(aspect, fov, near, far);
    let cgmath = from_cg(cgmath::perspective(cgmath::Rad(fov), aspect, near, far));
    prop_assert!(
        columns_close(&nalgebra, &cgmath, ORACLES_AGREE, 0.0),
        "nalgebra {nalgebra}\ncgmath {cgmath}"
    );
    Ok(nalgebra)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn look_at_matches_nalgebra_and_cgmath((eye, target, up) in arb_eye_target_up()) {
        let rh = [M4::look_at_rh(&p3(eye), &p3(target), &v3(up)), from_cg(cgmath::Matrix4::look_at_rh(cg_p3(eye), cg_p3(target), cg_v3(up)))];
        let lh = [M4::look_at_lh(&p3(eye), &p3(target), &v3(up)), from_cg(cgmath::Matrix4::look_at_lh(cg_p3(eye), cg_p3(target), cg_v3(up)))];
        for (ours, [nalgebra, cgmath]) in [(math::look_at_rh(eye, target, up), rh), (math::look_at_lh(eye, target, up), lh)] {
            let ours = na(ours.unwrap());
            prop_assert!(columns_close(&nalgebra, &cgmath, ORACLES_AGREE, 1.0), "nalgebra {nalgebra}\ncgmath {cgmath}");
            prop_assert!(view_close(&ours, &nalgebra, eye), "ours {ours}\nnalgebra {nalgebra}");
        }
    }

    #[test]
    fn look_to_matches_cgmath((eye, dir, up) in arb_eye_dir_up()) {
        // nalgebra has no look-to; cgmath's, with the look-at above, covers both of ours.
        let rh = from_cg(cgmath::Matrix4::look_to_rh(cg_p3(eye), cg_v3(dir), cg_v3(up)));
        let lh = from_cg(cgmath::Matrix4::look_to_lh(cg_p3(eye), cg_v3(dir), cg_v3(up)));
        prop_assert!(view_close(&na(math::look_to_rh(eye, dir, up).unwrap()), &rh, eye));
        prop_assert!(view_close(&na(math::look_to_lh(eye, dir, up).unwrap()), &lh, eye));
    }

    #[test]
    fn perspective_matches_in_every_convention(conv in arb_convention(), (fov, aspect, n, f) in arb_perspective()) {
        let gl = oracle_perspective(fov, aspect, n.into(), f.into())?;
        let ours = na(conv.perspective(fov, aspect, n, f).unwrap());
        let exact = in_convention(conv, gl);
        prop_assert!(columns_close(&ours, &exact, REL, 0.0), "{conv:?}\nours  {ours}\nexact {exact}");
    }

    #[test]
    fn infinite_and_reversed_perspectives_match_in_every_convention(
        conv in arb_convention(), (fov, aspect, n, f) in arb_perspective(),
    ) {
        let range = conv.depth_range();
        let infinite = in_convention(conv, oracle_perspective(fov, aspect, n.into(), 1e15 * f64::from(n))?);
        let finite = in_convention(conv, oracle_perspective(fov, aspect, n.into(), f.into())?);
        let cases = [
            ("reverse", conv.perspective_reverse(fov, aspect, n, f), reverse(range) * finite),
            ("infinite", conv.perspective_infinite(fov, aspect, n), infinite),
            ("infinite reverse", conv.perspective_infinite_reverse(fov, aspect, n), reverse(range) * infinite),
        ];
        for (name, ours, exact) in cases {
            let ours = na(ours.unwrap());
            prop_assert!(columns_close(&ours, &exact, REL, 0.0), "{conv:?} {name}\nours  {ours}\nexact {exact}");
        }
    }

    #[test]
    fn frustum_matches_cgmath_in_every_convention(conv in arb_convention(), [l, r, b, t, n, f] in arb_frustum()) {
        let gl = from_cg(cgmath::frustum(l.into(), r.into(), b.into(), t.into(), n.into(), f.into()));
        let ours = na(conv.frustum(l, r, b, t, n, f).unwrap());
        let exact = in_convention(conv, gl);
        prop_assert!(columns_close(&ours, &exact, REL, 0.0), "{conv:?}\nours  {ours}\nexact {exact}");
    }

    #[test]
    fn orthographic_matches_in_every_convention(conv in arb_convention(), [l, r, b, t, n, f] in arb_ortho()) {
        let [l64, r64, b64, t64, n64, f64_] = [l, r, b, t, n, f].map(f64::from);
        let nalgebra = M4::new_orthographic(l64, r64, b64, t64, n64, f64_);
        let cgmath = from_cg(cgmath::ortho(l64, r64, b64, t64, n64, f64_));
        prop_assert!(columns_close(&nalgebra, &cgmath, ORACLES_AGREE, 0.0), "nalgebra {nalgebra}\ncgmath {cgmath}");
        let ours = na(conv.orthographic(l, r, b, t, n, f).unwrap());
        let exact = in_convention(conv, nalgebra);
        // The depth translation -(f+n)/(f-n) cancels for a box far from the eye: |n|/(f-n) up to 1e4
        // in arb_ortho, which multiplies the rounding of its last column's z.
        let floor = f64::from(n.abs().max(f.abs()) / (f - n));
        prop_assert!(columns_close(&ours, &exact, REL, floor), "{conv:?}\nours  {ours}\nexact {exact}");
    }

    #[test]
    fn viewport_is_the_inverse_of_the_grid_boxs_orthographic_projection(
        width in 1.0f32..500.0, height in 1.0f32..500.0,
        depth in prop::sample::select(vec![DepthRange::NegOneToOne, DepthRange::ZeroToOne]),
    ) {
        // The grid's box: x in [0, width], y from height (bottom) to 0 (top), and view z from 0 to -1
        // (distances 0 to 1 in front of a right-handed eye), projected as glOrtho does.
        let (w, h) = (f64::from(width), f64::from(height));
        let zo = depth == DepthRange::ZeroToOne;
        let nalgebra = M4::new_orthographic(0.0, w, h, 0.0, 0.0, 1.0);
        let nalgebra = if zo { zero_to_one() * nalgebra } else { nalgebra }.try_inverse().unwrap();
        // cgmath's own ortho, carried to [0, 1] and inverted by cgmath.
        let cgmath = cgmath::ortho(0.0, w, h, 0.0, 0.0, 1.0);
        let cg_zero_to_one = cgmath::Matrix4::from_cols(
            cgmath::Vector4::unit_x(), cgmath::Vector4::unit_y(), cgmath::Vector4::new(0.0, 0.0, 0.5, 0.0), cgmath::Vector4::new(0.0, 0.0, 0.5, 1.0),
        );
        let cgmath = from_cg(if zo { cg_zero_to_one * cgmath } else { cgmath }.invert().unwrap());
        prop_assert!(columns_close(&nalgebra, &cgmath, ORACLES_AGREE, 1.0), "nalgebra {nalgebra}\ncgmath {cgmath}");
        // The inverse takes NDC back to the box, to view z in [0, -1]: grid depth is its negation.
        let exact = flip_z() * nalgebra;
        let ours = na(math::viewport(width, height, depth).unwrap());
        // w/2, h/2 and the depth scale and offset: one rounding each, 1e-6 of the column's size.
        prop_assert!(columns_close(&ours, &exact, 1e-6, 1.0), "ours  {ours}\nexact {exact}");
    }

    #[test]
    fn normal_matrix_is_the_f64_inverse_transpose_to_its_condition_number(model in arb_model_3x3()) {
        let m = Mat4::from_mat3(model);
        let Ok(ours) = math::normal_matrix(m) else {
            // A refusal is the math crate's call (math_normal.rs tests where it draws the line);
            // here only what it accepts.
            return Ok(());
        };
        let exact_m = Matrix3::from_column_slice(&model.to_cols_array().map(f64::from));
        let exact = exact_m.try_inverse().unwrap().transpose();
        let singular = exact_m.singular_values();
        let condition = singular.max() / singular.min();
        // An inverse's relative error is at most about the condition number times the rounding of
        // its input and arithmetic (Higham, Accuracy and Stability, §14.1): κ·ε·c, with c = 16 for the
        // column scaling, the cofactors and the division. Measured at commit 6df3e44 over 100,000
        // cases (κ up to 2e10 among the accepted): at most 1.4·κ·ε.
        let ours = Matrix3::from_column_slice(&ours.to_cols_array().map(f64::from));
        let error = (ours - exact).amax() / exact.amax();
        let bound = 16.0 * f64::from(f32::EPSILON / 2.0) * condition;
        prop_assert!(error <= bound, "error {error:e} > {bound:e} (κ = {condition:e})\nours  {ours}\nexact {exact}");
    }
}

/// A 3×3 model part: three columns with entries in [-1, 1] at magnitudes 1e-3 to 1e3, the third
/// sometimes nearly in the span of the other two (a relative offset down to 1e-7), so condition
/// numbers run from 1 to beyond what `normal_matrix` accepts.
fn arb_model_3x3() -> impl Strategy<Value = Mat3> {
    let column = || (arb_point(1.0), -3i32..=3).prop_map(|(v, e)| v * 10f32.powi(e));
    (column(), column(), column(), -4.0f32..3.0, -2.0f32..2.0, -2.0f32..2.0, any::<bool>()).prop_map(
        |(x, y, z, log_offset, s, t, dependent)| {
            let z = if dependent {
                s * x
                    + t * y
                    + z.normalize_or_zero() * 10f32.powf(log_offset) * (x.length() + y.length()) * 1e-4
            } else {
                z
            };
            Mat3::from_cols(x, y, z)
        },
    )
}
