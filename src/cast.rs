//! `mazewalk --record FILE`: the local walk written as an asciicast v2 file as it goes, in the
//! format of [`mazewalk_walk::cast`]. [`Recorder`] is the file behind a `BufWriter`, shared between
//! the walk's loop (resizes) and the terminal guard (every write, from whichever thread makes it),
//! reading the walk's clock. A write error stops the recording (kept, and told once by the caller
//! after the terminal is restored); the walk goes on.

use std::fs::File;
use std::io::{self, BufWriter};
use std::path::Path;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

pub use mazewalk_walk::cast::{CastWriter, Header};

/// A recording to a file, shared by the walk's loop and the terminal guard; times from the walk's
/// clock. Cloning shares it.
#[derive(Clone, Debug)]
pub struct Recorder {
    inner: Arc<Mutex<Recording>>,
}

#[derive(Debug)]
struct Recording {
    cast: CastWriter<BufWriter<File>>,
    clock: Instant,
}

impl Recorder {
    /// Creates (or truncates) `path` and writes `header`; events are timed from `clock`, the walk's
    /// time 0.
    ///
    /// # Errors
    /// The file could not be created or the header written.
    pub fn create(path: &Path, header: &Header, clock: Instant) -> io::Result<Recorder> {
        let file = File::create(path)?;
        let cast = CastWriter::new(BufWriter::new(file), header)?;
        Ok(Recorder { inner: Arc::new(Mutex::new(Recording { cast, clock })) })
    }

    fn with<T>(&self, f: impl FnOnce(&mut CastWriter<BufWriter<File>>, f64) -> T) -> T {
        let mut recording = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
        let now = recording.clock.elapsed().as_secs_f64(); // under the lock: times never go back
        f(&mut recording.cast, now)
    }

    /// Records bytes written to the terminal, now.
    pub fn output(&self, data: &[u8]) {
        self.with(|cast, now| cast.output(now, data));
    }

    /// Records the terminal's size, now, if it changed.
    pub fn resize(&self, cols: u16, rows: u16) {
        self.with(|cast, now| cast.resize(now, cols, rows));
    }

    /// Records a marker, now.
    pub fn marker(&self, label: &str) {
        self.with(|cast, now| cast.marker(now, label));
    }

    /// How many bytes sent were not UTF-8 and were recorded as U+FFFD (none from the walk's frames).
    #[must_use]
    pub fn replaced(&self) -> u64 {
        self.with(|cast, _| cast.replaced())
    }

    /// Flushes the file.
    ///
    /// # Errors
    /// The first write error of the recording (after which it stopped), or the flush's.
    pub fn finish(&self) -> io::Result<()> {
        self.with(|cast, _| cast.finish())
    }
}
