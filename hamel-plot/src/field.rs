//! A scalar field over a grid, drawn as a heatmap with a colour bar ([`Field`]): its colour
//! scale, centred on a level such as a stability boundary, and its contour lines.

use std::collections::HashMap;

use super::figure::{Rgb, Series};

/// ColorBrewer's diverging "RdBu" scheme (Cynthia Brewer, colorbrewer2.org; readable by
/// colour-blind readers and in greyscale), 11 classes, from the lowest value (dark blue)
/// through the centre (near white) to the highest (dark red).
const RD_BU: [Rgb; 11] = [
    Rgb(5, 48, 97),
    Rgb(33, 102, 172),
    Rgb(67, 147, 195),
    Rgb(146, 197, 222),
    Rgb(209, 229, 240),
    Rgb(247, 247, 247),
    Rgb(253, 219, 199),
    Rgb(244, 165, 130),
    Rgb(214, 96, 77),
    Rgb(178, 24, 43),
    Rgb(103, 0, 31),
];

/// The colour of a cell without a value (NaN): a mid grey, which the scale never gives.
pub const NO_VALUE: Rgb = Rgb(150, 150, 150);

/// A scalar field sampled on a grid — `values[j * x.len() + i]` at (x\[i\], y\[j\]) — drawn as
/// a heatmap: each sample fills the cell around it (out to the midpoints between grid
/// values, and half a step beyond the first and last), in a diverging colour scale with a
/// colour bar beside the plot.
///
/// The scale is centred on a level (by default 0), drawn near white: values below it run
/// to dark blue at the lowest, values above it to dark red at the highest, each side over
/// its own span (like matplotlib's `TwoSlopeNorm`), so that where the field crosses the
/// level — for the largest real part of a system's eigenvalues, the stability boundary —
/// stands out whatever the spans of the two sides; [`ColorScale::SymLog`] makes small
/// values on either side stand out too. The colour bar gives each side half its length,
/// with its values marked. [`Field::range`] fixes the span (values beyond it take the end
/// colours); cells without a value (NaN) are drawn grey ([`NO_VALUE`]).
///
/// [`Field::contour`] gives the lines where the field crosses a level, and
/// [`Field::contour_series`] the same as a [`Series`] to draw on the heatmap.
///
/// ```
/// use hamel::plot::{Field, Figure, Panel};
///
/// // Re λ of ẍ + c ẋ + k x = 0 (the larger root's real part) over damping c and stiffness k.
/// let c: Vec<f64> = (0..=40).map(|i| -1.0 + 0.05 * f64::from(i)).collect();
/// let k: Vec<f64> = (0..=30).map(|i| -1.0 + 0.1 * f64::from(i)).collect();
/// let abscissa = |c: f64, k: f64| {
///     let d = c * c - 4.0 * k;
///     if d < 0.0 { -c / 2.0 } else { (-c + d.sqrt()) / 2.0 }
/// };
/// let field = Field::from_fn("largest Re λ (1/s)", &c, &k, abscissa);
/// let boundary = field.contour_series("Re λ = 0", 0.0);
/// let panel = Panel::new("stability of ẍ + c ẋ + k x = 0")
///     .x_label("damping c (1/s)")
///     .y_label("stiffness k (1/s²)")
///     .field(field)
///     .series(boundary);
/// let svg = Figure::from(panel).to_svg()?;
/// assert!(svg.contains("largest Re λ (1/s)") && svg.contains("Re λ = 0"));
/// # Ok::<(), hamel::plot::PlotError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    label: String,
    x: Vec<f64>,
    y: Vec<f64>,
    values: Vec<f64>,
    center: f64,
    range: Option<(f64, f64)>,
    scale: ColorScale,
}

/// How a [`Field`]'s values map onto its colours, on each side of the centre c separately
/// (each side spans its own range: the lowest value takes the darkest blue, the highest the
/// darkest red).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum ColorScale {
    /// Colour in proportion to the distance from the centre.
    #[default]
    Linear,
    /// Colour in proportion to the distance from the centre within `linear` of it, and to
    /// the logarithm of the distance beyond (matplotlib's `SymLogNorm`): for values that
    /// span decades on either side, such as growth rates, so that a small value reads
    /// clearly on the side it is on. `linear` must be a positive number.
    SymLog {
        /// The distance from the centre within which the scale is linear.
        linear: f64,
    },
}

impl Field {
    /// The field with these values, `values[j * x.len() + i]` at (x\[i\], y\[j\]): row by row
    /// along y. `label` names it on the colour bar (with its unit). The grid must be finite
    /// and increasing along each axis, and there must be a value per grid point; this is
    /// checked when the figure is drawn.
    pub fn new(label: impl Into<String>, x: &[f64], y: &[f64], values: &[f64]) -> Field {
        Field {
            label: label.into(),
            x: x.to_vec(),
            y: y.to_vec(),
            values: values.to_vec(),
            center: 0.0,
            range: None,
            scale: ColorScale::Linear,
        }
    }

    /// The field f(x, y) at every grid point.
    pub fn from_fn(
        label: impl Into<String>,
        x: &[f64],
        y: &[f64],
        mut f: impl FnMut(f64, f64) -> f64,
    ) -> Field {
        let values: Vec<f64> = y
            .iter()
            .flat_map(|&yj| x.iter().map(move |&xi| (xi, yj)))
            .map(|(xi, yj)| f(xi, yj))
            .collect();
        Field::new(label, x, y, &values)
    }

    /// The value drawn in the scale's middle colour (by default 0).
    pub fn center(mut self, level: f64) -> Field {
        self.center = level;
        self
    }

    /// The colours span `lo` to `hi` (which must hold the centre) instead of the values'
    /// extent; values beyond take the end colours.
    pub fn range(mut self, lo: f64, hi: f64) -> Field {
        self.range = Some((lo, hi));
        self
    }

    /// How values map onto colours (by default linearly on each side of the centre).
    pub fn scale(mut self, scale: ColorScale) -> Field {
        self.scale = scale;
        self
    }

    /// The label on the colour bar.
    pub fn label(&self) -> &str {
        &self.label
    }

    /// The grid along x.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// The grid along y.
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// The value at (x\[i\], y\[j\]), or `None` outside the grid.
    pub fn value(&self, i: usize, j: usize) -> Option<f64> {
        (i < self.x.len())
            .then(|| self.values.get(j * self.x.len() + i).copied())
            .flatten()
    }

    pub(crate) fn values(&self) -> &[f64] {
        &self.values
    }

    pub(crate) fn center_level(&self) -> f64 {
        self.center
    }

    pub(crate) fn given_range(&self) -> Option<(f64, f64)> {
        self.range
    }

    pub(crate) fn color_scale(&self) -> ColorScale {
        self.scale
    }

    /// The lines where the field crosses `level`, by marching squares on the grid (linear
    /// interpolation along the cells' edges; a cell whose corners alternate takes the
    /// connection its centre's mean value gives): each a polyline of (x, y) points, closed
    /// (its last point its first) when it closes within the grid. Cells with a NaN corner
    /// are left out, so a line ends at them.
    pub fn contour(&self, level: f64) -> Vec<Vec<(f64, f64)>> {
        let (nx, ny) = (self.x.len(), self.y.len());
        if nx < 2 || ny < 2 || self.values.len() != nx * ny {
            return Vec::new();
        }
        let mut segments: Vec<(Edge, Edge)> = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                segments.extend(self.cell_segments(i, j, level));
            }
        }
        join(&segments)
            .into_iter()
            .map(|chain| chain.iter().map(|e| self.crossing(*e, level)).collect())
            .collect()
    }

    /// The field's crossings of `level` ([`Field::contour`]) as one series, the lines
    /// separated by gaps, drawn as a solid line.
    pub fn contour_series(&self, name: impl Into<String>, level: f64) -> Series {
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for line in self.contour(level) {
            if !xs.is_empty() {
                xs.push(f64::NAN);
                ys.push(f64::NAN);
            }
            for (x, y) in line {
                xs.push(x);
                ys.push(y);
            }
        }
        Series::line(name, &xs, &ys)
    }

    /// The value at grid point (i, j).
    fn at(&self, i: usize, j: usize) -> f64 {
        self.values[j * self.x.len() + i]
    }

    /// The contour's pieces in the cell from (i, j) to (i + 1, j + 1), as pairs of edges.
    fn cell_segments(&self, i: usize, j: usize, level: f64) -> Vec<(Edge, Edge)> {
        // Corners counter-clockwise from the lower left, and the edge after each.
        let corners = [
            self.at(i, j),
            self.at(i + 1, j),
            self.at(i + 1, j + 1),
            self.at(i, j + 1),
        ];
        if corners.iter().any(|v| v.is_nan()) {
            return Vec::new();
        }
        let edges = [
            Edge::Along(i, j),
            Edge::Across(i + 1, j),
            Edge::Along(i, j + 1),
            Edge::Across(i, j),
        ];
        let above: Vec<bool> = corners.iter().map(|&v| v > level).collect();
        let crossed: Vec<usize> = (0..4).filter(|&k| above[k] != above[(k + 1) % 4]).collect();
        match crossed.len() {
            2 => vec![(edges[crossed[0]], edges[crossed[1]])],
            4 => {
                // A saddle: the centre's mean decides which corners join across it.
                let mean = corners.iter().sum::<f64>() / 4.0;
                if (mean > level) == above[0] {
                    vec![(edges[0], edges[1]), (edges[2], edges[3])]
                } else {
                    vec![(edges[3], edges[0]), (edges[1], edges[2])]
                }
            }
            _ => Vec::new(),
        }
    }

    /// Where the field crosses `level` on `edge`, by linear interpolation.
    fn crossing(&self, edge: Edge, level: f64) -> (f64, f64) {
        let ((i0, j0), (i1, j1)) = match edge {
            Edge::Along(i, j) => ((i, j), (i + 1, j)),
            Edge::Across(i, j) => ((i, j), (i, j + 1)),
        };
        let (a, b) = (self.at(i0, j0), self.at(i1, j1));
        let t = ((level - a) / (b - a)).clamp(0.0, 1.0);
        let lerp = |p: f64, q: f64| p + t * (q - p);
        (lerp(self.x[i0], self.x[i1]), lerp(self.y[j0], self.y[j1]))
    }
}

/// A grid edge a contour crosses: `Along(i, j)` from (i, j) to (i + 1, j), `Across(i, j)`
/// from (i, j) to (i, j + 1). Two cells sharing an edge find the same crossing there, so
/// their pieces join exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Edge {
    Along(usize, usize),
    Across(usize, usize),
}

/// The segments joined end to end into chains, in a deterministic order: each chain starts
/// at an open end when it has one, and a closed chain repeats its first edge at its end.
fn join(segments: &[(Edge, Edge)]) -> Vec<Vec<Edge>> {
    let mut at: HashMap<Edge, Vec<usize>> = HashMap::new();
    for (k, (a, b)) in segments.iter().enumerate() {
        at.entry(*a).or_default().push(k);
        at.entry(*b).or_default().push(k);
    }
    let mut used = vec![false; segments.len()];
    let mut chains = Vec::new();
    // Open chains first, from their ends (an edge with one segment), then the closed ones.
    let open_ends = segments
        .iter()
        .enumerate()
        .flat_map(|(k, (a, b))| [(k, *a), (k, *b)])
        .filter(|(_, e)| at[e].len() == 1);
    let starts: Vec<(usize, Edge)> = open_ends
        .chain(segments.iter().enumerate().map(|(k, (a, _))| (k, *a)))
        .collect();
    for (first, start) in starts {
        if used[first] {
            continue;
        }
        let mut chain = vec![start];
        let (mut segment, mut end) = (first, start);
        loop {
            used[segment] = true;
            let (a, b) = segments[segment];
            end = if a == end { b } else { a };
            chain.push(end);
            match at[&end].iter().find(|&&k| !used[k]) {
                Some(&next) => segment = next,
                None => break,
            }
        }
        chains.push(chain);
    }
    chains
}

/// The colour at position `p` of the diverging scheme: −1 darkest blue, 0 its middle (near
/// white), 1 darkest red; NaN is [`NO_VALUE`].
pub(crate) fn rd_bu(p: f64) -> Rgb {
    if p.is_nan() {
        return NO_VALUE;
    }
    let position = (p.clamp(-1.0, 1.0) + 1.0) / 2.0 * (RD_BU.len() - 1) as f64;
    let k = (position.floor() as usize).min(RD_BU.len() - 2);
    let f = position - k as f64;
    let (a, b) = (RD_BU[k], RD_BU[k + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + f * (f64::from(q) - f64::from(p))).round() as u8;
    Rgb(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}
