//! Bresenham lines for the ascii outlines: integer points, clipped to the buffer, and a depth-tested drawer.
//!
//! A line from `p0` to `p1` with major extent `n = max(|dx|, |dy|)` and minor extent `m` visits, for
//! `k = 0..=n`, the point `k` steps along the major axis and `round(k·m / n)` (halves rounded away from the
//! lexicographically smaller endpoint) along the minor one: Bresenham's points, 8-connected, both
//! endpoints included, the same set whichever end it is drawn from. The closed form lets the segment be
//! clipped to the buffer before iterating, so a line from -1e9 to +1e9 costs only the visible points.

use glam::{Vec2, Vec3};

use super::samples::SampleBuffer;

/// Coordinates beyond ±2^40 are clamped (keeps `k·m` within `i128` and the loops finite).
const LIMIT: i64 = 1 << 40;

/// The visible points of a Bresenham line, from `p0` towards `p1`; see [`line_points`].
#[derive(Clone, Debug)]
pub struct LinePoints {
    /// The signs of x and y from the lexicographically smaller endpoint, where the closed form starts.
    sign: [i64; 2],
    n: i64,
    m: i64,
    /// Next k to yield and the last one (inclusive), in the canonical direction.
    k: i64,
    k_end: i64,
    /// +1 when drawing from the canonical start, -1 when drawing back from the other end.
    step: i64,
    done: bool,
    /// The point at `k`, carried from point to point with the closed form's remainder (Bresenham's
    /// error term): `2·k·m + n = 2·n·offset(k) + rest`, `0 ≤ rest < 2·n` (both 0 when `n` is 0).
    point: [i64; 2],
    rest: i64,
    /// What a step of `k` (in the drawing's direction) adds to the point and to `rest`, and what the
    /// offset's step (one more in that direction) adds to the point.
    forward: [i64; 2],
    rest_step: i64,
    across: [i64; 2],
}

/// The points of the line from `(x0, y0)` to `(x1, y1)` inside a `width × height` grid, in order from the
/// first endpoint; all octants, endpoints included, 8-connected, bounded by the visible part.
#[must_use]
pub fn line_points(x0: i64, y0: i64, x1: i64, y1: i64, width: usize, height: usize) -> LinePoints {
    let p0 = [x0.clamp(-LIMIT, LIMIT), y0.clamp(-LIMIT, LIMIT)];
    let p1 = [x1.clamp(-LIMIT, LIMIT), y1.clamp(-LIMIT, LIMIT)];
    let reversed = p1 < p0;
    let (a, b) = if reversed { (p1, p0) } else { (p0, p1) };
    let d = [b[0] - a[0], b[1] - a[1]];
    let major = usize::from(d[1].abs() > d[0].abs());
    let minor = 1 - major;
    let mut line = LinePoints {
        sign: d.map(|c| if c < 0 { -1 } else { 1 }),
        n: d[major].abs(),
        m: d[minor].abs(),
        k: 0,
        k_end: 0,
        step: 1,
        done: false,
        point: a,
        rest: 0,
        forward: [0; 2],
        rest_step: 0,
        across: [0; 2],
    };

    // Visible range of k: the major coordinate is linear in k, the minor one monotone (binary search).
    let (k_lo, k_hi) = line.steps_inside(a, major, line.n, (width, height));
    let (o_lo, o_hi) = line.steps_inside(a, minor, line.m, (width, height));
    let k_lo = k_lo.max(line.first_k_with_offset_at_least(o_lo));
    let k_hi = k_hi.min(line.first_k_with_offset_at_least(o_hi + 1) - 1);
    line.done = k_lo > k_hi || o_lo > o_hi;
    (line.k, line.k_end, line.step) = if reversed { (k_hi, k_lo, -1) } else { (k_lo, k_hi, 1) };
    if !line.done && line.n > 0 {
        // The first point's offset and remainder in 128 bits (k·m may pass 2⁶³ at the clamp); the
        // remainder stays below 2·n ≤ 2⁴² from there on.
        let offset;
        (offset, line.rest) = if line.n < 1 << 30 {
            // every line on a screen: 2·k·m + n < 2⁶³, and 64-bit divisions are far cheaper
            let (k, m, n) = (line.k, line.m, line.n);
            ((2 * k * m + n) / (2 * n), (2 * k * m + n) % (2 * n))
        } else {
            let (k, m, n) = (i128::from(line.k), i128::from(line.m), i128::from(line.n));
            (((2 * k * m + n) / (2 * n)) as i64, ((2 * k * m + n) % (2 * n)) as i64) // ≤ m, < 2·n: they fit
        };
        line.point[major] += line.sign[major] * line.k;
        line.point[minor] += line.sign[minor] * offset;
        line.forward[major] = line.sign[major] * line.step;
        line.across[minor] = line.sign[minor] * line.step;
        line.rest_step = 2 * line.m * line.step;
    }
    line
}

impl LinePoints {
    /// The steps `s` in `[0, max_steps]` that keep coordinate `axis` of `start + sign·s` inside a
    /// `width × height` grid (first and last; empty when first > last).
    fn steps_inside(
        &self,
        start: [i64; 2],
        axis: usize,
        max_steps: i64,
        (width, height): (usize, usize),
    ) -> (i64, i64) {
        let limit = i64::try_from(if axis == 0 { width } else { height }).unwrap_or(LIMIT) - 1;
        let (first, last) = if self.sign[axis] > 0 {
            (-start[axis], limit - start[axis])
        } else {
            (start[axis] - limit, start[axis])
        };
        (first.max(0), last.min(max_steps))
    }

    /// Minor-axis steps taken after `k` major steps: `round(k·m / n)`, halves up.
    #[cfg(test)]
    fn offset(&self, k: i64) -> i64 {
        if self.n == 0 {
            return 0;
        }
        if self.n < 1 << 30 {
            // Every line on a screen: 2·k·m + n < 2⁶³, and a 64-bit division is far cheaper.
            return (2 * k * self.m + self.n) / (2 * self.n);
        }
        let (k, m, n) = (i128::from(k), i128::from(self.m), i128::from(self.n));
        ((2 * k * m + n) / (2 * n)) as i64 // ≤ m, so it fits
    }

    /// The smallest k in [0, n + 1] whose offset is at least `target` (n + 1 if none): the offset
    /// `⌊(2·k·m + n) / 2·n⌋` is at least `target` exactly where `2·k·m ≥ 2·n·target − n`, so for a
    /// positive `target` the least such k is that quotient rounded up (in 128 bits: `n·target` may
    /// pass 2⁶³ at the clamp).
    fn first_k_with_offset_at_least(&self, target: i64) -> i64 {
        if target <= 0 {
            return 0; // offset(0) = ⌊n / 2n⌋ = 0
        }
        if self.m == 0 {
            return self.n + 1; // every offset is 0
        }
        let (m, n) = (self.m, self.n);
        if n < 1 << 30 && target <= n + 1 {
            // every line on a screen (a target is at most m + 1 ≤ n + 1 there): 2·n·target < 2⁶³
            return ((2 * n * target - n + 2 * m - 1) / (2 * m)).min(n + 1); // rounded up: the numerator is ≥ n > 0
        }
        let (m, n, target) = (i128::from(m), i128::from(n), i128::from(target));
        let k = (2 * n * target - n + 2 * m - 1) / (2 * m);
        k.min(n + 1) as i64
    }

    /// The next point and its k (in the canonical direction). The closed form's remainder is carried
    /// along: a step of k adds `2·m ≤ 2·n` to it (or takes it, drawing back), so the offset moves by
    /// at most one, where the remainder leaves [0, 2·n).
    #[inline]
    fn next_point(&mut self) -> Option<((usize, usize), i64)> {
        if self.done {
            return None;
        }
        let (p, k) = (self.point, self.k);
        self.done = k == self.k_end;
        if !self.done {
            self.k += self.step;
            self.point = [p[0] + self.forward[0], p[1] + self.forward[1]];
            self.rest += self.rest_step;
            let wrapped = if self.rest >= 2 * self.n {
                self.rest - 2 * self.n
            } else if self.rest < 0 {
                self.rest + 2 * self.n
            } else {
                self.rest
            };
            if wrapped != self.rest {
                self.rest = wrapped;
                self.point = [self.point[0] + self.across[0], self.point[1] + self.across[1]];
            }
        }
        Some(((p[0] as usize, p[1] as usize), k)) // inside the grid by the clipping in `line_points`
    }

    /// The next point with its parameter `t` in [0, 1] from the first endpoint to the second.
    fn next_with_t(&mut self) -> Option<((usize, usize), f32)> {
        let (p, k) = self.next_point()?;
        let t = if self.n == 0 { 0.0 } else { k as f32 / self.n as f32 };
        let t = if self.step < 0 { 1.0 - t } else { t };
        Some((p, t))
    }
}

impl Iterator for LinePoints {
    type Item = (usize, usize);

    #[inline]
    fn next(&mut self) -> Option<(usize, usize)> {
        self.next_point().map(|(p, _)| p)
    }
}

/// The samples a segment from `p` to `q` (grid space, in samples) passes over, sampled at the samples'
/// centres: along its major axis, each column (row) whose centre lies within the segment, and across
/// it the row (column) the segment's point there lies in. Only those inside a `width × height` grid;
/// a segment of no major extent, or with a non-finite end, has none.
///
/// Unlike [`line_points`], whose endpoints are rounded to samples first, it takes the segment as it
/// is: two grids that map one line each by an affine map of its own (the tiles of a foveated view)
/// and meet at a sample boundary place it on the same samples there, with no gap and no sample
/// twice, however each rounds its ends.
#[must_use]
pub fn centre_points(p: Vec2, q: Vec2, width: usize, height: usize) -> CentrePoints {
    let none = CentrePoints { next: 1, last: 0, major: 0, at: [0.0; 2], slope: 0.0, limit: 0 };
    if !(p.is_finite() && q.is_finite()) {
        return none;
    }
    let (p, q) = (p.as_dvec2().to_array(), q.as_dvec2().to_array());
    let major = usize::from((q[1] - p[1]).abs() > (q[0] - p[0]).abs());
    let (minor, size) = (1 - major, [width, height]);
    let (lo, hi) = if p[major] <= q[major] { (p, q) } else { (q, p) };
    if hi[major] == lo[major] {
        return none;
    }
    // the samples whose centre `k + ½` lies in [lo, hi], within the grid
    let first = (lo[major] - 0.5).ceil().max(0.0);
    let last = (hi[major] - 0.5).floor().min(size[major] as f64 - 1.0);
    if first > last {
        return none;
    }
    let slope = (hi[minor] - lo[minor]) / (hi[major] - lo[major]);
    CentrePoints { next: first as i64, last: last as i64, major, at: lo, slope, limit: size[minor] }
}

/// The points of [`centre_points`], in order along the major axis.
#[derive(Clone, Debug)]
pub struct CentrePoints {
    next: i64,
    last: i64,
    /// 0: x is the major axis; 1: y is.
    major: usize,
    /// The end the major axis starts from, and the minor axis's change per unit of the major one.
    at: [f64; 2],
    slope: f64,
    /// The grid's size across the major axis.
    limit: usize,
}

impl Iterator for CentrePoints {
    type Item = (usize, usize);

    fn next(&mut self) -> Option<(usize, usize)> {
        while self.next <= self.last {
            let k = self.next;
            self.next += 1;
            let across = self.at[1 - self.major] + (k as f64 + 0.5 - self.at[self.major]) * self.slope;
            // (its floor, without a call to libm's: `as` truncates toward zero, saturating)
            let minor = across as i64 - i64::from((across as i64) as f64 > across);
            if (0..self.limit as i64).contains(&minor) {
                let (k, minor) = (k as usize, minor as usize);
                return Some(if self.major == 0 { (k, minor) } else { (minor, k) });
            }
        }
        None
    }
}

/// The ascii glyph for a line going `(dx, dy)` samples (y down): `-`, `|`, `/` or `\` by its on-screen
/// angle, a sample being `sample_aspect` (width / height) as wide as it is tall; ±22.5° around each.
#[must_use]
pub fn line_glyph(dx: f32, dy: f32, sample_aspect: f32) -> char {
    let (across, down) = ((dx * sample_aspect).abs(), dy.abs());
    let tan_22_5 = std::f32::consts::SQRT_2 - 1.0; // tan(π/8)
    if down <= across * tan_22_5 || !(down.is_finite() && across.is_finite()) {
        '-'
    } else if across <= down * tan_22_5 {
        '|'
    } else if (dx > 0.0) == (dy > 0.0) {
        '\\' // right and down, on a grid with y down
    } else {
        '/'
    }
}

/// Draws the line from `p0` to `p1` (grid x, y in samples and depth z) into the outline layer where it is
/// not hidden: at each point, depth (linear along the line) ≤ buffer depth + `epsilon`. The glyph comes
/// from [`line_glyph`]. Returns the number of outline samples written; non-finite endpoints draw nothing.
pub fn draw_line(buffer: &mut SampleBuffer, p0: Vec3, p1: Vec3, sample_aspect: f32, epsilon: f32) -> usize {
    if !(p0.is_finite() && p1.is_finite()) {
        return 0;
    }
    let glyph = line_glyph(p1.x - p0.x, p1.y - p0.y, sample_aspect);
    let cell = |c: f32| (c.floor() as i64).clamp(-LIMIT, LIMIT); // the sample containing the point
    let width = buffer.width();
    let mut points = line_points(cell(p0.x), cell(p0.y), cell(p1.x), cell(p1.y), width, buffer.height());
    let (outline, depth) = buffer.outline_and_depth_mut();
    let mut written = 0;
    while let Some(((x, y), t)) = points.next_with_t() {
        let i = y * width + x;
        if p0.z + (p1.z - p0.z) * t <= depth[i] + epsilon {
            outline[i] = Some(glyph);
            written += 1;
        }
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line across two grids that meet at a row, each mapping the picture to itself by an affine
    /// map of its own (a foveated view's bands: another scale down each, continuous where they meet),
    /// covers each column it crosses exactly once: no gap where it passes from one to the other.
    #[test]
    fn centre_points_across_two_grids_leave_no_gap() {
        let (width, rows) = (40usize, 10usize); // the upper grid 40 × 10; the lower one's row 0 is the picture's 10
        for (k, (p, q)) in [
            (Vec2::new(0.3, 2.2), Vec2::new(39.6, 17.9)),
            (Vec2::new(39.9, 9.7), Vec2::new(0.1, 10.6)),
            (Vec2::new(3.0, 0.5), Vec2::new(35.2, 19.5)),
            (Vec2::new(5.5, 9.99), Vec2::new(30.5, 10.01)),
        ]
        .into_iter()
        .enumerate()
        {
            for scale in [0.5f32, 0.9, 1.0, 1.7, 3.0] {
                // the lower band, in the picture, is `y = 10 + (y_band) / scale`: the line is the
                // picture's, mapped into each grid (the upper one is the picture's rows 0..10)
                let lower = |v: Vec2| Vec2::new(v.x, (v.y - rows as f32) * scale);
                let upper: Vec<(usize, usize)> = centre_points(p, q, width, rows).collect();
                let below: Vec<(usize, usize)> =
                    centre_points(lower(p), lower(q), width, 10 * rows).map(|(x, y)| (x, y + rows)).collect();
                let major_x = (q.x - p.x).abs() >= (q.y - p.y).abs() * scale.max(1.0);
                if major_x {
                    let mut columns: Vec<usize> = upper.iter().chain(&below).map(|&(x, _)| x).collect();
                    columns.sort_unstable();
                    let expected: Vec<usize> = (0..width)
                        .filter(|&x| {
                            let c = x as f32 + 0.5;
                            c >= p.x.min(q.x) && c <= p.x.max(q.x)
                        })
                        .collect();
                    assert_eq!(columns, expected, "line {k} scale {scale}: each column once");
                }
                assert!(upper.iter().all(|&(x, y)| x < width && y < rows), "line {k}: inside the grid");
            }
        }
        assert_eq!(centre_points(Vec2::ZERO, Vec2::new(f32::NAN, 1.0), 4, 4).count(), 0, "not finite: none");
        assert_eq!(centre_points(Vec2::splat(1.2), Vec2::splat(1.2), 4, 4).count(), 0, "a point: none");
        let far = centre_points(Vec2::new(-1e6, -1e6), Vec2::new(1e6, 1e6), 8, 8);
        assert_eq!(
            far.collect::<Vec<_>>(),
            (0..8).map(|k| (k, k)).collect::<Vec<_>>(),
            "a long line: its visible part"
        );
    }

    #[test]
    fn a_shallow_line_steps_like_bresenham() {
        let points: Vec<_> = line_points(0, 0, 4, 2, 10, 10).collect();
        assert_eq!(points, [(0, 0), (1, 1), (2, 1), (3, 2), (4, 2)]);
        let back: Vec<_> = line_points(4, 2, 0, 0, 10, 10).collect();
        assert_eq!(back, points.iter().rev().copied().collect::<Vec<_>>());
    }

    /// The 64-bit offsets (every on-screen line) are the 128-bit ones, up to the longest such line.
    #[test]
    fn offsets_in_64_bits_are_exact_up_to_the_switch() {
        let wide = |k: i64, m: i64, n: i64| {
            let (k, m, n) = (i128::from(k), i128::from(m), i128::from(n));
            ((2 * k * m + n) / (2 * n)) as i64
        };
        for n in [1, 2, 7, 1000, (1 << 30) - 1, 1 << 30] {
            let line = line_points(0, 0, n, n - 1, 1, 1);
            for k in [0, 1, n / 3, n / 2, n - 1, n, n + 1] {
                assert_eq!(line.offset(k), wide(k, n - 1, n), "k {k} n {n}");
            }
        }
    }

    /// The points as the closed form gave them before the offset was carried from point to point:
    /// the visible range of k by binary search over `offset`, then `offset(k)` for each k.
    fn closed_form_points(
        x0: i64,
        y0: i64,
        x1: i64,
        y1: i64,
        w: usize,
        h: usize,
    ) -> Vec<((usize, usize), f32)> {
        let line = line_points(x0, y0, x1, y1, w, h); // its signs, n and m
        let (p0, p1) = ([x0, y0].map(|c| c.clamp(-LIMIT, LIMIT)), [x1, y1].map(|c| c.clamp(-LIMIT, LIMIT)));
        let (a, b) = if p1 < p0 { (p1, p0) } else { (p0, p1) };
        let major = usize::from((b[1] - a[1]).abs() > (b[0] - a[0]).abs());
        let search = |target: i64| {
            let (mut lo, mut hi) = (0, line.n + 1);
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if line.offset(mid) >= target { hi = mid } else { lo = mid + 1 }
            }
            lo
        };
        let minor = 1 - major;
        let (k_lo, k_hi) = line.steps_inside(a, major, line.n, (w, h));
        let (o_lo, o_hi) = line.steps_inside(a, minor, line.m, (w, h));
        let (k_lo, k_hi) = (k_lo.max(search(o_lo)), k_hi.min(search(o_hi + 1) - 1));
        if k_lo > k_hi || o_lo > o_hi {
            return Vec::new();
        }
        let reversed = p1 < p0;
        let ks: Vec<i64> = if reversed { (k_lo..=k_hi).rev().collect() } else { (k_lo..=k_hi).collect() };
        ks.into_iter()
            .map(|k| {
                let mut p = a;
                p[major] += line.sign[major] * k;
                p[minor] += line.sign[minor] * line.offset(k);
                let t = if line.n == 0 { 0.0 } else { k as f32 / line.n as f32 };
                ((p[0] as usize, p[1] as usize), if reversed { 1.0 - t } else { t })
            })
            .collect()
    }

    /// The offset carried from point to point, and the clipped range in closed form, give the
    /// points (and parameters) of the closed form at every k: lines of every octant and length, on
    /// and off grids of many sizes, huge and clamped ones, from either end.
    #[test]
    fn carried_offsets_are_the_closed_form() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let scales = [3, 40, 300, 5_000, 1 << 29, 1 << 31, 1 << 41, i64::MAX];
        let (mut points, mut stepped_back) = (0, 0);
        for case in 0..20_000 {
            let scale = scales[case % scales.len()];
            let mut coord = || {
                let c = (next() % (2 * scale.min(1 << 62) as u64 + 1)) as i64 - scale.min(1 << 62);
                if scale == i64::MAX && next() % 4 == 0 {
                    [i64::MIN, i64::MAX][(next() % 2) as usize]
                } else {
                    c
                }
            };
            let (x0, y0, x1, y1) = (coord(), coord(), coord(), coord());
            let (w, h) = ((next() % 130) as usize, (next() % 50) as usize);
            // lines near the grid too: shifted to start inside it
            let (x0, y0) = if case % 3 == 0 {
                (x0.rem_euclid(w.max(1) as i64), y0.rem_euclid(h.max(1) as i64))
            } else {
                (x0, y0)
            };
            let want = closed_form_points(x0, y0, x1, y1, w, h);
            let mut line = line_points(x0, y0, x1, y1, w, h);
            let got: Vec<_> = std::iter::from_fn(|| line.next_with_t()).collect();
            assert_eq!(got.len(), want.len(), "({x0}, {y0}) → ({x1}, {y1}) in {w}×{h}");
            for (g, e) in got.iter().zip(&want) {
                assert!(
                    g.0 == e.0 && g.1.to_bits() == e.1.to_bits(),
                    "({x0}, {y0}) → ({x1}, {y1}) in {w}×{h}: {g:?} {e:?}"
                );
            }
            let plain: Vec<_> = line_points(x0, y0, x1, y1, w, h).collect();
            assert_eq!(plain, want.iter().map(|&(p, _)| p).collect::<Vec<_>>());
            points += got.len();
            stepped_back += usize::from(got.len() > 1 && [x1, y1] < [x0, y0]);
        }
        assert!(points > 100_000 && stepped_back > 1_000, "{points} points, {stepped_back} lines drawn back");
    }

    #[test]
    fn glyphs_follow_the_on_screen_angle() {
        assert_eq!(line_glyph(5.0, 0.0, 0.5), '-');
        assert_eq!(line_glyph(0.0, -3.0, 0.5), '|');
        assert_eq!(line_glyph(2.0, 1.0, 0.5), '\\'); // 2 cells right = 1 cell-height: 45° on screen
        assert_eq!(line_glyph(2.0, -1.0, 0.5), '/');
        assert_eq!(line_glyph(1.0, 1.0, 0.5), '\\'); // 63.4° on screen, under the 67.5° threshold
        assert_eq!(line_glyph(1.0, 3.0, 0.5), '|'); // 80.5°
    }
}
