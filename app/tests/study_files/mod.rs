//! What the study tests share: the binary, a fresh scratch folder, a run that must succeed, and
//! `study.parquet` read back against `study.csv`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `lopin` binary under test.
pub fn lopin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lopin"))
}

/// A fresh (removed) folder `lopin-{prefix}-{name}-PID` in the temporary directory.
pub fn scratch(prefix: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lopin-{prefix}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Runs `c`, which must succeed; its output.
pub fn succeeds(c: &mut Command) -> Output {
    let out = c.output().expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// study.parquet holds the rows of study.csv, column by column: the same names and order, the
/// same numbers (the CSV's text round-trips each f64 exactly), nulls where the CSV is empty.
pub fn parquet_matches_csv(dir: &Path) {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;
    let text = std::fs::read_to_string(dir.join("study.csv")).expect("study.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let mut csv: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    csv.sort_by_key(|r| r[0].parse::<usize>().expect("index"));
    let file = std::fs::File::open(dir.join("study.parquet")).expect("study.parquet");
    let reader = SerializedFileReader::new(file).expect("a Parquet file");
    let table: Vec<parquet::record::Row> = reader
        .get_row_iter(None)
        .expect("rows")
        .map(|r| r.expect("row"))
        .collect();
    assert_eq!(table.len(), csv.len());
    for (row, line) in table.iter().zip(&csv) {
        let cells: Vec<(&String, &Field)> = row.get_column_iter().collect();
        assert_eq!(cells.len(), header.len());
        for ((name, field), (h, text)) in cells.iter().zip(header.iter().zip(line)) {
            assert_eq!(name.as_str(), *h);
            let same = match field {
                Field::Null => text.is_empty(),
                Field::Long(x) => text.parse::<i64>() == Ok(*x),
                Field::Double(x) => text.parse::<f64>() == Ok(*x),
                Field::Bool(x) => text.parse::<bool>() == Ok(*x),
                Field::Str(x) => x == text,
                other => panic!("{h}: unexpected Parquet value {other:?}"),
            };
            assert!(same, "{h}: Parquet {field:?} against CSV `{text}`");
        }
    }
}
