//! What the host and the shaders share, defined once in `shared.rs`: constants (shading modes,
//! binding numbers, workgroup sizes, ray offsets) and the structs of uniform blocks, push
//! constants and storage buffers. build.rs generates the GLSL header `interface.glsl` from the
//! same definition and refuses to build when Rust lays a struct out differently from GLSL;
//! `shaders/layout_probe.comp` checks on a device that the shaders read every field where Rust
//! wrote it (tests/gpu.rs).

#[macro_use]
pub mod glsl;
mod shared;

pub use shared::*;

#[cfg(test)]
mod tests {
    use super::glsl::*;
    use super::*;

    #[test]
    fn layouts_follow_the_glsl_rules() {
        check_layouts().unwrap();
        // Hand-computed std140: two mat4 (128) + 4 scalars = 144; then three vec4 and four
        // scalars.
        assert_eq!(GpuCamera::size(Layout::Std140), 144);
        assert_eq!(TraceParams::size(Layout::Std140), 144 + 48 + 32);
        assert_eq!(RasterPush::size(Layout::Std430), 96);
        assert_eq!(std::mem::offset_of!(TraceParams, width), 192);
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
        assert!(header.contains("const uint TRACE_BINDING_PARAMS = 8u;"));
        assert!(header.contains("const float T_MAX = 1e30;"));
        assert!(header.contains("struct TraceParams {\n    Camera camera;"));
        assert!(header.contains("uint layout_probe_Camera(Camera v, uint i)"));
        let scalars = scalars_of::<TraceParams>();
        assert_eq!(scalars.len(), 144 / 4 + 12 + 8);
        assert_eq!(scalars[17].path, "v.camera.screen_from_raster[0][1]");
        assert_eq!(scalars[17].offset, 64 + 4);
    }
}
