//! The lenses `RealLens::new` built last, by their arguments.

use std::sync::Mutex;

use super::{Aperture, RealLens, RealLensParams};

/// How many are kept (the preview goes back and forth between a few lenses and stops).
const KEPT: usize = 4;

static LENSES: Mutex<Vec<RealLens>> = Mutex::new(Vec::new());

pub(super) fn find(params: &RealLensParams, aspect: f32, aperture: &Aperture) -> Option<RealLens> {
    let lenses = LENSES.lock().unwrap_or_else(|e| e.into_inner());
    lenses
        .iter()
        .find(|l| {
            l.aspect.to_bits() == aspect.to_bits() && l.aperture == *aperture && l.params == *params
        })
        .cloned()
}

pub(super) fn keep(real: &RealLens) {
    let mut lenses = LENSES.lock().unwrap_or_else(|e| e.into_inner());
    if lenses.len() == KEPT {
        lenses.remove(0);
    }
    lenses.push(real.clone());
}
