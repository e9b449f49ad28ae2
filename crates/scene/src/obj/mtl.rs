//! MTL libraries: read, cleaned up for `tobj`, parsed.
//!
//! `tobj`'s MTL parser panics on a colour with fewer than three numbers (`Kd 0.5`, which the
//! MTL format allows and means grey) and rejects a whole library over one malformed line. Each
//! line is therefore checked first: a one-number colour is widened to three, a comment after the
//! numbers is dropped, and a line `tobj` could not read is left out with a warning naming it.

use std::path::{Path, PathBuf};

use super::scan::MtlLib;
use crate::SceneBuilder;

/// The largest MTL file read (real ones are kilobytes).
const MAX_MTL_BYTES: u64 = 64 << 20;

/// One material of a library, with the folder its texture paths are relative to.
pub(super) struct LibraryMaterial {
    pub material: tobj::Material,
    pub dir: PathBuf,
}

/// Every `mtllib` statement's result, in file order.
pub(super) struct Libraries {
    /// What `tobj` gets for each statement (it asks once per statement, in order).
    pub per_statement: Vec<tobj::MTLLoadResult>,
    /// The materials as `tobj` will number them: the successful statements' lists, concatenated.
    pub materials: Vec<LibraryMaterial>,
}

impl Libraries {
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.materials.iter().map(|m| m.material.name.as_str())
    }
}

/// Reads the libraries the OBJ names. A missing or unreadable library is a warning: faces that
/// use its materials get the default material.
pub(super) fn load_libraries(
    obj_dir: &Path,
    mtllibs: &[MtlLib],
    builder: &mut SceneBuilder,
) -> Libraries {
    let mut libraries = Libraries {
        per_statement: Vec::new(),
        materials: Vec::new(),
    };
    for statement in mtllibs {
        let result = load_statement(obj_dir, statement, &mut libraries.materials, builder);
        libraries.per_statement.push(result);
    }
    libraries
}

/// One `mtllib` statement: its files' materials appended to `materials` and merged into the
/// one result `tobj` gets for the statement.
fn load_statement(
    obj_dir: &Path,
    statement: &MtlLib,
    materials: &mut Vec<LibraryMaterial>,
    builder: &mut SceneBuilder,
) -> tobj::MTLLoadResult {
    if statement.argument.is_empty() {
        builder.warn(format!(
            "line {}: mtllib without a file name",
            statement.line
        ));
    }
    let mut merged: Option<tobj::MTLLoadResult> = None;
    for file in library_files(obj_dir, &statement.argument) {
        let parsed = read_library(&file, builder).and_then(|r| r.map_err(|e| e.to_string()));
        let (list, names) = match parsed {
            Ok(parsed) => parsed,
            Err(reason) => {
                builder.warn(format!(
                    "line {}: mtllib {}: {reason}; faces using its materials get the default \
                     material",
                    statement.line,
                    file.display()
                ));
                continue;
            }
        };
        let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
        materials.extend(list.iter().map(|material| LibraryMaterial {
            material: material.clone(),
            dir: dir.clone(),
        }));
        match &mut merged {
            Some(Ok((all, all_names))) => {
                // Later names win, as in `tobj`.
                let offset = all.len();
                all_names.extend(names.into_iter().map(|(n, i)| (n, i + offset)));
                all.extend(list);
            }
            _ => merged = Some(Ok((list, names))),
        }
    }
    merged.unwrap_or(Err(tobj::LoadError::OpenFileFailed))
}

/// The files a `mtllib` argument names: the whole argument when such a file exists (names may
/// hold spaces), else each word (the format allows several libraries on one line).
fn library_files(obj_dir: &Path, argument: &str) -> Vec<PathBuf> {
    if argument.is_empty() {
        return Vec::new();
    }
    let whole = resolve(obj_dir, argument);
    if whole.is_file() {
        return vec![whole];
    }
    argument
        .split_whitespace()
        .map(|name| resolve(obj_dir, name))
        .collect()
}

/// A path as written in an OBJ/MTL file, relative to `dir`. Backslashes (Windows exporters)
/// become separators; `.` components are dropped so that one file gets one key.
pub(super) fn resolve(dir: &Path, written: &str) -> PathBuf {
    dir.join(written.replace('\\', "/")).components().collect()
}

/// The parsed library; the error is why it could not be read, in words.
fn read_library(file: &Path, builder: &mut SceneBuilder) -> Result<tobj::MTLLoadResult, String> {
    let bytes = super::read_regular_file(file, MAX_MTL_BYTES).map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&bytes);
    let mut warnings = Vec::new();
    let clean = sanitize(&text, &mut warnings);
    let name = file.display();
    for warning in warnings {
        builder.warn(format!("{name}: {warning}"));
    }
    Ok(tobj::load_mtl_buf(&mut clean.as_bytes()))
}

/// The MTL text with every line `tobj` reads strictly checked (see the module comment).
fn sanitize(text: &str, warnings: &mut Vec<String>) -> String {
    let mut out = String::with_capacity(text.len() + 64);
    for (number, raw) in text.lines().enumerate() {
        let line = raw.trim();
        match sanitize_line(line, number + 1) {
            Ok(clean) => out.push_str(&clean),
            Err(reason) => warnings.push(format!("line {}: {reason}; line ignored", number + 1)),
        }
        out.push('\n');
    }
    out
}

fn sanitize_line(line: &str, number: usize) -> Result<String, String> {
    let mut words = line.split_whitespace();
    let Some(keyword) = words.next() else {
        return Ok(String::new());
    };
    let rest = line[keyword.len()..].trim();
    let values: Vec<&str> = words.take_while(|w| !w.starts_with('#')).collect();
    let is_number = |w: &&str| w.parse::<f32>().is_ok();
    match keyword {
        "newmtl" if rest.is_empty() => Ok(format!("newmtl unnamed (line {number})")),
        "Ka" | "Kd" | "Ks" | "Ke" => match values.as_slice() {
            [v] if is_number(v) => Ok(format!("{keyword} {v} {v} {v}")),
            [r, g, b, ..] if [r, g, b].iter().all(|w| is_number(w)) => {
                Ok(format!("{keyword} {r} {g} {b}"))
            }
            _ => Err(format!("{keyword} '{rest}' is not an RGB colour")),
        },
        "Ns" | "Ni" | "d" => match values.first() {
            Some(v) if is_number(v) => Ok(format!("{keyword} {v}")),
            _ => Err(format!("{keyword} '{rest}' is not a number")),
        },
        "illum" => match values.first().map(|w| w.parse::<u8>()) {
            Some(Ok(model)) => Ok(format!("illum {model}")),
            _ => Err(format!("illum '{rest}' is not a model number")),
        },
        "map_Ka" | "map_Kd" | "map_Ks" | "map_Ns" | "map_ns" | "map_NS" | "map_d" | "map_Bump"
        | "map_bump" | "bump"
            if rest.is_empty() =>
        {
            Err(format!("{keyword} without a file name"))
        }
        _ => Ok(line.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitize_widens_grey_and_drops_comments() {
        let mut warnings = Vec::new();
        let clean = sanitize(
            "newmtl a\nKd 0.5\nKs 1 0 0 # red\nKe spectral x.rfl\nillum 2.5\n",
            &mut warnings,
        );
        assert_eq!(clean, "newmtl a\nKd 0.5 0.5 0.5\nKs 1 0 0\n\n\n");
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(warnings[0].starts_with("line 4: Ke"), "{warnings:?}");
    }

    #[test]
    fn sanitize_names_an_unnamed_material() {
        let mut warnings = Vec::new();
        assert_eq!(
            sanitize("  newmtl  \n", &mut warnings),
            "newmtl unnamed (line 1)\n"
        );
    }

    #[test]
    fn resolve_turns_backslashes_into_separators() {
        let path = resolve(Path::new("/scenes/a"), "textures\\b.png");
        assert_eq!(path, Path::new("/scenes/a/textures/b.png"));
        assert_eq!(resolve(Path::new("x"), "./y.png"), Path::new("x/y.png"));
    }
}
