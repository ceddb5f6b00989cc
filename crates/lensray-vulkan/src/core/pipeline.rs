//! Pipelines with their layout and one descriptor set each (compute, graphics and ray
//! tracing, the last with its shader binding table).

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use crate::core::device::Context;
use crate::core::error::{pipeline_err, vk_err, GpuError};
use crate::core::sbt::{GroupCounts, ShaderBindingTable};
use crate::core::shader::ShaderModule;
use lensray_core::interface::{SetDecl, SPEC_SURFACES, SURFACE_SINGLE_SIDED};

/// One descriptor of a pipeline's set: binding number, type, stages (`descriptors::layout_of`
/// makes them from a set's declaration).
pub(crate) type Binding = (u32, vk::DescriptorType, vk::ShaderStageFlags);

/// A pipeline, its layout, and one descriptor set (with its layout and pool).
pub(crate) struct Pipeline {
    pub(super) ctx: Arc<Context>,
    /// The declaration of its descriptor set (`None`: bindings from elsewhere, the layout
    /// probe's).
    pub(super) set_decl: Option<&'static SetDecl>,
    /// The pipeline; of a graphics pipeline with surface variants, the one for all of them
    /// (the general code).
    pub pipeline: vk::Pipeline,
    /// The SURFACE_* bits the fragment stage is specialized on (0: none); entry s (below
    /// them) of `variants` is the pipeline for surfaces s, null where s has other bits.
    surface_variants: u32,
    variants: Vec<vk::Pipeline>,
    pub layout: vk::PipelineLayout,
    set_layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
    pub bind_point: vk::PipelineBindPoint,
    push_stages: vk::ShaderStageFlags,
    /// A ray-tracing pipeline's table (`None`: another kind).
    pub(super) sbt: Option<ShaderBindingTable>,
}

/// The stages of a ray-tracing pipeline whose ray generation stage traces kinds of ray: for
/// each kind (its index the `sbtRecordOffset` and `missIndex` the stage traces it with), its
/// miss stage and its hit group's stages.
pub(crate) struct RayTracingDesc<'a> {
    pub raygen: &'a [u8],
    pub rays: &'a [RayStages<'a>],
}

/// One kind of ray of a [`RayTracingDesc`].
pub(crate) struct RayStages<'a> {
    pub miss: &'a [u8],
    /// `None`: the kind skips the closest-hit stage.
    pub closest_hit: Option<&'a [u8]>,
    pub any_hit: Option<&'a [u8]>,
}

/// The graphics state of the G-buffer pass.
pub(crate) struct GraphicsDesc<'a> {
    pub vert: &'a [u8],
    pub frag: &'a [u8],
    pub render_pass: vk::RenderPass,
    pub color_attachments: u32,
    /// LESS for the course's depth (0 at the near plane), GREATER for reversed depth.
    pub depth_compare: vk::CompareOp,
    /// The SURFACE_* bits the fragment stage's specialization constant SPEC_SURFACES
    /// takes: one pipeline is made for each subset of them (0: one pipeline, unspecialized).
    pub surface_variants: u32,
    /// The stages (vertex, fragment) of the variant for none of those bits, where a build of
    /// them leaves out the inputs only the bits' code reads (lavapipe interpolates every input
    /// a fragment stage declares); `None`: `vert` and `frag`.
    pub plain: Option<(&'a [u8], &'a [u8])>,
}

impl Pipeline {
    /// Layout objects first, then the pipeline; on error `Drop` cleans up what exists.
    pub(super) fn with_layout(
        ctx: &Arc<Context>,
        bindings: &[Binding],
        push_size: u32,
        push_stages: vk::ShaderStageFlags,
        bind_point: vk::PipelineBindPoint,
    ) -> Result<Self, GpuError> {
        let mut this = Self {
            ctx: ctx.clone(),
            set_decl: None,
            pipeline: vk::Pipeline::null(),
            surface_variants: 0,
            variants: Vec::new(),
            layout: vk::PipelineLayout::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
            bind_point,
            push_stages,
            sbt: None,
        };
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|&(binding, ty, stages)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(ty)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: valid create-info on a live device.
        this.set_layout = unsafe { ctx.device.create_descriptor_set_layout(&info, None) }
            .map_err(vk_err("vkCreateDescriptorSetLayout"))?;

        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for &(_, ty, _) in bindings {
            match sizes.iter_mut().find(|s| s.ty == ty) {
                Some(s) => s.descriptor_count += 1,
                None => sizes.push(vk::DescriptorPoolSize {
                    ty,
                    descriptor_count: 1,
                }),
            }
        }
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid create-info.
        this.pool = unsafe { ctx.device.create_descriptor_pool(&pool_info, None) }
            .map_err(vk_err("vkCreateDescriptorPool"))?;
        let set_layouts = [this.set_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(this.pool)
            .set_layouts(&set_layouts);
        // SAFETY: the pool has room for exactly this set.
        this.set = unsafe { ctx.device.allocate_descriptor_sets(&alloc) }
            .map_err(vk_err("vkAllocateDescriptorSets"))?[0];

        let ranges = [vk::PushConstantRange::default()
            .stage_flags(push_stages)
            .offset(0)
            .size(push_size)];
        let mut layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
        if push_size > 0 {
            layout_info = layout_info.push_constant_ranges(&ranges);
        }
        // SAFETY: valid create-info referencing a live set layout.
        this.layout = unsafe { ctx.device.create_pipeline_layout(&layout_info, None) }
            .map_err(vk_err("vkCreatePipelineLayout"))?;
        Ok(this)
    }

    /// A compute pipeline of `spirv` whose descriptor set is `set`.
    pub(crate) fn compute(
        ctx: &Arc<Context>,
        set: &'static SetDecl,
        spirv: &[u8],
    ) -> Result<Self, GpuError> {
        Self::compute_specialized(ctx, set, spirv, None)
    }

    /// A compute pipeline whose SPEC_SURFACES is `surfaces` (`None`: the shader's default).
    pub(crate) fn compute_specialized(
        ctx: &Arc<Context>,
        set: &'static SetDecl,
        spirv: &[u8],
        surfaces: Option<u32>,
    ) -> Result<Self, GpuError> {
        let mut this = Self::with_set(ctx, set, vk::PipelineBindPoint::COMPUTE)?;
        this.pipeline = create_compute(ctx, spirv, this.layout, surfaces)?;
        Ok(this)
    }

    /// A compute pipeline over bindings made elsewhere than a set declaration: the layout
    /// probe's, generated from the list of shared structs.
    #[cfg(feature = "probes")]
    pub(crate) fn compute_with_bindings(
        ctx: &Arc<Context>,
        spirv: &[u8],
        bindings: &[Binding],
        push_size: u32,
    ) -> Result<Self, GpuError> {
        let mut this = Self::with_layout(
            ctx,
            bindings,
            push_size,
            vk::ShaderStageFlags::COMPUTE,
            vk::PipelineBindPoint::COMPUTE,
        )?;
        this.pipeline = create_compute(ctx, spirv, this.layout, None)?;
        Ok(this)
    }

    /// The layout and set of a pipeline whose code comes later (`respecialize`,
    /// `respecialize_ray_tracing`): a pass that may never use a traversal does not compile it.
    pub(crate) fn unbuilt(
        ctx: &Arc<Context>,
        set: &'static SetDecl,
        bind_point: vk::PipelineBindPoint,
    ) -> Result<Self, GpuError> {
        Self::with_set(ctx, set, bind_point)
    }

    /// Replaces the compute pipeline with one made from `spirv` with SPEC_SURFACES `surfaces`.
    /// The layout and set stay, and so does what is bound to them. No submission using the
    /// pipeline may be pending.
    pub(crate) fn respecialize(&mut self, spirv: &[u8], surfaces: u32) -> Result<(), GpuError> {
        let pipeline = create_compute(&self.ctx, spirv, self.layout, Some(surfaces))?;
        // SAFETY: no pending submission uses the old pipeline (the caller's contract).
        unsafe { self.ctx.device.destroy_pipeline(self.pipeline, None) };
        self.pipeline = pipeline;
        Ok(())
    }

    /// Replaces the ray-tracing pipeline (and its table) with one of `desc` with SPEC_SURFACES
    /// `surfaces`. No submission using the pipeline may be pending.
    pub(crate) fn respecialize_ray_tracing(
        &mut self,
        desc: &RayTracingDesc<'_>,
        surfaces: u32,
    ) -> Result<(), GpuError> {
        let pipeline = create_ray_tracing(&self.ctx, desc, self.layout, surfaces)?;
        let rays = desc.rays.len() as u32;
        let counts = GroupCounts {
            misses: rays,
            hits: rays,
        };
        let sbt = match ShaderBindingTable::new(&self.ctx, pipeline, counts) {
            Ok(sbt) => sbt,
            Err(e) => {
                // SAFETY: the pipeline was just created and never used.
                unsafe { self.ctx.device.destroy_pipeline(pipeline, None) };
                return Err(e);
            }
        };
        // SAFETY: no pending submission uses the old pipeline (the caller's contract).
        unsafe { self.ctx.device.destroy_pipeline(self.pipeline, None) };
        self.pipeline = pipeline;
        self.sbt = Some(sbt);
        Ok(())
    }

    /// A ray-tracing pipeline's shader binding table (`None`: another kind of pipeline).
    pub(crate) fn shader_binding_table(&self) -> Option<&ShaderBindingTable> {
        self.sbt.as_ref()
    }

    /// A graphics pipeline, specialized for every subset of `desc.surface_variants` (one
    /// vkCreateGraphicsPipelines call); [`Self::bind_surfaces`] picks one.
    pub(crate) fn graphics(
        ctx: &Arc<Context>,
        set: &'static SetDecl,
        desc: &GraphicsDesc<'_>,
    ) -> Result<Self, GpuError> {
        let mut this = Self::with_set(ctx, set, vk::PipelineBindPoint::GRAPHICS)?;
        ctx.announce_compile();
        let start = Instant::now();
        let general = [
            ShaderModule::new(ctx, desc.vert)?,
            ShaderModule::new(ctx, desc.frag)?,
        ];
        let plain = match desc.plain {
            Some((vert, frag)) => {
                Some([ShaderModule::new(ctx, vert)?, ShaderModule::new(ctx, frag)?])
            }
            None => None,
        };
        let mask = desc.surface_variants;
        // Index s: the pipeline for surfaces s; the last (s = mask) is `pipeline`.
        let surfaces: Vec<u32> = (0..=mask).filter(|s| s & !mask == 0).collect();
        let spec_data: Vec<[u8; 4]> = surfaces.iter().map(|s| s.to_ne_bytes()).collect();
        let specs: Vec<_> = spec_data
            .iter()
            .map(|data| {
                vk::SpecializationInfo::default()
                    .map_entries(&SURFACES_ENTRY)
                    .data(data)
            })
            .collect();
        let stages: Vec<_> = surfaces
            .iter()
            .zip(&specs)
            .map(|(&s, spec)| {
                // Culling back faces changes no fragment's code.
                let [vert, frag] = match &plain {
                    Some(plain) if s & !SURFACE_SINGLE_SIDED == 0 => plain,
                    _ => &general,
                };
                let frag = vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::FRAGMENT)
                    .module(frag.module)
                    .name(c"main");
                let vert = vk::PipelineShaderStageCreateInfo::default()
                    .stage(vk::ShaderStageFlags::VERTEX)
                    .module(vert.module)
                    .name(c"main");
                [
                    vert,
                    if mask == 0 {
                        frag
                    } else {
                        frag.specialization_info(spec)
                    },
                ]
            })
            .collect();
        let made = create_graphics(ctx, desc, this.layout, &stages, &surfaces)?;
        this.surface_variants = mask;
        this.variants = vec![vk::Pipeline::null(); mask as usize];
        for (&s, &pipeline) in surfaces.iter().zip(&made) {
            match this.variants.get_mut(s as usize) {
                Some(slot) => *slot = pipeline,
                None => this.pipeline = pipeline,
            }
        }
        ctx.counters.made_pipeline(start.elapsed());
        Ok(this)
    }

    /// Binds the pipeline and its set, and pushes `push` (if non-empty).
    pub(crate) fn bind(&self, cmd: vk::CommandBuffer, push: &[u8]) {
        // SAFETY: command buffer in the recording state; everything bound is live.
        unsafe {
            self.ctx
                .device
                .cmd_bind_pipeline(cmd, self.bind_point, self.pipeline);
            self.ctx.device.cmd_bind_descriptor_sets(
                cmd,
                self.bind_point,
                self.layout,
                0,
                &[self.set],
                &[],
            );
            if !push.is_empty() {
                self.ctx
                    .device
                    .cmd_push_constants(cmd, self.layout, self.push_stages, 0, push);
            }
        }
    }
}

impl Pipeline {
    /// Binds the graphics pipeline specialized for `surfaces` (SURFACE_* bits; those it is not
    /// specialized on take the general code). The set and push constants bound by
    /// [`Self::bind`] stay: every variant has the same layout.
    pub(crate) fn bind_surfaces(&self, cmd: vk::CommandBuffer, surfaces: u32) {
        let s = surfaces & self.surface_variants;
        let pipeline = self
            .variants
            .get(s as usize)
            .copied()
            .unwrap_or(self.pipeline);
        // SAFETY: command buffer in the recording state; the pipeline is live.
        unsafe {
            self.ctx
                .device
                .cmd_bind_pipeline(cmd, self.bind_point, pipeline)
        };
    }

    /// The SURFACE_* bits the pipeline is specialized on.
    pub(crate) fn surface_variants(&self) -> u32 {
        self.surface_variants
    }
}

/// The entry and map of SPEC_SURFACES: a u32 at offset 0.
const SURFACES_ENTRY: [vk::SpecializationMapEntry; 1] = [vk::SpecializationMapEntry {
    constant_id: SPEC_SURFACES,
    offset: 0,
    size: std::mem::size_of::<u32>(),
}];

/// A compute pipeline of `spirv` with `layout`, SPEC_SURFACES `surfaces` where given.
fn create_compute(
    ctx: &Context,
    spirv: &[u8],
    layout: vk::PipelineLayout,
    surfaces: Option<u32>,
) -> Result<vk::Pipeline, GpuError> {
    ctx.announce_compile();
    let start = Instant::now();
    let module = ShaderModule::new(ctx, spirv)?;
    let data = surfaces.map(u32::to_ne_bytes);
    let spec = data.as_ref().map(|data| {
        vk::SpecializationInfo::default()
            .map_entries(&SURFACES_ENTRY)
            .data(data)
    });
    let mut stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module.module)
        .name(c"main");
    if let Some(spec) = &spec {
        stage = stage.specialization_info(spec);
    }
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)];
    // SAFETY: the module and layout are live and match the shader's interface.
    let pipeline = unsafe {
        ctx.device
            .create_compute_pipelines(ctx.pipeline_cache, &info, None)
    }
    .map_err(pipeline_err("vkCreateComputePipelines"))?[0];
    ctx.counters.made_pipeline(start.elapsed());
    Ok(pipeline)
}

/// A ray-tracing pipeline of `desc` with `layout`, SPEC_SURFACES `surfaces` in every stage.
/// Its groups: the ray generation stage, a miss stage per kind of ray, a hit group per kind of
/// ray (the shader binding table's order, `sbt::GroupCounts`).
fn create_ray_tracing<'a>(
    ctx: &Context,
    desc: &RayTracingDesc<'a>,
    layout: vk::PipelineLayout,
    surfaces: u32,
) -> Result<vk::Pipeline, GpuError> {
    type Stage = vk::ShaderStageFlags;
    let rt = ctx.ray_tracing()?;
    ctx.announce_compile();
    let start = Instant::now();
    // Every stage, in group order; a hit group's stages are its closest hit, then its any hit.
    let mut spirv: Vec<(Stage, &'a [u8])> = vec![(Stage::RAYGEN_KHR, desc.raygen)];
    spirv.extend(desc.rays.iter().map(|r| (Stage::MISS_KHR, r.miss)));
    let general = |index: usize| {
        vk::RayTracingShaderGroupCreateInfoKHR::default()
            .ty(vk::RayTracingShaderGroupTypeKHR::GENERAL)
            .general_shader(index as u32)
            .closest_hit_shader(vk::SHADER_UNUSED_KHR)
            .any_hit_shader(vk::SHADER_UNUSED_KHR)
            .intersection_shader(vk::SHADER_UNUSED_KHR)
    };
    let mut groups: Vec<_> = (0..spirv.len()).map(general).collect();
    for ray in desc.rays {
        let mut stage_of = |stage: Stage, code: Option<&'a [u8]>| {
            code.map_or(vk::SHADER_UNUSED_KHR, |code| {
                spirv.push((stage, code));
                spirv.len() as u32 - 1
            })
        };
        let closest = stage_of(Stage::CLOSEST_HIT_KHR, ray.closest_hit);
        let any = stage_of(Stage::ANY_HIT_KHR, ray.any_hit);
        groups.push(
            vk::RayTracingShaderGroupCreateInfoKHR::default()
                .ty(vk::RayTracingShaderGroupTypeKHR::TRIANGLES_HIT_GROUP)
                .general_shader(vk::SHADER_UNUSED_KHR)
                .closest_hit_shader(closest)
                .any_hit_shader(any)
                .intersection_shader(vk::SHADER_UNUSED_KHR),
        );
    }
    let modules = spirv
        .iter()
        .map(|(_, code)| ShaderModule::new(ctx, code))
        .collect::<Result<Vec<_>, _>>()?;
    let data = surfaces.to_ne_bytes();
    let spec = vk::SpecializationInfo::default()
        .map_entries(&SURFACES_ENTRY)
        .data(&data);
    let stages: Vec<_> = spirv
        .iter()
        .zip(&modules)
        .map(|(&(stage, _), module)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(stage)
                .module(module.module)
                .name(c"main")
                .specialization_info(&spec)
        })
        .collect();
    // Only the ray generation stage traces rays.
    let info = [vk::RayTracingPipelineCreateInfoKHR::default()
        .stages(&stages)
        .groups(&groups)
        .max_pipeline_ray_recursion_depth(1)
        .layout(layout)];
    // SAFETY: the modules and layout are live and match the shaders' interface; the groups
    // name stages of `stages`.
    let pipeline = unsafe {
        rt.fns.create_ray_tracing_pipelines(
            vk::DeferredOperationKHR::null(),
            ctx.pipeline_cache,
            &info,
            None,
        )
    }
    .map_err(pipeline_err("vkCreateRayTracingPipelinesKHR"))?[0];
    ctx.counters.made_pipeline(start.elapsed());
    Ok(pipeline)
}

/// The fixed-function state of every scene draw and one pipeline per entry of `stages`
/// (vertex, fragment) for the SURFACE_* bits of the same entry of `surfaces`.
fn create_graphics(
    ctx: &Context,
    desc: &GraphicsDesc<'_>,
    layout: vk::PipelineLayout,
    stages: &[[vk::PipelineShaderStageCreateInfo<'_>; 2]],
    surfaces: &[u32],
) -> Result<Vec<vk::Pipeline>, GpuError> {
    // Vertices are pulled from storage buffers: no vertex input.
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // Double-sided surfaces: no culling, both windings. Single-sided ones cull their back
    // faces: a triangle seen counter-clockwise from the eye (glTF's front,
    // reference::is_back_face) is counter-clockwise in the image, as Vulkan's front face
    // COUNTER_CLOCKWISE takes it; the single-sided quads' tests check it against the CPU.
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let culled = raster.cull_mode(vk::CullModeFlags::BACK);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(desc.depth_compare);
    let blend: Vec<_> = (0..desc.color_attachments)
        .map(|_| {
            vk::PipelineColorBlendAttachmentState::default()
                .blend_enable(false)
                .color_write_mask(vk::ColorComponentFlags::RGBA)
        })
        .collect();
    let blend_state = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let infos: Vec<_> = stages
        .iter()
        .zip(surfaces)
        .map(|(stages, &s)| {
            vk::GraphicsPipelineCreateInfo::default()
                .stages(stages)
                .vertex_input_state(&vertex_input)
                .input_assembly_state(&assembly)
                .viewport_state(&viewport)
                .rasterization_state(if s & SURFACE_SINGLE_SIDED != 0 {
                    &culled
                } else {
                    &raster
                })
                .multisample_state(&multisample)
                .depth_stencil_state(&depth)
                .color_blend_state(&blend_state)
                .dynamic_state(&dynamic)
                .layout(layout)
                .render_pass(desc.render_pass)
                .subpass(0)
        })
        .collect();
    // SAFETY: every referenced state, module, layout and render pass is live.
    unsafe {
        ctx.device
            .create_graphics_pipelines(ctx.pipeline_cache, &infos, None)
    }
    .map_err(pipeline_err("vkCreateGraphicsPipelines"))
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // SAFETY: no submission using these objects is pending; null handles are ignored by
        // the destroy commands; the set is freed with its pool.
        unsafe {
            let d = &self.ctx.device;
            d.destroy_pipeline(self.pipeline, None);
            for &variant in &self.variants {
                d.destroy_pipeline(variant, None);
            }
            d.destroy_pipeline_layout(self.layout, None);
            d.destroy_descriptor_pool(self.pool, None);
            d.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
