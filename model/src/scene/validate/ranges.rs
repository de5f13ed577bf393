//! The ranges a scene's dimensional inputs lie in: wide enough for SI models from gels to
//! diamond and for dimensionless models (E = ρ = 1), narrow enough that no product the solver
//! forms overflows; the friction coefficients and search directions a solve accepts (METHOD
//! §10), and the checks that compare a value with its range.

/// Ranges of the dimensional inputs: wide enough for SI models from gels to diamond and for
/// dimensionless models (E = ρ = 1), narrow enough that no product the solver forms overflows.
pub(crate) const YOUNG_RANGE: (f64, f64) = (1e-3, 1e13);
pub(crate) const DENSITY_RANGE: (f64, f64) = (1e-3, 1e5);
pub(crate) const LENGTH_RANGE: (f64, f64) = (1e-9, 1e5);
/// Largest ratio of a box body's element edges (longest over shortest).
pub(crate) const MAX_ASPECT: f64 = 1e3;
/// The time step relative to the wave transit time of the smallest element, h_min / c_max (the
/// trapezoidal rule is stable for any Δt; outside this range the time grid is absurd for the
/// mesh: every wave crosses 10⁴ elements per step, or needs 10⁴ steps to cross one).
pub(crate) const COURANT_RANGE: (f64, f64) = (1e-4, 1e4);

/// The friction coefficients a contact accepts: measured Coulomb coefficients of engineering
/// pairs lie below about 1.5 (clean metals in vacuum reach a few); beyond 10 every contact
/// sticks, and a larger value only slows the iteration (the local stage's slip threshold f·|F_n|
/// outgrows every tangential force it is compared with).
pub const FRICTION_RANGE: (f64, f64) = (0.0, 10.0);

/// Checks a friction coefficient against [`FRICTION_RANGE`]; the reason names the range.
pub fn check_friction(f: f64) -> std::result::Result<(), String> {
    if f.is_finite() && (FRICTION_RANGE.0..=FRICTION_RANGE.1).contains(&f) {
        return Ok(());
    }
    Err(format!(
        "a friction coefficient lies in [{}, {}], got {f:?}",
        FRICTION_RANGE.0, FRICTION_RANGE.1
    ))
}

/// The search direction k relative to the impedance scale k0 = mean √(ρE) of the materials in
/// use (METHOD §10) that a solve accepts (the stress suite converges from 10⁻³ to 10³ k0, slowly
/// at the ends).
pub const K_RANGE: (f64, f64) = (1e-6, 1e6);

/// The search direction k against the impedance scale k0: within [`K_RANGE`] times it, or the
/// reason it is not (shared by the scene check and the solver's settings check).
pub fn check_k_against(k: f64, k0: f64) -> std::result::Result<(), String> {
    let ratio = k / k0;
    if ratio >= K_RANGE.0 && ratio <= K_RANGE.1 {
        return Ok(());
    }
    Err(format!(
        "{k:?} Pa·s/m is {ratio:.3e} times the model's impedance √(ρE) = {k0:.4e} Pa·s/m; \
         LATIN needs k within {:e} to {:e} times it",
        K_RANGE.0, K_RANGE.1
    ))
}

/// Checks that a pulse of `duration` seconds ends within a run of `run` seconds (the
/// scene's `duration` and the `duration` parameter); the reason says the longest accepted.
pub fn check_pulse_duration(duration: f64, run: f64) -> std::result::Result<(), String> {
    if duration <= run * (1.0 + 1e-9) {
        return Ok(());
    }
    let run = short(run);
    Err(format!(
        "a pulse of {duration:?} s is longer than the run ({run} s = time.steps × time.dt): the \
         run would end inside it; at most {run} s, or a longer run"
    ))
}

/// `x` with at most 6 significant digits, in the shortest form that keeps them.
pub(crate) fn short(x: f64) -> String {
    format!("{:?}", format!("{x:.5e}").parse::<f64>().unwrap_or(x))
}

/// The reason when `n` substructures cannot be cut from a body of `elements` elements (a build
/// without the graph partitioner, the web build, refuses n > 1 when it builds the scene).
pub(crate) fn check_substructures(n: usize, elements: usize) -> std::result::Result<(), String> {
    if n == 0 {
        return Err("must be at least 1".into());
    }
    if n > elements {
        return Err(format!(
            "{n} substructures asked of a body of {elements} elements (at most one per element)"
        ));
    }
    Ok(())
}

/// Whether `x` is finite and within `[lo, hi]`.
pub(crate) fn in_range(x: f64, (lo, hi): (f64, f64)) -> bool {
    x.is_finite() && x >= lo && x <= hi
}
