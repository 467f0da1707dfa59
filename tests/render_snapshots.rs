//! Image regression tests: the real shaders, rendered headless (lavapipe in CI), compared with
//! reference PNGs under tests/snapshots/ with a tolerance. On a mismatch the actual image and a
//! difference image go to target/snapshot-failures/. `PREHENSILE_UPDATE_SNAPSHOTS=1` rewrites
//! the references on purpose.
//!
//! Without any graphics adapter these tests FAIL (they never pass silently): install Mesa's
//! software renderers (`.ci/run` does).

use glam::Vec3;
use image::{Rgba, RgbaImage};
use prehensile::export::png::write_png_atomic;
use prehensile::headless::render_frame;
use prehensile::headless::solve_scene_file;
use prehensile::present::{Overlay, VisualOptions};
use prehensile::render::{Camera, DrawList, Quality, Renderer, Surface};
use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

const WIDTH: u32 = 480;
const HEIGHT: u32 = 270;
/// A pixel differs when one of its channels differs by more than this.
const CHANNEL_TOLERANCE: u8 = 16;
/// A snapshot fails when more than this fraction of its pixels differ.
const MAX_DIFFERING: f64 = 0.01;

/// One renderer for the whole test binary (creating pipelines costs time on a CPU renderer).
fn renderer() -> std::sync::MutexGuard<'static, Renderer> {
    static RENDERER: OnceLock<Result<Mutex<Renderer>, String>> = OnceLock::new();
    match RENDERER.get_or_init(|| {
        Renderer::new_headless()
            .map(Mutex::new)
            .map_err(|e| e.to_string())
    }) {
        Ok(r) => r.lock().unwrap_or_else(|e| e.into_inner()),
        Err(e) => panic!(
            "the render tests need a graphics adapter and found none: {e}\n\
             (CI installs Mesa's lavapipe: apt-get install mesa-vulkan-drivers libvulkan1)"
        ),
    }
}

fn manifest() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn failures_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest().join("target"))
        .join("snapshot-failures")
}

/// Pixels whose largest channel difference exceeds the tolerance, and the difference image
/// (the reference greyed, differing pixels in magenta).
fn compare(reference: &RgbaImage, actual: &RgbaImage) -> (usize, RgbaImage) {
    let mut diff = RgbaImage::new(reference.width(), reference.height());
    let mut count = 0;
    for (x, y, r) in reference.enumerate_pixels() {
        let a = actual.get_pixel(x, y);
        let d = (0..4).map(|k| r[k].abs_diff(a[k])).max().unwrap_or(0);
        let grey = ((r[0] as u32 + r[1] as u32 + r[2] as u32) / 6) as u8;
        if d > CHANNEL_TOLERANCE {
            count += 1;
            diff.put_pixel(x, y, Rgba([255, 0, 255, 255]));
        } else {
            diff.put_pixel(x, y, Rgba([grey, grey, grey, 255]));
        }
    }
    (count, diff)
}

/// Compares `actual` with tests/snapshots/`name`.png (or rewrites it when asked to).
fn check_snapshot(name: &str, actual: &RgbaImage) {
    let reference_path = manifest()
        .join("tests/snapshots")
        .join(format!("{name}.png"));
    if std::env::var("PREHENSILE_UPDATE_SNAPSHOTS").is_ok_and(|v| v == "1") {
        write_png_atomic(&reference_path, actual).expect("write the reference");
        eprintln!("updated {}", reference_path.display());
        return;
    }
    let save_failure = |what: &str, img: &RgbaImage| -> PathBuf {
        let p = failures_dir().join(format!("{name}-{what}.png"));
        write_png_atomic(&p, img).expect("write the failure image");
        p
    };
    let reference = match image::open(&reference_path) {
        Ok(img) => img.to_rgba8(),
        Err(e) => {
            let p = save_failure("actual", actual);
            panic!(
                "no usable reference {} ({e}); the actual image is {}. Run with \
                 PREHENSILE_UPDATE_SNAPSHOTS=1 to create it.",
                reference_path.display(),
                p.display()
            );
        }
    };
    if reference.dimensions() != actual.dimensions() {
        let p = save_failure("actual", actual);
        panic!(
            "{name}: size {:?}, reference {:?}; actual image: {}",
            actual.dimensions(),
            reference.dimensions(),
            p.display()
        );
    }
    let (count, diff) = compare(&reference, actual);
    let fraction = count as f64 / (reference.width() * reference.height()) as f64;
    if fraction > MAX_DIFFERING {
        let a = save_failure("actual", actual);
        let d = save_failure("diff", &diff);
        panic!(
            "{name}: {count} pixels ({:.2}%) differ by more than {CHANNEL_TOLERANCE} (allowed \
             {:.2}%).\n  actual: {}\n  diff:   {}\n  reference: {}\n(if the change is intended: \
             PREHENSILE_UPDATE_SNAPSHOTS=1 cargo test --release --test suite render_snapshots::)",
            fraction * 100.0,
            MAX_DIFFERING * 100.0,
            a.display(),
            d.display(),
            reference_path.display()
        );
    }
}

fn scene_snapshot(name: &str, scene: &str, overlay: Overlay, wireframe: bool, camera: &str) {
    let solved =
        solve_scene_file(&manifest().join("assets/scenes").join(scene)).expect("the scene solves");
    let options = VisualOptions {
        overlay,
        wireframe,
        ..Default::default()
    };
    let image = render_frame(&mut renderer(), &solved, 0, &options, camera, WIDTH, HEIGHT)
        .expect("renders");
    check_snapshot(name, &image);
}

/// The finger-flexion scene, solved once for the hand snapshots.
fn finger_flexion() -> &'static prehensile::headless::Solved {
    static SOLVED: OnceLock<prehensile::headless::Solved> = OnceLock::new();
    SOLVED.get_or_init(|| {
        solve_scene_file(&manifest().join("assets/scenes/finger-flexion.toml"))
            .expect("the scene solves")
    })
}

fn hand_snapshot(name: &str, frame: usize, options: VisualOptions, camera: &str) {
    let image = render_frame(
        &mut renderer(),
        finger_flexion(),
        frame,
        &options,
        camera,
        WIDTH,
        HEIGHT,
    )
    .expect("renders");
    check_snapshot(name, &image);
}

#[test]
fn rest_hand() {
    hand_snapshot("hand-rest", 0, VisualOptions::default(), "three-quarter");
}

#[test]
fn flexed_finger_with_bones_showing() {
    let options = VisualOptions {
        skin_opacity: 0.4,
        ..Default::default()
    };
    hand_snapshot("hand-flexed-bones", 3, options, "front");
}

#[test]
fn flexed_finger_bone_forces() {
    let options = VisualOptions {
        overlay: Overlay::Forces,
        skin_opacity: 0.4,
        ..Default::default()
    };
    hand_snapshot("hand-flexed-forces", 2, options, "front");
}

#[test]
fn ball_press_pressure_map() {
    scene_snapshot(
        "ball-on-table-pressure",
        "ball-on-table.toml",
        Overlay::Pressure,
        false,
        "under",
    );
}

#[test]
fn default_ball_stress() {
    scene_snapshot(
        "default-stress",
        "default.toml",
        Overlay::Stress,
        false,
        "three-quarter",
    );
}

#[test]
fn solid_ball_displacement() {
    scene_snapshot(
        "solid-ball-displacement",
        "solid-ball-on-table.toml",
        Overlay::Displacement,
        false,
        "three-quarter",
    );
}

#[test]
fn block_press_forces() {
    scene_snapshot(
        "block-press-forces",
        "block-press.toml",
        Overlay::Forces,
        false,
        "three-quarter",
    );
}

#[test]
fn default_ball_wireframe() {
    scene_snapshot(
        "default-wireframe",
        "default.toml",
        Overlay::None,
        true,
        "front",
    );
}

#[test]
fn comparison_counts_differing_pixels() {
    let a = RgbaImage::from_pixel(10, 10, Rgba([100, 100, 100, 255]));
    let mut b = a.clone();
    b.put_pixel(3, 4, Rgba([100, 100, 100 + CHANNEL_TOLERANCE + 1, 255]));
    b.put_pixel(5, 5, Rgba([100 + CHANNEL_TOLERANCE, 100, 100, 255]));
    let (count, diff) = compare(&a, &b);
    assert_eq!(count, 1);
    assert_eq!(diff.get_pixel(3, 4).0, [255, 0, 255, 255]);
    assert_eq!(diff.get_pixel(5, 5).0, [50, 50, 50, 255]);
}

/// A square of side 2 centred on `c`, facing +z, two triangles.
fn square(c: Vec3, color: [f32; 4]) -> Surface {
    let p = |dx: f32, dy: f32| [c.x + dx, c.y + dy, c.z];
    Surface {
        positions: vec![p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        scalars: None,
        color,
    }
}

fn top_camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, 10.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 30f32.to_radians(),
    }
}

fn px(img: &RgbaImage, p: [f32; 2]) -> [u8; 4] {
    img.get_pixel(p[0] as u32, p[1] as u32).0
}

#[test]
fn projected_corner_lands_on_the_drawn_corner() {
    // A red square seen from above: Camera::project of its corners must bound the red pixels.
    let mut r = renderer();
    let cam = top_camera();
    let list = DrawList {
        surfaces: vec![square(Vec3::new(0.5, 0.25, 0.0), [0.8, 0.05, 0.05, 1.0])],
        ..Default::default()
    };
    let img = r.render_to_rgba(&list, &cam, 200, 100).unwrap();
    let red = |c: [u8; 4]| c[0] as i32 > c[1] as i32 + 80 && c[0] as i32 > c[2] as i32 + 80;
    let lo = cam.project(Vec3::new(-0.5, 1.25, 0.0), 200, 100).unwrap();
    let hi = cam.project(Vec3::new(1.5, -0.75, 0.0), 200, 100).unwrap();
    // Top-left corner (x = -0.5, y = 1.25) and bottom-right: just inside is red, just outside not.
    assert!(
        red(px(&img, [lo[0] + 2.0, lo[1] + 2.0])),
        "{:?}",
        px(&img, [lo[0] + 2.0, lo[1] + 2.0])
    );
    assert!(!red(px(&img, [lo[0] - 2.0, lo[1] - 2.0])));
    assert!(red(px(&img, [hi[0] - 2.0, hi[1] - 2.0])));
    assert!(!red(px(&img, [hi[0] + 2.0, hi[1] + 2.0])));
    // The square spans 2 m at 10 m with a 30° field: 2 / (2·10·tan 15°) of the height.
    let expected = 2.0 / (2.0 * 10.0 * 15f32.to_radians().tan()) * 100.0;
    assert!(
        ((hi[1] - lo[1]) - expected).abs() < 0.01,
        "{} vs {expected}",
        hi[1] - lo[1]
    );
}

#[test]
fn translucent_surface_shows_what_is_behind() {
    let mut r = renderer();
    let cam = top_camera();
    let blue = square(Vec3::ZERO, [0.02, 0.05, 0.8, 1.0]);
    let mut list = DrawList {
        surfaces: vec![blue.clone()],
        ..Default::default()
    };
    let centre = [100.0, 50.0];
    let below = px(&r.render_to_rgba(&list, &cam, 200, 100).unwrap(), centre);
    list.surfaces
        .push(square(Vec3::new(0.0, 0.0, 1.0), [0.8, 0.05, 0.02, 0.5]));
    let both = px(&r.render_to_rgba(&list, &cam, 200, 100).unwrap(), centre);
    list.surfaces[1].color[3] = 1.0;
    let red = px(&r.render_to_rgba(&list, &cam, 200, 100).unwrap(), centre);
    // Half-transparent red over blue: redder than blue alone, bluer than opaque red.
    assert!(
        both[0] > below[0] + 40 && both[2] > red[2] + 40,
        "{below:?} {both:?} {red:?}"
    );
}

#[test]
fn updated_positions_move_the_drawn_surface() {
    let mut r = renderer();
    let cam = top_camera();
    let list = DrawList {
        surfaces: vec![square(Vec3::new(-1.2, 0.0, 0.0), [0.8, 0.05, 0.05, 1.0])],
        ..Default::default()
    };
    let mut scene = r.upload(&list).unwrap();
    let red = |c: [u8; 4]| c[0] as i32 > c[1] as i32 + 80 && c[0] as i32 > c[2] as i32 + 80;
    let left = cam.project(Vec3::new(-1.2, 0.0, 0.0), 200, 100).unwrap();
    let right = cam.project(Vec3::new(1.2, 0.0, 0.0), 200, 100).unwrap();
    let img = r.render_scene_to_rgba(&mut scene, &cam, 200, 100).unwrap();
    assert!(red(px(&img, left)) && !red(px(&img, right)));
    let moved: Vec<[f32; 3]> = list.surfaces[0]
        .positions
        .iter()
        .map(|p| [p[0] + 2.4, p[1], p[2]])
        .collect();
    let gpu = r.queue().clone();
    scene.surfaces[0].update_positions(&gpu, &moved).unwrap();
    let img = r.render_scene_to_rgba(&mut scene, &cam, 200, 100).unwrap();
    assert!(!red(px(&img, left)) && red(px(&img, right)));
    assert!(scene.surfaces[0]
        .update_positions(&gpu, &moved[..3])
        .is_err());
}

#[test]
fn rendering_is_repeatable() {
    let solved = solve_scene_file(&manifest().join("assets/scenes/block-press.toml")).unwrap();
    let opts = VisualOptions::default();
    let a = render_frame(&mut renderer(), &solved, 0, &opts, "side", 160, 90).unwrap();
    let b = render_frame(&mut renderer(), &solved, 0, &opts, "side", 160, 90).unwrap();
    assert_eq!(compare(&a, &b).0, 0);
    let err = render_frame(&mut renderer(), &solved, 3, &opts, "side", 160, 90).unwrap_err();
    assert!(err.to_string().contains("frame 3 does not exist"), "{err}");
    let err = render_frame(&mut renderer(), &solved, 0, &opts, "nowhere", 160, 90).unwrap_err();
    assert!(err.to_string().contains("three-quarter"), "{err}");
}

/// Reads a texture of the headless format back (test-side copy of what the window path draws).
fn read_texture(r: &Renderer, texture: &wgpu::Texture) -> Vec<u8> {
    let (w, h) = (texture.width(), texture.height());
    let row = (w * 4).div_ceil(256) * 256;
    let buffer = r.device().create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: (row * h) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = r.device().create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(h),
            },
        },
        texture.size(),
    );
    r.queue().submit([encoder.finish()]);
    buffer.map_async(wgpu::MapMode::Read, .., |res| res.expect("map"));
    r.wait_idle().unwrap();
    let data = buffer.get_mapped_range(..).unwrap();
    (0..h as usize)
        .flat_map(|y| data[y * row as usize..y * row as usize + w as usize * 4].to_vec())
        .collect()
}

/// A texture standing for the window's (`Renderer::render` draws into it), and its view.
fn window_target(r: &Renderer, (w, h): (u32, u32)) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = r.device().create_texture(&wgpu::TextureDescriptor {
        label: Some("window stand-in"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: prehensile::render::HEADLESS_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}

#[test]
fn window_path_draws_the_same_image_as_the_headless_path() {
    // The interactive window renders into its own texture view with `Renderer::render`.
    let solved =
        solve_scene_file(&manifest().join("assets/scenes/solid-ball-on-table.toml")).unwrap();
    let options = VisualOptions {
        overlay: Overlay::Displacement,
        ..Default::default()
    };
    let lists = prehensile::headless::draw_lists(&solved, &options).unwrap();
    let camera = prehensile::headless::camera_for(&lists, "side", 1.5).unwrap();
    let mut r = renderer();
    let mut scene = r.upload(&lists[0]).unwrap();
    let headless = r
        .render_scene_to_rgba(&mut scene, &camera, 150, 100)
        .unwrap();
    let (texture, view) = window_target(&r, (150, 100));
    r.render(&mut scene, &camera, &view, 150, 100).unwrap();
    let window = read_texture(&r, &texture);
    assert_eq!(window.len(), headless.as_raw().len());
    assert!(window == *headless.as_raw(), "the two paths differ");
    // And a bad size is an error, not a panic.
    assert!(r.render(&mut scene, &camera, &view, 0, 100).is_err());
}

/// Draws with `quality` for as long as it lives, then anti-aliased again (the test binary shares
/// one renderer).
struct Drawing<'a>(std::sync::MutexGuard<'a, Renderer>);

impl<'a> Drawing<'a> {
    fn at(mut r: std::sync::MutexGuard<'a, Renderer>, quality: Quality) -> Self {
        r.set_quality(quality);
        Drawing(r)
    }
}

impl Drop for Drawing<'_> {
    fn drop(&mut self) {
        self.0.set_quality(Quality::Full);
    }
}

/// The draft the window draws while its view changes fast (`Quality::Draft`: one sample per
/// pixel, one shadow tap, fewer samples of the ground's occlusion): a slanted edge anti-aliased
/// has pixels between the surface's colour and the background's, a draft's has none; a scene
/// with its ground and shadows drawn as a draft differs from the anti-aliased image only along
/// edges and penumbrae; the window's path draws the same draft as the headless one.
#[test]
fn a_draft_draws_the_same_scene_with_one_sample_per_pixel() {
    let cam = top_camera();
    let list = DrawList {
        surfaces: vec![Surface {
            positions: vec![[-1.5, -1.0, 0.0], [1.5, -0.6, 0.0], [-0.5, 1.2, 0.0]],
            indices: vec![0, 1, 2],
            scalars: None,
            color: [0.8, 0.05, 0.05, 1.0],
        }],
        ..Default::default()
    };
    let redness = |c: &Rgba<u8>| c[0] as i32 - c[1].max(c[2]) as i32;
    let full = renderer().render_to_rgba(&list, &cam, 200, 100).unwrap();
    let draft = Drawing::at(renderer(), Quality::Draft)
        .0
        .render_to_rgba(&list, &cam, 200, 100)
        .unwrap();
    let inside = redness(full.get_pixel(90, 50));
    let outside = redness(full.get_pixel(2, 2));
    assert!(inside > outside + 100, "{inside} vs {outside}");
    let between = |img: &RgbaImage| {
        img.pixels()
            .filter(|p| {
                let x = redness(p);
                x > outside + (inside - outside) / 4 && x < inside - (inside - outside) / 4
            })
            .count()
    };
    let (blended_full, blended_draft) = (between(&full), between(&draft));
    assert!(
        blended_full >= 20,
        "{blended_full} edge pixels anti-aliased"
    );
    assert_eq!(blended_draft, 0, "a draft blends no edge");

    let solved =
        solve_scene_file(&manifest().join("assets/scenes/solid-ball-on-table.toml")).unwrap();
    let lists = prehensile::headless::draw_lists(&solved, &VisualOptions::default()).unwrap();
    let camera = prehensile::headless::camera_for(&lists, "three-quarter", 1.5).unwrap();
    let (w, h) = (240, 160);
    let mut scene = renderer().upload(&lists[0]).unwrap();
    let full = renderer()
        .render_scene_to_rgba(&mut scene, &camera, w, h)
        .unwrap();
    let mut drawing = Drawing::at(renderer(), Quality::Draft);
    let r = &mut drawing.0;
    let draft = r.render_scene_to_rgba(&mut scene, &camera, w, h).unwrap();
    let (count, _) = compare(&full, &draft);
    let fraction = count as f64 / (w * h) as f64;
    eprintln!(
        "draft against anti-aliased: {count} pixels ({:.2} %) differ",
        100.0 * fraction
    );
    assert!(count > 0 && fraction < 0.05, "{count} pixels differ");
    let (texture, view) = window_target(r, (w, h));
    r.render(&mut scene, &camera, &view, w, h).unwrap();
    assert!(
        read_texture(r, &texture) == *draft.as_raw(),
        "the two paths differ"
    );
}

/// The lights' maps (shadow, under-map) are drawn again only when what casts shadows changed,
/// not when the camera alone moved: a square moved in place (`update_positions`, the bounds
/// unchanged — the lights' views the same) takes its shadow along, as drawn from a fresh
/// upload; an orbit with the maps kept draws what it draws with them drawn afresh.
#[test]
fn the_shadows_follow_the_casters_and_not_the_camera() {
    let mut r = renderer();
    let above = Camera {
        eye: Vec3::new(0.0, 0.0, 30.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y: 30f32.to_radians(),
    };
    let list = |x: f32| DrawList {
        surfaces: vec![
            square(Vec3::new(x, 0.0, 1.0), [0.2, 0.6, 0.2, 1.0]),
            // A sliver spanning the bounds, so that the square moves within them.
            Surface {
                positions: vec![[-4.0, -4.0, 0.0], [-3.9, -4.0, 0.0], [4.0, 4.0, 1.2]],
                indices: vec![0, 1, 2],
                scalars: None,
                color: [0.5, 0.5, 0.5, 1.0],
            },
        ],
        ground: Some(prehensile::render::Ground {
            height: 0.0,
            center: [0.0, 0.0],
            extent: 6.0,
        }),
        ..Default::default()
    };
    let (w, h) = (240, 240);
    let light = |img: &RgbaImage, x: f32, y: f32| {
        let p = px(img, above.project(Vec3::new(x, y, 0.0), w, h).unwrap());
        p[0] as i32 + p[1] as i32 + p[2] as i32
    };
    // The key light comes from (−0.3, −0.9, 1.6): a point 1 m up shadows the ground
    // (0.19, 0.56) m further; beyond the square's far edge (y = 1), y = 1.3 is in its shadow.
    let shadowed =
        |img: &RgbaImage, x: f32| light(img, x + 0.19, 1.3) + 60 < light(img, x + 0.19, -1.6);
    let mut scene = r.upload(&list(-1.5)).unwrap();
    let before = r.render_scene_to_rgba(&mut scene, &above, w, h).unwrap();
    assert!(shadowed(&before, -1.5) && !shadowed(&before, 1.5));
    let moved = list(1.5);
    let queue = r.queue().clone();
    scene.surfaces[0]
        .update_positions(&queue, &moved.surfaces[0].positions)
        .unwrap();
    let after = r.render_scene_to_rgba(&mut scene, &above, w, h).unwrap();
    assert!(!shadowed(&after, -1.5) && shadowed(&after, 1.5));
    let mut fresh = r.upload(&moved).unwrap();
    let expected = r.render_scene_to_rgba(&mut fresh, &above, w, h).unwrap();
    assert_eq!(compare(&after, &expected).0, 0);

    let orbited = Camera {
        eye: Vec3::new(8.0, -20.0, 14.0),
        ..above
    };
    let kept = r.render_scene_to_rgba(&mut scene, &orbited, w, h).unwrap();
    let mut other = r.upload(&list(0.0)).unwrap();
    r.render_scene_to_rgba(&mut other, &orbited, w, h).unwrap();
    let drawn_again = r.render_scene_to_rgba(&mut scene, &orbited, w, h).unwrap();
    assert!(
        kept == drawn_again,
        "an orbit with the maps kept draws otherwise"
    );
}
