//! Binary files of interface fields, through serde and postcard: a sweep value's warm-start
//! state s = (F, W) (`value-NNN.state`, METHOD §8) and a run's converged solution, s and
//! ŝ = (F̂, Ŵ) of every interface side (`solution.bin`, METHOD §6), from which `lopin export`
//! replays the fields without solving again. The core's [`InterfaceState`] and
//! [`TraceHistory`] are written through mirror types.
//!
//! Format 3, the layout of both kinds:
//!
//! | bytes | holds |
//! |---|---|
//! | 8 | magic naming kind and format: `LOPINST3` (state), `LOPINSO3` (solution) |
//! | 8 | the [`Fingerprint`] of the scene and settings the file belongs to (u64, little-endian) |
//! | … | the postcard body |
//! | 4 | crc32 of everything before it (u32, little-endian) |
//!
//! Reading checks, in this order, each with its own error: a header at all; the magic (a file
//! of another kind, of an older format — `…2` without checksum, `…1` Lopin's hand-written
//! codec — or not Lopin's at all is refused with that said); the checksum; the body; no
//! trailing bytes; the shapes (F and W of each trace hold `len` values per step); every value
//! finite (the error names the trace, the step and F or W); and last the fingerprint against
//! the one the caller expects. Nothing that fails one of these reaches the solver.

use std::borrow::Cow;
use std::path::Path;

use anyhow::{bail, Context};
use lopin_core::state::{InterfaceState, TraceHistory};
use lopin_core::Solution;
use serde::{Deserialize, Serialize};

use super::fingerprint::{crc32, Fingerprint};

/// Magic of a warm-start state file, format 3 (fingerprint, postcard, crc32).
const STATE_MAGIC: [u8; 8] = *b"LOPINST3";
/// Magic of a solution file, format 3 (fingerprint, postcard, crc32).
const SOLUTION_MAGIC: [u8; 8] = *b"LOPINSO3";
/// Magic and fingerprint.
const HEADER: usize = 16;
/// The crc32.
const TRAILER: usize = 4;

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

/// The magic, the fingerprint, the body, then the crc32 of all that.
fn encode<T: Serialize>(magic: [u8; 8], belongs_to: Fingerprint, body: &T) -> Vec<u8> {
    let mut head = magic.to_vec();
    head.extend_from_slice(&belongs_to.0.to_le_bytes());
    // postcard writes into a Vec without failing for these types
    let mut out = postcard::to_extend(body, head).unwrap_or_else(|e| unreachable!("postcard: {e}"));
    let sum = crc32(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// Checks the header, the magic and the checksum, and decodes the body, which must end the
/// file. Returns the stored fingerprint and the body.
fn decode<'a, T: Deserialize<'a>>(
    magic: [u8; 8],
    what: &str,
    bytes: &'a [u8],
) -> anyhow::Result<(Fingerprint, T)> {
    let Some((head, _)) = bytes.split_first_chunk::<8>() else {
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
    if bytes.len() < HEADER + TRAILER {
        bail!(
            "truncated: {} bytes, shorter than the header and checksum ({} bytes)",
            bytes.len(),
            HEADER + TRAILER
        );
    }
    let (content, trailer) = bytes.split_at(bytes.len() - TRAILER);
    let stored = u32::from_le_bytes(trailer.try_into()?);
    let computed = crc32(content);
    if stored != computed {
        bail!(
            "checksum mismatch (stored {stored:08x}, computed {computed:08x}): the file is damaged"
        );
    }
    let belongs_to = Fingerprint(u64::from_le_bytes(content[8..HEADER].try_into()?));
    let (value, rest) = postcard::take_from_bytes(&content[HEADER..])
        .context("the body does not decode (written by another program?)")?;
    if !rest.is_empty() {
        bail!("{} trailing bytes after the body", rest.len());
    }
    Ok((belongs_to, value))
}

/// The stored fingerprint must be the expected one.
fn check_belongs(stored: Fingerprint, expected: Fingerprint) -> anyhow::Result<()> {
    if stored == expected {
        return Ok(());
    }
    bail!("belongs to another scene or settings (hash {stored}, expected {expected})");
}

/// Every value of a history is finite; the error names `what`, F or W and the step.
fn check_finite(h: &TraceHistory, what: &str, [f, w]: [&str; 2]) -> anyhow::Result<()> {
    for (name, values) in [(f, &h.f), (w, &h.w)] {
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            bail!(
                "non-finite value {} in {name} of {what} at step {}",
                values[i],
                i / h.len.max(1)
            );
        }
    }
    Ok(())
}

/// Every value of a state is finite.
fn check_state_finite(s: &InterfaceState) -> anyhow::Result<()> {
    for (i, h) in s.subs.iter().enumerate() {
        check_finite(h, &format!("trace {i}"), ["F", "W"])?;
    }
    Ok(())
}

/// The checksum that names a state or solution file's content: the crc32 of everything before
/// its 4-byte trailer, i.e. the value a valid file ends with. (The crc32 of a whole file, which
/// ends with its own crc32, is the same constant, 2144df1c, for every valid file.)
pub fn file_checksum(bytes: &[u8]) -> u32 {
    crc32(&bytes[..bytes.len().saturating_sub(TRAILER)])
}

/// Encodes a warm-start state that belongs to `belongs_to`.
pub fn encode_state(s: &InterfaceState, belongs_to: Fingerprint) -> Vec<u8> {
    encode(STATE_MAGIC, belongs_to, &State::from(s))
}

/// Decodes a warm-start state, checked whole (see the module doc), that must belong to
/// `expected`.
pub fn decode_state(bytes: &[u8], expected: Fingerprint) -> anyhow::Result<InterfaceState> {
    let (belongs_to, body) = decode::<State>(STATE_MAGIC, "state", bytes)?;
    let state = body.state()?;
    check_state_finite(&state)?;
    check_belongs(belongs_to, expected)?;
    Ok(state)
}

/// Encodes a converged solution that belongs to `belongs_to` ([`super::fingerprint::of_run`]
/// of its scene and settings): iterations, η, convergence flag, s, then ŝ per interface side.
pub fn encode_solution_for(sol: &Solution, belongs_to: Fingerprint) -> Vec<u8> {
    encode(
        SOLUTION_MAGIC,
        belongs_to,
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

/// Decodes a converged solution (η history is not stored: run.json holds it), checked whole
/// (see the module doc), that must belong to `expected`.
pub fn decode_solution(bytes: &[u8], expected: Fingerprint) -> anyhow::Result<Solution> {
    let (belongs_to, body): (_, SolutionBody) = decode(SOLUTION_MAGIC, "solution", bytes)?;
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
    if !body.eta.is_finite() {
        bail!("non-finite η {}", body.eta);
    }
    check_state_finite(&state)?;
    for (e, sides) in hats.iter().enumerate() {
        for (k, h) in sides.iter().enumerate() {
            check_finite(h, &format!("interface {e} side {k}"), ["F̂", "Ŵ"])?;
        }
    }
    check_belongs(belongs_to, expected)?;
    Ok(Solution {
        state,
        hats,
        iterations: body.iterations,
        eta: body.eta,
        eta_smooth: None,
        eta_history: Vec::new(),
        converged: body.converged,
        cancelled: false,
        end: None,
    })
}

/// Reads and decodes a solution file that must belong to `expected`; errors name the file.
pub fn read_solution(path: &Path, expected: Fingerprint) -> anyhow::Result<Solution> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    decode_solution(&bytes, expected).with_context(|| path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINE: Fingerprint = Fingerprint(0x0123_4567_89ab_cdef);
    const OTHER: Fingerprint = Fingerprint(0xfedc_ba98_7654_3210);

    fn history(len: usize, seed: f64) -> TraceHistory {
        TraceHistory {
            len,
            f: (0..3 * len).map(|i| seed + i as f64 * 0.5).collect(),
            w: (0..3 * len).map(|i| -seed * 1e-300 * i as f64).collect(),
        }
    }

    fn state() -> InterfaceState {
        InterfaceState {
            steps: 2,
            subs: vec![history(1, 1.5), history(2, -3.0)],
        }
    }

    fn solution() -> Solution {
        Solution {
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
            eta_smooth: None,
            eta_history: Vec::new(),
            converged: true,
            cancelled: false,
            end: None,
        }
    }

    /// A file of `magic` with `body` as its postcard bytes and a valid checksum.
    fn sealed(magic: [u8; 8], belongs_to: Fingerprint, body: &[u8]) -> Vec<u8> {
        let mut out = magic.to_vec();
        out.extend_from_slice(&belongs_to.0.to_le_bytes());
        out.extend_from_slice(body);
        let sum = crc32(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    fn err<T: std::fmt::Debug>(r: anyhow::Result<T>) -> String {
        format!("{:#}", r.expect_err("an error"))
    }

    #[test]
    fn the_file_checksum_tells_valid_files_apart() {
        let mut other = state();
        other.subs[0].f[0] += 1.0;
        let (a, b) = (encode_state(&state(), MINE), encode_state(&other, MINE));
        // the crc32 of a whole file ending with its crc32 is a constant
        assert_eq!(crc32(&a), crc32(&b));
        assert_ne!(file_checksum(&a), file_checksum(&b));
        assert_eq!(a[a.len() - 4..], file_checksum(&a).to_le_bytes());
    }

    #[test]
    fn state_round_trips_with_its_fingerprint() {
        let s = state();
        let b = encode_state(&s, MINE);
        assert_eq!(&b[..8], b"LOPINST3");
        assert_eq!(b[8..16], MINE.0.to_le_bytes());
        assert_eq!(decode_state(&b, MINE).expect("decodes"), s);
    }

    #[test]
    fn solution_round_trips_with_its_fingerprint() {
        let sol = solution();
        let b = encode_solution_for(&sol, MINE);
        assert_eq!(&b[..8], b"LOPINSO3");
        let back = decode_solution(&b, MINE).expect("decodes");
        assert_eq!(back.state, sol.state);
        assert_eq!(back.hats, sol.hats);
        assert_eq!(
            (back.iterations, back.eta, back.converged),
            (17, 9.5e-4, true)
        );
    }

    #[test]
    fn a_flipped_byte_in_the_body_is_caught_by_the_checksum() {
        for b in [
            encode_state(&state(), MINE),
            encode_solution_for(&solution(), MINE),
        ] {
            for at in [HEADER, b.len() / 2, b.len() - TRAILER - 1, 9, b.len() - 1] {
                let mut bad = b.clone();
                bad[at] ^= 0x10;
                let e = if bad[..8] == *b"LOPINST3" {
                    err(decode_state(&bad, MINE))
                } else {
                    err(decode_solution(&bad, MINE))
                };
                assert!(
                    e.starts_with("checksum mismatch (stored ")
                        && e.ends_with("the file is damaged"),
                    "byte {at}: {e}"
                );
            }
        }
    }

    #[test]
    fn truncated_and_longer_files_are_errors() {
        let b = encode_solution_for(&solution(), MINE);
        assert!(err(decode_solution(&b[..5], MINE)).contains("no header"));
        assert!(err(decode_solution(&b[..18], MINE)).contains("truncated: 18 bytes"));
        assert!(err(decode_solution(&b[..b.len() - 8], MINE)).contains("checksum mismatch"));
        let mut longer = b.clone();
        longer.push(0);
        assert!(err(decode_solution(&longer, MINE)).contains("checksum mismatch"));
        // a solution is not a state
        assert!(err(decode_solution(&encode_state(&state(), MINE), MINE)).contains("bad magic"));
    }

    #[test]
    fn a_body_that_does_not_decode_or_has_trailing_bytes_is_an_error_despite_its_checksum() {
        let e = err(decode_state(&sealed(STATE_MAGIC, MINE, &[0xff; 12]), MINE));
        assert!(e.contains("the body does not decode"), "{e}");
        let body = postcard::to_stdvec(&State::from(&state())).expect("encodes");
        let mut longer = body.clone();
        longer.extend_from_slice(&[1, 2, 3]);
        let e = err(decode_state(&sealed(STATE_MAGIC, MINE, &longer), MINE));
        assert_eq!(e, "3 trailing bytes after the body");
    }

    #[test]
    fn a_shape_that_does_not_match_its_steps_is_an_error_despite_its_checksum() {
        let mut s = state();
        s.subs[1].w.pop();
        let body = postcard::to_stdvec(&State::from(&s)).expect("encodes");
        let e = err(decode_state(&sealed(STATE_MAGIC, MINE, &body), MINE));
        assert!(e.contains("holds 6 and 5 values over 3 steps"), "{e}");
    }

    #[test]
    fn a_nan_written_with_a_valid_checksum_is_caught_by_the_finiteness_check() {
        let mut s = state();
        s.subs[1].f[2 * 2 + 1] = f64::NAN;
        let e = err(decode_state(&encode_state(&s, MINE), MINE));
        assert_eq!(e, "non-finite value NaN in F of trace 1 at step 2");
        let mut s = state();
        s.subs[0].w[1] = f64::NEG_INFINITY;
        let e = err(decode_state(&encode_state(&s, MINE), MINE));
        assert_eq!(e, "non-finite value -inf in W of trace 0 at step 1");
        let mut sol = solution();
        sol.hats[0][1].f[4] = f64::INFINITY;
        let e = err(decode_solution(&encode_solution_for(&sol, MINE), MINE));
        assert_eq!(
            e,
            "non-finite value inf in F̂ of interface 0 side 1 at step 1"
        );
        let mut sol = solution();
        sol.state.subs[1].w[8] = f64::NAN;
        let e = err(decode_solution(&encode_solution_for(&sol, MINE), MINE));
        assert_eq!(e, "non-finite value NaN in W of trace 1 at step 2");
    }

    #[test]
    fn a_file_of_another_scene_or_settings_is_refused() {
        let e = err(decode_state(&encode_state(&state(), OTHER), MINE));
        assert_eq!(
            e,
            format!("belongs to another scene or settings (hash {OTHER}, expected {MINE})")
        );
        let e = err(decode_solution(
            &encode_solution_for(&solution(), OTHER),
            MINE,
        ));
        assert!(e.starts_with("belongs to another scene or settings"), "{e}");
    }

    #[test]
    fn old_and_foreign_files_are_refused_by_their_header() {
        let mut old = encode_state(&state(), MINE);
        old[7] = b'2';
        let e = err(decode_state(&old, MINE));
        assert!(
            e.contains("state file of format 2") && e.contains("LOPINST3") && e.contains("remake"),
            "{e}"
        );
        old[7] = b'1';
        assert!(err(decode_state(&old, MINE)).contains("format 1"));
        let e = err(decode_state(b"PK\x03\x04zipfile", MINE));
        assert!(e.contains("bad magic"), "{e}");
        assert!(decode_state(b"LOP", MINE).is_err());
    }
}
