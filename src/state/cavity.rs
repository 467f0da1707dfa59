//! The gas cavity of a solved frame: its volume in the frame's displacements and the pressure the
//! gas law gives it there (p = P0·V0/V − p_ambient; the solve applied that pressure, to 1e-9).

use super::Frame;
use crate::model::Model;
use serde::Serialize;

/// A gas cavity in a frame.
#[derive(Clone, Debug, Serialize)]
pub struct CavityState {
    /// The load that is the cavity.
    pub load: String,
    /// Gauge pressure (above ambient), Pa.
    pub gauge_pressure: f64,
    /// Volume, m³.
    pub volume: f64,
    /// Volume in the mesh as given, m³, where the gauge pressure is the load's `pressure`.
    pub rest_volume: f64,
    /// Absolute ambient pressure, Pa.
    pub ambient: f64,
}

/// The frame's gas cavity, if the model has one.
pub fn cavity_state(model: &Model, frame: &Frame) -> Option<CavityState> {
    let cavity = model.gas.as_ref()?;
    let volume = cavity.volume(&model.mesh.nodes, &frame.solution.displacement);
    Some(CavityState {
        load: cavity.name.clone(),
        gauge_pressure: cavity.gauge_at(volume),
        volume,
        rest_volume: cavity.rest_volume,
        ambient: cavity.ambient,
    })
}
