//! Issue #39, a new player in ascii (`--color none --charset ascii`, 120×40): down a corridor of twelve
//! cells the player read two. The floor's glyphs (`,` `_`) and the ceiling's (`` ` `` `"`) shade by
//! distance, not by cell, so nothing marked where one cell ends and the next begins; colour draws a
//! line across the floor and the ceiling at each cell boundary, ascii drew none.
//!
//! The properties, over views straight down the corridors of generated mazes (end walls 2–6 cells
//! ahead), in ascii without colour:
//! - **cells a reader counts on the floor**: in the corridor's centre column below the horizon, a
//!   reader counts the rows showing the cell-line glyph `~`. Each such row is a cell boundary's row
//!   (within one), no two are under two rows apart (no block of `~`), and every boundary whose row
//!   stands at least two rows from the one a cell nearer and from the end wall is drawn: the reader
//!   counts each near cell on the floor. Without the lines the count is 0 and the test fails.
//! - **the lines are no wall's glyph**: `~` is none of the walls' (faced `=#%@`, along the view
//!   `.;+*`, outlines `|-/\`, seams `:`, jambs `[]`), the floor's, the ceiling's or the beacon's.
//! - **seams counted far off**: on a side wall closed over two cells k and k + 1 (k + 1 ≤ 6), the
//!   boundary between them shows the seam's `:` within a column of where it stands, at the horizon
//!   row, wherever both cells are at least a column wide there: with the end wall, what a reader
//!   counts the far cells by (the floor's lines stop about two cells out at 40 rows).

use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::{Charset, RenderOptions, Renderer};
use mazewalk_term::frame::{ColorDepth, Frame};

use crate::draw;
use crate::openings::{Corridor, every_corridor};

const COLS: usize = 120;
const ROWS: usize = 40;
/// The cell lines' glyph.
const LINE: char = '~';
/// The ascii glyph of a line across an opening the exit's light comes through toward the eye (the way
/// one step nearer the exit, issue #39): a cell line too, with the same spacing.
const WAY: char = '^';
/// Every glyph a wall is drawn with in ascii (the short ramp's two families, the outlines, the seam,
/// the jambs), the floor's, the ceiling's and the beacon's.
const OTHERS: &str = "=#%@.;+*|-/\\:[],_`\"$!";
/// The least gap (rows) between two lines drawn.
const GAP: f32 = 2.0;

/// One corridor view in ascii without colour, with the grid position of a point of the corridor
/// `along` tiles ahead of the eye's cell centre, `across` tiles to the side (+: `dir.perp()`), at
/// height `z`.
fn view(maze: &mazewalk_maze::Maze, c: &Corridor) -> (Frame, impl Fn(f32, f32, f32) -> (f32, f32)) {
    let options =
        RenderOptions { charset: Charset::Ascii, color_depth: ColorDepth::None, ..RenderOptions::default() };
    let frame = draw(&mut Renderer::new(), maze, &c.camera, &options, COLS, ROWS);
    let eye = c.camera.eye(COLS, ROWS, Charset::Ascii.sample_aspect(options.cell_aspect)).expect("eye");
    let (at, dir, tile) = (c.at, c.dir, c.tile);
    let grid = move |along: f32, across: f32, z: f32| {
        let p = at + dir * along * tile + dir.perp() * across * tile;
        let g = eye.grid(eye.clip(p.extend(z)));
        (g.x, g.y)
    };
    (frame, grid)
}

fn mazes() -> Vec<mazewalk_maze::Maze> {
    [(20, 15, 12083), (20, 15, 3), (16, 12, 5392), (12, 8, 77), (23, 17, 4541), (18, 10, 91)]
        .into_iter()
        .map(|(w, h, seed)| generate(&GenOptions::walk(w, h, seed)).expect("generated maze"))
        .collect()
}

#[test]
fn the_cell_lines_glyph_is_no_other_surfaces() {
    assert!(!OTHERS.contains(LINE));
    assert!(!OTHERS.contains(WAY) && WAY != LINE && !"x".contains(WAY));
}

#[test]
fn in_ascii_a_reader_counts_the_near_cells_on_the_floor_and_the_lines_never_crowd() {
    let mut views = 0;
    for maze in mazes() {
        let z = maze.viewer().z;
        for c in every_corridor(&maze).iter().filter(|c| c.closed && (2..=6).contains(&c.ahead)) {
            views += 1;
            let (frame, grid) = view(&maze, c);
            let name = format!("at {:?} heading {:.0}, {} cells ahead", c.at, c.camera.yaw_deg, c.ahead);
            let column = grid(1000.0, 0.0, z).0.floor() as usize;
            let horizon = grid(1000.0, 0.0, z).1;
            // the floor's boundary rows (k = 0: the eye's own cell's far side), and the end wall's foot
            let row = |along: f32| grid(along, 0.0, -1.0).1;
            let bounds: Vec<f32> = (0..c.ahead).map(|k| row(k as f32 + 0.5)).collect();
            let end_foot = row(c.ahead as f32 + 0.5);
            let lines: Vec<usize> = (horizon.ceil() as usize..ROWS)
                .filter(|&r| matches!(frame.cells()[r * COLS + column].ch, LINE | WAY))
                .collect();
            for &r in &lines {
                let centre = r as f32 + 0.5;
                assert!(
                    bounds.iter().any(|&b| (b - centre).abs() <= 1.0),
                    "{name}: a line at row {r}, no boundary there ({bounds:?})"
                );
            }
            for pair in lines.windows(2) {
                assert!(pair[1] - pair[0] >= GAP as usize, "{name}: lines at rows {pair:?} crowd");
            }
            // every boundary standing clear of the one a cell nearer and of the end wall is drawn
            for (k, &b) in bounds.iter().enumerate() {
                let nearer = if k == 0 { f32::INFINITY } else { bounds[k - 1] };
                let clear = nearer - b >= GAP + 0.5 && b - end_foot >= GAP && b < ROWS as f32 - 1.0;
                if clear && b > horizon + 1.0 {
                    let r = b.floor() as usize;
                    let near = r.saturating_sub(1)..=(r + 1).min(ROWS - 1);
                    assert!(
                        near.clone().any(|r| lines.contains(&r)),
                        "{name}: the boundary {k} cells on (row {b:.1}) shows no line; lines {lines:?}"
                    );
                }
            }
        }
    }
    assert!(views >= 40, "only {views} views");
}

/// Every corridor view of the mazes: the corridor, its frame, its grid (as [`view`]'s), the eye's
/// height, the horizon's row and the view's name for messages.
fn at_the_horizon(
    mut check: impl FnMut(&Corridor, &Frame, &dyn Fn(f32, f32, f32) -> (f32, f32), f32, usize, &str),
) {
    for maze in mazes() {
        let z = maze.viewer().z;
        for c in every_corridor(&maze).iter() {
            let (frame, grid) = view(&maze, c);
            let horizon = grid(1000.0, 0.0, z).1.floor() as usize;
            let name = format!("at {:?} heading {:.0}, {} cells ahead", c.at, c.camera.yaw_deg, c.ahead);
            check(c, &frame, &grid, z, horizon, &name);
        }
    }
}

#[test]
fn in_ascii_seams_between_side_walls_show_up_to_six_cells_ahead() {
    let mut seams = 0;
    at_the_horizon(|c, frame, grid, z, horizon, name| {
        for (s, across) in [(0, 0.5), (1, -0.5)] {
            for k in 1..c.ahead.min(6) {
                if c.sides[k][s] || c.sides[k + 1][s] {
                    continue;
                }
                let x = |along: f32| grid(along, across, z).0;
                let (a, seam, b) = (x(k as f32 - 0.5), x(k as f32 + 0.5), x(k as f32 + 1.5));
                if (a - seam).abs() < 1.0
                    || (b - seam).abs() < 1.0
                    || !(1.0..COLS as f32 - 1.0).contains(&seam)
                {
                    continue;
                }
                seams += 1;
                let col = seam.floor() as usize;
                let shown: String =
                    (col - 1..=col + 1).map(|x| frame.cells()[horizon * COLS + x].ch).collect();
                assert!(
                    shown.contains(':'),
                    "{name}: the seam {k}–{} cells on, side {s}, shows {shown:?}",
                    k + 1
                );
            }
        }
    });
    assert!(seams >= 40, "only {seams} seams");
}

/// Jambs apart from corners: at the horizon row, a side wall that ends at a side opening 1–2 cells
/// ahead ends in a bracket whose back faces the opening (`]` where the wall lies to its left on the
/// picture, `[` to its right), and where a side wall starts again after the opening a bracket shows;
/// where a closed side wall meets the end wall 1–4 cells ahead, a corner, `|` and no bracket.
#[test]
fn in_ascii_jambs_face_their_opening_and_corners_stay_bars() {
    let (mut jambs, mut corners) = (0, 0);
    at_the_horizon(|c, frame, grid, z, horizon, name| {
        let shown = |x: f32| -> String {
            let col = x.floor() as usize;
            (col.saturating_sub(1)..=(col + 1).min(COLS - 1))
                .map(|x| frame.cells()[horizon * COLS + x].ch)
                .collect()
        };
        // side 0 is `dir.perp()`: the left hand
        for (s, across, left) in [(0, 0.5, true), (1, -0.5, false)] {
            let x = |along: f32| grid(along, across, z).0;
            for k in 1..=c.ahead.min(2) {
                if !c.sides[k][s] {
                    continue;
                }
                let (near, far) = (x(k as f32 - 0.5), x(k as f32 + 0.5));
                if (near - far).abs() < 2.0 {
                    continue;
                }
                // the wall before the opening ends at `near`: it lies outward on the picture
                if !c.sides[k - 1][s] && k >= 2 && (x(k as f32 - 1.5) - near).abs() >= 1.0 {
                    jambs += 1;
                    let want = if left { ']' } else { '[' };
                    assert!(
                        shown(near).contains(want),
                        "{name}: the wall before opening {k} (side {s}) ends in {:?}",
                        shown(near)
                    );
                }
                // the wall after it starts at `far`, where the side cell's far wall, seen square on
                // through the opening, ends too (a corner jutting toward the eye: a jamb to both
                // walls, one glyph where they meet): a bracket either way
                if k < c.ahead && !c.sides[k + 1][s] && (x(k as f32 + 1.5) - far).abs() >= 1.0 {
                    jambs += 1;
                    let seen = shown(far);
                    assert!(
                        seen.contains(['[', ']']),
                        "{name}: the wall after opening {k} (side {s}) starts in {seen:?}"
                    );
                }
            }
            let n = c.ahead;
            if c.closed && n <= 4 && !c.sides[n][s] && (x(n as f32 - 0.5) - x(n as f32 + 0.5)).abs() >= 3.0 {
                corners += 1;
                let seen = shown(x(n as f32 + 0.5));
                assert!(
                    seen.contains('|') && !seen.contains(['[', ']']),
                    "{name}: the corner at the end (side {s}) shows {seen:?}"
                );
            }
        }
    });
    assert!(jambs >= 40 && corners >= 40, "only {jambs} jambs, {corners} corners");
}

/// The least OKLab lightness by which a cell line's sample, as the terminal shows it, is lighter than
/// the plane beside it (two to four samples off, no other line there): twice the 256-colour grey
/// ramp's step at the floor's lightness (0.035), so a line is two entries or more above its plane,
/// more than the floor's own bands (one entry between neighbouring rows far off), and more than
/// `wall_floor`'s 0.05 (two and a half just-noticeable differences).
const VISIBLE_STEP: f32 = 0.07;

/// Issue #39, a new player in 256 colours: the lines across openings, on the floor and the ceiling,
/// were darker than the grey floor, and hard to see; in 16 colours they are light grey and obvious.
/// Over held-out views of generated mazes (in a cell, nose to a wall, down a corridor), 120×40 half
/// blocks in 256 colours: every sample of an ordinary opening's line 0–2 cells off (the way's lines
/// have a look of their own, `glow_way`) where it is drawn (not by a wall), with the plane round it
/// to compare, is lighter than that plane by [`VISIBLE_STEP`]. With the lines darker than their
/// plane, as at `0f10179`, 27,310 of 27,340 fail. Lines 3–5 cells off cannot be judged so at 120×40: down a
/// corridor they lie under two samples apart, with no plane between, and across a side opening
/// beside the wall seen through it, where lines are left out (not one sample over these views).
/// Both as plain perspective draws the views and foveated, as the walk does: there a line crossing
/// from one tile to the next, each rounding it on its own grid, left 17 of 33,284 samples undrawn
/// where bands meet when each tile's line ran between its ends rounded to samples (Bresenham).
#[test]
fn in_256_colours_every_near_cell_line_is_a_step_lighter_than_its_plane() {
    use crate::glow_way::{near_line, on_line, way_look};
    use mazewalk_maze::geometry::{CEILING_Z, FLOOR_Z};
    use mazewalk_render::quality::held_out_views;
    use mazewalk_render::samples::{CEILING, FLOOR};

    let options = RenderOptions {
        charset: Charset::Half,
        color_depth: ColorDepth::Ansi256,
        ..RenderOptions::default()
    };
    let way = way_look(ColorDepth::Ansi256);
    let (mut judged, mut failures) = (0, Vec::new());
    let mut renderer = Renderer::new();
    for seed in [58u64, 71, 3, 12, 5392, 91] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let openings: Vec<u32> = (0..maze.edges().len() as u32).filter(|&e| !maze.edge(e).opaque).collect();
        let views = held_out_views(&maze, seed, 60).into_iter().enumerate();
        for ((k, (kind, camera)), fovea) in views.flat_map(|view| [(view, false), (view, true)]) {
            let camera = mazewalk_render::Camera { fovea, ..camera };
            let (shown, eye) = half_view(&mut renderer, &maze, &camera, &options);
            let ids = renderer.samples().id();
            let (w, h) = (eye.width, eye.height);
            // every opening's line, within a sample: not the plane beside a line
            let mut lines = Vec::new();
            for &e in &openings {
                let (a, b) = maze.edge_points(e);
                for z in [FLOOR_Z, CEILING_Z] {
                    near_line(&eye, a.extend(z), b.extend(z), &mut lines);
                }
            }
            let mut on_a_line = vec![false; ids.len()];
            for i in lines {
                on_a_line[i] = true;
            }
            // the samples within `r` of sample `i` (Chebyshev), as (distance, index)
            let around = |i: usize, r: i64| {
                let (x, y) = ((i % w) as i64, (i / w) as i64);
                (-r..=r).flat_map(move |dy| (-r..=r).map(move |dx| (dx, dy))).filter_map(move |(dx, dy)| {
                    let (x, y) = (x + dx, y + dy);
                    ((0..w as i64).contains(&x) && (0..h as i64).contains(&y))
                        .then(|| (dx.abs().max(dy.abs()), (y * w as i64 + x) as usize))
                })
            };
            for &e in &openings {
                let (a, b) = maze.edge_points(e);
                let nearest = a
                    + (b - a) * ((camera.position - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                let cells = camera.position.distance(nearest) / mazewalk_maze::generate::CELL_SIZE;
                if cells >= 3.0 {
                    continue;
                }
                for (z, plane) in [(FLOOR_Z, FLOOR), (CEILING_Z, CEILING)] {
                    for i in on_line(&eye, a.extend(z), b.extend(z)) {
                        // drawn: a sample or more from anything but the plane (a wall's edge) and, toward
                        // the horizon, four or more from a wall (the lines are left out up to three
                        // off a far wall, and the line drawn may lie a row from its projection)
                        let off =
                            |k: usize| if plane == FLOOR { i.checked_sub(k * w) } else { Some(i + k * w) };
                        // (and not on the frame's border, where the line may fall just outside)
                        if around(i, 1).filter(|&(_, j)| ids[j] == plane).count() < 9
                            || (2..=4).any(|k| off(k).is_none_or(|j| ids.get(j) != Some(&plane)))
                        {
                            continue;
                        }
                        // the way's line (its own look) at or beside it
                        if around(i, 1).any(|(_, j)| shown[j].distance(way) < 1e-3) {
                            continue;
                        }
                        let beside: Vec<f32> = around(i, 4)
                            .filter(|&(d, j)| d >= 2 && ids[j] == plane && !on_a_line[j])
                            .map(|(_, j)| shown[j].x)
                            .collect();
                        if beside.len() < 2 {
                            continue;
                        }
                        let plane_l = beside.iter().sum::<f32>() / beside.len() as f32;
                        // the line is one sample wide and may round to the row or column beside
                        let line_l = around(i, 1).map(|(_, j)| shown[j].x).fold(f32::MIN, f32::max);
                        judged += 1;
                        if line_l - plane_l < VISIBLE_STEP {
                            failures.push(format!(
                                "seed {seed} view {k} {kind:?} fovea {fovea} at {} heading {:.0}: opening {e} ({cells:.1} cells), \
                                 plane {plane}, sample ({}, {}): line L {line_l:.3}, plane beside {plane_l:.3}",
                                camera.position,
                                camera.yaw_deg,
                                i % w,
                                i / w
                            ));
                        }
                    }
                }
            }
        }
    }
    crate::none_failed(
        judged,
        1000,
        &failures,
        &format!("cell-line samples under {VISIBLE_STEP} lighter than their plane"),
    );
}

/// Issue #39, a new player through the lens: a corridor's last cell opened to one side, the wall
/// faced across that opening in line with the end wall, read as an end wall and a side wall — the
/// floor's line along the opening stopped short of the wall it meets (lines were left out two samples
/// beside every wall, which is for a line running along a wall's foot). A line that meets a wall at
/// an angle now reaches the sample beside it. Over corridors of generated mazes ending one to three
/// cells ahead with such a last cell, in 256 colours, in the walk's field and through the lens (30°):
/// the line's samples drawn (a step lighter than the floor around) come within `REACH` samples of the
/// point where it meets the wall faced across the opening.
#[test]
fn in_256_colours_a_side_openings_floor_line_reaches_the_wall_it_meets() {
    use crate::glow_way::on_line;
    use mazewalk_maze::geometry::FLOOR_Z;
    use mazewalk_render::samples::FLOOR;

    /// Samples (Euclidean, on the grid) from the point the line meets the wall to its nearest sample
    /// drawn: 2.0–4.7 over these views; 4.2–8.2 with the lines left out two beside every wall, as at
    /// `94956db`, where 276 of the walk's views drew none of the line.
    const REACH: f32 = 5.0;
    let options = RenderOptions {
        charset: Charset::Half,
        color_depth: ColorDepth::Ansi256,
        ..RenderOptions::default()
    };
    let (mut judged, mut failures) = (0, Vec::new());
    let mut renderer = Renderer::new();
    for maze in mazes() {
        for c in every_corridor(&maze) {
            if !c.closed || !(1..=3).contains(&c.ahead) {
                continue;
            }
            let k = c.ahead as f32;
            for (s, sign) in [(0, 1.0), (1, -1.0)] {
                if !c.sides[c.ahead][s] {
                    continue;
                }
                // the wall faced across the opening: the side cell's, in line with the end wall
                let point =
                    |along: f32, across: f32| c.at + c.dir * along * c.tile + c.dir.perp() * across * c.tile;
                let faced = maze.cell_at(point(k, sign * 1.0)).is_some_and(|cell| {
                    maze.cell_edges(cell).iter().any(|&e| {
                        let (a, b) = maze.edge_points(e);
                        maze.edge(e).opaque && (a + b).distance(2.0 * point(k + 0.5, sign)) < 0.1 * c.tile
                    })
                });
                if !faced {
                    continue;
                }
                let (near, far) = (point(k - 0.5, sign * 0.5), point(k + 0.5, sign * 0.5));
                for hfov in [c.camera.hfov_deg, 30.0] {
                    let camera = if hfov == 30.0 {
                        mazewalk_render::Camera { hfov_deg: 30.0, min_vfov_deg: 0.0, ..c.camera }
                    } else {
                        c.camera
                    };
                    let (shown, eye) = half_view(&mut renderer, &maze, &camera, &options);
                    let ids = renderer.samples().id();
                    let (w, h) = (eye.width, eye.height);
                    let end = eye.grid(eye.clip(far.extend(FLOOR_Z)));
                    // drawn: a floor sample a step lighter than the darkest floor within two samples
                    let drawn = |i: usize| {
                        let (x, y) = ((i % w) as i64, (i / w) as i64);
                        let floor = (-2..=2i64)
                            .flat_map(|dy| (-2..=2i64).map(move |dx| (x + dx, y + dy)))
                            .filter(|&(x, y)| (0..w as i64).contains(&x) && (0..h as i64).contains(&y))
                            .map(|(x, y)| (y * w as i64 + x) as usize)
                            .filter(|&j| ids[j] == FLOOR)
                            .map(|j| shown[j].x)
                            .fold(f32::INFINITY, f32::min);
                        ids[i] == FLOOR && shown[i].x - floor >= VISIBLE_STEP
                    };
                    let nearest = on_line(&eye, near.extend(FLOOR_Z), far.extend(FLOOR_Z))
                        .into_iter()
                        .filter(|&i| drawn(i))
                        .map(|i| {
                            glam::Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5)
                                .distance(end.truncate())
                        })
                        .fold(f32::INFINITY, f32::min);
                    if !nearest.is_finite() {
                        continue; // not in view, or no sample of it drawn (too far, too thin)
                    }
                    judged += 1;
                    if nearest > REACH {
                        failures.push(format!(
                            "corridor at {:?} heading {:.0}, {} cells, side {s}, field {hfov}°: the line's nearest drawn sample {nearest:.1} samples from the wall",
                            c.at, c.camera.yaw_deg, c.ahead
                        ));
                    }
                }
            }
        }
    }
    crate::none_failed(judged, 10, &failures, "side openings' floor lines short of the wall they meet");
}

/// `camera`'s view of `maze` in half blocks at COLS × ROWS: the colours shown (OKLab per sample) and
/// the eye (the renderer keeps the samples' ids).
fn half_view(
    renderer: &mut Renderer,
    maze: &mazewalk_maze::Maze,
    camera: &mazewalk_render::Camera,
    options: &RenderOptions,
) -> (Vec<glam::Vec3>, mazewalk_render::Eye) {
    let frame = draw(renderer, maze, camera, options, COLS, ROWS);
    let shown = mazewalk_render::quality::shown(&frame, Charset::Half);
    let (w, h) = (renderer.samples().width(), renderer.samples().height());
    (shown, camera.eye(w, h, Charset::Half.sample_aspect(options.cell_aspect)).expect("eye"))
}
