//! Dormand–Prince 5(4) with dense output of order 4 (Hairer, Nørsett, Wanner, *Solving ODE I*,
//! sec. II.5), from `ode_solvers`.

use super::ode_solvers_adapter::dormand_prince_method;

dormand_prince_method! {
    /// Dormand–Prince 5(4).
    Dopri5, ode_solvers::Dopri5<_, _, _>, name = "dopri5", order = 5,
    beta = 0.04, fac_min = 0.2, fac_max = 10.0
}
