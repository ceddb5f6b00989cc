//! Which files a scene may name. On a desk, any: a file outside the folder of the file that
//! names it (`../textures/wood.png`, an absolute path) is read with one note naming it. A
//! service rendering uploaded scenes confines reads to one folder (`--assets-root DIR`, or
//! `LENSRAY_ASSETS_ROOT`): a file a scene names outside it, by `..`, an absolute path or a
//! link, is refused in one line. The folder holds for the whole process, as the command line
//! sets it.

use std::path::{Component, Path, PathBuf};
use std::sync::OnceLock;

static ASSETS_ROOT: OnceLock<PathBuf> = OnceLock::new();

/// Confines every file a scene names to `root` from now on; the error says why in a few words.
pub fn confine_reads_to(root: &Path) -> Result<(), String> {
    let canonical = root
        .canonicalize()
        .map_err(|e| format!("--assets-root {}: {e}", root.display()))?;
    if !canonical.is_dir() {
        return Err(format!("--assets-root {}: not a folder", root.display()));
    }
    match ASSETS_ROOT.set(canonical.clone()) {
        Ok(()) => Ok(()),
        Err(_) if ASSETS_ROOT.get() == Some(&canonical) => Ok(()),
        Err(_) => Err("the assets root is already set for this process".into()),
    }
}

/// A file a scene names, and the note it is read with, if any.
#[derive(Debug, PartialEq)]
pub struct NamedFile {
    pub path: PathBuf,
    pub note: Option<String>,
}

/// The file `name` (relative to `folder`, or absolute) that a file in `folder` names: refused
/// outside the assets root, noted outside `folder`.
pub fn named_file(folder: &Path, name: &Path) -> Result<NamedFile, String> {
    let path = folder.join(name);
    named_under(ASSETS_ROOT.get().map(PathBuf::as_path), folder, path)
}

fn named_under(root: Option<&Path>, folder: &Path, path: PathBuf) -> Result<NamedFile, String> {
    match root {
        Some(root) => {
            // Links resolved where the file exists; `..` taken away by hand where it does not.
            let resolved = path
                .canonicalize()
                .unwrap_or_else(|_| normalized(&absolute(&path)));
            if resolved.starts_with(root) {
                Ok(NamedFile { path, note: None })
            } else {
                Err(format!(
                    "{} is outside the assets root {} (--assets-root): it is not read",
                    path.display(),
                    root.display()
                ))
            }
        }
        None => {
            let inside = normalized(&absolute(&path)).starts_with(normalized(&absolute(folder)));
            let note = (!inside).then(|| {
                format!(
                    "reads {}, outside the folder of the file that names it",
                    path.display()
                )
            });
            Ok(NamedFile { path, note })
        }
    }
}

fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// `path` with `.` and `..` taken away without asking the file system.
fn normalized(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Without a root, a file beside or below the naming file is read quietly and one outside
    /// its folder with a note; under a root, a file inside it is read, and one outside it by
    /// `..`, an absolute path or a link is refused.
    #[test]
    fn reads_are_noted_outside_the_folder_and_refused_outside_the_root() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let root = dir.path().canonicalize().expect("the folder's path");
        let scene = root.join("scene");
        std::fs::create_dir_all(scene.join("textures")).expect("folders");
        let read = |root: Option<&Path>, name: &str| named_under(root, &scene, scene.join(name));

        assert_eq!(read(None, "textures/wood.png").expect("beside").note, None);
        let note = read(None, "../shared/wood.png").expect("outside").note;
        assert!(note.is_some_and(|n| n.contains("shared/wood.png")));
        assert!(read(None, "/etc/passwd").expect("absolute").note.is_some());

        let confined = Some(root.as_path());
        assert!(read(confined, "textures/wood.png").is_ok());
        assert!(read(confined, "../scene/textures/wood.png").is_ok());
        for outside in ["../../etc/passwd", "/etc/passwd", "textures/../../../x.bin"] {
            let e = read(confined, outside).expect_err(outside);
            assert!(e.contains("outside the assets root"), "{e}");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/etc", scene.join("link")).expect("a link");
            let e = read(confined, "link/passwd").expect_err("through a link");
            assert!(e.contains("outside the assets root"), "{e}");
        }
    }
}
