use super::*;

fn csv_of(t: &Table) -> String {
    let mut text = Vec::new();
    t.write_csv(&mut text).unwrap();
    String::from_utf8(text).unwrap()
}

fn two_columns() -> Table {
    Table::new(vec!["a".into(), "b".into()]).unwrap()
}

#[test]
fn tables_round_trip_through_csv_bit_for_bit() {
    let mut t = two_columns();
    t.push(3, Ok(vec![0.1 + 0.2, -1e-300])).unwrap();
    t.push(
        4,
        Err(Error::InvalidSetting {
            name: "x",
            value: 1.0,
            reason: "a \"quoted\", comma",
        }),
    )
    .unwrap();
    t.push(5, Ok(vec![1.0])).unwrap();
    let text = csv_of(&t);
    // A failed case's missing values are empty fields: null to pandas, polars and DuckDB,
    // whose means skip them (before, `NaN`, which made them NaN).
    assert!(text.starts_with(
        "case_index,a,b,error_kind,error\n3,0.30000000000000004,-1e-300,,\n4,,,invalid_setting,\""
    ));
    let back = Table::parse_csv(&text, "t.csv").unwrap();
    assert_eq!(back, t);
    assert_eq!(
        back.errors()[2].as_ref().unwrap().kind,
        "dimension_mismatch"
    );
    assert!(
        back.errors()[2]
            .as_ref()
            .unwrap()
            .message
            .contains("1 values for 2 columns")
    );
    assert_eq!(back.failed(), 2);
}

/// Before RFC 4180 by the `csv` crate, an error message with a line break (every multi-line
/// panic message) was written as a record the reader could not read back.
#[test]
fn every_message_and_value_reads_back_equal() {
    let mut t = two_columns();
    let messages = [
        "line one\nline two",
        "a \"quote\" and, a comma\r\nand a CRLF",
        "\"",
        "trailing newline\n",
        " spaces around ",
    ];
    for (i, m) in messages.iter().enumerate() {
        let values = vec![0.08 * i as f64, f64::NAN];
        let error = CaseError {
            kind: "case_panicked".into(),
            message: (*m).into(),
        };
        t.push_row(i as u64, values, Some(error)).unwrap();
    }
    let specials = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        -0.0,
        f64::MIN_POSITIVE,
    ];
    for (k, v) in specials.into_iter().enumerate() {
        t.push(100 + k as u64, Ok(vec![v, 5e-324])).unwrap();
    }
    let back = Table::parse_csv(&csv_of(&t), "t.csv").unwrap();
    assert_eq!(back, t);
    assert!(back.column("a").unwrap()[5].is_nan());
    assert_eq!(back.column("a").unwrap()[8].to_bits(), (-0.0f64).to_bits());
    // A panic's message, caught by the ensemble, as a row.
    let mut panicked = two_columns();
    let caught = Error::CasePanicked {
        case: 0,
        message: "assertion failed\n  left: 1\n right: 2".into(),
    };
    panicked.push(0, Err(caught)).unwrap();
    assert_eq!(
        Table::parse_csv(&csv_of(&panicked), "p.csv").unwrap(),
        panicked
    );
}

#[test]
fn failed_rows_keep_their_values_and_carry_a_kind() {
    let mut t = two_columns();
    let e = Error::CaseFailed {
        kind: "no_reversal".into(),
        message: "the spin never reversed".into(),
    };
    t.push_row(0, vec![0.2, f64::NAN], Some(CaseError::of(&e)))
        .unwrap();
    assert_eq!(t.column("a").unwrap()[0], 0.2);
    let back = Table::parse_csv(&csv_of(&t), "t.csv").unwrap();
    let error = back.errors()[0].as_ref().unwrap();
    assert_eq!(
        (error.kind.as_str(), error.message.as_str()),
        ("no_reversal", "the spin never reversed")
    );
    assert_eq!(back.column("a").unwrap()[0], 0.2);
    assert!(back.column("b").unwrap()[0].is_nan());
    assert!(csv_of(&t).ends_with("\n0,0.2,,no_reversal,the spin never reversed\n"));
    // A successful case's NaN is a value it computed, and stays one; a missing value in a
    // row that did not fail is not a table this module wrote.
    let mut computed = two_columns();
    computed.push(1, Ok(vec![f64::NAN, 1.0])).unwrap();
    assert!(csv_of(&computed).ends_with("\n1,NaN,1.0,,\n"));
    let e = Table::parse_csv("case_index,a,b,error_kind,error\n0,,2,,\n", "t.csv").unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.csv, line 2, column `a`: the value is missing, in a row that did not fail (no \
         error_kind)"
    );
    // An error without a kind is not a table this module wrote.
    let e =
        Table::parse_csv("case_index,a,b,error_kind,error\n0,1,2,,oops\n", "t.csv").unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.csv, line 2, column `error_kind`: an error needs its kind"
    );
}

#[test]
fn duplicate_case_indices_are_refused() {
    let text = "case_index,a,b,error_kind,error\n0,1,2,,\n1,1,2,,\n0,3,4,,\n";
    let e = Table::parse_csv(text, "t.csv").unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.csv, line 4, column `case_index`: the case index `0` is given twice: each case of a study \
         has one row"
    );
    let mut t = two_columns();
    t.push(7, Ok(vec![1.0, 2.0])).unwrap();
    assert!(matches!(
        t.push(7, Ok(vec![1.0, 2.0])),
        Err(Error::DuplicateName {
            kind: "case index",
            ..
        })
    ));
    let mut other = two_columns();
    other.push(7, Ok(vec![3.0, 4.0])).unwrap();
    assert!(t.append(other).is_err());
    assert_eq!(t.len(), 1);
}

#[test]
fn a_byte_order_mark_and_blank_lines_are_read_past() {
    let text = "\u{feff}trail,mass\r\n0.08,85\r\n\r\n0.1,90\r\n";
    let table = ParameterTable::parse(text, "grid.csv", &["trail", "mass"]).unwrap();
    assert_eq!(table.names(), ["trail", "mass"]);
    assert_eq!(table.len(), 2);
    let mut t = two_columns();
    t.push(0, Ok(vec![1.0, 2.0])).unwrap();
    let with_mark = format!("\u{feff}{}", csv_of(&t));
    assert_eq!(Table::parse_csv(&with_mark, "t.csv").unwrap(), t);
}

#[test]
fn missing_and_extra_columns_are_refused_naming_them() {
    let known = ["trail", "rider_mass", "speed"];
    let e = ParameterTable::parse("trail\n0.08\n", "grid.csv", &known).unwrap_err();
    assert_eq!(
        e.to_string(),
        "grid.csv, line 1: the study's parameters `rider_mass`, `speed` are missing; its \
         parameters are trail, rider_mass, speed"
    );
    let e = ParameterTable::parse(
        "trail,rider_mass,speed,colour\n0.08,85,1,2\n",
        "grid.csv",
        &known,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "grid.csv, line 1, column `colour`: unknown column; the study's parameters are trail, \
         rider_mass, speed"
    );
    // Any order of the columns is fine.
    let t =
        ParameterTable::parse("speed,trail,rider_mass\n1,0.08,85\n", "grid.csv", &known).unwrap();
    assert_eq!(t.get(0, "rider_mass"), Some(85.0));
}

#[test]
fn reading_a_missing_file_says_cannot_read() {
    let path = std::env::temp_dir()
        .join("hamel-no-such-dir")
        .join("grid.csv");
    for e in [
        ParameterTable::read(&path, &["trail"]).unwrap_err(),
        Table::read_csv(&path).unwrap_err(),
    ] {
        assert!(matches!(e, Error::Read { .. }), "{e}");
        assert!(e.to_string().starts_with("cannot read "), "{e}");
        assert!(e.to_string().contains("grid.csv"), "{e}");
    }
}

/// A parameter table is written only as one that reads back: a NaN is refused where the
/// table is made (before, it was written as `NaN`, which the reader refused).
#[test]
fn parameter_tables_round_trip_and_refuse_nan() {
    let names: Vec<String> = vec!["trail".into(), "mass".into()];
    let e = ParameterTable::from_rows(names.clone(), vec![vec![0.08, f64::NAN]]).unwrap_err();
    assert!(e.to_string().contains("mass (row 0"), "{e}");
    let rows = vec![vec![0.1 + 0.2, -0.0], vec![1e-310, 85.0]];
    let table = ParameterTable::from_rows(names, rows).unwrap();
    let back = ParameterTable::parse(&table.to_csv(), "grid.csv", &["trail", "mass"]).unwrap();
    assert_eq!(back, table);
    assert_eq!(back.get(0, "mass").unwrap().to_bits(), (-0.0f64).to_bits());
}

#[test]
fn bad_column_names_are_refused() {
    for bad in ["", "a,b", "case_index", "error", "error_kind", " a"] {
        assert!(Table::new(vec![bad.into()]).is_err(), "{bad:?}");
    }
    assert!(Table::new(vec!["a".into(), "a".into()]).is_err());
}

/// Before: `save_csv` wrote in place, and a file cut at a row boundary read back as a valid,
/// shorter table. Now it is written whole with its manifest, and `read_csv` refuses a file
/// that no longer matches it (and reads one without a manifest as it is).
#[test]
fn a_table_cut_short_after_it_was_written_is_refused() {
    let dir = std::env::temp_dir().join(format!("hamel-table-cut-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("results.csv");
    let mut t = two_columns();
    for i in 0..5 {
        t.push(i, Ok(vec![i as f64, 2.0 * i as f64])).unwrap();
    }
    t.save_csv(&path).unwrap();
    assert_eq!(Table::read_csv(&path).unwrap(), t);
    let text = std::fs::read_to_string(&path).unwrap();
    let cut: String = text.lines().take(3).map(|l| format!("{l}\n")).collect();
    std::fs::write(&path, &cut).unwrap();
    let e = Table::read_csv(&path).unwrap_err();
    assert!(matches!(e, Error::Read { .. }), "{e}");
    assert!(e.to_string().contains("truncated"), "{e}");
    // Without its manifest (copied alone, or written by another program) it reads as it is.
    std::fs::remove_file(crate::whole_file::manifest_of(&path)).unwrap();
    assert_eq!(Table::read_csv(&path).unwrap().len(), 2);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Before, a quote never closed made the rest of the file one value: a parameter table's
/// error quoted two lines as a number, or took the last value without a word, and a study
/// table counted the wrong fields. Now the error names the line the quote opened on.
#[test]
fn a_quote_never_closed_is_named_with_its_line() {
    let unclosed = |e: Error| {
        let text = e.to_string();
        assert!(
            text.contains("a quote opens a field here that is never closed"),
            "{text}"
        );
        text
    };
    let e = ParameterTable::parse(
        "trail,mass\n\"0.08,85\n0.1,90\n",
        "grid.csv",
        &["trail", "mass"],
    )
    .unwrap_err();
    assert!(unclosed(e).starts_with("grid.csv, line 2: "));
    let e = ParameterTable::parse(
        "trail,mass\n0.1,90\n0.08,\"85\n",
        "grid.csv",
        &["trail", "mass"],
    )
    .unwrap_err();
    assert!(unclosed(e).starts_with("grid.csv, line 3: "));
    let e =
        Table::parse_csv("case_index,a,error_kind,error\n0,1,\"x,\n1,2,,\n", "t.csv").unwrap_err();
    assert!(unclosed(e).starts_with("t.csv, line 2: "));
    // A closed quote with a line break inside, as multi-line messages are written, is fine.
    let text = "case_index,a,error_kind,error\n0,,k,\"two\nlines\"\n";
    assert_eq!(Table::parse_csv(text, "t.csv").unwrap().len(), 1);
}
