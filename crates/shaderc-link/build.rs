//! Debian's `libshaderc_combined.a` is not really combined and `libshaderc.so` lacks its glslang
//! dependencies, so anything that links `shaderc-sys` against the system library also needs
//! glslang and SPIRV-Tools. They are passed as plain `-l` flags (searched static archives, placed
//! after every Rust library on the link line, so the order of crates does not matter).
//!
//! `LENSRAY_SHADERC_EXTRA_LIBS=0` turns this off (for systems whose libshaderc is self-contained,
//! or when shaderc is built from source).

use std::path::Path;

const LIBS: &[&str] = &[
    "glslang",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "SPIRV",
    "glslang-default-resource-limits",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=LENSRAY_SHADERC_EXTRA_LIBS");
    if std::env::var("LENSRAY_SHADERC_EXTRA_LIBS").as_deref() == Ok("0") {
        return;
    }
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if os != "linux" {
        return;
    }
    let candidates = [
        format!("/usr/lib/{arch}-linux-gnu"),
        "/usr/lib64".to_string(),
        "/usr/lib".to_string(),
    ];
    let Some(dir) = candidates
        .iter()
        .find(|d| Path::new(d).join("libglslang.a").exists())
    else {
        // Nothing to add: a self-contained libshaderc (or a source build) needs none of this.
        return;
    };
    println!("cargo:rustc-link-search=native={dir}");
    for lib in LIBS {
        if Path::new(dir).join(format!("lib{lib}.a")).exists() {
            println!("cargo:rustc-link-lib=static:-bundle={lib}");
        }
    }
    println!("cargo:rustc-link-lib=dylib=stdc++");
}
