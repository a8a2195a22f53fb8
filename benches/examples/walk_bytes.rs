//! Where a walking player's truecolor bytes go (issue #42): `bandwidth`'s walk (120×40 half blocks,
//! the built-in maze, W held from 1 s to 4 s with auto-repeat, 60 frames/s at most, no link limit),
//! and for every frame the cells the terminal (vt100) shows changed, by what they show and why:
//!
//! - **edge moved**: a sample of the cell shows another surface than in the frame before (a wall's
//!   end, the seam with the floor, a figure: geometry crossing the cell);
//! - otherwise by surface (wall, floor, ceiling, fog), and by how far the cell's exact colour moved
//!   since the frame before (largest of its two samples, OKLab): a **jump** (more than the tolerance
//!   in one frame: a line, a checker square's edge or a seam sliding into the cell) or a **drift**
//!   (less: a slow fade resent once it has moved the tolerance from what the screen shows);
//! - **map** and **HUD**: the overlay and the bottom row.
//!
//! The bytes of a frame are split over its changed cells in proportion (each cell's share of the
//! frame's bytes is the same), so the KB/s columns add up to the walk's.
//!
//! ```sh
//! cargo run --release -p mazewalk-bench --example walk_bytes [--turn] [--256] [--ascii-rep | --no-rep]
//! ```
//!
//! The terminal (vt100) repeats any glyph on REP and says so to the session's probe, as xterm does;
//! `--ascii-rep` answers as tmux (a space repeated, a block glyph not: REP after ASCII only),
//! `--no-rep` as a terminal without REP.

use glam::Vec3;
use mazewalk_bench::stream;
use mazewalk_maze as maze;
use mazewalk_render::samples::{CEILING, FLOOR, NONE};
use mazewalk_render::{Charset, RenderOptions, Renderer, Target};
use mazewalk_term::caps::RepLevel;
use mazewalk_term::encoder::{DEFAULT_TOLERANCE, TOLERANCE_STEP};
use mazewalk_term::frame::{ColorDepth, oklab};
use mazewalk_walk::{App, Session, SessionOptions};

const COLS: u16 = 120;
const ROWS: u16 = 40;

/// What a changed cell shows, and why it changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Why {
    EdgeWallWall,
    EdgeWallPlane,
    EdgeNear,
    WallJump,
    WallDrift,
    FloorLine,
    CeilingLine,
    FloorJump,
    FloorDrift,
    CeilingJump,
    CeilingDrift,
    Mixed,
    Fog,
    Map,
    Hud,
}

const ALL: [Why; 15] = [
    Why::EdgeWallWall,
    Why::EdgeWallPlane,
    Why::EdgeNear,
    Why::WallJump,
    Why::WallDrift,
    Why::FloorLine,
    Why::CeilingLine,
    Why::FloorJump,
    Why::FloorDrift,
    Why::CeilingJump,
    Why::CeilingDrift,
    Why::Mixed,
    Why::Fog,
    Why::Map,
    Why::Hud,
];

type Screen = Vec<(String, vt100::Color, vt100::Color)>;

fn snapshot(parser: &vt100::Parser) -> Screen {
    let screen = parser.screen();
    let mut cells = Vec::with_capacity(usize::from(COLS) * usize::from(ROWS));
    for y in 0..ROWS {
        for x in 0..COLS {
            let cell = screen.cell(y, x).expect("on screen");
            cells.push((cell.contents().to_string(), cell.fgcolor(), cell.bgcolor()));
        }
    }
    cells
}

/// A sample as the diagnosis reads it.
#[derive(Clone, Copy)]
struct Sample {
    oklab: Vec3,
    id: u32,
    /// A floor or ceiling sample darker than its row's checker squares: a cell line.
    line: bool,
}

/// The view's samples for the session's camera, as the session renders them.
fn samples(renderer: &mut Renderer, session: &Session) -> Vec<Sample> {
    let app = session.app();
    let (cols, rows) = (usize::from(COLS), usize::from(ROWS) - 1);
    renderer
        .render(app.maze(), &app.camera, &[], &app.options, Target::Samples { cols, rows })
        .expect("a camera that renders");
    let s = renderer.samples();
    let width = s.width();
    let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    let mut out: Vec<Sample> = s
        .color()
        .iter()
        .zip(s.id())
        .map(|(c, &id)| Sample {
            oklab: Vec3::from_array(oklab(c.clamp(Vec3::ZERO, Vec3::ONE).to_array(), f32::cbrt)),
            id,
            line: false,
        })
        .collect();
    // Along a row, floor (or ceiling) samples are at one depth: the light squares are the row's
    // brightest, the dark ones 0.82 of it, the lines 0.7 of either.
    for (row, colors) in s.color().chunks_exact(width).enumerate() {
        for plane in [FLOOR, CEILING] {
            let ids = &s.id()[row * width..(row + 1) * width];
            let top = colors.iter().zip(ids).filter(|(_, id)| **id == plane).map(|(c, _)| luminance(*c));
            let top = top.fold(0.0f32, f32::max);
            for (x, c) in colors.iter().enumerate().filter(|(x, _)| ids[*x] == plane) {
                let ratio = luminance(*c) / top.max(1e-9);
                out[row * width + x].line = !(0.78..).contains(&ratio);
            }
        }
    }
    out
}

/// Bytes of a stream by kind ([`stream::Kinds`]), and what REP would save.
#[derive(Clone, Copy, Default, Debug)]
struct Kinds {
    stream: stream::Kinds,
    rep: usize,
}

impl Kinds {
    /// Bytes `REP` (`CSI n b`, repeat the last glyph n times) would save on runs of one glyph
    /// written with nothing between them (where it is shorter).
    fn rep_saving(bytes: &[u8]) -> usize {
        let text = String::from_utf8_lossy(bytes);
        let mut saving = 0;
        let mut in_escape = false;
        let mut run: Option<(char, usize)> = None;
        let flush = |run: Option<(char, usize)>| {
            run.map_or(0, |(c, n): (char, usize)| {
                let rep = 3 + (n - 1).to_string().len();
                ((n - 1) * c.len_utf8()).saturating_sub(rep)
            })
        };
        for c in text.chars() {
            if in_escape {
                if ('@'..='~').contains(&c) && c != '[' {
                    in_escape = false;
                }
                continue;
            }
            if c == '\x1b' {
                saving += flush(run.take());
                in_escape = true;
                continue;
            }
            if c.is_control() {
                saving += flush(run.take());
                continue;
            }
            run = match run {
                Some((r, n)) if r == c => Some((r, n + 1)),
                other => {
                    saving += flush(other);
                    Some((c, 1))
                }
            };
        }
        saving + flush(run)
    }

    fn add(&mut self, bytes: &[u8]) {
        self.rep += Self::rep_saving(bytes);
        self.stream.add(bytes);
    }
}

/// What one run found.
struct Found {
    frames: usize,
    seconds: f64,
    total: usize,
    kinds: Kinds,
    cells: [usize; ALL.len()],
    bytes: [f64; ALL.len()],
    vertical: usize,
    /// Over the frames, the different sets of colours the changed cells show (a blank its paper, a
    /// full block its ink, a half block its two colours either way round, other glyphs both).
    pairs: usize,
}

/// `bandwidth`'s walk, step by step as its link does with no limit (1 ms steps, the terminal answers
/// at once), diagnosing each frame drawn while the viewer moves.
fn walk(depth: ColorDepth, key: &[u8], rep: RepLevel) -> Found {
    let options = RenderOptions { charset: Charset::Half, color_depth: depth, ..RenderOptions::default() };
    let app = App::new(maze::builtin().expect("built-in maze"), options, 0.0).expect("viewer in a cell");
    let mut session =
        Session::new(app, COLS, ROWS, SessionOptions { flow_control: false, ..SessionOptions::default() });
    let nz = |n: u16| std::num::NonZeroU16::new(n).expect("not zero");
    let mut terminal = vt100::Parser::new(nz(ROWS), nz(COLS), 0);
    let (press, release) = (1.0, 4.0);
    let mut renderer = Renderer::new();
    let tolerance = f32::from(DEFAULT_TOLERANCE) * TOLERANCE_STEP;
    let mut found = Found {
        frames: 0,
        seconds: 0.0,
        total: 0,
        kinds: Kinds::default(),
        cells: [0; ALL.len()],
        bytes: [0.0; ALL.len()],
        vertical: 0,
        pairs: 0,
    };
    let (mut before, mut before_samples) = (snapshot(&terminal), samples(&mut renderer, &session));
    let mut viewer = (session.app().camera.position, session.app().camera.yaw_deg);
    let mut next_key = press + 0.5;
    let mut last_frame_at = press;
    let mut out = Vec::new();
    let mut step = 0u32;
    loop {
        step += 1;
        let now = f64::from(step) * 0.001;
        if now > release {
            break;
        }
        if (now - press).abs() < 0.0005 || (now >= next_key && now > press) {
            session.feed(key, now);
            if now >= next_key {
                next_key += 0.033;
            }
        }
        out.clear();
        if !session.frame(now, &mut out) || out.is_empty() {
            continue;
        }
        // As a terminal does: each cursor position query answered with where the cursor is then
        // (the session asks whether the terminal has REP so: after a space on row 2, after a block
        // on row 3); `--ascii-rep`: as tmux, the block not repeated; `--no-rep`: a terminal without.
        let mut rest = &out[..];
        while let Some(at) = rest.windows(4).position(|w| w == b"\x1b[6n") {
            terminal.process(&rest[..at + 4]);
            let (row, col) = terminal.screen().cursor_position();
            let repeated = match rep {
                RepLevel::Any => true,
                RepLevel::Ascii => row + 1 == 2,
                RepLevel::None => false,
            };
            let col = if repeated { col } else { 1 };
            session.feed(format!("\x1b[{};{}R", row + 1, col + 1).as_bytes(), now);
            rest = &rest[at + 4..];
        }
        terminal.process(rest);
        for _ in 0..out.windows(3).filter(|w| *w == b"\x1b[c").count() {
            session.feed(b"\x1b[?62;22c", now);
        }
        let now_viewer = (session.app().camera.position, session.app().camera.yaw_deg);
        let moved = now_viewer != viewer;
        viewer = now_viewer;
        let after = snapshot(&terminal);
        let after_samples = samples(&mut renderer, &session);
        if !moved || now <= press {
            (before, before_samples) = (after, after_samples);
            continue;
        }
        found.seconds += now - last_frame_at;
        last_frame_at = now;
        found.kinds.add(&out);
        let map = session.map_drawn();
        let width = usize::from(COLS);
        let mut why = Vec::new();
        for (k, (a, b)) in before.iter().zip(&after).enumerate() {
            if a == b {
                continue;
            }
            let (x, y) = (k % width, k / width);
            let in_map =
                map.is_some_and(|m| (m.x..m.x + m.width).contains(&x) && (m.y..m.y + m.height).contains(&y));
            let reason = if y + 1 == usize::from(ROWS) {
                Why::Hud
            } else if in_map {
                Why::Map
            } else {
                let top = 2 * y * width + x;
                let pair = [top, top + width];
                let rows = 2 * (usize::from(ROWS) - 1);
                // The cell's samples and their neighbours: a surface boundary there moves marks too.
                let near = pair.iter().flat_map(|&i| {
                    let (sx, sy) = (i % width, i / width);
                    [(0, 0), (-1, 0), (1, 0), (0, -1), (0, 1)].into_iter().filter_map(move |(dx, dy)| {
                        let (nx, ny) = (sx.checked_add_signed(dx)?, sy.checked_add_signed(dy)?);
                        (nx < width && ny < rows).then_some(ny * width + nx)
                    })
                });
                let mut near = near;
                let is_wall = |id: u32| id != FLOOR && id != CEILING && id != NONE;
                let own = pair.iter().find(|&&i| before_samples[i].id != after_samples[i].id);
                if let Some(&i) = own {
                    if is_wall(before_samples[i].id) && is_wall(after_samples[i].id) {
                        Why::EdgeWallWall
                    } else {
                        Why::EdgeWallPlane
                    }
                } else if near.any(|i| before_samples[i].id != after_samples[i].id) {
                    Why::EdgeNear
                } else {
                    let step = pair
                        .iter()
                        .map(|&i| before_samples[i].oklab.distance(after_samples[i].oklab))
                        .fold(0.0, f32::max);
                    let jump = step > tolerance;
                    let line = pair.iter().any(|&i| before_samples[i].line || after_samples[i].line);
                    let ids = pair.map(|i| after_samples[i].id);
                    let surface = |id: u32| match id {
                        FLOOR => 1,
                        CEILING => 2,
                        NONE => 3,
                        _ => 0,
                    };
                    match (surface(ids[0]), surface(ids[1]), jump) {
                        (0, 0, true) => Why::WallJump,
                        (0, 0, false) => Why::WallDrift,
                        (1, 1, _) if line => Why::FloorLine,
                        (2, 2, _) if line => Why::CeilingLine,
                        (1, 1, true) => Why::FloorJump,
                        (1, 1, false) => Why::FloorDrift,
                        (2, 2, true) => Why::CeilingJump,
                        (2, 2, false) => Why::CeilingDrift,
                        (3, 3, _) => Why::Fog,
                        _ => Why::Mixed,
                    }
                }
            };
            why.push(reason);
        }
        // Changed cells in vertical runs of one look (4 or more, one column), not continuing a
        // horizontal run of that look (the cell to the left changed to the same).
        let height = usize::from(ROWS);
        for x in 0..width {
            let mut y = 0;
            while y < height {
                let k = y * width + x;
                let lone = |k: usize| {
                    before[k] != after[k]
                        && !(x > 0 && before[k - 1] != after[k - 1] && after[k - 1] == after[k])
                };
                if !lone(k) {
                    y += 1;
                    continue;
                }
                let run = (y..height)
                    .take_while(|&yy| lone(yy * width + x) && after[yy * width + x] == after[k])
                    .count();
                if run >= 4 {
                    found.vertical += run;
                }
                y += run;
            }
        }
        let mut pairs = std::collections::HashSet::new();
        for ((ch, fg, bg), before) in after.iter().zip(&before) {
            if (ch, fg, bg) != (&before.0, &before.1, &before.2) {
                pairs.insert(match ch.as_str() {
                    " " => vec![format!("{bg:?}")],
                    "█" => vec![format!("{fg:?}")],
                    "▀" | "▄" => {
                        let mut two = vec![format!("{fg:?}"), format!("{bg:?}")];
                        two.sort();
                        two
                    }
                    _ => vec![format!("{fg:?}"), format!("{bg:?}"), ch.clone()],
                });
            }
        }
        found.pairs += pairs.len();
        found.frames += 1;
        found.total += out.len();
        for &reason in &why {
            let r = ALL.iter().position(|&w| w == reason).expect("listed");
            found.cells[r] += 1;
            found.bytes[r] += out.len() as f64 / why.len() as f64;
        }
        (before, before_samples) = (after, after_samples);
    }
    found
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let turn = args.iter().any(|a| a == "--turn");
    let depth = if args.iter().any(|a| a == "--256") { ColorDepth::Ansi256 } else { ColorDepth::TrueColor };
    let rep = if args.iter().any(|a| a == "--no-rep") {
        RepLevel::None
    } else if args.iter().any(|a| a == "--ascii-rep") {
        RepLevel::Ascii
    } else {
        RepLevel::Any
    };
    let found = walk(depth, if turn { b"\x1b[D" } else { b"w" }, rep);
    let Found { frames, seconds, total, kinds, cells, bytes, vertical, pairs } = found;
    println!(
        "changed cells in columns of one look (4 or more, not in a run along their row): {:.1} a frame",
        vertical as f64 / frames.max(1) as f64
    );
    let seconds = seconds.max(1e-3);
    println!(
        "{} (key held, auto-repeat), 120×40 half blocks, {depth}, built-in maze, REP {}: {frames} frames, {:.1} KB/s\n",
        if turn { "Turning" } else { "Walking" },
        match rep {
            RepLevel::Any => "after any glyph",
            RepLevel::Ascii => "after ASCII only",
            RepLevel::None => "off",
        },
        total as f64 / seconds / 1e3
    );
    let pct = |n: usize| 100.0 * n as f64 / total.max(1) as f64;
    println!(
        "Changed cells: {:.1} different sets of colours a frame (written set by set, the pen would change about as often)",
        pairs as f64 / frames.max(1) as f64
    );
    println!(
        "Bytes: SGR {:.0} % ({:.0} a frame), cursor moves and erasures {:.0} %, glyphs {:.0} %, markers {:.0} %; REP would save {:.0} %\n",
        pct(kinds.stream.sgr),
        kinds.stream.sgr_count as f64 / frames.max(1) as f64,
        pct(kinds.stream.moves + kinds.stream.erase),
        pct(kinds.stream.glyphs),
        pct(kinds.stream.markers),
        pct(kinds.rep)
    );
    println!("| changed cells | cells a frame | KB/s (the frame's bytes split over its cells) |");
    println!("|---|--:|--:|");
    for (r, why) in ALL.iter().enumerate() {
        println!(
            "| {why:?} | {:.1} | {:.1} |",
            cells[r] as f64 / frames.max(1) as f64,
            bytes[r] / seconds / 1e3
        );
    }
}
