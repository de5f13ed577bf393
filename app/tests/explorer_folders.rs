//! The explorer opening result folders with the `lopin` binary's reader, driven with
//! egui_kittest: a run folder is shown from its stored solution without an iteration (the
//! fields on screen equal those computed from `solution.bin` bit for bit); a study folder opens
//! with its table, each configuration warm-solved from its stored state to the quantities its
//! row holds, sortable by any column, two configurations pinned and compared as a difference
//! field; a sweep folder the same; a damaged `solution.bin`, a foreign folder and a damaged
//! state file each give a message naming the file in the window, and nothing else changes. A
//! run folder with stored step fields (`lopin run --out DIR --fields`) opens without its scene:
//! the fields on screen at the first step shown and after a scrub equal those replayed from
//! `solution.bin` to single precision (relative 1e-6 of the field's largest value), the probe's
//! histories likewise (its accelerations, differences of single-precision velocities, to 1e-3),
//! nothing is solved, another parameter value is refused with a message naming the folder; a
//! damaged step, head, cut file or another run's file each give a message naming `fields.bin`
//! and the reason; `lopin export DIR --fields` adds the same file to a run folder without it.

mod readers;

use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use lopin_app::run_dir::run_json::RunRecord;
use lopin_explorer::fields::{self, SubStepFields};
use lopin_explorer::result_folder::FolderKind;
use lopin_explorer::{ExplorerApp, Loaded, Options};
use readers::scratch;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

type H = Harness<'static, ExplorerApp>;

fn lopin(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_lopin"))
        .args(args)
        .output()
        .expect("lopin runs");
    assert!(
        out.status.success(),
        "lopin {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn harness(scene: &Path) -> H {
    let options = Options {
        reproducible: true,
        opener: Some(lopin_app::result_folder::opener()),
        ..Options::scene(&scene.display().to_string())
    };
    Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_eframe(move |cc| ExplorerApp::new(cc, options).expect("the folder opens"))
}

fn step_until(h: &mut H, what: &str, done: impl Fn(&ExplorerApp) -> bool) {
    let start = Instant::now();
    while !done(h.state()) {
        h.step();
        assert!(
            start.elapsed() < Duration::from_secs(180),
            "{what}: status {:?}, error {:?}",
            h.state().solve.status(),
            h.state().solve.error()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    h.step();
    h.step();
}

/// Clicks the widget labelled `label` (through accesskit, as assistive technology does) and
/// draws the two frames that take the click in.
fn click(h: &mut H, label: &str) {
    h.get_by_label(label).click_accesskit();
    h.step();
    h.step();
}

/// The newest request converged and its converged fields at the displayed step are on screen.
fn settled(a: &ExplorerApp) -> bool {
    a.solve.converged()
        && a.cache
            .shown()
            .is_some_and(|f| !f.live && f.step == a.clock.step())
}

#[test]
fn a_run_folder_is_shown_from_its_stored_solution_without_solving() {
    let dir = scratch("view-run");
    let run = dir.join("run");
    lopin(&["run", "two-blocks", "--out", run.to_str().expect("utf-8")]);
    let mut h = harness(&run);
    step_until(&mut h, "the stored run shown", settled);
    let app = h.state();
    let results = app.results.as_ref().expect("a folder is open");
    assert_eq!(results.kind, FolderKind::Run);
    assert_eq!(results.table.rows.len(), 1);
    let r = app.solve.reports().last().expect("a report");
    assert!(r.from_store && r.iterations == 0 && r.converged, "{r:?}");
    assert_eq!(app.solve.reports().len(), 1, "nothing solved");
    // the fields on screen are those of solution.bin, computed here from the file
    let (_, solver, solution) = RunRecord::open_run(&run).expect("the run reads back");
    let step = app.clock.step();
    let expected = lopin_explorer::fields::compute(&solver, &solution, step, 0, false);
    let shown = app.cache.shown().expect("fields");
    assert_eq!(shown.step, step);
    assert_eq!(shown.subs, expected.subs);
    assert!(
        shown
            .subs
            .iter()
            .flat_map(|s| &s.von_mises)
            .any(|&v| v > 1e6),
        "a stressed run at step {step}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_study_folder_opens_with_its_table_and_each_configuration_reaches_its_row() {
    let dir = scratch("view-study");
    let study = dir.join("study");
    lopin(&[
        "study",
        "two-blocks",
        "--param",
        "f=0:0.4:0.2",
        "--param",
        "gap=0:10e-6:10e-6",
        "--out",
        study.to_str().expect("utf-8"),
    ]);
    let mut h = harness(&study);
    h.state_mut().study.paused = true;
    step_until(&mut h, "the first configuration", settled);
    let table = h.state().results.as_ref().expect("open").table.clone();
    assert_eq!(table.rows.len(), 6);
    assert_eq!(table.parameters, vec!["f", "gap"]);
    // each configuration shown from its stored state reaches the quantities its row holds
    let check = |h: &H, r: usize| {
        let app = h.state();
        let f = table.rows[r].assigned[0].value;
        assert_eq!(app.solve.params().friction, Some(f));
        assert_eq!(
            app.solve.params().gap,
            Some(table.rows[r].assigned[1].value)
        );
        let report = app.solve.reports().last().expect("a report");
        assert!(report.converged && report.warm, "{report:?}");
        let point = app
            .study
            .points()
            .iter()
            .find(|p| (p.value - f).abs() < 1e-12)
            .expect("stored in the library");
        eprintln!(
            "row {r}: explorer {:?}, study.csv {:?}, {} iterations",
            point.quantities, table.rows[r].quantities, report.iterations
        );
        for (q, (&got, &want)) in point
            .quantities
            .iter()
            .zip(&table.rows[r].quantities)
            .enumerate()
        {
            let scale = table
                .rows
                .iter()
                .map(|row| row.quantities[q].abs())
                .fold(0.0, f64::max);
            // the warm-start bound of the sweeps and the explorer's re-solves: 30·tol
            let tol = app.solve.params().settings.tol;
            assert!(
                (got - want).abs() <= 30.0 * tol * scale,
                "row {r}, {}: {got} against {want}",
                table.quantities[q]
            );
        }
        report.iterations
    };
    let first_iterations = check(&h, 0);
    // sort by max slip, descending: the table's order follows the column
    click(&mut h, "max_slip (m)");
    click(&mut h, "max_slip (m) (asc)");
    let view = h.state().results.as_ref().expect("open");
    assert_eq!(view.sort, (3, false));
    let order = view.table.sorted(3, false);
    let slips: Vec<f64> = order.iter().map(|&r| table.rows[r].quantities[1]).collect();
    assert!(slips.windows(2).all(|w| w[0] >= w[1]), "{slips:?}");
    // pin configuration 0 (f = 0, gap = 0), show the one at f = 0.2, gap = 0: the difference
    // field is drawn on a symmetric range
    h.state_mut().study.paused = true;
    click(&mut h, "pin A");
    assert_eq!(h.state().study.pinned, Some(0.0));
    let find = |f: f64, gap: f64| {
        table
            .rows
            .iter()
            .position(|r| r.assigned[0].value == f && r.assigned[1].value == gap)
            .expect("in the grid")
    };
    let b = find(0.2, 0.0);
    click(&mut h, &format!("config {b}"));
    step_until(&mut h, "configuration B", settled);
    let iterations = check(&h, b);
    click(&mut h, "current − A");
    step_until(&mut h, "the difference field", |a| {
        a.layout.mesh().difference
    });
    let mesh = h.state().layout.mesh().clone();
    assert!(mesh.difference);
    assert!(mesh.extent.0 < mesh.extent.1, "{:?}", mesh.extent);
    assert!(
        mesh.range.0 < 0.0 && (mesh.range.0 + mesh.range.1).abs() < 1e-12 * mesh.range.1,
        "{:?}",
        mesh.range
    );
    // another base (gap 10 µm): shown, its own quantities
    let c = find(0.4, 10e-6);
    click(&mut h, &format!("config {c}"));
    step_until(&mut h, "configuration C", settled);
    check(&h, c);
    eprintln!("iterations from the stored states: {first_iterations}, {iterations}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_sweep_folder_opens_with_one_row_per_finished_value() {
    let dir = scratch("view-sweep");
    let sweep = dir.join("sweep");
    lopin(&[
        "sweep",
        "two-blocks",
        "--param",
        "f=0:0.2:0.1",
        "--out",
        sweep.to_str().expect("utf-8"),
    ]);
    let mut h = harness(&sweep);
    step_until(&mut h, "the first value", settled);
    let view = h.state().results.as_ref().expect("open");
    assert_eq!(view.kind, FolderKind::Sweep);
    let values: Vec<f64> = view
        .table
        .rows
        .iter()
        .map(|r| r.assigned[0].value)
        .collect();
    assert_eq!(values, vec![0.0, 0.1, 0.2]);
    click(&mut h, "value 2");
    step_until(&mut h, "value 2", settled);
    assert_eq!(h.state().solve.params().friction, Some(0.2));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn damaged_and_foreign_folders_give_a_message_in_the_window() {
    let dir = scratch("view-damaged");
    let run = dir.join("run");
    lopin(&["run", "two-blocks", "--out", run.to_str().expect("utf-8")]);
    let study = dir.join("study");
    lopin(&[
        "study",
        "two-blocks",
        "--param",
        "f=0:0.2:0.2",
        "--out",
        study.to_str().expect("utf-8"),
    ]);
    let mut h = harness(&study);
    // no background solve: what each click shows comes from the folder
    h.state_mut().study.paused = true;
    step_until(&mut h, "the study", settled);

    // a flipped byte in solution.bin: refused, naming it; the study stays open
    let damaged = dir.join("damaged");
    std::fs::create_dir_all(&damaged).expect("folder");
    for f in ["run.json", "solution.bin"] {
        std::fs::copy(run.join(f), damaged.join(f)).expect("copy");
    }
    let bin = damaged.join("solution.bin");
    let mut bytes = std::fs::read(&bin).expect("read");
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x10;
    std::fs::write(&bin, bytes).expect("write");
    let open = |h: &mut H, path: &Path| {
        h.state_mut().folder_input = path.display().to_string();
        h.step();
        click(h, "open");
    };
    open(&mut h, &damaged);
    let error = h.state().solve.error().expect("a message").to_string();
    assert!(error.contains("solution.bin"), "{error}");
    assert_eq!(
        h.state().results.as_ref().map(|r| r.kind),
        Some(FolderKind::Study),
        "the study stays"
    );
    h.get_by_label(&format!("error: {error}"));

    // a folder of something else
    let foreign = dir.join("foreign");
    std::fs::create_dir_all(&foreign).expect("folder");
    std::fs::write(foreign.join("notes.txt"), "not a result").expect("write");
    open(&mut h, &foreign);
    let error = h.state().solve.error().expect("a message").to_string();
    assert!(error.contains("not a result folder"), "{error}");

    // a damaged state: the table opens, the row names the file, another row still shows
    let state = study.join("states/config-0001.state");
    let mut bytes = std::fs::read(&state).expect("read");
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x10;
    std::fs::write(&state, bytes).expect("write");
    click(&mut h, "config 1");
    step_until(&mut h, "the error", |a| a.solve.error().is_some());
    let error = h.state().solve.error().expect("a message").to_string();
    assert!(error.contains("config-0001.state"), "{error}");
    click(&mut h, "config 0");
    step_until(&mut h, "configuration 0 again", settled);
    assert_eq!(h.state().solve.params().friction, Some(0.0));

    // the good run folder opens from the window's field
    open(&mut h, &run);
    step_until(&mut h, "the run", settled);
    assert_eq!(
        h.state().results.as_ref().map(|r| r.kind),
        Some(FolderKind::Run)
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The converged fields of the displayed step are on screen.
fn shown_at(a: &ExplorerApp, step: usize) -> bool {
    a.solve.converged()
        && a.cache
            .shown()
            .is_some_and(|f| !f.live && f.step == step && a.clock.step() == step)
}

/// `a` equals `b` to single precision: within 1e-6 of b's own size plus 1e-6 of the largest
/// value of the field.
fn close(what: &str, a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= 1e-6 * (y.abs() + scale),
            "{what}[{k}]: {x} against {y} (largest {scale})"
        );
    }
}

fn same_fields(step: usize, shown: &[SubStepFields], expected: &[SubStepFields]) {
    assert_eq!(shown.len(), expected.len());
    let flat = |f: &[SubStepFields], pick: fn(&SubStepFields) -> &Vec<f64>| -> Vec<f64> {
        f.iter().flat_map(|s| pick(s).iter().copied()).collect()
    };
    for (name, pick) in [
        ("u", (|s| &s.u) as fn(&SubStepFields) -> &Vec<f64>),
        ("v", |s| &s.v),
        ("von Mises", |s| &s.von_mises),
    ] {
        close(
            &format!("step {step}: {name}"),
            &flat(shown, pick),
            &flat(expected, pick),
        );
    }
    assert!(
        expected.iter().flat_map(|s| &s.von_mises).any(|&v| v > 1e6),
        "a stressed run at step {step}"
    );
}

#[test]
fn a_run_with_stored_fields_opens_without_its_scene_and_reads_each_step() {
    let dir = scratch("view-stored");
    let run = dir.join("run");
    lopin(&[
        "run",
        "two-blocks",
        "--out",
        run.to_str().expect("utf-8"),
        "--fields",
    ]);
    let record = RunRecord::read(&run).expect("run.json");
    assert!(
        record.files.iter().any(|f| f == "fields.bin"),
        "{:?}",
        record.files
    );
    let (_, solver, solution) = RunRecord::open_run(&run).expect("the run reads back");
    let steps = solver.problem().time.steps;

    let mut h = harness(&run);
    let first = h.state().clock.step();
    step_until(&mut h, "the stored run shown", |a| shown_at(a, first));
    let app = h.state();
    assert!(app.stored, "opened from its stored fields");
    assert_eq!(app.results.as_ref().map(|r| r.kind), Some(FolderKind::Run));
    assert_eq!(app.info.dofs, solver.problem().dof_count());
    assert_eq!(app.info.steps, steps);
    let r = app.solve.reports().last().expect("a report");
    assert!(r.from_store && r.iterations == 0 && r.converged, "{r:?}");
    let expected = fields::compute(&solver, &solution, first, 0, false);
    same_fields(
        first,
        &app.cache.shown().expect("fields").subs,
        &expected.subs,
    );

    // a scrub reads that step from the file
    let to = (3 * steps) / 4;
    h.state_mut().clock.set_step(to);
    step_until(&mut h, "the scrubbed step", |a| shown_at(a, to));
    let expected = fields::compute(&solver, &solution, to, 0, false);
    same_fields(
        to,
        &h.state().cache.shown().expect("fields").subs,
        &expected.subs,
    );
    assert_eq!(h.state().solve.reports().len(), 1, "nothing solved");

    // the probe: a node of A's top face, its histories read node by node through the steps
    let (sub, node, _) =
        lopin_core::post::nearest_node(solver.problem(), [0.02, 0.02, 0.04]).expect("a node");
    h.state_mut().set_probe(sub, node);
    step_until(&mut h, "the probe", |a| a.cache.probe_history().is_some());
    let got = h.state().cache.probe_history().expect("a probe").clone();
    let want = fields::probe(&solver, &solution, sub, node);
    close("probe |v|", &got.speed, &want.speed);
    close("probe von Mises", &got.von_mises, &want.von_mises);
    let peak = want.acceleration.iter().fold(0.0f64, |m, &x| m.max(x));
    assert!(peak > 0.0);
    for (x, y) in got.acceleration.iter().zip(&want.acceleration) {
        assert!((x - y).abs() <= 1e-3 * peak, "probe |a|: {x} against {y}");
    }
    assert_eq!(got.spectrum.len(), want.spectrum.len());
    let top = want
        .spectrum
        .iter()
        .flat_map(|s| s.1)
        .fold(0.0f64, f64::max);
    for (g, w) in got.spectrum.iter().zip(&want.spectrum) {
        assert_eq!(g.0, w.0);
        for c in 0..3 {
            assert!(
                (g.1[c] - w.1[c]).abs() <= 1e-3 * top,
                "spectrum {g:?} against {w:?}"
            );
        }
    }

    // another parameter value needs the scene: refused, naming the folder
    if let Some(f) = &mut h.state_mut().solve.params_mut().friction {
        *f += 0.1;
    }
    step_until(&mut h, "the refusal", |a| a.solve.error().is_some());
    let error = h.state().solve.error().expect("a message").to_string();
    assert!(
        error.contains(&run.display().to_string()) && error.contains("stored fields"),
        "{error}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Copies `run` to `to` and changes its fields.bin with `damage`.
fn damaged_copy(run: &Path, to: &Path, damage: impl FnOnce(&mut Vec<u8>)) {
    std::fs::create_dir_all(to).expect("folder");
    for f in ["run.json", "solution.bin", "fields.bin"] {
        std::fs::copy(run.join(f), to.join(f)).expect("copy");
    }
    let path = to.join("fields.bin");
    let mut bytes = std::fs::read(&path).expect("read");
    damage(&mut bytes);
    std::fs::write(&path, bytes).expect("write");
}

fn open_error(dir: &Path) -> String {
    match lopin_app::result_folder::open(dir) {
        Ok(_) => panic!("{}: opened", dir.display()),
        Err(e) => format!("{e:#}"),
    }
}

#[test]
fn damaged_or_foreign_stored_fields_are_refused_naming_the_file() {
    let dir = scratch("view-stored-damaged");
    let run = dir.join("run");
    let path = run.to_str().expect("utf-8");
    lopin(&["run", "two-blocks", "--out", path, "--fields"]);
    let other = dir.join("other");
    lopin(&[
        "run",
        "two-blocks",
        "--f",
        "0.1",
        "--out",
        other.to_str().expect("utf-8"),
        "--fields",
    ]);

    // added later to a run folder without it: the same file
    let plain = dir.join("plain");
    let plain_path = plain.to_str().expect("utf-8");
    lopin(&["run", "two-blocks", "--out", plain_path]);
    assert!(matches!(
        lopin_app::result_folder::open(&plain),
        Ok(Loaded::Folder(_))
    ));
    lopin(&["export", plain_path, "--fields"]);
    assert!(
        std::fs::read(plain.join("fields.bin")).ok() == std::fs::read(run.join("fields.bin")).ok(),
        "lopin export --fields writes the file lopin run --fields does"
    );
    let record = RunRecord::read(&plain).expect("run.json");
    assert!(record.files.iter().any(|f| f == "fields.bin"));
    assert!(matches!(
        lopin_app::result_folder::open(&plain),
        Ok(Loaded::Stored(_))
    ));

    // its head: refused at opening
    let head = dir.join("head");
    damaged_copy(&run, &head, |b| b[40] ^= 0x10);
    let e = open_error(&head);
    assert!(
        e.contains("fields.bin") && e.contains("head is damaged"),
        "{e}"
    );
    // cut short
    let cut = dir.join("cut");
    damaged_copy(&run, &cut, |b| b.truncate(b.len() - 10));
    let e = open_error(&cut);
    assert!(e.contains("fields.bin") && e.contains("cut short"), "{e}");
    // another run's file
    let foreign = dir.join("foreign");
    damaged_copy(&run, &foreign, |b| {
        *b = std::fs::read(other.join("fields.bin")).expect("read")
    });
    let e = open_error(&foreign);
    assert!(e.contains("fields.bin") && e.contains("another run"), "{e}");
    // not Lopin's
    let text = dir.join("text");
    damaged_copy(&run, &text, |b| {
        *b = b"just some text, long enough to be read".to_vec()
    });
    let e = open_error(&text);
    assert!(e.contains("fields.bin") && e.contains("not a Lopin"), "{e}");

    // a damaged last step: the folder opens, that step's picture is refused naming it
    let step = dir.join("step");
    damaged_copy(&run, &step, |b| {
        let n = b.len();
        b[n - 100] ^= 0x10
    });
    match lopin_app::result_folder::open(&step).expect("the head is intact") {
        Loaded::Stored(_) => {}
        _ => panic!("a run with fields.bin opens from it"),
    }
    let mut h = harness(&step);
    let first = h.state().clock.step();
    step_until(&mut h, "the first step", |a| shown_at(a, first));
    let last = h.state().clock.steps();
    h.state_mut().clock.set_step(last);
    step_until(&mut h, "the damaged step", |a| a.solve.error().is_some());
    let e = h.state().solve.error().expect("a message").to_string();
    assert!(
        e.contains("fields.bin") && e.contains(&format!("step {last} is damaged")),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
