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

/// Calls `f(i, a[i], b[i])` for every index of two slices of equal length, in parallel when the
/// `parallel` feature is enabled; allocates nothing.
pub fn for_each_zip_mut<A, B, F>(a: &mut [A], b: &mut [B], f: F)
where
    A: Send,
    B: Send,
    F: Fn(usize, &mut A, &mut B) + Sync + Send,
{
    debug_assert_eq!(a.len(), b.len());
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        a.par_iter_mut()
            .zip(b.par_iter_mut())
            .enumerate()
            .for_each(|(i, (x, y))| f(i, x, y));
    }
    #[cfg(not(feature = "parallel"))]
    {
        a.iter_mut()
            .zip(b.iter_mut())
            .enumerate()
            .for_each(|(i, (x, y))| f(i, x, y));
    }
}

/// Calls `f(i, a[i])` for every element, in parallel when the `parallel` feature is enabled;
/// allocates nothing.
pub fn for_each_mut<A, F>(a: &mut [A], f: F)
where
    A: Send,
    F: Fn(usize, &mut A) + Sync + Send,
{
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        a.par_iter_mut().enumerate().for_each(|(i, x)| f(i, x));
    }
    #[cfg(not(feature = "parallel"))]
    {
        a.iter_mut().enumerate().for_each(|(i, x)| f(i, x));
    }
}
