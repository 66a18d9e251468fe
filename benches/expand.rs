//! How long `#[hamel_system]` takes to expand the paper's robot (target: ≤ 50 ms), in both
//! input forms. A proc-macro crate cannot be linked by a benchmark, so, as serde_derive does
//! for its internals, this benchmark compiles the expansion modules itself.

// The modules are compiled here for `system::expand` only: the rest of them, and their unit
// tests (benches are built with `cfg(test)`, without running the tests), is unused here.
#![allow(unused)]

#[path = "../hamel-macros/src/differentiate.rs"]
mod differentiate;
#[path = "../hamel-macros/src/engine/mod.rs"]
mod engine;
#[path = "../hamel-macros/src/system/mod.rs"]
mod system;

use criterion::{Criterion, criterion_group, criterion_main};
use proc_macro2::TokenStream;
use quote::ToTokens;
use std::hint::black_box;

/// The `#[hamel_system(..)]` impl blocks of the catalogue's robot: (name, arguments, item).
fn robot_impls() -> Vec<(String, TokenStream, TokenStream)> {
    let source = include_str!("../src/models/mobile_robot.rs");
    let file: syn::File = syn::parse_str(source).expect("the model file parses");
    file.items
        .into_iter()
        .filter_map(|item| match item {
            syn::Item::Impl(mut imp) => {
                let at = imp
                    .attrs
                    .iter()
                    .position(|a| a.path().is_ident("hamel_system"))?;
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

fn expansion(c: &mut Criterion) {
    let mut group = c.benchmark_group("expand_robot");
    for (name, args, item) in robot_impls() {
        let out = system::expand(args.clone(), item.clone()).to_string();
        assert!(
            !out.contains("compile_error"),
            "{name} does not expand cleanly"
        );
        group.bench_function(&name, |b| {
            b.iter(|| system::expand(black_box(args.clone()), black_box(item.clone())))
        });
    }
    group.finish();
}

criterion_group!(benches, expansion);
criterion_main!(benches);
