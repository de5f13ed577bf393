//! ARCHITECTURE.md against the tree: every module file of every crate and every integration
//! test file has its line in its crate's section, so that a module added without saying what it
//! holds fails here. A module is described by a row of its own (`` `scene::validate` ``), by a
//! row of its parent that names it (`` `export` `` naming `` `export::vtu` ``), or, for a folder
//! module, by the rows of its submodules; the web crate's rows name files. The manifests keep the
//! two wings apart: the model names no Lopin crate, the reference the model and not the solver.
//! The scene pipeline imports one way and is entered through one door (`scene::open`).

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

/// The code of a Rust file before its unit tests (`#[cfg(test)]`), comments left out.
fn code_of(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("source");
    let code = text.split("#[cfg(test)]").next().unwrap_or(&text);
    code.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The scene modules (`model/src/scene/NAME.rs` or `NAME/`) and the other scene modules each
/// one names outside its tests (`crate::scene::X`, `super::X`, `scene::{X, …}`).
fn scene_imports() -> Vec<(String, Vec<String>)> {
    let dir = root().join("model/src/scene");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("scene")
        .filter_map(|e| {
            let path = e.ok()?.path();
            let stem = path.file_stem()?.to_string_lossy().to_string();
            (stem != "mod" && (path.is_dir() || path.extension()? == "rs")).then_some(stem)
        })
        .collect();
    names.sort();
    let mut out = Vec::new();
    for name in &names {
        let file = dir.join(format!("{name}.rs"));
        let code = if file.exists() {
            code_of(&file)
        } else {
            let mut all = String::new();
            for e in std::fs::read_dir(dir.join(name)).expect("folder") {
                all += &code_of(&e.expect("entry").path());
            }
            all
        };
        let named: Vec<String> = names
            .iter()
            .filter(|other| *other != name)
            .filter(|other| {
                [
                    format!("crate::scene::{other}"),
                    format!("super::{other}"),
                    format!("scene::{{{other}"),
                    format!(", {other}}}"),
                    format!(", {other},"),
                ]
                .iter()
                .any(|p| code.contains(p.as_str()))
            })
            .cloned()
            .collect();
        out.push((name.clone(), named));
    }
    out
}

/// The scene pipeline has no import circle: the schema and the generators' tables below the
/// checks, the checks below the build, the front door on top.
#[test]
fn the_scene_modules_import_one_way() {
    let graph = scene_imports();
    let index = |n: &str| graph.iter().position(|(m, _)| m == n).expect("module");
    // depth-first search for a cycle, reporting its path
    fn visit(
        at: usize,
        graph: &[(String, Vec<String>)],
        index: &dyn Fn(&str) -> usize,
        state: &mut [u8],
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state[at] = 1;
        path.push(graph[at].0.clone());
        for next in &graph[at].1 {
            let j = index(next);
            if state[j] == 1 {
                let mut cycle = path.clone();
                cycle.push(next.clone());
                return Some(cycle);
            }
            if state[j] == 0 {
                if let Some(c) = visit(j, graph, index, state, path) {
                    return Some(c);
                }
            }
        }
        path.pop();
        state[at] = 2;
        None
    }
    let mut state = vec![0u8; graph.len()];
    for start in 0..graph.len() {
        if state[start] == 0 {
            let cycle = visit(start, &graph, &index, &mut state, &mut Vec::new());
            assert!(
                cycle.is_none(),
                "scene modules import in a circle: {cycle:?}"
            );
        }
    }
    let open = &graph[index("open")].1;
    for stage in ["reading", "validate", "admission", "build", "granular"] {
        assert!(open.contains(&stage.to_string()), "open: {open:?}");
    }
}

/// Every file of the workspace's crates (outside `target/`) under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let path = e.path();
        let name = path.file_name().map(|n| n.to_string_lossy().to_string());
        if path.is_dir() && name.as_deref() != Some("target") {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            out.push(path);
        }
    }
}

/// One front door: the build step of the scene pipeline is called from `scene::open` only, in
/// every crate, test and example.
#[test]
fn only_the_front_door_builds_a_scene() {
    let root = root();
    let mut files = Vec::new();
    for dir in [
        "model",
        "core",
        "reference",
        "judge",
        "explorer",
        "app",
        "web",
        "tests",
    ] {
        rust_files(&root.join(dir), &mut files);
    }
    let call = concat!("build_", "expanded(");
    let callers: Vec<String> = files
        .iter()
        .filter(|f| {
            let text = std::fs::read_to_string(f).expect("source");
            text.contains(call) && !f.ends_with("scene/build/mod.rs")
        })
        .map(|f| {
            f.strip_prefix(&root)
                .expect("in root")
                .display()
                .to_string()
        })
        .collect();
    assert_eq!(callers, ["model/src/scene/open.rs"], "{callers:?}");
}
