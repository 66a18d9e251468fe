//! Writing a file whole or not at all: into a temporary file beside it, renamed over it
//! once complete, so that a failure leaves no partial file and a reader never sees one.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::error::{ErrorKind, SceneError};

/// Writes `bytes` to `path` through a temporary file in the same directory; on any failure
/// the temporary file is removed and the error names `path`.
pub(crate) fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    let io = |e: std::io::Error, doing: &str| {
        SceneError::from(ErrorKind::Io {
            message: format!("{doing}: {e}"),
        })
        .at(path)
    };
    let temporary = temporary_beside(path);
    let mut file = std::fs::File::create(&temporary).map_err(|e| {
        io(
            e,
            &format!(
                "cannot create a file in {} (does the directory exist, and may it be written?)",
                directory(path).display()
            ),
        )
    })?;
    let written = file
        .write_all(bytes)
        .and_then(|()| file.sync_all())
        .map_err(|e| io(e, "writing failed"))
        .and_then(|()| {
            drop(file);
            std::fs::rename(&temporary, path).map_err(|e| io(e, "cannot replace the file"))
        });
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

fn directory(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// A name beside `path` that no other writer in this or another process uses.
fn temporary_beside(path: &Path) -> PathBuf {
    static COUNT: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map_or_else(|| "scene".into(), |n| n.to_string_lossy().into_owned());
    let unique = format!(
        ".{name}.{}.{}.partial",
        std::process::id(),
        COUNT.fetch_add(1, Ordering::Relaxed)
    );
    directory(path).join(unique)
}
