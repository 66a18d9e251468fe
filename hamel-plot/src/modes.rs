//! A [`ModeSweep`]'s eigenvalues against its parameter, each mode by its name.

use super::figure::{PALETTE, Panel, Series, Style};
use hamel_runtime::{Crossing, ModeSweep};

impl Panel {
    /// The eigenvalues of `sweep` against its parameter, in the manner of Meijaard et al.'s
    /// Figure 3: each named mode in a colour of its own (the branches that share a name, a
    /// conjugate pair, share it and one entry of the legend), its real part solid and |Im λ|
    /// dashed where it oscillates; `crossings` (from [`ModeSweep::crossings`] or the ends of
    /// [`ModeSweep::stable_ranges`]) marked on the axis.
    ///
    /// ```
    /// use hamel::models::WhippleBicycle;
    /// use hamel::plot::{Figure, Panel};
    /// use hamel::{Error, HamelSystem, ModeSweep};
    ///
    /// // The benchmark bicycle's lateral modes over 0 … 10 m/s; the two least stable at
    /// // 0 m/s, real there, become the weave, a complex pair above 0.68 m/s.
    /// let bike = WhippleBicycle::default();
    /// let lateral = |v: f64| {
    ///     let x = bike.state_builder().set("rear_wheel_rate", -v / bike.r_r).build()?;
    ///     bike.linearize(0.0, &x, &[0.0, 0.0])?.reduce(&["phi", "delta", "roll_rate", "steer_rate"])
    /// };
    /// let speeds = (0..=20).map(|i| 0.5 * f64::from(i));
    /// let sweep = ModeSweep::track("v", speeds, &lateral)?.name(0, "weave")?.name(1, "weave")?;
    /// let stable = &sweep.stable_ranges(&lateral)?[0];
    /// let ends = [stable.opens.clone().unwrap(), stable.closes.clone().unwrap()];
    /// let panel = Panel::modes(&sweep, &ends);
    /// // Per name a solid line of Re λ (and |Im λ| dashed where it oscillates), and the ends.
    /// assert_eq!(panel.series_list().len(), 5);
    /// let svg = Figure::from(panel).to_svg().unwrap();
    /// assert!(svg.contains("weave") && svg.contains("mode_3"));
    /// assert!(sweep.branch("weave").unwrap().modes()[20].value.im != 0.0);
    /// # Ok::<(), Error>(())
    /// ```
    pub fn modes(sweep: &ModeSweep, crossings: &[Crossing]) -> Panel {
        let p = sweep.parameter();
        let mut panel = Panel::new(format!("Eigenvalues against {p}"))
            .x_label(p)
            .y_label("eigenvalue λ");
        let mut names: Vec<&String> = Vec::new();
        for name in sweep.names() {
            if !names.contains(&name) {
                names.push(name);
            }
        }
        for (k, name) in names.into_iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            // The branches of one name in one series each for Re and |Im|, broken between
            // branches (NaN), |Im| only where it is not zero.
            let (mut x, mut re, mut im) = (Vec::new(), Vec::new(), Vec::new());
            let mut oscillates = false;
            for (branch, _) in sweep
                .branches()
                .iter()
                .zip(sweep.names())
                .filter(|(_, n)| *n == name)
            {
                x.extend_from_slice(branch.parameters());
                re.extend(branch.eigenvalues().map(|l| l.re));
                im.extend(
                    branch
                        .eigenvalues()
                        .map(|l| if l.im == 0.0 { f64::NAN } else { l.im.abs() }),
                );
                oscillates |= branch.eigenvalues().any(|l| l.im != 0.0);
                x.push(f64::NAN);
                re.push(f64::NAN);
                im.push(f64::NAN);
            }
            panel = panel.series(Series::line(name.as_str(), &x, &re).color(color));
            if oscillates {
                panel = panel.series(Series::dashed("", &x, &im).color(color));
            }
        }
        if sweep
            .branches()
            .iter()
            .any(|b| b.eigenvalues().any(|l| l.im != 0.0))
        {
            panel = panel
                .key("Re λ", Style::Line, super::figure::Rgb(0, 0, 0))
                .key("|Im λ|", Style::Dashed, super::figure::Rgb(0, 0, 0));
        }
        if !crossings.is_empty() {
            let at: Vec<f64> = crossings.iter().map(|c| c.parameter).collect();
            let label = crossings
                .iter()
                .map(|c| {
                    format!(
                        "{} {} at {p} = {:.6}",
                        c.name,
                        if c.destabilizing { "grows" } else { "decays" },
                        c.parameter
                    )
                })
                .collect::<Vec<_>>()
                .join("; ");
            panel = panel.series(
                Series::points(label, &at, &vec![0.0; at.len()]).color(super::figure::Rgb(0, 0, 0)),
            );
        }
        panel
    }
}
