//! The lane layout of the SIMD Taylor kernels, derived from a table of equations (normally
//! [`EULER_POISSON`](crate::equations::EULER_POISSON); no second copy of the dynamics).
//!
//! Every component with at least one quadratic term gets a **lane** of an 8-wide vector (the
//! "Q" lanes); the terms of its right-hand side fill the **slots** of that lane in
//! [`ROWS`] rows. A slot is
//!
//! * a quadratic term c·p·xᵢxⱼ: left factor (c·p)·xᵢ, right factor xⱼ, whose Cauchy product
//!   (Σₘ xᵢ,ₘ xⱼ,ₙ₋ₘ) the kernel accumulates lane-wise; c = ±1, ±½ and p = 1 fold into the left
//!   factor exactly;
//! * a linear term c·p·xᵢ put into a free slot: left factor (c·p)·xᵢ, right factor the constant
//!   series 1 (1 at order 0, 0 after), so its "Cauchy product" is (c·p)·xᵢ,ₙ;
//! * empty (both factors 0).
//!
//! The coefficient f(x)ₙ of a Q component is then the sum over the rows of its lane. The
//! components without quadratic terms (ω₃ here: a α₂ − b β₁) are the "N" values, computed from
//! their linear terms in scalar code.
//!
//! A coefficient row xₙ is kept in lane form: the Q lanes (8) followed by the N values (at most
//! [`NMAX`]); [`Layout::pos`] gives the position of each component in it, and the factors of
//! the slots are lane permutations of it ([`PermSpec`]).
//!
//! For the Euler–Poisson table: Q = (ω₁, ω₂, α₁, α₂, α₃, β₁, β₂, β₃), two rows (the Poisson
//! equations have two terms per component; ω₁ and ω₂ have one quadratic and one linear term),
//! N = (ω₃). A table that does not fit (more than 8 Q components, more than [`ROWS`] terms in
//! one, more than [`NMAX`] − 1 N components) gets no layout and runs on the generic stepper.

use crate::equations::{Component, Param};
use crate::state::DIM;

/// Lanes of a row (one AVX-512 register, two AVX2 registers).
pub(crate) const LANES: usize = 8;
/// Slots per lane.
pub(crate) const ROWS: usize = 2;
/// Most components without quadratic terms, plus one: the last N lane is always zero (the
/// AVX2 path reads lanes without a source from it).
pub(crate) const NMAX: usize = 4;

/// A lane permutation: for each lane the position of its source in a coefficient row in lane
/// form (0..8: Q lanes, 8..8 + NMAX: N values), or `None` for a lane that is zero.
pub(crate) type PermSpec = [Option<usize>; LANES];

/// The right factor of a slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Right {
    /// No term in this slot.
    Empty,
    /// The series of component `i`.
    Component(usize),
    /// The constant series 1 (a linear term).
    One,
}

/// One slot of a lane: (c·param)·x_left · right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Slot {
    pub left: Option<usize>,
    pub c: f64,
    pub param: Param,
    pub right: Right,
}

const EMPTY: Slot = Slot {
    left: None,
    c: 0.0,
    param: Param::One,
    right: Right::Empty,
};

/// A linear term c·param·xᵢ of an N component (index into [`Layout::n`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NTerm {
    pub n: usize,
    pub c: f64,
    pub param: Param,
    pub i: usize,
}

/// The layout of one table (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Layout {
    /// The component of each Q lane (`None`: an unused lane, always zero).
    pub q: [Option<usize>; LANES],
    /// The N components (no quadratic term), in table order.
    pub n: Vec<usize>,
    /// `slots[r][lane]`.
    pub slots: [[Slot; LANES]; ROWS],
    /// The linear terms of the N components, in table order.
    pub n_terms: Vec<NTerm>,
    /// Position of each component in a row in lane form.
    pub pos: [usize; DIM],
}

impl Layout {
    /// The layout of `table`, or `None` when it does not fit the kernels' shape.
    pub fn from_table(table: &[Component; DIM]) -> Option<Self> {
        let mut q = [None; LANES];
        let mut n = Vec::new();
        let mut slots = [[EMPTY; LANES]; ROWS];
        let mut n_terms = Vec::new();
        let mut pos = [0; DIM];
        let mut lanes = 0;
        for (k, comp) in table.iter().enumerate() {
            if comp.quadratic.is_empty() {
                if n.len() + 1 == NMAX {
                    return None;
                }
                pos[k] = LANES + n.len();
                for t in comp.linear {
                    n_terms.push(NTerm {
                        n: n.len(),
                        c: t.c,
                        param: t.param,
                        i: t.i,
                    });
                }
                n.push(k);
                continue;
            }
            if lanes == LANES || comp.quadratic.len() + comp.linear.len() > ROWS {
                return None;
            }
            q[lanes] = Some(k);
            pos[k] = lanes;
            let quadratic = comp.quadratic.iter().map(|t| Slot {
                left: Some(t.i),
                c: t.c,
                param: t.param,
                right: Right::Component(t.j),
            });
            let linear = comp.linear.iter().map(|t| Slot {
                left: Some(t.i),
                c: t.c,
                param: t.param,
                right: Right::One,
            });
            for (r, slot) in quadratic.chain(linear).enumerate() {
                slots[r][lanes] = slot;
            }
            lanes += 1;
        }
        Some(Self {
            q,
            n,
            slots,
            n_terms,
            pos,
        })
    }

    /// The permutation that gathers the left factors of row `r` (before scaling by c·p).
    pub fn left_perm(&self, r: usize) -> PermSpec {
        std::array::from_fn(|lane| self.slots[r][lane].left.map(|i| self.pos[i]))
    }

    /// The permutation that gathers the right factors of row `r` (the constant series 1 and
    /// empty slots are zero here; [`Layout::unit_lanes`] adds the 1 at order 0).
    pub fn right_perm(&self, r: usize) -> PermSpec {
        std::array::from_fn(|lane| match self.slots[r][lane].right {
            Right::Component(i) => Some(self.pos[i]),
            Right::One | Right::Empty => None,
        })
    }

    /// 1.0 in the lanes of row `r` whose right factor is the constant series 1, else 0.
    pub fn unit_lanes(&self, r: usize) -> [f64; LANES] {
        std::array::from_fn(|lane| {
            if self.slots[r][lane].right == Right::One {
                1.0
            } else {
                0.0
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::equations::{idx::*, Linear, Quadratic, EULER_POISSON};

    #[test]
    fn euler_poisson_fills_eight_lanes_of_two_rows() {
        let l = Layout::from_table(&EULER_POISSON).expect("the table fits");
        assert_eq!(
            l.q,
            [W1, W2, A1, A2, A3, B1, B2, B3].map(Some),
            "Q lanes in table order"
        );
        assert_eq!(l.n, vec![W3]);
        assert_eq!(l.pos[W3], LANES);
        // ω̇₁ = ½ω₂ω₃ + ½bβ₃: the quadratic term in row 0, the linear one in row 1.
        let s = l.slots[0][0];
        assert_eq!(
            (s.left, s.c, s.right),
            (Some(W2), 0.5, Right::Component(W3))
        );
        let s = l.slots[1][0];
        assert_eq!((s.left, s.c, s.param), (Some(B3), 0.5, Param::B));
        assert_eq!(s.right, Right::One);
        // α̇₁ = α₂ω₃ − α₃ω₂ in lane 2.
        assert_eq!(l.slots[0][2].right, Right::Component(W3));
        assert_eq!((l.slots[1][2].left, l.slots[1][2].c), (Some(A3), -1.0));
        // Every term of the table is in exactly one slot or N term.
        let slots = l.slots.iter().flatten().filter(|s| s.right != Right::Empty);
        let terms: usize = EULER_POISSON
            .iter()
            .map(|c| c.quadratic.len() + c.linear.len())
            .sum();
        assert_eq!(slots.count() + l.n_terms.len(), terms);
        assert_eq!(l.unit_lanes(1)[0], 1.0);
        assert_eq!(l.unit_lanes(0), [0.0; LANES]);
        assert_eq!(l.right_perm(0)[3], Some(l.pos[W1]));
        assert_eq!(l.left_perm(1)[0], Some(l.pos[B3]));
    }

    #[test]
    fn tables_that_do_not_fit_get_no_layout() {
        static THREE: [Quadratic; 3] = [
            Quadratic {
                c: 1.0,
                param: Param::One,
                i: 0,
                j: 1,
            },
            Quadratic {
                c: 1.0,
                param: Param::One,
                i: 1,
                j: 2,
            },
            Quadratic {
                c: 1.0,
                param: Param::One,
                i: 2,
                j: 0,
            },
        ];
        let mut table = EULER_POISSON;
        table[3].quadratic = &THREE;
        assert!(Layout::from_table(&table).is_none());
        // A quadratic term for ω₃ too: nine Q components.
        static ONE: [Quadratic; 1] = [Quadratic {
            c: 1.0,
            param: Param::One,
            i: 0,
            j: 1,
        }];
        static NONE: [Linear; 0] = [];
        let mut table = EULER_POISSON;
        table[2].quadratic = &ONE;
        table[2].linear = &NONE;
        assert!(Layout::from_table(&table).is_none());
    }
}
