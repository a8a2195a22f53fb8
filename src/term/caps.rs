//! Terminal capabilities from the environment: colour depth and background-colour erase. Pure: the
//! caller passes the lookup, e.g. `|k| std::env::var(k).ok()`; a CLI flag overrides the result.

use crate::frame::ColorDepth;

/// The colour depth the environment promises, first match wins:
///
/// | environment | depth |
/// |---|---|
/// | `NO_COLOR` set and non-empty ([no-color.org](https://no-color.org)) | `None` |
/// | `COLORTERM=truecolor` or `24bit` | `TrueColor` |
/// | `TERM=dumb` | `None` |
/// | `TERM` naming a truecolor terminal (`*-direct`, `xterm-kitty`, `alacritty`, `wezterm`, `foot*`, `xterm-ghostty`), or `WT_SESSION` set (Windows Terminal) | `TrueColor` |
/// | `TERM` containing `256color` | `Ansi256` |
/// | `TERM=linux`, `vt*`, anything else, or unset | `Ansi16` |
///
/// The `TERM` names matter over SSH, which forwards `TERM` but not `COLORTERM`. Unknown or unset
/// falls back to 16 colours: every colour terminal has them, and a wrong guess upwards shows garbage
/// colours while a wrong guess downwards only shows fewer (`--color` raises it).
#[must_use]
pub fn detect_color_depth(get: impl Fn(&str) -> Option<String>) -> ColorDepth {
    if get("NO_COLOR").is_some_and(|v| !v.is_empty()) {
        return ColorDepth::None;
    }
    if get("COLORTERM").is_some_and(|v| matches!(v.to_ascii_lowercase().as_str(), "truecolor" | "24bit")) {
        return ColorDepth::TrueColor;
    }
    let term = get("TERM").unwrap_or_default().to_ascii_lowercase();
    const TRUECOLOR_TERMS: [&str; 5] = ["xterm-kitty", "alacritty", "wezterm", "xterm-ghostty", "contour"];
    if term == "dumb" {
        ColorDepth::None
    } else if term.ends_with("-direct")
        || term.starts_with("foot")
        || TRUECOLOR_TERMS.contains(&term.as_str())
        || get("WT_SESSION").is_some()
    {
        ColorDepth::TrueColor
    } else if term.contains("256color") {
        ColorDepth::Ansi256
    } else {
        ColorDepth::Ansi16
    }
}

/// Whether erasing fills with the current background colour (BCE), for
/// [`Encoder::set_bce`](super::encoder::Encoder::set_bce). True everywhere except GNU screen (`TERM`
/// `screen*` outside tmux), whose `defbce` is off by default. tmux also uses `screen*` names, but sets
/// `TMUX` and does BCE.
#[must_use]
pub fn detect_bce(get: impl Fn(&str) -> Option<String>) -> bool {
    let term = get("TERM").unwrap_or_default();
    !(term.starts_with("screen") && get("TMUX").is_none())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| vars.iter().find(|(name, _)| *name == k).map(|(_, v)| (*v).to_owned())
    }

    #[test]
    fn color_depth_table() {
        use ColorDepth::*;
        let table: &[(&[(&str, &str)], ColorDepth)] = &[
            (&[], Ansi16),
            (&[("NO_COLOR", "1"), ("COLORTERM", "truecolor")], None),
            (&[("NO_COLOR", ""), ("COLORTERM", "truecolor")], TrueColor), // empty NO_COLOR: not set
            (&[("COLORTERM", "truecolor"), ("TERM", "xterm")], TrueColor),
            (&[("COLORTERM", "24bit"), ("TERM", "screen")], TrueColor),
            (&[("COLORTERM", "yes"), ("TERM", "xterm")], Ansi16),
            (&[("TERM", "xterm-256color")], Ansi256),
            (&[("TERM", "tmux-256color")], Ansi256),
            (&[("TERM", "screen-256color")], Ansi256),
            (&[("TERM", "xterm-direct")], TrueColor),
            (&[("TERM", "xterm-kitty")], TrueColor),
            (&[("TERM", "alacritty")], TrueColor),
            (&[("TERM", "foot-extra")], TrueColor),
            (&[("TERM", "xterm"), ("WT_SESSION", "abc")], TrueColor),
            (&[("TERM", "dumb")], None),
            (&[("TERM", "dumb"), ("COLORTERM", "truecolor")], TrueColor), // COLORTERM is explicit
            (&[("TERM", "linux")], Ansi16),
            (&[("TERM", "vt100")], Ansi16),
            (&[("TERM", "xterm")], Ansi16),
        ];
        for (vars, want) in table {
            assert_eq!(detect_color_depth(env(vars)), *want, "{vars:?}");
        }
    }

    #[test]
    fn bce_is_off_only_in_gnu_screen() {
        assert!(detect_bce(env(&[("TERM", "xterm-256color")])));
        assert!(detect_bce(env(&[])));
        assert!(!detect_bce(env(&[("TERM", "screen-256color")])));
        assert!(detect_bce(env(&[("TERM", "screen-256color"), ("TMUX", "/tmp/tmux-0/default,1,0")])));
    }
}
