//! Files written by `TrajectoryLog`, read back with the `mcap` crate (independently of
//! `rsts_mcap::inspect`) and with `inspect`.

#![allow(clippy::needless_range_loop, clippy::type_complexity)]

use crate::common;

use std::collections::BTreeMap;

use common::{samples, tmp, write_log, T_END};
use rsts_mcap::demo::{self, matvec, Precession};
use rsts_mcap::{inspect, time_to_ns, topics, Quaternion, TrajectoryLog};
use serde_json::Value;

/// All messages of the file, by topic, via mcap's own MessageStream.
fn read_all(path: &std::path::Path) -> BTreeMap<String, Vec<mcap::Message<'static>>> {
    let buf = std::fs::read(path).unwrap();
    let mut by_topic: BTreeMap<String, Vec<mcap::Message<'static>>> = BTreeMap::new();
    for m in mcap::MessageStream::new(&buf).unwrap() {
        let m = m.unwrap();
        by_topic.entry(m.channel.topic.clone()).or_default().push(m);
    }
    by_topic
}

fn json(m: &mcap::Message) -> Value {
    serde_json::from_slice(&m.data).unwrap()
}

fn v3(v: &Value) -> [f64; 3] {
    [
        v["x"].as_f64().unwrap(),
        v["y"].as_f64().unwrap(),
        v["z"].as_f64().unwrap(),
    ]
}

#[test]
fn demo_motion_is_consistent() {
    // The closed forms of the demo: Ω = Q ω and Q orthogonal.
    let p = Precession::EXAMPLE;
    for i in 0..50 {
        let s = p.state(0.37 * i as f64);
        let w = matvec(&s.q, s.omega);
        for k in 0..3 {
            assert!(
                (w[k] - s.omega_fixed[k]).abs() < 1e-13,
                "{w:?} {:?}",
                s.omega_fixed
            );
        }
    }
}

#[test]
fn channels_schemas_counts_and_summary() {
    let n = 300;
    let (path, _) = write_log("counts.mcap", n);
    let buf = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&buf).unwrap().expect("summary section");
    let stats = summary.stats.as_ref().unwrap();
    let mut by_topic = BTreeMap::new();
    for (id, ch) in &summary.channels {
        let schema = ch.schema.as_ref().unwrap();
        assert_eq!(schema.encoding, "jsonschema");
        assert_eq!(ch.message_encoding, "json");
        // Every schema is valid JSON whose title is the schema name.
        let sv: Value = serde_json::from_slice(&schema.data).unwrap();
        assert_eq!(sv["title"], schema.name.as_str());
        by_topic.insert(
            ch.topic.clone(),
            (
                schema.name.clone(),
                stats.channel_message_counts.get(id).copied().unwrap_or(0),
            ),
        );
    }
    let expect = [
        (topics::METADATA, "rsts.Metadata", 1),
        (topics::TF, "foxglove.FrameTransform", 2 * n as u64),
        (topics::EXACT_STATE, "rsts.BodyState", n as u64),
        (topics::INTEGRATED_STATE, "rsts.BodyState", n as u64),
        (topics::ERRORS, "rsts.Errors", n as u64),
        (
            topics::EXACT_HODOGRAPH_MOVING,
            "foxglove.SceneUpdate",
            n as u64,
        ),
        (
            topics::EXACT_HODOGRAPH_FIXED,
            "foxglove.SceneUpdate",
            n as u64,
        ),
        (
            topics::INTEGRATED_HODOGRAPH_MOVING,
            "foxglove.SceneUpdate",
            n as u64,
        ),
        (
            topics::INTEGRATED_HODOGRAPH_FIXED,
            "foxglove.SceneUpdate",
            n as u64,
        ),
    ];
    assert_eq!(by_topic.len(), expect.len());
    for (topic, schema, count) in expect {
        assert_eq!(by_topic[topic], (schema.to_string(), count), "{topic}");
    }
    assert_eq!(stats.message_count, 1 + 9 * n as u64);
    assert_eq!(stats.message_start_time, 0);
    assert_eq!(stats.message_end_time, time_to_ns(T_END).unwrap());
    // Chunks are zstd-compressed and there are several of them (modest chunk size).
    assert!(
        summary.chunk_indexes.len() > 3,
        "{} chunks",
        summary.chunk_indexes.len()
    );
    assert!(summary
        .chunk_indexes
        .iter()
        .all(|c| c.compression == "zstd"));

    // The MessageStream agrees with the statistics.
    let all = read_all(&path);
    for (topic, (_, count)) in &by_topic {
        assert_eq!(all[topic].len() as u64, *count, "{topic}");
    }
}

#[test]
fn metadata_record_and_message() {
    let (path, _) = write_log("meta.mcap", 5);
    let buf = std::fs::read(&path).unwrap();
    let summary = mcap::Summary::read(&buf).unwrap().unwrap();
    assert_eq!(summary.metadata_indexes.len(), 1);
    let rec = mcap::read::metadata(&buf, &summary.metadata_indexes[0]).unwrap();
    assert_eq!(rec.name, topics::METADATA_RECORD_NAME);
    let md = demo::metadata(&Precession::EXAMPLE, T_END, 5);
    assert_eq!(rec.metadata["software_version"], md.software_version);
    assert_eq!(rec.metadata["case.samples"], "5");
    assert_eq!(rec.metadata["integrator.method"], "closed-form (demo)");
    let case: Value = serde_json::from_str(&rec.metadata["case"]).unwrap();
    assert_eq!(case, md.case);

    let all = read_all(&path);
    let m = &all[topics::METADATA];
    assert_eq!(m.len(), 1);
    assert_eq!(m[0].log_time, 0);
    let back: rsts_mcap::Metadata = serde_json::from_slice(&m[0].data).unwrap();
    assert_eq!(back, md);
}

#[test]
fn values_equal_what_was_logged() {
    let n = 120;
    let (path, samples) = write_log("values.mcap", n);
    let all = read_all(&path);

    let exact = &all[topics::EXACT_STATE];
    let integrated = &all[topics::INTEGRATED_STATE];
    let errors = &all[topics::ERRORS];
    for (i, s) in samples.iter().enumerate() {
        let ns = time_to_ns(s.t).unwrap();
        for (msg, st) in [
            (&exact[i], s.exact.unwrap()),
            (&integrated[i], s.integrated.unwrap()),
        ] {
            assert_eq!(msg.log_time, ns);
            assert_eq!(msg.publish_time, ns);
            let v = json(msg);
            // serde_json round-trips f64 exactly.
            assert_eq!(v["t"].as_f64().unwrap(), s.t);
            // Rows of Q as alpha, beta, gamma.
            for (i, row) in ["alpha", "beta", "gamma"].into_iter().enumerate() {
                let r: [f64; 3] = serde_json::from_value(v[row].clone()).unwrap();
                assert_eq!(r, st.q[i], "{row}");
            }
            let w: [f64; 3] = serde_json::from_value(v["omega"].clone()).unwrap();
            assert_eq!(w, st.omega);
            let wf: [f64; 3] = serde_json::from_value(v["omega_fixed"].clone()).unwrap();
            assert_eq!(wf, st.omega_fixed);
            assert_eq!(v["h"].as_f64().unwrap(), st.h);
            assert_eq!(v["k"].as_f64().unwrap(), st.k);
            assert_eq!(v["g"].as_f64().unwrap(), st.g);
        }
        let e = s.errors.unwrap();
        let v = json(&errors[i]);
        let back: rsts_mcap::ErrorSample = serde_json::from_value(v.clone()).unwrap();
        assert_eq!(back, e);
        assert_eq!(v["t"].as_f64().unwrap(), s.t);
    }
    // Errors are not trivially zero in the demo (so the comparison above means something).
    assert!(samples.last().unwrap().errors.unwrap().state_error > 1e-4);
}

#[test]
fn frame_transforms_reproduce_q() {
    let n = 80;
    let (path, samples) = write_log("tf.mcap", n);
    let all = read_all(&path);
    let tf = &all[topics::TF];
    assert_eq!(tf.len(), 2 * n);
    for (i, s) in samples.iter().enumerate() {
        for (j, (child, st)) in [
            (topics::FRAME_BODY_EXACT, s.exact.unwrap()),
            (topics::FRAME_BODY_INTEGRATED, s.integrated.unwrap()),
        ]
        .into_iter()
        .enumerate()
        {
            let m = &tf[2 * i + j];
            let v = json(m);
            assert_eq!(v["parent_frame_id"], topics::FRAME_WORLD);
            assert_eq!(v["child_frame_id"], child);
            let ns = time_to_ns(s.t).unwrap();
            assert_eq!(v["timestamp"]["sec"].as_u64().unwrap(), ns / 1_000_000_000);
            assert_eq!(v["timestamp"]["nsec"].as_u64().unwrap(), ns % 1_000_000_000);
            assert_eq!(v3(&v["translation"]), [0.0; 3]);
            let q: Quaternion = serde_json::from_value(v["rotation"].clone()).unwrap();
            // Rotating body axis e_k gives its world components, column k of Q;
            // rotating ω gives Ω.
            for k in 0..3 {
                let mut e = [0.0; 3];
                e[k] = 1.0;
                let col = q.rotate(e);
                for r in 0..3 {
                    assert!((col[r] - st.q[r][k]).abs() < 1e-14, "sample {i}");
                }
            }
            let w = q.rotate(st.omega);
            for r in 0..3 {
                assert!((w[r] - st.omega_fixed[r]).abs() < 1e-13);
            }
        }
    }
}

fn lines(v: &Value) -> Vec<Vec<[f64; 3]>> {
    let mut out = Vec::new();
    for e in v["entities"].as_array().unwrap() {
        for l in e["lines"].as_array().unwrap() {
            assert_eq!(l["type"], 0, "LINE_STRIP");
            out.push(l["points"].as_array().unwrap().iter().map(v3).collect());
        }
    }
    out
}

#[test]
fn hodographs_are_incremental() {
    let n = 400;
    let (path, samples) = write_log("hodo.mcap", n);
    let all = read_all(&path);
    let cases: [(&str, &str, bool, fn(&rsts_mcap::Sample) -> [f64; 3]); 4] = [
        (
            topics::EXACT_HODOGRAPH_MOVING,
            topics::FRAME_BODY_EXACT,
            true,
            |s| s.exact.unwrap().omega,
        ),
        (
            topics::EXACT_HODOGRAPH_FIXED,
            topics::FRAME_WORLD,
            false,
            |s| s.exact.unwrap().omega_fixed,
        ),
        (
            topics::INTEGRATED_HODOGRAPH_MOVING,
            topics::FRAME_BODY_INTEGRATED,
            true,
            |s| s.integrated.unwrap().omega,
        ),
        (
            topics::INTEGRATED_HODOGRAPH_FIXED,
            topics::FRAME_WORLD,
            false,
            |s| s.integrated.unwrap().omega_fixed,
        ),
    ];
    let mut colors = Vec::new();
    for (topic, frame, locked, point) in cases {
        let msgs = &all[topic];
        assert_eq!(msgs.len(), n);
        let mut ids = std::collections::HashSet::new();
        let sizes: Vec<usize> = msgs.iter().map(|m| m.data.len()).collect();
        for (i, m) in msgs.iter().enumerate() {
            let v = json(m);
            assert_eq!(v["deletions"].as_array().unwrap().len(), 0);
            for e in v["entities"].as_array().unwrap() {
                assert_eq!(e["frame_id"], frame);
                assert_eq!(e["frame_locked"], locked);
                assert_eq!(e["lifetime"]["sec"], 0);
                assert_eq!(e["lifetime"]["nsec"], 0);
                let id = e["id"].as_str().unwrap().to_string();
                if !e["lines"].as_array().unwrap().is_empty() {
                    // Segment entities never reuse an id: the curve accumulates.
                    assert!(ids.insert(id), "{topic}: segment id reused");
                    colors.push((topic, e["lines"][0]["color"].clone()));
                } else {
                    assert_eq!(id, "current");
                    // The arrow points along the current vector and has its length.
                    let a = &e["arrows"][0];
                    let q: Quaternion =
                        serde_json::from_value(a["pose"]["orientation"].clone()).unwrap();
                    let d = q.rotate([1.0, 0.0, 0.0]);
                    let p = point(&samples[i]);
                    let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                    let total =
                        a["shaft_length"].as_f64().unwrap() + a["head_length"].as_f64().unwrap();
                    assert!((total - len).abs() < 1e-12);
                    for k in 0..3 {
                        assert!((d[k] * len - p[k]).abs() < 1e-9);
                    }
                }
            }
            let ls = lines(&v);
            if i == 0 {
                assert!(ls.is_empty(), "no segment before the second point");
            } else {
                // Only the new segment: previous point → current point.
                assert_eq!(ls, vec![vec![point(&samples[i - 1]), point(&samples[i])]]);
            }
        }
        // Message size does not grow with t (ids gain a digit or two at most).
        let early = sizes[1..10].iter().max().unwrap();
        let late = sizes[n - 10..].iter().max().unwrap();
        assert!(*late <= early + 8, "{topic}: {early} -> {late} bytes");
    }
    // Exact and integrated curves have different colours.
    let exact_c = &colors
        .iter()
        .find(|c| c.0 == topics::EXACT_HODOGRAPH_FIXED)
        .unwrap()
        .1;
    let integ_c = &colors
        .iter()
        .find(|c| c.0 == topics::INTEGRATED_HODOGRAPH_FIXED)
        .unwrap()
        .1;
    assert_ne!(exact_c, integ_c);
}

#[test]
fn size_per_sample_is_a_few_kilobytes() {
    let n = 1000;
    let path = tmp("size.mcap");
    let p = Precession::EXAMPLE;
    let mut log = TrajectoryLog::create(&path, &demo::metadata(&p, T_END, n)).unwrap();
    for s in samples(n) {
        log.log_sample(&s).unwrap();
    }
    let stats = log.finish().unwrap();
    assert_eq!(stats.samples, n as u64);
    assert_eq!(stats.messages, 1 + 9 * n as u64);
    let on_disk = std::fs::metadata(&path).unwrap().len() as f64 / n as f64;
    let raw = stats.payload_bytes as f64 / n as f64;
    eprintln!("bytes per sample: {on_disk:.0} on disk, {raw:.0} uncompressed");
    assert!(on_disk < 2048.0, "{on_disk} B/sample on disk");
    assert!(raw < 8192.0, "{raw} B/sample uncompressed");
    // Every single message stays small.
    let all = read_all(&path);
    for (topic, msgs) in all {
        for m in msgs {
            assert!(m.data.len() < 2048, "{topic}: {} bytes", m.data.len());
        }
    }
}

#[test]
fn summarize_and_extract_a_complete_file() {
    let n = 250;
    let (path, samples) = write_log("inspect.mcap", n);
    let s = inspect::summarize(&path).unwrap();
    assert!(!s.recovered, "{:?}", s.notes);
    assert!(s.notes.is_empty());
    assert!(s.has_summary_section);
    assert_eq!(s.message_count, 1 + 9 * n as u64);
    assert_eq!(s.start_time_ns, Some(0));
    assert_eq!(s.end_time_ns, Some(time_to_ns(T_END).unwrap()));
    let tf = s.channels.iter().find(|c| c.topic == topics::TF).unwrap();
    assert_eq!(tf.schema_name.as_deref(), Some("foxglove.FrameTransform"));
    assert_eq!(tf.message_count, 2 * n as u64);
    assert_eq!(s.metadata.len(), 1);
    assert_eq!(s.metadata[0].metadata["case.samples"], n.to_string());
    // Maxima of |errors| equal the ones computed from the samples.
    let errs: Vec<_> = samples.iter().map(|s| (s.t, s.errors.unwrap())).collect();
    let check = |field: &str, get: fn(&rsts_mcap::ErrorSample) -> f64| {
        let (t, m) = errs.iter().map(|(t, e)| (*t, get(e).abs())).fold(
            (f64::NAN, f64::NEG_INFINITY),
            |a, b| if b.1 > a.1 { b } else { a },
        );
        let fm = s.error_maxima.iter().find(|f| f.field == field).unwrap();
        assert_eq!(fm.max_abs, m, "{field}");
        assert!((fm.at_t - t).abs() < 1e-9, "{field}: {} vs {t}", fm.at_t);
        assert_eq!(fm.non_finite, 0);
    };
    check("state_error", |e| e.state_error);
    check("orientation_error", |e| e.orientation_error);
    check("drift_h", |e| e.drift_h);
    check("constraint_drift", |e| e.constraint_drift);
    assert!(s.error_maxima.iter().all(|f| f.field != "t"));
    assert_eq!(s.error_maxima.len(), 7);
    let text = s.to_string();
    assert!(text.contains("status: complete"));
    assert!(text.contains("/errors"));
    assert!(text.contains("state_error"));
    // Serialisable for `--format json` style output.
    let j = serde_json::to_value(&s).unwrap();
    assert_eq!(j["recovered"], false);

    let series = inspect::extract(&path, topics::EXACT_STATE).unwrap();
    assert!(!series.recovered);
    assert_eq!(series.points.len(), n);
    for (p, smp) in series.points.iter().zip(&samples) {
        assert_eq!(p.log_time_ns, time_to_ns(smp.t).unwrap());
        assert_eq!(
            p.value["omega"][1].as_f64().unwrap(),
            smp.exact.unwrap().omega[1]
        );
    }
    let csv = series.to_csv();
    let mut rows = csv.lines();
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    // The CSV contract (docs/output.md): t, omega1 … beta3, the rest, log_time.
    assert_eq!(
        &header[..10],
        &[
            "t", "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2",
            "beta3"
        ]
    );
    assert_eq!(header.last(), Some(&"log_time"));
    let col = header.iter().position(|h| *h == "omega1").unwrap();
    let qcol = header.iter().position(|h| *h == "beta3").unwrap();
    for (row, smp) in rows.zip(&samples) {
        let f: Vec<&str> = row.split(',').collect();
        assert_eq!(f.len(), header.len());
        assert_eq!(f[col].parse::<f64>().unwrap(), smp.exact.unwrap().omega[0]);
        assert_eq!(f[qcol].parse::<f64>().unwrap(), smp.exact.unwrap().q[1][2]);
    }
    let js: Value = serde_json::from_str(&series.to_json()).unwrap();
    assert_eq!(js.as_array().unwrap().len(), n);
    assert_eq!(
        js[3]["message"]["h"].as_f64().unwrap(),
        samples[3].exact.unwrap().h
    );

    match inspect::extract(&path, "/nope") {
        Err(rsts_mcap::InspectError::UnknownTopic { available, .. }) => {
            assert!(available.contains(&topics::ERRORS.to_string()))
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn drop_without_finish_leaves_the_previous_file_and_finish_replaces_it() {
    let n = 50;
    let dir = tmp("dropped");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("dropped.mcap");
    std::fs::write(&path, b"previous").unwrap();
    {
        let mut log =
            TrajectoryLog::create(&path, &demo::metadata(&Precession::EXAMPLE, T_END, n)).unwrap();
        for s in samples(n).iter().take(20) {
            log.log_sample(s).unwrap();
        }
        assert_eq!(std::fs::read(&path).unwrap(), b"previous", "touched early");
        // Dropped here, as when a run fails: the log is discarded whole.
    }
    assert_eq!(std::fs::read(&path).unwrap(), b"previous");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "a temporary was left: {names:?}");
    // Finished (also what the CLI does on the first Ctrl-C): a complete file replaces it.
    let mut log =
        TrajectoryLog::create(&path, &demo::metadata(&Precession::EXAMPLE, T_END, n)).unwrap();
    for s in samples(n).iter().take(20) {
        log.log_sample(s).unwrap();
    }
    log.finish().unwrap();
    let s = inspect::summarize(&path).unwrap();
    assert!(!s.recovered, "{:?}", s.notes);
    assert!(s.has_summary_section);
    assert_eq!(s.message_count, 1 + 9 * 20);
    let buf = std::fs::read(&path).unwrap();
    assert!(buf.ends_with(mcap::MAGIC));
}

#[test]
fn partial_samples_and_bad_times() {
    let path = tmp("partial.mcap");
    let mut log =
        TrajectoryLog::create(&path, &demo::metadata(&Precession::EXAMPLE, 1.0, 3)).unwrap();
    let mut s = samples(3);
    s[1].integrated = None;
    s[1].errors = None;
    s[2].exact = None;
    for x in &s {
        log.log_sample(x).unwrap();
    }
    // Invalid times are rejected without breaking the log.
    let mut bad = s[2];
    bad.t = f64::NAN;
    assert!(matches!(
        log.log_sample(&bad),
        Err(rsts_mcap::LogError::BadTime(_))
    ));
    bad.t = -1.0;
    assert!(log.log_sample(&bad).is_err());
    bad.t = 0.1;
    assert!(matches!(
        log.log_sample(&bad),
        Err(rsts_mcap::LogError::TimeNotMonotonic { .. })
    ));
    log.finish().unwrap();
    let sum = inspect::summarize(&path).unwrap();
    assert!(!sum.recovered);
    let count = |t: &str| {
        sum.channels
            .iter()
            .find(|c| c.topic == t)
            .unwrap()
            .message_count
    };
    assert_eq!(count(topics::EXACT_STATE), 2);
    assert_eq!(count(topics::INTEGRATED_STATE), 2);
    assert_eq!(count(topics::ERRORS), 2);
    assert_eq!(count(topics::TF), 4);
    // The integrated hodograph connects sample 0 to sample 2 (sample 1 had none).
    let h = inspect::extract(&path, topics::INTEGRATED_HODOGRAPH_FIXED).unwrap();
    assert_eq!(h.points.len(), 2);
    let seg = &h.points[1].value["entities"][0]["lines"][0]["points"];
    assert_eq!(
        seg[0]["x"].as_f64().unwrap(),
        s[0].integrated.unwrap().omega_fixed[0]
    );
    assert_eq!(
        seg[1]["x"].as_f64().unwrap(),
        s[2].integrated.unwrap().omega_fixed[0]
    );
}

#[test]
fn quaternion_of_a_drifted_q_is_still_unit() {
    // An integrated Q that is slightly non-orthogonal still gives a unit quaternion close to it.
    let mut q = Precession::EXAMPLE.state(1.3).q;
    q[0][1] += 1e-7;
    let quat = Quaternion::from_orientation(&q);
    let n = (quat.x * quat.x + quat.y * quat.y + quat.z * quat.z + quat.w * quat.w).sqrt();
    assert!((n - 1.0).abs() < 1e-15);
    let r = quat.to_rotation_matrix();
    for i in 0..3 {
        for j in 0..3 {
            assert!((r[i][j] - q[i][j]).abs() < 1e-6);
        }
    }
}
