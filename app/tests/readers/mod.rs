//! The real readers the export tests check Lopin's files with: meshio (Python) for .vtu, the
//! `rerun` command-line tool of the Python package `rerun-sdk` (the crate's exact version) for
//! .rrd. `scripts/install-readers.sh` installs both into a virtual environment and
//! `scripts/test.sh` points `LOPIN_PYTHON` and `LOPIN_RERUN` at it.

#![allow(dead_code)] // each test file uses part of it

use std::path::{Path, PathBuf};
use std::process::Command;

/// The Python interpreter that has meshio.
pub fn python() -> String {
    std::env::var("LOPIN_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// The `rerun` command-line tool.
pub fn rerun() -> String {
    std::env::var("LOPIN_RERUN").unwrap_or_else(|_| "rerun".into())
}

/// The `lopin` binary of this build.
pub fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

/// A loopback port where nothing listens (bound, then released).
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port()
}

/// A fresh scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lopin-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn run(cmd: &mut Command, what: &str) -> String {
    let out = cmd.output().unwrap_or_else(|e| {
        panic!("{what}: cannot start ({e}); install the readers with ./scripts/install-readers.sh")
    });
    assert!(
        out.status.success(),
        "{what} failed: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// `vtu_probe.py` on a .pvd: entries of the collection and, per file, what meshio read.
pub fn read_vtu(pvd: &Path, node: usize, cell: usize) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/readers/vtu_probe.py");
    let text = run(
        Command::new(python())
            .arg(script)
            .arg(pvd)
            .arg(node.to_string())
            .arg(cell.to_string()),
        "meshio reader",
    );
    serde_json::from_str(&text).expect("the reader prints JSON")
}

/// The `rerun` tool with scratch config and data folders under `home`.
pub fn rerun_cmd(home: &Path) -> Command {
    let mut c = Command::new(rerun());
    c.env("XDG_CONFIG_HOME", home.join("config"))
        .env("XDG_DATA_HOME", home.join("data"));
    c
}

/// What a recording holds for one entity: per chunk, its timelines and its number of rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EntityChunks {
    /// (timelines of the chunk, sorted; rows).
    pub chunks: Vec<(Vec<String>, usize)>,
}

impl EntityChunks {
    /// Rows logged with `timeline` set.
    pub fn rows_on(&self, timeline: &str) -> usize {
        self.chunks
            .iter()
            .filter(|(t, _)| t.iter().any(|x| x == timeline))
            .map(|(_, n)| n)
            .sum()
    }

    /// Rows logged static (no timeline at all).
    pub fn static_rows(&self) -> usize {
        self.chunks
            .iter()
            .filter(|(t, _)| t.is_empty())
            .map(|(_, n)| n)
            .sum()
    }
}

/// Parses `rerun rrd print -vv`: each chunk's header line (`Chunk(…) with N rows (…) - /path - `)
/// and its column header row (`RowId ┆ timeline… ┆ Archetype:component…`).
pub fn entities(printed: &str) -> std::collections::BTreeMap<String, EntityChunks> {
    let mut out: std::collections::BTreeMap<String, EntityChunks> = Default::default();
    let mut current: Option<(String, usize)> = None;
    for line in printed.lines() {
        if let Some(rest) = line.strip_prefix("Chunk(") {
            let rows = rest
                .split(" with ")
                .nth(1)
                .and_then(|r| r.split(' ').next())
                .and_then(|n| n.parse().ok())
                .expect("chunk header has a row count");
            let path = rest
                .split(" - ")
                .nth(1)
                .expect("chunk header has an entity path")
                .trim()
                .to_string();
            current = Some((path, rows));
        } else if line.contains("RowId") {
            if let Some((path, rows)) = current.take() {
                let timelines: Vec<String> = {
                    let mut t: Vec<String> = line
                        .split('┆')
                        .map(|c| c.trim_matches(|ch: char| ch.is_whitespace() || ch == '│'))
                        .filter(|c| !c.is_empty() && *c != "RowId" && !c.contains(':'))
                        .map(str::to_string)
                        .collect();
                    t.sort();
                    t
                };
                out.entry(path).or_default().chunks.push((timelines, rows));
            }
        }
    }
    out
}

/// `rerun rrd print -vv FILE`: a recording's content, chunk by chunk.
pub fn print_rrd(file: &Path) -> String {
    let home = file.with_extension("rerun-home");
    run(
        rerun_cmd(&home).args(["rrd", "print", "-vv"]).arg(file),
        "rerun rrd print",
    )
}

/// `rerun rrd verify FILE` passes, and `rerun rrd print -vv FILE` gives its content.
pub fn read_rrd(file: &Path) -> String {
    let home = file.with_extension("rerun-home");
    let _ = run(
        rerun_cmd(&home).args(["analytics", "disable"]),
        "rerun analytics disable",
    );
    run(
        rerun_cmd(&home).args(["rrd", "verify"]).arg(file),
        "rerun rrd verify",
    );
    print_rrd(file)
}
