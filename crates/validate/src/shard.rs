//! Shards: `K/N` takes the runs whose index in the id-sorted list is ≡ K−1 (mod N), so N machines
//! given K = 1…N run every run exactly once, and the slice depends only on the suite
//! ([`Shard::select`] on [`crate::Suite::runs`]; the type is the harness's, shared with the
//! shards of a benchmark's ensemble).

pub use rsts_harness::shard::Shard;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::Suite;

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
