//! `mazewalk [MAZE]`: the full-screen walk on this process's terminal.

use std::io::{IsTerminal as _, Write};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context as _, bail};

use super::load_maze;
use crate::cli::WalkArgs;
use crate::guard;
use crate::run::run as run_session;
use mazewalk_render::Culling;
use mazewalk_term::caps;
use mazewalk_walk::state::Motion;
use mazewalk_walk::{App, Session, SessionOptions};

/// Walks the maze the flags name in this process's terminal until the player quits or a signal
/// ends it (exit 128 + n).
pub fn run(args: &WalkArgs) -> anyhow::Result<ExitCode> {
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
    if let Some(signal) = run_session(&mut session, clock).context("terminal")?.signal() {
        return Ok(ExitCode::from(u8::try_from(guard::exit_code_for_signal(signal)).unwrap_or(1)));
    }
    if let Some(seconds) = session.outcome().finished {
        let _ = writeln!(std::io::stdout(), "You found the exit in {seconds:.1} s."); // the walk is over either way
    }
    Ok(ExitCode::SUCCESS)
}
