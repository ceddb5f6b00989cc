// The GLSL header writer and the layout probe it declares: which blocks the probe reads each
// shared struct through, the checks the list of structs must pass for it, and the text of
// `interface.glsl`.

use super::glsl::{GlslConst, Layout, Scalar, ScalarKind, SharedStruct};

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

/// The layout probe reads an array of at least this many scalars in a loop.
const PROBE_LOOP_SCALARS: usize = 32;

/// A scalar's path from its struct (`.cam.world_from_camera[1][2]`).
fn probe_path(scalar: &Scalar) -> &str {
    scalar
        .path
        .strip_prefix('v')
        .expect("a scalar's path starts at the value `v`")
}

/// The probe's stored value of the scalar of `kind` at `path` in `block`: its bits.
fn probe_value(kind: ScalarKind, block: &str, path: &str) -> String {
    match kind {
        ScalarKind::Uint => format!("{block}{path}"),
        ScalarKind::Float => format!("floatBitsToUint({block}{path})"),
    }
}

/// An array's scalars, in order: `len` elements at `prefix[a]`, each the scalars `element`
/// (their kinds and their paths after the index).
struct ArrayRun<'a> {
    prefix: &'a str,
    len: usize,
    element: Vec<(ScalarKind, &'a str)>,
}

/// The array whose first element's first scalar starts `scalars`, as far as its elements
/// follow in order with the same scalars; `None` where `scalars[0]` is no array's element 0.
fn array_run(scalars: &[Scalar]) -> Option<ArrayRun<'_>> {
    // (prefix, index, suffix) of a path with an index.
    let split = |path: &str| -> Option<(usize, usize)> {
        let open = path.find('[')?;
        let close = open + path[open..].find(']')?;
        Some((open, close))
    };
    let first = probe_path(&scalars[0]);
    let (open, close) = split(first)?;
    if &first[open + 1..close] != "0" {
        return None;
    }
    let prefix = &first[..open];
    let parts = |scalar: &'_ Scalar| -> Option<(String, usize)> {
        let path = probe_path(scalar);
        let (open, close) = split(path)?;
        let index = path[open + 1..close].parse().ok()?;
        (&path[..open] == prefix).then(|| (path[close + 1..].to_string(), index))
    };
    let element: Vec<(ScalarKind, &str)> = scalars
        .iter()
        .map_while(|scalar| {
            let path = probe_path(scalar);
            let (open, close) = split(path)?;
            (&path[..open] == prefix && &path[open + 1..close] == "0")
                .then(|| (scalar.kind, &path[close + 1..]))
        })
        .collect();
    let m = element.len();
    let mut len = 1;
    while let Some(next) = scalars.get(len * m..(len + 1) * m) {
        let same = next.iter().zip(&element).all(|(scalar, &(kind, suffix))| {
            scalar.kind == kind && parts(scalar) == Some((suffix.to_string(), len))
        });
        if !same {
            break;
        }
        len += 1;
    }
    Some(ArrayRun {
        prefix,
        len,
        element,
    })
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
                "// GENERATED by build.rs from lensray-interface (constants.rs, shared.rs): do not edit.\n\
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
    }

    /// The probe's function for `s` read through the block `block` (an element of its array
    /// indexed by `c`, or the push constants' block): it stores every scalar straight from the
    /// block. A copy of the struct passed by value (thousands of scalars for `Lens`) made lavapipe
    /// compile the probe for minutes.
    fn probe_function(&mut self, s: &SharedStruct, name: &str, indexed: bool) {
        let (param, block) = if indexed {
            ("uint c, ", format!("{name}[c]"))
        } else {
            ("", name.to_string())
        };
        self.probes
            .push_str(&format!("uint {name}_stores({param}uint i) {{\n"));
        let mut k = 0;
        while k < s.scalars.len() {
            match array_run(&s.scalars[k..]) {
                Some(run) if run.len * run.element.len() >= PROBE_LOOP_SCALARS => {
                    // One loop over the array's elements: lavapipe's compile time grows faster
                    // than the straight-line code (the lens's tables are 3000 scalars).
                    self.probes.push_str(&format!(
                        "    [[dont_unroll]] for (uint a = 0u; a < {}u; ++a) {{\n",
                        run.len
                    ));
                    let m = run.element.len();
                    for (j, scalar) in run.element.iter().enumerate() {
                        let path = format!("{}[a]{}", run.prefix, scalar.1);
                        let value = probe_value(scalar.0, &block, &path);
                        self.probes.push_str(&format!(
                            "        layout_probe_out[i + {k}u + a * {m}u + {j}u] = {value};\n"
                        ));
                    }
                    self.probes.push_str("    }\n");
                    k += run.len * m;
                }
                _ => {
                    let scalar = &s.scalars[k];
                    let value = probe_value(scalar.kind, &block, probe_path(scalar));
                    self.probes
                        .push_str(&format!("    layout_probe_out[i + {k}u] = {value};\n"));
                    k += 1;
                }
            }
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
            let pushed = read.block == ProbeBlock::PushConstant;
            let values = if pushed {
                calls.push_str(&format!("    i = {name}_stores(i);\n"));
                name.clone()
            } else {
                for c in 0..read.copies {
                    calls.push_str(&format!("    i = {name}_stores({c}u, i);\n"));
                }
                format!("{name}[{}]", read.copies)
            };
            self.probes.push_str(&format!(
                "{decl} LayoutProbe_{kind}_{glsl} {{ {glsl} {values}; }};\n"
            ));
            self.probe_function(&structs[read.structure], &name, !pushed);
        }
        format!(
            "{}\n// For the layout probe (shaders/probes/layouts.comp, lensray-vulkan/src/probes/layouts.rs): \
             stores of every scalar.\n\
             #ifdef LENSRAY_LAYOUT_PROBE\n\
             #extension GL_EXT_control_flow_attributes : require\n\
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

#[cfg(test)]
mod tests {
    use super::*;

    fn scalar(path: &str, kind: ScalarKind) -> Scalar {
        Scalar {
            path: path.to_string(),
            offset: 0,
            kind,
        }
    }

    #[test]
    fn an_array_s_elements_make_one_run() {
        let mut scalars = vec![];
        for a in 0..8 {
            for k in 0..4 {
                scalars.push(scalar(&format!("v.table[{a}][{k}]"), ScalarKind::Float));
            }
        }
        scalars.push(scalar("v.count", ScalarKind::Uint));
        let run = array_run(&scalars).expect("an array");
        assert_eq!((run.prefix, run.len), (".table", 8));
        let suffixes: Vec<&str> = run.element.iter().map(|e| e.1).collect();
        assert_eq!(suffixes, ["[0]", "[1]", "[2]", "[3]"]);
        assert!(
            array_run(&scalars[32..]).is_none(),
            "a field outside any array"
        );
        assert!(
            array_run(&scalars[4..]).is_none(),
            "an element other than the first"
        );
    }

    #[test]
    fn a_run_stops_where_the_elements_differ() {
        let scalars = [
            scalar("v.lights[0].power", ScalarKind::Float),
            scalar("v.lights[0].kind", ScalarKind::Uint),
            scalar("v.lights[1].power", ScalarKind::Float),
            scalar("v.lights[1].kind", ScalarKind::Uint),
            scalar("v.lights[2].power", ScalarKind::Float),
            scalar("v.other[0].kind", ScalarKind::Uint),
        ];
        let run = array_run(&scalars).expect("an array");
        assert_eq!((run.len, run.element.len()), (2, 2));
    }

    #[test]
    fn the_probe_reads_the_lens_tables_in_loops() {
        let header = crate::glsl_header();
        let lens = header
            .split("uint layout_probe_storage_Lens_stores(uint c, uint i) {")
            .nth(1)
            .and_then(|rest| rest.split("\n}\n").next())
            .expect("the lens's stores");
        assert!(lens.contains(
            "    [[dont_unroll]] for (uint a = 0u; a < 32u; ++a) {\n        \
             layout_probe_out[i + 44u + a * 4u + 0u] = \
             floatBitsToUint(layout_probe_storage_Lens[c].surface_shape[a][0]);"
        ));
        // Fewer than 3119 straight-line stores: the tables are loops.
        assert!(lens.lines().count() < 200, "{} lines", lens.lines().count());
    }
}
