//! The names of mazewalk's choices as its command line and maze files spell them (`half`, `256`,
//! `orthographic`…): one table per enum ([`named!`]), one parser, one typed error; and [`quote`], the
//! one way a message shows text it was handed (a file's contents, a flag's value, a player's name),
//! with [`escape_json`] its counterpart for JSON lines; both escape the characters of [`unseen`].
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

/// [`quote`] with another limit: `s` with the characters of [`unseen`] escaped, and at most `max`
/// characters of that (escapes included, so the result is bounded whatever `s` holds), then `…`.
/// The one escaping of untrusted text on a terminal: messages ([`quote`]) and the server's log lines
/// (each with its own limit) both use it.
#[must_use]
pub fn quote_within(s: &str, max: usize) -> String {
    let mut out = String::with_capacity(s.len().min(4 * max.min(1024)));
    let mut shown = 0usize;
    for c in s.chars() {
        let escaped = unseen(c);
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

/// Whether `c` is a character a reader would not see as what it is, and so is escaped wherever
/// untrusted text is shown: a control (C0, DEL, C1: escape sequences, CR and LF that split a line,
/// U+009B that a terminal takes for CSI), a line or paragraph separator (U+2028, U+2029), or any
/// formatting character (Unicode's Cf: the bidi marks, embeddings, overrides and isolates that
/// reorder text, U+061C among them; zero-width and invisible ones such as U+200B, U+00AD, U+2060,
/// U+FEFF and the tag characters U+E0000..U+E007F that hide text).
#[must_use]
pub fn unseen(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            // Cf and Zl / Zp, as of Unicode 15 (U+2065, unassigned, with its neighbours)
            '\u{ad}'
                | '\u{600}'..='\u{605}'
                | '\u{61c}'
                | '\u{6dd}'
                | '\u{70f}'
                | '\u{890}'..='\u{891}'
                | '\u{8e2}'
                | '\u{180e}'
                | '\u{200b}'..='\u{200f}'
                | '\u{2028}'..='\u{202e}'
                | '\u{2060}'..='\u{206f}'
                | '\u{feff}'
                | '\u{fff9}'..='\u{fffb}'
                | '\u{110bd}'
                | '\u{110cd}'
                | '\u{13430}'..='\u{1343f}'
                | '\u{1bca0}'..='\u{1bca3}'
                | '\u{1d173}'..='\u{1d17a}'
                | '\u{e0001}'
                | '\u{e0020}'..='\u{e007f}'
        )
}

/// Whether the UTF-8 text `utf8` may hold a character of [`unseen`], from its bytes alone: never
/// `false` when it does, and `false` for printable ASCII and for the block, box and sextant
/// glyphs a frame is drawn in (U+2500..U+25FF, U+1FB00..), so that a frame's line is looked at no
/// closer (red-team pass 17: a cast's events, decoded character by character, took twice the time).
#[must_use]
pub fn may_hold_unseen(utf8: &[u8]) -> bool {
    // the first two bytes of each range of `unseen` past ASCII (the last byte alone: a C0 or DEL)
    utf8.last().is_some_and(|&b| b < 0x20 || b == 0x7f)
        || utf8.windows(2).any(|pair| match pair[0] {
            0x00..=0x1f | 0x7f | 0xd8 | 0xdb | 0xdc | 0xe0 | 0xe1 | 0xef => true,
            0xc2 => pair[1] <= 0x9f || pair[1] == 0xad,
            0xe2 => pair[1] <= 0x81,
            0xf0 => matches!(pair[1], 0x91 | 0x93 | 0x9b | 0x9d),
            0xf3 => pair[1] == 0xa0,
            _ => false,
        })
}

/// `json` (JSON text: a log line, a cast's line) with every character of [`unseen`] that is still
/// raw written as `\uXXXX` (a pair of them past U+FFFF), so that a terminal showing the line (`tail
/// -f`, `head` of a cast) acts on none of them. A JSON writer escapes only the controls below U+0020,
/// and, `json` being compact (nothing but spaces between its tokens), the others can only be inside
/// its strings, where the escape means the same character: the text parses to the same values.
#[must_use]
pub fn escape_json(json: &str) -> String {
    use std::fmt::Write as _;
    if !may_hold_unseen(json.as_bytes()) || !json.chars().any(unseen) {
        return json.to_owned();
    }
    let mut out = String::with_capacity(json.len() + 16);
    let mut units = [0u16; 2];
    for c in json.chars() {
        if unseen(c) {
            for unit in c.encode_utf16(&mut units) {
                let _ = write!(out, "\\u{unit:04x}"); // (writing to a String cannot fail)
            }
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

    /// Red-team pass 17: a bidi mark other than the escaped few (U+061C), a line separator, the soft
    /// hyphen and the invisible tag characters were shown raw (`facing \u{e0041}north` read as
    /// "facing `north`: expected east, north, west or south").
    #[test]
    fn every_formatting_character_and_separator_is_escaped() {
        assert_eq!(quote("a\u{61c}b"), "a\\u{61c}b");
        assert_eq!(quote("a\u{2028}b\u{2029}"), "a\\u{2028}b\\u{2029}");
        assert_eq!(quote("\u{e0041}\u{e0042}north"), "\\u{e0041}\\u{e0042}north");
        assert_eq!(quote("soft\u{ad}hy\u{180e}x\u{fff9}"), "soft\\u{ad}hy\\u{180e}x\\u{fff9}");
        assert_eq!(quote("\u{9b}31m"), "\\u{9b}31m", "C1's CSI");
        // what a reader sees as itself is left alone: letters, marks, emoji, a space
        assert_eq!(quote("ünï cødé 漢字 e\u{301} 🙂"), "ünï cødé 漢字 e\u{301} 🙂");
        for c in ['\u{200d}', '\u{2066}', '\u{2069}', '\u{feff}', '\u{e0001}', '\u{e007f}', '\u{1d173}'] {
            assert!(unseen(c), "{:x}", u32::from(c));
        }
        for c in ['a', ' ', 'é', '\u{301}', '\u{2027}', '\u{2030}', '\u{e0080}', '\u{fffc}'] {
            assert!(!unseen(c), "{:x}", u32::from(c));
        }
    }

    /// The look at bytes misses no character of [`unseen`], whatever comes before or after it, and
    /// passes a frame's glyphs.
    #[test]
    fn a_look_at_the_bytes_misses_no_unseen_character() {
        let mut buf = [0u8; 4];
        for c in (0..=0x10_ffff).filter_map(char::from_u32).filter(|&c| unseen(c)) {
            let one = c.encode_utf8(&mut buf).as_bytes().to_vec();
            for text in [one.clone(), [b"a".as_slice(), &one, "▀".as_bytes()].concat()] {
                assert!(may_hold_unseen(&text), "U+{:04X} in {text:?}", u32::from(c));
            }
        }
        let glyphs: String = ('\u{2500}'..='\u{25ff}').chain('\u{1fb00}'..='\u{1fbff}').collect();
        assert!(!may_hold_unseen(format!("[0.1, \"o\", \"\\u001b[31m{glyphs} ~\"]").as_bytes()));
    }

    /// JSON text keeps its values and loses every raw character of [`unseen`]: one `\\uXXXX` each, a
    /// surrogate pair past U+FFFF.
    #[test]
    fn json_text_has_its_unseen_characters_escaped_and_means_the_same() {
        let hostile =
            "\x1b]52;c;cHduZWQ=\x07\u{9b}31m\u{202e}gnp\u{61c}\u{2028}\r\nfake \"q\" \\ \u{7f}\u{e0041}é🙂";
        let json = serde_json::json!({ "TERM": hostile, "n": [1, "\u{85}"] }).to_string();
        assert!(json.chars().any(unseen), "the premise: serde_json leaves some raw: {json}");
        let escaped = escape_json(&json);
        assert!(!escaped.chars().any(unseen), "{escaped}");
        assert!(escaped.contains("\\u009b31m\\u202egnp\\u061c\\u2028"), "{escaped}");
        assert!(escaped.contains("\\udb40\\udc41é🙂"), "a tag character as a pair: {escaped}");
        let back: serde_json::Value = serde_json::from_str(&escaped).expect("JSON still");
        assert_eq!(back["TERM"], hostile);
        assert_eq!(back["n"][1], "\u{85}");
        assert_eq!(escape_json("{\"a\": \"b c\"}"), "{\"a\": \"b c\"}", "plain text is unchanged");
    }
}
