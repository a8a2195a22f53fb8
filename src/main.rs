//! The `mazewalk` binary: command-line wiring only; everything else lives in the library.
//!
//! `mazewalk [MAZE]` walks a maze (the built-in one without MAZE); `render`, `gen` and `check` are the
//! batch commands. Exit codes: 0 success, 2 usage errors (bad flags or values), 65 malformed or invalid
//! maze data, 66 cannot read the file, 1 anything else (e.g. no terminal). Maze errors go to stderr
//! as `FILE:LINE:COL: message`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::process::ExitCode;

use std::time::Instant;

use anyhow::{Context as _, bail};
use clap::{Args, Parser, Subcommand};
use glam::Vec2;
use mazewalk::app::run::run;
use mazewalk::app::state::{self, Motion};
use mazewalk::app::{App, Session, SessionOptions};
use mazewalk::frame::{ColorDepth, Frame, Region};
use mazewalk::maze::generate::{Algorithm, GenOptions, MAX_SIDE, generate, generate_grid};
use mazewalk::maze::{self, Format, LoadError, Maze};
use mazewalk::render::{Camera, Charset, Culling, Projection, RenderOptions, Renderer};
use mazewalk::term::{caps, encoder, guard};

#[derive(Parser)]
#[command(
    name = "mazewalk",
    version,
    about = "A first-person 3D maze walkthrough for the terminal",
    long_about = "A first-person 3D maze walkthrough for the terminal.\n\n\
        Without a command, walks MAZE (CS559 or grid format), a fresh --gen maze, or the built-in maze.\n\
        Keys: W/S walk, A/D strafe, arrows turn and look, [ ] down/up, + - fov, p projection, m map,\n\
        c glyphs, r reset, ? help, q quit.",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    walk: WalkArgs,
}

#[derive(Args)]
struct WalkArgs {
    #[command(flatten)]
    maze: MazeArgs,
    #[command(flatten)]
    look: LookArgs,
    /// Truecolor cells whose colours moved by at most this many 8-bit steps per channel since they were
    /// sent stay as they are (fewer bytes while walking; 0: every change is sent exactly).
    #[arg(long, value_name = "STEPS", default_value_t = encoder::DEFAULT_TOLERANCE, value_parser = clap::value_parser!(u8).range(0..=i64::from(encoder::MAX_TOLERANCE)))]
    color_tolerance: u8,
    /// Start the full-screen walk even where TERM says the terminal cannot take it (dumb, unset, empty).
    #[arg(long)]
    force_terminal: bool,
    /// Send frames as fast as they are drawn, without waiting for the terminal to show the previous
    /// ones (by default at most 2 frames are on their way: on a slow link the picture keeps up with
    /// the keys instead of falling behind).
    #[arg(long)]
    no_flow_control: bool,
    #[command(flatten)]
    motion: MotionArgs,
}

/// How far a tap moves and how fast a held key moves.
#[derive(Args)]
struct MotionArgs {
    /// Turning speed while ← or → is held, degrees per second (10..=720).
    #[arg(long, value_name = "DEG_PER_S", default_value_t = state::TURN_SPEED, value_parser = |s: &str| parse_in(s, state::TURN_SPEED_RANGE))]
    turn_speed: f32,
    /// Walking speed while W/S/A/D is held, maze units per second (0.5..=40; a generated cell is 4).
    #[arg(long, value_name = "UNITS_PER_S", default_value_t = state::WALK_SPEED, value_parser = |s: &str| parse_in(s, state::WALK_SPEED_RANGE))]
    walk_speed: f32,
    /// How far one tap of ← or → turns, degrees (1..=90).
    #[arg(long, value_name = "DEG", default_value_t = state::TURN_STEP_DEG, value_parser = |s: &str| parse_in(s, state::TURN_STEP_RANGE_DEG))]
    turn_step: f32,
    /// How far one tap of W/S/A/D walks, maze units (0.05..=4).
    #[arg(long, value_name = "UNITS", default_value_t = state::WALK_STEP, value_parser = |s: &str| parse_in(s, state::WALK_STEP_RANGE))]
    walk_step: f32,
}

/// Where the maze comes from.
#[derive(Args)]
struct MazeArgs {
    /// Maze file (CS559 or grid format, detected); the built-in maze if omitted.
    #[arg(value_name = "MAZE", conflicts_with = "gen")]
    maze: Option<PathBuf>,
    /// Walk a fresh random maze of WxH cells instead (with loops and an exit).
    #[arg(long = "gen", id = "gen", value_name = "WxH", value_parser = parse_size)]
    generate: Option<(u32, u32)>,
    /// Seed for --gen (the same seed gives the same maze).
    #[arg(long, default_value_t = 1, requires = "gen")]
    seed: u64,
    #[command(flatten)]
    read: ReadArgs,
}

/// How maze files are read.
#[derive(Args)]
struct ReadArgs {
    /// Refuse maze files larger than this many bytes (suffixes K, M, G: 1024-based).
    #[arg(long, value_name = "BYTES", default_value = "256M", value_parser = parse_bytes)]
    max_file_size: u64,
}

/// How frames look.
#[derive(Args)]
struct LookArgs {
    /// Glyphs: ascii (one sample per cell), half (▀, 1×2), quad (2×2) or sextant (2×3).
    #[arg(long, default_value = "half")]
    charset: Charset,
    /// Colour depth: none, 16, 256 or truecolor (default: from COLORTERM/TERM; NO_COLOR gives none).
    #[arg(long)]
    color: Option<ColorDepth>,
    /// Terminal cell width / height (cells are about twice as tall as wide).
    #[arg(long, default_value_t = 0.5, value_parser = parse_cell_aspect)]
    cell_aspect: f32,
}

#[derive(Subcommand)]
enum Command {
    /// Render one frame to stdout and exit (plain text with --color none, ANSI otherwise).
    Render(RenderArgs),
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
    #[arg(long, default_value = "prim")]
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
struct RenderArgs {
    #[command(flatten)]
    maze: MazeArgs,
    #[command(flatten)]
    look: LookArgs,
    /// Eye position X,Y in the maze plane (default: the file's viewer).
    #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true)]
    at: Option<Vec2>,
    /// Eye height, strictly between the floor (-1) and the ceiling (+1).
    #[arg(long, value_name = "Z", allow_hyphen_values = true, value_parser = parse_finite)]
    height: Option<f32>,
    /// Heading in degrees counter-clockwise from +x (default: the file's).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_heading)]
    heading: Option<f32>,
    /// Pitch in degrees, positive looks up (-90..=90).
    #[arg(long, value_name = "DEG", default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_pitch)]
    pitch: f32,
    /// Horizontal field of view across the whole frame, degrees (10..=170; default: the file's).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_finite)]
    fov: Option<f32>,
    /// Frame size in terminal cells: at most 2000 per side and 1,000,000 cells in all.
    #[arg(long, value_name = "COLSxROWS", default_value = "80x24", value_parser = parse_frame_size)]
    size: (usize, usize),
    /// perspective or orthographic.
    #[arg(long, default_value = "perspective")]
    projection: Projection,
    /// portal (cell-and-portal visibility) or none (every wall: brute force).
    #[arg(long, default_value = "portal")]
    culling: Culling,
    /// Print one JSON object of counts and timing on stderr.
    #[arg(long)]
    stats: bool,
    /// Write a CSV of ROWS lines × COLS values: the view-space depth of the wall seen through each
    /// cell's centre, empty where none.
    #[arg(long, value_name = "FILE")]
    depth_out: Option<PathBuf>,
}

#[derive(Args)]
struct CheckArgs {
    /// The maze file (CS559 or grid format; detected); `-` reads standard input.
    file: PathBuf,
    #[command(flatten)]
    read: ReadArgs,
}

/// Exit status for bad flags or values (as clap's).
const EXIT_USAGE: u8 = 2;
/// Exit status for malformed or invalid data (sysexits EX_DATAERR).
const EXIT_DATA: u8 = 65;
/// Exit status for an unreadable input file (sysexits EX_NOINPUT).
const EXIT_NO_INPUT: u8 = 66;

/// Exit status when the reader of stdout went away: 128 + SIGPIPE, as shells report a tool killed by it.
const EXIT_BROKEN_PIPE: u8 = 128 + 13;

/// Whether `err` is, or was caused by, writing to a pipe nobody reads.
fn is_broken_pipe(err: &anyhow::Error) -> bool {
    let broken = |e: &std::io::Error| e.kind() == std::io::ErrorKind::BrokenPipe;
    err.chain().any(|e| match e.downcast_ref::<maze::cs559::WriteToError>() {
        Some(maze::cs559::WriteToError::Io(e)) => broken(e),
        _ => e.downcast_ref::<std::io::Error>().is_some_and(broken),
    })
}

/// Fails if stdout was closed (`>&-`), so that a command does not exit 0 having written nothing.
/// The Rust runtime opens /dev/null read-write in place of a closed standard descriptor at start-up;
/// a shell's `> /dev/null` opens it write-only. So /dev/null open for reading and writing means
/// "closed" (and a descriptor that is really closed fails `fstat`).
fn stdout_open() -> anyhow::Result<()> {
    #[cfg(target_os = "linux")]
    {
        use rustix::fs::{FileType, OFlags, fcntl_getfl, fstat, major, minor};
        let stdout = std::io::stdout();
        let closed = match fstat(&stdout) {
            Err(_) => true,
            Ok(st) => {
                let dev_null = FileType::from_raw_mode(st.st_mode) == FileType::CharacterDevice
                    && (major(st.st_rdev), minor(st.st_rdev)) == (1, 3);
                dev_null && fcntl_getfl(&stdout).is_ok_and(|f| f.contains(OFlags::RDWR))
            }
        };
        if closed {
            bail!("stdout is closed: nowhere to write");
        }
    }
    Ok(())
}

/// Largest frame `render` makes, in cells (a million cells of sextants are 6 M samples, ~150 MB).
const MAX_FRAME_CELLS: usize = 1_000_000;

/// A flag value that parsed but makes no sense here (e.g. --at outside the maze): exit 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct Usage(String);

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => cmd_walk(&cli.walk),
        Some(Command::Render(args)) => cmd_render(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Gen(args)) => cmd_gen(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Check(args)) => cmd_check(&args).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        // A reader that went away (`mazewalk gen … | head`): end quietly, as if killed by SIGPIPE
        // like other Unix tools (Rust programs ignore the signal and see the error instead).
        Err(err) if is_broken_pipe(&err) => ExitCode::from(EXIT_BROKEN_PIPE),
        Err(err) => {
            let load = err.downcast_ref::<LoadError>();
            match load {
                Some(e) => eprintln!("{e}"), // FILE:LINE:COL: message, for editors to jump to
                None => eprintln!("mazewalk: {err:#}"),
            }
            ExitCode::from(match load {
                Some(LoadError::Parse(_) | LoadError::TooLarge { .. }) => EXIT_DATA,
                Some(LoadError::Io { .. } | LoadError::NotAFile { .. }) => EXIT_NO_INPUT,
                None if err.downcast_ref::<Usage>().is_some() => EXIT_USAGE,
                None => 1,
            })
        }
    }
}

/// Loads, generates or unpacks the maze the flags name.
fn load_maze(args: &MazeArgs) -> anyhow::Result<Maze> {
    if let Some((width, height)) = args.generate {
        let opts =
            GenOptions { width, height, seed: args.seed, loops: 0.1, exit: true, ..GenOptions::default() };
        return Ok(generate(&opts)?);
    }
    match &args.maze {
        Some(path) => Ok(maze::load_with(path, &args.read.options())?.maze),
        None => Ok(maze::builtin()?),
    }
}

impl LookArgs {
    fn options(&self, culling: Culling) -> RenderOptions {
        let env = |k: &str| std::env::var(k).ok();
        let color_depth = self.color.unwrap_or_else(|| caps::detect_color_depth(env));
        RenderOptions { charset: self.charset, color_depth, culling, cell_aspect: self.cell_aspect }
    }
}

fn cmd_walk(args: &WalkArgs) -> anyhow::Result<ExitCode> {
    use std::io::IsTerminal as _;
    let maze = load_maze(&args.maze)?;
    let term = std::env::var("TERM").unwrap_or_default();
    if !args.force_terminal && (term.is_empty() || term == "dumb") {
        bail!(
            "this terminal (TERM={}) cannot run the full-screen walk: it needs cursor movement and an \
             alternate screen; set TERM to your terminal (e.g. xterm-256color), use `mazewalk render`, \
             or start anyway with --force-terminal",
            if term.is_empty() { "unset" } else { "dumb" }
        );
    }
    if !std::io::stdin().is_terminal() || !std::io::stdout().is_terminal() {
        bail!("the walkthrough needs a terminal (try `mazewalk render` to print a frame, or --help)");
    }
    let clock = Instant::now(); // the walk's time 0
    let mut app = App::new(maze, args.look.options(Culling::Portal), 0.0)?;
    let m = &args.motion;
    app.motion = Motion {
        turn_speed_deg: m.turn_speed,
        walk_speed: m.walk_speed,
        turn_step_deg: m.turn_step,
        walk_step: m.walk_step,
    };
    let env = |k: &str| std::env::var(k).ok();
    let options = SessionOptions {
        bce: caps::detect_bce(env),
        color_tolerance: args.color_tolerance,
        flow_control: !args.no_flow_control,
    };
    let mut session = Session::new(app, 80, 24, options); // resized to the terminal by `run`
    if let Some(signal) = run(&mut session, clock).context("terminal")?.signal() {
        return Ok(ExitCode::from(u8::try_from(guard::exit_code_for_signal(signal)).unwrap_or(1)));
    }
    if let Some(seconds) = session.outcome().finished {
        println!("You found the exit in {seconds:.1} s.");
    }
    Ok(ExitCode::SUCCESS)
}

fn cmd_render(args: &RenderArgs) -> anyhow::Result<()> {
    stdout_open()?;
    let (cols, rows) = args.size;
    if cols * rows > MAX_FRAME_CELLS {
        return Err(Usage(format!(
            "--size {cols}x{rows} is {} cells; at most {MAX_FRAME_CELLS}",
            cols * rows
        ))
        .into());
    }
    let maze = load_maze(&args.maze)?;
    let viewer = maze.viewer();
    let position = args.at.unwrap_or(viewer.pos);
    if maze.cell_at(position).is_none() {
        let e = maze.extents();
        let inside = position.cmpge(e.min).all() && position.cmple(e.max).all();
        let what = if inside { "is inside a wall (in no cell)" } else { "is outside the maze" };
        let (lo, hi) = (e.min, e.max);
        return Err(Usage(format!(
            "--at {},{} {what}; the maze spans ({}, {}) .. ({}, {})",
            position.x, position.y, lo.x, lo.y, hi.x, hi.y
        ))
        .into());
    }
    let camera = Camera {
        eye_z: args.height.unwrap_or(viewer.z),
        pitch_deg: args.pitch,
        projection: args.projection,
        ..Camera::new(position, args.heading.unwrap_or(viewer.dir_deg), args.fov.unwrap_or(viewer.fov_deg))
    };
    camera.validate().map_err(|e| Usage(e.to_string()))?;
    let options = args.look.options(args.culling);
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(cols, rows);
    let started = Instant::now();
    let stats = renderer
        .render(&maze, &camera, &options, &mut frame, Region { col: 0, row: 0, cols, rows })
        .map_err(|e| Usage(e.to_string()))?;
    let micros = started.elapsed().as_micros();
    let mut out = Vec::with_capacity(cols * rows * 4);
    encoder::ansi_lines(&frame, &mut out);
    std::io::stdout().lock().write_all(&out).context("cannot write to stdout")?;
    if args.stats {
        let json = serde_json::json!({
            "cells_visited": stats.portal.cells_visited,
            "distinct_cells": stats.portal.distinct_cells,
            "portals_traversed": stats.portal.portals_traversed,
            "walls_drawn": stats.walls_drawn,
            "triangles": stats.triangles,
            "samples_written": stats.samples_written,
            "render_us": micros,
            "culling": args.culling.to_string(),
            "cells_in_maze": maze.cell_count(),
        });
        eprintln!("{json}");
    }
    if let Some(path) = &args.depth_out {
        let depths = renderer
            .depth_at_cell_centres(&maze, &camera, options.cell_aspect, args.culling, cols, rows)
            .map_err(|e| Usage(e.to_string()))?;
        let mut csv = String::with_capacity(depths.len() * 8);
        for row in depths.chunks(cols) {
            let fields: Vec<String> =
                row.iter().map(|d| d.map_or(String::new(), |d| format!("{d:.4}"))).collect();
            csv.push_str(&fields.join(","));
            csv.push('\n');
        }
        std::fs::write(path, csv).with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
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
        None => {
            stdout_open()?;
            (Box::new(std::io::stdout().lock()), "stdout".into())
        }
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
    stdout_open()?;
    let loaded = maze::load_with(&args.file, &args.read.options())?;
    let report = summary(&maze::quote_path(&args.file.display().to_string()), loaded.format, &loaded.maze);
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(report.as_bytes()).and_then(|()| stdout.flush()).context("cannot write to stdout")?;
    Ok(())
}

impl ReadArgs {
    fn options(&self) -> maze::LoadOptions {
        maze::LoadOptions { max_bytes: self.max_file_size }
    }
}

/// `123`, `64K`, `256M`, `2G` (1024-based).
fn parse_bytes(s: &str) -> Result<u64, String> {
    let (digits, shift) = match s.trim().char_indices().last() {
        Some((i, 'k' | 'K')) => (&s.trim()[..i], 10),
        Some((i, 'm' | 'M')) => (&s.trim()[..i], 20),
        Some((i, 'g' | 'G')) => (&s.trim()[..i], 30),
        _ => (s.trim(), 0),
    };
    match digits.parse::<u64>().ok().and_then(|n| n.checked_mul(1 << shift)) {
        Some(n) if n > 0 => Ok(n),
        _ => Err(format!("expected a size in bytes such as 1000000, 512K, 256M or 2G, found `{s}`")),
    }
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

/// `WxH` with each side in `1..=max`: maze sizes (`--gen`, `gen --size`) and frame sizes.
fn parse_dims<T>(s: &str, max: T, what: &str) -> Result<(T, T), String>
where
    T: std::str::FromStr + PartialOrd + From<u8> + std::fmt::Display + Copy,
{
    let (w, h) =
        s.split_once(['x', 'X']).ok_or_else(|| format!("expected {what}, e.g. 20x10, found `{s}`"))?;
    let side = |t: &str| match t.trim().parse::<T>() {
        Ok(n) if n >= T::from(1) && n <= max => Ok(n),
        _ => Err(format!("each side must be an integer in 1..={max}, found `{t}`")),
    };
    Ok((side(w)?, side(h)?))
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    parse_dims(s, MAX_SIDE, "WxH")
}

fn parse_loops(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        _ => Err(format!("expected a fraction in 0..=1, found `{s}`")),
    }
}

fn parse_format(s: &str) -> Result<Format, String> {
    match s {
        "cs559" => Ok(Format::Cs559),
        "grid" => Ok(Format::Grid),
        _ => Err(format!("unknown format `{s}` (expected cs559 or grid)")),
    }
}

fn parse_finite(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("expected a finite number, found `{s}`")),
    }
}

/// A heading in degrees: any within ±36,000 (a hundred turns), so that f32 still resolves it.
fn parse_heading(s: &str) -> Result<f32, String> {
    match parse_finite(s)? {
        x if x.abs() <= 36_000.0 => Ok(x),
        _ => Err("a heading must be within -36000..=36000 degrees".to_string()),
    }
}

/// A number in `lo..=hi` (speeds and steps).
fn parse_in(s: &str, (lo, hi): (f32, f32)) -> Result<f32, String> {
    match parse_finite(s)? {
        x if (lo..=hi).contains(&x) => Ok(x),
        x => Err(format!("{x} is outside {lo}..={hi}")),
    }
}

fn parse_pitch(s: &str) -> Result<f32, String> {
    match parse_finite(s)? {
        x if (-90.0..=90.0).contains(&x) => Ok(x),
        x => Err(format!("pitch {x}° is outside -90..=90 (straight down to straight up)")),
    }
}

fn parse_cell_aspect(s: &str) -> Result<f32, String> {
    match parse_finite(s)? {
        x if (0.1..=4.0).contains(&x) => Ok(x),
        x => Err(format!("cell aspect {x} is outside 0.1..=4 (width / height; about 0.5 for most fonts)")),
    }
}

fn parse_point(s: &str) -> Result<Vec2, String> {
    let (x, y) = s.split_once(',').ok_or_else(|| format!("expected X,Y, e.g. 2.5,3, found `{s}`"))?;
    Ok(Vec2::new(parse_finite(x)?, parse_finite(y)?))
}

/// Largest frame `render` makes, per side (a 2000-column frame is already 8 screens wide).
const MAX_FRAME_SIDE: usize = 2000;

fn parse_frame_size(s: &str) -> Result<(usize, usize), String> {
    parse_dims(s, MAX_FRAME_SIDE, "COLSxROWS")
}
