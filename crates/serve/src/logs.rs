//! The server's log kept bounded whatever clients do (issue #34: a loop of junk key exchanges grew it
//! by 128 MB in 5 s). Two rules:
//!
//! - **Text from outside is clipped.** An error from the SSH library is logged as a short reason of
//!   our own ([`error_reason`]); any text it carries that a client chose (russh's "no common algorithm"
//!   error holds the client's whole list) is cut to a few names of at most [`NAME_CHARS`] characters,
//!   control characters escaped ([`clip`]).
//! - **Lines about connections are rate-limited per address group** ([`LogLimit`]): a burst, then a
//!   trickle, per group (an IPv4 address, an IPv6 /64: [`address_group`](crate::slots::address_group))
//!   and in all. What is left out is counted and summed up in one line per group every
//!   [`SUMMARY_SECONDS`] ("log lines suppressed (rate limit) addresses=… lines=…"; past
//!   [`SUMMARY_GROUPS`] groups, one more line for the rest).
//!
//! How a line is written is the subscriber's choice: today's text, or [`JsonLines`] (`--log-format
//! json`), one JSON object a line for journald and log shippers. Either way the same lines, through
//! the same limits: the format only changes their shape.
//!
//! The limits are pure: time comes in as seconds.

use std::collections::HashMap;
use std::net::IpAddr;

use super::limits::RateLimit;

/// Most characters of one algorithm name a client offered, quoted in a log line: 48, so that every
/// name OpenSSH knows shows whole (the longest, `sk-ecdsa-sha2-nistp256-cert-v01@openssh.com`, has
/// 43), where a message's quote of untrusted text ([`mazewalk_maze::QUOTE_CHARS`], 40) would cut it.
pub const NAME_CHARS: usize = 48;

/// Most characters of a library error's text in a log line.
pub(crate) const ERROR_CHARS: usize = 160;

/// Most names of a client's algorithm list quoted in a log line.
pub(crate) const NAMES_QUOTED: usize = 4;

/// Lines one address group may log at once …
pub(crate) const GROUP_BURST: u32 = 20;
/// … and then one every this many seconds.
pub(crate) const GROUP_INTERVAL: f64 = 5.0;
/// Lines all groups together may log at once …
pub(crate) const GLOBAL_BURST: u32 = 200;
/// … and then this many a second.
pub(crate) const GLOBAL_RATE: u32 = 20;
/// How often the suppressed lines are summed up in the log.
pub(crate) const SUMMARY_SECONDS: u64 = 10;
/// Address groups whose counts are kept; beyond it, lines of new groups count against the global
/// budget only, and their suppressed lines are summed up together.
pub(crate) const TRACKED_GROUPS: usize = 4096;
/// Groups named one by one in a summary; the rest are summed up in one more line.
pub(crate) const SUMMARY_GROUPS: usize = 8;

/// `text` as a log line shows it: control and formatting characters (escape sequences, NUL, bidi
/// overrides) escaped, so nothing a client sent can move the cursor or hide text on the host's
/// terminal, and at most `max` characters of that (escapes included), then `…`.
#[must_use]
pub fn clip(text: &str, max: usize) -> String {
    mazewalk_maze::quote_within(text, max) // the one escaping of untrusted text
}

/// A word a client chose (an algorithm's name it offered) as a log line shows it: [`clip`]ped, and
/// its spaces, `=`, `"` and `\` spelled `\u{20}`, `\u{3d}`, `\u{22}`, `\u{5c}` too, so that it
/// reads as one word of the line: never as a field of it (`user=root` in a name offered as `x
/// user=root`: red-team pass 17), nor as a quoted value's start or end, nor as an escape that
/// [`clip`] wrote. A name as RFC 4251 has them (printable ASCII, no space) shows as it was sent, but
/// for `=`, `"` or `\` in it.
#[must_use]
pub(crate) fn clip_word(text: &str, max: usize) -> String {
    let mut out = String::new();
    let mut shown = 0usize;
    for c in text.chars() {
        // each character whole or not at all, escaped as `clip` does or for a word's sake
        let one = if matches!(c, ' ' | '=' | '"' | '\\') {
            c.escape_unicode().to_string()
        } else {
            clip(c.encode_utf8(&mut [0; 4]), usize::MAX)
        };
        let len = one.chars().count();
        if shown.saturating_add(len) > max {
            out.push('…');
            break;
        }
        shown += len;
        out.push_str(&one);
    }
    out
}

/// Why a connection ended, from the SSH library's error: a short reason of our own words, never the
/// library's text whole (see the module's doc).
#[must_use]
pub(crate) fn error_reason(err: &russh::Error) -> String {
    use russh::Error as E;
    match err {
        E::NoCommonAlgo { kind, theirs, .. } => {
            let kind = format!("{kind:?}").to_ascii_lowercase();
            let quoted: Vec<String> =
                theirs.iter().take(NAMES_QUOTED).map(|n| clip_word(n.as_ref(), NAME_CHARS)).collect();
            let more = theirs.len().saturating_sub(NAMES_QUOTED);
            let more = if more > 0 { format!(" (+{more} more)") } else { String::new() };
            format!("no common {kind} algorithm; the client offered {}{more}", quoted.join(","))
        }
        E::KeepaliveTimeout => "keepalive timeout".into(),
        E::InactivityTimeout => "inactivity timeout".into(),
        E::Version => "not an SSH client (bad identification line)".into(),
        E::PacketSize(n) => format!("bad packet size {n}"),
        E::PacketAuth | E::DecryptionError => "a packet failed its integrity check".into(),
        E::Kex | E::KexInit => "key exchange failed".into(),
        E::UnknownAlgo => "unknown algorithm".into(),
        E::HUP | E::Disconnect => "closed".into(),
        E::StrictKeyExchangeViolation { .. } => "strict key exchange violated".into(),
        E::IO(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => "connection lost".into(),
        E::IO(io) => format!("connection error: {}", clip(&io.to_string(), ERROR_CHARS)),
        other => clip(&other.to_string().to_lowercase(), ERROR_CHARS),
    }
}

/// One address group's budget and what it had left out.
#[derive(Clone, Copy, Debug)]
struct Group {
    bucket: RateLimit,
    suppressed: u64,
}

/// Lines left out since the last summary ([`LogLimit::take_suppressed`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Suppressed {
    /// The groups with most lines left out, most first (at most [`SUMMARY_GROUPS`]).
    pub groups: Vec<(IpAddr, u64)>,
    /// The rest: how many groups (untracked ones as one), and their lines.
    pub others: (usize, u64),
}

/// Which connection log lines are written: see the module's doc.
#[derive(Debug)]
pub(crate) struct LogLimit {
    groups: HashMap<IpAddr, Group>,
    global: RateLimit,
    /// Lines left out for the global budget or of groups past [`TRACKED_GROUPS`] (no group of
    /// their own).
    untracked: u64,
}

impl LogLimit {
    /// Full budgets at time `now`.
    #[must_use]
    pub fn new(now: f64) -> LogLimit {
        LogLimit {
            groups: HashMap::new(),
            global: RateLimit::new(GLOBAL_RATE, GLOBAL_BURST, now),
            untracked: 0,
        }
    }

    /// Whether a line about a connection from `group` may be written at `now`; if not, it is counted.
    pub fn allow(&mut self, group: IpAddr, now: f64) -> bool {
        if !self.groups.contains_key(&group) && self.groups.len() >= TRACKED_GROUPS {
            self.forget_quiet(now);
        }
        let tracked = self.groups.len() < TRACKED_GROUPS || self.groups.contains_key(&group);
        if !tracked {
            let allowed = self.global.take(1, now) == 1;
            self.untracked += u64::from(!allowed);
            return allowed;
        }
        let entry = self.groups.entry(group).or_insert_with(|| Group {
            bucket: RateLimit::new_per_interval(GROUP_INTERVAL, GROUP_BURST, now),
            suppressed: 0,
        });
        // The group's budget first: a group past its own does not use up everyone's.
        let allowed = entry.bucket.take(1, now) == 1 && self.global.take(1, now) == 1;
        entry.suppressed += u64::from(!allowed);
        allowed
    }

    /// The lines left out since the last call, for a summary; the counts start again from 0, and
    /// groups with nothing left out and a full budget are forgotten.
    pub(crate) fn take_suppressed(&mut self, now: f64) -> Suppressed {
        let mut counts: Vec<(IpAddr, u64)> = self
            .groups
            .iter_mut()
            .filter(|(_, g)| g.suppressed > 0)
            .map(|(ip, g)| (*ip, std::mem::take(&mut g.suppressed)))
            .collect();
        counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        let rest = counts.split_off(counts.len().min(SUMMARY_GROUPS));
        let untracked = std::mem::take(&mut self.untracked);
        let others =
            (rest.len() + usize::from(untracked > 0), rest.iter().map(|(_, n)| n).sum::<u64>() + untracked);
        self.forget_quiet(now);
        Suppressed { groups: counts, others }
    }

    /// Forgets the groups that have nothing left out and their whole budget back.
    fn forget_quiet(&mut self, now: f64) {
        self.groups.retain(|_, g| g.suppressed > 0 || !g.bucket.is_full(now));
    }

    /// Address groups whose counts are kept now.
    #[must_use]
    #[cfg(test)]
    pub fn tracked(&self) -> usize {
        self.groups.len()
    }
}

/// Log lines as JSON objects, one a line: `time` (RFC 3339, UTC), `level`, `event` (a short name:
/// the message's first words, see [`event_name`]), `address` (the client's, when the line is about a
/// connection), `player` (its user name, when known), `message` (the whole line, as the text format
/// says it), then the line's other fields under their own names (`seconds`, `reason`, `key`, …).
/// Strings are escaped by serde_json, and the characters it leaves as they are (DEL, the C1
/// controls, bidi and other formatting characters: [`mazewalk_maze::unseen`]) as `\uXXXX` too
/// ([`mazewalk_maze::escape_json`]): no byte a client chose reaches the log as a control.
#[derive(Clone, Copy, Debug, Default)]
pub struct JsonLines;

impl<S, N> tracing_subscriber::fmt::FormatEvent<S, N> for JsonLines
where
    S: tracing::Subscriber + for<'a> tracing_subscriber::registry::LookupSpan<'a>,
    N: for<'a> tracing_subscriber::fmt::FormatFields<'a> + 'static,
{
    fn format_event(
        &self,
        _: &tracing_subscriber::fmt::FmtContext<'_, S, N>,
        mut writer: tracing_subscriber::fmt::format::Writer<'_>,
        event: &tracing::Event<'_>,
    ) -> std::fmt::Result {
        use tracing_subscriber::fmt::time::{FormatTime as _, SystemTime};
        let mut time = String::new();
        SystemTime.format_time(&mut tracing_subscriber::fmt::format::Writer::new(&mut time))?;
        let mut fields = JsonFields::default();
        event.record(&mut fields);
        let level = event.metadata().level().as_str().to_ascii_lowercase();
        writeln!(writer, "{}", fields.line(&time, &level))
    }
}

/// One event's fields on their way to a JSON line.
#[derive(Default)]
struct JsonFields {
    message: String,
    address: Option<serde_json::Value>,
    player: Option<serde_json::Value>,
    others: Vec<(&'static str, serde_json::Value)>,
}

impl JsonFields {
    fn put(&mut self, field: &tracing::field::Field, value: serde_json::Value) {
        match field.name() {
            "message" => self.message = value.as_str().map_or_else(|| value.to_string(), str::to_string),
            "peer" => self.address = Some(value),
            "user" | "player" => self.player = Some(value),
            name => self.others.push((name, value)),
        }
    }

    /// The JSON object, keys in a fixed order (serde_json's map would sort them).
    fn line(self, time: &str, level: &str) -> String {
        use serde_json::Value;
        let event = event_name(&self.message);
        let mut pairs: Vec<(&str, Value)> = vec![
            ("time", Value::from(time)),
            ("level", Value::from(level)),
            ("event", Value::from(event)),
            ("address", self.address.unwrap_or(Value::Null)),
            ("player", self.player.unwrap_or(Value::Null)),
            ("message", Value::from(self.message)),
        ];
        for (name, value) in self.others {
            if !pairs.iter().any(|(key, _)| *key == name) {
                pairs.push((name, value));
            }
        }
        let mut line = String::from("{");
        for (i, (key, value)) in pairs.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            line.push_str(&Value::from(*key).to_string());
            line.push(':');
            line.push_str(&value.to_string());
        }
        line.push('}');
        mazewalk_maze::escape_json(&line) // (DEL, C1, bidi: serde_json leaves them raw)
    }
}

impl tracing::field::Visit for JsonFields {
    fn record_debug(&mut self, field: &tracing::field::Field, value: &dyn std::fmt::Debug) {
        // (`%value` fields come here as Display wrapped in Debug: this is their Display text.)
        self.put(field, serde_json::Value::from(format!("{value:?}")));
    }

    fn record_str(&mut self, field: &tracing::field::Field, value: &str) {
        self.put(field, serde_json::Value::from(value));
    }

    fn record_u64(&mut self, field: &tracing::field::Field, value: u64) {
        self.put(field, serde_json::Value::from(value));
    }

    fn record_i64(&mut self, field: &tracing::field::Field, value: i64) {
        self.put(field, serde_json::Value::from(value));
    }

    fn record_f64(&mut self, field: &tracing::field::Field, value: f64) {
        self.put(field, serde_json::Value::from(value)); // (NaN and infinities: null)
    }

    fn record_bool(&mut self, field: &tracing::field::Field, value: bool) {
        self.put(field, serde_json::Value::from(value));
    }
}

/// A line's short name for filtering: the lowercase words of its message before the first `:`, `(`
/// or digit, joined by `_` ("disconnected", "refused", "reached_the_exit_first",
/// "log_lines_suppressed"); what follows a colon (an address, a reason, a name a client chose) is
/// never part of it.
#[must_use]
pub fn event_name(message: &str) -> String {
    let head = message.split([':', '(']).next().unwrap_or_default();
    let head: String = head
        .chars()
        .take_while(|c| c.is_ascii_alphabetic() || matches!(c, ' ' | '\'' | '-'))
        .filter(|c| *c != '\'')
        .map(|c| c.to_ascii_lowercase())
        .collect();
    head.split_whitespace().take(8).collect::<Vec<_>>().join("_")
}

/// Seconds to a tenth, for a log line's `seconds` field: a number (`seconds=3.4` as text, `3.4` in
/// JSON), not a string.
#[must_use]
pub(crate) fn tenths(seconds: f64) -> f64 {
    (seconds * 10.0).round() / 10.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn client_text_is_clipped_and_escaped() {
        assert_eq!(clip("abc", 10), "abc");
        assert_eq!(clip("\x1b[2J\x07x", 20), "\\u{1b}[2J\\u{7}x");
        assert_eq!(clip("\x1b[2J", 8), "\\u{1b}[2…", "the escapes count");
        assert_eq!(clip(&"y".repeat(1 << 20), 5), "yyyyy…");
        assert_eq!(clip("\u{202e}gnp.exe", 20), "\\u{202e}gnp.exe");
    }

    /// Issue #34: russh's "no common algorithm" error carried the client's whole list (17 KB) into
    /// the log. Now: a few names, each clipped, and how many more.
    #[test]
    fn a_no_common_algorithm_error_names_a_few_of_the_clients_algorithms() {
        // (russh's error holds its own `Name`s; build one the way its negotiation does.)
        let theirs: Vec<String> = (0..2000).map(|i| format!("junk-{i}-{}", "x".repeat(100))).collect();
        let err = russh::Error::NoCommonAlgo {
            kind: russh::AlgorithmKind::Kex,
            ours: vec!["curve25519-sha256".into()],
            theirs: theirs.clone(),
        };
        assert!(err.to_string().len() > 200_000, "the premise: the library's text is huge");
        let reason = error_reason(&err);
        assert!(reason.len() < 400, "{} bytes: {reason}", reason.len());
        assert!(reason.starts_with("no common kex algorithm; the client offered junk-0-x"), "{reason}");
        assert!(reason.ends_with("(+1996 more)"), "{reason}");
        let io = russh::Error::IO(std::io::Error::other("\x1b]0;evil\x07".repeat(1000)));
        let reason = error_reason(&io);
        assert!(reason.chars().count() <= ERROR_CHARS + 40 && !reason.contains('\x1b'), "{reason}");
    }

    #[test]
    fn a_group_gets_a_burst_then_a_trickle_and_others_are_not_held_back() {
        let mut limit = LogLimit::new(0.0);
        let loud: IpAddr = "192.0.2.1".parse().unwrap();
        let quiet: IpAddr = "198.51.100.7".parse().unwrap();
        let allowed = (0..1000).filter(|i| limit.allow(loud, f64::from(*i) * 0.001)).count();
        assert_eq!(allowed, GROUP_BURST as usize, "the burst, within one second");
        assert!(limit.allow(quiet, 1.0), "another address still logs");
        assert!(!limit.allow(loud, 1.0));
        assert!(limit.allow(loud, 1.0 + GROUP_INTERVAL), "one more after the interval");
        let summary = limit.take_suppressed(2.0 + GROUP_INTERVAL);
        assert_eq!(summary.groups, [(loud, 1000 - GROUP_BURST as u64 + 1)]);
        assert_eq!(summary.others, (0, 0));
        assert_eq!(limit.take_suppressed(3.0 + GROUP_INTERVAL), Suppressed::default(), "counts start again");
    }

    /// Red-team pass 17: a client offering `x user=root key=SHA256:fake` had the text format's
    /// line end in `reason=no common kex algorithm; the client offered x user=root key=…`, two fields
    /// of its own making for a reader or a parser of `key=value` pairs. Each name is one word now.
    #[test]
    fn a_clients_algorithm_name_is_one_word_of_the_line() {
        let err = russh::Error::NoCommonAlgo {
            kind: russh::AlgorithmKind::Kex,
            ours: vec!["curve25519-sha256".into()],
            theirs: vec!["x user=root key=SHA256:fake".into(), "a\"b\\u{1b}".into(), "user=root".into()],
        };
        let reason = error_reason(&err);
        assert_eq!(
            reason,
            "no common kex algorithm; the client offered \
             x\\u{20}user\\u{3d}root\\u{20}key\\u{3d}SHA256:fake,a\\u{22}b\\u{5c}u{1b},user\\u{3d}root"
        );
        assert!(!reason.contains('=') && !reason.contains('"'), "{reason}");
        assert_eq!(
            clip_word("sk-ecdsa-sha2-nistp256-cert-v01@openssh.com", NAME_CHARS),
            "sk-ecdsa-sha2-nistp256-cert-v01@openssh.com"
        );
        assert_eq!(clip_word("a b\x1bc", 40), "a\\u{20}b\\u{1b}c", "escapes of both kinds");
        assert_eq!(clip_word(&" ".repeat(1 << 20), 13), "\\u{20}\\u{20}…", "the escapes count, whole");
        assert_eq!(clip_word("ab=c", 4), "ab…");
    }

    /// The library's errors are logged in our own short words, whatever its own text says.
    #[test]
    fn each_library_error_has_a_reason_of_our_own() {
        use russh::Error as E;
        let eof = std::io::Error::from(std::io::ErrorKind::UnexpectedEof);
        let cases = [
            (E::KeepaliveTimeout, "keepalive timeout"),
            (E::InactivityTimeout, "inactivity timeout"),
            (E::Version, "not an SSH client (bad identification line)"),
            (E::PacketSize(70_000), "bad packet size 70000"),
            (E::PacketAuth, "a packet failed its integrity check"),
            (E::DecryptionError, "a packet failed its integrity check"),
            (E::Kex, "key exchange failed"),
            (E::KexInit, "key exchange failed"),
            (E::UnknownAlgo, "unknown algorithm"),
            (E::HUP, "closed"),
            (E::Disconnect, "closed"),
            (
                E::StrictKeyExchangeViolation { message_type: 2, sequence_number: 0 },
                "strict key exchange violated",
            ),
            (E::IO(eof), "connection lost"),
            (E::IO(std::io::ErrorKind::ConnectionReset.into()), "connection error: connection reset"),
            (E::NotAuthenticated, "not yet authenticated"),
        ];
        for (err, reason) in cases {
            assert_eq!(error_reason(&err), reason, "{err:?}");
        }
        let offered = |n: usize| E::NoCommonAlgo {
            kind: russh::AlgorithmKind::Cipher,
            ours: vec!["aes256-gcm@openssh.com".into()],
            theirs: (0..n).map(|i| format!("c{i}")).collect(),
        };
        assert_eq!(error_reason(&offered(4)), "no common cipher algorithm; the client offered c0,c1,c2,c3");
        assert_eq!(
            error_reason(&offered(5)),
            "no common cipher algorithm; the client offered c0,c1,c2,c3 (+1 more)"
        );
    }

    /// A group is forgotten once its budget is whole again and nothing of it is left to sum up,
    /// never before: a loud group's spent budget outlives the summaries.
    #[test]
    fn a_groups_budget_is_forgotten_only_once_whole_again() {
        let mut limit = LogLimit::new(0.0);
        let quiet: IpAddr = "198.51.100.7".parse().unwrap();
        let loud: IpAddr = "192.0.2.1".parse().unwrap();
        assert!(limit.allow(quiet, 0.0));
        while limit.allow(loud, 0.0) {}
        assert_eq!(limit.take_suppressed(GROUP_INTERVAL - 0.5).groups, [(loud, 1)]);
        assert_eq!(limit.tracked(), 2, "neither budget whole yet");
        assert!(!limit.allow(loud, GROUP_INTERVAL - 0.5), "still spent after the summary");
        assert_eq!(limit.take_suppressed(GROUP_INTERVAL).groups, [(loud, 1)]);
        assert_eq!(limit.tracked(), 1, "the quiet one's line came back at the interval: forgotten");
        assert!(limit.allow(loud, GROUP_INTERVAL), "one line back");
        assert!(!limit.allow(loud, GROUP_INTERVAL));
    }

    /// With every tracked group's budget whole again, a new group takes a quiet one's place and gets
    /// its own burst and trickle; the summary names the loudest few and counts the rest, with the
    /// lines of untracked groups as one more.
    #[test]
    fn a_new_group_takes_a_quiet_ones_place_and_the_summary_counts_the_rest() {
        let mut limit = LogLimit::new(0.0);
        let group = |n: u32| IpAddr::from(std::net::Ipv4Addr::from(0x0a00_0000u32 + n));
        for n in 0..TRACKED_GROUPS as u32 {
            assert!(limit.allow(group(n), 0.0) || n >= GLOBAL_BURST);
        }
        assert_eq!(limit.tracked(), TRACKED_GROUPS);
        let later = 1000.0;
        let loud = group(1 << 20);
        let allowed = (0..100).filter(|i| limit.allow(loud, later + f64::from(*i) * 1e-3)).count();
        assert_eq!(allowed, GROUP_BURST as usize, "its own burst, not the global one");
        assert!(limit.tracked() < TRACKED_GROUPS);
        let summary = limit.take_suppressed(later + 1.0);
        assert_eq!(summary.groups[0], (loud, 100 - u64::from(GROUP_BURST)), "the loudest first");

        // ten groups, each past its burst by one line more than the last (the global burst whole)
        let mut limit = LogLimit::new(0.0);
        for n in 0..10u32 {
            for _ in 0..=(GROUP_BURST + n) {
                limit.allow(group(n), 0.0);
            }
        }
        let summary = limit.take_suppressed(0.0);
        assert_eq!(summary.groups.len(), SUMMARY_GROUPS);
        assert_eq!(summary.groups[0], (group(9), 10));
        assert_eq!(summary.others, (2, 2 + 1), "the two quietest");
        // past the tracked groups: the untracked ones' lines are one more
        let mut limit = LogLimit::new(0.0);
        for n in 0..(TRACKED_GROUPS as u32 + 300) {
            limit.allow(group(n), 0.0);
        }
        let summary = limit.take_suppressed(0.0);
        let rest = TRACKED_GROUPS - GLOBAL_BURST as usize - SUMMARY_GROUPS; // one line left out each
        assert_eq!(summary.others, (rest + 1, rest as u64 + 300), "the untracked as one");
    }

    /// A full table makes room by forgetting quiet groups only: a group whose lines were left out
    /// keeps its count for the summary, however long ago its budget came back whole. And a new
    /// group looks over the table only when it is full (a quiet group is kept till then).
    #[test]
    fn a_full_table_forgets_quiet_groups_and_keeps_the_left_out_counts() {
        let group = |n: u32| IpAddr::from(std::net::Ipv4Addr::from(0x0a00_0000u32 + n));
        let mut limit = LogLimit::new(0.0);
        let loud = group(0);
        let left_out = (0..GROUP_BURST + 5).filter(|_| !limit.allow(loud, 0.0)).count() as u64;
        assert_eq!(left_out, 5);
        // every budget whole again: a newcomer while the table has room forgets nobody
        let later = 1000.0;
        assert!(limit.allow(group(1), later));
        assert_eq!(limit.tracked(), 2, "no look over a table with room");
        // (one a global interval apart: none of them left out for the global budget)
        let mut at = later;
        for n in 2..TRACKED_GROUPS as u32 {
            at += 1.0 / f64::from(GLOBAL_RATE);
            assert!(limit.allow(group(n), at));
        }
        assert_eq!(limit.tracked(), TRACKED_GROUPS);
        // full: the next newcomer's look forgets the quiet ones, never the loud one's count
        let after = at + 2.0 * GROUP_INTERVAL;
        assert!(limit.allow(group(1 << 20), after));
        assert_eq!(limit.tracked(), 2, "the loud group and the newcomer");
        assert_eq!(limit.take_suppressed(after).groups, [(loud, left_out)]);
    }

    /// A word exactly as long as its room is shown whole; one character more is cut.
    #[test]
    fn a_word_that_fits_exactly_is_whole() {
        assert_eq!(clip_word("abcd", 4), "abcd");
        assert_eq!(clip_word("abcde", 4), "abcd…");
    }

    #[test]
    fn seconds_are_logged_to_a_tenth() {
        assert_eq!(tenths(12.34), 12.3);
        assert_eq!(tenths(12.36), 12.4);
        assert_eq!(tenths(0.04), 0.0);
        assert_eq!(tenths(7.0), 7.0);
    }

    /// Many addresses at once: the global budget bounds the lines; memory stays bounded by
    /// TRACKED_GROUPS; the summary names a few groups and sums up the rest.
    #[test]
    fn many_addresses_share_a_global_budget_and_bounded_memory() {
        let mut limit = LogLimit::new(0.0);
        let mut allowed = 0;
        for i in 0..20_000u32 {
            let ip = IpAddr::from(std::net::Ipv4Addr::from(0x0a00_0000u32 + i));
            allowed += usize::from(limit.allow(ip, f64::from(i) * 1e-5));
        }
        // 0.2 s went by: the global burst and a few lines of its rate.
        assert!((GLOBAL_BURST as usize..GLOBAL_BURST as usize + 10).contains(&allowed), "{allowed}");
        assert!(limit.tracked() <= TRACKED_GROUPS);
        let summary = limit.take_suppressed(1.0);
        let named: u64 = summary.groups.iter().map(|(_, n)| n).sum();
        assert!(summary.groups.len() <= SUMMARY_GROUPS);
        assert_eq!(named + summary.others.1, 20_000 - allowed as u64, "every line left out is counted");
    }

    /// `--log-format json`: every line one object with the fields a log shipper filters on, the
    /// client's text escaped (nothing below U+0020, no DEL, C1 or bidi control left raw), and the
    /// text that follows a colon never part of `event`.
    #[test]
    fn json_lines_are_one_object_each_with_client_text_escaped() {
        use std::sync::{Arc, Mutex};
        #[derive(Clone, Default)]
        struct Capture(Arc<Mutex<Vec<u8>>>);
        impl std::io::Write for Capture {
            fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
                self.0.lock().unwrap().extend_from_slice(buf);
                Ok(buf.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let capture = Capture::default();
        let writer = capture.clone();
        let subscriber =
            tracing_subscriber::fmt().with_writer(move || writer.clone()).event_format(JsonLines).finish();
        let peer: std::net::SocketAddr = "192.0.2.7:5000".parse().unwrap();
        let hostile = "\x1b]0;owned\x07\u{202e}\u{9b}2J\"\\\u{7f}\nfake=line\u{61c}\u{2028}\u{e0041}";
        tracing::subscriber::with_default(subscriber, || {
            tracing::info!(peer = %peer, user = %hostile, seconds = format_args!("{:.1}", 12.34), bytes_out = 4096u64, "disconnected");
            tracing::warn!(peer = %peer, "refused subsystem: {hostile}");
            tracing::info!(players = 3usize, "shutting down");
            tracing::info!(name = "a \"b\"", change = -3i64, seconds = 1.5f64, first = true, "typed");
        });
        let bytes = capture.0.lock().unwrap().clone();
        let text = String::from_utf8(bytes).expect("UTF-8");
        let risky = |c: char| c != '\n' && mazewalk_maze::unseen(c);
        assert!(!text.chars().any(risky), "a raw control character: {text:?}");
        let lines: Vec<serde_json::Value> =
            text.lines().map(|l| serde_json::from_str(l).expect("one JSON object a line")).collect();
        assert_eq!(lines.len(), 4, "{text}");
        let first = &lines[0];
        assert_eq!(first["level"], "info");
        assert_eq!(first["event"], "disconnected");
        assert_eq!(first["address"], "192.0.2.7:5000");
        assert_eq!(first["player"], hostile, "escaped, and read back whole");
        assert_eq!(first["seconds"], "12.3");
        assert_eq!(first["bytes_out"], 4096);
        let time = first["time"].as_str().expect("a time");
        assert!(time.len() >= 20 && time.ends_with('Z') && time.as_bytes()[10] == b'T', "{time}");
        assert_eq!(lines[1]["level"], "warn");
        assert_eq!(lines[1]["event"], "refused_subsystem");
        assert_eq!(lines[1]["message"], format!("refused subsystem: {hostile}"));
        assert_eq!(lines[2]["event"], "shutting_down");
        assert_eq!(lines[2]["address"], serde_json::Value::Null);
        assert_eq!(lines[2]["players"], 3);
        // a field keeps its type: a shipper filters `seconds > 60`, not a string
        let typed = &lines[3];
        assert_eq!((&typed["name"], &typed["change"]), (&"a \"b\"".into(), &(-3).into()));
        assert_eq!((&typed["seconds"], &typed["first"]), (&1.5.into(), &true.into()));
    }

    #[test]
    fn an_event_name_is_the_messages_first_words() {
        assert_eq!(event_name("disconnected"), "disconnected");
        assert_eq!(event_name("refused: every player's slot is taken"), "refused");
        assert_eq!(event_name("log lines suppressed (rate limit)"), "log_lines_suppressed");
        assert_eq!(event_name("the world's winner"), "the_worlds_winner");
        assert_eq!(event_name("refused remote port forwarding: port 80"), "refused_remote_port_forwarding");
        assert_eq!(event_name("dropped 3 malformed messages"), "dropped");
        assert_eq!(event_name(""), "");
    }
}
