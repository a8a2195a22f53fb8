//! Samples → [`Frame`] cells: ascii shading ramp, half blocks, quadrants and sextants.
//!
//! Each terminal cell covers `sx × sy` samples ([`Charset::samples_per_cell`]). In truecolor the block
//! charsets pick, per cell, the 2-colour partition of its samples that fits best (least squared error in
//! sRGB) and the block glyph drawing it; in 256 and 16 colours each sample takes the entry of its light
//! ramp ([`ramp_entry`]) first and the cell shows those entries. Without colour, and in ascii
//! at every depth, the floor, the ceiling and the walls each shade with glyphs of their own, by lightness.
//! Ascii overlays the outline layer. Sample bits within a cell are numbered row-major from the top-left:
//! bit `x + sx·y`.

use glam::{Vec3, Vec3A};
use wide::bytemuck::{cast, cast_slice};
use wide::{f32x8, i32x8, u32x8};

use super::raster::LANES;

use super::options::{ASCII_CEILING, ASCII_FLOOR, ASCII_RAMP_LONG, Charset, Ramp, RenderOptions};
use super::palette::{Palette, quantize_srgb8, ramp_entry, ramp_entry_dithered, threshold, xterm_rgb};
use super::samples::{CEILING, FLOOR, SampleBuffer};
use super::shade::{Srgb8Tables, luminance, srgb_to_linear};
use super::sprite::EXIT_ID;
use mazewalk_term::blocks::{HALF, QUAD, sextant_glyph};
use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame, Region};

/// The colourless block-mode ramp of walls (and everything but floor and ceiling), darkest first.
pub(crate) const BLOCK_RAMP: [char; 5] = [' ', '░', '▒', '▓', '█'];
/// The colourless block-mode glyphs of the floor, darkest first: bars at the foot of the cell, lower
/// one eighth, one quarter, three eighths (issue #33: floor, ceiling and walls each their own glyphs).
pub(crate) const FLOOR_BLOCKS: [char; 4] = [' ', '▁', '▂', '▃'];
/// The colourless block-mode glyphs of the ceiling, darkest first: a bar at the top of the cell.
pub(crate) const CEILING_BLOCKS: [char; 2] = [' ', '▔'];

/// The block glyph of `charset` for a sample mask (see the bit order in the module docs); `ascii` has
/// none and gives `█` or ` `.
#[must_use]
pub fn block_glyph(charset: Charset, mask: u8) -> char {
    match charset {
        Charset::Ascii => HALF[usize::from(mask & 1) * 3],
        Charset::Half => HALF[usize::from(mask & 3)],
        Charset::Quad => QUAD[usize::from(mask & 15)],
        Charset::Sextant => sextant_glyph(mask),
    }
}

/// Converts `samples` to the cells of `region` in `frame`: the region is as many cells as the samples
/// fill (`samples.width() / sx × samples.height() / sy`); the rest of the frame is left alone.
///
/// Ascii overlays the outline layer (the block charsets draw edges with their shapes) on glyphs by
/// surface (the samples' coverage ids): walls on the ramp of `options.ramp` ([`ASCII_RAMP`] or
/// [`ASCII_RAMP_LONG`], less the floor's and the ceiling's glyphs), the floor on [`ASCII_FLOOR`], the
/// ceiling on [`ASCII_CEILING`]. With [`ColorDepth::None`] every colour is [`Color::Default`] and a block
/// cell is the glyph of the surface most of its samples show: [`BLOCK_RAMP`] for walls,
/// [`FLOOR_BLOCKS`], [`CEILING_BLOCKS`]. Each ramp is indexed by lightness stretched over the range its
/// surface spans in a maze scene ([`RAMP_BOTTOM`]–[`RAMP_TOP`], [`FLOOR_RANGE`], [`CEILING_RANGE`]).
/// With [`ColorDepth::Ansi16`] and [`ColorDepth::Ansi256`] each sample takes its light ramp's entry
/// ([`ramp_entry`]; with `options.dither`, [`ramp_entry_dithered`] by the samples'
/// screen-anchored [`threshold`]s, block charsets only), then the cell shows its samples' entries: a
/// half-block cell is exactly its two samples, a quadrant or sextant cell with more than two entries
/// is the best split of them, each side in its most frequent entry.
///
/// [`ASCII_RAMP`]: super::options::ASCII_RAMP
/// # Panics
/// If `region` is not inside `frame` or not the samples' size in cells.
pub fn to_frame(samples: &SampleBuffer, options: &RenderOptions, frame: &mut Frame, region: Region) {
    to_frame_faced(samples, options, frame, region, &[]);
}

/// [`to_frame`] knowing, by wall id, which walls are seen square on (`faced`, from the pipeline: see
/// [`Renderer`](crate::Renderer)): in ascii with the short ramp, a wall seen square on takes its
/// glyph from [`ASCII_FACED`] and one along the view from [`ASCII_SIDE`], each by lightness, so a
/// wall faced through a side opening reads apart from the side walls beside it at any distance
/// (issue #39). Ids past `faced` (figures, or an empty `faced`) take the ramp, as in [`to_frame`].
pub(crate) fn to_frame_faced(
    samples: &SampleBuffer,
    options: &RenderOptions,
    frame: &mut Frame,
    region: Region,
    faced: &[bool],
) {
    let RenderOptions { charset, color_depth: depth, dither, ramp, .. } = *options;
    let (sx, sy) = charset.samples_per_cell();
    assert_eq!(
        (samples.width() / sx, samples.height() / sy),
        (region.cols, region.rows),
        "the region is not the samples' size in cells"
    );
    match charset {
        Charset::Ascii => {
            let tables = Srgb8Tables::get();
            // One loop per depth (the depth is the same for every cell); truecolor and no colour have
            // nothing to quantize.
            let srgb = |color: Vec3| tables.encode3(color);
            let to = (frame, region);
            match depth {
                ColorDepth::None => ascii_cells(samples, ramp, faced, to, |_, _| Color::Default),
                ColorDepth::TrueColor => ascii_cells(samples, ramp, faced, to, |_, color| {
                    let [r, g, b] = srgb(color);
                    Color::Rgb(r, g, b)
                }),
                ColorDepth::Ansi16 | ColorDepth::Ansi256 => {
                    // Each sample's entry, as `palette::picture_color` gives it.
                    let palette = Palette::of(depth).expect("a palette at 16 and 256 colours");
                    let entries = sample_entries(samples, palette, region.cols, region.rows);
                    ascii_cells(samples, ramp, faced, to, |at, _| Color::Indexed(entries[at]));
                }
            }
        }
        Charset::Half if depth == ColorDepth::TrueColor => half_truecolor(samples, frame, region),
        Charset::Half => block_cells::<1, 2>(samples, charset, depth, dither, frame, region),
        Charset::Quad => block_cells::<2, 2>(samples, charset, depth, dither, frame, region),
        Charset::Sextant => block_cells::<2, 3>(samples, charset, depth, dither, frame, region),
    }
}

/// [`to_frame`] for half blocks in truecolor, the default: each cell is its two samples exactly (the top
/// one the ink of `▀`, the bottom one the background; one colour is a space), what [`block_cells`] gives.
/// A sample with the same bits as the one before it in its sample row, or as the one above it, takes
/// that one's codes without encoding (the same bits, the same codes); the cell's glyph follows from
/// its codes without a branch (whether a cell holds one colour or two is a coin toss on a textured
/// floor: a branch there is mispredicted often).
fn half_truecolor(samples: &SampleBuffer, frame: &mut Frame, region: Region) {
    let (width, color, cols) = (samples.width(), samples.color(), region.cols);
    let tables = Srgb8Tables::get();
    // The codes of the sample row above the cells' top row (the last cell row's bottom samples).
    let mut above_codes = vec![[0u8; 3]; cols];
    for (row, cells) in frame.region_rows_mut(region).enumerate() {
        let top = &color[2 * row * width..][..cols];
        let bottom = &color[(2 * row + 1) * width..][..cols];
        // The sample row above the top one: none above the first.
        let above = row.checked_sub(1).map(|_| &color[(2 * row - 1) * width..][..cols]);
        let (Some(first_top), Some(first_bottom)) = (top.first(), bottom.first()) else { continue };
        // The last top and bottom samples and their codes (to start: the first cell's own).
        let mut last_top = (first_top, tables.encode3(*first_top));
        let mut last_bottom = (first_bottom, tables.encode3(*first_bottom));
        for x in 0..cols {
            let (t, b) = (&top[x], &bottom[x]);
            if !same_bits(t, last_top.0) {
                let codes = match above {
                    Some(above) if same_bits(&above[x], t) => above_codes[x],
                    _ => tables.encode3(*t),
                };
                last_top = (t, codes);
            }
            if !same_bits(b, last_bottom.0) {
                let codes = if same_bits(b, t) { last_top.1 } else { tables.encode3(*b) };
                last_bottom = (b, codes);
            }
            let ([r, g, bl], [r2, g2, b2]) = (last_top.1, last_bottom.1);
            above_codes[x] = last_bottom.1;
            let ch = HALF[usize::from(last_top.1 != last_bottom.1)];
            cells[x] = Cell { ch, fg: Color::Rgb(r, g, bl), bg: Color::Rgb(r2, g2, b2) };
        }
    }
}

/// [`to_frame`] for a block charset of `SX × SY` samples per cell (the shape as constants, so the
/// per-cell gathering unrolls).
fn block_cells<const SX: usize, const SY: usize>(
    samples: &SampleBuffer,
    charset: Charset,
    depth: ColorDepth,
    dither: bool,
    frame: &mut Frame,
    region: Region,
) {
    let palette = Palette::of(depth);
    if let (Some(palette), false) = (palette, dither) {
        return palette_cells::<SX, SY>(samples, charset, palette, frame, region);
    }
    let (width, color) = (samples.width(), samples.color());
    let cols = region.cols;
    let tables = Srgb8Tables::get();
    let ids = samples.id();
    let block_ramps = SurfaceRamps::new(&BLOCK_RAMP, &FLOOR_BLOCKS, &CEILING_BLOCKS);
    let mut indices = [0u8; 6];
    for (row, cells) in frame.region_rows_mut(region).enumerate() {
        // The cell's samples in bit order: row-major from its top-left (sample k at (k % SX, k / SX)).
        let rows: [&[Vec3]; SY] = std::array::from_fn(|dy| {
            let start = (row * SY + dy) * width;
            &color[start..start + cols * SX]
        });
        for (col, cell) in cells.iter_mut().enumerate() {
            *cell = if depth == ColorDepth::None {
                // The surface most of the cell's samples show (a wall on a tie), in their mean colour.
                let mut sums = [(Vec3::ZERO, 0usize); 3];
                for (dy, line) in rows.iter().enumerate() {
                    let row_ids = &ids[(row * SY + dy) * width..];
                    for dx in 0..SX {
                        let x = col * SX + dx;
                        let sum = &mut sums[Surface::of(row_ids[x]) as usize];
                        *sum = (sum.0 + line[x], sum.1 + 1);
                    }
                }
                let surface = [Surface::Wall, Surface::Floor, Surface::Ceiling]
                    .into_iter()
                    .rev()
                    .max_by_key(|&s| sums[s as usize].1)
                    .unwrap_or(Surface::Wall);
                let (sum, n) = sums[surface as usize];
                Cell::plain(block_ramps.glyph(surface, sum / n.max(1) as f32))
            } else if let Some(palette) = palette {
                // Each sample its ramp's entry at its threshold, then the cell shows those entries.
                for (dy, line) in rows.iter().enumerate() {
                    for dx in 0..SX {
                        let (x, y) = (col * SX + dx, row * SY + dy);
                        indices[dy * SX + dx] = ramp_entry_dithered(line[x], palette, threshold(x, y));
                    }
                }
                indexed_cell(&indices[..SX * SY], charset)
            } else {
                let mut cell_samples = [Vec3A::ZERO; 6];
                for (dy, line) in rows.iter().enumerate() {
                    for dx in 0..SX {
                        cell_samples[dy * SX + dx] = non_negative(line[col * SX + dx]);
                    }
                }
                let linear = &cell_samples[..SX * SY];
                fitted_cell(tables, linear, code_range(tables, linear), charset, depth)
            };
        }
    }
}

/// [`block_cells`] in 256 or 16 colours, undithered: each sample its light ramp's entry
/// ([`ramp_entry`], [`sample_entries`]), then the cell shows those entries ([`indexed_cell`]). Half
/// blocks by [`half_palette`], straight from the samples: always the top entry on the bottom one.
fn palette_cells<const SX: usize, const SY: usize>(
    samples: &SampleBuffer,
    charset: Charset,
    palette: Palette,
    frame: &mut Frame,
    region: Region,
) {
    if SX * SY == 2 {
        return half_palette(samples, palette, frame, region);
    }
    let (used, rows) = (region.cols * SX, region.rows * SY);
    let entries = sample_entries(samples, palette, used, rows);
    let mut indices = [0u8; 6];
    for (row, cells) in frame.region_rows_mut(region).enumerate() {
        // The cell's samples in bit order: row-major from its top-left (sample k at (k % SX, k / SX)).
        let lines: [&[u8]; SY] = std::array::from_fn(|dy| &entries[(row * SY + dy) * used..][..used]);
        for (col, cell) in cells.iter_mut().enumerate() {
            for (dy, line) in lines.iter().enumerate() {
                indices[dy * SX..][..SX].copy_from_slice(&line[col * SX..][..SX]);
            }
            *cell = indexed_cell(&indices[..SX * SY], charset);
        }
    }
}

/// [`palette_cells`] for half blocks: each cell its top sample's [`ramp_entry`] on its bottom one's
/// (one entry: a blank in it), what [`indexed_cell`] gives two entries, without a row of entries
/// in between.
///
/// A sample with the same bits as the one before it in its sample row, or as the one above it, takes
/// that one's entry without a lookup (the same bits, the same entry), as [`sample_entries`] does; and
/// a run of cells each of whose two samples has the bits of the cell's before it (a wall of one flat
/// colour, a floor's square, the fog) is the cell before it again, [`LANES`] cells at a time: their
/// 48 sample words compared at once with the run shifted by a cell.
fn half_palette(samples: &SampleBuffer, palette: Palette, frame: &mut Frame, region: Region) {
    let (width, color, cols) = (samples.width(), samples.color(), region.cols);
    let words: &[u32] = cast_slice(color);
    // The entries of the sample row above the cells' top row (the last cell row's bottom samples).
    let mut above_entries = vec![0u8; cols];
    for (row, cells) in frame.region_rows_mut(region).enumerate() {
        let (top_at, bottom_at) = (2 * row * width, (2 * row + 1) * width);
        let (top, bottom) = (&color[top_at..][..cols], &color[bottom_at..][..cols]);
        let (top_words, bottom_words) =
            (&words[3 * top_at..][..3 * cols], &words[3 * bottom_at..][..3 * cols]);
        // The sample row above the top one: none above the first.
        let above = row.checked_sub(1).map(|_| &color[(2 * row - 1) * width..][..cols]);
        let (Some(first_top), Some(first_bottom)) = (top.first(), bottom.first()) else { continue };
        // The last top and bottom samples and their entries (to start: the first cell's own).
        let first_top_entry = match above {
            Some(above) if same_bits(&above[0], first_top) => above_entries[0],
            _ => lookup(*first_top, palette),
        };
        let first_bottom_entry =
            if same_bits(first_bottom, first_top) { first_top_entry } else { lookup(*first_bottom, palette) };
        let mut last_top = (first_top, first_top_entry);
        let mut last_bottom = (first_bottom, first_bottom_entry);
        // Cells before this one go one by one: a run was looked for and not found (cells that
        // change often, a checker's far squares: the run is looked for again a group later).
        let (mut x, mut singles_to) = (0, 1);
        while x < cols {
            if x >= singles_to
                && x + LANES <= cols
                && same_as_before(top_words, x)
                && same_as_before(bottom_words, x)
            {
                // Cells x..x + 8: each sample the bits of the one before it, so each cell the one
                // before it (and the last samples' bits and entries stay those of x − 1).
                #[cfg(test)]
                HALF_CELLS_BY_RUNS.with(|n| n.set(n.get() + LANES));
                let before = cells[x - 1];
                cells[x..x + LANES].fill(before);
                above_entries[x..x + LANES].fill(last_bottom.1);
                x += LANES;
                continue;
            }
            if x >= singles_to {
                singles_to = x + LANES;
            }
            let (t, b) = (&top[x], &bottom[x]);
            if !same_bits(t, last_top.0) {
                let entry = match above {
                    Some(above) if same_bits(&above[x], t) => above_entries[x],
                    _ => lookup(*t, palette),
                };
                last_top = (t, entry);
            }
            if !same_bits(b, last_bottom.0) {
                let entry = if same_bits(b, t) { last_top.1 } else { lookup(*b, palette) };
                last_bottom = (b, entry);
            }
            let (ink, paper) = (last_top.1, last_bottom.1);
            above_entries[x] = paper;
            let ch = HALF[usize::from(ink != paper)]; // one entry: a blank in it (`solid`)
            cells[x] = Cell { ch, fg: Color::Indexed(ink), bg: Color::Indexed(paper) };
            x += 1;
        }
    }
}

#[cfg(test)]
thread_local! {
    /// Cells [`half_palette`] copied from the cell before them eight at a time, on this thread: for
    /// the test that holds the runs to the cells' definition.
    static HALF_CELLS_BY_RUNS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Whether samples `x..x + LANES` of a row (`words`: its samples' colours as bits, three a sample)
/// each have the bits of the sample before it; `x ≥ 1` and `x + LANES` within the row.
#[inline(always)]
fn same_as_before(words: &[u32], x: usize) -> bool {
    let lanes = |at: usize| u32x8::from(<[u32; LANES]>::try_from(&words[at..at + LANES]).expect("eight"));
    let (here, before) = (3 * x, 3 * x - 3);
    let equal = lanes(here).simd_eq(lanes(before))
        & lanes(here + LANES).simd_eq(lanes(before + LANES))
        & lanes(here + 2 * LANES).simd_eq(lanes(before + 2 * LANES));
    equal.all()
}

/// The [`ramp_entry`] of each sample of the first `used` columns of the first `rows` rows of
/// `samples`, row-major (`used` a row).
///
/// Neighbouring samples often share a colour: along a row, the floor's and the ceiling's squares; down
/// a column, a wall in a level view (its light changes only with depth). A sample whose bits are those
/// of the sample before it in its row, or of the one above it, takes that one's entry without a
/// lookup (the same bits, the same entry); equal runs along a row cost a comparison a sample.
fn sample_entries(samples: &SampleBuffer, palette: Palette, used: usize, rows: usize) -> Vec<u8> {
    let (width, color) = (samples.width(), samples.color());
    let mut entries = vec![0u8; used * rows];
    for y in 0..rows {
        let line = &color[y * width..][..used];
        let (done, here) = entries.split_at_mut(y * used);
        let here = &mut here[..used];
        // The row above: its samples and their entries (none above the first row).
        let above = y.checked_sub(1).map(|a| (&color[a * width..][..used], &done[a * used..][..used]));
        let entry = |x: usize| match above {
            Some((colors, entries)) if same_bits(&colors[x], &line[x]) => entries[x],
            _ => lookup(line[x], palette),
        };
        let Some(first) = line.first() else { continue };
        let (mut last, mut last_entry) = (first, entry(0));
        here[0] = last_entry;
        for x in 1..used {
            let sample = &line[x];
            if !same_bits(sample, last) {
                (last, last_entry) = (sample, entry(x));
            }
            here[x] = last_entry;
        }
    }
    entries
}

/// [`ramp_entry`], out of line: the loops above keep their registers for the common case.
#[inline(never)]
fn lookup(linear: Vec3, palette: Palette) -> u8 {
    ramp_entry(linear, palette)
}

/// Whether two samples are the same bits (so their entries are the same).
#[inline(always)]
fn same_bits(a: &Vec3, b: &Vec3) -> bool {
    let differ = |a: f32, b: f32| a.to_bits() ^ b.to_bits();
    differ(a.x, b.x) | differ(a.y, b.y) | differ(a.z, b.z) == 0
}

/// The lightness (sRGB-encoded luminance) a wall ramp starts at: darker is its first glyph (fog, the
/// far distance). See [`RAMP_TOP`].
pub const RAMP_BOTTOM: f32 = 0.05;
/// The lightness a wall ramp ends at: lighter is its last glyph. A lit wall near the viewer is about
/// 0.5, one six cells away about 0.25, so walls span the ramp from near to far.
pub const RAMP_TOP: f32 = 0.6;
/// The lightness range of the floor's glyphs ([`FLOOR_BLOCKS`], [`ASCII_FLOOR`]): from the far floor
/// (about 0.15) to the floor at the viewer's feet (about 0.4).
pub(crate) const FLOOR_RANGE: (f32, f32) = (0.1, 0.4);
/// The lightness range of the ceiling's glyphs ([`CEILING_BLOCKS`], [`ASCII_CEILING`]): the ceiling is
/// darker than the floor, marked where it is near.
pub(crate) const CEILING_RANGE: (f32, f32) = (0.02, 0.2);

/// Which glyphs a sample takes without colour: the floor's, the ceiling's, or a wall's (anything else:
/// walls, figures, the exit's beacon, the fog).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Surface {
    Wall,
    Floor,
    Ceiling,
}

impl Surface {
    fn of(id: u32) -> Surface {
        match id {
            FLOOR => Surface::Floor,
            CEILING => Surface::Ceiling,
            _ => Surface::Wall,
        }
    }
}

/// The glyph ramps of the three surfaces, and where their steps lie.
struct SurfaceRamps<'a> {
    glyphs: [&'a [char]; 3],
    steps: [RampSteps; 3],
}

impl<'a> SurfaceRamps<'a> {
    fn new(wall: &'a [char], floor: &'a [char], ceiling: &'a [char]) -> SurfaceRamps<'a> {
        SurfaceRamps {
            glyphs: [wall, floor, ceiling],
            steps: [
                RampSteps::new(wall.len(), (RAMP_BOTTOM, RAMP_TOP)),
                RampSteps::new(floor.len(), FLOOR_RANGE),
                RampSteps::new(ceiling.len(), CEILING_RANGE),
            ],
        }
    }

    /// The glyph of a linear colour on `surface`.
    #[inline]
    fn glyph(&self, surface: Surface, color: Vec3) -> char {
        let k = surface as usize;
        self.glyphs[k][self.steps[k].index(color)]
    }
}

struct RampSteps {
    /// `up[k]`: the luminance glyph `k + 1` starts at; the first `len − 1` are used.
    up: [f32; ASCII_RAMP_LONG.len() - 1],
    /// The first sixteen of `up`, in lanes (every ramp but the long one fits).
    up16: [f32x8; 2],
    len: usize,
}

impl RampSteps {
    /// # Panics
    /// If `len` is 0 or longer than the longest ramp.
    fn new(len: usize, (bottom, top): (f32, f32)) -> RampSteps {
        assert!((1..=ASCII_RAMP_LONG.len()).contains(&len), "a ramp of {len} glyphs");
        let mut up = [f32::INFINITY; ASCII_RAMP_LONG.len() - 1];
        for (k, up) in up.iter_mut().enumerate().take(len - 1) {
            let stretched = (k as f32 + 0.5) / (len - 1) as f32;
            *up = srgb_to_linear(bottom + stretched * (top - bottom));
        }
        let lanes = |from: usize| f32x8::from(<[f32; 8]>::try_from(&up[from..from + 8]).expect("eight"));
        RampSteps { up, up16: [lanes(0), lanes(8)], len }
    }

    /// The ramp index for a linear colour (NaN: 0, the darkest).
    #[inline]
    fn index(&self, color: Vec3) -> usize {
        let luminance = luminance(color);
        if self.len <= 17 {
            // No branch and no loop: sixteen compares in lanes, each -1 where the step is passed; the
            // steps past the ramp's are +∞, which only +∞ reaches, hence the `min`.
            let l = f32x8::splat(luminance);
            let passed = |up: f32x8| cast::<f32x8, i32x8>(l.simd_ge(up));
            let above = -(passed(self.up16[0]) + passed(self.up16[1])).reduce_add();
            (above as usize).min(self.len - 1)
        } else {
            self.up[..self.len - 1].partition_point(|&step| luminance >= step)
        }
    }
}

/// The exit beacon's glyphs in ascii (its green bands, its white ones): left out of the walls' ramp,
/// so nothing but the beacon looks like it (issue #39).
pub(crate) const BEACON_GLYPHS: [char; 2] = ['$', '!'];

/// The ascii glyphs of a wall seen square on (a wall across the way: the end of a corridor, the far
/// side of a side opening), darkest first: full, level strokes. With the short ramp only; see
/// [`to_frame_faced`].
pub(crate) const ASCII_FACED: [char; 5] = [' ', '=', '#', '%', '@'];
/// The ascii glyphs of a wall seen along the view (a corridor's side walls), darkest first: lighter,
/// broken strokes, none of them a glyph of [`ASCII_FACED`], of the outlines (`|` `-` `/` `\`, the
/// seam's `:`), of the floor, the ceiling or the beacon.
pub(crate) const ASCII_SIDE: [char; 5] = [' ', '.', ';', '+', '*'];

/// [`to_frame`] for the ascii charset, one sample per cell: its outline glyph or its surface's ramp
/// glyph (walls: `ramp` without the floor's and the ceiling's glyphs; with the short ramp, a wall
/// whose id `faced` knows, [`ASCII_FACED`] or [`ASCII_SIDE`]), inked in `ink(at, colour)` of its
/// place in the samples (row-major) and its linear colour (a blank has no ink to colour).
fn ascii_cells(
    samples: &SampleBuffer,
    ramp: Ramp,
    faced: &[bool],
    (frame, region): (&mut Frame, Region),
    ink: impl Fn(usize, Vec3) -> Color,
) {
    let (color, outline, ids) = (samples.color(), samples.outline(), samples.id());
    let mut wall = [' '; ASCII_RAMP_LONG.len()];
    let mut len = 0;
    for &g in ramp.glyphs() {
        let others = [&ASCII_FLOOR[..], &ASCII_CEILING[..], &BEACON_GLYPHS[..]];
        if g == ' ' || !others.iter().any(|glyphs| glyphs.contains(&g)) {
            (wall[len], len) = (g, len + 1);
        }
    }
    let ramps = SurfaceRamps::new(&wall[..len], &ASCII_FLOOR, &ASCII_CEILING);
    // (the two families: with the short ramp only; `faced` empty otherwise)
    let faced = if ramp == Ramp::Short { faced } else { &[] };
    let range = (RAMP_BOTTOM, RAMP_TOP);
    let (faced_steps, side_steps) =
        (RampSteps::new(ASCII_FACED.len(), range), RampSteps::new(ASCII_SIDE.len(), range));
    let wall_glyph = |id: u32, color: Vec3| match faced.get(id as usize) {
        Some(true) => ASCII_FACED[faced_steps.index(color)],
        Some(false) => ASCII_SIDE[side_steps.index(color)],
        None => ramps.glyph(Surface::of(id), color),
    };
    for (row, cells) in frame.region_rows_mut(region).enumerate() {
        let at = row * region.cols..(row + 1) * region.cols;
        let places = at.clone();
        for (((cell, (&color, &id)), outline), at) in
            cells.iter_mut().zip(color[at.clone()].iter().zip(&ids[at.clone()])).zip(&outline[at]).zip(places)
        {
            let ch = outline.unwrap_or_else(|| match id {
                // The beacon's bands: green `$`, white `!`, glyphs no wall is drawn with.
                EXIT_ID if color.y > 2.0 * color.x => BEACON_GLYPHS[0],
                EXIT_ID => BEACON_GLYPHS[1],
                _ => wall_glyph(id, color),
            });
            *cell = if ch == ' ' {
                Cell::plain(' ')
            } else {
                Cell { ch, fg: ink(at, color), bg: Color::Default }
            };
        }
    }
}

/// A sample in a SIMD register with NaN and negative channels as 0, which encode alike
/// ([`Srgb8Tables::encode`]): for [`code_range`], [`sample_codes`] and [`flat_mean`].
#[inline(always)]
fn non_negative(linear: Vec3) -> Vec3A {
    Vec3A::from(linear).max(Vec3A::ZERO) // `maxps` keeps its second operand where the first is NaN
}

/// The least and the greatest 8-bit sRGB code, per channel, of a cell's [`non_negative`] samples:
/// two encodings a channel, whatever the number of samples (the code is monotone in the value).
#[inline(always)]
fn code_range(tables: &Srgb8Tables, linear: &[Vec3A]) -> ([u8; 3], [u8; 3]) {
    let (low, high) = linear[1..].iter().fold((linear[0], linear[0]), |(l, h), &s| (l.min(s), h.max(s)));
    (low.to_array().map(|c| tables.encode(c)), high.to_array().map(|c| tables.encode(c)))
}

/// The 8-bit sRGB codes of a cell's samples whose channels' codes lie in `range` ([`code_range`]):
/// where a channel's codes are at most one apart (nine cells in ten), each sample's is its low code or
/// the next, one comparison; elsewhere each sample is encoded.
#[inline(always)]
fn sample_codes(
    tables: &Srgb8Tables,
    linear: &[Vec3A],
    (low, high): ([u8; 3], [u8; 3]),
    out: &mut [[u8; 3]],
) {
    for c in 0..3 {
        if high[c] - low[c] <= 1 {
            let next = usize::from(low[c]) + 1;
            for (out, sample) in out.iter_mut().zip(linear) {
                out[c] = low[c] + u8::from(tables.reaches(sample[c], next));
            }
        } else {
            for (out, sample) in out.iter_mut().zip(linear) {
                out[c] = tables.encode(sample[c]);
            }
        }
    }
}

/// The rounded mean of the 8-bit sRGB codes of a cell's samples whose channels each lie within one
/// code of `low` ([`code_range`]): `low` per sample, plus one for each at or past the next code.
#[inline(always)]
fn flat_mean(tables: &Srgb8Tables, linear: &[Vec3A], low: [u8; 3]) -> [u8; 3] {
    let n = linear.len() as i32;
    let sum = std::array::from_fn(|c| {
        let next = usize::from(low[c]) + 1;
        n * i32::from(low[c]) + linear.iter().map(|s| i32::from(tables.reaches(s[c], next))).sum::<i32>()
    });
    rounded_mean(sum, n)
}

/// The largest difference in any channel between two of a cell's samples (8-bit sRGB), from their
/// [`code_range`].
#[inline(always)]
fn spread((low, high): ([u8; 3], [u8; 3])) -> u8 {
    (0..3).map(|c| high[c] - low[c]).max().unwrap_or(0)
}

/// At most this [`spread`], a quadrant or sextant cell is drawn in its samples' mean colour.
const FLAT_SPREAD: u8 = 1;

/// A two-colour split of a cell's samples: the samples in `mask` are ink, the rest background.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Split {
    mask: u8,
    ink: [u8; 3],
    paper: [u8; 3],
}

/// `360 / (k · (n − k))` for a cell of `n` samples (up to 6) split `k` to `n − k`: the weight that makes
/// [`best_partition`]'s fractions integers with one denominator.
const SPLIT_WEIGHT: [[i64; 6]; 7] = {
    let mut weight = [[0; 6]; 7];
    let mut n = 2;
    while n <= 6 {
        let mut k = 1;
        while k < n {
            weight[n][k] = 360 / (k * (n - k)) as i64;
            assert!(weight[n][k] * (k * (n - k)) as i64 == 360);
            k += 1;
        }
        n += 1;
    }
    weight
};

/// The 2-colour partition of a cell's 8-bit sRGB samples with the least squared error, each side drawn
/// in its (rounded) mean. Only masks without the last sample are tried (a mask and its complement are the
/// same split), so the last sample is always background and mask 0 means one colour.
///
/// Exact, in integers: the error of a split is the samples' total scatter minus the scatter between the
/// two means, so the best split has the most between-means scatter, `|n·S_ink − n_ink·S|² ⁄ (n · n_ink ·
/// n_paper)` with `S` the sum of all `n` samples and `S_ink` that of the `n_ink` ink samples. Ties keep
/// the smaller mask.
fn best_partition(srgb: &[[u8; 3]]) -> Split {
    if let [a, b] = *srgb {
        return Split { mask: u8::from(a != b), ink: a, paper: b }; // half blocks: each sample its own side
    }
    let n = srgb.len();
    debug_assert!((1..=6).contains(&n), "{n} samples");
    if let Some(split) = two_colours(srgb) {
        return split; // the common case (flat or 8-bit-banded areas, wall edges): a split with no error
    }
    let samples: [[i32; 3]; 6] = std::array::from_fn(|k| srgb.get(k).map_or([0; 3], |s| s.map(i32::from)));
    let sum_of = |mask: usize| {
        let mut sum = [0; 3];
        for (k, s) in samples.iter().enumerate() {
            if mask >> k & 1 == 1 {
                (0..3).for_each(|c| sum[c] += s[c]);
            }
        }
        sum
    };
    let total = sum_of((1 << n) - 1);
    // A split's score is |n·ink − n_ink·total|² / (n_ink·(n − n_ink)) (the squared distance between the
    // two sides' means, weighted by their sizes: the most that a split's error falls below no split's).
    // With each sample taken as n·s − total (n times its offset from the mean), n·ink − n_ink·total is
    // the ink's sum of those: exact integers, one addition a channel per mask.
    let centred: [[i32; 3]; 6] =
        std::array::from_fn(|k| std::array::from_fn(|c| n as i32 * samples[k][c] - total[c]));
    // Every mask in ascending order, each one's ink sum and count from the mask without its lowest
    // sample's bit (found before it): one addition a channel per mask. Strictly greater scores win, so
    // of equal ones the smaller mask stays. The fraction's denominator n_ink·(n − n_ink) divides 360
    // for every n ≤ 6, so the score is compared as `numerator · 360 / denominator` in integers.
    let mut ink_sums = [[0i32; 3]; 32];
    let mut counts = [0usize; 32];
    let (mut best, mut best_score) = (0usize, 0i64);
    for mask in 1..1usize << (n - 1) {
        let (rest, k) = (mask & (mask - 1), mask.trailing_zeros() as usize);
        let ink: [i32; 3] = std::array::from_fn(|c| ink_sums[rest][c] + centred[k][c]);
        let n_ink = counts[rest] + 1;
        (ink_sums[mask], counts[mask]) = (ink, n_ink);
        // At most 3 · (6 · 5 · 255)² · 120 < 2⁶³.
        let score = i64::from(ink[0] * ink[0] + ink[1] * ink[1] + ink[2] * ink[2]) * SPLIT_WEIGHT[n][n_ink];
        if score > best_score {
            (best, best_score) = (mask, score);
        }
    }
    let n_ink = best.count_ones() as i32;
    let ink_sum = sum_of(best);
    let paper = rounded_mean([0, 1, 2].map(|c| total[c] - ink_sum[c]), n as i32 - n_ink);
    let ink = if n_ink == 0 { paper } else { rounded_mean(ink_sum, n_ink) };
    Split { mask: best as u8, ink, paper }
}

/// The split of a cell of at most two distinct colours (the last sample's is the background): the
/// only split with no error, so the one [`best_partition`]'s search would find; `None` for three or more.
fn two_colours(srgb: &[[u8; 3]]) -> Option<Split> {
    let (&paper, rest) = srgb.split_last()?;
    let mut ink = paper;
    let mut mask = 0u8;
    for (k, &s) in rest.iter().enumerate() {
        if s != paper {
            if mask != 0 && s != ink {
                return None;
            }
            (ink, mask) = (s, mask | 1 << k);
        }
    }
    Some(Split { mask, ink, paper })
}

/// `sum / n` per channel, rounded to nearest (halves up), for sums of `n` (1 to 6) 8-bit values.
fn rounded_mean(sum: [i32; 3], n: i32) -> [u8; 3] {
    // A constant divisor per arm: multiplications, where a variable one costs three integer divisions.
    fn by<const N: i32>(sum: [i32; 3]) -> [u8; 3] {
        sum.map(|s| ((2 * s + N) / (2 * N)) as u8)
    }
    match n {
        1 => by::<1>(sum),
        2 => by::<2>(sum),
        3 => by::<3>(sum),
        4 => by::<4>(sum),
        5 => by::<5>(sum),
        _ => by::<6>(sum),
    }
}

fn solid(color: Color) -> Cell {
    Cell { ch: ' ', fg: color, bg: color } // ink unused: same as the background so equal cells compare equal
}

/// A block cell in its samples' colours, undithered (`linear`: the cell's [`non_negative`] samples in
/// bit order, `range` their [`code_range`]). A quadrant or sextant cell whose samples are all within
/// [`FLAT_SPREAD`] of each other is their mean colour: within a step of every sample, as the encoder's
/// default tolerance; it saves the split's search (a third of a sextant frame), and sends a blank
/// instead of a glyph in two colours. Any other cell is its [`block_cell`].
#[inline(always)] // into each `block_cells` shape: its cell comes back in registers, not through memory
fn fitted_cell(
    tables: &Srgb8Tables,
    linear: &[Vec3A],
    range: ([u8; 3], [u8; 3]),
    charset: Charset,
    depth: ColorDepth,
) -> Cell {
    if linear.len() > 2 && spread(range) <= FLAT_SPREAD {
        return solid(quantize_srgb8(flat_mean(tables, linear, range.0), depth));
    }
    let mut srgb = [[0u8; 3]; 6];
    sample_codes(tables, linear, range, &mut srgb);
    block_cell(&srgb[..linear.len()], charset, depth)
}

/// One block cell from its samples (8-bit sRGB), in bit order: the best two-colour split, each side
/// quantized to `depth`; a blank where the two come out the same.
#[inline(always)]
fn block_cell(srgb: &[[u8; 3]], charset: Charset, depth: ColorDepth) -> Cell {
    let Split { mask, ink, paper } = best_partition(srgb);
    let (fg, bg) = (quantize_srgb8(ink, depth), quantize_srgb8(paper, depth));
    if mask == 0 || fg == bg {
        return solid(bg);
    }
    Cell { ch: block_glyph(charset, mask), fg, bg }
}

/// One block cell from its samples' palette entries, in bit order.
///
/// Two entries or fewer, the cell shows them exactly (the last sample's is the background): always so
/// for half blocks, and for every cell of a flat or smoothly shaded area (a surface's bands).
/// More (quadrants and sextants across an edge): the best split of their colours, each side drawn in its
/// most frequent entry (the earlier sample's on a tie).
fn indexed_cell(indices: &[u8], charset: Charset) -> Cell {
    if let [ink, paper] = *indices {
        // Half blocks: the top sample's entry on the bottom one's (what the general case gives).
        return if ink == paper {
            solid(Color::Indexed(paper))
        } else {
            Cell { ch: block_glyph(charset, 1), fg: Color::Indexed(ink), bg: Color::Indexed(paper) }
        };
    }
    let paper = indices[indices.len() - 1];
    let Some(&ink) = indices.iter().find(|&&i| i != paper) else {
        return solid(Color::Indexed(paper));
    };
    if indices.iter().all(|&i| i == paper || i == ink) {
        let mask = indices.iter().enumerate().fold(0u8, |m, (k, &i)| m | u8::from(i == ink) << k);
        return Cell { ch: block_glyph(charset, mask), fg: Color::Indexed(ink), bg: Color::Indexed(paper) };
    }
    let srgb: [[u8; 3]; 6] = std::array::from_fn(|k| indices.get(k).map_or([0; 3], |&i| xterm_rgb(i)));
    let Split { mask, .. } = best_partition(&srgb[..indices.len()]);
    let most_frequent = |side: bool| {
        let on_side = |k: usize| (mask >> k & 1 == 1) == side;
        let count = |i: u8| (0..indices.len()).filter(|&k| on_side(k) && indices[k] == i).count();
        // `max_by_key` keeps the last maximum: reversed, that is the earliest sample's entry.
        (0..indices.len()).filter(|&k| on_side(k)).map(|k| indices[k]).rev().max_by_key(|&i| count(i))
    };
    match (most_frequent(true), most_frequent(false)) {
        (Some(ink), Some(paper)) if ink != paper => {
            Cell { ch: block_glyph(charset, mask), fg: Color::Indexed(ink), bg: Color::Indexed(paper) }
        }
        (_, Some(paper)) => solid(Color::Indexed(paper)),
        (ink, None) => solid(Color::Indexed(ink.unwrap_or(paper))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::palette;
    use crate::shade::linear_to_srgb;

    /// Half blocks in truecolor are each cell's two samples exactly, whatever the memo of equal
    /// samples finds: on held-out views of generated mazes (level and pitched, exit light in some),
    /// with textures and without, every cell against its definition (top sample's codes the ink of
    /// `▀` on the bottom one's; one colour: a blank).
    #[test]
    fn truecolor_half_blocks_are_their_two_samples_on_held_out_views() {
        use crate::{Culling, Renderer, Target, quality};
        use mazewalk_maze::generate::{GenOptions, generate};
        let tables = Srgb8Tables::get();
        let (mut cells, mut two) = (0usize, 0usize);
        for (seed, (width, height)) in [(31u64, (12, 9)), (32, (20, 15))] {
            let opts = GenOptions { width, height, seed, loops: 0.2, exit: true, ..GenOptions::default() };
            let maze = generate(&opts).expect("generated maze");
            let mut renderer = Renderer::new();
            for (k, (_, mut camera)) in quality::held_out_views(&maze, seed, 10).into_iter().enumerate() {
                camera.pitch_deg = [0.0, 12.0, -20.0][k % 3];
                let (cols, rows) = ([60, 33][k % 2], 20);
                let options = RenderOptions {
                    charset: Charset::Half,
                    color_depth: ColorDepth::TrueColor,
                    culling: Culling::Portal,
                    textures: k % 2 == 1,
                    ..RenderOptions::default()
                };
                renderer.render(&maze, &camera, &[], &options, Target::Samples { cols, rows }).expect("view");
                let samples = renderer.samples();
                let region = Region { col: 0, row: 0, cols, rows };
                let mut frame = Frame::new(cols, rows);
                to_frame(samples, &options, &mut frame, region);
                for (row, line) in frame.region_rows_mut(region).enumerate() {
                    for (col, cell) in line.iter().enumerate() {
                        let at = |y: usize| tables.encode3(samples.color()[y * samples.width() + col]);
                        let ([r, g, b], [r2, g2, b2]) = (at(2 * row), at(2 * row + 1));
                        let (fg, bg) = (Color::Rgb(r, g, b), Color::Rgb(r2, g2, b2));
                        let expected = Cell { ch: HALF[usize::from(fg != bg)], fg, bg };
                        assert_eq!(*cell, expected, "seed {seed}, view {k}, cell ({col}, {row})");
                        (cells, two) = (cells + 1, two + usize::from(fg != bg));
                    }
                }
            }
        }
        assert!(two > cells / 20, "{two} of {cells} cells in two colours");
    }

    /// Frames in 256 and 16 colours are what they were before the lookups got faster (issue #42): on
    /// held-out views of generated mazes (issue #39's kinds: in cells, nose to a wall, down
    /// corridors; level and pitched), in every charset, plain and dithered, each frame of
    /// [`to_frame`] against the frame its samples make through the old lookup
    /// ([`palette::search`]: the slot by `f32::round`, the entry by a binary search, no memo), cell
    /// for cell.
    #[test]
    fn palette_frames_are_those_of_the_searched_lookup() {
        use crate::{Culling, Renderer, Target, quality};
        use mazewalk_maze::generate::{GenOptions, generate};
        let mut cells = 0usize;
        for (seed, (width, height)) in [(5u64, (12, 9)), (6, (20, 15)), (7, (8, 22))] {
            let opts = GenOptions { width, height, seed, loops: 0.2, exit: true, ..GenOptions::default() };
            let maze = generate(&opts).expect("generated maze");
            let mut renderer = Renderer::new();
            for (k, (_, mut camera)) in quality::held_out_views(&maze, seed, 12).into_iter().enumerate() {
                camera.pitch_deg = [0.0, 12.0, -20.0][k % 3];
                let charset = [Charset::Half, Charset::Quad, Charset::Sextant, Charset::Ascii][k % 4];
                let (cols, rows) = (60, 20);
                let options = RenderOptions { charset, culling: Culling::Portal, ..RenderOptions::default() };
                renderer.render(&maze, &camera, &[], &options, Target::Samples { cols, rows }).expect("view");
                let samples = renderer.samples();
                let region = Region { col: 0, row: 0, cols, rows };
                for (depth, dither) in [(ColorDepth::Ansi256, false), (ColorDepth::Ansi16, false)]
                    .into_iter()
                    .chain([(ColorDepth::Ansi256, true), (ColorDepth::Ansi16, true)])
                {
                    let palette = Palette::of(depth).expect("a palette");
                    let mut frame = Frame::new(cols, rows);
                    to_frame(
                        samples,
                        &RenderOptions { color_depth: depth, dither, ..options },
                        &mut frame,
                        region,
                    );
                    let mut expected = Frame::new(cols, rows);
                    let (sx, sy) = charset.samples_per_cell();
                    if charset == Charset::Ascii {
                        let ink = |_, c: Vec3| Color::Indexed(palette::search::ramp_entry(c, palette, None));
                        ascii_cells(samples, options.ramp, &[], (&mut expected, region), ink);
                    } else {
                        for (row, line) in expected.region_rows_mut(region).enumerate() {
                            for (col, cell) in line.iter_mut().enumerate() {
                                let indices: Vec<u8> = (0..sx * sy)
                                    .map(|k| {
                                        let (x, y) = (col * sx + k % sx, row * sy + k / sx);
                                        let sample = samples.color()[y * samples.width() + x];
                                        let threshold = dither.then(|| threshold(x, y));
                                        palette::search::ramp_entry(sample, palette, threshold)
                                    })
                                    .collect();
                                *cell = indexed_cell(&indices, charset);
                            }
                        }
                    }
                    assert!(
                        frame == expected,
                        "seed {seed}, view {k} ({charset:?}, {depth:?}, dither {dither}) differs"
                    );
                    cells += cols * rows;
                }
            }
        }
        assert_eq!(cells, 3 * 12 * 4 * 60 * 20);
    }

    /// Half blocks in 256 and 16 colours ([`half_palette`]: runs of cells copied eight at a time,
    /// the entries memoized) are each cell's two samples' entries by the lookup without any memo,
    /// on random views of generated mazes: level and pitched, with and without textures, chalk marks
    /// and figures, widths that leave runs of fewer than eight cells at a row's end, exit light in
    /// some. It fails if a run is taken where any of its samples differs from the one before it (a
    /// word left out of the comparison, a run shifted by a sample), or if the runs are never taken.
    #[test]
    fn palette_half_blocks_are_their_two_samples_entries_on_random_views() {
        use crate::{Culling, Renderer, Sprite, Target, quality};
        use glam::Vec2;
        use mazewalk_maze::generate::{GenOptions, generate};
        let (mut cells, before) = (0usize, HALF_CELLS_BY_RUNS.with(std::cell::Cell::get));
        for (seed, (width, height)) in [(41u64, (12, 9)), (42, (20, 15)), (43, (7, 19))] {
            let opts = GenOptions { width, height, seed, loops: 0.3, exit: true, ..GenOptions::default() };
            let maze = generate(&opts).expect("generated maze");
            let mut renderer = Renderer::new();
            let chalk: Vec<u32> = (0..maze.cell_count() as u32).step_by(3).collect();
            for (k, (_, mut camera)) in quality::held_out_views(&maze, seed, 16).into_iter().enumerate() {
                camera.pitch_deg = [0.0, 0.0, 12.0, -20.0, 0.001][k % 5];
                let (cols, rows) = [(60, 20), (33, 17), (120, 39), (9, 5)][k % 4];
                let figure = Sprite {
                    position: camera.position + Vec2::from_angle(camera.yaw_deg.to_radians()) * 3.0,
                    cell: maze.cell_at(camera.position).unwrap_or(0),
                    color: Vec3::new(0.9, 0.3, 0.2),
                    label: 'a',
                    ghost: false,
                };
                renderer.set_chalk(if k % 2 == 0 { &chalk } else { &[] });
                for depth in [ColorDepth::Ansi256, ColorDepth::Ansi16] {
                    let options = RenderOptions {
                        charset: Charset::Half,
                        color_depth: depth,
                        culling: Culling::Portal,
                        textures: k % 3 == 1,
                        ..RenderOptions::default()
                    };
                    let sprites = if k % 4 == 2 { std::slice::from_ref(&figure) } else { &[] };
                    let target = Target::Samples { cols, rows };
                    renderer.render(&maze, &camera, sprites, &options, target).expect("view");
                    let samples = renderer.samples();
                    let region = Region { col: 0, row: 0, cols, rows };
                    let mut frame = Frame::new(cols, rows);
                    to_frame(samples, &options, &mut frame, region);
                    let palette = Palette::of(depth).expect("a palette");
                    for (row, line) in frame.region_rows_mut(region).enumerate() {
                        for (col, cell) in line.iter().enumerate() {
                            let at = |y: usize| {
                                let sample = samples.color()[y * samples.width() + col];
                                palette::search::ramp_entry(sample, palette, None)
                            };
                            let expected = indexed_cell(&[at(2 * row), at(2 * row + 1)], Charset::Half);
                            assert_eq!(
                                *cell, expected,
                                "seed {seed}, view {k}, {depth:?}, cell ({col}, {row})"
                            );
                            cells += 1;
                        }
                    }
                }
            }
        }
        let by_runs = HALF_CELLS_BY_RUNS.with(std::cell::Cell::get) - before;
        assert!(by_runs > cells / 4 && by_runs < cells, "{by_runs} of {cells} cells copied by runs");
    }

    #[test]
    fn a_ramp_step_is_the_rounded_stretched_lightness() {
        // The definition, in f64 with the exact curve: [`RampSteps`] compares luminances instead.
        let by_lightness = |color: Vec3, len: usize| {
            let lightness = f64::from(linear_to_srgb(luminance(color)));
            let (bottom, top) = (f64::from(FLOOR_RANGE.0), f64::from(FLOOR_RANGE.1));
            let t = ((lightness - bottom) / (top - bottom)).clamp(0.0, 1.0);
            (t * (len - 1) as f64).round() as usize
        };
        for len in [1, 2, BLOCK_RAMP.len(), crate::options::ASCII_RAMP.len(), ASCII_RAMP_LONG.len()] {
            let steps = RampSteps::new(len, FLOOR_RANGE);
            let mut seen = vec![false; len];
            for k in 0..=4000 {
                let grey = Vec3::splat(k as f32 / 4000.0);
                for color in [grey, grey * Vec3::new(1.0, 0.5, 0.2), grey * Vec3::new(0.1, 0.3, 1.0)] {
                    let (got, want) = (steps.index(color), by_lightness(color, len));
                    assert_eq!(got, want, "len {len}, {color}");
                    seen[got] = true;
                }
            }
            assert!(seen.iter().all(|&s| s), "len {len}: every glyph of the ramp is reached");
            assert_eq!(steps.index(Vec3::NAN), 0);
            assert_eq!(steps.index(Vec3::splat(2.0)), len - 1);
            assert_eq!(steps.index(Vec3::INFINITY), len - 1, "len {len}: past the last glyph, the last");
        }
    }

    #[test]
    fn a_block_cell_within_one_step_is_one_colour_and_a_wider_one_is_split() {
        let tables = Srgb8Tables::get();
        let fitted = |codes: &[[u8; 3]], charset| {
            let linear: Vec<Vec3A> = codes
                .iter()
                .map(|code| non_negative(Vec3::from(code.map(|c| srgb_to_linear(f32::from(c) / 255.0)))))
                .collect();
            fitted_cell(tables, &linear, code_range(tables, &linear), charset, ColorDepth::TrueColor)
        };
        let (a, b) = ([100, 50, 20], [101, 51, 20]);
        for (charset, n) in [(Charset::Quad, 4), (Charset::Sextant, 6)] {
            let flat: Vec<[u8; 3]> = (0..n).map(|k| if k % 2 == 0 { a } else { b }).collect();
            let cell = fitted(&flat, charset);
            // The mean, rounded: every sample within one step of what is shown.
            assert_eq!(cell, solid(Color::Rgb(101, 51, 20)), "{charset:?}");
            let wider: Vec<[u8; 3]> = (0..n).map(|k| if k % 2 == 0 { a } else { [102, 50, 20] }).collect();
            let cell = fitted(&wider, charset);
            assert_ne!(cell.ch, ' ', "{charset:?}: two steps apart is a split");
            assert_eq!((cell.fg, cell.bg), (Color::Rgb(100, 50, 20), Color::Rgb(102, 50, 20)), "{charset:?}");
        }
    }

    #[test]
    fn charset_names_round_trip() {
        for c in Charset::ALL {
            assert_eq!(c.to_string().parse::<Charset>(), Ok(c));
        }
        assert!("braille".parse::<Charset>().is_err());
        assert_eq!(Charset::Half.sample_aspect(0.5), 1.0);
        assert_eq!(Charset::Sextant.sample_aspect(0.5), 0.75);
    }

    /// An indexed half-block cell is its top sample's entry (`▀`) on its bottom one's, a blank when
    /// they are equal.
    #[test]
    fn an_indexed_half_block_is_its_top_entry_on_its_bottom_one() {
        assert_eq!(
            indexed_cell(&[21, 196], Charset::Half),
            Cell { ch: '▀', fg: Color::Indexed(21), bg: Color::Indexed(196) }
        );
        assert_eq!(indexed_cell(&[40, 40], Charset::Half), solid(Color::Indexed(40)));
    }

    #[test]
    fn best_partition_splits_two_colours() {
        let (a, b) = ([230, 25, 25], [25, 25, 230]);
        let split = best_partition(&[a, b, a, b, a, a]);
        assert_eq!(split, Split { mask: 0b00_1010, ink: b, paper: a }); // the last sample is background
        assert_eq!(best_partition(&[a, a, a, a]).mask, 0);
        assert_eq!(best_partition(&[a, b]), Split { mask: 1, ink: a, paper: b });
        // Three near-blacks and a white: the white alone, the others in their rounded mean.
        let split = best_partition(&[[0, 0, 0], [255, 255, 255], [1, 1, 1], [2, 2, 2]]);
        assert_eq!(split, Split { mask: 0b0010, ink: [255; 3], paper: [1; 3] });
    }

    /// A cell's codes from its range are each sample's own encoding, its range is theirs, and a cell
    /// within one code per channel has the mean of them: for clustered values (most within a code of
    /// each other), spread ones, values outside 0..1, and NaN.
    #[test]
    fn codes_from_a_cells_range_are_each_samples_own() {
        let tables = Srgb8Tables::get();
        let mut seed = 7u64;
        let mut unit = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut flat_cells = 0;
        for trial in 0..20_000 {
            let n = [4, 6][trial % 2];
            let base = unit() * 1.2 - 0.1;
            let reach = [1e-4, 2e-3, 0.05, 0.6][trial / 2 % 4];
            let linear: Vec<Vec3> = (0..n)
                .map(|_| {
                    let mut c =
                        Vec3::new(base, base * 0.8, base * 0.5) + Vec3::new(unit(), unit(), unit()) * reach;
                    if unit() < 0.01 {
                        c.y = f32::NAN;
                    }
                    c
                })
                .collect();
            let own: Vec<[u8; 3]> = linear.iter().map(|&c| tables.encode3(c)).collect();
            let cell: Vec<Vec3A> = linear.iter().map(|&c| non_negative(c)).collect();
            let (low, high) = code_range(tables, &cell);
            for c in 0..3 {
                assert_eq!(low[c], own.iter().map(|s| s[c]).min().unwrap(), "{linear:?}");
                assert_eq!(high[c], own.iter().map(|s| s[c]).max().unwrap(), "{linear:?}");
            }
            let mut codes = [[0u8; 3]; 6];
            sample_codes(tables, &cell, (low, high), &mut codes);
            assert_eq!(&codes[..n], &own[..], "{linear:?}");
            if spread((low, high)) <= FLAT_SPREAD {
                flat_cells += 1;
                let sum = std::array::from_fn(|c| own.iter().map(|s| i32::from(s[c])).sum());
                assert_eq!(flat_mean(tables, &cell, low), rounded_mean(sum, n as i32), "{linear:?}");
            }
        }
        assert!(flat_cells > 2_000, "{flat_cells} flat cells");
    }

    /// The integer search agrees with trying every split and measuring its error directly.
    #[test]
    fn best_partition_has_the_least_squared_error() {
        let error = |srgb: &[[u8; 3]], split: Split| -> f64 {
            let exact_mean = |inside: bool| {
                let chosen: Vec<_> =
                    srgb.iter().enumerate().filter(|(k, _)| (split.mask >> k & 1 == 1) == inside).collect();
                (0..3)
                    .map(|c| {
                        chosen.iter().map(|(_, s)| f64::from(s[c])).sum::<f64>() / chosen.len().max(1) as f64
                    })
                    .collect::<Vec<_>>()
            };
            let (ink, paper) = (exact_mean(true), exact_mean(false));
            srgb.iter()
                .enumerate()
                .map(|(k, s)| {
                    let m = if split.mask >> k & 1 == 1 { &ink } else { &paper };
                    (0..3).map(|c| (f64::from(s[c]) - m[c]).powi(2)).sum::<f64>()
                })
                .sum()
        };
        let mut seed = 0x9E37_79B9_u32;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed >> 24) as u8 & 0xF0 // few levels, so ties happen
        };
        for n in [2usize, 4, 6] {
            for _ in 0..2000 {
                let srgb: Vec<[u8; 3]> = (0..n).map(|_| [next(), next(), next()]).collect();
                let split = best_partition(&srgb);
                let best = (0..1u8 << (n - 1))
                    .map(|mask| error(&srgb, Split { mask, ink: [0; 3], paper: [0; 3] }))
                    .fold(f64::INFINITY, f64::min);
                let chosen = error(&srgb, split);
                assert!(
                    chosen <= best + 1e-9,
                    "{srgb:?}: mask {:#b} error {chosen}, best {best}",
                    split.mask
                );
                assert!(split.mask >> (n - 1) == 0, "the last sample is background");
            }
        }
    }
}
