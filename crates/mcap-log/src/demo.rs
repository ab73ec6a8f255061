//! A closed-form synthetic motion (regular precession) for tests, examples and smoke
//! runs of the logging pipeline. Not the Kowalevski top: just a motion whose Q, ω and Ω
//! are known exactly and whose hodographs are circles.
//!
//! Attitude (body → world): Q(t) = R_z(ν t) R_x(θ) R_z(s t). Then
//! Ω = (s sin θ sin νt, −s sin θ cos νt, ν + s cos θ) and
//! ω = Qᵀ Ω = (ν sin θ sin st, ν sin θ cos st, ν cos θ + s).

use crate::writer::{BodyState, ErrorSample, Metadata, Sample};

/// Regular precession with precession rate `nu`, nutation angle `theta`, spin rate `spin`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Precession {
    pub nu: f64,
    pub theta: f64,
    pub spin: f64,
}

fn rz(a: f64) -> [[f64; 3]; 3] {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

fn rx(a: f64) -> [[f64; 3]; 3] {
    let (s, c) = a.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

/// Matrix product.
pub fn matmul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

/// Matrix-vector product.
pub fn matvec(a: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2])
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

impl Precession {
    /// A default, visibly non-degenerate precession.
    pub const EXAMPLE: Precession = Precession {
        nu: 0.7,
        theta: 0.6,
        spin: 2.3,
    };

    /// The body state at time `t`, integrals h = |ω|²/2, k = |Ω|², g = Ω_z (all constant).
    pub fn state(&self, t: f64) -> BodyState {
        let q = matmul(
            &matmul(&rz(self.nu * t), &rx(self.theta)),
            &rz(self.spin * t),
        );
        let (st, ct) = self.theta.sin_cos();
        let (sn, cn) = (self.nu * t).sin_cos();
        let (ss, cs) = (self.spin * t).sin_cos();
        let omega_fixed = [
            self.spin * st * sn,
            -self.spin * st * cn,
            self.nu + self.spin * ct,
        ];
        let omega = [
            self.nu * st * ss,
            self.nu * st * cs,
            self.nu * ct + self.spin,
        ];
        BodyState {
            q,
            omega,
            omega_fixed,
            h: 0.5 * norm(omega).powi(2),
            k: norm(omega_fixed).powi(2),
            g: omega_fixed[2],
        }
    }
}

/// Errors of `integrated` against `exact`, computed the simple way (for demos and tests).
pub fn errors(exact: &BodyState, integrated: &BodyState, initial: &BodyState) -> ErrorSample {
    let mut dq = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            dq += (exact.q[i][j] - integrated.q[i][j]).powi(2);
        }
    }
    let dw = norm([0, 1, 2].map(|i| exact.omega[i] - integrated.omega[i]));
    // Orthonormality defect of Q.
    let mut c = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let d: f64 = (0..3)
                .map(|k| integrated.q[i][k] * integrated.q[j][k])
                .sum();
            c += (d - if i == j { 1.0 } else { 0.0 }).powi(2);
        }
    }
    let qw = matvec(&integrated.q, integrated.omega);
    ErrorSample {
        state_error: (dq + dw * dw).sqrt(),
        orientation_error: dq.sqrt(),
        drift_h: integrated.h - initial.h,
        drift_k: integrated.k - initial.k,
        drift_g: integrated.g - initial.g,
        constraint_drift: c.sqrt(),
        off_n: norm([0, 1, 2].map(|i| qw[i] - integrated.omega_fixed[i])),
        distance_from_n: None,
        x_phi: None,
        along_n: None,
        phase_error_psi1: None,
        phase_error_psi2: None,
    }
}

/// Sample `i` of `n` over `[0, t_end]`: the exact precession and a slightly faster one
/// (ν(1 + eps)) standing in for an integrated motion, with their errors.
pub fn sample(exact: &Precession, eps: f64, t_end: f64, i: usize, n: usize) -> Sample {
    let t = if n > 1 {
        t_end * i as f64 / (n - 1) as f64
    } else {
        0.0
    };
    let integrated = Precession {
        nu: exact.nu * (1.0 + eps),
        ..*exact
    };
    let e = exact.state(t);
    let g = integrated.state(t);
    Sample {
        t,
        exact: Some(e),
        integrated: Some(g),
        errors: Some(errors(&e, &g, &exact.state(0.0))),
    }
}

/// Metadata describing a demo run.
pub fn metadata(p: &Precession, t_end: f64, samples: usize) -> Metadata {
    Metadata {
        software_version: format!("rsts-mcap {}", env!("CARGO_PKG_VERSION")),
        case: serde_json::json!({
            "kind": "demo regular precession",
            "nu": p.nu, "theta": p.theta, "spin": p.spin,
            "t_end": t_end, "samples": samples
        }),
        integrator: serde_json::json!({"method": "closed-form (demo)", "rtol": 0.0, "atol": 0.0, "digits": 17}),
    }
}
