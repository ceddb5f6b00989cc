//! Real lenses: where the course stops ("in practice, the ray will refract twice
//! when passing through the lens"), rays cross each spherical surface of a lens prescription.
//!
//! - [`prescription`]: the table of surfaces (pbrt's lens-file layout), checked.
//! - [`builtin`]: the lenses shipped in `assets/lenses/`.
//! - [`paraxial`]: ray-transfer (ABCD) matrices, cardinal points, pupils.
//! - [`trace`]: exact tracing (spheres, Snell's law), in f64 and f32 from one source.
//! - [`analysis`]: what `lensray lens` prints: first-order and real-ray data.

pub mod analysis;
pub mod builtin;
pub mod paraxial;
pub mod prescription;
pub mod trace;

pub use prescription::{Prescription, PrescriptionError, Surface};
