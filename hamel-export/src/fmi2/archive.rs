//! The `.fmu` file: a zip archive of `modelDescription.xml` and the library under
//! `binaries/<platform>/<modelIdentifier>.<so|dll|dylib>`, one for each platform it was
//! built for (feature `fmu`).
//!
//! Nothing here knows the model (the description comes as text): the export example
//! compiles this file alone, with zip, into the small program that writes a catalogue
//! model's archive, so that the zip crate (which turns on memchr's `std`) stays out of the
//! build that shares the catalogue with the robot example.

use std::io::Write;
use std::path::Path;
use zip::CompressionMethod;
use zip::write::{SimpleFileOptions, ZipWriter};

/// FMI 2.0's name of the platform this crate is built for, and its libraries' extension.
pub fn platform() -> Option<(&'static str, &'static str)> {
    let bits64 = cfg!(target_pointer_width = "64");
    if cfg!(target_os = "linux") {
        Some((if bits64 { "linux64" } else { "linux32" }, "so"))
    } else if cfg!(target_os = "windows") {
        Some((if bits64 { "win64" } else { "win32" }, "dll"))
    } else if cfg!(target_os = "macos") {
        Some((if bits64 { "darwin64" } else { "darwin32" }, "dylib"))
    } else {
        None
    }
}

/// The extension of a platform's libraries.
fn extension(platform: &str) -> Option<&'static str> {
    match platform {
        "linux64" | "linux32" => Some("so"),
        "win64" | "win32" => Some("dll"),
        "darwin64" | "darwin32" => Some("dylib"),
        _ => None,
    }
}

/// Writes the FMU `identifier` to `out`: `description` as `modelDescription.xml`, and
/// `library` (a `cdylib` with `hamel_export::fmi2!`, built for this platform) as
/// `binaries/<platform>/<identifier>.<ext>`. `others` adds libraries built for other
/// platforms (`("win64", path to the .dll)`, …).
pub fn write_archive(
    identifier: &str,
    description: &str,
    library: &Path,
    others: &[(String, &Path)],
    out: &Path,
) -> Result<(), String> {
    let (here, _) = platform().ok_or("this platform has no name in FMI 2.0")?;
    let mut libraries = vec![(here.to_string(), library)];
    libraries.extend(others.iter().map(|(p, l)| (p.clone(), *l)));
    let file =
        std::fs::File::create(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let mut zip = ZipWriter::new(file);
    let options = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let fail = |e: &dyn std::fmt::Display| format!("cannot write {}: {e}", out.display());
    zip.start_file("modelDescription.xml", options)
        .map_err(|e| fail(&e))?;
    zip.write_all(description.as_bytes())
        .map_err(|e| fail(&e))?;
    for (platform, path) in libraries {
        let ext = extension(&platform).ok_or_else(|| {
            format!(
                "`{platform}` is not a platform of FMI 2.0 (win32, win64, linux32, linux64, \
                 darwin32, darwin64)"
            )
        })?;
        let bytes =
            std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let name = format!("binaries/{platform}/{identifier}.{ext}");
        zip.start_file(name, options.unix_permissions(0o755))
            .map_err(|e| fail(&e))?;
        zip.write_all(&bytes).map_err(|e| fail(&e))?;
    }
    zip.finish().map_err(|e| fail(&e))?;
    Ok(())
}
