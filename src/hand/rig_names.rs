//! The joints of a rigged hand by name: which node of a rig is the joint at the start of each of
//! the hand's bones, in the naming conventions of the common rigs (Mixamo, Blender's Rigify,
//! MakeHuman, Unreal Engine), and the reverse, a node name recognised whatever the convention.
//!
//! A *joint key* names a point of the hand: `wrist`, the start of a bone (`index.proximal` is the
//! MCP joint, `index.middle` the PIP, `index.distal` the DIP, `thumb.metacarpal` the thumb's
//! CMC, `index.metacarpal` the index's carpometacarpal joint) or a digit's tip (`index.tip`).

use super::anatomy::DIGITS;
use super::skeleton::Side;

/// The naming conventions recognised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Convention {
    /// Mixamo: `mixamorig:RightHandIndex1` (proximal) … `Index4` (tip); no finger metacarpals.
    Mixamo,
    /// Blender's Rigify deform bones: `DEF-f_index.01.R`, `DEF-palm.01.R`, `DEF-thumb.01.R`.
    Rigify,
    /// MakeHuman's default skeleton: `finger2-1.R` (index proximal), `metacarpal1.R` (index
    /// metacarpal), `finger1-1.R` (thumb metacarpal).
    MakeHuman,
    /// Unreal Engine's mannequin: `index_01_r`, `index_metacarpal_r`, `thumb_01_r`.
    Unreal,
}

/// Every convention, in the order they are tried.
pub const CONVENTIONS: [Convention; 4] = [
    Convention::Mixamo,
    Convention::Rigify,
    Convention::MakeHuman,
    Convention::Unreal,
];

/// The joint keys, wrist first, then per digit (thumb first) its metacarpal, proximal, middle
/// (not the thumb), distal and tip.
pub fn joint_keys() -> Vec<String> {
    let mut keys = vec!["wrist".to_string()];
    for (d, digit) in DIGITS.iter().enumerate() {
        let parts: &[&str] = if d == 0 {
            &["metacarpal", "proximal", "distal", "tip"]
        } else {
            &["metacarpal", "proximal", "middle", "distal", "tip"]
        };
        keys.extend(parts.iter().map(|p| format!("{digit}.{p}")));
    }
    keys
}

/// Joints a rig must have: the wrist and, per digit, every joint from the first phalanx's on
/// (the finger metacarpals and the tips are placed from the skin when the rig has none).
pub fn required(key: &str) -> bool {
    key == "wrist"
        || !(key.ends_with(".tip") || (key.ends_with(".metacarpal") && key != "thumb.metacarpal"))
}

/// The thumb's bones numbered from 1 (metacarpal) to 3 (distal), as every convention numbers
/// them.
fn thumb_bone(part: &str) -> Option<u8> {
    match part {
        "metacarpal" => Some(1),
        "proximal" => Some(2),
        "distal" => Some(3),
        _ => None,
    }
}

/// The node name of joint `key` for a hand of `side` in `convention`, if that convention has
/// such a node.
pub fn node_name(convention: Convention, side: Side, key: &str) -> Option<String> {
    let (digit, part) = key.split_once('.').unwrap_or((key, ""));
    let d = DIGITS.iter().position(|&n| n == digit);
    let right = side == Side::Right;
    match convention {
        Convention::Mixamo => {
            let hand = if right { "RightHand" } else { "LeftHand" };
            if key == "wrist" {
                return Some(format!("mixamorig:{hand}"));
            }
            let d = d?;
            let name = ["Thumb", "Index", "Middle", "Ring", "Pinky"][d];
            let n = match (d, part) {
                (0, "metacarpal") => 1,
                (0, "proximal") => 2,
                (0, "distal") => 3,
                (0, "tip") => 4,
                (_, "proximal") => 1,
                (_, "middle") => 2,
                (_, "distal") => 3,
                (_, "tip") => 4,
                _ => return None,
            };
            Some(format!("mixamorig:{hand}{name}{n}"))
        }
        Convention::Rigify => {
            let s = if right { "R" } else { "L" };
            if key == "wrist" {
                return Some(format!("DEF-hand.{s}"));
            }
            let d = d?;
            if d == 0 {
                return Some(format!("DEF-thumb.0{}.{s}", thumb_bone(part)?));
            }
            let name = ["", "index", "middle", "ring", "pinky"][d];
            match part {
                "metacarpal" => Some(format!("DEF-palm.0{d}.{s}")),
                "proximal" => Some(format!("DEF-f_{name}.01.{s}")),
                "middle" => Some(format!("DEF-f_{name}.02.{s}")),
                "distal" => Some(format!("DEF-f_{name}.03.{s}")),
                _ => None,
            }
        }
        Convention::MakeHuman => {
            let s = if right { "R" } else { "L" };
            if key == "wrist" {
                return Some(format!("wrist.{s}"));
            }
            let d = d?;
            if d == 0 {
                return Some(format!("finger1-{}.{s}", thumb_bone(part)?));
            }
            let n = match part {
                "metacarpal" => return Some(format!("metacarpal{d}.{s}")),
                "proximal" => 1,
                "middle" => 2,
                "distal" => 3,
                _ => return None,
            };
            Some(format!("finger{}-{n}.{s}", d + 1))
        }
        Convention::Unreal => {
            let s = if right { "r" } else { "l" };
            if key == "wrist" {
                return Some(format!("hand_{s}"));
            }
            let d = d?;
            let name = ["thumb", "index", "middle", "ring", "pinky"][d];
            let n = match (d, part) {
                (0, "metacarpal") => 1,
                (0, "proximal") => 2,
                (0, "distal") => 3,
                (_, "metacarpal") => return Some(format!("{name}_metacarpal_{s}")),
                (_, "proximal") => 1,
                (_, "middle") => 2,
                (_, "distal") => 3,
                _ => return None,
            };
            Some(format!("{name}_0{n}_{s}"))
        }
    }
}

/// A node name reduced to what the conventions differ by: lower case, without an armature
/// prefix (`mixamorig:`, `mixamorig_`, `Armature|`) or Rigify's layer prefixes (`DEF-`, `ORG-`),
/// `:` and `|` read as separators. Exporters rewrite names (Blender turns `:` into `_` in some
/// paths), so names are compared in this form.
pub fn normalized(name: &str) -> String {
    let mut s = name.trim().to_ascii_lowercase();
    if let Some(i) = s.rfind('|') {
        s = s[i + 1..].to_string();
    }
    for prefix in [
        "mixamorig:",
        "mixamorig_",
        "mixamorig",
        "def-",
        "org-",
        "def_",
        "org_",
    ] {
        if let Some(rest) = s.strip_prefix(prefix) {
            s = rest.to_string();
            break;
        }
    }
    s
}

/// The joint key a node called `name` is, in any convention, for a hand of `side`.
pub fn recognise(name: &str, side: Side) -> Option<(Convention, String)> {
    let n = normalized(name);
    for convention in CONVENTIONS {
        for key in joint_keys() {
            if let Some(expected) = node_name(convention, side, &key) {
                if normalized(&expected) == n {
                    return Some((convention, key));
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_convention_names_the_required_joints_and_reads_them_back() {
        for side in [Side::Right, Side::Left] {
            for convention in CONVENTIONS {
                for key in joint_keys() {
                    let name = node_name(convention, side, &key);
                    if required(&key) {
                        assert!(name.is_some(), "{convention:?} has no {key}");
                    }
                    if let Some(name) = name {
                        assert_eq!(
                            recognise(&name, side),
                            Some((convention, key.clone())),
                            "{name}"
                        );
                        let other = if side == Side::Right {
                            Side::Left
                        } else {
                            Side::Right
                        };
                        assert_eq!(
                            recognise(&name, other),
                            None,
                            "{name} read as the other side"
                        );
                    }
                }
            }
        }
        assert_eq!(
            recognise("mixamorig_RightHandIndex1", Side::Right),
            Some((Convention::Mixamo, "index.proximal".into()))
        );
        assert_eq!(
            recognise("f_pinky.03.L", Side::Left),
            Some((Convention::Rigify, "little.distal".into()))
        );
    }
}
