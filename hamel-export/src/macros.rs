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
/// (`__hamel_rhs_parametric`, `__hamel_outputs_parametric` and their dependency tables).
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
            /// The parameters the generated code reads, as positions in `Parameters::NAMES`.
            const READ: [usize; <$system>::__HAMEL_PARAMETRIC_NAMES.len()] =
                $crate::__private::positions(
                    <$system as $crate::__private::Parameters>::NAMES,
                    <$system>::__HAMEL_PARAMETRIC_NAMES,
                );
        }

        const _: () = ::core::assert!(<$marker>::NY <= <$marker>::Z);

        impl $crate::Model for $marker {
            type System = $system;
            type Array<S: ::core::marker::Copy> = [S; <$marker>::Z];

            const TIME_DEPENDENT: bool = <$system>::__HAMEL_RHS_TIME;
            const RHS_COLUMNS: &'static [&'static [usize]] = <$system>::__HAMEL_RHS_COLUMNS;
            const RHS_PARAMETERS: &'static [&'static [&'static str]] =
                <$system>::__HAMEL_RHS_PARAMETERS;
            const OUTPUTS: &'static [&'static str] = <$system>::__HAMEL_OUTPUT_NAMES;
            const OUTPUT_COLUMNS: &'static [&'static [usize]] = <$system>::__HAMEL_OUTPUT_COLUMNS;
            const OUTPUT_PARAMETERS: &'static [&'static [&'static str]] =
                <$system>::__HAMEL_OUTPUT_PARAMETERS;

            #[inline]
            fn array<S: ::core::marker::Copy>(fill: S) -> [S; <$marker>::Z] {
                [fill; <$marker>::Z]
            }

            #[inline]
            fn rhs<S: $crate::__private::Scalar>(
                z: &[S; <$marker>::Z],
                dx: &mut [S; <$marker>::Z],
            ) -> ::core::result::Result<(), $crate::__private::Singularity> {
                let x: [S; <$marker>::NX] = ::core::array::from_fn(|i| z[i]);
                let u: [S; <$marker>::NU] = ::core::array::from_fn(|i| z[<$marker>::NX + i]);
                let p: [S; <$system>::__HAMEL_PARAMETRIC_NAMES.len()] =
                    ::core::array::from_fn(|i| {
                        z[<$marker>::NX + <$marker>::NU + <$marker>::READ[i]]
                    });
                let t = z[<$marker>::Z - 1];
                let mut out = [S::from_f64(0.0); <$marker>::NX];
                <$system>::__hamel_rhs_parametric(&p, t, &x, &u, &mut out)?;
                dx[..<$marker>::NX].copy_from_slice(&out);
                ::core::result::Result::Ok(())
            }

            #[inline]
            fn outputs<S: $crate::__private::Scalar>(
                z: &[S; <$marker>::Z],
                y: &mut [S; <$marker>::Z],
            ) {
                let x: [S; <$marker>::NX] = ::core::array::from_fn(|i| z[i]);
                let p: [S; <$system>::__HAMEL_PARAMETRIC_NAMES.len()] =
                    ::core::array::from_fn(|i| {
                        z[<$marker>::NX + <$marker>::NU + <$marker>::READ[i]]
                    });
                let t = z[<$marker>::Z - 1];
                let out = <$system>::__hamel_outputs_parametric(&p, t, &x);
                y[..<$marker>::NY].copy_from_slice(&out);
            }
        }
    };
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
/// right-hand side) and `name_h` (the outputs), each with `jac_`, `fwd1_`, `adj1_` and
/// `jac_adj1_` beside it, and every symbol CasADi looks for (see [`crate::casadi`]).
#[macro_export]
macro_rules! casadi {
    ($marker:ty, $name:literal) => {
        $crate::__casadi_family!($marker, $name, "_f", $crate::Which::Rhs);
        $crate::__casadi_family!($marker, $name, "_h", $crate::Which::Outputs);
    };
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
            $crate::__casadi_function!($marker, family, Value, "", $name, $suffix);
            $crate::__casadi_function!($marker, family, Jacobian, "jac_", $name, $suffix);
            $crate::__casadi_function!($marker, family, Forward, "fwd1_", $name, $suffix);
            $crate::__casadi_function!($marker, family, Adjoint, "adj1_", $name, $suffix);
            $crate::__casadi_function!(
                $marker,
                family,
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
    ($marker:ty, $family:ident, $kind:ident, $prefix:literal, $name:literal, $suffix:literal) => {
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
                    $crate::casadi::eval::<$marker>($family(), Kind::$kind, arg, res)
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
