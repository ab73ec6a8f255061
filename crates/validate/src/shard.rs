//! Shards: `K/N` takes the runs whose index in the id-sorted list is ≡ K−1 (mod N), so N machines
//! given K = 1…N run every run exactly once, and the slice depends only on the suite.

use serde::{Deserialize, Serialize};

use crate::suite::Run;
use crate::ValidateError;

/// Shard K of N (1 ≤ K ≤ N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = ValidateError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = |why: &str| ValidateError::Usage(format!("--shard '{s}': {why}"));
        let (k, n) = s
            .split_once('/')
            .ok_or_else(|| bad("expected K/N, e.g. 2/8"))?;
        let k: usize = k
            .trim()
            .parse()
            .map_err(|_| bad("K is not a whole number"))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| bad("N is not a whole number"))?;
        if n == 0 || k == 0 || k > n {
            return Err(bad("need 1 <= K <= N"));
        }
        Ok(Shard { k, n })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// The runs of this shard from the id-sorted runs of a suite.
    pub fn select(&self, runs: &[Run]) -> Vec<Run> {
        runs.iter()
            .enumerate()
            .filter(|(i, _)| i % self.n == self.k - 1)
            .map(|(_, r)| r.clone())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::Suite;

    #[test]
    fn parses_k_of_n_and_rejects_the_rest() {
        assert_eq!("2/8".parse::<Shard>().unwrap(), Shard { k: 2, n: 8 });
        assert_eq!(" 1 / 1 ".parse::<Shard>().unwrap(), Shard { k: 1, n: 1 });
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", "-1/3", "", "1/2/3"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }

    #[test]
    fn shards_partition_the_runs() {
        let s = Suite::parse(
            "[defaults]\nt_end = 1.0\n[[case]]\nname = \"V\"\nm = -0.7092\nh = 1.5643\ntori = \"all\"\nmethods = [\"dop853\", \"rk4\"]\n",
            "s",
        )
        .unwrap();
        let n = 3;
        let mut all: Vec<String> = (1..=n)
            .flat_map(|k| Shard { k, n }.select(&s.runs))
            .map(|r| r.id)
            .collect();
        all.sort();
        let expected: Vec<String> = s.runs.iter().map(|r| r.id.clone()).collect();
        assert_eq!(all, expected);
    }
}
