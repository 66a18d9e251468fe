//! The paper's mobile robot (Franke, Zaiczek & Röbenack, section 4) in both of hamel's input
//! forms — `MobileRobot` (energies from the bodies' 3D motion, B = A⁻¹ computed numerically)
//! and `MobileRobotPaper` (the paper's L̃(q, ω) of eq. (12), B given) — checked against
//!
//! 1. the closed form of `hamel::docs::design` (right-hand side and the coefficients γ),
//! 2. each other (right-hand sides and whole trajectories),
//! 3. the invariants of a free motion (energy, constraints),
//! 4. Lagrange's equations projected on the admissible directions, derived independently
//!    in `common/robot_projected_lagrange.rs` with num-dual and nalgebra.
//!
//! State x = (x, y, α, φ₁, φ₂, ω³, ω⁴, ω⁵), inputs u = (τ₁, τ₂). Random points come from a
//! seeded xorshift, so every run checks the same states. Run with `--nocapture` to see the
//! measured worst cases.

use std::f64::consts::PI;

use crate::common::robot_by_hand::MobileRobotByHand;
use crate::common::robot_closed_form::robot_rhs;
use crate::common::robot_projected_lagrange::projected_lagrange_rhs;
use crate::common::xorshift::XorShift;
use hamel::geometry::Mechanism;
use hamel::models::{MobileRobot, MobileRobotPaper};
use hamel::{DormandPrince, HamelSystem, Simulation, Trajectory};

/// Two evaluations of the same equations differ by rounding only: a few ulps of the largest
/// component, times the conditioning of the 3×3 solve.
const RHS_TOLERANCE: f64 = 1e-12;
/// γ is ±1 or 0 exactly; numerically B = A⁻¹ leaves rounding.
const GAMMA_TOLERANCE: f64 = 1e-12;
/// Two integrations of right-hand sides equal to rounding, at rtol = atol = 1e-13.
const TRAJECTORY_TOLERANCE: f64 = 1e-9;
const ENERGY_DRIFT_LIMIT: f64 = 1e-9;
const RESIDUAL_LIMIT: f64 = 1e-12;
/// Random states (or configurations) per parameter set and check.
const RANDOM_POINTS: usize = 200;

/// What every check needs of a model: the robot's dimensions (n = 5, p = 2, two inputs).
trait Robot:
    HamelSystem<
        State = [f64; 8],
        Inputs = [f64; 2],
        Coordinates = [f64; 5],
        Speeds = [f64; 3],
        Constraints = [f64; 2],
        Gamma = [[[f64; 3]; 3]; 5],
    >
{
}

impl<S> Robot for S where
    S: HamelSystem<
            State = [f64; 8],
            Inputs = [f64; 2],
            Coordinates = [f64; 5],
            Speeds = [f64; 3],
            Constraints = [f64; 2],
            Gamma = [[[f64; 3]; 3]; 5],
        >
{
}

/// The default robot, and a second one with different proportions (J_x < J_z, a larger
/// wheel, a longer lever) so that no check passes by a coincidence of the defaults.
fn parameter_sets() -> Vec<MobileRobot> {
    let other = MobileRobot {
        m0: 4.0,
        mw: 0.7,
        jx: 0.15,
        jy: 0.25,
        jz: 0.35,
        r: 0.15,
        b: 0.6,
        l: 0.3,
        g: 9.81,
    };
    vec![MobileRobot::default(), other]
}

/// A configuration: position anywhere near the origin, α anywhere, wheels turned by up to
/// several revolutions either way.
fn random_configuration(rng: &mut XorShift) -> [f64; 5] {
    [
        rng.uniform(-10.0, 10.0),
        rng.uniform(-10.0, 10.0),
        rng.uniform(-PI, PI),
        rng.uniform(-20.0, 20.0),
        rng.uniform(-20.0, 20.0),
    ]
}

/// A state: a random configuration with speeds ω³, ω⁴, ω⁵ of order 1–3.
fn random_state(rng: &mut XorShift) -> [f64; 8] {
    let q = random_configuration(rng);
    let mut x = [0.0; 8];
    x[..5].copy_from_slice(&q);
    for w in &mut x[5..] {
        *w = rng.uniform(-3.0, 3.0);
    }
    x
}

/// Motor torques of order 1.
fn random_inputs(rng: &mut XorShift) -> [f64; 2] {
    [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)]
}

/// max_k |a_k − b_k| / max_k |b_k|: every component is judged against the scale of the whole
/// vector, so a component that happens to be near zero in b does not demand digits that
/// rounding elsewhere cannot give.
fn normwise_error(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale.max(f64::MIN_POSITIVE)
}

/// The closed form of `hamel::docs::design` as a function returning ẋ.
fn closed_form(p: &MobileRobot, x: &[f64; 8], u: &[f64; 2]) -> [f64; 8] {
    let mut dx = [0.0; 8];
    robot_rhs(p, x, u, &mut dx);
    dx
}

fn rhs<S: Robot>(sys: &S, x: &[f64; 8], u: &[f64; 2]) -> [f64; 8] {
    let mut dx = [0.0; 8];
    sys.rhs(0.0, x, u, &mut dx)
        .unwrap_or_else(|s| panic!("rhs singular at {x:?}: {s:?}"));
    dx
}

/// The largest error of each model's right-hand side against `reference` over random states
/// and inputs of every parameter set, asserting each against the tolerance and printing
/// the worst.
fn worst_rhs_errors(
    seed: u64,
    what: &str,
    reference: impl Fn(&MobileRobot, &[f64; 8], &[f64; 2]) -> [f64; 8],
) {
    let mut rng = XorShift::new(seed);
    let (mut worst_everyday, mut worst_paper) = (0.0f64, 0.0f64);
    for robot in parameter_sets() {
        let paper = MobileRobotPaper::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = (random_state(&mut rng), random_inputs(&mut rng));
            let expected = reference(&robot, &x, &u);
            for (name, got, worst) in [
                ("MobileRobot", rhs(&robot, &x, &u), &mut worst_everyday),
                ("MobileRobotPaper", rhs(&paper, &x, &u), &mut worst_paper),
            ] {
                let err = normwise_error(&got, &expected);
                assert!(
                    err <= RHS_TOLERANCE,
                    "{name} vs {what}: relative error {err:e} at x = {x:?}, u = {u:?}, \
                     parameters {robot:?}\n  generated {got:?}\n  expected  {expected:?}"
                );
                *worst = worst.max(err);
            }
        }
    }
    println!(
        "{what}: worst norm-wise relative error {worst_everyday:.2e} (MobileRobot), \
         {worst_paper:.2e} (MobileRobotPaper) over {} states",
        2 * RANDOM_POINTS
    );
}

// ---------------------------------------------------------------------------------------
// 0. The robot from its two wheels against the robot by hand
// ---------------------------------------------------------------------------------------

/// The catalogue's robot, stated from its body and its two wheels rolling on the ground,
/// has the right-hand side and the energy of the robot whose energy, constraints and
/// quasi-velocities were written by hand (as the catalogue had it), at random states and
/// torques; the macro found that the second wheel's rows repeat the first's.
#[test]
fn the_robot_from_its_two_wheels_is_the_robot_by_hand() {
    let mut rng = XorShift::new(0x5eed_0007);
    let (mut worst_rhs, mut worst_energy) = (0.0f64, 0.0f64);
    for robot in parameter_sets() {
        let by_hand = MobileRobotByHand::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = (random_state(&mut rng), random_inputs(&mut rng));
            let (geometry, hand) = (rhs(&robot, &x, &u), rhs(&by_hand, &x, &u));
            let err = normwise_error(&geometry, &hand);
            assert!(
                err <= RHS_TOLERANCE,
                "relative difference {err:e} at x = {x:?}, u = {u:?}\n  from wheels {geometry:?}\n  \
                 by hand     {hand:?}"
            );
            worst_rhs = worst_rhs.max(err);
            let (e, h) = (
                robot.energy(0.0, &x).unwrap(),
                by_hand.energy(0.0, &x).unwrap(),
            );
            let err = (e - h).abs() / h.abs().max(1.0);
            assert!(err <= RHS_TOLERANCE, "energy {e} against {h} at x = {x:?}");
            worst_energy = worst_energy.max(err);
        }
    }
    println!(
        "robot from two wheels vs by hand: worst norm-wise relative difference {worst_rhs:.2e} \
         (right-hand side), {worst_energy:.2e} (energy) over {} states",
        2 * RANDOM_POINTS
    );
    assert_eq!(MobileRobot::BODIES, ["body", "right_wheel", "left_wheel"]);
    assert_eq!(MobileRobot::CONSTRAINTS, ["no_slip", "no_side_slip"]);
    let notes = MobileRobot::NOTES;
    println!("{notes:#?}");
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(notes[0].contains("contact 1's (`left_wheel`'s) slip along its heading repeats"));
    assert!(
        notes[0].contains("`no_slip`")
            && notes[0].contains("gives 1/2 to contact 0, 1/2 to contact 1")
    );
    assert!(notes[1].contains("along its axle") && notes[1].contains("`no_side_slip`"));
}

// ---------------------------------------------------------------------------------------
// 1. The closed form of `hamel::docs::design`
// ---------------------------------------------------------------------------------------

/// The generated ẋ — kinematics q̇ = Bᵣ ω and the accelerations ω̇ — equals the closed form
/// of `hamel::docs::design` (with its corrected signs of the γ terms) for both input forms.
#[test]
fn generated_rhs_equals_the_closed_form() {
    worst_rhs_errors(0x5eed_0001, "closed form", closed_form);
}

/// The accelerations ω̇ alone, judged against their own scale (stricter than the 8-component
/// rule, where the wheel rates r⁻¹ω⁴ dominate the scale).
#[test]
fn generated_accelerations_equal_the_closed_form_on_their_own_scale() {
    let mut rng = XorShift::new(0x5eed_0002);
    let mut worst = 0.0f64;
    for robot in parameter_sets() {
        let paper = MobileRobotPaper::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = (random_state(&mut rng), random_inputs(&mut rng));
            let expected = closed_form(&robot, &x, &u);
            for got in [rhs(&robot, &x, &u), rhs(&paper, &x, &u)] {
                let err = normwise_error(&got[5..], &expected[5..]);
                assert!(
                    err <= RHS_TOLERANCE,
                    "ω̇ relative error {err:e} at x = {x:?}, u = {u:?}: {:?} vs {:?}",
                    &got[5..],
                    &expected[5..]
                );
                worst = worst.max(err);
            }
        }
    }
    println!("closed form, ω̇ block on its own scale: worst {worst:.2e}");
}

/// γʲ_{l,k} expected of a model, by (j, l − p, k − p).
type Expected<'a> = dyn Fn(usize, usize, usize) -> f64 + 'a;

/// γ¹₄,₅ = −1, γ¹₅,₄ = +1 (1-based, as in `hamel::docs::design`) and every other γʲ_{l,k} with
/// l, k > 2 vanishes, at every configuration. `gamma` is indexed [j][l − p][k − p], 0-based,
/// p = 2. The robot from its wheels has the paper's rows in the other order and sign (a
/// wheel's slip along its heading, then along its axle: −ω², −ω¹), so its γ² is −γ¹.
#[test]
fn gamma_has_only_the_two_entries_of_the_paper() {
    let mut rng = XorShift::new(0x5eed_0003);
    let mut worst = 0.0f64;
    let papers = |j: usize, l: usize, k: usize| match (j, l, k) {
        (0, 1, 2) => -1.0,
        (0, 2, 1) => 1.0,
        _ => 0.0,
    };
    let wheels = |j: usize, l: usize, k: usize| match j {
        1 => -papers(0, l, k),
        _ => 0.0,
    };
    for robot in parameter_sets() {
        let paper = MobileRobotPaper::from(&robot);
        let by_hand = MobileRobotByHand::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let q = random_configuration(&mut rng);
            let rows: [(&str, _, &Expected); 3] = [
                ("MobileRobot", robot.gamma(0.0, &q).unwrap(), &wheels),
                (
                    "MobileRobotByHand",
                    by_hand.gamma(0.0, &q).unwrap(),
                    &papers,
                ),
                ("MobileRobotPaper", paper.gamma(0.0, &q).unwrap(), &papers),
            ];
            for (name, gamma, expected) in rows {
                for (j, gamma_j) in gamma.iter().enumerate() {
                    for (l, row) in gamma_j.iter().enumerate() {
                        for (k, &value) in row.iter().enumerate() {
                            let err = (value - expected(j, l, k)).abs();
                            assert!(
                                err <= GAMMA_TOLERANCE,
                                "{name}: γ^{}_{{{},{}}} = {value:e} at q = {q:?}, expected {}",
                                j + 1,
                                l + 3,
                                k + 3,
                                expected(j, l, k)
                            );
                            worst = worst.max(err);
                        }
                    }
                }
            }
        }
    }
    println!(
        "γ: worst absolute error {worst:.2e} over {} configurations",
        2 * RANDOM_POINTS
    );
}

// ---------------------------------------------------------------------------------------
// 2. The paper's form against the everyday form
// ---------------------------------------------------------------------------------------

#[test]
fn paper_form_and_everyday_form_have_equal_right_hand_sides() {
    let mut rng = XorShift::new(0x5eed_0004);
    let mut worst = 0.0f64;
    for robot in parameter_sets() {
        let paper = MobileRobotPaper::from(&robot);
        for _ in 0..RANDOM_POINTS {
            let (x, u) = (random_state(&mut rng), random_inputs(&mut rng));
            let (everyday, papers) = (rhs(&robot, &x, &u), rhs(&paper, &x, &u));
            let err = normwise_error(&everyday, &papers);
            assert!(
                err <= RHS_TOLERANCE,
                "relative difference {err:e} at x = {x:?}, u = {u:?}\n  MobileRobot      \
                 {everyday:?}\n  MobileRobotPaper {papers:?}"
            );
            worst = worst.max(err);
        }
    }
    println!(
        "paper vs everyday rhs: worst norm-wise relative difference {worst:.2e} over {} states",
        2 * RANDOM_POINTS
    );
}

/// For every state column c: max over samples |a_c − b_c| / max over samples |b_c| — each
/// quantity judged against its own scale over the run (metres, radians, rad/s).
fn worst_column_difference<S: Robot>(a: &Trajectory, b: &Trajectory) -> (f64, &'static str) {
    assert_eq!(
        a.times(),
        b.times(),
        "the two runs must sample the same times"
    );
    let mut worst = (0.0f64, "");
    for name in S::STATE {
        let (ca, cb) = (a.column(name).unwrap(), b.column(name).unwrap());
        let err = normwise_error(ca, cb);
        if err >= worst.0 {
            worst = (err, name);
        }
    }
    worst
}

/// Both forms integrated side by side from several initial states, one free and the others
/// driven: the trajectories agree to 1e-9 at every sample, so the forms agree not just at
/// random points but along the motion, where errors could accumulate.
#[test]
fn paper_form_and_everyday_form_give_the_same_trajectories() {
    // (configuration, speeds ω³ ω⁴ ω⁵, torques): body leaning forward and rolling freely;
    // hanging below the axle and swinging while steered by unequal torques; tipping backwards
    // while both motors push.
    let runs: [([f64; 5], [f64; 3], [f64; 2]); 3] = [
        ([0.0, 0.0, 0.3, 0.0, 0.0], [1.0, 1.5, 2.0], [0.0, 0.0]),
        ([1.0, -2.0, 2.5, 3.0, -1.0], [-2.0, 1.0, -1.0], [0.5, -0.3]),
        ([-3.0, 4.0, -1.0, -7.0, 5.0], [3.0, -2.0, 0.5], [1.0, 1.0]),
    ];
    let integrator = DormandPrince::new(1e-13, 1e-13);
    for robot in parameter_sets() {
        let paper = MobileRobotPaper::from(&robot);
        for (q, speeds, u) in runs {
            let simulate = |x0| {
                (
                    Simulation::new(&robot, x0)
                        .end_time(3.0)
                        .sample_interval(0.01)
                        .run_constant(&integrator, u)
                        .unwrap(),
                    Simulation::new(&paper, x0)
                        .end_time(3.0)
                        .sample_interval(0.01)
                        .run_constant(&integrator, u)
                        .unwrap(),
                )
            };
            let x0 = robot.state_from_speeds(0.0, &q, &speeds).unwrap();
            assert_eq!(x0, paper.state_from_speeds(0.0, &q, &speeds).unwrap());
            let (everyday, papers) = simulate(x0);
            assert_eq!(everyday.len(), 301);
            let (err, column) = worst_column_difference::<MobileRobot>(&papers, &everyday);
            println!(
                "trajectories from q = {q:?}, ω = {speeds:?}, τ = {u:?}: worst column-wise relative \
                 difference {err:.2e} (in {column}); steps {} / {}",
                everyday.summary().steps,
                papers.summary().steps
            );
            assert!(
                err <= TRAJECTORY_TOLERANCE,
                "the forms' trajectories differ by {err:e} (relative, column {column}) from \
                 q = {q:?}, ω = {speeds:?}, τ = {u:?}, parameters {robot:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// 3. Invariants of the free motion
// ---------------------------------------------------------------------------------------

/// The trajectory as its CSV would deliver it: the header and the rows, read back as numbers
/// (the CSV prints every f64 so that it reads back exactly).
fn csv_rows(trajectory: &Trajectory) -> (Vec<String>, Vec<Vec<f64>>) {
    let mut bytes = Vec::new();
    trajectory.write_csv(&mut bytes).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// Integrates 10 s with τ = 0 and checks energy and constraints from the summary and again
/// from the CSV-level samples. Returns (relative energy drift, max constraint residual).
fn free_motion_invariants<S: Robot>(sys: &S, name: &str) -> (f64, f64) {
    // Leaning forward, pitching, rolling and turning: everything moves.
    let q = [0.0, 0.0, 0.4, 1.0, -0.7];
    let x0 = sys.state_from_speeds(0.0, &q, &[1.2, 1.5, 2.0]).unwrap();
    let trajectory = Simulation::new(sys, x0)
        .end_time(10.0)
        .sample_interval(0.01)
        .run_constant(&DormandPrince::new(1e-12, 1e-12), [0.0, 0.0])
        .unwrap();
    let summary = trajectory.summary();

    // The run must be a real motion: the body pitches through a wide range, the robot travels.
    let alpha = trajectory.column("alpha").unwrap();
    let alpha_range = alpha.iter().fold(f64::NEG_INFINITY, |m, a| m.max(*a))
        - alpha.iter().fold(f64::INFINITY, |m, a| m.min(*a));
    let (xs, ys) = (
        trajectory.column("x").unwrap(),
        trajectory.column("y").unwrap(),
    );
    // Path length, not distance: the robot turns, so it drives in loops.
    let travelled: f64 = (1..xs.len())
        .map(|i| (xs[i] - xs[i - 1]).hypot(ys[i] - ys[i - 1]))
        .sum();
    assert!(alpha_range > 1.0, "{name}: α only spans {alpha_range}");
    assert!(
        travelled > 1.0,
        "{name}: the robot only moved {travelled} m"
    );

    // Recompute both monitors from the samples, with q̇ = B(q) ω from `velocities`.
    let (header, rows) = csv_rows(&trajectory);
    assert_eq!(rows.len(), 1001);
    let index = |n: &str| header.iter().position(|h| h == n).unwrap();
    let state_columns: Vec<usize> = S::STATE.iter().map(|n| index(n)).collect();
    let energy_column = index("energy");
    let e0 = rows[0][energy_column];
    let (mut residual, mut drift) = (0.0f64, 0.0f64);
    for row in &rows {
        let x: [f64; 8] = std::array::from_fn(|i| row[state_columns[i]]);
        let qd = sys.generalized_velocities(0.0, &x).unwrap();
        for r in sys.constraint_residual(0.0, &S::coordinates_of(&x), &qd) {
            residual = residual.max(r.abs());
        }
        assert_eq!(sys.energy(0.0, &x).unwrap(), row[energy_column]);
        drift = drift.max((row[energy_column] - e0).abs() / e0.abs());
    }
    println!(
        "{name}, τ = 0, 10 s, DOPRI5 rtol = atol = 1e-12: relative energy drift {:.2e} \
         (from the samples {drift:.2e}), E₀ = {e0:.6}, max constraint residual {:.2e} (from \
         the samples {residual:.2e}); {} steps, {} rejected; α spans {alpha_range:.2} rad, \
         {travelled:.2} m driven",
        summary.relative_energy_drift,
        summary.max_constraint_residual,
        summary.steps,
        summary.rejected,
    );
    assert_eq!(drift, summary.relative_energy_drift);
    assert_eq!(residual, summary.max_constraint_residual);
    assert!(
        summary.relative_energy_drift < ENERGY_DRIFT_LIMIT,
        "{name}: relative energy drift {:e}",
        summary.relative_energy_drift
    );
    assert!(
        summary.max_constraint_residual <= RESIDUAL_LIMIT,
        "{name}: constraint residual {:e}",
        summary.max_constraint_residual
    );
    (drift, residual)
}

/// With the torques at zero the robot's power vanishes (its only forces are the torques), so
/// a run with constant zero torques integrates no work; it must be, to the bit, the run that
/// integrates it (zero torques given as a function), its energy balance the energy drift.
#[test]
fn zero_torques_leave_out_the_work_and_change_no_bit() {
    const {
        assert!(MobileRobot::POWER_VANISHES_WITHOUT_INPUTS && !MobileRobot::CONSERVATIVE);
        assert!(MobileRobotPaper::POWER_VANISHES_WITHOUT_INPUTS);
    };
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_speeds(0.0, &[0.0, 0.0, 0.3, 0.0, 0.0], &[0.0, 0.5, 0.4])
        .unwrap();
    let simulation = Simulation::new(&robot, x0).end_time(3.0);
    let integrator = DormandPrince::new(1e-9, 1e-12);
    let constant = simulation.run_constant(&integrator, [0.0, 0.0]).unwrap();
    let function = simulation.run(&integrator, |_, _| [0.0, 0.0]).unwrap();
    assert_eq!(constant.names(), function.names());
    for name in constant.names() {
        let (a, b) = (
            constant.column(name).unwrap(),
            function.column(name).unwrap(),
        );
        let same = a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "column {name} differs between the two runs");
    }
    assert_eq!(constant.summary().steps, function.summary().steps);
    assert_eq!(constant.summary().work, 0.0);
    let (energy, balance) = (
        constant.column("energy").unwrap(),
        constant.column("energy_balance").unwrap(),
    );
    for (e, b) in energy.iter().zip(balance) {
        assert_eq!(*b, e - energy[0]);
    }
    // A torque does work: the run with it integrates the work and balances the energy.
    let pushed = simulation.run_constant(&integrator, [0.1, 0.05]).unwrap();
    assert!(
        pushed.summary().work.abs() > 1e-3,
        "{}",
        pushed.summary().work
    );
    assert!(pushed.summary().relative_energy_balance < 1e-7);
}

#[test]
fn free_motion_conserves_energy_and_keeps_the_constraints() {
    for robot in parameter_sets() {
        free_motion_invariants(&robot, "MobileRobot");
        free_motion_invariants(&MobileRobotPaper::from(&robot), "MobileRobotPaper");
    }
}

// ---------------------------------------------------------------------------------------
// 4. An independent derivation: the projected Lagrange equations
// ---------------------------------------------------------------------------------------

/// Hamel's equations as generated equal Lagrange's equations projected on the admissible
/// directions, with the Lagrangian, A(q), B = A⁻¹ and every derivative computed in the test.
#[test]
fn generated_rhs_equals_the_projected_lagrange_equations() {
    worst_rhs_errors(0x5eed_0005, "projected Lagrange", projected_lagrange_rhs);
}

/// The reference itself against the closed form: if the two references disagreed, a pass of
/// the generated code against one of them would mean less.
#[test]
fn projected_lagrange_reference_equals_the_closed_form() {
    let mut rng = XorShift::new(0x5eed_0006);
    let mut worst = 0.0f64;
    for robot in parameter_sets() {
        for _ in 0..RANDOM_POINTS {
            let (x, u) = (random_state(&mut rng), random_inputs(&mut rng));
            let closed = closed_form(&robot, &x, &u);
            let err = normwise_error(&projected_lagrange_rhs(&robot, &x, &u), &closed);
            assert!(
                err <= RHS_TOLERANCE,
                "references differ by {err:e} at x = {x:?}"
            );
            worst = worst.max(err);
        }
    }
    println!("projected Lagrange vs closed form: worst {worst:.2e}");
}
