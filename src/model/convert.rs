//! The scene file's names converted once into the solver's enums.

use super::flexion_settings::{FleshMethod, FlexionScheme};
use crate::contact::{ContactMethod, PairSides};
use crate::fem::solve::FillOrdering;
use crate::fem::{ElementKind, Volumetric};
use crate::hand::{Blend, Side};
use crate::scene::{
    BlendName, ContactMethodName, ElementName, FleshMethodName, FlexionSchemeName, HandSide,
    OrderingName, PairSidesName, VolumetricName,
};

impl From<HandSide> for Side {
    fn from(s: HandSide) -> Side {
        match s {
            HandSide::Right => Side::Right,
            HandSide::Left => Side::Left,
        }
    }
}

impl From<BlendName> for Blend {
    fn from(b: BlendName) -> Blend {
        match b {
            BlendName::Linear => Blend::Linear,
            BlendName::DualQuaternion => Blend::DualQuaternion,
        }
    }
}

impl From<FleshMethodName> for FleshMethod {
    fn from(m: FleshMethodName) -> FleshMethod {
        match m {
            FleshMethodName::Fem => FleshMethod::Fem,
            FleshMethodName::Skinning => FleshMethod::Skinning,
        }
    }
}

impl From<FlexionSchemeName> for FlexionScheme {
    fn from(s: FlexionSchemeName) -> FlexionScheme {
        match s {
            FlexionSchemeName::UpdatedLagrangian => FlexionScheme::UpdatedLagrangian,
            FlexionSchemeName::Corotational => FlexionScheme::Corotational,
            FlexionSchemeName::Linear => FlexionScheme::Linear,
            FlexionSchemeName::Nonlinear => FlexionScheme::Nonlinear,
        }
    }
}

impl From<ContactMethodName> for ContactMethod {
    fn from(m: ContactMethodName) -> ContactMethod {
        match m {
            ContactMethodName::Lagrange => ContactMethod::Lagrange,
            ContactMethodName::Paper => ContactMethod::Paper,
        }
    }
}

impl From<PairSidesName> for PairSides {
    fn from(p: PairSidesName) -> PairSides {
        match p {
            PairSidesName::SkinNodes => PairSides::SkinNodes,
            PairSidesName::ObjectNodes => PairSides::ObjectNodes,
            PairSidesName::Both => PairSides::Both,
        }
    }
}

impl From<VolumetricName> for Volumetric {
    fn from(v: VolumetricName) -> Volumetric {
        match v {
            VolumetricName::Full => Volumetric::Full,
            VolumetricName::MeanDilatation => Volumetric::MeanDilatation,
        }
    }
}

impl From<ElementName> for ElementKind {
    fn from(e: ElementName) -> ElementKind {
        match e {
            ElementName::Hex8 => ElementKind::Hex8,
            ElementName::IncompatibleModes => ElementKind::IncompatibleModes,
        }
    }
}

impl From<OrderingName> for FillOrdering {
    fn from(o: OrderingName) -> FillOrdering {
        match o {
            OrderingName::Auto => FillOrdering::Auto,
            OrderingName::NestedDissection => FillOrdering::NestedDissection,
            OrderingName::Amd => FillOrdering::Amd,
        }
    }
}
