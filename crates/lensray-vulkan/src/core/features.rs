//! The extensions and features a logical device is opened with: those of the traversals it is
//! opened for (`DeviceReport::opened_traversals`).

use std::ffi::CStr;

use ash::{khr, vk};

use crate::core::adapter::{DEVICE_EXTENSIONS, RT_PIPELINE_EXTENSIONS};
use crate::core::error::{vk_err, GpuError};
use crate::traversal::Traversal;

/// The ray-tracing extensions a device is opened with, from the traversals it is opened for.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayTracingUse {
    pub ray_query: bool,
    pub rt_pipeline: bool,
}

impl RayTracingUse {
    pub(crate) fn of(traversals: &[Traversal]) -> Self {
        Self {
            ray_query: traversals.contains(&Traversal::RayQuery),
            rt_pipeline: traversals.contains(&Traversal::RtPipeline),
        }
    }

    /// Whether the driver's acceleration structures (and the device addresses their builds
    /// take) are enabled: both traversals of the driver's trace through them.
    pub(crate) fn accel(self) -> bool {
        self.ray_query || self.rt_pipeline
    }
}

/// Creates the logical device of `physical` with one queue of `queue_family`, the ray-tracing
/// extensions and features of `uses`, and VK_KHR_swapchain when it `presents`.
pub(crate) fn create_device(
    instance: &ash::Instance,
    (physical, queue_family): (vk::PhysicalDevice, u32),
    uses: RayTracingUse,
    presents: bool,
) -> Result<ash::Device, GpuError> {
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(queue_family)
        .queue_priorities(&priorities)];
    let mut names: Vec<&CStr> = Vec::new();
    if uses.ray_query {
        names.extend(DEVICE_EXTENSIONS);
    }
    if uses.rt_pipeline {
        for name in RT_PIPELINE_EXTENSIONS {
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    if presents {
        names.push(khr::swapchain::NAME);
    }
    let extensions: Vec<_> = names.iter().map(|e| e.as_ptr()).collect();
    // Device addresses only feed the acceleration-structure builds and the shader binding
    // table. Timeline semaphores (core and required in Vulkan 1.2) order and report the
    // submissions (`submit`).
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default()
        .buffer_device_address(uses.accel())
        .timeline_semaphore(true);
    let mut f_as =
        vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
    let mut f_rq = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
    let mut f_rtp =
        vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default().ray_tracing_pipeline(true);
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12);
    if uses.accel() {
        features = features.push_next(&mut f_as);
    }
    if uses.ray_query {
        features = features.push_next(&mut f_rq);
    }
    if uses.rt_pipeline {
        features = features.push_next(&mut f_rtp);
    }
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .push_next(&mut features);
    // SAFETY: the device was checked to support these extensions and features; all
    // pointers in `info` refer to locals alive during the call.
    unsafe { instance.create_device(physical, &info, None) }.map_err(vk_err("vkCreateDevice"))
}

/// The alignment of acceleration-structure build scratch memory (acceleration structures
/// enabled).
pub(crate) fn accel_scratch_alignment(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> u64 {
    let mut as_props = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut as_props);
    // SAFETY: the extension is enabled; query only.
    unsafe { instance.get_physical_device_properties2(physical, &mut props2) };
    u64::from(as_props.min_acceleration_structure_scratch_offset_alignment).max(1)
}
