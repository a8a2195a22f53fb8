//! `mazewalk render`: one frame from a place in a maze, as text or a PNG, with its statistics and
//! depths on request.

use std::io::{BufWriter, IsTerminal as _, Write};
use std::time::Instant;

use anyhow::Context as _;

use super::{STDOUT, Usage, load_maze, stdout_open};
use crate::cli::{MAX_FRAME_CELLS, RenderArgs};
use mazewalk_maze::Maze;
use mazewalk_maze::movement::{Position, is_clear};
use mazewalk_render::{Camera, Charset, RenderStats, Renderer, Target};
use mazewalk_term::encoder;
use mazewalk_term::frame::{ColorDepth, Frame, Region};
use mazewalk_walk::screen::draw_range_marks;
use mazewalk_walk::state::{LOOK_AHEAD_FOV_DEG, stand, viewer_camera};

/// Renders the frame the flags describe and writes it (text or PNG), its statistics and its depths.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    check_outputs(args)?;
    let maze = load_maze(&args.maze)?;
    let (camera, stands) = camera(args, &maze)?;
    // The depths' file made now, so that a place it cannot go stops the command before the frame
    // is written anywhere.
    let depth_file = match &args.depth_out {
        Some(path) if path != STDOUT => Some(
            mazewalk_maze::files::create_output(path)
                .with_context(|| format!("{}: cannot create", path.display()))?,
        ),
        _ => None,
    };
    let mut options = args.look.options(args.culling, args.look.charset());
    if args.png.is_some() && args.look.color.is_none() {
        // a picture is no terminal: its colours are the frame's own unless --color asks for fewer
        options.color_depth = ColorDepth::TrueColor;
    }
    let (cols, rows) = args.size;
    let mut renderer = Renderer::new();
    renderer.set_chalk(&chalk_cells(args, &maze)?);
    let mut frame = Frame::new(cols, rows);
    let region = Region { col: 0, row: 0, cols, rows };
    let mut times_us = Vec::with_capacity(args.repeat as usize);
    let mut stats = None;
    for _ in 0..args.repeat {
        let started = Instant::now();
        let target = Target::Frame(&mut frame, region);
        stats =
            Some(renderer.render(&maze, &camera, &[], &options, target).map_err(|e| Usage(e.to_string()))?);
        times_us.push(started.elapsed().as_secs_f64() * 1e6);
    }
    let stats = stats.expect("--repeat is at least 1");
    if args.look_ahead {
        draw_range_marks(&mut frame, (&maze, &camera, stands.cell), &options, region);
    }
    if let Some(path) = &args.png {
        write_png(path, &frame, options.charset)?;
    } else {
        let mut out = Vec::with_capacity(cols * rows * 4);
        encoder::ansi_lines(&frame, &mut out);
        std::io::stdout().lock().write_all(&out).context("cannot write to stdout")?;
    }
    if args.stats {
        let json = stats_json(args, &stats, &mut times_us, maze.cell_count(), stands);
        writeln!(std::io::stderr(), "{json}").context("cannot write the stats to stderr")?;
    }
    if let Some(path) = &args.depth_out {
        renderer
            .render(&maze, &camera, &[], &options, Target::Depths { cols, rows })
            .map_err(|e| Usage(e.to_string()))?;
        let csv = depths_csv(renderer.cell_depths(), cols);
        match depth_file {
            Some(mut file) => {
                file.write_all(csv.as_bytes()).with_context(|| format!("{}: cannot write", path.display()))?
            }
            None => std::io::stdout().lock().write_all(csv.as_bytes()).context("cannot write to stdout")?,
        }
    }
    Ok(())
}

/// Refuses outputs that cannot all be written: the frame as text (without --png), the picture and
/// the depths may have at most one of them on standard output and no two in one file (the second
/// would overwrite the first); stdout must be open if anything goes there; the frame has a size limit.
fn check_outputs(args: &RenderArgs) -> anyhow::Result<()> {
    if args.png.is_some() && args.look.charset() == Charset::Ascii {
        return Err(
            Usage("--png draws the block charsets (half, quad, sextant); ascii is text".into()).into()
        );
    }
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
    Ok(())
}

/// The camera the flags ask for: the file's view as the walk starts from it (made usable:
/// `viewer_camera`), then the flags, which must be usable as given; and where it stands (`--at`, or
/// the walk's margin off a wall).
/// The cells `--chalk` marks: each point's.
fn chalk_cells(args: &RenderArgs, maze: &Maze) -> anyhow::Result<Vec<u32>> {
    let cell = |p: &glam::Vec2| {
        maze.cell_at(*p).ok_or_else(|| Usage(format!("--chalk {},{} is in no cell of the maze", p.x, p.y)))
    };
    Ok(args.chalk.iter().map(cell).collect::<Result<_, _>>()?)
}

fn camera(args: &RenderArgs, maze: &Maze) -> anyhow::Result<(Camera, Position)> {
    let viewer = maze.viewer();
    let position = args.at.unwrap_or(viewer.pos);
    let Some(stands) = stand(maze, position) else {
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
    if !is_clear(maze, stands, maze.clearance()) {
        return Err(Usage(format!(
            "--at {},{} has no room to stand: the walk keeps {} from every wall, and no place near it is \
             that far from them",
            position.x,
            position.y,
            maze.clearance()
        ))
        .into());
    }
    let from_file = viewer_camera(maze);
    let camera = Camera {
        position: stands.pos,
        eye_z: args.height.unwrap_or(from_file.eye_z),
        pitch_deg: args.pitch,
        projection: args.projection,
        yaw_deg: args.heading.unwrap_or(from_file.yaw_deg),
        hfov_deg: args.fov.unwrap_or(if args.look_ahead { LOOK_AHEAD_FOV_DEG } else { from_file.hfov_deg }),
        // `--fov` is the horizontal field as given, as the lens's is: no widening to keep a generated
        // maze's vertical one
        min_vfov_deg: if args.fov.is_some() || args.look_ahead { 0.0 } else { from_file.min_vfov_deg },
        fovea: !args.no_fovea,
        ..from_file
    };
    camera.validate().map_err(|e| Usage(e.to_string()))?;
    Ok((camera, stands))
}

/// `--stats` as one line of JSON: the portal pass's counts, the first (cold) render's time and, with
/// `--repeat`, the median, least and greatest (`times_us` is sorted).
fn stats_json(
    args: &RenderArgs,
    stats: &RenderStats,
    times_us: &mut [f64],
    cells_in_maze: usize,
    stands: Position,
) -> serde_json::Value {
    let mut json = serde_json::json!({
        "cells_visited": stats.portal.cells_visited,
        "distinct_cells": stats.portal.distinct_cells,
        "portals_traversed": stats.portal.portals_traversed,
        "walls_drawn": stats.walls_drawn,
        "triangles": stats.triangles,
        "samples_written": stats.samples_written,
        "render_us": times_us[0].round() as u64, // the first, cold render
        "culling": args.culling.to_string(),
        "cells_in_maze": cells_in_maze,
        // Where the frame was seen from: the asked place, or the walk's margin off a wall.
        "viewer": stands.pos.to_array().map(|x| (f64::from(x) * 1e4).round() / 1e4),
    });
    if args.repeat > 1 {
        times_us.sort_by(f64::total_cmp);
        let tenth = |us: f64| (us * 10.0).round() / 10.0;
        json["repeat"] = args.repeat.into();
        json["render_us_median"] = tenth(times_us[times_us.len() / 2]).into();
        json["render_us_min"] = tenth(times_us[0]).into();
        json["render_us_max"] = tenth(times_us[times_us.len() - 1]).into();
    }
    json
}

/// The depths as CSV, `cols` a row: four decimals, empty where no wall is seen.
fn depths_csv(depths: impl Iterator<Item = Option<f32>>, cols: usize) -> String {
    let depths: Vec<Option<f32>> = depths.collect();
    let mut csv = String::with_capacity(depths.len() * 8);
    for row in depths.chunks(cols.max(1)) {
        let fields: Vec<String> =
            row.iter().map(|d| d.map_or(String::new(), |d| format!("{d:.4}"))).collect();
        csv.push_str(&fields.join(","));
        csv.push('\n');
    }
    csv
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
    let file = mazewalk_maze::files::create_output(path)
        .with_context(|| format!("{}: cannot create", path.display()))?;
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
