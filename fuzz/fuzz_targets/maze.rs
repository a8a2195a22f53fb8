//! Feeds arbitrary bytes to the maze reader (both formats: a grid file starts with `mazewalk-grid`).
//! Asserts: no panic and no hang; an error names a location inside the input; a maze that loads
//! writes back and reads again to the same maze (CS559 always, grid when the grid can express it);
//! and a step of the viewer from its start stays in a cell that contains it.

#![no_main]

use libfuzzer_sys::fuzz_target;
use mazewalk_maze::{self as maze, Format, movement};

fuzz_target!(|bytes: &[u8]| {
    let maze = match maze::parse("fuzz", bytes) {
        Ok(maze) => maze,
        Err(err) => {
            let lines = bytes.split(|&b| b == b'\n').count() as u32;
            assert!(err.line >= 1 && err.line <= lines.max(1), "{err}: line outside the input");
            return;
        }
    };
    for format in [Format::Cs559, Format::Grid] {
        if let Ok(text) = maze::write(&maze, format) {
            let again = maze::parse("again", text.as_bytes())
                .unwrap_or_else(|e| panic!("{format} output does not read back: {e}\n{text}"));
            assert!(again == maze, "{format} round trip changed the maze");
        }
    }
    let start = movement::Position::of_viewer(&maze);
    let delta = glam::vec2(bytes.len() as f32 * 0.37, -(bytes.len() as f32) * 0.11);
    let end = movement::step(&maze, start, delta, 0.25);
    assert!(maze.cell_contains(end.cell, end.pos), "step left its cell: {end:?}");
});
