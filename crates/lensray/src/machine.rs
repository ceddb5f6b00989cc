//! The machine lensray runs on: what a bench's report names and what `auto`'s calibration is
//! kept for.

use serde::Serialize;

#[derive(Clone, Debug, Serialize)]
pub struct Machine {
    /// The CPU's model name (Linux: /proc/cpuinfo), or "unknown".
    pub cpu: String,
    /// Threads the process may run at once.
    pub threads: usize,
    /// The operating system's name (Linux: /etc/os-release), else Rust's name for it.
    pub os: String,
    pub arch: &'static str,
}

pub fn describe() -> Machine {
    let field = |file: &str, key: &str| -> Option<String> {
        let text = std::fs::read_to_string(file).ok()?;
        text.lines().find_map(|line| {
            let (k, v) = line.split_once([':', '='])?;
            (k.trim() == key).then(|| v.trim().trim_matches('"').to_string())
        })
    };
    Machine {
        cpu: field("/proc/cpuinfo", "model name").unwrap_or_else(|| "unknown".into()),
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        os: field("/etc/os-release", "PRETTY_NAME").unwrap_or_else(|| std::env::consts::OS.into()),
        arch: std::env::consts::ARCH,
    }
}
