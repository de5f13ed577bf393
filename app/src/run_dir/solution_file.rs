//! Binary files of interface fields (little-endian u64 sizes and f64 values): a sweep value's
//! warm-start state s = (F, W) (`LOPINST1`, METHOD §8) and a run's converged solution, s and
//! ŝ = (F̂, Ŵ) of every interface side (`LOPINSO1`, METHOD §6), from which `lopin export`
//! replays the fields without solving again.

use anyhow::{bail, Context};
use lopin_core::state::{InterfaceState, TraceHistory};
use lopin_core::Solution;
use std::path::Path;

const STATE_MAGIC: &[u8; 8] = b"LOPINST1";
const SOLUTION_MAGIC: &[u8; 8] = b"LOPINSO1";

/// Encodes a warm-start state.
pub fn encode_state(s: &InterfaceState) -> Vec<u8> {
    let mut b = Vec::with_capacity(24 + 16 * s.size());
    b.extend_from_slice(STATE_MAGIC);
    put_state(&mut b, s);
    b
}

/// Decodes a warm-start state.
pub fn decode_state(bytes: &[u8]) -> anyhow::Result<InterfaceState> {
    let mut r = Reader { b: bytes, pos: 0 };
    r.magic(STATE_MAGIC)?;
    let s = r.state()?;
    r.end()?;
    Ok(s)
}

/// Encodes a converged solution: iterations, η, convergence flag, s, then ŝ per interface side.
pub fn encode_solution(sol: &Solution) -> Vec<u8> {
    let hats: usize = sol.hats.iter().flatten().map(|h| h.f.len() * 2).sum();
    let mut b = Vec::with_capacity(64 + 16 * sol.state.size() + 8 * hats);
    b.extend_from_slice(SOLUTION_MAGIC);
    put_u64(&mut b, sol.iterations);
    b.extend_from_slice(&sol.eta.to_le_bytes());
    put_u64(&mut b, usize::from(sol.converged));
    put_state(&mut b, &sol.state);
    put_u64(&mut b, sol.hats.len());
    for sides in &sol.hats {
        put_u64(&mut b, sides.len());
        for h in sides {
            put_u64(&mut b, h.len);
        }
    }
    for h in sol.hats.iter().flatten() {
        put_values(&mut b, &h.f);
        put_values(&mut b, &h.w);
    }
    b
}

/// Decodes a converged solution (η history is not stored: run.json holds it).
pub fn decode_solution(bytes: &[u8]) -> anyhow::Result<Solution> {
    let mut r = Reader { b: bytes, pos: 0 };
    r.magic(SOLUTION_MAGIC)?;
    let iterations = r.word()?;
    let eta = r.value()?;
    let converged = r.word()? != 0;
    let state = r.state()?;
    let steps = state.steps;
    let interfaces = r.word()?;
    let mut shapes = Vec::new();
    for _ in 0..interfaces.min(bytes.len()) {
        let sides = r.word()?;
        let lens = (0..sides.min(bytes.len()))
            .map(|_| r.word())
            .collect::<anyhow::Result<Vec<_>>>()?;
        shapes.push(lens);
    }
    let mut hats = Vec::with_capacity(shapes.len());
    for lens in shapes {
        let mut sides = Vec::with_capacity(lens.len());
        for len in lens {
            let f = r.values(len * (steps + 1))?;
            let w = r.values(len * (steps + 1))?;
            sides.push(TraceHistory { len, f, w });
        }
        hats.push(sides);
    }
    r.end()?;
    Ok(Solution {
        state,
        hats,
        iterations,
        eta,
        eta_history: Vec::new(),
        converged,
        cancelled: false,
    })
}

/// Reads and decodes a solution file, naming the file in errors.
pub fn read_solution(path: &Path) -> anyhow::Result<Solution> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    decode_solution(&bytes)
        .with_context(|| format!("{}: not a Lopin solution file", path.display()))
}

fn put_u64(b: &mut Vec<u8>, x: usize) {
    b.extend_from_slice(&(x as u64).to_le_bytes());
}

fn put_values(b: &mut Vec<u8>, xs: &[f64]) {
    for x in xs {
        b.extend_from_slice(&x.to_le_bytes());
    }
}

fn put_state(b: &mut Vec<u8>, s: &InterfaceState) {
    put_u64(b, s.steps);
    put_u64(b, s.subs.len());
    for h in &s.subs {
        put_u64(b, h.len);
    }
    for h in &s.subs {
        put_values(b, &h.f);
        put_values(b, &h.w);
    }
}

/// A cursor over the bytes; every read checks the length.
struct Reader<'a> {
    b: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> anyhow::Result<&[u8]> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.b.len());
        let Some(end) = end else {
            bail!("truncated at byte {} (wanted {n} more)", self.pos);
        };
        let s = &self.b[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn magic(&mut self, m: &[u8; 8]) -> anyhow::Result<()> {
        if self.take(8)? != m {
            bail!("bad magic (expected {})", String::from_utf8_lossy(m));
        }
        Ok(())
    }

    fn word(&mut self) -> anyhow::Result<usize> {
        let s = self.take(8)?;
        Ok(u64::from_le_bytes(s.try_into().unwrap_or([0; 8])) as usize)
    }

    fn value(&mut self) -> anyhow::Result<f64> {
        let s = self.take(8)?;
        Ok(f64::from_le_bytes(s.try_into().unwrap_or([0; 8])))
    }

    fn values(&mut self, n: usize) -> anyhow::Result<Vec<f64>> {
        let bytes = self.take(n.saturating_mul(8))?;
        Ok(bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect())
    }

    fn state(&mut self) -> anyhow::Result<InterfaceState> {
        let steps = self.word()?;
        let nsubs = self.word()?;
        let lens = (0..nsubs.min(self.b.len()))
            .map(|_| self.word())
            .collect::<anyhow::Result<Vec<_>>>()?;
        let mut subs = Vec::with_capacity(lens.len());
        for len in lens {
            let count = len.saturating_mul(steps.saturating_add(1));
            let f = self.values(count)?;
            let w = self.values(count)?;
            subs.push(TraceHistory { len, f, w });
        }
        Ok(InterfaceState { steps, subs })
    }

    fn end(&self) -> anyhow::Result<()> {
        if self.pos != self.b.len() {
            bail!("{} trailing bytes", self.b.len() - self.pos);
        }
        Ok(())
    }
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
}
