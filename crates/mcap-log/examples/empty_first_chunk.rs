//! Rewrites an MCAP file in the layout rsts wrote before it was fixed (a first chunk without
//! messages), to show that the reader checks reject it:
//!
//!     cargo run --release -p rsts-mcap --example empty_first_chunk -- IN.mcap OUT.mcap
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = args.as_slice() else {
        eprintln!("usage: empty_first_chunk IN.mcap OUT.mcap");
        return ExitCode::from(2);
    };
    let result = std::fs::read(input)
        .map_err(|e| format!("cannot read {input}: {e}"))
        .and_then(|bytes| {
            rsts_mcap::compat::with_empty_first_chunk(&bytes)
                .map_err(|e| format!("{input} is not a complete MCAP file: {e}"))
        })
        .and_then(|bytes| {
            std::fs::write(output, bytes).map_err(|e| format!("cannot write {output}: {e}"))
        });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("empty_first_chunk: {e}");
            ExitCode::from(2)
        }
    }
}
