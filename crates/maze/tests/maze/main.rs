//! The maze crate's integration tests, one binary (one link) for all of them: errors located in the
//! file, the course files, generation, the grid format, and properties of the model, the readers and
//! movement.

mod maze_errors;
mod maze_files;
mod maze_gen;
mod maze_grid;
mod maze_props;
