//! How long `#[hamel_system]` takes to expand the paper's robot (target: ≤ 50 ms), in both
//! input forms, the Whipple bicycle, and the N-trailer for N = 24 and 64 (the body of
//! `hamel::n_trailer!` with its metavariables substituted). Filter with criterion's argument:
//! `cargo bench -p hamel-benches --bench expand -- NTrailer64`. A proc-macro crate cannot be linked by a benchmark, so, as serde_derive does
//! for its internals, this benchmark compiles the expansion modules itself.

// The modules are compiled here for `system::expand` only: the rest of them, and their unit
// tests (benches are built with `cfg(test)`, without running the tests), is unused here.
#![allow(unused)]

#[path = "../hamel-macros/src/differentiate/mod.rs"]
mod differentiate;
#[path = "../hamel-macros/src/engine/mod.rs"]
mod engine;
#[path = "../hamel-macros/src/helpers.rs"]
mod helpers;
#[path = "../hamel-macros/src/system/mod.rs"]
mod system;

use criterion::{Criterion, criterion_group, criterion_main};
use proc_macro2::TokenStream;
use quote::ToTokens;
use std::hint::black_box;

/// The `#[hamel_system(..)]` impl blocks of a model's source: (name, arguments, item).
fn impls(source: &str) -> Vec<(String, TokenStream, TokenStream)> {
    let file: syn::File = syn::parse_str(source).expect("the model file parses");
    file.items
        .into_iter()
        .filter_map(|item| match item {
            syn::Item::Impl(mut imp) => {
                let at = imp.attrs.iter().position(|a| {
                    a.path()
                        .segments
                        .last()
                        .is_some_and(|s| s.ident == "hamel_system")
                })?;
                let attr = imp.attrs.remove(at);
                let args = match attr.meta {
                    syn::Meta::List(list) => list.tokens,
                    _ => TokenStream::new(),
                };
                let name = imp.self_ty.to_token_stream().to_string();
                Some((name, args, imp.into_token_stream()))
            }
            _ => None,
        })
        .collect()
}

/// The items `hamel::n_trailer!` defines for N trailers, as source: the macro's body with
/// its metavariables substituted.
fn n_trailer_source(n: usize) -> String {
    let source = include_str!("../hamel-models/src/n_trailer.rs");
    let start = source
        .find("=> {\n")
        .expect("the n_trailer! macro has one rule")
        + "=> {\n".len();
    let end = start
        + source[start..]
            .find("\n    };\n}")
            .expect("the rule's body ends");
    source[start..end]
        .replace("$(#[$attr])*", "")
        .replace("$vis", "pub")
        .replace("$name", &format!("NTrailer{n}"))
        .replace("$crate", "hamel")
        .replace("$axles", &(n + 1).to_string())
        .replace("$n", &n.to_string())
}

/// The expansion cases: the catalogue's robot in both input forms, the Whipple bicycle, and
/// the N-trailer for N = 24 and 64.
fn cases() -> Vec<(String, TokenStream, TokenStream)> {
    let mut cases = impls(include_str!("../hamel-models/src/mobile_robot.rs"));
    cases.extend(impls(include_str!(
        "../hamel-models/src/whipple_bicycle.rs"
    )));
    for n in [24, 64] {
        cases.extend(impls(&n_trailer_source(n)));
    }
    cases
}

fn expansion(c: &mut Criterion) {
    let mut group = c.benchmark_group("expand");
    for (name, args, item) in cases() {
        let start = std::time::Instant::now();
        let out = system::expand(args.clone(), item.clone()).to_string();
        let once = start.elapsed().as_secs_f64();
        assert!(
            !out.contains("compile_error"),
            "{name} does not expand cleanly"
        );
        // Criterion's default of 100 samples would take minutes for the larger models.
        group.sample_size(if once > 0.05 { 10 } else { 100 });
        group.bench_function(&name, |b| {
            b.iter(|| system::expand(black_box(args.clone()), black_box(item.clone())))
        });
    }
    group.finish();
}

criterion_group!(benches, expansion);
criterion_main!(benches);
