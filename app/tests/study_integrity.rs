//! The records of `lopin study` cannot be damaged silently. A small study (four friction values
//! of `two-blocks`, every configuration solved cold, so that a configuration solved again gives
//! the same numbers to the last bit) is run once; each test copies it, damages `study.csv` the
//! way a disk or a hand could (a quantity or η made NaN or infinite, a value doubled, one digit
//! changed, a row duplicated, a configuration index out of the study, the older format without
//! checksums, a torn last line) and resumes it: the resume names each damaged row (line,
//! configuration, why) and sums up, solves exactly the damaged configurations again, keeps the
//! other rows byte for byte, and ends with the rows of the untouched study (every column but
//! the wall time and the checksum that covers it) and a `study.parquet` of the checked rows.
//! Also: `f` with `f@ZONE` is refused naming both, and a plan of 100,000 samples is made whole.

mod study_files;

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::sync::OnceLock;
use std::time::{Duration, Instant};
use study_files::{lopin, parquet_matches_csv, scratch, succeeds};

/// The study every test damages: 4 configurations, each solved cold.
const STUDY: [&str; 7] = [
    "study",
    "two-blocks",
    "--param",
    "f=0:0.3:0.1",
    "--rho-inf",
    "0.5",
    "--cold",
];

/// The untouched study, run once for every test.
fn untouched() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = scratch("integrity", "untouched");
        succeeds(lopin().args(STUDY).arg("--out").arg(&dir));
        dir
    })
}

/// study.csv: its header and its data lines in file order.
fn csv(dir: &Path) -> (String, Vec<String>) {
    let text = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    let mut lines = text.lines().map(String::from);
    let header = lines.next().expect("header");
    (header, lines.collect())
}

fn column(header: &str, name: &str) -> usize {
    header.split(',').position(|h| h == name).expect(name)
}

fn index_of(line: &str) -> usize {
    line.split(',')
        .next()
        .expect("index")
        .parse()
        .expect("index")
}

/// Sets field `name` of `line` to `value`.
fn set(header: &str, line: &str, name: &str, value: &str) -> String {
    let k = column(header, name);
    let mut f: Vec<&str> = line.split(',').collect();
    f[k] = value;
    f.join(",")
}

fn field<'a>(header: &str, line: &'a str, name: &str) -> &'a str {
    line.split(',').nth(column(header, name)).expect(name)
}

/// A row without its wall time and checksum (what a configuration solved again reproduces).
fn numbers(header: &str, line: &str) -> Vec<String> {
    let skip = [column(header, "wall_s"), column(header, "checksum")];
    line.split(',')
        .enumerate()
        .filter(|(k, _)| !skip.contains(k))
        .map(|(_, f)| f.to_string())
        .collect()
}

/// A copy of the untouched study whose study.csv `damage` rewrites (the header and the data
/// lines in, the file's text out); returns the folder.
fn damaged(name: &str, damage: impl Fn(&str, &[String]) -> String) -> PathBuf {
    let from = untouched();
    let dir = scratch("integrity", name);
    std::fs::create_dir_all(&dir).expect("creates");
    for f in ["study.json", "study.csv", "study.parquet"] {
        std::fs::copy(from.join(f), dir.join(f)).expect(f);
    }
    let (header, lines) = csv(from);
    std::fs::write(dir.join("study.csv"), damage(&header, &lines)).expect("writes");
    dir
}

/// The line (1-based, the header is line 1) of configuration `i` in the untouched study.
fn line_of(i: usize) -> usize {
    let (_, lines) = csv(untouched());
    lines
        .iter()
        .position(|l| index_of(l) == i)
        .expect("configuration")
        + 2
}

fn text(header: &str, lines: &[String]) -> String {
    let mut t = format!("{header}\n");
    for l in lines {
        t.push_str(l);
        t.push('\n');
    }
    t
}

/// Resumes the study in `dir`; its stderr. Checks that exactly `recomputed` were solved again
/// (one progress line each, their rows equal to the untouched study's but for the wall time),
/// that every other row is the untouched study's byte for byte, and that study.parquet holds
/// the checked rows.
fn resume(dir: &Path, recomputed: &[usize]) -> String {
    let out = succeeds(lopin().args(STUDY).args(["--resume", "--out"]).arg(dir));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let solves = stderr
        .lines()
        .filter(|l| l.trim_start().starts_with('[') && l.contains("iterations"))
        .count();
    assert_eq!(solves, recomputed.len(), "{stderr}");
    let (header, want) = csv(untouched());
    let (header_after, mut got) = csv(dir);
    assert_eq!(header_after, header);
    assert_eq!(got.len(), want.len(), "{got:#?}");
    got.sort_by_key(|l| index_of(l));
    let mut want = want;
    want.sort_by_key(|l| index_of(l));
    for (g, w) in got.iter().zip(&want) {
        let i = index_of(w);
        assert_eq!(index_of(g), i);
        if recomputed.contains(&i) {
            assert_eq!(
                numbers(&header, g),
                numbers(&header, w),
                "configuration {i}"
            );
            assert_ne!(
                field(&header, g, "wall_s"),
                field(&header, w, "wall_s"),
                "configuration {i} was not solved again"
            );
        } else {
            assert_eq!(g, w, "configuration {i} kept");
        }
        // every row's checksum: the crc32 of its text before it
        let body = &g[..g.rfind(',').expect("fields")];
        assert_eq!(
            field(&header, g, "checksum"),
            format!("{:08x}", crc32fast::hash(body.as_bytes()))
        );
    }
    parquet_matches_csv(dir);
    stderr
}

/// Damages field `name` of configuration `i` to `value`, resumes, and checks the message
/// `{csv} line L: configuration i: {why}: dropped, recomputing it` and the summary.
fn one_field(test: &str, i: usize, name: &str, value: impl Fn(&str) -> String, why: &str) {
    let dir = damaged(test, |h, lines| {
        let lines: Vec<String> = lines
            .iter()
            .map(|l| {
                if index_of(l) == i {
                    set(h, l, name, &value(field(h, l, name)))
                } else {
                    l.clone()
                }
            })
            .collect();
        text(h, &lines)
    });
    let stderr = resume(&dir, &[i]);
    let path = dir.join("study.csv");
    let want = format!(
        "{} line {}: configuration {i}: {why}: dropped, recomputing it",
        path.display(),
        line_of(i)
    );
    assert!(stderr.contains(&want), "`{want}` not in:\n{stderr}");
    let summary = format!(
        "{}: kept 3 rows, dropped 1 damaged row, recomputing 1 configuration ({i})",
        path.display()
    );
    assert!(stderr.contains(&summary), "`{summary}` not in:\n{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn study_resume_recomputes_a_nan_row() {
    one_field(
        "nan-force",
        1,
        "peak_normal_force",
        |_| "NaN".into(),
        "peak_normal_force is NaN, not a finite number",
    );
}

#[test]
fn study_resume_recomputes_an_infinite_slip() {
    one_field(
        "inf-slip",
        2,
        "max_slip",
        |_| "inf".into(),
        "max_slip is inf, not a finite number",
    );
}

#[test]
fn study_resume_recomputes_a_negative_infinite_energy() {
    one_field(
        "neg-inf-energy",
        0,
        "energy_end",
        |_| "-inf".into(),
        "energy_end is -inf, not a finite number",
    );
}

#[test]
fn study_resume_recomputes_a_nan_eta() {
    one_field(
        "nan-eta",
        3,
        "eta",
        |_| "NaN".into(),
        "eta is NaN, not a finite number",
    );
}

/// The checksum message for configuration `i` of a damaged copy in `dir`.
fn mismatch(dir: &Path, i: usize) -> String {
    let (header, lines) = csv(dir);
    let line = lines.iter().find(|l| index_of(l) == i).expect("row");
    let body = &line[..line.rfind(',').expect("fields")];
    format!(
        "checksum mismatch (stored `{}`, computed {:08x}): the row was edited or damaged",
        field(&header, line, "checksum"),
        crc32fast::hash(body.as_bytes())
    )
}

#[test]
fn study_resume_recomputes_an_edited_value() {
    // peak_normal_force doubled: a plausible number, caught by the checksum only
    let double = |x: &str| (2.0 * x.parse::<f64>().expect("number")).to_string();
    let dir = damaged("doubled", |h, lines| {
        let lines: Vec<String> = lines
            .iter()
            .map(|l| {
                if index_of(l) == 2 {
                    set(
                        h,
                        l,
                        "peak_normal_force",
                        &double(field(h, l, "peak_normal_force")),
                    )
                } else {
                    l.clone()
                }
            })
            .collect();
        text(h, &lines)
    });
    let why = mismatch(&dir, 2);
    one_field_checked(&dir, 2, &why);
}

#[test]
fn study_resume_recomputes_a_changed_digit() {
    // one digit of input_work changed (the third significant one, 0–8 → +1, 9 → 0)
    let dir = damaged("digit", |h, lines| {
        let lines: Vec<String> = lines
            .iter()
            .map(|l| {
                if index_of(l) != 1 {
                    return l.clone();
                }
                let x = field(h, l, "input_work");
                let k = x
                    .char_indices()
                    .filter(|(_, c)| c.is_ascii_digit())
                    .nth(2)
                    .expect("three digits")
                    .0;
                let c = x.as_bytes()[k];
                let d = if c == b'9' { '0' } else { char::from(c + 1) };
                let changed = format!("{}{d}{}", &x[..k], &x[k + 1..]);
                assert_ne!(changed, x);
                set(h, l, "input_work", &changed)
            })
            .collect();
        text(h, &lines)
    });
    let why = mismatch(&dir, 1);
    one_field_checked(&dir, 1, &why);
}

/// Resumes the copy in `dir` whose configuration `i` alone is damaged; checks the message.
fn one_field_checked(dir: &Path, i: usize, why: &str) {
    let stderr = resume(dir, &[i]);
    let path = dir.join("study.csv");
    let want = format!(
        "{} line {}: configuration {i}: {why}: dropped, recomputing it",
        path.display(),
        line_of(i)
    );
    assert!(stderr.contains(&want), "`{want}` not in:\n{stderr}");
    assert!(stderr.contains("kept 3 rows, dropped 1 damaged row, recomputing 1 configuration"));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn study_resume_refuses_duplicated_rows() {
    // configuration 2's row twice, the copy at the end: both copies dropped, 2 solved again
    let dir = damaged("duplicate", |h, lines| {
        let mut lines = lines.to_vec();
        let copy = lines
            .iter()
            .find(|l| index_of(l) == 2)
            .expect("row")
            .clone();
        lines.push(copy);
        text(h, &lines)
    });
    let stderr = resume(&dir, &[2]);
    let path = dir.join("study.csv");
    let want = format!(
        "{} lines {} and 6: configuration 2 is on 2 rows: every copy dropped, recomputing it",
        path.display(),
        line_of(2)
    );
    assert!(stderr.contains(&want), "`{want}` not in:\n{stderr}");
    let summary = format!(
        "{}: kept 3 rows, dropped 2 damaged rows, recomputing 1 configuration (2)",
        path.display()
    );
    assert!(stderr.contains(&summary), "`{summary}` not in:\n{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn study_resume_refuses_unknown_configuration_indices() {
    // a fifth row naming configuration 57 of a study of 4: dropped, nothing solved again
    let dir = damaged("unknown-index", |h, lines| {
        let mut lines = lines.to_vec();
        let copy = set(h, &lines[0], "index", "57");
        lines.push(copy);
        text(h, &lines)
    });
    let stderr = resume(&dir, &[]);
    let path = dir.join("study.csv");
    for want in [
        format!(
            "{} line 6: configuration 57 is not one of this study's (0 to 3): dropped",
            path.display()
        ),
        format!(
            "{}: kept 4 rows, dropped 1 damaged row, recomputing 0 configurations",
            path.display()
        ),
    ] {
        assert!(stderr.contains(&want), "`{want}` not in:\n{stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn study_resume_of_the_older_format_recomputes_every_row() {
    // study.csv without the checksum column: nothing can be verified, everything solved again
    let dir = damaged("older-format", |h, lines| {
        let strip = |l: &str| l[..l.rfind(',').expect("fields")].to_string();
        let lines: Vec<String> = lines.iter().map(|l| strip(l)).collect();
        text(&strip(h), &lines)
    });
    let stderr = resume(&dir, &[0, 1, 2, 3]);
    let want = format!(
        "{}: of an older format, without the checksum column: its 4 rows cannot be verified: \
         kept 0 rows, recomputing 4 configurations (0, 1, 2 and 3)",
        dir.join("study.csv").display()
    );
    assert!(stderr.contains(&want), "`{want}` not in:\n{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn study_resume_equals_an_uninterrupted_run() {
    // several damages at once: a NaN force on 0, a doubled slip on 3, and configuration 1's row
    // torn in the middle (the study stopped while writing it) at the end of the file
    let dir = damaged("several", |h, lines| {
        let mut out: Vec<String> = Vec::new();
        let mut torn = String::new();
        for l in lines {
            match index_of(l) {
                0 => out.push(set(h, l, "peak_normal_force", "NaN")),
                1 => torn = l[..l.len() / 2].to_string(),
                3 => {
                    let slip: f64 = field(h, l, "max_slip").parse().expect("number");
                    out.push(set(h, l, "max_slip", &(2.0 * slip).to_string()));
                }
                _ => out.push(l.clone()),
            }
        }
        let mut t = text(h, &out);
        t.push_str(&torn);
        t
    });
    let (header, lines) = csv(&dir);
    let fields = lines.last().expect("torn line").split(',').count();
    let stderr = resume(&dir, &[0, 1, 3]);
    let path = dir.join("study.csv");
    for want in [
        format!(
            "{} line 2: configuration 0: peak_normal_force is NaN, not a finite number: \
             dropped, recomputing it",
            path.display()
        ),
        format!(
            "{} line 5: configuration 1: {fields} fields where a row has {} (the last line, cut \
             short: the study was stopped while writing it): dropped, recomputing it",
            path.display(),
            header.split(',').count()
        ),
        format!(
            "{}: kept 1 row, dropped 3 damaged rows, recomputing 3 configurations (0, 1 and 3)",
            path.display()
        ),
    ] {
        assert!(stderr.contains(&want), "`{want}` not in:\n{stderr}");
    }
    // the totals of the untouched study
    let json = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("study.json")).expect("study.json"))
            .expect("json")
    };
    let (a, b) = (json(&dir), json(untouched()));
    for key in ["configurations", "converged", "iterations"] {
        assert_eq!(a["totals"][key], b["totals"][key], "{key}");
    }
    assert_eq!(a["totals"]["statistics"], b["totals"]["statistics"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `lopin study SCENE ARGS --out DIR` must fail naming every one of `needles`, writing nothing.
fn refused(scene: &str, args: &[&str], needles: &[&str]) {
    let dir = scratch("integrity", "refused");
    let out = lopin()
        .args(["study", scene])
        .args(args)
        .arg("--out")
        .arg(&dir)
        .output()
        .expect("runs");
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} accepted");
    for n in needles {
        assert!(msg.contains(n), "{args:?}: `{n}` not in: {msg}");
    }
    assert!(!dir.exists(), "{args:?} wrote {}", dir.display());
}

#[test]
fn zone_and_global_friction_together_are_refused() {
    let scene = format!(
        "{}/../assets/scenes/test/mini-stack-zones.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let why = "`f` (every interface) and `f@upper` (one zone) move the same parameter in that \
               zone, one value overwriting the other: give `f` alone, or one `f@ZONE` per zone";
    // in either order
    refused(
        &scene,
        &["--param", "f@upper=0,0.5", "--param", "f=0.1,0.2"],
        &["--param f=0.1,0.2: ", why],
    );
    refused(
        &scene,
        &["--param", "f=0.1,0.2", "--param", "f@upper=0,0.5"],
        &["--param f@upper=0,0.5: ", why],
    );
    // different parameters, or zones only, are not in conflict: gap with f@upper passes the
    // check (and is then refused for --samples 0, before anything is written)
    refused(
        &scene,
        &[
            "--param",
            "f@upper=0,0.5",
            "--param",
            "gap=0,1e-6",
            "--samples",
            "0",
        ],
        &["--samples: must be positive"],
    );
}

#[test]
fn study_plans_100000_samples() {
    // the plan (design, visiting order, chains) of 100,000 samples is made and written; the
    // study is stopped once it starts solving
    let dir = scratch("integrity", "plan");
    let mut child = lopin()
        .args(["study", "two-blocks", "--param", "f=uniform(0,0.5)"])
        .args([
            "--param",
            "gap=uniform(0,2e-6)",
            "--samples",
            "100000",
            "--out",
        ])
        .arg(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawns");
    let start = Instant::now();
    let plan: serde_json::Value = loop {
        // study.json is written whole (renamed into place) before the first solve
        if let Ok(text) = std::fs::read_to_string(dir.join("study.json")) {
            break serde_json::from_str(&text).expect("json");
        }
        if let Some(status) = child.try_wait().expect("wait") {
            panic!("the study ended ({status}) without a plan");
        }
        assert!(start.elapsed() < Duration::from_secs(600), "no plan");
        std::thread::sleep(Duration::from_millis(20));
    };
    child.kill().ok();
    child.wait().expect("reaped");
    let plan = &plan["plan"];
    assert_eq!(plan["configurations"], 100_000);
    assert_eq!(plan["design"], "lhs");
    let mut order: Vec<usize> = plan["order"]
        .as_array()
        .expect("order")
        .iter()
        .map(|v| v.as_u64().expect("index") as usize)
        .collect();
    assert_eq!(order.len(), 100_000);
    let path_length = plan["path_length"].as_f64().expect("length");
    let given_length = plan["given_length"].as_f64().expect("length");
    // the greedy path walks the unit square in short steps; the given order jumps across it
    assert!(
        path_length < 0.02 * given_length,
        "{path_length} against {given_length}"
    );
    order.sort_unstable();
    assert_eq!(order, (0..100_000).collect::<Vec<_>>());
    let _ = std::fs::remove_dir_all(&dir);
}
