//! URIs of buffers and images: base64 `data:` URIs, or paths relative to the `.gltf` file
//! (percent-encoded, as URIs are). Anything else (`http:`, `file:`, absolute paths) is refused.

use std::path::{Path, PathBuf};

use base64::Engine;
use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};

/// Base64 as data URIs carry it; writers differ on padding, so either form is accepted.
const BASE64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
);

/// Where a URI's bytes are.
pub(super) enum Resolved {
    /// The decoded payload of a `data:` URI.
    Data(Vec<u8>),
    /// A file next to (or below, or above) the glTF file.
    File(PathBuf),
}

/// Why a URI could not be resolved.
pub(super) enum UriError {
    Malformed(String),
    Unsupported(String),
}

/// Resolves `uri` against `base_dir`, decoding a data URI on the spot.
pub(super) fn resolve(base_dir: &Path, uri: &str) -> Result<Resolved, UriError> {
    if let Some(rest) = strip_prefix_ignore_case(uri, "data:") {
        return decode_data_uri(rest).map(Resolved::Data);
    }
    if let Some(scheme) = scheme(uri) {
        return Err(UriError::Unsupported(format!(
            "URI scheme \"{scheme}:\" is not supported (only relative paths and data URIs)"
        )));
    }
    let decoded = percent_decode(uri)?;
    if decoded.is_empty() {
        return Err(UriError::Malformed("empty URI".to_string()));
    }
    if decoded.starts_with('/') || decoded.starts_with('\\') || decoded.contains('\0') {
        return Err(UriError::Unsupported(format!(
            "URI \"{}\" is not a relative path",
            shorten(uri)
        )));
    }
    Ok(Resolved::File(base_dir.join(decoded)))
}

/// A URI cut to a length fit for an error message (data URIs can be megabytes).
pub(super) fn shorten(uri: &str) -> String {
    const MAX_CHARS: usize = 48;
    if uri.chars().count() <= MAX_CHARS {
        uri.to_string()
    } else {
        let head: String = uri.chars().take(MAX_CHARS).collect();
        format!("{head}...")
    }
}

fn strip_prefix_ignore_case<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| &s[prefix.len()..])
}

/// `rest` is what follows `data:`: `[<media type>][;base64],<payload>`.
fn decode_data_uri(rest: &str) -> Result<Vec<u8>, UriError> {
    let Some((header, payload)) = rest.split_once(',') else {
        return Err(UriError::Malformed(
            "malformed data URI: no ',' before its payload".to_string(),
        ));
    };
    let is_base64 = header
        .rsplit(';')
        .next()
        .is_some_and(|last| last.eq_ignore_ascii_case("base64"));
    if !is_base64 {
        return Err(UriError::Unsupported(format!(
            "data URI \"data:{header},...\" is not base64-encoded"
        )));
    }
    BASE64
        .decode(payload)
        .map_err(|e| UriError::Malformed(format!("malformed base64 in data URI: {e}")))
}

/// The URI's scheme, if it has one (RFC 3986: a letter, then letters, digits, `+`, `-`, `.`).
fn scheme(uri: &str) -> Option<&str> {
    let (scheme, _) = uri.split_once(':')?;
    let mut chars = scheme.chars();
    let first_is_letter = chars.next().is_some_and(|c| c.is_ascii_alphabetic());
    let rest_valid = chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'));
    (first_is_letter && rest_valid).then_some(scheme)
}

/// Decodes `%XX` escapes; the result must be UTF-8.
fn percent_decode(uri: &str) -> Result<String, UriError> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok());
            let Some(byte) = hex else {
                return Err(UriError::Malformed(format!(
                    "malformed percent escape in URI \"{}\"",
                    shorten(uri)
                )));
            };
            out.push(byte);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| {
        UriError::Malformed(format!("URI \"{}\" does not decode to UTF-8", shorten(uri)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(uri: &str) -> Option<PathBuf> {
        match resolve(Path::new("dir"), uri) {
            Ok(Resolved::File(p)) => Some(p),
            _ => None,
        }
    }

    #[test]
    fn percent_escapes_decode_to_a_relative_path() {
        assert_eq!(file("a%20b/c.bin"), Some(PathBuf::from("dir/a b/c.bin")));
        assert_eq!(file("../up.bin"), Some(PathBuf::from("dir/../up.bin")));
    }

    #[test]
    fn absolute_paths_schemes_and_bad_escapes_are_refused() {
        for uri in [
            "/etc/passwd",
            "http://x/y.bin",
            "file:///a",
            "a%2",
            "a%zz",
            "%ff",
            "",
        ] {
            assert!(file(uri).is_none(), "{uri}");
        }
    }

    #[test]
    fn data_uris_decode_with_or_without_padding() {
        for uri in [
            "data:application/octet-stream;base64,AAEC",
            "data:;base64,AAE",
        ] {
            match resolve(Path::new("."), uri) {
                Ok(Resolved::Data(bytes)) => assert_eq!(bytes[..2], [0, 1]),
                _ => panic!("{uri} did not decode"),
            }
        }
        for uri in ["data:abc", "data:text/plain,hello", "data:;base64,@@@@"] {
            assert!(resolve(Path::new("."), uri).is_err(), "{uri}");
        }
    }
}
