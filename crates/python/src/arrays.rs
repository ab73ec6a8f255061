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
/// an array of real numbers (lists, tuples), handed to `read` as its shape and its values in
/// row-major order (a float64 array is read where it is, not copied first). `what` names the
/// argument in errors.
fn float_array<R>(
    obj: &Bound<'_, PyAny>,
    what: &str,
    read: impl FnOnce(&[usize], &mut dyn Iterator<Item = f64>) -> PyResult<R>,
) -> PyResult<R> {
    let arr = float64(obj, what)?;
    let ro = arr.readonly();
    let view = ro.as_array();
    read(view.shape(), &mut view.iter().copied())
}

/// `obj` as a float64 numpy array (itself when it is one).
fn float64<'py>(obj: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
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
    let kwargs = pyo3::types::PyDict::new(py);
    kwargs.set_item("copy", false)?;
    let arr = arr.call_method("astype", ("float64",), Some(&kwargs))?;
    arr.cast_into::<PyArrayDyn<f64>>().map_err(PyErr::from)
}

/// Rows of states, shape (`rows`, 9), read a chunk at a time where they are by the flow of
/// `rsts.check` ([`rsts_flows::check::StateRows`]): a float64 array is not copied whole (a list
/// is made one first). The flow checks the values.
pub(crate) struct NumpyRows {
    array: Py<PyArrayDyn<f64>>,
    rows: usize,
}

/// `obj` as [`NumpyRows`] of shape (`rows`, 9), or ValueError naming `what`.
pub(crate) fn state_rows(obj: &Bound<'_, PyAny>, what: &str, rows: usize) -> PyResult<NumpyRows> {
    let array = float64(obj, what)?;
    let shape = array.shape().to_vec();
    if shape.len() != 2 || shape[1] != 9 || shape[0] != rows {
        return Err(PyValueError::new_err(format!(
            "{what}: expected shape ({rows}, 9) (one row of omega, alpha, beta per time), got shape {shape:?}"
        )));
    }
    Ok(NumpyRows {
        array: array.unbind(),
        rows,
    })
}

impl rsts_flows::check::StateRows for NumpyRows {
    fn rows(&self) -> usize {
        self.rows
    }

    fn read(&mut self, start: usize, out: &mut [[f64; 9]]) -> Result<(), rsts_flows::FlowError> {
        Python::attach(|py| {
            let array = self.array.bind(py).try_readonly().map_err(|e| {
                rsts_flows::FlowError::input(&["states"], format!("cannot read the array: {e}"))
            })?;
            let view = array.as_array();
            for (k, row) in out.iter_mut().enumerate() {
                for (c, x) in row.iter_mut().enumerate() {
                    *x = view[[start + k, c]];
                }
            }
            Ok(())
        })
    }
}

/// A 1-D array of finite numbers.
pub(crate) fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let (shape, values) = float_array(obj, what, |shape, values| {
        Ok((shape.to_vec(), values.collect::<Vec<f64>>()))
    })?;
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
    let (shape, values) = float_array(obj, what, |shape, values| {
        Ok((shape.to_vec(), values.collect::<Vec<f64>>()))
    })?;
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
    let want = match rows {
        Some(n) => format!("({n}, 9)"),
        None => "(N, 9)".into(),
    };
    // Copied once, row by row, from the array.
    let rows = float_array(obj, what, |shape, values| {
        if shape.len() != 2 || shape[1] != 9 || rows.is_some_and(|n| shape[0] != n) {
            return Err(PyValueError::new_err(format!(
                "{what}: expected shape {want} (one row of omega, alpha, beta per time), got shape {shape:?}"
            )));
        }
        let mut out: Vec<[f64; 9]> = Vec::with_capacity(shape[0]);
        for _ in 0..shape[0] {
            out.push(std::array::from_fn(|_| values.next().unwrap_or(f64::NAN)));
        }
        Ok(out)
    })?;
    // Refused as the CLI refuses a file's values: not finite, or beyond 1e8.
    if let Some(why) = rsts_flows::check::array_states_error(0, times.unwrap_or(&[]), &rows) {
        return Err(PyValueError::new_err(format!("{what}: {why}")));
    }
    Ok(rows)
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

/// Refuse more times than a run may have ([`rsts_flows::times::check_count`]) before they are
/// copied: `len(obj)` first (a list of 10⁸ times is not turned into 800 MB to be refused).
pub(crate) fn times_count(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<()> {
    if let Ok(n) = obj.len() {
        rsts_flows::times::check_count(n).map_err(|e| crate::value_error(&[what], e))?;
    }
    Ok(())
}
