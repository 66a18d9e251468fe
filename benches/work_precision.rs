//! Work–precision of Radau5 on the standard stiff test set (ROBER, VDPOL with ε = 10⁻⁶,
//! HIRES, OREGO, POLLU: `tests/validation/tests/common/stiff_problems.rs`, Bari Test Set
//! references) and on the suite's two mechanical stiff models (the disk with k = 10⁶ against
//! its closed form, the robot with a k = 10⁴ speed controller against Dormand–Prince at
//! 10⁻¹³), at rtol = 10⁻⁴ … 10⁻¹⁰: achieved error, steps, rejections, right-hand-side
//! evaluations, Jacobians, LU factorizations and wall time (median of 7 runs).
//!
//! `cargo bench -p hamel-benches --bench work_precision` prints the table and writes
//! `target/work_precision/hamel.csv`. With the other solvers' CSVs beside it (written by
//! `benches/work_precision/run.sh`, which runs this too: scipy's `Radau` and `BDF`, diffsol's
//! BDF and SDIRK), it also prints the side-by-side table of the README and draws one figure
//! per problem, error against wall time, into `benches/work_precision/<problem>.svg`.

#[allow(dead_code)]
#[path = "../tests/validation/tests/common/stiff_problems.rs"]
mod stiff_problems;

#[allow(dead_code)]
#[path = "../tests/validation/tests/common/disk_closed_forms.rs"]
mod disk_closed_forms;

#[path = "work_precision/compare.rs"]
mod compare;

use std::time::Instant;

use disk_closed_forms::{StiffDisk, StiffMotion};
use hamel::models::MobileRobot;
use hamel::{DormandPrince, Error, HamelSystem, Integrator, Ode, Radau5, Stats, Vector};
use stiff_problems::{
    Hires, Oregonator, Pollution, Robertson, StiffProblem, VanDerPol, mixed_error, radau5,
};

use compare::Row;

const TOLERANCES: [f64; 7] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

/// Repetitions of each run; the wall time is their median.
const REPEATS: usize = 7;

/// The median wall time of `REPEATS` runs of `f`, and its last result.
fn timed<T>(mut f: impl FnMut() -> T) -> (T, f64) {
    let mut times = Vec::with_capacity(REPEATS);
    let mut last = None;
    for _ in 0..REPEATS {
        let start = Instant::now();
        last = Some(f());
        times.push(start.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (last.unwrap(), times[REPEATS / 2])
}

fn row(problem: &str, rtol: f64, (stats, error, wall): (Stats, f64, f64)) -> Row {
    Row {
        problem: problem.into(),
        solver: "hamel Radau5".into(),
        rtol,
        error,
        steps: stats.steps as f64,
        rejected: stats.rejected as f64,
        evaluations: stats.evaluations as f64,
        jacobians: stats.jacobians as f64,
        factorizations: stats.factorizations as f64,
        wall,
    }
}

/// Radau5 on one problem of the test set at every tolerance.
fn test_set<P: StiffProblem>(rows: &mut Vec<Row>) {
    for rtol in TOLERANCES {
        let ((end, stats), wall) = timed(|| radau5::<P>(rtol).expect("the run"));
        rows.push(row(P::NAME, rtol, (stats, mixed_error::<P>(&end), wall)));
    }
}

/// A model with constant inputs as an `Ode` with its exact Jacobian (the statistics of a
/// `Simulation` omit Jacobians and factorizations).
struct Model<'s, S: HamelSystem, F> {
    system: &'s S,
    inputs: F,
}

impl<S: HamelSystem, F: Fn(&S, f64, &S::State) -> S::Inputs> Ode for Model<'_, S, F> {
    type State = S::State;

    fn rhs(&mut self, t: f64, x: &S::State, dx: &mut S::State) -> Result<(), Error> {
        let u = (self.inputs)(self.system, t, x);
        self.system
            .rhs(t, x, &u, dx)
            .map_err(|s| S::singular(s, t, x))
    }

    /// ∂F/∂x + ∂F/∂u·∂u/∂x, the last by central differences of the input law.
    fn jacobian(&mut self, t: f64, x: &S::State, j: &mut [f64]) -> Result<bool, Error> {
        let u = (self.inputs)(self.system, t, x);
        let (jx, ju) = self
            .system
            .jacobian(t, x, &u)
            .map_err(|s| S::singular(s, t, x))?;
        j.copy_from_slice(jx.as_ref());
        let (n, m) = (S::State::LEN, S::Inputs::LEN);
        for c in 0..n {
            let d = 1e-6 * x.as_ref()[c].abs().max(1.0);
            let (mut plus, mut minus) = (*x, *x);
            plus.as_mut()[c] += d;
            minus.as_mut()[c] -= d;
            let (up, um) = (
                (self.inputs)(self.system, t, &plus),
                (self.inputs)(self.system, t, &minus),
            );
            for k in 0..m {
                let du = (up.as_ref()[k] - um.as_ref()[k]) / (2.0 * d);
                for r in 0..n {
                    j[r * n + c] += ju.as_ref()[r * m + k] * du;
                }
            }
        }
        Ok(true)
    }
}

/// The stiff disk (k = 10⁶, c = 10⁶ + 1: modes e^(−t), e^(−10⁶t)) to t = 10, its error the
/// largest over 10 samples against the closed form, relative to the state's size (0.2).
fn stiff_disk(rows: &mut Vec<Row>) {
    let sys = StiffDisk::default();
    let start = [0.0, 0.0, 0.1, 0.2];
    let motion = StiffMotion::new(sys.r, start, -0.2, 1.0, (-1.0, -1e6));
    let x0 = sys.state_from_speeds(0.0, &start, &[-0.2, 1.0]).unwrap();
    let samples: Vec<f64> = (1..=10).map(|i| i as f64).collect();
    for rtol in TOLERANCES {
        let ((stats, error), wall) = timed(|| {
            let mut error = 0.0f64;
            let mut model = Model {
                system: &sys,
                inputs: |_: &StiffDisk, _, _: &[f64; 6]| [],
            };
            let stats = Radau5::new(rtol, rtol)
                .integrate(&mut model, 0.0, &x0, &samples, &mut |t, x| {
                    let exact = motion.state(t);
                    for i in 0..6 {
                        error = error.max((x[i] - exact[i]).abs() / (exact[i].abs() + 1.0));
                    }
                    Ok(())
                })
                .expect("the run");
            (stats, error)
        });
        rows.push(row("stiff disk", rtol, (stats, error, wall)));
    }
}

fn robot_controller(robot: &MobileRobot, t: f64, x: &[f64; 8]) -> [f64; 2] {
    let qd = robot.generalized_velocities(t, x).expect("regular");
    [-1e4 * (qd[3] - 5.0), -1e4 * (qd[4] - 5.0)]
}

/// The guide's stiff robot (k = 10⁴ N m s) to t = 5, its error at the end against
/// Dormand–Prince at rtol = atol = 10⁻¹³ (an explicit method: an independent answer).
fn stiff_robot(rows: &mut Vec<Row>) {
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_speeds(0.0, &[0.0, 0.0, 3.0, 0.0, 0.0], &[0.0, 0.0, 0.0])
        .unwrap();
    let model = || Model {
        system: &robot,
        inputs: robot_controller,
    };
    let mut reference = x0;
    DormandPrince::new(1e-13, 1e-13)
        .integrate(&mut model(), 0.0, &x0, &[5.0], &mut |_, x| {
            reference = *x;
            Ok(())
        })
        .expect("the reference run");
    for rtol in TOLERANCES {
        let ((stats, end), wall) = timed(|| {
            let mut end = x0;
            let stats = Radau5::new(rtol, rtol)
                .integrate(&mut model(), 0.0, &x0, &[5.0], &mut |_, x| {
                    end = *x;
                    Ok(())
                })
                .expect("the run");
            (stats, end)
        });
        let error = end
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs() / (b.abs() + 1.0))
            .fold(0.0, f64::max);
        rows.push(row("stiff robot", rtol, (stats, error, wall)));
    }
}

fn main() {
    let mut rows = Vec::new();
    test_set::<Robertson>(&mut rows);
    test_set::<VanDerPol>(&mut rows);
    test_set::<Hires>(&mut rows);
    test_set::<Oregonator>(&mut rows);
    test_set::<Pollution>(&mut rows);
    stiff_disk(&mut rows);
    stiff_robot(&mut rows);
    compare::report(rows);
}
