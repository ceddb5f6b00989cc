//! Motion blur and rolling shutter as a sequence renders them (`camera::motion`,
//! `settings::shutter`), measured against their analytic sizes: the camera slides 1 m a frame
//! sideways at 24 fps past a 0.2 m square (or a wide plate's vertical edge) 10 m ahead, at
//! 320x240 and a 40-degree vertical field of view, where 1 m at 10 m is
//! 240 / (2 * 10 * tan 20 deg) = 32.97 px.
//! - A 180-degree shutter is open for half a frame: the square streaks over 0.5 m, 16.5 px,
//!   the full width at half maximum of its streak; without motion blur, its own 6.6 px.
//! - A rolling shutter reading out in 1/48 s opens the bottom row half a frame after the top:
//!   a vertical edge leans by 16.5 px over the image's height.
//!
//! The GPU paths render the same frames, each within the usual bound of the CPU's.

use std::fs;
use std::path::Path;

use lensray_core::film::Image;

use crate::gpu_support::{compare, write_comparison};
use crate::{assert_rejected_on, read_exr, render_on_path};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

/// Pixels per metre at 10 m: the image's height over the field's height there.
fn pixels_per_metre() -> f64 {
    f64::from(HEIGHT) / (2.0 * 10.0 * 20f64.to_radians().tan())
}

/// A scene of the quad `x0..x1` by `y0..y1` at z = -10, white and unlit on black, and a
/// camera keyed from x = 0 at frame 0 to x = 10 at frame 10, looking down -z.
fn sliding_scene(dir: &Path, [x0, x1, y0, y1]: [f64; 4]) -> String {
    let obj =
        format!("v {x0} {y0} -10\nv {x1} {y0} -10\nv {x1} {y1} -10\nv {x0} {y1} -10\nf 1 2 3 4\n");
    fs::write(dir.join("quad.obj"), obj).unwrap();
    let text = format!(
        "mesh = \"quad.obj\"\n\
         [camera]\nvfov_degrees = 40.0\n\
         [image]\nwidth = {WIDTH}\nheight = {HEIGHT}\nfps = 24.0\n\
         [render]\nshading = \"unlit\"\nbackground = [0.0, 0.0, 0.0]\n\
         [[keyframe]]\nframe = 0\neye = [0.0, 0.0, 0.0]\ntarget = [0.0, 0.0, -10.0]\n\
         [[keyframe]]\nframe = 10\neye = [10.0, 0.0, 0.0]\ntarget = [10.0, 0.0, -10.0]\n"
    );
    let path = dir.join("sliding.toml");
    fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

/// Renders frame 5 of `scene` with `extra` on `path` (`cpu` or a GPU path, validation on) to
/// `name`.5.exr; `None` where a GPU path cannot run here and skipping is allowed.
fn frame5(
    test: &str,
    dir: &Path,
    scene: &str,
    path: &str,
    name: &str,
    extra: &[&str],
) -> Option<Image> {
    let out = format!("{name}.#.exr");
    // The scene file sets the size.
    let mut args = vec!["render", "--device", "cpu", "--spp", "64"];
    args.extend(["--scene", scene, "--frames", "5", "--out", &out]);
    args.extend_from_slice(extra);
    if !render_on_path(test, path, args, dir) {
        return None;
    }
    Some(read_exr(&dir.join(format!("{name}.5.exr"))))
}

/// The mean of the channels along `row`, less the row's least (the background).
pub(crate) fn row_profile(image: &Image, row: u32) -> Vec<f64> {
    let values: Vec<f64> = (0..image.width)
        .map(|x| f64::from(image.get(x, row).element_sum()) / 3.0)
        .collect();
    let floor = values.iter().copied().fold(f64::INFINITY, f64::min);
    values.iter().map(|v| v - floor).collect()
}

/// Where `profile` first crosses `level` going right from `from`, interpolated between pixel
/// centres (x + 0.5); `rising`: from below.
fn crossing(profile: &[f64], level: f64, from: usize, rising: bool) -> f64 {
    for x in from..profile.len() - 1 {
        let (a, b) = (profile[x], profile[x + 1]);
        if (rising && a < level && b >= level) || (!rising && a >= level && b < level) {
            return x as f64 + 0.5 + (level - a) / (b - a);
        }
    }
    panic!("the profile never crosses {level}");
}

/// The full width at half maximum of the streak across the square's middle rows (their mean),
/// the maximum being the mean of the plateau's three brightest pixels.
fn streak_width(image: &Image) -> f64 {
    let rows: Vec<Vec<f64>> = (118..122).map(|y| row_profile(image, y)).collect();
    let profile: Vec<f64> = (0..image.width as usize)
        .map(|x| rows.iter().map(|r| r[x]).sum::<f64>() / rows.len() as f64)
        .collect();
    let mut sorted = profile.clone();
    sorted.sort_by(f64::total_cmp);
    let peak = sorted[sorted.len() - 3..].iter().sum::<f64>() / 3.0;
    let left = crossing(&profile, 0.5 * peak, 0, true);
    let right = crossing(&profile, 0.5 * peak, left as usize, false);
    right - left
}

/// `image` against the CPU's `reference`, within the bound of the GPU paths' other tests.
fn assert_matches_cpu(test: &str, path: &str, image: &Image, reference: &Image) {
    let diff = compare(image, reference, 1.0 / 255.0);
    println!("{test} {path}: {diff:?}");
    if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
        let files = write_comparison(image, reference, &format!("{test}-{path}-vs-cpu"));
        panic!("{test}: {path} differs from the CPU: {diff:?}; wrote {files}");
    }
}

#[test]
fn a_moving_camera_streaks_by_its_motion_while_the_shutter_is_open() {
    let test = "a_moving_camera_streaks_by_its_motion_while_the_shutter_is_open";
    let dir = tempfile::tempdir().unwrap();
    let scene = sliding_scene(dir.path(), [4.9, 5.1, -0.1, 0.1]);
    let (square, motion) = (0.2 * pixels_per_metre(), 0.5 * pixels_per_metre());
    let sharp = frame5(test, dir.path(), &scene, "cpu", "sharp", &[]).unwrap();
    let width = streak_width(&sharp);
    println!("{test}: without motion blur {width:.2} px (the square: {square:.2} px)");
    assert!(
        (width - square).abs() < 1.0,
        "{test}: the still square is {width:.2} px wide, not {square:.2}"
    );
    let on = ["--motion-blur", "on"];
    let cpu = frame5(test, dir.path(), &scene, "cpu", "cpu", &on).unwrap();
    let width = streak_width(&cpu);
    println!("{test}: cpu streak {width:.2} px (the motion while open: {motion:.2} px)");
    assert!(
        (width - motion).abs() < 1.0,
        "{test}: cpu: the streak is {width:.2} px, not {motion:.2}"
    );
    for path in ["software", "rayquery", "rtpipeline"] {
        let Some(image) = frame5(test, dir.path(), &scene, path, path, &on) else {
            return;
        };
        let width = streak_width(&image);
        println!("{test}: {path} streak {width:.2} px");
        assert!(
            (width - motion).abs() < 1.0,
            "{test}: {path}: the streak is {width:.2} px, not {motion:.2}"
        );
        assert_matches_cpu(test, path, &image, &cpu);
    }
}

/// The x where the plate's edge (dark left, bright right) crosses half its brightness in `row`.
fn edge(image: &Image, row: u32) -> f64 {
    let profile = row_profile(image, row);
    let bright = profile.iter().copied().fold(0.0, f64::max);
    crossing(&profile, 0.5 * bright, 0, true)
}

#[test]
fn a_rolling_shutter_leans_a_panned_edge_by_the_analytic_angle() {
    let test = "a_rolling_shutter_leans_a_panned_edge_by_the_analytic_angle";
    let dir = tempfile::tempdir().unwrap();
    // The plate's edge at x = 5: where the camera looks at frame 5.
    let scene = sliding_scene(dir.path(), [5.0, 40.0, -20.0, 20.0]);
    let rolling = ["--rolling-shutter", "1/48"];
    let cpu = frame5(test, dir.path(), &scene, "cpu", "cpu", &rolling).unwrap();
    // Over the readout (half a frame) the camera moves 0.5 m to the right: rows further down
    // see the edge further left, in proportion.
    let lean = 0.5 * pixels_per_metre();
    let (top, bottom) = (8u32, HEIGHT - 8);
    let measured = edge(&cpu, top) - edge(&cpu, bottom);
    let expected = lean * f64::from(bottom - top) / f64::from(HEIGHT);
    println!(
        "{test}: the edge leans {measured:.2} px from row {top} to row {bottom}, {expected:.2} expected ({:.2} deg)",
        (expected / f64::from(bottom - top)).atan().to_degrees()
    );
    assert!(
        (measured - expected).abs() < 1.0,
        "{test}: the edge leans {measured:.2} px, not {expected:.2}"
    );
    // The middle row is read at the frame's time (the shutter centred on it): the edge there
    // is where the still frame has it, the image's centre.
    let middle = edge(&cpu, HEIGHT / 2);
    assert!(
        (middle - f64::from(WIDTH) / 2.0).abs() < 0.5,
        "{test}: the middle row's edge is at {middle:.2}"
    );
    let Some(image) = frame5(test, dir.path(), &scene, "software", "software", &rolling) else {
        return;
    };
    assert_matches_cpu(test, "software", &image, &cpu);
}

/// The raster and hybrid paths draw the image of one camera pose: a moving camera is one line
/// and no file.
#[test]
fn the_paths_of_one_pose_refuse_a_moving_camera_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let scene = sliding_scene(dir.path(), [4.9, 5.1, -0.1, 0.1]);
    for path in ["raster", "hybrid"] {
        let extra = [
            "--path", path, "--scene", &scene, "--frames", "5", "--out", "r.#.png",
        ];
        let needle = format!("--path {path} does not render motion blur");
        assert_rejected_on(
            "gpu",
            &[&extra[..], &["--motion-blur", "on"]].concat(),
            &needle,
        );
    }
}

/// AOVs are the G-buffer's: the surface at each pixel centre from the frame's own pose, which
/// the shutter does not move (the raster pass draws them on the GPU paths): on cpu the depth
/// AOV is the same with the shutter's motion on and off, whatever its position.
#[test]
fn aovs_are_drawn_from_the_frames_own_pose() {
    let test = "aovs_are_drawn_from_the_frames_own_pose";
    let dir = tempfile::tempdir().unwrap();
    let scene = sliding_scene(dir.path(), [4.9, 5.1, -0.1, 0.1]);
    let depth = ["--shading", "depth"];
    let still = frame5(test, dir.path(), &scene, "cpu", "still", &depth).unwrap();
    let moving = [
        &depth[..],
        &["--motion-blur", "on", "--shutter-position", "start"],
        &["--rolling-shutter", "1/48"],
    ]
    .concat();
    let blurred = frame5(test, dir.path(), &scene, "cpu", "moving", &moving).unwrap();
    assert!(
        still.pixels.iter().any(|p| p.x > 0.0),
        "{test}: the square is not seen"
    );
    assert_eq!(
        still.pixels, blurred.pixels,
        "{test}: the shutter moved an AOV"
    );
}
