//! Exact event times along the closed-form motion: the times in (t_start, t_end] at which a state
//! component (ωᵢ, αᵢ, βᵢ), a component of γ = α × β, or the rate ṡᵢ of a separated variable
//! crosses zero, to any number of digits (docs/events.md).
//!
//! * Turning points of s₁, s₂ (ṡᵢ = 0) come from the structure of the motion: the separated
//!   variable v is at λ when sn u = 0 and at μ when cn u = 0, so t = (jK − u₀)/u̇
//!   ([`ExplicitMotion::turning_times`]); no root finding.
//! * A component g(t) is bracketed on a grid of spacing min(P₁, P₂)/8, refined where needed by a
//!   certificate built from bounds on |g″| and |g‴| ([`bounds`], majorants of the equations of
//!   motion at the energy h), and each root is refined by Newton steps whose derivative g′ is
//!   the right-hand side of the Euler–Poisson equations at the closed-form state ([`isolate`]).
//!   A double root (an extremum of g at zero to the digits asked) is one `tangent` event.
//!
//! Everything runs at the motion's precision; [`working_bits`] is the precision asked plus
//! [`GUARD_BITS`].

pub mod bounds;
pub mod isolate;
mod report;

pub use report::{
    bytes_per_event, events_report, EventCase, EventRecord, EventsReport, EventsRun, Number,
};

use rsts_dynamics::dual::Dual;
use rsts_dynamics::scalar::{bits_for_digits, F64_BITS};
use rsts_dynamics::state::DIM;
use rsts_dynamics::vec3::cross;
use rsts_dynamics::{Fields, VectorField};
use rug::Float;
use serde::{Deserialize, Serialize};

use crate::error::ClosedFormError;
use crate::motion::ExplicitMotion;
use crate::scalar::GUARD_BITS;
use isolate::{Jet, Kind, Settings};

/// Largest number of grid cells (or turning points) of one event function in one window.
pub const MAX_CELLS: usize = 1_000_000;

/// The names of the event functions, in the order of [`EventName::index`].
pub const EVENT_NAMES: [&str; 14] = [
    "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
    "gamma1", "gamma2", "gamma3", "s1", "s2",
];

/// A function of the state whose zeros are events.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct EventName(usize);

impl EventName {
    /// `omega1` … `beta3`, `gamma1..3`, `s1`, `s2` (ṡᵢ = 0).
    pub fn parse(s: &str) -> Option<Self> {
        EVENT_NAMES.iter().position(|n| *n == s).map(EventName)
    }
    pub fn as_str(&self) -> &'static str {
        EVENT_NAMES[self.0]
    }
    /// Position in [`EVENT_NAMES`]: 0..9 the state (ω, α, β), 9..12 γ, 12 s₁, 13 s₂.
    pub fn index(&self) -> usize {
        self.0
    }
}

impl std::fmt::Display for EventName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// How an event function passes through zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Crossing {
    Up,
    Down,
    /// A double root: the function touches zero (to the digits asked) without crossing.
    Tangent,
}

impl Crossing {
    pub fn as_str(&self) -> &'static str {
        match self {
            Crossing::Up => "up",
            Crossing::Down => "down",
            Crossing::Tangent => "tangent",
        }
    }
}

/// Which crossings of one event function are asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum DirectionFilter {
    Up,
    Down,
    #[default]
    Both,
}

impl DirectionFilter {
    /// Tangencies pass every filter (a user asking for up-crossings is told of a touch).
    pub fn admits(&self, c: Crossing) -> bool {
        matches!(
            (self, c),
            (DirectionFilter::Both, _)
                | (_, Crossing::Tangent)
                | (DirectionFilter::Up, Crossing::Up)
                | (DirectionFilter::Down, Crossing::Down)
        )
    }
    pub fn as_str(&self) -> &'static str {
        match self {
            DirectionFilter::Up => "up",
            DirectionFilter::Down => "down",
            DirectionFilter::Both => "both",
        }
    }
}

/// One event function with the crossings asked for: `NAME[:up|down|both]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EventSpec {
    pub name: EventName,
    pub direction: DirectionFilter,
}

impl std::str::FromStr for EventSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (name, dir) = match s.split_once(':') {
            Some((n, d)) => (n, Some(d)),
            None => (s, None),
        };
        let name = EventName::parse(name.trim()).ok_or_else(|| {
            format!(
                "unknown event '{}' (known: {})",
                name.trim(),
                EVENT_NAMES.join(", ")
            )
        })?;
        let direction = match dir.map(str::trim) {
            None | Some("both") => DirectionFilter::Both,
            Some("up") => DirectionFilter::Up,
            Some("down") => DirectionFilter::Down,
            Some(d) => return Err(format!("unknown direction '{d}' (up, down, both)")),
        };
        Ok(EventSpec { name, direction })
    }
}

/// One exact event.
#[derive(Clone, Debug)]
pub struct ExactEvent {
    pub name: EventName,
    pub t: Float,
    pub direction: Crossing,
    /// (ω, α, β) at t.
    pub state: [Float; DIM],
}

/// Bits of the computation for `digits` decimal digits (`None`: f64): the precision asked plus
/// [`GUARD_BITS`].
pub fn working_bits(digits: Option<u32>) -> u32 {
    digits.map_or(F64_BITS, bits_for_digits) + GUARD_BITS
}

/// Every event of `specs` in (t_start, t_end], in time order (events at the same time in the
/// order of `specs`), at the precision of `motion` (build it at [`working_bits`]).
pub fn exact_events(
    motion: &ExplicitMotion<Float>,
    specs: &[EventSpec],
    t_start: &Float,
    t_end: &Float,
) -> Result<Vec<ExactEvent>, ClosedFormError> {
    let search = EventSearch::new(motion, specs, t_start, t_end)?;
    let mut out = Vec::new();
    search.for_each(motion, |e| {
        out.push(e);
        Ok::<(), ClosedFormError>(())
    })?;
    Ok(out)
}

/// Grid cells per piece of a window (8 of the shorter period): the events of a piece are found,
/// put in order and handed on before the next piece is started, so memory does not grow with
/// the window.
pub const PIECE_CELLS: u32 = 64;

/// The search for the events of `specs` in (t_start, t_end] along one motion, checked and laid
/// out before anything is computed: the grid of the isolation (spacing an eighth of the shorter
/// period, [`isolate`]) and how many events it may find ([`EventSearch::most_events`]). The
/// events are then found a piece of the grid at a time ([`EventSearch::for_each`]): the same
/// numbers in the same order as one pass over the whole window, since every grid cell is
/// settled from its own ends and every turning time is computed from its own index.
#[derive(Clone, Debug)]
pub struct EventSearch {
    specs: Vec<EventSpec>,
    t0: Float,
    t1: Float,
    /// Cells of the grid the window is cut along (at least 1).
    cells: u32,
    /// Cells of the isolation's grid ([`isolate::grid_cells`]; equal to `cells` unless it is 0).
    component_cells: u32,
    settings: Settings,
    /// Bounds on |g|, |g′|, |g″|, |g‴| of every component ([`bounds`]).
    bounds: [[f64; DIM + 3]; bounds::ORDERS],
    most: f64,
}

impl EventSearch {
    /// Check the window and the limits ([`MAX_CELLS`] grid cells, or turning points, per event
    /// function) and lay out the grid.
    pub fn new(
        motion: &ExplicitMotion<Float>,
        specs: &[EventSpec],
        t_start: &Float,
        t_end: &Float,
    ) -> Result<Self, ClosedFormError> {
        let bits = motion.constants.a.prec();
        if !(t_start.is_finite() && t_end.is_finite()) {
            return Err(ClosedFormError::Range(
                "t-end",
                "the window must be finite".into(),
            ));
        }
        if t_end <= t_start {
            return Err(ClosedFormError::Range(
                "t-end",
                format!(
                    "the window (t_start, t_end] = ({}, {}] is empty: need t_end > t_start",
                    short_time(t_start),
                    short_time(t_end)
                ),
            ));
        }
        let c = &motion.constants;
        let bounds = bounds::derivative_bounds(c.a.to_f64(), c.b.to_f64(), c.h.to_f64());
        let period = motion
            .periods()
            .iter()
            .map(|p| p.to_f64().abs())
            .fold(f64::INFINITY, f64::min);
        let settings = Settings {
            h0: period / 8.0,
            m2: 0.0,
            m3: 0.0,
            max_cells: MAX_CELLS,
        };
        let (t0, t1) = (Float::with_val(bits, t_start), Float::with_val(bits, t_end));
        let grid = isolate::grid_cells(&t0, &t1, settings);
        let mut most = 0.0;
        for spec in specs {
            let k = spec.name.index();
            if k >= 12 {
                let count = motion.turning_count(k - 12, &t0, &t1);
                if !(count.is_finite() && count <= MAX_CELLS as f64 + 3.0) {
                    return Err(too_long(spec.name, MAX_CELLS));
                }
                most += count;
            } else {
                let n = grid
                    .clone()
                    .map_err(|e| ClosedFormError::Range("t-end", format!("{}: {e}", spec.name)))?;
                // One event per grid cell: a component has a few zeros per period, the grid
                // eight cells per shorter period ([`EventSearch::for_each`] holds to it).
                most += f64::from(n);
            }
        }
        // The pieces follow the isolation's grid; with only turning points asked any grid cuts
        // the window into pieces.
        let component_cells = grid.clone().unwrap_or(0);
        let cells = grid.unwrap_or(MAX_CELLS as u32).max(1);
        Ok(Self {
            specs: specs.to_vec(),
            t0,
            t1,
            cells,
            component_cells,
            settings,
            bounds,
            most,
        })
    }

    /// The most events the search may find: the turning points in the window, and one per grid
    /// cell of each component asked. [`EventSearch::for_each`] stops with an error past it, so
    /// an output sized from it is a bound.
    pub fn most_events(&self) -> f64 {
        self.most
    }

    /// Find the events piece after piece of the grid ([`PIECE_CELLS`] cells each), handing each
    /// to `sink` in time order (events at the same time in the order of the specs) as soon as its
    /// piece is done. Stops at the first error of the search or of `sink`.
    pub fn for_each<E: From<ClosedFormError>>(
        &self,
        motion: &ExplicitMotion<Float>,
        mut sink: impl FnMut(ExactEvent) -> Result<(), E>,
    ) -> Result<(), E> {
        let bits = motion.constants.a.prec();
        let c = &motion.constants;
        let (a, b) = (c.a.clone(), c.b.clone());
        let field = VectorField::new(&Fields {
            a: a.clone(),
            b: b.clone(),
        });
        let dual_field = VectorField::new(&Fields {
            a: Dual::constant(a.clone()),
            b: Dual::constant(b.clone()),
        });
        let state_at = |t: &Float| -> [Float; DIM] {
            let s = motion.at(t);
            std::array::from_fn(|k| match k / 3 {
                0 => s.omega[k % 3].clone(),
                1 => s.alpha[k % 3].clone(),
                _ => s.beta[k % 3].clone(),
            })
        };
        let (t0, t1, n) = (&self.t0, &self.t1, self.cells);
        let mut handed = 0.0;
        let mut first = 0u32;
        while first < n {
            let last = first.saturating_add(PIECE_CELLS).min(n);
            let (pa, pb) = (
                isolate::grid_point(t0, t1, n, first),
                isolate::grid_point(t0, t1, n, last),
            );
            let mut out: Vec<(usize, ExactEvent)> = Vec::new();
            for (order, spec) in self.specs.iter().enumerate() {
                let k = spec.name.index();
                let mut push = |t: Float, direction: Crossing| {
                    if spec.direction.admits(direction) {
                        let state = state_at(&t);
                        out.push((
                            order,
                            ExactEvent {
                                name: spec.name,
                                t,
                                direction,
                                state,
                            },
                        ));
                    }
                };
                if k >= 12 {
                    let i = k - 12;
                    let times = motion
                        .turning_times(i, &pa, &pb, MAX_CELLS)
                        .ok_or_else(|| too_long(spec.name, MAX_CELLS))?;
                    for (t, at_lambda) in times {
                        // s₂ is least at λ (ṡ₂ turns up); x = 1/s₁ is least at λ, where s₁ = 1/x
                        // is greatest (ṡ₁ = −ẋ/x² turns down).
                        let up = at_lambda == (i == 1);
                        push(t, if up { Crossing::Up } else { Crossing::Down });
                    }
                    continue;
                }
                let mut jet = |t: &Float| -> Jet {
                    let x = state_at(t);
                    let dx = field.eval(&x);
                    let xd: [Dual<Float>; DIM] =
                        std::array::from_fn(|j| Dual::new(x[j].clone(), dx[j].clone()));
                    let ddx = dual_field.eval(&xd);
                    if k < DIM {
                        return Jet {
                            g: x[k].clone(),
                            d: dx[k].clone(),
                            c: ddx[k].eps.clone(),
                        };
                    }
                    // γ̇ = γ × ω, γ̈ = γ̇ × ω + γ × ω̇.
                    let v3 = |v: &[Float; DIM], o: usize| {
                        [v[o].clone(), v[o + 1].clone(), v[o + 2].clone()]
                    };
                    let (al, be, w) = (v3(&x, 3), v3(&x, 6), v3(&x, 0));
                    let dw: [Float; 3] = std::array::from_fn(|j| dx[j].clone());
                    let gamma = cross(&al, &be);
                    let dg = cross(&gamma, &w);
                    let cg = cross(&dg, &w);
                    let cg2 = cross(&gamma, &dw);
                    let j = k - DIM;
                    Jet {
                        g: gamma[j].clone(),
                        d: dg[j].clone(),
                        c: cg[j].clone() + &cg2[j],
                    }
                };
                let settings = Settings {
                    m2: self.bounds[2][k],
                    m3: self.bounds[3][k],
                    ..self.settings
                };
                let scale = self.bounds[0][k].max(1.0);
                let tol = Float::with_val(bits, scale) >> (bits - GUARD_BITS / 2);
                let cells = first..last;
                let zeros = isolate::zeros_in_cells(
                    &mut jet,
                    t0,
                    t1,
                    self.component_cells,
                    cells,
                    settings,
                    &tol,
                );
                for z in zeros {
                    let dir = match z.kind {
                        Kind::Up => Crossing::Up,
                        Kind::Down => Crossing::Down,
                        Kind::Tangent => Crossing::Tangent,
                    };
                    push(z.t, dir);
                }
            }
            out.sort_by(|(o1, e1), (o2, e2)| {
                e1.t.partial_cmp(&e2.t)
                    .unwrap_or(std::cmp::Ordering::Equal)
                    .then(o1.cmp(o2))
            });
            handed += out.len() as f64;
            if handed > self.most {
                return Err(ClosedFormError::Range(
                    "t-end",
                    format!(
                        "more than the {} events the window was estimated to hold (one per \
                         eighth of the shorter period and function); ask for a shorter window",
                        self.most
                    ),
                )
                .into());
            }
            for (_, e) in out {
                sink(e)?;
            }
            first = last;
        }
        Ok(())
    }
}

/// A time of the window as shown in a message (short: 1e300, not 301 digits).
fn short_time(t: &Float) -> String {
    rsts_dynamics::shown(t.to_f64())
}

fn too_long(name: EventName, limit: usize) -> ClosedFormError {
    ClosedFormError::Range(
        "t-end",
        format!("{name}: the window holds more than {limit} periods; ask for a shorter one"),
    )
}
