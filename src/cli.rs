//! The command line: every command, flag and value parser of the `mazewalk` binary (clap), in the
//! library so that a fuzz target and tests can parse argument lists exactly as the binary does. The
//! binary (`src/main.rs`) only dispatches and picks exit codes. Parsing is pure; `LookArgs::options`
//! reads the colour variables of the environment.
//!
//! ```
//! use clap::Parser as _;
//! use mazewalk::cli::{Cli, Command};
//! let cli = Cli::try_parse_from(["mazewalk", "render", "--size", "40x12", "--fov", "60"]).unwrap();
//! assert!(matches!(cli.command, Some(Command::Render(_))));
//! assert!(Cli::try_parse_from(["mazewalk", "render", "--pitch", "1000"]).is_err());
//! assert!(Cli::try_parse_from(["mazewalk", "render", "--fov", "-5"]).is_err());
//! ```

// Each flag's doc comment is its `--help` text; the structs and parsers mirror the command line, item
// by item, and need no second description.
#![allow(missing_docs)]

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use glam::Vec2;

use mazewalk_maze::generate::{Algorithm, MAX_SIDE};
use mazewalk_maze::{self as maze, Format};
use mazewalk_render::{Charset, Culling, Projection, Ramp, RenderOptions};
use mazewalk_term::frame::ColorDepth;
use mazewalk_term::{caps, encoder};
use mazewalk_walk::state;

#[derive(Parser)]
#[command(
    name = "mazewalk",
    version,
    about = "A first-person 3D maze walkthrough for the terminal",
    long_about = long_about(),
    args_conflicts_with_subcommands = true,
    allow_negative_numbers = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub walk: WalkArgs,
}

#[derive(Args)]
pub struct WalkArgs {
    #[command(flatten)]
    pub maze: MazeArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Cells whose colours moved by at most this many steps of 0.01 in OKLab (2: about what an eye can
    /// just tell apart) since they were sent stay as they are (fewer bytes while walking and turning;
    /// 0: every change is sent exactly): truecolor colours and the 256-colour cube and greys; the 16
    /// ANSI colours always go exactly.
    #[arg(long, value_name = "STEPS", default_value_t = encoder::DEFAULT_TOLERANCE, value_parser = clap::value_parser!(u8).range(0..=i64::from(encoder::MAX_TOLERANCE)))]
    pub color_tolerance: u8,
    /// Start the full-screen walk even where TERM says the terminal cannot take it (dumb, unset, empty).
    #[arg(long)]
    pub force_terminal: bool,
    /// Send frames as fast as they are drawn, without waiting for the terminal to show the previous
    /// ones (by default at most 2 frames are on their way: on a slow link the picture keeps up with
    /// the keys instead of falling behind).
    #[arg(long)]
    pub no_flow_control: bool,
    /// The map shows the whole maze and its exit from the start (by default only what you have seen).
    #[arg(long)]
    pub reveal_map: bool,
    /// Show the developer figures in the HUD from the start: frames per second, bytes of the last
    /// frame, cell, cells the portal pass visited, ms per frame (`i` shows and hides them).
    #[arg(long)]
    pub dev_figures: bool,
    /// Record the walk to FILE as an asciicast (v2; play it with `asciinema play FILE`): every byte
    /// sent to the terminal, timed, with the terminal's size and colour depth.
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
    /// Race the run in FILE as a ghost from your start (`g` hides and shows it): one written by
    /// --save-run or `mazewalk records MAZE --export-run`, of this maze.
    #[arg(long, value_name = "FILE")]
    pub ghost: Option<PathBuf>,
    /// When you reach the exit, write your run to FILE (at most ten minutes of it): race it later
    /// with --ghost FILE, play it with `mazewalk replay FILE`. A FILE that cannot be written is
    /// refused at the start.
    #[arg(long, value_name = "FILE")]
    pub save_run: Option<PathBuf>,
    #[command(flatten)]
    pub motion: MotionArgs,
}

/// How far a tap moves and how fast a held key moves.
#[derive(Args)]
pub struct MotionArgs {
    /// Turning speed while ← or → is held, degrees per second (10..=720).
    #[arg(long, value_name = "DEG_PER_S", default_value_t = state::TURN_SPEED, value_parser = |s: &str| parse_in(s, state::TURN_SPEED_RANGE))]
    pub turn_speed: f32,
    /// Walking speed while W/S/A/D is held, maze units per second (0.5..=40; a generated cell is 4).
    #[arg(long, value_name = "UNITS_PER_S", default_value_t = state::WALK_SPEED, value_parser = |s: &str| parse_in(s, state::WALK_SPEED_RANGE))]
    pub walk_speed: f32,
    /// How far one tap of ← or → turns, degrees (1..=90).
    #[arg(long, value_name = "DEG", default_value_t = state::TURN_STEP_DEG, value_parser = |s: &str| parse_in(s, state::TURN_STEP_RANGE_DEG))]
    pub turn_step: f32,
    /// How far one tap of W/S/A/D walks, maze units (0.05..=4).
    #[arg(long, value_name = "UNITS", default_value_t = state::WALK_STEP, value_parser = |s: &str| parse_in(s, state::WALK_STEP_RANGE))]
    pub walk_step: f32,
}

/// Where the maze comes from.
#[derive(Args)]
pub struct MazeArgs {
    /// Maze file (CS559 or grid format, detected); the built-in maze if omitted.
    #[arg(value_name = "MAZE", conflicts_with = "gen")]
    pub maze: Option<PathBuf>,
    /// A second maze file, refused by its parser (else clap took it for a subcommand and said so).
    #[arg(value_name = "MAZE", hide = true, num_args = 0.., value_parser = parse_second_maze)]
    pub more: Vec<PathBuf>,
    /// A fresh random maze of WxH cells instead of MAZE (with loops and an exit).
    #[arg(long = "gen", id = "gen", value_name = "WxH", value_parser = parse_size, allow_hyphen_values = true)]
    pub generate: Option<(u32, u32)>,
    /// Seed for --gen (the same seed gives the same maze: the one `mazewalk gen --size WxH --seed N
    /// --loops 0.1 --exit` writes).
    #[arg(long, default_value_t = DEFAULT_SEED, requires = "gen")]
    pub seed: u64,
    #[command(flatten)]
    pub read: ReadArgs,
}

/// How maze files are read.
#[derive(Args)]
pub struct ReadArgs {
    /// Refuse maze files larger than this many bytes (suffixes K, M, G: 1024-based).
    #[arg(long, value_name = "BYTES", default_value = "256M", value_parser = parse_bytes)]
    pub max_file_size: u64,
}

/// How frames look.
#[derive(Args)]
pub struct LookArgs {
    /// Glyphs: ascii (one sample per cell), half (▀, 1×2), quad (2×2) or sextant (2×3) (default:
    /// half; the walk draws ascii where block glyphs cannot show: on a DEC terminal, TERM=vt100,
    /// vt220…, and in a locale whose character set is not UTF-8, LANG=C).
    #[arg(long)]
    pub charset: Option<Charset>,
    /// Colour depth: none, 16, 256 or truecolor (default: from NO_COLOR, COLORTERM and TERM; the walk
    /// also reads terminfo, asks tmux, and asks the terminal itself for truecolor).
    #[arg(long)]
    pub color: Option<ColorDepth>,
    /// Terminal cell width / height (cells are about twice as tall as wide).
    #[arg(long, default_value_t = 0.5, value_parser = parse_cell_aspect)]
    pub cell_aspect: f32,
    /// In 256 and 16 colours, mix neighbouring palette entries that are close in an ordered pattern
    /// where the shading falls between them (smoother, about 1.5× the bytes; the walk stops mixing
    /// by itself on a slow link). By default each surface is drawn in clean bands of its own hues.
    #[arg(long)]
    pub dither: bool,
    /// The default (kept so that scripts written for the old dithered default still run).
    #[arg(long, hide = true, conflicts_with = "dither")]
    pub no_dither: bool,
    /// The ascii charset's shading ramp: short (10 characters, ` .:-=+*#%@`) or long (70).
    #[arg(long, default_value = "short")]
    pub ramp: Ramp,
    /// Brick walls and floor tiles filtered by distance (`t` toggles them in the walk).
    #[arg(long)]
    pub textures: bool,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render one frame to stdout and exit (plain text with --color none, ANSI otherwise).
    #[command(allow_negative_numbers = true)]
    Render(RenderArgs),
    /// Generate a random maze (a perfect maze unless --loops is given).
    #[command(visible_alias = "generate")]
    #[command(allow_negative_numbers = true)]
    Gen(GenArgs),
    /// Load a maze file and print a summary, or the located error (exit 65).
    #[command(allow_negative_numbers = true)]
    Check(CheckArgs),
    /// Host a maze over SSH: players connect with `ssh -p PORT HOST` and walk it together.
    #[command(allow_negative_numbers = true)]
    Serve(ServeArgs),
    /// Print the best times kept by `serve`: of one maze, or of every maze served.
    #[command(allow_negative_numbers = true)]
    Records(RecordsArgs),
    /// Play a stored run back in the terminal, first person, as the walk draws it (q quits, r
    /// starts again; the map, glyph and help keys work): RUN is a file from `--save-run` or
    /// `records --export-run`, the maze the one it was walked in. `--record FILE.cast` writes the
    /// playback as an asciicast.
    #[command(allow_negative_numbers = true)]
    Replay(ReplayArgs),
}

#[derive(Args)]
pub struct ReplayArgs {
    /// The run to play back.
    #[arg(value_name = "RUN")]
    pub run: PathBuf,
    /// The maze it was walked in, and how to draw it (as for the walk).
    #[command(flatten)]
    pub walk: WalkArgs,
}

#[derive(Args)]
pub struct ServeArgs {
    #[command(flatten)]
    pub maze: MazeArgs,
    /// Address and port to listen on: 0.0.0.0:2222 for every IPv4 interface, `[::]:2222` for every
    /// interface, or a host name (localhost:2222 listens on each of its addresses).
    #[arg(long, value_name = "HOST:PORT", default_value = "127.0.0.1:2222", value_parser = parse_listen)]
    pub listen: String,
    /// The server's ed25519 host key, made there on first start (default:
    /// $XDG_STATE_HOME/mazewalk/host_ed25519_key, or ~/.local/state/mazewalk/host_ed25519_key).
    #[arg(long, value_name = "FILE")]
    pub host_key: Option<PathBuf>,
    /// Let anyone in, with any user name and any key or none (a public game).
    #[arg(long, conflicts_with = "authorized_keys")]
    pub open: bool,
    /// Let in only the keys listed in FILE (OpenSSH authorized_keys format; default:
    /// ~/.ssh/authorized_keys, the keys that may log in to this account).
    #[arg(long, value_name = "FILE")]
    pub authorized_keys: Option<PathBuf>,
    /// Players at once, in all (1..=100000).
    #[arg(long, value_name = "N", default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_players: u32,
    /// Spectators at once (`ssh -p PORT watch@HOST`), in all; they have their own slots and never
    /// take a player's (0..=100000; 0: none).
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub max_spectators: u32,
    /// Spectators at once from one IP address, or one IPv6 /64 (1..=100000; `--max-spectators 0`
    /// takes none): a spectator has no idle timeout, so one address could otherwise hold every place
    /// for good. Raise it for a venue whose screens share one address.
    #[arg(long, value_name = "N", default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_spectators_per_address: u32,
    /// Connections still logging in (key exchange and authentication) at once, in all; they never
    /// take a player's slot. When all are taken, a newcomer takes the slot of the one longest
    /// without progress (1..=100000).
    #[arg(long, value_name = "N", default_value_t = 128, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_handshakes: u32,
    /// Connections at once from one IP address, or one IPv6 /64 (1..=100000).
    #[arg(long, value_name = "N", default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_per_address: u32,
    /// Samples all screens draw a second together, at most (cells × 2 for half blocks and ASCII, 4
    /// quadrants, 6 sextants): the screens drawing share it equally (default: 23,040,000 for each
    /// core: 100 players at 120×40 in half blocks get up to 48 frames a second each on 2 cores;
    /// 1000..=4000000000).
    #[arg(long, value_name = "SAMPLES", value_parser = clap::value_parser!(u32).range(1000..=4_000_000_000))]
    pub render_total: Option<u32>,
    /// Disconnect a player who sends nothing for this long (e.g. 90s, 30m, 2h; 1s..=7d).
    #[arg(long, value_name = "DUR", default_value = "30m", value_parser = parse_duration)]
    pub idle_timeout: std::time::Duration,
    /// Keep the best times in this SQLite file, mode 0600, in a folder that is there (default:
    /// records.sqlite beside the host key).
    #[arg(long, value_name = "FILE", conflicts_with = "no_records")]
    pub records: Option<PathBuf>,
    /// Keep no best times.
    #[arg(long)]
    pub no_records: bool,
    /// Walk one world with every server started with this URL and the same maze:
    /// `redis://[USER:PASS@]HOST:PORT[/DB]`, or `rediss://…` for TLS. The best times then live in that
    /// Redis (--records is not used).
    #[arg(long, value_name = "URL", conflicts_with = "records")]
    pub world: Option<String>,
    /// The certificate (PEM) of the CA that signed a rediss:// world's certificate, when the system
    /// does not trust it (as redis-cli's --cacert).
    #[arg(long, value_name = "FILE", requires = "world")]
    pub world_ca: Option<PathBuf>,
    /// With --world: other servers kept in view at once; messages from more are dropped and
    /// counted (1..=4096).
    #[arg(long, value_name = "N", default_value_t = 16, requires = "world", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub max_remote_servers: u32,
    /// With --world: other servers' players kept in view at once, in all; more are left out and
    /// counted (1..=65536).
    #[arg(long, value_name = "N", default_value_t = 1024, requires = "world", value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub max_remote_players: u32,
    /// Record each player's session as an asciicast v2 file in DIR (made if missing, but not its
    /// folder): one file a
    /// session, exactly what its terminal was sent; the player's HUD says `recorded`. Spectators
    /// are not recorded.
    #[arg(long, value_name = "DIR")]
    pub record_dir: Option<PathBuf>,
    /// With --record-dir: the most bytes of one cast (e.g. 64M, at least 1K); it stops there,
    /// still whole lines.
    #[arg(long, value_name = "BYTES", default_value = "64M", requires = "record_dir", value_parser = parse_bytes)]
    pub record_max_bytes: u64,
    /// With --record-dir: the most bytes of all the casts in DIR. A player is recorded only if the
    /// casts in progress, each counted at --record-max-bytes, fit; the oldest finished casts are
    /// deleted to make room for bytes written.
    #[arg(long, value_name = "BYTES", default_value = "1G", requires = "record_dir", value_parser = parse_bytes)]
    pub record_max_total: u64,
    /// With --record-dir: players recorded at once from one IP address, or one IPv6 /64, and twice
    /// that from one IPv4 /24 or IPv6 /48; more play unrecorded (1..=100000).
    #[arg(long, value_name = "N", default_value_t = 2, requires = "record_dir", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub record_max_per_address: u32,
    /// With --record-dir: the most casts in DIR (1..=10000000). When it holds that many, new
    /// players are not recorded until the host removes casts: none is deleted for the count, so
    /// a stranger's short sessions cannot push other players' casts out.
    #[arg(long, value_name = "N", default_value_t = 10_000, requires = "record_dir", value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    pub record_max_files: u32,
    /// How log lines (on stderr) are written: text, or json (one object a line: time, level, event,
    /// address, player, message, and the line's other fields) for journald and log shippers.
    #[arg(long, value_name = "FORMAT", default_value = "text")]
    pub log_format: LogFormat,
    /// Serve /metrics (Prometheus' text format) and a live status page (/) over HTTP on this
    /// address, e.g. 127.0.0.1:9222 (off unless given; an address other than loopback lets other
    /// machines read them).
    #[arg(long, value_name = "HOST:PORT", value_parser = parse_listen)]
    pub http: Option<String>,
}

/// `serve --log-format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum LogFormat {
    /// Lines for a person to read.
    Text,
    /// One JSON object a line.
    Json,
}

#[derive(Args)]
pub struct RecordsArgs {
    /// Only this maze's best times (a file, or --gen WxH --seed N as it was served); every maze's
    /// if omitted.
    #[arg(value_name = "MAZE")]
    pub maze: Option<PathBuf>,
    /// The maze served with --gen WxH (and --seed N).
    #[arg(long = "gen", id = "gen", value_name = "WxH", value_parser = parse_size, conflicts_with = "maze", allow_hyphen_values = true)]
    pub generate: Option<(u32, u32)>,
    /// Seed for --gen.
    #[arg(long, default_value_t = DEFAULT_SEED, requires = "gen")]
    pub seed: u64,
    /// The built-in maze's best times.
    #[arg(long, conflicts_with_all = ["maze", "gen"])]
    pub builtin: bool,
    /// The records file (default: records.sqlite in the host key's default folder,
    /// $XDG_STATE_HOME/mazewalk or ~/.local/state/mazewalk).
    #[arg(long, value_name = "FILE", conflicts_with = "world")]
    pub records: Option<PathBuf>,
    /// The best times of the shared world at this URL (as `serve --world` was given) instead of a
    /// file; the maze must be named.
    #[arg(long, value_name = "URL")]
    pub world: Option<String>,
    /// The CA's certificate (PEM) of a rediss:// world's Redis, as for `serve --world-ca`.
    #[arg(long, value_name = "FILE", requires = "world")]
    pub world_ca: Option<PathBuf>,
    /// Write a finish's run to FILE (for `--ghost FILE` or `replay FILE`): the run of the player at
    /// RANK in the best times or of the player NAME, `--export-run RANK|NAME FILE`; given one value,
    /// it is FILE and the rank 1; the maze must be named. Runs are kept for the best finish of each
    /// of a maze's best ten players.
    #[arg(long, num_args = 1..=2, value_names = ["RANK|NAME", "FILE"])]
    pub export_run: Option<Vec<String>>,
    #[command(flatten)]
    pub read: ReadArgs,
}

#[derive(Args)]
pub struct GenArgs {
    /// Cells east-west x north-south, e.g. 20x10 (each side 1..=1000).
    #[arg(long, value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Random seed: the same seed gives the same maze on every platform.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    pub seed: u64,
    /// Carving algorithm: prim (bushy), dfs (long corridors), wilson (uniform).
    #[arg(long, default_value = "prim")]
    pub algo: Algorithm,
    /// Fraction of the remaining interior walls to remove, adding cycles (0..=1).
    #[arg(long, default_value_t = 0.0, value_parser = parse_loops)]
    pub loops: f32,
    /// Output format: cs559 (thin walls) or grid (tiles: a WxH maze becomes (2W+1)x(2H+1) tiles).
    #[arg(long, default_value = "cs559")]
    pub format: Format,
    /// Mark the cell farthest from the start as the exit (in a 1x1 maze, the start itself).
    #[arg(long)]
    pub exit: bool,
    /// Write to FILE instead of stdout (`-`: stdout).
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub maze: MazeArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Eye position X,Y in the maze plane (default: the file's viewer). Like the walk's, it stands
    /// the maze's clearance from every wall (2/5 of its narrowest passage, 0.25 to 1.6: 1.6 in a
    /// generated maze): a position closer is moved out to it.
    #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true)]
    pub at: Option<Vec2>,
    /// Eye height, strictly between the floor (-1) and the ceiling (+1).
    #[arg(long, value_name = "Z", allow_hyphen_values = true, value_parser = parse_height)]
    pub height: Option<f32>,
    /// Heading in degrees counter-clockwise from +x (default: the file's).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_heading)]
    pub heading: Option<f32>,
    /// A chalk cross on the floor of the cell that holds X,Y, as the walk marks the cells walked
    /// (`x`); repeat it for more cells.
    #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true)]
    pub chalk: Vec<Vec2>,
    /// Pitch in degrees, positive looks up (-90..=90).
    #[arg(long, value_name = "DEG", default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_pitch)]
    pub pitch: f32,
    /// Horizontal field of view across the whole frame, degrees (10..=170; default: the file's).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = parse_fov)]
    pub fov: Option<f32>,
    /// The frame the walk's look-ahead lens (`z`) shows: a 30° field (unless --fov gives another),
    /// the floor's cell lines straight ahead numbered on the left edge and the wall that ends the
    /// way marked with the cells to it (`7|`).
    #[arg(long)]
    pub look_ahead: bool,
    /// Draw the view with one scale across it, as plain perspective does: without the walk's
    /// foveated view, whose middle is magnified and edges squeezed so far openings stay wide
    #[arg(long)]
    pub no_fovea: bool,
    /// Frame size in terminal cells: at most 2000 per side and 1,000,000 cells in all.
    #[arg(long, value_name = "COLSxROWS", default_value = "80x24", value_parser = parse_frame_size, allow_hyphen_values = true)]
    pub size: (usize, usize),
    /// perspective or orthographic.
    #[arg(long, default_value = "perspective")]
    pub projection: Projection,
    /// portal (cell-and-portal visibility) or none (every wall: brute force).
    #[arg(long, default_value = "portal")]
    pub culling: Culling,
    /// Print one JSON object of counts and timing on stderr.
    #[arg(long)]
    pub stats: bool,
    /// Render the same frame N times (1..=100000); `--stats` then adds the median, fastest and slowest
    /// render time (`render_us_median`, `render_us_min`, `render_us_max`): the first render of a
    /// process (`render_us`) pays for cold caches and buffers, the median is the steady frame cost.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub repeat: u32,
    /// Write a CSV of ROWS lines × COLS values: the view-space depth of the wall seen through each
    /// cell's centre, empty where none (`-`: standard output, with --png FILE).
    #[arg(long, value_name = "FILE")]
    pub depth_out: Option<PathBuf>,
    /// Write the frame as a PNG picture instead of printing it: exactly what a terminal shows, each
    /// sample a block of pixels (a cell is 12×24), in 8-bit RGB; in truecolor unless --color says
    /// otherwise (256 and 16 colours as xterm's palette shows them), whatever TERM says; block
    /// charsets only. `-` writes it to standard output (not a terminal).
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
}

#[derive(Args)]
pub struct CheckArgs {
    /// The maze file (CS559 or grid format; detected); `-` reads standard input.
    pub file: PathBuf,
    #[command(flatten)]
    pub read: ReadArgs,
}

impl LookArgs {
    /// The charset `--charset` names, else half blocks (`render`'s default whatever `TERM` says).
    pub fn charset(&self) -> Charset {
        self.charset.unwrap_or(Charset::Half)
    }

    /// The walk's charset: `--charset`, else half blocks, or ascii on a terminal that has no block
    /// glyphs ([`caps::detect_block_glyphs`]: a DEC terminal by `TERM`, or a locale whose character
    /// set is not UTF-8). (A value that is not UTF-8 is read lossily: a set locale still decides.)
    pub fn walk_charset(&self) -> Charset {
        self.charset.unwrap_or_else(|| {
            if caps::detect_block_glyphs(|k: &str| {
                std::env::var_os(k).map(|v| v.to_string_lossy().into_owned())
            }) {
                Charset::Half
            } else {
                Charset::Ascii
            }
        })
    }

    /// The render options, drawn with `charset` ([`Self::charset`] or [`Self::walk_charset`]).
    pub fn options(&self, culling: Culling, charset: Charset) -> RenderOptions {
        let env = |k: &str| std::env::var(k).ok();
        let color_depth = self.color.unwrap_or_else(|| caps::detect_color_depth(env));
        RenderOptions {
            charset,
            color_depth,
            culling,
            cell_aspect: self.cell_aspect,
            dither: self.dither,
            ramp: self.ramp,
            textures: self.textures,
        }
    }
}

impl ReadArgs {
    pub fn options(&self) -> maze::LoadOptions {
        maze::LoadOptions { max_bytes: self.max_file_size }
    }
}

/// Always an error: a command takes one maze file.
pub fn parse_second_maze(s: &str) -> Result<PathBuf, String> {
    Err(format!("one maze file at a time: `{s}` is a second"))
}

/// `WxH` with each side in `1..=max`: maze sizes (`--gen`, `gen --size`) and frame sizes.
pub fn parse_dims<T>(s: &str, max: T, what: &str) -> Result<(T, T), String>
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

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    parse_dims(s, MAX_SIDE, "WxH")
}

pub fn parse_loops(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(x) if (0.0..=1.0).contains(&x) => Ok(x),
        _ => Err(format!("expected a fraction in 0..=1, found `{s}`")),
    }
}

/// An eye height; exactly -1 or 1 passes here and is refused with the camera (strictly between).
pub fn parse_height(s: &str) -> Result<f32, String> {
    parse_within(s, (-1.0, 1.0), |t| {
        format!("eye height {t} is not strictly between the floor (-1) and the ceiling (+1)")
    })
}

/// A number in `lo..=hi`, or the message `outside` makes of its text: a number too large for an
/// `f32` is outside the range too, not "not a finite number".
fn parse_within(s: &str, (lo, hi): (f32, f32), outside: impl Fn(&str) -> String) -> Result<f32, String> {
    let t = s.trim();
    // The range is checked on the f32 the flag will hold (so a bound written as the range's own
    // text, `0.05` for 0.05f32, is in it); a finite number too large for an f32 is outside.
    match (t.parse::<f64>(), t.parse::<f32>()) {
        (Ok(x), Ok(y)) if x.is_finite() && (lo..=hi).contains(&y) => Ok(y),
        (Ok(x), _) if x.is_finite() => Err(outside(t)),
        _ => Err(format!("expected a finite number, found `{s}`")),
    }
}

/// A heading in degrees: any within ±36,000 (a hundred turns), so that f32 still resolves it.
pub fn parse_heading(s: &str) -> Result<f32, String> {
    parse_within(s, (-36_000.0, 36_000.0), |t| {
        format!("heading {t}° is out of range: a heading must be within -36000..=36000 degrees")
    })
}

/// A number in `lo..=hi` (speeds and steps).
pub fn parse_in(s: &str, (lo, hi): (f32, f32)) -> Result<f32, String> {
    parse_within(s, (lo, hi), |t| format!("{t} is outside {lo}..={hi}"))
}

pub fn parse_pitch(s: &str) -> Result<f32, String> {
    parse_within(s, (-90.0, 90.0), |t| {
        format!("pitch {t}° is outside -90..=90 (straight down to straight up)")
    })
}

pub fn parse_fov(s: &str) -> Result<f32, String> {
    let (lo, hi) = mazewalk_render::camera::FOV_RANGE_DEG;
    parse_within(s, (lo, hi), |t| format!("a field of view of {t}° is outside {lo}..={hi}°"))
}

pub fn parse_cell_aspect(s: &str) -> Result<f32, String> {
    parse_within(s, (0.1, 4.0), |t| {
        format!("cell aspect {t} is outside 0.1..=4 (width / height; about 0.5 for most fonts)")
    })
}

/// `X,Y`: two numbers. One past the coordinate bound but an `f32` is told where the maze is, later.
pub fn parse_point(s: &str) -> Result<Vec2, String> {
    let bound = maze::COORD_BOUND;
    let coord = |t: &str| {
        parse_within(t, (f32::MIN, f32::MAX), |t| {
            format!("{t} is out of range: a maze's X and Y are within ±{bound}")
        })
    };
    match s.split(',').collect::<Vec<_>>()[..] {
        [x, y] => Ok(Vec2::new(coord(x)?, coord(y)?)),
        _ => Err(format!("expected two numbers X,Y, e.g. 2.5,3, found `{s}`")),
    }
}

pub fn parse_frame_size(s: &str) -> Result<(usize, usize), String> {
    parse_dims(s, MAX_FRAME_SIDE, "COLSxROWS")
}

/// `123`, `64K`, `256M`, `2G` (1024-based).
pub fn parse_bytes(s: &str) -> Result<u64, String> {
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

/// `HOST:PORT` as `--listen` takes it: an IP address and port (`[…]` around an IPv6 address), or a
/// host name and port, which `serve` looks up when it starts (not here: parsing does no I/O).
pub fn parse_listen(s: &str) -> Result<String, String> {
    if s.parse::<std::net::SocketAddr>().is_ok() {
        return Ok(s.to_string());
    }
    let bad = || {
        format!(
            "expected HOST:PORT such as 127.0.0.1:2222, [::1]:2222 or localhost:2222, found `{}`",
            maze::quote(s)
        )
    };
    let (host, port) = s.rsplit_once(':').ok_or_else(bad)?;
    let host_ok = !host.is_empty()
        && host.len() <= 253
        && host.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '.' | '_'));
    match port.parse::<u16>() {
        Ok(_) if host_ok => Ok(s.to_string()),
        _ => Err(bad()),
    }
}

/// A duration: a whole number with `s`, `m`, `h` or `d` (seconds without a unit), 1 s to 7 days.
pub fn parse_duration(s: &str) -> Result<std::time::Duration, String> {
    let t = s.trim();
    let (digits, unit) = match t.char_indices().last() {
        Some((i, c @ ('s' | 'm' | 'h' | 'd'))) => (&t[..i], c),
        _ => (t, 's'),
    };
    let scale = match unit {
        'm' => 60,
        'h' => 3600,
        'd' => 86_400,
        _ => 1,
    };
    match digits.parse::<u64>().ok().and_then(|n| n.checked_mul(scale)) {
        Some(secs) if (1..=7 * 86_400).contains(&secs) => Ok(std::time::Duration::from_secs(secs)),
        _ => Err(format!("expected a duration from 1s to 7d such as 90s, 30m or 2h, found `{s}`")),
    }
}

/// `mazewalk --help`'s description: what it does, then the keys, from the one table the walk's `?`
/// help shows (`mazewalk_walk::overlay::help_lines`).
fn long_about() -> String {
    let keys = mazewalk_walk::overlay::help_lines(mazewalk_walk::overlay::Style::default(), false);
    format!(
        "A first-person 3D maze walkthrough for the terminal.\n\n\
         Without a command, walks MAZE (CS559 or grid format), a fresh --gen maze, or the built-in \
         maze.\n\nKeys:\n  {}",
        keys.join("\n  ")
    )
}

/// The seed of a generated maze when none is given, for `gen` and `--gen` alike (so that the same
/// size, with the same options, gives the same maze).
pub const DEFAULT_SEED: u64 = 1;

/// Largest frame `render` makes, per side (a 2000-column frame is already 8 screens wide).
pub const MAX_FRAME_SIDE: usize = 2000;

/// Largest frame `render` makes, in cells (a million cells of sextants are 6 M samples, ~150 MB).
pub const MAX_FRAME_CELLS: usize = 1_000_000;
