//! ARCHITECTURE.md against the tree: every module file of every crate and every integration
//! test file has its line in its crate's section, so that a module added without saying what it
//! holds fails here. A module is described by a row of its own (`` `scene::validate` ``), by a
//! row of its parent that names it (`` `export` `` naming `` `export::vtu` ``), or, for a folder
//! module, by the rows of its submodules; the web crate's rows name files. The manifests keep the
//! two wings apart: the model names no Lopin crate, the reference the model and not the solver.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace")
        .to_path_buf()
}

/// The text of the section whose heading starts with `heading`, up to the next `## `.
fn section<'a>(doc: &'a str, heading: &str) -> &'a str {
    let start = doc
        .find(heading)
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has no section `{heading}`"));
    let rest = &doc[start + heading.len()..];
    let end = rest.find("\n## ").map_or(rest.len(), |e| e);
    &rest[..end]
}

/// The rows of a section: the first backticked name of each table line, and the line.
fn rows(section: &str) -> Vec<(String, String)> {
    section
        .lines()
        .filter_map(|l| {
            let cell = l.strip_prefix("| `")?;
            let name = &cell[..cell.find('`')?];
            Some((name.to_string(), l.to_string()))
        })
        .collect()
}

/// Module paths (`a::b`) of the `.rs` files under `src`, with whether each is a folder module
/// (`mod.rs`); the crate root (`lib.rs`, `main.rs`) left out.
fn modules(src: &Path) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("read_dir") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = path
                .strip_prefix(src)
                .expect("under src")
                .with_extension("");
            let mut parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().to_string())
                .collect();
            let folder = parts.last().is_some_and(|p| p == "mod");
            if folder {
                parts.pop();
            }
            let name = parts.join("::");
            if name != "lib" && name != "main" && !name.is_empty() {
                out.push((name, folder));
            }
        }
    }
    out.sort();
    out
}

/// Whether module `m` is described by the rows.
fn described(m: &str, folder: bool, rows: &[(String, String)]) -> bool {
    let last = m.rsplit("::").next().unwrap_or(m);
    rows.iter().any(|(name, line)| {
        name == m
            || (m.starts_with(&format!("{name}::"))
                && (line.contains(&format!("`{last}`")) || line.contains(&format!("`{m}`"))))
            || (folder && name.starts_with(&format!("{m}::")))
    })
}

/// The top-level integration test files of a crate (`tests/NAME.rs`).
fn test_files(dir: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut out: Vec<String> = entries
        .filter_map(|e| {
            let path = e.ok()?.path();
            (path.extension()? == "rs").then(|| {
                format!(
                    "tests/{}",
                    path.file_name().expect("name").to_string_lossy()
                )
            })
        })
        .collect();
    out.sort();
    out
}

#[test]
fn every_module_and_test_file_has_its_line_in_architecture_md() {
    let root = root();
    let doc = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let mut missing = Vec::new();
    for (dir, heading) in [
        ("model", "## `lopin-model` modules"),
        ("core", "## `lopin-core` modules"),
        ("reference", "## `lopin-reference` modules"),
        ("judge", "## `lopin-judge` modules"),
        ("explorer", "## `lopin-explorer` modules"),
        ("app", "## `lopin` (app) modules"),
        ("tests", "## `lopin-tests`"),
    ] {
        let rows = rows(section(&doc, heading));
        for (m, folder) in modules(&root.join(dir).join("src")) {
            if !described(&m, folder, &rows) {
                missing.push(format!("{dir}: module `{m}`"));
            }
        }
        for t in test_files(&root.join(dir).join("tests")) {
            if !rows.iter().any(|(name, _)| name == &t) {
                missing.push(format!("{dir}: `{t}`"));
            }
        }
    }
    let web = rows(section(&doc, "## `lopin-web` modules"));
    for (m, _) in modules(&root.join("web/src")) {
        let file = format!("web/src/{}.rs", m.replace("::", "/"));
        if !web.iter().any(|(name, _)| name == &file) {
            missing.push(format!("web: `{file}`"));
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md has no line for:\n  {}",
        missing.join("\n  ")
    );
}

/// The dependencies a manifest's `[dependencies]` table names.
fn dependencies(manifest: &str) -> Vec<String> {
    let text = std::fs::read_to_string(root().join(manifest)).expect("manifest");
    let table = text
        .split("\n[dependencies]\n")
        .nth(1)
        .expect("a [dependencies] table");
    let table = table.split("\n[").next().unwrap_or(table);
    table
        .lines()
        .filter_map(|l| {
            let name = l.split(['=', '.', ' ']).next()?.trim();
            (!name.is_empty() && !name.starts_with('#')).then(|| name.to_string())
        })
        .collect()
}

/// The two wings: the model knows no solver, the reference knows the model and not the LATIN
/// solver, the judges see both.
#[test]
fn the_reference_depends_on_the_model_and_not_on_the_solver() {
    let model = dependencies("model/Cargo.toml");
    assert!(!model.iter().any(|d| d.starts_with("lopin")), "{model:?}");
    let reference = dependencies("reference/Cargo.toml");
    assert!(
        reference.contains(&"lopin-model".to_string()),
        "{reference:?}"
    );
    assert!(
        !reference.contains(&"lopin-core".to_string()),
        "{reference:?}"
    );
    let judge = dependencies("judge/Cargo.toml");
    for d in ["lopin-core", "lopin-reference"] {
        assert!(judge.contains(&d.to_string()), "{judge:?}");
    }
    let core = dependencies("core/Cargo.toml");
    assert!(core.contains(&"lopin-model".to_string()), "{core:?}");
    assert!(!core.contains(&"lopin-reference".to_string()), "{core:?}");
}
