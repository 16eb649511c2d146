//! Output memory: how much there is, and buffers the size of a sweep's outputs.
//!
//! A sweep's outputs are written once, front to back, into memory the process has never
//! touched: on Linux each 4 KiB page costs a fault on first write, which for a four-bar's
//! 27 columns is most of a step's time. Asking for transparent huge pages (as NumPy does
//! for its own arrays of 4 MiB and more) makes that one fault per 2 MiB.

/// Memory available for new allocations (Linux: MemAvailable of /proc/meminfo), or None
/// where it is not known.
pub fn available_memory() -> Option<usize> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    kb.checked_mul(1024)
}

/// Buffers from this size on are advised to use huge pages (NumPy's threshold).
pub const HUGE_PAGES_FROM: usize = 4 << 20;

/// Buffers from this size on have their pages faulted in by one call (16 pages: below
/// that the call costs about what the faults it saves do).
pub const POPULATE_FROM: usize = 64 << 10;

/// `len` zeros, in huge pages where the system has them and the buffer is large enough,
/// its pages faulted in.
pub fn zeroed<T: Copy + Default>(len: usize) -> Vec<T> {
    let v = vec![T::default(); len];
    advise_pages(&v);
    v
}

/// Advises the kernel to back the buffer's whole 2 MiB pages by huge pages, before its
/// first write (calloc's fresh mappings are not touched until then), and faults its pages
/// in. Advice only: where it is refused or means nothing, the buffer is the same.
#[cfg(target_os = "linux")]
fn advise_pages<T>(v: &[T]) {
    const HUGE: usize = 2 << 20;
    let bytes = std::mem::size_of_val(v);
    if bytes < POPULATE_FROM {
        return;
    }
    let start = v.as_ptr() as usize;
    let first = start.next_multiple_of(HUGE);
    let end = (start + bytes) / HUGE * HUGE;
    if bytes >= HUGE_PAGES_FROM && end > first {
        // SAFETY: [first, end) lies inside the allocation `v` owns; MADV_HUGEPAGE changes
        // how its pages are backed, never their contents.
        unsafe {
            libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
        }
    }
    // the whole buffer's pages in one call, instead of one fault per page as the sweep
    // first writes them (the head and tail short of a huge page are 4 KiB pages)
    let page = 4096;
    let (first, end) = (start.next_multiple_of(page), (start + bytes) / page * page);
    if end > first {
        // SAFETY: as above; MADV_POPULATE_WRITE faults in zero pages that calloc gave
        // untouched, and leaves written pages as they are.
        unsafe {
            libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_POPULATE_WRITE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_pages<T>(_: &[T]) {}

#[cfg(test)]
mod tests {
    use super::*;

    /// Large and small buffers are zeros of the asked length, writable end to end.
    #[test]
    fn zeroed_buffers_are_zeros() {
        for len in [0, 7, HUGE_PAGES_FROM / 8 + 12345] {
            let mut v: Vec<f64> = zeroed(len);
            assert_eq!(v.len(), len);
            assert!(v.iter().all(|&x| x == 0.0));
            for (i, x) in v.iter_mut().enumerate() {
                *x = i as f64;
            }
            assert!(v.iter().enumerate().all(|(i, &x)| x == i as f64));
        }
    }
}
