//! The [`SampleBuffer`]: colour, depth, coverage id and outline glyph per sample.
//!
//! Samples are the sub-cell pixels of the grid: a terminal cell holds `sx × sy` of them (see
//! [`Charset::samples_per_cell`](super::Charset::samples_per_cell)). Sample `(x, y)` covers
//! `[x, x+1) × [y, y+1)` in grid space (origin top-left, y down) and is stored row-major at `y * width + x`.
//! A window of the buffer ([`SampleBuffer::window`]: a foveated view's tile, drawn in its place in
//! the picture) is a buffer of its own size whose rows lie [`SampleBuffer::pitch`] apart.

use glam::Vec3;

/// Coverage id of a sample nothing has been drawn on.
pub const NONE: u32 = u32::MAX;
/// Coverage id of the floor.
pub const FLOOR: u32 = u32::MAX - 1;
/// Coverage id of the ceiling.
pub const CEILING: u32 = u32::MAX - 2;

/// Depth of a cleared sample: farther than anything, so geometry on the far plane (depth 1) still passes.
pub const FAR: f32 = f32::INFINITY;

/// A `width × height` grid of samples: linear colour, depth in [0, 1] (smaller = nearer), coverage id and
/// an optional outline glyph. Row-major, origin top-left, y down: the slices hold `width * height`
/// entries, sample `(x, y)` at `y * width + x`. A window ([`SampleBuffer::window`]) is drawn through
/// [`SampleBuffer::parts_mut`] (its slices from the window's first sample, its rows
/// [`SampleBuffer::pitch`] apart) and [`SampleBuffer::put`]; the other slices are the whole buffer's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleBuffer {
    width: usize,
    height: usize,
    /// Samples from a row to the next: `width`, or in a window the whole buffer's width.
    pitch: usize,
    /// A window's first sample in the whole buffer (0 for the whole buffer).
    origin: usize,
    /// The whole buffer's rows (`height` but in a window).
    rows: usize,
    color: Vec<Vec3>,
    depth: Vec<f32>,
    id: Vec<u32>,
    outline: Vec<Option<char>>,
    /// Whether any outline may be set (so clearing them is needed: most frames have none).
    outlined: bool,
}

impl SampleBuffer {
    /// A cleared buffer: black, depth [`FAR`], id [`NONE`], no outlines.
    #[must_use]
    pub fn new(width: usize, height: usize) -> SampleBuffer {
        let mut buffer = SampleBuffer::default();
        buffer.resize(width, height);
        buffer
    }

    /// Changes the size and clears everything to black; reuses the allocations.
    pub fn resize(&mut self, width: usize, height: usize) {
        (self.width, self.height, self.pitch, self.origin, self.rows) = (width, height, width, 0, height);
        let n = width * height;
        self.color.resize(n, Vec3::ZERO);
        self.depth.resize(n, FAR);
        self.id.resize(n, NONE);
        self.outline.resize(n, None);
        self.clear(Vec3::ZERO);
    }

    /// Changes the size, keeping the allocations, for a pass that clears what it needs itself
    /// ([`SampleBuffer::clear_coverage`] and colours of its own): the samples' contents are left
    /// as they fall.
    pub(crate) fn reshape(&mut self, width: usize, height: usize) {
        (self.width, self.height, self.pitch, self.origin, self.rows) = (width, height, width, 0, height);
        let n = width * height;
        self.color.resize(n, Vec3::ZERO);
        self.depth.resize(n, FAR);
        self.id.resize(n, NONE);
        self.outline.resize(n, None);
    }

    /// Sets every sample to `background` at depth [`FAR`] with id [`NONE`] and no outline.
    pub fn clear(&mut self, background: Vec3) {
        debug_assert!(!self.is_window(), "the whole buffer");
        self.color.fill(background);
        self.clear_coverage();
    }

    /// [`clear`](Self::clear) but for the colours, which keep the last frame's: for a pass that writes
    /// every sample's colour itself (the pipeline's floor and ceiling pass gives what no wall took
    /// either a plane or the fog).
    pub(crate) fn clear_coverage(&mut self) {
        debug_assert!(!self.is_window(), "the whole buffer (a window's samples: cleared with it)");
        for (depth, id) in self.depth.iter_mut().zip(&mut self.id) {
            (*depth, *id) = (FAR, NONE);
        }
        self.clear_outlines();
    }

    /// Clears every outline glyph (none to clear where none may be set).
    pub(crate) fn clear_outlines(&mut self) {
        if std::mem::take(&mut self.outlined) {
            self.outline.fill(None);
        }
    }

    /// Samples per row.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows of samples.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Samples from the start of a row to the start of the next in the slices: the width, but in a
    /// window ([`SampleBuffer::window`]).
    #[must_use]
    pub(crate) fn pitch(&self) -> usize {
        self.pitch
    }

    /// The index of sample `(x, y)` in the slices (`y * pitch + x`: in a window, in
    /// [`SampleBuffer::parts_mut`]'s), or `None` outside the buffer.
    #[must_use]
    pub fn index(&self, x: usize, y: usize) -> Option<usize> {
        (x < self.width && y < self.height).then(|| y * self.pitch + x)
    }

    /// Linear colours, row-major.
    #[must_use]
    pub fn color(&self) -> &[Vec3] {
        debug_assert!(!self.is_window(), "the whole buffer (a window's: `parts_mut`)");
        &self.color
    }

    /// Depths, row-major; [`FAR`] where nothing was drawn.
    #[must_use]
    pub fn depth(&self) -> &[f32] {
        debug_assert!(!self.is_window(), "the whole buffer (a window's: `parts_mut`)");
        &self.depth
    }

    /// Coverage ids, row-major: a wall or edge index, [`FLOOR`], [`CEILING`] or [`NONE`].
    #[must_use]
    pub fn id(&self) -> &[u32] {
        debug_assert!(!self.is_window(), "the whole buffer (a window's: `parts_mut`)");
        &self.id
    }

    /// Outline glyphs (ascii mode), row-major.
    #[must_use]
    pub fn outline(&self) -> &[Option<char>] {
        debug_assert!(!self.is_window(), "the whole buffer (a window's: `parts_mut`)");
        &self.outline
    }

    /// Colours, mutable (for a pipeline that paints the background itself).
    pub(crate) fn color_mut(&mut self) -> &mut [Vec3] {
        debug_assert!(!self.is_window(), "the whole buffer");
        &mut self.color
    }

    /// Coverage ids and colours, the colours mutable (for a pass that paints by surface).
    pub(crate) fn id_and_color_mut(&mut self) -> (&[u32], &mut [Vec3]) {
        debug_assert!(!self.is_window(), "the whole buffer");
        (&self.id, &mut self.color)
    }

    /// From now on the buffer is its `width × height` samples from (`x0`, `y0`), each where it is in
    /// the whole buffer (its rows [`SampleBuffer::pitch`] apart), until [`SampleBuffer::end_window`]:
    /// a foveated view's tile drawn in its place in the picture, with nothing to copy. The window
    /// must fit in the whole buffer.
    pub(crate) fn window(&mut self, x0: usize, y0: usize, width: usize, height: usize) {
        debug_assert!(!self.is_window(), "a window of the whole buffer");
        debug_assert!(x0 + width <= self.width && y0 + height <= self.height, "the window fits");
        (self.origin, self.width, self.height) = (y0 * self.pitch + x0, width, height);
    }

    /// The whole buffer again, after a [`SampleBuffer::window`].
    pub(crate) fn end_window(&mut self) {
        (self.origin, self.width, self.height) = (0, self.pitch, self.rows);
    }

    /// Whether the buffer is a window of a larger one.
    pub(crate) fn is_window(&self) -> bool {
        (self.width, self.height) != (self.pitch, self.rows)
    }

    /// Writes one sample unconditionally (no depth test); writes outside the buffer are ignored.
    pub fn put(&mut self, x: usize, y: usize, color: Vec3, depth: f32, id: u32) {
        if let Some(i) = self.index(x, y) {
            self.write(i, color, depth, id);
        }
    }

    /// Sets the outline glyph of sample `(x, y)`; writes outside the buffer are ignored.
    pub(crate) fn put_outline(&mut self, x: usize, y: usize, glyph: Option<char>) {
        debug_assert!(!self.is_window(), "outlines over a whole view");
        if let Some(i) = self.index(x, y) {
            self.outline[i] = glyph;
            self.outlined = true;
        }
    }

    /// Writes sample `i` (an [`index`](Self::index), in range).
    pub(crate) fn write(&mut self, i: usize, color: Vec3, depth: f32, id: u32) {
        let i = self.origin + i;
        self.color[i] = color;
        self.depth[i] = depth;
        self.id[i] = id;
    }

    /// Colours, depths and ids, mutable together (row loops that test and write all three); a
    /// window's from its first sample (the slices' sample `(x, y)` at `y * pitch + x`).
    pub(crate) fn parts_mut(&mut self) -> (&mut [Vec3], &mut [f32], &mut [u32]) {
        let at = self.origin;
        (&mut self.color[at..], &mut self.depth[at..], &mut self.id[at..])
    }

    /// Outline glyphs, mutable, with the depths to test them against.
    pub(crate) fn outline_and_depth_mut(&mut self) -> (&mut [Option<char>], &[f32]) {
        debug_assert!(!self.is_window(), "outlines over a whole view");
        self.outlined = true;
        (&mut self.outline, &self.depth)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resize_clears_and_keeps_lengths_consistent() {
        let mut buffer = SampleBuffer::new(3, 2);
        buffer.put(2, 1, Vec3::ONE, 0.5, 7);
        buffer.put(3, 0, Vec3::ONE, 0.5, 7); // outside: ignored
        assert_eq!(buffer.id()[5], 7);
        buffer.resize(2, 2);
        assert_eq!(buffer.color().len(), 4);
        assert!(buffer.id().iter().all(|&id| id == NONE));
        assert!(buffer.depth().iter().all(|&d| d == FAR));
        buffer.resize(0, 0);
        assert!(buffer.color().is_empty() && buffer.index(0, 0).is_none());
    }

    #[test]
    fn a_window_is_its_samples_where_they_are_in_the_whole_buffer() {
        let mut buffer = SampleBuffer::new(5, 4);
        buffer.window(1, 2, 3, 2);
        assert_eq!((buffer.width(), buffer.height(), buffer.pitch()), (3, 2, 5));
        buffer.put(2, 1, Vec3::ONE, 0.5, 7); // the whole buffer's (3, 3)
        buffer.put(3, 0, Vec3::ONE, 0.5, 8); // right of the window: ignored
        let (_, depths, ids) = buffer.parts_mut();
        (depths[5], ids[5]) = (0.25, 9); // the window's (0, 1): the whole buffer's (1, 3)
        buffer.end_window();
        assert_eq!((buffer.width(), buffer.height(), buffer.pitch()), (5, 4, 5));
        let drawn: Vec<_> =
            (0..20).filter(|&i| buffer.id()[i] != NONE).map(|i| (i, buffer.id()[i])).collect();
        assert_eq!(drawn, [(16, 9), (18, 7)]);
        assert_eq!((buffer.depth()[16], buffer.depth()[18], buffer.color()[18]), (0.25, 0.5, Vec3::ONE));
    }
}
