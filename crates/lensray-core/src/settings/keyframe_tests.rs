use std::path::Path;

use super::*;

fn keyframes(text: &str) -> Result<Keyframes, String> {
    #[derive(serde::Deserialize)]
    struct File {
        keyframe: Vec<toml::Table>,
    }
    let file: File = toml::from_str(text).expect("valid TOML");
    Keyframes::parse(&file.keyframe, Path::new("scenes"))
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-12 * want.abs().max(1.0),
        "{what}: got {got}, want {want} (off by {:e})",
        got - want
    );
}

fn focus_at(keys: &Keyframes, frame: u32) -> f64 {
    keys.settings_at(&Settings::default(), frame)
        .camera
        .focus_distance
        .expect("focus keyed")
}

#[test]
fn focus_moves_linearly_in_dioptres() {
    let keys = keyframes(
        "[[keyframe]]\nframe = 10\nfocus_distance = 1.0\n\
         [[keyframe]]\nframe = 20\nfocus_distance = 4.0\n",
    )
    .unwrap();
    // Halfway: (1/1 + 1/4) / 2 = 0.625 dioptres, 1.6 m (a linear pull in metres would give 2.5).
    close(focus_at(&keys, 15), 1.0 / 0.625, "frame 15");
    // A tenth of the way: 0.9 * 1 + 0.1 * 0.25 = 0.925 dioptres.
    close(focus_at(&keys, 11), 1.0 / 0.925, "frame 11");
    // Before the first key and after the last, the keys' own values.
    close(focus_at(&keys, 0), 1.0, "frame 0");
    close(focus_at(&keys, 10), 1.0, "frame 10");
    close(focus_at(&keys, 20), 4.0, "frame 20");
    close(focus_at(&keys, 99), 4.0, "frame 99");
}

#[test]
fn smooth_eases_in_and_out_and_hold_holds() {
    let keys = keyframes(
        "[[keyframe]]\nframe = 0\nf_number = 2.0\ninterpolation = \"smooth\"\n\
         [[keyframe]]\nframe = 4\nf_number = 10.0\ninterpolation = \"hold\"\n\
         [[keyframe]]\nframe = 8\nf_number = 4.0\n",
    )
    .unwrap();
    let f_number = |frame| {
        keys.settings_at(&Settings::default(), frame)
            .camera
            .f_number
            .unwrap()
    };
    // 3t^2 - 2t^3 at t = 1/4: 0.15625; at t = 1/2: 0.5; at t = 3/4: 0.84375.
    close(f_number(1), 2.0 + 8.0 * 0.15625, "smooth, t = 1/4");
    close(f_number(2), 6.0, "smooth, t = 1/2");
    close(f_number(3), 2.0 + 8.0 * 0.84375, "smooth, t = 3/4");
    for frame in 4..8 {
        close(f_number(frame), 10.0, &format!("hold, frame {frame}"));
    }
    close(f_number(8), 4.0, "the key after a hold");
}

#[test]
fn settings_follow_their_own_keys_and_others_stay() {
    let keys = keyframes(
        "[[keyframe]]\nframe = 0\neye = [0, 0, 4]\nexposure = -1.0\n\
         [[keyframe]]\nframe = 2\nexposure = 1.0\n\
         [[keyframe]]\nframe = 4\neye = [2, 0, 0]\n",
    )
    .unwrap();
    let mut base = Settings::default();
    base.camera.vfov_degrees = Some(30.0);
    let at1 = keys.settings_at(&base, 1);
    assert_eq!(
        at1.camera.eye,
        Some([0.5, 0.0, 3.0]),
        "eye a quarter of the way"
    );
    close(at1.camera.exposure.ev.unwrap(), 0.0, "exposure halfway");
    assert_eq!(
        at1.camera.vfov_degrees,
        Some(30.0),
        "an unkeyed setting stays"
    );
    assert_eq!(keys.settings_at(&base, 3).camera.exposure.ev, Some(1.0));
}

#[test]
fn points_and_pixels_wait_for_their_distances() {
    let mut keys = keyframes(
        "[[keyframe]]\nframe = 0\nfocus_point = [0, 0, -3]\n\
         [[keyframe]]\nframe = 10\nfocus_at = [12, 7]\n",
    )
    .unwrap();
    assert_eq!(
        keys.unresolved_focus(),
        vec![
            (0, FocusKey::Point([0.0, 0.0, -3.0])),
            (10, FocusKey::Pixel([12, 7]))
        ]
    );
    assert_eq!(
        keys.settings_at(&Settings::default(), 5)
            .camera
            .focus_distance,
        None
    );
    keys.resolve_focus(0, 2.0);
    keys.resolve_focus(10, 8.0);
    assert!(keys.unresolved_focus().is_empty());
    // 0.5 and 0.125 dioptres: halfway 0.3125.
    close(focus_at(&keys, 5), 1.0 / 0.3125, "frame 5");
}

#[test]
fn lengths_scale_and_lenses_hold() {
    let keys = keyframes(
        "[[keyframe]]\nframe = 0\nfocus_distance = 1000.0\nlens = \"double-gauss-50\"\ntarget = [0, 0, -500]\n\
         [[keyframe]]\nframe = 2\nfocus_distance = 2000.0\nlens = \"my.lens\"\n",
    )
    .unwrap()
    .scaled(0.001);
    let at1 = keys.settings_at(&Settings::default(), 1);
    close(
        at1.camera.focus_distance.unwrap(),
        1.0 / 0.75,
        "scaled focus",
    );
    assert_eq!(at1.camera.target, Some([0.0, 0.0, -0.5]));
    assert_eq!(
        at1.camera.lens.prescription.as_deref(),
        Some("double-gauss-50")
    );
    let at2 = keys.settings_at(&Settings::default(), 2);
    let lens = at2.camera.lens.prescription.unwrap();
    assert_eq!(Path::new(&lens), Path::new("scenes").join("my.lens"));
}

#[test]
fn bad_keyframes_name_the_key_and_the_frame() {
    let cases = [
        (
            "frame = 3\nfocus_distnce = 2.0",
            "frame 3: `focus_distnce` is not a keyframe key",
        ),
        (
            "frame = 5\nfocus_distance = -1.0",
            "frame 5: `focus_distance` must be a positive",
        ),
        (
            "frame = 5\nf_number = 0",
            "frame 5: `f_number` must be a positive",
        ),
        ("frame = 6\ntilt = 90.0", "frame 6: `tilt` must be degrees"),
        (
            "frame = 7\neye = [1, 2]",
            "frame 7: `eye` must be 3 finite numbers",
        ),
        (
            "frame = 8\ninterpolation = \"cubic\"",
            "frame 8: `interpolation` must be linear",
        ),
        (
            "frame = 9\nfocus_at = [1.5, 2]",
            "frame 9: `focus_at` must be a pixel",
        ),
        (
            "frame = 9\nfocus_at = [1, 2]\nfocus_distance = 3.0",
            "frame 9: `focus_distance` sets focus a second time",
        ),
        ("frame = -1", "`frame` must be a whole number"),
        ("focus_distance = 1.0", "[[keyframe]] 1: no `frame`"),
    ];
    for (table, want) in cases {
        let err = keyframes(&format!("[[keyframe]]\n{table}\n")).unwrap_err();
        assert!(err.contains(want), "{table:?}: got '{err}', want '{want}'");
        assert!(!err.contains('\n'), "one line: {err}");
    }
    let err = keyframes("[[keyframe]]\nframe = 4\n[[keyframe]]\nframe = 4\n").unwrap_err();
    assert!(
        err.contains("keyframe at frame 4: out of order") && err.contains("at frame 4"),
        "{err}"
    );
}

#[test]
fn frame_seeds_differ_and_repeat() {
    assert_eq!(frame_seed(7, 12), frame_seed(7, 12));
    let seeds: std::collections::BTreeSet<u32> = (0..1000).map(|f| frame_seed(0, f)).collect();
    assert_eq!(seeds.len(), 1000, "1000 frames, 1000 seeds");
    assert_ne!(frame_seed(1, 12), frame_seed(2, 12));
}
