//! Where lensray keeps what it measures or compiles once per machine (`auto`'s calibration,
//! the Vulkan pipeline cache): `LENSRAY_CACHE_DIR`, else the platform's cache directory
//! (`$XDG_CACHE_HOME/lensray`, `~/.cache/lensray` on Linux). Whatever is there may be deleted
//! at any time: it is measured or compiled again.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// The cache directory; `None` where the platform has none and the variable is unset.
pub fn dir() -> Option<PathBuf> {
    match std::env::var_os("LENSRAY_CACHE_DIR") {
        Some(dir) if !dir.is_empty() => Some(PathBuf::from(dir)),
        _ => dirs::cache_dir().map(|d| d.join("lensray")),
    }
}

/// Writes `bytes` to `file` whole: to a temporary file in its folder (made if missing), then
/// renamed, so a reader (another lensray running) never sees half of it.
pub fn write_whole(file: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    let folder = file.parent().context("a cache file has a folder")?;
    std::fs::create_dir_all(folder)
        .with_context(|| format!("cannot create {}", folder.display()))?;
    let mut temp = tempfile::NamedTempFile::new_in(folder)
        .with_context(|| format!("cannot write in {}", folder.display()))?;
    temp.write_all(bytes)?;
    temp.persist(file)
        .with_context(|| format!("cannot write {}", file.display()))?;
    Ok(())
}
