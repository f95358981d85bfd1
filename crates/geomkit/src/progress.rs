//! Progress and cancellation for long builds and meshing: a caller's callback, told how much
//! of a job is done, and able to stop it.
//!
//! The long jobs of the library (interpolating splines of any degree and their tiles, the
//! paper's cubic curves and surfaces and their tiles, heights over grids, tessellation of
//! surfaces and curves) take a [`Progress`] in their `*_with_progress` forms; the plain
//! forms pass [`Progress::none`], whose reports are one branch on a `None` (no
//! measurable cost). A job first announces its total of work units (rows of a system,
//! tiles, grid rows, refinement rounds), then reports units as they finish — from any rayon
//! worker: the reports are serialized by a lock, so the callback sees done counts that never
//! decrease, and the last report has `done == total` when the job succeeds. The callback is
//! called at most once per tile, window, parallel chunk of a solve, block of rows or round
//! (and every 16 384 points of a long curve refinement), never per point.
//!
//! The callback returns [`ControlFlow::Break`] to cancel: the job then stops at its next
//! report and returns [`Error::Cancelled`], never a partial result. The results with and
//! without a callback are the same bits (the callback only observes).
//!
//! ```
//! use geomkit::bspline::{make_interp_spline_with_progress, SplineOptions};
//! use geomkit::progress::Progress;
//! use std::ops::ControlFlow;
//! use std::sync::Mutex;
//! let x: Vec<f64> = (0..200_000).map(|i| i as f64).collect();
//! let y: Vec<f64> = x.iter().map(|v| (v * 1e-3).sin()).collect();
//! let seen = Mutex::new(Vec::new());
//! let report = |done: u64, total: u64| {
//!     seen.lock().unwrap().push((done, total));
//!     ControlFlow::Continue(())
//! };
//! let s = make_interp_spline_with_progress(&x, &y, 1, &SplineOptions::new(5), &Progress::new(&report))
//!     .unwrap();
//! let seen = seen.into_inner().unwrap();
//! assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0));
//! let (done, total) = *seen.last().unwrap();
//! assert_eq!(done, total);
//! assert_eq!(s.degree(), 5);
//!
//! // Cancelled at the first report: an error, no curve.
//! let stop = |_: u64, _: u64| ControlFlow::Break(());
//! let err = make_interp_spline_with_progress(&x, &y, 1, &SplineOptions::new(5), &Progress::new(&stop));
//! assert_eq!(err.unwrap_err(), geomkit::Error::Cancelled);
//! ```

use crate::{Error, Result};
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// The callback of a [`Progress`]: `(done, total)` in the job's work units; `Break` cancels.
/// Called from any thread of the pool (hence `Sync`), one call at a time.
pub type ProgressFn<'a> = dyn Fn(u64, u64) -> ControlFlow<()> + Sync + 'a;

/// Where a long job reports its progress, and how it learns that it is cancelled (module
/// docs).
pub struct Progress<'a> {
    report: Option<&'a ProgressFn<'a>>,
    /// (done, total) so far.
    state: Mutex<(u64, u64)>,
    cancelled: AtomicBool,
}

impl std::fmt::Debug for Progress<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Progress")
            .field("reports", &self.report.is_some())
            .field("cancelled", &self.is_cancelled())
            .finish()
    }
}

impl<'a> Progress<'a> {
    /// No callback: reports cost one branch, nothing is cancelled.
    pub fn none() -> Self {
        Progress {
            report: None,
            state: Mutex::new((0, 0)),
            cancelled: AtomicBool::new(false),
        }
    }

    /// Reports to `report` (module docs).
    pub fn new(report: &'a ProgressFn<'a>) -> Self {
        Progress {
            report: Some(report),
            ..Progress::none()
        }
    }

    /// Whether the callback asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// The (done, total) reported so far.
    pub fn state(&self) -> (u64, u64) {
        *self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Adds `units` to the job's total (a job of several phases adds each phase's units
    /// before it reports any of them, or all at the start) and reports the new total.
    pub(crate) fn add_total(&self, units: u64) -> Result<()> {
        self.update(|s| s.1 += units)
    }

    /// Reports `units` more done (capped at the total); `Err(Cancelled)` once the callback
    /// asked to stop.
    pub(crate) fn advance(&self, units: u64) -> Result<()> {
        self.update(|s| s.0 = (s.0 + units).min(s.1))
    }

    /// Reports the whole total done (a job that finished some units early, e.g. a refined
    /// solve after windows that did not hold).
    pub(crate) fn finish(&self) -> Result<()> {
        self.update(|s| s.0 = s.1)
    }

    /// `Err(Cancelled)` if the callback asked to stop (for long steps between reports).
    pub(crate) fn check(&self) -> Result<()> {
        if self.is_cancelled() {
            return Err(Error::Cancelled);
        }
        Ok(())
    }

    fn update(&self, change: impl FnOnce(&mut (u64, u64))) -> Result<()> {
        let Some(report) = self.report else {
            return Ok(());
        };
        self.check()?;
        let mut state = self.state.lock().unwrap_or_else(|e| e.into_inner());
        change(&mut state);
        if report(state.0, state.1).is_break() {
            self.cancelled.store(true, Ordering::Relaxed);
            return Err(Error::Cancelled);
        }
        Ok(())
    }
}

impl Default for Progress<'_> {
    fn default() -> Self {
        Progress::none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_are_monotone_and_capped() {
        let seen = Mutex::new(Vec::new());
        let f = |d: u64, t: u64| {
            seen.lock().unwrap().push((d, t));
            ControlFlow::Continue(())
        };
        let p = Progress::new(&f);
        p.add_total(10).unwrap();
        p.advance(4).unwrap();
        p.advance(40).unwrap();
        p.finish().unwrap();
        assert_eq!(
            seen.into_inner().unwrap(),
            [(0, 10), (4, 10), (10, 10), (10, 10)]
        );
    }

    #[test]
    fn break_cancels_and_stays_cancelled() {
        let f = |d: u64, _: u64| {
            if d >= 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let p = Progress::new(&f);
        p.add_total(5).unwrap();
        p.advance(1).unwrap();
        assert_eq!(p.advance(1), Err(Error::Cancelled));
        assert!(p.is_cancelled());
        assert_eq!(p.advance(1), Err(Error::Cancelled));
        assert_eq!(p.check(), Err(Error::Cancelled));
    }

    #[test]
    fn none_costs_nothing_and_never_cancels() {
        let p = Progress::none();
        p.add_total(3).unwrap();
        p.advance(5).unwrap();
        assert_eq!(p.state(), (0, 0));
        assert!(!p.is_cancelled());
    }
}
