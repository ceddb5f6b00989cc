//! Recording with barriers derived from accesses. A pass names what each command reads and
//! writes (a buffer and how: a shader's read or write, a transfer's, the host's); the recorder
//! keeps, per buffer, its last write and the reads since, and puts before each command the one
//! memory barrier its hazards need (read after write, write after read, write after write).
//! What happened before the command buffer is unknown to it: a buffer's first use in a recorder
//! waits for every earlier command's writes, as the queue's earlier submissions may hold some.
//!
//! The commands themselves are here too, so that the passes record without `unsafe`.

use std::collections::HashMap;

use ash::vk;

use crate::core::buffer::Buffer;
use crate::core::device::Context;
use crate::core::error::{vk_err, GpuError};
use crate::core::image::{transition, Transition};
use crate::core::pipeline::Pipeline;
use crate::core::query::QueryPool;
use crate::core::sync::{CommandBuffer, Fence};

/// How a command uses a buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Access {
    /// A compute shader's uniform block.
    Uniform,
    /// Read by a compute shader.
    ComputeRead,
    /// Read and written by a compute shader.
    ComputeWrite,
    /// A ray-tracing pipeline's uniform block.
    RayTracingUniform,
    /// Read by a ray-tracing pipeline's stages.
    RayTracingRead,
    /// Read and written by a ray-tracing pipeline's stages.
    RayTracingWrite,
    TransferRead,
    TransferWrite,
    /// Read by the host after the submission's wait (mapped memory).
    HostRead,
    /// An acceleration structure read by a build, a copy or a query of its properties.
    AccelBuildRead,
    /// An acceleration structure written by a build or a copy.
    AccelBuildWrite,
}

impl Access {
    fn stage(self) -> vk::PipelineStageFlags {
        match self {
            Access::Uniform | Access::ComputeRead | Access::ComputeWrite => {
                vk::PipelineStageFlags::COMPUTE_SHADER
            }
            Access::RayTracingUniform | Access::RayTracingRead | Access::RayTracingWrite => {
                vk::PipelineStageFlags::RAY_TRACING_SHADER_KHR
            }
            Access::TransferRead | Access::TransferWrite => vk::PipelineStageFlags::TRANSFER,
            Access::HostRead => vk::PipelineStageFlags::HOST,
            Access::AccelBuildRead | Access::AccelBuildWrite => {
                vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR
            }
        }
    }

    fn mask(self) -> vk::AccessFlags {
        match self {
            Access::Uniform | Access::RayTracingUniform => vk::AccessFlags::UNIFORM_READ,
            Access::ComputeRead | Access::RayTracingRead => vk::AccessFlags::SHADER_READ,
            Access::ComputeWrite | Access::RayTracingWrite => {
                vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE
            }
            Access::TransferRead => vk::AccessFlags::TRANSFER_READ,
            Access::TransferWrite => vk::AccessFlags::TRANSFER_WRITE,
            Access::HostRead => vk::AccessFlags::HOST_READ,
            Access::AccelBuildRead => vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
            Access::AccelBuildWrite => vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
        }
    }

    fn writes(self) -> bool {
        matches!(
            self,
            Access::ComputeWrite
                | Access::RayTracingWrite
                | Access::TransferWrite
                | Access::AccelBuildWrite
        )
    }

    /// The same access by a ray-tracing pipeline's stages where it is a compute shader's: a
    /// pass that records a dispatch or a trace of rays names its accesses once.
    pub(crate) fn in_ray_tracing(self) -> Self {
        match self {
            Access::Uniform => Access::RayTracingUniform,
            Access::ComputeRead => Access::RayTracingRead,
            Access::ComputeWrite => Access::RayTracingWrite,
            other => other,
        }
    }
}

/// What the recorder knows of a buffer: its last write not yet waited for by every later
/// stage, the stages and accesses that write is visible to, and the stages that read it since.
#[derive(Clone, Copy, Debug)]
struct Track {
    write: Option<(vk::PipelineStageFlags, vk::AccessFlags)>,
    visible: (vk::PipelineStageFlags, vk::AccessFlags),
    read_stages: vk::PipelineStageFlags,
}

impl Track {
    /// A buffer the recorder has not seen: any earlier command may have written or read it.
    fn unknown() -> Self {
        Self {
            write: Some((
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::AccessFlags::MEMORY_WRITE,
            )),
            visible: (vk::PipelineStageFlags::empty(), vk::AccessFlags::empty()),
            read_stages: vk::PipelineStageFlags::ALL_COMMANDS,
        }
    }
}

/// One barrier's scopes, accumulated over a command's accesses.
#[derive(Default)]
struct Scopes {
    src_stage: vk::PipelineStageFlags,
    src_access: vk::AccessFlags,
    dst_stage: vk::PipelineStageFlags,
    dst_access: vk::AccessFlags,
}

/// What a recorder knows of the buffers it touched, and the barriers their uses need.
#[derive(Default)]
struct Tracks(HashMap<vk::Buffer, Track>);

impl Tracks {
    /// The barrier that `uses` need after the uses noted so far (none: no hazard), noting
    /// them.
    fn barrier_for(&mut self, uses: &[(vk::Buffer, Access)]) -> Option<Scopes> {
        let mut scopes = Scopes::default();
        for &(buffer, access) in uses {
            let track = self.0.entry(buffer).or_insert_with(Track::unknown);
            let (stage, mask) = (access.stage(), access.mask());
            if access.writes() {
                // After the last write (its data) and every read since (their execution).
                if let Some((write_stage, write_mask)) = track.write {
                    scopes.src_stage |= write_stage;
                    scopes.src_access |= write_mask;
                }
                scopes.src_stage |= track.read_stages;
                scopes.dst_stage |= stage;
                scopes.dst_access |= mask;
                *track = Track {
                    write: Some((stage, mask & !vk::AccessFlags::SHADER_READ)),
                    visible: (vk::PipelineStageFlags::empty(), vk::AccessFlags::empty()),
                    read_stages: vk::PipelineStageFlags::empty(),
                };
            } else {
                // After the last write, unless an earlier barrier made it visible here.
                if let Some((write_stage, write_mask)) = track.write {
                    let seen = track.visible.0.contains(stage) && track.visible.1.contains(mask);
                    if !seen {
                        scopes.src_stage |= write_stage;
                        scopes.src_access |= write_mask;
                        scopes.dst_stage |= stage;
                        scopes.dst_access |= mask;
                        track.visible.0 |= stage;
                        track.visible.1 |= mask;
                    }
                }
                track.read_stages |= stage;
            }
        }
        (!scopes.src_stage.is_empty()).then_some(scopes)
    }
}

/// A command buffer being recorded, with what it knows of the buffers it touched.
pub(crate) struct Recorder<'a> {
    ctx: &'a Context,
    cmd: vk::CommandBuffer,
    tracks: Tracks,
}

impl<'a> Recorder<'a> {
    pub(crate) fn new(ctx: &'a Context, cmd: vk::CommandBuffer) -> Self {
        Self {
            ctx,
            cmd,
            tracks: Tracks::default(),
        }
    }

    /// Begins recording `cmd` anew, whose previous submission finished (`fence` waited): the
    /// fence and the command buffer are reset first. `finish` ends it.
    pub(crate) fn begin_again(
        ctx: &'a Context,
        cmd: &CommandBuffer,
        fence: &Fence,
    ) -> Result<Self, GpuError> {
        let device = &ctx.device;
        let (cmd, fence) = (cmd.handle, fence.handle);
        // SAFETY: the previous submission of `cmd` finished (the caller waited for `fence`):
        // the command buffer may be reset and recorded again, the fence reset.
        unsafe {
            device
                .reset_fences(&[fence])
                .map_err(vk_err("vkResetFences"))?;
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .map_err(vk_err("vkResetCommandBuffer"))?;
            device
                .begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .map_err(vk_err("vkBeginCommandBuffer"))?;
        }
        Ok(Self::new(ctx, cmd))
    }

    /// Ends a recording that `begin_again` began.
    pub(crate) fn finish(self) -> Result<(), GpuError> {
        // SAFETY: recording began in `begin_again`.
        unsafe { self.ctx.device.end_command_buffer(self.cmd) }
            .map_err(vk_err("vkEndCommandBuffer"))
    }

    /// Blits `src` (TRANSFER_SRC_OPTIMAL) 1:1 onto `dst` (TRANSFER_DST_OPTIMAL), both of
    /// `extent`: a copy that may reorder channels (RGBA8 to a window's BGRA8).
    pub(crate) fn blit(&mut self, src: vk::Image, dst: vk::Image, extent: vk::Extent2D) {
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let corner = vk::Offset3D {
            x: extent.width as i32,
            y: extent.height as i32,
            z: 1,
        };
        let region = vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner]);
        // SAFETY: both images are live, of `extent`, in the layouts named (the callers'
        // transitions); a 1:1 blit reads and writes texel for texel.
        unsafe {
            self.ctx.device.cmd_blit_image(
                self.cmd,
                src,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
                vk::Filter::NEAREST,
            )
        };
    }

    /// The command buffer, for the recording functions of `core` that are not the recorder's.
    pub(crate) fn cmd(&self) -> vk::CommandBuffer {
        self.cmd
    }

    pub(crate) fn ctx(&self) -> &'a Context {
        self.ctx
    }

    /// Puts the barrier that `uses` (buffers by handle) need after what was recorded before,
    /// and notes them.
    pub(crate) fn uses(&mut self, uses: &[(vk::Buffer, Access)]) {
        if let Some(scopes) = self.tracks.barrier_for(uses) {
            self.barrier(&scopes);
        }
    }

    fn barrier(&mut self, scopes: &Scopes) {
        let memory = [vk::MemoryBarrier::default()
            .src_access_mask(scopes.src_access)
            .dst_access_mask(scopes.dst_access)];
        // SAFETY: recording into a command buffer in the recording state.
        unsafe {
            self.ctx.device.cmd_pipeline_barrier(
                self.cmd,
                scopes.src_stage,
                scopes.dst_stage,
                vk::DependencyFlags::empty(),
                &memory,
                &[],
                &[],
            )
        };
    }

    /// Binds `pipeline` (compute) with `push` and dispatches `groups` workgroups, after the
    /// barrier `uses` need.
    pub(crate) fn dispatch(
        &mut self,
        pipeline: &Pipeline,
        push: &[u8],
        groups: [u32; 3],
        uses: &[(vk::Buffer, Access)],
    ) {
        self.uses(uses);
        pipeline.bind(self.cmd, push);
        // SAFETY: a compute pipeline with its complete descriptor set is bound.
        unsafe {
            self.ctx
                .device
                .cmd_dispatch(self.cmd, groups[0], groups[1], groups[2])
        };
    }

    /// Binds `pipeline` (ray tracing) with `push` and traces `extent` rays from its ray
    /// generation stage, after the barrier `uses` need (compute accesses stand for the same
    /// accesses of its stages, `Access::in_ray_tracing`).
    pub(crate) fn trace_rays(
        &mut self,
        pipeline: &Pipeline,
        push: &[u8],
        extent: [u32; 3],
        uses: &[(vk::Buffer, Access)],
    ) {
        let uses: Vec<_> = uses.iter().map(|&(b, a)| (b, a.in_ray_tracing())).collect();
        self.uses(&uses);
        let (Some(sbt), Some(rt)) = (pipeline.shader_binding_table(), &self.ctx.ray_tracing) else {
            unreachable!("a ray-tracing pipeline has its table, on a device with the extension");
        };
        pipeline.bind(self.cmd, push);
        // SAFETY: a ray-tracing pipeline with its complete descriptor set is bound; its table's
        // regions hold its groups' handles.
        unsafe {
            rt.fns.cmd_trace_rays(
                self.cmd,
                &sbt.raygen,
                &sbt.miss,
                &sbt.hit,
                &sbt.callable,
                extent[0],
                extent[1],
                extent[2],
            )
        };
    }

    /// Writes `data` (a multiple of 4 bytes, at most 64 KiB) at the start of `buffer`.
    pub(crate) fn update_buffer(&mut self, buffer: &Buffer, data: &[u8]) {
        self.uses(&[(buffer.buffer, Access::TransferWrite)]);
        // SAFETY: recording state; the buffer has TRANSFER_DST usage and the data's size is a
        // multiple of 4 under 64 KiB (the callers' structs).
        unsafe {
            self.ctx
                .device
                .cmd_update_buffer(self.cmd, buffer.buffer, 0, data)
        };
    }

    /// Fills `size` bytes of `buffer` from `offset` (multiples of 4, or `vk::WHOLE_SIZE`) with
    /// the word `value`.
    pub(crate) fn fill_buffer(&mut self, buffer: &Buffer, offset: u64, size: u64, value: u32) {
        self.uses(&[(buffer.buffer, Access::TransferWrite)]);
        // SAFETY: recording state; the buffer has TRANSFER_DST usage and the range lies in it.
        unsafe {
            self.ctx
                .device
                .cmd_fill_buffer(self.cmd, buffer.buffer, offset, size, value)
        };
    }

    /// Copies `regions` of `src` into `dst`.
    pub(crate) fn copy_buffer(&mut self, src: &Buffer, dst: &Buffer, regions: &[vk::BufferCopy]) {
        self.uses(&[
            (src.buffer, Access::TransferRead),
            (dst.buffer, Access::TransferWrite),
        ]);
        // SAFETY: recording state; the buffers have the TRANSFER usages and the regions lie in
        // them (the callers size them).
        unsafe {
            self.ctx
                .device
                .cmd_copy_buffer(self.cmd, src.buffer, dst.buffer, regions)
        };
    }

    /// Makes `buffers`' earlier writes visible to the host (after the submission's wait).
    pub(crate) fn read_on_host(&mut self, buffers: &[&Buffer]) {
        let uses: Vec<(vk::Buffer, Access)> = buffers
            .iter()
            .map(|b| (b.buffer, Access::HostRead))
            .collect();
        self.uses(&uses);
    }

    /// Makes `buffers`' writes so far visible to every later command, in this submission or a
    /// later one, which need not name them: what an upload leaves for the shaders to read.
    pub(crate) fn publish(&mut self, buffers: &[&Buffer]) {
        let mut scopes = Scopes {
            dst_stage: vk::PipelineStageFlags::ALL_COMMANDS,
            dst_access: vk::AccessFlags::MEMORY_READ,
            ..Scopes::default()
        };
        for buffer in buffers {
            let track = self
                .tracks
                .0
                .entry(buffer.buffer)
                .or_insert_with(Track::unknown);
            if let Some((stage, mask)) = track.write {
                scopes.src_stage |= stage;
                scopes.src_access |= mask;
            }
            track.visible = (
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::AccessFlags::MEMORY_READ,
            );
        }
        if !scopes.src_stage.is_empty() {
            self.barrier(&scopes);
        }
    }

    /// Resets `pool`'s queries, to be written again in this command buffer.
    pub(crate) fn reset_queries(&mut self, pool: &QueryPool) {
        pool.reset(self.cmd);
    }

    /// Writes timestamp `query` of `pool` when the commands before reach `stage`.
    pub(crate) fn timestamp(
        &mut self,
        pool: &QueryPool,
        stage: vk::PipelineStageFlags,
        query: u32,
    ) {
        pool.write(self.cmd, stage, query);
    }

    /// Moves `image` between layouts as `how` says (the image barrier orders its accesses).
    pub(crate) fn transition(&mut self, image: vk::Image, how: &Transition) {
        transition(self.ctx, self.cmd, image, how);
    }

    /// Copies the `extent` pixels at `offset` of colour image `image` (in TRANSFER_SRC_OPTIMAL,
    /// its writes ordered before transfers: a scene render pass's outgoing dependency) into
    /// `buffer`, packed row by row.
    pub(crate) fn copy_image_to_buffer(
        &mut self,
        image: vk::Image,
        buffer: &Buffer,
        offset: [u32; 2],
        extent: [u32; 2],
    ) {
        self.uses(&[(buffer.buffer, Access::TransferWrite)]);
        crate::core::image::record_copy_to_buffer(
            self.ctx,
            self.cmd,
            image,
            buffer.buffer,
            offset,
            extent,
        );
    }

    /// Begins `render_pass` over the whole `width` x `height` framebuffer with `clear`, the
    /// viewport and scissor set to it.
    pub(crate) fn begin_render_pass(
        &mut self,
        render_pass: vk::RenderPass,
        framebuffer: vk::Framebuffer,
        (width, height): (u32, u32),
        clear: &[vk::ClearValue],
    ) {
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D { width, height },
        };
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(render_pass)
            .framebuffer(framebuffer)
            .render_area(area)
            .clear_values(clear);
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: width as f32,
            height: height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: recording state, outside a render pass; the framebuffer matches the render
        // pass (their owners make them together).
        unsafe {
            self.ctx
                .device
                .cmd_begin_render_pass(self.cmd, &begin, vk::SubpassContents::INLINE);
            self.ctx.device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            self.ctx.device.cmd_set_scissor(self.cmd, 0, &[area]);
        }
    }

    /// Binds graphics `pipeline` with `push`, inside a render pass.
    pub(crate) fn bind_graphics(&mut self, pipeline: &Pipeline, push: &[u8]) {
        pipeline.bind(self.cmd, push);
    }

    /// Binds the variant of graphics `pipeline` specialized for `surfaces`.
    pub(crate) fn bind_surfaces(&mut self, pipeline: &Pipeline, surfaces: u32) {
        pipeline.bind_surfaces(self.cmd, surfaces);
    }

    /// Draws `count` vertices from `first`, one instance, with the graphics pipeline bound.
    pub(crate) fn draw(&mut self, first: u32, count: u32) {
        // SAFETY: inside a render pass with a graphics pipeline and its set bound; the
        // vertices are pulled from storage buffers, whose sizes the callers' ranges respect.
        unsafe { self.ctx.device.cmd_draw(self.cmd, count, 1, first, 0) };
    }

    pub(crate) fn end_render_pass(&mut self) {
        // SAFETY: inside the render pass that `begin_render_pass` began.
        unsafe { self.ctx.device.cmd_end_render_pass(self.cmd) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ash::vk::Handle;

    fn buffer(n: u64) -> vk::Buffer {
        vk::Buffer::from_raw(n)
    }

    #[test]
    fn barriers_follow_the_hazards() {
        let mut tracks = Tracks::default();
        let (a, b) = (buffer(1), buffer(2));
        // First use: after whatever came before the command buffer.
        let first = tracks.barrier_for(&[(a, Access::TransferWrite)]).unwrap();
        assert_eq!(first.src_stage, vk::PipelineStageFlags::ALL_COMMANDS);
        // Read after write: the write's data, made visible to the reader.
        let raw = tracks.barrier_for(&[(a, Access::ComputeRead)]).unwrap();
        assert_eq!(
            (raw.src_stage, raw.src_access),
            (
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE
            )
        );
        assert_eq!(raw.dst_access, vk::AccessFlags::SHADER_READ);
        // A second read of what is visible already: no barrier.
        assert!(tracks.barrier_for(&[(a, Access::ComputeRead)]).is_none());
        // Write after read: the readers' execution first, no data to make visible.
        let war = tracks.barrier_for(&[(a, Access::TransferWrite)]).unwrap();
        assert!(war
            .src_stage
            .contains(vk::PipelineStageFlags::COMPUTE_SHADER));
        // One barrier covers several buffers' hazards.
        tracks.barrier_for(&[(b, Access::ComputeWrite)]);
        let both = tracks
            .barrier_for(&[(a, Access::HostRead), (b, Access::TransferRead)])
            .unwrap();
        assert_eq!(
            both.dst_stage,
            vk::PipelineStageFlags::HOST | vk::PipelineStageFlags::TRANSFER
        );
        assert_eq!(
            both.src_access,
            vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE
        );
    }
}
