//! The solver thread. The window hands it jobs through a one-slot mailbox (a newer job replaces
//! one not yet started) and never waits for it; a running job made stale by a newer one is
//! cancelled cooperatively (it polls [`Cancel::is_stale`] between increments). Results come
//! back through a channel with the version of their job. A panic in a solve is caught and
//! reported as [`Failure::Panic`]; the thread goes on with the next job.

use super::jobs::{Failure, Job, JobResult, Solution};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;

/// Where the window sends jobs and reads results: the real thread, or a test double.
pub trait SolverPort {
    /// Sends a job; it supersedes every earlier one.
    fn submit(&mut self, job: Job);
    /// Results that arrived since the last call, oldest first (never blocks).
    fn poll(&mut self) -> Vec<JobResult>;
}

/// Tells a running job whether a newer one has been submitted.
#[derive(Clone)]
pub struct Cancel {
    latest: Arc<AtomicU64>,
    version: u64,
}

impl Cancel {
    /// A token for job `version` against the shared latest version.
    pub fn new(latest: Arc<AtomicU64>, version: u64) -> Self {
        Cancel { latest, version }
    }

    /// `true` once a newer job was submitted.
    pub fn is_stale(&self) -> bool {
        self.latest.load(Ordering::Acquire) != self.version
    }
}

/// The computation run for each job. `emit` sends one frame (or failure) back; a timeline job
/// emits several.
pub trait Solve: Send {
    /// Runs `job`, checking `cancel` as often as it can.
    fn run(&mut self, job: &Job, cancel: &Cancel, emit: &mut dyn FnMut(Result<Solution, Failure>));
}

impl<F> Solve for F
where
    F: FnMut(&Job, &Cancel, &mut dyn FnMut(Result<Solution, Failure>)) + Send,
{
    fn run(&mut self, job: &Job, cancel: &Cancel, emit: &mut dyn FnMut(Result<Solution, Failure>)) {
        self(job, cancel, emit)
    }
}

struct Shared {
    slot: Mutex<Option<Job>>,
    wake: Condvar,
    stop: AtomicBool,
    latest: Arc<AtomicU64>,
}

/// The solver thread and its mailbox.
pub struct ThreadSolver {
    shared: Arc<Shared>,
    results: Receiver<JobResult>,
    thread: Option<JoinHandle<()>>,
}

impl ThreadSolver {
    /// Starts the thread running `solve` for each job; `notify` is called after each result
    /// (the window asks for a repaint there).
    pub fn spawn(solve: impl Solve + 'static, notify: Arc<dyn Fn() + Send + Sync>) -> Self {
        let shared = Arc::new(Shared {
            slot: Mutex::new(None),
            wake: Condvar::new(),
            stop: AtomicBool::new(false),
            latest: Arc::new(AtomicU64::new(0)),
        });
        let (tx, results) = channel();
        let inner = shared.clone();
        let thread = std::thread::Builder::new()
            .name("prehensile-solver".into())
            .spawn(move || worker_loop(inner, solve, tx, notify))
            .expect("the solver thread starts");
        ThreadSolver {
            shared,
            results,
            thread: Some(thread),
        }
    }
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_string()
    }
}

fn worker_loop(
    shared: Arc<Shared>,
    mut solve: impl Solve,
    tx: Sender<JobResult>,
    notify: Arc<dyn Fn() + Send + Sync>,
) {
    loop {
        let job = {
            let mut slot = shared.slot.lock().unwrap_or_else(|e| e.into_inner());
            loop {
                if shared.stop.load(Ordering::Acquire) {
                    return;
                }
                if let Some(job) = slot.take() {
                    break job;
                }
                slot = shared.wake.wait(slot).unwrap_or_else(|e| e.into_inner());
            }
        };
        let cancel = Cancel::new(shared.latest.clone(), job.version);
        let version = job.version;
        // Each emitted frame goes out at once, except the newest, held back until the next one
        // or the job's end so that the last message of a job can say it is the last.
        let mut pending: Option<JobResult> = None;
        let mut alive = true;
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            solve.run(&job, &cancel, &mut |outcome| {
                // A preview goes out at once: it is never a job's last message.
                if matches!(&outcome, Ok(s) if s.preview) {
                    alive &= tx
                        .send(JobResult {
                            version,
                            outcome,
                            finished: false,
                        })
                        .is_ok();
                    notify();
                    return;
                }
                if let Some(r) = pending.replace(JobResult {
                    version,
                    outcome,
                    finished: false,
                }) {
                    alive &= tx.send(r).is_ok();
                    notify();
                }
            })
        }));
        if let Err(payload) = outcome {
            if let Some(r) = pending.take() {
                alive &= tx.send(r).is_ok();
            }
            pending = Some(JobResult {
                version,
                outcome: Err(Failure::Panic(panic_text(payload.as_ref()))),
                finished: false,
            });
        }
        let mut last = pending.unwrap_or(JobResult {
            version,
            outcome: Err(Failure::Cancelled),
            finished: false,
        });
        last.finished = true;
        if !alive || tx.send(last).is_err() {
            return;
        }
        notify();
    }
}

impl SolverPort for ThreadSolver {
    fn submit(&mut self, job: Job) {
        self.shared.latest.store(job.version, Ordering::Release);
        *self.shared.slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(job);
        self.shared.wake.notify_one();
    }

    fn poll(&mut self) -> Vec<JobResult> {
        self.results.try_iter().collect()
    }
}

impl Drop for ThreadSolver {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        self.shared.latest.store(u64::MAX, Ordering::Release);
        self.shared.wake.notify_one();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
