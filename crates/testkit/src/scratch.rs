//! A scratch folder of a test's own (tempfile's, under the system's temporary folder, its name
//! starting `mazewalk-NAME-`), removed with everything in it when the test drops it.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::require_tool;

/// A scratch folder, removed on drop.
pub struct Scratch(tempfile::TempDir);

impl Scratch {
    /// A new empty folder whose name starts `mazewalk-{name}-`.
    pub fn new(name: &str) -> Scratch {
        let dir =
            tempfile::Builder::new().prefix(&format!("mazewalk-{name}-")).tempdir().expect("scratch folder");
        Scratch(dir)
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        self.0.path()
    }

    /// A path in the folder.
    pub fn join(&self, name: impl AsRef<Path>) -> PathBuf {
        self.0.path().join(name)
    }

    /// A maze file `maze.grid` in the folder holding `text`; returns its path.
    pub fn maze(&self, text: &str) -> PathBuf {
        let path = self.join("maze.grid");
        std::fs::write(&path, text).expect("write the maze");
        path
    }

    /// The records database's usual place in the folder.
    pub fn db(&self) -> PathBuf {
        self.join("records.sqlite")
    }

    /// A fresh ed25519 key pair made by `ssh-keygen` in the folder; returns the private key's path.
    pub fn key(&self, name: &str) -> PathBuf {
        require_tool("ssh-keygen", "openssh-client");
        let path = self.join(name);
        let status = Command::new("ssh-keygen")
            .args(["-q", "-t", "ed25519", "-N", "", "-C", name, "-f"])
            .arg(&path)
            .stdin(Stdio::null())
            .status()
            .expect("ssh-keygen");
        assert!(status.success(), "ssh-keygen made no key");
        path
    }
}
