//! ASCII PLY meshes (vertices with normals and the (ψ₁, ψ₂) of each vertex, triangle faces),
//! readable by MeshLab, Blender and ParaView.

use std::fmt::Write as _;

use crate::mesh::vertex_normals;

/// The PLY text of a mesh. `angles` (one (ψ₁, ψ₂) per vertex) are written as extra properties
/// `psi1`, `psi2` when given.
pub fn ply_text(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    angles: Option<&[[f64; 2]]>,
    comment: &str,
) -> String {
    let normals = vertex_normals(vertices, triangles);
    let mut s = String::with_capacity(vertices.len() * 80 + triangles.len() * 24 + 400);
    s.push_str("ply\nformat ascii 1.0\n");
    for line in comment.lines() {
        let _ = writeln!(s, "comment {line}");
    }
    let _ = writeln!(s, "element vertex {}", vertices.len());
    s.push_str("property double x\nproperty double y\nproperty double z\n");
    s.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    let with_angles = angles.is_some_and(|a| a.len() == vertices.len());
    if with_angles {
        s.push_str("property double psi1\nproperty double psi2\n");
    }
    let _ = writeln!(s, "element face {}", triangles.len());
    s.push_str("property list uchar uint vertex_indices\nend_header\n");
    for (i, (p, n)) in vertices.iter().zip(&normals).enumerate() {
        let _ = write!(
            s,
            "{:e} {:e} {:e} {:.6} {:.6} {:.6}",
            p[0], p[1], p[2], n[0], n[1], n[2]
        );
        if let (true, Some(a)) = (with_angles, angles) {
            let _ = write!(s, " {:e} {:e}", a[i][0], a[i][1]);
        }
        s.push('\n');
    }
    for t in triangles {
        let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
    }
    s
}

/// Vertices and triangles of a mesh.
pub type MeshData = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// Parse the vertices and faces back from [`ply_text`] output (x, y, z and the triangle
/// indices; other properties ignored). For tests and tools; `None` on anything malformed.
pub fn parse_ply(text: &str) -> Option<MeshData> {
    let mut lines = text.lines();
    if lines.next()? != "ply" {
        return None;
    }
    let (mut nv, mut nf) = (None, None);
    for line in lines.by_ref() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["element", "vertex", n] => nv = n.parse::<usize>().ok(),
            ["element", "face", n] => nf = n.parse::<usize>().ok(),
            ["end_header"] => break,
            _ => {}
        }
    }
    let (nv, nf) = (nv?, nf?);
    let mut v = Vec::with_capacity(nv);
    for _ in 0..nv {
        let nums: Vec<f64> = lines
            .next()?
            .split_whitespace()
            .map(|x| x.parse().ok())
            .collect::<Option<_>>()?;
        v.push([*nums.first()?, *nums.get(1)?, *nums.get(2)?]);
    }
    let mut f = Vec::with_capacity(nf);
    for _ in 0..nf {
        let nums: Vec<u32> = lines
            .next()?
            .split_whitespace()
            .map(|x| x.parse().ok())
            .collect::<Option<_>>()?;
        if nums.len() != 4 || nums[0] != 3 || nums[1..].iter().any(|&i| i as usize >= nv) {
            return None;
        }
        f.push([nums[1], nums[2], nums[3]]);
    }
    Some((v, f))
}
