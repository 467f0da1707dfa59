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
