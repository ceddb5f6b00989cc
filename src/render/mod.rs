//! What every renderer (CPU reference, GPU paths) shares: what to compute and the image it fills.

pub mod accumulation;
pub mod compare;
pub mod film;
pub mod path;
pub mod progressive;
pub mod settings;
pub mod stats;

pub use accumulation::Accumulation;
pub use film::Image;
pub use settings::{PointLight, RenderSettings, Shading};
