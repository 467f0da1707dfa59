//! A hand's bones after a flexion from rest, as the hand tests compare them.

use prehensile::fem::solve::FillOrdering;
use prehensile::fem::Material;
use prehensile::hand::{HandModel, Pose};
use prehensile::model::FlexionSettings;
use prehensile::solve::Flexion;
use prehensile::state::HandState;

/// The flesh of the hand scenes: soft tissue of the finger pulp.
pub const FLESH: Material = Material {
    young: 5.0e4,
    poisson: 0.45,
    density: 1050.0,
};

/// The magnitude of the reaction on each bone of `hand` (flesh [`FLESH`], default flexion
/// settings) flexed from rest to `pose`, N.
pub fn bone_reactions(hand: &HandModel, pose: &[(&str, f64)]) -> Vec<f64> {
    let materials = vec![FLESH; hand.flesh.mesh.cells.len()];
    let settings = FlexionSettings::default();
    let mut stepper = Flexion::new(hand, "hand", materials, settings, FillOrdering::Auto);
    let mut state = HandState::rest(hand);
    let pose: Pose = pose.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    let target = hand.skeleton.apply_pose(&state.angles, &pose).unwrap();
    stepper.move_to(&mut state, &target).unwrap();
    state
        .bone_reactions(hand)
        .iter()
        .map(|r| r.norm())
        .collect()
}
