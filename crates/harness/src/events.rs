//! Detected events against exact ones (docs/events.md): reading a list of detected events (CSV
//! `name,t` or JSON `{"events": [{"name", "t"}]}`), locating events in sampled states by cubic
//! Hermite interpolation (how the built-in methods and plain trajectories report events), and
//! matching detected with exact events into the `"events"` part of a report.

use rsts_closed_form::events::{events_report, DirectionFilter, EventCase, EventName, EventSpec};
use rsts_dynamics::{Fields, VectorField};
use serde::Serialize;

pub use crate::detected::{
    parse_detected, read_detected, MAX_DETECTED_BYTES, MAX_DETECTED_EVENTS, MAX_DETECTED_LINE_BYTES,
};

use crate::analysis::Observer;
use crate::metrics::SampleRecord;
use crate::HarnessError;

/// An observer that keeps the integrated (t, ω, α, β) of every sample (for
/// [`locate_by_interpolation`]) and hands each record on.
pub struct StateCollector<'a> {
    inner: &'a mut dyn Observer,
    pub times: Vec<f64>,
    pub states: Vec<[f64; 9]>,
}

impl<'a> StateCollector<'a> {
    pub fn new(inner: &'a mut dyn Observer) -> Self {
        Self {
            inner,
            times: Vec::new(),
            states: Vec::new(),
        }
    }
}

impl Observer for StateCollector<'_> {
    fn on_sample(&mut self, r: &SampleRecord) -> Result<(), String> {
        let s = &r.integrated;
        let (w, al, be) = (s.omega, s.q[0], s.q[1]);
        self.times.push(r.t);
        self.states
            .push([w[0], w[1], w[2], al[0], al[1], al[2], be[0], be[1], be[2]]);
        self.inner.on_sample(r)
    }
    fn should_stop(&self) -> bool {
        self.inner.should_stop()
    }
}

/// Match the events of `specs` an integrator located with the exact ones along `case` over its
/// samples (0, t_last]: `answered` when it reported them (an adapter), else located in its
/// samples by [`locate_by_interpolation`].
pub fn events_of_run(
    case: &crate::Case,
    specs: &[EventSpec],
    answered: Option<&[(String, f64)]>,
    times: &[f64],
    states: &[[f64; 9]],
) -> Result<EventMatchReport, HarnessError> {
    let detected = match answered {
        Some(list) => detected_from_answer(list).map_err(HarnessError::Integrator)?,
        None => {
            let [a, b, _, _] = case.motion.parameters_f64();
            locate_by_interpolation(a, b, times, states, specs)
        }
    };
    let t_last = times.last().copied().unwrap_or(0.0);
    let exact = exact_event_times(&case.motion, specs, 0.0, t_last)?;
    Ok(match_events(&exact, &detected))
}

/// Detected events from an integrator's answer, as (name, t): unknown names are an error.
pub fn detected_from_answer(list: &[(String, f64)]) -> Result<Vec<DetectedEvent>, String> {
    let mut out: Vec<DetectedEvent> = list
        .iter()
        .map(|(n, t)| {
            EventName::parse(n)
                .map(|name| DetectedEvent { name, t: *t })
                .ok_or_else(|| format!("the integrator answered an unknown event '{n}'"))
        })
        .collect::<Result<_, _>>()?;
    out.sort_by(|p, q| p.t.total_cmp(&q.t));
    Ok(out)
}

/// An event reported by an integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct DetectedEvent {
    pub name: EventName,
    pub t: f64,
}

/// One line of the per-event list: a matched pair, a missed exact event (`t_detected` null) or
/// a spurious detection (`t_exact` null).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EventPair {
    pub name: String,
    pub t_exact: Option<f64>,
    pub t_detected: Option<f64>,
    /// |t_detected − t_exact| of a matched pair.
    pub time_error: Option<f64>,
}

/// The `"events"` part of a report: the counts, then the per-event list.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EventMatchReport {
    #[serde(flatten)]
    pub counts: EventCounts,
    pub per_event: Vec<EventPair>,
}

/// The counts and time errors of an [`EventMatchReport`] (alone: a bench row's `events`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct EventCounts {
    pub exact: usize,
    pub matched: usize,
    pub missed: usize,
    pub spurious: usize,
    /// Largest and median |t_detected − t_exact| over the matched events (null when none).
    pub max_time_error: Option<f64>,
    pub median_time_error: Option<f64>,
}

impl EventCounts {
    /// Why a run fails `--max-event-error limit` (a missed event or a larger time error).
    pub fn failure(&self, limit: f64) -> Option<String> {
        let worst = self.max_time_error.unwrap_or(0.0);
        (self.missed > 0 || worst > limit).then(|| {
            format!(
                "{} missed event(s), largest time error {worst:.3e} (--max-event-error {limit:e})",
                self.missed
            )
        })
    }
}

impl EventMatchReport {
    pub fn counts(&self) -> EventCounts {
        self.counts
    }

    /// One line for a text report.
    pub fn summary(&self) -> String {
        let e = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.3e}"));
        let c = &self.counts;
        format!(
            "{} exact, {} matched, {} missed, {} spurious; time error max {}, median {}",
            c.exact,
            c.matched,
            c.missed,
            c.spurious,
            e(c.max_time_error),
            e(c.median_time_error)
        )
    }
}

/// Pair each detected event with the nearest exact event of the same name when it lies within
/// half the gap from that exact event to its neighbours of the same name (the whole window on a
/// side without a neighbour); an exact event takes at most one detection (the nearest).
pub fn match_events(exact: &[DetectedEvent], detected: &[DetectedEvent]) -> EventMatchReport {
    let mut claimed: Vec<Option<(usize, f64)>> = vec![None; exact.len()];
    let mut spurious = Vec::new();
    for (j, d) in detected.iter().enumerate() {
        let same: Vec<usize> = (0..exact.len())
            .filter(|&i| exact[i].name == d.name)
            .collect();
        let nearest = same.iter().enumerate().min_by(|(_, &p), (_, &q)| {
            (exact[p].t - d.t)
                .abs()
                .total_cmp(&(exact[q].t - d.t).abs())
        });
        let Some((pos, &i)) = nearest else {
            spurious.push(j);
            continue;
        };
        let t = exact[i].t;
        let left = pos.checked_sub(1).map(|p| (t - exact[same[p]].t) / 2.0);
        let right = same.get(pos + 1).map(|&q| (exact[q].t - t) / 2.0);
        let reach = if d.t < t {
            left.or(right)
        } else {
            right.or(left)
        };
        let err = (d.t - t).abs();
        if reach.is_some_and(|r| err > r) {
            spurious.push(j);
            continue;
        }
        match claimed[i] {
            Some((_, e)) if e <= err => spurious.push(j),
            Some((other, _)) => {
                spurious.push(other);
                claimed[i] = Some((j, err));
            }
            None => claimed[i] = Some((j, err)),
        }
    }
    let mut per_event = Vec::new();
    let mut errors = Vec::new();
    for (i, e) in exact.iter().enumerate() {
        let pair = claimed[i].map(|(j, err)| (detected[j].t, err));
        if let Some((_, err)) = pair {
            errors.push(err);
        }
        per_event.push(EventPair {
            name: e.name.as_str().to_string(),
            t_exact: Some(e.t),
            t_detected: pair.map(|p| p.0),
            time_error: pair.map(|p| p.1),
        });
    }
    spurious.sort_unstable();
    for &j in &spurious {
        per_event.push(EventPair {
            name: detected[j].name.as_str().to_string(),
            t_exact: None,
            t_detected: Some(detected[j].t),
            time_error: None,
        });
    }
    errors.sort_by(f64::total_cmp);
    let median = (!errors.is_empty()).then(|| {
        let n = errors.len();
        if n % 2 == 1 {
            errors[n / 2]
        } else {
            0.5 * (errors[n / 2 - 1] + errors[n / 2])
        }
    });
    EventMatchReport {
        counts: EventCounts {
            exact: exact.len(),
            matched: errors.len(),
            missed: exact.len() - errors.len(),
            spurious: spurious.len(),
            max_time_error: errors.last().copied(),
            median_time_error: median,
        },
        per_event,
    }
}

/// The exact events of `specs` along a motion in (t_start, t_end], as f64 times (correctly
/// rounded).
pub fn exact_event_times(
    motion: &rsts_closed_form::Motion,
    specs: &[EventSpec],
    t_start: f64,
    t_end: f64,
) -> Result<Vec<DetectedEvent>, HarnessError> {
    if specs.is_empty() || t_end <= t_start {
        return Ok(Vec::new());
    }
    // The window of f64 data: its ends' exact binary values.
    let end = |t: f64| {
        rsts_closed_form::Decimal::from_f64(t).map_err(|e| HarnessError::Data(e.to_string()))
    };
    let case = EventCase {
        motion: motion.clone(),
        t_start: end(t_start)?,
        t_end: end(t_end)?,
        digits: None,
        camera: String::new(),
    };
    let report = events_report(case, specs)?;
    Ok(report
        .events
        .iter()
        .map(|e| DetectedEvent {
            name: EventName::parse(&e.name).expect("a known name"),
            t: e.t.to_f64(),
        })
        .collect())
}

/// Value and time derivative of event function `k` (0..12) at a state (ω, α, β), the derivative
/// from the equations of motion.
fn event_value(field: &VectorField<f64>, x: &[f64; 9], k: usize) -> (f64, f64) {
    let dx = field.eval(x);
    if k < 9 {
        return (x[k], dx[k]);
    }
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let g = cross([x[3], x[4], x[5]], [x[6], x[7], x[8]]);
    let dg = cross(g, [x[0], x[1], x[2]]);
    (g[k - 9], dg[k - 9])
}

/// Events of `specs` located in a sampled trajectory: on each interval between samples the
/// event function is the cubic Hermite interpolant of its values and derivatives (from the
/// equations) at both ends; a sign change of the cubic (on 8 sub-intervals) is refined by
/// bisection. A pair of roots inside one sub-interval is not seen: the interpolant's limit.
/// `s1`, `s2` (turning points of the separated variables) are not functions of the state alone
/// here and are skipped.
pub fn locate_by_interpolation(
    a: f64,
    b: f64,
    times: &[f64],
    states: &[[f64; 9]],
    specs: &[EventSpec],
) -> Vec<DetectedEvent> {
    let field = VectorField::new(&Fields { a, b });
    let mut out = Vec::new();
    for spec in specs.iter().filter(|s| s.name.index() < 12) {
        let k = spec.name.index();
        let values: Vec<(f64, f64)> = states.iter().map(|x| event_value(&field, x, k)).collect();
        for i in 1..times.len() {
            let (t0, t1) = (times[i - 1], times[i]);
            let h = t1 - t0;
            let ((g0, d0), (g1, d1)) = (values[i - 1], values[i]);
            let p = |s: f64| {
                let (h00, h10) = (
                    2.0 * s.powi(3) - 3.0 * s * s + 1.0,
                    s.powi(3) - 2.0 * s * s + s,
                );
                let (h01, h11) = (-2.0 * s.powi(3) + 3.0 * s * s, s.powi(3) - s * s);
                h00 * g0 + h10 * h * d0 + h01 * g1 + h11 * h * d1
            };
            let sub = 8;
            let mut prev = (0.0, g0);
            for j in 1..=sub {
                let s = j as f64 / sub as f64;
                let v = p(s);
                // Zero at the start of the window is not an event; one at a sample counts once
                // (as the end of the interval before it).
                let crosses = (prev.1 < 0.0 && v >= 0.0) || (prev.1 > 0.0 && v <= 0.0);
                if crosses && !(i == 1 && j == 1 && g0 == 0.0) {
                    let up = v > prev.1;
                    let (mut lo, mut hi) = (prev.0, s);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if (p(mid) > 0.0) == up {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    let dir = if up {
                        DirectionFilter::Up
                    } else {
                        DirectionFilter::Down
                    };
                    if spec.direction == DirectionFilter::Both || spec.direction == dir {
                        out.push(DetectedEvent {
                            name: spec.name,
                            t: t0 + 0.5 * (lo + hi) * h,
                        });
                    }
                }
                prev = (s, v);
            }
        }
    }
    out.sort_by(|p, q| p.t.total_cmp(&q.t));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(name: &str, t: f64) -> DetectedEvent {
        DetectedEvent {
            name: EventName::parse(name).unwrap(),
            t,
        }
    }

    #[test]
    fn one_dropped_event_is_one_missed_and_a_far_one_is_spurious() {
        let exact = [
            ev("omega1", 1.0),
            ev("omega1", 2.0),
            ev("omega1", 3.0),
            ev("s1", 1.5),
        ];
        // omega1 at 2 dropped; 3.0 found late; one omega1 far from any; s1 found early.
        let found = [
            ev("omega1", 1.0 + 1e-9),
            ev("s1", 1.5 - 2e-9),
            ev("omega1", 3.0 + 4e-9),
            ev("omega1", 9.0),
        ];
        let r = match_events(&exact, &found);
        let c = r.counts;
        assert_eq!(
            (c.exact, c.matched, c.missed, c.spurious),
            (4, 3, 1, 1),
            "{r:?}"
        );
        assert!((c.max_time_error.unwrap() - 4e-9).abs() < 1e-15);
        assert!((c.median_time_error.unwrap() - 2e-9).abs() < 1e-15);
        assert!(c.failure(1e-3).is_some() && c.failure(1.0).is_some());
        let all = match_events(&exact, &exact).counts;
        assert_eq!(all.failure(0.0), None);
        let missed: Vec<_> = r
            .per_event
            .iter()
            .filter(|p| p.t_detected.is_none())
            .collect();
        assert_eq!(missed.len(), 1);
        assert_eq!(missed[0].t_exact, Some(2.0));
        // Two detections of one exact event: the nearer is matched, the other is spurious.
        let r = match_events(&exact[..1], &[ev("omega1", 1.1), ev("omega1", 1.01)]).counts;
        assert_eq!((r.matched, r.spurious), (1, 1));
        assert!((r.max_time_error.unwrap() - 0.01).abs() < 1e-12);
    }

    #[test]
    fn files_with_unknown_names_name_the_line_and_any_order_is_sorted() {
        let ok = parse_detected("name,t\nomega1,0.5\n\ngamma3,0.7\n").unwrap();
        assert_eq!(ok, vec![ev("omega1", 0.5), ev("gamma3", 0.7)]);
        // The CSV of `rsts events`: t first, name later, other columns ignored.
        let same = parse_detected("t,omega1,name,direction\n0.5,0,omega1,up\n0.7,1,gamma3,down\n");
        assert_eq!(same.unwrap(), ok);
        let e = parse_detected("name,t\nomega1,0.5\nomega9,0.7\n").unwrap_err();
        assert!(e.starts_with("line 3: unknown event 'omega9'"), "{e}");
        // Events in any order are sorted on reading (scipy's t_events come grouped by event).
        let sorted = parse_detected("name,t\nomega1,0.5\nomega1,0.2\n").unwrap();
        assert_eq!(sorted, vec![ev("omega1", 0.2), ev("omega1", 0.5)]);
        let e = parse_detected(r#"{"events": [{"name": "s1", "t": 1}, {"name": "x", "t": 2}]}"#)
            .unwrap_err();
        assert!(e.starts_with("events[1]: unknown event 'x'"), "{e}");
        let sorted =
            parse_detected(r#"{"events": [{"name": "s1", "t": 2}, {"name": "s2", "t": 1}]}"#)
                .unwrap();
        assert_eq!(sorted, vec![ev("s2", 1.0), ev("s1", 2.0)]);
    }

    #[test]
    fn interpolation_finds_the_zeros_of_a_sampled_rotation() {
        // No fields (a = b = 0), ω = e3: α = (cos t, −sin t, 0), alpha1 vanishes at π/2, 3π/2.
        let (a, b) = (0.0, 0.0);
        let times: Vec<f64> = (0..=50).map(|k| k as f64 * 0.1).collect();
        let states: Vec<[f64; 9]> = times
            .iter()
            .map(|&t| [0.0, 0.0, 1.0, t.cos(), -t.sin(), 0.0, t.sin(), t.cos(), 0.0])
            .collect();
        let specs = vec!["alpha1".parse().unwrap()];
        let found = locate_by_interpolation(a, b, &times, &states, &specs);
        assert_eq!(found.len(), 2, "{found:?}");
        let pi = std::f64::consts::PI;
        assert!((found[0].t - pi / 2.0).abs() < 1e-5 && (found[1].t - 1.5 * pi).abs() < 1e-5);
    }
}
