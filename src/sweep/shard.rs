//! Shards: a run computes every N-th point from I; Slurm job arrays map to shards.

use super::SweepError;

/// Which part of the grid a run computes: point ids `index, index + count, …`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// first point id, 0 ≤ index < count
    pub index: usize,
    /// number of shards
    pub count: usize,
}

impl Shard {
    /// The whole grid.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `I/N`.
    pub fn parse(text: &str) -> Result<Shard, SweepError> {
        let err = |rule: &str| SweepError::Shard {
            text: text.to_string(),
            rule: rule.into(),
        };
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| err("write the shard as I/N, e.g. 0/8"))?;
        let index: usize = i
            .trim()
            .parse()
            .map_err(|_| err("I is not a whole number"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| err("N is not a whole number"))?;
        if count == 0 || index >= count {
            return Err(err("needs 0 <= I < N"));
        }
        Ok(Shard { index, count })
    }

    /// From a Slurm job array: I = (SLURM_ARRAY_TASK_ID − MIN)/STEP, N = SLURM_ARRAY_TASK_COUNT
    /// (MIN = SLURM_ARRAY_TASK_MIN, default 0; STEP = SLURM_ARRAY_TASK_STEP, default 1).
    pub fn from_env(get: impl Fn(&str) -> Option<String>) -> Result<Shard, SweepError> {
        let num = |name: &str, default: Option<usize>| -> Result<usize, SweepError> {
            match get(name) {
                Some(v) => v.trim().parse().map_err(|_| SweepError::Shard {
                    text: format!("{name}={v}"),
                    rule: "is not a whole number".into(),
                }),
                None => default.ok_or_else(|| SweepError::Shard {
                    text: name.into(),
                    rule: "is not set (run inside a Slurm job array, or use --shard I/N)".into(),
                }),
            }
        };
        let id = num("SLURM_ARRAY_TASK_ID", None)?;
        let count = num("SLURM_ARRAY_TASK_COUNT", None)?;
        let min = num("SLURM_ARRAY_TASK_MIN", Some(0))?;
        let step = num("SLURM_ARRAY_TASK_STEP", Some(1))?.max(1);
        if id < min || (id - min) % step != 0 {
            return Err(SweepError::Shard {
                text: format!("SLURM_ARRAY_TASK_ID={id}"),
                rule: format!("is not MIN + k·STEP (MIN = {min}, STEP = {step})"),
            });
        }
        Shard::parse(&format!("{}/{count}", (id - min) / step))
    }

    /// The point ids of this shard among `total`.
    pub fn ids(&self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count.max(1)).collect()
    }

    /// The records file name of this shard in the study's output folder.
    pub fn records_file(&self) -> String {
        if *self == Shard::ALL {
            "sweep.records.csv".into()
        } else {
            format!("sweep.shard-{}-of-{}.records.csv", self.index, self.count)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_grid() {
        let mut all: Vec<usize> = (0..3)
            .flat_map(|i| Shard { index: i, count: 3 }.ids(10))
            .collect();
        all.sort_unstable();
        assert_eq!(all, (0..10).collect::<Vec<_>>());
        assert_eq!(Shard::parse("1/3").expect("ok").ids(10), vec![1, 4, 7]);
        assert!(Shard::parse("3/3").is_err());
        assert!(Shard::parse("1-3").is_err());
    }

    #[test]
    fn slurm_ids_map_to_shards() {
        let env = |vars: &'static [(&'static str, &'static str)]| {
            move |k: &str| {
                vars.iter()
                    .find(|(n, _)| *n == k)
                    .map(|(_, v)| v.to_string())
            }
        };
        // --array=0-7
        let s = Shard::from_env(env(&[
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
        ]));
        assert_eq!(s.expect("ok"), Shard { index: 5, count: 8 });
        // --array=1-8
        let s = Shard::from_env(env(&[
            ("SLURM_ARRAY_TASK_ID", "8"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
        ]));
        assert_eq!(s.expect("ok"), Shard { index: 7, count: 8 });
        // --array=10-16:2 (10, 12, 14, 16)
        let s = Shard::from_env(env(&[
            ("SLURM_ARRAY_TASK_ID", "14"),
            ("SLURM_ARRAY_TASK_MIN", "10"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]));
        assert_eq!(s.expect("ok"), Shard { index: 2, count: 4 });
        assert!(Shard::from_env(env(&[("SLURM_ARRAY_TASK_ID", "1")])).is_err());
    }
}
