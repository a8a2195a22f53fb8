//! World geometry, stated once: where floor and ceiling are, how close the viewer may come to walls,
//! floor and ceiling, and which way a heading points in the maze plane. The renderer, the movement code
//! and the walkthrough all take these from here.
//!
//! World space: the maze plane is x (east) / y (north), z is up; walls are the maze's edges extruded from
//! [`FLOOR_Z`] to [`CEILING_Z`]. A heading is in radians, counter-clockwise from +x (the files' `dir`).
//!
//! ```
//! # use mazewalk_maze::geometry::{clamp_eye_height, heading_dir, heading_right, EYE_MARGIN, CEILING_Z};
//! let north = std::f32::consts::FRAC_PI_2;
//! assert!(heading_dir(north).distance(glam::vec2(0.0, 1.0)) < 1e-6);
//! assert!(heading_right(north).distance(glam::vec2(1.0, 0.0)) < 1e-6); // facing north, east is right
//! assert_eq!(clamp_eye_height(5.0), CEILING_Z - EYE_MARGIN);
//! ```

use glam::Vec2;

/// The floor plane: walls rise from z = -1.
pub const FLOOR_Z: f32 = -1.0;
/// The ceiling plane: walls end at z = +1.
pub const CEILING_Z: f32 = 1.0;
/// How close (maze units) the viewer's disc may come to a wall; the near plane's corners stay inside it.
pub const WALL_MARGIN: f32 = 0.25;
/// How close (maze units) the eye may come to the floor and the ceiling.
pub const EYE_MARGIN: f32 = 0.15;

/// Clamps an eye height to stay [`EYE_MARGIN`] away from the floor and the ceiling; NaN becomes 0 (mid-way).
#[must_use]
pub fn clamp_eye_height(z: f32) -> f32 {
    if z.is_nan() { 0.0 } else { z.clamp(FLOOR_Z + EYE_MARGIN, CEILING_Z - EYE_MARGIN) }
}

/// The unit vector in the maze plane along `heading` (radians, counter-clockwise from +x).
#[must_use]
pub fn heading_dir(heading: f32) -> Vec2 {
    Vec2::new(heading.cos(), heading.sin())
}

/// The unit vector in the maze plane to the right of `heading`: [`heading_dir`] turned 90° clockwise,
/// which is also the camera's screen-right for every pitch (forward × up has no z).
#[must_use]
pub fn heading_right(heading: f32) -> Vec2 {
    let dir = heading_dir(heading);
    Vec2::new(dir.y, -dir.x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Aabb;

    #[test]
    fn eye_height_stays_between_floor_and_ceiling() {
        assert_eq!(clamp_eye_height(5.0), CEILING_Z - EYE_MARGIN);
        assert_eq!(clamp_eye_height(-5.0), FLOOR_Z + EYE_MARGIN);
        assert_eq!(clamp_eye_height(0.3), 0.3);
        assert_eq!(clamp_eye_height(f32::NAN), 0.0);
    }

    #[test]
    fn right_is_the_heading_turned_clockwise() {
        for heading in [0.0f32, 0.7, 2.0, -3.0] {
            let (dir, right) = (heading_dir(heading), heading_right(heading));
            assert!((dir.length() - 1.0).abs() < 1e-6 && dir.dot(right).abs() < 1e-6);
            assert!(right.perp_dot(dir) > 0.0, "dir is counter-clockwise from right");
        }
    }

    #[test]
    fn box_intersection_and_containment_are_inclusive() {
        let a = Aabb::new(Vec2::new(0.0, 0.0), Vec2::new(2.0, 2.0));
        let b = Aabb::new(Vec2::new(2.0, 1.0), Vec2::new(3.0, 3.0));
        assert!(!a.intersection(b).is_empty(), "touching boxes overlap (conservative)");
        assert!(a.intersection(Aabb { min: Vec2::new(2.1, 1.0), ..b }).is_empty());
        assert!(a.contains(&a));
        assert!(!a.contains(&b));
        assert!(Aabb::EMPTY.is_empty());
    }

    #[test]
    fn segments_touching_a_box() {
        let r = Aabb::new(Vec2::ZERO, Vec2::ONE);
        assert!(r.touches_segment(Vec2::new(-1.0, 0.5), Vec2::new(2.0, 0.5)));
        assert!(r.touches_segment(Vec2::new(1.0, 1.0), Vec2::new(3.0, 3.0)), "touching a corner");
        assert!(!r.touches_segment(Vec2::new(1.5, -1.0), Vec2::new(1.5, 3.0)));
        assert!(r.touches_segment(Vec2::new(0.5, 0.5), Vec2::new(0.5, 0.5)), "a point inside");
    }
}
