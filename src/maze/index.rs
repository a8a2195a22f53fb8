//! A uniform grid of buckets over the maze extents, each listing the items (cells or edges) whose
//! bounding box touches it. Flat (CSR) storage: two `Vec`s, no allocation per bucket.

use glam::Vec2;

use super::Aabb;

/// Items by bucket; bucket (i, j) covers `origin + ([i, i+1) × [j, j+1)) * size`, `size` per axis.
#[derive(Clone, Debug, Default)]
pub(crate) struct SpatialGrid {
    origin: Vec2,
    inv_size: Vec2,
    nx: usize,
    ny: usize,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

/// The median width over the median height of (up to 1024 sampled) items' boxes, each median over
/// the boxes with some extent along its axis (a maze's edges are mostly horizontal or vertical, of
/// zero width or height), within 1/4096..=4096.
fn typical_aspect(n: usize, box_of: &impl Fn(usize) -> Aabb) -> f64 {
    let step = (n / 1024).max(1);
    let sizes: Vec<Vec2> =
        (0..n).step_by(step).map(box_of).map(|b| b.max - b.min).filter(|d| d.is_finite()).collect();
    let median = |axis: fn(&Vec2) -> f32| {
        let mut v: Vec<f32> = sizes.iter().map(axis).filter(|&d| d > 0.0).collect();
        if v.is_empty() {
            return None;
        }
        let mid = v.len() / 2;
        Some(f64::from(*v.select_nth_unstable_by(mid, f32::total_cmp).1))
    };
    match (median(|d| d.x), median(|d| d.y)) {
        (Some(w), Some(h)) => (w / h).clamp(1.0 / 4096.0, 4096.0),
        _ => 1.0,
    }
}

/// About this many bucket entries per item at most, else the grid is made coarser (long items).
const MAX_ENTRIES_PER_ITEM: usize = 16;

impl SpatialGrid {
    /// Indexes `n` items, item `i` with box `box_of(i)` inside `extents`, about one bucket per two
    /// items. Boxes are computed when needed, not stored (a box per edge of a big maze is 64 MB).
    pub(crate) fn build(n: usize, box_of: impl Fn(usize) -> Aabb, extents: Aabb) -> SpatialGrid {
        let size = (extents.max - extents.min).max(Vec2::splat(1e-6));
        // buckets shaped like the typical item (tall and thin for a comb of tall thin cells, which
        // would crowd square buckets), about n/2 of them (a box the size of a bucket touches up to 4)
        let aspect = typical_aspect(n, &box_of);
        let area = (2.0 * size.x as f64 * size.y as f64) / n.max(1) as f64;
        let mut side = Vec2::new((area * aspect).sqrt() as f32, (area / aspect).sqrt() as f32);
        // at most about n buckets along an axis (a comb of n cells wants one column each)
        let most = (n as f32).max(4096.0);
        side = side.max(size / most).max(Vec2::splat(1e-6));
        loop {
            // shift the lattice off round numbers, so boxes on a grid of the same pitch (a generated
            // maze) do not all straddle bucket boundaries
            let shift = side * 0.382;
            let cells = (size + shift) / side;
            let grid = SpatialGrid {
                origin: extents.min - shift,
                inv_size: 1.0 / side,
                nx: (cells.x as usize + 1).min(2 * most as usize),
                ny: (cells.y as usize + 1).min(2 * most as usize),
                offsets: Vec::new(),
                items: Vec::new(),
            };
            if let Some(grid) = grid.fill(n, &box_of, MAX_ENTRIES_PER_ITEM * n + 1024) {
                return grid;
            }
            side *= 2.0; // long items cover many buckets: coarsen
        }
    }

    /// Fills the buckets, or `None` if that would take more than `budget` entries (unless the grid
    /// is a single bucket already).
    fn fill(mut self, n: usize, box_of: &impl Fn(usize) -> Aabb, budget: usize) -> Option<SpatialGrid> {
        let buckets = self.nx * self.ny;
        let mut counts = vec![0u32; buckets + 1];
        let mut entries = 0usize;
        for i in 0..n {
            if let Some((xs, ys)) = self.span(&box_of(i)) {
                entries += xs.len() * ys.len();
                if entries > budget && buckets > 1 {
                    return None;
                }
                for y in ys {
                    for x in xs.clone() {
                        counts[y * self.nx + x + 1] += 1;
                    }
                }
            }
        }
        for b in 0..buckets {
            counts[b + 1] += counts[b];
        }
        let mut next = counts.clone();
        let mut items = vec![0u32; entries];
        for i in 0..n {
            if let Some((xs, ys)) = self.span(&box_of(i)) {
                for y in ys {
                    for x in xs.clone() {
                        let slot = &mut next[y * self.nx + x];
                        items[*slot as usize] = i as u32;
                        *slot += 1;
                    }
                }
            }
        }
        self.offsets = counts;
        self.items = items;
        Some(self)
    }

    /// The bucket columns and rows a box touches, or `None` for an empty or non-finite box.
    fn span(&self, b: &Aabb) -> Option<(std::ops::Range<usize>, std::ops::Range<usize>)> {
        if !(b.min.is_finite() && b.max.is_finite()) || b.min.cmpgt(b.max).any() {
            return None;
        }
        let lo = self.bucket(b.min);
        let hi = self.bucket(b.max);
        Some((lo.0..hi.0 + 1, lo.1..hi.1 + 1))
    }

    fn bucket(&self, p: Vec2) -> (usize, usize) {
        let g = (p - self.origin) * self.inv_size;
        // `as usize` saturates: negative → 0; clamp the top
        ((g.x as usize).min(self.nx - 1), (g.y as usize).min(self.ny - 1))
    }

    /// The items whose boxes touch the bucket holding `p` (clamped into the grid).
    pub(crate) fn query(&self, p: Vec2) -> &[u32] {
        if self.offsets.is_empty() {
            return &[];
        }
        let (x, y) = self.bucket(p);
        self.bucket_items(y * self.nx + x)
    }

    /// Number of buckets.
    pub(crate) fn bucket_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// The items in bucket `b`.
    pub(crate) fn bucket_items(&self, b: usize) -> &[u32] {
        &self.items[self.offsets[b] as usize..self.offsets[b + 1] as usize]
    }
}
