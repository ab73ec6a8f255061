//! The arctangent of a rotation angle that is not small (tan θ ≥ 2⁻¹⁴: the orientation error of
//! a sample whose error has saturated) in double-double, without the general atan2 (an f64
//! atan2, a square root, three divisions and a double-double sine and cosine): by a table of
//! atan(k/256) and a short series. With a ≤ b the smaller and the larger of sin θ and |cos θ|
//! and c = k/256 the table point nearest z = a/b,
//!   atan z = atan c + atan u,   u = (z − c)/(1 + zc) = (a − cb)/(b + ca),   |u| ≤ 2⁻⁹,
//! atan u = u − u³/3 + u⁵/5 in double-double and u⁷/7 … u¹³/13 (below 2⁻⁵⁴ u) in f64 (the next
//! term is below 2⁻¹²⁶ u); then θ = π/2 − atan z when sin θ > |cos θ| and π − θ when cos θ < 0.
//! Error: a few units of 2⁻¹⁰⁶ of θ (the rounding of cb, below 2⁻¹⁰⁵ c, is below 2⁻¹⁰⁴ of
//! θ ≥ c/2; the f64 tail's, below 2⁻⁵¹·u⁷, is below 2⁻¹⁰⁷ of θ).

use rsts_dynamics::scalar::{every_lane, DoubleDouble as Dd, DoubleDoubleLanes};
use rsts_dynamics::Real;

use super::atan_table::ATAN;

/// The table's points are k/STEPS, k = 0…STEPS.
pub(super) const STEPS: u32 = 256;

/// 1/3, 1/5 and π/2 to 106 bits.
pub(super) const THIRD: Dd = Dd {
    hi: 0.3333333333333333,
    lo: 1.850371707708594e-17,
};
pub(super) const FIFTH: Dd = Dd {
    hi: 0.2,
    lo: -1.1102230246251566e-17,
};
pub(super) const HALF_PI: Dd = Dd {
    hi: std::f64::consts::FRAC_PI_2,
    lo: 6.123233995736766e-17,
};

/// atan2(sin, cos) for sin ≥ 0 in each lane (see the module's text), the table's point chosen
/// per lane; the general double-double atan2 for a lane with a zero or non-finite argument.
#[inline(always)]
pub(crate) fn arctangent<const L: usize>(
    sin: DoubleDoubleLanes<L>,
    cos: DoubleDoubleLanes<L>,
) -> DoubleDoubleLanes<L> {
    type Lanes<const L: usize> = DoubleDoubleLanes<L>;
    let across = cos.abs();
    let mut swap = [false; L];
    for i in 0..L {
        swap[i] = sin.hi[i] > across.hi[i];
    }
    let (a, b) = (
        Lanes::select(swap, across, sin),
        Lanes::select(swap, sin, across),
    );
    let (mut valid, mut k, mut c) = ([false; L], [0usize; L], [0.0; L]);
    let mut table = Lanes::default();
    for i in 0..L {
        valid[i] = (b.hi[i] > 0.0) & b.hi[i].is_finite() & (a.hi[i] >= 0.0);
        // The nearest table point (a cast, not a call to the library's `round`; 0 where the
        // lane is not valid).
        let nearest = if valid[i] {
            a.hi[i] / b.hi[i] * f64::from(STEPS) + 0.5
        } else {
            0.0
        };
        k[i] = (nearest as usize).min(STEPS as usize);
        c[i] = k[i] as f64 / f64::from(STEPS);
        (table.hi[i], table.lo[i]) = ATAN[k[i]];
    }
    let u = (a - b.mul_f64(c)) / (b + a.mul_f64(c));
    let w = u.sqr();
    let mut tail = [0.0; L];
    for i in 0..L {
        let (u, w1) = (u.hi[i], w.hi[i]);
        tail[i] =
            u * w1 * w1 * w1 * (-1.0 / 7.0 + w1 * (1.0 / 9.0 - w1 * (1.0 / 11.0 - w1 / 13.0)));
    }
    let series = (u - u * w * (Lanes::splat(THIRD) - w * Lanes::splat(FIFTH))).add_f64(tail);
    let z = table + series;
    let angle = Lanes::select(swap, Lanes::splat(HALF_PI) - z, z);
    let mut behind = [false; L];
    for i in 0..L {
        behind[i] = cos.hi[i] < 0.0;
    }
    let mut angle = Lanes::select(behind, Lanes::splat(Dd::PI) - angle, angle);
    if !every_lane(valid) {
        for i in 0..L {
            if !valid[i] {
                angle.set_lane(i, sin.lane(i).atan2(&cos.lane(i)));
            }
        }
    }
    angle
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rug::Float;

    const MP: u32 = 300;

    /// The table atan(k/256) and 1/3, 1/5, π/2, π are MPFR's at 300 bits rounded to
    /// double-double.
    #[test]
    fn table_and_constants_are_mpfr_s() {
        for (k, &(hi, lo)) in ATAN.iter().enumerate() {
            let z = Float::with_val(MP, k as u32) / STEPS;
            assert_eq!(Dd { hi, lo }, Dd::from_float(&z.atan()), "atan({k}/256)");
        }
        let one = Float::with_val(MP, 1);
        let pi = Float::with_val(MP, rug::float::Constant::Pi);
        for (name, got, want) in [
            ("1/3", THIRD, Float::with_val(MP, &one / 3u32)),
            ("1/5", FIFTH, Float::with_val(MP, &one / 5u32)),
            ("π/2", HALF_PI, Float::with_val(MP, &pi / 2u32)),
            ("π", Dd::PI, pi.clone()),
        ] {
            assert_eq!(got, Dd::from_float(&want), "{name}");
        }
    }

    /// atan2(sin, cos) by the table and the series is MPFR's at 300 bits within 2⁻¹⁰⁰ of the
    /// angle, on 30 000 random angles from 2⁻¹⁴ to π (a third of them log-spread below 3) with
    /// radii from 1e-3 to 1e3 and low parts, and at the ends of the table's steps. Dropping
    /// u⁵/5 from the double-double part, or the f64 tail, breaks it.
    #[test]
    fn large_angles_are_mpfr_s_to_the_double_double_bound() {
        let mut rng = ChaCha8Rng::seed_from_u64(3030);
        let mut worst = 0.0f64;
        let low = |rng: &mut ChaCha8Rng, x: f64| {
            Dd::from_f64_exact(x).add_f64(x * 1e-17 * rng.gen_range(-0.5..0.5))
        };
        for n in 0..30_000 {
            let theta = match n % 3 {
                0 => 10f64.powf(rng.gen_range(-4.2..0.47)),
                1 => rng.gen_range(6.2e-5..std::f64::consts::PI),
                // Half-way between two points of the table (|u| largest), either octant.
                _ => {
                    let k = rng.gen_range(0..256) as f64 + 0.5;
                    let z = (k / 256.0).atan();
                    [z, std::f64::consts::FRAC_PI_2 - z, std::f64::consts::PI - z][n % 9 / 3]
                }
            };
            let r = 10f64.powf(rng.gen_range(-3.0..3.0));
            let (sin, cos) = (
                low(&mut rng, r * theta.sin()),
                low(&mut rng, r * theta.cos()),
            );
            let got = arctangent::<1>(sin.into(), cos.into()).lane(0).to_float(MP);
            let want = sin.to_float(MP).atan2(&cos.to_float(MP));
            let error = ((got - &want) / &want).abs().to_f64();
            worst = worst.max(error);
            assert!(
                error <= 2f64.powi(-100),
                "sample {n}: θ = {theta}, error {error:e}"
            );
        }
        eprintln!("worst relative error {worst:e}");
        assert!(
            worst > 2f64.powi(-112),
            "no rounding at all: the test does not measure"
        );
    }
}
