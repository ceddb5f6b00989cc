//! The CPU path on each of Embree's instruction sets this CPU runs (`LENSRAY_EMBREE_CONFIG`):
//! `lensray info` names the one Embree runs, the default render agrees across them, and a bad
//! configuration is one line.

use std::path::Path;
use std::process::{Command, Output};

use lensray_core::reference::Isa;

use crate::gpu_support::{compare, write_comparison};
use crate::{read_exr, stderr};

/// The instruction sets CI renders with: Embree's SSE4.2, AVX2 and AVX-512 kernels.
const CI_ISAS: [Isa; 3] = [Isa::Sse42, Isa::Avx2, Isa::Avx512];

fn lensray_with(config: &str, args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lensray"))
        .args(args)
        .current_dir(dir)
        .env("LENSRAY_EMBREE_CONFIG", config)
        .output()
        .expect("run lensray")
}

/// Embree's own name of an instruction set of lensray's, as its verbose output lists targets.
fn embree_target(isa: Isa) -> &'static str {
    match isa {
        Isa::Sse2 => "SSE2",
        Isa::Sse42 => "SSE4.2",
        Isa::Avx => "AVX",
        Isa::Avx2 => "AVX2",
        Isa::Avx512 => "AVX512",
    }
}

/// What Embree runs, from its own words (`verbose=1`): the widest of its compiled-in targets
/// among those it lists as supported under the configuration.
fn embree_says(stdout: &str) -> Isa {
    let targets = |suffix: &str| -> Vec<String> {
        let line = stdout
            .lines()
            .map(str::trim)
            .find(|l| l.ends_with(suffix))
            .unwrap_or_else(|| panic!("no `{suffix}` line in Embree's output:\n{stdout}"));
        let list = line
            .trim_start_matches("Targets :")
            .trim_end_matches(suffix);
        list.split_whitespace().map(str::to_string).collect()
    };
    let (supported, compiled) = (targets("(supported)"), targets("(compile time enabled)"));
    Isa::ALL
        .into_iter()
        .rev()
        .find(|&isa| {
            let name = embree_target(isa).to_string();
            supported.contains(&name) && compiled.contains(&name)
        })
        .unwrap_or_else(|| panic!("no target Embree runs in:\n{stdout}"))
}

/// `lensray info` names the instruction set Embree runs, as Embree itself reports it, for the
/// default configuration and each instruction set set by `isa=`.
#[test]
fn info_names_the_instruction_set_embree_runs() {
    let dir = tempfile::tempdir().unwrap();
    let mut configs = vec![String::new()];
    configs.extend(Isa::on_cpu().iter().map(|isa| format!("isa={isa}")));
    for config in configs {
        let verbose = if config.is_empty() {
            "verbose=1".to_string()
        } else {
            format!("{config},verbose=1")
        };
        let out = lensray_with(&verbose, &["info"], dir.path());
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(out.status.success(), "{verbose}: {}", stderr(&out));
        let ours = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("instruction set"))
            .and_then(|rest| rest.split_whitespace().next())
            .unwrap_or_else(|| panic!("{verbose}: no instruction set line in:\n{text}"));
        assert_eq!(
            Isa::parse(ours),
            Some(embree_says(&text)),
            "{verbose}: lensray says {ours}; Embree's own report:\n{text}"
        );
    }
}

/// Pixels of the default render that may differ between instruction sets, and by how much.
/// Embree's kernels compute t and the barycentrics in other orders per instruction set (a few
/// ulps apart), which moves hit points by ~1e-7 of the scene; a ray grazing an edge or a shadow
/// ray grazing an occluder may then land on the other side, which changes one of a pixel's 16
/// samples: up to 1/16 of the pixel's range, in that pixel alone. Measured on an AMD EPYC
/// (docs/testing.md): SSE4.2 against AVX-512, 1 pixel of 307,200 beyond 1/255 (by 0.052), mean
/// |difference| 8.5e-8; AVX2 against AVX-512, every pixel within 2.4e-7, mean 1.1e-9. The bounds
/// leave room for a few hundred such pixels and 10x the mean.
const ISA_WITHIN: f32 = 1.0 / 255.0;
const ISA_MIN_SHARE_WITHIN: f64 = 0.999;
const ISA_MAX_MEAN_ABS: f64 = 1e-6;

/// The README's default render (the built-in scene, lit, 640x480, 16 spp) on the CPU with each
/// instruction set in `CI_ISAS` the CPU runs agrees with the widest one's.
#[test]
fn default_render_agrees_across_instruction_sets() {
    let dir = tempfile::tempdir().unwrap();
    let isas: Vec<Isa> = CI_ISAS.into_iter().filter(|i| i.on_this_cpu()).collect();
    let images: Vec<(Isa, lensray_core::film::Image)> = isas
        .iter()
        .map(|&isa| {
            let file = format!("default-{isa}.exr");
            let args = [
                "render",
                "--path",
                "cpu",
                "--progress",
                "none",
                "--out",
                &file,
            ];
            let out = lensray_with(&format!("isa={isa}"), &args, dir.path());
            assert!(out.status.success(), "isa={isa}: {}", stderr(&out));
            let summary = String::from_utf8_lossy(&out.stdout).into_owned();
            assert!(
                summary.contains(&format!("Embree {isa}")),
                "the summary names the instruction set: {summary}"
            );
            (isa, read_exr(&dir.path().join(&file)))
        })
        .collect();
    let (widest, reference) = images.last().expect("SSE4.2 at least");
    for (isa, image) in &images[..images.len() - 1] {
        let diff = compare(image, reference, ISA_WITHIN);
        println!("{isa} against {widest}: {diff:?}");
        if diff.within < ISA_MIN_SHARE_WITHIN || diff.mean_abs > ISA_MAX_MEAN_ABS {
            let files = write_comparison(image, reference, &format!("isa-{isa}-vs-{widest}"));
            panic!(
                "{isa} against {widest}: {:.4} % of pixels within {ISA_WITHIN} (bound {} %), \
                 mean |difference| {:e} (bound {ISA_MAX_MEAN_ABS:e}), largest {}; images: {files}",
                diff.within * 100.0,
                ISA_MIN_SHARE_WITHIN * 100.0,
                diff.mean_abs,
                diff.max_abs
            );
        }
    }
}

/// A configuration Embree would ignore, or an instruction set the CPU lacks, is one line and a
/// non-zero exit, before anything renders.
#[test]
fn bad_embree_configuration_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let mut cases = vec![
        ("isa=foo", "not one of Embree's instruction sets"),
        ("threadz=4", "unknown key"),
        ("threads=-1", "not a whole number"),
    ];
    let lacking: Vec<String> = Isa::ALL
        .into_iter()
        .filter(|i| !i.on_this_cpu())
        .map(|i| format!("isa={i}"))
        .collect();
    cases.extend(lacking.iter().map(|c| (c.as_str(), "cannot run")));
    for (config, says) in cases {
        for args in [
            &["render", "--path", "cpu", "--out", "x.png"][..],
            &["info"],
        ] {
            let out = lensray_with(config, args, dir.path());
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(2), "{config} {args:?}: {err}");
            assert_eq!(err.lines().count(), 1, "{config} {args:?}: {err}");
            assert!(
                err.contains("LENSRAY_EMBREE_CONFIG") && err.contains(says),
                "{config}: {err}"
            );
            assert!(!dir.path().join("x.png").exists(), "{config}: left x.png");
        }
    }
}
