//! Material variants (`KHR_materials_variants`): one file, several dressings of it (a product
//! in its colours, a room by day and by night). The root lists the variants by name; a
//! primitive's mappings say which material it wears in which variants, and it wears its own
//! `material` in the others and when no variant is asked for.

use serde_json::Value;

use ::gltf::json;

use super::Input;
use crate::SceneError;

const VARIANTS: &str = "KHR_materials_variants";

/// The variants' names, in order; none where the file has no variants. Each must have one.
pub(super) fn names(input: &Input) -> Result<Vec<String>, SceneError> {
    let root = input.root.extensions.as_ref();
    let Some(extension) = root.and_then(|e| e.others.get(VARIANTS)) else {
        return Ok(Vec::new());
    };
    let Some(variants) = extension.get("variants").and_then(Value::as_array) else {
        return Err(input.error(format!("{VARIANTS}: no \"variants\" list")));
    };
    (variants.iter().enumerate())
        .map(
            |(i, variant)| match variant.get("name").and_then(Value::as_str) {
                Some(name) => Ok(name.to_owned()),
                None => Err(input.error(format!("{VARIANTS}: variant {i} has no name"))),
            },
        )
        .collect()
}

/// The index of the variant `choice` names, by index or by name, among `names`.
pub(super) fn chosen(input: &Input, names: &[String], choice: &str) -> Result<usize, SceneError> {
    let names: Vec<Option<&str>> = names.iter().map(|n| Some(n.as_str())).collect();
    super::index_or_name("material variant", choice, &names).map_err(|e| input.error(e))
}

/// The material `primitive` wears in variant `variant`, where one of its mappings names that
/// variant (checked to exist: the caller checks materials as it checks the primitive's own).
pub(super) fn mapped_material(
    input: &Input,
    primitive: &json::mesh::Primitive,
    variant: usize,
    label: &str,
) -> Result<Option<usize>, SceneError> {
    let extension = primitive.extensions.as_ref();
    let Some(extension) = extension.and_then(|e| e.others.get(VARIANTS)) else {
        return Ok(None);
    };
    let mappings = extension.get("mappings").and_then(Value::as_array);
    for (m, mapping) in mappings.into_iter().flatten().enumerate() {
        let material = mapping.get("material").and_then(Value::as_u64);
        let variants = mapping.get("variants").and_then(Value::as_array);
        let (Some(material), Some(variants)) = (material, variants) else {
            return Err(input.error(format!(
                "{label}: {VARIANTS} mapping {m} needs a material and a variants list"
            )));
        };
        if variants.iter().any(|v| v.as_u64() == Some(variant as u64)) {
            return Ok(Some(material as usize));
        }
    }
    Ok(None)
}
