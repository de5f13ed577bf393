//! The report of a run: the JSON object of `lopin run --json` and the human summary table.

use lopin_core::post::Summary;
use lopin_core::scene::SceneSpec;
use lopin_core::{Solution, Solver};
use serde_json::{json, Value};

/// Everything a run reports.
pub struct RunReport<'a> {
    spec: &'a SceneSpec,
    solver: &'a Solver,
    solution: &'a Solution,
    summary: &'a Summary,
    wall_s: f64,
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
        }
    }

    pub fn to_json(&self) -> Value {
        let macro_s = self.macro_seconds();
        let p = self.solver.problem();
        let set = self.solver.settings();
        let st = self.solver.counters().stage_times();
        let s = self.summary;
        json!({
            "scene": self.spec.name,
            "solver": "latin",
            "substructures": p.subs.len(),
            "interfaces": p.interfaces.len(),
            "contact_interfaces": p.contact_count(),
            "dofs": p.dof_count(),
            "steps": p.time.steps,
            "dt": p.time.dt,
            "settings": {
                "k": set.k, "mu": set.mu, "tol": set.tol, "max_iter": set.max_iter,
                "window": set.window, "macro": set.two_scale,
            },
            "factorizations": self.solver.factors().len(),
            "macro_dofs": self.solver.macro_problem().filter(|_| set.two_scale).map(|m| m.size),
            "peak_memory_bytes": peak_memory_bytes(),
            "iterations": self.solution.iterations,
            "eta": self.solution.eta,
            "converged": self.solution.converged,
            "wall_s": self.wall_s,
            "stages_s": {
                "setup": st.setup, "local": st.local, "linear": st.linear, "macro": macro_s,
                "post": st.post,
            },
            "energy": energy_json(s),
            "contact": contact_json(s),
        })
    }

    pub fn table(&self) -> String {
        let p = self.solver.problem();
        let set = self.solver.settings();
        let st = self.solver.counters().stage_times();
        let sol = self.solution;
        let mut out = String::new();
        let mut row = |k: &str, v: String| out.push_str(&row(k, v));
        row("scene", self.spec.name.clone());
        row("substructures", p.subs.len().to_string());
        row(
            "interfaces (contact)",
            format!("{} ({})", p.interfaces.len(), p.contact_count()),
        );
        row("dofs", p.dof_count().to_string());
        row(
            "steps x dt",
            format!("{} x {:.3e} s", p.time.steps, p.time.dt),
        );
        row(
            "k, mu, tol",
            format!("{:.4e} Pa.s/m, {}, {:.0e}", set.k, set.mu, set.tol),
        );
        row(
            "window",
            set.window
                .map_or("whole interval".to_string(), |w| format!("{w} steps")),
        );
        row(
            "linear stage",
            match self.solver.macro_problem().filter(|_| set.two_scale) {
                Some(mp) => format!("two-scale ({} macro dofs)", mp.size),
                None => "single-scale".into(),
            },
        );
        row(
            "factorizations",
            format!(
                "{} distinct for {} substructures",
                self.solver.factors().len(),
                p.subs.len()
            ),
        );
        row(
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
        row("eta", format!("{:.3e}", sol.eta));
        row("time setup", format!("{:.3} s", st.setup));
        row("time local stage", format!("{:.3} s", st.local));
        row("time linear stage", format!("{:.3} s", st.linear));
        if set.two_scale {
            row("  of which macro", format!("{:.3} s", self.macro_seconds()));
        }
        row("time post", format!("{:.3} s", st.post));
        row("wall time", format!("{:.3} s", self.wall_s));
        if let Some(b) = peak_memory_bytes() {
            row("peak memory", lopin_core::estimate::bytes(b as usize));
        }
        out.push_str(&summary_rows(self.summary));
        out
    }
}

impl RunReport<'_> {
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

/// The "energy" object of a report.
pub fn energy_json(s: &Summary) -> Value {
    json!({
        "kinetic_end": s.kinetic_end,
        "strain_end": s.strain_end,
        "input_work": s.input_work,
        "max_total_over_input": s.max_total_over_input,
    })
}

/// The "contact" object of a report.
pub fn contact_json(s: &Summary) -> Value {
    json!({
        "max_slip": s.max_slip,
        "peak_normal_force": s.peak_normal_force,
        "min_gap": s.min_gap,
    })
}

/// One table row.
pub fn row(k: &str, v: String) -> String {
    format!("  {k:<26} {v}\n")
}

/// The energy and contact rows of a summary table.
pub fn summary_rows(s: &Summary) -> String {
    let mut out = String::new();
    out.push_str(&row(
        "kinetic energy (end)",
        format!("{:.4e} J", s.kinetic_end),
    ));
    out.push_str(&row(
        "strain energy (end)",
        format!("{:.4e} J", s.strain_end),
    ));
    out.push_str(&row("input work", format!("{:.4e} J", s.input_work)));
    out.push_str(&row(
        "max E/(E0 + input)",
        format!("{:.6}", s.max_total_over_input),
    ));
    if let Some(g) = s.min_gap {
        out.push_str(&row(
            "contact: peak normal force",
            format!("{:.4e} N", s.peak_normal_force),
        ));
        out.push_str(&row("contact: max slip", format!("{:.4e} m", s.max_slip)));
        out.push_str(&row("contact: min gap", format!("{g:.4e} m")));
    }
    out
}
