//! A torus of N tabulated once per motion (stop 29): the projector of `rsts check` evaluates the
//! torus map C(ψ₁, ψ₂) and its derivatives in ψ₁, ψ₂, m and h a few times per sample, and the
//! elliptic functions (the AGM of sn, cn, dn over dual numbers and jets) cost ~10× the rest.
//!
//! The state is an algebraic function (eqs. 1.3, 1.4: [`body_state`](crate::formulas::body_state)) of the two separated
//! points (v, F, G)ᵢ, each a function of its own angle ψᵢ alone (through sn, cn of
//! u = ψᵢ·period/2π, [`SeparatedVariable::eval`]). So each variable's nine 2π-periodic
//! functions of ψᵢ — v, F, G and their ∂/∂m, ∂/∂h at fixed angle — are tabulated: on N equal
//! cells of [0, 2π), the polynomial of degree [`DEGREE`] interpolating the AGM path at the cell's
//! Chebyshev points. The cells double until the last two Chebyshev coefficients of every cell are
//! at the round-off of the samples (v, F, G) or below 1e-12 of their size (∂/∂m, ∂/∂h, which
//! only multiply the small shift of the torus); beyond [`MAX_CELLS`] (near Σ, where the nome →
//! 1 and sn steepens) there is no table and the projector keeps the AGM path. A torus point
//! then costs two cell look-ups, a few dozen multiply-adds and the formulas; its four
//! derivative columns one evaluation of the formulas over a jet of four directions.
//!
//! [`SeparatedVariable::eval`]: crate::separated::SeparatedVariable::eval

use rsts_dynamics::jet::Jet;
use rsts_dynamics::scalar::DoubleDouble;
use rsts_dynamics::state::DIM;
use rsts_dynamics::Real;

use crate::formulas::{
    body_state_with, BodyState, ConstantProducts, FormulaConstants, SeparatedCoordinates,
};
use crate::manifold::least_squares::{columns_of, LeastSquares, Rows};
use crate::manifold::torus_map::TorusMap;
use crate::motion::BatchPath;
use crate::separated::SeparatedPoint;

/// Degree of the polynomial on a cell.
pub const DEGREE: usize = 12;
/// Coefficients per polynomial.
const TERMS: usize = DEGREE + 1;
/// The most cells per variable before the table gives up.
pub const MAX_CELLS: usize = 1024;
const FIRST_CELLS: usize = 32;

/// The nine tabulated functions of one variable: v, F, G, then their ∂/∂m, then their ∂/∂h.
const FUNCTIONS: usize = 9;

/// One variable's nine functions of its angle, piecewise polynomial.
#[derive(Clone)]
struct Curve {
    /// Cells per 2π, their width and its inverse.
    cells: usize,
    width: f64,
    inv_width: f64,
    /// Per cell, the coefficients of t⁰ … t^DEGREE in t = 2(ψ − centre)/width, each of the
    /// nine functions' (power by power: the nine polynomials evaluated side by side).
    coef: Vec<[[f64; FUNCTIONS]; TERMS]>,
}

impl std::fmt::Debug for Curve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Curve({} cells of degree {DEGREE})", self.cells)
    }
}

/// The tabulated torus of one motion, in f64.
#[derive(Clone, Debug)]
pub struct TorusTable {
    curves: [Curve; 2],
    /// The formula constants with their ∂/∂m, ∂/∂h (directions 2, 3 of a four-direction jet).
    formula: FormulaConstants<Jet<f64, 4>>,
    /// Their values.
    plain: FormulaConstants<f64>,
    /// The products of the constants each point uses ([`ConstantProducts`]), formed once.
    formula_products: ConstantProducts<Jet<f64, 4>>,
    plain_products: ConstantProducts<f64>,
    /// The build of [`TorusTable::state_and_system`] this CPU runs.
    path: BatchPath,
}

/// The Chebyshev points x_k = cos(π(k + ½)/TERMS) of [−1, 1] and T_j(x_k), in double-double.
fn chebyshev_points() -> ([DoubleDouble; TERMS], [[DoubleDouble; TERMS]; TERMS]) {
    let pi = DoubleDouble::pi(106);
    let angle = |j: usize, k: usize| {
        let n = DoubleDouble::from_f64_exact((j * (2 * k + 1)) as f64);
        n * pi / DoubleDouble::from_f64_exact((2 * TERMS) as f64)
    };
    let x = std::array::from_fn(|k| angle(1, k).cos());
    let t = std::array::from_fn(|k| std::array::from_fn(|j| angle(j, k).cos()));
    (x, t)
}

/// The monomial coefficients of T_0 … T_DEGREE (integers, exact in f64).
fn chebyshev_monomials() -> [[f64; TERMS]; TERMS] {
    let mut p = [[0.0; TERMS]; TERMS];
    p[0][0] = 1.0;
    p[1][1] = 1.0;
    for j in 2..TERMS {
        for n in 0..TERMS {
            let up = if n > 0 { 2.0 * p[j - 1][n - 1] } else { 0.0 };
            p[j][n] = up - p[j - 2][n];
        }
    }
    p
}

/// The two tori a table is built from: the values from double-double, the derivatives in m, h
/// from f64 jets.
struct Source<'a> {
    fine: &'a TorusMap<DoubleDouble>,
    in_mh: &'a TorusMap<Jet<f64, 2>>,
}

impl Source<'_> {
    /// The nine functions of variable `i` at the angle ψ = centre + half·x.
    fn sample(
        &self,
        i: usize,
        centre: f64,
        half: f64,
        x: DoubleDouble,
    ) -> [DoubleDouble; FUNCTIONS] {
        let dd = DoubleDouble::from_f64_exact;
        let psi = dd(centre) + dd(half) * x;
        let p = self.fine.point(i, &psi);
        let d = self.in_mh.point(i, &Jet::constant(psi.to_f64()));
        [
            p.v,
            p.f,
            p.g,
            dd(d.v.eps[0]),
            dd(d.f.eps[0]),
            dd(d.g.eps[0]),
            dd(d.v.eps[1]),
            dd(d.f.eps[1]),
            dd(d.g.eps[1]),
        ]
    }
}

impl Curve {
    /// The table of variable `i` on `cells` cells, or `None` when a cell's Chebyshev tail is
    /// above the tolerance.
    fn build(source: &Source<'_>, i: usize, cells: usize) -> Option<Self> {
        let (x, t) = chebyshev_points();
        let mono = chebyshev_monomials();
        let width = std::f64::consts::TAU / cells as f64;
        let mut coef = Vec::with_capacity(cells);
        let mut tails = Vec::with_capacity(cells);
        let mut scale = [0.0f64; FUNCTIONS];
        for cell in 0..cells {
            let centre = (cell as f64 + 0.5) * width;
            let values: [[DoubleDouble; FUNCTIONS]; TERMS] =
                std::array::from_fn(|k| source.sample(i, centre, 0.5 * width, x[k]));
            let mut c = [[0.0; TERMS]; FUNCTIONS];
            let mut tail = [0.0f64; FUNCTIONS];
            let zero = DoubleDouble::from_f64_exact(0.0);
            for f in 0..FUNCTIONS {
                // Chebyshev coefficients of the interpolant, then its monomial coefficients, in
                // double-double (in f64 their round-off alone would be a few ulps of the value).
                let cheb: [DoubleDouble; TERMS] = std::array::from_fn(|j| {
                    let s = (0..TERMS).fold(zero, |acc, k| acc + values[k][f] * t[k][j]);
                    let w = if j == 0 { 1.0 } else { 2.0 } / TERMS as f64;
                    s * DoubleDouble::from_f64_exact(w)
                });
                for (n, cn) in c[f].iter_mut().enumerate() {
                    let sum = (n..TERMS).fold(zero, |acc, j| {
                        acc + cheb[j] * DoubleDouble::from_f64_exact(mono[j][n])
                    });
                    *cn = sum.to_f64();
                }
                tail[f] = cheb[DEGREE].to_f64().abs() + cheb[DEGREE - 1].to_f64().abs();
                for v in &values {
                    scale[f] = scale[f].max(v[f].to_f64().abs());
                }
            }
            coef.push(std::array::from_fn(|n| std::array::from_fn(|f| c[f][n])));
            tails.push(tail);
        }
        // Values at the round-off of their samples; ∂/∂m, ∂/∂h to 1e-12.
        let tolerance: [f64; FUNCTIONS] =
            std::array::from_fn(|f| scale[f] * if f < 3 { 2e-17 } else { 1e-12 });
        let fits = tails
            .iter()
            .all(|tail| (0..FUNCTIONS).all(|f| tail[f] <= tolerance[f]));
        fits.then(|| Self {
            cells,
            width,
            inv_width: 1.0 / width,
            coef,
        })
    }

    /// The cell of ψ and t ∈ [−1, 1] in it.
    #[inline(always)]
    fn locate(&self, psi: f64) -> (&[[f64; FUNCTIONS]; TERMS], f64) {
        // ⌊x⌋ without the library's `floor` (a call without SSE4.1): exact for |x| < 2⁵³.
        let x = psi * self.inv_width;
        let mut k = x as i64;
        if k as f64 > x {
            k -= 1;
        }
        let j = k as f64;
        let t = (psi - (j + 0.5) * self.width) * (2.0 * self.inv_width);
        let cell = k.rem_euclid(self.cells as i64) as usize;
        (&self.coef[cell], t)
    }

    /// v, F, G at ψ.
    #[inline(always)]
    fn point(&self, psi: f64) -> SeparatedPoint<f64> {
        let (c, t) = self.locate(psi);
        let [v, f, g] = horner::<3>(c, t);
        SeparatedPoint { v, f, g }
    }

    /// v, F, G at ψ with their derivatives in (ψ₁, ψ₂, m, h) as jets (this is variable `i`).
    #[inline(always)]
    fn jet_point(&self, i: usize, psi: f64) -> SeparatedPoint<Jet<f64, 4>> {
        let (c, t) = self.locate(psi);
        let d_psi = 2.0 * self.inv_width;
        let (p, slope) = horner_slope(c, t);
        let [v, f, g] = std::array::from_fn(|k| {
            let mut eps = [0.0; 4];
            eps[i] = slope[k] * d_psi;
            eps[2] = p[3 + k];
            eps[3] = p[6 + k];
            Jet { re: p[k], eps }
        });
        SeparatedPoint { v, f, g }
    }
}

/// Σ cₙtⁿ of the first `N` functions, side by side (each the Horner scheme from cₙ at the top:
/// the same operations per polynomial as one at a time).
#[inline(always)]
fn horner<const N: usize>(c: &[[f64; FUNCTIONS]; TERMS], t: f64) -> [f64; N] {
    let mut acc = [0.0; N];
    for cn in c.iter().rev() {
        for (a, x) in acc.iter_mut().zip(cn) {
            *a = *a * t + x;
        }
    }
    acc
}

/// Σ cₙtⁿ of all nine functions, and the derivative in t of the first three (v, F, G).
#[inline(always)]
fn horner_slope(c: &[[f64; FUNCTIONS]; TERMS], t: f64) -> ([f64; FUNCTIONS], [f64; 3]) {
    // The top coefficient: v, F, G's as they are, the others' through 0·t + c (as `horner`).
    let mut p: [f64; FUNCTIONS] = std::array::from_fn(|f| {
        if f < 3 {
            c[DEGREE][f]
        } else {
            0.0 * t + c[DEGREE][f]
        }
    });
    let mut d = [0.0; 3];
    for cn in c[..DEGREE].iter().rev() {
        for (dk, pk) in d.iter_mut().zip(&p) {
            *dk = *dk * t + pk;
        }
        for (a, x) in p.iter_mut().zip(cn) {
            *a = *a * t + x;
        }
    }
    (p, d)
}

fn phase_vector<S: Clone>(b: BodyState<S>) -> [S; DIM] {
    let [w0, w1, w2] = b.omega;
    let [a0, a1, a2] = b.alpha;
    let [b0, b1, b2] = b.beta;
    [w0, w1, w2, a0, a1, a2, b0, b1, b2]
}

impl TorusTable {
    /// The table of the torus `fine` (in double-double) with the derivatives of `in_mh` (the
    /// same torus over f64 jets seeded in m and h), or `None` where [`MAX_CELLS`] cells do not
    /// reach the tolerance.
    pub fn new(fine: &TorusMap<DoubleDouble>, in_mh: &TorusMap<Jet<f64, 2>>) -> Option<Self> {
        let source = Source { fine, in_mh };
        let curve = |i: usize| {
            let mut cells = FIRST_CELLS;
            loop {
                if let Some(c) = Curve::build(&source, i, cells) {
                    return Some(c);
                }
                cells *= 2;
                if cells > MAX_CELLS {
                    return None;
                }
            }
        };
        let curves = [curve(0)?, curve(1)?];
        let f = in_mh.formula();
        let formula = f.map(|x| Jet {
            re: x.re,
            eps: [0.0, 0.0, x.eps[0], x.eps[1]],
        });
        let plain = f.map(|x| x.re);
        Some(Self {
            curves,
            formula_products: ConstantProducts::new(&formula),
            plain_products: ConstantProducts::new(&plain),
            formula,
            plain,
            path: BatchPath::detect(),
        })
    }

    /// The point (v, F, G) of separated variable `i` at its angle ψᵢ.
    pub fn point(&self, i: usize, psi: f64) -> SeparatedPoint<f64> {
        self.curves[i].point(psi)
    }

    /// Cells per 2π of the two variables.
    pub fn cells(&self) -> [usize; 2] {
        [self.curves[0].cells, self.curves[1].cells]
    }

    /// The state (ω, α, β) at (ψ₁, ψ₂).
    #[inline]
    pub fn state_at(&self, psi: &[f64; 2]) -> [f64; DIM] {
        let p =
            SeparatedCoordinates::new(self.curves[0].point(psi[0]), self.curves[1].point(psi[1]));
        phase_vector(body_state_with(&self.plain, &self.plain_products, &p))
    }

    /// The state at (ψ₁, ψ₂) and its derivatives ∂/∂ψ₁, ∂/∂ψ₂, ∂/∂m, ∂/∂h (at fixed angles).
    #[inline]
    pub fn state_and_derivatives(&self, psi: &[f64; 2]) -> ([f64; DIM], [[f64; DIM]; 4]) {
        let (value, rows) = self.state_and_rows(psi);
        (value, columns_of(&rows))
    }

    /// [`TorusTable::state_and_derivatives`] with the derivatives by rows: the four lanes of
    /// each component's jet.
    #[inline(always)]
    pub(crate) fn state_and_rows(&self, psi: &[f64; 2]) -> ([f64; DIM], Rows) {
        let p = SeparatedCoordinates::new(
            self.curves[0].jet_point(0, psi[0]),
            self.curves[1].jet_point(1, psi[1]),
        );
        let x = phase_vector(body_state_with(&self.formula, &self.formula_products, &p));
        (
            std::array::from_fn(|k| x[k].re),
            std::array::from_fn(|k| x[k].eps),
        )
    }

    /// The state at (ψ₁, ψ₂) and the elimination of the Gauss–Newton step with its Jacobian
    /// (`None`: singular), compiled with AVX2 where the CPU has it (the jet's four derivative
    /// lanes and the rows of JᵀJ one register each): the same numbers on every path, since
    /// both perform the same operations (no multiply-add is fused; tested).
    #[inline]
    pub(crate) fn state_and_system(&self, psi: &[f64; 2]) -> ([f64; DIM], Option<LeastSquares>) {
        match self.path {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `path` is Avx2Fma only where the CPU has AVX2 and FMA (BatchPath::detect).
            BatchPath::Avx2Fma => unsafe { self.state_and_system_avx2(psi) },
            _ => self.state_and_system_portable(psi),
        }
    }

    /// [`TorusTable::state_and_system`] on a given build; `None` when this CPU lacks it.
    #[cfg(test)]
    pub(crate) fn state_and_system_on(
        &self,
        path: BatchPath,
        psi: &[f64; 2],
    ) -> Option<([f64; DIM], Option<LeastSquares>)> {
        path.available().then(|| {
            Self {
                path,
                ..self.clone()
            }
            .state_and_system(psi)
        })
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn state_and_system_avx2(&self, psi: &[f64; 2]) -> ([f64; DIM], Option<LeastSquares>) {
        self.system(psi)
    }

    fn state_and_system_portable(&self, psi: &[f64; 2]) -> ([f64; DIM], Option<LeastSquares>) {
        self.system(psi)
    }

    #[inline(always)]
    fn system(&self, psi: &[f64; 2]) -> ([f64; DIM], Option<LeastSquares>) {
        let (value, rows) = self.state_and_rows(psi);
        (value, LeastSquares::new(&rows))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifold::Projector;
    use crate::motion::{ExplicitMotion, TorusChoice};

    /// An angle a few turns below 0 or above 2π falls in its cell: the point of the AGM path.
    #[test]
    fn the_cells_repeat_every_turn() {
        let motion = ExplicitMotion::new(1.0, 0.5, -0.7092, 1.5643, TorusChoice::default());
        let motion = motion.unwrap();
        let table = Projector::new(&motion).unwrap().table().unwrap().clone();
        let agm = TorusMap::of_motion(&motion);
        let tau = std::f64::consts::TAU;
        for k in 0..500 {
            let psi = 0.0123 * k as f64;
            for turns in [-3.0, -1.0, 1.0, 5.0] {
                for i in 0..2 {
                    let (p, q) = (agm.point(i, &psi), table.point(i, psi + turns * tau));
                    for (u, v) in [(p.v, q.v), (p.f, q.f), (p.g, q.g)] {
                        assert!((u - v).abs() < 1e-12, "ψ = {psi}, {turns} turns: {u} {v}");
                    }
                }
            }
        }
    }

    /// The AVX2 build of the state, its Jacobian and the Gauss–Newton step gives the portable
    /// build's numbers bit for bit, in a camera with m > 0 and one with m < 0.
    #[test]
    fn the_avx2_system_is_the_portable_one_bit_for_bit() {
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let mut avx2 = true;
        for (m, h, torus) in [(0.3, -0.375, 0), (-0.7092, 1.5643, 2)] {
            let choice = TorusChoice {
                torus,
                ..TorusChoice::default()
            };
            let motion = ExplicitMotion::new(1.0, 0.5, m, h, choice).unwrap();
            let projector = Projector::new(&motion).unwrap();
            let table = projector.table().unwrap();
            for k in 0..2000 {
                let psi = [0.0137 * k as f64 - 3.0, 40.0 - 0.0291 * k as f64];
                let r: [f64; DIM] = std::array::from_fn(|i| ((k * 7 + i) as f64).sin() * 1e-4);
                let run = |path| {
                    table
                        .state_and_system_on(path, &psi)
                        .map(|(value, system)| {
                            let system = system.unwrap();
                            let rows = system.rows().concat();
                            (bits(&value), bits(&rows), bits(&system.step(&r)))
                        })
                };
                let portable = run(BatchPath::Portable).unwrap();
                match run(BatchPath::Avx2Fma) {
                    Some(fast) => assert_eq!(fast, portable, "({m}, {h}) ψ = {psi:?}"),
                    None => avx2 = false,
                }
            }
        }
        if !avx2 {
            rsts_io::report_skip(
                "the_avx2_system_is_the_portable_one_bit_for_bit (AVX2 + FMA build)",
                "this CPU lacks AVX2 or FMA",
            );
        }
    }
}
