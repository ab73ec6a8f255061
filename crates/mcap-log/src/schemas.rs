//! JSON Schemas (schema encoding `jsonschema`) of every channel.
//!
//! The two Foxglove schemas are the official JSON schemas of `@foxglove/schemas` 2.1.0
//! (`foxglove.FrameTransform`, `foxglove.SceneUpdate`, vendored unchanged in
//! `schemas/foxglove/`), so Foxglove and Lichtblick decode the messages with their built-in
//! 3D panel and no extension, and any JSON-schema validator accepts them as Foxglove's own.
//! The `rsts.*` schemas describe our numeric series so that the Plot panel lists their
//! fields; like the official ones they are in the subset Foxglove's JSON-schema parser
//! accepts (every sub-schema inlined, no `$ref`) and list their `required` fields.

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

/// `foxglove.FrameTransform`: the official schema of `@foxglove/schemas` 2.1.0 (vendored in
/// `schemas/foxglove/`, see its README), emitted compact.
pub static FRAME_TRANSFORM: LazyLock<String> =
    LazyLock::new(|| compact(include_str!("../schemas/foxglove/FrameTransform.json")));

/// `foxglove.SceneUpdate`: the official schema of `@foxglove/schemas` 2.1.0 (vendored in
/// `schemas/foxglove/`), emitted compact. Every sub-schema is inlined there (no `$ref`).
pub static SCENE_UPDATE: LazyLock<String> =
    LazyLock::new(|| compact(include_str!("../schemas/foxglove/SceneUpdate.json")));

/// The vendored JSON text, re-serialized without whitespace (the same JSON value).
fn compact(text: &str) -> String {
    serde_json::from_str::<Value>(text)
        .expect("the vendored Foxglove schemas are valid JSON (tests/mcap/schemas.rs)")
        .to_string()
}

/// `rsts.BodyState`: one body state of the exact or the integrated motion.
pub static BODY_STATE: LazyLock<String> = LazyLock::new(|| {
    let mut quaternion = object(numbers(&["x", "y", "z", "w"]));
    quaternion["description"] = "attitude quaternion (body to world) from Q".into();
    object(json!({
        "t": described(number(), "motion time (s)"),
        "alpha": triple("row 1 of Q: the fixed axis alpha in the body frame"),
        "beta": triple("row 2 of Q: the fixed axis beta in the body frame"),
        "gamma": triple("row 3 of Q: the fixed axis gamma in the body frame"),
        "quaternion": quaternion,
        "omega": triple("angular velocity, body frame"),
        "omega_fixed": triple("angular velocity, fixed frame (Q omega)"),
        "h": described(number(), "energy integral"),
        "k": described(number(), "second (Kowalevski-type) integral"),
        "g": described(number(), "third integral"),
    }))
    .titled(
        BODY_STATE_NAME,
        "State of the rigid body at motion time t. Q has rows alpha, beta, gamma (fixed axes in the body frame), Omega = Q omega.",
    )
});

/// The error and drift fields of `/errors` (besides `t`), with their descriptions. Each one
/// has a companion `log10_<name>` = log10 |value| (see [`log10_field`]), so that a plot on a
/// linear axis shows errors of 1e-14 and 1e-3 alike.
pub const ERROR_FIELDS: &[(&str, &str)] = &[
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
];

/// The fields of `/errors` that the harness adds when it measures the geometry of the error
/// (issue 11); optional, each with its `log10_<name>` companion like [`ERROR_FIELDS`].
pub const OPTIONAL_ERROR_FIELDS: &[(&str, &str)] = &[
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

/// The name of the log10 companion of an `/errors` field: `log10_<name>`.
pub fn log10_field(name: &str) -> String {
    format!("log10_{name}")
}

/// `rsts.Errors`: differences between the integrated and the exact motion. The fields of
/// [`ERROR_FIELDS`] and `t` are required; their `log10_…` companions are left out of a
/// message where the value is 0 or not finite (no point is plotted there).
pub static ERRORS: LazyLock<String> = LazyLock::new(|| {
    let mut properties = Map::new();
    properties.insert("t".into(), described(number(), "motion time (s)"));
    for (name, desc) in ERROR_FIELDS.iter().chain(OPTIONAL_ERROR_FIELDS) {
        properties.insert(name.to_string(), described(number(), desc));
    }
    for (name, _) in ERROR_FIELDS.iter().chain(OPTIONAL_ERROR_FIELDS) {
        let desc = format!(
            "log10 |{name}| (absent where {name} is 0 or not finite): plot this to see the errors on a logarithmic scale"
        );
        properties.insert(log10_field(name), described(number(), &desc));
    }
    let required: Vec<&str> = std::iter::once("t")
        .chain(ERROR_FIELDS.iter().map(|(name, _)| *name))
        .collect();
    let mut schema = object(Value::Object(properties));
    schema["required"] = json!(required);
    schema.titled(
        ERRORS_NAME,
        "Errors of the integrated motion against the exact one at motion time t",
    )
});

/// `rsts.Metadata`: the comparison's case, integrator configuration and software version.
pub static METADATA: LazyLock<String> = LazyLock::new(|| {
    let free_object = |desc: &str| json!({"type": "object", "description": desc, "properties": {}});
    object(json!({
        "software_version": {"type": "string"},
        "case": free_object("the case: a, b, m, h, torus, phases, t_end, samples"),
        "integrator": free_object("method, rtol, atol, digits"),
    }))
    .titled(
        METADATA_NAME,
        "Case, integrator configuration and software version of one comparison",
    )
});

/// `{"type": "number"}`.
fn number() -> Value {
    json!({"type": "number"})
}

/// An object schema with the given `properties`, all of them required.
fn object(properties: Value) -> Value {
    let required: Vec<String> = properties
        .as_object()
        .map(|p| p.keys().cloned().collect())
        .unwrap_or_default();
    json!({"type": "object", "properties": properties, "required": required})
}

/// A top-level schema: `title` and `description` added, serialized.
trait Titled {
    fn titled(self, title: &str, description: &str) -> String;
}

impl Titled for Value {
    fn titled(mut self, title: &str, description: &str) -> String {
        self["title"] = title.into();
        self["description"] = description.into();
        self.to_string()
    }
}

/// `schema` with a `description`.
fn described(mut schema: Value, description: &str) -> Value {
    schema["description"] = description.into();
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
