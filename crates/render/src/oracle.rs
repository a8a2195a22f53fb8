//! The portal pass checked against brute force: render a view both ways and compare every sample.
//! Used by the property tests and the fuzz target (and handy when changing the portal code).
//!
//! The frames must be equal sample for sample — same wall id, same depth, same colour — except where
//! the raster, not visibility, decides: a sample whose centre lies within [`SNAP`] of the outline of
//! the wall that wins it in brute force. The rasterizer snaps vertices to 1/256 of a sample, so such a
//! sample may be covered by a wall its ray (in exact arithmetic) just misses, or missed by one it just
//! hits. Two cases occur: a ray running exactly through the corner where two walls meet (a true depth
//! tie, which brute force resolves by wall id while the portal pass may only have the front wall), and,
//! in orthographic views held almost level, the floor or ceiling line, where every wall's bottom or top
//! edge projects to within a hair of the same row. The exception is bounded: the brute-force winner
//! must be a wall covering the sample by less than [`SNAP`], the portal frame's sample may not be
//! nearer than brute force's, and there are at most two rows' and four columns' worth of such samples.

use glam::Vec2;

use super::camera::{Camera, Eye};
use super::options::Charset;
use super::options::{Culling, RenderOptions};
use super::pipeline::{Renderer, Target};
use super::wall::{ClipScratch, clip_wall};
use mazewalk_maze::Maze;

/// How close (in samples) a sample centre must be to a wall's projected outline for snapping to decide
/// its coverage: four times the rasterizer's 1/256 sample precision.
pub(crate) const SNAP: f32 = 1.0 / 64.0;

/// What a successful comparison found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Agreement {
    /// Samples that differ where snapping decides coverage (see the module docs).
    pub snapped: usize,
    /// Distinct cells the portal pass visited.
    pub cells_visited: usize,
    /// Walls the portal pass chose.
    pub walls_chosen: usize,
}

/// Renders `camera`'s view of `maze` into a `cols × rows` grid of `charset` both ways and compares.
///
/// # Errors
/// A description of the first disagreement (or of a camera the renderer refused).
pub fn portal_matches_brute(
    maze: &Maze,
    camera: &Camera,
    charset: Charset,
    cols: usize,
    rows: usize,
) -> Result<Agreement, String> {
    // Visibility only: the edge pass (a post-process reading each sample's neighbours) would carry a
    // tolerated difference at one sample into its neighbours' colours.
    let (mut brute, mut portal) = (Renderer::new(), Renderer::new());
    (brute.no_edges, portal.no_edges) = (true, true);
    let draw = |r: &mut Renderer, culling| {
        r.render(
            maze,
            camera,
            &[],
            &RenderOptions { charset, culling, ..RenderOptions::default() },
            Target::Samples { cols, rows },
        )
        .map_err(|e| e.to_string())
    };
    draw(&mut brute, Culling::None)?;
    let stats = draw(&mut portal, Culling::Portal)?;
    let (b, p) = (brute.samples(), portal.samples());
    let chosen = &portal.portal().walls;
    let walls = maze.edges().len() as u32;
    let (sx, sy) = charset.samples_per_cell();
    let eye = camera.eye(cols * sx, rows * sy, charset.sample_aspect(0.5)).map_err(|e| e.to_string())?;
    let mut scratch = ClipScratch::default();
    let mut snapped = 0;
    for i in 0..b.id().len() {
        let (bid, pid) = (b.id()[i], p.id()[i]);
        let (db, dp) = (b.depth()[i], p.depth()[i]);
        if bid != pid {
            let centre = Vec2::new((i % b.width()) as f32 + 0.5, (i / b.width()) as f32 + 0.5);
            if bid >= walls {
                return Err(format!("sample {i}: brute force shows {bid}, the portal pass wall {pid}"));
            }
            let distance = outline_distance(maze, &eye, bid, centre, &mut scratch);
            if distance > SNAP {
                return Err(format!(
                    "sample {i}: brute force shows wall {bid} (its outline {distance} samples away), \
                     the portal pass {pid}"
                ));
            }
            if dp < db {
                return Err(format!("sample {i}: the portal frame is nearer ({dp}) than brute force ({db})"));
            }
            snapped += 1;
            continue;
        }
        if bid < walls && !chosen.contains(&bid) {
            return Err(format!("wall {bid} wins sample {i} in brute force but the portal pass skipped it"));
        }
        if db.to_bits() != dp.to_bits() || b.color()[i] != p.color()[i] {
            return Err(format!("sample {i}: same wall {bid}, different depth or colour"));
        }
    }
    if snapped > 2 * b.width() + 4 * b.height() {
        return Err(format!("{snapped} snapped samples in a {}×{} frame", b.width(), b.height()));
    }
    Ok(Agreement { snapped, cells_visited: stats.portal.distinct_cells, walls_chosen: chosen.len() })
}

/// Distance (samples) from `centre` to the outline of wall `e` as the raster sees it (clipped, in grid
/// space); infinite when the wall is not in view.
fn outline_distance(maze: &Maze, eye: &Eye, e: u32, centre: Vec2, scratch: &mut ClipScratch) -> f32 {
    let Some(poly) = clip_wall(maze, eye, e, scratch) else { return f32::INFINITY };
    let points: Vec<Vec2> = poly.iter().map(|v| eye.grid(v.clip).truncate()).collect();
    let mut best = f32::INFINITY;
    for (k, &a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((centre - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min(centre.distance(a + ab * t));
    }
    best
}
