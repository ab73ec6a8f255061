//! Jacobi elliptic functions sn, cn, dn and the complete integral K for a real modulus, generic
//! over [`Real`], by the arithmetic–geometric mean of (1, k′): Bulirsch's algorithm (R. Bulirsch,
//! Numer. Math. 7 (1965) 78–90; the `sncndn` of Numerical Recipes), which works with k′² directly
//! and builds cn multiplicatively, so it keeps full relative accuracy as k → 1 (near Σ, where the
//! period grows without bound); near the zeros of sn, where Bulirsch's cotangent recursion would
//! overflow, the descending Landen transformation (DLMF 22.20(ii)) is used. The parameter is given
//! as the pair (k², k′²) so that k → 1 and k → 0 are both computed without cancellation.

use rsts_dynamics::Real;

mod lanes;

/// A modulus with its AGM sequence precomputed, ready for many evaluations.
#[derive(Clone, Debug)]
pub struct EllipticModulus<T> {
    /// k².
    pub k2: T,
    /// k′² = 1 − k².
    pub kc2: T,
    /// Complete elliptic integral of the first kind K(k).
    pub big_k: T,
    /// a₀…a_N, b₀…b_N and c₀…c_N of the AGM(1, k′).
    a: Vec<T>,
    b: Vec<T>,
    c: Vec<T>,
    /// α_i = a_{i−1}a_i and β_i = b_{i−1}a_i for i = 1…N (the recursion of [`Self::sn_cn_dn`]
    /// multiplies by them), at index i − 1.
    alpha: Vec<T>,
    beta: Vec<T>,
}

impl<T: Real> EllipticModulus<T> {
    /// Modulus from k² and k′² (must satisfy k² + k′² = 1, 0 ≤ k² < 1).
    pub fn new(k2: T, kc2: T) -> Self {
        let one = k2.one_like();
        let eps = k2.epsilon();
        let mut a = vec![one.clone()];
        let mut bs = vec![kc2.sqrt()];
        let mut c = vec![k2.sqrt()];
        // AGM: a_{n+1} = (a_n + b_n)/2, b_{n+1} = √(a_n b_n), c_{n+1} = (a_n − b_n)/2.
        for _ in 0..64 {
            let an = a.last().unwrap().clone();
            let bn = bs.last().unwrap().clone();
            let cn = c.last().unwrap().clone();
            if cn.abs() <= eps.clone() * &an {
                break;
            }
            a.push((an.clone() + &bn) / an.lit(2.0));
            c.push((an.clone() - &bn) / an.lit(2.0));
            bs.push((an * &bn).sqrt());
        }
        let pi = T::pi(k2.prec());
        let big_k = pi / (a.last().unwrap().clone() * k2.lit(2.0));
        Self {
            k2,
            kc2,
            big_k,
            a,
            b: bs,
            c,
            alpha: Vec::new(),
            beta: Vec::new(),
        }
        .evaluation_levels()
    }

    /// Keep only the AGM levels sn, cn, dn need at this precision: K above comes from the
    /// AGM run until c_N ≤ ε·a_N, but the recursion of [`Self::sn_cn_dn`] is accurate to ε
    /// once c_N ≤ √ε·a_N (a_N then differs from the mean by c_N²/4a_N ≤ ε·a_N/4; the stopping
    /// rule of Numerical Recipes' `sncndn`, "the accuracy is the square of CA"). For a motion
    /// built 64 bits beyond its working precision and rounded, this drops the levels only the
    /// guard bits needed (two of six in f64 at k² ≈ 0.4).
    fn evaluation_levels(mut self) -> Self {
        let root_eps = self.k2.epsilon().sqrt();
        if let Some(n) =
            (0..self.a.len()).find(|&n| self.c[n].abs() <= root_eps.clone() * &self.a[n])
        {
            let keep = n + 1;
            self.a.truncate(keep);
            self.b.truncate(keep);
            self.c.truncate(keep);
        }
        let n = self.a.len();
        self.alpha = (1..n).map(|i| self.a[i - 1].clone() * &self.a[i]).collect();
        self.beta = (1..n).map(|i| self.b[i - 1].clone() * &self.a[i]).collect();
        self
    }

    /// The same modulus in another scalar (each stored number mapped).
    pub fn map<U: Real>(&self, f: &impl Fn(&T) -> U) -> EllipticModulus<U> {
        EllipticModulus {
            k2: f(&self.k2),
            kc2: f(&self.kc2),
            big_k: f(&self.big_k),
            a: self.a.iter().map(f).collect(),
            b: self.b.iter().map(f).collect(),
            c: self.c.iter().map(f).collect(),
            alpha: Vec::new(),
            beta: Vec::new(),
        }
        .evaluation_levels()
    }

    /// (sn u, cn u, dn u).
    #[inline(always)]
    pub fn sn_cn_dn(&self, u: &T) -> (T, T, T) {
        let (sn, cn, dn) = self.evaluate(u, true);
        (sn, cn, dn.unwrap_or_else(|| u.one_like()))
    }

    /// (sn u, cn u): [`Self::sn_cn_dn`] without the last level's dn (one division less), the
    /// same sn and cn bit for bit.
    #[inline(always)]
    pub fn sn_cn(&self, u: &T) -> (T, T) {
        let (sn, cn, _) = self.evaluate(u, false);
        (sn, cn)
    }

    /// sn, cn and, if `want_dn`, dn (always from the circular and Landen branches).
    #[inline(always)]
    fn evaluate(&self, u: &T, want_dn: bool) -> (T, T, Option<T>) {
        let n = self.a.len() - 1;
        if n == 0 {
            // k = 0 to working precision: circular functions.
            return (u.sin(), u.cos(), Some(u.one_like()));
        }
        // Bulirsch: with the AGM mean c = a_N, sin(cu) and cos(cu), then the recursion below.
        let c_agm = &self.a[n];
        let uc = u.clone() * c_agm;
        let (s, co) = uc.sin_cos();
        // |sin| below 1e-30 (compared in f64: no numbers made for it).
        if s.to_f64().abs() < 1e-30 {
            let (sn, cn, dn) = self.landen(u);
            return (sn, cn, Some(dn));
        }
        let mut x = Recursion::new(co * c_agm, s);
        for i in (1..=n).rev() {
            self.level(&mut x, i, want_dn);
        }
        x.finish(want_dn)
    }

    /// (sn, cn) of two moduli at once (the two separated variables of a motion): the same
    /// numbers as [`Self::sn_cn`] of each, with the two recursions' levels side by side so
    /// that the processor overlaps their chains of dependent operations.
    #[inline(always)]
    pub fn sn_cn_pair(first: &Self, u1: &T, second: &Self, u2: &T) -> ((T, T), (T, T)) {
        let (n1, n2) = (first.a.len() - 1, second.a.len() - 1);
        if n1 == 0 || n2 == 0 {
            return (first.sn_cn(u1), second.sn_cn(u2));
        }
        let (s1, c1) = (u1.clone() * &first.a[n1]).sin_cos();
        let (s2, c2) = (u2.clone() * &second.a[n2]).sin_cos();
        if s1.to_f64().abs() < 1e-30 || s2.to_f64().abs() < 1e-30 {
            return (first.sn_cn(u1), second.sn_cn(u2));
        }
        let mut x = Recursion::new(c1 * &first.a[n1], s1);
        let mut y = Recursion::new(c2 * &second.a[n2], s2);
        Self::levels_side_by_side(first, &mut x, second, &mut y);
        let ((sn1, cn1, _), (sn2, cn2, _)) = (x.finish(false), y.finish(false));
        ((sn1, cn1), (sn2, cn2))
    }

    /// sn u : cn u of two moduli at once from sin and cos of a_N·u given by the caller (who
    /// may know the angle a_N·u = 2π·u/4K more cheaply than from u: in turns), as pairs (q, p)
    /// with sn = q/√(p² + q²) and cn = p/√(p² + q²), both scaled by one power of two that
    /// brings the larger near 1: Bulirsch's recursion of [`Self::sn_cn_pair`] without its last
    /// step (a square root and two products), for what is homogeneous of degree 0 in (sn, cn)
    /// ([`crate::separated::SeparatedVariable::eval`]). Near a zero of sin (the Landen branch)
    /// `u1`, `u2` give u and the pair is (sn, cn).
    #[inline(always)]
    pub fn sn_cn_ratio_pair(
        first: &Self,
        (s1, c1): (T, T),
        u1: impl FnOnce() -> T,
        second: &Self,
        (s2, c2): (T, T),
        u2: impl FnOnce() -> T,
    ) -> ((T, T), (T, T)) {
        if s1.to_f64().abs() < 1e-30 || s2.to_f64().abs() < 1e-30 {
            return (first.sn_cn(&u1()), second.sn_cn(&u2()));
        }
        let (n1, n2) = (first.a.len() - 1, second.a.len() - 1);
        let mut x = Recursion::new(c1 * &first.a[n1], s1);
        let mut y = Recursion::new(c2 * &second.a[n2], s2);
        Self::levels_side_by_side(first, &mut x, second, &mut y);
        (x.ratio(), y.ratio())
    }

    /// The levels N…1 of two recursions (without the last dn), level by level side by side so
    /// that the processor overlaps their chains of dependent operations.
    #[inline(always)]
    fn levels_side_by_side(
        first: &Self,
        x: &mut Recursion<T>,
        second: &Self,
        y: &mut Recursion<T>,
    ) {
        let (n1, n2) = (first.a.len() - 1, second.a.len() - 1);
        for j in 0..n1.max(n2) {
            if j < n1 {
                first.level(x, n1 - j, false);
            }
            if j < n2 {
                second.level(y, n2 - j, false);
            }
        }
    }

    /// Level i of Bulirsch's recursion (see [`Recursion`]); at i = 1 without dn only c ← c·dn.
    #[inline(always)]
    fn level(&self, x: &mut Recursion<T>, i: usize, want_dn: bool) {
        let (p2, q2) = (x.p.square(), x.q.square());
        if let Some((r, s)) = x.dn.take() {
            x.p *= &r;
            x.q *= &s;
        }
        if i == 1 && !want_dn {
            return;
        }
        let r = (q2.clone() * &self.beta[i - 1]).add_same_sign(&p2);
        let s = (q2 * &self.alpha[i - 1]).add_same_sign(&p2);
        x.dn = Some((r, s));
        rescale(&mut x.p, &mut x.q);
    }

    /// The inverse of [`Self::sn_cn_dn`]: the u ∈ [0, 4K) with (sn u, cn u) = (s, c)/√(s² + c²).
    /// The amplitude φ = am u ∈ [0, π/2] of the first quarter goes through the descending
    /// Landen transformation of the same AGM, tan(φₙ₊₁ − φₙ) = (bₙ/aₙ) tan φₙ, and
    /// F(φ) = φ_N/(2^N a_N) (DLMF 19.8.12 with 22.20(ii)); the other quarters by symmetry.
    pub fn u_of(&self, s: &T, c: &T) -> T {
        let zero = s.zero_like();
        let pi = T::pi(s.prec());
        let two_k = self.big_k.clone() * s.lit(2.0);
        // φ ∈ [0, π/2] from |s|, |c|, then u = F(φ), 2K − F, 2K + F or 4K − F by quadrant.
        let phi = s.abs().atan2(&c.abs());
        let f = self.incomplete(&phi, &pi);
        match (*s >= zero, *c >= zero) {
            (true, true) => f,
            (true, false) => two_k - f,
            (false, false) => two_k + f,
            (false, true) => two_k.clone() + two_k - f,
        }
    }

    /// F(φ | k) for φ ∈ [0, π/2].
    fn incomplete(&self, phi: &T, pi: &T) -> T {
        let n = self.a.len() - 1;
        let two_pi = pi.clone() * phi.lit(2.0);
        let mut phi = phi.clone();
        for i in 0..n {
            // atan2 lands in the quadrant of φₙ (aₙ, bₙ > 0); add the turns φₙ has made.
            let t = (self.b[i].clone() * phi.sin()).atan2(&(self.a[i].clone() * phi.cos()));
            let turns = ((phi.clone() - &t) / &two_pi + phi.lit(0.5)).floor();
            phi = phi.clone() + t + turns * &two_pi;
        }
        let scale = self.a[n].clone() * phi.lit(2f64.powi(n as i32));
        phi / scale
    }

    /// The descending Landen transformation: φ_N = 2^N a_N u, φ_{n−1} = (φ_n + asin(c_n/a_n sin φ_n))/2.
    fn landen(&self, u: &T) -> (T, T, T) {
        let n = self.a.len() - 1;
        let mut phi = u.clone() * &self.a[n] * u.lit(2f64.powi(n as i32));
        let mut phi_prev = phi.clone();
        for j in (1..=n).rev() {
            let y = self.c[j].clone() / &self.a[j] * phi.sin();
            let one = y.one_like();
            let asin = y.atan2(&((one.clone() - &y) * (one + &y)).sqrt());
            phi_prev = phi.clone();
            phi = (phi + asin) / u.lit(2.0);
        }
        let (s, c) = (phi.sin(), phi.cos());
        let dn = c.clone() / (phi_prev - &phi).cos();
        (s, c, dn)
    }
}

/// Bulirsch's recursion (Numerical Recipes' `sncndn`) with its c and dn carried as fractions
/// c = p/q, dn = r/s, so that no level divides: from c = cos(a_N u)·a_N/sin(a_N u) and, at level
/// i = N…1 (α_i = a_{i−1}a_i, β_i = b_{i−1}a_i),
///   c ← c·dn,  dn ← (b_{i−1} + c²/a_i)/(a_{i−1} + c²/a_i) = (β_i q² + p²)/(α_i q² + p²),
/// then sn = sign(sin)/√(1 + c²) = q/√(p² + q²) and cn = c·sn = p/√(p² + q²). Every sum adds two
/// positive numbers (no cancellation), so p, q, r, s keep their relative accuracy (also near
/// the zeros of sn and cn); the last dn is skipped when not wanted.
struct Recursion<T> {
    p: T,
    q: T,
    /// dn = r/s (None: 1).
    dn: Option<(T, T)>,
}

impl<T: Real> Recursion<T> {
    #[inline(always)]
    fn new(p: T, q: T) -> Self {
        Self { p, q, dn: None }
    }

    /// (sn, cn, dn if wanted).
    #[inline(always)]
    fn finish(self, want_dn: bool) -> (T, T, Option<T>) {
        let mag = self.p.square().add_same_sign(&self.q.square()).recip_sqrt();
        let dn = want_dn.then(|| self.dn.map_or_else(|| mag.one_like(), |(r, s)| r / s));
        (self.q * &mag, self.p * &mag, dn)
    }

    /// (q, p) = sn : cn (the recursion run to its end, without the normalisation of
    /// [`Self::finish`]), the larger brought into [1, 2) by a power of two (exact).
    #[inline(always)]
    fn ratio(self) -> (T, T) {
        debug_assert!(self.dn.is_none());
        let (mut p, mut q) = (self.p, self.q);
        // The biased exponent e of the larger: times 2^(1023 − e), exactly, when both are normal.
        let e = (p.to_f64().abs().max(q.to_f64().abs()).to_bits() >> 52) as u32;
        if (1..=2045).contains(&e) {
            let f = p.lit(f64::from_bits(u64::from(2046 - e) << 52));
            p *= &f;
            q *= &f;
        }
        (q, p)
    }
}

/// p and q times one power of two that brings the larger near 1 when it leaves [1e-50, 1e50]
/// (exact; the fraction p/q is unchanged). Each level of the recursion at most cubes them, so
/// f64 and double-double numbers never leave their range; MPFR's never need it.
#[inline(always)]
fn rescale<T: Real>(p: &mut T, q: &mut T) {
    let m = p.to_f64().abs().max(q.to_f64().abs());
    if (1e-50..=1e50).contains(&m) || !(m.is_finite() && m > 0.0) {
        return;
    }
    let k = -(m.log2().round() as i32);
    let f = p.lit(2f64.powi(k));
    *p *= &f;
    *q *= &f;
}

#[cfg(test)]
mod tests {
    use super::*;
    use rug::Float;

    fn f(x: f64) -> Float {
        Float::with_val(300, x)
    }

    #[test]
    fn identities_and_derivative_hold_at_high_precision() {
        for &k2 in &[0.0, 1e-12, 0.3, 0.9, 1.0 - 1e-9] {
            let kc2 = f(1.0) - f(k2);
            let m = EllipticModulus::new(f(k2), kc2);
            for &u in &[0.1, 0.7, 1.9, 3.3, -2.2] {
                let (s, c, d) = m.sn_cn_dn(&f(u));
                // sn_cn skips the last dn: the same sn and cn, bit for bit.
                assert_eq!(m.sn_cn(&f(u)), (s.clone(), c.clone()), "k2={k2} u={u}");
                let one = f(1.0);
                let e1 = (s.clone() * &s + c.clone() * &c - &one).abs();
                let e2 = (d.clone() * &d + f(k2) * s.clone() * &s - &one).abs();
                assert!(e1 < 1e-85 && e2 < 1e-85, "k2={k2} u={u}: {e1} {e2}");
                // d sn/du = cn dn, checked by a central difference at 300 bits.
                let h = f(1e-30);
                let (sp, _, _) = m.sn_cn_dn(&(f(u) + &h));
                let (sm, _, _) = m.sn_cn_dn(&(f(u) - &h));
                let fd = (sp - sm) / (h * f(2.0));
                assert!((fd - c * d).abs() < 1e-50);
            }
        }
    }

    #[test]
    fn u_of_inverts_sn_cn_in_every_quarter() {
        for &k2 in &[0.0, 1e-12, 0.3, 0.9, 1.0 - 1e-9] {
            let m = EllipticModulus::new(f(k2), f(1.0) - f(k2));
            let four_k = m.big_k.clone() * f(4.0);
            for frac in [
                0.0, 0.01, 0.2, 0.25, 0.49, 0.5, 0.51, 0.74, 0.75, 0.9, 0.999,
            ] {
                let u = four_k.clone() * f(frac);
                let (s, c, _) = m.sn_cn_dn(&u);
                let back = m.u_of(&s, &c);
                assert!(
                    (back.clone() - &u).abs() < 1e-80,
                    "k2={k2} u/4K={frac}: {back} vs {u}"
                );
            }
        }
        // A wrong quadrant is not silently accepted: (sn, −cn) is another u.
        let m = EllipticModulus::new(f(0.3), f(0.7));
        let (s, c, _) = m.sn_cn_dn(&f(0.4));
        assert!((m.u_of(&s, &(-c)) - f(0.4)).abs() > 1.0);
        let m64 = EllipticModulus::new(0.5f64, 0.5);
        let (s, c, _) = m64.sn_cn_dn(&2.5);
        assert_eq!(m64.sn_cn(&2.5), (s, c));
        assert!((m64.u_of(&s, &c) - 2.5).abs() < 1e-14);
    }

    /// Two moduli at once give each one's (sn, cn) bit for bit, also with different level
    /// counts, a circular modulus (k = 0) and a u at a zero of sn (the Landen branch).
    #[test]
    fn pairs_are_each_modulus_alone() {
        use rsts_dynamics::scalar::DoubleDouble;
        fn check<T: Real>(lift: impl Fn(f64) -> T) {
            let k2s = [0.0, 0.3, 0.425, 0.98, 1.0 - 1e-9];
            let moduli: Vec<_> = k2s
                .iter()
                .map(|&k2| EllipticModulus::new(lift(k2), lift(1.0) - lift(k2)))
                .collect();
            let levels: Vec<usize> = moduli.iter().map(|m| m.a.len()).collect();
            assert!(levels.windows(2).any(|w| w[0] != w[1]), "{levels:?}");
            for m1 in &moduli {
                for m2 in &moduli {
                    for (u1, u2) in [(0.1, 2.9), (1.7, -0.4), (0.0, 3.3), (5.5, 0.0)] {
                        let (u1, u2) = (lift(u1), lift(u2));
                        let pair = EllipticModulus::sn_cn_pair(m1, &u1, m2, &u2);
                        assert_eq!(pair, (m1.sn_cn(&u1), m2.sn_cn(&u2)), "{levels:?}");
                    }
                }
            }
        }
        check(|x| x);
        check(DoubleDouble::from_f64_exact);
        check(f);
    }

    #[test]
    fn quarter_period_is_where_sn_is_one() {
        for &k2 in &[0.2, 0.99] {
            let m = EllipticModulus::new(f(k2), f(1.0) - f(k2));
            let (s, c, _) = m.sn_cn_dn(&m.big_k);
            assert!((s - f(1.0)).abs() < 1e-80 && c.abs() < 1e-40);
        }
        // f64 K(k²=0.5) = 1.8540746773013719 (A&S Table 17.1).
        let m = EllipticModulus::new(0.5f64, 0.5);
        assert!((m.big_k - 1.854_074_677_301_371_9).abs() < 1e-15);
    }
}
