//! The logical device with its queue, allocator and command pool (the [`Context`] every GPU
//! object holds an `Arc` to), and its submissions on one timeline.

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::{khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::core::adapter::{enumerate, queue_family, select, DeviceReport};
use crate::core::counters::DeviceCounters;
use crate::core::error::{alloc_err, vk_err, GpuError};
use crate::core::features::{accel_scratch_alignment, create_device, RayTracingUse};
use crate::core::instance::Instance;
use crate::core::pipeline_cache;
use crate::core::recorder::Recorder;
use crate::core::sbt::RayTracing;
use crate::core::surface::WindowSurface;
use crate::core::sync::{CommandBuffer, Fence, Semaphore};
use crate::traversal::Traversal;
use crate::GpuOptions;

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
    /// The acceleration-structure functions, when ray queries or the ray-tracing pipeline are
    /// enabled.
    pub accel: Option<khr::acceleration_structure::Device>,
    /// The ray-tracing pipeline's functions and properties, when it is enabled.
    pub ray_tracing: Option<RayTracing>,
    /// The traversals this device was opened for (`DeviceReport::opened_traversals`).
    pub traversals: Vec<Traversal>,
    pub queue: vk::Queue,
    pub command_pool: vk::CommandPool,
    /// Every pipeline is created through it; loaded from and saved to disk
    /// (`pipeline_cache`).
    pub pipeline_cache: vk::PipelineCache,
    pipeline_cache_file: pipeline_cache::PipelineCacheFile,
    /// Whether to say, once, that the driver compiles the shaders: this device and driver have
    /// no pipeline cache file yet (their first use), and the caller wants notices.
    announce_compile: std::sync::Once,
    first_use_notice: bool,
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
    /// The ray-tracing extensions and features are enabled for the traversals the device is
    /// opened for (`DeviceReport::opened_traversals`): none for `options.traversal` Software.
    pub(crate) fn new(
        instance: Arc<Instance>,
        options: &GpuOptions,
        surface: Option<&WindowSurface>,
    ) -> Result<Self, GpuError> {
        let adapter = pick_adapter(&instance.instance, options, surface)?;
        let uses = RayTracingUse::of(&adapter.traversals);
        let (physical, family) = (adapter.physical, adapter.queue_family);
        let device = create_device(
            &instance.instance,
            (physical, family),
            uses,
            surface.is_some(),
        )?;
        // SAFETY: the queue family was requested with one queue.
        let queue = unsafe { device.get_device_queue(adapter.queue_family, 0) };
        let accel = uses
            .accel()
            .then(|| khr::acceleration_structure::Device::new(&instance.instance, &device));
        let ray_tracing = uses
            .rt_pipeline
            .then(|| RayTracing::load(&instance.instance, physical, &device));
        let mut scratch_alignment = 1;
        if uses.accel() {
            scratch_alignment = accel_scratch_alignment(&instance.instance, adapter.physical);
        }
        let objects = create_objects(&instance.instance, &device, &adapter, uses.accel())?;
        let Adapter {
            physical,
            report,
            traversals,
            timestamp_bits,
            ..
        } = adapter;
        let first_use_notice =
            options.first_use_notice && objects.pipeline_cache_file.is_first_use();
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
            ray_tracing,
            traversals,
            queue,
            command_pool: objects.command_pool,
            pipeline_cache: objects.pipeline_cache,
            pipeline_cache_file: objects.pipeline_cache_file,
            announce_compile: std::sync::Once::new(),
            first_use_notice,
            counters: DeviceCounters::default(),
            timeline: objects.timeline,
            submitted: Mutex::new((0, Vec::new())),
            allocator: ManuallyDrop::new(Mutex::new(objects.allocator)),
            report,
            scratch_alignment,
        })
    }

    /// The acceleration-structure functions; an error when no traversal of the driver's is
    /// enabled.
    pub(crate) fn accel(&self) -> Result<&khr::acceleration_structure::Device, GpuError> {
        self.accel.as_ref().ok_or_else(|| {
            GpuError::Invalid("acceleration structures are not enabled on this device".into())
        })
    }

    /// The ray-tracing pipeline's functions; an error when it is not enabled.
    pub(crate) fn ray_tracing(&self) -> Result<&RayTracing, GpuError> {
        self.ray_tracing.as_ref().ok_or_else(|| {
            GpuError::Invalid("the ray-tracing pipeline is not enabled on this device".into())
        })
    }

    /// Creates a sampler and forgets it: a deliberate leak for the tests of the leak report.
    #[cfg(feature = "probes")]
    pub(crate) fn leak_sampler(&self) -> Result<(), GpuError> {
        let info = vk::SamplerCreateInfo::default();
        // SAFETY: valid create-info on a live device; the handle is dropped on purpose.
        unsafe { self.device.create_sampler(&info, None) }
            .map(|_| ())
            .map_err(vk_err("vkCreateSampler"))
    }

    /// The physical device's limits.
    #[cfg(feature = "probes")]
    pub(crate) fn limits(&self) -> vk::PhysicalDeviceLimits {
        // SAFETY: the physical device was enumerated from this instance; a query only.
        unsafe {
            self.instance
                .instance
                .get_physical_device_properties(self.physical_device)
        }
        .limits
    }

    /// Before the first pipeline of a device's first use: one line saying that the driver
    /// compiles the shaders now (on lavapipe for half a minute) and caches them for later runs.
    pub(crate) fn announce_compile(&self) {
        if self.first_use_notice {
            self.announce_compile.call_once(|| {
                eprintln!(
                    "compiling shaders for {} (first use; cached after)",
                    self.report.name
                );
            });
        }
    }

    /// Nanoseconds between two timestamps of this queue (0 without timestamp support).
    pub(crate) fn elapsed_ns(&self, start: u64, end: u64) -> f64 {
        if !self.timestamps {
            return 0.0;
        }
        (end.wrapping_sub(start) & self.timestamp_mask) as f64 * self.timestamp_period_ns
    }

    pub(crate) fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Records `record` into a fresh command buffer, submits it, waits for it to finish.
    pub(crate) fn submit_and_wait(
        &self,
        record: impl FnOnce(&mut Recorder<'_>) -> Result<(), GpuError>,
    ) -> Result<(), GpuError> {
        let value = self.submit(record)?;
        self.wait_until(value)
    }

    /// Records `record` into a fresh command buffer and submits it without waiting: it
    /// signals the returned value of the device's timeline when it finishes (`completed`,
    /// `wait_until`). Submissions run in order on the one queue; a later one orders itself
    /// after earlier ones with barriers as usual.
    pub(crate) fn submit(
        &self,
        record: impl FnOnce(&mut Recorder<'_>) -> Result<(), GpuError>,
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
        record: impl FnOnce(&mut Recorder<'_>) -> Result<(), GpuError>,
    ) -> Result<(), GpuError> {
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: fresh command buffer from our pool.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }
            .map_err(vk_err("vkBeginCommandBuffer"))?;
        record(&mut Recorder::new(self, cmd))?;
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

    /// Submits a frame's recorded `cmd`, its commands from `wait.1` on waiting for `wait.0` (the
    /// window image's acquire); it signals `signal` (the image's present waits on it) and
    /// `fence` when it finishes. Outside the timeline of `submit`: the frame's fence tells when.
    pub(crate) fn submit_frame(
        &self,
        cmd: &CommandBuffer,
        wait: (&Semaphore, vk::PipelineStageFlags),
        signal: &Semaphore,
        fence: &Fence,
    ) -> Result<(), GpuError> {
        let waits = [wait.0.handle];
        let wait_stages = [wait.1];
        let cmds = [cmd.handle];
        let signals = [signal.handle];
        let submit = vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&wait_stages)
            .command_buffers(&cmds)
            .signal_semaphores(&signals);
        // SAFETY: the command buffer is recorded; the semaphores and fence are the slot's and
        // the image's, unsignalled and not waited on by anything pending.
        unsafe {
            self.device
                .queue_submit(self.queue, &[submit], fence.handle)
        }
        .map_err(vk_err("vkQueueSubmit"))?;
        self.counters.submitted();
        Ok(())
    }

    /// Waits until the device is idle: on rare events only (resize, screenshot, exit).
    pub(crate) fn wait_idle(&self) -> Result<(), GpuError> {
        // SAFETY: a live device; its queue's submissions come from the caller's thread.
        unsafe { self.device.device_wait_idle() }.map_err(vk_err("vkDeviceWaitIdle"))
    }

    /// Waits until every submission so far finished (none pending: no wait).
    pub(crate) fn wait_all(&self) -> Result<(), GpuError> {
        let last = self.submitted.lock().unwrap_or_else(|p| p.into_inner()).0;
        if last > self.completed()? {
            self.wait_until(last)?;
        }
        Ok(())
    }

    /// The timeline value of the last submission (0 before any).
    pub(crate) fn last_submitted(&self) -> u64 {
        self.submitted.lock().unwrap_or_else(|p| p.into_inner()).0
    }

    /// The last timeline value the device finished, without waiting (progress).
    pub(crate) fn completed(&self) -> Result<u64, GpuError> {
        // SAFETY: our own timeline semaphore.
        unsafe { self.device.get_semaphore_counter_value(self.timeline) }
            .map_err(vk_err("vkGetSemaphoreCounterValue"))
    }

    /// Waits until the submission that signals `value` and every earlier one finished (their
    /// fences), then frees their command buffers and fences.
    pub(crate) fn wait_until(&self, value: u64) -> Result<(), GpuError> {
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

/// The device `Context::new` opens: the selected physical device and its report, the
/// traversals it is opened for, and the queue family everything runs on.
struct Adapter {
    physical: vk::PhysicalDevice,
    report: DeviceReport,
    traversals: Vec<Traversal>,
    queue_family: u32,
    /// The valid bits of the queue family's timestamps (`timestampValidBits`).
    timestamp_bits: u32,
}

/// Picks the device to open (ray queries hidden when `options` asks), the traversals to open
/// it for and its queue family; an error when that family cannot present to `surface`.
fn pick_adapter(
    instance: &ash::Instance,
    options: &GpuOptions,
    surface: Option<&WindowSurface>,
) -> Result<Adapter, GpuError> {
    let mut devices = enumerate(instance)?;
    if options.hide_ray_query {
        for (_, r) in &mut devices {
            r.hide_ray_query();
        }
    }
    let (physical, report) = select(&devices, options.device_index, options.traversal)?;
    let traversals = report.opened_traversals(options.traversal);
    let (queue_family, timestamp_bits) = queue_family(instance, physical)
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
    Ok(Adapter {
        physical,
        report,
        traversals,
        queue_family,
        timestamp_bits,
    })
}

/// What is created once with the logical device, after its queue.
struct DeviceObjects {
    command_pool: vk::CommandPool,
    timeline: vk::Semaphore,
    pipeline_cache_file: pipeline_cache::PipelineCacheFile,
    pipeline_cache: vk::PipelineCache,
    allocator: Allocator,
}

/// Creates the command pool, the submissions' timeline, the pipeline cache (from its file) and
/// the allocator of `device`; on an error, destroys what it created and the device.
fn create_objects(
    instance: &ash::Instance,
    device: &ash::Device,
    adapter: &Adapter,
    device_addresses: bool,
) -> Result<DeviceObjects, GpuError> {
    let command_pool = match create_command_pool(device, adapter.queue_family) {
        Ok(p) => p,
        Err(e) => {
            // SAFETY: nothing else was created from the device.
            unsafe { device.destroy_device(None) };
            return Err(e);
        }
    };
    let timeline = match create_timeline(device) {
        Ok(s) => s,
        Err(e) => {
            // SAFETY: only the pool was created from the device.
            unsafe {
                device.destroy_command_pool(command_pool, None);
                device.destroy_device(None);
            }
            return Err(e);
        }
    };
    let pipeline_cache_file =
        pipeline_cache::load(&adapter.report, crate::core::shader::shaders_hash());
    let pipeline_cache = match create_pipeline_cache(device, &pipeline_cache_file.data) {
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
        instance: instance.clone(),
        device: device.clone(),
        physical_device: adapter.physical,
        debug_settings: Default::default(),
        buffer_device_address: device_addresses,
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
    Ok(DeviceObjects {
        command_pool,
        timeline,
        pipeline_cache_file,
        pipeline_cache,
        allocator,
    })
}

/// The command pool of the submissions, on `queue_family`; its buffers can be reset.
fn create_command_pool(
    device: &ash::Device,
    queue_family: u32,
) -> Result<vk::CommandPool, GpuError> {
    let pool_info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(queue_family)
        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
    // SAFETY: valid device and create-info.
    unsafe { device.create_command_pool(&pool_info, None) }.map_err(vk_err("vkCreateCommandPool"))
}

/// The timeline semaphore every submission signals, starting at 0.
fn create_timeline(device: &ash::Device) -> Result<vk::Semaphore, GpuError> {
    let mut timeline_info = vk::SemaphoreTypeCreateInfo::default()
        .semaphore_type(vk::SemaphoreType::TIMELINE)
        .initial_value(0);
    let semaphore_info = vk::SemaphoreCreateInfo::default().push_next(&mut timeline_info);
    // SAFETY: valid device with the timelineSemaphore feature enabled.
    unsafe { device.create_semaphore(&semaphore_info, None) }.map_err(vk_err("vkCreateSemaphore"))
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
