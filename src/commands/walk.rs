//! `mazewalk [MAZE]`: the full-screen walk on this process's terminal.

use std::io::{IsTerminal as _, Read as _, Write};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context as _, bail};

use super::{load_maze, maze_name};
use crate::cast::{Header, Recorder};
use crate::cli::{ReplayArgs, WalkArgs};
use crate::guard;
use crate::run::run as run_session;
use mazewalk_render::{Culling, RenderOptions};
use mazewalk_term::caps::{self, ColorFacts, ColorPlan};
use mazewalk_walk::state::Motion;
use mazewalk_walk::{App, Session, SessionOptions};

/// Walks the maze the flags name in this process's terminal until the player quits or a signal
/// ends it (exit 128 + n).
pub fn run(args: &WalkArgs) -> anyhow::Result<ExitCode> {
    walk(args, None)
}

/// `mazewalk replay RUN [MAZE]`: the walk's screen driven by a stored run instead of the keys.
pub fn replay(args: &ReplayArgs) -> anyhow::Result<ExitCode> {
    if args.walk.save_run.is_some() {
        bail!("replay: --save-run keeps a walk's own run; a replay has none");
    }
    walk(&args.walk, Some(&args.run))
}

/// The walk, or with `replay` the playback of the run in that file.
fn walk(args: &WalkArgs, replay: Option<&std::path::Path>) -> anyhow::Result<ExitCode> {
    if args.maze.maze.as_deref() == Some(std::path::Path::new("-")) && !std::io::stdin().is_terminal() {
        bail!(
            "the walk reads its keys from standard input, so the maze cannot come from there: save it \
             to a file and give its path (`mazewalk gen --size 20x10 --exit --format grid > maze.grid`, \
             then `mazewalk maze.grid`)"
        );
    }
    let maze = load_maze(&args.maze)?;
    // the maze's hash, for a run to race or to keep (a 1000 × 1000 maze takes tenths of a second)
    let hash =
        (args.ghost.is_some() || args.save_run.is_some() || replay.is_some()).then(|| maze.content_hash());
    let ghost = match (&args.ghost, hash) {
        (Some(path), Some(hash)) => Some(read_run(path, hash, maze.extents())?),
        _ => None,
    };
    let replay = match (replay, hash) {
        (Some(path), Some(hash)) => Some(read_run(path, hash, maze.extents())?),
        _ => None,
    };
    // before the walk, as `--record`'s file: a path that cannot be written is refused now, not after
    let mut run_file = args.save_run.as_deref().map(RunFile::open).transpose()?;
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
    let env = |k: &str| std::env::var(k).ok();
    let terminfo = terminfo(env);
    let plan = match args.look.color {
        Some(depth) => ColorPlan { depth, ask: false },
        None => caps::plan_color_depth(env, color_facts(env, terminfo.as_deref())),
    };
    // no alternate screen where terminfo says so; unknown (no infocmp, no entry): today's bytes
    let alternate_screen = terminfo.as_deref().is_none_or(caps::terminfo_has_alternate_screen);
    let clock = Instant::now(); // the walk's time 0
    let options = RenderOptions {
        color_depth: plan.depth,
        ..args.look.options(Culling::Portal, args.look.walk_charset())
    };
    let mut app = App::new(maze, options, 0.0)?;
    app.ghost = ghost.is_some();
    let status = replay.as_ref().map(|run| {
        let who = if run.holder.is_empty() { String::new() } else { format!("{} ", run.holder) };
        format!("replay {who}{}", mazewalk_walk::clock::clock_text(run.seconds()))
    });
    if let Some(run) = replay {
        app.set_replay(std::sync::Arc::new(run));
    }
    app.reveal_map = args.reveal_map;
    app.figures = args.dev_figures;
    let m = &args.motion;
    app.motion = Motion {
        turn_speed_deg: m.turn_speed,
        walk_speed: m.walk_speed,
        turn_step_deg: m.turn_step,
        walk_step: m.walk_step,
    };
    let options = SessionOptions {
        bce: caps::detect_bce(env),
        color_tolerance: args.color_tolerance,
        flow_control: !args.no_flow_control,
        sample_rate: None, // the local walk draws at the terminal's pace
    };
    let mut session = Session::new(app, 80, 24, options); // resized to the terminal by `run`
    session.set_ghost_run(ghost.map(std::sync::Arc::new));
    session.set_status(status.as_deref());
    let recorder = match &args.record {
        Some(path) => Some(start_recording(path, args, plan, clock)?),
        None => None,
    };
    let guard = guard::GuardOptions { alternate_screen, ..guard::GuardOptions::default() };
    let ended = run_session(&mut session, clock, plan.ask, recorder.as_ref(), guard);
    if let (Some(recorder), Some(path)) = (&recorder, &args.record) {
        // once, now that the terminal is restored; the walk went on without it
        let path = mazewalk_maze::quote_path(&path.display().to_string());
        if let Err(err) = recorder.finish() {
            let _ = writeln!(
                guard::Patient::new(std::io::stderr()),
                "mazewalk: the recording {path} stopped: {err}"
            );
        }
        let replaced = recorder.replaced();
        if replaced > 0 {
            let _ = writeln!(
                guard::Patient::new(std::io::stderr()),
                "mazewalk: the recording {path} has U+FFFD in place of {replaced} bytes that were not UTF-8"
            );
        }
    }
    if let Some(signal) = ended.context("terminal")?.signal() {
        return Ok(ExitCode::from(u8::try_from(guard::exit_code_for_signal(signal)).unwrap_or(1)));
    }
    let replayed = status.is_some();
    if let Some(seconds) = session.outcome().finished.filter(|_| !replayed) {
        // as the finish box said it; the walk is over either way
        let _ = writeln!(
            guard::Patient::new(std::io::stdout()),
            "You found the exit in {}.",
            mazewalk_walk::clock::clock_text(seconds)
        );
    }
    if let (Some(file), Some(hash)) = (&mut run_file, hash) {
        save_run(&session, hash, file)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// Reads the run in the file at `path` to race as a ghost: at most [`MAX_BYTES`] read, decoded and
/// checked against the maze of hash `hash` and `extents`, as any untrusted file. Only a regular
/// file is read (a FIFO, a device or a directory: exit 66, at once).
///
/// [`MAX_BYTES`]: mazewalk_walk::run::MAX_BYTES
pub(crate) fn read_run(
    path: &std::path::Path,
    hash: mazewalk_maze::ContentHash,
    extents: mazewalk_maze::Aabb,
) -> anyhow::Result<mazewalk_walk::run::Run> {
    use mazewalk_walk::run::{MAX_BYTES, Run};
    let shown = mazewalk_maze::quote_path(&path.display().to_string());
    let no_input = |source| super::NoInput { what: format!("the run {shown}"), source };
    // only a regular file, opened without blocking, as a maze is: a FIFO would wait forever and a
    // device has no length to check
    let file = mazewalk_maze::files::open_regular(path).map_err(|e| match e {
        mazewalk_maze::files::OpenError::Io(source) => no_input(source),
        mazewalk_maze::files::OpenError::NotAFile(what) => no_input(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("not a regular file ({what})"),
        )),
    })?;
    let mut bytes = Vec::new();
    file.take(MAX_BYTES as u64 + 1).read_to_end(&mut bytes).map_err(no_input)?;
    let run = Run::decode(&bytes)
        .and_then(|run| run.check_maze(hash, extents).map(|()| run))
        .map_err(|e| super::BadData { what: format!("the run {shown}"), source: e.into() })?;
    Ok(run)
}

/// `--save-run`'s file, opened for writing before the walk, so that a path that cannot be written (no
/// such directory, no permission, not a regular file) is refused at the start, as `--record`'s is,
/// and not after a ten-minute walk. A file that did not exist is created, and removed again unless a
/// run is written to it; one that did is left as it was until a run replaces its contents.
struct RunFile {
    file: std::fs::File,
    path: std::path::PathBuf,
    /// Created by this walk, and nothing written to it yet: removed on drop.
    created_empty: bool,
}

impl RunFile {
    fn open(path: &std::path::Path) -> anyhow::Result<RunFile> {
        let shown = mazewalk_maze::quote_path(&path.display().to_string());
        let cannot = || format!("cannot write the run {shown}");
        // only a regular file, never through a symbolic link (red-team pass 8, finding 7), as
        // --record's
        let (file, created_empty) =
            mazewalk_maze::files::open_to_write(path).map_err(|e| anyhow::Error::new(e).context(cannot()))?;
        Ok(RunFile { file, path: path.to_path_buf(), created_empty })
    }

    /// Replaces the file's contents with `bytes`.
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.created_empty = false;
        self.file.set_len(0)?;
        self.file.write_all(bytes)?;
        self.file.sync_all()
    }
}

impl Drop for RunFile {
    fn drop(&mut self) {
        if self.created_empty {
            let _ = std::fs::remove_file(&self.path); // no run: no empty file left behind
        }
    }
}

/// `--save-run`: the run of the walk's finish, written to `file` (nothing when the walk did not
/// reach the exit, or took longer than a run holds); labelled with `$USER` as a player name.
fn save_run(session: &Session, hash: mazewalk_maze::ContentHash, file: &mut RunFile) -> anyhow::Result<()> {
    let shown = mazewalk_maze::quote_path(&file.path.display().to_string());
    let user = std::env::var("USER").unwrap_or_default();
    let holder: String =
        user.chars().filter(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.')).take(16).collect();
    let Some(run) = session.app().run(hash, &holder) else {
        if session.outcome().finished.is_some() {
            let _ = writeln!(
                guard::Patient::new(std::io::stderr()),
                "mazewalk: no run written to {shown}: the walk took too long"
            );
        }
        return Ok(());
    };
    let bytes = run.encode().with_context(|| format!("the run for {shown}"))?;
    file.write(&bytes).with_context(|| format!("cannot write the run {shown}"))?;
    let _ = writeln!(
        guard::Patient::new(std::io::stdout()),
        "Your run is in {shown}: race it with --ghost, play it with `mazewalk replay`."
    );
    Ok(())
}

/// Creates the `--record` file at `path` and writes its header: the terminal's size now, the colour
/// depth the walk starts at, TERM and COLORTERM.
fn start_recording(
    path: &std::path::Path,
    args: &WalkArgs,
    plan: ColorPlan,
    clock: Instant,
) -> anyhow::Result<Recorder> {
    let (width, height) = guard::size().context("terminal size")?;
    let header = Header {
        width,
        height,
        timestamp: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .ok()
            .map(|d| d.as_secs()),
        title: format!("mazewalk {}", maze_name(&args.maze)),
        term: std::env::var("TERM").ok(),
        colorterm: std::env::var("COLORTERM").ok(),
        color_depth: plan.depth,
        charset: args.look.walk_charset(),
        asked_truecolor: plan.ask,
    };
    let shown = mazewalk_maze::quote_path(&path.display().to_string());
    Recorder::create(path, &header, clock).with_context(|| format!("cannot record to {shown}"))
}

/// How long each of the system's tools may take to answer about the terminal (`infocmp`, `tmux`):
/// they answer in milliseconds, and a walk must not hang on one that does not.
const TOOL_TIMEOUT: Duration = Duration::from_millis(500);

/// The most of a tool's output read (bytes): a terminfo description is a few KB.
const TOOL_OUTPUT_LIMIT: u64 = 256 * 1024;

/// The terminfo entry of `TERM`, as `infocmp -x` describes it; `None` if the tool is missing, fails
/// (no such entry) or is slow.
fn terminfo(env: impl Fn(&str) -> Option<String>) -> Option<String> {
    env("TERM")
        .filter(|term| !term.is_empty() && !term.starts_with('-'))
        .and_then(|term| tool_output(Command::new("infocmp").arg("-x").arg(term)))
}

/// What the system says about the terminal's 24-bit colour: its `terminfo` entry ([`terminfo`]),
/// and inside tmux (`TMUX` set) whether tmux's client has the `RGB` feature (tmux answers no query
/// itself). A tool that is missing, fails or is slow says nothing.
fn color_facts(env: impl Fn(&str) -> Option<String>, terminfo: Option<&str>) -> ColorFacts {
    let decided = env("NO_COLOR").is_some_and(|v| !v.is_empty())
        || env("COLORTERM").is_some_and(|v| matches!(v.as_str(), "truecolor" | "24bit"));
    if decided {
        return ColorFacts::default(); // nothing to look up
    }
    let terminfo_rgb = terminfo.map(caps::terminfo_has_truecolor);
    let tmux_rgb = env("TMUX")
        .and_then(|_| {
            tool_output(Command::new("tmux").args(["display-message", "-p", "#{client_termfeatures}"]))
        })
        .map(|text| caps::tmux_has_rgb(&text));
    ColorFacts { terminfo_rgb, tmux_rgb }
}

/// What `command` writes to stdout, if it exits successfully and its output ends within
/// [`TOOL_TIMEOUT`]: at most [`TOOL_OUTPUT_LIMIT`] bytes, as text. The tool runs in a process group of
/// its own, killed whole when the time is up or the tool failed: a child it leaves behind (a wrapper
/// script's, `sleep 30 &`) holds the output's pipe open, and the walk does not wait for it (red-team
/// pass 8: a fake `infocmp` on `PATH` delayed the start by its leftover's whole life).
fn tool_output(command: &mut Command) -> Option<String> {
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(command, 0);
    let mut child = command.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::null()).spawn().ok()?;
    let stdout = child.stdout.take()?;
    // Read on a thread: a tool that writes more than a pipe holds must not block until the timeout.
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut text = String::new();
        let _ = tx.send(stdout.take(TOOL_OUTPUT_LIMIT).read_to_string(&mut text).ok().map(|_| text));
    });
    let deadline = Instant::now() + TOOL_TIMEOUT;
    let succeeded = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status.success(),
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(2)),
            _ => {
                kill_group(&child); // (before the wait: the group's id cannot be reused meanwhile)
                let _ = child.wait();
                return None;
            }
        }
    };
    // The output ends when the last process holding the pipe is gone: the tool's leftovers too.
    let text = succeeded.then(|| rx.recv_timeout(deadline.saturating_duration_since(Instant::now())));
    match text {
        Some(Ok(text)) => text,
        _ => {
            kill_group(&child); // whatever it left behind (and the reader thread then ends)
            None
        }
    }
}

/// Kills the process group `child` leads ([`tool_output`]'s), whatever is left of it.
fn kill_group(child: &std::process::Child) {
    #[cfg(unix)]
    if let Some(group) = rustix::process::Pid::from_raw(child.id() as i32) {
        let _ = rustix::process::kill_process_group(group, rustix::process::Signal::KILL);
    }
    #[cfg(not(unix))]
    let _ = child;
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// Whether process `pid` is gone (or a zombie: killed, not yet reaped by its new parent).
    fn gone(pid: &str) -> bool {
        std::fs::read_to_string(format!("/proc/{pid}/stat")).map_or(true, |stat| {
            stat.rsplit_once(')').is_some_and(|(_, rest)| rest.trim_start().starts_with('Z'))
        })
    }

    /// Red-team pass 8, finding 10: a tool whose child outlives it (here it answers, exits 0 and
    /// leaves a `sleep 60` holding its output) delayed the walk's start by that child's whole life.
    /// Now its answer is not waited for past the timeout, and what it left behind is killed.
    #[test]
    fn a_tool_that_leaves_a_child_behind_is_not_waited_for() {
        let dir = mazewalk_testkit::scratch::Scratch::new("tool-leftover");
        let pid_file = dir.join("pid");
        for exit in ["0", "1"] {
            let script = format!("sleep 60 & echo $! > '{}'; echo answer; exit {exit}", pid_file.display());
            let (tx, rx) = std::sync::mpsc::channel();
            std::thread::spawn(move || {
                let _ = tx.send(tool_output(Command::new("sh").arg("-c").arg(script)));
            });
            // (bounded: the old wait lasted the leftover's 60 s)
            let answer =
                rx.recv_timeout(Duration::from_secs(20)).expect("the tool's leftover was waited for");
            assert_eq!(answer, None, "exit {exit}: an answer whose end never came");
            let pid = std::fs::read_to_string(&pid_file).expect("the leftover's pid");
            let deadline = Instant::now() + Duration::from_secs(10);
            while !gone(pid.trim()) && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(10));
            }
            assert!(gone(pid.trim()), "exit {exit}: the leftover {} still runs", pid.trim());
        }
        // A tool that answers and ends is read as before.
        assert_eq!(tool_output(Command::new("sh").arg("-c").arg("echo answer")).as_deref(), Some("answer\n"));
    }
}
