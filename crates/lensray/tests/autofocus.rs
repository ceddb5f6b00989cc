//! `lensray render --focus-at X,Y` through the real command line, on the CPU and on the GPU (with
//! validation): the focus distance it finds is the known depth of the surface at that pixel, and
//! the render that follows is sharp there. The GPU tests do not skip: without a working ray-query
//! device they fail.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

// The edge fit that lensray-core's tests use too: one copy.
#[path = "../../lensray-core/tests/edge_fit/mod.rs"]
mod edge_fit;
mod gpu_support;

/// Image size of every render here. With vfov 40 degrees a screen unit (the plane z = 1 in front
/// of the eye) is HEIGHT / (2 tan 20 deg) = 43.96 pixels.
const WIDTH: u32 = 96;
const HEIGHT: u32 = 32;

fn pixels_per_screen_unit() -> f64 {
    HEIGHT as f64 / (2.0 * 20f64.to_radians().tan())
}

/// The eye looks from (0, 0, EYE_Z) at the origin, down world -z (camera +x is world +x).
const EYE_Z: f64 = 3.0;

fn lensray(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lensray")
}

/// Writes `name.obj` (the given quads, each a material name and four corners), `name.mtl`
/// (black and white) and `name.toml` (camera focused at 1.0, far from anything in the scene, with
/// a large aperture; unlit). Returns the scene file's path.
fn write_scene(dir: &Path, name: &str, quads: &[(&str, [[f64; 3]; 4])], spp: u32) -> PathBuf {
    std::fs::write(
        dir.join(format!("{name}.mtl")),
        "newmtl black\nKd 0 0 0\nnewmtl white\nKd 1 1 1\n",
    )
    .unwrap();
    let mut obj = format!("mtllib {name}.mtl\n");
    for (i, (material, corners)) in quads.iter().enumerate() {
        obj += &format!("usemtl {material}\n");
        for [x, y, z] in corners {
            obj += &format!("v {x:.9} {y:.9} {z:.9}\n");
        }
        let k = 4 * i + 1;
        obj += &format!("f {} {} {} {}\n", k, k + 1, k + 2, k + 3);
    }
    std::fs::write(dir.join(format!("{name}.obj")), obj).unwrap();
    let toml = format!(
        "mesh = \"{name}.obj\"\n\
         [camera]\n\
         eye = [0.0, 0.0, {EYE_Z:.1}]\n\
         target = [0.0, 0.0, 0.0]\n\
         up = [0.0, 1.0, 0.0]\n\
         vfov_degrees = 40.0\n\
         aperture_radius = 0.2\n\
         focus_distance = 1.0\n\
         [image]\n\
         width = {WIDTH}\n\
         height = {HEIGHT}\n\
         spp = {spp}\n\
         [render]\n\
         shading = \"unlit\"\n\
         background = [0.0, 0.0, 0.0]\n"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, toml).unwrap();
    path
}

/// Renders `scene` on `device` (`--validate` on the GPU) into `out` (.exr, linear); returns
/// stderr. Fails the test if the command fails, except on a machine without a GPU with
/// LENSRAY_SKIP_GPU_TESTS=1, where the skip is recorded and this returns `None`.
fn render(device: &str, scene: &Path, extra: &[&str], out: &str, dir: &Path) -> Option<String> {
    let mut args = vec![
        "render",
        "--device",
        device,
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out,
    ];
    if device == "gpu" {
        args.push("--validate");
    }
    args.extend_from_slice(extra);
    let output = lensray(&args, dir);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    if device == "gpu" && !output.status.success() {
        gpu_support::skip_or_fail(&format!("autofocus {args:?}"), &stderr);
        return None;
    }
    assert!(output.status.success(), "lensray {args:?} failed: {stderr}");
    Some(stderr)
}

/// The distance from the line `autofocus: pixel X,Y is D away along the view axis`.
fn autofocus_distance(stderr: &str, pixel: [u32; 2]) -> f64 {
    let prefix = format!("autofocus: pixel {},{} is ", pixel[0], pixel[1]);
    let line = stderr
        .lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no '{prefix}...' line in stderr: {stderr}"));
    line[prefix.len()..]
        .split_whitespace()
        .next()
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("no distance in '{line}'"))
}

/// The red channel of an EXR averaged over rows, one value per column.
fn column_profile(path: &Path) -> Vec<f64> {
    let image = image::open(path).expect("EXR written").into_rgb32f();
    assert_eq!((image.width(), image.height()), (WIDTH, HEIGHT));
    (0..WIDTH)
        .map(|c| {
            (0..HEIGHT)
                .map(|r| image.get_pixel(c, r)[0] as f64)
                .sum::<f64>()
                / HEIGHT as f64
        })
        .collect()
}

/// A plane perpendicular to the view axis at view depth 3 (world z = 0), black left of a vertical
/// edge, white right of it. Focusing on a pixel of the plane away from the edge must give 3 and
/// a sharp edge; the scene file's own focus (1.0) gives the circle of confusion
/// 0.2 |1/1 - 1/3| = 0.133 screen units = 5.9 px, so without --focus-at the edge is blurred.
fn autofocus_on_a_perpendicular_plane(device: &str) {
    let dir = tempfile::tempdir().unwrap();
    // The edge's pinhole projection falls 0.37 px right of the image's middle pixel boundary.
    let edge_raster = WIDTH as f64 / 2.0 + 0.37;
    let e = 0.37 * EYE_Z / pixels_per_screen_unit();
    let scene = write_scene(
        dir.path(),
        "edge",
        &[
            (
                "black",
                [
                    [-10.0, -10.0, 0.0],
                    [e, -10.0, 0.0],
                    [e, 10.0, 0.0],
                    [-10.0, 10.0, 0.0],
                ],
            ),
            (
                "white",
                [
                    [e, -10.0, 0.0],
                    [10.0, -10.0, 0.0],
                    [10.0, 10.0, 0.0],
                    [e, 10.0, 0.0],
                ],
            ),
        ],
        256,
    );
    let pixel = [12, 20];
    let Some(stderr) = render(
        device,
        &scene,
        &["--focus-at", "12,20"],
        "focused.exr",
        dir.path(),
    ) else {
        return;
    };
    let focus = autofocus_distance(&stderr, pixel);
    let focused = edge_fit::fit(&column_profile(&dir.path().join("focused.exr")));
    if render(device, &scene, &[], "unfocused.exr", dir.path()).is_none() {
        return;
    }
    let unfocused = edge_fit::fit(&column_profile(&dir.path().join("unfocused.exr")));
    println!("{device}: autofocus {focus}; focused {focused:?}; unfocused {unfocused:?}");
    assert!(
        (focus / EYE_Z - 1.0).abs() < 1e-3,
        "{device}: autofocus on pixel {pixel:?} found {focus}, the plane is at {EYE_Z}"
    );
    // Focused at 3 (to 1e-3) the CoC is below 0.01 px: only the pixel box filter remains, so the
    // fitted blur radius is below half a pixel (the reference tests measure the fit to 0.3% of
    // the radius and 0.03 px of the edge at this noise level).
    assert!(
        focused.radius < 0.5 && (focused.edge - edge_raster).abs() < 0.1,
        "{device}: after autofocus the edge is not sharp: {focused:?}, expected radius < 0.5 px \
         at x = {edge_raster}"
    );
    // The control: the file's focus distance blurs the edge by its CoC, 5.9 px.
    let coc = 0.2 * (1.0 - 1.0 / EYE_Z) * pixels_per_screen_unit();
    assert!(
        (unfocused.radius / coc - 1.0).abs() < 0.05,
        "{device}: without autofocus the edge should be blurred by {coc} px: {unfocused:?}"
    );
}

/// A plane tilted about both axes, world z = 0.5 x + 0.25 y: the depth differs from pixel to
/// pixel (about 1% per column, 0.5% per row here), so autofocus must read the very pixel given.
/// The expected depth is that of the pixel centre's pinhole ray, computed here by hand.
fn autofocus_on_a_tilted_plane(device: &str) {
    let dir = tempfile::tempdir().unwrap();
    let z = |x: f64, y: f64| 0.5 * x + 0.25 * y;
    let corners =
        [[-4.0, -4.0], [4.0, -4.0], [4.0, 4.0], [-4.0, 4.0]].map(|[x, y]| [x, y, z(x, y)]);
    let scene = write_scene(dir.path(), "tilted", &[("white", corners)], 1);
    let pixel_size = 1.0 / pixels_per_screen_unit();
    for pixel in [[20u32, 7u32], [75, 26]] {
        let focus_at = format!("{},{}", pixel[0], pixel[1]);
        let Some(stderr) = render(
            device,
            &scene,
            &["--focus-at", &focus_at],
            "tilted.exr",
            dir.path(),
        ) else {
            return;
        };
        let focus = autofocus_distance(&stderr, pixel);
        // Pinhole ray through the pixel centre: (dx, dy, -1) per unit of view depth t, from
        // (0, 0, 3); it meets the plane where 3 - t = 0.5 t dx + 0.25 t dy.
        let dx = (pixel[0] as f64 + 0.5 - WIDTH as f64 / 2.0) * pixel_size;
        let dy = (HEIGHT as f64 / 2.0 - pixel[1] as f64 - 0.5) * pixel_size;
        let depth = EYE_Z / (1.0 + 0.5 * dx + 0.25 * dy);
        assert!(
            (focus / depth - 1.0).abs() < 1e-3,
            "{device}: autofocus on pixel {pixel:?} of the tilted plane found {focus}, \
             expected {depth}"
        );
    }
}

#[test]
fn cpu_autofocus_focuses_on_a_plane_at_a_known_depth() {
    autofocus_on_a_perpendicular_plane("cpu");
}

#[test]
fn gpu_autofocus_focuses_on_a_plane_at_a_known_depth() {
    autofocus_on_a_perpendicular_plane("gpu");
}

#[test]
fn cpu_autofocus_reads_the_depth_of_the_given_pixel() {
    autofocus_on_a_tilted_plane("cpu");
}

#[test]
fn gpu_autofocus_reads_the_depth_of_the_given_pixel() {
    autofocus_on_a_tilted_plane("gpu");
}
