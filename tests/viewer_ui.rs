//! The viewer's real widgets driven headlessly (egui_kittest, through AccessKit as a screen reader
//! would): a joint slider sends a solve request and its result replaces the shown frame; a stale
//! result is discarded; a panicking solve leaves the window alive and says so; editing a key
//! keeps the timeline frames before it.

use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use prehensile::app::jobs::{Failure, Job, JobResult, Solution, Target};
use prehensile::app::testing::{tiny_solution, FakePort};
use prehensile::app::worker::{Cancel, ThreadSolver};
use prehensile::app::ViewerState;
use prehensile::scene::{Scene, DEFAULT_SCENE};
use std::sync::Arc;
use std::time::{Duration, Instant};

fn scene() -> Scene {
    Scene::parse(DEFAULT_SCENE, "default").unwrap()
}

fn harness(state: ViewerState) -> Harness<'static, ViewerState> {
    Harness::builder()
        .with_size([1600.0, 900.0])
        .build_ui_state(|ui, state: &mut ViewerState| state.ui(ui), state)
}

/// The slider labelled `label` (its value box has the same label).
fn slider<'a>(h: &'a Harness<'static, ViewerState>, label: &'a str) -> egui_kittest::Node<'a> {
    h.get_by_role_and_label(egui::Role::Slider, label)
}

fn joint(state: &ViewerState, name: &str) -> usize {
    state.hands[0]
        .skeleton
        .dofs
        .iter()
        .position(|d| d.name == name)
        .unwrap()
}

/// The x of the first vertex drawn: tells the fake solutions apart.
fn shown_x(state: &ViewerState) -> Option<f32> {
    state
        .shown
        .as_ref()
        .map(|s| s.solution.draw_list.surfaces[0].positions[0][0])
}

fn pose_jobs(port: &FakePort) -> Vec<Job> {
    port.jobs()
        .into_iter()
        .filter(|j| matches!(j.target, Target::Pose { .. }))
        .collect()
}

fn pose_angle(job: &Job, joint: usize) -> f64 {
    match &job.target {
        Target::Pose { pose, .. } => pose[0].1[joint],
        _ => panic!("not a pose job"),
    }
}

/// A state on the default scene whose first request (version 1) is answered with a frame at x = 0.
fn answered() -> (FakePort, Harness<'static, ViewerState>) {
    let port = FakePort::new();
    let mut state = ViewerState::new(scene(), "default", Box::new(port.clone())).unwrap();
    state.timeline_solving = false;
    let mut h = harness(state);
    assert_eq!(
        pose_jobs(&port).len(),
        1,
        "the first frame is requested at start"
    );
    port.answer_frame(1, 0.0, None);
    h.step();
    assert_eq!(shown_x(h.state()), Some(0.0));
    (port, h)
}

#[test]
fn moving_a_joint_slider_requests_a_solve_and_shows_its_result() {
    let (port, mut h) = answered();
    let pip = joint(h.state(), "index.pip");
    slider(&h, "index.pip").set_value_accesskit(40.0);
    h.step();
    let jobs = pose_jobs(&port);
    assert_eq!(jobs.len(), 2, "one request for the slider change");
    let job = jobs.last().unwrap();
    assert_eq!(pose_angle(job, pip), 40.0);
    assert!(job.version > 1);
    assert!(
        h.state().computing(),
        "the status says the frame is being computed"
    );
    // The old frame stays until the result arrives, then the new one is shown.
    assert_eq!(shown_x(h.state()), Some(0.0));
    port.answer_frame(job.version, 5.0, None);
    h.step();
    assert_eq!(shown_x(h.state()), Some(5.0));
    assert_eq!(h.state().shown.as_ref().unwrap().version, job.version);
    assert!(!h.state().computing());
    h.get_by_label("shown frame is current");
}

#[test]
fn a_stale_result_is_discarded() {
    let (port, mut h) = answered();
    slider(&h, "index.pip").set_value_accesskit(30.0);
    h.step();
    slider(&h, "index.pip").set_value_accesskit(60.0);
    h.step();
    let jobs = pose_jobs(&port);
    assert_eq!(jobs.len(), 3);
    let (older, newer) = (jobs[1].version, jobs[2].version);
    assert!(newer > older);
    // The result of the superseded request arrives late: it is not shown.
    port.answer_frame(older, 3.0, None);
    h.step();
    assert_eq!(shown_x(h.state()), Some(0.0));
    assert_eq!(h.state().status.discarded, 1);
    assert!(h.state().computing());
    port.answer_frame(newer, 6.0, None);
    h.step();
    assert_eq!(shown_x(h.state()), Some(6.0));
}

#[test]
fn a_failed_solve_keeps_the_last_good_frame_and_says_why() {
    let (port, mut h) = answered();
    slider(&h, "index.pip").set_value_accesskit(100.0);
    h.step();
    let v = pose_jobs(&port).last().unwrap().version;
    port.answer_failure(
        v,
        Failure::Error("flesh element 12 would turn inside out".into()),
    );
    h.step();
    assert_eq!(shown_x(h.state()), Some(0.0));
    h.get_by_label_contains("flesh element 12 would turn inside out");
}

/// A draft of the pose asked (a preview, or a frame whose contact is being settled) is shown
/// while the job runs, the Status panel saying `said`; when the pose then fails with `error`,
/// the last solved frame comes back with the error, not the draft of a pose that has no
/// solution.
fn draft_until_its_pose_fails(draft: fn(&mut Solution), said: &str, error: &str) {
    let (port, mut h) = answered();
    slider(&h, "index.pip").set_value_accesskit(100.0);
    h.step();
    let job = pose_jobs(&port).last().unwrap().clone();
    let v = job.version;
    let mut shown = tiny_solution(9.0, None);
    draft(&mut shown);
    shown.visual = job.visual;
    port.answer(JobResult {
        version: v,
        outcome: Ok(shown),
        finished: false,
    });
    h.step();
    let drafted = |s: &ViewerState| s.showing_preview() || s.showing_settling();
    assert_eq!(shown_x(h.state()), Some(9.0));
    assert!(h.state().computing() && drafted(h.state()));
    h.get_by_label_contains(said);
    port.answer_failure(v, Failure::Error(error.into()));
    h.step();
    assert_eq!(shown_x(h.state()), Some(0.0));
    assert!(!h.state().computing() && !drafted(h.state()));
    h.get_by_label_contains(error);
}

/// A pose job's preview ("shown: a preview" in Status), its pose then failing.
#[test]
fn a_preview_is_shown_until_its_pose_fails_then_the_last_solved_frame() {
    draft_until_its_pose_fails(
        |s| s.preview = true,
        "shown: a preview",
        "flesh element 12 would turn inside out",
    );
}

/// A frame solved at the pose while its contact settles ("its contact is being settled"), the
/// corrections then failing: the last settled frame comes back, not the draft of a pose that
/// did not settle (whose stresses, left pending unless drawn, would also be what showed a cell
/// turned inside out).
#[test]
fn a_settling_frame_is_shown_until_its_pose_fails_then_the_last_solved_frame() {
    draft_until_its_pose_fails(
        |s| s.settling = true,
        "its contact is being settled",
        "the corrections at the pose did not settle",
    );
}

#[test]
fn a_panicking_solve_leaves_the_ui_alive_and_says_so() {
    let pip = {
        let s = scene();
        let hands = prehensile::app::pose::hands_of(&s);
        hands[0]
            .skeleton
            .dofs
            .iter()
            .position(|d| d.name == "index.pip")
            .unwrap()
    };
    // The real solver thread, with a solve that panics past 50° at the index PIP.
    let solve = move |job: &Job, _: &Cancel, emit: &mut dyn FnMut(Result<Solution, Failure>)| {
        if let Target::Pose { pose, .. } = &job.target {
            if pose[0].1[pip] > 50.0 {
                panic!("index.pip beyond 50° (test double)");
            }
            let mut s = tiny_solution(pose[0].1[pip] as f32, None);
            s.visual = job.visual;
            emit(Ok(s));
        }
    };
    let port = ThreadSolver::spawn(solve, Arc::new(|| {}));
    let mut state = ViewerState::new(scene(), "default", Box::new(port)).unwrap();
    state.timeline_solving = false;
    let mut h = harness(state);
    let wait = |h: &mut Harness<'static, ViewerState>, done: &dyn Fn(&ViewerState) -> bool| {
        let start = Instant::now();
        while !done(h.state()) {
            assert!(start.elapsed() < Duration::from_secs(30), "no answer");
            std::thread::sleep(Duration::from_millis(5));
            h.step();
        }
    };
    wait(&mut h, &|s| s.shown.is_some());
    let good = shown_x(h.state()).unwrap();
    slider(&h, "index.pip").set_value_accesskit(80.0);
    h.step();
    wait(&mut h, &|s| s.status.error.is_some());
    let error = h.state().status.error.clone().unwrap();
    assert!(
        error.contains("panicked") && error.contains("beyond 50°"),
        "{error}"
    );
    h.get_by_label_contains("the solver panicked");
    assert_eq!(shown_x(h.state()), Some(good), "the last good frame stays");
    // The thread survived: the next request is solved and clears the failure.
    slider(&h, "index.pip").set_value_accesskit(20.0);
    h.step();
    wait(&mut h, &|s| shown_x(s) == Some(20.0));
    assert!(h.state().status.error.is_none());
}

#[test]
fn editing_a_key_keeps_the_frames_before_it() {
    let port = FakePort::new();
    let state = ViewerState::new(scene(), "default", Box::new(port.clone())).unwrap();
    let mut h = harness(state);
    port.answer_frame(1, 0.0, None);
    h.step();
    // Idle with unsolved keys: the timeline is requested from key 0, from rest.
    let job = port.jobs().last().unwrap().clone();
    let Target::Timeline {
        first,
        start,
        poses,
    } = &job.target
    else {
        panic!("a timeline job")
    };
    assert_eq!((*first, start.is_none(), poses.len()), (0, true, 3));
    for i in 0..3 {
        port.answer_frame(job.version, 10.0 + i as f32, Some(i));
    }
    h.step();
    assert_eq!(h.state().timeline.first_unsolved(), None);
    // Scrub to key 2, move the index PIP, and set the key: only key 2's frame is dropped.
    h.state_mut().scrub_to(2);
    h.step();
    assert_eq!(shown_x(h.state()), Some(12.0));
    slider(&h, "index.pip").set_value_accesskit(70.0);
    h.step();
    h.get_by_label("Set key to current pose").click();
    h.step();
    let frames = &h.state().timeline.frames;
    assert!(frames[0].is_some() && frames[1].is_some() && frames[2].is_none());
    // The pose request is answered; then the timeline resumes at key 2 from frame 1.
    let v = pose_jobs(&port).last().unwrap().version;
    port.answer_frame(v, 7.0, None);
    h.step();
    h.step();
    let job = port.jobs().last().unwrap().clone();
    let Target::Timeline {
        first,
        start,
        poses,
    } = &job.target
    else {
        panic!("a timeline job")
    };
    assert_eq!((*first, poses.len()), (2, 1));
    let start = start.as_ref().expect("starts from the cached frame 1");
    let frame1 = &h.state().timeline.frames[1].as_ref().unwrap().frame;
    assert!(Arc::ptr_eq(start, frame1));
    let pip = joint(h.state(), "index.pip");
    assert_eq!(poses[0][0].1[pip], 70.0);
}

#[test]
fn presets_and_reset_move_the_sliders_and_request_frames() {
    let (port, mut h) = answered();
    let pip = joint(h.state(), "index.pip");
    h.get_by_label("Fist").click();
    h.step();
    let job = pose_jobs(&port).last().unwrap().clone();
    assert_eq!(pose_angle(&job, pip), 105.0);
    assert_eq!(h.state().pose[0].1[pip], 105.0);
    h.get_by_label("Reset").click();
    h.step();
    let job = pose_jobs(&port).last().unwrap().clone();
    assert_eq!(pose_angle(&job, pip), 15.0, "the scene's initial pose");
}

#[test]
fn object_edits_rebuild_the_scene_ball() {
    let (port, mut h) = answered();
    let before = port.jobs().last().unwrap().scene_revision;
    slider(&h, "Young's modulus").set_value_accesskit(1.0e9);
    h.step();
    let job = port.jobs().last().unwrap().clone();
    assert!(job.scene_revision > before, "a new model");
    let ball = job.scene.material.iter().find(|m| m.young == 1.0e9);
    assert!(ball.is_some(), "the ball's material is in the scene sent");
    assert!(job
        .scene
        .material
        .iter()
        .any(|m| m.name == "flesh" && m.young == 5.0e4));
}

/// The skin's friction on the ball, set in the Object panel, goes to the solver as the scene's
/// `[[friction]]` pair of the hand's flesh and the ball's material (the default scene has none:
/// a hold against gravity is not held without it, and its status points here).
#[test]
fn the_skin_friction_slider_pairs_flesh_and_ball() {
    let (port, mut h) = answered();
    assert!(port.jobs().last().unwrap().scene.friction.is_empty());
    slider(&h, "skin friction μ").set_value_accesskit(0.8);
    h.step();
    let job = port.jobs().last().unwrap().clone();
    let ball = &job
        .scene
        .body
        .iter()
        .find(|b| b.name == "ball")
        .unwrap()
        .material;
    let pair = job
        .scene
        .friction
        .iter()
        .find(|f| f.between.contains(ball) && f.between.contains(&"flesh".to_string()))
        .unwrap_or_else(|| panic!("{:?}", job.scene.friction));
    assert_eq!(pair.mu, 0.8);
}

#[test]
fn the_far_fingers_checkbox_writes_the_scene_key() {
    use prehensile::scene::FarFromContact;
    let (port, mut h) = answered();
    assert!(
        h.state().solver.skin_far_fingers,
        "skinning far fingers is the default"
    );
    h.get_by_label("skin fingers far from contact").click();
    h.step();
    let job = port.jobs().last().unwrap().clone();
    assert_eq!(
        job.scene.solver.far_from_contact,
        Some(FarFromContact::Solve)
    );
    let model = prehensile::model::Model::build(&job.scene, "viewer").unwrap();
    assert_eq!(model.flexion.near_contact, None);
}

/// The Solver panel's self-contact checkbox writes `[solver] self_contact` (off by default, as
/// in the scene), and the model built from the job keeps the skin out of itself.
#[test]
fn the_self_contact_checkbox_writes_the_scene_key() {
    let (port, mut h) = answered();
    assert!(!h.state().solver.self_contact);
    h.get_by_label("skin kept out of itself").click();
    h.step();
    let job = port.jobs().last().unwrap().clone();
    assert_eq!(job.scene.solver.self_contact, Some(true));
    let model = prehensile::model::Model::build(&job.scene, "viewer").unwrap();
    assert!(model.flexion.self_contact.is_some());
    h.get_by_label("skin kept out of itself").click();
    h.step();
    let job = port.jobs().last().unwrap().clone();
    assert_eq!(job.scene.solver.self_contact, Some(false));
    let model = prehensile::model::Model::build(&job.scene, "viewer").unwrap();
    assert!(model.flexion.self_contact.is_none());
}

/// The Solver panel's "cells split" slider writes the hand's `subdivisions` (absent, 1, in the
/// default scene), and the hand built from the job has each cell of its lattice split in eight.
#[test]
fn the_cells_split_slider_refines_the_hand_nested() {
    use prehensile::scene::Shape;
    let (port, mut h) = answered();
    assert_eq!(h.state().solver.subdivisions, 1);
    let before = port.jobs().last().unwrap().clone();
    slider(&h, "cells split").set_value_accesskit(2.0);
    h.run_steps(2);
    let job = port.jobs().last().unwrap().clone();
    assert!(job.scene_revision > before.scene_revision, "a new model");
    let written = job.scene.body.iter().find_map(|b| match &b.shape {
        Shape::Hand { subdivisions, .. } => Some(*subdivisions),
        _ => None,
    });
    assert_eq!(written, Some(Some(2)));
    let cells = |scene: &Scene| {
        let model = prehensile::model::Model::build(scene, "viewer").unwrap();
        let hand = model.bodies.iter().find_map(|b| b.hand.clone()).unwrap();
        (hand.flesh.mesh.cells.len(), hand.subdivisions)
    };
    let (coarse, n1) = cells(&before.scene);
    let (fine, n2) = cells(&job.scene);
    assert_eq!((n1, n2), (1, 2));
    assert_eq!(fine, 8 * coarse);
}

/// With the skin kept out of itself, the Fist preset goes in two stages, each solved before the
/// next is asked: the four fingers close (every one at PIP 105°, DIP 70°), the thumb
/// where it was; then the thumb folds over (IP 70°). Without self-contact, one pose. A slider
/// moved before the first stage is solved drops the second.
#[test]
fn the_fist_with_self_contact_closes_the_fingers_then_the_thumb() {
    let (port, mut h) = answered();
    let (pip, little, thumb) = (
        joint(h.state(), "index.pip"),
        joint(h.state(), "little.pip"),
        joint(h.state(), "thumb.ip"),
    );
    let thumb_before = h.state().pose[0].1[thumb];
    h.get_by_label("skin kept out of itself").click();
    h.step();
    port.answer_frame(pose_jobs(&port).last().unwrap().version, 1.0, None);
    h.step();
    h.get_by_label("Fist").click();
    h.step();
    let first = pose_jobs(&port).last().unwrap().clone();
    assert_eq!(pose_angle(&first, pip), 105.0);
    assert_eq!(pose_angle(&first, little), 105.0);
    assert_eq!(pose_angle(&first, thumb), thumb_before);
    let asked = pose_jobs(&port).len();
    h.step();
    assert_eq!(
        pose_jobs(&port).len(),
        asked,
        "the thumb waits for the fingers"
    );
    port.answer_frame(first.version, 2.0, None);
    h.step();
    h.step();
    let second = pose_jobs(&port).last().unwrap().clone();
    assert!(second.version > first.version);
    assert_eq!(pose_angle(&second, thumb), 70.0);
    assert_eq!(pose_angle(&second, pip), 105.0);
    assert_eq!(h.state().pose[0].1[thumb], 70.0);
    port.answer_frame(second.version, 3.0, None);
    h.step();
    assert!(!h.state().computing());

    // A slider moved meanwhile: the thumb stays where the slider put it.
    h.get_by_label("Rest").click();
    h.step();
    port.answer_frame(pose_jobs(&port).last().unwrap().version, 4.0, None);
    h.step();
    h.get_by_label("Fist").click();
    h.step();
    let first = pose_jobs(&port).last().unwrap().clone();
    slider(&h, "index.pip").set_value_accesskit(60.0);
    h.step();
    let moved = pose_jobs(&port).last().unwrap().clone();
    port.answer_frame(first.version, 5.0, None);
    port.answer_frame(moved.version, 6.0, None);
    h.step();
    h.step();
    assert_eq!(pose_jobs(&port).last().unwrap().version, moved.version);
    assert_eq!(h.state().pose[0].1[thumb], 0.0);

    // Without self-contact the Fist is one pose, the thumb across.
    h.get_by_label("skin kept out of itself").click();
    h.step();
    port.answer_frame(pose_jobs(&port).last().unwrap().version, 7.0, None);
    h.step();
    h.get_by_label("Fist").click();
    h.step();
    let one = pose_jobs(&port).last().unwrap().clone();
    assert_eq!(pose_angle(&one, little), 105.0);
    assert_eq!(pose_angle(&one, thumb), 30.0);
    port.answer_frame(one.version, 8.0, None);
    h.step();
    h.step();
    assert_eq!(pose_jobs(&port).last().unwrap().version, one.version);
}

/// The File panel's glTF button writes the solved timeline frames as one animated
/// `animation.glb`: one mesh per surface, a morph target per later frame, the keys' times.
#[test]
fn the_gltf_button_exports_the_solved_timeline() {
    let port = FakePort::new();
    let state = ViewerState::new(scene(), "default", Box::new(port.clone())).unwrap();
    let mut h = harness(state);
    port.answer_frame(1, 0.0, None);
    h.step();
    // Before any timeline frame: told so, nothing written.
    let dir = std::env::temp_dir().join(format!("prehensile-gltf-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    h.state_mut().export_dir = dir.display().to_string();
    h.state_mut()
        .timeline
        .frames
        .iter_mut()
        .for_each(|f| *f = None);
    h.get_by_label("glTF").click_accesskit();
    h.step();
    let message = h.state().status.message.clone().unwrap_or_default();
    assert!(
        message.starts_with("no glTF"),
        "{message:?} {:?}",
        h.state().status.error
    );
    assert!(!dir.join("animation.glb").exists());
    // The timeline solved (three keys): written.
    let job = port.jobs().last().unwrap().clone();
    for i in 0..3 {
        port.answer_frame(job.version, 10.0 + i as f32, Some(i));
    }
    h.step();
    h.get_by_label("glTF").click_accesskit();
    h.step();
    let message = h.state().status.message.clone().unwrap_or_default();
    assert!(
        message.starts_with("wrote") && message.ends_with("animation.glb"),
        "{message}"
    );
    let gltf = gltf::Gltf::from_slice(&std::fs::read(dir.join("animation.glb")).unwrap()).unwrap();
    let blob = gltf.blob.clone().unwrap();
    let mesh = gltf.meshes().next().unwrap();
    assert_eq!(mesh.name(), Some("b"));
    let primitive = mesh.primitives().next().unwrap();
    let reader = primitive.reader(|_| Some(&blob[..]));
    assert_eq!(reader.read_morph_targets().count(), 2);
    let times: Vec<f32> = gltf
        .animations()
        .next()
        .unwrap()
        .channels()
        .next()
        .unwrap()
        .reader(|_| Some(&blob[..]))
        .read_inputs()
        .unwrap()
        .collect();
    let keys: Vec<f32> = h
        .state()
        .timeline
        .keys
        .iter()
        .map(|k| k.time as f32)
        .collect();
    assert_eq!(times, keys);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Solver panel's hand size menu writes the hand's `size` into the scene sent to the
/// solver, and the hand built from it is that size: the 50th-percentile woman's is 180 mm
/// from the wrist's cut to the middle finger's tip.
#[test]
fn the_hand_size_menu_rebuilds_the_hand_at_that_size() {
    use prehensile::scene::{HandSizeDef, Shape};
    let (port, mut h) = answered();
    let before = port.jobs().last().unwrap().scene_revision;
    h.get_by_role_and_label(egui::Role::ComboBox, "hand size")
        .click();
    h.run_steps(2);
    h.get_by_label("ANSUR II women 50th: 180 × 78 mm").click();
    h.run_steps(2);
    let job = port.jobs().last().unwrap().clone();
    assert!(job.scene_revision > before, "a new model");
    let size = job.scene.body.iter().find_map(|b| match &b.shape {
        Shape::Hand { size, .. } => Some(size.clone()),
        _ => None,
    });
    assert_eq!(
        size,
        Some(Some(HandSizeDef::Percentile("female-50".into())))
    );
    let model = prehensile::model::Model::build(&job.scene, "viewer").unwrap();
    let hand = model.bodies.iter().find_map(|b| b.hand.clone()).unwrap();
    let tip = hand
        .flesh
        .mesh
        .nodes
        .iter()
        .map(|p| p.x)
        .fold(f64::NEG_INFINITY, f64::max);
    let wrist = prehensile::hand::anatomy::PALM.wrist_x;
    assert!(
        ((tip - wrist) - 0.180).abs() < 1e-3,
        "hand length {} m",
        tip - wrist
    );
}

/// The Solver panel's hand form menu writes the hand's `form` into the scene sent to the
/// solver, and the hand built from it is of that form: the default scene's anatomical hand
/// (its thumb resting at `thumb.cmc.abd` = 20°, 26.8° out of the palm's plane) turned simple
/// (at 0°, 6.8°) and back.
#[test]
fn the_hand_form_menu_rebuilds_the_hand_in_that_form() {
    use prehensile::scene::Shape;
    let (port, mut h) = answered();
    let mut before = port.jobs().last().unwrap().scene_revision;
    for (form, rest, out) in [("simple", 0.0, 6.8), ("anatomical", 20.0, 26.8)] {
        h.get_by_role_and_label(egui::Role::ComboBox, "hand form")
            .click();
        h.run_steps(2);
        h.get_by_label(form).click();
        h.run_steps(2);
        let job = port.jobs().last().unwrap().clone();
        assert!(job.scene_revision > before, "{form}: a new model");
        before = job.scene_revision;
        let written = job.scene.body.iter().find_map(|b| match &b.shape {
            Shape::Hand { form, .. } => Some(form.clone()),
            _ => None,
        });
        assert_eq!(written, Some(Some(form.to_string())));
        let model = prehensile::model::Model::build(&job.scene, "viewer").unwrap();
        let hand = model.bodies.iter().find_map(|b| b.hand.clone()).unwrap();
        let sk = &hand.skeleton;
        let abd = sk
            .dofs
            .iter()
            .position(|d| d.name == "thumb.cmc.abd")
            .unwrap();
        assert_eq!(sk.rest_angles()[abd], rest, "{form}");
        let b = &sk.bones[sk.bone_index("thumb.metacarpal").unwrap()];
        let angle = (b.end - b.start).normalize().z.abs().asin().to_degrees();
        assert!(
            (angle - out).abs() < 0.1,
            "{form}: the thumb {angle}° out of the palm"
        );
    }
}

/// The default scene's anatomical hand opens at its rest: the thumb's abduction slider reads
/// 20° (the thumb at its natural rest, not moved back into the palm's plane by the first frame
/// asked), and the Rest preset returns it there; the simple form's rest is 0°.
#[test]
fn the_anatomical_hand_opens_and_rests_with_its_thumb_at_its_natural_rest() {
    for (form, rest) in [("anatomical", 20.0), ("simple", 0.0)] {
        let mut scene = scene();
        for body in &mut scene.body {
            if let prehensile::scene::Shape::Hand { form: f, .. } = &mut body.shape {
                *f = Some(form.into());
            }
        }
        let port = FakePort::new();
        let mut state = ViewerState::new(scene, "default", Box::new(port.clone())).unwrap();
        state.timeline_solving = false;
        let mut h = harness(state);
        let abd = joint(h.state(), "thumb.cmc.abd");
        let first = pose_jobs(&port)[0].clone();
        assert_eq!(
            pose_angle(&first, abd),
            rest,
            "{form}: the first frame asked"
        );
        port.answer_frame(first.version, 0.0, None);
        h.step();
        h.get_by_label("Power grasp").click();
        h.step();
        assert_eq!(
            h.state().pose[0].1[abd],
            35.0,
            "{form}: the preset names it"
        );
        port.answer_frame(pose_jobs(&port).last().unwrap().version, 1.0, None);
        h.step();
        h.get_by_label("Rest").click();
        h.step();
        let last = pose_jobs(&port).last().unwrap().clone();
        assert_eq!(pose_angle(&last, abd), rest, "{form}: Rest");
    }
}
