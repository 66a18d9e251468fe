//! A study's [`Table`] as Apache Parquet (feature `parquet`), with the arrow-rs `parquet`
//! crate: a column `case_index` (int64), one nullable `double` column per value column (null
//! where a failed case has no value, so that DuckDB's `avg` and polars' `mean` skip failed
//! cases), and `error_kind` and `error`, nullable UTF-8 strings (null for a case that
//! succeeded). Compressed with Snappy
//! (pure Rust), in row groups of [`ROW_GROUP`] rows; each column's unit and description are
//! in the file's key-value metadata (`<column>.unit`, `<column>.description`), which pyarrow
//! reads with `pq.read_metadata(path).metadata`. pandas (`read_parquet`) and polars
//! (`read_parquet`, or `scan_parquet("results/*.parquet")` for a sharded study's files) read
//! the tables as they are.
//!
//! [`Writer`] streams a table of any length a block of rows at a time, in the memory of one
//! row group; its bytes depend only on the rows, not on how they were split into blocks, so
//! a study's shards joined give the file one task would write.
//!
//! ```no_run
//! use hamel::{Ensemble, Table};
//!
//! let table = Ensemble::new(4).table(vec!["square".into()], |i| Ok(vec![(i * i) as f64]))?;
//! hamel::ensemble::write_complete("squares.parquet", |file| {
//!     hamel::parquet::write(&table, file, "squares.parquet", &[])
//! })?;
//! assert_eq!(hamel::parquet::read("squares.parquet")?, table);
//! # Ok::<(), hamel::Error>(())
//! ```

use std::io::Write;
use std::path::Path;
use std::sync::Arc;

use ::parquet::basic::{Compression, LogicalType, Repetition, Type as Physical};
use ::parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use ::parquet::errors::ParquetError;
use ::parquet::file::metadata::KeyValue;
use ::parquet::file::properties::WriterProperties;
use ::parquet::file::reader::{FileReader, SerializedFileReader};
use ::parquet::file::writer::{
    SerializedColumnWriter, SerializedFileWriter, SerializedRowGroupWriter,
};
use ::parquet::record::{Field, RowAccessor};
use ::parquet::schema::types::Type;

use crate::ensemble::{CASE_COLUMN, CaseError};
use crate::{Error, Table};

/// Rows per row group: a study's rows are buffered until a group is full, so this bounds
/// the writer's memory (about 8 bytes a value, a few MiB for tens of columns).
pub const ROW_GROUP: usize = 65_536;

/// What a column is: its unit and description, for the file's metadata.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColumnInfo {
    pub name: String,
    pub unit: String,
    pub description: String,
}

/// The schema of a table with these value columns.
fn schema(names: &[String]) -> Result<Type, ParquetError> {
    let required = |name: &str, physical| {
        Type::primitive_type_builder(name, physical)
            .with_repetition(Repetition::REQUIRED)
            .build()
            .map(Arc::new)
    };
    let text = |name: &str| {
        Type::primitive_type_builder(name, Physical::BYTE_ARRAY)
            .with_repetition(Repetition::OPTIONAL)
            .with_logical_type(Some(LogicalType::String))
            .build()
            .map(Arc::new)
    };
    let optional = |name: &str, physical| {
        Type::primitive_type_builder(name, physical)
            .with_repetition(Repetition::OPTIONAL)
            .build()
            .map(Arc::new)
    };
    let mut fields = vec![required(CASE_COLUMN, Physical::INT64)?];
    for name in names {
        fields.push(optional(name, Physical::DOUBLE)?);
    }
    fields.push(text("error_kind")?);
    fields.push(text("error")?);
    Type::group_type_builder("study")
        .with_fields(fields)
        .build()
}

/// The file's key-value metadata: each described column's unit and description.
fn metadata(columns: &[ColumnInfo]) -> Vec<KeyValue> {
    let mut all = vec![
        KeyValue::new(
            format!("{CASE_COLUMN}.description"),
            "the case's row in the parameter table".to_string(),
        ),
        KeyValue::new(
            "error_kind.description".into(),
            "why the case failed, in a word (empty if it succeeded)".to_string(),
        ),
        KeyValue::new(
            "error.description".into(),
            "why the case failed".to_string(),
        ),
    ];
    for c in columns {
        if !c.unit.is_empty() {
            all.push(KeyValue::new(format!("{}.unit", c.name), c.unit.clone()));
        }
        if !c.description.is_empty() {
            all.push(KeyValue::new(
                format!("{}.description", c.name),
                c.description.clone(),
            ));
        }
    }
    all
}

/// A study table's Parquet file written a block of rows at a time.
pub struct Writer<W: Write + Send> {
    writer: SerializedFileWriter<W>,
    names: Vec<String>,
    /// The rows of the row group being filled.
    buffer: Table,
}

impl<W: Write + Send> Writer<W> {
    /// A writer of a table with the value columns `names` into `w`, the units and
    /// descriptions of `columns` in its metadata.
    pub fn new(w: W, names: &[String], columns: &[ColumnInfo]) -> Result<Writer<W>, ParquetError> {
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .set_key_value_metadata(Some(metadata(columns)))
            .build();
        let writer = SerializedFileWriter::new(w, Arc::new(schema(names)?), Arc::new(properties))?;
        let buffer =
            Table::new(names.to_vec()).map_err(|e| ParquetError::General(e.to_string()))?;
        Ok(Writer {
            writer,
            names: names.to_vec(),
            buffer,
        })
    }

    /// Adds `block`'s rows (its columns must be the writer's); full row groups are written.
    pub fn write(&mut self, block: &Table) -> Result<(), ParquetError> {
        let general = |e: Error| ParquetError::General(e.to_string());
        for i in 0..block.len() {
            let values = block.row(i).unwrap_or_default();
            let error = block.errors()[i].clone();
            self.buffer
                .push_row(block.cases()[i], values, error)
                .map_err(general)?;
            if self.buffer.len() == ROW_GROUP {
                self.flush()?;
            }
        }
        Ok(())
    }

    /// Writes the last row group and the footer, and returns the underlying writer.
    pub fn finish(mut self) -> Result<W, ParquetError> {
        if !self.buffer.is_empty() {
            self.flush()?;
        }
        self.writer.into_inner()
    }

    /// Writes the buffered rows as one row group.
    fn flush(&mut self) -> Result<(), ParquetError> {
        let empty =
            Table::new(self.names.clone()).map_err(|e| ParquetError::General(e.to_string()))?;
        let rows = std::mem::replace(&mut self.buffer, empty);
        let mut group = self.writer.next_row_group()?;
        let cases: Vec<i64> = rows.cases().iter().map(|&c| c as i64).collect();
        let mut column = next_column(&mut group)?;
        column
            .typed::<Int64Type>()
            .write_batch(&cases, None, None)?;
        column.close()?;
        for name in &self.names {
            let values = rows.column(name).unwrap_or_default();
            // Definition level 0: null, a value a failed case could not compute (NaN); 1: the
            // value, which a successful case's NaN is.
            let present = |i: usize| rows.errors()[i].is_none() || !values[i].is_nan();
            let levels: Vec<i16> = (0..values.len()).map(|i| i16::from(present(i))).collect();
            let written: Vec<f64> = (0..values.len())
                .filter(|&i| present(i))
                .map(|i| values[i])
                .collect();
            let mut column = next_column(&mut group)?;
            column
                .typed::<DoubleType>()
                .write_batch(&written, Some(&levels), None)?;
            column.close()?;
        }
        // Definition level 1: the text is there; 0: null, the case succeeded.
        let levels: Vec<i16> = rows
            .errors()
            .iter()
            .map(|e| i16::from(e.is_some()))
            .collect();
        for part in [
            |e: &CaseError| e.kind.clone(),
            |e: &CaseError| e.message.clone(),
        ] {
            let texts: Vec<ByteArray> = rows
                .errors()
                .iter()
                .flatten()
                .map(|e| ByteArray::from(part(e).as_str()))
                .collect();
            let mut column = next_column(&mut group)?;
            column
                .typed::<ByteArrayType>()
                .write_batch(&texts, Some(&levels), None)?;
            column.close()?;
        }
        group.close()?;
        Ok(())
    }
}

/// The row group's next column.
fn next_column<'g, W: Write + Send>(
    group: &'g mut SerializedRowGroupWriter<'_, W>,
) -> Result<SerializedColumnWriter<'g>, ParquetError> {
    group
        .next_column()?
        .ok_or_else(|| ParquetError::General("fewer columns than the schema's".into()))
}

/// Writes `table` as Parquet into `w` (`path` names it in errors), with the units and
/// descriptions of `columns`.
pub fn write<W: Write + Send>(
    table: &Table,
    w: W,
    path: &str,
    columns: &[ColumnInfo],
) -> Result<(), Error> {
    let io = |e: ParquetError| Error::Io {
        path: path.to_string(),
        message: e.to_string(),
    };
    let mut writer = Writer::new(w, table.names(), columns).map_err(io)?;
    writer.write(table).map_err(io)?;
    writer.finish().map_err(io)?;
    Ok(())
}

/// The table in a Parquet file [`write`] or a [`Writer`] wrote. A file with a manifest beside
/// it (a study's shard, or a file written whole: [`crate::whole_file`]) is checked against it
/// first, as `Table::read_csv` checks a CSV file: a file altered or replaced since it was
/// written (another shard's copied over it) is an error, not another table.
pub fn read(path: impl AsRef<Path>) -> Result<Table, Error> {
    let path = path.as_ref();
    let io = |message: String| Error::Read {
        path: path.display().to_string(),
        message,
    };
    let manifest = crate::whole_file::check_manifest(path)?;
    let file = std::fs::File::open(path).map_err(|e| io(e.to_string()))?;
    let reader = SerializedFileReader::new(file).map_err(|e| io(e.to_string()))?;
    let fields = reader.metadata().file_metadata().schema().get_fields();
    let width = fields.len();
    let names: Vec<String> = fields.iter().map(|f| f.name().to_string()).collect();
    if width < 3
        || names[0] != CASE_COLUMN
        || names[width - 2] != "error_kind"
        || names[width - 1] != "error"
    {
        return Err(io(format!(
            "its columns ({}) are not a study table's ({CASE_COLUMN}, …, error_kind, error)",
            names.join(", ")
        )));
    }
    let mut table = Table::new(names[1..width - 2].to_vec()).map_err(|e| io(e.to_string()))?;
    let rows = reader.get_row_iter(None).map_err(|e| io(e.to_string()))?;
    for row in rows {
        let row = row.map_err(|e| io(e.to_string()))?;
        let case = row.get_long(0).map_err(|e| io(e.to_string()))? as u64;
        let values = row
            .get_column_iter()
            .skip(1)
            .take(width - 3)
            .map(|(name, field)| match field {
                Field::Double(v) => Ok(*v),
                // A value a failed case could not compute.
                Field::Null => Ok(f64::NAN),
                other => Err(io(format!(
                    "the column `{name}` holds {other}, not a number"
                ))),
            })
            .collect::<Result<Vec<f64>, Error>>()?;
        let error = match (row.get_string(width - 2), row.get_string(width - 1)) {
            (Ok(kind), Ok(message)) => Some(CaseError {
                kind: kind.clone(),
                message: message.clone(),
            }),
            _ => None,
        };
        table
            .push_row(case, values, error)
            .map_err(|e| io(e.to_string()))?;
    }
    match manifest {
        Some(m) if m.rows != table.len() as u64 => Err(io(format!(
            "it holds {} rows where its manifest says {}: it is not the file that was written",
            table.len(),
            m.rows
        ))),
        _ => Ok(table),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_round_trip_bit_for_bit_compressed_with_their_units() {
        let mut table = Table::new(vec!["x@0.25".into(), "final_w4".into()]).unwrap();
        table.push(7, Ok(vec![0.1 + 0.2, -0.0])).unwrap();
        let message = "a \"quoted\", comma\nand a second line";
        let failed = CaseError {
            kind: "case_panicked".into(),
            message: message.into(),
        };
        table
            .push_row(8, vec![0.5, f64::NAN], Some(failed))
            .unwrap();
        table.push(9, Ok(vec![1e-300, f64::INFINITY])).unwrap();
        let dir = std::env::temp_dir().join(format!("hamel-parquet-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("table.parquet");
        let info = [ColumnInfo {
            name: "x@0.25".into(),
            unit: "m".into(),
            description: "the position at t = 0.25".into(),
        }];
        let name = path.display().to_string();
        crate::ensemble::write_complete(&path, |file| write(&table, file, &name, &info)).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back, table);
        assert_eq!(
            back.column("x@0.25").unwrap()[1],
            0.5,
            "a failed row keeps its values"
        );
        // Its value it could not compute is null (before, NaN, which made DuckDB's `avg` and
        // polars' `mean` NaN); the first column is `case_index` (`case` is SQL's keyword).
        let reader = SerializedFileReader::new(std::fs::File::open(&path).unwrap()).unwrap();
        let rows: Vec<Vec<(String, Field)>> = reader
            .get_row_iter(None)
            .unwrap()
            .map(|r| {
                r.unwrap()
                    .get_column_iter()
                    .map(|(n, f)| (n.clone(), f.clone()))
                    .collect()
            })
            .collect();
        assert_eq!(rows[0][0].0, "case_index");
        assert_eq!(rows[1][2], ("final_w4".to_string(), Field::Null));
        assert_eq!(rows[1][1], ("x@0.25".to_string(), Field::Double(0.5)));
        assert_eq!(
            rows[2][2],
            ("final_w4".to_string(), Field::Double(f64::INFINITY))
        );
        // The file begins and ends with Parquet's magic; its columns are Snappy-compressed
        // and the units in its metadata.
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"PAR1") && bytes.ends_with(b"PAR1"));
        let reader = SerializedFileReader::new(std::fs::File::open(&path).unwrap()).unwrap();
        let group = reader.metadata().row_group(0);
        assert!(
            group
                .columns()
                .iter()
                .all(|c| c.compression() == Compression::SNAPPY)
        );
        let kv = reader
            .metadata()
            .file_metadata()
            .key_value_metadata()
            .unwrap();
        let get = |k: &str| kv.iter().find(|e| e.key == k).and_then(|e| e.value.clone());
        assert_eq!(get("x@0.25.unit").as_deref(), Some("m"));
        assert_eq!(
            get("x@0.25.description").as_deref(),
            Some("the position at t = 0.25")
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A file written whole is read against its manifest, as a CSV file is. Before, a Parquet
    /// file was read without it: a shard with another's file copied over it read as the
    /// other's table.
    #[test]
    fn a_file_written_whole_is_read_against_its_manifest() {
        use crate::whole_file::WholeFile;
        let dir =
            std::env::temp_dir().join(format!("hamel-parquet-manifest-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let written = |name: &str, rows: u64| {
            let mut table = Table::new(vec!["v".into()]).unwrap();
            for case in 0..rows {
                table.push(case, Ok(vec![case as f64])).unwrap();
            }
            let path = dir.join(name);
            let mut file = WholeFile::create(&path).unwrap();
            write(&table, &mut file, name, &[]).unwrap();
            file.commit(rows).unwrap();
            path
        };
        let (one, other) = (written("one.parquet", 3), written("other.parquet", 5));
        assert_eq!(read(&one).unwrap().len(), 3);
        std::fs::copy(&other, &one).unwrap();
        let e = read(&one).unwrap_err().to_string();
        assert!(
            e.contains("its manifest") && e.contains("one.parquet"),
            "{e}"
        );
        // Cut short (a copy interrupted): the manifest's size, not a reader's error deep in
        // the footer, or a shorter table.
        let bytes = std::fs::read(&other).unwrap();
        std::fs::write(&other, &bytes[..bytes.len() / 2]).unwrap();
        let e = read(&other).unwrap_err().to_string();
        assert!(
            e.contains("truncated") && e.contains("other.parquet"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The bytes depend on the rows alone: written in blocks of any size, or whole.
    #[test]
    fn blocks_of_any_size_give_the_same_bytes() {
        let names = vec!["v".to_string()];
        let mut whole = Table::new(names.clone()).unwrap();
        for i in 0..(ROW_GROUP as u64 + 10) {
            whole.push(i, Ok(vec![i as f64 * 0.5])).unwrap();
        }
        let bytes_of = |block: usize| {
            let mut w = Writer::new(Vec::new(), &names, &[]).unwrap();
            let mut part = Table::new(names.clone()).unwrap();
            for i in 0..whole.len() {
                part.push(whole.cases()[i], Ok(whole.row(i).unwrap()))
                    .unwrap();
                if part.len() == block {
                    w.write(&part).unwrap();
                    part = Table::new(names.clone()).unwrap();
                }
            }
            w.write(&part).unwrap();
            w.finish().unwrap()
        };
        let one = bytes_of(usize::MAX);
        assert_eq!(bytes_of(4096), one);
        assert_eq!(bytes_of(7), one);
    }
}
