//! `lopin run --out --vtu --rerun` and `lopin export` on two-blocks, read back by real readers:
//! meshio reads every .vtu of the .pvd collection (counts, field names, values at a probe node
//! and cell equal to what lopin-core computes for the same run), the `rerun` tool verifies and
//! prints the recording (entity paths, timelines, one row per time step), run.json says how to
//! reproduce the run, `lopin export` rewrites identical VTU files from the saved run, and bad
//! inputs get clear errors.

mod readers;

use lopin_app::record::entity_name;
use lopin_core::elements::hex8;
use lopin_core::window_choice::{choose, Task};
use lopin_core::{post, scene, Settings, Solver};
use readers::{free_port, lopin, read_rrd, read_vtu, scratch};

/// two-blocks solved here, as the binary solves it.
fn reference() -> (Solver, Vec<Vec<post::SubFields>>) {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    // the windows `lopin run` chooses for one cold solve
    settings.window = choose(Task::Single, None, spec.solver.window, spec.has_contact()).window;
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    let sol = solver.solve(None).expect("solves");
    let history = post::history(&solver, &sol);
    (solver, history)
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-9 * scale.max(1e-300)
}

#[test]
fn run_writes_vtu_pvd_rerun_and_run_json_that_real_readers_accept() {
    let dir = scratch("exports");
    let (out, vtu, rrd) = (dir.join("run"), dir.join("vtu"), dir.join("two-blocks.rrd"));
    let o = lopin()
        .args(["run", "two-blocks", "--json", "--out"])
        .arg(&out)
        .arg("--vtu")
        .arg(&vtu)
        .arg("--rerun")
        .arg(&rrd)
        .output()
        .expect("lopin runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON report");
    let (solver, history) = reference();
    let p = solver.problem();
    let n = p.time.steps;
    let subs = p.subs.len();

    // --- VTU / PVD, read by meshio
    let vtu_out = &report["outputs"]["vtu"];
    assert_eq!(vtu_out["files"].as_u64(), Some(((n + 1) * subs) as u64));
    // probe: the node of largest speed at mid-run in substructure 0, and element 0
    let m = n / 2;
    let v = &history[0][m].v;
    let node = (0..v.len() / 3)
        .max_by(|&a, &b| {
            let s = |k: usize| v[3 * k].hypot(v[3 * k + 1]).hypot(v[3 * k + 2]);
            s(a).total_cmp(&s(b))
        })
        .expect("nodes");
    let cell = 0;
    let read = read_vtu(&vtu.join("run.pvd"), node, cell);
    let entries = read["entries"].as_array().expect("entries");
    assert_eq!(
        entries.len(),
        (n + 1) * subs,
        "one dataset per substructure and step"
    );
    for (k, e) in entries.iter().enumerate() {
        let (step, part) = (k / subs, k % subs);
        assert_eq!(e["part"].as_u64(), Some(part as u64));
        let t = e["time"].as_f64().expect("time");
        assert!(close(t, p.time.time(step), p.time.dt), "{t} at step {step}");
    }
    let speed_scale = history
        .iter()
        .flatten()
        .flat_map(|f| f.v.iter())
        .fold(0.0_f64, |a, &b| a.max(b.abs()));
    for (step, e) in entries.iter().enumerate().filter(|(k, _)| k % subs == 0) {
        let step = step / subs;
        let f = &read["files"][e["file"].as_str().expect("file")];
        let mesh = &p.subs[0].mesh;
        assert_eq!(f["points"].as_u64(), Some(mesh.nodes.len() as u64));
        assert_eq!(
            f["cell_blocks"],
            serde_json::json!([["hexahedron", mesh.elements.len()]])
        );
        assert_eq!(
            f["point_data"],
            serde_json::json!(["displacement", "velocity", "velocity_avg"])
        );
        assert_eq!(
            f["cell_data"],
            serde_json::json!(["material", "stress", "substructure", "von_mises"])
        );
        let h = &history[0][step];
        for c in 0..3 {
            assert!(close(
                f["x"][c].as_f64().expect("x"),
                mesh.nodes[node][c],
                1.0
            ));
            let u = f["displacement"][c].as_f64().expect("u");
            assert!(
                close(u, h.u[3 * node + c], 1e-3),
                "step {step}: u {u} vs {}",
                h.u[3 * node + c]
            );
            let vel = f["velocity"][c].as_f64().expect("v");
            assert!(
                close(vel, h.v[3 * node + c], speed_scale),
                "step {step}: v {vel}"
            );
            // the step average (v_m + v_{m−1})/2, v_0 itself at m = 0
            let before = &history[0][step.saturating_sub(1)];
            let avg = f["velocity_avg"][c].as_f64().expect("v avg");
            let expected = 0.5 * (h.v[3 * node + c] + before.v[3 * node + c]);
            assert!(
                close(avg, expected, speed_scale),
                "step {step}: v avg {avg} vs {expected}"
            );
        }
        let stress = post::element_stress(&solver, 0, &h.u)[cell];
        let vm = hex8::von_mises(&stress);
        let scale = vm.abs().max(1.0);
        assert!(close(f["von_mises"][0].as_f64().expect("vm"), vm, scale));
        let [xx, yy, zz, xy, yz, zx] = stress;
        let full = [xx, xy, zx, xy, yy, yz, zx, yz, zz];
        for (k, s) in full.iter().enumerate() {
            assert!(close(f["stress"][k].as_f64().expect("stress"), *s, scale));
        }
        assert_eq!(f["substructure"][0].as_f64(), Some(0.0));
        assert_eq!(
            f["material"][0].as_f64(),
            Some(p.subs[0].material_id as f64)
        );
    }
    // the probe moves: its speed at mid-run is a real number, not zero
    let mid = &read["files"][entries[m * subs]["file"].as_str().expect("file")];
    assert!(mid["max_velocity"].as_f64().expect("max v") > 0.1);

    // --- run.json
    let run_json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("run.json")).expect("run.json"))
            .expect("JSON");
    assert_eq!(run_json["kind"], "run");
    assert_eq!(run_json["lopin"]["version"], env!("CARGO_PKG_VERSION"));
    assert!(!run_json["lopin"]["commit"]
        .as_str()
        .expect("commit")
        .is_empty());
    assert_eq!(run_json["scene"]["name"], "two-blocks");
    assert_eq!(run_json["problem"]["steps"].as_u64(), Some(n as u64));
    assert_eq!(
        run_json["settings"]["tol"].as_f64(),
        Some(solver.settings().tol)
    );
    assert_eq!(run_json["result"]["iterations"], report["iterations"]);
    assert!(run_json["timings_s"]["wall"].as_f64().expect("wall") > 0.0);
    assert!(
        vtu.join("run.json").exists(),
        "the VTU folder says how it was made too"
    );

    // --- Rerun, read by the rerun tool
    check_recording(
        &read_rrd(&rrd),
        p,
        n + 1,
        report["iterations"].as_u64().expect("its"),
    );

    // --- lopin export from the saved run: the same files, bit for bit
    let again = dir.join("vtu-again");
    let o = lopin()
        .arg("export")
        .arg(&out)
        .arg("--vtu")
        .arg(&again)
        .output()
        .expect("lopin export runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for e in entries.iter().step_by(17) {
        let name = e["file"].as_str().expect("file");
        let a = std::fs::read(vtu.join(name)).expect("first");
        let b = std::fs::read(again.join(name)).expect("again");
        assert!(a == b, "{name} differs after export");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Entity paths, timelines and the number of logged steps of a two-blocks recording.
fn check_recording(printed: &str, p: &lopin_core::Problem, steps: usize, iterations: u64) {
    let e = readers::entities(printed);
    let get = |path: &str| {
        e.get(path)
            .unwrap_or_else(|| panic!("no entity {path} in {:?}", e.keys().collect::<Vec<_>>()))
    };
    assert_eq!(get("/scene").static_rows(), 1, "the run is described once");
    assert_eq!(get("/colormap").rows_on("time"), 1);
    for s in &p.subs {
        let name = entity_name(&s.name);
        let surface = get(&format!("/bodies/{name}/surface"));
        assert_eq!(surface.static_rows(), 1, "triangles once, static");
        assert_eq!(
            surface.rows_on("time"),
            steps,
            "positions and colours per step"
        );
        assert_eq!(
            get(&format!("/bodies/{name}/velocity")).rows_on("time"),
            steps
        );
    }
    let contacts: Vec<_> = p.interfaces.iter().filter(|i| i.is_contact()).collect();
    assert!(!contacts.is_empty());
    for c in contacts {
        for q in ["pressure", "normal_force", "max_slip"] {
            let path = format!("/contact/{}/{q}", entity_name(&c.name));
            assert_eq!(get(&path).rows_on("time"), steps, "{path}");
        }
    }
    for q in ["eta", "local_s", "linear_s"] {
        let c = get(&format!("/convergence/{q}"));
        assert_eq!(
            c.rows_on("iteration") as u64,
            iterations,
            "{q} per iteration"
        );
        assert_eq!(c.rows_on("time"), 0);
    }
    assert!(e
        .values()
        .all(|c| c.rows_on("parameter") == 0 && c.rows_on("solve") == 0));
}

#[test]
fn rerun_connect_streams_the_same_recording_to_a_viewer_on_loopback() {
    let dir = scratch("rerun-connect");
    let port = free_port();
    let saved = dir.join("received.rrd");
    // the rerun tool as a server that saves what it receives
    let mut server = readers::rerun_cmd(&dir)
        .args(["--bind", "127.0.0.1", "--port", &port.to_string(), "--save"])
        .arg(&saved)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("the rerun tool starts (./scripts/install-readers.sh)");
    let start = std::time::Instant::now();
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            start.elapsed().as_secs() < 60,
            "the rerun server does not listen"
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let o = lopin()
        .args(["run", "two-blocks", "--json", "--rerun-connect"])
        .arg(format!("127.0.0.1:{port}"))
        .output()
        .expect("lopin runs");
    // wait until the server has written everything (the size stops moving)
    let mut last = 0;
    for _ in 0..50 {
        std::thread::sleep(std::time::Duration::from_millis(200));
        let len = std::fs::metadata(&saved).map_or(0, |m| m.len());
        if len > 0 && len == last {
            break;
        }
        last = len;
    }
    let _ = server.kill();
    let _ = server.wait();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    // a streamed file has no footer (the server was stopped), so it is printed, not verified
    let printed = readers::print_rrd(&saved);
    let (solver, _) = reference();
    let p = solver.problem();
    check_recording(
        &printed,
        p,
        p.time.steps + 1,
        report["iterations"].as_u64().expect("iterations"),
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sweep_records_each_value_on_the_parameter_timeline_and_writes_run_json() {
    let dir = scratch("sweep-rerun");
    let (out, rrd) = (dir.join("sweep"), dir.join("sweep.rrd"));
    let o = lopin()
        .args([
            "sweep",
            "two-blocks",
            "--param",
            "f=0.1,0.2,0.3",
            "--json",
            "--out",
        ])
        .arg(&out)
        .arg("--rerun")
        .arg(&rrd)
        .output()
        .expect("lopin sweep runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let total = report["total_iterations"].as_u64().expect("total");
    let e = readers::entities(&read_rrd(&rrd));
    for q in [
        "f",
        "iterations",
        "eta",
        "peak_normal_force",
        "max_slip",
        "energy_end",
    ] {
        let path = format!("/sweep/{q}");
        assert_eq!(e[&path].rows_on("parameter"), 3, "{path}");
    }
    assert_eq!(e["/convergence/eta"].rows_on("iteration") as u64, total);
    let (solver, _) = reference();
    let steps = solver.problem().time.steps + 1;
    let surface = &e["/bodies/A/surface"];
    assert_eq!(surface.rows_on("time"), 3 * steps, "every value's steps");
    assert_eq!(surface.rows_on("parameter"), 3 * steps);
    let run_json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("run.json")).expect("run.json in the sweep folder"),
    )
    .expect("JSON");
    assert_eq!(run_json["kind"], "sweep");
    assert_eq!(run_json["sweep"]["finished"].as_u64(), Some(3));
    assert_eq!(run_json["sweep"]["total_iterations"].as_u64(), Some(total));
    assert_eq!(
        run_json["sweep"]["values"],
        serde_json::json!([0.1, 0.2, 0.3])
    );
    assert!(run_json["files"]
        .as_array()
        .expect("files")
        .iter()
        .any(|f| f == "value-002.state"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_outputs_and_run_directories_get_clear_errors() {
    let dir = scratch("export-errors");
    // a viewer address where nothing listens: refused at once, before solving
    let port = free_port();
    let o = lopin()
        .args(["run", "two-blocks", "--rerun-connect"])
        .arg(format!("127.0.0.1:{port}"))
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no Rerun viewer listens"), "{err}");
    // export from a folder that is not a run
    let o = lopin()
        .arg("export")
        .arg(&dir)
        .arg("--vtu")
        .arg(dir.join("x"))
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("run.json") && err.contains("lopin run --out"),
        "{err}"
    );
    // nothing asked
    let o = lopin().arg("export").arg(&dir).output().expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("nothing to export"), "{err}");
    // a damaged solution file is named
    std::fs::write(dir.join("run.json"), "{\"kind\":\"run\"}").expect("write");
    let o = lopin()
        .arg("export")
        .arg(&dir)
        .arg("--vtu")
        .arg(dir.join("x"))
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("run.json") && err.contains("not a Lopin run.json"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene on tetrahedra (`elements = "tet4"`) exports VTK_TETRA cells that meshio reads as
/// `tetra` blocks: 162 per cube of `mini-impact` (27 hexahedra × 6), with finite stresses.
#[test]
fn tetrahedra_export_as_vtk_tetra_cells() {
    let dir = scratch("exports-tet");
    let scene = dir.join("mini-impact-tet.toml");
    let o = lopin()
        .args(["export-scene", "mini-impact"])
        .output()
        .expect("runs");
    let text = String::from_utf8(o.stdout).expect("toml");
    let text = text.replace("[[body]]\n", "[[body]]\nelements = \"tet4\"\n");
    std::fs::write(&scene, text).expect("scene file");
    let vtu = dir.join("vtu");
    let o = lopin()
        .arg("run")
        .arg(&scene)
        .arg("--vtu")
        .arg(&vtu)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read = read_vtu(&vtu.join("run.pvd"), 0, 5);
    let files = read["files"].as_object().expect("files");
    assert!(!files.is_empty());
    for (name, f) in files {
        let blocks = f["cell_blocks"].as_array().expect("blocks");
        assert_eq!(blocks.len(), 1, "{name}: {blocks:?}");
        assert_eq!(blocks[0][0], "tetra", "{name}");
        assert_eq!(blocks[0][1], 162, "{name}");
        assert_eq!(f["points"], 64, "{name}");
        let vm = f["von_mises"][0].as_f64().expect("von Mises");
        assert!(vm.is_finite() && vm >= 0.0, "{name}: {vm}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
