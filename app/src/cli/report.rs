//! The reports of a solve, shared by `lopin run`, `lopin reference` and `lopin compare`: one set
//! of `Serialize` types for their `--json` objects ([`SolveReport`], generic over the part that
//! depends on the method, so the common shape of a LATIN and a reference report is one type),
//! and the key–value summary tables (comfy-table) with the energy and contact rows they share.

use comfy_table::{presets, CellAlignment, Table};
use lopin_core::post::Summary;
use lopin_core::scene::SceneSpec;
use lopin_core::stages::indicator::StopTest;
use lopin_core::window_choice::WindowChoice;
use lopin_core::{Solution, Solver};
use serde::Serialize;

use crate::run_dir::run_json::ProblemFacts;

/// The `--json` object of a solve: the fields every solver reports, plus the method's own
/// (`M`: its settings and sizes, flattened into the same object).
#[derive(Debug, Clone, Serialize)]
pub struct SolveReport<M> {
    pub scene: String,
    /// "latin" or "monolithic".
    pub solver: &'static str,
    #[serde(flatten)]
    pub sizes: ProblemFacts,
    #[serde(flatten)]
    pub method: M,
    pub factorizations: usize,
    pub macro_dofs: Option<usize>,
    pub peak_memory_bytes: Option<u64>,
    /// The preload's static phase (LATIN, when the scene has a preload).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preload: Option<Preload>,
    pub iterations: usize,
    pub eta: f64,
    /// η̄, the indicator on step-averaged fields (LATIN only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eta_smooth: Option<f64>,
    pub converged: bool,
    pub wall_s: f64,
    pub stages_s: Stages,
    pub energy: Energy,
    pub contact: Contact,
}

/// The "preload" object of a report: the static phase's iterations, η, search direction and
/// seconds.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Preload {
    pub iterations: usize,
    pub eta: f64,
    pub k: f64,
    pub wall_s: f64,
}

/// Seconds per stage of a solve.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Stages {
    pub setup: f64,
    pub local: f64,
    pub linear: f64,
    /// Of the linear stage, the macro problem (LATIN only).
    #[serde(rename = "macro", skip_serializing_if = "Option::is_none")]
    pub macro_s: Option<f64>,
    pub post: f64,
}

/// The "energy" object of a report.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Energy {
    pub kinetic_end: f64,
    pub strain_end: f64,
    pub input_work: f64,
    #[serde(skip_serializing_if = "is_zero")]
    pub damping_work: f64,
    pub max_total_over_input: f64,
}

/// True for an undamped run's dissipated energy, left out of the report.
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// The "contact" object of a report.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Contact {
    pub max_slip: f64,
    pub peak_normal_force: f64,
    pub min_gap: Option<f64>,
}

impl From<&Summary> for Energy {
    fn from(s: &Summary) -> Self {
        Energy {
            kinetic_end: s.kinetic_end,
            strain_end: s.strain_end,
            input_work: s.input_work,
            damping_work: s.damping_work,
            max_total_over_input: s.max_total_over_input,
        }
    }
}

impl From<&Summary> for Contact {
    fn from(s: &Summary) -> Self {
        Contact {
            max_slip: s.max_slip,
            peak_normal_force: s.peak_normal_force,
            min_gap: s.min_gap,
        }
    }
}

/// What only a LATIN report holds.
#[derive(Debug, Clone, Serialize)]
pub struct Latin {
    pub settings: LatinSettings,
}

/// The LATIN settings of a report.
#[derive(Debug, Clone, Serialize)]
pub struct LatinSettings {
    pub k: f64,
    pub mu: f64,
    pub tol: f64,
    pub max_iter: usize,
    pub window: Option<usize>,
    #[serde(rename = "macro")]
    pub two_scale: bool,
    pub directions: lopin_core::interfaces::search_direction::Directions,
    /// Which indicator ended the windows.
    pub stop: lopin_core::stages::indicator::StopTest,
    /// Anderson depth (0: plain relaxation).
    pub anderson: usize,
    /// Where cold windows start.
    pub window_start: lopin_core::scene::settings::WindowStart,
    /// The precision the factors keep.
    pub factors: lopin_core::scene::settings::FactorPrecision,
    /// Why these windows (absent where the command set them itself).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub window_reason: Option<String>,
}

/// Everything a run reports.
pub struct RunReport<'a> {
    spec: &'a SceneSpec,
    solver: &'a Solver,
    solution: &'a Solution,
    summary: &'a Summary,
    wall_s: f64,
    windows: Option<&'a WindowChoice>,
}

impl<'a> RunReport<'a> {
    pub fn new(
        spec: &'a SceneSpec,
        solver: &'a Solver,
        solution: &'a Solution,
        summary: &'a Summary,
        wall_s: f64,
    ) -> Self {
        Self {
            spec,
            solver,
            solution,
            summary,
            wall_s,
            windows: None,
        }
    }

    /// Says in the report why the solve ran on these windows.
    pub fn with_windows(mut self, windows: &'a WindowChoice) -> Self {
        self.windows = Some(windows);
        self
    }

    /// The `--json` object.
    pub fn report(&self) -> SolveReport<Latin> {
        let set = self.solver.settings();
        let st = self.solver.counters().stage_times();
        SolveReport {
            scene: self.spec.name.clone(),
            solver: "latin",
            sizes: ProblemFacts::of(self.solver.problem()),
            method: Latin {
                settings: LatinSettings {
                    k: set.k,
                    mu: set.mu,
                    tol: set.tol,
                    max_iter: set.max_iter,
                    window: set.window,
                    two_scale: set.two_scale,
                    directions: set.directions,
                    stop: set.stop,
                    anderson: set.anderson,
                    window_start: set.window_start,
                    factors: set.factors,
                    window_reason: self.windows.map(|w| w.reason.clone()),
                },
            },
            factorizations: self.solver.factors().len(),
            macro_dofs: self.macro_dofs(),
            peak_memory_bytes: peak_memory_bytes(),
            preload: self.solver.preload().map(|r| Preload {
                iterations: r.iterations,
                eta: r.eta,
                k: r.k,
                wall_s: r.seconds,
            }),
            iterations: self.solution.iterations,
            eta: self.solution.eta,
            eta_smooth: self.solution.eta_smooth,
            converged: self.solution.converged,
            wall_s: self.wall_s,
            stages_s: Stages {
                setup: st.setup,
                local: st.local,
                linear: st.linear,
                macro_s: Some(self.macro_seconds()),
                post: st.post,
            },
            energy: self.summary.into(),
            contact: self.summary.into(),
        }
    }

    /// The summary rows (sizes, settings, iterations, times, energy and contact).
    pub fn rows(&self) -> Rows {
        let p = self.solver.problem();
        let set = self.solver.settings();
        let st = self.solver.counters().stage_times();
        let sol = self.solution;
        let mut rows = Rows::default();
        rows.row("scene", &self.spec.name);
        rows.row("substructures", p.subs.len());
        rows.row(
            "interfaces (contact)",
            format!("{} ({})", p.interfaces.len(), p.contact_count()),
        );
        rows.row("dofs", p.dof_count());
        rows.row(
            "steps x dt",
            format!("{} x {:.3e} s", p.time.steps, p.time.dt),
        );
        rows.row(
            "k, mu, tol",
            format!("{:.4e} Pa.s/m, {}, {:.0e}", set.k, set.mu, set.tol),
        );
        rows.row("window", {
            let windows = match self.windows {
                Some(w) => w.to_string(),
                None => set
                    .window
                    .map_or("whole interval".to_string(), |w| format!("{w} steps")),
            };
            match set.window {
                Some(_) => {
                    let start = set.window_start.resolve(set.tol);
                    if start == set.window_start {
                        format!("{windows}; start {}", start.name())
                    } else {
                        format!(
                            "{windows}; start {} (auto at tol {:.0e})",
                            start.name(),
                            set.tol
                        )
                    }
                }
                None => windows,
            }
        });
        rows.row(
            "linear stage",
            match self.macro_dofs() {
                Some(n) => format!("two-scale ({n} macro dofs)"),
                None => "single-scale".into(),
            },
        );
        rows.row(
            "factorizations",
            format!(
                "{} distinct for {} substructures, {} ({})",
                self.solver.factors().len(),
                p.subs.len(),
                lopin_core::estimate::bytes(self.solver.factor_bytes()),
                precision_words(set.factors, &self.solver.factors())
            ),
        );
        if let Some(r) = self.solver.preload() {
            rows.row(
                "preload (statics)",
                format!(
                    "{} iterations, eta {:.2e}, k {:.3e} Pa/m, {:.3} s",
                    r.iterations, r.eta, r.k, r.seconds
                ),
            );
        }
        rows.row(
            "iterations",
            format!(
                "{}{}",
                sol.iterations,
                if sol.converged {
                    ""
                } else {
                    "  (NOT converged)"
                }
            ),
        );
        let stop = |t: StopTest| {
            if set.stop == t {
                "  (stopping test)"
            } else {
                ""
            }
        };
        rows.row("eta", format!("{:.3e}{}", sol.eta, stop(StopTest::Eta)));
        if let Some(e) = sol.eta_smooth {
            rows.row(
                "eta smooth",
                format!("{e:.3e}{}  (step-averaged fields)", stop(StopTest::Smooth)),
            );
        }
        rows.row("time setup", format!("{:.3} s", st.setup));
        rows.row("time local stage", format!("{:.3} s", st.local));
        rows.row("time linear stage", format!("{:.3} s", st.linear));
        if set.two_scale {
            rows.row("  of which macro", format!("{:.3} s", self.macro_seconds()));
        }
        rows.row("time post", format!("{:.3} s", st.post));
        rows.row("wall time", format!("{:.3} s", self.wall_s));
        if let Some(b) = peak_memory_bytes() {
            rows.row("peak memory", lopin_core::estimate::bytes(b as usize));
        }
        rows.summary(self.summary);
        rows
    }

    /// Size of the macro problem when the linear stage is two-scale.
    fn macro_dofs(&self) -> Option<usize> {
        let two_scale = self.solver.settings().two_scale;
        self.solver
            .macro_problem()
            .filter(|_| two_scale)
            .map(|m| m.size)
    }

    /// Seconds in the macro problem (right-hand sides and solves) over the solve.
    fn macro_seconds(&self) -> f64 {
        self.solver
            .counters()
            .iterations
            .iter()
            .map(|r| r.macro_s)
            .sum()
    }
}

/// Peak resident memory of this process (VmHWM of /proc/self/status; None where there is none).
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// The rows of a key–value summary table.
#[derive(Debug, Clone, Default)]
pub struct Rows(Vec<(String, String)>);

impl Rows {
    /// Appends one row.
    pub fn row(&mut self, key: impl Into<String>, value: impl ToString) {
        self.0.push((key.into(), value.to_string()));
    }

    /// The energy and contact rows of a summary.
    pub fn summary(&mut self, s: &Summary) {
        self.row("kinetic energy (end)", format!("{:.4e} J", s.kinetic_end));
        self.row("strain energy (end)", format!("{:.4e} J", s.strain_end));
        self.row("input work", format!("{:.4e} J", s.input_work));
        if s.damping_work != 0.0 {
            self.row("damping dissipated", format!("{:.4e} J", s.damping_work));
        }
        self.row(
            "max E/(E0 + input)",
            format!("{:.6}", s.max_total_over_input),
        );
        if let Some(g) = s.min_gap {
            self.row(
                "contact: peak normal force",
                format!("{:.4e} N", s.peak_normal_force),
            );
            self.row("contact: max slip", format!("{:.4e} m", s.max_slip));
            self.row("contact: min gap", format!("{g:.4e} m"));
        }
    }

    /// The two-column table, keys left, values left.
    pub fn table(&self) -> Table {
        let mut t = plain_table();
        for (k, v) in &self.0 {
            t.add_row([k, v]);
        }
        t
    }
}

impl std::fmt::Display for Rows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}", self.table().trim_fmt())
    }
}

/// A borderless table (columns separated by spaces).
pub fn plain_table() -> Table {
    let mut t = Table::new();
    t.load_preset(presets::NOTHING);
    t
}

/// Borders of [`column_table`]: only the line under the header (comfy-table's preset order:
/// left, right, top, bottom, then the header line is the sixth).
const HEADER_LINE_ONLY: &str = "     -             ";

/// A table with a header row underlined, every column but the first right-aligned (numbers).
/// Print it with `trim_fmt` (no trailing spaces).
pub fn column_table<S: ToString>(header: impl IntoIterator<Item = S>) -> Table {
    let mut t = Table::new();
    t.load_preset(HEADER_LINE_ONLY);
    t.set_header(header.into_iter().map(|h| h.to_string()));
    for c in t.column_iter_mut().skip(1) {
        c.set_cell_alignment(CellAlignment::Right);
    }
    t
}

/// A Markdown table (for the guide).
pub fn markdown_table<S: ToString>(header: impl IntoIterator<Item = S>) -> Table {
    let mut t = Table::new();
    t.load_preset(presets::ASCII_MARKDOWN);
    t.set_header(header.into_iter().map(|h| h.to_string()));
    t
}

/// The precision the factors keep, in words: `single precision`, `double precision`, or for
/// `auto` which it chose (`auto: 2 single, 6 double`).
fn precision_words(
    asked: lopin_core::scene::settings::FactorPrecision,
    factors: &[&lopin_core::linalg::factor::CholeskyFactor],
) -> String {
    let single = factors.iter().filter(|f| f.is_single()).count();
    let words = match (single, factors.len() - single) {
        (0, _) => "double precision".to_string(),
        (_, 0) => "single precision".to_string(),
        (s, d) => format!("{s} single, {d} double"),
    };
    if asked.is_auto() && !factors.is_empty() {
        format!("auto: {words}")
    } else {
        words
    }
}
