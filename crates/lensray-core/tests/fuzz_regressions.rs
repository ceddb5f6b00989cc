//! Every crash the fuzzers found (fuzz/regressions/TARGET) through the target's own code, on
//! the stable toolchain: each loads or is refused, without a panic. The corpus (fuzz/corpus,
//! some 3000 inputs, about 10 s here) is replayed by scripts/fuzz.sh in CI instead;
//! docs/testing.md ("Fuzzing") says how the fuzzers run.

use std::fs;
use std::panic::catch_unwind;
use std::path::{Path, PathBuf};

#[path = "../../../fuzz/src/targets.rs"]
mod targets;

/// The files of `folder`, by name; none where it does not exist.
fn files(folder: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(folder)
        .map(|entries| entries.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    files.sort();
    files
}

#[test]
fn every_crash_the_fuzzers_found_loads_or_is_refused() {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz");
    // The targets write each input's files under this folder, removed when the test ends.
    let scratch = tempfile::tempdir().expect("a scratch folder");
    std::env::set_var("LENSRAY_FUZZ_DIR", scratch.path());
    let mut ran = 0;
    let mut panicked = Vec::new();
    for (target, run) in targets::TARGETS {
        for file in files(&fuzz.join("regressions").join(target)) {
            let bytes = fs::read(&file).expect("a fuzz input reads");
            if catch_unwind(|| run(&bytes)).is_err() {
                panicked.push(format!("{target}: {}", file.display()));
            }
            ran += 1;
        }
    }
    assert!(ran > 0, "no regressions under {}", fuzz.display());
    assert!(
        panicked.is_empty(),
        "inputs that panic:\n{}",
        panicked.join("\n")
    );
}
