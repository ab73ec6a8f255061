//! `rsts.Case`: a motion on N (a, b, m, h, torus, phases), checked as the CLI checks it, and its
//! exact reference at any times (`rsts reference`).

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyList;

use rsts_harness::reference::{check_digits, check_times, ReferenceTable};

use crate::arrays;
use crate::{harness_error, value_error, Interrupts};

/// A motion on the invariant manifold N: fields a > b > 0, the point (m, h) of N off Σ, the
/// Liouville torus (0-based) and the angles (psi1, psi2) on it at t = 0.
///
/// Checked as `rsts compare` checks its options: bad values raise ValueError with the CLI's
/// message, naming the arguments (`m/h: (m, h) lies on the bifurcation diagram Σ ...`).
/// Attributes: a, b, m, h, torus, phase1, phase2, camera (the paper's camera of (m, h), e.g.
/// "I+").
#[pyclass(module = "rsts", frozen, eq, from_py_object)]
#[derive(Clone, PartialEq)]
pub struct Case {
    /// Strength a of the first field.
    #[pyo3(get)]
    a: f64,
    /// Strength b of the second field.
    #[pyo3(get)]
    b: f64,
    /// Value m of the partial integral of N.
    #[pyo3(get)]
    m: f64,
    /// Energy h.
    #[pyo3(get)]
    h: f64,
    /// The Liouville torus (0-based).
    #[pyo3(get)]
    torus: usize,
    /// Angle psi1 on the torus at t = 0 (radians).
    #[pyo3(get)]
    phase1: f64,
    /// Angle psi2 on the torus at t = 0 (radians).
    #[pyo3(get)]
    phase2: f64,
    /// The camera of (m, h): I+, I-, II+, ..., VI.
    #[pyo3(get)]
    camera: String,
}

/// A whole number >= 0 (a torus, a count), or ValueError naming it.
pub(crate) fn whole(name: &str, x: i64) -> PyResult<usize> {
    usize::try_from(x).map_err(|_| value_error(&[name], format!("must be >= 0, got {x}")))
}

impl Case {
    /// The case given, else the README's (`Case.default()`).
    pub(crate) fn or_default(case: Option<Case>) -> PyResult<Self> {
        match case {
            Some(c) => Ok(c),
            None => Self::checked(rsts_harness::Case::default_i_plus()),
        }
    }

    /// Check a harness case (its a, b, m, h, torus, phases; the grid is the caller's).
    pub(crate) fn checked(case: rsts_harness::Case) -> PyResult<Self> {
        let case = rsts_harness::Case {
            t_end: 0.0,
            samples: 1,
            ..case
        };
        case.validate().map_err(harness_error)?;
        let (motion, _) = case.reference_motion(64).map_err(harness_error)?;
        let rsts_harness::Case {
            a,
            b,
            m,
            h,
            torus,
            phase1,
            phase2,
            ..
        } = case;
        Ok(Self {
            a,
            b,
            m,
            h,
            torus,
            phase1,
            phase2,
            camera: motion.camera.label().to_string(),
        })
    }

    /// The harness case on `samples` times evenly spaced on [0, t_end].
    pub(crate) fn on_grid(&self, t_end: f64, samples: usize) -> rsts_harness::Case {
        rsts_harness::Case {
            a: self.a,
            b: self.b,
            m: self.m,
            h: self.h,
            torus: self.torus,
            phase1: self.phase1,
            phase2: self.phase2,
            t_end,
            samples,
        }
    }
}

#[pymethods]
impl Case {
    #[new]
    #[pyo3(signature = (a, b, m, h, torus = 0, phase1 = 0.0, phase2 = 0.0))]
    fn new(a: f64, b: f64, m: f64, h: f64, torus: i64, phase1: f64, phase2: f64) -> PyResult<Self> {
        Self::checked(rsts_harness::Case {
            a,
            b,
            m,
            h,
            torus: whole("torus", torus)?,
            phase1,
            phase2,
            t_end: 0.0,
            samples: 1,
        })
    }

    /// The README's case: camera I+, a = 1, b = 0.5, m = 0.3, h = -0.375, torus 0, phases 0
    /// (the defaults of `rsts compare` and `rsts reference`).
    #[staticmethod]
    fn default() -> PyResult<Self> {
        Self::checked(rsts_harness::Case::default_i_plus())
    }

    fn __repr__(&self) -> String {
        let c = self;
        format!(
            "Case(a={:?}, b={:?}, m={:?}, h={:?}, torus={}, phase1={:?}, phase2={:?})",
            c.a, c.b, c.m, c.h, c.torus, c.phase1, c.phase2
        )
    }

    /// The exact motion at `times` (1-D, strictly increasing, any spacing): a float64 array of
    /// shape (len(times), 9), the rows (omega, alpha, beta) in the body frame, equal bit for bit
    /// to the columns omega1..beta3 of `rsts reference` at the same times (the closed form at
    /// 30 digits + 64 bits, rounded once to f64).
    ///
    /// With `digits` (18 to 10000): a list of len(times) lists of 9 decimal strings, each value
    /// carrying that many digits (as `rsts reference --digits D`).
    ///
    /// The GIL is released while the rows are computed; Ctrl-C raises KeyboardInterrupt.
    #[pyo3(signature = (times, digits = None))]
    fn reference<'py>(
        &self,
        py: Python<'py>,
        times: &Bound<'py, PyAny>,
        digits: Option<i64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let times = arrays::vector(times, "times")?;
        check_times(&times).map_err(|e| value_error(&["times"], e))?;
        let digits = check_digits(digits).map_err(|e| value_error(&["digits"], e))?;
        let case = self.on_grid(0.0, 1);
        let rows = py.detach(move || -> Result<Rows, RowsError> {
            let table = ReferenceTable::new(&case, &times, digits).map_err(RowsError::Case)?;
            let mut interrupts = Interrupts::new();
            let mut text = Vec::new();
            let mut values = Vec::new();
            for &t in &times {
                if interrupts.stopped() {
                    return Err(RowsError::Interrupted(interrupts.take()));
                }
                let row = table.row(t).map_err(RowsError::Row)?;
                let state = &row[1..10];
                if digits.is_some() {
                    text.push(state.iter().map(|x| table.text(x)).collect());
                } else {
                    values.extend(state.iter().map(|x| x.to_f64()));
                }
            }
            Ok(if digits.is_some() {
                Rows::Text(text)
            } else {
                Rows::Values(values)
            })
        });
        match rows {
            Err(RowsError::Case(e)) => Err(harness_error(e)),
            Err(RowsError::Row(e)) => Err(PyRuntimeError::new_err(e)),
            Err(RowsError::Interrupted(e)) => {
                Err(e.unwrap_or_else(|| PyRuntimeError::new_err("interrupted")))
            }
            Ok(Rows::Text(text)) => Ok(PyList::new(py, text)?.into_any()),
            Ok(Rows::Values(values)) => arrays::matrix(py, values, 9),
        }
    }
}

/// The rows of a reference: decimal strings (with digits) or f64 values, row-major.
enum Rows {
    Text(Vec<Vec<String>>),
    Values(Vec<f64>),
}

/// Why the rows of a reference could not be made.
enum RowsError {
    Case(rsts_harness::HarnessError),
    Row(String),
    Interrupted(Option<PyErr>),
}
