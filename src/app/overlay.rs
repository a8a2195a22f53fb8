//! What is drawn over the 3D view: the map, the HUD line, the key help, the exit screen, and the message
//! for a terminal too small to draw in. Pure: frames in, frames out; tested as text.

use glam::Vec2;

use super::controls::HELP;
use crate::frame::{Cell, Color, Frame};
use crate::maze::geometry::heading_dir;
use crate::maze::{Aabb, Maze};
use crate::render::camera::Camera;
use crate::render::line_points;

/// The smallest terminal the walkthrough draws in (columns, rows).
pub const MIN_SIZE: (usize, usize) = (20, 6);

const HUD_FG: Color = Color::Indexed(252);
const HUD_BG: Color = Color::Indexed(236);
const BOX_FG: Color = Color::Indexed(255);
const BOX_BG: Color = Color::Indexed(24);
const ROCK: Cell = Cell { ch: '░', fg: Color::Indexed(240), bg: Color::Indexed(234) };
const FLOOR_BG: Color = Color::Indexed(235);
const VISITED_BG: Color = Color::Indexed(17);
const VIEWER_FG: Color = Color::Indexed(226);
const FRUSTUM_FG: Color = Color::Indexed(178);
const EXIT_FG: Color = Color::Indexed(46);

/// True when a `cols × rows` terminal is too small for the walkthrough.
#[must_use]
pub fn too_small(cols: usize, rows: usize) -> bool {
    cols < MIN_SIZE.0 || rows < MIN_SIZE.1
}

/// Fills `frame` with a short note that the terminal is too small: the longest wording that fits the
/// width, on as many rows as there are (even 1×1 shows something).
pub fn draw_too_small(frame: &mut Frame) {
    frame.fill(Cell::BLANK);
    let (w, h) = (frame.width(), frame.height());
    let need = format!("need {}×{}", MIN_SIZE.0, MIN_SIZE.1);
    let title =
        ["terminal too small", "too small", "small", "!"].into_iter().find(|t| t.chars().count() <= w);
    let lines: Vec<&str> = title.into_iter().chain([need.as_str(), "q quits"]).take(h).collect();
    for (i, line) in lines.iter().enumerate() {
        let x = w.saturating_sub(line.chars().count()) / 2;
        frame.put_str(x, i + (h - lines.len()) / 2, line, Color::Default, Color::Default);
    }
}

/// The HUD: one line at the bottom of the frame.
pub fn draw_hud(frame: &mut Frame, text: &str) {
    let Some(y) = frame.height().checked_sub(1) else { return };
    let w = frame.width();
    for x in 0..w {
        frame.set(x, y, Cell { ch: ' ', fg: HUD_FG, bg: HUD_BG });
    }
    frame.put_str(0, y, text, HUD_FG, HUD_BG);
}

/// A box of text lines centred in the frame (help, exit screen), clipped to the frame.
pub fn draw_box(frame: &mut Frame, title: &str, lines: &[String]) {
    let inner = lines.iter().map(|l| l.chars().count()).chain([title.chars().count()]).max().unwrap_or(0);
    let (bw, bh) = ((inner + 4).min(frame.width()), (lines.len() + 4).min(frame.height()));
    let (x0, y0) = ((frame.width() - bw) / 2, (frame.height() - bh) / 2);
    for y in y0..y0 + bh {
        for x in x0..x0 + bw {
            frame.set(x, y, Cell { ch: ' ', fg: BOX_FG, bg: BOX_BG });
        }
    }
    let tx = x0 + bw.saturating_sub(title.chars().count()) / 2;
    frame.put_str(tx, y0 + 1, title, BOX_FG, BOX_BG);
    for (i, line) in lines.iter().enumerate() {
        if 3 + i >= bh {
            break;
        }
        let clipped: String = line.chars().take(bw.saturating_sub(4)).collect();
        frame.put_str(x0 + 2, y0 + 3 + i, &clipped, BOX_FG, BOX_BG);
    }
}

/// The key help as box lines.
#[must_use]
pub fn help_lines() -> Vec<String> {
    HELP.iter().map(|(keys, what)| format!("{keys:<8} {what}")).collect()
}

/// Where the map goes and how much of the maze one map character shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapArea {
    /// Left column in the frame.
    pub x: usize,
    /// Top row in the frame.
    pub y: usize,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Maze units per map column (a row shows twice as much: terminal cells are twice as tall).
    pub units_per_col: f32,
    /// The maze point at the area's centre.
    pub centre: Vec2,
}

impl MapArea {
    /// A small map in the top-right corner, centred on the viewer, about 40 maze units across.
    #[must_use]
    pub fn corner(frame: &Frame, viewer: Vec2) -> MapArea {
        let width = (frame.width() / 3).clamp(1, 40);
        let height = (frame.height() / 3).clamp(1, 14);
        MapArea {
            x: frame.width() - width,
            y: 0,
            width,
            height,
            units_per_col: 40.0 / width as f32,
            centre: viewer,
        }
    }

    /// The whole frame: the whole maze if it fits at a readable scale, else a window on the viewer.
    #[must_use]
    pub fn full(frame: &Frame, maze: &Maze, viewer: Vec2) -> MapArea {
        let (width, height) = (frame.width().max(1), frame.height().saturating_sub(1).max(1));
        let (lo, hi) = (maze.extents().min, maze.extents().max);
        let size = hi - lo;
        let fit = (size.x / width as f32).max(size.y / (2.0 * height as f32));
        // At most 2 units per column (half a generated cell): beyond that, follow the viewer.
        let (units_per_col, centre) =
            if fit <= 2.0 { (fit.max(0.25), (lo + hi) * 0.5) } else { (2.0, viewer) };
        MapArea { x: 0, y: 0, width, height, units_per_col, centre }
    }

    /// The maze-plane box one map character covers.
    fn world_box(&self, col: usize, row: usize) -> Aabb {
        let (u, v) = (self.units_per_col, 2.0 * self.units_per_col);
        let x0 = self.centre.x + (col as f32 - self.width as f32 / 2.0) * u;
        let y1 = self.centre.y - (row as f32 - self.height as f32 / 2.0) * v; // north is up
        Aabb::new(Vec2::new(x0, y1 - v), Vec2::new(x0 + u, y1))
    }

    /// The map character (column, row) showing maze point `p`, as floats.
    fn to_map(self, p: Vec2) -> Vec2 {
        Vec2::new(
            (p.x - self.centre.x) / self.units_per_col + self.width as f32 / 2.0,
            -(p.y - self.centre.y) / (2.0 * self.units_per_col) + self.height as f32 / 2.0,
        )
    }
}

/// Draws the top-down map into `area`: rock outside the cells, walls in their colours, the cells the
/// portal pass visited this frame tinted, the exit, the viewer and its view frustum.
pub fn draw_map(
    frame: &mut Frame,
    area: &MapArea,
    maze: &Maze,
    camera: &Camera,
    visited: &dyn Fn(u32) -> bool,
) {
    for row in 0..area.height {
        for col in 0..area.width {
            let world_box = area.world_box(col, row);
            let cell = match maze.cell_at(world_box.centre()) {
                None => ROCK,
                Some(c) => {
                    let wall = maze.cell_edges(c).iter().map(|&e| (e, maze.edge(e))).find(|&(e, edge)| {
                        let (a, b) = maze.edge_points(e);
                        edge.opaque && world_box.touches_segment(a, b)
                    });
                    let bg = if visited(c) { VISITED_BG } else { FLOOR_BG };
                    match wall {
                        Some((_, edge)) => Cell { ch: '█', fg: rgb(edge.color.to_array()), bg },
                        None => Cell { ch: ' ', fg: Color::Default, bg },
                    }
                }
            };
            frame.set(area.x + col, area.y + row, cell);
        }
    }
    let put = |frame: &mut Frame, p: Vec2, ch: char, fg: Color| {
        let m = area.to_map(p);
        if m.x >= 0.0 && m.y >= 0.0 && (m.x as usize) < area.width && (m.y as usize) < area.height {
            let (x, y) = (area.x + m.x as usize, area.y + m.y as usize);
            let bg = frame.get(x, y).map_or(Color::Default, |c| c.bg);
            frame.set(x, y, Cell { ch, fg, bg });
        }
    };
    // The view frustum: two rays at ±fov/2 from the heading, a few cells long, over floor only.
    let eye = area.to_map(camera.position);
    for side in [-0.5f32, 0.5] {
        let heading = (camera.yaw_deg + side * camera.hfov_deg).to_radians();
        let reach = 12.0 * area.units_per_col;
        let tip = area.to_map(camera.position + heading_dir(heading) * reach);
        let (w, h) = (area.width, area.height);
        for (x, y) in line_points(eye.x as i64, eye.y as i64, tip.x as i64, tip.y as i64, w, h) {
            let (fx, fy) = (area.x + x, area.y + y);
            if frame.get(fx, fy).is_some_and(|c| c.ch == ' ') {
                let bg = frame.get(fx, fy).map_or(Color::Default, |c| c.bg);
                frame.set(fx, fy, Cell { ch: '·', fg: FRUSTUM_FG, bg });
            }
        }
    }
    if let Some(exit) = maze.exit_point() {
        put(frame, exit, 'E', EXIT_FG);
    }
    put(frame, camera.position, heading_arrow(camera.yaw_deg), VIEWER_FG);
}

/// An arrow glyph pointing along the heading (counter-clockwise from east), in 45° steps.
#[must_use]
pub fn heading_arrow(yaw_deg: f32) -> char {
    const ARROWS: [char; 8] = ['→', '↗', '↑', '↖', '←', '↙', '↓', '↘'];
    let octant = ((yaw_deg.rem_euclid(360.0) + 22.5) / 45.0) as usize % 8;
    ARROWS[octant]
}

fn rgb([r, g, b]: [f32; 3]) -> Color {
    let q = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    Color::Rgb(q(r), q(g), q(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn too_small_message_fits_any_size_without_panicking() {
        for (w, h) in [(0, 0), (1, 1), (5, 2), (19, 5), (80, 24)] {
            let mut frame = Frame::new(w, h);
            draw_too_small(&mut frame);
            assert_eq!((frame.width(), frame.height()), (w, h));
        }
        let mut frame = Frame::new(20, 3);
        draw_too_small(&mut frame);
        assert_eq!(frame.lines()[0], " terminal too small ");
        assert!(too_small(19, 24) && too_small(80, 5) && !too_small(20, 6));
    }

    #[test]
    fn arrows_follow_the_heading() {
        assert_eq!(heading_arrow(0.0), '→');
        assert_eq!(heading_arrow(90.0), '↑');
        assert_eq!(heading_arrow(-90.0), '↓');
        assert_eq!(heading_arrow(200.0), '←');
        assert_eq!(heading_arrow(44.0), '↗');
    }

    #[test]
    fn hud_and_box_are_clipped_to_the_frame() {
        let mut frame = Frame::filled(12, 5, Cell::plain('.'));
        draw_hud(&mut frame, "a long heads-up line");
        assert_eq!(frame.lines()[4], "a long heads");
        draw_box(&mut frame, "Help", &["one".to_string(), "two".to_string()]);
        let lines = frame.lines();
        // an 8×5 box (text + 2 padding each side) centred on the dots
        assert_eq!(lines[0], "..        ..");
        assert_eq!(lines[1], "..  Help  ..");
        assert_eq!(lines[3], "..  one   ..");
        let mut tiny = Frame::new(1, 1);
        draw_box(&mut tiny, "Help", &help_lines());
        draw_hud(&mut tiny, "x");
    }
}
