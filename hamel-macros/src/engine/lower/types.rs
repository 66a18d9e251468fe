//! Signatures: which argument and result types a differentiated function may have.

use super::value::{Shape, Value};
use super::{Env, Lowerer};
use quote::ToTokens;
use syn::{FnArg, ReturnType, Type};

pub const SUPPORTED_TYPES: &str = "`f64` or a fixed-size array `[f64; N]` (by value or by reference; \
     arrays may nest); helpers called from a body may also take integers such as `usize`";

/// Most numbers an argument or result may hold.
pub const MAX_ARRAY_ELEMENTS: usize = 4096;

/// One typed argument of a function.
#[derive(Clone)]
pub struct Arg {
    pub pat: syn::Pat,
    pub ty: Type,
    pub shape: Shape,
}

/// What lowering needs to know of a signature.
#[derive(Clone)]
pub struct Signature {
    /// Whether the function takes `self` (it then reads parameters as `self.field`).
    pub receiver: bool,
    pub args: Vec<Arg>,
    /// `None` when the return type is not supported (already reported).
    pub output: Option<Shape>,
}

/// A type as the user would write it: `Vec<f64>`, `&[f32; 3]` (token streams print as
/// `Vec < f64 >`).
pub fn render_type(ty: &Type) -> String {
    let mut text = ty.to_token_stream().to_string();
    for (from, to) in [
        (" <", "<"),
        ("< ", "<"),
        (" >", ">"),
        (" ,", ","),
        (" ;", ";"),
        ("& ", "&"),
        ("[ ", "["),
        (" ]", "]"),
        ("( ", "("),
        (" )", ")"),
        (" ::", "::"),
        (":: ", "::"),
    ] {
        text = text.replace(from, to);
    }
    text
}

fn is_integer_type(name: &str) -> bool {
    matches!(
        name,
        "usize" | "isize" | "u8" | "u16" | "u32" | "u64" | "i8" | "i16" | "i32" | "i64"
    )
}

impl<'a> Lowerer<'a, '_> {
    /// Check a signature against the supported subset; errors are recorded, and `None`
    /// comes back when the function cannot be lowered at all.
    pub fn signature(&mut self, f: &syn::ImplItemFn) -> Option<Signature> {
        let errors_before = self.errors.len();
        self.current_signature = self.signature_hints.get(&f.sig.ident.to_string()).cloned();
        let signature = self.signature_inner(f);
        self.current_signature = None;
        if self.errors.len() > errors_before {
            self.faulty.insert(f.sig.ident.to_string());
        }
        signature
    }

    fn signature_inner(&mut self, f: &syn::ImplItemFn) -> Option<Signature> {
        let sig = &f.sig;
        let mut ok = true;
        if !sig.generics.params.is_empty() {
            self.error(
                &sig.generics,
                "generic functions cannot be differentiated: write the function over `f64`",
            );
            ok = false;
        }
        if let Some(a) = &sig.asyncness {
            self.error(a, "`async` functions cannot be differentiated");
            ok = false;
        }
        if let Some(v) = &sig.variadic {
            self.error(v, "variadic functions cannot be differentiated");
            ok = false;
        }
        let mut receiver = false;
        let mut args = Vec::new();
        for input in &sig.inputs {
            match input {
                FnArg::Receiver(r) => {
                    let by_mut_ref = matches!(r.kind, syn::ReceiverKind::Reference(_, _, Some(_)));
                    if r.mutability.is_some() || by_mut_ref {
                        self.error(
                            r,
                            "the model is read-only here: take `&self`, not `&mut self`",
                        );
                        ok = false;
                    }
                    receiver = true;
                }
                FnArg::Typed(pt) => match self.shape_of(&pt.ty) {
                    Some(shape) => args.push(Arg {
                        pat: (*pt.pat).clone(),
                        ty: (*pt.ty).clone(),
                        shape,
                    }),
                    None => ok = false,
                },
            }
        }
        let output = match &sig.output {
            ReturnType::Default => {
                let expected = match &self.current_signature {
                    Some(signature) => {
                        format!("this function must have the signature `{signature}`")
                    }
                    None => format!("a differentiated function returns {SUPPORTED_TYPES}"),
                };
                self.error(
                    &sig.ident,
                    format!("`{}` returns nothing: {expected}", sig.ident),
                );
                None
            }
            ReturnType::Type(_, ty) => self.shape_of(ty),
        };
        ok.then_some(Signature {
            receiver,
            args,
            output,
        })
    }

    /// The shape of a supported type, or an error at the type.
    pub fn shape_of(&mut self, ty: &Type) -> Option<Shape> {
        match ty {
            Type::Paren(p) => self.shape_of(&p.elem),
            Type::Group(g) => self.shape_of(&g.elem),
            Type::Reference(r) => {
                if r.mutability.is_some() {
                    self.error(ty, "mutable references cannot be differentiated: take the value or a shared reference");
                    return None;
                }
                self.shape_of(&r.elem)
            }
            Type::Array(a) => {
                let inner = self.shape_of(&a.elem)?;
                if inner == Shape::Int {
                    self.error(
                        &a.elem,
                        format!("arrays of integers are not supported; expected {SUPPORTED_TYPES}"),
                    );
                    return None;
                }
                let len = self.array_length(&a.len)?;
                match usize::try_from(len) {
                    Ok(n) if n.saturating_mul(inner.len().max(1)) <= MAX_ARRAY_ELEMENTS => {
                        Some(Shape::Array(n, Box::new(inner)))
                    }
                    Ok(_) => {
                        self.error(
                            ty,
                            format!(
                                "this array holds more than {MAX_ARRAY_ELEMENTS} numbers: every element is a \
                                 separate input of the generated straight-line code"
                            ),
                        );
                        None
                    }
                    Err(_) => {
                        self.error(&a.len, "an array length cannot be negative");
                        None
                    }
                }
            }
            Type::Path(p) if p.qself.is_none() => {
                let segments: Vec<String> = p
                    .path
                    .segments
                    .iter()
                    .map(|s| s.ident.to_string())
                    .collect();
                let segments: Vec<&str> = segments.iter().map(String::as_str).collect();
                if let Some(kind) = super::geometry::GeoKind::from_path(&segments)
                    && p.path.segments.iter().all(|s| s.arguments.is_none())
                {
                    return Some(Shape::Geo(kind));
                }
                let name = render_type(ty);
                if name == "f64" {
                    Some(Shape::Real)
                } else if is_integer_type(&name) {
                    Some(Shape::Int)
                } else {
                    let hint = if name == "f32" {
                        " (hamel computes in `f64`)"
                    } else {
                        ""
                    };
                    let expected = self.expected_types();
                    self.error(ty, format!("unsupported type `{name}`{hint}: {expected}"));
                    None
                }
            }
            _ => {
                let expected = self.expected_types();
                self.error(
                    ty,
                    format!("unsupported type `{}`: {expected}", render_type(ty)),
                );
                None
            }
        }
    }

    /// What a type should have been, for messages: the role's signature when a role function
    /// is being checked, else the subset's types.
    fn expected_types(&self) -> String {
        match &self.current_signature {
            Some(signature) => format!("this function must have the signature `{signature}`"),
            None => format!("expected {SUPPORTED_TYPES}"),
        }
    }

    /// An array's length: an integer known at compile time. A constant defined outside the
    /// impl block (`[f64; N]` with a module's `const N`) is not one the macro can read — it
    /// sees the impl block's tokens alone — and is reported once however many signatures
    /// use it (it was an error at each, calling it an `f64`).
    fn array_length(&mut self, e: &syn::Expr) -> Option<i64> {
        let Some(name) = self.outside_constant(e) else {
            return self.const_int(e, "an array length");
        };
        if self.reported_lengths.insert(name.clone()) {
            self.error(
                e,
                format!(
                    "the array length `{name}` is a constant defined outside the impl block, \
                     which `#[hamel_system]` cannot read (a macro sees the impl block's tokens \
                     alone): write the length as a number, `[f64; 3]`, or define the constant in \
                     the impl block, `const {}: usize = 3;`, and write `Self::{}`",
                    name.rsplit("::").next().unwrap_or(&name),
                    name.rsplit("::").next().unwrap_or(&name),
                ),
            );
        } else {
            self.note_repeated_mistake();
        }
        None
    }

    /// The first path in `e` that names no constant of the impl block (nor one the expansion
    /// defines), if any: `N`, `consts::N`, `Self::M` for an `M` the block lacks.
    fn outside_constant(&self, e: &syn::Expr) -> Option<String> {
        struct Paths<'p>(Vec<&'p syn::ExprPath>);
        impl<'p> syn::visit::Visit<'p> for Paths<'p> {
            fn visit_expr_path(&mut self, p: &'p syn::ExprPath) {
                self.0.push(p);
            }
        }
        let mut paths = Paths(Vec::new());
        syn::visit::Visit::visit_expr(&mut paths, e);
        paths.0.iter().find_map(|p| {
            let segments: Vec<String> = p
                .path
                .segments
                .iter()
                .map(|s| s.ident.to_string())
                .collect();
            match segments.as_slice() {
                [this, name] if this == "Self" && self.knows_constant(name) => None,
                _ => Some(segments.join("::")),
            }
        })
    }

    /// Evaluate an expression that must be an integer known at compile time (array lengths,
    /// loop bounds, indices).
    pub fn const_int(&mut self, e: &syn::Expr, what: &str) -> Option<i64> {
        let mut env = Env::default();
        match self.expr(&mut env, e) {
            Value::Int(n) => Some(n),
            Value::Poison => None,
            other => {
                self.error(
                    e,
                    format!(
                        "{what} must be an integer known at compile time, found {}",
                        other.describe()
                    ),
                );
                None
            }
        }
    }
}
