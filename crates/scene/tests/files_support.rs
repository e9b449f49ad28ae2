//! What the tests of scene formats written as text (Mitsuba's, pbrt's) share: the shipped
//! scenes, and mangled copies of a file.

use std::path::{Path, PathBuf};

/// A scene shipped in `scenes/`.
pub fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

/// The error a load ended in, which must be one line (`what` names the input if it loaded).
pub fn refusal(loaded: Result<scene::Scene, scene::SceneError>, what: &str) -> String {
    let message = loaded
        .err()
        .unwrap_or_else(|| panic!("loaded: {what}"))
        .to_string();
    assert!(!message.contains('\n'), "{message}");
    message
}

/// `rounds` copies of `original` mangled by a fixed xorshift sequence: every fourth cut short,
/// each with one to four bytes replaced by one of `replacements` (the format's own syntax, so
/// the parser is led into its corners).
pub fn mangled(original: &[u8], rounds: usize, replacements: &[u8]) -> Vec<Vec<u8>> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state as usize
    };
    (0..rounds)
        .map(|round| {
            let mut bytes = original.to_vec();
            if round % 4 == 0 {
                bytes.truncate(next() % bytes.len());
            }
            for _ in 0..1 + next() % 4 {
                let at = next() % bytes.len().max(1);
                if let Some(byte) = bytes.get_mut(at) {
                    *byte = replacements[next() % replacements.len()];
                }
            }
            bytes
        })
        .collect()
}
