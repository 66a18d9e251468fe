//! Linearizations and LQR designs for Python: A and B as NumPy arrays, the eigenvalues, the
//! modes with their states named, the reduced linearization, and the regulator.

use numpy::{Complex64, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use hamel::control::Lqr;
use hamel::nalgebra::DMatrix;
use hamel::{Linearization, NamedValues};

use crate::errors::to_py;

/// An operating point for Python: the time, and the state and inputs by name.
type OperatingPoint<'py> = (f64, Bound<'py, PyDict>, Bound<'py, PyDict>);

/// A linearization: `hamel.Linearization` wraps it.
#[pyclass(frozen, module = "hamel")]
pub struct NativeLinearization {
    pub linearization: Linearization,
}

/// A matrix as a NumPy array (a copy: these are small).
pub fn matrix<'py>(py: Python<'py>, m: &DMatrix<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (r, c) = m.shape();
    let mut data = Vec::with_capacity(r * c);
    for i in 0..r {
        for j in 0..c {
            data.push(m[(i, j)]);
        }
    }
    PyArray1::from_vec(py, data).reshape([r, c])
}

fn complex<'py>(
    py: Python<'py>,
    values: &[hamel::nalgebra::Complex<f64>],
) -> Bound<'py, PyArray1<Complex64>> {
    let values: Vec<Complex64> = values.iter().map(|z| Complex64::new(z.re, z.im)).collect();
    PyArray1::from_vec(py, values)
}

fn named<'py>(py: Python<'py>, values: &NamedValues) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, value) in &values.0 {
        d.set_item(name, value)?;
    }
    Ok(d)
}

/// A weight matrix given from Python, square of `size`.
fn weight(
    m: PyReadonlyArray2<'_, f64>,
    name: &str,
    size: usize,
    over: &str,
) -> PyResult<DMatrix<f64>> {
    let a = m.as_array();
    if a.shape() != [size, size] {
        return Err(PyValueError::new_err(format!(
            "{name}: the weight is {}×{}; it must be {size}×{size}, over the {over}",
            a.shape()[0],
            a.shape()[1]
        )));
    }
    Ok(DMatrix::from_fn(size, size, |i, j| a[[i, j]]))
}

#[pymethods]
impl NativeLinearization {
    fn states(&self) -> Vec<String> {
        self.linearization.states().to_vec()
    }

    fn inputs(&self) -> Vec<String> {
        self.linearization.inputs().to_vec()
    }

    fn a<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.linearization.a_matrix())
    }

    fn b<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.linearization.b_matrix())
    }

    /// `(t, state dict, inputs dict)`, or None for a linearization of given matrices.
    fn operating_point<'py>(&self, py: Python<'py>) -> PyResult<Option<OperatingPoint<'py>>> {
        match self.linearization.operating_point() {
            Some(p) => Ok(Some((p.t, named(py, &p.state)?, named(py, &p.inputs)?))),
            None => Ok(None),
        }
    }

    fn eigenvalues<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<Complex64>>> {
        let values = self.linearization.eigenvalues().map_err(|e| to_py(&e))?;
        Ok(complex(py, &values))
    }

    /// `[(eigenvalue, [(state, component), ...]), ...]` in the order of the eigenvalues.
    fn modes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let modes = self.linearization.modes().map_err(|e| to_py(&e))?;
        let list = PyList::empty(py);
        for mode in modes {
            let vector: Vec<(String, Complex64)> = mode
                .vector
                .iter()
                .map(|(n, z)| (n.clone(), Complex64::new(z.re, z.im)))
                .collect();
            list.append((Complex64::new(mode.value.re, mode.value.im), vector))?;
        }
        Ok(list)
    }

    fn reduce(&self, keep: Vec<String>) -> PyResult<NativeLinearization> {
        let keep: Vec<&str> = keep.iter().map(String::as_str).collect();
        let linearization = self.linearization.reduce(&keep).map_err(|e| to_py(&e))?;
        Ok(NativeLinearization { linearization })
    }

    fn with_inputs(&self, keep: Vec<String>) -> PyResult<NativeLinearization> {
        let keep: Vec<&str> = keep.iter().map(String::as_str).collect();
        let linearization = self
            .linearization
            .with_inputs(&keep)
            .map_err(|e| to_py(&e))?;
        Ok(NativeLinearization { linearization })
    }

    /// The LQR design with the weights Q (over the states) and R (over the inputs).
    fn lqr(
        &self,
        q: PyReadonlyArray2<'_, f64>,
        r: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<NativeLqr> {
        let (n, m) = (
            self.linearization.states().len(),
            self.linearization.inputs().len(),
        );
        let q = weight(q, "Q", n, "states")?;
        let r = weight(r, "R", m, "inputs")?;
        let lqr = Lqr::new(&self.linearization, &q, &r).map_err(|e| to_py(&e))?;
        Ok(NativeLqr { lqr })
    }

    /// A and B as Rust prints them (aligned tables).
    fn text(&self) -> String {
        self.linearization.to_string()
    }
}

/// An LQR design: `hamel.Lqr` wraps it.
#[pyclass(frozen, module = "hamel")]
pub struct NativeLqr {
    pub lqr: Lqr,
}

#[pymethods]
impl NativeLqr {
    fn gain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.lqr.gain())
    }

    fn solution<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, &self.lqr.riccati().solution)
    }

    fn residual(&self) -> f64 {
        self.lqr.riccati().residual
    }

    fn closed_loop_eigenvalues<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<Complex64>> {
        complex(py, self.lqr.closed_loop_eigenvalues())
    }

    fn states(&self) -> Vec<String> {
        self.lqr.states().to_vec()
    }

    fn inputs(&self) -> Vec<String> {
        self.lqr.inputs().to_vec()
    }
}
