//! `fmuResourceLocation`: decoding the URI an importer passes into a path (exporter side),
//! and encoding a path as that URI (importer side, [`file_uri`]).
//!
//! The standard passes the location of the unpacked FMU's `resources` folder as a URI
//! (RFC 3986, `file` scheme, RFC 8089). Importers spell it in several ways; all of these
//! are accepted:
//!
//! | input | path |
//! |---|---|
//! | `file:///abs/path/resources/` | `/abs/path/resources/` |
//! | `file://localhost/abs/path` | `/abs/path` |
//! | `file:/abs/path` | `/abs/path` |
//! | `file:///tmp/my%20fmu/resources` | `/tmp/my fmu/resources` |
//! | `/abs/path` (a bare absolute path, as some older tools pass) | `/abs/path` |
//!
//! The scheme is matched case-insensitively, `%XX` escapes are decoded to bytes (on Unix
//! the bytes become the path as they are, so non-UTF-8 names work). Rejected with a
//! reason: an empty location, other schemes (`http:` …), a host other than `localhost`,
//! relative paths, malformed escapes (`%2`, `%zz`) and an encoded NUL byte. On Windows
//! `file:///C:/dir` becomes `C:/dir`.

use std::path::PathBuf;

/// Decode `fmuResourceLocation` to a path, or explain why it cannot be used.
pub fn resource_path(location: &str) -> Result<PathBuf, String> {
    if location.is_empty() {
        return Err("fmuResourceLocation is empty".to_owned());
    }
    let Some(rest) = strip_prefix_ignore_case(location, "file:") else {
        if has_uri_scheme(location) {
            return Err(format!(
                "fmuResourceLocation '{location}' is not a file URI (only the file: scheme is supported)"
            ));
        }
        let path = PathBuf::from(location);
        return if path.is_absolute() {
            Ok(path)
        } else {
            Err(format!(
                "fmuResourceLocation '{location}' is neither a file URI nor an absolute path"
            ))
        };
    };

    let encoded_path = if let Some(after_slashes) = rest.strip_prefix("//") {
        // file://authority/path
        let (authority, path) = match after_slashes.find('/') {
            Some(i) => after_slashes.split_at(i),
            None => (after_slashes, ""),
        };
        if !(authority.is_empty() || authority.eq_ignore_ascii_case("localhost")) {
            return Err(format!(
                "fmuResourceLocation '{location}' names the host '{authority}'; only local files are supported"
            ));
        }
        if path.is_empty() {
            return Err(format!("fmuResourceLocation '{location}' has no path"));
        }
        path
    } else if rest.starts_with('/') {
        // file:/path
        rest
    } else {
        return Err(format!(
            "fmuResourceLocation '{location}' is a relative file URI; an absolute path is required"
        ));
    };

    let bytes = percent_decode(encoded_path)
        .map_err(|e| format!("fmuResourceLocation '{location}': {e}"))?;
    bytes_to_path(bytes).map_err(|e| format!("fmuResourceLocation '{location}': {e}"))
}

/// The `file:///…` URI of an absolute path (for passing `fmuResourceLocation` to an FMU):
/// every byte outside RFC 3986's unreserved characters and `/` is percent-encoded.
pub fn file_uri(path: &std::path::Path) -> Result<String, String> {
    if !path.is_absolute() {
        return Err(format!("{} is not an absolute path", path.display()));
    }
    let bytes = path_bytes(path)?;
    let mut uri = String::from("file://");
    if bytes.first() != Some(&b'/') {
        uri.push('/'); // Windows: file:///C:/dir
    }
    for &b in &bytes {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' => {
                uri.push(char::from(b))
            }
            b'\\' if cfg!(windows) => uri.push('/'),
            b':' if cfg!(windows) => uri.push(':'),
            _ => uri.push_str(&format!("%{b:02X}")),
        }
    }
    Ok(uri)
}

#[cfg(unix)]
fn path_bytes(path: &std::path::Path) -> Result<Vec<u8>, String> {
    use std::os::unix::ffi::OsStrExt;
    Ok(path.as_os_str().as_bytes().to_vec())
}

#[cfg(not(unix))]
fn path_bytes(path: &std::path::Path) -> Result<Vec<u8>, String> {
    path.to_str()
        .map(|s| s.as_bytes().to_vec())
        .ok_or_else(|| format!("{} is not valid Unicode", path.display()))
}

fn strip_prefix_ignore_case<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| &s[prefix.len()..])
}

/// `scheme:` per RFC 3986 (ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":"), excluding a
/// single letter (a Windows drive such as `C:`).
fn has_uri_scheme(s: &str) -> bool {
    let Some(colon) = s.find(':') else {
        return false;
    };
    let scheme = &s[..colon];
    scheme.len() > 1
        && scheme
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// Decode `%XX` escapes; every other byte is kept.
pub fn percent_decode(s: &str) -> Result<Vec<u8>, String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .ok_or_else(|| format!("truncated percent-encoding at byte {i}"))?;
            let value = hex_value(hex[0])
                .zip(hex_value(hex[1]))
                .map(|(hi, lo)| hi << 4 | lo)
                .ok_or_else(|| {
                    format!(
                        "invalid percent-encoding '%{}' at byte {i}",
                        String::from_utf8_lossy(hex)
                    )
                })?;
            if value == 0 {
                return Err(format!("encoded NUL byte at byte {i}"));
            }
            out.push(value);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Ok(out)
}

fn hex_value(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'a'..=b'f' => Some(c - b'a' + 10),
        b'A'..=b'F' => Some(c - b'A' + 10),
        _ => None,
    }
}

#[cfg(unix)]
fn bytes_to_path(bytes: Vec<u8>) -> Result<PathBuf, String> {
    use std::os::unix::ffi::OsStringExt;
    Ok(PathBuf::from(std::ffi::OsString::from_vec(bytes)))
}

#[cfg(not(unix))]
fn bytes_to_path(bytes: Vec<u8>) -> Result<PathBuf, String> {
    let s = String::from_utf8(bytes).map_err(|_| "decoded path is not UTF-8".to_owned())?;
    // "/C:/dir" → "C:/dir"
    let b = s.as_bytes();
    let s = if b.len() >= 3 && b[0] == b'/' && b[1].is_ascii_alphabetic() && b[2] == b':' {
        s[1..].to_owned()
    } else {
        s
    };
    Ok(PathBuf::from(s))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn ok(s: &str) -> PathBuf {
        resource_path(s).unwrap_or_else(|e| panic!("{s}: {e}"))
    }

    fn err(s: &str) -> String {
        match resource_path(s) {
            Ok(p) => panic!("{s} decoded to {p:?}, expected an error"),
            Err(e) => e,
        }
    }

    #[test]
    fn triple_slash_uri() {
        assert_eq!(
            ok("file:///abs/path/resources/"),
            Path::new("/abs/path/resources/")
        );
    }

    #[test]
    fn single_slash_and_localhost_forms() {
        assert_eq!(ok("file:/abs/path"), Path::new("/abs/path"));
        assert_eq!(ok("file://localhost/abs/path"), Path::new("/abs/path"));
        assert_eq!(ok("FILE://LocalHost/abs"), Path::new("/abs"));
        assert_eq!(ok("File:///x"), Path::new("/x"));
    }

    #[test]
    fn percent_escapes_are_decoded() {
        assert_eq!(
            ok("file:///tmp/my%20fmu/resources"),
            Path::new("/tmp/my fmu/resources")
        );
        assert_eq!(ok("file:///a%2Fb%25c"), Path::new("/a/b%c"));
        assert_eq!(ok("file:///caf%C3%A9"), Path::new("/café"));
        // Unencoded non-ASCII (some importers do not encode) passes through.
        assert_eq!(ok("file:///café dir"), Path::new("/café dir"));
    }

    #[cfg(unix)]
    #[test]
    fn non_utf8_bytes_survive_on_unix() {
        use std::os::unix::ffi::OsStrExt;
        let p = ok("file:///x%FFy");
        assert_eq!(p.as_os_str().as_bytes(), b"/x\xFFy");
    }

    #[test]
    fn bare_absolute_path_is_accepted() {
        assert_eq!(ok("/abs/path"), Path::new("/abs/path"));
    }

    #[test]
    fn malformed_locations_are_rejected_with_a_reason() {
        assert!(err("").contains("empty"));
        assert!(err("http://example.com/r").contains("not a file URI"));
        assert!(err("file://server/share").contains("host 'server'"));
        assert!(err("file:relative/path").contains("relative"));
        assert!(err("relative/path").contains("neither"));
        assert!(err("file:///a%2").contains("truncated"));
        assert!(err("file:///a%zzb").contains("invalid percent-encoding '%zz'"));
        assert!(err("file:///a%00b").contains("NUL"));
        assert!(err("file://").contains("no path"));
    }

    #[test]
    fn file_uri_round_trips() {
        for p in ["/abs/path/resources/", "/tmp/my fmu/r%s#x?y", "/café/ü"] {
            let uri = file_uri(Path::new(p)).unwrap();
            assert!(uri.starts_with("file:///"), "{uri}");
            assert!(!uri.contains(' '));
            assert_eq!(resource_path(&uri).unwrap(), Path::new(p), "{uri}");
        }
        assert_eq!(file_uri(Path::new("/a b/c")).unwrap(), "file:///a%20b/c");
        assert!(file_uri(Path::new("relative")).is_err());
    }

    #[test]
    fn percent_decode_keeps_plain_bytes() {
        assert_eq!(percent_decode("abc").unwrap(), b"abc");
        assert_eq!(percent_decode("%41%62").unwrap(), b"Ab");
        assert_eq!(percent_decode("").unwrap(), b"");
    }

    #[test]
    fn file_uris_match_pathlib() {
        assert_eq!(
            file_uri(std::path::Path::new("/tmp/tbi-fmu-1/resources")).unwrap(),
            "file:///tmp/tbi-fmu-1/resources"
        );
        assert_eq!(
            file_uri(std::path::Path::new("/home/a b/r\u{e9}s#1%/x~y")).unwrap(),
            "file:///home/a%20b/r%C3%A9s%231%25/x~y"
        );
        assert!(file_uri(std::path::Path::new("relative/dir")).is_err());
    }
}
