//! Where a simulation's samples go as they are produced: into memory (a [`crate::Trajectory`])
//! or streamed to a writer ([`CsvSink`]), so that a run of 10⁸ samples needs no more memory
//! than one of ten.

use std::io::Write;

use crate::error::Error;
use crate::events::EventRecord;
use crate::whole_file::WholeFile;

/// A destination of a simulation's samples: the column names first, then one row per sample
/// in time order, and the events as they are located (between the rows of their step).
pub trait Sink {
    /// The column names, once, before any row.
    fn begin(&mut self, columns: &[String]) -> Result<(), Error>;
    /// One sample, one value per column.
    fn row(&mut self, values: &[f64]) -> Result<(), Error>;
    /// An event (default: ignored).
    fn event(&mut self, _event: &EventRecord) -> Result<(), Error> {
        Ok(())
    }
    /// The run is over (flush what is buffered).
    fn end(&mut self) -> Result<(), Error> {
        Ok(())
    }
}

/// Streams samples as CSV: a header of the column names, then a line per sample, numbers in
/// Rust's shortest form that reads back to the same `f64` (as `Trajectory::write_csv`).
/// Buffered; events are not written (see [`crate::Simulation::stream`] for where they go).
pub struct CsvSink<W: Write> {
    out: std::io::BufWriter<W>,
    name: String,
    rows: usize,
    /// What the end of the run does to the writer besides flushing it: a file of
    /// [`CsvSink::create`] is renamed to its path and given its manifest.
    finish: Option<Finish<W>>,
}

/// What ends a file sink's run: the writer and the rows written.
type Finish<W> = fn(&mut W, u64) -> Result<(), Error>;

impl<W: Write> CsvSink<W> {
    /// A CSV stream into `writer`; `name` names it in I/O errors (a path, "standard output").
    pub fn new(writer: W, name: impl Into<String>) -> Self {
        CsvSink {
            out: std::io::BufWriter::new(writer),
            name: name.into(),
            rows: 0,
            finish: None,
        }
    }

    /// The rows written so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    fn io(&self, e: std::io::Error) -> Error {
        Error::Io {
            path: self.name.clone(),
            message: e.to_string(),
        }
    }
}

impl CsvSink<WholeFile> {
    /// A CSV stream into the file `path`, whole or not at all: the rows go to a file of its
    /// own beside `path`, which the end of the run flushes to disk and renames to `path`
    /// (replacing a file there), with its manifest `<path>.manifest` (the row count, size and
    /// checksum, [`crate::whole_file`]). A run that fails or is stopped leaves no file (and
    /// what was at `path` before).
    pub fn create(path: impl AsRef<std::path::Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let mut sink = CsvSink::new(WholeFile::create(path)?, path.display().to_string());
        sink.finish = Some(|file, rows| file.commit(rows));
        Ok(sink)
    }
}

impl<W: Write> Sink for CsvSink<W> {
    fn begin(&mut self, columns: &[String]) -> Result<(), Error> {
        writeln!(self.out, "{}", columns.join(",")).map_err(|e| self.io(e))
    }

    fn row(&mut self, values: &[f64]) -> Result<(), Error> {
        let result = (|| {
            for (j, v) in values.iter().enumerate() {
                if j > 0 {
                    self.out.write_all(b",")?;
                }
                write!(self.out, "{v:?}")?;
            }
            self.out.write_all(b"\n")
        })();
        result.map_err(|e| self.io(e))?;
        self.rows += 1;
        Ok(())
    }

    fn end(&mut self) -> Result<(), Error> {
        self.out.flush().map_err(|e| self.io(e))?;
        match self.finish.take() {
            Some(finish) => finish(self.out.get_mut(), self.rows as u64),
            None => Ok(()),
        }
    }
}
