//! Real lenses: where the course stops ("in practice, the ray will refract twice
//! when passing through the lens"), rays cross each surface of a lens prescription.
//!
//! - [`prescription`]: the table of surfaces (pbrt's lens-file layout), checked.
//! - [`glass`]: each medium's index at any wavelength (the Cauchy fit through n_d and V_d).
//! - [`coating`]: what a surface reflects, bare or under an anti-reflection layer (thin-film
//!   Fresnel, per wavelength): the light of a lens's ghosts.
//! - [`ghost`]: the share of a ray's power a ghost's path carries.
//! - [`asphere`]: even aspheric surfaces (conic and polynomial sag).
//! - [`builtin`]: the lenses shipped in `assets/lenses/`.
//! - [`paraxial`]: ray-transfer (ABCD) matrices, cardinal points, pupils.
//! - [`trace`]: exact tracing (spheres, aspheres, Snell's law at a wavelength), in f64 and f32
//!   from one source.
//! - [`analysis`]: what `lensray lens` prints: first-order and real-ray data.

pub mod analysis;
pub mod asphere;
pub mod builtin;
pub mod coating;
pub mod ghost;
pub mod glass;
pub mod paraxial;
pub mod prescription;
pub mod trace;

pub use glass::Glass;
pub use prescription::{Prescription, PrescriptionError, Surface};
