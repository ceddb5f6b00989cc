//! The lens's own light in the preview (`--flare`, `--starburst`, the lens panel's toggles):
//! once the window converges, the final view adds the flare `render` draws. The screenshot of
//! a lamp at night through double-gauss-50 at f/8 (software path, validation on) is the
//! headless render with the same options, within the float rounding of the light the window
//! adds to its accumulation (bound 1e-6 of the peak; measured 6e-8 on values up to 1.6e4).

use std::path::Path;

use super::{headless, preview_with, read_exr};

/// A 0.1 m lamp emitting 20000 right of centre over a grey ground, through double-gauss-50.
fn night(dir: &Path) -> String {
    let obj = "mtllib night.mtl\n\
        usemtl ground\nv -30 0 -60\nv 30 0 -60\nv 30 0 5\nv -30 0 5\nf 1 4 3 2\n\
        usemtl lamp\nv 1.95 1.15 -12\nv 2.05 1.15 -12\nv 2.05 1.25 -12\nv 1.95 1.25 -12\nf 5 6 7 8\n";
    let mtl = "newmtl ground\nKd 0.3 0.3 0.3\nnewmtl lamp\nKd 0 0 0\nKe 20000 20000 20000\n";
    std::fs::write(dir.join("night.obj"), obj).unwrap();
    std::fs::write(dir.join("night.mtl"), mtl).unwrap();
    let toml = "mesh = \"night.obj\"\n\
        [camera]\neye = [0.0, 1.2, 0.0]\ntarget = [0.0, 1.2, -10.0]\nup = [0.0, 1.0, 0.0]\n\
        f_number = 8.0\nfocus_distance = 12.0\n\
        [camera.lens]\nprescription = \"double-gauss-50\"\n\
        [render]\nenvironment = [0.01, 0.012, 0.02]\n";
    std::fs::write(dir.join("night.toml"), toml).unwrap();
    "night.toml".into()
}

#[test]
fn the_preview_draws_the_flare_render_draws() {
    let test = "the_preview_draws_the_flare_render_draws";
    let dir = tempfile::tempdir().unwrap();
    let scene = night(dir.path());
    let view = [
        "--scene",
        &scene,
        "--width",
        "160",
        "--height",
        "96",
        "--spp",
        "8",
        "--flare",
        "on",
        "--starburst",
        "on",
    ];
    let script = "0 wait converged\n0 screenshot p.exr\n0 quit\n";
    let Some(_) = preview_with(test, dir.path(), script, &view, &["--path", "software"]) else {
        return;
    };
    let mut args = vec!["--path", "software", "--out", "r.exr"];
    args.extend(view);
    headless(dir.path(), &args);
    let (shown, rendered) = (
        read_exr(&dir.path().join("p.exr")),
        read_exr(&dir.path().join("r.exr")),
    );
    let plain = {
        let mut args = vec!["--path", "software", "--out", "plain.exr"];
        args.extend(&view[..8]);
        headless(dir.path(), &args);
        read_exr(&dir.path().join("plain.exr"))
    };
    let (mut worst, mut peak, mut flare) = (0.0f32, 0.0f32, 0.0f64);
    for ((a, b), c) in shown.pixels().zip(rendered.pixels()).zip(plain.pixels()) {
        for k in 0..3 {
            worst = worst.max((a.0[k] - b.0[k]).abs());
            peak = peak.max(b.0[k].abs());
            flare += f64::from((b.0[k] - c.0[k]).abs());
        }
    }
    println!("the window's flare against the render's: {worst:.3e} at most (peak {peak:.3e}); the flare adds {flare:.3e}");
    assert!(flare > 1.0, "the render drew no flare ({flare})");
    assert!(
        worst <= 1e-6 * peak,
        "the window's image differs by {worst} (peak {peak})"
    );
}
