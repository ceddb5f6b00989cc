//! lensray's core: everything a render is made of, without Vulkan.
//!
//! What to render: the [`camera`] (the course's coordinate spaces and projections, and its lens:
//! pinhole, thin or real, whose prescriptions [`optics`] reads and traces), the [`sampler`], the
//! [`scene`] and the [`settings`] a user gives, resolved into one shot. What a render fills: the
//! [`film`] (image, accumulation, comparison, colour encoding); [`image_file`] decodes image files
//! within a stated size. The CPU [`reference`](mod@reference)
//! renderer that every other path is checked against, and the [`interface`] whose layouts the
//! GLSL shaders of `lensray-vulkan` share. [`stats`] and [`cache`] serve the layers above.

// `pub` means exported: what no other crate can reach is `pub(crate)`.
#![deny(unreachable_pub)]
#![forbid(unsafe_code)]

pub mod cache;
pub mod camera;
pub mod film;
pub mod image_file;
pub use lensray_interface as interface;
pub mod optics;
pub mod reference;
pub mod sampler;
pub mod scene;
pub mod settings;
pub mod stats;
