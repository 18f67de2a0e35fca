//! CSV column tables: a write → read round trip is exact to the bit (`io::shortest` prints the shortest
//! text that parses back to the same f64), writes are atomic, and malformed input is an error
//! naming the file, the line and what was expected.

use articula::error::Error;
use articula::report::csv::{
    columns_to_string, parse_columns, read_columns, write_columns, write_filled_rows,
    write_row_table,
};
use std::path::Path;

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

/// A deterministic spread of awkward doubles: subnormals, huge, negative zero, thirds, π.
fn awkward(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    let mut out = vec![
        0.1,
        -0.0,
        1.0 / 3.0,
        std::f64::consts::PI,
        f64::MIN_POSITIVE,
        5e-324,
        f64::MAX,
        -1.7976931348623157e308,
        1e21,
        123456789.0,
    ];
    while out.len() < n {
        // xorshift64: random bit patterns, keeping only finite ones
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let x = f64::from_bits(s);
        if x.is_finite() {
            out.push(x);
        }
    }
    out.truncate(n);
    out
}

#[test]
fn round_trip_is_bit_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.csv");
    let a = awkward(200, 0x9E37_79B9_7F4A_7C15);
    let b = awkward(200, 0x0123_4567_89AB_CDEF);
    let c: Vec<f64> = (0..200).map(|i| i as f64 * 0.01).collect();
    let header = names(&["t_s", "knee, left (N·m)", "say \"hi\""]);
    write_columns(&path, &header, &[&c, &a, &b]).unwrap();
    let (h, cols) = read_columns(&path).unwrap();
    assert_eq!(h, header);
    assert_eq!(cols.len(), 3);
    for (got, want) in cols.iter().zip([&c, &a, &b]) {
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(want.iter()) {
            assert_eq!(g.to_bits(), w.to_bits(), "{g} != {w}");
        }
    }
}

/// Never a NaN in a file: a non-finite value fails the export, naming its column and row (and
/// `write_columns` leaves no file); a file read in may hold them.
#[test]
fn non_finite_values_are_not_written_but_read() {
    for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
        let e = columns_to_string(&names(&["x", "y"]), &[&[1.0, 2.0], &[0.5, bad]]).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("\"y\"") && msg.contains("row 2"), "{msg}");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        assert!(write_columns(&path, &names(&["x"]), &[&[bad]]).is_err());
        assert!(!path.exists());
    }
    let (_, cols) = parse_columns("x\ninf\n-inf\nNaN\n", Path::new("mem.csv")).unwrap();
    assert_eq!(cols[0][0], f64::INFINITY);
    assert_eq!(cols[0][1], f64::NEG_INFINITY);
    assert!(cols[0][2].is_nan());
}

#[test]
fn numbers_are_shortest_round_trip() {
    let text = columns_to_string(&names(&["a", "b"]), &[&[0.1, 2.0], &[1e-7, -3.25]]).unwrap();
    assert_eq!(text, "a,b\n0.1,1e-7\n2.0,-3.25\n");
}

#[test]
fn shape_mismatches_are_errors() {
    assert!(matches!(
        columns_to_string(&names(&["a"]), &[&[1.0], &[2.0]]),
        Err(Error::Invalid(_))
    ));
    assert!(matches!(
        columns_to_string(&names(&["a", "b"]), &[&[1.0, 2.0], &[2.0]]),
        Err(Error::Invalid(_))
    ));
    assert!(matches!(
        columns_to_string(&[], &[]),
        Err(Error::Invalid(_))
    ));
}

fn parse_err(text: &str) -> (usize, usize, String) {
    match parse_columns(text, Path::new("bad.csv")) {
        Err(Error::Parse { at, message }) => {
            assert_eq!(at.file, Path::new("bad.csv"));
            (at.line, at.column, message)
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn wrong_field_count_names_the_line() {
    let (line, _, msg) = parse_err("a,b\n1,2\n3,4\n5\n");
    assert_eq!(line, 4);
    assert!(msg.contains("1 fields, expected 2"), "{msg}");
    let (line, _, _) = parse_err("a,b\n1,2,3\n");
    assert_eq!(line, 2);
}

#[test]
fn non_numeric_field_names_line_column_and_header() {
    let (line, col, msg) = parse_err("t,x\n0,1\n0.5,oops\n");
    assert_eq!((line, col), (3, 5));
    assert!(msg.contains("\"x\"") && msg.contains("oops"), "{msg}");
}

#[test]
fn empty_file_is_an_error_and_header_only_is_empty_columns() {
    let (line, _, msg) = parse_err("");
    assert_eq!(line, 1);
    assert!(msg.contains("header"), "{msg}");
    let (h, cols) = parse_columns("a,b\n", Path::new("x.csv")).unwrap();
    assert_eq!(h, names(&["a", "b"]));
    assert!(cols.iter().all(Vec::is_empty));
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let err = read_columns(Path::new("/nonexistent/articula.csv")).unwrap_err();
    assert!(matches!(err, Error::Io { .. }));
    assert!(err.to_string().contains("/nonexistent/articula.csv"));
}

/// A table written from its rows is the text of the same table written from its columns, over
/// more rows than one thread formats at once (the pieces join in order), and reads back to
/// the bit; a row of the wrong width or a non-finite value is an error that writes nothing.
#[test]
fn rows_write_the_text_of_their_columns() {
    let n = 1_300;
    let a = awkward(n, 0x9E37_79B9_7F4A_7C15);
    let b = awkward(n, 0x0123_4567_89AB_CDEF);
    let t: Vec<f64> = (0..n).map(|i| i as f64 / 120.0).collect();
    let header = names(&["time", "a", "b"]);
    let rows: Vec<Vec<f64>> = (0..n).map(|i| vec![t[i], a[i], b[i]]).collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rows.csv");
    write_row_table(&path, &header, &rows).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, columns_to_string(&header, &[&t, &a, &b]).unwrap());
    assert_eq!(text.lines().count(), n + 1);
    let (h, cols) = read_columns(&path).unwrap();
    assert_eq!(h, header);
    for (got, want) in cols.iter().zip([&t, &a, &b]) {
        assert!(
            got.iter()
                .zip(want.iter())
                .all(|(g, w)| g.to_bits() == w.to_bits())
        );
    }
    // an empty table is its header
    write_row_table(&path, &header, &[]).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "time,a,b\n");
    let other = dir.path().join("bad.csv");
    let mut short = rows.clone();
    short[700].pop();
    let e = write_row_table(&other, &header, &short).unwrap_err();
    assert!(
        matches!(e, Error::Invalid(_)) && e.to_string().contains("row 701"),
        "{e}"
    );
    let mut nan = rows;
    nan[1_299][2] = f64::NAN;
    let e = write_row_table(&other, &header, &nan).unwrap_err();
    assert!(
        e.to_string().contains("\"b\"") && e.to_string().contains("row 1300"),
        "{e}"
    );
    assert!(!other.exists());
}

/// The text is each row's numbers by the one number printer, line after line, whatever the
/// number of threads: over several batches of pieces (each worker formats two pieces of 2¹⁶
/// numbers, 1,024 rows of this 64-column table, at a time, written before the next batch goes
/// into the same buffers), for pools of one, two and three threads, from rows, columns and a
/// row function, into a file as into a string.
#[test]
fn batches_of_pieces_join_in_order_for_any_thread_count() {
    use articula::io::shortest::Shortest;
    let (n, width) = (2 * 3 * 1024 * 2 + 17, 64);
    let cols: Vec<Vec<f64>> = (0..width)
        .map(|j| awkward(n, 0x5DEE_CE66_D1CE_4E5B ^ (j as u64 + 1)))
        .collect();
    let header: Vec<String> = (0..width).map(|j| format!("c{j}")).collect();
    let mut want = header.join(",") + "\n";
    let mut s = Shortest::new();
    for i in 0..n {
        for (j, c) in cols.iter().enumerate() {
            if j > 0 {
                want.push(',');
            }
            want.push_str(s.format(c[i]));
        }
        want.push('\n');
    }
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|i| cols.iter().map(|c| c[i]).collect())
        .collect();
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let dir = tempfile::tempdir().unwrap();
    for threads in 1..=3 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let path = dir.path().join(format!("t{threads}.csv"));
        pool.install(|| write_row_table(&path, &header, &rows))
            .unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), want, "{threads}");
        let text = pool.install(|| columns_to_string(&header, &refs)).unwrap();
        assert_eq!(text, want, "{threads}");
        let fill = |k: usize, r: &mut Vec<f64>| r.extend(cols.iter().map(|c| c[k]));
        pool.install(|| write_filled_rows(&path, &header, n, &fill))
            .unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), want, "{threads}");
    }
}

/// Rows made on the fly are checked as rows held are: a row of the wrong width, or a value
/// that is not finite (the first column holding one named, with its first row), writes nothing.
#[test]
fn filled_rows_are_checked_before_anything_is_written() {
    let header = names(&["time", "x", "y"]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("filled.csv");
    let short = |k: usize, r: &mut Vec<f64>| {
        r.extend([k as f64, 1.0]);
        if k != 3 {
            r.push(2.0);
        }
    };
    let e = write_filled_rows(&path, &header, 10, &short).unwrap_err();
    assert!(
        matches!(e, Error::Invalid(_)) && e.to_string().contains("row 4 has 2 values"),
        "{e}"
    );
    let nan = |k: usize, r: &mut Vec<f64>| {
        let y = if k >= 5 { f64::INFINITY } else { 0.5 };
        let x = if k == 7 { f64::NAN } else { 1.0 };
        r.extend([k as f64, x, y]);
    };
    let e = write_filled_rows(&path, &header, 10, &nan).unwrap_err();
    assert!(e.to_string().contains("\"x\" is NaN at row 8"), "{e}");
    assert!(!path.exists());
    write_filled_rows(&path, &header, 0, &nan).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "time,x,y\n");
}
