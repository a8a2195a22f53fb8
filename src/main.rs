//! The `mazewalk` binary: command-line wiring only — the flags are parsed by [`mazewalk::cli`], each
//! command's work is in [`mazewalk::commands`]; here each command is dispatched and its outcome turned
//! into an exit code.
//!
//! `mazewalk [MAZE]` walks a maze (the built-in one without MAZE); `render`, `gen` and `check` are the
//! batch commands, `serve` hosts a maze over SSH, `records` prints its best times and `replay` plays a
//! stored run back. Exit codes: 0 success, 2 usage errors (bad flags or values), 65 malformed or
//! invalid maze data, a file over the size limit, or a run (`--ghost`, `replay`) that does not decode
//! or is of another maze, 66 cannot read the file, 141 stdout's reader went away,
//! 128 + n the walk ended by signal n, 1 anything else (e.g. no terminal). Maze errors go to stderr
//! as `FILE:LINE:COL: message`.

use std::io::Write;
use std::process::ExitCode;

use clap::Parser as _;
use mazewalk::cli::{Cli, Command};
use mazewalk::commands::{self, BadData, NoInput, Usage, is_broken_pipe};
use mazewalk_maze::LoadError;

/// Exit status for bad flags or values (as clap's).
const EXIT_USAGE: u8 = 2;
/// Exit status for malformed or invalid data (sysexits EX_DATAERR).
const EXIT_DATA: u8 = 65;
/// Exit status for an unreadable input file (sysexits EX_NOINPUT).
const EXIT_NO_INPUT: u8 = 66;

/// Exit status when the reader of stdout went away: 128 + SIGPIPE, as shells report a tool killed by it.
const EXIT_BROKEN_PIPE: u8 = 128 + 13;

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

/// [`commands::note_stdout_at_start`], run by the loader before Rust's start-up, which replaces a
/// closed stdout with /dev/null: only then can a closed one be told from /dev/null. The one
/// `unsafe` of the binary is the attribute that puts the function in the ELF `.init_array` (as the
/// `ctor` crate does); the function itself is safe code.
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
#[used]
#[unsafe(link_section = ".init_array")]
static LOOK_AT_STDOUT: extern "C" fn() = {
    extern "C" fn look_at_stdout() {
        commands::note_stdout_at_start();
    }
    look_at_stdout
};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // clap's own exit ignores a failed write, so `--help > /dev/full` would report success.
        Err(e) => return clap_exit(&e),
    };
    let result = match cli.command {
        None => walk(&cli),
        Some(Command::Render(args)) => commands::render::run(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Gen(args)) => commands::generate::run(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Check(args)) => commands::check::run(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Serve(args)) => commands::serve::run(&args),
        Some(Command::Records(args)) => commands::records::run(&args).map(|()| ExitCode::SUCCESS),
        Some(Command::Replay(args)) => commands::walk::replay(&args),
    };
    match result {
        Ok(code) => code,
        // A reader that went away (`mazewalk gen … | head`): end quietly, as if killed by SIGPIPE
        // like other Unix tools (Rust programs ignore the signal and see the error instead).
        Err(err) if is_broken_pipe(&err) => ExitCode::from(EXIT_BROKEN_PIPE),
        Err(err) => {
            let load = err.downcast_ref::<LoadError>();
            // (Not eprintln!, which panics when stderr cannot be written: the exit code still tells.
            // Patient: a terminal the walk found non-blocking may not take the line at once.)
            let mut stderr = mazewalk::guard::Patient::new(std::io::stderr());
            let _ = match load {
                Some(e) => writeln!(stderr, "{e}"), // FILE:LINE:COL: message, for editors
                None => writeln!(stderr, "mazewalk: {err:#}"),
            };
            ExitCode::from(match load {
                Some(LoadError::Parse(_) | LoadError::TooLarge { .. }) => EXIT_DATA,
                Some(LoadError::Io { .. } | LoadError::NotAFile { .. }) => EXIT_NO_INPUT,
                None if err.downcast_ref::<Usage>().is_some() => EXIT_USAGE,
                None if err.downcast_ref::<NoInput>().is_some() => EXIT_NO_INPUT,
                None if err.downcast_ref::<BadData>().is_some() => EXIT_DATA,
                None => 1,
            })
        }
    }
}

/// The walk (no command): on Unix, in this process's terminal.
fn walk(cli: &Cli) -> anyhow::Result<ExitCode> {
    #[cfg(unix)]
    return commands::walk::run(&cli.walk);
    #[cfg(not(unix))]
    anyhow::bail!("the full-screen walk runs on Unix only (try `mazewalk render`)");
}
