//! Axes: ticks at round values (1, 2 or 5 × 10ᵏ on a linear axis, powers of ten on a
//! logarithmic one) and how their values are written.

use super::prepare::inside;

/// One axis: its range and ticks in the plot's coordinates (log₁₀ of the value on a
/// logarithmic axis), and how tick values are written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Axis {
    pub lo: f64,
    pub hi: f64,
    /// Labelled ticks, with a grid line each.
    pub ticks: Vec<f64>,
    /// Unlabelled ticks (a lighter grid): 2×, 3×, … between decades on a log axis.
    pub minor: Vec<f64>,
    labels: Labels,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Labels {
    /// `-0.25`: this many decimals.
    Fixed(usize),
    /// `1.5e-7`: the mantissa with this many decimals, relative to 10^exponent.
    Scientific { exponent: i32, decimals: usize },
    /// `10⁻³`, `2×10⁻³`: the tick is log₁₀ of the value.
    Log,
}

/// A linear axis over `range` with about `target` ticks at 1, 2 or 5 × 10ᵏ steps.
pub(crate) fn linear_axis(range: (f64, f64), target: usize) -> Axis {
    let (lo, hi) = range;
    let raw = (hi - lo) / target as f64;
    let exponent = raw.log10().floor() as i32;
    let magnitude = 10f64.powi(exponent);
    let (mantissa, exponent) = match raw / magnitude {
        m if m <= 1.0 => (1.0, exponent),
        m if m <= 2.0 => (2.0, exponent),
        m if m <= 5.0 => (5.0, exponent),
        _ => (1.0, exponent + 1),
    };
    let step = mantissa * 10f64.powi(exponent);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    let ticks = (first..=last)
        .map(|k| k as f64 * step)
        // k·step for k = 0 is exactly 0, never -0 or 1e-17.
        .collect();
    let largest = lo.abs().max(hi.abs());
    let order = largest.log10().floor() as i32;
    let labels = if largest > 0.0 && !(-3..6).contains(&order) {
        Labels::Scientific {
            exponent: order,
            decimals: (order - exponent).max(0) as usize,
        }
    } else {
        Labels::Fixed((-exponent).max(0) as usize)
    };
    Axis {
        lo,
        hi,
        ticks,
        minor: Vec::new(),
        labels,
    }
}

/// A logarithmic axis over `range` (log₁₀ of the values): ticks at powers of ten, every
/// decade or every few, with unlabelled 2×…9× ticks between when every decade is labelled;
/// over less than two decades, ticks at 1, 2 and 5 × 10ᵏ, or at whatever a linear axis
/// would choose when even those are too few.
pub(crate) fn log_axis(range: (f64, f64), target: usize) -> Axis {
    let (lo, hi) = range;
    let (first, last) = (lo.ceil() as i64, hi.floor() as i64);
    let decades = last - first + 1;
    let within = |v: &f64| inside(*v, range);
    let (ticks, minor) = if decades >= 2 {
        let every = (decades as usize).div_ceil(target).max(1) as i64;
        let ticks: Vec<f64> = (first..=last)
            .filter(|k| k % every == 0)
            .map(|k| k as f64)
            .collect();
        let minor = if every == 1 {
            let between = (first - 1..=last)
                .flat_map(|k| (2..10).map(move |m| k as f64 + f64::from(m).log10()));
            between.filter(within).collect()
        } else {
            (first..=last)
                .filter(|k| k % every != 0)
                .map(|k| k as f64)
                .collect()
        };
        (ticks, minor)
    } else {
        let candidates = |mantissas: &'static [u32]| -> Vec<f64> {
            (first - 1..=last + 1)
                .flat_map(|k| {
                    mantissas
                        .iter()
                        .map(move |&m| k as f64 + f64::from(m).log10())
                })
                .filter(within)
                .collect()
        };
        let mut ticks = candidates(&[1, 2, 5]);
        if ticks.len() < 2 {
            ticks = candidates(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
        }
        if ticks.len() < 2 {
            let linear = linear_axis((10f64.powf(lo), 10f64.powf(hi)), target);
            ticks = linear
                .ticks
                .iter()
                .filter(|&&v| v > 0.0)
                .map(|v| v.log10())
                .collect();
        }
        (ticks, Vec::new())
    };
    Axis {
        lo,
        hi,
        ticks,
        minor,
        labels: Labels::Log,
    }
}

impl Axis {
    /// The label of the tick at `v` (in the plot's coordinates).
    pub fn label(&self, v: f64) -> String {
        match self.labels {
            Labels::Fixed(decimals) => plain(v, decimals),
            Labels::Scientific { exponent, decimals } => {
                if v == 0.0 {
                    "0".to_string()
                } else {
                    format!("{}e{exponent}", plain(v / 10f64.powi(exponent), decimals))
                }
            }
            Labels::Log => power_of_ten(v),
        }
    }
}

/// `v` with `decimals` decimals, never `-0`.
fn plain(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// 10^`exponent` as `10⁻³`, `2×10⁻³` or `2.5×10⁻³` (three significant digits at most).
fn power_of_ten(exponent: f64) -> String {
    let mut k = exponent.floor();
    let mut mantissa = 10f64.powf(exponent - k);
    // 10^(log10 2) may come out as 1.9999999: round the mantissa to 3 digits first.
    mantissa = (mantissa * 100.0).round() / 100.0;
    if mantissa >= 10.0 {
        mantissa /= 10.0;
        k += 1.0;
    }
    let power = format!("10{}", superscript(k as i64));
    if mantissa == 1.0 {
        power
    } else {
        let m = format!("{mantissa:.2}");
        format!("{}×{power}", m.trim_end_matches('0').trim_end_matches('.'))
    }
}

/// An integer in superscript digits: `⁻¹²`.
fn superscript(n: i64) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

/// `v` with three significant digits at most, trailing zeros dropped (`0.05`, `-1.5`, `600`),
/// in scientific notation beyond 10⁵ or below 10⁻³ (`2.5e-5`), and never `-0`: for values
/// that are not on a common grid, such as a colour bar's.
pub(crate) fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v.is_finite() {
            "0".to_string()
        } else {
            v.to_string()
        };
    }
    let order = v.abs().log10().floor() as i32;
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if (-3..5).contains(&order) {
        let decimals = (2 - order).max(0) as usize;
        trim(plain(v, decimals))
    } else {
        let mantissa = trim(plain(v / 10f64.powi(order), 2));
        format!("{mantissa}e{order}")
    }
}
