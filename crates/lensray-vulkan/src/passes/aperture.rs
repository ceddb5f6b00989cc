//! The aperture image's tables on the device (`camera::aperture::image`): the storage buffer
//! that trace.comp (`ApertureGroup`) and the mirror probe read: the cumulative tables,
//! then the cells' transmissions (a real lens's stop reads them, `Lens.aperture_transmission_start`).
//! A placeholder while the aperture is no image; uploaded again only when the camera's image
//! changes.

use std::sync::Arc;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::descriptors::Gpu;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::pipeline::Pipeline;
use lensray_core::camera::aperture::ApertureImage;
use lensray_core::camera::Camera;
use lensray_core::interface::ApertureGroup;

pub(crate) struct ApertureTable {
    ctx: Arc<Context>,
    pub buffer: Buffer,
    /// The image whose tables `buffer` holds (`None`: the placeholder).
    image: Option<Arc<ApertureImage>>,
}

impl ApertureTable {
    /// Points `pipeline`'s `ApertureGroup` at the buffer.
    pub(crate) fn bind(&self, pipeline: &Pipeline) {
        pipeline.bind_group(&ApertureGroup::<Gpu> {
            aperture_table: &self.buffer,
        });
    }

    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        Ok(ApertureTable {
            ctx: ctx.clone(),
            buffer: Self::upload(ctx, &[0.0; 4])?,
            image: None,
        })
    }

    /// The tables of `camera`'s aperture image, for a one-off dispatch (the probe, the ghosts).
    pub(crate) fn of(ctx: &Arc<Context>, camera: &Camera) -> Result<Buffer, GpuError> {
        match camera.lens.first_order().aperture.image() {
            Some(image) => Self::upload_image(ctx, image),
            None => Self::upload(ctx, &[0.0; 4]),
        }
    }

    fn upload(ctx: &Arc<Context>, table: &[f32]) -> Result<Buffer, GpuError> {
        Buffer::with_data(
            ctx,
            "aperture image tables",
            bytemuck::cast_slice(table),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )
    }

    /// The image's tables, then its cells' transmissions.
    fn upload_image(ctx: &Arc<Context>, image: &ApertureImage) -> Result<Buffer, GpuError> {
        let values: Vec<f32> = image
            .table()
            .iter()
            .chain(image.transmission())
            .copied()
            .collect();
        Self::upload(ctx, &values)
    }

    /// Whether `camera`'s aperture image is not the one the buffer holds.
    pub(crate) fn differs(&self, camera: &Camera) -> bool {
        match (&self.image, &camera.lens.first_order().aperture.shape.image) {
            (None, None) => false,
            (Some(a), Some(b)) => !(Arc::ptr_eq(a, b) || a == b),
            _ => true,
        }
    }

    /// Makes the buffer hold `camera`'s image tables. Returns whether it is a new buffer (to
    /// bind again); a change waits for the device first, since pending work binds the old one
    /// (an aperture image changes rarely: once per render or per file edit).
    pub(crate) fn ensure(&mut self, camera: &Camera) -> Result<bool, GpuError> {
        if !self.differs(camera) {
            return Ok(false);
        }
        let wanted = camera.lens.first_order().aperture.shape.image.as_ref();
        self.ctx.wait_all()?;
        self.buffer = match wanted {
            Some(image) => Self::upload_image(&self.ctx, image)?,
            None => Self::upload(&self.ctx, &[0.0; 4])?,
        };
        self.image = wanted.cloned();
        Ok(true)
    }
}
