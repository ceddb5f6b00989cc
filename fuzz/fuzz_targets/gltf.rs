//! A glTF scene as `lensray render scene.gltf` (or `.glb`) loads it, then the shot. Half the
//! mutations keep the JSON valid (`gltf_mutator`), so inputs reach the accessors, animations
//! and textures rather than stopping at JSON syntax.
#![no_main]

use lensray_fuzz::gltf_mutator;
use libfuzzer_sys::{fuzz_mutator, fuzz_target, fuzzer_mutate};

fuzz_target!(|data: &[u8]| lensray_fuzz::targets::gltf(data));

fuzz_mutator!(|data: &mut [u8], size: usize, max_size: usize, seed: u32| {
    if seed.is_multiple_of(2) {
        if let Some(changed) = gltf_mutator::mutate(&data[..size], seed) {
            if changed.len() <= max_size {
                data[..changed.len()].copy_from_slice(&changed);
                return changed.len();
            }
        }
    }
    fuzzer_mutate(data, size, max_size)
});
