//! The dense output of an adapter (`--dense K`, docs/own-integrator.md): a request with
//! `"dense": K` asks for the times of the adapter's own steps, `"stats": {"step_times": [t₀ = 0,
//! t₁, …, tₙ]}`, and for `"dense": [samples]`: in each step (tᵢ, tᵢ₊₁], the K samples of its
//! interpolant at tᵢ + j(tᵢ₊₁ − tᵢ)/(K + 1), j = 1 … K, then its state at tᵢ₊₁ — K + 1 samples
//! per step, in time order, each `{"t", "omega", "alpha", "beta"}`. One run answers both the
//! requested times and these (the steps of a second run with other times could differ).

use serde_json::{json, Value};

use rsts_dynamics::integrators::dense::{interior_times, StepSamples};

use crate::files::parse_json;

/// Most samples (K + 1 per step) a dense answer may hold.
pub const MAX_DENSE_ANSWER_SAMPLES: usize = 200_000;

/// Bytes a dense answer may add to an answer: per sample ten values of up to 64 characters and
/// 200 of keys and layout, doubled, plus 32 per step time.
pub fn max_dense_bytes() -> usize {
    MAX_DENSE_ANSWER_SAMPLES * (2 * (10 * 64 + 200) + 32)
}

/// The `stats.step_times` of an answer (checked: finite, from 0, strictly increasing, at most
/// [`MAX_DENSE_ANSWER_SAMPLES`] + 1), `None` when it has none.
pub fn parse_step_times(doc: &Value) -> Result<Option<Vec<f64>>, String> {
    let Some(v) = doc.get("stats").and_then(|s| s.get("step_times")) else {
        return Ok(None);
    };
    let list = v
        .as_array()
        .ok_or("stats.step_times must be an array of times")?;
    if list.len() > MAX_DENSE_ANSWER_SAMPLES + 1 {
        return Err(format!(
            "stats.step_times has {} times, more than the {} accepted",
            list.len(),
            MAX_DENSE_ANSWER_SAMPLES + 1
        ));
    }
    let mut times = Vec::with_capacity(list.len());
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
                "stats.step_times must start at 0 (the start of the run), got {t}"
            ));
        }
        if times.last().is_some_and(|&p| t <= p) {
            return Err(format!(
                "stats.step_times[{i}] = {t} does not come after {}",
                times[i - 1]
            ));
        }
        times.push(t);
    }
    Ok(Some(times))
}

/// The dense samples of an answer to a request with `"dense": k`: `step_times` and the
/// `"dense"` list, checked against the rule of the module doc.
pub fn parse_dense(doc: &Value, k: usize) -> Result<StepSamples, String> {
    let asked = format!(
        "the request asked \"dense\": {k} (--dense), which needs \"stats\": {{\"step_times\": [...]}} \
         and \"dense\": [samples] in the answer (docs/own-integrator.md)"
    );
    let step_times = parse_step_times(doc)?
        .ok_or_else(|| format!("{asked}; the answer has no \"stats.step_times\""))?;
    let list = doc
        .get("dense")
        .ok_or_else(|| format!("{asked}; the answer has no \"dense\""))?;
    let steps = step_times.len().saturating_sub(1);
    let want = steps * (k + 1);
    if want > MAX_DENSE_ANSWER_SAMPLES {
        return Err(format!(
            "{steps} steps with {k} samples inside each make {want} dense samples, more than the \
             {MAX_DENSE_ANSWER_SAMPLES} accepted; shorten t-end or ask fewer"
        ));
    }
    let raw = parse_json(&json!({ "samples": list })).map_err(|e| format!("dense: {e}"))?;
    if raw.len() != want {
        return Err(format!(
            "\"dense\" has {} samples; {steps} steps with {k} inside each and the step's end \
             make {want}",
            raw.len()
        ));
    }
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
                    "dense[{n}] is at t = {got}; the rule asks t = {want} (step {} to {}, {k} \
                     inside)",
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

    fn sample(t: f64) -> Value {
        json!({"t": t, "omega": [t, 0, 0], "alpha": [1, 0, 0], "beta": [0, 1, 0]})
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
        let s = parse_dense(&doc, 3).unwrap();
        assert_eq!(s.steps(), 2);
        assert_eq!(s.at_step_end.iter().filter(|e| **e).count(), 2);
        assert_eq!(s.states[4][0], 1.5);
        let short = json!({"stats": {"step_times": [0, 1, 3]}, "dense": good[..7]});
        assert!(parse_dense(&short, 3).unwrap_err().contains("make 8"));
        let moved = json!({"stats": {"step_times": [0, 1, 2.9]}, "dense": good});
        assert!(parse_dense(&moved, 3).unwrap_err().contains("dense[4]"));
        let none = json!({"dense": good});
        assert!(parse_dense(&none, 3)
            .unwrap_err()
            .contains("no \"stats.step_times\""));
        let bad = json!({"stats": {"step_times": [0, 2, 1]}});
        assert!(parse_step_times(&bad).unwrap_err().contains("[2] = 1"));
    }
}
