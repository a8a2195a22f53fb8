//! The real course files load; every example in mazes/ loads and passes the checks.

use mazewalk_maze::{self as maze, Format};

const REAL: [(&str, usize, usize, usize); 3] =
    [("maze-1x1-45.maze", 4, 4, 1), ("maze-3x3-50.maze", 16, 24, 9), ("maze-10x10-100.maze", 121, 220, 100)];

fn shared(name: &str) -> String {
    mazewalk_testkit::maze_path(&format!("cs559/{name}"))
}

#[test]
fn real_course_files_load() {
    for (name, nv, ne, nc) in REAL {
        let m = maze::load(shared(name)).unwrap_or_else(|e| panic!("{e}")).maze;
        assert_eq!((m.vertices().len(), m.edges().len(), m.cell_count()), (nv, ne, nc), "{name}");
        assert!(m.cell_at(m.viewer().pos).is_some());
    }
}

#[test]
fn real_course_files_round_trip() {
    for (name, ..) in REAL {
        let m = maze::load(shared(name)).unwrap().maze;
        let text = maze::write(&m, Format::Cs559).unwrap();
        assert_eq!(maze::parse(name, text.as_bytes()).unwrap(), m, "{name}");
    }
}
