//! A lens prescription as `lensray lens FILE` reads it: the rows, the checks, and the
//! first-order, real-ray and colour data.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| lensray_fuzz::targets::lens(data));
