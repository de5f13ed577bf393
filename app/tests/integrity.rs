//! Integrity of what Lopin reads back, through the real `lopin` binary on `mini-blocks`: a
//! resumed sweep recomputes, from the first damaged value on, a state file filled with garbage,
//! a valid state file of another value, a state holding NaN behind valid checksums, or an
//! edited record, and ends with the numbers
//! of the uninterrupted sweep; it refuses a damaged `sweep.json` and a scene file edited since
//! the sweep; `lopin export` refuses a damaged `solution.bin`, one holding NaN behind a valid
//! checksum, and one of another run, naming the file and the reason and writing nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use lopin_app::run_dir::checked_json;
use lopin_app::run_dir::fingerprint::Fingerprint;
use lopin_app::run_dir::run_json::RunRecord;
use lopin_app::run_dir::solution_file;

fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lopin-integrity-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn succeeds(o: Output) -> Output {
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

const SWEEP: [&str; 4] = ["sweep", "mini-blocks", "--param", "f=0.1,0.2,0.3"];

/// The 3-value sweep into `dir`, with `extra` options.
fn sweep(dir: &Path, extra: &[&str]) -> Output {
    lopin()
        .args(SWEEP)
        .args(extra)
        .arg("--out")
        .arg(dir)
        .output()
        .expect("lopin sweep runs")
}

fn record(dir: &Path, i: usize) -> serde_json::Value {
    let path = dir.join(format!("value-{i:03}.json"));
    serde_json::from_str(&std::fs::read_to_string(&path).expect("record")).expect("JSON")
}

/// The numbers of two records agree (not their timings).
fn same_numbers(a: &serde_json::Value, b: &serde_json::Value) {
    assert_eq!(a["iterations"], b["iterations"], "value {}", a["value"]);
    assert_eq!(a["value"], b["value"]);
    assert_eq!(a["converged"], b["converged"]);
    for key in ["eta", "peak_normal_force", "max_slip", "energy_end"] {
        let (x, y) = (a[key].as_f64().expect("num"), b[key].as_f64().expect("num"));
        assert!(
            (x - y).abs() <= 1e-12 * x.abs().max(1e-300),
            "{key}: {x} vs {y}"
        );
    }
    assert_eq!(
        a["eta_history"].as_array().map(Vec::len),
        b["eta_history"].as_array().map(Vec::len)
    );
}

/// Damages `dir` with `damage`, resumes, and checks that the resume succeeds, reports
/// `file` on stderr with `reason` and recomputes values 1 and 2 to the numbers of the
/// uninterrupted sweep, keeping value 0 as it was. Returns stderr.
fn damage_and_resume(name: &str, file: &str, reason: &str, damage: impl FnOnce(&Path)) -> String {
    let dir = scratch(name);
    succeeds(sweep(&dir, &[]));
    let before: Vec<_> = (0..3).map(|i| record(&dir, i)).collect();
    let first = std::fs::read(dir.join("value-000.json")).expect("value 0");
    damage(&dir);
    let o = succeeds(sweep(&dir, &["--resume"]));
    let err = stderr(&o);
    let named = dir.join(file).display().to_string();
    assert!(err.contains(&named), "{err}");
    assert!(err.contains(reason), "{err}");
    assert!(err.contains("recomputing values 1 … 2"), "{err}");
    assert!(err.contains("1 of 3 values finished"), "{err}");
    assert_eq!(
        std::fs::read(dir.join("value-000.json")).expect("value 0"),
        first,
        "the valid value before the damage is kept as it was"
    );
    for (i, b) in before.iter().enumerate() {
        same_numbers(b, &record(&dir, i));
    }
    // the repaired directory resumes without recomputing anything
    let again = succeeds(sweep(&dir, &["--resume"]));
    let err2 = stderr(&again);
    assert!(
        !err2.contains("recomputing") && err2.contains("3 of 3 values finished"),
        "{err2}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    err
}

#[test]
fn resume_recomputes_a_state_file_filled_with_garbage() {
    let err = damage_and_resume(
        "garbage-state",
        "value-001.state",
        "the file is damaged",
        |dir| {
            let path = dir.join("value-001.state");
            let len = std::fs::metadata(&path).expect("state").len() as usize;
            let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
            let garbage: Vec<u8> = (0..len)
                .map(|_| {
                    x = x
                        .wrapping_mul(6_364_136_223_846_793_005)
                        .wrapping_add(1_442_695_040_888_963_407);
                    (x >> 56) as u8
                })
                .collect();
            std::fs::write(&path, garbage).expect("garbage");
        },
    );
    assert!(err.contains("checksum mismatch (recorded"), "{err}");
}

#[test]
fn resume_recomputes_a_valid_state_file_of_another_value() {
    damage_and_resume(
        "swapped-state",
        "value-001.state",
        "checksum mismatch (recorded",
        |dir| {
            std::fs::copy(dir.join("value-000.state"), dir.join("value-001.state"))
                .expect("copies");
        },
    );
}

#[test]
fn resume_recomputes_a_state_with_nan_behind_valid_checksums() {
    damage_and_resume(
        "nan-state",
        "value-001.state",
        "non-finite value NaN in F of trace 1 at step 7",
        |dir| {
            // a state written by Lopin's own encoder, bound to the sweep, with one NaN; the
            // record's checksums are remade to match, so only the finiteness check can see it
            let record_path = dir.join("value-001.json");
            let mut rec = record(dir, 1);
            let hash: Fingerprint = rec["sweep_hash"]
                .as_str()
                .expect("sweep_hash")
                .parse()
                .expect("fingerprint");
            let path = dir.join("value-001.state");
            let bytes = std::fs::read(&path).expect("state");
            let mut state = solution_file::decode_state(&bytes, hash).expect("valid state");
            let len = state.subs[1].len;
            state.subs[1].f[7 * len] = f64::NAN;
            let bytes = solution_file::encode_state(&state, hash);
            std::fs::write(&path, &bytes).expect("writes");
            rec["state_checksum"] = format!("{:08x}", solution_file::file_checksum(&bytes)).into();
            rec["checksum"] = checked_json::PLACEHOLDER.into();
            std::fs::write(&record_path, checked_json::seal(&rec).expect("seals")).expect("writes");
        },
    );
}

#[test]
fn resume_recomputes_a_record_whose_checksum_fails() {
    let err = damage_and_resume(
        "edited-record",
        "value-001.json",
        "checksum mismatch (stored",
        |dir| {
            let path = dir.join("value-001.json");
            let text = std::fs::read_to_string(&path).expect("record");
            let it = record(dir, 1)["iterations"].as_u64().expect("iterations");
            let edited = text.replace(
                &format!("\"iterations\": {it},"),
                &format!("\"iterations\": {},", it + 1),
            );
            assert_ne!(edited, text);
            std::fs::write(&path, edited).expect("writes");
        },
    );
    assert!(err.contains("the file is damaged or was edited"), "{err}");
}

#[test]
fn resume_refuses_a_damaged_sweep_header() {
    let dir = scratch("damaged-header");
    succeeds(sweep(&dir, &[]));
    let head = dir.join("sweep.json");
    let text = std::fs::read_to_string(&head).expect("sweep.json");
    let last = std::fs::read(dir.join("value-002.json")).expect("record");
    std::fs::write(
        &head,
        text.replace("\"mode\": \"warm\"", "\"mode\": \"cold\""),
    )
    .expect("w");
    let o = sweep(&dir, &["--resume"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains(&head.display().to_string()) && err.contains("checksum mismatch (stored"),
        "{err}"
    );
    // cut short: not JSON any more
    std::fs::write(&head, &text[..text.len() / 2]).expect("w");
    let o = sweep(&dir, &["--resume"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains(&head.display().to_string()) && err.contains("not JSON"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(dir.join("value-002.json")).expect("record"),
        last,
        "nothing rewritten"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn resume_refuses_when_the_scene_file_changed() {
    let dir = scratch("scene-changed");
    let scene = dir.join("blocks.toml");
    let o = succeeds(
        lopin()
            .args(["export-scene", "mini-blocks"])
            .output()
            .expect("runs"),
    );
    std::fs::write(&scene, &o.stdout).expect("scene file");
    let out = dir.join("sweep");
    let run = |resume: bool| {
        let mut c = lopin();
        c.arg("sweep")
            .arg(&scene)
            .args(["--param", "f=0.1,0.2", "--out"])
            .arg(&out);
        if resume {
            c.arg("--resume");
        }
        c.output().expect("runs")
    };
    succeeds(run(false));
    succeeds(run(true));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let denser = text.replacen("density = 7800.0", "density = 7900.0", 1);
    assert_ne!(denser, text, "the scene file holds the steel density");
    std::fs::write(&scene, denser).expect("edits");
    let o = run(true);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains(&scene.display().to_string())
            && err.contains("the scene changed since this sweep was made")
            && err.contains("sweep.json"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `lopin run mini-blocks --out DIR` with `extra` options.
fn run_out(dir: &Path, extra: &[&str]) {
    succeeds(
        lopin()
            .args(["run", "mini-blocks"])
            .args(extra)
            .arg("--out")
            .arg(dir)
            .output()
            .expect("lopin run runs"),
    );
}

/// `lopin export RUN --vtu VTU`.
fn export(run: &Path, vtu: &Path) -> Output {
    lopin()
        .arg("export")
        .arg(run)
        .arg("--vtu")
        .arg(vtu)
        .output()
        .expect("lopin export runs")
}

/// Export fails, naming `solution.bin` of `run` and `reason`, and writes nothing.
fn export_refused(run: &Path, reason: &str) -> String {
    let vtu = run.with_extension("vtu-refused");
    let o = export(run, &vtu);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    let bin = run.join("solution.bin").display().to_string();
    assert!(err.contains(&bin) && err.contains(reason), "{err}");
    assert!(!vtu.exists(), "nothing written");
    err
}

#[test]
fn export_refuses_a_damaged_solution_file() {
    let dir = scratch("damaged-solution");
    let run = dir.join("run");
    run_out(&run, &[]);
    succeeds(export(&run, &dir.join("vtu")));
    let path = run.join("solution.bin");
    let mut bytes = std::fs::read(&path).expect("solution.bin");
    let at = bytes.len() / 2;
    bytes[at] ^= 0x40;
    std::fs::write(&path, &bytes).expect("writes");
    let err = export_refused(&run, "checksum mismatch (stored");
    assert!(err.contains("the file is damaged"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_refuses_a_solution_with_nan() {
    let dir = scratch("nan-solution");
    let run = dir.join("run");
    run_out(&run, &[]);
    let record = RunRecord::read(&run).expect("run.json");
    let path = run.join("solution.bin");
    let mut sol = solution_file::read_solution(&path, record.fingerprint()).expect("valid");
    let len = sol.hats[0][1].len;
    sol.hats[0][1].w[3 * len + 2] = f64::NAN;
    std::fs::write(
        &path,
        solution_file::encode_solution_for(&sol, record.fingerprint()),
    )
    .expect("writes");
    export_refused(
        &run,
        "non-finite value NaN in Ŵ of interface 0 side 1 at step 3",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_refuses_a_solution_of_another_run() {
    let dir = scratch("foreign-solution");
    let (mine, other) = (dir.join("mine"), dir.join("other"));
    run_out(&mine, &[]);
    // same layout, another friction: only the fingerprint tells the files apart
    run_out(&other, &["--f", "0.5"]);
    std::fs::copy(other.join("solution.bin"), mine.join("solution.bin")).expect("copies");
    export_refused(&mine, "belongs to another scene or settings (hash ");
    let _ = std::fs::remove_dir_all(&dir);
}
