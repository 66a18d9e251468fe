//! The C header of an exported model, written from what the model's traits carry: the
//! names, units and doc comments of its state, inputs, parameters and outputs, the sizes and
//! indices as macros, and every exported function with its arguments.

use crate::casadi::{Family, Kind};
use crate::model::{Model, Sizes};
use crate::primal::Which;
use hamel_runtime::{HamelSystem, Parameters};
use std::fmt::Write;

/// The header `<name>.h` for the symbols `c_api!` and `casadi!` export under `name`.
pub fn header<M: Model>(name: &str) -> String {
    let upper = name.to_uppercase();
    let s = Sizes::of::<M>();
    let mut h = String::new();
    let w = &mut h;
    line(
        w,
        &format!("/* {name}.h: the model `{name}` exported by hamel (hamel-export)."),
    );
    line(w, " * Generated from the model's definition; do not edit.");
    line(w, " *");
    line(
        w,
        " * Every function is thread-safe and allocates nothing when it succeeds. A function",
    );
    line(
        w,
        " * that returns int returns 0 on success, else one of the status codes below, and",
    );
    line(
        w,
        &format!(" * {name}_last_error() then says what went wrong (per thread). */"),
    );
    line(w, &format!("#ifndef {upper}_H"));
    line(w, &format!("#define {upper}_H"));
    line(w, "");
    line(w, "#include <stddef.h>");
    line(w, "");
    line(w, "#ifdef __cplusplus");
    line(w, "extern \"C\" {");
    line(w, "#endif");
    line(w, "");
    line(w, "#ifndef casadi_real");
    line(w, "#define casadi_real double");
    line(w, "#endif");
    line(w, "#ifndef casadi_int");
    line(w, "#define casadi_int long long int");
    line(w, "#endif");
    line(w, "");
    status_codes(w, &upper);
    sizes::<M>(w, &upper, s);
    c_api(w, name, s);
    for which in [Which::Rhs, Which::Outputs, Which::Lie] {
        if which == Which::Lie && M::LIE == 0 {
            continue;
        }
        casadi_family::<M>(w, name, which);
    }
    line(w, "#ifdef __cplusplus");
    line(w, "} /* extern \"C\" */");
    line(w, "#endif");
    line(w, "");
    line(w, &format!("#endif /* {upper}_H */"));
    h
}

fn line(w: &mut String, text: &str) {
    w.push_str(text);
    w.push('\n');
}

fn status_codes(w: &mut String, upper: &str) {
    line(w, "/* Status codes. */");
    let codes = [
        ("OK", 0, "success"),
        (
            "NULL_POINTER",
            1,
            "a pointer that must not be null was null",
        ),
        ("BAD_DIMENSION", 2, "an array's length is not the model's"),
        ("NON_FINITE", 3, "an argument is NaN or infinite"),
        (
            "SINGULAR",
            4,
            "the model met a singular configuration or mass matrix",
        ),
        (
            "INTERNAL",
            5,
            "an internal error (a bug): the message says where",
        ),
    ];
    for (code, value, meaning) in codes {
        line(
            w,
            &format!("#define {upper}_{code} {value} /* {meaning} */"),
        );
    }
    line(w, "");
}

/// A name with its unit, if the model gives one: `alpha (rad)`.
fn with_unit(name: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("{name} ({u})"),
        None => name.to_string(),
    }
}

/// What the comment of each component of a block says: name, unit, description.
fn components<M: Model>(block: &str) -> Vec<String> {
    let unit = <M::System as HamelSystem>::unit;
    match block {
        "x" => <M::System as HamelSystem>::STATE
            .iter()
            .map(|n| with_unit(n, unit(n)))
            .collect(),
        "u" => <M::System as HamelSystem>::INPUTS
            .iter()
            .map(|n| with_unit(n, unit(n)))
            .collect(),
        "p" => {
            let docs = <M::System as Parameters>::DOCS;
            <M::System as Parameters>::NAMES
                .iter()
                .zip(docs)
                .map(|(n, d)| {
                    let unit = <M::System as Parameters>::parameter_unit(n);
                    let doc = d.trim();
                    match (unit, doc.is_empty()) {
                        (_, true) => with_unit(n, unit),
                        _ => format!("{n}: {doc}"),
                    }
                })
                .collect()
        }
        "y" | "h" => M::OUTPUTS.iter().map(|n| n.to_string()).collect(),
        "t" => vec![with_unit("t", unit("t"))],
        "xdot" => <M::System as HamelSystem>::STATE
            .iter()
            .map(|n| {
                let rate = unit(n).map(|u| rate_unit(u, unit("t").unwrap_or("s")));
                with_unit(&format!("d{n}/dt"), rate.as_deref())
            })
            .collect(),
        "lie" => lie_labels::<M>(),
        _ => Vec::new(),
    }
}

/// The unit of a quantity's rate: `m` gives `m/s`, `rad/s` gives `rad/s^2`.
fn rate_unit(unit: &str, time: &str) -> String {
    match unit.strip_suffix(&format!("/{time}")) {
        Some(base) => format!("{base}/{time}^2"),
        None => format!("{unit}/{time}"),
    }
}

/// The Lie derivatives' components: `L_f^k h_i` for k = 0 … order (`px`, `L_f px`,
/// `L_f^2 px`), then `L_gj L_f^k h_i` for k < order, i, j (`L_g_tau1 L_f px`).
pub fn lie_labels<M: Model>() -> Vec<String> {
    let (outputs, inputs) = (M::OUTPUTS, <M::System as HamelSystem>::INPUTS);
    let (ny, nu) = (outputs.len(), inputs.len());
    if ny == 0 {
        return Vec::new();
    }
    // LIE = (order + 1) ny + order ny nu.
    let order = (M::LIE - ny) / (ny * (1 + nu));
    let power = |k: usize| match k {
        0 => String::new(),
        1 => "L_f ".to_string(),
        k => format!("L_f^{k} "),
    };
    let mut labels = Vec::with_capacity(M::LIE);
    for k in 0..=order {
        labels.extend(outputs.iter().map(|h| format!("{}{h}", power(k))));
    }
    for k in 0..order {
        for h in outputs {
            labels.extend(inputs.iter().map(|u| format!("L_g_{u} {}{h}", power(k))));
        }
    }
    labels
}

/// A C identifier from a component's name (`w[3]` gives `W_3`).
fn ident(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect::<String>()
        .trim_end_matches('_')
        .to_string()
}

fn sizes<M: Model>(w: &mut String, upper: &str, s: Sizes) {
    line(
        w,
        "/* Sizes: the state x, the inputs u, the parameters p, the outputs y. */",
    );
    line(w, &format!("#define {upper}_NX {}", s.nx));
    line(w, &format!("#define {upper}_NU {}", s.nu));
    line(w, &format!("#define {upper}_NP {}", s.np));
    line(w, &format!("#define {upper}_NY {}", s.ny));
    line(
        w,
        &format!(
            "/* Whether f and h take the time t as their last argument (the model depends on it). */\n#define {upper}_TIME_DEPENDENT {}",
            u8::from(M::TIME_DEPENDENT)
        ),
    );
    line(w, "");
    let blocks = [
        ("x", "X", "the state", <M::System as HamelSystem>::STATE),
        ("u", "U", "the inputs", <M::System as HamelSystem>::INPUTS),
        (
            "p",
            "P",
            "the parameters, in the order of the model struct's fields",
            <M::System as Parameters>::NAMES,
        ),
        ("y", "Y", "the outputs", M::OUTPUTS),
    ];
    for (block, letter, what, names) in blocks {
        if names.is_empty() {
            continue;
        }
        line(w, &format!("/* Indices into {block}: {what}. */"));
        for (i, (n, comment)) in names.iter().zip(components::<M>(block)).enumerate() {
            line(
                w,
                &format!("#define {upper}_{letter}_{} {i} /* {comment} */", ident(n)),
            );
        }
        line(w, "");
    }
}

fn c_api(w: &mut String, name: &str, s: Sizes) {
    line(
        w,
        "/* This thread's last error message: empty after a success. */",
    );
    line(w, &format!("const char* {name}_last_error(void);"));
    line(w, "");
    line(
        w,
        &format!(
            "/* xdot = F(t, x, u; p): the right-hand side of the model's reduced ODE.\n * x[{}], u[{}], p[{}] in, xdot[{}] out; each length is checked (nx, nu, np, nxdot). */",
            s.nx, s.nu, s.np, s.nx
        ),
    );
    line(
        w,
        &format!(
            "int {name}_rhs(double t, const double* x, size_t nx, const double* u, size_t nu,\n    const double* p, size_t np, double* xdot, size_t nxdot);"
        ),
    );
    line(w, "");
    line(
        w,
        &format!(
            "/* y = h(t, x; p): the model's outputs (none without #[outputs]); y[{}] out. */",
            s.ny
        ),
    );
    line(
        w,
        &format!(
            "int {name}_outputs(double t, const double* x, size_t nx, const double* p, size_t np,\n    double* y, size_t ny);"
        ),
    );
    line(w, "");
    line(
        w,
        "/* The model's default parameters, in the order of p. */",
    );
    line(
        w,
        &format!("int {name}_default_parameters(double* p, size_t np);"),
    );
    line(w, "");
}

fn casadi_family<M: Model>(w: &mut String, name: &str, which: Which) {
    let family = Family::new::<M>(which);
    let base = format!("{name}_{}", which.suffix());
    let what = match which {
        Which::Rhs => "the right-hand side xdot = F(x, u, p)",
        Which::Outputs => "the outputs y = h(x, p)",
        Which::Lie => {
            "the outputs' Lie derivatives along the drift f and the input fields g_j\n * \
             (xdot = f(x) + sum_j g_j(x) u_j): L_f^k h for k = 0 .. order, then L_gj L_f^k h for\n * k < order"
        }
    };
    line(
        w,
        &format!(
            "/* CasADi's external functions of {what}: casadi.external(\"{base}\", library).\n * Inputs and outputs are CasADi's arrays of pointers (arg, res); a null input is zero,\n * a null output is not computed. Sparse outputs are in compressed column storage. */"
        ),
    );
    for kind in Kind::ALL {
        let f = family.function(kind);
        let fname = format!("{}{base}", kind.prefix());
        line(w, &format!("/* {fname}: {} */", describe(kind)));
        for (i, port) in f.inputs.iter().enumerate() {
            let p = &port.pattern;
            line(
                w,
                &format!(
                    " /*   arg[{i}] {}: {}x{}, {} nonzeros{} */",
                    port.name(),
                    p.nrow,
                    p.ncol,
                    p.nnz(),
                    block_note::<M>(port.name())
                ),
            );
        }
        for (i, (port, _)) in f.outputs.iter().enumerate() {
            let p = &port.pattern;
            line(
                w,
                &format!(
                    " /*   res[{i}] {}: {}x{}, {} nonzeros{} */",
                    port.name(),
                    p.nrow,
                    p.ncol,
                    p.nnz(),
                    block_note::<M>(port.name())
                ),
            );
        }
        prototypes(w, &fname);
    }
}

/// The components of a primal input, listed after its port.
fn block_note<M: Model>(port: &str) -> String {
    let list = components::<M>(port);
    if list.is_empty() {
        String::new()
    } else {
        format!(": {}", list.join(", "))
    }
}

fn describe(kind: Kind) -> &'static str {
    match kind {
        Kind::Value => "the values",
        Kind::Jacobian => "every Jacobian block, exact",
        Kind::Forward => "one forward directional derivative",
        Kind::Forward2 | Kind::Forward4 | Kind::Forward8 => {
            "forward directional derivatives, one column of each fwd_ block per direction (CasADi calls fwdN for a batch of exactly N directions)"
        }
        Kind::Adjoint => "one adjoint (reverse) directional derivative",
        Kind::AdjointJacobian => {
            "the Jacobian of adj1: the second derivatives weighted by adj (an exact Hessian of a Lagrangian)"
        }
    }
}

fn prototypes(w: &mut String, f: &str) {
    let mut text = String::new();
    let _ = write!(
        text,
        "int {f}(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem);
casadi_int {f}_n_in(void);
casadi_int {f}_n_out(void);
const char* {f}_name_in(casadi_int i);
const char* {f}_name_out(casadi_int i);
const casadi_int* {f}_sparsity_in(casadi_int i);
const casadi_int* {f}_sparsity_out(casadi_int i);
int {f}_work(casadi_int* sz_arg, casadi_int* sz_res, casadi_int* sz_iw, casadi_int* sz_w);
casadi_real {f}_default_in(casadi_int i);
void {f}_incref(void);
void {f}_decref(void);
int {f}_checkout(void);
void {f}_release(int mem);
int {f}_alloc_mem(void);
int {f}_init_mem(int mem);
void {f}_free_mem(int mem);
"
    );
    w.push_str(&text);
    w.push('\n');
}
