//! `mazewalk gen`: a random maze, written in either format.

use std::io::{BufWriter, Write};

use anyhow::Context as _;

use super::{STDOUT, stdout_open};
use crate::cli::GenArgs;
use mazewalk_maze::generate::{GenOptions, generate, generate_grid};
use mazewalk_maze::{self as maze, Format};

/// Generates the maze the flags describe and writes it to the file or stdout, streamed.
pub fn run(args: &GenArgs) -> anyhow::Result<()> {
    let opts = GenOptions {
        width: args.size.0,
        height: args.size.1,
        seed: args.seed,
        algorithm: args.algo,
        loops: args.loops,
        exit: args.exit,
        ..GenOptions::default()
    };
    let (sink, name): (Box<dyn Write>, String) = match &args.output {
        Some(path) if path != STDOUT => (
            Box::new(
                mazewalk_maze::files::create_output(path)
                    .with_context(|| format!("{}: cannot create", path.display()))?,
            ),
            path.display().to_string(),
        ),
        _ => {
            stdout_open()?;
            (Box::new(std::io::stdout().lock()), "stdout".into())
        }
    };
    let mut out = BufWriter::new(sink);
    let cannot_write = || format!("{name}: cannot write");
    match args.format {
        // streamed: a 1000x1000 maze is 160 MB of text
        Format::Cs559 => maze::cs559::write_to(&generate(&opts)?, &mut out).with_context(cannot_write)?,
        Format::Grid => {
            out.write_all(generate_grid(&opts)?.to_text().as_bytes()).with_context(cannot_write)?
        }
    }
    out.flush().with_context(cannot_write)?;
    Ok(())
}
