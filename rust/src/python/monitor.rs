//! Errors, progress and interruption across the Python boundary: crate errors become the
//! exceptions of `mdrvisc.errors`; computations run on a rayon worker with the GIL released
//! while the calling thread serves Ctrl-C and the progress callbacks, so that Python code
//! never runs on, or holds, a worker of the pool.

use crate::support::error::Error;
use crate::support::monitor::{Monitor, Stop};
use pyo3::prelude::*;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Raises the matching exception class of `mdrvisc.errors`.
pub(crate) fn to_pyerr(py: Python<'_>, e: Error) -> PyErr {
    let errors = match py.import("mdrvisc.errors") {
        Ok(m) => m,
        Err(err) => return err,
    };
    let msg = e.to_string();
    let made = match &e {
        Error::InvalidInput(_) => errors
            .getattr("InvalidInputError")
            .and_then(|c| c.call1((msg,))),
        Error::NotConverged {
            iterations,
            residual,
            ..
        } => errors
            .getattr("ConvergenceError")
            .and_then(|c| c.call1((msg, *iterations, *residual))),
        Error::Domain(_) => errors.getattr("DomainError").and_then(|c| c.call1((msg,))),
        Error::Interrupted => return pyo3::exceptions::PyKeyboardInterrupt::new_err(msg),
    };
    match made {
        Ok(obj) => PyErr::from_value(obj),
        Err(err) => err,
    }
}

/// What the worker running a computation tells the thread that waits for it.
enum Message<T> {
    /// `done` of `total` units of a stage are finished.
    Progress(String, usize, usize),
    /// The computation's result.
    Done(crate::Result<T>),
}

/// Serves an optional Python callback `progress(stage, done, total)` at most every 200 ms
/// (and at the end of each stage), on the calling thread, and stops the computation when
/// the callback raises or that thread caught a signal (`run`).
pub(crate) struct PyMonitor {
    callback: Option<Py<PyAny>>,
}

/// The monitor a computation sees on its worker: it forwards progress to the waiting thread
/// without waiting for it, so that no worker is ever held by Python code (a callback that
/// runs and joins another solve cannot starve the pool), and stops when told to.
struct Forward<T> {
    tx: mpsc::Sender<Message<T>>,
    last: Option<Instant>,
    cancel: Stop,
}

impl<T> Monitor for Forward<T> {
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> crate::Result<()> {
        self.cancel.check()?;
        if done < total
            && self
                .last
                .is_some_and(|t| t.elapsed() < Duration::from_millis(200))
        {
            return Ok(());
        }
        self.last = Some(Instant::now());
        // The receiver outlives the computation: the send cannot fail.
        let _ = self.tx.send(Message::Progress(stage.into(), done, total));
        Ok(())
    }

    fn stop(&self) -> Stop {
        self.cancel.clone()
    }
}

impl PyMonitor {
    pub(crate) fn new(callback: Option<Py<PyAny>>) -> Self {
        PyMonitor { callback }
    }

    /// Runs `f` on a worker of the crate's pool with the GIL released, while the calling
    /// thread serves the progress callback and checks for signals (Ctrl-C) every 50 ms; a
    /// signal or a raising callback stops `f` at its next progress report. Returns f's
    /// result, or the Python exception that stopped it.
    pub(crate) fn run<T: Send>(
        self,
        py: Python<'_>,
        f: impl FnOnce(&mut dyn Monitor) -> crate::Result<T> + Send,
    ) -> PyResult<T> {
        let pool = crate::support::pool::get().map_err(|e| to_pyerr(py, e))?;
        let cancel = Stop::default();
        let (tx, rx) = mpsc::channel();
        let mut forward = Forward {
            tx,
            last: None,
            cancel: cancel.clone(),
        };
        let callback = self.callback;
        let (r, stop) = py.detach(move || {
            let mut stop: Option<PyErr> = None;
            let r = pool.in_place_scope(|s| {
                s.spawn(move |_| {
                    let r = f(&mut forward);
                    let _ = forward.tx.send(Message::Done(r));
                });
                loop {
                    let message = rx.recv_timeout(Duration::from_millis(50));
                    let served = Python::attach(|py| -> PyResult<()> {
                        if stop.is_none() {
                            py.check_signals()?;
                        }
                        match (&message, &callback) {
                            (Ok(Message::Progress(stage, done, total)), Some(cb))
                                if stop.is_none() =>
                            {
                                cb.call1(py, (stage.as_str(), *done, *total)).map(|_| ())
                            }
                            _ => Ok(()),
                        }
                    });
                    if let Err(e) = served {
                        cancel.request();
                        stop = Some(e);
                    }
                    match message {
                        Ok(Message::Done(r)) => break r,
                        Ok(Message::Progress(..)) | Err(RecvTimeoutError::Timeout) => {}
                        // The job panicked: the scope re-raises the panic when it ends.
                        Err(RecvTimeoutError::Disconnected) => break Err(Error::Interrupted),
                    }
                }
            });
            (r, stop)
        });
        match stop {
            Some(e) => Err(e),
            None => r.map_err(|e| to_pyerr(py, e)),
        }
    }
}

/// Runs `f` on a worker of the crate's pool with the GIL released and waits for it: its
/// parallel loops then split among the workers without waking the calling thread each time
/// (for short computations that serve no progress callback; the others use
/// `PyMonitor::run`).
pub(crate) fn in_pool<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| crate::support::pool::run(f))
        .map_err(|e| to_pyerr(py, e))
}
