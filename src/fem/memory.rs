//! Large solver buffers backed by transparent huge pages where the kernel offers them.
//!
//! A Cholesky factor of a 3D mesh runs to hundreds of megabytes; touching it page by page costs
//! a fault per 4 KiB. Advising the kernel to back it with 2 MiB pages (`MADV_HUGEPAGE`) removes
//! most of that cost. Elsewhere this is a plain allocation.

use std::mem::MaybeUninit;

/// Makes `buffer` `len` elements long, advising huge pages on new memory. Elements it already
/// held keep their values (only new ones are `fill`ed): the caller overwrites them (faer zeroes
/// a factor's values itself, and writing them here too took a memset of the whole factor per
/// factorization).
pub fn grow<T>(buffer: &mut Vec<T>, len: usize, fill: impl FnMut() -> T) {
    reserve(buffer, len);
    if buffer.len() > len {
        buffer.truncate(len);
    } else {
        buffer.resize_with(len, fill);
    }
}

/// Makes room in `buffer` for `len` elements, in new memory advised to huge pages where it
/// has to be allocated (its elements are then dropped).
fn reserve<T>(buffer: &mut Vec<T>, len: usize) {
    if buffer.capacity() < len {
        // A quarter more than asked: a factor that grows by a few columns from one solve to
        // the next (a contact region along a motion) keeps its memory, and its huge pages.
        let capacity = len.saturating_add(len / 4);
        *buffer = Vec::with_capacity(capacity);
        advise_huge_pages(
            buffer.as_mut_ptr() as *mut u8,
            capacity * std::mem::size_of::<T>(),
        );
    }
}

/// [`grow`] for a factor's values: new elements zeroed on every core (the first touch of new
/// memory is a page fault each: the full hand's first factor at resolution 1, 61 MB, took
/// 8–95 ms to zero on one core).
pub fn grow_zeroed(buffer: &mut Vec<f64>, len: usize) {
    use rayon::prelude::*;
    if buffer.len() >= len {
        buffer.truncate(len);
        return;
    }
    reserve(buffer, len);
    let old = buffer.len();
    buffer.spare_capacity_mut()[..len - old]
        .par_chunks_mut(1 << 16)
        .for_each(|chunk| {
            for x in chunk {
                x.write(0.0);
            }
        });
    // SAFETY: every element below `len` is initialised: those up to `old` were, the rest were
    // just written.
    unsafe { buffer.set_len(len) };
}

/// Uninitialised scratch of at least `bytes` bytes, 8-byte aligned.
pub fn scratch(buffer: &mut Vec<MaybeUninit<u64>>, bytes: usize) -> &mut [MaybeUninit<u64>] {
    let words = bytes.div_ceil(8) + 1;
    if buffer.len() < words {
        grow(buffer, words, MaybeUninit::uninit);
    }
    &mut buffer[..words]
}

#[cfg(target_os = "linux")]
fn advise_huge_pages(ptr: *mut u8, bytes: usize) {
    const HUGE: usize = 2 << 20;
    if bytes < 2 * HUGE {
        return;
    }
    let start = (ptr as usize).div_ceil(HUGE) * HUGE;
    let end = (ptr as usize + bytes) / HUGE * HUGE;
    if end > start {
        // SAFETY: the range lies inside an allocation we own; MADV_HUGEPAGE only changes how the
        // kernel backs it and never its contents. A refusal is harmless.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages(_ptr: *mut u8, _bytes: usize) {}

/// The memory a solve may still take, bytes, as asked (`[solver] max_memory`) — a budget of the
/// whole process, set once by whoever runs a model ([`set_budget`]).
static BUDGET: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(u64::MAX);

/// Sets the memory a solve may take (`None`: what the machine has free).
pub fn set_budget(bytes: Option<u64>) {
    BUDGET.store(
        bytes.unwrap_or(u64::MAX),
        std::sync::atomic::Ordering::Relaxed,
    );
}

static RESERVE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Sets the memory the solve will still allocate after its factorization (the nonlinear tier's
/// element states): [`budget`] leaves it out of what a factor may take.
pub fn set_reserve(bytes: u64) {
    RESERVE.store(bytes, std::sync::atomic::Ordering::Relaxed);
}

/// The share of a model's elements (rounded down to a percent, with a fifth to spare) whose
/// memory fits `available` bytes where the whole needs `needed`, the memory growing as the
/// element count to the power `growth` (1 for the stiffness pattern, 4/3 for a 3D mesh's
/// sparse factor by nested dissection).
pub fn fewer_share(available: u64, needed: u64, growth: f64) -> f64 {
    if needed == 0 {
        return 1.0;
    }
    let share = 0.8 * (available as f64 / needed as f64).powf(1.0 / growth);
    (share * 100.0).floor().clamp(0.0, 100.0) / 100.0
}

/// Where the memory a solve may take comes from, for an error that says so.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BudgetSource {
    /// `[solver] max_memory`.
    Asked,
    /// The machine's available memory (`MemAvailable`).
    Machine,
    /// The process's address-space limit (`ulimit -v`) less what it already maps.
    AddressSpace,
}

impl std::fmt::Display for BudgetSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BudgetSource::Asked => "[solver] max_memory",
            BudgetSource::Machine => "the machine's available memory",
            BudgetSource::AddressSpace => "the process's address-space limit less what it maps",
        })
    }
}

impl BudgetSource {
    /// What raises this limit, to follow "use fewer elements, or …".
    pub fn remedy(&self) -> &'static str {
        match self {
            BudgetSource::Asked => "raise `[solver] max_memory` where the machine has the memory",
            BudgetSource::Machine => {
                "free memory on this machine (close other programs) or run on a larger one"
            }
            BudgetSource::AddressSpace => "raise the process's address-space limit (`ulimit -v`)",
        }
    }
}

/// How much more memory a solve may take now, bytes, and what sets it: the least of
/// `[solver] max_memory`, the machine's available memory and the address space left under the
/// process's limit; `None` where none of them is known.
pub fn budget() -> Option<(u64, BudgetSource)> {
    let asked = BUDGET.load(std::sync::atomic::Ordering::Relaxed);
    let reserve = RESERVE.load(std::sync::atomic::Ordering::Relaxed);
    budget_with((asked != u64::MAX).then_some(asked))
        .map(|(bytes, source)| (bytes.saturating_sub(reserve), source))
}

/// [`budget`] with `asked` in place of the budget set.
pub fn budget_with(asked: Option<u64>) -> Option<(u64, BudgetSource)> {
    let asked = asked.unwrap_or(u64::MAX);
    let mut best: Option<(u64, BudgetSource)> =
        (asked != u64::MAX).then_some((asked, BudgetSource::Asked));
    let mut consider = |bytes: Option<u64>, source| {
        if let Some(b) = bytes {
            if best.is_none_or(|(least, _)| b < least) {
                best = Some((b, source));
            }
        }
    };
    consider(machine_available(), BudgetSource::Machine);
    consider(address_space_left(), BudgetSource::AddressSpace);
    best
}

/// `MemAvailable` of /proc/meminfo, bytes.
#[cfg(target_os = "linux")]
fn machine_available() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

#[cfg(not(target_os = "linux"))]
fn machine_available() -> Option<u64> {
    None
}

/// The address space left under the process's `RLIMIT_AS` (its `VmSize` taken off), bytes;
/// `None` without a limit.
#[cfg(target_os = "linux")]
fn address_space_left() -> Option<u64> {
    let mut limit = libc::rlimit {
        rlim_cur: 0,
        rlim_max: 0,
    };
    // SAFETY: getrlimit writes the struct it is given.
    if unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } != 0
        || limit.rlim_cur == libc::RLIM_INFINITY
    {
        return None;
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmSize:"))?;
    let used: u64 = line
        .split_whitespace()
        .nth(1)?
        .parse::<u64>()
        .ok()?
        .checked_mul(1024)?;
    #[allow(clippy::unnecessary_cast)] // rlim_t is u32 on some targets
    Some(
        (limit.rlim_cur as u64)
            .saturating_sub(used)
            .saturating_sub(worker_address_space()),
    )
}

/// Address space each linear-algebra worker takes outside the solve's own buffers when it
/// first works, bytes: the dense kernels' scratch pages, 64 MiB a thread (private-gemm's
/// thread-local page buffer, allocated whole on a thread's first product), and the C
/// allocator's arena a new thread reserves, 64 MiB on 64-bit glibc. Under `ulimit -v` they are
/// what the budget must leave room for: without it, a solve the budget let through aborted
/// with "memory allocation of 67108864 bytes failed" (`ulimit -v 400000`, the five-digit grasp).
/// (Workers that already ran are in `VmSize` too, so they are counted twice: the budget errs
/// on the side of refusing.)
#[cfg(target_os = "linux")]
const WORKER_ADDRESS_SPACE: u64 = 2 * 64 * 1024 * 1024;

/// [`WORKER_ADDRESS_SPACE`] for every worker of the thread pool, and the scratch pages of the
/// calling thread (which allocates in the main arena, already mapped).
#[cfg(target_os = "linux")]
fn worker_address_space() -> u64 {
    (rayon::current_num_threads() as u64)
        .saturating_mul(WORKER_ADDRESS_SPACE)
        .saturating_add(WORKER_ADDRESS_SPACE / 2)
}

#[cfg(not(target_os = "linux"))]
fn address_space_left() -> Option<u64> {
    None
}

/// `bytes` for people: "3.2 GB", "640 MB".
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.0} MB", b / 1e6)
    } else {
        format!("{:.0} kB", b / 1e3)
    }
}
