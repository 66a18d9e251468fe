//! The standard stiff test set through the plain `Ode` interface, each problem with its exact
//! Jacobian and its published reference solution: the problems of the stiff-set test
//! (`long_runs/stiff_set.rs`) and of the work–precision benchmark (`benches/work_precision.rs`).
//!
//! Definitions, initial values, spans and reference solutions are those of the *Test Set for
//! IVP Solvers* (F. Mazzia and C. Magherini, release 2.4, University of Bari, 2008; files
//! rober.F, vdpol.F, hires.F, orego.F, pollu.F, revisions of 2006), which also describe the
//! problems' origins (Hairer & Wanner, *Solving Ordinary Differential Equations II*, 2nd ed.,
//! IV.10; Verwer, *SIAM J. Sci. Comput.* 15 (1994) for the pollution model). The reference
//! solutions were computed there with RADAU5 at rtol = atol = 1.1·10⁻¹⁸ in extended precision.
//!
//! The achieved error of a run is the Test Set's mixed error at the end point,
//! max_i |yᵢ − refᵢ| / (|refᵢ| + atol/rtol): relative for components above atol/rtol,
//! absolute (relative to atol/rtol) below. Each problem sets atol/rtol
//! ([`StiffProblem::ATOL_RATIO`]) to the size below which a component is negligible.

use hamel::{Error, Integrator, NamedValues, Ode, Radau5, Rodas5P, Stats, Vector};

/// A problem of the test set.
pub trait StiffProblem: Ode + Default {
    /// The Test Set's name.
    const NAME: &'static str;
    /// The end of the span (it starts at 0).
    const T_END: f64;
    /// atol = ATOL_RATIO·rtol in every run.
    const ATOL_RATIO: f64;
    fn start() -> Self::State;
    /// The Test Set's reference solution at `T_END`.
    fn reference() -> Self::State;
}

/// Radau5 with rtol and atol = rtol·`P::ATOL_RATIO`, default settings otherwise, from the
/// start to the end of `P`'s span: the end state and the statistics.
pub fn radau5<P: StiffProblem>(rtol: f64) -> Result<(P::State, Stats), Error> {
    let mut end = P::start();
    let method = Radau5::new(rtol, rtol * P::ATOL_RATIO);
    let stats = method.integrate(
        &mut P::default(),
        0.0,
        &P::start(),
        &[P::T_END],
        &mut |_, y| {
            end = *y;
            Ok(())
        },
    )?;
    Ok((end, stats))
}

/// Rodas5P with rtol and atol = rtol·`P::ATOL_RATIO` (as [`radau5`]).
pub fn rodas5p<P: StiffProblem>(rtol: f64) -> Result<(P::State, Stats), Error> {
    run::<P, _, _>(&Rodas5P::new(rtol, rtol * P::ATOL_RATIO), &mut P::default())
}

/// `method` from the start to the end of `P`'s span on `ode` (`P` itself, or `P` without its
/// Jacobian): the end state and the statistics.
pub fn run<P: StiffProblem, I: Integrator, O: Ode<State = P::State>>(
    method: &I,
    ode: &mut O,
) -> Result<(P::State, Stats), Error> {
    let mut end = P::start();
    let stats = method.integrate(ode, 0.0, &P::start(), &[P::T_END], &mut |_, y| {
        end = *y;
        Ok(())
    })?;
    Ok((end, stats))
}

/// A problem with its right-hand side alone, as a user's `Ode` without a Jacobian or ∂f/∂t:
/// the methods difference them.
#[derive(Default)]
pub struct Differenced<P>(pub P);

impl<P: Ode> Ode for Differenced<P> {
    type State = P::State;

    fn rhs(&mut self, t: f64, y: &P::State, f: &mut P::State) -> Result<(), Error> {
        self.0.rhs(t, y, f)
    }

    fn describe(&self, y: &P::State) -> NamedValues {
        self.0.describe(y)
    }
}

/// The Test Set's mixed error of `y` at the end of `P`'s span.
pub fn mixed_error<P: StiffProblem>(y: &P::State) -> f64 {
    let reference = P::reference();
    y.as_ref()
        .iter()
        .zip(reference.as_ref())
        .map(|(v, r)| (v - r).abs() / (r.abs() + P::ATOL_RATIO))
        .fold(0.0, f64::max)
}

/// Robertson's chemical kinetics (ROBER): three species, rate constants 0.04, 10⁴ and
/// 3·10⁷, over 10¹¹ s (the Test Set's span; Hairer & Wanner's 4·10¹⁰ lies inside it).
#[derive(Clone, Copy, Debug, Default)]
pub struct Robertson;

impl Ode for Robertson {
    type State = [f64; 3];

    fn rhs(&mut self, _t: f64, y: &[f64; 3], f: &mut [f64; 3]) -> Result<(), Error> {
        f[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
        f[1] = 0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1];
        f[2] = 3e7 * y[1] * y[1];
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, y: &[f64; 3], j: &mut [f64]) -> Result<bool, Error> {
        j.copy_from_slice(&[
            -0.04,
            1e4 * y[2],
            1e4 * y[1],
            0.04,
            -1e4 * y[2] - 6e7 * y[1],
            -1e4 * y[1],
            0.0,
            6e7 * y[1],
            0.0,
        ]);
        Ok(true)
    }

    /// Autonomous: ∂f/∂t = 0.
    fn time_derivative(
        &mut self,
        _t: f64,
        _y: &Self::State,
        d: &mut Self::State,
    ) -> Result<bool, Error> {
        *d = Self::State::zeros();
        Ok(true)
    }
}

impl StiffProblem for Robertson {
    const NAME: &'static str = "ROBER";
    const T_END: f64 = 1e11;
    const ATOL_RATIO: f64 = 1e-6;
    fn start() -> [f64; 3] {
        [1.0, 0.0, 0.0]
    }
    // The Test Set's digits as published (a trailing zero included).
    #[allow(clippy::excessive_precision)]
    fn reference() -> [f64; 3] {
        [
            0.2083340149701255e-7,
            0.8333360770334713e-13,
            0.9999999791665050,
        ]
    }
}

/// Van der Pol's equation with ε = 10⁻⁶ (VDPOL): y₁′ = y₂, y₂′ = ((1 − y₁²) y₂ − y₁)/ε over
/// [0, 2], a relaxation oscillation with jumps on the time scale ε.
#[derive(Clone, Copy, Debug, Default)]
pub struct VanDerPol;

const VDPOL_EPS: f64 = 1e-6;

impl Ode for VanDerPol {
    type State = [f64; 2];

    fn rhs(&mut self, _t: f64, y: &[f64; 2], f: &mut [f64; 2]) -> Result<(), Error> {
        f[0] = y[1];
        f[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / VDPOL_EPS;
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, y: &[f64; 2], j: &mut [f64]) -> Result<bool, Error> {
        j.copy_from_slice(&[
            0.0,
            1.0,
            (-2.0 * y[0] * y[1] - 1.0) / VDPOL_EPS,
            (1.0 - y[0] * y[0]) / VDPOL_EPS,
        ]);
        Ok(true)
    }

    /// Autonomous: ∂f/∂t = 0.
    fn time_derivative(
        &mut self,
        _t: f64,
        _y: &Self::State,
        d: &mut Self::State,
    ) -> Result<bool, Error> {
        *d = Self::State::zeros();
        Ok(true)
    }
}

impl StiffProblem for VanDerPol {
    const NAME: &'static str = "VDPOL";
    const T_END: f64 = 2.0;
    const ATOL_RATIO: f64 = 1.0;
    fn start() -> [f64; 2] {
        [2.0, 0.0]
    }
    fn reference() -> [f64; 2] {
        [0.1706167732170483e1, -0.8928097010247975]
    }
}

/// The High Irradiance Response of photomorphogenesis (HIRES; Schäfer 1975): eight species
/// over [0, 321.8122].
#[derive(Clone, Copy, Debug, Default)]
pub struct Hires;

impl Ode for Hires {
    type State = [f64; 8];

    fn rhs(&mut self, _t: f64, y: &[f64; 8], f: &mut [f64; 8]) -> Result<(), Error> {
        f[0] = -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007;
        f[1] = 1.71 * y[0] - 8.75 * y[1];
        f[2] = -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4];
        f[3] = 8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3];
        f[4] = -1.745 * y[4] + 0.43 * (y[5] + y[6]);
        f[5] = -280.0 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6];
        f[6] = 280.0 * y[5] * y[7] - 1.81 * y[6];
        f[7] = -f[6];
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, y: &[f64; 8], j: &mut [f64]) -> Result<bool, Error> {
        j.fill(0.0);
        let mut set = |r: usize, c: usize, v: f64| j[r * 8 + c] = v;
        set(0, 0, -1.71);
        set(0, 1, 0.43);
        set(0, 2, 8.32);
        set(1, 0, 1.71);
        set(1, 1, -8.75);
        set(2, 2, -10.03);
        set(2, 3, 0.43);
        set(2, 4, 0.035);
        set(3, 1, 8.32);
        set(3, 2, 1.71);
        set(3, 3, -1.12);
        set(4, 4, -1.745);
        set(4, 5, 0.43);
        set(4, 6, 0.43);
        set(5, 3, 0.69);
        set(5, 4, 1.71);
        set(5, 5, -280.0 * y[7] - 0.43);
        set(5, 6, 0.69);
        set(5, 7, -280.0 * y[5]);
        set(6, 5, 280.0 * y[7]);
        set(6, 6, -1.81);
        set(6, 7, 280.0 * y[5]);
        set(7, 5, -280.0 * y[7]);
        set(7, 6, 1.81);
        set(7, 7, -280.0 * y[5]);
        Ok(true)
    }

    /// Autonomous: ∂f/∂t = 0.
    fn time_derivative(
        &mut self,
        _t: f64,
        _y: &Self::State,
        d: &mut Self::State,
    ) -> Result<bool, Error> {
        *d = Self::State::zeros();
        Ok(true)
    }
}

impl StiffProblem for Hires {
    const NAME: &'static str = "HIRES";
    const T_END: f64 = 321.8122;
    const ATOL_RATIO: f64 = 1e-4;
    fn start() -> [f64; 8] {
        [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057]
    }
    fn reference() -> [f64; 8] {
        [
            0.7371312573325668e-3,
            0.1442485726316185e-3,
            0.5888729740967575e-4,
            0.1175651343283149e-2,
            0.2386356198831331e-2,
            0.6238968252742796e-2,
            0.2849998395185769e-2,
            0.2850001604814231e-2,
        ]
    }
}

/// The Oregonator (OREGO; Field & Noyes 1974): the Belousov–Zhabotinskii reaction, three
/// species over [0, 360].
#[derive(Clone, Copy, Debug, Default)]
pub struct Oregonator;

impl Ode for Oregonator {
    type State = [f64; 3];

    fn rhs(&mut self, _t: f64, y: &[f64; 3], f: &mut [f64; 3]) -> Result<(), Error> {
        f[0] = 77.27 * (y[1] + y[0] * (1.0 - 8.375e-6 * y[0] - y[1]));
        f[1] = (y[2] - (1.0 + y[0]) * y[1]) / 77.27;
        f[2] = 0.161 * (y[0] - y[2]);
        Ok(())
    }

    fn jacobian(&mut self, _t: f64, y: &[f64; 3], j: &mut [f64]) -> Result<bool, Error> {
        j.copy_from_slice(&[
            77.27 * (1.0 - 2.0 * 8.375e-6 * y[0] - y[1]),
            77.27 * (1.0 - y[0]),
            0.0,
            -y[1] / 77.27,
            -(1.0 + y[0]) / 77.27,
            1.0 / 77.27,
            0.161,
            0.0,
            -0.161,
        ]);
        Ok(true)
    }

    /// Autonomous: ∂f/∂t = 0.
    fn time_derivative(
        &mut self,
        _t: f64,
        _y: &Self::State,
        d: &mut Self::State,
    ) -> Result<bool, Error> {
        *d = Self::State::zeros();
        Ok(true)
    }
}

impl StiffProblem for Oregonator {
    const NAME: &'static str = "OREGO";
    const T_END: f64 = 360.0;
    const ATOL_RATIO: f64 = 1.0;
    fn start() -> [f64; 3] {
        [1.0, 2.0, 3.0]
    }
    fn reference() -> [f64; 3] {
        [
            0.1000814870318523e1,
            0.1228178521549917e4,
            0.1320554942846706e3,
        ]
    }
}

/// The air pollution model of the Dutch National Institute of Public Health (POLLU; Verwer
/// 1994): 20 species, 25 reactions, over [0, 60].
#[derive(Clone, Copy, Debug, Default)]
pub struct Pollution;

/// POLLU's rate constants k₁ … k₂₅.
const POLLU_K: [f64; 25] = [
    0.35, 0.266e2, 0.123e5, 0.86e-3, 0.82e-3, 0.15e5, 0.13e-3, 0.24e5, 0.165e5, 0.9e4, 0.22e-1,
    0.12e5, 0.188e1, 0.163e5, 0.48e7, 0.35e-3, 0.175e-1, 0.1e9, 0.444e12, 0.124e4, 0.21e1, 0.578e1,
    0.474e-1, 0.178e4, 0.312e1,
];

/// POLLU's reactions: (rate constant, the species it is proportional to, 1-based as in the
/// Test Set; 0 for none).
const POLLU_REACTIONS: [(usize, usize); 25] = [
    (1, 0),
    (2, 4),
    (5, 2),
    (7, 0),
    (7, 0),
    (7, 6),
    (9, 0),
    (9, 6),
    (11, 2),
    (11, 1),
    (13, 0),
    (10, 2),
    (14, 0),
    (1, 6),
    (3, 0),
    (4, 0),
    (4, 0),
    (16, 0),
    (16, 0),
    (17, 6),
    (19, 0),
    (19, 0),
    (1, 4),
    (19, 1),
    (20, 0),
];

/// POLLU's stoichiometry: for each species, the reactions that consume it and produce it
/// (1-based reaction numbers; a reaction listed twice counts twice).
const POLLU_CONSUMED: [&[usize]; 20] = [
    &[1, 10, 14, 23, 24],
    &[2, 3, 9, 12],
    &[15],
    &[2, 16, 17, 23],
    &[3],
    &[6, 8, 14, 20],
    &[4, 5, 6],
    &[],
    &[7, 8],
    &[12],
    &[9, 10],
    &[],
    &[11],
    &[13],
    &[],
    &[18, 19],
    &[20],
    &[],
    &[21, 22, 24],
    &[25],
];
const POLLU_PRODUCED: [&[usize]; 20] = [
    &[2, 3, 9, 11, 12, 22, 25],
    &[1, 21],
    &[1, 17, 19, 22],
    &[15],
    &[4, 4, 6, 7, 13, 20],
    &[3, 18, 18],
    &[13],
    &[4, 5, 6, 7],
    &[],
    &[7, 9],
    &[8, 11],
    &[9],
    &[10],
    &[12],
    &[14],
    &[16],
    &[],
    &[20],
    &[23, 25],
    &[24],
];

impl Pollution {
    /// The reaction rates r₁ … r₂₅ (pollu.F's r(1) … r(25)).
    fn rates(y: &[f64; 20]) -> [f64; 25] {
        core::array::from_fn(|i| {
            let (a, b) = POLLU_REACTIONS[i];
            let second = if b == 0 { 1.0 } else { y[b - 1] };
            POLLU_K[i] * y[a - 1] * second
        })
    }
}

impl Ode for Pollution {
    type State = [f64; 20];

    fn rhs(&mut self, _t: f64, y: &[f64; 20], f: &mut [f64; 20]) -> Result<(), Error> {
        let r = Self::rates(y);
        for (s, fs) in f.iter_mut().enumerate() {
            let made: f64 = POLLU_PRODUCED[s].iter().map(|&k| r[k - 1]).sum();
            let used: f64 = POLLU_CONSUMED[s].iter().map(|&k| r[k - 1]).sum();
            *fs = made - used;
        }
        Ok(())
    }

    /// ∂fₛ/∂yⱼ = Σ_reactions ±∂r/∂yⱼ, each rate a product of at most two species.
    fn jacobian(&mut self, _t: f64, y: &[f64; 20], j: &mut [f64]) -> Result<bool, Error> {
        j.fill(0.0);
        for (s, (made, used)) in POLLU_PRODUCED.iter().zip(POLLU_CONSUMED).enumerate() {
            let signed = made
                .iter()
                .map(|&k| (k, 1.0))
                .chain(used.iter().map(|&k| (k, -1.0)));
            for (k, sign) in signed {
                let (a, b) = POLLU_REACTIONS[k - 1];
                let rate = POLLU_K[k - 1];
                if b == 0 {
                    j[s * 20 + a - 1] += sign * rate;
                } else {
                    j[s * 20 + a - 1] += sign * rate * y[b - 1];
                    j[s * 20 + b - 1] += sign * rate * y[a - 1];
                }
            }
        }
        Ok(true)
    }

    /// Autonomous: ∂f/∂t = 0.
    fn time_derivative(
        &mut self,
        _t: f64,
        _y: &Self::State,
        d: &mut Self::State,
    ) -> Result<bool, Error> {
        *d = Self::State::zeros();
        Ok(true)
    }
}

impl StiffProblem for Pollution {
    const NAME: &'static str = "POLLU";
    const T_END: f64 = 60.0;
    const ATOL_RATIO: f64 = 1e-4;
    fn start() -> [f64; 20] {
        let mut y = [0.0; 20];
        y[1] = 0.2;
        y[3] = 0.04;
        y[6] = 0.1;
        y[7] = 0.3;
        y[8] = 0.01;
        y[16] = 0.007;
        y
    }
    // The Test Set's digits as published (a trailing zero included).
    #[allow(clippy::excessive_precision)]
    fn reference() -> [f64; 20] {
        [
            0.5646255480022769e-1,
            0.1342484130422339,
            0.4139734331099427e-8,
            0.5523140207484359e-2,
            0.2018977262302196e-6,
            0.1464541863493966e-6,
            0.7784249118997964e-1,
            0.3245075353396018,
            0.7494013383880406e-2,
            0.1622293157301561e-7,
            0.1135863833257075e-7,
            0.2230505975721359e-2,
            0.2087162882798630e-3,
            0.1396921016840158e-4,
            0.8964884856898295e-2,
            0.4352846369330103e-17,
            0.6899219696263405e-2,
            0.1007803037365946e-3,
            0.1772146513969984e-5,
            0.5682943292316392e-4,
        ]
    }
}
