//! Test doubles for the solver thread: a [`SolverPort`] that records jobs and hands back the
//! results a test gives it, and small real solutions to give.

use super::jobs::{Failure, Job, JobResult, Solution};
use super::worker::SolverPort;
use crate::headless::solve_scene;
use crate::present::VisualOptions;
use crate::render::{DrawList, Surface};
use crate::scene::Scene;
use std::sync::{Arc, Mutex};

/// What the fake port saw and what it will answer, shared with the test.
#[derive(Default)]
pub struct FakeLog {
    /// Every job submitted, in order.
    pub jobs: Vec<Job>,
    /// Results waiting to be polled.
    pub results: Vec<JobResult>,
}

/// A [`SolverPort`] that records jobs and returns whatever the test queued.
#[derive(Clone, Default)]
pub struct FakePort {
    /// The shared log.
    pub log: Arc<Mutex<FakeLog>>,
}

impl FakePort {
    /// A new port and its log.
    pub fn new() -> Self {
        Self::default()
    }

    /// Jobs submitted so far.
    pub fn jobs(&self) -> Vec<Job> {
        self.log.lock().expect("log").jobs.clone()
    }

    /// Queues a result for the next poll.
    pub fn answer(&self, result: JobResult) {
        self.log.lock().expect("log").results.push(result);
    }

    /// Queues a finished frame for `version` whose draw list holds one triangle at `x`.
    /// The draw options are those of the job of that version, as the real solver's would be.
    pub fn answer_frame(&self, version: u64, x: f32, timeline_frame: Option<usize>) {
        let mut solution = tiny_solution(x, timeline_frame);
        if let Some(job) = self.jobs().iter().find(|j| j.version == version) {
            solution.visual = job.visual;
        }
        self.answer(JobResult {
            version,
            outcome: Ok(solution),
            finished: true,
        });
    }

    /// Queues a failure for `version`.
    pub fn answer_failure(&self, version: u64, failure: Failure) {
        self.answer(JobResult {
            version,
            outcome: Err(failure),
            finished: true,
        });
    }
}

impl SolverPort for FakePort {
    fn submit(&mut self, job: Job) {
        self.log.lock().expect("log").jobs.push(job);
    }

    fn poll(&mut self) -> Vec<JobResult> {
        std::mem::take(&mut self.log.lock().expect("log").results)
    }
}

/// A real (tiny) solved block whose draw list is one triangle at `x`, so that a test can tell
/// solutions apart by what would be drawn.
pub fn tiny_solution(x: f32, timeline_frame: Option<usize>) -> Solution {
    let scene = Scene::parse(
        r#"
        [[material]]
        name = "m"
        young = 1.0e6
        poisson = 0.3
        [[body]]
        name = "b"
        material = "m"
        shape = { box = { min = [0, 0, 0], max = [1, 1, 1], cells = [1, 1, 1] } }
        [[constraint]]
        name = "base"
        body = "b"
        where = { face = "z-" }
        displacement = [0, 0, 0]
        "#,
        "tiny",
    )
    .expect("the tiny scene parses");
    let solved = solve_scene(&scene, "tiny").expect("the tiny scene solves");
    let list = DrawList {
        surfaces: vec![Surface {
            positions: vec![[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x, 1.0, 0.0]],
            indices: vec![0, 1, 2],
            scalars: None,
            color: [0.5, 0.5, 0.5, 1.0],
        }],
        ..Default::default()
    };
    Solution {
        model: Arc::new(solved.model),
        frame: Arc::new(solved.frames.into_iter().next().expect("one frame")),
        draw_list: Arc::new(list),
        solve_ms: 1.0,
        timeline_frame,
        visual: VisualOptions::default(),
        preview: false,
        settling: false,
        tactile: None,
        pressed_inside_out: Vec::new(),
    }
}
