//! `articula.Model.from_urdf(path)`: a robot's `rnea`, `crba` and `aba` on numpy arrays, one
//! state per row (a 1-D array is one state).

use crate::to_py;
use articula_core::dynamics::{self, Workspace};
use articula_core::model::urdf::UrdfOptions;
use articula_core::pipeline::{self, ModelSource, TakeOptions};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;

/// A robot model (immutable), as `articula id --urdf` builds it.
#[pyclass(frozen, module = "articula")]
pub struct Model {
    model: articula_core::model::Model,
}

/// An argument as rows of `width` numbers: the rows, and whether it was 1-D.
struct Rows {
    data: Vec<f64>,
    rows: usize,
    one: bool,
}

fn rows(py: Python<'_>, x: &Bound<'_, PyAny>, width: usize, what: &str) -> PyResult<Rows> {
    let array = py
        .import("numpy")?
        .call_method1("ascontiguousarray", (x, "float64"))?;
    let a: PyReadonlyArrayDyn<f64> = array.extract()?;
    let shape = a.shape().to_vec();
    let (rows, one) = match shape[..] {
        [n] if n == width => (1, true),
        [r, n] if n == width => (r, false),
        _ => {
            return Err(PyValueError::new_err(format!(
                "{what}: expected {width} numbers per row (a 1-D array of {width}, or rows × \
                 {width}), got shape {shape:?}"
            )));
        }
    };
    Ok(Rows {
        data: a.as_slice()?.to_vec(),
        rows,
        one,
    })
}

fn same_rows(a: &Rows, b: &Rows, what: &str) -> PyResult<()> {
    if a.rows != b.rows || a.one != b.one {
        return Err(PyValueError::new_err(format!(
            "{what}: the arrays have different numbers of rows ({} and {})",
            a.rows, b.rows
        )));
    }
    Ok(())
}

/// `rows × width` numbers as a 1-D array (one row) or rows × dims.
fn array<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    one: bool,
    dims: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let a = PyArray1::from_vec(py, data);
    let rows = a.len() / dims.iter().product::<usize>().max(1);
    let mut shape = if one { vec![] } else { vec![rows] };
    shape.extend_from_slice(dims);
    Ok(a.reshape(shape)?.into_any())
}

#[pymethods]
impl Model {
    /// A URDF robot: fixed base unless `floating`, gravity `[x, y, z]` m/s² (default z up).
    #[staticmethod]
    #[pyo3(signature = (path, *, floating = false, gravity = None))]
    fn from_urdf(
        py: Python<'_>,
        path: PathBuf,
        floating: bool,
        gravity: Option<[f64; 3]>,
    ) -> PyResult<Self> {
        let mut o = UrdfOptions {
            floating,
            ..Default::default()
        };
        if let Some([x, y, z]) = gravity {
            o.gravity = nalgebra::Vector3::new(x, y, z);
        }
        let model = py
            .detach(|| pipeline::load_model(&ModelSource::Urdf(path, o), &TakeOptions::default()))
            .map_err(to_py)?;
        Ok(Self { model })
    }

    #[getter]
    fn nq(&self) -> usize {
        self.model.nq
    }

    #[getter]
    fn nv(&self) -> usize {
        self.model.nv
    }

    /// Names of the configuration coordinates q.
    #[getter]
    fn q_names(&self) -> Vec<String> {
        self.model.q_names.clone()
    }

    /// Names of the velocity coordinates v (and of τ).
    #[getter]
    fn v_names(&self) -> Vec<String> {
        self.model.v_names.clone()
    }

    /// Inverse dynamics (RNEA): τ = M(q) a + h(q, v), one row per state.
    fn rnea<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = &self.model;
        let (q, v, a) = (
            rows(py, q, m.nq, "q")?,
            rows(py, v, m.nv, "v")?,
            rows(py, a, m.nv, "a")?,
        );
        same_rows(&q, &v, "rnea(q, v, a)")?;
        same_rows(&q, &a, "rnea(q, v, a)")?;
        let out = py.detach(|| {
            let mut ws = Workspace::new(m);
            let mut out = Vec::with_capacity(q.rows * m.nv);
            for k in 0..q.rows {
                let (qk, vk, ak) = (
                    &q.data[k * m.nq..][..m.nq],
                    &v.data[k * m.nv..][..m.nv],
                    &a.data[k * m.nv..][..m.nv],
                );
                out.extend_from_slice(dynamics::rnea(m, &mut ws, qk, vk, ak, None).as_slice());
            }
            out
        });
        array(py, out, q.one, &[m.nv])
    }

    /// The joint-space mass matrix M(q) (CRBA), nv × nv per row of q.
    fn crba<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let m = &self.model;
        let q = rows(py, q, m.nq, "q")?;
        let out = py.detach(|| {
            let mut ws = Workspace::new(m);
            let mut out = Vec::with_capacity(q.rows * m.nv * m.nv);
            for k in 0..q.rows {
                let d = dynamics::crba(m, &mut ws, &q.data[k * m.nq..][..m.nq]);
                // row-major, as numpy's
                for i in 0..m.nv {
                    for j in 0..m.nv {
                        out.push(d[(i, j)]);
                    }
                }
            }
            out
        });
        array(py, out, q.one, &[m.nv, m.nv])
    }

    /// Forward dynamics (ABA): the accelerations a = M(q)⁻¹ (τ − h(q, v)), one row per state.
    fn aba<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = &self.model;
        let (q, v, tau) = (
            rows(py, q, m.nq, "q")?,
            rows(py, v, m.nv, "v")?,
            rows(py, tau, m.nv, "tau")?,
        );
        same_rows(&q, &v, "aba(q, v, tau)")?;
        same_rows(&q, &tau, "aba(q, v, tau)")?;
        let out = py
            .detach(|| {
                let mut ws = Workspace::new(m);
                let mut out = Vec::with_capacity(q.rows * m.nv);
                for k in 0..q.rows {
                    let a = dynamics::aba(
                        m,
                        &mut ws,
                        &q.data[k * m.nq..][..m.nq],
                        &v.data[k * m.nv..][..m.nv],
                        &tau.data[k * m.nv..][..m.nv],
                        None,
                    )?;
                    out.extend_from_slice(a.as_slice());
                }
                Ok(out)
            })
            .map_err(to_py)?;
        array(py, out, q.one, &[m.nv])
    }

    fn __repr__(&self) -> String {
        format!("<articula.Model nq={} nv={}>", self.model.nq, self.model.nv)
    }
}
