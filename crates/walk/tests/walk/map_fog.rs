//! The map's fog of war: only cells the viewer has seen are drawn, and the exit once seen.

use mazewalk_maze::{Maze, grid};
use mazewalk_render::{RenderOptions, Renderer, Target};
use mazewalk_term::frame::Frame;
use mazewalk_walk::state::MapMode;
use mazewalk_walk::{App, Session, SessionOptions};

/// Two corridors joined at the east end; the start looks east along the top one, the exit is at the
/// west end of the bottom one, out of sight behind the wall between them.
const TWO_CORRIDORS: &str = "mazewalk-grid 1
#########
#>......#
#######.#
#E......#
#########
";

fn maze() -> Maze {
    grid::parse_str("two.grid", TWO_CORRIDORS).unwrap()
}

fn session(reveal: bool) -> Session {
    let mut app = App::new(maze(), RenderOptions::default(), 0.0).unwrap();
    app.map = MapMode::Full;
    app.reveal_map = reveal;
    Session::new(app, 100, 30, SessionOptions { flow_control: false, ..SessionOptions::default() })
}

/// The map's characters that are not blank (the full map covers all rows but the HUD).
fn drawn(frame: &Frame) -> usize {
    frame.cells()[..frame.width() * (frame.height() - 1)]
        .iter()
        .filter(|c| c.ch != ' ' || c.bg != mazewalk_term::frame::Color::Default)
        .count()
}

fn has_exit(frame: &Frame) -> bool {
    frame.lines()[..frame.height() - 1].iter().any(|l| l.contains('E'))
}

#[test]
fn at_the_start_the_map_holds_exactly_the_cells_in_view_and_no_exit() {
    let mut s = session(false);
    s.frame(0.0, &mut Vec::new());
    // What the first frame showed, from the renderer on its own.
    let app = s.app();
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(100, 29);
    let region = frame.region();
    renderer.render(app.maze(), &app.camera, &[], &app.options, Target::Frame(&mut frame, region)).unwrap();
    let mut visible = renderer.portal().visited.clone();
    visible.sort_unstable();
    let seen: Vec<u32> = (0..app.maze().cell_count() as u32).filter(|&c| app.has_seen(c)).collect();
    assert_eq!(seen, visible, "seen = the cells of the first view");
    let exit = app.maze().exit().unwrap().cell;
    assert!(!app.has_seen(exit));
    assert!(!has_exit(s.screen()), "the exit is not on the map before it is seen");
    // Revealed, the whole maze and the exit are there from the start.
    let mut all = session(true);
    all.frame(0.0, &mut Vec::new());
    assert!(has_exit(all.screen()));
    assert!(drawn(all.screen()) > drawn(s.screen()) + 50, "{} vs {}", drawn(all.screen()), drawn(s.screen()));
}

#[test]
fn walking_adds_what_comes_into_view_and_forgets_nothing() {
    let mut s = session(false);
    let mut out = Vec::new();
    s.frame(0.0, &mut out);
    let count =
        |s: &Session| (0..s.app().maze().cell_count() as u32).filter(|&c| s.app().has_seen(c)).count();
    let first = count(&s);
    let seen_first: Vec<u32> =
        (0..s.app().maze().cell_count() as u32).filter(|&c| s.app().has_seen(c)).collect();
    // Walk to the east end, snap right (south), walk down to the bottom corridor, snap right (west):
    // the exit is straight ahead.
    let mut t = 0.0;
    let walk_until = |s: &mut Session, t: &mut f64, done: &dyn Fn(&Session) -> bool| {
        for _ in 0..400 {
            if done(s) {
                break;
            }
            *t += 0.05;
            s.feed(b"w", *t);
            s.frame(*t, &mut Vec::new());
        }
        *t += 0.5; // let go: the glide stops
        s.frame(*t, &mut Vec::new());
    };
    let snap_right = |s: &mut Session, t: &mut f64| {
        *t += 0.5;
        s.feed(b".", *t);
        *t += 1.0; // the snap's animation ends
        s.frame(*t, &mut Vec::new());
    };
    walk_until(&mut s, &mut t, &|s| s.app().camera.position.x >= 29.0);
    snap_right(&mut s, &mut t);
    walk_until(&mut s, &mut t, &|s| s.app().camera.position.y <= 6.5);
    snap_right(&mut s, &mut t);
    t += 1.0;
    s.invalidate();
    s.frame(t, &mut out);
    assert!(count(&s) > first, "new cells came into view");
    assert!(seen_first.iter().all(|&c| s.app().has_seen(c)), "nothing seen is forgotten");
    let exit = s.app().maze().exit().unwrap().cell;
    assert!(s.app().has_seen(exit), "walking round the corner shows the exit");
    assert!(has_exit(s.screen()), "and the map shows it:\n{}", s.screen().lines().join("\n"));
}
