//! Malformed OBJ/MTL input ends in a one-line [`SceneError`], never a panic.

use std::path::Path;

use scene::SceneError;

fn load_bytes(bytes: &[u8]) -> Result<scene::Scene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    load_bytes_in(dir.path(), bytes)
}

fn load_bytes_in(dir: &Path, bytes: &[u8]) -> Result<scene::Scene, SceneError> {
    let path = dir.join("bad.obj");
    std::fs::write(&path, bytes).unwrap();
    let result = scene::obj::load(&path);
    if let Err(e) = &result {
        let message = e.to_string();
        assert!(!message.contains('\n'), "one line: {message:?}");
        assert!(message.contains("bad.obj"), "names the file: {message}");
    }
    result
}

fn format_error(obj: &str) -> String {
    match load_bytes(obj.as_bytes()) {
        Err(SceneError::Format { message, .. }) => message,
        other => panic!("expected a format error for {obj:?}, got {other:?}"),
    }
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn missing_file_is_an_io_error() {
    let result = scene::obj::load(Path::new("/nonexistent/kousen/scene.obj"));
    assert!(matches!(result, Err(SceneError::Io { .. })), "{result:?}");
}

#[test]
fn empty_and_comment_only_files_have_no_triangles() {
    for text in ["", "# nothing here\n\n", TRIANGLE] {
        let result = load_bytes(text.as_bytes());
        assert!(
            matches!(result, Err(SceneError::NoTriangles { .. })),
            "{result:?}"
        );
    }
}

#[test]
fn garbage_is_a_format_error() {
    assert!(format_error("hello world\nthis is not an obj\n").contains("not an OBJ"));
    let binary: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    assert!(matches!(
        load_bytes(&binary),
        Err(SceneError::Format { .. }) | Err(SceneError::NoTriangles { .. })
    ));
}

#[test]
fn face_index_out_of_range_names_the_line() {
    let message = format_error(&format!("{TRIANGLE}f 1 2 4\n"));
    assert!(
        message.contains("line 4") && message.contains("vertex index 4"),
        "{message}"
    );
    let message = format_error(&format!("{TRIANGLE}vt 0 0\nf 1/2 2/1 3/1\n"));
    assert!(message.contains("texture coordinate index 2"), "{message}");
    let message = format_error(&format!("{TRIANGLE}f 1//1 2//1 3//1\n"));
    assert!(message.contains("normal index 1"), "{message}");
    assert!(format_error(&format!("{TRIANGLE}f 0 1 2\n")).contains("index 0"));
}

#[test]
fn relative_indices_before_the_first_element_are_refused() {
    // tobj would overflow computing this texture coordinate's offset (a panic in debug builds).
    let message = format_error(&format!("{TRIANGLE}vt 0 0\nf 1/-3 2/1 3/1\n"));
    assert!(
        message.contains("line 5") && message.contains("relative"),
        "{message}"
    );
    format_error(&format!(
        "{TRIANGLE}vn 0 0 1\nf 1//-9223372036854775808 2//1 3//1\n"
    ));
    format_error(&format!("{TRIANGLE}f -4 -2 -1\n"));
    format_error(&format!(
        "{TRIANGLE}vn 0 0 1\nf 1//9999999999999999999 2//1 3//1\n"
    ));
}

#[test]
fn malformed_statements_name_their_line() {
    let cases = [
        ("v 0 0 0\nv 1 0\n", "line 2"),
        ("v 0 0 0\nv 1 0 0 0\n", "line 2"),
        (&format!("{TRIANGLE}vt 0.5\n") as &str, "line 4"),
        (&format!("{TRIANGLE}vn 0 0\n"), "line 4"),
        (&format!("{TRIANGLE}f 1 2 x\n"), "line 4"),
        (&format!("{TRIANGLE}f 1/1/1/1 2 3\n"), "line 4"),
        (&format!("{TRIANGLE}f /1 2 3\n"), "line 4"),
        (&format!("{TRIANGLE}usemtl\nf 1 2 3\n"), "line 4"),
    ];
    for (obj, expected) in cases {
        let message = format_error(obj);
        assert!(message.contains(expected), "{obj:?}: {message}");
    }
}

#[test]
fn non_finite_or_huge_positions_are_format_errors() {
    assert!(format_error("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").contains("non-finite"));
    format_error("v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    format_error("v 3e38 0 0\nv -3e38 3e38 0\nv 0 -3e38 0\nf 1 2 3\n");
    format_error(&format!("{TRIANGLE}vt nan 0\nf 1/1 2/1 3/1\n"));
}

#[test]
fn non_finite_material_values_are_format_errors() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.mtl"), "newmtl m\nKd nan 0 0\n").unwrap();
    let path = dir.path().join("m.obj");
    std::fs::write(
        &path,
        format!("mtllib m.mtl\n{TRIANGLE}usemtl m\nf 1 2 3\n"),
    )
    .unwrap();
    let error = scene::obj::load(&path).unwrap_err();
    assert!(error.to_string().contains("Kd"), "{error}");
}

#[test]
fn garbage_mtl_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut mtl =
        b"newmtl m\nKd 1\nKs 1 2\nKe\nNi x\nd\nillum 300\nmap_Kd\nmap_d   \nbump\n".to_vec();
    mtl.extend((0..2000u32).map(|i| (i.wrapping_mul(2_246_822_519) >> 11) as u8));
    std::fs::write(dir.path().join("m.mtl"), mtl).unwrap();
    let path = dir.path().join("m.obj");
    std::fs::write(
        &path,
        format!("mtllib m.mtl\n{TRIANGLE}usemtl m\nf 1 2 3\n"),
    )
    .unwrap();
    let scene = scene::obj::load(&path).unwrap();
    assert_eq!(scene.triangles.len(), 1);
    assert!(!scene.warnings.is_empty());
}

/// A small deterministic generator (SplitMix64) for the fuzz test.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[(self.next() % items.len() as u64) as usize]
    }
}

#[test]
fn random_statements_never_panic() {
    let keywords = [
        "v", "vt", "vn", "f", "f", "f", "l", "p", "usemtl", "mtllib", "g", "o", "s", "#", "vp", "",
    ];
    let values = [
        "0",
        "1",
        "-1",
        "2",
        "-2",
        "3",
        "0.5",
        "-0.5",
        "1e38",
        "-1e38",
        "nan",
        "inf",
        "x",
        "1/1",
        "1//1",
        "1/1/1",
        "-1/-1/-1",
        "/",
        "//",
        "2/",
        "1/2/3/4",
        "99999999999999999999",
        "-9",
        "+1",
        "m.mtl",
        "a b",
        "\t",
        "é",
    ];
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.mtl"), "newmtl a b\nKd 1\nmap_d x.png\n").unwrap();
    let mut rng = SplitMix(0x6b6f_7573_656e);
    for _ in 0..800 {
        let mut obj = String::new();
        for _ in 0..(rng.next() % 24) {
            obj += rng.pick(&keywords);
            for _ in 0..(rng.next() % 6) {
                obj.push(' ');
                obj += rng.pick(&values);
            }
            obj.push('\n');
        }
        // Only the absence of a panic is checked; `load_bytes` checks errors are one line.
        let _ = load_bytes_in(dir.path(), obj.as_bytes());
    }
}

#[test]
fn devices_and_directories_named_by_a_scene_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("folder.png")).unwrap();
    std::fs::write(
        dir.path().join("m.mtl"),
        "newmtl m\nmap_Kd /dev/zero\nmap_d folder.png\n",
    )
    .unwrap();
    let path = dir.path().join("m.obj");
    let obj = format!("mtllib /dev/zero\nmtllib m.mtl\n{TRIANGLE}usemtl m\nf 1 2 3\n");
    std::fs::write(&path, obj).unwrap();
    let scene = scene::obj::load(&path).unwrap();
    let refused = scene
        .warnings
        .iter()
        .filter(|w| w.contains("not a regular file"))
        .count();
    assert_eq!(refused, 3, "{:?}", scene.warnings);
    assert!(matches!(
        scene::obj::load(dir.path()),
        Err(SceneError::Io { .. })
    ));
}
