//! An environment map as a scene's `environment = "FILE"` loads it: Radiance HDR or OpenEXR
//! (by the file's first bytes), mended, turned and made into a light to sample.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lensray_fuzz::targets::environment(data));
