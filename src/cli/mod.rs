//! The command line: clap arguments and dispatch (view | solve | render | export-hand | bench);
//! main.rs calls it.
//! May import everything.
//!
//! The `prehensile` command line: the interactive viewer (the default), and the headless
//! commands: solve scenes, render them to PNG, export the built-in hand as a rigged glTF, run
//! benchmarks.

use crate::app::pose::Preset;
use crate::app::{run_viewer, ViewOptions, ViewerError};
use crate::bench::elements::{element_rows, element_table};
use crate::bench::flexion_refinement::{nested_refinement_rows, refinement_table};
use crate::bench::hand::{hand_rows, hand_tables};
use crate::bench::render::{frame_times, render_table, update_rows};
use crate::bench::solver::{solver_rows, solver_table};
use crate::export::vtu_grid::VtuEncoding;
use crate::fem::solve::FillOrdering;
use crate::headless::{solve_scene_file, write_solved_as, Solved};
use crate::render::Renderer;
use crate::scene::{Scene, DEFAULT_SCENE};
use crate::util::timing::ms;
use anyhow::{Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

mod export_hand;
mod ranges;
mod render;
use export_hand::ExportHandArgs;
use render::{OverlayArg, RenderArgs};

#[derive(Parser)]
#[command(
    name = "prehensile",
    version,
    about = "Finite element simulation of a hand grasping a deformable object (after Gourret, \
             Magnenat-Thalmann & Thalmann 1989)",
    long_about = "Finite element simulation of a hand grasping a deformable object.\n\n\
                  Without a subcommand, opens the viewer window on the built-in default scene (a \
                  hand beside a pressurised rubber ball). Without a display, use the headless \
                  commands: solve, render, export-hand, bench."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the interactive viewer on a scene (the default, on the built-in scene, when no
    /// subcommand is given). Needs a display (X11; Wayland through XWayland).
    View {
        /// The scene (TOML); the built-in default scene when absent.
        scene: Option<PathBuf>,
        /// Write a PNG screenshot of the window once the first frame is solved, then close.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Close after this many frames (with --screenshot: take it then at the latest).
        #[arg(long)]
        exit_after_frames: Option<u64>,
        /// Window width, points.
        #[arg(long, default_value_t = 1600.0)]
        width: f32,
        /// Window height, points.
        #[arg(long, default_value_t = 900.0)]
        height: f32,
        /// Starting pose of the hands.
        #[arg(long, value_enum)]
        preset: Option<PresetArg>,
        /// Starting overlay.
        #[arg(long, value_enum)]
        overlay: Option<OverlayArg>,
        /// Show this key of the scene's timeline (0 = time 0) once it is solved; with
        /// --screenshot, the screenshot waits for it.
        #[arg(long)]
        key: Option<usize>,
    },
    /// Solve a scene file; write report.json, one VTU per frame and frames.pvd into --out.
    Solve {
        /// The scene (TOML).
        scene: PathBuf,
        /// Output folder (created if missing; files appear only when all are written).
        #[arg(long)]
        out: PathBuf,
        /// How the VTU files hold their numbers: binary (zlib-compressed, appended; about a
        /// fifth of the size) or ascii (text).
        #[arg(long, value_enum, default_value = "binary")]
        vtu: VtuArg,
    },
    /// Render frames of a scene to PNG without a window (software rendering works: lavapipe or
    /// llvmpipe; WGPU_BACKEND=vulkan|gl chooses the backend). Prints the adapter to stderr.
    Render(RenderArgs),
    /// Write the built-in hand at rest as a rigged glTF 2.0 binary (.glb): its skin, a skeleton
    /// of joint nodes named in a common rig convention, and skinning weights, as Blender imports
    /// an armature deforming a mesh.
    ExportHand(ExportHandArgs),
    /// Benchmarks; print a Markdown table.
    Bench {
        #[command(subcommand)]
        which: BenchCommand,
    },
}

/// The `--vtu` encodings.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum VtuArg {
    /// zlib-compressed binary blocks in the appended section.
    Binary,
    /// Text.
    Ascii,
}

#[derive(Subcommand)]
enum BenchCommand {
    /// Assembly, factorization, solve and peak memory on an n×n×n cube.
    Solver {
        /// Cells per edge, 1 to 170 (n³ within a body's 5 000 000 elements), comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "10,20,30,40",
            value_parser = ranges::count(ranges::CUBE_CELLS)
        )]
        sizes: Vec<usize>,
        /// Fill-reducing ordering.
        #[arg(long, default_value = "auto", value_parser = ordering_parser())]
        ordering: FillOrdering,
        /// Assembly repetitions (the best time is kept), at least 1.
        #[arg(long, default_value_t = 3, value_parser = ranges::positive)]
        repeats: usize,
    },
    /// Cantilever tip error against Timoshenko and time: hex8, incompatible modes, nonlinear.
    Elements {
        /// Elements through the thickness (mesh 8k × k × k), 1 to 16, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "1,2,4",
            value_parser = ranges::count(ranges::CANTILEVER_CELLS)
        )]
        resolutions: Vec<usize>,
    },
    /// Index finger flexed 0° → 90° at the PIP in 10° increments: FEM (local and whole-hand
    /// regions) and skinning, per mesh resolution.
    Hand {
        /// Mesh resolutions, 0.5 to 4, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "0.75,1,1.25,1.5",
            value_parser = ranges::hand_resolution
        )]
        resolutions: Vec<f64>,
        /// Skip the whole-hand FEM region above this resolution.
        #[arg(long, default_value_t = 1.25, value_parser = ranges::finite)]
        whole_limit: f64,
    },
    /// A free flexion's bone reactions under refinement: the index PIP flexed from rest to each
    /// angle (corotated, local region) on the flesh lattice moved by up to six offsets, per
    /// resolution — the middle phalanx's reaction (mean, lowest, highest over the offsets) and,
    /// over three successive resolutions, the observed order of the mean and its limit. The
    /// defaults take about 47 min on 2 cores.
    FlexionRefinement {
        /// PIP angles, degrees, comma separated (within the joint's range, 0 to 110).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "20,45",
            value_parser = ranges::finite
        )]
        angles: Vec<f64>,
        /// Mesh resolutions, 0.5 to 4, comma separated (each built once per offset; at 4 a
        /// lattice and its flexion take up to 4.8 GB).
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "2.5,3,3.5,4",
            value_parser = ranges::hand_resolution
        )]
        resolutions: Vec<f64>,
        /// How many of the six lattice offsets, 1 to 6.
        #[arg(long, default_value_t = 6, value_parser = ranges::count(ranges::LATTICE_OFFSETS))]
        offsets: usize,
        /// Each lattice also split, every cell into n × n × n, for each n, comma separated (1 to
        /// 4; 1: the lattice itself): the nested refinement, which keeps the lattice's hand; the
        /// orders are then read along the splits.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "1",
            value_parser = ranges::count(ranges::SUBDIVISIONS)
        )]
        subdivisions: Vec<usize>,
    },
    /// Contact methods (Lagrange active set, the paper's iteration) on the same scenes:
    /// iterations, factorizations, time of the contact keyframe.
    Contact {
        /// Scene files, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "assets/scenes/finger-press-ball.toml,assets/scenes/hand-grasp-ball.toml,assets/scenes/bowl-grasp.toml"
        )]
        scenes: Vec<String>,
        /// Coulomb friction coefficients (at least 0) to solve each scene with again
        /// (Lagrange), comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "0.5",
            value_parser = ranges::friction
        )]
        friction: Vec<f64>,
    },
    /// The grasps a user meets: the viewer's presets on the default scene and the shipped grasp
    /// scenes, per hand resolution and tier — time per keyframe, contact steps, factorizations,
    /// the force on the hands or why it stopped.
    Grasp {
        /// Viewer presets on the built-in default scene, comma separated (Pinch, Power grasp,
        /// Fist).
        #[arg(long, value_delimiter = ',', default_value = "Pinch,Power grasp,Fist")]
        presets: Vec<String>,
        /// Scene files, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "assets/scenes/finger-press-ball.toml,assets/scenes/finger-press-sealed-ball.toml,assets/scenes/hand-grasp-ball.toml,assets/scenes/hand-power-grasp.toml,assets/scenes/bowl-grasp.toml"
        )]
        scenes: Vec<String>,
        /// Hand mesh resolutions, 0.5 to 4, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "1",
            value_parser = ranges::hand_resolution
        )]
        resolutions: Vec<f64>,
        /// Tiers (skinning, linear, incremental, corotational, nonlinear), comma separated.
        #[arg(long, value_delimiter = ',', default_value = "corotational")]
        tiers: Vec<String>,
        /// Contact methods (lagrange: exact; paper: the paper's iteration), comma separated.
        #[arg(long, value_delimiter = ',', default_value = "lagrange")]
        methods: Vec<String>,
    },
    /// The skin kept out of itself (self-contact) against the skin passing through itself: the
    /// index PIP to 110°, the middle finger adducted onto the ring finger, the shipped full fist
    /// (the fingers closed, then the thumb over them), per hand resolution — time, increments,
    /// factorizations, the pairs held by the barrier (a point near a facet, an edge near an
    /// edge) and their force, the largest bone reaction, the flesh's change of volume and the
    /// flesh crushed below half its volume. Each motion is a scene of the built-in hand solved
    /// by the keyframe driver, as `prehensile solve` solves it.
    SelfContact {
        /// Hand mesh resolutions, 0.5 to 4, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "1,1.5",
            value_parser = ranges::hand_resolution
        )]
        resolutions: Vec<f64>,
        /// The nonlinear tier (the skin kept out of itself by a barrier in its energy) on the
        /// motions that fold a crease: the index PIP to 110°, the index and middle PIP together.
        #[arg(long)]
        nonlinear: bool,
    },
    /// The gentlest grip from preshape to grip (grasp keyframes): per grasp and hand resolution,
    /// whether it holds, the closing, grip, margin and drift found, the poses solved and the
    /// time; over several resolutions, the grip's refinement study.
    Gentle {
        /// Grasps, comma separated: `power` (the Power-grasp scene with skin friction 0.8, the
        /// power preshape held against gravity) or scene files with grasp keyframes.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "power,assets/scenes/hand-gentle-grip.toml"
        )]
        grasps: Vec<String>,
        /// Hand mesh resolutions, 0.5 to 4, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "1",
            value_parser = ranges::hand_resolution
        )]
        resolutions: Vec<f64>,
    },
    /// Modelling only what a scene requires: the grasp animation solved as by default (FEM near
    /// moving joints and near the contact only) and with everything everywhere; time saved and
    /// the difference in the result.
    Region {
        /// Scene files, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "assets/scenes/finger-press-ball.toml,assets/scenes/hand-and-ball.toml,assets/scenes/hand-grasp-ball.toml"
        )]
        scenes: Vec<String>,
    },
    /// Speed against accuracy: every solver tier (and element option) at three resolutions on
    /// the cantilever, Lamé's sphere, Hertz contact, the index flexion (30°, 90°) and the ball
    /// grasp; prints the tables and writes docs/speed-vs-accuracy.md with its plot.
    Accuracy {
        /// Smaller resolutions and one increment size: a run of a minute or so.
        #[arg(long)]
        quick: bool,
        /// Problems to run, comma separated (cantilever, lame, hertz, flexion30, flexion90,
        /// grasp); all when absent.
        #[arg(long, value_delimiter = ',')]
        only: Vec<String>,
        /// Largest increments of the incremental and corotational tiers, degrees, comma
        /// separated (default 20,10; with --quick 10).
        #[arg(long, value_delimiter = ',')]
        steps: Vec<f64>,
        /// The document written.
        #[arg(long, default_value = "docs/speed-vs-accuracy.md")]
        doc: PathBuf,
        /// The plot written.
        #[arg(long, default_value = "docs/images/speed-vs-accuracy.png")]
        plot: PathBuf,
        /// Print the tables only; write neither the document nor the plot.
        #[arg(long)]
        no_write: bool,
    },
    /// Viewer responsiveness: UI frame time while the solver thread works, and the latency from
    /// a slider change to the new frame on screen (default scene, headless); then the Power
    /// grasp preset and a finger in contact dragged by 2° at a time, with where the time goes.
    Viewer {
        /// Slider changes measured per tier (free fingers), at least 1.
        #[arg(long, default_value_t = 5, value_parser = ranges::positive)]
        changes: usize,
        /// Changes of a finger in contact after the Power grasp preset (0: skip that part).
        #[arg(long, default_value_t = 8)]
        drags: usize,
        /// Only the grasp part (the preset and the drags).
        #[arg(long)]
        grasp_only: bool,
    },
    /// Headless 1280×720 frame time and the per-frame cost of updating a deformed mesh.
    Render {
        /// Frames averaged per measurement, at least 1.
        #[arg(long, default_value_t = 10, value_parser = ranges::positive)]
        frames: usize,
        /// Bigger spheres (n × 2n quads, n from 1 to 1000) for the update cost, comma
        /// separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "100,300",
            value_parser = ranges::count(ranges::SPHERE_RINGS)
        )]
        spheres: Vec<usize>,
    },
}

#[derive(Clone, Copy, ValueEnum)]
enum PresetArg {
    Rest,
    Fist,
    Pinch,
    PowerGrasp,
}

/// `--ordering`: parsed straight into the solver's ordering.
fn ordering_parser() -> impl clap::builder::TypedValueParser<Value = FillOrdering> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(["auto", "nested-dissection", "amd"]).map(|s| match s
        .as_str()
    {
        "amd" => FillOrdering::Amd,
        "nested-dissection" => FillOrdering::NestedDissection,
        _ => FillOrdering::Auto,
    })
}

/// The `prehensile` command: parses the arguments, runs the command, and exits non-zero with the
/// error's chain on failure.
pub fn main() {
    // Mesa's Vulkan device-select layer probes Wayland and X11 for the display's GPU and, with no
    // display (headless), prints "XDG_RUNTIME_DIR is invalid" twice. Prehensile's headless
    // rendering has no display to match, so the layer is skipped unless the user set
    // NODEVICE_SELECT. Done first, while the process has a single thread.
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
    if let Err(e) = run() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    faer::set_global_parallelism(faer::Par::rayon(0));
    let cli = Cli::parse();
    match cli.command {
        None => view(None, ViewOptions::default())?,
        Some(Command::View {
            scene,
            screenshot,
            exit_after_frames,
            width,
            height,
            preset,
            overlay,
            key,
        }) => view(
            scene,
            ViewOptions {
                screenshot,
                exit_after_frames,
                size: [width, height],
                preset: preset.map(|p| match p {
                    PresetArg::Rest => Preset::Rest,
                    PresetArg::Fist => Preset::Fist,
                    PresetArg::Pinch => Preset::Pinch,
                    PresetArg::PowerGrasp => Preset::PowerGrasp,
                }),
                overlay: overlay.map(Into::into),
                key,
            },
        )?,
        Some(Command::Solve { scene, out, vtu }) => {
            let parsed = crate::scene::Scene::load(&scene)?;
            crate::headless::refuse_writing_over_inputs(&parsed, &scene, &out)?;
            let solved = solve_scene_file(&scene)?;
            let encoding = match vtu {
                VtuArg::Binary => VtuEncoding::Binary,
                VtuArg::Ascii => VtuEncoding::Ascii,
            };
            let written = write_solved_as(&solved, &out, encoding)?;
            print_summary(&solved);
            for w in &solved.report.warnings {
                eprintln!("warning: {w}");
            }
            for path in written {
                println!("wrote {}", path.display());
            }
            if let Some(message) = crate::headless::unsolved(&solved) {
                eprintln!("error: {message}");
                std::process::exit(2);
            }
        }
        Some(Command::Render(args)) => render::run(args)?,
        Some(Command::ExportHand(args)) => export_hand::run(args)?,
        Some(Command::Bench { which }) => match which {
            BenchCommand::Solver {
                sizes,
                ordering,
                repeats,
            } => {
                println!(
                    "solver benchmark: unit cube, bottom clamped, top pressed; ordering {ordering:?}; {} threads",
                    rayon::current_num_threads()
                );
                let rows = solver_rows(&sizes, ordering, repeats)?;
                print!("{}", solver_table(&rows));
            }
            BenchCommand::Elements { resolutions } => {
                println!(
                    "element benchmark: cantilever 8×1×1 m, E = 1 MPa, ν = 0.3, tip load 1 N; {} threads",
                    rayon::current_num_threads()
                );
                print!("{}", element_table(&element_rows(&resolutions)?));
            }
            BenchCommand::Hand {
                resolutions,
                whole_limit,
            } => {
                println!(
                    "hand benchmark: index PIP 0° → 90° in 10° increments (linear tier: keyframes every 15°); {} threads",
                    rayon::current_num_threads()
                );
                print!("{}", hand_tables(&hand_rows(&resolutions, whole_limit)?));
            }
            BenchCommand::FlexionRefinement {
                angles,
                resolutions,
                offsets,
                subdivisions,
            } => {
                println!(
                    "flexion refinement benchmark: index PIP from rest, corotated, local region; {} threads",
                    rayon::current_num_threads()
                );
                print!(
                    "{}",
                    refinement_table(&nested_refinement_rows(
                        &angles,
                        &resolutions,
                        &subdivisions,
                        offsets
                    )?)
                );
            }
            BenchCommand::Contact { scenes, friction } => {
                println!(
                    "contact benchmark: last keyframe of each scene, {} threads",
                    rayon::current_num_threads()
                );
                let rows = crate::bench::contact::contact_rows(&scenes, &friction)?;
                print!("{}", crate::bench::contact::contact_table(&rows));
            }
            BenchCommand::Grasp {
                presets,
                scenes,
                resolutions,
                tiers,
                methods,
            } => {
                let tiers = tiers
                    .iter()
                    .map(|t| match t.as_str() {
                        "skinning" => Ok(crate::scene::TierName::Skinning),
                        "linear" => Ok(crate::scene::TierName::Linear),
                        "incremental" => Ok(crate::scene::TierName::Incremental),
                        "corotational" => Ok(crate::scene::TierName::Corotational),
                        "nonlinear" => Ok(crate::scene::TierName::Nonlinear),
                        other => Err(anyhow::anyhow!(
                            "--tiers: no tier \"{other}\" (skinning, linear, incremental, \
                             corotational, nonlinear)"
                        )),
                    })
                    .collect::<anyhow::Result<Vec<_>>>()?;
                let methods = methods
                    .iter()
                    .map(|m| {
                        use crate::scene::ContactMethodName;
                        ContactMethodName::ALL
                            .into_iter()
                            .find(|c| c.name() == m.trim())
                            .ok_or_else(|| {
                                anyhow::anyhow!(
                                    "--methods: no contact method \"{m}\" (lagrange, paper)"
                                )
                            })
                    })
                    .collect::<anyhow::Result<Vec<_>>>()?;
                println!("grasp benchmark: {} threads", rayon::current_num_threads());
                let rows = crate::bench::grasp::grasp_rows(
                    &presets,
                    &scenes,
                    &resolutions,
                    &tiers,
                    &methods,
                )?;
                print!("{}", crate::bench::grasp::grasp_table(&rows));
            }
            BenchCommand::SelfContact {
                resolutions,
                nonlinear,
            } => {
                println!(
                    "self-contact benchmark{}: {} threads",
                    if nonlinear {
                        ", the nonlinear tier"
                    } else {
                        ""
                    },
                    rayon::current_num_threads()
                );
                let rows = crate::bench::self_contact::self_contact_rows(&resolutions, nonlinear)?;
                print!("{}", crate::bench::self_contact::self_contact_table(&rows));
            }
            BenchCommand::Gentle {
                grasps,
                resolutions,
            } => {
                println!(
                    "gentlest-grip benchmark: {} threads",
                    rayon::current_num_threads()
                );
                let rows = crate::bench::gentle::gentle_rows(&grasps, &resolutions)?;
                print!("{}", crate::bench::gentle::gentle_table(&rows));
            }
            BenchCommand::Region { scenes } => {
                println!("region benchmark: {} threads", rayon::current_num_threads());
                for scene in &scenes {
                    println!("\n### {scene}\n");
                    let runs = crate::bench::region::region_runs(scene)?;
                    print!("{}", crate::bench::region::region_table(&runs));
                }
            }
            BenchCommand::Accuracy {
                quick,
                only,
                steps,
                doc,
                plot,
                no_write,
            } => accuracy(quick, &only, steps, &doc, &plot, no_write)?,
            BenchCommand::Viewer {
                changes,
                drags,
                grasp_only,
            } => {
                println!(
                    "viewer benchmark: default scene, {} threads",
                    rayon::current_num_threads()
                );
                if !grasp_only {
                    print!("{}", crate::bench::viewer::run(changes)?);
                }
                if drags > 0 || grasp_only {
                    println!();
                    print!("{}", crate::bench::viewer_contact::run(drags)?);
                }
            }
            BenchCommand::Render { frames, spheres } => {
                let t = std::time::Instant::now();
                let mut renderer = Renderer::new_headless()?;
                let renderer_ms = ms(t);
                eprintln!("adapter: {}", renderer.adapter_summary());
                let times = frame_times(renderer_ms, &mut renderer, frames)?;
                let rows = update_rows(&mut renderer, &spheres, frames)?;
                print!("{}", render_table(&times, &rows));
            }
        },
    }
    Ok(())
}

/// `prehensile bench accuracy`: runs the bench, prints the tables, writes the document and plot.
fn accuracy(
    quick: bool,
    only: &[String],
    steps: Vec<f64>,
    doc: &std::path::Path,
    plot: &std::path::Path,
    no_write: bool,
) -> Result<()> {
    use crate::bench::accuracy as ba;
    let mut settings = ba::Settings::new(quick);
    if !only.is_empty() {
        settings.problems = only
            .iter()
            .map(|k| ba::ProblemId::from_key(k.trim()))
            .collect::<Result<_, _>>()
            .map_err(anyhow::Error::msg)
            .context("--only")?;
    }
    if !steps.is_empty() {
        settings.steps = steps;
    }
    settings.validate().map_err(anyhow::Error::msg)?;
    let machine = ba::Machine::now();
    println!("accuracy benchmark: {}", machine.summary());
    let results = ba::accuracy_results(&settings, &mut |line| eprintln!("{line}"))
        .map_err(anyhow::Error::msg)?;
    for p in &settings.problems {
        print!("\n{}", ba::problem_section(&results, *p));
    }
    if no_write {
        return Ok(());
    }
    let command = std::env::args()
        .skip(1)
        .fold(String::from("prehensile"), |s, a| s + " " + &a);
    // Some problems only: their sections replace those of the document, whose other sections
    // and plot stay (a whole document of one problem would lose the others).
    if !only.is_empty() {
        if let Ok(existing) = std::fs::read_to_string(doc) {
            let text = ba::merged_text(&existing, &results, &machine, &command);
            ba::write_atomic(doc, &text).with_context(|| doc.display().to_string())?;
            println!(
                "\nwrote the sections of {} into {} (the plot, {}, is left as it was: run \
                 without --only to redraw it)",
                only.join(", "),
                doc.display(),
                plot.display()
            );
            return Ok(());
        }
    }
    let title = format!(
        "Speed against accuracy{}: {}",
        if quick { " (quick)" } else { "" },
        machine.summary()
    );
    ba::write_plot(plot, &results, &title).map_err(anyhow::Error::msg)?;
    ba::write_doc(doc, &results, &machine, &ba::plot_link(doc, plot), &command)
        .map_err(anyhow::Error::msg)?;
    println!("\nwrote {} and {}", doc.display(), plot.display());
    Ok(())
}

/// Opens the viewer; without a display, one line naming the headless commands and exit code 2.
fn view(scene: Option<PathBuf>, options: ViewOptions) -> Result<()> {
    let (scene, name) = match scene {
        Some(path) => (Scene::load(&path)?, path.display().to_string()),
        None => (
            Scene::parse(DEFAULT_SCENE, "<built-in default scene>")?,
            "built-in default scene".to_string(),
        ),
    };
    match run_viewer(scene, &name, options) {
        Ok(()) => Ok(()),
        Err(e @ ViewerError::NoDisplay { .. }) => {
            eprintln!("prehensile: {e}");
            std::process::exit(2);
        }
        Err(e) => Err(e.into()),
    }
}

fn print_summary(solved: &Solved) {
    let r = &solved.report;
    println!(
        "{}: {} nodes, {} elements, {} dofs",
        r.scene, r.model.nodes, r.model.elements, r.model.dofs
    );
    for f in &r.frames {
        let s = &f.solver;
        println!(
            "frame {}: {} free / {} prescribed dofs; assembly {:.1} ms, symbolic {:.1} ms, \
             factorization {:.1} ms, solve {:.1} ms; residual {:.2e}",
            f.frame,
            s.free_dofs,
            s.prescribed_dofs,
            s.timings_ms.assembly,
            s.timings_ms.symbolic,
            s.timings_ms.factorization,
            s.timings_ms.solve,
            s.residual
        );
        println!(
            "  max displacement {:.4e} m, max von Mises {:.4e} Pa, out of balance [{:.2e}, {:.2e}, {:.2e}] N",
            f.max_displacement,
            f.max_von_mises,
            f.equilibrium.imbalance[0],
            f.equilibrium.imbalance[1],
            f.equilibrium.imbalance[2]
        );
        for (name, c) in &f.constraints {
            println!(
                "  constraint {name}: reaction [{:.4e}, {:.4e}, {:.4e}] N over {} dofs",
                c.reaction[0], c.reaction[1], c.reaction[2], c.dofs
            );
        }
        for (name, h) in &f.hands {
            let m = &h.motion;
            let (bone, largest) = h
                .bones
                .iter()
                .map(|(n, b)| (n.as_str(), b.magnitude))
                .fold(("-", 0.0), |a, b| if b.1 > a.1 { b } else { a });
            println!(
                "  hand {name}: {} increments, {} factorizations over {} FEM cells ({} free dofs; \
                 {} cells skinned far from contact{}), {:.0} ms; flesh volume change {:+.3} %; \
                 largest bone reaction {largest:.3} N ({bone}){}",
                m.increments,
                m.factorizations,
                m.fem_cells,
                m.free_dofs,
                m.far_cells,
                if m.far_digits.is_empty() {
                    String::new()
                } else {
                    format!(": {}", m.far_digits.join(", "))
                },
                m.total_ms,
                h.volume_change * 100.0,
                if m.self_contacts > 0 {
                    format!(
                        "; self-contact {} pairs held, {:.3} N",
                        m.self_contacts, m.self_contact_force
                    )
                } else {
                    String::new()
                }
            );
        }
        // A grasp its muscles cannot hold (the paper: not realisable), with what to do.
        for (name, h) in f.hands.iter().filter(|(_, h)| !h.realisable) {
            for o in &h.overloads {
                println!(
                    "  hand {name}: not realisable: {} pushed with {:.3} N, above its threshold \
                     {:.3} N; {}",
                    o.bone, o.reaction, o.threshold, o.advice
                );
            }
        }
        for (name, p) in &f.probes {
            println!(
                "  probe {name}: displacement [{:.4e}, {:.4e}, {:.4e}] m",
                p.displacement[0], p.displacement[1], p.displacement[2]
            );
        }
    }
}
