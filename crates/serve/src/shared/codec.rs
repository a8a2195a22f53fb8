//! The shared world's wire format: what one server publishes about its players, and what it stores
//! as its presence and as the winner. Small, binary, little-endian, versioned; pure.
//!
//! Every message starts with the same 36-byte header:
//!
//! ```text
//! "MW" | version u8 | kind u8 | maze tag u64 | server u64 | seq u64 | sent_ms u64
//! ```
//!
//! then, by kind:
//!
//! ```text
//! Full   players: u16 + Player*  finished: u16 + Finish*  winner: u8 (0|1) + Winner?
//!                                                                 everyone on the server, now
//! Delta  joined: u16 + Player*  moved: u16 + Move*  left: u16 + id u32*  finished: u16 + Finish*
//! Bye    (nothing)                                                 the server is stopping
//!
//! Player  id u32 | joined_ms u64 | colour u8 | label u8 | name: u8 + bytes | Whereabouts
//! Move    id u32 | Whereabouts
//! Where…  x f32 | y f32 | heading_deg f32 | pitch_deg f32 | cell u32                (20 bytes)
//! Finish  id u32 | seconds f64 | won u8 (0|1) | name: u8 + bytes
//! Winner  server u64 | id u32 | seconds f64 | name: u8 + bytes
//! ```
//!
//! A message from Redis is untrusted input (anyone with the Redis password can publish):
//! [`decode`] checks the size before anything else ([`MAX_MESSAGE_BYTES`]), every count against
//! [`MAX_PLAYERS`] and against the bytes left before it allocates, every name against the rule
//! [`player_name`] applies to SSH user names, every label and colour against those a server hands
//! out, every number for finiteness, every position against the maze's extents and every cell
//! against its cell count ([`Bounds`]); a server's view of the others then checks each position
//! against the cell it names ([`Others::with_maze`](super::view::Others::with_maze)). Whatever fails
//! is a [`DecodeError`]: the caller drops the message and counts it. The `world_codec` fuzz target
//! holds it to that.

use glam::Vec2;
use thiserror::Error;

use crate::identity::PLAYER_COLORS;
use crate::identity::{MAX_NAME, player_name};
use mazewalk_maze::Maze;

/// The two bytes every message starts with.
pub const MAGIC: [u8; 2] = *b"MW";
/// The format's version; a message of another version is dropped (and counted).
pub const VERSION: u8 = 1;
/// The header's length in bytes.
pub const HEADER_BYTES: usize = 36;
/// The longest message decoded: a full message of [`MAX_PLAYERS`] players with the longest names
/// fits (4,096 × 51 bytes ≈ 204 KiB); anything longer is dropped unread.
pub(crate) const MAX_MESSAGE_BYTES: usize = 256 * 1024;
/// The most players (or moves, leaves, finishes) in one list of one message.
pub const MAX_PLAYERS: usize = 4096;
/// The largest |heading| accepted, degrees (a server sends [0, 360]; the rest is wrapped into it).
const MAX_HEADING_DEG: f32 = 1.0e4;
/// The largest |pitch|, degrees.
const MAX_PITCH_DEG: f32 = 90.0;
/// The longest walk accepted as a finish, seconds (a year).
const MAX_SECONDS: f64 = 365.0 * 24.0 * 3600.0;
/// How far outside the maze's extents a position may be, maze units (rounding only: a viewer stays
/// inside its cell).
const EXTENTS_SLACK: f32 = 1.0e-3;

/// One server's id in the world: random, new at every start.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ServerId(pub u64);

/// Where a player is: position (maze plane), heading and pitch (degrees), cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Whereabouts {
    /// Where it stands (maze plane).
    pub position: Vec2,
    /// Which way it faces, degrees counter-clockwise from +x, in [0, 360).
    pub heading_deg: f32,
    /// How far it looks up (+) or down (−), degrees.
    pub pitch_deg: f32,
    /// The cell it stands in.
    pub cell: u32,
}

/// A player as the other servers learn of it.
#[derive(Clone, Debug, PartialEq)]
pub struct PlayerRecord {
    /// Its id on its server.
    pub id: u32,
    /// When it joined, milliseconds since the Unix epoch by its server's clock (who came first
    /// keeps a label both want: [`yields_label`](super::view::yields_label)).
    pub joined_ms: u64,
    /// Its colour: an index into [`PLAYER_COLORS`].
    pub color: u8,
    /// The character it is shown by: an ASCII digit, an upper-case ASCII letter, or `?`.
    pub label: char,
    /// Its name, as [`player_name`] makes them.
    pub name: String,
    /// Where it is.
    pub at: Whereabouts,
}

/// A player that moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// Its id on its server.
    pub id: u32,
    /// Where it is now.
    pub at: Whereabouts,
}

/// A player reached the exit.
#[derive(Clone, Debug, PartialEq)]
pub struct Finish {
    /// Its id on its server.
    pub id: u32,
    /// Its name.
    pub name: String,
    /// How long its walk took, seconds.
    pub seconds: f64,
    /// It was the first in the world: its server's claim on the winner succeeded.
    pub won: bool,
}

/// The first player at the exit, as stored under the world's winner key and sent in full messages.
#[derive(Clone, Debug, PartialEq)]
pub struct WinnerRecord {
    /// The winner's server.
    pub server: ServerId,
    /// Its id on that server.
    pub id: u32,
    /// How long its walk took, seconds.
    pub seconds: f64,
    /// Its name.
    pub name: String,
}

/// What a message says.
#[derive(Clone, Debug, PartialEq)]
pub enum Body {
    /// Everyone on the server now (what the receiver knew of that server is replaced), and the
    /// winner as the server knows it.
    Full {
        /// Every player.
        players: Vec<PlayerRecord>,
        /// Players that reached the exit since the server's last message.
        finished: Vec<Finish>,
        /// The world's winner, if the server knows one.
        winner: Option<WinnerRecord>,
    },
    /// What changed since the server's last message.
    Delta {
        /// Players new to the others (or whose name, colour or label changed).
        joined: Vec<PlayerRecord>,
        /// Players that moved.
        moved: Vec<Move>,
        /// Ids of players that left.
        left: Vec<u32>,
        /// Players that reached the exit.
        finished: Vec<Finish>,
    },
    /// The server is stopping: its players are gone.
    Bye,
}

/// One message from one server.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    /// The maze's tag ([`maze_tag`]): a message about another maze is dropped.
    pub maze: u64,
    /// Who sent it.
    pub server: ServerId,
    /// The sender's count of its messages, from 1: a message older than one already heard from the
    /// same server is dropped.
    pub seq: u64,
    /// When it was sent, milliseconds since the Unix epoch by the sender's clock (latency figures
    /// only: nothing depends on clocks agreeing).
    pub sent_ms: u64,
    /// What it says.
    pub body: Body,
}

/// What positions and cells are valid: the maze's extents and cell count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// The smallest x and y of any vertex.
    pub min: Vec2,
    /// The largest x and y of any vertex.
    pub max: Vec2,
    /// How many cells the maze has.
    pub cells: u32,
}

impl Bounds {
    /// The bounds of `maze`.
    #[must_use]
    pub fn of(maze: &Maze) -> Bounds {
        let extents = maze.extents();
        let cells = u32::try_from(maze.cell_count()).unwrap_or(u32::MAX);
        Bounds { min: extents.min, max: extents.max, cells }
    }

    pub(crate) fn contains(&self, p: Vec2) -> bool {
        p.cmpge(self.min - EXTENTS_SLACK).all() && p.cmple(self.max + EXTENTS_SLACK).all()
    }
}

/// The 64-bit tag of a maze's content hash (FNV-1a of its text): stamped on every message so that a
/// message meant for another maze's world is dropped even on a shared channel.
#[must_use]
pub fn maze_tag(maze_hash: &str) -> u64 {
    maze_hash.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// Why a message was dropped.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
pub enum DecodeError {
    /// Longer than [`MAX_MESSAGE_BYTES`].
    #[error("{0} bytes, over the {max} limit", max = MAX_MESSAGE_BYTES)]
    TooLong(usize),
    /// It ends inside a field.
    #[error("cut short")]
    Truncated,
    /// Bytes left after the last field.
    #[error("{0} bytes after the end")]
    Trailing(usize),
    /// Not a mazewalk message.
    #[error("not a mazewalk message")]
    Magic,
    /// A format version this server does not read.
    #[error("format version {0} (this server reads {VERSION})")]
    Version(u8),
    /// An unknown kind of message.
    #[error("unknown kind {0}")]
    Kind(u8),
    /// About another maze.
    #[error("about another maze")]
    OtherMaze,
    /// A list longer than [`MAX_PLAYERS`], or than the bytes left could hold.
    #[error("a list of {0}")]
    Count(usize),
    /// A name that is empty, too long, or has characters a name cannot have.
    #[error("a malformed name")]
    Name,
    /// A label that is not a digit, an upper-case letter or `?`.
    #[error("a malformed label")]
    Label,
    /// A colour outside the palette.
    #[error("colour {0} outside the palette")]
    Color(u8),
    /// A flag other than 0 or 1.
    #[error("a malformed flag")]
    Flag,
    /// A coordinate, heading, pitch or time that is not finite or out of range.
    #[error("a number out of range")]
    Number,
    /// A position outside the maze.
    #[error("a position outside the maze")]
    Outside,
    /// A cell the maze does not have.
    #[error("cell {0} is not in the maze")]
    Cell(u32),
    /// A position outside the cell it is said to be in (checked where the maze itself is known:
    /// [`Others::with_maze`](super::view::Others::with_maze)). A server moves its players cell to
    /// cell, so each is always inside the one it names.
    #[error("a position outside its cell {0}")]
    Misplaced(u32),
}

const FULL: u8 = 1;
const DELTA: u8 = 2;
const BYE: u8 = 3;

/// The message's bytes, appended to `out`.
///
/// # Panics
/// A list longer than [`MAX_PLAYERS`], or a name longer than 255 bytes: the server never sends
/// those (it holds at most `--max-players` players, whose names are [`player_name`]s).
pub fn encode(message: &Message, out: &mut Vec<u8>) {
    out.extend_from_slice(&MAGIC);
    out.push(VERSION);
    out.push(match message.body {
        Body::Full { .. } => FULL,
        Body::Delta { .. } => DELTA,
        Body::Bye => BYE,
    });
    for n in [message.maze, message.server.0, message.seq, message.sent_ms] {
        out.extend_from_slice(&n.to_le_bytes());
    }
    match &message.body {
        Body::Full { players, finished, winner } => {
            list(out, players, put_player);
            list(out, finished, put_finish);
            match winner {
                Some(w) => {
                    out.push(1);
                    put_winner(out, w);
                }
                None => out.push(0),
            }
        }
        Body::Delta { joined, moved, left, finished } => {
            list(out, joined, put_player);
            list(out, moved, |out, m| {
                out.extend_from_slice(&m.id.to_le_bytes());
                put_at(out, &m.at);
            });
            list(out, left, |out, id| out.extend_from_slice(&id.to_le_bytes()));
            list(out, finished, put_finish);
        }
        Body::Bye => {}
    }
}

/// A winner record's bytes (the value of the world's winner key).
#[must_use]
pub fn encode_winner(winner: &WinnerRecord) -> Vec<u8> {
    let mut out = Vec::with_capacity(21 + winner.name.len());
    put_winner(&mut out, winner);
    out
}

/// Reads a winner record (the value of the world's winner key).
///
/// # Errors
/// As [`decode`], for the record's fields.
pub fn decode_winner(bytes: &[u8]) -> Result<WinnerRecord, DecodeError> {
    if bytes.len() > MAX_MESSAGE_BYTES {
        return Err(DecodeError::TooLong(bytes.len()));
    }
    let mut r = Reader { bytes };
    let winner = r.winner()?;
    r.end()?;
    Ok(winner)
}

fn list<T>(out: &mut Vec<u8>, items: &[T], mut put: impl FnMut(&mut Vec<u8>, &T)) {
    assert!(items.len() <= MAX_PLAYERS, "a list of {} (at most {MAX_PLAYERS})", items.len());
    out.extend_from_slice(&(items.len() as u16).to_le_bytes());
    for item in items {
        put(out, item);
    }
}

fn put_name(out: &mut Vec<u8>, name: &str) {
    let len = u8::try_from(name.len()).expect("a player name is short");
    out.push(len);
    out.extend_from_slice(name.as_bytes());
}

fn put_at(out: &mut Vec<u8>, at: &Whereabouts) {
    for f in [at.position.x, at.position.y, at.heading_deg, at.pitch_deg] {
        out.extend_from_slice(&f.to_le_bytes());
    }
    out.extend_from_slice(&at.cell.to_le_bytes());
}

fn put_player(out: &mut Vec<u8>, p: &PlayerRecord) {
    out.extend_from_slice(&p.id.to_le_bytes());
    out.extend_from_slice(&p.joined_ms.to_le_bytes());
    out.push(p.color);
    out.push(u8::try_from(p.label).unwrap_or(b'?'));
    put_name(out, &p.name);
    put_at(out, &p.at);
}

fn put_finish(out: &mut Vec<u8>, f: &Finish) {
    out.extend_from_slice(&f.id.to_le_bytes());
    out.extend_from_slice(&f.seconds.to_le_bytes());
    out.push(u8::from(f.won));
    put_name(out, &f.name);
}

fn put_winner(out: &mut Vec<u8>, w: &WinnerRecord) {
    out.extend_from_slice(&w.server.0.to_le_bytes());
    out.extend_from_slice(&w.id.to_le_bytes());
    out.extend_from_slice(&w.seconds.to_le_bytes());
    put_name(out, &w.name);
}

/// The smallest encoding of one item of each list: what a count is checked against before any
/// allocation.
const MIN_PLAYER: usize = 4 + 8 + 1 + 1 + 2 + WHEREABOUTS; // a one-byte name
const MIN_MOVE: usize = 4 + WHEREABOUTS;
const MIN_FINISH: usize = 4 + 8 + 1 + 2;
const WHEREABOUTS: usize = 20;

/// Reads a message about the maze tagged `maze` (bounded by `bounds`), validating every field.
///
/// # Errors
/// The message is too long, cut short, of another version, maze or kind, or holds a field out of
/// bounds ([`DecodeError`]).
pub fn decode(bytes: &[u8], maze: u64, bounds: &Bounds) -> Result<Message, DecodeError> {
    if bytes.len() > MAX_MESSAGE_BYTES {
        return Err(DecodeError::TooLong(bytes.len()));
    }
    let mut r = Reader { bytes };
    if r.take(2)? != MAGIC {
        return Err(DecodeError::Magic);
    }
    let version = r.u8()?;
    if version != VERSION {
        return Err(DecodeError::Version(version));
    }
    let kind = r.u8()?;
    let tag = r.u64()?;
    let server = ServerId(r.u64()?);
    let (seq, sent_ms) = (r.u64()?, r.u64()?);
    if tag != maze {
        return Err(DecodeError::OtherMaze);
    }
    let body = match kind {
        FULL => {
            let players = r.list(MIN_PLAYER, |r| r.player(bounds))?;
            let finished = r.list(MIN_FINISH, Reader::finish)?;
            let winner = if r.flag()? { Some(r.winner()?) } else { None };
            Body::Full { players, finished, winner }
        }
        DELTA => Body::Delta {
            joined: r.list(MIN_PLAYER, |r| r.player(bounds))?,
            moved: r.list(MIN_MOVE, |r| Ok(Move { id: r.u32()?, at: r.at(bounds)? }))?,
            left: r.list(4, Reader::u32)?,
            finished: r.list(MIN_FINISH, Reader::finish)?,
        },
        BYE => Body::Bye,
        other => return Err(DecodeError::Kind(other)),
    };
    r.end()?;
    Ok(Message { maze: tag, server, seq, sent_ms, body })
}

/// A cursor over untrusted bytes.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        if n > self.bytes.len() {
            return Err(DecodeError::Truncated);
        }
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Ok(head)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], DecodeError> {
        Ok(self.take(N)?.try_into().expect("N bytes"))
    }

    fn u8(&mut self) -> Result<u8, DecodeError> {
        Ok(self.array::<1>()?[0])
    }

    fn u32(&mut self) -> Result<u32, DecodeError> {
        self.array().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, DecodeError> {
        self.array().map(u64::from_le_bytes)
    }

    fn f32(&mut self) -> Result<f32, DecodeError> {
        let f = f32::from_le_bytes(self.array()?);
        if f.is_finite() { Ok(f) } else { Err(DecodeError::Number) }
    }

    fn flag(&mut self) -> Result<bool, DecodeError> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(DecodeError::Flag),
        }
    }

    fn seconds(&mut self) -> Result<f64, DecodeError> {
        let s = f64::from_le_bytes(self.array()?);
        if (0.0..=MAX_SECONDS).contains(&s) { Ok(s) } else { Err(DecodeError::Number) }
    }

    /// A count, then that many items of at least `min_size` bytes each: the count is checked
    /// against [`MAX_PLAYERS`] and the bytes left before anything is allocated.
    fn list<T>(
        &mut self,
        min_size: usize,
        mut item: impl FnMut(&mut Self) -> Result<T, DecodeError>,
    ) -> Result<Vec<T>, DecodeError> {
        let n = usize::from(u16::from_le_bytes(self.array()?));
        if n > MAX_PLAYERS || n * min_size > self.bytes.len() {
            return Err(DecodeError::Count(n));
        }
        let mut items = Vec::with_capacity(n);
        for _ in 0..n {
            items.push(item(self)?);
        }
        Ok(items)
    }

    fn name(&mut self) -> Result<String, DecodeError> {
        let len = usize::from(self.u8()?);
        if len == 0 || len > MAX_NAME {
            return Err(DecodeError::Name);
        }
        let bytes = self.take(len)?;
        let name = std::str::from_utf8(bytes).map_err(|_| DecodeError::Name)?;
        // The rule SSH user names go through: nothing else can reach another player's screen.
        if player_name(name) != name {
            return Err(DecodeError::Name);
        }
        Ok(name.to_owned())
    }

    fn at(&mut self, bounds: &Bounds) -> Result<Whereabouts, DecodeError> {
        let position = Vec2::new(self.f32()?, self.f32()?);
        let (heading_deg, pitch_deg) = (self.f32()?, self.f32()?);
        let cell = self.u32()?;
        if heading_deg.abs() > MAX_HEADING_DEG || pitch_deg.abs() > MAX_PITCH_DEG {
            return Err(DecodeError::Number);
        }
        if !bounds.contains(position) {
            return Err(DecodeError::Outside);
        }
        if cell >= bounds.cells {
            return Err(DecodeError::Cell(cell));
        }
        // `rem_euclid` of a tiny negative heading rounds to 360.0 itself in f32: that is 0.
        let heading_deg = Some(heading_deg.rem_euclid(360.0)).filter(|&h| h < 360.0).unwrap_or(0.0);
        Ok(Whereabouts { position, heading_deg, pitch_deg, cell })
    }

    fn player(&mut self, bounds: &Bounds) -> Result<PlayerRecord, DecodeError> {
        let (id, joined_ms) = (self.u32()?, self.u64()?);
        let color = self.u8()?;
        if usize::from(color) >= PLAYER_COLORS.len() {
            return Err(DecodeError::Color(color));
        }
        let label = char::from(self.u8()?);
        if !is_label(label) {
            return Err(DecodeError::Label);
        }
        let name = self.name()?;
        Ok(PlayerRecord { id, joined_ms, color, label, name, at: self.at(bounds)? })
    }

    fn finish(&mut self) -> Result<Finish, DecodeError> {
        let (id, seconds, won) = (self.u32()?, self.seconds()?, self.flag()?);
        Ok(Finish { id, seconds, won, name: self.name()? })
    }

    fn winner(&mut self) -> Result<WinnerRecord, DecodeError> {
        let (server, id, seconds) = (ServerId(self.u64()?), self.u32()?, self.seconds()?);
        Ok(WinnerRecord { server, id, seconds, name: self.name()? })
    }

    fn end(&self) -> Result<(), DecodeError> {
        if self.bytes.is_empty() { Ok(()) } else { Err(DecodeError::Trailing(self.bytes.len())) }
    }
}

/// Whether `c` is a label a server hands out: an ASCII digit, an upper-case ASCII letter, or `?`.
#[must_use]
pub(crate) fn is_label(c: char) -> bool {
    c.is_ascii_digit() || c.is_ascii_uppercase() || c == '?'
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bounds() -> Bounds {
        Bounds { min: Vec2::ZERO, max: Vec2::new(10.0, 5.0), cells: 12 }
    }

    fn at(x: f32, y: f32, cell: u32) -> Whereabouts {
        Whereabouts { position: Vec2::new(x, y), heading_deg: 90.0, pitch_deg: -10.0, cell }
    }

    fn player(id: u32, name: &str, label: char) -> PlayerRecord {
        PlayerRecord {
            id,
            joined_ms: 1_700_000_000_000 + u64::from(id),
            color: 3,
            label,
            name: name.into(),
            at: at(1.5, 2.5, 4),
        }
    }

    fn message(body: Body) -> Message {
        Message { maze: maze_tag("abc"), server: ServerId(42), seq: 7, sent_ms: 99, body }
    }

    fn bytes(m: &Message) -> Vec<u8> {
        let mut out = Vec::new();
        encode(m, &mut out);
        out
    }

    fn winner() -> WinnerRecord {
        WinnerRecord { server: ServerId(9), id: 2, seconds: 83.5, name: "bob".into() }
    }

    fn every_kind() -> Vec<Message> {
        vec![
            message(Body::Full {
                players: vec![player(1, "alice", 'A'), player(2, "bob.b-2_", '2')],
                finished: vec![Finish { id: 2, name: "bob.b-2_".into(), seconds: 83.5, won: false }],
                winner: Some(winner()),
            }),
            message(Body::Full { players: vec![], finished: vec![], winner: None }),
            message(Body::Delta {
                joined: vec![player(3, "carol", 'C')],
                moved: vec![Move { id: 1, at: at(9.0, 4.0, 11) }],
                left: vec![2, 5],
                finished: vec![Finish { id: 1, name: "alice".into(), seconds: 61.25, won: true }],
            }),
            message(Body::Bye),
        ]
    }

    #[test]
    fn every_kind_reads_back_as_written() {
        for m in every_kind() {
            let b = bytes(&m);
            assert_eq!(decode(&b, maze_tag("abc"), &bounds()), Ok(m.clone()), "{m:?}");
        }
        let w = winner();
        assert_eq!(decode_winner(&encode_winner(&w)), Ok(w));
    }

    /// A mover costs 24 bytes: 100 walkers at 30 ticks a second are 72 KB/s of moves.
    #[test]
    fn a_move_costs_24_bytes_and_the_header_36() {
        let delta =
            |moved: Vec<Move>| message(Body::Delta { joined: vec![], moved, left: vec![], finished: vec![] });
        let (none, one) = (bytes(&delta(vec![])), bytes(&delta(vec![Move { id: 1, at: at(1.0, 1.0, 0) }])));
        assert_eq!(none.len(), HEADER_BYTES + 8);
        assert_eq!(one.len() - none.len(), MIN_MOVE);
        assert_eq!(MIN_MOVE, 24);
    }

    #[test]
    fn every_cut_of_a_message_is_refused_without_a_panic() {
        for m in every_kind() {
            let b = bytes(&m);
            for len in 0..b.len() {
                assert!(decode(&b[..len], maze_tag("abc"), &bounds()).is_err(), "{len} of {}", b.len());
            }
            let mut longer = b.clone();
            longer.push(0);
            assert_eq!(decode(&longer, maze_tag("abc"), &bounds()), Err(DecodeError::Trailing(1)));
        }
    }

    #[test]
    fn a_message_over_the_limit_is_refused_unread() {
        let big = vec![0u8; 1 << 20];
        assert_eq!(decode(&big, 0, &bounds()), Err(DecodeError::TooLong(1 << 20)));
    }

    #[test]
    fn another_version_maze_or_kind_is_refused() {
        let b = bytes(&message(Body::Bye));
        assert_eq!(decode(&b, maze_tag("abd"), &bounds()), Err(DecodeError::OtherMaze));
        let mut v2 = b.clone();
        v2[2] = 2;
        assert_eq!(decode(&v2, maze_tag("abc"), &bounds()), Err(DecodeError::Version(2)));
        let mut kind = b.clone();
        kind[3] = 9;
        assert_eq!(decode(&kind, maze_tag("abc"), &bounds()), Err(DecodeError::Kind(9)));
        assert_eq!(decode(b"garbage garbage garbage garbage garbage", 0, &bounds()), Err(DecodeError::Magic));
    }

    /// A count is checked against the bytes left before a list is allocated: 4,096 players claimed
    /// by a 40-byte message allocate nothing.
    #[test]
    fn a_count_larger_than_the_bytes_left_is_refused_before_allocating() {
        let mut b = bytes(&message(Body::Full { players: vec![], finished: vec![], winner: None }));
        b[HEADER_BYTES..HEADER_BYTES + 2].copy_from_slice(&4096u16.to_le_bytes());
        assert_eq!(decode(&b, maze_tag("abc"), &bounds()), Err(DecodeError::Count(4096)));
        b[HEADER_BYTES..HEADER_BYTES + 2].copy_from_slice(&5000u16.to_le_bytes());
        b.resize(MAX_MESSAGE_BYTES, 0);
        assert_eq!(decode(&b, maze_tag("abc"), &bounds()), Err(DecodeError::Count(5000)), "over the cap");
    }

    /// Each field out of bounds, in a message otherwise fine.
    #[test]
    fn fields_out_of_bounds_are_refused() {
        let full = |p: PlayerRecord| message(Body::Full { players: vec![p], finished: vec![], winner: None });
        let check = |p: PlayerRecord, want: DecodeError| {
            assert_eq!(decode(&bytes(&full(p.clone())), maze_tag("abc"), &bounds()), Err(want), "{p:?}");
        };
        check(PlayerRecord { at: at(10.5, 2.0, 1), ..player(1, "a", 'A') }, DecodeError::Outside);
        check(PlayerRecord { at: at(-1.0, 2.0, 1), ..player(1, "a", 'A') }, DecodeError::Outside);
        check(PlayerRecord { at: at(1.0, 2.0, 12), ..player(1, "a", 'A') }, DecodeError::Cell(12));
        check(PlayerRecord { at: at(f32::NAN, 2.0, 1), ..player(1, "a", 'A') }, DecodeError::Number);
        check(PlayerRecord { at: at(1.0, f32::INFINITY, 1), ..player(1, "a", 'A') }, DecodeError::Number);
        let tilted = Whereabouts { pitch_deg: 91.0, ..at(1.0, 1.0, 1) };
        check(PlayerRecord { at: tilted, ..player(1, "a", 'A') }, DecodeError::Number);
        check(
            PlayerRecord { color: PLAYER_COLORS.len() as u8, ..player(1, "a", 'A') },
            DecodeError::Color(8),
        );
        check(player(1, "a", 'a'), DecodeError::Label);
        check(player(1, "a", '\x1b'), DecodeError::Label);
        check(player(1, "\x1b[2J", 'A'), DecodeError::Name);
        check(player(1, "ünï", 'A'), DecodeError::Name);
        check(player(1, &"x".repeat(MAX_NAME + 1), 'A'), DecodeError::Name);
        let mut empty = bytes(&full(player(1, "a", 'A')));
        let name_at = HEADER_BYTES + 2 + 4 + 8 + 2;
        empty[name_at] = 0;
        assert_eq!(decode(&empty, maze_tag("abc"), &bounds()), Err(DecodeError::Name));
        let slow = Finish { id: 1, name: "a".into(), seconds: -1.0, won: false };
        let delta =
            message(Body::Delta { joined: vec![], moved: vec![], left: vec![], finished: vec![slow] });
        assert_eq!(decode(&bytes(&delta), maze_tag("abc"), &bounds()), Err(DecodeError::Number));
    }

    #[test]
    fn headings_are_wrapped_into_a_turn() {
        // The heading a move sent as `heading_deg` is read back as.
        let read_as = |heading_deg: f32| {
            let at = Whereabouts { heading_deg, ..at(1.0, 1.0, 1) };
            let m = message(Body::Delta {
                joined: vec![],
                moved: vec![Move { id: 1, at }],
                left: vec![],
                finished: vec![],
            });
            let Ok(Message { body: Body::Delta { moved, .. }, .. }) =
                decode(&bytes(&m), maze_tag("abc"), &bounds())
            else {
                panic!("decodes");
            };
            moved[0].at.heading_deg
        };
        assert_eq!(read_as(-90.0), 270.0);
        // A heading a hair below zero wraps to 360.0 in f32 arithmetic: it is read as 0 (found by
        // the fuzz target `world_codec`).
        assert_eq!(read_as(-1e-6), 0.0);
    }

    #[test]
    fn the_bounds_of_the_builtin_maze_hold_its_start() {
        let maze = mazewalk_maze::builtin().unwrap();
        let b = Bounds::of(&maze);
        assert!(b.contains(maze.viewer().pos));
        assert_eq!(b.cells as usize, maze.cell_count());
    }
}
