//! Primitive assembly: which positions of the vertex (or index) stream form each triangle or
//! line segment. A segment is drawn as two triangles, so line topologies count two per segment.

use crate::api::pipeline::{ProvokingVertex, Topology};

/// Triangles formed by `count` vertices.
pub fn triangle_count(topology: Topology, count: u32) -> u32 {
    match topology {
        Topology::TriangleList => count / 3,
        Topology::TriangleStrip | Topology::TriangleFan => count.saturating_sub(2),
        Topology::LineList | Topology::LineStrip | Topology::LineLoop => 2 * segment_count(topology, count),
        Topology::PointList => 2 * count,
    }
}

/// Line segments formed by `count` vertices.
pub fn segment_count(topology: Topology, count: u32) -> u32 {
    match topology {
        Topology::LineList => count / 2,
        Topology::LineStrip => count.saturating_sub(1),
        Topology::LineLoop if count >= 2 => count,
        _ => 0,
    }
}

/// Stream positions of segment `s` of a line topology drawn with `count` vertices.
#[inline]
pub fn segment(topology: Topology, s: u32, count: u32) -> [u32; 2] {
    match topology {
        Topology::LineList => [2 * s, 2 * s + 1],
        Topology::LineLoop if s + 1 == count => [s, 0],
        _ => [s, s + 1],
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
        Topology::LineList | Topology::LineStrip | Topology::LineLoop | Topology::PointList => {
            unreachable!("lines and points are expanded")
        }
    }
}

/// Which of [`triangle`]'s three positions is the provoking vertex (see [`ProvokingVertex`]):
/// the first is always 0; the last stream position is `3t + 2` or `t + 2`, which odd strip
/// triangles and fans hold at 1.
#[inline]
pub fn provoking_corner(topology: Topology, t: u32, provoking: ProvokingVertex) -> usize {
    match (provoking, topology) {
        (ProvokingVertex::First, _) => 0,
        (ProvokingVertex::Last, Topology::TriangleStrip) if !t.is_multiple_of(2) => 1,
        (ProvokingVertex::Last, Topology::TriangleFan) => 1,
        (ProvokingVertex::Last, _) => 2,
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

    /// GL's last vertex is the highest stream position of each triangle (ES 3.0 table 2.12:
    /// `3t + 2` for lists, `t + 2` for strips and fans); Vulkan's first is `triangle`'s first.
    #[test]
    fn provoking_corners_name_gl_and_vulkan_vertices() {
        for topology in [Topology::TriangleList, Topology::TriangleStrip, Topology::TriangleFan] {
            for t in 0..6 {
                let positions = triangle(topology, t);
                let last = positions[provoking_corner(topology, t, ProvokingVertex::Last)];
                let expected = if topology == Topology::TriangleList { 3 * t + 2 } else { t + 2 };
                assert_eq!(last, expected, "{topology:?} triangle {t}");
                assert_eq!(provoking_corner(topology, t, ProvokingVertex::First), 0);
            }
        }
    }

    #[test]
    fn line_topologies_count_two_triangles_per_segment() {
        assert_eq!(triangle_count(Topology::LineList, 5), 4);
        assert_eq!(triangle_count(Topology::LineStrip, 4), 6);
        assert_eq!(triangle_count(Topology::LineLoop, 4), 8);
        assert_eq!(triangle_count(Topology::LineLoop, 1), 0);
        assert_eq!(segment(Topology::LineLoop, 3, 4), [3, 0]);
        assert_eq!(segment(Topology::LineStrip, 2, 4), [2, 3]);
        assert_eq!(segment(Topology::LineList, 1, 4), [2, 3]);
    }
}
