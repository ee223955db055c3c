//! Procedural meshes: position and normal per vertex, u32 indices, counter-clockwise front
//! faces (right-handed, y up).

use glam::Vec3;

/// A vertex with a position and a normal, as the built-in shaders read it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// Triangles as vertices and indices.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    fn push(&mut self, position: Vec3, normal: Vec3) -> u32 {
        self.vertices.push(Vertex { position: position.to_array(), normal: normal.to_array() });
        (self.vertices.len() - 1) as u32
    }

    pub fn triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// A UV sphere of radius 1 with `rings` bands and `segments` slices.
    pub fn sphere(rings: u32, segments: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for r in 0..=rings {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let phi = std::f32::consts::TAU * s as f32 / segments as f32;
                let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
                mesh.push(n, n);
            }
        }
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let (a, b) = (r * row + s, (r + 1) * row + s);
                mesh.indices.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        mesh
    }

    /// A cube from −1 to 1 with flat faces.
    pub fn cube() -> Mesh {
        let mut mesh = Mesh::default();
        let axes = [Vec3::X, Vec3::Y, Vec3::Z];
        for (i, axis) in axes.iter().enumerate() {
            for sign in [1.0f32, -1.0] {
                let n = *axis * sign;
                let u = axes[(i + 1) % 3];
                let v = n.cross(u);
                let base = mesh.vertices.len() as u32;
                for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    mesh.push(n + u * du + v * dv, n);
                }
                mesh.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
            }
        }
        mesh
    }

    /// A torus around the y axis: ring radius `major`, tube radius `minor`.
    pub fn torus(major: f32, minor: f32, rings: u32, segments: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for r in 0..=rings {
            let a = std::f32::consts::TAU * r as f32 / rings as f32;
            let centre = Vec3::new(a.cos(), 0.0, -a.sin()) * major;
            for s in 0..=segments {
                let b = std::f32::consts::TAU * s as f32 / segments as f32;
                let n = Vec3::new(a.cos() * b.cos(), b.sin(), -a.sin() * b.cos());
                mesh.push(centre + n * minor, n);
            }
        }
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let (a, b) = (r * row + s, (r + 1) * row + s);
                mesh.indices.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        mesh
    }

    /// A square in the xz plane from −1 to 1, facing +y, cut into `cells × cells` quads.
    pub fn plane(cells: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for z in 0..=cells {
            for x in 0..=cells {
                let p = Vec3::new(-1.0 + 2.0 * x as f32 / cells as f32, 0.0, -1.0 + 2.0 * z as f32 / cells as f32);
                mesh.push(p, Vec3::Y);
            }
        }
        let row = cells + 1;
        for z in 0..cells {
            for x in 0..cells {
                let (a, b) = (z * row + x, (z + 1) * row + x);
                mesh.indices.extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle faces the way its normals point (counter-clockwise seen from outside).
    fn assert_outward(mesh: &Mesh) {
        for t in mesh.indices.as_chunks::<3>().0 {
            let p = t.map(|i| Vec3::from(mesh.vertices[i as usize].position));
            let n: Vec3 = t.iter().map(|&i| Vec3::from(mesh.vertices[i as usize].normal)).sum();
            let face = (p[1] - p[0]).cross(p[2] - p[0]);
            if face.length() > 1e-6 {
                assert!(face.dot(n) > 0.0, "triangle {t:?} faces inwards");
            }
        }
    }

    #[test]
    fn meshes_face_outwards() {
        assert_outward(&Mesh::sphere(8, 16));
        assert_outward(&Mesh::cube());
        assert_outward(&Mesh::torus(1.0, 0.3, 16, 8));
        assert_outward(&Mesh::plane(4));
    }
}
