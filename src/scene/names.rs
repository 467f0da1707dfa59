//! The scene file's own names for the solver's choices. The file format owns them (their
//! spelling in TOML is part of it); `model` converts each once into the solver's enum.

use serde::{Deserialize, Serialize};

/// How the scene file spells `value` (one of the names below: `"corotational"`,
/// `"incompatible_modes"` …), from its serde name: the messages quote the file's own word.
pub fn spelling<T: Serialize>(value: &T) -> String {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(s)) => s,
        _ => unreachable!("the scene's names serialise as strings"),
    }
}

/// `side` of a built-in hand.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum HandSide {
    /// Right hand (thumb towards +y).
    Right,
    /// Left hand (mirror image in y).
    Left,
}

/// `[solver] skinning`: how bone motions are blended.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BlendName {
    /// Linear blend skinning.
    Linear,
    /// Dual-quaternion skinning (the default).
    DualQuaternion,
}

/// `[solver] flesh` and `flesh_digits`: how the flesh of a part of a hand moves.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FleshMethodName {
    /// Finite elements (the default).
    Fem,
    /// Geometric skinning only.
    Skinning,
}

/// `[solver] flexion`: the scheme of the flexion increments.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum FlexionSchemeName {
    /// The paper's updated-Lagrangian increments.
    UpdatedLagrangian,
    /// Corotated increments (the default).
    Corotational,
    /// One linear solve on the rest geometry.
    Linear,
    /// Neo-Hookean increments solved to equilibrium.
    Nonlinear,
}

/// `[solver] contact`: how contact is resolved.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ContactMethodName {
    /// Lagrange multipliers through the Schur complement (the default).
    #[default]
    Lagrange,
    /// The paper's six-step iteration.
    Paper,
}

impl ContactMethodName {
    /// Every method, in the order the help lists them.
    pub const ALL: [ContactMethodName; 2] = [ContactMethodName::Lagrange, ContactMethodName::Paper];

    /// The name in the scene file.
    pub fn name(self) -> &'static str {
        match self {
            ContactMethodName::Lagrange => "lagrange",
            ContactMethodName::Paper => "paper",
        }
    }
}

/// `[solver] contact_pairs`: which side of a hand–object contact is checked node against facet.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PairSidesName {
    /// Skin nodes against object facets (the default).
    #[default]
    SkinNodes,
    /// Object nodes against skin facets (the paper's direction).
    ObjectNodes,
    /// Both ways.
    Both,
}

/// `[solver] volumetric`: integration of the Neo-Hookean volumetric energy.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum VolumetricName {
    /// 2×2×2 Gauss points: locks as ν → ½.
    Full,
    /// Mean dilatation (the default).
    MeanDilatation,
}

/// `[solver] element`: the element of the linear static solve.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ElementName {
    /// Trilinear hexahedron, 2×2×2 Gauss points (the default).
    #[default]
    Hex8,
    /// Hexahedron with Wilson–Taylor incompatible modes.
    IncompatibleModes,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::TierName;

    #[test]
    fn a_name_is_spelled_as_the_file_writes_it() {
        assert_eq!(spelling(&TierName::Corotational), "corotational");
        assert_eq!(
            spelling(&ElementName::IncompatibleModes),
            "incompatible_modes"
        );
        assert_eq!(spelling(&PairSidesName::SkinNodes), "skin_nodes");
        let back: TierName = serde_json::from_value(spelling(&TierName::Nonlinear).into()).unwrap();
        assert_eq!(back, TierName::Nonlinear);
    }
}
