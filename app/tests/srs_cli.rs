//! `lopin srs` on a saved run of `bar` (pushed at x = 0 by a (1 − cos) velocity ramp of 10 m/s
//! over 2 µs): the acceleration history at the driven end is the ramp's step-averaged
//! acceleration (V(t_m) − V(t_{m−1}))/Δt to 1e-6 of its peak; the spectrum written is the
//! spectrum of the history written (the filter itself is checked against closed forms in
//! `lopin_core::shock_spectrum`), over the default band 1/T to 1/(10Δt); the transverse
//! components stay at rest (ν = 0); the figure is a PNG; bad probes and bands are refused with
//! the flag and the reason. On a measured history (the top of `base-shock`'s stack), SciPy's
//! `lsim` of each oscillator's transfer function gives the same spectrum (to 1e-6).

mod readers;

use std::path::Path;

use lopin_core::shock_spectrum;
use readers::{lopin, python, scratch};

/// The rows of a CSV file of numbers (its header skipped).
fn rows(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .expect("csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().expect("number")).collect())
        .collect()
}

#[test]
fn the_driven_end_of_bar_has_the_ramps_acceleration_and_its_spectrum() {
    let dir = scratch("srs");
    let (run, out) = (dir.join("run"), dir.join("srs"));
    let o = lopin()
        .args(["run", "bar", "--tol", "1e-9", "--window", "1", "--out"])
        .arg(&run)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = lopin()
        .args(["srs"])
        .arg(&run)
        .args(["--at", "0,0.005,0.005", "--at", "0.05,0.005,0.005", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    println!("{stdout}");
    assert!(
        stdout.contains("probe 2 at [0.05, 0.005, 0.005]"),
        "{stdout}"
    );

    // bar: Δt = 1e-7 s, 150 steps, V(t) = 5 (1 − cos(πt/2 µs)) then 10 m/s
    let (dt, ramp) = (1e-7, 2e-6);
    let v = |t: f64| {
        if t >= ramp {
            10.0
        } else {
            5.0 * (1.0 - (std::f64::consts::PI * t / ramp).cos())
        }
    };
    let history = rows(&out.join("probe-1.csv"));
    assert_eq!(history.len(), 150);
    let peak = 10.0 * std::f64::consts::PI / (2.0 * ramp);
    let mut worst: f64 = 0.0;
    for (m, r) in history.iter().enumerate() {
        let t0 = m as f64 * dt;
        assert!(
            (r[0] - (t0 + 0.5 * dt)).abs() < 1e-15,
            "mid-step time {r:?}"
        );
        let expected = (v(t0 + dt) - v(t0)) / dt;
        worst = worst.max((r[1] - expected).abs());
    }
    println!("driven end: largest error {worst:.3e} m/s² of a peak {peak:.4e}");
    assert!(worst < 1e-6 * peak, "{worst:e}");

    let spectrum = rows(&out.join("srs-1.csv"));
    let freqs: Vec<f64> = spectrum.iter().map(|r| r[0]).collect();
    assert!(
        (freqs[0] - 1.0 / 15e-6).abs() < 1e-6 * freqs[0],
        "band starts at 1/T"
    );
    assert!(
        (freqs[freqs.len() - 1] - 1e6).abs() < 1e-3,
        "band ends at 1/(10Δt)"
    );
    let ax: Vec<f64> = history.iter().map(|r| r[1]).collect();
    let again = shock_spectrum::spectrum(&ax, dt, &freqs, 0.05);
    for (r, s) in spectrum.iter().zip(&again) {
        assert!(
            (r[1] - s).abs() <= 1e-12 * s,
            "{} Hz: {} against {s}",
            r[0],
            r[1]
        );
    }
    // the bar has ν = 0: the transverse components stay at rest
    for r in rows(&out.join("srs-2.csv")) {
        assert!(r[2].abs() < 1e-3 && r[3].abs() < 1e-3, "{r:?}");
    }
    let png = std::fs::read(out.join("srs.png")).expect("figure");
    assert_eq!(&png[1..4], b"PNG");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_probes_and_bands_are_refused_naming_the_flag() {
    let dir = scratch("srs-bad");
    let run = dir.join("run");
    let o = lopin()
        .args(["run", "bar", "--out"])
        .arg(&run)
        .output()
        .expect("runs");
    assert!(o.status.success());
    let cases: [(&[&str], &str); 5] = [
        (&["--at", "1,2"], "--at 1,2: expected three"),
        (&["--at", "5,5,5"], "outside the model"),
        (&["--at", "0,0,0", "--band", "5:1"], "--band 5:1"),
        (&["--at", "0,0,0", "--band", "1:1e9"], "Nyquist"),
        (&["--at", "0,0,0", "--q", "0.1"], "--q"),
    ];
    for (args, expected) in cases {
        let o = lopin()
            .arg("srs")
            .arg(&run)
            .args(args)
            .arg("--out")
            .arg(dir.join("out"))
            .output()
            .expect("runs");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(err.contains(expected), "{args:?}: {err}");
    }
    let o = lopin()
        .arg("srs")
        .arg(&dir)
        .args(["--at", "0,0,0", "--out"])
        .arg(dir.join("out"))
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("run.json") && err.contains("lopin run --out"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The spectrum of a measured history, the top of `base-shock` (a base shaken by a half-sine
/// acceleration, damped materials, frictional contact), against an independent one: SciPy's
/// `lsim` of H(s) = (2ζωs + ω²)/(s² + 2ζωs + ω²) per frequency (`readers/srs_scipy.py`), at
/// every one of its 37 frequencies to 1e-6.
#[test]
fn a_measured_historys_spectrum_matches_scipy() {
    let dir = scratch("srs-scipy");
    let (run, out) = (dir.join("run"), dir.join("srs"));
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../assets/scenes/shock/base-shock.toml"
    );
    let o = lopin()
        .args(["run", scene, "--out"])
        .arg(&run)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = lopin()
        .arg("srs")
        .arg(&run)
        .args(["--at", "0.02,0.02,0.04", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/readers/srs_scipy.py");
    let o = std::process::Command::new(python())
        .arg(script)
        .arg(out.join("probe-1.csv"))
        .arg(out.join("srs-1.csv"))
        .args(["3", "10"])
        .output()
        .unwrap_or_else(|e| {
            panic!("python: {e}; install the readers with ./scripts/install-readers.sh")
        });
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
    let scipy: Vec<f64> = json["srs"]
        .as_array()
        .expect("srs")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    let ours = rows(&out.join("srs-1.csv"));
    assert_eq!(ours.len(), scipy.len());
    assert!(ours.len() >= 10);
    let worst = ours
        .iter()
        .zip(&scipy)
        .map(|(r, s)| (r[3] / s - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "base-shock top: SRS against SciPy lsim at {} frequencies: {worst:.2e}",
        ours.len()
    );
    assert!(worst < 1e-6, "{worst:e}");
    let _ = std::fs::remove_dir_all(&dir);
}
