//! A window's Vulkan surface (VK_KHR_surface + the platform extension ash-window picks), owned
//! with the instance it was made from.

use std::sync::Arc;

use ash::{khr, vk};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use crate::core::error::{vk_err, GpuError};
use crate::core::instance::Instance;

pub(crate) struct WindowSurface {
    /// The surface must go before the instance: keep it alive.
    instance: Arc<Instance>,
    pub loader: khr::surface::Instance,
    pub handle: vk::SurfaceKHR,
}

/// What the surface offers a device: formats, present modes, extents.
pub(crate) struct SurfaceSupport {
    pub capabilities: vk::SurfaceCapabilitiesKHR,
    pub formats: Vec<vk::SurfaceFormatKHR>,
    pub present_modes: Vec<vk::PresentModeKHR>,
}

impl WindowSurface {
    pub(crate) fn new(
        instance: &Arc<Instance>,
        display: RawDisplayHandle,
        window: RawWindowHandle,
    ) -> Result<Self, GpuError> {
        // SAFETY: the handles come from a live winit window that outlives the surface (the
        // viewer is dropped before the window), and the instance has the extensions
        // `ash_window::enumerate_required_extensions` named for this display.
        let handle = unsafe {
            ash_window::create_surface(&instance.entry, &instance.instance, display, window, None)
        }
        .map_err(vk_err("vkCreate*SurfaceKHR"))?;
        Ok(Self {
            instance: instance.clone(),
            loader: khr::surface::Instance::new(&instance.entry, &instance.instance),
            handle,
        })
    }

    /// Whether `queue_family` of `device` can present to this surface.
    pub(crate) fn supported_by(
        &self,
        device: vk::PhysicalDevice,
        queue_family: u32,
    ) -> Result<bool, GpuError> {
        // SAFETY: live physical device, surface and a valid queue family index.
        unsafe {
            self.loader
                .get_physical_device_surface_support(device, queue_family, self.handle)
        }
        .map_err(vk_err("vkGetPhysicalDeviceSurfaceSupportKHR"))
    }

    pub(crate) fn support(&self, device: vk::PhysicalDevice) -> Result<SurfaceSupport, GpuError> {
        // SAFETY: queries on a live physical device and surface.
        unsafe {
            Ok(SurfaceSupport {
                capabilities: self
                    .loader
                    .get_physical_device_surface_capabilities(device, self.handle)
                    .map_err(vk_err("vkGetPhysicalDeviceSurfaceCapabilitiesKHR"))?,
                formats: self
                    .loader
                    .get_physical_device_surface_formats(device, self.handle)
                    .map_err(vk_err("vkGetPhysicalDeviceSurfaceFormatsKHR"))?,
                present_modes: self
                    .loader
                    .get_physical_device_surface_present_modes(device, self.handle)
                    .map_err(vk_err("vkGetPhysicalDeviceSurfacePresentModesKHR"))?,
            })
        }
    }
}

impl Drop for WindowSurface {
    fn drop(&mut self) {
        // SAFETY: the swapchains made from it were destroyed first (the viewer owns them and
        // drops them before the surface); the instance is still alive (held above).
        unsafe { self.loader.destroy_surface(self.handle, None) };
        let _ = &self.instance;
    }
}
