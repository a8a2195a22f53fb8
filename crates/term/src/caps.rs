//! Terminal capabilities: colour depth and background-colour erase from the environment, and whether
//! to ask the terminal itself about 24-bit colour. Pure: the caller passes the lookup, e.g.
//! `|k| std::env::var(k).ok()`, and what it learnt from the system's tools ([`ColorFacts`]: terminfo,
//! tmux); a CLI flag overrides the result.
//!
//! Truecolor is decided as Neovim does since 0.10 ([`plan_color_depth`]): `COLORTERM`, then terminfo,
//! then — inside tmux — tmux's own word on its client, else the terminal is asked
//! ([`TRUECOLOR_QUERY`]) while the walk starts at the depth the environment promises; a positive
//! answer ([`Reply::DirectColor`](crate::input::Reply::DirectColor)) raises it to truecolor.

use crate::frame::ColorDepth;

/// The colour depth the environment promises, first match wins:
///
/// | environment | depth |
/// |---|---|
/// | `NO_COLOR` set and non-empty ([no-color.org](https://no-color.org)) | `None` |
/// | `COLORTERM=truecolor` or `24bit`, except inside GNU screen (below) | `TrueColor` |
/// | `TERM=dumb`, a monochrome entry by terminfo's naming (`*-mono`, `*-m`: `xterm-mono`, `linux-m`), or a DEC terminal (`vt` and a digit: `vt52`, `vt100`, `vt102`, `vt220`, `vt320`, `vt420`, `vt525`; terminfo gives none of them `colors`) | `None` |
/// | `TERM` naming a truecolor terminal (`*-direct`, `xterm-kitty`, `alacritty`, `wezterm`, `foot*`, `xterm-ghostty`), or `WT_SESSION` set (Windows Terminal) | `TrueColor` |
/// | `TERM` containing `256color` | `Ansi256` |
/// | `TERM=linux`, `screen`, `ansi` (8 `colors` in terminfo, and bright ones by bold), anything else, or unset | `Ansi16` |
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
    if term == "dumb" || term.ends_with("-mono") || term.ends_with("-m") || dec_terminal(&term) {
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

/// Whether the terminal can show Unicode's block glyphs (`▀` and the rest), by `TERM` and the locale:
///
/// | `TERM`, locale ([`locale_is_utf8`]) | block glyphs |
/// |---|---|
/// | a DEC terminal (`vt` and a digit: `vt100`, `vt102`, `vt220`, …; their fonts are DEC's, with no Unicode) | no: ASCII |
/// | a locale that names no UTF-8 codeset (`LANG=C`, `LC_ALL=POSIX`, `en_US.ISO-8859-1`: the terminal shows each UTF-8 glyph as 3 bytes of mojibake) | no: ASCII |
/// | anything else (`linux`, `screen`, `xterm*`, `dumb`, unset; a UTF-8 locale or none set) | yes |
///
/// (`xterm-mono` is an xterm without colour: its font has the blocks.)
#[must_use]
pub fn detect_block_glyphs(get: impl Fn(&str) -> Option<String>) -> bool {
    !dec_terminal(&get("TERM").unwrap_or_default().to_ascii_lowercase())
        && locale_is_utf8(&get) != Some(false)
}

/// Whether the locale's character set is UTF-8, by tmux's rule: the first of `LC_ALL`, `LC_CTYPE` and
/// `LANG` that is set and not empty decides, and it is UTF-8 where it names the codeset `UTF-8` or
/// `utf8` (in any case: `en_US.UTF-8`, `C.utf8`). `None`: none of the three is set, which says nothing
/// (the walk keeps its default, block glyphs).
///
/// ```
/// use mazewalk_term::caps::locale_is_utf8;
/// let env = |vars: &'static [(&str, &str)]| {
///     move |k: &str| vars.iter().find(|(name, _)| *name == k).map(|(_, v)| v.to_string())
/// };
/// assert_eq!(locale_is_utf8(env(&[("LANG", "en_US.UTF-8")])), Some(true));
/// assert_eq!(locale_is_utf8(env(&[("LC_ALL", "C"), ("LANG", "en_US.UTF-8")])), Some(false));
/// assert_eq!(locale_is_utf8(env(&[("LC_ALL", ""), ("LC_CTYPE", "C.utf8")])), Some(true));
/// assert_eq!(locale_is_utf8(env(&[])), None);
/// ```
#[must_use]
pub fn locale_is_utf8(get: impl Fn(&str) -> Option<String>) -> Option<bool> {
    let locale = ["LC_ALL", "LC_CTYPE", "LANG"].into_iter().find_map(|k| get(k).filter(|v| !v.is_empty()))?;
    let locale = locale.to_ascii_lowercase();
    Some(locale.contains("utf-8") || locale.contains("utf8"))
}

/// A DEC video terminal by terminfo's naming: `vt` and a digit (`vt100`, `vt220-8bit`), not `vte`.
fn dec_terminal(term: &str) -> bool {
    term.strip_prefix("vt").is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_digit()))
}

/// The questions about 24-bit colour, sent once at the start (on the alternate screen, before the first
/// frame, which paints over anything a terminal that does not understand them might show):
///
/// 1. set the background to RGB (1, 2, 3) and ask for the pen back (DECRQSS `m`): a terminal that keeps
///    24-bit colour answers `DCS 1 $ r …48:2…:1:2:3 m ST` (xterm, kitty, foot, Ghostty, iTerm2, VTE ≥
///    0.78, Windows Terminal), one that does not `…48:5:N…`; then reset the pen at once;
/// 2. ask for the terminfo capabilities `RGB` and `Tc` (XTGETTCAP, one query each: xterm drops the rest
///    of a list after a name it does not know): `DCS 1 + r 524742[=…] ST` (xterm, foot, Ghostty,
///    WezTerm, iTerm2), `DCS 1 + r 5463… ST` (kitty).
///
/// Silence or a `0` ("invalid") answer proves nothing (Alacritty, Konsole and tmux show 24-bit colour
/// and answer neither). No device-attributes query here: the one after the first frame fences the
/// answers (a terminal answers in order), see `Session::ask_truecolor` in mazewalk-walk.
pub const TRUECOLOR_QUERY: &[u8] =
    b"\x1b[0m\x1b[48;2;1;2;3m\x1bP$qm\x1b\\\x1b[0m\x1bP+q524742\x1b\\\x1bP+q5463\x1b\\";

/// How far the terminal repeats glyphs on `CSI n b` (REP, ECMA-48), as [`REP_PROBE`] finds out.
/// Ordered: each level repeats what the one below it does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RepLevel {
    /// No REP (GNU screen, a terminal that did not answer): every glyph is written out.
    #[default]
    None,
    /// REP after an ASCII glyph only: tmux (its parser forgets the last character on any UTF-8
    /// one, `input_top_bit_set` in its `input.c`), and xterm before it repeated more than
    /// codepoints below 256.
    Ascii,
    /// REP after any glyph the encoder writes, block glyphs too (xterm today, VTE, kitty, foot,
    /// Alacritty, the `vt100` crate: each keeps the last printed character whatever it is; WezTerm
    /// copies the cell before the cursor).
    Any,
}

/// Whether, and after which glyphs, the terminal repeats a glyph on `CSI n b` (REP, ECMA-48), asked
/// before the first frame (which clears the screen over it), in two questions each answered by a
/// cursor position report (`CSI 6 n`):
///
/// 1. row 2, column 1: a space and `CSI b`: a terminal with REP answers `CSI 2 ; 3 R` (two cells
///    written), one without `CSI 2 ; 2 R`;
/// 2. row 3, column 1: `▀` and `CSI 2 b`: a terminal that repeats a block glyph answers `CSI 3 ; 4 R`
///    (three cells), one that repeats only ASCII (tmux) `CSI 3 ; 2 R`. Two repeats, not one, so that
///    a terminal drawing `▀` two cells wide (East Asian ambiguous width set wide) cannot answer
///    column 4 (it would say 3 without REP, 7 with).
///
/// [`rep_answer`] reads the reports. Rows 2 and 3, not 1: `CSI 1 ; 3 R` is also how xterm sends
/// Alt-F3, and no key is sent as a report of another row.
pub const REP_PROBE: &[u8] = "\x1b[2H \x1b[b\x1b[6n\x1b[3H▀\x1b[2b\x1b[6n".as_bytes();

/// The first of [`REP_PROBE`]'s questions alone (a space repeated), for a screen drawn in ASCII only
/// (the ascii charset: a terminal or font without block glyphs is sent none, not even to ask).
pub const REP_PROBE_ASCII: &[u8] = b"\x1b[2H \x1b[b\x1b[6n";

/// What a cursor position report says in answer to one of [`REP_PROBE`]'s two questions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RepReport {
    /// The space question (row 2): whether a space was repeated.
    Space(bool),
    /// The block question (row 3): whether `▀` was repeated (twice, as asked).
    Block(bool),
}

/// What a cursor position report (1-based `row`, `col`) says in answer to [`REP_PROBE`]: `None` if it
/// is not an answer to it (another row: a key, a screen of one row, a report someone else asked
/// for). Row 2: column 3 yes, 2 no. Row 3: column 4 yes; any other column no (a terminal that
/// does not take `▀` as one glyph one cell wide should not be sent runs of it as REP either).
#[must_use]
pub fn rep_answer(row: u16, col: u16) -> Option<RepReport> {
    match (row, col) {
        (2, 3) => Some(RepReport::Space(true)),
        (2, 2) => Some(RepReport::Space(false)),
        (3, col) => Some(RepReport::Block(col == 4)),
        _ => None,
    }
}

/// What the system's own tools say about the terminal's 24-bit colour, learnt by the caller (the
/// binary runs `infocmp -x` and `tmux display`; a server knows neither about its players).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ColorFacts {
    /// Whether `TERM`'s terminfo entry promises 24-bit colour ([`terminfo_has_truecolor`]); `None`:
    /// not looked up.
    pub terminfo_rgb: Option<bool>,
    /// Inside tmux: whether tmux's client has the `RGB` feature ([`tmux_has_rgb`]); `None`: not asked.
    pub tmux_rgb: Option<bool>,
}

/// The colour depth to start with, and whether to ask the terminal for more ([`TRUECOLOR_QUERY`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ColorPlan {
    /// The depth of the first frame.
    pub depth: ColorDepth,
    /// Whether to ask the terminal: a positive answer raises the depth to truecolor.
    pub ask: bool,
}

/// How deep the colours go and whether to ask the terminal, first match wins (Neovim ≥ 0.10's order,
/// with GNU screen, tmux and consoles that cannot be asked set apart):
///
/// | what | depth | ask |
/// |---|---|---|
/// | `NO_COLOR` set and non-empty | none | no |
/// | `COLORTERM=truecolor` or `24bit`, outside GNU screen | truecolor | no |
/// | in GNU screen (it garbles 24-bit colour) | [`detect_color_depth`]'s | no |
/// | terminfo has `Tc`, `RGB`, or `setrgbf` and `setrgbb` | truecolor | no |
/// | in tmux (`TMUX` set, or `TERM` `tmux*`/`screen*`): tmux's client has `RGB` | truecolor | no |
/// | in tmux otherwise (tmux answers no query, and a DCS query can crash tmux 3.4) | [`detect_color_depth`]'s | no |
/// | [`detect_color_depth`] says truecolor or none | that | no |
/// | `COLORTERM` set to anything else (as Neovim: the environment has spoken) | [`detect_color_depth`]'s | no |
/// | `TERM=linux`, `vt*`, or `TERM_PROGRAM=Apple_Terminal` (may print the question as text) | [`detect_color_depth`]'s | no |
/// | anything else (`xterm-256color` over SSH, most of the time) | [`detect_color_depth`]'s | yes |
#[must_use]
pub fn plan_color_depth(get: impl Fn(&str) -> Option<String>, facts: ColorFacts) -> ColorPlan {
    let known = |depth| ColorPlan { depth, ask: false };
    let env_depth = detect_color_depth(&get);
    if get("NO_COLOR").is_some_and(|v| !v.is_empty()) {
        return known(ColorDepth::None);
    }
    if env_depth == ColorDepth::TrueColor && get("COLORTERM").is_some_and(|v| !v.is_empty()) {
        return known(env_depth); // COLORTERM=truecolor, believed
    }
    if in_gnu_screen(&get) {
        return known(env_depth);
    }
    if facts.terminfo_rgb == Some(true) {
        return known(ColorDepth::TrueColor);
    }
    let term = get("TERM").unwrap_or_default().to_ascii_lowercase();
    if get("TMUX").is_some() || term.starts_with("tmux") || term.starts_with("screen") {
        return known(if facts.tmux_rgb == Some(true) { ColorDepth::TrueColor } else { env_depth });
    }
    let silent_console = term == "linux" || term.starts_with("vt");
    if matches!(env_depth, ColorDepth::TrueColor | ColorDepth::None)
        || get("COLORTERM").is_some_and(|v| !v.is_empty())
        || silent_console
        || get("TERM_PROGRAM").is_some_and(|p| p == "Apple_Terminal")
    {
        return known(env_depth);
    }
    ColorPlan { depth: env_depth, ask: true }
}

/// Whether `infocmp -x`'s description of a terminal promises 24-bit colour: the extended boolean `Tc`
/// or `RGB`, or both strings `setrgbf` and `setrgbb` (what Neovim's TUI looks for). Anything else in
/// the text is ignored, so a partial or garbled description is simply not a promise.
///
/// ```
/// use mazewalk_term::caps::terminfo_has_truecolor;
/// assert!(terminfo_has_truecolor("xterm-direct|xterm with direct-color indexing,\n\tRGB, am,\n"));
/// assert!(!terminfo_has_truecolor("xterm-256color|xterm with 256 colors,\n\tam, bce, colors#0x100,\n"));
/// ```
#[must_use]
pub fn terminfo_has_truecolor(infocmp: &str) -> bool {
    let caps = terminfo_caps(infocmp);
    let boolean = |name: &str| caps.iter().any(|c| c == name);
    boolean("Tc")
        || boolean("RGB")
        || (terminfo_string(&caps, "setrgbf") && terminfo_string(&caps, "setrgbb"))
}

/// Whether `infocmp -x`'s description of a terminal gives it an alternate screen: the string `smcup`
/// (enter full-screen mode). The Linux console, `vt100` and `vt220` have none (their terminals show
/// one screen, and `CSI ? 1049 h` does nothing), xterm, tmux, screen and the rest do. As with
/// [`terminfo_has_truecolor`], a partial or garbled description is no promise.
///
/// ```
/// use mazewalk_term::caps::terminfo_has_alternate_screen;
/// assert!(terminfo_has_alternate_screen("xterm|xterm,\n\tam, smcup=\\E[?1049h\\E[22;0;0t, smam=\\E[?7h,\n"));
/// assert!(!terminfo_has_alternate_screen("linux|Linux console,\n\tam, bce, smam=\\E[?7h, smacs=^N,\n"));
/// ```
#[must_use]
pub fn terminfo_has_alternate_screen(infocmp: &str) -> bool {
    terminfo_string(&terminfo_caps(infocmp), "smcup")
}

/// The capabilities of `infocmp`'s description, one each, trimmed: `am`, `colors#0x100`, `smcup=…`.
fn terminfo_caps(infocmp: &str) -> Vec<String> {
    // Capabilities are separated by commas, one or several a line after the names line; a comma or a
    // backslash inside a string value is escaped (`\,`, `\\`).
    let mut caps: Vec<String> = Vec::new();
    let mut cap = String::new();
    let mut chars = infocmp
        .lines()
        .skip_while(|l| !l.starts_with(char::is_whitespace))
        .flat_map(|l| l.chars().chain(['\n']));
    while let Some(c) = chars.next() {
        match c {
            '\\' => cap.extend([c].into_iter().chain(chars.next())),
            ',' => caps.push(std::mem::take(&mut cap).trim().to_string()),
            c => cap.push(c),
        }
    }
    caps
}

/// Whether `caps` ([`terminfo_caps`]) has the string capability `name` (`name=…`).
fn terminfo_string(caps: &[String], name: &str) -> bool {
    caps.iter().any(|c| c.strip_prefix(name).is_some_and(|rest| rest.starts_with('=')))
}

/// Whether tmux's `#{client_termfeatures}` (features joined by commas) lists `RGB`.
///
/// ```
/// use mazewalk_term::caps::tmux_has_rgb;
/// assert!(tmux_has_rgb("bpaste,ccolour,clipboard,cstyle,focus,RGB,title\n"));
/// assert!(!tmux_has_rgb("bpaste,ccolour,clipboard,cstyle,focus,title"));
/// ```
#[must_use]
pub fn tmux_has_rgb(features: &str) -> bool {
    features.trim().split(',').any(|f| f.trim() == "RGB")
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
    fn block_glyphs_table() {
        let table: &[(&[(&str, &str)], bool)] = &[
            (&[], true),
            (&[("TERM", "xterm-256color")], true),
            (&[("TERM", "xterm-mono")], true),
            (&[("TERM", "linux")], true),
            (&[("TERM", "screen")], true),
            (&[("TERM", "vte-256color")], true),
            (&[("TERM", "vt100")], false),
            (&[("TERM", "vt102")], false),
            (&[("TERM", "vt220")], false),
            (&[("TERM", "vt220-8bit")], false),
            (&[("TERM", "VT320")], false),
            // QA finding 2: a locale that names no UTF-8 codeset gets ASCII; none set, the default
            (&[("TERM", "xterm-256color"), ("LANG", "C")], false),
            (&[("TERM", "xterm-256color"), ("LC_ALL", "C"), ("LANG", "C")], false),
            (&[("TERM", "xterm"), ("LC_ALL", "POSIX")], false),
            (&[("TERM", "xterm"), ("LANG", "en_US.UTF-8")], true),
            (&[("TERM", "vt100"), ("LANG", "en_US.UTF-8")], false),
            (&[("LANG", "")], true),
        ];
        for (vars, blocks) in table {
            assert_eq!(detect_block_glyphs(env(vars)), *blocks, "{vars:?}");
        }
    }

    /// QA finding 3: where terminfo has no `smcup`, the walk clears its last frame on the way out.
    #[test]
    fn terminfo_says_whether_there_is_an_alternate_screen() {
        // (from `infocmp -x vt100`, ncurses 6.4: no smcup)
        let vt100 = "#\tReconstructed via infocmp from file: /lib/terminfo/v/vt100\n\
                     vt100|vt100-am|DEC VT100 (w/advanced video),\n\
                     \tOTbs, am, mc5i, msgr, xenl, xon,\n\
                     \tcols#80, it#8, lines#24, vt#3,\n\
                     \tclear=\\E[H\\E[J$<50>, cr=\\r, csr=\\E[%i%p1%d;%p2%dr,\n\
                     \trmacs=^O, rmam=\\E[?7l, smacs=^N, smam=\\E[?7h, smkx=\\E[?1h\\E=,\n";
        assert!(!terminfo_has_alternate_screen(vt100));
        let xterm = vt100.replace("smam=", "rmcup=\\E[?1049l\\E[23;0;0t, smcup=\\E[?1049h, smam=");
        assert!(terminfo_has_alternate_screen(&xterm));
        for (text, has) in [
            ("x|x,\n\trmcup=\\E[?1049l,\n", false), // leaving is not entering
            ("x|x,\n\tsmcup@,\n", false),           // cancelled
            ("x|x,\n\txsmcup=\\E[?47h,\n", false),  // another name
            ("x|x,\n\tsgr0=\\E[m\\, smcup=\\E7,\n", false), // inside a string, after an escaped comma
            ("x|x,\n\tsgr0=\\E[m, smcup=\\E7,\n", true),
            ("", false),
            ("smcup=\\E[?1049h,", false), // no capability lines at all (garbled)
        ] {
            assert_eq!(terminfo_has_alternate_screen(text), has, "{text:?}");
        }
    }

    /// QA finding 2, tmux's rule: the first of LC_ALL, LC_CTYPE, LANG set (not empty) decides.
    #[test]
    fn the_locale_decides_utf8_by_its_first_set_variable() {
        type Vars = &'static [(&'static str, &'static str)];
        let table: &[(Vars, Option<bool>)] = &[
            (&[], None),
            (&[("LC_ALL", ""), ("LC_CTYPE", ""), ("LANG", "")], None),
            (&[("LANG", "en_US.UTF-8")], Some(true)),
            (&[("LANG", "C.utf8")], Some(true)),
            (&[("LANG", "de_DE.Utf-8@euro")], Some(true)),
            (&[("LANG", "C")], Some(false)),
            (&[("LANG", "POSIX")], Some(false)),
            (&[("LANG", "en_US.ISO-8859-1")], Some(false)),
            (&[("LANG", "en_US")], Some(false)),
            (&[("LANG", "utf")], Some(false)),
            // LC_ALL over LC_CTYPE over LANG
            (&[("LC_ALL", "C"), ("LC_CTYPE", "en_US.UTF-8"), ("LANG", "en_US.UTF-8")], Some(false)),
            (&[("LC_ALL", "en_US.UTF-8"), ("LC_CTYPE", "C"), ("LANG", "C")], Some(true)),
            (&[("LC_CTYPE", "C"), ("LANG", "en_US.UTF-8")], Some(false)),
            (&[("LC_CTYPE", "en_US.UTF-8"), ("LANG", "C")], Some(true)),
            // an empty one is not set: the next decides
            (&[("LC_ALL", ""), ("LC_CTYPE", "C"), ("LANG", "en_US.UTF-8")], Some(false)),
            (&[("LC_ALL", ""), ("LANG", "C.UTF-8")], Some(true)),
            // other LC_* say nothing of the character set
            (&[("LC_MESSAGES", "C"), ("LANG", "en_US.UTF-8")], Some(true)),
        ];
        for (vars, utf8) in table {
            assert_eq!(locale_is_utf8(env(vars)), *utf8, "{vars:?}");
        }
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
            // DEC terminals: terminfo (`infocmp -1 vt100 | grep colors`) gives them no colours
            (&[("TERM", "vt100")], None),
            (&[("TERM", "vt102")], None),
            (&[("TERM", "vt220")], None),
            (&[("TERM", "VT52")], None),
            (&[("TERM", "vt100"), ("COLORTERM", "truecolor")], TrueColor), // COLORTERM is explicit
            (&[("TERM", "vte")], Ansi16),                                  // GNOME's VTE, not a DEC terminal
            (&[("TERM", "vte-256color")], Ansi256),
            (&[("TERM", "ansi")], Ansi16),
            (&[("TERM", "screen")], Ansi16),
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

    // issue #33: truecolor wherever the terminal can show it, decided as Neovim does.
    #[test]
    fn color_plan_table() {
        use ColorDepth::*;
        let none = ColorFacts::default();
        let terminfo = ColorFacts { terminfo_rgb: Some(true), ..none };
        let no_terminfo = ColorFacts { terminfo_rgb: Some(false), ..none };
        let tmux_rgb = ColorFacts { tmux_rgb: Some(true), ..none };
        let tmux_plain = ColorFacts { tmux_rgb: Some(false), terminfo_rgb: Some(false) };
        let ask = |depth| ColorPlan { depth, ask: true };
        let known = |depth| ColorPlan { depth, ask: false };
        type Vars<'a> = &'a [(&'a str, &'a str)];
        let table: &[(Vars, ColorFacts, ColorPlan)] = &[
            // over SSH: TERM only, no COLORTERM: ask
            (&[("TERM", "xterm-256color")], none, ask(Ansi256)),
            (&[("TERM", "xterm-256color")], no_terminfo, ask(Ansi256)),
            (&[("TERM", "xterm")], none, ask(Ansi16)),
            (&[("TERM", "xterm-256color"), ("COLORTERM", "")], none, ask(Ansi256)),
            // COLORTERM decides, either way
            (&[("TERM", "xterm-256color"), ("COLORTERM", "truecolor")], none, known(TrueColor)),
            (&[("TERM", "xterm-256color"), ("COLORTERM", "24bit")], no_terminfo, known(TrueColor)),
            (&[("TERM", "xterm-256color"), ("COLORTERM", "256")], none, known(Ansi256)),
            (&[("TERM", "xterm-256color"), ("COLORTERM", "256")], terminfo, known(TrueColor)),
            // terminfo
            (&[("TERM", "xterm-256color")], terminfo, known(TrueColor)),
            (&[("TERM", "xterm-direct")], none, known(TrueColor)),
            (&[("TERM", "xterm-kitty")], none, known(TrueColor)),
            // NO_COLOR and monochrome: never asked
            (&[("TERM", "xterm-256color"), ("NO_COLOR", "1")], terminfo, known(None)),
            (&[("TERM", "xterm-mono")], none, known(None)),
            (&[("TERM", "dumb")], none, known(None)),
            // tmux: its client's features, never the terminal
            (&[("TERM", "tmux-256color"), ("TMUX", "/tmp/t,1,0")], tmux_rgb, known(TrueColor)),
            (&[("TERM", "tmux-256color"), ("TMUX", "/tmp/t,1,0")], tmux_plain, known(Ansi256)),
            (&[("TERM", "screen-256color"), ("TMUX", "/tmp/t,1,0")], none, known(Ansi256)),
            (&[("TERM", "xterm-256color"), ("TMUX", "/tmp/t,1,0")], none, known(Ansi256)),
            // a tmux over SSH (TMUX is not forwarded): not asked either
            (&[("TERM", "tmux-256color")], none, known(Ansi256)),
            (&[("TERM", "screen")], none, known(Ansi16)),
            // GNU screen garbles 24-bit colour whatever terminfo says
            (&[("TERM", "screen.xterm-256color"), ("COLORTERM", "truecolor")], terminfo, known(Ansi256)),
            (&[("TERM", "xterm-256color"), ("STY", "1.pts-0.host")], terminfo, known(Ansi256)),
            // consoles that may print the question
            (&[("TERM", "linux")], none, known(Ansi16)),
            (&[("TERM", "vt220")], none, known(None)), // (no colours at all: a DEC terminal)
            (&[("TERM", "xterm-256color"), ("TERM_PROGRAM", "Apple_Terminal")], none, known(Ansi256)),
        ];
        for (vars, facts, want) in table {
            assert_eq!(plan_color_depth(env(vars), *facts), *want, "{vars:?} {facts:?}");
        }
    }

    #[test]
    fn terminfo_promises_truecolor_by_tc_rgb_or_both_rgb_strings() {
        // `infocmp -x -1` and the default layout (several capabilities a line)
        let direct = "#\tReconstructed via infocmp from file: /usr/share/terminfo/x/xterm-direct\nxterm-direct|xterm with direct-color indexing,\n\tRGB,\n\tam,\n\tcolors#0x1000000,\n";
        assert!(terminfo_has_truecolor(direct));
        let kitty = "xterm-kitty|KovIdTTY,\n\tTc, am, ccc,\n\tsetrgbb=\\E[48\\:2\\:%p1%d\\:%p2%d\\:%p3%dm,\n\tsetrgbf=\\E[38\\:2\\:%p1%d\\:%p2%d\\:%p3%dm,\n";
        assert!(terminfo_has_truecolor(kitty));
        let strings_only =
            "x|x,\n\tsetrgbb=\\E[48;2;%p1%d;%p2%d;%p3%dm, setrgbf=\\E[38;2;%p1%d;%p2%d;%p3%dm,\n";
        assert!(terminfo_has_truecolor(strings_only));
        let one_string = "x|x,\n\tsetrgbf=\\E[38;2;%p1%d;%p2%d;%p3%dm,\n";
        assert!(!terminfo_has_truecolor(one_string));
        let plain = "xterm-256color|xterm with 256 colors,\n\tam, bce, ccc, km, mc5i,\n\tcolors#0x100, cols#80,\n\tsetab=\\E[%?%p1%{8}%<%t4%p1%d%e%p1%{16}%<%t10%p1%{8}%-%d%e48;5;%p1%d%;m,\n";
        assert!(!terminfo_has_truecolor(plain));
        // the names line is not a capability: a terminal named "RGB" promises nothing
        assert!(!terminfo_has_truecolor("RGB|Tc|a terminal,\n\tam,\n"));
        assert!(!terminfo_has_truecolor(""));
        assert!(!terminfo_has_truecolor("infocmp: couldn't open terminfo file"));
        // a value that merely mentions a name
        assert!(!terminfo_has_truecolor("x|x,\n\tuser1=RGB\\,Tc,\n"));
    }

    // issue #42: the three outcomes of the REP probe, read from its two reports.
    #[test]
    fn rep_reports_tell_no_rep_ascii_only_and_any_glyph() {
        use RepReport::{Block, Space};
        // (space report, block report) as each kind of terminal answers → what each says
        let table = [
            ((2, 2), (3, 2), "no REP (GNU screen)", Space(false), Block(false)),
            ((2, 3), (3, 2), "REP after ASCII only (tmux)", Space(true), Block(false)),
            ((2, 3), (3, 4), "REP after any glyph (xterm, VTE, kitty…)", Space(true), Block(true)),
            ((2, 2), (3, 3), "no REP, `▀` two cells wide", Space(false), Block(false)),
            ((2, 3), (3, 7), "REP, `▀` two cells wide", Space(true), Block(false)),
        ];
        for ((sr, sc), (br, bc), what, space, block) in table {
            assert_eq!(rep_answer(sr, sc), Some(space), "{what}");
            assert_eq!(rep_answer(br, bc), Some(block), "{what}");
        }
        // Not answers: row 1 (xterm's Alt-F3 is `CSI 1 ; 3 R`), other rows, other columns of row 2.
        for (row, col) in [(1, 3), (1, 4), (1, 2), (2, 1), (2, 4), (4, 4), (0, 0), (u16::MAX, 4)] {
            assert_eq!(rep_answer(row, col), None, "({row}, {col})");
        }
        assert!(RepLevel::None < RepLevel::Ascii && RepLevel::Ascii < RepLevel::Any);
        assert_eq!(RepLevel::default(), RepLevel::None);
        // Two reports asked, rows 2 and 3, nothing on row 1.
        assert_eq!(REP_PROBE.windows(4).filter(|w| *w == b"\x1b[6n").count(), 2);
        assert!(REP_PROBE.starts_with(b"\x1b[2H") && REP_PROBE.windows(4).any(|w| w == b"\x1b[3H"));
    }

    #[test]
    fn tmux_features_list_rgb_or_not() {
        assert!(tmux_has_rgb("RGB"));
        assert!(tmux_has_rgb("256,RGB,bpaste"));
        assert!(!tmux_has_rgb(""));
        assert!(!tmux_has_rgb("256,bpaste,RGBX"));
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
