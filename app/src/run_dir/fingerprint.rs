//! What a saved file belongs to, as a stable 64-bit [`Fingerprint`], and the crc32 checksums of
//! the files themselves.
//!
//! A fingerprint hashes the scene ([`lopin_core::scene::to_toml`], after `--refine` and
//! `--split`) and the parameter values set on its problem (`--f`, `--set`) together with the LATIN settings that change the solution
//! ([`lopin_core::Settings`] through serde_json), or, for a sweep, its header (which holds both
//! as fingerprints, the parameter, its values, mode and predictor). `solution.bin` and every
//! `value-NNN.state` carry the fingerprint of what they were computed for, and readers refuse a
//! file whose fingerprint is not the one they expect (a file copied from another run, or a
//! scene edited since).
//!
//! The hash is two crc32 (crc32fast) of the framed bytes, forward and reversed, so it is the
//! same in every run and every build (no `DefaultHasher`); it guards against mistakes, not
//! against forgery.

use std::fmt;
use std::str::FromStr;

use lopin_core::scene::{self, SceneSpec};
use lopin_core::target::Assignment;
use lopin_core::Settings;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A 64-bit hash of what a file belongs to, written as 16 hexadecimal digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fingerprint(pub u64);

impl Fingerprint {
    /// Hash of tagged parts: each is framed by its tag and length, so parts cannot run into
    /// one another.
    pub fn of_parts(parts: &[(&str, &[u8])]) -> Fingerprint {
        let mut framed = Vec::new();
        for (tag, bytes) in parts {
            framed.extend_from_slice(tag.as_bytes());
            framed.push(0);
            framed.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
            framed.extend_from_slice(bytes);
        }
        let forward = crc32fast::hash(&framed);
        framed.reverse();
        let backward = crc32fast::hash(&framed);
        Fingerprint((u64::from(forward) << 32) | u64::from(backward))
    }
}

impl fmt::Display for Fingerprint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:016x}", self.0)
    }
}

impl FromStr for Fingerprint {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.len() != 16 {
            return Err(format!(
                "`{s}` is not a fingerprint (16 hexadecimal digits)"
            ));
        }
        u64::from_str_radix(s, 16)
            .map(Fingerprint)
            .map_err(|_| format!("`{s}` is not a fingerprint (16 hexadecimal digits)"))
    }
}

impl Serialize for Fingerprint {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Fingerprint {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

/// The scene and the parameter values set on its problem: its TOML text, and the values'
/// JSON when there are any.
pub fn of_scene(spec: &SceneSpec, assignments: &[Assignment]) -> Fingerprint {
    of_identity(spec, assignments, None)
}

/// The LATIN settings: their JSON text.
pub fn of_settings(settings: &Settings) -> Fingerprint {
    of_json("settings", settings)
}

/// What a run's `solution.bin` belongs to: the scene, the parameter values set on its problem
/// (when there are any) and the settings.
pub fn of_run(spec: &SceneSpec, assignments: &[Assignment], settings: &Settings) -> Fingerprint {
    of_identity(spec, assignments, Some(settings))
}

/// The parts of [`of_scene`] and [`of_run`]: the scene, the values when there are any, the
/// settings when given.
fn of_identity(
    spec: &SceneSpec,
    assignments: &[Assignment],
    settings: Option<&Settings>,
) -> Fingerprint {
    let toml = scene::to_toml(spec);
    let values = json_bytes(&assignments);
    let settings = settings.map(json_bytes);
    let mut parts: Vec<(&str, &[u8])> = vec![("scene", toml.as_bytes())];
    if !assignments.is_empty() {
        parts.push(("assignments", values.as_slice()));
    }
    if let Some(s) = &settings {
        parts.push(("settings", s.as_slice()));
    }
    Fingerprint::of_parts(&parts)
}

/// Any serializable value under a tag, through its compact JSON text.
pub fn of_json<T: Serialize>(tag: &str, value: &T) -> Fingerprint {
    Fingerprint::of_parts(&[(tag, json_bytes(value).as_slice())])
}

fn json_bytes<T: Serialize>(value: &T) -> Vec<u8> {
    // the types hashed here (settings, sweep headers) have string keys and no maps of other
    // keys, so serde_json cannot fail on them
    serde_json::to_vec(value).unwrap_or_else(|e| unreachable!("serde_json: {e}"))
}

/// The crc32 of `bytes` (the checksum of the files and records).
pub fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fingerprints_are_stable_and_tell_parts_apart() {
        let parts = |a: &'static str, b: &'static str| {
            Fingerprint::of_parts(&[("scene", a.as_bytes()), ("settings", b.as_bytes())])
        };
        let a = parts("abc", "d");
        assert_eq!(a, parts("abc", "d"));
        assert_ne!(a, parts("ab", "cd"));
        // the standard crc32 check value: the checksum cannot change between builds
        assert_eq!(crc32(b"123456789"), 0xcbf4_3926);
        let known = Fingerprint::of_parts(&[("x", b"".as_slice())]);
        assert_eq!(known.to_string().len(), 16);
        assert_eq!(known.to_string().parse::<Fingerprint>(), Ok(known));
        assert!("xyz".parse::<Fingerprint>().is_err());
        let json = serde_json::to_string(&a).expect("serializes");
        assert_eq!(json, format!("\"{a}\""));
        assert_eq!(
            serde_json::from_str::<Fingerprint>(&json).expect("parses"),
            a
        );
    }

    #[test]
    fn a_scene_edit_changes_the_fingerprint() {
        let spec = scene::load("mini-blocks").expect("scene");
        let mut denser = spec.clone();
        denser.materials[0].density *= 1.01;
        assert_eq!(of_scene(&spec, &[]), of_scene(&spec.clone(), &[]));
        assert_ne!(of_scene(&spec, &[]), of_scene(&denser, &[]));
    }
}
