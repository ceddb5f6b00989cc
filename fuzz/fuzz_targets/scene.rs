//! A scene file as `lensray render scene.toml` loads it: the TOML with its `[[keyframe]]`s,
//! the mesh it names, and the files its settings name (lens prescription, environment map,
//! aperture image), then the shot and the keyframes' frames.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lensray_fuzz::targets::scene(data));
