//! Every measured figure README.md quotes is the one `scripts/readme_figures.py` computes from
//! the stored runs under docs/bench/, verbatim (docs that match the code).

use std::process::Command;

#[test]
fn readme_quotes_the_stored_bench_figures() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let output = Command::new("python3")
        .args(["scripts/readme_figures.py", "--check", "README.md"])
        .current_dir(root)
        .output()
        .expect("python3 runs scripts/readme_figures.py");
    assert!(
        output.status.success(),
        "README.md differs from docs/bench/ ({}):\n{}{}",
        output.status,
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}
