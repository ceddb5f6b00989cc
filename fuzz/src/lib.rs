//! lensray's fuzz targets (docs/testing.md, "Fuzzing"): what each runs ([`targets`]) and the
//! glTF target's mutation that keeps the JSON valid ([`gltf_mutator`]).

pub mod gltf_mutator;
pub mod targets;

pub use targets::SEPARATOR;
