//! Data parallelism: on all cores (rayon) with the `parallel` feature, and the same calls run
//! sequentially on the calling thread without it. Results never depend on the choice: every
//! parallel pass in geocert writes disjoint outputs or reduces with an order-independent
//! operation (`min`, `all`, collecting in index order).

#[cfg(feature = "parallel")]
pub(crate) mod prelude {
    pub(crate) use rayon::prelude::*;
}

#[cfg(feature = "parallel")]
pub(crate) use rayon::iter::repeat_n;

/// Threads a parallel pass runs on: rayon's pool size, or 1 without the `parallel` feature.
pub(crate) fn threads() -> usize {
    #[cfg(feature = "parallel")]
    return rayon::current_num_threads();
    #[cfg(not(feature = "parallel"))]
    return 1;
}

#[cfg(not(feature = "parallel"))]
pub(crate) use std::iter::repeat_n;

/// Sequential stand-ins for the rayon methods geocert calls, with the same names.
#[cfg(not(feature = "parallel"))]
pub(crate) mod prelude {
    /// `into_par_iter`: the ordinary iterator.
    pub(crate) trait IntoParallelIterator: IntoIterator + Sized {
        fn into_par_iter(self) -> Self::IntoIter {
            self.into_iter()
        }
    }
    impl<I: IntoIterator> IntoParallelIterator for I {}

    /// `par_iter`, `par_chunks`, `par_windows` on slices.
    pub(crate) trait ParallelSlice<T> {
        fn par_iter(&self) -> std::slice::Iter<'_, T>;
        fn par_chunks(&self, n: usize) -> std::slice::Chunks<'_, T>;
        fn par_windows(&self, n: usize) -> std::slice::Windows<'_, T>;
    }
    impl<T> ParallelSlice<T> for [T] {
        fn par_iter(&self) -> std::slice::Iter<'_, T> {
            self.iter()
        }
        fn par_chunks(&self, n: usize) -> std::slice::Chunks<'_, T> {
            self.chunks(n)
        }
        fn par_windows(&self, n: usize) -> std::slice::Windows<'_, T> {
            self.windows(n)
        }
    }

    /// `par_iter_mut`, `par_chunks_mut` on slices.
    pub(crate) trait ParallelSliceMut<T> {
        fn par_iter_mut(&mut self) -> std::slice::IterMut<'_, T>;
        fn par_chunks_mut(&mut self, n: usize) -> std::slice::ChunksMut<'_, T>;
    }
    impl<T> ParallelSliceMut<T> for [T] {
        fn par_iter_mut(&mut self) -> std::slice::IterMut<'_, T> {
            self.iter_mut()
        }
        fn par_chunks_mut(&mut self, n: usize) -> std::slice::ChunksMut<'_, T> {
            self.chunks_mut(n)
        }
    }

    /// `map_init` (one state for the whole sequential pass) and `flatten_iter`.
    pub(crate) trait ParallelIterator: Iterator + Sized {
        fn map_init<S, R>(
            self,
            init: impl Fn() -> S,
            f: impl Fn(&mut S, Self::Item) -> R,
        ) -> impl Iterator<Item = R> {
            let mut state = init();
            self.map(move |x| f(&mut state, x))
        }

        fn flatten_iter(self) -> std::iter::Flatten<Self>
        where
            Self::Item: IntoIterator,
        {
            self.flatten()
        }
    }
    impl<I: Iterator> ParallelIterator for I {}

    /// `par_extend`: `extend`.
    pub(crate) trait ParallelExtend<T> {
        fn par_extend(&mut self, items: impl IntoIterator<Item = T>);
    }
    impl<T> ParallelExtend<T> for Vec<T> {
        fn par_extend(&mut self, items: impl IntoIterator<Item = T>) {
            self.extend(items)
        }
    }
}

/// `rayon::join` with the `parallel` feature (both closures possibly on two threads), else
/// `(a(), b())` in order.
pub(crate) fn join<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    #[cfg(feature = "parallel")]
    return rayon::join(a, b);
    #[cfg(not(feature = "parallel"))]
    return (a(), b());
}

/// `items.iter().map(f)` collected in order, the items taken in order one at a time by
/// whichever thread is free (list scheduling: with the largest items first, no core is
/// left alone with a large one at the end, which rayon's halving of the range does not
/// promise). Sequential without the `parallel` feature.
pub(crate) fn map_in_turn<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    #[cfg(feature = "parallel")]
    {
        use std::sync::atomic::{AtomicUsize, Ordering};
        use std::sync::Mutex;
        let next = AtomicUsize::new(0);
        let done: Mutex<Vec<(usize, R)>> = Mutex::new(Vec::with_capacity(items.len()));
        rayon::scope(|s| {
            for _ in 0..threads().min(items.len()) {
                s.spawn(|_| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break };
                        mine.push((i, f(item)));
                    }
                    // A poisoned lock can only follow a panic in `f`, which rayon re-raises.
                    if let Ok(mut all) = done.lock() {
                        all.append(&mut mine);
                    }
                });
            }
        });
        let mut all = done.into_inner().unwrap_or_else(|e| e.into_inner());
        all.sort_by_key(|(i, _)| *i);
        all.into_iter().map(|(_, r)| r).collect()
    }
    #[cfg(not(feature = "parallel"))]
    items.iter().map(f).collect()
}
