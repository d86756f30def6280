//! `catflip.Problem`: a problem loaded, overridden and validated by the library
//! (`catflip::problem::Problem::load` / `from_toml`), resolved once on first use
//! (`catflip::engines::resolved::Resolved`, where every command starts) and kept resolved.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

use catflip::engines::circulation::CirculationError;
use catflip::engines::resolved::Resolved;
use pyo3::prelude::*;

use crate::refuse;

/// A loaded problem and, once a command asked for it, its resolution.
pub struct Loaded {
    /// The problem as loaded.
    pub problem: catflip::problem::Problem,
    resolved: OnceLock<Arc<Resolved>>,
}

impl Loaded {
    /// The problem resolved (its circulation, calibrated if asked, and its schedule): made by the
    /// first call, kept for the next ones.
    pub fn resolved(&self) -> Result<Arc<Resolved>, CirculationError> {
        if let Some(r) = self.resolved.get() {
            return Ok(r.clone());
        }
        let r = Arc::new(Resolved::new(&self.problem)?);
        Ok(self.resolved.get_or_init(|| r).clone())
    }
}

/// A catflip problem (the problem file's contents, validated).
#[pyclass(frozen, module = "catflip._catflip")]
pub struct Problem {
    /// Shared with the worker threads of running calls.
    pub inner: Arc<Loaded>,
}

#[pymethods]
impl Problem {
    /// The problem's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.problem.name.clone()
    }

    /// What the CLI warns of when it loads the problem (careless input that is not an error).
    fn warnings(&self) -> Vec<String> {
        self.inner.problem.warnings()
    }

    /// The whole problem, every default filled in, as JSON text.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.inner.problem).map_err(refuse)
    }

    /// The whole problem, every default filled in, as a dict of its sections (``from_dict``
    /// loads it back).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (self.to_json()?,))
    }

    /// The whole problem as TOML text (it loads back to the same problem).
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.inner.problem).map_err(refuse)
    }

    fn __repr__(&self) -> String {
        format!("<catflip.Problem {:?}>", self.inner.problem.name)
    }

    /// Pickling (a `multiprocessing` pool's workers): the problem as its TOML text, every default
    /// written, which `from_toml` loads back to the same problem.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Reduced<'py>> {
        let load = py.import("catflip._catflip")?.getattr("from_toml")?;
        Ok((load, (self.to_toml()?, format!("<pickled problem {:?}>", self.inner.problem.name), Vec::new())))
    }
}

/// What `__reduce__` gives pickle: the loader and its arguments (text, origin, overrides).
type Reduced<'py> = (Bound<'py, PyAny>, (String, String, Vec<String>));

fn wrap(problem: catflip::problem::Problem) -> Problem {
    Problem { inner: Arc::new(Loaded { problem, resolved: OnceLock::new() }) }
}

/// Reads, overrides and validates a problem file (`Problem::load`).
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf, overrides: Vec<String>) -> PyResult<Problem> {
    py.detach(|| catflip::problem::Problem::load(&path, &overrides)).map(wrap).map_err(refuse)
}

/// Parses TOML text named `origin` in messages, overrides and validates, as a file's text
/// (`Problem::from_user_text`: an empty text is refused, what it leaves out is warned of).
#[pyfunction]
pub fn from_toml(py: Python<'_>, text: String, origin: String, overrides: Vec<String>) -> PyResult<Problem> {
    py.detach(|| catflip::problem::Problem::from_user_text(&text, &origin, &overrides)).map(wrap).map_err(refuse)
}
