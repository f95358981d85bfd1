//! Progress and Ctrl-C for the long builds of the package (`with geomkit.progress(): ...`):
//! the job runs on a worker thread without the GIL, reporting to the library's hook
//! ([`geomkit::progress`]) through two atomics; the calling thread wakes every 50 ms, hands
//! (done, total) to the Python callable `report` and runs Python's signal handlers. A
//! `KeyboardInterrupt` (or any exception of `report`) cancels the job through the same hook —
//! it stops at its next report, within one tile or block of rows — and is raised once the
//! worker has returned: no partial result. Without `report` the job runs as before, with
//! the GIL released and no thread.

use geomkit::progress::Progress;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

/// How often the calling thread reports and checks for signals.
const TICK: Duration = Duration::from_millis(50);

/// Runs `job` (module docs). The outer error is Python's (an interrupt, an exception of
/// `report`, a panic of the job); the inner one the library's.
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    report: Option<&Bound<'_, PyAny>>,
    job: impl FnOnce(&Progress) -> geomkit::Result<T> + Send,
) -> PyResult<geomkit::Result<T>> {
    let Some(report) = report else {
        return Ok(py.detach(|| job(&Progress::none())));
    };
    let (done, total, cancel) = (AtomicU64::new(0), AtomicU64::new(0), AtomicBool::new(false));
    let hook = |d: u64, t: u64| {
        done.store(d, Ordering::Relaxed);
        total.store(t, Ordering::Relaxed);
        if cancel.load(Ordering::Relaxed) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let progress = Progress::new(&hook);
    std::thread::scope(|scope| {
        let worker = scope.spawn(|| job(&progress));
        let mut failure: Option<PyErr> = None;
        while !worker.is_finished() {
            py.detach(|| std::thread::park_timeout(TICK));
            if failure.is_some() {
                continue;
            }
            let state = (done.load(Ordering::Relaxed), total.load(Ordering::Relaxed));
            let step = report.call1(state).and_then(|_| py.check_signals());
            if let Err(e) = step {
                cancel.store(true, Ordering::Relaxed);
                failure = Some(e);
            }
        }
        let result = py
            .detach(|| worker.join())
            .map_err(|_| PyRuntimeError::new_err("internal error: the computation panicked"))?;
        if let Some(e) = failure {
            return Err(e);
        }
        let state = (done.load(Ordering::Relaxed), total.load(Ordering::Relaxed));
        report.call1(state)?;
        Ok(result)
    })
}
