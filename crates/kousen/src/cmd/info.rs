//! `kousen info SCENE [--json]`: what a scene holds and what its BVH costs.

use std::time::Instant;

use serde::Serialize;

use crate::cli::{BvhArgs, InfoArgs};

/// The JSON printed by `--json`. Field names are a contract for scripts (issue 2).
#[derive(Serialize)]
struct Info {
    scene: String,
    load_ms: f64,
    triangles: usize,
    degenerate_dropped: usize,
    materials: usize,
    /// Materials by the surface kousen maps them onto (`scene::Surface`), in words.
    material_kinds: Vec<MaterialKind>,
    /// Materials with a normal map (glTF `normalTexture`).
    normal_mapped_materials: usize,
    /// Materials (blend members) whose surface a metallic-roughness texture picks at each hit
    /// (`scene::RoughnessMap`); the kinds above are theirs at the texture's mean.
    roughness_mapped_materials: usize,
    /// Blends (`scene::Blend`: glTF's partial metallic or transmission factors), each a
    /// chain of member materials counted among `materials`.
    blends: usize,
    /// Materials (blend members) under a clear coat (`scene::Clearcoat`: glTF's
    /// `KHR_materials_clearcoat`).
    clear_coated_materials: usize,
    /// Materials (blend members) with a sheen (`scene::Sheen`: glTF's `KHR_materials_sheen`).
    sheened_materials: usize,
    /// Materials (blend members) with diffuse transmission (`scene::DiffuseTransmission`:
    /// glTF's `KHR_materials_diffuse_transmission`).
    translucent_materials: usize,
    /// Of those, the ones bounding a translucent solid (`scene::DiffuseTransmission::volume`:
    /// with glTF's `KHR_materials_volume`), which absorbs inside.
    translucent_solids: usize,
    /// Of those, the ones scattering inside (`scene::Material::scattering`: glTF's
    /// `KHR_materials_volume_scatter`).
    scattering_solids: usize,
    /// Materials of murky glass: solid glass scattering inside
    /// (`scene::Material::has_murky_glass`: glTF's `KHR_materials_volume_scatter` on
    /// transmission), whose light is gathered where it scatters (`render::scattering`).
    murky_glass_materials: usize,
    /// Materials (blend members) brushed (`scene::Anisotropy`: glTF's
    /// `KHR_materials_anisotropy`).
    brushed_materials: usize,
    /// Materials (blend members) under a thin film (`scene::Iridescence`: glTF's
    /// `KHR_materials_iridescence`, which colours their metal, glass or coat).
    iridescent_materials: usize,
    /// Materials (blend members) under a specular layer (`scene::SpecularLayer`: glTF's
    /// `KHR_materials_specular` other than its defaults).
    specular_layers: usize,
    /// Whether the meshes carry their own tangents (glTF TANGENT), the frame of normal maps
    /// and brushing (else each triangle's texture coordinates give it).
    vertex_tangents: bool,
    /// Materials whose surfaces lie inside a solid dielectric (`render::nesting`), with it:
    /// their indices of refraction count against its.
    inside_solids: Vec<InsideSolid>,
    /// The medium filling all space outside the solids (`scene::Scene::atmosphere`: Mitsuba's
    /// sensor medium, pbrt's camera medium), if any; its material counts among `materials`.
    atmosphere: Option<AtmosphereInfo>,
    textures: usize,
    cameras: usize,
    /// The file's animations (glTF): what `--animation-time` and `--animation` choose from.
    animations: Vec<AnimationInfo>,
    /// The file's material variants (glTF `KHR_materials_variants`), by name: what
    /// `--variant` chooses from.
    variants: Vec<String>,
    emissive_triangles: usize,
    /// glTF `KHR_lights_punctual` lights by kind.
    punctual_lights: PunctualInfo,
    /// Total emitted flux, mean of the RGB channels.
    light_power: f32,
    light_power_rgb: [f32; 3],
    bounds: BoundsInfo,
    bvh: BvhInfo,
    memory: MemoryInfo,
    warnings: Vec<String>,
}

/// The material variants as the table lists them: index and name.
fn variants_line(variants: &[String]) -> String {
    if variants.is_empty() {
        return "none".to_string();
    }
    let named: Vec<String> = (variants.iter().enumerate())
        .map(|(i, name)| format!("{i} \"{name}\""))
        .collect();
    named.join(", ")
}

/// The animations as the table lists them: index, name where there is one, length.
fn animations_line(animations: &[AnimationInfo]) -> String {
    if animations.is_empty() {
        return "none".to_string();
    }
    let clips: Vec<String> = (animations.iter().enumerate())
        .map(|(i, clip)| match &clip.name {
            Some(name) => format!("{i} \"{name}\" ({:.2} s)", clip.seconds),
            None => format!("{i} ({:.2} s)", clip.seconds),
        })
        .collect();
    clips.join(", ")
}

#[derive(Serialize)]
struct AnimationInfo {
    name: Option<String>,
    /// Its last keyframe's time.
    seconds: f32,
}

#[derive(Serialize)]
struct InsideSolid {
    material: String,
    solid: String,
}

#[derive(Serialize)]
struct AtmosphereInfo {
    /// Per unit of length and channel.
    absorption: [f32; 3],
    scattering: [f32; 3],
    /// Henyey–Greenstein's g.
    anisotropy: f32,
}

fn atmosphere(scene: &scene::Scene) -> Option<AtmosphereInfo> {
    let air = &scene.materials[scene.atmosphere? as usize];
    Some(AtmosphereInfo {
        absorption: air.absorption.to_array(),
        scattering: air.scattering.to_array(),
        anisotropy: air.scatter_anisotropy,
    })
}

/// The materials `render::nesting` finds inside solids, by name (the atmosphere around the
/// rest is none).
fn inside_solids(scene: &scene::Scene) -> Vec<InsideSolid> {
    let nesting = render::nesting::Nesting::of(scene);
    let name = |id: usize| scene.materials[id].name.clone();
    (nesting.exterior.iter().enumerate())
        .filter(|(_, around)| **around != render::medium::NO_MEDIUM)
        .filter(|(_, around)| Some(**around) != scene.atmosphere)
        .map(|(id, &around)| InsideSolid {
            material: name(id),
            solid: name(around as usize),
        })
        .collect()
}

#[derive(Serialize)]
struct MaterialKind {
    kind: &'static str,
    count: usize,
}

/// The kind of surface a material is, in a user's words (glass with absorption inside it is
/// "tinted", glass whose index depends on the wavelength "dispersive").
fn material_kind(material: &scene::Material) -> &'static str {
    use scene::Surface;
    let tinted = material.interior_absorption() != glam::Vec3::ZERO;
    let dispersive = material.dispersion > 0.0;
    match (material.surface, tinted, dispersive) {
        (Surface::Dielectric { .. }, true, true) => return "tinted dispersive glass",
        (Surface::Dielectric { .. }, false, true) => return "dispersive glass",
        (Surface::RoughDielectric { .. }, true, true) => return "tinted dispersive frosted glass",
        (Surface::RoughDielectric { .. }, false, true) => return "dispersive frosted glass",
        _ => {}
    }
    match material.surface {
        Surface::Diffuse => "diffuse",
        Surface::Mirror => "mirror",
        Surface::RoughConductor { .. } => "rough metal",
        Surface::Dielectric {
            thin_walled: true, ..
        } => "glass sheet",
        Surface::RoughDielectric {
            thin_walled: true, ..
        } => "frosted glass sheet",
        Surface::Dielectric { .. } if tinted => "tinted glass",
        Surface::Dielectric { .. } => "glass",
        Surface::RoughDielectric { .. } if tinted => "tinted frosted glass",
        Surface::RoughDielectric { .. } => "frosted glass",
        Surface::Plastic { alpha, .. } if alpha > 0.0 => "glossy plastic",
        Surface::Plastic { .. } => "plastic",
    }
}

/// The blends among `materials`: the chains' first members (no material names them as the
/// one taken otherwise).
fn blend_count(materials: &[scene::Material]) -> usize {
    let later: Vec<u32> = materials
        .iter()
        .filter_map(|m| m.blend)
        .map(|b| b.other)
        .collect();
    (0..materials.len() as u32)
        .filter(|id| materials[*id as usize].blend.is_some() && !later.contains(id))
        .count()
}

/// Counts of each kind, in the order kinds first appear among the materials.
fn material_kinds(materials: &[scene::Material]) -> Vec<MaterialKind> {
    let mut kinds: Vec<MaterialKind> = Vec::new();
    for material in materials {
        let kind = material_kind(material);
        match kinds.iter_mut().find(|k| k.kind == kind) {
            Some(k) => k.count += 1,
            None => kinds.push(MaterialKind { kind, count: 1 }),
        }
    }
    kinds
}

#[derive(Serialize)]
struct PunctualInfo {
    point: usize,
    spot: usize,
    directional: usize,
}

impl PunctualInfo {
    fn count(lights: &scene::Lights) -> PunctualInfo {
        let of = |kind: fn(&scene::PunctualKind) -> bool| {
            lights
                .punctual
                .iter()
                .filter(|e| kind(&e.light.kind))
                .count()
        };
        PunctualInfo {
            point: of(|k| matches!(k, scene::PunctualKind::Point)),
            spot: of(|k| matches!(k, scene::PunctualKind::Spot { .. })),
            directional: of(|k| matches!(k, scene::PunctualKind::Directional)),
        }
    }
}

#[derive(Serialize)]
struct BoundsInfo {
    min: [f32; 3],
    max: [f32; 3],
}

#[derive(Serialize)]
struct BvhInfo {
    nodes: usize,
    leaves: usize,
    depth: usize,
    sah_cost: f64,
    /// The binned SAH build (what Embree's build times measure), with the chosen tree's
    /// threading and packing; with splitting left to the probe (the default), both builds
    /// and packings and the probe.
    build_ms: f64,
    /// Threading for TBVH and the six MTBVH orders, and packing for the GPU.
    thread_and_pack_ms: f64,
    /// Making the compact MTBVH from the packed one (`bvh::compact`); null where it could
    /// not be made (see `memory.mtbvh_compact_error`).
    compact_ms: Option<f64>,
    max_leaf_size: usize,
    /// Extra references to split triangles asked for, in percent of the triangles.
    split_percent: u32,
    /// Triangles as packed for the GPU: one per reference, so a split triangle counts once per
    /// piece.
    packed_triangles: usize,
    /// `leaf_size_histogram[k]` = number of leaves holding k triangles.
    leaf_size_histogram: Vec<usize>,
}

#[derive(Serialize)]
struct MemoryInfo {
    tbvh_bytes: usize,
    mtbvh_bytes: usize,
    tbvh_bytes_per_triangle: f64,
    mtbvh_bytes_per_triangle: f64,
    mtbvh_over_tbvh: f64,
    /// What the GPU's stack, TBVH and MTBVH kernels read (`bvh::threaded`: every threading's
    /// nodes again in its own pre-order, one load a traversal step).
    gpu_threaded_bytes: usize,
    gpu_threaded_bytes_per_triangle: f64,
    /// The compact MTBVH ("mtbvh16": 16-bit boxes and links, `bvh::compact`) with its
    /// triangles; the `mtbvh_compact_*` keys are null where it could not be made.
    mtbvh_compact_bytes: Option<usize>,
    mtbvh_compact_bytes_per_triangle: Option<f64>,
    mtbvh_compact_over_tbvh: Option<f64>,
    mtbvh_compact_over_mtbvh: Option<f64>,
    /// Nodes whose links pass 16-bit offsets and live in a 32-byte far record.
    mtbvh_compact_far_records: Option<usize>,
    /// Why the compact MTBVH could not be made, else null.
    mtbvh_compact_error: Option<String>,
    /// The four-wide MTBVH ("mtbvh4", `bvh::wide`) with the packed triangles, as the other
    /// rows count them: its nodes, its leaves (the triangles' positions again, four to a
    /// record) and the packed triangles the CPU backend shades hits from; the `mtbvh4_*` keys
    /// are null where it could not be made.
    mtbvh4_bytes: Option<usize>,
    mtbvh4_bytes_per_triangle: Option<f64>,
    mtbvh4_nodes: Option<usize>,
    /// Its SAH cost per ray through the root's box, a four-box node test counting 1 and a
    /// four-triangle leaf record `bvh::wide::collapse::LEAF_COST` (the collapse minimises it).
    mtbvh4_sah_cost: Option<f64>,
    mtbvh4_ms: Option<f64>,
    /// Why the four-wide MTBVH could not be made, else null.
    mtbvh4_error: Option<String>,
}

pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    let info = gather(args)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print_table(&info);
    }
    Ok(())
}

fn gather(args: &InfoArgs) -> anyhow::Result<Info> {
    let started = Instant::now();
    let scene = scene::load_with(&args.scene, &args.load.options())?;
    let load_ms = millis(started);

    check_bvh_limits(&scene)?;
    let options = build_options(args.bvh);
    let started = Instant::now();
    let (tree, _) = bvh::probe::build_chosen(&scene.triangles, &options);
    let build_ms = millis(started);
    // Packed once more, alone, to time it (this command's purpose).
    let started = Instant::now();
    let packed = bvh::PackedBvh::from_bvh(&scene.triangles, &tree);
    let thread_and_pack_ms = millis(started);
    let memory = packed.memory();
    let started = Instant::now();
    let compact = bvh::CompactMtbvh::new(&packed);
    let compact_ms = millis(started);
    let started = Instant::now();
    let wide = bvh::WideMtbvh::new(&packed);
    let wide_ms = millis(started);

    let triangles = scene.triangles.len();
    let per_triangle = |bytes: usize| bytes as f64 / triangles as f64;
    let compact_memory = compact
        .as_ref()
        .ok()
        .map(|c| (c.memory(packed.triangles.len()).total_bytes, c.far_count()));
    let compact_bytes = compact_memory.map(|(bytes, _)| bytes);
    let wide_bytes = wide
        .as_ref()
        .ok()
        .map(|w| w.bytes() + memory.triangle_bytes);
    let bounds = scene.bounds();
    // Materials (blend members) with a feature.
    let count =
        |has: fn(&scene::Material) -> bool| scene.materials.iter().filter(|m| has(m)).count();
    Ok(Info {
        scene: args.scene.display().to_string(),
        load_ms,
        triangles,
        degenerate_dropped: scene.degenerate_dropped,
        materials: scene.materials.len(),
        material_kinds: material_kinds(&scene.materials),
        normal_mapped_materials: count(|m| m.normal_texture.is_some()),
        roughness_mapped_materials: count(|m| m.roughness_map.is_some()),
        blends: blend_count(&scene.materials),
        clear_coated_materials: count(|m| m.clearcoat.is_some()),
        sheened_materials: count(|m| m.sheen.is_some()),
        translucent_materials: count(|m| m.diffuse_transmission.is_some()),
        translucent_solids: count(|m| m.diffuse_transmission.is_some_and(|t| t.volume)),
        scattering_solids: count(|m| {
            m.is_translucent_solid() && m.interior_scattering().max_element() > 0.0
        }),
        murky_glass_materials: count(|m| m.has_murky_glass()),
        brushed_materials: count(|m| m.anisotropy.is_some()),
        iridescent_materials: count(|m| m.iridescence.is_some()),
        specular_layers: count(|m| m.specular.is_some()),
        vertex_tangents: scene.has_vertex_tangents(),
        inside_solids: inside_solids(&scene),
        atmosphere: atmosphere(&scene),
        textures: scene.textures.len(),
        cameras: scene.cameras.len(),
        animations: (scene.animations.iter())
            .map(|clip| AnimationInfo {
                name: clip.name.clone(),
                seconds: clip.seconds,
            })
            .collect(),
        variants: scene.variants.clone(),
        emissive_triangles: scene.lights.triangles.len(),
        punctual_lights: PunctualInfo::count(&scene.lights),
        light_power: scene.lights.total_power_scalar(),
        light_power_rgb: scene.lights.total_power.to_array(),
        bounds: BoundsInfo {
            min: bounds.min.to_array(),
            max: bounds.max.to_array(),
        },
        bvh: BvhInfo {
            nodes: tree.node_count(),
            leaves: tree.leaf_count(),
            depth: tree.depth(),
            sah_cost: tree.sah_cost(),
            build_ms,
            thread_and_pack_ms,
            compact_ms: compact.is_ok().then_some(compact_ms),
            max_leaf_size: options.max_leaf_size,
            split_percent: options.split_percent,
            packed_triangles: packed.triangles.len(),
            leaf_size_histogram: tree.leaf_size_histogram(),
        },
        memory: MemoryInfo {
            tbvh_bytes: memory.tbvh_bytes,
            mtbvh_bytes: memory.mtbvh_bytes,
            tbvh_bytes_per_triangle: per_triangle(memory.tbvh_bytes),
            mtbvh_bytes_per_triangle: per_triangle(memory.mtbvh_bytes),
            mtbvh_over_tbvh: memory.mtbvh_bytes as f64 / memory.tbvh_bytes as f64,
            gpu_threaded_bytes: memory.gpu_threaded_bytes,
            gpu_threaded_bytes_per_triangle: per_triangle(memory.gpu_threaded_bytes),
            mtbvh_compact_bytes: compact_bytes,
            mtbvh_compact_bytes_per_triangle: compact_bytes.map(per_triangle),
            mtbvh_compact_over_tbvh: compact_bytes.map(|b| b as f64 / memory.tbvh_bytes as f64),
            mtbvh_compact_over_mtbvh: compact_bytes.map(|b| b as f64 / memory.mtbvh_bytes as f64),
            mtbvh_compact_far_records: compact_memory.map(|(_, far)| far),
            mtbvh_compact_error: compact.err().map(|e| e.to_string()),
            mtbvh4_bytes: wide_bytes,
            mtbvh4_bytes_per_triangle: wide_bytes.map(per_triangle),
            mtbvh4_nodes: wide.as_ref().ok().map(|w| w.nodes.len()),
            mtbvh4_sah_cost: wide.as_ref().ok().map(|w| w.sah_cost),
            mtbvh4_ms: wide.is_ok().then_some(wide_ms),
            mtbvh4_error: wide.err().map(|e| e.to_string()),
        },
        warnings: scene.warnings,
    })
}

pub fn build_options(args: BvhArgs) -> bvh::BuildOptions {
    let mut options = bvh::BuildOptions::default();
    if let Some(n) = args.leaf_size {
        options.max_leaf_size = n as usize;
    }
    if let Some(percent) = args.split_percent {
        // Asked for by number: forced, not left to the probe.
        options.split_percent = percent;
        options.probe_split = false;
    }
    options
}

/// The packed BVH's own limits, checked before building so that a huge scene is refused in
/// words rather than by a panic.
pub fn check_bvh_limits(scene: &scene::Scene) -> anyhow::Result<()> {
    if scene.triangles.len() > bvh::build_sah::MAX_TRIANGLES {
        anyhow::bail!(
            "the scene has {} triangles; the BVH holds at most {}",
            scene.triangles.len(),
            bvh::build_sah::MAX_TRIANGLES
        );
    }
    if scene.materials.len() > bvh::PackedTriangle::MAX_MATERIAL as usize {
        anyhow::bail!(
            "the scene has {} materials; packed vertices hold at most {}",
            scene.materials.len(),
            bvh::PackedTriangle::MAX_MATERIAL
        );
    }
    Ok(())
}

fn millis(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

fn print_table(info: &Info) {
    let bytes =
        |b: usize, per: f64| format!("{b} B ({per:.1} B/triangle, {:.1} floats)", per / 4.0);
    let rows = [
        ("scene", info.scene.clone()),
        ("load", format!("{:.1} ms", info.load_ms)),
        ("triangles", info.triangles.to_string()),
        ("degenerate dropped", info.degenerate_dropped.to_string()),
        (
            "materials",
            if info.material_kinds.is_empty() {
                info.materials.to_string()
            } else {
                let kinds: Vec<String> = info
                    .material_kinds
                    .iter()
                    .map(|k| format!("{} {}", k.count, k.kind))
                    .collect();
                format!("{} ({})", info.materials, kinds.join(", "))
            },
        ),
        (
            "normal maps",
            format!(
                "{} materials (frame: {})",
                info.normal_mapped_materials,
                if info.vertex_tangents {
                    "the meshes' tangents"
                } else {
                    "texture coordinates"
                }
            ),
        ),
        (
            "roughness maps",
            format!(
                "{} materials (metallic-roughness texture: surface per texel)",
                info.roughness_mapped_materials
            ),
        ),
        (
            "blends",
            format!(
                "{} (their member surfaces among the materials)",
                info.blends
            ),
        ),
        (
            "clear coats",
            format!("{} materials", info.clear_coated_materials),
        ),
        ("sheens", format!("{} materials", info.sheened_materials)),
        (
            "diffuse transmission",
            format!(
                "{} materials ({} bounding solids, {} scattering inside)",
                info.translucent_materials, info.translucent_solids, info.scattering_solids
            ),
        ),
        (
            "anisotropy",
            format!("{} materials", info.brushed_materials),
        ),
        (
            "iridescence",
            format!("{} materials", info.iridescent_materials),
        ),
        (
            "specular layers",
            format!("{} materials", info.specular_layers),
        ),
        (
            "murky glass",
            format!("{} materials", info.murky_glass_materials),
        ),
        (
            "inside solids",
            if info.inside_solids.is_empty() {
                "none".to_string()
            } else {
                let pairs: Vec<String> = (info.inside_solids.iter())
                    .map(|n| format!("{} in {}", n.material, n.solid))
                    .collect();
                pairs.join(", ")
            },
        ),
        (
            "atmosphere",
            match &info.atmosphere {
                None => "none".to_string(),
                Some(air) => {
                    let rgb = |[r, g, b]: [f32; 3]| format!("({r:.4}, {g:.4}, {b:.4})");
                    format!(
                        "absorption {}, scattering {} per unit length, g {}",
                        rgb(air.absorption),
                        rgb(air.scattering),
                        air.anisotropy
                    )
                }
            },
        ),
        ("textures", info.textures.to_string()),
        ("cameras", info.cameras.to_string()),
        ("animations", animations_line(&info.animations)),
        ("material variants", variants_line(&info.variants)),
        ("emissive triangles", info.emissive_triangles.to_string()),
        (
            "punctual lights",
            format!(
                "{} point, {} spot, {} directional",
                info.punctual_lights.point,
                info.punctual_lights.spot,
                info.punctual_lights.directional
            ),
        ),
        (
            "light power",
            format!("{:.4} (rgb {:?})", info.light_power, info.light_power_rgb),
        ),
        (
            "bounds",
            format!("{:?} .. {:?}", info.bounds.min, info.bounds.max),
        ),
        (
            "bvh nodes",
            format!("{} ({} leaves)", info.bvh.nodes, info.bvh.leaves),
        ),
        ("bvh depth", info.bvh.depth.to_string()),
        ("bvh SAH cost", format!("{:.2}", info.bvh.sah_cost)),
        (
            "bvh build",
            format!(
                "{:.1} ms (leaves ≤ {})",
                info.bvh.build_ms, info.bvh.max_leaf_size
            ),
        ),
        ("leaf sizes", histogram(&info.bvh.leaf_size_histogram)),
        (
            "split triangles",
            format!(
                "{} packed for {} triangles (budget {} %)",
                info.bvh.packed_triangles, info.triangles, info.bvh.split_percent
            ),
        ),
        (
            "TBVH memory",
            bytes(info.memory.tbvh_bytes, info.memory.tbvh_bytes_per_triangle),
        ),
        (
            "MTBVH memory",
            bytes(
                info.memory.mtbvh_bytes,
                info.memory.mtbvh_bytes_per_triangle,
            ),
        ),
        (
            "MTBVH / TBVH",
            format!("{:.3}×", info.memory.mtbvh_over_tbvh),
        ),
        (
            "GPU threaded layout",
            bytes(
                info.memory.gpu_threaded_bytes,
                info.memory.gpu_threaded_bytes_per_triangle,
            ),
        ),
        ("compact MTBVH", compact_row(info, bytes)),
        ("four-wide MTBVH", wide_row(info, bytes)),
    ];
    for (name, value) in rows {
        println!("{name:<20} {value}");
    }
    for warning in &info.warnings {
        println!("{:<20} {warning}", "warning");
    }
}

/// The compact MTBVH's memory, its ratios and far records, or why it could not be made.
fn compact_row(info: &Info, bytes: impl Fn(usize, f64) -> String) -> String {
    let m = &info.memory;
    match (
        m.mtbvh_compact_bytes,
        m.mtbvh_compact_bytes_per_triangle,
        m.mtbvh_compact_over_tbvh,
        m.mtbvh_compact_over_mtbvh,
    ) {
        (Some(total), Some(per), Some(over_tbvh), Some(over_mtbvh)) => format!(
            "{}, {over_tbvh:.3}× TBVH, {over_mtbvh:.3}× MTBVH, {} far records, made in {:.1} ms",
            bytes(total, per),
            m.mtbvh_compact_far_records.unwrap_or(0),
            info.bvh.compact_ms.unwrap_or(0.0)
        ),
        _ => format!(
            "n/a ({})",
            m.mtbvh_compact_error.as_deref().unwrap_or("not made")
        ),
    }
}

/// The four-wide MTBVH's memory and nodes, or why it could not be made.
fn wide_row(info: &Info, bytes: impl Fn(usize, f64) -> String) -> String {
    let m = &info.memory;
    match (m.mtbvh4_bytes, m.mtbvh4_bytes_per_triangle, m.mtbvh4_nodes) {
        (Some(total), Some(per), Some(nodes)) => format!(
            "{}, {nodes} nodes, SAH cost {:.2}, made in {:.1} ms",
            bytes(total, per),
            m.mtbvh4_sah_cost.unwrap_or(0.0),
            m.mtbvh4_ms.unwrap_or(0.0)
        ),
        _ => format!("n/a ({})", m.mtbvh4_error.as_deref().unwrap_or("not made")),
    }
}

/// "1:532 2:1200 …", sizes with no leaves left out.
fn histogram(counts: &[usize]) -> String {
    let parts: Vec<String> = counts
        .iter()
        .enumerate()
        .filter(|&(_, &n)| n > 0)
        .map(|(size, n)| format!("{size}:{n}"))
        .collect();
    parts.join(" ")
}
