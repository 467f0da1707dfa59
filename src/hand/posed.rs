//! A posed hand's bone geometry: every bone's surface moved by its rigid motion for a set of
//! joint angles (what the renderer and the OBJ / VTU exports draw).

use super::{bone_surface, HandModel, TriangleSurface};
use nalgebra::Point3;

impl HandModel {
    /// The surfaces of every bone at the joint `angles` (degrees), with the bone index.
    pub fn posed_bones(&self, angles: &[f64]) -> Vec<(usize, TriangleSurface)> {
        let transforms = self.skeleton.transforms(angles);
        self.skeleton
            .bones
            .iter()
            .enumerate()
            .map(|(b, bone)| {
                let (pos, tri) = bone_surface(bone);
                let pos = pos
                    .iter()
                    .map(|p| (transforms[b] * Point3::from(*p)).coords)
                    .collect();
                (b, (pos, tri))
            })
            .collect()
    }
}
