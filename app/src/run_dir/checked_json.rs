//! JSON files that carry their own checksum (`sweep.json`, `value-NNN.json`): the last field,
//! `"checksum": "XXXXXXXX"`, is the crc32 of the file's text written with that field set to
//! `"00000000"`. The check works on the text, not on parsed numbers (serde_json's default
//! float parsing may differ from the written value in the last bit), so any edit of a number,
//! a name or the layout is seen.

use crate::run_dir::fingerprint::crc32;
use serde::Serialize;

/// The value of the `checksum` field while the checksum is computed.
pub const PLACEHOLDER: &str = "00000000";

fn field(value: &str) -> String {
    format!("\"checksum\": \"{value}\"")
}

/// Pretty JSON of `value`, whose `checksum` field (a string, last) must hold [`PLACEHOLDER`],
/// with the checksum filled in.
pub fn seal<T: Serialize>(value: &T) -> anyhow::Result<String> {
    let text = serde_json::to_string_pretty(value)?;
    let blank = field(PLACEHOLDER);
    let Some(at) = text.rfind(&blank) else {
        anyhow::bail!("internal: no blank checksum field to fill in");
    };
    let sum = crc32(text.as_bytes());
    Ok(format!(
        "{}{}{}",
        &text[..at],
        field(&format!("{sum:08x}")),
        &text[at + blank.len()..]
    ))
}

/// Checks the checksum `stored` (read from the file's `checksum` field) against `text`.
/// The error says what is wrong, without the file name.
pub fn verify(text: &str, stored: &str) -> Result<(), String> {
    let value = if stored.len() == 8 && stored.bytes().all(|b| b.is_ascii_hexdigit()) {
        u32::from_str_radix(stored, 16).ok()
    } else {
        None
    };
    let Some(value) = value else {
        return Err(format!(
            "checksum `{stored}` is not 8 hexadecimal digits: the file is damaged"
        ));
    };
    let written = field(stored);
    let Some(at) = text.rfind(&written) else {
        return Err("the checksum field was moved or reformatted: the file was edited".into());
    };
    let blanked = format!(
        "{}{}{}",
        &text[..at],
        field(PLACEHOLDER),
        &text[at + written.len()..]
    );
    let computed = crc32(blanked.as_bytes());
    if computed != value {
        return Err(format!(
            "checksum mismatch (stored {stored}, computed {computed:08x}): the file is damaged \
             or was edited"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Doc {
        a: f64,
        name: String,
        checksum: String,
    }

    #[test]
    fn a_sealed_text_verifies_and_any_edit_is_seen() {
        let text = seal(&Doc {
            a: 0.15000000000000002,
            name: "\"checksum\": \"00000000\"".into(),
            checksum: PLACEHOLDER.into(),
        })
        .expect("seals");
        let stored: serde_json::Value = serde_json::from_str(&text).expect("json");
        let sum = stored["checksum"].as_str().expect("string");
        assert_ne!(sum, PLACEHOLDER);
        assert_eq!(verify(&text, sum), Ok(()));
        let edited = text.replace("0.15000000000000002", "0.15000000000000003");
        let e = verify(&edited, sum).expect_err("edited");
        assert!(e.starts_with("checksum mismatch (stored"), "{e}");
        assert!(verify(&text, "zz").is_err());
        assert!(verify(&text.replace("\"checksum\": ", "\"checksum\":"), sum).is_err());
    }
}
