//! The one rule for a number of threads asked for (`--jobs` of every command, a validation's
//! `jobs`): at least 1, at most [`MAX_JOBS_PER_CORE`] per core of this machine. More threads
//! only add memory (each holds a closed form and its samples) and, past the process table,
//! take the machine down.

/// Most threads per core a run may ask for.
pub const MAX_JOBS_PER_CORE: usize = 8;

/// Cores of this machine (1 when unknown).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The most threads a run may ask for on this machine: [`MAX_JOBS_PER_CORE`] per core.
pub fn max_jobs() -> usize {
    MAX_JOBS_PER_CORE * cores()
}

/// Check `n` threads against the rule of the module doc; the message names no option.
pub fn check_jobs(n: usize) -> Result<usize, String> {
    let cores = cores();
    let max = MAX_JOBS_PER_CORE * cores;
    match n {
        0 => Err("must be at least 1".into()),
        n if n > max => Err(format!(
            "at most {max} threads ({MAX_JOBS_PER_CORE} per core on this machine's {cores}); more only add memory, got {n}"
        )),
        n => Ok(n),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jobs_are_one_to_eight_per_core() {
        assert_eq!(check_jobs(1), Ok(1));
        assert_eq!(check_jobs(max_jobs()), Ok(max_jobs()));
        let e = check_jobs(max_jobs() + 1).unwrap_err();
        assert!(
            e.starts_with(&format!("at most {} threads (8 per core", max_jobs())),
            "{e}"
        );
        assert!(check_jobs(0).is_err());
    }
}
