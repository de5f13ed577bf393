//! The user guide (`docs/`, an mdBook) holds: its generated references are what `lopin docs`
//! prints now (so a scene key or a flag added without being documented fails here), every
//! relative link of the book and the README reaches a file and, with `#anchor`, a heading of
//! it, every page of `docs/src` is in the book's table of contents, and no page speaks of issue
//! numbers. The tutorials' shell blocks run in `scripts/tutorials.py` (the README's test
//! command), which needs the whole toolchain.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the workspace")
        .to_path_buf()
}

fn lopin_docs(what: &str) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_lopin"))
        .args(["docs", what])
        .output()
        .expect("lopin runs");
    assert!(
        out.status.success(),
        "lopin docs {what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

/// Asserts the stored page is what `lopin docs WHAT` prints now, and returns that text.
fn assert_page_is(page: &str, what: &str) -> String {
    let path = root().join("docs/src/reference").join(page);
    let stored = std::fs::read_to_string(&path).unwrap_or_default();
    let now = lopin_docs(what);
    assert!(
        stored == now,
        "{} is not what `lopin docs {what}` prints now: regenerate it with\n    lopin docs {what} > \
         docs/src/reference/{page}\nfirst difference at line {}",
        path.display(),
        stored
            .lines()
            .zip(now.lines())
            .position(|(a, b)| a != b)
            .map_or(stored.lines().count().min(now.lines().count()) + 1, |l| l + 1)
    );
    now
}

#[test]
fn the_scene_reference_is_generated_from_the_schema() {
    let page = assert_page_is("scene.md", "scene");
    // a key of every table, with its unit and the validator's own message
    for row in [
        "| `dt` | number | s | required |",
        "| `young` | number | Pa | required |",
        "| `friction` | number | — | absent | [0, 10] |",
        "| `ramp` | one of `cosine`, `linear`, `step` |",
        "| `grains` | integer | — | required | 1 to 500 |",
    ] {
        assert!(page.contains(row), "no row `{row}` in the scene reference");
    }
    assert!(page.contains(
        "`scene.toml: field 'interface[0].friction': a friction coefficient lies in [0, 10], got 11.0`"
    ));
}

#[test]
fn the_schema_lists_every_table() {
    let schema: serde_json::Value =
        serde_json::from_str(&lopin_docs("schema")).expect("the schema is JSON");
    let props = schema["properties"].as_object().expect("properties");
    for key in [
        "name",
        "time",
        "solver",
        "material",
        "body",
        "mesh_body",
        "interface",
        "boundary",
        "zone",
        "granular",
        "granular_poly",
    ] {
        assert!(props.contains_key(key), "the schema has no `{key}`");
    }
    assert_eq!(
        schema["additionalProperties"],
        serde_json::Value::Bool(false)
    );
}

#[test]
fn the_command_line_reference_is_generated_from_clap() {
    let page = assert_page_is("cli.md", "cli");
    for heading in [
        "## `lopin run`",
        "## `lopin study`",
        "## `lopin mesh info`",
        "## `lopin docs`",
    ] {
        assert!(page.contains(heading), "no {heading}");
    }
    assert!(page.contains("| `--tol` |"));
}

/// The Markdown files of the book and the README.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).expect("docs/src") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "md") {
                out.push(p);
            }
        }
    }
    let mut out = vec![root().join("README.md")];
    walk(&root().join("docs/src"), &mut out);
    out.sort();
    out
}

/// The anchor mdBook (and GitHub) gives a heading: lower case, punctuation dropped, spaces to
/// hyphens.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a page's headings (outside code blocks).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            code = !code;
        } else if !code && line.starts_with('#') {
            out.insert(anchor(line.trim_start_matches('#')));
        }
    }
    out
}

/// The targets of a page's Markdown links and images that are not web addresses.
fn local_links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            code = !code;
            continue;
        }
        if code {
            continue;
        }
        let mut rest = line;
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else { break };
            let target = &after[..end];
            if !target.contains("://") && !target.starts_with("mailto:") {
                out.push(target.to_string());
            }
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_link_of_the_guide_and_the_readme_resolves() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("page");
        for link in local_links(&text) {
            checked += 1;
            let (file, frag) = link.split_once('#').unwrap_or((&link, ""));
            let target = if file.is_empty() {
                page.clone()
            } else {
                page.parent().expect("a folder").join(file)
            };
            if !target.exists() {
                broken.push(format!(
                    "{}: `{link}`: no file {}",
                    page.display(),
                    target.display()
                ));
                continue;
            }
            if !frag.is_empty() && target.extension().is_some_and(|x| x == "md") {
                let there = std::fs::read_to_string(&target).expect("target");
                if !anchors(&there).contains(frag) {
                    broken.push(format!(
                        "{}: `{link}`: no heading `#{frag}`",
                        page.display()
                    ));
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} links");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn every_page_is_in_the_table_of_contents() {
    let src = root().join("docs/src");
    let summary = std::fs::read_to_string(src.join("SUMMARY.md")).expect("SUMMARY.md");
    let listed: BTreeSet<String> = local_links(&summary).into_iter().collect();
    // the book's pages: all but the README
    for page in pages() {
        let Ok(rel) = page.strip_prefix(&src) else {
            continue;
        };
        let rel = rel.to_string_lossy().to_string();
        if rel != "SUMMARY.md" {
            assert!(listed.contains(&rel), "docs/src/{rel} is not in SUMMARY.md");
        }
    }
}

#[test]
fn no_page_speaks_of_issue_numbers() {
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("page");
        for (n, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            let tagged = lower
                .match_indices("issue ")
                .any(|(i, _)| lower[i + 6..].starts_with(|c: char| c.is_ascii_digit()));
            assert!(!tagged, "{}:{}: {line}", page.display(), n + 1);
        }
    }
}
