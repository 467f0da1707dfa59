//! Writing an output folder so that nothing is half-written: every file goes first into a
//! staging folder beside it, and is renamed into place only when all files are complete.

use std::path::{Path, PathBuf};

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

    /// Moves every staged file into place (each rename is atomic) and removes the staging folder.
    pub fn commit(self) -> std::io::Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for name in &self.names {
            let target = self.dir.join(name);
            std::fs::rename(self.staging.join(name), &target)?;
            written.push(target);
        }
        std::fs::remove_dir_all(&self.staging)?;
        Ok(written)
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        // Abandoned before commit (an error): leave no staging folder behind.
        let _ = std::fs::remove_dir_all(&self.staging);
    }
}
