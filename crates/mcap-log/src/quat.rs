//! Attitude quaternion from the orientation matrix Q.
//!
//! Convention: the rows of Q are the fixed axes α, β, γ written in the body frame,
//! n_i = Q_ik e_k. Hence the body axis e_k has the world components Q_ik (column k of Q)
//! and a body vector with components ω has the world components Ω = Q ω. The rotation of
//! the Foxglove transform world (parent) → body (child) maps child coordinates to parent
//! coordinates, so it is Q itself: rotating the unit vector e_k by the quaternion gives
//! column k of Q.

use serde::{Deserialize, Serialize};

/// A quaternion `w + x i + y j + z k` (Foxglove's field order and names).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

impl Quaternion {
    /// The identity rotation.
    pub const IDENTITY: Quaternion = Quaternion {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };

    /// Unit quaternion of the rotation matrix `r` (Shepperd's method: the largest of
    /// w², x², y², z² is computed from the trace/diagonal, so no catastrophic
    /// cancellation near 180° rotations). The result is normalised and has `w >= 0`.
    /// `r` should be close to a rotation; a slightly non-orthogonal `r` (integrator drift)
    /// gives the quaternion of a nearby rotation. Non-finite input gives a non-finite result.
    pub fn from_rotation_matrix(r: &[[f64; 3]; 3]) -> Quaternion {
        let (m00, m11, m22) = (r[0][0], r[1][1], r[2][2]);
        let tr = m00 + m11 + m22;
        let q = if tr >= m00 && tr >= m11 && tr >= m22 {
            let s = 2.0 * (1.0 + tr).max(0.0).sqrt(); // s = 4w
            Quaternion {
                w: 0.25 * s,
                x: (r[2][1] - r[1][2]) / s,
                y: (r[0][2] - r[2][0]) / s,
                z: (r[1][0] - r[0][1]) / s,
            }
        } else if m00 >= m11 && m00 >= m22 {
            let s = 2.0 * (1.0 + m00 - m11 - m22).max(0.0).sqrt(); // s = 4x
            Quaternion {
                w: (r[2][1] - r[1][2]) / s,
                x: 0.25 * s,
                y: (r[0][1] + r[1][0]) / s,
                z: (r[0][2] + r[2][0]) / s,
            }
        } else if m11 >= m22 {
            let s = 2.0 * (1.0 + m11 - m00 - m22).max(0.0).sqrt(); // s = 4y
            Quaternion {
                w: (r[0][2] - r[2][0]) / s,
                x: (r[0][1] + r[1][0]) / s,
                y: 0.25 * s,
                z: (r[1][2] + r[2][1]) / s,
            }
        } else {
            let s = 2.0 * (1.0 + m22 - m00 - m11).max(0.0).sqrt(); // s = 4z
            Quaternion {
                w: (r[1][0] - r[0][1]) / s,
                x: (r[0][2] + r[2][0]) / s,
                y: (r[1][2] + r[2][1]) / s,
                z: 0.25 * s,
            }
        };
        let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
        let n = (q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z).sqrt() * sign;
        Quaternion {
            x: q.x / n,
            y: q.y / n,
            z: q.z / n,
            w: q.w / n,
        }
    }

    /// Attitude quaternion of the body: the rotation taking body components to world
    /// components, i.e. of the matrix Q itself (see the module docs).
    pub fn from_orientation(q: &[[f64; 3]; 3]) -> Quaternion {
        Self::from_rotation_matrix(q)
    }

    /// Rotates `v` by this (unit) quaternion: q v q*.
    pub fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let u = [self.x, self.y, self.z];
        let w = self.w;
        // v' = v + 2 w (u × v) + 2 u × (u × v)
        let c1 = cross(u, v);
        let c2 = cross(u, c1);
        [
            v[0] + 2.0 * (w * c1[0] + c2[0]),
            v[1] + 2.0 * (w * c1[1] + c2[1]),
            v[2] + 2.0 * (w * c1[2] + c2[2]),
        ]
    }

    /// The rotation matrix of this (unit) quaternion.
    pub fn to_rotation_matrix(&self) -> [[f64; 3]; 3] {
        let c0 = self.rotate([1.0, 0.0, 0.0]);
        let c1 = self.rotate([0.0, 1.0, 0.0]);
        let c2 = self.rotate([0.0, 0.0, 1.0]);
        [
            [c0[0], c1[0], c2[0]],
            [c0[1], c1[1], c2[1]],
            [c0[2], c1[2], c2[2]],
        ]
    }

    /// The shortest rotation taking the +x axis onto the direction of `d`
    /// (identity for a zero or non-finite `d`). Used to orient Foxglove arrows.
    pub fn x_axis_to(d: [f64; 3]) -> Quaternion {
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(n.is_finite() && n > 0.0) {
            return Quaternion::IDENTITY;
        }
        let d = [d[0] / n, d[1] / n, d[2] / n];
        let w = 1.0 + d[0];
        if w < 1e-12 {
            // d ≈ -x: half turn about z.
            return Quaternion {
                x: 0.0,
                y: 0.0,
                z: 1.0,
                w: 0.0,
            };
        }
        // q ∝ (1 + x·d, x × d) with x × d = (0, -d_z, d_y).
        let q = [w, 0.0, -d[2], d[1]];
        let m = (q[0] * q[0] + q[2] * q[2] + q[3] * q[3]).sqrt();
        Quaternion {
            w: q[0] / m,
            x: 0.0,
            y: q[2] / m,
            z: q[3] / m,
        }
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    fn rot(axis: [f64; 3], angle: f64) -> [[f64; 3]; 3] {
        // Rodrigues.
        let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        let (x, y, z) = (axis[0] / n, axis[1] / n, axis[2] / n);
        let (s, c) = angle.sin_cos();
        let t = 1.0 - c;
        [
            [c + x * x * t, x * y * t - z * s, x * z * t + y * s],
            [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
            [z * x * t - y * s, z * y * t + x * s, c + z * z * t],
        ]
    }

    fn assert_mat_close(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3], tol: f64) {
        for i in 0..3 {
            for j in 0..3 {
                assert!((a[i][j] - b[i][j]).abs() < tol, "{a:?} vs {b:?}");
            }
        }
    }

    #[test]
    fn roundtrip_over_many_rotations_including_half_turns() {
        let axes = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 2.0, -3.0],
            [-0.3, 0.1, 0.9],
            [1.0, 1.0, 1.0],
        ];
        for axis in axes {
            for k in 0..=64 {
                // Angles from -π to π, hitting ±π (half turns, trace = -1) exactly.
                let angle = -std::f64::consts::PI + k as f64 * std::f64::consts::PI / 32.0;
                let r = rot(axis, angle);
                let q = Quaternion::from_rotation_matrix(&r);
                let norm = (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w).sqrt();
                assert!((norm - 1.0).abs() < 1e-14);
                assert!(q.w >= 0.0);
                assert_mat_close(&q.to_rotation_matrix(), &r, 1e-14);
            }
        }
    }

    #[test]
    fn direction_world_to_body_is_q() {
        // Q with rows = fixed axes in body components. Take the body rotated by 90° about the
        // fixed z axis: body e_1 points along world y. Then world y (β) has body components
        // (1,0,0) and world x (α) has body components (0,-1,0).
        let q = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        let quat = Quaternion::from_orientation(&q);
        let e1_world = quat.rotate([1.0, 0.0, 0.0]);
        // e_1 in world components = column 0 of Q = (0, 1, 0): world y.
        assert!((e1_world[0]).abs() < 1e-15);
        assert!((e1_world[1] - 1.0).abs() < 1e-15);
        assert!((e1_world[2]).abs() < 1e-15);
        for k in 0..3 {
            let mut e = [0.0; 3];
            e[k] = 1.0;
            let v = quat.rotate(e);
            for i in 0..3 {
                assert!((v[i] - q[i][k]).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn arrow_orientation_maps_x_to_direction() {
        for d in [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.3, -0.4, 1.2],
            [-1.0, 1e-9, 0.0],
        ] {
            let q = Quaternion::x_axis_to(d);
            let v = q.rotate([1.0, 0.0, 0.0]);
            let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            for i in 0..3 {
                assert!((v[i] - d[i] / n).abs() < 1e-8, "{d:?} -> {v:?}");
            }
        }
        assert_eq!(Quaternion::x_axis_to([0.0; 3]), Quaternion::IDENTITY);
        assert_eq!(Quaternion::x_axis_to([f64::NAN; 3]), Quaternion::IDENTITY);
    }
}
