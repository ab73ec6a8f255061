//! MCAP logs of one integrator-vs-exact comparison, readable by Foxglove and Lichtblick
//! with no plugin, and a tolerant reader for `rsts inspect`.
//!
//! * [`TrajectoryLog`] writes one file per comparison: zstd-compressed chunks, Foxglove's
//!   well-known JSON schemas (`foxglove.FrameTransform`, `foxglove.SceneUpdate`) for the
//!   3D panel, JSON series with a JSON Schema for the Plot panel, and the case metadata.
//! * [`inspect::summarize`] and [`inspect::extract`] read a file back, recovering what
//!   can be recovered from a truncated or damaged file, never panicking.
//!
//! The channel layout is documented in `docs/mcap.md`; the names are in [`topics`].
//! Time convention: a sample at motion time `t` seconds is logged with
//! `log_time = publish_time = round(t · 10⁹)` nanoseconds (see [`time_to_ns`]).

pub mod compat;
pub mod demo;
mod events;
mod framing;
pub mod inspect;
pub mod quat;
pub mod schemas;
mod writer;

pub use events::EventMark;
pub use inspect::{extract, summarize, InspectError, Series, Summary};
pub use quat::Quaternion;
pub use writer::{
    time_to_ns, BodyState, ErrorSample, LogError, LogOptions, LogStats, Metadata, Sample,
    TrajectoryLog,
};

/// Topic and frame names of the channel layout (see `docs/mcap.md`).
pub mod topics {
    /// `rsts.Metadata` JSON message at t = 0.
    pub const METADATA: &str = "/metadata";
    /// `foxglove.FrameTransform`: world → body_exact and world → body_integrated.
    pub const TF: &str = "/tf";
    /// `rsts.BodyState` of the exact motion.
    pub const EXACT_STATE: &str = "/exact/state";
    /// `rsts.BodyState` of the integrated motion.
    pub const INTEGRATED_STATE: &str = "/integrated/state";
    /// `rsts.Errors`.
    pub const ERRORS: &str = "/errors";
    /// `foxglove.Log`: one line per exact, missed or spurious event (`compare --event`).
    pub const EVENTS: &str = "/events";
    /// `rsts.EventMarker`: the same events as numbers for the Plot panel.
    pub const EVENT_MARKERS: &str = "/events/markers";
    /// `foxglove.SceneUpdate`: moving hodograph (ω, frame `body_exact`).
    pub const EXACT_HODOGRAPH_MOVING: &str = "/exact/hodograph/moving";
    /// `foxglove.SceneUpdate`: fixed hodograph (Ω, frame `world`).
    pub const EXACT_HODOGRAPH_FIXED: &str = "/exact/hodograph/fixed";
    /// `foxglove.SceneUpdate`: moving hodograph (ω, frame `body_integrated`).
    pub const INTEGRATED_HODOGRAPH_MOVING: &str = "/integrated/hodograph/moving";
    /// `foxglove.SceneUpdate`: fixed hodograph (Ω, frame `world`).
    pub const INTEGRATED_HODOGRAPH_FIXED: &str = "/integrated/hodograph/fixed";
    /// All topics, in the order their channels are written.
    pub const ALL: [&str; 9] = [
        METADATA,
        TF,
        EXACT_STATE,
        INTEGRATED_STATE,
        ERRORS,
        EXACT_HODOGRAPH_MOVING,
        EXACT_HODOGRAPH_FIXED,
        INTEGRATED_HODOGRAPH_MOVING,
        INTEGRATED_HODOGRAPH_FIXED,
    ];
    /// Name of the MCAP Metadata record.
    pub const METADATA_RECORD_NAME: &str = "rsts";
    /// The fixed frame.
    pub const FRAME_WORLD: &str = "world";
    /// The body frame of the exact motion.
    pub const FRAME_BODY_EXACT: &str = "body_exact";
    /// The body frame of the integrated motion.
    pub const FRAME_BODY_INTEGRATED: &str = "body_integrated";
}
