//! What the host and the shaders share, defined once: in `constants.rs` the constants (shading
//! modes, workgroup sizes, ray offsets), in `shared.rs` the structs of uniform blocks, push constants and storage
//! buffers; in `bindings.rs` every pipeline's descriptor set, binding by binding. build.rs generates the GLSL header `interface.glsl` from the
//! same definition and refuses to build when Rust lays a struct out differently from GLSL;
//! `shaders/probes/layouts.comp` checks on a device that the shaders read every field where Rust
//! wrote it (lensray-vulkan's tests/renderer/mirrors.rs), through blocks generated from the same list of structs
//! (`shared_structs()`, `glsl::layout_probe_reads`).

#![forbid(unsafe_code)]

#[macro_use]
pub mod glsl;
pub mod bindings;
mod constants;
mod header;
mod shared;

pub use bindings::*;
pub use constants::*;
pub use shared::*;

#[cfg(test)]
mod tests {
    use super::glsl::*;
    use super::*;

    #[test]
    fn layouts_follow_the_glsl_rules() {
        check_layouts().unwrap();
        // Hand-computed std140: two mat4 (128) + 8 scalars (32) + two vec4 (32) + vec4[32]
        // (512) + the motion's 4 scalars (16) and two vec4[8] (256) = 976; then two vec4
        // (background, environment), eight scalars and the footprint's four vec4.
        assert_eq!(GpuCamera::size(Layout::Std140), 976);
        assert_eq!(TraceParams::size(Layout::Std140), 976 + 32 + 32 + 64);
        assert_eq!(RasterPush::size(Layout::Std430), 96);
        // The view pass's push constants stay within the 128 bytes every device offers.
        assert_eq!(ViewPush::size(Layout::Std430), 128);
        assert_eq!(std::mem::offset_of!(TraceParams, width), 1008);
    }

    #[test]
    fn std140_rounds_a_scalar_struct_to_16_bytes() {
        // A struct of one uint is 4 bytes in std430, 16 in std140 (rule 9).
        assert_eq!(struct_size(Layout::Std430, &[(4, 4)]), 4);
        assert_eq!(struct_size(Layout::Std140, &[(4, 4)]), 16);
        // uint then vec4: the vec4 is aligned to 16.
        assert_eq!(struct_size(Layout::Std430, &[(4, 4), (16, 16)]), 32);
    }

    #[test]
    fn header_declares_every_constant_and_struct() {
        let header = glsl_header();
        assert!(header.contains("const uint TRACE_GROUP_SIZE = 8u;"));
        assert!(header.contains("const float T_MAX = 1e30;"));
        assert!(header.contains("struct TraceParams {\n    Camera camera;"));
        assert!(header.contains("uint layout_probe_uniform_Camera_stores(uint c, uint i)"));
        assert!(header.contains("uint layout_probe_push_TracePush_stores(uint i)"));
        let scalars = scalars_of::<TraceParams>();
        assert_eq!(scalars.len(), 976 / 4 + 8 + 8 + 16);
        assert_eq!(scalars[17].path, "v.camera.screen_from_raster[0][1]");
        assert_eq!(scalars[17].offset, 64 + 4);
    }

    #[test]
    fn layout_probe_reads_every_struct() {
        let structs = shared_structs();
        let reads = layout_probe_reads(&structs);
        let header = glsl_header();
        for (k, s) in structs.iter().enumerate() {
            let read = reads.iter().find(|r| r.structure == k).expect(s.rust);
            assert_eq!(read.block, ProbeBlock::of(s.layout), "{}", s.rust);
            assert_eq!(read.copies, LAYOUT_PROBE_COPIES);
            let kind = read.block.short_name();
            for c in 0..read.copies {
                let call = format!("i = layout_probe_{kind}_{0}_stores({c}u, i);", s.glsl);
                assert!(header.contains(&call), "{call}");
            }
        }
        let mut bindings: Vec<u32> = reads.iter().filter_map(|r| r.binding).collect();
        bindings.push(LAYOUT_PROBE_BINDING_OUT);
        bindings.sort_unstable();
        bindings.dedup();
        assert_eq!(bindings.len(), structs.len() + 1, "bindings must differ");
        let pushed: Vec<&ProbeRead> = reads
            .iter()
            .filter(|r| r.block == ProbeBlock::PushConstant)
            .collect();
        assert_eq!(pushed.len(), 1);
        assert_eq!(structs[pushed[0].structure].rust, "TracePush");
        assert!(header.contains(
            "layout(push_constant) uniform LayoutProbe_push_TracePush { TracePush \
             layout_probe_push_TracePush; };"
        ));
        assert!(header.contains(
            "layout(std140, set = 0, binding = 1) uniform LayoutProbe_uniform_Camera { Camera \
             layout_probe_uniform_Camera[2]; };"
        ));
    }

    #[test]
    fn the_probe_list_refuses_a_second_or_oversized_push() {
        let mut structs = shared_structs();
        let mut errors = Vec::new();
        check_probe(&structs, &mut errors);
        assert!(errors.is_empty(), "{errors:?}");
        let view_push = structs.iter_mut().find(|s| s.rust == "ViewPush").unwrap();
        view_push.probe_push = true;
        view_push.size = 132;
        check_probe(&structs, &mut errors);
        assert_eq!(errors.len(), 2, "{errors:?}");
    }
}
