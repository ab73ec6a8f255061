//! numpy in and out: arrays of times and states read with checks that name what was wrong
//! (never a crash, never a silent NaN), and results as float64 arrays.

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Names of the nine state components, in the order of a row: ω, α, β in the body frame.
pub(crate) const STATE_COLUMNS: [&str; 9] = [
    "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
];

/// What a value is, for messages: `list`, `NoneType`, `numpy.ndarray of shape (3, 9)`.
pub(crate) fn describe(obj: &Bound<'_, PyAny>) -> String {
    if let Ok(a) = obj.cast::<numpy::PyUntypedArray>() {
        return format!("a numpy array of shape {:?}", a.shape());
    }
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "an object".into())
}

/// `obj` as a float64 array of any shape: a numpy array or anything `numpy.asarray` turns into
/// an array of real numbers (lists, tuples). `what` names the argument in errors.
fn float_array<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<(Vec<usize>, Vec<f64>)> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let arr = np.call_method1("asarray", (obj,)).map_err(|e| {
        PyValueError::new_err(format!(
            "{what}: not an array of numbers ({}: {})",
            describe(obj),
            e.value(py)
        ))
    })?;
    let kind: String = arr.getattr("dtype")?.getattr("kind")?.extract()?;
    if !matches!(kind.as_str(), "i" | "u" | "f") {
        let dtype = arr.getattr("dtype")?.str()?.to_string();
        return Err(PyValueError::new_err(format!(
            "{what}: expected real numbers, got {} with dtype {dtype}",
            describe(obj)
        )));
    }
    let arr = arr.call_method1("astype", ("float64",))?;
    let arr = arr.cast::<PyArrayDyn<f64>>().map_err(PyErr::from)?;
    let ro = arr.readonly();
    let view = ro.as_array();
    Ok((view.shape().to_vec(), view.iter().copied().collect()))
}

/// A 1-D array of finite numbers.
pub(crate) fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let (shape, values) = float_array(obj, what)?;
    if shape.len() != 1 {
        return Err(PyValueError::new_err(format!(
            "{what}: expected a 1-D array, got shape {shape:?}"
        )));
    }
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{what}: element {k} is not a finite number ({})",
            values[k]
        )));
    }
    Ok(values)
}

/// One state (ω, α, β): 9 finite numbers.
pub(crate) fn state(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 9]> {
    let (shape, values) = float_array(obj, what)?;
    if shape != [9] {
        return Err(PyValueError::new_err(format!(
            "{what}: expected 9 numbers (omega, alpha, beta), got shape {shape:?}"
        )));
    }
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{what}: {} is not a finite number ({})",
            STATE_COLUMNS[k], values[k]
        )));
    }
    Ok(std::array::from_fn(|k| values[k]))
}

/// Rows of states, shape (rows, 9) (`rows`: the number required, if any), all finite; `times`
/// (when given) name the row's time in errors.
pub(crate) fn states(
    obj: &Bound<'_, PyAny>,
    what: &str,
    rows: Option<usize>,
    times: Option<&[f64]>,
) -> PyResult<Vec<[f64; 9]>> {
    let (shape, values) = float_array(obj, what)?;
    let want = match rows {
        Some(n) => format!("({n}, 9)"),
        None => "(N, 9)".into(),
    };
    if shape.len() != 2 || shape[1] != 9 || rows.is_some_and(|n| shape[0] != n) {
        return Err(PyValueError::new_err(format!(
            "{what}: expected shape {want} (one row of omega, alpha, beta per time), got shape {shape:?}"
        )));
    }
    if let Some(k) = values.iter().position(|x| !x.is_finite()) {
        let (row, col) = (k / 9, k % 9);
        let at = match times {
            Some(t) => format!(" (t = {})", t[row]),
            None => String::new(),
        };
        return Err(PyValueError::new_err(format!(
            "{what}: row {row}{at}, {}: not a finite number ({})",
            STATE_COLUMNS[col], values[k]
        )));
    }
    Ok(values
        .chunks_exact(9)
        .map(|c| std::array::from_fn(|k| c[k]))
        .collect())
}

/// A float64 array of shape (rows, cols) from row-major values.
pub(crate) fn matrix<'py>(
    py: Python<'py>,
    values: Vec<f64>,
    cols: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let rows = values.len() / cols;
    Ok(numpy::PyArray1::from_vec(py, values)
        .reshape([rows, cols])?
        .into_any())
}
