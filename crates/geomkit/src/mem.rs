//! Large result buffers.
//!
//! A result of 10^7 points is hundreds of megabytes of fresh memory, and on Linux each 4 KB
//! page of it costs a page fault when it is first written (a fifth of an interpolation's
//! time at that size). [`zeros`] asks the kernel for transparent huge pages (2 MB, one
//! fault each) on large buffers, as NumPy does for its arrays (`madvise(MADV_HUGEPAGE)`):
//! where the system allows them (`/sys/kernel/mm/transparent_hugepage/enabled` set to
//! `madvise` or `always`) the faults drop 512-fold; elsewhere, and on other systems, the
//! advice is a no-op. The contents never change.

/// Buffers of at least this many bytes are advised: glibc's allocator maps buffers this
/// large afresh every time (its largest mmap threshold), so the advice meets untouched
/// pages. (Smaller ones come from reused heap memory, where advising measured slower, not
/// faster: NumPy's threshold of 4 MB was tried.)
const HUGE_FROM: usize = 1 << 25;

/// `len` zeros for a large result that the caller's threads then fill, its pages advised
/// as huge pages where that helps (module docs): the buffer to give a batched evaluation
/// of millions of points, as NumPy's arrays are for the Python package.
///
/// ```
/// use geomkit::bspline::BsplineCurve;
/// let curve = BsplineCurve::new(1, vec![0.0, 0.0, 1.0, 1.0], vec![vec![0.0], vec![2.0]]).unwrap();
/// let ts: Vec<f64> = (0..5).map(|i| i as f64 / 4.0).collect();
/// let mut out = geomkit::mem::zeros(ts.len());
/// curve.eval_many_par(&ts, &mut out).unwrap();
/// assert_eq!(out, [0.0, 0.5, 1.0, 1.5, 2.0]);
/// ```
pub fn zeros(len: usize) -> Vec<f64> {
    let v = vec![0.0f64; len];
    if len * std::mem::size_of::<f64>() >= HUGE_FROM {
        advise_huge(&v);
    }
    v
}

/// A copy of `v` for a large result: [`zeros`] filled in parallel blocks (the first-touch
/// faults shared by the threads) where `v` is long.
pub(crate) fn copy_of(v: &[f64]) -> Vec<f64> {
    const BLOCK: usize = 1 << 16;
    if v.len() <= BLOCK {
        return v.to_vec();
    }
    use crate::par::*;
    let mut out = zeros(v.len());
    out.par_chunks_mut(BLOCK)
        .zip(v.par_chunks(BLOCK))
        .for_each(|(o, i)| o.copy_from_slice(i));
    out
}

#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
fn advise_huge(v: &[f64]) {
    const PAGE: usize = 4096;
    let start = v.as_ptr() as usize;
    let end = start + std::mem::size_of_val(v);
    let first = start.next_multiple_of(PAGE);
    if first >= end {
        return;
    }
    // SAFETY: the range [first, end) lies inside `v`'s allocation, `first` is page aligned
    // as madvise requires, and MADV_HUGEPAGE only changes how the kernel backs the pages
    // (never their contents or their mapping), so no Rust reference is affected. A failure
    // (e.g. a kernel without transparent huge pages) leaves everything as it was and is
    // ignored.
    unsafe {
        libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge(_: &[f64]) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeros_are_zeros_of_the_length_asked() {
        for len in [0, 1, 1000, HUGE_FROM / 8 + 3] {
            let v = zeros(len);
            assert_eq!(v.len(), len);
            assert!(v.iter().all(|&x| x == 0.0));
            let w: Vec<f64> = (0..len).map(|i| i as f64 - 0.5).collect();
            assert_eq!(copy_of(&w), w);
        }
    }
}
