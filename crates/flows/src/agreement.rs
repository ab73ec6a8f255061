//! One motion, one number (issue 32): on decimal inputs `explicit`, `reference`, `events` and
//! `identify` describe the same motion — at 40 digits to within 1e-40 relative, and in f64 bit
//! for bit (each f64 output the correctly rounded value of the exact motion). A test per pair of
//! flows, on two motions whose decimals are not f64 numbers (camera V, a = 1.3, b = 0.7,
//! m = −0.52, h = 2.07, torus 1, phases 0.3, 1.1; and a = 1.9, b = 0.45, m = 0.33, h = 1.21,
//! phase1 = 0.9). Every comparison is between two flows' outputs; where one flow reads the
//! other's output, it reads more digits than it reports (45 or 50), so that the comparison at 40
//! digits sees the flows and not the rounding of the text passed between them.

use rug::Float;
use serde_json::Value;

use rsts_closed_form::events::{EventRecord, Number};
use rsts_closed_form::{Decimal, Motion, Times};

use crate::events::{event_specs, events_report, EventsRequest};
use crate::explicit::{explicit, ExplicitRequest, Rows};
use crate::identify::{identify, IdentifyOutcome, IdentifyRequest};
use crate::reference::{reference_rows, ReferenceRequest, ReferenceRow};

/// Relative agreement asked at 40 digits.
const REL: f64 = 1e-40;

fn d(s: &str) -> Decimal {
    Decimal::parse(s).unwrap()
}

fn camera_v() -> Motion {
    Motion::from_decimals(["1.3", "0.7", "-0.52", "2.07"], 1, ["0.3", "1.1"]).unwrap()
}

fn second() -> Motion {
    Motion::from_decimals(["1.9", "0.45", "0.33", "1.21"], 0, ["0.9", "0"]).unwrap()
}

fn motions() -> [Motion; 2] {
    [camera_v(), second()]
}

/// A decimal string at 600 bits.
fn big(s: &str) -> Float {
    Float::with_val(600, Float::parse(s).unwrap_or_else(|e| panic!("{s}: {e}")))
}

/// |x − y| ≤ rel · max(|x|, |y|) for two decimal strings.
fn agree(x: &str, y: &str, rel: f64) -> bool {
    let (a, b) = (big(x), big(y));
    let diff = Float::with_val(600, &a - &b).abs();
    let scale = Float::with_val(600, a.abs_ref()).max(&Float::with_val(600, b.abs_ref()));
    diff <= scale * rel
}

/// `x` (40 significant digits) is `y` rounded to 40 digits: |x − y| ≤ half a unit of x's last
/// digit.
fn rounds_to(x: &str, y: &str) -> bool {
    let a = big(x);
    if a.is_zero() {
        return big(y).abs() < 1e-300;
    }
    let lead = a.clone().abs().log10().floor().to_f64() as i32;
    let half_unit = big(&format!("5e{}", lead - 40));
    Float::with_val(600, &a - &big(y)).abs() <= half_unit * 1.000001
}

fn text(x: &Number) -> String {
    match x {
        Number::Decimal(s) => s.clone(),
        Number::F64(v) => format!("{v:e}"),
    }
}

fn value_text(x: &Value) -> String {
    match x {
        Value::String(s) => s.clone(),
        other => format!("{:e}", other.as_f64().unwrap()),
    }
}

/// The decimal strings of explicit's rows (t, ω, α, β, γ, Ω).
fn explicit_decimals(motion: &Motion, times: Times, digits: u32) -> Vec<Vec<String>> {
    let doc = explicit(&ExplicitRequest {
        motion: motion.clone(),
        times,
        digits: Some(digits),
    })
    .unwrap();
    match doc.samples {
        Rows::Decimal(r) => r,
        Rows::F64(_) => unreachable!(),
    }
}

fn explicit_f64(motion: &Motion, times: Times) -> Vec<[f64; 16]> {
    let doc = explicit(&ExplicitRequest {
        motion: motion.clone(),
        times,
        digits: None,
    })
    .unwrap();
    match doc.samples {
        Rows::F64(r) => r,
        Rows::Decimal(_) => unreachable!(),
    }
}

fn reference(motion: &Motion, times: Times, digits: Option<u32>) -> Vec<ReferenceRow> {
    reference_rows(&ReferenceRequest {
        motion: motion.clone(),
        times,
        digits,
        jobs: Some(2),
    })
    .unwrap()
    .1
}

fn events(motion: &Motion, digits: Option<u32>) -> Vec<EventRecord> {
    let request = EventsRequest {
        motion: motion.clone(),
        events: event_specs(&["omega1", "gamma3", "alpha2", "s2"]).unwrap(),
        t_start: d("0"),
        t_end: d("8"),
        digits,
    };
    events_report(&request).unwrap().events
}

/// ω, α, β of an event as 9 numbers.
fn event_state(e: &EventRecord) -> Vec<&Number> {
    e.state
        .omega
        .iter()
        .chain(&e.state.alpha)
        .chain(&e.state.beta)
        .collect()
}

/// Two values of a state agree at 40 digits: to 1e-40 relative, or both zero to 40 digits of
/// the state's scale (1: |α| = |β| = 1). At an event the event's own component, and at a
/// turning point the components that vanish with ṡᵢ, are zero exactly; a flow shows what is
/// left of them at its working precision, which is not a digit of the motion.
fn agree_in_state(x: &str, y: &str) -> bool {
    agree(x, y, REL) || (big(x).abs() < 1e-40 && big(y).abs() < 1e-40)
}

/// Two f64 values of a state are the same, or both zero to the working precision (below
/// 2⁻¹⁰⁰ of the state's scale, 1).
fn same_in_state(x: f64, y: f64) -> bool {
    x == y || (x.abs() < 2f64.powi(-100) && y.abs() < 2f64.powi(-100))
}

/// A grid whose times are not all f64 numbers: k·1.3/5 (0.26, 0.52, …).
fn grid() -> Times {
    Times::grid(d("1.3"), 6)
}

/// explicit and reference: the same state at the same decimal times, at 40 digits and in f64.
#[test]
fn explicit_and_reference_agree() {
    for motion in motions() {
        let e = explicit_decimals(&motion, grid(), 40);
        let r = reference(&motion, grid(), Some(40));
        for (k, (er, rr)) in e.iter().zip(&r).enumerate() {
            let ReferenceRow::Decimal(rr) = rr else {
                unreachable!()
            };
            for j in 0..10 {
                assert!(
                    agree(&er[j], &rr[j], REL),
                    "{motion}, row {k}, value {j}: {} vs {}",
                    er[j],
                    rr[j]
                );
            }
        }
        let e = explicit_f64(&motion, grid());
        let r = reference(&motion, grid(), None);
        for (k, (er, rr)) in e.iter().zip(&r).enumerate() {
            let ReferenceRow::F64(rr) = rr else {
                unreachable!()
            };
            assert_eq!(er[..10], rr[..10], "{motion}, row {k}");
        }
    }
}

/// Each flow's f64 output is its 40-digit output correctly rounded: the exact motion rounded
/// once, whatever path (double-double or MPFR) made it.
#[test]
fn f64_outputs_are_the_exact_motion_rounded() {
    for motion in motions() {
        let e40 = explicit_decimals(&motion, grid(), 40);
        let e = explicit_f64(&motion, grid());
        for (k, (x, y)) in e.iter().zip(&e40).enumerate() {
            for j in 0..16 {
                assert_eq!(
                    x[j],
                    big(&y[j]).to_f64(),
                    "{motion}, explicit row {k}, value {j}"
                );
            }
        }
        let (ev, ev40) = (events(&motion, None), events(&motion, Some(40)));
        assert_eq!(ev.len(), ev40.len(), "{motion}");
        for (x, y) in ev.iter().zip(&ev40) {
            assert_eq!(
                x.t.to_f64(),
                big(&text(&y.t)).to_f64(),
                "{motion}, {}",
                x.name
            );
            for (a, b) in event_state(x).iter().zip(event_state(y)) {
                let (a, b) = (a.to_f64(), big(&text(b)).to_f64());
                assert!(same_in_state(a, b), "{motion}, {}: {a:e} vs {b:e}", x.name);
            }
        }
    }
}

/// explicit at an event's time (50 digits of it) is the event's state, and its event function
/// is zero there, to 40 digits; in f64, explicit at that time gives the event's f64 state.
#[test]
fn explicit_and_events_agree() {
    for motion in motions() {
        let (at40, at50, in_f64) = (
            events(&motion, Some(40)),
            events(&motion, Some(50)),
            events(&motion, None),
        );
        assert!(at40.len() >= 6, "{motion}: {} events", at40.len());
        assert_eq!(at50.len(), at40.len());
        assert_eq!(in_f64.len(), at40.len());
        let times = Times::Decimals(at50.iter().map(|e| d(&text(&e.t))).collect());
        let rows = explicit_decimals(&motion, times.clone(), 40);
        let rows_f64 = explicit_f64(&motion, times);
        for (k, e) in at40.iter().enumerate() {
            let (row, row_f64) = (&rows[k], &rows_f64[k]);
            for (j, x) in event_state(e).iter().enumerate() {
                assert!(
                    agree_in_state(&row[1 + j], &text(x)),
                    "{motion}, {} at {}: {} vs {}",
                    e.name,
                    text(&e.t),
                    row[1 + j],
                    text(x)
                );
            }
            for (j, x) in event_state(&in_f64[k]).iter().enumerate() {
                let (a, b) = (row_f64[1 + j], x.to_f64());
                assert!(same_in_state(a, b), "{motion}, {}: {a:e} vs {b:e}", e.name);
            }
            // The event function at the event: ω₁, α₂ (state), γ₃ (row's γ), ṡ₂ (not a value).
            let zero = match e.name.as_str() {
                "omega1" => Some(&row[1]),
                "alpha2" => Some(&row[5]),
                "gamma3" => Some(&row[12]),
                _ => None,
            };
            if let Some(z) = zero {
                assert!(
                    big(z).abs() < 1e-40,
                    "{motion}, {} at {}: {z}",
                    e.name,
                    text(&e.t)
                );
            }
        }
    }
}

/// reference at an event's time is the event's state, at 40 digits and in f64.
#[test]
fn reference_and_events_agree() {
    for motion in motions() {
        let (at40, at50, in_f64) = (
            events(&motion, Some(40)),
            events(&motion, Some(50)),
            events(&motion, None),
        );
        let times = Times::Decimals(at50.iter().map(|e| d(&text(&e.t))).collect());
        let rows = reference(&motion, times.clone(), Some(40));
        let rows_f64 = reference(&motion, times, None);
        for (k, e) in at40.iter().enumerate() {
            let (ReferenceRow::Decimal(row), ReferenceRow::F64(row_f64)) = (&rows[k], &rows_f64[k])
            else {
                unreachable!()
            };
            for (j, x) in event_state(e).iter().enumerate() {
                assert!(
                    agree_in_state(&row[1 + j], &text(x)),
                    "{motion}, {} at {}: {} vs {}",
                    e.name,
                    text(&e.t),
                    row[1 + j],
                    text(x)
                );
            }
            for (j, x) in event_state(&in_f64[k]).iter().enumerate() {
                let (a, b) = (row_f64[1 + j], x.to_f64());
                assert!(same_in_state(a, b), "{motion}, {}: {a:e} vs {b:e}", e.name);
            }
        }
    }
}

/// identify of a state gives back the motion's decimals: m, h always, the torus and the phases
/// at t = 0 (where the state is the motion's start); 40 digits from a 45-digit state, and f64
/// outputs that are the decimals' nearest f64.
fn assert_identifies(motion: &Motion, state: &[String], at_start: bool, what: &str) {
    let request = |digits| IdentifyRequest {
        a: motion.a.clone(),
        b: motion.b.clone(),
        state: std::array::from_fn(|k| d(&state[k])),
        tolerance: 1e-30,
        digits,
    };
    let (IdentifyOutcome::OnN(at40), IdentifyOutcome::OnN(in_f64)) = (
        identify(&request(Some(40))).unwrap(),
        identify(&request(None)).unwrap(),
    ) else {
        panic!("{what}: off N");
    };
    let mut pairs = vec![
        ("m", &motion.m, &at40.m, &in_f64.m),
        ("h", &motion.h, &at40.h, &in_f64.h),
    ];
    if at_start {
        assert_eq!(at40.torus, motion.torus, "{what}");
        pairs.push(("phase1", &motion.phase1, &at40.phase1, &in_f64.phase1));
        pairs.push(("phase2", &motion.phase2, &at40.phase2, &in_f64.phase2));
    }
    for (name, exact, x40, x64) in pairs {
        assert!(
            agree(&value_text(x40), exact.as_str(), REL),
            "{what}: {name} = {} for {exact}",
            value_text(x40)
        );
        let x = x64.as_f64().unwrap();
        if exact.to_f64() == 0.0 {
            // A phase of 0 is known to the state's digits (45) only: its f64 is within them.
            assert!(x.abs() < 1e-30, "{what}: {name} in f64: {x:e}");
        } else {
            assert_eq!(x, exact.to_f64(), "{what}: {name} in f64");
        }
    }
}

#[test]
fn explicit_and_identify_agree() {
    for motion in motions() {
        let rows = explicit_decimals(&motion, Times::grid(d("2.5"), 3), 45);
        for (k, row) in rows.iter().enumerate() {
            assert_identifies(
                &motion,
                &row[1..10],
                k == 0,
                &format!("{motion}, explicit row {k}"),
            );
        }
    }
}

#[test]
fn reference_and_identify_agree() {
    for motion in motions() {
        let rows = reference(&motion, Times::Decimals(vec![d("0"), d("0.7")]), Some(45));
        for (k, row) in rows.iter().enumerate() {
            let ReferenceRow::Decimal(row) = row else {
                unreachable!()
            };
            assert_identifies(
                &motion,
                &row[1..10],
                k == 0,
                &format!("{motion}, reference row {k}"),
            );
        }
    }
}

#[test]
fn events_and_identify_agree() {
    for motion in motions() {
        for e in events(&motion, Some(45)).iter().take(3) {
            let state: Vec<String> = event_state(e).iter().map(|x| text(x)).collect();
            assert_identifies(
                &motion,
                &state,
                false,
                &format!("{motion}, event {}", e.name),
            );
        }
    }
}

/// A decimal motion is the same motion at every precision: explicit at 40 digits is explicit at
/// 60 digits rounded to 40.
#[test]
fn a_decimal_motion_is_the_same_at_every_precision() {
    for motion in motions() {
        let (a, b) = (
            explicit_decimals(&motion, grid(), 40),
            explicit_decimals(&motion, grid(), 60),
        );
        for (x, y) in a.iter().zip(&b) {
            for j in 0..16 {
                assert!(rounds_to(&x[j], &y[j]), "{motion}: {} vs {}", x[j], y[j]);
            }
        }
    }
}
