//! Leaf blocks on huge pages.
//!
//! The traversal of a large mesh reads leaf blocks scattered over tens of megabytes (160 bytes
//! each: about 42 MB for the 1M-triangle benchmark mesh, 170 MB for 4M), so on 4 KiB pages almost
//! every block it visits needs an address translation of its own. Linux backs an anonymous
//! range with 2 MiB pages when asked to (`madvise(MADV_HUGEPAGE)`, for transparent huge pages
//! in `madvise` mode, the setting of most distributions) before the range is first touched: the
//! block array is allocated, its 2 MiB-aligned interior advised, and only then filled. It is a
//! hint: contents and results are the same with or without it, and off Linux, or where huge
//! pages are disabled, it is a plain allocation. The interior node array (224 bytes a node, an
//! eighth of the blocks' size) is built by the tree build and left as it is: copying it onto
//! advised memory would raise the peak by its size.
//!
//! Measured side by side (`OPHIS_HUGE_PAGES=0` against the default, one thread each, CPU time,
//! 2026-12-03): cornell-mesh 1.033× (se 0.018, 8 pairs), 1.011× (0.016, 16 pairs) and 1.024×
//! (0.014, 10 pairs), the 4M mesh 1.032× (0.015, 8 pairs); cornell-box, whose blocks fill no
//! huge page, 1.020× (0.019): the method's noise.

/// Size of a huge page (x86-64 and most Linux configurations).
const HUGE: usize = 2 << 20;

/// An empty vector with room for `n` values whose memory was advised to use huge pages before
/// anything was written to it (see the module notes), for the caller to fill, in parallel
/// (rayon's `collect_into_vec` writes in place when the capacity suffices): the pages are then
/// first touched, and cleared by the kernel, on all threads rather than on one.
/// `OPHIS_HUGE_PAGES=0` in the environment skips the advice.
pub fn with_capacity<T>(n: usize) -> Vec<T> {
    let v: Vec<T> = Vec::with_capacity(n);
    if let Some((start, len)) = interior(v.as_ptr() as usize, n * std::mem::size_of::<T>()) {
        if std::env::var_os("OPHIS_HUGE_PAGES").is_none_or(|s| s != "0") {
            advise(start, len);
        }
    }
    v
}

/// The whole huge pages inside `len` bytes from `start`: their first address and length.
fn interior(start: usize, len: usize) -> Option<(usize, usize)> {
    let first = start.checked_next_multiple_of(HUGE)?;
    let end = start.checked_add(len)? & !(HUGE - 1);
    (end > first).then(|| (first, end - first))
}

#[cfg(target_os = "linux")]
fn advise(start: usize, len: usize) {
    // SAFETY: the range lies inside an allocation the caller owns; MADV_HUGEPAGE changes only
    // how pages not yet touched will be backed, never any contents. A failure (e.g. a kernel
    // without transparent huge pages) leaves ordinary pages: ignored.
    unsafe {
        libc::madvise(start as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_: usize, _: usize) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interior_is_the_whole_huge_pages_inside_the_range() {
        assert_eq!(interior(0, 3 * HUGE), Some((0, 3 * HUGE)));
        assert_eq!(interior(1, 3 * HUGE), Some((HUGE, 2 * HUGE)));
        assert_eq!(
            interior(HUGE - 4096, 2 * HUGE + 4096),
            Some((HUGE, 2 * HUGE))
        );
        assert_eq!(interior(4096, HUGE), None);
        assert_eq!(interior(HUGE, HUGE - 1), None);
        assert_eq!(interior(8, 0), None);
        assert_eq!(interior(usize::MAX - 10, 100), None);
        for (start, len) in [(12345usize, 7 * HUGE + 999), (HUGE * 5 + 64, HUGE * 3)] {
            let (a, n) = interior(start, len).unwrap();
            assert!(a >= start && a + n <= start + len && a % HUGE == 0 && n % HUGE == 0);
            assert!(a - start < HUGE && start + len - (a + n) < HUGE);
        }
    }

    #[test]
    fn with_capacity_holds_the_values_whatever_the_size() {
        use rayon::prelude::*;
        for n in [0, 1, 1000, (3 * HUGE) / 160 + 7] {
            let mut v = with_capacity::<[u32; 40]>(n);
            assert!(v.is_empty() && v.capacity() >= n);
            let at = v.as_ptr();
            (0..n)
                .into_par_iter()
                .map(|i| [i as u32; 40])
                .collect_into_vec(&mut v);
            assert_eq!(v.len(), n);
            // Filled in place, in the advised buffer.
            assert!(n == 0 || v.as_ptr() == at);
            assert!(v.iter().enumerate().all(|(i, b)| *b == [i as u32; 40]));
        }
        assert!(with_capacity::<()>(5).is_empty());
    }
}
