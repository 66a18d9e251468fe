//! A study's command line: what each option means, and every mistake refused with a message
//! before any case runs.

use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use crate::ensemble::{
    Shard, ShardState, Written, check_writable, remove_leftovers, shard_state, write_complete,
    write_shard,
};
use crate::{Error, ParameterTable, Table};

use super::output::{Format, Sink, default_path, merge, stamp};
use super::{Finished, Study, array, stream};

/// Which shard a task runs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ShardSpec {
    Given(Shard),
    /// From a job array's environment, with the count if given (`env/8`).
    Environment(Option<usize>),
}

/// What the command line asks for.
#[derive(Debug, PartialEq)]
struct Settings {
    write_grid: Option<PathBuf>,
    table: Option<PathBuf>,
    shard: Option<ShardSpec>,
    out: Option<PathBuf>,
    merge: Option<PathBuf>,
    into: Option<PathBuf>,
    threads: Option<usize>,
    format: Format,
}

/// Runs the study as `args` ask; see [`Study::main`].
pub(crate) fn main(study: &Study, args: &[String]) -> ExitCode {
    let (mut out, mut err) = (std::io::stdout(), std::io::stderr());
    main_to(study, args, &mut Console::new(&mut out, &mut err))
}

/// [`main`], its messages written to `console`.
pub(crate) fn main_to(study: &Study, args: &[String], console: &mut Console) -> ExitCode {
    let settings = match parse(args) {
        Ok(Some(s)) => s,
        Ok(None) => {
            console.out(&help(study));
            return ExitCode::SUCCESS;
        }
        Err(message) => {
            console.err(&format!("error: {message}\n"));
            return ExitCode::from(2);
        }
    };
    match run(study, &settings, console) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            console.err(&format!("error: {e}\n"));
            ExitCode::FAILURE
        }
    }
}

/// Where the command line's messages go. They only report on the files, which are written
/// whole whatever happens to them: a closed standard output (`study | head -1`) or error
/// stream loses them and fails nothing (`println!` panics there).
pub(crate) struct Console<'w> {
    out: &'w mut dyn Write,
    err: &'w mut dyn Write,
}

impl<'w> Console<'w> {
    pub(crate) fn new(out: &'w mut dyn Write, err: &'w mut dyn Write) -> Self {
        Console { out, err }
    }

    /// `text` on the standard output, if it can be written.
    fn out(&mut self, text: &str) {
        let _ = self
            .out
            .write_all(text.as_bytes())
            .and_then(|()| self.out.flush());
    }

    /// `line` and a line break on the standard output.
    fn say(&mut self, line: &str) {
        self.out(&format!("{line}\n"));
    }

    /// `text` on the standard error stream, if it can be written.
    fn err(&mut self, text: &str) {
        let _ = self
            .err
            .write_all(text.as_bytes())
            .and_then(|()| self.err.flush());
    }

    /// The summary of the cases that panicked, if any did.
    fn panics(&mut self, summary: Option<&str>) {
        if let Some(summary) = summary {
            self.err(&format!("{summary}\n"));
        }
    }
}

/// The `--help` text: the study, its options, its parameters and outputs with their units.
fn help(study: &Study) -> String {
    let name = study.name();
    let mut text = format!("{}\n\nUsage: {name} [options]\n", study.about);
    let _ = write!(
        text,
        "  (no options)             the default grid here: {name}.csv (or .parquet), then the report
  --write-grid FILE        write the default grid as a parameter table
  --table FILE --out DIR   run the table's cases (one of its shards) into DIR/shard-<i>-of-<n>.csv;
                           a shard whose file and manifest are complete is skipped, any other
                           computed again
  --shard i/n              shard i of n (0 <= i < n; default 0/1)
  --shard env[/n]          the shard of this task of a Slurm, PBS or LSF job array (n: the
                           array's size, which PBS does not give)
  --table FILE --merge DIR join the complete shards in DIR into one file ({name}.csv, or --into FILE)
  --format csv|parquet     the files' format (default csv; parquet needs hamel's feature `parquet`)
  --threads N              threads (default: every core)
  --help                   this text
An option's value follows it, or an `=` (`--threads=2`).

Parameters (the table's columns):
"
    );
    let line = |c: &super::Column| {
        let unit = if c.unit.is_empty() {
            String::new()
        } else {
            format!(" [{}]", c.unit)
        };
        format!("  {:<24} {}{unit}\n", c.name, c.description)
    };
    for (c, values) in &study.parameters {
        text.push_str(&line(c));
        let _ = writeln!(text, "  {:<24} default grid: {} values", "", values.len());
    }
    text.push_str("Outputs (the result's columns after the parameters, then error_kind, error):\n");
    for c in &study.outputs {
        text.push_str(&line(c));
    }
    text
}

/// The options that take a value.
const OPTIONS: [&str; 8] = [
    "--write-grid",
    "--table",
    "--shard",
    "--out",
    "--merge",
    "--into",
    "--format",
    "--threads",
];

/// The options that name a file or a directory: never empty (an empty path would be the
/// current directory).
const PATHS: [&str; 5] = ["--write-grid", "--table", "--out", "--merge", "--into"];

/// Parses the options, each `--name value` or `--name=value`; `None` for `--help`. Every
/// mistake is a message, never a panic.
fn parse(args: &[String]) -> Result<Option<Settings>, String> {
    let mut s = Settings {
        write_grid: None,
        table: None,
        shard: None,
        out: None,
        merge: None,
        into: None,
        threads: None,
        format: Format::Csv,
    };
    let mut rest = args.iter();
    while let Some(arg) = rest.next() {
        let (option, inline) = match arg.split_once('=') {
            Some((option, value)) if option.starts_with("--") => (option, Some(value)),
            _ => (arg.as_str(), None),
        };
        if option == "--help" || option == "-h" {
            return match inline {
                Some(_) => Err(format!("--help takes no value, not `{arg}`")),
                None => Ok(None),
            };
        }
        if !option.starts_with("--") {
            return Err(format!(
                "`{arg}` is not an option: options begin with `--`, and each takes one value \
                 (see --help)"
            ));
        }
        if !OPTIONS.contains(&option) {
            return Err(format!("unknown option `{option}` (see --help)"));
        }
        let value = match inline {
            Some(value) => value,
            None => match rest.next() {
                Some(next) if next.starts_with("--") && next.len() > 2 => {
                    return Err(format!(
                        "option `{option}` needs a value, not the option `{next}` (see --help)"
                    ));
                }
                Some(next) => next.as_str(),
                None => return Err(format!("option `{option}` needs a value (see --help)")),
            },
        };
        if value.is_empty() && PATHS.contains(&option) {
            return Err(format!(
                "{option} needs a path, not '' (an empty path would be the current directory)"
            ));
        }
        match option {
            "--write-grid" => s.write_grid = Some(value.into()),
            "--table" => s.table = Some(value.into()),
            "--shard" => s.shard = Some(shard_spec(value)?),
            "--out" => s.out = Some(value.into()),
            "--merge" => s.merge = Some(value.into()),
            "--into" => s.into = Some(value.into()),
            "--format" => s.format = Format::from_name(value)?,
            _ => match value.parse::<usize>() {
                Ok(n) if n > 0 => s.threads = Some(n),
                _ => return Err(format!("--threads needs a whole number ≥ 1, not `{value}`")),
            },
        }
    }
    check(&s)?;
    Ok(Some(s))
}

/// `i/n`, `env` or `env/n`.
fn shard_spec(value: &str) -> Result<ShardSpec, String> {
    match value.strip_prefix("env") {
        Some("") => Ok(ShardSpec::Environment(None)),
        Some(rest) => match rest.strip_prefix('/').map(|n| n.parse::<usize>()) {
            Some(Ok(n)) if n > 0 => Ok(ShardSpec::Environment(Some(n))),
            _ => Err(format!(
                "--shard `{value}`: the array's size after `env/` is a whole number ≥ 1 (`env/8`)"
            )),
        },
        None => Shard::parse(value)
            .map(ShardSpec::Given)
            .map_err(|e| e.to_string()),
    }
}

/// Options that go together, and only those.
fn check(s: &Settings) -> Result<(), String> {
    if s.write_grid.is_some()
        && (s.table.is_some() || s.out.is_some() || s.shard.is_some() || s.merge.is_some())
    {
        return Err("--write-grid writes the grid and does nothing else: give it alone".into());
    }
    if (s.shard.is_some() || s.out.is_some()) && s.table.is_none() {
        return Err(
            "--shard and --out run a parameter table's cases: give the table with \
                    --table FILE (write the study's grid as one with --write-grid FILE)"
                .into(),
        );
    }
    if s.merge.is_some() && (s.out.is_some() || s.shard.is_some()) {
        return Err(
            "--merge joins finished shards: give it with --table FILE alone (and \
                    --into FILE), not with --out or --shard"
                .into(),
        );
    }
    if s.into.is_some() && s.merge.is_none() {
        return Err("--into names the file --merge writes: give it with --merge DIR".into());
    }
    if s.table.is_some() && s.out.is_none() && s.merge.is_none() {
        return Err(
            "--table needs --out DIR, where its shard's file is written (or --merge \
                    DIR, to join the shards there)"
                .into(),
        );
    }
    Ok(())
}

/// Does what the settings ask.
fn run(study: &Study, s: &Settings, console: &mut Console) -> Result<(), Error> {
    study.check()?;
    if let Some(path) = &s.write_grid {
        let grid = study.grid()?;
        write_complete(path, |file| {
            file.write_all(grid.to_csv().as_bytes())
                .map_err(|e| super::output::io(path, e))
        })?;
        console.say(&format!("wrote {} cases to {}", grid.len(), path.display()));
        return Ok(());
    }
    match (&s.table, &s.out, &s.merge) {
        (Some(table), Some(out), _) => shard_task(study, s, table, out, console),
        (Some(table), None, Some(dir)) => {
            let cases = read_table(study, table)?;
            let into = s
                .into
                .clone()
                .unwrap_or_else(|| default_path(study, s.format));
            let (rows, shards) = merge(study, &cases, dir, s.format, &into)?;
            console.say(&format!(
                "merged {shards} shards ({rows} rows) of {} into {}",
                dir.display(),
                into.display()
            ));
            Ok(())
        }
        _ => local(study, s, console),
    }
}

/// The parameter table at `path`, its columns the study's parameters.
fn read_table(study: &Study, path: &Path) -> Result<ParameterTable, Error> {
    let names = study.parameter_names();
    let known: Vec<&str> = names.iter().map(String::as_str).collect();
    ParameterTable::read(path, &known)
}

/// One task of a batch engine: its shard of the table at `table` into `out`.
fn shard_task(
    study: &Study,
    s: &Settings,
    table: &Path,
    out: &Path,
    console: &mut Console,
) -> Result<(), Error> {
    // Everything that can be refused is refused before any case runs.
    let shard = match s.shard.unwrap_or(ShardSpec::Given(Shard::ALL)) {
        ShardSpec::Given(shard) => shard,
        ShardSpec::Environment(count) => {
            array::shard_from_environment(count, |name| std::env::var(name).ok())?
        }
    };
    check_writable(out)?;
    let cases = read_table(study, table)?;
    let path = out.join(shard.file_name(s.format.extension()));
    let stamp = stamp(study, &cases, shard, s.format);
    match shard_state(&path, &stamp) {
        ShardState::Complete => {
            remove_leftovers(&path);
            console.say(&format!("{} is complete: nothing to do", path.display()));
            return Ok(());
        }
        ShardState::Incomplete(why) => {
            console.say(&format!(
                "{} is not complete ({why}): computing it again",
                path.display()
            ));
        }
        ShardState::Missing => {}
    }
    let rows = shard.rows(cases.len());
    let started = Instant::now();
    let mut done = None;
    let written = write_shard(&path, &stamp, |file| {
        let mut sink = Sink::open(s.format, file, study, &path)?;
        let mut write = |block: &Table| sink.write(block, &path);
        done = Some(stream::run(
            study,
            &cases,
            rows.clone(),
            s.threads,
            true,
            &mut write,
        )?);
        sink.finish(&path)
    })?;
    let failed = done.as_ref().map_or(0, |d| d.failed);
    console.panics(done.and_then(|d| d.panics).as_deref());
    let by = match written {
        Written::Written => "wrote",
        Written::ByAnother => "another task given the same shard completed",
    };
    console.say(&format!(
        "shard {}/{}: rows {}..{} of {}, {failed} failed, in {:.1} s; {by} {}",
        shard.index,
        shard.count,
        rows.start,
        rows.end,
        cases.len(),
        started.elapsed().as_secs_f64(),
        path.display()
    ));
    Ok(())
}

/// The default grid on this machine, into `<name>.<format>`, then the study's report.
fn local(study: &Study, s: &Settings, console: &mut Console) -> Result<(), Error> {
    let cases = study.grid()?;
    let path = default_path(study, s.format);
    let mut all = Table::new(study.columns())?;
    let started = Instant::now();
    let mut done = None;
    write_complete(&path, |file| {
        let mut sink = Sink::open(s.format, file, study, &path)?;
        let mut write = |block: &Table| {
            sink.write(block, &path)?;
            all.append(block.clone())
        };
        done = Some(stream::run(
            study,
            &cases,
            0..cases.len(),
            s.threads,
            true,
            &mut write,
        )?);
        sink.finish(&path)
    })?;
    let elapsed = started.elapsed();
    let threads_used = done.as_ref().map_or(1, |d| d.threads);
    console.panics(done.and_then(|d| d.panics).as_deref());
    console.say(&format!(
        "{}: {} cases, {} failed, in {:.2} s on {threads_used} threads; wrote {} ({})",
        study.name(),
        all.len(),
        all.failed(),
        elapsed.as_secs_f64(),
        path.display(),
        [crate::ensemble::CASE_COLUMN]
            .into_iter()
            .map(String::from)
            .chain(study.columns())
            .chain(["error_kind".into(), "error".into()])
            .collect::<Vec<_>>()
            .join(",")
    ));
    match &study.report {
        Some(report) => report(&Finished {
            table: &all,
            path: &path,
            threads: s.threads,
            threads_used,
            elapsed,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(line: &str) -> Vec<String> {
        line.split_whitespace().map(String::from).collect()
    }

    /// Before, `--shard`/`--out` without `--table` ran the whole grid into the current
    /// directory and exited 0.
    #[test]
    fn options_that_do_not_go_together_are_refused() {
        for (line, says) in [
            (
                "--shard 0/2 --out results",
                "give the table with --table FILE",
            ),
            ("--out results", "give the table with --table FILE"),
            ("--table grid.csv", "--table needs --out DIR"),
            (
                "--write-grid g.csv --table grid.csv --out r",
                "give it alone",
            ),
            (
                "--table g.csv --merge r --shard 1/2",
                "not with --out or --shard",
            ),
            ("--into all.csv", "give it with --merge DIR"),
            ("--threads 0", "whole number ≥ 1"),
            ("--shard 2/2 --table g.csv --out r", "out of range"),
            ("--shard env/0 --table g.csv --out r", "`env/8`"),
            ("--format xlsx", "not `xlsx`"),
            ("--colour red", "unknown option `--colour`"),
            ("--table", "needs a value"),
        ] {
            let e = parse(&args(line)).unwrap_err();
            assert!(e.contains(says), "{line}: {e}");
        }
        let s = parse(&args("--table g.csv --out r --shard env/8 --threads 2"))
            .unwrap()
            .unwrap();
        assert_eq!(s.shard, Some(ShardSpec::Environment(Some(8))));
        assert_eq!(parse(&args("--help")).unwrap(), None);
    }

    /// Before, `--threads=2` was "unknown option `--threads=2`" (or, last, "needs a value"),
    /// a trailing unknown option "needs a value", and an empty path was taken as the current
    /// directory (`--out ''` wrote the shard there).
    #[test]
    fn options_are_read_as_a_user_writes_them() {
        let s = parse(&args("--table=g.csv --out=r --threads=2 --shard=1/4"))
            .unwrap()
            .unwrap();
        assert_eq!(s.threads, Some(2));
        assert_eq!(s.table, Some(PathBuf::from("g.csv")));
        assert_eq!(
            s.shard,
            Some(ShardSpec::Given(Shard { index: 1, count: 4 }))
        );
        for (line, says) in [
            ("--threads=0", "whole number ≥ 1, not `0`"),
            (
                "--table g.csv --out r --colour",
                "unknown option `--colour`",
            ),
            (
                "--table g.csv --out r --colour=red",
                "unknown option `--colour`",
            ),
            (
                "--table g.csv --out r results",
                "`results` is not an option",
            ),
            ("--help=yes", "--help takes no value"),
        ] {
            let e = parse(&args(line)).unwrap_err();
            assert!(e.contains(says), "{line}: {e}");
            assert!(!e.contains("needs a value"), "{line}: {e}");
        }
        // `--threads=2` alone is a complete command line: the default grid on two threads.
        assert_eq!(
            parse(&args("--threads=2")).unwrap().unwrap().threads,
            Some(2)
        );
        for option in ["--out", "--table", "--merge", "--into", "--write-grid"] {
            let mut line = match option {
                "--out" => args("--table g.csv"),
                "--merge" => args("--table g.csv"),
                "--into" => args("--table g.csv --merge r"),
                _ => Vec::new(),
            };
            line.extend([option.to_string(), String::new()]);
            let e = parse(&line).unwrap_err();
            assert!(e.contains(&format!("{option} needs a path, not ''")), "{e}");
        }
    }

    /// Before, the format depended on whether the binary was last built with the feature.
    #[test]
    fn the_format_is_chosen_when_the_program_runs() {
        let s = parse(&args("--table g.csv --out r")).unwrap().unwrap();
        assert_eq!(s.format, Format::Csv);
        let parquet = parse(&args("--table g.csv --out r --format parquet"));
        if cfg!(feature = "parquet") {
            assert_eq!(parquet.unwrap().unwrap().format, Format::Parquet);
        } else {
            let e = parquet.unwrap_err();
            assert!(
                e.contains("feature `parquet`") && e.contains("--features parquet"),
                "{e}"
            );
        }
    }
}
