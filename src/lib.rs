//! lensray: thin-lens depth of field, rendered by a CPU reference and Vulkan paths that are
//! checked against it.
//!
//! Top-down: what to render ([`camera`], [`sampler`], [`scene`], [`settings`]), what a render
//! fills ([`film`]), the algorithms that fill it ([`paths`]: the CPU [`reference`](mod@reference) and the
//! Vulkan renderer in [`gpu`], which shares its layouts with the shaders through
//! [`interface`]), and the commands ([`cli`]: `render` writes through [`output`], `preview`
//! opens the window of [`preview`], `bench` compares the paths with [`bench`](mod@bench), reporting
//! medians from [`stats`]).

#![deny(unsafe_code)]

pub mod bench;
pub mod cache;
pub mod camera;
pub mod cli;
pub mod film;
// The Vulkan module is the only place allowed to use `unsafe` (each block says why).
#[allow(unsafe_code)]
pub mod gpu;
pub mod interface;
pub mod optics;
pub mod output;
pub mod paths;
pub mod preview;
pub mod reference;
pub mod sampler;
pub mod scene;
pub mod settings;
pub mod stats;
