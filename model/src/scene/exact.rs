//! Fixed-length arrays of scene files read with their length checked: `divisions = [4, 4, 4, 4]`
//! or `min = [0, 0]` is an error saying how many values the field takes, never silently cut or
//! padded.

use serde::{Deserialize, Deserializer};

/// Deserializes `[T; N]` from a sequence of exactly N values.
pub fn exactly<'de, D, T, const N: usize>(deserializer: D) -> Result<[T; N], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    let values = Vec::<T>::deserialize(deserializer)?;
    let got = values.len();
    values.try_into().map_err(|_| {
        serde::de::Error::custom(format!(
            "expected exactly {N} values{}, got {got}",
            if N == 3 { " (x, y, z)" } else { "" }
        ))
    })
}
