//! Deterministic GUIDs tying `modelDescription.xml` to the binary and its resources.
//!
//! [`guid`] hashes the model identifier, a build identifier and the bytes of the resources
//! that define the model with the 128-bit XXH3 hash (seed 0, default secret) and formats the
//! digest as an RFC 9562 UUID of version 8 ("custom"): the version nibble is set to `8` and
//! the variant bits to `10`, so 122 bits of the digest remain. The FMU packager (writing
//! `guid="…"` into `modelDescription.xml`) and the model (answering
//! [`crate::FmuModel::guid`] from the resources it reads at instantiation) call the same
//! function with the same inputs and obtain the same string; `fmi2Instantiate` refuses a
//! GUID that differs. XXH3 digests megabytes of resources (a track record) in a fraction
//! of a millisecond, where a byte-at-a-time hash took milliseconds on both sides.
//!
//! The digest input is `"fmi-export/guid/v2\0"` followed by each argument as a
//! little-endian `u64` byte length and the bytes, so no two different argument triples
//! produce the same input. XXH3 is not a cryptographic hash: the GUID detects a
//! mismatched or stale `modelDescription.xml`, it does not authenticate anything.
//!
//! What to pass as `build_id` is the caller's choice; it must be computable by both sides
//! (for example `env!("CARGO_PKG_VERSION")` of the FMU crate, or that plus a format
//! revision of the resource files).

const FNV64_OFFSET: u64 = 0xcbf29ce484222325;
const FNV64_PRIME: u64 = 0x100000001b3;

/// Incremental 64-bit FNV-1a, also as a [`std::hash::Hasher`] (the component and state
/// type tag hashes a `TypeId` with it).
#[derive(Debug, Clone, Copy)]
pub struct Fnv1a64(u64);

impl Default for Fnv1a64 {
    fn default() -> Self {
        Fnv1a64(FNV64_OFFSET)
    }
}

impl std::hash::Hasher for Fnv1a64 {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(FNV64_PRIME);
        }
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// 64-bit FNV-1a of `bytes` (used for the FMU-state header and checksum).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    use std::hash::Hasher;
    let mut h = Fnv1a64::default();
    h.write(bytes);
    h.finish()
}

/// The GUID of an FMU: a UUID-formatted (`xxxxxxxx-xxxx-8xxx-yxxx-xxxxxxxxxxxx`,
/// lowercase, no braces) digest of `model_identifier`, `build_id` and `resource_bytes`.
/// Deterministic across platforms and runs; see the module documentation.
pub fn guid(model_identifier: &str, build_id: &str, resource_bytes: &[u8]) -> String {
    let mut h = xxhash_rust::xxh3::Xxh3::new();
    h.update(b"fmi-export/guid/v2\0");
    for part in [
        model_identifier.as_bytes(),
        build_id.as_bytes(),
        resource_bytes,
    ] {
        h.update(&(part.len() as u64).to_le_bytes());
        h.update(part);
    }
    format_uuid_v8(h.digest128())
}

fn format_uuid_v8(digest: u128) -> String {
    // version (bits 76..80 from the least significant end) = 8, variant (bits 62..64) = 0b10
    let v = (digest & !(0xF << 76) | (0x8 << 76)) & !(0b11 << 62) | (0b10 << 62);
    let hex = format!("{v:032x}");
    format!(
        "{}-{}-{}-{}-{}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_reference_vectors() {
        // Published test vectors: XXH3-128 of the empty input (seed 0), FNV-1a 64.
        assert_eq!(
            xxhash_rust::xxh3::xxh3_128(b""),
            0x99aa06d3014798d86001c324468d497f
        );
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn guid_is_a_version_8_uuid() {
        let g = guid("bridge", "0.1.0", b"E = 2.1e11\n");
        assert_eq!(g.len(), 36);
        let groups: Vec<&str> = g.split('-').collect();
        assert_eq!(
            groups.iter().map(|s| s.len()).collect::<Vec<_>>(),
            vec![8, 4, 4, 4, 12]
        );
        assert!(g
            .chars()
            .all(|c| c == '-' || c.is_ascii_digit() || ('a'..='f').contains(&c)));
        assert!(groups[2].starts_with('8'), "{g}");
        assert!(
            matches!(groups[3].as_bytes()[0], b'8' | b'9' | b'a' | b'b'),
            "{g}"
        );
    }

    #[test]
    fn guid_is_deterministic_and_sensitive_to_every_input() {
        let base = guid("m", "1", b"data");
        assert_eq!(base, guid("m", "1", b"data"));
        assert_ne!(base, guid("n", "1", b"data"));
        assert_ne!(base, guid("m", "2", b"data"));
        assert_ne!(base, guid("m", "1", b"datb"));
        // Length prefixes: moving bytes between arguments changes the GUID.
        assert_ne!(guid("ab", "c", b""), guid("a", "bc", b""));
        assert_ne!(guid("a", "", b"b"), guid("a", "b", b""));
    }

    #[test]
    fn guid_matches_the_documented_construction() {
        // Recompute the digest input by hand from the module documentation.
        let mut input = b"fmi-export/guid/v2\0".to_vec();
        for part in [&b"testmodel"[..], b"0.1.0", b"x = 1\n"] {
            input.extend_from_slice(&(part.len() as u64).to_le_bytes());
            input.extend_from_slice(part);
        }
        let digest = xxhash_rust::xxh3::xxh3_128(&input);
        let hex = format!("{digest:032x}");
        let g = guid("testmodel", "0.1.0", b"x = 1\n");
        let g_hex: String = g.chars().filter(|c| *c != '-').collect();
        // All nibbles except the version nibble and the two variant bits are the digest's.
        for (i, (a, b)) in hex.chars().zip(g_hex.chars()).enumerate() {
            match i {
                12 => assert_eq!(b, '8'),
                16 => {
                    let da = a.to_digit(16).unwrap();
                    let db = b.to_digit(16).unwrap();
                    assert_eq!(da & 0b0011, db & 0b0011);
                    assert_eq!(db >> 2, 0b10);
                }
                _ => assert_eq!(a, b, "nibble {i}"),
            }
        }
    }
}
