//! `mazewalk serve` as a process of its own, for the measuring examples (`benches/examples/`) that
//! keep the server apart from their clients so that its CPU, memory and log are its own: where the
//! release binary is, the address its first line names, and the examples' `--flag value` arguments.

use std::io::{BufRead as _, BufReader, Read};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::{Child, ChildStdout};

/// The `mazewalk` binary beside the running example: `target/release/examples/NAME` →
/// `target/release/mazewalk` (built or not: the caller says how to build it).
///
/// # Panics
/// When the running example has no folder two levels up.
#[must_use]
pub fn release_binary() -> PathBuf {
    let exe = std::env::current_exe().expect("current exe");
    exe.parent().and_then(|p| p.parent()).map(|p| p.join("mazewalk")).expect("target dir")
}

/// The address a server's first line names, `mazewalk: serving on ADDR[, ADDR…]`: the first one.
#[must_use]
pub fn serving_on(line: &str) -> Option<SocketAddr> {
    let first = line.trim().split(", ").next()?;
    first.rsplit_once(' ').and_then(|(_, addr)| addr.parse().ok())
}

/// Reads the first line of a server just started with its stdout piped, and returns the address it
/// names ([`serving_on`]) and the rest of stdout: read further lines from it if need be, then hand it
/// to [`drain`].
///
/// # Panics
/// When stdout is not piped, or the first line names no address.
pub fn announced(child: &mut Child) -> (SocketAddr, BufReader<ChildStdout>) {
    let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
    let mut line = String::new();
    stdout.read_line(&mut line).expect("first line");
    (serving_on(&line).expect("serving on ADDR"), stdout)
}

/// Reads and drops the rest of what a server prints, on a thread of its own: a closed pipe would end
/// the server at its next line.
pub fn drain(mut stdout: impl Read + Send + 'static) {
    std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink()));
}

/// The running example's arguments as `--flag value` pairs, in order ([`pairs`]); with `-h` or
/// `--help` among the flags ([`asks_help`]), `usage` is printed and the example ends there (exit 0).
#[must_use]
pub fn flags(usage: &str) -> Vec<(String, String)> {
    let flags = pairs(std::env::args().skip(1));
    if asks_help(&flags) {
        println!("{usage}");
        std::process::exit(0);
    }
    flags
}

/// Whether `-h` or `--help` is one of the flags (not a value).
#[must_use]
pub fn asks_help(flags: &[(String, String)]) -> bool {
    flags.iter().any(|(flag, _)| flag == "-h" || flag == "--help")
}

/// `value` read as `flag`'s value, or the example ends with what it wanted and `usage` on stderr
/// (exit 2), as a command-line tool refuses a value it cannot read (red-team pass 10: `--help`
/// panicked at "unknown argument").
pub fn value<T: std::str::FromStr>(flag: &str, value: &str, usage: &str) -> T {
    value.parse().unwrap_or_else(|_| refuse(&format!("{flag}: cannot read {value:?}"), usage))
}

/// Ends the example with `what` and `usage` on stderr, exit 2: a flag it does not know, or a value
/// it cannot read.
pub fn refuse(what: &str, usage: &str) -> ! {
    eprintln!("error: {what}\n\n{usage}");
    std::process::exit(2)
}

/// `args` two by two, as `(flag, value)`; a last flag without its value gets an empty one.
#[must_use]
pub fn pairs(args: impl IntoIterator<Item = String>) -> Vec<(String, String)> {
    let args: Vec<String> = args.into_iter().collect();
    args.chunks(2).map(|pair| (pair[0].clone(), pair.get(1).cloned().unwrap_or_default())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_address_of_the_first_line_is_read() {
        let one = "mazewalk: serving on 127.0.0.1:2222\n";
        assert_eq!(serving_on(one), Some(SocketAddr::from(([127, 0, 0, 1], 2222))));
        let two = "mazewalk: serving on 127.0.0.1:2222, [::1]:2223\n";
        assert_eq!(serving_on(two), Some(SocketAddr::from(([127, 0, 0, 1], 2222))));
        assert_eq!(serving_on("mazewalk: error: address in use"), None);
        assert_eq!(serving_on(""), None);
    }

    // red-team pass 10: `--example load -- --help` panicked ("unknown argument --help")
    #[test]
    fn help_is_asked_by_either_flag_in_a_flags_place_only() {
        let asks = |args: &[&str]| asks_help(&pairs(args.iter().map(|a| a.to_string())));
        assert!(asks(&["--help"]));
        assert!(asks(&["-h"]));
        assert!(asks(&["--seconds", "5", "--help"]));
        assert!(!asks(&["--seconds", "5"]));
        assert!(!asks(&["--world", "--help"]), "a value that reads --help is the flag's value");
        assert!(!asks(&[]));
    }

    #[test]
    fn arguments_pair_up_and_a_lone_flag_gets_an_empty_value() {
        let args = ["--seconds", "5", "--only"].map(String::from);
        let expected = [("--seconds", "5"), ("--only", "")].map(|(f, v)| (f.to_string(), v.to_string()));
        assert_eq!(pairs(args), expected);
        assert!(pairs(Vec::new()).is_empty());
    }
}
