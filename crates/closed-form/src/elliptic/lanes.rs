//! Bulirsch's recursion to the ratio sn : cn for four samples at once ([`DoubleDouble4`]):
//! [`EllipticModulus::sn_cn_ratio_pair`] lane by lane, the same operations in the same order,
//! the rescaling and the final scaling by a power of 2 decided per lane (by the scalar code
//! itself where a lane needs one).

use rsts_dynamics::scalar::{every_lane, DoubleDouble, DoubleDouble4, LANES};
use rsts_dynamics::Real;

use super::{rescale, EllipticModulus, Recursion};

/// One recursion of four samples (see [`Recursion`]).
struct Recursion4 {
    p: DoubleDouble4,
    q: DoubleDouble4,
    dn: Option<(DoubleDouble4, DoubleDouble4)>,
}

impl EllipticModulus<DoubleDouble> {
    /// [`Self::sn_cn_ratio_pair`] of four samples from (sin, cos) of a_N·u of each variable,
    /// for lanes where neither sin is below 1e-30 (the caller takes the others alone: they go
    /// to the Landen branch).
    #[inline(always)]
    pub fn sn_cn_ratio_pair4(
        first: &Self,
        (s1, c1): (DoubleDouble4, DoubleDouble4),
        second: &Self,
        (s2, c2): (DoubleDouble4, DoubleDouble4),
    ) -> (
        (DoubleDouble4, DoubleDouble4),
        (DoubleDouble4, DoubleDouble4),
    ) {
        let (n1, n2) = (first.a.len() - 1, second.a.len() - 1);
        let mut x = Recursion4 {
            p: c1 * DoubleDouble4::splat(first.a[n1]),
            q: s1,
            dn: None,
        };
        let mut y = Recursion4 {
            p: c2 * DoubleDouble4::splat(second.a[n2]),
            q: s2,
            dn: None,
        };
        for j in 0..n1.max(n2) {
            if j < n1 {
                first.level4(&mut x, n1 - j);
            }
            if j < n2 {
                second.level4(&mut y, n2 - j);
            }
        }
        (x.ratio(), y.ratio())
    }

    /// Level i of the recursion without the last dn ([`Self::level`] with `want_dn` false).
    #[inline(always)]
    fn level4(&self, x: &mut Recursion4, i: usize) {
        let (p2, q2) = (x.p.sqr(), x.q.sqr());
        if let Some((r, s)) = x.dn.take() {
            x.p *= r;
            x.q *= s;
        }
        if i == 1 {
            return;
        }
        let r = (q2 * DoubleDouble4::splat(self.beta[i - 1])).add_no_cancel(p2);
        let s = (q2 * DoubleDouble4::splat(self.alpha[i - 1])).add_no_cancel(p2);
        x.dn = Some((r, s));
        rescale4(&mut x.p, &mut x.q);
    }
}

impl Recursion4 {
    /// [`Recursion::ratio`] of each lane: (q, p) times 2^(1023 − e), e the biased exponent of
    /// the larger, in the four lanes at once when all are normal.
    #[inline(always)]
    fn ratio(self) -> (DoubleDouble4, DoubleDouble4) {
        let (p, q) = (self.p, self.q);
        let mut factor = [0.0; LANES];
        let mut normal = true;
        for (i, f) in factor.iter_mut().enumerate() {
            let (pi, qi) = (Real::to_f64(&p.lane(i)), Real::to_f64(&q.lane(i)));
            let e = (pi.abs().max(qi.abs()).to_bits() >> 52) as u32;
            normal &= (1..=2045).contains(&e);
            *f = f64::from_bits(u64::from(2046u32.wrapping_sub(e) & 0x7ff) << 52);
        }
        if normal {
            let f = DoubleDouble4 {
                hi: factor,
                lo: [0.0; LANES],
            };
            return (q * f, p * f);
        }
        let mut out = (DoubleDouble4::default(), DoubleDouble4::default());
        for i in 0..LANES {
            let (qi, pi) = Recursion {
                p: p.lane(i),
                q: q.lane(i),
                dn: None,
            }
            .ratio();
            out.0.set_lane(i, qi);
            out.1.set_lane(i, pi);
        }
        out
    }
}

/// [`rescale`] of each lane: nothing while every lane's larger value lies in [1e-50, 1e50]
/// (the scalar code's common case), else the scalar code lane by lane.
#[inline(always)]
fn rescale4(p: &mut DoubleDouble4, q: &mut DoubleDouble4) {
    let mut calm = [false; LANES];
    for (i, calm) in calm.iter_mut().enumerate() {
        let m = Real::to_f64(&p.lane(i))
            .abs()
            .max(Real::to_f64(&q.lane(i)).abs());
        *calm = (1e-50..=1e50).contains(&m);
    }
    if every_lane(calm) {
        return;
    }
    for i in 0..LANES {
        let (mut pi, mut qi) = (p.lane(i), q.lane(i));
        rescale(&mut pi, &mut qi);
        p.set_lane(i, pi);
        q.set_lane(i, qi);
    }
}
