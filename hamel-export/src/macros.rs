//! The macros a crate exports a model with:
//!
//! ```ignore
//! hamel_export::model!(Robot => hamel::models::MobileRobot);
//! hamel_export::c_api!(Robot, "mobile_robot");   // mobile_robot_rhs, _last_error, …
//! hamel_export::casadi!(Robot, "mobile_robot");  // mobile_robot_f, jac_mobile_robot_f, …
//! ```
//!
//! in a crate of type `cdylib`; its header is [`crate::header::header`]`::<Robot>("mobile_robot")`.

/// `model!(Marker => path::to::Model)`: a marker type `Marker` of the calling crate that
/// implements [`crate::Model`] for the model, from the items `#[hamel_system]` generates
/// (`__hamel_rhs_parametric`, `__hamel_outputs_parametric` and their dependency tables; with
/// the feature `compiled`, the exported functions' derivative code, `__hamel_export_*`).
#[macro_export]
macro_rules! model {
    ($marker:ident => $system:ty) => {
        /// The model as `hamel_export` exports it.
        pub struct $marker;

        impl $marker {
            const NX: usize = <$system as $crate::__private::HamelSystem>::STATE.len();
            const NU: usize = <$system as $crate::__private::HamelSystem>::INPUTS.len();
            const NP: usize = <$system as $crate::__private::Parameters>::NAMES.len();
            const NY: usize = <$system>::__HAMEL_OUTPUT_NAMES.len();
            const Z: usize = <$marker>::NX + <$marker>::NU + <$marker>::NP + 1;
            /// How many parameters the generated code reads.
            const NPL: usize = <$system>::__HAMEL_PARAMETRIC_NAMES.len();
            /// The parameters the generated code reads, as positions in `Parameters::NAMES`.
            /// A name that `Parameters::NAMES` lacks is a compile error here, at `model!`,
            /// that names it.
            const READ: [usize; <$system>::__HAMEL_PARAMETRIC_NAMES.len()] =
                match $crate::__private::positions(
                    <$system as $crate::__private::Parameters>::NAMES,
                    <$system>::__HAMEL_PARAMETRIC_NAMES,
                ) {
                    ::core::result::Result::Ok(read) => read,
                    ::core::result::Result::Err(name) => ::core::panic!(
                        "{}",
                        $crate::__private::unlisted_parameter(name).as_str()
                    ),
                };
            /// The length of the arrays: z, and every function's output.
            const LEN: usize = $crate::__private::max(
                <$marker>::Z,
                $crate::__private::max(<$marker>::NY, $crate::__lie_len!($system)),
            );

            /// x, u, the parameters the generated code reads, and t, from z.
            #[inline(always)]
            fn split<S: ::core::marker::Copy>(
                z: &[S; <$marker>::LEN],
            ) -> (
                [S; <$marker>::NX],
                [S; <$marker>::NU],
                [S; <$system>::__HAMEL_PARAMETRIC_NAMES.len()],
                S,
            ) {
                let x = ::core::array::from_fn(|i| z[i]);
                let u = ::core::array::from_fn(|i| z[<$marker>::NX + i]);
                let p = ::core::array::from_fn(|i| {
                    z[<$marker>::NX + <$marker>::NU + <$marker>::READ[i]]
                });
                (x, u, p, z[<$marker>::Z - 1])
            }
        }

        $crate::__model_layout!($marker => $system);

        impl $marker {
            /// x and u from z as they are (no copies), the parameters the generated code
            /// reads, and t: the compiled code's arguments (used with the feature `compiled`).
            #[allow(dead_code)]
            #[inline(always)]
            fn split_f64(
                z: &[f64; <$marker>::LEN],
            ) -> (
                &[f64; <$marker>::NX],
                &[f64; <$marker>::NU],
                [f64; <$system>::__HAMEL_PARAMETRIC_NAMES.len()],
                f64,
            ) {
                // The lengths are constants within z's (`LEN` is at least z's): never the
                // zeros.
                let x = z.first_chunk().unwrap_or(&[0.0; <$marker>::NX]);
                let u = z[<$marker>::NX..]
                    .first_chunk()
                    .unwrap_or(&[0.0; <$marker>::NU]);
                let p = ::core::array::from_fn(|i| {
                    z[<$marker>::NX + <$marker>::NU + <$marker>::READ[i]]
                });
                (x, u, p, z[<$marker>::Z - 1])
            }
        }

        impl $crate::Model for $marker {
            type System = $system;
            type Array<S: ::core::marker::Copy> = [S; <$marker>::LEN];

            const TIME_DEPENDENT: bool = <$system>::__HAMEL_RHS_TIME;
            const RHS_COLUMNS: &'static [&'static [usize]] = <$system>::__HAMEL_RHS_COLUMNS;
            const RHS_PARAMETERS: &'static [&'static [&'static str]] =
                <$system>::__HAMEL_RHS_PARAMETERS;
            const OUTPUTS: &'static [&'static str] = <$system>::__HAMEL_OUTPUT_NAMES;
            const OUTPUT_COLUMNS: &'static [&'static [usize]] = <$system>::__HAMEL_OUTPUT_COLUMNS;
            const OUTPUT_PARAMETERS: &'static [&'static [&'static str]] =
                <$system>::__HAMEL_OUTPUT_PARAMETERS;
            const READ: &'static [usize] = &<$marker>::READ;
            const READS_ALL: bool = $crate::__private::reads_all(
                &<$marker>::READ,
                <$system as $crate::__private::Parameters>::NAMES.len(),
            );

            // Always inlined: `fwd8_f` fills two arrays of 8-value rows a call, which a call
            // of this function fills value by value and, inlined, a `memset` does.
            #[inline(always)]
            fn array<S: ::core::marker::Copy>(fill: S) -> [S; <$marker>::LEN] {
                [fill; <$marker>::LEN]
            }

            #[inline(always)]
            unsafe fn assume_init_ref(
                a: &[::core::mem::MaybeUninit<f64>; <$marker>::LEN],
            ) -> &[f64; <$marker>::LEN] {
                // SAFETY: every value is initialized (the caller's contract), and an array
                // of `MaybeUninit<f64>` has the layout of one of `f64`.
                unsafe { &*::core::ptr::from_ref(a).cast::<[f64; <$marker>::LEN]>() }
            }

            #[inline]
            fn rhs<S: $crate::__private::Scalar>(
                z: &[S; <$marker>::LEN],
                dx: &mut [S; <$marker>::LEN],
            ) -> ::core::result::Result<(), $crate::__private::Singularity> {
                let (x, u, p, t) = <$marker>::split(z);
                let mut out = [S::from_f64(0.0); <$marker>::NX];
                <$system>::__hamel_rhs_parametric(&p, t, &x, &u, &mut out)?;
                dx[..<$marker>::NX].copy_from_slice(&out);
                ::core::result::Result::Ok(())
            }

            #[inline]
            fn outputs<S: $crate::__private::Scalar>(
                z: &[S; <$marker>::LEN],
                y: &mut [S; <$marker>::LEN],
            ) {
                let (x, _, p, t) = <$marker>::split(z);
                let out = <$system>::__hamel_outputs_parametric(&p, t, &x);
                y[..<$marker>::NY].copy_from_slice(&out);
            }

            $crate::__model_compiled!($marker => $system);
        }
    };
}

/// The length of the Lie derivatives' output (zero without compiled code).
#[cfg(feature = "compiled")]
#[doc(hidden)]
#[macro_export]
macro_rules! __lie_len {
    ($system:ty) => {
        <$system>::__HAMEL_EXPORT_LIE_DEPENDS.len()
    };
}

#[cfg(not(feature = "compiled"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __lie_len {
    ($system:ty) => {
        0
    };
}
/// One family's compiled function of `$system`, chosen by the constant `W`: the right-hand
/// side's, the outputs' or the Lie derivatives' (the three take the same arguments).
#[doc(hidden)]
#[macro_export]
macro_rules! __by_family {
    ($w:expr, $system:ty, [$rhs:ident, $outputs:ident, $lie:ident], ($($arg:expr),* $(,)?)) => {
        match $w {
            $crate::units::RHS => <$system>::$rhs::<()>($($arg),*),
            $crate::units::OUTPUTS => <$system>::$outputs::<()>($($arg),*),
            _ => <$system>::$lie::<()>($($arg),*),
        }
    };
}

/// The compiled functions of [`crate::Model`], without the feature `compiled`: none (every
/// derivative by dual numbers, no Lie derivatives).
#[cfg(not(feature = "compiled"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __model_compiled {
    ($marker:ident => $system:ty) => {
        type Prepared = ();
        type Scratch = [::core::mem::MaybeUninit<f64>; 0];
        const LIE: usize = 0;
        const COMPILED: bool = false;

        #[inline(always)]
        fn scratch() -> [::core::mem::MaybeUninit<f64>; 0] {
            []
        }

        fn lie<S: $crate::__private::Scalar>(
            _z: &[S; <$marker>::LEN],
            _out: &mut [S; <$marker>::LEN],
        ) -> ::core::result::Result<(), $crate::__private::Singularity> {
            ::core::result::Result::Ok(())
        }

        fn tables(_which: $crate::Which) -> ::core::option::Option<$crate::model::Tables> {
            ::core::option::Option::None
        }

        #[inline]
        fn with_prepared<R>(_p: &[f64], then: impl FnOnce(&()) -> R) -> R {
            then(&())
        }

        fn compiled_value(
            _which: $crate::Which,
            _prepared: &(),
            _z: &[f64; <$marker>::LEN],
            _out: &mut [f64],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            ::core::option::Option::None
        }

        unsafe fn compiled_jacobian(
            _which: $crate::Which,
            _prepared: &(),
            _z: &[f64; <$marker>::LEN],
            _parameters: bool,
            _to: &$crate::layout::Destinations,
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            ::core::option::Option::None
        }

        fn compiled_forward(
            _which: $crate::Which,
            _prepared: &(),
            _z: &[f64; <$marker>::LEN],
            _direction: &[f64],
            _parameters: bool,
            _out: &mut [f64],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            ::core::option::Option::None
        }

        fn compiled_adjoint(
            _which: $crate::Which,
            _prepared: &(),
            _z: &[f64; <$marker>::LEN],
            _weights: &[f64],
            _parameters: bool,
            _out: &mut [::core::mem::MaybeUninit<f64>; <$marker>::LEN],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            ::core::option::Option::None
        }

        unsafe fn compiled_second(
            _which: $crate::Which,
            _prepared: &(),
            _z: &[f64; <$marker>::LEN],
            _weights: &[f64],
            _parameters: bool,
            _to: &$crate::layout::Destinations,
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            ::core::option::Option::None
        }
    };
}

/// The compiled functions of [`crate::Model`], from the items `#[hamel_system]` emits with
/// the feature `compiled`: each function of the three families (`rhs`, `outputs`, `lie`)
/// called with its own stack arrays.
#[cfg(feature = "compiled")]
#[doc(hidden)]
#[macro_export]
macro_rules! __model_compiled {
    ($marker:ident => $system:ty) => {
        type Prepared = [f64; <$system>::__HAMEL_EXPORT_PREPARED];
        type Scratch = [::core::mem::MaybeUninit<f64>; <$marker>::SCRATCH];
        const LIE: usize = <$system>::__HAMEL_EXPORT_LIE_DEPENDS.len();
        const COMPILED: bool = true;

        #[inline(always)]
        fn scratch() -> [::core::mem::MaybeUninit<f64>; <$marker>::SCRATCH] {
            [::core::mem::MaybeUninit::uninit(); <$marker>::SCRATCH]
        }

        #[inline]
        fn lie<S: $crate::__private::Scalar>(
            z: &[S; <$marker>::LEN],
            out: &mut [S; <$marker>::LEN],
        ) -> ::core::result::Result<(), $crate::__private::Singularity> {
            let (x, u, p, t) = <$marker>::split(z);
            let mut values = [S::from_f64(0.0); <$system>::__HAMEL_EXPORT_LIE_DEPENDS.len()];
            <$system>::__hamel_export_lie_generic(&p, t, &x, &u, &mut values)?;
            out[..values.len()].copy_from_slice(&values);
            ::core::result::Result::Ok(())
        }

        fn tables(which: $crate::Which) -> ::core::option::Option<$crate::model::Tables> {
            ::core::option::Option::Some(match which {
                $crate::Which::Rhs => $crate::__tables!($marker, $system, RHS),
                $crate::Which::Outputs => $crate::__tables!($marker, $system, OUTPUTS),
                $crate::Which::Lie => $crate::__tables!($marker, $system, LIE),
            })
        }

        // Always inlined: a few instructions (the cache's check; the new set's values are
        // out of line) that every call of every function makes.
        #[inline(always)]
        fn with_prepared<R>(
            p: &[f64],
            then: impl FnOnce(&[f64; <$system>::__HAMEL_EXPORT_PREPARED]) -> R,
        ) -> R {
            type Cache =
                $crate::__private::Cache<{ <$marker>::NP }, { <$system>::__HAMEL_EXPORT_PREPARED }>;
            ::std::thread_local! {
                static CACHE: ::core::cell::RefCell<Cache> =
                    const { ::core::cell::RefCell::new(Cache::EMPTY) };
            }
            // Out of line and cold: inlined, its code (hundreds of instructions) made the
            // cache's check a call with a large stack frame on every call of every function.
            #[cold]
            #[inline(never)]
            fn prepare(p: &[f64; <$marker>::NP]) -> [f64; <$system>::__HAMEL_EXPORT_PREPARED] {
                let read: [f64; <$system>::__HAMEL_PARAMETRIC_NAMES.len()] =
                    ::core::array::from_fn(|i| p[<$marker>::READ[i]]);
                <$system>::__hamel_export_prepare::<()>(&read)
            }
            let Ok(p) = <&[f64; <$marker>::NP]>::try_from(p) else {
                return then(&prepare(&[0.0; <$marker>::NP]));
            };
            // The first parameter set, shared by every thread (see `First`), then this
            // thread's last.
            static FIRST: $crate::__private::First<
                { <$marker>::NP },
                { <$system>::__HAMEL_EXPORT_PREPARED },
            > = $crate::__private::First::new();
            if let ::core::option::Option::Some(prepared) = FIRST.get(p, prepare) {
                return then(prepared);
            }
            // This thread's cache by its address: `LocalKey::with` around the whole call
            // was not inlined (a call with a frame of its own and the result copied, on
            // every call of every function); around the address it is.
            let cache = CACHE.with(|cache| -> *const ::core::cell::RefCell<Cache> { cache });
            // SAFETY: this thread's value, which lives as long as the thread, on which this
            // call runs; shared only as the `RefCell` (whose borrow is checked below).
            let cache = unsafe { &*cache };
            match cache.try_borrow_mut() {
                ::core::result::Result::Ok(mut cache) => then(cache.get(p, prepare)),
                ::core::result::Result::Err(_) => then(&prepare(p)),
            }
        }

        // The compiled code of each family, called by `hamel_export::units` only (see there
        // why): `match W` on the constant keeps one family's code in each instance.
        #[inline]
        fn value_of<const W: u8>(
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            out: &mut [f64],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            let (x, u, p, t) = <$marker>::split_f64(z);
            let p = &p;
            ::core::option::Option::Some($crate::__by_family!(
                W,
                $system,
                [
                    __hamel_export_rhs,
                    __hamel_export_outputs,
                    __hamel_export_lie
                ],
                (prepared, p, t, x, u, $crate::__private::array_mut(out)?,)
            ))
        }

        #[inline]
        unsafe fn jacobian_of<const W: u8>(
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            parameters: bool,
            to: &$crate::layout::Destinations,
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            let (x, u, p, t) = <$marker>::split_f64(z);
            let p = &p;
            // Each entry straight into its output: `k` and the slot are constants once the
            // compiled code is inlined here.
            macro_rules! run {
                ($f:ident, $slots:ident) => {{
                    let put = &mut |k: usize, v: f64| {
                        let (output, slot) = <$marker>::$slots[k];
                        // SAFETY: `to[output]` has room for `slot` (the caller's contract).
                        unsafe { *to[output].add(slot) = v };
                    };
                    ::core::option::Option::Some(<$system>::$f::<(), _>(
                        prepared, p, t, x, u, parameters, put,
                    ))
                }};
            }
            match W {
                $crate::units::RHS => run!(__hamel_export_rhs_jacobian, RHS_JACOBIAN),
                $crate::units::OUTPUTS => {
                    run!(__hamel_export_outputs_jacobian, OUTPUTS_JACOBIAN)
                }
                _ => run!(__hamel_export_lie_jacobian, LIE_JACOBIAN),
            }
        }

        #[inline]
        unsafe fn products_of<const N: usize>(
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            directions: &[::core::mem::MaybeUninit<[f64; N]>; <$marker>::LEN],
            out: &mut [::core::mem::MaybeUninit<[f64; N]>; <$marker>::LEN],
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            let (x, u, p, t) = <$marker>::split_f64(z);
            let p = &p;
            // Each entry times its column's directions, added to its row's: `k`, the row
            // and the column are constants once the compiled code is inlined here.
            let put = &mut |k: usize, v: f64| {
                let (r, c) = <$system>::__HAMEL_EXPORT_RHS_JACOBIAN[k];
                // SAFETY: row `c` of the directions and row `r` of `out` are initialized
                // (the caller's contract).
                unsafe {
                    $crate::casadi::plan::add_scaled(
                        v,
                        directions[c].assume_init_ref(),
                        out[r].assume_init_mut(),
                    )
                };
            };
            ::core::option::Option::Some(<$system>::__hamel_export_rhs_jacobian::<(), _>(
                prepared, p, t, x, u, false, put,
            ))
        }

        #[inline]
        fn forward_of<const W: u8>(
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            direction: &[f64],
            parameters: bool,
            out: &mut [f64],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            let (x, u, p, t) = <$marker>::split_f64(z);
            let p = &p;
            ::core::option::Option::Some($crate::__by_family!(
                W,
                $system,
                [
                    __hamel_export_rhs_forward,
                    __hamel_export_outputs_forward,
                    __hamel_export_lie_forward
                ],
                (
                    prepared,
                    p,
                    t,
                    x,
                    u,
                    $crate::__private::array(direction)?,
                    parameters,
                    $crate::__private::array_mut(out)?,
                )
            ))
        }

        #[inline]
        fn adjoint_of<const W: u8>(
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            weights: &[f64],
            parameters: bool,
            out: &mut [::core::mem::MaybeUninit<f64>; <$marker>::LEN],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            let (x, u, p, t) = <$marker>::split_f64(z);
            let p = &p;
            // `Model::compiled_adjoint`'s promise: the generated code writes every local
            // column of x, u and t, and with `parameters` those of the parameters it reads,
            // as the tables it states beside it say; checked here when the model is
            // exported.
            const {
                use $crate::__private::writes_every_column as every;
                let (states, read) = (<$marker>::NX + <$marker>::NU, <$marker>::NPL);
                assert!(
                    every(<$system>::__HAMEL_EXPORT_RHS_ADJOINT_WRITES, states, read)
                        && every(
                            <$system>::__HAMEL_EXPORT_OUTPUTS_ADJOINT_WRITES,
                            states,
                            read
                        )
                        && every(<$system>::__HAMEL_EXPORT_LIE_ADJOINT_WRITES, states, read),
                    "hamel internal error: the compiled adjoint does not write every column"
                )
            };
            ::core::option::Option::Some($crate::__by_family!(
                W,
                $system,
                [
                    __hamel_export_rhs_adjoint,
                    __hamel_export_outputs_adjoint,
                    __hamel_export_lie_adjoint
                ],
                (
                    prepared,
                    p,
                    t,
                    x,
                    u,
                    $crate::__private::array(weights)?,
                    parameters,
                    out.first_chunk_mut()?,
                )
            ))
        }

        #[inline]
        unsafe fn second_of<const W: u8>(
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            weights: &[f64],
            parameters: bool,
            to: &$crate::layout::Destinations,
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            let (x, u, p, t) = <$marker>::split_f64(z);
            let p = &p;
            // The second derivatives' entries (two places each off the diagonal), then the
            // Jacobian's (its transposed blocks), each straight into its output.
            macro_rules! run {
                ($f:ident, $second:ident, $transposed:ident) => {{
                    let put = &mut |k: usize, v: f64| {
                        if k < <$marker>::$second.len() {
                            let [(o, s), (r, t)] = <$marker>::$second[k];
                            // SAFETY: `to[o]` and `to[r]` have room for `s` and `t` (the
                            // caller's contract).
                            unsafe {
                                *to[o].add(s) = v;
                                *to[r].add(t) = v;
                            }
                        } else {
                            let (o, s) = <$marker>::$transposed[k - <$marker>::$second.len()];
                            // SAFETY: as above.
                            unsafe { *to[o].add(s) = v };
                        }
                    };
                    ::core::option::Option::Some(<$system>::$f::<(), _>(
                        prepared,
                        p,
                        t,
                        x,
                        u,
                        $crate::__private::array(weights)?,
                        parameters,
                        put,
                    ))
                }};
            }
            match W {
                $crate::units::RHS => {
                    run!(__hamel_export_rhs_second, RHS_SECOND, RHS_TRANSPOSED)
                }
                $crate::units::OUTPUTS => run!(
                    __hamel_export_outputs_second,
                    OUTPUTS_SECOND,
                    OUTPUTS_TRANSPOSED
                ),
                _ => run!(__hamel_export_lie_second, LIE_SECOND, LIE_TRANSPOSED),
            }
        }

        #[inline]
        fn compiled_value(
            which: $crate::Which,
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            out: &mut [f64],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            use $crate::units::{LIE, OUTPUTS, RHS, value::call};
            match which {
                $crate::Which::Rhs => call::<Self, RHS>(prepared, z, out),
                $crate::Which::Outputs => call::<Self, OUTPUTS>(prepared, z, out),
                $crate::Which::Lie => call::<Self, LIE>(prepared, z, out),
            }
        }

        #[inline]
        unsafe fn compiled_jacobian(
            which: $crate::Which,
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            parameters: bool,
            to: &$crate::layout::Destinations,
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            use $crate::units::{LIE, OUTPUTS, RHS, jacobian::call};
            // SAFETY: the caller's contract, which is `call`'s.
            unsafe {
                match which {
                    $crate::Which::Rhs => call::<Self, RHS>(prepared, z, parameters, to),
                    $crate::Which::Outputs => call::<Self, OUTPUTS>(prepared, z, parameters, to),
                    $crate::Which::Lie => call::<Self, LIE>(prepared, z, parameters, to),
                }
            }
        }

        #[inline]
        fn compiled_forward(
            which: $crate::Which,
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            direction: &[f64],
            parameters: bool,
            out: &mut [f64],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            use $crate::units::{LIE, OUTPUTS, RHS, forward::call};
            match which {
                $crate::Which::Rhs => call::<Self, RHS>(prepared, z, direction, parameters, out),
                $crate::Which::Outputs => {
                    call::<Self, OUTPUTS>(prepared, z, direction, parameters, out)
                }
                $crate::Which::Lie => call::<Self, LIE>(prepared, z, direction, parameters, out),
            }
        }

        #[inline]
        fn compiled_adjoint(
            which: $crate::Which,
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            weights: &[f64],
            parameters: bool,
            out: &mut [::core::mem::MaybeUninit<f64>; <$marker>::LEN],
        ) -> ::core::option::Option<::core::result::Result<(), $crate::__private::Singularity>> {
            use $crate::units::{LIE, OUTPUTS, RHS, adjoint::call};
            match which {
                $crate::Which::Rhs => call::<Self, RHS>(prepared, z, weights, parameters, out),
                $crate::Which::Outputs => {
                    call::<Self, OUTPUTS>(prepared, z, weights, parameters, out)
                }
                $crate::Which::Lie => call::<Self, LIE>(prepared, z, weights, parameters, out),
            }
        }

        #[inline]
        unsafe fn compiled_second(
            which: $crate::Which,
            prepared: &[f64; <$system>::__HAMEL_EXPORT_PREPARED],
            z: &[f64; <$marker>::LEN],
            weights: &[f64],
            parameters: bool,
            to: &$crate::layout::Destinations,
        ) -> ::core::option::Option<::core::result::Result<bool, $crate::__private::Singularity>> {
            use $crate::units::{LIE, OUTPUTS, RHS, second::call};
            // SAFETY: the caller's contract, which is `call`'s.
            unsafe {
                match which {
                    $crate::Which::Rhs => call::<Self, RHS>(prepared, z, weights, parameters, to),
                    $crate::Which::Outputs => {
                        call::<Self, OUTPUTS>(prepared, z, weights, parameters, to)
                    }
                    $crate::Which::Lie => call::<Self, LIE>(prepared, z, weights, parameters, to),
                }
            }
        }
    };
}

/// A family's [`crate::model::Tables`] from its generated constants.
#[cfg(feature = "compiled")]
#[doc(hidden)]
#[macro_export]
macro_rules! __tables {
    ($marker:ident, $system:ty, RHS) => {
        $crate::__tables!(@ $marker, $system, __HAMEL_EXPORT_RHS_DEPENDS, __HAMEL_EXPORT_RHS_JACOBIAN,
            __HAMEL_EXPORT_RHS_SECOND, __HAMEL_EXPORT_RHS_COMPILED, __HAMEL_EXPORT_RHS_STATES,
            RHS_JACOBIAN, RHS_SECOND, RHS_TRANSPOSED)
    };
    ($marker:ident, $system:ty, OUTPUTS) => {
        $crate::__tables!(@ $marker, $system, __HAMEL_EXPORT_OUTPUTS_DEPENDS,
            __HAMEL_EXPORT_OUTPUTS_JACOBIAN, __HAMEL_EXPORT_OUTPUTS_SECOND,
            __HAMEL_EXPORT_OUTPUTS_COMPILED, __HAMEL_EXPORT_OUTPUTS_STATES,
            OUTPUTS_JACOBIAN, OUTPUTS_SECOND, OUTPUTS_TRANSPOSED)
    };
    ($marker:ident, $system:ty, LIE) => {
        $crate::__tables!(@ $marker, $system, __HAMEL_EXPORT_LIE_DEPENDS, __HAMEL_EXPORT_LIE_JACOBIAN,
            __HAMEL_EXPORT_LIE_SECOND, __HAMEL_EXPORT_LIE_COMPILED, __HAMEL_EXPORT_LIE_STATES,
            LIE_JACOBIAN, LIE_SECOND, LIE_TRANSPOSED)
    };
    (@ $marker:ident, $system:ty, $depends:ident, $jacobian:ident, $second:ident, $compiled:ident,
        $states:ident, $jacobian_slots:ident, $second_slots:ident, $transposed_slots:ident) => {
        $crate::model::Tables {
            outputs: <$system>::$depends.len(),
            jacobian: <$system>::$jacobian,
            second: <$system>::$second,
            compiled: <$system>::$compiled,
            states: <$system>::$states,
            depends: <$system>::$depends,
            layout: $crate::layout::Layout {
                jacobian: &<$marker>::$jacobian_slots,
                second: &<$marker>::$second_slots,
                transposed: &<$marker>::$transposed_slots,
            },
        }
    };
}

/// The places of the compiled code's entries in CasADi's outputs ([`crate::layout`]), as
/// constants of the marker type, with the scratch buffer's length.
#[cfg(feature = "compiled")]
#[doc(hidden)]
#[macro_export]
macro_rules! __model_layout {
    ($marker:ident => $system:ty) => {
        impl $marker {
            /// The compiled code's columns as the right-hand side's blocks (x, u, p, t) and
            /// as those of the outputs and the Lie derivatives (x, p, t).
            const WITH_U: $crate::layout::Columns = $crate::layout::Columns {
                nx: <$marker>::NX,
                nu: <$marker>::NU,
                read: &<$marker>::READ,
                with_u: true,
                time: <$system>::__HAMEL_RHS_TIME,
            };
            const WITHOUT_U: $crate::layout::Columns = $crate::layout::Columns {
                with_u: false,
                ..<$marker>::WITH_U
            };
            $crate::__model_layout!(@ $marker, $system, WITH_U, RHS_JACOBIAN, RHS_SECOND,
                RHS_TRANSPOSED, __HAMEL_EXPORT_RHS_JACOBIAN, __HAMEL_EXPORT_RHS_SECOND);
            $crate::__model_layout!(@ $marker, $system, WITHOUT_U, OUTPUTS_JACOBIAN,
                OUTPUTS_SECOND, OUTPUTS_TRANSPOSED, __HAMEL_EXPORT_OUTPUTS_JACOBIAN,
                __HAMEL_EXPORT_OUTPUTS_SECOND);
            $crate::__model_layout!(@ $marker, $system, WITHOUT_U, LIE_JACOBIAN, LIE_SECOND,
                LIE_TRANSPOSED, __HAMEL_EXPORT_LIE_JACOBIAN, __HAMEL_EXPORT_LIE_SECOND);
            /// The longest output a table can fill: the scratch buffer's length.
            const SCRATCH: usize = $crate::__private::max(
                2 * <$system>::__HAMEL_EXPORT_RHS_SECOND.len()
                    + <$system>::__HAMEL_EXPORT_RHS_JACOBIAN.len(),
                $crate::__private::max(
                    2 * <$system>::__HAMEL_EXPORT_OUTPUTS_SECOND.len()
                        + <$system>::__HAMEL_EXPORT_OUTPUTS_JACOBIAN.len(),
                    2 * <$system>::__HAMEL_EXPORT_LIE_SECOND.len()
                        + <$system>::__HAMEL_EXPORT_LIE_JACOBIAN.len(),
                ),
            ) + 1;
        }
    };
    (@ $marker:ident, $system:ty, $columns:ident, $jacobian:ident, $second:ident,
        $transposed:ident, $jacobian_table:ident, $second_table:ident) => {
        const $jacobian: [$crate::layout::Slot; <$system>::$jacobian_table.len()] =
            $crate::layout::jacobian(<$system>::$jacobian_table, <$marker>::$columns);
        const $second: [[$crate::layout::Slot; 2]; <$system>::$second_table.len()] =
            $crate::layout::second(<$system>::$second_table, <$marker>::$columns);
        const $transposed: [$crate::layout::Slot; <$system>::$jacobian_table.len()] =
            $crate::layout::transposed(<$system>::$jacobian_table, <$marker>::$columns);
    };
}

#[cfg(not(feature = "compiled"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __model_layout {
    ($marker:ident => $system:ty) => {};
}

/// `c_api!(Marker, "name")`: the plain C functions of a model: `name_rhs`, `name_outputs`,
/// `name_default_parameters`, `name_last_error` (see the generated header).
#[macro_export]
macro_rules! c_api {
    ($marker:ty, $name:literal) => {
        const _: () = {
            use $crate::__private::{c_char, c_int};

            /// This thread's last error message (empty after a success).
            #[unsafe(export_name = concat!($name, "_last_error"))]
            pub extern "C" fn last_error() -> *const c_char {
                $crate::abi::last_error()
            }

            /// ẋ = F(t, x, u; p), every length checked.
            #[unsafe(export_name = concat!($name, "_rhs"))]
            pub unsafe extern "C" fn rhs(
                t: f64,
                x: *const f64,
                nx: usize,
                u: *const f64,
                nu: usize,
                p: *const f64,
                np: usize,
                xdot: *mut f64,
                nxdot: usize,
            ) -> c_int {
                $crate::abi::guard(concat!($name, "_rhs"), || unsafe {
                    $crate::c_api::rhs::<$marker>(t, (x, nx), (u, nu), (p, np), (xdot, nxdot))
                })
            }

            /// y = h(t, x; p), every length checked.
            #[unsafe(export_name = concat!($name, "_outputs"))]
            pub unsafe extern "C" fn outputs(
                t: f64,
                x: *const f64,
                nx: usize,
                p: *const f64,
                np: usize,
                y: *mut f64,
                ny: usize,
            ) -> c_int {
                $crate::abi::guard(concat!($name, "_outputs"), || unsafe {
                    $crate::c_api::outputs::<$marker>(t, (x, nx), (p, np), (y, ny))
                })
            }

            /// The model's default parameters, in the order of `p`.
            #[unsafe(export_name = concat!($name, "_default_parameters"))]
            pub unsafe extern "C" fn default_parameters(p: *mut f64, np: usize) -> c_int {
                $crate::abi::guard(concat!($name, "_default_parameters"), || unsafe {
                    $crate::c_api::default_parameters::<$marker>(p, np)
                })
            }
        };
    };
}

/// `casadi!(Marker, "name")`: CasADi's external functions of a model: `name_f` (the
/// right-hand side) and `name_h` (the outputs), each with `jac_`, `fwd1_`, `adj1_`,
/// `jac_adj1_`, `fwd2_`, `fwd4_` and `fwd8_` beside it, and every symbol CasADi looks for (see
/// [`crate::casadi`](mod@crate::casadi)); with the feature `compiled`, `name_lie` too (the
/// outputs' Lie derivatives, empty for a model without `control(..)`).
#[macro_export]
macro_rules! casadi {
    ($marker:ty, $name:literal) => {
        $crate::__casadi_family!($marker, $name, "_f", $crate::Which::Rhs);
        $crate::__casadi_family!($marker, $name, "_h", $crate::Which::Outputs);
        $crate::__casadi_lie!($marker, $name);
    };
}

/// The Lie derivatives' family: only with compiled code, which computes them.
#[cfg(feature = "compiled")]
#[doc(hidden)]
#[macro_export]
macro_rules! __casadi_lie {
    ($marker:ty, $name:literal) => {
        $crate::__casadi_family!($marker, $name, "_lie", $crate::Which::Lie);
    };
}

#[cfg(not(feature = "compiled"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __casadi_lie {
    ($marker:ty, $name:literal) => {};
}

#[doc(hidden)]
#[macro_export]
macro_rules! __casadi_family {
    ($marker:ty, $name:literal, $suffix:literal, $which:expr) => {
        const _: () = {
            static FAMILY: ::std::sync::OnceLock<$crate::casadi::Family> =
                ::std::sync::OnceLock::new();
            fn family() -> &'static $crate::casadi::Family {
                FAMILY.get_or_init(|| $crate::casadi::Family::new::<$marker>($which))
            }
            $crate::__casadi_function!($marker, family, $which, Value, "", $name, $suffix);
            $crate::__casadi_function!($marker, family, $which, Jacobian, "jac_", $name, $suffix);
            $crate::__casadi_function!($marker, family, $which, Forward, "fwd1_", $name, $suffix);
            $crate::__casadi_function!($marker, family, $which, Forward2, "fwd2_", $name, $suffix);
            $crate::__casadi_function!($marker, family, $which, Forward4, "fwd4_", $name, $suffix);
            $crate::__casadi_function!($marker, family, $which, Forward8, "fwd8_", $name, $suffix);
            $crate::__casadi_function!($marker, family, $which, Adjoint, "adj1_", $name, $suffix);
            $crate::__casadi_function!(
                $marker,
                family,
                $which,
                AdjointJacobian,
                "jac_adj1_",
                $name,
                $suffix
            );
        };
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __casadi_function {
    ($marker:ty, $family:ident, $which:expr, $kind:ident, $prefix:literal, $name:literal,
        $suffix:literal) => {
        const _: () = {
            use $crate::__private::{CasadiInt, c_char, c_int};
            use $crate::casadi::{Kind, symbols};

            #[unsafe(export_name = concat!($prefix, $name, $suffix))]
            pub unsafe extern "C" fn eval(
                arg: *const *const f64,
                res: *const *mut f64,
                _iw: *mut CasadiInt,
                _w: *mut f64,
                _mem: c_int,
            ) -> c_int {
                $crate::abi::guard(concat!($prefix, $name, $suffix), || unsafe {
                    $crate::casadi::call::<$marker>($which, $family, Kind::$kind, arg, res)
                })
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_n_in"))]
            pub extern "C" fn n_in() -> CasadiInt {
                symbols::n_in($family(), Kind::$kind)
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_n_out"))]
            pub extern "C" fn n_out() -> CasadiInt {
                symbols::n_out($family(), Kind::$kind)
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_name_in"))]
            pub extern "C" fn name_in(i: CasadiInt) -> *const c_char {
                symbols::name_in($family(), Kind::$kind, i)
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_name_out"))]
            pub extern "C" fn name_out(i: CasadiInt) -> *const c_char {
                symbols::name_out($family(), Kind::$kind, i)
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_sparsity_in"))]
            pub extern "C" fn sparsity_in(i: CasadiInt) -> *const CasadiInt {
                symbols::sparsity_in($family(), Kind::$kind, i)
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_sparsity_out"))]
            pub extern "C" fn sparsity_out(i: CasadiInt) -> *const CasadiInt {
                symbols::sparsity_out($family(), Kind::$kind, i)
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_work"))]
            pub unsafe extern "C" fn work(
                sz_arg: *mut CasadiInt,
                sz_res: *mut CasadiInt,
                sz_iw: *mut CasadiInt,
                sz_w: *mut CasadiInt,
            ) -> c_int {
                unsafe { symbols::work($family(), Kind::$kind, sz_arg, sz_res, sz_iw, sz_w) }
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_default_in"))]
            pub extern "C" fn default_in(i: CasadiInt) -> f64 {
                symbols::default_in(i)
            }

            /// The functions hold no state: reference counting, memory and checkout have
            /// nothing to do, and any thread may call with any `mem`.
            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_incref"))]
            pub extern "C" fn incref() {}

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_decref"))]
            pub extern "C" fn decref() {}

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_checkout"))]
            pub extern "C" fn checkout() -> c_int {
                0
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_release"))]
            pub extern "C" fn release(_mem: c_int) {}

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_alloc_mem"))]
            pub extern "C" fn alloc_mem() -> c_int {
                0
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_init_mem"))]
            pub extern "C" fn init_mem(_mem: c_int) -> c_int {
                0
            }

            #[unsafe(export_name = concat!($prefix, $name, $suffix, "_free_mem"))]
            pub extern "C" fn free_mem(_mem: c_int) {}
        };
    };
}
