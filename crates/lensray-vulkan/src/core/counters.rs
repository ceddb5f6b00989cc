//! What the host asks of the device, counted: submissions, host waits, bytes read back,
//! pipelines made and the time the driver took to compile them.

/// What the host asked of the device since it was opened: queue submissions, waits that block
/// the host on the device (fences, semaphores), bytes read back from mapped memory and query
/// results, and pipelines made. Counted where those calls are made (`Context`, `Buffer::read`,
/// `QueryPool::results`, `Fence::wait`, `Pipeline`).
#[derive(Debug, Default)]
pub(crate) struct DeviceCounters {
    pub submits: std::sync::atomic::AtomicU64,
    pub cpu_waits: std::sync::atomic::AtomicU64,
    pub readback_bytes: std::sync::atomic::AtomicU64,
    pub pipelines: std::sync::atomic::AtomicU64,
    pub compile_micros: std::sync::atomic::AtomicU64,
}

/// A snapshot of `DeviceCounters`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counters {
    pub submits: u64,
    pub cpu_waits: u64,
    pub readback_bytes: u64,
    /// Pipelines made (compute and graphics), each once per device: what a path compiles.
    pub pipelines: u64,
    /// Microseconds the host spent making them (the driver compiles the shaders then: seconds
    /// on a device's first use, little once its caches hold them).
    pub compile_micros: u64,
}

impl Counters {
    /// What happened between `earlier` and `self`.
    pub fn since(&self, earlier: &Counters) -> Counters {
        Counters {
            submits: self.submits - earlier.submits,
            cpu_waits: self.cpu_waits - earlier.cpu_waits,
            readback_bytes: self.readback_bytes - earlier.readback_bytes,
            pipelines: self.pipelines - earlier.pipelines,
            compile_micros: self.compile_micros - earlier.compile_micros,
        }
    }

    /// Seconds spent making pipelines.
    pub fn compile_seconds(&self) -> f64 {
        self.compile_micros as f64 * 1e-6
    }
}

impl DeviceCounters {
    pub(crate) fn submitted(&self) {
        self.submits
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub(crate) fn waited(&self) {
        self.cpu_waits
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

    pub(crate) fn read_back(&self, bytes: u64) {
        self.readback_bytes
            .fetch_add(bytes, std::sync::atomic::Ordering::Relaxed);
    }

    /// A pipeline made in `took`.
    pub(crate) fn made_pipeline(&self, took: std::time::Duration) {
        self.pipelines
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.compiled(took);
    }

    /// A pipeline's shaders compiled in `took` (at its making, or in a first dispatch).
    pub(crate) fn compiled(&self, took: std::time::Duration) {
        self.compile_micros.fetch_add(
            took.as_micros() as u64,
            std::sync::atomic::Ordering::Relaxed,
        );
    }

    pub(crate) fn snapshot(&self) -> Counters {
        use std::sync::atomic::Ordering::Relaxed;
        Counters {
            submits: self.submits.load(Relaxed),
            cpu_waits: self.cpu_waits.load(Relaxed),
            readback_bytes: self.readback_bytes.load(Relaxed),
            pipelines: self.pipelines.load(Relaxed),
            compile_micros: self.compile_micros.load(Relaxed),
        }
    }
}
