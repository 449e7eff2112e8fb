//! An allocator for dem2d's binaries (`dem2d`, `dem2d-lab`): the system's, advising the kernel
//! to back large blocks with transparent huge pages, and counting the bytes and the allocations
//! it hands out ([`allocated`], [`allocations`]) for the throughput benchmark. The library itself
//! allocates through whatever allocator its user installs; nothing here is used unless a binary
//! makes it its `#[global_allocator]`. The unsafe code is the allocator's contract, forwarded
//! unchanged to the system allocator, and the `madvise` advice (which cannot change contents).

use std::sync::atomic::{AtomicUsize, Ordering};

/// Bytes currently allocated through [`HugePageAllocator`] (0 when it is not installed).
pub fn allocated() -> usize {
    ALLOCATED.load(Ordering::Relaxed)
}

/// Allocations and reallocations so far through [`HugePageAllocator`].
pub fn allocations() -> usize {
    ALLOCATIONS.load(Ordering::Relaxed)
}

/// The system allocator, counting the bytes currently allocated (for the throughput benchmark's
/// bytes per body: the world's real heap footprint, not an estimate), and asking Linux for
/// transparent huge pages on large blocks ([`advise_huge_pages`]). A binary installs it with
/// `#[global_allocator] static GLOBAL: dem2d::alloc::HugePageAllocator = dem2d::alloc::HugePageAllocator;`.
pub struct HugePageAllocator;

/// Blocks at least this large (a million-body world's arrays: bodies, slots, contact data) are
/// advised to live on transparent huge pages.
const HUGE_PAGE_MIN_BLOCK: usize = 4 << 20;

/// Asks the kernel to back the 2 MiB-aligned interior of a freshly allocated block with
/// transparent huge pages (`madvise(MADV_HUGEPAGE)`). A step of a 10⁶-body world streams some
/// 700 MB through a dozen arrays; on 4 KiB pages each array crosses a page every few hundred
/// bodies and the processor walks the page tables (its TLB covers ~12 MB): advised, 10⁶ disks
/// step ~3 % faster (docs/src/lab-notebook.md, "This pass"). Debian's default THP mode is
/// `madvise`: only advised memory gets huge pages. Advice only — where THP is off or the call
/// fails, nothing changes — and never affects a result.
#[inline]
fn advise_huge_pages(ptr: *mut u8, size: usize) {
    #[cfg(target_os = "linux")]
    if size >= HUGE_PAGE_MIN_BLOCK && !ptr.is_null() {
        const HUGE: usize = 2 << 20;
        let start = (ptr as usize).next_multiple_of(HUGE);
        let end = (ptr as usize + size) & !(HUGE - 1);
        if end > start {
            // SAFETY: advice on whole pages inside the block just handed out; it changes no
            // contents and its failure is harmless.
            unsafe {
                libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (ptr, size);
}

static ALLOCATED: AtomicUsize = AtomicUsize::new(0);
/// Number of allocations (and reallocations) so far: `dem2d bench` checks the step allocates
/// nothing.
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

/// A block of `size` bytes just handed out at `ptr` by `alloc` or `alloc_zeroed`: counted, and
/// advised onto huge pages when large.
#[inline]
fn new_block(ptr: *mut u8, size: usize) -> *mut u8 {
    ALLOCATED.fetch_add(size, Ordering::Relaxed);
    ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    advise_huge_pages(ptr, size);
    ptr
}

// SAFETY: every call is forwarded unchanged to the system allocator; the counter is only
// bookkeeping.
unsafe impl std::alloc::GlobalAlloc for HugePageAllocator {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        new_block(unsafe { std::alloc::System.alloc(layout) }, layout.size())
    }

    unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        new_block(
            unsafe { std::alloc::System.alloc_zeroed(layout) },
            layout.size(),
        )
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
        ALLOCATED.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { std::alloc::System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: std::alloc::Layout, new_size: usize) -> *mut u8 {
        ALLOCATED.fetch_add(new_size, Ordering::Relaxed);
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        ALLOCATED.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        let ptr = unsafe { std::alloc::System.realloc(ptr, layout, new_size) };
        advise_huge_pages(ptr, new_size);
        ptr
    }
}
