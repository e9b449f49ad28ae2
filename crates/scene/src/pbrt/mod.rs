//! pbrt scene files (`.pbrt`, pbrt-v4's format and pbrt-v3's spellings), so that the many
//! scenes set up for pbrt render in kousen as they are, and the two renderers can be compared.
//!
//! # What is read
//! - **Transforms**: `Identity`, `Translate`, `Scale`, `Rotate`, `LookAt`, `Transform`,
//!   `ConcatTransform`, `CoordinateSystem`, `CoordSysTransform` (`"camera"` among the names),
//!   `TransformBegin`/`TransformEnd`, `ReverseOrientation`, `AttributeBegin`/`AttributeEnd`
//!   (pbrt-v3's `WorldEnd` too). Motion (`ActiveTransform EndTime`) keeps the start.
//! - **Camera**: `perspective` (`fov` across the image's shorter side, `lensradius`,
//!   `focaldistance`, `frameaspectratio`) and `orthographic`, placed by the transform at
//!   `Camera`; the `Film`'s `xresolution` and `yresolution` as the aspect ratio.
//! - **Shapes** (`shapes`): `trianglemesh`, `plymesh` (PLY, gzipped too), `bilinearmesh`,
//!   `loopsubdiv` (Loop-subdivided `levels` times, at its limit positions: `subdivision`),
//!   `sphere`, `disk`, `cylinder` (tessellated), with the current material, area light and
//!   `alpha` (a float image: a cut-out; 0: the shape and its light left out).
//! - **Materials** (`materials`): pbrt-v4's `diffuse`, `coateddiffuse`, `coatedconductor`,
//!   `conductor`, `dielectric`, `thindielectric`, `diffusetransmission`, `mix`, `interface`,
//!   pbrt-v3's `matte`, `plastic`, `metal`, `mirror`, `glass`, `uber`, `substrate`,
//!   `translucent`, `disney`, `mix`; `MakeNamedMaterial`/`NamedMaterial` (a shape may name a
//!   material defined later in the file, as pbrt-v4 allows); float and spectrum `Texture`s
//!   (each their own names) `imagemap`, `constant`, `scale`, `checkerboard` and `mix` (means).
//! - **Lights** (`lights`): `AreaLightSource "diffuse"`, `LightSource` `point`, `spot`,
//!   `distant`, `infinite` (a colour or an image: pbrt-v4's equal-area square or pbrt-v3's
//!   latitude–longitude map), with `scale`, `power` or `illuminance` as pbrt reads them.
//! - `Include` and `Import` (read in place; gzipped files too; an Import's state changes stay
//!   in it), `ObjectBegin`/`ObjectEnd`/`ObjectInstance`.
//! - **Media**: a `homogeneous` `MakeNamedMedium` (`sigma_a`, `sigma_s`, `scale`, `g`) that
//!   `MediumInterface` puts inside the shapes after it fills them (`crate::media`): solid
//!   glass keeps its surface, an `interface` becomes glass of index 1 (`materials`). The
//!   camera's medium (the outside one where `Camera` is declared), where no shape is filled
//!   with it, fills all space outside the solids: the scene's atmosphere. Media outside
//!   shapes are found from the geometry (the solid around them).
//! - Ignored: `Sampler`, `Integrator`, `PixelFilter`, `Accelerator`, `Option` (kousen renders
//!   by its own settings). Warned about: other media (grids, clouds, presets), media that
//!   fill no shape and are not the camera's, other shapes, materials, textures and lights,
//!   the film's ISO (with the `--exposure` that shows pbrt's image) and every parameter
//!   nothing read (as pbrt warns), the film's among them.
//!
//! # Handedness
//! pbrt's space is left-handed (its camera's right is `up × forward`), kousen's right-handed.
//! Where the camera's transform keeps handedness the whole scene is mirrored (x → −x), so
//! that kousen shows the image pbrt shows; where it mirrors (an exporter's `Scale -1 1 1`),
//! nothing is. Every surface keeps the side pbrt treats as its front (where an area light
//! emits, and a glass's outside).
//!
//! Spectra are read in linear sRGB (`spectra`). Errors are one line naming the file and line.

mod lights;
mod materials;
mod shapes;
mod spectra;
mod subdivision;
mod tokens;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Vec3};

use crate::{Camera, Lens, Scene, SceneBuilder, SceneError, TextureId};
use tokens::{Kind, Params, Tokens};

/// The largest scene file read (inline meshes make them large).
const MAX_FILE_BYTES: u64 = 4 << 30;
/// How deep `Include`s may nest: enough for any scene, and a bound on a cycle.
const MAX_INCLUDE_DEPTH: u32 = 16;
/// Directives of the world block, and of the options before it.
const WORLD_ONLY: [&str; 11] = [
    "Shape",
    "LightSource",
    "AreaLightSource",
    "Material",
    "MakeNamedMaterial",
    "NamedMaterial",
    "Texture",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Import",
];
const OPTIONS_ONLY: [&str; 3] = ["Camera", "Film", "WorldBegin"];
/// pbrt-v4's film size where the file gives none.
const DEFAULT_FILM: (f32, f32) = (1280.0, 720.0);

/// Loads a pbrt scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let mut reader = Reader::new(path);
    reader.read_file(path, 0)?;
    reader.finish()
}

/// What the directives set and the shapes after them use (`AttributeBegin` saves it).
#[derive(Clone)]
struct State {
    /// pbrt's current transform (object to world in the world block).
    ctm: Mat4,
    reverse_orientation: bool,
    material: MaterialRef,
    /// The area light shapes get.
    area_light: Option<AreaLight>,
    /// The named medium inside the shapes made now (`MediumInterface`'s first name), if any.
    interior: Option<String>,
    /// The named medium outside them (its second name), if any: the camera's, where the
    /// camera is declared.
    exterior: Option<String>,
}

/// An `AreaLightSource`: the radiance shapes emit, from which faces, or their total `power`
/// (which sets the radiance by each shape's area).
#[derive(Clone, Copy, Debug)]
struct AreaLight {
    radiance: Vec3,
    two_sided: bool,
    power: Option<f32>,
}

/// Which material shapes get.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
enum MaterialRef {
    /// pbrt's default: diffuse, reflectance 0.5.
    Default,
    /// A `Material` directive's, by its place among them.
    Anonymous(usize),
    Named(String),
}

/// A material made for shapes: which, its emission's bits, its cut-out's parameter and the
/// medium inside it.
type MadeKey = (
    MaterialRef,
    Option<[u32; 4]>,
    Option<String>,
    Option<String>,
);

/// A material or texture as the file describes it, kept until a shape uses it.
#[derive(Clone)]
struct Definition {
    /// Material type, or texture class.
    class: String,
    params: Params,
    /// The file it was read from (for errors and relative names).
    file: PathBuf,
}

/// A shape kept inside `ObjectBegin`/`ObjectEnd`, made at each `ObjectInstance`.
#[derive(Clone)]
struct ShapeCall {
    kind: String,
    params: Params,
    state: State,
    file: PathBuf,
    line: u32,
}

/// The camera directive's transform, type and parameters.
struct CameraCall {
    camera_from_world: Mat4,
    kind: String,
    params: Params,
    file: PathBuf,
    /// The medium outside shapes where the camera is declared (pbrt's camera medium), if any.
    medium: Option<String>,
}

pub(super) struct Reader {
    /// The main file: pbrt resolves relative names against its folder.
    main: PathBuf,
    builder: SceneBuilder,
    state: State,
    saved: Vec<State>,
    coordinate_systems: HashMap<String, Mat4>,
    /// Whether `ActiveTransform` leaves the start time's transform alone (`EndTime`).
    transforms_ignored: bool,
    anonymous: Vec<Definition>,
    named_materials: HashMap<String, Definition>,
    /// `MakeNamedMedium`s by name (`type` their class), and those read so far (`None`: not
    /// homogeneous, warned about).
    media: HashMap<String, Definition>,
    media_read: HashMap<String, Option<crate::media::Medium>>,
    /// The media shapes are filled with, by name.
    media_filled: HashSet<String>,
    /// Named textures by whether they are float ones (pbrt keeps float and spectrum textures
    /// apart: one name may be both) and name.
    textures: HashMap<(bool, String), Definition>,
    /// Builder ids of materials made so far, by material, emission and cut-out.
    made: HashMap<MadeKey, materials::Made>,
    /// Named textures read so far.
    texture_colours: HashMap<(bool, String), materials::Colour>,
    /// Images decoded so far, by file and colour (sRGB) or data.
    images: HashMap<(PathBuf, bool), TextureId>,
    objects: HashMap<String, Vec<ShapeCall>>,
    /// The object being defined, and its shapes so far.
    recording: Option<(String, Vec<ShapeCall>)>,
    /// Shapes (with their instance's transform) whose material is named before it is
    /// defined, which pbrt allows: made once the whole file is read.
    deferred: Vec<(ShapeCall, Mat4)>,
    camera: Option<CameraCall>,
    film: Option<(Params, PathBuf)>,
    /// kousen's world from pbrt's: the mirror x → −x, or the identity (see the module).
    mirror: Mat4,
    world_begun: bool,
    warnings: Vec<String>,
    warned: HashSet<String>,
    /// A uniform `infinite` light's radiance, and a map's (resampled to kousen's layout).
    sky: Option<Vec3>,
    sky_map: Option<crate::SkyMap>,
}

impl Reader {
    fn new(path: &Path) -> Reader {
        let initial = State {
            ctm: Mat4::IDENTITY,
            reverse_orientation: false,
            material: MaterialRef::Default,
            area_light: None,
            interior: None,
            exterior: None,
        };
        Reader {
            main: path.to_path_buf(),
            builder: SceneBuilder::new(path),
            state: initial,
            saved: Vec::new(),
            coordinate_systems: HashMap::new(),
            transforms_ignored: false,
            anonymous: Vec::new(),
            named_materials: HashMap::new(),
            media: HashMap::new(),
            media_read: HashMap::new(),
            media_filled: HashSet::new(),
            textures: HashMap::new(),
            made: HashMap::new(),
            texture_colours: HashMap::new(),
            images: HashMap::new(),
            objects: HashMap::new(),
            recording: None,
            deferred: Vec::new(),
            camera: None,
            film: None,
            mirror: Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
            world_begun: false,
            warnings: Vec::new(),
            warned: HashSet::new(),
            sky: None,
            sky_map: None,
        }
    }

    /// A file the scene names, relative to the main file's folder.
    fn resolve(&self, name: &str) -> PathBuf {
        let folder = self.main.parent().unwrap_or(Path::new(""));
        folder.join(name.replace('\\', "/"))
    }

    /// Records a warning, once per distinct message (naming `file` where it is an included
    /// one).
    fn warn(&mut self, file: &Path, message: impl std::fmt::Display) {
        let name = match file == self.main {
            true => String::new(),
            false => format!("{}: ", file.display()),
        };
        let message = format!("{name}{message}");
        if self.warned.insert(message.clone()) {
            self.warnings.push(message);
        }
    }

    /// Warns of each parameter of `params` nothing read.
    fn warn_unused(&mut self, file: &Path, what: &str, params: &Params) {
        let unused: Vec<String> = params
            .unused()
            .map(|p| {
                format!(
                    "line {}: \"{} {}\" of {what} is not read",
                    p.line, p.ty, p.name
                )
            })
            .collect();
        for message in unused {
            self.warn(file, message);
        }
    }

    fn read_file(&mut self, path: &Path, depth: u32) -> Result<(), SceneError> {
        let bytes = crate::files::read_maybe_gzipped(path, MAX_FILE_BYTES)?;
        let text = String::from_utf8(bytes).map_err(|_| {
            SceneError::format(path, "not a UTF-8 text file (a pbrt scene is text)")
        })?;
        let mut tokens = Tokens::new(&text);
        let fail = |message: String| SceneError::format(path, message);
        while let Some(token) = tokens.next().map_err(fail)? {
            let Kind::Word(directive) = token.kind else {
                return Err(fail(format!(
                    "line {}: expected a directive (a word such as Shape), found a {}",
                    token.line,
                    match token.kind {
                        Kind::Quoted(_) => "quoted string",
                        _ => "bracket",
                    }
                )));
            };
            self.directive(directive, token.line, &mut tokens, path, depth)
                .map_err(|e| locate(e, path, token.line, directive))?;
        }
        Ok(())
    }

    fn directive(
        &mut self,
        directive: &str,
        line: u32,
        tokens: &mut Tokens,
        file: &Path,
        depth: u32,
    ) -> Result<(), SceneError> {
        let fail = |message: String| SceneError::format(file, message);
        // `read_file` names the line and the directive (`locate`).
        let at = |message: &str| fail(message.to_string());
        if WORLD_ONLY.contains(&directive) && !self.world_begun {
            return Err(at("before WorldBegin"));
        }
        if OPTIONS_ONLY.contains(&directive) && self.world_begun {
            return Err(at("after WorldBegin"));
        }
        match directive {
            "Identity" => self.transform(|_| Mat4::IDENTITY),
            "Translate" => {
                let v = tokens.numbers(3, directive).map_err(fail)?;
                let t = Mat4::from_translation(vec3(&v));
                self.transform(|ctm| ctm * t);
            }
            "Scale" => {
                let v = tokens.numbers(3, directive).map_err(fail)?;
                let s = Mat4::from_scale(vec3(&v));
                self.transform(|ctm| ctm * s);
            }
            "Rotate" => {
                let v = tokens.numbers(4, directive).map_err(fail)?;
                let axis = vec3(&v[1..])
                    .try_normalize()
                    .ok_or_else(|| at("the axis has no length"))?;
                let r = Mat4::from_axis_angle(axis, (v[0] as f32).to_radians());
                self.transform(|ctm| ctm * r);
            }
            "LookAt" => {
                let v = tokens.numbers(9, directive).map_err(fail)?;
                let (eye, target, up) = (vec3(&v), vec3(&v[3..]), vec3(&v[6..]));
                let view = look_at(eye, target, up).ok_or_else(|| {
                    at("the eye, the point looked at and the up vector leave no view")
                })?;
                self.transform(|ctm| ctm * view);
            }
            "Transform" | "ConcatTransform" => {
                let v = tokens.numbers(16, directive).map_err(fail)?;
                let m: Vec<f32> = v.iter().map(|&x| x as f32).collect();
                // pbrt lists the matrix by columns (its translation last), as glam stores it.
                let m = Mat4::from_cols_slice(&m);
                match directive {
                    "Transform" => self.transform(|_| m),
                    _ => self.transform(|ctm| ctm * m),
                }
            }
            "CoordinateSystem" => {
                let name = tokens.string("a name").map_err(fail)?;
                self.coordinate_systems.insert(name, self.state.ctm);
            }
            "CoordSysTransform" => {
                let name = tokens.string("a name").map_err(fail)?;
                match self.coordinate_systems.get(&name) {
                    Some(&m) => self.transform(|_| m),
                    None => self.warn(
                        file,
                        format!("line {line}: no coordinate system \"{name}\""),
                    ),
                }
            }
            "ActiveTransform" => {
                let which = tokens.next().map_err(fail)?;
                self.transforms_ignored = match which.map(|t| t.kind) {
                    Some(Kind::Word("All" | "StartTime")) => false,
                    Some(Kind::Word("EndTime")) => {
                        self.warn(
                            file,
                            "motion is not rendered: the start time's transforms kept",
                        );
                        true
                    }
                    _ => return Err(at("expected All, StartTime or EndTime")),
                };
            }
            "TransformTimes" => {
                tokens.numbers(2, directive).map_err(fail)?;
            }
            "ReverseOrientation" => {
                self.state.reverse_orientation = !self.state.reverse_orientation;
            }
            "AttributeBegin" | "TransformBegin" => self.saved.push(self.state.clone()),
            "AttributeEnd" | "TransformEnd" => {
                let saved = self
                    .saved
                    .pop()
                    .ok_or_else(|| at("without a matching begin"))?;
                match directive {
                    "TransformEnd" => self.state.ctm = saved.ctm,
                    _ => self.state = saved,
                }
            }
            "Attribute" => {
                tokens.string("a target").map_err(fail)?;
                tokens.params().map_err(fail)?;
                self.warn(
                    file,
                    format!("line {line}: Attribute defaults are not read"),
                );
            }
            "Option" => {
                tokens.params().map_err(fail)?;
            }
            "ColorSpace" => {
                let name = tokens.string("a colour space").map_err(fail)?;
                if name != "srgb" {
                    self.warn(
                        file,
                        format!("line {line}: colour space \"{name}\" read as sRGB"),
                    );
                }
            }
            "Camera" => {
                let kind = tokens.string("a camera type").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                let camera_from_world = self.state.ctm;
                if camera_from_world.determinant() == 0.0 {
                    return Err(at("the camera's transform cannot be inverted"));
                }
                self.coordinate_systems
                    .insert("camera".into(), camera_from_world.inverse());
                self.camera = Some(CameraCall {
                    camera_from_world,
                    kind,
                    params,
                    file: file.to_path_buf(),
                    medium: self.state.exterior.clone(),
                });
            }
            "Film" => {
                tokens.string("a film type").map_err(fail)?;
                self.film = Some((tokens.params().map_err(fail)?, file.to_path_buf()));
            }
            "Sampler" | "Integrator" | "PixelFilter" | "Accelerator" | "SurfaceIntegrator"
            | "VolumeIntegrator" | "Renderer" => {
                tokens.string("a type").map_err(fail)?;
                tokens.params().map_err(fail)?;
            }
            "MakeNamedMedium" => {
                let name = tokens.string("a medium's name").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                let class = params.string("type").map_err(fail)?.unwrap_or_default();
                let definition = Definition {
                    class,
                    params,
                    file: file.to_path_buf(),
                };
                self.media.insert(name, definition);
            }
            "MediumInterface" => {
                let inside = tokens.string("a medium's name").map_err(fail)?;
                let outside = match tokens.peek().map_err(fail)? {
                    Some(t) if matches!(t.kind, Kind::Quoted(_)) => {
                        tokens.string("a medium's name").map_err(fail)?
                    }
                    _ => inside.clone(),
                };
                // The same medium on both sides bounds nothing (pbrt's one-name form). The
                // outside of shapes is found from the geometry (the solid around them); the
                // camera's outside medium may be the scene's atmosphere (`finish`).
                self.state.interior = (!inside.is_empty() && inside != outside).then_some(inside);
                self.state.exterior = (!outside.is_empty()).then_some(outside);
            }
            "WorldBegin" => self.world_begin(),
            "WorldEnd" => {}
            "Texture" => {
                let name = tokens.string("a texture's name").map_err(fail)?;
                let kind = tokens.string("a texture's type").map_err(fail)?;
                let class = tokens.string("a texture's class").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                let key = (kind == "float", name);
                let definition = Definition {
                    class,
                    params,
                    file: file.to_path_buf(),
                };
                self.texture_colours.remove(&key);
                self.textures.insert(key, definition);
            }
            "Material" => {
                let class = tokens.string("a material's type").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                self.anonymous.push(Definition {
                    class,
                    params,
                    file: file.to_path_buf(),
                });
                self.state.material = MaterialRef::Anonymous(self.anonymous.len() - 1);
            }
            "MakeNamedMaterial" => {
                let name = tokens.string("a material's name").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                let class = params
                    .string("type")
                    .map_err(fail)?
                    .ok_or_else(|| at(&format!("material \"{name}\" has no \"string type\"")))?;
                let definition = Definition {
                    class,
                    params,
                    file: file.to_path_buf(),
                };
                self.named_materials.insert(name.clone(), definition);
                // A redefinition replaces what shapes after it get.
                self.made
                    .retain(|(m, ..), _| *m != MaterialRef::Named(name.clone()));
            }
            "NamedMaterial" => {
                let name = tokens.string("a material's name").map_err(fail)?;
                self.state.material = MaterialRef::Named(name);
            }
            "LightSource" => {
                let kind = tokens.string("a light's type").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                self.light(&kind, &params, file)?;
                self.warn_unused(file, &format!("light \"{kind}\""), &params);
            }
            "AreaLightSource" => {
                let kind = tokens.string("an area light's type").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                self.state.area_light = self.area_light(&kind, &params, file)?;
                self.warn_unused(file, &format!("area light \"{kind}\""), &params);
            }
            "Shape" => {
                let kind = tokens.string("a shape's type").map_err(fail)?;
                let params = tokens.params().map_err(fail)?;
                let call = ShapeCall {
                    kind,
                    params,
                    state: self.state.clone(),
                    file: file.to_path_buf(),
                    line,
                };
                match &mut self.recording {
                    Some((_, shapes)) => shapes.push(call),
                    None => self.shape_or_defer(call, Mat4::IDENTITY)?,
                }
            }
            "ObjectBegin" => {
                let name = tokens.string("an object's name").map_err(fail)?;
                if self.recording.is_some() {
                    return Err(at("an object inside an object"));
                }
                self.saved.push(self.state.clone());
                self.recording = Some((name, Vec::new()));
            }
            "ObjectEnd" => {
                let (name, shapes) = self
                    .recording
                    .take()
                    .ok_or_else(|| at("outside an object"))?;
                self.objects.insert(name, shapes);
                self.state = self.saved.pop().ok_or_else(|| at("without ObjectBegin"))?;
            }
            "ObjectInstance" => {
                let name = tokens.string("an object's name").map_err(fail)?;
                if self.recording.is_some() {
                    return Err(at("an instance inside an object"));
                }
                let shapes = (self.objects.get(&name).cloned())
                    .ok_or_else(|| at(&format!("no object \"{name}\"")))?;
                let outer = self.state.ctm;
                for call in shapes {
                    self.shape_or_defer(call, outer)?;
                }
            }
            "Include" | "Import" => {
                let name = tokens.string("a file name").map_err(fail)?;
                if depth >= MAX_INCLUDE_DEPTH {
                    return Err(at("files included too deep (an Include cycle?)"));
                }
                let included = self.resolve(&name);
                // An Import's changes to the graphics state stay in it.
                let state = (directive == "Import").then(|| self.state.clone());
                self.read_file(&included, depth + 1)?;
                if let Some(state) = state {
                    self.state = state;
                }
            }
            other => return Err(fail(format!("line {line}: unknown directive \"{other}\""))),
        }
        Ok(())
    }

    /// Sets the current transform to `f` of it (unless motion's end is being given).
    fn transform(&mut self, f: impl FnOnce(Mat4) -> Mat4) {
        if !self.transforms_ignored {
            self.state.ctm = f(self.state.ctm);
        }
    }

    /// `WorldBegin`: the camera is known, so whether the scene is mirrored is too.
    fn world_begin(&mut self) {
        let world_from_camera = match &self.camera {
            Some(c) => c.camera_from_world.inverse(),
            None => Mat4::IDENTITY,
        };
        // pbrt's camera right is its transform's +x; kousen's is forward × up, which is that
        // only where the transform mirrors.
        self.mirror = match Mat3::from_mat4(world_from_camera).determinant() > 0.0 {
            true => Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
            false => Mat4::IDENTITY,
        };
        self.coordinate_systems
            .insert("world".into(), Mat4::IDENTITY);
        self.state.ctm = Mat4::IDENTITY;
        self.state.reverse_orientation = false;
        self.world_begun = true;
    }

    /// Makes a shape now, or once the file is read where its material is named before it is
    /// defined.
    fn shape_or_defer(&mut self, call: ShapeCall, outer: Mat4) -> Result<(), SceneError> {
        match self.material_defined(&call.state.material, materials::MAX_NESTING) {
            true => self.shape(&call, outer),
            false => {
                self.deferred.push((call, outer));
                Ok(())
            }
        }
    }

    /// Whether every named material `material` refers to (through mixes) is defined yet.
    fn material_defined(&self, material: &MaterialRef, depth: u32) -> bool {
        let definition = match material {
            MaterialRef::Default => return true,
            MaterialRef::Anonymous(i) => &self.anonymous[*i],
            MaterialRef::Named(name) => match self.named_materials.get(name) {
                Some(definition) => definition,
                None => return false,
            },
        };
        let p = &definition.params;
        if definition.class != "mix" || depth == 0 {
            return true;
        }
        let v4 = p.strings("materials").ok().flatten();
        let v3 = ["namedmaterial1", "namedmaterial2"].map(|n| p.string(n).ok().flatten());
        let members = v4.unwrap_or_else(|| v3.into_iter().flatten().collect());
        members
            .into_iter()
            .all(|name| self.material_defined(&MaterialRef::Named(name), depth - 1))
    }

    fn finish(mut self) -> Result<Scene, SceneError> {
        for (call, outer) in std::mem::take(&mut self.deferred) {
            self.shape(&call, outer)
                .map_err(|e| locate(e, &call.file, call.line, "Shape"))?;
        }
        if let Some(call) = self.camera.take() {
            let (medium, file) = (call.medium.clone(), call.file.clone());
            self.make_camera(call)?;
            // The camera's medium, where no shape is filled with it, fills all space outside
            // the solids (`crate::media`).
            if let Some(name) = medium.filter(|name| !self.media_filled.contains(name))
                && let Some(medium) = self.interior_medium(&name, &file)?
            {
                self.builder.set_atmosphere(medium);
            }
        }
        let mut unused: Vec<(&String, &Definition)> = (self.media.iter())
            .filter(|(name, _)| !self.media_read.contains_key(*name))
            .collect();
        unused.sort_by_key(|(name, _)| name.as_str());
        let unused: Vec<(String, PathBuf)> = (unused.into_iter())
            .map(|(name, d)| (name.clone(), d.file.clone()))
            .collect();
        for (name, file) in unused {
            self.warn(&file, format!("medium \"{name}\" fills no shape: not read"));
        }
        let Reader {
            mut builder,
            warnings,
            sky,
            sky_map,
            ..
        } = self;
        for warning in warnings {
            builder.warn(warning);
        }
        let path = builder.path().to_path_buf();
        let mut scene = builder.finish()?;
        let bounds = scene.bounds();
        if let Some(map) = sky_map {
            let sky = crate::Sky::with_map(std::sync::Arc::new(map), Vec3::ONE, 0.0, bounds);
            scene.lights.replace_sky(sky);
        } else if let Some(radiance) = sky {
            scene.lights.set_sky(radiance, bounds);
        }
        scene.dim_far_lights(&path);
        Ok(scene)
    }

    /// The camera, in kousen's world (mirrored where the scene is).
    fn make_camera(&mut self, call: CameraCall) -> Result<(), SceneError> {
        let file = call.file.clone();
        let fail = |message: String| SceneError::format(&file, message);
        let params = &call.params;
        let (width, height) = match self.film.take() {
            Some((film, film_file)) => {
                let fail = |message: String| SceneError::format(&film_file, message);
                let width = film.float("xresolution", DEFAULT_FILM.0).map_err(fail)?;
                let height = film.float("yresolution", DEFAULT_FILM.1).map_err(fail)?;
                let iso = film.float("iso", 100.0).map_err(fail)?;
                if iso != 100.0 {
                    let ratio = iso / 100.0;
                    let message = format!(
                        "film iso {iso}: pbrt's image is {ratio}× the radiance kousen writes (a PNG as pbrt's: --exposure {:.2})",
                        ratio.log2()
                    );
                    self.warn(&film_file, message);
                }
                // Where the image goes, and how pbrt writes it: kousen's command line says.
                film.get("filename");
                self.warn_unused(&film_file, "the film", &film);
                (width, height)
            }
            None => DEFAULT_FILM,
        };
        let aspect = params
            .float("frameaspectratio", width / height)
            .map_err(fail)?;
        if !(aspect.is_finite() && aspect > 0.0) {
            return Err(fail(format!(
                "the film's aspect ratio {aspect} is not positive"
            )));
        }
        if params.get("screenwindow").is_some() {
            self.warn(
                &file,
                "the camera's screenwindow is not read: the whole film is used",
            );
        }
        let world = self.mirror * call.camera_from_world.inverse();
        let eye = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::Z);
        let up = world.transform_vector3(Vec3::Y);
        // The film's shorter side spans pbrt's field of view (or its screen window's 2 units).
        let shorter_over_height = aspect.min(1.0);
        let camera = match call.kind.as_str() {
            "perspective" => {
                let fov = params.float("fov", 90.0).map_err(fail)?;
                if !(fov > 0.0 && fov < 180.0) {
                    return Err(fail(format!("fov {fov}° is not in (0°, 180°)")));
                }
                let tan_y = (fov.to_radians() / 2.0).tan() / shorter_over_height;
                let camera = Camera::look_at(eye, eye + forward, up, 2.0 * tan_y.atan());
                let camera =
                    camera.ok_or_else(|| fail("the camera's transform leaves no view".into()))?;
                let radius = params.float("lensradius", 0.0).map_err(fail)?;
                let focus = params.float("focaldistance", 1e6).map_err(fail)?;
                let lens = Lens::new(radius, focus).ok_or_else(|| {
                    fail(format!(
                        "lensradius {radius} or focaldistance {focus} is not positive"
                    ))
                })?;
                camera.with_lens(lens)
            }
            "orthographic" => {
                let camera = Camera::look_at(eye, eye + forward, up, 1.0)
                    .ok_or_else(|| fail("the camera's transform leaves no view".into()))?;
                // The camera transform's scale along y scales the film.
                let half_height = up.length() / shorter_over_height;
                camera
                    .orthographic(half_height)
                    .ok_or_else(|| fail("the orthographic film has no size".into()))?
            }
            other => {
                self.warn(
                    &file,
                    format!("camera \"{other}\" is not read: kousen frames the scene"),
                );
                return Ok(());
            }
        };
        let mut camera = camera.named("camera");
        camera.aspect_ratio = Some(aspect);
        self.builder.add_camera(camera);
        self.warn_unused(&file, "the camera", params);
        Ok(())
    }
}

/// `error` placed at `line` of `file`, naming `directive`, where it is this file's and names
/// no line of its own.
fn locate(error: SceneError, file: &Path, line: u32, directive: &str) -> SceneError {
    match error {
        SceneError::Format { path, message } if path == file && !message.starts_with("line ") => {
            SceneError::Format {
                path,
                message: format!("line {line}: {directive}: {message}"),
            }
        }
        other => other,
    }
}

fn vec3(v: &[f64]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// pbrt's `LookAt`: the camera-from-world transform of a camera at `eye` looking at
/// `target`, its +x `up × forward` (pbrt's left-handed frame), +y up, +z forward.
fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
    let forward = (target - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(forward).try_normalize()?;
    let new_up = forward.cross(right);
    let world_from_camera = Mat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        forward.extend(0.0),
        eye.extend(1.0),
    );
    eye.is_finite().then(|| world_from_camera.inverse())
}
