//! Primitive assembly: which positions of the vertex (or index) stream form each triangle.

use crate::api::pipeline::Topology;

/// Triangles formed by `count` vertices.
pub fn triangle_count(topology: Topology, count: u32) -> u32 {
    match topology {
        Topology::TriangleList => count / 3,
        Topology::TriangleStrip | Topology::TriangleFan => count.saturating_sub(2),
    }
}

/// Stream positions (relative to the draw's first) of triangle `t`, provoking vertex first.
/// Strips swap the first two vertices of odd triangles so all keep the strip's winding, and
/// fans are `(t+1, t+2, 0)`: both exactly as Vulkan defines them.
#[inline]
pub fn triangle(topology: Topology, t: u32) -> [u32; 3] {
    match topology {
        Topology::TriangleList => [3 * t, 3 * t + 1, 3 * t + 2],
        Topology::TriangleStrip if t.is_multiple_of(2) => [t, t + 1, t + 2],
        Topology::TriangleStrip => [t, t + 2, t + 1],
        Topology::TriangleFan => [t + 1, t + 2, 0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_keep_their_winding() {
        assert_eq!(triangle(Topology::TriangleStrip, 0), [0, 1, 2]);
        assert_eq!(triangle(Topology::TriangleStrip, 1), [1, 3, 2]);
        assert_eq!(triangle_count(Topology::TriangleStrip, 5), 3);
        assert_eq!(triangle_count(Topology::TriangleList, 7), 2);
        assert_eq!(triangle(Topology::TriangleFan, 2), [3, 4, 0]);
    }
}
