//! Physical device reports and selection: what each Vulkan device supports for lensray, and
//! which one a renderer opens.

use std::ffi::CStr;

use ash::{khr, vk};

use crate::core::error::{vk_err, GpuError};
use crate::traversal::Traversal;

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
    /// Whether it can run the ray-tracing pipeline's traversal (VK_KHR_ray_tracing_pipeline
    /// over the same acceleration structures).
    pub rt_pipeline: bool,
    /// What is missing for the ray-tracing pipeline; empty when `rt_pipeline`.
    pub missing_rt_pipeline: Vec<String>,
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
    /// The largest memory allocation the driver is sure to make (maxMemoryAllocationSize; 2 GiB
    /// on lavapipe, whose larger ones crash in its copies).
    pub max_memory_allocation_size: u64,
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

/// The extensions of the ray-tracing pipeline's traversal.
pub(crate) const RT_PIPELINE_EXTENSIONS: [&CStr; 3] = [
    khr::acceleration_structure::NAME,
    khr::ray_tracing_pipeline::NAME,
    khr::deferred_host_operations::NAME,
];

impl DeviceReport {
    /// Whether the device is a CPU implementation of Vulkan (VK_PHYSICAL_DEVICE_TYPE_CPU, as
    /// lavapipe): it runs on the cores the CPU reference renders with.
    pub fn is_cpu(&self) -> bool {
        self.device_type == type_name(vk::PhysicalDeviceType::CPU)
    }

    /// The traversals this device can run, the driver's first: ray queries, the ray-tracing
    /// pipeline, then the software traversal.
    pub fn traversals(&self) -> Vec<Traversal> {
        let mut out = Vec::new();
        if self.ray_query {
            out.push(Traversal::RayQuery);
        }
        if self.rt_pipeline {
            out.push(Traversal::RtPipeline);
        }
        if self.software {
            out.push(Traversal::Software);
        }
        out
    }

    /// The traversals a device opened for `wanted` (`None`: its best) runs: the one wanted,
    /// else every one it can run but the ray-tracing pipeline where ray queries serve (they
    /// trace from the same compute pass as the other traversals, and a second pipeline of the
    /// driver's would be compiled for nothing).
    pub fn opened_traversals(&self, wanted: Option<Traversal>) -> Vec<Traversal> {
        self.traversals()
            .into_iter()
            .filter(|&t| match wanted {
                Some(wanted) => wanted == t,
                None => t != Traversal::RtPipeline || !self.ray_query,
            })
            .collect()
    }

    fn can_run(&self, traversal: Option<Traversal>) -> bool {
        match traversal {
            Some(Traversal::RayQuery) => self.ray_query,
            Some(Traversal::RtPipeline) => self.rt_pipeline,
            _ => self.software,
        }
    }

    fn missing_for(&self, traversal: Option<Traversal>) -> &[String] {
        match traversal {
            Some(Traversal::RayQuery) => &self.missing,
            Some(Traversal::RtPipeline) => &self.missing_rt_pipeline,
            _ => &self.missing_software,
        }
    }

    /// Reports the device as lacking ray queries and the ray-tracing pipeline
    /// (`GpuOptions::hide_ray_query`): a device without ray-tracing support, which traces with
    /// the software traversal.
    pub(crate) fn hide_ray_query(&mut self) {
        if self.ray_query {
            self.ray_query = false;
            self.missing
                .push("VK_KHR_ray_query (hidden: --hide-ray-query)".into());
        }
        if self.rt_pipeline {
            self.rt_pipeline = false;
            self.missing_rt_pipeline
                .push("VK_KHR_ray_tracing_pipeline (hidden: --hide-ray-query)".into());
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
pub(crate) fn queue_family(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<(u32, u32)> {
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
    let mut missing_rt_pipeline = Vec::new();
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
    for name in RT_PIPELINE_EXTENSIONS {
        if !has(name) {
            missing_rt_pipeline.push(name.to_string_lossy().into_owned());
        }
    }
    let mut driver = String::new();
    let mut maintenance3 = vk::PhysicalDeviceMaintenance3Properties::default();
    if api_ok {
        let mut driver_props = vk::PhysicalDeviceDriverProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default()
            .push_next(&mut driver_props)
            .push_next(&mut maintenance3);
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

        let (rq, rtp) = missing_features(instance, pd, &has);
        missing.extend(rq);
        missing_rt_pipeline.extend(rtp);
    }
    let family = queue_family(instance, pd);
    if family.is_none() {
        missing_software.push("a graphics + compute queue".into());
    }
    // Ray queries need everything the software traversal needs, first in the list.
    missing.splice(0..0, missing_software.iter().cloned());
    missing_rt_pipeline.splice(0..0, missing_software.iter().cloned());
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
        rt_pipeline: missing_rt_pipeline.is_empty(),
        missing_rt_pipeline,
        software: missing_software.is_empty(),
        missing_software,
        max_image_dimension_2d: limits.max_image_dimension2_d,
        max_compute_work_group_count: limits.max_compute_work_group_count,
        max_compute_work_group_size: limits.max_compute_work_group_size,
        max_compute_work_group_invocations: limits.max_compute_work_group_invocations,
        max_storage_buffer_range: limits.max_storage_buffer_range,
        max_memory_allocation_size: maintenance3.max_memory_allocation_size,
        timestamp_period_ns: limits.timestamp_period,
        timestamps: limits.timestamp_compute_and_graphics == vk::TRUE
            && family.is_some_and(|(_, bits)| bits > 0),
        vendor_id: props.vendor_id,
        device_id: props.device_id,
        pipeline_cache_uuid: props.pipeline_cache_uuid,
    })
}

/// The features that `pd` (Vulkan 1.2) lacks for ray queries and for the ray-tracing pipeline,
/// of those its extensions (`has`) bring: each list with the acceleration structures' first.
fn missing_features(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    has: &dyn Fn(&CStr) -> bool,
) -> (Vec<String>, Vec<String>) {
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut f_as = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut f_rq = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut f_rtp = vk::PhysicalDeviceRayTracingPipelineFeaturesKHR::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12);
    if has(khr::acceleration_structure::NAME) {
        features = features.push_next(&mut f_as);
    }
    if has(khr::ray_query::NAME) {
        features = features.push_next(&mut f_rq);
    }
    if has(khr::ray_tracing_pipeline::NAME) {
        features = features.push_next(&mut f_rtp);
    }
    // SAFETY: only structures of supported extensions are chained.
    unsafe { instance.get_physical_device_features2(pd, &mut features) };
    let mut accel = Vec::new();
    if f12.buffer_device_address == vk::FALSE {
        accel.push("feature bufferDeviceAddress".to_string());
    }
    if has(khr::acceleration_structure::NAME) && f_as.acceleration_structure == vk::FALSE {
        accel.push("feature accelerationStructure".into());
    }
    let mut rtp = accel.clone();
    let mut rq = accel;
    if has(khr::ray_query::NAME) && f_rq.ray_query == vk::FALSE {
        rq.push("feature rayQuery".into());
    }
    if has(khr::ray_tracing_pipeline::NAME) && f_rtp.ray_tracing_pipeline == vk::FALSE {
        rtp.push("feature rayTracingPipeline".into());
    }
    (rq, rtp)
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
        Some(Traversal::RtPipeline) => "supports VK_KHR_ray_tracing_pipeline",
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
                Some(Traversal::RtPipeline) => "does not support VK_KHR_ray_tracing_pipeline",
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
                rt_pipeline: false,
                missing_rt_pipeline: vec!["VK_KHR_ray_tracing_pipeline".into()],
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
                max_memory_allocation_size: 1 << 31,
                timestamp_period_ns: 1.0,
                timestamps: true,
                vendor_id: 0,
                device_id: index as u32,
                pipeline_cache_uuid: [index as u8; 16],
            },
        )
    }

    #[test]
    fn the_rt_pipeline_is_opened_where_ray_queries_are_absent_or_when_asked_for() {
        let mut both = fake(0, "both", "discrete GPU", &[]).1;
        both.rt_pipeline = true;
        both.missing_rt_pipeline.clear();
        let all = [
            Traversal::RayQuery,
            Traversal::RtPipeline,
            Traversal::Software,
        ];
        assert_eq!(both.traversals(), all);
        assert_eq!(
            both.opened_traversals(None),
            [Traversal::RayQuery, Traversal::Software]
        );
        let rt = Some(Traversal::RtPipeline);
        assert_eq!(both.opened_traversals(rt), [Traversal::RtPipeline]);
        // A GPU with the pipeline but no ray queries traces with the pipeline first.
        let mut pipeline_only = both.clone();
        pipeline_only.ray_query = false;
        pipeline_only.missing.push("VK_KHR_ray_query".into());
        assert_eq!(
            pipeline_only.opened_traversals(None),
            [Traversal::RtPipeline, Traversal::Software]
        );
        let devices = [(vk::Handle::from_raw(1), pipeline_only.clone())];
        assert_eq!(select(&devices, None, rt).unwrap().1.name, "both");
        let text = select(&devices, None, Some(Traversal::RayQuery))
            .err()
            .unwrap()
            .to_string();
        assert!(text.contains("VK_KHR_ray_query"), "{text}");
        both.hide_ray_query();
        assert_eq!(both.opened_traversals(None), [Traversal::Software]);
        assert!(both.opened_traversals(rt).is_empty());
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
