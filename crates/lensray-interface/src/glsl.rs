// The machinery behind `shader_interface!`: the GLSL types and block layouts of the shared
// structs, and the macro that declares them (the header's text and the layout probe are in
// `header.rs`).

// What `shader_interface!`'s expansion and the crate's users (`interface::glsl::*`) name; a
// glob, as build.rs uses only part of it.
pub use super::header::*;

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

/// An array of vec4 or uvec4 (GLSL's `vec4[N] name;`): 16-byte stride under both layouts.
macro_rules! glsl_vec4_array {
    ($element:ty, $n:literal, $glsl:literal) => {
        impl GlslType for [$element; $n] {
            const GLSL: &'static str = $glsl;
            fn align(_: Layout) -> usize {
                16
            }
            fn size(_: Layout) -> usize {
                16 * $n
            }
            fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>) {
                for i in 0..$n {
                    <$element>::scalars(&format!("{path}[{i}]"), offset + 16 * i, out);
                }
            }
        }
    };
}

glsl_vec4_array!([f32; 4], 3, "vec4[3]");
glsl_vec4_array!([f32; 4], 8, "vec4[8]");
glsl_vec4_array!([f32; 4], 32, "vec4[32]");
glsl_vec4_array!([f32; 4], 64, "vec4[64]");
glsl_vec4_array!([f32; 4], 256, "vec4[256]");
glsl_vec4_array!([u32; 4], 4, "uvec4[4]");

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
        format!("const float {name} = {};", glsl_float(*self))
    }
}

impl<const N: usize> GlslConst for [u32; N] {
    fn declaration(&self, name: &str) -> String {
        let items: Vec<String> = self.iter().map(|v| format!("{v}u")).collect();
        format!("const uint {name}[{N}] = uint[{N}]({});", items.join(", "))
    }
}

impl<const N: usize> GlslConst for [f32; N] {
    fn declaration(&self, name: &str) -> String {
        let items: Vec<String> = self.iter().map(|&v| glsl_float(v)).collect();
        format!(
            "const float {name}[{N}] = float[{N}]({});",
            items.join(", ")
        )
    }
}

/// A GLSL literal of `v` that glslang reads back as `v` itself. Debug prints the shortest text
/// that reads back as the same f32 when read as an f32; glslang reads a literal as an f64 and
/// rounds that to f32, which can round twice, so the text is checked that way too and more
/// digits are written where the shortest text fails.
pub fn glsl_float(v: f32) -> String {
    assert!(v.is_finite(), "a GLSL float literal of {v}");
    let reads_back = |text: &str| text.parse::<f64>().map(|x| x as f32) == Ok(v);
    let shortest = format!("{v:?}");
    if reads_back(&shortest) {
        return shortest;
    }
    // Seventeen significant digits are the f64 nearest `v`, exactly `v`.
    let long = format!("{v:.16e}");
    assert!(reads_back(&long), "no GLSL literal reads back as {v:?}");
    long
}

/// One struct of `shader_interface!`'s list, as the GLSL header and the layout probe take it.
#[derive(Clone, Debug)]
pub struct SharedStruct {
    /// The Rust name (`GpuCamera`) and the GLSL one (`Camera`).
    pub rust: &'static str,
    pub glsl: &'static str,
    pub layout: Layout,
    /// Bytes in Rust, which `check_layouts` holds to the GLSL size under `layout`; also the
    /// stride of an array of it (a struct's size is a multiple of its alignment).
    pub size: usize,
    pub doc: &'static [&'static str],
    pub fields: Vec<Field>,
    /// Every scalar in declaration order (`scalars_of`).
    pub scalars: Vec<Scalar>,
    /// Marked `#[layout_probe(push_constant)]`: the layout probe reads it through its
    /// push-constant block too.
    pub probe_push: bool,
}

impl SharedStruct {
    pub fn of<S: GlslStruct>(
        rust: &'static str,
        doc: &'static [&'static str],
        probe_push: bool,
    ) -> Self {
        Self {
            rust,
            glsl: S::GLSL,
            layout: S::LAYOUT,
            size: std::mem::size_of::<S>(),
            doc,
            fields: S::fields(),
            scalars: scalars_of::<S>(),
            probe_push,
        }
    }
}

/// The value of a `#[layout_probe(...)]` mark (none: false).
macro_rules! layout_probe_push {
    () => {
        false
    };
    (push_constant) => {
        true
    };
}

/// Declares the constants shared with the shaders, once: the Rust items and
/// `declare_constants`, which writes them into the GLSL header.
macro_rules! shader_constants {
    ( $( $(#[doc = $cdoc:literal])* $cname:ident : $cty:ty = $cval:expr; )* ) => {
        $( $(#[doc = $cdoc])* pub const $cname: $cty = $cval; )*

        /// Declares every shared constant in the GLSL header, in the order of their list.
        pub(crate) fn declare_constants(header: &mut HeaderWriter) {
            $( header.constant(stringify!($cname), &[$($cdoc),*], $cname); )*
        }
    };
}

/// Declares the structs shared with the shaders, once: the Rust items, the GLSL
/// header (`glsl_header()`, with the constants of `shader_constants!`), the layout check (`check_layouts()`) and the list of structs
/// (`shared_structs()`), from which the layout probe's blocks are generated. A struct marked
/// `#[layout_probe(push_constant)]` (after its doc comment) is read by the probe through push
/// constants too.
macro_rules! shader_interface {
    (
        structs {
            $(
                $(#[doc = $sdoc:literal])*
                $(#[layout_probe($probe:ident)])?
                $layout:ident struct $sname:ident as $gname:ident {
                    $( $(#[doc = $fdoc:literal])* $fname:ident : $fty:ty ),* $(,)?
                }
            )*
        }
    ) => {
        $(
            $(#[doc = $sdoc])*
            #[repr(C)]
            #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
            pub struct $sname {
                $( $(#[doc = $fdoc])* pub $fname: $fty, )*
            }

            /// All zeros (arrays longer than 32 have no derived `Default`).
            impl Default for $sname {
                fn default() -> Self {
                    bytemuck::Zeroable::zeroed()
                }
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

        /// Every shared struct, in declaration order: what the GLSL header declares and the
        /// layout probe reads (`layout_probe_reads`).
        pub fn shared_structs() -> Vec<SharedStruct> {
            vec![$(
                SharedStruct::of::<$sname>(
                    stringify!($sname),
                    &[$($sdoc),*],
                    layout_probe_push!($($probe)?),
                )
            ),*]
        }

        /// The GLSL header `interface.glsl` (written by build.rs, included by the shaders).
        pub fn glsl_header() -> String {
            let mut header = HeaderWriter::new();
            declare_constants(&mut header);
            let structs = shared_structs();
            for s in &structs {
                header.structure(s);
            }
            header.finish(&structs)
        }

        /// Every field of every shared struct where GLSL expects it, and the list fit for the
        /// layout probe (build.rs fails otherwise).
        pub fn check_layouts() -> Result<(), String> {
            let mut errors = Vec::new();
            $( check_layout::<$sname>(&mut errors); )*
            check_probe(&shared_structs(), &mut errors);
            if errors.is_empty() { Ok(()) } else { Err(errors.join("\n")) }
        }
    };
}
