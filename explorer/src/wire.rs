//! The explorer's messages as bytes, for a solver side that shares no memory with the UI (the
//! browser's Web Worker): what goes to the solver ([`ToSolver`]: the scene to open, the
//! requests of [`crate::protocol`], the displayed step) and the [`Event`]s that come back,
//! each encoded with postcard (field arrays as raw little-endian floats, lengths as varints), so
//! one message is one byte buffer a page can transfer without copying. The solver settings
//! inside a message travel as their JSON text ([`as_json`]): their serde form skips default
//! fields and has untagged choices, which only a self-describing format reads back.

use crate::protocol::{Event, Request};

/// The scene a remote solver side opens: the same [`crate::app::load_scene`] as the UI side's,
/// so both hold the same problem.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Start {
    /// Built-in scene name (or a path the solver side can read).
    pub scene: String,
    /// Two-scale linear stage on or off (None: the scene's `solver.macro`).
    pub two_scale: Option<bool>,
}

/// A message to the solver side.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) enum ToSolver {
    /// Open the scene and factorize (the first message).
    Start(Start),
    /// A request of the UI.
    Request(Request),
    /// The step on screen moved (live fields are computed there).
    DisplayStep(usize),
}

/// Why a message could not be read.
#[derive(Debug, Clone, PartialEq)]
pub struct WireError(String);

impl std::fmt::Display for WireError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "unreadable message between the explorer and its solver: {}",
            self.0
        )
    }
}

impl std::error::Error for WireError {}

fn encode<T: serde::Serialize>(message: &T) -> Vec<u8> {
    // every message type is plain data (no maps with non-string keys, no borrowed data): postcard
    // serializes it into a Vec without failing
    postcard::to_allocvec(message).unwrap_or_default()
}

fn decode<'a, T: serde::Deserialize<'a>>(bytes: &'a [u8]) -> Result<T, WireError> {
    postcard::from_bytes(bytes).map_err(|e| WireError(format!("{e} ({} bytes)", bytes.len())))
}

/// A message to the solver side as bytes.
pub(crate) fn encode_to_solver(message: &ToSolver) -> Vec<u8> {
    encode(message)
}

/// A message to the solver side from bytes.
pub(crate) fn decode_to_solver(bytes: &[u8]) -> Result<ToSolver, WireError> {
    decode(bytes)
}

/// The first message to a solver side, as bytes (what [`crate::worker::Worker::spawn_remote`]
/// sends; a page may send it earlier, while it starts).
pub fn encode_start(start: &Start) -> Vec<u8> {
    encode(&ToSolver::Start(start.clone()))
}

/// An event as bytes.
pub fn encode_event(event: &Event) -> Vec<u8> {
    encode(event)
}

/// An event from bytes.
pub fn decode_event(bytes: &[u8]) -> Result<Event, WireError> {
    decode(bytes)
}

/// A field's value as its JSON text inside a message (`#[serde(with = "crate::wire::as_json")]`),
/// for types whose serde form needs a self-describing format.
pub(crate) mod as_json {
    use serde::de::{DeserializeOwned, Error as _};
    use serde::ser::Error as _;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(crate) fn serialize<T: Serialize, S: Serializer>(
        value: &T,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        let text = serde_json::to_string(value).map_err(S::Error::custom)?;
        serializer.serialize_str(&text)
    }

    pub(crate) fn deserialize<'de, T: DeserializeOwned, D: Deserializer<'de>>(
        deserializer: D,
    ) -> Result<T, D::Error> {
        let text = String::deserialize(deserializer)?;
        serde_json::from_str(&text).map_err(D::Error::custom)
    }
}
