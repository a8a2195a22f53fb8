//! The shared world of a served maze: who is in it, where each player stands, and who reached the exit
//! first. Pure data behind one lock in the server, held for data only: a change writes a few fields
//! and bumps [`World::version`]; a look ([`World::look`]) copies out a snapshot of everyone (an `Arc`,
//! rebuilt once per version), which each player's task filters by what it shows
//! ([`Player::look`](crate::player::Player::look)) after the lock is gone. The server publishes the
//! version so that each player's task looks again (and redraws only if what it shows of the others
//! changed).

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::Vec2;

use mazewalk_term::frame::Color;
use mazewalk_walk::overlay::Peer;
use mazewalk_walk::screen::clock_text;

/// The colours players are drawn in, by order of arrival (256-colour indices: bright and distinct from
/// the map's own yellow viewer, green exit and grey walls; [`mazewalk_walk::overlay::limit_colors`] takes
/// them down to the terminal's depth).
pub const PLAYER_COLORS: [Color; 8] = [
    Color::Indexed(196), // red
    Color::Indexed(33),  // blue
    Color::Indexed(201), // magenta
    Color::Indexed(51),  // cyan
    Color::Indexed(208), // orange
    Color::Indexed(129), // purple
    Color::Indexed(118), // lime
    Color::Indexed(231), // white
];

/// A player's id in the world, unique for the server's lifetime.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PlayerId(pub u64);

/// One player as the others see it.
#[derive(Clone, Debug, PartialEq)]
pub struct Seen {
    /// The (sanitized) name.
    pub name: String,
    /// Where the player stands (maze plane).
    pub position: Vec2,
    /// Which way it faces, degrees counter-clockwise from +x.
    pub heading_deg: f32,
    /// The cell it stands in.
    pub cell: u32,
    /// Its colour.
    pub color: Color,
    /// The character it is shown by, on the map, on its figure's head and in the player list
    /// ([`label_for`]).
    pub label: char,
    /// When it joined (the server's clock, seconds).
    pub joined_at: f64,
    /// Its best time to the exit (seconds) since it joined, if it has reached it.
    pub best: Option<f64>,
}

impl Seen {
    /// The player as the map draws it.
    #[must_use]
    pub fn peer(&self) -> Peer {
        Peer {
            position: self.position,
            heading_deg: self.heading_deg,
            initial: self.label,
            color: self.color,
            cell: Some(self.cell),
        }
    }
}

/// The character a newcomer named `name` is shown by: the first character of its name (upper-cased)
/// that no one in the maze is shown by now, so that `u1` and `u2`, or `anna` and `alan`, can be told
/// apart (`U` and `2`; `A` and `L`); else a digit or letter no one shows; else its initial.
fn label_for(name: &str, taken: impl Fn(char) -> bool) -> char {
    let from_name = name.chars().filter(char::is_ascii_alphanumeric).map(|c| c.to_ascii_uppercase());
    let spare = ('1'..='9').chain('A'..='Z').chain(['0']);
    from_name.clone().chain(spare).find(|&c| !taken(c)).or_else(|| from_name.clone().next()).unwrap_or('?')
}

/// The first player to reach the exit.
#[derive(Clone, Debug, PartialEq)]
pub struct Winner {
    /// Who.
    pub id: PlayerId,
    /// Their name.
    pub name: String,
    /// How long the walk took, seconds.
    pub seconds: f64,
}

impl Winner {
    /// The announcement everyone sees.
    #[must_use]
    pub fn announcement(&self) -> String {
        format!("{} reached the exit first, in {}!", self.name, clock_text(self.seconds))
    }

    /// The announcement as player `viewer` sees it: the winner is told it was them.
    #[must_use]
    pub fn announcement_for(&self, viewer: PlayerId) -> String {
        if viewer == self.id {
            format!("You reached the exit first, in {}!", clock_text(self.seconds))
        } else {
            self.announcement()
        }
    }
}

/// What a player's task takes from the world at a look: everyone as of the world's last change, and
/// the winner. Cheap to take (two `Arc`s), so the world's lock is held for no more than that.
#[derive(Clone, Debug, Default)]
pub struct Look {
    /// Every player, in order of arrival, as of [`version`](Self::version).
    pub players: Arc<[(PlayerId, Seen)]>,
    /// The first to reach the exit, if anyone has.
    pub winner: Option<Arc<Winner>>,
    /// The world's version it was taken at.
    pub version: u64,
}

/// Everyone in the maze.
#[derive(Debug, Default)]
pub struct World {
    players: BTreeMap<PlayerId, Seen>,
    next_id: u64,
    winner: Option<Arc<Winner>>,
    version: u64,
    /// The last look handed out, while the version is the same.
    look: Option<Look>,
}

impl World {
    /// An empty world.
    #[must_use]
    pub fn new() -> World {
        World::default()
    }

    /// Bumped by every change.
    #[must_use]
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Players in the world.
    #[must_use]
    pub fn len(&self) -> usize {
        self.players.len()
    }

    /// Whether nobody is in the world.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.players.is_empty()
    }

    /// A player named `name` joins at `position` in `cell` at time `now`; its colour is the one the
    /// fewest wear.
    pub fn join(&mut self, name: &str, position: Vec2, heading_deg: f32, cell: u32, now: f64) -> PlayerId {
        let id = PlayerId(self.next_id);
        self.next_id += 1;
        // The colour the fewest players now wear (the first of those): all differ while there are
        // enough to go round, however many have come and gone.
        let wearing = |color: &Color| self.players.values().filter(|p| p.color == *color).count();
        let color = *PLAYER_COLORS.iter().min_by_key(|c| wearing(c)).expect("a palette");
        let label = label_for(name, |c| self.players.values().any(|p| p.label == c));
        let seen = Seen {
            name: name.to_string(),
            position,
            heading_deg,
            cell,
            color,
            label,
            joined_at: now,
            best: None,
        };
        self.players.insert(id, seen);
        self.version += 1;
        id
    }

    /// The player left.
    pub fn leave(&mut self, id: PlayerId) {
        if self.players.remove(&id).is_some() {
            self.version += 1;
        }
    }

    /// The player is now at `position`, facing `heading_deg`, in `cell`. Returns whether that changed
    /// anything.
    pub fn moved(&mut self, id: PlayerId, position: Vec2, heading_deg: f32, cell: u32) -> bool {
        let Some(seen) = self.players.get_mut(&id) else { return false };
        if (seen.position, seen.heading_deg, seen.cell) == (position, heading_deg, cell) {
            return false;
        }
        (seen.position, seen.heading_deg, seen.cell) = (position, heading_deg, cell);
        self.version += 1;
        true
    }

    /// The player reached the exit after `seconds`: its best time is kept (for the player list), and
    /// if it is the first to reach it, it is the winner and the announcement is returned.
    pub fn finished(&mut self, id: PlayerId, seconds: f64) -> Option<String> {
        let seen = self.players.get_mut(&id)?;
        if seen.best.is_none_or(|best| seconds < best) {
            seen.best = Some(seconds);
            self.version += 1;
        }
        if self.winner.is_some() {
            return None;
        }
        let name = seen.name.clone();
        let winner = Winner { id, name, seconds };
        let text = winner.announcement();
        self.winner = Some(Arc::new(winner));
        self.version += 1;
        Some(text)
    }

    /// The first to reach the exit, if anyone has.
    #[must_use]
    pub fn winner(&self) -> Option<&Winner> {
        self.winner.as_deref()
    }

    /// Where every player stands.
    #[must_use]
    pub fn positions(&self) -> Vec<Vec2> {
        self.players.values().map(|p| p.position).collect()
    }

    /// One player, if it is in the world.
    #[must_use]
    pub fn get(&self, id: PlayerId) -> Option<&Seen> {
        self.players.get(&id)
    }

    /// Everyone and the winner, as of now: the snapshot of this version (made at the first look
    /// after a change, then shared by every look until the next change).
    pub fn look(&mut self) -> Look {
        if let Some(look) = self.look.as_ref().filter(|look| look.version == self.version) {
            return look.clone();
        }
        let players: Arc<[(PlayerId, Seen)]> =
            self.players.iter().map(|(&id, seen)| (id, seen.clone())).collect();
        let look = Look { players, winner: self.winner.clone(), version: self.version };
        self.look = Some(look.clone());
        look
    }
}

impl Look {
    /// The players other than `me` for which `shows(position, cell)` holds, as the map draws them,
    /// into `out` (cleared first), in order of arrival.
    pub fn peers_of(&self, me: PlayerId, shows: impl Fn(Vec2, u32) -> bool, out: &mut Vec<Peer>) {
        out.clear();
        out.extend(
            self.players
                .iter()
                .filter(|(id, seen)| *id != me && shows(seen.position, seen.cell))
                .map(|(_, seen)| seen.peer()),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_newcomer_wears_a_free_colour() {
        let mut world = World::new();
        let ids: Vec<PlayerId> =
            (0..PLAYER_COLORS.len()).map(|i| world.join(&format!("p{i}"), Vec2::ZERO, 0.0, 0, 0.0)).collect();
        let color_of = |world: &World, id: PlayerId| world.players[&id].color;
        let freed = color_of(&world, ids[2]);
        world.leave(ids[2]);
        let newcomer = world.join("anna", Vec2::ZERO, 0.0, 0, 0.0);
        assert_eq!(color_of(&world, newcomer), freed, "the one colour nobody wears");
        let colors: std::collections::HashSet<_> = world.players.values().map(|p| p.color).collect();
        assert_eq!(colors.len(), PLAYER_COLORS.len(), "all different");
    }

    #[test]
    fn players_see_the_others_not_themselves() {
        let mut world = World::new();
        let a = world.join("alice", Vec2::ZERO, 0.0, 0, 0.0);
        let b = world.join("bob", Vec2::new(4.0, 0.0), 90.0, 1, 0.0);
        let mut out = Vec::new();
        world.look().peers_of(a, |_, _| true, &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!((out[0].initial, out[0].position), ('B', Vec2::new(4.0, 0.0)));
        assert_ne!(out[0].color, world.get(a).unwrap().color, "each its own colour");
        world.look().peers_of(a, |_, cell| cell == 0, &mut out);
        assert!(out.is_empty(), "bob's cell is not shown to alice");
        let v = world.version();
        assert!(!world.moved(b, Vec2::new(4.0, 0.0), 90.0, 1), "standing still changes nothing");
        assert!(world.moved(b, Vec2::new(5.0, 0.0), 90.0, 1));
        assert!(world.version() > v);
        world.leave(b);
        world.look().peers_of(a, |_, _| true, &mut out);
        assert!(out.is_empty());
        assert_eq!(world.len(), 1);
    }

    /// Players whose names share an initial are shown by different characters, each from its own
    /// name where it can be, and a label is free again once its player has left.
    #[test]
    fn players_are_told_apart_by_their_labels() {
        let mut world = World::new();
        let ids: Vec<PlayerId> = ["u1", "u2", "u3", "anna", "alan", "x", "x", "x"]
            .iter()
            .map(|n| world.join(n, Vec2::ZERO, 0.0, 0, 0.0))
            .collect();
        let labels: Vec<char> = ids.iter().map(|&id| world.get(id).unwrap().label).collect();
        assert_eq!(labels, ['U', '2', '3', 'A', 'L', 'X', '1', '4']);
        world.leave(ids[0]);
        let back = world.join("ursula", Vec2::ZERO, 0.0, 0, 0.0);
        assert_eq!(world.get(back).unwrap().label, 'U', "free again");
        let mut out = Vec::new();
        world.look().peers_of(back, |_, _| true, &mut out);
        assert_eq!(out.iter().map(|p| p.initial).collect::<String>(), "23ALX14");
        assert_eq!(label_for("", |_| false), '1', "(names are never empty: `player_name`)");
    }

    #[test]
    fn a_look_is_shared_until_the_world_changes() {
        let mut world = World::new();
        let a = world.join("alice", Vec2::ZERO, 0.0, 0, 0.0);
        let (first, second) = (world.look(), world.look());
        assert!(Arc::ptr_eq(&first.players, &second.players), "one snapshot per version");
        world.moved(a, Vec2::ONE, 0.0, 0);
        let third = world.look();
        assert!(!Arc::ptr_eq(&first.players, &third.players));
        assert_eq!(third.players[0].1.position, Vec2::ONE, "the snapshot is of now");
        assert_eq!(first.players[0].1.position, Vec2::ZERO, "an old look keeps what it saw");
    }

    #[test]
    fn only_the_first_at_the_exit_wins() {
        let mut world = World::new();
        let a = world.join("alice", Vec2::ZERO, 0.0, 0, 0.0);
        let b = world.join("bob", Vec2::ZERO, 0.0, 0, 0.0);
        assert_eq!(world.finished(b, 83.0).as_deref(), Some("bob reached the exit first, in 1:23.0!"));
        assert_eq!(world.finished(a, 10.0), None);
        assert_eq!(world.winner().map(|w| w.name.as_str()), Some("bob"));
        let winner = world.winner().unwrap();
        assert_eq!(winner.announcement_for(b), "You reached the exit first, in 1:23.0!");
        assert_eq!(winner.announcement_for(a), "bob reached the exit first, in 1:23.0!");
        // Every finish counts for the player list: each player's best.
        let v = world.version();
        assert_eq!(world.finished(a, 12.0), None);
        assert_eq!(world.get(a).unwrap().best, Some(10.0), "a slower finish keeps the best");
        assert_eq!(world.version(), v, "nothing changed");
        world.finished(b, 70.0);
        assert_eq!((world.get(b).unwrap().best, world.version() > v), (Some(70.0), true));
    }
}
