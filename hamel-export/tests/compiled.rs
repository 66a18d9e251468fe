//! The compiled derivatives (feature `compiled`) against dual and hyper-dual numbers through
//! the model's generic right-hand side, for catalogue models of every kind: the paper's robot
//! in both forms (B given, and A inverted at run time), a model whose right-hand side
//! depends on the time (the ball on a turntable), a holonomic one (the rolling disk), the
//! Whipple bicycle (whose parameter stages are too large to compile: dual numbers there),
//! the 24-trailer train (whose Jacobian and second derivatives are all by dual numbers),
//! and the outputs and Lie derivatives of the robot. At random points, through CasADi's
//! calling convention: values bit for bit, every Jacobian block, forward and adjoint
//! derivatives and every weighted second-derivative block, each entry within 1e-12 of the
//! passes' relative to the largest of its row or block (both are exact derivatives, computed
//! by different operations); and the compiled sparsity exact: the passes find nothing
//! outside it.
//!
//! `cargo test -p hamel-export --features compiled --test compiled` (a `.ci/run`
//! stage: the feature compiles the catalogue's derivative code).
#![cfg(feature = "compiled")]
// The checks walk matrices by their (row, column) positions, as the derivatives are written.
#![allow(clippy::needless_range_loop)]

use hamel_export::casadi::sparsity::Pattern;
use hamel_export::casadi::{Family, Kind};
use hamel_export::{Model, Sizes, Which, passes};
use hamel_runtime::{HamelSystem, Parameters, Vector};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::mem::MaybeUninit;
use std::sync::atomic::{AtomicUsize, Ordering};

hamel_export::model!(Robot => hamel_models::MobileRobot);
hamel_export::model!(Paper => hamel_models::MobileRobotPaper);
hamel_export::model!(Turntable => hamel_models::BallOnTurntable);
hamel_export::model!(Disk => hamel_models::RollingDisk);
hamel_export::model!(Bicycle => hamel_models::WhippleBicycle);
hamel_export::model!(Train => hamel_models::NTrailer24);

/// A small deterministic generator (xorshift), for reproducible points.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [−a, a].
    fn within(&mut self, a: f64) -> f64 {
        a * (2.0 * self.next() - 1.0)
    }
}

/// z = (x, u, p, t): the state and inputs random, the parameters the defaults within ±10 %.
fn point<M: Model>(random: &mut Random) -> Vec<f64> {
    let s = Sizes::of::<M>();
    let system = M::System::default();
    let mut z: Vec<f64> = (0..s.p()).map(|_| random.within(0.8)).collect();
    for name in <M::System as Parameters>::NAMES {
        let value = system.get(name).unwrap_or(0.0);
        z.push(value * (1.0 + random.within(0.1)));
    }
    z.push(random.within(2.0));
    z
}

/// Dense from compressed column storage.
fn dense(pattern: &Pattern, values: &[f64]) -> Vec<Vec<f64>> {
    let mut m = vec![vec![0.0; pattern.ncol]; pattern.nrow];
    for c in 0..pattern.ncol {
        for k in pattern.column(c) {
            m[pattern.row(k)][c] = values[k];
        }
    }
    m
}

/// Call `kind` of `family` with `args` (null for `None`); its outputs, all wanted.
fn call<M: Model>(family: &Family, kind: Kind, args: &[Option<&[f64]>]) -> Vec<Vec<f64>> {
    call_wanting::<M>(family, kind, args, |_| true)
        .into_iter()
        .map(Option::unwrap_or_default)
        .collect()
}

/// Call `kind` of `family` with `args` (null for `None`), wanting the outputs `wanted` says
/// (the others null, as CasADi passes what it does not need).
fn call_wanting<M: Model>(
    family: &Family,
    kind: Kind,
    args: &[Option<&[f64]>],
    wanted: impl Fn(usize) -> bool,
) -> Vec<Option<Vec<f64>>> {
    let f = family.function(kind);
    let mut outs: Vec<Option<Vec<f64>>> = f
        .outputs
        .iter()
        .enumerate()
        .map(|(k, (port, _))| wanted(k).then(|| vec![f64::NAN; port.pattern.nnz()]))
        .collect();
    let arg: Vec<*const f64> = (0..f.inputs.len())
        .map(|i| {
            args.get(i)
                .copied()
                .flatten()
                .map_or(core::ptr::null(), <[f64]>::as_ptr)
        })
        .collect();
    let res: Vec<*mut f64> = outs
        .iter_mut()
        .map(|o| o.as_mut().map_or(core::ptr::null_mut(), |o| o.as_mut_ptr()))
        .collect();
    // SAFETY: a pointer per port, null or to as many values as its pattern has nonzeros.
    unsafe { hamel_export::casadi::eval::<M>(family, kind, arg.as_ptr(), res.as_ptr()) }
        .unwrap_or_else(|e| panic!("{kind:?}: {}", e.message));
    outs
}

/// The outputs of `kind` that do not involve the parameters, wanted alone (those by p null:
/// the compiled code then skips its parameters' stage), equal the same outputs of a call
/// that wants every one (`all`), bit for bit.
fn without_parameters<M: Model>(
    family: &Family,
    kind: Kind,
    args: &[Option<&[f64]>],
    all: &[Vec<f64>],
) {
    let f = family.function(kind);
    let p = family.primal.inputs.iter().position(|b| b.name == "p");
    let by_p = |k: usize| {
        let name = f.outputs[k].0.name();
        p.is_some() && (name.ends_with("_p") || name.starts_with("jac_adj_p_"))
    };
    let some = call_wanting::<M>(family, kind, args, |k| !by_p(k));
    for (k, out) in some.iter().enumerate() {
        if let Some(out) = out {
            let (a, b): (Vec<u64>, Vec<u64>) = (
                out.iter().map(|v| v.to_bits()).collect(),
                all[k].iter().map(|v| v.to_bits()).collect(),
            );
            assert_eq!(a, b, "{kind:?} {} without p", f.outputs[k].0.name());
        }
    }
}

/// The primal inputs' slices of z.
fn blocks<'a>(family: &Family, z: &'a [f64]) -> Vec<Option<&'a [f64]>> {
    family
        .primal
        .inputs
        .iter()
        .map(|b| Some(&z[b.offset..b.offset + b.len]))
        .collect()
}

/// Within 1e-12 of `scale`, the largest entry of the derivative compared: both sides are
/// exact derivatives, but computed by different operations, and an entry that is zero on the
/// graph is the rounding of a cancellation by dual numbers (1e-17 where others are 1).
fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale.max(1e-300)
}

/// `fwd2_f`, `fwd4_f`, `fwd8_f` along random directions of every input, and of all but the
/// parameters (the compiled Jacobian's stage by x, u and t alone): each column the product
/// of the Jacobian (by columns of dual numbers) with its direction, as `fwd1_f` is checked.
fn forward_directions<M: Model>(
    family: &Family,
    args: &[Option<&[f64]>],
    columns: &[Vec<f64>],
    random: &mut Random,
) {
    let primal = &family.primal;
    let (no, nz) = (primal.output.1, columns.len());
    for kind in [Kind::Forward2, Kind::Forward4, Kind::Forward8] {
        let n = kind.directions();
        for with_parameters in [true, false] {
            // Direction d over z; zero in p unless `with_parameters`.
            let direction: Vec<Vec<f64>> = (0..n)
                .map(|_| {
                    (0..nz)
                        .map(|c| {
                            let in_p = primal.inputs.iter().any(|b| {
                                b.name == "p" && (b.offset..b.offset + b.len).contains(&c)
                            });
                            let v = random.within(1.0);
                            if in_p && !with_parameters { 0.0 } else { v }
                        })
                        .collect()
                })
                .collect();
            // CasADi's stacked columns, block by block.
            let stacked: Vec<Vec<f64>> = primal
                .inputs
                .iter()
                .map(|b| {
                    direction
                        .iter()
                        .flat_map(|v| v[b.offset..b.offset + b.len].iter().copied())
                        .collect()
                })
                .collect();
            let mut fwd_args = args.to_vec();
            fwd_args.push(None);
            fwd_args.extend(stacked.iter().map(|v| Some(v.as_slice())));
            let fwd = call::<M>(family, kind, &fwd_args);
            for (d, v) in direction.iter().enumerate() {
                let scale = (0..no)
                    .flat_map(|r| (0..nz).map(move |c| (r, c)))
                    .map(|(r, c)| (columns[c][r] * v[c]).abs())
                    .fold(0.0, f64::max);
                for r in 0..no {
                    let exact: f64 = (0..nz).map(|c| columns[c][r] * v[c]).sum();
                    assert!(
                        close(fwd[0][d * no + r], exact, scale),
                        "{:?} fwd{n} direction {d} row {r}: {} vs {exact}",
                        primal.which,
                        fwd[0][d * no + r]
                    );
                }
            }
        }
    }
}

/// The model's own right-hand side (`HamelSystem::rhs`) at z.
fn own_rhs<M: Model>(z: &[f64], out: &mut [f64]) {
    let s = Sizes::of::<M>();
    let mut system = M::System::default();
    for (name, value) in <M::System as Parameters>::NAMES
        .iter()
        .zip(&z[s.p()..s.t()])
    {
        system.set(name, *value).unwrap();
    }
    let mut x = <M::System as HamelSystem>::State::zeros();
    x.as_mut().copy_from_slice(&z[..s.nx]);
    let mut u = <M::System as HamelSystem>::Inputs::zeros();
    u.as_mut().copy_from_slice(&z[s.u()..s.p()]);
    let mut dx = <M::System as HamelSystem>::State::zeros();
    system.rhs(z[s.t()], &x, &u, &mut dx).unwrap();
    out[..s.nx].copy_from_slice(dx.as_ref());
}

/// Every function of `which` against the passes at a few random points.
fn check<M: Model>(which: Which, seed: u64) {
    let family = Family::new::<M>(which);
    // The places the library was compiled with (`hamel_export::layout`) are the outputs'
    // patterns': else every block would be left to the dual numbers.
    if let Some(plans) = &family.plans {
        assert!(plans.jacobian.agrees(), "{which:?}: jac_ layout disagrees");
        assert!(
            plans.second.agrees(),
            "{which:?}: jac_adj1_ layout disagrees"
        );
    }
    let primal = &family.primal;
    let (no, nz) = (primal.output.1, Sizes::of::<M>().z());
    if no == 0 {
        return;
    }
    let mut random = Random(seed);
    for _ in 0..3 {
        let z = point::<M>(&mut random);
        let args = blocks(&family, &z);
        // Values: the right-hand side bit for bit the model's own (`HamelSystem::rhs`, which
        // prepares its parameter-only values too); the outputs and Lie derivatives within a
        // few roundings of the generic code's (which computes those values inline).
        let value = call::<M>(&family, Kind::Value, &args);
        let mut expected = vec![0.0; nz.max(no)];
        passes::value::<M>(which, &z, &mut expected).unwrap();
        if which == Which::Rhs {
            own_rhs::<M>(&z, &mut expected);
        }
        let scale = expected.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for r in 0..no {
            if which == Which::Rhs {
                assert_eq!(
                    value[0][r].to_bits(),
                    expected[r].to_bits(),
                    "{which:?} value {r}"
                );
            } else {
                assert!(
                    (value[0][r] - expected[r]).abs() <= 4.0 * f64::EPSILON * scale,
                    "{which:?} value {r}: {} vs {}",
                    value[0][r],
                    expected[r]
                );
            }
        }
        // The Jacobian by columns of dual numbers.
        let mut columns = vec![vec![0.0; no]; nz];
        for (c, column) in columns.iter_mut().enumerate() {
            let mut out = vec![0.0; nz.max(no)];
            passes::column::<M>(which, &z, c, &mut out).unwrap();
            column.copy_from_slice(&out[..no]);
        }
        let jacobian = call::<M>(&family, Kind::Jacobian, &args);
        without_parameters::<M>(&family, Kind::Jacobian, &args, &jacobian);
        let scale = columns
            .iter()
            .flatten()
            .map(|v| v.abs())
            .fold(0.0, f64::max);
        for (k, block) in primal.inputs.iter().enumerate() {
            let pattern = &family.function(Kind::Jacobian).outputs[k].0.pattern;
            let m = dense(pattern, &jacobian[k]);
            for r in 0..no {
                for c in 0..block.len {
                    let exact = columns[block.offset + c][r];
                    assert!(
                        close(m[r][c], exact, scale),
                        "{which:?} jac {} ({r}, {c}): {} vs {exact}",
                        block.name,
                        m[r][c]
                    );
                    if exact.abs() > 1e-12 * scale {
                        assert!(
                            pattern.position(r, c).is_some(),
                            "{which:?} pattern ({r}, {c})"
                        );
                    }
                }
            }
        }
        // Forward along a random direction of every input; adjoint with random weights.
        let direction: Vec<f64> = (0..nz).map(|_| random.within(1.0)).collect();
        let weights: Vec<f64> = (0..no).map(|_| random.within(1.0)).collect();
        let mut fwd_args = args.clone();
        fwd_args.push(None);
        fwd_args.extend(blocks(&family, &direction));
        let fwd = call::<M>(&family, Kind::Forward, &fwd_args);
        // As for the Jacobian, relative to the largest term of the whole derivative: an
        // entry whose terms cancel is the rounding of intermediate values of that size.
        let scale = (0..no)
            .flat_map(|r| (0..nz).map(move |c| (r, c)))
            .map(|(r, c)| (columns[c][r] * direction[c]).abs())
            .fold(0.0, f64::max);
        for r in 0..no {
            let exact: f64 = (0..nz).map(|c| columns[c][r] * direction[c]).sum();
            assert!(
                close(fwd[0][r], exact, scale),
                "{which:?} fwd {r}: {} vs {exact}",
                fwd[0][r]
            );
        }
        forward_directions::<M>(&family, &args, &columns, &mut random);
        let mut adj_args = args.clone();
        adj_args.push(None);
        adj_args.push(Some(&weights));
        let adj = call::<M>(&family, Kind::Adjoint, &adj_args);
        for (k, block) in primal.inputs.iter().enumerate() {
            // Relative to the largest term of the block, as for the second derivatives.
            let scale = (0..block.len)
                .flat_map(|c| (0..no).map(move |r| (r, c)))
                .map(|(r, c)| (columns[block.offset + c][r] * weights[r]).abs())
                .fold(0.0, f64::max);
            for c in 0..block.len {
                let exact: f64 = (0..no)
                    .map(|r| columns[block.offset + c][r] * weights[r])
                    .sum();
                assert!(
                    close(adj[k][c], exact, scale),
                    "{which:?} adj {} {c}: {} vs {exact} (scale {scale})",
                    block.name,
                    adj[k][c]
                );
            }
        }
        // The weighted second derivatives, every block, by hyper-dual numbers.
        let second = call::<M>(&family, Kind::AdjointJacobian, &adj_args);
        without_parameters::<M>(&family, Kind::AdjointJacobian, &adj_args, &second);
        let f = family.function(Kind::AdjointJacobian);
        let nb = primal.inputs.len();
        for (i, bi) in primal.inputs.iter().enumerate() {
            for (j, bj) in primal.inputs.iter().enumerate() {
                let k = i * (nb + 2) + j;
                let pattern = &f.outputs[k].0.pattern;
                let m = dense(pattern, &second[k]);
                let mut exact = vec![vec![0.0; bj.len]; bi.len];
                let mut scale = 0.0f64;
                for a in 0..bi.len {
                    for b in 0..bj.len {
                        let mut out = vec![0.0; nz.max(no)];
                        passes::second::<M>(which, &z, (bi.offset + a, bj.offset + b), &mut out)
                            .unwrap();
                        let terms: Vec<f64> = (0..no).map(|r| weights[r] * out[r]).collect();
                        exact[a][b] = terms.iter().sum();
                        scale = terms.iter().map(|t| t.abs()).fold(scale, f64::max);
                    }
                }
                for a in 0..bi.len {
                    for b in 0..bj.len {
                        assert!(
                            close(m[a][b], exact[a][b], scale),
                            "{which:?} second {}{} ({a}, {b}): {} vs {}",
                            bi.name,
                            bj.name,
                            m[a][b],
                            exact[a][b]
                        );
                        if exact[a][b].abs() > 1e-12 * scale {
                            assert!(
                                pattern.position(a, b).is_some(),
                                "{which:?} pattern {}{} ({a}, {b})",
                                bi.name,
                                bj.name
                            );
                        }
                    }
                }
            }
            // The transposed Jacobian block.
            let k = i * (nb + 2) + nb + 1;
            let m = dense(&f.outputs[k].0.pattern, &second[k]);
            for a in 0..bi.len {
                for r in 0..no {
                    let exact = columns[bi.offset + a][r];
                    assert!(
                        close(m[a][r], exact, scale),
                        "{which:?} transposed {} ({a}, {r})",
                        bi.name
                    );
                }
            }
        }
    }
}

#[test]
fn robot_bodies() {
    assert!(Robot::tables(Which::Rhs).is_some_and(|t| t.compiled == [true; 4]));
    check::<Robot>(Which::Rhs, 1);
    check::<Robot>(Which::Outputs, 2);
    check::<Robot>(Which::Lie, 3);
}

#[test]
fn robot_paper() {
    check::<Paper>(Which::Rhs, 4);
}

#[test]
fn time_dependent() {
    const { assert!(<Turntable as Model>::TIME_DEPENDENT) };
    check::<Turntable>(Which::Rhs, 5);
}

#[test]
fn holonomic() {
    check::<Disk>(Which::Rhs, 6);
}

#[test]
fn bicycle() {
    let tables = Bicycle::tables(Which::Rhs).unwrap();
    assert_eq!(tables.compiled, [true, false, true, false]);
    check::<Bicycle>(Which::Rhs, 7);
    check::<Bicycle>(Which::Lie, 8);
}

#[test]
fn train() {
    let tables = Train::tables(Which::Rhs).unwrap();
    assert_eq!(tables.compiled, [false; 4]);
    check::<Train>(Which::Rhs, 9);
}

/// The compiled adjoint writes every one of its local columns (x, u, the parameters the
/// code reads, t), the parameters' with `parameters`: what `adj1_f` relies on to read
/// them from an array it does not zero. Each column is first a NaN whose payload the code
/// never makes, and must not be that NaN after the call.
fn adjoint_writes_every_column<M: Model>(which: Which, seed: u64) {
    const UNWRITTEN: u64 = 0x7ff8_dead_beef_0001;
    let s = Sizes::of::<M>();
    let columns = hamel_export::model::local_columns::<M>();
    let outputs = match which {
        Which::Rhs => s.nx,
        Which::Outputs => s.ny,
        Which::Lie => M::LIE,
    };
    let mut random = Random(seed);
    let z = point::<M>(&mut random);
    let mut point = M::array(0.0);
    point.as_mut()[..z.len()].copy_from_slice(&z);
    let weights: Vec<f64> = (0..outputs).map(|_| random.within(1.0)).collect();
    let adjoint = |parameters: bool| {
        let mut local = M::array(MaybeUninit::new(f64::from_bits(UNWRITTEN)));
        let written = M::with_prepared(&z[s.p()..s.t()], |prepared| {
            M::compiled_adjoint(which, prepared, &point, &weights, parameters, &mut local)
        });
        assert!(
            matches!(written, Some(Ok(()))),
            "{which:?}: the compiled adjoint did not run"
        );
        // SAFETY: every value was initialized (to UNWRITTEN) before the call.
        let local = unsafe { M::assume_init_ref(&local) };
        local.as_ref()[..columns.len()].to_vec()
    };
    let (all, states) = (adjoint(true), adjoint(false));
    for (c, &column) in columns.iter().enumerate() {
        assert_ne!(
            all[c].to_bits(),
            UNWRITTEN,
            "{which:?}: column {c} not written"
        );
        if !(s.p()..s.t()).contains(&column) {
            assert_eq!(
                states[c].to_bits(),
                all[c].to_bits(),
                "{which:?}: column {c}"
            );
        }
    }
}

#[test]
fn compiled_adjoint_writes_every_column() {
    adjoint_writes_every_column::<Robot>(Which::Rhs, 11);
    adjoint_writes_every_column::<Robot>(Which::Outputs, 12);
    adjoint_writes_every_column::<Robot>(Which::Lie, 13);
    adjoint_writes_every_column::<Turntable>(Which::Rhs, 14);
    adjoint_writes_every_column::<Bicycle>(Which::Rhs, 15);
}

/// Counts the heap allocations of the threads that ask for it (the tests run in parallel).
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static COUNTED: Cell<bool> = const { Cell::new(false) };
}

// SAFETY: every call is forwarded to the system allocator unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTED.with(Cell::get) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Once a family is described, a call of any of its functions allocates nothing, with the
/// parameters changing between calls (the prepared values computed again).
#[test]
fn calls_allocate_nothing() {
    let family = Family::new::<Robot>(Which::Rhs);
    let mut random = Random(10);
    for kind in Kind::ALL {
        let f = family.function(kind);
        let z = point::<Robot>(&mut random);
        // Enough for the largest seed port (fwd8_f's directions in p).
        let seeds: Vec<f64> = (0..8 * Sizes::of::<Robot>().z())
            .map(|_| random.within(1.0))
            .collect();
        // Every input given (the nominal outputs as zeros), every output wanted.
        let inputs: Vec<Vec<f64>> = f
            .inputs
            .iter()
            .enumerate()
            .map(|(k, port)| match family.primal.inputs.get(k) {
                Some(b) => z[b.offset..b.offset + b.len].to_vec(),
                None => seeds[..port.pattern.nnz()].to_vec(),
            })
            .collect();
        let mut outs: Vec<Vec<f64>> = f
            .outputs
            .iter()
            .map(|(port, _)| vec![0.0; port.pattern.nnz()])
            .collect();
        let arg: Vec<*const f64> = inputs.iter().map(|v| v.as_ptr()).collect();
        let res: Vec<*mut f64> = outs.iter_mut().map(|o| o.as_mut_ptr()).collect();
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        COUNTED.with(|c| c.set(true));
        // SAFETY: a pointer per port, each to as many values as its pattern has nonzeros.
        let result = unsafe {
            hamel_export::casadi::eval::<Robot>(&family, kind, arg.as_ptr(), res.as_ptr())
        };
        COUNTED.with(|c| c.set(false));
        assert!(result.is_ok(), "{kind:?}");
        assert_eq!(
            ALLOCATIONS.load(Ordering::Relaxed),
            before,
            "{kind:?} allocated"
        );
    }
}
