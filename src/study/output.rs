//! A study's files: CSV or Parquet chosen when the program runs, written a block of rows at
//! a time; a shard's file with its manifest; the shards joined into one file.

use std::path::{Path, PathBuf};

use crate::ensemble::{
    CsvWriter, Shard, ShardFile, ShardStamp, ShardState, shard_state, write_complete,
};
use crate::{Error, ParameterTable, Table};

use super::Study;

/// A study table's file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// RFC 4180 CSV.
    Csv,
    /// Apache Parquet, compressed (needs hamel's feature `parquet`).
    Parquet,
}

impl Format {
    /// `csv` or `parquet`, as on the command line; Parquet in a build without the feature
    /// `parquet` is an error saying how to build it.
    pub fn from_name(name: &str) -> Result<Format, String> {
        match name {
            "csv" => Ok(Format::Csv),
            "parquet" if cfg!(feature = "parquet") => Ok(Format::Parquet),
            "parquet" => Err(PARQUET_MISSING.to_string()),
            other => Err(format!("--format is `csv` or `parquet`, not `{other}`")),
        }
    }

    /// The files' extension.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Parquet => "parquet",
        }
    }
}

/// The message for Parquet asked of a build without it.
const PARQUET_MISSING: &str = "--format parquet needs hamel's feature `parquet`, which this \
     program was built without: build it with `--features parquet` (cargo build --features \
     parquet, or `hamel = { features = [\"parquet\"] }` in Cargo.toml), or use --format csv";

/// A table's writer in either format, over a file being written.
pub(crate) enum Sink<'w> {
    Csv(CsvWriter<&'w mut ShardFile>),
    #[cfg(feature = "parquet")]
    Parquet(crate::parquet::Writer<&'w mut ShardFile>),
}

impl<'w> Sink<'w> {
    /// Starts the table of `study` in `file` (`path` names it in errors).
    pub(crate) fn open(
        format: Format,
        file: &'w mut ShardFile,
        study: &Study,
        path: &Path,
    ) -> Result<Sink<'w>, Error> {
        let names = study.columns();
        match format {
            Format::Csv => CsvWriter::new(file, &names)
                .map(Sink::Csv)
                .map_err(|e| io(path, e)),
            #[cfg(feature = "parquet")]
            Format::Parquet => {
                let info: Vec<crate::parquet::ColumnInfo> = study
                    .described()
                    .into_iter()
                    .map(|c| crate::parquet::ColumnInfo {
                        name: c.name,
                        unit: c.unit,
                        description: c.description,
                    })
                    .collect();
                crate::parquet::Writer::new(file, &names, &info)
                    .map(Sink::Parquet)
                    .map_err(|e| io(path, e))
            }
            #[cfg(not(feature = "parquet"))]
            Format::Parquet => Err(io(path, PARQUET_MISSING)),
        }
    }

    /// Writes a block of rows.
    pub(crate) fn write(&mut self, block: &Table, path: &Path) -> Result<(), Error> {
        match self {
            Sink::Csv(w) => w.write(block).map_err(|e| io(path, e)),
            #[cfg(feature = "parquet")]
            Sink::Parquet(w) => w.write(block).map_err(|e| io(path, e)),
        }
    }

    /// Ends the table.
    pub(crate) fn finish(self, path: &Path) -> Result<(), Error> {
        match self {
            Sink::Csv(w) => w.finish().map(|_| ()).map_err(|e| io(path, e)),
            #[cfg(feature = "parquet")]
            Sink::Parquet(w) => w.finish().map(|_| ()).map_err(|e| io(path, e)),
        }
    }
}

/// An error writing `path`.
pub(crate) fn io(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// The table in a study's file of this format.
pub(crate) fn read(format: Format, path: &Path) -> Result<Table, Error> {
    match format {
        Format::Csv => Table::read_csv(path),
        #[cfg(feature = "parquet")]
        Format::Parquet => crate::parquet::read(path),
        #[cfg(not(feature = "parquet"))]
        Format::Parquet => Err(Error::Read {
            path: path.display().to_string(),
            message: PARQUET_MISSING.into(),
        }),
    }
}

/// The stamp of `shard` of `study` over `table` in `format`.
pub(crate) fn stamp(
    study: &Study,
    table: &ParameterTable,
    shard: Shard,
    format: Format,
) -> ShardStamp {
    let rows = (0..table.len()).filter_map(|i| table.row(i));
    ShardStamp::new(
        table.names(),
        rows,
        shard,
        &study.columns(),
        format.extension(),
        study.program(),
    )
}

/// The shards of `table`'s study in `dir` joined, in order, into `into`: each must be
/// complete; their count is read from their names. The file is the one a single task
/// running the whole table writes, byte for byte. Returns the number of rows and shards.
pub(crate) fn merge(
    study: &Study,
    table: &ParameterTable,
    dir: &Path,
    format: Format,
    into: &Path,
) -> Result<(usize, usize), Error> {
    let count = shard_count(dir, format)?;
    let mut shards = Vec::with_capacity(count);
    for index in 0..count {
        let shard = Shard { index, count };
        let path = dir.join(shard.file_name(format.extension()));
        match shard_state(&path, &stamp(study, table, shard, format)) {
            ShardState::Complete => shards.push(path),
            ShardState::Missing => return Err(not_complete(&path, shard, "it is missing")),
            ShardState::Incomplete(why) => return Err(not_complete(&path, shard, &why)),
        }
    }
    let mut rows = 0;
    write_complete(into, |file| {
        let mut sink = Sink::open(format, file, study, into)?;
        for path in &shards {
            let part = read(format, path)?;
            if part.names() != study.columns() {
                return Err(Error::Read {
                    path: path.display().to_string(),
                    message: format!(
                        "its columns ({}) are not the study's ({})",
                        part.names().join(", "),
                        study.columns().join(", ")
                    ),
                });
            }
            rows += part.len();
            sink.write(&part, into)?;
        }
        sink.finish(into)
    })?;
    Ok((rows, count))
}

/// The error for a shard that a merge needs and that is not complete.
fn not_complete(path: &Path, shard: Shard, why: &str) -> Error {
    Error::Read {
        path: path.display().to_string(),
        message: format!(
            "shard {}/{} is not complete: {why}; run its task again (`--shard {}/{}`), then merge",
            shard.index, shard.count, shard.index, shard.count
        ),
    }
}

/// The number of shards of the study's files in `dir`, from their names
/// (`shard-<i>-of-<n>.<extension>`): one n for all, or an error naming the others.
fn shard_count(dir: &Path, format: Format) -> Result<usize, Error> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::Read {
        path: dir.display().to_string(),
        message: e.to_string(),
    })?;
    let suffix = format!(".{}", format.extension());
    let mut counts: Vec<usize> = entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let stem = name.strip_prefix("shard-")?.strip_suffix(suffix.as_str())?;
            let (i, n) = stem.split_once("-of-")?;
            i.parse::<usize>().ok()?;
            n.parse::<usize>().ok()
        })
        .collect();
    counts.sort_unstable();
    counts.dedup();
    match counts.as_slice() {
        [n] => Ok(*n),
        [] => Err(Error::Read {
            path: dir.display().to_string(),
            message: format!("it holds no shard files (shard-<i>-of-<n>{suffix}) to merge"),
        }),
        more => Err(Error::Read {
            path: dir.display().to_string(),
            message: format!(
                "it holds the shards of studies split {} ways: merge one study's shards, in a \
                 directory of their own",
                more.iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }),
    }
}

/// `<study name>.<extension>`, the whole table's file.
pub(crate) fn default_path(study: &Study, format: Format) -> PathBuf {
    PathBuf::from(format!("{}.{}", study.name(), format.extension()))
}
