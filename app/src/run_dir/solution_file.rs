//! Binary files of interface fields, through serde and postcard: a sweep value's warm-start
//! state s = (F, W) (`value-NNN.state`, METHOD §8) and a run's converged solution, s and
//! ŝ = (F̂, Ŵ) of every interface side (`solution.bin`, METHOD §6), from which `lopin export`
//! replays the fields without solving again. Each file starts with an 8-byte magic naming its
//! kind and format version (`LOPINST2`, `LOPINSO2`); a file of another kind, of an older
//! format (`…1`, Lopin's hand-written codec) or not Lopin's at all is refused with that said.
//! The core's [`InterfaceState`] and [`TraceHistory`] are written through mirror types.

use std::borrow::Cow;
use std::path::Path;

use anyhow::{bail, Context};
use lopin_core::state::{InterfaceState, TraceHistory};
use lopin_core::Solution;
use serde::{Deserialize, Serialize};

/// Magic of a warm-start state file, format 2 (postcard).
const STATE_MAGIC: [u8; 8] = *b"LOPINST2";
/// Magic of a solution file, format 2 (postcard).
const SOLUTION_MAGIC: [u8; 8] = *b"LOPINSO2";

/// One trace history: `len` values per step, F and W over steps 0..=N.
#[derive(Serialize, Deserialize)]
struct Trace<'a> {
    len: usize,
    f: Cow<'a, [f64]>,
    w: Cow<'a, [f64]>,
}

/// s = (F, W) of every substructure trace.
#[derive(Serialize, Deserialize)]
struct State<'a> {
    steps: usize,
    subs: Vec<Trace<'a>>,
}

/// A converged solution (its η history is in run.json).
#[derive(Serialize, Deserialize)]
struct SolutionBody<'a> {
    iterations: usize,
    eta: f64,
    converged: bool,
    state: State<'a>,
    /// ŝ per interface, per side.
    hats: Vec<Vec<Trace<'a>>>,
}

impl<'a> From<&'a TraceHistory> for Trace<'a> {
    fn from(h: &'a TraceHistory) -> Self {
        Trace {
            len: h.len,
            f: Cow::Borrowed(&h.f),
            w: Cow::Borrowed(&h.w),
        }
    }
}

impl<'a> From<&'a InterfaceState> for State<'a> {
    fn from(s: &'a InterfaceState) -> Self {
        State {
            steps: s.steps,
            subs: s.subs.iter().map(Trace::from).collect(),
        }
    }
}

impl Trace<'_> {
    /// The history, checked against the number of steps.
    fn history(self, steps: usize) -> anyhow::Result<TraceHistory> {
        let count = self.len.checked_mul(steps + 1);
        if count != Some(self.f.len()) || count != Some(self.w.len()) {
            bail!(
                "a trace of {} values per step holds {} and {} values over {} steps",
                self.len,
                self.f.len(),
                self.w.len(),
                steps + 1
            );
        }
        Ok(TraceHistory {
            len: self.len,
            f: self.f.into_owned(),
            w: self.w.into_owned(),
        })
    }
}

impl State<'_> {
    fn state(self) -> anyhow::Result<InterfaceState> {
        let steps = self.steps;
        Ok(InterfaceState {
            steps,
            subs: self
                .subs
                .into_iter()
                .map(|t| t.history(steps))
                .collect::<anyhow::Result<_>>()?,
        })
    }
}

/// The magic, then the body.
fn encode<T: Serialize>(magic: [u8; 8], body: &T) -> Vec<u8> {
    // postcard writes into a Vec without failing for these types
    postcard::to_extend(body, magic.to_vec()).unwrap_or_else(|e| unreachable!("postcard: {e}"))
}

/// Checks the magic and decodes the body, which must end the file.
fn decode<'a, T: Deserialize<'a>>(
    magic: [u8; 8],
    what: &str,
    bytes: &'a [u8],
) -> anyhow::Result<T> {
    let Some((head, body)) = bytes.split_first_chunk::<8>() else {
        bail!("truncated: {} bytes, no header", bytes.len());
    };
    if *head != magic {
        if head[..7] == magic[..7] {
            bail!(
                "a {what} file of format {}, this Lopin reads format {} ({}): remake it with this \
                 version",
                char::from(head[7]),
                char::from(magic[7]),
                String::from_utf8_lossy(&magic)
            );
        }
        bail!(
            "bad magic {:?} (expected {}, a {what} file)",
            String::from_utf8_lossy(head),
            String::from_utf8_lossy(&magic)
        );
    }
    let (value, rest) = postcard::take_from_bytes(body).context("truncated or damaged")?;
    if !rest.is_empty() {
        bail!("{} trailing bytes", rest.len());
    }
    Ok(value)
}

/// Encodes a warm-start state.
pub fn encode_state(s: &InterfaceState) -> Vec<u8> {
    encode(STATE_MAGIC, &State::from(s))
}

/// Decodes a warm-start state.
pub fn decode_state(bytes: &[u8]) -> anyhow::Result<InterfaceState> {
    decode::<State>(STATE_MAGIC, "state", bytes)?.state()
}

/// Encodes a converged solution: iterations, η, convergence flag, s, then ŝ per interface side.
pub fn encode_solution(sol: &Solution) -> Vec<u8> {
    encode(
        SOLUTION_MAGIC,
        &SolutionBody {
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            state: State::from(&sol.state),
            hats: sol
                .hats
                .iter()
                .map(|sides| sides.iter().map(Trace::from).collect())
                .collect(),
        },
    )
}

/// Decodes a converged solution (η history is not stored: run.json holds it).
pub fn decode_solution(bytes: &[u8]) -> anyhow::Result<Solution> {
    let body: SolutionBody = decode(SOLUTION_MAGIC, "solution", bytes)?;
    let state = body.state.state()?;
    let steps = state.steps;
    let hats = body
        .hats
        .into_iter()
        .map(|sides| {
            sides
                .into_iter()
                .map(|t| t.history(steps))
                .collect::<anyhow::Result<Vec<_>>>()
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok(Solution {
        state,
        hats,
        iterations: body.iterations,
        eta: body.eta,
        eta_history: Vec::new(),
        converged: body.converged,
        cancelled: false,
    })
}

/// Reads and decodes a solution file, naming the file in errors.
pub fn read_solution(path: &Path) -> anyhow::Result<Solution> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    decode_solution(&bytes)
        .with_context(|| format!("{}: not a Lopin solution file", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn history(len: usize, seed: f64) -> TraceHistory {
        TraceHistory {
            len,
            f: (0..3 * len).map(|i| seed + i as f64 * 0.5).collect(),
            w: (0..3 * len).map(|i| -seed * 1e-300 * i as f64).collect(),
        }
    }

    #[test]
    fn state_round_trips_and_truncation_is_an_error() {
        let s = InterfaceState {
            steps: 2,
            subs: vec![history(1, 1.5), history(2, -3.0)],
        };
        let b = encode_state(&s);
        assert_eq!(decode_state(&b).expect("decodes"), s);
        assert!(decode_state(&b[..b.len() - 1]).is_err());
    }

    #[test]
    fn solution_round_trips_and_damage_is_an_error() {
        let sol = Solution {
            state: InterfaceState {
                steps: 2,
                subs: vec![history(3, 1.0), history(3, 2.0)],
            },
            hats: vec![
                vec![history(3, 4.0), history(3, 5.0)],
                vec![history(1, 6.0)],
            ],
            iterations: 17,
            eta: 9.5e-4,
            eta_history: Vec::new(),
            converged: true,
            cancelled: false,
        };
        let b = encode_solution(&sol);
        let back = decode_solution(&b).expect("decodes");
        assert_eq!(back.state, sol.state);
        assert_eq!(back.hats, sol.hats);
        assert_eq!(
            (back.iterations, back.eta, back.converged),
            (17, 9.5e-4, true)
        );
        assert!(decode_solution(&b[..b.len() - 8]).is_err());
        let mut longer = b.clone();
        longer.push(0);
        assert!(decode_solution(&longer).is_err());
        assert!(decode_solution(&encode_state(&sol.state)).is_err());
    }

    #[test]
    fn old_and_foreign_files_are_refused_by_their_header() {
        let s = InterfaceState {
            steps: 0,
            subs: vec![history(1, 1.0)],
        };
        let mut old = encode_state(&s);
        old[7] = b'1';
        let e = format!("{:#}", decode_state(&old).expect_err("format 1"));
        assert!(e.contains("format 1") && e.contains("LOPINST2"), "{e}");
        let e = format!(
            "{:#}",
            decode_state(b"PK\x03\x04zipfile").expect_err("foreign")
        );
        assert!(e.contains("bad magic"), "{e}");
        assert!(decode_state(b"LOP").is_err());
    }
}
