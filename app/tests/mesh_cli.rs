//! `lopin mesh info`: a committed Gmsh MSH 4.1 file (`assets/meshes/unit-cube.msh`, the unit
//! cube as 6 tetrahedra with a physical volume `cube` and a physical surface `bottom`) is read
//! and reported with exact measures; a missing or damaged file is one clear error line and exit
//! status 2.

use std::process::Command;

fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

/// The JSON a successful command prints.
fn json_of(cmd: &mut Command) -> serde_json::Value {
    let out = cmd.output().expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("json")
}

fn asset() -> String {
    format!(
        "{}/../assets/meshes/unit-cube.msh",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn mesh_info_reports_groups_and_measures() {
    let v = json_of(lopin().args(["mesh", "info", &asset(), "--json"]));
    assert_eq!(v["nodes"], 8);
    assert_eq!(v["tetrahedra"], 6);
    assert_eq!(v["hexahedra"], 0);
    let groups = v["physicals"].as_array().expect("groups");
    for (name, dim, elements) in [("bottom", 2, 2), ("cube", 3, 6)] {
        let g = groups
            .iter()
            .find(|g| g["name"] == name)
            .expect("group present");
        assert_eq!(g["dim"], dim);
        assert_eq!(g["elements"], elements);
        let m = g["measure"].as_f64().expect("measure");
        assert!((m - 1.0).abs() < 1e-14, "{name}: {m}");
    }
    let table = lopin()
        .args(["mesh", "info", &asset()])
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(
        text.contains("6 tetrahedra") && text.contains("cube"),
        "{text}"
    );
}

#[test]
fn a_missing_or_damaged_mesh_is_one_clear_error() {
    let dir = std::env::temp_dir().join(format!("lopin-mesh-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let missing = dir.join("nothere.msh");
    let damaged = dir.join("damaged.msh");
    let good = std::fs::read_to_string(asset()).expect("asset");
    std::fs::write(&damaged, good.replacen("4.1 0 8", "2.2 0 8", 1)).expect("write");
    for (file, says) in [(&missing, "cannot read"), (&damaged, "MSH version 2.2")] {
        let out = lopin()
            .args(["mesh", "info"])
            .arg(file)
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&file.display().to_string()) && err.contains(says),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `lopin mesh granular`: the `granular-poly` sample (10 grains) is placed and meshed by gmsh
/// (needs gmsh: the README's test command installs it), written where asked, and `lopin mesh
/// info` reads it back with one physical volume per grain plus the matrix, whose volumes add up
/// to the cube's; gmsh missing is one clear error saying how to install it.
#[test]
fn mesh_granular_writes_a_sample_that_mesh_info_reads_back() {
    let dir = std::env::temp_dir().join(format!("lopin-mesh-granular-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let msh = dir.join("sample.msh");
    let geo = dir.join("sample.geo");
    let v = json_of(
        lopin()
            .args(["mesh", "granular", "granular-poly", "--json", "-o"])
            .arg(&msh)
            .arg("--geo")
            .arg(&geo),
    );
    assert_eq!(v["grains"], 10);
    let nodes = v["nodes"].as_u64().expect("nodes");
    assert!((3_000..10_000).contains(&nodes), "{nodes} nodes");
    let script = std::fs::read_to_string(&geo).expect("script written");
    assert!(script.contains("BooleanFragments") && script.contains("Physical Volume(\"grain10\""));
    let info = json_of(lopin().args(["mesh", "info", "--json"]).arg(&msh));
    assert_eq!(info["nodes"].as_u64(), Some(nodes));
    let groups = info["physicals"].as_array().expect("groups");
    let volumes: Vec<f64> = groups
        .iter()
        .filter(|g| g["dim"] == 3)
        .map(|g| g["measure"].as_f64().expect("volume"))
        .collect();
    assert_eq!(volumes.len(), 11, "matrix and 10 grains");
    let total: f64 = volumes.iter().sum();
    assert!(
        (total / 1e-3 - 1.0).abs() < 1e-9,
        "volumes add up to {total}"
    );
    for name in ["top", "bottom"] {
        assert!(groups.iter().any(|g| g["name"] == name && g["dim"] == 2));
    }
    // gmsh missing: one line saying how to install it (a sample that is not cached yet)
    let out = lopin()
        .args(["mesh", "granular", "granular-poly", "--seed", "77"])
        .env("LOPIN_GMSH", "/nonexistent/gmsh")
        .env("LOPIN_CACHE", &dir)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("apt-get install gmsh") && err.contains("pip install gmsh"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
