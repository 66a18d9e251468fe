//! Files written whole or not at all, and read back only whole.
//!
//! A file is written under a name of its own beside its final one (`<name>.partial-<pid>-<n>`),
//! flushed to disk and renamed: a crash, a kill or a full disk leaves the final name either
//! absent or holding the previous complete file, never a partial one. Then its manifest,
//! `<name>.manifest`, is written the same way: the row count, the byte count and the XXH3
//! checksum of the file. A reader that finds the manifest checks the file against it, so that
//! a file cut short afterwards (a copy interrupted, a disk that filled) is an error instead
//! of a shorter table, even when the cut falls between two rows. The data file itself stays
//! plain CSV, which pandas, polars and DuckDB read as it is; a file without its manifest (one
//! copied alone, or written by another program) is read as it is.
//!
//! A process killed while writing leaves its `.partial-*` file: the next write of the same
//! name removes those of processes that no longer run.

use std::hash::Hasher as _;
use std::io::{BufWriter, Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use twox_hash::XxHash3_64;

use crate::error::Error;

/// The manifest's first line.
const MANIFEST_HEADER: &str = "hamel file manifest 1";

/// `path` with `suffix` added to its file name.
pub(crate) fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(suffix);
    path.with_file_name(name)
}

/// The manifest beside a file written whole: `<name>.manifest`.
pub fn manifest_of(path: &Path) -> PathBuf {
    with_suffix(path, ".manifest")
}

/// A name no other writer uses, beside `path`: `<name>.partial-<pid>-<n>`, where a file is
/// written before it is renamed to `path`. A process killed while writing leaves it;
/// [`remove_dead_leftovers`] removes it.
pub fn partial_path(path: &Path) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    with_suffix(path, &format!(".partial-{}-{n}", std::process::id()))
}

/// An I/O error naming `path`.
pub(crate) fn io(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// A file being written under a name of its own: buffered, its bytes counted and
/// checksummed. [`WholeFile::commit`] renames it to its final name and writes its manifest
/// (after which it takes no more bytes); dropped without that (the write failed), it is
/// removed.
pub struct WholeFile {
    file: Option<BufWriter<std::fs::File>>,
    path: PathBuf,
    partial: PathBuf,
    hasher: XxHash3_64,
    bytes: u64,
}

impl WholeFile {
    /// A file that will become `path` when committed.
    pub fn create(path: impl AsRef<Path>) -> Result<WholeFile, Error> {
        let path = path.as_ref().to_path_buf();
        let partial = partial_path(&path);
        let file = std::fs::File::create(&partial).map_err(|e| io(&path, e))?;
        Ok(WholeFile {
            file: Some(BufWriter::with_capacity(1 << 16, file)),
            path,
            partial,
            hasher: XxHash3_64::with_seed(0),
            bytes: 0,
        })
    }

    /// The final name.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes the file to disk, renames it to its final name and writes its manifest,
    /// saying it holds `rows` rows. An older manifest is removed first, so that no manifest
    /// ever describes another file than the one beside it.
    pub fn commit(&mut self, rows: u64) -> Result<(), Error> {
        let Some(writer) = self.file.take() else {
            return Err(io(&self.path, "the file was already committed"));
        };
        let file = writer
            .into_inner()
            .map_err(|e| io(&self.path, e.into_error()))?;
        file.sync_all().map_err(|e| io(&self.path, e))?;
        drop(file);
        let manifest = manifest_of(&self.path);
        match std::fs::remove_file(&manifest) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io(&manifest, e)),
            _ => {}
        }
        std::fs::rename(&self.partial, &self.path).map_err(|e| io(&self.path, e))?;
        let name = self.path.file_name().unwrap_or_default().to_string_lossy();
        let text = format!(
            "{MANIFEST_HEADER}\nfile {name}\nrows {rows}\nbytes {}\nxxh3 {:016x}\n",
            self.bytes,
            self.hasher.finish()
        );
        write_renamed(&manifest, text.as_bytes())?;
        remove_dead_leftovers(&self.path);
        sync_directory(&self.path);
        Ok(())
    }
}

impl Write for WholeFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let Some(file) = self.file.as_mut() else {
            return Err(std::io::Error::other("the file was already committed"));
        };
        let n = file.write(buf)?;
        self.hasher.write(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.as_mut().map_or(Ok(()), Write::flush)
    }
}

impl Drop for WholeFile {
    /// A file not committed is not a file: its partial copy goes.
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.partial);
        }
    }
}

/// Writes `bytes` to `path` whole: through a file of its own, flushed and renamed.
fn write_renamed(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let partial = partial_path(path);
    let written = (|| {
        let mut file = std::fs::File::create(&partial)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&partial, path)
    })();
    written.map_err(|e| {
        let _ = std::fs::remove_file(&partial);
        io(path, e)
    })
}

/// Flushes a directory's entries (the renames) to disk, where the system allows it.
pub(crate) fn sync_directory(path: &Path) {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Removes the `.partial-<pid>-<n>` files of `path` and of its manifest that processes which
/// no longer run left (killed while writing): where the system lists its processes
/// (`/proc`), those of a running process, this one's included, are left to it. Every write
/// of a file whole calls it once the file is in place, so that a killed write's leftover
/// lasts until the next write of the same name.
pub fn remove_dead_leftovers(path: &Path) {
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
    let processes = Path::new("/proc/self").exists();
    for entry in entries.flatten() {
        let file = entry.file_name();
        let file = file.to_string_lossy();
        let Some(rest) = prefixes.iter().find_map(|p| file.strip_prefix(p.as_str())) else {
            continue;
        };
        let pid = rest.split('-').next().unwrap_or_default();
        let running = pid == std::process::id().to_string()
            || (processes && Path::new("/proc").join(pid).exists());
        if !running {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// What a file's manifest says of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Manifest {
    pub rows: u64,
    pub bytes: u64,
    pub checksum: u64,
}

/// Checks the file at `path` against its manifest, if it has one: the manifest (`None`
/// without one), or an [`Error::Read`] naming the file when its size or checksum differs —
/// it was cut short or altered since it was written — or the manifest is not one hamel
/// wrote.
///
/// ```
/// use hamel_runtime::whole_file::{WholeFile, check_manifest};
/// use std::io::Write;
///
/// let path = std::env::temp_dir().join(format!("whole-{}.csv", std::process::id()));
/// let mut file = WholeFile::create(&path)?;
/// file.write_all(b"t,x\n0,1\n0.5,2\n").unwrap();
/// file.commit(2)?;
/// assert_eq!(check_manifest(&path)?.map(|m| m.rows), Some(2));
/// // Cut between two rows: still CSV, but not the file that was written.
/// std::fs::write(&path, b"t,x\n0,1\n").unwrap();
/// let e = check_manifest(&path).unwrap_err();
/// assert!(e.to_string().contains("truncated"), "{e}");
/// # std::fs::remove_file(&path).unwrap();
/// # std::fs::remove_file(hamel_runtime::whole_file::manifest_of(&path)).unwrap();
/// # Ok::<(), hamel_runtime::Error>(())
/// ```
pub fn check_manifest(path: impl AsRef<Path>) -> Result<Option<Manifest>, Error> {
    let path = path.as_ref();
    let read_error = |message: String| Error::Read {
        path: path.display().to_string(),
        message,
    };
    let manifest_path = manifest_of(path);
    let text = match std::fs::read_to_string(&manifest_path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(read_error(format!("its manifest cannot be read: {e}"))),
    };
    let manifest = parse(&text).ok_or_else(|| {
        read_error(format!(
            "its manifest, {}, is not one hamel wrote",
            manifest_path.display()
        ))
    })?;
    let (bytes, checksum) = checksum(path).map_err(|e| read_error(e.to_string()))?;
    if bytes != manifest.bytes {
        return Err(read_error(format!(
            "it is truncated or altered: it has {bytes} bytes where its manifest says {} ({} \
             rows); write it again, or remove {} to read it as it is",
            manifest.bytes,
            manifest.rows,
            manifest_path.display()
        )));
    }
    if checksum != manifest.checksum {
        return Err(read_error(format!(
            "it was altered since it was written: its checksum differs from its manifest's; \
             write it again, or remove {} to read it as it is",
            manifest_path.display()
        )));
    }
    Ok(Some(manifest))
}

/// The first words of a study's shard manifest as `ensemble::shard` writes them, for a build
/// without the feature `ensemble` to check a shard's file as one with it does (a test checks
/// them against the shards' own constant).
#[cfg(any(test, not(feature = "ensemble")))]
const SHARD_MANIFEST_WORDS: &str = "hamel shard manifest ";
#[cfg(feature = "ensemble")]
use crate::ensemble::shard::SHARD_MANIFEST;
#[cfg(not(feature = "ensemble"))]
const SHARD_MANIFEST: &str = SHARD_MANIFEST_WORDS;

/// Whether `header` begins a study's shard manifest.
fn is_shard_manifest(header: &str) -> bool {
    header.starts_with(SHARD_MANIFEST)
}

/// A manifest's fields: one of a file written whole, or of a study's shard
/// (`ensemble::shard`), which records the same and the hash of what it was computed from.
fn parse(text: &str) -> Option<Manifest> {
    let mut lines = text.lines();
    let header = lines.next()?;
    if header != MANIFEST_HEADER && !is_shard_manifest(header) {
        return None;
    }
    let mut field = |key: &str, radix: u32| -> Option<u64> {
        let line = lines.find(|l| l.starts_with(key))?;
        u64::from_str_radix(line.strip_prefix(key)?.trim(), radix).ok()
    };
    Some(Manifest {
        rows: field("rows ", 10)?,
        bytes: field("bytes ", 10)?,
        checksum: field("xxh3 ", 16)?,
    })
}

/// The size and XXH3 checksum of a file's bytes.
pub(crate) fn checksum(path: &Path) -> std::io::Result<(u64, u64)> {
    let mut file = std::fs::File::open(path)?;
    let mut h = XxHash3_64::with_seed(0);
    let mut buffer = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            return Ok((bytes, h.finish()));
        }
        h.write(&buffer[..n]);
        bytes += n as u64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "ensemble")]
    #[test]
    fn shard_manifests_are_recognized_as_the_shards_write_them() {
        assert_eq!(SHARD_MANIFEST_WORDS, crate::ensemble::shard::SHARD_MANIFEST);
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("hamel-whole-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_file_appears_whole_with_its_manifest_or_not_at_all() {
        let d = dir("appears");
        let path = d.join("t.csv");
        let mut f = WholeFile::create(&path).unwrap();
        f.write_all(b"a\n1\n").unwrap();
        // Until it is committed, the final name is absent.
        assert!(!path.exists());
        f.commit(1).unwrap();
        assert_eq!(names(&d), ["t.csv", "t.csv.manifest"]);
        assert_eq!(check_manifest(&path).unwrap().unwrap().rows, 1);
        // A write that fails leaves the complete file it would have replaced.
        let mut g = WholeFile::create(&path).unwrap();
        g.write_all(b"a\n2\n3\n").unwrap();
        drop(g);
        assert_eq!(names(&d), ["t.csv", "t.csv.manifest"]);
        assert_eq!(std::fs::read(&path).unwrap(), b"a\n1\n");
        // A manifest that does not describe the file beside it.
        std::fs::write(&path, b"a\n9\n").unwrap();
        assert!(
            check_manifest(&path)
                .unwrap_err()
                .to_string()
                .contains("altered")
        );
        std::fs::write(manifest_of(&path), "something else\n").unwrap();
        let e = check_manifest(&path).unwrap_err().to_string();
        assert!(e.contains("not one hamel wrote"), "{e}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn leftovers_of_killed_writers_go_with_the_next_write() {
        let d = dir("leftovers");
        let path = d.join("t.csv");
        // A process id that is not running (above Linux's largest, 2²²), and this one's.
        let dead = d.join("t.csv.partial-4194305-0");
        let ours = d.join(format!("t.csv.partial-{}-999", std::process::id()));
        std::fs::write(&dead, b"a\n1\n").unwrap();
        std::fs::write(&ours, b"a\n").unwrap();
        let mut f = WholeFile::create(&path).unwrap();
        f.write_all(b"a\n1\n").unwrap();
        f.commit(1).unwrap();
        let left = names(&d);
        assert!(
            !left.contains(&"t.csv.partial-4194305-0".to_string()),
            "{left:?}"
        );
        assert!(ours.exists(), "{left:?}");
        std::fs::remove_dir_all(&d).unwrap();
    }
}
