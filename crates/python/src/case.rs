//! `rsts.Case`: a motion on N (a, b, m, h, torus, phases), checked as the CLI checks it, and its
//! exact reference at any times (`rsts reference`).

use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt, PyList, PyString};
use rsts_closed_form::{Decimal, Motion};

use rsts_harness::reference::{check_digits, check_times, ReferenceTable};

use crate::arrays;
use crate::{harness_error, value_error, Interrupts};

/// A motion on the invariant manifold N: fields a > b > 0, the point (m, h) of N off Σ, the
/// Liouville torus (0-based) and the angles (psi1, psi2) on it at t = 0.
///
/// Numbers: a `str` is the decimal it holds, exactly (`Case("1.3", "0.7", "-0.52", "2.07")` is
/// the motion `rsts compare --a 1.3 …` means); a float is its exact binary value (`0.3` is
/// 0.299999999999999988897769753748434595763683319091796875); an int is that integer.
/// Checked as `rsts compare` checks its options: bad values raise ValueError with the CLI's
/// message, naming the arguments (`m/h: (m, h) lies on the bifurcation diagram Σ ...`).
/// Attributes: a, b, m, h, torus, phase1, phase2 (floats: the nearest f64), camera (the
/// paper's camera of (m, h), e.g. "I+"), decimals (the exact numbers as strings).
#[pyclass(module = "rsts", frozen, eq, from_py_object)]
#[derive(Clone, PartialEq)]
pub struct Case {
    pub(crate) motion: Motion,
    /// The camera of (m, h): I+, I-, II+, ..., VI.
    #[pyo3(get)]
    camera: String,
}

/// A whole number >= 0 (a torus, a count), or ValueError naming it.
pub(crate) fn whole(name: &str, x: i64) -> PyResult<usize> {
    usize::try_from(x).map_err(|_| value_error(&[name], format!("must be >= 0, got {x}")))
}

/// A number argument: a `str` is the decimal it holds, a float its exact binary value, an int
/// that integer; anything else is a TypeError naming the argument.
pub(crate) fn number(name: &'static str, x: &Bound<'_, PyAny>) -> PyResult<Decimal> {
    let parsed = if let Ok(s) = x.cast::<PyString>() {
        Decimal::parse(&s.to_cow()?)
    } else if x.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a number (float, int or decimal str), got bool"
        )));
    } else if let Ok(i) = x.cast::<PyInt>() {
        Decimal::parse(&i.str()?.to_cow()?)
    } else if let Ok(f) = x.extract::<f64>() {
        Decimal::from_f64(f)
    } else {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a number (float, int or decimal str), got {}",
            x.get_type().name()?
        )));
    };
    parsed.map_err(|e| value_error(&[name], e))
}

/// A float time (`t_end`): its exact binary value, or ValueError naming it.
pub(crate) fn time(name: &'static str, t: f64) -> PyResult<Decimal> {
    Decimal::from_f64(t).map_err(|e| value_error(&[name], e))
}

impl Case {
    /// The case given, else the README's (`Case.default()`).
    pub(crate) fn or_default(case: Option<Case>) -> PyResult<Self> {
        match case {
            Some(c) => Ok(c),
            None => Self::checked(Motion::default_i_plus()),
        }
    }

    /// Check a motion (its a, b, m, h, torus, phases).
    pub(crate) fn checked(motion: Motion) -> PyResult<Self> {
        let probe = rsts_harness::Case::new(motion.clone(), Decimal::from_integer(0), 1);
        probe.validate().map_err(harness_error)?;
        let (explicit, _) = probe.reference_motion(64).map_err(harness_error)?;
        Ok(Self {
            camera: explicit.camera.label().to_string(),
            motion,
        })
    }

    /// The harness case on `samples` times evenly spaced on [0, t_end].
    pub(crate) fn on_grid(&self, t_end: Decimal, samples: usize) -> rsts_harness::Case {
        rsts_harness::Case::new(self.motion.clone(), t_end, samples)
    }
}

#[pymethods]
impl Case {
    #[new]
    #[pyo3(signature = (a, b, m, h, torus = 0, phase1 = None, phase2 = None))]
    fn new(
        a: &Bound<'_, PyAny>,
        b: &Bound<'_, PyAny>,
        m: &Bound<'_, PyAny>,
        h: &Bound<'_, PyAny>,
        torus: i64,
        phase1: Option<&Bound<'_, PyAny>>,
        phase2: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let phase = |name, x: Option<&Bound<'_, PyAny>>| match x {
            Some(x) => number(name, x),
            None => Ok(Decimal::from_integer(0)),
        };
        Self::checked(Motion {
            a: number("a", a)?,
            b: number("b", b)?,
            m: number("m", m)?,
            h: number("h", h)?,
            torus: whole("torus", torus)?,
            phase1: phase("phase1", phase1)?,
            phase2: phase("phase2", phase2)?,
        })
    }

    /// The built-in default case: camera I+, a = 1, b = 0.5, m = 0.3, h = -0.375 (decimals).
    #[staticmethod]
    fn default() -> PyResult<Self> {
        Self::checked(Motion::default_i_plus())
    }

    /// Strength a of the first field (the nearest float).
    #[getter]
    fn a(&self) -> f64 {
        self.motion.a.to_f64()
    }
    /// Strength b of the second field (the nearest float).
    #[getter]
    fn b(&self) -> f64 {
        self.motion.b.to_f64()
    }
    /// Value m of the partial integral of N (the nearest float).
    #[getter]
    fn m(&self) -> f64 {
        self.motion.m.to_f64()
    }
    /// Energy h (the nearest float).
    #[getter]
    fn h(&self) -> f64 {
        self.motion.h.to_f64()
    }
    /// The Liouville torus (0-based).
    #[getter]
    fn torus(&self) -> usize {
        self.motion.torus
    }
    /// Angle psi1 on the torus at t = 0 (radians; the nearest float).
    #[getter]
    fn phase1(&self) -> f64 {
        self.motion.phase1.to_f64()
    }
    /// Angle psi2 on the torus at t = 0 (radians; the nearest float).
    #[getter]
    fn phase2(&self) -> f64 {
        self.motion.phase2.to_f64()
    }
    /// The exact numbers as decimal strings: {"a": ..., "b": ..., "m": ..., "h": ...,
    /// "phase1": ..., "phase2": ...}.
    #[getter]
    fn decimals(&self) -> std::collections::BTreeMap<&'static str, String> {
        let m = &self.motion;
        [
            ("a", &m.a),
            ("b", &m.b),
            ("m", &m.m),
            ("h", &m.h),
            ("phase1", &m.phase1),
            ("phase2", &m.phase2),
        ]
        .into_iter()
        .map(|(k, v)| (k, v.as_str().to_string()))
        .collect()
    }

    fn __repr__(&self) -> String {
        let m = &self.motion;
        format!(
            "Case(a='{}', b='{}', m='{}', h='{}', torus={}, phase1='{}', phase2='{}')",
            m.a, m.b, m.m, m.h, m.torus, m.phase1, m.phase2
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
        let case = self.on_grid(Decimal::from_integer(0), 1);
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
