//! `prehensile export-hand`: the built-in hand at rest as a rigged glTF 2.0 binary (`.glb`) —
//! skin, skeleton named in a common rig convention, skinning weights — for Blender and as the
//! fixture of the glTF import.

use crate::export::hand_rig::{bone_joints, rig_joints, write_hand_rig};
use crate::export::rig_mesh::{rig_mesh, RigOptions, RigSkin};
use crate::hand::rig_names::Convention;
use crate::hand::{HandForm, HandModel, HandSize, Side};
use crate::model::hand_size;
use crate::scene::HandSizeDef;
use anyhow::{bail, Context, Result};
use clap::ValueEnum;
use std::path::{Path, PathBuf};

/// The `--side` values.
#[derive(Clone, Copy, ValueEnum)]
pub enum SideArg {
    /// A right hand.
    Right,
    /// A left hand (the mirror image).
    Left,
}

/// The `--convention` values.
#[derive(Clone, Copy, ValueEnum)]
pub enum ConventionArg {
    /// `mixamorig:RightHandIndex1` …; no finger metacarpals, tips `…4`.
    Mixamo,
    /// Blender's Rigify deform bones: `DEF-f_index.01.R`, `DEF-palm.01.R`.
    Rigify,
    /// MakeHuman: `finger2-1.R`, `metacarpal1.R`.
    Makehuman,
    /// Unreal Engine's mannequin: `index_01_r`, `index_metacarpal_r`.
    Unreal,
}

/// What to export (the `export-hand` subcommand's arguments).
#[derive(clap::Args)]
pub struct ExportHandArgs {
    /// The .glb file written (a temporary file beside it, renamed when complete); its name
    /// must end in .glb: the file is binary glTF, not a .gltf's JSON.
    #[arg(long)]
    pub out: PathBuf,
    /// Which hand.
    #[arg(long, value_enum, default_value = "right")]
    pub side: SideArg,
    /// The hand's mesh resolution (0.5 … 4; 1 = default), as in a scene.
    #[arg(long, default_value_t = 1.0)]
    pub resolution: f64,
    /// The hand's size: an ANSUR II percentile (female-5, female-50, female-95, male-5,
    /// male-50, male-95) or its length in metres (wrist crease to the middle finger's tip);
    /// the built-in hand's own (0.1975 m) when absent.
    #[arg(long)]
    pub size: Option<String>,
    /// The built-in hand's form: anatomical (the default: the thumb at its natural rest, the
    /// palm's hollow and eminences, knuckles, pulps) or simple, as a scene's `form`.
    #[arg(long, value_parser = ["simple", "anatomical"], default_value = "anatomical")]
    pub form: String,
    /// The naming convention of the joint nodes.
    #[arg(long, value_enum, default_value = "mixamo")]
    pub convention: ConventionArg,
    /// Leave out the flat wrist cut: the skin ends in an open loop at the wrist, as an
    /// animator's hand mesh does.
    #[arg(long)]
    pub open_wrist: bool,
    /// Export the contact skin (the skin at the flesh lattice's resolution, a small file)
    /// instead of the smooth display skin.
    #[arg(long)]
    pub contact_skin: bool,
}

/// Builds the hand, writes the file and says what it holds.
pub fn run(args: ExportHandArgs) -> Result<()> {
    check_out(&args.out)?;
    let side = match args.side {
        SideArg::Right => Side::Right,
        SideArg::Left => Side::Left,
    };
    let convention = match args.convention {
        ConventionArg::Mixamo => Convention::Mixamo,
        ConventionArg::Rigify => Convention::Rigify,
        ConventionArg::Makehuman => Convention::MakeHuman,
        ConventionArg::Unreal => Convention::Unreal,
    };
    let options = RigOptions {
        open_wrist: args.open_wrist,
        skin: if args.contact_skin {
            RigSkin::Contact
        } else {
            RigSkin::Display
        },
    };
    let form = HandForm::from_name(&args.form).expect("clap checks the form");
    let size = match &args.size {
        None => None,
        Some(text) => {
            // As a scene's `size`: a length (breadth in proportion) or a percentile's name.
            let def = match text.parse::<f64>() {
                Ok(length) => HandSizeDef::Measured {
                    length,
                    breadth: None,
                },
                Err(_) => HandSizeDef::Percentile(text.clone()),
            };
            Some(hand_size(&def).map_err(|_| {
                anyhow::anyhow!(
                    "--size: \"{text}\" is neither a length in metres nor an ANSUR II \
                     percentile ({})",
                    HandSize::percentile_names()
                )
            })?)
        }
    };
    let hand = match (size, form) {
        (None, HandForm::Simple) => {
            HandModel::new(side, args.resolution).context("--resolution")?
        }
        (size, form) => HandModel::built_in(side, size, form, args.resolution, None)
            .context("--size/--resolution")?,
    };
    write_hand_rig(&args.out, &hand, convention, &options)?;
    let joints = rig_joints(&hand, convention)?;
    let mesh = rig_mesh(&hand, &options, &bone_joints(&hand.skeleton, &joints));
    let size = std::fs::metadata(&args.out).map(|m| m.len()).unwrap_or(0);
    println!(
        "wrote {} ({:.1} MB): {} joints ({convention:?} names, {} … {}), skin of {} vertices, {} triangles{}",
        args.out.display(),
        size as f64 / 1e6,
        joints.len(),
        joints[0].name,
        joints[joints.len() - 1].name,
        mesh.positions.len(),
        mesh.triangles.len(),
        if args.open_wrist {
            ", open at the wrist"
        } else {
            ""
        }
    );
    Ok(())
}

/// `--out`, checked before the hand is built (seconds): a name ending in `.glb` (any case), not
/// a folder.
fn check_out(out: &Path) -> Result<()> {
    let glb = out
        .extension()
        .is_some_and(|ext| ext.eq_ignore_ascii_case("glb"));
    if !glb {
        bail!(
            "--out {}: export-hand writes binary glTF (.glb); name the file .glb",
            out.display()
        );
    }
    if out.is_dir() {
        bail!(
            "--out {}: this is a folder; give the .glb file's path",
            out.display()
        );
    }
    Ok(())
}
