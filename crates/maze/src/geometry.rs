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
/// The least clearance (maze units) between the viewer's eye and a wall, in any maze: the near plane's
/// corners stay inside it. A maze's own clearance ([`crate::Maze::clearance`], [`clearance_for`]) is
/// this or more.
pub const WALL_MARGIN: f32 = 0.25;
/// The most clearance a maze gets: 2/5 of a generated maze's 4-unit corridor ([`clearance_for`]).
pub const MAX_CLEARANCE: f32 = 1.6;
/// A maze's clearance as a share of its narrowest passage ([`clearance_for`]).
pub const CLEARANCE_SHARE: f32 = 0.4;
/// Where the foot (and the top) of a wall faced square on from the closest stand lies, as a fraction
/// of the way from the view's centre to its bottom (top) edge, with the least vertical field of view
/// [`floor_showing_half_tan`] asks for: 0.9 leaves a tenth of the half-height, two sample rows of 24
/// at 80×24 half blocks, for the floor below the wall and the ceiling above it. The same share of the
/// half width is where [`ends_showing_half_tan`] puts a wall's far end.
pub const FOOT_AT: f32 = 0.9;
/// The narrowest view the walk is played in, width to height: 120×40 cells of half blocks (120 × 80
/// square samples). A wider view (80×24 half blocks: 1.67) keeps the vertical field and widens the
/// horizontal one, so what this view shows at its sides a wider one shows too.
pub const NARROW_ASPECT: f32 = 1.5;

/// The clearance of a maze whose narrowest passage is `narrowest` units across (the narrowest cell, or
/// the shortest opening between cells): 2/5 of it ([`CLEARANCE_SHARE`]), between [`WALL_MARGIN`] and
/// [`MAX_CLEARANCE`] — so the viewer's disc (4/5 of the passage across) passes every opening with a
/// fifth of it to spare, a cell too narrow for that keeps [`WALL_MARGIN`], and a generated maze (cells
/// and openings 4 wide) gets 1.6. NaN gives [`WALL_MARGIN`].
///
/// Why 2/5, stated once (the geometry of [`floor_showing_half_tan`] and [`ends_showing_half_tan`]):
/// standing `c` from a wall `w` long (a passage across), facing it square on, a centred eye sees its
/// ends at tan `(w/2)/c` either side, and an eye as far off-centre as the clearance lets it
/// (`w/2 − c`, against a closed side) sees the far end at tan `(w − c)/c`. A generated maze's 96°
/// vertical field gives a horizontal tan of 1.67 at 120×40 half blocks (118°), 1.85 at 80×24 (123°).
/// With a quarter (`c` = 1) a centred eye needs 2 just to reach the ends: one flat colour fills the
/// view and no side, open or closed, shows. With 3/8 (1.5) the far end from the corner needs
/// 2.5/1.5 = 1.67, the very edge of the 120×40 view. With 2/5 (1.6) a centred eye sees the ends at
/// ±1.25/1.67 = 0.75 of the half width (columns 15 and 105 of 120) with what is beside them, the
/// far end from the corner at 2.4/1.6 = 1.5, [`FOOT_AT`] of the half width (column 114), and the
/// floor below the wall with a tan of 1/(1.6·0.9) = 0.69 (a quarter needs 1.11).
///
/// ```
/// # use mazewalk_maze::geometry::{clearance_for, WALL_MARGIN, MAX_CLEARANCE};
/// assert_eq!(clearance_for(4.0), 1.6);
/// assert_eq!(clearance_for(0.6), WALL_MARGIN);
/// assert_eq!(clearance_for(100.0), MAX_CLEARANCE);
/// ```
#[must_use]
pub fn clearance_for(narrowest: f32) -> f32 {
    if narrowest.is_nan() {
        WALL_MARGIN
    } else {
        (CLEARANCE_SHARE * narrowest).clamp(WALL_MARGIN, MAX_CLEARANCE)
    }
}

/// The least tan(θ), θ the vertical half field of view, with which an eye at height `eye_z` standing
/// `clearance` from a wall, facing it square on, sees the floor below it and the ceiling above it.
///
/// The geometry, stated once: level and facing the wall square on, every column meets the wall at view
/// depth `d` = `clearance`; its foot, `h` = `eye_z − FLOOR_Z` below the eye, shows at `h / (d·tan θ)`
/// of the way from the view's centre to its bottom edge, so the floor shows below the wall when
/// `d·tan θ > h` (and the ceiling above it when `d·tan θ > CEILING_Z − eye_z`). This asks for the foot at
/// [`FOOT_AT`] of the way. A generated maze (eye mid-way, `h` = 1, `d` = 1.6) needs tan θ ≥ 0.69, a
/// vertical field of 69°; its field is wider, for the wall's ends ([`ends_showing_half_tan`]).
/// Turned by φ from square on, the column nearest the wall meets it at depth
/// `d / (cos φ + tan(hfov/2)·sin φ)`, closer: no field of view shows the floor in every column at
/// every heading from the clearance (it would take `d` ≥ the view's aspect × `h`).
#[must_use]
pub fn floor_showing_half_tan(clearance: f32, eye_z: f32) -> f32 {
    (eye_z - FLOOR_Z).max(CEILING_Z - eye_z) / (clearance * FOOT_AT)
}

/// The least tan(φ), φ the horizontal half field of view, with which an eye standing `clearance` from
/// a wall `passage` long, facing it square on, sees both of its ends and what is beyond them from
/// anywhere the clearance lets it stand before the wall between closed sides: from the corner of that
/// band, `passage/2 − clearance` off-centre, the far end is `passage − clearance` to the side, and
/// shows at [`FOOT_AT`] of the way from the view's centre to its edge (nearer the middle from anywhere
/// else in the band). A generated maze (4 units, 1.6) needs 1.5/0.9 = 1.67.
///
/// ```
/// # use mazewalk_maze::geometry::ends_showing_half_tan;
/// assert!((ends_showing_half_tan(4.0, 1.6) - 2.4 / 1.6 / 0.9).abs() < 1e-5);
/// ```
#[must_use]
pub fn ends_showing_half_tan(passage: f32, clearance: f32) -> f32 {
    (passage - clearance).max(0.0) / (clearance * FOOT_AT)
}
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
