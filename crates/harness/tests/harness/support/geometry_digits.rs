//! One check shared by the harness's and the CLI's tests (included with `#[path]`).

use serde_json::Value;

/// `a` and `b` are the same report but for the last digits of the geometry's numbers
/// (`normal`, `phase_error`, `error_split`): the f64 path of `rsts check` starts each
/// projection from the sample before (a warm start), the MPFR path of the same samples from the
/// exact angles. |Δx| ≤ 1e-8·|x| + 1e-15; the growth fits' numbers to 1e-2 (a fit weighs the
/// samples at the round-off as much as the others: on a perturbation of 1e-12 it moves by
/// 1.4e-3), with the same model.
pub fn assert_same_but_the_geometrys_last_digits(a: &Value, b: &Value, what: &str) {
    fn close(a: &Value, b: &Value, at: &str) {
        match (a, b) {
            (Value::Number(x), Value::Number(y)) => {
                let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
                let rel = if at.contains("growth") { 1e-2 } else { 1e-8 };
                assert!(
                    (x - y).abs() <= rel * x.abs().max(y.abs()) + 1e-15,
                    "{at}: {x:e} against {y:e}"
                );
            }
            (Value::Object(x), Value::Object(y)) => {
                assert_eq!(x.len(), y.len(), "{at}");
                for (k, v) in x {
                    close(v, &y[k], &format!("{at}.{k}"));
                }
            }
            _ => assert_eq!(a, b, "{at}"),
        }
    }
    let (mut a, mut b) = (a.clone(), b.clone());
    for key in ["normal", "phase_error", "error_split"] {
        let (x, y) = (a[key].take(), b[key].take());
        close(&x, &y, &format!("{what}: {key}"));
    }
    assert_eq!(a, b, "{what}");
}
