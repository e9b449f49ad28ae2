//! Reading a Mitsuba element's properties: `<float name=".." value=".."/>` and its kin, with
//! `$name` defaults substituted, names matched across Mitsuba's spellings (0.6's `toWorld`,
//! `intIOR` and 3's `to_world`, `int_ior`), and transforms composed as Mitsuba composes them.

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Vec3};
use roxmltree::Node;

use crate::SceneError;

/// What every reader of the file needs: where it is (for messages and relative paths), its
/// text (for line numbers) and its `<default>` values.
pub(super) struct Context<'a> {
    pub path: &'a Path,
    pub text: &'a str,
    pub defaults: HashMap<String, String>,
}

impl Context<'_> {
    /// A one-line error about `node`, naming its line.
    pub fn error(&self, node: Node, message: impl std::fmt::Display) -> SceneError {
        let line = self.line(node);
        let tag = node.tag_name().name();
        SceneError::format(self.path, format!("line {line}, <{tag}>: {message}"))
    }

    /// The line of the file `node` starts on (from 1).
    pub fn line(&self, node: Node) -> usize {
        self.text[..node.range().start].matches('\n').count() + 1
    }

    /// Attribute `name` of `node` with `$default` references replaced.
    pub fn attribute(&self, node: Node, name: &str) -> Option<String> {
        let raw = node.attribute(name)?;
        if !raw.contains('$') {
            return Some(raw.to_string());
        }
        let mut value = raw.to_string();
        // Longest names first, so that `$spp` does not eat the start of `$spp_max`.
        let mut names: Vec<&String> = self.defaults.keys().collect();
        names.sort_by_key(|n| std::cmp::Reverse(n.len()));
        for name in names {
            value = value.replace(&format!("${name}"), &self.defaults[name]);
        }
        Some(value)
    }

    /// Attribute `name` of `node`, required.
    pub fn required(&self, node: Node, name: &str) -> Result<String, SceneError> {
        self.attribute(node, name)
            .ok_or_else(|| self.error(node, format!("has no \"{name}\" attribute")))
    }

    /// The finite numbers of attribute `name` (separated by spaces or commas).
    pub fn numbers(&self, node: Node, name: &str) -> Result<Vec<f32>, SceneError> {
        let text = self.required(node, name)?;
        parse_numbers(&text).map_err(|e| self.error(node, format!("{name}=\"{text}\": {e}")))
    }

    /// One finite number.
    pub fn number(&self, node: Node, name: &str) -> Result<f32, SceneError> {
        match self.numbers(node, name)?[..] {
            [x] => Ok(x),
            _ => Err(self.error(node, format!("{name} must be one number"))),
        }
    }

    /// A point or vector: `x`, `y`, `z` attributes (missing ones 0) or `value="x y z"`.
    pub fn vector(&self, node: Node) -> Result<Vec3, SceneError> {
        if node.attribute("value").is_some() {
            return match self.numbers(node, "value")?[..] {
                [x, y, z] => Ok(Vec3::new(x, y, z)),
                [v] => Ok(Vec3::splat(v)),
                _ => Err(self.error(node, "value must hold three numbers")),
            };
        }
        self.axes(node, 0.0)
    }

    /// `x`, `y`, `z` attributes, `missing` where absent.
    fn axes(&self, node: Node, missing: f32) -> Result<Vec3, SceneError> {
        let mut v = Vec3::splat(missing);
        for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
            if node.attribute(axis).is_some() {
                v[i] = self.number(node, axis)?;
            }
        }
        Ok(v)
    }

    /// A colour from `<rgb>` (three numbers, one, or `#rrggbb`), `<spectrum>` (a uniform
    /// value, or wavelength:value pairs averaged, with a warning) or `<float>`.
    pub fn colour(&self, node: Node, warnings: &mut Vec<String>) -> Result<Vec3, SceneError> {
        let text = self.required(node, "value")?;
        if let Some(hex) = text.trim().strip_prefix('#') {
            let channel = |i: usize| {
                hex.get(i..i + 2)
                    .and_then(|h| u8::from_str_radix(h, 16).ok())
            };
            let linear = crate::textures::srgb_to_linear;
            return match (hex.len(), channel(0), channel(2), channel(4)) {
                (6, Some(r), Some(g), Some(b)) => Ok(Vec3::new(linear(r), linear(g), linear(b))),
                _ => Err(self.error(node, format!("\"{text}\" is not a #rrggbb colour"))),
            };
        }
        if node.tag_name().name() == "spectrum" && text.contains(':') {
            let values: Result<Vec<f32>, String> = text
                .split(',')
                .map(|pair| match pair.split_once(':') {
                    Some((_, value)) => parse_number(value.trim()),
                    None => Err(format!("\"{pair}\" is not wavelength:value")),
                })
                .collect();
            let values = values.map_err(|e| self.error(node, e))?;
            if values.is_empty() {
                return Err(self.error(node, "an empty spectrum"));
            }
            warnings.push(format!(
                "a spectrum given by wavelengths (line {}) is read as its mean value",
                self.line(node)
            ));
            return Ok(Vec3::splat(
                values.iter().sum::<f32>() / values.len() as f32,
            ));
        }
        match self.numbers(node, "value")?[..] {
            [v] => Ok(Vec3::splat(v)),
            [r, g, b] => Ok(Vec3::new(r, g, b)),
            _ => Err(self.error(node, "a colour needs one or three numbers")),
        }
    }

    /// A `<transform>` element: its operations applied in the order written (each one's matrix
    /// multiplied on the left, as Mitsuba does).
    pub fn transform(&self, node: Node) -> Result<Mat4, SceneError> {
        let mut matrix = Mat4::IDENTITY;
        for op in node.children().filter(Node::is_element) {
            let step = match op.tag_name().name() {
                "translate" => Mat4::from_translation(self.vector(op)?),
                "scale" => {
                    let s = match op.attribute("value") {
                        Some(_) => self.vector(op)?,
                        None => self.axes(op, 1.0)?,
                    };
                    Mat4::from_scale(s)
                }
                "rotate" => {
                    let axis = match op.attribute("value") {
                        Some(_) => self.vector(op)?,
                        None => self.axes(op, 0.0)?,
                    };
                    let axis = axis
                        .try_normalize()
                        .ok_or_else(|| self.error(op, "the rotation axis is zero"))?;
                    Mat4::from_axis_angle(axis, self.number(op, "angle")?.to_radians())
                }
                "matrix" => {
                    let values = self.numbers(op, "value")?;
                    match values.len() {
                        16 => Mat4::from_cols_slice(&values).transpose(),
                        9 => {
                            let m = glam::Mat3::from_cols_slice(&values).transpose();
                            Mat4::from_mat3(m)
                        }
                        n => return Err(self.error(op, format!("16 or 9 numbers, not {n}"))),
                    }
                }
                "lookat" => self.look_at(op)?,
                other => return Err(self.error(op, format!("unknown transform step <{other}>"))),
            };
            matrix = step * matrix;
        }
        if !matrix.is_finite() {
            return Err(self.error(node, "the transform is not finite"));
        }
        Ok(matrix)
    }

    /// Mitsuba's `lookat`: the frame's +Z towards `target`, +Y towards `up`, +X to the left
    /// (up × direction), placed at `origin`.
    fn look_at(&self, node: Node) -> Result<Mat4, SceneError> {
        let point = |name: &str| -> Result<Vec3, SceneError> {
            match self.numbers(node, name)?[..] {
                [x, y, z] => Ok(Vec3::new(x, y, z)),
                _ => Err(self.error(node, format!("{name} needs three numbers"))),
            }
        };
        let origin = point("origin")?;
        let target = point("target")?;
        let up = if node.attribute("up").is_some() {
            point("up")?
        } else {
            Vec3::Y
        };
        let direction = (target - origin)
            .try_normalize()
            .ok_or_else(|| self.error(node, "origin and target are the same point"))?;
        let left = up
            .cross(direction)
            .try_normalize()
            .ok_or_else(|| self.error(node, "up is parallel to the view direction"))?;
        let new_up = direction.cross(left);
        Ok(Mat4::from_cols(
            left.extend(0.0),
            new_up.extend(0.0),
            direction.extend(0.0),
            origin.extend(1.0),
        ))
    }
}

/// A property's name as compared: lower case without underscores, so that Mitsuba 0.6's
/// `toWorld` and `intIOR` match 3's `to_world` and `int_ior`.
pub(super) fn normalised(name: &str) -> String {
    name.chars()
        .filter(|&c| c != '_')
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// The child element of `node` holding property `name` (any spelling), if any.
pub(super) fn property<'a, 'input>(node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
    let wanted = normalised(name);
    node.children()
        .filter(Node::is_element)
        .find(|c| c.attribute("name").is_some_and(|n| normalised(n) == wanted))
}

fn parse_number(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("{text} is not finite")),
        Err(_) => Err(format!("\"{text}\" is not a number")),
    }
}

fn parse_numbers(text: &str) -> Result<Vec<f32>, String> {
    let numbers: Result<Vec<f32>, String> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(parse_number)
        .collect();
    match numbers? {
        n if n.is_empty() => Err("no numbers".into()),
        n => Ok(n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with_document<T>(xml: &str, f: impl FnOnce(&Context, Node) -> T) -> T {
        let document = roxmltree::Document::parse(xml).expect("XML");
        let context = Context {
            path: Path::new("test.xml"),
            text: xml,
            defaults: HashMap::from([("s".to_string(), "2".to_string())]),
        };
        f(&context, document.root_element())
    }

    #[test]
    fn transforms_compose_in_the_order_written() {
        let xml = r#"<transform name="to_world">
            <scale value="$s"/><rotate y="1" angle="90"/><translate x="1" y="2" z="3"/>
        </transform>"#;
        let m = with_document(xml, |c, n| c.transform(n)).expect("a transform");
        // (1, 0, 0) scaled to (2, 0, 0), turned about +y to (0, 0, −2), moved by (1, 2, 3).
        let p = m.transform_point3(Vec3::X);
        assert!(p.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5), "{p}");
    }

    #[test]
    fn a_lookat_frame_puts_z_forward_and_x_left() {
        let xml = r#"<transform name="to_world">
            <lookat origin="0, 0, 5" target="0 0 0" up="0 1 0"/>
        </transform>"#;
        let m = with_document(xml, |c, n| c.transform(n)).expect("a transform");
        assert!(m.transform_vector3(Vec3::Z).abs_diff_eq(Vec3::NEG_Z, 1e-6));
        assert!(m.transform_vector3(Vec3::X).abs_diff_eq(Vec3::NEG_X, 1e-6));
        assert!(
            m.transform_point3(Vec3::ZERO)
                .abs_diff_eq(Vec3::new(0.0, 0.0, 5.0), 1e-6)
        );
    }

    #[test]
    fn matrices_are_written_row_by_row() {
        let xml = r#"<transform name="to_world">
            <matrix value="1 0 0 4  0 1 0 5  0 0 1 6  0 0 0 1"/>
        </transform>"#;
        let m = with_document(xml, |c, n| c.transform(n)).expect("a transform");
        assert_eq!(m.transform_point3(Vec3::ZERO), Vec3::new(4.0, 5.0, 6.0));
    }

    #[test]
    fn colours_read_every_spelling() {
        let mut warnings = Vec::new();
        let cases = [
            (
                r#"<rgb name="r" value="0.1, 0.2, 0.3"/>"#,
                Vec3::new(0.1, 0.2, 0.3),
            ),
            (r#"<rgb name="r" value="0.5"/>"#, Vec3::splat(0.5)),
            (r#"<spectrum name="r" value="0.25"/>"#, Vec3::splat(0.25)),
            (
                r#"<spectrum name="r" value="400:0.2, 700:0.4"/>"#,
                Vec3::splat(0.3),
            ),
            (r##"<rgb name="r" value="#ff0000"/>"##, Vec3::X),
        ];
        for (xml, expected) in cases {
            let colour = with_document(xml, |c, n| c.colour(n, &mut warnings)).expect(xml);
            assert!(colour.abs_diff_eq(expected, 1e-6), "{xml}: {colour}");
        }
        assert_eq!(warnings.len(), 1, "{warnings:?}");
    }

    #[test]
    fn bad_numbers_name_their_line() {
        let xml = "<transform name=\"to_world\">\n<translate value=\"1 nan 2\"/></transform>";
        let error = with_document(xml, |c, n| c.transform(n)).expect_err("NaN refused");
        let message = error.to_string();
        assert!(
            message.contains("line 2") && message.contains("not finite"),
            "{message}"
        );
    }

    #[test]
    fn names_match_across_mitsuba_versions() {
        assert_eq!(normalised("toWorld"), normalised("to_world"));
        assert_eq!(normalised("intIOR"), normalised("int_ior"));
    }
}
