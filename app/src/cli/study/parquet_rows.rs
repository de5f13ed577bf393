//! `study.parquet`: the rows of `study.csv` as one typed Parquet file (for pandas, polars,
//! DuckDB, Spark), written at the end of a study, beside the CSV that stays the crash-safe
//! record (Parquet cannot be appended to). Same columns and names as the CSV: counts as INT64,
//! parameters, distances, residuals, η, times and quantities as DOUBLE, `converged` as BOOLEAN,
//! `start_change` ("k-l", the parallelogram's other two configurations) as a UTF-8 string; a
//! column the CSV leaves empty on some rows (a cold start's `start`, `cold_iterations` without
//! `--compare-cold`) is OPTIONAL and null there. One row group, uncompressed.

use std::fs::File;
use std::path::Path as FsPath;
use std::sync::Arc;

use lopin_core::study::runner::Outcome;
use lopin_core::study::{Design, Quantities};
use parquet::basic::{LogicalType, Repetition, Type as Physical};
use parquet::data_type::{BoolType, ByteArray, ByteArrayType, DataType, DoubleType, Int64Type};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::{SerializedColumnWriter, SerializedFileWriter};
use parquet::schema::types::Type;

/// One column's values, None where the row has none.
enum Column {
    Int(Vec<Option<i64>>),
    Double(Vec<Option<f64>>),
    Bool(Vec<Option<bool>>),
    Text(Vec<Option<String>>),
}

impl Column {
    fn physical(&self) -> Physical {
        match self {
            Self::Int(_) => Physical::INT64,
            Self::Double(_) => Physical::DOUBLE,
            Self::Bool(_) => Physical::BOOLEAN,
            Self::Text(_) => Physical::BYTE_ARRAY,
        }
    }

    /// Whether some row lacks a value.
    fn has_nulls(&self) -> bool {
        match self {
            Self::Int(v) => v.iter().any(Option::is_none),
            Self::Double(v) => v.iter().any(Option::is_none),
            Self::Bool(v) => v.iter().any(Option::is_none),
            Self::Text(v) => v.iter().any(Option::is_none),
        }
    }
}

/// Writes one column: the present values and, for an OPTIONAL column, the definition levels
/// (1 present, 0 null).
fn put<T: DataType>(
    w: &mut SerializedColumnWriter<'_>,
    v: &[Option<T::T>],
    optional: bool,
) -> parquet::errors::Result<()> {
    let values: Vec<T::T> = v.iter().flatten().cloned().collect();
    let levels: Option<Vec<i16>> =
        optional.then(|| v.iter().map(|x| i16::from(x.is_some())).collect());
    w.typed::<T>()
        .write_batch(&values, levels.as_deref(), None)?;
    Ok(())
}

fn count(x: usize) -> i64 {
    i64::try_from(x).unwrap_or(i64::MAX)
}

/// The columns of the rows `outcomes` (in the order given), named as in `study.csv`.
fn columns(design: &Design, outcomes: &[Outcome]) -> Vec<(String, Column)> {
    let int = |f: &dyn Fn(&Outcome) -> Option<i64>| Column::Int(outcomes.iter().map(f).collect());
    let dbl =
        |f: &dyn Fn(&Outcome) -> Option<f64>| Column::Double(outcomes.iter().map(f).collect());
    let mut c: Vec<(String, Column)> = vec![
        ("index".into(), int(&|o| Some(count(o.index)))),
        ("chain".into(), int(&|o| Some(count(o.chain)))),
        ("position".into(), int(&|o| Some(count(o.position)))),
    ];
    for (d, t) in design.targets.iter().enumerate() {
        c.push((t.label.clone(), dbl(&|o| Some(design.points[o.index][d]))));
    }
    c.extend([
        ("start".into(), int(&|o| o.start.map(count))),
        ("start_distance".into(), dbl(&|o| o.start_distance)),
        (
            "start_change".into(),
            Column::Text(
                outcomes
                    .iter()
                    .map(|o| o.start_change.map(|(k, l)| format!("{k}-{l}")))
                    .collect(),
            ),
        ),
        (
            "start_residual_nearest".into(),
            dbl(&|o| o.start_residual.map(|r| r.0)),
        ),
        (
            "start_residual".into(),
            dbl(&|o| o.start_residual.map(|r| r.1)),
        ),
        ("iterations".into(), int(&|o| Some(count(o.iterations)))),
        ("eta".into(), dbl(&|o| Some(o.eta))),
        (
            "converged".into(),
            Column::Bool(outcomes.iter().map(|o| Some(o.converged)).collect()),
        ),
        ("wall_s".into(), dbl(&|o| Some(o.wall_s))),
        (
            "cold_iterations".into(),
            int(&|o| o.cold_iterations.map(count)),
        ),
    ]);
    for (k, (name, _)) in Quantities::NAMES.iter().enumerate() {
        c.push((name.to_string(), dbl(&|o| Some(o.quantities.values()[k]))));
    }
    c
}

/// Writes `outcomes` (in the order given) to `path`.
pub fn write(path: &FsPath, design: &Design, outcomes: &[Outcome]) -> anyhow::Result<()> {
    let columns = columns(design, outcomes);
    let fields = columns
        .iter()
        .map(|(name, col)| {
            let repetition = if col.has_nulls() {
                Repetition::OPTIONAL
            } else {
                Repetition::REQUIRED
            };
            let mut b =
                Type::primitive_type_builder(name, col.physical()).with_repetition(repetition);
            if let Column::Text(_) = col {
                b = b.with_logical_type(Some(LogicalType::String));
            }
            Ok(Arc::new(b.build()?))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let schema = Arc::new(
        Type::group_type_builder("study")
            .with_fields(fields)
            .build()?,
    );
    let file = File::create(path)?;
    let mut writer =
        SerializedFileWriter::new(file, schema, Arc::new(WriterProperties::builder().build()))?;
    let mut group = writer.next_row_group()?;
    for (_, col) in &columns {
        let optional = col.has_nulls();
        let Some(mut w) = group.next_column()? else {
            anyhow::bail!("the Parquet writer has fewer columns than the schema");
        };
        match col {
            Column::Int(v) => put::<Int64Type>(&mut w, v, optional)?,
            Column::Double(v) => put::<DoubleType>(&mut w, v, optional)?,
            Column::Bool(v) => put::<BoolType>(&mut w, v, optional)?,
            Column::Text(v) => {
                let bytes: Vec<Option<ByteArray>> = v
                    .iter()
                    .map(|s| s.as_ref().map(|s| ByteArray::from(s.as_bytes().to_vec())))
                    .collect();
                put::<ByteArrayType>(&mut w, &bytes, optional)?;
            }
        }
        w.close()?;
    }
    group.close()?;
    writer.close()?;
    Ok(())
}
