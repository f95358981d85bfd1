//! A progress bar on standard error for long jobs: shown only when stderr is a terminal and
//! only once the job has run for a second (short jobs print nothing), cleared at the end.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::ops::ControlFlow;
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::thread::JoinHandle;
use std::time::Duration;

/// How long a job runs before its bar appears.
const DELAY: Duration = Duration::from_secs(1);

/// A progress bar that appears after [`DELAY`]; phases change its message and length.
pub struct Progress {
    bar: ProgressBar,
    stop: Option<Sender<()>>,
    watcher: Option<JoinHandle<()>>,
}

impl Progress {
    /// Starts the clock of a job. Nothing is drawn unless stderr is a terminal.
    pub fn start() -> Self {
        let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::hidden());
        if !std::io::stderr().is_terminal() {
            return Progress {
                bar,
                stop: None,
                watcher: None,
            };
        }
        let (stop, wait) = mpsc::channel::<()>();
        let shown = bar.clone();
        let watcher = std::thread::spawn(move || {
            if let Err(RecvTimeoutError::Timeout) = wait.recv_timeout(DELAY) {
                shown.set_draw_target(ProgressDrawTarget::stderr());
                shown.enable_steady_tick(Duration::from_millis(150));
            }
        });
        Progress {
            bar,
            stop: Some(stop),
            watcher: Some(watcher),
        }
    }

    /// A progress bar that never draws (for library-like callers such as the demo).
    pub fn hidden() -> Self {
        Progress {
            bar: ProgressBar::hidden(),
            stop: None,
            watcher: None,
        }
    }

    /// Starts a phase of `len` units named `message` ("reading", "solving", ...).
    pub fn phase(&self, message: &'static str, len: u64) {
        if let Ok(style) =
            ProgressStyle::with_template("{msg:>10} {bar:32.cyan/blue} {percent:>3}% {elapsed}")
        {
            self.bar.set_style(style.progress_chars("=> "));
        }
        self.bar.set_message(message);
        self.bar.set_length(len);
        self.bar.set_position(0);
    }

    /// Starts a phase whose progress cannot be measured (one library call): a spinner.
    pub fn busy(&self, message: &'static str) {
        if let Ok(style) = ProgressStyle::with_template("{msg:>10} {spinner:.cyan} {elapsed}") {
            self.bar.set_style(style);
        }
        self.bar.set_message(message);
    }

    /// Sets the position within the phase.
    pub fn set(&self, position: u64) {
        self.bar.set_position(position);
    }

    /// Advances the position.
    pub fn inc(&self, units: u64) {
        self.bar.inc(units);
    }

    /// The callback of the library's progress hook (`geomkit::progress::Progress::new`):
    /// the bar follows the job's (done, total). Start a [`Progress::phase`] first.
    pub fn reporter(&self) -> impl Fn(u64, u64) -> ControlFlow<()> + Sync + '_ {
        move |done, total| {
            self.bar.set_length(total);
            self.bar.set_position(done);
            ControlFlow::Continue(())
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(w) = self.watcher.take() {
            let _ = w.join();
        }
        self.bar.finish_and_clear();
    }
}
