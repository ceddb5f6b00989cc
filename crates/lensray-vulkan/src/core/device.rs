//! Physical device reports and selection, and the logical device with its queue, allocator and
//! command pool (the [`Context`] every GPU object holds an `Arc` to).

use std::ffi::CStr;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::{khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::core::error::{alloc_err, vk_err, GpuError};
use crate::core::instance::Instance;
use crate::core::pipeline_cache;
use crate::present::surface::Surface;
use crate::traversal::Traversal;
use crate::GpuOptions;

/// What `lensray info` shows about one Vulkan device.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DeviceReport {
    /// Position in the instance's device list (what `GpuOptions::device_index` takes).
    pub index: usize,
    pub name: String,
    /// "discrete GPU", "integrated GPU", "virtual GPU", "CPU" or "other".
    pub device_type: String,
    /// Vulkan API version the device supports, "major.minor.patch".
    pub api_version: String,
    /// The raw driver version, decoded as a Vulkan version (vendors may encode it differently).
    pub driver_version: String,
    /// Driver name and info (VkPhysicalDeviceDriverProperties), e.g. "llvmpipe: Mesa 25.0.7".
    pub driver: String,
    /// Whether it can run the ray-query traversal: the extensions and features below are all
    /// present.
    pub ray_query: bool,
    /// What is missing for ray queries (extension names, features); empty when `ray_query`.
    pub missing: Vec<String>,
    /// Whether it can run the software traversal (Vulkan 1.2 and a graphics + compute queue;
    /// no ray-tracing support needed).
    pub software: bool,
    /// What is missing for the software traversal; empty when `software`.
    pub missing_software: Vec<String>,
    pub max_image_dimension_2d: u32,
    pub max_compute_work_group_count: [u32; 3],
    pub max_compute_work_group_size: [u32; 3],
    pub max_compute_work_group_invocations: u32,
    pub max_storage_buffer_range: u32,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    /// Whether graphics and compute queues support timestamps.
    pub timestamps: bool,
    /// What a pipeline cache's data is valid for (VkPhysicalDeviceProperties): the vendor,
    /// device and cache UUID, which a driver changes when its compiled code would change.
    pub vendor_id: u32,
    pub device_id: u32,
    pub pipeline_cache_uuid: [u8; 16],
}

pub(crate) const DEVICE_EXTENSIONS: [&CStr; 3] = [
    khr::acceleration_structure::NAME,
    khr::ray_query::NAME,
    khr::deferred_host_operations::NAME,
];

impl DeviceReport {
    /// Whether the device is a CPU implementation of Vulkan (VK_PHYSICAL_DEVICE_TYPE_CPU, as
    /// lavapipe): it runs on the cores the CPU reference renders with.
    pub fn is_cpu(&self) -> bool {
        self.device_type == type_name(vk::PhysicalDeviceType::CPU)
    }

    /// The traversals this device can run, ray queries first.
    pub fn traversals(&self) -> Vec<Traversal> {
        let mut out = Vec::new();
        if self.ray_query {
            out.push(Traversal::RayQuery);
        }
        if self.software {
            out.push(Traversal::Software);
        }
        out
    }

    fn can_run(&self, traversal: Option<Traversal>) -> bool {
        match traversal {
            Some(Traversal::RayQuery) => self.ray_query,
            _ => self.software,
        }
    }

    fn missing_for(&self, traversal: Option<Traversal>) -> &[String] {
        match traversal {
            Some(Traversal::RayQuery) => &self.missing,
            _ => &self.missing_software,
        }
    }

    /// Reports the device as lacking ray queries (`GpuOptions::hide_ray_query`).
    pub(crate) fn hide_ray_query(&mut self) {
        if self.ray_query {
            self.ray_query = false;
            self.missing
                .push("VK_KHR_ray_query (hidden: --hide-ray-query)".into());
        }
    }
}

fn version_string(v: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(v),
        vk::api_version_minor(v),
        vk::api_version_patch(v)
    )
}

fn type_name(t: vk::PhysicalDeviceType) -> &'static str {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
        vk::PhysicalDeviceType::CPU => "CPU",
        _ => "other",
    }
}

fn type_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// The queue family used for everything: graphics + compute (transfer is implied).
fn queue_family(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<(u32, u32)> {
    // SAFETY: `pd` was enumerated from this instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    families
        .iter()
        .position(|f| {
            f.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        })
        .map(|i| (i as u32, families[i].timestamp_valid_bits))
}

pub(crate) fn report(
    instance: &ash::Instance,
    index: usize,
    pd: vk::PhysicalDevice,
) -> Result<DeviceReport, GpuError> {
    // SAFETY: `pd` was enumerated from this instance; queries only.
    let props = unsafe { instance.get_physical_device_properties(pd) };
    // SAFETY: as above.
    let exts = unsafe { instance.enumerate_device_extension_properties(pd) }
        .map_err(vk_err("vkEnumerateDeviceExtensionProperties"))?;
    let has = |name: &CStr| exts.iter().any(|e| e.extension_name_as_c_str() == Ok(name));

    let mut missing = Vec::new();
    let mut missing_software = Vec::new();
    let api_ok = props.api_version >= vk::API_VERSION_1_2;
    if !api_ok {
        missing_software.push(format!(
            "Vulkan 1.2 (device has {})",
            version_string(props.api_version)
        ));
    }
    for name in DEVICE_EXTENSIONS {
        if !has(name) {
            missing.push(name.to_string_lossy().into_owned());
        }
    }
    let mut driver = String::new();
    if api_ok {
        let mut driver_props = vk::PhysicalDeviceDriverProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver_props);
        // SAFETY: the device supports Vulkan 1.2, where the driver properties are core.
        unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
        driver = format!(
            "{}: {}",
            driver_props
                .driver_name_as_c_str()
                .unwrap_or_default()
                .to_string_lossy(),
            driver_props
                .driver_info_as_c_str()
                .unwrap_or_default()
                .to_string_lossy()
        );

        let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut f_as = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
        let mut f_rq = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
        let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12);
        if has(khr::acceleration_structure::NAME) {
            features = features.push_next(&mut f_as);
        }
        if has(khr::ray_query::NAME) {
            features = features.push_next(&mut f_rq);
        }
        // SAFETY: only structures of supported extensions are chained.
        unsafe { instance.get_physical_device_features2(pd, &mut features) };
        if f12.buffer_device_address == vk::FALSE {
            missing.push("feature bufferDeviceAddress".into());
        }
        if has(khr::acceleration_structure::NAME) && f_as.acceleration_structure == vk::FALSE {
            missing.push("feature accelerationStructure".into());
        }
        if has(khr::ray_query::NAME) && f_rq.ray_query == vk::FALSE {
            missing.push("feature rayQuery".into());
        }
    }
    let family = queue_family(instance, pd);
    if family.is_none() {
        missing_software.push("a graphics + compute queue".into());
    }
    // Ray queries need everything the software traversal needs, first in the list.
    missing.splice(0..0, missing_software.iter().cloned());
    let limits = props.limits;
    Ok(DeviceReport {
        index,
        name: props
            .device_name_as_c_str()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned(),
        device_type: type_name(props.device_type).into(),
        api_version: version_string(props.api_version),
        driver_version: version_string(props.driver_version),
        driver,
        ray_query: missing.is_empty(),
        missing,
        software: missing_software.is_empty(),
        missing_software,
        max_image_dimension_2d: limits.max_image_dimension2_d,
        max_compute_work_group_count: limits.max_compute_work_group_count,
        max_compute_work_group_size: limits.max_compute_work_group_size,
        max_compute_work_group_invocations: limits.max_compute_work_group_invocations,
        max_storage_buffer_range: limits.max_storage_buffer_range,
        timestamp_period_ns: limits.timestamp_period,
        timestamps: limits.timestamp_compute_and_graphics == vk::TRUE
            && family.is_some_and(|(_, bits)| bits > 0),
        vendor_id: props.vendor_id,
        device_id: props.device_id,
        pipeline_cache_uuid: props.pipeline_cache_uuid,
    })
}

pub(crate) fn enumerate(
    instance: &ash::Instance,
) -> Result<Vec<(vk::PhysicalDevice, DeviceReport)>, GpuError> {
    // SAFETY: enumeration on a live instance.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(vk_err("vkEnumeratePhysicalDevices"))?;
    devices
        .into_iter()
        .enumerate()
        .map(|(i, pd)| Ok((pd, report(instance, i, pd)?)))
        .collect()
}

fn describe_missing(reports: &[DeviceReport], traversal: Option<Traversal>) -> String {
    reports
        .iter()
        .map(|r| {
            format!(
                "{}: missing {}",
                r.name,
                r.missing_for(traversal).join(", ")
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// What a device must support for `traversal` (None: either), for error messages.
fn requirement(traversal: Option<Traversal>) -> &'static str {
    match traversal {
        Some(Traversal::RayQuery) => "supports VK_KHR_ray_query",
        _ => "can run lensray (Vulkan 1.2 with a graphics + compute queue)",
    }
}

/// Picks the device: the one asked for, else the best type (discrete first) that can run
/// `traversal` (None: either traversal; ties go to a device with ray queries).
pub(crate) fn select(
    devices: &[(vk::PhysicalDevice, DeviceReport)],
    index: Option<usize>,
    traversal: Option<Traversal>,
) -> Result<(vk::PhysicalDevice, DeviceReport), GpuError> {
    let reports: Vec<DeviceReport> = devices.iter().map(|(_, r)| r.clone()).collect();
    if let Some(index) = index {
        let Some((pd, r)) = devices.get(index) else {
            let names = if reports.is_empty() {
                String::new()
            } else {
                format!(
                    " ({})",
                    reports
                        .iter()
                        .map(|r| format!("{}: {}", r.index, r.name))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            };
            return Err(GpuError::DeviceIndex {
                index,
                count: devices.len(),
                names,
            });
        };
        if !r.can_run(traversal) {
            let what = match traversal {
                Some(Traversal::RayQuery) => "does not support VK_KHR_ray_query",
                _ => "cannot run lensray",
            };
            return Err(GpuError::NoRayQueryDevice(format!(
                "Vulkan device {index} {what} ({}: missing {})",
                r.name,
                r.missing_for(traversal).join(", ")
            )));
        }
        return Ok((*pd, r.clone()));
    }
    if devices.is_empty() {
        return Err(GpuError::NoRayQueryDevice(format!(
            "no Vulkan device {} (no Vulkan device found; install a driver, e.g. Mesa's \
             lavapipe >= 24.1)",
            requirement(traversal)
        )));
    }
    devices
        .iter()
        .filter(|(_, r)| r.can_run(traversal))
        .min_by_key(|(pd, r)| (type_rank(device_type(r)), !r.ray_query, *pd != devices[0].0))
        .map(|(pd, r)| (*pd, r.clone()))
        .ok_or_else(|| {
            GpuError::NoRayQueryDevice(format!(
                "no Vulkan device {} (found: {})",
                requirement(traversal),
                describe_missing(&reports, traversal)
            ))
        })
}

fn device_type(r: &DeviceReport) -> vk::PhysicalDeviceType {
    match r.device_type.as_str() {
        "discrete GPU" => vk::PhysicalDeviceType::DISCRETE_GPU,
        "integrated GPU" => vk::PhysicalDeviceType::INTEGRATED_GPU,
        "virtual GPU" => vk::PhysicalDeviceType::VIRTUAL_GPU,
        "CPU" => vk::PhysicalDeviceType::CPU,
        _ => vk::PhysicalDeviceType::OTHER,
    }
}

/// What the host asked of the device since it was opened: queue submissions, waits that block
/// the host on the device (fences, semaphores), bytes read back from mapped memory and query
/// results, and pipelines made. Counted where those calls are made (`Context`, `Buffer::read`,
/// `QueryPool::results`, the preview's frames, `Pipeline`).
#[derive(Debug, Default)]
pub struct DeviceCounters {
    pub submits: std::sync::atomic::AtomicU64,
    pub cpu_waits: std::sync::atomic::AtomicU64,
    pub readback_bytes: std::sync::atomic::AtomicU64,
    pub pipelines: std::sync::atomic::AtomicU64,
}

/// A snapshot of [`DeviceCounters`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counters {
    pub submits: u64,
    pub cpu_waits: u64,
    pub readback_bytes: u64,
    /// Pipelines made (compute and graphics), each once per device: what a path compiles.
    pub pipelines: u64,
}

impl Counters {
    /// What happened between `earlier` and `self`.
    pub fn since(&self, earlier: &Counters) -> Counters {
        Counters {
            submits: self.submits - earlier.submits,
            cpu_waits: self.cpu_waits - earlier.cpu_waits,
            readback_bytes: self.readback_bytes - earlier.readback_bytes,
            pipelines: self.pipelines - earlier.pipelines,
        }
    }
}

impl DeviceCounters {
    pub fn submitted(&self) {
        self.submits
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub fn waited(&self) {
        self.cpu_waits
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub fn read_back(&self, bytes: u64) {
        self.readback_bytes
            .fetch_add(bytes, std::sync::atomic::Ordering::Relaxed);
    }

    pub fn made_pipeline(&self) {
        self.pipelines
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub fn snapshot(&self) -> Counters {
        use std::sync::atomic::Ordering::Relaxed;
        Counters {
            submits: self.submits.load(Relaxed),
            cpu_waits: self.cpu_waits.load(Relaxed),
            readback_bytes: self.readback_bytes.load(Relaxed),
            pipelines: self.pipelines.load(Relaxed),
        }
    }
}

/// A submission not yet known to be finished: its timeline value, command buffer and fence.
struct Pending {
    value: u64,
    cmd: vk::CommandBuffer,
    /// The host's wait is on the fence (the timeline gives progress): a fence also tells the
    /// driver that the command buffer may be freed after it.
    fence: vk::Fence,
}

/// The logical device and what is created once with it. Destroyed last (everything else holds
/// an `Arc<Context>`), after its allocator and command pool.
pub(crate) struct Context {
    /// Kept alive until the device is destroyed.
    pub instance: Arc<Instance>,
    pub physical_device: vk::PhysicalDevice,
    pub device: ash::Device,
    /// The acceleration-structure functions, when ray queries are enabled.
    pub accel: Option<khr::acceleration_structure::Device>,
    /// The traversals this device was opened for (ray queries enabled or not).
    pub traversals: Vec<Traversal>,
    pub queue: vk::Queue,
    pub command_pool: vk::CommandPool,
    /// Every pipeline is created through it; loaded from and saved to disk
    /// (`pipeline_cache`).
    pub pipeline_cache: vk::PipelineCache,
    pipeline_cache_file: pipeline_cache::CacheFile,
    pub counters: DeviceCounters,
    /// Every `submit` signals the next value of this timeline semaphore.
    timeline: vk::Semaphore,
    /// The last value signalled (or to be) by a submission, and the command buffers of the
    /// submissions not yet known to be finished, with their values.
    submitted: Mutex<(u64, Vec<Pending>)>,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    pub report: DeviceReport,
    pub scratch_alignment: u64,
    timestamp_period_ns: f64,
    timestamps: bool,
    /// The valid bits of a timestamp (`timestampValidBits`).
    timestamp_mask: u64,
}

impl Context {
    /// `surface`: a window the device must present to (adds VK_KHR_swapchain).
    /// With `options.traversal` Software, or a device without (or hiding) ray queries, the
    /// ray-tracing extensions and features are not enabled.
    pub fn new(
        instance: Arc<Instance>,
        options: &GpuOptions,
        surface: Option<&Surface>,
    ) -> Result<Self, GpuError> {
        let mut devices = enumerate(&instance.instance)?;
        if options.hide_ray_query {
            for (_, r) in &mut devices {
                r.hide_ray_query();
            }
        }
        let (physical, report) = select(&devices, options.device_index, options.traversal)?;
        let traversals: Vec<Traversal> = report
            .traversals()
            .into_iter()
            .filter(|t| options.traversal.is_none_or(|wanted| wanted == *t))
            .collect();
        let ray_query = traversals.contains(&Traversal::RayQuery);
        let (queue_family, timestamp_bits) = queue_family(&instance.instance, physical)
            .ok_or_else(|| GpuError::NoRayQueryDevice("no graphics + compute queue".into()))?;
        if let Some(surface) = surface {
            if !surface.supported_by(physical, queue_family)? {
                return Err(GpuError::Invalid(format!(
                    "{} cannot present to this window (its queue family {queue_family} lacks \
                     presentation support)",
                    report.name
                )));
            }
        }

        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut extensions: Vec<_> = Vec::new();
        if ray_query {
            extensions.extend(DEVICE_EXTENSIONS.iter().map(|e| e.as_ptr()));
        }
        if surface.is_some() {
            extensions.push(khr::swapchain::NAME.as_ptr());
        }
        // Device addresses only feed the acceleration-structure builds. Timeline semaphores
        // (core and required in Vulkan 1.2) order and report the submissions (`submit`).
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default()
            .buffer_device_address(ray_query)
            .timeline_semaphore(true);
        let mut f_as = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut f_rq = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12);
        if ray_query {
            features = features.push_next(&mut f_as).push_next(&mut f_rq);
        }
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&extensions)
            .push_next(&mut features);
        // SAFETY: the device was checked to support these extensions and features; all
        // pointers in `info` refer to locals alive during the call.
        let device = unsafe { instance.instance.create_device(physical, &info, None) }
            .map_err(vk_err("vkCreateDevice"))?;
        // SAFETY: the queue family was requested with one queue.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let accel = ray_query
            .then(|| khr::acceleration_structure::Device::new(&instance.instance, &device));

        let mut scratch_alignment = 1;
        if ray_query {
            let mut as_props = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut as_props);
            // SAFETY: the extension is enabled; query only.
            unsafe {
                instance
                    .instance
                    .get_physical_device_properties2(physical, &mut props2)
            };
            scratch_alignment =
                u64::from(as_props.min_acceleration_structure_scratch_offset_alignment).max(1);
        }

        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create-info.
        let command_pool = match unsafe { device.create_command_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(e) => {
                // SAFETY: nothing else was created from the device.
                unsafe { device.destroy_device(None) };
                return Err(vk_err("vkCreateCommandPool")(e));
            }
        };
        let mut timeline_info = vk::SemaphoreTypeCreateInfo::default()
            .semaphore_type(vk::SemaphoreType::TIMELINE)
            .initial_value(0);
        let semaphore_info = vk::SemaphoreCreateInfo::default().push_next(&mut timeline_info);
        // SAFETY: valid device with the timelineSemaphore feature enabled.
        let timeline = match unsafe { device.create_semaphore(&semaphore_info, None) } {
            Ok(s) => s,
            Err(e) => {
                // SAFETY: only the pool was created from the device.
                unsafe {
                    device.destroy_command_pool(command_pool, None);
                    device.destroy_device(None);
                }
                return Err(vk_err("vkCreateSemaphore")(e));
            }
        };
        let pipeline_cache_file = pipeline_cache::load(&report);
        let pipeline_cache = match create_pipeline_cache(&device, &pipeline_cache_file.data) {
            Ok(cache) => cache,
            Err(e) => {
                // SAFETY: only the pool and the timeline were created from the device.
                unsafe {
                    device.destroy_semaphore(timeline, None);
                    device.destroy_command_pool(command_pool, None);
                    device.destroy_device(None);
                }
                return Err(e);
            }
        };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: ray_query,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: only the pool, the timeline and the pipeline cache were created from
                // the device.
                unsafe {
                    device.destroy_pipeline_cache(pipeline_cache, None);
                    device.destroy_semaphore(timeline, None);
                    device.destroy_command_pool(command_pool, None);
                    device.destroy_device(None);
                }
                return Err(alloc_err("the allocator")(e));
            }
        };
        Ok(Self {
            timestamp_period_ns: f64::from(report.timestamp_period_ns),
            timestamps: report.timestamps,
            timestamp_mask: if timestamp_bits >= 64 {
                u64::MAX
            } else {
                (1u64 << timestamp_bits) - 1
            },
            instance,
            physical_device: physical,
            device,
            accel,
            traversals,
            queue,
            command_pool,
            pipeline_cache,
            pipeline_cache_file,
            counters: DeviceCounters::default(),
            timeline,
            submitted: Mutex::new((0, Vec::new())),
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            report,
            scratch_alignment,
        })
    }

    /// The acceleration-structure functions; an error when ray queries are not enabled.
    pub fn accel(&self) -> Result<&khr::acceleration_structure::Device, GpuError> {
        self.accel
            .as_ref()
            .ok_or_else(|| GpuError::Invalid("ray queries are not enabled on this device".into()))
    }

    /// Creates a sampler and forgets it: a deliberate leak for the tests of the leak report.
    #[cfg(feature = "probes")]
    pub fn leak_sampler(&self) -> Result<(), GpuError> {
        let info = vk::SamplerCreateInfo::default();
        // SAFETY: valid create-info on a live device; the handle is dropped on purpose.
        unsafe { self.device.create_sampler(&info, None) }
            .map(|_| ())
            .map_err(vk_err("vkCreateSampler"))
    }

    /// Nanoseconds between two timestamps of this queue (0 without timestamp support).
    pub fn elapsed_ns(&self, start: u64, end: u64) -> f64 {
        if !self.timestamps {
            return 0.0;
        }
        (end.wrapping_sub(start) & self.timestamp_mask) as f64 * self.timestamp_period_ns
    }

    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Records `record` into a fresh command buffer, submits it, waits for it to finish.
    pub fn submit_and_wait(
        &self,
        record: impl FnOnce(vk::CommandBuffer) -> Result<(), GpuError>,
    ) -> Result<(), GpuError> {
        let value = self.submit(record)?;
        self.wait_until(value)
    }

    /// Records `record` into a fresh command buffer and submits it without waiting: it
    /// signals the returned value of the device's timeline when it finishes (`completed`,
    /// `wait_until`). Submissions run in order on the one queue; a later one orders itself
    /// after earlier ones with barriers as usual.
    pub fn submit(
        &self,
        record: impl FnOnce(vk::CommandBuffer) -> Result<(), GpuError>,
    ) -> Result<u64, GpuError> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let mut submitted = self.submitted.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: the pool belongs to this device; its users are serialized by the lock.
        let cmd = unsafe { self.device.allocate_command_buffers(&info) }
            .map_err(vk_err("vkAllocateCommandBuffers"))?[0];
        let value = submitted.0 + 1;
        // SAFETY: valid device.
        let fence = match unsafe {
            self.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        } {
            Ok(fence) => fence,
            Err(e) => {
                // SAFETY: never submitted: the buffer is not in use.
                unsafe { self.device.free_command_buffers(self.command_pool, &[cmd]) };
                return Err(vk_err("vkCreateFence")(e));
            }
        };
        match self.record_and_submit(cmd, value, fence, record) {
            Ok(()) => {
                submitted.0 = value;
                submitted.1.push(Pending { value, cmd, fence });
                Ok(value)
            }
            Err(e) => {
                // SAFETY: the submission never started: the buffer and fence are not in use.
                unsafe {
                    self.device.free_command_buffers(self.command_pool, &[cmd]);
                    self.device.destroy_fence(fence, None);
                }
                Err(e)
            }
        }
    }

    fn record_and_submit(
        &self,
        cmd: vk::CommandBuffer,
        value: u64,
        fence: vk::Fence,
        record: impl FnOnce(vk::CommandBuffer) -> Result<(), GpuError>,
    ) -> Result<(), GpuError> {
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: fresh command buffer from our pool.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }
            .map_err(vk_err("vkBeginCommandBuffer"))?;
        record(cmd)?;
        // SAFETY: recording began above.
        unsafe { self.device.end_command_buffer(cmd) }.map_err(vk_err("vkEndCommandBuffer"))?;
        let cmds = [cmd];
        let signals = [self.timeline];
        let values = [value];
        let mut timeline =
            vk::TimelineSemaphoreSubmitInfo::default().signal_semaphore_values(&values);
        let submit = vk::SubmitInfo::default()
            .command_buffers(&cmds)
            .signal_semaphores(&signals)
            .push_next(&mut timeline);
        // SAFETY: the command buffer is fully recorded; the timeline value is above every
        // value signalled before; the fence is new and unsignalled.
        unsafe { self.device.queue_submit(self.queue, &[submit], fence) }
            .map_err(vk_err("vkQueueSubmit"))?;
        self.counters.submitted();
        Ok(())
    }

    /// Waits until every submission so far finished (none pending: no wait).
    pub fn wait_all(&self) -> Result<(), GpuError> {
        let last = self.submitted.lock().unwrap_or_else(|p| p.into_inner()).0;
        if last > self.completed()? {
            self.wait_until(last)?;
        }
        Ok(())
    }

    /// The timeline value of the last submission (0 before any).
    pub fn last_submitted(&self) -> u64 {
        self.submitted.lock().unwrap_or_else(|p| p.into_inner()).0
    }

    /// The last timeline value the device finished, without waiting (progress).
    pub fn completed(&self) -> Result<u64, GpuError> {
        // SAFETY: our own timeline semaphore.
        unsafe { self.device.get_semaphore_counter_value(self.timeline) }
            .map_err(vk_err("vkGetSemaphoreCounterValue"))
    }

    /// Waits until the submission that signals `value` and every earlier one finished (their
    /// fences), then frees their command buffers and fences.
    pub fn wait_until(&self, value: u64) -> Result<(), GpuError> {
        let mut submitted = self.submitted.lock().unwrap_or_else(|p| p.into_inner());
        let (done, pending): (Vec<Pending>, Vec<Pending>) =
            submitted.1.drain(..).partition(|p| p.value <= value);
        submitted.1 = pending;
        if done.is_empty() {
            return Ok(());
        }
        let fences: Vec<vk::Fence> = done.iter().map(|p| p.fence).collect();
        self.counters.waited();
        // SAFETY: our own fences, each of a submission.
        let waited = unsafe { self.device.wait_for_fences(&fences, true, u64::MAX) }
            .map_err(vk_err("vkWaitForFences"));
        let cmds: Vec<vk::CommandBuffer> = done.iter().map(|p| p.cmd).collect();
        // SAFETY: those submissions finished (or the device is lost): nothing uses the buffers
        // and fences.
        unsafe {
            if waited.is_ok() {
                self.device.free_command_buffers(self.command_pool, &cmds);
            }
            for fence in fences {
                self.device.destroy_fence(fence, None);
            }
        }
        waited
    }
}

/// The device's pipeline cache, from `data` when the driver takes it (checked against the
/// device first, `pipeline_cache::load`), else empty.
fn create_pipeline_cache(device: &ash::Device, data: &[u8]) -> Result<vk::PipelineCache, GpuError> {
    let info = vk::PipelineCacheCreateInfo::default().initial_data(data);
    // SAFETY: valid device; `data` is empty or has this device's cache header.
    match unsafe { device.create_pipeline_cache(&info, None) } {
        Ok(cache) => Ok(cache),
        Err(_) if !data.is_empty() => {
            eprintln!("notice: the driver refused the saved pipeline cache; compiling afresh");
            create_pipeline_cache(device, &[])
        }
        Err(e) => Err(vk_err("vkCreatePipelineCache")(e)),
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every object created from the device holds an `Arc<Context>` and is gone; the
        // device is idle after the wait; the allocator frees its memory blocks before the
        // device is destroyed.
        unsafe {
            let _ = self.device.device_wait_idle();
            if let Ok(data) = self.device.get_pipeline_cache_data(self.pipeline_cache) {
                pipeline_cache::save(&self.pipeline_cache_file, &data);
            }
            self.device
                .destroy_pipeline_cache(self.pipeline_cache, None);
            // The pending command buffers go with their pool; their fences go here.
            let submitted = self.submitted.get_mut().unwrap_or_else(|p| p.into_inner());
            for pending in submitted.1.drain(..) {
                self.device.destroy_fence(pending.fence, None);
            }
            self.device.destroy_semaphore(self.timeline, None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_device(None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fake(
        index: usize,
        name: &str,
        ty: &str,
        missing: &[&str],
    ) -> (vk::PhysicalDevice, DeviceReport) {
        (
            vk::Handle::from_raw(index as u64 + 1),
            DeviceReport {
                index,
                name: name.into(),
                device_type: ty.into(),
                api_version: "1.3.0".into(),
                driver_version: "0.0.1".into(),
                driver: String::new(),
                ray_query: missing.is_empty(),
                missing: missing.iter().map(|m| m.to_string()).collect(),
                software: !missing.iter().any(|m| m.starts_with("Vulkan 1.2")),
                missing_software: missing
                    .iter()
                    .filter(|m| m.starts_with("Vulkan 1.2"))
                    .map(|m| m.to_string())
                    .collect(),
                max_image_dimension_2d: 16384,
                max_compute_work_group_count: [65535; 3],
                max_compute_work_group_size: [1024; 3],
                max_compute_work_group_invocations: 1024,
                max_storage_buffer_range: 1 << 27,
                timestamp_period_ns: 1.0,
                timestamps: true,
                vendor_id: 0,
                device_id: index as u32,
                pipeline_cache_uuid: [index as u8; 16],
            },
        )
    }

    #[test]
    fn prefers_a_discrete_gpu_with_ray_queries() {
        let devices = [
            fake(0, "llvmpipe", "CPU", &[]),
            fake(1, "old", "discrete GPU", &["VK_KHR_ray_query"]),
            fake(2, "igpu", "integrated GPU", &[]),
            fake(3, "dgpu", "discrete GPU", &[]),
        ];
        let rq = Some(Traversal::RayQuery);
        assert_eq!(select(&devices, None, rq).unwrap().1.name, "dgpu");
        assert_eq!(select(&devices[..3], None, rq).unwrap().1.name, "igpu");
        assert_eq!(select(&devices, Some(0), rq).unwrap().1.name, "llvmpipe");
        // Either traversal: discrete first, ray queries breaking the tie.
        assert_eq!(select(&devices, None, None).unwrap().1.name, "dgpu");
        assert_eq!(select(&devices[..3], None, None).unwrap().1.name, "old");
        assert_eq!(
            select(&devices[..3], None, Some(Traversal::Software))
                .unwrap()
                .1
                .name,
            "old"
        );
        assert_eq!(select(&devices, Some(1), None).unwrap().1.name, "old");
        assert!(select(&devices, Some(1), rq).is_err());
    }

    #[test]
    fn software_needs_no_ray_queries() {
        let mut d = fake(0, "old", "discrete GPU", &["VK_KHR_ray_query"]).1;
        assert_eq!(d.traversals(), vec![Traversal::Software]);
        let mut full = fake(1, "new", "CPU", &[]).1;
        assert_eq!(
            full.traversals(),
            vec![Traversal::RayQuery, Traversal::Software]
        );
        full.hide_ray_query();
        assert_eq!(full.traversals(), vec![Traversal::Software]);
        assert!(full.missing.iter().any(|m| m.contains("hidden")));
        d.software = false;
        d.missing_software = vec!["Vulkan 1.2 (device has 1.1.0)".into()];
        let devices = [(vk::Handle::from_raw(1), d)];
        let text = select(&devices, None, None).unwrap_err().to_string();
        assert_eq!(
            text,
            "no Vulkan device can run lensray (Vulkan 1.2 with a graphics + compute queue) \
             (found: old: missing Vulkan 1.2 (device has 1.1.0))"
        );
    }

    #[test]
    fn errors_name_what_is_missing() {
        let devices = [fake(
            0,
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            "CPU",
            &["VK_KHR_acceleration_structure", "VK_KHR_ray_query"],
        )];
        let text = select(&devices, None, Some(Traversal::RayQuery))
            .unwrap_err()
            .to_string();
        assert_eq!(
            text,
            "no Vulkan device supports VK_KHR_ray_query (found: llvmpipe (LLVM 15.0.6, 256 \
             bits): missing VK_KHR_acceleration_structure, VK_KHR_ray_query)"
        );
        let text = select(&devices, Some(0), Some(Traversal::RayQuery))
            .unwrap_err()
            .to_string();
        assert!(
            text.contains("device 0") && text.contains("missing"),
            "{text}"
        );
        let text = select(&devices, Some(5), None).unwrap_err().to_string();
        assert!(
            text.contains("index 5") && text.contains("1 device(s)"),
            "{text}"
        );
        let text = select(&[], None, None).unwrap_err().to_string();
        assert!(text.contains("no Vulkan device found"), "{text}");
    }
}
