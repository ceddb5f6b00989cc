//! The passes of the renderer, one per file: the aperture image's tables (`aperture`), the real lens (`lens`), the raster G-buffer (`gbuffer`, drawing the scene
//! with `draw`), the thin-lens compute pass (`trace`) and the accumulations it keeps on the device (`films`), the raster path's visibility pass
//! (`visibility`), the hybrid path's plan on the device (`hybrid_plan`) and a real lens's
//! ghosts (`ghosts`).

pub(crate) mod aperture;
pub(crate) mod draw;
pub(crate) mod films;
pub(crate) mod gbuffer;
pub(crate) mod ghosts;
pub(crate) mod hybrid_plan;
pub(crate) mod lens;
pub(crate) mod trace;
pub(crate) mod visibility;
