// The machinery behind `shader_interface!`. This file is compiled twice: as
// `crate::interface::glsl` and by build.rs (through `include!`), so it uses no crate paths and no
// inner attributes, and needs nothing beyond std and bytemuck.

/// The two GLSL block layouts lensray uses: std140 (uniform blocks) and std430 (storage
/// buffers, push constants).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    Std140,
    Std430,
}

/// How a 32-bit scalar is read back by the layout probe (`floatBitsToUint` or as is).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalarKind {
    Uint,
    Float,
}

/// One 32-bit scalar of a struct: its GLSL access path (`v.cam.world_from_camera[1][2]`) and
/// its byte offset in the Rust value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Scalar {
    pub path: String,
    pub offset: usize,
    pub kind: ScalarKind,
}

/// A Rust type with a GLSL counterpart of the same bytes.
pub trait GlslType {
    /// The GLSL type name.
    const GLSL: &'static str;
    /// Base alignment and size in bytes under `layout` (GLSL 4.60, section 7.6.2.2).
    fn align(layout: Layout) -> usize;
    fn size(layout: Layout) -> usize;
    /// Every scalar of a value at `offset` reached by `path`, in declaration order.
    fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>);
}

macro_rules! glsl_scalar {
    ($rust:ty, $glsl:literal, $kind:ident) => {
        impl GlslType for $rust {
            const GLSL: &'static str = $glsl;
            fn align(_: Layout) -> usize {
                4
            }
            fn size(_: Layout) -> usize {
                4
            }
            fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>) {
                out.push(Scalar {
                    path: path.to_string(),
                    offset,
                    kind: ScalarKind::$kind,
                });
            }
        }
    };
}

glsl_scalar!(u32, "uint", Uint);
glsl_scalar!(f32, "float", Float);

macro_rules! glsl_vec4 {
    ($rust:ty, $glsl:literal, $kind:ident) => {
        impl GlslType for $rust {
            const GLSL: &'static str = $glsl;
            fn align(_: Layout) -> usize {
                16
            }
            fn size(_: Layout) -> usize {
                16
            }
            fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>) {
                for i in 0..4 {
                    out.push(Scalar {
                        path: format!("{path}[{i}]"),
                        offset: offset + 4 * i,
                        kind: ScalarKind::$kind,
                    });
                }
            }
        }
    };
}

glsl_vec4!([f32; 4], "vec4", Float);
glsl_vec4!([u32; 4], "uvec4", Uint);

/// mat4, column-major on both sides (glam's `to_cols_array`): four vec4 columns.
impl GlslType for [f32; 16] {
    const GLSL: &'static str = "mat4";
    fn align(_: Layout) -> usize {
        16
    }
    fn size(_: Layout) -> usize {
        64
    }
    fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>) {
        for column in 0..4 {
            for row in 0..4 {
                out.push(Scalar {
                    path: format!("{path}[{column}][{row}]"),
                    offset: offset + 4 * (4 * column + row),
                    kind: ScalarKind::Float,
                });
            }
        }
    }
}

/// A struct declared by `shader_interface!`.
pub trait GlslStruct: GlslType + Sized {
    /// The layout of the blocks that hold it; `check_layout` holds Rust to it.
    const LAYOUT: Layout;
    /// Fields in declaration order: name, GLSL type, Rust offset, base alignment and size
    /// under `LAYOUT`, doc comment.
    fn fields() -> Vec<Field>;
}

#[derive(Clone, Debug)]
pub struct Field {
    pub name: &'static str,
    pub glsl: &'static str,
    pub rust_offset: usize,
    pub align: usize,
    pub size: usize,
    pub doc: &'static str,
}

pub fn round_up(value: usize, align: usize) -> usize {
    value.div_ceil(align) * align
}

/// A struct's base alignment: its largest member's, rounded up to a vec4's under std140.
pub fn struct_align(layout: Layout, member_aligns: &[usize]) -> usize {
    let align = member_aligns.iter().copied().max().unwrap_or(4);
    match layout {
        Layout::Std140 => round_up(align, 16),
        Layout::Std430 => align,
    }
}

/// A struct's size: its members placed at their alignments, padded to the struct's alignment.
pub fn struct_size(layout: Layout, members: &[(usize, usize)]) -> usize {
    let end = members
        .iter()
        .fold(0, |offset, &(align, size)| round_up(offset, align) + size);
    let aligns: Vec<usize> = members.iter().map(|m| m.0).collect();
    round_up(end, struct_align(layout, &aligns))
}

/// Where GLSL places each field of `S` under `S::LAYOUT`, against where Rust does; an error
/// line per difference.
pub fn check_layout<S: GlslStruct>(errors: &mut Vec<String>) {
    let mut offset = 0;
    for field in S::fields() {
        let glsl_offset = round_up(offset, field.align);
        if glsl_offset != field.rust_offset {
            errors.push(format!(
                "{}.{}: GLSL {:?} puts it at byte {glsl_offset}, Rust at {}",
                S::GLSL,
                field.name,
                S::LAYOUT,
                field.rust_offset
            ));
        }
        offset = glsl_offset + field.size;
    }
    let glsl_size = S::size(S::LAYOUT);
    if glsl_size != std::mem::size_of::<S>() {
        errors.push(format!(
            "{}: GLSL {:?} size {glsl_size} bytes, Rust {}",
            S::GLSL,
            S::LAYOUT,
            std::mem::size_of::<S>()
        ));
    }
}

/// Every scalar of `S` with its GLSL path from a variable named `v`.
pub fn scalars_of<S: GlslStruct>() -> Vec<Scalar> {
    let mut out = Vec::new();
    S::scalars("v", 0, &mut out);
    out
}

/// A constant's GLSL declaration.
pub trait GlslConst {
    fn declaration(&self, name: &str) -> String;
}

impl GlslConst for u32 {
    fn declaration(&self, name: &str) -> String {
        format!("const uint {name} = {self}u;")
    }
}

impl GlslConst for f32 {
    fn declaration(&self, name: &str) -> String {
        // Debug prints the shortest text that reads back as the same f32 ("1e30", "0.0001").
        format!("const float {name} = {self:?};")
    }
}

impl<const N: usize> GlslConst for [u32; N] {
    fn declaration(&self, name: &str) -> String {
        let items: Vec<String> = self.iter().map(|v| format!("{v}u")).collect();
        format!("const uint {name}[{N}] = uint[{N}]({});", items.join(", "))
    }
}

/// Writes the GLSL header: constants, struct declarations and, for the layout probe, one
/// function per struct that stores every scalar into `layout_probe_out`.
pub struct HeaderWriter {
    text: String,
    probes: String,
}

impl Default for HeaderWriter {
    fn default() -> Self {
        Self::new()
    }
}

impl HeaderWriter {
    pub fn new() -> Self {
        Self {
            text: String::from(
                "// GENERATED by build.rs from src/interface/shared.rs: do not edit.\n\
                 // The constants and struct layouts that the host and the shaders share.\n\
                 #ifndef LENSRAY_INTERFACE_GLSL\n#define LENSRAY_INTERFACE_GLSL\n\n",
            ),
            probes: String::new(),
        }
    }

    fn comment(&mut self, doc: &[&str], indent: &str) {
        for line in doc {
            self.text.push_str(&format!("{indent}//{line}\n"));
        }
    }

    pub fn constant<T: GlslConst>(&mut self, name: &str, doc: &[&str], value: T) {
        self.comment(doc, "");
        self.text.push_str(&value.declaration(name));
        self.text.push('\n');
    }

    pub fn structure<S: GlslStruct>(&mut self, doc: &[&str]) {
        self.text.push('\n');
        self.comment(doc, "");
        self.text.push_str(&format!(
            "// {:?}: {} bytes.\nstruct {} {{\n",
            S::LAYOUT,
            S::size(S::LAYOUT),
            S::GLSL
        ));
        for field in S::fields() {
            let doc = field.doc.trim();
            let comment = if doc.is_empty() {
                String::new()
            } else {
                format!("  // {doc}")
            };
            self.text
                .push_str(&format!("    {} {};{comment}\n", field.glsl, field.name));
        }
        self.text.push_str("};\n");

        let scalars = scalars_of::<S>();
        self.probes.push_str(&format!(
            "uint layout_probe_{0}({0} v, uint i) {{\n",
            S::GLSL
        ));
        for (k, s) in scalars.iter().enumerate() {
            let value = match s.kind {
                ScalarKind::Uint => s.path.clone(),
                ScalarKind::Float => format!("floatBitsToUint({})", s.path),
            };
            self.probes
                .push_str(&format!("    layout_probe_out[i + {k}u] = {value};\n"));
        }
        self.probes
            .push_str(&format!("    return i + {}u;\n}}\n", scalars.len()));
    }

    pub fn finish(self) -> String {
        format!(
            "{}\n// For the layout probe (shaders/layout_probe.comp): stores of every scalar.\n\
             #ifdef LENSRAY_LAYOUT_PROBE\n\
             layout(std430, set = 0, binding = LAYOUT_PROBE_BINDING_OUT) writeonly buffer \
             LayoutProbeOut {{ uint layout_probe_out[]; }};\n{}#endif\n\n#endif\n",
            self.text, self.probes
        )
    }
}

/// Declares the constants and structs shared with the shaders, once: the Rust items, the GLSL
/// header (`glsl_header()`), the layout check (`check_layouts()`) and the list of structs.
macro_rules! shader_interface {
    (
        constants {
            $( $(#[doc = $cdoc:literal])* $cname:ident : $cty:ty = $cval:expr; )*
        }
        structs {
            $(
                $(#[doc = $sdoc:literal])*
                $layout:ident struct $sname:ident as $gname:ident {
                    $( $(#[doc = $fdoc:literal])* $fname:ident : $fty:ty ),* $(,)?
                }
            )*
        }
    ) => {
        $( $(#[doc = $cdoc])* pub const $cname: $cty = $cval; )*

        $(
            $(#[doc = $sdoc])*
            #[repr(C)]
            #[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
            pub struct $sname {
                $( $(#[doc = $fdoc])* pub $fname: $fty, )*
            }

            impl GlslType for $sname {
                const GLSL: &'static str = stringify!($gname);
                fn align(layout: Layout) -> usize {
                    struct_align(layout, &[$(<$fty as GlslType>::align(layout)),*])
                }
                fn size(layout: Layout) -> usize {
                    struct_size(
                        layout,
                        &[$((<$fty as GlslType>::align(layout), <$fty as GlslType>::size(layout))),*],
                    )
                }
                fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>) {
                    $(
                        <$fty as GlslType>::scalars(
                            &format!("{path}.{}", stringify!($fname)),
                            offset + std::mem::offset_of!($sname, $fname),
                            out,
                        );
                    )*
                }
            }

            impl GlslStruct for $sname {
                const LAYOUT: Layout = Layout::$layout;
                fn fields() -> Vec<Field> {
                    vec![$(
                        Field {
                            name: stringify!($fname),
                            glsl: <$fty as GlslType>::GLSL,
                            rust_offset: std::mem::offset_of!($sname, $fname),
                            align: <$fty as GlslType>::align(Layout::$layout),
                            size: <$fty as GlslType>::size(Layout::$layout),
                            doc: concat!($($fdoc),*),
                        }
                    ),*]
                }
            }
        )*

        /// The GLSL header `interface.glsl` (written by build.rs, included by the shaders).
        pub fn glsl_header() -> String {
            let mut header = HeaderWriter::new();
            $( header.constant(stringify!($cname), &[$($cdoc),*], $cname); )*
            $( header.structure::<$sname>(&[$($sdoc),*]); )*
            header.finish()
        }

        /// Every field of every shared struct where GLSL expects it (build.rs fails otherwise).
        pub fn check_layouts() -> Result<(), String> {
            let mut errors = Vec::new();
            $( check_layout::<$sname>(&mut errors); )*
            if errors.is_empty() { Ok(()) } else { Err(errors.join("\n")) }
        }
    };
}
