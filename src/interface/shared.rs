// The one definition of what the host and the shaders share: constants, binding numbers,
// workgroup sizes and the structs of uniform blocks, push constants and storage buffers.
// build.rs writes `interface.glsl` from it; the shaders include that, so a shader that names a
// constant or field that is gone here fails to build. Compiled twice (crate and build.rs):
// no crate paths, no inner attributes.

use super::glsl::*;

shader_interface! {
    constants {
        /// Shading modes traced by the compute pass (`render::Shading`).
        SHADING_UNLIT: u32 = 0;
        SHADING_LIT: u32 = 1;
        /// `Camera.projection`.
        PROJECTION_PERSPECTIVE: u32 = 0;
        PROJECTION_ORTHOGRAPHIC: u32 = 1;
        /// Bit 31 of a triangle's info word: its mesh has vertex normals. Bits 0..30: material.
        TRI_HAS_NORMALS: u32 = 0x8000_0000;
        /// Far end of camera rays on the GPU (ray queries take a finite tMax; the CPU uses
        /// infinity, which no scene within f32 range can tell apart).
        T_MAX: f32 = 1e30;
        /// Shadow rays start this far off the surface along the facing geometric normal, times
        /// (1 + the largest coordinate magnitude): float spacing grows with the coordinates.
        SHADOW_ORIGIN_OFFSET: f32 = 1e-4;
        PI: f32 = std::f32::consts::PI;

        /// What the preview window shows (`preview::ViewMode`, shaders/resolve.comp): the
        /// thin-lens accumulation, a G-buffer AOV, or each pixel's circle of confusion.
        VIEW_FINAL: u32 = 0;
        VIEW_ALBEDO: u32 = 1;
        VIEW_NORMAL: u32 = 2;
        VIEW_DEPTH: u32 = 3;
        VIEW_COC: u32 = 4;

        /// Workgroups: trace.comp is TRACE_GROUP_SIZE x TRACE_GROUP_SIZE (a coherent tile).
        TRACE_GROUP_SIZE: u32 = 8;
        PROBE_GROUP_SIZE: u32 = 64;

        /// Scene arrays (shaders/scene.glsl), in the set the including shader names.
        SCENE_BINDING_POSITIONS: u32 = 0;
        SCENE_BINDING_NORMALS: u32 = 1;
        SCENE_BINDING_INDICES: u32 = 2;
        SCENE_BINDING_TRI_INFO: u32 = 3;
        SCENE_BINDING_MATERIALS: u32 = 4;
        /// trace.comp: after the scene arrays.
        TRACE_BINDING_TLAS: u32 = 5;
        TRACE_BINDING_ACCUM: u32 = 6;
        TRACE_BINDING_COUNTERS: u32 = 7;
        TRACE_BINDING_PARAMS: u32 = 8;
        /// probe.comp.
        PROBE_BINDING_QUERIES: u32 = 0;
        PROBE_BINDING_RESULTS: u32 = 1;
        PROBE_BINDING_CAMERA: u32 = 2;
        /// resolve.comp (the preview): the accumulation, the G-buffer images, the display image.
        RESOLVE_GROUP_SIZE: u32 = 8;
        RESOLVE_BINDING_ACCUM: u32 = 0;
        RESOLVE_BINDING_NORMAL: u32 = 1;
        RESOLVE_BINDING_ALBEDO: u32 = 2;
        RESOLVE_BINDING_VIEW_DEPTH: u32 = 3;
        RESOLVE_BINDING_DISPLAY: u32 = 4;
        /// layout_probe.comp.
        LAYOUT_PROBE_BINDING_OUT: u32 = 0;
        LAYOUT_PROBE_BINDING_PARAMS: u32 = 1;
        LAYOUT_PROBE_BINDING_RASTER: u32 = 2;
        LAYOUT_PROBE_BINDING_MATERIALS: u32 = 3;
    }
    structs {
        /// The camera as the shaders see it (shaders/camera.glsl); there is no second camera:
        /// the matrices are the Rust camera's.
        Std140 struct GpuCamera as Camera {
            world_from_camera: [f32; 16],
            screen_from_raster: [f32; 16],
            /// PROJECTION_*
            projection: u32,
            near_z: f32,
            aperture_radius: f32,
            focus_distance: f32,
        }
        /// The uniform block of trace.comp.
        Std140 struct TraceParams as TraceParams {
            camera: GpuCamera,
            background: [f32; 4],
            light_position: [f32; 4],
            /// W/sr per channel.
            light_intensity: [f32; 4],
            width: u32,
            height: u32,
            seed: u32,
            /// SHADING_*
            shading: u32,
        }
        /// Push constants of one trace.comp dispatch: the blocks of TRACE_GROUP_SIZE rows
        /// block_first + i * block_stride (i < block_count) of the band of band_height rows from
        /// image row band_origin (the accumulation buffer holds that band), samples
        /// sample_begin..sample_end.
        Std430 struct TracePush as TracePush {
            band_origin: u32,
            band_height: u32,
            block_first: u32,
            block_stride: u32,
            block_count: u32,
            sample_begin: u32,
            sample_end: u32,
            pad: u32,
        }
        /// Push constants of the G-buffer pass.
        Std430 struct RasterPush as RasterPush {
            clip_from_world: [f32; 16],
            eye: [f32; 4],
            /// xyz: the view axis; w: 1 orthographic (viewer direction is the axis), 0 perspective.
            forward: [f32; 4],
        }
        /// Push constants of resolve.comp: what to show and the lens data of the circle of
        /// confusion (camera.glsl's coc_radius_pixels mirrors Camera::coc_radius_pixels).
        Std430 struct ResolvePush as ResolvePush {
            width: u32,
            height: u32,
            /// VIEW_*
            view: u32,
            /// PROJECTION_*
            projection: u32,
            aperture_radius: f32,
            focus_distance: f32,
            near_z: f32,
            far_z: f32,
            /// Pixels per screen-space unit (height / screen window height).
            pixels_per_screen_unit: f32,
            /// The circle-of-confusion radius, in pixels, shown as white.
            coc_display_max: f32,
            pad0: u32,
            pad1: u32,
        }
        /// A material of the scene's storage buffer.
        Std430 struct GpuMaterial as Material {
            /// Kd
            diffuse: [f32; 4],
            /// Ke
            emission: [f32; 4],
        }
    }
}
