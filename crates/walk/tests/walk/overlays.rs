//! Overlays for players (issue #33): the HUD's compass point and ticking clock, the corner map sized
//! to what has been seen, the full map's walls and viewer, the exit box that any key closes, the
//! question before a stray q quits a long walk, and a help that tells of the exit. Screens as text,
//! through the Session's bytes where the HUD's timing matters.

use glam::Vec2;
use mazewalk_maze as maze;
use mazewalk_maze::generate::{GenOptions, generate};
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::{Color, ColorDepth, Frame};
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::overlay::{self, MapArea, MapCells, Style};
use mazewalk_walk::state::{CONFIRM_QUIT_AFTER, EXIT_BOX_GRACE};
use mazewalk_walk::{App, Session, SessionOptions};

fn session(maze: maze::Maze, cols: u16, rows: u16) -> Session {
    let app = App::new(maze, RenderOptions::default(), 0.0).unwrap();
    Session::new(app, cols, rows, SessionOptions { flow_control: false, ..SessionOptions::default() })
}

fn hud(s: &Session) -> String {
    s.screen().lines().last().unwrap().clone()
}

/// Two cells side by side, the exit in the east one; the viewer starts in the west one facing it.
fn two_cells() -> maze::Maze {
    let m = generate(&GenOptions { width: 2, height: 1, exit: true, ..GenOptions::default() }).unwrap();
    assert!(m.exit().is_some());
    m
}

/// An app in [`two_cells`] that faces the exit.
fn facing_the_exit() -> App {
    let mut app = App::new(two_cells(), RenderOptions::default(), 0.0).unwrap();
    let to_exit = app.maze().exit_point().unwrap() - app.camera.position;
    app.camera.yaw_deg = to_exit.to_angle().to_degrees();
    app
}

#[test]
fn the_hud_shows_where_the_player_faces_and_how_many_are_in() {
    let mut s = session(maze::builtin().unwrap(), 160, 30);
    s.set_players_in(Some(3));
    s.frame(0.0, &mut Vec::new());
    let line = hud(&s);
    assert!(line.starts_with(" heading 0° E  time 0:00  3 in"), "{line:?}");
    assert!(!line.contains("fps") && !line.contains("cell "), "no developer figures: {line:?}");
    s.feed(b"i", 0.1); // the developer figures
    s.frame(0.1, &mut Vec::new());
    assert!(hud(&s).contains(" fps ") && hud(&s).contains("cell "), "{:?}", hud(&s));
    s.set_players_in(None);
    s.frame(0.5, &mut Vec::new());
    assert!(!hud(&s).contains(" in "), "{:?}", hud(&s));
}

// issue #33: the exit clock ticks every second while it runs, standing still too, for a few bytes.
#[test]
fn the_exit_clock_ticks_every_second_for_a_few_bytes() {
    let mut s = session(maze::builtin().unwrap(), 120, 40);
    let mut out = Vec::new();
    s.frame(0.0, &mut out);
    for second in 1..=3u32 {
        let at = s.next_wake(f64::from(second) - 0.9).expect("the clock wakes the host");
        assert!((at - f64::from(second)).abs() < 1e-9, "wakes at the second: {at}");
        out.clear();
        assert!(s.frame(at, &mut out), "a frame at {at}");
        assert!(hud(&s).contains(&format!("time 0:0{second}")), "{:?}", hud(&s));
        assert!(out.len() < 60, "{} bytes for a tick", out.len());
    }
    // found: the clock stops (nothing more to draw)
    let mut s = session(two_cells(), 80, 24);
    s.app_mut().finished = Some(12.3);
    s.frame(0.0, &mut Vec::new());
    assert!(hud(&s).contains("exit in 0:12.3"), "{:?}", hud(&s));
    assert_eq!(s.next_wake(0.5), None);
    // no exit, no clock
    let mut s =
        session(generate(&GenOptions { width: 3, height: 3, ..GenOptions::default() }).unwrap(), 80, 24);
    s.frame(0.0, &mut Vec::new());
    assert_eq!(s.next_wake(0.5), None);
    assert!(!hud(&s).contains("time"), "{:?}", hud(&s));
}

// issue #33: the exit box closes with any key; Esc does not quit; a key held to walk into the exit
// does not close it before it is seen.
#[test]
fn the_exit_box_closes_with_any_key_and_esc_does_not_quit() {
    for (key, quits, resets) in [
        (Key::Char('x'), false, false),
        (Key::Esc, false, false),
        (Key::Char('w'), false, false),
        (Key::Char('q'), true, false),
        (Key::Char('r'), false, true),
    ] {
        let mut app = facing_the_exit();
        // W held without key releases: a press, then the auto-repeat every 33 ms until 3 s
        let mut t = 1.0;
        app.key(Key::Char('w'), KeyPhase::Press, t);
        t += 0.5;
        while t < 3.0 {
            app.key(Key::Char('w'), KeyPhase::Press, t);
            app.tick(t);
            t += 0.033;
        }
        assert!(app.finished.is_some() && app.exit_box, "walked into the exit, the box is up");
        assert!(!app.is_animating(t), "the box stopped the walk");
        let at = app.camera.position;
        app.key(key, KeyPhase::Press, t + EXIT_BOX_GRACE + 0.1);
        app.tick(t + 1.0);
        assert!(!app.exit_box, "{key:?} closes the box");
        assert_eq!(app.quit, quits, "{key:?}");
        assert_eq!(app.finished.is_none(), resets, "{key:?}");
        if !resets {
            assert_eq!(app.camera.position, at, "{key:?} only closes the box");
        }
    }
    // a key pressed at once after reaching the exit does not close the box unseen
    let mut app = facing_the_exit();
    let mut t = 1.0;
    while app.finished.is_none() {
        app.key(Key::Char('w'), KeyPhase::Press, t);
        app.tick(t + 0.1);
        t += 0.2;
    }
    assert!(app.exit_box);
    app.key(Key::Char('x'), KeyPhase::Press, t);
    assert!(app.exit_box, "within the grace");
    app.key(Key::Char('x'), KeyPhase::Press, t + EXIT_BOX_GRACE);
    assert!(!app.exit_box, "after it");
}

// issue #39: the exit box redrew as the host changed what it shows: its "first" line went when the
// host took its notice away, a few seconds in. While open it shows what it showed (the standings added
// when the records answer); only the HUD follows the world (players come and go).
#[test]
fn the_exit_box_holds_still_while_open() {
    let (cols, rows) = (100, 30);
    let mut s = session(two_cells(), cols, rows);
    let above_hud = |s: &Session| s.screen().lines()[..usize::from(rows) - 1].join("\n");
    let standings = |players: u32| {
        vec![
            String::new(),
            format!("Best times here ({players} players)"),
            " 1. ada  1:23.0  you".to_string(),
        ]
    };
    s.set_players_in(Some(2));
    s.app_mut().finished = Some(83.0);
    s.app_mut().exit_box = true;
    s.set_notice(Some("You reached the exit first, in 1:23.0!".into()));
    s.frame(0.0, &mut Vec::new());
    let opened = above_hud(&s);
    assert!(opened.contains("You found the exit in 1:23.0.") && opened.contains("exit first"), "{opened}");
    s.set_standings(standings(2)); // the records answered
    s.frame(0.5, &mut Vec::new());
    let shown = above_hud(&s);
    assert!(shown.contains("exit first") && shown.contains("Best times here (2 players)"), "{shown}");
    // the host takes the notice away, a player comes, the standings are asked again: the box stays
    s.set_notice(None);
    s.set_players_in(Some(3));
    s.set_standings(standings(3));
    for t in [5.0, 6.0, 30.0] {
        s.frame(t, &mut Vec::new());
        assert_eq!(above_hud(&s), shown, "at {t} s");
    }
    assert!(hud(&s).contains("3 in"), "{}", hud(&s));
    // closed, it holds nothing: opened again (the walk walked again), it shows what the host shows then
    s.feed(b"x", 31.0);
    s.frame(31.0, &mut Vec::new());
    assert!(!above_hud(&s).contains("Found the exit!"));
    s.set_standings(Vec::new());
    s.app_mut().exit_box = true;
    s.frame(32.0, &mut Vec::new());
    let again = above_hud(&s);
    assert!(
        again.contains("Found the exit!") && !again.contains("exit first") && !again.contains("Best"),
        "{again}"
    );
}

// issue #33: a stray q after more than a minute asks; q again quits, any other key walks on.
#[test]
fn a_stray_q_late_in_a_walk_asks_once() {
    let mut app = App::new(maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
    app.key(Key::Char('q'), KeyPhase::Press, CONFIRM_QUIT_AFTER + 1.0);
    assert!(app.confirm_quit && !app.quit, "asks");
    app.key(Key::Char('x'), KeyPhase::Press, CONFIRM_QUIT_AFTER + 2.0);
    assert!(!app.confirm_quit && !app.quit, "any other key walks on");
    app.key(Key::Char('q'), KeyPhase::Press, CONFIRM_QUIT_AFTER + 3.0);
    app.key(Key::Esc, KeyPhase::Press, CONFIRM_QUIT_AFTER + 4.0);
    assert!(!app.confirm_quit && !app.quit, "Esc walks on");
    app.key(Key::Char('q'), KeyPhase::Press, CONFIRM_QUIT_AFTER + 5.0);
    app.key(Key::Char('q'), KeyPhase::Press, CONFIRM_QUIT_AFTER + 6.0);
    assert!(app.quit, "q, q quits");
    // within the first minute q quits at once
    let mut early = App::new(maze::builtin().unwrap(), RenderOptions::default(), 0.0).unwrap();
    early.key(Key::Char('q'), KeyPhase::Press, 30.0);
    assert!(early.quit);
    // the box says so
    let mut s = session(maze::builtin().unwrap(), 80, 24);
    s.feed(b"q", CONFIRM_QUIT_AFTER + 1.0);
    s.frame(CONFIRM_QUIT_AFTER + 1.0, &mut Vec::new());
    let text = s.screen().lines().join("\n");
    assert!(text.contains("Quit?") && text.contains("q    quit") && !s.is_over(), "{text}");
}

/// The map characters drawn in `area` that are not the view's (a box over it is the map's).
fn map_text(frame: &Frame, area: &MapArea) -> Vec<String> {
    (area.y..area.y + area.height)
        .map(|y| (area.x..area.x + area.width).map(|x| frame.get(x, y).unwrap().ch).collect())
        .collect()
}

// issue #33: the corner map takes at most a sixth of the screen at 120×40, and at the start it is
// what has been seen, not a mostly empty black box.
#[test]
fn the_corner_map_is_small_and_sized_to_what_has_been_seen() {
    let mut s = session(maze::builtin().unwrap(), 120, 40);
    s.frame(0.0, &mut Vec::new());
    let area = s.map_drawn().expect("a corner map");
    assert!(area.width * area.height * 6 <= 120 * 40, "{area:?}");
    let whole = MapArea::corner(s.screen(), s.app().camera.position);
    assert_eq!(s.map_area(), Some(whole), "a host counts the whole corner as the map's");
    assert!(area.width * area.height < whole.width * whole.height / 2, "{area:?} of {whole:?}");
    assert_eq!((area.x + area.width, area.y), (120, 0), "in the top-right corner");
    let frame = s.screen();
    let cells: Vec<_> = (area.y..area.y + area.height)
        .flat_map(|y| (area.x..area.x + area.width).map(move |x| (x, y)))
        .map(|(x, y)| frame.get(x, y).unwrap())
        .collect();
    let blank = cells.iter().filter(|c| c.ch == ' ' && c.bg == Color::Default).count();
    assert!(
        blank * 4 < cells.len(),
        "{blank} of {} blank:\n{}",
        cells.len(),
        map_text(frame, &area).join("\n")
    );
    // With more seen, more map (the whole maze revealed: as much of the corner as the maze covers;
    // the viewer starts by the maze's north-west corner, so not all of it).
    let mut all = session(maze::builtin().unwrap(), 120, 40);
    all.app_mut().reveal_map = true;
    all.frame(0.0, &mut Vec::new());
    let revealed = all.map_drawn().unwrap();
    assert!(revealed.width * revealed.height > area.width * area.height, "{revealed:?} vs {area:?}");
    assert!(revealed.width <= whole.width && revealed.height <= whole.height);
}

/// The full map of `maze` from `viewer`, every cell seen, on a `cols × rows` screen.
fn full_map(maze: &maze::Maze, viewer: Vec2, cols: usize, rows: usize) -> (Frame, MapArea) {
    let mut frame = Frame::new(cols, rows);
    let area = MapArea::full(&frame, maze, viewer);
    let camera = mazewalk_render::Camera::new(viewer, 90.0, 90.0);
    overlay::draw_map(
        &mut frame,
        &area,
        maze,
        &camera,
        &|_| true,
        None,
        Style::default(),
        &mut MapCells::default(),
    );
    (frame, area)
}

// issue #33: walls one character thick on the full map (a wall on the line between two characters
// was drawn in both).
#[test]
fn the_full_maps_walls_are_one_character_thick() {
    // a small maze drawn large (0.25 units a column) and a bigger one at one unit a column
    let small = generate(&GenOptions { width: 3, height: 2, ..GenOptions::default() }).unwrap();
    let big = generate(&GenOptions { width: 12, height: 8, ..GenOptions::default() }).unwrap();
    for (maze, cols, rows) in [(small, 60, 20), (big, 120, 40)] {
        let viewer = maze.viewer().pos;
        let (frame, area) = full_map(&maze, viewer, cols, rows);
        let text = map_text(&frame, &area);
        // a wall is a run of blocks three long or more; drawn twice as thick, the run would have a
        // twin beside it
        let grid: Vec<Vec<bool>> = text.iter().map(|row| row.chars().map(|c| c == '█').collect()).collect();
        let wall = |x: usize, y: usize| grid.get(y).and_then(|row| row.get(x)).copied().unwrap_or(false);
        for y in 1..area.height - 1 {
            for x in 1..area.width - 1 {
                let horizontal = |y| wall(x - 1, y) && wall(x, y) && wall(x + 1, y);
                let vertical = |x| wall(x, y - 1) && wall(x, y) && wall(x, y + 1);
                assert!(
                    !(horizontal(y) && horizontal(y + 1)),
                    "a double wall at row {y}:\n{}",
                    text.join("\n")
                );
                assert!(
                    !(vertical(x) && vertical(x + 1)),
                    "a double wall at column {x}:\n{}",
                    text.join("\n")
                );
            }
        }
    }
}

// issue #33: a maze larger than the screen: the full map keeps the viewer in view, anywhere in the
// maze, with the window inside the maze (not half a screen of nothing by its side), above the HUD.
#[test]
fn the_full_map_keeps_the_viewer_in_view_and_fills_the_screen() {
    let maze = generate(&GenOptions { width: 60, height: 40, ..GenOptions::default() }).unwrap();
    let (lo, hi) = (maze.extents().min, maze.extents().max);
    for viewer in
        [lo + Vec2::splat(2.0), hi - Vec2::splat(2.0), (lo + hi) * 0.5, Vec2::new(lo.x + 2.0, hi.y - 2.0)]
    {
        let (frame, area) = full_map(&maze, viewer, 120, 40);
        assert_eq!((area.x, area.y, area.width, area.height), (0, 0, 120, 39), "above the HUD");
        assert!(area.shows(viewer), "{viewer} off the map");
        let arrow = frame.lines()[..39].iter().any(|l| l.contains('↑'));
        assert!(arrow, "the viewer's arrow at {viewer}");
        let blank_rows = frame.lines()[..39].iter().filter(|l| l.trim().is_empty()).count();
        let blank_cols = (0..120).filter(|&x| (0..39).all(|y| frame.get(x, y).unwrap().ch == ' ')).count();
        assert!(
            blank_rows <= 1 && blank_cols <= 1,
            "{viewer}: {blank_rows} blank rows, {blank_cols} blank columns"
        );
    }
}

/// The characters of the map that draw a wall, as (column, row) in the frame.
fn wall_chars(frame: &Frame, area: &MapArea) -> Vec<(usize, usize)> {
    let chars =
        (area.y..area.y + area.height).flat_map(|y| (area.x..area.x + area.width).map(move |x| (x, y)));
    chars.filter(|&(x, y)| frame.get(x, y).unwrap().ch == '█').collect()
}

// issue #39: the full map of a `--gen 20x15` maze at 120×40 lost its east and south walls (its scale
// fitted the maze's width and height, not the outline a character past them). At several maze and
// screen sizes: a maze that fits at one unit a column or finer is drawn whole, its outline closed and
// every cell the same size; a larger one scrolls with the viewer's surroundings in view. Either way
// the viewer's arrow is on the screen.
#[test]
fn the_full_map_fits_the_maze_or_keeps_the_viewers_surroundings() {
    // (maze, whether its outline is all wall: a generated maze's is, the built-in one opens onto nothing)
    let grid = |width, height| {
        (generate(&GenOptions { width, height, seed: 3, ..GenOptions::default() }).unwrap(), true)
    };
    let mazes = [
        grid(3, 2),
        grid(12, 8),
        grid(20, 15),
        grid(16, 9),
        grid(40, 12),
        grid(60, 40),
        (maze::builtin().unwrap(), false),
    ];
    for (maze, closed_outline) in &mazes {
        let (lo, hi) = (maze.extents().min, maze.extents().max);
        let size = hi - lo;
        for (cols, rows) in [(40, 12), (80, 24), (100, 30), (120, 40), (200, 60)] {
            // the viewer at its start and by each corner of the maze
            let inset = Vec2::splat(1.5);
            let corners = [lo + inset, hi - inset, Vec2::new(lo.x, hi.y) + Vec2::new(1.5, -1.5)];
            for viewer in std::iter::once(maze.viewer().pos).chain(corners) {
                let (frame, area) = full_map(maze, viewer, cols, rows);
                let case = format!("{size} maze at {cols}x{rows}, viewer at {viewer}");
                let text = || frame.lines()[..rows - 1].join("\n");
                assert!(area.shows(viewer), "{case}: the viewer is off the map");
                let arrows: Vec<(usize, usize)> = (0..rows - 1)
                    .flat_map(|y| (0..cols).map(move |x| (x, y)))
                    .filter(|&(x, y)| "→↗↑↖←↙↓↘".contains(frame.get(x, y).unwrap().ch))
                    .collect();
                assert_eq!(arrows.len(), 1, "{case}: the viewer's arrow\n{}", text());
                let walls = wall_chars(&frame, &area);
                let (x0, x1) =
                    (walls.iter().map(|w| w.0).min().unwrap(), walls.iter().map(|w| w.0).max().unwrap());
                let (y0, y1) =
                    (walls.iter().map(|w| w.1).min().unwrap(), walls.iter().map(|w| w.1).max().unwrap());
                let fits = size.x + 1.0 <= cols as f32 && size.y / 2.0 + 1.0 <= (rows - 1) as f32;
                if fits {
                    // the outline: a closed rectangle of walls, the maze's extent at the map's scale
                    let u = area.units_per_col;
                    assert!(u <= 1.0, "{case}: {u} units a column");
                    let chars = |units: f32| (units / u).round() as usize;
                    assert_eq!(
                        (x1 - x0, y1 - y0),
                        (chars(size.x), chars(size.y / 2.0)),
                        "{case}\n{}",
                        text()
                    );
                    // (the viewer's arrow stands over a wall near one)
                    let wall = |x, y| walls.contains(&(x, y)) || arrows[0] == (x, y);
                    let closed = (x0..=x1).all(|x| wall(x, y0) && wall(x, y1))
                        && (y0..=y1).all(|y| wall(x0, y) && wall(x1, y));
                    assert!(closed || !closed_outline, "{case}: the outline is open\n{}", text());
                    // every cell of a grid the same size: the walls stand on multiples of a cell
                    let cell = (4.0 / u).round();
                    assert!((4.0 / u - cell).abs() < 1e-3, "{case}: {} columns a cell", 4.0 / u);
                    assert!(
                        walls
                            .iter()
                            .all(|&(x, y)| (x - x0) % cell as usize == 0
                                || (y - y0) % (cell as usize / 2) == 0),
                        "{case}\n{}",
                        text()
                    );
                } else {
                    // scrolled at one unit a column: what lies within a dozen columns and six rows of
                    // the viewer (three cells across, one and a half up and down) is on the map
                    assert_eq!(area.units_per_col, 1.0, "{case}");
                    for dx in [-12.0, 0.0, 12.0] {
                        for dy in [-12.0, 0.0, 12.0] {
                            let p = (viewer + Vec2::new(dx, dy)).clamp(lo, hi);
                            assert!(area.shows(p), "{case}: {p} is off the map");
                        }
                    }
                }
            }
        }
    }
}

// issue #33: the help says there is an exit to find; in ascii no `?` stands for a glyph or a degree.
#[test]
fn the_help_tells_of_the_exit_and_in_ascii_spells_everything() {
    let with_exit = overlay::help_lines(Style::default(), true);
    assert!(with_exit.iter().any(|l| l.contains("find the exit")), "{with_exit:?}");
    assert!(!overlay::help_lines(Style::default(), false).iter().any(|l| l.contains("exit")));
    let ascii = Style { depth: ColorDepth::Ansi16, ascii: true };
    let unicode = overlay::help_lines(Style::default(), true);
    for (line, original) in overlay::help_lines(ascii, true).iter().zip(&unicode) {
        assert!(line.is_ascii(), "{line:?}");
        // the only `?` are the key's own ("? / h")
        assert_eq!(line.matches('?').count(), original.matches('?').count(), "{line:?} for {original:?}");
    }
    let lines = overlay::help_lines(ascii, true).join("\n");
    assert!(lines.contains("half, quad, sextant (2x3)") && lines.contains("(tap: 15 deg)"), "{lines}");
    // the whole screen in ascii: HUD and boxes
    let options = RenderOptions { charset: Charset::Ascii, ..RenderOptions::default() };
    let mut s = Session::new(
        App::new(maze::builtin().unwrap(), options, 0.0).unwrap(),
        100,
        40,
        SessionOptions::default(),
    );
    s.feed(b"?", 0.0);
    s.frame(0.0, &mut Vec::new());
    let text = s.screen().lines().join("\n");
    assert!(text.is_ascii() && text.contains("heading 0 deg E"), "{text}");
}

// The corner map fitted to what has been seen still shows the other players in its area, seen or
// not (a host draws the players its map area holds: `Session::map_area` is the whole corner).
#[test]
fn the_fitted_corner_map_shows_the_other_players_in_its_area() {
    use mazewalk_walk::overlay::Peer;
    let mut s = session(maze::builtin().unwrap(), 120, 40);
    s.frame(0.0, &mut Vec::new());
    let whole = s.map_area().unwrap();
    // a point of the built-in maze in the corner's area but out of sight of the start: south, behind
    // the corridor's wall
    let at = s.app().camera.position + Vec2::new(4.0, -8.0);
    assert!(whole.shows(at) && !s.map_drawn().unwrap().shows(at), "unseen, in the area");
    let peer = Peer { position: at, heading_deg: 0.0, initial: 'Z', color: Color::Indexed(196), cell: None };
    s.set_peers(&[peer]);
    s.frame(0.1, &mut Vec::new());
    let drawn = s.map_drawn().unwrap();
    assert!(drawn.shows(at), "{drawn:?}");
    assert!(
        map_text(s.screen(), &drawn).iter().any(|row| row.contains('Z')),
        "{:?}",
        map_text(s.screen(), &drawn)
    );
}

/// Two players in a served maze's list, the second the viewer.
fn two_players() -> Vec<mazewalk_walk::roster::Entry> {
    let entry = |name: &str, label, best, me| mazewalk_walk::roster::Entry {
        name: name.into(),
        label,
        color: Color::Indexed(196),
        joined_at: 0.0,
        best,
        me,
    };
    vec![entry("ada", 'A', Some(231.7), false), entry("bob", 'B', None, true)]
}

/// Opens the help of `s` at `now` and reads it page by page (Space turns them): each page's screen
/// as text. Stops when a page comes round again.
fn help_screens(s: &mut Session, now: f64) -> Vec<String> {
    s.feed(b"?", now);
    let mut screens: Vec<String> = Vec::new();
    for page in 0..10 {
        let t = now + 0.2 * f64::from(page);
        s.frame(t, &mut Vec::new());
        let text = s.screen().lines().join("\n");
        if screens.contains(&text) {
            break;
        }
        screens.push(text);
        s.feed(b" ", t + 0.1);
    }
    screens
}

// Bug: at 80×24 the help was cut off with "…" after the `g` line (`r`, `Ctrl-Z` and a served game's
// `Tab` never shown) and could not be scrolled; a served player's help listed Ctrl-Z, which does
// nothing over SSH. At 120×40 it is whole on one screen; at 80×24 on two pages, each saying how to
// see the next; every key line on some page, whole.
#[test]
fn every_line_of_the_help_is_shown_at_80x24_and_120x40() {
    let style = Style::default();
    for served in [false, true] {
        let want = overlay::help_lines_for(style, true, served);
        assert_eq!(want.iter().any(|l| l.starts_with("Ctrl-Z ")), !served, "{want:?}");
        assert_eq!(want.iter().any(|l| l.starts_with("Tab ")), served, "{want:?}");
        // red-team pass 3: nor the developer keys, which do nothing there (`b`: every wall drawn)
        for key in ["b ", "v ", "i "] {
            assert_eq!(want.iter().any(|l| l.starts_with(key)), !served, "{key:?} in {want:?}");
        }
        // (a served player's, without the developer keys, fits one page at 80×24)
        for (cols, rows, pages) in [(120, 40, 1), (80, 24, if served { 1 } else { 2 })] {
            let mut s = Session::new(
                facing_the_exit(),
                cols,
                rows,
                SessionOptions { flow_control: false, ..SessionOptions::default() },
            );
            if served {
                s.set_roster(&two_players());
            }
            let screens = help_screens(&mut s, 0.0);
            assert_eq!(screens.len(), pages, "{cols}×{rows}, served {served}:\n{}", screens.join("\n\n"));
            for line in &want {
                assert!(
                    screens.iter().any(|screen| screen.lines().any(|row| row.contains(line.as_str()))),
                    "{cols}×{rows}, served {served}: {line:?} not shown:\n{}",
                    screens.join("\n\n")
                );
            }
            for (i, screen) in screens.iter().enumerate() {
                let says = overlay::page_row(i + 1, pages);
                assert_eq!(screen.contains(&says), pages > 1, "{cols}×{rows}:\n{screen}");
                assert!(!screen.contains('…'), "nothing cut at {cols}×{rows}:\n{screen}");
            }
        }
    }
}

// At 60×20 the help does not fit whole either: it says how to see the rest, and PgDn / PgUp turn
// its pages too; closed and opened again, it starts at its first page.
#[test]
fn a_help_too_tall_says_how_to_see_the_rest_and_its_pages_turn() {
    let mut s = Session::new(
        facing_the_exit(),
        60,
        20,
        SessionOptions { flow_control: false, ..SessionOptions::default() },
    );
    s.set_roster(&two_players());
    let screens = help_screens(&mut s, 0.0);
    assert!(screens.len() >= 2, "{screens:?}");
    let page = |n: usize| overlay::page_row(n, screens.len());
    assert!(screens[0].contains(&page(1)), "{}", screens[0]);
    // every page but the last says Space shows the next; the last, that it goes round to the first
    for (i, screen) in screens.iter().enumerate() {
        let last = i + 1 == screens.len();
        assert_eq!(screen.contains("Space / PgDn: first page"), last, "{screen}");
        assert_eq!(screen.contains("Space / PgDn: next page"), !last, "{screen}");
    }
    let shown = |s: &Session| s.screen().lines().join("\n");
    // (Space went round to the first page) PgDn the second, PgUp the first again
    s.feed(b"\x1b[6~", 5.0);
    s.frame(5.0, &mut Vec::new());
    assert!(shown(&s).contains(&page(2)), "{}", shown(&s));
    s.feed(b"\x1b[5~", 5.2);
    s.frame(5.2, &mut Vec::new());
    assert!(shown(&s).contains(&page(1)), "{}", shown(&s));
    s.feed(b" ?", 5.4); // the second page, then closed
    s.frame(5.4, &mut Vec::new());
    assert!(!shown(&s).contains("next page"), "{}", shown(&s));
    s.feed(b"?", 5.6);
    s.frame(5.6, &mut Vec::new());
    assert!(shown(&s).contains(&page(1)), "{}", shown(&s));
    // under the player list its pages do not turn: Space there is not the help's
    s.feed(b"\t", 5.8);
    s.frame(5.8, &mut Vec::new());
    assert!(shown(&s).contains("Players: 2") && !shown(&s).contains("next page"), "{}", shown(&s));
    s.feed(b" \t", 6.0);
    s.frame(6.0, &mut Vec::new());
    assert!(shown(&s).contains(&page(1)), "{}", shown(&s));
}

// Bug: the player list opened over the News box left the news's first and last characters (an `a`,
// a `!`) on either side of its rows: the wider News box still showed round the narrower list. The
// list now shows instead of the other boxes: the screen with the list open is the same with news
// as without, and the News box comes back whole when the list closes.
#[test]
fn the_player_list_over_the_news_leaves_nothing_of_it() {
    let news = "ada reached the exit first, in 3:51.7!";
    let screens: Vec<(Vec<String>, Vec<String>)> = [Some(news), None]
        .into_iter()
        .map(|notice| {
            let mut s = session(maze::builtin().unwrap(), 80, 24);
            s.set_roster(&two_players());
            s.set_notice(notice.map(String::from));
            s.frame(0.0, &mut Vec::new());
            let before = s.screen().lines();
            s.feed(b"\t", 0.1);
            s.frame(0.2, &mut Vec::new());
            let open = s.screen().lines();
            s.feed(b"\t", 0.3);
            s.frame(0.4, &mut Vec::new());
            assert_eq!(s.screen().lines(), before, "closed, the screen is as before");
            (before, open)
        })
        .collect();
    let ((news_before, news_open), (_, plain_open)) = (&screens[0], &screens[1]);
    assert!(news_before.iter().any(|l| l.contains(news)), "{}", news_before.join("\n"));
    assert!(news_open.iter().any(|l| l.contains("Players: 2")), "{}", news_open.join("\n"));
    assert_eq!(news_open, plain_open, "nothing of the news shows round the list");
}
