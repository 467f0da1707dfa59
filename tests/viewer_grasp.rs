//! The viewer's Grasp row (issue 17) on the built-in default scene, with the real solver thread,
//! driven through the real widgets (egui_kittest): "grip force" then Grasp closes the hand on
//! the ball to the least closing that presses it with the 5 N asked; the sliders go to the pose
//! found and the status says what was found; "Does it hold?" judges that pose as posed (held,
//! the same grip, nothing added to the timeline). "hold against gravity" then Grasp, on a scene
//! with no friction, is a result too: not held, and why.

use crate::common;

use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use prehensile::app::ViewerState;
use prehensile::state::GraspOutcome;
use std::time::{Duration, Instant};

/// Steps the UI until nothing is being computed; returns the grasp outcome of the shown frame.
fn settle(h: &mut Harness<'static, ViewerState>) -> Option<GraspOutcome> {
    let start = Instant::now();
    loop {
        h.step();
        let s = h.state();
        if let Some(e) = &s.status.error {
            panic!("the viewer reports: {e}");
        }
        if !s.computing() && s.shown.as_ref().is_some_and(|x| !x.solution.preview) {
            return s.shown.as_ref().unwrap().solution.frame.hands[0]
                .grasp
                .clone();
        }
        assert!(
            start.elapsed() < Duration::from_secs(600),
            "no result after 10 minutes: {:?}",
            s.status
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn the_grasp_button_closes_the_hand_to_the_grip_asked() {
    let mut h = common::viewer::default_viewer();
    assert!(settle(&mut h).is_none(), "the scene's own pose is no grasp");
    assert_eq!(h.state().grasp.object, "ball");

    h.get_by_label("grip force").click();
    h.run();
    assert_eq!(h.state().grasp.force, Some(5.0));
    let keys_before = h.state().timeline.keys.len();
    h.get_by_label("Grasp").click();
    let g = settle(&mut h).expect("the grasp's frame carries its outcome");
    assert!(g.held, "{g:?}");
    assert!(g.grip >= 5.0 && g.grip <= 5.5, "grip {} N", g.grip);
    let s = h.state();
    let frame = &s.shown.as_ref().unwrap().solution.frame;
    // The sliders are at the pose found, which is the frame's: not rounded to their display's
    // whole degrees (which re-solved the hand at another pose and lost the grasp).
    assert_eq!(s.pose[0].1, frame.hands[0].angles);
    assert!(s.pose[0].1.iter().any(|a| a.fract() != 0.0));
    let status = s.status.grasp.clone().unwrap();
    assert!(status.starts_with("held \"ball\" (power)"), "{status}");
    // The closing is on the timeline: the preshape, then the grip found, as two keys after
    // the one that was current, in time order.
    let t = &s.timeline;
    assert_eq!(t.keys.len(), keys_before + 2);
    let (pre, grip) = (&t.keys[t.current - 1], &t.keys[t.current]);
    assert_eq!(grip.pose[0].1, frame.hands[0].angles);
    let skeleton = &s.hands[0].skeleton;
    assert_eq!(skeleton.pose_of(&pre.pose[0].1), g.preshape_pose);
    assert!(
        g.preshape_pose["index.pip"] < g.pose["index.pip"],
        "the grip closes past the preshape: {} against {}",
        g.pose["index.pip"],
        g.preshape_pose["index.pip"]
    );
    assert!(t.keys[t.current - 2].time < pre.time && pre.time < grip.time);
    let keys_after_grasp = t.keys.len();
    let found = s.pose[0].1.clone();

    // "Does it hold?" on the pose found: judged as posed (no closing, `close = false`), it
    // presses the ball as the grasp found (the same pose solved again from itself), held; the
    // sliders stay and nothing is added to the timeline.
    h.get_by_label("Does it hold?").click();
    let judged = settle(&mut h).expect("the judged pose's frame carries its outcome");
    println!("{judged:?}");
    assert!(judged.held && !judged.closed, "{judged:?}");
    assert_eq!((judged.closing_deg, judged.trials), (0.0, 1));
    assert!(
        (judged.grip - g.grip).abs() <= 0.02 * g.grip,
        "judged {} N against the grasp's {} N",
        judged.grip,
        g.grip
    );
    let s = h.state();
    assert_eq!(s.pose[0].1, found);
    assert_eq!(s.timeline.keys.len(), keys_after_grasp);
    let status = s.status.grasp.clone().unwrap();
    assert!(
        status.starts_with("held \"ball\": grip")
            && status.contains("of 5 N asked, judged as posed"),
        "{status}"
    );

    // A slider moved after the grasp: its preview and its result are no grasp (the preview
    // carried the grasp frame's outcome until 2026-11-27 and added the closing again).
    h.get_by_role_and_label(egui::Role::Slider, "index.pip")
        .set_value_accesskit(g.pose["index.pip"] + 3.0);
    h.step();
    assert!(settle(&mut h).is_none(), "a pose moved by hand is no grasp");
    assert_eq!(h.state().timeline.keys.len(), keys_after_grasp);
    assert_eq!(h.state().status.grasp, None);

    // Against gravity, without friction between skin and rubber: not held, and why.
    h.get_by_label("hold against gravity").click();
    h.run();
    h.get_by_label("Grasp").click();
    let g = settle(&mut h).expect("an outcome");
    assert!(!g.held);
    // Not held after its first contact alone (closing 0°): no closing to put on the timeline.
    assert_eq!(g.closing_deg, 0.0);
    assert_eq!(h.state().timeline.keys.len(), keys_after_grasp);
    let status = h.state().status.grasp.clone().unwrap();
    assert!(
        status.starts_with("not held")
            && status.contains("μ = 0")
            && status.ends_with("(here: the Object panel's skin friction μ)"),
        "{status}"
    );
}
