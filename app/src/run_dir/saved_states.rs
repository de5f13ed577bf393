//! The converged interface states of a parametric run on disk (a sweep's values, a study's
//! configurations): one binary file per configuration ([`super::solution_file`]'s state form),
//! bound to the run's fingerprint and written atomically, read back checked whole (its own
//! crc32, the checksum its record holds where it holds one, its fingerprint, finite values, the
//! problem's layout). A resumed sweep or study seeds its chains with them, so the configurations
//! after a resume start where they would have started without the stop (METHOD §8).

use std::path::{Path, PathBuf};

use lopin_core::state::InterfaceState;
use lopin_core::Problem;

use super::fingerprint::Fingerprint;
use super::solution_file::{decode_state, encode_state, file_checksum};

/// The states of one run in its folder.
#[derive(Debug, Clone)]
pub struct SavedStates {
    dir: PathBuf,
    /// What every state belongs to.
    owner: Fingerprint,
}

/// Why a saved state cannot be used: the file and the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct Unusable {
    pub path: PathBuf,
    pub reason: String,
}

impl SavedStates {
    /// The states in `dir` of the run `owner` names.
    pub fn new(dir: &Path, owner: Fingerprint) -> Self {
        Self {
            dir: dir.to_path_buf(),
            owner,
        }
    }

    /// Writes `state` as `name` (atomically); returns the file's checksum, which a record may
    /// hold to tell a replaced file from the one it was written with.
    pub fn save(&self, name: &str, state: &InterfaceState) -> anyhow::Result<String> {
        let bytes = encode_state(state, self.owner);
        super::write_atomic(&self.dir.join(name), &bytes)?;
        Ok(checksum_text(&bytes))
    }

    /// Reads `name` back, checked whole, against the checksum a record holds (`recorded`) and
    /// the layout of `problem`.
    pub fn load(
        &self,
        name: &str,
        recorded: Option<&str>,
        problem: &Problem,
    ) -> Result<InterfaceState, Unusable> {
        let path = self.dir.join(name);
        let fail = |reason: String| Unusable {
            path: path.clone(),
            reason,
        };
        let bytes = std::fs::read(&path).map_err(|e| fail(format!("unreadable: {e}")))?;
        if let Some(recorded) = recorded {
            let computed = checksum_text(&bytes);
            if computed != recorded {
                return Err(fail(format!(
                    "checksum mismatch (recorded {recorded}, computed {computed}): the file is \
                     damaged or was replaced"
                )));
            }
        }
        let state = decode_state(&bytes, self.owner).map_err(|e| fail(format!("{e:#}")))?;
        state
            .check_fits(problem)
            .map_err(|e| fail(format!("does not fit the problem: {e}")))?;
        Ok(state)
    }
}

/// A state file's checksum as records write it.
fn checksum_text(bytes: &[u8]) -> String {
    format!("{:08x}", file_checksum(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem_and_state() -> (Problem, InterfaceState) {
        let problem = lopin_core::scene::problem_of(
            &lopin_core::scene::load("mini-blocks").expect("scene"),
            "mini-blocks",
        )
        .expect("builds");
        let mut state = InterfaceState::cold(&problem);
        for (k, h) in state.subs.iter_mut().enumerate() {
            for (j, x) in h.f.iter_mut().enumerate() {
                *x = (k * 31 + j) as f64 * 1e-3;
            }
        }
        (problem, state)
    }

    /// A state reads back bit for bit; a flipped byte, another run's fingerprint, a replaced
    /// file and a missing one are each refused with the file's path and the reason.
    #[test]
    fn states_read_back_exactly_and_every_damage_is_named() {
        let dir = std::env::temp_dir().join(format!("lopin-saved-states-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("tmp");
        let (problem, state) = problem_and_state();
        let owner = Fingerprint::of_parts(&[("test", b"run a")]);
        let saved = SavedStates::new(dir.as_path(), owner);
        let sum = saved.save("s.state", &state).expect("writes");
        let back = saved.load("s.state", Some(&sum), &problem).expect("reads");
        assert_eq!(back.subs, state.subs);

        let other = SavedStates::new(dir.as_path(), Fingerprint::of_parts(&[("test", b"run b")]));
        let e = other
            .load("s.state", None, &problem)
            .expect_err("another run");
        assert!(e.reason.contains("belongs to another"), "{}", e.reason);

        let e = saved
            .load("s.state", Some("00000000"), &problem)
            .expect_err("another checksum");
        assert!(e.reason.contains("checksum mismatch"), "{}", e.reason);

        let path = dir.as_path().join("s.state");
        let mut bytes = std::fs::read(&path).expect("read");
        let middle = bytes.len() / 2;
        bytes[middle] ^= 0x40;
        std::fs::write(&path, &bytes).expect("write");
        let e = saved.load("s.state", None, &problem).expect_err("flipped");
        assert_eq!(e.path, path);

        let e = saved
            .load("none.state", None, &problem)
            .expect_err("missing");
        assert!(e.reason.starts_with("unreadable"), "{}", e.reason);
        std::fs::remove_dir_all(&dir).expect("cleans up");
    }
}
