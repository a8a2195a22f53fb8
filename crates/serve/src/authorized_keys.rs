//! Who may play when the server is not `--open`: an OpenSSH `authorized_keys` file, read line by line
//! as sshd reads it (`sshd(8)`, AUTHORIZED_KEYS FILE FORMAT; OpenSSH's `auth2-pubkeyfile.c`):
//!
//! ```text
//! [options] keytype base64-key [comment]
//! restrict,command="borg serve --restrict-to-path /srv/backup" ssh-ed25519 AAAA… backup@host
//! ```
//!
//! - Blank lines and lines starting with `#` (after leading blanks) are skipped; so is a UTF-8 byte
//!   order mark at the start of the file, and a `\r` at the end of a line.
//! - Fields are separated by runs of spaces or tabs. A line is tried as a key first; if that fails,
//!   its first field is options: comma-separated, a value in double quotes may hold spaces, commas and
//!   `\"` (so `command="echo \"a, b\""` is one option), and the key follows.
//! - A line that cannot be read — an unterminated quote, an unknown option, a key type the server
//!   cannot check (`ssh-dss`, names it does not know), a bad key — is skipped and reported with its
//!   line number (`FILE:LINE: why`), as sshd skips it; it never fails the whole file.
//!
//! The key itself is read by the `ssh-key` crate (russh's). Its own `authorized_keys` parser is not
//! used: ssh-key 0.7 splits a line at every space, inside quotes too, so the common
//! `command="borg serve …"` failed the whole file, and `environment="A=\"",from="10.0.0.1"` came
//! back as one harmless option — the key let in without its `from=`.
//!
//! **Options.** The server enforces none of sshd's options, so a key whose options limit it in a way
//! that matters to the game — `command=`, `from=`, `expiry-time=`, `principals=`, `tunnel=`,
//! `verify-required`, or no pty (`no-pty`, `restrict` without a later `pty`) — is left out rather
//! than let in unlimited. `cert-authority` names a certificate authority, not a player, and is left
//! out too. Options about what the game never offers (forwarding, X11, agent, rc files, environment)
//! are harmless. Pure: text in, keys and reports out.

use russh::keys::ssh_key::public::KeyData;
use russh::keys::{Algorithm, PublicKey};

/// The keys of an `authorized_keys` file that may play, those left out, and the lines skipped.
#[derive(Debug, Default)]
pub struct AuthorizedKeys {
    /// The keys that may play.
    pub keys: Vec<KeyData>,
    /// Keys whose options limit them in ways the server does not enforce: left out.
    pub left_out: Vec<LeftOut>,
    /// Lines that could not be read: skipped.
    pub skipped: Vec<Skipped>,
}

/// A key of an `authorized_keys` file left out, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeftOut {
    /// Its line, from 1.
    pub line: usize,
    /// Its comment (often who it is), as written.
    pub comment: String,
    /// The option that limits it, as written.
    pub option: String,
}

/// A line of an `authorized_keys` file that could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Skipped {
    /// The line, from 1.
    pub line: usize,
    /// Why.
    pub why: String,
}

/// What one line holds.
#[derive(Debug)]
enum Line {
    /// Blank or a comment.
    Nothing,
    /// A key and its options (the raw options field, if any).
    Key { options: Option<String>, key: PublicKey },
}

/// Options about what the game never offers (forwarding, X11, agent, rc files, the environment of a
/// shell it never runs, touch of a security key): harmless to ignore.
const HARMLESS: [&str; 13] = [
    "no-port-forwarding",
    "no-agent-forwarding",
    "no-x11-forwarding",
    "no-user-rc",
    "port-forwarding",
    "agent-forwarding",
    "x11-forwarding",
    "user-rc",
    "no-touch-required",
    "permitopen",
    "permitlisten",
    "environment",
    "pty",
];

/// Options that limit a key in ways the server does not enforce.
const LIMITING: [&str; 7] =
    ["command", "from", "expiry-time", "principals", "tunnel", "verify-required", "cert-authority"];

/// Reads the text of an `authorized_keys` file (see the module's doc).
#[must_use]
pub fn parse(text: &str) -> AuthorizedKeys {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut read = AuthorizedKeys::default();
    for (number, line) in (1..).zip(text.split('\n')) {
        match read_line(line) {
            Ok(Line::Nothing) => {}
            Ok(Line::Key { options, key }) => match options.as_deref().map_or(Ok(None), limit) {
                Err(why) => read.skipped.push(Skipped { line: number, why }),
                Ok(Some(option)) => {
                    read.left_out.push(LeftOut { line: number, comment: key.comment().to_string(), option });
                }
                Ok(None) => read.keys.push(key.key_data().clone()),
            },
            Err(why) => read.skipped.push(Skipped { line: number, why }),
        }
    }
    read
}

/// One line: nothing, or a key with its options; else why it cannot be read.
fn read_line(line: &str) -> Result<Line, String> {
    let line = line.strip_suffix('\r').unwrap_or(line).trim_matches([' ', '\t']);
    if line.is_empty() || line.starts_with('#') {
        return Ok(Line::Nothing);
    }
    let as_key = match read_key(line) {
        Ok(key) => return Ok(Line::Key { options: None, key }),
        Err(why) => why,
    };
    // Not a key: the first field is options, unless it names a key type (then it was a bad key).
    let first = line.split([' ', '\t']).next().unwrap_or_default();
    if first.parse::<Algorithm>().is_ok_and(|a| !matches!(a, Algorithm::Other(_))) {
        return Err(as_key);
    }
    let end = options_end(line).ok_or("an unterminated quote in the options")?;
    let (options, rest) = line.split_at(end);
    match read_key(rest.trim_start_matches([' ', '\t'])) {
        Ok(key) => Ok(Line::Key { options: Some(options.to_string()), key }),
        Err(why) if looks_like_options(options) => Err(why),
        Err(_) => Err(format!("unknown key type `{}`", quote(first))),
    }
}

/// Whether a first field that is not a key type reads as options rather than an unknown key type.
fn looks_like_options(field: &str) -> bool {
    let name = field.split([',', '=']).next().unwrap_or_default().to_ascii_lowercase();
    field.contains([',', '='])
        || ["restrict", "no-pty"].contains(&name.as_str())
        || HARMLESS.contains(&name.as_str())
        || LIMITING.contains(&name.as_str())
}

/// Where the options field ends: at the first blank outside double quotes (in which `\"` is a quote).
fn options_end(line: &str) -> Option<usize> {
    let mut quoted = false;
    let mut chars = line.char_indices();
    while let Some((i, c)) = chars.next() {
        match c {
            '\\' if quoted => {
                chars.next();
            }
            '"' => quoted = !quoted,
            ' ' | '\t' if !quoted => return Some(i),
            _ => {}
        }
    }
    None
}

/// The options field split at commas outside double quotes (in which `\"` is a quote).
#[must_use]
pub(crate) fn split_options(options: &str) -> Vec<&str> {
    let (mut out, mut start, mut quoted, mut escaped) = (Vec::new(), 0, false, false);
    for (i, c) in options.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if quoted => escaped = true,
            '"' => quoted = !quoted,
            ',' if !quoted => {
                out.push(&options[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&options[start..]);
    out
}

/// The first option of `options` that keeps its key from playing (`Ok(None)`: none does), or why the
/// options cannot be read (the line is skipped, as sshd skips it).
fn limit(options: &str) -> Result<Option<String>, String> {
    let mut pty_off: Option<&str> = None;
    for option in split_options(options) {
        let (name, value) = match option.split_once('=') {
            Some((name, value)) => (name, Some(value)),
            None => (option, None),
        };
        let name = name.to_ascii_lowercase();
        if value.is_some_and(|v| !(v.len() >= 2 && v.starts_with('"') && v.ends_with('"'))) {
            return Err(format!("option `{}` needs a value in double quotes", quote(option)));
        }
        match name.as_str() {
            "restrict" | "no-pty" => pty_off = Some(option),
            "pty" => pty_off = None, // (after `restrict`, as sshd reads them in order)
            _ if LIMITING.contains(&name.as_str()) => return Ok(Some(option.to_string())),
            _ if HARMLESS.contains(&name.as_str()) => {}
            "" => return Err("an empty option".into()),
            _ => return Err(format!("unknown option `{}`", quote(option))),
        }
    }
    Ok(pty_off.map(str::to_string))
}

/// `keytype base64 [comment]` with any run of blanks between the fields, read by ssh-key; a key type
/// the server cannot check a signature of is refused.
fn read_key(s: &str) -> Result<PublicKey, String> {
    let mut fields = s.splitn(2, [' ', '\t']);
    let kind = fields.next().unwrap_or_default();
    let rest = fields.next().unwrap_or_default().trim_start_matches([' ', '\t']);
    let mut fields = rest.splitn(2, [' ', '\t']);
    let blob = fields.next().unwrap_or_default();
    let comment = fields.next().unwrap_or_default().trim_matches([' ', '\t']);
    if kind.is_empty() || blob.is_empty() {
        return Err("not a key".into());
    }
    let mut key = PublicKey::from_openssh(&format!("{kind} {blob}"))
        .map_err(|e| format!("not a key of type `{}`: {e}", quote(kind)))?;
    match key.algorithm() {
        Algorithm::Dsa | Algorithm::Other(_) => {
            return Err(format!("key type `{}` is not supported", quote(kind)));
        }
        algorithm if algorithm.as_str() != kind => {
            return Err(format!("the key is of type {}, not `{}`", algorithm.as_str(), quote(kind)));
        }
        _ => {}
    }
    key.set_comment(comment);
    Ok(key)
}

/// A piece of the file as a message shows it (bounded, control characters escaped), as every
/// message quotes untrusted text.
fn quote(s: &str) -> String {
    mazewalk_maze::quote(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Two throwaway keys made by `ssh-keygen -t ed25519` and `-t ecdsa`.
    const ED: &str = "ssh-ed25519 AAAAC3NzaC1lZDI1NTE5AAAAIImypI4iL/4FB/6AB6xXtu8e4gvbqReOWrZZSz/4daGN";
    const EC: &str = "ecdsa-sha2-nistp256 AAAAE2VjZHNhLXNoYTItbmlzdHAyNTYAAAAIbmlzdHAyNTYAAABBBBg4snonrKOw6L3i1D+EEG1p6Xzrvcld/biJSS02iIGTdEJBfuXZxnS3yw7yON5gLHXRUEl3N8CRYBEg8GIQds0=";

    fn ed() -> KeyData {
        PublicKey::from_openssh(ED).unwrap().key_data().clone()
    }

    /// Issue #34, high 3: these common lines failed the whole file ("not an OpenSSH key file:
    /// Base64 encoding error", exit 1, no line number). Each is read as sshd reads it: the keys of
    /// restricted lines (borg, gitolite, rrsync) are left out with the option that limits them; a key
    /// with only harmless options plays.
    #[test]
    fn real_world_lines_are_read_and_restricted_keys_left_out() {
        let lines = [
            format!(r#"restrict,command="borg serve --restrict-to-path /srv/backup" {ED} backup@nas"#),
            format!(
                r#"command="/usr/share/gitolite3/gitolite-shell alice",no-port-forwarding,no-X11-forwarding,no-agent-forwarding,no-pty {ED} alice"#
            ),
            format!(r#"command="rrsync -ro /srv/files",restrict {ED} rrsync"#),
            format!(r#"cert-authority,principals="alice,bob" {ED} our CA"#),
            format!(r#"environment="A=b c",no-agent-forwarding {ED} env with a space"#),
            format!(r#"from="10.0.0.?,*.example.com",no-pty {ED} from"#),
            format!(r#"command="echo \"hi, there\"",no-pty {ED} escaped quotes"#),
            format!("no-port-forwarding,no-X11-forwarding {EC} plays"),
            format!("restrict,pty {ED} restricted but with a pty"),
        ];
        let read = parse(&lines.join("\n"));
        assert_eq!(read.skipped, []);
        let out: Vec<(usize, &str, &str)> =
            read.left_out.iter().map(|l| (l.line, l.comment.as_str(), l.option.as_str())).collect();
        assert_eq!(
            out,
            [
                (1, "backup@nas", r#"command="borg serve --restrict-to-path /srv/backup""#),
                (2, "alice", r#"command="/usr/share/gitolite3/gitolite-shell alice""#),
                (3, "rrsync", r#"command="rrsync -ro /srv/files""#),
                (4, "our CA", "cert-authority"),
                (6, "from", r#"from="10.0.0.?,*.example.com""#),
                (7, "escaped quotes", r#"command="echo \"hi, there\"""#),
            ]
        );
        assert_eq!(read.keys.len(), 3, "env with a space, plays, restricted but with a pty");
        assert!(read.keys.contains(&ed()));
    }

    /// Issue #34: `environment="A=\"",from="10.0.0.1"` came back from ssh-key as one (harmless)
    /// environment option, and the key was let in without its `from=`.
    #[test]
    fn an_escaped_quote_does_not_hide_the_next_option() {
        assert_eq!(
            split_options(r#"environment="A=\"",from="10.0.0.1",no-pty"#),
            [r#"environment="A=\"""#, r#"from="10.0.0.1""#, "no-pty"]
        );
        let read = parse(&format!(r#"environment="A=\"",from="10.0.0.1" {ED} sneaky"#));
        assert!(read.keys.is_empty(), "let in unlimited");
        assert_eq!(read.left_out[0].option, r#"from="10.0.0.1""#);
    }

    /// Whitespace as sshd takes it, a BOM, CRLF, comments; a line that cannot be read is skipped with
    /// its number and the rest are read.
    #[test]
    fn blanks_a_bom_and_bad_lines_are_taken_as_sshd_takes_them() {
        let text = [
            format!("\u{feff}{ED} bom"),
            format!("  \t{ED} leading blanks"),
            "ssh-ed25519  AAAAC3NzaC1lZDI1NTE5AAAAIImypI4iL/4FB/6AB6xXtu8e4gvbqReOWrZZSz/4daGN  two spaces"
                .into(),
            format!("no-agent-forwarding\t{}\ttabs", ED.replace(' ', "\t")),
            format!("{ED} crlf\r"),
            "# a comment".into(),
            "   # an indented comment".into(),
            String::new(),
            "ssh-foo AAAAB3NzaC1yc2EAAAADAQABAAABAQ unknown".into(),
            format!(r#"command="unterminated {ED} x"#),
            format!("frobnicate {ED} unknown option"),
            "ssh-ed25519 not-base64 bad".into(),
            format!("ssh-rsa {} mislabelled", ED.split(' ').nth(1).unwrap()),
            format!("{ED} the last one"),
        ]
        .join("\n");
        let read = parse(&text);
        assert_eq!(read.keys.len(), 6, "{read:?}");
        let skipped: Vec<usize> = read.skipped.iter().map(|s| s.line).collect();
        assert_eq!(skipped, [9, 10, 11, 12, 13], "{:?}", read.skipped);
        assert!(read.skipped[0].why.contains("unknown key type `ssh-foo`"), "{:?}", read.skipped[0]);
        assert!(read.skipped[2].why.contains("unknown option `frobnicate`"), "{:?}", read.skipped[2]);
        assert!(read.skipped[1].why.contains("unterminated quote"), "{:?}", read.skipped[1]);
        assert!(read.skipped[4].why.contains("`ssh-rsa`"), "{:?}", read.skipped[4]);
        assert!(read.left_out.is_empty());
    }

    /// A hostile line cannot put escape sequences on the host's terminal through a report.
    #[test]
    fn reports_quote_the_files_text() {
        let read = parse(&format!("\x1b]0;pwned\x07=\"x\" {ED} c"));
        let why = &read.skipped[0].why;
        assert!(!why.contains('\x1b') && why.contains("\\u{1b}"), "{why}");
    }

    proptest! {
        #![proptest_config(mazewalk_testkit::config())]

        /// Any text is read without a panic, each line once at most.
        #[test]
        fn any_text_is_read_without_a_panic(
            lines in prop::collection::vec(
                prop_oneof![
                    "[a-z=,\"\\\\ \t#-]{0,40}",
                    ".{0,60}",
                    Just(ED.to_string()),
                    "[a-z-]{1,12}(=\"[^\"]{0,10}\")?".prop_map(|o| format!("{o} {ED} c")),
                ],
                0..12,
            )
        ) {
            let text = lines.join("\n");
            let read = parse(&text);
            let accounted = read.keys.len() + read.left_out.len() + read.skipped.len();
            prop_assert!(accounted <= text.split('\n').count());
        }
    }
}
