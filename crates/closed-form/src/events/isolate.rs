//! Certified isolation of the zeros of a smooth function g on a window (t₀, t₁], given bounds
//! |g″| ≤ M₂ and |g‴| ≤ M₃ on the whole window, and refinement by safeguarded Newton steps.
//!
//! The window is cut into a grid of spacing h₀ and every cell [tₐ, t_b] (width h) is classified
//! from the values g, g′, g″ at its ends; cells that cannot be classified are halved:
//!
//! * **monotone** — g′ keeps its sign: g′(t) ≥ g′ₐ − M₂(t − tₐ) and ≥ g′_b − M₂(t_b − t), and
//!   the larger of the two lines is positive on the cell iff |g′ₐ| + |g′_b| > M₂h (both of one
//!   sign). Then g has a zero iff its end values differ in sign, and exactly one.
//! * **no zero** — ends of one sign with min(|gₐ|, |g_b|) > M₂h²/8 (the chord's error bound).
//! * **convex or concave** — g″ keeps its sign (the same test with M₃): g′ has at most one zero
//!   t*, found by Newton steps on g′; g is monotone on [tₐ, t*] and [t*, t_b], so there is one
//!   zero on each side whose end values differ in sign from g(t*). When |g(t*)| ≤ `tol` the two
//!   zeros coincide to the precision asked: one **tangency** (a double root) at t*, reported
//!   once.
//!
//! A root is then never missed and never counted twice: each is inside exactly one cell that
//! proves it. A root at a cell's end is attributed to the cell on its left (its sign is read from
//! g′ there), so a zero at t₀ is outside the window and one at t₁ inside.

use rug::Float;

/// g, g′ and g″ at one time.
#[derive(Clone, Debug)]
pub struct Jet {
    pub g: Float,
    pub d: Float,
    pub c: Float,
}

/// How g passes through zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// From negative to positive.
    Up,
    /// From positive to negative.
    Down,
    /// Touches zero (a double root to the precision asked).
    Tangent,
}

/// A zero of g.
#[derive(Clone, Debug)]
pub struct Zero {
    pub t: Float,
    pub kind: Kind,
}

/// What the isolation needs to know about g on the window.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Initial grid spacing.
    pub h0: f64,
    /// Bound on |g″|.
    pub m2: f64,
    /// Bound on |g‴|.
    pub m3: f64,
    /// Largest number of grid cells.
    pub max_cells: usize,
}

fn sign(x: &Float) -> i32 {
    if x.is_zero() {
        0
    } else if x.is_sign_negative() {
        -1
    } else {
        1
    }
}

/// The sign of g just right of a point (left end of a cell).
fn sign_after(j: &Jet) -> i32 {
    [&j.g, &j.d, &j.c]
        .into_iter()
        .map(sign)
        .find(|&s| s != 0)
        .unwrap_or(0)
}

/// The sign of g just left of a point (right end of a cell).
fn sign_before(j: &Jet) -> i32 {
    match (sign(&j.g), sign(&j.d)) {
        (0, 0) => sign(&j.c),
        (0, d) => -d,
        (g, _) => g,
    }
}

/// Whether a quantity with end values `x`, `y` and derivative bound `m` keeps one strict sign on
/// a cell of width `h`.
fn keeps_sign(x: &Float, y: &Float, m: f64, h: f64) -> bool {
    let (sx, sy) = (sign(x), sign(y));
    sx != 0 && sx == sy && x.to_f64().abs() + y.to_f64().abs() > m * h * (1.0 + 1e-9)
}

/// Zeros of g in (t₀, t₁], in time order. `f` evaluates g, g′, g″ at the working precision;
/// `tol` is the |g| below which an extremum is a tangency. Errors when the window needs more than
/// `max_cells` grid cells.
pub fn zeros(
    f: &mut dyn FnMut(&Float) -> Jet,
    t0: &Float,
    t1: &Float,
    settings: Settings,
    tol: &Float,
) -> Result<Vec<Zero>, String> {
    let n = grid_cells(t0, t1, settings)?;
    Ok(zeros_in_cells(f, t0, t1, n, 0..n, settings, tol))
}

/// The cells of the grid on (t₀, t₁]: ⌈(t₁ − t₀)/h₀⌉ (0 for an empty window); an error when
/// more than `max_cells`.
pub fn grid_cells(t0: &Float, t1: &Float, settings: Settings) -> Result<u32, String> {
    let bits = t0.prec();
    let width = Float::with_val(bits, t1 - t0).to_f64();
    if width.is_nan() || width <= 0.0 {
        return Ok(0);
    }
    let cells = (width / settings.h0).ceil().max(1.0);
    if cells.is_nan() || cells > settings.max_cells as f64 {
        return Err(format!(
            "the window needs {cells:e} grid cells of {:e}, more than {}",
            settings.h0, settings.max_cells
        ));
    }
    Ok(cells as u32)
}

/// Point `k` of the grid of `n` cells on [t₀, t₁] (t₀ for 0, t₁ for n): the same number
/// whichever part of the grid is asked for.
pub fn grid_point(t0: &Float, t1: &Float, n: u32, k: u32) -> Float {
    match k {
        0 => t0.clone(),
        k if k == n => t1.clone(),
        k => Float::with_val(t0.prec(), t1 - t0) * k / n + t0,
    }
}

/// The zeros of g in the cells `cells` (cell c is (point c, point c + 1], numbered from 0) of
/// the grid of `n` cells on (t₀, t₁], in time order: the zeros [`zeros`] finds in those cells,
/// the same numbers (each cell is settled from its own ends), so that a long window can be done
/// a part at a time.
pub fn zeros_in_cells(
    f: &mut dyn FnMut(&Float) -> Jet,
    t0: &Float,
    t1: &Float,
    n: u32,
    cells: std::ops::Range<u32>,
    settings: Settings,
    tol: &Float,
) -> Vec<Zero> {
    let end = cells.end.min(n);
    if cells.start >= end {
        return Vec::new();
    }
    let mut found = Vec::new();
    let start = grid_point(t0, t1, n, cells.start);
    let mut left = (start.clone(), f(&start));
    for c in cells.start..end {
        let t = grid_point(t0, t1, n, c + 1);
        let right = (t.clone(), f(&t));
        let mut stack = vec![(left.clone(), right.clone())];
        while let Some((a, b)) = stack.pop() {
            if let Some(mid) = classify(f, &a, &b, settings, tol, &mut found) {
                stack.push((mid.clone(), b));
                stack.push((a, mid));
            }
        }
        left = right;
    }
    found.sort_by(|p: &Zero, q: &Zero| p.t.partial_cmp(&q.t).unwrap_or(std::cmp::Ordering::Equal));
    found
}

type Point = (Float, Jet);

/// Settle one cell (pushing its zeros) or return its midpoint to halve it.
fn classify(
    f: &mut dyn FnMut(&Float) -> Jet,
    (ta, ja): &Point,
    (tb, jb): &Point,
    s: Settings,
    tol: &Float,
    found: &mut Vec<Zero>,
) -> Option<Point> {
    let bits = ta.prec();
    let h = Float::with_val(bits, tb - ta).to_f64();
    let (sa, sb) = (sign_after(ja), sign_before(jb));
    let push_root = |found: &mut Vec<Zero>, f: &mut dyn FnMut(&Float) -> Jet| {
        let t = refine(f, Which::G, ta, tb, sa);
        found.push(Zero {
            t,
            kind: if sb > sa { Kind::Up } else { Kind::Down },
        });
    };
    if keeps_sign(&ja.d, &jb.d, s.m2, h) {
        if sa != sb {
            push_root(found, f);
        }
        return None;
    }
    if sa == sb && sa != 0 {
        let least = ja.g.to_f64().abs().min(jb.g.to_f64().abs());
        if least > s.m2 * h * h / 8.0 * (1.0 + 1e-9) {
            return None;
        }
    }
    let scale = Float::with_val(bits, ta.abs_ref()).max(&Float::with_val(bits, 1u32));
    let tiny = Float::with_val(bits, tb - ta) <= scale >> (bits - 8);
    let convex = keeps_sign(&ja.c, &jb.c, s.m3, h);
    if convex && sign(&ja.d) == sign(&jb.d) && sign(&ja.d) != 0 {
        // g′ is monotone and of one sign at both ends: g is monotone.
        if sa != sb {
            push_root(found, f);
        }
        return None;
    }
    if convex {
        // One extremum t* inside: g′ changes sign once.
        let da = if sign(&ja.d) == 0 {
            -sign(&jb.d)
        } else {
            sign(&ja.d)
        };
        let t_star = refine(f, Which::D, ta, tb, da);
        let js = f(&t_star);
        if Float::with_val(bits, js.g.abs_ref()) <= *tol {
            if sa == sb {
                found.push(Zero {
                    t: t_star,
                    kind: Kind::Tangent,
                });
            } else {
                push_root(found, f);
            }
            return None;
        }
        let ss = sign(&js.g);
        if ss != sa {
            let t = refine(f, Which::G, ta, &t_star, sa);
            found.push(Zero {
                t,
                kind: if ss > sa { Kind::Up } else { Kind::Down },
            });
        }
        if ss != sb {
            let t = refine(f, Which::G, &t_star, tb, ss);
            found.push(Zero {
                t,
                kind: if sb > ss { Kind::Up } else { Kind::Down },
            });
        }
        return None;
    }
    if tiny {
        // Not provable at this width (a zero of g′ and g″ together): a sign change is one root.
        if sa != sb {
            push_root(found, f);
        }
        return None;
    }
    let mid = Float::with_val(bits, ta + tb) / 2u32;
    let jm = f(&mid);
    Some((mid, jm))
}

#[derive(Clone, Copy)]
enum Which {
    /// A zero of g (Newton with g′).
    G,
    /// A zero of g′ (Newton with g″).
    D,
}

/// The zero in [a, b] of g (or g′) whose sign just right of a is `sa` and changes once: Newton
/// steps kept inside the bracket (halving it when a step leaves it), to the last bit.
fn refine(f: &mut dyn FnMut(&Float) -> Jet, which: Which, a: &Float, b: &Float, sa: i32) -> Float {
    let bits = a.prec();
    let (mut lo, mut hi) = (a.clone(), b.clone());
    let pick = |j: Jet| match which {
        Which::G => (j.g, j.d),
        Which::D => (j.d, j.c),
    };
    let mut t = Float::with_val(bits, &lo + &hi) / 2u32;
    for _ in 0..4 * bits + 64 {
        let (v, dv) = pick(f(&t));
        let s = sign(&v);
        if s == 0 {
            return t;
        }
        if s == sa {
            lo = t.clone();
        } else {
            hi = t.clone();
        }
        let newton = Float::with_val(bits, &t - Float::with_val(bits, &v / &dv));
        let next = if newton.is_finite() && newton > lo && newton < hi {
            newton
        } else {
            Float::with_val(bits, &lo + &hi) / 2u32
        };
        let step = Float::with_val(bits, &next - &t).abs();
        let scale = Float::with_val(bits, t.abs_ref()).max(&Float::with_val(bits, 1u32));
        t = next;
        if step <= scale.clone() >> (bits - 2)
            || Float::with_val(bits, &hi - &lo) <= scale >> (bits - 1)
        {
            break;
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    const BITS: u32 = 200;

    fn fl(x: f64) -> Float {
        Float::with_val(BITS, x)
    }

    /// g = (t − 1)² − δ: two roots 1 ± √δ, a tangency at 1 for δ = 0.
    fn parabola(delta: &Float) -> impl FnMut(&Float) -> Jet + '_ {
        move |t: &Float| {
            let u = Float::with_val(BITS, t - 1u32);
            Jet {
                g: Float::with_val(BITS, u.square_ref()) - delta,
                d: u * 2u32,
                c: fl(2.0),
            }
        }
    }

    fn settings() -> Settings {
        Settings {
            h0: 0.7,
            m2: 2.0,
            m3: 0.0,
            max_cells: 1000,
        }
    }

    #[test]
    fn near_tangent_crossings_are_two_and_a_tangency_one() {
        let tol = fl(1e-50);
        for (delta, expect) in [(1e-40, 2), (1e-60, 1), (0.0, 1), (-1e-40, 0)] {
            let d = fl(delta);
            let z = zeros(&mut parabola(&d), &fl(0.0), &fl(3.0), settings(), &tol).unwrap();
            assert_eq!(z.len(), expect, "delta {delta}: {z:?}");
            if expect == 2 {
                let r = Float::with_val(BITS, d.sqrt_ref());
                let e0 = Float::with_val(BITS, &z[0].t - (fl(1.0) - &r))
                    .abs()
                    .to_f64();
                let e1 = Float::with_val(BITS, &z[1].t - (fl(1.0) + &r))
                    .abs()
                    .to_f64();
                assert!(e0 < 1e-55 && e1 < 1e-55, "{e0:e} {e1:e}");
                assert_eq!((z[0].kind, z[1].kind), (Kind::Down, Kind::Up));
            }
            if expect == 1 {
                assert_eq!(z[0].kind, Kind::Tangent);
                assert!(Float::with_val(BITS, &z[0].t - 1u32).abs().to_f64() < 1e-25);
            }
        }
    }

    /// A window done a few cells at a time gives the zeros of the whole window, bit for bit.
    #[test]
    fn parts_of_the_grid_give_the_same_zeros() {
        let mut sine = |t: &Float| Jet {
            g: Float::with_val(BITS, t.sin_ref()),
            d: Float::with_val(BITS, t.cos_ref()),
            c: -Float::with_val(BITS, t.sin_ref()),
        };
        let s = Settings {
            h0: 0.3,
            m2: 1.0,
            m3: 1.0,
            max_cells: 1000,
        };
        let (t0, t1) = (fl(-0.1), fl(40.0));
        let whole = zeros(&mut sine, &t0, &t1, s, &fl(1e-50)).unwrap();
        assert_eq!(whole.len(), 13, "0, π, …, 12π");
        let n = grid_cells(&t0, &t1, s).unwrap();
        for part in [1, 7, 64] {
            let mut pieces = Vec::new();
            let mut c = 0;
            while c < n {
                pieces.extend(zeros_in_cells(
                    &mut sine,
                    &t0,
                    &t1,
                    n,
                    c..c + part,
                    s,
                    &fl(1e-50),
                ));
                c += part;
            }
            let same = pieces.len() == whole.len()
                && pieces
                    .iter()
                    .zip(&whole)
                    .all(|(p, w)| p.t == w.t && p.kind == w.kind);
            assert!(same, "{part} cells at a time: {pieces:?}");
        }
    }

    #[test]
    fn sine_roots_are_exact_and_a_root_at_the_start_is_outside() {
        let mut sine = |t: &Float| Jet {
            g: Float::with_val(BITS, t.sin_ref()),
            d: Float::with_val(BITS, t.cos_ref()),
            c: -Float::with_val(BITS, t.sin_ref()),
        };
        let s = Settings {
            h0: 2.5,
            m2: 1.0,
            m3: 1.0,
            max_cells: 1000,
        };
        let pi = Float::with_val(BITS, rug::float::Constant::Pi);
        let end = Float::with_val(BITS, &pi * 3u32);
        let z = zeros(&mut sine, &fl(0.0), &end, s, &fl(1e-50)).unwrap();
        assert_eq!(z.len(), 3, "{z:?}");
        for (k, zero) in z.iter().enumerate() {
            let exact = Float::with_val(BITS, &pi * (k as u32 + 1));
            assert!(Float::with_val(BITS, &zero.t - &exact).abs().to_f64() < 1e-55);
            let kind = if k % 2 == 0 { Kind::Down } else { Kind::Up };
            assert_eq!(zero.kind, kind);
        }
    }
}
