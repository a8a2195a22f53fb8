//! Walls as geometry: each maze edge extruded from floor to ceiling, taken to clip space and clipped.

use glam::{Vec3, Vec4};

use super::camera::Eye;
use mazewalk_math::{ClipPlane, ClipPlanes, ClipVertex, clip_polygon};
use mazewalk_maze::Maze;
use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};

/// A wall vertex on its way through the pipeline: clip-space position plus the view-space position
/// (interpolated linearly in clip space, then perspective-correctly in the raster, for lighting and fog).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WallVertex {
    /// Clip space.
    pub clip: Vec4,
    /// View space (for shading: distance, light direction).
    pub view: Vec3,
}

impl ClipVertex for WallVertex {
    fn clip(&self) -> Vec4 {
        self.clip
    }
    fn lerp(&self, other: &Self, t: f32) -> Self {
        WallVertex { clip: self.clip.lerp(other.clip, t), view: self.view.lerp(other.view, t) }
    }
}

/// Buffers reused by every clip, so the hot path does not allocate.
#[derive(Debug, Default, Clone)]
pub(crate) struct ClipScratch {
    input: Vec<WallVertex>,
    output: Vec<WallVertex>,
    temp: Vec<WallVertex>,
}

/// Edge `e`'s wall quad in world space: start-floor, end-floor, end-ceiling, start-ceiling.
#[must_use]
pub(crate) fn wall_quad_world(maze: &Maze, e: u32) -> [Vec3; 4] {
    let (a, b) = maze.edge_points(e);
    [a.extend(FLOOR_Z), b.extend(FLOOR_Z), b.extend(CEILING_Z), a.extend(CEILING_Z)]
}

/// Edge `e`'s wall quad taken world → view → clip and clipped against the whole view volume, in
/// homogeneous clip space (nothing is divided by w before this). `None` when nothing is left.
pub(crate) fn clip_wall<'s>(
    maze: &Maze,
    eye: &Eye,
    e: u32,
    scratch: &'s mut ClipScratch,
) -> Option<&'s [WallVertex]> {
    scratch.input.clear();
    for world in wall_quad_world(maze, e) {
        let view = eye.world_to_view.transform_point3(world); // world → view
        let clip = eye.world_to_clip * world.extend(1.0); // world → clip (projection · view)
        scratch.input.push(WallVertex { clip, view });
    }
    let depth = eye.camera.convention.depth_range();
    clip_polygon(&scratch.input, ClipPlanes::ALL, depth, &mut scratch.output, &mut scratch.temp);
    (scratch.output.len() >= 3).then_some(scratch.output.as_slice())
}

/// The segment `p`–`q` (world space) taken to clip space and clipped against the view volume
/// (Liang–Barsky on the homogeneous plane distances, so nothing is divided by w first). `None` when
/// nothing is left. Used for the ascii outlines.
#[must_use]
pub(crate) fn clip_segment(eye: &Eye, p: Vec3, q: Vec3) -> Option<(Vec4, Vec4)> {
    let (a, b) = (eye.clip(p), eye.clip(q));
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    let depth = eye.camera.convention.depth_range();
    for plane in ClipPlane::ALL {
        // Signed distances, linear in clip coordinates: inside where >= 0.
        let (da, db) = (plane.distance(a, depth), plane.distance(b, depth));
        match (da < 0.0, db < 0.0) {
            (true, true) => return None,                  // wholly outside this plane
            (true, false) => t0 = t0.max(da / (da - db)), // enters at the crossing
            (false, true) => t1 = t1.min(da / (da - db)), // leaves at the crossing
            (false, false) => {}                          // wholly inside (on it counts as inside)
        }
    }
    (t0 <= t1).then(|| (a.lerp(b, t0), a.lerp(b, t1)))
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;
    use crate::camera::{Camera, Projection};
    use mazewalk_math::{ClipPlane, Convention};

    /// An orthographic eye at (5, 5) looking exactly along +x, depth in [0, 1]: its near plane is
    /// the world plane x = 5 (the eye's own), where clip z is exactly 0.
    fn eye() -> Eye {
        let mut camera = Camera::new(Vec2::new(5.0, 5.0), 0.0, 90.0);
        camera.projection = Projection::Orthographic;
        camera.convention = Convention::RhZo;
        camera.eye(40, 20, 1.0).unwrap()
    }

    fn near_distance(eye: &Eye, clip: Vec4) -> f32 {
        ClipPlane::Near.distance(clip, eye.camera.convention.depth_range())
    }

    /// Clipping a segment keeps exactly its part inside the view volume, a point on a boundary
    /// plane counting as inside (as for polygons): a segment lying in the near plane is kept whole,
    /// one touching it from behind keeps its touching point (either way round), one wholly behind
    /// is gone, and one crossing it is cut at the plane.
    #[test]
    fn a_segment_keeps_its_part_inside_and_on_the_boundary() {
        let eye = eye();
        let on = Vec3::new(5.0, 5.5, 0.0);
        let (on_too, behind, ahead) =
            (Vec3::new(5.0, 4.5, 0.5), Vec3::new(4.0, 5.5, 0.0), Vec3::new(8.0, 5.0, 0.0));
        assert_eq!(near_distance(&eye, eye.clip(on)), 0.0, "the test's premise: exactly on the plane");
        assert_eq!(clip_segment(&eye, on, on_too), Some((eye.clip(on), eye.clip(on_too))), "lying in it");
        assert_eq!(
            clip_segment(&eye, on, behind),
            Some((eye.clip(on), eye.clip(on))),
            "touching, ahead first"
        );
        assert_eq!(
            clip_segment(&eye, behind, on),
            Some((eye.clip(on), eye.clip(on))),
            "touching, behind first"
        );
        assert_eq!(clip_segment(&eye, behind, Vec3::new(3.0, 4.0, 0.5)), None, "wholly behind");
        assert_eq!(clip_segment(&eye, on, ahead), Some((eye.clip(on), eye.clip(ahead))), "wholly inside");
        let (a, b) = clip_segment(&eye, behind + Vec3::Y * 0.2, ahead).expect("crosses the near plane");
        assert!(near_distance(&eye, a).abs() < 1e-6, "cut at the plane: {a}");
        assert_eq!(b, eye.clip(ahead));
    }
}
