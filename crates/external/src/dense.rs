//! The dense output of an adapter (`--dense K`, docs/own-integrator.md): a request with
//! `"dense": K` asks for the times of the adapter's own steps, `"stats": {"step_times": [t₀ = 0,
//! t₁, …, tₙ]}`, and for `"dense": [samples]`: in each step (tᵢ, tᵢ₊₁], the K samples of its
//! interpolant at tᵢ + j(tᵢ₊₁ − tᵢ)/(K + 1), j = 1 … K, then its state at tᵢ₊₁ — K + 1 samples
//! per step, in time order, each `{"t", "omega", "alpha", "beta"}`. One run answers both the
//! requested times and these (the steps of a second run with other times could differ).

use serde_json::Value;

use rsts_dynamics::integrators::dense::{interior_times, StepSamples};

use crate::exec::answer_doc::AnswerDoc;

/// Most samples (K + 1 per step) a dense answer may hold.
pub const MAX_DENSE_ANSWER_SAMPLES: usize = 200_000;

/// Bytes a dense answer may add to an answer: per sample ten values of up to 64 characters and
/// 200 of keys and layout, doubled, plus 32 per step time.
pub fn max_dense_bytes() -> usize {
    MAX_DENSE_ANSWER_SAMPLES * (2 * (10 * 64 + 200) + 32)
}

/// The `stats.step_times` of an answer (checked: finite, from 0, strictly increasing, at most
/// [`MAX_DENSE_ANSWER_SAMPLES`] + 1, ending at `t_end`: the run's last requested time, within
/// the tolerance of the samples' times), `None` when it has none.
fn step_times_of(doc: &AnswerDoc, t_end: f64) -> Result<Option<Vec<f64>>, String> {
    let Some(v) = doc.stats.as_ref().and_then(|s| s.get("step_times")) else {
        return Ok(None);
    };
    let list = v
        .as_array()
        .ok_or("stats.step_times must be an array of times")?;
    if doc.step_times_count > MAX_DENSE_ANSWER_SAMPLES + 1 {
        return Err(format!(
            "stats.step_times has {} times, more than the {} accepted",
            doc.step_times_count,
            MAX_DENSE_ANSWER_SAMPLES + 1
        ));
    }
    let short = rsts_dynamics::shown;
    let mut times: Vec<f64> = Vec::with_capacity(list.len());
    for (i, x) in list.iter().enumerate() {
        let t = match x {
            Value::Number(n) => n.as_f64(),
            Value::String(s) => s.trim().parse().ok(),
            _ => None,
        }
        .filter(|t: &f64| t.is_finite())
        .ok_or_else(|| format!("stats.step_times[{i}] must be a finite number"))?;
        if i == 0 && t != 0.0 {
            return Err(format!(
                "stats.step_times must start at 0 (the start of the run), got {}",
                short(t)
            ));
        }
        if times.last().is_some_and(|&p| t <= p) {
            return Err(format!(
                "stats.step_times[{i}] = {t:?} does not come after {:?}",
                times[i - 1]
            ));
        }
        times.push(t);
    }
    let last = times.last().copied().unwrap_or(0.0);
    if (last - t_end).abs() > 1e-12 * t_end.abs().max(1.0) {
        return Err(format!(
            "stats.step_times ends at {last:?}, not at the end of the run t = {t_end:?}: the \
             steps must cover the run (the last step ends at the last requested time)"
        ));
    }
    Ok(Some(times))
}

/// The dense samples of an answer to a request with `"dense": k` for a run to `t_end`:
/// `step_times` and the `"dense"` list, checked against the rule of the module doc.
pub(crate) fn dense_of_answer(
    doc: &AnswerDoc,
    k: usize,
    t_end: f64,
) -> Result<StepSamples, String> {
    let asked = format!(
        "the request asked \"dense\": {k} (--dense), which needs \"stats\": {{\"step_times\": [...]}} \
         and \"dense\": [samples] in the answer (docs/own-integrator.md)"
    );
    let step_times = step_times_of(doc, t_end)?
        .ok_or_else(|| format!("{asked}; the answer has no \"stats.step_times\""))?;
    let list = doc
        .dense
        .as_ref()
        .ok_or_else(|| format!("{asked}; the answer has no \"dense\""))?;
    let steps = step_times.len().saturating_sub(1);
    let want = steps * (k + 1);
    if want > MAX_DENSE_ANSWER_SAMPLES {
        return Err(format!(
            "{steps} steps with {k} samples inside each make {want} dense samples, more than the \
             {MAX_DENSE_ANSWER_SAMPLES} accepted; shorten t-end or ask fewer"
        ));
    }
    if let Some(e) = &list.error {
        let e = e.replacen("\"samples\" must", "\"dense\" must", 1);
        return Err(format!("dense: {e}"));
    }
    if list.count != want {
        return Err(format!(
            "\"dense\" has {} samples; {steps} steps with {k} inside each and the step's end \
             make {want}",
            list.count
        ));
    }
    if want == 0 {
        return Err(format!(
            "{asked}; its stats.step_times [0] has no step: nothing to check"
        ));
    }
    let raw = &list.raw;
    let mut out = StepSamples {
        step_times: step_times.clone(),
        ..StepSamples::default()
    };
    let mut n = 0;
    for w in step_times.windows(2) {
        let times = interior_times(w[0], w[1], k).map(|t| (t, false));
        for (want, end) in times.chain([(w[1], true)]) {
            let got = raw.times[n].to_f64();
            if (got - want).abs() > 1e-12 * want.abs().max(1.0) {
                return Err(format!(
                    "dense[{n}] is at t = {got:?}; the rule asks t = {want:?} (step {:?} to {:?}, \
                     {k} inside)",
                    w[0], w[1]
                ));
            }
            let y = std::array::from_fn(|i| raw.states[n][i].to_f64());
            out.push(got, y, end);
            n += 1;
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn sample(t: f64) -> Value {
        json!({"t": t, "omega": [t, 0, 0], "alpha": [1, 0, 0], "beta": [0, 1, 0]})
    }

    fn dense(doc: Value, k: usize, t_end: f64) -> Result<StepSamples, String> {
        let doc = AnswerDoc::read(doc.to_string().as_bytes(), 0).unwrap();
        dense_of_answer(&doc, k, t_end)
    }

    /// The rule: K inside each step, then its end; a wrong count, a wrong time or a missing
    /// list is refused with what was expected.
    #[test]
    fn dense_answers_follow_the_rule() {
        let good: Vec<Value> = [0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0]
            .into_iter()
            .map(sample)
            .collect();
        let doc = json!({"stats": {"step_times": [0, 1, 3]}, "dense": good});
        let s = dense(doc, 3, 3.0).unwrap();
        assert_eq!(s.steps(), 2);
        assert_eq!(s.at_step_end.iter().filter(|e| **e).count(), 2);
        assert_eq!(s.states[4][0], 1.5);
        let short = json!({"stats": {"step_times": [0, 1, 3]}, "dense": good[..7]});
        assert!(dense(short, 3, 3.0).unwrap_err().contains("make 8"));
        let moved = json!({"stats": {"step_times": [0, 1, 2.9]}, "dense": good});
        assert!(dense(moved, 3, 2.9).unwrap_err().contains("dense[4]"));
        let none = json!({"dense": good});
        assert!(dense(none, 3, 3.0)
            .unwrap_err()
            .contains("no \"stats.step_times\""));
        let bad = json!({"stats": {"step_times": [0, 2, 1]}, "dense": []});
        assert!(dense(bad, 3, 1.0).unwrap_err().contains("[2] = 1.0"));
    }

    /// Step times must end where the run ends; a run of no step checks nothing and is refused
    /// (it used to report dense_max_error 0).
    #[test]
    fn step_times_cover_the_run() {
        let good: Vec<Value> = [0.5, 1.0].into_iter().map(sample).collect();
        let doc = json!({"stats": {"step_times": [0, 1]}, "dense": good});
        assert!(dense(doc.clone(), 1, 1.0).is_ok());
        let e = dense(doc, 1, 2.0).unwrap_err();
        assert!(
            e.starts_with("stats.step_times ends at 1.0, not at the end of the run t = 2.0"),
            "{e}"
        );
        let e = dense(json!({"stats": {"step_times": [0]}, "dense": []}), 1, 1.0).unwrap_err();
        assert!(e.contains("ends at 0.0"), "{e}");
        let e = dense(json!({"stats": {"step_times": [0]}, "dense": []}), 1, 0.0).unwrap_err();
        assert!(e.contains("has no step: nothing to check"), "{e}");
        let e = dense(
            json!({"stats": {"step_times": [1e300]}, "dense": []}),
            1,
            1.0,
        )
        .unwrap_err();
        assert!(e.ends_with("got 1e300"), "{e}");
    }
}
