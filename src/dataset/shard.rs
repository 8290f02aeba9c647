//! Shards: disjoint, deterministic slices of a dataset for array jobs (Slurm, Kubernetes
//! Indexed Jobs). Scene `i` belongs to shard `i mod count`.

/// A shard that cannot exist, or a `--shard` value that is not `I/N`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// `count` is zero or `index` is not below it.
    #[error("shard {index}/{count}: need count >= 1 and index < count (shards are 0-based)")]
    OutOfRange {
        /// The index given.
        index: u64,
        /// The count given.
        count: u64,
    },
    /// Not of the form `I/N` with whole numbers.
    #[error("--shard {0:?}: expected I/N with whole numbers, such as 0/4")]
    Syntax(String),
}

/// Shard `index` of `count` (0-based); `Shard::WHOLE` is the unsharded dataset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, `0..count`.
    pub index: u64,
    /// Number of shards, at least 1.
    pub count: u64,
}

impl Shard {
    /// The whole dataset as one shard.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// A checked shard `index` of `count`.
    pub fn new(index: u64, count: u64) -> Result<Shard, ShardError> {
        if count == 0 || index >= count {
            return Err(ShardError::OutOfRange { index, count });
        }
        Ok(Shard { index, count })
    }

    /// Parses `I/N`.
    pub fn parse(s: &str) -> Result<Shard, ShardError> {
        let syntax = || ShardError::Syntax(s.to_string());
        let (i, n) = s.split_once('/').ok_or_else(syntax)?;
        let num = |x: &str| x.trim().parse::<u64>().map_err(|_| syntax());
        Shard::new(num(i)?, num(n)?)
    }

    /// Whether scene `index` belongs to this shard.
    pub fn contains(&self, index: u64) -> bool {
        index % self.count == self.index
    }

    /// `true` for the unsharded dataset.
    pub fn is_whole(&self) -> bool {
        self.count == 1
    }

    /// How many of the scenes `0..total` belong to this shard (arithmetic, so a huge `total`
    /// costs nothing).
    pub fn len(&self, total: u64) -> u64 {
        if self.index >= total {
            0
        } else {
            (total - 1 - self.index) / self.count + 1
        }
    }

    /// The scene indices of this shard among `0..total`, ascending.
    pub fn indices(&self, total: u64) -> impl Iterator<Item = u64> + '_ {
        (self.index..total).step_by(self.count as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn len_counts_the_indices_without_walking_them() {
        for (i, n, total) in [(0, 1, 23), (3, 4, 23), (2, 4, 23), (5, 7, 3), (0, 2, 0)] {
            let s = Shard::new(i, n).unwrap();
            assert_eq!(
                s.len(total),
                s.indices(total).count() as u64,
                "{i}/{n} of {total}"
            );
        }
        assert_eq!(Shard::WHOLE.len(u64::MAX), u64::MAX);
    }

    #[test]
    fn shards_are_disjoint_and_cover_everything() {
        let total = 23;
        let mut seen = vec![0; total as usize];
        for i in 0..4 {
            let s = Shard::new(i, 4).unwrap();
            for k in s.indices(total) {
                assert!(s.contains(k));
                seen[k as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
        assert_eq!(Shard::parse("1/3").unwrap(), Shard { index: 1, count: 3 });
        assert!(Shard::parse("3/3").is_err() && Shard::parse("x").is_err());
    }
}
