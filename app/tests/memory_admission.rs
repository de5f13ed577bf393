//! Memory admission against the memory a run really holds: for each family of scene (box
//! bodies, a `[granular]` table, a Gmsh mesh body, a study's chains), a limit just above what
//! `lopin estimate` counts admits the run, whose peak resident memory (the kernel's high-water
//! mark, `VmHWM`, read while it runs) stays under that limit; a limit below the count refuses it
//! before anything is built, with what would fit.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

/// Share of the limit a solve may plan to use (as the admission does).
const USABLE: f64 = 0.9;

fn lopin() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_lopin"));
    cmd.env_remove("LOPIN_MEMORY_LIMIT");
    cmd
}

/// What `lopin estimate ARGS --json` counts, in bytes: every solve held at once plus the
/// process.
fn counted(args: &[&str]) -> u64 {
    let out = lopin()
        .arg("estimate")
        .args(args)
        .arg("--json")
        .output()
        .expect("estimate runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let fp = &json["footprint"];
    let field = |k: &str| fp[k].as_u64().unwrap_or_else(|| panic!("{k} in {fp}"));
    let solve = [
        "interface_bytes",
        "cache_bytes",
        "operator_bytes",
        "factor_bytes",
        "macro_bytes",
    ]
    .iter()
    .map(|k| field(k))
    .sum::<u64>();
    solve * field("copies") + field("process_bytes")
}

/// Runs `lopin ARGS` under `LOPIN_MEMORY_LIMIT = limit` bytes: whether it succeeded, its
/// stderr and its peak resident memory in bytes.
fn run_under(args: &[&str], limit: u64) -> (bool, String, u64) {
    let mut child = lopin()
        .args(args)
        .env("LOPIN_MEMORY_LIMIT", limit.to_string())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("lopin starts");
    let status_file = PathBuf::from(format!("/proc/{}/status", child.id()));
    let mut peak = 0u64;
    let status = loop {
        if let Ok(text) = std::fs::read_to_string(&status_file) {
            if let Some(kib) = text
                .lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
            {
                peak = peak.max(kib * 1024);
            }
        }
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        std::io::Read::read_to_string(&mut e, &mut stderr).expect("stderr");
    }
    (status.success(), stderr, peak)
}

/// A limit just large enough for `bytes` to be admitted, and one that refuses it.
fn limits(bytes: u64) -> (u64, u64) {
    let admitted = (bytes as f64 / USABLE).ceil() as u64 + (1 << 20);
    let refused = (bytes as f64 * 0.8) as u64;
    (admitted, refused)
}

fn check_family(name: &str, estimate: &[&str], run: &[&str]) {
    let bytes = counted(estimate);
    let (admitted, refused) = limits(bytes);
    let (ok, stderr, peak) = run_under(run, admitted);
    println!(
        "{name}: counted {:.1} MiB, limit {:.1} MiB, peak resident {:.1} MiB ({:.2} of the limit)",
        bytes as f64 / 1048576.0,
        admitted as f64 / 1048576.0,
        peak as f64 / 1048576.0,
        peak as f64 / admitted as f64
    );
    assert!(ok, "{name}: admitted run failed: {stderr}");
    assert!(peak > 0, "{name}: no memory reading");
    assert!(
        peak <= admitted,
        "{name}: peak {peak} B over the limit {admitted} B that admitted it"
    );
    let (ok, stderr, _) = run_under(run, refused);
    assert!(
        !ok,
        "{name}: ran under {refused} B, below its count {bytes} B"
    );
    assert!(
        stderr.contains("more than this machine can give it") && stderr.contains("What would fit"),
        "{name}: {stderr}"
    );
}

#[test]
fn peak_memory_of_admitted_runs_stays_under_the_limit_box_bodies() {
    check_family(
        "two-blocks",
        &["two-blocks"],
        &["run", "two-blocks", "--json"],
    );
    check_family(
        "two-blocks --refine 2",
        &["two-blocks", "--refine", "2"],
        &["run", "two-blocks", "--refine", "2", "--json"],
    );
}

#[test]
fn peak_memory_of_admitted_runs_stays_under_the_limit_granular_table() {
    check_family(
        "granular-small",
        &["granular-small"],
        &["run", "granular-small", "--json"],
    );
}

#[test]
fn peak_memory_of_admitted_runs_stays_under_the_limit_mesh_body() {
    let dir = std::env::temp_dir().join(format!("lopin-memory-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let mesh = format!(
        "{}/../assets/meshes/unit-cube.msh",
        env!("CARGO_MANIFEST_DIR")
    );
    let scene = dir.join("cube.toml");
    std::fs::write(
        &scene,
        format!(
            r#"
name = "cube"
[time]
dt = 1e-6
steps = 40
[[material]]
name = "steel"
young = 210e9
poisson = 0.3
density = 7800.0
[[mesh_body]]
name = "cube"
material = "steel"
mesh = "{mesh}"
velocity = [0.0, 0.0, -1.0]
[[boundary]]
body = "cube"
surface = "bottom"
clamped = true
"#
        ),
    )
    .expect("scene");
    let scene = scene.display().to_string();
    check_family(
        "mesh body",
        &[&scene, "--window", "1"],
        &["run", &scene, "--window", "1", "--json"],
    );
}

#[test]
fn study_chains_are_admitted_together() {
    // what one solve and the process hold: a limit that fits one chain but not four
    let one = counted(&["two-blocks"]);
    let process = 32u64 << 20;
    let solve = one - process;
    let limit = ((process + solve + solve / 2) as f64 / USABLE) as u64;
    let out = std::env::temp_dir().join(format!("lopin-memory-chains-{}", std::process::id()));
    let study = |chains: &str, dir: &str| {
        let d = out.join(dir).display().to_string();
        run_under(
            &[
                "study",
                "two-blocks",
                "--param",
                "f=0:0.3:0.1",
                "--chains",
                chains,
                "--out",
                &d,
                "--json",
            ],
            limit,
        )
    };
    let (ok, stderr, _) = study("4", "four");
    assert!(!ok, "four chains ran under {limit} B");
    assert!(
        stderr.contains("4 solves at once") && stderr.contains("at most 1 (now 4; `--chains`)"),
        "{stderr}"
    );
    let (ok, stderr, peak) = study("1", "one");
    assert!(ok, "{stderr}");
    println!(
        "study, one chain: limit {:.1} MiB, peak resident {:.1} MiB",
        limit as f64 / 1048576.0,
        peak as f64 / 1048576.0
    );
    assert!(peak <= limit, "peak {peak} B over the limit {limit} B");
}
