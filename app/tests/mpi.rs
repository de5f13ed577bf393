//! `lopin` under `mpirun` (feature `mpi`): the same scene on 1, 2, 3 and 4 ranks
//! (oversubscribed on a 2-core machine) takes the same iterations, reaches the same η (same
//! bits) and writes the same solution file, byte for byte, as the run on one machine:
//! `two-blocks --split 2`, `granular-small` single- and two-scale, `two-blocks-nonmatching`
//! (its non-matching contact across two ranks), and a 3-value friction sweep
//! (its state files); a study's chains dealt to 2 and 3 ranks give the rows of the same chains
//! on threads of one process; a run restarted from a checkpoint writes the solution of the
//! uninterrupted run; bad input ends every rank with one message; a rank that dies ends the job
//! within seconds, and the job's output says which rank and where to restart. The run and study
//! folders an mpirun job writes open in the explorer, every stored state readable.
#![cfg(feature = "mpi")]

use lopin_explorer::result_folder::{FolderKind, StoredResult};
use lopin_explorer::Loaded;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const LOPIN: &str = env!("CARGO_BIN_EXE_lopin");

fn mpirun(ranks: usize, args: &[&str]) -> Command {
    let mut c = Command::new("mpirun");
    c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .args(["-np", &ranks.to_string(), LOPIN])
        .args(args);
    c
}

fn run(c: &mut Command) -> Output {
    let out = c.output().expect("starts");
    assert!(
        out.status.success(),
        "{c:?}: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("lopin-mpi-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The stderr of a job that failed and its one `error` line (every rank agreed on one message).
fn one_error(out: &Output) -> (String, String) {
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let ours: Vec<&str> = err.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(ours.len(), 1, "{err}");
    let line = ours[0].to_string();
    (err, line)
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn runs_equal_the_run_on_one_machine_on_one_to_four_ranks() {
    let cases: [&[&str]; 3] = [
        &["two-blocks", "--split", "2"],
        &["granular-small", "--macro", "off"],
        &["granular-small", "--macro", "on"],
    ];
    for case in cases {
        let dir = scratch("one");
        let one = dir.display().to_string();
        let mut args: Vec<&str> = vec!["run"];
        args.extend(case);
        args.extend(["--json", "--out", &one]);
        let serial = json(&run(Command::new(LOPIN).args(&args)));
        for ranks in 1..=4 {
            let d = scratch(&format!("np{ranks}"));
            let out = d.display().to_string();
            let mut a: Vec<&str> = vec!["run"];
            a.extend(case);
            a.extend(["--json", "--out", &out]);
            let dist = json(&run(&mut mpirun(ranks, &a)));
            assert_eq!(
                dist["iterations"], serial["iterations"],
                "{case:?} on {ranks}"
            );
            assert_eq!(dist["eta"], serial["eta"], "{case:?} on {ranks}");
            assert!(
                bytes(&d.join("solution.bin")) == bytes(&dir.join("solution.bin")),
                "{case:?} on {ranks} ranks: the solution file differs"
            );
            if ranks == 2 {
                opens_in_the_explorer(&d, &dist);
            }
            println!(
                "{case:?}: {ranks} ranks, {} iterations, eta {}, solution file identical",
                dist["iterations"], dist["eta"]
            );
        }
    }
}

/// The folder an mpirun run wrote opens in the explorer: one row, its stored solution (the
/// run's iterations) read back whole for the rebuilt problem.
fn opens_in_the_explorer(dir: &Path, report: &serde_json::Value) {
    let Loaded::Folder(f) = lopin_app::result_folder::open(dir).expect("the explorer opens it")
    else {
        panic!("a run folder without stored fields opens with its scene");
    };
    assert_eq!(f.kind, FolderKind::Run);
    assert_eq!(f.table.rows.len(), 1);
    match (f.loader)(0, &f.scene.problem).expect("the solution reads back") {
        StoredResult::Solution(s) => {
            assert_eq!(Some(s.iterations as u64), report["iterations"].as_u64());
        }
        StoredResult::State(_) => panic!("a run's folder holds its whole solution"),
    }
}

/// A run's stored step fields written under mpirun (every rank's fields gathered on rank 0)
/// are the file one machine writes, byte for byte, and open in the explorer without the scene.
#[test]
fn stored_fields_on_two_ranks_are_those_of_one_machine() {
    let one = scratch("fields-one");
    let two = scratch("fields-two");
    let args = ["run", "two-blocks", "--split", "2", "--fields", "--out"];
    run(Command::new(LOPIN).args(args).arg(&one));
    run(mpirun(2, &args).arg(&two));
    let file = |d: &Path| bytes(&d.join("fields.bin"));
    assert!(
        file(&one) == file(&two),
        "fields.bin differs between one machine and two ranks"
    );
    assert!(matches!(
        lopin_app::result_folder::open(&two),
        Ok(Loaded::Stored(_))
    ));
    std::fs::remove_dir_all(&one).ok();
    std::fs::remove_dir_all(&two).ok();
}

/// A non-matching contact whose two sides (A and B, one substructure each) sit on two ranks.
#[test]
fn a_non_matching_contact_across_two_ranks_equals_the_run_on_one_machine() {
    let dir = scratch("nonmatching-one");
    let one = dir.display().to_string();
    let args = ["run", "two-blocks-nonmatching", "--json", "--out"];
    let serial = json(&run(Command::new(LOPIN).args(args).arg(&one)));
    let d = scratch("nonmatching-np2");
    let out = d.display().to_string();
    let dist = json(&run(mpirun(2, &args).arg(&out)));
    assert_eq!(dist["iterations"], serial["iterations"]);
    assert_eq!(dist["eta"], serial["eta"]);
    assert!(
        bytes(&d.join("solution.bin")) == bytes(&dir.join("solution.bin")),
        "the solution file differs"
    );
    println!(
        "two-blocks-nonmatching: 2 ranks, {} iterations, eta {}, solution file identical",
        dist["iterations"], dist["eta"]
    );
}

#[test]
fn a_sweep_equals_the_sweep_on_one_machine() {
    let values = "f=0.1,0.3,0.5";
    let one = scratch("sweep-one");
    let o = one.display().to_string();
    let args = [
        "sweep",
        "two-blocks",
        "--split",
        "2",
        "--param",
        values,
        "--json",
    ];
    run(Command::new(LOPIN).args(args).args(["--out", &o]));
    for ranks in [2, 3] {
        let d = scratch(&format!("sweep-np{ranks}"));
        let out = d.display().to_string();
        let mut a = args.to_vec();
        a.extend(["--out", &out]);
        run(&mut mpirun(ranks, &a));
        for v in 0..3 {
            let f = format!("value-{v:03}.state");
            assert_eq!(
                bytes(&d.join(&f)),
                bytes(&one.join(&f)),
                "{f} on {ranks} ranks"
            );
        }
    }
}

/// study.csv's rows by configuration, without the wall time (the only column a machine changes).
fn study_rows(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    let header: Vec<&str> = text.lines().next().expect("header").split(',').collect();
    let wall = header.iter().position(|&h| h == "wall_s").expect("wall_s");
    // each row's checksum covers its wall time
    let sum = header
        .iter()
        .position(|&h| h == "checksum")
        .expect("checksum");
    let mut rows: Vec<(usize, String)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let fields: Vec<&str> = l.split(',').collect();
            let kept: Vec<&str> = fields
                .iter()
                .enumerate()
                .filter(|&(k, _)| k != wall && k != sum)
                .map(|(_, f)| *f)
                .collect();
            (fields[0].parse().expect("index"), kept.join(","))
        })
        .collect();
    rows.sort();
    rows.into_iter().map(|(_, r)| r).collect()
}

#[test]
fn a_study_on_ranks_equals_its_chains_on_threads() {
    let args = [
        "study",
        "two-blocks",
        "--param",
        "f=0,0.1,0.2,0.3,0.4,0.5",
        "--param",
        "gap=0,1e-6",
        "--rho-inf",
        "0.5",
        "--json",
    ];
    for ranks in [2, 3] {
        let chains = ranks.to_string();
        let one = scratch(&format!("study-threads{ranks}"));
        let o = one.display().to_string();
        let threads = json(&run(Command::new(LOPIN)
            .args(args)
            .args(["--chains", &chains, "--out", &o])));
        let d = scratch(&format!("study-np{ranks}"));
        let out = d.display().to_string();
        let mut a = args.to_vec();
        a.extend(["--out", &out]);
        let dist = json(&run(&mut mpirun(ranks, &a)));
        let rows = study_rows(&d);
        assert_eq!(rows.len(), 12, "{ranks} ranks");
        assert_eq!(rows, study_rows(&one), "{ranks} ranks");
        // every chain ran on its rank: chain c on rank c mod P, each cold at its start
        let chain_of: std::collections::BTreeSet<&str> = rows
            .iter()
            .map(|r| r.split(',').nth(1).expect("chain"))
            .collect();
        assert_eq!(chain_of.len(), ranks, "{rows:?}");
        assert_eq!(dist["plan"]["chains"], ranks);
        for key in ["iterations", "configurations", "converged", "state_bytes"] {
            assert_eq!(dist["totals"][key], threads["totals"][key], "{key}");
        }
        // the other ranks' rows were taken into study.csv and their folders removed
        for r in 1..ranks {
            assert!(!d.join(format!("rank-{r}")).exists());
        }
        // the folder opens in the explorer with every configuration's state, whichever rank
        // wrote it
        let Loaded::Folder(f) = lopin_app::result_folder::open(&d).expect("the explorer opens it")
        else {
            panic!("a study folder opens with its scene");
        };
        assert_eq!(f.kind, FolderKind::Study);
        assert_eq!(f.table.rows.len(), 12);
        for r in 0..12 {
            let s = (f.loader)(r, &f.scene.problem);
            assert!(
                matches!(s, Ok(StoredResult::State(_))),
                "row {r}: {:?}",
                s.err()
            );
        }
    }
    // fewer chains than ranks: refused once, naming the option
    let out = mpirun(
        2,
        &["study", "two-blocks", "--param", "f=0,0.5", "--chains", "1"],
    )
    .output()
    .expect("starts");
    let (err, _) = one_error(&out);
    assert!(err.contains("--chains") && err.contains("idle"), "{err}");
}

#[test]
fn a_restart_from_a_checkpoint_equals_the_uninterrupted_run() {
    let full = scratch("full");
    let cp = scratch("checkpoint");
    let re = scratch("restarted");
    let (f, c, r) = (
        full.display().to_string(),
        cp.display().to_string(),
        re.display().to_string(),
    );
    let base = ["run", "two-blocks", "--split", "2", "--json"];
    let whole = json(&run(&mut mpirun(2, &[&base[..], &["--out", &f]].concat())));
    // stopped at iteration 150, the last checkpoint at 100
    let halted = mpirun(
        2,
        &[
            &base[..],
            &[
                "--checkpoint",
                &c,
                "--checkpoint-every",
                "50",
                "--halt-after",
                "150",
            ],
        ]
        .concat(),
    )
    .output()
    .expect("starts");
    assert!(!halted.status.success());
    assert!(String::from_utf8_lossy(&halted.stderr).contains("checkpoint: iteration 150"));
    let again = json(&run(&mut mpirun(
        2,
        &[&base[..], &["--restart", &c, "--out", &r]].concat(),
    )));
    assert_eq!(again["iterations"], whole["iterations"]);
    assert_eq!(again["eta"], whole["eta"]);
    assert_eq!(
        bytes(&re.join("solution.bin")),
        bytes(&full.join("solution.bin"))
    );
    // another number of ranks is refused, naming the one to use
    let wrong = mpirun(3, &[&base[..], &["--restart", &c]].concat())
        .output()
        .expect("starts");
    let err = String::from_utf8_lossy(&wrong.stderr);
    assert!(err.contains("restart with mpirun -np 2"), "{err}");
}

#[test]
fn bad_input_ends_every_rank_with_one_message() {
    let t = Instant::now();
    let out = mpirun(3, &["run", "two-blocks", "--split", "2", "--tol", "-1"])
        .output()
        .expect("starts");
    let (err, line) = one_error(&out);
    assert!(line.contains("tol"), "{err}");
    assert!(t.elapsed() < Duration::from_secs(60));
}

#[test]
fn a_rank_that_dies_ends_the_job_within_seconds() {
    let cp = scratch("dies");
    let c = cp.display().to_string();
    let job = mpirun(
        2,
        &[
            "run",
            "granular-small",
            "--checkpoint",
            &c,
            "--checkpoint-every",
            "5",
            "--max-iter",
            "100000",
            "--tol",
            "1e-14",
        ],
    )
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .expect("starts");
    // wait for the first checkpoint, then kill rank 1
    let t = Instant::now();
    while !cp.join("checkpoint.json").exists() {
        assert!(t.elapsed() < Duration::from_secs(120), "no checkpoint");
        std::thread::sleep(Duration::from_millis(200));
    }
    let pids = Command::new("pgrep")
        .args([
            "-f",
            &format!("^{LOPIN} run granular-small --checkpoint {c}"),
        ])
        .output()
        .expect("pgrep");
    let pids: Vec<String> = String::from_utf8_lossy(&pids.stdout)
        .split_whitespace()
        .map(String::from)
        .collect();
    assert!(pids.len() >= 2, "{pids:?}");
    let killed = Instant::now();
    Command::new("kill")
        .args(["-9", &pids[1]])
        .status()
        .expect("kill");
    let out = job.wait_with_output().expect("ends");
    let ended = killed.elapsed();
    assert!(!out.status.success());
    assert!(ended < Duration::from_secs(30), "{ended:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("rank"), "{err}");
    assert!(err.contains(&format!("--restart {c}")), "{err}");
    println!("the job ended {ended:?} after a rank was killed:\n{err}");
}
