//! Figures of simulations and analyses, written as SVG (feature `plot`, on by default) or PNG
//! (feature `png`, which adds plotters' bitmap backend and the PNG encoder to the build;
//! without it a PNG is an [`ErrorKind::PngNotBuilt`]).
//!
//! A [`Figure`] is a grid of [`Panel`]s; a panel has a title, axis labels, a linear or
//! logarithmic y axis, any number of named [`Series`] (solid or dashed lines, or dots) and
//! at most one [`Field`], a scalar over a grid drawn as a heatmap with a colour bar (a
//! stability map: the largest real part of the eigenvalues over two parameters, its zero
//! level between blue and red). The legend goes in a corner where it hides no line and no
//! dot, or outside the plotting area where none is free ([`Legend`]); [`Panel::key`] adds
//! entries that explain a style once. [`Figure::save`] picks the format from the path's
//! extension. For a [`hamel::Trajectory`], [`time_series`], [`xy`], [`energy_drift`] and
//! [`constraint_residual`] write the usual figures in one call, and [`Panel::time_series`],
//! [`Panel::xy`], [`Panel::energy_drift`] and [`Panel::constraint_residual`] give the same
//! panels to combine into one figure; [`Panel::units`] adds the units a model states to
//! their axes ([`Units`]: `y (m)`, `t (s)`).
//!
//! Eigenvalues of a linearization against a parameter, real parts solid and imaginary
//! parts dashed in the same colour, in the manner of Meijaard et al. (2007), Figure 3:
//!
//! ```
//! use hamel::plot::{Figure, PALETTE, Panel, Series};
//!
//! let v: Vec<f64> = (0..=100).map(|i| f64::from(i) * 0.1).collect();
//! // Two made-up modes, each as (real part, imaginary part) at each speed.
//! let weave = |v: f64| (2.0 - 0.6 * v, (1.0 + v).sqrt());
//! let capsize = |v: f64| (-0.02 * v, 0.0);
//! let mut panel = Panel::new("eigenvalues against speed")
//!     .x_label("speed v (m/s)")
//!     .y_label("eigenvalue λ (1/s)")
//!     .y_range(-10.0, 10.0);
//! for (i, (name, mode)) in [("weave", weave as fn(f64) -> (f64, f64)), ("capsize", capsize)]
//!     .into_iter()
//!     .enumerate()
//! {
//!     let (re, im): (Vec<f64>, Vec<f64>) = v.iter().map(|&v| mode(v)).unzip();
//!     panel = panel
//!         .series(Series::line(format!("Re λ {name}"), &v, &re).color(PALETTE[i]))
//!         .series(Series::dashed(format!("Im λ {name}"), &v, &im).color(PALETTE[i]));
//! }
//! let svg = Figure::from(panel).to_svg()?;
//! assert!(svg.starts_with("<svg") && svg.contains("Im λ weave"));
//! # Ok::<(), hamel::plot::PlotError>(())
//! ```
//!
//! A mobile robot's run in one figure: its path, its pitch and its energy drift, the axes
//! labelled with the units the model states.
//!
//! ```no_run
//! use hamel::models::MobileRobot;
//! use hamel::plot::{Figure, Panel, Units};
//!
//! # fn demo(run: &hamel::Trajectory) -> Result<(), hamel::Error> {
//! let units = Units::of::<MobileRobot>();
//! Figure::new()
//!     .columns(3)
//!     .panel(Panel::xy(run, "x", "y")?.units(&units))
//!     .panel(Panel::time_series(run, &["alpha"])?.units(&units))
//!     .panel(Panel::energy_drift(run)?.units(&units))
//!     .save("mobile_robot.png")?;
//! # Ok(())
//! # }
//! ```
//!
//! # What is drawn, and the errors
//!
//! Points with a non-finite coordinate, and on a logarithmic axis points with y ≤ 0, are
//! left out, and lines are broken there (see [`Panel`]); nothing else is ever skipped or
//! changed, and no NaN reaches a file. Every failure is a [`PlotError`]: I/O, an unknown
//! extension, a figure, panel or series without data, x and y of different lengths, a
//! panel with nothing left to draw, an invalid range or size, an unknown column. A
//! [`PlotError`] converts into [`hamel::Error::Io`], so `?` works in functions returning
//! `hamel::Error`.
//!
//! # Fonts
//!
//! SVG text is left to the viewer's sans-serif font. PNG text is drawn with DejaVu Sans,
//! bundled in the library (`hamel-plot/src/font/`, with its licence): no font of the system is
//! read, and nothing but the file written touches the disk. The glyphs of a line are set on
//! one baseline at their exact pen positions (plotters' own bitmap text rounds each glyph's
//! offset on its own, which raised a decimal point by a pixel: "0·04").
//!
//! [`hamel::Trajectory`]: hamel_runtime::Trajectory
//! [`hamel::Error::Io`]: hamel_runtime::Error::Io

mod axis;
mod colorbar;
mod error;
mod field;
mod figure;
mod heatmap;
mod legend;
mod modes;
mod prepare;
mod render;
#[cfg(feature = "png")]
mod text;
mod trajectory;
mod units;

pub use error::{ErrorKind, PlotError};
pub use field::{ColorScale, Field, NO_VALUE};
pub use figure::{Figure, Format, Legend, PALETTE, PANEL_SIZE, Panel, Rgb, Scale, Series, Style};
pub use trajectory::{constraint_residual, energy_drift, time_series, xy};
pub use units::Units;

#[cfg(test)]
mod tests;
