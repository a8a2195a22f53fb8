//! Issue #39: the exit's light spills down the corridors (block light, `mazewalk_maze::light`): walls
//! within fifteen cells' path of the exit turn the exit's green, pale at the edge of its reach and
//! greener closer, in truecolor, 256 and 16 colours; walls beyond its reach, or behind a wall from
//! it, are drawn as in a maze without an exit.

use glam::Vec3;
use mazewalk_maze::Maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_maze::light::ExitLight;
use mazewalk_render::{Camera, Charset, RenderOptions, Renderer, Target, quality};
use mazewalk_term::frame::{ColorDepth, Frame};

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
    let mut frame = Frame::new(120, 40);
    let region = frame.region();
    let mut renderer = Renderer::new();
    let options = RenderOptions { color_depth: ColorDepth::TrueColor, ..RenderOptions::default() };
    renderer.render(maze, camera, &[], &options, Target::Frame(&mut frame, region)).expect("camera");
    (renderer.samples().color().to_vec(), renderer.samples().id().to_vec())
}

/// What the terminal shows on each sample of `camera`'s view in `depth` (OKLab, half blocks,
/// 120×40), and the samples' ids.
fn shown(maze: &Maze, camera: &Camera, depth: ColorDepth) -> (Vec<Vec3>, Vec<u32>) {
    let mut frame = Frame::new(120, 40);
    let region = frame.region();
    let mut renderer = Renderer::new();
    let options = RenderOptions { color_depth: depth, ..RenderOptions::default() };
    renderer.render(maze, camera, &[], &options, Target::Frame(&mut frame, region)).expect("camera");
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

/// The difference of two OKLab hue angles (radians), 0..=π.
fn hue_off(a: Vec3, b: Vec3) -> f32 {
    let d = (a.z.atan2(a.y) - b.z.atan2(b.y)).abs() % std::f32::consts::TAU;
    d.min(std::f32::consts::TAU - d)
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
                // The exit's green (the beacon's hue), its chroma a share of its lightness (OKLab
                // C ⁄ L) between the faintest glow's 0.10 and the exit's 0.125, well below the
                // beacon's 0.18, and lighter toward the exit (truecolor, the steps of
                // `shade::GLOW_STEPS`, of the wall's lightness, so within the 10 % by which generated
                // walls' luminances differ with their hue): no darker than 0.8 of the wall unlit at
                // the edge of the reach, at least 1.1 times it within the five cells round the exit.
                let lab = oklab(a);
                assert!(
                    hue_off(lab, oklab(EXIT_GLOW)) < 12f32.to_radians(),
                    "cell {cell} level {level}: {lab}"
                );
                let share = lab.y.hypot(lab.z) / lab.x;
                assert!((0.095..0.13).contains(&share), "cell {cell} level {level}: chroma {share} of L");
                shares.push((level, share));
                let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
                let ratio = luminance(a) / luminance(b);
                assert!(ratio > 0.8, "cell {cell} level {level}: {a} against {b}");
                if level >= 12 {
                    assert!(ratio >= 1.1, "cell {cell} level {level}: {a} against {b}");
                }
                near_walls += 1;
            }
        }
    }
    assert!(near_walls >= 8, "walls faced within the light's reach: {near_walls}");
    assert!(
        shares.iter().any(|&(l, _)| l <= 3) && shares.iter().any(|&(l, _)| l >= 14),
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

/// Issue #39, in 256 colours over three generated mazes: from inside every lit cell at each heading,
/// every sample inside one of the cell's own walls shows an entry a palette step (0.03 in OKLab) off
/// the same wall without the exit's light, coloured, and closer in hue to the glow than to any
/// generated wall colour (side walls and walls faced square on alike, near and across the cell);
/// and walls faced square on near the exit show a greener entry than far from it.
#[test]
fn in_256_colours_every_lit_wall_shows_the_glows_hue_a_step_off_its_own() {
    use mazewalk_maze::generate::WALL_COLOURS;
    let hue = |lab: Vec3| lab.z.atan2(lab.y);
    let off = |a: f32, b: f32| {
        let d = (a - b).abs() % std::f32::consts::TAU;
        d.min(std::f32::consts::TAU - d)
    };
    let oklab_of = |rgb: [u8; 3]| {
        let lin = rgb.map(|v| mazewalk_render::shade::srgb_to_linear(f32::from(v) / 255.0));
        Vec3::from_array(mazewalk_term::frame::oklab(lin, f32::cbrt))
    };
    let glow_hue = hue(Vec3::from_array(mazewalk_term::frame::oklab(EXIT_GLOW.to_array(), f32::cbrt)));
    let wall_hues: Vec<f32> = WALL_COLOURS.iter().map(|&c| hue(oklab_of(c))).collect();
    let mut judged = 0;
    let mut levels_seen = std::collections::BTreeSet::new();
    let mut faced = Vec::new();
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
                    assert!(a.distance(b) >= 0.03, "{why}");
                    assert!(a.y.hypot(a.z) > 0.04, "grey: {why}");
                    assert!(wall_hues.iter().all(|&h| off(hue(a), glow_hue) < off(hue(a), h)), "{why}");
                    judged += 1;
                    levels_seen.insert(light.level(cell));
                }
                // The wall straight ahead, faced square on: its chroma, to compare near and far.
                let middle = (ids.len() / 120 / 2) * 120 + 60;
                if own.contains(&ids[middle]) && inside(&ids, middle) {
                    faced.push((light.level(cell), lit[middle].y.hypot(lit[middle].z)));
                }
            }
        }
    }
    assert!(judged > 10_000, "{judged}");
    assert!(levels_seen.contains(&1) && levels_seen.contains(&16), "{levels_seen:?}");
    // Greener or lighter nearer: `in_256_colours_like_walls_get_greener_or_lighter_toward_the_exit`.
    assert!(faced.len() >= 40, "{faced:?}");
}

/// The entries (OKLab) that walls of one kind show in 256 colours from the centre of every lit cell
/// of `seeds`' mazes, by the wall's orientation (so one side to the sun) and the cell's level:
/// `faced` the cell's own wall straight ahead (2 units off, square on), `side` its own wall at the
/// view's edge (along the view, as far off at every cell).
fn like_walls(seeds: &[u64]) -> [std::collections::BTreeMap<(u8, u8), Vec<Vec3>>; 2] {
    let mut kinds: [std::collections::BTreeMap<(u8, u8), Vec<Vec3>>; 2] = Default::default();
    for &seed in seeds {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
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
                    kinds[0].entry((h, level)).or_default().push(shown[middle]);
                }
                for (k, right) in [(row * 120 + 2, 0), (row * 120 + 117, 1)] {
                    if ids[k] != ids[middle] && own.contains(&ids[k]) && inside(&ids, k) {
                        kinds[1].entry((h * 2 + right, level)).or_default().push(shown[k]);
                    }
                }
            }
        }
    }
    kinds
}

/// OKLab `b` is greener or lighter than `a` by a visible step in 256 colours: lighter by 0.03 and
/// at most a little less saturated, or more saturated by 0.02 and at most a little darker.
fn greener_or_lighter(a: Vec3, b: Vec3) -> bool {
    let (ca, cb) = (a.y.hypot(a.z), b.y.hypot(b.z));
    (b.x >= a.x + 0.03 && cb >= ca - 0.035) || (cb >= ca + 0.02 && b.x >= a.x - 0.03)
}

/// Issue #39, "which way": in 256 colours, over five generated mazes, walls of one kind seen from
/// the centres of lit cells (the cell's own wall straight ahead, square on; its own wall at the
/// view's edge, along it) get greener or lighter by a visible step toward the exit and never the
/// reverse: every wall faced square on from a cell at least six levels (cells of path) nearer the
/// exit shows a greener or lighter entry than every one from the further cell, and along the view
/// at least eleven levels nearer; over the reach each kind shows at least two looks (faced three);
/// and at the first and last steps the two kinds show different entries (a corner between two lit
/// walls changes colour).
#[test]
fn in_256_colours_like_walls_get_greener_or_lighter_toward_the_exit() {
    let [faced, side] = like_walls(&[71, 3, 74174, 12255, 98794]);
    let mut judged = 0;
    for (name, kind, apart) in [("faced", &faced, 6u8), ("side", &side, 11)] {
        let levels: std::collections::BTreeSet<u8> = kind.keys().map(|&(_, l)| l).collect();
        assert!(levels.len() == 16, "{name}: levels seen {levels:?}");
        let mut looks = Vec::new();
        for (&(o, a), at_a) in kind {
            for (&(_, b), at_b) in kind.range((o, a + 1)..(o + 1, 0)) {
                for (x, y) in at_a.iter().flat_map(|x| at_b.iter().map(move |y| (x, y))) {
                    let why = format!("{name} {o}: level {a} {x} against level {b} {y}");
                    if b >= a + apart {
                        assert!(greener_or_lighter(*x, *y), "not a step toward the exit: {why}");
                    } else {
                        assert!(!greener_or_lighter(*y, *x), "backwards: {why}");
                    }
                    judged += 1;
                }
            }
            for c in at_a {
                if !looks.iter().any(|l: &Vec3| l.distance(*c) < 1e-4) {
                    looks.push(*c);
                }
            }
        }
        assert!(looks.len() >= if name == "faced" { 3 } else { 2 }, "{name}: {looks:?}");
    }
    assert!(judged > 10_000, "{judged}");
    // corners: a cell's faced wall against its side walls, seen at one heading
    for ((o, level), at) in &faced {
        if [1, 2, 15, 16].contains(level) {
            for s in [2 * o, 2 * o + 1].iter().filter_map(|&so| side.get(&(so, *level))).flatten() {
                assert!(
                    at.iter().all(|f| f.distance(*s) > 0.03),
                    "level {level} heading {o}: corner {at:?} {s}"
                );
            }
        }
    }
}

/// Issue #39: two lit walls meeting in a line (one cell's side wall and the next's) are two walls,
/// not one: the seam the edge pass draws between them shows. Over five generated mazes, from the
/// centre of every lit cell at four headings, every boundary on three rows between two such walls
/// (both lit, both seen two samples either side of it): in truecolor the seam's samples differ from
/// the walls' (0.02 in OKLab) at every one; in 256 colours at least two in five (286 of 586 at
/// `GLOW_STEPS`; 176 with the glow's chroma growing by level and the luminance kept, the seam, 0.7 of
/// the wall's light, inside the wide entry (95, 135, 95) of side walls). In 16 colours a lit wall
/// shows one dark green and its seams do not show (1 of 586).
/// How many of the boundaries between two lit walls (in a line: `seams`; at an angle: corners) on
/// rows 16, 20 and 24 of 120×40 views from every lit cell at four headings, in five 20×15 mazes,
/// show a colour step on either side in `depths` (the OKLab distance 0.02 and more), and how many
/// there are: one (shown, all) per depth.
fn lit_boundaries_shown(depths: &[ColorDepth], seams: bool) -> Vec<(usize, usize)> {
    let mut counts = vec![(0usize, 0usize); depths.len()];
    for seed in [71u64, 3, 74174, 12255, 98794] {
        let maze = generate(&GenOptions::walk(20, 15, seed)).expect("maze");
        let light = ExitLight::of(&maze);
        let walls = maze.edges().len() as u32;
        let collinear = |a: u32, b: u32| {
            let ((p, q), (r, s)) = (maze.edge_points(a), maze.edge_points(b));
            let d = q - p;
            let off = |x: glam::Vec2| d.perp_dot(x - p).abs() / d.length();
            off(r) < 1e-3 && off(s) < 1e-3
        };
        let lit_wall = |e: u32| {
            let edge = maze.edge(e);
            [edge.left, edge.right].iter().flatten().any(|&c| light.level(c) > 0)
        };
        for cell in (0..maze.cell_count() as u32).filter(|&c| light.level(c) > 0) {
            for heading in [0.0, 90.0, 180.0, 270.0] {
                let camera = cell_camera(&maze, cell, heading);
                for (d, &depth) in depths.iter().enumerate() {
                    let (shown, ids) = shown(&maze, &camera, depth);
                    for row in [16usize, 20, 24] {
                        for x in 3..116 {
                            let (k, a, b) = (row * 120 + x, ids[row * 120 + x], ids[row * 120 + x + 1]);
                            if a == b || a >= walls || b >= walls || !lit_wall(a) || !lit_wall(b) {
                                continue;
                            }
                            if ids[k - 2] != a || ids[k + 3] != b || collinear(a, b) != seams {
                                continue;
                            }
                            let shows = shown[k].distance(shown[k - 2]) > 0.02
                                || shown[k + 1].distance(shown[k + 3]) > 0.02;
                            counts[d].0 += usize::from(shows);
                            counts[d].1 += 1;
                        }
                    }
                }
            }
        }
    }
    counts
}

#[test]
fn seams_between_lit_walls_in_a_line_show() {
    let depths = [ColorDepth::TrueColor, ColorDepth::Ansi256, ColorDepth::Ansi16];
    let counts = lit_boundaries_shown(&depths, true);
    let [(true_shown, true_all), (shown_256, all_256), (shown_16, all_16)] = counts[..] else {
        unreachable!()
    };
    assert!(true_all > 300 && true_shown == true_all, "truecolor: {true_shown} of {true_all}");
    assert!(shown_256 * 5 >= all_256 * 2, "256 colours: {shown_256} of {all_256}");
    // In 16 colours every lit wall is one dark green: the seams are drawn black (583 of 586; before,
    // drawn as darker shades of the wall, which are the same dark green: 1 of 586).
    assert!(all_16 > 300 && shown_16 * 100 >= all_16 * 97, "16 colours: {shown_16} of {all_16}");
}

/// Issue #39: in 16 colours a corner between two lit walls shows, as it does in truecolor (lit
/// walls there are one dark green, their corners' darker shades too).
#[test]
fn corners_between_lit_walls_show_in_16_colours() {
    let counts = lit_boundaries_shown(&[ColorDepth::TrueColor, ColorDepth::Ansi16], false);
    let [(true_shown, true_all), (shown_16, all_16)] = counts[..] else { unreachable!() };
    // 478 of 478 (before, as darker shades of the dark green: 128 of 478)
    assert!(true_all > 300 && true_shown == true_all, "truecolor: {true_shown} of {true_all}");
    assert!(
        shown_16 * 100 >= all_16 * 97,
        "16 colours: {shown_16} of {all_16} (truecolor {true_shown} of {true_all})"
    );
}
