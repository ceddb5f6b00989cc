//! The window's swapchain: images the viewer blits into and draws the overlay on, one
//! "rendering finished" semaphore per image (waited on by its present), recreated on resize or
//! when the surface reports it out of date.

use std::sync::Arc;

use ash::{khr, vk};

use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::image::subresource_range;
use crate::core::surface::WindowSurface;
use crate::core::sync::Semaphore;

/// 8-bit UNORM formats: the viewer writes sRGB-encoded values itself (the resolve pass), so the
/// presentation engine must not encode again.
const FORMATS: [vk::Format; 2] = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM];

pub(crate) struct Swapchain {
    ctx: Arc<Context>,
    loader: khr::swapchain::Device,
    pub handle: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub views: Vec<vk::ImageView>,
    /// Signalled when image i's frame is rendered; its present waits on it.
    pub rendered: Vec<Semaphore>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub present_mode: vk::PresentModeKHR,
}

/// What acquiring an image gave.
pub(crate) enum Acquired {
    Image(u32),
    /// The surface changed (resized, out of date): recreate the swapchain first.
    OutOfDate,
}

impl Swapchain {
    /// A swapchain of the window's current size (`window_size` where the surface leaves it to
    /// the application); `None` while the window has no area (minimised).
    pub(crate) fn new(
        ctx: &Arc<Context>,
        surface: &WindowSurface,
        window_size: [u32; 2],
        present_mode: vk::PresentModeKHR,
        old: Option<&Swapchain>,
    ) -> Result<Option<Self>, GpuError> {
        let support = surface.support(ctx.physical_device)?;
        let caps = support.capabilities;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: window_size[0]
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: window_size[1]
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let format = support
            .formats
            .iter()
            .find(|f| {
                FORMATS.contains(&f.format) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR
            })
            .copied()
            .ok_or_else(|| {
                GpuError::Invalid(format!(
                    "the window offers no 8-bit UNORM sRGB-nonlinear format (it offers {:?})",
                    support.formats
                ))
            })?;
        let present_mode = if support.present_modes.contains(&present_mode) {
            present_mode
        } else {
            vk::PresentModeKHR::FIFO // always supported
        };
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let composite_alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|a| caps.supported_composite_alpha.contains(*a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let usage = vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::COLOR_ATTACHMENT;
        if !caps.supported_usage_flags.contains(usage) {
            return Err(GpuError::Invalid(
                "the window's images cannot be copied to and drawn on".into(),
            ));
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.handle)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(composite_alpha)
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.handle));
        let loader = khr::swapchain::Device::new(&ctx.instance.instance, &ctx.device);
        // SAFETY: valid create-info; the surface is live and supported by the device's queue.
        let handle = unsafe { loader.create_swapchain(&info, None) }
            .map_err(vk_err("vkCreateSwapchainKHR"))?;
        let mut this = Self {
            ctx: ctx.clone(),
            loader,
            handle,
            images: Vec::new(),
            views: Vec::new(),
            rendered: Vec::new(),
            format: format.format,
            extent,
            present_mode,
        };
        // SAFETY: the swapchain was just created.
        this.images = unsafe { this.loader.get_swapchain_images(handle) }
            .map_err(vk_err("vkGetSwapchainImagesKHR"))?;
        for &image in &this.images {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format.format)
                .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR));
            // SAFETY: a swapchain image of this format; destroyed in Drop before the swapchain.
            let view = unsafe { ctx.device.create_image_view(&view_info, None) }
                .map_err(vk_err("vkCreateImageView"))?;
            this.views.push(view);
            this.rendered.push(Semaphore::new(ctx)?);
        }
        Ok(Some(this))
    }

    /// The next image to render to; `signal` is signalled when it may be written.
    pub(crate) fn acquire(&self, signal: &Semaphore) -> Result<Acquired, GpuError> {
        // SAFETY: live swapchain; the semaphore is unsignalled with no pending wait (each frame
        // slot's semaphore is waited on by that slot's previous submission, finished by now).
        match unsafe {
            self.loader
                .acquire_next_image(self.handle, u64::MAX, signal.handle, vk::Fence::null())
        } {
            // A suboptimal image is still presented; the next frame recreates the swapchain.
            Ok((index, _suboptimal)) => Ok(Acquired::Image(index)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(e) => Err(vk_err("vkAcquireNextImageKHR")(e)),
        }
    }

    /// Presents image `index` once its `rendered` semaphore is signalled; false when the
    /// swapchain should be recreated (out of date or suboptimal).
    pub(crate) fn present(&self, index: u32) -> Result<bool, GpuError> {
        let wait = [self.rendered[index as usize].handle];
        let swapchains = [self.handle];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and a submission signalling `wait` was made.
        match unsafe { self.loader.queue_present(self.ctx.queue, &info) } {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(e) => Err(vk_err("vkQueuePresentKHR")(e)),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // SAFETY: the viewer waits for the device to be idle before replacing or dropping a
        // swapchain, so no submission or present uses these objects any more.
        unsafe {
            for &view in &self.views {
                self.ctx.device.destroy_image_view(view, None);
            }
        }
        // The semaphores go before the swapchain whose presents waited on them.
        self.rendered.clear();
        // SAFETY: as above; its views are destroyed.
        unsafe { self.loader.destroy_swapchain(self.handle, None) };
    }
}
