//! A maze's identity: [`Maze::content_hash`], the SHA-256 of everything that decides a walk through it
//! — its plan (vertices, walls and openings, cells), its start and its exit — in a canonical binary
//! form, so that the same maze has the same hash however it was written (a CS559 file, a grid file,
//! `--gen` with the same size and seed) and on every platform. A server keeps its best times under it.
//!
//! The form, version 1, all integers little-endian, each `f32` as its IEEE bits with −0 written as +0:
//!
//! ```text
//! "mazewalk-maze-v1\n"
//! u64 vertex count, then x, y per vertex                         (f32, f32)
//! u64 edge count, then start, end, left, right, opaque per edge  (u32, u32, u32, u32, u8; no cell = u32::MAX)
//! u64 cell count, then per cell its edge count and edge ids       (u32, u32…)
//! the viewer: x, y, eye height, heading, field of view           (5 × f32)
//! the exit: 0 | 1 cell | 2 cell x y                               (u8 [u32 [f32 f32]])
//! ```
//!
//! Wall colours are left out: recolouring a maze keeps its records.

use sha2::{Digest, Sha256};

use super::Maze;

/// A maze's [`content_hash`](Maze::content_hash): 32 bytes, shown as 64 lower-case hex digits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ContentHash(pub [u8; 32]);

impl std::fmt::Display for ContentHash {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.iter().try_for_each(|b| write!(f, "{b:02x}"))
    }
}

/// Feeds the canonical form to a hasher, in pieces.
struct Canonical(Sha256);

impl Canonical {
    fn bytes(&mut self, b: &[u8]) {
        self.0.update(b);
    }

    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }

    fn f32(&mut self, v: f32) {
        self.u32((v + 0.0).to_bits()); // −0 + 0 = +0: one form for zero
    }
}

impl Maze {
    /// The SHA-256 of the maze's plan, start and exit in the canonical form of [`hash`](self) (wall
    /// colours left out): the same maze, however written, has the same hash. Linear in the maze's
    /// size; a 1000 × 1000 maze takes a few tenths of a second.
    #[must_use]
    pub fn content_hash(&self) -> ContentHash {
        let side = |c: Option<u32>| c.unwrap_or(u32::MAX);
        let mut h = Canonical(Sha256::new());
        h.bytes(b"mazewalk-maze-v1\n");
        h.u64(self.vertices().len() as u64);
        for v in self.vertices() {
            h.f32(v.x);
            h.f32(v.y);
        }
        h.u64(self.edges().len() as u64);
        for e in self.edges().iter() {
            h.u32(e.start);
            h.u32(e.end);
            h.u32(side(e.left));
            h.u32(side(e.right));
            h.bytes(&[u8::from(e.opaque)]);
        }
        h.u64(self.cell_count() as u64);
        for c in 0..self.cell_count() as u32 {
            let edges = self.cell_edges(c);
            h.u32(edges.len() as u32);
            edges.iter().for_each(|&e| h.u32(e));
        }
        let v = self.viewer();
        [v.pos.x, v.pos.y, v.z, v.dir_deg, v.fov_deg].into_iter().for_each(|x| h.f32(x));
        match self.exit() {
            None => h.bytes(&[0]),
            Some(exit) => match exit.point {
                None => {
                    h.bytes(&[1]);
                    h.u32(exit.cell);
                }
                Some(p) => {
                    h.bytes(&[2]);
                    h.u32(exit.cell);
                    h.f32(p.x);
                    h.f32(p.y);
                }
            },
        }
        ContentHash(h.0.finalize().into())
    }
}

#[cfg(test)]
mod tests {
    use crate::generate::{GenOptions, generate};
    use crate::{Format, parse, write};

    /// The same maze written either way, or generated twice, has one hash; any change to its plan,
    /// start or exit gives another; its colours do not count.
    #[test]
    fn the_same_maze_has_one_hash_and_any_change_another() {
        let opts = GenOptions { width: 6, height: 4, seed: 3, exit: true, ..GenOptions::default() };
        let maze = generate(&opts).unwrap();
        let hash = maze.content_hash();
        assert_eq!(hash, generate(&opts).unwrap().content_hash(), "deterministic");
        let text = write(&maze, Format::Cs559).unwrap();
        assert_eq!(
            parse("again.maze", text.as_bytes()).unwrap().content_hash(),
            hash,
            "written and read back"
        );
        assert_eq!(hash.to_string().len(), 64);
        assert!(hash.to_string().chars().all(|c| c.is_ascii_hexdigit() && !c.is_ascii_uppercase()));
        let other = GenOptions { seed: 4, ..opts };
        assert_ne!(generate(&other).unwrap().content_hash(), hash, "another maze");
        // the start moved a little: another race
        let moved = text.lines().rev().find(|l| l.split_whitespace().count() == 5).unwrap().to_string();
        let fields: Vec<f32> = moved.split_whitespace().map(|f| f.parse().unwrap()).collect();
        let nudged = format!("{} {} {} {} {}", fields[0] + 0.125, fields[1], fields[2], fields[3], fields[4]);
        let start_moved = text.replace(&moved, &nudged);
        assert_ne!(parse("moved.maze", start_moved.as_bytes()).unwrap().content_hash(), hash);
        // recoloured: the same race
        let edge = text.lines().find(|l| l.split_whitespace().count() == 8).unwrap();
        let fields: Vec<&str> = edge.split_whitespace().collect();
        let recoloured = format!("{} 0.25 0.25 0.25", fields[..5].join(" "));
        let colours = text.replacen(edge, &recoloured, 1);
        assert_ne!(colours, text, "the premise: some wall's colour changed");
        assert_eq!(parse("recoloured.maze", colours.as_bytes()).unwrap().content_hash(), hash);
    }

    /// One room's hash, pinned: the canonical form must not change unnoticed (every server's records
    /// are kept under these hashes). A deliberate change bumps the form's version.
    #[test]
    fn the_canonical_form_is_pinned() {
        let room = "4  0 0  4 0  0 4  4 4
                    4  0 1 0 -1 1 .5 .5 .5   2 3 -1 0 1 .5 .5 .5   0 2 -1 0 1 .5 .5 .5   1 3 0 -1 1 .5 .5 .5
                    1  3 1 2 0
                    2 2 0 90 90";
        let hash = parse("room.maze", room.as_bytes()).unwrap().content_hash().to_string();
        // (computed from the form above by an independent Python script: hashlib.sha256 over struct.pack)
        assert_eq!(hash, "1e12b8a1159fe414a5aece15b4f20e17e746d599c9934558d8c138b855aa1b9b");
    }
}
