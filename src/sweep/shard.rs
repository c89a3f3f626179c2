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
    ///
    /// COUNT, MIN and STEP describe the *submission*, not the sweep: a single index resubmitted
    /// with `sbatch --array=1` has COUNT = 1 and MIN = 1 and would run as shard 0/1. Use
    /// [`Shard::from_env_with_count`] for a task that may be resubmitted.
    pub fn from_env(get: impl Fn(&str) -> Option<String>) -> Result<Shard, SweepError> {
        let id = env_number(&get, "SLURM_ARRAY_TASK_ID", None)?;
        let count = env_number(&get, "SLURM_ARRAY_TASK_COUNT", None)?;
        let min = env_number(&get, "SLURM_ARRAY_TASK_MIN", Some(0))?;
        let step = env_number(&get, "SLURM_ARRAY_TASK_STEP", Some(1))?.max(1);
        if id < min || (id - min) % step != 0 {
            return Err(SweepError::Shard {
                text: format!("SLURM_ARRAY_TASK_ID={id}"),
                rule: format!("is not MIN + k·STEP (MIN = {min}, STEP = {step})"),
            });
        }
        Shard::parse(&format!("{}/{count}", (id - min) / step))
    }

    /// From a Slurm job array with the shard count fixed by the caller (`--shards N`): the
    /// array index is the shard index, I = SLURM_ARRAY_TASK_ID, 0 ≤ I < N, whatever the
    /// submission's COUNT, MIN and STEP. The whole sweep is `--array=0-(N−1)`; any single index
    /// resubmitted alone (`sbatch --array=5`) is still shard 5/N and resumes its own records.
    pub fn from_env_with_count(
        get: impl Fn(&str) -> Option<String>,
        count: usize,
    ) -> Result<Shard, SweepError> {
        if count == 0 {
            return Err(SweepError::Shard {
                text: "--shards 0".into(),
                rule: "must be at least 1".into(),
            });
        }
        let id = env_number(&get, "SLURM_ARRAY_TASK_ID", None)?;
        if id >= count {
            return Err(SweepError::Shard {
                text: format!("SLURM_ARRAY_TASK_ID={id} with --shards {count}"),
                rule: format!(
                    "the array index is the shard index and needs 0 <= ID < {count}; submit --array=0-{}",
                    count - 1
                ),
            });
        }
        Ok(Shard { index: id, count })
    }

    /// The point ids of this shard among `total`.
    pub fn ids(&self, total: usize) -> Vec<usize> {
        (self.index..total).step_by(self.count.max(1)).collect()
    }

    /// The records file name of this shard in the study's output folder.
    pub fn records_file(&self) -> String {
        self.records_file_of("sweep")
    }

    /// The records file name of this shard for an analysis whose files start with `stem`
    /// (`sweep`, `uncertainty`).
    pub fn records_file_of(&self, stem: &str) -> String {
        if *self == Shard::ALL {
            format!("{stem}.records.csv")
        } else {
            format!("{stem}.shard-{}-of-{}.records.csv", self.index, self.count)
        }
    }
}

/// A whole-number environment variable, or `default` when it is not set.
fn env_number(
    get: &impl Fn(&str) -> Option<String>,
    name: &str,
    default: Option<usize>,
) -> Result<usize, SweepError> {
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
}

/// The shard counts `N` of the files `sweep.shard-I-of-N.records.csv` among `names`, sorted,
/// each once: the counts a sweep's output folder already holds records for.
pub fn recorded_counts<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<usize> {
    recorded_counts_of("sweep", names)
}

/// [`recorded_counts`] of the records files `<stem>.shard-I-of-N.records.csv`.
pub fn recorded_counts_of<'a>(stem: &str, names: impl IntoIterator<Item = &'a str>) -> Vec<usize> {
    let prefix = format!("{stem}.shard-");
    let mut counts: Vec<usize> = names
        .into_iter()
        .filter_map(|n| {
            let rest = n
                .strip_prefix(prefix.as_str())?
                .strip_suffix(".records.csv")?;
            let (i, n) = rest.split_once("-of-")?;
            i.parse::<usize>().ok()?;
            n.parse().ok().filter(|&n: &usize| n > 0)
        })
        .collect();
    counts.sort_unstable();
    counts.dedup();
    counts
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

    /// `sbatch --array=1 job.sh` after a 4-task array: Slurm sets COUNT = 1, MIN = MAX = 1.
    const RESUBMITTED_INDEX_1: &[(&str, &str)] = &[
        ("SLURM_ARRAY_TASK_ID", "1"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_MAX", "1"),
        ("SLURM_ARRAY_TASK_STEP", "1"),
        ("SLURM_ARRAY_TASK_COUNT", "1"),
    ];

    fn lookup(vars: &'static [(&'static str, &'static str)]) -> impl Fn(&str) -> Option<String> {
        move |k: &str| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn resubmitted_array_index_ran_as_shard_0_of_1() {
        // the defect: the submission's own COUNT and MIN made index 1 the whole grid
        let old = Shard::from_env(lookup(RESUBMITTED_INDEX_1)).expect("parses");
        assert_eq!(old, Shard { index: 0, count: 1 });
        // the fix: with the count given, index 1 stays shard 1 of 4
        let s = Shard::from_env_with_count(lookup(RESUBMITTED_INDEX_1), 4).expect("ok");
        assert_eq!(s, Shard { index: 1, count: 4 });
        assert_eq!(s.ids(10), vec![1, 5, 9]);
        assert_eq!(s.records_file(), "sweep.shard-1-of-4.records.csv");
        // an index outside the shards, and no shards at all, are refused
        let e = Shard::from_env_with_count(lookup(RESUBMITTED_INDEX_1), 1).expect_err("1 >= 1");
        assert!(e.to_string().contains("--array=0-0"), "{e}");
        assert!(Shard::from_env_with_count(lookup(RESUBMITTED_INDEX_1), 0).is_err());
        assert!(Shard::from_env_with_count(lookup(&[]), 4).is_err());
    }

    #[test]
    fn recorded_counts_read_the_file_names() {
        let names = [
            "sweep.shard-0-of-4.records.csv",
            "sweep.shard-3-of-4.records.csv",
            "sweep.records.csv",
            "sweep.shard-0-of-1.records.csv",
            "sweep.shard-x-of-4.records.csv",
            "sweep.csv",
        ];
        assert_eq!(recorded_counts(names), vec![1, 4]);
    }
}
