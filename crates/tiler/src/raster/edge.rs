//! Edge functions and the top-left fill rule.
//!
//! For a triangle oriented so that its signed area is positive in window coordinates (y down;
//! setup swaps two vertices where needed), the edge from `a` to `b` has the edge function
//!
//! ```text
//!   E(p) = A·p.x + B·p.y + C,   A = a.y − b.y,   B = b.x − a.x,   C = −(A·a.x + B·a.y)
//! ```
//!
//! in sub-pixels, positive on the triangle's side. A sample is covered when it is on the
//! inner side of all three edges. **Top-left rule** (Vulkan "Polygon Rasterization", the same
//! as Direct3D's): a sample exactly on an edge is covered only if the edge is a *top* edge
//! (horizontal, with the triangle below it: `A = 0, B > 0`) or a *left* edge (the triangle
//! to its right: `A > 0`). So two triangles sharing an edge never both cover a sample on it,
//! and a mesh covers each sample exactly once. The rule is folded into `C`: for edges that
//! are neither top nor left, `C` is lowered by one, and then "covered" is simply `E ≥ 0`
//! everywhere (E is an integer).

use super::fixed::SubPixel;

/// One edge function, with the fill rule folded into `c` (covered ⇔ `eval ≥ 0`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    pub a: i64,
    pub b: i64,
    pub c: i64,
}

impl Edge {
    /// The edge from `a` to `b` of a triangle with positive signed area.
    pub fn new(a: (SubPixel, SubPixel), b: (SubPixel, SubPixel)) -> Edge {
        let (ax, ay) = (a.0.raw(), a.1.raw());
        let (bx, by) = (b.0.raw(), b.1.raw());
        let ea = ay - by;
        let eb = bx - ax;
        let c = -(ea * ax + eb * ay);
        let top_left = ea > 0 || (ea == 0 && eb > 0);
        Edge { a: ea, b: eb, c: if top_left { c } else { c - 1 } }
    }

    /// E at a position in sub-pixels.
    #[inline(always)]
    pub fn eval(&self, x: i64, y: i64) -> i64 {
        self.a * x + self.b * y + self.c
    }

    /// The largest E over the rectangle `[x0, x1] × [y0, y1]` of sample positions (sub-pixels):
    /// E is linear, so it is reached at the corner the gradient points to. Negative means no
    /// sample in the rectangle is covered by this edge.
    #[inline(always)]
    pub fn max_over(&self, x0: i64, y0: i64, x1: i64, y1: i64) -> i64 {
        self.eval(if self.a > 0 { x1 } else { x0 }, if self.b > 0 { y1 } else { y0 })
    }

    /// The smallest E over the rectangle: non-negative means every sample in it is covered by
    /// this edge.
    #[inline(always)]
    pub fn min_over(&self, x0: i64, y0: i64, x1: i64, y1: i64) -> i64 {
        self.eval(if self.a > 0 { x0 } else { x1 }, if self.b > 0 { y0 } else { y1 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: i32, y: i32) -> (SubPixel, SubPixel) {
        (SubPixel(x * 256), SubPixel(y * 256))
    }

    #[test]
    fn classifies_top_and_left_edges() {
        // (0,0) → (4,0) → (0,4): positive area in y-down coordinates.
        let (a, b, c) = (p(0, 0), p(4, 0), p(0, 4));
        let top = Edge::new(a, b);
        let hypotenuse = Edge::new(b, c);
        let left = Edge::new(c, a);
        // On the top edge and on the left edge: covered; on the hypotenuse: not.
        assert!(top.eval(256, 0) >= 0);
        assert!(left.eval(0, 256) >= 0);
        assert!(hypotenuse.eval(512, 512) < 0);
        // Inside: covered by all three.
        assert!([top, hypotenuse, left].iter().all(|e| e.eval(256, 256) >= 0));
    }

    #[test]
    fn extremes_bound_every_sample() {
        let e = Edge::new(p(0, 0), p(3, 7));
        let (mut lo, mut hi) = (i64::MAX, i64::MIN);
        for x in 0..=8 {
            for y in 0..=8 {
                let v = e.eval(x * 100, y * 100);
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        assert_eq!(e.max_over(0, 0, 800, 800), hi);
        assert_eq!(e.min_over(0, 0, 800, 800), lo);
    }
}
