//! Fuzzing of scene files, in process: the TOML of the small registry scenes
//! is mutated by proptest strategies (a number replaced by an extreme value, a line deleted or
//! duplicated, an array element appended or dropped, a name or reference renamed, a `[solver]`
//! table appended; one to three of them), then parsed, counted, built, set up and solved with a
//! capped iteration count. Every case must
//!
//! - not panic (each case runs under `catch_unwind` in a worker thread),
//! - finish within [`CASE_BOUND`] (waited for with a timeout, so a hang is caught too),
//! - on an error, name its source: errors of the scene stage (parse, count, build) are scene,
//!   file, size or mesh-matching errors naming `fuzz.toml`; errors of the solver stage (set-up,
//!   solve) name the solver setting, the substructure whose factorization failed, or where a
//!   non-finite value appeared (see [`unnamed_source`]),
//! - on success, give a finite η, η history and run summary (a non-finite η must come back as
//!   `LopinError::NonFinite`, never as a solution holding NaN).
//!
//! The unmutated scenes and the edits of [`FIXED`] (stage edges, failures found) run first,
//! every time. The generator is seeded (ChaCha, fixed seed; `LOPIN_FUZZ_SEED` picks another) so
//! a CI failure is reproduced by running the test again. `LOPIN_FUZZ_CASES` sets the number of
//! drawn cases (default 64) and `LOPIN_FUZZ_BUDGET_SECONDS`, if set, stops drawing new cases
//! once that much time has passed (`scripts/fuzz.sh` runs longer campaigns). All cases run; every
//! failure is printed with its case number and mutated TOML, then the test fails listing them.

use std::panic::{self, AssertUnwindSafe};
use std::sync::{mpsc, Mutex, Once};
use std::time::{Duration, Instant};

use lopin_core::scene::admission::{footprint, SolveShape};
use lopin_core::{post, scene, LopinError, Settings, Solver};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::strategy::ValueTree;
use proptest::test_runner::TestRunner;

/// The name every error of a mutated scene must carry.
const SOURCE: &str = "fuzz.toml";
/// Scenes whose text is mutated: small registry scenes and the stress suite's test scenes.
const SCENES: [&str; 9] = [
    "two-blocks",
    "two-blocks-nonmatching",
    "gap-impact",
    "bar",
    "bar-bimaterial",
    "granular-small",
    "mini-blocks",
    "mini-impact",
    "mini-bar",
];
/// Default number of cases (`LOPIN_FUZZ_CASES`).
const DEFAULT_CASES: u32 = 64;
/// Default seed (`LOPIN_FUZZ_SEED`).
#[path = "../fuzz/runner.rs"]
mod fuzz_runner;
use fuzz_runner::env_number;

const DEFAULT_SEED: u64 = 0x4c4f_5049_4e46_5a31;
/// Largest problem that is built and solved (counted from the scene before building it).
const MAX_DOFS: usize = 15_000;
/// Longest time grid that is solved.
const MAX_STEPS: usize = 400;
/// Largest dofs × (steps + 1) solved: bounds the work of one iteration.
const MAX_WORK: usize = 2_000_000;
/// Iteration cap of every solve (per window).
const MAX_ITER: usize = 40;
/// Wall-clock bound of one case.
const CASE_BOUND: Duration = Duration::from_secs(20);

/// Replacement numbers for an integer token: zero, one, small counts, signs, the ends of i64
/// and u64, a float and a NaN where an integer belongs, large mesh divisions.
const INTEGERS: [&str; 14] = [
    "0",
    "1",
    "2",
    "3",
    "7",
    "-1",
    "100000",
    "9223372036854775807",
    "4611686018427387905",
    "18446744073709551615",
    "1e20",
    "0.5",
    "nan",
    "1000",
];

/// Replacement numbers for a float token: zero, signs, the ends of f64, NaN and infinities,
/// subnormals, values just inside and outside the ranges the checks use, and the ends of the
/// ranges the scene checks accept (moduli 1e-3…1e13 Pa, densities 1e-3…1e5 kg/m³, lengths
/// 1e-9…1e5 m, Courant numbers 1e-4…1e4).
const FLOATS: [&str; 26] = [
    "0.0",
    "-0.0",
    "-1.0",
    "1.0",
    "1e300",
    "-1e300",
    "5e-324",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "1e20",
    "0.5",
    "0.499999",
    "-0.99",
    "100000.0",
    "1e-12",
    "1.5",
    "3",
    "9223372036854775807",
    "1e13",
    "1e-3",
    "1e5",
    "1e-9",
    "1e4",
    "1e-4",
];

/// Factors a float token is multiplied by: plausible-but-off values that pass the parser and
/// reach the builder and the solver.
const FACTORS: [f64; 10] = [-1.0, 1e-6, 1e-3, 0.1, 0.5, 2.0, 10.0, 1e3, 1e6, 1e12];

/// Replacement strings: body, material and scene names, interface kinds, faces, ramps, axes,
/// empty, unknown and non-ASCII.
const STRINGS: [&str; 22] = [
    "",
    "A",
    "B",
    "C",
    "steel",
    "aluminium",
    "bar",
    "matrix",
    "grain",
    "contact",
    "perfect",
    "free",
    "z+",
    "z-",
    "x-",
    "y+",
    "top",
    "cosine",
    "linear",
    "step",
    "xyz",
    "ü\u{1f980}",
];

/// Elements appended to an inline array (numbers, and names for `bodies = [...]`).
const ELEMENTS: [&str; 8] = ["1", "0", "-1", "1e300", "nan", "\"A\"", "\"B\"", "\"C\""];

/// Settings of an appended `[solver]` table, each with the values tried (ordinary ones first).
const SOLVER_SETTINGS: [(&str, &[&str]); 6] = [
    (
        "tol",
        &[
            "1e-3", "0.5", "1e-12", "0.0", "-1.0", "1.0", "5e-324", "1e300", "nan", "inf",
        ],
    ),
    (
        "mu",
        &[
            "0.8", "1.0", "0.5", "1e-6", "0.0", "-0.99", "1.5", "5e-324", "nan", "inf",
        ],
    ),
    (
        "k",
        &[
            "4e7", "4e4", "4e10", "4e-3", "4e16", "0.0", "-1.0", "5e-324", "1e300", "nan",
        ],
    ),
    (
        "max_iter",
        &["1", "2", "40", "0", "-1", "18446744073709551615", "0.5"],
    ),
    (
        "window",
        &[
            "1",
            "2",
            "7",
            "1000",
            "0",
            "-1",
            "18446744073709551615",
            "nan",
        ],
    ),
    ("macro", &["true", "false", "1", "\"on\""]),
];

/// Edits run before the drawn ones, every time (scene, text replaced — empty: append —, new
/// text): the edges of each stage, and the failures the fuzzer found.
const FIXED: [(&str, &str, &str); 10] = [
    // nodes that do not match across an interface (found: the error did not name the file;
    // now a non-matching interface)
    (
        "mini-blocks",
        "divisions = [4, 4, 2]",
        "divisions = [7, 4, 2]",
    ),
    // a non-matching contact whose faces overlap in part
    (
        "two-blocks-nonmatching",
        "min = [0.0, 0.0, 0.0]",
        "min = [0.013, 0.0, 0.0]",
    ),
    (
        "bar-bimaterial",
        "max = [0.1, 0.01, 0.01]",
        "max = [0.1, 0.499999, 0.01]",
    ),
    ("two-blocks", "steps = 60", "steps = 0"),
    ("bar", "dt = 1e-7", "dt = nan"),
    ("two-blocks", "", "[solver]\nk = 4e16"),
    (
        "granular-small",
        "grid = [4, 4, 4]",
        "grid = [4611686018427387905, 4, 4]",
    ),
    (
        "gap-impact",
        "velocity = [0.0, 0.0, -5.0]",
        "velocity = [0.0, 0.0, -5000.0]",
    ),
    ("mini-impact", "search = 2e-4", "search = 1e300"),
    ("mini-bar", "velocity = 10.0", "velocity = 5000.0"),
];

/// One edit of a scene's TOML text; the indices pick among what the text holds when applied.
#[derive(Debug, Clone)]
enum Mutation {
    /// Replace a numeric token by one of [`INTEGERS`] or [`FLOATS`] (of its own kind).
    Number { at: Index, value: Index },
    /// Multiply a float token by one of [`FACTORS`].
    Scale { at: Index, factor: Index },
    /// Delete a line.
    DeleteLine(Index),
    /// Duplicate a line.
    DuplicateLine(Index),
    /// Append one of [`ELEMENTS`] to an inline array.
    AppendElement { at: Index, value: Index },
    /// Drop an element of an inline array.
    DropElement { at: Index, which: Index },
    /// Replace a quoted string (a name, a reference, a kind, a face) by one of [`STRINGS`].
    RenameString { at: Index, name: Index },
    /// Append a `[solver]` table with one setting.
    SolverSetting { key: Index, value: Index },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<Index>(), any::<Index>())
            .prop_map(|(at, value)| Mutation::Number { at, value }),
        3 => (any::<Index>(), any::<Index>())
            .prop_map(|(at, factor)| Mutation::Scale { at, factor }),
        1 => any::<Index>().prop_map(Mutation::DeleteLine),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), any::<Index>())
            .prop_map(|(at, value)| Mutation::AppendElement { at, value }),
        1 => (any::<Index>(), any::<Index>())
            .prop_map(|(at, which)| Mutation::DropElement { at, which }),
        2 => (any::<Index>(), any::<Index>())
            .prop_map(|(at, name)| Mutation::RenameString { at, name }),
        2 => (any::<Index>(), any::<Index>())
            .prop_map(|(key, value)| Mutation::SolverSetting { key, value }),
    ]
}

/// A case: a scene and one to three mutations of its text (one most often, so that more cases
/// get past the parser).
fn case() -> impl Strategy<Value = (Index, Vec<Mutation>)> {
    let count = prop_oneof![3 => Just(1usize), 2 => Just(2usize), 1 => Just(3usize)];
    (
        any::<Index>(),
        count.prop_flat_map(|n| prop::collection::vec(mutation(), n)),
    )
}

/// Byte ranges (absolute) of the code of each line: the line without its comment.
fn code_lines(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for line in text.split_inclusive('\n') {
        let body = line.trim_end_matches('\n');
        let mut in_string = false;
        let mut end = body.len();
        for (i, c) in body.char_indices() {
            match c {
                '"' => in_string = !in_string,
                '#' if !in_string => {
                    end = i;
                    break;
                }
                _ => {}
            }
        }
        out.push((start, start + end));
        start += line.len();
    }
    out
}

/// Byte ranges of quoted strings (their contents) in code.
fn strings(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (a, b) in code_lines(text) {
        let mut open = None;
        for (i, c) in text[a..b].char_indices() {
            if c == '"' {
                match open.take() {
                    Some(s) => out.push((a + s, a + i)),
                    None => open = Some(i + 1),
                }
            }
        }
    }
    out
}

/// Byte ranges of numeric tokens in code, outside strings.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let quoted = strings(text);
    let inside = |p: usize| quoted.iter().any(|&(a, b)| p >= a && p < b);
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    for (a, b) in code_lines(text) {
        let mut i = a;
        while i < b {
            let c = bytes[i];
            let prev_ok = i == a || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_');
            let next_digit = i + 1 < b && bytes[i + 1].is_ascii_digit();
            let starts = c.is_ascii_digit() || (matches!(c, b'-' | b'+' | b'.') && next_digit);
            if prev_ok && starts && !inside(i) {
                let mut j = i + 1;
                while j < b
                    && (bytes[j].is_ascii_digit() || matches!(bytes[j], b'.' | b'e' | b'E' | b'_'))
                {
                    j += 1;
                    // an exponent sign
                    if matches!(bytes[j - 1], b'e' | b'E')
                        && j < b
                        && matches!(bytes[j], b'+' | b'-')
                    {
                        j += 1;
                    }
                }
                out.push((i, j));
                i = j;
            } else {
                i += 1;
            }
        }
    }
    out
}

/// Byte ranges of inline arrays `key = [ ... ]` (the brackets included), one per line.
fn arrays(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (a, b) in code_lines(text) {
        let code = &text[a..b];
        let Some(eq) = code.find('=') else { continue };
        let Some(open) = code[eq..].find('[').map(|o| eq + o) else {
            continue;
        };
        if let Some(close) = code[open..].rfind(']').map(|c| open + c) {
            out.push((a + open, a + close + 1));
        }
    }
    out
}

/// Line number (1-based) of a byte offset.
fn line_of(text: &str, at: usize) -> usize {
    text[..at].matches('\n').count() + 1
}

/// Applies one mutation (a no-op if the text holds nothing of the kind); returns the new text
/// and what was done.
fn apply(text: &str, m: &Mutation) -> (String, String) {
    let splice = |(a, b): (usize, usize), with: &str| format!("{}{with}{}", &text[..a], &text[b..]);
    let unchanged = |what: &str| (text.to_string(), format!("no {what} to edit"));
    match m {
        Mutation::Number { at, value } => {
            let tokens = numbers(text);
            if tokens.is_empty() {
                return unchanged("number");
            }
            let (a, b) = tokens[at.index(tokens.len())];
            let token = &text[a..b];
            let with = if token.contains(['.', 'e', 'E']) {
                FLOATS[value.index(FLOATS.len())]
            } else {
                INTEGERS[value.index(INTEGERS.len())]
            };
            (
                splice((a, b), with),
                format!("line {}: number `{token}` -> `{with}`", line_of(text, a)),
            )
        }
        Mutation::Scale { at, factor } => {
            let floats: Vec<(usize, usize)> = numbers(text)
                .into_iter()
                .filter(|&(a, b)| text[a..b].contains(['.', 'e', 'E']))
                .collect();
            if floats.is_empty() {
                return unchanged("float");
            }
            let (a, b) = floats[at.index(floats.len())];
            let token = &text[a..b];
            let x: f64 = token.replace('_', "").parse().unwrap_or(1.0);
            let with = format!("{:e}", x * FACTORS[factor.index(FACTORS.len())]);
            (
                splice((a, b), &with),
                format!("line {}: number `{token}` -> `{with}`", line_of(text, a)),
            )
        }
        Mutation::DeleteLine(at) | Mutation::DuplicateLine(at) => {
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return unchanged("line");
            }
            let i = at.index(lines.len());
            let line = lines[i];
            let what = if matches!(m, Mutation::DeleteLine(_)) {
                lines.remove(i);
                "deleted"
            } else {
                lines.insert(i, line);
                "duplicated"
            };
            (
                lines.join("\n") + "\n",
                format!("line {}: {what} `{line}`", i + 1),
            )
        }
        Mutation::AppendElement { at, value } => {
            let found = arrays(text);
            if found.is_empty() {
                return unchanged("array");
            }
            let (a, b) = found[at.index(found.len())];
            let inner = text[a + 1..b - 1].trim();
            let element = ELEMENTS[value.index(ELEMENTS.len())];
            let new = if inner.is_empty() {
                format!("[{element}]")
            } else {
                format!("[{inner}, {element}]")
            };
            (
                splice((a, b), &new),
                format!(
                    "line {}: array `{}` -> `{new}`",
                    line_of(text, a),
                    &text[a..b]
                ),
            )
        }
        Mutation::DropElement { at, which } => {
            let found = arrays(text);
            if found.is_empty() {
                return unchanged("array");
            }
            let (a, b) = found[at.index(found.len())];
            let mut items: Vec<&str> = text[a + 1..b - 1].split(',').map(str::trim).collect();
            items.retain(|s| !s.is_empty());
            if !items.is_empty() {
                items.remove(which.index(items.len()));
            }
            let new = format!("[{}]", items.join(", "));
            (
                splice((a, b), &new),
                format!(
                    "line {}: array `{}` -> `{new}`",
                    line_of(text, a),
                    &text[a..b]
                ),
            )
        }
        Mutation::RenameString { at, name } => {
            let found = strings(text);
            if found.is_empty() {
                return unchanged("string");
            }
            let (a, b) = found[at.index(found.len())];
            let with = STRINGS[name.index(STRINGS.len())];
            (
                splice((a, b), with),
                format!(
                    "line {}: string \"{}\" -> \"{with}\"",
                    line_of(text, a),
                    &text[a..b]
                ),
            )
        }
        Mutation::SolverSetting { key, value } => {
            let (name, values) = SOLVER_SETTINGS[key.index(SOLVER_SETTINGS.len())];
            let setting = format!("{name} = {}", values[value.index(values.len())]);
            (
                format!("{text}\n[solver]\n{setting}\n"),
                format!("appended [solver] {setting}"),
            )
        }
    }
}

/// Where an error was raised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// `scene::from_toml`, `admission::footprint`, `scene::build::build`: the file is the source.
    Scene,
    /// `Solver::new`, `Solver::solve`: a setting, a substructure or the place of a non-finite
    /// value is the source.
    Solver,
}

/// Why an error does not name its source (None when it does). The rule:
/// - every message is non-empty;
/// - scene, file, size and mesh-matching errors (`Scene`, `Io`, `TooLarge`, `NonConforming`)
///   carry `fuzz.toml` as their source (a scene error also a non-empty field and reason, a
///   mesh-matching error the two substructures), at any stage;
/// - at the solver stage, a `Setting` error starts `solver setting `FIELD`` with a non-empty
///   field, a `Factorization` error names its substructure, and a `NonFinite` error names the
///   interface or substructure where the value appeared, or the search direction `k` of an
///   overflowing η;
/// - anything else (an unknown scene, a state mismatch, a reference error, or a setting error
///   raised while reading the file) does not name the file it came from.
fn unnamed_source(e: &LopinError, stage: Stage) -> Option<String> {
    let msg = e.to_string();
    if msg.trim().is_empty() {
        return Some("empty error message".into());
    }
    let ok = match e {
        LopinError::Scene {
            source_name,
            field,
            reason,
        } => source_name == SOURCE && !field.is_empty() && !reason.is_empty(),
        LopinError::Io { path, .. } => path == SOURCE,
        LopinError::TooLarge { source_name, .. } => source_name == SOURCE,
        LopinError::NonConforming {
            source_name, a, b, ..
        } => source_name == SOURCE && !a.is_empty() && !b.is_empty(),
        LopinError::Setting { field, .. } => {
            stage == Stage::Solver
                && !field.is_empty()
                && msg.starts_with(&format!("solver setting `{field}`"))
        }
        LopinError::Factorization { sub, .. } => {
            stage == Stage::Solver && !sub.is_empty() && msg.contains(&format!("`{sub}`"))
        }
        LopinError::NonFinite(what) => {
            stage == Stage::Solver
                && (what.contains("substructure `")
                    || what.contains("interface `")
                    || what.contains("k = "))
        }
        _ => false,
    };
    (!ok || (stage == Stage::Scene && !msg.contains(SOURCE))).then(|| {
        format!(
            "error at the {stage:?} stage does not name its source ({}): {msg}",
            if stage == Stage::Scene {
                "expected a scene, file, size or mesh-matching error naming `fuzz.toml`"
            } else {
                "expected `fuzz.toml`, a solver setting, a substructure or the place of a \
                 non-finite value"
            }
        )
    })
}

/// What a case came to (tallied over the run).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    Unparsed,
    Uncounted,
    TooLargeHere,
    Unbuilt,
    SolverRefused,
    SolveFailed,
    NotConverged,
    Converged,
}

/// What one case came to: its outcome, the error that ended it (if any) and the failed checks.
struct Report {
    outcome: Outcome,
    error: Option<String>,
    problems: Vec<String>,
}

/// Runs one mutated scene through parse, count, build, set-up, solve and summary.
fn run_case(text: &str) -> Report {
    let refused = |outcome: Outcome, e: &LopinError, stage: Stage| Report {
        outcome,
        error: Some(e.to_string()),
        problems: unnamed_source(e, stage).into_iter().collect(),
    };
    let spec = match scene::from_toml(text, SOURCE) {
        Ok(spec) => spec,
        Err(e) => return refused(Outcome::Unparsed, &e, Stage::Scene),
    };
    let fp = match footprint(&spec, SOURCE, SolveShape::smallest()) {
        Ok(fp) => fp,
        Err(e) => return refused(Outcome::Uncounted, &e, Stage::Scene),
    };
    if fp.dofs > MAX_DOFS
        || fp.steps > MAX_STEPS
        || fp.dofs.saturating_mul(fp.steps.saturating_add(1)) > MAX_WORK
    {
        return Report {
            outcome: Outcome::TooLargeHere,
            error: None,
            problems: Vec::new(),
        };
    }
    let problem = match scene::problem_of(&spec, SOURCE) {
        Ok(p) => p,
        Err(e) => return refused(Outcome::Unbuilt, &e, Stage::Scene),
    };
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.max_iter = settings.max_iter.min(MAX_ITER);
    let mut solver = match Solver::new(problem, settings) {
        Ok(s) => s,
        Err(e) => return refused(Outcome::SolverRefused, &e, Stage::Solver),
    };
    let sol = match solver.solve(None) {
        Ok(sol) => sol,
        Err(e) => return refused(Outcome::SolveFailed, &e, Stage::Solver),
    };
    let mut problems = Vec::new();
    if !sol.eta.is_finite() {
        problems.push(format!(
            "solve returned Ok with a non-finite η = {} (expected LopinError::NonFinite)",
            sol.eta
        ));
    }
    if let Some((i, v)) = sol
        .eta_history
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
    {
        problems.push(format!("solve returned Ok with eta_history[{i}] = {v}"));
    }
    let s = post::summary(&solver, &sol);
    let named = [
        ("kinetic_end", s.kinetic_end),
        ("strain_end", s.strain_end),
        ("input_work", s.input_work),
        ("max_total_over_input", s.max_total_over_input),
        ("max_slip", s.max_slip),
        ("peak_normal_force", s.peak_normal_force),
        ("min_gap", s.min_gap.unwrap_or(0.0)),
    ];
    for (name, v) in named {
        if !v.is_finite() {
            problems.push(format!("summary.{name} = {v} after an Ok solve"));
        }
    }
    Report {
        outcome: if sol.converged {
            Outcome::Converged
        } else {
            Outcome::NotConverged
        },
        error: None,
        problems,
    }
}

/// Panic messages with their location, recorded by the panic hook (cases run one at a time).
static PANICS: Mutex<Vec<String>> = Mutex::new(Vec::new());

fn record_panics() {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if let Ok(mut p) = PANICS.lock() {
                p.push(info.to_string());
            }
            previous(info);
        }));
    });
}

/// How a case ended, seen from the fuzzing loop.
enum Ended {
    Finished(Report, Duration),
    Panicked(String),
    TimedOut,
}

/// Runs a case in a worker thread under `catch_unwind`, waiting at most [`CASE_BOUND`].
fn run_bounded(text: &str) -> Ended {
    if let Ok(mut p) = PANICS.lock() {
        p.clear();
    }
    let (tx, rx) = mpsc::channel();
    let owned = text.to_string();
    let spawned = std::thread::Builder::new()
        .name("fuzz-case".into())
        .stack_size(8 << 20)
        .spawn(move || {
            let start = Instant::now();
            let result = panic::catch_unwind(AssertUnwindSafe(|| run_case(&owned)));
            // the receiver is gone only after a timeout, which is reported already
            let _ = tx.send((result, start.elapsed()));
        });
    if let Err(e) = spawned {
        return Ended::Panicked(format!("could not start the case's thread: {e}"));
    }
    match rx.recv_timeout(CASE_BOUND) {
        Ok((Ok(report), took)) => Ended::Finished(report, took),
        Ok((Err(payload), _)) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(non-string panic payload)".into());
            let hooked = PANICS.lock().map(|p| p.join(" | ")).unwrap_or_default();
            Ended::Panicked(format!("{message} [{hooked}]"))
        }
        Err(_) => Ended::TimedOut,
    }
}

#[test]
fn mutated_scenes_never_panic_hang_or_report_non_finite_numbers() {
    record_panics();
    let cases = env_number::<u32>("LOPIN_FUZZ_CASES").unwrap_or(DEFAULT_CASES);
    let budget = env_number::<f64>("LOPIN_FUZZ_BUDGET_SECONDS").map(Duration::from_secs_f64);
    let (mut runner, seed) = fuzz_runner::runner(cases, DEFAULT_SEED);
    let strategy = case();
    let start = Instant::now();
    let mut failures: Vec<String> = Vec::new();
    let mut tally: std::collections::BTreeMap<Outcome, usize> = Default::default();
    let mut slowest = (Duration::ZERO, usize::MAX);
    let mut ran = 0;

    // the unmutated scenes and the fixed edits first: the harness itself must pass them
    let originals = SCENES.iter().map(|name| {
        let text = scene::registry::source(name).expect("registry scene");
        (format!("{name} (unmutated)"), text.to_string())
    });
    let fixed = FIXED.iter().enumerate().map(|(i, (name, from, to))| {
        let text = scene::registry::source(name).expect("registry scene");
        let edited = if from.is_empty() {
            format!("{text}\n{to}\n")
        } else {
            text.replacen(from, to, 1)
        };
        assert_ne!(edited, text, "fixed edit {i} does not apply to {name}");
        (format!("fixed {i}: {name}: `{from}` -> `{to}`"), edited)
    });
    let mutated = (0..cases).map_while(|i| {
        if budget.is_some_and(|b| start.elapsed() > b) {
            return None;
        }
        let (scene, mutations) = strategy
            .new_tree(&mut runner)
            .expect("the case strategy always generates")
            .current();
        let name = SCENES[scene.index(SCENES.len())];
        let mut text = scene::registry::source(name)
            .expect("registry scene")
            .to_string();
        let mut done = Vec::new();
        for m in &mutations {
            let (new, what) = apply(&text, m);
            text = new;
            done.push(what);
        }
        Some((format!("case {i}: {name}: {}", done.join("; ")), text))
    });
    let first: Vec<_> = originals.chain(fixed).collect();
    for (label, text) in first.into_iter().chain(mutated) {
        println!("{label}");
        let describe = |what: &str| format!("{label}\n  {what}\n--- mutated TOML ---\n{text}---");
        match run_bounded(&text) {
            Ended::Finished(report, took) => {
                let Report {
                    outcome,
                    error,
                    problems,
                } = report;
                println!("  {outcome:?} in {:.2} s", took.as_secs_f64());
                if let Some(e) = error {
                    println!("  error: {e}");
                }
                *tally.entry(outcome).or_default() += 1;
                if took > slowest.0 {
                    slowest = (took, ran);
                }
                for p in problems {
                    let f = describe(&p);
                    eprintln!("FAILURE {f}");
                    failures.push(f);
                }
            }
            Ended::Panicked(message) => {
                let f = describe(&format!("panicked: {message}"));
                eprintln!("FAILURE {f}");
                failures.push(f);
            }
            Ended::TimedOut => {
                let f = describe(&format!(
                    "did not finish within {} s (the case's thread is still running; stopping)",
                    CASE_BOUND.as_secs()
                ));
                eprintln!("FAILURE {f}");
                failures.push(f);
                break;
            }
        }
        ran += 1;
    }
    println!(
        "{ran} cases (seed {seed:#x}) in {:.1} s, slowest {:.2} s; outcomes {tally:?}",
        start.elapsed().as_secs_f64(),
        slowest.0.as_secs_f64()
    );
    fuzz_runner::assert_no_failures(&failures, seed);
}

/// The mutators do what they say on a known text.
#[test]
fn mutators_edit_numbers_arrays_and_strings() {
    let text = "a = 1.5e-3 # 7\nb = [1, -2, 3]\nname = \"x1\"\n[[body]]\n";
    let nums: Vec<&str> = numbers(text).iter().map(|&(a, b)| &text[a..b]).collect();
    assert_eq!(nums, ["1.5e-3", "1", "-2", "3"]);
    let arr: Vec<&str> = arrays(text).iter().map(|&(a, b)| &text[a..b]).collect();
    assert_eq!(arr, ["[1, -2, 3]"]);
    let strs: Vec<&str> = strings(text).iter().map(|&(a, b)| &text[a..b]).collect();
    assert_eq!(strs, ["x1"]);
    let (mut runner, _) = fuzz_runner::runner(1, DEFAULT_SEED);
    let index = |runner: &mut TestRunner| any::<Index>().new_tree(runner).expect("index").current();
    let at = index(&mut runner);
    let (out, _) = apply(
        text,
        &Mutation::AppendElement {
            at,
            value: index(&mut runner),
        },
    );
    assert!(out.contains("[1, -2, 3, "), "{out}");
    let (out, _) = apply(
        text,
        &Mutation::DropElement {
            at,
            which: index(&mut runner),
        },
    );
    assert_eq!(arrays(&out).len(), 1, "{out}");
    assert_eq!(out.matches(',').count(), 1, "{out}");
}
