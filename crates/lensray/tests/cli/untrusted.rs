//! Files nobody here wrote: an image declaring a huge size (a decompression bomb: a few bytes
//! that would decode to gigabytes) is refused from its header in one line naming the file and
//! the size, within bounded memory, as a texture, an environment map and an aperture image.
//! What does not fit the GPU (an image past its largest allocation, a scene past its
//! storage-buffer range) is one line naming it and the device's limit.

use std::path::Path;

use crate::gpu_support::{record_skip, skip_or_fail};
use crate::{lensray, render_args, stderr};
use lensray_vulkan::GpuOptions;

/// CRC-32 (ISO 3309, as PNG chunks carry it).
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// A PNG whose header declares `width` x `height` grey pixels, followed by a few bytes of image
/// data and its end: under 100 bytes, declaring what would take gigabytes.
fn declared_png(width: u32, height: u32) -> Vec<u8> {
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8], data: &[u8]| {
        png.extend((data.len() as u32).to_be_bytes());
        let body: Vec<u8> = kind.iter().chain(data).copied().collect();
        png.extend(&body);
        png.extend(crc32(&body).to_be_bytes());
    };
    let mut header = width.to_be_bytes().to_vec();
    header.extend(height.to_be_bytes());
    header.extend([8, 0, 0, 0, 0]);
    chunk(b"IHDR", &header);
    chunk(b"IDAT", &[0x78, 0x9c, 0x63, 0x00, 0x00]);
    chunk(b"IEND", &[]);
    png
}

/// Runs `lensray` under GNU time: its stderr without time's line, and its peak resident memory
/// in MiB.
fn run_measured(args: &[&str], dir: &Path) -> (std::process::Output, String, f64) {
    let out = std::process::Command::new("/usr/bin/time")
        .args(["-f", "peak %M"])
        .arg(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run lensray under /usr/bin/time (the `time` package; scripts/setup.sh)");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    // time's own lines: the peak, and the exit status it reports.
    let (lines, peak): (Vec<&str>, Vec<&str>) = err
        .lines()
        .filter(|l| !l.starts_with("Command exited with non-zero status"))
        .partition(|l| !l.starts_with("peak "));
    let kib: f64 = peak
        .last()
        .and_then(|l| l.trim_start_matches("peak ").trim().parse().ok())
        .unwrap_or_else(|| panic!("no peak memory from time: {err}"));
    (out, lines.join("\n"), kib / 1024.0)
}

#[test]
fn images_declaring_huge_sizes_are_refused_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("bomb.png"), declared_png(60_000, 60_000)).unwrap();
    let hdr = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 60000 +X 120000\n";
    std::fs::write(d.join("bomb.hdr"), hdr).unwrap();
    std::fs::write(
        d.join("bomb.obj"),
        "mtllib bomb.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    std::fs::write(d.join("bomb.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd bomb.png\n").unwrap();
    let cases: [(&[&str], &str); 3] = [
        (&["--scene", "bomb.obj"], "bomb.png"),
        (&["--environment", "bomb.hdr"], "bomb.hdr"),
        (&["--aperture-image", "bomb.png"], "bomb.png"),
    ];
    for (extra, file) in cases {
        let mut args = extra.to_vec();
        args.extend(["--out", "out.png"]);
        let (out, err, peak_mib) = run_measured(&render_args(&args), d);
        println!(
            "{extra:?}: exit {:?}, peak {peak_mib:.0} MiB: {err}",
            out.status.code()
        );
        let size = if file.ends_with(".hdr") {
            "120000 x 60000 pixels"
        } else {
            "60000 x 60000 pixels"
        };
        assert!(
            !out.status.success() && err.lines().count() == 1,
            "{extra:?}: {err}"
        );
        assert!(err.contains(file) && err.contains(size), "{extra:?}: {err}");
        assert!(peak_mib < 1024.0, "{extra:?}: peak {peak_mib:.0} MiB");
        assert!(!d.join("out.png").exists(), "{extra:?} wrote an image");
    }
}

/// A file a scene names outside its folder is read with one note naming it; under
/// `--assets-root` (or `LENSRAY_ASSETS_ROOT`) one outside the root is refused in one line,
/// before it is read: a glTF buffer at `../../../../etc/passwd` as the issue found it read.
#[test]
fn reads_outside_the_assets_root_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::create_dir_all(d.join("scene")).unwrap();
    std::fs::create_dir_all(d.join("lib")).unwrap();
    std::fs::write(
        d.join("scene/tri.obj"),
        "mtllib ../lib/m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
    )
    .unwrap();
    std::fs::write(d.join("lib/m.mtl"), "newmtl m\nKd 0.8 0.2 0.2\n").unwrap();
    let passwd = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": []}],
        "buffers": [{"uri": "../../../../../../../../etc/passwd", "byteLength": 44}]}"#;
    std::fs::write(d.join("scene/passwd.gltf"), passwd).unwrap();

    let out = crate::lensray(
        &render_args(&["--scene", "scene/tri.obj", "--out", "a.png"]),
        d,
    );
    let err = crate::stderr(&out);
    assert!(out.status.success(), "{err}");
    let notes: Vec<&str> = err.lines().filter(|l| l.contains("outside")).collect();
    assert!(
        notes.len() == 1 && notes[0].contains("m.mtl"),
        "one note naming the library: {err}"
    );

    let root = d.join("scene");
    let root = root.to_str().unwrap();
    for (args, env) in [
        (
            vec!["--assets-root", root, "--scene", "scene/tri.obj"],
            None,
        ),
        (vec!["--scene", "scene/passwd.gltf"], Some(root)),
        (
            vec!["--assets-root", root, "--scene", "scene/passwd.gltf"],
            None,
        ),
    ] {
        let mut args = render_args(&args);
        args.extend(["--out", "b.png"]);
        let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_lensray"));
        command.args(&args).current_dir(d);
        if let Some(root) = env {
            command.env("LENSRAY_ASSETS_ROOT", root);
        }
        let out = command.output().unwrap();
        let err = crate::stderr(&out);
        println!("{args:?} (LENSRAY_ASSETS_ROOT {env:?}): {err}");
        assert!(
            !out.status.success() && err.lines().count() == 1,
            "{args:?}: {err}"
        );
        assert!(err.contains("outside the assets root"), "{err}");
        assert!(!d.join("b.png").exists());
    }
}

/// Runs a GPU render of `extra` with validation on in `dir`, and checks that it fails in one
/// line containing `needle` and writes no image; `None` (skip recorded) without a device.
fn assert_does_not_fit(test: &str, extra: &[&str], needle: &str, dir: &Path) {
    let mut args = vec!["render", "--device", "gpu", "--validate", "--spp", "1"];
    args.extend(["--shading", "unlit", "--out", "big.png"]);
    args.extend(extra);
    let out = lensray(&args, dir);
    let err = stderr(&out);
    println!("{extra:?}: exit {:?}: {err}", out.status.code());
    if !err.contains(needle) {
        skip_or_fail(test, &err);
        return;
    }
    // A device's first use also says that it compiles shaders (`caches.rs`).
    let lines = err.lines().filter(|l| !l.starts_with("compiling shaders"));
    assert!(!out.status.success() && lines.count() == 1, "{err}");
    assert!(!dir.join("big.png").exists(), "{extra:?} wrote an image");
}

/// An image whose accumulation film (16 bytes a pixel) passes the device's largest allocation
/// (lavapipe: 2 GiB; a larger buffer crashed in its copies) and a scene whose software-traversal
/// triangles (48 bytes each) pass its storage-buffer range (lavapipe: 128 MiB) are refused in
/// one line naming what did not fit and the limit, with no validation message. A device with
/// room for them (a real GPU's limits are larger) records a skip.
#[test]
fn what_does_not_fit_the_device_is_one_line() {
    let test = "what_does_not_fit_the_device_is_one_line";
    let device = match lensray_vulkan::preferred_device(&GpuOptions::default()) {
        Ok(device) => device,
        Err(e) => return skip_or_fail(test, &e.to_string()),
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (width, height) = (16_000u64, 9_000u64);
    if width * height * 16 <= device.max_memory_allocation_size {
        record_skip(
            test,
            &format!("{} allocates a 16000 x 9000 film", device.name),
        );
    } else {
        let size = ["--width", "16000", "--height", "9000", "--path", "software"];
        assert_does_not_fit(test, &size, "accumulation film needs", d);
    }
    let triangles = 3_000_000u64;
    if triangles * 48 <= u64::from(device.max_storage_buffer_range) {
        return record_skip(
            test,
            &format!("{} holds 3M triangles in one buffer", device.name),
        );
    }
    let generate = [
        "generate",
        "dense",
        "--gltf",
        "--triangles",
        "3000000",
        "--out",
        ".",
    ];
    assert!(
        lensray(&generate, d).status.success(),
        "generate the dense scene"
    );
    let scene = [
        "--scene",
        "dense.toml",
        "--path",
        "software",
        "--width",
        "16",
    ];
    assert_does_not_fit(test, &scene, "maximum storage buffer range", d);
}
