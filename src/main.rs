//! The `mazewalk` binary: command-line wiring only; everything else lives in the library.
//!
//! Exit codes: 0 success, 2 usage errors (clap), 65 malformed or invalid maze data, 66 cannot read
//! the file, 1 anything else. Errors go to stderr as `FILE:LINE:COL: message`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context as _;
use clap::{Args, Parser, Subcommand};
use mazewalk::maze::generate::{Algorithm, GenOptions, MAX_SIDE, generate, generate_grid};
use mazewalk::maze::{self, Format, LoadError, Maze};

#[derive(Parser)]
#[command(name = "mazewalk", version, about = "A first-person 3D maze walkthrough for the terminal")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate a random maze (a perfect maze unless --loops is given).
    Gen(GenArgs),
    /// Load a maze file and print a summary, or the located error (exit 65).
    Check(CheckArgs),
}

#[derive(Args)]
struct GenArgs {
    /// Cells east-west x north-south, e.g. 20x10 (each side 1..=1000).
    #[arg(long, value_parser = parse_size)]
    size: (u32, u32),
    /// Random seed: the same seed gives the same maze on every platform.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Carving algorithm: prim (bushy), dfs (long corridors), wilson (uniform).
    #[arg(long, default_value = "prim", value_parser = parse_algo)]
    algo: Algorithm,
    /// Fraction of the remaining interior walls to remove, adding cycles (0..=1).
    #[arg(long, default_value_t = 0.0, value_parser = parse_loops)]
    loops: f32,
    /// Output format: cs559 (thin walls) or grid (tiles: a WxH maze becomes (2W+1)x(2H+1) tiles).
    #[arg(long, default_value = "cs559", value_parser = parse_format)]
    format: Format,
    /// Mark the cell farthest from the start as the exit.
    #[arg(long)]
    exit: bool,
    /// Write to FILE instead of stdout.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

#[derive(Args)]
struct CheckArgs {
    /// The maze file (CS559 or grid format; detected).
    file: PathBuf,
}

/// Exit status for malformed or invalid data (sysexits EX_DATAERR).
const EXIT_DATA: u8 = 65;
/// Exit status for an unreadable input file (sysexits EX_NOINPUT).
const EXIT_NO_INPUT: u8 = 66;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Gen(args) => cmd_gen(&args),
        Command::Check(args) => cmd_check(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            let load = err.downcast_ref::<LoadError>();
            match load {
                Some(e) => eprintln!("{e}"), // FILE:LINE:COL: message, for editors to jump to
                None => eprintln!("mazewalk: {err:#}"),
            }
            ExitCode::from(match load {
                Some(LoadError::Parse(_)) => EXIT_DATA,
                Some(LoadError::Io { .. }) => EXIT_NO_INPUT,
                None => 1,
            })
        }
    }
}

fn cmd_gen(args: &GenArgs) -> anyhow::Result<()> {
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
        Some(path) => (
            Box::new(File::create(path).with_context(|| format!("{}: cannot create", path.display()))?),
            path.display().to_string(),
        ),
        None => (Box::new(std::io::stdout().lock()), "stdout".into()),
    };
    let mut out = BufWriter::new(sink);
    match args.format {
        // streamed: a 1000x1000 maze is 160 MB of text
        Format::Cs559 => maze::cs559::write_to(&generate(&opts)?, &mut out)?,
        Format::Grid => out.write_all(generate_grid(&opts)?.to_text().as_bytes())?,
    }
    out.flush().with_context(|| format!("{name}: cannot write"))?;
    Ok(())
}

fn cmd_check(args: &CheckArgs) -> anyhow::Result<()> {
    let bytes = std::fs::read(&args.file)
        .map_err(|source| LoadError::Io { path: args.file.display().to_string(), source })?;
    let name = args.file.display().to_string();
    let format = maze::detect_format(&String::from_utf8_lossy(&bytes));
    let maze = maze::parse(&name, &bytes).map_err(LoadError::from)?;
    print!("{}", summary(&name, format, &maze));
    Ok(())
}

/// The `check` report.
fn summary(name: &str, format: Format, maze: &Maze) -> String {
    let e = maze.extents();
    let v = maze.viewer();
    let exit = maze.exit().map_or("none".to_string(), |x| match x.point {
        Some(p) => format!("cell {} at ({}, {})", x.cell, p.x, p.y),
        None => format!("cell {}", x.cell),
    });
    format!(
        "{name}: ok\n  format:   {format}\n  cells:    {}\n  edges:    {} ({} opaque walls, {} portals)\n  \
         extents:  ({}, {}) .. ({}, {})\n  viewer:   ({}, {}) z {} facing {}° fov {}° in cell {}\n  \
         exit:     {exit}\n  perfect:  {}\n",
        maze.cell_count(),
        maze.edges().len(),
        maze.wall_count(),
        maze.portal_count(),
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

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("expected WxH, e.g. 20x10, found `{s}`"))?;
    let side = |t: &str| match t.trim().parse::<u32>() {
        Ok(n) if (1..=MAX_SIDE).contains(&n) => Ok(n),
        _ => Err(format!("each side must be an integer in 1..={MAX_SIDE}, found `{t}`")),
    };
    Ok((side(w)?, side(h)?))
}

fn parse_loops(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        _ => Err(format!("expected a fraction in 0..=1, found `{s}`")),
    }
}

fn parse_algo(s: &str) -> Result<Algorithm, String> {
    s.parse()
}

fn parse_format(s: &str) -> Result<Format, String> {
    match s {
        "cs559" => Ok(Format::Cs559),
        "grid" => Ok(Format::Grid),
        _ => Err(format!("unknown format `{s}` (expected cs559 or grid)")),
    }
}
