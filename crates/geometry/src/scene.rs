//! An MCAP scene of Poinsot's picture: the P-surface fixed in the body frame (which the
//! `/tf` transform world → body rotates by Q) and the Π-surface fixed in the world frame, each
//! logged as a `foxglove.SceneUpdate` triangle list at the start (and once more 0.2 s later,
//! see [`SURFACES_AGAIN_NS`]); then the moving hodograph ω(t) drawn
//! incrementally in the body frame — it rolls with the P-surface — while the fixed hodograph
//! Ω(t) = Qω traces the Π-surface. At every instant the body-frame point ω, carried to the world
//! by Q, is the world point Ω: the P-surface touches the Π-surface there.
//!
//! Channels (all JSON with Foxglove's JSON schemas from `rsts_mcap::schemas`):
//! `/tf` (FrameTransform world → body), `/surface/p` (frame `body`, frame-locked),
//! `/surface/pi` (frame `world`), `/hodograph/moving` (frame `body`), `/hodograph/fixed`
//! (frame `world`). Log time of a sample at motion time t: round(t·10⁹) ns.

use std::collections::BTreeMap;
use std::path::Path;

use mcap::records::MessageHeader;
use rsts_mcap::{schemas, time_to_ns, Quaternion};
use serde_json::{json, Value};

use crate::mesh::{Hodograph, TorusMesh};
use crate::GeometryError;

/// Topic names of the scene.
pub mod topics {
    pub const TF: &str = "/tf";
    pub const SURFACE_P: &str = "/surface/p";
    pub const SURFACE_PI: &str = "/surface/pi";
    pub const HODOGRAPH_MOVING: &str = "/hodograph/moving";
    pub const HODOGRAPH_FIXED: &str = "/hodograph/fixed";
    pub const FRAME_WORLD: &str = "world";
    pub const FRAME_BODY: &str = "body";
}

/// Counts of what was written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct SceneStats {
    pub messages: u64,
    pub bytes: u64,
}

fn mcap_err(e: impl std::error::Error + 'static) -> GeometryError {
    GeometryError::Mcap(rsts_io::error_text(&e))
}

fn stamp(ns: u64) -> Value {
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

fn point(p: [f64; 3]) -> Value {
    json!({"x": p[0], "y": p[1], "z": p[2]})
}

const IDENTITY_POSE: &str =
    r#"{"position":{"x":0,"y":0,"z":0},"orientation":{"x":0,"y":0,"z":0,"w":1}}"#;

fn identity_pose() -> Value {
    serde_json::from_str(IDENTITY_POSE).unwrap_or(Value::Null)
}

fn entity(ns: u64, frame: &str, id: &str, locked: bool, body: Value) -> Value {
    let mut e = json!({
        "timestamp": stamp(ns),
        "frame_id": frame,
        "id": id,
        "lifetime": {"sec": 0, "nsec": 0},
        "frame_locked": locked,
        "metadata": [],
        "arrows": [], "cubes": [], "spheres": [], "cylinders": [],
        "lines": [], "triangles": [], "texts": [], "models": []
    });
    if let (Value::Object(m), Value::Object(b)) = (&mut e, body) {
        m.extend(b);
    }
    e
}

/// A SceneUpdate with one triangle-list entity (indexed vertices).
pub fn surface_update(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    frame: &str,
    id: &str,
    color: [f64; 4],
) -> Value {
    let prim = json!({
        "pose": identity_pose(),
        "points": vertices.iter().map(|p| point(*p)).collect::<Vec<_>>(),
        "color": {"r": color[0], "g": color[1], "b": color[2], "a": color[3]},
        "colors": [],
        "indices": triangles.iter().flatten().copied().collect::<Vec<u32>>(),
    });
    let locked = frame == topics::FRAME_BODY;
    json!({"deletions": [], "entities": [entity(0, frame, id, locked, json!({"triangles": [prim]}))]})
}

struct Writer {
    w: mcap::Writer<rsts_io::AtomicFile>,
    seq: BTreeMap<u16, u32>,
    stats: SceneStats,
}

impl Writer {
    fn put(&mut self, channel: u16, ns: u64, v: &Value) -> Result<(), GeometryError> {
        let data = serde_json::to_vec(v).map_err(mcap_err)?;
        let seq = self.seq.entry(channel).or_insert(0);
        *seq += 1;
        self.w
            .write_to_known_channel(
                &MessageHeader {
                    channel_id: channel,
                    sequence: *seq,
                    log_time: ns,
                    publish_time: ns,
                },
                &data,
            )
            .map_err(mcap_err)?;
        self.stats.messages += 1;
        self.stats.bytes += data.len() as u64;
        Ok(())
    }
}

/// Points of the hodographs per SceneUpdate (one LINE_STRIP entity per batch).
pub const BATCH: usize = 8;

/// The surfaces are logged at the start and once more this long after it (when the motion is
/// that long). Foxglove Studio 1.x reads the first 99 ms of a file before its 3-D panels have
/// subscribed to their topics when they subscribe while the file loads, and then never delivers
/// those messages until the user seeks: the surfaces, logged once at the start, were missing
/// in about half the openings (seen with `scripts/check_viewer.sh`). The second copy arrives
/// during playback.
pub const SURFACES_AGAIN_NS: u64 = 200_000_000;

/// Write the scene of one torus and a stretch of its motion to `path`, whole or not at all (a
/// temporary beside it is renamed into place at the end).
pub fn write_scene(
    path: &Path,
    mesh: &TorusMesh,
    motion: &Hodograph,
) -> Result<SceneStats, GeometryError> {
    let io = |context: String| move |source| GeometryError::Io { context, source };
    let file = rsts_io::AtomicFile::create(path)
        .map_err(io(format!("cannot create {}", path.display())))?;
    let opts = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .profile("")
        .library(format!("rsts-geometry/{}", env!("CARGO_PKG_VERSION")));
    let mut w = opts.create(file).map_err(mcap_err)?;
    let tf_s = w
        .add_schema(
            schemas::FRAME_TRANSFORM_NAME,
            "jsonschema",
            schemas::FRAME_TRANSFORM.as_bytes(),
        )
        .map_err(mcap_err)?;
    let su_s = w
        .add_schema(
            schemas::SCENE_UPDATE_NAME,
            "jsonschema",
            schemas::SCENE_UPDATE.as_bytes(),
        )
        .map_err(mcap_err)?;
    let none = BTreeMap::new();
    let mut ch = |schema, topic| w.add_channel(schema, topic, "json", &none);
    let tf = ch(tf_s, topics::TF).map_err(mcap_err)?;
    let sp = ch(su_s, topics::SURFACE_P).map_err(mcap_err)?;
    let spi = ch(su_s, topics::SURFACE_PI).map_err(mcap_err)?;
    let hm = ch(su_s, topics::HODOGRAPH_MOVING).map_err(mcap_err)?;
    let hf = ch(su_s, topics::HODOGRAPH_FIXED).map_err(mcap_err)?;
    let mut out = Writer {
        w,
        seq: BTreeMap::new(),
        stats: SceneStats::default(),
    };
    let p_color = [0.95, 0.62, 0.32, 0.55];
    let pi_color = [0.42, 0.62, 0.92, 0.45];
    let t0 = time_to_ns(motion.t.first().copied().unwrap_or(0.0)).map_err(mcap_err)?;
    let p_surface = surface_update(
        &mesh.omega,
        &mesh.triangles,
        topics::FRAME_BODY,
        "p_surface",
        p_color,
    );
    let pi_surface = surface_update(
        &mesh.omega_fixed,
        &mesh.triangles,
        topics::FRAME_WORLD,
        "pi_surface",
        pi_color,
    );
    out.put(sp, t0, &p_surface)?;
    out.put(spi, t0, &pi_surface)?;
    // Sent again (same entity ids: a replacement, nothing changes on screen) once the motion
    // passes t0 + SURFACES_AGAIN_NS: see SURFACES_AGAIN_NS.
    let mut again = Some(t0 + SURFACES_AGAIN_NS);
    let curve_color = |rgb: [f64; 3]| json!({"r": rgb[0], "g": rgb[1], "b": rgb[2], "a": 1.0});
    let n = motion.t.len();
    let mut start = 0;
    let mut batch_no = 0;
    for i in 0..n {
        let ns = time_to_ns(motion.t[i]).map_err(mcap_err)?;
        let tf_msg = json!({
            "timestamp": stamp(ns),
            "parent_frame_id": topics::FRAME_WORLD,
            "child_frame_id": topics::FRAME_BODY,
            "translation": {"x": 0.0, "y": 0.0, "z": 0.0},
            "rotation": Quaternion::from_orientation(&motion.q[i]),
        });
        out.put(tf, ns, &tf_msg)?;
        if again.is_some_and(|at| ns >= at) {
            out.put(sp, ns, &p_surface)?;
            out.put(spi, ns, &pi_surface)?;
            again = None;
        }
        if i - start < BATCH && i + 1 < n {
            continue;
        }
        batch_no += 1;
        for (channel, pts, frame, rgb) in [
            (hm, &motion.omega, topics::FRAME_BODY, [0.55, 0.0, 0.1]),
            (
                hf,
                &motion.omega_fixed,
                topics::FRAME_WORLD,
                [0.0, 0.15, 0.55],
            ),
        ] {
            let strip = json!({
                "type": 0,
                "pose": identity_pose(),
                "thickness": 2.0,
                "scale_invariant": true,
                "points": pts[start..=i].iter().map(|p| point(*p)).collect::<Vec<_>>(),
                "color": curve_color(rgb),
                "colors": [],
                "indices": []
            });
            let p = pts[i];
            let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let arrow = json!({
                "pose": {"position": point([0.0; 3]), "orientation": Quaternion::x_axis_to(p)},
                "shaft_length": 0.85 * len,
                "shaft_diameter": 0.02 * len,
                "head_length": 0.15 * len,
                "head_diameter": 0.06 * len,
                "color": curve_color(rgb)
            });
            let locked = frame == topics::FRAME_BODY;
            let msg = json!({"deletions": [], "entities": [
                entity(ns, frame, &format!("seg{batch_no}"), locked, json!({"lines": [strip]})),
                entity(ns, frame, "current", locked, json!({"arrows": [arrow]})),
            ]});
            out.put(channel, ns, &msg)?;
        }
        start = i;
    }
    let Writer { mut w, stats, .. } = out;
    w.finish().map_err(mcap_err)?;
    w.into_inner()
        .commit()
        .map_err(io(format!("cannot write {}", path.display())))?;
    Ok(stats)
}
