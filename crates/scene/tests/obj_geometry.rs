//! OBJ geometry: triangulation, normals, texture coordinates, indices, odd statements.

use std::path::PathBuf;

use glam::{Vec2, Vec3};
use scene::Scene;

fn load_text(obj: &str) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mesh.obj");
    std::fs::write(&path, obj).unwrap();
    scene::obj::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn quads_and_polygons_are_fan_triangulated() {
    let scene = load_text(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n\
         v 0 0 1\nv 1 0 1\nv 2 1 1\nv 1 2 1\nv 0 1 1\nf 5 6 7 8 9\n",
    );
    assert_eq!(scene.triangles.len(), 2 + 3);
    let first = scene.triangles[0].positions();
    assert_eq!(first, [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)]);
    let second = scene.triangles[1].positions();
    assert_eq!(second, [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]);
    // Counter-clockwise seen from +z: the front faces +z.
    for t in &scene.triangles {
        assert!(t.geometric_normal_unnormalized().z > 0.0);
    }
}

#[test]
fn missing_normals_become_area_weighted_smooth_normals() {
    // Two triangles folded along the y axis, one facing +x+z and one -x+z.
    let scene = load_text("v 0 0 0\nv 0 1 0\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 2 4\n");
    let shared = scene.triangles[0].vertices[0].normal;
    assert!((shared - Vec3::Z).length() < 1e-6, "{shared}");
    assert_eq!(scene.triangles[1].vertices[0].normal, shared);
    // A corner only one triangle touches keeps that triangle's normal.
    let lone = scene.triangles[0].vertices[1].normal;
    let face = scene.triangles[0]
        .geometric_normal_unnormalized()
        .normalize();
    assert!((lone - face).length() < 1e-6);
}

#[test]
fn vt_and_vn_are_used_with_v_flipped() {
    let scene = load_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvt 1 0\nvt 0 1\nvn 0 0 2\nvn 0 1 1\n\
         f 1/1/1 2/2/2 3/3/1\n",
    );
    let [a, b, c] = scene.triangles[0].vertices;
    assert_eq!(a.uv, Vec2::new(0.25, 0.25));
    assert_eq!(b.uv, Vec2::new(1.0, 1.0));
    assert_eq!(c.uv, Vec2::new(0.0, 0.0));
    assert_eq!(a.normal, Vec3::Z, "made unit length");
    assert!((b.normal - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 1e-6);
}

#[test]
fn v_slash_slash_vn_and_relative_indices_work() {
    let scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\n");
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(scene.triangles[0].vertices[2].position, Vec3::Y);
    assert_eq!(scene.triangles[0].vertices[0].uv, Vec2::ZERO);
}

#[test]
fn faces_without_usemtl_get_the_default_material() {
    let scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].name, "default");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn zero_area_triangles_are_dropped_and_counted() {
    let scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(scene.degenerate_dropped, 1);
}

#[test]
fn points_short_faces_and_polylines_are_ignored_with_warnings() {
    let scene =
        load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1\nf 1 2\nl 1 2 3 4\np 1\nf 1 2 3\n");
    assert_eq!(scene.triangles.len(), 1);
    assert_eq!(scene.degenerate_dropped, 0);
    assert!(
        scene.warnings.iter().any(|w| w.contains("2 faces")),
        "{:?}",
        scene.warnings
    );
    assert!(scene.warnings.iter().any(|w| w.contains("polyline")));
}

#[test]
fn crlf_indented_and_tab_separated_statements_are_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.mtl"), "newmtl red\r\nKd 1 0 0\r\n").unwrap();
    let obj = "mtllib\tm.mtl\r\n  v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n  usemtl red\r\nf 1 2 3\r\n";
    let path: PathBuf = dir.path().join("m.obj");
    std::fs::write(&path, obj).unwrap();
    let scene = scene::obj::load(&path).unwrap();
    assert_eq!(scene.materials[0].name, "red");
    assert_eq!(scene.triangles[0].material, 0);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn invalid_utf8_is_replaced_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("latin1.obj");
    let mut bytes = b"# caf\xe9\n".to_vec();
    bytes.extend_from_slice(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    std::fs::write(&path, bytes).unwrap();
    let scene = scene::obj::load(&path).unwrap();
    assert_eq!(scene.triangles.len(), 1);
    assert!(scene.warnings.iter().any(|w| w.contains("UTF-8")));
}

#[test]
fn several_objects_and_libraries_on_one_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
    std::fs::write(dir.path().join("b.mtl"), "newmtl b\nKd 0 1 0\n").unwrap();
    let obj = "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
               o first\nusemtl b\nf 1 2 3\no second\nusemtl a\nf 3 2 1\n";
    let path = dir.path().join("two.obj");
    std::fs::write(&path, obj).unwrap();
    let scene = scene::load(&path).unwrap();
    let names: Vec<_> = scene
        .triangles
        .iter()
        .map(|t| &scene.materials[t.material as usize].name)
        .collect();
    assert_eq!(names, ["b", "a"]);
}

#[test]
fn objects_with_vt_and_vn_on_only_some_faces_fall_back_with_warnings() {
    let scene = load_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0.5 0.5\nvn 0 0 1\n\
         f 1/1/1 2/1/1 3/1/1\nf 2 4 3\n",
    );
    assert_eq!(scene.triangles.len(), 2);
    for v in scene.triangles.iter().flat_map(|t| t.vertices) {
        assert_eq!(v.uv, Vec2::ZERO);
        assert!((v.normal - Vec3::Z).length() < 1e-6);
    }
    assert_eq!(scene.warnings.len(), 2, "{:?}", scene.warnings);
}
