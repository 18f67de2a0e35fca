//! The Python module `articula` (its native part, `articula._native`): takes, their inverse
//! dynamics, anatomy, simulation and exports as numpy tables, and robot models' RNEA, CRBA and
//! ABA vectorised over rows. Everything is the library's own path, as the command line's: the
//! take options are parsed by `pipeline::flags`, each command's choices by
//! `pipeline::commands`, and each table (column names and numbers) by `pipeline::table`.
//! Computation runs with the GIL released.

mod model;
mod options;
mod take;

use pyo3::prelude::*;

/// mimalloc for the module's own allocations, as for the `articula` binary (src/main.rs): a
/// process that loads take after take (a Dask worker, a notebook) gets freed pages back for
/// the next take instead of faulting them in again. Python's objects keep Python's allocator;
/// the numpy arrays made from the module's vectors are freed by this one, which made them.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

pyo3::create_exception!(
    articula,
    ArticulaError,
    pyo3::exceptions::PyException,
    "An error of articula: its message names the file, line or option to change."
);

/// A library error as the Python exception carrying its message.
pub(crate) fn to_py(e: articula_core::error::Error) -> PyErr {
    ArticulaError::new_err(e.to_string())
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ArticulaError", m.py().get_type::<ArticulaError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(take::load, m)?)?;
    m.add_class::<take::Take>()?;
    m.add_class::<take::Table>()?;
    m.add_class::<model::Model>()?;
    Ok(())
}
