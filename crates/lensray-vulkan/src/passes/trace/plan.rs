//! The hybrid path's plan as the trace shader reads it (`HybridTraceGroup`): one vec4 per pixel,
//! written by the device plan pass (and, lit, completed by the shortcut pre-pass), the surface
//! depths beside it, and how many pixels the plan last made covers. One entry while no plan is
//! needed: the binding must be valid in every mode. Adaptive sampling's rounds use the same
//! entries (`TRACE_MODE_ADAPTIVE`): the host uploads each pixel's count or `ADAPTIVE_IDLE` and
//! its class A sum, the shader adds to the sum, the host reads it back.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::GpuError;
use lensray_core::interface::{TRACE_MODE_ADAPTIVE, TRACE_MODE_HYBRID};

pub(crate) struct PlanBuffers {
    ctx: Arc<Context>,
    /// The plan's entries (`HybridTraceGroup`).
    plan: Buffer,
    /// Per pixel of the plan: the camera-space depth of the surface the G-buffer sees (0:
    /// none), from the device plan.
    surface_depth: Buffer,
    /// Pixels of the plan the device plan pass wrote (`use_device_plan`); `None`: no plan.
    pixels: Option<u64>,
}

impl PlanBuffers {
    /// Buffers of one entry, and no plan.
    pub(crate) fn new(ctx: &Arc<Context>) -> Result<Self, GpuError> {
        Ok(Self {
            ctx: ctx.clone(),
            plan: Self::plan_buffer(ctx, 16)?,
            surface_depth: Self::surface_depth_buffer(ctx, 16)?,
            pixels: None,
        })
    }

    fn plan_buffer(ctx: &Arc<Context>, bytes: u64) -> Result<Buffer, GpuError> {
        // Written by the device plan pass, read (and, lit, completed by the shortcut pre-pass)
        // by the shader on every pass: device-local; the probes copy it out to read it, and
        // adaptive sampling copies its rounds' entries in and out.
        Buffer::new(
            ctx,
            "hybrid plan",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )
    }

    fn surface_depth_buffer(ctx: &Arc<Context>, bytes: u64) -> Result<Buffer, GpuError> {
        // Written by the device plan, read by the hybrid's lit shortcut samples.
        Buffer::new(
            ctx,
            "hybrid surface depth",
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )
    }

    /// Makes the plan buffer hold at least `pixels` entries, and the surface depths as many.
    /// Returns whether they are new buffers (to bind again). No submission using them may be
    /// pending.
    pub(super) fn ensure_capacity(&mut self, pixels: u64) -> Result<bool, GpuError> {
        let bytes = (pixels * 16).max(16);
        if self.plan.size >= bytes {
            return Ok(false);
        }
        self.plan = Self::plan_buffer(&self.ctx, bytes)?;
        self.surface_depth = Self::surface_depth_buffer(&self.ctx, bytes / 4)?;
        Ok(true)
    }

    /// The plan buffer (for the device plan pass to write).
    pub(crate) fn plan(&self) -> &Buffer {
        &self.plan
    }

    /// The surface depths (for the device plan pass to write).
    pub(crate) fn surface_depth(&self) -> &Buffer {
        &self.surface_depth
    }

    /// Later `accumulate` calls follow the plan of `pixels` entries that the device plan pass
    /// wrote into the plan buffer.
    pub(crate) fn use_device_plan(&mut self, pixels: u64) {
        self.pixels = Some(pixels);
    }

    /// Later `accumulate` calls follow no plan (the hybrid's mode is refused until a new one).
    pub(crate) fn clear(&mut self) {
        self.pixels = None;
    }

    /// An error when the shader's `mode` cannot run on an image of `pixels` pixels: the
    /// hybrid's and adaptive sampling's need a plan covering the image.
    pub(super) fn check(&self, pixels: u64, mode: u32) -> Result<(), GpuError> {
        match self.pixels {
            _ if mode != TRACE_MODE_HYBRID && mode != TRACE_MODE_ADAPTIVE => Ok(()),
            Some(n) if n == pixels => Ok(()),
            Some(n) => Err(GpuError::Invalid(format!(
                "the hybrid plan has {n} pixels, the image {pixels}"
            ))),
            None => Err(GpuError::Invalid("the hybrid's plan is not made".into())),
        }
    }

    /// Writes `entries` over the plan's first entries (the buffer holds them:
    /// `TracePass::ensure_plan_capacity`) in a submission of its own, waited for, and follows
    /// them from now on (`use_device_plan`).
    pub(crate) fn upload(&mut self, entries: &[[f32; 4]]) -> Result<(), GpuError> {
        let bytes = std::mem::size_of_val(entries) as u64;
        if bytes > self.plan.size {
            return Err(GpuError::Invalid(format!(
                "the plan buffer has no {} entries",
                entries.len()
            )));
        }
        let mut host = Buffer::new(
            &self.ctx,
            "plan upload",
            bytes.max(16),
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        host.write(bytemuck::cast_slice(entries))?;
        self.ctx.submit_and_wait(|rec| {
            let copy = vk::BufferCopy::default().size(bytes.max(16));
            rec.copy_buffer(&host, &self.plan, &[copy]);
            rec.publish(&[&self.plan]);
            Ok(())
        })?;
        self.use_device_plan(entries.len() as u64);
        Ok(())
    }

    /// The plan's first `pixels` entries as the device left them, copied to host-visible
    /// memory in a submission of their own, waited for.
    pub(crate) fn read(&self, pixels: u64) -> Result<Vec<[f32; 4]>, GpuError> {
        let bytes = pixels * 16;
        if bytes > self.plan.size {
            return Err(GpuError::Invalid(format!(
                "the plan buffer has no {pixels} entries"
            )));
        }
        let host = Buffer::new(
            &self.ctx,
            "hybrid plan read-back",
            bytes.max(16),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.ctx.submit_and_wait(|rec| {
            let copy = vk::BufferCopy::default().size(bytes.max(16));
            rec.copy_buffer(&self.plan, &host, &[copy]);
            rec.read_on_host(&[&host]);
            Ok(())
        })?;
        let entries: &[[f32; 4]] = bytemuck::cast_slice(host.read()?);
        Ok(entries[..pixels as usize].to_vec())
    }
}
