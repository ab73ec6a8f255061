//! JSON Schemas (schema encoding `jsonschema`) of every channel.
//!
//! The two Foxglove schemas follow Foxglove's published JSON schemas for
//! `foxglove.FrameTransform` and `foxglove.SceneUpdate` (same field names, types and
//! enum values), so Foxglove and Lichtblick decode the messages with their built-in
//! 3D panel and no extension. The `rsts.*` schemas describe our numeric series so that
//! the Plot panel lists their fields.
//!
//! Foxglove's JSON-schema parser does not resolve `$ref`, so every sub-schema is inlined
//! in the emitted text; here each one is written once, as a function returning its
//! [`Value`], and each schema is built (and serialized) once, on first use.

use std::sync::LazyLock;

use serde_json::{json, Map, Value};

/// Schema name of the body-orientation transforms.
pub const FRAME_TRANSFORM_NAME: &str = "foxglove.FrameTransform";
/// Schema name of the hodograph scene updates.
pub const SCENE_UPDATE_NAME: &str = "foxglove.SceneUpdate";
/// Schema name of `/exact/state` and `/integrated/state`.
pub const BODY_STATE_NAME: &str = "rsts.BodyState";
/// Schema name of `/errors`.
pub const ERRORS_NAME: &str = "rsts.Errors";
/// Schema name of `/metadata`.
pub const METADATA_NAME: &str = "rsts.Metadata";

/// `foxglove.FrameTransform`.
pub static FRAME_TRANSFORM: LazyLock<String> = LazyLock::new(|| {
    json!({
        "title": FRAME_TRANSFORM_NAME,
        "description": "A transform between two reference frames in 3D space",
        "type": "object",
        "properties": {
            "timestamp": described(time(), "Timestamp of transform"),
            "parent_frame_id": described(string(), "Name of the parent frame"),
            "child_frame_id": described(string(), "Name of the child frame"),
            "translation": described(
                describe_fields(vector3(), |k| format!("{k} coordinate length")),
                "Translation component of the transform",
            ),
            "rotation": described(
                describe_fields(quaternion(), |k| format!("{k} value")),
                "Rotation component of the transform",
            ),
        }
    })
    .to_string()
});

/// `foxglove.SceneUpdate`, every sub-schema inlined (no `$ref`: Foxglove's JSON-schema
/// parser does not resolve references), as in Foxglove's published schema.
pub static SCENE_UPDATE: LazyLock<String> = LazyLock::new(|| {
    let deletion = object(
        "foxglove.SceneEntityDeletion",
        json!({
            "timestamp": time(),
            "type": enumeration(
                "foxglove.SceneEntityDeletionType",
                json!([{"title": "MATCHING_ID", "const": 0}, {"title": "ALL", "const": 1}]),
            ),
            "id": string(),
        }),
    );
    let line_type = described(
        enumeration(
            "foxglove.LineType",
            json!([
                {
                    "title": "LINE_STRIP",
                    "const": 0,
                    "description": "Connected line segments: 0-1, 1-2, ..., (n-1)-n"
                },
                {
                    "title": "LINE_LOOP",
                    "const": 1,
                    "description": "Closed polygon: 0-1, 1-2, ..., (n-1)-n, n-0"
                },
                {
                    "title": "LINE_LIST",
                    "const": 2,
                    "description": "Individual line segments: 0-1, 2-3, 4-5, ..."
                }
            ]),
        ),
        "An enumeration indicating how input points should be interpreted to create lines",
    );
    let entity = object(
        "foxglove.SceneEntity",
        json!({
            "timestamp": time(),
            "frame_id": string(),
            "id": string(),
            "lifetime": duration(),
            "frame_locked": boolean(),
            "metadata": array(object(
                "foxglove.KeyValuePair",
                json!({"key": string(), "value": string()}),
            )),
            "arrows": primitives("Arrow", json!({
                "shaft_length": number(),
                "shaft_diameter": number(),
                "head_length": number(),
                "head_diameter": number(),
            })),
            "cubes": primitives("Cube", json!({"size": vector3()})),
            "spheres": primitives("Sphere", json!({"size": vector3()})),
            "cylinders": primitives("Cylinder", json!({
                "size": vector3(),
                "bottom_scale": number(),
                "top_scale": number(),
            })),
            "lines": primitives("Line", json!({
                "type": line_type,
                "thickness": {"type": "number", "minimum": 0},
                "scale_invariant": boolean(),
                "points": array(point3()),
                "colors": array(color()),
                "indices": array(unsigned()),
            })),
            "triangles": primitives("TriangleList", json!({
                "points": array(point3()),
                "colors": array(color()),
                "indices": array(unsigned()),
            })),
            "texts": primitives("Text", json!({
                "billboard": boolean(),
                "font_size": number(),
                "scale_invariant": boolean(),
                "text": string(),
            })),
            "models": primitives("Model", json!({
                "scale": vector3(),
                "override_color": boolean(),
                "url": string(),
                "media_type": string(),
                "data": {"type": "string", "contentEncoding": "base64"},
            })),
        }),
    );
    json!({
        "title": SCENE_UPDATE_NAME,
        "description": "An update to the entities displayed in a 3D scene",
        "type": "object",
        "properties": {"deletions": array(deletion), "entities": array(entity)}
    })
    .to_string()
});

/// `rsts.BodyState`: one body state of the exact or the integrated motion.
pub static BODY_STATE: LazyLock<String> = LazyLock::new(|| {
    json!({
        "title": BODY_STATE_NAME,
        "description": "State of the rigid body at motion time t. Q has rows alpha, beta, gamma (fixed axes in the body frame), Omega = Q omega.",
        "type": "object",
        "properties": {
            "t": described(number(), "motion time (s)"),
            "alpha": triple("row 1 of Q: the fixed axis alpha in the body frame"),
            "beta": triple("row 2 of Q: the fixed axis beta in the body frame"),
            "gamma": triple("row 3 of Q: the fixed axis gamma in the body frame"),
            "quaternion": {
                "type": "object",
                "description": "attitude quaternion (body to world) from Q",
                "properties": numbers(&["x", "y", "z", "w"]),
            },
            "omega": triple("angular velocity, body frame"),
            "omega_fixed": triple("angular velocity, fixed frame (Q omega)"),
            "h": described(number(), "energy integral"),
            "k": described(number(), "second (Kowalevski-type) integral"),
            "g": described(number(), "third integral"),
        }
    })
    .to_string()
});

/// `rsts.Errors`: differences between the integrated and the exact motion.
pub static ERRORS: LazyLock<String> = LazyLock::new(|| {
    let fields = [
        ("t", "motion time (s)"),
        ("state_error", "norm of the state difference"),
        (
            "orientation_error",
            "angle or norm of the orientation difference",
        ),
        (
            "drift_h",
            "drift of the integral h along the integrated motion",
        ),
        (
            "drift_k",
            "drift of the integral k along the integrated motion",
        ),
        (
            "drift_g",
            "drift of the integral g along the integrated motion",
        ),
        (
            "constraint_drift",
            "drift of the geometric constraints (orthonormality of Q)",
        ),
        (
            "off_n",
            "drift of the on-N integral relations max(|K - r^4 m^2|, |2G - p^2 H - r^4 m|)",
        ),
        (
            "distance_from_n",
            "distance of the integrated state from its nearest point on N (state units)",
        ),
        (
            "x_phi",
            "|X_Phi| at the integrated state, Phi = r^4 K - (2G - p^2 H)^2",
        ),
        (
            "along_n",
            "distance of the nearest point on N from the exact state (drift along N)",
        ),
        (
            "phase_error_psi1",
            "psi1 of the nearest point on N minus the exact psi1 (rad)",
        ),
        (
            "phase_error_psi2",
            "psi2 of the nearest point on N minus the exact psi2 (rad)",
        ),
    ];
    let properties: Map<String, Value> = fields
        .iter()
        .map(|(name, desc)| (name.to_string(), described(number(), desc)))
        .collect();
    json!({
        "title": ERRORS_NAME,
        "description": "Errors of the integrated motion against the exact one at motion time t",
        "type": "object",
        "properties": properties
    })
    .to_string()
});

/// `rsts.Metadata`: the comparison's case, integrator configuration and software version.
pub static METADATA: LazyLock<String> = LazyLock::new(|| {
    let free_object = |desc: &str| json!({"type": "object", "description": desc, "properties": {}});
    json!({
        "title": METADATA_NAME,
        "description": "Case, integrator configuration and software version of one comparison",
        "type": "object",
        "properties": {
            "software_version": string(),
            "case": free_object("the case: a, b, m, h, torus, phases, t_end, samples"),
            "integrator": free_object("method, rtol, atol, digits"),
        }
    })
    .to_string()
});

/// `{"type": "number"}`.
fn number() -> Value {
    json!({"type": "number"})
}

/// `{"type": "string"}`.
fn string() -> Value {
    json!({"type": "string"})
}

/// `{"type": "boolean"}`.
fn boolean() -> Value {
    json!({"type": "boolean"})
}

/// A non-negative integer.
fn unsigned() -> Value {
    json!({"type": "integer", "minimum": 0})
}

/// An array of `items`.
fn array(items: Value) -> Value {
    json!({"type": "array", "items": items})
}

/// An object schema titled `title` with the given `properties`.
fn object(title: &str, properties: Value) -> Value {
    json!({"title": title, "type": "object", "properties": properties})
}

/// An enum: `oneOf` titled numeric `const` alternatives.
fn enumeration(title: &str, alternatives: Value) -> Value {
    json!({"title": title, "oneOf": alternatives})
}

/// `schema` with a `description`.
fn described(mut schema: Value, description: &str) -> Value {
    schema["description"] = description.into();
    schema
}

/// `schema` (an object schema) with a description `describe(name)` on each of its fields.
fn describe_fields(mut schema: Value, describe: impl Fn(&str) -> String) -> Value {
    if let Some(props) = schema["properties"].as_object_mut() {
        for (name, field) in props {
            field["description"] = describe(name).into();
        }
    }
    schema
}

/// The properties of an object whose fields `names` are numbers.
fn numbers(names: &[&str]) -> Value {
    names
        .iter()
        .map(|name| (name.to_string(), number()))
        .collect::<Map<String, Value>>()
        .into()
}

/// Three numbers as an array, described.
fn triple(description: &str) -> Value {
    json!({
        "type": "array",
        "description": description,
        "items": number(),
        "minItems": 3,
        "maxItems": 3
    })
}

/// Nanoseconds, 0..=999999999.
fn nanoseconds() -> Value {
    json!({"type": "integer", "minimum": 0, "maximum": 999_999_999})
}

/// Foxglove's `time`.
fn time() -> Value {
    object("time", json!({"sec": unsigned(), "nsec": nanoseconds()}))
}

/// Foxglove's `duration` (signed seconds).
fn duration() -> Value {
    object(
        "duration",
        json!({"sec": {"type": "integer"}, "nsec": nanoseconds()}),
    )
}

/// `foxglove.Vector3`.
fn vector3() -> Value {
    object("foxglove.Vector3", numbers(&["x", "y", "z"]))
}

/// `foxglove.Point3`.
fn point3() -> Value {
    object("foxglove.Point3", numbers(&["x", "y", "z"]))
}

/// `foxglove.Quaternion`.
fn quaternion() -> Value {
    object("foxglove.Quaternion", numbers(&["x", "y", "z", "w"]))
}

/// `foxglove.Color`.
fn color() -> Value {
    object("foxglove.Color", numbers(&["r", "g", "b", "a"]))
}

/// `foxglove.Pose`.
fn pose() -> Value {
    object(
        "foxglove.Pose",
        json!({"position": vector3(), "orientation": quaternion()}),
    )
}

/// An array of `foxglove.{kind}Primitive`: a `pose`, a `color` and the other `fields`.
fn primitives(kind: &str, fields: Value) -> Value {
    let mut properties = fields;
    properties["pose"] = pose();
    properties["color"] = color();
    array(object(&format!("foxglove.{kind}Primitive"), properties))
}
