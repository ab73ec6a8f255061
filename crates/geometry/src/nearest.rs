//! Nearest-vertex queries on a point cloud: a static k-d tree (median split along the widest
//! axis of each box, leaves of a few points), O(log n) per query wherever the query lies.

/// A k-d tree over a slice of points.
pub struct KdTree<'a> {
    points: &'a [[f64; 3]],
    /// Point indices, permuted so each node owns a contiguous range.
    order: Vec<u32>,
    nodes: Vec<Node>,
}

const LEAF: usize = 8;

#[derive(Clone, Copy)]
struct Node {
    start: usize,
    end: usize,
    /// Split axis and value (unused for a leaf).
    axis: usize,
    split: f64,
    /// Children (0: leaf).
    left: usize,
    right: usize,
}

impl<'a> KdTree<'a> {
    pub fn new(points: &'a [[f64; 3]]) -> Self {
        let mut tree = Self {
            points,
            order: (0..points.len() as u32).collect(),
            nodes: Vec::new(),
        };
        if !points.is_empty() {
            tree.build(0, points.len());
        }
        tree
    }

    fn build(&mut self, start: usize, end: usize) -> usize {
        let id = self.nodes.len();
        self.nodes.push(Node {
            start,
            end,
            axis: 0,
            split: 0.0,
            left: 0,
            right: 0,
        });
        if end - start <= LEAF {
            return id;
        }
        let pts = self.points;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &i in &self.order[start..end] {
            for k in 0..3 {
                lo[k] = lo[k].min(pts[i as usize][k]);
                hi[k] = hi[k].max(pts[i as usize][k]);
            }
        }
        let axis = (0..3)
            .max_by(|&p, &q| (hi[p] - lo[p]).total_cmp(&(hi[q] - lo[q])))
            .unwrap_or(0);
        let mid = (start + end) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |&p, &q| {
            pts[p as usize][axis].total_cmp(&pts[q as usize][axis])
        });
        let split = pts[self.order[mid] as usize][axis];
        let left = self.build(start, mid);
        let right = self.build(mid, end);
        let node = &mut self.nodes[id];
        node.axis = axis;
        node.split = split;
        node.left = left;
        node.right = right;
        id
    }

    /// Distance from `q` to the nearest point (infinity for an empty cloud).
    pub fn nearest_distance(&self, q: [f64; 3]) -> f64 {
        if self.nodes.is_empty() {
            return f64::INFINITY;
        }
        let mut best2 = f64::INFINITY;
        self.search(0, &q, &mut best2);
        best2.sqrt()
    }

    fn search(&self, id: usize, q: &[f64; 3], best2: &mut f64) {
        let n = self.nodes[id];
        if n.left == 0 {
            for &i in &self.order[n.start..n.end] {
                let p = self.points[i as usize];
                let d2 = (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>();
                if d2 < *best2 {
                    *best2 = d2;
                }
            }
            return;
        }
        let diff = q[n.axis] - n.split;
        let (near, far) = if diff < 0.0 {
            (n.left, n.right)
        } else {
            (n.right, n.left)
        };
        self.search(near, q, best2);
        if diff * diff < *best2 {
            self.search(far, q, best2);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tree_agrees_with_brute_force() {
        let pts: Vec<[f64; 3]> = (0..700)
            .map(|i| {
                let t = i as f64 * 0.37;
                [t.sin() * 2.0, (1.7 * t).cos(), (0.3 * t).sin() * 0.5]
            })
            .collect();
        let tree = KdTree::new(&pts);
        for k in 0..300 {
            let s = k as f64 * 0.91;
            let q = [s.cos() * 3.0, s.sin(), (2.0 * s).cos() * 10.0];
            let brute = pts
                .iter()
                .map(|p| (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>().sqrt())
                .fold(f64::INFINITY, f64::min);
            assert!((tree.nearest_distance(q) - brute).abs() < 1e-12);
        }
        assert!(KdTree::new(&[]).nearest_distance([0.0; 3]).is_infinite());
    }
}
