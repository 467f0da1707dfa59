//! Named poses of the hand for tests, benchmarks and scenes.

use super::skeleton::Pose;

/// A full fist: every finger at MCP 88°, PIP 105°, DIP 70°, the thumb folded across (CMC flexion
/// 25°, CMC abduction 40°, MCP 30°, IP 30°) — issue 16's fist, near the joints' limits.
pub fn full_fist() -> Pose {
    let mut pose = Pose::new();
    for finger in ["index", "middle", "ring", "little"] {
        pose.insert(format!("{finger}.mcp.flex"), 88.0);
        pose.insert(format!("{finger}.pip"), 105.0);
        pose.insert(format!("{finger}.dip"), 70.0);
    }
    for (joint, angle) in [
        ("thumb.cmc.flex", 25.0),
        ("thumb.cmc.abd", 40.0),
        ("thumb.mcp", 30.0),
        ("thumb.ip", 30.0),
    ] {
        pose.insert(joint.to_string(), angle);
    }
    pose
}

/// The thumb folded over the closed fingers beside the index (CMC flexion 0°, abduction 25°,
/// MCP 30°, IP 70°): its bones stay at least 9.5 mm from every finger's all the way from rest
/// once the fingers are closed ([`four_finger_fist`]); [`full_fist`]'s thumb ends 2.2 mm from
/// the middle finger's bones, where flesh kept out of itself is crushed
/// (assets/scenes/hand-full-fist.toml's second keyframe; docs/hand.md, "Self-contact").
pub fn thumb_over_fist() -> Pose {
    [
        ("thumb.cmc.flex", 0.0),
        ("thumb.cmc.abd", 25.0),
        ("thumb.mcp", 30.0),
        ("thumb.ip", 70.0),
    ]
    .into_iter()
    .map(|(joint, angle)| (joint.to_string(), angle))
    .collect()
}

/// The four fingers closed as in [`full_fist`] (MCP 88°, PIP 105°, DIP 70°), the thumb at rest.
/// (Until 2026-12-05 the little finger stopped at PIP 95°, DIP 60°: at the full angles its distal
/// phalanx's bone comes within 6.2 mm of its metacarpal's, through its pulp and the palm's flesh;
/// the self-contact's Newton settled there once its steps were lengthened down the barrier's
/// negative curvature, and at resolution 1.5 once the linear flesh was kept from being crushed
/// inside out, `fem::crush_barrier`; docs/hand.md, "Self-contact".)
pub fn four_finger_fist() -> Pose {
    let mut pose = full_fist();
    pose.retain(|joint, _| super::digit_of(joint) != "thumb");
    pose
}
