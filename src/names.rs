//! The names of the library's choices as the CLI and the maze files spell them (`half`, `256`,
//! `orthographic`…): one table per enum, one parser, one typed error.
//!
//! ```
//! use mazewalk::frame::ColorDepth;
//! assert_eq!("256".parse::<ColorDepth>(), Ok(ColorDepth::Ansi256));
//! assert_eq!(ColorDepth::Ansi256.to_string(), "256");
//! let err = "257".parse::<ColorDepth>().unwrap_err();
//! assert_eq!(err.to_string(), "unknown colour depth `257` (expected none, 16, 256 or truecolor)");
//! ```

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
    /// What was given, quoted safely ([`crate::maze::quote`]: at most 40 characters, controls escaped).
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
        UnknownName { what: T::WHAT, found: crate::maze::quote(s), expected }
    })
}

/// Implements [`Named`], `FromStr` (with [`UnknownName`]) and `Display` (the canonical name) for an
/// enum from its table of names, canonical first for each value.
macro_rules! named {
    ($ty:ty, $what:literal, [$(($name:literal, $value:expr)),+ $(,)?]) => {
        impl $crate::names::Named for $ty {
            const WHAT: &'static str = $what;
            const NAMES: &'static [(&'static str, $ty)] = &[$(($name, $value)),+];
        }

        impl std::str::FromStr for $ty {
            type Err = $crate::names::UnknownName;
            fn from_str(s: &str) -> Result<$ty, $crate::names::UnknownName> {
                $crate::names::parse(s)
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str($crate::names::Named::name(*self))
            }
        }
    };
}
pub(crate) use named;
