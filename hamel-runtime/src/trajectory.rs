//! A recorded simulation: named columns sampled at the output times, a summary of what the
//! run cost and how well it kept its invariants, and CSV output.

use core::fmt;
use std::io::Write;
use std::path::Path;

use crate::crossing::SingularCrossing;
use crate::error::{Error, Num};
use crate::events::EventRecord;
use crate::sink::Sink;
use crate::system::HamelSystem;
use crate::whole_file::WholeFile;

/// What a run cost and how well it kept energy and constraints.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Accepted integrator steps.
    pub steps: usize,
    /// Rejected integrator steps.
    pub rejected: usize,
    /// Right-hand-side evaluations.
    pub evaluations: usize,
    /// Recorded samples (rows).
    pub samples: usize,
    /// The largest |(A_c(q) q̇)ᵢ| over samples and constraints. Hamel's reduced state satisfies
    /// the constraints by construction, so anything above rounding points to a faulty model.
    pub max_constraint_residual: f64,
    /// The energy at the first sample.
    pub initial_energy: f64,
    /// max |E − E₀| over the samples: for a conservative system the integration's error in
    /// the energy (its drift), for a forced one the energy's change.
    pub max_energy_drift: f64,
    /// max |E − E₀| relative to [`Self::energy_scale`] (the error measure of a conservative
    /// system; for a forced one the energy balance is).
    pub relative_energy_drift: f64,
    /// What the relative energy figures are relative to, and its value: |E₀|, unless the
    /// energy in motion is larger (a model whose E₀ is 0, or small beside its motion).
    pub energy_scale: EnergyScale,
    /// Whether the system is `CONSERVATIVE`: then no work is done on it, W ≡ 0, and the
    /// energy balance is the energy drift.
    pub conservative: bool,
    /// K, the number of holonomic constraints.
    pub holonomic_constraints: usize,
    /// The largest |fᵢ(t, q)| over samples and holonomic constraints (0 when K = 0): the
    /// integration's error in the constraints, or rounding when they are projected.
    pub max_holonomic_residual: f64,
    /// W at the last sample: the work done on the system since the first, ∫ power dt.
    pub work: f64,
    /// max |E − E₀ − W| over the samples: the energy balance, which holds exactly for the
    /// true motion, so this is the integration's error in the energy.
    pub max_energy_balance: f64,
    /// max |E − E₀ − W| relative to [`Self::energy_scale`]: for a forced system the largest
    /// energy in the balance, |E₀|, max |E − E₀| or max |W| (E₀ alone may be 0, for a body
    /// at rest set moving).
    pub relative_energy_balance: f64,
    /// Why the run ended before its end time, if it did.
    pub stopped: Option<Stopped>,
    /// The configurations where A(q, t) is singular that the run crossed: after the first,
    /// the results are unreliable although the run returned `Ok`.
    pub singular_crossings: Vec<SingularCrossing>,
    /// Whether a symmetric method (Gauss–Legendre, the implicit midpoint rule) ran a model
    /// that is not [`crate::HamelSystem::REVERSIBLE`]: its energy error is then not bounded
    /// over long runs, which is what such a method is chosen for. The summary's `Display`
    /// says so.
    pub symmetric_not_reversible: bool,
}

/// The energy a run's relative energy figures are relative to ([`Summary::energy_scale`]),
/// with its value: the largest of the energies that take part, each a scale that means
/// something where the others may not (E₀ is 0 for a body at rest set moving, or where the
/// potential's zero happens to be).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EnergyScale {
    /// |E₀|, the initial energy's magnitude.
    InitialEnergy(f64),
    /// The largest kinetic energy over the samples, E(q, s) − E(q, 0) (conservative systems).
    KineticEnergy(f64),
    /// The largest change max |E − E₀| over the samples (forced systems).
    EnergyChange(f64),
    /// The largest |W|, the work done on the system (forced systems).
    Work(f64),
}

impl EnergyScale {
    /// The scale's value.
    pub fn value(&self) -> f64 {
        match *self {
            EnergyScale::InitialEnergy(v)
            | EnergyScale::KineticEnergy(v)
            | EnergyScale::EnergyChange(v)
            | EnergyScale::Work(v) => v,
        }
    }

    /// A conservative system's: |E₀| or the largest kinetic energy, whichever is larger.
    pub(crate) fn conservative(e0: f64, max_kinetic: f64) -> EnergyScale {
        if max_kinetic > e0.abs() {
            EnergyScale::KineticEnergy(max_kinetic)
        } else {
            EnergyScale::InitialEnergy(e0.abs())
        }
    }

    /// A forced system's: |E₀|, the largest change of E or the largest |W|, whichever is
    /// largest.
    pub(crate) fn forced(e0: f64, max_change: f64, max_work: f64) -> EnergyScale {
        let mut scale = EnergyScale::InitialEnergy(e0.abs());
        if max_change > scale.value() {
            scale = EnergyScale::EnergyChange(max_change);
        }
        if max_work > scale.value() {
            scale = EnergyScale::Work(max_work);
        }
        scale
    }
}

impl fmt::Display for EnergyScale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            EnergyScale::InitialEnergy(_) => f.write_str("|E₀|"),
            EnergyScale::KineticEnergy(v) => write!(f, "the largest kinetic energy, {}", Num(v)),
            EnergyScale::EnergyChange(v) => write!(f, "the largest energy change, {}", Num(v)),
            EnergyScale::Work(v) => write!(f, "the largest |work done|, {}", Num(v)),
        }
    }
}

/// The relative error in the energy above which a summary flags the run
/// ([`Summary::energy_inaccurate`]): 1 % of the energy's scale, far beyond what an
/// integration at any sensible tolerance or step leaves.
pub const ENERGY_WARNING: f64 = 1e-2;

/// Why a run ended before its end time.
#[derive(Clone, Debug, PartialEq)]
pub enum Stopped {
    /// A terminal event happened.
    Event { name: String, t: f64 },
    /// The progress callback asked to stop.
    Cancelled { t: f64 },
}

impl fmt::Display for Stopped {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stopped::Event { name, t } => write!(f, "at t = {} by the event `{name}`", Num(*t)),
            Stopped::Cancelled { t } => write!(f, "at t = {}, cancelled", Num(*t)),
        }
    }
}

impl Summary {
    /// The summary of a run of `S` before its first sample.
    pub(crate) fn new<S: HamelSystem>() -> Summary {
        Summary {
            steps: 0,
            rejected: 0,
            evaluations: 0,
            samples: 0,
            max_constraint_residual: 0.0,
            initial_energy: f64::NAN,
            max_energy_drift: 0.0,
            relative_energy_drift: 0.0,
            energy_scale: EnergyScale::InitialEnergy(0.0),
            conservative: S::CONSERVATIVE,
            holonomic_constraints: S::K,
            max_holonomic_residual: 0.0,
            work: 0.0,
            max_energy_balance: 0.0,
            relative_energy_balance: 0.0,
            stopped: None,
            singular_crossings: Vec::new(),
            symmetric_not_reversible: false,
        }
    }
}

impl Summary {
    /// The run's relative error in the energy: the drift of a conservative system, the
    /// balance E − E₀ − W of a forced one, each relative to [`Self::energy_scale`].
    pub fn energy_error(&self) -> f64 {
        if self.conservative {
            self.relative_energy_drift
        } else {
            self.relative_energy_balance
        }
    }

    /// Whether the energy error exceeds [`ENERGY_WARNING`] (or is NaN): the integration is
    /// far less accurate than its results look; use a smaller step or tolerance. The
    /// summary's `Display` says so.
    pub fn energy_inaccurate(&self) -> bool {
        let error = self.energy_error();
        error.is_nan() || error > ENERGY_WARNING
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "steps                    {}", self.steps)?;
        writeln!(f, "rejected                 {}", self.rejected)?;
        writeln!(f, "evaluations              {}", self.evaluations)?;
        writeln!(f, "samples                  {}", self.samples)?;
        writeln!(
            f,
            "max constraint residual  {:.3e}",
            self.max_constraint_residual
        )?;
        write!(f, "initial energy           {}", self.initial_energy)?;
        if self.conservative {
            write!(
                f,
                "\nmax energy drift         {:.3e}\nrelative energy drift    {:.3e} of {}",
                self.max_energy_drift, self.relative_energy_drift, self.energy_scale
            )?;
        } else {
            // A forced system's energy changes: its error is the balance below.
            write!(
                f,
                "\nmax energy change        {:.3e}",
                self.max_energy_drift
            )?;
        }
        if self.holonomic_constraints > 0 {
            write!(
                f,
                "\nmax holonomic residual   {:.3e}",
                self.max_holonomic_residual
            )?;
        }
        if !self.conservative {
            write!(f, "\nwork                     {}", Num(self.work))?;
            write!(
                f,
                "\nmax energy balance       {:.3e}",
                self.max_energy_balance
            )?;
            write!(
                f,
                "\nrelative energy balance  {:.3e} of {}",
                self.relative_energy_balance, self.energy_scale
            )?;
        }
        if self.energy_inaccurate() {
            write!(
                f,
                "\nwarning: the energy's relative error, {:.3e}, exceeds {ENERGY_WARNING}: the \
                 integration is far less accurate than it looks; use a smaller step or \
                 tolerance",
                self.energy_error()
            )?;
        }
        if let Some(stopped) = &self.stopped {
            write!(f, "\nstopped                  {stopped}")?;
        }
        for crossing in &self.singular_crossings {
            write!(f, "\nwarning: {crossing}")?;
        }
        if self.symmetric_not_reversible {
            write!(
                f,
                "\nnote: a symmetric method ran a model that is not REVERSIBLE (forces, moving or \
                 affine constraints, or terms odd in the speeds): its energy error is not bounded \
                 over long runs, and as it is A-stable but not L-stable it does not damp a stiff, \
                 damped motion (use Radau5 for one)"
            )?;
        }
        Ok(())
    }
}

/// Samples of named quantities, stored by column: `t` first, then whatever the producer
/// recorded (for a [`crate::Simulation`]: the state, then the energy, then, for a system
/// that is not conservative, the energy balance E − E₀ − W).
#[derive(Clone, PartialEq)]
pub struct Trajectory {
    names: Vec<String>,
    /// `columns[j][i]`: quantity j at sample i. By column, because plots and checks read
    /// quantities, and a column is then a slice.
    columns: Vec<Vec<f64>>,
    events: Vec<EventRecord>,
    summary: Summary,
    /// The rows the producer said to expect: reserved in every column at `begin` (and then
    /// 0 again), so that recording never moves a column.
    expected_rows: usize,
}

/// A trajectory collects a simulation's samples and events in memory.
impl Sink for Trajectory {
    fn begin(&mut self, columns: &[String]) -> Result<(), Error> {
        self.names = columns.to_vec();
        let rows = std::mem::take(&mut self.expected_rows);
        self.columns = (0..columns.len())
            .map(|_| Vec::with_capacity(rows))
            .collect();
        Ok(())
    }

    fn row(&mut self, values: &[f64]) -> Result<(), Error> {
        self.push(values.iter().copied());
        Ok(())
    }

    fn event(&mut self, event: &EventRecord) -> Result<(), Error> {
        self.events.push(event.clone());
        Ok(())
    }
}

impl Trajectory {
    /// An empty trajectory with these column names (the first should be the time).
    pub(crate) fn new(names: Vec<String>, summary: Summary) -> Self {
        let columns = vec![Vec::new(); names.len()];
        Trajectory {
            names,
            columns,
            events: Vec::new(),
            summary,
            expected_rows: 0,
        }
    }

    /// An empty trajectory that expects `rows` samples (a simulation knows how many).
    pub(crate) fn expecting(rows: usize, summary: Summary) -> Self {
        Trajectory {
            expected_rows: rows,
            ..Trajectory::new(Vec::new(), summary)
        }
    }

    /// The events of the run, in time order (for a [`crate::Simulation`] with events).
    pub fn events(&self) -> &[EventRecord] {
        &self.events
    }

    /// The times of the events called `name`.
    pub fn event_times(&self, name: &str) -> Vec<f64> {
        self.events
            .iter()
            .filter(|e| e.name == name)
            .map(|e| e.t)
            .collect()
    }

    pub(crate) fn set_summary(&mut self, summary: Summary) {
        self.summary = summary;
    }

    /// Appends one sample, one value per column, in column order.
    pub(crate) fn push(&mut self, row: impl IntoIterator<Item = f64>) {
        let mut width = 0;
        for (column, value) in self.columns.iter_mut().zip(row) {
            column.push(value);
            width += 1;
        }
        debug_assert_eq!(
            width,
            self.names.len(),
            "a row must have one value per column"
        );
    }

    /// The column names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The sample times (the first column).
    pub fn times(&self) -> &[f64] {
        self.columns.first().map_or(&[], Vec::as_slice)
    }

    /// The column called `name`, if there is one.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let j = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[j])
    }

    /// Sample i as one value per column.
    pub fn row(&self, i: usize) -> Option<Vec<f64>> {
        (i < self.len()).then(|| self.columns.iter().map(|c| c[i]).collect())
    }

    /// The samples in order, each as one value per column (copied out of the columns).
    pub fn rows(&self) -> impl ExactSizeIterator<Item = Vec<f64>> + '_ {
        (0..self.len()).map(|i| self.columns.iter().map(|c| c[i]).collect())
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn summary(&self) -> &Summary {
        &self.summary
    }

    /// CSV: a header of the column names, then one line per sample. Numbers are printed in
    /// Rust's shortest form that reads back to the same `f64`, so nothing is lost; very small
    /// and very large magnitudes in exponent form (`1e-17`), which every CSV reader accepts.
    pub fn write_csv<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        writeln!(w, "{}", self.names.join(","))?;
        for i in 0..self.len() {
            for (j, column) in self.columns.iter().enumerate() {
                if j > 0 {
                    w.write_all(b",")?;
                }
                write!(w, "{:?}", column[i])?;
            }
            w.write_all(b"\n")?;
        }
        Ok(())
    }

    /// Writes the CSV to a file, whole or not at all: under a name of its own, flushed to disk
    /// and renamed to `path` (replacing a file there), then its manifest `<path>.manifest`
    /// (the row count, the size and checksum), by which a reader tells a file cut short
    /// afterwards from a shorter run ([`crate::whole_file`]). A failed write leaves what was
    /// at `path` before.
    pub fn save_csv(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        let mut file = WholeFile::create(path)?;
        self.write_csv(&mut file)
            .map_err(|e| crate::whole_file::io(path, e))?;
        file.commit(self.len() as u64)
    }
}

/// A summary, not the data: a trajectory has thousands of numbers.
impl fmt::Debug for Trajectory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let times = self.times();
        let mut s = f.debug_struct("Trajectory");
        s.field("names", &self.names).field("samples", &self.len());
        if let (Some(first), Some(last)) = (times.first(), times.last()) {
            s.field("t", &format_args!("{first}..={last}"));
        }
        s.finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary() -> Summary {
        Summary {
            steps: 12,
            rejected: 1,
            evaluations: 79,
            samples: 0,
            max_constraint_residual: 1.5e-16,
            initial_energy: 2.5,
            max_energy_drift: 3e-12,
            relative_energy_drift: 1.2e-12,
            energy_scale: EnergyScale::InitialEnergy(2.5),
            conservative: true,
            holonomic_constraints: 0,
            max_holonomic_residual: 0.0,
            work: 0.0,
            max_energy_balance: 3e-12,
            relative_energy_balance: 1.2e-12,
            stopped: None,
            singular_crossings: Vec::new(),
            symmetric_not_reversible: false,
        }
    }

    fn sample() -> Trajectory {
        let mut t = Trajectory::new(vec!["t".into(), "x".into(), "energy".into()], summary());
        t.push([0.0, 1.0, 0.5]);
        t.push([0.1, 0.1 + 0.2, -1e-20]);
        t.push([0.2, f64::NAN, 1e21]);
        t
    }

    #[test]
    fn columns_rows_and_lengths() {
        let t = sample();
        assert_eq!(t.len(), 3);
        assert!(!t.is_empty());
        assert_eq!(t.names(), ["t", "x", "energy"]);
        assert_eq!(t.times(), [0.0, 0.1, 0.2]);
        assert_eq!(t.column("energy"), Some(&[0.5, -1e-20, 1e21][..]));
        assert_eq!(t.column("y"), None);
        assert_eq!(t.row(1), Some(vec![0.1, 0.30000000000000004, -1e-20]));
        assert_eq!(t.row(3), None);
        assert_eq!(t.rows().len(), 3);
        assert_eq!(t.rows().next(), Some(vec![0.0, 1.0, 0.5]));
        let empty = Trajectory::new(vec!["t".into()], summary());
        assert!(empty.is_empty());
        assert_eq!(empty.times(), &[] as &[f64]);
    }

    #[test]
    fn csv_is_exact_and_round_trips() {
        let mut out = Vec::new();
        sample().write_csv(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "t,x,energy\n0.0,1.0,0.5\n0.1,0.30000000000000004,-1e-20\n0.2,NaN,1e21\n"
        );
        for line in text.lines().skip(1) {
            for field in line.split(',') {
                field.parse::<f64>().unwrap();
            }
        }
    }

    #[test]
    fn save_csv_names_the_path_on_failure() {
        let dir =
            std::env::temp_dir().join(format!("hamel-trajectory-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("out.csv");
        sample().save_csv(&good).unwrap();
        assert!(
            std::fs::read_to_string(&good)
                .unwrap()
                .starts_with("t,x,energy\n0.0,1.0,0.5\n")
        );

        let bad = dir.join("missing-directory").join("out.csv");
        match sample().save_csv(&bad) {
            Err(Error::Io { path, message }) => {
                assert_eq!(path, bad.display().to_string());
                assert!(!message.is_empty());
            }
            other => panic!("expected an I/O error, got {other:?}"),
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn debug_is_a_summary() {
        let mut t = Trajectory::new(vec!["t".into(), "x".into()], summary());
        for i in 0..10_000 {
            t.push([i as f64 * 1e-3, 0.123456789]);
        }
        let debug = format!("{t:?}");
        assert_eq!(
            debug,
            r#"Trajectory { names: ["t", "x"], samples: 10000, t: 0..=9.999, .. }"#
        );
    }

    #[test]
    fn summary_display_has_one_item_per_line() {
        let text = summary().to_string();
        assert_eq!(text.lines().count(), 8);
        assert!(text.starts_with("steps                    12\n"));
        assert!(text.contains("relative energy drift    1.200e-12 of |E₀|"));
        assert!(!text.contains("balance") && !text.contains("holonomic"));
        assert!(!text.contains("warning"));
    }

    #[test]
    fn summary_display_adds_the_figures_that_mean_something() {
        let holonomic = Summary {
            holonomic_constraints: 2,
            max_holonomic_residual: 4.5e-14,
            ..summary()
        };
        let text = holonomic.to_string();
        assert_eq!(text.lines().count(), 9);
        assert!(
            text.ends_with("\nmax holonomic residual   4.500e-14"),
            "{text}"
        );

        // A forced system: its energy changes, and the balance is its error.
        let forced = Summary {
            conservative: false,
            work: -1.2345678,
            max_energy_balance: 2e-13,
            relative_energy_balance: 8e-14,
            energy_scale: EnergyScale::Work(2.5),
            ..holonomic
        };
        let text = forced.to_string();
        assert_eq!(text.lines().count(), 11);
        assert!(
            text.contains("\nmax energy change        3.000e-12\n"),
            "{text}"
        );
        assert!(!text.contains("drift"), "{text}");
        assert!(
            text.ends_with(
                "max holonomic residual   4.500e-14\nwork                     -1.235\n\
                 max energy balance       2.000e-13\nrelative energy balance  8.000e-14 of the \
                 largest |work done|, 2.5"
            ),
            "{text}"
        );
    }

    #[test]
    fn an_inaccurate_energy_is_flagged() {
        // A fixed-step RK4 run with a step far too large: the issue's 1.2e6.
        let drifting = Summary {
            max_energy_drift: 3e6,
            relative_energy_drift: 1.2e6,
            ..summary()
        };
        assert!(drifting.energy_inaccurate());
        let text = drifting.to_string();
        assert!(
            text.ends_with(
                "warning: the energy's relative error, 1.200e6, exceeds 0.01: the integration \
                 is far less accurate than it looks; use a smaller step or tolerance"
            ),
            "{text}"
        );
        // A forced system is judged by its balance, not by how much its energy changed.
        let forced = Summary {
            conservative: false,
            relative_energy_drift: 17.0,
            relative_energy_balance: 3e-10,
            ..summary()
        };
        assert!(!forced.energy_inaccurate());
        assert!(
            Summary {
                relative_energy_balance: 0.5,
                ..forced
            }
            .energy_inaccurate()
        );
        assert!(!summary().energy_inaccurate());
    }

    #[test]
    fn energy_scales_take_the_largest_energy() {
        assert_eq!(
            EnergyScale::conservative(-2.0, 1.0),
            EnergyScale::InitialEnergy(2.0)
        );
        assert_eq!(
            EnergyScale::conservative(0.0, 1.0),
            EnergyScale::KineticEnergy(1.0)
        );
        assert_eq!(
            EnergyScale::forced(0.0, 0.0, 0.0),
            EnergyScale::InitialEnergy(0.0)
        );
        assert_eq!(
            EnergyScale::forced(1.0, 3.0, 2.0),
            EnergyScale::EnergyChange(3.0)
        );
        assert_eq!(EnergyScale::forced(1.0, 3.0, 4.0), EnergyScale::Work(4.0));
        assert_eq!(
            EnergyScale::KineticEnergy(1.5).to_string(),
            "the largest kinetic energy, 1.5"
        );
    }
}
