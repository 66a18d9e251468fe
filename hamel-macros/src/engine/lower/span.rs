//! Where a piece of syntax starts and ends, for errors that underline the whole of it.

use crate::engine::graph::SpanRange;
use proc_macro2::Span;
use quote::ToTokens;
use syn::Expr;
use syn::spanned::Spanned;

/// First and last token of any syntax.
pub fn span_range(tokens: &dyn ToTokens) -> SpanRange {
    let mut iter = tokens.to_token_stream().into_iter();
    let start = iter.next().map_or_else(Span::call_site, |t| t.span());
    let end = iter.last().map_or(start, |t| t.span());
    SpanRange { start, end }
}

/// First and last token of an expression, without re-tokenizing the common cases (this runs
/// for every node an expression creates, inside unrolled loops too).
pub fn expr_range(e: &Expr) -> SpanRange {
    let pair = |start: Span, end: Span| SpanRange { start, end };
    match e {
        Expr::Binary(b) => pair(expr_range(&b.left).start, expr_range(&b.right).end),
        Expr::MethodCall(m) => pair(expr_range(&m.receiver).start, m.paren_token.span.close()),
        Expr::Call(c) => pair(expr_range(&c.func).start, c.paren_token.span.close()),
        Expr::Index(i) => pair(expr_range(&i.expr).start, i.bracket_token.span.close()),
        Expr::Paren(p) => pair(p.paren_token.span.open(), p.paren_token.span.close()),
        Expr::Unary(u) => pair(span_range(&u.op).start, expr_range(&u.expr).end),
        Expr::Field(f) => pair(expr_range(&f.base).start, f.member.span()),
        Expr::Lit(l) => pair(l.lit.span(), l.lit.span()),
        Expr::Path(p) => match (p.path.segments.first(), p.path.segments.last()) {
            (Some(first), Some(last)) => pair(first.ident.span(), last.ident.span()),
            _ => span_range(e),
        },
        _ => span_range(e),
    }
}
