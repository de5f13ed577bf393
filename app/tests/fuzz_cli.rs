//! Fuzzing of the command line: proptest draws argument vectors for
//! `lopin run`, `lopin estimate` and `lopin sweep` on small built-in scenes, with options taking
//! ordinary and extreme values (0, negatives, 1e300, NaN, infinities, 2^64 − 1, 2^62 + 1, the
//! smallest subnormal, empty ranges, garbage), and runs the real binary on each. Every case must
//!
//! - exit normally (no signal) with 0, 1 (not converged) or 2 (an error), never 101 (a Rust
//!   panic) or an abort, within [`CASE_BOUND`] (the process is killed past it);
//! - print no panic message (`panicked at`, `RUST_BACKTRACE`) on stderr;
//! - on exit 2, print a line starting with `error:` whose text (with the lines after it) names
//!   its source: see [`names_source`];
//! - on exit 0 or 1, print no non-finite number: `--json` output parses and holds no `null`
//!   where a result number belongs (see [`bad_nulls`]), a table holds no `NaN` or `inf`, and the
//!   JSON files written under `--out` (run.json, sweep records) obey the same rule; with
//!   `lopin run --json`, exit 0 means `converged: true` and exit 1 `converged: false`.
//!
//! The command lines of [`FIXED`] (the edges the issue lists, failures found) run first, every
//! time. Each case's command line is printed before it runs. The generator is seeded (ChaCha,
//! fixed seed; `LOPIN_FUZZ_SEED` picks another), `LOPIN_FUZZ_CASES` sets the number of drawn
//! cases (default 24), `LOPIN_FUZZ_BUDGET_SECONDS`, if set, stops drawing new cases once that
//! much time has passed. All cases run; the test then fails listing every failure.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::sample::Index;
use proptest::strategy::ValueTree;
use serde_json::Value;

/// Default number of cases (`LOPIN_FUZZ_CASES`).
const DEFAULT_CASES: u32 = 24;
/// Default seed (`LOPIN_FUZZ_SEED`).
#[path = "../../tests/fuzz/runner.rs"]
mod fuzz_runner;
use fuzz_runner::env_number;

const DEFAULT_SEED: u64 = 0x4c4f_5049_4e43_4c49;
/// Wall-clock bound of one case.
const CASE_BOUND: Duration = Duration::from_secs(60);
/// Iteration cap added to every case that does not set `--max-iter`.
const MAX_ITER: &str = "30";

/// Subcommands fuzzed.
const COMMANDS: [&str; 3] = ["run", "estimate", "sweep"];
/// Scenes: small built-ins, and names that are not scenes.
const SCENES: [&str; 4] = ["two-blocks", "bar", "mini-blocks", "gap-impact"];
/// Scenes whose ordinary `--refine` is 1: at 2 (16 times the work) a sweep of two-blocks takes
/// half of [`CASE_BOUND`] on 2 cores.
const LARGE_AT_REFINE_2: [&str; 2] = ["two-blocks", "gap-impact"];
/// Scene arguments that are not scenes.
const BAD_SCENES: [&str; 4] = [
    "no-such-scene",
    "",
    "/nonexistent/fuzz.toml",
    "two-blocks.toml",
];

/// An option: its flag, ordinary values (drawn 70 % of the time) and extreme or malformed ones;
/// `{out}` is the case's scratch directory.
struct Opt {
    flag: &'static str,
    ordinary: &'static [&'static str],
    extreme: &'static [&'static str],
}

const OPTIONS: [Opt; 11] = [
    Opt {
        flag: "--refine",
        ordinary: &["1", "2"],
        extreme: &[
            "0",
            "-1",
            "1e300",
            "nan",
            "18446744073709551615",
            "4611686018427387905",
            "abc",
            "",
        ],
    },
    Opt {
        flag: "--split",
        ordinary: &["1", "2"],
        extreme: &[
            "3",
            "0",
            "-1",
            "18446744073709551615",
            "4611686018427387905",
            "x",
        ],
    },
    Opt {
        flag: "--k",
        ordinary: &["4e7", "1e7", "1e8"],
        extreme: &[
            "0", "-1", "1", "1e300", "nan", "inf", "-inf", "5e-324", "abc",
        ],
    },
    Opt {
        flag: "--mu",
        ordinary: &["0.8", "1", "0.5"],
        extreme: &["0", "-1", "1.5", "nan", "inf", "5e-324"],
    },
    Opt {
        flag: "--tol",
        ordinary: &["1e-3", "1e-2", "1e-6"],
        extreme: &[
            "0", "-1", "1", "0.5", "nan", "inf", "1e300", "5e-324", "1e-300",
        ],
    },
    Opt {
        flag: "--window",
        ordinary: &["1", "2", "7"],
        extreme: &["0", "-1", "18446744073709551615", "nan", "1000000"],
    },
    Opt {
        flag: "--max-iter",
        ordinary: &["30", "1", "5"],
        extreme: &["0", "-1", "nan", "1e3", ""],
    },
    Opt {
        flag: "--f",
        ordinary: &["0", "0.3", "1"],
        extreme: &["-1", "nan", "inf", "1e300", "5e-324", "-0"],
    },
    Opt {
        flag: "--macro",
        ordinary: &["on", "off"],
        extreme: &["maybe", ""],
    },
    Opt {
        flag: "--factors",
        ordinary: &["double", "single"],
        extreme: &["half", "", "DOUBLE"],
    },
    Opt {
        flag: "--out",
        ordinary: &["{out}/run"],
        extreme: &["{out}", "/dev/null", "/proc/lopin-fuzz"],
    },
];

/// Arguments the command line does not know, added now and then.
const UNKNOWN: [&str; 3] = ["--bogus", "-x", "extra-positional"];

/// `--param` values of a sweep: short ordinary lists (drawn 70 % of the time), then ranges and
/// values to refuse.
const PARAMS: [&str; 6] = [
    "f=0:0.3:0.3",
    "f=0.1,0.2",
    "v0=5,10",
    "gap=0,1e-5",
    "f=0.2",
    "v0=1",
];
const BAD_PARAMS: [&str; 18] = [
    "f=0.5:0:0.1",
    "f=0:1e300:1",
    "f=0:1:5e-324",
    "f=0:1:0",
    "f=0:0.5:-0.1",
    "f=nan",
    "f=inf,1",
    "gap=-1",
    "gap=1e300",
    "v0=inf",
    "v0=1e300",
    "v0=-1e300",
    "f=",
    "=1",
    "mass=1",
    "f",
    "f=1e300",
    "f=4611686018427387905",
];

/// One drawn option: which, whether extreme, which value, and whether written `--flag=value`
/// (the only way a value starting with `-` reaches the option).
#[derive(Debug, Clone)]
struct DrawnOpt {
    which: Index,
    extreme: bool,
    value: Index,
    equals: bool,
}

/// A drawn case, as indices into the tables above.
#[derive(Debug, Clone)]
struct Drawn {
    command: Index,
    /// None: a bad scene (`bad` picks it).
    scene: Option<Index>,
    bad: Index,
    options: Vec<DrawnOpt>,
    json: bool,
    param: Index,
    bad_param: bool,
    /// A sweep without `--param`.
    drop_param: bool,
    /// An unknown argument.
    unknown: Option<Index>,
    /// A last option without its value.
    dangling: Option<Index>,
}

fn drawn_opt() -> impl Strategy<Value = DrawnOpt> {
    (
        any::<Index>(),
        prop::bool::weighted(0.3),
        any::<Index>(),
        prop::bool::weighted(0.3),
    )
        .prop_map(|(which, extreme, value, equals)| DrawnOpt {
            which,
            extreme,
            value,
            equals,
        })
}

fn drawn() -> impl Strategy<Value = Drawn> {
    let rare = |n: u32| prop_oneof![n => Just(None), 1 => any::<Index>().prop_map(Some)];
    (
        any::<Index>(),
        prop_oneof![12 => any::<Index>().prop_map(Some), 1 => Just(None)],
        any::<Index>(),
        prop::collection::vec(drawn_opt(), 0..=4),
        any::<bool>(),
        (any::<Index>(), prop::bool::weighted(0.3)),
        prop::bool::weighted(0.04),
        rare(24),
        rare(24),
    )
        .prop_map(
            |(
                command,
                scene,
                bad,
                options,
                json,
                (param, bad_param),
                drop_param,
                unknown,
                dangling,
            )| Drawn {
                command,
                scene,
                bad,
                options,
                json,
                param,
                bad_param,
                drop_param,
                unknown,
                dangling,
            },
        )
}

/// A case ready to run.
struct Case {
    command: &'static str,
    scene: String,
    args: Vec<String>,
    json: bool,
    /// The option flags given (values excluded).
    flags: Vec<&'static str>,
    /// The unknown argument added, if any.
    unknown: Option<&'static str>,
}

impl Case {
    fn of(d: &Drawn, out: &Path) -> Case {
        let command = COMMANDS[d.command.index(COMMANDS.len())];
        let scene = match &d.scene {
            Some(i) => SCENES[i.index(SCENES.len())],
            None => BAD_SCENES[d.bad.index(BAD_SCENES.len())],
        }
        .to_string();
        let mut args = vec![command.to_string(), scene.clone()];
        let out_text = out.display().to_string();
        let mut flags = Vec::new();
        for o in &d.options {
            let opt = &OPTIONS[o.which.index(OPTIONS.len())];
            if opt.flag == "--out" && command != "run" {
                // sweeps get their own --out; estimate has none
                continue;
            }
            let values = if o.extreme { opt.extreme } else { opt.ordinary };
            let mut value = values[o.value.index(values.len())].replace("{out}", &out_text);
            if opt.flag == "--refine" && !o.extreme && LARGE_AT_REFINE_2.contains(&scene.as_str()) {
                value = "1".into();
            }
            flags.push(opt.flag);
            if o.equals {
                args.push(format!("{}={value}", opt.flag));
            } else {
                args.push(opt.flag.into());
                args.push(value);
            }
        }
        let unknown = d.unknown.as_ref().map(|i| UNKNOWN[i.index(UNKNOWN.len())]);
        if let Some(u) = unknown {
            args.push(u.into());
        }
        if !flags.contains(&"--max-iter") {
            flags.push("--max-iter");
            args.extend(["--max-iter".into(), MAX_ITER.into()]);
        }
        if command == "sweep" {
            if !d.drop_param {
                flags.push("--param");
                args.push("--param".into());
                let params: &[&str] = if d.bad_param { &BAD_PARAMS } else { &PARAMS };
                args.push(params[d.param.index(params.len())].into());
            }
            flags.push("--out");
            args.push("--out".into());
            args.push(out.join("sweep").display().to_string());
        }
        if d.json {
            flags.push("--json");
            args.push("--json".into());
        }
        if let Some(i) = &d.dangling {
            let flag = OPTIONS[i.index(OPTIONS.len())].flag;
            flags.push(flag);
            args.push(flag.into());
        }
        Case {
            command,
            scene,
            args,
            json: d.json,
            flags,
            unknown,
        }
    }

    /// The command line, quoted where needed.
    fn line(&self) -> String {
        std::iter::once("lopin".to_string())
            .chain(self.args.iter().map(|a| {
                if a.is_empty() || a.contains(char::is_whitespace) {
                    format!("'{a}'")
                } else {
                    a.clone()
                }
            }))
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// What the process did.
struct Ran {
    status: Option<ExitStatus>,
    stdout: String,
    stderr: String,
    took: Duration,
}

/// Runs the binary with the case's arguments in `dir`, killing it past [`CASE_BOUND`].
fn run(case: &Case, dir: &Path) -> Ran {
    let out_path = dir.join("stdout.txt");
    let err_path = dir.join("stderr.txt");
    let start = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_lopin"))
        .args(&case.args)
        .current_dir(dir)
        .env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(File::create(&out_path).expect("stdout file"))
        .stderr(File::create(&err_path).expect("stderr file"))
        .spawn()
        .expect("the lopin binary starts");
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break Some(status);
        }
        if start.elapsed() > CASE_BOUND {
            child.kill().ok();
            child.wait().ok();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into();
    Ran {
        status,
        stdout: read(&out_path),
        stderr: read(&err_path),
        took: start.elapsed(),
    }
}

/// The names an error may use for an option: the flag, and the setting or word the core uses.
fn aliases(flag: &str) -> &'static [&'static str] {
    match flag {
        "--k" => &["`k`", "k ="],
        "--mu" => &["`mu`", "μ"],
        "--tol" => &["`tol`", "tolerance"],
        "--window" => &["`window`", "window"],
        "--max-iter" => &["`max_iter`", "max_iter"],
        "--macro" => &["macro"],
        "--factors" => &["factors"],
        "--refine" => &["refine"],
        "--split" => &["split"],
        "--f" => &["friction"],
        "--param" => &["param"],
        _ => &[],
    }
}

/// Whether an error text (the `error:` line and the lines after it, up to clap's `Usage:` or
/// `For more information` lines) names its source: it names an option (`--` and a letter: one
/// given, or one missing), the setting name the core uses for an option given (e.g. `` `k` ``
/// for `--k`, `max_iter` for `--max-iter`), `scene `, `.toml`, `` solver setting ` `` (a
/// setting the core names), the scene argument in backticks, a path given on the command line,
/// or the unknown argument the case added (quoted as clap quotes it). A value alone (clap's
/// "unexpected argument '-1' found" for `--k -1`) does not name the option it was meant for.
fn names_source(text: &str, case: &Case) -> bool {
    let mut names: Vec<String> = ["scene ", ".toml", "solver setting `"]
        .map(String::from)
        .to_vec();
    if !case.scene.is_empty() {
        names.push(format!("`{}`", case.scene));
    }
    for f in &case.flags {
        names.push((*f).to_string());
        names.extend(aliases(f).iter().map(|a| (*a).to_string()));
    }
    // a path given (to --out) names a file
    names.extend(
        case.args
            .iter()
            .map(|a| a.split_once('=').map_or(a.as_str(), |(_, v)| v))
            .filter(|a| a.starts_with('/'))
            .map(String::from),
    );
    if let Some(u) = case.unknown {
        names.push(format!("'{u}'"));
    }
    let names_an_option = text
        .match_indices("--")
        .any(|(i, _)| text[i + 2..].starts_with(|c: char| c.is_ascii_lowercase()));
    names_an_option || names.iter().any(|n| text.contains(n.as_str()))
}

/// Keys whose value is a result number: a `null` there is a non-finite number serde_json wrote.
const RESULT_KEYS: [&str; 33] = [
    "eta",
    "iterations",
    "converged",
    "kinetic_end",
    "strain_end",
    "input_work",
    "max_total_over_input",
    "max_slip",
    "peak_normal_force",
    "wall_s",
    "value",
    "energy_end",
    "total_iterations",
    "total_wall_s",
    "gain",
    "gain_wall",
    "cold_total_iterations",
    "cold_total_wall_s",
    "k",
    "mu",
    "tol",
    "dt",
    "dofs",
    "steps",
    "setup",
    "local",
    "linear",
    "post",
    "wall",
    "outputs",
    "total_bytes",
    "setup_s",
    "iteration_s",
];

/// Where a JSON document holds a `null` a number belongs in. The rule: outside the echoed input
/// scene (`scene` objects of run.json, where absent options are `null`), a `null` is a failure
/// as an array element (η histories, value lists), as the value of a result key
/// ([`RESULT_KEYS`]), as the `energy` or `contact` object or any member of them, except
/// `contact.min_gap` of a problem without contact interfaces (`contact_interfaces` 0).
fn bad_nulls(v: &Value) -> Vec<String> {
    fn walk(v: &Value, path: &str, contact_free: bool, out: &mut Vec<String>) {
        match v {
            Value::Null => {
                let mut keys = path.rsplit('.');
                let key = keys.next().unwrap_or(path);
                let container = keys.next().unwrap_or("");
                let in_array = path.ends_with(']');
                let in_result_object = matches!(container, "energy" | "contact");
                let allowed_min_gap = key == "min_gap" && contact_free;
                if !allowed_min_gap
                    && (in_array
                        || in_result_object
                        || RESULT_KEYS.contains(&key)
                        || key == "energy"
                        || key == "contact")
                {
                    out.push(format!("`{path}` is null"));
                }
            }
            Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    walk(item, &format!("{path}[{i}]"), contact_free, out);
                }
            }
            Value::Object(map) => {
                let contact_free = map
                    .get("contact_interfaces")
                    .or_else(|| map.get("problem").and_then(|p| p.get("contact_interfaces")))
                    .and_then(Value::as_u64)
                    .map_or(contact_free, |n| n == 0);
                for (k, item) in map {
                    if k == "scene" && item.is_object() {
                        continue;
                    }
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(item, &p, contact_free, out);
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(v, "", false, &mut out);
    out
}

/// Words of a text that spell a non-finite number (`NaN`, `inf`, `-inf`, `infinity`).
fn non_finite_words(text: &str) -> Vec<String> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-' || c == '+'))
        .filter(|w| {
            let w = w.trim_start_matches(['-', '+']).to_ascii_lowercase();
            w == "nan" || w == "inf" || w == "infinity"
        })
        .map(str::to_string)
        .collect()
}

/// The JSON files written under a directory (run.json, sweep records and header).
fn json_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(json_files(&p));
        } else if p.extension().is_some_and(|x| x == "json") {
            out.push(p);
        }
    }
    out.sort();
    out
}

/// The failed checks of a finished case (empty when all hold).
fn check(case: &Case, ran: &Ran, dir: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    let Some(status) = ran.status else {
        return vec![format!(
            "did not finish within {} s (killed)",
            CASE_BOUND.as_secs()
        )];
    };
    for marker in ["panicked at", "RUST_BACKTRACE"] {
        if ran.stderr.contains(marker) {
            problems.push(format!("stderr holds `{marker}`"));
        }
    }
    let Some(code) = status.code() else {
        problems.push(format!("ended by a signal: {status}"));
        return problems;
    };
    match code {
        0 | 1 => {
            if case.json {
                match serde_json::from_str::<Value>(&ran.stdout) {
                    Ok(v) => {
                        for n in bad_nulls(&v) {
                            problems.push(format!("stdout JSON: {n}"));
                        }
                        if case.command == "run" {
                            let converged = v.get("converged").and_then(Value::as_bool);
                            if converged != Some(code == 0) {
                                problems.push(format!(
                                    "exit {code} but `converged` is {converged:?} in the JSON"
                                ));
                            }
                        }
                    }
                    Err(e) => problems.push(format!("stdout is not JSON: {e}")),
                }
            } else {
                let words = non_finite_words(&ran.stdout);
                if !words.is_empty() {
                    problems.push(format!("stdout table holds non-finite numbers {words:?}"));
                }
            }
            let words = non_finite_words(&ran.stderr);
            if !words.is_empty() {
                problems.push(format!("stderr holds non-finite numbers {words:?}"));
            }
            for file in json_files(dir) {
                let text = std::fs::read_to_string(&file).unwrap_or_default();
                match serde_json::from_str::<Value>(&text) {
                    Ok(v) => {
                        for n in bad_nulls(&v) {
                            problems.push(format!("{}: {n}", file.display()));
                        }
                    }
                    Err(e) => problems.push(format!("{} is not JSON: {e}", file.display())),
                }
            }
        }
        2 => {
            let lines: Vec<&str> = ran.stderr.lines().collect();
            match lines.iter().position(|l| l.starts_with("error:")) {
                None => problems.push("exit 2 without a line starting with `error:`".into()),
                Some(i) => {
                    let text = lines[i..]
                        .iter()
                        .take_while(|l| {
                            !(l.starts_with("Usage:") || l.starts_with("For more information"))
                        })
                        .copied()
                        .collect::<Vec<_>>()
                        .join("\n");
                    if lines[i].trim() == "error:" {
                        problems.push("the `error:` line is empty".into());
                    } else if !names_source(&text, case) {
                        problems.push(format!(
                            "the error does not name its source (no option given, setting, \
                             scene or file in it): {}",
                            lines[i]
                        ));
                    }
                }
            }
        }
        101 => problems.push("exit 101 (a Rust panic)".into()),
        other => problems.push(format!("exit {other} (expected 0, 1 or 2)")),
    }
    problems
}

/// Command lines run before the drawn ones, every time: the edges the issue lists, and the
/// failures the fuzzer found (`--max-iter 30` and a sweep's `--out` are added as for drawn cases).
const FIXED: [&str; 16] = [
    "run mini-blocks --k -1",
    "run mini-blocks --k=-1",
    "run mini-blocks --k -inf",
    "run mini-blocks --mu -0.5",
    "run bar --window -1",
    "run bar --refine 18446744073709551615",
    "run bar --split 4611686018427387905",
    "run mini-blocks --tol nan --json",
    "run mini-blocks --tol 5e-324 --max-iter 3 --json",
    "run gap-impact --window 1 --max-iter 5 --json",
    "estimate two-blocks --window 0 --json",
    "estimate mini-blocks --macro on --json",
    "sweep bar --param f=0.5:0:0.1",
    "sweep mini-blocks --param f=0:1:5e-324",
    "sweep mini-blocks --param v0=1e300 --json",
    "run no-such-scene",
];

impl Case {
    /// A case from one of the [`FIXED`] command lines.
    fn fixed(line: &str, out: &Path) -> Case {
        let mut args: Vec<String> = line.split_whitespace().map(String::from).collect();
        let command = COMMANDS
            .into_iter()
            .find(|c| *c == args[0])
            .expect("a fuzzed command");
        let known = |a: &str| {
            OPTIONS
                .iter()
                .map(|o| o.flag)
                .chain(["--param", "--json", "--out", "--max-iter"])
                .find(|f| a.split_once('=').map_or(a, |(f, _)| f) == *f)
        };
        if !args.iter().any(|a| known(a) == Some("--max-iter")) {
            args.extend(["--max-iter".into(), MAX_ITER.into()]);
        }
        if command == "sweep" {
            args.extend(["--out".into(), out.join("sweep").display().to_string()]);
        }
        Case {
            command,
            scene: args[1].clone(),
            json: args.iter().any(|a| a == "--json"),
            flags: args.iter().filter_map(|a| known(a)).collect(),
            unknown: None,
            args,
        }
    }
}

/// Tallies of a fuzzing run.
#[derive(Default)]
struct Tally {
    ran: usize,
    failures: Vec<String>,
    codes: std::collections::BTreeMap<String, usize>,
    slowest: (Duration, String),
}

impl Tally {
    /// Runs a case in `dir` (removed afterwards), checks it and records the result.
    fn run(&mut self, label: &str, case: &Case, dir: &Path) {
        let line = case.line();
        println!("{label}: {line}");
        let ran = run(case, dir);
        let code = ran.status.map_or("killed".to_string(), |s| format!("{s}"));
        println!("  {code} in {:.2} s", ran.took.as_secs_f64());
        if let Some(e) = ran.stderr.lines().find(|l| l.starts_with("error:")) {
            println!("  {e}");
        }
        *self.codes.entry(code).or_default() += 1;
        if ran.took > self.slowest.0 {
            self.slowest = (ran.took, line.clone());
        }
        let problems = check(case, &ran, dir);
        if !problems.is_empty() {
            let f = format!(
                "{label}: {line}\n  {}\n--- stderr ---\n{}\n--- stdout (first 2000 bytes) ---\n{}",
                problems.join("\n  "),
                ran.stderr.trim_end(),
                ran.stdout.chars().take(2000).collect::<String>().trim_end()
            );
            eprintln!("FAILURE {f}");
            self.failures.push(f);
        }
        std::fs::remove_dir_all(dir).ok();
        self.ran += 1;
    }
}

#[test]
fn fuzzed_command_lines_exit_cleanly_name_their_errors_and_print_finite_numbers() {
    let cases = env_number::<u32>("LOPIN_FUZZ_CASES").unwrap_or(DEFAULT_CASES);
    let budget = env_number::<f64>("LOPIN_FUZZ_BUDGET_SECONDS").map(Duration::from_secs_f64);
    let (mut runner, seed) = fuzz_runner::runner(cases, DEFAULT_SEED);
    let strategy = drawn();
    let root = std::env::temp_dir().join(format!("lopin-fuzz-cli-{}", std::process::id()));
    let scratch = |name: String| {
        let dir = root.join(name);
        std::fs::create_dir_all(&dir).expect("scratch directory");
        dir
    };
    let start = Instant::now();
    let mut tally = Tally::default();
    for (i, line) in FIXED.iter().enumerate() {
        let dir = scratch(format!("fixed-{i}"));
        tally.run(&format!("fixed {i}"), &Case::fixed(line, &dir), &dir);
    }
    for i in 0..cases {
        if budget.is_some_and(|b| start.elapsed() > b) {
            println!("time budget reached after {i} cases");
            break;
        }
        let d = strategy
            .new_tree(&mut runner)
            .expect("the case strategy always generates")
            .current();
        let dir = scratch(format!("case-{i}"));
        tally.run(&format!("case {i}"), &Case::of(&d, &dir), &dir);
    }
    std::fs::remove_dir_all(&root).ok();
    let Tally {
        ran,
        failures,
        codes,
        slowest,
    } = tally;
    println!(
        "{ran} cases (seed {seed:#x}) in {:.1} s; exits {codes:?}; slowest {:.2} s: {}",
        start.elapsed().as_secs_f64(),
        slowest.0.as_secs_f64(),
        slowest.1
    );
    fuzz_runner::assert_no_failures(&failures, seed);
}

/// The checks themselves: nulls where results belong, non-finite words, error naming.
#[test]
fn checks_catch_nulls_non_finite_words_and_unnamed_errors() {
    let v: Value = serde_json::from_str(
        r#"{"eta": null, "contact_interfaces": 0, "contact": {"min_gap": null, "max_slip": 1},
            "scene": {"solver": {"k": null}}, "values": [{"eta_history": [1, null]}],
            "macro_dofs": null}"#,
    )
    .expect("json");
    assert_eq!(
        bad_nulls(&v),
        ["`eta` is null", "`values[0].eta_history[1]` is null"]
    );
    let with_contact: Value =
        serde_json::from_str(r#"{"contact_interfaces": 1, "contact": {"min_gap": null}}"#)
            .expect("json");
    assert_eq!(bad_nulls(&with_contact), ["`contact.min_gap` is null"]);
    assert_eq!(
        non_finite_words("eta 1e-3 NaN -inf info infinite 5e-324"),
        ["NaN", "-inf"]
    );
    let case = Case {
        command: "run",
        scene: "bar".into(),
        args: vec!["run".into(), "bar".into(), "--k".into(), "-1".into()],
        json: false,
        flags: vec!["--k"],
        unknown: None,
    };
    assert!(names_source(
        "error: setting up the solver: solver setting `k`: x",
        &case
    ));
    assert!(names_source("error: --k must be positive", &case));
    assert!(!names_source("error: something failed", &case));
    assert!(!names_source(
        "error: unexpected argument '-1' found",
        &case
    ));
}
