//! Issue #39: the exit's light spills down the corridors (block light, `mazewalk_maze::light`): walls
//! within twenty-seven cells' path of the exit keep their own colours tinted toward the exit's
//! green, faint at the edge of its reach and greener and lighter closer, in truecolor and 256
//! colours (16 colours: the dark green, its seams and corners drawn); walls beyond its reach, or
//! behind a wall from it, are drawn as in a maze without an exit.

use crate::draw;
use glam::Vec3;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::light::ExitLight;
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, quality};
use mazewalk_term::frame::ColorDepth;

/// The maze without its exit: the same walls, no light.
fn without_exit(maze: &Maze) -> Maze {
    let mut edges = mazewalk_maze::Edges::new();
    for e in 0..maze.edges().len() {
        edges.push(maze.edge(e as u32));
    }
    Maze::new(maze.vertices().to_vec(), edges, maze.cells().clone(), *maze.viewer(), None).expect("maze")
}

/// Linear colours and ids of the samples of `camera`'s view (truecolor, half blocks, 120×40).
fn samples(maze: &Maze, camera: &Camera) -> (Vec<Vec3>, Vec<u32>) {
    let mut renderer = Renderer::new();
    let options = RenderOptions { color_depth: ColorDepth::TrueColor, ..RenderOptions::default() };
    draw(&mut renderer, maze, camera, &options, 120, 40);
    (renderer.samples().color().to_vec(), renderer.samples().id().to_vec())
}

/// What the terminal shows on each sample of `camera`'s view in `depth` (OKLab, half blocks,
/// 120×40), and the samples' ids.
fn shown(maze: &Maze, camera: &Camera, depth: ColorDepth) -> (Vec<Vec3>, Vec<u32>) {
    let mut renderer = Renderer::new();
    let options = RenderOptions { color_depth: depth, ..RenderOptions::default() };
    let frame = draw(&mut renderer, maze, camera, &options, 120, 40);
    (quality::shown(&frame, Charset::Half), renderer.samples().id().to_vec())
}

/// The exit's light (linear RGB, as the beacon's glow).
const EXIT_GLOW: Vec3 = Vec3::new(0.20, 1.0, 0.42);

/// The maze viewer's camera at `cell`'s centroid, facing `heading` (degrees).
fn cell_camera(maze: &Maze, cell: u32, heading: f32) -> Camera {
    let v = maze.viewer();
    Camera {
        eye_z: v.z,
        min_vfov_deg: maze.min_vfov_deg(),
        fovea: true,
        ..Camera::new(maze.cell_centroid(cell), heading, v.fov_deg)
    }
}

/// Whether sample `k` of a 120-sample-wide view lies inside its surface (its four neighbours show it too).
fn inside(ids: &[u32], k: usize) -> bool {
    let width = 120;
    [k.wrapping_sub(1), k + 1, k.wrapping_sub(width), k + width]
        .iter()
        .all(|&n| ids.get(n).is_none_or(|&id| id == ids[k]))
}

/// OKLab of a linear colour.
fn oklab(c: Vec3) -> Vec3 {
    Vec3::from_array(mazewalk_term::frame::oklab(c.to_array(), f32::cbrt))
}

#[test]
fn walls_near_the_exit_turn_green_greener_nearer_and_walls_out_of_its_reach_do_not() {
    let maze = generate(&GenOptions::walk(20, 15, 71)).expect("maze");
    let dark = without_exit(&maze);
    let light = ExitLight::of(&maze);
    let mut near_walls = 0;
    let mut far_walls = 0;
    let mut shares = Vec::new();
    for cell in 0..maze.cell_count() as u32 {
        let level = light.level(cell);
        for heading in [0.0, 90.0, 180.0, 270.0] {
            let camera = cell_camera(&maze, cell, heading);
            let ((lit, ids), (unlit, _)) = (samples(&maze, &camera), samples(&dark, &camera));
            // The wall straight ahead, in the middle of the view, if it belongs to this cell.
            let middle = (ids.len() / 120 / 2) * 120 + 60;
            let id = ids[middle];
            let Some(&e) = maze.cell_edges(cell).iter().find(|&&e| e == id) else { continue };
            assert!(maze.edge(e).opaque);
            let (a, b) = (lit[middle], unlit[middle]);
            if level == 0 {
                assert_eq!(a, b, "cell {cell} (no light) heading {heading}: wall {e} changed");
                far_walls += 1;
            } else {
                // The wall's own colour tinted toward the exit's green (`shade::exit_lit_wall`):
                // greener than unlit (its OKLab (a, b) along the beacon's hue more by 0.02), its
                // chroma no more than 0.17 of its lightness (the beacon's 0.18), no darker than 0.9
                // of the wall unlit, and lighter within the last seven cells (1.1 times, or the
                // lightness cap 0.84 reached).
                let (lab, unlit) = (oklab(a), oklab(b));
                let g = oklab(EXIT_GLOW);
                let g = glam::Vec2::new(g.y, g.z).normalize();
                let green = |c: Vec3| glam::Vec2::new(c.y, c.z).dot(g);
                assert!(
                    green(lab) >= green(unlit) + 0.02,
                    "cell {cell} level {level}: {lab} against {unlit}"
                );
                let share = lab.y.hypot(lab.z) / lab.x;
                assert!(share <= 0.171, "cell {cell} level {level}: chroma {share} of L");
                shares.push((level, share));
                let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
                let ratio = luminance(a) / luminance(b);
                assert!(ratio > 0.9, "cell {cell} level {level}: {a} against {b}");
                if level >= 22 {
                    assert!(ratio >= 1.1 || lab.x >= 0.839, "cell {cell} level {level}: {a} against {b}");
                }
                near_walls += 1;
            }
        }
    }
    assert!(near_walls >= 8, "walls faced within the light's reach: {near_walls}");
    assert!(
        shares.iter().any(|&(l, _)| l <= 3) && shares.iter().any(|&(l, _)| l >= 26),
        "walls faced at both ends of the light: {shares:?}"
    );
    assert!(far_walls >= 100, "walls faced beyond it: {far_walls}");
}

/// Issue #39: in 16 colours the walls of a lit cell, seen from inside it at each heading, show the
/// glow's dark green (xterm's 2, or black) and nothing else, never the beacon's bright green; the
/// walls of a cell out of the light's reach are as in the maze without an exit (shown colours,
/// inside walls: an edge sample depends on its neighbours).
#[test]
fn sixteen_colours_show_the_glow_as_the_dark_green_on_lit_walls_only() {
    let maze = generate(&GenOptions::walk(20, 15, 71)).expect("maze");
    let dark = without_exit(&maze);
    let light = ExitLight::of(&maze);
    let render = |maze: &Maze, camera: &Camera| shown(maze, camera, ColorDepth::Ansi16);
    let oklab_of = |rgb: [u8; 3]| {
        let lin = rgb.map(|v| mazewalk_render::shade::srgb_to_linear(f32::from(v) / 255.0));
        Vec3::from_array(mazewalk_term::frame::oklab(lin, f32::cbrt))
    };
    let xterm = |i: u8| oklab_of(mazewalk_render::palette::xterm_rgb(i));
    let (glow_green, black) = (xterm(2), xterm(0));
    let (mut lit_samples, mut dark_samples) = (0, 0);
    for cell in (0..maze.cell_count() as u32)
        .step_by(3)
        .chain((0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0))
    {
        let level = light.level(cell);
        for heading in [0.0, 90.0, 180.0, 270.0] {
            let camera = cell_camera(&maze, cell, heading);
            let ((lit, ids), (unlit, _)) = (render(&maze, &camera), render(&dark, &camera));
            let own = maze.cell_edges(cell);
            for k in (0..ids.len()).filter(|&k| own.contains(&ids[k]) && inside(&ids, k)) {
                if level > 0 {
                    assert!(
                        lit[k].distance(glow_green) < 1e-3 || lit[k].distance(black) < 1e-3,
                        "cell {cell} level {level} heading {heading} sample {k}: {}",
                        lit[k]
                    );
                    lit_samples += 1;
                } else {
                    assert_eq!(lit[k], unlit[k], "cell {cell} heading {heading} sample {k}");
                    dark_samples += 1;
                }
            }
        }
    }
    assert!(lit_samples > 1000 && dark_samples > 1000, "{lit_samples} lit, {dark_samples} dark");
}

/// OKLab `b` is toward the exit's look from `a` by a visible step in 256 colours: its (a, b) along
/// the glow's hue more by 0.02 and at most a little darker, or lighter by 0.03 and at most a little
/// less green.
fn toward_glow(a: Vec3, b: Vec3) -> bool {
    let g = oklab(EXIT_GLOW);
    let g = glam::Vec2::new(g.y, g.z).normalize();
    let (ga, gb) = (glam::Vec2::new(a.y, a.z).dot(g), glam::Vec2::new(b.y, b.z).dot(g));
    (gb >= ga + 0.02 && b.x >= a.x - 0.03) || (b.x >= a.x + 0.03 && gb >= ga - 0.02)
}

/// Issue #39, in 256 colours over three generated mazes: from inside every lit cell at each heading,
/// every sample inside one of the cell's own walls shows an entry no less green (its OKLab (a, b)
/// along the glow's hue) than the same wall's without the exit's light, and at least four in five
/// one greener by 0.02 (side walls and walls faced square on alike, near and across the cell; a
/// wall whose hue is opposite the glow's may show a grey there, greener than its own but darker).
#[test]
fn in_256_colours_every_lit_wall_leans_toward_the_glow_from_its_own_colour() {
    let (mut judged, mut toward) = (0, 0);
    let g = oklab(EXIT_GLOW);
    let g = glam::Vec2::new(g.y, g.z).normalize();
    let green = |c: Vec3| glam::Vec2::new(c.y, c.z).dot(g);
    let mut levels_seen = std::collections::BTreeSet::new();
    for seed in [71u64, 3, 74174] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let dark = without_exit(&maze);
        let light = ExitLight::of(&maze);
        let render = |maze: &Maze, camera: &Camera| shown(maze, camera, ColorDepth::Ansi256);
        for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0) {
            for heading in [0.0, 90.0, 180.0, 270.0] {
                let camera = cell_camera(&maze, cell, heading);
                let ((lit, ids), (unlit, _)) = (render(&maze, &camera), render(&dark, &camera));
                let own = maze.cell_edges(cell);
                for k in (0..ids.len()).filter(|&k| own.contains(&ids[k]) && inside(&ids, k)) {
                    let (a, b) = (lit[k], unlit[k]);
                    let why = format!(
                        "seed {seed} cell {cell} level {} heading {heading} sample {k}: {a} against {b}",
                        light.level(cell)
                    );
                    assert!(green(a) >= green(b) - 0.005, "{why}");
                    toward += usize::from(green(a) >= green(b) + 0.02);
                    judged += 1;
                    levels_seen.insert(light.level(cell));
                }
            }
        }
    }
    assert!(judged > 10_000, "{judged}");
    assert!(toward * 5 >= judged * 4, "{toward} of {judged} a step toward the glow");
    assert!(levels_seen.contains(&1) && levels_seen.contains(&28), "{levels_seen:?}");
}

/// The entries (OKLab) that walls of one kind and colour show in 256 colours from the centre of every
/// lit cell of `seeds`' mazes, each maze generated again with every wall one of five generated
/// colours, by the colour, the wall's orientation (so one side to the sun) and the cell's level:
/// `faced` the cell's own wall straight ahead (2 units off, square on), `side` its own wall at the
/// view's edge (along the view, as far off at every cell).
type LikeWalls = std::collections::BTreeMap<(usize, u8, u8), Vec<Vec3>>;
fn like_walls(seeds: &[u64]) -> [LikeWalls; 2] {
    use mazewalk_maze::generate::WALL_COLOURS;
    let mut kinds: [LikeWalls; 2] = Default::default();
    for (c, colour) in [0usize, 20, 40, 60, 80].into_iter().enumerate() {
        let srgb = Vec3::from_array(WALL_COLOURS[colour].map(f32::from)) / 255.0;
        for &seed in seeds {
            let options = GenOptions { palette: Some(vec![srgb]), ..GenOptions::walk(20, 15, seed) };
            let maze = generate(&options).expect("maze");
            let light = ExitLight::of(&maze);
            for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0) {
                let level = light.level(cell);
                for (h, heading) in [0.0, 90.0, 180.0, 270.0].into_iter().enumerate() {
                    let camera = cell_camera(&maze, cell, heading);
                    let (shown, ids) = shown(&maze, &camera, ColorDepth::Ansi256);
                    let h = h as u8;
                    let own = maze.cell_edges(cell);
                    let row = ids.len() / 120 / 2;
                    let middle = row * 120 + 60;
                    if own.contains(&ids[middle]) && inside(&ids, middle) {
                        kinds[0].entry((c, h, level)).or_default().push(shown[middle]);
                    }
                    for (k, right) in [(row * 120 + 2, 0), (row * 120 + 117, 1)] {
                        if ids[k] != ids[middle] && own.contains(&ids[k]) && inside(&ids, k) {
                            kinds[1].entry((c, h * 2 + right, level)).or_default().push(shown[k]);
                        }
                    }
                }
            }
        }
    }
    kinds
}

/// Issue #39, "which way": in 256 colours, walls of one colour and kind seen from the centres of
/// lit cells (the cell's own wall straight ahead, square on; its own wall at the view's edge, along
/// it) in two generated mazes drawn in each of five wall colours: from a cell a look (seven cells
/// of path) or more nearer the exit, at least two in five show a visible step toward the glow's
/// look ([`toward_glow`]: greener or lighter), at most one in ten a step back; from one across
/// the whole reach (21 or more nearer: the first look against the last) at least three in four.
#[test]
fn in_256_colours_like_walls_get_greener_or_lighter_toward_the_exit() {
    let [faced, side] = like_walls(&[71, 3]);
    for (name, kind) in [("faced", &faced), ("side", &side)] {
        let levels: std::collections::BTreeSet<u8> = kind.keys().map(|&(_, _, l)| l).collect();
        assert!(levels.len() >= 26, "{name}: levels seen {levels:?}");
        let (mut look, mut reach) = ([0usize; 3], [0usize; 2]); // (toward, back, all), (toward, all)
        for (&(c, o, a), at_a) in kind {
            for (&(_, _, b), at_b) in kind.range((c, o, a + 7)..(c, o + 1, 0)) {
                for (x, y) in at_a.iter().flat_map(|x| at_b.iter().map(move |y| (x, y))) {
                    look[0] += usize::from(toward_glow(*x, *y));
                    look[1] += usize::from(toward_glow(*y, *x));
                    look[2] += 1;
                    if b >= a + 21 {
                        reach[0] += usize::from(toward_glow(*x, *y));
                        reach[1] += 1;
                    }
                }
            }
        }
        eprintln!("{name}: a look or more: {look:?}; the reach: {reach:?}");
        assert!(look[2] > 1000 && reach[1] > 50, "{name}: {look:?} {reach:?}");
        assert!(look[0] * 5 >= look[2] * 2, "{name}: toward the glow {} of {}", look[0], look[2]);
        assert!(look[1] * 10 <= look[2], "{name}: back {} of {}", look[1], look[2]);
        assert!(reach[0] * 4 >= reach[1] * 3, "{name}: over the reach {} of {}", reach[0], reach[1]);
    }
}

/// Whether walls `a` and `b` of `maze` lie on one line (a side wall and the next cell's).
fn walls_in_a_line(maze: &Maze, a: u32, b: u32) -> bool {
    let ((p, q), (r, s)) = (maze.edge_points(a), maze.edge_points(b));
    let d = q - p;
    let off = |x: glam::Vec2| d.perp_dot(x - p).abs() / d.length();
    off(r) < 1e-3 && off(s) < 1e-3
}

/// Whether wall `e` borders a cell the exit's light reaches.
fn lit_by_the_exit(maze: &Maze, light: &ExitLight, e: u32) -> bool {
    let edge = maze.edge(e);
    [edge.left, edge.right].iter().flatten().any(|&c| light.level(c) > 0)
}

/// How many of the boundaries between two lit walls (in a line: `seams`; at an angle: corners) on
/// rows 16, 20 and 24 of 120×40 views from every lit cell at four headings, in five 20×15 mazes,
/// show a colour step on either side in `depths` (the OKLab distance 0.02 and more), and how many
/// there are: one (shown, all) per depth.
fn lit_boundaries_shown(depths: &[ColorDepth], seams: bool) -> Vec<(usize, usize)> {
    let mut counts = vec![(0usize, 0usize); depths.len()];
    wall_boundaries(depths, true, |d, _, b| {
        if b.lit != [true, true] || b.in_a_line != seams {
            return;
        }
        let (shown, k) = (b.shown, b.k);
        let shows = shown[k].distance(shown[k - 2]) > 0.02 || shown[k + 1].distance(shown[k + 3]) > 0.02;
        counts[d].0 += usize::from(shows);
        counts[d].1 += 1;
    });
    counts
}

/// A boundary between two walls on a row of a 120×40 view, each seen two samples either side of it
/// (the left wall's last sample is `k`): the view's colours as shown, whether each wall borders a
/// cell the exit's light reaches, and whether the two lie in a line.
struct Boundary<'a> {
    shown: &'a [Vec3],
    k: usize,
    lit: [bool; 2],
    in_a_line: bool,
}

/// Every [`Boundary`] (each wall seen above and below it too: on a wall's top or bottom edge row the
/// edge is drawn there, not the seam; the foveated view's magnified middle puts such rows among those
/// judged) on rows 16, 20 and 24 of the 120×40 views in each of `depths` (`visit`'s
/// first argument is its index) from the centre of every cell (only the lit ones if `lit_only`;
/// its second argument: whether the cell is lit) at four headings, in five 20×15 generated mazes.
fn wall_boundaries(depths: &[ColorDepth], lit_only: bool, mut visit: impl FnMut(usize, bool, Boundary)) {
    for seed in [71u64, 3, 74174, 12255, 98794] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let light = ExitLight::of(&maze);
        let walls = maze.edges().len() as u32;
        for cell in 0..maze.cell_count() as u32 {
            let lit_cell = light.level(cell) > 0;
            if lit_only && !lit_cell {
                continue;
            }
            for heading in [0.0, 90.0, 180.0, 270.0] {
                let camera = cell_camera(&maze, cell, heading);
                for (d, &depth) in depths.iter().enumerate() {
                    let (shown, ids) = shown(&maze, &camera, depth);
                    for row in [16usize, 20, 24] {
                        for x in 3..116 {
                            let (k, a, b) = (row * 120 + x, ids[row * 120 + x], ids[row * 120 + x + 1]);
                            // (each wall seen above and below too: not on its top or bottom edge's
                            // row, where the edge, not the seam, is drawn)
                            let upright = |j: usize, id: u32| ids[j - 120] == id && ids[j + 120] == id;
                            if a == b
                                || a >= walls
                                || b >= walls
                                || ids[k - 2] != a
                                || ids[k + 3] != b
                                || !upright(k - 2, a)
                                || !upright(k + 3, b)
                            {
                                continue;
                            }
                            let lit = [lit_by_the_exit(&maze, &light, a), lit_by_the_exit(&maze, &light, b)];
                            let in_a_line = walls_in_a_line(&maze, a, b);
                            visit(d, lit_cell, Boundary { shown: &shown, k, lit, in_a_line });
                        }
                    }
                }
            }
        }
    }
}

/// Issue #39: two lit walls meeting in a line (one cell's side wall and the next's) are two walls,
/// not one: the seam the edge pass draws between them shows. Over five generated mazes, from the
/// centre of every lit cell at four headings, every boundary on three rows between two such walls
/// (both lit, both seen two samples either side of it): in truecolor the seam's samples differ from
/// the walls' (0.02 in OKLab) at every one; in 256 colours at least two in five; in 16 colours, where
/// a lit wall is one dark green, the seams are drawn black and show at 97 in 100 or more. At
/// `de48035` (the light reaching 27 cells): 2,034 of 2,034, 1,492 and 2,023. (By `721aa90`, the
/// light reaching 15 cells, 586 seams: 286 in 256 colours at `GLOW_STEPS`, 176 with the glow's chroma
/// growing by level and the luminance kept, the seam, 0.7 of the wall's light, inside the wide entry
/// (95, 135, 95) of side walls; in 16 colours, the seams drawn as darker shades of the same dark
/// green, 1.)
#[test]
fn seams_between_lit_walls_in_a_line_show() {
    let depths = [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16];
    let counts = lit_boundaries_shown(&depths, true);
    let [(true_shown, true_all), (shown_256, all_256), (shown_16, all_16)] = counts[..] else {
        unreachable!()
    };
    assert!(true_all > 300 && true_shown == true_all, "truecolor: {true_shown} of {true_all}");
    assert!(shown_256 * 5 >= all_256 * 2, "256 colours: {shown_256} of {all_256}");
    // In 16 colours every lit wall is one dark green: the seams are drawn black (2,023 of 2,034 at
    // `de48035`; drawn as darker shades of the wall, which are the same dark green: 1 of 586).
    assert!(all_16 > 300 && shown_16 * 100 >= all_16 * 97, "16 colours: {shown_16} of {all_16}");
}

/// Issue #39: in 16 colours a corner between two lit walls shows, as it does in truecolor (lit
/// walls there are one dark green, their corners' darker shades too).
#[test]
fn corners_between_lit_walls_show_in_16_colours() {
    let counts = lit_boundaries_shown(&[ColorDepth::TrueColor, ColorDepth::Ansi16], false);
    let [(true_shown, true_all), (shown_16, all_16)] = counts[..] else { unreachable!() };
    // 1,906 of 1,906 at `de48035` (as darker shades of the dark green, of 478 then: 128)
    assert!(true_all > 300 && true_shown == true_all, "truecolor: {true_shown} of {true_all}");
    assert!(
        shown_16 * 100 >= all_16 * 97,
        "16 colours: {shown_16} of {all_16} (truecolor {true_shown} of {true_all})"
    );
}

/// The seams between two walls in a line (one cell's side wall and the next's) on rows 16, 20 and 24
/// of 120×40 views from cells' centres at four headings, in five 20×15 mazes, whose two walls show
/// different colours in `depth` (the samples two either side of the seam, 0.02 apart in OKLab or
/// more): (apart, all) where both walls are lit by the exit's light, seen from every lit cell, and
/// where neither is, seen from every unlit cell.
fn seam_sides_apart(depth: ColorDepth) -> [(usize, usize); 2] {
    let mut counts = [(0usize, 0usize); 2];
    wall_boundaries(&[depth], false, |_, lit_cell, b| {
        if !b.in_a_line || b.lit != [lit_cell; 2] {
            return;
        }
        let count = &mut counts[usize::from(!lit_cell)];
        count.0 += usize::from(b.shown[b.k - 2].distance(b.shown[b.k + 3]) > 0.02);
        count.1 += 1;
    });
    counts
}

/// Issue #39: inside the exit's light walls keep their cells. A seam between two walls in a line
/// (where a player counts cells along a side wall, or tells a wall seen through an opening from the
/// end wall) has two colours on its two sides as often among lit walls as among unlit ones, within
/// ten points, in truecolor and 256 colours (before, one green for every lit wall: 7 % and 11 % of
/// 586 lit seams, against 100 % of 2,220 unlit ones). 16 colours draw lit walls one dark green and
/// mark their seams with lines instead (`seams_between_lit_walls_in_a_line_show`).
#[test]
fn lit_walls_in_a_line_keep_their_own_colours_as_unlit_ones_do() {
    for depth in [ColorDepth::TrueColor, ColorDepth::Ansi256] {
        let [lit, unlit] = seam_sides_apart(depth);
        let share = |(apart, all): (usize, usize)| 100.0 * apart as f64 / all as f64;
        eprintln!("{depth:?}: lit {lit:?} {:.1} %, unlit {unlit:?} {:.1} %", share(lit), share(unlit));
        assert!(lit.1 > 1000 && unlit.1 > 500, "{depth:?}: {lit:?} {unlit:?}");
        assert!(share(lit) >= share(unlit) - 10.0, "{depth:?}: lit {lit:?}, unlit {unlit:?}");
    }
}
