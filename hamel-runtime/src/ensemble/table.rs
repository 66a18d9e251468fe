//! A study's results as a table of named `f64` columns, and the parameter table its cases
//! are read from: both as CSV (RFC 4180, written and read by the `csv` crate) that pandas
//! (`read_csv`) and polars read as they are, and that this module reads back equal.

use std::collections::HashSet;
use std::io::Write;
use std::path::Path;

use super::quotes::{QuoteScan, UNCLOSED};
use crate::error::Error;
use crate::whole_file::{WholeFile, check_manifest};

/// The columns every study table has besides its own: the case index first (not `case`,
/// which SQL reserves: DuckDB needed it quoted), the error's kind and message last.
pub const CASE_COLUMN: &str = "case_index";
const CASE: &str = CASE_COLUMN;
const ERROR_KIND: &str = "error_kind";
const ERROR: &str = "error";

/// Why a case failed: the error's kind ([`Error::kind`], `singular_mass_matrix`, or a
/// study's own) and its message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CaseError {
    /// A short name that groups failures: never empty.
    pub kind: String,
    /// What happened, for the study's user.
    pub message: String,
}

impl CaseError {
    /// The kind and message of `error`.
    pub fn of(error: &Error) -> CaseError {
        CaseError {
            kind: error.kind().to_string(),
            message: error.to_string(),
        }
    }
}

impl std::fmt::Display for CaseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.message, self.kind)
    }
}

/// A study's results: one row per case, with the case's index (its row in the study's
/// parameter table), a value for every named column, and the error of a case that failed
/// (its values it could not compute are NaN). Written as CSV with the header
/// `case_index,<columns>,error_kind,error`, numbers in Rust's shortest form that reads back
/// to the same `f64` (bit for bit; `NaN`, `inf`), `error_kind` and `error` empty for a case
/// that succeeded. A failed case's values that it could not compute (NaN) are empty fields,
/// which pandas, polars and DuckDB read as missing (null): their means and averages skip the
/// failed rows, where a `NaN` would make them NaN. Each case index appears once.
///
/// Two tables are equal when their names, cases and errors are, and their values bit for
/// bit, any NaN being equal to any other: a table read back from its CSV equals the table.
#[derive(Clone, Debug)]
pub struct Table {
    names: Vec<String>,
    cases: Vec<u64>,
    columns: Vec<Vec<f64>>,
    errors: Vec<Option<CaseError>>,
    seen: HashSet<u64>,
}

impl PartialEq for Table {
    fn eq(&self, other: &Table) -> bool {
        let same = |a: &f64, b: &f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        self.names == other.names
            && self.cases == other.cases
            && self.errors == other.errors
            && self
                .columns
                .iter()
                .zip(&other.columns)
                .all(|(a, b)| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same(x, y)))
    }
}

impl Table {
    /// An empty table with these value columns. A name that is empty, holds a comma, quote or
    /// line break, or repeats (or is `case_index`, `error_kind` or `error`) is an error.
    pub fn new(names: Vec<String>) -> Result<Table, Error> {
        check_names(&names)?;
        let columns = vec![Vec::new(); names.len()];
        Ok(Table {
            names,
            cases: Vec::new(),
            columns,
            errors: Vec::new(),
            seen: HashSet::new(),
        })
    }

    /// Appends the row of case `index`: its values (one per column), or its error (its values
    /// NaN). Values of another length are an error in the row's place. A case index the
    /// table has already is refused ([`Error::DuplicateName`]).
    pub fn push(&mut self, index: u64, row: Result<Vec<f64>, Error>) -> Result<(), Error> {
        let width = self.names.len();
        match row {
            Ok(values) if values.len() == width => self.push_row(index, values, None),
            Ok(values) => {
                let e = Error::DimensionMismatch {
                    what: format!(
                        "case {index} has {} values for {width} columns",
                        values.len()
                    ),
                };
                self.push_row(index, vec![f64::NAN; width], Some(CaseError::of(&e)))
            }
            Err(e) => self.push_row(index, vec![f64::NAN; width], Some(CaseError::of(&e))),
        }
    }

    /// Appends a row as it is: its values (one per column; a failed case keeps those it has,
    /// its parameters, NaN for the others) and its error, if it failed.
    pub fn push_row(
        &mut self,
        index: u64,
        values: Vec<f64>,
        error: Option<CaseError>,
    ) -> Result<(), Error> {
        if values.len() != self.names.len() {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "case {index} has {} values for the {} columns ({})",
                    values.len(),
                    self.names.len(),
                    self.names.join(", ")
                ),
            });
        }
        if !self.seen.insert(index) {
            return Err(duplicate_case(index));
        }
        self.cases.push(index);
        for (column, v) in self.columns.iter_mut().zip(values) {
            column.push(v);
        }
        self.errors.push(error.map(|mut e| {
            if e.kind.is_empty() {
                e.kind = "error".into();
            }
            e
        }));
        Ok(())
    }

    /// The rows of `other` after this table's (the shards of a study, in order); its columns
    /// must be the same, its case indices others than this table's.
    pub fn append(&mut self, other: Table) -> Result<(), Error> {
        if other.names != self.names {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "tables with the columns ({}) and ({}) cannot be joined",
                    self.names.join(", "),
                    other.names.join(", ")
                ),
            });
        }
        if let Some(&index) = other.cases.iter().find(|c| self.seen.contains(c)) {
            return Err(duplicate_case(index));
        }
        self.seen.extend(other.cases.iter().copied());
        self.cases.extend(other.cases);
        for (column, more) in self.columns.iter_mut().zip(other.columns) {
            column.extend(more);
        }
        self.errors.extend(other.errors);
        Ok(())
    }

    /// The value columns' names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.cases.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cases.is_empty()
    }

    /// Each row's case index.
    pub fn cases(&self) -> &[u64] {
        &self.cases
    }

    /// The column called `name`, if there is one.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let j = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[j])
    }

    /// Each row's error, `None` for a case that succeeded.
    pub fn errors(&self) -> &[Option<CaseError>] {
        &self.errors
    }

    /// The number of rows that carry an error.
    pub fn failed(&self) -> usize {
        self.errors.iter().filter(|e| e.is_some()).count()
    }

    /// Row i's values, one per column.
    pub fn row(&self, i: usize) -> Option<Vec<f64>> {
        (i < self.len()).then(|| self.columns.iter().map(|c| c[i]).collect())
    }

    /// The CSV text: `case_index,<columns>,error_kind,error`, then a record per row.
    pub fn write_csv<W: Write>(&self, w: W) -> std::io::Result<()> {
        let mut writer = CsvWriter::new(w, &self.names)?;
        writer.write(self)?;
        writer.finish().map(|_| ())
    }

    /// The table read back from [`Self::write_csv`]'s text (`source` names it in errors).
    /// Every mistake is an [`Error::Table`] naming the line and column: a header that is not
    /// `case_index,<columns>,error_kind,error`, a record of another length, a case index that
    /// is not a whole number or repeats, a value that is not a number (or missing in a row
    /// that did not fail), an error without its kind, a quoted field whose quote is not
    /// closed.
    pub fn parse_csv(text: &str, source: &str) -> Result<Table, Error> {
        let mut reader = reader(text.as_bytes());
        unless_unclosed(&mut reader, source, |reader| {
            Table::read_records(reader, source)
        })
    }

    /// The records of a study table's CSV.
    fn read_records<R: std::io::Read>(
        reader: &mut csv::Reader<R>,
        source: &str,
    ) -> Result<Table, Error> {
        let header = header(reader, source, "a study table")?;
        let problem = |p: String| table_error(source, 1, "", p);
        let width = header.len();
        if width < 3
            || header[0] != CASE
            || header[width - 2] != ERROR_KIND
            || header[width - 1] != ERROR
        {
            return Err(problem(format!(
                "a study table's header is `{CASE},<columns>,{ERROR_KIND},{ERROR}`, not `{}`",
                header.join(",")
            )));
        }
        let mut table =
            Table::new(header[1..width - 2].to_vec()).map_err(|e| problem(e.to_string()))?;
        for record in reader.records() {
            let (line, fields) = record_fields(record, source)?;
            if fields.len() != width {
                return Err(table_error(
                    source,
                    line,
                    "",
                    format!("{} fields for {width} columns", fields.len()),
                ));
            }
            let case = fields[0].parse::<u64>().map_err(|_| {
                table_error(
                    source,
                    line,
                    CASE,
                    format!("`{}` is not a case index", fields[0]),
                )
            })?;
            let (kind, message) = (&fields[width - 2], &fields[width - 1]);
            let mut values = Vec::with_capacity(width - 3);
            for (name, field) in header[1..].iter().zip(&fields[1..width - 2]) {
                // Empty: a value a failed case could not compute.
                let v = match field.as_str() {
                    "" if !kind.is_empty() => f64::NAN,
                    "" => {
                        return Err(table_error(
                            source,
                            line,
                            name,
                            "the value is missing, in a row that did not fail (no error_kind)"
                                .into(),
                        ));
                    }
                    _ => field.parse::<f64>().map_err(|_| {
                        table_error(source, line, name, format!("`{field}` is not a number"))
                    })?,
                };
                values.push(v);
            }
            let error = match (kind.is_empty(), message.is_empty()) {
                (true, true) => None,
                (true, false) => {
                    return Err(table_error(
                        source,
                        line,
                        ERROR_KIND,
                        "an error needs its kind".into(),
                    ));
                }
                (false, _) => Some(CaseError {
                    kind: kind.clone(),
                    message: message.clone(),
                }),
            };
            table
                .push_row(case, values, error)
                .map_err(|e| table_error(source, line, CASE, e.to_string()))?;
        }
        Ok(table)
    }

    /// The table in the CSV file at `path`, checked against its manifest when it has one
    /// ([`Self::save_csv`] writes it): a file cut short since it was written, even between two
    /// rows, is an [`Error::Read`] saying so, not a shorter table.
    pub fn read_csv(path: impl AsRef<Path>) -> Result<Table, Error> {
        let path = path.as_ref();
        let manifest = check_manifest(path)?;
        let table = Table::parse_csv(&read_text(path)?, &path.display().to_string())?;
        if let Some(m) = manifest
            && m.rows != table.len() as u64
        {
            return Err(Error::Read {
                path: path.display().to_string(),
                message: format!(
                    "it holds {} rows where its manifest says {}: it is not the file that was \
                     written",
                    table.len(),
                    m.rows
                ),
            });
        }
        Ok(table)
    }

    /// Writes the CSV to a file, whole or not at all: under a name of its own, flushed to disk
    /// and renamed to `path`, then its manifest `<path>.manifest` (the row count, the size
    /// and checksum), which [`Self::read_csv`] checks ([`crate::whole_file`]). The CSV itself
    /// is plain RFC 4180, for any reader. A failed write leaves what was at `path` before.
    pub fn save_csv(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        let mut file = WholeFile::create(path)?;
        self.write_csv(&mut file)
            .map_err(|e| crate::whole_file::io(path, e))?;
        file.commit(self.len() as u64)
    }
}

/// A study table's CSV written a block of rows at a time, so that a study of any size is
/// written in the memory of one block: the header first, then each [`Table`]'s rows as they
/// come (the blocks' case indices are the writer's to keep apart).
pub struct CsvWriter<W: Write> {
    writer: csv::Writer<W>,
    names: Vec<String>,
    /// One record's fields, reused.
    record: csv::ByteRecord,
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header `case_index,<names>,error_kind,error` to `w`.
    pub fn new(w: W, names: &[String]) -> std::io::Result<CsvWriter<W>> {
        let mut writer = csv::WriterBuilder::new()
            .quote_style(csv::QuoteStyle::Necessary)
            .from_writer(w);
        let header = std::iter::once(CASE)
            .chain(names.iter().map(String::as_str))
            .chain([ERROR_KIND, ERROR]);
        writer.write_record(header)?;
        Ok(CsvWriter {
            writer,
            names: names.to_vec(),
            record: csv::ByteRecord::new(),
        })
    }

    /// Writes `block`'s rows (its columns must be the writer's).
    pub fn write(&mut self, block: &Table) -> std::io::Result<()> {
        if block.names != self.names {
            return Err(std::io::Error::other(format!(
                "a block of the columns ({}) written to a table of ({})",
                block.names.join(", "),
                self.names.join(", ")
            )));
        }
        use std::fmt::Write as _;
        let mut number = String::new();
        for (i, case) in block.cases.iter().enumerate() {
            self.record.clear();
            number.clear();
            let _ = write!(number, "{case}");
            self.record.push_field(number.as_bytes());
            let failed = block.errors[i].is_some();
            for column in &block.columns {
                number.clear();
                // A failed case's missing value is an empty field (a null to other readers);
                // otherwise `{:?}`, the shortest text that reads back to the same bits.
                if !(failed && column[i].is_nan()) {
                    let _ = write!(number, "{:?}", column[i]);
                }
                self.record.push_field(number.as_bytes());
            }
            match &block.errors[i] {
                Some(e) => {
                    self.record.push_field(e.kind.as_bytes());
                    self.record.push_field(e.message.as_bytes());
                }
                None => {
                    self.record.push_field(b"");
                    self.record.push_field(b"");
                }
            }
            self.writer.write_byte_record(&self.record)?;
        }
        Ok(())
    }

    /// Flushes what is buffered and returns the underlying writer.
    pub fn finish(self) -> std::io::Result<W> {
        self.writer
            .into_inner()
            .map_err(|e| std::io::Error::other(e.error().to_string()))
    }
}

/// The error for a case index given twice.
fn duplicate_case(index: u64) -> Error {
    Error::DuplicateName {
        kind: "case index",
        name: index.to_string(),
        context: "each case of a study has one row",
    }
}

/// Names must be usable as CSV column names, once each, and not the table's own.
fn check_names(names: &[String]) -> Result<(), Error> {
    for (i, name) in names.iter().enumerate() {
        let reason = if name.is_empty() {
            Some("a column needs a name")
        } else if name.contains([',', '"', '\n', '\r']) {
            Some("a column name may not contain a comma, a quote or a line break (CSV)")
        } else if name.trim() != name {
            Some("a column name may not begin or end with a space")
        } else {
            None
        };
        if let Some(reason) = reason {
            return Err(Error::InvalidColumnName {
                kind: "column",
                name: name.clone(),
                reason,
            });
        }
        if names[..i].contains(name) || [CASE, ERROR_KIND, ERROR].contains(&name.as_str()) {
            return Err(Error::DuplicateName {
                kind: "column",
                name: name.clone(),
                context: "a study table's columns are `case`, then each named once, then \
                          `error_kind` and `error`",
            });
        }
    }
    Ok(())
}

/// The error for a table's `line` (1-based, the header is line 1) and `column`.
fn table_error(source: &str, line: usize, column: &str, problem: String) -> Error {
    Error::Table {
        file: source.to_string(),
        line,
        column: column.to_string(),
        problem,
    }
}

/// The text of the file at `path`, or "cannot read" naming it.
fn read_text(path: &Path) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(|e| Error::Read {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// A reader of RFC 4180 text: records of any length (checked here, to say which line),
/// a byte-order mark (which spreadsheets write) skipped.
fn reader<R: std::io::BufRead>(mut input: R) -> csv::Reader<QuoteScan<R>> {
    if input
        .fill_buf()
        .is_ok_and(|b| b.starts_with("\u{feff}".as_bytes()))
    {
        input.consume(3);
    }
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(QuoteScan::new(input))
}

/// `read`'s result, unless a quote in the input is never closed: then that is the error,
/// naming the line it opened on (whatever `read` made of the rest of the file, read as one
/// value).
fn unless_unclosed<R: std::io::Read, T>(
    reader: &mut csv::Reader<QuoteScan<R>>,
    source: &str,
    read: impl FnOnce(&mut csv::Reader<QuoteScan<R>>) -> Result<T, Error>,
) -> Result<T, Error> {
    let result = read(reader);
    match reader.get_mut().unclosed() {
        Some(line) => Err(table_error(source, line, "", UNCLOSED.into())),
        None => result,
    }
}

/// The first record, the header; `what` names the table in the message of an empty one.
fn header<R: std::io::Read>(
    reader: &mut csv::Reader<R>,
    source: &str,
    what: &str,
) -> Result<Vec<String>, Error> {
    match reader.records().next() {
        Some(record) => Ok(record_fields(record, source)?.1),
        None => Err(table_error(
            source,
            1,
            "",
            format!("the file is empty: {what} needs a header of column names"),
        )),
    }
}

/// A record's line and fields, or the reader's error naming the line.
fn record_fields(
    record: Result<csv::StringRecord, csv::Error>,
    source: &str,
) -> Result<(usize, Vec<String>), Error> {
    match record {
        Ok(record) => {
            let line = record.position().map_or(0, |p| p.line() as usize);
            Ok((line, record.iter().map(str::to_string).collect()))
        }
        Err(e) => {
            let line = e.position().map_or(0, |p| p.line() as usize);
            let problem = match e.kind() {
                csv::ErrorKind::Utf8 { .. } => "the text is not UTF-8".to_string(),
                _ => e.to_string(),
            };
            Err(table_error(source, line, "", problem))
        }
    }
}

/// A study's cases read from CSV: a header of parameter names, then one row of numbers per
/// case. Every mistake is an error naming the line and the column: a column the study does
/// not know, or given twice, or one of its parameters missing; a missing value; a field that
/// is not a finite number.
///
/// ```
/// use hamel_runtime::ParameterTable;
///
/// let table = ParameterTable::parse("trail,mass\n0.08,85\n0.1,90\n", "grid.csv", &["trail", "mass"])?;
/// assert_eq!((table.len(), table.get(1, "mass")), (2, Some(90.0)));
/// let e = ParameterTable::parse("trail,mass\n0.08,heavy\n", "grid.csv", &["trail", "mass"]).unwrap_err();
/// assert_eq!(e.to_string(), "grid.csv, line 2, column `mass`: `heavy` is not a number");
/// let e = ParameterTable::parse("trail\n0.08\n", "grid.csv", &["trail", "mass"]).unwrap_err();
/// assert_eq!(
///     e.to_string(),
///     "grid.csv, line 1: the study's parameter `mass` is missing; its parameters are trail, mass"
/// );
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterTable {
    names: Vec<String>,
    /// The rows one after another, each as long as the names: a table of 10⁶ cases of two
    /// parameters is 16 MB.
    values: Vec<f64>,
    count: usize,
}

impl ParameterTable {
    /// The table in `text` (`source` names it in errors, a path); its columns must be
    /// `known`, each once, in any order.
    pub fn parse(text: &str, source: &str, known: &[&str]) -> Result<ParameterTable, Error> {
        ParameterTable::from_reader(text.as_bytes(), source, known)
    }

    /// The table in the file at `path`, read as a stream (the table is held as numbers, not
    /// as text).
    pub fn read(path: impl AsRef<Path>, known: &[&str]) -> Result<ParameterTable, Error> {
        let path = path.as_ref();
        let file = std::fs::File::open(path).map_err(|e| Error::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        let source = path.display().to_string();
        ParameterTable::from_reader(std::io::BufReader::new(file), &source, known)
    }

    /// The table read from `input`.
    fn from_reader(
        input: impl std::io::BufRead,
        source: &str,
        known: &[&str],
    ) -> Result<ParameterTable, Error> {
        let mut reader = reader(input);
        unless_unclosed(&mut reader, source, |reader| {
            ParameterTable::read_records(reader, source, known)
        })
    }

    /// The records of a parameter table's CSV.
    fn read_records<R: std::io::Read>(
        reader: &mut csv::Reader<R>,
        source: &str,
        known: &[&str],
    ) -> Result<ParameterTable, Error> {
        let names = header(reader, source, "a parameter table").map_err(|e| match e {
            Error::Table { file, line, .. } => Error::Table {
                file,
                line,
                column: String::new(),
                problem: "the table is empty: it needs a header of parameter names".into(),
            },
            e => e,
        })?;
        let names: Vec<String> = names.iter().map(|n| n.trim().to_string()).collect();
        check_header(&names, source, known)?;
        let (mut values, mut count) = (Vec::new(), 0);
        let mut record = csv::StringRecord::new();
        loop {
            match reader.read_record(&mut record) {
                Ok(true) => {}
                Ok(false) => break,
                Err(e) => return Err(record_fields(Err(e), source).unwrap_err()),
            }
            let line = record.position().map_or(0, |p| p.line() as usize);
            if record.iter().all(|f| f.trim().is_empty()) {
                continue;
            }
            if record.len() > names.len() {
                return Err(table_error(
                    source,
                    line,
                    "",
                    format!("{} values for {} columns", record.len(), names.len()),
                ));
            }
            for (j, name) in names.iter().enumerate() {
                let field = record.get(j).map_or("", |f| f.trim());
                values.push(parse_value(field).map_err(|p| table_error(source, line, name, p))?);
            }
            count += 1;
        }
        Ok(ParameterTable {
            names,
            values,
            count,
        })
    }

    /// A table of these columns and rows (each as long as the names, every value a finite
    /// number), as a study builds its grid; [`Self::to_csv`] writes it for the shards to read.
    pub fn from_rows(names: Vec<String>, rows: Vec<Vec<f64>>) -> Result<ParameterTable, Error> {
        check_names(&names)?;
        for (i, row) in rows.iter().enumerate() {
            if row.len() != names.len() {
                return Err(Error::DimensionMismatch {
                    what: format!(
                        "row {i} has {} values for {} columns",
                        row.len(),
                        names.len()
                    ),
                });
            }
            if let Some(j) = row.iter().position(|v| !v.is_finite()) {
                return Err(Error::InvalidParameter {
                    name: format!("{} (row {i} of the parameter table)", names[j]),
                    value: row[j],
                });
            }
        }
        let count = rows.len();
        Ok(ParameterTable {
            names,
            values: rows.into_iter().flatten().collect(),
            count,
        })
    }

    /// The column names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The number of rows (cases).
    pub fn len(&self) -> usize {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Row i's values, in the order of [`Self::names`].
    pub fn row(&self, i: usize) -> Option<&[f64]> {
        let width = self.names.len();
        (i < self.count).then(|| &self.values[i * width..(i + 1) * width])
    }

    /// Row i's value of the column `name`, if both exist.
    pub fn get(&self, i: usize, name: &str) -> Option<f64> {
        let j = self.names.iter().position(|n| n == name)?;
        self.row(i).map(|r| r[j])
    }

    /// The CSV text, numbers exact (they read back to the same bits): [`Self::parse`] with
    /// the same names gives the same table.
    pub fn to_csv(&self) -> String {
        let mut writer = csv::Writer::from_writer(Vec::new());
        let text = (|| -> csv::Result<Vec<u8>> {
            writer.write_record(&self.names)?;
            for row in (0..self.count).filter_map(|i| self.row(i)) {
                writer.write_record(row.iter().map(|v| format!("{v:?}")))?;
            }
            writer.into_inner().map_err(|e| e.into_error().into())
        })();
        // Writing to memory cannot fail, and every field is ASCII or a checked name.
        String::from_utf8(text.unwrap_or_default()).unwrap_or_default()
    }
}

/// A parameter table's header: exactly the study's parameters, each once.
fn check_header(names: &[String], source: &str, known: &[&str]) -> Result<(), Error> {
    let header = |column: &str, problem: String| table_error(source, 1, column, problem);
    let parameters = known.join(", ");
    for (j, name) in names.iter().enumerate() {
        if !known.contains(&name.as_str()) {
            return Err(header(
                name,
                format!("unknown column; the study's parameters are {parameters}"),
            ));
        }
        if names[..j].contains(name) {
            return Err(header(name, "the column is given twice".into()));
        }
    }
    let missing: Vec<&str> = known
        .iter()
        .copied()
        .filter(|k| !names.iter().any(|n| n == k))
        .collect();
    match missing.as_slice() {
        [] => Ok(()),
        [one] => Err(header(
            "",
            format!("the study's parameter `{one}` is missing; its parameters are {parameters}"),
        )),
        more => Err(header(
            "",
            format!(
                "the study's parameters `{}` are missing; its parameters are {parameters}",
                more.join("`, `")
            ),
        )),
    }
}

/// A parameter's value: a finite number.
fn parse_value(field: &str) -> Result<f64, String> {
    if field.is_empty() {
        return Err("the value is missing".into());
    }
    match field.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("`{field}` is not a finite number")),
        Err(_) => Err(format!("`{field}` is not a number")),
    }
}

#[cfg(test)]
mod tests;
