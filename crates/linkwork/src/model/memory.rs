//! Output memory: how much there is, and buffers the size of a sweep's outputs.
//!
//! A sweep's outputs are written once, front to back, into memory the process has never
//! touched: on Linux each 4 KiB page costs a fault on first write, which for a four-bar's
//! 27 columns is most of a step's time. Asking for transparent huge pages (as NumPy does
//! for its own arrays of 4 MiB and more) makes that one fault per 2 MiB; a sweep's columns
//! share one allocation (`Columns`), so that the small ones lie in huge pages too.

use std::alloc::Layout;
use std::ptr::NonNull;
use std::sync::Arc;

/// Memory available for new allocations (Linux: MemAvailable of /proc/meminfo), or None
/// where it is not known.
pub fn available_memory() -> Option<usize> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    kb.checked_mul(1024)
}

/// Outputs from this size on are advised to use huge pages (NumPy's threshold).
pub const HUGE_PAGES_FROM: usize = 4 << 20;

/// Outputs from this size on have their pages faulted in by one call (16 pages: below
/// that the call costs about what the faults it saves do).
pub const POPULATE_FROM: usize = 64 << 10;

/// A huge page (x86-64, and the aarch64 kernels with 4 KiB pages).
#[cfg(target_os = "linux")]
const HUGE: usize = 2 << 20;

/// Faults in the whole 4 KiB pages of a fresh heap buffer of `bytes` at `start` in one
/// call, instead of one fault per page as a sweep first writes them, from `POPULATE_FROM`
/// on. Advice only: where it is refused or means nothing, the buffer is the same.
#[cfg(target_os = "linux")]
fn populate_heap(start: usize, bytes: usize) {
    let page = 4096;
    let (first, end) = (start.next_multiple_of(page), (start + bytes) / page * page);
    if bytes >= POPULATE_FROM && end > first {
        populate(first, end - first);
    }
}

#[cfg(not(target_os = "linux"))]
fn populate_heap(_: usize, _: usize) {}

/// Faults in the pages of [start, start + bytes) (page-aligned, mapped) in one call.
#[cfg(target_os = "linux")]
fn populate(start: usize, bytes: usize) {
    // SAFETY: the range is mapped and owned by the caller; MADV_POPULATE_WRITE faults in
    // zero pages where none is yet, and leaves written pages as they are.
    unsafe {
        libc::madvise(start as *mut libc::c_void, bytes, libc::MADV_POPULATE_WRITE);
    }
}

/// One zeroed allocation that several `Column`s share: a sweep's outputs in one piece, so
/// that all of them (the diagnostics too, each too small on its own) lie in huge pages,
/// which cost a tenth of what 4 KiB pages do a byte to fault in (0.1 against 1 us a
/// 4 KiB page, measured). Freed when the last column of it is dropped.
#[derive(Debug)]
pub struct Block {
    ptr: NonNull<u8>,
    /// the bytes asked for
    len: usize,
    how: Backing,
}

#[derive(Debug)]
enum Backing {
    /// nothing allocated (no bytes asked for)
    Empty,
    /// the global allocator's, with this layout
    Heap(Layout),
    /// an anonymous mapping of its own (Linux), at this address and length
    #[cfg(target_os = "linux")]
    Mapped(usize, usize),
}

// SAFETY: a Block is plain memory that it alone frees; the columns over it are disjoint.
unsafe impl Send for Block {}
unsafe impl Sync for Block {}

impl Block {
    /// `bytes` zero bytes aligned for f64, or None where the system has not that much. From
    /// `HUGE_PAGES_FROM` on (Linux) a mapping of its own starting on a huge page, advised
    /// to be backed by huge pages, its length rounded up to whole huge pages where that
    /// adds at most an eighth; from `POPULATE_FROM` on its pages faulted in by one call.
    pub fn zeroed(bytes: usize) -> Option<Block> {
        if bytes == 0 {
            return Some(Block { ptr: NonNull::<f64>::dangling().cast(), len: 0, how: Backing::Empty });
        }
        #[cfg(target_os = "linux")]
        if bytes >= HUGE_PAGES_FROM {
            return Block::mapped(bytes);
        }
        // f64's alignment, which the allocator's calloc gives (a larger one: memset,
        // which faults in every page one by one)
        let layout = Layout::from_size_align(bytes, 8).ok()?;
        // SAFETY: the layout's size is not zero
        let ptr = NonNull::new(unsafe { std::alloc::alloc_zeroed(layout) })?;
        populate_heap(ptr.as_ptr() as usize, bytes);
        Some(Block { ptr, len: bytes, how: Backing::Heap(layout) })
    }

    #[cfg(target_os = "linux")]
    fn mapped(bytes: usize) -> Option<Block> {
        let rounded = bytes.checked_next_multiple_of(HUGE)?;
        let used = if (rounded - bytes) * 8 <= bytes { rounded } else { bytes.next_multiple_of(4096) };
        // a huge page more, to start on one
        let map_len = used.checked_add(HUGE)?;
        // SAFETY: a fresh private anonymous mapping (zero pages), which this Block unmaps
        let at = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                map_len,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            )
        };
        if at == libc::MAP_FAILED {
            return None;
        }
        let start = (at as usize).next_multiple_of(HUGE);
        let whole = (start + used) / HUGE * HUGE;
        // SAFETY: [start, whole) lies inside the mapping; advice only
        unsafe {
            libc::madvise(start as *mut libc::c_void, whole - start, libc::MADV_HUGEPAGE);
        }
        populate(start, used);
        let ptr = NonNull::new(start as *mut u8)?;
        Some(Block { ptr, len: bytes, how: Backing::Mapped(at as usize, map_len) })
    }

    /// The bytes asked for.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

impl Drop for Block {
    fn drop(&mut self) {
        match self.how {
            Backing::Empty => {}
            // SAFETY: allocated by `alloc_zeroed` with this layout, freed once
            Backing::Heap(layout) => unsafe { std::alloc::dealloc(self.ptr.as_ptr(), layout) },
            // SAFETY: mapped by `mapped` at this address and length, unmapped once
            #[cfg(target_os = "linux")]
            Backing::Mapped(at, len) => unsafe {
                libc::munmap(at as *mut libc::c_void, len);
            },
        }
    }
}

/// Lays out columns in one `Block`: the lengths first (`add`), then the Block and the
/// columns over it (`finish`, `take`), in the order added.
#[derive(Debug, Default)]
pub struct Columns {
    /// each column's byte offset and length in elements
    at: Vec<(usize, usize)>,
    bytes: usize,
    block: Option<Arc<Block>>,
    next: usize,
}

impl Columns {
    /// Adds a column of `len` elements of T (8-byte aligned in the Block).
    pub fn add<T>(&mut self, len: usize) {
        debug_assert!(std::mem::align_of::<T>() <= 8);
        let bytes = len.checked_mul(std::mem::size_of::<T>()).expect("a column's size overflows");
        self.at.push((self.bytes, len));
        self.bytes = self.bytes.checked_add(bytes.next_multiple_of(8)).expect("the columns' size overflows");
    }

    /// The bytes of the columns added so far.
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// Allocates the Block (aborting, as a Vec does, where it cannot).
    pub fn finish(&mut self) {
        let block = Block::zeroed(self.bytes).unwrap_or_else(|| {
            std::alloc::handle_alloc_error(Layout::from_size_align(self.bytes.max(1), 8).expect("layout"))
        });
        self.block = Some(Arc::new(block));
        self.next = 0;
    }

    /// The next column, in the order added, as T (zeros).
    pub fn take<T: Copy>(&mut self) -> Column<T> {
        let (offset, len) = self.at[self.next];
        self.next += 1;
        let block = self.block.clone().expect("Columns::finish before take");
        // SAFETY: offset + len * size_of::<T>() lies inside the Block (as `add` laid it
        // out), aligned to 8 >= align_of::<T>(); each column taken once, so disjoint
        let ptr = unsafe { NonNull::new_unchecked(block.ptr.as_ptr().add(offset).cast::<T>()) };
        let ptr = if len == 0 { NonNull::dangling() } else { ptr };
        Column { ptr, len, block: Some(block) }
    }
}

/// A column of a sweep's outputs: its elements in a `Block` it shares with the other
/// columns of the sweep (`Columns`), or in one of its own. A slice of T (Deref) that
/// keeps its Block alive.
pub struct Column<T: Copy> {
    ptr: NonNull<T>,
    len: usize,
    block: Option<Arc<Block>>,
}

// SAFETY: a column's elements are its alone (columns over one Block are disjoint); the
// Block is freed by the last column over it
unsafe impl<T: Copy + Send> Send for Column<T> {}
unsafe impl<T: Copy + Sync> Sync for Column<T> {}

impl<T: Copy> Column<T> {
    /// Keeps the first `len` elements (none is dropped: T is Copy).
    pub fn truncate(&mut self, len: usize) {
        self.len = self.len.min(len);
    }

    /// The Block the column lies in (None: empty, no memory).
    pub fn block(&self) -> Option<&Arc<Block>> {
        self.block.as_ref()
    }
}

impl<T: Copy> Default for Column<T> {
    fn default() -> Self {
        Column { ptr: NonNull::dangling(), len: 0, block: None }
    }
}

impl<T: Copy> From<&[T]> for Column<T> {
    /// A copy in a Block of its own.
    fn from(v: &[T]) -> Self {
        let mut columns = Columns::default();
        columns.add::<T>(v.len());
        columns.finish();
        let mut c = columns.take::<T>();
        c.copy_from_slice(v);
        c
    }
}

impl<T: Copy> From<Vec<T>> for Column<T> {
    fn from(v: Vec<T>) -> Self {
        Column::from(&v[..])
    }
}

impl<T: Copy> Clone for Column<T> {
    /// A copy in a Block of its own.
    fn clone(&self) -> Self {
        Column::from(&self[..])
    }
}

impl<T: Copy> std::ops::Deref for Column<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        // SAFETY: ptr and len describe elements of the Block this column keeps alive
        // (or none: dangling, 0)
        unsafe { std::slice::from_raw_parts(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Copy> std::ops::DerefMut for Column<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        // SAFETY: as `deref`; no other column covers these elements
        unsafe { std::slice::from_raw_parts_mut(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Copy + std::fmt::Debug> std::fmt::Debug for Column<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Copy + PartialEq> PartialEq for Column<T> {
    fn eq(&self, other: &Self) -> bool {
        self[..] == other[..]
    }
}

impl<T: Copy + PartialEq> PartialEq<Vec<T>> for Column<T> {
    fn eq(&self, other: &Vec<T>) -> bool {
        self[..] == other[..]
    }
}

impl<'a, T: Copy> IntoIterator for &'a Column<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns laid out in one Block, small and above `HUGE_PAGES_FROM` (its own mapping),
    /// are zeros of their lengths, each writable end to end without touching another,
    /// and outlive each other in any order; clones and truncations are their own.
    #[test]
    fn columns_share_a_block_and_stay_apart() {
        for n in [0, 3, 1000, HUGE_PAGES_FROM / 8 + 777] {
            let mut c = Columns::default();
            c.add::<f64>(n);
            c.add::<u32>(n + 1);
            c.add::<f64>(2 * n);
            assert_eq!(c.bytes(), 8 * n + (4 * (n + 1)).next_multiple_of(8) + 16 * n);
            c.finish();
            let (mut a, mut b, mut d) = (c.take::<f64>(), c.take::<u32>(), c.take::<f64>());
            assert_eq!((a.len(), b.len(), d.len()), (n, n + 1, 2 * n));
            assert!(a.iter().all(|&x| x == 0.0) && b.iter().all(|&x| x == 0) && d.iter().all(|&x| x == 0.0));
            if n > 0 {
                assert!(Arc::ptr_eq(a.block().unwrap(), d.block().unwrap()));
                assert_eq!(a.block().unwrap().len(), c.bytes());
            }
            a.iter_mut().enumerate().for_each(|(i, x)| *x = i as f64 + 0.5);
            b.iter_mut().enumerate().for_each(|(i, x)| *x = u32::MAX - i as u32);
            d.iter_mut().enumerate().for_each(|(i, x)| *x = -(i as f64));
            let copy = a.clone();
            drop(a);
            assert!(b.iter().enumerate().all(|(i, &x)| x == u32::MAX - i as u32));
            assert!(d.iter().enumerate().all(|(i, &x)| x == -(i as f64)));
            assert!(copy.iter().enumerate().all(|(i, &x)| x == i as f64 + 0.5));
            d.truncate(n);
            assert_eq!(d.len(), n);
            drop(b);
            assert_eq!(d, (0..n).map(|i| -(i as f64)).collect::<Vec<_>>());
        }
        assert!(Column::<f64>::default().is_empty());
    }
}
