//! Terminal capabilities from the environment: colour depth and background-colour erase. Pure: the
//! caller passes the lookup, e.g. `|k| std::env::var(k).ok()`; a CLI flag overrides the result.

use crate::frame::ColorDepth;

/// The colour depth the environment promises, first match wins:
///
/// | environment | depth |
/// |---|---|
/// | `NO_COLOR` set and non-empty ([no-color.org](https://no-color.org)) | `None` |
/// | `COLORTERM=truecolor` or `24bit`, except inside GNU screen (below) | `TrueColor` |
/// | `TERM=dumb`, or a monochrome entry by terminfo's naming (`*-mono`, `*-m`: `xterm-mono`, `linux-m`) | `None` |
/// | `TERM` naming a truecolor terminal (`*-direct`, `xterm-kitty`, `alacritty`, `wezterm`, `foot*`, `xterm-ghostty`), or `WT_SESSION` set (Windows Terminal) | `TrueColor` |
/// | `TERM` containing `256color` | `Ansi256` |
/// | `TERM=linux`, `vt*`, anything else, or unset | `Ansi16` |
///
/// GNU screen 4 keeps the outer terminal's `COLORTERM` in its windows but cannot show 24-bit colour
/// (it garbles it), so there `COLORTERM` is not believed ([`in_gnu_screen`]). The `TERM` names matter
/// over SSH, which forwards `TERM` but not `COLORTERM`. Unknown or unset
/// falls back to 16 colours: every colour terminal has them, and a wrong guess upwards shows garbage
/// colours while a wrong guess downwards only shows fewer (`--color` raises it).
#[must_use]
pub fn detect_color_depth(get: impl Fn(&str) -> Option<String>) -> ColorDepth {
    if get("NO_COLOR").is_some_and(|v| !v.is_empty()) {
        return ColorDepth::None;
    }
    if get("COLORTERM").is_some_and(|v| matches!(v.to_ascii_lowercase().as_str(), "truecolor" | "24bit"))
        && !in_gnu_screen(&get)
    {
        return ColorDepth::TrueColor;
    }
    let term = get("TERM").unwrap_or_default().to_ascii_lowercase();
    const TRUECOLOR_TERMS: [&str; 5] = ["xterm-kitty", "alacritty", "wezterm", "xterm-ghostty", "contour"];
    if term == "dumb" || term.ends_with("-mono") || term.ends_with("-m") {
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
    !(in_gnu_screen(&get) || (term.starts_with("screen") && get("TMUX").is_none()))
}

/// Whether the program runs in a GNU screen window, on positive evidence: screen's own `STY` outside
/// tmux, or a `TERM` of screen's `screen.<outer terminal>` form (tmux never uses it), which also tells
/// a GNU screen started inside tmux (where `TMUX` is inherited) from tmux itself.
fn in_gnu_screen(get: impl Fn(&str) -> Option<String>) -> bool {
    let term = get("TERM").unwrap_or_default();
    term.starts_with("screen.") || (get("STY").is_some() && get("TMUX").is_none())
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
            (&[("TERM", "xterm-mono")], None),
            (&[("TERM", "linux-m")], None),
            (&[("TERM", "xterm-mono"), ("COLORTERM", "truecolor")], TrueColor), // COLORTERM is explicit
            (&[("TERM", "vt100")], Ansi16),
            (&[("TERM", "xterm")], Ansi16),
            // GNU screen keeps COLORTERM but garbles 24-bit colour; tmux shows it.
            (&[("COLORTERM", "truecolor"), ("TERM", "screen.xterm-256color")], Ansi256),
            (&[("COLORTERM", "truecolor"), ("TERM", "screen"), ("STY", "12.pts-0.host")], Ansi16),
            (
                &[("COLORTERM", "truecolor"), ("TERM", "screen.xterm-256color"), ("TMUX", "/tmp/t,1,0")],
                Ansi256,
            ),
            (&[("COLORTERM", "truecolor"), ("TERM", "screen-256color"), ("TMUX", "/tmp/t,1,0")], TrueColor),
            (
                &[("COLORTERM", "truecolor"), ("TERM", "tmux-256color"), ("STY", "1.x"), ("TMUX", "/t,1,0")],
                TrueColor,
            ),
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
        // GNU screen started inside tmux: TMUX is inherited, the TERM is screen's own form.
        assert!(!detect_bce(env(&[("TERM", "screen.xterm-256color"), ("TMUX", "/tmp/tmux-0/default,1,0")])));
        assert!(!detect_bce(env(&[("TERM", "xterm-256color"), ("STY", "12.pts-0.host")])));
    }
}
