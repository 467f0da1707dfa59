//! An object held by the hand alone (issue 17's let-go): equilibrium, Coulomb's cone, no
//! penetration.

use nalgebra::Vector3;

/// The body `object` held by the hand alone in the last frame of `solved`, under `gravity`
/// (m/s²) with skin friction `mu`: its load is its weight; the contact forces on it (normal and
/// friction) balance that weight to 10⁻³ of the gross contact force (what the stabilising
/// springs may carry); every contact lies within its Coulomb cone; nothing goes through the
/// skin by more than the contact tolerance.
pub fn held_by_the_hand_alone(
    solved: &prehensile::headless::Solved,
    object: &str,
    gravity: Vector3<f64>,
    mu: f64,
) {
    let model = &solved.model;
    let frame = solved.frames.last().unwrap();
    let body = model.bodies.iter().position(|b| b.name == object).unwrap();
    let nodes = model.bodies[body].nodes.clone();
    let mut load = Vector3::<f64>::zeros();
    for n in nodes.clone() {
        for a in 0..3 {
            load[a] += model.load_vector[3 * n + a];
        }
    }
    let weight = model.bodies[body].mass * gravity;
    assert!(
        (load - weight).norm() < 1e-9 * weight.norm(),
        "load {load:?} against the weight {weight:?}"
    );
    let contact = frame.contact.as_ref().expect("in contact");
    let mut on_object = Vector3::<f64>::zeros();
    let mut gross = 0.0;
    for c in &contact.contacts {
        for (n, f) in c.nodal_forces() {
            if nodes.contains(&n) {
                on_object += f;
                gross += f.norm();
            }
        }
        assert!(
            c.tangential.norm() <= mu * c.force * (1.0 + 1e-6) + 1e-12,
            "friction {} over μλ = {}",
            c.tangential.norm(),
            mu * c.force
        );
    }
    let unbalanced = (on_object + load).norm();
    assert!(
        unbalanced < 1e-3 * gross.max(weight.norm()),
        "contact on {object} {on_object:?} against its weight {weight:?} N: {unbalanced} N left"
    );
    assert!(contact.max_penetration <= model.contact.tolerance * 1.01);
}
