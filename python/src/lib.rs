//! `catflip._catflip`: the Rust half of the `catflip` Python package (the Python half,
//! `python/catflip/`, turns what these functions return into dicts, dataclasses and numpy arrays).
//!
//! Nothing is computed here: every function calls the library function the `catflip` binary calls
//! for the same command (`src/main.rs`) and hands back its serde report as JSON text, so every
//! number equals the CLI's `--json` output by construction. Time series are the schedule files the
//! CLI exports (`catflip::exchange::write_schedule`), as CSV text.
//!
//! - Errors: every refusal becomes `catflip.CatflipError` (a `ValueError`) whose message is the
//!   CLI's line without its `error: ` prefix (the error, then `: cause` for each cause).
//! - Threads: each call runs on a worker thread while the calling thread waits without the GIL,
//!   checking Python's signals every 50 ms ([`worker::run`]): Ctrl-C raises `KeyboardInterrupt` at
//!   once, and the worker finishes its computation in the background (its result is dropped).

mod commands;
mod problem;
mod worker;

use pyo3::prelude::*;

pyo3::create_exception!(
    _catflip,
    CatflipError,
    pyo3::exceptions::PyValueError,
    "A problem, schedule or sweep catflip refuses, with the message the command line prints."
);

/// The message the CLI prints for `e` (without `error: `): the error, then `: cause` for each of
/// its causes (anyhow's chain, as `main` in `src/main.rs` prints it).
fn message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        text.push_str(": ");
        text.push_str(&c.to_string());
        cause = c.source();
    }
    text
}

/// `e` as a [`CatflipError`] with the CLI's message.
fn refuse(e: impl std::error::Error + 'static) -> PyErr {
    CatflipError::new_err(message(&e))
}

/// The module.
#[pymodule]
fn _catflip(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CatflipError", m.py().get_type::<CatflipError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<problem::Problem>()?;
    m.add_class::<commands::Schedule>()?;
    m.add_function(wrap_pyfunction!(problem::load, m)?)?;
    m.add_function(wrap_pyfunction!(problem::from_toml, m)?)?;
    m.add_function(wrap_pyfunction!(commands::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(commands::schedule_file, m)?)?;
    m.add_function(wrap_pyfunction!(commands::compare, m)?)?;
    m.add_function(wrap_pyfunction!(commands::compare_models, m)?)?;
    m.add_function(wrap_pyfunction!(commands::optimize, m)?)?;
    m.add_function(wrap_pyfunction!(commands::optimize_whole, m)?)?;
    m.add_function(wrap_pyfunction!(commands::read_schedule, m)?)?;
    m.add_function(wrap_pyfunction!(commands::schedule_from_columns, m)?)?;
    m.add_function(wrap_pyfunction!(commands::simulate_schedule, m)?)?;
    m.add_function(wrap_pyfunction!(commands::model_files, m)?)?;
    m.add_function(wrap_pyfunction!(commands::sweep, m)?)?;
    Ok(())
}
