//! Writes what `#[hamel_system]` expands every model of the repository into, and what
//! `#[differentiate]` expands every impl it marks into, one file per impl block, so that a
//! change meant to leave the generated code alone can be checked: the catalogue
//! (`hamel-models/src/`, the N-trailer for N = 1, 2, 24), the examples, the validation suite's
//! models and differentiated functions, and every compile-fail case (whose expansion is the
//! error fallback with its messages).
//!
//! ```text
//! cargo bench -p hamel-benches --bench expansions -- /tmp/before
//! # change the macro
//! cargo bench -p hamel-benches --bench expansions -- /tmp/after
//! diff -r /tmp/before /tmp/after && echo byte-identical
//! ```
//!
//! Like `expand.rs`, it compiles the macro crate's expansion modules itself (a proc-macro
//! crate cannot be linked by a program), so the expansion is that of the source tree.

#![allow(unused)]

#[path = "../hamel-macros/src/differentiate/mod.rs"]
mod differentiate;
#[path = "../hamel-macros/src/engine/mod.rs"]
mod engine;
#[path = "../hamel-macros/src/helpers.rs"]
mod helpers;
#[path = "../hamel-macros/src/system/mod.rs"]
mod system;

use proc_macro2::TokenStream;
use quote::ToTokens;
use std::path::{Path, PathBuf};

/// Which macro an impl block carries.
#[derive(Clone, Copy, PartialEq)]
enum Macro {
    HamelSystem,
    Differentiate,
}

/// The `#[hamel_system]` and `#[differentiate]` items of a source file, at any depth of
/// inline modules and functions' bodies: (macro, label, attribute arguments, item without the
/// attribute).
fn models(source: &str) -> Vec<(Macro, String, TokenStream, TokenStream)> {
    let Ok(file) = syn::parse_file(source) else {
        return Vec::new();
    };
    let mut found = Vec::new();
    collect(&file.items, &mut found);
    found
}

fn collect(items: &[syn::Item], found: &mut Vec<(Macro, String, TokenStream, TokenStream)>) {
    for item in items {
        match item {
            syn::Item::Impl(imp) => {
                let mut imp = imp.clone();
                let marked = |name: &str| {
                    imp.attrs
                        .iter()
                        .position(|a| a.path().segments.last().is_some_and(|s| s.ident == name))
                };
                let (kind, at) = match (marked("hamel_system"), marked("differentiate")) {
                    (Some(at), _) => (Macro::HamelSystem, at),
                    (None, Some(at)) => (Macro::Differentiate, at),
                    (None, None) => continue,
                };
                let attr = imp.attrs.remove(at);
                let args = match attr.meta {
                    syn::Meta::List(list) => list.tokens,
                    _ => TokenStream::new(),
                };
                let label = imp.self_ty.to_token_stream().to_string().replace(' ', "");
                found.push((kind, label, args, imp.into_token_stream()));
            }
            syn::Item::Mod(m) => {
                if let Some((_, items)) = &m.content {
                    collect(items, found);
                }
            }
            syn::Item::Fn(f) => {
                let items: Vec<syn::Item> = f
                    .block
                    .stmts
                    .iter()
                    .filter_map(|s| match s {
                        syn::Stmt::Item(i) => Some(i.clone()),
                        _ => None,
                    })
                    .collect();
                collect(&items, found);
            }
            _ => {}
        }
    }
}

/// The items `hamel::n_trailer!` defines for N trailers, as source (as in `expand.rs`).
fn n_trailer_source(root: &Path, n: usize) -> String {
    let source =
        std::fs::read_to_string(root.join("hamel-models/src/n_trailer.rs")).unwrap_or_default();
    let Some(start) = source.find("=> {\n").map(|s| s + "=> {\n".len()) else {
        return String::new();
    };
    let Some(end) = source[start..].find("\n    };\n}").map(|e| start + e) else {
        return String::new();
    };
    source[start..end]
        .replace("$(#[$attr])*", "")
        .replace("$vis", "pub")
        .replace("$name", &format!("NTrailer{n}"))
        .replace("$crate", "hamel")
        .replace("$axles", &(n + 1).to_string())
        .replace("$n", &n.to_string())
}

/// The Rust files under `dir`, sorted, recursively.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            out.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    out.sort();
    out
}

fn main() {
    // `cargo bench` passes `--bench`; the first other argument is the output directory.
    let out = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with("--"))
        .unwrap_or_else(|| "target/expansions".to_string());
    let out = PathBuf::from(out);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    std::fs::create_dir_all(&out).expect("the output directory can be made");
    let mut sources: Vec<(String, String)> = Vec::new();
    for dir in ["src", "hamel-models/src", "examples", "tests", "benches"] {
        for path in rust_files(&root.join(dir)) {
            let label = path
                .strip_prefix(&root)
                .unwrap_or(&path)
                .to_string_lossy()
                .replace('/', "__");
            sources.push((label, std::fs::read_to_string(&path).unwrap_or_default()));
        }
    }
    for n in [1, 2, 24] {
        sources.push((format!("n_trailer_{n}"), n_trailer_source(&root, n)));
    }
    let mut count = 0;
    for (label, source) in sources {
        for (i, (kind, name, args, item)) in models(&source).into_iter().enumerate() {
            let expanded = match kind {
                Macro::HamelSystem => system::expand(args, item).to_string(),
                Macro::Differentiate => differentiate::expand(args, item).to_string(),
            };
            let file = out.join(format!("{label}__{i}_{name}.txt"));
            std::fs::write(&file, expanded).expect("the expansion can be written");
            count += 1;
        }
    }
    println!("wrote {count} expansions to {}", out.display());
}
