//! Reading files a scene names, which may be anything: a device (`/dev/zero`), a pipe, a
//! directory. Both loaders read through here so that none of those can hang a load or make it
//! allocate without bound.

use std::io::Read;
use std::path::Path;

use crate::SceneError;

/// The bytes of file `path`, at most `limit` of them (a longer file is refused), gunzipped
/// first where its name ends in `.gz`.
pub(crate) fn read_maybe_gzipped(path: &Path, limit: u64) -> Result<Vec<u8>, SceneError> {
    let (bytes, length) = read_regular_file(path, limit).map_err(|e| SceneError::io(path, e))?;
    if length > limit {
        let message = format!("{length} bytes: larger than kousen reads ({limit})");
        return Err(SceneError::format(path, message));
    }
    match path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"))
    {
        true => gunzip(&bytes, limit).map_err(|message| SceneError::format(path, message)),
        false => Ok(bytes),
    }
}

/// The bytes of a gzip stream (PLY meshes, pbrt scenes), at most `limit` of them.
fn gunzip(bytes: &[u8], limit: u64) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let mut decoder = flate2::read::GzDecoder::new(bytes).take(limit + 1);
    decoder
        .read_to_end(&mut out)
        .map_err(|e| format!("not a gzip file: {e}"))?;
    if out.len() as u64 > limit {
        return Err(format!("unpacks to more than kousen reads ({limit} bytes)"));
    }
    Ok(out)
}

/// Reads at most `limit` bytes of `path`, which must be a regular file. Returns the bytes and
/// the file's whole length, so a caller can refuse an oversized file or report a short one.
/// Nothing is allocated beyond what the file holds.
pub(crate) fn read_regular_file(path: &Path, limit: u64) -> std::io::Result<(Vec<u8>, u64)> {
    let file = std::fs::File::open(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        let kind = std::io::ErrorKind::InvalidInput;
        return Err(std::io::Error::new(kind, "not a regular file"));
    }
    let length = metadata.len();
    let mut bytes = Vec::with_capacity(limit.min(length) as usize);
    file.take(limit).read_to_end(&mut bytes)?;
    Ok((bytes, length))
}
