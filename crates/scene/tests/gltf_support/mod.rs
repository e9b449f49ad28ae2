//! glTF files built in code for the loader's tests: a [`Doc`] collects JSON objects and one
//! binary buffer, then is written as `.gltf` with a data URI, `.gltf` + `.bin`, or `.glb`.
#![allow(dead_code)] // each test file uses a different part

use std::path::{Path, PathBuf};

use base64::Engine;
use scene::{Scene, SceneError};
use serde_json::{Value, json};

pub const UNSIGNED_BYTE: u32 = 5121;
pub const UNSIGNED_SHORT: u32 = 5123;
pub const UNSIGNED_INT: u32 = 5125;
pub const FLOAT: u32 = 5126;

/// How a [`Doc`] is written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Layout {
    /// `.gltf`, buffer as a base64 data URI.
    DataUri,
    /// `.gltf` + `scene.bin`.
    ExternalBin,
    /// `.glb`, buffer in the BIN chunk.
    Glb,
}

/// A glTF document under construction. `json` may be edited directly; if it has no
/// `buffers`, one covering the collected binary data is added when written.
pub struct Doc {
    pub json: Value,
    pub bin: Vec<u8>,
}

impl Default for Doc {
    fn default() -> Self {
        Doc {
            json: json!({ "asset": { "version": "2.0" } }),
            bin: Vec::new(),
        }
    }
}

impl Doc {
    /// Appends `value` to the top-level array `key`; returns its index.
    pub fn push(&mut self, key: &str, value: Value) -> usize {
        let array = self.json[key].as_array_mut();
        match array {
            Some(a) => {
                a.push(value);
                a.len() - 1
            }
            None => {
                self.json[key] = json!([value]);
                0
            }
        }
    }

    /// Adds `bytes` (4-byte aligned) to the buffer and a bufferView over them.
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.push(
            "bufferViews",
            json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes.len() }),
        )
    }

    /// Adds a view over `bytes` and an accessor reading `count` elements from it.
    pub fn accessor(&mut self, bytes: &[u8], component_type: u32, count: usize, ty: &str) -> usize {
        let view = self.view(bytes);
        self.push(
            "accessors",
            json!({ "bufferView": view, "componentType": component_type, "count": count, "type": ty }),
        )
    }

    pub fn vec3s(&mut self, values: &[[f32; 3]]) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let index = self.accessor(&bytes, FLOAT, values.len(), "VEC3");
        let (min, max) = bounds(values);
        self.json["accessors"][index]["min"] = json!(min);
        self.json["accessors"][index]["max"] = json!(max);
        index
    }

    pub fn vec2s(&mut self, values: &[[f32; 2]]) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        self.accessor(&bytes, FLOAT, values.len(), "VEC2")
    }

    /// An index accessor of the given component type.
    pub fn indices(&mut self, indices: &[u32], component_type: u32) -> usize {
        let bytes: Vec<u8> = match component_type {
            UNSIGNED_BYTE => indices.iter().map(|&i| i as u8).collect(),
            UNSIGNED_SHORT => indices
                .iter()
                .flat_map(|&i| (i as u16).to_le_bytes())
                .collect(),
            _ => indices.iter().flat_map(|&i| i.to_le_bytes()).collect(),
        };
        self.accessor(&bytes, component_type, indices.len(), "SCALAR")
    }

    /// A mesh of one indexed triangle primitive (u16 indices); returns the mesh index.
    pub fn mesh(
        &mut self,
        positions: &[[f32; 3]],
        indices: &[u32],
        material: Option<usize>,
    ) -> usize {
        let position = self.vec3s(positions);
        let indices = self.indices(indices, UNSIGNED_SHORT);
        let mut primitive = json!({ "attributes": { "POSITION": position }, "indices": indices });
        if let Some(m) = material {
            primitive["material"] = json!(m);
        }
        self.push("meshes", json!({ "primitives": [primitive] }))
    }

    pub fn node(&mut self, node: Value) -> usize {
        self.push("nodes", node)
    }

    /// A root node showing `mesh`, listed in scene 0.
    pub fn instance(&mut self, mesh: usize) -> usize {
        let node = self.node(json!({ "mesh": mesh }));
        self.add_root(node);
        node
    }

    /// Lists `node` in scene 0.
    pub fn add_root(&mut self, node: usize) {
        if self.json["scenes"].as_array().is_none() {
            self.json["scenes"] = json!([{ "nodes": [] }]);
        }
        self.json["scenes"][0]["nodes"]
            .as_array_mut()
            .expect("scene 0 has a node list")
            .push(json!(node));
    }

    pub fn material(&mut self, material: Value) -> usize {
        self.push("materials", material)
    }

    /// The JSON as written for `layout` (`bin_name` names the external buffer).
    pub fn json_for(&self, layout: Layout, bin_name: &str) -> Value {
        let mut json = self.json.clone();
        if json.get("buffers").is_none() && !self.bin.is_empty() {
            let mut buffer = json!({ "byteLength": self.bin.len() });
            match layout {
                Layout::DataUri => {
                    let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
                    buffer["uri"] = json!(format!("data:application/octet-stream;base64,{data}"));
                }
                Layout::ExternalBin => buffer["uri"] = json!(bin_name),
                Layout::Glb => {}
            }
            json["buffers"] = json!([buffer]);
        }
        json
    }

    /// Writes the document into `dir` as `scene.gltf`/`scene.glb`; returns its path.
    pub fn write(&self, dir: &Path, layout: Layout) -> PathBuf {
        let json = serde_json::to_vec(&self.json_for(layout, "scene.bin")).expect("JSON");
        let (name, bytes) = match layout {
            Layout::Glb => ("scene.glb", glb(&json, &self.bin)),
            Layout::ExternalBin => {
                std::fs::write(dir.join("scene.bin"), &self.bin).expect("write .bin");
                ("scene.gltf", json)
            }
            Layout::DataUri => ("scene.gltf", json),
        };
        let path = dir.join(name);
        std::fs::write(&path, bytes).expect("write scene");
        path
    }

    pub fn load_as(&self, layout: Layout) -> Result<Scene, SceneError> {
        let dir = tempfile::tempdir().expect("tempdir");
        scene::gltf::load(&self.write(dir.path(), layout))
    }

    /// Loads the document written with a data URI.
    pub fn load(&self) -> Result<Scene, SceneError> {
        self.load_as(Layout::DataUri)
    }
}

fn bounds(values: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut min = [f32::MAX; 3];
    let mut max = [f32::MIN; 3];
    for v in values {
        for k in 0..3 {
            min[k] = min[k].min(v[k]);
            max[k] = max[k].max(v[k]);
        }
    }
    (min, max)
}

/// A GLB container holding `json` and, if not empty, `bin`.
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |mut chunk: Vec<u8>, fill: u8| {
        chunk.resize(chunk.len().next_multiple_of(4), fill);
        chunk
    };
    let json = pad(json.to_vec(), b' ');
    let bin = pad(bin.to_vec(), 0);
    let mut out = Vec::new();
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}

/// Loads raw bytes written to a file called `name`.
pub fn load_bytes(name: &str, bytes: &[u8]) -> Result<Scene, SceneError> {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).expect("write");
    scene::gltf::load(&path)
}

/// The unit square in the xy plane, facing +z (counter-clockwise seen from +z).
pub const QUAD: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
];
pub const QUAD_INDICES: [u32; 6] = [0, 1, 2, 0, 2, 3];

/// A document showing [`QUAD`] once, with `material` if given.
pub fn quad_doc(material: Option<Value>) -> Doc {
    let mut doc = Doc::default();
    let material = material.map(|m| doc.material(m));
    let mesh = doc.mesh(&QUAD, &QUAD_INDICES, material);
    doc.instance(mesh);
    doc
}

/// The error's one-line message; panics (failing the test) if loading succeeded.
pub fn error_of(result: Result<Scene, SceneError>) -> String {
    match result {
        Ok(scene) => panic!(
            "expected an error, loaded {} triangles",
            scene.triangles.len()
        ),
        Err(e) => {
            let message = e.to_string();
            assert!(!message.contains('\n'), "multi-line error: {message}");
            message
        }
    }
}

/// Asserts that `message` contains every one of `parts`.
pub fn assert_mentions(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(
            message.contains(part),
            "{message:?} does not mention {part:?}"
        );
    }
}
