//! Wavefront OBJ + MTL loader (placeholder until the loader lands).

use std::path::Path;

use crate::{Scene, SceneError};

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError::unsupported(path, "OBJ loading is not implemented yet"))
}
