use super::*;

/// A fresh directory for one test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hamel-shard-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn stamp(rows: &[Vec<f64>], shard: Shard) -> ShardStamp {
    stamp_of(rows, shard, Program::new("squares", Some("1")))
}

fn stamp_of(rows: &[Vec<f64>], shard: Shard, program: Program) -> ShardStamp {
    let names = vec!["a".to_string()];
    ShardStamp::new(
        &names,
        rows.iter().map(Vec::as_slice),
        shard,
        &["a".into()],
        "csv",
        program,
    )
}

#[test]
fn shards_parse_and_cover_the_rows_in_order() {
    assert_eq!(Shard::parse("3/8").unwrap(), Shard { index: 3, count: 8 });
    assert_eq!(Shard::parse(" 0 / 1 ").unwrap(), Shard::ALL);
    for bad in ["8/8", "9/8", "0/0", "-1/8", "a/8", "3", "3/8/1", ""] {
        let e = Shard::parse(bad).unwrap_err();
        assert!(matches!(e, Error::InvalidShard { .. }), "{bad}: {e}");
        assert!(e.to_string().contains(&format!("`{bad}`")), "{e}");
    }
    for total in [0, 1, 7, 8, 100, 1001] {
        let mut next = 0;
        for index in 0..8 {
            let rows = Shard { index, count: 8 }.rows(total);
            assert_eq!(rows.start, next);
            assert!(rows.len() <= total / 8 + 1);
            next = rows.end;
        }
        assert_eq!(next, total);
    }
}

/// Before, the index was padded to four digits: past 9,999 shards `shard-10000-of-12000`
/// sorted before `shard-9999-of-12000`.
#[test]
fn shard_names_sort_in_shard_order_for_any_count() {
    assert_eq!(
        Shard { index: 3, count: 8 }.file_name("csv"),
        "shard-0003-of-0008.csv"
    );
    assert_eq!(
        Shard {
            index: 3,
            count: 12000
        }
        .file_name("csv"),
        "shard-00003-of-12000.csv"
    );
    for count in [1, 9, 10, 11, 9999, 10000, 10001, 123_457] {
        let names: Vec<String> = (0..count)
            .map(|index| Shard { index, count }.file_name("parquet"))
            .collect();
        let mut sorted = names.clone();
        sorted.sort();
        assert_eq!(sorted, names, "{count} shards");
    }
}

fn write(path: &Path, stamp: &ShardStamp, text: &str) -> Written {
    write_shard(path, stamp, |f| {
        f.write_all(text.as_bytes()).map_err(|e| Error::Io {
            path: "test".into(),
            message: e.to_string(),
        })
    })
    .unwrap()
}

/// Before, a shard counted as complete if its file existed: a truncated file, one without
/// its manifest or one of an edited grid was skipped.
#[test]
fn a_shard_is_complete_only_with_a_manifest_that_matches() {
    let dir = scratch("states");
    let rows = vec![vec![1.0], vec![2.0], vec![3.0]];
    let s = stamp(&rows, Shard::ALL);
    let path = dir.join(Shard::ALL.file_name("csv"));
    assert_eq!(shard_state(&path, &s), ShardState::Missing);
    assert_eq!(
        write(&path, &s, "case,a\n0,1\n1,2\n2,3\n"),
        Written::Written
    );
    assert_eq!(shard_state(&path, &s), ShardState::Complete);
    assert!(
        std::fs::read_to_string(manifest_path(&path))
            .unwrap()
            .contains("rows 3\n")
    );

    // An edited grid: every shard is stale.
    let edited = stamp(&[vec![1.0], vec![2.0], vec![3.5]], Shard::ALL);
    assert!(
        matches!(shard_state(&path, &edited), ShardState::Incomplete(r) if r.contains("another parameter table"))
    );
    // Truncated, then altered in place.
    std::fs::write(&path, "case,a\n0,1\n").unwrap();
    assert!(matches!(shard_state(&path, &s), ShardState::Incomplete(r) if r.contains("truncated")));
    std::fs::write(&path, "case,a\n0,1\n1,2\n2,4\n").unwrap();
    assert!(matches!(shard_state(&path, &s), ShardState::Incomplete(r) if r.contains("checksum")));
    // A file without its manifest (its task killed between the two renames).
    std::fs::remove_file(manifest_path(&path)).unwrap();
    assert!(
        matches!(shard_state(&path, &s), ShardState::Incomplete(r) if r.contains("no manifest"))
    );
    // A manifest that is not one.
    std::fs::write(manifest_path(&path), "hello").unwrap();
    assert!(
        matches!(shard_state(&path, &s), ShardState::Incomplete(r) if r.contains("not one hamel wrote"))
    );
    // Rewritten: complete again, and a killed task's leftovers removed.
    let leftover = dir.join(format!("{}.partial-1-0", Shard::ALL.file_name("csv")));
    std::fs::write(&leftover, "case,a\n0,").unwrap();
    write(&path, &s, "case,a\n0,1\n1,2\n2,3\n");
    assert_eq!(shard_state(&path, &s), ShardState::Complete);
    assert!(!leftover.exists());
    // The stamp tells the shards of one table apart, and the format.
    let rows8 = vec![vec![0.0]; 16];
    assert_ne!(
        stamp(&rows8, Shard { index: 0, count: 8 }),
        stamp(&rows8, Shard { index: 1, count: 8 })
    );
    let names = vec!["a".to_string()];
    let parquet = ShardStamp::new(
        &names,
        rows8.iter().map(Vec::as_slice),
        Shard::ALL,
        &names,
        "parquet",
        Program::new("squares", Some("1")),
    );
    assert_ne!(parquet, stamp(&rows8, Shard::ALL));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_file_that_fails_while_written_is_never_complete() {
    let dir = scratch("failed-write");
    let path = dir.join("shard-0000-of-0001.csv");
    let s = stamp(&[vec![1.0]], Shard::ALL);
    let e = write_shard(&path, &s, |file| {
        file.write_all(b"case,x,error\n0,").unwrap();
        Err(Error::Io {
            path: "disk".into(),
            message: "full".into(),
        })
    })
    .unwrap_err();
    assert!(matches!(e, Error::Io { .. }));
    assert_eq!(shard_state(&path, &s), ShardState::Missing);
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "nothing left behind"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Two writers of one shard, at once: each writes under its own name, so both succeed and
/// leave one complete file (before, both wrote `<name>.partial`, and one's rename failed).
#[test]
fn two_writers_of_one_shard_leave_one_complete_file() {
    let dir = scratch("two-writers");
    let path = dir.join(Shard::ALL.file_name("csv"));
    let s = stamp(&[vec![1.0]], Shard::ALL);
    let text: String = (0..20_000).map(|i| format!("{i},{}\n", i * 7)).collect();
    for _ in 0..10 {
        std::thread::scope(|scope| {
            let a = scope.spawn(|| write(&path, &s, &text));
            let b = scope.spawn(|| write(&path, &s, &text));
            a.join().unwrap();
            b.join().unwrap();
        });
        assert_eq!(shard_state(&path, &s), ShardState::Complete);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
    }
    let files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(files.len(), 2, "{files:?}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// Before, a shard's record hashed the parameter table but not the program: shards written by
/// a changed build of the same study were merged silently beside new ones. Now the manifest
/// records the study, the program's version and hamel's, and a shard of another program is
/// not complete for this one, the difference named.
#[test]
fn a_shard_of_another_program_is_not_complete_for_this_one() {
    let dir = scratch("programs");
    let rows = vec![vec![1.0], vec![2.0]];
    let path = dir.join(Shard::ALL.file_name("csv"));
    let v1 = stamp(&rows, Shard::ALL);
    write(&path, &v1, "case,a\n0,1\n1,2\n");
    let manifest = std::fs::read_to_string(manifest_path(&path)).unwrap();
    assert!(
        manifest.contains("study squares\nprogram 1\nhamel "),
        "{manifest}"
    );
    assert_eq!(shard_state(&path, &v1), ShardState::Complete);
    let cases = [
        (
            Program::new("squares", Some("2")),
            "the program's version is `1` in its manifest and `2` here",
        ),
        (
            Program::new("cubes", Some("1")),
            "the study is `squares` in its manifest and `cubes` here",
        ),
        (
            Program {
                hamel: "0.0.1".into(),
                ..Program::new("squares", Some("1"))
            },
            "hamel's version",
        ),
    ];
    for (program, why) in cases {
        let other = stamp_of(&rows, Shard::ALL, program);
        match shard_state(&path, &other) {
            ShardState::Incomplete(r) => {
                assert!(r.contains(why), "{r}");
                assert!(r.contains("not mixed"), "{r}");
            }
            state => panic!("{state:?}"),
        }
    }
    // Without a version, the program is the running executable.
    let unset = Program::new("squares", None);
    assert!(unset.version.starts_with("executable "), "{unset:?}");
    assert_ne!(unset.version, "executable unknown");
    assert_eq!(unset, Program::new("squares", None));
    // A manifest of the hamel before this record.
    std::fs::write(
        manifest_path(&path),
        "hamel shard manifest 1\nfile x\ngrid 0\nrows 2\nbytes 9\nxxh3 0\n",
    )
    .unwrap();
    assert!(
        matches!(shard_state(&path, &v1), ShardState::Incomplete(r) if r.contains("older hamel"))
    );
    std::fs::remove_dir_all(dir).unwrap();
}
