//! Triangle and convex-polygon rasterization into a [`SampleBuffer`]: exact, watertight, depth-tested.
//!
//! Grid space: origin top-left, y down; sample `(x, y)` is hit iff its centre `(x + 0.5, y + 0.5)` is inside.
//! Vertices are snapped to a fixed-point grid of [`SUBPIXEL_BITS`] fractional bits and the edge functions
//! are evaluated in `i64`, so two triangles sharing an edge never both cover, nor both miss, a sample on it
//! (the top-left rule decides, as in Direct3D / OpenGL; see Giesen, "The barycentric conspiracy" and
//! "Triangle rasterization in practice", <https://fgiesen.wordpress.com/2013/02/08/triangle-rasterization-in-practice/>).
//! Both windings are accepted (walls are two-sided); zero-area triangles cover nothing.
//!
//! Depth is interpolated linearly in grid space (NDC z is affine there); attributes are interpolated
//! perspective-correctly through `1/w`.

use glam::{Vec2, Vec3, Vec4};
use wide::bytemuck::cast;
use wide::f32x8;

use super::samples::SampleBuffer;

/// Fractional bits of the fixed-point grid vertices are snapped to (1/256 of a sample).
pub(crate) const SUBPIXEL_BITS: u32 = 8;
/// Largest accepted |coordinate| in samples; a triangle with a vertex beyond it (or not finite) is skipped.
/// The pipeline clips against the frustum first, so this only guards against overflow: at 2^20 samples
/// and 8 fractional bits the edge functions stay below 2^60.
pub(crate) const MAX_COORD: f32 = (1u32 << 20) as f32;

const ONE: i64 = 1 << SUBPIXEL_BITS;
const HALF: i64 = ONE / 2;

/// An attribute that can be interpolated across a triangle: a weighted sum of three values.
pub trait Varying: Copy {
    /// `w[0] * v[0] + w[1] * v[1] + w[2] * v[2]`.
    #[must_use]
    fn weighted(v: [Self; 3], w: [f32; 3]) -> Self;
}

impl Varying for () {
    fn weighted(_: [(); 3], _: [f32; 3]) {}
}

impl<const N: usize> Varying for [f32; N] {
    fn weighted(v: [Self; 3], w: [f32; 3]) -> Self {
        std::array::from_fn(|k| w[0] * v[0][k] + w[1] * v[1][k] + w[2] * v[2][k])
    }
}

macro_rules! varying_by_ops {
    ($($t:ty),*) => {$(
        impl Varying for $t {
            fn weighted(v: [Self; 3], w: [f32; 3]) -> Self {
                w[0] * v[0] + w[1] * v[1] + w[2] * v[2]
            }
        }
    )*};
}
varying_by_ops!(f32, Vec2, Vec3, Vec4);

/// A vertex in grid space: after the divide by w and the viewport transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridVertex<A> {
    /// Grid position in samples: origin top-left, y down.
    pub pos: Vec2,
    /// Depth in [0, 1], smaller = nearer; affine in grid space.
    pub depth: f32,
    /// `1 / w_clip`, for perspective-correct attributes; 1.0 under an orthographic projection.
    pub inv_w: f32,
    /// Attributes interpolated perspective-correctly (e.g. view-space position and normal for shading).
    pub attrs: A,
}

/// `pos` snapped to the fixed-point grid, or `None` if not finite or beyond [`MAX_COORD`].
fn snap(pos: Vec2) -> Option<[i64; 2]> {
    let ok = |c: f32| c.is_finite() && c.abs() <= MAX_COORD;
    (ok(pos.x) && ok(pos.y))
        .then(|| [round_to_i64(f64::from(pos.x) * ONE as f64), round_to_i64(f64::from(pos.y) * ONE as f64)])
}

/// `x.round() as i64` (halves away from zero) for a finite `x` well within `i64`, without a call to
/// libm's `round` (baseline x86-64 has no rounding instruction): `x` less its truncation is exact.
#[inline]
fn round_to_i64(x: f64) -> i64 {
    let toward_zero = x as i64;
    let rest = x - toward_zero as f64;
    toward_zero + i64::from(rest >= 0.5) - i64::from(rest <= -0.5)
}

/// Edge function of `a → b` at `p`: twice the signed area of (a, b, p); > 0 on the interior side once the
/// triangle is oriented so that `edge(v0, v1, v2) > 0`.
fn edge(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Top-left rule with y down and the interior on the positive side: a left edge has the interior to its
/// right (the edge goes up, dy < 0); a top edge is horizontal with the interior below (it goes right).
fn is_top_left(a: [i64; 2], b: [i64; 2]) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    dy < 0 || (dy == 0 && dx > 0)
}

/// Calls `hit(x, y, bary)` for every sample of a `width × height` buffer whose centre the triangle covers
/// (top-left rule on edges), with the grid-space barycentric weights of the centre in the order of `pos`.
///
/// The raw coverage function: either winding, nothing for zero-area or non-finite triangles, nothing
/// outside the buffer, never more than `width * height` calls.
pub fn for_each_sample(
    width: usize,
    height: usize,
    pos: [Vec2; 3],
    mut hit: impl FnMut(usize, usize, [f32; 3]),
) {
    for_each_span(width, height, pos, |span| {
        for i in 0..span.len {
            hit(span.x + i, span.y, span.bary(i));
        }
    });
}

/// One row's run of covered samples, with what gives each its barycentric weights exactly.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Span<'t> {
    /// Row.
    pub y: usize,
    /// First column.
    pub x: usize,
    /// Samples covered (at least one).
    pub len: usize,
    /// Edge functions at the row's first column of the bounding box, biased by the top-left rule
    /// (≥ 0 inside), and the span's first sample's offset from that column: the edge functions at
    /// the first sample are worked out only by a caller that weighs its samples ([`Span::edge`]).
    row: [i64; 3],
    first: i64,
    triangle: &'t SpanEdges,
}

/// What the spans of one triangle share: the edge functions' steps per sample to the right, in the
/// normalised winding, their top-left bias, and the area; vertex `order[k]` gets edge `k`'s weight.
#[derive(Clone, Copy, Debug)]
struct SpanEdges {
    step: [i64; 3],
    bias: [i64; 3],
    order: [usize; 3],
    inv_area: f64,
    /// Whether the area is below 2^53 (see [`Span::edges_x8`]).
    exact_in_f64: bool,
    /// Each edge's steps to the eight lanes of a group, `step · lane` in `f64`, and to the next
    /// group, in the caller's vertex order: worked out once a triangle, not once a span (the same
    /// products added to a span's first edge functions, so the same bits).
    lane_steps: [[f64; LANES]; 3],
    step8: [f64; 3],
}

impl Span<'_> {
    /// Edge function `k` at the span's first sample, biased (≥ 0 inside).
    #[inline]
    fn edge(&self, k: usize) -> i64 {
        self.row[k] + self.triangle.step[k] * self.first
    }

    /// The barycentric weights of sample `i` of the span, in the caller's vertex order: the edge
    /// functions at it in `i64`, exactly, divided by the area in `f64`.
    #[inline]
    pub(crate) fn bary(&self, i: usize) -> [f32; 3] {
        let t = self.triangle;
        let mut bary = [0.0; 3];
        for k in 0..3 {
            let e = self.edge(k) + t.step[k] * i as i64 - t.bias[k];
            bary[t.order[k]] = (e as f64 * t.inv_area) as f32;
        }
        bary
    }

    /// The edge functions of the span's samples eight at a time, from its first: [`EdgesX8::bary`]
    /// gives the weights of the current eight (lanes past the span's end get weights off the
    /// triangle, for the caller to mask), [`EdgesX8::advance`] moves to the next eight.
    ///
    /// The same bits as [`Span::bary`], eight at a time: an edge function on a covered sample lies in
    /// `0..=area`, so while the area is below 2^53 it and its steps are integers an `f64` holds
    /// exactly, and stepping it in `f64` (which vectorizes; `i64` → `f64` does not on x86-64) gives the
    /// value `bary` converts. Larger triangles (beyond the pipeline's clipped walls) take `bary` itself.
    #[inline]
    pub(crate) fn edges_x8(&self) -> EdgesX8<'_> {
        let t = self.triangle;
        // in the caller's vertex order
        let mut first = [0.0; 3];
        for k in 0..3 {
            first[t.order[k]] = (self.edge(k) - t.bias[k]) as f64;
        }
        let e = std::array::from_fn(|j| std::array::from_fn(|l| first[j] + t.lane_steps[j][l]));
        EdgesX8 { e, step8: t.step8, inv_area: t.inv_area, span: self, start: 0 }
    }

    /// [`EdgesX8::bary`] by [`Span::bary`], for the rare triangle of area 2^53 or more.
    #[cold]
    fn bary_one_by_one(&self, start: usize) -> [[f32; LANES]; 3] {
        let singles: [[f32; 3]; LANES] = std::array::from_fn(|lane| self.bary(start + lane));
        std::array::from_fn(|k| singles.map(|single| single[k]))
    }
}

/// A span's edge functions at eight consecutive samples, in `f64` (the caller's vertex order): see
/// [`Span::edges_x8`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgesX8<'s> {
    e: [[f64; LANES]; 3],
    step8: [f64; 3],
    inv_area: f64,
    span: &'s Span<'s>,
    start: usize,
}

impl EdgesX8<'_> {
    /// The barycentric weights of the current eight samples: the bits of [`Span::bary`] for each.
    ///
    /// (Exact while the area is below 2^53: see [`Span::edges_x8`].)
    #[inline]
    pub(crate) fn bary(&self) -> [f32x8; 3] {
        if !self.span.triangle.exact_in_f64 {
            return self.span.bary_one_by_one(self.start).map(f32x8::from);
        }
        let weights = |k: usize| {
            let mut out = [0.0; LANES];
            for (out, &e) in out.iter_mut().zip(&self.e[k]) {
                *out = (e * self.inv_area) as f32;
            }
            f32x8::from(out)
        };
        [weights(0), weights(1), weights(2)]
    }

    /// On to the next eight samples.
    #[inline]
    pub(crate) fn advance(&mut self) {
        for (lanes, step) in self.e.iter_mut().zip(self.step8) {
            for e in lanes {
                *e += step;
            }
        }
        self.start += LANES;
    }
}

/// Calls `span` for each row's run of samples the triangle covers, top to bottom (see
/// [`for_each_sample`]: the same samples, grouped by row).
pub(crate) fn for_each_span(width: usize, height: usize, pos: [Vec2; 3], span: impl FnMut(&Span<'_>)) {
    let (Some(p0), Some(p1), Some(p2)) = (snap(pos[0]), snap(pos[1]), snap(pos[2])) else { return };
    for_each_span_snapped(width, height, [p0, p1, p2], span);
}

/// [`for_each_span`] of a triangle already snapped ([`snap`]).
fn for_each_span_snapped(
    width: usize,
    height: usize,
    snapped: [[i64; 2]; 3],
    mut span: impl FnMut(&Span<'_>),
) {
    let (mut v, mut order) = (snapped, [0, 1, 2]);
    let mut area = edge(v[0], v[1], v[2]);
    match area.cmp(&0) {
        // degenerate: a line or a point covers no sample centre exactly enough to matter
        std::cmp::Ordering::Equal => return,
        // normalise the winding so the interior is on the positive side of every edge
        std::cmp::Ordering::Less => {
            v.swap(1, 2);
            order.swap(1, 2);
            area = -area;
        }
        std::cmp::Ordering::Greater => {}
    }

    // Bounding box in samples whose centres (k * ONE + HALF) can lie inside, clamped to the buffer.
    let clamp_hi = |n: usize| i64::try_from(n).unwrap_or(i64::MAX) - 1;
    let (min_x, max_x) =
        (v.iter().map(|p| p[0]).min().unwrap_or(0), v.iter().map(|p| p[0]).max().unwrap_or(0));
    let (min_y, max_y) =
        (v.iter().map(|p| p[1]).min().unwrap_or(0), v.iter().map(|p| p[1]).max().unwrap_or(0));
    let ceil_div = |a: i64| (a + ONE - 1).div_euclid(ONE);
    let x_lo = ceil_div(min_x - HALF).max(0);
    let y_lo = ceil_div(min_y - HALF).max(0);
    let x_hi = (max_x - HALF).div_euclid(ONE).min(clamp_hi(width));
    let y_hi = (max_y - HALF).div_euclid(ONE).min(clamp_hi(height));
    if x_lo > x_hi || y_lo > y_hi {
        return;
    }

    // Edge k is the one opposite vertex k, so its function is vertex k's barycentric weight times `area`.
    let edges = [(v[1], v[2]), (v[2], v[0]), (v[0], v[1])];
    let bias = edges.map(|(a, b)| if is_top_left(a, b) { 0 } else { -1 }); // E >= 0 on top-left, E > 0 else
    let step_x = edges.map(|(a, b)| -(b[1] - a[1]) * ONE);
    let step_y = edges.map(|(a, b)| (b[0] - a[0]) * ONE);
    let start = [x_lo * ONE + HALF, y_lo * ONE + HALF];
    let mut row: [i64; 3] = std::array::from_fn(|k| edge(edges[k].0, edges[k].1, start) + bias[k]);
    let triangle = SpanEdges {
        step: step_x,
        bias,
        order,
        inv_area: 1.0 / area as f64,
        exact_in_f64: area < 1 << f64::MANTISSA_DIGITS,
        lane_steps: {
            let mut lane_steps = [[0.0; LANES]; 3];
            for k in 0..3 {
                lane_steps[order[k]] = std::array::from_fn(|l| step_x[k] as f64 * l as f64);
            }
            lane_steps
        },
        step8: {
            let mut step8 = [0.0; 3];
            for k in 0..3 {
                step8[order[k]] = (step_x[k] * LANES as i64) as f64;
            }
            step8
        },
    };

    for y in y_lo..=y_hi {
        // The row's span, solved exactly in integers: E_k(x_lo + i) = row_k + step_x_k · i ≥ 0 for all k.
        let (mut first, mut last) = (0, x_hi - x_lo);
        for k in 0..3 {
            match step_x[k] {
                // inside at the box's first column, the edge stays inside along the row: no divide
                s if s > 0 && row[k] < 0 => first = first.max((-row[k] + s - 1) / s),
                s if s > 0 => {}
                s if s < 0 => last = last.min(if row[k] < 0 { -1 } else { row[k] / -s }),
                _ if row[k] < 0 => last = -1,
                _ => {}
            }
        }
        if first <= last {
            debug_assert!((0..3).all(|k| row[k] + step_x[k] * first >= 0 && row[k] + step_x[k] * last >= 0));
            span(&Span {
                y: y as usize,
                x: (x_lo + first) as usize, // in [0, width) by the clamps above
                len: (last - first + 1) as usize,
                row,
                first,
                triangle: &triangle,
            });
        }
        for k in 0..3 {
            row[k] += step_y[k];
        }
    }
}

/// How many times each sample of a `width × height` buffer is covered by the fan triangulation of
/// `polygon` from vertex 0 (row-major); a convex polygon gives only 0s and 1s. For tests and debugging.
#[must_use]
pub fn polygon_coverage(width: usize, height: usize, polygon: &[Vec2]) -> Vec<u32> {
    let mut count = vec![0; width * height];
    for k in 1..polygon.len().saturating_sub(1) {
        for_each_sample(width, height, [polygon[0], polygon[k], polygon[k + 1]], |x, y, _| {
            count[y * width + x] += 1;
        });
    }
    count
}

/// Rasterizes one triangle with a LESS depth test; returns the number of samples written.
///
/// For each covered sample nearer than the buffer's depth, `shade` gets the perspective-correct attributes
/// and returns the linear colour; colour, depth and `id` are written. Triangles with a non-finite depth or
/// `inv_w` are skipped.
pub fn fill_triangle<A: Varying>(
    buffer: &mut SampleBuffer,
    tri: [&GridVertex<A>; 3],
    id: u32,
    shade: impl FnMut(A) -> Vec3,
) -> usize {
    cover_triangle(buffer, tri, id, None, shade)
}

/// [`fill_triangle`], or with `alpha` a translucent triangle: each covered sample nearer than the
/// buffer's depth takes `alpha` of `shade`'s colour over what is there, and `id`, but keeps its
/// depth (what is behind still hides what is further).
fn cover_triangle<A: Varying>(
    buffer: &mut SampleBuffer,
    tri: [&GridVertex<A>; 3],
    id: u32,
    alpha: Option<f32>,
    mut shade: impl FnMut(A) -> Vec3,
) -> usize {
    if !tri.iter().all(|v| v.depth.is_finite() && v.inv_w.is_finite()) {
        return 0;
    }
    let pitch = buffer.pitch(); // (a window's rows: its picture's apart)
    let depth = tri.map(|v| v.depth);
    let inv_w = tri.map(|v| v.inv_w);
    let attrs = tri.map(|v| v.attrs);
    let mut written = 0;
    let (width, height) = (buffer.width(), buffer.height());
    let (colors, depths, ids) = buffer.parts_mut();
    for_each_sample(width, height, tri.map(|v| v.pos), |x, y, b| {
        let i = y * pitch + x;
        // Affine in grid space; written relative to vertex 0 so a constant depth stays exact.
        let z = depth[0] + b[1] * (depth[1] - depth[0]) + b[2] * (depth[2] - depth[0]);
        if z.is_nan() || z >= depths[i] {
            return; // LESS: hidden (or tied) by what is already there
        }
        // Perspective-correct weights: attr/w and 1/w are affine in grid space, attr is not.
        let pw = [b[0] * inv_w[0], b[1] * inv_w[1], b[2] * inv_w[2]];
        let sum = pw[0] + pw[1] + pw[2];
        let w = if sum.is_normal() { pw.map(|p| p / sum) } else { b }; // 1/w ≈ 0: fall back to affine
        let color = shade(A::weighted(attrs, w));
        match alpha {
            None => (colors[i], depths[i], ids[i]) = (color, z, id),
            Some(a) => (colors[i], ids[i]) = (colors[i].lerp(color, a), id), // (the depth kept)
        }
        written += 1;
    });
    written
}

/// Rasterizes a convex polygon as a triangle fan from vertex 0 (either winding; the pipeline's clipped
/// wall polygons); returns the number of samples written. Watertight: the fan's internal edges are shared
/// exactly, so no sample is written twice by one polygon, and polygons sharing an edge meet without cracks.
pub fn fill_polygon<A: Varying>(
    buffer: &mut SampleBuffer,
    polygon: &[GridVertex<A>],
    id: u32,
    mut shade: impl FnMut(A) -> Vec3,
) -> usize {
    let mut written = 0;
    for k in 1..polygon.len().saturating_sub(1) {
        written += fill_triangle(buffer, [&polygon[0], &polygon[k], &polygon[k + 1]], id, &mut shade);
    }
    written
}

/// [`fill_polygon`] translucent: `alpha` of each sample's colour over what is there, the depths kept
/// ([`cover_triangle`]); a ghost's figure.
pub fn blend_polygon<A: Varying>(
    buffer: &mut SampleBuffer,
    polygon: &[GridVertex<A>],
    id: u32,
    alpha: f32,
    mut shade: impl FnMut(A) -> Vec3,
) -> usize {
    let mut written = 0;
    for k in 1..polygon.len().saturating_sub(1) {
        let tri = [&polygon[0], &polygon[k], &polygon[k + 1]];
        written += cover_triangle(buffer, tri, id, Some(alpha), &mut shade);
    }
    written
}

/// Samples a SIMD step of [`fill_polygon_x8`] takes at once ([`f32x8`]: two SSE registers on baseline
/// x86-64, one with AVX).
pub(crate) const LANES: usize = 8;

/// [`fill_polygon`] for a wall of one flat colour, eight samples of a row at a time: the same samples,
/// depths and ids as the scalar fill with `|_| color` (the same operations in the same order lane by
/// lane, so the same bits), each written sample `color`. What the pipeline draws its untextured walls
/// with; the scalar [`fill_polygon`] stays the reference (and takes any shading).
///
/// Where a fan triangle's depth is a function of the column alone ([`column_depths`]: in a level view,
/// the triangle whose apex and one other corner are one end of a wall, its top and bottom, one above
/// the other), its samples' depths are computed once a column into `columns` (scratch, reused) and
/// loaded by the row's groups of eight, instead of weighing each sample's edge functions.
pub(crate) fn fill_polygon_x8(
    buffer: &mut SampleBuffer,
    polygon: &[GridVertex<Vec3>],
    id: u32,
    color: Vec3,
    columns: &mut Vec<f32>,
) -> usize {
    let mut written = 0;
    for k in 1..polygon.len().saturating_sub(1) {
        let tri = [&polygon[0], &polygon[k], &polygon[k + 1]];
        written += fill_triangle_x8(buffer, tri, id, color, columns);
    }
    written
}

/// Whether every sample `tri` covers has a depth that depends on its column alone, the bits
/// [`fill_triangle`] gives it; if so, `columns[x - x_lo]` holds them for the columns `x_lo..` of the
/// triangle's bounding box (clamped to `width`), padded by [`LANES`], and `Some(x_lo)` is returned.
///
/// A sample's depth is `(d₀ + b₁·(d₁ − d₀)) + b₂·(d₂ − d₀)` in `f32`, each weight `bₖ` its edge function
/// (an exact integer) times `1 / area` in `f64`, rounded to `f32`. When `d₂ − d₀` is zero (±0), the
/// last term is a zero of its sign for every covered sample (`b₂ ≥ +0` there: its edge function is
/// `≥ 0`), so it adds nothing but that sign; and when the edge opposite vertex 1 (from vertex 2 to 0)
/// is vertical on the fixed-point grid, `b₁`'s edge function does not change down a column, so
/// neither does the depth. The same with the roles of 1 and 2 swapped. Both differences zero (a wall
/// faced square on): one depth for all. Otherwise `None`, and the caller weighs each sample.
fn column_depths(
    width: usize,
    tri: [&GridVertex<Vec3>; 3],
    [p0, p1, p2]: [[i64; 2]; 3],
    columns: &mut Vec<f32>,
) -> Option<i64> {
    let depth0 = tri[0].depth;
    let (depth_1, depth_2) = (tri[1].depth - tri[0].depth, tri[2].depth - tri[0].depth);
    let signed = edge(p0, p1, p2);
    if signed == 0 || width == 0 {
        return None;
    }
    // Which weight varies along the row, as (its vertex's edge: from, to), or none.
    let varying = match (depth_1 == 0.0, depth_2 == 0.0) {
        (true, true) => None,
        (false, true) if p2[0] == p0[0] => Some((depth_1, (p2, p0))),
        (true, false) if p0[0] == p1[0] => Some((depth_2, (p0, p1))),
        _ => return None,
    };
    let inv_area = 1.0 / signed.unsigned_abs() as f64;
    let sign = signed.signum();
    let (min_x, max_x) = (p0[0].min(p1[0]).min(p2[0]), p0[0].max(p1[0]).max(p2[0]));
    let x_lo = (min_x - HALF + ONE - 1).div_euclid(ONE).max(0);
    let x_hi = (max_x - HALF).div_euclid(ONE).min(i64::try_from(width).unwrap_or(i64::MAX) - 1);
    if x_lo > x_hi {
        return None;
    }
    columns.clear();
    // A zero term of the sign it has at every covered sample: `b · ±0` with `b ≥ +0`.
    let zero = |difference: f32| 0.0 * difference;
    match varying {
        None => {
            let depth = depth0 + zero(depth_1) + zero(depth_2);
            columns.resize((x_hi - x_lo + 1) as usize + LANES, depth);
        }
        Some((difference, (a, b))) => {
            for x in x_lo..=x_hi {
                // The edge function at the column's sample centres (on a vertical edge, any row's),
                // in the normalised winding: as [`Span::bary`] weighs it.
                let e = sign * edge(a, b, [x * ONE + HALF, a[1]]);
                let weight = (e as f64 * inv_area) as f32;
                columns.push(if depth_2 == 0.0 {
                    depth0 + weight * difference + zero(depth_2)
                } else {
                    depth0 + zero(depth_1) + weight * difference
                });
            }
            columns.resize(columns.len() + LANES, 0.0);
        }
    }
    Some(x_lo)
}

#[cfg(test)]
thread_local! {
    /// Triangles [`fill_polygon_x8`] filled with depths a column, on this thread: for tests that
    /// the views they hold to the reference take that path.
    pub(crate) static FILLED_BY_COLUMN: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

fn fill_triangle_x8(
    buffer: &mut SampleBuffer,
    tri: [&GridVertex<Vec3>; 3],
    id: u32,
    color: Vec3,
    columns: &mut Vec<f32>,
) -> usize {
    if !tri.iter().all(|v| v.depth.is_finite() && v.inv_w.is_finite()) {
        return 0;
    }
    let s = f32x8::splat;
    let (width, height, pitch) = (buffer.width(), buffer.height(), buffer.pitch());
    let depth0 = s(tri[0].depth);
    let (depth_1, depth_2) = (s(tri[1].depth - tri[0].depth), s(tri[2].depth - tri[0].depth));
    // Snapped once for both the columns' depths and the spans; a corner off the grid covers nothing.
    let [Some(p0), Some(p1), Some(p2)] = tri.map(|v| snap(v.pos)) else { return 0 };
    let by_column = column_depths(width, tri, [p0, p1, p2], columns);
    #[cfg(test)]
    FILLED_BY_COLUMN.with(|n| n.set(n.get() + [0, 1][usize::from(by_column.is_some())]));
    let x_lo = by_column.map_or(0, |x| x as usize);
    let columns = &columns[..];
    let eight_colors = [color; LANES];
    let (colors, depths, ids) = buffer.parts_mut();
    let mut written = 0;
    for_each_span_snapped(width, height, [p0, p1, p2], |span| {
        let row = span.y * pitch + span.x; // (a window's rows: its picture's apart)
        // The edge functions only where the depths are not the columns'.
        let mut edges = by_column.is_none().then(|| span.edges_x8());
        for start in (0..span.len).step_by(LANES) {
            let n = (span.len - start).min(LANES);
            let at = row + start..row + start + n;
            // Depth: affine in grid space, relative to vertex 0; LESS (NaN fails; lanes past the span masked).
            let z = match edges.as_mut() {
                Some(edges) => {
                    let b = edges.bary();
                    edges.advance();
                    depth0 + b[1] * depth_1 + b[2] * depth_2
                }
                None => {
                    // x_lo ≤ span.x (the same bounding box), and the table is padded by eight
                    let from = span.x + start - x_lo;
                    f32x8::from(<[f32; LANES]>::try_from(&columns[from..from + LANES]).expect("eight"))
                }
            };
            // Eight depths from the buffer even past the span's end (lanes it masks out), but for the
            // buffer's last few samples.
            let old = match depths.get(row + start..row + start + LANES) {
                Some(eight) => f32x8::from(<[f32; LANES]>::try_from(eight).expect("eight")),
                None => {
                    let mut old = [f32::NEG_INFINITY; LANES];
                    old[..n].copy_from_slice(&depths[at.clone()]);
                    f32x8::from(old)
                }
            };
            let visible = z.simd_lt(old).to_bitmask() & ((1 << n) - 1);
            if visible == 0 {
                continue;
            }
            let z = cast::<f32x8, [f32; LANES]>(z);
            if visible == (1 << LANES) - 1 {
                // Eight visible samples (the common case inside a wall): stored without a branch each.
                let eight = row + start..row + start + LANES;
                colors[eight.clone()].copy_from_slice(&eight_colors);
                depths[eight.clone()].copy_from_slice(&z);
                ids[eight].copy_from_slice(&[id; LANES]);
                written += LANES;
                continue;
            }
            // A part group: its visible lanes one by one, into the group's eight (but for the
            // buffer's last few samples), so that each store is checked against eight, not the buffer.
            let eight = row + start..row + start + LANES;
            if let (Some(c8), Some(d8), Some(i8)) =
                (colors.get_mut(eight.clone()), depths.get_mut(eight.clone()), ids.get_mut(eight))
            {
                let mut left = visible;
                while left != 0 {
                    let lane = left.trailing_zeros() as usize;
                    left &= left - 1;
                    (c8[lane], d8[lane], i8[lane]) = (color, z[lane], id);
                    written += 1;
                }
                continue;
            }
            let mut left = visible;
            while left != 0 {
                let lane = left.trailing_zeros() as usize;
                left &= left - 1;
                let i = row + start + lane;
                (colors[i], depths[i], ids[i]) = (color, z[lane], id);
                written += 1;
            }
        }
    });
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_to_i64_is_rounding_halves_away_from_zero() {
        let mut values =
            vec![0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994];
        values.extend([4503599627370495.5, -4503599627370495.5, 4503599627370497.0, 1e15 + 0.5, -1e15 - 0.5]);
        let mut z = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..100_000 {
            z = z.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let unit = (z >> 11) as f64 / (1u64 << 53) as f64;
            values.push((unit - 0.5) * 2.0 * MAX_COORD as f64 * ONE as f64);
            values.push(((unit * 2000.0).floor() - 1000.0) + 0.5); // halves
        }
        for x in values {
            assert_eq!(round_to_i64(x), x.round() as i64, "{x}");
        }
    }

    fn covered(width: usize, height: usize, tri: [Vec2; 3]) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for_each_sample(width, height, tri, |x, y, _| out.push((x, y)));
        out
    }

    #[test]
    fn a_sample_centre_on_an_edge_belongs_to_the_top_left_triangle_only() {
        // Square [0.5, 2.5]² split along its diagonal; centres on the left/top edges are in, right/bottom out.
        let (a, b, c, d) =
            (Vec2::new(0.5, 0.5), Vec2::new(2.5, 0.5), Vec2::new(2.5, 2.5), Vec2::new(0.5, 2.5));
        let mut all = covered(4, 4, [a, b, c]);
        all.extend(covered(4, 4, [a, c, d]));
        all.sort_unstable();
        assert_eq!(all, [(0, 0), (0, 1), (1, 0), (1, 1)]);
    }

    /// A row's run is solved exactly: a centre one fixed-point unit (1/256 sample) inside a right
    /// edge is covered. The triangle (0, ½), (129/256, ½), (129/256, 129/256) holds the centre of
    /// sample (0, 0) on its top edge (in, by the top-left rule) and a hair inside its right edge.
    #[test]
    fn a_centre_a_hair_inside_a_right_edge_is_covered() {
        let u = 1.0 / 256.0;
        let tri = [Vec2::new(0.0, 0.5), Vec2::new(129.0 * u, 0.5), Vec2::new(129.0 * u, 129.0 * u)];
        assert_eq!(covered(4, 4, tri), [(0, 0)]);
        // one unit further left, the right edge passes through the centre: a right edge's own
        // centres are out
        let on_edge = [Vec2::new(0.0, 0.5), Vec2::new(0.5, 0.5), Vec2::new(0.5, 129.0 * u)];
        assert_eq!(covered(4, 4, on_edge), []);
    }

    /// The eight-lane fill writes what the scalar fill writes with one colour — the same samples,
    /// depths and ids — and both return how many samples they wrote: polygons of 3–5 corners, partly
    /// off the grid, one behind another (its hidden samples are not written, so not counted).
    #[test]
    fn the_eight_lane_fill_writes_and_counts_what_the_scalar_fill_does() {
        let vertex = |x: f32, y: f32, depth: f32, w: f32| GridVertex {
            pos: Vec2::new(x, y),
            depth,
            inv_w: 1.0 / w,
            attrs: Vec3::new(x * 0.01, y * 0.02, depth),
        };
        let polygons = [
            vec![vertex(2.3, 1.7, 0.5, 1.0), vertex(30.9, 4.2, 0.4, 2.0), vertex(11.1, 20.6, 0.6, 3.0)],
            vec![
                vertex(-5.0, -3.0, 0.3, 1.5),
                vertex(25.5, 2.5, 0.3, 1.5),
                vertex(28.0, 17.0, 0.2, 4.0),
                vertex(1.0, 22.0, 0.2, 4.0),
            ],
            // 1/w summing past f32's range, and to zero: the affine weights, in both fills
            vec![
                vertex(3.0, 3.0, 0.05, 3e-39),
                vertex(12.0, 3.0, 0.05, 3e-39),
                vertex(6.0, 12.0, 0.05, 3e-39),
            ],
            vec![
                vertex(20.0, 12.0, 0.04, f32::INFINITY),
                vertex(32.0, 12.0, 0.04, f32::INFINITY),
                vertex(26.0, 18.0, 0.04, f32::INFINITY),
            ],
            vec![
                vertex(10.0, 5.0, 0.1, 1.0),
                vertex(20.0, 6.0, 0.9, 1.0),
                vertex(24.0, 14.0, 0.9, 2.0),
                vertex(15.0, 30.0, 0.1, 2.0),
                vertex(8.0, 12.0, 0.1, 1.0),
            ],
        ];
        let (mut scalar, mut lanes) = (SampleBuffer::new(33, 19), SampleBuffer::new(33, 19));
        scalar.clear(Vec3::ZERO);
        lanes.clear(Vec3::ZERO);
        let mut columns = Vec::new();
        let mut total = 0;
        for (id, polygon) in (0..).zip(&polygons) {
            let before: Vec<u32> = scalar.id().to_vec();
            let color = Vec3::new(0.1 * id as f32, 0.5, 1.0 / (1.0 + id as f32));
            let a = fill_polygon(&mut scalar, polygon, id, |_| color);
            let b = fill_polygon_x8(&mut lanes, polygon, id, color, &mut columns);
            assert_eq!(a, b, "polygon {id}: samples written");
            let changed = scalar.id().iter().zip(&before).filter(|(now, was)| now != was).count();
            assert!(a >= changed && a > 0, "polygon {id}: {a} written, {changed} changed hands");
            total += a;
        }
        assert!(total > 33 * 19 / 2, "the polygons cover much of the grid: {total}");
        // A corner whose depth or 1/w is not finite (either one alone) draws nothing, either way.
        for (depth, w) in [(f32::NAN, 1.0), (0.5, 0.0), (f32::INFINITY, 1.0), (0.5, f32::NAN)] {
            let bad =
                [vertex(1.0, 1.0, 0.05, 1.0), vertex(30.0, 2.0, 0.05, 1.0), vertex(9.0, 18.0, depth, w)];
            assert_eq!(fill_polygon(&mut scalar, &bad, 9, |attrs| attrs), 0, "depth {depth}, w {w}");
            assert_eq!(
                fill_polygon_x8(&mut lanes, &bad, 9, Vec3::ONE, &mut columns),
                0,
                "depth {depth}, w {w}"
            );
        }
        // A corner off the fixed-point grid (beyond it, or not finite) draws nothing either: the
        // eight-lane fill snaps a triangle's corners once, for its columns' depths and its spans.
        for pos in [Vec2::new(3e6, 5.0), Vec2::new(f32::NAN, 5.0), Vec2::new(9.0, f32::INFINITY)] {
            let bad = [
                vertex(1.0, 1.0, 0.05, 1.0),
                vertex(30.0, 2.0, 0.05, 1.0),
                GridVertex { pos, ..vertex(9.0, 18.0, 0.05, 1.0) },
            ];
            assert_eq!(fill_polygon(&mut scalar, &bad, 9, |attrs| attrs), 0, "{pos}");
            assert_eq!(fill_polygon_x8(&mut lanes, &bad, 9, Vec3::ONE, &mut columns), 0, "{pos}");
        }
        assert_eq!(scalar.id(), lanes.id());
        assert_eq!(scalar.depth(), lanes.depth());
        assert_eq!(scalar.color(), lanes.color());
    }

    /// Wall quads as a level view draws them (each end's top and bottom one above the other, at one
    /// depth), the fan started at each corner, either winding, partly off the grid, faced square on
    /// (a −0 among the depth differences too), ends less than a sample apart, and skewed ones whose
    /// ends are not quite vertical: the eight-lane fill, whose fan triangles take their depths a
    /// column where [`column_depths`] finds them a function of the column, writes the scalar fill's
    /// samples, depths and ids bit for bit, one quad over another; and the column path is taken.
    #[test]
    fn depths_by_column_are_the_weighed_depths() {
        let mut state = 0x2545_f491_u64;
        let mut unit = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let (width, height) = (61, 37);
        let (mut scalar, mut lanes) = (SampleBuffer::new(width, height), SampleBuffer::new(width, height));
        scalar.clear(Vec3::ZERO);
        lanes.clear(Vec3::ZERO);
        let mut columns = Vec::new();
        let (mut by_column, mut weighed, mut written) = (0, 0, 0);
        for id in 0..400u32 {
            let xa = unit() * 90.0 - 15.0;
            // sometimes on sample centres: a column whose weight is exactly 0
            let xa = if (id / 4) % 3 == 1 { xa.floor() + 0.5 } else { xa };
            let xb = match id % 5 {
                0 => xa + unit() * 0.9, // ends less than a sample apart
                _ => unit() * 90.0 - 15.0,
            };
            let (za, zb) = match id % 7 {
                0 => (0.5, 0.5),
                1 => (0.0, -0.0),
                2 => (-0.0, 0.0),
                // a −0 corner over a nearer end: where a zero's sign shows in the sum
                3 => (-0.0, -0.5 * unit()),
                _ => (unit(), unit()),
            };
            let skew = if id % 3 == 2 { 0.3 * unit() } else { 0.0 };
            let (ha, hb) = (unit() * 30.0 + 1.0, unit() * 30.0 + 1.0);
            let (ca, cb) = (unit() * 40.0 - 2.0, unit() * 40.0 - 2.0);
            let corner = |x: f32, y: f32, depth: f32| GridVertex {
                pos: Vec2::new(x, y),
                depth,
                inv_w: 1.0,
                attrs: Vec3::ZERO,
            };
            let mut quad = vec![
                corner(xa, ca + ha, za),
                corner(xb, cb + hb, zb),
                corner(xb + skew, cb - hb, zb),
                corner(xa, ca - ha, za),
            ];
            quad.rotate_left(id as usize % 4);
            if id % 2 == 1 {
                quad.reverse();
            }
            for k in 1..3 {
                let tri = [&quad[0], &quad[k], &quad[k + 1]];
                let snapped = tri.map(|v| snap(v.pos).expect("on the grid"));
                match column_depths(width, tri, snapped, &mut columns) {
                    Some(_) => by_column += 1,
                    None => weighed += 1,
                }
            }
            let color = Vec3::new(unit(), unit(), unit());
            let a = fill_polygon(&mut scalar, &quad, id, |_| color);
            let b = fill_polygon_x8(&mut lanes, &quad, id, color, &mut columns);
            assert_eq!(a, b, "quad {id}: samples written");
            written += a;
            let bits = |buffer: &SampleBuffer| buffer.depth().iter().map(|d| d.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&scalar), bits(&lanes), "quad {id}: {quad:?}");
            assert_eq!(scalar.id(), lanes.id(), "quad {id}");
            assert_eq!(scalar.color(), lanes.color(), "quad {id}");
        }
        // A −0 apex above a −0 corner, a nearer end beyond: on the column through the vertical edge
        // (its weight exactly 0) the sum's zeros decide the sign, +0 (either vertex order).
        let corner = |x: f32, y: f32, depth: f32| GridVertex {
            pos: Vec2::new(x, y),
            depth,
            inv_w: 1.0,
            attrs: Vec3::ZERO,
        };
        let (top, bottom, far) =
            (corner(10.5, 5.0, -0.0), corner(10.5, 20.0, -0.0), corner(30.0, 18.0, -0.25));
        for tri in [[top, bottom, far], [top, far, bottom]] {
            let snapped = tri.map(|v| snap(v.pos).expect("on the grid"));
            assert!(column_depths(width, [&tri[0], &tri[1], &tri[2]], snapped, &mut columns).is_some());
            let (mut scalar, mut lanes) =
                (SampleBuffer::new(width, height), SampleBuffer::new(width, height));
            scalar.clear(Vec3::ZERO);
            lanes.clear(Vec3::ZERO);
            fill_triangle(&mut scalar, [&tri[0], &tri[1], &tri[2]], 1, |_| Vec3::ONE);
            fill_polygon_x8(&mut lanes, &tri, 1, Vec3::ONE, &mut columns);
            let bits = |buffer: &SampleBuffer| buffer.depth().iter().map(|d| d.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&scalar), bits(&lanes));
            assert_eq!(lanes.depth()[10 * width + 10].to_bits(), 0, "+0 on the edge's column");
        }
        assert!(by_column > 300 && weighed > 200, "{by_column} triangles by column, {weighed} weighed");
        assert!(written > 2 * width * height, "the quads are seen over much of the grid: {written}");
    }

    /// Eight lanes of weights are the bits of eight single ones, stepped in `f64` (the pipeline's
    /// triangles) or, for a triangle of area 2^53 or more (one far beyond the grid), one by one.
    #[test]
    fn eight_lane_weights_are_the_single_weights() {
        let triangles = [
            [Vec2::new(2.3, 1.7), Vec2::new(30.9, 4.2), Vec2::new(11.1, 20.6)],
            [Vec2::new(-5.0, -3.0), Vec2::new(28.0, 17.0), Vec2::new(25.5, 2.5)],
            [Vec2::new(-9.0e5, -9.0e5), Vec2::new(9.0e5, -8.0e5), Vec2::new(3.0, 9.5e5)],
        ];
        let mut spans = [0; 3];
        for (t, tri) in triangles.into_iter().enumerate() {
            for_each_span(37, 23, tri, |span| {
                spans[t] += 1;
                assert_eq!(span.triangle.exact_in_f64, t < 2, "triangle {t} steps in f64");
                let mut edges = span.edges_x8();
                for start in (0..span.len).step_by(LANES) {
                    let lanes = edges.bary().map(cast::<f32x8, [f32; LANES]>);
                    edges.advance();
                    for lane in 0..(span.len - start).min(LANES) {
                        let single = span.bary(start + lane).map(f32::to_bits);
                        let eight = lanes.map(|weights| weights[lane].to_bits());
                        assert_eq!(eight, single, "triangle {t}, {span:?}, lane {lane}");
                    }
                }
            });
        }
        assert!(spans.iter().all(|&n| n > 10), "every triangle covers rows: {spans:?}");
    }

    /// Attributes of any kind interpolate as `w₀·v₀ + w₁·v₁ + w₂·v₂`, component by component.
    #[test]
    fn varyings_are_weighted_sums_of_the_three_vertices() {
        let v = [[1.0, 10.0], [2.0, 20.0], [4.0, 40.0]];
        assert_eq!(<[f32; 2]>::weighted(v, [0.5, 0.25, 0.25]), [0.5 + 0.5 + 1.0, 5.0 + 5.0 + 10.0]);
        assert_eq!(<[f32; 2]>::weighted(v, [0.0, 0.0, 1.0]), [4.0, 40.0]);
        let w = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(Vec3::weighted([w, w * 2.0, w * 4.0], [0.25, 0.25, 0.5]), w * 2.75);
        let p = Vec2::new(1.0, -1.0);
        assert_eq!(Vec2::weighted([p, p * 3.0, -p], [0.5, 0.5, 1.0]), p);
    }

    #[test]
    fn barycentric_weights_are_in_the_callers_vertex_order() {
        let tri = [Vec2::new(0.5, 0.5), Vec2::new(0.5, 8.5), Vec2::new(8.5, 0.5)];
        for_each_sample(10, 10, tri, |x, y, b| {
            if (x, y) == (0, 0) {
                assert_eq!(b, [1.0, 0.0, 0.0]);
            }
            if (x, y) == (0, 4) {
                assert!((b[1] - 0.5).abs() < 1e-6 && (b[0] - 0.5).abs() < 1e-6);
            }
        });
    }

    #[test]
    fn non_finite_or_huge_vertices_cover_nothing() {
        let ok = Vec2::new(1.0, 1.0);
        for bad in [Vec2::new(f32::NAN, 0.0), Vec2::new(0.0, f32::INFINITY), Vec2::new(3e6, 0.0)] {
            assert!(covered(8, 8, [ok, bad, Vec2::new(5.0, 7.0)]).is_empty());
        }
    }
}
