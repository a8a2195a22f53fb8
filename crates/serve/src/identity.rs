//! Who a player is to the others: a name made safe for every screen, and a colour from the players'
//! palette. Below the world, the players and the shared world's wire format, which all check them.

use mazewalk_term::frame::Color;

/// The longest player name, in characters.
pub(crate) const MAX_NAME: usize = 16;

/// The player name for an SSH user name: ASCII letters, digits, `-`, `_` and `.` only (no control
/// characters, escape sequences, wide or invisible characters can reach another player's screen),
/// at most [`MAX_NAME`] of them; `player` if none are left. Every name shown is cleaned by it, from
/// wherever it came: an SSH user name, the records file, the shared world.
#[must_use]
pub fn player_name(user: &str) -> String {
    let name: String = user
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
        .take(MAX_NAME)
        .collect();
    if name.is_empty() { "player".to_string() } else { name }
}

/// The colours players are drawn in, by order of arrival (256-colour indices: bright and distinct from
/// the map's own yellow viewer, green exit and grey walls; [`mazewalk_walk::overlay::limit_colors`] takes
/// them down to the terminal's depth).
pub(crate) const PLAYER_COLORS: [Color; 8] = [
    Color::Indexed(196), // red
    Color::Indexed(33),  // blue
    Color::Indexed(201), // magenta
    Color::Indexed(51),  // cyan
    Color::Indexed(208), // orange
    Color::Indexed(129), // purple
    Color::Indexed(118), // lime
    Color::Indexed(231), // white
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_keep_only_harmless_ascii_and_are_capped() {
        assert_eq!(player_name("alice"), "alice");
        assert_eq!(player_name("\x1b[31mbob\x07"), "31mbob");
        assert_eq!(player_name("ünï cødé"), "ncd");
        assert_eq!(player_name(""), "player");
        assert_eq!(player_name("\u{202e}\u{200b}"), "player");
        assert_eq!(player_name(&"x".repeat(10_000)).len(), MAX_NAME);
    }
}
