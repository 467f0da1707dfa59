//! Writing an output folder so that nothing is half-written and no reader ever sees old and new
//! results mixed. Every file goes first into a staging folder beside the output folder; when all
//! are complete, the staging folder and the output folder trade places in one atomic rename
//! (Linux `renameat2(RENAME_EXCHANGE)`), so the folder's path names the old set or the new set,
//! never a mix. The user's own files in the folder (anything not named as this program names its
//! outputs nor listed in the folder's manifest, [`MANIFEST`]) are carried over: files as hard
//! links before the exchange (present throughout), folders moved after it. The old folder is
//! then removed. A write stopped between the exchange and the end (Ctrl-C, kill) is completed by
//! the next write into the same folder, which moves back what the user's was and removes the
//! rest ([`swap::recover`]).
//!
//! Where the exchange is not possible (not Linux, a file system without it, an output folder
//! that is a mount point or the working directory, a parent folder not writable) the files are
//! renamed into the folder one by one (each atomic), the staging folder inside it.
//!
//! Either way the new set replaces the previous one as a whole: files of an earlier write that
//! the new set does not have are gone, so no frame of an older run is left beside the new ones.
//! Other files in the folder are left alone. A set may own fewer of the program's names
//! ([`Outputs`]): `render --all`'s frames replace rendered frames only, a solve's report and
//! VTUs beside them stay.

mod swap;

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

/// Whether `name` is a frame `render --all` writes: `frame_` followed by a four-digit (or longer)
/// frame number and `.png`.
pub fn is_frame_image_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|rest| rest.strip_suffix(".png"))
        .is_some_and(|number| number.len() >= 4 && number.bytes().all(|b| b.is_ascii_digit()))
}

/// Which of a folder's files a set replaces: those it writes, and those of the same kind an
/// earlier write left there (gone when the new set lacks them). The rest is the user's: kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outputs {
    /// Every name this program gives its outputs ([`is_output_name`]) and every name the
    /// folder's manifest lists: a solve's folder, the viewer's exports.
    All,
    /// Rendered frames only ([`is_frame_image_name`]; `prehensile render --all`): a solve's
    /// report, VTUs and OBJs in the same folder are left as they are.
    FrameImages,
}

impl Outputs {
    /// Whether `name` is one of the files a set of this kind writes.
    fn names(self, name: &str) -> bool {
        match self {
            Outputs::All => is_output_name(name),
            Outputs::FrameImages => is_frame_image_name(name),
        }
    }
}

/// Files to be written together into one folder.
pub struct OutputSet {
    /// The folder as the caller named it (the paths returned).
    dir: PathBuf,
    /// The folder itself, every link resolved (what is exchanged).
    real: PathBuf,
    staging: PathBuf,
    /// The staging folder is beside the output folder: the sets may be exchanged whole.
    beside: bool,
    /// The folders were exchanged: the staging folder's path holds the old set.
    exchanged: bool,
    /// The folders this set created (the output folder and the parents it lacked), deepest
    /// first: removed again, if still empty, when the set is abandoned (a run that fails
    /// leaves no empty folder behind); cleared once committed.
    created: Vec<PathBuf>,
    names: Vec<String>,
    /// Which files of the folder the set replaces.
    outputs: Outputs,
}

impl OutputSet {
    /// Prepares to write into `dir` (created if missing, with its parents). Completes or removes
    /// what earlier writes into it left when their process ended before they finished.
    pub fn new(dir: &Path) -> std::io::Result<Self> {
        Self::of(dir, Outputs::All)
    }

    /// [`Self::new`] for a set replacing only the `outputs` of the folder.
    pub fn of(dir: &Path, outputs: Outputs) -> std::io::Result<Self> {
        // A name that is already something else than a folder (a file, a link to nothing or to
        // itself) is told as such, not as the creation's "file exists".
        if std::fs::symlink_metadata(dir).is_ok() {
            match std::fs::metadata(dir) {
                Ok(m) if m.is_dir() => {}
                Ok(_) => {
                    return Err(std::io::Error::other(
                        "it is a file, not a folder: name a folder for the results",
                    ))
                }
                Err(e) => {
                    return Err(std::io::Error::other(format!(
                        "it is a link that leads to no folder ({e})"
                    )))
                }
            }
        }
        let created: Vec<PathBuf> = dir
            .ancestors()
            .filter(|d| !d.as_os_str().is_empty())
            .take_while(|d| std::fs::symlink_metadata(d).is_err())
            .map(Path::to_path_buf)
            .collect();
        std::fs::create_dir_all(dir)?;
        let real = std::fs::canonicalize(dir)?;
        swap::recover(&real);
        remove_abandoned_staging(&real);
        let beside = swap::staging_beside(&real)
            .filter(|_| swap::may_exchange(&real))
            .filter(|s| fresh_folder(s).is_ok());
        let (staging, beside) = match beside {
            Some(s) => (s, true),
            None => {
                let s = real.join(format!(".staging-{}", std::process::id()));
                fresh_folder(&s)?;
                (s, false)
            }
        };
        Ok(Self {
            dir: dir.to_path_buf(),
            real,
            staging,
            beside,
            exchanged: false,
            created,
            names: Vec::new(),
            outputs,
        })
    }

    /// Writes one file into the staging folder. `name` must be one this program gives its
    /// outputs of the set's kind ([`is_output_name`], [`Outputs`]): a later write recognises its
    /// files by their names.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> std::io::Result<()> {
        if !self.outputs.names(name) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{name} is not a name of this program's outputs"),
            ));
        }
        std::fs::write(self.staging.join(name), bytes)?;
        self.names.push(name.to_string());
        Ok(())
    }

    /// Puts the staged set in place of the folder's previous one, as a whole: by exchanging
    /// the folders where possible, else file by file; records the set in [`MANIFEST`].
    /// Returns the paths of the files written.
    pub fn commit(self) -> std::io::Result<Vec<PathBuf>> {
        self.commit_as(true)
    }

    /// [`Self::commit`], exchanging the folders only when `exchange` (and possible).
    fn commit_as(mut self, exchange: bool) -> std::io::Result<Vec<PathBuf>> {
        let written = self.commit_staged(exchange)?;
        self.created.clear();
        Ok(written)
    }

    /// [`Self::commit_as`]'s work.
    fn commit_staged(&mut self, exchange: bool) -> std::io::Result<Vec<PathBuf>> {
        // A name the folder holds as something else than a file (a folder) would stop the
        // renames halfway, old and new files mixed: refused before any is moved.
        for name in &self.names {
            let target = self.real.join(name);
            if std::fs::symlink_metadata(&target).is_ok_and(|m| m.is_dir()) {
                return Err(std::io::Error::other(format!(
                    "{} is a folder, where this output's file {name} goes: move it away (nothing \
                     was replaced)",
                    self.dir.join(name).display()
                )));
            }
        }
        let manifest: String = self.names.iter().map(|n| format!("{n}\n")).collect();
        std::fs::write(self.staging.join(MANIFEST), manifest)?;
        let written = self.names.iter().map(|n| self.dir.join(n)).collect();
        let exchanged = match exchange && self.beside {
            true => swap::exchange(&self.real, &self.staging, &self.names, self.outputs)?,
            false => None,
        };
        if let Some(permissions) = exchanged {
            // The staging folder's path now holds the old set (and what of the user's could
            // not be linked): the user's entries go to the new one, then the old is removed.
            // What could not be moved stays there for the next write's recovery. The new
            // folder then takes the old one's permissions.
            self.exchanged = true;
            if swap::carry_over(&self.staging, &self.real, self.outputs) {
                std::fs::remove_dir_all(&self.staging)?;
            }
            std::fs::set_permissions(&self.real, permissions)?;
            return Ok(written);
        }
        self.commit_file_by_file()?;
        Ok(written)
    }

    /// Moves every staged file into place (each rename is atomic), removes the files of an
    /// earlier write that the new set lacks, then the manifest and the staging folder.
    fn commit_file_by_file(&self) -> std::io::Result<()> {
        let stale = self.stale()?;
        for name in &self.names {
            std::fs::rename(self.staging.join(name), self.real.join(name))?;
        }
        for name in stale {
            match std::fs::remove_file(self.real.join(&name)) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
                _ => {}
            }
        }
        std::fs::rename(self.staging.join(MANIFEST), self.real.join(MANIFEST))?;
        std::fs::remove_dir_all(&self.staging)
    }

    /// The files of the set's kind an earlier write left in the folder that the new set does
    /// not replace.
    fn stale(&self) -> std::io::Result<Vec<String>> {
        let listed = manifest_names(&self.real);
        let mut stale: Vec<String> = listed
            .iter()
            .filter(|n| is_ours(n, &listed, self.outputs))
            .cloned()
            .collect();
        for entry in std::fs::read_dir(&self.real)? {
            let entry = entry?;
            if !entry.file_type()?.is_file() {
                continue;
            }
            if let Some(name) = entry.file_name().to_str() {
                if self.outputs.names(name) {
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

/// The names the manifest of folder `dir` lists (those that stay inside the folder).
fn manifest_names(dir: &Path) -> Vec<String> {
    std::fs::read_to_string(dir.join(MANIFEST))
        .unwrap_or_default()
        .lines()
        .filter(|n| !n.is_empty() && !n.contains(['/', '\\']) && *n != "." && *n != "..")
        .map(str::to_string)
        .collect()
}

/// Whether the entry `name` of a folder whose manifest lists `listed` was written by this
/// program as `outputs` (an output of that kind, the manifest): the rest is the user's.
fn is_ours(name: &str, listed: &[String], outputs: Outputs) -> bool {
    name == MANIFEST
        || outputs.names(name)
        || (outputs == Outputs::All && listed.iter().any(|n| n == name))
}

/// Creates `path` as an empty folder (emptied if it was there).
fn fresh_folder(path: &Path) -> std::io::Result<()> {
    if std::fs::symlink_metadata(path).is_ok() {
        std::fs::remove_dir_all(path)?;
    }
    std::fs::create_dir(path)
}

/// Removes the staging folders a write into `dir` left when its process ended before it
/// finished (stopped with Ctrl-C, killed: no destructor ran): `.staging-<pid>` of a process that
/// no longer runs.
fn remove_abandoned_staging(dir: &Path) {
    for folder in abandoned_staging(dir, b".staging-") {
        let _ = std::fs::remove_dir_all(folder);
    }
}

/// The folders of `dir` named `prefix` followed by the id of a process that no longer runs
/// (staging folders whose write was stopped); empty where the running processes cannot be
/// listed (no `/proc`).
fn abandoned_staging(dir: &Path, prefix: &[u8]) -> Vec<PathBuf> {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return Vec::new();
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter(|entry| {
            let name = entry.file_name();
            let ended = name
                .as_encoded_bytes()
                .strip_prefix(prefix)
                .and_then(|pid| std::str::from_utf8(pid).ok())
                .filter(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
                .is_some_and(|pid| !proc.join(pid).exists());
            ended && entry.file_type().is_ok_and(|t| t.is_dir())
        })
        .map(|entry| entry.path())
        .collect()
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        // Abandoned before commit (an error): leave no staging folder behind. After the
        // exchange its path holds the old set, removed by the commit when all of the user's
        // entries were carried over, else kept for the next write's recovery.
        if !self.exchanged {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
        // The folders it created, if nothing else went into them (`remove_dir` removes only
        // an empty folder).
        for d in &self.created {
            if std::fs::remove_dir(d).is_err() {
                break;
            }
        }
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

    /// A set abandoned before its commit (the run failed while writing) removes the folders it
    /// created for the results, if nothing else went into them; one committed keeps them, and
    /// a folder that was there before stays.
    #[test]
    fn an_abandoned_set_leaves_no_empty_folder_it_created() {
        let top = std::env::temp_dir().join(format!("prehensile-created-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&top);
        std::fs::create_dir_all(&top).unwrap();
        let dir = top.join("a").join("b");
        let mut set = OutputSet::new(&dir).unwrap();
        set.write("report.json", b"{}").unwrap();
        assert!(dir.is_dir());
        drop(set);
        assert!(!top.join("a").exists(), "the folders it made are gone");
        assert!(top.is_dir(), "the folder that was there stays");
        // Something of the user's put in meanwhile: that folder stays.
        let set = OutputSet::new(&dir).unwrap();
        std::fs::write(top.join("a").join("notes.txt"), "mine").unwrap();
        drop(set);
        assert!(!dir.exists() && top.join("a").join("notes.txt").exists());
        // Committed: kept.
        let mut set = OutputSet::new(&dir).unwrap();
        set.write("report.json", b"{}").unwrap();
        set.commit().unwrap();
        assert_eq!(std::fs::read(dir.join("report.json")).unwrap(), b"{}");
        let _ = std::fs::remove_dir_all(&top);
    }

    /// A fresh folder under the temporary folder for test `tag`.
    fn scratch(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("prehensile-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Writes generation `g` of a set of `frames` frames into `dir`.
    fn write_set(dir: &Path, g: usize, frames: usize, exchange: bool) {
        let mut set = OutputSet::new(dir).unwrap();
        set.write("report.json", format!("{g}").as_bytes()).unwrap();
        for i in 0..frames {
            set.write(&format!("frame_{i:04}.vtu"), format!("{g}").as_bytes())
                .unwrap();
        }
        set.commit_as(exchange).unwrap();
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .collect();
        names.sort();
        names
    }

    /// Both ways of committing leave the same folder: the new set, its manifest, the user's
    /// file, folder and link; no frame of the older, longer run; nothing beside the folder.
    #[test]
    fn a_set_replaces_the_last_one_whole_and_keeps_the_users_entries() {
        for exchange in [true, false] {
            let root = scratch(&format!("replace-{exchange}"));
            let dir = root.join("out");
            write_set(&dir, 1, 5, exchange);
            std::fs::write(dir.join("notes.txt"), "mine").unwrap();
            std::fs::create_dir(dir.join("mine")).unwrap();
            std::fs::write(dir.join("mine").join("frame_0000.vtu"), "mine").unwrap();
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                std::os::unix::fs::symlink("notes.txt", dir.join("link")).unwrap();
                std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o750)).unwrap();
            }
            write_set(&dir, 2, 2, exchange);
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                let mode = std::fs::metadata(&dir).unwrap().permissions().mode() & 0o777;
                assert_eq!(mode, 0o750, "the folder keeps its permissions");
            }
            let mut expected = vec![
                MANIFEST,
                "frame_0000.vtu",
                "frame_0001.vtu",
                "mine",
                "notes.txt",
                "report.json",
            ];
            if cfg!(unix) {
                expected.push("link");
            }
            expected.sort();
            assert_eq!(listing(&dir), expected, "exchange {exchange}");
            assert_eq!(std::fs::read(dir.join("frame_0001.vtu")).unwrap(), b"2");
            assert_eq!(std::fs::read(dir.join("notes.txt")).unwrap(), b"mine");
            assert_eq!(
                std::fs::read(dir.join("mine").join("frame_0000.vtu")).unwrap(),
                b"mine"
            );
            #[cfg(unix)]
            assert_eq!(std::fs::read(dir.join("link")).unwrap(), b"mine");
            assert_eq!(listing(&root), ["out"], "nothing left beside the folder");
            let _ = std::fs::remove_dir_all(&root);
        }
    }

    /// A reader that opens the folder while sets are committed in turn sees one generation in
    /// every snapshot, never old and new files mixed (file by file, it does see them mixed).
    #[cfg(target_os = "linux")]
    #[test]
    fn a_reader_never_sees_two_sets_mixed() {
        let root = scratch("mixed");
        let dir = root.join("out");
        write_set(&dir, 0, 8, true);
        let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let reader = {
            let (dir, done) = (dir.clone(), done.clone());
            std::thread::spawn(move || {
                use std::os::fd::AsRawFd;
                let mut snapshots = 0;
                while !done.load(std::sync::atomic::Ordering::Relaxed) {
                    // The folder opened once: its files read through it, whatever its path
                    // names meanwhile.
                    let Ok(folder) = std::fs::File::open(&dir) else {
                        continue;
                    };
                    let at = PathBuf::from(format!("/proc/self/fd/{}", folder.as_raw_fd()));
                    let mut seen = std::collections::BTreeSet::new();
                    for entry in std::fs::read_dir(&at).into_iter().flatten().flatten() {
                        let name = entry.file_name().to_string_lossy().to_string();
                        if is_output_name(&name) {
                            if let Ok(text) = std::fs::read_to_string(at.join(&name)) {
                                seen.insert(text);
                            }
                        }
                    }
                    assert!(seen.len() <= 1, "a snapshot mixes generations {seen:?}");
                    snapshots += 1;
                }
                snapshots
            })
        };
        for g in 1..=60 {
            write_set(&dir, g, 8, true);
        }
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        let snapshots = reader.join().unwrap();
        assert!(snapshots > 0);
        assert_eq!(std::fs::read(dir.join("report.json")).unwrap(), b"60");
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A write killed after the exchange left the old set beside the folder with the user's
    /// folder still in it: the next write moves that folder back and removes the rest. One
    /// killed before the exchange left the new set there: removed, the folder untouched.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_write_stopped_half_way_is_completed_by_the_next() {
        let root = scratch("recover");
        let dir = root.join("out");
        write_set(&dir, 1, 2, true);
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        // After the exchange: the old set with the user's folder, beside the new one.
        let dead = root.join(".out.staging-999999999");
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join("frame_0005.vtu"), "0").unwrap();
        std::fs::write(dead.join("extra.dat"), "0").unwrap();
        std::fs::write(dead.join(MANIFEST), "extra.dat\nframe_0005.vtu\n").unwrap();
        std::fs::hard_link(dir.join("notes.txt"), dead.join("notes.txt")).unwrap();
        std::fs::create_dir(dead.join("mine")).unwrap();
        std::fs::write(dead.join("mine").join("a.txt"), "mine").unwrap();
        let set = OutputSet::new(&dir).unwrap();
        drop(set);
        assert!(!dead.exists());
        assert_eq!(
            std::fs::read(dir.join("mine").join("a.txt")).unwrap(),
            b"mine"
        );
        assert!(!dir.join("extra.dat").exists() && !dir.join("frame_0005.vtu").exists());

        // Before the exchange: a new set not yet in place.
        let before = listing(&dir);
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join("frame_0000.vtu"), "9").unwrap();
        std::fs::hard_link(dir.join("notes.txt"), dead.join("notes.txt")).unwrap();
        drop(OutputSet::new(&dir).unwrap());
        assert!(!dead.exists());
        assert_eq!(listing(&dir), before);
        assert_eq!(std::fs::read(dir.join("frame_0000.vtu")).unwrap(), b"1");
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A file, a link in a loop: refused saying what the name is, nothing created.
    #[test]
    fn a_name_that_is_no_folder_is_told_as_such() {
        let root = scratch("nofolder");
        std::fs::write(root.join("afile"), "mine").unwrap();
        let e = OutputSet::new(&root.join("afile")).err().unwrap();
        assert!(e.to_string().contains("a file, not a folder"), "{e}");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("loop", root.join("loop")).unwrap();
            let e = OutputSet::new(&root.join("loop")).err().unwrap();
            assert!(
                e.to_string().contains("a link that leads to no folder"),
                "{e}"
            );
        }
        assert_eq!(std::fs::read(root.join("afile")).unwrap(), b"mine");
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A set of rendered frames replaces the frames of an earlier, longer one and nothing else:
    /// a solve's report and VTUs in the same folder stay, both ways of committing.
    #[test]
    fn frame_images_replace_frame_images_only() {
        for exchange in [true, false] {
            let root = scratch(&format!("frames-{exchange}"));
            let dir = root.join("out");
            write_set(&dir, 1, 2, exchange);
            let frames = |n: usize| {
                let mut set = OutputSet::of(&dir, Outputs::FrameImages).unwrap();
                for i in 0..n {
                    set.write(&format!("frame_{i:04}.png"), b"png").unwrap();
                }
                assert!(set.write("report.json", b"{}").is_err(), "not a frame");
                set.commit_as(exchange).unwrap();
            };
            frames(3);
            frames(1);
            assert_eq!(
                listing(&dir),
                [
                    MANIFEST,
                    "frame_0000.png",
                    "frame_0000.vtu",
                    "frame_0001.vtu",
                    "report.json"
                ],
                "exchange {exchange}"
            );
            assert_eq!(std::fs::read(dir.join("frame_0001.vtu")).unwrap(), b"1");
            assert_eq!(listing(&root), ["out"], "nothing left beside the folder");
            let _ = std::fs::remove_dir_all(&root);
        }
    }

    #[test]
    fn only_output_names_are_written() {
        let root = scratch("names");
        let mut set = OutputSet::new(&root.join("out")).unwrap();
        let e = set.write("notes.txt", b"x").unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        drop(set);
        let _ = std::fs::remove_dir_all(&root);
    }
}
