//! `mazewalk --record FILE`: the local walk written as an asciicast v2 file as it goes, in the
//! format of [`mazewalk_walk::cast`]. [`Recorder`] is the file behind a `BufWriter`, shared between
//! the walk's loop (resizes) and the terminal guard (every write, from whichever thread makes it),
//! reading the walk's clock. Each write to the terminal is flushed to the file as it is recorded, so
//! the file is whole lines of asciicast between frames. A write error (a full disk, a file-size limit:
//! the walk catches SIGXFSZ, so such a write fails with `EFBIG`) stops the recording, and the file is
//! cut back to its last whole line at once; the error is kept, and told once by the caller after the
//! terminal is restored; the walk goes on.

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
    /// The cast, until a write fails ([`Recording::stop`]).
    cast: Option<CastWriter<BufWriter<File>>>,
    /// Why the recording stopped, once it did.
    stopped: Option<io::Error>,
    /// [`CastWriter::replaced`] when it stopped.
    replaced: u64,
    clock: Instant,
}

impl Recording {
    /// After a write failed: the file cut back to its last whole line (a write that failed part-way
    /// may have left part of one), the bytes still buffered dropped, the error kept.
    fn stop(&mut self) {
        let Some(mut cast) = self.cast.take() else { return };
        let error = cast.finish().err().unwrap_or_else(|| io::Error::other("the recording stopped"));
        self.replaced = cast.replaced();
        let flushed = cast.flushed();
        let (file, _buffered) = cast.into_inner().into_parts(); // (dropped unwritten)
        self.stopped = Some(match file.set_len(flushed) {
            Ok(()) => error,
            Err(cut) => io::Error::new(
                error.kind(),
                format!("{error} (and it could not be cut back to whole lines: {cut})"),
            ),
        });
    }
}

impl Recorder {
    /// Creates (or truncates) `path` and writes `header`; events are timed from `clock`, the walk's
    /// time 0. A symbolic link is not followed: in a folder others write to (`/tmp`), a link put where
    /// the recording is to go would have had a file of the player's, wherever it names, truncated.
    /// Nor is anything but a regular file written to: a FIFO put there would have made the walk
    /// wait for a reader, then streamed the session to it.
    ///
    /// # Errors
    /// `path` is a symbolic link or not a regular file (a FIFO, a socket, a device), or the file
    /// could not be created or the header written.
    pub fn create(path: &Path, header: &Header, clock: Instant) -> io::Result<Recorder> {
        let file = create_unfollowed(path)?;
        let mut cast = CastWriter::new(BufWriter::new(file), header)?;
        cast.finish()?; // the header's line in the file: whole lines from here on
        let recording = Recording { cast: Some(cast), stopped: None, replaced: 0, clock };
        Ok(Recorder { inner: Arc::new(Mutex::new(recording)) })
    }

    /// Runs `f` on the cast, now, unless the recording stopped; stops it if a write failed.
    fn with(&self, f: impl FnOnce(&mut CastWriter<BufWriter<File>>, f64)) {
        let mut recording = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
        let now = recording.clock.elapsed().as_secs_f64(); // under the lock: times never go back
        let Some(cast) = recording.cast.as_mut() else { return };
        f(cast, now);
        if cast.failed() {
            recording.stop();
        }
    }

    /// Records bytes written to the terminal, now, and flushes them to the file.
    pub fn output(&self, data: &[u8]) {
        self.with(|cast, now| {
            cast.output(now, data);
            cast.flush();
        });
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
        let recording = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
        recording.cast.as_ref().map_or(recording.replaced, CastWriter::replaced)
    }

    /// Flushes the file.
    ///
    /// # Errors
    /// The first write error of the recording (after which it stopped, the file cut back to its
    /// last whole line), or the flush's.
    pub fn finish(&self) -> io::Result<()> {
        let mut recording = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(cast) = recording.cast.as_mut()
            && cast.finish().is_err()
        {
            recording.stop();
        }
        match &recording.stopped {
            Some(error) => Err(io::Error::new(error.kind(), error.to_string())),
            None => Ok(()),
        }
    }
}

/// `path` created, or truncated, for writing, unless it is not a regular file: opened as every
/// file a walk writes is ([`open_to_write`](mazewalk_maze::files::open_to_write): a symbolic link
/// not followed, a FIFO, a socket or a device refused without waiting; red-team passes 6 and 7),
/// and truncated only once it is known to be a regular file. A character device is refused too,
/// `/dev/null` and `/dev/full` included: a recording is a file to play back (the full-disk test
/// fills a real file under `ulimit -f`).
fn create_unfollowed(path: &Path) -> io::Result<File> {
    use mazewalk_maze::files::{OpenError, open_to_write};
    let (file, _) = open_to_write(path).map_err(|e| match e {
        OpenError::Io(e) => e,
        // (what to do instead, too)
        OpenError::NotAFile("a symbolic link") => {
            io::Error::new(io::ErrorKind::InvalidInput, format!("{e}: record to the file it names"))
        }
        e => io::Error::new(io::ErrorKind::InvalidInput, format!("{e}: record to a file")),
    })?;
    file.set_len(0)?;
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> Header {
        Header {
            width: 80,
            height: 24,
            timestamp: None,
            title: "mazewalk test".into(),
            term: None,
            colorterm: None,
            color_depth: mazewalk_term::frame::ColorDepth::Ansi256,
            charset: mazewalk_render::Charset::Half,
            asked_truecolor: false,
        }
    }

    /// Red-team pass 6: `--record` through a link put in its place truncated the file the link named.
    #[cfg(unix)]
    #[test]
    fn a_recording_does_not_follow_a_symbolic_link() {
        let dir = mazewalk_testkit::scratch::Scratch::new("cast-link");
        let (target, link) = (dir.join("precious"), dir.join("walk.cast"));
        std::fs::write(&target, "keep me").unwrap();
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let error = Recorder::create(&link, &header(), Instant::now()).expect_err("a link was followed");
        assert!(error.to_string().contains("symbolic link"), "{error}");
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep me");
        // a file of its own at the path is recorded over, as before
        std::fs::write(dir.join("old.cast"), "an old recording, longer than a header line").unwrap();
        drop(Recorder::create(&dir.join("old.cast"), &header(), Instant::now()).expect("an existing file"));
        let cast = std::fs::read_to_string(dir.join("old.cast")).unwrap();
        assert!(cast.starts_with("{\"version\": 2") || cast.starts_with("{\"version\":2"), "{cast}");
        assert!(!cast.contains("an old recording"), "{cast}");
    }

    /// Red-team pass 7: a FIFO at the path made the walk wait for a reader before its first frame,
    /// then streamed the session to it. Now only a regular file is recorded to, and the open never
    /// waits (bounded here: the old one waited for ever).
    #[cfg(unix)]
    #[test]
    fn a_recording_is_made_only_in_a_regular_file() {
        let dir = mazewalk_testkit::scratch::Scratch::new("cast-fifo");
        let fifo = dir.join("walk.cast");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success(), "mkfifo");
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _ = tx.send(Recorder::create(&fifo, &header(), Instant::now()).map(drop));
        });
        let opened =
            rx.recv_timeout(std::time::Duration::from_secs(10)).expect("the open waits for a reader");
        let error = opened.expect_err("a FIFO recorded to");
        assert!(error.to_string().contains("not a regular file"), "{error}");
        let error =
            Recorder::create(Path::new("/dev/null"), &header(), Instant::now()).expect_err("a device");
        assert!(error.to_string().contains("not a regular file"), "{error}");
    }
}
