//! Writing an output folder so that nothing is half-written: every file goes first into a
//! staging folder beside it, and is renamed into place only when all files are complete. The
//! new set replaces the previous one as a whole: files of an earlier write into the folder
//! (listed in its manifest, [`MANIFEST`], or named as this program names its outputs) that the
//! new set does not have are removed, so no frame of an older run is left beside the new ones.
//! Other files in the folder are left alone.

use std::path::{Path, PathBuf};

/// The file listing what the last write into a folder put there.
pub const MANIFEST: &str = ".prehensile-output";

/// Whether `name` is one this program gives its outputs: `report.json`, `frames.pvd`,
/// `animation.glb`, and
/// `frame_`, `hand_`, `bones_`, `skin_` followed by a four-digit (or longer) frame number and
/// `.vtu`, `.obj` or `.png`.
pub fn is_output_name(name: &str) -> bool {
    if matches!(name, "report.json" | "frames.pvd" | "animation.glb") {
        return true;
    }
    let Some((stem, ext)) = name.rsplit_once('.') else {
        return false;
    };
    if !matches!(ext, "vtu" | "obj" | "png") {
        return false;
    }
    let Some((kind, number)) = stem.split_once('_') else {
        return false;
    };
    matches!(kind, "frame" | "hand" | "bones" | "skin")
        && number.len() >= 4
        && number.bytes().all(|b| b.is_ascii_digit())
}

/// Files to be written together into one folder.
pub struct OutputSet {
    dir: PathBuf,
    staging: PathBuf,
    names: Vec<String>,
}

impl OutputSet {
    /// Prepares to write into `dir` (created if missing, with its parents).
    pub fn new(dir: &Path) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        remove_abandoned_staging(dir);
        let staging = dir.join(format!(".staging-{}", std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging)?;
        }
        std::fs::create_dir(&staging)?;
        Ok(Self {
            dir: dir.to_path_buf(),
            staging,
            names: Vec::new(),
        })
    }

    /// Writes one file into the staging folder.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> std::io::Result<()> {
        std::fs::write(self.staging.join(name), bytes)?;
        self.names.push(name.to_string());
        Ok(())
    }

    /// Moves every staged file into place (each rename is atomic), removes the files of an
    /// earlier write that the new set lacks, records the new set in [`MANIFEST`] and removes
    /// the staging folder.
    pub fn commit(self) -> std::io::Result<Vec<PathBuf>> {
        // A name the folder holds as something else than a file (a folder) would stop the
        // renames halfway, old and new files mixed: refused before any is moved.
        for name in &self.names {
            let target = self.dir.join(name);
            if std::fs::symlink_metadata(&target).is_ok_and(|m| m.is_dir()) {
                return Err(std::io::Error::other(format!(
                    "{} is a folder, where this output's file {name} goes: move it away (nothing \
                     was replaced)",
                    target.display()
                )));
            }
        }
        let stale = self.stale()?;
        let mut written = Vec::new();
        for name in &self.names {
            let target = self.dir.join(name);
            std::fs::rename(self.staging.join(name), &target)?;
            written.push(target);
        }
        for name in stale {
            match std::fs::remove_file(self.dir.join(&name)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
                _ => {}
            }
        }
        let manifest: String = self.names.iter().map(|n| format!("{n}\n")).collect();
        std::fs::write(self.staging.join(MANIFEST), manifest)?;
        std::fs::rename(self.staging.join(MANIFEST), self.dir.join(MANIFEST))?;
        std::fs::remove_dir_all(&self.staging)?;
        Ok(written)
    }

    /// The files of the folder an earlier write left that the new set does not replace.
    fn stale(&self) -> std::io::Result<Vec<String>> {
        let listed = std::fs::read_to_string(self.dir.join(MANIFEST)).unwrap_or_default();
        let mut stale: Vec<String> = listed
            .lines()
            .filter(|n| !n.is_empty() && !n.contains(['/', '\\']) && *n != "." && *n != "..")
            .map(str::to_string)
            .collect();
        for entry in std::fs::read_dir(&self.dir)? {
            let entry = entry?;
            if !entry.file_type()?.is_file() {
                continue;
            }
            if let Some(name) = entry.file_name().to_str() {
                if is_output_name(name) {
                    stale.push(name.to_string());
                }
            }
        }
        stale.retain(|n| !self.names.contains(n));
        stale.sort();
        stale.dedup();
        Ok(stale)
    }
}

/// Removes the staging folders a write into `dir` left when its process ended before it
/// finished (stopped with Ctrl-C, killed: no destructor ran): `.staging-<pid>` of a process that
/// no longer runs. Where the running processes cannot be listed (no `/proc`), none is removed.
fn remove_abandoned_staging(dir: &Path) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix(".staging-"))
            .filter(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
        else {
            continue;
        };
        if entry.file_type().is_ok_and(|t| t.is_dir()) && !proc.join(pid).exists() {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        // Abandoned before commit (an error): leave no staging folder behind.
        let _ = std::fs::remove_dir_all(&self.staging);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A write stopped by Ctrl-C leaves its staging folder; the next write into the folder
    /// removes it, and leaves a running process's (pid 1) and other folders alone.
    #[test]
    fn a_staging_folder_left_by_a_process_that_ended_is_removed() {
        let dir = std::env::temp_dir().join(format!("prehensile-staging-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        // pid_max is at most 2²² on Linux: no process has this pid.
        let dead = dir.join(".staging-999999999");
        let running = dir.join(".staging-1");
        let mine = dir.join("results-of-mine");
        for d in [&dead, &running, &mine] {
            std::fs::create_dir_all(d).unwrap();
            std::fs::write(d.join("frame_0000.vtu"), "half").unwrap();
        }
        let mut set = OutputSet::new(&dir).unwrap();
        set.write("report.json", b"{}").unwrap();
        set.commit().unwrap();
        assert!(!dead.exists(), "the abandoned staging folder is gone");
        if Path::new("/proc/1").exists() {
            assert!(running.exists(), "a running process's staging folder stays");
        }
        assert!(mine.join("frame_0000.vtu").exists());
        assert_eq!(std::fs::read(dir.join("report.json")).unwrap(), b"{}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
