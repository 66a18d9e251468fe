//! Work–precision of Radau5 and Rodas5P on the standard stiff test set (ROBER, VDPOL with
//! ε = 10⁻⁶, HIRES, OREGO, POLLU: `tests/validation/tests/common/stiff_problems.rs`, Bari Test
//! Set references) and on the suite's two mechanical stiff models (the disk with k = 10⁶
//! against its closed form, the robot with a k = 10⁴ speed controller against Dormand–Prince
//! at 10⁻¹³), at rtol = 10⁻³ … 10⁻¹⁰ (Radau5 also at 10⁻¹¹ … 10⁻¹³: `RADAU5_TOLERANCES`;
//! Rodas5P also at 10⁻²: `RODAS5P_TOLERANCES`):
//! achieved error, steps, rejections, right-hand-side evaluations, Jacobians, LU
//! factorizations and wall time.
//!
//! `benches/work_precision/run.sh` compares it with scipy's `Radau` and `BDF` and diffsol's
//! BDF and ESDIRK34 by calling this binary in two modes:
//! - `round R PROBLEM`: Radau5 on PROBLEM at every tolerance, a batch of runs of at least
//!   0.1 s each (the wall time the batch's mean), appended to
//!   `target/work_precision/hamel.csv` as round R (the other solvers are run likewise, round
//!   after round, alternating with it);
//! - `report`: the tables of all three CSVs, the side-by-side ratios at equal error and one
//!   figure per problem, error against wall time, into `benches/work_precision/<problem>.svg`.
//!
//! Without a mode (`cargo bench -p hamel-benches --bench work_precision`) it prints hamel's
//! table alone, from three rounds, and writes nothing. `once PROBLEM` runs each tolerance
//! once, untimed, and prints the rows as CSV (wall time NaN): a fixed amount of work, for an
//! instruction count (`valgrind --tool=callgrind <binary> once POLLU`; a round's batches
//! depend on the clock) and for checking that a change keeps every count and error. `at
//! PROBLEM SOLVER RTOL...` does the same at the tolerances given (`trend.py` runs it on a fine
//! grid of them).

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
use hamel::{
    DormandPrince, Error, HamelSystem, Integrator, Ode, Radau5, Rodas5P, SampleObserver,
    SampleTimes, Stats, Vector,
};
use stiff_problems::{
    Differenced, Hires, Oregonator, Pollution, Robertson, StiffProblem, VanDerPol, mixed_error, run,
};

use compare::Row;

const TOLERANCES: [f64; 8] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

/// Radau5's tolerances: the others' and three tighter. Radau5 holds its local error to
/// RADAU5's transformed tolerance 0.1·rtol^(2/3) (`Radau5`'s documentation), so its rtol 10⁻¹⁰
/// is a local tolerance of 2·10⁻⁸ and its curve would stop short of the errors the other
/// solvers reach there; at rtol 10⁻¹³ it is 4.6·10⁻¹⁰, still looser than the others'
/// tightest (10⁻¹⁰). The comparison is at equal achieved error: these runs extend Radau5's
/// curve to those errors, and the points compared stay each solver's rtol 10⁻³…10⁻¹⁰.
const RADAU5_TOLERANCES: [f64; 11] = [
    1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13,
];

/// Rodas5P's tolerances: the others' and one looser. Its local error is held to rtol itself
/// where Radau5's is held to 0.1·rtol^(2/3), so at rtol 10⁻³ Rodas5P's error comes out far
/// below Radau5's (ROBER 1.4·10⁻⁶ against 2.2·10⁻⁵, POLLU 1.2·10⁻⁵ against 1.9·10⁻⁴), and
/// without this run its curve stops short of the errors Radau5 reaches at its loosest: the
/// faster of the two there would be Radau5 for want of a rival. As Radau5's tighter runs,
/// this one extends the curve that the others are read on; the points compared stay every
/// solver's rtol 10⁻³…10⁻¹⁰.
const RODAS5P_TOLERANCES: [f64; 9] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10];

/// One run of a problem at rtol: the statistics and the achieved error.
type Run = Box<dyn FnMut(f64) -> (Stats, f64)>;
/// A problem's run with a solver of hamel's (`None` where the solver does not apply).
type NewRun = fn(Solver) -> Option<Run>;

/// hamel's solvers: Radau5 and Rodas5P on the exact Jacobian (and ∂f/∂t), and on the test
/// set also as a user's `Ode` without them (differenced).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Solver {
    Radau5,
    Rodas5P,
    Radau5Differenced,
    Rodas5PDifferenced,
}

const SOLVERS: [Solver; 4] = [
    Solver::Radau5,
    Solver::Rodas5P,
    Solver::Radau5Differenced,
    Solver::Rodas5PDifferenced,
];

impl Solver {
    /// The tolerances the solver runs at.
    fn tolerances(self) -> &'static [f64] {
        match self {
            Solver::Radau5 | Solver::Radau5Differenced => &RADAU5_TOLERANCES,
            Solver::Rodas5P | Solver::Rodas5PDifferenced => &RODAS5P_TOLERANCES,
        }
    }

    fn label(self) -> &'static str {
        match self {
            Solver::Radau5 => compare::RADAU5,
            Solver::Rodas5P => compare::RODAS5P,
            Solver::Radau5Differenced => compare::RADAU5_DIFFERENCED,
            Solver::Rodas5PDifferenced => compare::RODAS5P_DIFFERENCED,
        }
    }
}

/// The problems by name, each with the constructor of its run.
const PROBLEMS: [(&str, NewRun); 7] = [
    (Robertson::NAME, test_set::<Robertson>),
    (VanDerPol::NAME, test_set::<VanDerPol>),
    (Hires::NAME, test_set::<Hires>),
    (Oregonator::NAME, test_set::<Oregonator>),
    (Pollution::NAME, test_set::<Pollution>),
    ("stiff disk", stiff_disk),
    ("stiff robot", stiff_robot),
];

/// The least time a batch of runs takes: runs shorter than this are repeated, and their wall
/// time is the batch's mean. A sub-millisecond run fits in one time slice of a loaded machine
/// or loses a whole one to another process, where a long run (scipy's) gets the machine's
/// average share: batches of similar length see the same share.
const BATCH_SECONDS: f64 = 0.1;

/// `f`'s last result and its mean wall time over a batch of at least [`BATCH_SECONDS`].
fn batch<T>(mut f: impl FnMut() -> T) -> (T, f64) {
    let start = Instant::now();
    let mut runs = 0;
    loop {
        let result = f();
        runs += 1;
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed >= BATCH_SECONDS {
            return (result, elapsed / runs as f64);
        }
    }
}

/// One round on `problem`: every solver of hamel's in turn, a batch at every tolerance, after
/// an untimed warm-up run (the first run in a process pays for cold caches).
fn round(problem: &str, round: usize) -> Result<Vec<Row>, String> {
    let mut all = Vec::new();
    for solver in SOLVERS {
        all.extend(rows(problem, solver, solver.tolerances(), round, true)?);
    }
    Ok(all)
}

/// The rows of `problem` with `solver` at each of `tolerances`: timed (a warm-up run, then a
/// batch at each) or not (one run at each, the wall time NaN); none where the solver does not
/// apply.
fn rows(
    problem: &str,
    solver: Solver,
    tolerances: &[f64],
    round: usize,
    timed: bool,
) -> Result<Vec<Row>, String> {
    let (_, new) = PROBLEMS
        .iter()
        .find(|(name, _)| *name == problem)
        .ok_or_else(|| {
            let names: Vec<&str> = PROBLEMS.iter().map(|(name, _)| *name).collect();
            format!("no problem {problem:?}: one of {names:?}")
        })?;
    let Some(mut run) = new(solver) else {
        return Ok(Vec::new());
    };
    if timed {
        run(TOLERANCES[1]);
    }
    Ok(tolerances
        .iter()
        .map(|&rtol| {
            let ((stats, error), wall) = if timed {
                batch(|| run(rtol))
            } else {
                (run(rtol), f64::NAN)
            };
            Row {
                round,
                problem: problem.into(),
                solver: solver.label().into(),
                rtol,
                error,
                steps: stats.steps as f64,
                rejected: stats.rejected as f64,
                evaluations: stats.evaluations as f64,
                jacobians: stats.jacobians as f64,
                factorizations: stats.factorizations as f64,
                wall,
            }
        })
        .collect())
}

/// `solver` on one problem of the test set.
fn test_set<P: StiffProblem + 'static>(solver: Solver) -> Option<Run> {
    Some(Box::new(move |rtol| {
        let atol = rtol * P::ATOL_RATIO;
        let (radau, rodas) = (Radau5::new(rtol, atol), Rodas5P::new(rtol, atol));
        let (end, stats) = match solver {
            Solver::Radau5 => run::<P, _, _>(&radau, &mut P::default()),
            Solver::Rodas5P => run::<P, _, _>(&rodas, &mut P::default()),
            Solver::Radau5Differenced => run::<P, _, _>(&radau, &mut Differenced(P::default())),
            Solver::Rodas5PDifferenced => run::<P, _, _>(&rodas, &mut Differenced(P::default())),
        }
        .expect("the run");
        (stats, mixed_error::<P>(&end))
    }))
}

/// A model's run with Radau5 or Rodas5P at rtol = atol = `rtol` (the models have their exact
/// Jacobian: the differenced solvers are the test set's).
fn integrate_model<O: Ode, T: SampleTimes + ?Sized>(
    solver: Solver,
    rtol: f64,
    ode: &mut O,
    x0: &O::State,
    samples: &T,
    observe: &mut SampleObserver<'_, O::State>,
) -> Result<Stats, Error> {
    match solver {
        Solver::Rodas5P => Rodas5P::new(rtol, rtol).integrate(ode, 0.0, x0, samples, observe),
        _ => Radau5::new(rtol, rtol).integrate(ode, 0.0, x0, samples, observe),
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
fn stiff_disk(solver: Solver) -> Option<Run> {
    if !matches!(solver, Solver::Radau5 | Solver::Rodas5P) {
        return None;
    }
    let sys = StiffDisk::default();
    let start = [0.0, 0.0, 0.1, 0.2];
    let motion = StiffMotion::new(sys.r, start, -0.2, 1.0, (-1.0, -1e6));
    let x0 = sys.state_from_speeds(0.0, &start, &[-0.2, 1.0]).unwrap();
    let samples: Vec<f64> = (1..=10).map(|i| i as f64).collect();
    Some(Box::new(move |rtol| {
        let mut error = 0.0f64;
        let mut model = Model {
            system: &sys,
            inputs: |_: &StiffDisk, _, _: &[f64; 6]| [],
        };
        let stats = integrate_model(solver, rtol, &mut model, &x0, &samples[..], &mut |t, x| {
            let exact = motion.state(t);
            for i in 0..6 {
                error = error.max((x[i] - exact[i]).abs() / (exact[i].abs() + 1.0));
            }
            Ok(())
        })
        .expect("the run");
        (stats, error)
    }))
}

fn robot_controller(robot: &MobileRobot, t: f64, x: &[f64; 8]) -> [f64; 2] {
    let qd = robot.generalized_velocities(t, x).expect("regular");
    [-1e4 * (qd[3] - 5.0), -1e4 * (qd[4] - 5.0)]
}

/// The robot under its speed controller.
fn model(robot: &MobileRobot) -> impl Ode<State = [f64; 8]> + '_ {
    Model {
        system: robot,
        inputs: robot_controller,
    }
}

/// The guide's stiff robot (k = 10⁴ N m s) to t = 5, its error at the end against
/// Dormand–Prince at rtol = atol = 10⁻¹³ (an explicit method: an independent answer).
fn stiff_robot(solver: Solver) -> Option<Run> {
    if !matches!(solver, Solver::Radau5 | Solver::Rodas5P) {
        return None;
    }
    let robot = MobileRobot::default();
    let x0 = robot
        .state_from_speeds(0.0, &[0.0, 0.0, 3.0, 0.0, 0.0], &[0.0, 0.0, 0.0])
        .unwrap();
    let mut reference = x0;
    DormandPrince::new(1e-13, 1e-13)
        .integrate(&mut model(&robot), 0.0, &x0, &[5.0], &mut |_, x| {
            reference = *x;
            Ok(())
        })
        .expect("the reference run");
    Some(Box::new(move |rtol| {
        let mut end = x0;
        let stats = integrate_model(
            solver,
            rtol,
            &mut model(&robot),
            &x0,
            &[5.0],
            &mut |_, x| {
                end = *x;
                Ok(())
            },
        )
        .expect("the run");
        let error = end
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs() / (b.abs() + 1.0))
            .fold(0.0, f64::max);
        (stats, error)
    }))
}

fn main() {
    // `cargo bench` passes `--bench`.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let result = match args[..] {
        ["round", number, problem] => number
            .parse()
            .map_err(|_| format!("the round is a number, not {number:?}"))
            .and_then(|number| round(problem, number))
            .map(|rows| compare::append_csv(&rows, &compare::data_dir().join("hamel.csv"))),
        ["once", problem] => SOLVERS
            .iter()
            .map(|&solver| rows(problem, solver, solver.tolerances(), 0, false))
            .collect::<Result<Vec<Vec<Row>>, String>>()
            .map(|rows| print!("{}", compare::csv_text(&rows.concat(), true))),
        ["once", problem, solver] => SOLVERS
            .iter()
            .find(|s| s.label() == solver)
            .ok_or_else(|| format!("no solver {solver:?}"))
            .and_then(|&s| rows(problem, s, s.tolerances(), 0, false))
            .map(|rows| print!("{}", compare::csv_text(&rows, true))),
        ["at", problem, solver, ref tolerances @ ..] => {
            let tolerances: Result<Vec<f64>, String> = tolerances
                .iter()
                .map(|t| match t.parse::<f64>() {
                    Ok(v) if v > 0.0 && v < 1.0 => Ok(v),
                    _ => Err(format!("a tolerance is a number in (0, 1), not {t:?}")),
                })
                .collect();
            tolerances.and_then(|tolerances| {
                let solver = SOLVERS
                    .iter()
                    .find(|s| s.label() == solver)
                    .ok_or_else(|| format!("no solver {solver:?}"))?;
                let rows = rows(problem, *solver, &tolerances, 0, false)?;
                print!("{}", compare::csv_text(&rows, true));
                Ok(())
            })
        }
        ["report"] => {
            let mut rows = Vec::new();
            for solver in ["hamel", "scipy", "hairer", "diffsol"] {
                rows.extend(compare::read_csv(
                    &compare::data_dir().join(format!("{solver}.csv")),
                ));
            }
            if rows.is_empty() {
                Err("no rows in target/work_precision/: run benches/work_precision/run.sh".into())
            } else {
                compare::report(&rows, true);
                Ok(())
            }
        }
        [] => (1..=3)
            .flat_map(|number| PROBLEMS.iter().map(move |(name, _)| round(name, number)))
            .collect::<Result<Vec<Vec<Row>>, String>>()
            .map(|rows| compare::report(&rows.concat(), false)),
        _ => Err(
            "usage: work_precision [round R PROBLEM | once PROBLEM [SOLVER] | at PROBLEM SOLVER \
             RTOL... | report]"
                .into(),
        ),
    };
    if let Err(message) = result {
        eprintln!("work_precision: {message}");
        std::process::exit(2);
    }
}
