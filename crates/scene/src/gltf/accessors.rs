//! Accessors: typed, strided arrays inside buffer views, read here by hand (little-endian)
//! after every bound has been checked: the type and component type the semantic allows,
//! `byteOffset + stride·(count−1) + element size ≤ bufferView.byteLength`, finite values.
//! An accessor without a buffer view holds zeros; a sparse one replaces the elements its
//! indices name (each checked below its count) by its values: how exporters such as Blender
//! write morph targets, which move a few vertices. Where a file uses `KHR_mesh_quantization`, positions, normals and texture coordinates may
//! also be integers (dequantized here; the nodes' transforms scale them), as that extension
//! allows.

use glam::{Mat4, Vec2, Vec3, Vec4};

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
    /// A morph target's POSITION, NORMAL or TANGENT displacements: VEC3 of FLOAT (quantized:
    /// also of BYTE or SHORT, normalized or not).
    Displacement,
    /// JOINTS_n: VEC4 of UNSIGNED_BYTE / UNSIGNED_SHORT.
    Joints,
    /// WEIGHTS_n: VEC4 of FLOAT, or of normalized UNSIGNED_BYTE / UNSIGNED_SHORT.
    Weights,
    /// A skin's inverseBindMatrices: MAT4 of FLOAT.
    Matrix,
    /// An animation sampler's input: SCALAR of FLOAT (seconds).
    KeyTimes,
    /// An animation sampler's translations or scales: VEC3 of FLOAT.
    KeyVectors,
    /// Its rotations: VEC4 of FLOAT, or of normalized BYTE, UNSIGNED_BYTE, SHORT or
    /// UNSIGNED_SHORT.
    KeyRotations,
    /// Its morph target weights: SCALAR of FLOAT, or of those normalized integers.
    KeyWeights,
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
            Semantic::Displacement => {
                ty == Type::Vec3
                    && (component == F32 || (quantized && matches!(component, I8 | I16)))
            }
            Semantic::Joints => ty == Type::Vec4 && matches!(component, U8 | U16),
            Semantic::Weights => {
                ty == Type::Vec4
                    && (component == F32 || (normalized && matches!(component, U8 | U16)))
            }
            Semantic::Matrix => ty == Type::Mat4 && component == F32,
            Semantic::KeyTimes => ty == Type::Scalar && component == F32,
            Semantic::KeyVectors => ty == Type::Vec3 && component == F32,
            Semantic::KeyRotations => {
                ty == Type::Vec4 && (component == F32 || (normalized && small))
            }
            Semantic::KeyWeights => {
                ty == Type::Scalar && (component == F32 || (normalized && small))
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
            (Semantic::Displacement, false) => "VEC3 of FLOAT",
            (Semantic::Displacement, true) => "VEC3 of FLOAT, BYTE or SHORT",
            (Semantic::Joints, _) => "VEC4 of UNSIGNED_BYTE/UNSIGNED_SHORT",
            (Semantic::Weights, _) => "VEC4 of FLOAT or of normalized UNSIGNED_BYTE/UNSIGNED_SHORT",
            (Semantic::Matrix, _) => "MAT4 of FLOAT",
            (Semantic::KeyTimes, _) => "SCALAR of FLOAT",
            (Semantic::KeyVectors, _) => "VEC3 of FLOAT",
            (Semantic::KeyRotations, _) => "VEC4 of FLOAT or of normalized integers",
            (Semantic::KeyWeights, _) => "SCALAR of FLOAT or of normalized integers",
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

    /// Component `k` of element `i` of an unsigned-integer accessor.
    fn unsigned(&self, i: usize, k: usize) -> u32 {
        let e = self.get(i);
        match self.component {
            ComponentType::U8 => e[k] as u32,
            ComponentType::U16 => u16::from_le_bytes([e[2 * k], e[2 * k + 1]]) as u32,
            _ => u32::from_le_bytes([e[4 * k], e[4 * k + 1], e[4 * k + 2], e[4 * k + 3]]),
        }
    }
}

/// A checked accessor: its elements (zeros where it has no buffer view) and, where it is
/// sparse, the elements replacing some of them.
struct Accessor<'a> {
    base: Elements<'a>,
    sparse: Option<Sparse<'a>>,
    /// Components an element.
    width: usize,
}

/// A sparse accessor's substitutions: element `indices[j]` is `values[j]`.
struct Sparse<'a> {
    indices: Elements<'a>,
    values: Elements<'a>,
}

impl Accessor<'_> {
    /// Every element read by `read`, the sparse substitutions made; an index at or past the
    /// count is an error.
    fn read_all<T>(
        &self,
        input: &Input,
        read: impl Fn(&Elements, usize) -> T,
    ) -> Result<Vec<T>, SceneError> {
        let count = self.base.count;
        let mut values: Vec<T> = (0..count).map(|i| read(&self.base, i)).collect();
        if let Some(sparse) = &self.sparse {
            for j in 0..sparse.indices.count {
                let target = sparse.indices.unsigned(j, 0) as usize;
                let Some(value) = values.get_mut(target) else {
                    return Err(input.error(format!(
                        "sparse index {target} out of range for {count} elements"
                    )));
                };
                *value = read(&sparse.values, j);
            }
        }
        Ok(values)
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
    let accessor =
        accessor(input, index, semantic).context(|| format!("accessor {index} ({role})"))?;
    Ok(accessor.base.count)
}

/// Reads a VEC3 accessor (POSITION, NORMAL, a morph target's displacements, an instance's
/// TRANSLATION or SCALE). `role` says where it is used, for errors. Non-finite positions,
/// displacements and instance vectors are an error; non-finite normals are left to the
/// builder, which replaces them by the geometric normal.
pub(super) fn read_vec3(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
) -> Result<Vec<Vec3>, SceneError> {
    let must_be_finite = matches!(
        semantic,
        Semantic::Position | Semantic::InstanceVector | Semantic::Displacement
    );
    read_finite(
        input,
        index,
        semantic,
        role,
        must_be_finite,
        "a non-finite position or displacement",
    )
}

/// Reads an `EXT_mesh_gpu_instancing` ROTATION accessor as quaternions (x, y, z, w), every
/// component finite; a WEIGHTS accessor, every weight finite; or a TANGENT accessor, whose
/// non-finite tangents the mesh drops (its vertex then takes the triangle's texture frame).
pub(super) fn read_vec4(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
) -> Result<Vec<Vec4>, SceneError> {
    let must_be_finite = matches!(semantic, Semantic::InstanceRotation | Semantic::Weights);
    read_finite(
        input,
        index,
        semantic,
        role,
        must_be_finite,
        "a non-finite rotation or weight",
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

/// Reads a skin's inverseBindMatrices (column-major); every element must be finite.
pub(super) fn read_matrices(
    input: &Input,
    index: usize,
    role: &str,
) -> Result<Vec<Mat4>, SceneError> {
    let context = || format!("accessor {index} ({role})");
    let accessor = accessor(input, index, Semantic::Matrix).context(context)?;
    let matrices = accessor
        .read_all(input, |e, i| {
            Mat4::from_cols_array(&std::array::from_fn(|k| e.float(i, k)))
        })
        .context(context)?;
    if let Some(i) = matrices.iter().position(|m| !m.is_finite()) {
        return Err(input.error(format!("{}: matrix {i} is not finite", context())));
    }
    Ok(matrices)
}

/// Reads a float accessor of any width as one flat list, every value finite, with its width
/// (components an element): animation keyframe times and values.
pub(super) fn read_floats(
    input: &Input,
    index: usize,
    semantic: Semantic,
    role: &str,
) -> Result<(Vec<f32>, usize), SceneError> {
    let context = || format!("accessor {index} ({role})");
    let accessor = accessor(input, index, semantic).context(context)?;
    let width = accessor.width;
    let elements = accessor
        .read_all(input, |e, i| {
            (0..width).map(|k| e.float(i, k)).collect::<Vec<f32>>()
        })
        .context(context)?;
    let values: Vec<f32> = elements.into_iter().flatten().collect();
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(input.error(format!(
            "{}: element {} is not finite",
            context(),
            i / width.max(1)
        )));
    }
    Ok((values, width))
}

/// Reads a JOINTS_n accessor: four joint indices a vertex (into its skin's `joints`).
pub(super) fn read_joints(
    input: &Input,
    index: usize,
    role: &str,
) -> Result<Vec<[u32; 4]>, SceneError> {
    let context = || format!("accessor {index} ({role})");
    let accessor = accessor(input, index, Semantic::Joints).context(context)?;
    accessor
        .read_all(input, |e, i| std::array::from_fn(|k| e.unsigned(i, k)))
        .context(context)
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
    let accessor = accessor(input, index, semantic).context(context)?;
    let values = accessor
        .read_all(input, |e, i| V::from_components(|k| e.float(i, k)))
        .context(context)?;
    // Looked for only where it matters (normals and tangents may hold non-finite values).
    let non_finite = (must_be_finite)
        .then(|| values.iter().enumerate().find(|(_, v)| !v.is_finite()))
        .flatten();
    if let Some((i, v)) = non_finite {
        return Err(input.error(format!("{}: vertex {i} has {what} {v}", context())));
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
    let accessor = accessor(input, index, Semantic::Indices).context(context)?;
    let values = accessor
        .read_all(input, |e, i| e.unsigned(i, 0))
        .context(context)?;
    if let Some(value) = values.iter().find(|&&v| v as usize >= vertex_count) {
        return Err(input.error(format!(
            "{}: index {value} out of range for {vertex_count} vertices",
            context()
        )));
    }
    Ok(values)
}

/// The bytes an accessor without a buffer view reads: zeros, one element long (its stride is
/// 0), as long as the largest element (MAT4 of FLOAT).
static ZEROS: [u8; 64] = [0; 64];

/// Checks accessor `index` for `semantic` and locates its elements and sparse substitutions.
fn accessor<'a>(
    input: &'a Input,
    index: usize,
    semantic: Semantic,
) -> Result<Accessor<'a>, SceneError> {
    let Some(accessor) = input.root.accessors.get(index) else {
        return Err(input.error(format!(
            "does not exist ({} accessors)",
            input.root.accessors.len()
        )));
    };
    let (ty, component) = kind(input, accessor, semantic)?;
    let element_size = ty.multiplicity() * component.size();
    let count = accessor.count.0;
    let normalized = accessor.normalized;
    let base = match accessor.buffer_view {
        Some(view_index) => {
            let view_index = view_index.value();
            let view = input.buffers.view(view_index)?;
            let offset = accessor.byte_offset.map_or(0, |o| o.0);
            let stride = view.stride.unwrap_or(element_size);
            let placed = Placed {
                count,
                element_size,
                stride,
                offset,
            };
            let bytes = placed.within(view.bytes).ok_or_else(|| {
                let length = view.bytes.len();
                input.error(format!(
                    "{placed}, overrun bufferView {view_index} of {length} bytes"
                ))
            })?;
            Elements {
                bytes,
                stride,
                count: count as usize,
                element_size,
                component,
                normalized,
            }
        }
        None => Elements {
            bytes: &ZEROS[..element_size],
            stride: 0,
            count: count as usize,
            element_size,
            component,
            normalized,
        },
    };
    let sparse = match &accessor.sparse {
        None => None,
        Some(sparse) => Some(sparse_substitutions(
            input,
            sparse,
            element_size,
            (component, normalized),
        )?),
    };
    Ok(Accessor {
        base,
        sparse,
        width: ty.multiplicity(),
    })
}

/// A sparse accessor's indices and values, each tightly packed in its buffer view.
fn sparse_substitutions<'a>(
    input: &'a Input,
    sparse: &json::accessor::sparse::Sparse,
    element_size: usize,
    (component, normalized): (ComponentType, bool),
) -> Result<Sparse<'a>, SceneError> {
    let count = sparse.count.0;
    let Checked::Valid(index_type) = sparse.indices.component_type else {
        return Err(input.error("sparse indices: invalid componentType"));
    };
    let index_type = index_type.0;
    if !matches!(
        index_type,
        ComponentType::U8 | ComponentType::U16 | ComponentType::U32
    ) {
        return Err(input.error(format!(
            "sparse indices: expected UNSIGNED_BYTE/UNSIGNED_SHORT/UNSIGNED_INT, found {}",
            component_name(index_type)
        )));
    }
    let packed = |what: &str, view_index: usize, offset: u64, size: usize| {
        let view = input.buffers.view(view_index)?;
        let placed = Placed {
            count,
            element_size: size,
            stride: size,
            offset,
        };
        placed.within(view.bytes).ok_or_else(|| {
            let length = view.bytes.len();
            input.error(format!(
                "sparse {what}: {placed}, overrun bufferView {view_index} of {length} bytes"
            ))
        })
    };
    let index_size = index_type.size();
    let indices = packed(
        "indices",
        sparse.indices.buffer_view.value(),
        sparse.indices.byte_offset.0,
        index_size,
    )?;
    let values = packed(
        "values",
        sparse.values.buffer_view.value(),
        sparse.values.byte_offset.0,
        element_size,
    )?;
    let elements = |bytes, element_size, component, normalized| Elements {
        bytes,
        stride: element_size,
        count: count as usize,
        element_size,
        component,
        normalized,
    };
    Ok(Sparse {
        indices: elements(indices, index_size, index_type, false),
        values: elements(values, element_size, component, normalized),
    })
}

/// Where `count` elements of `element_size` bytes lie, `stride` apart from `offset`.
struct Placed {
    count: u64,
    element_size: usize,
    stride: usize,
    offset: u64,
}

impl Placed {
    /// The bytes from the first element on, if the last ends within `view`.
    fn within<'v>(&self, view: &'v [u8]) -> Option<&'v [u8]> {
        let needed = match self.count {
            0 => Some(self.offset),
            n => (self.stride as u64)
                .checked_mul(n - 1)
                .and_then(|s| s.checked_add(self.offset))
                .and_then(|s| s.checked_add(self.element_size as u64)),
        };
        needed
            .filter(|&needed| needed <= view.len() as u64)
            .map(|_| &view[self.offset as usize..])
    }
}

impl std::fmt::Display for Placed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let Placed {
            count,
            element_size,
            stride,
            offset,
        } = self;
        write!(
            f,
            "{count} elements of {element_size} bytes, {stride} apart from offset {offset}"
        )
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
