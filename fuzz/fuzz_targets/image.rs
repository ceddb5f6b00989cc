//! An image file as lensray reads textures (a glTF's or an MTL's, colour, data and coverage,
//! decoded and mip-mapped) and aperture images (PNG or EXR, by the file's first bytes).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lensray_fuzz::targets::image(data));
