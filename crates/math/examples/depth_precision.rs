//! How many distinct depths an f32 depth buffer keeps along a corridor 1000 units long, for every
//! projection of the crate: forward and reversed depth, finite and infinite far plane, in each
//! convention. Prints the Markdown table the crate's README shows.
//!
//! ```sh
//! cargo run --release -p mazewalk-math --example depth_precision
//! ```
//!
//! The stored depth is what a renderer keeps: the point at distance `d` straight ahead, through the
//! projection, the divide by w and the viewport (NDC depth → [0, 1]), all in f32. "Distinct" counts
//! the different stored values among 999,901 distances 1 mm apart, from the near plane (0.1) to
//! 1000; "step at D" is the smallest decrease of distance below D that changes the stored value
//! (`step`: how close in front of a surface at D another must be for the depth test to tell them
//! apart).

use glam::{Mat4, Vec3};
use mazewalk_math::{Convention, MathError, viewport};

const NEAR: f32 = 0.1;
const FAR: f32 = 1000.0;

/// The stored depth of the point `distance` straight ahead.
fn stored(conv: Convention, proj: Mat4, grid: Mat4, distance: f32) -> f32 {
    let clip = proj * (conv.forward() * distance).extend(1.0);
    let ndc = clip.truncate() / clip.w;
    grid.transform_point3(Vec3::new(0.0, 0.0, ndc.z)).z
}

/// The smallest decrease of distance below `at` that changes the stored depth, by bisection over f32
/// distances (the stored depth is monotonic in the distance): how close in front of a surface at
/// `at` another must be for the depth test to tell them apart.
fn step(depth: impl Fn(f32) -> f32, at: f32) -> f32 {
    let here = depth(at);
    let (mut lo, mut hi) = (at / 2.0, at); // depth(lo) differs, depth(hi) is here's
    if depth(lo) == here {
        return f32::INFINITY; // unresolved over a whole halving
    }
    while lo.next_up() < hi {
        let mid = lo + (hi - lo) / 2.0;
        let mid = if mid <= lo { lo.next_up() } else { mid };
        if depth(mid) == here { hi = mid } else { lo = mid }
    }
    at - lo
}

fn show(step: f32) -> String {
    match step {
        s if s.is_infinite() => "—".to_owned(),
        s if s < 1e-3 => format!("{:.2} µm", s * 1e6),
        s if s < 1.0 => format!("{:.2} mm", s * 1e3),
        s => format!("{s:.2} units"),
    }
}

fn main() -> Result<(), MathError> {
    let (fov, aspect) = (1.0, 1.0); // depth does not depend on either
    println!(
        "| convention | depth | distinct (of 999,901) | step at 1 | step at 10 | step at 100 | step at 1000 |"
    );
    println!("|---|---|--:|--:|--:|--:|--:|");
    for conv in Convention::ALL {
        let grid = viewport(1.0, 1.0, conv.depth_range())?;
        let projections = [
            ("forward", conv.perspective(fov, aspect, NEAR, FAR)?),
            ("reversed", conv.perspective_reverse(fov, aspect, NEAR, FAR)?),
            ("infinite", conv.perspective_infinite(fov, aspect, NEAR)?),
            ("infinite reversed", conv.perspective_infinite_reverse(fov, aspect, NEAR)?),
        ];
        for (name, proj) in projections {
            let depth = |d: f32| stored(conv, proj, grid, d);
            // Distances 1 mm apart, each computed from its index (no accumulated rounding).
            let mut values: Vec<u32> =
                (0..999_901u32).map(|i| depth(NEAR + i as f32 * 1e-3).to_bits()).collect();
            values.sort_unstable();
            values.dedup();
            let steps: Vec<String> =
                [1.0, 10.0, 100.0, 1000.0].iter().map(|&d| show(step(depth, d))).collect();
            println!("| {conv:?} | {name} | {} | {} |", values.len(), steps.join(" | "));
        }
    }
    Ok(())
}
