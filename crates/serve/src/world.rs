//! The shared world of a served maze: who is in it, where each player stands, and who reached the exit
//! first. Pure data behind one lock in the server, held for data only: a change writes a few fields
//! and bumps [`World::version`]; a look ([`World::look`]) copies out a snapshot of everyone (an `Arc`,
//! rebuilt once per version), which each player's task filters by what it shows
//! ([`Player::look`](crate::player::Player::look)) after the lock is gone. The server publishes the
//! version so that each player's task looks again (and redraws only if what it shows of the others
//! changed).
//!
//! Served with `--world` ([`crate::shared`]), the world also holds the other servers' players
//! ([`World::set_others`]: after this server's own, in a separate id space, [`remote_id`]), whether
//! the world is online ([`Look::online`]), and its first finish comes from Redis's claim
//! ([`World::set_winner`]) rather than from this server's first finish.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use glam::Vec2;

use crate::shared::codec::{Finish, PlayerRecord, WinnerRecord};
use crate::shared::view::{Others, arrival};
use crate::shared::{LocalFinish, ServerId};
use mazewalk_term::frame::Color;
use mazewalk_walk::clock::clock_text;
use mazewalk_walk::overlay::Peer;

use crate::identity::PLAYER_COLORS;

/// A player's id in the world, unique for the server's lifetime. This server's players count up
/// from 0; another server's (shared world) have the top bit set ([`remote_id`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PlayerId(pub u64);

/// The top bit of every other server's player's id.
const REMOTE: u64 = 1 << 63;

/// The id of player `id` of server `server` in this server's world: the top bit set, the rest a mix
/// of both (never one of this server's own ids).
#[must_use]
pub(crate) fn remote_id(server: ServerId, id: u32) -> PlayerId {
    let mixed = server.0.wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(32) ^ u64::from(id);
    PlayerId(REMOTE | mixed)
}

/// One player as the others see it.
#[derive(Clone, Debug, PartialEq)]
pub struct Seen {
    /// The (sanitized) name.
    pub name: String,
    /// Where the player stands (maze plane).
    pub position: Vec2,
    /// Which way it faces, degrees counter-clockwise from +x.
    pub heading_deg: f32,
    /// How far it looks up (+) or down (−), degrees (shared with the other servers of a `--world`;
    /// the figures do not show it).
    pub pitch_deg: f32,
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
    /// Its exit clock as it sees it (a spectator following it shows the same); `None` for another
    /// server's player (the world's messages do not carry it).
    pub clock: Option<WalkClock>,
}

/// A player's exit clock: when its walk started (the server's clock, seconds; `r` starts another)
/// and, once that walk reached the exit, how long it took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkClock {
    /// When the walk started.
    pub started: f64,
    /// The walk's time to the exit, once reached.
    pub took: Option<f64>,
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
    /// The announcement everyone sees. A winner whose name reads as "you" (`You`, `YOU.`, `_you-`:
    /// any name may be chosen) is named as a player, or every other player and spectator read "You
    /// reached the exit first" as the winner's own announcement does, and believed they had won
    /// (red-team pass 16).
    #[must_use]
    pub fn announcement(&self) -> String {
        let reads_you = self.name.trim_matches(['.', '-', '_']).eq_ignore_ascii_case("you");
        let who = if reads_you { format!("The player named {}", self.name) } else { self.name.clone() };
        format!("{who} reached the exit first, in {}!", clock_text(self.seconds))
    }

    /// The announcement as player `viewer` sees it: the winner is told it was them.
    #[must_use]
    pub(crate) fn announcement_for(&self, viewer: PlayerId) -> String {
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
    /// Served with `--world`: whether this server hears the shared world now (`None`: the world is
    /// this server's alone).
    pub online: Option<bool>,
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
    /// The shared world's part (`None`: in-process).
    shared: Option<SharedPart>,
}

/// What a world served with `--world` holds besides its own players.
#[derive(Debug)]
struct SharedPart {
    /// This server's id in the shared world, once joined.
    me: Option<ServerId>,
    /// The Unix time (ms) of the server's clock's zero, to tell the others when players joined.
    epoch_ms: u64,
    /// The other servers' players, as last heard (frozen while offline).
    remote: Vec<(PlayerId, Seen)>,
    /// When each of them came, as every server orders arrivals ([`arrival`]), in `remote`'s order.
    arrivals: Vec<(u64, ServerId, u32)>,
    /// Where each of them is in `remote` (a finish or a gone player is found in O(1), never by a
    /// scan: `remote` holds up to `--max-remote-players`).
    index: HashMap<PlayerId, usize>,
    /// The other servers' players' best times heard since this server started.
    remote_best: HashMap<PlayerId, f64>,
    /// This server hears the world.
    online: bool,
    /// This server's finishes not yet taken by the world task.
    finishes: Vec<LocalFinish>,
}

/// This server's finishes kept for the world task at most (beyond, the oldest go).
const MAX_FINISHES: usize = 1024;

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
        let wearing = |color: &Color| self.everyone().filter(|p| p.color == *color).count();
        let color = *PLAYER_COLORS.iter().min_by_key(|c| wearing(c)).expect("a palette");
        let label = label_for(name, |c| self.everyone().any(|p| p.label == c));
        let seen = Seen {
            name: name.to_string(),
            position,
            heading_deg,
            pitch_deg: 0.0,
            cell,
            color,
            label,
            joined_at: now,
            best: None,
            clock: Some(WalkClock { started: now, took: None }),
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

    /// The player now looks `pitch_deg` up (+) or down (−). The figures do not show it, but a
    /// spectator following the player does (issue #43): a change bumps the version.
    pub fn pitched(&mut self, id: PlayerId, pitch_deg: f32) {
        if let Some(seen) = self.players.get_mut(&id)
            && seen.pitch_deg != pitch_deg
        {
            seen.pitch_deg = pitch_deg;
            self.version += 1;
        }
    }

    /// The player's exit clock is now `clock` (a new walk, or a finish): a change bumps the version,
    /// for the spectators following it.
    pub fn clocked(&mut self, id: PlayerId, clock: WalkClock) {
        if let Some(seen) = self.players.get_mut(&id)
            && seen.clock != Some(clock)
        {
            seen.clock = Some(clock);
            self.version += 1;
        }
    }

    /// The player reached the exit after `seconds`: its best time is kept (for the player list), and
    /// if it is the first to reach it, it is the winner and the announcement is returned. In a shared
    /// world the finish waits for the world task instead, which claims the win in Redis
    /// ([`set_winner`](Self::set_winner)): `None` then.
    pub fn finished(&mut self, id: PlayerId, seconds: f64) -> Option<String> {
        let seen = self.players.get_mut(&id)?;
        if seen.best.is_none_or(|best| seconds < best) {
            seen.best = Some(seconds);
            self.version += 1;
        }
        if let Some(shared) = &mut self.shared {
            if shared.finishes.len() >= MAX_FINISHES {
                shared.finishes.remove(0);
            }
            let id = local_u32(id);
            shared.finishes.push(LocalFinish { id, name: seen.name.clone(), seconds });
            return None;
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

    /// Where every player stands (the other servers' too).
    #[must_use]
    pub fn positions(&self) -> Vec<Vec2> {
        self.everyone().map(|p| p.position).collect()
    }

    /// Whether the world is shared with other servers (`--world`).
    #[must_use]
    pub fn is_shared(&self) -> bool {
        self.shared.is_some()
    }

    /// Where every player but `id` stands (the other servers' too).
    #[must_use]
    pub fn positions_but(&self, id: PlayerId) -> Vec<Vec2> {
        let own = self.players.iter().filter(|&(&other, _)| other != id).map(|(_, p)| p);
        let remote = self.shared.iter().flat_map(|s| s.remote.iter().map(|(_, seen)| seen));
        own.chain(remote).map(|p| p.position).collect()
    }

    /// Whether a player of another server who came into the world before this server's player `id`
    /// (by the order every server computes alike, [`arrival`]) stands within `within` of it: two
    /// newcomers who joined two servers within a message's way of each other took one spot, or this
    /// server had not heard of the other's player yet (it started or came back online less than a
    /// full message ago). The later one moves; the earlier one's server answers `false`, so exactly
    /// one of the two does. O(other servers' players). `false` in a world of this server's alone.
    #[must_use]
    pub fn came_first_near(&self, id: PlayerId, within: f32) -> bool {
        let (Some(shared), Some(seen)) = (&self.shared, self.players.get(&id)) else { return false };
        let Some(me) = shared.me else { return false };
        let mine = arrival(me, joined_ms(shared.epoch_ms, seen.joined_at), local_u32(id));
        shared
            .remote
            .iter()
            .zip(&shared.arrivals)
            .any(|((_, other), &theirs)| theirs < mine && other.position.distance(seen.position) < within)
    }

    /// This server's players, then the other servers'.
    fn everyone(&self) -> impl Iterator<Item = &Seen> {
        let remote = self.shared.iter().flat_map(|s| s.remote.iter().map(|(_, seen)| seen));
        self.players.values().chain(remote)
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
        let remote = self.shared.iter().flat_map(|s| s.remote.iter().cloned());
        let players: Arc<[(PlayerId, Seen)]> =
            self.players.iter().map(|(&id, seen)| (id, seen.clone())).chain(remote).collect();
        let online = self.shared.as_ref().map(|s| s.online);
        let look = Look { players, winner: self.winner.clone(), version: self.version, online };
        self.look = Some(look.clone());
        look
    }
}

/// This server's player `id` as the shared world knows it (ids count up from 0: a server's lifetime
/// never reaches 2³² players).
fn local_u32(id: PlayerId) -> u32 {
    u32::try_from(id.0).unwrap_or(u32::MAX)
}

/// When a player who joined at `joined_at` (the server's clock, seconds) joined, in Unix
/// milliseconds, for a server whose clock's zero was at `epoch_ms`: what the others are told, and what
/// this server orders arrivals by ([`World::came_first_near`]), alike.
fn joined_ms(epoch_ms: u64, joined_at: f64) -> u64 {
    epoch_ms.saturating_add((joined_at.max(0.0) * 1e3) as u64)
}

/// The shared world's colour index of `color` (0 for a colour not in the palette).
fn color_index(color: Color) -> u8 {
    PLAYER_COLORS.iter().position(|&c| c == color).map_or(0, |i| i as u8)
}

impl World {
    /// An empty world that is part of a shared one (`--world`): its clock's zero was at `epoch_ms`
    /// (Unix milliseconds). It is offline until the world task says otherwise.
    #[must_use]
    pub fn shared(epoch_ms: u64) -> World {
        let part = SharedPart {
            me: None,
            epoch_ms,
            remote: Vec::new(),
            arrivals: Vec::new(),
            index: HashMap::new(),
            remote_best: HashMap::new(),
            online: false,
            finishes: Vec::new(),
        };
        World { shared: Some(part), ..World::default() }
    }

    /// This server's id in the shared world (known once it has joined).
    pub(crate) fn set_server(&mut self, me: ServerId) {
        if let Some(shared) = &mut self.shared {
            shared.me = Some(me);
        }
    }

    /// This server's players for the world task, into `players` (cleared first, in id order), and
    /// their finishes since the last call, appended to `finished`.
    pub fn locals(&mut self, players: &mut Vec<PlayerRecord>, finished: &mut Vec<LocalFinish>) {
        players.clear();
        let Some(shared) = &mut self.shared else { return };
        finished.append(&mut shared.finishes);
        let epoch_ms = shared.epoch_ms;
        players.extend(self.players.iter().map(|(&id, seen)| PlayerRecord {
            id: local_u32(id),
            joined_ms: joined_ms(epoch_ms, seen.joined_at),
            color: color_index(seen.color),
            label: seen.label,
            name: seen.name.clone(),
            at: crate::shared::codec::Whereabouts {
                position: seen.position,
                heading_deg: seen.heading_deg.rem_euclid(360.0),
                pitch_deg: if seen.pitch_deg.is_finite() { seen.pitch_deg.clamp(-90.0, 90.0) } else { 0.0 },
                cell: seen.cell,
            },
        }));
    }

    /// The other servers' players as the world task has them, and whether the world is online, at
    /// `now` (the server's clock). Returns whether that changed anything.
    pub(crate) fn set_others(&mut self, others: &Others, online: bool, now: f64) -> bool {
        let Some(shared) = &mut self.shared else { return false };
        let now_ms = shared.epoch_ms.saturating_add((now.max(0.0) * 1e3) as u64);
        shared.arrivals.clear();
        shared.arrivals.extend(others.players().map(|(server, p)| arrival(server, p.joined_ms, p.id)));
        let remote: Vec<(PlayerId, Seen)> = others
            .players()
            .map(|(server, p)| {
                let id = remote_id(server, p.id);
                let seen = Seen {
                    name: p.name.clone(),
                    position: p.at.position,
                    heading_deg: p.at.heading_deg,
                    pitch_deg: p.at.pitch_deg,
                    cell: p.at.cell,
                    color: PLAYER_COLORS[usize::from(p.color) % PLAYER_COLORS.len()],
                    label: p.label,
                    joined_at: now - now_ms.saturating_sub(p.joined_ms) as f64 / 1e3,
                    best: shared.remote_best.get(&id).copied(),
                    clock: None,
                };
                (id, seen)
            })
            .collect();
        // (The join time moves with the clock's rounding: compared without it.)
        let same = shared.remote.len() == remote.len()
            && shared.remote.iter().zip(&remote).all(|((a, sa), (b, sb))| {
                a == b && Seen { joined_at: 0.0, ..sa.clone() } == Seen { joined_at: 0.0, ..sb.clone() }
            });
        if same && shared.online == online {
            return false;
        }
        if !same {
            // issue #40: a scan of `remote` per best time here was O(players²) under the lock.
            shared.index = remote.iter().enumerate().map(|(i, (id, _))| (*id, i)).collect();
            let index = &shared.index;
            shared.remote_best.retain(|id, _| index.contains_key(id));
            shared.remote = remote;
        }
        shared.online = online;
        self.version += 1;
        true
    }

    /// The world's winner, as Redis has it (the first claim): announced as an in-process winner is.
    /// Returns whether it changed.
    pub(crate) fn set_winner(&mut self, winner: &WinnerRecord) -> bool {
        let Some(shared) = &self.shared else { return false };
        let id = if shared.me == Some(winner.server) {
            PlayerId(u64::from(winner.id))
        } else {
            remote_id(winner.server, winner.id)
        };
        let new = Winner { id, name: winner.name.clone(), seconds: winner.seconds };
        if self.winner.as_deref() == Some(&new) {
            return false;
        }
        self.winner = Some(Arc::new(new));
        self.version += 1;
        true
    }

    /// Players of server `server` reached the exit: their best times show in the player list.
    /// O(finishes) (issue #40). Returns whether that changed anything.
    pub(crate) fn remote_finished(&mut self, server: ServerId, finishes: &[Finish]) -> bool {
        let Some(shared) = &mut self.shared else { return false };
        let mut changed = false;
        for finish in finishes {
            let id = remote_id(server, finish.id);
            let Some(&i) = shared.index.get(&id) else { continue };
            let seen = &mut shared.remote[i].1;
            if seen.best.is_some_and(|best| best <= finish.seconds) {
                continue;
            }
            seen.best = Some(finish.seconds);
            shared.remote_best.insert(id, finish.seconds);
            changed = true;
        }
        if changed {
            self.version += 1;
        }
        changed
    }

    /// These players of this server show a label an earlier player of another server shows: each
    /// takes another if one is free (else keeps its own: never a label someone else shows).
    /// Returns whether any changed.
    pub fn relabel(&mut self, ids: &[u32]) -> bool {
        // How many show each label, counted once: O(players + ids), not a scan per candidate.
        let mut shown: HashMap<char, usize> = HashMap::new();
        for seen in self.everyone() {
            *shown.entry(seen.label).or_default() += 1;
        }
        let mut changed = false;
        for &id in ids {
            let id = PlayerId(u64::from(id));
            let Some(seen) = self.players.get_mut(&id) else { continue };
            let own = seen.label;
            let taken = |c: char| shown.get(&c).copied().unwrap_or(0) > usize::from(c == own);
            let label = label_for(&seen.name, taken);
            if !taken(label) && label != own {
                seen.label = label;
                *shown.entry(own).or_default() -= 1;
                *shown.entry(label).or_default() += 1;
                changed = true;
            }
        }
        if changed {
            self.version += 1;
        }
        changed
    }
}

impl Look {
    /// The players other than `me` for which `shows(position, cell)` holds, as the map draws them,
    /// into `out` (cleared first), in order of arrival.
    pub(crate) fn peers_of(&self, me: PlayerId, shows: impl Fn(Vec2, u32) -> bool, out: &mut Vec<Peer>) {
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
    fn a_player_named_you_does_not_tell_the_others_they_won() {
        let mut world = World::new();
        let a = world.join("alice", Vec2::ZERO, 0.0, 0, 0.0);
        for name in ["You", "you", "YOU", "You.", "_you-"] {
            let winner = Winner { id: PlayerId(99), name: name.into(), seconds: 83.0 };
            let told = winner.announcement_for(a);
            assert!(!told.starts_with("You ") && !told.to_lowercase().starts_with("you"), "{told}");
            assert_eq!(told, format!("The player named {name} reached the exit first, in 1:23.0!"));
            assert_eq!(winner.announcement(), told, "as a spectator sees it");
            assert!(winner.announcement_for(PlayerId(99)).starts_with("You reached the exit first"));
        }
        let youth = Winner { id: PlayerId(99), name: "youth".into(), seconds: 83.0 };
        assert_eq!(youth.announcement_for(a), "youth reached the exit first, in 1:23.0!");
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

    /// Players of another server, as the world task hears them (issue #35).
    fn others_with(players: &[(u64, u32, &str, char, Vec2)]) -> crate::shared::view::Others {
        use crate::shared::codec::{Body, Bounds, Message, Whereabouts};
        let bounds = Bounds { min: Vec2::splat(-100.0), max: Vec2::splat(100.0), cells: 100 };
        let mut others = Others::new(ServerId(1), 7, bounds);
        for (i, &(server, id, name, label, position)) in players.iter().enumerate() {
            let record = PlayerRecord {
                id,
                joined_ms: 1_000,
                color: 0,
                label,
                name: name.into(),
                at: Whereabouts { position, heading_deg: 0.0, pitch_deg: 0.0, cell: 3 },
            };
            let message = Message {
                maze: 7,
                server: ServerId(server),
                seq: i as u64 + 1,
                sent_ms: 1_000,
                body: Body::Full { players: vec![record], finished: Vec::new(), winner: None },
            };
            others.apply(message, 0.0);
        }
        others
    }

    // issue #35: the other servers' players are in every look, after this server's, never "me".
    #[test]
    fn a_shared_world_shows_the_other_servers_players() {
        let mut world = World::shared(0);
        world.set_server(ServerId(1));
        let a = world.join("alice", Vec2::ZERO, 0.0, 0, 0.0);
        assert_eq!(world.look().online, Some(false), "offline until the world task says");
        let others = others_with(&[(2, 0, "bob", 'B', Vec2::new(3.0, 4.0))]);
        assert!(world.set_others(&others, true, 1.0));
        assert!(!world.set_others(&others, true, 1.5), "nothing new");
        let look = world.look();
        assert_eq!(look.online, Some(true));
        assert_eq!(look.players.len(), 2);
        let mut out = Vec::new();
        look.peers_of(a, |_, _| true, &mut out);
        assert_eq!((out[0].initial, out[0].position), ('B', Vec2::new(3.0, 4.0)));
        assert!(look.players[1].0.0 >= REMOTE, "a remote id is never one of ours");
        // a newcomer here takes neither bob's label nor the colour the fewest wear
        let b2 = world.join("bert", Vec2::ZERO, 0.0, 0, 2.0);
        assert_eq!(world.get(b2).unwrap().label, 'E', "B is bob's (on the other server)");
        // the world goes offline: bob stays where he was, the look says so
        assert!(world.set_others(&others, false, 3.0));
        assert_eq!((world.look().online, world.look().players.len()), (Some(false), 3));
        // in-process worlds say nothing of it
        assert_eq!(World::new().look().online, None);
    }

    // Two newcomers on two servers on one spot: the later comer is told so, the earlier one not;
    // a far player, or an in-process world, says nothing.
    #[test]
    fn the_later_of_two_newcomers_on_one_spot_is_told_to_move() {
        let mut world = World::shared(0);
        world.set_server(ServerId(1));
        let spot = Vec2::new(2.0, 2.0);
        let early = world.join("ada", spot, 0.0, 0, 0.5); // joined at 500 ms, bob at 1,000
        let late = world.join("cy", spot, 0.0, 0, 2.0); // at 2,000
        assert!(!world.came_first_near(late, 1.0), "nobody else's player yet");
        world.set_others(&others_with(&[(2, 0, "bob", 'B', spot)]), true, 2.5);
        assert!(world.came_first_near(late, 1.0), "bob came before cy, on cy's spot");
        assert!(!world.came_first_near(early, 1.0), "ada came before bob: bob moves, on his server");
        world.set_others(&others_with(&[(2, 0, "bob", 'B', spot + Vec2::new(4.0, 0.0))]), true, 3.0);
        assert!(!world.came_first_near(late, 1.0), "a cell away");
        assert_eq!(world.positions_but(late), [spot, spot + Vec2::new(4.0, 0.0)]);
        let mut alone = World::new();
        let a = alone.join("ada", spot, 0.0, 0, 0.0);
        alone.join("bob", spot, 0.0, 0, 0.0);
        assert!(!alone.came_first_near(a, 1.0));
        assert!(world.is_shared() && !alone.is_shared());
    }

    // issue #35: in a shared world the first finish here is not the winner until Redis says so.
    #[test]
    fn a_shared_worlds_winner_comes_from_its_claim() {
        let mut world = World::shared(0);
        world.set_server(ServerId(1));
        let a = world.join("alice", Vec2::ZERO, 0.0, 0, 0.0);
        assert_eq!(world.finished(a, 30.0), None, "not crowned here");
        assert!(world.winner().is_none());
        let (mut players, mut finished) = (Vec::new(), Vec::new());
        world.locals(&mut players, &mut finished);
        assert_eq!((players.len(), players[0].name.as_str()), (1, "alice"));
        assert_eq!(finished, [LocalFinish { id: 0, name: "alice".into(), seconds: 30.0 }]);
        world.locals(&mut players, &mut finished);
        assert_eq!(finished.len(), 1, "taken once");
        // the pitch goes to the others, and to the spectators here (issue #43: a new version)
        let v = world.version();
        world.pitched(a, 12.0);
        world.locals(&mut players, &mut finished);
        assert_eq!((players[0].at.pitch_deg, world.version()), (12.0, v + 1));
        world.pitched(a, 12.0);
        assert_eq!(world.version(), v + 1, "the same pitch: nothing new");
        // bob on server 2 won first, as Redis says
        let others = others_with(&[(2, 5, "bob", 'B', Vec2::ZERO)]);
        world.set_others(&others, true, 1.0);
        let bob = WinnerRecord { server: ServerId(2), id: 5, seconds: 12.0, name: "bob".into() };
        assert!(world.set_winner(&bob));
        assert!(!world.set_winner(&bob), "once");
        let winner = world.look().winner.unwrap();
        assert_eq!(winner.announcement_for(a), "bob reached the exit first, in 0:12.0!");
        assert_eq!(winner.id, remote_id(ServerId(2), 5));
        // his finish shows in the player list
        let finish = Finish { id: 5, name: "bob".into(), seconds: 12.0, won: true };
        assert!(world.remote_finished(ServerId(2), std::slice::from_ref(&finish)));
        assert!(!world.remote_finished(ServerId(2), &[finish]), "no better");
        let look = world.look();
        assert_eq!(look.players.iter().find(|(_, s)| s.name == "bob").unwrap().1.best, Some(12.0));
        // our own win, as Redis says it, is announced to the winner as theirs
        let ours = WinnerRecord { server: ServerId(1), id: 0, seconds: 30.0, name: "alice".into() };
        world.set_winner(&ours);
        assert_eq!(world.winner().unwrap().announcement_for(a), "You reached the exit first, in 0:30.0!");
    }

    // issue #40: finishes and departures of other servers' players are found by id, not by a scan
    // (it was O(players²) under the world's lock): a best time stays while its player does, and
    // goes with it; finishes of players not in the world change nothing.
    #[test]
    fn remote_best_times_follow_their_players() {
        let mut world = World::shared(0);
        world.set_server(ServerId(1));
        let both = others_with(&[(2, 5, "bob", 'B', Vec2::ZERO), (3, 6, "cy", 'C', Vec2::ONE)]);
        world.set_others(&both, true, 1.0);
        let finish = |id, seconds| Finish { id, name: "x".into(), seconds, won: false };
        assert!(world.remote_finished(ServerId(2), &[finish(5, 20.0), finish(5, 12.0), finish(7, 1.0)]));
        assert!(world.remote_finished(ServerId(3), &[finish(6, 30.0)]));
        let best = |world: &mut World, name: &str| {
            world.look().players.iter().find(|(_, s)| s.name == name).and_then(|(_, s)| s.best)
        };
        assert_eq!((best(&mut world, "bob"), best(&mut world, "cy")), (Some(12.0), Some(30.0)));
        assert!(!world.remote_finished(ServerId(9), &[finish(5, 1.0)]), "no such player");
        // cy's server is gone: its best time goes with it; bob's stays through an update.
        let bob_only = others_with(&[(2, 5, "bob", 'B', Vec2::X)]);
        world.set_others(&bob_only, true, 2.0);
        assert_eq!((best(&mut world, "bob"), world.look().players.len()), (Some(12.0), 1));
        world.set_others(&both, true, 3.0);
        assert_eq!(best(&mut world, "cy"), None, "forgotten");
    }

    // issue #35: a label an earlier player of another server shows is given up for a free one.
    #[test]
    fn a_relabel_takes_a_free_label_only() {
        let mut world = World::shared(0);
        let a = world.join("bea", Vec2::ZERO, 0.0, 0, 0.0);
        assert_eq!(world.get(a).unwrap().label, 'B');
        let others = others_with(&[(2, 0, "bob", 'B', Vec2::ZERO)]);
        world.set_others(&others, true, 1.0);
        assert!(world.relabel(&[0]));
        assert_eq!(world.get(a).unwrap().label, 'E');
        assert!(!world.relabel(&[0]), "E is free: kept");
    }
}
