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
    /// Whether the solver runs nothing: no job, and none of the work it does ahead while it
    /// waits for one ([`Solve::idle`]).
    fn idle(&self) -> bool {
        true
    }
    /// Holds the solver's idle work (what it does ahead) while `held`: the user is moving
    /// something (a slider, the camera), and the window's frames and its software renderer
    /// want the cores. Jobs are not held.
    fn hold_idle_work(&self, held: bool) {
        let _ = held;
    }
}

/// Tells a running job whether a newer one has been submitted.
#[derive(Clone)]
pub struct Cancel {
    latest: Arc<AtomicU64>,
    version: u64,
    /// Set while the idle work is to wait ([`SolverPort::hold_idle_work`]).
    held: Option<Arc<AtomicBool>>,
}

impl Cancel {
    /// A token for job `version` against the shared latest version.
    pub fn new(latest: Arc<AtomicU64>, version: u64) -> Self {
        Cancel {
            latest,
            version,
            held: None,
        }
    }

    /// `true` once a newer job was submitted.
    pub fn is_stale(&self) -> bool {
        self.latest.load(Ordering::Acquire) != self.version
    }

    /// Waits while the idle work is held ([`SolverPort::hold_idle_work`]) and no newer job
    /// came; then whether one came ([`Self::is_stale`]). The check of idle work.
    pub fn wait_then_is_stale(&self) -> bool {
        while self
            .held
            .as_ref()
            .is_some_and(|h| h.load(Ordering::Acquire))
            && !self.is_stale()
        {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        self.is_stale()
    }

    /// Whether the idle work is held now.
    pub fn is_held(&self) -> bool {
        self.held
            .as_ref()
            .is_some_and(|h| h.load(Ordering::Acquire))
    }
}

/// The computation run for each job. `emit` sends one frame (or failure) back; a timeline job
/// emits several.
pub trait Solve: Send {
    /// Runs `job`, checking `cancel` as often as it can.
    fn run(&mut self, job: &Job, cancel: &Cancel, emit: &mut dyn FnMut(Result<Solution, Failure>));

    /// Work done ahead while no job waits, after a job's last result went out; `cancel` turns
    /// stale when a job arrives.
    fn idle(&mut self, cancel: &Cancel) {
        let _ = cancel;
    }
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
    /// Set (under `slot`'s lock) when a job is submitted, cleared (under it too) once the
    /// thread has run it and its idle work with no job waiting.
    working: AtomicBool,
    /// The idle work held ([`SolverPort::hold_idle_work`]).
    held: Arc<AtomicBool>,
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
            working: AtomicBool::new(false),
            held: Arc::new(AtomicBool::new(false)),
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
                // A preview, or a frame settling, goes out at once: it is never a job's last
                // message.
                if matches!(&outcome, Ok(s) if s.preview || s.settling) {
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
        idle(&shared, &mut solve);
    }
}

/// The solver's idle work, unless a job already waits; then the thread is marked not working
/// unless one arrived meanwhile. A panic in it loses that work only.
fn idle(shared: &Shared, solve: &mut impl Solve) {
    let waiting = || {
        shared
            .slot
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .is_some()
    };
    if waiting() || shared.stop.load(Ordering::Acquire) {
        return;
    }
    let mut cancel = Cancel::new(shared.latest.clone(), shared.latest.load(Ordering::Acquire));
    cancel.held = Some(shared.held.clone());
    let _ = catch_unwind(AssertUnwindSafe(|| solve.idle(&cancel)));
    let slot = shared.slot.lock().unwrap_or_else(|e| e.into_inner());
    if slot.is_none() {
        shared.working.store(false, Ordering::Release);
    }
}

impl SolverPort for ThreadSolver {
    fn submit(&mut self, job: Job) {
        self.shared.latest.store(job.version, Ordering::Release);
        {
            let mut slot = self.shared.slot.lock().unwrap_or_else(|e| e.into_inner());
            *slot = Some(job);
            self.shared.working.store(true, Ordering::Release);
        }
        self.shared.wake.notify_one();
    }

    fn poll(&mut self) -> Vec<JobResult> {
        self.results.try_iter().collect()
    }

    fn idle(&self) -> bool {
        !self.shared.working.load(Ordering::Acquire)
    }

    fn hold_idle_work(&self, held: bool) {
        self.shared.held.store(held, Ordering::Release);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::jobs::Target;
    use crate::present::VisualOptions;
    use crate::scene::{Scene, DEFAULT_SCENE};
    use std::time::{Duration, Instant};

    fn job(version: u64) -> Job {
        Job {
            version,
            scene: Arc::new(Scene::parse(DEFAULT_SCENE, "default").unwrap()),
            scene_revision: 0,
            visual: VisualOptions::default(),
            target: Target::Pose {
                pose: Vec::new(),
                start: None,
            },
            ahead: Default::default(),
        }
    }

    /// Runs nothing for a job; its idle work lasts until a job arrives or a second passed,
    /// and says which — or, `checks`, checks in once (as a knot's increment would) and says
    /// when it got past.
    struct Idler {
        log: Arc<Mutex<Vec<String>>>,
        checks: bool,
    }

    impl Solve for Idler {
        fn run(&mut self, job: &Job, _: &Cancel, _: &mut dyn FnMut(Result<Solution, Failure>)) {
            self.log
                .lock()
                .unwrap()
                .push(format!("job {}", job.version));
        }

        fn idle(&mut self, cancel: &Cancel) {
            if self.checks {
                let stale = cancel.wait_then_is_stale();
                self.log.lock().unwrap().push(format!("checked: {stale}"));
                return;
            }
            let start = Instant::now();
            while start.elapsed() < Duration::from_secs(1) {
                if cancel.is_stale() {
                    self.log.lock().unwrap().push("idle stopped".into());
                    return;
                }
                std::thread::sleep(Duration::from_millis(2));
            }
            self.log.lock().unwrap().push("idle done".into());
        }
    }

    /// While the window holds the idle work (a slider or the camera moved), the idle work waits
    /// at its next check; released, it goes on; a job arriving while it is held ends it.
    #[test]
    fn held_idle_work_waits_until_released_or_a_job_comes() {
        let log = Arc::new(Mutex::new(Vec::new()));
        let mut port = ThreadSolver::spawn(
            Idler {
                log: log.clone(),
                checks: true,
            },
            Arc::new(|| {}),
        );
        port.hold_idle_work(true);
        port.submit(job(1));
        wait_until("job 1 run", || log.lock().unwrap().len() == 1);
        std::thread::sleep(Duration::from_millis(100));
        assert_eq!(*log.lock().unwrap(), ["job 1"], "held: not past its check");
        assert!(!port.idle());
        port.hold_idle_work(false);
        wait_until("idle", || port.idle());
        assert_eq!(*log.lock().unwrap(), ["job 1", "checked: false"]);
        // Held again, then a job: the check answers stale at once, the job runs.
        port.hold_idle_work(true);
        port.submit(job(2));
        wait_until("job 2 run", || log.lock().unwrap().len() == 3);
        // (Its idle work then waits at its check.)
        std::thread::sleep(Duration::from_millis(100));
        port.submit(job(3));
        wait_until("job 3 run", || log.lock().unwrap().len() == 5);
        assert_eq!(
            *log.lock().unwrap(),
            ["job 1", "checked: false", "job 2", "checked: true", "job 3"]
        );
        port.hold_idle_work(false);
        wait_until("idle", || port.idle());
    }

    fn wait_until(what: &str, mut done: impl FnMut() -> bool) {
        let start = Instant::now();
        while !done() {
            assert!(start.elapsed() < Duration::from_secs(30), "never {what}");
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    #[test]
    fn idle_work_runs_after_a_job_and_stops_for_the_next() {
        let log = Arc::new(Mutex::new(Vec::new()));
        let mut port = ThreadSolver::spawn(
            Idler {
                log: log.clone(),
                checks: false,
            },
            Arc::new(|| {}),
        );
        assert!(port.idle(), "nothing submitted yet");
        port.submit(job(1));
        assert!(!port.idle(), "working from the submission on");
        let mut answers = Vec::new();
        wait_until("answered", || {
            answers.extend(port.poll());
            !answers.is_empty()
        });
        // The job's answer went out before its idle work ended: still working.
        assert!(!port.idle(), "the idle work runs after the answer");
        wait_until("idle", || port.idle());
        assert_eq!(*log.lock().unwrap(), ["job 1", "idle done"]);

        // A job submitted during the idle work stops it, then runs.
        port.submit(job(2));
        wait_until("job 2 run", || log.lock().unwrap().len() >= 3);
        std::thread::sleep(Duration::from_millis(20));
        port.submit(job(3));
        wait_until("idle", || port.idle());
        let log = log.lock().unwrap().clone();
        assert_eq!(
            log,
            [
                "job 1",
                "idle done",
                "job 2",
                "idle stopped",
                "job 3",
                "idle done"
            ]
        );
    }
}
