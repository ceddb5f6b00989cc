//! `--flare` and `--starburst` as a user renders them (`camera::flare`): a night scene, a small
//! very bright lamp right of centre at the eye's height through double-gauss-50 at f/8. The
//! ghost light is the difference between the render with `--flare on` and the same render
//! without it (the same samples):
//! - outside the lamp's neighbourhood it holds between 1e-5 and 5e-2 of the lamp's light;
//! - it is mirror-symmetric about the line through the image's centre and the lamp (the
//!   image's middle row: the lens is rotationally symmetric), away from the lamp, within 5 %
//!   of itself (measured 0.8 %: the lamp's image, and so the ghosts' sources, carry the
//!   samples' noise);
//! - part of it lies past the centre, on the image's left;
//! - with `--flare off` nothing changes.
//!
//! And what cannot have a flare is refused in one line.

use std::fs;
use std::path::Path;

use lensray_core::film::Image;

use crate::{assert_rejected, lensray, read_exr, stderr};

const WIDTH: u32 = 240;
const HEIGHT: u32 = 136;

/// The lamp: a 0.1 m square at (2, 1.2, -12) emitting 20000 (a ground below, dim sky).
fn night_scene(dir: &Path) -> String {
    let obj = "mtllib night.mtl\n\
        usemtl ground\nv -30 0 -60\nv 30 0 -60\nv 30 0 5\nv -30 0 5\nf 1 4 3 2\n\
        usemtl lamp\nv 1.95 1.15 -12\nv 2.05 1.15 -12\nv 2.05 1.25 -12\nv 1.95 1.25 -12\nf 5 6 7 8\n";
    let mtl = "newmtl ground\nKd 0.3 0.3 0.3\nnewmtl lamp\nKd 0 0 0\nKe 20000 20000 20000\n";
    fs::write(dir.join("night.obj"), obj).unwrap();
    fs::write(dir.join("night.mtl"), mtl).unwrap();
    let toml = format!(
        "mesh = \"night.obj\"\n\
         [camera]\neye = [0.0, 1.2, 0.0]\ntarget = [0.0, 1.2, -10.0]\nup = [0.0, 1.0, 0.0]\n\
         f_number = 8.0\nfocus_distance = 12.0\n\
         [camera.lens]\nprescription = \"double-gauss-50\"\n\
         [image]\nwidth = {WIDTH}\nheight = {HEIGHT}\nspp = 16\n\
         [render]\nenvironment = [0.01, 0.012, 0.02]\n"
    );
    fs::write(dir.join("night.toml"), toml).unwrap();
    "night.toml".into()
}

fn render(dir: &Path, scene: &str, name: &str, extra: &[&str]) -> Image {
    let out = format!("{name}.exr");
    let mut args = vec!["render", "--device", "cpu", "--scene", scene, "--out", &out];
    args.extend_from_slice(extra);
    let run = lensray(&args, dir);
    assert!(run.status.success(), "{name}: {}", stderr(&run));
    read_exr(&dir.join(out))
}

#[test]
fn a_bright_lamp_s_ghosts_are_faint_symmetric_and_reach_past_the_centre() {
    let dir = tempfile::tempdir().unwrap();
    let scene = night_scene(dir.path());
    let plain = render(dir.path(), &scene, "plain", &[]);
    let off = render(dir.path(), &scene, "off", &["--flare", "off"]);
    assert_eq!(plain.pixels, off.pixels, "--flare off changes the image");
    let on = render(dir.path(), &scene, "on", &["--flare", "on"]);
    let (w, h) = (WIDTH as usize, HEIGHT as usize);
    let luminance = |v: glam::Vec3| f64::from(v.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722)));
    // The lamp: the pixels past 16 (where the flare takes its sources), its centroid.
    let (mut lamp, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for (i, p) in plain.pixels.iter().enumerate() {
        let l = luminance(*p);
        if l > 16.0 {
            lamp += l;
            sx += l * ((i % w) as f64 + 0.5);
            sy += l * ((i / w) as f64 + 0.5);
        }
    }
    let (sx, sy) = (sx / lamp, sy / lamp);
    assert!(
        sx > 0.6 * w as f64,
        "the lamp at column {sx:.1}, not right of centre"
    );
    assert!(
        (sy - 0.5 * h as f64).abs() < 1.0,
        "the lamp at row {sy:.2}, not the middle"
    );
    let ghost: Vec<f64> = (0..w * h)
        .map(|i| luminance(on.pixels[i] - plain.pixels[i]))
        .collect();
    let (mut away, mut far_side, mut total, mut unmirrored) = (0.0, 0.0, 0.0, 0.0);
    for row in 0..h {
        for column in 0..w {
            let value = ghost[row * w + column];
            let mirrored = ghost[(h - 1 - row) * w + column];
            let (x, y) = (column as f64 + 0.5, row as f64 + 0.5);
            total += value;
            if (x - sx).hypot(y - sy) > 8.0 {
                away += value;
                unmirrored += (value - mirrored).abs();
            }
            if x < 0.5 * w as f64 {
                far_side += value;
            }
        }
    }
    let ratio = away / lamp;
    let asymmetry = unmirrored / away;
    println!(
        "the lamp at ({sx:.1}, {sy:.1}) px, its light {lamp:.4e}; ghost light away from it {ratio:.3e} of it, {:.1} % past the centre; mirrored, it differs by {:.2} % of itself",
        100.0 * far_side / total,
        100.0 * asymmetry
    );
    assert!(
        (1e-5..5e-2).contains(&ratio),
        "ghosts {ratio:.3e} of the lamp"
    );
    assert!(
        far_side > 0.01 * total,
        "{far_side} of {total} past the centre"
    );
    assert!(
        asymmetry < 0.05,
        "mirrored, the ghosts differ by {asymmetry:.4} of themselves"
    );
}

#[test]
fn a_flare_needs_a_real_lens_and_light() {
    assert_rejected(&["--flare", "on"], "--lens");
    assert_rejected(&["--starburst", "on", "--focal-length-mm", "50"], "--lens");
    assert_rejected(
        &[
            "--flare",
            "on",
            "--lens",
            "double-gauss-50",
            "--shading",
            "depth",
        ],
        "depth",
    );
}
