//! Floors and regimes judged against the round-off (issue 33, item 1), with integrators of our
//! own: Runge–Kutta tableaux in f64 run through [`FixedStepIntegrator`], explicit or implicit
//! (stages by fixed-point iteration stopped at a residual, as a Newton iteration with a
//! tolerance stops).

use super::*;
use rsts_dynamics::equations::VectorField;
use rsts_dynamics::integrators::Stats;
use rsts_dynamics::state::{State, DIM};

/// A Runge–Kutta method by its Butcher tableau (a full matrix: implicit when a row reaches the
/// diagonal), in f64; implicit stages iterate until no stage derivative moves by more than
/// `stop`.
struct Tableau {
    name: &'static str,
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
    stop: f64,
}

impl Tableau {
    /// The classical RK4 with `db` added to the weight of k2 and `-dc` to... (see the callers).
    fn rk4(name: &'static str, b: [f64; 4]) -> Self {
        Tableau {
            name,
            a: vec![
                vec![0.0; 4],
                vec![0.5, 0.0, 0.0, 0.0],
                vec![0.0, 0.5, 0.0, 0.0],
                vec![0.0, 0.0, 1.0, 0.0],
            ],
            b: b.to_vec(),
            stop: 0.0,
        }
    }

    /// Two-stage Gauss–Legendre (order 4) with its stages solved to a residual `stop`.
    fn gauss4(stop: f64) -> Self {
        let r = 3f64.sqrt() / 6.0;
        Tableau {
            name: "gl4",
            a: vec![vec![0.25, 0.25 - r], vec![0.25 + r, 0.25]],
            b: vec![0.5, 0.5],
            stop,
        }
    }

    fn step(&self, f: &VectorField<f64>, y: &[f64; DIM], h: f64) -> [f64; DIM] {
        let s = self.b.len();
        let stage = |k: &[[f64; DIM]], i: usize| -> [f64; DIM] {
            std::array::from_fn(|c| y[c] + h * (0..s).map(|j| self.a[i][j] * k[j][c]).sum::<f64>())
        };
        let mut k = vec![[0.0; DIM]; s];
        let implicit = (0..s).any(|i| (i..s).any(|j| self.a[i][j] != 0.0));
        if implicit {
            let f0 = f.eval(y);
            k.iter_mut().for_each(|ki| *ki = f0);
            for _ in 0..200 {
                let next: Vec<[f64; DIM]> = (0..s).map(|i| f.eval(&stage(&k, i))).collect();
                let residual = next
                    .iter()
                    .zip(&k)
                    .flat_map(|(n, o)| n.iter().zip(o).map(|(x, y)| (x - y).abs()))
                    .fold(0.0, f64::max);
                // Stopped as a Newton iteration stops: the stages whose residual is small
                // enough are kept, not improved once more.
                if residual <= self.stop {
                    break;
                }
                k = next;
            }
        } else {
            for i in 0..s {
                k[i] = f.eval(&stage(&k, i));
            }
        }
        std::array::from_fn(|c| y[c] + h * (0..s).map(|j| self.b[j] * k[j][c]).sum::<f64>())
    }
}

impl FixedStepIntegrator for Tableau {
    fn name(&self) -> String {
        self.name.into()
    }
    fn working_bits(&self) -> u32 {
        53
    }
    fn integrate_at(
        &mut self,
        step: f64,
        problem: &Problem<Float>,
        times: &[f64],
    ) -> Result<Trajectory, HarnessError> {
        let bits = problem.initial.omega[0].prec();
        let p = map_problem(problem, |x| x.to_f64());
        let f = VectorField::new(&p.fields);
        let mut y = p.initial.to_array();
        let mut states = vec![problem.initial.clone()];
        let mut steps = 0;
        for w in times.windows(2) {
            let n = ((w[1] - w[0]) / step).round().max(1.0);
            let h = (w[1] - w[0]) / n;
            for _ in 0..n as u64 {
                y = self.step(&f, &y, h);
                steps += 1;
            }
            states.push(State::from_slice(&y).map(|x| Float::with_val(bits, x)));
        }
        Ok(Trajectory {
            times: times.to_vec(),
            states,
            stats: Stats {
                accepted_steps: steps,
                rhs_evals: steps * self.b.len() as u64,
                ..Stats::default()
            },
            wall_seconds: None,
        })
    }
}

fn case(t_end: f64, samples: usize) -> Case {
    let mut c = Case::default_i_plus();
    c.t_end = rsts_closed_form::Decimal::from_f64(t_end).unwrap();
    c.samples = samples;
    c
}

fn fit_of(method: &mut dyn FixedStepIntegrator, steps: &[f64]) -> (OrderFit, Vec<ConvergenceRow>) {
    let plan = ConvergencePlan::new(case(10.0, 11), steps).unwrap();
    let report = convergence(&plan, &mut [method]).unwrap();
    (report.fits[0].clone(), report.rows)
}

fn show(fit: &OrderFit, rows: &[ConvergenceRow]) -> String {
    let rows: Vec<String> = rows
        .iter()
        .map(|r| format!("h {:.3e} e {:.3e}", r.step, r.max_error))
        .collect();
    format!("{}\n{}\n{fit:#?}", fit.describe(), rows.join("\n"))
}

const SIXTH: f64 = 1.0 / 6.0;
const THIRD: f64 = 1.0 / 3.0;

/// RK4 with the weight of k2 off by 4e-10 (Σbᵢ = 1 + 4e-10: an error 4e-10·|f|·t that no step
/// removes): the error falls as h⁴, then stops near 4e-9, thousands of times the round-off
/// f64 allows after those steps. It is a floor above round-off, said so, and a doubt for
/// `--strict`; no step is called "round-off floor". (Before issue 33 those steps were all
/// "round-off floor: the error stops falling".)
#[test]
fn a_wrong_weight_is_a_floor_above_round_off() {
    let mut m = Tableau::rk4("rk4-w", [SIXTH, THIRD + 4e-10, THIRD, SIXTH]);
    let (fit, rows) = fit_of(&mut m, &halvings(0.5, 12));
    let floor = fit.floor.expect("a floor");
    assert_eq!(
        floor.kind,
        FloorKind::AboveRoundOff,
        "{}",
        show(&fit, &rows)
    );
    assert!(
        floor.error > 1e3 * floor.expected_round_off,
        "{}",
        show(&fit, &rows)
    );
    assert!((fit.order - 4.0).abs() < 0.1, "{}", show(&fit, &rows));
    assert!(
        fit.excluded
            .iter()
            .all(|e| e.kind != ExcludedKind::RoundOffFloor && !e.why.contains("round-off floor")),
        "{}",
        show(&fit, &rows)
    );
    // A flat floor, not noise: its steps are "floor above round-off".
    assert!(
        fit.excluded.iter().all(|e| e.kind != ExcludedKind::Noise)
            && fit
                .excluded
                .iter()
                .any(|e| e.kind == ExcludedKind::FloorAboveRoundOff),
        "{}",
        show(&fit, &rows)
    );
    let doubts = fit.doubts();
    assert!(
        doubts.len() == 1 && doubts[0].contains("above round-off"),
        "{doubts:?}"
    );
    assert!(
        fit.describe().contains("above round-off"),
        "{}",
        fit.describe()
    );
}

/// Two-stage Gauss–Legendre whose stage iteration stops at a residual of 1e-10 (as the
/// `differential-equations` crate's Newton iteration does): the error falls as h⁴ to ~1e-9,
/// then wanders between ~2e-12 and ~1e-10 as the step halves. The wandering is noise and a
/// floor above round-off; a run of three points inside it that happens to fall is not a
/// regime (it does not get a decade below the errors above it).
#[test]
fn a_stopped_newton_iteration_is_noise_above_round_off() {
    let mut m = Tableau::gauss4(1e-10);
    let (fit, rows) = fit_of(&mut m, &halvings(0.5, 12));
    let floor = fit.floor.expect("a floor");
    assert_eq!(
        floor.kind,
        FloorKind::AboveRoundOff,
        "{}",
        show(&fit, &rows)
    );
    assert_eq!(fit.regimes.len(), 1, "{}", show(&fit, &rows));
    assert!((fit.order - 4.0).abs() < 0.1, "{}", show(&fit, &rows));
    assert!(!fit.competing, "{}", show(&fit, &rows));
    assert!(
        fit.excluded.iter().any(|e| e.kind == ExcludedKind::Noise),
        "{}",
        show(&fit, &rows)
    );
    assert!(
        fit.excluded
            .iter()
            .all(|e| e.kind != ExcludedKind::PreAsymptotic && e.kind != ExcludedKind::RoundOffFloor),
        "{}",
        show(&fit, &rows)
    );
    assert!(!fit.doubts().is_empty());
}

/// RK4 with weights 1/3 ± 4e-5 on k2 and k3: orders 1 and 2 hold, the order-3 condition
/// Σbᵢaᵢⱼcⱼ = 1/6 is off by 1e-5. The error is C₄h⁴ + C₂·1e-5·h²: order 4 at large steps, then
/// order 2. Both regimes are reported, the asymptotic order is 2, and they do not compete
/// (the error falls all the way). The order-2 regime is the coefficient's: with the condition
/// off by half as much, its errors halve.
#[test]
fn a_nearly_satisfied_order_condition_is_a_second_regime() {
    let steps = halvings(0.5, 13);
    let near = |d: f64| Tableau::rk4("rk4-near", [SIXTH, THIRD + d, THIRD - d, SIXTH]);
    let (fit, rows) = fit_of(&mut near(4e-5), &steps);
    assert_eq!(fit.regimes.len(), 2, "{}", show(&fit, &rows));
    assert!(
        (fit.regimes[0].order - 4.0).abs() < 0.2,
        "{}",
        show(&fit, &rows)
    );
    assert!(
        (fit.regimes[1].order - 2.0).abs() < 0.1,
        "{}",
        show(&fit, &rows)
    );
    assert_eq!(fit.order, fit.regimes[1].order);
    assert!(
        !fit.competing && fit.doubts().is_empty(),
        "{}",
        show(&fit, &rows)
    );
    let text = fit.describe();
    assert!(
        text.contains("then order 1.98")
            || text.contains("then order 1.99")
            || text.contains("then order 2.0"),
        "{text}"
    );
    assert!(text.contains("order condition nearly satisfied"), "{text}");
    let (_, half) = fit_of(&mut near(2e-5), &steps);
    let (e1, e2) = (
        rows.last().unwrap().max_error,
        half.last().unwrap().max_error,
    );
    assert!((e1 / e2 - 2.0).abs() < 0.1, "{e1:e} {e2:e}");
}

/// The built-in rk4 and dopri5 swept into their floors: the floors are round-off, no doubt.
#[test]
fn plain_methods_reach_a_round_off_floor() {
    for (method, steps, p) in [
        (MethodName::Rk4, halvings(0.5, 13), 4.0),
        (MethodName::Dopri5, halvings(0.5, 10), 5.0),
    ] {
        let mut m = FixedStepMethod::new(method, None, 50).unwrap();
        let (fit, rows) = fit_of(&mut m, &steps);
        let floor = fit.floor.expect("a floor");
        assert_eq!(floor.kind, FloorKind::RoundOff, "{}", show(&fit, &rows));
        assert!((fit.order - p).abs() < 0.15, "{}", show(&fit, &rows));
        assert!(fit.doubts().is_empty(), "{}", show(&fit, &rows));
        assert!(
            fit.excluded
                .iter()
                .any(|e| e.kind == ExcludedKind::RoundOffFloor),
            "{}",
            show(&fit, &rows)
        );
    }
}

/// Synthetic sweeps (round-off 1e-16 everywhere): an error that grows as the step halves above
/// the window is noise, not pre-asymptotic; an order-4 line, a jump up, then an order-2 line
/// falling decades below: two windows that compete, said so and a doubt.
#[test]
fn noise_and_competing_windows_are_said() {
    let steps = halvings(0.5, 10);
    let r = vec![1e-16; steps.len()];
    // 0.5 and 0.25: the error grows as the step halves, then C·h⁴.
    let mut errors: Vec<f64> = steps.iter().map(|h| 1e-3 * h.powi(4)).collect();
    errors[0] = 1e-6;
    errors[1] = 5e-6;
    let fit = fit_order(&steps, &errors, &r).unwrap();
    let kind = |h: f64| fit.excluded.iter().find(|e| e.step == h).map(|e| e.kind);
    assert_eq!(kind(0.5), Some(ExcludedKind::Noise), "{fit:#?}");
    assert!((fit.order - 4.0).abs() < 1e-9, "{fit:#?}");
    // h⁴ over 0.5 ... 0.0625, a jump up at 0.03125, then 1e-3·h² falling far below.
    let errors: Vec<f64> = steps
        .iter()
        .map(|&h| {
            if h > 0.05 {
                1e-3 * h.powi(4)
            } else {
                1e-3 * h * h
            }
        })
        .collect();
    let fit = fit_order(&steps, &errors, &r).unwrap();
    assert_eq!(fit.regimes.len(), 2, "{fit:#?}");
    assert!(fit.competing, "{fit:#?}");
    assert!(fit.describe().contains("compete"), "{}", fit.describe());
    assert!(fit.doubts().iter().any(|d| d.contains("compete")));
    // Fewer than 3 points: no order, the reason given.
    let e = fit_order(&steps[..2], &errors[..2], &r[..2]).unwrap_err();
    assert!(e.contains("at least 3 steps"), "{e}");
}
