//! One tree of RRT-Connect: configurations stored flat, each with its parent.

/// The parent of a root.
const ROOT: usize = usize::MAX;

/// Configurations grown from one or more roots.
#[derive(Debug, Clone)]
pub(crate) struct Tree {
    dof: usize,
    q: Vec<f64>,
    parent: Vec<usize>,
}

impl Tree {
    /// A tree of the given roots (the start, or every goal configuration).
    pub(crate) fn with_roots(dof: usize, roots: &[Vec<f64>]) -> Tree {
        let mut tree = Tree { dof, q: Vec::with_capacity(dof * 1024), parent: Vec::with_capacity(1024) };
        for r in roots {
            tree.q.extend_from_slice(r);
            tree.parent.push(ROOT);
        }
        tree
    }

    pub(crate) fn len(&self) -> usize {
        self.parent.len()
    }

    pub(crate) fn node(&self, i: usize) -> &[f64] {
        &self.q[i * self.dof..(i + 1) * self.dof]
    }

    /// Adds `q` as a child of `parent`; returns its index.
    pub(crate) fn add(&mut self, q: &[f64], parent: usize) -> usize {
        self.q.extend_from_slice(q);
        self.parent.push(parent);
        self.parent.len() - 1
    }

    /// The node nearest to `q` (Euclidean joint-space distance), by a scan:
    /// trees stay small because RRT-Connect joins them early.
    pub(crate) fn nearest(&self, q: &[f64]) -> usize {
        let mut best = (f64::INFINITY, 0);
        for (i, node) in self.q.chunks_exact(self.dof).enumerate() {
            let d: f64 = node.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum();
            if d < best.0 {
                best = (d, i);
            }
        }
        best.1
    }

    /// The configurations from node `i` back to its root, `i` first.
    pub(crate) fn to_root(&self, mut i: usize) -> Vec<Vec<f64>> {
        let mut path = vec![self.node(i).to_vec()];
        while self.parent[i] != ROOT {
            i = self.parent[i];
            path.push(self.node(i).to_vec());
        }
        path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_lead_back_to_their_root_and_nearest_is_the_closest() {
        let mut tree = Tree::with_roots(2, &[vec![0.0, 0.0], vec![5.0, 5.0]]);
        let a = tree.add(&[1.0, 0.0], 0);
        let b = tree.add(&[2.0, 0.0], a);
        let c = tree.add(&[5.0, 4.0], 1);
        assert_eq!(tree.to_root(b), [vec![2.0, 0.0], vec![1.0, 0.0], vec![0.0, 0.0]]);
        assert_eq!(tree.to_root(c), [vec![5.0, 4.0], vec![5.0, 5.0]]);
        assert_eq!(tree.nearest(&[1.9, 0.3]), b);
        assert_eq!(tree.nearest(&[6.0, 6.0]), 1);
        assert_eq!(tree.len(), 5);
    }
}
