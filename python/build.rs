//! Bundles the Rust sources `hamel.compile` builds a user's model against into the extension
//! module (`_native.rust_sources()`): the facade crate `hamel` (its manifest, README and
//! `src/`), each `hamel-*` crate of the repository's workspace (without tests and benches),
//! `hamel-python`, and this package's Cargo.lock, so that a compiled model uses the versions
//! the wheel was built with. The root manifest is rewritten so that its workspace holds these
//! crates only, with PyO3 and numpy among its dependencies.
//!
//! The format is a sequence of entries, each the path (UTF-8), a zero byte, the length as a
//! little-endian u64, and the bytes; the Python side (`hamel._compile`) unpacks it.

use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let here =
        PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let root = here
        .parent()
        .expect("python/ is inside the repository")
        .to_path_buf();
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let manifest = fs::read_to_string(root.join("Cargo.toml")).unwrap_or_else(|e| {
        panic!(
            "hamel's Python package is built from the repository (`pip install ./python`): \
             cannot read {}: {e}",
            root.join("Cargo.toml").display()
        )
    });
    let crates = needed(&root, &manifest);
    let mut bundle = Vec::new();
    add(
        &mut bundle,
        "Cargo.toml",
        rewrite(
            &manifest,
            &crates,
            &fs::read_to_string(here.join("Cargo.toml")).unwrap_or_default(),
        )
        .as_bytes(),
    );
    add_file(&mut bundle, &root, Path::new("README.md"));
    add_tree(&mut bundle, &root, Path::new("src"));
    // The guides include an example's source (`hamel::docs::studies`).
    add_tree(&mut bundle, &root, Path::new("examples"));
    for name in &crates {
        add_file(&mut bundle, &root, &Path::new(name).join("Cargo.toml"));
        add_tree(&mut bundle, &root, &Path::new(name).join("src"));
    }
    add_file(&mut bundle, &here, Path::new("hamel-python/Cargo.toml"));
    add_tree(&mut bundle, &here, Path::new("hamel-python/src"));
    if let Ok(lock) = fs::read(here.join("Cargo.lock")) {
        add(&mut bundle, "work/Cargo.lock", &lock);
    }
    fs::write(out.join("sources.bin"), &bundle).expect("OUT_DIR is writable");
    fs::write(out.join("sources.hash"), format!("{:016x}", fnv(&bundle)))
        .expect("OUT_DIR is writable");
    println!(
        "cargo:rerun-if-changed={}",
        root.join("Cargo.toml").display()
    );
    println!("cargo:rerun-if-changed={}", root.join("src").display());
    println!("cargo:rerun-if-changed={}", root.join("examples").display());
    println!(
        "cargo:rerun-if-changed={}",
        here.join("hamel-python").display()
    );
    println!(
        "cargo:rerun-if-changed={}",
        here.join("Cargo.lock").display()
    );
    for name in &crates {
        println!("cargo:rerun-if-changed={}", root.join(name).display());
    }
}

/// The workspace members the root manifest lists (`members = [..]`, on one line or several).
fn members(manifest: &str) -> Vec<String> {
    let Some(start) = manifest.find("members") else {
        return Vec::new();
    };
    let rest = &manifest[start..];
    let (Some(open), Some(close)) = (rest.find('['), rest.find(']')) else {
        return Vec::new();
    };
    rest[open + 1..close]
        .split(',')
        .map(|s| s.trim().trim_matches('"').to_string())
        .filter(|s| !s.is_empty())
        .collect()
}

/// The workspace's `hamel-*` crates the facade depends on, directly or through each other
/// (not, say, `hamel-export`, which nothing of the facade uses).
fn needed(root: &Path, manifest: &str) -> Vec<String> {
    let crates: Vec<String> = members(manifest)
        .into_iter()
        .filter(|m| m.starts_with("hamel-") && root.join(m).join("Cargo.toml").exists())
        .collect();
    let dependencies = |text: &str| -> String {
        text.split("\n[")
            .filter(|section| {
                section.starts_with("dependencies]") || section.starts_with("[dependencies]")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let mut needed: Vec<String> = Vec::new();
    let mut pending = vec![dependencies(manifest)];
    while let Some(text) = pending.pop() {
        for name in &crates {
            if !needed.contains(name) && text.contains(name.as_str()) {
                needed.push(name.clone());
                let own =
                    fs::read_to_string(root.join(name).join("Cargo.toml")).unwrap_or_default();
                pending.push(dependencies(&own));
            }
        }
    }
    needed.sort();
    needed
}

/// The root manifest for the bundle: its members the bundled crates and `hamel-python`, no
/// `exclude`, no examples (they are not bundled), and PyO3 and numpy, as this package's
/// manifest has them, among the workspace's dependencies.
fn rewrite(manifest: &str, crates: &[String], python: &str) -> String {
    let mut list: Vec<String> = crates.iter().map(|c| format!("\"{c}\"")).collect();
    list.push("\"hamel-python\"".into());
    let mut out = String::new();
    let mut skipping_example = false;
    let mut in_members = false;
    for line in manifest.lines() {
        let trimmed = line.trim_start();
        if in_members {
            in_members = !line.contains(']');
            continue;
        }
        if trimmed.starts_with("members") {
            out += &format!("members = [{}]\n", list.join(", "));
            in_members = !line.contains(']');
            continue;
        }
        if trimmed.starts_with("exclude") {
            continue;
        }
        if trimmed.starts_with("[[example]]") {
            skipping_example = true;
            continue;
        }
        if skipping_example {
            if trimmed.starts_with('[') {
                skipping_example = false;
            } else {
                continue;
            }
        }
        // The facade as the wheel uses it: studies, without plots.
        if trimmed.starts_with("hamel = {") && !trimmed.contains("default-features") {
            out += &line.replacen(
                "hamel = {",
                "hamel = { default-features = false, features = [\"study\"],",
                1,
            );
            out.push('\n');
            continue;
        }
        out += line;
        out.push('\n');
        if trimmed.starts_with("[workspace.dependencies]") {
            for dep in python
                .lines()
                .filter(|l| l.starts_with("pyo3 =") || l.starts_with("numpy ="))
            {
                out += dep;
                out.push('\n');
            }
        }
    }
    out
}

fn add(bundle: &mut Vec<u8>, path: &str, bytes: &[u8]) {
    bundle.extend_from_slice(path.as_bytes());
    bundle.push(0);
    bundle.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    bundle.extend_from_slice(bytes);
}

fn add_file(bundle: &mut Vec<u8>, base: &Path, relative: &Path) {
    let bytes = fs::read(base.join(relative))
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", base.join(relative).display()));
    add(
        bundle,
        &relative.to_string_lossy().replace('\\', "/"),
        &bytes,
    );
}

/// Every file under `dir`, in a fixed order (the bundle's hash does not depend on the order
/// the file system lists them in).
fn add_tree(bundle: &mut Vec<u8>, base: &Path, dir: &Path) {
    let Ok(entries) = fs::read_dir(base.join(dir)) else {
        return;
    };
    let mut names: Vec<PathBuf> = entries
        .filter_map(|e| e.ok())
        .map(|e| dir.join(e.file_name()))
        .collect();
    names.sort();
    for relative in names {
        let full = base.join(&relative);
        if full.is_dir() {
            add_tree(bundle, base, &relative);
        } else {
            add_file(bundle, base, &relative);
        }
    }
}

/// FNV-1a, 64 bits: the bundle's identity in the compile cache's key.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
