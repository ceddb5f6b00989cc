//! The Vulkan instance and, when validation is on, the Khronos validation layer with
//! synchronization validation and a debug-utils messenger that records warnings and errors.

use std::ffi::{c_char, c_void, CStr};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use ash::{ext, vk};

use crate::core::error::{loader_err, vk_err, GpuError};

pub(crate) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Warnings and errors reported by the validation layer (and the loader), newest last.
/// Cloning shares the log: keep a clone to check messages after the renderer is dropped (the
/// layer reports leaked objects when the device and instance are destroyed).
#[derive(Clone, Debug, Default)]
pub struct ValidationLog {
    messages: Arc<Mutex<Vec<String>>>,
    instance_destroyed: Arc<AtomicBool>,
}

impl ValidationLog {
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    /// True once the instance was destroyed, i.e. every object of the renderer was dropped
    /// (each holds an `Arc` to the device, which holds the instance). A leaked Rust value would
    /// keep the device alive, hiding its objects from the layer's leak report: tests check this.
    pub fn instance_destroyed(&self) -> bool {
        self.instance_destroyed.load(Ordering::SeqCst)
    }

    fn push(&self, message: String) {
        if let Ok(mut m) = self.messages.lock() {
            m.push(message);
        }
    }
}

/// Owns the instance and the messenger; destroys them in order on drop.
pub(crate) struct Instance {
    /// The loaded Vulkan library: dropped (unloaded) after the instance is destroyed.
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    debug: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// The messenger callbacks receive a pointer to this box: it must outlive the instance.
    _log_box: Box<ValidationLog>,
    pub log: ValidationLog,
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data for the duration of the call, and `user` is
    // the `ValidationLog` box owned by `Instance`, which outlives the instance and messenger.
    unsafe {
        if data.is_null() || user.is_null() {
            return vk::FALSE;
        }
        let message = (*data)
            .message_as_c_str()
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default();
        let level = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            "ERROR"
        } else {
            "WARNING"
        };
        let text = format!("[{level} {kind:?}] {message}");
        eprintln!("vulkan: {text}");
        (*(user as *const ValidationLog)).push(text);
    }
    vk::FALSE
}

fn messenger_info(log: &ValidationLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        // INFO and VERBOSE (loader chatter) are filtered out here, never delivered.
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(debug_callback))
        .user_data(log as *const ValidationLog as *mut c_void)
}

impl Instance {
    /// `window_extensions`: what a window surface needs (`ash_window`), empty when headless.
    pub(crate) fn new(
        validation: bool,
        window_extensions: &[*const c_char],
    ) -> Result<Self, GpuError> {
        // SAFETY: loading the system Vulkan loader runs its initialisation code; nothing else
        // in this process replaces or unloads it while `entry` lives.
        let entry = unsafe { ash::Entry::load() }.map_err(loader_err)?;

        let mut layers = Vec::new();
        let mut extensions = window_extensions.to_vec();
        let mut sync_validation = false;
        if validation {
            // SAFETY: plain enumeration query on a loaded entry.
            let available = unsafe { entry.enumerate_instance_layer_properties() }
                .map_err(vk_err("vkEnumerateInstanceLayerProperties"))?;
            let has_layer = available
                .iter()
                .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
            if !has_layer {
                return Err(GpuError::MissingLayer(
                    VALIDATION_LAYER.to_string_lossy().into_owned(),
                ));
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            // SAFETY: plain enumeration query on a loaded entry.
            let layer_exts =
                unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                    .map_err(vk_err("vkEnumerateInstanceExtensionProperties"))?;
            sync_validation = layer_exts
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(ext::validation_features::NAME));
            if sync_validation {
                extensions.push(ext::validation_features::NAME.as_ptr());
            }
            extensions.push(ext::debug_utils::NAME.as_ptr());
        }

        let log = ValidationLog::default();
        let log_box = Box::new(log.clone());
        let app = vk::ApplicationInfo::default()
            .application_name(c"lensray")
            .engine_name(c"lensray")
            .api_version(vk::API_VERSION_1_2);
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
        // Chained into the instance create-info: covers vkCreateInstance / vkDestroyInstance.
        let mut chained_messenger = messenger_info(&log_box);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validation {
            info = info.push_next(&mut chained_messenger);
            if sync_validation {
                info = info.push_next(&mut features);
            }
        }
        // SAFETY: every pointer in `info` refers to locals that live until the call returns;
        // the messenger's user data is the boxed log kept in the returned value.
        let instance = unsafe { entry.create_instance(&info, None) }.map_err(|e| match e {
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => GpuError::NoDriver,
            e => vk_err("vkCreateInstance")(e),
        })?;

        let debug = if validation {
            let loader = ext::debug_utils::Instance::new(&entry, &instance);
            let info = messenger_info(&log_box);
            // SAFETY: the instance was created with VK_EXT_debug_utils; user data outlives it.
            match unsafe { loader.create_debug_utils_messenger(&info, None) } {
                Ok(m) => Some((loader, m)),
                Err(e) => {
                    // SAFETY: nothing else was created from this instance yet.
                    unsafe { instance.destroy_instance(None) };
                    return Err(vk_err("vkCreateDebugUtilsMessengerEXT")(e));
                }
            }
        } else {
            None
        };
        Ok(Self {
            entry,
            instance,
            debug,
            _log_box: log_box,
            log,
        })
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: every device and object created from this instance holds an `Arc` to it and
        // has been destroyed already; the messenger goes before the instance.
        unsafe {
            if let Some((loader, messenger)) = self.debug.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
        self.log.instance_destroyed.store(true, Ordering::SeqCst);
    }
}
