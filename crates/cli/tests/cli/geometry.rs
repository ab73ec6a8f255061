//! `rsts table1`, `rsts table2` and `rsts surfaces` as a user runs them: the JSON layout, the
//! files written, and bad input (exit 2 with `error: ...`, never a panic).

use serde_json::Value;

use crate::common;
use common::{fails, rsts, tmp};

fn json(args: &[&str]) -> Value {
    let out = rsts(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

fn fails_cleanly(args: &[&str]) -> String {
    let err = fails(args);
    assert!(err.starts_with("error:"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

const LABELS: [&str; 9] = ["I+", "I-", "II+", "II-", "III", "IV+", "IV-", "V", "VI"];

#[test]
fn table2_json_has_one_row_per_camera() {
    let v = json(&["table2", "--a", "1", "--b", "0.5", "--format", "json"]);
    let rows = v["cameras"].as_array().unwrap();
    let labels: Vec<&str> = rows.iter().map(|r| r["camera"].as_str().unwrap()).collect();
    assert_eq!(labels, LABELS);
    for r in rows {
        for key in ["first_partial", "second_partial", "semi_moving"] {
            let k = r[key].as_str().unwrap();
            assert!(k == "oscillation" || k == "rotation", "{key}: {k}");
        }
        let planes = r["symmetry_planes"].as_array().unwrap();
        assert!(!planes.is_empty());
        for p in planes {
            assert!(["omega1", "omega2", "omega3"].contains(&p.as_str().unwrap()));
        }
        let tori = r["tori"].as_u64().unwrap();
        assert!([1, 2, 4].contains(&tori));
        // Consistency of the measured planes with the measured kinds (sec. 3: a reflection of a
        // connected surface needs both flipped radicals to change sign on the torus): a torus
        // with a free sign is never symmetric to all three planes.
        if tori > 1 {
            assert!(planes.len() < 3, "{r}");
        }
    }
}

#[test]
fn table1_json_agrees_with_the_printed_table() {
    let v = json(&["table1", "--format", "json"]);
    let rows = v["cameras"].as_array().unwrap();
    assert_eq!(rows.len(), 9);
    for r in rows {
        assert_eq!(r["roots_agree"], Value::Bool(true), "{r}");
        assert_eq!(r["segments_agree"], Value::Bool(true), "{r}");
    }
    let text = rsts(&["table1", "--b", "0.3"]);
    assert!(text.status.success());
    assert!(String::from_utf8_lossy(&text.stdout).contains("rows agree with the paper"));
}

#[test]
fn surfaces_writes_meshes_pictures_and_scene() {
    let dir = tmp("iii");
    let d = dir.to_str().unwrap();
    let out = rsts(&[
        "surfaces",
        "--m",
        "-2.9877",
        "--h",
        "1.2605",
        "--grid",
        "24",
        "--scene-grid",
        "16",
        "--size",
        "120",
        "--samples",
        "200",
        "--out",
        d,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Camera III has two tori: both written.
    for k in 0..2 {
        for f in ["p.ply", "pi.ply", "p.png", "pi.png", "scene.mcap"] {
            let p = dir.join(format!("torus{k}_{f}"));
            assert!(
                p.metadata().map(|m| m.len() > 100).unwrap_or(false),
                "{}",
                p.display()
            );
        }
    }
    let ply = std::fs::read_to_string(dir.join("torus1_p.ply")).unwrap();
    assert!(ply.contains("element vertex 576") && ply.contains("element face 1152"));
    let png = std::fs::read(dir.join("torus0_pi.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let summary = rsts(&["inspect", dir.join("torus0_scene.mcap").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&summary.stdout);
    for topic in [
        "/tf",
        "/surface/p",
        "/surface/pi",
        "/hodograph/moving",
        "/hodograph/fixed",
    ] {
        assert!(text.contains(topic), "{text}");
    }

    // One torus only, without PLY and MCAP.
    let one = tmp("one");
    let out = rsts(&[
        "surfaces",
        "--m",
        "0.3",
        "--h",
        "-0.375",
        "--torus",
        "0",
        "--grid",
        "16",
        "--size",
        "96",
        "--samples",
        "50",
        "--no-ply",
        "--no-mcap",
        "--out",
        one.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let names: Vec<String> = std::fs::read_dir(&one)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let d = tmp("bad");
    let d = d.to_str().unwrap();
    let e = fails_cleanly(&["surfaces", "--m", "5", "--h", "0", "--out", d]);
    assert!(e.contains("admissible"), "{e}");
    let e = fails_cleanly(&[
        "surfaces", "--m", "0.3", "--h", "-0.375", "--torus", "1", "--out", d,
    ]);
    assert!(e.contains("torus"), "{e}");
    fails_cleanly(&[
        "surfaces", "--m", "0.3", "--h", "-0.375", "--grid", "2", "--out", d,
    ]);
    fails_cleanly(&[
        "surfaces", "--m", "0.3", "--h", "-0.375", "--size", "5", "--out", d,
    ]);
    fails_cleanly(&[
        "surfaces",
        "--m",
        "0.3",
        "--h",
        "-0.375",
        "--periods",
        "0",
        "--out",
        d,
    ]);
    fails_cleanly(&["surfaces", "--m", "nan", "--h", "-0.375", "--out", d]);
    fails_cleanly(&["table2", "--a", "0.5", "--b", "1"]);
    fails_cleanly(&["table1", "--b", "-1"]);
    fails_cleanly(&["table2", "--a", "inf"]);
}

#[test]
fn table2_planes_are_symmetries_of_the_meshes_and_the_others_are_not() {
    use rsts_geometry::classify::reflection_score;
    use rsts_geometry::mesh::{all_tori, local_spacing};
    use rsts_geometry::nearest::KdTree;

    let v = json(&["table2", "--format", "json"]);
    for r in v["cameras"].as_array().unwrap() {
        let (m, h) = (r["m"].as_f64().unwrap(), r["h"].as_f64().unwrap());
        let listed: Vec<usize> = r["symmetry_planes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| match p.as_str().unwrap() {
                "omega1" => 0,
                "omega2" => 1,
                _ => 2,
            })
            .collect();
        // A finer mesh than table2 uses (64): the verdict must not depend on the grid.
        for mesh in all_tori(1.0, 0.5, m, h, 80, 72).unwrap() {
            let spacing = local_spacing(&mesh.omega, &mesh.triangles);
            let tree = KdTree::new(&mesh.omega);
            for axis in 0..3 {
                let score = reflection_score(&mesh.omega, &spacing, &tree, axis);
                if listed.contains(&axis) {
                    assert!(
                        score < 0.1,
                        "{} torus {} axis {axis}: {score}",
                        r["camera"],
                        mesh.torus
                    );
                } else {
                    assert!(
                        score > 3.0,
                        "{} torus {} axis {axis}: {score}",
                        r["camera"],
                        mesh.torus
                    );
                }
            }
        }
    }
}
