//! The lens's own light in the preview (`--flare`, `--starburst`, the lens panel's toggles):
//! once the window converges, the final view adds the flare `render` draws. The screenshot of
//! assets/night (a lamp through double-gauss-50 at f/8, 7 blades; software path, validation
//! on) is the headless render with the same options, within the float rounding of the light
//! the window adds to its accumulation (bound 1e-6 of the peak).

use super::{headless, preview_with, read_exr};

#[test]
fn the_preview_draws_the_flare_render_draws() {
    let test = "the_preview_draws_the_flare_render_draws";
    let dir = tempfile::tempdir().unwrap();
    let night =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/night/night.toml");
    let view = [
        "--scene",
        night.to_str().unwrap(),
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
