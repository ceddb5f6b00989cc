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

/// An array of vec4 (GLSL's `vec4[N] name;`): 16-byte stride under both layouts.
macro_rules! glsl_vec4_array {
    ($n:literal, $glsl:literal) => {
        impl GlslType for [[f32; 4]; $n] {
            const GLSL: &'static str = $glsl;
            fn align(_: Layout) -> usize {
                16
            }
            fn size(_: Layout) -> usize {
                16 * $n
            }
            fn scalars(path: &str, offset: usize, out: &mut Vec<Scalar>) {
                for i in 0..$n {
                    <[f32; 4]>::scalars(&format!("{path}[{i}]"), offset + 16 * i, out);
                }
            }
        }
    };
}

glsl_vec4_array!(32, "vec4[32]");
glsl_vec4_array!(64, "vec4[64]");

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

/// The kinds of block the layout probe reads a struct through: the one its real users read it
/// through (std140 structs a uniform block, std430 ones a storage buffer), and push constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProbeBlock {
    Uniform,
    Storage,
    PushConstant,
}

impl ProbeBlock {
    /// The block kind whose layout is `layout`, short of push constants.
    pub fn of(layout: Layout) -> Self {
        match layout {
            Layout::Std140 => ProbeBlock::Uniform,
            Layout::Std430 => ProbeBlock::Storage,
        }
    }

    /// A word for GLSL names.
    pub fn short_name(self) -> &'static str {
        match self {
            ProbeBlock::Uniform => "uniform",
            ProbeBlock::Storage => "storage",
            ProbeBlock::PushConstant => "push",
        }
    }
}

/// One block of the layout probe (shaders/probes/layouts.comp, its blocks and `main`
/// generated in `interface.glsl`): `copies` values of struct `structure` (an index in
/// `shared_structs()`; an array, whose second value checks the stride) at descriptor binding
/// `binding` of set 0 (None: the push constants).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ProbeRead {
    pub structure: usize,
    pub block: ProbeBlock,
    pub binding: Option<u32>,
    pub copies: usize,
}

/// The layout probe's output: every scalar it read, then how many it stored.
pub const LAYOUT_PROBE_BINDING_OUT: u32 = 0;
/// Values of each struct in its descriptor block: the second one checks the array stride.
pub const LAYOUT_PROBE_COPIES: usize = 2;
/// Push-constant bytes every Vulkan device has (the least `maxPushConstantsSize`).
pub const MIN_PUSH_CONSTANTS_SIZE: usize = 128;

/// What the layout probe reads, in order: every struct of `structs` through the block kind of
/// its layout (binding LAYOUT_PROBE_BINDING_OUT + 1 + its index), then the one marked
/// `#[layout_probe(push_constant)]` through the push constants.
pub fn layout_probe_reads(structs: &[SharedStruct]) -> Vec<ProbeRead> {
    let blocks = structs.iter().enumerate().map(|(k, s)| ProbeRead {
        structure: k,
        block: ProbeBlock::of(s.layout),
        binding: Some(LAYOUT_PROBE_BINDING_OUT + 1 + k as u32),
        copies: LAYOUT_PROBE_COPIES,
    });
    let push = structs
        .iter()
        .enumerate()
        .filter(|(_, s)| s.probe_push)
        .map(|(k, _)| ProbeRead {
            structure: k,
            block: ProbeBlock::PushConstant,
            binding: None,
            copies: 1,
        });
    blocks.chain(push).collect()
}

/// What the layout probe needs of the list: distinct GLSL names (they name its blocks) and at
/// most one push-constant struct, std430, within MIN_PUSH_CONSTANTS_SIZE.
pub fn check_probe(structs: &[SharedStruct], errors: &mut Vec<String>) {
    for (k, s) in structs.iter().enumerate() {
        if structs[..k].iter().any(|t| t.glsl == s.glsl) {
            errors.push(format!(
                "{}: two shared structs are named {} in GLSL",
                s.rust, s.glsl
            ));
        }
    }
    let pushed: Vec<&SharedStruct> = structs.iter().filter(|s| s.probe_push).collect();
    if pushed.len() > 1 {
        errors.push(format!(
            "the layout probe has one push-constant block, but {} structs are marked for it",
            pushed.len()
        ));
    }
    for s in pushed {
        if s.layout != Layout::Std430 || s.size > MIN_PUSH_CONSTANTS_SIZE {
            errors.push(format!(
                "{}: push constants are std430 and at most {MIN_PUSH_CONSTANTS_SIZE} bytes \
                 everywhere; it is {:?}, {} bytes",
                s.rust, s.layout, s.size
            ));
        }
    }
}

/// Writes the GLSL header: constants, struct declarations and, for the layout probe, one
/// function per struct that stores every scalar into `layout_probe_out`, its blocks and the
/// function that reads them all.
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

    pub fn structure(&mut self, s: &SharedStruct) {
        self.text.push('\n');
        self.comment(s.doc, "");
        self.text.push_str(&format!(
            "// {:?}: {} bytes.\nstruct {} {{\n",
            s.layout, s.size, s.glsl
        ));
        for field in &s.fields {
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

        self.probes.push_str(&format!(
            "uint layout_probe_{0}({0} v, uint i) {{\n",
            s.glsl
        ));
        for (k, scalar) in s.scalars.iter().enumerate() {
            let value = match scalar.kind {
                ScalarKind::Uint => scalar.path.clone(),
                ScalarKind::Float => format!("floatBitsToUint({})", scalar.path),
            };
            self.probes
                .push_str(&format!("    layout_probe_out[i + {k}u] = {value};\n"));
        }
        self.probes
            .push_str(&format!("    return i + {}u;\n}}\n", s.scalars.len()));
    }

    /// The header, with the layout probe's blocks and reads (`layout_probe_reads(structs)`).
    pub fn finish(mut self, structs: &[SharedStruct]) -> String {
        let reads = layout_probe_reads(structs);
        self.probes.push_str(&format!(
            "// Every shared struct through the kind of block its real users read it through, \
             {LAYOUT_PROBE_COPIES} values\n// of each (the second checks the array stride); the \
             marked one through push constants too.\n"
        ));
        let mut calls = String::new();
        for read in &reads {
            let glsl = structs[read.structure].glsl;
            let decl = match (read.block, read.binding) {
                (ProbeBlock::Uniform, Some(b)) => {
                    format!("layout(std140, set = 0, binding = {b}) uniform")
                }
                (ProbeBlock::Storage, Some(b)) => {
                    format!("layout(std430, set = 0, binding = {b}) readonly buffer")
                }
                _ => String::from("layout(push_constant) uniform"),
            };
            let kind = read.block.short_name();
            let name = format!("layout_probe_{kind}_{glsl}");
            let values = if read.block == ProbeBlock::PushConstant {
                calls.push_str(&format!("    i = layout_probe_{glsl}({name}, i);\n"));
                name
            } else {
                for c in 0..read.copies {
                    calls.push_str(&format!("    i = layout_probe_{glsl}({name}[{c}], i);\n"));
                }
                format!("{name}[{}]", read.copies)
            };
            self.probes.push_str(&format!(
                "{decl} LayoutProbe_{kind}_{glsl} {{ {glsl} {values}; }};\n"
            ));
        }
        format!(
            "{}\n// For the layout probe (shaders/probes/layouts.comp, src/gpu/probes/layouts.rs): \
             stores of every scalar.\n\
             #ifdef LENSRAY_LAYOUT_PROBE\n\
             const uint LAYOUT_PROBE_BINDING_OUT = {LAYOUT_PROBE_BINDING_OUT}u;\n\
             layout(std430, set = 0, binding = LAYOUT_PROBE_BINDING_OUT) writeonly buffer \
             LayoutProbeOut {{ uint layout_probe_out[]; }};\n{}\
             // Stores every scalar of every block above in order, then how many it stored.\n\
             void layout_probe_all() {{\n    uint i = 0u;\n{calls}    \
             layout_probe_out[i] = i;\n}}\n#endif\n\n#endif\n",
            self.text, self.probes
        )
    }
}

/// Declares the constants and structs shared with the shaders, once: the Rust items, the GLSL
/// header (`glsl_header()`), the layout check (`check_layouts()`) and the list of structs
/// (`shared_structs()`), from which the layout probe's blocks are generated. A struct marked
/// `#[layout_probe(push_constant)]` (after its doc comment) is read by the probe through push
/// constants too.
macro_rules! shader_interface {
    (
        constants {
            $( $(#[doc = $cdoc:literal])* $cname:ident : $cty:ty = $cval:expr; )*
        }
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
        $( $(#[doc = $cdoc])* pub const $cname: $cty = $cval; )*

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
            $( header.constant(stringify!($cname), &[$($cdoc),*], $cname); )*
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
