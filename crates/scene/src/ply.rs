//! Stanford PLY meshes, as Mitsuba and pbrt scenes name them: ASCII or binary (either byte
//! order), gzip-compressed where the name ends in `.gz` (as pbrt-v4 reads them);
//! a `vertex` element's `x y z`, `nx ny nz` and texture coordinates (`u v`, `s t` or
//! `texture_u texture_v`), a `face` element's index list (`vertex_indices` or `vertex_index`,
//! polygons fan-triangulated). Other elements and properties are read past. Every count is
//! checked against the bytes there, every index against the vertices.

use std::path::Path;

use glam::Vec3;

use crate::files::read_maybe_gzipped;
use crate::shapes::IndexedMesh;
use crate::{SceneError, Vertex};

/// The largest PLY file read.
const MAX_PLY_BYTES: u64 = 4 << 30;

#[derive(Clone, Copy, PartialEq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// A property's scalar type: its size in bytes, and whether it is a float or signed.
#[derive(Clone, Copy)]
struct Scalar {
    size: usize,
    float: bool,
    signed: bool,
}

fn scalar(name: &str) -> Option<Scalar> {
    let (size, float, signed) = match name {
        "char" | "int8" => (1, false, true),
        "uchar" | "uint8" => (1, false, false),
        "short" | "int16" => (2, false, true),
        "ushort" | "uint16" => (2, false, false),
        "int" | "int32" => (4, false, true),
        "uint" | "uint32" => (4, false, false),
        "float" | "float32" => (4, true, true),
        "double" | "float64" => (8, true, true),
        _ => return None,
    };
    Some(Scalar {
        size,
        float,
        signed,
    })
}

struct Property {
    name: String,
    /// `Some(count type)` for a list.
    list: Option<Scalar>,
    value: Scalar,
}

struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Reads values one after another from the body.
struct Body<'a> {
    bytes: &'a [u8],
    at: usize,
    encoding: Encoding,
}

impl Body<'_> {
    fn value(&mut self, s: Scalar) -> Result<f64, String> {
        if self.encoding == Encoding::Ascii {
            while self.at < self.bytes.len() && self.bytes[self.at].is_ascii_whitespace() {
                self.at += 1;
            }
            let start = self.at;
            while self.at < self.bytes.len() && !self.bytes[self.at].is_ascii_whitespace() {
                self.at += 1;
            }
            let word = std::str::from_utf8(&self.bytes[start..self.at]).unwrap_or("");
            return match word.parse::<f64>() {
                Ok(x) => Ok(x),
                Err(_) if word.is_empty() => Err("the file ends early".into()),
                Err(_) => Err(format!("\"{word}\" is not a number")),
            };
        }
        let bytes = self
            .bytes
            .get(self.at..self.at + s.size)
            .ok_or("the file ends early")?;
        self.at += s.size;
        let mut raw = [0u8; 8];
        raw[..s.size].copy_from_slice(bytes);
        if self.encoding == Encoding::Big {
            raw[..s.size].reverse();
        }
        Ok(match (s.size, s.float, s.signed) {
            (4, true, _) => f32::from_le_bytes(raw[..4].try_into().unwrap()) as f64,
            (8, true, _) => f64::from_le_bytes(raw),
            (1, _, true) => raw[0] as i8 as f64,
            (1, _, false) => raw[0] as f64,
            (2, _, true) => i16::from_le_bytes([raw[0], raw[1]]) as f64,
            (2, _, false) => u16::from_le_bytes([raw[0], raw[1]]) as f64,
            (4, _, true) => i32::from_le_bytes(raw[..4].try_into().unwrap()) as f64,
            _ => u32::from_le_bytes(raw[..4].try_into().unwrap()) as f64,
        })
    }
}

/// Reads a PLY file's indexed triangles (gunzipped first where its name ends in `.gz`).
pub(crate) fn read(path: &Path) -> Result<IndexedMesh, SceneError> {
    let bytes = read_maybe_gzipped(path, MAX_PLY_BYTES)?;
    parse(&bytes).map_err(|message| SceneError::format(path, message))
}

fn parse(bytes: &[u8]) -> Result<IndexedMesh, String> {
    let end = find(bytes, b"end_header").ok_or("not a PLY file (no end_header)")?;
    let header = std::str::from_utf8(&bytes[..end]).map_err(|_| "the header is not text")?;
    let mut body_start = end + b"end_header".len();
    // The line ending after end_header: \n or \r\n.
    if bytes.get(body_start) == Some(&b'\r') {
        body_start += 1;
    }
    if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let (encoding, elements) = parse_header(header)?;
    let mut body = Body {
        bytes: &bytes[body_start..],
        at: 0,
        encoding,
    };
    // Every value takes a byte at least (two in ASCII): no count may promise more.
    let most = body.bytes.len();
    let mut vertices: Vec<Vertex> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut with_normals = false;
    for element in &elements {
        if element.count > most {
            return Err(format!(
                "{} {}s cannot fit in the file",
                element.count, element.name
            ));
        }
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        if is_vertex {
            vertices.reserve(element.count);
        }
        for _ in 0..element.count {
            let mut vertex = Vertex::default();
            let mut has_normal = false;
            for property in &element.properties {
                let Some(count_type) = property.list else {
                    let value = body.value(property.value)? as f32;
                    if is_vertex {
                        has_normal |= set_vertex(&mut vertex, &property.name, value);
                    }
                    continue;
                };
                let count = body.value(count_type)?;
                if !(count >= 0.0 && count as usize <= most) {
                    return Err(format!("a list of {count} values cannot fit in the file"));
                }
                let mut indices = Vec::with_capacity(count as usize);
                for _ in 0..count as usize {
                    indices.push(body.value(property.value)?);
                }
                let is_indices =
                    matches!(property.name.as_str(), "vertex_indices" | "vertex_index");
                if is_face && is_indices {
                    fan(&indices, vertices.len(), &mut triangles)?;
                }
            }
            if is_vertex {
                if !vertex.position.is_finite() {
                    return Err(format!("vertex {} is not finite", vertices.len()));
                }
                if !has_normal || !vertex.normal.is_finite() {
                    vertex.normal = Vec3::ZERO;
                }
                with_normals |= has_normal;
                vertices.push(vertex);
            }
        }
    }
    if triangles.is_empty() {
        return Err("no faces".into());
    }
    Ok(IndexedMesh {
        vertices,
        triangles,
        with_normals,
    })
}

/// Sets the vertex attribute `name` names; whether it was a normal's.
fn set_vertex(vertex: &mut Vertex, name: &str, value: f32) -> bool {
    match name {
        "x" => vertex.position.x = value,
        "y" => vertex.position.y = value,
        "z" => vertex.position.z = value,
        "nx" => vertex.normal.x = value,
        "ny" => vertex.normal.y = value,
        "nz" => vertex.normal.z = value,
        "u" | "s" | "texture_u" | "texture_s" => vertex.uv.x = value,
        "v" | "t" | "texture_v" | "texture_t" => vertex.uv.y = value,
        _ => {}
    }
    matches!(name, "nx" | "ny" | "nz")
}

/// A polygon's triangles, fanned from its first corner, among `vertices` vertices.
fn fan(indices: &[f64], vertices: usize, triangles: &mut Vec<[u32; 3]>) -> Result<(), String> {
    let corner = |i: f64| match i >= 0.0 && i.fract() == 0.0 && (i as usize) < vertices {
        true => Ok(i as u32),
        false => Err(format!(
            "face index {i} is not one of the {vertices} vertices"
        )),
    };
    for k in 2..indices.len() {
        triangles.push([
            corner(indices[0])?,
            corner(indices[k - 1])?,
            corner(indices[k])?,
        ]);
    }
    Ok(())
}

fn parse_header(header: &str) -> Result<(Encoding, Vec<Element>), String> {
    let mut lines = header.lines().map(str::trim);
    if lines.next() != Some("ply") {
        return Err("not a PLY file (no \"ply\" line)".into());
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for line in lines {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words[..] {
            ["format", format, _] => {
                encoding = Some(match format {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(format!("unknown PLY format \"{other}\"")),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| format!("element {name}: count \"{count}\""))?,
                properties: Vec::new(),
            }),
            ["property", "list", count, value, name] => {
                let element = elements.last_mut().ok_or("a property before any element")?;
                let unknown = || format!("property {name}: unknown type");
                element.properties.push(Property {
                    name: name.to_string(),
                    list: Some(scalar(count).ok_or_else(unknown)?),
                    value: scalar(value).ok_or_else(unknown)?,
                });
            }
            ["property", value, name] => {
                let element = elements.last_mut().ok_or("a property before any element")?;
                element.properties.push(Property {
                    name: name.to_string(),
                    list: None,
                    value: scalar(value)
                        .ok_or_else(|| format!("property {name}: unknown type \"{value}\""))?,
                });
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            _ => return Err(format!("unreadable header line \"{line}\"")),
        }
    }
    Ok((encoding.ok_or("no format line")?, elements))
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    const ASCII_QUAD: &str = "ply\nformat ascii 1.0\ncomment a quad\nelement vertex 4\n\
        property float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n";

    #[test]
    fn an_ascii_quad_is_two_triangles() {
        let mesh = parse(ASCII_QUAD.as_bytes()).expect("a quad").smooth();
        assert_eq!(mesh.len(), 2);
        assert_eq!(mesh[1][2].position, Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(mesh[1][1].uv, Vec2::new(1.0, 1.0));
        // No normals given: smooth ones, as Mitsuba makes them.
        assert_eq!(mesh[0][0].normal, Vec3::Z);
    }

    #[test]
    fn gzipped_files_read_as_plain_ones_and_pbrt_keeps_them_flat() {
        use std::io::Write;
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        encoder.write_all(ASCII_QUAD.as_bytes()).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("quad.ply.gz");
        std::fs::write(&path, encoder.finish().unwrap()).unwrap();
        let mesh = read(&path).expect("a quad").flat();
        assert_eq!(mesh.len(), 2);
        // No normals given: none (flat, as pbrt shades it).
        assert_eq!(mesh[0][0].normal, Vec3::ZERO);
        std::fs::write(&path, ASCII_QUAD).unwrap();
        let error = read(&path).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(error.contains("not a gzip file"), "{error}");
    }

    /// The same quad in both binary byte orders, with normals and an extra element.
    #[test]
    fn binary_files_read_as_ascii_ones() {
        for (format, big) in [("binary_little_endian", false), ("binary_big_endian", true)] {
            let mut bytes = format!(
                "ply\nformat {format} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
                 property float z\nproperty float nz\nelement face 1\n\
                 property list uchar uint vertex_index\nelement extra 1\nproperty short s\nend_header\n"
            )
            .into_bytes();
            let f = |x: f32| {
                if big {
                    x.to_be_bytes()
                } else {
                    x.to_le_bytes()
                }
            };
            for [x, y] in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]] {
                for value in [x, y, 0.0, 1.0] {
                    bytes.extend(f(value));
                }
            }
            bytes.push(4);
            for i in 0u32..4 {
                bytes.extend(if big {
                    i.to_be_bytes()
                } else {
                    i.to_le_bytes()
                });
            }
            bytes.extend([0, 7]);
            let mesh = parse(&bytes).expect(format).smooth();
            assert_eq!(mesh.len(), 2, "{format}");
            assert_eq!(mesh[0][1].position, Vec3::X, "{format}");
            assert_eq!(mesh[0][1].normal, Vec3::Z, "{format}");
        }
    }

    #[test]
    fn bad_files_say_why() {
        let cases = [
            (
                ASCII_QUAD.replace("4 0 1 2 3", "4 0 1 2 9"),
                "not one of the 4 vertices",
            ),
            (
                ASCII_QUAD.replace("element vertex 4", "element vertex 99999999999"),
                "cannot fit",
            ),
            (
                ASCII_QUAD.replace("0 1 0 0 1\n4", "0 1 0 0 x\n4"),
                "not a number",
            ),
            (ASCII_QUAD.replace("end_header", "end"), "no end_header"),
            (ASCII_QUAD.replace("ascii", "utf16"), "unknown PLY format"),
            (ASCII_QUAD[..ASCII_QUAD.len() - 6].to_string(), "ends early"),
        ];
        for (text, why) in cases {
            let error = parse(text.as_bytes()).err().unwrap_or_default();
            assert!(error.contains(why), "{why}: {error}");
        }
    }
}
