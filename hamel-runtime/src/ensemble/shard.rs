//! Splitting a study among the tasks of a batch engine: shard i of n takes a contiguous
//! block of the table's rows, so that the shards' tables, concatenated in order, are the
//! table one task would write.
//!
//! A shard's file counts as complete only when its manifest says so: written after the data
//! (each by atomic rename, after a flush to disk), it holds the hash of what the shard was
//! computed from ([`ShardStamp`]: the parameter table, the shard, the study's columns and
//! format), the row count, and the data file's size and checksum (XXH3). A file without its
//! manifest (a task killed while writing), a truncated or altered one, or one of another grid
//! (the table edited since) is recomputed. Every writer writes under a name of its own and
//! renames, so two tasks given the same shard leave one complete file.

use std::hash::Hasher as _;
use std::io::{BufWriter, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

use twox_hash::XxHash3_64;

use crate::error::Error;
use crate::whole_file::{
    checksum, partial_path, remove_dead_leftovers, sync_directory, with_suffix,
};

/// Shard `index` of `count` (0 ≤ index < count): `Shard::parse("3/8")`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole study as one shard.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// `i/n`, as given on a command line (a Slurm array's `$SLURM_ARRAY_TASK_ID/n`).
    pub fn parse(spec: &str) -> Result<Shard, Error> {
        let invalid = |reason| Error::InvalidShard {
            spec: spec.to_string(),
            reason,
        };
        let (i, n) = spec
            .split_once('/')
            .ok_or_else(|| invalid("is not of the form i/n"))?;
        let parse = |s: &str| s.trim().parse::<usize>();
        let (index, count) = match (parse(i), parse(n)) {
            (Ok(i), Ok(n)) => (i, n),
            _ => return Err(invalid("does not have whole numbers on both sides of `/`")),
        };
        Shard::new(index, count).map_err(|_| {
            invalid(if count == 0 {
                "has no parts (n = 0)"
            } else {
                "is out of range: i must be less than n"
            })
        })
    }

    /// Shard `index` of `count`, checked: 0 ≤ index < count.
    pub fn new(index: usize, count: usize) -> Result<Shard, Error> {
        if index < count {
            Ok(Shard { index, count })
        } else {
            Err(Error::InvalidShard {
                spec: format!("{index}/{count}"),
                reason: if count == 0 {
                    "has no parts (n = 0)"
                } else {
                    "is out of range: i must be less than n"
                },
            })
        }
    }

    /// The rows of a table of `total` rows this shard takes: a contiguous block, the blocks
    /// of the n shards covering the table in order, their sizes differing by one at most.
    pub fn rows(&self, total: usize) -> Range<usize> {
        let at = |k: usize| (total as u128 * k as u128 / self.count as u128) as usize;
        at(self.index)..at(self.index + 1)
    }

    /// The shard's file name, `shard-0003-of-0008.<extension>`: both numbers padded to the
    /// digits of n − 1 (at least four), so that the names of one study's shards sort in shard
    /// order for any n (`shard-00003-of-12000`).
    pub fn file_name(&self, extension: &str) -> String {
        let width = (self.count.saturating_sub(1).max(1).ilog10() as usize + 1).max(4);
        format!(
            "shard-{:0width$}-of-{:0width$}.{extension}",
            self.index, self.count
        )
    }
}

/// What a shard's file must have been computed from to count as complete: a hash of the
/// parameter table, the shard, the study's columns and the format
/// ([`ShardStamp::new`]), the number of rows, and the program that computes it
/// ([`Program`]). Two shards of one study from different programs are never mixed: a
/// shard written by another program counts as incomplete, and is computed again, or makes a
/// merge stop, naming the difference.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShardStamp {
    pub grid: u64,
    pub rows: u64,
    pub program: Program,
}

/// The program a shard was computed by, as its manifest records it in words: the study's
/// name, the program's version (the one its user set, or else a hash of the running
/// executable, so that any rebuild that changes it counts as another program), and hamel's
/// version.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    pub study: String,
    pub version: String,
    pub hamel: String,
}

impl Program {
    /// The program `version` of the study `study` (`None`: the running executable's hash,
    /// [`Program::executable_version`]), with this hamel's version.
    pub fn new(study: &str, version: Option<&str>) -> Program {
        Program {
            study: one_line(study),
            version: version.map_or_else(Program::executable_version, one_line),
            hamel: env!("CARGO_PKG_VERSION").to_string(),
        }
    }

    /// `executable <xxh3>`: the hash of the running program's file, so that a rebuild that
    /// changes the program changes it (`executable unknown` where the file cannot be read).
    pub fn executable_version() -> String {
        static HASH: std::sync::OnceLock<String> = std::sync::OnceLock::new();
        HASH.get_or_init(|| {
            let hash = std::env::current_exe()
                .and_then(|path| crate::whole_file::checksum(&path))
                .map_or_else(|_| "unknown".to_string(), |(_, h)| format!("{h:016x}"));
            format!("executable {hash}")
        })
        .clone()
    }

    /// Why a shard of `other` is not one of this program, if it is not.
    fn differs(&self, other: &Program) -> Option<String> {
        let pairs = [
            ("the study", &self.study, &other.study),
            ("the program's version", &self.version, &other.version),
            ("hamel's version", &self.hamel, &other.hamel),
        ];
        let (what, ours, theirs) = pairs.into_iter().find(|(_, a, b)| a != b)?;
        Some(format!(
            "it was computed by another program: {what} is `{theirs}` in its manifest and \
             `{ours}` here; shards of different programs are not mixed (run its task again with \
             this program, or merge with the one that wrote it)"
        ))
    }
}

/// `text` on one line, for a manifest.
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}

impl ShardStamp {
    /// The stamp of shard `shard` of a study of `columns`, written as `format` by `program`,
    /// whose parameter table has the column names `names` and the rows `rows` (all of them,
    /// not only the shard's: a table edited anywhere moves every shard's rows).
    pub fn new<'a>(
        names: &[String],
        rows: impl IntoIterator<Item = &'a [f64]>,
        shard: Shard,
        columns: &[String],
        format: &str,
        program: Program,
    ) -> ShardStamp {
        let mut h = XxHash3_64::with_seed(0);
        let text = |h: &mut XxHash3_64, s: &str| {
            h.write_u64(s.len() as u64);
            h.write(s.as_bytes());
        };
        text(&mut h, "hamel study shard 1");
        for name in names {
            text(&mut h, name);
        }
        let mut total = 0usize;
        for row in rows {
            for v in row {
                h.write_u64(v.to_bits());
            }
            total += 1;
        }
        h.write_u64(total as u64);
        h.write_u64(shard.index as u64);
        h.write_u64(shard.count as u64);
        for column in columns {
            text(&mut h, column);
        }
        text(&mut h, format);
        ShardStamp {
            grid: h.finish(),
            rows: shard.rows(total).len() as u64,
            program,
        }
    }
}

/// Whether a shard's file is complete, and if not, why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShardState {
    /// The file and its manifest are there and agree with each other and with the stamp.
    Complete,
    /// Neither is there: the shard has not been written.
    Missing,
    /// Something is there but not a complete shard of this study: the reason.
    Incomplete(String),
}

/// The manifest's name: beside the file, `.manifest` added.
pub fn manifest_path(path: &Path) -> PathBuf {
    with_suffix(path, ".manifest")
}

/// The state of the shard file at `path` against `stamp`.
pub fn shard_state(path: impl AsRef<Path>, stamp: &ShardStamp) -> ShardState {
    let path = path.as_ref();
    let manifest = match std::fs::read_to_string(manifest_path(path)) {
        Ok(text) => text,
        Err(_) if path.exists() => {
            return ShardState::Incomplete(
                "it has no manifest (its task was stopped before it finished)".into(),
            );
        }
        Err(_) => return ShardState::Missing,
    };
    if manifest.starts_with(OLDER_SHARD_MANIFEST_HEADER) {
        return ShardState::Incomplete(
            "it was computed by an older hamel, whose manifest does not record the program; \
             shards of different programs are not mixed"
                .into(),
        );
    }
    let Some(m) = Manifest::parse(&manifest) else {
        return ShardState::Incomplete("its manifest is not one hamel wrote".into());
    };
    if let Some(why) = stamp.program.differs(&m.program) {
        return ShardState::Incomplete(why);
    }
    if m.grid != stamp.grid {
        return ShardState::Incomplete(
            "it was computed from another parameter table or study (its manifest's grid hash \
             differs)"
                .into(),
        );
    }
    if m.rows != stamp.rows {
        return ShardState::Incomplete(format!(
            "its manifest says {} rows, the shard has {}",
            m.rows, stamp.rows
        ));
    }
    match checksum(path) {
        Ok((bytes, _)) if bytes != m.bytes => ShardState::Incomplete(format!(
            "it has {bytes} bytes, its manifest says {} (truncated or altered)",
            m.bytes
        )),
        Ok((_, sum)) if sum != m.checksum => {
            ShardState::Incomplete("its checksum differs from its manifest's (altered)".into())
        }
        Ok(_) => ShardState::Complete,
        Err(e) => ShardState::Incomplete(format!("it cannot be read: {e}")),
    }
}

/// What a manifest records.
struct Manifest {
    program: Program,
    grid: u64,
    rows: u64,
    bytes: u64,
    checksum: u64,
}

/// How a shard manifest's first line begins, before its version.
pub(crate) const SHARD_MANIFEST: &str = "hamel shard manifest ";
/// A shard manifest's first line.
const SHARD_MANIFEST_HEADER: &str = "hamel shard manifest 2";
/// That of hamel's manifests before they recorded the program.
const OLDER_SHARD_MANIFEST_HEADER: &str = "hamel shard manifest 1";

impl Manifest {
    fn text(&self, file: &str) -> String {
        let p = &self.program;
        format!(
            "{SHARD_MANIFEST_HEADER}\nfile {file}\nstudy {}\nprogram {}\nhamel {}\ngrid \
             {:016x}\nrows {}\nbytes {}\nxxh3 {:016x}\n",
            p.study, p.version, p.hamel, self.grid, self.rows, self.bytes, self.checksum
        )
    }

    fn parse(text: &str) -> Option<Manifest> {
        let mut lines = text.lines();
        if lines.next()? != SHARD_MANIFEST_HEADER {
            return None;
        }
        let mut word = |key: &str| -> Option<String> {
            let line = lines.find(|l| l.starts_with(key))?;
            Some(line.strip_prefix(key)?.to_string())
        };
        let program = Program {
            study: word("study ")?,
            version: word("program ")?,
            hamel: word("hamel ")?,
        };
        let mut field = |key: &str, radix: u32| -> Option<u64> {
            u64::from_str_radix(word(key)?.trim(), radix).ok()
        };
        Some(Manifest {
            grid: field("grid ", 16)?,
            rows: field("rows ", 10)?,
            bytes: field("bytes ", 10)?,
            checksum: field("xxh3 ", 16)?,
            program,
        })
    }
}

/// A shard's file while it is written: buffered, its bytes counted and checksummed.
pub struct ShardFile {
    file: BufWriter<std::fs::File>,
    hasher: XxHash3_64,
    bytes: u64,
}

impl Write for ShardFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.hasher.write(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// How a shard's writing ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Written {
    /// This task wrote it.
    Written,
    /// Another task given the same shard completed it while this one was writing.
    ByAnother,
}

/// Writes a shard's file whole or not at all, and then its manifest: `write` fills a file
/// of this task's own beside `path`, which is flushed to disk and renamed to `path`; the
/// manifest (`stamp`, the file's size and checksum) is then written and renamed the same way.
/// A task killed at any point leaves no manifest that describes a file other than the one
/// beside it. Leftover files of killed tasks (`<name>.partial-*`) are removed afterwards.
pub fn write_shard(
    path: impl AsRef<Path>,
    stamp: &ShardStamp,
    write: impl FnOnce(&mut ShardFile) -> Result<(), Error>,
) -> Result<Written, Error> {
    let path = path.as_ref();
    let io = |p: &Path, e: std::io::Error| Error::Io {
        path: p.display().to_string(),
        message: e.to_string(),
    };
    let (bytes, checksum) = match write_renamed(path, write)? {
        Some(done) => done,
        None => return by_another(path, stamp),
    };
    let manifest = Manifest {
        program: stamp.program.clone(),
        grid: stamp.grid,
        rows: stamp.rows,
        bytes,
        checksum,
    };
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let text = manifest.text(&name);
    let written = write_renamed(&manifest_path(path), |f| {
        f.write_all(text.as_bytes()).map_err(|e| io(path, e))
    })?;
    if written.is_none() {
        return by_another(path, stamp);
    }
    remove_leftovers(path);
    sync_directory(path);
    Ok(Written::Written)
}

/// When this task's rename found its file gone (another task's clean-up removed it), the
/// shard is complete if the other task completed it.
fn by_another(path: &Path, stamp: &ShardStamp) -> Result<Written, Error> {
    match shard_state(path, stamp) {
        ShardState::Complete => Ok(Written::ByAnother),
        state => Err(Error::Io {
            path: path.display().to_string(),
            message: format!(
                "this task's file was removed while it was written, and the shard is not \
                 complete ({state:?}): was the output directory cleared meanwhile?"
            ),
        }),
    }
}

/// Writes through a file of this task's own and renames it to `path`: the size and checksum
/// written, or `None` when the file was removed before the rename (by another task).
fn write_renamed(
    path: &Path,
    write: impl FnOnce(&mut ShardFile) -> Result<(), Error>,
) -> Result<Option<(u64, u64)>, Error> {
    let partial = partial_path(path);
    let io = |p: &Path, e: std::io::Error| Error::Io {
        path: p.display().to_string(),
        message: e.to_string(),
    };
    let file = std::fs::File::create(&partial).map_err(|e| io(&partial, e))?;
    let mut shard = ShardFile {
        file: BufWriter::with_capacity(1 << 16, file),
        hasher: XxHash3_64::with_seed(0),
        bytes: 0,
    };
    if let Err(e) = write(&mut shard) {
        let _ = std::fs::remove_file(&partial);
        return Err(e);
    }
    let file = shard
        .file
        .into_inner()
        .map_err(|e| io(&partial, e.into_error()))?;
    file.sync_all().map_err(|e| io(&partial, e))?;
    drop(file);
    match std::fs::rename(&partial, path) {
        Ok(()) => Ok(Some((shard.bytes, shard.hasher.finish()))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && !partial.exists() => Ok(None),
        Err(e) => Err(io(path, e)),
    }
}

/// Removes the files that killed tasks left while writing the shard at `path` or its
/// manifest (`<name>.partial-*`): [`write_shard`] does after writing, and a task that finds
/// the shard complete should (the task that completed it may have been killed before it
/// did). A task still writing one of them finds the shard complete when it renames, and
/// says so ([`Written::ByAnother`]).
pub fn remove_leftovers(path: &Path) {
    let (Some(dir), Some(name)) = (path.parent(), path.file_name()) else {
        return;
    };
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    let name = name.to_string_lossy();
    let prefixes = [
        format!("{name}.partial-"),
        format!("{name}.manifest.partial-"),
    ];
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let file = file.to_string_lossy();
        if prefixes.iter().any(|p| file.starts_with(p.as_str())) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Writes a file whole or not at all (no manifest: a study's single result file): `write`
/// fills a file of this task's own beside `path`, flushed to disk and renamed to `path`.
/// What killed writers of `path` left (`<name>.partial-<pid>-<n>` of processes that no
/// longer run) is removed then.
pub fn write_complete(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut ShardFile) -> Result<(), Error>,
) -> Result<(), Error> {
    let path = path.as_ref();
    match write_renamed(path, write)? {
        Some(_) => {
            remove_dead_leftovers(path);
            Ok(())
        }
        None => Err(Error::Io {
            path: path.display().to_string(),
            message: "the file being written was removed before it was complete".into(),
        }),
    }
}

/// Makes sure a study can write into `dir` before it runs anything: creates the directory
/// if it is missing and writes (and removes) a probe file there; an error names the
/// directory.
pub fn check_writable(dir: impl AsRef<Path>) -> Result<(), Error> {
    let dir = dir.as_ref();
    let io = |e: std::io::Error| Error::Io {
        path: dir.display().to_string(),
        message: format!("the output directory is not writable: {e}"),
    };
    std::fs::create_dir_all(dir).map_err(io)?;
    let probe = dir.join(format!(".hamel-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(io)?;
    std::fs::remove_file(&probe).map_err(io)
}

#[cfg(test)]
mod tests;
