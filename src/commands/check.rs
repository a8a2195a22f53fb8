//! `mazewalk check`: loads a maze file and prints a summary, or the located error.

use std::io::Write;

use anyhow::Context as _;

use super::stdout_open;
use crate::cli::CheckArgs;
use mazewalk_maze::{self as maze, Format, Maze};
use mazewalk_walk::state::stand;

/// Loads the file, prints its summary to stdout (or the located error, from `main`).
pub fn run(args: &CheckArgs) -> anyhow::Result<()> {
    stdout_open()?;
    let loaded = maze::load_with(&args.file, &args.read.options())?;
    let report = summary(&maze::quote_path(&args.file.display().to_string()), loaded.format, &loaded.maze);
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(report.as_bytes()).and_then(|()| stdout.flush()).context("cannot write to stdout")?;
    Ok(())
}

/// The `check` report.
fn summary(name: &str, format: Format, maze: &Maze) -> String {
    let e = maze.extents();
    let v = maze.viewer();
    let start = stand(maze, v.pos);
    // the cell the walk starts in
    let start_cell = start.as_ref().map(|at| at.cell);
    let exit = maze.exit().map_or("none".to_string(), |x| {
        let place = match x.point {
            Some(p) => format!("cell {} at ({}, {})", x.cell, p.x, p.y),
            None => format!("cell {}", x.cell),
        };
        match start_cell {
            Some(c) if !maze.connected(c, x.cell) => {
                format!("{place} (not reachable from the start: no opening leads from cell {c} to it)")
            }
            _ => place,
        }
    });
    // Where the walk starts instead, when the file's viewer stands closer to a wall than it may.
    let moved = match start {
        Some(at) if at.pos != v.pos => format!(
            "\n            (closer than {} to a wall: the walk starts at ({}, {}))",
            maze.clearance(),
            at.pos.x,
            at.pos.y
        ),
        _ => String::new(),
    };
    format!(
        "{name}: ok\n  format:   {format}\n  cells:    {}\n  edges:    {} ({} opaque {}, {} {})\n  \
         extents:  ({}, {}) .. ({}, {})\n  viewer:   ({}, {}) z {} facing {}° fov {}° in cell {}{moved}\n  \
         exit:     {exit}\n  perfect:  {}\n",
        maze.cell_count(),
        maze.edges().len(),
        maze.wall_count(),
        if maze.wall_count() == 1 { "wall" } else { "walls" },
        maze.portal_count(),
        if maze.portal_count() == 1 { "portal" } else { "portals" },
        e.min.x,
        e.min.y,
        e.max.x,
        e.max.y,
        v.pos.x,
        v.pos.y,
        v.z,
        v.dir_deg,
        v.fov_deg,
        maze.cell_at(v.pos).map_or("?".into(), |c| c.to_string()),
        if maze.is_perfect() { "yes" } else { "no" },
    )
}
