//! The camera's tables that the trace shader reads: the aperture image's tables
//! (`ApertureGroup`) and the real lens's prescription (`LensGroup`), uploaded only when the
//! camera's aperture image or lens changes, and bound to every trace pipeline.

use std::sync::Arc;

use super::pipelines::TracePipelines;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use crate::passes::aperture::ApertureTable;
use crate::passes::lens::LensBuffer;
use lensray_core::camera::Camera;

pub(crate) struct CameraTables {
    /// The aperture image's tables.
    aperture: ApertureTable,
    /// The real lens.
    lens: LensBuffer,
}

impl CameraTables {
    /// The tables of no aperture image and a thin lens.
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        Ok(Self {
            aperture: ApertureTable::new(ctx)?,
            lens: LensBuffer::new(ctx)?,
        })
    }

    /// Points `pipeline`'s aperture and lens groups at the tables.
    pub(crate) fn bind(&self, pipeline: &Pipeline) {
        self.aperture.bind(pipeline);
        self.lens.bind(pipeline);
    }

    /// Makes the tables those of `camera` (see `ApertureTable::ensure`, `LensBuffer::ensure`),
    /// binding each one that changes to every pipeline of `pipelines` anew. Called before
    /// recording work with `camera`'s parameters.
    pub(super) fn ensure(
        &mut self,
        camera: &Camera,
        pipelines: &TracePipelines,
    ) -> Result<(), GpuError> {
        if self.aperture.ensure(camera)? {
            pipelines.bind_each(|p| self.aperture.bind(p));
        }
        if self.lens.ensure(camera)? {
            pipelines.bind_each(|p| self.lens.bind(p));
        }
        Ok(())
    }

    /// Whether `ensure(camera)` would upload new tables (and wait for the device).
    pub(crate) fn differ(&self, camera: &Camera) -> bool {
        self.aperture.differs(camera) || self.lens.differs(camera)
    }
}
