//! A set of cell indices 0..n that finds its k-th smallest member in O(log n) (a Fenwick tree of
//! membership counts): the granular generator draws a random free cell and a random frontier
//! cell of a growing grain this way, so a layout costs O(cells log cells) however large the grid
//! or the grains, and draws exactly the cells a sorted list would give.

/// Cells 0..n, each in or out of the set.
#[derive(Debug, Clone)]
pub struct CellSet {
    /// Fenwick tree of membership counts (1-based).
    tree: Vec<u32>,
    member: Vec<bool>,
    len: usize,
}

impl CellSet {
    /// The empty set over cells 0..n.
    pub fn empty(n: usize) -> Self {
        Self {
            tree: vec![0; n + 1],
            member: vec![false; n],
            len: 0,
        }
    }

    /// Every cell 0..n (built in O(n)).
    pub fn full(n: usize) -> Self {
        let mut tree = vec![0u32; n + 1];
        for i in 1..=n {
            tree[i] += 1;
            let parent = i + (i & i.wrapping_neg());
            if parent <= n {
                tree[parent] += tree[i];
            }
        }
        Self {
            tree,
            member: vec![true; n],
            len: n,
        }
    }

    /// Members.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no cell is a member.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Whether cell `c` is a member.
    pub fn contains(&self, c: usize) -> bool {
        self.member[c]
    }

    /// Adds cell `c` (nothing if it is a member).
    pub fn insert(&mut self, c: usize) {
        if !self.member[c] {
            self.member[c] = true;
            self.len += 1;
            self.update(c, true);
        }
    }

    /// Removes cell `c` (nothing if it is not a member).
    pub fn remove(&mut self, c: usize) {
        if self.member[c] {
            self.member[c] = false;
            self.len -= 1;
            self.update(c, false);
        }
    }

    fn update(&mut self, c: usize, add: bool) {
        let mut i = c + 1;
        while i < self.tree.len() {
            if add {
                self.tree[i] += 1;
            } else {
                self.tree[i] -= 1;
            }
            i += i & i.wrapping_neg();
        }
    }

    /// The member of rank `k` in increasing order (0-based); `k` must be below [`Self::len`].
    pub fn nth(&self, k: usize) -> usize {
        debug_assert!(k < self.len);
        let n = self.tree.len() - 1;
        let mut pos = 0;
        let mut rest = k as u64;
        let mut step = if n == 0 { 0 } else { 1 << n.ilog2() };
        while step > 0 {
            let next = pos + step;
            if next <= n && u64::from(self.tree[next]) <= rest {
                pos = next;
                rest -= u64::from(self.tree[next]);
            }
            step >>= 1;
        }
        // pos cells before the answer hold exactly k members
        pos
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::splitmix::SplitMix64;

    /// Random inserts and removals against a sorted list: the same k-th member every time.
    #[test]
    fn nth_matches_a_sorted_list() {
        for n in [1usize, 2, 7, 64, 200] {
            let mut rng = SplitMix64(n as u64);
            let mut set = CellSet::empty(n);
            let mut full = CellSet::full(n);
            let mut list: Vec<usize> = Vec::new();
            for _ in 0..4 * n {
                let c = rng.below(n);
                if rng.below(3) == 0 {
                    set.remove(c);
                    full.insert(c);
                    list.retain(|&x| x != c);
                } else {
                    set.insert(c);
                    full.remove(c);
                    if let Err(at) = list.binary_search(&c) {
                        list.insert(at, c);
                    }
                }
                assert_eq!(set.len(), list.len());
                assert_eq!(full.len(), n - list.len());
                for (k, &x) in list.iter().enumerate() {
                    assert_eq!(set.nth(k), x);
                    assert!(set.contains(x) && !full.contains(x));
                }
                let rest: Vec<usize> = (0..n).filter(|&c| !set.contains(c)).collect();
                for (k, &x) in rest.iter().enumerate() {
                    assert_eq!(full.nth(k), x);
                }
            }
        }
    }
}
