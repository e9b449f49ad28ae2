//! Shadow rays from a coarse smooth-shaded sphere start on the smooth surface of its vertex
//! normals (`render::shadow_terminator`, `SurfaceHit::shadow_origin`): wherever both the
//! shading and the geometric normal face a distant light, nothing of the sphere itself blocks
//! the light, though from the flat facets the neighbouring facets do (the staircase terminator),
//! and the renderer's light samples (`cpu::kernels::direct_light`) light those points.

use glam::Vec3;
use render::buffers::{RAY_T_MAX, SppmParams};
use render::medium::NO_MEDIUM;
use scene::{Material, PunctualKind, PunctualLight, SceneBuilder, Triangle, Vertex};

/// A unit UV sphere of 8 segments × 4 rings at the origin, exact normals, facing outwards.
fn coarse_sphere() -> scene::Scene {
    let (segments, rings) = (8u32, 4u32);
    let mut builder = SceneBuilder::new(std::path::Path::new("coarse sphere"));
    let material = builder.add_material(Material::default());
    let vertex = |ring: u32, segment: u32| {
        let theta = std::f32::consts::PI * ring as f32 / rings as f32;
        let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
        let d = Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        );
        Vertex {
            position: d,
            normal: d,
            ..Vertex::default()
        }
    };
    let mut add = |mut vertices: [Vertex; 3]| {
        let t = Triangle { vertices, material };
        let centre = vertices.iter().map(|v| v.position).sum::<Vec3>();
        if t.geometric_normal_unnormalized().dot(centre) < 0.0 {
            vertices.swap(1, 2);
        }
        builder
            .add_triangle(Triangle { vertices, material })
            .unwrap();
    };
    for ring in 0..rings {
        for segment in 0..segments {
            let [a, b] = [vertex(ring, segment), vertex(ring, segment + 1)];
            let [c, d] = [vertex(ring + 1, segment), vertex(ring + 1, segment + 1)];
            if ring > 0 {
                add([a, b, d]);
            }
            if ring + 1 < rings {
                add([a, d, c]);
            }
        }
    }
    // A sun along the test's light direction.
    builder
        .add_punctual_light(PunctualLight {
            kind: PunctualKind::Directional,
            position: Vec3::ZERO,
            direction: -towards_light(),
            intensity: Vec3::ONE,
        })
        .unwrap();
    builder.finish().unwrap()
}

fn towards_light() -> Vec3 {
    Vec3::new(1.0, 0.3, 0.2).normalize()
}

#[test]
fn shadow_rays_from_the_smooth_surface_clear_the_coarse_sphere() {
    let scene = coarse_sphere();
    let bvh = bvh::PackedBvh::build(&scene.triangles, &bvh::BuildOptions::default());
    let data = cpu::SceneData::new(&scene, bvh);
    let params = SppmParams {
        epsilon: 1e-4,
        ..SppmParams::default()
    };
    let towards_light = towards_light();
    let (mut lit, mut blocked_from_facet, mut blocked_from_smooth) = (0, 0, 0);
    let mut dark = 0;
    // Camera rays along −z, across the light: the terminator runs through the view.
    let n = 96;
    for j in 0..n {
        for i in 0..n {
            let x = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
            let y = -1.0 + 2.0 * (j as f32 + 0.5) / n as f32;
            let origin = Vec3::new(x, y, 5.0);
            let direction = Vec3::NEG_Z;
            let Some(hit) = cpu::surface::trace(&data, origin, direction) else {
                continue;
            };
            // Lit by the smooth normal, turned away by the facet: the terminator's staircase.
            let cos_shading = hit.shading.dot(towards_light);
            if !(cos_shading > 0.05 && hit.geometric.dot(towards_light) <= 0.0) {
                continue;
            }
            lit += 1;
            let clear = |from: Vec3| {
                let start = from + params.epsilon * hit.geometric;
                cpu::surface::unoccluded(&data, &params, start, towards_light, RAY_T_MAX)
            };
            blocked_from_facet += usize::from(!clear(hit.position));
            blocked_from_smooth += usize::from(!clear(hit.shadow_origin));
            // The renderer's light sample there: lit, by the smooth normal's cosine.
            let diffuse = cpu::kernels::LitLobes {
                diffuse: Vec3::ONE,
                ..Default::default()
            };
            let light = cpu::kernels::direct_light(
                &data,
                &params,
                &hit,
                hit.shading,
                &diffuse,
                NO_MEDIUM,
                || 0.5,
            );
            dark += usize::from(light.max_element() <= 0.0);
        }
    }
    println!(
        "{lit} lit points: {blocked_from_facet} blocked from the facet, \
         {blocked_from_smooth} from the smooth surface"
    );
    assert!(lit > 200, "{lit} lit points");
    assert!(
        blocked_from_facet * 50 > lit,
        "the setup shows the staircase: {blocked_from_facet} of {lit} blocked from the facets"
    );
    assert_eq!(blocked_from_smooth, 0, "of {lit}");
    assert_eq!(
        dark, 0,
        "light samples found no light at {dark} of {lit} points"
    );
}
