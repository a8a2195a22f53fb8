//! The `mazewalk` binary: command-line wiring only — the flags are parsed by [`mazewalk::cli`], every
//! command's work is the library's; here each command is dispatched and its outcome turned into an
//! exit code.
//!
//! `mazewalk [MAZE]` walks a maze (the built-in one without MAZE); `render`, `gen` and `check` are the
//! batch commands. Exit codes: 0 success, 2 usage errors (bad flags or values), 65 malformed or invalid
//! maze data or a file over the size limit, 66 cannot read the file, 141 stdout's reader went away,
//! 128 + n the walk ended by signal n, 1 anything else (e.g. no terminal). Maze errors go to stderr
//! as `FILE:LINE:COL: message`.

use std::fs::File;
use std::io::{BufWriter, IsTerminal as _, Write};
use std::process::ExitCode;

use std::time::Instant;

use anyhow::{Context as _, bail};
use clap::Parser as _;
use mazewalk::cli::{
    CheckArgs, Cli, Command, GenArgs, MAX_FRAME_CELLS, MazeArgs, RenderArgs, ServeArgs, WalkArgs,
};
use mazewalk::guard;
use mazewalk::run::run;
use mazewalk_maze::generate::{GenOptions, generate, generate_grid};
use mazewalk_maze::geometry::WALL_MARGIN;
use mazewalk_maze::movement::is_clear;
use mazewalk_maze::{self as maze, Format, LoadError, Maze};
use mazewalk_render::{Camera, Charset, Culling, Renderer, Target};
use mazewalk_term::frame::{Frame, Region};
use mazewalk_term::{caps, encoder};
use mazewalk_walk::state::{Motion, stand, viewer_camera};
use mazewalk_walk::{App, Session, SessionOptions};

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

/// Prints clap's help, version or usage error and gives its exit code, or says why it could not print.
fn clap_exit(e: &clap::Error) -> ExitCode {
    let code = ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(1));
    match e.print().and_then(|()| std::io::stdout().flush()) {
        Ok(()) => code,
        // A usage error that stderr cannot show still has its exit code, as other errors below.
        Err(_) if e.use_stderr() => code,
        Err(err) if err.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::from(EXIT_BROKEN_PIPE),
        Err(err) => {
            let _ = writeln!(std::io::stderr(), "mazewalk: cannot write to stdout: {err}");
            ExitCode::FAILURE
        }
    }
}

/// A flag value that parsed but makes no sense here (e.g. --at outside the maze): exit 2.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct Usage(String);

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // clap's own exit ignores a failed write, so `--help > /dev/full` would report success.
        Err(e) => return clap_exit(&e),
    };
    let result = match cli.command {
        None => cmd_walk(&cli.walk),
        Some(Command::Render(args)) => cmd_render(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Gen(args)) => cmd_gen(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Check(args)) => cmd_check(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Serve(args)) => cmd_serve(&args),
    };
    match result {
        Ok(code) => code,
        // A reader that went away (`mazewalk gen … | head`): end quietly, as if killed by SIGPIPE
        // like other Unix tools (Rust programs ignore the signal and see the error instead).
        Err(err) if is_broken_pipe(&err) => ExitCode::from(EXIT_BROKEN_PIPE),
        Err(err) => {
            let load = err.downcast_ref::<LoadError>();
            // (Not eprintln!, which panics when stderr cannot be written: the exit code still tells.)
            let _ = match load {
                Some(e) => writeln!(std::io::stderr(), "{e}"), // FILE:LINE:COL: message, for editors
                None => writeln!(std::io::stderr(), "mazewalk: {err:#}"),
            };
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

fn cmd_walk(args: &WalkArgs) -> anyhow::Result<ExitCode> {
    let maze = load_maze(&args.maze)?;
    let unfit = match std::env::var("TERM") {
        Err(std::env::VarError::NotPresent) => Some("TERM is unset"),
        Err(std::env::VarError::NotUnicode(_)) => Some("TERM is not UTF-8"),
        Ok(term) if term.is_empty() => Some("TERM is empty"),
        Ok(term) if term == "dumb" => Some("TERM=dumb"),
        Ok(_) => None,
    };
    if let Some(unfit) = unfit
        && !args.force_terminal
    {
        bail!(
            "this terminal ({unfit}) cannot run the full-screen walk: it needs cursor movement and an \
             alternate screen; set TERM to your terminal (e.g. xterm-256color), use `mazewalk render`, \
             or start anyway with --force-terminal"
        );
    }
    if !std::io::stdin().is_terminal() || !std::io::stdout().is_terminal() {
        bail!("the walkthrough needs a terminal (try `mazewalk render` to print a frame, or --help)");
    }
    let clock = Instant::now(); // the walk's time 0
    let mut app = App::new(maze, args.look.options(Culling::Portal), 0.0)?;
    app.reveal_map = args.reveal_map;
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
        let _ = writeln!(std::io::stdout(), "You found the exit in {seconds:.1} s."); // the walk is over either way
    }
    Ok(ExitCode::SUCCESS)
}

/// Writes `frame` as drawn with `charset` as a PNG (8-bit RGB) to `path` (`-`: standard output), one
/// row of cells at a time (the largest `--size` is a 12,000 × 24,000-pixel picture: never whole in
/// memory).
fn write_png(path: &std::path::Path, frame: &Frame, charset: Charset) -> anyhow::Result<()> {
    if path == STDOUT {
        let stdout = std::io::stdout();
        if stdout.is_terminal() {
            return Err(Usage(
                "--png -: standard output is a terminal, not the place for a picture; redirect it (> frame.png)"
                    .into(),
            )
            .into());
        }
        return write_png_to(BufWriter::new(stdout.lock()), "stdout", frame, charset);
    }
    let file = File::create(path).with_context(|| format!("{}: cannot create", path.display()))?;
    write_png_to(BufWriter::new(file), &path.display().to_string(), frame, charset)
}

/// [`write_png`] into `sink`, named `name` in errors.
fn write_png_to(sink: impl Write, name: &str, frame: &Frame, charset: Charset) -> anyhow::Result<()> {
    use mazewalk_render::picture::{for_each_band, picture_size};
    let mut sink = PipeWatch { inner: sink, broken: false };
    let (width, height) = picture_size(frame);
    let mut encode = || -> anyhow::Result<()> {
        let mut png = png::Encoder::new(&mut sink, width as u32, height as u32);
        png.set_color(png::ColorType::Rgb);
        png.set_depth(png::BitDepth::Eight);
        let mut png = png.write_header()?;
        let mut stream = png.stream_writer()?;
        for_each_band(frame, charset, |band| stream.write_all(band))?;
        stream.finish()?;
        png.finish()?; // the end chunk, and the buffer flushed: its errors too
        Ok(())
    };
    let result = encode();
    // png's errors keep an io::Error's text but not its kind, which `is_broken_pipe` looks for.
    let result = match result {
        Err(_) if sink.broken => Err(std::io::Error::from(std::io::ErrorKind::BrokenPipe).into()),
        result => result,
    };
    result.with_context(|| format!("{name}: cannot write"))
}

/// A writer that remembers whether a write failed because its reader went away.
struct PipeWatch<W> {
    inner: W,
    broken: bool,
}

impl<W: Write> PipeWatch<W> {
    fn watch<T>(&mut self, result: std::io::Result<T>) -> std::io::Result<T> {
        if let Err(e) = &result {
            self.broken |= e.kind() == std::io::ErrorKind::BrokenPipe;
        }
        result
    }
}

impl<W: Write> Write for PipeWatch<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let result = self.inner.write(buf);
        self.watch(result)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let result = self.inner.flush();
        self.watch(result)
    }
}

/// The path that names standard output in `render --png`, `--depth-out` and `gen -o`.
const STDOUT: &str = "-";

/// `mazewalk serve`: checks the maze, the host key and who may play before listening, prints where and
/// how to connect, then serves until SIGINT, SIGTERM or SIGHUP (exit 128 + n, as the walk).
#[cfg(all(unix, feature = "serve"))]
fn cmd_serve(args: &ServeArgs) -> anyhow::Result<ExitCode> {
    use mazewalk_render::RenderOptions;
    use mazewalk_serve::{Access, Limits, ServeOptions, host_key};
    let maze = load_maze(&args.maze)?;
    App::new(maze.clone(), RenderOptions::default(), 0.0)?; // a start in no cell fails here, not per player
    let env = |k: &str| std::env::var(k).ok();
    let key_path = match &args.host_key {
        Some(path) => path.clone(),
        None => host_key::default_path(env)?,
    };
    let (host_key, made) = host_key::load_or_create(&key_path).context("host key")?;
    let access = if args.open {
        Access::Open
    } else {
        let path = match &args.authorized_keys {
            Some(path) => path.clone(),
            None => std::path::PathBuf::from(env("HOME").unwrap_or_default()).join(".ssh/authorized_keys"),
        };
        let read = host_key::read_authorized_keys(&path)
            .with_context(|| "who may play (give --authorized-keys FILE, or --open to let anyone in)")?;
        for left in &read.left_out {
            let _ = writeln!(
                std::io::stderr(),
                "mazewalk: {}: key {} ({}) is limited by `{}`, which mazewalk does not enforce: it may not play",
                path.display(),
                left.number,
                left.comment,
                left.option
            );
        }
        if read.keys.is_empty() {
            bail!("{}: no keys that may play, so nobody could (add some, or use --open)", path.display());
        }
        Access::Keys(read.keys)
    };
    let fingerprint = host_key::fingerprint(host_key.public_key());
    let limits = Limits {
        max_players: args.max_players as usize,
        max_per_address: args.max_per_address as usize,
        idle_timeout: args.idle_timeout,
        ..Limits::default()
    };
    let options = ServeOptions { maze, listen: args.listen, host_key, access, limits };
    tracing_subscriber::fmt().with_writer(std::io::stderr).with_target(false).init();
    let signal = mazewalk_serve::run(options, |addr| {
        let made = if made { ", made now" } else { "" };
        // for the host to read; a closed pipe (`serve | head -1`) must not end the server
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "mazewalk: serving on {addr}")
            .and_then(|()| writeln!(out, "host key {fingerprint} ({}{made})", key_path.display()))
            .and_then(|()| {
                // Listening on every address: the players need one of this machine's names.
                let host =
                    if addr.ip().is_unspecified() { "THIS-HOST".to_string() } else { addr.ip().to_string() };
                writeln!(out, "players connect with: ssh -p {} {host}", addr.port())
            })
            .and_then(|()| out.flush());
    })
    .with_context(|| format!("serving on {}", args.listen))?;
    Ok(ExitCode::from(u8::try_from(guard::exit_code_for_signal(signal)).unwrap_or(1)))
}

#[cfg(not(all(unix, feature = "serve")))]
fn cmd_serve(_: &ServeArgs) -> anyhow::Result<ExitCode> {
    if cfg!(unix) {
        bail!("this mazewalk was built without `serve` (build it with the default features to host a maze)");
    }
    bail!("`mazewalk serve` runs on Unix only");
}

fn cmd_render(args: &RenderArgs) -> anyhow::Result<()> {
    if args.png.is_some() && args.look.charset == Charset::Ascii {
        return Err(
            Usage("--png draws the block charsets (half, quad, sextant); ascii is text".into()).into()
        );
    }
    // Where each output goes: the frame as text (without --png), the picture, the depths. At most one
    // of them on standard output, and no two into one file (the second would overwrite the first).
    let to_stdout = |path: &Option<std::path::PathBuf>| path.as_deref().is_some_and(|p| p == STDOUT);
    if args.png.is_none() && to_stdout(&args.depth_out) {
        return Err(Usage(
            "--depth-out -: standard output already gets the frame; write the depths to a file, or the frame with --png FILE"
                .into(),
        )
        .into());
    }
    if let (Some(png), Some(depths)) = (&args.png, &args.depth_out)
        && png == depths
    {
        let what = if png == STDOUT { "standard output".to_owned() } else { png.display().to_string() };
        return Err(Usage(format!("--png and --depth-out both write {what}: give them two places")).into());
    }
    if args.png.is_none() || to_stdout(&args.png) || to_stdout(&args.depth_out) {
        stdout_open()?;
    }
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
    let Some(stands) = stand(&maze, position) else {
        let e = maze.extents();
        let inside = position.cmpge(e.min).all() && position.cmple(e.max).all();
        let what = if inside { "is inside a wall (in no cell)" } else { "is outside the maze" };
        let (lo, hi) = (e.min, e.max);
        return Err(Usage(format!(
            "--at {},{} {what}; the maze spans ({}, {}) .. ({}, {})",
            position.x, position.y, lo.x, lo.y, hi.x, hi.y
        ))
        .into());
    };
    if !is_clear(&maze, stands, WALL_MARGIN) {
        return Err(Usage(format!(
            "--at {},{} has no room to stand: the walk keeps {WALL_MARGIN} from every wall, and no place near \
             it is that far from them",
            position.x, position.y
        ))
        .into());
    }
    // The file's view as the walk starts from it (made usable: `viewer_camera`), then the flags,
    // which must be usable as given.
    let from_file = viewer_camera(viewer);
    let camera = Camera {
        position: stands.pos,
        eye_z: args.height.unwrap_or(from_file.eye_z),
        pitch_deg: args.pitch,
        projection: args.projection,
        yaw_deg: args.heading.unwrap_or(from_file.yaw_deg),
        hfov_deg: args.fov.unwrap_or(from_file.hfov_deg),
        ..from_file
    };
    camera.validate().map_err(|e| Usage(e.to_string()))?;
    // The depths' file made now, so that a place it cannot go stops the command before the frame
    // is written anywhere.
    let depth_file = match &args.depth_out {
        Some(path) if path != STDOUT => {
            Some(File::create(path).with_context(|| format!("{}: cannot create", path.display()))?)
        }
        _ => None,
    };
    let options = args.look.options(args.culling);
    let mut renderer = Renderer::new();
    let mut frame = Frame::new(cols, rows);
    let region = Region { col: 0, row: 0, cols, rows };
    let mut times_us = Vec::with_capacity(args.repeat as usize);
    let mut stats = None;
    for _ in 0..args.repeat {
        let started = Instant::now();
        stats = Some(
            renderer
                .render(&maze, &camera, &[], &options, Target::Frame(&mut frame, region))
                .map_err(|e| Usage(e.to_string()))?,
        );
        times_us.push(started.elapsed().as_secs_f64() * 1e6);
    }
    let stats = stats.expect("--repeat is at least 1");
    let micros = times_us[0].round() as u64; // the first, cold render
    if let Some(path) = &args.png {
        write_png(path, &frame, options.charset)?;
    } else {
        let mut out = Vec::with_capacity(cols * rows * 4);
        encoder::ansi_lines(&frame, &mut out);
        std::io::stdout().lock().write_all(&out).context("cannot write to stdout")?;
    }
    if args.stats {
        let mut json = serde_json::json!({
            "cells_visited": stats.portal.cells_visited,
            "distinct_cells": stats.portal.distinct_cells,
            "portals_traversed": stats.portal.portals_traversed,
            "walls_drawn": stats.walls_drawn,
            "triangles": stats.triangles,
            "samples_written": stats.samples_written,
            "render_us": micros,
            "culling": args.culling.to_string(),
            "cells_in_maze": maze.cell_count(),
            // Where the frame was seen from: the asked place, or the walk's margin off a wall.
            "viewer": stands.pos.to_array().map(|x| (f64::from(x) * 1e4).round() / 1e4),
        });
        if args.repeat > 1 {
            times_us.sort_by(f64::total_cmp);
            let median = times_us[times_us.len() / 2];
            json["repeat"] = args.repeat.into();
            json["render_us_median"] = ((median * 10.0).round() / 10.0).into();
            json["render_us_min"] = ((times_us[0] * 10.0).round() / 10.0).into();
            json["render_us_max"] = ((times_us[times_us.len() - 1] * 10.0).round() / 10.0).into();
        }
        writeln!(std::io::stderr(), "{json}").context("cannot write the stats to stderr")?;
    }
    if let Some(path) = &args.depth_out {
        renderer
            .render(&maze, &camera, &[], &options, Target::Depths { cols, rows })
            .map_err(|e| Usage(e.to_string()))?;
        let depths: Vec<Option<f32>> = renderer.cell_depths().collect();
        let mut csv = String::with_capacity(depths.len() * 8);
        for row in depths.chunks(cols) {
            let fields: Vec<String> =
                row.iter().map(|d| d.map_or(String::new(), |d| format!("{d:.4}"))).collect();
            csv.push_str(&fields.join(","));
            csv.push('\n');
        }
        match depth_file {
            Some(mut file) => {
                file.write_all(csv.as_bytes())
                    .with_context(|| format!("{}: cannot write", path.display()))?;
            }
            None => std::io::stdout().lock().write_all(csv.as_bytes()).context("cannot write to stdout")?,
        }
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
        Some(path) if path != STDOUT => (
            Box::new(File::create(path).with_context(|| format!("{}: cannot create", path.display()))?),
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

fn cmd_check(args: &CheckArgs) -> anyhow::Result<()> {
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
    let exit = maze.exit().map_or("none".to_string(), |x| match x.point {
        Some(p) => format!("cell {} at ({}, {})", x.cell, p.x, p.y),
        None => format!("cell {}", x.cell),
    });
    // Where the walk starts instead, when the file's viewer stands closer to a wall than it may.
    let moved = match stand(maze, v.pos) {
        Some(at) if at.pos != v.pos => format!(
            "\n            (closer than {WALL_MARGIN} to a wall: the walk starts at ({}, {}))",
            at.pos.x, at.pos.y
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
