//! The one place the library touches its thread pool.
//!
//! With the `parallel` feature (on by default) this re-exports the few pieces of rayon the
//! kernels use; without it, the same names run on the calling thread: `par_chunks_mut` is
//! `chunks_mut`, `for_each_init` calls `init` once, `current_num_threads` is 1. The kernels
//! keep one code path either way, and they give the same values, bit for bit: only the
//! order in which chunks run differs.

#[cfg(feature = "parallel")]
pub(crate) use rayon::current_num_threads;
#[cfg(feature = "parallel")]
pub(crate) use rayon::prelude::*;

#[cfg(not(feature = "parallel"))]
pub(crate) use sequential::*;

/// Whether a batch asked to run with `parallelism` may use the thread pool.
#[inline]
pub(crate) fn allowed(parallelism: crate::geom::Parallelism) -> bool {
    cfg!(feature = "parallel") && parallelism == crate::geom::Parallelism::Auto
}

/// Runs `f` on matching chunks of `out` (`out_chunk` long) and `input` (`in_chunk` long),
/// on the pool when `parallel`, else in order on the calling thread.
pub(crate) fn zip_chunks<F>(
    parallel: bool,
    out: &mut [f64],
    out_chunk: usize,
    input: &[f64],
    in_chunk: usize,
    f: F,
) where
    F: Fn(&mut [f64], &[f64]) + Sync + Send,
{
    if parallel {
        out.par_chunks_mut(out_chunk)
            .zip(input.par_chunks(in_chunk))
            .for_each(|(o, i)| f(o, i));
    } else {
        out.chunks_mut(out_chunk)
            .zip(input.chunks(in_chunk))
            .for_each(|(o, i)| f(o, i));
    }
}

#[cfg(not(feature = "parallel"))]
mod sequential {
    //! rayon's names over std's sequential iterators.

    /// One thread: the caller's.
    pub(crate) fn current_num_threads() -> usize {
        1
    }

    /// `par_chunks`, `par_iter` on slices.
    pub(crate) trait ParallelSlice<T> {
        fn par_chunks(&self, size: usize) -> std::slice::Chunks<'_, T>;
        fn par_iter(&self) -> std::slice::Iter<'_, T>;
    }

    impl<T> ParallelSlice<T> for [T] {
        fn par_chunks(&self, size: usize) -> std::slice::Chunks<'_, T> {
            self.chunks(size)
        }
        fn par_iter(&self) -> std::slice::Iter<'_, T> {
            self.iter()
        }
    }

    /// `par_chunks_mut`, `par_iter_mut` on slices.
    pub(crate) trait ParallelSliceMut<T> {
        fn par_chunks_mut(&mut self, size: usize) -> std::slice::ChunksMut<'_, T>;
        fn par_iter_mut(&mut self) -> std::slice::IterMut<'_, T>;
    }

    impl<T> ParallelSliceMut<T> for [T] {
        fn par_chunks_mut(&mut self, size: usize) -> std::slice::ChunksMut<'_, T> {
            self.chunks_mut(size)
        }
        fn par_iter_mut(&mut self) -> std::slice::IterMut<'_, T> {
            self.iter_mut()
        }
    }

    /// `into_par_iter` on anything iterable.
    pub(crate) trait IntoParallelIterator: IntoIterator + Sized {
        fn into_par_iter(self) -> Self::IntoIter {
            self.into_iter()
        }
    }

    impl<I: IntoIterator> IntoParallelIterator for I {}

    /// rayon's iterator methods that std's `Iterator` lacks.
    pub(crate) trait ParallelIterator: Iterator + Sized {
        /// `init` once, then every item.
        fn for_each_init<S, I, F>(self, init: I, mut f: F)
        where
            I: FnOnce() -> S,
            F: FnMut(&mut S, Self::Item),
        {
            let mut state = init();
            self.for_each(|x| f(&mut state, x));
        }

        /// `init` once, then every item until the first error.
        fn try_for_each_init<S, I, F, E>(self, init: I, mut f: F) -> Result<(), E>
        where
            I: FnOnce() -> S,
            F: FnMut(&mut S, Self::Item) -> Result<(), E>,
        {
            let mut state = init();
            for x in self {
                f(&mut state, x)?;
            }
            Ok(())
        }

        /// `init` once, then a map with the state.
        fn map_init<S, I, F, R>(self, init: I, mut f: F) -> impl Iterator<Item = R>
        where
            I: FnOnce() -> S,
            F: FnMut(&mut S, Self::Item) -> R,
        {
            let mut state = init();
            self.map(move |x| f(&mut state, x))
        }

        /// `reduce` (rayon's name for the reduction without an identity).
        fn reduce_with<F>(self, f: F) -> Option<Self::Item>
        where
            F: FnMut(Self::Item, Self::Item) -> Self::Item,
        {
            self.reduce(f)
        }

        /// The first `Some`: `find_map` in order.
        fn find_map_first<R, F>(mut self, f: F) -> Option<R>
        where
            F: FnMut(Self::Item) -> Option<R>,
        {
            self.find_map(f)
        }
    }

    impl<T: Iterator> ParallelIterator for T {}
}
