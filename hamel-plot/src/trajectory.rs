//! Panels and figures of a [`Trajectory`]'s columns, labelled with the columns' names.

use std::path::Path;

use super::error::{ErrorKind, PlotError};
use super::figure::{Figure, Panel};
use hamel_runtime::{HamelSystem, Trajectory, Vector};

/// The column called `name`, or an error that lists the trajectory's columns.
fn column<'a>(trajectory: &'a Trajectory, name: &str) -> Result<&'a [f64], PlotError> {
    trajectory.column(name).ok_or_else(|| {
        ErrorKind::UnknownColumn {
            name: name.to_string(),
            known: trajectory.names().join(", "),
        }
        .into()
    })
}

/// The name of the time column (the first), `t` for a simulation's trajectory.
fn time_name(trajectory: &Trajectory) -> &str {
    trajectory.names().first().map_or("t", String::as_str)
}

impl Panel {
    /// The columns `names` against time, one line each, in one panel titled and labelled
    /// with their names.
    ///
    /// ```
    /// use hamel::models::KnifeEdge;
    /// use hamel::plot::Panel;
    /// use hamel::{DormandPrince, HamelSystem, Simulation};
    ///
    /// let skate = KnifeEdge::default();
    /// let x0 = skate.state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 0.5])?;
    /// let run = Simulation::new(&skate, x0)
    ///     .end_time(2.0)
    ///     .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
    /// let panel = Panel::time_series(&run, &["v", "omega"])?;
    /// assert_eq!(panel.series_list().len(), 2);
    /// assert!(Panel::time_series(&run, &["speed"]).is_err()); // no such column
    /// # Ok::<(), hamel::Error>(())
    /// ```
    pub fn time_series(trajectory: &Trajectory, names: &[&str]) -> Result<Panel, PlotError> {
        let joined = names.join(", ");
        let t = time_name(trajectory);
        if names.is_empty() {
            let panel = format!("no columns against {t}");
            return Err(ErrorKind::NoSeries { panel }.into());
        }
        let mut panel = Panel::new(format!("{joined} against {t}"))
            .x_label(t)
            .y_label(joined)
            .quantities(&[t], names);
        for name in names {
            panel = panel.line(*name, trajectory.times(), column(trajectory, name)?);
        }
        Ok(panel)
    }

    /// Column `y` against column `x`, in equal scales: for `x` and `y` the coordinates of a
    /// point in the plane, its path.
    pub fn xy(trajectory: &Trajectory, x: &str, y: &str) -> Result<Panel, PlotError> {
        let (xs, ys) = (column(trajectory, x)?, column(trajectory, y)?);
        Ok(Panel::new(format!("{y} against {x}"))
            .x_label(x)
            .y_label(y)
            .quantities(&[x], &[y])
            .equal_aspect()
            .line(format!("({x}, {y})"), xs, ys))
    }

    /// The energy drift |E − E₀| against time on a logarithmic axis, from the column
    /// `energy`; with it, for a system on which forces do work, |E − E₀ − W| from the column
    /// `energy_balance` (the integration's error in the energy balance). The first sample,
    /// where the drift is 0, cannot be shown on the logarithmic axis and is left out.
    pub fn energy_drift(trajectory: &Trajectory) -> Result<Panel, PlotError> {
        let energy = column(trajectory, "energy")?;
        let e0 = energy.first().copied().unwrap_or(f64::NAN);
        let drift: Vec<f64> = energy.iter().map(|e| (e - e0).abs()).collect();
        let t = trajectory.times();
        let time = time_name(trajectory);
        let mut panel = Panel::new("energy drift")
            .x_label(time)
            .y_label("energy error")
            .quantities(&[time], &["energy"])
            .log_y()
            .line("|E − E₀|", t, &drift);
        if let Some(balance) = trajectory.column("energy_balance") {
            let error: Vec<f64> = balance.iter().map(|b| b.abs()).collect();
            panel = panel.line("|E − E₀ − W|", t, &error);
        }
        Ok(panel)
    }
}

impl Panel {
    /// The constraint residual against time on a logarithmic axis: at each sample, the
    /// largest |A_c(q, t) q̇ + a_c(q, t)| over the constraint rows, with q̇ from the recorded
    /// state (and, for a system with holonomic constraints, the largest |f(t, q)|), beside the
    /// rounding level ε·max(1, max|q̇|) as a dashed line. Hamel's reduced state satisfies the
    /// velocity constraints by construction, so the residual stays at that level for a sound
    /// model; samples where it is exactly 0 cannot be shown on the axis and are left out.
    ///
    /// The trajectory must have `system`'s state columns (a run of it).
    ///
    /// ```
    /// use hamel::models::KnifeEdge;
    /// use hamel::plot::Panel;
    /// use hamel::{DormandPrince, HamelSystem, Simulation};
    ///
    /// let skate = KnifeEdge::default();
    /// let x0 = skate.state_from_speeds(0.0, &[0.0, 0.0, 0.0], &[1.0, 0.5])?;
    /// let run = Simulation::new(&skate, x0)
    ///     .end_time(2.0)
    ///     .run_constant(&DormandPrince::new(1e-8, 1e-10), [])?;
    /// let panel = Panel::constraint_residual(&skate, &run)?;
    /// assert_eq!(panel.series_list().len(), 2); // the residual and the rounding level
    /// # Ok::<(), hamel::Error>(())
    /// ```
    pub fn constraint_residual<S: HamelSystem>(
        system: &S,
        trajectory: &Trajectory,
    ) -> Result<Panel, PlotError> {
        let columns = S::STATE
            .iter()
            .map(|name| column(trajectory, name))
            .collect::<Result<Vec<_>, _>>()?;
        let t = trajectory.times();
        let (mut residual, mut holonomic, mut rounding) = (Vec::new(), Vec::new(), Vec::new());
        let mut x = S::State::zeros();
        for (i, &ti) in t.iter().enumerate() {
            for (xj, c) in x.as_mut().iter_mut().zip(&columns) {
                *xj = c[i];
            }
            let q = S::coordinates_of(&x);
            // A state where the velocities cannot be formed is left out (NaN), as the run
            // that recorded it would have stopped there.
            let (r, scale) = match system.generalized_velocities(ti, &x) {
                Ok(qd) => (
                    max_abs(system.constraint_residual(ti, &q, &qd).as_ref()),
                    max_abs(qd.as_ref()).max(1.0),
                ),
                Err(_) => (f64::NAN, f64::NAN),
            };
            residual.push(r);
            rounding.push(f64::EPSILON * scale);
            holonomic.push(max_abs(system.holonomic_residual(ti, &q).as_ref()));
        }
        let time = time_name(trajectory);
        let mut panel = Panel::new("constraint residual")
            .x_label(time)
            .y_label("residual")
            .quantities(&[time], &[])
            .log_y()
            .line("max |A_c q̇ + a_c|", t, &residual);
        if S::K > 0 {
            panel = panel.line("max |f(t, q)|", t, &holonomic);
        }
        Ok(panel.dashed("ε·max(1, |q̇|)", t, &rounding))
    }
}

fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(
        0.0,
        |m, v| if v.is_nan() { f64::NAN } else { m.max(v.abs()) },
    )
}

/// Writes the columns `names` against time ([`Panel::time_series`]) to `path`, `.svg` or
/// `.png`.
///
/// ```no_run
/// # fn demo(trajectory: &hamel::Trajectory) -> Result<(), hamel::Error> {
/// hamel::plot::time_series(trajectory, &["alpha"], "pitch.svg")?;
/// # Ok(())
/// # }
/// ```
pub fn time_series(
    trajectory: &Trajectory,
    names: &[&str],
    path: impl AsRef<Path>,
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let panel = Panel::time_series(trajectory, names).map_err(|e| e.at(path))?;
    Figure::from(panel).save(path)
}

/// Writes column `y` against column `x` ([`Panel::xy`]) to `path`, `.svg` or `.png`.
///
/// ```no_run
/// # fn demo(trajectory: &hamel::Trajectory) -> Result<(), hamel::Error> {
/// hamel::plot::xy(trajectory, "x", "y", "path.png")?;
/// # Ok(())
/// # }
/// ```
pub fn xy(
    trajectory: &Trajectory,
    x: &str,
    y: &str,
    path: impl AsRef<Path>,
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let panel = Panel::xy(trajectory, x, y).map_err(|e| e.at(path))?;
    Figure::from(panel).save(path)
}

/// Writes the energy drift ([`Panel::energy_drift`]) to `path`, `.svg` or `.png`.
///
/// ```no_run
/// # fn demo(trajectory: &hamel::Trajectory) -> Result<(), hamel::Error> {
/// hamel::plot::energy_drift(trajectory, "energy.svg")?;
/// # Ok(())
/// # }
/// ```
pub fn energy_drift(trajectory: &Trajectory, path: impl AsRef<Path>) -> Result<(), PlotError> {
    let path = path.as_ref();
    let panel = Panel::energy_drift(trajectory).map_err(|e| e.at(path))?;
    Figure::from(panel).save(path)
}

/// Writes the constraint residual ([`Panel::constraint_residual`]) to `path`, `.svg` or
/// `.png`.
///
/// ```no_run
/// # fn demo(robot: &hamel::models::MobileRobot, run: &hamel::Trajectory) -> Result<(), hamel::Error> {
/// hamel::plot::constraint_residual(robot, run, "residual.svg")?;
/// # Ok(())
/// # }
/// ```
pub fn constraint_residual<S: HamelSystem>(
    system: &S,
    trajectory: &Trajectory,
    path: impl AsRef<Path>,
) -> Result<(), PlotError> {
    let path = path.as_ref();
    let panel = Panel::constraint_residual(system, trajectory).map_err(|e| e.at(path))?;
    Figure::from(panel).save(path)
}
