//! The `lensray` app: the render [`paths`] (their kinds, `auto` and its calibration, one mapping
//! from a kind to its implementation), the [`preview`] window, the [`bench`](mod@bench), the
//! command line ([`cli`]) and image files ([`output`]).
//!
//! Its modules, top to bottom; each imports only from those below it:
//! - [`cli`]: the subcommands and their options (`main.rs` parses them);
//! - [`preview`] and [`bench`](mod@bench);
//! - [`focus`]: focusing on what a path sees under a pixel (`render` and the preview), and
//!   [`frame_settings`]: a sequence's settings at each frame (`render --frames` and the
//!   preview's frame slider);
//! - [`lens_flare`]: the lens's own light added to a rendered image (`--flare`, `--starburst`);
//! - [`paths`]: the render paths and `auto`;
//! - [`output`] (image files) and [`machine`] (the machine lensray runs on).
//!
//! It stands on two crates: `lensray-core` (camera, optics, sampler, scene, shot, film and the
//! CPU reference; no Vulkan) and `lensray-vulkan` (the device, the passes and presentation; the
//! only `unsafe` code). Imports point down only.

// `pub` means exported: what no other crate can reach is `pub(crate)`.
#![deny(unreachable_pub)]
#![forbid(unsafe_code)]

pub mod bench;
pub mod cli;
pub mod focus;
pub mod frame_settings;
pub mod lens_flare;
pub mod machine;
pub mod output;
pub mod paths;
pub mod preview;
