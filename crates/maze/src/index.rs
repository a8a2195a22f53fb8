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

/// How many threads may fill an index: two when the caller has the other core to spare and the
/// index is big enough to pay for a thread (tens of µs to start).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Threads {
    One,
    Two,
}

/// Items from which [`Threads::Two`] is taken up.
const PARALLEL_ITEMS: usize = 1 << 15;

/// The buckets an item's box touches, recorded by the count for the placing: the first bucket
/// (`first`) and the span's columns and rows, each 1..=15, in a nibble each (`shape`); or
/// [`NO_SPAN`] (an empty or non-finite box); or [`BIG_SPAN`] (the box is computed again). Five
/// bytes an item, in two arrays.
fn encode_span(xs: &std::ops::Range<usize>, ys: &std::ops::Range<usize>, nx: usize) -> (u32, u8) {
    let (w, h) = (xs.len(), ys.len());
    match u32::try_from(ys.start * nx + xs.start) {
        Ok(first) if first != u32::MAX && (1..16).contains(&w) && (1..16).contains(&h) => {
            (first, (w - 1) as u8 | ((h - 1) as u8) << 4)
        }
        _ => BIG_SPAN,
    }
}

const NO_SPAN: (u32, u8) = (u32::MAX, 0xFF);
const BIG_SPAN: (u32, u8) = (u32::MAX, 0xFE);

fn decode_span(first: u32, shape: u8, nx: usize) -> Option<(std::ops::Range<usize>, std::ops::Range<usize>)> {
    if first == u32::MAX {
        return None;
    }
    let (x, y) = (first as usize % nx, first as usize / nx);
    let (w, h) = (usize::from(shape & 15) + 1, usize::from(shape >> 4) + 1);
    Some((x..x + w, y..y + h))
}

impl SpatialGrid {
    /// Indexes `n` items, item `i` with box `box_of(i)` inside `extents`, about one bucket per two
    /// items. A box is computed once or, for a long item, twice, and not stored (a box per edge of a big
    /// maze is 64 MB): the count records the buckets each item touches in five bytes.
    pub(crate) fn build(
        n: usize,
        box_of: impl Fn(usize) -> Aabb + Sync,
        extents: Aabb,
        threads: Threads,
    ) -> SpatialGrid {
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
            if let Some(grid) = grid.fill(n, &box_of, MAX_ENTRIES_PER_ITEM * n + 1024, threads) {
                return grid;
            }
            side *= 2.0; // long items cover many buckets: coarsen
        }
    }

    /// Fills the buckets, or `None` if that would take more than `budget` entries (unless the grid
    /// is a single bucket already). Items list in increasing order within a bucket.
    ///
    /// Two passes: count each bucket's entries (the boxes are the cost: a cell's box reads its
    /// edges and their corners), then place the items. A big index runs each pass on two threads:
    /// the counting over two halves of the items, each half's counts summed after; the placing over
    /// two runs of buckets, each thread writing only its own part of `items` (split where its run
    /// starts) from the spans the count recorded, so no box is computed twice. Either way the
    /// result is the same, entry for entry.
    fn fill(
        mut self,
        n: usize,
        box_of: &(impl Fn(usize) -> Aabb + Sync),
        budget: usize,
        threads: Threads,
    ) -> Option<SpatialGrid> {
        let buckets = self.nx * self.ny;
        let two = threads == Threads::Two && n >= PARALLEL_ITEMS;
        let (mut firsts, mut shapes) = (vec![NO_SPAN.0; n], vec![NO_SPAN.1; n]);
        // pass 1: counts by bucket, for a share of the items (from `start`)
        let count = |start: usize, firsts: &mut [u32], shapes: &mut [u8]| -> Option<(Vec<u32>, usize)> {
            let mut counts = vec![0u32; buckets];
            let mut entries = 0usize;
            for (k, (first, shape)) in firsts.iter_mut().zip(shapes.iter_mut()).enumerate() {
                let Some((xs, ys)) = self.span(&box_of(start + k)) else { continue };
                entries += xs.len() * ys.len();
                if entries > budget && buckets > 1 {
                    return None;
                }
                for y in ys.clone() {
                    counts[y * self.nx + xs.start..y * self.nx + xs.end].iter_mut().for_each(|c| *c += 1);
                }
                (*first, *shape) = encode_span(&xs, &ys, self.nx);
            }
            Some((counts, entries))
        };
        let shares = if two {
            let half = n / 2;
            let (first_a, first_b) = firsts.split_at_mut(half);
            let (shape_a, shape_b) = shapes.split_at_mut(half);
            std::thread::scope(|s| {
                let second = s.spawn(|| count(half, first_b, shape_b));
                let first = count(0, first_a, shape_a);
                vec![first, second.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))]
            })
        } else {
            vec![count(0, &mut firsts, &mut shapes)]
        };
        let shares: Vec<(Vec<u32>, usize)> = shares.into_iter().collect::<Option<_>>()?;
        let entries: usize = shares.iter().map(|share| share.1).sum();
        if entries > budget && buckets > 1 {
            return None;
        }
        let mut offsets = vec![0u32; buckets + 1];
        for b in 0..buckets {
            offsets[b + 1] = offsets[b] + shares.iter().map(|share| share.0[b]).sum::<u32>();
        }
        drop(shares);
        // pass 2: each bucket's items in increasing order, for a run of buckets written into `out`
        let mut items = vec![0u32; entries];
        let place = |run: std::ops::Range<usize>, out: &mut [u32]| {
            let base = offsets[run.start];
            let mut next: Vec<u32> = offsets[run.clone()].iter().map(|&o| o - base).collect();
            for (i, (&first, &shape)) in firsts.iter().zip(&shapes).enumerate() {
                let spans = decode_span(first, shape, self.nx);
                let big = || ((first, shape) == BIG_SPAN).then(|| self.span(&box_of(i))).flatten();
                let Some((xs, ys)) = spans.or_else(big) else { continue };
                for y in ys {
                    let row = y * self.nx;
                    for b in (row + xs.start).max(run.start)..(row + xs.end).min(run.end) {
                        let slot = &mut next[b - run.start];
                        out[*slot as usize] = i as u32;
                        *slot += 1;
                    }
                }
            }
        };
        if two {
            // two runs of buckets holding about half of the entries each
            let middle = offsets.partition_point(|&o| (o as usize) < entries / 2).min(buckets);
            let (a, b) = items.split_at_mut(offsets[middle] as usize);
            std::thread::scope(|s| {
                let second = s.spawn(|| place(middle..buckets, b));
                place(0..middle, a);
                second.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            });
        } else {
            place(0..buckets, &mut items);
        }
        self.offsets = offsets;
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

#[cfg(test)]
mod tests {
    use glam::vec2;

    use super::*;

    /// Boxes of every kind an index meets: points, tiles, long thin items across many buckets,
    /// huge ones, empty and non-finite ones.
    fn boxes(n: usize) -> Vec<Aabb> {
        (0..n)
            .map(|i| {
                let f = i as f32;
                let at = vec2((f * 7.31) % 1000.0, (f * 3.77) % 600.0);
                match i % 9 {
                    0 => Aabb { min: at, max: at },
                    1 => Aabb { min: vec2(at.x, 0.0), max: vec2(at.x + 0.5, 600.0) },
                    2 => Aabb { min: vec2(0.0, at.y), max: vec2(1000.0, at.y) },
                    3 => Aabb::EMPTY,
                    4 => Aabb { min: at, max: vec2(f32::NAN, at.y) },
                    _ => Aabb { min: at, max: at + vec2(4.0, 4.0) },
                }
            })
            .collect()
    }

    fn extents() -> Aabb {
        Aabb { min: Vec2::ZERO, max: vec2(1004.0, 604.0) }
    }

    #[test]
    fn two_threads_fill_the_index_one_fills() {
        // above the threshold, so the second thread is used
        let boxes = boxes(PARALLEL_ITEMS + 1234);
        let build = |threads| SpatialGrid::build(boxes.len(), |i| boxes[i], extents(), threads);
        let (one, two) = (build(Threads::One), build(Threads::Two));
        assert_eq!((one.nx, one.ny), (two.nx, two.ny));
        assert_eq!(one.offsets, two.offsets);
        assert_eq!(one.items, two.items);
    }

    #[test]
    fn every_bucket_lists_exactly_the_items_whose_boxes_touch_it_in_order() {
        let boxes = boxes(PARALLEL_ITEMS + 99);
        let grid = SpatialGrid::build(boxes.len(), |i| boxes[i], extents(), Threads::Two);
        let mut expected = vec![Vec::new(); grid.bucket_count()];
        for (i, b) in boxes.iter().enumerate() {
            if let Some((xs, ys)) = grid.span(b) {
                for y in ys {
                    for x in xs.clone() {
                        expected[y * grid.nx + x].push(i as u32);
                    }
                }
            }
        }
        for (b, want) in expected.iter().enumerate() {
            assert_eq!(grid.bucket_items(b), want.as_slice(), "bucket {b}");
        }
        // and a point finds every item whose box holds it
        for (i, b) in boxes.iter().enumerate().filter(|(_, b)| b.min.is_finite() && b.max.is_finite()) {
            if b.min.cmple(b.max).all() {
                assert!(grid.query(b.min).contains(&(i as u32)), "item {i} at {:?}", b.min);
            }
        }
    }

    #[test]
    fn a_span_too_big_to_record_is_recomputed_when_placing() {
        // items 16+ buckets long: the count records `BIG_SPAN` for them
        let boxes: Vec<Aabb> = (0..PARALLEL_ITEMS)
            .map(|i| {
                let x = (i % 1000) as f32;
                if i % 2 == 0 {
                    Aabb { min: vec2(x, 0.0), max: vec2(x, 600.0) }
                } else {
                    Aabb { min: vec2(x, 300.0), max: vec2(x + 1.0, 301.0) }
                }
            })
            .collect();
        let one = SpatialGrid::build(boxes.len(), |i| boxes[i], extents(), Threads::One);
        let two = SpatialGrid::build(boxes.len(), |i| boxes[i], extents(), Threads::Two);
        assert!(one.ny >= 16, "the long items must span 16 rows or more: {} rows", one.ny);
        assert_eq!(one.items, two.items);
        // item 502 stands at x = 502 the whole height (not item 0: an unfilled slot reads 0)
        for y in [10.0, 300.0, 590.0] {
            assert!(one.query(vec2(502.1, y)).contains(&502), "item 502 at y = {y}");
        }
        for b in 0..one.bucket_count() {
            assert!(one.bucket_items(b).is_sorted_by(|a, b| a < b), "bucket {b}: items in increasing order");
        }
    }
}
