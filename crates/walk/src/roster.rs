//! The player list of a served maze (`Tab`): who is in, each with the label and colour they are drawn
//! in (in the view and on the map), how long they have been in the maze and their best time to the
//! exit. A box of its own over the view, centred above the HUD; pure, tested as text.
//!
//! ```text
//!  Players: 3                 Tab closes
//!
//!  A  alice             12:03    1:02.5
//!  B  bob (you)          3:40         -
//!  C  carol              0:12         -
//! ```

use mazewalk_term::frame::{Cell, Color, ColorDepth, Frame};

use crate::clock::clock_text;
use crate::overlay::{Style, fit_line};

/// One player in the list.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// The player's name.
    pub name: String,
    /// The character it is drawn by, in the view and on the map.
    pub label: char,
    /// Its colour.
    pub color: Color,
    /// When it came into the maze (seconds, the host's clock).
    pub joined_at: f64,
    /// Its best time to the exit (seconds), if it has reached it.
    pub best: Option<f64>,
    /// The viewer itself.
    pub me: bool,
}

/// What the list's header says closes it, for a player (`Tab` opens and closes it; a spectator's
/// `Tab` is the next player, and its `p` opens and closes the list).
pub const CLOSE_HINT: &str = "Tab closes";

/// The box's colours (those of the walk's other boxes).
const FG: Color = Color::Indexed(255);
const BG: Color = Color::Indexed(24);

/// `h:mm:ss` or `m:ss` for a time in the maze (whole seconds).
#[must_use]
pub(crate) fn duration_text(seconds: f64) -> String {
    let s = seconds.max(0.0) as u64;
    let (h, m, s) = (s / 3600, s / 60 % 60, s % 60);
    if h > 0 { format!("{h}:{m:02}:{s:02}") } else { format!("{m}:{s:02}") }
}

/// The list's rows at time `now`: label, name, time in the maze, best time.
#[must_use]
pub fn lines(entries: &[Entry], now: f64) -> Vec<String> {
    let name = |e: &Entry| if e.me { format!("{} (you)", e.name) } else { e.name.clone() };
    let width = entries.iter().map(|e| name(e).chars().count()).max().unwrap_or(0);
    entries
        .iter()
        .map(|e| {
            let best = e.best.map_or_else(|| "-".to_string(), clock_text);
            format!("{}  {:<width$}  {:>8}  {:>8}", e.label, name(e), duration_text(now - e.joined_at), best)
        })
        .collect()
}

/// Draws the list over `frame` (above its HUD row), at time `now`; rows that do not fit end in a row
/// saying how many more there are. Each label is drawn in its player's colour (where the terminal has
/// colour). Its header says `hint`: what closes it ([`CLOSE_HINT`] for a player).
pub fn draw(frame: &mut Frame, entries: &[Entry], now: f64, hint: &str, style: Style) {
    let (w, h) = (frame.width(), frame.height().saturating_sub(1));
    let title = format!("Players: {}", entries.len());
    let header = format!("{title}    {hint}");
    let mut rows = lines(entries, now);
    let inner = rows.iter().map(|l| l.chars().count()).chain([header.chars().count()]).max().unwrap_or(0);
    let bw = (inner + 4).min(w);
    let text_width = bw.saturating_sub(4);
    // title, a blank row, the rows, a row above and below
    let room = h.saturating_sub(4);
    if rows.len() > room {
        let more = rows.len() + 1 - room.max(1);
        rows.truncate(room.saturating_sub(1));
        rows.push(format!("… and {more} more"));
    }
    let bh = (rows.len() + 4).min(h);
    let (x0, y0) = ((w - bw) / 2, (h - bh) / 2);
    let plain = style.depth == ColorDepth::None;
    let (fg, bg) = if plain { (Color::Default, Color::Default) } else { (FG, BG) };
    for y in y0..y0 + bh {
        for x in x0..x0 + bw {
            let edge = plain && (x == x0 || x + 1 == x0 + bw || y == y0 || y + 1 == y0 + bh);
            let ch = match (edge, x == x0 || x + 1 == x0 + bw, y == y0 || y + 1 == y0 + bh) {
                (true, true, true) => '+',
                (true, true, false) => '|',
                (true, false, true) => '-',
                _ => ' ',
            };
            frame.set(x, y, Cell { ch, fg, bg });
        }
    }
    let ellipsis = if style.ascii { "..." } else { "…" };
    let header = if header.chars().count() <= text_width { header } else { title };
    frame.put_str(x0 + 2, y0 + 1, &fit_line(&header, text_width, ellipsis), fg, bg);
    for (i, row) in rows.iter().enumerate() {
        let y = y0 + 3 + i;
        if y + 1 >= y0 + bh {
            break;
        }
        let row = fit_line(&style.text(row), text_width, ellipsis);
        frame.put_str(x0 + 2, y, &row, fg, bg);
        if let Some(entry) = entries.get(i).filter(|_| !plain && !row.starts_with('…')) {
            frame.set(x0 + 2, y, Cell { ch: entry.label, fg: entry.color, bg });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(name: &str, label: char, joined_at: f64, best: Option<f64>, me: bool) -> Entry {
        Entry { name: name.into(), label, color: Color::Indexed(196), joined_at, best, me }
    }

    #[test]
    fn rows_say_who_for_how_long_and_their_best() {
        let entries = [entry("alice", 'A', 0.0, Some(62.5), false), entry("bob", 'B', 500.0, None, true)];
        assert_eq!(
            lines(&entries, 723.0),
            ["A  alice         12:03    1:02.5", "B  bob (you)      3:43         -"]
        );
        assert_eq!(duration_text(3725.0), "1:02:05");
    }

    #[test]
    fn the_box_shows_the_labels_in_their_colours_and_what_does_not_fit_is_counted() {
        let style = Style::new(mazewalk_render::Charset::Half, ColorDepth::Ansi256);
        let entries: Vec<Entry> = (0..30)
            .map(|i| entry(&format!("p{i}"), char::from(b'A' + i as u8 % 26), 0.0, None, i == 0))
            .collect();
        let mut frame = Frame::new(60, 14);
        draw(&mut frame, &entries, 65.0, CLOSE_HINT, style);
        let text = frame.lines().join("\n");
        assert!(text.contains("Players: 30") && text.contains("Tab closes"), "{text}");
        assert!(text.contains("A  p0 (you)") && text.contains("1:05"), "{text}");
        assert!(text.contains("… and 22 more"), "{text}");
        assert!(frame.lines()[13].trim().is_empty(), "the HUD's row is left alone");
        let (x, y) = (0..60)
            .flat_map(|x| (0..13).map(move |y| (x, y)))
            .find(|&(x, y)| frame.get(x, y).is_some_and(|c| c.ch == 'A'))
            .unwrap();
        assert_eq!(frame.get(x, y).unwrap().fg, Color::Indexed(196), "the label in its player's colour");
    }
}
