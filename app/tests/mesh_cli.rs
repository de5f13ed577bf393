//! `lopin mesh info`: a committed Gmsh MSH 4.1 file (`assets/meshes/unit-cube.msh`, the unit
//! cube as 6 tetrahedra with a physical volume `cube` and a physical surface `bottom`) is read
//! and reported with exact measures; a missing or damaged file is one clear error line and exit
//! status 2.

use std::process::Command;

fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

fn asset() -> String {
    format!(
        "{}/../assets/meshes/unit-cube.msh",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn mesh_info_reports_groups_and_measures() {
    let out = lopin()
        .args(["mesh", "info", &asset(), "--json"])
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
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
