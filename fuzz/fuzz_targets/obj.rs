//! An OBJ scene as `lensray render scene.obj` loads it: the OBJ, its MTL libraries and their
//! textures, then the shot.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lensray_fuzz::targets::obj(data));
