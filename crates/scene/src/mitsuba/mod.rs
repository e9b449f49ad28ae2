//! Mitsuba scene files (`.xml`, Mitsuba 3's format and 0.6's), so that a scene set up for
//! Mitsuba renders in kousen as it is, and the two renderers can be compared on it.
//!
//! # What is read
//! - `<default name value>` and `$name` references in any attribute; property names in either
//!   version's spelling (`toWorld` or `to_world`, `intIOR` or `int_ior`); `id`s of top-level
//!   `<bsdf>` and `<texture>` elements, used through `<ref id>`.
//! - **Shapes**: `obj` (through kousen's OBJ loader, its own materials replaced),
//!   `ply` (ASCII and binary: positions, normals, texture coordinates, polygons),
//!   `serialized` (Mitsuba's own compressed meshes, by `shape_index`; smooth normals where a
//!   PLY or serialized mesh has none, as Mitsuba makes them), and `instance`s of a
//!   `shapegroup` (each a copy of its shapes, placed by the instance's `to_world`),
//!   `rectangle`, `cube`, `disk`, `sphere` (`center`, `radius`; 128 × 64 facets with smooth
//!   normals) and `cylinder` (`p0`, `p1`, `radius`: an open tube, 128 facets round), each with `to_world`, `flip_normals` and `face_normals`, its BSDF (inline or
//!   by reference; Mitsuba's default, diffuse 0.5, where none) and an `area` emitter's
//!   `radiance` (emitted from the front face, as Mitsuba's).
//! - **BSDFs** onto kousen's materials (a base colour `bitmap`'s `to_uv` applied to the
//!   texture coordinates of the shapes wearing it): `diffuse` (reflectance colour or `bitmap`) →
//!   Lambertian; `dielectric`, `thindielectric`, `roughdielectric` (`int_ior` / `ext_ior`,
//!   numbers or Mitsuba's named indices; `alpha`) → glass, smooth or frosted (GGX of width
//!   `alpha`), tinted by `specular_transmittance`; `conductor`, `roughconductor` → metal
//!   reflecting its reflectance at normal incidence (from `eta` and `k`, or its `material`
//!   among Ag, Al, Au, Cr, Cu, Ni; "none" a perfect mirror) × `specular_reflectance` at every
//!   angle; `plastic`, `roughplastic` → plastic (Lambertian `diffuse_reflectance` under a coat
//!   of `int_ior`); Mitsuba 3's `principled` → glTF's metallic-roughness material (metal of
//!   share `metallic`, glass of `spec_trans` of the rest, plastic, of its `roughness`: a blend
//!   where more than one has a share);
//!   `twosided` → the BSDF inside it (kousen's surfaces reflect on both faces); `null` →
//!   invisible (cut out). Rough BSDFs are GGX whatever `distribution` says, and as with glTF
//!   materials a metal or plastic coat of `alpha` ≥ 0.25 is rendered Lambertian. `mask` with
//!   a bitmap `opacity` cuts the BSDF inside it out where the opacity is below ½ (leaves,
//!   fences: kousen's alpha cut-outs). `blendbsdf` → a blend of its two BSDFs, the second
//!   drawn with probability `weight` (`SceneBuilder::add_mixture`: Lambertian-lobed members
//!   read as one of their mean colour, with a warning). `bumpmap` and `normalmap` are read as
//!   the BSDF inside them, with a warning.
//! - **Emitters**: `point` (`position` or `to_world`, `intensity`), `spot` (`intensity`,
//!   `cutoff_angle`, `beam_width`, along `to_world`'s +Z; Mitsuba's falloff, linear in the angle between the cones),
//!   `directional` (`irradiance`, `direction` or `to_world`'s +Z), `constant` (a uniform sky
//!   of `radiance`), `envmap` (`filename`: `.hdr`, `.exr` or 8-bit sRGB; `scale`; turned about
//!   +Y as Mitsuba turns it, `to_world`'s turn about +Y included).
//! - **Sensors**: `perspective` and `thinlens` (`aperture_radius`, `focus_distance`), with
//!   `to_world`, `fov` along `fov_axis` (x, y, diagonal, smaller, larger) or `focal_length`
//!   (35 mm film), and the `hdrfilm`'s `width` and `height` as the aspect ratio.
//! - **Media** (`media`): a shape's `homogeneous` interior medium (`sigma_t` × `scale` and
//!   `albedo`, or 0.6's `sigmaA` and `sigmaS`; an `hg` phase's `g`), inline or by reference,
//!   fills it (`crate::media`): a solid `dielectric` keeps its surface, a `null` BSDF becomes
//!   glass of index 1.
//! - Ignored: `integrator`, `sampler`, `rfilter` and the film's other settings (kousen renders
//!   by its own settings). Skipped with a warning: other shapes (curves),
//!   emitters, sensors, exterior media, other media, media no shape is filled with, and
//!   `include`.
//!
//! Spectra are read in RGB (a `<spectrum>` of wavelength:value pairs as its mean, with a
//! warning). Errors are one line naming the element's line in the file.

mod bsdfs;
mod media;
mod properties;
mod serialized;
mod shapes;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use roxmltree::Node;

use crate::files::read_regular_file;
use crate::{
    Camera, Lens, PunctualKind, PunctualLight, Scene, SceneBuilder, SceneError, SpotFalloff,
    TextureId,
};
use properties::{Context, normalised, property};

/// The largest XML file read (a scene description; meshes live in their own files).
const MAX_XML_BYTES: u64 = 256 << 20;

/// Mitsuba's film size where a sensor gives none.
const DEFAULT_FILM: (f32, f32) = (768.0, 576.0);

/// Loads a Mitsuba scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let (bytes, length) =
        read_regular_file(path, MAX_XML_BYTES).map_err(|e| SceneError::io(path, e))?;
    if length > MAX_XML_BYTES {
        let message = format!("{length} bytes: more than a scene file of {MAX_XML_BYTES}");
        return Err(SceneError::format(path, message));
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| SceneError::format(path, "not a UTF-8 text file (a Mitsuba scene is XML)"))?;
    let document = roxmltree::Document::parse(&text)
        .map_err(|e| SceneError::format(path, format!("not well-formed XML: {e}")))?;
    let root = document.root_element();
    if !root.has_tag_name("scene") {
        let tag = root.tag_name().name();
        return Err(SceneError::format(
            path,
            format!("the root element is <{tag}>, not <scene>"),
        ));
    }
    let mut context = Context {
        path,
        text: &text,
        defaults: HashMap::new(),
    };
    for default in root.children().filter(|c| c.has_tag_name("default")) {
        let name = context.required(default, "name")?;
        let value = context.required(default, "value")?;
        context.defaults.insert(name, value);
    }
    let mut reader = Reader::new(context, root);
    for child in root.children().filter(Node::is_element) {
        reader.element(child)?;
    }
    reader.place_outside_media()?;
    let mut unused: Vec<Node> = (reader.media.iter())
        .filter(|(id, _)| !reader.media_used.contains(*id))
        .map(|(_, node)| *node)
        .collect();
    unused.sort_by_key(|node| node.range().start);
    for medium in unused {
        reader.warn(medium, "a medium no solid is filled with is not read");
    }
    let Reader {
        mut builder,
        mut warnings,
        sky,
        sky_map,
        ..
    } = reader;
    if sky.is_some() && sky_map.is_some() {
        warnings.push("a constant emitter beside an envmap: kousen has one sky, the envmap".into());
    }
    for warning in warnings {
        builder.warn(warning);
    }
    let mut scene = builder.finish()?;
    let bounds = scene.bounds();
    match (sky_map, sky) {
        (Some((map, scale, rotation)), _) => {
            let map = std::sync::Arc::new(map);
            let sky = crate::Sky::with_map(map, Vec3::splat(scale), rotation, bounds);
            scene.lights.replace_sky(sky);
        }
        (None, Some(radiance)) => scene.lights.set_sky(radiance, bounds),
        (None, None) => {}
    }
    scene.dim_far_lights(path);
    Ok(scene)
}

/// The scene being read and what it has read so far.
pub(super) struct Reader<'a> {
    context: Context<'a>,
    builder: SceneBuilder,
    /// Top-level BSDFs and textures by `id`, and every top-level `id` (media among them).
    bsdfs: HashMap<String, Node<'a, 'a>>,
    /// Top-level `shapegroup` shapes by `id`, which `instance` shapes place.
    groups: HashMap<String, Node<'a, 'a>>,
    /// Top-level media by `id`, and those a shape has filled itself with.
    media: HashMap<String, Node<'a, 'a>>,
    media_used: std::collections::HashSet<String>,
    /// The media shapes are filled with, by `id` (`media`).
    media_filled: std::collections::HashSet<String>,
    /// Media named around shapes (`exterior`) and lights: (the naming element, the medium).
    media_around: Vec<(Node<'a, 'a>, Node<'a, 'a>)>,
    /// The sensor's medium, if it names one.
    sensor_medium: Option<Node<'a, 'a>>,
    ids: std::collections::HashSet<String>,
    textures: HashMap<String, Node<'a, 'a>>,
    /// Images decoded so far, by file and colour (sRGB) or data.
    bitmaps: HashMap<(PathBuf, bool), TextureId>,
    /// Builder ids of the materials of BSDFs referred to by `id` (shapes without emitters),
    /// with their base colour bitmap's `to_uv`.
    materials: HashMap<String, (u32, Option<Mat4>)>,
    warnings: Vec<String>,
    /// A `constant` emitter's radiance.
    sky: Option<Vec3>,
    /// An `envmap` emitter's map, scale and turn about +Y in kousen's convention.
    sky_map: Option<(crate::SkyMap, f32, f32)>,
}

impl<'a> Reader<'a> {
    fn new(context: Context<'a>, root: Node<'a, 'a>) -> Reader<'a> {
        let mut bsdfs = HashMap::new();
        let mut textures = HashMap::new();
        let mut groups = HashMap::new();
        let mut media = HashMap::new();
        let mut ids = std::collections::HashSet::new();
        for child in root.children().filter(Node::is_element) {
            let Some(id) = child.attribute("id") else {
                continue;
            };
            ids.insert(id.to_string());
            match child.tag_name().name() {
                "bsdf" => bsdfs.insert(id.to_string(), child),
                "shape" if child.attribute("type") == Some("shapegroup") => {
                    groups.insert(id.to_string(), child)
                }
                "texture" => textures.insert(id.to_string(), child),
                "medium" => media.insert(id.to_string(), child),
                _ => None,
            };
        }
        Reader {
            builder: SceneBuilder::new(context.path),
            context,
            bsdfs,
            groups,
            media,
            media_used: std::collections::HashSet::new(),
            media_filled: std::collections::HashSet::new(),
            media_around: Vec::new(),
            sensor_medium: None,
            ids,
            textures,
            bitmaps: HashMap::new(),
            materials: HashMap::new(),
            warnings: Vec::new(),
            sky: None,
            sky_map: None,
        }
    }

    fn element(&mut self, node: Node<'a, 'a>) -> Result<(), SceneError> {
        match node.tag_name().name() {
            "shape" => self.shape(node),
            "emitter" => self.emitter(node),
            "sensor" => self.sensor(node),
            // Read where used, or kousen's own settings.
            "default" | "bsdf" | "texture" | "integrator" | "sampler" | "rfilter" | "film" => {
                Ok(())
            }
            "medium" if node.attribute("id").is_some() => Ok(()),
            other => {
                self.warn(node, format!("<{other}> is not read"));
                Ok(())
            }
        }
    }

    /// A warning naming `node`'s line.
    fn warn(&mut self, node: Node, message: impl std::fmt::Display) {
        let line = self.context.line(node);
        self.warnings.push(format!("line {line}: {message}"));
    }

    /// The element a `<ref id>` names among the top-level ones of `kind` ("bsdf", "texture",
    /// "shapegroup").
    fn referenced(&self, node: Node<'a, 'a>, kind: &str) -> Result<Node<'a, 'a>, SceneError> {
        let id = self.context.required(node, "id")?;
        let table = match kind {
            "bsdf" => &self.bsdfs,
            "shapegroup" => &self.groups,
            "medium" => &self.media,
            _ => &self.textures,
        };
        table.get(&id).copied().ok_or_else(|| {
            self.context
                .error(node, format!("no {kind} has id \"{id}\""))
        })
    }

    /// `node` itself if it is a `<bsdf>`, else the BSDF its `<ref>` names.
    fn resolve_bsdf(&self, node: Node<'a, 'a>) -> Result<Node<'a, 'a>, SceneError> {
        match node.has_tag_name("ref") {
            true => self.referenced(node, "bsdf"),
            false => Ok(node),
        }
    }

    /// A file the scene names, relative to the scene file's folder.
    fn file(&self, name: &str) -> PathBuf {
        let dir = self.context.path.parent().unwrap_or(Path::new(""));
        dir.join(name.replace('\\', "/"))
    }

    /// Image `file` (relative to the scene file) decoded as sRGB colour or linear data.
    fn decode(&self, node: Node, file: &str, srgb: bool) -> Result<crate::Texture, SceneError> {
        let path = self.file(file);
        crate::Texture::read_file(&path, file, srgb, |e| self.context.error(node, e))
    }

    /// The texture of image `file`, decoded once (sRGB colour or linear data).
    fn bitmap(&mut self, node: Node, file: &str, srgb: bool) -> Result<TextureId, SceneError> {
        let path = self.file(file);
        if let Some(id) = self.bitmaps.get(&(path.clone(), srgb)) {
            return Ok(*id);
        }
        let texture = self.decode(node, file, srgb)?;
        let id = self.builder.add_texture(texture);
        self.bitmaps.insert((path, srgb), id);
        Ok(id)
    }

    /// A boolean property, `default` where absent.
    fn boolean(&self, node: Node, name: &str, default: bool) -> Result<bool, SceneError> {
        let Some(p) = property(node, name) else {
            return Ok(default);
        };
        match self.context.required(p, "value")?.as_str() {
            "true" => Ok(true),
            "false" => Ok(false),
            other => Err(self
                .context
                .error(p, format!("\"{other}\" is not true or false"))),
        }
    }

    /// A string property, if given.
    fn string(&self, node: Node, name: &str) -> Result<Option<String>, SceneError> {
        property(node, name)
            .map(|p| self.context.required(p, "value"))
            .transpose()
    }

    /// A point or vector property, if given.
    fn vector(&self, node: Node, name: &str) -> Result<Option<Vec3>, SceneError> {
        property(node, name)
            .map(|p| self.context.vector(p))
            .transpose()
    }

    /// `to_world` (identity where absent).
    fn to_world(&self, node: Node) -> Result<Mat4, SceneError> {
        match property(node, "to_world") {
            Some(t) if t.has_tag_name("transform") => self.context.transform(t),
            Some(t) => Err(self.context.error(t, "to_world must be a <transform>")),
            None => Ok(Mat4::IDENTITY),
        }
    }

    fn emitter(&mut self, node: Node<'a, 'a>) -> Result<(), SceneError> {
        let kind = self.context.required(node, "type")?;
        if let Some(named) = self.endpoint_medium(node)? {
            self.media_around.push(named);
        }
        let to_world = self.to_world(node)?;
        let position = match self.vector(node, "position")? {
            Some(p) => p,
            None => to_world.transform_point3(Vec3::ZERO),
        };
        let along_z = to_world.transform_vector3(Vec3::Z).try_normalize();
        let light = |kind, direction: Option<Vec3>, intensity| PunctualLight {
            kind,
            position,
            direction: direction.unwrap_or(Vec3::NEG_Y),
            intensity,
        };
        let light = match kind.as_str() {
            "point" => light(
                PunctualKind::Point,
                None,
                self.colour(node, "intensity", Vec3::ONE)?,
            ),
            "spot" => {
                let cutoff = self.float(node, "cutoff_angle", 20.0)?;
                if !(cutoff > 0.0 && cutoff <= 90.0) {
                    let message = format!("cutoff_angle {cutoff}° is not in (0°, 90°]");
                    return Err(self.context.error(node, message));
                }
                // A hard-edged spot (beam as wide as the cutoff) keeps a ramp a thousandth
                // of its angle wide: kousen's cones must differ.
                let beam = self.float(node, "beam_width", cutoff * 0.75)?;
                let beam = beam.clamp(0.0, cutoff * 0.999);
                let (cos_inner, cos_outer) = (beam.to_radians().cos(), cutoff.to_radians().cos());
                let intensity = self.colour(node, "intensity", Vec3::ONE)?;
                let direction = along_z
                    .ok_or_else(|| self.context.error(node, "to_world leaves no direction"))?;
                light(
                    PunctualKind::Spot {
                        cos_inner,
                        cos_outer,
                        falloff: SpotFalloff::LinearAngle,
                    },
                    Some(direction),
                    intensity,
                )
            }
            "directional" => {
                let direction = match self.vector(node, "direction")? {
                    Some(d) => d.try_normalize(),
                    None => along_z,
                };
                let direction = direction.ok_or_else(|| {
                    self.context
                        .error(node, "a directional emitter needs a direction")
                })?;
                let irradiance = self.colour(node, "irradiance", Vec3::ONE)?;
                light(PunctualKind::Directional, Some(direction), irradiance)
            }
            "constant" => {
                let radiance = self.colour(node, "radiance", Vec3::ONE)?;
                self.sky = Some(self.sky.unwrap_or(Vec3::ZERO) + radiance);
                return Ok(());
            }
            "envmap" => return self.envmap(node, to_world),
            other => {
                let hint = match other {
                    "area" => ": an area emitter belongs inside the shape it lights",
                    _ => "",
                };
                self.warn(node, format!("emitter \"{other}\" is not read{hint}"));
                return Ok(());
            }
        };
        self.builder.add_punctual_light(light).map_err(|e| match e {
            SceneError::Format { message, .. } => self.context.error(node, message),
            e => e,
        })
    }

    /// An `envmap`: its equirectangular image (`.hdr`, `.exr`, or 8-bit sRGB) × `scale`.
    /// Mitsuba's map faces its centre column along +Z and its quarter column along +X
    /// (checked against Mitsuba's own `eval`); kousen's faces −Z and +X at three quarters,
    /// so the map is turned half a turn about +Y, plus the turn of its `to_world` about +Y
    /// (a tilt is not kept: warned).
    fn envmap(&mut self, node: Node<'a, 'a>, to_world: Mat4) -> Result<(), SceneError> {
        let file = (self.string(node, "filename")?)
            .ok_or_else(|| self.context.error(node, "an envmap needs a filename"))?;
        let scale = self.float(node, "scale", 1.0)?;
        if scale < 0.0 {
            return Err(self
                .context
                .error(node, format!("scale {scale} is negative")));
        }
        let image = self.decode(node, &file, true)?;
        let texels = (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .map(|(x, y)| image.texel_linear(x, y).truncate())
            .collect();
        let map = crate::SkyMap::new(image.width, image.height, texels)
            .map_err(|e| self.context.error(node, e))?;
        let up = to_world.transform_vector3(Vec3::Y).normalize_or_zero();
        if up.dot(Vec3::Y) < 0.9999 {
            self.warn(
                node,
                "the envmap's to_world tilts it; kousen turns it about +Y only",
            );
        }
        let centre = to_world.transform_vector3(Vec3::Z);
        let turn = centre.x.atan2(centre.z);
        self.sky_map = Some((map, scale, turn + std::f32::consts::PI));
        Ok(())
    }

    fn sensor(&mut self, node: Node<'a, 'a>) -> Result<(), SceneError> {
        let kind = self.context.required(node, "type")?;
        if kind != "perspective" && kind != "thinlens" {
            self.warn(node, format!("sensor \"{kind}\" is not read"));
            return Ok(());
        }
        if let Some((naming, medium)) = self.endpoint_medium(node)? {
            match self.sensor_medium {
                None => self.sensor_medium = Some(medium),
                // Another sensor's: checked as a light's is.
                Some(_) => self.media_around.push((naming, medium)),
            }
        }
        let film = node.children().find(|c| c.has_tag_name("film"));
        let (width, height) = match film {
            Some(film) => (
                self.float(film, "width", DEFAULT_FILM.0)?,
                self.float(film, "height", DEFAULT_FILM.1)?,
            ),
            None => DEFAULT_FILM,
        };
        if !(width >= 1.0 && height >= 1.0) {
            return Err(self
                .context
                .error(node, "the film's width and height must be at least 1"));
        }
        let aspect = width / height;
        let yfov = self.vertical_fov(node, aspect)?;
        let to_world = self.to_world(node)?;
        if to_world.determinant() < 0.0 {
            self.warn(
                node,
                "the sensor's to_world mirrors the image; kousen renders it unmirrored",
            );
        }
        let eye = to_world.transform_point3(Vec3::ZERO);
        let forward = to_world.transform_vector3(Vec3::Z);
        let up = to_world.transform_vector3(Vec3::Y);
        let mut camera = Camera::look_at(eye, eye + forward, up, yfov)
            .ok_or_else(|| {
                self.context.error(
                    node,
                    "the sensor's to_world or field of view leaves no camera",
                )
            })?
            .named(node.attribute("id").unwrap_or("sensor"));
        camera.aspect_ratio = Some(aspect);
        if kind == "thinlens" {
            let radius = self.float(node, "aperture_radius", 0.0)?;
            let focus = self.float(node, "focus_distance", 0.0)?;
            let lens = Lens::new(radius, focus).ok_or_else(|| {
                self.context
                    .error(node, "aperture_radius and focus_distance must be positive")
            })?;
            camera = camera.with_lens(lens);
        }
        self.builder.add_camera(camera);
        Ok(())
    }

    /// The vertical field of view (radians) of a sensor's `fov` along its `fov_axis`, or of
    /// its `focal_length` on 35 mm film (36 × 24 mm, along x), on a film of `aspect`.
    fn vertical_fov(&mut self, node: Node<'a, 'a>, aspect: f32) -> Result<f32, SceneError> {
        let half_tan = |degrees: f32| (degrees.to_radians() / 2.0).tan();
        let tan_y = match property(node, "fov") {
            Some(_) => {
                let fov = self.float(node, "fov", 0.0)?;
                if !(fov > 0.0 && fov < 180.0) {
                    return Err(self
                        .context
                        .error(node, format!("fov {fov}° is not in (0°, 180°)")));
                }
                let t = half_tan(fov);
                let diagonal = (aspect * aspect + 1.0).sqrt();
                let axis = self.string(node, "fov_axis")?.unwrap_or_else(|| "x".into());
                // The height is the smaller side where aspect ≥ 1.
                match normalised(&axis).as_str() {
                    "x" => t / aspect,
                    "y" => t,
                    "diagonal" => t / diagonal,
                    "smaller" if aspect >= 1.0 => t,
                    "smaller" => t / aspect,
                    "larger" if aspect >= 1.0 => t / aspect,
                    "larger" => t,
                    other => {
                        return Err(self
                            .context
                            .error(node, format!("unknown fov_axis \"{other}\"")));
                    }
                }
            }
            None => {
                let focal = self
                    .string(node, "focal_length")?
                    .unwrap_or_else(|| "50mm".into());
                let millimetres = focal.trim().trim_end_matches("mm").trim().parse::<f32>();
                let millimetres = millimetres
                    .ok()
                    .filter(|f| f.is_finite() && *f > 0.0)
                    .ok_or_else(|| {
                        self.context
                            .error(node, format!("focal_length \"{focal}\""))
                    })?;
                // Half of 35 mm film's 36 mm width over the focal length.
                18.0 / millimetres / aspect
            }
        };
        Ok(2.0 * tan_y.atan())
    }
}
