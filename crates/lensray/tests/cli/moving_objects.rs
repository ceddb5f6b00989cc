//! Motion blur of a file's animated meshes, measured against the analytic sizes: a glTF node
//! moves a mesh 10 m ahead of a camera that stands still, at 320x240, a 40-degree vertical
//! field of view and 24 fps, where 1 m at 10 m is 240 / (2 * 10 * tan 20 deg) = 32.97 px.
//! - A 0.2 m square sliding 1 m a frame sideways streaks, with a 180-degree shutter, over
//!   0.5 m: 16.5 px at half maximum, as the moving camera's test (`motion_blur.rs`) measures.
//! - A 3 m bar turning 36 degrees a frame about the view axis sweeps 18 degrees while the
//!   shutter is open: at 2 m from the axis its angular profile is 18 degrees wide at half
//!   maximum (the sweep, wider than the bar's own 2.9 degrees there).
//! - A still of the file blurs as frame 0 of a sequence: the square holds before its first key
//!   at 0 s and slides 0.25 m over the shutter's half after it, so its light's centre moves
//!   by half the mean of 0 and 0.25 m: 0.0625 m, 2.06 px.
//!
//! The CPU path and the software traversal blur moving objects, the software traversal's images
//! within the usual bound of the CPU's; the other GPU paths refuse in one line.

use std::fs;
use std::path::Path;

use lensray_core::film::Image;

use crate::gpu_support::{compare, write_comparison};
use crate::motion_blur::row_profile;
use crate::{lensray, read_exr, render_on_path, stderr};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;

/// Pixels per metre at 10 m.
fn pixels_per_metre() -> f64 {
    f64::from(HEIGHT) / (2.0 * 10.0 * 20f64.to_radians().tan())
}

/// Two triangles (a quad) from corner `a` along `u` and `v`, in z = 0.
fn quad(a: [f32; 2], u: [f32; 2], v: [f32; 2]) -> Vec<f32> {
    let flat = |p: [f32; 2]| [p[0], p[1], 0.0];
    crate::camera_animation::quad(flat(a), flat(u), flat(v))
}

/// One buffer of `arrays` (little-endian f32s) and its views, one an array, as glTF's
/// `bufferViews` lists them.
fn buffer_views(arrays: &[&[f32]]) -> (String, Vec<u8>) {
    let mut bin = Vec::new();
    let mut views = Vec::new();
    for data in arrays {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            data.len() * 4
        ));
        bin.extend(data.iter().flat_map(|x| x.to_le_bytes()));
    }
    (views.join(","), bin)
}

/// A glTF (`data.bin` beside it) of the quad `positions` under a node at (0, 0, -10) whose
/// `path` ("translation" or "rotation") is keyed to `values` (VEC3 or VEC4 each) at frames
/// `frames` at 24 fps, and the scene file over it: unlit white on black.
fn animated_scene(
    dir: &Path,
    positions: &[f32],
    path: &str,
    (frames, values): (&[f32], &[Vec<f32>]),
) -> String {
    let times: Vec<f32> = frames.iter().map(|f| f / 24.0).collect();
    let flat: Vec<f32> = values.concat();
    let (views, bin) = buffer_views(&[positions, &times, &flat]);
    let kind = if values[0].len() == 3 { "VEC3" } else { "VEC4" };
    let last = times[times.len() - 1];
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0,"translation":[0,0,-10]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"animations":[{{"name":"move","samplers":[{{"input":1,"output":2}}],
"channels":[{{"sampler":0,"target":{{"node":0,"path":"{path}"}}}}]}}],
"accessors":[
{{"bufferView":0,"componentType":5126,"count":{},"type":"VEC3","min":[-3,-3,0],"max":[3,3,0]}},
{{"bufferView":1,"componentType":5126,"count":{},"type":"SCALAR","min":[0],"max":[{last}]}},
{{"bufferView":2,"componentType":5126,"count":{},"type":"{kind}"}}],
"bufferViews":[{}],"buffers":[{{"uri":"data.bin","byteLength":{}}}]}}"#,
        positions.len() / 3,
        times.len(),
        values.len(),
        views,
        bin.len()
    );
    fs::write(dir.join("data.bin"), &bin).unwrap();
    fs::write(dir.join("moving.gltf"), text).unwrap();
    let scene = "mesh = \"moving.gltf\"\n\
         [camera]\nvfov_degrees = 40.0\n\
         [image]\nwidth = 320\nheight = 240\nfps = 24.0\n\
         [render]\nshading = \"unlit\"\nbackground = [0.0, 0.0, 0.0]\n";
    fs::write(dir.join("moving.toml"), scene).unwrap();
    "moving.toml".into()
}

/// The sliding square: 0.2 m, centred on its node, keyed from x = -5 m at frame 0 to
/// x = 5 m at frame 10.
fn sliding_square(dir: &Path) -> String {
    let square = quad([-0.1, -0.1], [0.2, 0.0], [0.0, 0.2]);
    let keys = vec![vec![-5.0, 0.0, -10.0], vec![5.0, 0.0, -10.0]];
    animated_scene(dir, &square, "translation", (&[0.0, 10.0], &keys))
}

/// Renders `scene` in `dir` on the CPU with the camera at `(x, 0, 0)` looking down -z and
/// `extra`, to `name` (a frame pattern's frame `frame`, or a still without `frame`).
fn render(
    dir: &Path,
    scene: &str,
    x: f64,
    frame: Option<u32>,
    name: &str,
    extra: &[&str],
) -> Image {
    render_on("cpu", dir, scene, (x, frame), name, extra).expect("the CPU renders")
}

/// [`render`] on `path` (`cpu`, or a GPU path with validation on); `None` where the GPU path
/// cannot run here and skipping is allowed.
fn render_on(
    path: &str,
    dir: &Path,
    scene: &str,
    (x, frame): (f64, Option<u32>),
    name: &str,
    extra: &[&str],
) -> Option<Image> {
    let (eye, target) = (format!("{x},0,0"), format!("{x},0,-10"));
    let frames = frame.map(|f| f.to_string());
    let out = match frame {
        Some(_) => format!("{name}.#.exr"),
        None => format!("{name}.exr"),
    };
    let mut args = vec!["render", "--device", "cpu", "--spp", "64", "--scene", scene];
    args.extend([
        "--eye", &eye, "--target", &target, "--up", "0,1,0", "--out", &out,
    ]);
    if let Some(frames) = &frames {
        args.extend(["--frames", frames]);
    }
    args.extend_from_slice(extra);
    if !render_on_path(name, path, args, dir) {
        return None;
    }
    let file = match frame {
        Some(f) => format!("{name}.{f}.exr"),
        None => out,
    };
    Some(read_exr(&dir.join(file)))
}

/// The software traversal's frame `frame` of `scene` with motion blur, against the CPU's
/// `cpu`: within the bound of the GPU paths' other tests.
fn assert_software_matches(test: &str, dir: &Path, scene: &str, frame: u32, cpu: &Image) {
    let on = ["--motion-blur", "on"];
    let Some(image) = render_on("software", dir, scene, (0.0, Some(frame)), "software", &on) else {
        return;
    };
    let diff = compare(&image, cpu, 1.0 / 255.0);
    println!("{test} software: {diff:?}");
    if diff.within < 0.999 || diff.mean_abs >= 1e-3 {
        let files = write_comparison(&image, cpu, &format!("{test}-software-vs-cpu"));
        panic!("{test}: software differs from the CPU: {diff:?}; wrote {files}");
    }
}

/// The width at half maximum of `profile` (samples `step` apart), the maximum the mean of its
/// three largest samples; crossings interpolated between samples.
fn width_at_half(profile: &[f64], step: f64) -> f64 {
    let mut sorted = profile.to_vec();
    sorted.sort_by(f64::total_cmp);
    let half = 0.5 * sorted[sorted.len() - 3..].iter().sum::<f64>() / 3.0;
    let crossing = |from: usize, rising: bool| {
        (from..profile.len() - 1)
            .find_map(|i| {
                let (a, b) = (profile[i], profile[i + 1]);
                let crosses = if rising {
                    a < half && b >= half
                } else {
                    a >= half && b < half
                };
                crosses.then(|| i as f64 + (half - a) / (b - a))
            })
            .unwrap_or_else(|| panic!("the profile never crosses {half}"))
    };
    let left = crossing(0, true);
    let right = crossing(left as usize, false);
    (right - left) * step
}

/// The full width at half maximum across the square's middle rows (their mean), pixels.
fn streak_width(image: &Image) -> f64 {
    let rows: Vec<Vec<f64>> = (118..122).map(|y| row_profile(image, y)).collect();
    let profile: Vec<f64> = (0..image.width as usize)
        .map(|x| rows.iter().map(|r| r[x]).sum::<f64>() / rows.len() as f64)
        .collect();
    width_at_half(&profile, 1.0)
}

#[test]
fn a_moving_mesh_streaks_by_its_motion_while_the_shutter_is_open() {
    let test = "a_moving_mesh_streaks_by_its_motion_while_the_shutter_is_open";
    let dir = tempfile::tempdir().unwrap();
    let scene = sliding_square(dir.path());
    let (square, motion) = (0.2 * pixels_per_metre(), 0.5 * pixels_per_metre());
    // Frame 5 has the square at x = 0, before the camera.
    let sharp = render(dir.path(), &scene, 0.0, Some(5), "sharp", &[]);
    let width = streak_width(&sharp);
    println!("{test}: without motion blur {width:.2} px (the square: {square:.2} px)");
    assert!(
        (width - square).abs() < 1.0,
        "{test}: the square at rest is {width:.2} px wide, not {square:.2}"
    );
    let blurred = render(
        dir.path(),
        &scene,
        0.0,
        Some(5),
        "blurred",
        &["--motion-blur", "on"],
    );
    let width = streak_width(&blurred);
    println!("{test}: the streak is {width:.2} px (the motion while open: {motion:.2} px)");
    assert!(
        (width - motion).abs() < 1.0,
        "{test}: the streak is {width:.2} px, not {motion:.2}"
    );
    assert_software_matches(test, dir.path(), &scene, 5, &blurred);
}

/// The centre of the light across the square's middle rows, pixels right of the image's
/// centre.
fn light_centre(image: &Image) -> f64 {
    let (mut mass, mut moment) = (0.0, 0.0);
    for y in 118..122 {
        for (x, v) in row_profile(image, y).iter().enumerate() {
            mass += v;
            moment += v * (x as f64 + 0.5);
        }
    }
    moment / mass - f64::from(WIDTH) / 2.0
}

#[test]
fn a_still_of_an_animated_file_blurs_as_its_frame_0() {
    let test = "a_still_of_an_animated_file_blurs_as_its_frame_0";
    let dir = tempfile::tempdir().unwrap();
    let scene = sliding_square(dir.path());
    // At 0 s the square is at x = -5 m, where the camera looks (a still without motion blur
    // shows the node's own transform: frame 0 is the pose at 0 s).
    let sharp = render(dir.path(), &scene, -5.0, Some(0), "sharp", &[]);
    let on = ["--motion-blur", "on"];
    let still = render(dir.path(), &scene, -5.0, None, "still", &on);
    let frame = render(dir.path(), &scene, -5.0, Some(0), "frame", &on);
    let (at_rest, centre, frame_centre) = (
        light_centre(&sharp),
        light_centre(&still),
        light_centre(&frame),
    );
    let expected = 0.0625 * pixels_per_metre();
    println!(
        "{test}: the light's centre at rest {at_rest:.3} px, blurred {centre:.3} px ({expected:.3} expected), frame 0's {frame_centre:.3} px"
    );
    assert!(
        at_rest.abs() < 0.1,
        "{test}: the square at rest is at {at_rest:.3} px"
    );
    assert!(
        (centre - expected).abs() < 0.2,
        "{test}: the still's light is centred at {centre:.3} px, not {expected:.3}"
    );
    assert!(
        (centre - frame_centre).abs() < 0.1,
        "{test}: the still ({centre:.3} px) is not frame 0 ({frame_centre:.3} px)"
    );
}

/// The bar's brightness along the circle of `radius` pixels about the image's centre, from
/// `from` to `to` degrees (counter-clockwise from +x, as the scene's y is up), every 0.1
/// degree, read bilinearly.
fn angular_profile(image: &Image, radius: f64, (from, to): (f64, f64)) -> Vec<f64> {
    let value = |x: f64, y: f64| {
        let (x, y) = (x - 0.5, y - 0.5);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |dx: f64, dy: f64| {
            let v = image.get((x0 + dx) as u32, (y0 + dy) as u32);
            f64::from(v.element_sum()) / 3.0
        };
        (at(0.0, 0.0) * (1.0 - fx) + at(1.0, 0.0) * fx) * (1.0 - fy)
            + (at(0.0, 1.0) * (1.0 - fx) + at(1.0, 1.0) * fx) * fy
    };
    let (cx, cy) = (f64::from(WIDTH) / 2.0, f64::from(HEIGHT) / 2.0);
    let steps = ((to - from) / 0.1).round() as usize;
    (0..=steps)
        .map(|k| {
            let angle = (from + 0.1 * k as f64).to_radians();
            value(cx + radius * angle.cos(), cy - radius * angle.sin())
        })
        .collect()
}

#[test]
fn a_turning_bar_blurs_over_the_arc_it_sweeps() {
    let test = "a_turning_bar_blurs_over_the_arc_it_sweeps";
    let dir = tempfile::tempdir().unwrap();
    // A 3 m by 0.1 m bar from the node's origin along +x, turned 36 degrees a frame about z:
    // at frame 5 it points along -x (180 degrees).
    let bar = quad([0.0, -0.05], [3.0, 0.0], [0.0, 0.1]);
    let keys: Vec<Vec<f32>> = (0..=10)
        .map(|k| {
            let half = (36.0f32 * k as f32).to_radians() / 2.0;
            vec![0.0, 0.0, half.sin(), half.cos()]
        })
        .collect();
    let frames: Vec<f32> = (0..=10).map(|k| k as f32).collect();
    let scene = animated_scene(dir.path(), &bar, "rotation", (&frames, &keys));
    let radius = 2.0 * pixels_per_metre();
    let one_pixel = (1.0 / radius).to_degrees();
    let sharp = render(dir.path(), &scene, 0.0, Some(5), "sharp", &[]);
    let profile = angular_profile(&sharp, radius, (150.0, 210.0));
    let width = width_at_half(&profile, 0.1);
    let own = (0.1f64 / 2.0).to_degrees();
    println!("{test}: without motion blur {width:.2} degrees wide (the bar: {own:.2})");
    assert!(
        (width - own).abs() < one_pixel,
        "{test}: the bar at rest is {width:.2} degrees wide, not {own:.2}"
    );
    let blurred = render(
        dir.path(),
        &scene,
        0.0,
        Some(5),
        "blurred",
        &["--motion-blur", "on"],
    );
    let profile = angular_profile(&blurred, radius, (150.0, 210.0));
    let width = width_at_half(&profile, 0.1);
    // The centre of the arc: the mean angle, weighed by brightness.
    let total: f64 = profile.iter().sum();
    let centre = 150.0
        + profile
            .iter()
            .enumerate()
            .map(|(k, v)| 0.1 * k as f64 * v)
            .sum::<f64>()
            / total;
    println!(
        "{test}: the blur spans {width:.2} degrees about {centre:.2} (18 about 180 expected; a pixel is {one_pixel:.2} degrees here)"
    );
    assert!(
        (width - 18.0).abs() < one_pixel,
        "{test}: the blur spans {width:.2} degrees, not the 18 swept"
    );
    assert!(
        (centre - 180.0).abs() < 0.5 * one_pixel,
        "{test}: the arc is centred at {centre:.2} degrees, not 180"
    );
    assert_software_matches(test, dir.path(), &scene, 5, &blurred);
}

#[test]
fn the_paths_that_hold_one_pose_refuse_to_blur_moving_objects_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let scene = sliding_square(dir.path());
    for path in ["rayquery", "rtpipeline", "raster", "hybrid"] {
        let args = [
            "render",
            "--scene",
            &scene,
            "--frames",
            "5",
            "--width",
            "32",
            "--height",
            "24",
            "--spp",
            "1",
            "--motion-blur",
            "on",
            "--path",
            path,
            "--out",
            "f.#.png",
        ];
        let run = lensray(&args, dir.path());
        let err = stderr(&run);
        let lines: Vec<&str> = err
            .lines()
            .filter(|l| !l.starts_with("animation"))
            .collect();
        assert!(!run.status.success(), "{path}: accepted: {err}");
        assert!(!err.contains("panicked"), "{path}: {err}");
        assert_eq!(lines.len(), 1, "{path}: one line expected: {err}");
        assert!(
            lines[0].contains(&format!("--path {path} does not blur moving objects")),
            "{path}: {err}"
        );
        assert!(
            !dir.path().join("f.5.png").exists(),
            "{path} left its frame"
        );
    }
}

/// A glTF (`light.bin` beside it) of a 20 m floor facing +z at z = -10 and a point light
/// (`KHR_lights_punctual`, 10 cd) 0.5 m before it, keyed from x = -5 m at frame 0 to x = 5 m at
/// frame 10 at 24 fps, and the scene file over it: lit, black background, no sky.
fn moving_light_scene(dir: &Path) -> String {
    let floor = quad([-10.0, -10.0], [20.0, 0.0], [0.0, 20.0]);
    let times = [0.0f32, 10.0 / 24.0];
    let keys = [-5.0f32, 0.0, -9.5, 5.0, 0.0, -9.5];
    let (views, bin) = buffer_views(&[&floor, &times, &keys]);
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,1]}}],
"extensionsUsed":["KHR_lights_punctual"],
"extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"point","intensity":10}}]}}}},
"nodes":[{{"mesh":0,"translation":[0,0,-10]}},
{{"translation":[-5,0,-9.5],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"animations":[{{"name":"slide","samplers":[{{"input":1,"output":2}}],
"channels":[{{"sampler":0,"target":{{"node":1,"path":"translation"}}}}]}}],
"accessors":[
{{"bufferView":0,"componentType":5126,"count":6,"type":"VEC3","min":[-10,-10,0],"max":[10,10,0]}},
{{"bufferView":1,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[{}]}},
{{"bufferView":2,"componentType":5126,"count":2,"type":"VEC3"}}],
"bufferViews":[{}],"buffers":[{{"uri":"light.bin","byteLength":{}}}]}}"#,
        times[1],
        views,
        bin.len()
    );
    fs::write(dir.join("light.bin"), &bin).unwrap();
    fs::write(dir.join("light.gltf"), text).unwrap();
    let scene = "mesh = \"light.gltf\"\n\
         [camera]\nvfov_degrees = 40.0\n\
         [image]\nwidth = 96\nheight = 72\nfps = 24.0\n\
         [render]\nshading = \"lit\"\nbackground = [0.0, 0.0, 0.0]\n";
    fs::write(dir.join("light.toml"), scene).unwrap();
    "light.toml".into()
}

/// A light that moves while the shutter is open lights the floor as the mean of its light over
/// the shutter: the blurred frame 5 against the trapezoid mean of nine still frames spanning
/// its shutter (frames 76 to 84 at 384 fps, the same times), where a point light's direct
/// light has no noise but the moment's. The software traversal renders the same frame.
#[test]
fn a_moving_light_lights_as_its_mean_over_the_shutter() {
    let test = "a_moving_light_lights_as_its_mean_over_the_shutter";
    let dir = tempfile::tempdir().unwrap();
    let scene = moving_light_scene(dir.path());
    let on = ["--motion-blur", "on"];
    let blurred = render(dir.path(), &scene, 0.0, Some(5), "blurred", &on);
    let fine = ["--fps", "384"];
    let stills: Vec<Image> = (76..=84)
        .map(|f| render(dir.path(), &scene, 0.0, Some(f), "still", &fine))
        .collect();
    let weights = [1.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 1.0].map(|w| w / 16.0);
    let brightness = |v: glam::Vec3| f64::from(v.element_sum()) / 3.0;
    let (mut error, mut moved, mut total) = (0.0, 0.0, 0.0);
    for i in 0..blurred.pixels.len() {
        let mean: f64 = (stills.iter().zip(weights))
            .map(|(s, w)| w * brightness(s.pixels[i]))
            .sum();
        error += (brightness(blurred.pixels[i]) - mean).abs();
        moved += (brightness(stills[4].pixels[i]) - mean).abs();
        total += mean;
    }
    let (error, moved) = (error / total, moved / total);
    println!(
        "{test}: the blurred frame is {:.3} % off the mean over the shutter (the still frame: {:.3} %)",
        100.0 * error,
        100.0 * moved
    );
    // What is left is the moments' noise at 64 spp and the trapezoid rule's error (measured:
    // 0.28 %, where the still frame is 3.9 % off).
    assert!(
        error < 0.005 && moved > 5.0 * error,
        "{test}: the blurred frame is {:.3} % off the mean over the shutter, the still {:.3} %",
        100.0 * error,
        100.0 * moved
    );
    assert_software_matches(test, dir.path(), &scene, 5, &blurred);
}
