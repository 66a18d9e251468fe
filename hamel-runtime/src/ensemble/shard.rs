//! Splitting a study among the tasks of a batch engine: shard i of n takes a contiguous
//! block of the table's rows, so that the shards' tables, concatenated in order, are the
//! table one task would write. Each shard's file is written whole or not at all, so that a
//! restarted study skips exactly the shards that finished.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::Error;

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
        if count == 0 {
            return Err(invalid("has no parts (n = 0)"));
        }
        if index >= count {
            return Err(invalid("is out of range: i must be less than n"));
        }
        Ok(Shard { index, count })
    }

    /// The rows of a table of `total` rows this shard takes: a contiguous block, the blocks
    /// of the n shards covering the table in order, their sizes differing by one at most.
    pub fn rows(&self, total: usize) -> Range<usize> {
        let at = |k: usize| (total as u128 * k as u128 / self.count as u128) as usize;
        at(self.index)..at(self.index + 1)
    }

    /// The shard's file name: `shard-0003-of-0008.<extension>`, which sorts in shard order.
    pub fn file_name(&self, extension: &str) -> String {
        format!("shard-{:04}-of-{:04}.{extension}", self.index, self.count)
    }
}

/// The name a file is written under until it is complete: beside it, with `.partial` added.
fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// Whether the file at `path` is complete: [`write_complete`] gives a file its name only once
/// it is written and flushed, so a file by that name is whole; a half-written one has
/// another name and is never taken for it.
pub fn is_complete(path: impl AsRef<Path>) -> bool {
    path.as_ref().is_file()
}

/// Writes a file whole or not at all: `write` fills `<path>.partial`, which is flushed to
/// disk and then renamed to `path` (atomic within a file system). A task killed in between
/// leaves only the `.partial` file, which the next attempt overwrites.
pub fn write_complete(
    path: impl AsRef<Path>,
    write: impl FnOnce(&mut std::fs::File) -> Result<(), Error>,
) -> Result<(), Error> {
    let path = path.as_ref();
    let partial = partial_path(path);
    let io = |p: &Path, e: std::io::Error| Error::Io {
        path: p.display().to_string(),
        message: e.to_string(),
    };
    let mut file = std::fs::File::create(&partial).map_err(|e| io(&partial, e))?;
    write(&mut file)?;
    file.sync_all().map_err(|e| io(&partial, e))?;
    drop(file);
    std::fs::rename(&partial, path).map_err(|e| io(path, e))
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
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_cover_the_rows_in_order() {
        assert_eq!(Shard::parse("3/8").unwrap(), Shard { index: 3, count: 8 });
        assert_eq!(Shard::parse(" 0 / 1 ").unwrap(), Shard::ALL);
        for bad in ["8/8", "9/8", "0/0", "-1/8", "a/8", "3", "3/8/1", ""] {
            let e = Shard::parse(bad).unwrap_err();
            assert!(matches!(e, Error::InvalidShard { .. }), "{bad}: {e}");
            assert!(e.to_string().contains(&format!("`{bad}`")), "{e}");
        }
        for total in [0, 1, 7, 8, 100, 1001] {
            let mut next = 0;
            for index in 0..8 {
                let rows = Shard { index, count: 8 }.rows(total);
                assert_eq!(rows.start, next);
                assert!(rows.len() <= total / 8 + 1);
                next = rows.end;
            }
            assert_eq!(next, total);
        }
        assert_eq!(
            Shard { index: 3, count: 8 }.file_name("csv"),
            "shard-0003-of-0008.csv"
        );
    }
}
