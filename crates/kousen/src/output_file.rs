//! Files that appear whole or not at all: written to a temporary sibling, then renamed into
//! place, so a failure never leaves a half-written image or JSON file behind.

use std::fs::File;
use std::path::{Path, PathBuf};

use anyhow::Context;

/// A file being written: a temporary sibling of `path` that becomes `path` on
/// [`PendingFile::commit`] and is removed if dropped before that.
pub struct PendingFile {
    path: PathBuf,
    temporary: tempfile::NamedTempFile,
}

impl PendingFile {
    /// Creates the temporary sibling now, so that an unwritable path fails before the work.
    pub fn create(path: &Path) -> anyhow::Result<PendingFile> {
        let directory = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let temporary = tempfile::Builder::new()
            .prefix(".kousen-")
            .suffix(".partial")
            .tempfile_in(directory)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(PendingFile {
            path: path.to_path_buf(),
            temporary,
        })
    }

    pub fn file(&mut self) -> &mut File {
        self.temporary.as_file_mut()
    }

    /// Moves the written file into place.
    pub fn commit(self) -> anyhow::Result<()> {
        // Temporary files are created private (0600); an output should be as readable as any
        // file the user writes.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let readable = std::fs::Permissions::from_mode(0o644);
            std::fs::set_permissions(self.temporary.path(), readable)?;
        }
        self.temporary
            .persist(&self.path)
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        Ok(())
    }
}

/// Writes `contents` to `path` whole or not at all.
pub fn write_atomically(path: &Path, contents: &[u8]) -> anyhow::Result<()> {
    use std::io::Write;
    let mut file = PendingFile::create(path)?;
    file.file()
        .write_all(contents)
        .with_context(|| format!("cannot write {}", path.display()))?;
    file.commit()
}
