//! Opening files named by users (mazes, and `mazewalk serve`'s key files): only regular files, and
//! never blocking on the way in. I/O.

use std::fs::File;
use std::path::Path;

/// Why [`open_regular`] opened nothing.
#[derive(Debug)]
pub enum OpenError {
    /// The operating system's reason.
    Io(std::io::Error),
    /// The path names something else, which might never end or never answer: "a directory",
    /// "a FIFO", "a device", "a socket" or "not a file".
    NotAFile(&'static str),
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
    let what = if kind.is_dir() {
        "a directory"
    } else {
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
    };
    Err(OpenError::NotAFile(what))
}
