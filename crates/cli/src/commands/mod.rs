//! One module per subcommand, each with `Args`, `EXAMPLES` and `run(args, out)`.

pub mod bench;
pub mod check;
pub mod compare;
pub mod convergence;
pub mod dashboard;
pub mod diagram;
pub mod events;
pub mod explicit;
pub mod history;
pub mod identify;
pub mod inspect;
pub mod integrate;
pub mod reference;
pub mod surfaces;
pub mod table1;
pub mod table2;
pub mod validate;
