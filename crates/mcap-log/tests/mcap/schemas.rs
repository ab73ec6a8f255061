//! The JSON Schemas are in the subset that the JSON-schema parser of Foxglove and Lichtblick
//! (`parseJsonSchema` in their mcap-support package) accepts — it throws, and the channel
//! cannot be shown, otherwise: every object has `properties`; every field has a `type` among
//! boolean/string/number/integer/object/array, or is an enum given as `oneOf` alternatives
//! with a numeric `const` and a `title`; no `$ref`; array items are primitives or objects
//! (no arrays of arrays); strings have no `contentEncoding` other than `base64`. The two
//! Foxglove schemas are the official ones of `@foxglove/schemas` (vendored in
//! `schemas/foxglove/`). And every logged message conforms to the schema of its channel,
//! `required` fields and integer bounds included (checked here offline; the CLI test
//! `mcap_readers` validates them again with Ajv against the npm package's schemas).

use crate::common;

use common::write_log;
use rsts_mcap::schemas;
use serde_json::Value;

const PRIMITIVES: [&str; 4] = ["boolean", "string", "number", "integer"];

/// Checks that `schema` (an object schema) is in the supported subset; `path` for messages.
fn check_supported(schema: &Value, path: &str) {
    assert_eq!(schema["type"], "object", "{path}: not an object schema");
    let props = schema["properties"]
        .as_object()
        .unwrap_or_else(|| panic!("{path}: object without properties"));
    for (name, field) in props {
        let p = format!("{path}.{name}");
        assert!(field.get("$ref").is_none(), "{p}: $ref");
        if let Some(alts) = field.get("oneOf") {
            let alts = alts.as_array().unwrap();
            assert!(!alts.is_empty());
            assert!(
                alts.iter()
                    .all(|a| a["const"].is_u64() && a["title"].is_string()),
                "{p}: oneOf must be titled numeric consts"
            );
            continue;
        }
        let ty = field["type"]
            .as_str()
            .unwrap_or_else(|| panic!("{p}: field without a type"));
        match ty {
            "string" => {
                let enc = field.get("contentEncoding");
                assert!(
                    enc.is_none() || enc == Some(&Value::from("base64")),
                    "{p}: {enc:?}"
                );
            }
            t if PRIMITIVES.contains(&t) => {}
            "object" => check_supported(field, &p),
            "array" => {
                let items = &field["items"];
                let it = items["type"]
                    .as_str()
                    .unwrap_or_else(|| panic!("{p}: untyped items"));
                match it {
                    "object" => check_supported(items, &format!("{p}[]")),
                    t if PRIMITIVES.contains(&t) => {}
                    other => panic!("{p}: arrays of {other} are not supported"),
                }
            }
            other => panic!("{p}: unsupported type {other}"),
        }
    }
}

/// Checks that `msg` conforms to `schema`: every `required` field present, no field outside
/// the schema, every value of the declared type (numbers may be null: non-finite values),
/// integers within `minimum`/`maximum`, arrays within `minItems`/`maxItems`.
fn conforms(msg: &Value, schema: &Value, path: &str) -> Result<(), String> {
    if let Some(alts) = schema.get("oneOf") {
        return match alts.as_array().unwrap().iter().any(|a| a["const"] == *msg) {
            true => Ok(()),
            false => Err(format!("{path}: {msg} not among the enum values")),
        };
    }
    let fail = |what: &str| Err(format!("{path}: {msg} {what}"));
    match schema["type"].as_str().unwrap() {
        "object" => {
            let Some(obj) = msg.as_object() else {
                return fail("is not an object");
            };
            let props = schema["properties"].as_object().unwrap();
            for r in schema["required"].as_array().into_iter().flatten() {
                if !obj.contains_key(r.as_str().unwrap()) {
                    return Err(format!("{path}: required field {r} missing"));
                }
            }
            if props.is_empty() {
                return Ok(()); // free-form object (metadata case and integrator)
            }
            for (k, v) in obj {
                let Some(sub) = props.get(k) else {
                    return Err(format!("{path}.{k}: field not in the schema"));
                };
                conforms(v, sub, &format!("{path}.{k}"))?;
            }
            Ok(())
        }
        "array" => {
            let Some(items) = msg.as_array() else {
                return fail("is not an array");
            };
            let n = items.len() as u64;
            if schema["minItems"].as_u64().is_some_and(|m| n < m)
                || schema["maxItems"].as_u64().is_some_and(|m| n > m)
            {
                return fail("has the wrong length");
            }
            for (i, v) in items.iter().enumerate() {
                conforms(v, &schema["items"], &format!("{path}[{i}]"))?;
            }
            Ok(())
        }
        "number" if msg.is_number() || msg.is_null() => Ok(()),
        "integer" if msg.is_i64() || msg.is_u64() => {
            let x = msg.as_f64().unwrap();
            if schema["minimum"].as_f64().is_some_and(|m| x < m)
                || schema["maximum"].as_f64().is_some_and(|m| x > m)
            {
                return fail("is out of range");
            }
            Ok(())
        }
        "string" if msg.is_string() => Ok(()),
        "boolean" if msg.is_boolean() => Ok(()),
        other => fail(&format!("is not of type {other}")),
    }
}

#[test]
fn schemas_are_in_the_supported_subset() {
    for (name, text) in [
        (
            schemas::FRAME_TRANSFORM_NAME,
            schemas::FRAME_TRANSFORM.as_str(),
        ),
        (schemas::SCENE_UPDATE_NAME, schemas::SCENE_UPDATE.as_str()),
        (schemas::BODY_STATE_NAME, schemas::BODY_STATE.as_str()),
        (schemas::ERRORS_NAME, schemas::ERRORS.as_str()),
        (schemas::METADATA_NAME, schemas::METADATA.as_str()),
    ] {
        let v: Value = serde_json::from_str(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(v["title"], name);
        assert!(!text.contains("$ref"), "{name}");
        check_supported(&v, name);
    }
    // The Foxglove schemas have the fields Foxglove's 3D panel reads.
    let su: Value = serde_json::from_str(&schemas::SCENE_UPDATE).unwrap();
    let entity = &su["properties"]["entities"]["items"]["properties"];
    for f in [
        "timestamp",
        "frame_id",
        "id",
        "lifetime",
        "frame_locked",
        "lines",
        "arrows",
    ] {
        assert!(entity.get(f).is_some(), "SceneEntity.{f}");
    }
    let line = &entity["lines"]["items"]["properties"];
    for f in [
        "type",
        "pose",
        "thickness",
        "scale_invariant",
        "points",
        "color",
        "colors",
        "indices",
    ] {
        assert!(line.get(f).is_some(), "LinePrimitive.{f}");
    }
    let tf: Value = serde_json::from_str(&schemas::FRAME_TRANSFORM).unwrap();
    for f in [
        "timestamp",
        "parent_frame_id",
        "child_frame_id",
        "translation",
        "rotation",
    ] {
        assert!(tf["properties"].get(f).is_some(), "FrameTransform.{f}");
    }
}

/// The messages of a log with their channel's schema.
fn messages(name: &str, n: usize) -> Vec<(String, Value, Value)> {
    let (path, _) = write_log(name, n);
    let buf = std::fs::read(&path).unwrap();
    mcap::MessageStream::new(&buf)
        .unwrap()
        .map(|m| {
            let m = m.unwrap();
            let schema = m.channel.schema.as_ref().unwrap();
            (
                m.channel.topic.clone(),
                serde_json::from_slice(&schema.data).unwrap(),
                serde_json::from_slice(&m.data).unwrap(),
            )
        })
        .collect()
}

#[test]
fn every_message_conforms_to_its_schema() {
    let all = messages("schemas.mcap", 30);
    assert_eq!(all.len(), 1 + 9 * 30);
    for (topic, schema, msg) in &all {
        conforms(msg, schema, topic).unwrap();
    }
}

#[test]
fn the_conformance_check_fails_on_wrong_messages() {
    let all = messages("schemas-wrong.mcap", 3);
    let pick = |topic: &str| {
        all.iter()
            .rev()
            .find(|(t, _, _)| t == topic)
            .cloned()
            .unwrap()
    };
    let (_, su, mut hodo) = pick("/exact/hodograph/fixed");
    hodo["entities"][0]
        .as_object_mut()
        .unwrap()
        .remove("frame_locked");
    let e = conforms(&hodo, &su, "su").unwrap_err();
    assert!(e.contains("required field \"frame_locked\" missing"), "{e}");
    let (_, tf, mut msg) = pick("/tf");
    msg["timestamp"]["nsec"] = 1_000_000_000u64.into();
    assert!(conforms(&msg, &tf, "tf")
        .unwrap_err()
        .contains("out of range"));
    let (_, er, mut errors) = pick("/errors");
    errors.as_object_mut().unwrap().remove("drift_g");
    assert!(conforms(&errors, &er, "errors").is_err());
    let (_, st, mut state) = pick("/exact/state");
    state["omega"] = serde_json::json!([1.0, 2.0]);
    assert!(conforms(&state, &st, "state").is_err());
}

/// The Foxglove schemas the files carry are the vendored official ones, unchanged as JSON.
#[test]
fn foxglove_schemas_are_the_official_files() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("schemas/foxglove");
    for (file, emitted) in [
        ("FrameTransform.json", schemas::FRAME_TRANSFORM.as_str()),
        ("SceneUpdate.json", schemas::SCENE_UPDATE.as_str()),
    ] {
        let official: Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join(file)).unwrap()).unwrap();
        let emitted: Value = serde_json::from_str(emitted).unwrap();
        assert_eq!(emitted, official, "{file}");
        assert!(official["$comment"]
            .as_str()
            .unwrap()
            .contains("foxglove-sdk"));
        assert!(official["required"].is_array(), "{file}");
    }
    let su: Value = serde_json::from_str(&schemas::SCENE_UPDATE).unwrap();
    let entity = &su["properties"]["entities"]["items"];
    assert_eq!(entity["required"].as_array().unwrap().len(), 14);
}

/// `/errors` carries every error and drift of the schema with its log10 companion, equal to
/// log10 |value|, and nothing else; companions are left out where the value is 0.
#[test]
fn errors_carry_log10_fields() {
    let all = messages("schemas-log10.mcap", 20);
    let errors: Vec<&Value> = all
        .iter()
        .filter(|(t, _, _)| t == "/errors")
        .map(|(_, _, m)| m)
        .collect();
    assert_eq!(errors.len(), 20);
    let mut with_logs = 0;
    for m in &errors {
        let obj = m.as_object().unwrap();
        for (name, _) in schemas::ERROR_FIELDS {
            let x = obj[*name].as_f64().unwrap();
            match obj.get(&schemas::log10_field(name)) {
                Some(l) => {
                    let l = l.as_f64().unwrap();
                    assert!((10f64.powf(l) - x.abs()).abs() <= 1e-12 * x.abs(), "{name}");
                    with_logs += 1;
                }
                None => assert_eq!(x, 0.0, "{name}: log10 missing for {x}"),
            }
        }
        let logs = obj.keys().filter(|k| k.starts_with("log10_")).count();
        assert!(logs <= schemas::ERROR_FIELDS.len() + schemas::OPTIONAL_ERROR_FIELDS.len());
    }
    // The demo motion has non-zero errors after t = 0.
    assert!(with_logs >= 19 * 3, "{with_logs}");
}
