//! A study's results as a table of named `f64` columns, and the parameter table its cases
//! are read from: both as CSV that pandas (`read_csv`) and polars read as they are.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use crate::error::Error;

/// The columns every study table has besides its own: the case index first, the error last.
const CASE: &str = "case";
const ERROR: &str = "error";

/// A study's results: one row per case, with the case's index (its row in the study's
/// parameter table), a value for every named column, and the error of a case that failed (its
/// values are then NaN). Written as CSV with the header `case,<columns>,error`, numbers in
/// Rust's shortest form that reads back to the same `f64` (bit for bit), an empty `error` for
/// a case that succeeded.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    names: Vec<String>,
    cases: Vec<u64>,
    columns: Vec<Vec<f64>>,
    errors: Vec<Option<String>>,
}

impl Table {
    /// An empty table with these value columns. A name that is empty, holds a comma, quote or
    /// line break, or repeats (or is `case` or `error`) is an error.
    pub fn new(names: Vec<String>) -> Result<Table, Error> {
        check_names(&names)?;
        let columns = vec![Vec::new(); names.len()];
        Ok(Table {
            names,
            cases: Vec::new(),
            columns,
            errors: Vec::new(),
        })
    }

    /// Appends the row of case `index`: its values (one per column), or its error. Values
    /// of another length are an error in the row's place.
    pub fn push(&mut self, index: u64, row: Result<Vec<f64>, Error>) {
        let row = row.and_then(|values| {
            if values.len() == self.names.len() {
                Ok(values)
            } else {
                Err(Error::DimensionMismatch {
                    what: format!(
                        "case {index} has {} values for {} columns",
                        values.len(),
                        self.names.len()
                    ),
                })
            }
        });
        self.cases.push(index);
        match row {
            Ok(values) => {
                for (column, v) in self.columns.iter_mut().zip(values) {
                    column.push(v);
                }
                self.errors.push(None);
            }
            Err(e) => {
                self.cases.pop();
                self.push_failed(index, e.to_string());
            }
        }
    }

    /// Appends the row of case `index` that failed with the message `error` (its values
    /// NaN): a row read back from a file.
    pub fn push_failed(&mut self, index: u64, error: String) {
        self.cases.push(index);
        for column in &mut self.columns {
            column.push(f64::NAN);
        }
        self.errors.push(Some(error));
    }

    /// The rows of `other` after this table's (the shards of a study, in order); its columns
    /// must be the same.
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

    /// Each row's error message, `None` for a case that succeeded.
    pub fn errors(&self) -> &[Option<String>] {
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

    /// The CSV text: `case,<columns>,error`, then a line per row.
    pub fn write_csv<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        writeln!(w, "{CASE},{},{ERROR}", self.names.join(","))?;
        let mut line = String::new();
        for (i, case) in self.cases.iter().enumerate() {
            line.clear();
            let _ = write!(line, "{case}");
            for column in &self.columns {
                let _ = write!(line, ",{:?}", column[i]);
            }
            line.push(',');
            if let Some(e) = &self.errors[i] {
                // RFC 4180: quoted, a quote doubled.
                let _ = write!(line, "\"{}\"", e.replace('"', "\"\""));
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    }

    /// The table read back from [`Self::write_csv`]'s text (`source` names it in errors).
    pub fn parse_csv(text: &str, source: &str) -> Result<Table, Error> {
        let mut lines = records(text);
        let header = match lines.next() {
            Some((_, Ok(fields))) => fields,
            Some((line, Err(problem))) => return Err(table_error(source, line, "", problem)),
            None => return Err(table_error(source, 1, "", "the file is empty".into())),
        };
        let (first, last) = (header.first(), header.last());
        if header.len() < 2
            || first.map(String::as_str) != Some(CASE)
            || last.map(String::as_str) != Some(ERROR)
        {
            return Err(table_error(
                source,
                1,
                "",
                format!("a study table's header is `{CASE},<columns>,{ERROR}`"),
            ));
        }
        let mut table = Table::new(header[1..header.len() - 1].to_vec())?;
        for (line, fields) in lines {
            let fields = fields.map_err(|problem| table_error(source, line, "", problem))?;
            if fields.len() != header.len() {
                return Err(table_error(
                    source,
                    line,
                    "",
                    format!("{} fields for {} columns", fields.len(), header.len()),
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
            let mut values = Vec::with_capacity(header.len() - 2);
            for (name, field) in header[1..].iter().zip(&fields[1..fields.len() - 1]) {
                let v = field.parse::<f64>().map_err(|_| {
                    table_error(source, line, name, format!("`{field}` is not a number"))
                })?;
                values.push(v);
            }
            let error = &fields[fields.len() - 1];
            table.cases.push(case);
            for (column, v) in table.columns.iter_mut().zip(values) {
                column.push(v);
            }
            table
                .errors
                .push((!error.is_empty()).then(|| error.clone()));
        }
        Ok(table)
    }

    /// Writes the CSV to a file (created or truncated).
    pub fn save_csv(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        let io = |e: std::io::Error| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        };
        let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
        self.write_csv(&mut w).map_err(io)?;
        w.flush().map_err(io)
    }
}

/// Names must be usable as CSV column names, once each, and not the table's own.
fn check_names(names: &[String]) -> Result<(), Error> {
    for (i, name) in names.iter().enumerate() {
        let reason = if name.is_empty() {
            Some("a column needs a name")
        } else if name.contains([',', '"', '\n', '\r']) {
            Some("a column name may not contain a comma, a quote or a line break (CSV)")
        } else {
            None
        };
        if let Some(reason) = reason {
            return Err(Error::InvalidColumnName {
                name: name.clone(),
                reason,
            });
        }
        if names[..i].contains(name) || name == CASE || name == ERROR {
            return Err(Error::DuplicateName {
                kind: "column",
                name: name.clone(),
                context: "a study table's columns are `case`, then each named once, then `error`",
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

/// The records of CSV text with their line numbers: fields split at commas, RFC 4180 quotes
/// honoured within a line (a record spans one line), blank lines skipped.
fn records(text: &str) -> impl Iterator<Item = (usize, Result<Vec<String>, String>)> + '_ {
    text.lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.strip_suffix('\r').unwrap_or(line)))
        .filter(|(_, line)| !line.trim().is_empty())
        .map(|(n, line)| (n, fields(line)))
}

/// One line's fields.
fn fields(line: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut field = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut at_start = true;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (false, ',') => {
                out.push(std::mem::take(&mut field));
                at_start = true;
                continue;
            }
            (false, '"') if at_start => quoted = true,
            (false, '"') => return Err("a quote inside an unquoted field".into()),
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (_, c) => field.push(c),
        }
        at_start = false;
    }
    if quoted {
        return Err("a quoted field is not closed on its line".into());
    }
    out.push(field);
    Ok(out)
}

/// A study's cases read from CSV: a header of parameter names, then one row of numbers per
/// case. Every mistake is an error naming the line and the column: a name the study does
/// not know, or given twice; a missing value; a field that is not a finite number.
///
/// ```
/// use hamel_runtime::ParameterTable;
///
/// let table = ParameterTable::parse("trail,mass\n0.08,85\n0.1,90\n", "grid.csv", &["trail", "mass"])?;
/// assert_eq!((table.len(), table.get(1, "mass")), (2, Some(90.0)));
/// let e = ParameterTable::parse("trail,mass\n0.08,heavy\n", "grid.csv", &["trail", "mass"]).unwrap_err();
/// assert_eq!(e.to_string(), "grid.csv, line 2, column `mass`: `heavy` is not a number");
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterTable {
    names: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl ParameterTable {
    /// The table in `text` (`source` names it in errors, a path); its columns must be among
    /// `known`.
    pub fn parse(text: &str, source: &str, known: &[&str]) -> Result<ParameterTable, Error> {
        let mut lines = records(text);
        let names = match lines.next() {
            Some((_, Ok(names))) => names,
            Some((line, Err(problem))) => return Err(table_error(source, line, "", problem)),
            None => {
                return Err(table_error(
                    source,
                    1,
                    "",
                    "the table is empty: it needs a header of parameter names".into(),
                ));
            }
        };
        for (j, name) in names.iter().enumerate() {
            let name = name.trim();
            if !known.contains(&name) {
                return Err(table_error(
                    source,
                    1,
                    name,
                    format!(
                        "unknown column; the study's parameters are {}",
                        known.join(", ")
                    ),
                ));
            }
            if names[..j].iter().any(|n| n.trim() == name) {
                return Err(table_error(
                    source,
                    1,
                    name,
                    "the column is given twice".into(),
                ));
            }
        }
        let names: Vec<String> = names.iter().map(|n| n.trim().to_string()).collect();
        let mut rows = Vec::new();
        for (line, fields) in lines {
            let fields = fields.map_err(|problem| table_error(source, line, "", problem))?;
            if fields.len() > names.len() {
                return Err(table_error(
                    source,
                    line,
                    "",
                    format!("{} values for {} columns", fields.len(), names.len()),
                ));
            }
            let mut row = Vec::with_capacity(names.len());
            for (j, name) in names.iter().enumerate() {
                let field = fields.get(j).map_or("", |f| f.trim());
                if field.is_empty() {
                    return Err(table_error(
                        source,
                        line,
                        name,
                        "the value is missing".into(),
                    ));
                }
                match field.parse::<f64>() {
                    Ok(v) if v.is_finite() => row.push(v),
                    Ok(_) => {
                        return Err(table_error(
                            source,
                            line,
                            name,
                            format!("`{field}` is not a finite number"),
                        ));
                    }
                    Err(_) => {
                        return Err(table_error(
                            source,
                            line,
                            name,
                            format!("`{field}` is not a number"),
                        ));
                    }
                }
            }
            rows.push(row);
        }
        Ok(ParameterTable { names, rows })
    }

    /// The table in the file at `path`.
    pub fn read(path: impl AsRef<Path>, known: &[&str]) -> Result<ParameterTable, Error> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        ParameterTable::parse(&text, &path.display().to_string(), known)
    }

    /// A table of these columns and rows (each as long as the names), as a study builds its
    /// grid; [`Self::to_csv`] writes it for the shards to read.
    pub fn from_rows(names: Vec<String>, rows: Vec<Vec<f64>>) -> Result<ParameterTable, Error> {
        check_names(&names)?;
        if let Some(i) = rows.iter().position(|r| r.len() != names.len()) {
            return Err(Error::DimensionMismatch {
                what: format!(
                    "row {i} has {} values for {} columns",
                    rows[i].len(),
                    names.len()
                ),
            });
        }
        Ok(ParameterTable { names, rows })
    }

    /// The column names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The number of rows (cases).
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// Row i's values, in the order of [`Self::names`].
    pub fn row(&self, i: usize) -> Option<&[f64]> {
        self.rows.get(i).map(Vec::as_slice)
    }

    /// Row i's value of the column `name`, if both exist.
    pub fn get(&self, i: usize, name: &str) -> Option<f64> {
        let j = self.names.iter().position(|n| n == name)?;
        self.rows.get(i).map(|r| r[j])
    }

    /// The CSV text, numbers exact (they read back to the same bits).
    pub fn to_csv(&self) -> String {
        let mut text = self.names.join(",");
        text.push('\n');
        for row in &self.rows {
            let fields: Vec<String> = row.iter().map(|v| format!("{v:?}")).collect();
            text.push_str(&fields.join(","));
            text.push('\n');
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_fields_follow_rfc_4180() {
        assert_eq!(fields("a,b,,c").unwrap(), ["a", "b", "", "c"]);
        assert_eq!(
            fields("1,\"x, \"\"y\"\"\",2").unwrap(),
            ["1", "x, \"y\"", "2"]
        );
        assert!(fields("1,\"open").is_err());
        assert!(fields("1,a\"b").is_err());
    }

    #[test]
    fn tables_round_trip_through_csv_bit_for_bit() {
        let mut t = Table::new(vec!["a".into(), "b".into()]).unwrap();
        t.push(3, Ok(vec![0.1 + 0.2, -1e-300]));
        t.push(
            4,
            Err(Error::InvalidSetting {
                name: "x",
                value: 1.0,
                reason: "a \"quoted\", comma",
            }),
        );
        t.push(5, Ok(vec![1.0]));
        let mut text = Vec::new();
        t.write_csv(&mut text).unwrap();
        let text = String::from_utf8(text).unwrap();
        assert!(text.starts_with("case,a,b,error\n3,0.30000000000000004,-1e-300,\n4,NaN,NaN,\""));
        let back = Table::parse_csv(&text, "t.csv").unwrap();
        assert_eq!(back.cases(), [3, 4, 5]);
        assert_eq!(back.errors(), t.errors());
        assert_eq!(back.row(0), t.row(0));
        assert!(
            back.errors()[2]
                .as_deref()
                .unwrap()
                .contains("1 values for 2 columns")
        );
        assert_eq!(back.failed(), 2);
    }

    #[test]
    fn bad_column_names_are_refused() {
        for bad in ["", "a,b", "case", "error"] {
            assert!(Table::new(vec![bad.into()]).is_err(), "{bad:?}");
        }
        assert!(Table::new(vec!["a".into(), "a".into()]).is_err());
    }
}
