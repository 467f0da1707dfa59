//! The built-in hand's two forms (`shape = { hand = { form = "anatomical" } }`).
//!
//! - **Simple** (the default): the rounded palm slab, fingers as tapered round cones, the thumb
//!   resting nearly in the palm's plane.
//! - **Anatomical** (the default scene's): the same skeleton and joint angles, with what an
//!   animator reads as a hand — the thumb at its natural rest, abducted out of the palm
//!   ([`THUMB_REST_ABDUCTION_DEG`]); the palm's distal edge along the knuckles' arc, its rims
//!   rounded, its front hollowed between the thenar and hypothenar eminences, its back domed
//!   across (the transverse arch); the first web space between thumb and index; the heads of
//!   the metacarpals standing out on the back (the knuckles); each finger's phalanges narrower
//!   between their joints than at them; a pulp under each distal phalanx.
//!
//! The thumb's rest is a rest *pose*, not another joint convention: the anatomical skeleton
//! is built with the thumb turned palmar about its CMC abduction axis, and that axis's angle at
//! rest is `thumb.cmc.abd` = [`THUMB_REST_ABDUCTION_DEG`] (`Skeleton::rest_angles`). Every
//! pose therefore puts every bone where it puts the simple hand's (to round-off,
//! tests/hand_form.rs): presets, synergies and scenes mean the same in both forms; only the
//! flesh is meshed about another rest. The flesh lattice passes through the simple hand's anchor
//! in both forms, so that the two forms cut the joints' creases on the same lines.

use super::anatomy::{FINGERS, PALM, THUMB};
use nalgebra::{Unit, UnitQuaternion, Vector3};

/// Which of the built-in hand's forms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HandForm {
    /// The rounded slab and round cones.
    Simple,
    /// The thumb at its natural rest, the palm's arches and eminences, knuckles and pulps (the
    /// default).
    #[default]
    Anatomical,
}

impl HandForm {
    /// Its name in a scene.
    pub fn name(self) -> &'static str {
        match self {
            HandForm::Simple => "simple",
            HandForm::Anatomical => "anatomical",
        }
    }

    /// The form of that name.
    pub fn from_name(name: &str) -> Option<HandForm> {
        [HandForm::Simple, HandForm::Anatomical]
            .into_iter()
            .find(|f| f.name() == name)
    }

    /// The thumb's palmar abduction at rest, degrees (`thumb.cmc.abd` of the rest pose).
    pub fn thumb_rest_abduction_deg(self) -> f64 {
        match self {
            HandForm::Simple => 0.0,
            HandForm::Anatomical => THUMB_REST_ABDUCTION_DEG,
        }
    }

    /// The thumb's direction at rest (unit, a right hand's frame): `THUMB.direction`, turned
    /// palmar by the rest abduction about the CMC's abduction axis as the skeleton defines it
    /// (normal to the thumb and to the dorsal normal z; `Skeleton::from_joints`).
    pub fn thumb_direction(self) -> Vector3<f64> {
        let d = Vector3::from(THUMB.direction).normalize();
        let angle = self.thumb_rest_abduction_deg();
        if angle == 0.0 {
            return d;
        }
        let z = Vector3::z();
        let zp = (z - d * z.dot(&d)).normalize();
        let outward = Unit::new_normalize(zp.cross(&d));
        UnitQuaternion::from_axis_angle(&outward, angle.to_radians()) * d
    }
}

/// A relaxed hand holds its thumb abducted and pronated out of the palm, not in its plane: the
/// anatomical hand's thumb at rest, turned palmar about its CMC abduction axis, degrees (26.8°
/// out of the palm's plane, against 6.8° for the simple hand).
pub const THUMB_REST_ABDUCTION_DEG: f64 = 20.0;

/// A phalanx's skin at its middle against the mean of its two joints' (the joints stand out
/// from the shafts between them).
pub const WAIST: f64 = 0.96;
/// Blending radius between a distal phalanx and its pulp, m.
const PULP_BLEND: f64 = 0.004;
/// Blending radius between the back of the hand and the knuckles, m.
const KNUCKLE_BLEND: f64 = 0.004;
/// Blending radius of the palm's knuckle face and hollow, m.
const FACE_BLEND: f64 = 0.008;
const HOLLOW_BLEND: f64 = 0.006;
/// The palm's rims' rounding in the anatomical form, m (the simple slab's: `PALM.rounding`).
pub const ROUNDING: f64 = 0.009;

/// The palm slab's midline across the hand (y), m.
pub const SLAB_MID_Y: f64 = -0.002;
/// The palm slab's line of its knuckles (x), m: where it stops tapering.
pub const SLAB_KNUCKLES_X: f64 = 0.086;

/// The palm slab's half-width at `x`, m: tapering from the knuckles' to the wrist's.
pub fn slab_half_width(x: f64) -> f64 {
    let t = ((x - PALM.wrist_x) / (SLAB_KNUCKLES_X - PALM.wrist_x)).clamp(0.0, 1.0);
    PALM.half_width[0] + (PALM.half_width[1] - PALM.half_width[0]) * t
}

/// The back of the hand's rise at its middle (the dorsal side of the metacarpals' transverse
/// arch: the middle and ring fingers' metacarpals stand higher than the index's and the little
/// finger's), m. The front's side of the arch is the hollow ([`HOLLOW`]).
pub const ARCH_RISE: f64 = 0.002;

/// How far the anatomical form raises the back of the palm above the slab's flat face at
/// (x, y), m: [`ARCH_RISE`] on the slab's midline, falling smoothly (as (1 − s²)², s across
/// the flat face) to nothing where the rims begin to round, and rising from the wrist's cut.
/// It only adds flesh: the bones' cover over the index's and little finger's metacarpals is the
/// simple hand's.
pub fn dorsal_rise(x: f64, y: f64) -> f64 {
    let flat = slab_half_width(x) - ROUNDING;
    let s = (y - SLAB_MID_Y) / flat;
    let across = (1.0 - s * s).max(0.0);
    // Rising from the wrist's cut, which stays flat-topped as the simple hand's (the cut's rim
    // is a crease of the skin, where the display skin's projection would wander on a dome).
    let u = ((x - PALM.wrist_x) / ARCH_FROM_WRIST).clamp(0.0, 1.0);
    let along = u * u * (3.0 - 2.0 * u);
    ARCH_RISE * across * across * along
}

/// Over how far from the wrist's cut the arch rises to its height, m.
const ARCH_FROM_WRIST: f64 = 0.020;

/// `p` taken into the flat slab: above the palm's front face, the thickness is scaled back by
/// the rise (the slab's distance evaluated there is the arched slab's, to a factor within
/// T / (T + [`ARCH_RISE`]) of 1, T the palm's thickness).
pub fn unarched(p: &Vector3<f64>) -> Vector3<f64> {
    let rise = dorsal_rise(p.x, p.y);
    if rise == 0.0 || p.z <= -PALM.palmar {
        return *p;
    }
    let thick = PALM.dorsal + PALM.palmar;
    Vector3::new(
        p.x,
        p.y,
        -PALM.palmar + (p.z + PALM.palmar) * thick / (thick + rise),
    )
}

/// The hollow of the palm: an ellipsoid (centre, semi-axes, m) carved from the front between
/// the eminences.
const HOLLOW: ([f64; 3], [f64; 3]) = ([0.050, -0.003, -0.0285], [0.024, 0.018, 0.0155]);
/// The hypothenar eminence (the little finger's muscles along the ulnar rim of the palm): an
/// ellipsoid (centre, semi-axes, m).
const HYPOTHENAR: ([f64; 3], [f64; 3]) = ([0.036, -0.027, -0.0085], [0.030, 0.012, 0.0095]);

/// An ellipsoid along its own orthonormal `axes`, of semi-axes `r`.
#[derive(Clone, Copy, Debug)]
pub struct Ellipsoid {
    c: Vector3<f64>,
    axes: [Vector3<f64>; 3],
    r: Vector3<f64>,
}

impl Ellipsoid {
    /// Aligned with the hand's frame.
    fn aligned((c, r): ([f64; 3], [f64; 3])) -> Ellipsoid {
        Ellipsoid {
            c: c.into(),
            axes: [Vector3::x(), Vector3::y(), Vector3::z()],
            r: r.into(),
        }
    }

    /// Approximate signed distance (exact on its surface, scaled by the smallest semi-axis).
    pub fn distance(&self, p: &Vector3<f64>) -> f64 {
        let d = p - self.c;
        let q = Vector3::new(
            d.dot(&self.axes[0]) / self.r.x,
            d.dot(&self.axes[1]) / self.r.y,
            d.dot(&self.axes[2]) / self.r.z,
        );
        (q.norm() - 1.0) * self.r.min()
    }

    /// A box around it, corners (lo, hi).
    pub fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        let mut half = Vector3::zeros();
        for (a, r) in self.axes.iter().zip(self.r.iter()) {
            half += a.abs() * *r;
        }
        (self.c - half, self.c + half)
    }
}

/// A digit's distal phalanx as its skin's round cone lays it (a right hand's frame).
#[derive(Clone, Copy, Debug)]
pub struct DistalPhalanx {
    /// The skin axis at the DIP (the thumb's IP), m.
    pub dip: Vector3<f64>,
    /// Where the skin ends beyond the tip, on the axis, m.
    pub tip: Vector3<f64>,
    /// The skin's mean radius along it, m.
    pub radius: f64,
    /// Where its pad faces (unit, normal to the phalanx).
    pub palmar: Vector3<f64>,
}

/// What the anatomical form adds to the simple skin (a right hand's frame, the anatomy
/// tables' size).
#[derive(Clone, Debug)]
pub struct Features {
    /// The first web space (a round cone: ends, radii): the fold of skin and muscle (adductor
    /// pollicis, first dorsal interosseous) from the thumb's metacarpal, short of its head, to
    /// the radial side of the index's metacarpal head.
    pub web: (Vector3<f64>, Vector3<f64>, f64, f64),
    /// The heads of the fingers' metacarpals under the back of the hand.
    knuckles: Vec<Ellipsoid>,
    /// Each digit's pulp, thumb first.
    pulps: Vec<Ellipsoid>,
}

impl Features {
    /// The features of a hand whose thumb's joints are `thumb` (CMC, MCP, IP, tip), its skin's
    /// axis `down` from them (the skin set palmar of the bones), with the digits' distal
    /// phalanges `distal` (thumb first).
    pub fn new(thumb: &[Vector3<f64>], down: Vector3<f64>, distal: &[DistalPhalanx]) -> Features {
        let index = &FINGERS[0];
        let web = (
            thumb[0] + (thumb[1] - thumb[0]) * 0.75 + down,
            // Beside the index's metacarpal head, not under it: the index flexing at its MCP
            // would press its own skin into a web laid under the head (measured: skin inside the
            // flesh at MCP 20°).
            Vector3::new(index.mcp[0] - 0.020, index.mcp[1] + 0.008, 0.0),
            0.0075,
            0.0055,
        );
        // Each metacarpal's head under the back of the hand, a millimetre proud of it.
        let knuckles = FINGERS
            .iter()
            .map(|f| Ellipsoid {
                c: Vector3::new(
                    f.mcp[0] - 0.004,
                    f.mcp[1],
                    PALM.dorsal - 0.0035 + dorsal_rise(f.mcp[0] - 0.004, f.mcp[1]),
                ),
                axes: [Vector3::x(), Vector3::y(), Vector3::z()],
                r: Vector3::new(0.009, 0.6 * f.skin[0], 0.0045),
            })
            .collect();
        let pulps = distal
            .iter()
            .map(|d| pulp(d.dip, d.tip, d.radius, d.palmar))
            .collect();
        Features {
            web,
            knuckles,
            pulps,
        }
    }

    /// The palm's distance with the anatomical form's palm features: `slab` is the distance
    /// to the slab reaching past the knuckles, `thenar` to the thenar eminence, `web` to the
    /// first web space.
    pub fn palm(&self, p: &Vector3<f64>, slab: f64, thenar: f64, web: f64, blend: f64) -> f64 {
        let palm = smooth_max(slab, knuckle_face(p), FACE_BLEND);
        let palm = smooth_max(palm, -Ellipsoid::aligned(HOLLOW).distance(p), HOLLOW_BLEND);
        let palm = smooth_min(palm, thenar, blend);
        let palm = smooth_min(palm, Ellipsoid::aligned(HYPOTHENAR).distance(p), blend);
        let palm = smooth_min(palm, web, blend);
        self.knuckles
            .iter()
            .fold(palm, |d, k| smooth_min(d, k.distance(p), KNUCKLE_BLEND))
    }

    /// Digit `digit`'s distance `d` with its pulp.
    pub fn digit(&self, digit: usize, p: &Vector3<f64>, d: f64) -> f64 {
        smooth_min(d, self.pulps[digit].distance(p), PULP_BLEND)
    }

    /// The features' boxes (for the skin's bounds).
    pub fn bounds(&self) -> impl Iterator<Item = (Vector3<f64>, Vector3<f64>)> + '_ {
        let fixed = [Ellipsoid::aligned(HYPOTHENAR)];
        let half = PALM.half_width[1];
        let arch = (
            Vector3::new(PALM.wrist_x, SLAB_MID_Y - half, PALM.dorsal),
            Vector3::new(SLAB_KNUCKLES_X, SLAB_MID_Y + half, PALM.dorsal + ARCH_RISE),
        );
        self.pulps
            .iter()
            .chain(&self.knuckles)
            .copied()
            .chain(fixed)
            .map(|e| e.bounds())
            .chain([arch])
    }
}

/// The pulp under a distal phalanx whose skin axis runs from `dip` to `tip` (the skin's end),
/// of mean radius `r`: from a little past the DIP crease to short of the tip, swelling about a
/// millimetre beyond the round cone towards `palmar` (unit, normal to the phalanx).
fn pulp(dip: Vector3<f64>, tip: Vector3<f64>, r: f64, palmar: Vector3<f64>) -> Ellipsoid {
    let length = (tip - dip).norm();
    let dir = (tip - dip) / length;
    let side = palmar.cross(&dir).normalize();
    Ellipsoid {
        c: dip + dir * (0.55 * length) + palmar * (0.34 * r),
        axes: [dir, side, palmar],
        r: Vector3::new(0.40 * length, 0.80 * r, 0.76 * r),
    }
}

/// The thumb's palmar direction at rest (unit, normal to its direction `d`): the palm's
/// normal turned about the thumb by its pronation, towards the fingers (a right hand's frame).
pub fn thumb_palmar(d: Vector3<f64>) -> Vector3<f64> {
    let down = -Vector3::z();
    let n = (down - d * down.dot(&d)).normalize();
    let turn = |s: f64| {
        UnitQuaternion::from_axis_angle(
            &Unit::new_normalize(d),
            s * THUMB.pronation_deg.to_radians(),
        ) * n
    };
    let (a, b) = (turn(1.0), turn(-1.0));
    if a.y < b.y {
        a
    } else {
        b
    }
}

/// The knuckles' arc: the palm's distal face, slanted as the line from the index's MCP to the
/// little finger's, through x = 0.086 m on the middle finger's axis.
fn knuckle_face(p: &Vector3<f64>) -> f64 {
    let [index, middle, little] = [&FINGERS[0], &FINGERS[1], &FINGERS[3]];
    let slope = (index.mcp[0] - little.mcp[0]) / (index.mcp[1] - little.mcp[1]);
    (p.x - SLAB_KNUCKLES_X - slope * (p.y - middle.mcp[1])) / (1.0 + slope * slope).sqrt()
}

/// How far the anatomical palm's slab reaches past the knuckles' line, m (the knuckle face
/// bounds it, so that the blend rounds the corners without sinking the face).
pub const SLAB_PAST_KNUCKLES: f64 = 0.012;

/// Polynomial smooth minimum with blending radius `k`.
pub fn smooth_min(a: f64, b: f64, k: f64) -> f64 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k * 0.25
}

/// Polynomial smooth maximum with blending radius `k`.
fn smooth_max(a: f64, b: f64, k: f64) -> f64 {
    -smooth_min(-a, -b, k)
}
