//! The command line's allocator: the C library's, except that a block of [`LARGE`] bytes or
//! more is mapped on its own and offered to the kernel for transparent huge pages, the C
//! library's heap, as it grows, is offered too, blocks of at most [`SMALL`] bytes are kept
//! in lists of their own, and the last over-aligned block given back is kept for the next
//! request of its layout ([`Spare`]: matrixmultiply's packing buffer, one per matrix product).
//!
//! **Why.** An order-60 reduced observer writes 122 MB of JSON and holds about 280 MB at its
//! peak; every 4 KiB page of that was a page fault of its own, a third of the command's CPU
//! time in the kernel (68 000 faults). A large block advised `MADV_HUGEPAGE` faults in 2 MiB at
//! a time where the kernel allows it (`/sys/kernel/mm/transparent_hugepage/enabled` set to
//! `madvise` or `always`); elsewhere the advice is refused or ignored and the block behaves as
//! any mapping. Small blocks — everything a small command allocates — stay with the C library,
//! so a command's fixed cost does not change (an allocator that advised its whole heap, or
//! mimalloc, which does, moved 0.2–0.5 ms of zeroing into every start).
//!
//! **How.** `alloc` maps a block of `size` rounded up to the page, `dealloc` unmaps it, and
//! `realloc` of a large block to a large size moves the mapping (`mremap`, no copy); a block
//! crossing the threshold either way is copied between the two. The size of a block is its
//! layout's, which Rust hands back on `dealloc` and `realloc`, so no header is kept. Alignments
//! above the page size go to the C library whatever the size.
//!
//! **The heap.** A fresh 4 KiB page costs about 1.8 µs on the 2-core machine (a fault, a page
//! found and zeroed), a fresh 2 MiB huge page about 40 µs: 0.08 µs a 4 KiB. So at its first
//! allocation the allocator asks the C library (`mallopt`) to grow its heap 16 MiB at a time
//! ([`HEAP_PAD`]; address space only, until touched), to keep blocks below [`LARGE`] in the
//! heap rather than in mappings of their own that are unmapped and faulted afresh each time,
//! and to keep freed memory; after every request to the C library it looks at the program break (`sbrk(0)`,
//! a read of the C library's variable) and advises the heap's growth since the last look
//! ([`watch_heap`]). The 2 MiB stretches of the growth that nothing has touched then fault in
//! whole. The stretch below the first 2 MiB boundary of the heap stays in 4 KiB pages (the
//! kernel places a huge page only on a whole aligned stretch of one mapping), so a command
//! that needs little beyond the heap's first 132 KiB — most small ones — rarely touches a huge
//! page: where a command starts on one depends on where the kernel placed the heap, which
//! varies from run to run. Measured against the C library's own policy (40 interleaved runs
//! each, minimum and median CPU time above `owb --version`): a 100-state `zoh` 2.93 → 2.26 ms
//! (median 3.24 → 2.99), a 50-state one 0.78 → 0.69, a 10-state one 0.23 → 0.17, a 10-state
//! `gain --summary` 0.46 → 0.32, a 40-state `reduced` 73.6 → 60.9 ms (7 runs); the floor
//! itself did not rise. Under a limit on the process's data below 16 MiB (`ulimit -d`, as a
//! sandbox may set) such a growth is refused where the request itself fits: the first refused
//! request puts the C library's own growth (128 KiB) back and is asked again
//! ([`from_heap`]; before that, every command failed to allocate there).
//!
//! **Small blocks.** Most of what the exact commands allocate is small — a big integer's few
//! words, a fraction, a short string: of a 10-state `gain`'s 2 073 allocations, 1 900 are of
//! 256 bytes or fewer. The C library spends 100–170 instructions on each allocation and its
//! release (locks, bins, the consolidation of freed blocks), a fifth of that command's work
//! above the process floor. A block of at most [`SMALL`] bytes (alignment at most 16) is
//! instead one of 16 size classes, 16 bytes apart; each thread keeps, for each class, a list of
//! its free blocks threaded through their first word, and cuts new ones from a 64 KiB chunk
//! of the C library's heap: taking or giving back a block is a few instructions, with no lock.
//! A block given back goes to the list of the thread that gives it back (its thread of birth
//! does not matter), and stays in its class: memory freed in small blocks serves only small
//! blocks of that size, and is never returned to the C library (the peak memory of a 40-state
//! `reduced` or `control` and a 60-state `control` did not change: 65, 98 and 420 MB). While a
//! thread exits (its storage gone), a small block comes from the C library at its class's full
//! size, and a block given back is left alone. Measured (40 interleaved runs, minimum above
//! the floor): a 10-state `gain --summary` 0.30 → 0.26 ms (1.67 → 1.33 million instructions),
//! `zoh` 0.155 → 0.125 ms; a 40-state `reduced` 63.4 → 58.9 ms; the floor itself 1.12 → 0.88
//! million instructions.
//!
//! The project's second module with `unsafe` (with the time budget's alarm): the system calls and the
//! `GlobalAlloc` contract, each with the reason it is sound beside it.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Blocks of this many bytes or more are mapped on their own (4 MiB: two huge pages).
pub const LARGE: usize = 4 << 20;

/// The page size the mappings are rounded to (the kernel rounds lengths up to it anyway).
const PAGE: usize = 4096;

/// The allocator (`#[global_allocator]` in the `owb` binary).
pub struct LargePages;

/// Blocks of at most this many bytes (and alignment at most 16) are small: kept in per-thread
/// lists by size, 16 bytes apart ([`ThreadBlocks`]).
const SMALL: usize = 256;

/// The size classes of small blocks: 16, 32, …, [`SMALL`] bytes.
const CLASSES: usize = SMALL / 16;

/// Small blocks are cut from chunks of this many bytes, taken from the C library.
const CHUNK: usize = 64 << 10;

/// Where a block of a layout lives: the one place the tiers are chosen, so a block is given back
/// where it was taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tier {
    /// At most [`SMALL`] bytes, alignment at most 16: size class `k` holds `16 (k + 1)` bytes.
    Small(usize),
    /// The C library's heap.
    Heap,
    /// Alignment above 16, below [`LARGE`] bytes: the C library's heap, the last block given
    /// back on a thread kept for that thread's next request of its very layout ([`Spare`]).
    Aligned,
    /// [`LARGE`] bytes or more, alignment at most a page: a mapping of its own.
    Large,
}

fn tier(layout: &Layout) -> Tier {
    if layout.size() <= SMALL && layout.align() <= 16 {
        Tier::Small(layout.size().saturating_sub(1) / 16)
    } else if layout.size() >= LARGE && layout.align() <= PAGE {
        Tier::Large
    } else if layout.align() > 16 && layout.size() < LARGE {
        Tier::Aligned
    } else {
        Tier::Heap
    }
}

/// A thread's kept blocks: for each small class, the free blocks as a list threaded through their
/// first word; and the rest of the chunk being cut.
struct ThreadBlocks {
    free: [Cell<*mut u8>; CLASSES],
    next: Cell<*mut u8>,
    end: Cell<*mut u8>,
    /// The last [`Tier::Aligned`] block given back, with its size and alignment ([`Spare`]);
    /// null when none is kept.
    spare: Cell<(*mut u8, usize, usize)>,
}

thread_local! {
    static THREAD_BLOCKS: ThreadBlocks = const {
        ThreadBlocks {
            free: [const { Cell::new(std::ptr::null_mut()) }; CLASSES],
            next: Cell::new(std::ptr::null_mut()),
            end: Cell::new(std::ptr::null_mut()),
            spare: Cell::new((std::ptr::null_mut(), 0, 0)),
        }
    };
}

/// Blocks of the [`Tier::Aligned`] tier (alignment above 16, below [`LARGE`]): the last one given
/// back on a thread is kept there, and handed to that thread's next request of the very same
/// layout.
///
/// **Why.** matrixmultiply takes such a block (64-byte aligned) for its packing buffer at the
/// start of every matrix product and gives it back at the end. The C library did not serve the
/// next product from it: the product's own result, allocated in between, took part of the freed
/// block, so each buffer came from fresh pages. A 100-state `zoh` faulted in 237 pages (almost
/// 1 MB) in the packing alone, about a third of its page faults above the process floor.
/// Kept, measured with huge pages off (so every page is a fault): a 100-state `zoh` touches 351
/// pages above the floor instead of 527, a 50-state one 87 instead of 130; in 60 interleaved
/// runs with them on, the median CPU time above the floor went from 2.72 to 2.49 ms and from
/// 0.93 to 0.77 ms. (Since session 30 `zoh`'s products are `linalg::gemm`'s, which take no such
/// block; `kalman`'s and `dlqe`'s still go through matrixmultiply.)
///
/// One block is kept per thread, for the thread's life (a thread that exits with one leaves
/// it, as it leaves its small blocks); a block of another layout given back replaces it, and
/// the replaced one goes back to the C library.
struct Spare;

impl Spare {
    /// The kept block, if it has exactly this layout (taken out of the slot).
    fn take(layout: &Layout) -> Option<*mut u8> {
        THREAD_BLOCKS
            .try_with(|s| {
                let (p, size, align) = s.spare.get();
                (!p.is_null() && size == layout.size() && align == layout.align()).then(|| {
                    s.spare.set((std::ptr::null_mut(), 0, 0));
                    p
                })
            })
            .ok()
            .flatten()
    }

    /// Keeps `ptr` (a live block of `layout`, given up by the caller); returns the block the
    /// C library should have back instead — the one kept before, or `ptr` itself while the
    /// thread exits.
    fn keep(ptr: *mut u8, layout: Layout) -> Option<(*mut u8, Layout)> {
        THREAD_BLOCKS
            .try_with(|s| {
                let (old, size, align) = s.spare.replace((ptr, layout.size(), layout.align()));
                // SAFETY: the kept block was made with this size and alignment, a valid layout.
                (!old.is_null()).then(|| {
                    (old, unsafe {
                        Layout::from_size_align_unchecked(size, align)
                    })
                })
            })
            .unwrap_or(Some((ptr, layout)))
    }
}

/// A small block of class `class`: the thread's last freed one, else cut from its chunk, else
/// from a fresh chunk; null when the C library has no memory.
fn small_alloc(class: usize) -> *mut u8 {
    let size = (class + 1) * 16;
    let from_lists = THREAD_BLOCKS.try_with(|s| {
        let head = s.free[class].get();
        if !head.is_null() {
            // SAFETY: a listed block is free, at least 16 bytes, 16-aligned, its first word
            // the next listed block (written by `small_free`).
            s.free[class].set(unsafe { head.cast::<*mut u8>().read() });
            return head;
        }
        let (next, end) = (s.next.get(), s.end.get());
        if (end as usize).wrapping_sub(next as usize) >= size && !next.is_null() {
            // SAFETY: [next, end) is the uncut rest of a live chunk.
            s.next.set(unsafe { next.add(size) });
            return next;
        }
        // SAFETY: CHUNK and 16 make a valid nonzero layout.
        let chunk =
            from_heap(|| unsafe { System.alloc(Layout::from_size_align_unchecked(CHUNK, 16)) });
        if chunk.is_null() {
            return chunk;
        }
        // SAFETY: the chunk holds CHUNK ≥ size bytes.
        unsafe {
            s.next.set(chunk.add(size));
            s.end.set(chunk.add(CHUNK));
        }
        chunk
    });
    // a thread's storage gone (only while it exits): a block of the class's full size from the
    // C library, which a later `small_free` may list like any other
    from_lists.unwrap_or_else(|_| {
        // SAFETY: size and 16 make a valid nonzero layout.
        from_heap(|| unsafe { System.alloc(Layout::from_size_align_unchecked(size, 16)) })
    })
}

/// Lists a small block of class `class` as free on this thread (kept, never returned to the C
/// library; while the thread exits, left alone).
///
/// # Safety
///
/// `ptr` is a live block of that class that the caller gives up.
unsafe fn small_free(ptr: *mut u8, class: usize) {
    let _ = THREAD_BLOCKS.try_with(|s| {
        // SAFETY: the block is the caller's to give up, at least 16 bytes and 16-aligned.
        unsafe { ptr.cast::<*mut u8>().write(s.free[class].get()) };
        s.free[class].set(ptr);
    });
}

fn mapped_length(size: usize) -> usize {
    size.div_ceil(PAGE) * PAGE
}

/// A fresh private anonymous mapping of `size` bytes (zeroed by the kernel), advised for huge
/// pages; null when the kernel refuses it.
fn map(size: usize) -> *mut u8 {
    // SAFETY: an anonymous private mapping at an address the kernel chooses touches no
    // existing memory.
    let p = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            mapped_length(size),
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if p == libc::MAP_FAILED {
        return std::ptr::null_mut();
    }
    advise(p, size);
    p.cast()
}

/// Asks for huge pages over the mapping; a refusal (huge pages disabled) changes nothing.
fn advise(p: *mut libc::c_void, size: usize) {
    // SAFETY: the advice changes no memory's contents, and over a range that is not (or no
    // longer) mapped the kernel refuses it; `p` is page-aligned.
    let _ = unsafe { libc::madvise(p, mapped_length(size), libc::MADV_HUGEPAGE) };
}

/// How much the C library's heap grows past what a request needs (its `M_TOP_PAD`): room for
/// several whole 2 MiB stretches, untouched when advised.
const HEAP_PAD: usize = 16 << 20;

/// The program break up to which the heap has been advised; 0 before the first allocation.
static ADVISED_TO: AtomicUsize = AtomicUsize::new(0);

/// The C library's heap grown [`HEAP_PAD`] at a time, blocks below [`LARGE`] kept in it, freed
/// memory kept (GNU's `mallopt`; elsewhere the C library's own policy).
fn heap_policy() {
    #[cfg(target_env = "gnu")]
    // SAFETY: mallopt changes the C library's policy only, which it allows at any time.
    unsafe {
        libc::mallopt(libc::M_TOP_PAD, HEAP_PAD as libc::c_int);
        libc::mallopt(libc::M_MMAP_THRESHOLD, LARGE as libc::c_int);
        libc::mallopt(libc::M_TRIM_THRESHOLD, (2 * HEAP_PAD) as libc::c_int);
    }
}

/// The C library's own growth of its heap (glibc's `DEFAULT_TOP_PAD`), put back when a request
/// fails ([`from_heap`]).
const C_LIBRARY_PAD: usize = 128 << 10;

/// Whether the heap's growth has been put back to [`C_LIBRARY_PAD`], after a request failed.
static RELAXED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `request()` to the C library, then the heap's growth advised ([`watch_heap`]); if it failed,
/// asked once more with the C library's own growth: under a limit on the process's data
/// (`ulimit -d`, `RLIMIT_DATA`) below [`HEAP_PAD`], growing the heap 16 MiB at a time fails
/// where the request itself would fit (every command failed under 16 MB).
fn from_heap(request: impl Fn() -> *mut u8) -> *mut u8 {
    let mut p = request();
    if p.is_null() && !RELAXED.swap(true, Ordering::Relaxed) {
        #[cfg(target_env = "gnu")]
        // SAFETY: mallopt changes the C library's policy only, which it allows at any time.
        unsafe {
            libc::mallopt(libc::M_TOP_PAD, C_LIBRARY_PAD as libc::c_int);
        }
        p = request();
    }
    watch_heap();
    p
}

/// At the first call, the heap's policy; afterwards, huge pages asked for over the heap's
/// growth since the last call.
fn watch_heap() {
    let seen = ADVISED_TO.load(Ordering::Relaxed);
    if seen == 0 {
        heap_policy();
        // SAFETY: sbrk(0) reads the break.
        let brk = unsafe { libc::sbrk(0) } as usize;
        ADVISED_TO.store(brk.max(1), Ordering::Relaxed);
        return;
    }
    // SAFETY: sbrk(0) reads the break.
    let brk = unsafe { libc::sbrk(0) } as usize;
    // one thread advises each growth; a shrink is recorded so that the regrowth is advised
    if brk != seen
        && ADVISED_TO
            .compare_exchange(seen, brk, Ordering::Relaxed, Ordering::Relaxed)
            .is_ok()
    {
        let start = seen.next_multiple_of(PAGE);
        if brk > start {
            // [start, brk) lies in the heap's mapping, which ends at the break
            advise(start as *mut libc::c_void, brk - start);
        }
    }
}

unsafe impl GlobalAlloc for LargePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        match tier(&layout) {
            Tier::Small(class) => small_alloc(class),
            // SAFETY: the caller's layout has a nonzero size (GlobalAlloc's contract), passed on.
            Tier::Heap => from_heap(|| unsafe { System.alloc(layout) }),
            // SAFETY: as for the heap.
            Tier::Aligned => Spare::take(&layout)
                .unwrap_or_else(|| from_heap(|| unsafe { System.alloc(layout) })),
            Tier::Large => map(layout.size()),
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        match tier(&layout) {
            Tier::Small(class) => {
                let p = small_alloc(class);
                if !p.is_null() {
                    // SAFETY: the block holds at least `layout.size()` bytes.
                    unsafe { std::ptr::write_bytes(p, 0, layout.size()) };
                }
                p
            }
            // SAFETY: as for `alloc` (a kept block is not zeroed, so it is not handed out here).
            Tier::Heap | Tier::Aligned => from_heap(|| unsafe { System.alloc_zeroed(layout) }),
            // a fresh anonymous mapping is zero
            Tier::Large => map(layout.size()),
        }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        match tier(&layout) {
            // SAFETY: a small layout's block is one of its class (`alloc` made it so), and the
            // caller gives it up.
            Tier::Small(class) => unsafe { small_free(ptr, class) },
            // SAFETY: a heap layout's block came from the C library with this layout.
            Tier::Heap => unsafe { System.dealloc(ptr, layout) },
            Tier::Aligned => {
                if let Some((ptr, layout)) = Spare::keep(ptr, layout) {
                    // SAFETY: as for the heap: the block came from the C library with this
                    // layout (a kept one with the layout it was kept with), and it is given up,
                    // by the caller or out of the slot.
                    unsafe { System.dealloc(ptr, layout) }
                }
            }
            // SAFETY: a large layout's block was mapped by `map` (or moved by `realloc`) with
            // this length, and the caller gives it up.
            Tier::Large => {
                unsafe { libc::munmap(ptr.cast(), mapped_length(layout.size())) };
            }
        }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY (whole body): `ptr` is a live block of `layout` (GlobalAlloc's contract);
        // `new_layout` is valid because the caller guarantees `new_size` rounded to the
        // alignment does not overflow.
        unsafe {
            let new_layout = Layout::from_size_align_unchecked(new_size, layout.align());
            match (tier(&layout), tier(&new_layout)) {
                // the block already holds the new size
                (Tier::Small(old), Tier::Small(new)) if old == new => ptr,
                // a failed realloc leaves the block as it was, so it may be asked again
                (Tier::Heap, Tier::Heap) | (Tier::Aligned, Tier::Aligned) => {
                    from_heap(|| System.realloc(ptr, layout, new_size))
                }
                (Tier::Large, Tier::Large) => {
                    let p = libc::mremap(
                        ptr.cast(),
                        mapped_length(layout.size()),
                        mapped_length(new_size),
                        libc::MREMAP_MAYMOVE,
                    );
                    if p == libc::MAP_FAILED {
                        return std::ptr::null_mut();
                    }
                    advise(p, new_size);
                    p.cast()
                }
                (Tier::Small(_) | Tier::Heap | Tier::Aligned | Tier::Large, _) => {
                    // into another tier or class: a new block there, the bytes copied
                    let fresh = self.alloc(new_layout);
                    if !fresh.is_null() {
                        std::ptr::copy_nonoverlapping(ptr, fresh, layout.size().min(new_size));
                        self.dealloc(ptr, layout);
                    }
                    fresh
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Fills a block with bytes that name it, and checks them.
    fn fill(p: *mut u8, n: usize, tag: u8) {
        // SAFETY (callers): `p` is a live block of at least `n` bytes.
        for i in 0..n {
            unsafe { *p.add(i) = tag.wrapping_add(i as u8) };
        }
    }
    fn holds(p: *mut u8, n: usize, tag: u8) -> bool {
        (0..n).all(|i| unsafe { *p.add(i) } == tag.wrapping_add(i as u8))
    }

    /// An over-aligned block given back is handed to the next request of its layout, and of
    /// no other; a second one given back replaces it.
    #[test]
    fn the_spare_serves_its_own_layout() {
        let a = LargePages;
        let layout = Layout::from_size_align(135_744, 64).unwrap();
        let other = Layout::from_size_align(135_744 + 64, 64).unwrap();
        // SAFETY: valid nonzero layouts; each block is written within its size while live and
        // given back once with its layout.
        unsafe {
            let p = a.alloc(layout);
            fill(p, layout.size(), 7);
            a.dealloc(p, layout);
            let q = a.alloc(other);
            assert_ne!(q, p, "a block of another size was served from the spare");
            let r = a.alloc(layout);
            assert_eq!(r, p, "the spare was not reused");
            assert_eq!(r as usize % 64, 0);
            fill(q, other.size(), 1);
            fill(r, layout.size(), 2);
            assert!(holds(r, layout.size(), 2) && holds(q, other.size(), 1));
            a.dealloc(q, other);
            a.dealloc(r, layout); // replaces q in the slot; q goes back to the C library
            let t = a.alloc(layout);
            assert_eq!(t, p);
            a.dealloc(t, layout);
        }
    }

    proptest! {
        /// Blocks of every tier, given out, grown, shrunk and given back in random order,
        /// keep their bytes (so no two live blocks overlap) and their alignment.
        #[test]
        fn live_blocks_keep_their_bytes(
            steps in proptest::collection::vec((0usize..3, 1usize..700, 0u32..6, any::<u16>()), 1..300),
        ) {
            let a = LargePages;
            let mut live: Vec<(*mut u8, Layout, u8)> = Vec::new();
            for (step, (what, size, align, pick)) in steps.into_iter().enumerate() {
                let tag = step as u8;
                // SAFETY: every layout is valid and nonzero; each pointer is used only while
                // live, within its size, and given back with its layout.
                unsafe {
                    match what {
                        0 => {
                            let layout = Layout::from_size_align(size, 1 << align).unwrap();
                            let p = if pick % 2 == 0 { a.alloc(layout) } else { a.alloc_zeroed(layout) };
                            prop_assert!(!p.is_null());
                            prop_assert_eq!(p as usize % layout.align(), 0);
                            if pick % 2 == 1 {
                                prop_assert!((0..size).all(|i| *p.add(i) == 0), "not zeroed");
                            }
                            fill(p, size, tag);
                            live.push((p, layout, tag));
                        }
                        1 if !live.is_empty() => {
                            let (p, layout, t) = live.swap_remove(usize::from(pick) % live.len());
                            prop_assert!(holds(p, layout.size(), t), "a block lost its bytes");
                            a.dealloc(p, layout);
                        }
                        _ if !live.is_empty() => {
                            let at = usize::from(pick) % live.len();
                            let (p, layout, t) = live[at];
                            let q = a.realloc(p, layout, size);
                            prop_assert!(!q.is_null());
                            prop_assert!(holds(q, layout.size().min(size), t), "realloc lost bytes");
                            let grown = Layout::from_size_align(size, layout.align()).unwrap();
                            fill(q, size, tag);
                            live[at] = (q, grown, tag);
                        }
                        _ => {}
                    }
                }
            }
            for (p, layout, t) in live {
                prop_assert!(holds(p, layout.size(), t));
                // SAFETY: live, with its layout.
                unsafe { a.dealloc(p, layout) };
            }
        }
    }

    /// A small block given back on another thread than the one that made it is listed there
    /// and given out again whole.
    #[test]
    fn small_blocks_cross_threads() {
        let a = LargePages;
        let layout = Layout::from_size_align(40, 8).unwrap();
        // SAFETY: a valid layout; the block is filled within its size.
        let p = unsafe { a.alloc(layout) } as usize;
        fill(p as *mut u8, 40, 7);
        let again = std::thread::spawn(move || {
            let a = LargePages;
            // SAFETY: the block is live and given up here, then taken again on this thread.
            unsafe {
                assert!(holds(p as *mut u8, 40, 7));
                a.dealloc(p as *mut u8, layout);
                let q = a.alloc(layout);
                fill(q, 40, 9);
                q as usize
            }
        })
        .join()
        .unwrap();
        assert_eq!(
            again, p,
            "the freed block is this thread's first of its class"
        );
        // SAFETY: live, with its layout.
        unsafe { a.dealloc(again as *mut u8, layout) };
    }

    /// Blocks below, at and above the threshold, grown and shrunk across it, keep their bytes;
    /// a zeroed large block is zero.
    #[test]
    fn blocks_keep_their_bytes_across_the_threshold() {
        let a = LargePages;
        let sizes = [
            64,
            LARGE - 1,
            LARGE,
            LARGE + 1,
            3 * LARGE + 17,
            100,
            5 * LARGE,
        ];
        // SAFETY: every layout has a nonzero size and alignment 8; each pointer is used only
        // while live, within its size, and given back with the layout it has.
        unsafe {
            let mut layout = Layout::from_size_align(sizes[0], 8).unwrap();
            let mut p = a.alloc(layout);
            assert!(!p.is_null());
            let fill = |p: *mut u8, n: usize| {
                for i in 0..n {
                    *p.add(i) = (i % 251) as u8;
                }
            };
            let check = |p: *mut u8, n: usize| {
                for i in 0..n {
                    assert_eq!(*p.add(i), (i % 251) as u8, "byte {i} of {n}");
                }
            };
            fill(p, sizes[0]);
            for &size in &sizes[1..] {
                p = a.realloc(p, layout, size);
                assert!(!p.is_null());
                check(p, layout.size().min(size));
                layout = Layout::from_size_align(size, 8).unwrap();
                fill(p, size);
            }
            a.dealloc(p, layout);
            let zeroed = Layout::from_size_align(LARGE + 5, 8).unwrap();
            let z = a.alloc_zeroed(zeroed);
            assert!((0..zeroed.size()).step_by(997).all(|i| *z.add(i) == 0));
            a.dealloc(z, zeroed);
            // an alignment above the page goes to the C library
            let aligned = Layout::from_size_align(LARGE, 2 * PAGE).unwrap();
            assert_eq!(tier(&aligned), Tier::Heap);
            // below that size, an alignment above 16 is the spare's tier, the small sizes too
            for (size, align) in [(135_744, 64), (16, 32), (LARGE - 1, PAGE)] {
                let layout = Layout::from_size_align(size, align).unwrap();
                assert_eq!(tier(&layout), Tier::Aligned, "{layout:?}");
            }
            let q = a.alloc(aligned);
            assert_eq!(q as usize % (2 * PAGE), 0);
            a.dealloc(q, aligned);
        }
    }
}
