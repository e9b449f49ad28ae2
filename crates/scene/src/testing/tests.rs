//! Checks of the fixtures themselves.

use std::collections::HashMap;

use super::*;

fn centroid(t: &Triangle) -> Vec3 {
    t.positions().iter().sum::<Vec3>() / 3.0
}

fn faces_towards(t: &Triangle, point: Vec3) -> bool {
    t.geometric_normal_unnormalized().dot(point - centroid(t)) > 0.0
}

/// Every edge of a closed mesh is shared by exactly two triangles.
fn is_closed(triangles: &[Triangle]) -> bool {
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut edges: HashMap<_, u32> = HashMap::new();
    for t in triangles {
        let p = t.positions();
        for k in 0..3 {
            let (a, b) = (key(p[k]), key(p[(k + 1) % 3]));
            *edges
                .entry(if a < b { (a, b) } else { (b, a) })
                .or_default() += 1;
        }
    }
    edges.values().all(|&n| n == 2)
}

#[test]
fn cornell_box_faces_into_the_room_and_its_light_down() {
    let scene = cornell_box();
    assert_eq!(scene.triangles.len(), CORNELL_BOX_TRIANGLES);
    assert_eq!(scene.degenerate_dropped, 0);
    let (room, blocks) = scene.triangles.split_at(18);
    let inside = Vec3::new(278.0, 274.4, 279.6);
    assert!(room.iter().all(|t| faces_towards(t, inside)));
    for block in blocks.chunks(10) {
        let centre = block.iter().map(centroid).sum::<Vec3>() / 10.0;
        assert!(block.iter().all(|t| !faces_towards(t, centre)));
    }
    assert_eq!(scene.lights.triangles.len(), 2);
    for light in &scene.lights.triangles {
        let t = &scene.triangles[light.triangle as usize];
        assert!(t.geometric_normal_unnormalized().normalize().y < -0.999);
    }
    let expected_power = CORNELL_LIGHT_RADIANCE * 130.0 * 105.0 * std::f32::consts::PI;
    assert!(
        (scene.lights.total_power - expected_power)
            .abs()
            .max_element()
            < 1.0
    );
    let camera = &scene.cameras[0];
    assert_eq!(
        (camera.eye, camera.forward, camera.up),
        (Vec3::new(278.0, 273.0, -800.0), Vec3::Z, Vec3::Y)
    );
    assert!((camera.yfov.to_degrees() - 39.3077).abs() < 1e-3);
    // Red (x ≈ 556) is on the image's left: the camera's right is −x.
    assert_eq!(camera.right(), Vec3::NEG_X);
}

#[test]
fn cornell_caustics_has_closed_round_spheres() {
    let scene = cornell_caustics();
    assert_eq!(scene.triangles.len(), 18 + 2 * SPHERE_TRIANGLES);
    let (_, spheres) = scene.triangles.split_at(18);
    let (glass, mirror) = spheres.split_at(SPHERE_TRIANGLES);
    for (sphere, centre) in [
        (glass, Vec3::new(180.0, 90.0, 170.0)),
        (mirror, Vec3::new(380.0, 110.0, 370.0)),
    ] {
        assert!(is_closed(sphere));
        assert!(sphere.iter().all(|t| !faces_towards(t, centre)));
        for v in sphere.iter().flat_map(|t| t.vertices) {
            assert!((v.normal - (v.position - centre).normalize()).length() < 1e-5);
        }
    }
    let material = |t: &Triangle| &scene.materials[t.material as usize];
    assert_eq!(
        material(&glass[0]).surface,
        Surface::Dielectric {
            ior: 1.5,
            thin_walled: false
        }
    );
    assert_eq!(material(&mirror[0]).surface, Surface::Mirror);
}

#[test]
fn furnace_sphere_is_closed_and_faces_inwards() {
    let scene = furnace_sphere();
    assert_eq!(scene.triangles.len(), SPHERE_TRIANGLES);
    assert!(is_closed(&scene.triangles));
    assert!(scene.triangles.iter().all(|t| faces_towards(t, Vec3::ZERO)));
    for v in scene.triangles.iter().flat_map(|t| t.vertices) {
        assert!(
            (v.normal + v.position).length() < 1e-5,
            "inward unit normal"
        );
    }
    assert_eq!(scene.lights.triangles.len(), SPHERE_TRIANGLES);
    assert_eq!(FURNACE_RADIANCE, 1.0);
}

#[test]
fn lit_plane_radiance_matches_numerical_integration() {
    let scene = lit_plane();
    assert_eq!(scene.triangles.len(), 4);
    assert!(faces_towards(&scene.triangles[0], Vec3::Y));
    assert!(faces_towards(&scene.triangles[2], Vec3::ZERO));
    // E = Le ∫ cos θ cos θ' / r² dA = Le ∫ h² / r⁴ dA over the light (midpoint rule).
    let n = 2000;
    let (half, h) = (
        LIT_PLANE_LIGHT_HALF_SIZE as f64,
        LIT_PLANE_LIGHT_HEIGHT as f64,
    );
    let cell = 2.0 * half / n as f64;
    for (x, z) in [(0.0, 0.0), (0.4, -0.3)] {
        let mut irradiance = 0.0;
        for i in 0..n {
            for j in 0..n {
                let dx = -half + (i as f64 + 0.5) * cell - x;
                let dz = -half + (j as f64 + 0.5) * cell - z;
                let r2 = dx * dx + dz * dz + h * h;
                irradiance += h * h / (r2 * r2) * cell * cell;
            }
        }
        let expected =
            LIT_PLANE_ALBEDO as f64 * LIT_PLANE_EMISSION as f64 * irradiance / std::f64::consts::PI;
        let analytic = lit_plane_radiance(x as f32, z as f32) as f64;
        assert!(
            (analytic - expected).abs() < 1e-5,
            "({x}, {z}): {analytic} vs {expected}"
        );
    }
    assert!((lit_plane_radiance(0.0, 0.0) - 0.49594).abs() < 1e-4);
}
