//! The output folder and its staging folder trading places in one rename (Linux
//! `renameat2(RENAME_EXCHANGE)`), the user's entries carried from the old folder to the new, and
//! the recovery of a write stopped half-way.

use super::{abandoned_staging, is_ours, manifest_names, Outputs};
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The staging folder of this process beside the output folder `real`:
/// `<parent>/.<name>.staging-<pid>`.
pub(super) fn staging_beside(real: &Path) -> Option<PathBuf> {
    let parent = real.parent()?;
    let mut name = OsString::from(".");
    name.push(real.file_name()?);
    name.push(format!(".staging-{}", std::process::id()));
    Some(parent.join(name))
}

/// Whether the folder `real` may be exchanged: on Linux, when it is not a mount point (the
/// staging folder beside it would be on another file system) nor this process's working
/// directory or one of its parents (the process, and the shell it was started from, would be
/// left in the old folder).
pub(super) fn may_exchange(real: &Path) -> bool {
    if !cfg!(target_os = "linux") {
        return false;
    }
    let inside = std::env::current_dir()
        .and_then(std::fs::canonicalize)
        .is_ok_and(|cwd| cwd.starts_with(real));
    !inside && real.parent().is_some_and(|p| same_device(real, p))
}

#[cfg(unix)]
fn same_device(a: &Path, b: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_device(_: &Path, _: &Path) -> bool {
    false
}

/// Links the user's files of `real` (not the program's `outputs`, not named in `names`) into `staging`
/// and exchanges the two folders. Returns the permissions `real` had (for the caller to give
/// the new folder once the user's entries are carried over: a read-only folder would refuse
/// them), or `None` when the exchange is not possible here (nothing was moved; the caller
/// renames file by file).
pub(super) fn exchange(
    real: &Path,
    staging: &Path,
    names: &[String],
    outputs: Outputs,
) -> std::io::Result<Option<std::fs::Permissions>> {
    let permissions = std::fs::metadata(real)?.permissions();
    let listed = manifest_names(real);
    for entry in std::fs::read_dir(real)? {
        let entry = entry?;
        let name = entry.file_name();
        if name
            .to_str()
            .is_some_and(|n| is_ours(n, &listed, outputs) || names.iter().any(|m| m == n))
        {
            continue;
        }
        // A file the link fails for, and every folder, is moved after the exchange.
        let kind = entry.file_type()?;
        if kind.is_file() {
            let _ = std::fs::hard_link(entry.path(), staging.join(&name));
        } else if kind.is_symlink() {
            copy_link(&entry.path(), &staging.join(&name));
        }
    }
    Ok(rename_exchange(staging, real).then_some(permissions))
}

#[cfg(unix)]
fn copy_link(from: &Path, to: &Path) {
    if let Ok(target) = std::fs::read_link(from) {
        let _ = std::os::unix::fs::symlink(target, to);
    }
}

#[cfg(not(unix))]
fn copy_link(_: &Path, _: &Path) {}

/// Exchanges the folders `a` and `b` atomically; false when that failed (nothing moved).
#[cfg(target_os = "linux")]
fn rename_exchange(a: &Path, b: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    let (Ok(a), Ok(b)) = (
        std::ffi::CString::new(a.as_os_str().as_bytes()),
        std::ffi::CString::new(b.as_os_str().as_bytes()),
    ) else {
        return false;
    };
    // SAFETY: two valid NUL-terminated paths; renameat2 reads them and touches nothing else.
    let done = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    done == 0
}

#[cfg(not(target_os = "linux"))]
fn rename_exchange(_: &Path, _: &Path) -> bool {
    false
}

/// Moves the user's entries of folder `old` (not the program's `outputs`, by `old`'s own
/// manifest) that `real` does not hold into `real`; where both hold one by a name but not the
/// same file, the one modified last stays. True when every one of the user's entries is in
/// `real`.
pub(super) fn carry_over(old: &Path, real: &Path, outputs: Outputs) -> bool {
    let listed = manifest_names(old);
    let Ok(entries) = std::fs::read_dir(old) else {
        return false;
    };
    let mut all = true;
    for entry in entries.flatten() {
        let name = entry.file_name();
        if name.to_str().is_some_and(|n| is_ours(n, &listed, outputs)) {
            continue;
        }
        let (from, to) = (entry.path(), real.join(&name));
        if let (Ok(a), Ok(b)) = (
            std::fs::symlink_metadata(&from),
            std::fs::symlink_metadata(&to),
        ) {
            if same_file(&a, &b) || a.modified().ok() <= b.modified().ok() {
                continue;
            }
        }
        all &= std::fs::rename(&from, &to).is_ok();
    }
    all
}

#[cfg(unix)]
fn same_file(a: &std::fs::Metadata, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_file(_: &std::fs::Metadata, _: &std::fs::Metadata) -> bool {
    false
}

/// Completes the writes into `real` whose process ended before they finished: each
/// `.<name>.staging-<pid>` beside it of a process that no longer runs holds either a set not
/// yet exchanged (the user's files in it are links to those in `real`) or, after the
/// exchange, the old set with the user's folders not yet moved back. Either way the user's
/// entries go to `real` and the folder is removed. Where the running processes cannot be
/// listed (no `/proc`), nothing is done.
pub(super) fn recover(real: &Path) {
    let (Some(parent), Some(name)) = (real.parent(), real.file_name()) else {
        return;
    };
    let mut prefix = OsString::from(".");
    prefix.push(name);
    prefix.push(".staging-");
    for folder in abandoned_staging(parent, prefix.as_encoded_bytes()) {
        // Which kind of set the stopped write was is not known: the user's entries are those
        // that are no output of this program's at all.
        if carry_over(&folder, real, Outputs::All) {
            let _ = std::fs::remove_dir_all(folder);
        }
    }
}
