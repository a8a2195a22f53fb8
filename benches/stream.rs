//! A terminal stream's bytes by kind, for the tools that split a walk's bytes (`walk_bytes`,
//! `palette_bytes`) and the encoder benchmark's report.

/// Bytes of a stream by kind: SGR (and how many), erasures (`CSI K`, `CSI J`), cursor moves (the other
/// CSI sequences but private modes, and `\r`, `\n`, backspace), sync and cursor markers (private
/// modes: `CSI ? …`), glyphs.
#[derive(Clone, Copy, Default, Debug)]
pub struct Kinds {
    /// Bytes of SGR sequences.
    pub sgr: usize,
    /// How many SGR sequences.
    pub sgr_count: usize,
    /// Bytes of cursor moves.
    pub moves: usize,
    /// Bytes of erasures.
    pub erase: usize,
    /// Bytes of private-mode sequences (synchronized output's markers).
    pub markers: usize,
    /// Bytes of everything else: the glyphs.
    pub glyphs: usize,
}

impl Kinds {
    /// Counts `bytes` in.
    pub fn add(&mut self, bytes: &[u8]) {
        let mut i = 0;
        while i < bytes.len() {
            if bytes[i] == 0x1b && bytes.get(i + 1) == Some(&b'[') {
                let end = (i + 2..bytes.len())
                    .find(|&j| (0x40..0x7f).contains(&bytes[j]))
                    .unwrap_or(bytes.len() - 1);
                let len = end + 1 - i;
                match (bytes[end], bytes.get(i + 2)) {
                    (b'm', _) => (self.sgr, self.sgr_count) = (self.sgr + len, self.sgr_count + 1),
                    (b'K' | b'J', _) => self.erase += len,
                    (_, Some(b'?')) => self.markers += len,
                    _ => self.moves += len,
                }
                i = end + 1;
            } else if matches!(bytes[i], b'\r' | b'\n' | 0x08) {
                self.moves += 1;
                i += 1;
            } else {
                self.glyphs += 1;
                i += 1;
            }
        }
    }

    /// The bytes of `bytes`, by kind.
    pub fn of(bytes: &[u8]) -> Kinds {
        let mut kinds = Kinds::default();
        kinds.add(bytes);
        kinds
    }

    /// Adds the counts of `other`.
    pub fn merge(&mut self, other: Kinds) {
        self.sgr += other.sgr;
        self.sgr_count += other.sgr_count;
        self.moves += other.moves;
        self.erase += other.erase;
        self.markers += other.markers;
        self.glyphs += other.glyphs;
    }

    /// Every byte counted.
    pub fn total(&self) -> usize {
        self.sgr + self.moves + self.erase + self.markers + self.glyphs
    }
}
