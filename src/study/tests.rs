//! A study run as a batch engine runs it: shards as separate processes of this test binary
//! (killed and restarted, two at once on one shard), joined, and compared byte for byte with
//! one task's file, in both formats.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use super::*;
use crate::ensemble::{Shard, manifest_path};

/// z = x² + y; the case x = 0.5, y = 2 fails with a kind of its own, x = 1, y = 3 panics
/// with a message of two lines and x = 20, y = 5 (case 804) with one. With `HAMEL_STUDY_SLOW` set, each case sleeps a millisecond.
fn study() -> Study<'static> {
    let slow = std::env::var_os("HAMEL_STUDY_SLOW").is_some();
    // With `HAMEL_STUDY_PANIC_FROM=i`, every case from i on panics too.
    let panic_from = std::env::var("HAMEL_STUDY_PANIC_FROM")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
        .unwrap_or(usize::MAX);
    Study::new("squares", "x² + y")
        .parameter("x", "m", "a length", steps(0.0, 0.5, 50))
        .parameter("y", "m²", "an area", steps(1.0, 1.0, 20))
        .output("z", "m²", "x² + y")
        .case(move |row| {
            if slow {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
            let (x, y) = (row.get("x")?, row.get("y")?);
            if (x, y) == (0.5, 2.0) {
                return Err(Error::CaseFailed {
                    kind: "too_small".into(),
                    message: "x is too small for y".into(),
                });
            }
            assert!((x, y) != (1.0, 3.0), "x = 1 and y = 3:\nno such square");
            // Case 804, in the seventh of eight shards: its message must name it as the
            // study's case, as one task names it.
            assert!((x, y) != (20.0, 5.0), "x = 20 and y = 5");
            assert!(row.index() < panic_from, "case {} of many", row.index());
            Ok(vec![x * x + y])
        })
}

/// A fresh directory for one test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-study-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn args(parts: &[&dyn AsRef<std::ffi::OsStr>]) -> Vec<String> {
    parts
        .iter()
        .map(|p| p.as_ref().to_string_lossy().into_owned())
        .collect()
}

/// Runs the study's command line in this process, its messages kept from the test's
/// output (written to the standard streams, they would pass the harness' capture).
fn quiet(args: &[String]) -> ExitCode {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    cli::main_to(&study(), args, &mut cli::Console::new(&mut out, &mut err))
}

/// Runs the study's command line in this process; panics unless it succeeds.
fn run_here(args: &[String]) {
    assert_eq!(quiet(args), ExitCode::SUCCESS, "{args:?}");
}

/// The formats this build writes.
fn formats() -> Vec<Format> {
    if cfg!(feature = "parquet") {
        vec![Format::Csv, Format::Parquet]
    } else {
        vec![Format::Csv]
    }
}

fn shard_file(dir: &Path, index: usize, count: usize, format: Format) -> PathBuf {
    dir.join(Shard { index, count }.file_name(format.extension()))
}

/// The grid written as a table, for the shards to read.
fn grid_file(dir: &Path) -> PathBuf {
    let grid = dir.join("grid.csv");
    run_here(&args(&[&"--write-grid", &grid]));
    grid
}

#[test]
fn one_shard_and_eight_joined_are_the_same_bytes_on_any_threads() {
    let dir = scratch("shards");
    let grid = grid_file(&dir);
    for format in formats() {
        let f = format.extension();
        let (one, eight, two) = (
            dir.join(format!("one-{f}")),
            dir.join(format!("eight-{f}")),
            dir.join(format!("two-{f}")),
        );
        run_here(&args(&[
            &"--table",
            &grid,
            &"--out",
            &one,
            &"--threads",
            &"1",
            &"--format",
            &f,
        ]));
        run_here(&args(&[
            &"--table",
            &grid,
            &"--out",
            &two,
            &"--threads",
            &"2",
            &"--format",
            &f,
        ]));
        for i in 0..8 {
            let shard = format!("{i}/8");
            run_here(&args(&[
                &"--table",
                &grid,
                &"--out",
                &eight,
                &"--shard",
                &shard,
                &"--format",
                &f,
            ]));
        }
        let merged = dir.join(format!("merged.{f}"));
        run_here(&args(&[
            &"--table",
            &grid,
            &"--merge",
            &eight,
            &"--into",
            &merged,
            &"--format",
            &f,
        ]));
        let single = std::fs::read(shard_file(&one, 0, 1, format)).unwrap();
        assert_eq!(
            std::fs::read(&merged).unwrap(),
            single,
            "8 shards against 1 ({f})"
        );
        assert_eq!(
            std::fs::read(shard_file(&two, 0, 1, format)).unwrap(),
            single,
            "2 threads against 1 ({f})"
        );

        // The rows: failed ones keep their parameters and carry their kind and message.
        let table = output::read(format, &merged).unwrap();
        assert_eq!(table.len(), 1000);
        assert_eq!(table.names(), ["x", "y", "z"]);
        let failed = table.errors()[21].as_ref().unwrap();
        assert_eq!(
            (failed.kind.as_str(), failed.message.as_str()),
            ("too_small", "x is too small for y")
        );
        assert_eq!(table.row(21).unwrap()[..2], [0.5, 2.0]);
        assert!(table.row(21).unwrap()[2].is_nan());
        let panicked = table.errors()[42].as_ref().unwrap();
        assert_eq!(panicked.kind, "case_panicked");
        assert!(
            panicked
                .message
                .ends_with("x = 1 and y = 3:\nno such square"),
            "{panicked}"
        );
        assert_eq!(table.row(42).unwrap()[..2], [1.0, 3.0]);
        // Before, the merged file named it "case 54", its place in its shard's block.
        let late = table.errors()[804].as_ref().unwrap();
        assert_eq!(late.message, "case 804 panicked: x = 20 and y = 5");
        assert_eq!(table.failed(), 3);
        assert_eq!(table.row(999).unwrap(), [24.5, 20.0, 24.5 * 24.5 + 20.0]);
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The environment variables that make this test binary a worker running the study's
/// command line.
const WORKER: &str = "HAMEL_STUDY_WORKER";

/// Runs the study's command line in a process of its own (this test binary, as a worker).
fn worker(args: &[String], slow: bool) -> Command {
    let mut command = Command::new(std::env::current_exe().unwrap());
    command
        .args([
            "study::tests::worker_entry",
            "--exact",
            "--test-threads=1",
            "--nocapture",
        ])
        .env(WORKER, args.join("\u{1f}"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if slow {
        command.env("HAMEL_STUDY_SLOW", "1");
    }
    command
}

/// A worker's entry: runs the command line it was given and exits with its code.
#[test]
fn worker_entry() {
    if let Ok(line) = std::env::var(WORKER) {
        let args: Vec<String> = line
            .split('\u{1f}')
            .filter(|a| !a.is_empty())
            .map(String::from)
            .collect();
        let code = study().main_with(&args);
        std::process::exit(if code == ExitCode::SUCCESS { 0 } else { 1 });
    }
}

/// Eight shard tasks started at once and killed (SIGKILL) after a while, three times over,
/// then left to finish: the shards joined are the uninterrupted run's bytes. A task killed
/// while writing leaves a file without its manifest, or none, and its shard is computed
/// again; finished shards are skipped.
#[test]
fn a_killed_study_resumes_to_the_same_bytes() {
    let dir = scratch("killed");
    let grid = grid_file(&dir);
    let (one, eight) = (dir.join("one"), dir.join("eight"));
    run_here(&args(&[&"--table", &grid, &"--out", &one]));
    let shard_args = |i: usize| {
        args(&[
            &"--table",
            &grid,
            &"--out",
            &eight,
            &"--shard",
            &format!("{i}/8"),
            &"--threads",
            &"1",
        ])
    };
    for wait in [40, 90, 150] {
        let mut children: Vec<_> = (0..8)
            .map(|i| worker(&shard_args(i), true).spawn().unwrap())
            .collect();
        std::thread::sleep(std::time::Duration::from_millis(wait));
        for child in &mut children {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
    let mut skipped = 0;
    for i in 0..8 {
        let output = worker(&shard_args(i), false).output().unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        skipped += usize::from(String::from_utf8_lossy(&output.stdout).contains("nothing to do"));
    }
    let merged = dir.join("merged.csv");
    run_here(&args(&[
        &"--table", &grid, &"--merge", &eight, &"--into", &merged,
    ]));
    assert_eq!(
        std::fs::read(&merged).unwrap(),
        std::fs::read(shard_file(&one, 0, 1, Format::Csv)).unwrap()
    );
    // Each shard's leftovers are gone: the shard files are the shards and their manifests.
    // (A task killed while it probed the directory leaves its `.hamel-probe-<pid>`, which no
    // pattern of shard names takes.)
    let left: Vec<String> = std::fs::read_dir(&eight)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.starts_with("shard-"))
        .collect();
    assert_eq!(left.len(), 16, "skipped {skipped}: {left:?}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Two tasks given the same shard at once: both exit 0 and one complete file is left
/// (before, in 2 of 10 trials one task exited 1 though the file was complete).
#[test]
fn two_tasks_on_one_shard_both_succeed() {
    let dir = scratch("two-tasks");
    let grid = grid_file(&dir);
    let out = dir.join("out");
    let expected = {
        let one = dir.join("one");
        run_here(&args(&[
            &"--table", &grid, &"--out", &one, &"--shard", &"1/2",
        ]));
        std::fs::read(shard_file(&one, 1, 2, Format::Csv)).unwrap()
    };
    let task = args(&[&"--table", &grid, &"--out", &out, &"--shard", &"1/2"]);
    for _ in 0..5 {
        let _ = std::fs::remove_dir_all(&out);
        let children: Vec<_> = (0..2)
            .map(|_| worker(&task, false).spawn().unwrap())
            .collect();
        for child in children {
            let output = child.wait_with_output().unwrap();
            assert!(
                output.status.success(),
                "{}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        assert_eq!(
            std::fs::read(shard_file(&out, 1, 2, Format::Csv)).unwrap(),
            expected
        );
        assert!(manifest_path(&shard_file(&out, 1, 2, Format::Csv)).exists());
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// A shard of another grid (the table edited after it ran) or a truncated one is computed
/// again; a merge refuses shards that are not complete, naming them.
#[test]
fn stale_and_truncated_shards_are_computed_again() {
    let dir = scratch("stale");
    let grid = grid_file(&dir);
    let out = dir.join("out");
    let task = |i: usize| {
        args(&[
            &"--table",
            &grid,
            &"--out",
            &out,
            &"--shard",
            &format!("{i}/2"),
        ])
    };
    run_here(&task(0));
    run_here(&task(1));
    let zero = shard_file(&out, 0, 2, Format::Csv);
    let good = std::fs::read(&zero).unwrap();
    // Edited: the first row's y from 1 to 1.5.
    let text = std::fs::read_to_string(&grid)
        .unwrap()
        .replacen("0.0,1.0", "0.0,1.5", 1);
    std::fs::write(&grid, text).unwrap();
    run_here(&task(0));
    let edited = std::fs::read_to_string(&zero).unwrap();
    assert!(edited.contains("\n0,0.0,1.5,1.5,,\n"), "{}", &edited[..80]);
    let into = dir.join("all.csv");
    let merge = args(&[&"--table", &grid, &"--merge", &out, &"--into", &into]);
    assert_eq!(
        quiet(&merge),
        ExitCode::FAILURE,
        "shard 1 is of the old grid"
    );
    run_here(&task(1));
    run_here(&merge);
    // Truncated after it finished: computed again, to the same bytes.
    std::fs::write(&zero, &edited[..edited.len() / 2]).unwrap();
    run_here(&task(0));
    assert_eq!(std::fs::read_to_string(&zero).unwrap(), edited);
    assert_ne!(edited.as_bytes(), good.as_slice());
    std::fs::remove_dir_all(dir).unwrap();
}

/// A table without one of the study's parameters is refused before any case runs (before,
/// the bicycle's study used 85 kg for a missing rider mass).
#[test]
fn a_table_without_a_parameter_is_refused() {
    let dir = scratch("missing-column");
    let grid = dir.join("grid.csv");
    std::fs::write(&grid, "x\n0.5\n").unwrap();
    let e = stream::run(
        &study(),
        &ParameterTable::read(&grid, &["x"]).unwrap(),
        0..1,
        Some(1),
        false,
        &mut |_| Ok(()),
    )
    .err()
    .unwrap();
    assert!(
        e.to_string()
            .contains("are not the study's parameters (x, y)"),
        "{e}"
    );
    let out = dir.join("out");
    let code = quiet(&args(&[&"--table", &grid, &"--out", &out]));
    assert_eq!(code, ExitCode::FAILURE);
    assert!(!shard_file(&out, 0, 1, Format::Csv).exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_shard_is_read_from_a_job_arrays_environment() {
    let env = |vars: &'static [(&'static str, &'static str)]| {
        move |name: &str| {
            vars.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.to_string())
        }
    };
    let shard = |count, vars| shard_from_environment(count, env(vars)).map(|s| (s.index, s.count));
    // Slurm, from 0 or from its minimum; PBS from 0, its size given; LSF from 1.
    assert_eq!(
        shard(
            None,
            &[
                ("SLURM_ARRAY_TASK_ID", "3"),
                ("SLURM_ARRAY_TASK_COUNT", "8")
            ]
        )
        .unwrap(),
        (3, 8)
    );
    const FROM_ONE: [(&str, &str); 3] = [
        ("SLURM_ARRAY_TASK_ID", "8"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_COUNT", "8"),
    ];
    assert_eq!(shard(None, &FROM_ONE).unwrap(), (7, 8));
    assert_eq!(shard(Some(4), &[("PBS_ARRAY_INDEX", "2")]).unwrap(), (2, 4));
    assert_eq!(shard(Some(4), &[("PBS_ARRAYID", "3")]).unwrap(), (3, 4));
    assert_eq!(
        shard(None, &[("LSB_JOBINDEX", "1"), ("LSB_JOBINDEX_END", "8")]).unwrap(),
        (0, 8)
    );
    // Mistakes, each saying what to do.
    let says = |count, vars, text: &str| {
        let e = shard(count, vars).unwrap_err().to_string();
        assert!(e.contains(text), "{e}");
    };
    says(None, &[], "none is set");
    says(None, &[("PBS_ARRAY_INDEX", "2")], "`--shard env/8`");
    says(
        None,
        &[("SLURM_ARRAY_TASK_ID", "x")],
        "SLURM_ARRAY_TASK_ID=x",
    );
    says(
        None,
        &[
            ("SLURM_ARRAY_TASK_ID", "9"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
        ],
        "out of range",
    );
    says(
        None,
        &[("LSB_JOBINDEX", "0"), ("LSB_JOBINDEX_END", "8")],
        "count from 1",
    );
}

/// Before, a task whose index was below the array's minimum ran shard 0 (a second task on
/// it), and an index between the array's steps ran the shard below it.
#[test]
fn an_array_index_off_the_array_is_refused() {
    let vars = |id: &'static str| {
        move |name: &str| {
            match name {
                "SLURM_ARRAY_TASK_ID" => Some(id),
                "SLURM_ARRAY_TASK_MIN" => Some("1"),
                "SLURM_ARRAY_TASK_STEP" => Some("2"),
                "SLURM_ARRAY_TASK_COUNT" => Some("4"),
                _ => None,
            }
            .map(String::from)
        }
    };
    // `--array=1-7:2`: the tasks 1, 3, 5, 7 are the shards 0 … 3.
    let shard = |id| shard_from_environment(None, vars(id)).map(|s| (s.index, s.count));
    assert_eq!(shard("1").unwrap(), (0, 4));
    assert_eq!(shard("7").unwrap(), (3, 4));
    let below = shard("0").unwrap_err().to_string();
    assert!(
        below.contains("SLURM_ARRAY_TASK_ID=0, SLURM_ARRAY_TASK_MIN=1")
            && below.contains("below the array's minimum"),
        "{below}"
    );
    let between = shard("4").unwrap_err().to_string();
    assert!(
        between.contains("SLURM_ARRAY_TASK_STEP=2")
            && between.contains("between two of the array's steps"),
        "{between}"
    );
}

/// Before, `Study::run(.., Some(0))` ran on every core, where `--threads 0` is refused.
#[test]
fn zero_threads_are_refused_in_a_program_too() {
    let study = study();
    let grid = study.grid().unwrap();
    let e = study.run(&grid, Some(0)).unwrap_err().to_string();
    assert!(e.contains("threads") && e.contains("at least 1"), "{e}");
}

/// Before, a parameter whose name cannot be a column was called "the output name".
#[test]
fn a_bad_parameter_name_is_called_a_parameter_name() {
    let bad = Study::new("bad", "a bad name")
        .parameter("x,y", "m", "two names in one", [1.0])
        .output("z", "m", "an output")
        .case(|_| Ok(vec![0.0]));
    let e = bad.grid().unwrap_err().to_string();
    assert!(e.contains("parameter name \"x,y\""), "{e}");
    assert!(!e.contains("output"), "{e}");
    let bad = Study::new("bad", "a bad name")
        .parameter("x", "m", "a length", [1.0])
        .output(" z", "m", "a space before")
        .case(|_| Ok(vec![0.0]));
    let e = bad.grid().unwrap_err().to_string();
    assert!(e.contains("output name \" z\""), "{e}");
}

/// Before, each of a thousand panicking cases printed its panic (four lines) on the
/// standard error stream; now the run prints how many panicked and the first few, with
/// where they panicked. The worker is another process, so that its stderr is counted.
#[test]
fn panicking_cases_are_summed_up_on_stderr() {
    let dir = scratch("panics");
    let grid = grid_file(&dir);
    let out = dir.join("out");
    let mut command = worker(
        &args(&[&"--table", &grid, &"--out", &out, &"--threads", &"2"]),
        false,
    );
    command.env("HAMEL_STUDY_PANIC_FROM", "600");
    let output = command.output().unwrap();
    assert!(output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    let lines = stderr.lines().count();
    assert!(lines <= 12, "{lines} lines:\n{stderr}");
    assert!(
        stderr.contains("401 cases panicked")
            && stderr.contains("case 42 panicked")
            && stderr.contains("src/study/tests.rs"),
        "{stderr}"
    );
    let table = Table::read_csv(shard_file(&out, 0, 1, Format::Csv)).unwrap();
    assert_eq!(table.failed(), 402);
    std::fs::remove_dir_all(dir).unwrap();
}

/// A writer whose reader has gone, as a closed pipe's.
struct Closed;

impl std::io::Write for Closed {
    fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
        Err(std::io::ErrorKind::BrokenPipe.into())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Err(std::io::ErrorKind::BrokenPipe.into())
    }
}

/// Before, a closed standard output (`study | true`) made the study panic at its first
/// message, after or before writing its file; now the messages are lost and the run is not.
#[test]
fn a_closed_standard_output_fails_nothing() {
    let dir = scratch("closed");
    let grid = dir.join("grid.csv");
    let out = dir.join("out");
    let (mut stdout, mut stderr) = (Closed, Closed);
    let mut console = cli::Console::new(&mut stdout, &mut stderr);
    for line in [
        args(&[&"--write-grid", &grid]),
        args(&[&"--table", &grid, &"--out", &out]),
        args(&[&"--help"]),
        args(&[&"--colour"]),
    ] {
        let code = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            cli::main_to(&study(), &line, &mut console)
        }))
        .unwrap_or_else(|_| panic!("{line:?} panicked"));
        let expected = if line[0] == "--colour" {
            ExitCode::from(2)
        } else {
            ExitCode::SUCCESS
        };
        assert_eq!(code, expected, "{line:?}");
    }
    assert_eq!(
        Table::read_csv(shard_file(&out, 0, 1, Format::Csv))
            .unwrap()
            .len(),
        1000
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// The names in `dir` that are not the files a study writes whole: its writers' leftovers.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.contains(".partial"))
        .collect()
}

/// The default grid's task killed while it writes `squares.csv` leaves its `.partial` file;
/// the next run removes it (before, the leftovers of every killed run stayed).
#[test]
fn a_killed_run_of_the_default_grid_leaves_nothing_behind_the_next() {
    let dir = scratch("killed-grid");
    let started = std::time::Instant::now();
    let mut killed = 0;
    while leftovers(&dir).is_empty() {
        assert!(
            started.elapsed().as_secs() < 60,
            "no run was killed while writing"
        );
        let mut child = worker(&args(&[&"--threads", &"1"]), true)
            .current_dir(&dir)
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(150 + 50 * killed));
        let _ = child.kill();
        let _ = child.wait();
        killed += 1;
    }
    let output = worker(&[], false).current_dir(&dir).output().unwrap();
    assert!(output.status.success());
    assert_eq!(leftovers(&dir), Vec::<String>::new());
    assert_eq!(
        Table::read_csv(dir.join("squares.csv")).unwrap().len(),
        1000
    );
    std::fs::remove_dir_all(dir).unwrap();
}
