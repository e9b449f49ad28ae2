//! glTF 2.0 loader (placeholder until the loader lands).

use std::path::Path;

use crate::{Scene, SceneError};

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError::unsupported(path, "glTF loading is not implemented yet"))
}
