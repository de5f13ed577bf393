//! `lopin study` from the command line: a study killed with SIGKILL after a few
//! configurations and resumed keeps every finished row byte for byte, solves the rest, and ends
//! with the same configurations, starts, iterations and quantities (to 1e-9: the resumed chain
//! starts from the kept configurations' converged states) as an uninterrupted study, with its
//! figures and `study.parquet` (the CSV's rows, typed); a resume whose kept state is damaged
//! names the file and goes on without it; the rows a killed distributed study left
//! in a rank's folder are taken in by the resume; a study over two zones of a Gmsh scene (its
//! contact face's physical surfaces) writes a column per zone; bad input is refused with a
//! message naming the option and the reason, before anything is written.

mod study_files;

use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};
use study_files::{lopin, parquet_matches_csv, scratch, succeeds};

const ARGS: [&str; 8] = [
    "study",
    "two-blocks",
    "--param",
    "f=0:0.3:0.1",
    "--param",
    "gap=0,2e-6",
    "--rho-inf",
    "0.5",
];

/// Data rows of study.csv keyed by configuration index.
fn rows(dir: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    let mut out: Vec<(usize, String)> = text
        .lines()
        .skip(1)
        .map(|l| {
            (
                l.split(',')
                    .next()
                    .expect("test value")
                    .parse()
                    .expect("test value"),
                l.to_string(),
            )
        })
        .collect();
    out.sort();
    out
}

fn field<'a>(line: &'a str, header: &str, name: &str) -> &'a str {
    let k = header.split(',').position(|h| h == name).expect(name);
    line.split(',').nth(k).expect("test value")
}

fn column(line: &str, header: &str, name: &str) -> f64 {
    let k = header.split(',').position(|h| h == name).expect(name);
    line.split(',')
        .nth(k)
        .expect("test value")
        .parse()
        .expect("number")
}

#[test]
fn a_killed_study_resumes_without_losing_a_row() {
    let full = scratch("study", "full");
    let out = succeeds(lopin().args(ARGS).args(["--json", "--out"]).arg(&full));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(json["totals"]["configurations"], 8);
    assert_eq!(json["totals"]["converged"], 8);
    // the path walks f first: one gap step in the whole study
    let order: Vec<usize> = json["plan"]["order"]
        .as_array()
        .expect("order")
        .iter()
        .map(|v| v.as_u64().expect("test value") as usize)
        .collect();
    assert_eq!(order, [0, 2, 4, 6, 7, 5, 3, 1]);
    for f in [
        "quantities.png",
        "map.png",
        "sensitivities.png",
        "sensitivities.csv",
    ] {
        assert!(full.join(f).exists(), "{f}");
    }
    assert_eq!(rows(&full).len(), 8);

    let part = scratch("study", "part");
    let mut child = lopin()
        .args(ARGS)
        .arg("--out")
        .arg(&part)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawns");
    let start = Instant::now();
    loop {
        let n = std::fs::read_to_string(part.join("study.csv")).map_or(0, |t| t.lines().count());
        if n >= 4 || child.try_wait().expect("wait").is_some() {
            break;
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no progress");
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().ok(); // SIGKILL
    child.wait().expect("reaped");
    let kept = rows(&part);
    println!("killed after {} rows", kept.len());
    assert!(!kept.is_empty());

    // without --resume the folder is refused and left as it was
    let refused = lopin()
        .args(ARGS)
        .arg("--out")
        .arg(&part)
        .output()
        .expect("runs");
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--resume"));
    assert_eq!(rows(&part), kept);
    // another study cannot be resumed into it
    let other = lopin()
        .args([
            "study",
            "two-blocks",
            "--param",
            "f=0:0.3:0.15",
            "--resume",
            "--out",
        ])
        .arg(&part)
        .output()
        .expect("runs");
    assert!(!other.status.success());
    let msg = String::from_utf8_lossy(&other.stderr);
    assert!(
        msg.contains("study.json") && msg.contains("differs"),
        "{msg}"
    );
    assert_eq!(rows(&part), kept);

    succeeds(lopin().args(ARGS).args(["--resume", "--out"]).arg(&part));
    let after = rows(&part);
    assert_eq!(after.len(), 8);
    // the typed table of every row, kept and resumed alike
    parquet_matches_csv(&part);
    for row in &kept {
        assert!(after.contains(row), "row lost or changed: {row:?}");
    }
    let header = std::fs::read_to_string(full.join("study.csv")).expect("test value");
    let header = header.lines().next().expect("test value").to_string();
    for ((i, a), (j, b)) in rows(&full).iter().zip(&after) {
        assert_eq!(i, j);
        for q in ["start", "iterations"] {
            assert_eq!(
                field(a, &header, q),
                field(b, &header, q),
                "configuration {i} {q}"
            );
        }
        for q in ["peak_normal_force", "energy_end", "input_work"] {
            let (x, y) = (column(a, &header, q), column(b, &header, q));
            assert!(
                (x - y).abs() <= 1e-9 * x.abs(),
                "configuration {i} {q}: {x} vs {y}"
            );
        }
    }

    // the states: one per configuration; a damaged one is named, and the chain goes on from
    // another (every configuration still solved and converged)
    let states = part.join("states");
    assert_eq!(std::fs::read_dir(&states).expect("states").count(), 8);
    let damaged = scratch("study", "damaged-state");
    std::fs::create_dir_all(damaged.join("states")).expect("mkdir");
    let first: Vec<String> = std::fs::read_to_string(part.join("study.csv"))
        .expect("csv")
        .lines()
        .take(3)
        .map(str::to_string)
        .collect();
    std::fs::write(damaged.join("study.csv"), first.join("\n") + "\n").expect("csv");
    std::fs::copy(part.join("study.json"), damaged.join("study.json")).expect("json");
    let kept_index: Vec<usize> = first[1..]
        .iter()
        .map(|l| l.split(',').next().expect("index").parse().expect("index"))
        .collect();
    for &i in &kept_index {
        let name = format!("config-{i:04}.state");
        std::fs::copy(states.join(&name), damaged.join("states").join(&name)).expect("copy");
    }
    let bad = damaged
        .join("states")
        .join(format!("config-{:04}.state", kept_index[1]));
    let mut bytes = std::fs::read(&bad).expect("state");
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x10;
    std::fs::write(&bad, bytes).expect("write");
    let out = succeeds(lopin().args(ARGS).args(["--resume", "--out"]).arg(&damaged));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&bad.display().to_string())
            && stderr.contains(&format!("configuration {} is kept", kept_index[1])),
        "{stderr}"
    );
    let resumed = rows(&damaged);
    assert_eq!(resumed.len(), 8);
    assert!(resumed
        .iter()
        .all(|(_, l)| field(l, &header, "converged") == "true"));

    // a distributed study killed mid-way leaves rank 1's rows in rank-1/: a resume takes them in
    // (solving none of them again: every row comes back byte for byte) and removes the folder
    let split = scratch("study", "ranks");
    let side = split.join("rank-1");
    std::fs::create_dir_all(&side).expect("test value");
    for d in [&split, &side] {
        std::fs::copy(full.join("study.json"), d.join("study.json")).expect("test value");
    }
    let (mut even, mut odd) = (format!("{header}\n"), format!("{header}\n"));
    for (i, r) in rows(&full) {
        let to = if i % 2 == 0 { &mut even } else { &mut odd };
        to.push_str(&r);
        to.push('\n');
    }
    std::fs::write(split.join("study.csv"), even).expect("test value");
    std::fs::write(side.join("study.csv"), odd).expect("test value");
    let taken = succeeds(
        lopin()
            .args(ARGS)
            .args(["--resume", "--json", "--out"])
            .arg(&split),
    );
    assert_eq!(rows(&split), rows(&full));
    parquet_matches_csv(&split);
    assert!(!side.exists(), "rank-1/ is left");
    let taken: serde_json::Value = serde_json::from_slice(&taken.stdout).expect("json");
    assert_eq!(taken["totals"]["iterations"], json["totals"]["iterations"]);
}

/// Runs `lopin study two-blocks ARGS --out DIR`, which must fail with a message holding every
/// one of `needles`, writing nothing.
fn refused(args: &[&str], needles: &[&str]) {
    let dir = scratch("study", "bad");
    let out = lopin()
        .args(["study", "two-blocks"])
        .args(args)
        .arg("--out")
        .arg(&dir)
        .output()
        .expect("runs");
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} accepted");
    assert!(!msg.contains("panicked"), "{msg}");
    for n in needles {
        assert!(msg.contains(n), "{args:?}: `{n}` not in: {msg}");
    }
    assert!(!dir.exists(), "{args:?} wrote {}", dir.display());
}

#[test]
fn bad_study_input_is_refused_with_the_option_and_the_reason() {
    refused(
        &["--param", "mu=0:1:0.1"],
        &["--param mu=0:1:0.1", "unknown parameter `mu`"],
    );
    refused(
        &["--param", "f@nowhere=0:0.5:0.1"],
        &["unknown zone `nowhere`"],
    );
    refused(&["--param", "f=0.5:0:0.1"], &["stop ≥ start"]);
    refused(
        &["--param", "f=0:0.5:0.1", "--samples", "-5"],
        &["--samples", "positive"],
    );
    refused(
        &["--param", "f=0:0.5:0.1", "--samples", "0"],
        &["--samples", "positive"],
    );
    refused(
        &["--param", "f=normal(0.1,0.2)", "--samples", "20"],
        &["f = -", "non-negative", "normal(0.1, 0.2)", "lognormal"],
    );
    refused(&["--param", "gap=inf,0"], &["gap", "is not a number"]);
    refused(
        &["--param", "f=uniform(0,1)"],
        &["distribution", "--samples"],
    );
    refused(
        &["--param", "f=lognormal(0,0)"],
        &["standard deviation must be positive"],
    );
    refused(&["--param", "f=0,1", "--param", "f=0.2"], &["given twice"]);
    refused(&["--param", "f"], &["--param must look like"]);
    refused(&["--param", "f=0:0.5:0.1", "--chains", "0"], &["--chains"]);
    refused(
        &["--param", "f=0:0.5:0.1", "--resume"],
        &["--resume", "no study to resume"],
    );
}

/// `lopin study` over two zones of a Gmsh scene, the contact face's physical surfaces `centre`
/// and `rim` (needs gmsh: the README's test command installs it): one column per zone, every
/// configuration converged, the rim's friction holding the slip (with f = 0.5 at the centre and
/// 0 on the rim the slip is over 5 times that the other way round), and study.parquet with the
/// same rows.
#[test]
fn a_study_over_two_zones_of_a_gmsh_scene_moves_each_zone() {
    let dir = scratch("study", "zones");
    let scene = format!(
        "{}/../assets/scenes/gmsh/two-blocks-pads-gmsh.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    succeeds(
        lopin()
            .args(["study", &scene, "--param", "f@centre=0,0.5"])
            .args(["--param", "f@rim=0,0.5", "--window", "whole", "--out"])
            .arg(&dir),
    );
    let text = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    let header = text.lines().next().expect("header");
    assert!(header.contains(",f@centre,f@rim,"), "{header}");
    let rows = rows(&dir);
    assert_eq!(rows.len(), 4);
    let at = |c: f64, r: f64| {
        rows.iter()
            .map(|(_, l)| l)
            .find(|l| column(l, header, "f@centre") == c && column(l, header, "f@rim") == r)
            .expect("configuration")
    };
    for (_, l) in &rows {
        assert!(l.contains(",true,"), "not converged: {l}");
    }
    let (free_rim, held_rim) = (
        column(at(0.5, 0.0), header, "max_slip"),
        column(at(0.0, 0.5), header, "max_slip"),
    );
    println!("max slip: f@centre 0.5, f@rim 0: {free_rim:.3e} m; f@centre 0, f@rim 0.5: {held_rim:.3e} m");
    assert!(free_rim > 5.0 * held_rim, "{free_rim:e} {held_rim:e}");
    parquet_matches_csv(&dir);
    let _ = std::fs::remove_dir_all(&dir);
}
