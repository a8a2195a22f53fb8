//! Opening files named by users (mazes, and `mazewalk serve`'s key files, to read; a recording or a
//! run, to write): only regular files, never through a symbolic link when writing, and never
//! blocking on the way in. I/O.

use std::fs::File;
use std::path::Path;

/// Why [`open_regular`] or [`open_to_write`] opened nothing. Shown as the system's words, or as
/// "not a regular file (a FIFO)", "a symbolic link, not followed".
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// The operating system's reason.
    #[error(transparent)]
    Io(std::io::Error),
    /// The path names something else, which might never end or never answer: "a directory",
    /// "a FIFO", "a device", "a socket" or "not a file"; or, to write ([`open_to_write`]), "a
    /// symbolic link" (not followed) or "a FIFO or a socket" (which one, unknown without opening it);
    /// or, for an output ([`create_output`]), "a FIFO nobody reads".
    #[error("{}", not_a_file(.0))]
    NotAFile(&'static str),
}

/// How [`OpenError::NotAFile`] reads.
fn not_a_file(what: &str) -> String {
    match what {
        "a symbolic link" => "a symbolic link, not followed".to_string(),
        "a FIFO nobody reads" => "a FIFO nobody reads (nothing would take what is written)".to_string(),
        what => format!("not a regular file ({what})"),
    }
}

/// Opens `path` for reading if it is a regular file, without blocking on a FIFO (`open` on a FIFO
/// with no writer waits forever; a regular file ignores the flag).
pub fn open_regular(path: &Path) -> Result<File, OpenError> {
    let mut open = std::fs::OpenOptions::new();
    open.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        open.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    let file = open.open(path).map_err(OpenError::Io)?;
    let kind = file.metadata().map_err(OpenError::Io)?.file_type();
    if kind.is_file() {
        return Ok(file);
    }
    Err(OpenError::NotAFile(kind_name(kind)))
}

/// What is at `path` (links followed) when something is there and it is not a regular file: "a
/// directory", "a FIFO", "a device"… as [`OpenError::NotAFile`] says it. `None` for a regular file,
/// or nothing there. Opens nothing (a FIFO is not waited on): for a path a library opens itself.
#[must_use]
pub fn not_regular(path: &Path) -> Option<&'static str> {
    let kind = std::fs::metadata(path).ok()?.file_type();
    (!kind.is_file()).then(|| kind_name(kind))
}

/// What a path that is not a regular file names, for [`OpenError::NotAFile`].
fn kind_name(kind: std::fs::FileType) -> &'static str {
    if kind.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        if kind.is_fifo() {
            "a FIFO"
        } else if kind.is_char_device() || kind.is_block_device() {
            "a device"
        } else if kind.is_socket() {
            "a socket"
        } else {
            "not a file"
        }
    }
    #[cfg(not(unix))]
    "not a file"
}

/// Opens `path` for writing, made (with the umask's mode) if there is none, if it is a regular
/// file; `true` with it when this call made it. Nothing is truncated: the caller replaces the
/// contents once it has them (`set_len(0)`, then writes).
///
/// Where others can write (`/tmp`), a path can be a trap. So a symbolic link at `path` is not
/// followed (`O_NOFOLLOW`): a link put there would have had whatever file of the user's it names
/// overwritten (red-team passes 6 and 8). And the open never waits (`O_NONBLOCK`, left on: it
/// changes nothing for a regular file): a FIFO nobody reads is refused at once rather than waited
/// on, one somebody reads, a socket or a device after `fstat`. The one way a recording
/// (`--record`), a run (`--save-run`) and an exported run (`records --export-run`) are opened.
///
/// # Errors
/// [`OpenError::NotAFile`] for a symbolic link ("a symbolic link"), a FIFO, a socket, a device or a
/// directory; [`OpenError::Io`] for what the system refused (no folder, no permission).
pub fn open_to_write(path: &Path) -> Result<(File, bool), OpenError> {
    let mut open = std::fs::OpenOptions::new();
    open.write(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        open.custom_flags((rustix::fs::OFlags::NOFOLLOW | rustix::fs::OFlags::NONBLOCK).bits() as i32);
    }
    let refused = |e: std::io::Error| {
        #[cfg(unix)]
        {
            use rustix::io::Errno;
            match e.raw_os_error() {
                Some(n) if n == Errno::LOOP.raw_os_error() => return OpenError::NotAFile("a symbolic link"),
                // (what O_NONBLOCK says of a FIFO nobody reads, or of a socket, instead of waiting)
                Some(n) if n == Errno::NXIO.raw_os_error() => {
                    return OpenError::NotAFile("a FIFO or a socket");
                }
                Some(n) if n == Errno::ISDIR.raw_os_error() => return OpenError::NotAFile("a directory"),
                _ => {}
            }
        }
        OpenError::Io(e)
    };
    // (O_CREAT | O_EXCL fails on any link, even one naming nothing: then the open below says why)
    let (file, made) = match open.clone().create_new(true).open(path) {
        Ok(file) => (file, true),
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => (open.open(path).map_err(refused)?, false),
        Err(e) => return Err(refused(e)),
    };
    let kind = file.metadata().map_err(OpenError::Io)?.file_type();
    if !kind.is_file() {
        return Err(OpenError::NotAFile(kind_name(kind))); // (a FIFO someone reads, a device)
    }
    Ok((file, made))
}

/// Opens `path` for an output a command writes as the user asks (`gen -o`, `render --png`,
/// `--depth-out`): made, or truncated, as [`File::create`] does; links followed; a pipe or a device
/// written too (`-o /dev/stdout`, a process substitution's `/dev/fd/63`). But the open never waits:
/// a FIFO nobody reads is refused at once (red-team pass 11: `gen -o FIFO` waited for a reader
/// for ever). `O_NONBLOCK` is on for the open only: the writes then wait for a slow reader.
///
/// # Errors
/// [`OpenError::NotAFile`] for a FIFO nobody reads ("a FIFO nobody reads") or a directory;
/// [`OpenError::Io`] for what the system refused (no folder, no permission).
pub fn create_output(path: &Path) -> Result<File, OpenError> {
    let mut open = std::fs::OpenOptions::new();
    open.write(true).create(true).truncate(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt as _;
        open.custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32);
    }
    let file = open.open(path).map_err(|e| {
        #[cfg(unix)]
        {
            use rustix::io::Errno;
            match e.raw_os_error() {
                // (what O_NONBLOCK says of a FIFO nobody reads, instead of waiting)
                Some(n) if n == Errno::NXIO.raw_os_error() => {
                    return OpenError::NotAFile("a FIFO nobody reads");
                }
                Some(n) if n == Errno::ISDIR.raw_os_error() => return OpenError::NotAFile("a directory"),
                _ => {}
            }
        }
        OpenError::Io(e)
    })?;
    #[cfg(unix)]
    {
        let flags = rustix::fs::fcntl_getfl(&file).map_err(|e| OpenError::Io(e.into()))?;
        rustix::fs::fcntl_setfl(&file, flags - rustix::fs::OFlags::NONBLOCK)
            .map_err(|e| OpenError::Io(e.into()))?;
    }
    Ok(file)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    /// A scratch folder of the test's own, removed at the end.
    struct Dir(std::path::PathBuf);

    impl Dir {
        fn new(name: &str) -> Dir {
            let dir = std::env::temp_dir().join(format!("mazewalk-files-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            Dir(dir)
        }
    }

    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    #[test]
    fn a_file_to_write_is_made_or_opened_and_never_truncated() {
        use std::io::Write as _;
        let dir = Dir::new("write");
        let path = dir.0.join("out");
        let (mut file, made) = open_to_write(&path).unwrap();
        assert!(made);
        file.write_all(b"first").unwrap();
        drop(file);
        let (file, made) = open_to_write(&path).unwrap();
        assert!(!made);
        drop(file);
        assert_eq!(std::fs::read(&path).unwrap(), b"first", "opened, not truncated");
    }

    /// Red-team pass 8 (local side), finding 7: `--save-run` and `records --export-run` wrote
    /// through a symbolic link put at their path, over the file it named.
    #[test]
    fn a_file_to_write_is_not_a_symbolic_link_nor_anything_but_a_file() {
        let dir = Dir::new("links");
        let victim = dir.0.join("victim");
        std::fs::write(&victim, "keep me").unwrap();
        let link = dir.0.join("link");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let dangling = dir.0.join("dangling");
        std::os::unix::fs::symlink(dir.0.join("nothing"), &dangling).unwrap();
        for path in [&link, &dangling] {
            let refused = open_to_write(path).map(drop).unwrap_err();
            assert!(matches!(refused, OpenError::NotAFile("a symbolic link")), "{path:?}: {refused:?}");
        }
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
        assert!(!dir.0.join("nothing").exists(), "nothing made where the dangling link points");
        let refused = open_to_write(&dir.0).map(drop).unwrap_err();
        assert!(matches!(refused, OpenError::NotAFile("a directory")), "{refused:?}");
        let refused = open_to_write(Path::new("/dev/null")).map(drop).unwrap_err();
        assert!(matches!(refused, OpenError::NotAFile("a device")), "{refused:?}");
        let fifo = dir.0.join("fifo");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success(), "mkfifo");
        // (bounded: a blocking open would wait for a reader for ever)
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || tx.send(open_to_write(&fifo).map(drop)));
        let refused = rx.recv_timeout(std::time::Duration::from_secs(10)).expect("no wait").unwrap_err();
        assert!(matches!(refused, OpenError::NotAFile("a FIFO or a socket")), "{refused:?}");
        let missing = open_to_write(&dir.0.join("no").join("such")).map(drop).unwrap_err();
        assert!(matches!(missing, OpenError::Io(_)), "{missing:?}");
    }
}
