//! The names of mazewalk's choices as its command line and maze files spell them (`half`, `256`,
//! `orthographic`…): one table per enum ([`named!`]), one parser, one typed error; and [`quote`], the
//! one way a message shows text it was handed (a file's contents, a flag's value, a player's name).
//!
//! ```
//! #[derive(Clone, Copy, Debug, PartialEq)]
//! enum Depth { None, Ansi256 }
//! mazewalk_names::named!(Depth, "colour depth", [("none", Depth::None), ("256", Depth::Ansi256)]);
//!
//! assert_eq!("256".parse::<Depth>(), Ok(Depth::Ansi256));
//! assert_eq!(Depth::Ansi256.to_string(), "256");
//! let err = "257".parse::<Depth>().unwrap_err();
//! assert_eq!(err.to_string(), "unknown colour depth `257` (expected none or 256)");
//! ```

#![forbid(unsafe_code)]

/// An enum whose values have names: the first name of each value is how it is written; any other is
/// an alias that parses to it.
pub trait Named: Sized + Copy + PartialEq + 'static {
    /// What the values are, for messages ("colour depth").
    const WHAT: &'static str;
    /// Every name, canonical first for each value.
    const NAMES: &'static [(&'static str, Self)];

    /// The canonical name.
    fn name(self) -> &'static str {
        Self::NAMES.iter().find(|(_, v)| *v == self).map_or("?", |(n, _)| n)
    }
}

/// A name that is none of a [`Named`] enum's.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {what} `{found}` (expected {expected})")]
pub struct UnknownName {
    /// What was asked for ("charset").
    pub what: &'static str,
    /// What was given, quoted safely ([`quote`]: at most 40 characters, controls escaped).
    pub found: String,
    /// The canonical names, as a list for people ("a, b or c").
    pub expected: String,
}

/// Parses `s` as one of `T`'s names.
///
/// # Errors
/// [`UnknownName`] when it is none of them.
pub fn parse<T: Named>(s: &str) -> Result<T, UnknownName> {
    T::NAMES.iter().find(|(n, _)| *n == s).map(|&(_, v)| v).ok_or_else(|| {
        let mut canonical: Vec<&str> = Vec::new();
        for (n, v) in T::NAMES {
            if T::NAMES.iter().find(|(_, w)| w == v).is_some_and(|(first, _)| first == n) {
                canonical.push(n);
            }
        }
        let expected = match canonical.split_last() {
            Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
            _ => canonical.join(""),
        };
        UnknownName { what: T::WHAT, found: quote(s), expected }
    })
}

/// Implements [`Named`], `FromStr` (with [`UnknownName`]) and `Display` (the canonical name) for an
/// enum from its table of names, canonical first for each value.
#[macro_export]
macro_rules! named {
    ($ty:ty, $what:literal, [$(($name:literal, $value:expr)),+ $(,)?]) => {
        impl $crate::Named for $ty {
            const WHAT: &'static str = $what;
            const NAMES: &'static [(&'static str, $ty)] = &[$(($name, $value)),+];
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::UnknownName;
            fn from_str(s: &str) -> Result<$ty, $crate::UnknownName> {
                $crate::parse(s)
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str($crate::Named::name(*self))
            }
        }
    };
}

/// Most characters of a piece of text a message quotes; longer pieces end in `…`.
pub const QUOTE_CHARS: usize = 40;

/// A piece of untrusted text (a file's, a flag's, a client's) as a message shows it: at most [`QUOTE_CHARS`] characters (escapes included) and an ellipsis,
/// control and formatting characters (escape sequences, NUL, bidi overrides) escaped as `\u{1b}`.
#[must_use]
pub fn quote(s: &str) -> String {
    quote_within(s, QUOTE_CHARS)
}

/// A path as a message shows it: control characters escaped, at any length.
#[must_use]
pub fn quote_path(s: &str) -> String {
    quote_within(s, usize::MAX)
}

/// [`quote`] with another limit: `s` with control and formatting characters escaped, and at most
/// `max` characters of that (escapes included, so the result is bounded whatever `s` holds), then
/// `…`. The one escaping of untrusted text: messages ([`quote`]) and the server's log lines (each
/// with its own limit) both use it.
#[must_use]
pub fn quote_within(s: &str, max: usize) -> String {
    let mut out = String::with_capacity(s.len().min(4 * max.min(1024)));
    let mut shown = 0usize;
    for c in s.chars() {
        // Cc controls, plus Cf formatting characters that reorder or hide text (U+200B..U+206F, BOM)
        let escaped = c.is_control()
            || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2060}'..='\u{206f}' | '\u{feff}');
        let len = if escaped { c.escape_default().count() } else { 1 };
        if shown.saturating_add(len) > max {
            out.push('…');
            break;
        }
        shown += len;
        if escaped {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quote_bounds_and_escapes() {
        assert_eq!(quote("abc"), "abc");
        assert_eq!(quote("\x1b]0;pwned\x07"), "\\u{1b}]0;pwned\\u{7}");
        assert_eq!(quote("a\0b"), "a\\u{0}b");
        let long = "x".repeat(10_000_000);
        assert_eq!(quote(&long), format!("{}…", "x".repeat(QUOTE_CHARS)));
        assert_eq!(quote("\u{202e}evil"), "\\u{202e}evil");
        // The escapes count against the limit: the result is bounded whatever the input holds.
        let escapes = "\x1b".repeat(1000);
        assert_eq!(quote(&escapes), format!("{}…", "\\u{1b}".repeat(QUOTE_CHARS / 6)));
        assert_eq!(quote_within("\x1b[2J", 8), "\\u{1b}[2…");
        assert_eq!(quote_within("abc", 3), "abc");
    }
}
