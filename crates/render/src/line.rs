//! Bresenham lines for the ascii outlines: integer points, clipped to the buffer, and a depth-tested drawer.
//!
//! A line from `p0` to `p1` with major extent `n = max(|dx|, |dy|)` and minor extent `m` visits, for
//! `k = 0..=n`, the point `k` steps along the major axis and `round(k·m / n)` (halves rounded away from the
//! lexicographically smaller endpoint) along the minor one: Bresenham's points, 8-connected, both
//! endpoints included, the same set whichever end it is drawn from. The closed form lets the segment be
//! clipped to the buffer before iterating, so a line from -1e9 to +1e9 costs only the visible points.

use glam::Vec3;

use super::samples::SampleBuffer;

/// Coordinates beyond ±2^40 are clamped (keeps `k·m` within `i128` and the loops finite).
const LIMIT: i64 = 1 << 40;

/// The visible points of a Bresenham line, from `p0` towards `p1`; see [`line_points`].
#[derive(Clone, Debug)]
pub struct LinePoints {
    /// The lexicographically smaller endpoint, where the closed form starts.
    start: [i64; 2],
    /// 0 if x is the major axis, 1 if y is.
    major: usize,
    sign: [i64; 2],
    n: i64,
    m: i64,
    /// Next k to yield and the last one (inclusive), in the canonical direction.
    k: i64,
    k_end: i64,
    /// +1 when drawing from the canonical start, -1 when drawing back from the other end.
    step: i64,
    done: bool,
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
        start: a,
        major,
        sign: d.map(|c| if c < 0 { -1 } else { 1 }),
        n: d[major].abs(),
        m: d[minor].abs(),
        k: 0,
        k_end: 0,
        step: 1,
        done: false,
    };

    // Visible range of k: the major coordinate is linear in k, the minor one monotone (binary search).
    let limit = |axis: usize| i64::try_from(if axis == 0 { width } else { height }).unwrap_or(LIMIT) - 1;
    let range_along = |axis: usize, max_steps: i64| {
        // Steps s in [0, max_steps] with start[axis] + sign[axis]·s in [0, limit(axis)].
        let (first, last) = if line.sign[axis] > 0 {
            (-a[axis], limit(axis) - a[axis])
        } else {
            (a[axis] - limit(axis), a[axis])
        };
        (first.max(0), last.min(max_steps))
    };
    let (k_lo, k_hi) = range_along(major, line.n);
    let (o_lo, o_hi) = range_along(minor, line.m);
    let k_lo = k_lo.max(line.first_k_with_offset_at_least(o_lo));
    let k_hi = k_hi.min(line.first_k_with_offset_at_least(o_hi + 1) - 1);
    line.done = k_lo > k_hi || o_lo > o_hi;
    (line.k, line.k_end, line.step) = if reversed { (k_hi, k_lo, -1) } else { (k_lo, k_hi, 1) };
    line
}

impl LinePoints {
    /// Minor-axis steps taken after `k` major steps: `round(k·m / n)`, halves up.
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

    /// The smallest k in [0, n + 1] whose offset is at least `target` (n + 1 if none).
    fn first_k_with_offset_at_least(&self, target: i64) -> i64 {
        let (mut lo, mut hi) = (0, self.n + 1);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if self.offset(mid) >= target { hi = mid } else { lo = mid + 1 }
        }
        lo
    }

    /// The next point with its parameter `t` in [0, 1] from the first endpoint to the second.
    fn next_with_t(&mut self) -> Option<((usize, usize), f32)> {
        if self.done {
            return None;
        }
        let k = self.k;
        self.done = k == self.k_end;
        self.k += self.step;
        let mut p = self.start;
        p[self.major] += self.sign[self.major] * k;
        p[1 - self.major] += self.sign[1 - self.major] * self.offset(k);
        let t = if self.n == 0 { 0.0 } else { k as f32 / self.n as f32 };
        let t = if self.step < 0 { 1.0 - t } else { t };
        Some(((p[0] as usize, p[1] as usize), t)) // inside the grid by the clipping in `line_points`
    }
}

impl Iterator for LinePoints {
    type Item = (usize, usize);

    fn next(&mut self) -> Option<(usize, usize)> {
        self.next_with_t().map(|(p, _)| p)
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
