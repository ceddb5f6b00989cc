//! What a camera's lens is: a thin lens (a pinhole when closed), or a real lens traced surface
//! by surface together with its first-order model.

use std::sync::Arc;

use super::{RealLens, ThinLens};

/// A camera's lens: the one thing camera rays go through (`Camera::generate_ray`).
#[derive(Clone, Debug, PartialEq)]
pub enum Lens {
    /// A thin lens; a pinhole when its aperture radius is 0.
    Thin(ThinLens),
    /// A real lens traced surface by surface (its entrance pupil is camera space's origin), and
    /// its first-order model: the thin lens at the entrance pupil with the pupil's radius,
    /// focused where the real lens is.
    Real {
        real: Arc<RealLens>,
        first_order: ThinLens,
    },
}

impl Lens {
    /// The thin lens itself, or a real lens's first-order model: what rasterizing passes draw,
    /// the GPU's camera holds, and circles of confusion and AOVs use.
    pub fn first_order(&self) -> &ThinLens {
        match self {
            Lens::Thin(thin) => thin,
            Lens::Real { first_order, .. } => first_order,
        }
    }

    /// [`first_order`](Self::first_order), to change.
    pub fn first_order_mut(&mut self) -> &mut ThinLens {
        match self {
            Lens::Thin(thin) => thin,
            Lens::Real { first_order, .. } => first_order,
        }
    }

    /// The real lens whose surfaces camera rays cross, if the lens is one.
    pub fn real(&self) -> Option<&Arc<RealLens>> {
        match self {
            Lens::Thin(_) => None,
            Lens::Real { real, .. } => Some(real),
        }
    }

    /// Whether this is a pinhole: a thin lens closed to aperture radius 0.
    pub fn is_pinhole(&self) -> bool {
        matches!(self, Lens::Thin(thin) if thin.aperture_radius == 0.0)
    }

    /// The first-order model alone, as a thin lens: no real lens traced.
    pub fn first_order_only(&self) -> Lens {
        Lens::Thin(self.first_order().clone())
    }
}
