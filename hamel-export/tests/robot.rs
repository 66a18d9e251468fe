//! The paper's robot through the exported C functions, called as C calls them: values equal
//! to the model's own right-hand side bit for bit, derivatives equal to the runtime's
//! Jacobian and to central differences, and every bad argument refused with a status and a
//! message, never a panic.

// Matrices are compared entry by entry, by their indices.
#![allow(clippy::needless_range_loop)]

use core::ffi::{CStr, c_int};
use hamel_export::casadi::sparsity::CasadiInt;
use hamel_models::MobileRobot;
use hamel_runtime::{HamelSystem, Parameters};

hamel_export::model!(Robot => MobileRobot);
hamel_export::c_api!(Robot, "robot");
hamel_export::casadi!(Robot, "robot");

unsafe extern "C" {
    fn robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn jac_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn adj1_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn fwd1_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn fwd2_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn fwd4_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn fwd8_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn fwd8_robot_f_sparsity_in(i: CasadiInt) -> *const CasadiInt;
    fn jac_adj1_robot_f(
        a: *const *const f64,
        r: *const *mut f64,
        iw: *mut CasadiInt,
        w: *mut f64,
        m: c_int,
    ) -> c_int;
    fn jac_robot_f_sparsity_out(i: CasadiInt) -> *const CasadiInt;
    fn jac_adj1_robot_f_sparsity_out(i: CasadiInt) -> *const CasadiInt;
    fn jac_adj1_robot_f_n_out() -> CasadiInt;
    fn robot_f_name_in(i: CasadiInt) -> *const core::ffi::c_char;
    fn robot_last_error() -> *const core::ffi::c_char;
    fn robot_rhs(
        t: f64,
        x: *const f64,
        nx: usize,
        u: *const f64,
        nu: usize,
        p: *const f64,
        np: usize,
        xd: *mut f64,
        nxd: usize,
    ) -> c_int;
}

type Eval = unsafe extern "C" fn(
    *const *const f64,
    *const *mut f64,
    *mut CasadiInt,
    *mut f64,
    c_int,
) -> c_int;

const X: [f64; 8] = [0.3, -0.2, 0.25, 1.1, -0.7, 0.4, 0.8, -0.3];
const U: [f64; 2] = [0.6, -0.2];

fn parameters() -> Vec<f64> {
    let robot = MobileRobot::default();
    MobileRobot::NAMES
        .iter()
        .map(|n| robot.get(n).unwrap())
        .collect()
}

fn last_error() -> String {
    unsafe { CStr::from_ptr(robot_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// Dense blocks from CasADi's compressed column storage.
fn dense(pattern: *const CasadiInt, values: &[f64]) -> Vec<Vec<f64>> {
    let head = unsafe { core::slice::from_raw_parts(pattern, 2) };
    let (nrow, ncol) = (head[0] as usize, head[1] as usize);
    let colind = unsafe { core::slice::from_raw_parts(pattern.add(2), ncol + 1) };
    let nnz = colind[ncol] as usize;
    let rows = unsafe { core::slice::from_raw_parts(pattern.add(3 + ncol), nnz) };
    let mut m = vec![vec![0.0; ncol]; nrow];
    for c in 0..ncol {
        for k in colind[c] as usize..colind[c + 1] as usize {
            m[rows[k] as usize][c] = values[k];
        }
    }
    m
}

fn call(f: Eval, args: &[*const f64], outs: &mut [Vec<f64>]) -> c_int {
    let mut res: Vec<*mut f64> = outs.iter_mut().map(|o| o.as_mut_ptr()).collect();
    unsafe {
        f(
            args.as_ptr(),
            res.as_mut_ptr(),
            core::ptr::null_mut(),
            core::ptr::null_mut(),
            0,
        )
    }
}

/// `f` called with null argument and result arrays: status 1 and a message naming the null
/// pointer, never a crash.
fn refuses_null_arrays(f: Eval) {
    let status = unsafe {
        f(
            core::ptr::null(),
            core::ptr::null(),
            core::ptr::null_mut(),
            core::ptr::null_mut(),
            0,
        )
    };
    assert_eq!(status, 1);
    assert!(last_error().contains("null pointer"), "{}", last_error());
}

fn rhs(p: &[f64], x: &[f64; 8], u: &[f64; 2]) -> [f64; 8] {
    let mut robot = MobileRobot::default();
    for (n, v) in MobileRobot::NAMES.iter().zip(p) {
        robot.set(n, *v).unwrap();
    }
    let mut dx = [0.0; 8];
    robot.rhs(0.0, x, u, &mut dx).unwrap();
    dx
}

#[test]
fn values_are_the_models_right_hand_side_bit_for_bit() {
    let p = parameters();
    let mut out = vec![vec![0.0; 8]];
    assert_eq!(
        call(robot_f, &[X.as_ptr(), U.as_ptr(), p.as_ptr()], &mut out),
        0
    );
    let expected = rhs(&p, &X, &U);
    for (a, b) in out[0].iter().zip(&expected) {
        assert_eq!(a.to_bits(), b.to_bits(), "{:?} vs {expected:?}", out[0]);
    }
    let mut plain = [0.0; 8];
    let status = unsafe {
        robot_rhs(
            0.0,
            X.as_ptr(),
            8,
            U.as_ptr(),
            2,
            p.as_ptr(),
            9,
            plain.as_mut_ptr(),
            8,
        )
    };
    assert_eq!(status, 0);
    assert_eq!(plain.map(f64::to_bits), expected.map(f64::to_bits));
}

#[test]
fn jacobian_blocks_are_the_runtimes_and_central_differences() {
    let p = parameters();
    let mut out = vec![vec![0.0; 64], vec![0.0; 16], vec![0.0; 72]];
    assert_eq!(
        call(
            jac_robot_f,
            &[X.as_ptr(), U.as_ptr(), p.as_ptr(), core::ptr::null()],
            &mut out
        ),
        0
    );
    let fx = dense(unsafe { jac_robot_f_sparsity_out(0) }, &out[0]);
    let fu = dense(unsafe { jac_robot_f_sparsity_out(1) }, &out[1]);
    let fp = dense(unsafe { jac_robot_f_sparsity_out(2) }, &out[2]);
    let (a, b) = MobileRobot::default().jacobian(0.0, &X, &U).unwrap();
    for r in 0..8 {
        for c in 0..8 {
            assert!(
                (fx[r][c] - a[r * 8 + c]).abs() <= 1e-14 * (1.0 + a[r * 8 + c].abs()),
                "x {r} {c}"
            );
        }
        for c in 0..2 {
            assert!(
                (fu[r][c] - b[r * 2 + c]).abs() <= 1e-14 * (1.0 + b[r * 2 + c].abs()),
                "u {r} {c}"
            );
        }
    }
    // ∂F/∂p against central differences (h = 1e-6 of the parameter: truncation ~1e-12,
    // rounding ~1e-10 of the values).
    for (c, value) in p.iter().enumerate() {
        let h = 1e-6 * value.abs().max(1.0);
        let (mut up, mut down) = (p.clone(), p.clone());
        up[c] += h;
        down[c] -= h;
        let (fu, fd) = (rhs(&up, &X, &U), rhs(&down, &X, &U));
        for r in 0..8 {
            let difference = (fu[r] - fd[r]) / (2.0 * h);
            assert!(
                (fp[r][c] - difference).abs() <= 1e-6 * (1.0 + difference.abs()),
                "p {r} {c}: {} vs {difference}",
                fp[r][c]
            );
        }
    }
}

#[test]
fn forward_and_adjoint_derivatives_agree_with_the_jacobian() {
    let p = parameters();
    let mut jac = vec![vec![0.0; 64], vec![0.0; 16], vec![0.0; 72]];
    call(
        jac_robot_f,
        &[X.as_ptr(), U.as_ptr(), p.as_ptr(), core::ptr::null()],
        &mut jac,
    );
    let fx = dense(unsafe { jac_robot_f_sparsity_out(0) }, &jac[0]);
    let seed = [0.1, 0.2, -0.3, 0.4, 0.5, -0.6, 0.7, 0.8];
    let mut fwd = vec![vec![0.0; 8]];
    let null = core::ptr::null();
    assert_eq!(
        call(
            fwd1_robot_f,
            &[
                X.as_ptr(),
                U.as_ptr(),
                p.as_ptr(),
                null,
                seed.as_ptr(),
                null,
                null
            ],
            &mut fwd
        ),
        0
    );
    let mut adj = vec![vec![0.0; 8], vec![0.0; 2], vec![0.0; 9]];
    assert_eq!(
        call(
            adj1_robot_f,
            &[X.as_ptr(), U.as_ptr(), p.as_ptr(), null, seed.as_ptr()],
            &mut adj
        ),
        0
    );
    for r in 0..8 {
        let expected: f64 = (0..8).map(|c| fx[r][c] * seed[c]).sum();
        assert!((fwd[0][r] - expected).abs() < 1e-13, "fwd {r}");
        let expected: f64 = (0..8).map(|k| fx[k][r] * seed[k]).sum();
        assert!((adj[0][r] - expected).abs() < 1e-13, "adj {r}");
    }
}

/// With the feature `compiled`, `f`, `fwd1_f` (with no direction in p, or one of zeros),
/// `adj1_f`, `jac_f` and `jac_adj1_f` called with x, u and p given take a path of their own;
/// a null block (zeros, by CasADi's convention) takes the general one. Both must give the same bits, and the
/// refusals must be the general path's.
#[test]
fn the_common_calls_path_and_the_general_one_agree() {
    let p = parameters();
    let null = core::ptr::null();
    let zeros_u = [0.0; 2];
    let zeros_p = [0.0; 9];
    let seed = [0.1, 0.2, -0.3, 0.4, 0.5, -0.6, 0.7, 0.8];
    let seed_u = [-0.4, 0.9];
    let mut fast = vec![vec![0.0; 8]];
    let mut general = vec![vec![0.0; 8]];
    // u = 0: given (the common path) or null (the general path).
    assert_eq!(
        call(
            robot_f,
            &[X.as_ptr(), zeros_u.as_ptr(), p.as_ptr()],
            &mut fast
        ),
        0
    );
    assert_eq!(
        call(robot_f, &[X.as_ptr(), null, p.as_ptr()], &mut general),
        0
    );
    assert_eq!(fast, general);
    assert_eq!(fast[0], rhs(&p, &X, &[0.0; 2]));
    let args = |u: *const f64, dp: *const f64| {
        [
            X.as_ptr(),
            u,
            p.as_ptr(),
            null,
            seed.as_ptr(),
            seed_u.as_ptr(),
            dp,
        ]
    };
    for dp in [null, zeros_p.as_ptr()] {
        assert_eq!(
            call(fwd1_robot_f, &args(zeros_u.as_ptr(), dp), &mut fast),
            0
        );
        assert_eq!(call(fwd1_robot_f, &args(null, dp), &mut general), 0);
        assert_eq!(fast, general);
    }
    // The second derivatives likewise, every block wanted.
    let blocks = unsafe { jac_adj1_robot_f_n_out() } as usize;
    let mut fast = vec![vec![0.0; 96]; blocks];
    let mut general = vec![vec![1.0; 96]; blocks];
    let weights = [0.3, -0.1, 0.7, 0.2, -0.5, 1.1, 0.4, -0.9];
    let second = |u: *const f64| [X.as_ptr(), u, p.as_ptr(), null, weights.as_ptr()];
    assert_eq!(
        call(jac_adj1_robot_f, &second(zeros_u.as_ptr()), &mut fast),
        0
    );
    assert_eq!(call(jac_adj1_robot_f, &second(null), &mut general), 0);
    for k in 0..blocks {
        let pattern = unsafe { jac_adj1_robot_f_sparsity_out(k as CasadiInt) };
        // Compressed columns: nrow, ncol, the column starts; the last start is nnz.
        let nnz = unsafe { *pattern.add(2 + *pattern.add(1) as usize) } as usize;
        assert_eq!(fast[k][..nnz], general[k][..nnz], "block {k}");
    }
    // The Jacobian likewise, every block.
    let mut fast = vec![vec![0.0; 64], vec![0.0; 16], vec![0.0; 72]];
    let mut general = vec![vec![1.0; 64], vec![1.0; 16], vec![1.0; 72]];
    let point = |u: *const f64| [X.as_ptr(), u, p.as_ptr(), null];
    assert_eq!(call(jac_robot_f, &point(zeros_u.as_ptr()), &mut fast), 0);
    assert_eq!(call(jac_robot_f, &point(null), &mut general), 0);
    for k in 0..3 {
        let pattern = unsafe { jac_robot_f_sparsity_out(k as CasadiInt) };
        let nnz = unsafe { *pattern.add(2 + *pattern.add(1) as usize) } as usize;
        assert_eq!(fast[k][..nnz], general[k][..nnz], "block {k}");
    }
    // The adjoint likewise, by x, u and p.
    let mut fast = vec![vec![0.0; 8], vec![0.0; 2], vec![0.0; 9]];
    let mut general = vec![vec![1.0; 8], vec![1.0; 2], vec![1.0; 9]];
    assert_eq!(call(adj1_robot_f, &second(zeros_u.as_ptr()), &mut fast), 0);
    assert_eq!(call(adj1_robot_f, &second(null), &mut general), 0);
    assert_eq!(fast, general);
    let mut fast = vec![vec![0.0; 8]];
    let mut general = vec![vec![0.0; 8]];
    // A direction in p: the general path, the derivative along it added.
    let mut dp = zeros_p;
    dp[0] = 1.0;
    assert_eq!(
        call(
            fwd1_robot_f,
            &args(zeros_u.as_ptr(), dp.as_ptr()),
            &mut general
        ),
        0
    );
    assert_ne!(fast, general);
    // A direction that is not finite is refused and named, on either path.
    let bad = [0.1, f64::INFINITY, -0.3, 0.4, 0.5, -0.6, 0.7, 0.8];
    let bad_args = [
        X.as_ptr(),
        U.as_ptr(),
        p.as_ptr(),
        null,
        bad.as_ptr(),
        null,
        null,
    ];
    assert_eq!(call(fwd1_robot_f, &bad_args, &mut fast), 3);
    assert_eq!(
        last_error(),
        "fwd1_robot_f: fwd_x[1] = inf is not a finite number"
    );
    // A state that is not finite: refused by name in `fwd1_f` as in `f`.
    let mut x = X;
    x[0] = f64::NAN;
    let nan_args = [
        x.as_ptr(),
        U.as_ptr(),
        p.as_ptr(),
        null,
        seed.as_ptr(),
        null,
        null,
    ];
    assert_eq!(call(fwd1_robot_f, &nan_args, &mut fast), 3);
    assert_eq!(
        last_error(),
        "fwd1_robot_f: x[0] (x) = NaN is not a finite number"
    );
    // After a refusal, a success clears the message.
    assert_eq!(call(fwd1_robot_f, &args(U.as_ptr(), null), &mut fast), 0);
    assert_eq!(last_error(), "");
}

/// `n` directions in x, u and p (CasADi's stacked columns), each different; `p_scale` scales
/// those in p (0: a direction of zeros, as CasADi gives where the parameters are fixed).
fn directions(n: usize, p_scale: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let entry = |d: usize, i: usize| ((7 * d + 3 * i) % 11) as f64 / 5.0 - 1.0;
    let dx = (0..8 * n).map(|k| entry(k / 8, k % 8)).collect();
    let du = (0..2 * n).map(|k| entry(k / 2, 8 + k % 2)).collect();
    let dp = (0..9 * n)
        .map(|k| p_scale * entry(k / 9, 10 + k % 9))
        .collect();
    (dx, du, dp)
}

/// `fwd2_f`, `fwd4_f` and `fwd8_f`: each column the derivative `fwd1_f` gives along that
/// column's direction, on the common calls' path (x, u, p given, none of the directions in
/// p) and on the general one (u null; or a direction in p); a direction that is not finite
/// is refused and named as in `fwd1_f`. With the feature `compiled` the columns are the
/// compiled Jacobian's products with the directions, `fwd1_f` the compiled forward code
/// (exact derivatives by different operations: within 1e-12 of the largest term, as in
/// tests/compiled.rs); without it, both are the same dual-number pass per direction (bit for
/// bit).
#[test]
fn several_forward_directions_are_as_many_calls_of_fwd1() {
    let p = parameters();
    let null = core::ptr::null();
    let bits = !cfg!(feature = "compiled");
    let cases: [(Eval, usize); 3] = [(fwd2_robot_f, 2), (fwd4_robot_f, 4), (fwd8_robot_f, 8)];
    for (fwd_n, n) in cases {
        for (u, p_scale) in [(U.as_ptr(), 0.0), (null, 0.0), (U.as_ptr(), 1.0)] {
            let (dx, du, dp) = directions(n, p_scale);
            let mut all = vec![vec![f64::NAN; 8 * n]];
            let args = [
                X.as_ptr(),
                u,
                p.as_ptr(),
                null,
                dx.as_ptr(),
                du.as_ptr(),
                dp.as_ptr(),
            ];
            assert_eq!(call(fwd_n, &args, &mut all), 0, "{}", last_error());
            let mut jac = vec![vec![0.0; 64], vec![0.0; 16], vec![0.0; 72]];
            let point = [X.as_ptr(), u, p.as_ptr(), null];
            assert_eq!(call(jac_robot_f, &point, &mut jac), 0);
            let dense_jacobian: Vec<Vec<Vec<f64>>> = (0..3)
                .map(|k| dense(unsafe { jac_robot_f_sparsity_out(k) }, &jac[k as usize]))
                .collect();
            for d in 0..n {
                let (sx, su, sp) = (&dx[8 * d..][..8], &du[2 * d..][..2], &dp[9 * d..][..9]);
                let mut one = vec![vec![f64::NAN; 8]];
                let args = [
                    X.as_ptr(),
                    u,
                    p.as_ptr(),
                    null,
                    sx.as_ptr(),
                    su.as_ptr(),
                    sp.as_ptr(),
                ];
                assert_eq!(call(fwd1_robot_f, &args, &mut one), 0);
                // The largest term of the product of the Jacobian with the direction, by row.
                let mut scale = [0.0f64; 8];
                for (m, s) in dense_jacobian.iter().zip([sx, su, sp]) {
                    for r in 0..8 {
                        for c in 0..s.len() {
                            scale[r] = scale[r].max((m[r][c] * s[c]).abs());
                        }
                    }
                }
                for r in 0..8 {
                    let (a, b) = (all[0][8 * d + r], one[0][r]);
                    if bits {
                        assert_eq!(a.to_bits(), b.to_bits(), "fwd{n} direction {d} row {r}");
                    } else {
                        assert!(
                            (a - b).abs() <= 1e-12 * scale[r],
                            "fwd{n} direction {d} row {r}: {a} vs {b}"
                        );
                    }
                }
            }
        }
    }
    // The ports: as CasADi's `forward(8)`, a column per direction.
    let fwd_x = unsafe { core::slice::from_raw_parts(fwd8_robot_f_sparsity_in(4), 2) };
    assert_eq!(fwd_x, [8, 8]);
    // A direction that is not finite: refused, named by its place in the stacked columns.
    let (mut dx, du, dp) = directions(4, 0.0);
    dx[8 * 2 + 5] = f64::INFINITY;
    let mut out = vec![vec![0.0; 32]];
    let args = [
        X.as_ptr(),
        U.as_ptr(),
        p.as_ptr(),
        null,
        dx.as_ptr(),
        du.as_ptr(),
        dp.as_ptr(),
    ];
    assert_eq!(call(fwd4_robot_f, &args, &mut out), 3);
    assert_eq!(
        last_error(),
        "fwd4_robot_f: fwd_x[21] = inf is not a finite number"
    );
    let mut x = X;
    x[1] = f64::NAN;
    let (dx, ..) = directions(4, 0.0);
    let args = [
        x.as_ptr(),
        U.as_ptr(),
        p.as_ptr(),
        null,
        dx.as_ptr(),
        du.as_ptr(),
        dp.as_ptr(),
    ];
    assert_eq!(call(fwd4_robot_f, &args, &mut out), 3);
    assert_eq!(
        last_error(),
        "fwd4_robot_f: x[1] (y) = NaN is not a finite number"
    );
    refuses_null_arrays(fwd8_robot_f);
}

#[test]
fn second_derivatives_are_the_adjoints_central_differences() {
    let p = parameters();
    let weights = [0.3, -0.1, 0.7, 0.2, -0.5, 1.1, 0.4, -0.9];
    let null = core::ptr::null();
    let n_out = unsafe { jac_adj1_robot_f_n_out() } as usize;
    assert_eq!(n_out, 15);
    let mut out: Vec<Vec<f64>> = (0..n_out).map(|_| vec![0.0; 400]).collect();
    let args = [
        X.as_ptr(),
        U.as_ptr(),
        p.as_ptr(),
        null,
        weights.as_ptr(),
        null,
        null,
        null,
    ];
    assert_eq!(call(jac_adj1_robot_f, &args, &mut out), 0);
    let hxx = dense(unsafe { jac_adj1_robot_f_sparsity_out(0) }, &out[0]);
    let hxu = dense(unsafe { jac_adj1_robot_f_sparsity_out(1) }, &out[1]);
    let adjoint = |x: &[f64; 8], u: &[f64; 2]| {
        let mut adj = vec![vec![0.0; 8], vec![0.0; 2], vec![0.0; 9]];
        call(
            adj1_robot_f,
            &[x.as_ptr(), u.as_ptr(), p.as_ptr(), null, weights.as_ptr()],
            &mut adj,
        );
        adj
    };
    for c in 0..10 {
        let h = 1e-6;
        let (mut xu, mut xd, mut uu, mut ud) = (X, X, U, U);
        if c < 8 {
            xu[c] += h;
            xd[c] -= h;
        } else {
            uu[c - 8] += h;
            ud[c - 8] -= h;
        }
        let (up, down) = (adjoint(&xu, &uu), adjoint(&xd, &ud));
        for r in 0..8 {
            let difference = (up[0][r] - down[0][r]) / (2.0 * h);
            let exact = if c < 8 { hxx[r][c] } else { hxu[r][c - 8] };
            assert!(
                (exact - difference).abs() <= 1e-6 * (1.0 + difference.abs()),
                "H {r} {c}: {exact} vs {difference}"
            );
        }
    }
    // Symmetric, and symmetric blocks agree.
    for r in 0..8 {
        for c in 0..8 {
            assert_eq!(hxx[r][c], hxx[c][r]);
        }
    }
}

#[test]
fn bad_arguments_are_refused_with_a_status_and_a_message() {
    let p = parameters();
    let mut out = vec![vec![0.0; 8]];
    let mut x = X;
    x[2] = f64::NAN;
    assert_eq!(
        call(robot_f, &[x.as_ptr(), U.as_ptr(), p.as_ptr()], &mut out),
        3
    );
    assert_eq!(
        last_error(),
        "robot_f: x[2] (alpha) = NaN is not a finite number"
    );
    refuses_null_arrays(robot_f);
    let mut xdot = [0.0; 8];
    let status = unsafe {
        robot_rhs(
            0.0,
            X.as_ptr(),
            7,
            U.as_ptr(),
            2,
            p.as_ptr(),
            9,
            xdot.as_mut_ptr(),
            8,
        )
    };
    assert_eq!(status, 2);
    assert_eq!(
        last_error(),
        "robot_rhs: `x` has 7 entries; the model's has 8"
    );
    let status = unsafe {
        robot_rhs(
            0.0,
            X.as_ptr(),
            8,
            core::ptr::null(),
            2,
            p.as_ptr(),
            9,
            xdot.as_mut_ptr(),
            8,
        )
    };
    assert_eq!(status, 1);
    assert!(unsafe { robot_f_name_in(7) }.is_null());
    assert!(last_error().contains("out of range"), "{}", last_error());
    let name = unsafe { CStr::from_ptr(robot_f_name_in(2)) };
    assert_eq!(name.to_str().unwrap(), "p");
}

/// `f`, `fwd1_f` and `adj1_f` at a finite point are taken by a fast path (with compiled
/// code) that checks the point and the weights by their sums and leaves every call it does
/// not take to the general one. Whatever path takes them: a value that is not finite in x,
/// u, p or an adjoint's weights is refused, named; finite values whose sum overflows are
/// computed (the same bits as the model's right-hand side); a singularity is refused, the
/// state named.
#[test]
fn what_the_fast_calls_leave_is_refused_or_computed_as_by_the_general_path() {
    let p = parameters();
    let weights = [0.3, -0.1, 0.7, 0.2, -0.5, 1.1, 0.4, -0.9];
    let adjoint = |x: &[f64; 8], u: &[f64; 2], p: &[f64], w: &[f64; 8]| {
        let mut out = vec![vec![0.0; 8], vec![0.0; 2], vec![0.0; 9]];
        let null = core::ptr::null();
        let args = [x.as_ptr(), u.as_ptr(), p.as_ptr(), null, w.as_ptr()];
        (call(adj1_robot_f, &args, &mut out), last_error())
    };
    let value = |f: Eval, x: &[f64; 8], u: &[f64; 2], p: &[f64]| {
        let mut out = vec![vec![0.0; 8]];
        let seed = [0.5; 8];
        let args = [
            x.as_ptr(),
            u.as_ptr(),
            p.as_ptr(),
            core::ptr::null(),
            seed.as_ptr(),
        ];
        (call(f, &args, &mut out), last_error(), out.remove(0))
    };
    let refusal = |(status, message, _): (c_int, String, Vec<f64>)| (status, message);
    let (inputs, names) = (MobileRobot::INPUTS, MobileRobot::NAMES);
    let mut u = U;
    u[1] = f64::INFINITY;
    let expected = format!("robot_f: u[1] ({}) = inf is not a finite number", inputs[1]);
    assert_eq!(refusal(value(robot_f, &X, &u, &p)), (3, expected));
    let mut q = p.clone();
    q[8] = f64::NEG_INFINITY;
    let expected = format!("robot_f: p[8] ({}) = -inf is not a finite number", names[8]);
    assert_eq!(refusal(value(robot_f, &X, &U, &q)), (3, expected));
    let mut x = X;
    x[7] = f64::NAN;
    let (status, message, _) = value(fwd1_robot_f, &x, &U, &p);
    assert_eq!(
        (status, message.as_str()),
        (3, "fwd1_robot_f: x[7] (w5) = NaN is not a finite number")
    );
    q = p.clone();
    q[0] = f64::NAN;
    let expected = format!(
        "adj1_robot_f: p[0] ({}) = NaN is not a finite number",
        names[0]
    );
    assert_eq!(adjoint(&X, &U, &q, &weights), (3, expected));
    let mut w = weights;
    w[3] = -f64::INFINITY;
    assert_eq!(
        adjoint(&X, &U, &p, &w),
        (
            3,
            "adj1_robot_f: adj_xdot[3] = -inf is not a finite number".to_string()
        )
    );
    // The position does not enter ẋ: at the largest finite coordinates the sum of the point
    // overflows, and the call is computed all the same.
    x = X;
    x[0] = f64::MAX;
    x[1] = f64::MAX;
    let (status, _, xdot) = value(robot_f, &x, &U, &p);
    assert_eq!(status, 0);
    let bits = |v: &[f64]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&xdot), bits(&rhs(&p, &x, &U)));
    assert_eq!(adjoint(&x, &U, &p, &weights).0, 0);
    // No mass: the reduced mass matrix is singular.
    let massless = vec![0.0; 9];
    for (status, message) in [
        refusal(value(robot_f, &X, &U, &massless)),
        adjoint(&X, &U, &massless, &weights),
    ] {
        assert_eq!(status, 4, "{message}");
        assert!(message.contains("alpha = 0.25"), "{message}");
    }
}

/// Threads calling at once, each with its own parameters and a set they share (the
/// parameters' prepared values are kept for the first set any thread gives, shared, and
/// per thread for the last): each call's values are the model's for its parameters.
#[test]
fn threads_calling_at_once_get_the_values_of_their_own_parameters() {
    let base = parameters();
    let sets: Vec<Vec<f64>> = (0..4)
        .map(|k| base.iter().map(|v| v * (1.0 + 0.1 * k as f64)).collect())
        .collect();
    let bits = |v: &[f64]| v.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let expected: Vec<Vec<u64>> = sets.iter().map(|p| bits(&rhs(p, &X, &U))).collect();
    std::thread::scope(|scope| {
        for own in 0..sets.len() {
            let (sets, expected) = (&sets, &expected);
            scope.spawn(move || {
                for round in 0..500 {
                    let k = if round % 3 == 0 { 0 } else { own };
                    let mut out = vec![vec![0.0; 8]];
                    let args = [X.as_ptr(), U.as_ptr(), sets[k].as_ptr()];
                    assert_eq!(call(robot_f, &args, &mut out), 0);
                    assert_eq!(bits(&out[0]), expected[k], "thread {own}, set {k}");
                }
            });
        }
    });
}
