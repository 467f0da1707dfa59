//! The viewer's state and its traffic with the solver thread: the inputs of the panels (scene
//! with its edits, pose, solver and display settings, timeline), the frame shown, and the rules
//! that keep them apart — every change sends a job with a new version, only the newest result is
//! shown, a failure keeps the last good frame.
//!
//! The panels (`super::panels`) draw and edit this state; the 3D view is behind [`SceneView`] and
//! the solver behind [`SolverPort`], so that both can be replaced by test doubles.

use super::jobs::{Failure, Job, JobResult, Pose, Solution, Target};
use super::object::BallParams;
use super::pose::{hands_of, HandInfo};
use super::settings::{DisplayParams, SolverParams};
use super::timeline::Timeline;
use super::worker::SolverPort;
use crate::present::VisualOptions;
use crate::scene::Scene;
use std::path::PathBuf;
use std::sync::Arc;

/// The 3D view: draws solutions (the window's uses the project's renderer).
pub trait SceneView {
    /// Shows `solution`'s draw list with the colour `range`.
    fn show_solution(&mut self, solution: &Solution, range: [f32; 2]);
    /// Changes the colour range of what is shown.
    fn set_range(&mut self, range: [f32; 2]);
    /// Draws the view into `ui` (the central panel), handling camera input.
    fn ui(&mut self, ui: &mut egui::Ui);
    /// Renders `solution` (or, with `None`, what is shown) off screen at `width`×`height` with
    /// the view's camera, for export.
    fn capture(
        &mut self,
        solution: Option<&Solution>,
        width: u32,
        height: u32,
    ) -> Result<image::RgbaImage, String>;
}

/// Where the frame shown came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The pose of the sliders.
    Interactive,
    /// A cached timeline frame.
    Timeline(usize),
}

/// The frame on screen.
#[derive(Clone)]
pub struct Shown {
    /// Version of the job that computed it.
    pub version: u64,
    /// The solution.
    pub solution: Solution,
    /// Where it came from.
    pub source: Source,
}

/// Counters and the last failure, for the Status panel.
#[derive(Clone, Debug, Default)]
pub struct Status {
    /// The last failure (error or panic) not yet followed by a good frame.
    pub error: Option<String>,
    /// Results shown.
    pub shown: usize,
    /// Results discarded because a newer request had been made.
    pub discarded: usize,
    /// Jobs cancelled by a newer request.
    pub cancelled: usize,
    /// A short message (saved, exported, ...).
    pub message: Option<String>,
    /// What the last grasp found (the gentlest grip), in words.
    pub grasp: Option<String>,
}

/// The Grasp row of the Joints panel: what the hand closes on, from which preshape, how firmly.
#[derive(Clone, Debug, PartialEq)]
pub struct GraspParams {
    /// The body grasped (a body that is not a hand).
    pub object: String,
    /// `"power"`, `"pinch"` or `"tripod"`.
    pub preshape: String,
    /// `None`: hold against gravity with `margin`; `Some(N)`: press with that grip force.
    pub force: Option<f64>,
    /// Safety factor on the friction a gravity hold needs.
    pub margin: f64,
}

impl GraspParams {
    /// The first object of `scene`, the power preshape, a gravity hold with the default margin.
    pub fn from_scene(scene: &Scene) -> Self {
        let object = scene
            .body
            .iter()
            .find(|b| !matches!(b.shape, crate::scene::Shape::Hand { .. }))
            .map(|b| b.name.clone())
            .unwrap_or_default();
        GraspParams {
            object,
            preshape: "power".into(),
            force: None,
            margin: crate::model::DEFAULT_MARGIN,
        }
    }

    /// As a scene's grasp judging the pose `pose` (joint angles by name, degrees) as posed:
    /// no closing (`close = false`), held as this row asks.
    pub fn judging(&self, pose: std::collections::BTreeMap<String, f64>) -> crate::scene::GraspDef {
        crate::scene::GraspDef {
            preshape: Some(crate::scene::PreshapeDef::Pose(pose)),
            close: Some(false),
            ..self.def()
        }
    }

    /// As a scene's grasp.
    pub fn def(&self) -> crate::scene::GraspDef {
        crate::scene::GraspDef {
            object: self.object.clone(),
            preshape: Some(crate::scene::PreshapeDef::Named(self.preshape.clone())),
            hold: None,
            force: self.force,
            margin: self.force.is_none().then_some(self.margin),
            close: None,
        }
    }
}

/// Everything the window shows and edits.
pub struct ViewerState {
    /// The scene with the panels' edits applied (keyframes as loaded or saved).
    pub scene: Scene,
    /// Name of the scene (its file, or "built-in default scene").
    pub scene_name: String,
    /// Path the File panel saves to and loads from.
    pub scene_path: String,
    /// Folder the exports go to.
    pub export_dir: String,
    /// The hands of the scene.
    pub hands: Vec<HandInfo>,
    /// The pose of the sliders.
    pub pose: Pose,
    /// The ball of the Object panel, if the scene has one.
    pub ball: Option<BallParams>,
    /// The Grasp row of the Joints panel.
    pub grasp: GraspParams,
    /// The Solver panel.
    pub solver: SolverParams,
    /// The Display panel.
    pub display: DisplayParams,
    /// Keys and cached frames.
    pub timeline: Timeline,
    /// Solve frames of the timeline in the background when idle.
    pub timeline_solving: bool,
    /// Counters and failures.
    pub status: Status,
    /// The frame on screen.
    pub shown: Option<Shown>,
    /// The last solved frame shown (not a preview): back on screen when the pose a preview
    /// shows fails.
    last_solved: Option<Shown>,
    /// The 3D view (none in UI tests).
    pub view: Option<Box<dyn SceneView>>,
    port: Box<dyn SolverPort>,
    scene_revision: u64,
    next_version: u64,
    /// The newest pose job: only its result is shown.
    pose_version: Option<u64>,
    /// The timeline job whose frames are accepted.
    timeline_job: Option<u64>,
    /// The newest job not finished.
    in_flight: Option<u64>,
    /// A timeline frame failed: no more automatic timeline jobs until something changes.
    timeline_failed: bool,
    /// The draw options last asked for the shown frame (to ask once per change).
    redraw_asked: Option<(u64, VisualOptions)>,
    /// Set by the panels during a frame, acted on at its end.
    pub(crate) pose_changed: bool,
    /// The Grasp button was pressed: a grasp job goes out at the end of the frame.
    pub(crate) grasp_asked: bool,
    /// The "Does it hold?" button was pressed: the sliders' pose is judged as posed (a grasp
    /// job that does not close) at the end of the frame.
    pub(crate) judge_asked: bool,
    /// The Grasp job in flight (its version) and the timeline key current when it was asked:
    /// its result, and only its, puts the closing on the timeline after that key (a pose judged
    /// as posed, its outcome not `closed`, adds nothing).
    grasp_job: Option<(u64, usize)>,
    /// A preset in stages (the Fist with self-contact: the fingers, then the thumb): the pose
    /// asked now, and the pose asked once it is solved — unless the sliders moved meanwhile.
    pub(crate) staged: Option<(Pose, Pose)>,
    pub(crate) scene_changed: bool,
    pub(crate) range_changed: bool,
}

impl ViewerState {
    /// The state for `scene` (called `name`), solving through `port`; the first frame is
    /// requested at the end of the first [`ViewerState::ui`] (or [`ViewerState::dispatch`]).
    pub fn new(scene: Scene, name: &str, port: Box<dyn SolverPort>) -> Result<Self, String> {
        let hands = hands_of(&scene);
        let timeline = Timeline::from_scene(&scene, &hands)?;
        let pose = timeline.keys[0].pose.clone();
        Ok(ViewerState {
            ball: BallParams::from_scene(&scene),
            grasp: GraspParams::from_scene(&scene),
            solver: SolverParams::from_scene(&scene),
            display: DisplayParams::default(),
            scene_name: name.to_string(),
            scene_path: if name.ends_with(".toml") {
                name.to_string()
            } else {
                "scene.toml".to_string()
            },
            export_dir: "export".to_string(),
            hands,
            pose,
            timeline,
            timeline_solving: true,
            scene,
            status: Status::default(),
            shown: None,
            last_solved: None,
            view: None,
            port,
            scene_revision: 0,
            next_version: 1,
            pose_version: None,
            timeline_job: None,
            in_flight: None,
            timeline_failed: false,
            redraw_asked: None,
            pose_changed: true,
            grasp_asked: false,
            judge_asked: false,
            grasp_job: None,
            staged: None,
            scene_changed: false,
            range_changed: false,
        })
    }

    /// Replaces the scene (File → Load): new hands, timeline and model.
    pub fn replace_scene(&mut self, scene: Scene, name: &str) -> Result<(), String> {
        let hands = hands_of(&scene);
        let timeline = Timeline::from_scene(&scene, &hands)?;
        self.pose = timeline.keys[0].pose.clone();
        self.timeline = timeline;
        self.hands = hands;
        self.ball = BallParams::from_scene(&scene);
        self.grasp = GraspParams::from_scene(&scene);
        self.solver = SolverParams::from_scene(&scene);
        self.scene = scene;
        self.scene_name = name.to_string();
        self.scene_revision += 1;
        self.timeline_failed = false;
        self.pose_changed = true;
        Ok(())
    }

    /// Tells the state that `pose` was edited (as a joint slider does): a pose job goes out at
    /// the end of the frame.
    pub fn pose_edited(&mut self) {
        self.pose_changed = true;
    }

    /// The scene with the current keys written in (what File → Save writes).
    pub fn scene_with_keys(&self) -> Scene {
        let mut scene = self.scene.clone();
        self.timeline.write_to(&mut scene, &self.hands);
        scene
    }

    /// `true` while a job whose result would replace the shown frame is outstanding.
    pub fn computing(&self) -> bool {
        self.pose_changed
            || self.grasp_asked
            || self.judge_asked
            || self.pose_version.is_some_and(|v| self.in_flight == Some(v))
    }

    /// Whether the solver thread runs nothing: no job, nor the work it does ahead while it
    /// waits for one.
    pub fn solver_idle(&self) -> bool {
        !self.computing() && self.port.idle()
    }

    /// Holds the solver's idle work while `moving` (see [`SolverPort::hold_idle_work`]).
    pub fn hold_idle_work(&self, moving: bool) {
        self.port.hold_idle_work(moving);
    }

    /// The version of the newest job submitted (0 before any).
    pub fn latest_version(&self) -> u64 {
        self.next_version - 1
    }

    fn submit(&mut self, target: Target) -> u64 {
        let version = self.next_version;
        self.next_version += 1;
        let ahead = super::jobs::Ahead {
            poses: super::pose::preset_poses_ahead(
                &self.hands,
                &self.pose,
                self.solver.self_contact,
            ),
            // A timeline job leaves the frame shown as it is; the other jobs replace it with
            // theirs, the hands where they leave them.
            start: match &target {
                Target::Timeline { .. } => self.start_frame(),
                _ => None,
            },
        };
        self.port.submit(Job {
            version,
            scene: Arc::new(self.scene.clone()),
            scene_revision: self.scene_revision,
            visual: self.display.visual(),
            target,
            ahead,
        });
        self.in_flight = Some(version);
        version
    }

    /// The frame to start a pose job from: the shown one if it came from the timeline.
    fn start_frame(&self) -> Option<Arc<crate::state::Frame>> {
        self.shown
            .as_ref()
            .filter(|s| matches!(s.source, Source::Timeline(_)))
            .map(|s| s.solution.frame.clone())
    }

    /// Sends what the changes of this frame call for (at most one job).
    pub fn dispatch(&mut self) {
        if self.scene_changed {
            self.scene_changed = false;
            if let Some(ball) = &self.ball {
                ball.apply(&mut self.scene);
            }
            self.solver.apply(&mut self.scene);
            self.scene_revision += 1;
            self.timeline.invalidate_from(0);
            self.timeline_failed = false;
            self.pose_changed = true;
        }
        if self.range_changed {
            self.range_changed = false;
            let range = self.current_range();
            if let Some(view) = &mut self.view {
                view.set_range(range);
            }
        }
        if (self.grasp_asked || self.judge_asked) && !self.pose_changed {
            let closes = self.grasp_asked;
            self.grasp_asked = false;
            self.judge_asked = false;
            if let Some(hand) = self.hands.first() {
                let grasp = if closes {
                    self.grasp.def()
                } else {
                    let angles = self
                        .pose
                        .iter()
                        .find(|(b, _)| *b == hand.body)
                        .map_or(&[][..], |(_, a)| a.as_slice());
                    self.grasp.judging(hand.skeleton.pose_of(angles))
                };
                let start = self.start_frame();
                let v = self.submit(Target::Grasp {
                    body: hand.body,
                    grasp,
                    start,
                });
                self.pose_version = Some(v);
                self.grasp_job = Some((v, self.timeline.current));
                self.status.grasp = Some(if closes { CLOSING } else { JUDGING }.into());
                return;
            }
        }
        if self.pose_changed {
            self.pose_changed = false;
            // A pose moved by hand is no longer the grasp's.
            self.status.grasp = None;
            let start = self.start_frame();
            let v = self.submit(Target::Pose {
                pose: self.pose.clone(),
                start,
            });
            self.pose_version = Some(v);
            return;
        }
        let visual = self.display.visual();
        if let Some(shown) = &self.shown {
            let asked = Some((shown.version, visual));
            // (Not from a preview: its frame is no state to solve from; the solved frame that
            // replaces it is redrawn then.)
            if shown.solution.visual != visual
                && self.redraw_asked != asked
                && !shown.solution.preview
            {
                self.redraw_asked = asked;
                let pose = shown
                    .solution
                    .frame
                    .hands
                    .iter()
                    .map(|h| (h.body, h.angles.clone()))
                    .collect();
                let start = Some(shown.solution.frame.clone());
                let v = self.submit(Target::Pose { pose, start });
                self.pose_version = Some(v);
                return;
            }
        }
        if self.in_flight.is_none() && self.timeline_solving && !self.timeline_failed {
            if let Some(first) = self.timeline.first_unsolved() {
                let start = match first {
                    0 => None,
                    k => self.timeline.frames[k - 1]
                        .as_ref()
                        .map(|s| s.frame.clone()),
                };
                let poses = self.timeline.keys[first..]
                    .iter()
                    .map(|k| k.pose.clone())
                    .collect();
                let v = self.submit(Target::Timeline {
                    first,
                    start,
                    poses,
                });
                self.timeline_job = Some(v);
            }
        }
    }

    /// The colour range for the shown draw list.
    pub fn current_range(&self) -> [f32; 2] {
        let auto = self
            .shown
            .as_ref()
            .and_then(|s| s.solution.draw_list.legend.as_ref())
            .map_or([0.0, 1.0], |l| l.range);
        self.display.range(auto)
    }

    fn show(&mut self, version: u64, solution: Solution, source: Source) {
        let shown = Shown {
            version,
            solution,
            source,
        };
        // (Nor a frame whose contact is still being settled: the pose may yet fail.)
        if !shown.solution.preview && !shown.solution.settling {
            self.last_solved = Some(shown.clone());
        }
        self.shown = Some(shown);
        self.status.shown += 1;
        self.redraw_shown();
    }

    /// Hands the shown frame to the 3D view.
    fn redraw_shown(&mut self) {
        let range = self.current_range();
        if let (Some(view), Some(shown)) = (&mut self.view, &self.shown) {
            view.show_solution(&shown.solution, range);
        }
    }

    /// Takes the results that arrived and shows the newest.
    pub fn receive(&mut self) {
        for r in self.port.poll() {
            self.take(r);
        }
    }

    fn take(&mut self, r: JobResult) {
        if r.finished && self.in_flight == Some(r.version) {
            self.in_flight = None;
        }
        let newest_pose = self.pose_version == Some(r.version);
        let timeline = self.timeline_job == Some(r.version);
        let failed = matches!(r.outcome, Err(Failure::Error(_) | Failure::Panic(_)));
        if newest_pose
            && r.outcome.is_err()
            && matches!(self.status.grasp.as_deref(), Some(CLOSING | JUDGING))
        {
            self.status.grasp = None;
        }
        if failed && newest_pose && (self.showing_preview() || self.showing_settling()) {
            // The pose a preview (or a frame whose contact was being settled) showed failed:
            // the last solved frame goes back on screen.
            self.shown = self.last_solved.clone();
            self.redraw_shown();
        }
        match r.outcome {
            Ok(solution) => {
                if let Some(i) = solution.timeline_frame {
                    if !timeline || i >= self.timeline.frames.len() {
                        self.status.discarded += 1;
                        return;
                    }
                    self.timeline.frames[i] = Some(solution.clone());
                    let showing_key = self
                        .shown
                        .as_ref()
                        .is_none_or(|s| s.source != Source::Interactive);
                    if i == self.timeline.current && showing_key && !self.computing() {
                        self.show(r.version, solution, Source::Timeline(i));
                    }
                } else if newest_pose {
                    self.status.error = None;
                    // A grasp found its pose: the sliders go there, and the closing (the
                    // preshape, then the grip) goes on the timeline as two keys after the key
                    // that was current when Grasp was pressed. Only the Grasp job's own result
                    // does (a later pose's preview carries the grasp frame's outcome along).
                    let grasp_job = self
                        .grasp_job
                        .filter(|(v, _)| *v == r.version && !solution.preview);
                    for h in &solution.frame.hands {
                        let (Some(g), Some((_, key))) = (&h.grasp, grasp_job) else {
                            continue;
                        };
                        let Some(i) = self.pose.iter().position(|(b, _)| *b == h.body) else {
                            continue;
                        };
                        self.pose[i].1.clone_from(&h.angles);
                        self.status.grasp = Some(grasp_summary(g));
                        if g.closed && (g.closing_deg > 0.0 || g.held) {
                            self.add_closing(key, i, g, &h.angles);
                        }
                    }
                    if grasp_job.is_some() {
                        self.grasp_job = None;
                    }
                    let solved = !solution.preview && !solution.settling;
                    self.show(r.version, solution, Source::Interactive);
                    // The next stage of a preset, once its first is solved.
                    if solved {
                        if let Some((first, then)) = self.staged.take() {
                            if self.pose == first {
                                self.pose = then;
                                self.pose_changed = true;
                            }
                        }
                    }
                } else {
                    self.status.discarded += 1;
                }
            }
            Err(Failure::Cancelled) => self.status.cancelled += 1,
            Err(Failure::Error(e)) if newest_pose || timeline => {
                if newest_pose {
                    self.staged = None;
                }
                if timeline {
                    self.timeline_failed = true;
                    self.status.error = Some(format!("timeline: {e}"));
                } else {
                    self.status.error = Some(e);
                }
            }
            Err(Failure::Panic(p)) if newest_pose || timeline => {
                if newest_pose {
                    self.staged = None;
                }
                self.timeline_failed |= timeline;
                self.status.error = Some(format!(
                    "the solver panicked: {p} (the last good frame stays on screen)"
                ));
            }
            Err(_) => self.status.discarded += 1,
        }
    }

    /// `true` while the frame on screen is a preview (its pose is being solved).
    pub fn showing_preview(&self) -> bool {
        self.shown.as_ref().is_some_and(|s| s.solution.preview)
    }

    /// `true` while the frame on screen is solved at its pose but its contact is being settled
    /// (the corrections at the pose run; the settled frame follows).
    pub fn showing_settling(&self) -> bool {
        self.shown.as_ref().is_some_and(|s| s.solution.settling)
    }

    /// The closing of a grasp on the timeline: the preshape, then the grip found (`angles`), for
    /// hand `i` of the sliders' pose, as two keys after key `after` (one when the grip is the
    /// preshape).
    fn add_closing(
        &mut self,
        after: usize,
        i: usize,
        g: &crate::state::GraspOutcome,
        angles: &[f64],
    ) {
        self.timeline.current = after.min(self.timeline.keys.len().saturating_sub(1));
        let body = self.pose[i].0;
        let preshape = self
            .hands
            .iter()
            .find(|info| info.body == body)
            .and_then(|info| info.skeleton.apply_pose(angles, &g.preshape_pose).ok());
        if let Some(preshape) = preshape.filter(|p| p.as_slice() != angles) {
            let mut key = self.pose.clone();
            key[i].1 = preshape;
            self.timeline.add_key(key);
        }
        self.timeline.add_key(self.pose.clone());
    }

    /// Shows key `k` of the timeline (its cached frame if solved) and puts the sliders there.
    pub fn scrub_to(&mut self, k: usize) {
        if k >= self.timeline.keys.len() {
            return;
        }
        self.timeline.current = k;
        self.pose = self.timeline.keys[k].pose.clone();
        if let Some(solution) = self.timeline.frames[k].clone() {
            let version = self.latest_version();
            self.pose_version = None;
            self.show(version, solution, Source::Timeline(k));
        }
    }

    /// The per-frame work that is not drawing: results, playback, then the jobs the panels'
    /// changes call for.
    pub fn step(&mut self, dt: f64) {
        self.receive();
        if self.timeline.advance(dt) {
            let k = self.timeline.current;
            self.scrub_to(k);
        }
    }

    /// The bone forces of the shown frame: (hand, bone, |force| N), largest first per hand.
    pub fn bone_forces(&self) -> Vec<(String, String, f64)> {
        let Some(shown) = &self.shown else {
            return Vec::new();
        };
        let model = &shown.solution.model;
        let mut out = Vec::new();
        for h in &shown.solution.frame.hands {
            let Some(hand) = model.bodies.get(h.body).and_then(|b| b.hand.as_deref()) else {
                continue;
            };
            let mut rows: Vec<(String, String, f64)> = hand
                .skeleton
                .bones
                .iter()
                .zip(&h.bone_reactions)
                .map(|(b, r)| (model.bodies[h.body].name.clone(), b.name.clone(), r.norm()))
                .filter(|r| r.2.is_finite())
                .collect();
            rows.sort_by(|a, b| b.2.total_cmp(&a.2));
            out.extend(rows);
        }
        out
    }

    /// Where File → Save writes.
    pub fn scene_file(&self) -> PathBuf {
        PathBuf::from(&self.scene_path)
    }
}

/// The status line while a grasp is solved.
const CLOSING: &str = "closing the hand…";

/// The status while a pose is judged as posed.
const JUDGING: &str = "letting go of the object in this pose…";

/// What a grasp found, in a line of the status panel.
fn grasp_summary(g: &crate::state::GraspOutcome) -> String {
    let how = match (g.force_target, g.margin_target) {
        (Some(f), _) => format!("grip {:.2} N of {f} N asked", g.grip),
        (None, Some(m)) => match g.drift {
            Some(d) => format!(
                "grip {:.2} N, friction margin {:.2} of {m}, let go of it moves {:.2} mm",
                g.grip,
                g.margin,
                1e3 * d
            ),
            None => format!(
                "grip {:.2} N, friction margin {:.2} of {m}",
                g.grip, g.margin
            ),
        },
        (None, None) => format!("grip {:.2} N", g.grip),
    };
    let head = if g.held { "held" } else { "not held" };
    let closing = if !g.closed {
        "judged as posed".to_string()
    } else if g.closing_deg < 0.0 {
        format!("{:.1}° short of first contact", -g.closing_deg)
    } else {
        format!("{:.1}° past first contact", g.closing_deg)
    };
    let mut line = if g.closed {
        format!(
            "{head} \"{}\" ({}): {how}, {closing}, {} poses solved",
            g.object, g.preshape, g.trials
        )
    } else {
        format!("{head} \"{}\": {how}, {closing}", g.object)
    };
    if g.preshape_grip > 0.0 && g.closed {
        line.push_str(&format!(
            " — the open hand already presses it with {:.2} N in the preshape: nothing gentler \
             along the synergies; move the object out of the open hand",
            g.preshape_grip
        ));
    }
    if let Some(r) = &g.reason {
        line.push_str(" — ");
        line.push_str(r);
        // The scene file's advice, as the viewer sets it.
        if r.contains("[[friction]]") {
            line.push_str(" (here: the Object panel's skin friction μ)");
        }
        if r.contains("leave out close = false") {
            line.push_str(" (here: the Grasp button)");
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::grasp_summary;
    use crate::state::GraspOutcome;

    #[test]
    fn a_pose_judged_as_posed_is_told_so_and_the_advice_names_the_grasp_button() {
        let g = GraspOutcome {
            object: "ball".into(),
            preshape: "pose".into(),
            held: false,
            pose: Default::default(),
            preshape_pose: Default::default(),
            margin: 0.0,
            margin_target: Some(1.5),
            grip: 20.318,
            force_target: None,
            closing_deg: 0.0,
            preshape_grip: 20.318,
            drift: None,
            digits_touching: vec!["thumb".into()],
            trials: 1,
            search: Vec::new(),
            reason: Some(
                "as posed, let go of, the hand does not hold it: close the digits further, or \
                 leave out close = false and the hand closes to the gentlest grip that holds"
                    .into(),
            ),
            closed: false,
        };
        let line = grasp_summary(&g);
        assert!(
            line.starts_with("not held \"ball\": grip 20.32 N, friction margin 0.00 of 1.5, judged as posed — as posed"),
            "{line}"
        );
        assert!(!line.contains("already presses"), "{line}");
        assert!(line.ends_with("(here: the Grasp button)"), "{line}");
    }

    #[test]
    fn a_grasp_short_of_first_contact_and_a_preshape_into_the_object_are_told() {
        let mut g = GraspOutcome {
            object: "ball".into(),
            preshape: "pinch".into(),
            held: true,
            pose: Default::default(),
            preshape_pose: Default::default(),
            margin: 0.0,
            margin_target: None,
            grip: 13.376,
            force_target: Some(3.0),
            closing_deg: -13.78,
            preshape_grip: 13.376,
            drift: None,
            digits_touching: vec!["thumb".into()],
            trials: 1,
            search: Vec::new(),
            reason: None,
            closed: true,
        };
        let line = grasp_summary(&g);
        assert!(line.starts_with("held \"ball\" (pinch): grip 13.38 N of 3 N asked, 13.8° short of first contact, 1 poses solved"), "{line}");
        assert!(
            line.contains("already presses it with 13.38 N in the preshape"),
            "{line}"
        );
        (g.closing_deg, g.preshape_grip) = (2.5, 0.0);
        let line = grasp_summary(&g);
        assert!(
            line.contains("2.5° past first contact") && !line.contains("preshape:"),
            "{line}"
        );
        // A gravity hold let go of: how far the object moved.
        (g.force_target, g.margin_target, g.margin, g.drift) = (None, Some(1.5), 4.0, Some(2.5e-4));
        let line = grasp_summary(&g);
        assert!(
            line.contains("friction margin 4.00 of 1.5, let go of it moves 0.25 mm"),
            "{line}"
        );
    }
}
