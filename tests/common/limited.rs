//! The command line run as a user runs it, in a child process with a time limit and (on Linux)
//! an address-space limit, so that a scene that would allocate without bound fails in the child
//! instead of taking the machine down.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// How a run ended.
pub enum Ending {
    /// Exited by itself.
    Exited(ExitStatus),
    /// Killed at the time limit.
    TimedOut,
}

/// Runs `prehensile solve scene --out out`, stderr into `stderr_file`, killed after
/// `time_limit`, with at most `address_space` bytes of address space (Linux).
pub fn solve_limited(
    scene: &Path,
    out: &Path,
    stderr_file: &Path,
    time_limit: Duration,
    address_space: u64,
) -> std::io::Result<(Ending, Duration)> {
    solve_limited_with(scene, out, stderr_file, (time_limit, address_space), &[])
}

/// [`solve_limited`] with the variables `env` set in the child (`RAYON_NUM_THREADS`, …).
pub fn solve_limited_with(
    scene: &Path,
    out: &Path,
    stderr_file: &Path,
    (time_limit, address_space): (Duration, u64),
    env: &[(&str, &str)],
) -> std::io::Result<(Ending, Duration)> {
    let stderr = fs::File::create(stderr_file)?;
    let mut command = Command::new(env!("CARGO_BIN_EXE_prehensile"));
    command.envs(env.iter().copied());
    command
        .arg("solve")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .env("RUST_BACKTRACE", "0")
        .env("NODEVICE_SELECT", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::from(stderr));
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: between fork and exec the closure only calls setrlimit, which is
        // async-signal-safe, and allocates nothing.
        unsafe {
            command.pre_exec(move || {
                let limit = libc::rlimit {
                    rlim_cur: address_space as libc::rlim_t,
                    rlim_max: address_space as libc::rlim_t,
                };
                if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            });
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = address_space;
    let start = Instant::now();
    let mut child = command.spawn()?;
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok((Ending::Exited(status), start.elapsed()));
        }
        if start.elapsed() > time_limit {
            child.kill()?;
            child.wait()?;
            return Ok((Ending::TimedOut, start.elapsed()));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The signal that ended a run, if one did.
#[cfg(unix)]
pub fn signal(s: &ExitStatus) -> Option<i32> {
    use std::os::unix::process::ExitStatusExt;
    s.signal()
}

/// The signal that ended a run, if one did.
#[cfg(not(unix))]
pub fn signal(_: &ExitStatus) -> Option<i32> {
    None
}

/// Every file and folder under `dir`, relative to it and sorted (none when it does not exist).
pub fn written(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            out.push(
                path.strip_prefix(dir)
                    .unwrap_or(&path)
                    .display()
                    .to_string(),
            );
            if path.is_dir() {
                stack.push(path);
            }
        }
    }
    out.sort();
    out
}

/// `text` trimmed, at most its first `chars` characters.
pub fn trimmed(text: &str, chars: usize) -> String {
    let text = text.trim();
    match text.char_indices().nth(chars) {
        Some((i, _)) => format!("{} […]", &text[..i]),
        None => text.to_string(),
    }
}

/// The `.toml` files in `relative` (a folder of the crate), sorted by name.
pub fn toml_files(relative: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}
