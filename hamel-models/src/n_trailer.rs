//! A tractor pulling N trailers with on-axle hitching, written once for every N: the macro
//! [`n_trailer!`](crate::n_trailer!) defines the model for the number of trailers it is
//! given, and the catalogue instantiates it for N = 1, 2, 8 and 24.
//!
//! The tractor is a body on one wheel axle, its centre P₀ = (x, y), heading θ₀. Trailer i
//! (1 ≤ i ≤ N) rests on one axle whose centre Pᵢ lies a distance dᵢ behind the hitch, and the
//! hitch is the centre of the previous axle (on-axle hitching):
//!
//! Pᵢ = Pᵢ₋₁ − dᵢ (cos θᵢ, sin θᵢ).
//!
//! The wheels of every axle roll without sliding sideways: the velocity of each axle centre
//! has no component along the axle, Ṗᵢ · (−sin θᵢ, cos θᵢ) = 0 for i = 0…N — N + 1
//! nonholonomic constraints on the N + 3 coordinates q = (x, y, θ₀, …, θ_N). The free speeds
//! are the tractor's forward speed v and turning rate ω = θ̇₀, so the state has
//! 2n − p = N + 5 components. Each body is a point mass mᵢ at its axle centre with a moment of
//! inertia Iᵢ about the vertical through it; T = Σᵢ ½ mᵢ |Ṗᵢ|² + ½ Iᵢ θ̇ᵢ².
//!
//! On the motion each axle pulls the next along the classical kinematics of the N-trailer
//! (Laumond, *Controllability of a multibody mobile robot*, IEEE Trans. Robot. Autom. 9
//! (1993); Sørdalen, *Conversion of the kinematic model of a car with n trailers into a
//! chained form*, ICRA 1993): with vᵢ the forward speed of axle i (v₀ = v),
//!
//! θ̇ᵢ = (vᵢ₋₁ / dᵢ) sin(θᵢ₋₁ − θᵢ),   vᵢ = vᵢ₋₁ cos(θᵢ₋₁ − θᵢ).
//!
//! Two inputs act on the tractor: a drive force along its heading, applied at its axle
//! centre, and a steering torque about the vertical.
//!
//! The model gives no closed-form inverse (`#[velocities]`): A(q) is block triangular along
//! the train, which the macro's sparse LU of it exploits. The inverse is easy to
//! write — rolling\[i\] = Ṗᵢ₋₁ · nᵢ − dᵢ θ̇ᵢ gives θ̇ᵢ axle by axle from the tractor back — and
//! gives the same motion, but composed into L̃ = L(q, B(q) ω) it made the code for N = 24
//! larger and slower: a release build of this crate took about four times as long (18 s
//! against 4 to 5 s), and a right-hand side 1.8 µs instead of 1.4 µs (on one machine).
//!
//! The module `hamel::models` runs one of them, and `hamel::n_trailer!` defines another.

/// Defines the model of a tractor pulling `trailers` trailers with on-axle hitching (see
/// the module [`n_trailer`](mod@crate::n_trailer)): a parameter struct and its
/// `#[hamel_system]` impl.
///
///
/// The arguments are the struct's attributes (doc comments, further derives) and visibility,
/// its name, the number N of trailers and the number N + 1 of axles, both as integer
/// literals. The macro needs N + 1 written out because names and parameters are given as
/// indexed groups — `coordinates(x, y, theta[N + 1])`, `m: [f64; N + 1]` — and a group's or
/// a parameter array's length must be an integer literal, which `macro_rules!` cannot compute
/// from N. The bodies are written in N + 1 alone (`for i in 1..axles`, `q: &[f64; axles + 2]`)
/// and `trailers` only names N, so that numbers that do not match are one error, a
/// compile-time assertion's, which says that `axles` must be `trailers + 1`.
///
/// The model:
///
/// * coordinates `x, y, theta0 … thetaN`: the tractor's axle centre and heading, the
///   trailers' headings (`Self::THETA + i` is the index of θᵢ);
/// * speeds `v, omega`: the tractor's forward speed and turning rate;
/// * inputs `drive, steer`: a force along the tractor's heading at its axle centre (newtons)
///   and a torque on the tractor about the vertical (N m);
/// * parameters, one entry per body (0: the tractor, i: trailer i): `m` the masses (kg),
///   point masses at the axle centres, `inertia` the moments of inertia about the vertical
///   through the axle centres (kg m²), `d` the distances from each trailer's hitch to its axle
///   centre (m) — `d[0]` is unused, kept so that `d[i]` is trailer i's; a trailer's must not be
///   0, or nothing determines its heading rate (`Error::SingularTransformation`);
/// * constraints `axle0 … axleN`: the sideways velocity of each axle centre (`Self::AXLE + i`
///   is the index of axle i's; its constraint force is the column `lambda_axle<i>`);
/// * no `#[velocities]`: B(q) comes from the LU factorization of A(q) (see the module
///   documentation for why);
/// * an associated constant `TRAILERS` = N.
///
/// `Default` is a small train: a tractor of 2 kg and 0.1 kg m², trailers of 1 kg and
/// 0.05 kg m² hitched 0.5 m ahead of their axles (`d[0]` = 0).
#[macro_export]
macro_rules! n_trailer {
    ($(#[$attr:meta])* $vis:vis $name:ident, trailers = $n:literal, axles = $axles:literal) => {
        $(#[$attr])*
        #[$crate::hamel_system]
        #[derive(Clone, Debug, PartialEq)]
        $vis struct $name {
            /// mass of each body, a point mass at its axle centre (kg)
            pub m: [f64; $axles],
            /// moment of inertia of each body about the vertical through its axle centre (kg m²)
            pub inertia: [f64; $axles],
            /// distance from each trailer's hitch to its axle centre (m); entry 0 is unused
            pub d: [f64; $axles],
        }

        // Group lengths must be literals, so N + 1 is passed in: check it is.
        const _: () = ::core::assert!(
            $axles == $n + 1,
            "n_trailer!: `axles` must be `trailers + 1`"
        );

        impl $name {
            /// The number of trailers N.
            pub const TRAILERS: usize = $n;
        }

        impl ::core::default::Default for $name {
            fn default() -> Self {
                let mut m = [1.0; $axles];
                let mut inertia = [0.05; $axles];
                let mut d = [0.5; $axles];
                m[0] = 2.0;
                inertia[0] = 0.1;
                d[0] = 0.0;
                $name { m, inertia, d }
            }
        }

        #[$crate::hamel_system(
            coordinates(x, y, theta[$axles]),
            speeds(v, omega),
            inputs(drive, steer),
            constraints(axle[$axles]),
            units(
                t = "s", x = "m", y = "m", theta = "rad", v = "m/s", omega = "rad/s",
                drive = "N", steer = "N m", energy = "J"
            )
        )]
        impl $name {
            /// The velocities of the axle centres: Ṗ₀ = (ẋ, ẏ), and differentiating
            /// Pᵢ = Pᵢ₋₁ − dᵢ (cos θᵢ, sin θᵢ), Ṗᵢ = Ṗᵢ₋₁ + dᵢ θ̇ᵢ (sin θᵢ, −cos θᵢ).
            fn axle_velocities(
                &self,
                q: &[f64; $axles + 2],
                qd: &[f64; $axles + 2],
            ) -> [[f64; 2]; $axles] {
                let mut p = [[0.0; 2]; $axles];
                p[0][0] = qd[Self::X];
                p[0][1] = qd[Self::Y];
                for i in 1..$axles {
                    let (s, c) = q[Self::THETA + i].sin_cos();
                    let rate = self.d[i] * qd[Self::THETA + i];
                    p[i][0] = p[i - 1][0] + rate * s;
                    p[i][1] = p[i - 1][1] - rate * c;
                }
                p
            }

            /// T = Σᵢ ½ mᵢ |Ṗᵢ|² + ½ Iᵢ θ̇ᵢ².
            #[kinetic_energy]
            fn kinetic_energy(&self, q: &[f64; $axles + 2], qd: &[f64; $axles + 2]) -> f64 {
                let p = self.axle_velocities(q, qd);
                let mut t = 0.0;
                for i in 0..$axles {
                    let rate = qd[Self::THETA + i];
                    t += 0.5 * self.m[i] * (p[i][0] * p[i][0] + p[i][1] * p[i][1])
                        + 0.5 * self.inertia[i] * rate * rate;
                }
                t
            }

            /// Every axle rolls: its centre's velocity across the axle direction,
            /// Ṗᵢ · (−sin θᵢ, cos θᵢ), vanishes.
            #[constraints]
            fn rolling(&self, q: &[f64; $axles + 2], qd: &[f64; $axles + 2]) -> [f64; $axles] {
                let p = self.axle_velocities(q, qd);
                let mut rows = [0.0; $axles];
                for i in 0..$axles {
                    let (s, c) = q[Self::THETA + i].sin_cos();
                    rows[i] = -p[i][0] * s + p[i][1] * c;
                }
                rows
            }

            /// The tractor's forward speed and turning rate.
            #[quasi_velocities]
            fn tractor(&self, q: &[f64; $axles + 2], qd: &[f64; $axles + 2]) -> [f64; 2] {
                let (s, c) = q[Self::THETA].sin_cos();
                [qd[Self::X] * c + qd[Self::Y] * s, qd[Self::THETA]]
            }

            /// The drive force along the tractor's heading, at its axle centre, and the
            /// steering torque on the tractor.
            #[forces]
            fn forces(
                &self,
                _t: f64,
                q: &[f64; $axles + 2],
                _qd: &[f64; $axles + 2],
                u: &[f64; 2],
            ) -> [f64; $axles + 2] {
                let mut f = [0.0; $axles + 2];
                let (s, c) = q[Self::THETA].sin_cos();
                f[Self::X] = u[Self::DRIVE] * c;
                f[Self::Y] = u[Self::DRIVE] * s;
                f[Self::THETA] = u[Self::STEER];
                f
            }
        }
    };
}

n_trailer!(
    /// A tractor with one trailer (N = 1): q = (x, y, θ₀, θ₁).
    pub NTrailer1, trailers = 1, axles = 2
);

n_trailer!(
    /// A tractor with two trailers (N = 2).
    pub NTrailer2, trailers = 2, axles = 3
);

n_trailer!(
    /// A tractor with eight trailers (N = 8).
    pub NTrailer8, trailers = 8, axles = 9
);

n_trailer!(
    /// A tractor with twenty-four trailers (N = 24).
    pub NTrailer24, trailers = 24, axles = 25
);
