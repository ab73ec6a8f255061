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
}
