//! The exercise the math core grew from, runnable: build a frustum (and a box) by hand and watch its
//! eight corners land on the corners of the NDC cube, in each convention.
//!
//! ```sh
//! cargo run -p mazewalk-math --example ndc_cube
//! ```
//!
//! A perspective frustum `[l, r] × [b, t]` on the near plane, between distances `near` and `far`:
//! its near corners are `(x, y)` at distance `near`, its far corners the same rays at `far`
//! (`(x, y) · far / near`). After the projection and the divide by w, x and y are ±1 and z is the
//! depth range's near end (-1 or 0) at the near plane and 1 at the far one. The orthographic box's
//! corners land on the same cube, without the divide doing anything (w stays 1).

use glam::{Mat4, Vec3};
use mazewalk_math::{Convention, MathError};

/// The view-space point `(x, y)` at `distance` in front of the eye (-Z right-handed, +Z left-handed).
fn ahead(conv: Convention, x: f32, y: f32, distance: f32) -> Vec3 {
    Vec3::new(x, y, 0.0) + conv.forward() * distance
}

/// Projects and divides: view → clip → NDC.
fn to_ndc(proj: Mat4, view: Vec3) -> Vec3 {
    let clip = proj * view.extend(1.0);
    clip.truncate() / clip.w
}

fn main() -> Result<(), MathError> {
    let (l, r, b, t, near, far) = (-1.0, 3.0, -0.5, 1.5, 1.0, 10.0); // off-centre on purpose
    for conv in Convention::ALL {
        let range = conv.depth_range();
        println!("{conv:?}: view space looks down {}, NDC depth in [{}, 1]", conv.forward(), range.near());
        let frustum = conv.frustum(l, r, b, t, near, far)?;
        let ortho = conv.orthographic(l, r, b, t, near, far)?;
        for (name, proj, perspective) in [("frustum", frustum, true), ("orthographic", ortho, false)] {
            println!("  {name}");
            for (distance, nz) in [(near, range.near()), (far, range.far())] {
                // A perspective's far corners are its near corners' rays, scaled out to `far`.
                let spread = if perspective { distance / near } else { 1.0 };
                for (x, nx) in [(l, -1.0), (r, 1.0)] {
                    for (y, ny) in [(b, -1.0), (t, 1.0)] {
                        let view = ahead(conv, x * spread, y * spread, distance);
                        let ndc = to_ndc(proj, view);
                        let corner = Vec3::new(nx, ny, nz);
                        println!("    view {:>22} → NDC {:>22}", format!("{view:.2}"), format!("{ndc:.4}"));
                        assert!(
                            ndc.abs_diff_eq(corner, 1e-5),
                            "{conv:?} {name}: {view} → {ndc}, not {corner}"
                        );
                    }
                }
            }
        }
    }
    println!("Every corner landed on its corner of the NDC cube, in every convention.");
    Ok(())
}
