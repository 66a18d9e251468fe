//! The functions a model exports, each as CasADi sees a function: named dense inputs
//! (blocks of z) and one dense output, with the dependency of each output component on z's
//! components (from the generated code's graph), which gives the sparsity of every
//! derivative the compiled code does not give more exactly.

use crate::model::{Model, Sizes, local_columns};
use hamel_runtime::Parameters;

/// Which of the model's functions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Which {
    /// ẋ = F(x, u, p[, t]), named `<model>_f`.
    Rhs,
    /// y = h(x, p[, t]), named `<model>_h`.
    Outputs,
    /// The outputs' Lie derivatives (a model with `control(..)`, compiled code only): L_f^k h
    /// for k = 0 … order, then L_{g_j} L_f^k h for k < order, named `<model>_lie`.
    Lie,
}

impl Which {
    /// The suffix of the exported name: `f` or `h`.
    pub fn suffix(self) -> &'static str {
        match self {
            Which::Rhs => "f",
            Which::Outputs => "h",
            Which::Lie => "lie",
        }
    }

    /// How many output components `which` has for the model.
    pub fn outputs<M: Model>(self) -> usize {
        let s = Sizes::of::<M>();
        match self {
            Which::Rhs => s.nx,
            Which::Outputs => s.ny,
            Which::Lie => M::LIE,
        }
    }
}

/// An input of a primal function: a named block of z.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Block {
    pub name: &'static str,
    /// Where the block starts in z.
    pub offset: usize,
    pub len: usize,
}

/// A primal function's blocks, output and dependencies.
#[derive(Clone, Debug)]
pub struct Primal {
    pub which: Which,
    pub inputs: Vec<Block>,
    /// The output's name (`xdot`, `y`) and length.
    pub output: (&'static str, usize),
    /// For each output component, the indices into z it depends on, ascending.
    pub depends: Vec<Vec<usize>>,
    pub sizes: Sizes,
}

impl Primal {
    pub fn new<M: Model>(which: Which) -> Primal {
        let s = Sizes::of::<M>();
        let mut inputs = vec![Block {
            name: "x",
            offset: 0,
            len: s.nx,
        }];
        if which == Which::Rhs {
            inputs.push(Block {
                name: "u",
                offset: s.u(),
                len: s.nu,
            });
        }
        inputs.push(Block {
            name: "p",
            offset: s.p(),
            len: s.np,
        });
        if M::TIME_DEPENDENT {
            inputs.push(Block {
                name: "t",
                offset: s.t(),
                len: 1,
            });
        }
        let (output, columns, parameters) = match which {
            Which::Rhs => (("xdot", s.nx), M::RHS_COLUMNS, M::RHS_PARAMETERS),
            Which::Outputs => (("y", s.ny), M::OUTPUT_COLUMNS, M::OUTPUT_PARAMETERS),
            Which::Lie => (("lie", M::LIE), &[][..], &[][..]),
        };
        let names = <M::System as Parameters>::NAMES;
        // The Lie derivatives' dependencies are those the compiled code's graph gives.
        let compiled = M::tables(which).filter(|_| which == Which::Lie);
        let local = local_columns::<M>();
        let depends = (0..output.1)
            .map(|row| {
                let mut d: Vec<usize> = columns.get(row).copied().unwrap_or(&[]).to_vec();
                for name in parameters.get(row).copied().unwrap_or(&[]) {
                    if let Some(i) = names.iter().position(|n| n == name) {
                        d.push(s.p() + i);
                    }
                }
                if let Some(tables) = &compiled {
                    let row = tables.depends.get(row).copied().unwrap_or(&[]);
                    d.extend(row.iter().filter_map(|&c| local.get(c)));
                }
                if M::TIME_DEPENDENT {
                    d.push(s.t());
                }
                d.sort_unstable();
                d.dedup();
                d
            })
            .collect();
        Primal {
            which,
            inputs,
            output,
            depends,
            sizes: s,
        }
    }

    /// Whether output component `row` depends on z's component `column`.
    pub fn depends_on(&self, row: usize, column: usize) -> bool {
        self.depends
            .get(row)
            .is_some_and(|d| d.binary_search(&column).is_ok())
    }

    /// Whether some output component depends on both `a` and `b`: the second derivatives
    /// that can be nonzero.
    pub fn pair(&self, a: usize, b: usize) -> bool {
        self.depends
            .iter()
            .any(|d| d.binary_search(&a).is_ok() && d.binary_search(&b).is_ok())
    }
}
