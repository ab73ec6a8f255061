//! The JSON Schemas are in the subset that the JSON-schema parser of Foxglove and Lichtblick
//! (`parseJsonSchema` in their mcap-support package) accepts — it throws, and the channel
//! cannot be shown, otherwise: every object has `properties`; every field has a `type` among
//! boolean/string/number/integer/object/array, or is an enum given as `oneOf` alternatives
//! with a numeric `const` and a `title`; no `$ref`; array items are primitives or objects
//! (no arrays of arrays); strings have no `contentEncoding` other than `base64`. And every
//! logged message conforms to the schema of its channel.

mod common;

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

/// Checks that `msg` conforms to `schema`: no field outside the schema, every value of the
/// declared type (numbers may be null: non-finite values).
fn conforms(msg: &Value, schema: &Value, path: &str) {
    if let Some(alts) = schema.get("oneOf") {
        assert!(
            alts.as_array().unwrap().iter().any(|a| a["const"] == *msg),
            "{path}: {msg} not among the enum values"
        );
        return;
    }
    match schema["type"].as_str().unwrap() {
        "object" => {
            let obj = msg
                .as_object()
                .unwrap_or_else(|| panic!("{path}: not an object"));
            let props = schema["properties"].as_object().unwrap();
            if props.is_empty() {
                return; // free-form object (metadata case and integrator)
            }
            for (k, v) in obj {
                let sub = props
                    .get(k)
                    .unwrap_or_else(|| panic!("{path}.{k}: field not in the schema"));
                conforms(v, sub, &format!("{path}.{k}"));
            }
        }
        "array" => {
            for (i, v) in msg
                .as_array()
                .unwrap_or_else(|| panic!("{path}: not an array"))
                .iter()
                .enumerate()
            {
                conforms(v, &schema["items"], &format!("{path}[{i}]"));
            }
        }
        "number" => assert!(
            msg.is_number() || msg.is_null(),
            "{path}: {msg} not a number"
        ),
        "integer" => assert!(msg.is_i64() || msg.is_u64(), "{path}: {msg} not an integer"),
        "string" => assert!(msg.is_string(), "{path}: {msg} not a string"),
        "boolean" => assert!(msg.is_boolean(), "{path}: {msg} not a boolean"),
        other => panic!("{path}: type {other}"),
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

#[test]
fn every_message_conforms_to_its_schema() {
    let (path, _) = write_log("schemas.mcap", 30);
    let buf = std::fs::read(&path).unwrap();
    let mut checked = 0;
    for m in mcap::MessageStream::new(&buf).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().unwrap();
        let s: Value = serde_json::from_slice(&schema.data).unwrap();
        let v: Value = serde_json::from_slice(&m.data).unwrap();
        conforms(&v, &s, &m.channel.topic);
        checked += 1;
    }
    assert_eq!(checked, 1 + 9 * 30);
}
