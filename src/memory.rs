//! Large working arrays on transparent huge pages.
//!
//! The fast paths fill arrays of tens to hundreds of megabytes (an isosurface's vertices and
//! triangles, a decimation's fan lists). On 4 KiB pages their first touch costs one page
//! fault per page and their random access one TLB miss per page; on Linux, where transparent
//! huge pages are commonly enabled in `madvise` mode, asking for 2 MiB pages removes most of
//! both (on the 256³ gyroid the fast extraction ran about 30 % faster). Elsewhere, or when the
//! kernel declines, nothing changes.
//!
//! The crate's only `unsafe` code is here: two calls that change timing, not memory (a cache
//! prefetch hint and `madvise(MADV_HUGEPAGE)`); each carries its proof of soundness.
#![allow(unsafe_code)]

use crate::par::prelude::*;

/// Arrays smaller than this are left alone (one huge page).
const THRESHOLD: usize = 2 << 20;

/// Arrays of at least this many bytes are first written on all cores (rayon): the kernel
/// clears each page at its first touch, and on the 810k-node decimation that clearing took
/// about a tenth of a second on one core.
const PARALLEL_FILL: usize = 4 << 20;

/// Asks the kernel to back the pages wholly inside `v`'s allocation (its capacity, filled or
/// not) with huge pages. Call it before the buffer is first written.
pub fn advise_huge_pages<T>(v: &mut Vec<T>) {
    let bytes = v.capacity() * std::mem::size_of::<T>();
    if bytes < THRESHOLD {
        return;
    }
    advise(v.as_mut_ptr() as usize, bytes);
}

/// `vec![value; n]`, with [`advise_huge_pages`] applied before it is filled (on all cores
/// when large).
pub fn huge_vec<T: Clone + Send + Sync>(value: T, n: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    advise_huge_pages(&mut v);
    if n.saturating_mul(std::mem::size_of::<T>()) >= PARALLEL_FILL {
        v.par_extend(crate::par::repeat_n(value, n));
    } else {
        v.resize(n, value);
    }
    v
}

/// A copy of `items`, with [`advise_huge_pages`] applied before it is filled (on all cores
/// when large).
pub fn huge_copy<T: Clone + Send + Sync>(items: &[T]) -> Vec<T> {
    let mut v = Vec::with_capacity(items.len());
    advise_huge_pages(&mut v);
    if std::mem::size_of_val(items) >= PARALLEL_FILL {
        v.par_extend(items.par_iter().cloned());
    } else {
        v.extend_from_slice(items);
    }
    v
}

/// Writes `value` over `v`'s spare capacity on all cores and truncates `v` back, when that
/// capacity is large: its pages are then present (cleared by the kernel in parallel) before
/// a sequential writer appends to `v`. Contents and capacity are unchanged.
pub fn prefault<T: Clone + Send + Sync>(v: &mut Vec<T>, value: T) {
    let len = v.len();
    let spare = v.capacity() - len;
    if spare.saturating_mul(std::mem::size_of::<T>()) >= PARALLEL_FILL {
        v.par_extend(crate::par::repeat_n(value, spare));
        v.truncate(len);
    }
}

/// Asks the processor to start loading the cache line holding `item` (a hint: it changes
/// nothing but timing). A no-op off x86-64.
#[inline(always)]
pub fn prefetch<T>(item: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: the pointer comes from a live reference. `prefetch` is an architectural
        // no-op: it never faults (not even on invalid addresses), reads nothing into the
        // program and writes nothing; it only moves a line toward the cache. SSE, its target
        // feature, is part of the x86-64 baseline, so the instruction always exists.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(item as *const T as *const i8) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = item;
}

#[cfg(target_os = "linux")]
fn advise(start: usize, bytes: usize) {
    const PAGE: usize = 4096;
    let first = start.div_ceil(PAGE) * PAGE;
    let last = (start + bytes) / PAGE * PAGE;
    if last > first {
        // SAFETY: `[first, last)` is a page-aligned range inside one live allocation that we
        // own (a `Vec`'s buffer, aligned inwards). `madvise(MADV_HUGEPAGE)` only records a
        // paging preference for those pages: it does not read, write, move or free memory,
        // so no Rust reference or value is affected. Its result is ignored on purpose: when
        // it fails (THP disabled, old kernel) the memory stays on ordinary pages.
        unsafe {
            libc::madvise(
                first as *mut libc::c_void,
                last - first,
                libc::MADV_HUGEPAGE,
            );
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_start: usize, _bytes: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_vec_is_an_ordinary_vec() {
        let v = huge_vec(7u32, 3 << 20);
        assert_eq!(v.len(), 3 << 20);
        assert!(v.iter().all(|&x| x == 7));
        let mut w: Vec<u64> = Vec::with_capacity(1 << 20);
        advise_huge_pages(&mut w);
        w.extend(0..10);
        assert_eq!(w[9], 9);
        let cap = w.capacity();
        prefault(&mut w, 0);
        assert_eq!((w.len(), w.capacity(), w[9]), (10, cap, 9));
        let big: Vec<u64> = (0..1u64 << 20).collect();
        assert_eq!(huge_copy(&big), big);
    }
}
