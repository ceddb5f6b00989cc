//! `--shift`, `--tilt`, `--tilt-direction` and `--focus-plane` from the command line: bad
//! input gets one line and a non-zero exit; a plane laid through three floor pixels is printed
//! with the options that lay it again.

use crate::{assert_rejected, lensray, render_args, stderr};

#[test]
fn bad_shift_and_tilt_are_rejected_in_one_line() {
    assert_rejected(&["--tilt", "90"], "tilt must be in [0, 90)");
    assert_rejected(&["--tilt", "-1"], "tilt must be in [0, 90)");
    assert_rejected(&["--tilt", "nan"], "tilt");
    assert_rejected(&["--shift", "1"], "two comma-separated numbers");
    assert_rejected(&["--shift", "inf,0"], "shift");
    // Three pixels along one image row see three floor points on one line.
    assert_rejected(
        &["--focus-plane", "30,28", "38,28", "46,28"],
        "lie on one line",
    );
    // The sky above the default scene's horizon.
    assert_rejected(&["--focus-plane", "24,1", "30,28", "46,28"], "background");
    assert_rejected(&["--focus-plane", "30,28", "46,28", "60,20"], "outside");
    assert_rejected(
        &["--focus-plane", "28,30", "46,30", "40,17", "--tilt", "3"],
        "cannot be used with",
    );
    // A real lens's image circle: the shifted film's corner lies past it.
    assert_rejected(
        &["--lens", "double-gauss-50", "--shift", "40,0"],
        "past its image circle",
    );
    // Tilted, the film's far corner swings out past wide-22's image circle.
    assert_rejected(
        &["--lens", "wide-22", "--tilt", "12"],
        "past the lens's image circle",
    );
}

#[test]
fn focus_plane_prints_the_options_that_lay_it() {
    let dir = tempfile::tempdir().unwrap();
    let args = render_args(&[
        "--focus-plane",
        "28,30",
        "46,30",
        "40,17",
        "--out",
        "plane.png",
    ]);
    let out = lensray(&args, dir.path());
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    let line = err
        .lines()
        .find(|l| l.starts_with("focus plane:"))
        .unwrap_or_else(|| panic!("no focus plane line in: {err}"));
    // "... it passes within 1.2e-7 of the three points"
    let miss: f64 = line
        .split("passes within ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no distance in: {line}"));
    assert!(miss < 1e-3, "{line}");
    // The printed options render again.
    let options = line
        .split('(')
        .nth(1)
        .and_then(|s| s.split(')').next())
        .unwrap_or_else(|| panic!("no options in: {line}"));
    let mut again: Vec<&str> = options.split_whitespace().collect();
    again.extend(["--out", "again.png"]);
    let out = lensray(&render_args(&again), dir.path());
    assert!(out.status.success(), "{}", stderr(&out));
}
