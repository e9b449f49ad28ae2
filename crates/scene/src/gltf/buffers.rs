//! Buffers and buffer views. A buffer is loaded the first time a view of it is read (so an
//! unused `.bin`, say one holding only animations, is never opened), and only after its
//! declared `byteLength` has been checked against the bytes really there: nothing is ever
//! allocated on a length the file merely claims. A view compressed by
//! `EXT_meshopt_compression` or `KHR_meshopt_compression` is decoded from its compressed range
//! on first use ([`super::meshopt`]); its fallback buffer, which may hold nothing, is never
//! read.

use std::cell::OnceCell;
use std::path::Path;

use ::gltf::json;

use super::Context;
use super::meshopt::{self, Compressed};
use super::uri::{self, Resolved, UriError};
use crate::SceneError;

/// The extensions that compress buffer views: the original and Khronos's, which adds version 1
/// of the attribute codec and the colour filter (`super::meshopt`).
pub(super) const MESHOPT: [&str; 2] = ["EXT_meshopt_compression", "KHR_meshopt_compression"];

/// The bytes of a buffer view and its stride, if it declares one.
#[derive(Clone, Copy)]
pub(super) struct View<'a> {
    pub bytes: &'a [u8],
    pub stride: Option<usize>,
}

pub(super) struct Buffers<'a> {
    /// The glTF file: errors name it, relative URIs start from its folder.
    path: &'a Path,
    buffers: &'a [json::Buffer],
    views: &'a [json::buffer::View],
    glb_bin: Option<&'a [u8]>,
    loaded: Vec<OnceCell<Vec<u8>>>,
    /// Compressed views, decoded.
    decoded: Vec<OnceCell<Vec<u8>>>,
}

impl<'a> Buffers<'a> {
    pub fn new(path: &'a Path, root: &'a json::Root, glb_bin: Option<&'a [u8]>) -> Self {
        Buffers {
            path,
            buffers: &root.buffers,
            views: &root.buffer_views,
            glb_bin,
            loaded: root.buffers.iter().map(|_| OnceCell::new()).collect(),
            decoded: root.buffer_views.iter().map(|_| OnceCell::new()).collect(),
        }
    }

    /// Buffer view `index`, checked to lie within its buffer.
    pub fn view(&self, index: usize) -> Result<View<'_>, SceneError> {
        let Some(view) = self.views.get(index) else {
            return Err(self.error(format!(
                "bufferView {index} does not exist ({} buffer views)",
                self.views.len()
            )));
        };
        let stride = match view.byte_stride {
            Some(json::buffer::Stride(s)) if !(4..=252).contains(&s) || s % 4 != 0 => {
                return Err(self.error(format!(
                    "bufferView {index}: byteStride {s} is not a multiple of 4 in [4, 252]"
                )));
            }
            stride => stride.map(|s| s.0),
        };
        let compressed = (view.extensions.as_ref()).and_then(|e| {
            MESHOPT.iter().find_map(|&name| {
                let value = e.others.get(name)?;
                Some((name, serde_json::from_value::<Compressed>(value.clone())))
            })
        });
        if let Some((name, compressed)) = compressed {
            let context = || format!("bufferView {index}: {name}");
            let compressed = compressed
                .map_err(|e| self.error(e.to_string()))
                .context(context)?;
            let bytes = self.decoded_view(index, &compressed).context(context)?;
            return Ok(View { bytes, stride });
        }
        let buffer = self
            .buffer(view.buffer.value())
            .context(|| format!("bufferView {index}"))?;
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let length = view.byte_length.0;
        let end = offset.saturating_add(length);
        if end > buffer.len() as u64 {
            return Err(self.error(format!(
                "bufferView {index} (bytes {offset}..{end}) overruns buffer {} of {} bytes",
                view.buffer.value(),
                buffer.len()
            )));
        }
        Ok(View {
            bytes: &buffer[offset as usize..end as usize],
            stride,
        })
    }

    /// The bytes a compressed view decodes to, decoded on first use: `count × byteStride`
    /// of them, which must be the view's `byteLength`.
    fn decoded_view(&self, index: usize, compressed: &Compressed) -> Result<&[u8], SceneError> {
        let view = &self.views[index];
        let cell = &self.decoded[index];
        if let Some(bytes) = cell.get() {
            return Ok(bytes);
        }
        let decoded_length = (compressed.count as u64).checked_mul(compressed.byte_stride as u64);
        if decoded_length != Some(view.byte_length.0) {
            return Err(self.error(format!(
                "{} elements of {} bytes do not fill the view's {} bytes",
                compressed.count, compressed.byte_stride, view.byte_length.0
            )));
        }
        let source = self.buffer(compressed.buffer)?;
        let start = compressed.byte_offset;
        let end = start.saturating_add(compressed.byte_length);
        if end > source.len() as u64 {
            return Err(self.error(format!(
                "its compressed bytes {start}..{end} overrun buffer {} of {} bytes",
                compressed.buffer,
                source.len()
            )));
        }
        let data = &source[start as usize..end as usize];
        let bytes = meshopt::decode(compressed, data).map_err(|e| self.error(e))?;
        Ok(cell.get_or_init(|| bytes).as_slice())
    }

    /// Buffer `index`: exactly `byteLength` bytes, loaded on first use.
    fn buffer(&self, index: usize) -> Result<&[u8], SceneError> {
        let Some(buffer) = self.buffers.get(index) else {
            return Err(self.error(format!(
                "buffer {index} does not exist ({} buffers)",
                self.buffers.len()
            )));
        };
        let declared = buffer.byte_length.0;
        let context = || format!("buffer {index}");
        if buffer.uri.is_none() {
            // GLB: the first buffer without a URI is the BIN chunk.
            let bin = match self.glb_bin {
                Some(bin) if index == 0 => bin,
                _ => {
                    return Err(self.error(format!(
                        "buffer {index} has no uri, and no GLB BIN chunk stands for it"
                    )));
                }
            };
            return self.check_length(bin, declared).context(context);
        }
        if let Some(bytes) = self.loaded[index].get() {
            return Ok(bytes);
        }
        let bytes = self.load(buffer).context(context)?;
        self.check_length(&bytes, declared).context(context)?;
        Ok(self.loaded[index].get_or_init(|| bytes).as_slice())
    }

    /// The first `declared` bytes of `bytes`, if it has that many.
    fn check_length<'b>(&self, bytes: &'b [u8], declared: u64) -> Result<&'b [u8], SceneError> {
        match usize::try_from(declared) {
            Ok(n) if n <= bytes.len() => Ok(&bytes[..n]),
            _ => Err(self.error(format!(
                "byteLength is {declared} but only {} bytes are there",
                bytes.len()
            ))),
        }
    }

    fn load(&self, buffer: &json::Buffer) -> Result<Vec<u8>, SceneError> {
        let uri = buffer.uri.as_deref().unwrap_or_default();
        match resolve_uri(self.path, uri)? {
            Resolved::Data(bytes) => Ok(bytes),
            Resolved::File(file) => read_regular(&file, Some(buffer.byte_length.0)),
        }
    }

    fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::format(self.path, message)
    }
}

/// Resolves a buffer's or an image's URI relative to the glTF file `path`.
pub(super) fn resolve_uri(path: &Path, uri: &str) -> Result<Resolved, SceneError> {
    let base_dir = path.parent().unwrap_or(Path::new(""));
    uri::resolve(base_dir, uri).map_err(|e| match e {
        UriError::Malformed(m) => SceneError::format(path, m),
        UriError::Unsupported(m) => SceneError::unsupported(path, m),
    })
}

/// Reads at most `limit` bytes (all of it if `None`) of `file`, which must be a regular file
/// (not a device such as /dev/zero, nor a pipe). Nothing is allocated beyond what the file
/// holds: a file shorter than a buffer's declared length gives fewer bytes, which the caller
/// reports.
pub(super) fn read_regular(file: &Path, limit: Option<u64>) -> Result<Vec<u8>, SceneError> {
    crate::files::read_regular_file(file, limit.unwrap_or(u64::MAX))
        .map(|(bytes, _)| bytes)
        .map_err(|e| SceneError::io(file, e))
}
