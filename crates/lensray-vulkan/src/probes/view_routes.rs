//! Tests' check of the view pass: a non-final preview view drawn by both of the preview's
//! routes, the G-buffer pass followed by the resolve (lensray-vulkan/src/present/resolve.rs), and the view pass
//! (lensray-vulkan/src/present/view_pass.rs) into an image of the resolve's display format, both read back.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::core::image::DeviceImage;
use crate::passes::gbuffer::GBufferPass;
use crate::present::resolve::{ResolvePass, DISPLAY_FORMAT};
use crate::present::view_pass::ViewPass;
use crate::scene::SceneBuffers;
use lensray_core::camera::Camera;

/// One view by both routes: 8-bit RGBA per pixel, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewRoutes {
    /// The G-buffer pass, then the resolve (what the final view's frames do).
    pub resolved: Vec<[u8; 4]>,
    /// The view pass (what the other views' frames draw into the window).
    pub drawn: Vec<[u8; 4]>,
}

pub(crate) fn run(
    ctx: &Arc<Context>,
    gbuffer: &mut GBufferPass,
    scene: &SceneBuffers,
    camera: &Camera,
    background: Vec3,
    view: u32,
) -> Result<ViewRoutes, GpuError> {
    let (width, height) = (camera.width, camera.height);
    gbuffer.ensure_targets(width, height)?;
    let targets = gbuffer.targets.as_ref().expect("ensured above");
    // The resolve binds an accumulation; the non-final views never read it.
    let accumulation = Buffer::new(
        ctx,
        "view probe accumulation",
        16,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )?;
    let mut resolve = ResolvePass::new(ctx)?;
    resolve.bind(&accumulation, targets, width, height)?;
    // Declared before the pass, so dropped after the framebuffer over it.
    let target = DeviceImage::new(
        ctx,
        "view probe target",
        width,
        height,
        DISPLAY_FORMAT,
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
        vk::ImageAspectFlags::COLOR,
    )?;
    let mut pass = ViewPass::new(ctx, DISPLAY_FORMAT, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)?;
    pass.ensure_view(view, scene)?;
    pass.attach(&[target.view], width, height)?;
    let readback = |name| {
        Buffer::new(
            ctx,
            name,
            u64::from(width) * u64::from(height) * 4,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )
    };
    let resolved_rb = readback("view probe resolved readback")?;
    let drawn_rb = readback("view probe drawn readback")?;
    let display = resolve.display.as_ref().expect("bound above");
    ctx.submit_and_wait(|rec| {
        gbuffer.record(rec, scene, camera, background, None);
        resolve.record(
            rec,
            targets,
            &crate::upload::resolve_push(
                camera,
                view,
                &lensray_core::film::tonemap::Display::LINEAR,
            ),
        );
        pass.record(
            rec,
            scene,
            camera,
            background,
            crate::upload::view_params(camera, view),
            0,
        );
        // The resolve and the view pass left their images in TRANSFER_SRC_OPTIMAL, their
        // writes ordered before transfers; the buffers hold the whole image.
        for (image, buffer) in [(display, &resolved_rb), (&target, &drawn_rb)] {
            rec.copy_image_to_buffer(image.image, buffer, [0, 0], [width, height]);
        }
        rec.read_on_host(&[&resolved_rb, &drawn_rb]);
        Ok(())
    })?;
    let pixels = |buffer: &Buffer| -> Result<Vec<[u8; 4]>, GpuError> {
        Ok(
            bytemuck::cast_slice::<u8, [u8; 4]>(buffer.read()?)[..(width * height) as usize]
                .to_vec(),
        )
    };
    Ok(ViewRoutes {
        resolved: pixels(&resolved_rb)?,
        drawn: pixels(&drawn_rb)?,
    })
}
