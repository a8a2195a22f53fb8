//! A uniform grid of buckets over the maze extents, each listing the items (cells or edges) whose
//! bounding box touches it. Flat (CSR) storage: two `Vec`s, no allocation per bucket.

use glam::Vec2;

use super::Aabb;

/// Items by bucket; bucket (i, j) covers `origin + [i, i+1) × [j, j+1) * size`.
#[derive(Clone, Debug, Default)]
pub(crate) struct SpatialGrid {
    origin: Vec2,
    inv_size: f32,
    nx: usize,
    ny: usize,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

/// About this many bucket entries per item at most, else the grid is made coarser (long items).
const MAX_ENTRIES_PER_ITEM: usize = 16;

impl SpatialGrid {
    /// Indexes `n` items with boxes `aabb(i)` inside `extents`, about one bucket per item.
    pub(crate) fn build(n: usize, extents: Aabb, aabb: impl Fn(usize) -> Aabb) -> SpatialGrid {
        let size = (extents.max - extents.min).max(Vec2::splat(1e-6));
        // square buckets, about n of them
        let mut side = ((size.x as f64 * size.y as f64) / n.max(1) as f64).sqrt().max(1e-6) as f32;
        side = side.max(size.x / 4096.0).max(size.y / 4096.0);
        loop {
            let grid = SpatialGrid {
                origin: extents.min,
                inv_size: 1.0 / side,
                nx: ((size.x / side) as usize + 1).min(8192),
                ny: ((size.y / side) as usize + 1).min(8192),
                offsets: Vec::new(),
                items: Vec::new(),
            };
            let entries: usize =
                (0..n).map(|i| grid.span(&aabb(i)).map_or(0, |(x, y)| x.len() * y.len())).sum();
            if entries <= MAX_ENTRIES_PER_ITEM * n + 1024 || (grid.nx == 1 && grid.ny == 1) {
                return grid.fill(n, entries, aabb);
            }
            side *= 2.0; // long items cover many buckets: coarsen
        }
    }

    fn fill(mut self, n: usize, entries: usize, aabb: impl Fn(usize) -> Aabb) -> SpatialGrid {
        let buckets = self.nx * self.ny;
        let mut counts = vec![0u32; buckets + 1];
        for i in 0..n {
            if let Some((xs, ys)) = self.span(&aabb(i)) {
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
            if let Some((xs, ys)) = self.span(&aabb(i)) {
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
        self
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
