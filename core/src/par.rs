//! Data parallelism over substructures and interfaces: rayon when the `parallel` feature is on
//! (native default), a plain loop otherwise (wasm32 needs no threads).

/// Applies `f` to every element (with its index) and collects the results, in parallel when the
/// `parallel` feature is enabled.
pub fn map_mut<T, R, F>(items: &mut [T], f: F) -> Vec<R>
where
    T: Send,
    R: Send,
    F: Fn(usize, &mut T) -> R + Sync + Send,
{
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items
            .par_iter_mut()
            .enumerate()
            .map(|(i, t)| f(i, t))
            .collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        items.iter_mut().enumerate().map(|(i, t)| f(i, t)).collect()
    }
}

/// Maps `f` over `0..n`, in parallel when the `parallel` feature is enabled.
pub fn map_range<R, F>(n: usize, f: F) -> Vec<R>
where
    R: Send,
    F: Fn(usize) -> R + Sync + Send,
{
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        (0..n).into_par_iter().map(f).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        (0..n).map(f).collect()
    }
}
