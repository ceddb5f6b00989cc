//! A real lens on the device (`camera::real_lens`): the storage buffer that trace.comp
//! (`LensGroup`) and the mirror probe read, laid out as `interface::GpuLens`. It
//! holds `surface_count` 0 while the camera has a thin lens; uploaded again only when the
//! lens or the image size changes (focusing or stopping down makes a new lens).

use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use lensray_core::camera::{Camera, RealLens};
use lensray_core::interface::{GpuLens, LensGroup};

pub(crate) struct LensBuffer {
    ctx: Arc<Context>,
    pub buffer: Buffer,
    /// What `buffer` holds: the lens (`None`: none) and the image size it was written for.
    holds: (Option<Arc<RealLens>>, u32, u32),
}

impl LensBuffer {
    /// Points `pipeline`'s `LensGroup` at the buffer.
    pub(crate) fn bind(&self, pipeline: &Pipeline) {
        pipeline.bind_group(&LensGroup::<Gpu> { lens: &self.buffer });
    }

    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        Ok(LensBuffer {
            ctx: ctx.clone(),
            buffer: Self::upload(ctx, &crate::upload::thin_lens())?,
            holds: (None, 0, 0),
        })
    }

    /// The lens of `camera`, for a one-off dispatch (the probe, the ghosts).
    pub(crate) fn of(ctx: &Arc<Context>, camera: &Camera) -> Result<Buffer, GpuError> {
        Self::upload(ctx, &crate::upload::gpu_lens(camera)?)
    }

    fn upload(ctx: &Arc<Context>, lens: &GpuLens) -> Result<Buffer, GpuError> {
        Buffer::with_data(
            ctx,
            "real lens",
            bytemuck::bytes_of(lens),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )
    }

    /// Whether `camera`'s lens (or image size, for a real lens) is not what the buffer holds.
    pub(crate) fn differs(&self, camera: &Camera) -> bool {
        match (self.holds.0.as_ref(), camera.lens.real()) {
            (None, None) => false,
            (Some(a), Some(b)) => {
                !(Arc::ptr_eq(a, b) || a == b)
                    || (self.holds.1, self.holds.2) != (camera.width, camera.height)
            }
            _ => true,
        }
    }

    /// Makes the buffer hold `camera`'s lens. Returns whether it is a new buffer (to bind
    /// again); a change waits for the device first, since pending work binds the old one.
    pub(crate) fn ensure(&mut self, camera: &Camera) -> Result<bool, GpuError> {
        if !self.differs(camera) {
            return Ok(false);
        }
        let lens = crate::upload::gpu_lens(camera)?;
        self.ctx.wait_all()?;
        self.buffer = Self::upload(&self.ctx, &lens)?;
        self.holds = (camera.lens.real().cloned(), camera.width, camera.height);
        Ok(true)
    }
}
