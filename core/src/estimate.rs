//! Memory and time estimates of a solve, printed before a large run. Memory follows METHOD §11:
//! per interface side and step, F, W, F̂, Ŵ (4 × dim doubles per node), plus what Lopin keeps
//! beside them (the unrelaxed linear-stage output, the skip cache of whole-interval runs), the
//! assembled operators and the homogenized operators Z_E (METHOD §9). Time: the triangular
//! solves dominate an iteration (METHOD §11 cost model); their cost is measured once per
//! distinct factorization and multiplied out.

use crate::counters::Instant;
use crate::problem::Problem;
use crate::solver::{Settings, Solver};

/// Bytes per double.
const F64: usize = 8;

/// What a solve will hold and cost.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Estimate {
    /// Degrees of freedom.
    pub dofs: usize,
    /// Substructures.
    pub substructures: usize,
    /// Interfaces (of which contact).
    pub interfaces: usize,
    /// Contact interfaces.
    pub contact_interfaces: usize,
    /// Trace entries over all substructures (Σ interface-side dofs).
    pub trace_entries: usize,
    /// Time steps N.
    pub steps: usize,
    /// Bytes of the interface fields: s (F, W) and the linear stage output per substructure
    /// trace, ŝ (F̂, Ŵ) per interface side, steps 0..N (METHOD §11: 32·dim·N·Σ nodes, plus the
    /// unrelaxed copy).
    pub interface_bytes: usize,
    /// Bytes of the skip cache of whole-interval runs (inputs and outputs of every substructure's
    /// last linear stage; 0 for windowed runs).
    pub cache_bytes: usize,
    /// Bytes of the assembled stiffness matrices, mass and per-substructure work vectors.
    pub operator_bytes: usize,
    /// Bytes of the factorizations (known once factorized).
    pub factor_bytes: Option<usize>,
    /// Bytes of the homogenized operators Z_E, L_E (two-scale, known once built).
    pub macro_bytes: Option<usize>,
    /// Distinct factorizations (known once factorized).
    pub factorizations: Option<usize>,
    /// Seconds of the triangular solves of one iteration over the whole interval, on the
    /// threads available (known once factorized and measured).
    pub iteration_s: Option<f64>,
}

impl Estimate {
    /// The memory estimate of a problem under some settings, before anything is factorized.
    pub fn of(problem: &Problem, settings: &Settings) -> Self {
        let n1 = problem.time.steps + 1;
        let trace: usize = problem.subs.iter().map(|s| s.trace_len()).sum();
        let sides: usize = problem
            .interfaces
            .iter()
            .map(|i| i.len * i.sides.len())
            .sum();
        let interface_bytes = 2 * F64 * n1 * (2 * trace + sides);
        let whole = settings.window.is_none_or(|w| w >= problem.time.steps);
        let cache_bytes = if whole && settings.skip_unchanged && !settings.two_scale {
            4 * F64 * n1 * trace
        } else {
            0
        };
        let mut seen = std::collections::HashSet::new();
        let operator_bytes = problem
            .subs
            .iter()
            .map(|s| {
                // shared stiffness matrices count once
                let k = if seen.insert(std::sync::Arc::as_ptr(&s.stiffness)) {
                    s.stiffness.bytes()
                } else {
                    0
                };
                // mass, LinearWork (7 vectors) and the window-start state (5 vectors)
                k + 13 * s.ndof() * F64
            })
            .sum();
        Self {
            dofs: problem.dof_count(),
            substructures: problem.subs.len(),
            interfaces: problem.interfaces.len(),
            contact_interfaces: problem.contact_count(),
            trace_entries: trace,
            steps: problem.time.steps,
            interface_bytes,
            cache_bytes,
            operator_bytes,
            factor_bytes: None,
            macro_bytes: None,
            factorizations: None,
            iteration_s: None,
        }
    }

    /// The full estimate of a factorized solver: memory of its factors and macro problem, and
    /// the time of one whole-interval iteration's triangular solves, measured on one solve of
    /// each distinct factorization.
    pub fn of_solver(solver: &Solver) -> Self {
        let p = solver.problem();
        let mut e = Self::of(p, solver.settings());
        e.factorizations = Some(solver.factors().len());
        e.factor_bytes = Some(solver.factor_bytes());
        e.macro_bytes = solver.macro_problem().map(|mp| {
            mp.homogenized
                .iter()
                .map(|h| (h.z.len() + h.l.len()) * F64)
                .sum::<usize>()
                + mp.factor_nnz() * (F64 + std::mem::size_of::<usize>())
        });
        // one measured solve per class, weighted by the class size
        let classes = solver.classes();
        let mut members = vec![0usize; classes.count()];
        classes.of.iter().for_each(|&c| members[c] += 1);
        let mut per_step = 0.0;
        for (c, f) in solver.class_factors() {
            let mut x: Vec<f64> = (0..f.n()).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut scratch = f.scratch();
            let reps = 3;
            let start = Instant::now();
            for _ in 0..reps {
                f.solve_in_place(&mut x, &mut scratch);
            }
            per_step += members[c] as f64 * start.elapsed().as_secs_f64() / reps as f64;
        }
        let threads = threads();
        e.iteration_s = Some(per_step * p.time.steps as f64 / threads as f64);
        e
    }

    /// Total bytes known so far.
    pub fn total_bytes(&self) -> usize {
        self.interface_bytes
            + self.cache_bytes
            + self.operator_bytes
            + self.factor_bytes.unwrap_or(0)
            + self.macro_bytes.unwrap_or(0)
    }

    /// Whether a run is large enough to announce (over 200,000 dofs or 1 GiB).
    pub fn is_large(&self) -> bool {
        self.dofs > 200_000 || self.total_bytes() > 1 << 30
    }

    /// Human-readable lines.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![
            format!(
                "{} dofs, {} substructures, {} interfaces ({} contact), {} trace entries, {} steps",
                self.dofs,
                self.substructures,
                self.interfaces,
                self.contact_interfaces,
                self.trace_entries,
                self.steps
            ),
            format!(
                "memory: interface fields {} + skip cache {} + operators {}{}{} = {}",
                bytes(self.interface_bytes),
                bytes(self.cache_bytes),
                bytes(self.operator_bytes),
                self.factor_bytes
                    .map_or(String::new(), |b| format!(" + factors {}", bytes(b))),
                self.macro_bytes
                    .map_or(String::new(), |b| format!(" + macro {}", bytes(b))),
                bytes(self.total_bytes())
            ),
        ];
        if let Some(f) = self.factorizations {
            out.push(format!(
                "{f} distinct factorization{} for {} substructures",
                if f == 1 { "" } else { "s" },
                self.substructures
            ));
        }
        if let Some(t) = self.iteration_s {
            out.push(format!(
                "time: about {:.2} s of triangular solves per iteration over the whole interval \
                 ({:.3} s per one-step window iteration) on {} thread{}",
                t,
                t / self.steps.max(1) as f64,
                threads(),
                if threads() == 1 { "" } else { "s" }
            ));
        }
        out
    }
}

fn threads() -> usize {
    #[cfg(feature = "parallel")]
    {
        rayon::current_num_threads()
    }
    #[cfg(not(feature = "parallel"))]
    {
        1
    }
}

/// Bytes in B, KiB, MiB, GiB, TiB, PiB or EiB.
pub fn bytes(b: usize) -> String {
    crate::scene::admission::bytes(b as u64)
}
