//! One module per subcommand, each with `Args`, `EXAMPLES` and `run(args, out)`.

pub mod explicit;
pub mod integrate;
