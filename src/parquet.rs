//! A study's [`Table`] as Apache Parquet (feature `parquet`), with the arrow-rs `parquet`
//! crate: a column `case` (int64), one `double` column per value column, and `error`, a
//! nullable UTF-8 string (null for a case that succeeded). pandas (`read_parquet`) and polars
//! (`read_parquet`, or `scan_parquet("results/*.parquet")` for a sharded study's files) read
//! it as it is. Uncompressed: a study's table is small, and no codec is built.
//!
//! ```no_run
//! use hamel::ensemble::{Shard, write_complete};
//! use hamel::{Ensemble, Table};
//!
//! let table = Ensemble::new(4).table(vec!["square".into()], |i| Ok(vec![(i * i) as f64]))?;
//! let path = format!("results/{}", Shard::ALL.file_name("parquet"));
//! write_complete(&path, |file| hamel::parquet::write(&table, file, &path))?;
//! assert_eq!(hamel::parquet::read(&path)?, table);
//! # Ok::<(), hamel::Error>(())
//! ```

use std::path::Path;
use std::sync::Arc;

use ::parquet::basic::{LogicalType, Repetition, Type as Physical};
use ::parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use ::parquet::file::properties::WriterProperties;
use ::parquet::file::reader::{FileReader, SerializedFileReader};
use ::parquet::file::writer::SerializedFileWriter;
use ::parquet::record::RowAccessor;
use ::parquet::schema::types::Type;

use crate::{Error, Table};

/// The schema of a table with these value columns.
fn schema(names: &[String]) -> Result<Type, ::parquet::errors::ParquetError> {
    let mut fields = vec![Arc::new(
        Type::primitive_type_builder("case", Physical::INT64)
            .with_repetition(Repetition::REQUIRED)
            .build()?,
    )];
    for name in names {
        fields.push(Arc::new(
            Type::primitive_type_builder(name, Physical::DOUBLE)
                .with_repetition(Repetition::REQUIRED)
                .build()?,
        ));
    }
    fields.push(Arc::new(
        Type::primitive_type_builder("error", Physical::BYTE_ARRAY)
            .with_repetition(Repetition::OPTIONAL)
            .with_logical_type(Some(LogicalType::String))
            .build()?,
    ));
    Type::group_type_builder("study")
        .with_fields(fields)
        .build()
}

/// Writes `table` as Parquet into `file` (`path` names it in errors): one row group.
pub fn write(table: &Table, file: &mut std::fs::File, path: &str) -> Result<(), Error> {
    write_to(table, file).map_err(|e| Error::Io {
        path: path.to_string(),
        message: e.to_string(),
    })
}

fn write_to(
    table: &Table,
    file: &mut std::fs::File,
) -> Result<(), ::parquet::errors::ParquetError> {
    let schema = Arc::new(schema(table.names())?);
    let properties = Arc::new(WriterProperties::builder().build());
    let mut writer = SerializedFileWriter::new(file, schema, properties)?;
    let mut group = writer.next_row_group()?;
    let cases: Vec<i64> = table.cases().iter().map(|&c| c as i64).collect();
    let mut column = group.next_column()?.expect("the case column");
    column
        .typed::<Int64Type>()
        .write_batch(&cases, None, None)?;
    column.close()?;
    for name in table.names() {
        let values = table.column(name).expect("the table's own column");
        let mut column = group.next_column()?.expect("a value column");
        column
            .typed::<DoubleType>()
            .write_batch(values, None, None)?;
        column.close()?;
    }
    // Definition level 1: the message is there; 0: null, the case succeeded.
    let levels: Vec<i16> = table
        .errors()
        .iter()
        .map(|e| i16::from(e.is_some()))
        .collect();
    let messages: Vec<ByteArray> = table
        .errors()
        .iter()
        .flatten()
        .map(|e| ByteArray::from(e.as_str()))
        .collect();
    let mut column = group.next_column()?.expect("the error column");
    column
        .typed::<ByteArrayType>()
        .write_batch(&messages, Some(&levels), None)?;
    column.close()?;
    group.close()?;
    writer.close()?;
    Ok(())
}

/// The table in a Parquet file [`write`] wrote.
pub fn read(path: impl AsRef<Path>) -> Result<Table, Error> {
    let path = path.as_ref();
    let io = |message: String| Error::Io {
        path: path.display().to_string(),
        message,
    };
    let file = std::fs::File::open(path).map_err(|e| io(e.to_string()))?;
    let reader = SerializedFileReader::new(file).map_err(|e| io(e.to_string()))?;
    let fields = reader.metadata().file_metadata().schema().get_fields();
    let width = fields.len();
    let names: Vec<String> = fields
        .iter()
        .skip(1)
        .take(width.saturating_sub(2))
        .map(|f| f.name().to_string())
        .collect();
    let mut table = Table::new(names)?;
    let rows = reader.get_row_iter(None).map_err(|e| io(e.to_string()))?;
    for row in rows {
        let row = row.map_err(|e| io(e.to_string()))?;
        let case = row.get_long(0).map_err(|e| io(e.to_string()))? as u64;
        match row.get_string(width - 1) {
            Ok(message) => table.push_failed(case, message.clone()),
            Err(_) => {
                let values = (1..width - 1)
                    .map(|j| row.get_double(j))
                    .collect::<Result<Vec<f64>, _>>()
                    .map_err(|e| io(e.to_string()))?;
                table.push(case, Ok(values));
            }
        }
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ensemble::{Shard, write_complete};

    #[test]
    fn tables_round_trip_bit_for_bit() {
        let mut table = Table::new(vec!["x@0.25".into(), "final_w4".into()]).unwrap();
        table.push(7, Ok(vec![0.1 + 0.2, -0.0]));
        table.push(
            8,
            Err(Error::InvalidSetting {
                name: "x",
                value: 1.0,
                reason: "a \"quoted\", comma",
            }),
        );
        table.push(9, Ok(vec![1e-300, f64::INFINITY]));
        let dir = std::env::temp_dir().join(format!("hamel-parquet-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(Shard::ALL.file_name("parquet"));
        let name = path.display().to_string();
        write_complete(&path, |file| write(&table, file, &name)).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back.names(), table.names());
        assert_eq!(back.cases(), [7, 8, 9]);
        assert_eq!(back.errors(), table.errors());
        let bits = |t: &Table| -> Vec<u64> {
            t.names()
                .iter()
                .flat_map(|n| t.column(n).unwrap().iter().map(|v| v.to_bits()))
                .collect()
        };
        assert_eq!(bits(&back), bits(&table));
        // The file begins and ends with Parquet's magic.
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"PAR1") && bytes.ends_with(b"PAR1"));
        std::fs::remove_dir_all(dir).unwrap();
    }
}
