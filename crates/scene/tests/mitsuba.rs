//! Mitsuba scene files (`scene::mitsuba`): what the shipped one holds, both versions'
//! spellings, shapes from OBJ and PLY files, emitters and sensors, and bad files refused in
//! one line naming where.

use std::path::Path;

use glam::Vec3;
use scene::{PunctualKind, Scene, Surface};

use crate::files_support::{mangled, refusal, shipped};

/// Writes `body` inside `<scene>` to `scene.xml` in `dir` and loads it.
fn load_in(dir: &Path, body: &str) -> Result<Scene, scene::SceneError> {
    let path = dir.join("scene.xml");
    std::fs::write(
        &path,
        format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n"),
    )
    .unwrap();
    scene::load(&path)
}

fn load(body: &str) -> Result<Scene, scene::SceneError> {
    load_in(tempfile::tempdir().unwrap().path(), body)
}

/// An emitting rectangle, so that a scene has a light and a triangle.
const LAMP: &str = r#"<shape type="rectangle"><emitter type="area">
    <rgb name="radiance" value="1, 2, 3"/></emitter></shape>"#;

fn error(body: &str) -> String {
    refusal(load(body), body)
}

#[test]
fn the_shipped_cornell_box_loads_as_written() {
    let scene = scene::load(&shipped("mitsuba/cornell-box.xml")).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let surfaces: Vec<&Surface> = scene.materials.iter().map(|m| &m.surface).collect();
    assert!(surfaces.contains(&&Surface::Dielectric {
        ior: 1.5046 / 1.000277,
        thin_walled: false
    }));
    assert!(surfaces.contains(&&Surface::RoughConductor { alpha: 0.1 }));
    assert!(
        surfaces
            .iter()
            .any(|s| matches!(s, Surface::Plastic { ior, .. } if *ior == 1.5 / 1.000277))
    );
    // The light: 0.5 × 0.4 m of radiance (17, 12, 4), facing down.
    assert_eq!(scene.lights.triangles.len(), 2);
    let area: f32 = scene.lights.triangles.iter().map(|t| t.area).sum();
    assert!((area - 0.2).abs() < 1e-5, "{area}");
    let camera = scene.camera(None).unwrap();
    assert!(camera.eye.abs_diff_eq(Vec3::new(0.0, 1.0, 3.8), 1e-5));
    assert!(camera.forward.abs_diff_eq(Vec3::NEG_Z, 1e-6));
    assert!(camera.up.abs_diff_eq(Vec3::Y, 1e-6));
    // 40° across a square film.
    assert!(
        (camera.yfov.to_degrees() - 40.0).abs() < 1e-3,
        "{}",
        camera.yfov.to_degrees()
    );
    assert_eq!(camera.aspect_ratio, Some(1.0));
    let bounds = scene.bounds();
    assert!(bounds.min.abs_diff_eq(Vec3::new(-1.0, 0.0, -1.0), 1e-5));
    assert!(bounds.max.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5));
}

/// Mitsuba 0.6's names (`toWorld`, `intIOR`, `fovAxis`) read as 3's, `$` defaults fill in
/// values, and a referenced BSDF is one material however many shapes use it.
#[test]
fn both_versions_spellings_and_defaults_are_read() {
    let scene = load(&format!(
        r#"<default name="ior" value="1.33"/>
        <bsdf type="dielectric" id="water"><float name="intIOR" value="$ior"/></bsdf>
        <shape type="cube"><ref id="water"/></shape>
        <shape type="cube"><transform name="toWorld"><translate x="3"/></transform>
            <ref name="bsdf" id="water"/></shape>
        <sensor type="perspective"><float name="fov" value="30"/><string name="fovAxis" value="y"/>
            <transform name="toWorld"><lookat origin="0,0,10" target="0,0,0" up="0,1,0"/></transform>
            <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film>
        </sensor>
        {LAMP}"#
    ))
    .expect("loads");
    let glass: Vec<_> = (scene.materials.iter())
        .filter(|m| matches!(m.surface, Surface::Dielectric { .. }))
        .collect();
    assert_eq!(glass.len(), 1, "one material for both cubes");
    assert_eq!(
        glass[0].surface,
        Surface::Dielectric {
            ior: 1.33 / 1.000277,
            thin_walled: false
        }
    );
    assert_eq!(scene.triangles.len(), 2 * 12 + 2);
    let camera = scene.camera(None).unwrap();
    assert!((camera.yfov.to_degrees() - 30.0).abs() < 1e-4);
    assert_eq!(camera.aspect_ratio, Some(2.0));
}

/// A horizontal field of view (Mitsuba's default axis) on a wide film is a narrower
/// vertical one; a focal length is on 35 mm film.
#[test]
fn fields_of_view_follow_their_axis() {
    let sensor = |fov: &str| {
        format!(
            r#"<sensor type="perspective">{fov}
            <film type="hdrfilm"><integer name="width" value="300"/><integer name="height" value="150"/></film>
            </sensor>{LAMP}"#
        )
    };
    let yfov = |body: &str| load(body).unwrap().camera(None).unwrap().yfov;
    let expected = 2.0 * (45f32.to_radians().tan() / 2.0).atan();
    assert!((yfov(&sensor(r#"<float name="fov" value="90"/>"#)) - expected).abs() < 1e-5);
    let expected = 2.0 * (18.0f32 / 50.0 / 2.0).atan();
    assert!(
        (yfov(&sensor(r#"<string name="focal_length" value="50mm"/>"#)) - expected).abs() < 1e-5
    );
}

#[test]
fn obj_and_ply_shapes_are_placed_with_their_bsdf() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    std::fs::write(dir.path().join("tri.ply"), ply).unwrap();
    let scene = load_in(
        dir.path(),
        &format!(
            r#"<shape type="obj"><string name="filename" value="tri.obj"/>
                <transform name="to_world"><translate z="5"/></transform>
                <bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
            <shape type="ply"><string name="filename" value="tri.ply"/>
                <boolean name="flip_normals" value="true"/>
                <bsdf type="plastic"/></shape>
            {LAMP}"#
        ),
    )
    .expect("loads");
    let gold = &scene.materials[scene.triangles[0].material as usize];
    assert_eq!(gold.surface, Surface::Mirror);
    assert!(
        gold.base_color
            .abs_diff_eq(Vec3::new(1.0, 0.782, 0.344), 1e-6)
    );
    assert!(
        scene.triangles[0]
            .vertices
            .iter()
            .all(|v| v.position.z == 5.0)
    );
    let flipped = &scene.triangles[1];
    assert!(
        flipped
            .vertices
            .iter()
            .all(|v| v.normal.abs_diff_eq(Vec3::NEG_Z, 1e-6))
    );
    let plastic = &scene.materials[flipped.material as usize];
    assert!(matches!(plastic.surface, Surface::Plastic { .. }));
}

#[test]
fn emitters_become_lights() {
    let scene = load(
        r#"<emitter type="point"><point name="position" x="1" y="2" z="3"/>
            <rgb name="intensity" value="5"/></emitter>
        <emitter type="spot"><transform name="to_world">
            <lookat origin="0,4,0" target="0,0,0" up="0,0,1"/></transform>
            <float name="cutoff_angle" value="30"/></emitter>
        <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/>
            <spectrum name="irradiance" value="2"/></emitter>
        <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
        <shape type="sphere"/>"#,
    )
    .expect("loads");
    let kinds: Vec<PunctualKind> = scene.lights.punctual.iter().map(|p| p.light.kind).collect();
    assert!(matches!(
        kinds[..],
        [
            PunctualKind::Point,
            PunctualKind::Spot { .. },
            PunctualKind::Directional
        ]
    ));
    let point = scene.lights.punctual[0].light;
    assert_eq!(
        (point.position, point.intensity),
        (Vec3::new(1.0, 2.0, 3.0), Vec3::splat(5.0))
    );
    let hard_spot = r#"<emitter type="spot"><float name="cutoff_angle" value="30"/>
        <float name="beam_width" value="30"/></emitter><shape type="cube"/>"#;
    assert!(load(hard_spot).is_ok(), "a hard-edged spot loads");
    let spot = scene.lights.punctual[1].light;
    assert!(spot.direction.abs_diff_eq(Vec3::NEG_Y, 1e-6));
    let PunctualKind::Spot {
        cos_outer,
        cos_inner,
        falloff,
    } = spot.kind
    else {
        unreachable!()
    };
    // Mitsuba's spot falls off linearly in the angle.
    assert_eq!(falloff, scene::SpotFalloff::LinearAngle);
    assert!((cos_outer - 30f32.to_radians().cos()).abs() < 1e-6);
    assert!((cos_inner - 22.5f32.to_radians().cos()).abs() < 1e-6);
    assert_eq!(
        scene.lights.sky.as_ref().map(|s| s.radiance),
        Some(Vec3::splat(0.5))
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn bad_files_are_one_line_errors_naming_where() {
    let cases = [
        ("<shape type=\"cube\">", "not well-formed XML"),
        (
            r#"<shape type="cube"><ref id="nowhere"/></shape>"#,
            "no element has id \"nowhere\"",
        ),
        (
            r#"<shape type="obj"><string name="filename" value="missing.obj"/></shape>"#,
            "missing.obj",
        ),
        (
            "<shape type=\"cube\">\n<transform name=\"to_world\"><scale value=\"inf\"/></transform></shape>",
            "line 3",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="-1"/></shape>"#,
            "not positive",
        ),
        (
            r#"<shape type="cube"><bsdf type="dielectric"><string name="int_ior" value="unobtainium"/></bsdf></shape>"#,
            "unknown index",
        ),
        (
            r#"<sensor type="perspective"><float name="fov" value="180"/></sensor>"#,
            "fov 180",
        ),
        (
            r#"<shape type="cube"><transform name="to_world"><rotate angle="9"/></transform></shape>"#,
            "axis is zero",
        ),
        (
            r#"<bsdf type="twosided" id="a"><ref id="a"/></bsdf><shape type="cube"><ref id="a"/></shape>"#,
            "reference cycle",
        ),
        (
            r#"<emitter type="spot"><float name="cutoff_angle" value="120"/></emitter>"#,
            "cutoff_angle 120",
        ),
        (
            r#"<shape type="cube"><bsdf type="dielectric"/><medium type="homogeneous" name="interior"><float name="albedo" value="1.5"/></medium></shape>"#,
            "must be ≥ 0",
        ),
        (
            r#"<shape type="cube"><bsdf type="dielectric"/><medium type="homogeneous" name="interior"><phase type="hg"><float name="g" value="1"/></phase></medium></shape>"#,
            "g 1 is not in",
        ),
        (
            r#"<shape type="cube"><bsdf type="dielectric"/><medium type="homogeneous" name="interior"><volume name="albedo" type="gridvolume"/></medium></shape>"#,
            "volume grid",
        ),
        (
            r#"<shape type="cube"><bsdf type="dielectric"/><ref name="interior" id="none"/></shape>"#,
            "no element has id",
        ),
    ];
    for (body, why) in cases {
        let message = error(body);
        assert!(message.contains(why), "{why}: {message}");
        assert!(
            message.contains("scene.xml") || message.contains("missing.obj"),
            "{message}"
        );
    }
    let message =
        error(r#"<emitter type="envmap"><string name="filename" value="no.hdr"/></emitter>"#);
    assert!(message.contains("no.hdr"), "{message}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other.xml");
    std::fs::write(&path, "<notascene/>").unwrap();
    assert!(
        scene::load(&path)
            .unwrap_err()
            .to_string()
            .contains("not <scene>")
    );
}

#[test]
fn unsupported_parts_are_warned_about_and_skipped() {
    let scene = load(&format!(
        r#"<shape type="curve"/>
        <shape type="cube"><bsdf type="hair"/></shape>
        <medium type="homogeneous" id="fog"/>
        {LAMP}"#
    ))
    .expect("loads");
    assert_eq!(scene.warnings.len(), 3, "{:?}", scene.warnings);
    assert_eq!(scene.triangles.len(), 12 + 2);
}

/// A `blendbsdf` of two BSDFs of their own colours is a blend of whole materials, the second
/// drawn with probability `weight`; two Lambertian ones are read as one of their mean colour.
#[test]
fn blend_bsdfs_mix_whole_materials() {
    let scene = load(&format!(
        r#"<shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="0.3"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf>
            <bsdf type="conductor"><rgb name="specular_reflectance" value="0.2, 0.9, 0.2"/></bsdf>
        </bsdf></shape>
        <shape type="cube"><bsdf type="blendbsdf"><float name="weight" value="0.25"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.4"/></bsdf>
        </bsdf></shape>{LAMP}"#
    ))
    .expect("loads");
    let first = &scene.materials[scene.triangles[0].material as usize];
    // The metal (0.3) first, the Lambertian member last, each of its own colour.
    assert_eq!(first.surface, Surface::Mirror);
    assert_eq!(first.base_color, Vec3::new(0.2, 0.9, 0.2));
    let blend = first.blend.expect("a blend");
    assert!((blend.weight - 0.3).abs() < 1e-6);
    let diffuse = &scene.materials[blend.other as usize];
    assert_eq!(
        (diffuse.surface, diffuse.base_color),
        (Surface::Diffuse, Vec3::new(0.8, 0.1, 0.1))
    );
    let second = &scene.materials[scene.triangles[12].material as usize];
    assert_eq!(second.blend, None);
    assert!(second.base_color.abs_diff_eq(Vec3::splat(0.7), 1e-6));
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
}

/// Conductors' Fresnel rise (`Material::metal_edge`): a named metal's rises to white, one
/// tinted by `specular_reflectance` to the tint, Mitsuba's `"none"` (its default) not at all.
#[test]
fn conductors_rise_towards_their_tint_at_grazing_angles() {
    let scene = load(&format!(
        r#"<shape type="cube"><bsdf type="conductor"><string name="material" value="Cu"/></bsdf></shape>
        <shape type="cube"><bsdf type="roughconductor"><string name="material" value="Cu"/>
            <rgb name="specular_reflectance" value="0.5, 0.8, 1"/></bsdf></shape>
        <shape type="cube"><bsdf type="conductor">
            <rgb name="specular_reflectance" value="0.9, 0.7, 0.4"/></bsdf></shape>{LAMP}"#
    ))
    .expect("loads");
    let metal = |shape: usize| &scene.materials[scene.triangles[12 * shape].material as usize];
    let copper = scene::material::metal_f0("Cu").unwrap();
    assert_eq!(
        (metal(0).base_color, metal(0).metal_edge),
        (copper, Vec3::ONE)
    );
    // Tinted: F0 = tint·copper, F90 = tint, so F0 + edge·(1 − F0) = tint.
    let tint = Vec3::new(0.5, 0.8, 1.0);
    let tinted = metal(1);
    assert!(tinted.base_color.abs_diff_eq(tint * copper, 1e-6));
    let f90 = tinted.base_color + tinted.metal_edge * (Vec3::ONE - tinted.base_color);
    assert!(f90.abs_diff_eq(tint, 1e-5), "{f90}");
    assert_eq!(
        (metal(2).base_color, metal(2).metal_edge),
        (Vec3::new(0.9, 0.7, 0.4), Vec3::ZERO)
    );
}

/// Homogeneous interior media fill solids: glass keeps its surface and takes the medium's
/// absorption and scattering (Mitsuba 3's `sigma_t` × `scale` and `albedo`, 0.6's `sigmaA` and
/// `sigmaS`) and its phase's `g`; a `null` boundary becomes glass of index 1. An exterior
/// medium that fills a shape is what kousen finds around the shape anyway: not warned about.
/// A light's medium that fills nothing (and is not the sensor's), media of other surfaces and
/// media nothing names are warned about.
#[test]
fn interior_media_fill_solids() {
    let scene = load(&format!(
        r#"<medium type="homogeneous" id="smoke">
            <float name="sigmaA" value="0.5"/><rgb name="sigmaS" value="1, 2, 3"/>
        </medium>
        <medium type="homogeneous" id="unused"/>
        <medium type="homogeneous" id="haze"/>
        <emitter type="point"><ref name="medium" id="haze"/></emitter>
        <shape type="sphere"><bsdf type="dielectric"/>
            <medium type="homogeneous" name="interior">
                <rgb name="sigma_t" value="1, 2, 4"/><rgb name="albedo" value="0.5, 0.25, 1"/>
                <float name="scale" value="2"/><phase type="hg"><float name="g" value="0.6"/></phase>
            </medium>
            <ref name="exterior" id="smoke"/>
        </shape>
        <shape type="cube"><bsdf type="null"/><ref name="interior" id="smoke"/></shape>
        <shape type="cube"><bsdf type="diffuse"/><ref name="interior" id="smoke"/></shape>
        {LAMP}"#
    ))
    .expect("loads");
    let sphere_triangles = scene.triangles.len() - 2 * 12 - 2;
    let glass = &scene.materials[scene.triangles[0].material as usize];
    assert!(matches!(
        glass.surface,
        Surface::Dielectric {
            thin_walled: false,
            ..
        }
    ));
    // σt = (2, 4, 8), albedo (0.5, 0.25, 1): scattering (1, 1, 8), absorption (1, 3, 0).
    assert_eq!(glass.scattering, Vec3::new(1.0, 1.0, 8.0));
    assert_eq!(glass.absorption, Vec3::new(1.0, 3.0, 0.0));
    assert_eq!(glass.scatter_anisotropy, 0.6);
    let fog = &scene.materials[scene.triangles[sphere_triangles].material as usize];
    assert_eq!(
        fog.surface,
        Surface::Dielectric {
            ior: 1.0,
            thin_walled: false
        }
    );
    assert_eq!((fog.alpha, fog.base_color), (1.0, Vec3::ONE));
    assert_eq!(fog.absorption, Vec3::splat(0.5));
    assert_eq!(fog.scattering, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(fog.scatter_anisotropy, 0.0);
    let wall = &scene.materials[scene.triangles[sphere_triangles + 12].material as usize];
    assert_eq!(
        (wall.surface, wall.absorption),
        (Surface::Diffuse, Vec3::ZERO)
    );
    let warned = |what: &str| scene.warnings.iter().filter(|w| w.contains(what)).count();
    assert_eq!(
        warned("medium \"haze\" fills no shape"),
        1,
        "{:?}",
        scene.warnings
    );
    assert_eq!(warned("inside solid glass or a null BSDF only"), 1);
    assert_eq!(warned("no solid is filled with"), 1);
    assert_eq!(scene.warnings.len(), 3, "{:?}", scene.warnings);
    assert_eq!(scene.atmosphere, None);
}

/// The sensor's medium, where no shape bounds it, fills all space outside the solids: the
/// scene's atmosphere, a material of glass of index 1 holding the medium that no triangle
/// uses. Shapes naming it as their exterior are not warned about. Reaching to infinity, it
/// keeps the sky's and the directional lights' light from the scene in every channel where it
/// has extinction (warned). Where a shape is filled with the sensor's medium, the camera's
/// place decides (no atmosphere).
#[test]
fn a_sensor_medium_no_shape_bounds_is_the_atmosphere() {
    let fog = r#"<medium type="homogeneous" id="fog">
            <rgb name="sigma_t" value="0.5, 0.5, 0"/><rgb name="albedo" value="0.8, 0.8, 0.8"/>
            <phase type="hg"><float name="g" value="0.3"/></phase>
        </medium>
        <sensor type="perspective"><ref name="medium" id="fog"/></sensor>"#;
    let scene = load(&format!(
        r#"{fog}
        <shape type="sphere"><bsdf type="dielectric"/><ref name="exterior" id="fog"/></shape>
        <emitter type="constant"><rgb name="radiance" value="1, 2, 3"/></emitter>
        <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/>
            <rgb name="irradiance" value="4, 5, 6"/></emitter>
        {LAMP}"#
    ))
    .expect("loads");
    let atmosphere = scene.atmosphere.expect("an atmosphere");
    assert!(scene.triangles.iter().all(|t| t.material != atmosphere));
    let air = &scene.materials[atmosphere as usize];
    assert_eq!(
        air.surface,
        Surface::Dielectric {
            ior: 1.0,
            thin_walled: false
        }
    );
    assert!(air.has_murky_glass());
    assert!(air.absorption.abs_diff_eq(Vec3::new(0.1, 0.1, 0.0), 1e-6));
    assert!(air.scattering.abs_diff_eq(Vec3::new(0.4, 0.4, 0.0), 1e-6));
    assert_eq!(air.scatter_anisotropy, 0.3);
    // Clear in blue alone: only blue light comes from infinitely far away.
    assert_eq!(scene.far_light_mask(), Vec3::Z);
    let sky = scene.lights.sky.as_ref().expect("a sky");
    assert_eq!(sky.radiance, Vec3::new(0.0, 0.0, 3.0));
    assert_eq!((sky.power.x, sky.power.y), (0.0, 0.0));
    let sun = &scene.lights.punctual[0];
    assert_eq!(sun.light.intensity, Vec3::new(0.0, 0.0, 6.0));
    assert_eq!((sun.power.x, sun.power.y), (0.0, 0.0));
    let lamp = scene.lights.triangles.iter().map(|t| t.power).sum::<Vec3>();
    let total = lamp + sky.power + sun.power;
    assert!(
        scene
            .lights
            .total_power
            .abs_diff_eq(total, 1e-3 * total.max_element())
    );
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(scene.warnings[0].contains("hides the sky"));

    let bounded = load(&format!(
        r#"{fog}
        <shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
        {LAMP}"#
    ))
    .expect("loads");
    assert_eq!(bounded.atmosphere, None);
    assert!(bounded.warnings.is_empty(), "{:?}", bounded.warnings);
}

/// The shipped foggy box: its sensor's medium is the atmosphere, the spot and the panel light
/// it, and nothing is warned about.
#[test]
fn the_shipped_foggy_box_loads_as_written() {
    let scene = scene::load(&shipped("mitsuba/cornell-fog.xml")).expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let air = &scene.materials[scene.atmosphere.expect("an atmosphere") as usize];
    assert!(air.absorption.abs_diff_eq(Vec3::splat(0.08), 1e-6));
    assert!(air.scattering.abs_diff_eq(Vec3::splat(0.32), 1e-6));
    assert!(matches!(
        scene.lights.punctual[0].light.kind,
        PunctualKind::Spot { .. }
    ));
    assert_eq!(scene.lights.triangles.len(), 2);
}

/// A `cylinder` is an open tube from `p0` to `p1`, facing out.
#[test]
fn cylinders_run_from_p0_to_p1() {
    let scene = load(&format!(
        r#"<shape type="cylinder"><point name="p0" x="1" y="0" z="0"/>
        <point name="p1" x="1" y="3" z="0"/><float name="radius" value="0.5"/></shape>{LAMP}"#
    ))
    .expect("loads");
    let tube = &scene.triangles[..scene.triangles.len() - 2];
    let area: f32 = tube
        .iter()
        .map(|t| t.geometric_normal_unnormalized().length() / 2.0)
        .sum();
    let exact = std::f32::consts::TAU * 0.5 * 3.0;
    assert!((area / exact - 1.0).abs() < 1e-3, "{area} against {exact}");
    for v in tube.iter().flat_map(|t| t.vertices) {
        let radial = v.position - Vec3::new(1.0, v.position.y, 0.0);
        assert!((radial.length() - 0.5).abs() < 1e-5 && (0.0..=3.0).contains(&v.position.y));
        assert!(v.normal.dot(radial) > 0.0, "faces out");
    }
}

/// A `mask` with a bitmap opacity cuts its BSDF out where the opacity is below ½: the
/// opacity becomes the alpha of the base colour's texture (white where it has none).
#[test]
fn a_mask_s_opacity_bitmap_becomes_an_alpha_cut_out() {
    let dir = tempfile::tempdir().unwrap();
    image::GrayImage::from_raw(2, 1, vec![0, 255])
        .unwrap()
        .save(dir.path().join("leaf.png"))
        .unwrap();
    let scene = load_in(
        dir.path(),
        &format!(
            r#"<shape type="rectangle"><bsdf type="mask">
                <texture type="bitmap" name="opacity"><string name="filename" value="leaf.png"/></texture>
                <bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.6, 0.1"/></bsdf>
            </bsdf></shape>{LAMP}"#
        ),
    )
    .expect("loads");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let leaf = &scene.materials[scene.triangles[0].material as usize];
    assert_eq!(leaf.alpha_mode, scene::AlphaMode::Mask { cutoff: 0.5 });
    assert_eq!(leaf.base_color, Vec3::new(0.2, 0.6, 0.1));
    let texture = &scene.textures[leaf.base_color_texture.expect("a cut-out texture") as usize];
    assert_eq!(texture.texel_linear(0, 0).w, 0.0);
    assert_eq!(texture.texel_linear(1, 0), glam::Vec4::ONE);
}

/// Mitsuba's own `.serialized` meshes, picked by `shape_index`, from a fixture Mitsuba 3's
/// loader reads back as written (`scripts/make_serialized_fixture.py`).
#[test]
fn serialized_meshes_are_read_by_index() {
    let dir = tempfile::tempdir().unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/two-meshes.serialized");
    std::fs::copy(data, dir.path().join("two.serialized")).unwrap();
    let shape = |index: u32| {
        format!(
            r#"<shape type="serialized"><string name="filename" value="two.serialized"/>
            <integer name="shape_index" value="{index}"/></shape>"#
        )
    };
    let scene = load_in(dir.path(), &format!("{}{}{LAMP}", shape(0), shape(1))).expect("loads");
    assert_eq!(scene.triangles.len(), 1 + 2 + 2);
    let [a, b, c] = scene.triangles[0].vertices.map(|v| v.position);
    assert_eq!((a, b, c), (Vec3::ZERO, Vec3::X, Vec3::Y));
    let square: Vec<Vec3> = (scene.triangles[1..3].iter())
        .flat_map(|t| t.vertices.map(|v| v.position))
        .collect();
    assert!(square.contains(&Vec3::new(2.0, 2.0, 2.0)));
    assert!(square.iter().all(|p| p.z == 2.0));
    let message = load_in(dir.path(), &shape(2)).unwrap_err().to_string();
    assert!(message.contains("holds 2 meshes"), "{message}");
}

/// A `shapegroup` is drawn only where `instance`s place it, each a copy moved by the
/// instance's `to_world` after the group's own shapes' transforms.
#[test]
fn instances_place_copies_of_their_shape_group() {
    let scene = load(&format!(
        r#"<shape type="shapegroup" id="pair">
            <shape type="rectangle"><transform name="to_world"><translate z="1"/></transform></shape>
            <shape type="cube"/>
        </shape>
        <shape type="instance"><ref id="pair"/>
            <transform name="to_world"><translate x="10"/></transform></shape>
        <shape type="instance"><ref id="pair"/>
            <transform name="to_world"><translate x="-10"/></transform></shape>
        {LAMP}"#
    ))
    .expect("loads");
    assert_eq!(scene.triangles.len(), 2 * (2 + 12) + 2);
    let xs: Vec<f32> = (scene.triangles.iter())
        .map(|t| t.vertices[0].position.x.round())
        .collect();
    assert_eq!(xs.iter().filter(|&&x| x >= 9.0).count(), 14);
    assert_eq!(xs.iter().filter(|&&x| x <= -9.0).count(), 14);
    let moved = scene.triangles[0].vertices[0].position;
    assert_eq!(moved.z, 1.0, "the group's own transform first");
    let message = error(r#"<shape type="instance"><ref id="nowhere"/></shape>"#);
    assert!(message.contains("no shapegroup has id"), "{message}");
}

/// Mitsuba 3's principled BSDF as glTF's metallic-roughness material: one surface where only
/// one part has a share, else a blend of metal, glass and plastic by their shares.
#[test]
fn principled_bsdfs_blend_their_parts() {
    let principled = |params: &str| {
        let scene = load(&format!(
            r#"<shape type="cube"><bsdf type="principled">
                <rgb name="base_color" value="0.8, 0.6, 0.2"/>{params}</bsdf></shape>{LAMP}"#
        ))
        .expect("loads");
        let root = scene.triangles[0].material;
        let members: Vec<(Surface, Option<f32>)> = scene::blend_members(&scene.materials, root)
            .map(|id| {
                let m = &scene.materials[id as usize];
                (m.surface, m.blend.map(|b| b.weight))
            })
            .collect();
        members
    };
    let metal =
        principled(r#"<float name="metallic" value="1"/><float name="roughness" value="0"/>"#);
    assert_eq!(metal, [(Surface::Mirror, None)]);
    let half = principled(
        r#"<float name="metallic" value="0.25"/><float name="spec_trans" value="0.5"/>
        <float name="roughness" value="0.2"/>"#,
    );
    let surfaces: Vec<Surface> = half.iter().map(|(s, _)| *s).collect();
    assert!(
        matches!(
            surfaces[..],
            [
                Surface::RoughConductor { .. },
                Surface::RoughDielectric { .. },
                Surface::Plastic { .. }
            ]
        ),
        "{surfaces:?}"
    );
    // Metal 0.25, then glass 0.375 of 0.75 left (a half), then plastic.
    assert!((half[0].1.unwrap() - 0.25).abs() < 1e-6, "{half:?}");
    assert!((half[1].1.unwrap() - 0.5).abs() < 1e-6, "{half:?}");
}

/// A bitmap's `to_uv` (a tiled floor) maps the texture coordinates of every shape wearing it,
/// also through a shared, referenced BSDF.
#[test]
fn a_bitmap_s_to_uv_maps_texture_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    image::RgbImage::from_pixel(2, 2, image::Rgb([200, 100, 50]))
        .save(dir.path().join("tile.png"))
        .unwrap();
    let scene = load_in(
        dir.path(),
        &format!(
            r#"<bsdf type="diffuse" id="tiles"><texture type="bitmap" name="reflectance">
                <string name="filename" value="tile.png"/>
                <transform name="to_uv"><scale x="3" y="2"/><translate x="0.5"/></transform>
            </texture></bsdf>
            <shape type="rectangle"><ref id="tiles"/></shape>
            <shape type="rectangle"><ref id="tiles"/>
                <transform name="to_world"><translate z="4"/></transform></shape>
            {LAMP}"#
        ),
    )
    .expect("loads");
    for triangle in &scene.triangles[..4] {
        for v in &triangle.vertices {
            // The rectangle's corner (x, y) has uv ((x + 1) / 2, (y + 1) / 2).
            let uv = glam::Vec2::new((v.position.x + 1.0) / 2.0, (v.position.y + 1.0) / 2.0);
            let expected = glam::Vec2::new(3.0 * uv.x + 0.5, 2.0 * uv.y);
            assert!(
                v.uv.abs_diff_eq(expected, 1e-6),
                "{} against {expected}",
                v.uv
            );
        }
    }
}

/// The shipped file cut short and with bytes changed at random (a fixed xorshift sequence):
/// every one loads or is refused, none panics.
#[test]
fn mangled_files_never_panic() {
    let original = std::fs::read(shipped("mitsuba/cornell-box.xml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mangled.xml");
    for bytes in mangled(&original, 200, b"<>\"/=$ -.e9x0") {
        std::fs::write(&path, &bytes).unwrap();
        let _ = scene::load(&path);
    }
}
