//! [`RasterPasses`]: the renderer's passes that rasterize or read the raster, each made on its
//! first use (a traced render compiles no raster pipeline): the G-buffer (AOVs, focus picking,
//! the hybrid's plan, the preview), the raster path's visibility pass (which the hybrid's lit
//! pre-pass uses too), and the hybrid's plan pass. Each is reached through the function that
//! makes it, or, once made, through one that says whether it is.

use std::sync::Arc;

use crate::core::device::Context;
use crate::core::error::GpuError;
use crate::passes::gbuffer::{GBufferPass, GBufferTargets};
use crate::passes::hybrid_plan::HybridPlanPass;
use crate::passes::trace::TracePass;
use crate::passes::visibility::VisibilityPass;
use crate::scene::SceneBuffers;

pub(super) struct RasterPasses {
    ctx: Arc<Context>,
    gbuffer: Option<GBufferPass>,
    visibility: Option<VisibilityPass>,
    hybrid_plan: Option<HybridPlanPass>,
}

/// The passes that record the hybrid's plan, as `RasterPasses::prepare_hybrid_plan` left them:
/// the G-buffer pass, its targets, and the plan pass bound to them.
pub(super) struct PlanPasses<'p> {
    pub(super) gbuffer: &'p GBufferPass,
    pub(super) targets: &'p GBufferTargets,
    pub(super) plan: &'p HybridPlanPass,
}

/// The pass in `slot`, made by `make` on its first use.
fn made<T>(
    slot: &mut Option<T>,
    make: impl FnOnce() -> Result<T, GpuError>,
) -> Result<&mut T, GpuError> {
    match slot {
        Some(pass) => Ok(pass),
        None => Ok(slot.insert(make()?)),
    }
}

/// A G-buffer pass, bound to `scene` when one is loaded.
fn new_gbuffer(ctx: &Arc<Context>, scene: Option<&SceneBuffers>) -> Result<GBufferPass, GpuError> {
    let pass = GBufferPass::new(ctx)?;
    if let Some(scene) = scene {
        pass.bind_scene(scene);
    }
    Ok(pass)
}

impl RasterPasses {
    /// None made yet.
    pub(super) fn new(ctx: &Arc<Context>) -> Self {
        Self {
            ctx: ctx.clone(),
            gbuffer: None,
            visibility: None,
            hybrid_plan: None,
        }
    }

    /// Points the passes made so far at a newly loaded scene (the later ones bind it when
    /// made).
    pub(super) fn bind_scene(&self, scene: &SceneBuffers) {
        if let Some(gbuffer) = &self.gbuffer {
            gbuffer.bind_scene(scene);
        }
        if let Some(visibility) = &self.visibility {
            visibility.bind_scene(scene);
        }
    }

    /// The G-buffer pass, made (and bound to `scene`, when one is loaded) on first use.
    pub(super) fn gbuffer_pass(
        &mut self,
        scene: Option<&SceneBuffers>,
    ) -> Result<&mut GBufferPass, GpuError> {
        made(&mut self.gbuffer, || new_gbuffer(&self.ctx, scene))
    }

    /// The G-buffer pass, once made.
    pub(super) fn gbuffer(&self) -> Option<&GBufferPass> {
        self.gbuffer.as_ref()
    }

    /// The G-buffer's targets, once made.
    pub(super) fn gbuffer_targets(&self) -> Option<&GBufferTargets> {
        self.gbuffer.as_ref().and_then(|g| g.targets.as_ref())
    }

    /// The visibility pass, once made (`prepare_visibility`).
    pub(super) fn visibility(&self) -> Option<&VisibilityPass> {
        self.visibility.as_ref()
    }

    /// Makes the visibility pass (on first use, bound to `scene`) and its targets for a `width`
    /// x `height` image, bound to `trace` when new.
    pub(super) fn prepare_visibility(
        &mut self,
        scene: &SceneBuffers,
        trace: &mut TracePass,
        (width, height): (u32, u32),
    ) -> Result<(), GpuError> {
        let visibility = made(&mut self.visibility, || {
            let pass = VisibilityPass::new(&self.ctx)?;
            pass.bind_scene(scene);
            Ok(pass)
        })?;
        if let Some(targets) = visibility.ensure_targets(width, height)? {
            trace.pipelines.bind_visibility(&targets.buffer);
        }
        Ok(())
    }

    /// Makes what the hybrid's plan of a `width` x `height` image needs, each on first use: the
    /// plan pass (only the hybrid compiles its pipeline), the G-buffer's targets, and `trace`'s
    /// plan buffers; binds the plan pass to the targets and the plan buffers (`plan_passes`
    /// then records with them). No submission using the plan pass may be pending.
    pub(super) fn prepare_hybrid_plan(
        &mut self,
        scene: Option<&SceneBuffers>,
        trace: &mut TracePass,
        (width, height): (u32, u32),
    ) -> Result<(), GpuError> {
        let plan = made(&mut self.hybrid_plan, || HybridPlanPass::new(&self.ctx))?;
        let gbuffer = made(&mut self.gbuffer, || new_gbuffer(&self.ctx, scene))?;
        let targets = gbuffer.ensure_targets(width, height)?;
        trace.ensure_plan_capacity(u64::from(width) * u64::from(height))?;
        plan.bind(targets, trace.plan.plan(), trace.plan.surface_depth())
    }

    /// What records the hybrid's plan, once `prepare_hybrid_plan` made it.
    pub(super) fn plan_passes(&self) -> Result<PlanPasses<'_>, GpuError> {
        match (&self.gbuffer, &self.hybrid_plan) {
            (Some(gbuffer), Some(plan)) => Ok(PlanPasses {
                gbuffer,
                targets: gbuffer.targets.as_ref().ok_or_else(plan_not_prepared)?,
                plan,
            }),
            _ => Err(plan_not_prepared()),
        }
    }
}

fn plan_not_prepared() -> GpuError {
    GpuError::Invalid("the hybrid's plan passes are not prepared (prepare_hybrid_plan)".into())
}
