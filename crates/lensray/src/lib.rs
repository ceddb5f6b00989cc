//! The `lensray` app: the render [`paths`] (their kinds, `auto` and its calibration, one mapping
//! from a kind to its implementation), the [`preview`] window, the [`bench`](mod@bench), the
//! command line ([`cli`]) and image files ([`output`]).
//!
//! It stands on two crates: `lensray-core` (camera, optics, sampler, scene, shot, film and the
//! CPU reference; no Vulkan) and `lensray-vulkan` (the device, the passes and presentation; the
//! only `unsafe` code). Imports point down only.

// `pub` means exported: what no other crate can reach is `pub(crate)`.
#![deny(unreachable_pub)]
#![forbid(unsafe_code)]

pub mod bench;
pub mod cli;
pub mod output;
pub mod paths;
pub mod preview;
