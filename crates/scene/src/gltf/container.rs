//! The file itself: a `.gltf` (JSON) or a `.glb` (a 12-byte header, a JSON chunk and an
//! optional BIN chunk), told apart by the GLB magic rather than the extension.
//!
//! The GLB header is checked against the file's real size before anything is sliced, and the
//! JSON is deserialised without the `gltf` crate's validation (whose hooks index arrays
//! unchecked): the other modules check every reference they follow.

use std::ops::Range;
use std::path::Path;

use ::gltf::json;

use crate::SceneError;

const GLB_MAGIC: &[u8; 4] = b"glTF";
const GLB_HEADER_BYTES: usize = 12;
const CHUNK_HEADER_BYTES: usize = 8;
const CHUNK_JSON: &[u8; 4] = b"JSON";
const CHUNK_BIN: &[u8; 4] = b"BIN\0";
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// A parsed file: its JSON document and, for a GLB, where its BIN chunk lies in `bytes`.
pub(super) struct Container {
    pub root: json::Root,
    bytes: Vec<u8>,
    bin: Option<Range<usize>>,
}

impl Container {
    /// The GLB's BIN chunk, if the file is a GLB that has one.
    pub fn bin_chunk(&self) -> Option<&[u8]> {
        self.bin.clone().map(|range| &self.bytes[range])
    }
}

/// Reads and parses `path`.
pub(super) fn read(path: &Path) -> Result<Container, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::io(path, e))?;
    if bytes.is_empty() {
        return Err(SceneError::format(path, "empty file"));
    }
    let (json_range, bin) = if bytes.starts_with(GLB_MAGIC) {
        split_glb(&bytes).map_err(|message| SceneError::format(path, message))?
    } else {
        (0..bytes.len(), None)
    };
    let text = &bytes[json_range];
    let text = text.strip_prefix(UTF8_BOM).unwrap_or(text);
    // Some GLB writers pad the JSON chunk with zeros instead of spaces.
    let text = text.trim_ascii_end();
    let text = &text[..text.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1)];
    let root: json::Root = json::deserialize::from_slice(text)
        .map_err(|e| SceneError::format(path, format!("invalid glTF JSON: {e}")))?;
    Ok(Container { root, bytes, bin })
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let word = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([word[0], word[1], word[2], word[3]]))
}

/// Splits a GLB into the byte ranges of its JSON chunk and its BIN chunk (if any).
fn split_glb(bytes: &[u8]) -> Result<(Range<usize>, Option<Range<usize>>), String> {
    let (Some(version), Some(declared)) = (read_u32(bytes, 4), read_u32(bytes, 8)) else {
        return Err(format!(
            "truncated GLB header: {} bytes, a header needs {GLB_HEADER_BYTES}",
            bytes.len()
        ));
    };
    if version != 2 {
        return Err(format!("GLB container version {version} (expected 2)"));
    }
    let declared = declared as usize;
    if declared > bytes.len() {
        return Err(format!(
            "truncated GLB: its header claims {declared} bytes but the file has {}",
            bytes.len()
        ));
    }
    // Bytes after the declared length are not part of the GLB; ignore them.
    let glb = &bytes[..declared];
    let json = chunk(glb, GLB_HEADER_BYTES, "first")?;
    if &glb[json.kind.clone()] != CHUNK_JSON {
        return Err("GLB's first chunk is not a JSON chunk".to_string());
    }
    let bin = if json.data.end + CHUNK_HEADER_BYTES <= glb.len() {
        let second = chunk(glb, json.data.end, "second")?;
        (&glb[second.kind] == CHUNK_BIN).then_some(second.data)
    } else {
        None
    };
    Ok((json.data, bin))
}

struct Chunk {
    kind: Range<usize>,
    data: Range<usize>,
}

/// The chunk whose header starts at `start`; its data must lie within `glb`.
fn chunk(glb: &[u8], start: usize, which: &str) -> Result<Chunk, String> {
    let Some(length) = read_u32(glb, start) else {
        return Err(format!(
            "GLB of {} bytes has no room for its {which} chunk's header",
            glb.len()
        ));
    };
    let kind = start + 4..start + CHUNK_HEADER_BYTES;
    let data_start = start + CHUNK_HEADER_BYTES;
    let available = glb.len().saturating_sub(data_start);
    if data_start > glb.len() || length as usize > available {
        return Err(format!(
            "GLB's {which} chunk claims {length} bytes but only {available} remain"
        ));
    }
    Ok(Chunk {
        kind,
        data: data_start..data_start + length as usize,
    })
}
