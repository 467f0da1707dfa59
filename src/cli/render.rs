//! `prehensile render`: solve a scene and write PNG images of its frames, without a window.

use crate::export::output::{OutputSet, Outputs};
use crate::export::png::{png_bytes, write_png_atomic};
use crate::headless::solve_scene_file;
use crate::headless::{draw_lists, scene_camera};
use crate::present::{Overlay, VisualOptions};
use crate::render::Renderer;
use anyhow::{bail, Context, Result};
use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};

/// `--scale`: 0 draws the bodies undeformed, 1 at true scale, above 1 exaggerated — up to 1000
/// (a hand's displacements, its motion included, are far out of the picture well before that;
/// 1e30 drew nothing but the sky).
pub const DISPLACEMENT_SCALE: std::ops::RangeInclusive<f64> = 0.0..=1000.0;

/// The `--overlay` values.
#[derive(Clone, Copy, ValueEnum)]
pub enum OverlayArg {
    /// Contact pressure (needs contact).
    Pressure,
    /// Von Mises stress.
    Stress,
    /// Displacement magnitude.
    Displacement,
    /// Reaction force arrows.
    Forces,
    /// Plain bodies.
    None,
}

impl From<OverlayArg> for Overlay {
    fn from(o: OverlayArg) -> Self {
        match o {
            OverlayArg::Pressure => Overlay::Pressure,
            OverlayArg::Stress => Overlay::Stress,
            OverlayArg::Displacement => Overlay::Displacement,
            OverlayArg::Forces => Overlay::Forces,
            OverlayArg::None => Overlay::None,
        }
    }
}

/// What to render (the `render` subcommand's arguments).
#[derive(clap::Args)]
pub struct RenderArgs {
    /// The scene (TOML).
    pub scene: PathBuf,
    /// The PNG file, or with --all the folder receiving frame_0000.png, frame_0001.png, ...
    /// (replacing the frames an earlier --all left there; other files stay).
    #[arg(long)]
    pub out: PathBuf,
    /// The frame to render (default 0).
    #[arg(long, conflicts_with = "all")]
    pub frame: Option<usize>,
    /// Render every frame into the --out folder.
    #[arg(long)]
    pub all: bool,
    /// Image width, pixels.
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Image height, pixels.
    #[arg(long, default_value_t = 720)]
    pub height: u32,
    /// Camera: a preset (three-quarter, front, side, top, below) or a `[[camera]]` of the scene.
    #[arg(long, default_value = "three-quarter")]
    pub camera: String,
    /// What colours the bodies or is drawn over them.
    #[arg(long, value_enum, default_value = "stress")]
    pub overlay: OverlayArg,
    /// Displacements are multiplied by this for display: 0 (undeformed) to 1000 (exaggerated);
    /// 1 = true scale.
    #[arg(long, default_value_t = 1.0)]
    pub scale: f64,
    /// Also draw the edges of the simulation mesh.
    #[arg(long)]
    pub wireframe: bool,
    /// Opacity of hand skin, 0–1 (below 1 the bones show through).
    #[arg(long, default_value_t = 1.0)]
    pub skin_opacity: f32,
}

pub fn run(args: RenderArgs) -> Result<()> {
    // Checked before the solve: a display option that cannot be drawn is the option's error.
    if !DISPLACEMENT_SCALE.contains(&args.scale) {
        bail!(
            "--scale {}: the displacement scale must be a number between {} (undeformed) and {} \
             (exaggerated a thousand times; 1 = true scale)",
            crate::util::number::readable(args.scale),
            DISPLACEMENT_SCALE.start(),
            DISPLACEMENT_SCALE.end()
        );
    }
    if !(args.skin_opacity.is_finite() && (0.0..=1.0).contains(&args.skin_opacity)) {
        bail!(
            "--skin-opacity {}: the skin's opacity must be between 0 and 1",
            args.skin_opacity
        );
    }
    if args.all {
        if args.out.exists() && !args.out.is_dir() {
            bail!(
                "--out {}: with --all, --out is the folder receiving frame_0000.png, \
                 frame_0001.png, …, and this is a file",
                args.out.display()
            );
        }
    } else {
        if let Some(ext) = args.out.extension() {
            if !ext.eq_ignore_ascii_case("png") {
                bail!(
                    "--out {}: render writes PNG images; name the file .png",
                    args.out.display()
                );
            }
        }
        if args.out.is_dir() {
            bail!(
                "--out {}: this is a folder; give the PNG file's path (or --all to write every \
                 frame into the folder)",
                args.out.display()
            );
        }
    }
    // The image size against the adapter, before the scene is solved.
    let mut renderer = Renderer::new_headless()?;
    renderer.check_size(args.width, args.height)?;
    let solved = solve_scene_file(&args.scene)?;
    let options = VisualOptions {
        overlay: args.overlay.into(),
        displacement_scale: args.scale,
        wireframe: args.wireframe,
        skin_opacity: args.skin_opacity,
        bones: true,
    };
    let lists = draw_lists(&solved, &options).with_context(|| args.scene.display().to_string())?;
    let camera = scene_camera(
        &solved,
        &lists,
        &args.camera,
        args.width as f32 / args.height.max(1) as f32,
    )?;
    let frames: Vec<usize> = if args.all {
        (0..lists.len()).collect()
    } else {
        let k = args.frame.unwrap_or(0);
        if k >= lists.len() {
            bail!(
                "frame {k} does not exist: the scene has {} frame(s), numbered from 0",
                lists.len()
            );
        }
        vec![k]
    };
    eprintln!("adapter: {}", renderer.adapter_summary());
    if !args.all {
        let image = renderer
            .render_to_rgba(&lists[frames[0]], &camera, args.width, args.height)
            .with_context(|| format!("rendering frame {}", frames[0]))?;
        write_png(&args.out, &image)?;
        println!("wrote {}", args.out.display());
        return Ok(());
    }
    // Every frame into the folder as one set (as `solve` writes its own): the frames of an
    // earlier, longer run that this one lacks are removed; files other than rendered frames
    // (a solve's report and VTUs, the user's) stay.
    let mut set = OutputSet::of(&args.out, Outputs::FrameImages)
        .with_context(|| format!("--out {}", args.out.display()))?;
    let bar = ProgressBar::new(frames.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} frames {elapsed}")
            .expect("valid template"),
    );
    for &k in &frames {
        let image = renderer
            .render_to_rgba(&lists[k], &camera, args.width, args.height)
            .with_context(|| format!("rendering frame {k}"))?;
        let name = format!("frame_{k:04}.png");
        png_bytes(&image)
            .and_then(|bytes| set.write(&name, &bytes))
            .with_context(|| format!("writing {}", args.out.join(&name).display()))?;
        bar.inc(1);
    }
    set.commit()
        .with_context(|| format!("writing into {}", args.out.display()))?;
    bar.finish_and_clear();
    println!(
        "wrote {} frame(s) into {}",
        frames.len(),
        args.out.display()
    );
    Ok(())
}

fn write_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    write_png_atomic(path, image).with_context(|| format!("writing {}", path.display()))
}
