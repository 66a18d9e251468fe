//! Tests of the engine and of `#[differentiate]` as a whole, from the outside:
//!
//! * `garbled` — unsupported or malformed input must come back as `compile_error!` naming
//!   the problem, never as a panic (hand-written cases and random token soup);
//! * `random_exprs` — random expression trees, differentiated by the engine and checked
//!   against hyper-dual numbers evaluated on the same tree.
//!
//! The unit tests next to each engine module test its parts; these test the whole path.
//!
//! The random tests draw a fixed sequence of cases (fixed seeds), so every run repeats the
//! same ones. `cargo test` runs the first fifth of each sequence, which keeps the workspace
//! suite within its time budget in a debug build; `HAMEL_FUZZ=full` runs all of them, and
//! `.ci/run` does so on every submission.

mod garbled;
mod random_exprs;

use proc_macro2::{Delimiter, TokenStream, TokenTree};

/// How many of a random test's `full` cases to run: all of them with `HAMEL_FUZZ=full`, else
/// the first fifth (the same cases every run, as the seeds are fixed).
fn fuzz_cases(full: u32) -> u32 {
    match std::env::var("HAMEL_FUZZ").as_deref() {
        Ok("full") => full,
        _ => (full / 5).max(1),
    }
}

/// The messages of every `compile_error!` in `tokens`, in order.
///
/// `#[differentiate]` echoes the user's item next to its errors, so searching the whole
/// output for a word would find the user's own code; only the messages count.
fn compile_errors(tokens: &TokenStream) -> Vec<String> {
    let mut messages = Vec::new();
    collect_errors(tokens.clone(), &mut messages);
    messages
}

fn collect_errors(tokens: TokenStream, messages: &mut Vec<String>) {
    let trees: Vec<TokenTree> = tokens.into_iter().collect();
    for (i, tree) in trees.iter().enumerate() {
        let TokenTree::Group(group) = tree else {
            continue;
        };
        // `compile_error ! { "message" }` (or with parentheses).
        let is_invocation = i >= 2
            && matches!(&trees[i - 1], TokenTree::Punct(p) if p.as_char() == '!')
            && matches!(&trees[i - 2], TokenTree::Ident(id) if id == "compile_error")
            && group.delimiter() != Delimiter::None;
        if is_invocation {
            let message = syn::parse2::<syn::LitStr>(group.stream())
                .map(|lit| lit.value())
                .unwrap_or_else(|_| group.stream().to_string());
            messages.push(message);
        } else {
            collect_errors(group.stream(), messages);
        }
    }
}

/// Parse source text into tokens; the test inputs are written to be lexically valid.
fn tokens(source: &str) -> TokenStream {
    source
        .parse()
        .unwrap_or_else(|e| panic!("test input does not lex: {e}\n{source}"))
}
