//! One share of a batch job (`--shard i/n`): the batch's items split into `n`
//! contiguous blocks, so that shard outputs written one after the other
//! (the first with the header, the others without) are the unsharded output
//! byte for byte, whichever machine ran each.

use std::fmt;
use std::ops::Range;
use std::str::FromStr;

use kinema::{Error, InputError};

/// Shard `index` of `count` (1-based as written: `1/4` … `4/4`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// The whole batch: one shard of one.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Shard `index` (1-based) of `count`.
    pub fn new(index: usize, count: usize) -> Result<Shard, Error> {
        if count == 0 || index == 0 || index > count {
            return Err(Error::Input(InputError::DoesNotFit {
                what: "shard".into(),
                reason: format!("{index}/{count}: expected i/n with 1 ≤ i ≤ n (e.g. 2/4, the second of four)"),
            }));
        }
        Ok(Shard { index, count })
    }

    /// Its index, 1-based.
    pub fn index(&self) -> usize {
        self.index
    }

    /// How many shards the batch is split into.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The items of a batch of `len` this shard takes: block `index` of
    /// `count` nearly equal contiguous blocks (sizes differ by at most one).
    pub fn range(&self, len: usize) -> Range<usize> {
        let bound = |k: usize| (k as u128 * len as u128 / self.count as u128) as usize;
        bound(self.index - 1)..bound(self.index)
    }

    /// This shard's items of `items`.
    pub fn take<T>(&self, mut items: Vec<T>) -> Vec<T> {
        let range = self.range(items.len());
        items.truncate(range.end);
        items.drain(..range.start);
        items
    }

    /// Whether this shard's output starts with the header line: only the
    /// first shard's does, so the shards concatenate into one file.
    pub fn writes_header(&self) -> bool {
        self.index == 1
    }
}

impl FromStr for Shard {
    type Err = Error;

    fn from_str(text: &str) -> Result<Shard, Error> {
        let bad = || {
            Error::Input(InputError::DoesNotFit {
                what: "shard".into(),
                reason: format!("`{text}`: expected i/n with 1 ≤ i ≤ n (e.g. 2/4, the second of four)"),
            })
        };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let parse = |s: &str| s.trim().parse::<usize>().map_err(|_| bad());
        Shard::new(parse(i)?, parse(n)?)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blocks_cover_the_batch_once_in_order() {
        for len in [0, 1, 2, 3, 7, 10, 1000, 1001] {
            for count in 1..=12 {
                let mut covered = Vec::new();
                for index in 1..=count {
                    let r = Shard::new(index, count).unwrap().range(len);
                    assert!(r.len() == len / count || r.len() == len / count + 1, "{len} {index}/{count}: {r:?}");
                    covered.extend(r);
                }
                assert_eq!(covered, (0..len).collect::<Vec<_>>(), "{len} in {count}");
            }
        }
        let items: Vec<u32> = (0..10).collect();
        assert_eq!(Shard::new(2, 3).unwrap().take(items), vec![3, 4, 5]);
    }

    #[test]
    fn text_round_trips_and_bad_text_is_named() {
        let s: Shard = "2/4".parse().unwrap();
        assert_eq!((s.index(), s.count(), s.to_string()), (2, 4, "2/4".to_string()));
        assert!(s.range(8) == (2..4) && !s.writes_header() && Shard::ALL.writes_header());
        for bad in ["0/4", "5/4", "1/0", "2", "a/b", "-1/3", ""] {
            let e = bad.parse::<Shard>().unwrap_err().to_string();
            assert!(e.contains("shard") && e.contains("1 ≤ i ≤ n"), "{bad}: {e}");
        }
    }
}
