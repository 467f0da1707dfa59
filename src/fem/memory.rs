//! Large solver buffers backed by transparent huge pages where the kernel offers them.
//!
//! A Cholesky factor of a 3D mesh runs to hundreds of megabytes; touching it page by page costs
//! a fault per 4 KiB. Advising the kernel to back it with 2 MiB pages (`MADV_HUGEPAGE`) removes
//! most of that cost. Elsewhere this is a plain allocation.

use std::mem::MaybeUninit;

/// Grows `buffer` to at least `len` elements, advising huge pages on the new memory.
pub fn grow<T>(buffer: &mut Vec<T>, len: usize, fill: impl FnMut() -> T) {
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
    buffer.clear();
    buffer.resize_with(len, fill);
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
