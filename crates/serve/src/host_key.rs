//! The server's host key: an ed25519 key in OpenSSH format, made on first start and kept with 0600
//! permissions in a folder only the owner may enter, so that players' `known_hosts` stay valid across
//! restarts. Default place: `$XDG_STATE_HOME/mazewalk/host_ed25519_key`, else
//! `~/.local/state/mazewalk/host_ed25519_key` (`--host-key FILE` overrides).
//!
//! Also where the authorized-keys file is read from ([`read_authorized_keys`]; what its lines mean is
//! [`authorized_keys`]).

use std::fs::{self, OpenOptions};
use std::io::{self, Read as _, Write as _};
use std::os::unix::fs::{DirBuilderExt as _, OpenOptionsExt as _, PermissionsExt as _};
use std::path::{Path, PathBuf};

use russh::keys::ssh_key::private::Ed25519Keypair;
use russh::keys::ssh_key::{self, LineEnding};
use russh::keys::{HashAlg, PrivateKey, PublicKey};

use super::authorized_keys::{self, AuthorizedKeys};
use mazewalk_maze::files::{OpenError, open_regular};

/// Why the host key or the authorized keys could not be had.
#[derive(Debug, thiserror::Error)]
pub enum KeyError {
    /// Reading, creating or writing a file failed. (The reasons are part of the messages, not error
    /// sources: a chain printed whole would say them twice.)
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed.
        error: io::Error,
    },
    /// The file is not a key (or not a list of keys) in OpenSSH format.
    #[error("{}: not an OpenSSH key file: {error}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What the parser said.
        error: ssh_key::Error,
    },
    /// The host key file holds something other than an OpenSSH private key.
    #[error(
        "{}: not an OpenSSH private key (no `{OPENSSH_PRIVATE_KEY}` line); make one with ssh-keygen -t ed25519, or give a path where none is yet",
        path.display()
    )]
    NotAPrivateKey {
        /// The file.
        path: PathBuf,
    },
    /// The file is larger than any key file (it is read whole).
    #[error("{}: larger than {MAX_KEY_FILE} bytes, too large for a key file", path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
    },
    /// The private key file may be read by others (as sshd, the server refuses it).
    #[error("{}: permissions {mode:o} let others read the host key; chmod 600 it", path.display())]
    TooOpen {
        /// The file.
        path: PathBuf,
        /// Its permission bits.
        mode: u32,
    },
    /// The key is protected by a passphrase, which a server starting unattended cannot type.
    #[error("{}: the host key has a passphrase; give a key without one (ssh-keygen -t ed25519 -N '' -f FILE)", path.display())]
    Encrypted {
        /// The file.
        path: PathBuf,
    },
    /// The path names a directory or another thing that is not a regular file.
    #[error("{}: not a regular file ({what}); give a key file's path", path.display())]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is instead ("a directory", "a FIFO"…).
        what: &'static str,
    },
    /// No place for the key: neither `XDG_STATE_HOME` nor `HOME` is set.
    #[error("no place for the host key: set HOME or XDG_STATE_HOME, or give --host-key FILE")]
    NoHome,
}

/// The largest key file read: an ed25519 private key is about 400 bytes, an authorized key line about
/// 100 (so some ten thousand players' keys fit).
pub(crate) const MAX_KEY_FILE: u64 = 1 << 20;

/// The first line of an OpenSSH private key file.
const OPENSSH_PRIVATE_KEY: &str = "-----BEGIN OPENSSH PRIVATE KEY-----";

/// The bytes of the key file at `path`: a regular file (a FIFO is refused, not waited on) of at most
/// [`MAX_KEY_FILE`] bytes.
fn read_file(path: &Path) -> Result<Vec<u8>, KeyError> {
    let io = |error| KeyError::Io { path: path.to_path_buf(), error };
    let file = open_regular(path).map_err(|error| match error {
        OpenError::Io(error) => io(error),
        OpenError::NotAFile(what) => KeyError::NotAFile { path: path.to_path_buf(), what },
    })?;
    let mut bytes = Vec::new();
    // (One byte past the limit tells a file over it, whatever its size said when opened.)
    file.take(MAX_KEY_FILE + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > MAX_KEY_FILE {
        return Err(KeyError::TooLarge { path: path.to_path_buf() });
    }
    Ok(bytes)
}

/// The text of the key file at `path` ([`read_file`]), in UTF-8.
fn read_key_file(path: &Path) -> Result<String, KeyError> {
    String::from_utf8(read_file(path)?).map_err(|_| KeyError::Io {
        path: path.to_path_buf(),
        error: io::Error::new(io::ErrorKind::InvalidData, "not UTF-8 text"),
    })
}

/// The host key's default path from the environment lookup `get` (`XDG_STATE_HOME`, `HOME`).
///
/// # Errors
/// [`KeyError::NoHome`] when neither variable is set (or both are empty).
pub fn default_path(get: impl Fn(&str) -> Option<String>) -> Result<PathBuf, KeyError> {
    let non_empty = |k: &str| get(k).filter(|v| !v.is_empty()).map(PathBuf::from);
    let state = non_empty("XDG_STATE_HOME")
        .or_else(|| non_empty("HOME").map(|home| home.join(".local").join("state")))
        .ok_or(KeyError::NoHome)?;
    Ok(state.join("mazewalk").join("host_ed25519_key"))
}

/// Reads the host key at `path`, or makes a new ed25519 key there (its folders with mode 0700, the
/// file with mode 0600) if there is none. Returns the key and whether it was made now.
///
/// # Errors
/// The file cannot be read, made or written, is not an OpenSSH private key, or others may read it.
pub fn load_or_create(path: &Path) -> Result<(PrivateKey, bool), KeyError> {
    let io = |error| KeyError::Io { path: path.to_path_buf(), error };
    match fs::metadata(path) {
        Ok(meta) => {
            let mode = meta.permissions().mode() & 0o777;
            if meta.is_file() && mode & 0o077 != 0 {
                return Err(KeyError::TooOpen { path: path.to_path_buf(), mode });
            }
            let text = read_key_file(path)?;
            if !text.trim_start().starts_with(OPENSSH_PRIVATE_KEY) {
                return Err(KeyError::NotAPrivateKey { path: path.to_path_buf() });
            }
            let key = PrivateKey::from_openssh(text.as_bytes())
                .map_err(|error| KeyError::Format { path: path.to_path_buf(), error })?;
            if key.is_encrypted() {
                // (It parses: the public half is in the clear. Every handshake would fail.)
                return Err(KeyError::Encrypted { path: path.to_path_buf() });
            }
            Ok((key, false))
        }
        Err(err) if err.kind() == io::ErrorKind::NotFound => {
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                fs::DirBuilder::new().recursive(true).mode(0o700).create(dir).map_err(io)?;
            }
            let mut seed = [0u8; 32];
            getrandom::fill(&mut seed).map_err(|e| io(io::Error::other(e.to_string())))?;
            let key = PrivateKey::from(Ed25519Keypair::from_seed(&seed));
            seed.fill(0);
            let text = key
                .to_openssh(LineEnding::LF)
                .map_err(|error| KeyError::Format { path: path.to_path_buf(), error })?;
            // create_new: never overwrite a key another server made meanwhile.
            let mut file =
                OpenOptions::new().write(true).create_new(true).mode(0o600).open(path).map_err(io)?;
            file.write_all(text.as_bytes()).and_then(|()| file.sync_all()).map_err(io)?;
            Ok((key, true))
        }
        Err(err) => Err(io(err)),
    }
}

/// The key's fingerprint as OpenSSH prints it (`SHA256:…`).
#[must_use]
pub fn fingerprint(key: &PublicKey) -> String {
    key.fingerprint(HashAlg::Sha256).to_string()
}

/// Reads the `authorized_keys` file at `path` ([`authorized_keys`]: line by
/// line as sshd does; a line that cannot be read is skipped and reported, never the whole file).
///
/// # Errors
/// The file cannot be read (missing, not a regular file, larger than [`MAX_KEY_FILE`]).
pub fn read_authorized_keys(path: &Path) -> Result<AuthorizedKeys, KeyError> {
    let bytes = read_file(path)?;
    Ok(authorized_keys::parse(&String::from_utf8_lossy(&bytes))) // (only comments may be other than ASCII)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_place_is_the_state_folder() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |k: &str| vars.iter().find(|(n, _)| *n == k).map(|(_, v)| (*v).to_string())
        };
        assert_eq!(
            default_path(env(&[("HOME", "/home/a")])).unwrap(),
            Path::new("/home/a/.local/state/mazewalk/host_ed25519_key")
        );
        assert_eq!(
            default_path(env(&[("HOME", "/home/a"), ("XDG_STATE_HOME", "/s")])).unwrap(),
            Path::new("/s/mazewalk/host_ed25519_key")
        );
        assert!(matches!(default_path(env(&[("HOME", "")])), Err(KeyError::NoHome)));
    }

    /// A throwaway ed25519 key with the passphrase `secret`.
    const ENCRYPTED_KEY: &str = "-----BEGIN OPENSSH PRIVATE KEY-----
b3BlbnNzaC1rZXktdjEAAAAACmFlczI1Ni1jdHIAAAAGYmNyeXB0AAAAGAAAABCj8NHZnl
lIQyAnJuSXww7sAAAAEAAAAAEAAAAzAAAAC3NzaC1lZDI1NTE5AAAAIImypI4iL/4FB/6A
B6xXtu8e4gvbqReOWrZZSz/4daGNAAAAkCfo1g0bNCR5Pur0wHMV4Zt8IEobH04nVhWbvk
Yj671VdUFeEHbvCJXE9pPYezi+6BDRh3J7h6SvBGimoJ/i+GYsXEtXOObkwp6gEbDIJlZK
LQqSRnHbD1ht80vUcKxG8liq8bpOLYZgg9989nIKlb/+3ZEQkfuFAJ7LtIDLwe+AgD+S9M
Yhg9caVlscNzhaBQ==
-----END OPENSSH PRIVATE KEY-----
";

    #[test]
    fn a_key_is_made_once_private_and_then_read_back() {
        let dir = std::env::temp_dir().join(format!("mazewalk-host-key-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let path = dir.join("deep").join("host_key");
        let (made, new) = load_or_create(&path).unwrap();
        assert!(new);
        assert_eq!(fs::metadata(&path).unwrap().permissions().mode() & 0o777, 0o600);
        assert_eq!(fs::metadata(path.parent().unwrap()).unwrap().permissions().mode() & 0o777, 0o700);
        let (read, new) = load_or_create(&path).unwrap();
        assert!(!new);
        assert_eq!(fingerprint(made.public_key()), fingerprint(read.public_key()));
        assert!(fingerprint(read.public_key()).starts_with("SHA256:"));
        fs::set_permissions(&path, fs::Permissions::from_mode(0o644)).unwrap();
        assert!(matches!(load_or_create(&path), Err(KeyError::TooOpen { mode: 0o644, .. })));
        // A key with a passphrase (`ssh-keygen -t ed25519 -N secret`): refused before serving.
        let encrypted = dir.join("encrypted");
        fs::write(&encrypted, ENCRYPTED_KEY).unwrap();
        fs::set_permissions(&encrypted, fs::Permissions::from_mode(0o600)).unwrap();
        let err = load_or_create(&encrypted).unwrap_err();
        assert!(matches!(err, KeyError::Encrypted { .. }) && err.to_string().contains("passphrase"), "{err}");
        // A directory is not a key, whatever its permissions.
        let err = load_or_create(&dir).unwrap_err();
        assert!(matches!(err, KeyError::NotAFile { .. }), "{err}");
        let keys = dir.join("authorized_keys");
        let line = made.public_key().to_openssh().unwrap();
        fs::write(&keys, format!("# a comment\n\n{line} someone@somewhere\n")).unwrap();
        assert_eq!(read_authorized_keys(&keys).unwrap().keys, vec![made.public_key().key_data().clone()]);
        // A line that is not a key is skipped, not the whole file (issue #34); a comment in Latin-1
        // does not fail it either.
        let mut bytes = format!("ssh-ed25519 not-base64\n{line} caf").into_bytes();
        bytes.extend(b"\xe9\n");
        fs::write(&keys, bytes).unwrap();
        let read = read_authorized_keys(&keys).unwrap();
        assert_eq!((read.keys.len(), read.skipped.len(), read.skipped[0].line), (1, 1, 1));
        fs::remove_dir_all(&dir).unwrap();
    }

    /// Key files are read whole, so only regular files of a key file's size are: a FIFO is refused
    /// without waiting for a writer, a device without reading it, a file past the limit after
    /// reading one byte more; and each refusal says its reason once.
    #[test]
    fn only_a_regular_file_of_a_key_files_size_is_read() {
        let dir = std::env::temp_dir().join(format!("mazewalk-key-files-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::DirBuilder::new().mode(0o700).create(&dir).unwrap();
        let fifo = dir.join("fifo");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        for (path, what) in [(fifo.as_path(), "a FIFO"), (Path::new("/dev/zero"), "a device")] {
            let err = read_authorized_keys(path).unwrap_err();
            assert!(matches!(err, KeyError::NotAFile { what: w, .. } if w == what), "{err}");
            assert!(matches!(load_or_create(path), Err(KeyError::NotAFile { .. })));
        }
        let big = dir.join("big");
        let line = "ssh-ed25519 AAAAC3NzaC1lZDI1NTE5AAAAIImypI4iL/4FB/6AB6xXtu8e4gvbqReOWrZZSz/4daGN a@b\n";
        let lines = usize::try_from(MAX_KEY_FILE).unwrap() / line.len() + 1;
        fs::write(&big, line.repeat(lines)).unwrap();
        assert!(matches!(read_authorized_keys(&big), Err(KeyError::TooLarge { .. })));
        fs::write(&big, line.repeat(lines - 1)).unwrap();
        assert_eq!(read_authorized_keys(&big).unwrap().keys.len(), lines - 1, "just under the limit");
        // Not a private key at all: said so, not a parser's guess.
        let garbage = dir.join("garbage");
        fs::write(&garbage, "garbage\n").unwrap();
        fs::set_permissions(&garbage, fs::Permissions::from_mode(0o600)).unwrap();
        let err = load_or_create(&garbage).unwrap_err();
        assert!(
            matches!(err, KeyError::NotAPrivateKey { .. }) && err.to_string().contains("ssh-keygen"),
            "{err}"
        );
        // The reason once, even printed as a chain of causes.
        let missing = dir.join("missing");
        let message = format!("{:#}", anyhow::Error::new(read_authorized_keys(&missing).unwrap_err()));
        assert_eq!(message.matches("No such file").count(), 1, "{message}");
        fs::remove_dir_all(&dir).unwrap();
    }
}
