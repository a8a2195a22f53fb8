//! Chalk marks (issue #39, the map off): the view marks the floor of every cell walked, `x` turns the
//! marks off and on, `r` wipes the floor clean.

use mazewalk_maze::{Maze, generate};
use mazewalk_render::RenderOptions;
use mazewalk_term::input::{Key, KeyPhase};
use mazewalk_walk::state::MapMode;
use mazewalk_walk::{App, Session, SessionOptions};

fn maze() -> Maze {
    let options = generate::GenOptions { width: 8, height: 6, seed: 7, loops: 0.1, ..Default::default() };
    generate::generate(&options).expect("maze")
}

/// Taps `key` `n` times, 0.3 s apart from `t` on (taps, never a hold); returns the time after.
fn taps(app: &mut App, key: Key, n: usize, t: f64) -> f64 {
    let mut t = t;
    for _ in 0..n {
        app.key(key, KeyPhase::Press, t);
        t += 0.3;
        app.tick(t);
    }
    t
}

/// The view's rows of the screen (all but the HUD) as text.
fn view(s: &mut Session, now: f64) -> Vec<String> {
    s.frame(now, &mut Vec::new());
    let lines = s.screen().lines();
    lines[..lines.len() - 1].to_vec()
}

#[test]
fn the_cells_walked_are_chalked_in_order_once_each_and_r_wipes_them() {
    let mut app = App::new(maze(), RenderOptions::default(), 0.0).unwrap();
    let start = app.cell;
    assert_eq!(app.chalked(), [start], "the start is walked");
    // walk the way the viewer faces until it has entered two new cells or is stuck
    let (mut t, mut cells) = (0.0, vec![start]);
    for _ in 0..40 {
        t = taps(&mut app, Key::Char('w'), 1, t);
        if cells.last() != Some(&app.cell) && !cells.contains(&app.cell) {
            cells.push(app.cell);
        }
    }
    // back again: no cell twice
    t = taps(&mut app, Key::Char('s'), 40, t);
    assert!(cells.len() >= 2, "walked on from the start: {cells:?}");
    assert_eq!(app.chalked(), cells.as_slice());
    app.key(Key::Char('x'), KeyPhase::Press, t);
    assert!(app.chalked().is_empty(), "x: no marks");
    app.key(Key::Char('x'), KeyPhase::Press, t + 0.3);
    assert_eq!(app.chalked(), cells.as_slice(), "x again: the same marks");
    app.key(Key::Char('r'), KeyPhase::Press, t + 0.6);
    assert_eq!(app.chalked(), [start], "r: a new walk from the start");
}

#[test]
fn the_marks_show_in_the_view_with_the_map_off_and_x_hides_them() {
    let mut app = App::new(maze(), RenderOptions::default(), 0.0).unwrap();
    app.map = MapMode::Off;
    // walk ahead into the next cell, then turn round: the start's cell is in view, marked
    let mut t = 0.0;
    let start = app.cell;
    while app.cell == start && t < 20.0 {
        t = taps(&mut app, Key::Char('w'), 1, t);
    }
    assert_ne!(app.cell, start, "the viewer faces an open way");
    t = taps(&mut app, Key::Char('w'), 2, t); // into the new cell's middle
    for key in [Key::Char('.'), Key::Char('.')] {
        app.key(key, KeyPhase::Press, t);
        t += 1.0;
        app.tick(t);
    }
    let mut s =
        Session::new(app, 120, 40, SessionOptions { flow_control: false, ..SessionOptions::default() });
    let marked = view(&mut s, t);
    s.app_mut().key(Key::Char('x'), KeyPhase::Press, t);
    let plain = view(&mut s, t + 0.1);
    let differ: usize = marked
        .iter()
        .zip(&plain)
        .map(|(a, b)| a.chars().zip(b.chars()).filter(|(x, y)| x != y).count())
        .sum();
    assert!(differ >= 2, "the start's mark shows in {differ} cells of the view");
    // only the floor half of the view changes
    let first = marked.iter().zip(&plain).position(|(a, b)| a != b).expect("differ");
    assert!(first >= marked.len() / 2, "the first changed row {first} is on the floor");
}
