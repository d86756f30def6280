//! Long calls without the GIL, interruptible: the computation runs on a worker thread while the
//! calling thread waits for it with the GIL released, waking every [`POLL`] to let Python run its
//! signal handlers. A `KeyboardInterrupt` (or any exception a handler raises) is raised at once;
//! the worker cannot be stopped from outside, so it finishes in the background and its result is
//! dropped. A panic in the worker (a bug) is a `RuntimeError`, never a crash of the interpreter.

use std::sync::mpsc::{channel, RecvTimeoutError};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread checks Python's signals.
pub const POLL: Duration = Duration::from_millis(50);

/// The worker's stack, bytes: the main thread's usual 8 MiB, which the CLI runs on.
const STACK: usize = 8 << 20;

/// Runs `f` on a worker thread; returns its result, or the exception a signal handler raised while
/// waiting.
pub fn run<T: Send + 'static>(py: Python<'_>, f: impl FnOnce() -> T + Send + 'static) -> PyResult<T> {
    let (tx, rx) = channel();
    std::thread::Builder::new()
        .name("catflip".into())
        .stack_size(STACK)
        .spawn(move || {
            // The receiver is gone when the caller was interrupted: nothing to deliver to.
            let _ = tx.send(f());
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start a worker thread: {e}")))?;
    let mut rx = rx;
    loop {
        // The receiver is not `Sync`: it goes into the GIL-free closure and comes back out.
        let (back, received) = py.detach(move || {
            let received = rx.recv_timeout(POLL);
            (rx, received)
        });
        rx = back;
        match received {
            Ok(value) => return Ok(value),
            Err(RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err(
                    "catflip's computation panicked (a bug: please report it with the problem file)",
                ))
            }
        }
    }
}
