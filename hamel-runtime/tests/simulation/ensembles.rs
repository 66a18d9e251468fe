//! Studies of the skate: the same results for any number of threads and of shards (run as
//! separate processes, as a batch engine runs them), failed cases as rows carrying their
//! errors, and bad tables, shard specifications and output directories refused with a
//! message that names them.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use hamel_runtime::ensemble::{ShardStamp, ShardState, check_writable, shard_state, write_shard};
use hamel_runtime::{
    DormandPrince, Ensemble, Error, Outputs, ParameterTable, Shard, Simulation, Table,
};

use super::{Skate, X0};

/// The study's parameters: the skate's mass and inertia, its initial speed, and the gain of
/// a braking force that depends on the state (an input function per case).
const PARAMETERS: [&str; 4] = ["mass", "inertia", "speed", "brake"];

/// 48 cases on a grid; the last has no mass, so its run fails (a singular mass matrix).
fn grid() -> ParameterTable {
    let mut rows = Vec::new();
    for i in 0..48 {
        let k = i as f64;
        let mass = if i == 47 { 0.0 } else { 1.0 + 0.1 * k };
        rows.push(vec![mass, 0.2 + 0.01 * k, 0.5 + 0.05 * k, 0.1 * (k % 5.0)]);
    }
    ParameterTable::from_rows(PARAMETERS.iter().map(|s| s.to_string()).collect(), rows)
        .expect("a valid grid")
}

/// What each case keeps.
fn outputs() -> Outputs {
    Outputs::new().final_state().summary().sample_at(0.25)
}

/// Case `row` of `table`: the skate with those parameters, braked by −brake·v, for 0.5 s.
fn case(table: &ParameterTable, row: usize) -> Result<Vec<f64>, Error> {
    let p = |name| table.get(row, name).expect("the grid's columns");
    let skate: Skate = Skate {
        mass: p("mass"),
        inertia: p("inertia"),
    };
    let mut x0 = X0;
    x0[3] = p("speed");
    let brake = p("brake");
    let run = Simulation::new(&skate, x0)
        .end_time(0.5)
        .sample_interval(0.05)
        .run(&DormandPrince::new(1e-9, 1e-9), move |_, x| {
            [-brake * x[3], 0.0]
        })?;
    outputs().values::<Skate>(&run)
}

/// The study of `table`'s rows in `rows`, on `threads` threads, as a table.
fn study(table: &ParameterTable, rows: std::ops::Range<usize>, threads: usize) -> Table {
    let indices: Vec<u64> = rows.clone().map(|i| i as u64).collect();
    Ensemble::new(rows.len())
        .threads(threads)
        .table_of(outputs().names::<Skate>(), indices, |i| {
            case(table, rows.start + i)
        })
        .expect("the study's settings are valid")
}

fn csv(table: &Table) -> String {
    let mut out = Vec::new();
    table.write_csv(&mut out).unwrap();
    String::from_utf8(out).unwrap()
}

#[test]
fn a_study_gives_the_same_bits_on_any_number_of_threads() {
    let table = grid();
    let one = csv(&study(&table, 0..table.len(), 1));
    for threads in [2, 8] {
        assert_eq!(
            csv(&study(&table, 0..table.len(), threads)),
            one,
            "{threads} threads"
        );
    }
    // The failed case is a row with its error; the others ran.
    let result = Table::parse_csv(&one, "study").unwrap();
    assert_eq!(result.len(), 48);
    assert_eq!(result.failed(), 1);
    let error = result.errors()[47].as_ref().unwrap();
    assert_eq!(error.kind, "singular_mass_matrix");
    assert!(
        error.message.contains("singular reduced mass matrix"),
        "{error}"
    );
    assert!(result.column("final_x").unwrap()[47].is_nan());
    assert!(
        result.column("final_x").unwrap()[..47]
            .iter()
            .all(|v| v.is_finite())
    );
}

#[test]
fn a_case_that_panics_is_a_row_with_its_message() {
    let rows = Ensemble::new(4)
        .threads(2)
        .run(|i| {
            assert!(i != 2, "case two is broken");
            Ok(i)
        })
        .unwrap();
    assert!(
        matches!(&rows[2], Err(Error::CasePanicked { case: 2, message }) if message == "case two is broken")
    );
    assert_eq!(rows.iter().filter(|r| r.is_ok()).count(), 3);
    assert!(Ensemble::new(1).threads(0).run(|_| Ok(())).is_err());
}

/// The environment variables that make this test a worker running one shard.
const WORKER_SHARD: &str = "HAMEL_TEST_SHARD";
const WORKER_DIR: &str = "HAMEL_TEST_SHARD_DIR";

/// What a batch engine's task does: read the parameter table, run its shard's rows unless
/// the shard's file is complete, write the file whole or not at all, then its manifest.
fn run_shard(dir: &Path, shard: Shard) -> Result<(), Error> {
    let path = dir.join(shard.file_name("csv"));
    let table = ParameterTable::read(dir.join("grid.csv"), &PARAMETERS)?;
    let rows = (0..table.len()).map(|i| table.row(i).unwrap());
    let stamp = ShardStamp::new(
        table.names(),
        rows,
        shard,
        &outputs().names::<Skate>(),
        "csv",
        hamel_runtime::ensemble::Program::new("skates", Some("1")),
    );
    if shard_state(&path, &stamp) == ShardState::Complete {
        return Ok(());
    }
    let result = study(&table, shard.rows(table.len()), 2);
    write_shard(&path, &stamp, |file| {
        result.write_csv(file).map_err(|e| Error::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    })
    .map(|_| ())
}

/// A fresh directory for one test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs shards `i/n` for every i as separate processes of this test binary.
fn shards_in_processes(dir: &Path, n: usize) {
    let exe = std::env::current_exe().unwrap();
    let children: Vec<_> = (0..n)
        .map(|i| {
            Command::new(&exe)
                .args([&worker_test_name(), "--exact", "--test-threads=1"])
                .env(WORKER_SHARD, format!("{i}/{n}"))
                .env(WORKER_DIR, dir)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for child in children {
        let output = child.wait_with_output().unwrap();
        assert!(
            output.status.success(),
            "a shard failed: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

/// The name the test harness gives `shards_as_separate_processes_give_the_same_rows`: its
/// module's path without the crate's name (`simulation::ensembles::…`), so that a worker
/// runs that test alone wherever the module sits.
fn worker_test_name() -> String {
    let module = module_path!().split_once("::").map_or("", |(_, m)| m);
    format!("{module}::shards_as_separate_processes_give_the_same_rows")
}

/// The shards' tables in order, joined.
fn joined(dir: &Path, n: usize) -> Table {
    let mut all: Option<Table> = None;
    for index in 0..n {
        let path = dir.join(Shard { index, count: n }.file_name("csv"));
        let part = Table::parse_csv(&std::fs::read_to_string(&path).unwrap(), "shard").unwrap();
        match &mut all {
            None => all = Some(part),
            Some(all) => all.append(part).unwrap(),
        }
    }
    all.unwrap()
}

#[test]
fn shards_as_separate_processes_give_the_same_rows() {
    if let (Ok(spec), Ok(dir)) = (std::env::var(WORKER_SHARD), std::env::var(WORKER_DIR)) {
        // A worker: one shard, then done.
        run_shard(Path::new(&dir), Shard::parse(&spec).unwrap()).unwrap();
        return;
    }
    let (one, eight) = (scratch("one-shard"), scratch("eight-shards"));
    for dir in [&one, &eight] {
        std::fs::write(dir.join("grid.csv"), grid().to_csv()).unwrap();
    }
    shards_in_processes(&one, 1);
    shards_in_processes(&eight, 8);
    let whole = std::fs::read_to_string(one.join(Shard::ALL.file_name("csv"))).unwrap();
    assert_eq!(csv(&joined(&eight, 8)), whole, "8 shards against 1");

    // A restart recomputes what is missing and only that: shard 5 was killed while writing
    // (its half-written file has a name of its own and is not taken for it), shard 6 was
    // truncated after it finished, shard 2 finished.
    let five = eight.join(Shard { index: 5, count: 8 }.file_name("csv"));
    std::fs::remove_file(&five).unwrap();
    std::fs::remove_file(hamel_runtime::ensemble::manifest_path(&five)).unwrap();
    let half = eight.join(format!(
        "{}.partial-1-0",
        Shard { index: 5, count: 8 }.file_name("csv")
    ));
    std::fs::write(&half, "case,final_x\n3,0.1").unwrap();
    let six = eight.join(Shard { index: 6, count: 8 }.file_name("csv"));
    let text = std::fs::read_to_string(&six).unwrap();
    std::fs::write(&six, &text[..text.len() / 2]).unwrap();
    let two = eight.join(Shard { index: 2, count: 8 }.file_name("csv"));
    let before = std::fs::metadata(&two).unwrap().modified().unwrap();
    shards_in_processes(&eight, 8);
    assert_eq!(std::fs::metadata(&two).unwrap().modified().unwrap(), before);
    assert!(!half.exists());
    assert_eq!(std::fs::read_to_string(&six).unwrap(), text);
    assert_eq!(csv(&joined(&eight, 8)), whole, "after the restart");
    for dir in [one, eight] {
        std::fs::remove_dir_all(dir).unwrap();
    }
}

#[test]
fn bad_tables_shards_and_directories_are_refused_naming_them() {
    let known = &PARAMETERS;
    let cases = [
        (
            "mass,volume\n1,2\n",
            "grid.csv, line 1, column `volume`: unknown column; the study's parameters are mass, inertia, speed, brake",
        ),
        (
            "mass,inertia,speed,brake\n1,0.2,3,4\n2,heavy,3,4\n",
            "grid.csv, line 3, column `inertia`: `heavy` is not a number",
        ),
        (
            "mass,inertia,speed,brake\n1,0.2,3,4\n2\n",
            "grid.csv, line 3, column `inertia`: the value is missing",
        ),
        (
            "mass,inertia,speed,brake\n1,2,3,4,\n",
            "grid.csv, line 2: 5 values for 4 columns",
        ),
        (
            "mass,inertia,speed,brake\n1,inf,3,4\n",
            "grid.csv, line 2, column `inertia`: `inf` is not a finite number",
        ),
        (
            "mass,mass\n1,1\n",
            "grid.csv, line 1, column `mass`: the column is given twice",
        ),
        (
            "",
            "grid.csv, line 1: the table is empty: it needs a header of parameter names",
        ),
        (
            "mass,inertia,speed\n1,0.2,3\n",
            "grid.csv, line 1: the study's parameter `brake` is missing; its parameters are \
             mass, inertia, speed, brake",
        ),
    ];
    for (text, message) in cases {
        let e = ParameterTable::parse(text, "grid.csv", known).unwrap_err();
        assert!(matches!(e, Error::Table { .. }), "{e:?}");
        assert_eq!(e.to_string(), message);
    }
    let e = Shard::parse("8/8").unwrap_err();
    assert!(e.to_string().contains("`8/8` is out of range"), "{e}");

    // An output directory that cannot be written is refused before any run: here a path
    // under a file.
    let dir = scratch("unwritable");
    let file = dir.join("a-file");
    std::fs::write(&file, "").unwrap();
    let e = check_writable(file.join("results")).unwrap_err();
    assert!(
        matches!(&e, Error::Io { path, message } if path.ends_with("results") && message.contains("not writable")),
        "{e}"
    );
    check_writable(dir.join("new").join("results")).unwrap();
    std::fs::remove_dir_all(dir).unwrap();
}

/// Events and samples as columns: the skate on its circle passes x = 1.5 going one way at a
/// time that depends on its speed; a sample time the run does not have is a row's error.
#[test]
fn outputs_keep_event_times_and_chosen_samples() {
    let outputs = Outputs::new().event("x = 1.5").sample_at(0.5).summary();
    // The summary first, then the events, then the samples, whatever the order asked in.
    let names = outputs.names::<Skate>();
    assert_eq!(names[0], "steps");
    assert_eq!(names[9..12], ["x = 1.5_first", "x = 1.5_count", "x@0.5"]);
    let rows = Ensemble::new(3)
        .run(|i| {
            let mut x0 = X0;
            x0[3] = 1.0 + i as f64;
            let run = Simulation::new(&super::SKATE, x0)
                .end_time(1.0)
                .sample_interval(0.25)
                .event(hamel_runtime::Event::new("x = 1.5", |_, x: &[f64; 5]| {
                    x[0] - 1.5
                }))
                .run_constant(&DormandPrince::new(1e-10, 1e-10), [0.0, 0.0])?;
            outputs.values::<Skate>(&run)
        })
        .unwrap();
    let first: Vec<f64> = rows.iter().map(|r| r.as_ref().unwrap()[9]).collect();
    // Faster skates get there sooner; the count is one each.
    assert!(first[0] > first[1] && first[1] > first[2], "{first:?}");
    assert!(rows.iter().all(|r| r.as_ref().unwrap()[10] == 1.0));
    // The state at t = 0.5 (its x), and the summary: steps taken, the stop time NaN (every
    // run ran to its end).
    let row = rows[0].as_ref().unwrap();
    assert_eq!(row.len(), names.len());
    assert!(
        row[11] > X0[0] && row[0] > 0.0 && row[8].is_nan(),
        "{row:?}"
    );
    let e = Outputs::new()
        .sample_at(0.3)
        .values::<Skate>(
            &Simulation::new(&super::SKATE, X0)
                .end_time(1.0)
                .sample_interval(0.25)
                .run_constant(&DormandPrince::new(1e-8, 1e-8), [0.0, 0.0])
                .unwrap(),
        )
        .unwrap_err();
    assert!(matches!(e, Error::InvalidSetting { name: "sample time", value, .. } if value == 0.3));
}
