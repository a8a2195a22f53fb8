//! Issue #43: racing a stored run's ghost. A walk that reaches the exit keeps its run; a session
//! given a run shows its ghost — translucent, through the renderer, captioned with the holder's name
//! and time, and on the map — where the run was at the same time into the walk, and nowhere once
//! toggled off (`g`).

use std::sync::Arc;

use glam::Vec2;
use mazewalk_maze::{Maze, grid};
use mazewalk_render::{Charset, RenderOptions};
use mazewalk_term::frame::ColorDepth;
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::run::{Pose, Run};
use mazewalk_walk::state::MapMode;
use mazewalk_walk::{App, Session, SessionOptions};

/// A long corridor east from the start (6, 6) to the exit at its far end.
const CORRIDOR: &str = "mazewalk-grid 1
####################
#>................E#
####################
";

fn corridor() -> Maze {
    grid::parse_str("corridor.grid", CORRIDOR).unwrap()
}

fn options() -> RenderOptions {
    RenderOptions { charset: Charset::Half, color_depth: ColorDepth::Ansi256, ..RenderOptions::default() }
}

/// A run east along the corridor at 5 units/s from the start, 12 s long.
fn run_east(maze: &Maze) -> Run {
    let samples = (0..=120)
        .map(|k| Pose {
            position: Vec2::new(6.0 + 0.5 * k as f32, 6.0).min(Vec2::new(70.0, 6.0)),
            yaw_deg: 0.0,
            pitch_deg: 0.0,
        })
        .collect();
    Run { maze: maze.content_hash(), holder: "ada".into(), millis: 12_000, samples }
}

fn session(maze: Maze) -> Session {
    let app = App::new(maze, options(), 0.0).unwrap();
    Session::new(app, 100, 30, SessionOptions { flow_control: false, ..SessionOptions::default() })
}

fn text(session: &Session) -> String {
    session.screen().lines().join("\n")
}

#[test]
fn a_ghost_runs_ahead_down_the_corridor_in_real_time_and_goes_when_toggled_off() {
    let maze = corridor();
    let run = Arc::new(run_east(&maze));
    let mut s = session(maze);
    s.app_mut().map = MapMode::Full; // the map's whole corridor: where the ghost is on it
    s.set_ghost_run(Some(Arc::clone(&run)));
    let mut out = Vec::new();
    // not wanted yet: no ghost, whatever the run
    assert!(s.frame(0.0, &mut out));
    assert!(!text(&s).contains("ghost ada"), "{}", text(&s));
    // `g` at 0: the ghost starts with the walk, standing on the viewer; 2 s later it is 10 units
    // ahead, in the middle of the view, with its caption over its head and its mark on the map
    s.feed(b"g", 0.0);
    s.app_mut().map = MapMode::Off;
    assert!(s.frame(2.0, &mut out));
    let view = text(&s);
    let lines: Vec<&str> = view.lines().collect();
    let caption = lines.iter().position(|l| l.contains("ghost ada 0:12.0")).expect(&view);
    assert!(caption > 3 && caption < 25, "over the head, mid-view: row {caption}\n{view}");
    let col = lines[caption].find("ghost").unwrap();
    assert!((35..55).contains(&col), "centred on the ghost ahead: column {col}\n{view}");
    assert!(lines[29].contains("ghost ada 0:12.0"), "the HUD names the ghost raced:\n{view}");
    // on the full map: 10 units east of the viewer's arrow, on its row
    s.app_mut().map = MapMode::Full;
    assert!(s.frame(2.1, &mut out));
    let map = text(&s);
    let row = map.lines().find(|l| l.contains('◌')).expect(&map);
    let (ghost_at, me_at) = (row.find('◌').unwrap(), row.find('→').expect(row));
    assert!(ghost_at > me_at, "the ghost ahead of the viewer on the map: {row:?}");
    // it keeps running: 4 s in it is further on the map
    assert!(s.frame(4.0, &mut out));
    let later = text(&s);
    let row4 = later.lines().find(|l| l.contains('◌')).expect(&later);
    assert!(row4.find('◌').unwrap() > ghost_at, "{row4:?} after {row:?}");
    // past its finish it waits at the exit and no more frames are due for it
    assert!(s.frame(20.0, &mut out));
    assert_eq!(s.next_wake(20.1), Some(21.0), "only the exit clock's tick is due");
    // `g` again: gone from the view, the map and the HUD
    s.feed(b"g", 21.0);
    assert!(s.frame(21.0, &mut out));
    let off = text(&s);
    assert!(!off.contains('◌') && !off.contains("ghost"), "{off}");
}

/// QA finding 10: `g` with no run to race says what to do: served, that none is there yet; in the
/// local walk, which `--ghost FILE` gives one.
#[test]
fn g_without_a_run_says_why_there_is_no_ghost() {
    for (served, says) in [(false, "no ghost (--ghost FILE)"), (true, "no ghost yet")] {
        let mut s = session(corridor());
        if served {
            s.set_players_in(Some(1));
        }
        s.frame(0.0, &mut out());
        assert!(!text(&s).contains("no ghost"), "{}", text(&s));
        s.feed(b"g", 0.1);
        s.frame(0.2, &mut out());
        let hud = text(&s).lines().last().unwrap().to_string();
        assert!(hud.contains(says), "served {served}: {hud:?}");
    }
}

#[test]
fn a_ghost_turned_on_mid_walk_starts_from_the_toggle() {
    let maze = corridor();
    let run = Arc::new(run_east(&maze));
    let mut s = session(maze);
    s.set_ghost_run(Some(run));
    s.app_mut().map = MapMode::Full;
    s.feed(b"g", 30.0);
    assert!(s.frame(30.0, &mut out()));
    let map = text(&s);
    // at the toggle the ghost stands on the start, under the viewer's own arrow: not drawn over it
    assert!(!map.contains('◌'), "{map}");
    assert!(s.frame(31.0, &mut out()));
    assert!(text(&s).contains('◌'), "a second after the toggle it is on its way");
}

fn out() -> Vec<u8> {
    Vec::new()
}

#[test]
fn a_walk_to_the_exit_keeps_its_run() {
    let maze = corridor();
    let hash = maze.content_hash();
    let mut app = App::new(maze, options(), 100.0).unwrap();
    assert_eq!(app.run(hash, "ada"), None, "no finish, no run");
    app.key(Key::Char('w'), KeyPhase::Press, 100.0);
    let mut t = 100.0;
    while app.finished.is_none() && t < 130.0 {
        t += 1.0 / 30.0;
        app.key(Key::Char('w'), KeyPhase::Repeat, t); // held: its auto-repeat
        app.tick(t);
    }
    let took = app.finished.expect("walked to the exit");
    let run = app.run(hash, "ada").expect("a finish keeps its run");
    assert_eq!(run.millis, (took * 1000.0).round() as u32);
    assert_eq!(run.samples.len(), run.millis as usize / 100 + 1);
    let (first, last) = (run.samples[0].position, run.samples[run.samples.len() - 1].position);
    assert!(first.distance(Vec2::new(6.0, 6.0)) < 0.01, "from the start: {first}");
    assert_eq!(app.maze().cell_at(last), app.maze().exit().map(|e| e.cell), "to the exit: {last}");
    // and the samples between walk east, never back
    assert!(run.samples.windows(2).all(|w| w[1].position.x >= w[0].position.x));
    let bytes = run.encode().unwrap();
    assert_eq!(Run::decode(&bytes).unwrap(), run);
    // walking on after the finish changes nothing; `r` starts a new walk with no run yet
    app.key(Key::Char('r'), KeyPhase::Press, t + 5.0);
    app.key(Key::Char('r'), KeyPhase::Press, t + 6.0);
    assert_eq!(app.run(hash, "ada"), None);
}

// `mazewalk replay`: a run drives the viewer instead of the keys.
#[test]
fn a_replay_moves_the_viewer_along_the_run_and_the_walking_keys_do_nothing() {
    let maze = corridor();
    let run = Arc::new(run_east(&maze));
    let mut app = App::new(maze, options(), 0.0).unwrap();
    app.set_replay(Arc::clone(&run));
    assert!(app.is_animating(0.0));
    app.tick(2.0);
    assert!((app.camera.position.x - 16.0).abs() < 0.01, "{}", app.camera.position);
    assert!(!app.key(Key::Char('w'), KeyPhase::Press, 2.0), "w walks nothing");
    assert!(!app.key(Key::Left, KeyPhase::Press, 2.0));
    app.tick(2.5);
    assert!((app.camera.position.x - 18.5).abs() < 0.01, "{}", app.camera.position);
    assert_eq!(app.camera.yaw_deg, 0.0);
    app.tick(20.0);
    assert_eq!(app.finished, Some(12.0), "the run's time at its end");
    assert!(!app.exit_box && !app.is_animating(20.0));
    assert!(app.key(Key::Char('m'), KeyPhase::Press, 20.0), "the map key works");
    // `r` plays it again from the start
    app.key(Key::Char('r'), KeyPhase::Press, 30.0);
    app.tick(31.0);
    assert!((app.camera.position.x - 11.0).abs() < 0.01 && app.finished.is_none());
}
