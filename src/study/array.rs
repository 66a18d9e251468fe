//! The shard of a task of a job array, read from the batch engine's environment: Slurm
//! (`SLURM_ARRAY_TASK_ID`, with `_MIN`, `_STEP` and `_COUNT`), PBS (`PBS_ARRAY_INDEX`, or
//! Torque's `PBS_ARRAYID`; the array numbered from 0, its size given) or LSF
//! (`LSB_JOBINDEX`, numbered from 1, with `LSB_JOBINDEX_END` and `_STEP`).

use crate::Error;
use crate::ensemble::Shard;

/// The shard of this task of a Slurm, PBS or LSF job array, read by `var` (the process's
/// environment: `|name| std::env::var(name).ok()`); `count`, when given, is the number of
/// shards (PBS does not say it). A missing or malformed variable is an error naming it.
///
/// ```
/// use hamel::study::shard_from_environment;
///
/// let slurm = |name: &str| match name {
///     "SLURM_ARRAY_TASK_ID" => Some("3".to_string()),
///     "SLURM_ARRAY_TASK_COUNT" => Some("8".to_string()),
///     _ => None,
/// };
/// let shard = shard_from_environment(None, slurm)?;
/// assert_eq!((shard.index, shard.count), (3, 8));
/// # Ok::<(), hamel::Error>(())
/// ```
pub fn shard_from_environment(
    count: Option<usize>,
    var: impl Fn(&str) -> Option<String>,
) -> Result<Shard, Error> {
    let number = |name: &'static str| -> Result<Option<usize>, Error> {
        match var(name) {
            None => Ok(None),
            Some(v) => v
                .trim()
                .parse::<usize>()
                .map(Some)
                .map_err(|_| Error::InvalidShard {
                    spec: format!("{name}={v}"),
                    reason: "is not a whole number ≥ 0",
                }),
        }
    };
    let (index, found, described) = if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
        let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let step = number("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
        let n = number("SLURM_ARRAY_TASK_COUNT")?;
        let described = format!("SLURM_ARRAY_TASK_ID={id}");
        let place =
            format!("{described}, SLURM_ARRAY_TASK_MIN={min}, SLURM_ARRAY_TASK_STEP={step}");
        (on_steps(id, min, step, &place)?, n, described)
    } else if let Some(i) = number("PBS_ARRAY_INDEX")?.or(number("PBS_ARRAYID")?) {
        (i, None, format!("PBS array index {i}"))
    } else if let Some(i) = number("LSB_JOBINDEX")? {
        let step = number("LSB_JOBINDEX_STEP")?.unwrap_or(1).max(1);
        let end = number("LSB_JOBINDEX_END")?;
        if i == 0 {
            return Err(Error::InvalidShard {
                spec: "LSB_JOBINDEX=0".into(),
                reason: "is not an LSF array's index: they count from 1 (`bsub -J \"study[1-8]\"`)",
            });
        }
        let place = format!("LSB_JOBINDEX={i}, LSB_JOBINDEX_STEP={step}");
        (
            on_steps(i, 1, step, &place)?,
            end.map(|e| (e.max(1) - 1) / step + 1),
            format!("LSB_JOBINDEX={i}"),
        )
    } else {
        return Err(Error::InvalidShard {
            spec: "env".into(),
            reason: "reads the shard from a job array's environment, and none is set: \
                     SLURM_ARRAY_TASK_ID (Slurm), PBS_ARRAY_INDEX or PBS_ARRAYID (PBS), \
                     LSB_JOBINDEX (LSF); outside an array give the shard as i/n",
        });
    };
    let count = count.or(found).ok_or(Error::InvalidShard {
        spec: format!("env ({described})"),
        reason: "has no count of shards: PBS does not give the array's size, so give it, \
                 `--shard env/8` for `-J 0-7`",
    })?;
    Shard::new(index, count).map_err(|_| Error::InvalidShard {
        spec: format!("env ({described}, {count} shards)"),
        reason: "is out of range: the array's indices must run over 0 … n − 1 (Slurm from \
                 its minimum, PBS from 0, LSF from 1)",
    })
}

/// The place of the array index `id` among `first`, `first + step`, …: an index below the
/// first, or between two steps, is no task of the array (a variable set by hand, or an
/// array other than the one described), and an error rather than another task's shard.
fn on_steps(id: usize, first: usize, step: usize, place: &str) -> Result<usize, Error> {
    let Some(offset) = id.checked_sub(first) else {
        return Err(Error::InvalidShard {
            spec: format!("env ({place})"),
            reason: "is below the array's minimum, so it is no task of the array: run it \
                     in the array, or give the shard as i/n",
        });
    };
    if offset % step != 0 {
        return Err(Error::InvalidShard {
            spec: format!("env ({place})"),
            reason: "is between two of the array's steps, so it is no task of the array: \
                     run it in the array, or give the shard as i/n",
        });
    }
    Ok(offset / step)
}
