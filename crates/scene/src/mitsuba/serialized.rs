//! Mitsuba's own mesh files (`.serialized`, versions 3 and 4, as Mitsuba 0.6's exporters wrote
//! them): one or more meshes, each a header (`0x041C`, the version) and a zlib stream of flags,
//! (version 4) a name, vertex and triangle counts, positions, optional normals, texture
//! coordinates and colours, in f32 or f64, and the triangles' indices; a table of the meshes'
//! offsets at the end of the file. The format was checked against Mitsuba 3's own loader.

use std::io::Read;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::files::read_regular_file;
use crate::shapes::{IndexedMesh, Mesh};
use crate::{SceneError, Vertex};

const MAGIC: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLOURS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;

/// The largest file read, and the most vertices and triangles a mesh may claim (as many as
/// a glTF file may place: `crate::gltf::MAX_TRIANGLES`).
const MAX_FILE_BYTES: u64 = 4 << 30;
const MAX_ELEMENTS: u64 = crate::gltf::MAX_TRIANGLES as u64;

/// Reads mesh `index` of a `.serialized` file.
pub(super) fn read(path: &Path, index: usize) -> Result<Mesh, SceneError> {
    let (bytes, length) =
        read_regular_file(path, MAX_FILE_BYTES).map_err(|e| SceneError::io(path, e))?;
    if length > MAX_FILE_BYTES {
        return Err(SceneError::format(path, "larger than kousen reads (4 GiB)"));
    }
    parse(&bytes, index).map_err(|message| SceneError::format(path, message))
}

fn parse(bytes: &[u8], index: usize) -> Result<Mesh, String> {
    let version = header(bytes)?;
    let start = match index {
        0 => 0,
        _ => mesh_offset(bytes, version, index)?,
    };
    let version = header(&bytes[start..])?;
    let mut stream = flate2::read::ZlibDecoder::new(&bytes[start + 4..]);
    let mut input = Stream(&mut stream);
    let flags = input.u32()?;
    if version == 4 {
        // The mesh's name, null-terminated (bounded, so a corrupt one ends).
        let mut length = 0;
        while input.u8()? != 0 {
            length += 1;
            if length > 4096 {
                return Err("a mesh name longer than 4096 bytes".into());
            }
        }
    }
    let vertex_count = input.u64()?;
    let triangle_count = input.u64()?;
    if vertex_count > MAX_ELEMENTS || triangle_count > MAX_ELEMENTS {
        return Err(format!(
            "{vertex_count} vertices and {triangle_count} triangles: more than kousen reads"
        ));
    }
    let real = |input: &mut Stream<'_>| -> Result<f32, String> {
        match flags & DOUBLE_PRECISION {
            0 => input.f32(),
            _ => input.f64().map(|x| x as f32),
        }
    };
    let mut vertices = vec![Vertex::default(); vertex_count as usize];
    for v in &mut vertices {
        v.position = Vec3::new(real(&mut input)?, real(&mut input)?, real(&mut input)?);
        if !v.position.is_finite() {
            return Err("a vertex position is not finite".into());
        }
    }
    if flags & HAS_NORMALS != 0 {
        for v in &mut vertices {
            let n = Vec3::new(real(&mut input)?, real(&mut input)?, real(&mut input)?);
            v.normal = if n.is_finite() { n } else { Vec3::ZERO };
        }
    }
    if flags & HAS_TEXCOORDS != 0 {
        for v in &mut vertices {
            v.uv = Vec2::new(real(&mut input)?, real(&mut input)?);
        }
    }
    if flags & HAS_COLOURS != 0 {
        for _ in 0..3 * vertex_count {
            real(&mut input)?;
        }
    }
    let wide = vertex_count > u32::MAX as u64;
    let mut triangles = Vec::with_capacity(triangle_count as usize);
    for _ in 0..triangle_count {
        let mut triangle = [0u32; 3];
        for corner in &mut triangle {
            let i = if wide {
                input.u64()?
            } else {
                input.u32()? as u64
            };
            if i >= vertex_count {
                return Err(format!(
                    "index {i} is not one of the {vertex_count} vertices"
                ));
            }
            *corner = i as u32;
        }
        triangles.push(triangle);
    }
    if triangles.is_empty() {
        return Err("a mesh without triangles".into());
    }
    let mesh = IndexedMesh {
        vertices,
        triangles,
        with_normals: flags & HAS_NORMALS != 0,
    };
    Ok(mesh.smooth())
}

/// The version (3 or 4) of the mesh header at the start of `bytes`.
fn header(bytes: &[u8]) -> Result<u16, String> {
    let word = |at: usize| {
        bytes
            .get(at..at + 2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
    };
    match (word(0), word(2)) {
        (Some(MAGIC), Some(version @ (3 | 4))) => Ok(version),
        (Some(MAGIC), Some(version)) => Err(format!("version {version} (kousen reads 3 and 4)")),
        _ => Err("not a Mitsuba .serialized mesh (no 0x041C header)".into()),
    }
}

/// Where mesh `index` starts, from the table of offsets at the end of the file: the count of
/// meshes (u32) last, before it one offset a mesh (u64 in version 4, u32 in version 3).
fn mesh_offset(bytes: &[u8], version: u16, index: usize) -> Result<usize, String> {
    let read = |at: usize, size: usize| -> Option<u64> {
        let b = bytes.get(at..at + size)?;
        let mut raw = [0u8; 8];
        raw[..size].copy_from_slice(b);
        Some(u64::from_le_bytes(raw))
    };
    let end = bytes.len().checked_sub(4).ok_or("no table of meshes")?;
    let count = read(end, 4).ok_or("no table of meshes")? as usize;
    if index >= count {
        return Err(format!(
            "shape_index {index}: the file holds {count} meshes"
        ));
    }
    let size = if version == 4 { 8 } else { 4 };
    let table = end
        .checked_sub(count.checked_mul(size).ok_or("a corrupt table of meshes")?)
        .ok_or("a corrupt table of meshes")?;
    let offset = read(table + index * size, size).ok_or("a corrupt table of meshes")?;
    match usize::try_from(offset) {
        Ok(offset) if offset + 4 <= table => Ok(offset),
        _ => Err(format!(
            "mesh {index}'s offset {offset} lies outside the file"
        )),
    }
}

/// Little-endian values from the decompressed stream.
struct Stream<'a>(&'a mut dyn Read);

impl Stream<'_> {
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], String> {
        let mut buffer = [0u8; N];
        self.0.read_exact(&mut buffer).map_err(|e| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => "the mesh data ends early".to_string(),
            _ => format!("its compressed data is corrupt ({e})"),
        })?;
        Ok(buffer)
    }

    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.bytes::<1>()?[0])
    }

    fn u32(&mut self) -> Result<u32, String> {
        self.bytes().map(u32::from_le_bytes)
    }

    fn u64(&mut self) -> Result<u64, String> {
        self.bytes().map(u64::from_le_bytes)
    }

    fn f32(&mut self) -> Result<f32, String> {
        self.bytes().map(f32::from_le_bytes)
    }

    fn f64(&mut self) -> Result<f64, String> {
        self.bytes().map(f64::from_le_bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// One mesh as Mitsuba writes it (version 4, f32): `positions`, `normals` if given,
    /// and `triangles`.
    fn mesh(
        positions: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
        triangles: &[[u32; 3]],
    ) -> Vec<u8> {
        let mut body = Vec::new();
        let flags = 0x1000 | if normals.is_some() { HAS_NORMALS } else { 0 };
        body.extend(flags.to_le_bytes());
        body.extend(b"mesh\0");
        body.extend((positions.len() as u64).to_le_bytes());
        body.extend((triangles.len() as u64).to_le_bytes());
        for value in positions.iter().chain(normals.unwrap_or(&[])).flatten() {
            body.extend(value.to_le_bytes());
        }
        for index in triangles.iter().flatten() {
            body.extend(index.to_le_bytes());
        }
        let mut bytes = vec![0x1C, 0x04, 4, 0];
        let mut encoder =
            flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(&body).unwrap();
        bytes.extend(encoder.finish().unwrap());
        bytes
    }

    /// Two meshes and the table of their offsets.
    fn two_meshes() -> Vec<u8> {
        let first = mesh(
            &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            Some(&[[0.0, 0.0, 1.0]; 3]),
            &[[0, 1, 2]],
        );
        let square = [
            [0.0, 0.0, 2.0],
            [2.0, 0.0, 2.0],
            [2.0, 2.0, 2.0],
            [0.0, 2.0, 2.0],
        ];
        let second = mesh(&square, None, &[[0, 1, 2], [0, 2, 3]]);
        let mut bytes = first.clone();
        bytes.extend(&second);
        bytes.extend(0u64.to_le_bytes());
        bytes.extend((first.len() as u64).to_le_bytes());
        bytes.extend(2u32.to_le_bytes());
        bytes
    }

    #[test]
    fn meshes_are_found_by_index() {
        let bytes = two_meshes();
        let first = parse(&bytes, 0).expect("mesh 0");
        assert_eq!(first.len(), 1);
        assert_eq!(first[0][1].position, Vec3::X);
        let second = parse(&bytes, 1).expect("mesh 1");
        assert_eq!(second.len(), 2);
        assert_eq!(second[1][2].position, Vec3::new(0.0, 2.0, 2.0));
        // No normals in the file: smooth ones, facing +z.
        assert_eq!(second[0][0].normal, Vec3::Z);
    }

    #[test]
    fn bad_files_say_why() {
        let bytes = two_meshes();
        let mut truncated = mesh(&[[0.0; 3]; 3], None, &[[0, 1, 2]]);
        truncated.truncate(truncated.len() - 6);
        let mut bad_index = bytes.clone();
        bad_index.truncate(0);
        bad_index.extend(mesh(&[[0.0; 3]; 3], None, &[[0, 1, 7]]));
        let cases: [(&[u8], usize, &str); 5] = [
            (&bytes, 2, "holds 2 meshes"),
            (b"PLY not this", 0, "no 0x041C header"),
            (&truncated, 0, "ends early"),
            (&bad_index, 0, "index 7"),
            (&[0x1C, 0x04, 9, 0], 0, "version 9"),
        ];
        for (bytes, index, why) in cases {
            let error = parse(bytes, index).err().unwrap_or_default();
            assert!(error.contains(why), "{why}: {error}");
        }
    }
}
