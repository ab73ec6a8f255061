//! Dormand–Prince 8(5,3) with dense output of order 7 (Hairer, Nørsett, Wanner, *Solving ODE I*,
//! sec. II.10), from `ode_solvers`.

use super::ode_solvers_adapter::dormand_prince_method;

dormand_prince_method! {
    /// Dormand–Prince 8(5,3).
    Dop853, ode_solvers::Dop853<_, _, _>, name = "dop853", order = 8,
    beta = 0.0, fac_min = 0.333, fac_max = 6.0
}
