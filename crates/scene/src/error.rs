//! The one error type every loader returns: a path and a one-line reason.

use std::path::{Path, PathBuf};

/// Why a scene could not be loaded. `Display` is one line naming the file, fit for a CLI.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file (or a file it refers to) could not be read. (Not marked as the error's
    /// source: the message already says it, and a CLI printing the chain would repeat it.)
    #[error("{}: {error}", path.display())]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    /// The file is malformed: bad syntax, out-of-range references, non-finite values.
    #[error("{}: {message}", path.display())]
    Format { path: PathBuf, message: String },
    /// The file is valid but asks for something kousen does not support.
    #[error("{}: {message}", path.display())]
    Unsupported { path: PathBuf, message: String },
    /// The file loaded but holds no usable triangle.
    #[error("{}: the scene has no triangles{detail}", path.display())]
    NoTriangles { path: PathBuf, detail: String },
}

impl SceneError {
    pub fn io(path: &Path, error: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            error,
        }
    }

    pub fn format(path: &Path, message: impl Into<String>) -> Self {
        Self::Format {
            path: path.to_path_buf(),
            message: one_line(message.into()),
        }
    }

    pub fn unsupported(path: &Path, message: impl Into<String>) -> Self {
        Self::Unsupported {
            path: path.to_path_buf(),
            message: one_line(message.into()),
        }
    }
}

/// Dependencies' messages sometimes span lines; a CLI error must not.
fn one_line(message: String) -> String {
    if message.contains('\n') {
        message.split_whitespace().collect::<Vec<_>>().join(" ")
    } else {
        message
    }
}
