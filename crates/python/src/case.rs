//! `rsts.Case`: a motion on N (a, b, m, h, torus, phases), checked as the CLI checks it, and its
//! exact reference at any times (`rsts reference`).

use pyo3::exceptions::{PyOverflowError, PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyInt, PyList, PyString, PyTuple};
use rsts_closed_form::{Decimal, Motion};

use rsts_flows::reference::{reference, ReferenceHead, ReferenceRequest, ReferenceRow};
use rsts_flows::{Sink, Times};
use rsts_harness::reference::check_digits;

use crate::arrays;
use crate::{flow_error, harness_error, value_error, Interrupts};

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

/// A whole-number argument as Python gives it: an int of any size. One beyond 64 bits is kept as
/// its text (cut at 40 characters) and refused by [`Int::get`] as ValueError naming the argument
/// (PyO3's own conversion raises a bare OverflowError that names nothing).
#[derive(Clone, Debug)]
pub(crate) struct Int(Result<i64, String>);

impl Int {
    pub(crate) const fn of(x: i64) -> Self {
        Int(Ok(x))
    }

    /// The value, or ValueError naming the argument `name` for an int beyond 64 bits.
    pub(crate) fn get(&self, name: &str) -> PyResult<i64> {
        self.0
            .clone()
            .map_err(|text| value_error(&[name], format!("{text} is out of range")))
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Int {
    type Error = PyErr;
    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        match obj.extract::<i64>() {
            Ok(x) => Ok(Int(Ok(x))),
            Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => {
                let text = obj.str()?.to_string();
                let n = text.chars().count();
                let text = if n > 40 {
                    let head: String = text.chars().take(20).collect();
                    format!("{head}… ({n} characters)")
                } else {
                    text
                };
                Ok(Int(Err(text)))
            }
            Err(e) => Err(e),
        }
    }
}

/// An optional whole-number argument, or ValueError naming it ([`Int::get`]).
pub(crate) fn int(name: &str, x: Option<Int>) -> PyResult<Option<i64>> {
    x.map(|x| x.get(name)).transpose()
}

/// A whole number >= 0 (a torus, a count), or ValueError naming it.
pub(crate) fn whole(name: &str, x: Int) -> PyResult<usize> {
    let x = x.get(name)?;
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

/// A list or tuple holding a `str`: each element a number as [`number`] reads it (decimals as
/// written); `None` for anything else (read it as an array of floats).
pub(crate) fn numbers(name: &'static str, x: &Bound<'_, PyAny>) -> PyResult<Option<Vec<Decimal>>> {
    let items: Vec<Bound<'_, PyAny>> = if let Ok(l) = x.cast::<PyList>() {
        l.iter().collect()
    } else if let Ok(t) = x.cast::<PyTuple>() {
        t.iter().collect()
    } else {
        return Ok(None);
    };
    if !items.iter().any(|i| i.is_instance_of::<PyString>()) {
        return Ok(None);
    }
    items
        .iter()
        .map(|i| number(name, i))
        .collect::<PyResult<_>>()
        .map(Some)
}

/// `digits` of a function: `None`, or a whole number in `range` (ValueError naming it).
pub(crate) fn digits_arg(
    d: Option<i64>,
    range: std::ops::RangeInclusive<u32>,
) -> PyResult<Option<u32>> {
    match d {
        None => Ok(None),
        Some(d) => match u32::try_from(d) {
            Ok(x) if range.contains(&x) => Ok(Some(x)),
            _ => Err(value_error(
                &["digits"],
                format!(
                    "must be between {} and {}, got {d}",
                    range.start(),
                    range.end()
                ),
            )),
        },
    }
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
    #[pyo3(signature = (a, b, m, h, torus = Int::of(0), phase1 = None, phase2 = None))]
    fn new(
        a: &Bound<'_, PyAny>,
        b: &Bound<'_, PyAny>,
        m: &Bound<'_, PyAny>,
        h: &Bound<'_, PyAny>,
        torus: Int,
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
    /// 30 digits + 64 bits, rounded once to f64). Times are numbers as in `Case`: floats (a numpy
    /// array) their exact binary values; a list holding strings the decimals they hold (as
    /// `rsts reference --times`: the state at the exact time 0.1, rounded).
    ///
    /// With `digits` (18 to 10000): a list of len(times) lists of 9 decimal strings, each value
    /// carrying that many digits (as `rsts reference --digits D`).
    ///
    /// The GIL is released while the rows are computed (on every core); Ctrl-C raises
    /// KeyboardInterrupt.
    #[pyo3(signature = (times, digits = None))]
    fn reference<'py>(
        &self,
        py: Python<'py>,
        times: &Bound<'py, PyAny>,
        digits: Option<Int>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let digits = int("digits", digits)?;
        arrays::times_count(times, "times")?;
        let times = match numbers("times", times)? {
            Some(d) => Times::Decimals(d),
            None => Times::Binary(arrays::vector(times, "times")?),
        };
        let request = ReferenceRequest {
            motion: self.motion.clone(),
            times,
            digits: check_digits(digits).map_err(|e| value_error(&["digits"], e))?,
            jobs: None,
        };
        let rows = py.detach(move || {
            let mut sink = Rows {
                interrupts: Interrupts::new(),
                text: Vec::new(),
                values: Vec::new(),
            };
            // The state's nine values of each row (not t, H, K, G).
            let state = |row: ReferenceRow| match row {
                ReferenceRow::F64(r) => Row::F64(r[1..10].try_into().expect("nine values")),
                ReferenceRow::Decimal(r) => Row::Text(r[1..10].to_vec()),
            };
            reference(&request, state, &mut sink).map(|_| sink)
        });
        match rows {
            Err(RowsError::Flow(e)) => Err(flow_error(e)),
            Err(RowsError::Interrupted(e)) => Err(e),
            Ok(rows) if digits.is_some() => Ok(PyList::new(py, rows.text)?.into_any()),
            Ok(rows) => arrays::matrix(py, rows.values, 9),
        }
    }
}

/// A row of a reference as kept: the state's nine values.
enum Row {
    F64([f64; 9]),
    Text(Vec<String>),
}

/// The rows of a reference (decimal strings with digits, else f64 values row-major), kept as
/// they come; Ctrl-C stops them.
struct Rows {
    interrupts: Interrupts,
    text: Vec<Vec<String>>,
    values: Vec<f64>,
}

/// Why the rows of a reference could not be made.
enum RowsError {
    Flow(rsts_flows::FlowError),
    Interrupted(PyErr),
}

impl From<rsts_flows::FlowError> for RowsError {
    fn from(e: rsts_flows::FlowError) -> Self {
        RowsError::Flow(e)
    }
}

impl Sink<ReferenceHead, Row> for Rows {
    type Error = RowsError;
    fn head(&mut self, _: &ReferenceHead) -> Result<(), RowsError> {
        Ok(())
    }
    fn row(&mut self, row: Row) -> Result<(), RowsError> {
        if self.interrupts.stopped() {
            let e = self.interrupts.take();
            return Err(RowsError::Interrupted(
                e.unwrap_or_else(|| PyRuntimeError::new_err("interrupted")),
            ));
        }
        match row {
            Row::F64(v) => self.values.extend(v),
            Row::Text(t) => self.text.push(t),
        }
        Ok(())
    }
}
