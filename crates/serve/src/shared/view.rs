//! The shared world's rules, without Redis: what this server tells the others each tick
//! ([`Outbox`]), what it knows of them ([`Others`]), and which of two players showing the same label
//! keeps it ([`yields_label`]). Pure: messages and time (seconds) in, messages and views out.
//!
//! Each server speaks for its own players only, and states are absolute: a move carries the
//! position, not a step, and a full message every [`FULL_EVERY`] seconds carries everyone, so a lost
//! or dropped message is repaired by the next full one, and a server that starts or comes back
//! learns everything within a second without asking anyone.

use std::collections::BTreeMap;
use std::sync::Arc;

use mazewalk_maze::Maze;

use super::codec::{
    Body, Bounds, DecodeError, Finish, MAX_PLAYERS, Message, Move, PlayerRecord, ServerId, Whereabouts,
    WinnerRecord, decode,
};

/// A server publishes at most this many messages a second, whatever its number of players: the
/// players that moved within a tick go out together.
pub(crate) const TICKS_PER_SECOND: f64 = 30.0;
/// Seconds between a server's full messages (everyone, even if nobody moved): the heartbeat that
/// keeps it alive in the others' views and repairs anything they missed.
pub(crate) const FULL_EVERY: f64 = 1.0;
/// A server not heard from for this long (while this one hears Redis) has gone: its players leave
/// the view. Three missed heartbeats.
pub(crate) const SILENCE: f64 = 3.0;

/// What one server tells the others: the difference between its players now and what it last
/// published, once a tick at most, and all of them every [`FULL_EVERY`] seconds.
#[derive(Debug)]
pub(crate) struct Outbox {
    server: ServerId,
    maze: u64,
    seq: u64,
    /// What the others know of this server's players (as of the last message).
    published: BTreeMap<u32, PlayerRecord>,
    /// When the last full message went out (`None`: the next one is full).
    last_full: Option<f64>,
}

impl Outbox {
    /// The outbox of server `server` in the world of the maze tagged `maze`.
    #[must_use]
    pub fn new(server: ServerId, maze: u64) -> Outbox {
        Outbox { server, maze, seq: 0, published: BTreeMap::new(), last_full: None }
    }

    /// The next message to send at `now` (seconds) given this server's `players` now and the
    /// `finished` since the last message, or `None` when nothing changed and no full one is due.
    /// `sent_ms` stamps it (wall clock, for latency figures). At most [`MAX_PLAYERS`] players are
    /// told of (a server holds `--max-players`, far fewer).
    pub fn tick(
        &mut self,
        now: f64,
        players: &[PlayerRecord],
        finished: Vec<Finish>,
        winner: Option<&WinnerRecord>,
        sent_ms: u64,
    ) -> Option<Message> {
        let players = &players[..players.len().min(MAX_PLAYERS)];
        let finished = finished.into_iter().take(MAX_PLAYERS).collect::<Vec<_>>();
        let full_due = self.last_full.is_none_or(|at| now - at >= FULL_EVERY);
        let body = if full_due {
            self.last_full = Some(now);
            self.published = players.iter().map(|p| (p.id, p.clone())).collect();
            Body::Full { players: players.to_vec(), finished, winner: winner.cloned() }
        } else {
            let (mut joined, mut moved) = (Vec::new(), Vec::new());
            for p in players {
                match self.published.get(&p.id) {
                    Some(old)
                        if (old.name.as_str(), old.color, old.label)
                            == (p.name.as_str(), p.color, p.label) =>
                    {
                        if old.at != p.at {
                            moved.push(Move { id: p.id, at: p.at });
                        }
                    }
                    _ => joined.push(p.clone()),
                }
            }
            let mut left: Vec<u32> = Vec::new();
            let mut now_in = players.iter().map(|p| p.id).peekable();
            for &id in self.published.keys() {
                // Both in id order: a merge.
                while now_in.next_if(|&n| n < id).is_some() {}
                if now_in.peek() != Some(&id) {
                    left.push(id);
                }
            }
            left.truncate(MAX_PLAYERS);
            if joined.is_empty() && moved.is_empty() && left.is_empty() && finished.is_empty() {
                return None;
            }
            for id in &left {
                self.published.remove(id);
            }
            for p in joined.iter() {
                self.published.insert(p.id, p.clone());
            }
            for m in &moved {
                if let Some(p) = self.published.get_mut(&m.id) {
                    p.at = m.at;
                }
            }
            Body::Delta { joined, moved, left, finished }
        };
        Some(self.message(body, sent_ms))
    }

    /// The next message is a full one (after Redis came back, say).
    pub fn resync(&mut self) {
        self.last_full = None;
    }

    /// The goodbye of a stopping server: its players leave the others' views at once.
    pub fn bye(&mut self, sent_ms: u64) -> Message {
        self.message(Body::Bye, sent_ms)
    }

    fn message(&mut self, body: Body, sent_ms: u64) -> Message {
        self.seq += 1;
        Message { maze: self.maze, server: self.server, seq: self.seq, sent_ms, body }
    }
}

/// How much of the other servers one server keeps, whatever Redis carries (`--max-remote-servers`,
/// `--max-remote-players`): the work per message and the memory of the view are bounded by them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Caps {
    /// Other servers at once; messages from more are dropped (and counted) until one leaves.
    pub servers: usize,
    /// Other servers' players at once, in all; players beyond are left out (and counted).
    pub players: usize,
}

impl Default for Caps {
    fn default() -> Self {
        Caps { servers: 16, players: 1024 }
    }
}

/// Messages heard and what became of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Applied to the view.
    pub applied: u64,
    /// This server's own messages, heard back from the channel.
    pub own: u64,
    /// Older than one already heard from the same server (a stored snapshot read late, say).
    pub stale: u64,
    /// Refused by the decoder ([`DecodeError`]): too long, malformed, out of bounds, another maze.
    pub dropped: u64,
    /// Moves of players the view did not know of (their join was missed: the next full message
    /// brings them).
    pub unknown: u64,
    /// Messages from a server beyond [`Caps::servers`], dropped.
    pub over_servers: u64,
    /// Players left out of messages for [`Caps::players`].
    pub over_players: u64,
}

/// The cell of the first player of `message` whose position is not inside it in `maze` (within the
/// maze's on-edge tolerance, as a server's own moves keep its players), if any.
fn misplaced(message: &Message, maze: Option<&Maze>) -> Option<u32> {
    let maze = maze?;
    let outside = |at: &Whereabouts| !maze.cell_contains(at.cell, at.position);
    match &message.body {
        Body::Full { players, .. } => players.iter().map(|p| &p.at).find(|at| outside(at)),
        Body::Delta { joined, moved, .. } => {
            joined.iter().map(|p| &p.at).chain(moved.iter().map(|m| &m.at)).find(|at| outside(at))
        }
        Body::Bye => None,
    }
    .map(|at| at.cell)
}

/// One other server as this one knows it.
#[derive(Debug)]
struct Known {
    seq: u64,
    heard: f64,
    players: BTreeMap<u32, PlayerRecord>,
}

/// What one heard message meant for this server.
#[derive(Debug, Default, PartialEq)]
pub struct Heard {
    /// Who sent it.
    pub server: Option<ServerId>,
    /// The view changed (someone joined, moved, left or was relabelled).
    pub changed: bool,
    /// Players of that server who reached the exit (those in the view only).
    pub finished: Vec<Finish>,
    /// The winner as that server claims it (a claim only: the winner is read from Redis).
    pub winner: Option<WinnerRecord>,
    /// Milliseconds since the Unix epoch at which it was sent (by the sender's clock).
    pub sent_ms: u64,
}

/// Everyone on the other servers, as this server heard of them.
#[derive(Debug)]
pub struct Others {
    me: ServerId,
    maze: u64,
    bounds: Bounds,
    /// The maze itself, where known: each player's position checked against its cell.
    cells: Option<Arc<Maze>>,
    caps: Caps,
    servers: BTreeMap<ServerId, Known>,
    /// Players of all servers in `servers`, kept as they change (never summed per message).
    players: usize,
    counts: Counts,
}

impl Others {
    /// The view of server `me` in the world of the maze tagged `maze`, whose positions and cells
    /// must be within `bounds`.
    #[must_use]
    pub fn new(me: ServerId, maze: u64, bounds: Bounds) -> Others {
        Others {
            me,
            maze,
            bounds,
            cells: None,
            caps: Caps::default(),
            servers: BTreeMap::new(),
            players: 0,
            counts: Counts::default(),
        }
    }

    /// The same view, keeping at most `caps` of the other servers.
    #[must_use]
    pub fn with_caps(self, caps: Caps) -> Others {
        Others { caps, ..self }
    }

    /// The same view, checking each player's position against the cell it names in `maze` (the
    /// maze the bounds are of): a message naming a player outside its cell is dropped whole, as the
    /// decoder drops one outside the maze. Without it, such a player's figure would be drawn where
    /// it stands but shown or hidden as its cell is seen, and its map dot put in the wrong cell.
    #[must_use]
    pub fn with_maze(self, maze: Arc<Maze>) -> Others {
        Others { cells: Some(maze), ..self }
    }

    /// A message heard at `now` (seconds): decoded, checked, and applied.
    ///
    /// # Errors
    /// The decoder refused it, or a player in it stands outside its cell ([`Others::with_maze`]):
    /// it is counted as dropped.
    pub fn hear(&mut self, bytes: &[u8], now: f64) -> Result<Heard, DecodeError> {
        let message = decode(bytes, self.maze, &self.bounds)
            .and_then(|message| match misplaced(&message, self.cells.as_deref()) {
                Some(cell) => Err(DecodeError::Misplaced(cell)),
                None => Ok(message),
            })
            .inspect_err(|_| self.counts.dropped += 1)?;
        Ok(self.apply(message, now))
    }

    /// A decoded message, applied. O(its length) whatever the view holds: beyond [`Caps`], a new
    /// server's messages are dropped and players are left out (both counted).
    pub fn apply(&mut self, message: Message, now: f64) -> Heard {
        let mut heard = Heard { server: Some(message.server), sent_ms: message.sent_ms, ..Heard::default() };
        if message.server == self.me {
            self.counts.own += 1;
            return heard;
        }
        if !self.servers.contains_key(&message.server) {
            if matches!(message.body, Body::Bye) {
                return heard; // nothing to forget
            }
            if self.servers.len() >= self.caps.servers {
                self.counts.over_servers += 1;
                return Heard { server: None, ..heard };
            }
        }
        let cap = self.caps.players;
        let total = &mut self.players;
        let known = self.servers.entry(message.server).or_insert(Known {
            seq: 0,
            heard: now,
            players: BTreeMap::new(),
        });
        if message.seq <= known.seq {
            self.counts.stale += 1;
            return heard;
        }
        (known.seq, known.heard) = (message.seq, now);
        self.counts.applied += 1;
        match message.body {
            Body::Full { players, finished, winner } => {
                // Room for this server's players: the cap less everyone else's.
                let room = cap.saturating_sub(*total - known.players.len());
                let offered = players.len();
                let players: BTreeMap<u32, PlayerRecord> =
                    players.into_iter().take(room).map(|p| (p.id, p)).collect();
                self.counts.over_players += offered.saturating_sub(room) as u64;
                heard.changed = players != known.players;
                *total = *total - known.players.len() + players.len();
                known.players = players;
                heard.finished = finished;
                heard.winner = winner;
            }
            Body::Delta { joined, moved, left, finished } => {
                for p in joined {
                    if !known.players.contains_key(&p.id) && *total >= cap {
                        self.counts.over_players += 1;
                        continue;
                    }
                    heard.changed |= known.players.get(&p.id) != Some(&p);
                    if known.players.insert(p.id, p).is_none() {
                        *total += 1;
                    }
                }
                for m in moved {
                    match known.players.get_mut(&m.id) {
                        Some(p) => {
                            heard.changed |= p.at != m.at;
                            p.at = m.at;
                        }
                        None => self.counts.unknown += 1,
                    }
                }
                for id in left {
                    if known.players.remove(&id).is_some() {
                        heard.changed = true;
                        *total -= 1;
                    }
                }
                heard.finished = finished;
            }
            Body::Bye => {
                heard.changed = !known.players.is_empty();
                *total -= known.players.len();
                self.servers.remove(&message.server);
            }
        }
        // A finish that won is a claim on the win, like a full message's winner (the world task
        // reads the winner from Redis when it hears one).
        if heard.winner.is_none()
            && let Some(f) = heard.finished.iter().find(|f| f.won)
        {
            let (server, id, seconds, name) = (message.server, f.id, f.seconds, f.name.clone());
            heard.winner = Some(WinnerRecord { server, id, seconds, name });
        }
        // Finishes of players not in the view (left out, or never there) say nothing to anyone.
        if let Some(known) = self.servers.get(&message.server) {
            heard.finished.retain(|f| known.players.contains_key(&f.id));
        }
        heard
    }

    /// Forgets the servers not heard from for [`SILENCE`] seconds at `now`. Returns whether anyone
    /// left the view. Call it only while this server hears Redis (else everyone would go).
    pub fn expire(&mut self, now: f64) -> bool {
        let before = self.players;
        let total = &mut self.players;
        self.servers.retain(|_, known| {
            let keep = now - known.heard < SILENCE;
            if !keep {
                *total -= known.players.len();
            }
            keep
        });
        before != self.players
    }

    /// This server hears Redis again at `now` after an outage: everyone's silence counts from now
    /// (their messages could not arrive meanwhile).
    pub(crate) fn reconnected(&mut self, now: f64) {
        for known in self.servers.values_mut() {
            known.heard = now;
        }
    }

    /// Everyone on the other servers, by server then id.
    pub fn players(&self) -> impl Iterator<Item = (ServerId, &PlayerRecord)> {
        self.servers.iter().flat_map(|(&s, known)| known.players.values().map(move |p| (s, p)))
    }

    /// How many players the other servers have.
    #[must_use]
    pub fn len(&self) -> usize {
        self.players
    }

    /// Whether no other server has a player.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The other servers heard from.
    pub fn servers(&self) -> impl Iterator<Item = ServerId> {
        self.servers.keys().copied()
    }

    /// What became of the messages heard so far.
    #[must_use]
    pub fn counts(&self) -> Counts {
        self.counts
    }

    /// This server's players (`locals`) who show a label that a player on another server who
    /// came first also shows ([`yields_label`]): they should take another, if one is free. `?`
    /// (shown when no label is free) is everyone's. O(others + locals).
    #[must_use]
    pub(crate) fn label_conflicts(&self, locals: &[PlayerRecord]) -> Vec<u32> {
        // The first comer of each label among the others.
        let mut first: BTreeMap<char, (ServerId, &PlayerRecord)> = BTreeMap::new();
        for (server, p) in self.players().filter(|(_, p)| p.label != '?') {
            match first.get(&p.label) {
                Some(&earlier) if !yields_label(earlier, (server, p)) => {}
                _ => {
                    first.insert(p.label, (server, p));
                }
            }
        }
        locals
            .iter()
            .filter(|mine| {
                first.get(&mine.label).is_some_and(|&theirs| yields_label((self.me, mine), theirs))
            })
            .map(|p| p.id)
            .collect()
    }
}

/// Whether `mine` (on its server) gives its label up to `theirs` (on theirs), both showing it: the
/// one who joined later yields — by the join times, then the server ids, then the player ids, an
/// order every server computes alike, so exactly one of the two yields.
#[must_use]
pub(crate) fn yields_label(mine: (ServerId, &PlayerRecord), theirs: (ServerId, &PlayerRecord)) -> bool {
    let key = |(server, p): (ServerId, &PlayerRecord)| arrival(server, p.joined_ms, p.id);
    key(mine) > key(theirs)
}

/// Who came first in the world, as every server computes it alike: by the join times (the Unix
/// milliseconds its server stamped), then the servers' ids, then the players' ids. A label both
/// show stays with the earlier ([`yields_label`]), and so does a spawn spot two newcomers took on two
/// servers at once (the later one moves: `World::came_first_near`).
#[must_use]
pub(crate) fn arrival(server: ServerId, joined_ms: u64, id: u32) -> (u64, ServerId, u32) {
    (joined_ms, server, id)
}

#[cfg(test)]
mod tests {
    use super::super::codec::{Whereabouts, encode};
    use super::*;
    use glam::Vec2;

    const MAZE: u64 = 77;

    fn bounds() -> Bounds {
        Bounds { min: Vec2::ZERO, max: Vec2::splat(100.0), cells: 50 }
    }

    fn at(x: f32) -> Whereabouts {
        Whereabouts { position: Vec2::new(x, 1.0), heading_deg: 0.0, pitch_deg: 0.0, cell: 1 }
    }

    fn p(id: u32, name: &str, x: f32) -> PlayerRecord {
        PlayerRecord {
            id,
            joined_ms: 1000 + u64::from(id),
            color: 0,
            label: 'A',
            name: name.into(),
            at: at(x),
        }
    }

    fn wire(m: &Message) -> Vec<u8> {
        let mut out = Vec::new();
        encode(m, &mut out);
        out
    }

    fn names(others: &Others) -> Vec<String> {
        others.players().map(|(s, p)| format!("{}:{}@{}", s.0, p.name, p.at.position.x)).collect()
    }

    /// The first tick is full; then only what changed, with nothing at all when nothing did; the
    /// next full one after FULL_EVERY seconds.
    #[test]
    fn the_outbox_sends_a_full_message_then_only_changes() {
        let mut out = Outbox::new(ServerId(1), MAZE);
        let (a, b) = (p(1, "alice", 1.0), p(2, "bob", 2.0));
        let first = out.tick(0.0, &[a.clone(), b.clone()], vec![], None, 0).unwrap();
        assert!(matches!(&first.body, Body::Full { players, .. } if players.len() == 2));
        assert_eq!(out.tick(0.03, &[a.clone(), b.clone()], vec![], None, 0), None, "nothing changed");
        let b2 = p(2, "bob", 3.0);
        let c = p(3, "carol", 4.0);
        let m = out.tick(0.06, &[b2.clone(), c.clone()], vec![], None, 0).unwrap();
        assert_eq!(
            m.body,
            Body::Delta {
                joined: vec![c.clone()],
                moved: vec![Move { id: 2, at: at(3.0) }],
                left: vec![1],
                finished: vec![]
            }
        );
        assert_eq!(m.seq, 2);
        let relabelled = PlayerRecord { label: 'Q', ..c.clone() };
        let m = out.tick(0.1, &[b2.clone(), relabelled.clone()], vec![], None, 0).unwrap();
        assert!(
            matches!(&m.body, Body::Delta { joined, .. } if joined == std::slice::from_ref(&relabelled)),
            "sent again whole"
        );
        assert!(matches!(out.tick(1.0, &[b2, relabelled], vec![], None, 0).unwrap().body, Body::Full { .. }));
    }

    #[test]
    fn a_finish_goes_out_at_the_next_tick_whatever_else_happens() {
        let mut out = Outbox::new(ServerId(1), MAZE);
        let a = p(1, "alice", 1.0);
        out.tick(0.0, std::slice::from_ref(&a), vec![], None, 0);
        let done = Finish { id: 1, name: "alice".into(), seconds: 12.0, won: true };
        let m = out.tick(0.5, std::slice::from_ref(&a), vec![done.clone()], None, 0).unwrap();
        assert!(matches!(&m.body, Body::Delta { finished, .. } if finished == std::slice::from_ref(&done)));
        let m = out.tick(1.0, &[a], vec![done.clone()], None, 0).unwrap();
        assert!(matches!(&m.body, Body::Full { finished, .. } if finished == &[done]), "in a full one too");
    }

    /// Two servers' outboxes into a third's view, through the wire: it sees what they have, in
    /// order; its own messages and stale ones change nothing; a bye empties a server at once.
    #[test]
    fn the_view_follows_the_other_servers_through_the_wire() {
        let mut view = Others::new(ServerId(3), MAZE, bounds());
        let (mut one, mut two) = (Outbox::new(ServerId(1), MAZE), Outbox::new(ServerId(2), MAZE));
        let m1 = one.tick(0.0, &[p(1, "alice", 1.0)], vec![], None, 0).unwrap();
        let m2 = two.tick(0.0, &[p(1, "bob", 2.0), p(2, "bea", 3.0)], vec![], None, 0).unwrap();
        assert!(view.hear(&wire(&m1), 0.0).unwrap().changed);
        assert!(view.hear(&wire(&m2), 0.0).unwrap().changed);
        assert_eq!(names(&view), ["1:alice@1", "2:bob@2", "2:bea@3"]);
        let later = two.tick(0.1, &[p(1, "bob", 5.0)], vec![], None, 0).unwrap();
        assert!(view.hear(&wire(&later), 0.1).unwrap().changed);
        assert_eq!(names(&view), ["1:alice@1", "2:bob@5"]);
        assert!(!view.hear(&wire(&m2), 0.2).unwrap().changed, "an old full message is stale");
        assert_eq!(names(&view), ["1:alice@1", "2:bob@5"]);
        let mut mine = Outbox::new(ServerId(3), MAZE);
        let own = mine.tick(0.0, &[p(1, "me", 9.0)], vec![], None, 0).unwrap();
        assert!(!view.hear(&wire(&own), 0.2).unwrap().changed);
        assert!(view.hear(&wire(&two.bye(0)), 0.3).unwrap().changed);
        assert_eq!(names(&view), ["1:alice@1"]);
        assert_eq!(view.counts(), Counts { applied: 4, own: 1, stale: 1, ..Counts::default() });
        assert!(view.hear(b"\x00garbage", 0.4).is_err());
        assert_eq!(view.counts().dropped, 1);
    }

    /// A player standing outside the cell its server names (inside the maze and naming a cell it
    /// has: what the decoder alone lets through) is dropped with its message and counted, once the
    /// view knows the maze; players in their cells, even on a cell's edge, are taken.
    #[test]
    fn a_player_outside_the_cell_it_names_is_dropped_with_its_message() {
        use mazewalk_maze::generate::{GenOptions, generate};
        let maze = Arc::new(generate(&GenOptions { width: 3, height: 2, ..GenOptions::default() }).unwrap());
        let bounds = Bounds::of(&maze);
        let (c0, c5) = (maze.cell_centroid(0), maze.cell_centroid(5));
        assert!(!maze.cell_contains(0, c5) && bounds.contains(c5), "two cells apart");
        let edge = {
            let (a, b) = maze.edge_points(maze.cell_edges(0)[0]);
            (a + b) / 2.0 // on cell 0's boundary
        };
        let player = |id: u32, position: Vec2, cell: u32| PlayerRecord {
            at: Whereabouts { position, heading_deg: 0.0, pitch_deg: 0.0, cell },
            ..p(id, "alice", 0.0)
        };
        let full = |seq: u64, players: Vec<PlayerRecord>| Message {
            maze: MAZE,
            server: ServerId(1),
            seq,
            sent_ms: 0,
            body: Body::Full { players, finished: vec![], winner: None },
        };
        let mut view = Others::new(ServerId(3), MAZE, bounds).with_maze(Arc::clone(&maze));
        assert!(view.hear(&wire(&full(1, vec![player(1, c0, 0), player(2, edge, 0)])), 0.0).unwrap().changed);
        let lying = full(2, vec![player(1, c0, 0), player(2, c5, 0)]);
        assert_eq!(view.hear(&wire(&lying), 0.1), Err(DecodeError::Misplaced(0)));
        let moved = Message {
            seq: 3,
            body: Body::Delta {
                joined: vec![],
                moved: vec![Move { id: 1, at: player(1, c5, 0).at }],
                left: vec![],
                finished: vec![],
            },
            ..full(3, vec![])
        };
        assert_eq!(view.hear(&wire(&moved), 0.2), Err(DecodeError::Misplaced(0)), "a move too");
        assert_eq!(view.counts().dropped, 2);
        assert!(view.players().all(|(_, p)| maze.cell_contains(p.at.cell, p.at.position)), "as they were");
        // Without the maze, only the extents and the cell count are checked: the same lie is taken.
        let mut blind = Others::new(ServerId(3), MAZE, bounds);
        assert!(blind.hear(&wire(&lying), 0.0).is_ok());
    }

    /// A server killed without a goodbye falls silent: its players leave everyone's view SILENCE
    /// seconds after its last message, not before; the servers still talking stay.
    #[test]
    fn a_silent_server_leaves_the_view() {
        let mut view = Others::new(ServerId(3), MAZE, bounds());
        let (mut one, mut two) = (Outbox::new(ServerId(1), MAZE), Outbox::new(ServerId(2), MAZE));
        for t in 0..=4 {
            let now = f64::from(t);
            view.hear(&wire(&one.tick(now, &[p(1, "alice", 1.0)], vec![], None, 0).unwrap()), now).unwrap();
            if t == 0 {
                view.hear(&wire(&two.tick(now, &[p(1, "bob", 1.0)], vec![], None, 0).unwrap()), now).unwrap();
            }
            let gone = view.expire(now + 0.5);
            assert_eq!(gone, t == 3, "at {now}");
            assert_eq!(view.len(), if t < 3 { 2 } else { 1 }, "at {now}");
        }
    }

    #[test]
    fn an_outage_does_not_count_as_silence() {
        let mut view = Others::new(ServerId(3), MAZE, bounds());
        let mut one = Outbox::new(ServerId(1), MAZE);
        view.hear(&wire(&one.tick(0.0, &[p(1, "alice", 1.0)], vec![], None, 0).unwrap()), 0.0).unwrap();
        // Redis away from 0.5 s to 10.5 s: expire() is not called meanwhile.
        view.reconnected(10.5);
        assert!(!view.expire(11.0));
        assert_eq!(view.len(), 1, "frozen in place, not gone");
        assert!(view.expire(10.5 + SILENCE));
    }

    /// Moves of a player whose join was missed are counted, and the next full message brings it.
    #[test]
    fn a_missed_join_is_repaired_by_the_next_full_message() {
        let mut view = Others::new(ServerId(3), MAZE, bounds());
        let mut one = Outbox::new(ServerId(1), MAZE);
        let _missed = one.tick(0.0, &[p(1, "alice", 1.0)], vec![], None, 0).unwrap();
        let moved = one.tick(0.1, &[p(1, "alice", 2.0)], vec![], None, 0).unwrap();
        assert!(!view.hear(&wire(&moved), 0.1).unwrap().changed);
        assert_eq!(view.counts().unknown, 1);
        let full = one.tick(1.0, &[p(1, "alice", 3.0)], vec![], None, 0).unwrap();
        assert!(view.hear(&wire(&full), 1.0).unwrap().changed);
        assert_eq!(names(&view), ["1:alice@3"]);
    }

    // issue #40: one writer invented 10 servers of 4,096 players each. The view keeps at most
    // `Caps::servers` servers and `Caps::players` players, counts what it left out, and frees the
    // room when a server leaves.
    #[test]
    fn the_view_keeps_within_its_caps_and_counts_the_rest() {
        let caps = Caps { servers: 3, players: 50 };
        let mut view = Others::new(ServerId(99), MAZE, bounds()).with_caps(caps);
        let mut outs: Vec<Outbox> = (1..=10).map(|k| Outbox::new(ServerId(k), MAZE)).collect();
        let crowd = |k: u32| (0..40).map(|i| p(i, &format!("s{k}p{i}"), 1.0)).collect::<Vec<_>>();
        for (k, out) in outs.iter_mut().enumerate() {
            let m = out.tick(0.0, &crowd(k as u32), vec![], None, 0).unwrap();
            view.hear(&wire(&m), 0.0).unwrap();
        }
        assert_eq!((view.servers().count(), view.len(), view.players().count()), (3, 50, 50));
        let counts = view.counts();
        assert_eq!((counts.applied, counts.over_servers, counts.over_players), (3, 7, 30 + 40));
        // A delta joining more to a full view is left out too; a move of a kept player is not.
        let mut more = crowd(0);
        more.push(p(100, "late", 2.0));
        more[0].at = at(3.0);
        let m = outs[0].tick(0.1, &more, vec![], None, 0).unwrap();
        assert!(view.hear(&wire(&m), 0.1).unwrap().changed);
        assert_eq!((view.len(), view.counts().over_players), (50, 71));
        // Finishes of players left out are not passed on.
        let finish = |id| Finish { id, name: "x".into(), seconds: 1.0, won: false };
        let m = outs[1].tick(0.2, &crowd(1), vec![finish(0), finish(39)], None, 0).unwrap();
        let heard = view.hear(&wire(&m), 0.2).unwrap();
        assert_eq!(
            heard.finished.iter().map(|f| f.id).collect::<Vec<_>>(),
            [0],
            "player 39 of server 2 is not in view"
        );
        // The first server says goodbye: room for another.
        view.hear(&wire(&outs[0].bye(0)), 0.3).unwrap();
        assert_eq!(view.len(), 10);
        let m = outs[5].tick(1.0, &crowd(5), vec![], None, 0).unwrap();
        view.hear(&wire(&m), 1.0).unwrap();
        assert_eq!((view.servers().count(), view.len()), (3, 50));
        assert!(view.expire(0.9 + SILENCE), "all but server 6 fell silent");
        assert_eq!((view.servers().count(), view.len()), (1, 40));
    }

    /// The view's count of players (kept as messages come, never summed per message) is the number
    /// it holds, and within the cap, through any sequence of full messages, deltas, goodbyes and
    /// silences from servers over the cap too.
    #[test]
    fn the_players_count_follows_any_sequence_of_messages() {
        let caps = Caps { servers: 4, players: 30 };
        let mut view = Others::new(ServerId(99), MAZE, bounds()).with_caps(caps);
        let mut outs: Vec<Outbox> = (1..=6).map(|k| Outbox::new(ServerId(k), MAZE)).collect();
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        for step in 0..3000 {
            let now = f64::from(step) * 0.05;
            let k = next(6) as usize;
            let players: Vec<PlayerRecord> =
                (0..next(16) as u32).map(|i| p(i * 2 + next(2) as u32, "x", 1.0 + next(5) as f32)).collect();
            let mut players = players;
            players.sort_by_key(|p| p.id);
            players.dedup_by_key(|p| p.id);
            let message = match next(10) {
                0 => outs[k].bye(0),
                1 => {
                    view.expire(now);
                    continue;
                }
                _ => match outs[k].tick(now, &players, vec![], None, 0) {
                    Some(m) => m,
                    None => continue,
                },
            };
            view.hear(&wire(&message), now).unwrap();
            assert_eq!(view.len(), view.players().count(), "at step {step}");
            assert!(view.len() <= caps.players && view.servers().count() <= caps.servers, "at step {step}");
        }
        let counts = view.counts();
        assert!(counts.over_players > 0 && counts.over_servers > 0, "the caps were reached: {counts:?}");
    }

    /// A finish that won is a claim, passed on as one (the world task asks Redis).
    #[test]
    fn a_winning_finish_is_a_claim() {
        let mut view = Others::new(ServerId(3), MAZE, bounds());
        let mut one = Outbox::new(ServerId(1), MAZE);
        let won = Finish { id: 1, name: "alice".into(), seconds: 9.0, won: true };
        let m = one.tick(0.0, &[p(1, "alice", 1.0)], vec![won], None, 0).unwrap();
        let heard = view.hear(&wire(&m), 0.0).unwrap();
        let claim = WinnerRecord { server: ServerId(1), id: 1, seconds: 9.0, name: "alice".into() };
        assert_eq!(heard.winner, Some(claim));
    }

    /// Of two players showing one label, whoever joined later yields, and only one of the two.
    #[test]
    fn the_later_joiner_yields_its_label() {
        let mut view = Others::new(ServerId(2), MAZE, bounds());
        let mut one = Outbox::new(ServerId(1), MAZE);
        let early = PlayerRecord { joined_ms: 10, ..p(1, "anna", 1.0) };
        let late = PlayerRecord { joined_ms: 20, ..p(1, "alan", 1.0) };
        view.hear(&wire(&one.tick(0.0, std::slice::from_ref(&early), vec![], None, 0).unwrap()), 0.0)
            .unwrap();
        assert_eq!(view.label_conflicts(std::slice::from_ref(&late)), [1]);
        let other = PlayerRecord { label: 'L', ..late.clone() };
        assert!(view.label_conflicts(&[other]).is_empty());
        assert!(yields_label((ServerId(2), &late), (ServerId(1), &early)));
        assert!(!yields_label((ServerId(1), &early), (ServerId(2), &late)));
        let unlabelled = PlayerRecord { label: '?', ..late.clone() };
        let mut two = Outbox::new(ServerId(3), MAZE);
        let other_unlabelled = PlayerRecord { label: '?', ..early.clone() };
        view.hear(&wire(&two.tick(0.0, &[other_unlabelled], vec![], None, 0).unwrap()), 0.0).unwrap();
        assert!(view.label_conflicts(&[unlabelled]).is_empty(), "`?` is everyone's");
        let same_time = PlayerRecord { joined_ms: 10, ..late };
        assert!(
            yields_label((ServerId(2), &same_time), (ServerId(1), &early))
                != yields_label((ServerId(1), &early), (ServerId(2), &same_time)),
            "exactly one yields"
        );
    }
}
