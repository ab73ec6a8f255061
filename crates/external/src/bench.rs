//! An external integrator in a benchmark: asked for events in its request, it may answer them.

use rsts_harness::bench::BenchIntegrator;

use crate::Exec;

impl BenchIntegrator for Exec {
    fn ask_events(&mut self, events: &[(String, String)]) {
        self.events = events.to_vec();
    }

    fn answered_events(&self) -> Option<Vec<(String, f64)>> {
        self.answered_events.clone()
    }

    fn ask_dense(&mut self, k: Option<usize>) {
        self.dense = k;
    }

    fn answered_dense(&mut self) -> Option<rsts_dynamics::integrators::dense::StepSamples> {
        self.answered_dense.take()
    }
}
