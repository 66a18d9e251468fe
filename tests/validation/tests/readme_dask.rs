//! The README's Dask snippet, run as written — as a script, by Python — on the bicycle
//! study's example binary, where Python and dask are installed (`HAMEL_PYTHON` names the
//! interpreter, `python3` otherwise); skipped with a message where they are not. Nothing is
//! installed and nothing is built: the snippet's `target/release/examples/bicycle_study` is,
//! in a scratch directory, a link to the debug binary `cargo test --workspace` builds, and its
//! `grid.csv` a table of eight cases.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The README's Python block that uses `dask.distributed`.
fn dask_snippet() -> String {
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md");
    let text = std::fs::read_to_string(&readme).expect("the README");
    text.split("```python\n")
        .skip(1)
        .filter_map(|block| block.split("```").next())
        .find(|block| block.contains("dask.distributed"))
        .expect("the README has a Dask snippet")
        .to_string()
}

/// The debug build of the study example, beside this test's binary.
fn example_binary() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    let profile = exe.parent()?.parent()?;
    let binary = profile.join("examples").join("bicycle_study");
    binary.is_file().then_some(binary)
}

#[test]
fn the_readmes_dask_snippet_runs_as_written() {
    let python = std::env::var("HAMEL_PYTHON").unwrap_or_else(|_| "python3".into());
    let has_dask = Command::new(&python)
        .args(["-c", "import dask.distributed"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_dask {
        println!(
            "skipped: `{python}` with dask.distributed is not installed (HAMEL_PYTHON names another)"
        );
        return;
    }
    let Some(binary) = example_binary() else {
        println!(
            "skipped: the bicycle_study example is not built (cargo build --features png,study --example bicycle_study)"
        );
        return;
    };
    let dir = std::env::temp_dir().join(format!("hamel-readme-dask-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let examples = dir.join("target/release/examples");
    std::fs::create_dir_all(&examples).unwrap();
    std::os::unix::fs::symlink(&binary, examples.join("bicycle_study")).unwrap();
    let rows: String = (0..8)
        .map(|i| {
            format!(
                "{},{}\n",
                0.06 + 0.005 * f64::from(i),
                70.0 + 2.5 * f64::from(i)
            )
        })
        .collect();
    std::fs::write(dir.join("grid.csv"), format!("trail,rider_mass\n{rows}")).unwrap();
    std::fs::write(dir.join("study.py"), dask_snippet()).unwrap();
    let output = Command::new(&python)
        .arg("study.py")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "the snippet failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    for i in 0..8 {
        let shard = dir.join(format!("results/shard-{i:04}-of-0008.csv"));
        let text = std::fs::read_to_string(&shard).unwrap();
        assert_eq!(text.lines().count(), 2, "{text}");
        assert!(
            dir.join(format!("results/shard-{i:04}-of-0008.csv.manifest"))
                .is_file()
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}
