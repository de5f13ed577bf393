//! Cross-crate validation tests live in `tests/`.
