//! The Euler–Poisson equations of the Kowalevski top in two constant fields, written **once**, as
//! data: each component of the right-hand side is a sum of quadratic terms `c·xᵢ·xⱼ` and linear
//! terms `c·xᵢ`, with coefficients that are numbers times 1, `a` or `b`.
//!
//! Everything else is derived from this one table: the right-hand side in any scalar
//! ([`VectorField::eval`]), the Taylor coefficients of a solution (Cauchy products,
//! [`VectorField::taylor_coefficient`]), the Jacobian ([`VectorField::jacobian`]).
//!
//! With inertia I = diag(2, 2, 1), M = Iω, the equations (seed sec. 1; Kharlamov, RCD 10 (2005))
//!
//! ```text
//!   dM/dt = M×ω + a e₁×α + b e₂×β,   dα/dt = α×ω,   dβ/dt = β×ω,
//! ```
//!
//! written out component by component (M×ω = (ω₂ω₃, −ω₁ω₃, 0)):
//!
//! ```text
//!   ω̇₁ =  ½ ω₂ω₃ + ½ b β₃        α̇₁ = α₂ω₃ − α₃ω₂      β̇₁ = β₂ω₃ − β₃ω₂
//!   ω̇₂ = −½ ω₁ω₃ − ½ a α₃        α̇₂ = α₃ω₁ − α₁ω₃      β̇₂ = β₃ω₁ − β₁ω₃
//!   ω̇₃ =  a α₂ − b β₁            α̇₃ = α₁ω₂ − α₂ω₁      β̇₃ = β₁ω₂ − β₂ω₁
//! ```

use crate::fields::Fields;
use crate::scalar::Real;
use crate::state::DIM;

/// Which parameter multiplies a coefficient.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    One,
    A,
    B,
}

/// Index of each coordinate in the state vector (ω, α, β).
pub mod idx {
    pub const W1: usize = 0;
    pub const W2: usize = 1;
    pub const W3: usize = 2;
    pub const A1: usize = 3;
    pub const A2: usize = 4;
    pub const A3: usize = 5;
    pub const B1: usize = 6;
    pub const B2: usize = 7;
    pub const B3: usize = 8;
}
use idx::*;

/// `c · param · x[i] · x[j]`.
#[derive(Clone, Copy, Debug)]
pub struct Quadratic {
    pub c: f64,
    pub param: Param,
    pub i: usize,
    pub j: usize,
}
/// `c · param · x[i]`.
#[derive(Clone, Copy, Debug)]
pub struct Linear {
    pub c: f64,
    pub param: Param,
    pub i: usize,
}

/// One component of the right-hand side.
#[derive(Clone, Copy, Debug)]
pub struct Component {
    pub quadratic: &'static [Quadratic],
    pub linear: &'static [Linear],
}

const fn q(c: f64, i: usize, j: usize) -> Quadratic {
    Quadratic {
        c,
        param: Param::One,
        i,
        j,
    }
}
const fn l(c: f64, param: Param, i: usize) -> Linear {
    Linear { c, param, i }
}

/// Poisson equation dv/dt = v×ω for the unit vector whose components start at `v`.
const fn poisson(v: usize, k: usize) -> [Quadratic; 2] {
    // (v×ω)_k = v_{k+1} ω_{k+2} − v_{k+2} ω_{k+1}  (indices mod 3)
    let k1 = (k + 1) % 3;
    let k2 = (k + 2) % 3;
    [q(1.0, v + k1, W1 + k2), q(-1.0, v + k2, W1 + k1)]
}

const ALPHA_DOT: [[Quadratic; 2]; 3] = [poisson(A1, 0), poisson(A1, 1), poisson(A1, 2)];
const BETA_DOT: [[Quadratic; 2]; 3] = [poisson(B1, 0), poisson(B1, 1), poisson(B1, 2)];

/// The right-hand side of the Euler–Poisson equations: the single definition of the dynamics.
pub const EULER_POISSON: [Component; DIM] = [
    Component {
        quadratic: &[q(0.5, W2, W3)],
        linear: &[l(0.5, Param::B, B3)],
    },
    Component {
        quadratic: &[q(-0.5, W1, W3)],
        linear: &[l(-0.5, Param::A, A3)],
    },
    Component {
        quadratic: &[],
        linear: &[l(1.0, Param::A, A2), l(-1.0, Param::B, B1)],
    },
    Component {
        quadratic: &ALPHA_DOT[0],
        linear: &[],
    },
    Component {
        quadratic: &ALPHA_DOT[1],
        linear: &[],
    },
    Component {
        quadratic: &ALPHA_DOT[2],
        linear: &[],
    },
    Component {
        quadratic: &BETA_DOT[0],
        linear: &[],
    },
    Component {
        quadratic: &BETA_DOT[1],
        linear: &[],
    },
    Component {
        quadratic: &BETA_DOT[2],
        linear: &[],
    },
];

/// One quadratic term of [`EULER_POISSON`] with the component `k` it belongs to, flattened at
/// compile time from the table ([`QUADRATIC_TERMS`]).
#[derive(Clone, Copy, Debug)]
struct FlatQuadratic {
    term: Quadratic,
    k: usize,
}

/// Number of quadratic terms of a table (const-evaluated).
const fn count_quadratic(table: &[Component; DIM]) -> usize {
    let mut count = 0;
    let mut k = 0;
    while k < DIM {
        count += table[k].quadratic.len();
        k += 1;
    }
    count
}

/// Number of quadratic terms of [`EULER_POISSON`].
const NQ: usize = count_quadratic(&EULER_POISSON);

/// The quadratic terms of [`EULER_POISSON`] in table order (component by component), derived
/// from the table at compile time: the f64 Taylor kernel loops over this constant list, so the
/// compiler unrolls it into straight-line code with constant indices.
const QUADRATIC_TERMS: [FlatQuadratic; NQ] = {
    let mut out = [FlatQuadratic {
        term: q(0.0, 0, 0),
        k: 0,
    }; NQ];
    let mut n = 0;
    let mut k = 0;
    while k < DIM {
        let quad = EULER_POISSON[k].quadratic;
        let mut t = 0;
        while t < quad.len() {
            out[n] = FlatQuadratic { term: quad[t], k };
            n += 1;
            t += 1;
        }
        k += 1;
    }
    out
};

/// One linear term of [`EULER_POISSON`] with its component `k` ([`LINEAR_TERMS`]).
#[derive(Clone, Copy, Debug)]
struct FlatLinear {
    term: Linear,
    k: usize,
}

/// Number of linear terms of a table (const-evaluated).
const fn count_linear(table: &[Component; DIM]) -> usize {
    let mut count = 0;
    let mut k = 0;
    while k < DIM {
        count += table[k].linear.len();
        k += 1;
    }
    count
}

/// Number of linear terms of [`EULER_POISSON`].
const NL: usize = count_linear(&EULER_POISSON);

/// The linear terms of [`EULER_POISSON`] in table order, derived at compile time.
const LINEAR_TERMS: [FlatLinear; NL] = {
    let mut out = [FlatLinear {
        term: l(0.0, Param::One, 0),
        k: 0,
    }; NL];
    let mut n = 0;
    let mut k = 0;
    while k < DIM {
        let lin = EULER_POISSON[k].linear;
        let mut t = 0;
        while t < lin.len() {
            out[n] = FlatLinear { term: lin[t], k };
            n += 1;
            t += 1;
        }
        k += 1;
    }
    out
};

/// Same table as [`EULER_POISSON`] (term by term)?
fn is_euler_poisson(table: &[Component; DIM]) -> bool {
    fn same_q(a: &Quadratic, b: &Quadratic) -> bool {
        a.c.to_bits() == b.c.to_bits() && a.param == b.param && a.i == b.i && a.j == b.j
    }
    fn same_l(a: &Linear, b: &Linear) -> bool {
        a.c.to_bits() == b.c.to_bits() && a.param == b.param && a.i == b.i
    }
    table.iter().zip(&EULER_POISSON).all(|(a, b)| {
        a.quadratic.len() == b.quadratic.len()
            && a.linear.len() == b.linear.len()
            && a.quadratic
                .iter()
                .zip(b.quadratic)
                .all(|(x, y)| same_q(x, y))
            && a.linear.iter().zip(b.linear).all(|(x, y)| same_l(x, y))
    })
}

/// Scratch of [`VectorField::taylor_coefficient_orders`]: the factors of every quadratic term
/// of [`EULER_POISSON`] gathered order by order (`left[m][t]` = x_{i(t),m}, `right[m][t]` =
/// x_{j(t),m}), so each Cauchy step is one element-wise multiply-add over contiguous
/// `[T; NQ]` rows (vectorised in f64), and the even/odd partial sums.
#[derive(Clone, Debug)]
pub struct CauchyScratch<T> {
    left: Vec<[T; NQ]>,
    right: Vec<[T; NQ]>,
    /// Rows of `left`/`right` gathered from the current series.
    rows: usize,
    /// Even- and odd-m partial sums; moved out into locals during a call (so in f64 they
    /// live in registers), never reallocated.
    sums: Option<([T; NQ], [T; NQ])>,
}

impl<T: Real> CauchyScratch<T> {
    pub fn new(like: &T) -> Self {
        let zeros = || std::array::from_fn(|_| like.zero_like());
        Self {
            left: Vec::new(),
            right: Vec::new(),
            rows: 0,
            sums: Some((zeros(), zeros())),
        }
    }

    /// Gather row m of the factors from `row` = x_m.
    fn gather(&mut self, m: usize, row: &[T; DIM]) {
        while self.left.len() <= m {
            let zeros: [T; NQ] = std::array::from_fn(|_| row[0].zero_like());
            self.left.push(zeros.clone());
            self.right.push(zeros);
        }
        let (left, right) = (&mut self.left[m], &mut self.right[m]);
        for t in 0..NQ {
            left[t].clone_from(&row[QUADRATIC_TERMS[t].term.i]);
            right[t].clone_from(&row[QUADRATIC_TERMS[t].term.j]);
        }
    }
}

/// A quadratic term flattened: coefficient (parameter multiplied in), i, j, component k.
pub(crate) type FlatTerm<T> = (T, usize, usize, usize);
/// A linear term flattened: coefficient, i, component k.
pub(crate) type FlatLinearTerm<T> = (T, usize, usize);

/// A term with its coefficient evaluated in the scalar type.
#[derive(Clone, Debug)]
struct Term<T> {
    c: T,
    i: usize,
    j: Option<usize>,
}

/// The Euler–Poisson vector field for given field strengths, ready to evaluate in scalar `T`.
#[derive(Clone, Debug)]
pub struct VectorField<T> {
    /// The table the field was built from.
    table: [Component; DIM],
    terms: Vec<Vec<Term<T>>>,
    /// Built from [`EULER_POISSON`] itself: the const-unrolled kernel applies.
    standard: bool,
    /// Coefficients of [`QUADRATIC_TERMS`] then [`LINEAR_TERMS`] (parameters multiplied in),
    /// when `standard`.
    quad_c: Vec<T>,
    lin_c: Vec<T>,
    /// Flattened terms (coefficient, i, j, component k) of the table, for other tables.
    quad: Vec<FlatTerm<T>>,
    /// Flattened linear terms (coefficient, i, component k).
    lin: Vec<FlatLinearTerm<T>>,
}

fn coefficient<T: Real>(fields: &Fields<T>, c: f64, param: Param) -> T {
    let c = fields.a.lit(c);
    match param {
        Param::One => c,
        Param::A => c * &fields.a,
        Param::B => c * &fields.b,
    }
}

impl<T: Real> VectorField<T> {
    /// Build the field from the table [`EULER_POISSON`].
    pub fn new(fields: &Fields<T>) -> Self {
        Self::from_table(fields, &EULER_POISSON)
    }

    /// Build a field from any table of the same shape (tests use it to break the equations).
    pub fn from_table(fields: &Fields<T>, table: &[Component; DIM]) -> Self {
        let terms = table
            .iter()
            .map(|comp| {
                let quad = comp.quadratic.iter().map(|t| Term {
                    c: coefficient(fields, t.c, t.param),
                    i: t.i,
                    j: Some(t.j),
                });
                let lin = comp.linear.iter().map(|t| Term {
                    c: coefficient(fields, t.c, t.param),
                    i: t.i,
                    j: None,
                });
                quad.chain(lin).collect()
            })
            .collect();
        let standard = is_euler_poisson(table);
        let quad_c = if standard {
            QUADRATIC_TERMS
                .iter()
                .map(|f| coefficient(fields, f.term.c, f.term.param))
                .collect()
        } else {
            Vec::new()
        };
        let lin_c = if standard {
            LINEAR_TERMS
                .iter()
                .map(|f| coefficient(fields, f.term.c, f.term.param))
                .collect()
        } else {
            Vec::new()
        };
        let mut quad = Vec::new();
        let mut lin = Vec::new();
        for (k, comp) in table.iter().enumerate() {
            for t in comp.quadratic {
                quad.push((coefficient(fields, t.c, t.param), t.i, t.j, k));
            }
            for t in comp.linear {
                lin.push((coefficient(fields, t.c, t.param), t.i, k));
            }
        }
        Self {
            table: *table,
            terms,
            standard,
            quad_c,
            lin_c,
            quad,
            lin,
        }
    }

    /// The table's terms flattened in table order: quadratic terms (coefficient with its
    /// parameter multiplied in, i, j, component k) and linear terms (coefficient, i, k). The
    /// limb-level MPFR kernel is built from this list.
    pub(crate) fn flat_terms(&self) -> (&[FlatTerm<T>], &[FlatLinearTerm<T>]) {
        (&self.quad, &self.lin)
    }

    /// The table of equations the field was built from.
    pub fn table(&self) -> &[Component; DIM] {
        &self.table
    }

    /// dx/dt = f(x).
    pub fn eval(&self, x: &[T; DIM]) -> [T; DIM] {
        std::array::from_fn(|k| self.eval_component(k, x))
    }

    /// dx/dt = f(x), into an existing buffer (no allocation for Copy scalars).
    pub fn eval_into(&self, x: &[T], out: &mut [T]) {
        for (k, o) in out.iter_mut().enumerate().take(DIM) {
            let mut acc = x[0].zero_like();
            for t in &self.terms[k] {
                match t.j {
                    Some(j) => acc += t.c.clone() * &x[t.i] * &x[j],
                    None => acc += t.c.clone() * &x[t.i],
                }
            }
            *o = acc;
        }
    }

    fn eval_component(&self, k: usize, x: &[T; DIM]) -> T {
        let mut acc = x[0].zero_like();
        for t in &self.terms[k] {
            match t.j {
                Some(j) => acc += t.c.clone() * &x[t.i] * &x[j],
                None => acc += t.c.clone() * &x[t.i],
            }
        }
        acc
    }

    /// Coefficient `n` of the Taylor series of f(x(t)), given the coefficients `0..=n` of x(t)
    /// (`series[i][k]` is the k-th coefficient of xᵢ). Quadratic terms are Cauchy products:
    /// (xᵢxⱼ)ₙ = Σₖ xᵢ,ₖ xⱼ,ₙ₋ₖ. The Taylor recursion is then x_{n+1} = f(x)ₙ / (n+1).
    pub fn taylor_coefficient(&self, series: &[Vec<T>], n: usize) -> [T; DIM] {
        std::array::from_fn(|k| {
            let mut acc = series[0][0].zero_like();
            for t in &self.terms[k] {
                match t.j {
                    Some(j) => {
                        let (xi, xj) = (&series[t.i], &series[j]);
                        let mut cauchy = acc.zero_like();
                        for m in 0..=n {
                            cauchy += xi[m].clone() * &xj[n - m];
                        }
                        acc += t.c.clone() * cauchy;
                    }
                    None => acc += t.c.clone() * &series[t.i][n],
                }
            }
            acc
        })
    }

    /// Buffered form of [`taylor_coefficient`](Self::taylor_coefficient) for the Taylor
    /// integrators: writes coefficient `n` of f(x(t)) into `out[..DIM]`, reusing the values in
    /// `out` and `scratch` (no allocation for MPFR numbers; products are fused where the scalar
    /// can: [`Real::mul_add_assign`]). `series[i]` needs the coefficients `0..=n` of xᵢ. Cost:
    /// one Cauchy product of length n + 1 per quadratic term of the table.
    pub fn taylor_coefficient_into(
        &self,
        series: &[Vec<T>],
        n: usize,
        out: &mut [T],
        scratch: &mut T,
    ) {
        for (k, o) in out.iter_mut().enumerate().take(DIM) {
            let mut first = true;
            for t in &self.terms[k] {
                let term_value: &T = match t.j {
                    Some(j) => {
                        let (xi, xj) = (&series[t.i], &series[j]);
                        // (xᵢxⱼ)ₙ = Σₘ xᵢ,ₘ xⱼ,ₙ₋ₘ
                        // Two interleaved partial sums (even and odd m): two independent
                        // dependency chains, about twice the throughput in f64.
                        let (xi, xj) = (&xi[..=n], &xj[..=n]);
                        scratch.clone_from(&xi[0]);
                        *scratch *= &xj[n];
                        if n >= 1 {
                            let mut odd = xi[1].clone();
                            odd *= &xj[n - 1];
                            let mut m = 2;
                            while m < n {
                                scratch.mul_add_assign(&xi[m], &xj[n - m]);
                                odd.mul_add_assign(&xi[m + 1], &xj[n - m - 1]);
                                m += 2;
                            }
                            if m == n {
                                scratch.mul_add_assign(&xi[n], &xj[0]);
                            }
                            *scratch += &odd;
                        }
                        scratch
                    }
                    None => &series[t.i][n],
                };
                if first {
                    o.clone_from(&t.c);
                    *o *= term_value;
                    first = false;
                } else {
                    o.mul_add_assign(&t.c, term_value);
                }
            }
            if first {
                // A component with no terms (never in the Euler–Poisson table).
                *o = series[0][0].zero_like();
            }
        }
    }

    /// Coefficient `n` of f(x(t)) from series stored order by order (`series[m][i]` is the
    /// m-th coefficient of xᵢ; `series[..=n]` is read), into `out`: the form the Taylor
    /// integrators use. Same terms, same order of the terms as
    /// [`taylor_coefficient_into`](Self::taylor_coefficient_into), and the same even/odd split
    /// of each Cauchy sum, so the results are the same (bit for bit in f64, up to the sign of
    /// zeros); all the table's products advance together, so their sums are independent
    /// chains.
    /// For the table [`EULER_POISSON`] itself the loop over the products runs over the
    /// compile-time list derived from it (straight-line code in f64); any other table goes
    /// through the same loop over its run-time term list.
    ///
    /// `scratch` keeps the factors gathered from the rows 0..n of earlier calls: a call for
    /// n ≥ 1 right after the call for n − 1 reuses them, so between the calls for 0, 1, …, n of
    /// one recursion only row `series[n]` may be new (any other pattern of calls regathers).
    pub fn taylor_coefficient_orders(
        &self,
        series: &[[T; DIM]],
        n: usize,
        out: &mut [T; DIM],
        scratch: &mut CauchyScratch<T>,
    ) {
        let series = &series[..=n];
        for o in out.iter_mut() {
            *o = o.zero_like();
        }
        let (mut even, mut odd) = scratch.sums.take().expect("scratch in place");
        if self.standard {
            // Rows 0..n were gathered by the calls for 0..n on the same series (the Taylor
            // recursion's order); otherwise (n = 0, or out of sequence) gather them all.
            if n == 0 || scratch.rows != n {
                for (m, row) in series[..n].iter().enumerate() {
                    scratch.gather(m, row);
                }
            }
            scratch.gather(n, &series[n]);
            scratch.rows = n + 1;
            cauchy_sums(&scratch.left, &scratch.right, n, &mut even, &mut odd);
            let quad_c: &[T; NQ] = self.quad_c[..].try_into().expect("one per term");
            for t in 0..NQ {
                out[QUADRATIC_TERMS[t].k].mul_add_assign(&quad_c[t], &even[t]);
            }
            // Linear terms after the quadratic ones, per component (the order of the table).
            let lin_c: &[T; NL] = self.lin_c[..].try_into().expect("one per term");
            let last = &series[n];
            for t in 0..NL {
                out[LINEAR_TERMS[t].k].mul_add_assign(&lin_c[t], &last[LINEAR_TERMS[t].term.i]);
            }
        } else {
            let (e, o) = (&mut even[..1], &mut odd[..1]);
            let e: &mut [T; 1] = e.try_into().expect("one slot");
            let o: &mut [T; 1] = o.try_into().expect("one slot");
            for &(ref c, i, j, k) in &self.quad {
                let left: Vec<[T; 1]> = series.iter().map(|r| [r[i].clone()]).collect();
                let right: Vec<[T; 1]> = series.iter().map(|r| [r[j].clone()]).collect();
                cauchy_sums(&left, &right, n, e, o);
                out[k].mul_add_assign(c, &e[0]);
            }
            let last = &series[n];
            for &(ref c, i, k) in &self.lin {
                out[k].mul_add_assign(c, &last[i]);
            }
        }
        scratch.sums = Some((even, odd));
    }

    /// The Jacobian–vector product J(x)·v, from the table (one pass over the terms: the cost of
    /// about one right-hand-side evaluation).
    pub fn jacobian_vector_product(&self, x: &[T], v: &[T]) -> [T; DIM] {
        std::array::from_fn(|k| {
            let mut acc = x[0].zero_like();
            for t in &self.terms[k] {
                match t.j {
                    // ∂(c xᵢ xⱼ)·v = c (vᵢ xⱼ + xᵢ vⱼ)
                    Some(j) => {
                        acc += t.c.clone() * (v[t.i].clone() * &x[j] + x[t.i].clone() * &v[j])
                    }
                    None => acc += t.c.clone() * &v[t.i],
                }
            }
            acc
        })
    }

    /// The Jacobian ∂fₖ/∂xᵢ at x.
    pub fn jacobian(&self, x: &[T; DIM]) -> [[T; DIM]; DIM] {
        let zero = x[0].zero_like();
        let mut jac: [[T; DIM]; DIM] =
            std::array::from_fn(|_| std::array::from_fn(|_| zero.clone()));
        for (k, row) in jac.iter_mut().enumerate() {
            for t in &self.terms[k] {
                match t.j {
                    Some(j) => {
                        row[t.i] += t.c.clone() * &x[j];
                        row[j] += t.c.clone() * &x[t.i];
                    }
                    None => row[t.i] += t.c.clone(),
                }
            }
        }
        jac
    }
}

/// (xᵢxⱼ)ₙ = Σₘ xᵢ,ₘ xⱼ,ₙ₋ₘ for every quadratic term t at once, into `even`, from the
/// gathered factors (`left[m][t]` = x_{i(t),m}, `right[m][t]` = x_{j(t),m}, m = 0..=n; `odd`
/// is scratch). Even and odd m are summed apart and added at the end, exactly as in
/// [`VectorField::taylor_coefficient_into`] (so f64 results are bit-for-bit the same); each
/// step is an element-wise multiply-add of two contiguous rows.
#[inline(always)]
fn cauchy_sums<T: Real, const N: usize>(
    left: &[[T; N]],
    right: &[[T; N]],
    n: usize,
    even: &mut [T; N],
    odd: &mut [T; N],
) {
    let (left, right) = (&left[..=n], &right[..=n]);
    for (e, o) in even.iter_mut().zip(odd.iter_mut()) {
        *e = e.zero_like();
        *o = o.zero_like();
    }
    let mut m = 0;
    while m < n {
        let (a0, b0) = (&left[m], &right[n - m]);
        let (a1, b1) = (&left[m + 1], &right[n - m - 1]);
        for t in 0..N {
            even[t].mul_add_assign(&a0[t], &b0[t]);
            odd[t].mul_add_assign(&a1[t], &b1[t]);
        }
        m += 2;
    }
    if m == n {
        let (a, b) = (&left[n], &right[0]);
        for (t, e) in even.iter_mut().enumerate() {
            e.mul_add_assign(&a[t], &b[t]);
        }
    }
    if n >= 1 {
        for (e, o) in even.iter_mut().zip(odd.iter()) {
            *e += o;
        }
    }
}
