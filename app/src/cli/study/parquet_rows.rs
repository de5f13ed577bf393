//! `study.parquet`: the rows of `study.csv` as one typed Parquet file (for pandas, polars,
//! DuckDB, Spark), written at the end of a study, beside the CSV that stays the crash-safe
//! record (Parquet cannot be appended to). Same columns and names as the CSV: counts as INT64,
//! parameters, distances, residuals, η, times and quantities as DOUBLE, `converged` as BOOLEAN,
//! `start_change` ("k-l", the parallelogram's other two configurations) as a UTF-8 string; a
//! column the CSV leaves empty on some rows (a cold start's `start`, `cold_iterations` without
//! `--compare-cold`) is OPTIONAL and null there; `checksum`, the row's checksum in the CSV, as
//! a UTF-8 string. Written from the rows kept after their checks ([`super::rows`]). One row
//! group, uncompressed.

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

use super::rows::{header, row};

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

/// The columns of the rows `outcomes` (in the order given), in the order of the CSV header.
fn columns(design: &Design, outcomes: &[Outcome]) -> Vec<Column> {
    let int = |f: &dyn Fn(&Outcome) -> Option<i64>| Column::Int(outcomes.iter().map(f).collect());
    let dbl =
        |f: &dyn Fn(&Outcome) -> Option<f64>| Column::Double(outcomes.iter().map(f).collect());
    let mut c = vec![
        int(&|o| Some(count(o.index))),
        int(&|o| Some(count(o.chain))),
        int(&|o| Some(count(o.position))),
    ];
    for d in 0..design.targets.len() {
        c.push(dbl(&|o| Some(design.points[o.index][d])));
    }
    c.extend([
        int(&|o| o.start.map(count)),
        dbl(&|o| o.start_distance),
        Column::Text(
            outcomes
                .iter()
                .map(|o| o.start_change.map(|(k, l)| format!("{k}-{l}")))
                .collect(),
        ),
        dbl(&|o| o.start_residual.map(|r| r.0)),
        dbl(&|o| o.start_residual.map(|r| r.1)),
        int(&|o| Some(count(o.iterations))),
        dbl(&|o| Some(o.eta)),
        Column::Bool(outcomes.iter().map(|o| Some(o.converged)).collect()),
        dbl(&|o| Some(o.wall_s)),
        int(&|o| o.cold_iterations.map(count)),
    ]);
    for k in 0..Quantities::NAMES.len() {
        c.push(dbl(&|o| Some(o.quantities.values()[k])));
    }
    c.push(Column::Text(
        outcomes.iter().map(|o| row(design, o).pop()).collect(),
    ));
    c
}

/// Writes `outcomes` (in the order given) to `path`, the columns named by the CSV header.
pub fn write(path: &FsPath, design: &Design, outcomes: &[Outcome]) -> anyhow::Result<()> {
    let labels: Vec<String> = design.targets.iter().map(|t| t.label.clone()).collect();
    let names = header(&labels);
    let columns = columns(design, outcomes);
    anyhow::ensure!(
        names.len() == columns.len(),
        "study.parquet: {} columns for {} CSV headers",
        columns.len(),
        names.len()
    );
    let optional: Vec<bool> = columns.iter().map(Column::has_nulls).collect();
    let fields = names
        .iter()
        .zip(&columns)
        .zip(&optional)
        .map(|((name, col), &optional)| {
            let repetition = if optional {
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
    for (col, &optional) in columns.iter().zip(&optional) {
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
