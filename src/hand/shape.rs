//! The skin's shape in the rest pose as a signed distance function (negative inside): a rounded
//! palm slab blended smoothly with one chain of round cones per digit, finger axes set slightly
//! palmar of the bones so that the flesh is thin on the back of the fingers (bone nearly flush
//! with the skin) and thick on the palmar pads.

use super::anatomy::{FINGERS, PALM, THUMB};
use super::form::{
    slab_half_width, DistalPhalanx, Features, HandForm, SLAB_KNUCKLES_X, SLAB_MID_Y,
    SLAB_PAST_KNUCKLES, WAIST,
};
use super::mesh_skin::MeshSkin;
use super::skeleton::Side;
use super::stretch::Stretch;
use nalgebra::Vector3;

/// Offset of a finger's skin axis from its bone axis towards the palm, m.
const PALMAR_OFFSET: f64 = 0.0014;
/// Flesh beyond the end of the distal phalanx, m.
const TIP_PAD: f64 = 0.0035;
/// Blending radius between the palm and each digit, m.
const BLEND: f64 = 0.008;

/// A round cone: a capsule whose radius goes from `r0` at `a` to `r1` at `b`.
#[derive(Clone, Copy, Debug)]
struct RoundCone {
    a: Vector3<f64>,
    b: Vector3<f64>,
    r0: f64,
    r1: f64,
}

impl RoundCone {
    /// Exact signed distance to a round cone (sphere-swept cone between two spheres).
    fn distance(&self, p: &Vector3<f64>) -> f64 {
        let ba = self.b - self.a;
        let l2 = ba.norm_squared();
        let rr = self.r0 - self.r1;
        let a2 = l2 - rr * rr;
        let il2 = 1.0 / l2;
        let pa = p - self.a;
        let y = pa.dot(&ba);
        let z = y - l2;
        let x2 = (pa * l2 - ba * y).norm_squared();
        let y2 = y * y * l2;
        let z2 = z * z * l2;
        let k = rr.signum() * rr * rr * x2;
        if z.signum() * a2 * z2 > k {
            return (x2 + z2).sqrt() * il2 - self.r1;
        }
        if y.signum() * a2 * y2 < k {
            return (x2 + y2).sqrt() * il2 - self.r0;
        }
        ((x2 * a2 * il2).sqrt() + y * rr) * il2 - self.r0
    }

    /// How much the skin narrows at `p`'s place along the cone, m: nothing at its ends,
    /// (1 − [`WAIST`]) of the radius at its middle, smoothly between (sin²).
    fn waist(&self, p: &Vector3<f64>) -> f64 {
        let ba = self.b - self.a;
        let t = ((p - self.a).dot(&ba) / ba.norm_squared()).clamp(0.0, 1.0);
        let r = self.r0 + (self.r1 - self.r0) * t;
        r * (1.0 - WAIST) * (std::f64::consts::PI * t).sin().powi(2)
    }
}

use super::form::smooth_min;

/// The skin of a rest hand: the built-in hand's shape, or an imported skin mesh.
#[derive(Clone, Debug)]
pub enum SkinShape {
    /// The built-in hand's.
    Builtin(BuiltinSkin),
    /// An imported mesh's (hand frame).
    Mesh(Box<MeshSkin>),
}

impl SkinShape {
    /// The built-in hand's skin.
    pub fn new(side: Side) -> SkinShape {
        SkinShape::Builtin(BuiltinSkin::new(side))
    }

    /// The built-in hand's skin of `form`, stretched to another size.
    pub fn sized(side: Side, stretch: Stretch, form: HandForm) -> SkinShape {
        SkinShape::Builtin(BuiltinSkin::sized(side, stretch, form))
    }

    /// A point the flesh lattice's lines pass through (a right hand's frame), if the shape
    /// has one: a stretched built-in hand's lattice passes through the stretched anchor of the
    /// anatomy tables' hand ([`BuiltinSkin::lattice_anchor`]), so that with its spacing
    /// stretched alike it is that hand's lattice stretched; an imported skin's, through the
    /// anchor its skeleton places ([`MeshSkin::with_lattice_anchor`]). Laid from the skin's own
    /// padded bounds instead, it would move with whatever moves those bounds.
    pub fn lattice_anchor(&self) -> Option<Vector3<f64>> {
        match self {
            SkinShape::Builtin(s) => Some(s.stretch.apply(&BuiltinSkin::lattice_anchor())),
            SkinShape::Mesh(s) => s.lattice_anchor(),
        }
    }

    /// Signed distance from `p` (rest, hand frame) to the skin, m (negative inside).
    pub fn distance(&self, p: &Vector3<f64>) -> f64 {
        match self {
            SkinShape::Builtin(s) => s.distance(p),
            SkinShape::Mesh(s) => s.distance(p),
        }
    }

    /// The point of the skin nearest `p`.
    pub fn project(&self, p: &Vector3<f64>) -> Vector3<f64> {
        match self {
            SkinShape::Builtin(s) => s.project(p),
            SkinShape::Mesh(s) => s.project(p),
        }
    }

    /// Axis-aligned bounds of the skin, m (padded by 2 mm).
    pub fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        match self {
            SkinShape::Builtin(s) => s.bounds(),
            SkinShape::Mesh(s) => s.bounds(),
        }
    }
}

/// The built-in hand's skin.
#[derive(Clone, Debug)]
pub struct BuiltinSkin {
    side: Side,
    stretch: Stretch,
    digits: Vec<Vec<RoundCone>>,
    thenar: (Vector3<f64>, Vector3<f64>),
    /// What the anatomical form adds (`None`: the simple form).
    features: Option<Box<Features>>,
}

impl BuiltinSkin {
    /// The built-in hand's skin.
    pub fn new(side: Side) -> BuiltinSkin {
        BuiltinSkin::sized(side, Stretch::IDENTITY, HandForm::Simple)
    }

    /// The point the built-in hand's flesh lattice's lines pass through (a right hand's frame,
    /// the anatomy tables' size): its simple form's skin's lower corner (the anatomical form's
    /// too, so that both forms cut the joints' creases on the same lines).
    pub fn lattice_anchor() -> Vector3<f64> {
        BuiltinSkin::new(Side::Right).bounds().0
    }

    /// Which hand it is.
    pub fn side(&self) -> Side {
        self.side
    }

    /// How it is stretched from the anatomy tables' hand.
    pub fn stretch(&self) -> Stretch {
        self.stretch
    }

    /// The built-in hand's skin of `form`, stretched from the anatomy tables' size by
    /// `stretch`.
    pub fn sized(side: Side, stretch: Stretch, form: HandForm) -> BuiltinSkin {
        let mut digits = Vec::new();
        // Thumb: from the thenar base along its three bones.
        let d = form.thumb_direction();
        let down = Vector3::new(0.0, 0.0, -PALMAR_OFFSET);
        let mut joints = vec![Vector3::from(THUMB.cmc)];
        for len in THUMB.bones {
            let last = *joints.last().unwrap();
            joints.push(last + d * len);
        }
        digits.push(chain(&joints, &THUMB.skin, d, down));
        for f in &FINGERS {
            let mcp = Vector3::new(f.mcp[0], f.mcp[1], 0.0);
            let mut joints = vec![mcp - Vector3::x() * 0.010];
            let mut x = mcp;
            for len in f.phalanges {
                joints.push(x);
                x += Vector3::x() * len;
            }
            joints.push(x);
            // Skin radii: at the metacarpal head, MCP, PIP, DIP, tip.
            let radii = [f.skin[0], f.skin[0], f.skin[1], f.skin[2], f.skin[3]];
            digits.push(chain(&joints, &radii, Vector3::x(), down));
        }
        let features = (form == HandForm::Anatomical).then(|| {
            let distal: Vec<_> = digits
                .iter()
                .enumerate()
                .map(|(k, cones)| {
                    let last: &RoundCone = cones.last().expect("a digit has cones");
                    let palmar = if k == 0 {
                        super::form::thumb_palmar(d)
                    } else {
                        -Vector3::z()
                    };
                    // To the skin's end, the round cone's last sphere beyond its axis.
                    let dir = (last.b - last.a).normalize();
                    DistalPhalanx {
                        dip: last.a,
                        tip: last.b + dir * last.r1,
                        radius: (last.r0 + last.r1) / 2.0,
                        palmar,
                    }
                })
                .collect();
            Box::new(Features::new(&joints_of_thumb(d), down, &distal))
        });
        // The thenar eminence: an ellipsoid-like swelling palmar of the thumb metacarpal (where
        // the metacarpal lies before the anatomical form's rest abduction: the muscles fill the
        // palm's side the abducted thumb leaves).
        let d0 = Vector3::from(THUMB.direction).normalize();
        let c = Vector3::from(THUMB.cmc) + d0 * 0.022 + Vector3::new(0.004, -0.008, -0.006);
        BuiltinSkin {
            side,
            stretch,
            digits,
            thenar: (c, Vector3::new(0.024, 0.016, 0.010)),
            features,
        }
    }

    /// Signed distance from `p` (rest frame) to the skin, m (an approximation away from the
    /// surface, exact enough near it to project nodes onto it).
    pub fn distance(&self, p: &Vector3<f64>) -> f64 {
        let p = match self.side {
            Side::Right => *p,
            Side::Left => Vector3::new(p.x, -p.y, p.z),
        };
        self.reference_distance(&self.stretch.inverse(&p)) * self.stretch.distance()
    }

    /// Signed distance to the anatomy tables' right hand.
    fn reference_distance(&self, p: &Vector3<f64>) -> f64 {
        if let Some(features) = &self.features {
            return self.anatomical_distance(p, features);
        }
        let p = *p;
        let palm = palm_distance(&p);
        let (c, r) = self.thenar;
        let q = (p - c).component_div(&r);
        let thenar = (q.norm() - 1.0) * r.min();
        let palm = smooth_min(palm, thenar, BLEND);
        let mut d = f64::INFINITY;
        for digit in &self.digits {
            let dd = digit
                .iter()
                .map(|cone| cone.distance(&p))
                .fold(f64::INFINITY, f64::min);
            d = d.min(smooth_min(palm, dd, BLEND));
        }
        // The forearm is cut at the wrist.
        d.max(PALM.wrist_x - p.x)
    }

    /// [`BuiltinSkin::reference_distance`] of the anatomical form.
    fn anatomical_distance(&self, p: &Vector3<f64>, features: &Features) -> f64 {
        let (c, r) = self.thenar;
        let thenar = ((p - c).component_div(&r).norm() - 1.0) * r.min();
        let (a, b, r0, r1) = features.web;
        let web = RoundCone { a, b, r0, r1 }.distance(p);
        let slab = slab_distance(
            &super::form::unarched(p),
            SLAB_KNUCKLES_X + SLAB_PAST_KNUCKLES,
            super::form::ROUNDING,
        );
        let palm = features.palm(p, slab, thenar, web, BLEND);
        let mut d = f64::INFINITY;
        for (k, digit) in self.digits.iter().enumerate() {
            let n = digit.len();
            let dd = digit
                .iter()
                .enumerate()
                .map(|(i, cone)| {
                    let d = cone.distance(p);
                    // Each phalanx but the digit's first segment and its distal one.
                    if i > 0 && i + 1 < n {
                        d + cone.waist(p)
                    } else {
                        d
                    }
                })
                .fold(f64::INFINITY, f64::min);
            d = d.min(smooth_min(palm, features.digit(k, p, dd), BLEND));
        }
        d.max(PALM.wrist_x - p.x)
    }

    /// Gradient of the distance (central differences), unnormalised.
    pub fn gradient(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let h = 1e-5;
        let mut g = Vector3::zeros();
        for i in 0..3 {
            let mut e = Vector3::zeros();
            e[i] = h;
            g[i] = (self.distance(&(p + e)) - self.distance(&(p - e))) / (2.0 * h);
        }
        g
    }

    /// The point of the skin nearest `p` (Newton steps along the gradient).
    pub fn project(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let mut q = *p;
        for _ in 0..6 {
            let g = self.gradient(&q);
            let g2 = g.norm_squared();
            if g2 < 1e-12 {
                break;
            }
            let d = self.distance(&q);
            q -= g * (d / g2);
            if d.abs() < 1e-7 {
                break;
            }
        }
        q
    }

    /// Axis-aligned bounds of the skin, m (padded by 2 mm).
    pub fn bounds(&self) -> (Vector3<f64>, Vector3<f64>) {
        let mut lo = Vector3::new(PALM.wrist_x, -PALM.half_width[1], -PALM.palmar);
        let mut hi = Vector3::new(0.0, PALM.half_width[1], PALM.dorsal);
        for digit in &self.digits {
            for cone in digit {
                for (p, r) in [(cone.a, cone.r0), (cone.b, cone.r1)] {
                    lo = lo.inf(&(p - Vector3::repeat(r)));
                    hi = hi.sup(&(p + Vector3::repeat(r)));
                }
            }
        }
        let (c, r) = self.thenar;
        lo = lo.inf(&(c - r));
        hi = hi.sup(&(c + r));
        for (a, b) in self.features.iter().flat_map(|f| f.bounds()) {
            lo = lo.inf(&a);
            hi = hi.sup(&b);
        }
        lo.x = lo.x.max(PALM.wrist_x);
        let (lo, hi) = (self.stretch.apply(&lo), self.stretch.apply(&hi));
        let pad = Vector3::repeat(0.002);
        let (mut lo, mut hi) = (lo - pad, hi + pad);
        if self.side == Side::Left {
            (lo.y, hi.y) = (-hi.y, -lo.y);
        }
        (lo, hi)
    }
}

/// Round cones through `joints` with `radii`; the last one is shortened so that the skin ends
/// [`TIP_PAD`] beyond the last joint (the bone tip).
fn chain(
    joints: &[Vector3<f64>],
    radii: &[f64],
    dir: Vector3<f64>,
    offset: Vector3<f64>,
) -> Vec<RoundCone> {
    let n = joints.len();
    let mut cones = Vec::new();
    for i in 0..n - 1 {
        let mut b = joints[i + 1];
        if i == n - 2 {
            b += dir * (TIP_PAD - radii[i + 1]);
        }
        cones.push(RoundCone {
            a: joints[i] + offset,
            b: b + offset,
            r0: radii[i],
            r1: radii[i + 1],
        });
    }
    cones
}

/// The palm: a slab from the wrist to the knuckles, tapering from the knuckles to the wrist,
/// rounded at its edges.
fn palm_distance(p: &Vector3<f64>) -> f64 {
    slab_distance(p, SLAB_KNUCKLES_X, PALM.rounding)
}

/// The thumb's joints (CMC, MCP, IP, tip) at rest along `d`.
fn joints_of_thumb(d: Vector3<f64>) -> Vec<Vector3<f64>> {
    let mut joints = vec![Vector3::from(THUMB.cmc)];
    for len in THUMB.bones {
        let last = *joints.last().unwrap();
        joints.push(last + d * len);
    }
    joints
}

/// The palm's slab: from the wrist to `x1`, tapering from the knuckles ([`SLAB_KNUCKLES_X`]) to
/// the wrist ([`slab_half_width`]), its edges rounded over `r`.
fn slab_distance(p: &Vector3<f64>, x1: f64, r: f64) -> f64 {
    let x0 = PALM.wrist_x - 0.01;
    let half_w = slab_half_width(p.x);
    let center = Vector3::new(
        (x0 + x1) / 2.0,
        SLAB_MID_Y,
        (PALM.dorsal - PALM.palmar) / 2.0,
    );
    let half = Vector3::new((x1 - x0) / 2.0, half_w, (PALM.dorsal + PALM.palmar) / 2.0);
    let q = (p - center).abs() - (half - Vector3::repeat(r));
    q.sup(&Vector3::zeros()).norm() + q.max().min(0.0) - r
}
