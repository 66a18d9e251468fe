//! Writing a file whole or not at all: into a file of its own beside it
//! (`<name>.partial-<pid>-<n>`, as every file hamel writes whole), renamed over it once
//! complete, so that a failure leaves no partial file and a reader never sees one. A process
//! killed while writing leaves that file; the next write of the same name removes it.

use std::io::Write as _;
use std::path::Path;

use hamel_runtime::whole_file::{partial_path, remove_dead_leftovers};

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
    let temporary = partial_path(path);
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
    match written {
        // What writers killed before they renamed left goes now.
        Ok(()) => remove_dead_leftovers(path),
        Err(_) => {
            let _ = std::fs::remove_file(&temporary);
        }
    }
    written
}

fn directory(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}
