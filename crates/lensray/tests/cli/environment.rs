//! `--environment FILE`: an HDR map lights the scene and is seen behind it, turned and scaled
//! as asked, from the command line and from a scene file; bad maps and values are one line.

use std::path::{Path, PathBuf};

use glam::Vec3;
use lensray_core::scene::environment::studio::write_environment;
use lensray_core::scene::environment::EnvironmentMap;

use crate::{assert_rejected, lensray, render_args, stderr};

fn studio() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/environments/studio.hdr")
}

/// Renders the default scene with `extra` into `name` (EXR: linear) and reads its pixels.
fn render(dir: &Path, name: &str, extra: &[&str]) -> Vec<[f32; 3]> {
    let mut args = vec!["--out", name];
    args.extend_from_slice(extra);
    let out = lensray(&render_args(&args), dir);
    assert!(out.status.success(), "{extra:?}: {}", stderr(&out));
    assert!(
        !stderr(&out).contains("warning"),
        "{extra:?}: {}",
        stderr(&out)
    );
    let image = image::open(dir.join(name))
        .expect("readable EXR")
        .into_rgb32f();
    image.pixels().map(|p| p.0).collect()
}

#[test]
fn a_map_lights_and_is_seen_turned_and_scaled() {
    let dir = tempfile::tempdir().unwrap();
    let map = studio();
    let map = map.to_str().unwrap();
    let plain = render(dir.path(), "plain.exr", &["--environment", map]);
    let turned = render(
        dir.path(),
        "turned.exr",
        &["--environment", map, "--environment-rotation", "180"],
    );
    let brighter = render(
        dir.path(),
        "brighter.exr",
        &["--environment", map, "--environment-intensity", "2"],
    );
    let without = render(
        dir.path(),
        "without.exr",
        &["--environment", map, "--environment-intensity", "0"],
    );
    let black = render(
        dir.path(),
        "black.exr",
        &["--environment", map, "--background", "0,0,0"],
    );
    let sum = |p: &[[f32; 3]]| p.iter().map(|c| c[0] + c[1] + c[2]).sum::<f32>();
    let changed = plain.iter().zip(&turned).filter(|(a, b)| a != b).count();
    println!(
        "turned: {changed} of {} pixels differ; sums plain {} brighter {} black {}",
        plain.len(),
        sum(&plain),
        sum(&brighter),
        sum(&black)
    );
    assert!(
        changed > plain.len() / 2,
        "turning the map changed {changed} pixels"
    );
    // The map's light scales with its intensity, over the scene's own lights: the same draws,
    // so intensity 2 adds to intensity 1 what 1 adds to 0.
    for ((a, b), z) in plain.iter().zip(&brighter).zip(&without) {
        for c in 0..3 {
            let step = (b[c] - a[c]) - (a[c] - z[c]);
            assert!(
                step.abs() <= 1e-4 * b[c].abs().max(1.0),
                "{z:?} {a:?} {b:?}"
            );
        }
    }
    // A background given hides the map where rays leave the scene; the map still lights.
    let hidden = black.iter().filter(|c| **c == [0.0; 3]).count();
    assert!(hidden > 0 && sum(&black) > 0.0, "{hidden} black pixels");
    assert!(sum(&black) < sum(&plain));
}

#[test]
fn a_scene_file_names_its_map_beside_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(studio(), dir.path().join("sky.hdr")).unwrap();
    let out = lensray(&["generate", "spheres", "--out", "."], dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
    let toml = "mesh = \"spheres.obj\"\n[render]\nenvironment = \"sky.hdr\"\n\
                environment_rotation = 45.0\nbounces = 2\n";
    std::fs::write(dir.path().join("shot.toml"), toml).unwrap();
    let out = lensray(
        &render_args(&["--scene", "shot.toml", "--out", "shot.png"]),
        dir.path(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("shot.png").exists());
}

#[test]
fn bad_maps_and_values_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let square = dir.path().join("square.hdr");
    let map = EnvironmentMap::new(4, 4, vec![Vec3::ONE; 16]).unwrap();
    write_environment(&map, &square).unwrap();
    let square = square.to_str().unwrap().to_string();
    assert_rejected(&["--environment", &square], "equirectangular");
    assert_rejected(&["--environment", "/nonexistent/sky.hdr"], "environment");
    assert_rejected(&["--environment", "sky.png"], ".hdr");
    assert_rejected(&["--environment", "1,2"], "three");
    let studio = studio();
    let map = studio.to_str().unwrap();
    assert_rejected(
        &["--environment", map, "--environment-intensity", "-1"],
        "intensity",
    );
    assert_rejected(
        &["--environment", map, "--environment-rotation", "nan"],
        "rotation",
    );
    assert_rejected(&["--bounces", "0"], "bounces");
    assert_rejected(&["--bounces", "17"], "bounces");
}
