//! The one error type of the Vulkan renderer, and one mapping function per kind of failing call.

use ash::vk;
use thiserror::Error;

use crate::core::device::Context;
use crate::traversal::Traversal;

#[derive(Debug, Error)]
pub enum GpuError {
    /// The Vulkan loader library could not be found or opened.
    #[error("cannot load the Vulkan library: {0}")]
    Loader(String),
    /// The loader found no Vulkan driver (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER).
    #[error(
        "no Vulkan driver is installed (Debian/Ubuntu: apt-get install mesa-vulkan-drivers for \
         lavapipe, or your GPU vendor's driver)"
    )]
    NoDriver,
    /// The device was lost (VK_ERROR_DEVICE_LOST: a GPU fault, a driver reset or a watchdog's
    /// timeout): nothing it was computing can be read back.
    #[error(
        "the GPU device was lost during {call} (a GPU fault, a driver reset or a timeout): the \
         render stopped and wrote nothing"
    )]
    DeviceLost { call: &'static str },
    /// A Vulkan call returned an error code.
    #[error("Vulkan call {call} failed: {result}")]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },
    /// One resource needs more memory than the device allocates at once.
    #[error(
        "{what} needs {} MiB of GPU memory, more than {device} allocates at once \
         ({} MiB, maxMemoryAllocationSize): render a smaller image or scene",
        bytes >> 20,
        limit >> 20
    )]
    TooLarge {
        what: String,
        bytes: u64,
        device: String,
        limit: u64,
    },
    /// gpu-allocator could not provide memory.
    #[error("GPU memory allocation for {what} failed: {source}")]
    Allocation {
        what: String,
        #[source]
        source: gpu_allocator::AllocationError,
    },
    /// No device (or not the chosen one) can run lensray with the requested traversal (ray
    /// queries, or any for the software traversal).
    #[error("{0}")]
    NoRayQueryDevice(String),
    /// The opened device cannot trace with this traversal (not supported, hidden, or not
    /// requested when it was opened).
    #[error("the {traversal} traversal is not available on {device} (available: {available})")]
    TraversalUnavailable {
        traversal: Traversal,
        device: String,
        available: String,
    },
    /// `GpuOptions::device_index` names no device.
    #[error("Vulkan device index {index} does not exist: {count} device(s) found{names}")]
    DeviceIndex {
        index: usize,
        count: usize,
        names: String,
    },
    /// The validation layer was asked for but is not installed.
    #[error(
        "validation requested but the layer {0} is not installed (Debian/Ubuntu: apt-get install \
         vulkan-validationlayers; elsewhere: the Vulkan SDK)"
    )]
    MissingLayer(String),
    /// The validation layer reported warnings or errors (leaks at shutdown included).
    #[error("Vulkan validation reported {count} message(s); first: {first}")]
    Validation { count: usize, first: String },
    /// A call that needs a scene came before `load_scene`.
    #[error("no scene loaded: call GpuRenderer::load_scene first")]
    NoScene,
    /// Input that the GPU path cannot handle (too large, inconsistent).
    #[error("invalid input for the GPU renderer: {0}")]
    Invalid(String),
    /// An accumulation whose current sums another device holds.
    #[error(transparent)]
    OnDevice(#[from] lensray_core::film::OnDevice),
}

/// Maps the error code of Vulkan call `call` (use the command's name).
pub(crate) fn vk_err(call: &'static str) -> impl FnOnce(vk::Result) -> GpuError {
    move |result| match result {
        vk::Result::ERROR_DEVICE_LOST => GpuError::DeviceLost { call },
        result => GpuError::Vulkan { call, result },
    }
}

/// Maps a pipeline-creation error, which comes with the partially created pipelines.
pub(crate) fn pipeline_err(
    call: &'static str,
) -> impl FnOnce((Vec<vk::Pipeline>, vk::Result)) -> GpuError {
    move |(_, result)| vk_err(call)(result)
}

/// Maps an allocation failure of gpu-allocator for the resource `what`.
pub(crate) fn alloc_err(
    what: &str,
) -> impl FnOnce(gpu_allocator::AllocationError) -> GpuError + '_ {
    move |source| GpuError::Allocation {
        what: what.to_string(),
        source,
    }
}

/// `Err(TooLarge)` where `bytes` of the resource `what` pass the device's largest allocation:
/// a driver may make a larger one and fail later (lavapipe's copies then crash), so none is
/// asked for.
pub(crate) fn check_allocation(ctx: &Context, what: &str, bytes: u64) -> Result<(), GpuError> {
    let limit = ctx.report.max_memory_allocation_size;
    if bytes > limit {
        return Err(GpuError::TooLarge {
            what: what.to_string(),
            bytes,
            device: ctx.report.name.clone(),
            limit,
        });
    }
    Ok(())
}

/// Maps a failure to load the Vulkan library.
pub(crate) fn loader_err(e: ash::LoadingError) -> GpuError {
    GpuError::Loader(e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lost device (which lavapipe cannot be made to lose) is one line naming it and the
    /// call; other codes keep their name.
    #[test]
    fn a_lost_device_is_one_line_naming_it() {
        let lost = vk_err("vkQueueSubmit2")(vk::Result::ERROR_DEVICE_LOST).to_string();
        assert!(matches!(
            vk_err("vkQueueSubmit2")(vk::Result::ERROR_DEVICE_LOST),
            GpuError::DeviceLost { .. }
        ));
        assert_eq!(lost.lines().count(), 1, "{lost}");
        assert!(
            lost.contains("device was lost") && lost.contains("vkQueueSubmit2"),
            "{lost}"
        );
        let memory = vk_err("vkAllocateMemory")(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY);
        assert!(
            memory.to_string().contains("memory allocation has failed"),
            "{memory}"
        );
    }
}
