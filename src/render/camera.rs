//! The camera: a perspective view (z up) with framing, orbit / pan / zoom and named presets.

use glam::camera::rh::proj::directx::perspective;
use glam::camera::rh::view::look_at_mat4;
use glam::{Mat4, Vec3, Vec4};

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Bounds {
    /// An empty box (includes nothing; [`Bounds::is_valid`] is false).
    pub fn empty() -> Self {
        Self {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
        }
    }

    /// Bounds of some points.
    pub fn of(points: impl IntoIterator<Item = Vec3>) -> Self {
        let mut b = Self::empty();
        points.into_iter().for_each(|p| b.include(p));
        b
    }

    /// Grows the box to include `p` (non-finite points are ignored).
    pub fn include(&mut self, p: Vec3) {
        if p.is_finite() {
            self.min = self.min.min(p);
            self.max = self.max.max(p);
        }
    }

    /// Whether the box holds at least one point.
    pub fn is_valid(&self) -> bool {
        self.min.cmple(self.max).all()
    }

    /// Centre.
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Radius of the bounding sphere around the centre (never zero).
    pub fn radius(&self) -> f32 {
        ((self.max - self.min).length() * 0.5).max(1e-6)
    }

    /// The eight corners.
    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }
}

/// A perspective camera. World z is up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position, m.
    pub eye: Vec3,
    /// The point looked at (the centre of orbits), m.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

/// Named view directions: from where the camera looks at the scene (eye − target).
pub const PRESETS: [(&str, [f32; 3]); 5] = [
    ("three-quarter", [0.95, -1.35, 0.85]),
    ("front", [0.0, -1.0, 0.08]),
    ("side", [1.0, 0.0, 0.08]),
    ("top", [0.0, -0.02, 1.0]),
    ("below", [0.6, -1.0, -0.5]),
];

/// Default vertical field of view: 35°.
pub const DEFAULT_FOV_Y: f32 = 35.0 * std::f32::consts::PI / 180.0;

impl Camera {
    /// Looks at `bounds` from `direction` (eye − target, any length) so that its bounding
    /// sphere fits the view of a landscape image (width ≥ height), with a small margin.
    pub fn framing(bounds: &Bounds, direction: Vec3) -> Self {
        Self::framing_for_aspect(bounds, direction, 1.0)
    }

    /// As [`Camera::framing`], for images of aspect `width / height` (portrait images fit the
    /// narrower horizontal field).
    pub fn framing_for_aspect(bounds: &Bounds, direction: Vec3, aspect: f32) -> Self {
        let fov_y = DEFAULT_FOV_Y;
        let half_x = ((fov_y * 0.5).tan() * aspect.max(1e-3)).atan();
        let half = (fov_y * 0.5).min(half_x);
        let dir = direction.try_normalize().unwrap_or(Vec3::NEG_Y);
        let distance = bounds.radius() * 1.08 / half.sin();
        let target = bounds.center();
        Self {
            eye: target + dir * distance,
            target,
            up: Self::up_for(dir),
            fov_y,
        }
    }

    /// A named preset framing `bounds` (see [`PRESETS`]), or `None` for an unknown name.
    pub fn preset(name: &str, bounds: &Bounds, aspect: f32) -> Option<Self> {
        PRESETS
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, d)| Self::framing_for_aspect(bounds, Vec3::from(*d), aspect))
    }

    /// The preset names, comma separated (for messages).
    pub fn preset_names() -> String {
        PRESETS.map(|(n, _)| n).join(", ")
    }

    fn up_for(dir: Vec3) -> Vec3 {
        if dir.cross(Vec3::Z).length() < 1e-3 {
            Vec3::Y
        } else {
            Vec3::Z
        }
    }

    /// Distance from eye to target.
    pub fn distance(&self) -> f32 {
        (self.eye - self.target).length()
    }

    /// Unit vectors (right, true up, forward) of the view.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.eye).normalize_or(Vec3::Y);
        let right = forward.cross(self.up).normalize_or(Vec3::X);
        (right, right.cross(forward), forward)
    }

    /// Turns the eye around the target: `yaw` about the world z axis, `pitch` about the view's
    /// right axis (radians; positive pitch raises the eye), keeping clear of the poles.
    pub fn orbit(&mut self, yaw: f32, pitch: f32) {
        let offset = self.eye - self.target;
        let r = offset.length();
        let mut azimuth = offset.y.atan2(offset.x) + yaw;
        if !azimuth.is_finite() {
            azimuth = 0.0;
        }
        let elevation = ((offset.z / r).clamp(-1.0, 1.0).asin() + pitch).clamp(-1.55, 1.55);
        self.eye = self.target
            + r * Vec3::new(
                elevation.cos() * azimuth.cos(),
                elevation.cos() * azimuth.sin(),
                elevation.sin(),
            );
        self.up = Vec3::Z;
    }

    /// Moves eye and target in the view plane by (`dx`, `dy`) fractions of the visible height at
    /// the target (positive: the scene moves right and up on screen... the camera moves left and
    /// down).
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let (right, up, _) = self.basis();
        let height = 2.0 * self.distance() * (self.fov_y * 0.5).tan();
        let shift = (-dx * right - dy * up) * height;
        self.eye += shift;
        self.target += shift;
    }

    /// Moves the eye towards the target by `factor` (< 1 zooms in, > 1 out) of its distance.
    pub fn zoom(&mut self, factor: f32) {
        let factor = if factor.is_finite() && factor > 0.0 {
            factor
        } else {
            1.0
        };
        let offset = (self.eye - self.target) * factor;
        self.eye = self.target + offset.clamp_length_min(1e-5);
    }

    /// World to view matrix.
    pub fn view(&self) -> Mat4 {
        let (_, up, _) = self.basis();
        look_at_mat4(self.eye, self.target, up)
    }

    /// Projection (depth 0 at `near`, 1 at `far`).
    pub fn projection(&self, aspect: f32, near: f32, far: f32) -> Mat4 {
        perspective(self.fov_y, aspect, near, far)
    }

    /// Near and far distances for the depth buffer: far encloses `everything`; near sits well
    /// in front of `objects` (what must never be clipped), and no closer than far / 10⁴.
    pub fn depth_range(&self, objects: &Bounds, everything: &Bounds) -> (f32, f32) {
        let (_, _, forward) = self.basis();
        let along = |b: &Bounds| {
            b.corners()
                .iter()
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), c| {
                    let d = (*c - self.eye).dot(forward);
                    (lo.min(d), hi.max(d))
                })
        };
        let far = (along(everything).1.max(along(objects).1) * 1.05).max(1e-3);
        let near = (along(objects).0 * 0.3).max(far * 1e-4);
        (near, far)
    }

    /// Pixel (x right, y down, pixel centres at .5) where world point `p` lands in a
    /// `width`×`height` image, or `None` behind the eye.
    pub fn project(&self, p: Vec3, width: u32, height: u32) -> Option<[f32; 2]> {
        let m = self.projection(width as f32 / height as f32, 1e-4, 1e4) * self.view();
        let c: Vec4 = m * p.extend(1.0);
        if c.w <= 0.0 {
            return None;
        }
        let ndc = c.truncate() / c.w;
        Some([
            (ndc.x * 0.5 + 0.5) * width as f32,
            (0.5 - ndc.y * 0.5) * height as f32,
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_points() -> Vec<Vec3> {
        let mut pts = Vec::new();
        for i in 0..40 {
            for j in 0..20 {
                let (a, b) = (i as f32 * 0.157, j as f32 * 0.157 - 1.5);
                pts.push(
                    Vec3::new(0.3, -0.2, 0.05)
                        + 0.07 * Vec3::new(b.cos() * a.cos(), b.cos() * a.sin(), b.sin()),
                );
            }
        }
        pts
    }

    #[test]
    fn framing_keeps_every_point_inside_the_image() {
        let pts = sphere_points();
        let b = Bounds::of(pts.iter().copied());
        for (w, h) in [(1280, 720), (400, 800), (500, 500)] {
            for (name, _) in PRESETS {
                let cam = Camera::preset(name, &b, w as f32 / h as f32).unwrap();
                let mut used = [f32::INFINITY, f32::NEG_INFINITY];
                for p in &pts {
                    let [x, y] = cam.project(*p, w, h).unwrap();
                    assert!(
                        x > 0.0 && x < w as f32 && y > 0.0 && y < h as f32,
                        "{name} {x} {y}"
                    );
                    used = [used[0].min(y), used[1].max(y)];
                }
                // ...and the framing is not lazily far away: the object spans a good part of
                // the limiting side.
                let span = if w >= h {
                    (used[1] - used[0]) / h as f32
                } else {
                    1.0
                };
                assert!(span > 0.4, "{name} {span}");
            }
        }
    }

    #[test]
    fn known_points_land_on_known_pixels() {
        let cam = Camera {
            eye: Vec3::new(0.0, -2.0, 0.0),
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y: 90f32.to_radians(),
        };
        let [x, y] = cam.project(Vec3::ZERO, 200, 100).unwrap();
        assert!((x - 100.0).abs() < 1e-3 && (y - 50.0).abs() < 1e-3);
        // tan(45°) = 1: a point at height 2 at distance 2 lands on the top edge.
        let [x, y] = cam.project(Vec3::new(0.0, 0.0, 1.0), 200, 100).unwrap();
        assert!(
            (x - 100.0).abs() < 1e-3 && (y - 25.0).abs() < 1e-3,
            "{x} {y}"
        );
        // Right of the target is +x seen from -y; aspect 2 widens the view.
        let [x, _] = cam.project(Vec3::new(2.0, 0.0, 0.0), 200, 100).unwrap();
        assert!((x - 150.0).abs() < 1e-3, "{x}");
        assert!(cam.project(Vec3::new(0.0, -3.0, 0.0), 200, 100).is_none());
    }

    #[test]
    fn orbit_pan_zoom() {
        let b = Bounds::of([Vec3::ZERO, Vec3::ONE]);
        let mut cam = Camera::preset("front", &b, 1.5).unwrap();
        let d = cam.distance();
        cam.orbit(std::f32::consts::FRAC_PI_2, 0.0);
        assert!((cam.distance() - d).abs() < 1e-4 * d);
        // From -y, a quarter turn anticlockwise about z puts the eye on +x.
        assert!((cam.eye - cam.target).normalize().x > 0.99);
        cam.orbit(0.0, 10.0);
        assert!((cam.eye - cam.target).normalize().z < 1.0 && cam.view().is_finite());
        cam.zoom(0.5);
        assert!((cam.distance() - d * 0.5).abs() < 1e-4 * d);
        let t = cam.target;
        cam.pan(0.1, 0.0);
        assert!(
            ((cam.target - t).length() - 0.1 * 2.0 * cam.distance() * (cam.fov_y * 0.5).tan())
                .abs()
                < 1e-4
        );
        let unknown = Camera::preset("nope", &b, 1.0);
        assert!(unknown.is_none());
    }
}
