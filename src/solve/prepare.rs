//! What the first keyframe of a workspace would acquire on its way, acquired ahead: for a
//! solver thread that is idle once a model is shown (the viewer's). Each hand whose flexion
//! factorizes linear increments gets the memory of its largest factorization (the FEM region
//! of every FEM cell) written once: the first factorization of a process otherwise pays for
//! the pages of its factor (the hand's 61 MB at resolution 1). Measured on the default scene in
//! docs/performance.md ("Memory acquired ahead").
//!
//! Nothing here changes a result: the keyframes after it solve the same equations in the same
//! elimination order.

use super::driver::{hand_stepper, Posed, Workspace};
use super::flexion::CancelCheck;
use super::SimError;
use crate::model::Model;

impl Workspace {
    /// Acquires ahead what the first keyframe from `posed` would acquire on its way (see the
    /// module). `cancel` is asked before each hand: once it answers `true`, the rest is left to
    /// the keyframe that needs it.
    pub fn prepare(
        &mut self,
        model: &Model,
        posed: &Posed,
        cancel: Option<&CancelCheck>,
    ) -> Result<(), SimError> {
        for hand in &posed.hands {
            if cancel.is_some_and(|c| c()) {
                return Ok(());
            }
            if model.bodies[hand.body].hand.is_none() {
                continue;
            }
            let mut stepper = hand_stepper(model, &mut self.caches, hand.body);
            let prepared = stepper.prepare(&hand.state);
            self.caches.push((hand.body, stepper.into_caches()));
            prepared?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// A workspace prepared ahead flexes the index PIP to 45° to the same flesh as one that
    /// was not, bit for bit, and acquires no factor memory on the way: what it would have
    /// acquired was held already.
    #[test]
    fn memory_acquired_ahead_changes_no_result_and_is_what_the_keyframe_needs() {
        let text = include_str!("../../assets/scenes/finger-flexion.toml")
            .replace("resolution = 1.0", "resolution = 0.75");
        let scene = Scene::parse(&text, "finger-flexion.toml").unwrap();
        let model = Model::build(&scene, "finger-flexion.toml").unwrap();
        let held = |ws: &Workspace| {
            ws.caches
                .first()
                .map_or(0, |c| c.1.solver.factor_capacity())
        };
        let flex = |prepared: bool| {
            let mut workspace = Workspace::new(&model).unwrap();
            let mut posed = Posed::rest(&model);
            let before = if prepared {
                workspace.prepare(&model, &posed, None).unwrap();
                held(&workspace)
            } else {
                0
            };
            let hand = &model.bodies[posed.hands[0].body];
            let dofs = &hand.hand.as_ref().unwrap().skeleton.dofs;
            let pip = dofs.iter().position(|d| d.name == "index.pip").unwrap();
            let mut angles = posed.hands[0].state.angles.clone();
            angles[pip] = 45.0;
            let body = posed.hands[0].body;
            let frame = workspace
                .move_hands(&model, &mut posed, &[(body, angles)], None)
                .unwrap();
            (frame, before, held(&workspace))
        };
        let (cold, _, cold_held) = flex(false);
        let (warm, before, after) = flex(true);
        assert!(cold_held > 0, "the keyframe factorized");
        assert!(
            before >= cold_held,
            "prepared {before} entries, the keyframe needed {cold_held}"
        );
        assert_eq!(
            after, before,
            "the keyframe acquired factor memory after all"
        );
        assert_eq!(warm.solution.displacement, cold.solution.displacement);
        assert_eq!(
            warm.hands[0].stats.factorizations,
            cold.hands[0].stats.factorizations
        );
    }
}
