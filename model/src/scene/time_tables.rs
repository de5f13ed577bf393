//! The tables of a scene's time functions read from CSV files beside the scene file
//! (`table_file`, METHOD §5 boundary data): one `t,value` pair per line, a header line and `#`
//! comments skipped; each file read into its component's `table` when the scene file is read, so
//! the scene as recorded carries its points. Errors name the scene, the field, the file, the
//! line and the reason.

use crate::error::{LopinError, Result};
use crate::scene::mesh_bodies::mesh_path;
use crate::scene::spec::SceneSpec;

/// Reads every `table_file` of `spec` (read from `source`) into its `table`.
pub fn read_files(spec: &mut SceneSpec, source: &str) -> Result<()> {
    for (i, bc) in spec.boundaries.iter_mut().enumerate() {
        for (axis, c) in [("x", &mut bc.x), ("y", &mut bc.y), ("z", &mut bc.z)] {
            let Some(c) = c.as_mut() else { continue };
            let Some(file) = c.table_file.clone() else {
                continue;
            };
            let field = format!("boundary[{i}].{axis}.table_file");
            if c.table.is_some() {
                return Err(LopinError::scene(
                    source,
                    field,
                    "give the points either inline (`table`) or in a file (`table_file`), not both",
                ));
            }
            let path = mesh_path(source, &file);
            let text = std::fs::read_to_string(&path).map_err(|e| {
                LopinError::scene(source, &field, format!("{}: {e}", path.display()))
            })?;
            let points = parse(&text).map_err(|e| {
                LopinError::scene(source, &field, format!("{}: {e}", path.display()))
            })?;
            c.table = Some(points);
        }
    }
    Ok(())
}

/// The points of a CSV text: `t,value` per line (`;` or whitespace also separate), blank lines
/// and `#` comments skipped, and a first line that is not numbers taken as a header.
pub fn parse(text: &str) -> std::result::Result<Vec<[f64; 2]>, String> {
    let mut points = Vec::new();
    let mut first = true;
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|f| !f.is_empty())
            .collect();
        let numbers: Vec<Option<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
        let header = first && numbers.iter().any(Option::is_none);
        first = false;
        if header {
            continue;
        }
        match numbers[..] {
            [Some(t), Some(v)] => points.push([t, v]),
            _ => {
                return Err(format!(
                    "line {}: expected two numbers `t,value`, got `{line}`",
                    n + 1
                ))
            }
        }
    }
    if points.is_empty() {
        return Err("no `t,value` line".into());
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_tables_read_with_a_header_comments_and_any_separator() {
        let text = "time_s,velocity_m_s\n# measured\n0, 0\n1e-3;0.5\n\n2e-3 1.0 # peak\n";
        assert_eq!(parse(text), Ok(vec![[0.0, 0.0], [1e-3, 0.5], [2e-3, 1.0]]));
        let e = parse("t,v\n0,0\n1e-3,fast\n").expect_err("a word");
        assert_eq!(e, "line 3: expected two numbers `t,value`, got `1e-3,fast`");
        let e = parse("0,1,2\n").expect_err("three numbers");
        assert!(e.starts_with("line 1:"), "{e}");
        assert_eq!(parse("t,v\n"), Err("no `t,value` line".into()));
    }
}
