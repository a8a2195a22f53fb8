//! Whether any two segments cross or overlap, in O(n log n) whatever their shape: the Shamos–Hoey
//! sweep (Shamos & Hoey 1976; de Berg et al., *Computational Geometry*, ch. 2).
//!
//! The sweep visits the segments' end points in lexicographic (x, then y) order. The segments it
//! is inside ("active") are kept in a balanced search tree ordered bottom to top along the sweep
//! line. Segments that neither cross nor overlap never change their order while both are active, and
//! two segments that do must be neighbours in that order just before the leftmost bad point `q` is
//! reached: anything between them would have to pass through `q` (and cross one of them there, an
//! earlier or equal bad pair) or end at `q` (its removal at `q` makes them neighbours). So it is
//! enough to test each new pair of neighbours: a segment against the two beside it when inserted,
//! and the two around a removed segment against each other. Sharing an end point, or one segment
//! ending on another (a T), is allowed and never reported.
//!
//! At one point, removals come before insertions, so a segment ending where another starts is gone
//! before the other is placed. Comparisons are orientation tests in `f64` on `f32` input (exact for
//! the coordinates a maze uses, as [`conflict`] is).
//!
//! The oracle is the brute-force pair test in this module's tests.

use std::cmp::Ordering;

use glam::{DVec2, Vec2};

use super::orient;

/// What is wrong between two segments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Conflict {
    /// Neither: apart, or touching at a point.
    None,
    /// A proper crossing.
    Cross,
    /// A collinear overlap of positive length.
    Overlap,
}

/// Segments p and q: a proper crossing, a collinear overlap of positive length, or neither
/// (apart, or touching at a point).
pub(crate) fn conflict(p1: DVec2, p2: DVec2, q1: DVec2, q2: DVec2) -> Conflict {
    let (d1, d2) = (orient(q1, q2, p1), orient(q1, q2, p2));
    let (d3, d4) = (orient(p1, p2, q1), orient(p1, p2, q2));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return Conflict::Cross;
    }
    if d1 == 0.0 && d2 == 0.0 {
        // collinear: overlap of the projections on the longer axis of p
        let axis = if (p2 - p1).x.abs() >= (p2 - p1).y.abs() { DVec2::X } else { DVec2::Y };
        let (a0, a1) = (p1.dot(axis).min(p2.dot(axis)), p1.dot(axis).max(p2.dot(axis)));
        let (b0, b1) = (q1.dot(axis).min(q2.dot(axis)), q1.dot(axis).max(q2.dot(axis)));
        if a1.min(b1) > a0.max(b0) {
            return Conflict::Overlap;
        }
    }
    Conflict::None
}

/// The first bad pair the sweep meets among `n` segments, segment `i` being `segment(i)`:
/// `(a, b, what)` with `a < b`, or `None` when no two cross or overlap. Zero-length segments are not
/// expected (the model rules them out). Memory: 20 bytes a segment (two sorted id lists and the tree),
/// 16 more while a list is sorted.
pub(crate) fn first_conflict(n: usize, segment: impl Fn(u32) -> [Vec2; 2]) -> Option<(u32, u32, Conflict)> {
    let ends = |i: u32| left_to_right(segment(i));
    let left = |i: u32| ends(i).keys[0];
    let right = |i: u32| ends(i).keys[1];
    let points = |i: u32| ends(i).points();
    let starts = sorted(0..n as u32, &left);
    let stops = sorted(0..n as u32, &right);
    let report = |a: u32, b: u32, c: Conflict| Some((a.min(b), a.max(b), c));
    let check = |a: u32, b: u32| {
        let ([p1, p2], [q1, q2]) = (points(a), points(b));
        conflict(p1, p2, q1, q2)
    };
    let mut tree = Treap::new(n);
    let (mut i, mut j) = (0, 0);
    while j < n {
        // at one point, removals first
        if i < n && left(starts[i]) < right(stops[j]) {
            let s = starts[i];
            i += 1;
            let new = points(s);
            match tree.insert(s, |t| place(new, points(t))) {
                Err(t) => return report(s, t, Conflict::Overlap),
                Ok(()) => {
                    for t in [tree.neighbour(s, 0), tree.neighbour(s, 1)].into_iter().flatten() {
                        let c = check(s, t);
                        if c != Conflict::None {
                            return report(s, t, c);
                        }
                    }
                }
            }
        } else {
            let s = stops[j];
            j += 1;
            let (below, above) = (tree.neighbour(s, 0), tree.neighbour(s, 1));
            tree.remove(s);
            if let (Some(a), Some(b)) = (below, above) {
                let c = check(a, b);
                if c != Conflict::None {
                    return report(a, b, c);
                }
            }
        }
    }
    None
}

/// Two cells that share area: `(a, b)` with `a < b`, or `None` when no point lies in two cells.
/// `sides(i)` are the cells left and right of segment `i` as `segment(i)` runs (`None`: no cell).
/// The segments must neither cross nor overlap, as [`first_conflict`] checks.
///
/// The sweep keeps the active segments in order as [`first_conflict`] does, but moves from one
/// abscissa to the next, with every segment ending there removed before any starting there is
/// placed, and leaves vertical segments out: the order is then the one just right of the abscissa,
/// where two neighbours bound one face. So the cell above the lower one (the cell on a left-to-right
/// segment's left) must be the cell below the upper one, and nothing lies below the lowest or above
/// the highest. A point inside two cells breaks that at every abscissa through it; where the inner
/// cell starts, the pair it breaks is new, and only new pairs are tested: beside each segment placed,
/// and round each removed one. O(n log n).
pub(crate) fn first_overlap(
    n: usize,
    segment: impl Fn(u32) -> [Vec2; 2],
    sides: impl Fn(u32) -> [Option<u32>; 2],
) -> Option<(u32, u32)> {
    let ends = |i: u32| left_to_right(segment(i));
    let (left, right) = (|i: u32| ends(i).keys[0], |i: u32| ends(i).keys[1]);
    // (below, above): running left to right, a segment has its left side above
    let faces = |i: u32| {
        let [l, r] = sides(i);
        if ends(i).reversed { [l, r] } else { [r, l] }
    };
    let x_of = |key: u64| key >> 32;
    let sloped = (0..n as u32).filter(|&i| x_of(left(i)) != x_of(right(i)));
    let starts = sorted(sloped.clone(), &left);
    let stops = sorted(sloped, &right);
    let mut tree = Treap::new(n);
    let mut active = vec![false; n];
    let mut touched = Vec::new();
    let (mut i, mut j) = (0, 0);
    while j < stops.len() {
        let x = x_of(right(stops[j])).min(starts.get(i).map_or(u64::MAX, |&s| x_of(left(s))));
        touched.clear();
        while j < stops.len() && x_of(right(stops[j])) == x {
            let s = stops[j];
            j += 1;
            touched.extend([tree.neighbour(s, 0), tree.neighbour(s, 1)].into_iter().flatten());
            tree.remove(s);
            active[s as usize] = false;
        }
        while i < starts.len() && x_of(left(starts[i])) == x {
            let s = starts[i];
            i += 1;
            let new = ends(s).points();
            if let Err(t) = tree.insert(s, |t| place(new, ends(t).points())) {
                // an overlap of edges, which the caller has ruled out: two cells on one line
                let cell = |i: u32| faces(i).into_iter().flatten().next();
                return cell(s).zip(cell(t)).map(|(a, b)| (a.min(b), a.max(b)));
            }
            active[s as usize] = true;
            touched.push(s);
        }
        for &s in &touched {
            if !active[s as usize] {
                continue;
            }
            for (lower, upper) in [(tree.neighbour(s, 0), Some(s)), (Some(s), tree.neighbour(s, 1))] {
                let between = (lower.and_then(|l| faces(l)[1]), upper.and_then(|u| faces(u)[0]));
                let (a, b) = match between {
                    (a, b) if a == b => continue,
                    (Some(a), Some(b)) => (a, b),
                    // one face between two segments, and the cell one of them faces it with holds
                    // the other: whose cell lies in there is on that segment's far side
                    (Some(a), None) => (a, upper.and_then(|u| faces(u)[1]).unwrap_or(a)),
                    (None, Some(b)) => (lower.and_then(|l| faces(l)[0]).unwrap_or(b), b),
                    (None, None) => unreachable!("equal"),
                };
                return Some((a.min(b), a.max(b)));
            }
        }
    }
    None
}

/// A segment from its lexicographically smaller end ("left") to the other.
struct LeftToRight {
    /// The ends' sort keys ([`ordered`] x, then y).
    keys: [u64; 2],
    ends: [Vec2; 2],
    /// Whether the segment was given right to left.
    reversed: bool,
}

impl LeftToRight {
    fn points(&self) -> [DVec2; 2] {
        self.ends.map(Vec2::as_dvec2)
    }
}

fn left_to_right([a, b]: [Vec2; 2]) -> LeftToRight {
    let key = |p: Vec2| (u64::from(ordered(p.x)) << 32) | u64::from(ordered(p.y));
    let (ka, kb) = (key(a), key(b));
    if ka <= kb {
        LeftToRight { keys: [ka, kb], ends: [a, b], reversed: false }
    } else {
        LeftToRight { keys: [kb, ka], ends: [b, a], reversed: true }
    }
}

/// `ids` by `key_of`, sorted as (key, id) pairs rather than by a key looked up per comparison: the
/// pairs sort in cache, the look-ups would not (1.4-1.8x faster at 10^5 segments).
fn sorted(ids: impl Iterator<Item = u32>, key_of: &dyn Fn(u32) -> u64) -> Vec<u32> {
    let mut pairs: Vec<(u64, u32)> = ids.map(|i| (key_of(i), i)).collect();
    pairs.sort_unstable();
    pairs.into_iter().map(|(_, i)| i).collect()
}

/// Whether the segment `[l, r]` being placed goes above (Greater) or below the active segment
/// `[tl, tr]`, just right of `l` (both left to right); Equal when collinear and overlapping.
fn place([l, r]: [DVec2; 2], [tl, tr]: [DVec2; 2]) -> Ordering {
    let o = orient(tl, tr, l);
    let o = if o == 0.0 { orient(tl, tr, r) } else { o };
    o.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
}

/// `x`'s bits, mapped so that unsigned order is numeric order (`-0.0` counts as `0.0`).
fn ordered(x: f32) -> u32 {
    let bits = (x + 0.0).to_bits();
    if bits >> 31 == 1 { !bits } else { bits | 1 << 31 }
}

const NIL: u32 = u32::MAX;

/// A treap over segment ids, one node per segment (node `s` is segment `s`), ordered by a
/// comparison supplied at insertion; parent links let a segment be removed, and its neighbours
/// found, without comparisons. Priorities are a hash of the id: expected depth O(log n).
struct Treap {
    root: u32,
    /// Children (below, above) and parent of each node.
    kids: Vec<[u32; 2]>,
    parent: Vec<u32>,
}

impl Treap {
    fn new(n: usize) -> Treap {
        Treap { root: NIL, kids: vec![[NIL; 2]; n], parent: vec![NIL; n] }
    }

    fn priority(s: u32) -> u64 {
        // splitmix64's finaliser: a fixed, well-mixed order
        let mut z = u64::from(s).wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Inserts `s`, where `place(t)` says whether `s` goes below (Less) or above (Greater) node `t`;
    /// `Err(t)` when `place` cannot tell `s` and `t` apart (collinear and overlapping).
    fn insert(&mut self, s: u32, place: impl Fn(u32) -> Ordering) -> Result<(), u32> {
        let (mut at, mut side) = (NIL, 0);
        let mut t = self.root;
        while t != NIL {
            side = match place(t) {
                Ordering::Less => 0,
                Ordering::Greater => 1,
                Ordering::Equal => return Err(t),
            };
            at = t;
            t = self.kids[t as usize][side];
        }
        self.kids[s as usize] = [NIL; 2];
        self.parent[s as usize] = at;
        if at == NIL {
            self.root = s;
        } else {
            self.kids[at as usize][side] = s;
        }
        while self.parent[s as usize] != NIL && Self::priority(self.parent[s as usize]) < Self::priority(s) {
            self.rotate_up(s);
        }
        Ok(())
    }

    /// Removes `s` (which must be in the tree).
    fn remove(&mut self, s: u32) {
        // rotate s down below its higher-priority child until it is a leaf
        loop {
            let [a, b] = self.kids[s as usize];
            let c = match (a, b) {
                (NIL, NIL) => break,
                (c, NIL) | (NIL, c) => c,
                _ if Self::priority(a) > Self::priority(b) => a,
                _ => b,
            };
            self.rotate_up(c);
        }
        let p = self.parent[s as usize];
        if p == NIL {
            self.root = NIL;
        } else {
            let side = usize::from(self.kids[p as usize][1] == s);
            self.kids[p as usize][side] = NIL;
        }
        self.parent[s as usize] = NIL;
    }

    /// The node next to `s`: below for `dir` 0, above for 1.
    fn neighbour(&self, s: u32, dir: usize) -> Option<u32> {
        let mut x = self.kids[s as usize][dir];
        if x != NIL {
            while self.kids[x as usize][1 - dir] != NIL {
                x = self.kids[x as usize][1 - dir];
            }
            return Some(x);
        }
        let mut x = s;
        loop {
            let p = self.parent[x as usize];
            if p == NIL {
                return None;
            }
            if self.kids[p as usize][1 - dir] == x {
                return Some(p);
            }
            x = p;
        }
    }

    /// Puts `x` in its parent's place, keeping the in-order sequence.
    fn rotate_up(&mut self, x: u32) {
        let p = self.parent[x as usize];
        let g = self.parent[p as usize];
        let dir = usize::from(self.kids[p as usize][1] == x);
        let b = self.kids[x as usize][1 - dir];
        self.kids[p as usize][dir] = b;
        if b != NIL {
            self.parent[b as usize] = p;
        }
        self.kids[x as usize][1 - dir] = p;
        self.parent[p as usize] = x;
        self.parent[x as usize] = g;
        if g == NIL {
            self.root = x;
        } else {
            let side = usize::from(self.kids[g as usize][1] == p);
            self.kids[g as usize][side] = x;
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::vec2;
    use proptest::prelude::*;

    use super::*;

    /// The oracle: every pair.
    fn brute_force(segments: &[[Vec2; 2]]) -> bool {
        (0..segments.len()).any(|i| {
            (i + 1..segments.len()).any(|j| {
                let ([p1, p2], [q1, q2]) = (segments[i], segments[j]);
                conflict(p1.as_dvec2(), p2.as_dvec2(), q1.as_dvec2(), q2.as_dvec2()) != Conflict::None
            })
        })
    }

    /// Segments between points of a small integer lattice: many shared ends, T's, collinear runs.
    fn arb_segments() -> impl Strategy<Value = Vec<[Vec2; 2]>> {
        let point = (0..6i32, 0..6i32).prop_map(|(x, y)| vec2(x as f32, y as f32));
        prop::collection::vec((point.clone(), point), 0..12)
            .prop_map(|v| v.into_iter().filter(|(a, b)| a != b).map(|(a, b)| [a, b]).collect())
    }

    proptest! {
        #![proptest_config(mazewalk_testkit::config())]

        #[test]
        fn the_sweep_agrees_with_every_pair(segments in arb_segments()) {
            let found = first_conflict(segments.len(), |i| segments[i as usize]);
            prop_assert_eq!(found.is_some(), brute_force(&segments), "{:?} {:?}", segments, found);
            if let Some((a, b, c)) = found {
                let ([p1, p2], [q1, q2]) = (segments[a as usize], segments[b as usize]);
                prop_assert_eq!(conflict(p1.as_dvec2(), p2.as_dvec2(), q1.as_dvec2(), q2.as_dvec2()), c);
            }
        }
    }

    #[test]
    fn a_grid_of_cells_has_no_conflict_and_a_long_diagonal_has_one() {
        let mut segments = Vec::new();
        for i in 0..=10 {
            for j in 0..10 {
                let (i, j) = (i as f32, j as f32);
                segments.push([vec2(i, j), vec2(i, j + 1.0)]);
                segments.push([vec2(j, i), vec2(j + 1.0, i)]);
            }
        }
        assert_eq!(first_conflict(segments.len(), |i| segments[i as usize]), None);
        segments.push([vec2(0.5, 0.5), vec2(9.5, 9.0)]);
        let found = first_conflict(segments.len(), |i| segments[i as usize]);
        assert!(matches!(found, Some((_, _, Conflict::Cross))), "{found:?}");
    }
}
