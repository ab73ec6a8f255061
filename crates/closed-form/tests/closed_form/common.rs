//! Shared helpers of the closed-form tests: representative points and the checks of a closed-form
//! state against the equations of motion, the constraints and the integrals.

#![allow(dead_code)]

use rsts_closed_form::{ExplicitMotion, ExplicitState, TorusChoice};
use rsts_dynamics::dual::Dual;
use rsts_dynamics::integrals::integrals;
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::vec3::{cross, det, mat_t_vec, mat_vec, mul, mul_bt, Mat3, Vec3};
use rsts_dynamics::{Fields, Real, State, VectorField};
use rug::Float;

/// One point (m, h) per camera for a = 1, b = 1/2 (the camera of each is asserted in the tests).
pub const CAMERA_POINTS: [(&str, f64, f64); 9] = {
    let p = rsts_closed_form::EXAMPLE_POINTS_A1_B05;
    let mut out = [("", 0.0, 0.0); 9];
    let mut k = 0;
    while k < 9 {
        out[k] = (LABELS[k], p[k].1, p[k].2);
        k += 1;
    }
    out
};
const LABELS: [&str; 9] = ["I+", "I-", "II+", "II-", "III", "IV+", "IV-", "V", "VI"];

pub fn mp(x: f64, bits: u32) -> Float {
    Float::with_val(bits, x)
}

/// Parse a decimal exactly at `bits` (so "0.3" is 3/10, not the f64 nearest to it).
pub fn dec(s: &str, bits: u32) -> Float {
    <Float as Real>::parse(s, bits).unwrap()
}

pub fn motion_mp(
    a: &str,
    b: &str,
    m: &str,
    h: &str,
    digits: u32,
    choice: TorusChoice,
) -> ExplicitMotion<Float> {
    let bits = bits_for_digits(digits);
    ExplicitMotion::new(
        dec(a, bits),
        dec(b, bits),
        dec(m, bits),
        dec(h, bits),
        choice,
    )
    .unwrap()
}

pub fn phase_vec<T: Real>(s: &ExplicitState<T>) -> [T; 9] {
    let v = [&s.omega, &s.alpha, &s.beta];
    std::array::from_fn(|k| v[k / 3][k % 3].clone())
}

fn max_abs<T: Real>(it: impl IntoIterator<Item = T>) -> f64 {
    it.into_iter().map(|x| x.abs().to_f64()).fold(0.0, f64::max)
}

fn mat_err<T: Real>(a: &Mat3<T>, b: &Mat3<T>) -> f64 {
    max_abs((0..9).map(|k| a[k / 3][k % 3].clone() - &b[k / 3][k % 3]))
}

fn vec_err<T: Real>(a: &Vec3<T>, b: &Vec3<T>) -> f64 {
    max_abs((0..3).map(|k| a[k].clone() - &b[k]))
}

/// The vee map so(3) → R³: v(A) = (A₃₂, A₁₃, A₂₁) (seed sec. 2, aᵢⱼ = −εᵢⱼₖ aₖ).
fn vee<T: Real>(m: &Mat3<T>) -> Vec3<T> {
    [m[2][1].clone(), m[0][2].clone(), m[1][0].clone()]
}

/// All residuals of a closed-form state at time t: name → max abs error.
pub fn residuals(motion: &ExplicitMotion<Float>, t: f64) -> Vec<(&'static str, f64)> {
    let bits = motion.constants.a.prec();
    let sd = motion.at_with_derivative(&mp(t, bits));
    let re = |v: &Vec3<Dual<Float>>| -> Vec3<Float> { std::array::from_fn(|i| v[i].re.clone()) };
    let re_m = |m: &Mat3<Dual<Float>>| -> Mat3<Float> { std::array::from_fn(|i| re(&m[i])) };
    let eps_m = |m: &Mat3<Dual<Float>>| -> Mat3<Float> {
        std::array::from_fn(|i| std::array::from_fn(|j| m[i][j].eps.clone()))
    };
    let c = &motion.constants;
    let fields = Fields {
        a: c.a.clone(),
        b: c.b.clone(),
    };
    let x: [Float; 9] = std::array::from_fn(|k| phase_vec(&sd)[k].re.clone());
    let dx: [Float; 9] = std::array::from_fn(|k| phase_vec(&sd)[k].eps.clone());
    let fx = VectorField::new(&fields).eval(&x);
    let state = State::from_slice(&x);
    let ints = integrals(&fields, &state);
    let r4 = c.r2.clone() * &c.r2;
    let one = mp(1.0, bits);
    let (alpha, beta, omega) = (re(&sd.alpha), re(&sd.beta), re(&sd.omega));
    let q = re_m(&[sd.alpha.clone(), sd.beta.clone(), sd.gamma.clone()]);
    let qp = re_m(&sd.q_prime);
    let qs = re_m(&sd.q_second);
    let ident: Mat3<Float> =
        std::array::from_fn(|i| std::array::from_fn(|j| mp(if i == j { 1.0 } else { 0.0 }, bits)));
    let omega_second: Vec3<Float> =
        std::array::from_fn(|i| sd.omega_second_1[i].re.clone() + &sd.omega_second_2[i].re);
    let decomposition: Vec3<Float> = {
        let t = mat_t_vec(&qp, &omega_second);
        std::array::from_fn(|i| sd.omega_prime[i].re.clone() + &t[i])
    };
    // ω′ = v(Q′ᵀ dQ′/dt) and ω″ = v(Q″ᵀ dQ″/dt), the definitions of sec. 2.
    let tr = |m: &Mat3<Float>| -> Mat3<Float> {
        std::array::from_fn(|i| std::array::from_fn(|j| m[j][i].clone()))
    };
    let omega_prime_def = vee(&mul(&tr(&qp), &eps_m(&sd.q_prime)));
    let omega_second_def = vee(&mul(&tr(&qs), &eps_m(&sd.q_second)));
    vec![
        (
            "euler-poisson",
            max_abs((0..9).map(|k| dx[k].clone() - &fx[k])),
        ),
        ("constraints", max_abs(state.constraint_residuals())),
        (
            "gamma (2.5) = alpha x beta",
            vec_err(&re(&sd.gamma), &cross(&alpha, &beta)),
        ),
        (
            "Omega (3.1) = Q omega",
            vec_err(&re(&sd.omega_fixed), &mat_vec(&q, &omega)),
        ),
        ("Q orthogonal", mat_err(&mul_bt(&q, &q), &ident)),
        ("det Q = 1", (det(&q) - &one).abs().to_f64()),
        ("H = h", (ints.h - &c.h).abs().to_f64()),
        (
            "K = r^4 m^2",
            (ints.k - r4.clone() * &c.m * &c.m).abs().to_f64(),
        ),
        (
            "G = (p^2 h + r^4 m)/2",
            (ints.g - (c.p2.clone() * &c.h + r4 * &c.m) / mp(2.0, bits))
                .abs()
                .to_f64(),
        ),
        ("Q = Q''Q'", mat_err(&q, &mul(&qs, &qp))),
        ("Q' orthogonal", mat_err(&mul_bt(&qp, &qp), &ident)),
        (
            "omega = omega' + Q'^T omega''",
            vec_err(&omega, &decomposition),
        ),
        (
            "omega' (2.6) = v(Q'^T dQ'/dt)",
            vec_err(&re(&sd.omega_prime), &omega_prime_def),
        ),
        (
            "omega'' (2.8) = v(Q''^T dQ''/dt)",
            vec_err(&omega_second, &omega_second_def),
        ),
    ]
}

/// Assert every residual is below `tol` (scaled by the size of the motion).
pub fn assert_all_below(motion: &ExplicitMotion<Float>, t: f64, tol: f64, what: &str) {
    let c = &motion.constants;
    let scale =
        1.0 + c.h.to_f64().abs() + c.m.to_f64().abs() * c.p2.to_f64() + c.a.to_f64() * c.a.to_f64();
    for (name, err) in residuals(motion, t) {
        assert!(
            err <= tol * scale * scale,
            "{what}, t = {t}: {name} off by {err:e} (tolerance {tol:e})"
        );
    }
}

/// Convert a high-precision state to f64 for comparisons.
pub fn to_f64_state(s: &ExplicitState<Float>) -> [f64; 9] {
    phase_vec(s).map(|x| x.to_f64())
}
