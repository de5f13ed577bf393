//! The seeded proptest runner both fuzz harnesses share (`tests/tests/fuzz_scenes.rs`,
//! `app/tests/fuzz_cli.rs`, which include this file with `#[path]`): ChaCha from a fixed seed
//! (or `LOPIN_FUZZ_SEED`), no failure-persistence files, so a CI failure is reproducible.

use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// A number from the environment variable `name`, if set (a malformed one stops the test).
pub fn env_number<T: std::str::FromStr>(name: &str) -> Option<T> {
    let text = std::env::var(name).ok()?;
    Some(
        text.trim()
            .parse()
            .unwrap_or_else(|_| panic!("{name} must be a number, got `{text}`")),
    )
}

/// The seeded runner for `cases` cases, and the seed it uses (`LOPIN_FUZZ_SEED` or `default`).
pub fn runner(cases: u32, default: u64) -> (TestRunner, u64) {
    let seed = env_number::<u64>("LOPIN_FUZZ_SEED").unwrap_or(default);
    let mut bytes = [0u8; 32];
    for (i, chunk) in bytes.chunks_mut(8).enumerate() {
        chunk.copy_from_slice(
            &(seed ^ (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)).to_le_bytes(),
        );
    }
    let config = Config {
        cases,
        rng_algorithm: RngAlgorithm::ChaCha,
        failure_persistence: None,
        ..Config::default()
    };
    (
        TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes)),
        seed,
    )
}

/// Fails the test with every failure listed, if there is any.
pub fn assert_no_failures(failures: &[String], seed: u64) {
    assert!(
        failures.is_empty(),
        "{} failure(s) (seed {seed:#x}):\n\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}
