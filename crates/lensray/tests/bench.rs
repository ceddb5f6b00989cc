//! `lensray bench` on tiny configurations: the table, the JSON file and the plot are written
//! and consistent, the reference is cached and reused, sweeps run, GPU and CPU paths measure
//! the same error, and bad input is one clear line. (Speed itself belongs to the bench.)

mod gpu_support;

use std::path::Path;
use std::process::{Command, Output};

use gpu_support::skip_or_fail;
use serde_json::Value;

/// 32x24 px, 2 spp, one timed run, a 16-spp reference: well under a second per path.
const TINY: [&str; 10] = [
    "--width",
    "32",
    "--height",
    "24",
    "--spp",
    "2",
    "--repeat",
    "1",
    "--reference-spp",
    "16",
];

fn bench(extra: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .arg("bench")
        .args(TINY)
        .args(["--cache-dir", "cache"])
        .args(extra)
        .current_dir(dir)
        .output()
        .expect("run lensray")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn read_json(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).expect("valid JSON")
}

/// Every measurement of the report, with its point.
fn measurements(json: &Value) -> Vec<(&Value, &Value)> {
    json["points"]
        .as_array()
        .expect("points")
        .iter()
        .flat_map(|p| {
            p["results"]
                .as_array()
                .expect("results")
                .iter()
                .map(move |m| (p, m))
        })
        .collect()
}

/// Fields every measurement has, errors finite and positive, PSNR = -20 log10(RMSE).
fn check_measurement(m: &Value) {
    let rmse = m["rmse"].as_f64().expect("rmse");
    let psnr = m["psnr_db"].as_f64().expect("psnr_db");
    assert!(rmse.is_finite() && rmse > 0.0, "{m}");
    assert!((psnr + 20.0 * rmse.log10()).abs() < 1e-9, "{m}");
    let t = &m["trace_seconds"];
    let (lo, med, hi) = (t["min"].as_f64(), t["median"].as_f64(), t["max"].as_f64());
    let (lo, med, hi) = (lo.unwrap(), med.unwrap(), hi.unwrap());
    assert!(0.0 < lo && lo <= med && med <= hi, "{m}");
    assert!(m["rays"].as_u64().unwrap() > 0, "{m}");
    assert!(m["rays_per_second"].as_f64().unwrap() > 0.0, "{m}");
    assert!(m["wall_seconds"]["median"].as_f64().unwrap() > 0.0, "{m}");
    assert_eq!(m["runs"].as_array().unwrap().len(), 1, "{m}");
    for field in [
        "peak_device_bytes",
        "accel_bytes",
        "build_seconds",
        "device",
        "clock",
    ] {
        assert!(!m[field].is_null(), "no {field}: {m}");
    }
    // The render's phases: tracing as `trace_seconds`, the rest of the call's wall time beyond
    // it and the read-back, and the passes (one per sample, at least one).
    let phases = &m["phases"];
    let tracing = phases["tracing_seconds"].as_f64().unwrap();
    assert!((tracing - med).abs() <= 1e-9, "{m}");
    let beyond = phases["beyond_tracing_seconds"].as_f64().unwrap();
    let readback = phases["readback_seconds"].as_f64().unwrap();
    let wall = m["wall_seconds"]["median"].as_f64().unwrap();
    assert!(beyond >= 0.0 && readback >= 0.0, "{m}");
    assert!(tracing + beyond + readback <= wall + 1e-6, "{m}");
    assert!(phases["passes"].as_u64().unwrap() >= 1, "{m}");
}

/// The default scene's camera as the JSON gives it, at the top and at every point.
fn check_camera(json: &Value) {
    let camera = &json["camera"];
    let numbers = |key: &str| -> Vec<f64> {
        let values = camera[key]
            .as_array()
            .unwrap_or_else(|| panic!("{key}: {camera}"));
        values.iter().map(|v| v.as_f64().unwrap()).collect()
    };
    // f32 values, written in the shortest form that reads back as the same f32.
    let eye: Vec<f32> = numbers("eye").iter().map(|&x| x as f32).collect();
    assert_eq!(eye, [0.0, 1.6, 8.0]);
    // A unit step along the view axis towards the subject at (0, 0.5, 0); up made orthogonal.
    let (eye, target, up) = (numbers("eye"), numbers("target"), numbers("up"));
    let forward: Vec<f64> = target.iter().zip(&eye).map(|(t, e)| t - e).collect();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    assert!((dot(&forward, &forward) - 1.0).abs() < 1e-5, "{camera}");
    assert!(dot(&forward, &up).abs() < 1e-5 && (dot(&up, &up) - 1.0).abs() < 1e-5);
    assert!(
        (forward[1] / forward[2] - 1.1 / 8.0).abs() < 1e-5,
        "{camera}"
    );
    assert_eq!(camera["projection"], "perspective");
    assert!((camera["vfov_degrees"].as_f64().unwrap() - 40.0).abs() < 1e-5);
    assert!(camera["ortho_height"].is_null());
    assert_eq!(
        (&camera["lens"], &camera["aperture"]),
        (&"thin".into(), &"round".into())
    );
    assert_eq!(camera["aperture_radius"].as_f64().unwrap() as f32, 0.12);
    assert_eq!(camera["focus_distance"].as_f64().unwrap() as f32, 8.0753);
    assert_eq!(
        (&camera["width"], &camera["height"]),
        (&32.into(), &24.into())
    );
    assert!(camera["near"].as_f64().unwrap() < camera["far"].as_f64().unwrap());
    for point in json["points"].as_array().unwrap() {
        assert_eq!(&point["camera"], camera);
    }
}

fn check_png(path: &Path) {
    let plot = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(plot.width() > 0 && plot.height() > 0);
}

/// The CPU path: table, JSON and plot (an spp sweep: 1 and 2 spp), then a second run that
/// reads the reference from the cache.
#[test]
fn bench_writes_json_and_plot_and_reuses_the_cached_reference() {
    let dir = tempfile::tempdir().unwrap();
    let out = bench(
        &["--paths", "cpu", "--json", "a.json", "--plot", "a.png"],
        dir.path(),
    );
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    assert!(
        stdout.contains("RMSE") && stdout.contains("PSNR"),
        "{stdout}"
    );
    assert!(
        stdout.contains("rendered in") && stdout.contains("now cached"),
        "{stdout}"
    );

    let json = read_json(&dir.path().join("a.json"));
    assert_eq!(json["schema"], "lensray-bench/1");
    assert_eq!(json["sweep"], "spp");
    assert_eq!(json["settings"]["width"], 32);
    assert_eq!(json["settings"]["reference_spp"], 16);
    assert!(json["machine"]["cpu"].is_string());
    assert!(json["scene"]["triangles"].as_u64().unwrap() > 1000);
    assert_eq!(json["paths"][0]["path"], "cpu");
    check_camera(&json);
    let spps: Vec<u64> = json["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["spp"].as_u64().unwrap())
        .collect();
    assert_eq!(spps, [1, 2]);
    let errors: Vec<f64> = measurements(&json)
        .iter()
        .map(|(_, m)| {
            check_measurement(m);
            assert_eq!(m["clock"], "wall_clock");
            m["rmse"].as_f64().unwrap()
        })
        .collect();
    assert!(
        errors[1] < errors[0],
        "more samples, less error: {errors:?}"
    );
    check_png(&dir.path().join("a.png"));

    let again = bench(&["--paths", "cpu", "--json", "b.json"], dir.path());
    let stdout = text(&again.stdout);
    assert!(again.status.success(), "{}", text(&again.stderr));
    assert!(stdout.contains(", cached (cache"), "{stdout}");
    assert!(!stdout.contains("rendered in"), "{stdout}");
    let json = read_json(&dir.path().join("b.json"));
    assert_eq!(json["sweep"], Value::Null);
    let reference = &json["points"][0]["reference"];
    assert_eq!(reference["cached"], true);
    assert!(reference["noise_rmse"].as_f64().unwrap() > 0.0);

    // How much is in focus: the default camera's blur (CoC up to 15.6 px at 640x480, so
    // ~0.8 px at this bench's 32 px width), then a pinhole, where every surface is in focus.
    let focus = |json: &Value| {
        let f = &json["points"][0]["focus"];
        let get = |k: &str| f[k].as_f64().unwrap_or_else(|| panic!("focus.{k} in {f}"));
        (
            get("in_focus_fraction"),
            get("background_fraction"),
            get("mean_coc_pixels"),
            get("largest_coc_pixels"),
        )
    };
    let (in_focus, background, mean, largest) = focus(&json);
    assert!(
        (0.2..0.6).contains(&background) && in_focus + background < 1.0,
        "focus {in_focus} background {background}"
    );
    assert!(
        0.0 < mean && mean < largest && (0.6..1.0).contains(&largest),
        "CoC mean {mean} largest {largest}"
    );
    let pinhole = bench(
        &[
            "--paths",
            "cpu",
            "--aperture-radius",
            "0",
            "--json",
            "c.json",
        ],
        dir.path(),
    );
    assert!(pinhole.status.success(), "{}", text(&pinhole.stderr));
    let (in_focus, background, mean, largest) = focus(&read_json(&dir.path().join("c.json")));
    assert!(
        (in_focus + background - 1.0).abs() < 1e-12 && (mean, largest) == (0.0, 0.0),
        "pinhole: in focus {in_focus}, background {background}, CoC mean {mean} largest {largest}"
    );
}

/// Every path this machine runs (validation on) measures the error the CPU does: same sampler
/// and seed, so the images agree up to float noise (the hybrid and raster paths: of the same
/// order).
#[test]
fn gpu_paths_measure_the_cpu_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = bench(
        &["--device", "auto", "--validate", "--json", "all.json"],
        dir.path(),
    );
    if !out.status.success() {
        skip_or_fail("gpu_paths_measure_the_cpu_error", &text(&out.stderr));
        return;
    }
    let json = read_json(&dir.path().join("all.json"));
    let results = measurements(&json);
    let cpu = results
        .iter()
        .find(|(_, m)| m["path"] == "cpu")
        .expect("the CPU path runs by default")
        .1["rmse"]
        .as_f64()
        .unwrap();
    let gpu: Vec<_> = results.iter().filter(|(_, m)| m["path"] != "cpu").collect();
    assert!(!gpu.is_empty(), "no GPU path ran: {json}");
    for (_, m) in gpu {
        check_measurement(m);
        assert_eq!(m["clock"], "gpu_timestamps", "{m}");
        assert!(m["peak_device_bytes"].as_u64().unwrap() > 0, "{m}");
        assert!(m["speedup_vs_cpu"].as_f64().unwrap() > 0.0, "{m}");
        let rmse = m["rmse"].as_f64().unwrap();
        if m["path"] == "hybrid" || m["path"] == "raster" {
            // Other estimators (hybrid: fewer samples, checked shortcuts; raster: the same
            // camera samples in every pixel, so one image's error is one draw of them): at
            // 32x24 and 2 spp the error is of the same order; tests/hybrid.rs and
            // tests/raster.rs check them against the traced image.
            assert!(
                rmse < 2.5 * cpu,
                "{}: RMSE {rmse} against the CPU's {cpu}",
                m["path"]
            );
            continue;
        }
        assert!(
            (rmse / cpu - 1.0).abs() < 0.03,
            "{}: RMSE {rmse} against the CPU's {cpu}",
            m["path"]
        );
    }
}

/// Sweeps of resolution and triangles run, in increasing order, and plot.
#[test]
fn resolution_and_triangle_sweeps_run() {
    let dir = tempfile::tempdir().unwrap();
    let sweeps = [
        ("resolution", "48x36,32x24", "width"),
        ("triangles", "6k,12k", "triangles"),
    ];
    for (sweep, points, field) in sweeps {
        let file = format!("{sweep}.json");
        let plot = format!("{sweep}.png");
        let args = [
            "--paths",
            "cpu",
            "--sweep",
            sweep,
            "--sweep-points",
            points,
            "--json",
            &file,
            "--plot",
            &plot,
        ];
        let out = bench(&args, dir.path());
        assert!(out.status.success(), "{sweep}: {}", text(&out.stderr));
        let json = read_json(&dir.path().join(&file));
        assert_eq!(json["sweep"], sweep);
        let values: Vec<u64> = json["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p[field].as_u64().unwrap())
            .collect();
        assert_eq!(values.len(), 2, "{sweep}: {values:?}");
        assert!(values[0] < values[1], "{sweep}: {values:?}");
        for (_, m) in measurements(&json) {
            check_measurement(m);
        }
        for path in json["paths"].as_array().unwrap() {
            let scene = path["startup"]["scene_seconds"].as_f64().unwrap();
            assert!(scene > 0.0, "the scene's start-up: {path}");
        }
        check_png(&dir.path().join(&plot));
    }
}

/// The aperture sweep: the round aperture is measured with the shapes asked for, each path's
/// cost is its time over the round one's (1 for round), the table prints the costs, and the
/// shaped images differ from the round one (the shapes reach the renderer).
#[test]
fn aperture_sweep_weighs_shapes_against_the_round_aperture() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--paths",
        "cpu",
        "--sweep",
        "aperture",
        "--sweep-points",
        "image,hexagon",
        "--json",
        "aperture.json",
    ];
    let out = bench(&args, dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(
        table.contains("aperture cost") && table.contains("cpu: hexagon"),
        "{table}"
    );
    let json = read_json(&dir.path().join("aperture.json"));
    assert_eq!(json["sweep"], "aperture");
    let points = json["points"].as_array().unwrap();
    let shapes: Vec<&str> = points
        .iter()
        .map(|p| p["aperture"].as_str().unwrap())
        .collect();
    assert_eq!(shapes, ["round", "hexagon", "image"]);
    let mut errors = Vec::new();
    for (p, m) in measurements(&json) {
        check_measurement(m);
        let cost = m["cost_vs_round"].as_f64().expect("cost_vs_round");
        let times: Vec<f64> = points[0]["results"][0]["trace_seconds"]["median"]
            .as_f64()
            .into_iter()
            .collect();
        let expected = m["trace_seconds"]["median"].as_f64().unwrap() / times[0];
        assert!((cost - expected).abs() < 1e-9, "{cost} vs {expected}");
        if p["aperture"] == "round" {
            assert_eq!(cost, 1.0);
        }
        errors.push(m["rmse"].as_f64().unwrap());
    }
    assert!(
        errors[0] != errors[1] && errors[0] != errors[2],
        "the shapes rendered the round image: {errors:?}"
    );
}

/// The movements sweep: the plain shot is measured with the moved one, each path's ratio is its
/// time per sample over the plain one's (1 for plain), the table prints it, each point records
/// its movements, and the moved image differs from the plain one (they reach the renderer).
#[test]
fn movements_sweep_weighs_the_moved_shot_against_the_plain_one() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "--paths",
        "cpu",
        "--sweep",
        "movements",
        "--sweep-points",
        "moved",
        "--json",
        "movements.json",
    ];
    let out = bench(&args, dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(
        table.contains("movements cost") && table.contains("cpu   moved"),
        "{table}"
    );
    let json = read_json(&dir.path().join("movements.json"));
    assert_eq!(json["sweep"], "movements");
    let points = json["points"].as_array().unwrap();
    let shots: Vec<&str> = points
        .iter()
        .map(|p| p["movements"]["point"].as_str().unwrap())
        .collect();
    assert_eq!(shots, ["plain", "moved"]);
    let (plain, moved) = (&points[0]["movements"], &points[1]["movements"]);
    assert_eq!(plain["tilt_degrees"], 0.0);
    assert_eq!(plain["focus_tilt"], serde_json::json!([0.0, 0.0]));
    assert_eq!(moved["tilt_degrees"], 82.0);
    assert_eq!(moved["shift"], serde_json::json!([0.0, -0.1]));
    let window_y = moved["window_shift_image_heights"][1].as_f64().unwrap();
    assert!((window_y + 0.1).abs() < 1e-6, "{moved}");
    let plain_time = points[0]["results"][0]["trace_seconds"]["median"]
        .as_f64()
        .unwrap();
    let mut errors = Vec::new();
    for (p, m) in measurements(&json) {
        check_measurement(m);
        let ratio = m["time_per_sample_vs_plain"].as_f64().expect("a ratio");
        let expected = m["trace_seconds"]["median"].as_f64().unwrap() / plain_time;
        assert!((ratio - expected).abs() < 1e-9, "{ratio} vs {expected}");
        if p["movements"]["point"] == "plain" {
            assert_eq!(ratio, 1.0);
        }
        errors.push(m["rmse"].as_f64().unwrap());
    }
    assert_ne!(
        errors[0], errors[1],
        "the moved shot rendered the plain image"
    );
}

/// The lens sweep (CPU path, default points: every built-in lens with its first-order thin
/// lens): each lens lets more than 70 % of the camera samples through at the image centre,
/// its thin model all of them; every measurement has a positive cost per camera
/// ray against the thin model (1 for the thin point itself); under unlit shading the CPU
/// path's rays are the camera rays counted apart; the table prints the costs.
#[test]
fn lens_sweep_reports_pass_shares_and_costs_against_the_thin_lens() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--paths", "cpu", "--sweep", "lens", "--json", "lens.json"];
    let out = bench(&args, dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(
        table.contains("per camera ray vs thin") && table.contains("thin:double-gauss-50"),
        "{table}"
    );
    let json = read_json(&dir.path().join("lens.json"));
    assert_eq!(json["sweep"], "lens");
    assert_eq!(json["settings"]["shading"], "unlit");
    let points = json["points"].as_array().unwrap();
    let names = lensray_core::optics::builtin::names();
    assert_eq!(points.len(), 2 * names.len());
    for name in names {
        for model in ["thin", "real"] {
            let point = points
                .iter()
                .find(|p| p["lens"]["lens"] == name && p["lens"]["model"] == model)
                .unwrap_or_else(|| panic!("no {model} point for {name}"));
            let lens = &point["lens"];
            let get = |k: &str| lens[k].as_f64().unwrap_or_else(|| panic!("{k} in {lens}"));
            let (share, centre) = (get("pass_share"), get("centre_pass_share"));
            if model == "thin" {
                assert_eq!((share, centre), (1.0, 1.0), "{name}: {lens}");
            } else {
                assert!(centre > 0.7, "{name}: centre pass share {centre}");
                assert!(0.0 < share && share < 1.0, "{name}: pass share {share}");
            }
            assert!(get("f_number") > 1.0, "{lens}");
            let m = &point["results"][0];
            check_measurement(m);
            assert_eq!(m["rays"], lens["camera_rays"], "{name} {model}: {m}");
            let cost = m["cost_per_camera_ray_vs_thin"]
                .as_f64()
                .unwrap_or_else(|| panic!("no cost per camera ray: {m}"));
            assert!(cost.is_finite() && cost > 0.0, "{name} {model}: {cost}");
            if model == "thin" {
                assert_eq!(cost, 1.0);
            }
            assert!(m["camera_rays_per_second"].as_f64().unwrap() > 0.0, "{m}");
        }
    }
}

/// Bad input: one line naming the problem, a non-zero exit, no panic, no file written.
/// `--flare on --starburst on` with a real lens (assets/night: a lamp through double-gauss-50):
/// each path's flare time against its render's, in the table and the JSON (each run traces the
/// ghosts again, on the GPU path's device).
#[test]
fn flare_is_timed_against_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let night = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/night/night.toml");
    let mut args = vec!["--scene-file", night.to_str().unwrap(), "--shading", "lit"];
    args.extend(["--flare", "on", "--starburst", "on", "--json", "out.json"]);
    args.extend(["--paths", "cpu"]);
    let out = bench(&args, dir.path());
    assert!(out.status.success(), "{}", text(&out.stderr));
    let table = text(&out.stdout);
    assert!(table.contains("flare / render"), "{table}");
    let json = read_json(&dir.path().join("out.json"));
    for (_, m) in measurements(&json) {
        let ratio = m["flare_vs_render"].as_f64().expect("a flare ratio");
        let flare = m["phases"]["flare_seconds"]
            .as_f64()
            .expect("flare seconds");
        assert!(ratio > 0.0 && flare > 0.0, "{m}");
    }
}

#[test]
fn bad_input_is_one_clear_line_and_writes_nothing() {
    let cases: [(&[&str], &str); 12] = [
        (&["--paths", "cpu", "--flare", "on"], "--lens"),
        (
            &["--paths", "cpu", "--flare", "on", "--sweep", "spp"],
            "--sweep",
        ),
        (&["--paths", "cpu,warp"], "warp"),
        (&["--repeat", "0"], "--repeat"),
        (&["--paths", "rayquery", "--device", "cpu"], "--device cpu"),
        (
            &["--paths", "cpu", "--json", "missing/a.json"],
            "missing/a.json",
        ),
        (&["--paths", "cpu", "--plot", "a.svg"], ".png"),
        (
            &["--paths", "cpu", "--sweep", "spp", "--sweep-points", "0"],
            "--sweep-points",
        ),
        (
            &[
                "--paths",
                "cpu",
                "--sweep",
                "lens",
                "--sweep-points",
                "fisheye",
            ],
            "fisheye",
        ),
        (
            &["--sweep", "lens", "--aperture-radius", "0.1"],
            "--aperture-radius",
        ),
        (
            &[
                "--paths",
                "cpu",
                "--sweep",
                "movements",
                "--sweep-points",
                "swing",
            ],
            "swing",
        ),
        (
            &["--paths", "cpu", "--sweep", "movements", "--tilt", "95"],
            "tilt",
        ),
    ];
    for (args, needle) in cases {
        let dir = tempfile::tempdir().unwrap();
        let mut all = args.to_vec();
        if !args.contains(&"--json") {
            all.extend(["--json", "out.json"]);
        }
        let out = bench(&all, dir.path());
        let stderr = text(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert!(left.is_empty(), "{args:?} left {left:?}");
    }
}
