//! Holonomic constraints on a hand-written system whose answers are known in closed form:
//! assembling a configuration by Newton's method, the state builder, the checks of
//! `state_from_*`, and the projection of a simulation onto f(q) = 0.
//!
//! Run with `--nocapture` to see the measured figures.

use crate::common;

use hamel_runtime::{
    AssemblyFailure, DormandPrince, Error, HamelSystem, Parameters, Rk4, Simulation, Singularity,
};

/// A skate (see `tests/simulation.rs`) towing a massless crank of length ℓ whose angle φ is
/// tied to the skate's x by the holonomic constraint f = ℓ sin φ − x = 0: φ = asin(x/ℓ) on the
/// branch |φ| < π/2, π − asin(x/ℓ) on the other, and no solution for |x| > ℓ. The crank's dead
/// centres φ = ±π/2 are where ∂f/∂φ = ℓ cos φ vanishes.
///
/// Constraint rows: the blade's no-slip row ẋ sin θ − ẏ cos θ and the crank's ḟ = ℓ cos φ φ̇ − ẋ;
/// free quasi-velocities v = ẋ cos θ + ẏ sin θ and ω = θ̇. The crank has no mass, so the
/// motion is the skate's: m v̇ = F, I ω̇ = τ, and φ̇ = ẋ/(ℓ cos φ) carries the crank along.
struct CrankSkate {
    mass: f64,
    inertia: f64,
    length: f64,
}

impl Parameters for CrankSkate {
    const NAMES: &'static [&'static str] = &["mass", "inertia", "length"];
    const DOCS: &'static [&'static str] = &[
        "mass of the skate",
        "moment of inertia about the contact point",
        "length of the crank",
    ];

    fn get(&self, name: &str) -> Option<f64> {
        match name {
            "mass" => Some(self.mass),
            "inertia" => Some(self.inertia),
            "length" => Some(self.length),
            _ => None,
        }
    }

    fn set(&mut self, name: &str, value: f64) -> Result<(), Error> {
        match name {
            "mass" => self.mass = value,
            "inertia" => self.inertia = value,
            "length" => self.length = value,
            _ => {
                return Err(Error::UnknownParameter {
                    name: name.into(),
                    known: Self::NAMES.join(", "),
                });
            }
        }
        Ok(())
    }
}

impl CrankSkate {
    /// The reduced mass matrix diag(m, I), or the first pivot that is not positive.
    fn pivots(&self) -> Result<[f64; 2], Singularity> {
        for (speed, value) in [self.mass, self.inertia].into_iter().enumerate() {
            if value.is_nan() || value <= 0.0 {
                return Err(Singularity::MassMatrix { speed, value });
            }
        }
        Ok([self.mass, self.inertia])
    }

    /// ℓ cos φ, the crank's lever for ẋ, or the singularity at a dead centre.
    fn lever(&self, phi: f64) -> Result<f64, Singularity> {
        let lever = self.length * phi.cos();
        if lever == 0.0 || lever.is_nan() {
            return Err(Singularity::Transformation {
                coordinate: 3,
                value: lever,
            });
        }
        Ok(lever)
    }

    /// q̇ of a state.
    fn qdot(&self, x: &[f64; 6]) -> Result<[f64; 4], Singularity> {
        let [_, _, theta, phi, v, omega] = *x;
        let (s, c) = theta.sin_cos();
        Ok([v * c, v * s, omega, v * c / self.lever(phi)?])
    }
}

impl HamelSystem for CrankSkate {
    type Coordinates = [f64; 4];
    type Speeds = [f64; 2];
    type Constraints = [f64; 2];
    type State = [f64; 6];
    type Inputs = [f64; 2];
    type Holonomic = [f64; 1];
    type HolonomicJacobian = [f64; 4];
    type Extended = [f64; 7];
    type MassMatrix = [[f64; 2]; 2];
    type Gamma = [[[f64; 2]; 2]; 4];
    type StateJacobian = [f64; 36];
    type InputJacobian = [f64; 12];

    const N: usize = 4;
    const P: usize = 2;
    const M: usize = 2;
    const K: usize = 1;
    const COORDINATES: &'static [&'static str] = &["x", "y", "theta", "phi"];
    const SPEEDS: &'static [&'static str] = &["v", "omega"];
    const CONSTRAINTS: &'static [&'static str] = &["no_slip", "crank[0]"];
    const INPUTS: &'static [&'static str] = &["force", "torque"];
    const STATE: &'static [&'static str] = &["x", "y", "theta", "phi", "v", "omega"];
    const DEPENDENT: &'static [usize] = &[3];
    const CONSERVATIVE: bool = false;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 6],
        u: &[f64; 2],
        dx: &mut [f64; 6],
    ) -> Result<(), Singularity> {
        let [m, i] = self.pivots()?;
        let [xd, yd, thd, phid] = self.qdot(x)?;
        *dx = [xd, yd, thd, phid, u[0] / m, u[1] / i];
        Ok(())
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 6]) -> Result<[f64; 4], Singularity> {
        self.qdot(x)
    }

    fn energy(&self, _t: f64, x: &[f64; 6]) -> Result<f64, Singularity> {
        Ok(0.5 * self.mass * x[4] * x[4] + 0.5 * self.inertia * x[5] * x[5])
    }

    fn power(&self, _t: f64, x: &[f64; 6], u: &[f64; 2]) -> Result<f64, Singularity> {
        Ok(u[0] * x[4] + u[1] * x[5])
    }

    /// The blade's centripetal force −m v ω; the massless crank transmits nothing.
    fn multipliers(&self, _t: f64, x: &[f64; 6], _u: &[f64; 2]) -> Result<[f64; 2], Singularity> {
        Ok([-self.mass * x[4] * x[5], 0.0])
    }

    fn constraint_residual(&self, _t: f64, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        let (s, c) = q[2].sin_cos();
        [
            qd[0] * s - qd[1] * c,
            self.length * q[3].cos() * qd[3] - qd[0],
        ]
    }

    fn speeds(&self, _t: f64, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        [qd[0] * q[2].cos() + qd[1] * q[2].sin(), qd[2]]
    }

    fn holonomic_residual(&self, _t: f64, q: &[f64; 4]) -> [f64; 1] {
        [self.length * q[3].sin() - q[0]]
    }

    fn holonomic_jacobian(&self, _t: f64, q: &[f64; 4]) -> [f64; 4] {
        [-1.0, 0.0, 0.0, self.length * q[3].cos()]
    }

    fn mass_matrix(&self, _t: f64, _x: &[f64; 6]) -> Result<[[f64; 2]; 2], Singularity> {
        let [m, i] = self.pivots()?;
        Ok([[m, 0.0], [0.0, i]])
    }

    /// γ as for the skate: the crank's row is a total derivative, so its γ vanish, and the
    /// crank's column of B does not enter the skate's rows.
    fn gamma(&self, _t: f64, _q: &[f64; 4]) -> Result<[[[f64; 2]; 2]; 4], Singularity> {
        let mut g = [[[0.0; 2]; 2]; 4];
        g[0][0][1] = -1.0;
        g[0][1][0] = 1.0;
        Ok(g)
    }

    /// A·B − I with A's rows (no-slip, crank, v, ω) and B = A⁻¹ in closed form.
    fn inverse_defect(&self, _t: f64, q: &[f64; 4]) -> Result<f64, Singularity> {
        let (s, c) = q[2].sin_cos();
        let l = self.lever(q[3])?;
        let a = [
            [s, -c, 0.0, 0.0],
            [-1.0, 0.0, 0.0, l],
            [c, s, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let b = [
            [s, 0.0, c, 0.0],
            [-c, 0.0, s, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [s / l, 1.0 / l, c / l, 0.0],
        ];
        let b = &b;
        let defect = a
            .iter()
            .enumerate()
            .flat_map(|(i, row)| {
                (0..4).map(move |j| {
                    let p: f64 = row.iter().zip(b).map(|(aik, bk)| aik * bk[j]).sum();
                    (p - if i == j { 1.0 } else { 0.0 }).abs()
                })
            })
            .fold(0.0, f64::max);
        Ok(defect)
    }

    /// ∂F/∂x of F = (v c, v s, ω, v c/(ℓ cos φ), F/m, τ/I) with (s, c) = (sin θ, cos θ): the
    /// crank's rate φ̇ = v c/(ℓ cos φ) depends on θ, φ and v; ∂F/∂u is diag(1/m, 1/I) in the
    /// rows of v̇ and ω̇.
    fn jacobian(
        &self,
        _t: f64,
        x: &[f64; 6],
        _u: &[f64; 2],
    ) -> Result<([f64; 36], [f64; 12]), Singularity> {
        let [m, i] = self.pivots()?;
        let [_, _, theta, phi, v, _] = *x;
        let lever = self.lever(phi)?;
        let (s, c) = theta.sin_cos();
        let mut a = [0.0; 36];
        a[2] = -v * s;
        a[4] = c;
        a[6 + 2] = v * c;
        a[6 + 4] = s;
        a[2 * 6 + 5] = 1.0;
        a[3 * 6 + 2] = -v * s / lever;
        // d/dφ (1/(ℓ cos φ)) = ℓ sin φ/(ℓ cos φ)²
        a[3 * 6 + 3] = v * c * self.length * phi.sin() / (lever * lever);
        a[3 * 6 + 4] = c / lever;
        let mut b = [0.0; 12];
        b[4 * 2] = 1.0 / m;
        b[5 * 2 + 1] = 1.0 / i;
        Ok((a, b))
    }
}

const CRANK: CrankSkate = CrankSkate {
    mass: 2.0,
    inertia: 0.5,
    length: 3.0,
};

/// x = 1.2 = ℓ·0.4: the crank's angle is asin(0.4) (or π − asin(0.4)).
const Q_GUESS: [f64; 4] = [1.2, -0.5, 0.3, 0.1];

/// The failure, time, residual and message of an assembly error, after checking that it names
/// the crank's constraint and angle and the whole configuration.
fn expect_assembly_error<T: std::fmt::Debug>(
    result: Result<T, Error>,
) -> (AssemblyFailure, f64, f64, String) {
    match result {
        Err(Error::Assembly {
            constraint,
            coordinate,
            failure,
            residual,
            t,
            configuration,
        }) => {
            assert_eq!(
                (constraint.as_str(), coordinate.as_str()),
                ("crank[0]", "phi")
            );
            assert_eq!(configuration.0.len(), 4);
            assert!(residual.is_finite(), "{residual}");
            let message = Error::Assembly {
                constraint,
                coordinate,
                t,
                failure,
                residual,
                configuration,
            }
            .to_string();
            (failure, t, residual, message)
        }
        other => panic!("expected an assembly error, got {other:?}"),
    }
}

#[test]
fn assemble_solves_the_crank_angle_on_the_guessed_branch() {
    let q = CRANK.assemble(0.0, &Q_GUESS).unwrap();
    let exact = 0.4f64.asin();
    println!("phi = {:.17} (asin 0.4 = {exact:.17})", q[3]);
    assert!((q[3] - exact).abs() <= 2.0 * f64::EPSILON, "{q:?}");
    assert_eq!(q[..3], Q_GUESS[..3], "the other coordinates are held");
    let residual = CRANK.holonomic_residual(0.0, &q)[0];
    assert!(residual.abs() <= 1e-14 * (1.2 + 3.0), "{residual:e}");

    // A guess beyond the dead centre picks the other branch.
    let other = CRANK.assemble(0.0, &[1.2, -0.5, 0.3, 2.5]).unwrap();
    let exact = std::f64::consts::PI - 0.4f64.asin();
    assert!((other[3] - exact).abs() <= 4.0 * f64::EPSILON, "{other:?}");

    // A solution comes back bit for bit.
    assert_eq!(CRANK.assemble(0.0, &q).unwrap(), q);

    // Next to the dead centre the full Newton step (−8.4) lands at a larger residual, and so
    // do its halves down to an eighth, which reaches the principal branch: without the
    // damping the iteration would leave for another branch.
    let near_dead_centre = CRANK.assemble(0.0, &[1.2, -0.5, 0.3, 1.5]).unwrap();
    assert!(
        (near_dead_centre[3] - 0.4f64.asin()).abs() <= 4.0 * f64::EPSILON,
        "{near_dead_centre:?}"
    );
}

#[test]
fn assemble_names_the_constraint_when_it_cannot_be_solved() {
    // At the dead centre the crank's angle does not move x: Newton's method has no direction.
    let dead_centre = [1.2, -0.5, 0.3, std::f64::consts::FRAC_PI_2];
    let (failure, t, _, message) = expect_assembly_error(CRANK.assemble(0.25, &dead_centre));
    println!("{message}");
    assert!(matches!(failure, AssemblyFailure::Singular { pivot } if pivot.abs() < 1e-15));
    assert_eq!(t, 0.25);
    assert!(
        message.contains("start from a better value of `phi`"),
        "{message}"
    );
    assert!(message.contains("t = 0.25"), "{message}");
    assert!(message.contains("phi = 1.57"), "{message}");

    // x beyond the crank's reach: no angle satisfies the constraint; the iteration ends near a
    // dead centre, where |f| is smallest, and says so instead of returning a wrong angle.
    let (failure, _, residual, message) =
        expect_assembly_error(CRANK.assemble(0.0, &[3.6, 0.0, 0.0, 0.3]));
    println!("{message}");
    assert!(
        matches!(
            failure,
            AssemblyFailure::Stalled { .. } | AssemblyFailure::Singular { .. }
        ),
        "{failure:?}"
    );
    assert!(
        (residual + 0.6).abs() < 1e-3,
        "min |3 sin φ − 3.6| = 0.6, not {residual}"
    );

    // A crank of length zero: the constraint does not involve φ at all.
    let (failure, ..) = expect_assembly_error(
        CrankSkate {
            length: 0.0,
            ..CRANK
        }
        .assemble(0.0, &Q_GUESS),
    );
    assert_eq!(failure, AssemblyFailure::Singular { pivot: 0.0 });
}

#[test]
fn assemble_rejects_values_that_are_not_numbers() {
    let broken = CrankSkate {
        length: f64::NAN,
        ..CRANK
    };
    match broken.assemble(0.0, &Q_GUESS) {
        Err(Error::InvalidParameter { name, value }) => {
            assert!(name == "length" && value.is_nan())
        }
        other => panic!("{other:?}"),
    }
    // Finite, but ℓ·cos φ·φ overflows: the residual's scale is not a number to judge it by.
    let huge = CrankSkate {
        length: 1e308,
        ..CRANK
    };
    let (failure, ..) = expect_assembly_error(huge.assemble(0.0, &[0.0, 0.0, 0.0, 10.0]));
    assert_eq!(failure, AssemblyFailure::NonFinite);
    match huge.state_from_speeds(0.0, &[0.0, 0.0, 0.0, 10.0], &[0.0, 0.0]) {
        Err(Error::HolonomicViolation { tolerance, .. }) => assert!(tolerance.is_infinite()),
        other => panic!("{other:?}"),
    }
    match CRANK.assemble(0.0, &[1.2, f64::INFINITY, 0.3, 0.1]) {
        Err(Error::NonFiniteInitialValue { name, .. }) => assert_eq!(name, "y"),
        other => panic!("{other:?}"),
    }
    match CRANK.assemble(f64::NAN, &Q_GUESS) {
        Err(Error::InvalidSetting { name, .. }) => assert_eq!(name, "time"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn states_from_an_inconsistent_configuration_are_errors() {
    let q = CRANK.assemble(0.0, &Q_GUESS).unwrap();
    let (s, c) = 0.3f64.sin_cos();
    let v = 1.5;
    let qd = |q: &[f64; 4]| [v * c, v * s, 0.7, v * c / (3.0 * q[3].cos())];
    let x = CRANK.state_from_velocities(0.0, &q, &qd(&q)).unwrap();
    assert_eq!(x, [q[0], q[1], q[2], q[3], v, 0.7]);
    assert_eq!(CRANK.state_from_speeds(0.0, &q, &[v, 0.7]).unwrap(), x);

    // φ written to three digits misses the constraint by 3e-4.
    let rough = [1.2, -0.5, 0.3, 0.412];
    for result in [
        CRANK.state_from_speeds(0.0, &rough, &[v, 0.7]),
        CRANK.state_from_velocities(0.0, &rough, &qd(&rough)),
    ] {
        match result {
            Err(
                ref e @ Error::HolonomicViolation {
                    ref constraint,
                    ref coordinate,
                    residual,
                    tolerance,
                    ..
                },
            ) => {
                assert_eq!(
                    (constraint.as_str(), coordinate.as_str()),
                    ("crank[0]", "phi")
                );
                assert!((residual - (3.0 * 0.412f64.sin() - 1.2)).abs() < 1e-15);
                assert!(tolerance < 1e-8, "{tolerance}");
                let message = e.to_string();
                assert!(message.contains("`assemble`"), "{message}");
                assert!(message.contains("phi = 0.412"), "{message}");
            }
            other => panic!("expected a holonomic violation, got {other:?}"),
        }
    }
}

#[test]
fn the_builder_sets_by_name_and_solves_the_crank_angle() {
    let phi = 0.4f64.asin();
    let x = CRANK
        .state_builder()
        .at_time(2.0)
        .set("x", 1.2)
        .set("y", -0.5)
        .set("theta", 0.3)
        .set("v", 1.5)
        .set("omega", 0.7)
        .build()
        .unwrap();
    assert_eq!(x[..3], [1.2, -0.5, 0.3]);
    assert_eq!(x[4..], [1.5, 0.7]);
    assert!((x[3] - phi).abs() <= 2.0 * f64::EPSILON, "{x:?}");

    // A value set for the crank angle is Newton's start: it picks the branch.
    let other = CRANK
        .state_builder()
        .coordinates(&[1.2, -0.5, 0.3, 2.5])
        .speeds(&[1.5, 0.7])
        .build()
        .unwrap();
    assert!((other[3] - (std::f64::consts::PI - phi)).abs() <= 4.0 * f64::EPSILON);

    // Velocities instead of speeds: the speeds follow from them.
    let (s, c) = 0.3f64.sin_cos();
    let qd = [1.5 * c, 1.5 * s, 0.7, 1.5 * c / (3.0 * phi.cos())];
    let from_velocities = CRANK
        .state_builder()
        .coordinates(&[1.2, -0.5, 0.3, 0.0])
        .velocities(&qd)
        .build()
        .unwrap();
    for (a, b) in from_velocities.iter().zip(&x) {
        assert!((a - b).abs() <= 4.0 * f64::EPSILON, "{from_velocities:?}");
    }
    // ... and are checked against the constraints: these slide sideways.
    match CRANK
        .state_builder()
        .coordinates(&Q_GUESS)
        .velocities(&[1.5 * c, 1.5 * s + 0.1, 0.7, qd[3]])
        .build()
    {
        Err(Error::ConstraintViolation { name, .. }) => assert_eq!(name, "no_slip"),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_builder_reports_the_first_mistake() {
    let result = CRANK
        .state_builder()
        .set("x", 1.2)
        .set("speed", 1.5)
        .set("heading", 0.3)
        .build();
    match result {
        Err(e @ Error::UnknownStateName { .. }) => {
            let message = e.to_string();
            assert_eq!(
                message,
                "unknown name `speed`: a state is set by the names of its coordinates \
                 (x, y, theta, phi) and speeds (v, omega)"
            );
        }
        other => panic!("{other:?}"),
    }
    match CRANK
        .state_builder()
        .set("omega", 0.7)
        .velocities(&[0.0; 4])
        .build()
    {
        Err(Error::AmbiguousState { speed }) => assert_eq!(speed, "omega"),
        other => panic!("{other:?}"),
    }
    match CRANK.state_builder().at_time(f64::INFINITY).build() {
        Err(Error::InvalidSetting { name, value, .. }) => {
            assert_eq!((name, value), ("time", f64::INFINITY))
        }
        other => panic!("{other:?}"),
    }
    // Out of the crank's reach: the assembly error, not a state.
    let (failure, ..) = expect_assembly_error(CRANK.state_builder().set("x", -3.5).build());
    assert!(
        !matches!(failure, AssemblyFailure::NonFinite),
        "{failure:?}"
    );
}

/// The largest |f| = |ℓ sin φ − x| over a trajectory's samples in the rows `range`.
fn residual_over(trajectory: &hamel_runtime::Trajectory, range: std::ops::Range<usize>) -> f64 {
    let (x, phi) = (
        trajectory.column("x").unwrap(),
        trajectory.column("phi").unwrap(),
    );
    range
        .map(|i| (3.0 * phi[i].sin() - x[i]).abs())
        .fold(0.0, f64::max)
}

/// The free crank skate from the state the builder assembles, for 200 s (32 turns of the
/// circle), with or without projection.
fn free_run<M: hamel_runtime::Integrator>(
    method: &M,
    dt: f64,
    project: bool,
) -> hamel_runtime::Trajectory {
    let x0 = CRANK
        .state_builder()
        .coordinates(&Q_GUESS)
        .speeds(&[1.5, 0.7])
        .build()
        .unwrap();
    Simulation::new(&CRANK, x0)
        .end_time(200.0)
        .sample_interval(dt)
        .project_holonomic(project)
        .run_constant(method, [0.0, 0.0])
        .unwrap()
}

/// Integrated, φ drifts off asin(x/ℓ): slowly, since the error partly cancels over each
/// turn; projected after every step, it stays on it to rounding, at no cost for RK4.
#[test]
fn projection_keeps_the_crank_on_its_constraint() {
    let rk4 = Rk4::new(0.2);
    let (free, projected) = (free_run(&rk4, 1.0, false), free_run(&rk4, 1.0, true));
    let n = free.len();
    let (early, late) = (
        residual_over(&free, 0..n / 10),
        residual_over(&free, n - n / 10..n),
    );
    let (plain, kept) = (free.summary(), projected.summary());
    println!(
        "RK4, h = 0.2: |f| ≤ {early:.3e} in the first 20 s, {late:.3e} in the last; \
         projected {:.3e}",
        kept.max_holonomic_residual
    );
    assert!(
        late > 4.0 * early,
        "the residual grows: {early:e} → {late:e}"
    );
    assert!(plain.max_holonomic_residual < 1e-4, "{plain}");
    assert_eq!(plain.max_holonomic_residual, residual_over(&free, 0..n));
    assert!(kept.max_holonomic_residual <= 1e-13, "{kept}");
    assert_eq!(kept.max_holonomic_residual, residual_over(&projected, 0..n));
    // Four stages a step; the run's steps are watched (for a singular crossing), and the
    // slope at each step's end, evaluated for the dense output, is the next step's first
    // stage: one evaluation more in all, at the end.
    assert_eq!((kept.steps, kept.evaluations), (1000, 4001));
    // The skate's own motion is the same either way: φ does not act on it.
    for name in ["x", "y", "theta", "v", "omega"] {
        assert_eq!(free.column(name), projected.column(name), "{name}");
    }
    assert!(kept.to_string().contains("\nmax holonomic residual   "));
}

/// Dormand–Prince with samples every 0.05 s, most of them inside steps: the samples are
/// projected as well as the steps, and each projected step but the last costs one
/// evaluation for the derivative the next one starts from.
#[test]
fn projection_covers_interpolated_samples() {
    let method = DormandPrince::new(1e-8, 1e-8);
    let (free, projected) = (
        free_run(&method, 0.05, false),
        free_run(&method, 0.05, true),
    );
    let (plain, kept) = (free.summary(), projected.summary());
    println!("DP5, tol 1e-8, free:\n{plain}\nprojected:\n{kept}");
    assert!(plain.max_holonomic_residual > 1e-8, "{plain}");
    assert!(kept.max_holonomic_residual <= 1e-13, "{kept}");
    assert_eq!(
        kept.max_holonomic_residual,
        residual_over(&projected, 0..projected.len())
    );
    assert!(
        kept.samples > 4 * kept.steps,
        "most samples are interpolated: {kept}"
    );
    let plain_cost = 2 + 6 * (kept.steps + kept.rejected);
    assert!(
        kept.evaluations > plain_cost && kept.evaluations < plain_cost + kept.steps,
        "{kept}"
    );
}

/// Straight ahead at unit speed from x = 0, the skate reaches the crank's reach x = ℓ = 3 at
/// t = 3, where φ̇ = ẋ/(ℓ cos φ) becomes infinite, and beyond it no φ exists. A projected run
/// stops there with the assembly error, naming the time and the whole state; an unprojected
/// adaptive one runs out of steps instead of crawling on forever.
#[test]
fn a_run_past_the_crank_reach_is_a_named_error() {
    let x0 = CRANK.state_builder().speeds(&[1.0, 0.0]).build().unwrap();
    let run = |project: bool, method: &dyn Fn(Simulation<'_, CrankSkate>) -> _| {
        method(
            Simulation::new(&CRANK, x0)
                .end_time(3.5)
                .sample_interval(0.5)
                .project_holonomic(project),
        )
    };
    let rk4 = |s: Simulation<'_, CrankSkate>| s.run_constant(&Rk4::new(0.1), [0.0, 0.0]);
    match run(true, &rk4) {
        Err(e @ Error::Assembly { .. }) => {
            println!("{e}");
            let Error::Assembly {
                t, configuration, ..
            } = &e
            else {
                unreachable!()
            };
            // The first step that ends beyond the reach.
            assert!((t - 3.1).abs() < 1e-12, "{t}");
            let names: Vec<&str> = configuration.0.iter().map(|(n, _)| n.as_str()).collect();
            assert_eq!(names, ["x", "y", "theta", "phi", "v", "omega", "work"]);
            assert!((configuration.get("x").unwrap() - 3.1).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
    let limited = |s: Simulation<'_, CrankSkate>| {
        s.run_constant(
            &DormandPrince::new(1e-8, 1e-8).with_max_steps(20_000),
            [0.0, 0.0],
        )
    };
    // Unprojected, the steps shrink towards the dead centre until they fall below the
    // floor (10⁻¹² of the span), long before the step limit.
    match run(false, &limited) {
        Err(Error::StepSizeUnderflow { t, h, .. }) => {
            println!("unprojected: the step fell to {h:e} at t = {t}");
            assert!((t - 3.0).abs() < 1e-6 && h < 1e-9, "{t} {h}");
        }
        other => panic!("{other:?}"),
    }
    match run(true, &limited) {
        Err(Error::Assembly { t, .. }) => assert!((t - 3.0).abs() < 1e-6, "{t}"),
        other => panic!("{other:?}"),
    }
}

/// The hand-derived Jacobian against central differences of the right-hand side, at a state
/// where every entry that can be nonzero is (the crank's rate depends on θ, φ and v).
#[test]
fn the_crank_skates_jacobian_is_the_derivative_of_its_rate() {
    let x = [1.2, -0.5, 0.3, 0.4f64.asin(), 1.5, 0.7];
    let u = [0.3, -0.2];
    let (a, b) = CRANK.jacobian(0.0, &x, &u).unwrap();
    let (fa, fb) = common::central_differences(&CRANK, 0.0, &x, &u);
    let (da, db) = (
        common::relative_difference(&a, &fa),
        common::relative_difference(&b, &fb),
    );
    println!("relative difference from central differences: A {da:.1e}, B {db:.1e}");
    assert!(da <= 1e-8 && db <= 1e-8, "{da:e} {db:e}");
}
