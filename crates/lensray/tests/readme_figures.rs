//! Every measured figure README.md and the docs quote is the one `scripts/readme_figures.py`
//! computes from the stored runs under docs/bench/, verbatim in one of the pages that quote
//! figures (docs that match the code).

use std::process::Command;

/// The pages that quote figures of the stored runs; each figure must appear in one of them.
const PAGES: [&str; 6] = [
    "README.md",
    "docs/cli.md",
    "docs/performance.md",
    "docs/architecture.md",
    "docs/lenses.md",
    "docs/preview.md",
];

#[test]
fn readme_and_docs_quote_the_stored_bench_figures() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let output = Command::new("python3")
        .arg("scripts/readme_figures.py")
        .arg("--check")
        .args(PAGES)
        .current_dir(root)
        .output()
        .expect("python3 runs scripts/readme_figures.py");
    assert!(
        output.status.success(),
        "{} differ from docs/bench/ ({}):\n{}{}",
        PAGES.join(", "),
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}
