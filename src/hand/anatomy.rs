//! Dimensions of an adult right hand, in metres, in the hand frame: x from the wrist towards the
//! finger tips, y towards the thumb side, z dorsal (the back of the hand). The left hand is its
//! mirror image in y.
//!
//! Lengths follow published adult phalanx and metacarpal means (about 50th percentile, male);
//! bone radii are those of the shafts and of the condyles (heads), which are wider at the joints.

/// The five digits, thumb first.
pub const DIGITS: [&str; 5] = ["thumb", "index", "middle", "ring", "little"];

/// One long finger (index to little) in the rest pose, fingers straight in the palm plane.
pub struct FingerDims {
    /// Name.
    pub name: &'static str,
    /// Carpometacarpal end of the metacarpal (x, y), m; z = 0.
    pub base: [f64; 2],
    /// Metacarpophalangeal joint centre (x, y), m; z = 0.
    pub mcp: [f64; 2],
    /// Lengths of the proximal, middle and distal phalanges, m.
    pub phalanges: [f64; 3],
    /// Bone shaft radius of the proximal, middle and distal phalanges, m.
    pub shaft: [f64; 3],
    /// Flesh (skin) radius at the MCP, PIP, DIP joints and at the tip, m.
    pub skin: [f64; 4],
}

/// Index, middle, ring and little fingers.
pub const FINGERS: [FingerDims; 4] = [
    FingerDims {
        name: "index",
        base: [0.030, 0.014],
        mcp: [0.094, 0.030],
        phalanges: [0.040, 0.024, 0.019],
        shaft: [0.0034, 0.0029, 0.0024],
        skin: [0.0090, 0.0082, 0.0075, 0.0068],
    },
    FingerDims {
        name: "middle",
        base: [0.030, 0.004],
        mcp: [0.097, 0.009],
        phalanges: [0.045, 0.028, 0.020],
        shaft: [0.0035, 0.0030, 0.0025],
        skin: [0.0092, 0.0084, 0.0077, 0.0070],
    },
    FingerDims {
        name: "ring",
        base: [0.028, -0.008],
        mcp: [0.092, -0.011],
        phalanges: [0.042, 0.027, 0.019],
        shaft: [0.0033, 0.0028, 0.0023],
        skin: [0.0087, 0.0080, 0.0073, 0.0066],
    },
    FingerDims {
        name: "little",
        base: [0.026, -0.018],
        mcp: [0.083, -0.030],
        phalanges: [0.033, 0.020, 0.018],
        shaft: [0.0029, 0.0025, 0.0021],
        skin: [0.0078, 0.0071, 0.0065, 0.0060],
    },
];

/// The thumb in the rest pose: its metacarpal leaves the carpus at `cmc` along `direction`
/// (in the palm plane, 40° from the fingers), tilted slightly palmar.
pub struct ThumbDims {
    /// Carpometacarpal joint centre, m.
    pub cmc: [f64; 3],
    /// Unit direction of the thumb (before normalisation).
    pub direction: [f64; 3],
    /// Rotation of the thumb nail about the thumb axis away from the dorsal normal, degrees
    /// (the thumb's nail faces sideways, not up).
    pub pronation_deg: f64,
    /// Lengths of metacarpal, proximal and distal phalanx, m.
    pub bones: [f64; 3],
    /// Bone shaft radii, m.
    pub shaft: [f64; 3],
    /// Flesh radius at CMC, MCP, IP and at the tip, m.
    pub skin: [f64; 4],
}

/// The thumb.
pub const THUMB: ThumbDims = ThumbDims {
    cmc: [0.018, 0.026, -0.006],
    direction: [0.766, 0.643, -0.12],
    pronation_deg: 60.0,
    bones: [0.044, 0.032, 0.025],
    shaft: [0.0040, 0.0034, 0.0027],
    skin: [0.0130, 0.0100, 0.0092, 0.0078],
};

/// Condyle (joint head) radius relative to the shaft radius.
pub const CONDYLE_RATIO: f64 = 1.3;

/// Half the joint space between two bones (articular cartilage), m.
pub const JOINT_GAP: f64 = 0.0006;

/// The palm's skin: a rounded slab from the wrist (x = `wrist_x`) to just past the knuckles,
/// thicker on the palmar side.
pub struct PalmDims {
    /// Wrist cut, x, m.
    pub wrist_x: f64,
    /// Half width at the wrist and at the knuckles, m.
    pub half_width: [f64; 2],
    /// Dorsal and palmar extent from the bone plane (z), m.
    pub dorsal: f64,
    /// Palmar extent (positive number), m.
    pub palmar: f64,
    /// Rounding radius, m.
    pub rounding: f64,
}

/// The palm.
pub const PALM: PalmDims = PalmDims {
    wrist_x: -0.004,
    half_width: [0.030, 0.042],
    dorsal: 0.0105,
    palmar: 0.0160,
    rounding: 0.007,
};

/// Carpal block (the wrist bones, fused here into one rigid bone): centre and half extents, m.
pub const CARPUS: ([f64; 3], [f64; 3]) = ([0.014, 0.000, -0.002], [0.014, 0.022, 0.0055]);

/// Range of one joint angle, degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Smallest angle.
    pub min: f64,
    /// Largest angle.
    pub max: f64,
}

/// Active ranges of motion of healthy adult joints (degrees; flexion positive, extension
/// negative; abduction positive away from the middle finger, or palmar for the thumb's CMC).
pub mod limits {
    use super::Limits;
    /// Finger MCP flexion.
    pub const MCP_FLEX: Limits = Limits {
        min: -30.0,
        max: 90.0,
    };
    /// Finger MCP abduction.
    pub const MCP_ABD: Limits = Limits {
        min: -20.0,
        max: 20.0,
    };
    /// Finger PIP flexion.
    pub const PIP: Limits = Limits {
        min: 0.0,
        max: 110.0,
    };
    /// Finger DIP flexion.
    pub const DIP: Limits = Limits {
        min: -10.0,
        max: 90.0,
    };
    /// Thumb CMC flexion (across the palm).
    pub const CMC_FLEX: Limits = Limits {
        min: -20.0,
        max: 50.0,
    };
    /// Thumb CMC abduction (away from the palm plane, palmar).
    pub const CMC_ABD: Limits = Limits {
        min: -10.0,
        max: 70.0,
    };
    /// Thumb CMC axial rotation: the metacarpal turned about its own axis, positive pronation
    /// (the pad turning to face the fingers' pads, as in opposition). The trapeziometacarpal
    /// joint is a saddle whose axial rotation is conjunct with flexion and abduction (Kapandji);
    /// it is a joint angle of its own here, so that a rig or a preshape sets it, and it lumps
    /// the thumb column's axial turn (trapeziometacarpal, about 20°, and the MCP's conjunct
    /// pronation) in one angle.
    pub const CMC_ROT: Limits = Limits {
        min: -10.0,
        max: 60.0,
    };
    /// Thumb MCP flexion.
    pub const THUMB_MCP: Limits = Limits {
        min: -10.0,
        max: 60.0,
    };
    /// Thumb IP flexion.
    pub const THUMB_IP: Limits = Limits {
        min: -20.0,
        max: 80.0,
    };
}

/// Default muscle force threshold of a bone, N: the largest reaction its muscles can hold before
/// the grasp is "not realisable". Approximate adult maxima: fingertip press forces of about
/// 40 N (index, middle), 30 N (ring), 25 N (little) and 60 N for the thumb tip (pinch), larger
/// towards the palm, where more muscles act with longer lever arms.
pub fn bone_threshold(name: &str) -> f64 {
    let (digit, bone) = name.split_once('.').unwrap_or((name, ""));
    let tip = match digit {
        "thumb" => 60.0,
        "index" | "middle" => 40.0,
        "ring" => 30.0,
        "little" => 25.0,
        _ => return 300.0,
    };
    match bone {
        "distal" => tip,
        "middle" => 1.3 * tip,
        "proximal" => 1.6 * tip,
        _ => 2.5 * tip,
    }
}
