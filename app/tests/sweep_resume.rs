//! A sweep killed after a few values and resumed gives the same records as an uninterrupted
//! sweep (iterations and η identical, quantities equal to 1e-12 relative), and the JSON has the
//! documented shape.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lopin-sweep-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

const ARGS: [&str; 4] = ["sweep", "two-blocks", "--param", "f=0:0.3:0.05"];

fn records(dir: &Path) -> Vec<serde_json::Value> {
    (0..7)
        .map(|i| {
            let text =
                std::fs::read_to_string(dir.join(format!("value-{i:03}.json"))).expect("record");
            serde_json::from_str(&text).expect("json")
        })
        .collect()
}

#[test]
fn killed_and_resumed_sweep_equals_uninterrupted_sweep() {
    let full = scratch("full");
    let out = lopin()
        .args(ARGS)
        .args(["--compare-cold", "--json", "--out"])
        .arg(&full)
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json on stdout");
    assert_eq!(json["values"].as_array().map(Vec::len), Some(7));
    let total = json["total_iterations"].as_u64().expect("total");
    let cold = json["cold_total_iterations"].as_u64().expect("cold total");
    assert!(json["gain"]
        .as_f64()
        .is_some_and(|g| (g - cold as f64 / total as f64).abs() < 1e-12));
    assert!(json["gain_wall"].as_f64().is_some_and(|g| g > 0.0));
    assert!(full.join("convergence.png").exists() && full.join("quantities.png").exists());

    // interrupted run: kill the process once two values are finished
    let part = scratch("part");
    let mut child = lopin()
        .args(ARGS)
        .args(["--compare-cold", "--out"])
        .arg(&part)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawns");
    let start = Instant::now();
    while !part.join("value-001.json").exists() {
        assert!(start.elapsed() < Duration::from_secs(120), "no progress");
        if child.try_wait().expect("wait").is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().ok();
    child.wait().expect("reaped");
    let finished = (0..7)
        .filter(|i| part.join(format!("value-{i:03}.json")).exists())
        .count();
    println!("killed after {finished} finished values");

    // without --resume the directory is refused, nothing is overwritten
    let refused = lopin()
        .args(ARGS)
        .args(["--compare-cold", "--out"])
        .arg(&part)
        .output()
        .expect("runs");
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--resume"));

    let resumed = lopin()
        .args(ARGS)
        .args(["--compare-cold", "--resume", "--out"])
        .arg(&part)
        .output()
        .expect("runs");
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    for (a, b) in records(&full).iter().zip(records(&part)) {
        assert_eq!(a["iterations"], b["iterations"], "value {}", a["value"]);
        assert_eq!(a["cold"]["iterations"], b["cold"]["iterations"]);
        for key in ["eta", "peak_normal_force", "max_slip", "energy_end"] {
            let (x, y) = (a[key].as_f64().expect("num"), b[key].as_f64().expect("num"));
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(1e-300),
                "{key}: {x} vs {y}"
            );
        }
    }
    // a different sweep cannot be resumed into the same directory
    let other = lopin()
        .args([
            "sweep",
            "two-blocks",
            "--param",
            "f=0:0.2:0.1",
            "--compare-cold",
            "--resume",
            "--out",
        ])
        .arg(&part)
        .output()
        .expect("runs");
    assert!(!other.status.success());
    assert!(String::from_utf8_lossy(&other.stderr).contains("different sweep"));
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&part);
}
