//! Disjoint sets (union-find) with deterministic component labels.

/// Disjoint sets over the elements `0..len`, with path halving. A union makes the
/// smaller root the parent, so every component's root is its smallest element and
/// the result does not depend on the order of the unions.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` singleton sets.
    ///
    /// # Panics
    /// If `n` exceeds `u32::MAX` (the parents are stored as `u32`).
    pub fn new(n: usize) -> Self {
        let n = u32::try_from(n).expect("a union-find holds at most u32::MAX elements");
        Self {
            parent: (0..n).collect(),
        }
    }

    /// How many elements there are.
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// Whether there are no elements.
    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// The root (smallest element) of `i`'s set.
    pub fn find(&mut self, i: usize) -> usize {
        let mut i = i as u32;
        while self.parent[i as usize] != i {
            let p = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = p;
            i = p;
        }
        i as usize
    }

    /// Joins the sets of `a` and `b`; whether they were apart.
    pub fn union(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return false;
        }
        self.parent[ra.max(rb)] = ra.min(rb) as u32;
        true
    }

    /// A label per element of `items`, in its order: components are numbered 0, 1, …
    /// in the order in which `items` first meets them.
    pub fn labels_of(&mut self, items: impl IntoIterator<Item = usize>) -> Vec<u32> {
        let mut label = vec![u32::MAX; self.len()];
        let mut next = 0;
        items
            .into_iter()
            .map(|i| {
                let root = self.find(i);
                if label[root] == u32::MAX {
                    label[root] = next;
                    next += 1;
                }
                label[root]
            })
            .collect()
    }

    /// A label per element, components numbered 0, 1, … by their smallest element.
    pub fn labels(&mut self) -> Vec<u32> {
        self.labels_of(0..self.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_follow_the_smallest_element_whatever_the_union_order() {
        let mut a = UnionFind::new(6);
        assert!(a.union(5, 3));
        assert!(a.union(1, 5));
        assert!(!a.union(3, 1));
        let mut b = UnionFind::new(6);
        b.union(1, 3);
        b.union(3, 5);
        assert_eq!(a.labels(), vec![0, 1, 2, 1, 3, 1]);
        assert_eq!(a.labels(), b.labels());
        assert_eq!(a.find(5), 1);
        assert_eq!(a.labels_of([4, 3, 0]), vec![0, 1, 2]);
    }
}
