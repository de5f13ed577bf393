//! The hardening cases as a user meets them on the command line, one test per case, each named
//! after it: every one ends with exit status 2 and one `error:` line naming the option, file or
//! field and the reason — never a panic, an abort, a silent wrap or a NaN result.

use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn lopin(args: &[&str], env: &[(&str, &str)]) -> (Output, Duration) {
    let start = Instant::now();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_lopin"));
    cmd.args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("lopin runs");
    (out, start.elapsed())
}

/// Runs lopin, expects exit status 2, and returns its stderr.
fn refused(args: &[&str], env: &[(&str, &str)]) -> String {
    let (out, _) = lopin(args, env);
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
    stderr
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lopin-hardening-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// A scene file: `lopin export-scene NAME` with `edit` applied.
fn scene_file(name: &str, file: &str, edit: impl Fn(String) -> String) -> String {
    let (out, _) = lopin(&["export-scene", name], &[]);
    assert!(out.status.success());
    let original = String::from_utf8(out.stdout).expect("utf8");
    let text = edit(original.clone());
    assert_ne!(text, original, "{file}: the edit did not apply");
    let path = temp(file);
    std::fs::write(&path, text).expect("write");
    path.to_str().expect("utf8").to_string()
}

#[test]
fn estimate_of_a_10_12_element_scene_answers_at_once_with_a_refusal() {
    let file = scene_file("two-blocks", "huge.toml", |t| {
        t.replace(
            "divisions = [\n    10,\n    10,\n    5,\n]",
            "divisions = [10000, 10000, 5000]",
        )
    });
    let (out, took) = lopin(&["estimate", &file], &[]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    for part in [
        "huge.toml",
        "1000000000000 hexahedra",
        "more than this machine can give it",
        "What would fit",
    ] {
        assert!(stderr.contains(part), "no `{part}` in {stderr}");
    }
    // a bound against hangs (the answer takes milliseconds; the guide gives the figure)
    assert!(took < Duration::from_secs(20), "{took:?}");
}

#[test]
fn estimate_of_refine_100_is_refused_with_the_refinement_that_fits() {
    let stderr = refused(&["estimate", "two-blocks", "--refine", "100"], &[]);
    assert!(
        stderr.contains("scene two-blocks")
            && stderr.contains("--refine ")
            && stderr.contains(" fits"),
        "{stderr}"
    );
}

#[test]
fn run_with_refine_u64_max_is_an_error_not_a_capacity_overflow_panic() {
    let stderr = refused(
        &["run", "two-blocks", "--refine", "18446744073709551615"],
        &[],
    );
    assert!(
        stderr.contains("--refine 18446744073709551615") && stderr.contains("does not fit"),
        "{stderr}"
    );
}

#[test]
fn run_with_refine_that_used_to_wrap_to_1_is_an_error() {
    let stderr = refused(
        &["run", "two-blocks", "--refine", "4611686018427387905"],
        &[],
    );
    assert!(stderr.contains("--refine 4611686018427387905"), "{stderr}");
}

#[test]
fn run_that_cannot_fit_is_refused_before_allocating_with_what_would_fit() {
    let stderr = refused(
        &["run", "granular-small"],
        &[("LOPIN_MEMORY_LIMIT", "64MiB")],
    );
    for part in [
        "scene granular-small",
        "LOPIN_MEMORY_LIMIT",
        "What would fit",
        "`time.steps` at most",
    ] {
        assert!(stderr.contains(part), "no `{part}` in {stderr}");
    }
    // a limit below what the process itself holds says so
    let stderr = refused(
        &["run", "granular-small"],
        &[("LOPIN_MEMORY_LIMIT", "16MiB")],
    );
    assert!(
        stderr.contains("a memory limit above the 32.0 MiB the process itself holds"),
        "{stderr}"
    );
    let stderr = refused(&["run", "two-blocks"], &[("LOPIN_MEMORY_LIMIT", "lots")]);
    assert!(
        stderr.contains("LOPIN_MEMORY_LIMIT") && stderr.contains("`lots`"),
        "{stderr}"
    );
}

#[test]
fn run_with_k_1e300_names_k_not_a_pivot() {
    let stderr = refused(&["run", "two-blocks", "--k", "1e300"], &[]);
    assert!(
        stderr.contains("`k`") && stderr.contains("impedance") && !stderr.contains("pivot"),
        "{stderr}"
    );
}

#[test]
fn sweep_of_v0_1e300_is_an_error_not_a_plotting_panic() {
    let out = temp("sweep-v0");
    let stderr = refused(
        &[
            "sweep",
            "bar",
            "--param",
            "v0=1e300",
            "--out",
            out.to_str().expect("utf8"),
        ],
        &[],
    );
    assert!(
        stderr.contains("v0") && stderr.contains("slowest wave speed"),
        "{stderr}"
    );
}

#[test]
fn out_on_an_existing_file_names_the_path_before_solving() {
    let file = temp("not-a-folder");
    std::fs::write(&file, "x").expect("write");
    let path = file.to_str().expect("utf8");
    let stderr = refused(&["run", "bar", "--out", path], &[]);
    assert!(
        stderr.contains("--out") && stderr.contains(path) && stderr.contains("not a folder"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&file).expect("kept"), "x");
}

#[test]
fn max_iter_0_in_the_solver_table_names_the_file_and_field() {
    let file = scene_file("two-blocks", "max-iter.toml", |t| {
        t.replace("[solver]\n", "[solver]\nmax_iter = 0\n")
    });
    let stderr = refused(&["run", &file], &[]);
    assert!(
        stderr.contains("max-iter.toml") && stderr.contains("solver.max_iter"),
        "{stderr}"
    );
}

#[test]
fn dt_5e_324_names_time_dt_and_the_scale_it_is_judged_against() {
    let file = scene_file("two-blocks", "dt.toml", |t| {
        t.replace("dt = 0.00000025", "dt = 5e-324")
    });
    let stderr = refused(&["run", &file], &[]);
    assert!(
        stderr.contains("dt.toml") && stderr.contains("time.dt") && stderr.contains("P wave"),
        "{stderr}"
    );
}

/// `--rho-inf` outside [0, 1] is refused naming the option and the range; inside, the run's JSON
/// reports the scheme it solved with.
#[test]
fn rho_inf_out_of_range() {
    for bad in ["1.5", "-0.2", "nan"] {
        let err = refused(&["run", "bar", "--rho-inf", bad], &[]);
        assert!(err.contains("--rho-inf") && err.contains("[0, 1]"), "{err}");
    }
    let (out, _) = lopin(&["run", "bar", "--rho-inf", "0.8", "--json"], &[]);
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(json["rho_inf"], 0.8);
}

/// `--set NAME[@ZONE]=VALUE` sets an interface parameter on the built problem through
/// `Parameter`, as `--f` does: the same solve, iteration for iteration; `run.json` records the
/// value, not a changed scene; a parameter, zone or value that does not apply is refused naming
/// it.
#[test]
fn set_assigns_interface_parameters() {
    let solve = |args: &[&str]| {
        let mut all = vec!["run", "mini-blocks", "--json"];
        all.extend_from_slice(args);
        let (out, _) = lopin(&all, &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        (json["iterations"].clone(), json["eta"].clone())
    };
    let by_f = solve(&["--f", "0.45"]);
    assert_eq!(solve(&["--set", "f=0.45"]), by_f);
    assert_ne!(solve(&[]), by_f, "f = 0.45 changes the solve");
    // applied in order, after --f: the last value stands
    assert_eq!(solve(&["--f", "0.1", "--set", "f=0.45"]), by_f);
    for (scene, set, says) in [
        ("mini-blocks", "mu=0.3", "unknown parameter `mu`"),
        ("mini-blocks", "f@nowhere=0.3", "unknown zone `nowhere`"),
        ("mini-blocks", "f=abc", "not a number"),
        ("mini-blocks", "f=20", "[0, 10]"),
        ("bar", "f=0.3", "applies to nothing"),
    ] {
        let all = ["run", scene, "--set", set];
        let args = &all[2..];
        let err = refused(&all, &[]);
        assert!(err.contains(says), "{args:?}: {err}");
    }
    let dir = std::env::temp_dir().join(format!("lopin-set-{}", std::process::id()));
    let out_dir = dir.to_str().expect("utf-8");
    let (out, _) = lopin(
        &["run", "mini-blocks", "--set", "gap=1e-6", "--out", out_dir],
        &[],
    );
    assert!(out.status.success());
    let run: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run.json")).expect("run.json"))
            .expect("json");
    assert_eq!(run["assignments"][0]["target"], "gap");
    assert_eq!(run["assignments"][0]["value"], 1e-6);
    let vtu = dir.join("vtu");
    let (out, _) = lopin(
        &["export", out_dir, "--vtu", vtu.to_str().expect("utf-8")],
        &[],
    );
    assert!(
        out.status.success(),
        "the recorded assignment rebuilds the same problem: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--directions` takes `isotropic` or `wave`: another name is refused with both listed; the
/// report says which direction ran.
#[test]
fn unknown_search_direction() {
    let err = refused(&["run", "bar", "--directions", "tensor"], &[]);
    assert!(
        err.contains("--directions") && err.contains("isotropic or wave"),
        "{err}"
    );
    let (out, _) = lopin(&["run", "bar", "--directions", "wave", "--json"], &[]);
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(json["settings"]["directions"], "wave");
}

/// With no `--window`, one cold solve of a scene with contact runs on one-step windows and one
/// without contact on the whole interval, saying why; `--window whole`
/// and a number are obeyed and reported as asked for; anything else is refused naming what is
/// accepted.
#[test]
fn windows_are_chosen_for_the_task_and_reported() {
    let settings = |args: &[&str]| {
        let (out, _) = lopin(args, &[]);
        assert!(out.status.success(), "{args:?}");
        let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        json["settings"].clone()
    };
    let auto = settings(&["run", "two-blocks", "--json"]);
    assert_eq!(auto["window"], 1);
    assert!(
        auto["window_reason"]
            .as_str()
            .is_some_and(|r| r.starts_with("auto: one cold solve with contact")),
        "{auto}"
    );
    let no_contact = settings(&["run", "bar", "--json"]);
    assert!(no_contact["window"].is_null(), "{no_contact}");
    let whole = settings(&["run", "two-blocks", "--window", "whole", "--json"]);
    assert!(whole["window"].is_null() && whole["window_reason"] == "asked for");
    assert_eq!(
        settings(&["run", "bar", "--window", "4", "--json"])["window"],
        4
    );
    let err = refused(&["run", "bar", "--window", "half"], &[]);
    assert!(
        err.contains("--window") && err.contains("`whole` or `auto`"),
        "{err}"
    );
}

/// `--rho-inf` goes into the run's settings: a run directory of a damped run exports again (the
/// scene rebuilds to the same problem, ρ∞ included).
#[test]
fn a_damped_run_exports_again() {
    let dir = std::env::temp_dir().join(format!("lopin-rho-inf-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (run_dir, vtu) = (dir.join("run"), dir.join("vtu"));
    let (run_dir, vtu) = (
        run_dir.to_str().expect("utf-8"),
        vtu.to_str().expect("utf-8"),
    );
    let (out, _) = lopin(&["run", "bar", "--rho-inf", "0.8", "--out", run_dir], &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (out, _) = lopin(&["export", run_dir, "--vtu", vtu], &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_with_f_1e300_is_refused_naming_the_range() {
    let stderr = refused(&["run", "two-blocks", "--f", "1e300"], &[]);
    assert!(
        stderr.contains("--f: a friction coefficient lies in [0, 10], got 1e300"),
        "{stderr}"
    );
    let stderr = refused(&["run", "two-blocks", "--f=-1e300"], &[]);
    assert!(
        stderr.contains("--f: must be non-negative, got -1e300"),
        "{stderr}"
    );
}
