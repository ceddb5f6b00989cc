//! Exposure and tone maps on the command line and in scene files: bad values refused in one
//! line, `--exposure 1` brighter, the tone maps' PNGs, EXR linear unless `--expose-exr`, and
//! the keys of `[camera.exposure]`.

use std::path::Path;

use crate::{assert_rejected, lensray, render_args, stderr};

#[test]
fn bad_exposure_values_are_rejected_with_one_line() {
    assert_rejected(&["--iso", "-100", "--shutter", "0.01"], "ISO");
    assert_rejected(&["--iso", "0", "--shutter", "0.01"], "ISO");
    assert_rejected(&["--shutter", "0"], "shutter");
    assert_rejected(&["--shutter", "-1/125"], "shutter");
    assert_rejected(&["--shutter", "1/0"], "shutter");
    assert_rejected(&["--shutter", "fast"], "seconds");
    assert_rejected(&["--iso", "400"], "shutter");
    assert_rejected(&["--exposure", "nan"], "exposure");
    assert_rejected(&["--exposure", "two"], "exposure");
    assert_rejected(&["--tonemap", "filmic"], "tonemap");
    // A pinhole's f-number sets the exposure only with a shutter time.
    assert_rejected(&["--f-number", "8"], "focal length");
}

/// Renders `extra` to `name` in `dir` and returns its pixels as floats (PNG: the bytes / 255).
fn render(dir: &Path, name: &str, extra: &[&str]) -> Vec<f32> {
    let mut args = extra.to_vec();
    args.extend(["--out", name]);
    let out = lensray(&render_args(&args), dir);
    assert!(out.status.success(), "{extra:?}: {}", stderr(&out));
    let img = image::open(dir.join(name)).expect("readable image");
    img.to_rgb32f().into_raw()
}

fn mean(v: &[f32]) -> f64 {
    v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64
}

#[test]
fn exposure_brightens_pngs_and_reaches_exr_only_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for tonemap in ["none", "neutral", "agx"] {
        let plain = render(d, "plain.png", &["--tonemap", tonemap]);
        let brighter = render(d, "bright.png", &["--tonemap", tonemap, "--exposure", "1"]);
        assert!(
            mean(&brighter) > mean(&plain) + 0.02,
            "{tonemap}: --exposure 1 gives {} against {}",
            mean(&brighter),
            mean(&plain)
        );
        assert!(
            plain.iter().zip(&brighter).all(|(a, b)| b >= a),
            "{tonemap}"
        );
    }
    // The default tone map is neutral.
    assert_eq!(
        render(d, "d.png", &[]),
        render(d, "x.png", &["--tonemap", "neutral"])
    );
    // EXR: the render's values whatever the exposure, unless --expose-exr (and never a tone map).
    let linear = render(d, "a.exr", &[]);
    assert_eq!(
        render(d, "b.exr", &["--exposure", "1", "--tonemap", "agx"]),
        linear
    );
    let exposed = render(d, "c.exr", &["--exposure", "1", "--expose-exr"]);
    for (a, b) in linear.iter().zip(&exposed) {
        assert_eq!(*b, 2.0 * a);
    }
}

#[test]
fn physical_exposure_prints_its_settings() {
    let dir = tempfile::tempdir().unwrap();
    let out = lensray(
        &render_args(&["--iso", "100", "--shutter", "1/125", "--out", "s.png"]),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(
        summary.contains("exposure: f/16 1/125 s ISO 100: EV100 14.97"),
        "{summary}"
    );
    // A tiny exposure on the built-in scene's lights (not photometric): nearly black.
    let img = image::open(dir.path().join("s.png")).unwrap().to_rgb8();
    assert!(img.pixels().all(|p| p.0.iter().all(|&v| v < 8)));
}

#[test]
fn scene_files_take_the_exposure_keys() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("tri.obj"), "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        d.join("s.toml"),
        "mesh = \"tri.obj\"\n[camera.exposure]\nev = 1.0\ntonemap = \"neutral\"\nexpose_exr = true\n",
    )
    .unwrap();
    let from_file = render(d, "f.exr", &["--scene", "s.toml"]);
    let given = render(
        d,
        "g.exr",
        &["--scene", "tri.obj", "--exposure", "1", "--expose-exr"],
    );
    assert_eq!(from_file, given);
    let png = render(d, "f.png", &["--scene", "s.toml"]);
    let png_given = render(
        d,
        "g.png",
        &[
            "--scene",
            "tri.obj",
            "--exposure",
            "1",
            "--tonemap",
            "neutral",
        ],
    );
    assert_eq!(png, png_given);
    // The command line overrides the file's keys; an unknown key is an error.
    let none = render(
        d,
        "n.png",
        &["--scene", "s.toml", "--exposure", "0", "--tonemap", "none"],
    );
    assert_eq!(
        none,
        render(d, "m.png", &["--scene", "tri.obj", "--tonemap", "none"])
    );
    std::fs::write(
        d.join("bad.toml"),
        "mesh = \"tri.obj\"\n[camera.exposure]\nfstop = 2\n",
    )
    .unwrap();
    let out = lensray(&render_args(&["--scene", "bad.toml", "--out", "x.png"]), d);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("fstop"), "{}", stderr(&out));
}
