//! Accessors: typed, strided arrays inside buffer views, read here by hand (little-endian)
//! after every bound has been checked: the type and component type the semantic allows,
//! `byteOffset + stride·(count−1) + element size ≤ bufferView.byteLength`, finite values.
//! Sparse accessors and accessors without a buffer view (all zeros) are not supported.
//! Where a file uses `KHR_mesh_quantization`, positions, normals and texture coordinates may
//! also be integers (dequantized here; the nodes' transforms scale them), as that extension
//! allows.

use glam::{Vec2, Vec3, Vec4};

use ::gltf::json;
use json::accessor::{ComponentType, Type};
use json::validation::Checked;

use super::{Context, Input};

/// The extension that lets vertex attributes be small integers.
pub(super) const QUANTIZATION: &str = "KHR_mesh_quantization";
use crate::SceneError;

/// What an accessor is read as; each allows the types the glTF spec allows for it, and with
/// `KHR_mesh_quantization` the integer types that extension adds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Semantic {
    /// VEC3 of FLOAT (quantized: also of BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT,
    /// normalized or not).
    Position,
    /// VEC3 of FLOAT (quantized: also of normalized BYTE or SHORT).
    Normal,
    /// VEC2 of FLOAT, or of normalized UNSIGNED_BYTE / UNSIGNED_SHORT (quantized: also of
    /// BYTE, UNSIGNED_BYTE, SHORT, UNSIGNED_SHORT, normalized or not).
    TexCoord,
    /// SCALAR of UNSIGNED_BYTE / UNSIGNED_SHORT / UNSIGNED_INT.
    Indices,
    /// `EXT_mesh_gpu_instancing`'s TRANSLATION and SCALE: VEC3 of FLOAT.
    InstanceVector,
    /// Its ROTATION: VEC4 of FLOAT, or of normalized BYTE / SHORT (a quaternion).
    InstanceRotation,
    /// TANGENT: VEC4 of FLOAT (quantized: also of normalized BYTE or SHORT).
    Tangent,
}

impl Semantic {
    fn accepts(
        self,
        ty: Type,
        component: ComponentType,
        normalized: bool,
        quantized: bool,
    ) -> bool {
        use ComponentType::{F32, I8, I16, U8, U16, U32};
        let small = matches!(component, I8 | U8 | I16 | U16);
        match self {
            Semantic::Position => ty == Type::Vec3 && (component == F32 || (quantized && small)),
            Semantic::Normal => {
                ty == Type::Vec3
                    && (component == F32
                        || (quantized && normalized && matches!(component, I8 | I16)))
            }
            Semantic::TexCoord => {
                ty == Type::Vec2
                    && (component == F32
                        || (normalized && matches!(component, U8 | U16))
                        || (quantized && small))
            }
            Semantic::Indices => ty == Type::Scalar && matches!(component, U8 | U16 | U32),
            Semantic::InstanceVector => ty == Type::Vec3 && component == F32,
            Semantic::InstanceRotation => {
                ty == Type::Vec4
                    && (component == F32 || (normalized && matches!(component, I8 | I16)))
            }
            Semantic::Tangent => {
                ty == Type::Vec4
                    && (component == F32
                        || (quantized && normalized && matches!(component, I8 | I16)))
            }
        }
    }

    fn expected(self, quantized: bool) -> &'static str {
        match (self, quantized) {
            (Semantic::Position, false) | (Semantic::Normal, false) => "VEC3 of FLOAT",
            (Semantic::Position, true) => {
                "VEC3 of FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT"
            }
            (Semantic::Normal, true) => "VEC3 of FLOAT or of normalized BYTE/SHORT",
            (Semantic::TexCoord, false) => {
                "VEC2 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT"
            }
            (Semantic::TexCoord, true) => {
                "VEC2 of FLOAT, BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT"
            }
            (Semantic::Indices, _) => "SCALAR of UNSIGNED_BYTE/UNSIGNED_SHORT/UNSIGNED_INT",
            (Semantic::InstanceVector, _) => "VEC3 of FLOAT",
            (Semantic::InstanceRotation, _) | (Semantic::Tangent, true) => {
                "VEC4 of FLOAT or of normalized BYTE/SHORT"
            }
            (Semantic::Tangent, false) => "VEC4 of FLOAT",
        }
    }
}

/// A checked accessor: element `i` is `bytes[i·stride ..][.. element_size]`, all in bounds.
struct Elements<'a> {
    bytes: &'a [u8],
    stride: usize,
    count: usize,
    element_size: usize,
    component: ComponentType,
    normalized: bool,
}

impl Elements<'_> {
    fn get(&self, i: usize) -> &[u8] {
        let start = i * self.stride;
        &self.bytes[start..start + self.element_size]
    }

    /// Component `k` of element `i` as a float: normalized integers as glTF maps them
    /// (unsigned to [0, 1], signed to [−1, 1]: c / max, at least −1), others as they are.
    fn float(&self, i: usize, k: usize) -> f32 {
        let e = self.get(i);
        let (value, max) = match self.component {
            ComponentType::U8 => (f32::from(e[k]), 255.0),
            ComponentType::I8 => (f32::from(e[k] as i8), 127.0),
            ComponentType::U16 => (
                f32::from(u16::from_le_bytes([e[2 * k], e[2 * k + 1]])),
                65535.0,
            ),
            ComponentType::I16 => (
                f32::from(i16::from_le_bytes([e[2 * k], e[2 * k + 1]])),
                32767.0,
            ),
            _ => {
                return f32::from_le_bytes([e[4 * k], e[4 * k + 1], e[4 * k + 2], e[4 * k + 3]]);
            }
        };
        if self.normalized {
            (value / max).max(-1.0)
        } else {
            value
        }
    }

    /// Element `i` of a SCALAR unsigned-integer accessor.
    fn unsigned(&self, i: usize) -> u32 {
        let e = self.get(i);
        match self.component {
            ComponentType::U8 => e[0] as u32,
            ComponentType::U16 => u16::from_le_bytes([e[0], e[1]]) as u32,
            _ => u32::from_le_bytes([e[0], e[1], e[2], e[3]]),
        }
    }
}

/// The number of elements of accessor `index`, checked for `semantic` and against its
/// buffer view, without reading them.
pub(super) fn count(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
) -> Result<usize, SceneError> {
    let elements =
        elements(input, index, semantic).context(|| format!("accessor {index} ({role})"))?;
    Ok(elements.count)
}

/// Reads a VEC3 accessor (POSITION, NORMAL, an instance's TRANSLATION or SCALE). `role` says
/// where it is used, for errors. Non-finite positions and instance vectors are an error;
/// non-finite normals are left to the builder, which replaces them by the geometric normal.
pub(super) fn read_vec3(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
) -> Result<Vec<Vec3>, SceneError> {
    let must_be_finite = matches!(semantic, Semantic::Position | Semantic::InstanceVector);
    read_finite(
        input,
        index,
        semantic,
        role,
        must_be_finite,
        "a non-finite position",
    )
}

/// Reads an `EXT_mesh_gpu_instancing` ROTATION accessor as quaternions (x, y, z, w), every
/// component finite, or a TANGENT accessor, whose non-finite tangents the mesh drops (its
/// vertex then takes the triangle's texture frame).
pub(super) fn read_vec4(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
) -> Result<Vec<Vec4>, SceneError> {
    let must_be_finite = semantic == Semantic::InstanceRotation;
    read_finite(
        input,
        index,
        semantic,
        role,
        must_be_finite,
        "a non-finite rotation",
    )
}

/// Reads a TEXCOORD accessor; every coordinate must be finite.
pub(super) fn read_texcoords(
    input: &Input,
    index: usize,
    role: &str,
) -> Result<Vec<Vec2>, SceneError> {
    let semantic = Semantic::TexCoord;
    read_finite(
        input,
        index,
        semantic,
        role,
        true,
        "a non-finite texture coordinate",
    )
}

/// A vector of floats read from an accessor, `N` components an element.
trait FloatVector: Sized + std::fmt::Display {
    fn from_components(read: impl Fn(usize) -> f32) -> Self;
    fn is_finite(&self) -> bool;
}

impl FloatVector for Vec2 {
    fn from_components(read: impl Fn(usize) -> f32) -> Self {
        Vec2::new(read(0), read(1))
    }
    fn is_finite(&self) -> bool {
        Vec2::is_finite(*self)
    }
}

impl FloatVector for Vec3 {
    fn from_components(read: impl Fn(usize) -> f32) -> Self {
        Vec3::new(read(0), read(1), read(2))
    }
    fn is_finite(&self) -> bool {
        Vec3::is_finite(*self)
    }
}

impl FloatVector for Vec4 {
    fn from_components(read: impl Fn(usize) -> f32) -> Self {
        Vec4::new(read(0), read(1), read(2), read(3))
    }
    fn is_finite(&self) -> bool {
        Vec4::is_finite(*self)
    }
}

/// Reads accessor `index` as `semantic`, element by element; where `must_be_finite`, a
/// non-finite element is an error saying the vertex has `what`.
fn read_finite<V: FloatVector>(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
    must_be_finite: bool,
    what: &str,
) -> Result<Vec<V>, SceneError> {
    let context = || format!("accessor {index} ({role})");
    let elements = elements(input, index, semantic).context(context)?;
    let mut values = Vec::with_capacity(elements.count);
    for i in 0..elements.count {
        let v = V::from_components(|k| elements.float(i, k));
        if must_be_finite && !v.is_finite() {
            return Err(input.error(format!("{}: vertex {i} has {what} {v}", context())));
        }
        values.push(v);
    }
    Ok(values)
}

/// Reads an index accessor; every index must be below `vertex_count`.
pub(super) fn read_indices(
    input: &Input,
    index: usize,
    role: &str,
    vertex_count: usize,
) -> Result<Vec<u32>, SceneError> {
    let context = || format!("accessor {index} ({role})");
    let elements = elements(input, index, Semantic::Indices).context(context)?;
    let mut values = Vec::with_capacity(elements.count);
    for i in 0..elements.count {
        let value = elements.unsigned(i);
        if value as usize >= vertex_count {
            return Err(input.error(format!(
                "{}: index {value} out of range for {vertex_count} vertices",
                context()
            )));
        }
        values.push(value);
    }
    Ok(values)
}

/// Checks accessor `index` for `semantic` and locates its elements.
fn elements<'a>(
    input: &'a Input,
    index: usize,
    semantic: Semantic,
) -> Result<Elements<'a>, SceneError> {
    let Some(accessor) = input.root.accessors.get(index) else {
        return Err(input.error(format!(
            "does not exist ({} accessors)",
            input.root.accessors.len()
        )));
    };
    if accessor.sparse.is_some() {
        return Err(input.unsupported("sparse accessors are not supported"));
    }
    let Some(view_index) = accessor.buffer_view else {
        return Err(
            input.unsupported("accessors without a bufferView (all zeros) are not supported")
        );
    };
    let (ty, component) = kind(input, accessor, semantic)?;
    let view = input.buffers.view(view_index.value())?;
    let element_size = ty.multiplicity() * component.size();
    let stride = view.stride.unwrap_or(element_size);
    let offset = accessor.byte_offset.map_or(0, |o| o.0);
    let count = accessor.count.0;
    let needed = match count {
        0 => Some(offset),
        n => (stride as u64)
            .checked_mul(n - 1)
            .and_then(|s| s.checked_add(offset))
            .and_then(|s| s.checked_add(element_size as u64)),
    };
    let view_length = view.bytes.len() as u64;
    match needed {
        Some(needed) if needed <= view_length => Ok(Elements {
            bytes: &view.bytes[offset as usize..],
            stride,
            count: count as usize,
            element_size,
            component,
            normalized: accessor.normalized,
        }),
        _ => Err(input.error(format!(
            "{count} elements of {element_size} bytes, {stride} apart from offset {offset}, \
             overrun bufferView {} of {view_length} bytes",
            view_index.value()
        ))),
    }
}

/// The accessor's type and component type, if `semantic` allows them.
fn kind(
    input: &Input,
    accessor: &json::Accessor,
    semantic: Semantic,
) -> Result<(Type, ComponentType), SceneError> {
    let (Checked::Valid(ty), Checked::Valid(component)) = (accessor.type_, accessor.component_type)
    else {
        return Err(input.error("invalid type or componentType"));
    };
    let component = component.0;
    let quantized = input.uses_extension(QUANTIZATION);
    if !semantic.accepts(ty, component, accessor.normalized, quantized) {
        let normalized = if accessor.normalized {
            "normalized "
        } else {
            ""
        };
        return Err(input.error(format!(
            "expected {}, found {} of {normalized}{}",
            semantic.expected(quantized),
            type_name(ty),
            component_name(component)
        )));
    }
    Ok((ty, component))
}

fn type_name(ty: Type) -> &'static str {
    match ty {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn component_name(component: ComponentType) -> &'static str {
    match component {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}
