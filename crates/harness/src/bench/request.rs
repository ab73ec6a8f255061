//! What a benchmark is asked ([`BenchRequest`]): its methods — built-in, or from outside and
//! made for each tolerance ([`OutsideMethod`], [`BenchIntegrator`]) — and an ensemble's plan;
//! and what it tells while it runs ([`BenchObserver`]).

use rsts_closed_form::events::EventSpec;
use rsts_closed_form::Camera;
use rsts_dynamics::integrators::{MethodName, Tolerances};

use crate::integrator::Integrator;
use crate::shard::Shard;
use crate::{Case, HarnessError};

/// An integrator of a benchmark at one tolerance. Besides integrating, it may locate the
/// requested events itself (an external process asked for them in its request).
pub trait BenchIntegrator: Integrator {
    /// Ask for these events (name, direction) in the runs to come; default: not able to.
    fn ask_events(&mut self, events: &[(String, String)]) {
        let _ = events;
    }
    /// The events (name, time) the last run located itself; `None`: the harness locates them
    /// in its samples.
    fn answered_events(&self) -> Option<Vec<(String, f64)>> {
        None
    }
    /// Ask for K samples inside each step in the runs to come (`None`: stop asking); default:
    /// not able to.
    fn ask_dense(&mut self, k: Option<usize>) {
        let _ = k;
    }
    /// The steps and dense samples of the last run, when it reported them.
    fn answered_dense(&mut self) -> Option<rsts_dynamics::integrators::dense::StepSamples> {
        None
    }
}

/// A user's f64 [`Propagator`](rsts_dynamics::integrators::Propagator) in a benchmark.
impl<P: rsts_dynamics::integrators::Propagator<f64>> BenchIntegrator for crate::Propagated<P> {}

/// A method from outside the library (an `--exec` process, a Python callable), made for each
/// tolerance of a benchmark.
pub trait OutsideMethod {
    /// How errors name it (`--exec`, the callable's name).
    fn what(&self) -> String;
    /// What tells it from another method in the request digest of an ensemble's shards (an
    /// `--exec` command; default: [`OutsideMethod::what`]).
    fn identity(&self) -> String {
        self.what()
    }
    /// The integrator at `tolerances` (rtol = atol), its requests at `digits` decimal digits.
    fn at(
        &mut self,
        tolerances: Tolerances,
        digits: u32,
    ) -> Result<Box<dyn BenchIntegrator>, HarnessError>;
}

/// A method of a benchmark.
pub enum BenchMethod<'a> {
    BuiltIn(MethodName),
    Outside(&'a mut (dyn OutsideMethod + Send)),
}

/// What to measure: the case (its T and samples), the methods, the tolerances (rtol = atol),
/// repeats per run, taylor-mp's digits (default
/// [`default_mp_digits`](super::default_mp_digits)) and events to locate.
pub struct BenchRequest<'a> {
    pub case: Case,
    pub methods: Vec<BenchMethod<'a>>,
    pub tolerances: Vec<f64>,
    pub repeats: usize,
    pub digits: Option<u32>,
    pub events: Vec<EventSpec>,
}

/// What a benchmark tells while it runs (notes, progress) and whether it should stop.
pub trait BenchObserver {
    /// A note for the user (a skipped tolerance).
    fn note(&mut self, text: &str) {
        let _ = text;
    }
    /// The runs are about to start: `total` of them.
    fn start(&mut self, total: usize) {
        let _ = total;
    }
    /// A run starts (`label at tolerance`); an error stops the benchmark with it.
    fn running(&mut self, what: &str) -> Result<(), HarnessError> {
        let _ = what;
        Ok(())
    }
    /// A run is done.
    fn done(&mut self) {}
}

/// Observes nothing.
pub struct Quiet;
impl BenchObserver for Quiet {}

/// An ensemble asked of a benchmark: `n` motions drawn with `seed` from `cameras` (all nine
/// when empty), see [`crate::ensemble`]; with a `shard`, only the motions of that shard run
/// ([`super::merge`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EnsemblePlan {
    pub n: usize,
    pub seed: u64,
    pub cameras: Vec<Camera>,
    pub shard: Option<Shard>,
}
