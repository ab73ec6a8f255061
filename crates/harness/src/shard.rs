//! Shards (`--shard K/N`): item i of a fixed list (the id-sorted runs of a validation suite, the
//! motions of an ensemble) belongs to shard K of N when i ≡ K − 1 (mod N), so N machines given
//! K = 1…N do every item exactly once, and the slice depends only on what is asked. Shards of
//! one request carry the same [`fnv1a`] digest of it, which their merge checks.

use serde::{Deserialize, Serialize};

use crate::HarnessError;

/// Shard K of N (1 ≤ K ≤ N).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl std::str::FromStr for Shard {
    type Err = HarnessError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = |why: &str| HarnessError::Setting(vec!["shard".into()], format!("'{s}': {why}"));
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
    /// Whether item `index` (from 0) of the list belongs to this shard.
    pub fn holds(&self, index: usize) -> bool {
        index % self.n == self.k - 1
    }

    /// The items of this shard, in their order.
    pub fn select<T: Clone>(&self, items: &[T]) -> Vec<T> {
        items
            .iter()
            .enumerate()
            .filter(|(i, _)| self.holds(*i))
            .map(|(_, x)| x.clone())
            .collect()
    }
}

/// FNV-1a, 64 bits: the digest shards of one request share (not a cryptographic hash: it tells
/// different requests apart, it does not guard against forgery).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// [`fnv1a`] as 16 hexadecimal digits.
pub fn digest(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_k_of_n_and_rejects_the_rest_naming_the_option() {
        assert_eq!("2/8".parse::<Shard>().unwrap(), Shard { k: 2, n: 8 });
        assert_eq!(" 1 / 1 ".parse::<Shard>().unwrap(), Shard { k: 1, n: 1 });
        for bad in ["0/3", "4/3", "3", "a/b", "1/0", "-1/3", "", "1/2/3"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert_eq!(e.parameters(), ["shard"], "{bad}");
            assert!(e.to_string().contains(&format!("'{bad}'")), "{e}");
        }
        assert_eq!(Shard { k: 3, n: 8 }.to_string(), "3/8");
    }

    /// Every item in exactly one shard, each shard's items in their order.
    #[test]
    fn shards_partition_a_list() {
        let items: Vec<usize> = (0..23).collect();
        for n in [1, 2, 4, 7, 30] {
            let mut all: Vec<usize> = (1..=n)
                .flat_map(|k| Shard { k, n }.select(&items))
                .collect();
            assert!(Shard { k: 1, n }
                .select(&items)
                .windows(2)
                .all(|w| w[0] < w[1]));
            all.sort();
            assert_eq!(all, items, "n = {n}");
        }
        assert_eq!(Shard { k: 2, n: 4 }.select(&items), [1, 5, 9, 13, 17, 21]);
    }

    /// The reference values of FNV-1a 64 (Fowler, Noll, Vo: the empty string and "a").
    #[test]
    fn fnv1a_matches_its_reference_values() {
        assert_eq!(fnv1a(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(digest(b"a"), "af63dc4c8601ec8c");
    }
}
