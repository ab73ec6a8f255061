//! Checking a trajectory computed elsewhere — a file (`rsts check`), arrays (`rsts.check` in
//! Python) — against the closed-form motion on N: the motion is given (m, h, torus, phases) or
//! identified from the first sample, then every sample is analysed as `compare` analyses an
//! integrator's ([`crate::Analysis`]). Both faces call [`check`] and serialise its
//! [`CheckReport`].

use rug::Float;
use serde::Serialize;

use rsts_closed_form::manifold::{identify, IdentifyError};
use rsts_closed_form::{Decimal, Motion};
use rsts_dynamics::scalar::bits_for_digits;
use rsts_dynamics::{Fields, Real, State};

use crate::analysis::{Analysis, Observer, RunInfo};
use crate::case::Case;
use crate::check_stream::CheckStream;
use crate::metrics::Report;
use crate::{HarnessError, REFERENCE_GUARD_BITS};

/// Relative distance from N above which a first sample is refused for identification.
pub const ON_N_TOLERANCE: f64 = 1e-8;

/// What a trajectory is checked against.
// One value per check request: its size (the motion's seven decimals) costs nothing, and a box
// would only add a step to every construction and match.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum CheckMotion {
    /// The motion, given.
    Given(Motion),
    /// Identified from the first sample, on N of these fields (a, b).
    Identify { a: Decimal, b: Decimal },
}

impl CheckMotion {
    /// The field strengths a, b.
    pub fn fields(&self) -> (&Decimal, &Decimal) {
        match self {
            CheckMotion::Given(m) => (&m.a, &m.b),
            CheckMotion::Identify { a, b } => (a, b),
        }
    }
}

/// What to check a trajectory against, and how to name it.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckRequest {
    /// Where the trajectory came from, as the report's `file` shows it (a path, or a
    /// description such as `<arrays>`).
    pub file: String,
    /// The report's `method`: the trajectory's short name (a file name).
    pub name: String,
    pub motion: CheckMotion,
    /// Decimal digits the data carry (f64 data: 15).
    pub digits: u32,
}

impl CheckRequest {
    /// Check what can be checked before the data are read: the fields, and the motion when it
    /// is given (a point of N off Σ with the torus asked).
    pub fn validate(&self) -> Result<(), HarnessError> {
        let (a, b) = self.motion.fields();
        Fields::new(a.to_float(64), b.to_float(64))?;
        if let CheckMotion::Given(motion) = &self.motion {
            motion.validate()?;
        }
        Ok(())
    }

    /// Bits of the closed-form reference: the data's digits (at least 30) plus
    /// [`REFERENCE_GUARD_BITS`].
    pub fn reference_bits(&self) -> u32 {
        bits_for_digits(self.digits.max(30)) + REFERENCE_GUARD_BITS
    }
}

/// The motion a trajectory was checked against (serialised flat: a, b, m, h, torus, phase1,
/// phase2, identified).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckedCase {
    #[serde(flatten)]
    pub motion: Motion,
    /// True when (m, h, torus, phases) were identified from the first sample.
    pub identified: bool,
}

/// The result of a check: the JSON of `rsts check` (without the MCAP path the CLI adds).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckReport {
    pub file: String,
    pub case: CheckedCase,
    /// max |x − x_exact| over the nine components at the first sample (the start of the run).
    pub start_state_error: f64,
    /// Relative distance of the first sample from N (identification only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start_distance_from_n: Option<f64>,
    /// The first sample far from the motion given ([`StartOffset`]); absent when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start_offset: Option<StartOffset>,
    #[serde(flatten)]
    pub report: Report,
    /// Times of the first and last sample given (not serialised: the table shows them).
    #[serde(skip)]
    pub span: (f64, f64),
    /// Samples given (the report's `samples_compared` is smaller when the run was stopped).
    #[serde(skip)]
    pub samples_given: usize,
}

/// What a message about a first row off N adds when a, b are the defaults (1, 0.5): that they
/// are, and how to give others.
fn fields_hint(a: &Decimal, b: &Decimal) -> String {
    if a.to_f64() == 1.0 && b.to_f64() == 0.5 {
        "; a and b default to 1 and 0.5: if the data are of other fields, give them with \
         --a A --b B (Python: a=, b=)"
            .into()
    } else {
        String::new()
    }
}

/// A start state error above this, times max(1, |x₀|) (the first sample's largest component),
/// is a start offset: far above what data of any precision carry, so the motion checked
/// against is not the data's.
pub const START_OFFSET: f64 = 1e-6;

/// The first sample far from the motion given (issue 33, item 5): the error there, and the
/// motion the first sample identifies on N of the same a, b.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StartOffset {
    /// The start state error.
    pub error: f64,
    /// Where a start offset begins: [`START_OFFSET`]·max(1, |x₀|).
    pub threshold: f64,
    /// The motion the first sample identifies (phases at t = 0), when it does.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub identified: Option<Motion>,
    /// Its camera, when it has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camera: Option<rsts_closed_form::Camera>,
    /// Why no motion was identified.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_identified: Option<String>,
}

impl StartOffset {
    /// The offset and the motion of the data, in words.
    pub fn describe(&self) -> String {
        let mut s = format!(
            "the first sample is {:.3e} from the motion given (more than {:.0e}): it is not a \
             sample of that motion",
            self.error, self.threshold
        );
        match (&self.identified, &self.not_identified) {
            (Some(m), _) => s.push_str(&format!(
                "; it identifies camera {}, m = {}, h = {}, torus {}, phases {:.12}, {:.12} at \
                 t = 0 (give those, or check without --m/--h to identify it)",
                self.camera.map_or("?".to_string(), |c| c.to_string()),
                m.m,
                m.h,
                m.torus,
                m.phase1.to_f64(),
                m.phase2.to_f64()
            )),
            (None, Some(why)) => s.push_str(&format!("; it identifies no motion: {why}")),
            (None, None) => {}
        }
        s
    }

    /// Judge the first sample (time `t0`, state `first`) of a check against `case` given, its
    /// start state error `error`: `None` when it is no offset.
    pub fn judge(
        case: &CheckedCase,
        error: f64,
        t0: &Float,
        first: &State<Float>,
    ) -> Option<StartOffset> {
        if case.identified {
            return None;
        }
        let size = first
            .to_array()
            .iter()
            .map(|x| x.to_f64().abs())
            .fold(1.0, f64::max);
        let threshold = START_OFFSET * size;
        if !(error.is_nan() || error > threshold) {
            return None;
        }
        let (a, b) = (&case.motion.a, &case.motion.b);
        let (identified, camera, not_identified) = match identify_case(a, b, t0, first) {
            Ok((c, _)) => {
                let m = c.motion;
                let camera = rsts_closed_form::diagram::camera_at(
                    a.to_f64(),
                    b.to_f64(),
                    m.m.to_f64(),
                    m.h.to_f64(),
                );
                (Some(m), camera, None)
            }
            Err(e) => (None, None, Some(e.to_string())),
        };
        Some(StartOffset {
            error,
            threshold,
            identified,
            camera,
            not_identified,
        })
    }
}

/// Identify the motion from the first sample (time `t0`, at the reference precision): (m, h,
/// torus) and the phases at t = 0, and the sample's relative distance from N.
pub fn identify_case(
    a: &Decimal,
    b: &Decimal,
    t0: &Float,
    first: &State<Float>,
) -> Result<(CheckedCase, f64), HarnessError> {
    let bits = t0.prec();
    let hint = fields_hint(a, b);
    let id = identify(&a.to_float(bits), &b.to_float(bits), first).map_err(|e| {
        HarnessError::Data(match e {
            IdentifyError::Input(msg) => format!("first row: {msg}"),
            IdentifyError::NoTorus {
                m,
                h,
                distance,
                reason,
            } => format!(
                "first row: not a state of a motion on N of a = {a}, b = {b}: its (m, h) = ({m}, {h}) has no torus ({reason}); its relative distance from N is {distance:.3e}{hint}"
            ),
        })
    })?;
    let relative = id.distance.relative.to_f64();
    if relative.is_nan() || relative > ON_N_TOLERANCE {
        return Err(HarnessError::Data(format!(
            "first row: not on N of a = {a}, b = {b}: its relative distance from N is {relative:.3e} (> {ON_N_TOLERANCE:e}); give the motion with --m, --h (and --torus, --phase1, --phase2) to check it anyway{hint}"
        )));
    }
    // The identified numbers as decimals that round back to them at this precision.
    let digits = rsts_dynamics::scalar::digits_for_bits(bits) + 3;
    let decimal = |x: &Float| {
        Decimal::parse(&x.to_decimal(digits)).map_err(|e| {
            HarnessError::Data(format!("first row: an identified value is not finite: {e}"))
        })
    };
    let zero = Decimal::from_integer(0);
    let on_torus = Motion {
        a: a.clone(),
        b: b.clone(),
        m: decimal(&id.m)?,
        h: decimal(&id.h)?,
        torus: id.torus,
        phase1: zero.clone(),
        phase2: zero,
    };
    let nu = on_torus.explicit::<Float>(bits, 0.0)?.frequencies();
    let two_pi = Float::with_val(bits, rug::float::Constant::Pi) * 2u32;
    // ψ(t) = ψ⁰ + ν t: the phases at t = 0 from those at the first sample's time.
    let at_zero = |psi: &Float, nu: &Float| {
        let x = Float::with_val(bits, psi - nu.clone() * t0);
        let turns = Float::with_val(bits, &x / &two_pi).floor();
        let psi = Float::with_val(bits, x - turns * &two_pi);
        // 2π − 1e-16 is 0 on the torus.
        if Float::with_val(bits, &two_pi - &psi) < 1e-12 {
            Float::with_val(bits, 0)
        } else {
            psi
        }
    };
    let phases = [
        decimal(&at_zero(&id.phases[0], &nu[0]))?,
        decimal(&at_zero(&id.phases[1], &nu[1]))?,
    ];
    let motion = on_torus.on_torus(id.torus, phases);
    Ok((
        CheckedCase {
            motion,
            identified: true,
        },
        relative,
    ))
}

/// A check under way: the motion is known (given or identified), the samples come next.
pub struct Check {
    pub(crate) file: String,
    pub(crate) case: CheckedCase,
    pub(crate) distance: Option<f64>,
    pub(crate) analysis: Analysis,
    /// The case of the reference; its `t_end`, the |t| its phase clock is built for.
    pub(crate) reference: Case,
}

impl Check {
    /// Start checking a trajectory whose first sample is `first` at time `t0` and whose times
    /// reach at most `t_extent` in absolute value (the phase clock of the reference is built
    /// for it). Identifies the motion from the first sample when the request does not give it.
    pub fn start(
        request: &CheckRequest,
        t0: &Float,
        first: &State<Float>,
        t_extent: f64,
    ) -> Result<Self, HarnessError> {
        let bits = request.reference_bits();
        let (case, distance) = match &request.motion {
            CheckMotion::Given(motion) => (
                CheckedCase {
                    motion: motion.clone(),
                    identified: false,
                },
                None,
            ),
            CheckMotion::Identify { a, b } => {
                let t0 = Float::with_val(bits, t0);
                let first = first.map(|x| Float::with_val(bits, x));
                let (case, d) = identify_case(a, b, &t0, &first)?;
                (case, Some(d))
            }
        };
        let t_extent =
            Decimal::from_f64(t_extent).map_err(|e| HarnessError::Data(format!("times: {e}")))?;
        let harness_case = Case::new(case.motion.clone(), t_extent, 1);
        let info = RunInfo {
            method: request.name.clone(),
            rtol: None,
            atol: None,
            digits: request.digits,
        };
        let analysis = Analysis::for_case(&harness_case, bits, info).map_err(|e| {
            if case.identified {
                HarnessError::Data(format!(
                    "the motion identified from the first row of {}: {e}",
                    request.file
                ))
            } else {
                e
            }
        })?;
        Ok(Self {
            file: request.file.clone(),
            case,
            distance,
            analysis,
            reference: harness_case,
        })
    }

    /// The motion the trajectory is checked against.
    pub fn case(&self) -> &CheckedCase {
        &self.case
    }

    /// Analyse the samples in time order (each handed to `observer`; when it asks to stop, the
    /// report says `complete: false`) and report: [`CheckStream::feed`] once, then
    /// [`CheckStream::finish`].
    pub fn run(
        self,
        times: &[Float],
        states: &[State<Float>],
        observer: &mut dyn Observer,
    ) -> Result<CheckReport, HarnessError> {
        check_lengths(times, states)?;
        let mut stream = CheckStream::new(self);
        stream.feed(times, states, observer)?;
        Ok(stream.finish())
    }
}

/// As many states as times, and at least one.
pub(crate) fn check_lengths(times: &[Float], states: &[State<Float>]) -> Result<(), HarnessError> {
    if times.len() != states.len() {
        return Err(HarnessError::Data(format!(
            "{} times and {} states",
            times.len(),
            states.len()
        )));
    }
    if times.is_empty() {
        return Err(HarnessError::Data("no samples to check".into()));
    }
    Ok(())
}

/// Check a trajectory: `times` (strictly increasing, any spacing) and one state per time, at
/// [`CheckRequest::reference_bits`] (wider values are rounded by the arithmetic, narrower ones
/// are exact): [`Check::start`] from the first sample, then [`Check::run`] over all of them.
pub fn check(
    request: &CheckRequest,
    times: &[Float],
    states: &[State<Float>],
    observer: &mut dyn Observer,
) -> Result<CheckReport, HarnessError> {
    check_lengths(times, states)?;
    let t_extent = times.iter().fold(0.0, |m: f64, t| m.max(t.to_f64().abs()));
    Check::start(request, &times[0], &states[0], t_extent)?.run(times, states, observer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NoObserver;

    fn request(motion: Option<Motion>) -> CheckRequest {
        let d = |s: &str| Decimal::parse(s).unwrap();
        CheckRequest {
            file: "<test>".into(),
            name: "test".into(),
            motion: match motion {
                Some(m) => CheckMotion::Given(m),
                None => CheckMotion::Identify {
                    a: d("1"),
                    b: d("0.5"),
                },
            },
            digits: 15,
        }
    }

    /// Exact samples of camera I+ from t = 2: the motion is identified (the phases at t = 0
    /// are those of the case), the errors are round-off of the reference, and the same samples
    /// checked against the motion given report the same case, not identified.
    #[test]
    fn exact_samples_are_identified_and_have_no_error() {
        let d = |s: &str| Decimal::parse(s).unwrap();
        let motion = Motion::default_i_plus().on_torus(0, [d("0.4"), d("1.1")]);
        let case = Case::new(motion.clone(), d("100"), 1001);
        let r = request(None);
        let bits = r.reference_bits();
        let (exact, _) = case.reference_motion(bits).unwrap();
        let times: Vec<Float> = [2.0, 2.5, 7.0]
            .iter()
            .map(|&t| Float::with_val(bits, t))
            .collect();
        let states: Vec<State<Float>> = times
            .iter()
            .map(|t| crate::metrics::exact_state(&exact.at(t)))
            .collect();
        let report = check(&r, &times, &states, &mut NoObserver).unwrap();
        assert!(report.case.identified);
        let found = &report.case.motion;
        assert_eq!(found.torus, 0);
        assert!((found.m.to_f64() - 0.3).abs() < 1e-12, "{:?}", report.case);
        assert!(
            (found.phase1.to_f64() - 0.4).abs() < 1e-9,
            "{:?}",
            report.case
        );
        assert!(
            (found.phase2.to_f64() - 1.1).abs() < 1e-9,
            "{:?}",
            report.case
        );
        assert!(report.report.max_state_error < 1e-12, "{report:?}");
        assert_eq!(report.span, (2.0, 7.0));
        assert_eq!(report.report.samples_compared, 3);
        assert_eq!(report.report.method, "test");

        let given = request(Some(motion));
        let report = check(&given, &times, &states, &mut NoObserver).unwrap();
        assert!(!report.case.identified);
        assert!(report.start_distance_from_n.is_none());
        assert!(report.report.max_state_error < 1e-40, "{report:?}");
    }

    /// Samples of the motion with phases (0.4, 1.1) checked against the same (m, h) at phases
    /// (0, 0): the start is an offset, named with the motion the first sample identifies
    /// (camera I+, torus 0, phases 0.4 and 1.1); checked against their own motion, none.
    /// (Before issue 33 the report only had `start_state_error`, and nothing said it.)
    #[test]
    fn a_start_offset_names_the_motion_of_the_data() {
        let d = |s: &str| Decimal::parse(s).unwrap();
        let motion = Motion::default_i_plus().on_torus(0, [d("0.4"), d("1.1")]);
        let case = Case::new(motion.clone(), d("10"), 11);
        let bits = request(None).reference_bits();
        let (exact, _) = case.reference_motion(bits).unwrap();
        let times: Vec<Float> = [0.0, 1.0, 2.0]
            .iter()
            .map(|&t| Float::with_val(bits, t))
            .collect();
        let states: Vec<State<Float>> = times
            .iter()
            .map(|t| crate::metrics::exact_state(&exact.at(t)))
            .collect();
        let wrong = request(Some(Motion::default_i_plus()));
        let report = check(&wrong, &times, &states, &mut NoObserver).unwrap();
        let offset = report.start_offset.clone().expect("a start offset");
        assert!(offset.error > 1e-2 && offset.error == report.start_state_error);
        let found = offset.identified.clone().expect("identified");
        assert_eq!(found.torus, 0);
        assert!((found.phase1.to_f64() - 0.4).abs() < 1e-9, "{offset:?}");
        assert!((found.phase2.to_f64() - 1.1).abs() < 1e-9, "{offset:?}");
        assert_eq!(offset.camera, Some(rsts_closed_form::Camera::IPlus));
        let text = offset.describe();
        assert!(
            text.contains("not a sample of that motion") && text.contains("camera I+"),
            "{text}"
        );
        let right = request(Some(motion));
        let report = check(&right, &times, &states, &mut NoObserver).unwrap();
        assert!(report.start_offset.is_none(), "{:?}", report.start_offset);
    }

    /// A first row off N for the default fields says they are the defaults and how to give
    /// others (old text: "first row: not on N of a = 1, b = 0.5: its relative distance from N
    /// is … to check it anyway", nothing about the defaults).
    #[test]
    fn off_n_with_default_fields_says_they_are_defaults() {
        let r = request(None);
        let bits = r.reference_bits();
        let f = |x: f64| Float::with_val(bits, x);
        let off = State {
            omega: [f(0.3), f(-0.2), f(0.5)],
            alpha: [f(1.0), f(0.0), f(0.0)],
            beta: [f(0.0), f(1.0), f(0.0)],
        };
        let e = check(&r, &[f(0.0)], std::slice::from_ref(&off), &mut NoObserver)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("a and b default to 1 and 0.5") && e.contains("--a A --b B"),
            "{e}"
        );
    }

    /// A first row off N is refused; a motion given that does not exist is refused before
    /// any data are read; empty and mismatched data are refused.
    #[test]
    fn bad_requests_and_data_are_refused() {
        let r = request(None);
        let bits = r.reference_bits();
        let f = |x: f64| Float::with_val(bits, x);
        let off = State {
            omega: [f(0.3), f(-0.2), f(0.5)],
            alpha: [f(1.0), f(0.0), f(0.0)],
            beta: [f(0.0), f(1.0), f(0.0)],
        };
        let e = check(&r, &[f(0.0)], std::slice::from_ref(&off), &mut NoObserver).unwrap_err();
        assert!(e.to_string().starts_with("first row: not"), "{e}");
        assert!(check(&r, &[], &[], &mut NoObserver).is_err());
        assert!(check(&r, &[f(0.0), f(1.0)], &[off], &mut NoObserver).is_err());
        let nowhere = request(Some(Motion {
            h: Decimal::parse("-100").unwrap(),
            ..Motion::default_i_plus()
        }));
        assert!(nowhere.validate().is_err());
        assert!(request(None).validate().is_ok());
        let fields = CheckRequest {
            motion: CheckMotion::Identify {
                a: Decimal::parse("1").unwrap(),
                b: Decimal::parse("2").unwrap(),
            },
            ..request(None)
        };
        assert!(fields.validate().is_err());
    }
}
