//! Small generic 3-vector and 3×3-matrix helpers over [`Real`].

use crate::scalar::Real;

pub type Vec3<T> = [T; 3];
pub type Mat3<T> = [[T; 3]; 3];

pub fn dot<T: Real>(u: &Vec3<T>, v: &Vec3<T>) -> T {
    u[0].clone() * &v[0] + u[1].clone() * &v[1] + u[2].clone() * &v[2]
}

pub fn cross<T: Real>(u: &Vec3<T>, v: &Vec3<T>) -> Vec3<T> {
    [
        u[1].clone() * &v[2] - u[2].clone() * &v[1],
        u[2].clone() * &v[0] - u[0].clone() * &v[2],
        u[0].clone() * &v[1] - u[1].clone() * &v[0],
    ]
}

pub fn norm<T: Real>(u: &Vec3<T>) -> T {
    dot(u, u).sqrt()
}

pub fn scale<T: Real>(c: &T, u: &Vec3<T>) -> Vec3<T> {
    std::array::from_fn(|i| c.clone() * &u[i])
}

pub fn sub<T: Real>(u: &Vec3<T>, v: &Vec3<T>) -> Vec3<T> {
    std::array::from_fn(|i| u[i].clone() - &v[i])
}

pub fn add<T: Real>(u: &Vec3<T>, v: &Vec3<T>) -> Vec3<T> {
    std::array::from_fn(|i| u[i].clone() + &v[i])
}

/// M v.
pub fn mat_vec<T: Real>(m: &Mat3<T>, v: &Vec3<T>) -> Vec3<T> {
    std::array::from_fn(|i| dot(&m[i], v))
}

/// Mᵀ v.
pub fn mat_t_vec<T: Real>(m: &Mat3<T>, v: &Vec3<T>) -> Vec3<T> {
    std::array::from_fn(|i| {
        m[0][i].clone() * &v[0] + m[1][i].clone() * &v[1] + m[2][i].clone() * &v[2]
    })
}

/// A Bᵀ.
pub fn mul_bt<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    std::array::from_fn(|i| std::array::from_fn(|j| dot(&a[i], &b[j])))
}

/// A B.
pub fn mul<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> Mat3<T> {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            a[i][0].clone() * &b[0][j] + a[i][1].clone() * &b[1][j] + a[i][2].clone() * &b[2][j]
        })
    })
}

pub fn transpose<T: Real>(m: &Mat3<T>) -> Mat3<T> {
    std::array::from_fn(|i| std::array::from_fn(|j| m[j][i].clone()))
}

pub fn det<T: Real>(m: &Mat3<T>) -> T {
    dot(&m[0], &cross(&m[1], &m[2]))
}

/// Rotation angle of an orthogonal matrix R, robust near 0 and π:
/// θ = atan2(|vee(R − Rᵀ)|/2·2, tr R − 1)… computed as atan2(|axis·sinθ|, cosθ).
pub fn rotation_angle<T: Real>(r: &Mat3<T>) -> T {
    let two = r[0][0].lit(2.0);
    let s = [
        r[2][1].clone() - &r[1][2],
        r[0][2].clone() - &r[2][0],
        r[1][0].clone() - &r[0][1],
    ];
    let sin = norm(&s) / &two;
    let cos = (r[0][0].clone() + &r[1][1] + &r[2][2] - r[0][0].lit(1.0)) / &two;
    sin.atan2(&cos)
}
