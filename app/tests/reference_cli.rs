//! The command-line faces of the reference: `lopin reference --json` has the shape of `run`
//! with `solver: "monolithic"`, `lopin compare --json` reports small differences at a tight
//! tolerance, and `lopin accuracy` writes its CSV (one row per method and tolerance, errors
//! falling with the tolerance) and PNG.

use std::process::Command;

fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = lopin().args(args).output().expect("runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

#[test]
fn reference_json_has_the_shape_of_run() {
    let r = json(&["reference", "gap-impact", "--json"]);
    let run = json(&["run", "gap-impact", "--json"]);
    assert_eq!(r["solver"], "monolithic");
    for key in run.as_object().expect("object").keys() {
        assert!(r.get(key).is_some(), "reference JSON lacks `{key}`");
    }
    // same discrete problem: the energy balance agrees with LATIN's to its tolerance
    let (a, b) = (
        r["energy"]["kinetic_end"].as_f64().expect("number"),
        run["energy"]["kinetic_end"].as_f64().expect("number"),
    );
    assert!((a - b).abs() <= 1e-2 * a.abs(), "{a} vs {b}");
    assert!(r["contact"]["min_gap"].as_f64().expect("number") >= -6.25e-7 * (1.0 + 1e-9));
}

#[test]
fn compare_reports_small_differences_at_a_tight_tolerance() {
    let c = json(&["compare", "two-blocks", "--tol", "1e-7", "--json"]);
    let dv = c["rel_diff_velocity"].as_f64().expect("number");
    let df = c["rel_diff_force"].as_f64().expect("number");
    println!("compare two-blocks at 1e-7: {dv:.3e} {df:.3e}");
    assert!(dv < 1e-5 && df < 1e-5, "{c}");
    assert_eq!(c["reference"]["solver"], "monolithic");
    assert_eq!(c["latin"]["solver"], "latin");
}

#[test]
fn accuracy_writes_csv_and_png() {
    let dir = std::env::temp_dir().join(format!("lopin-accuracy-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = lopin()
        .args(["accuracy", "bar", "--tols", "1e-1,1e-3,1e-5", "--out"])
        .arg(&dir)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("accuracy.csv")).expect("csv");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // the reference, then 3 tolerances of each: whole interval on η, on η̄, incremental with the
    // default (smooth) and the held window start
    assert_eq!(rows.len(), 1 + 3 + 3 + 3 + 3, "{csv}");
    let errors = |method: &str| -> Vec<f64> {
        rows.iter()
            .filter(|r| r[2] == method)
            .map(|r| r[7].parse().expect("error"))
            .collect()
    };
    for method in [
        "latin",
        "latin-smooth",
        "latin-incremental",
        "latin-incremental-hold",
    ] {
        let e = errors(method);
        assert!(e[0] > e[1] && e[1] > e[2], "{method}: {e:?}");
    }
    // every LATIN row carries the field errors (displacement, column 9), falling with the
    // tolerance; the reference's are empty
    assert_eq!(rows[0][9], "");
    let u: Vec<f64> = rows[1..4]
        .iter()
        .map(|r| r[9].parse().expect("displacement error"))
        .collect();
    assert!(u[0] > u[1] && u[1] > u[2], "{u:?}");
    let fields = std::fs::read(dir.join("accuracy-fields.png")).expect("fields png");
    assert_eq!(&fields[..8], b"\x89PNG\r\n\x1a\n");
    // the bar has an exact solution: every row carries the error against it, above the floor
    let floor: f64 = rows[0][8].parse().expect("floor");
    assert!(floor > 0.0 && floor < 0.2, "{floor}");
    assert!(rows
        .iter()
        .all(|r| r[8].parse::<f64>().expect("exact") >= floor * 0.99));
    let png = std::fs::read(dir.join("accuracy.png")).expect("png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let _ = std::fs::remove_dir_all(&dir);
}
