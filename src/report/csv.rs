//! Column tables as CSV: one header line, then one line per sample, one column per series.
//!
//! Numbers are printed by `ryu` (Adams 2018, *Ryū: fast float-to-string conversion*, PLDI): the
//! shortest text that parses back to the same `f64`, so a write → read round trip is exact to the
//! bit. A non-finite value (NaN, ±∞) is never written: the export fails naming its column and
//! row, and nothing is written (a file read in may hold `NaN`, `inf`, `-inf`). The values are
//! whatever SI quantities the caller puts in; the header names carry the unit (e.g.
//! `"knee_tau_Nm"`, `"t_s"`). Files are written atomically ([`crate::io::write_atomic`]).

use crate::error::Error;
use std::path::Path;

/// The CSV text of `columns` under `header`: a header line, then row `i` holds `columns[j][i]`.
///
/// Errors when `header` and `columns` differ in length, when the columns differ in length, when
/// there are no columns, or when a value is not finite.
pub fn columns_to_string(header: &[String], columns: &[&[f64]]) -> Result<String, Error> {
    // shape checks: one header per column, every column the same length
    if columns.is_empty() {
        return Err(Error::Invalid(
            "CSV export: no columns to write (give at least one series)".into(),
        ));
    }
    if header.len() != columns.len() {
        return Err(Error::Invalid(format!(
            "CSV export: {} header names for {} columns; give one name per column",
            header.len(),
            columns.len()
        )));
    }
    let rows = columns[0].len();
    if let Some((j, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != rows) {
        return Err(Error::Invalid(format!(
            "CSV export: column {:?} has {} values but column {:?} has {rows}; columns must have \
             the same length",
            header[j],
            c.len(),
            header[0]
        )));
    }

    if let Some((j, i)) = columns
        .iter()
        .enumerate()
        .find_map(|(j, c)| c.iter().position(|x| !x.is_finite()).map(|i| (j, i)))
    {
        return Err(Error::Numerical(format!(
            "CSV export: column {:?} is {} at row {}; nothing written",
            header[j],
            columns[j][i],
            i + 1
        )));
    }

    // header through the csv writer (quotes names holding commas or quotes), numbers via ryu
    let mut w = ::csv::WriterBuilder::new()
        .terminator(::csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    w.write_record(header)
        .map_err(|e| Error::Invalid(format!("CSV export: header: {e}")))?;
    let mut out = w
        .into_inner()
        .map_err(|e| Error::Invalid(format!("CSV export: header: {e}")))?;
    let mut buf = ryu::Buffer::new();
    for i in 0..rows {
        for (j, c) in columns.iter().enumerate() {
            if j > 0 {
                out.push(b',');
            }
            out.extend_from_slice(buf.format(c[i]).as_bytes());
        }
        out.push(b'\n');
    }
    String::from_utf8(out).map_err(|e| Error::Invalid(format!("CSV export: header: {e}")))
}

/// Writes [`columns_to_string`] to `path` atomically.
pub fn write_columns(path: &Path, header: &[String], columns: &[&[f64]]) -> Result<(), Error> {
    let text = columns_to_string(header, columns)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// The CSV text of a table of text cells (a summary: names, statuses, messages, numbers
/// already formatted) under `header`; every row holds one cell per header name.
///
/// Cells holding commas, quotes or line breaks are quoted by the csv writer.
pub fn table_to_string(header: &[String], rows: &[Vec<String>]) -> Result<String, Error> {
    if let Some((i, r)) = rows
        .iter()
        .enumerate()
        .find(|(_, r)| r.len() != header.len())
    {
        return Err(Error::Invalid(format!(
            "CSV export: row {} has {} cells for {} header names; give one cell per column",
            i + 1,
            r.len(),
            header.len()
        )));
    }
    let mut w = ::csv::WriterBuilder::new()
        .terminator(::csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    for record in std::iter::once(header).chain(rows.iter().map(Vec::as_slice)) {
        w.write_record(record)
            .map_err(|e| Error::Invalid(format!("CSV export: {e}")))?;
    }
    let out = w
        .into_inner()
        .map_err(|e| Error::Invalid(format!("CSV export: {e}")))?;
    String::from_utf8(out).map_err(|e| Error::Invalid(format!("CSV export: {e}")))
}

/// Writes [`table_to_string`] to `path` atomically.
pub fn write_table(path: &Path, header: &[String], rows: &[Vec<String>]) -> Result<(), Error> {
    let text = table_to_string(header, rows)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// Reads a file written by [`write_columns`] (or any header + numeric CSV): the header names and
/// one `Vec` per column.
///
/// Bad input is a [`Error::Parse`] naming the file, the 1-based line and the column of the
/// offending field: a row with the wrong number of fields, a field that is not a number, a file
/// without a header. Blank lines are skipped; spaces around fields are ignored.
pub fn read_columns(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_columns(&text, path)
}

/// Parses CSV `text` as [`read_columns`] does; `file` is only used in error messages.
pub fn parse_columns(text: &str, file: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), Error> {
    let mut rdr = ::csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(::csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut records = rdr.records();

    // header: the first record
    let header: Vec<String> = match records.next() {
        Some(Ok(r)) => r.iter().map(str::to_string).collect(),
        Some(Err(e)) => return Err(csv_error(file, &e)),
        None => {
            return Err(Error::parse(
                file,
                1,
                1,
                "empty file: expected a header line of column names",
            ));
        }
    };
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); header.len()];

    // rows: exactly one number per header name
    for r in records {
        let r = r.map_err(|e| csv_error(file, &e))?;
        let line = r.position().map_or(0, |p| p.line() as usize);
        if r.len() != header.len() {
            return Err(Error::parse(
                file,
                line,
                1,
                format!(
                    "{} fields, expected {} (one per header column)",
                    r.len(),
                    header.len()
                ),
            ));
        }
        // column of each field: 1 + the lengths of the fields and commas before it (exact for
        // unquoted, untrimmed fields, which is what numbers are)
        let mut col = 1;
        for (j, field) in r.iter().enumerate() {
            let x: f64 = field.parse().map_err(|_| {
                Error::parse(
                    file,
                    line,
                    col,
                    format!(
                        "column {:?}: {field:?} is not a number, expected a decimal number",
                        header[j]
                    ),
                )
            })?;
            columns[j].push(x);
            col += field.len() + 1;
        }
    }
    Ok((header, columns))
}

/// A csv crate error (bad UTF-8, unterminated quote) as a located parse error.
fn csv_error(file: &Path, e: &::csv::Error) -> Error {
    let line = e.position().map_or(0, |p| p.line() as usize);
    Error::parse(file, line, 1, format!("malformed CSV: {e}"))
}
