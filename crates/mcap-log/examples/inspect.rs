//! What `rsts inspect` does, as a standalone example of the reading API:
//!
//! `cargo run -p rsts-mcap --example inspect -- FILE.mcap [--channel TOPIC [--format csv|json]]`
//!
//! Exit status: 0 for a healthy file, 1 on error, 3 when the file was damaged and only
//! partly recovered (the recovered data is still printed).

use std::io::Write;

use rsts_mcap::inspect;

/// Prints to stdout; a closed pipe (`| head`) is not an error.
fn out(text: &str) {
    let mut o = std::io::stdout().lock();
    if let Err(e) = o.write_all(text.as_bytes()).and_then(|()| o.flush()) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("error: cannot write output: {e}");
            std::process::exit(1);
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: inspect FILE.mcap [--channel TOPIC [--format csv|json]]");
        std::process::exit(2);
    };
    let opt = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let recovered = match opt("--channel") {
        None => match inspect::summarize(path) {
            Ok(s) => {
                out(&s.to_string());
                s.recovered
            }
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        },
        Some(topic) => match inspect::extract(path, &topic) {
            Ok(series) => {
                match opt("--format").as_deref().unwrap_or("csv") {
                    "json" => out(&series.to_json()),
                    _ => out(&series.to_csv()),
                }
                for n in &series.notes {
                    eprintln!("warning: {n}");
                }
                series.recovered
            }
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
        },
    };
    if recovered {
        std::process::exit(3);
    }
}
