//! Column tables as CSV: one header line, then one line per sample, one column per series.
//!
//! Numbers are printed by [`Shortest`] (the digits of Ryū, Adams 2018, PLDI, made by `zmij`): the
//! shortest text that parses back to the same `f64`, so a write → read round trip is exact to the
//! bit. A non-finite value (NaN, ±∞) is never written: the export fails naming its column and
//! row, and nothing is written (a file read in may hold `NaN`, `inf`, `-inf`). The values are
//! whatever SI quantities the caller puts in; the header names carry the unit (e.g.
//! `"knee_tau_Nm"`, `"t_s"`). Files are written atomically ([`crate::io::write_atomic`]).
//! Tables come as columns, as rows (`pipeline`'s row tables, one row per frame) or as a
//! function that makes each row (written without holding the table); the rows are formatted in
//! pieces of about 2¹⁶ numbers, a few pieces at a time in parallel, and the pieces written in
//! order, so the text is the same whatever the number of threads.

use crate::error::Error;
use crate::io::shortest::Shortest;
use std::io::Write;
use std::path::Path;

/// The CSV text of `columns` under `header`: a header line, then row `i` holds `columns[j][i]`.
///
/// Errors when `header` and `columns` differ in length, when the columns differ in length, when
/// there are no columns, or when a value is not finite.
pub fn columns_to_string(header: &[String], columns: &[&[f64]]) -> Result<String, Error> {
    let table = Table::checked(header, Cells::Columns(columns))?;
    let mut text = Vec::new();
    table
        .write(&mut text)
        .map_err(|e| Error::Invalid(format!("CSV export: {e}")))?;
    String::from_utf8(text).map_err(|e| Error::Invalid(format!("CSV export: {e}")))
}

/// Writes [`columns_to_string`] to `path` atomically.
pub fn write_columns(path: &Path, header: &[String], columns: &[&[f64]]) -> Result<(), Error> {
    let table = Table::checked(header, Cells::Columns(columns))?;
    crate::io::write_atomic_with(path, |w| table.write(w))
}

/// Writes the CSV of `rows` (row `i` holds the values of line `i`, one per header name) to
/// `path` atomically: the same text as [`write_columns`] of their columns, without making the
/// columns.
pub fn write_row_table(path: &Path, header: &[String], rows: &[Vec<f64>]) -> Result<(), Error> {
    let table = Table::checked(header, Cells::Rows(rows))?;
    crate::io::write_atomic_with(path, |w| table.write(w))
}

/// Writes the CSV of `nrows` rows, row `i` being what `fill(i, row)` appends to an empty `row`
/// (one value per header name), to `path` atomically: the text of [`write_row_table`] of those
/// rows without making them (an output table of a minute take is 5–17 MB of fresh memory, whose
/// first touch costs more than formatting it). `fill` is called more than once per row.
pub fn write_filled_rows(
    path: &Path,
    header: &[String],
    nrows: usize,
    fill: &(dyn Fn(usize, &mut Vec<f64>) + Sync),
) -> Result<(), Error> {
    let table = Table::checked(header, Cells::Filled { nrows, fill })?;
    crate::io::write_atomic_with(path, |w| table.write(w))
}

/// The numbers of a table as a caller holds them.
#[derive(Clone, Copy)]
enum Cells<'a> {
    /// Column `j` is `columns[j]`.
    Columns(&'a [&'a [f64]]),
    /// Row `i` is `rows[i]`.
    Rows(&'a [Vec<f64>]),
    /// Row `i` is what `fill(i, row)` appends to an empty `row`.
    Filled {
        nrows: usize,
        fill: &'a (dyn Fn(usize, &mut Vec<f64>) + Sync),
    },
}

/// The shape of `nrows` rows under `header`, which must name at least one column.
fn rows_under(header: &[String], nrows: usize) -> Result<(usize, usize), Error> {
    if header.is_empty() {
        return Err(Error::Invalid(
            "CSV export: no columns to write (give at least one series)".into(),
        ));
    }
    Ok((header.len(), nrows))
}

impl Cells<'_> {
    /// Number of columns and rows, or what does not fit (columns or rows of unequal lengths).
    fn shape(&self, header: &[String]) -> Result<(usize, usize), Error> {
        match *self {
            Cells::Columns(columns) => {
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
                        "CSV export: column {:?} has {} values but column {:?} has {rows}; \
                         columns must have the same length",
                        header[j],
                        c.len(),
                        header[0]
                    )));
                }
                Ok((columns.len(), rows))
            }
            // the rows' widths are checked as they are read (`Table::checked`)
            Cells::Rows(rows) => rows_under(header, rows.len()),
            Cells::Filled { nrows, .. } => rows_under(header, nrows),
        }
    }

    /// Appends the values of row `i` to `out`.
    #[inline]
    fn row_into(&self, i: usize, out: &mut Vec<f64>) {
        match *self {
            Cells::Columns(columns) => out.extend(columns.iter().map(|c| c[i])),
            Cells::Rows(rows) => out.extend_from_slice(&rows[i]),
            Cells::Filled { fill, .. } => fill(i, out),
        }
    }
}

/// Numbers per piece of text formatted on one thread (about 1.3 MB of text), whole rows: 675
/// rows of a 96-coordinate take's torques, 7 of its mass matrix's 9,217 columns.
const CELLS_PER_PIECE: usize = 1 << 16;

/// Pieces formatted at once per worker thread: each batch of pieces is written before the next
/// is formatted into the same buffers.
const PIECES_PER_THREAD: usize = 2;

/// A numeric table checked for writing: its header line (through the csv writer, which quotes
/// names holding commas or quotes) and its numbers, every one finite.
struct Table<'a> {
    head: Vec<u8>,
    cells: Cells<'a>,
    ncols: usize,
    nrows: usize,
}

impl<'a> Table<'a> {
    /// `cells` under `header`, or what cannot be written (a shape that does not fit, or the
    /// first non-finite value column by column, named with its row): nothing is written then.
    fn checked(header: &[String], cells: Cells<'a>) -> Result<Self, Error> {
        let (ncols, nrows) = cells.shape(header)?;
        // row by row: a row of the wrong width, else the first non-finite value of each
        // column; the message names the first column that has one
        let mut first_bad: Vec<Option<(usize, f64)>> = vec![None; ncols];
        let mut row = Vec::with_capacity(ncols);
        for i in 0..nrows {
            row.clear();
            cells.row_into(i, &mut row);
            if row.len() != ncols {
                return Err(Error::Invalid(format!(
                    "CSV export: row {} has {} values for {ncols} header names; give one value \
                     per column",
                    i + 1,
                    row.len(),
                )));
            }
            if crate::lanes::all_finite(&row) {
                continue;
            }
            for (bad, &x) in first_bad.iter_mut().zip(&row) {
                if bad.is_none() && !x.is_finite() {
                    *bad = Some((i, x));
                }
            }
        }
        if let Some((j, (i, x))) =
            (first_bad.iter().enumerate()).find_map(|(j, b)| Some((j, (*b)?)))
        {
            return Err(Error::Numerical(format!(
                "CSV export: column {:?} is {x} at row {}; nothing written",
                header[j],
                i + 1
            )));
        }
        let mut w = ::csv::WriterBuilder::new()
            .terminator(::csv::Terminator::Any(b'\n'))
            .from_writer(Vec::new());
        w.write_record(header)
            .map_err(|e| Error::Invalid(format!("CSV export: header: {e}")))?;
        let head = w
            .into_inner()
            .map_err(|e| Error::Invalid(format!("CSV export: header: {e}")))?;
        Ok(Self {
            head,
            cells,
            ncols,
            nrows,
        })
    }

    /// Writes the text to `w`: the header line, then the rows by [`Shortest`],
    /// [`CELLS_PER_PIECE`] numbers (whole rows, at least one) to a piece, a batch of
    /// [`PIECES_PER_THREAD`] pieces per worker formatted in parallel and written in order, the
    /// next batch into the same buffers (each piece is the same text whichever thread made it;
    /// a minute take's 14 MB of text is never held at once).
    fn write(&self, w: &mut dyn Write) -> std::io::Result<()> {
        use rayon::prelude::*;
        w.write_all(&self.head)?;
        let (ncols, nrows) = (self.ncols, self.nrows);
        let rows_per_piece = (CELLS_PER_PIECE / ncols.max(1)).max(1);
        let starts: Vec<usize> = (0..nrows).step_by(rows_per_piece).collect();
        let per_batch = PIECES_PER_THREAD * rayon::current_num_threads();
        let mut pieces: Vec<Vec<u8>> = vec![Vec::new(); per_batch.min(starts.len())];
        for batch in starts.chunks(per_batch) {
            let pieces = &mut pieces[..batch.len()];
            pieces
                .par_iter_mut()
                .zip(batch)
                .for_each(|(piece, &first)| {
                    let rows = first..nrows.min(first + rows_per_piece);
                    // the buffer moved here while it is filled: the pieces' lengths side by
                    // side in one cache line, updated at every number by two threads, made
                    // two-thread runs slower than one
                    let mut out = std::mem::take(piece);
                    // a number takes at most 24 bytes and its comma or line end one: no
                    // regrowth
                    out.clear();
                    out.reserve(rows.len() * ncols * 25);
                    let mut buf = Shortest::new();
                    let mut row = Vec::with_capacity(ncols);
                    for i in rows {
                        row.clear();
                        self.cells.row_into(i, &mut row);
                        for (j, &x) in row.iter().enumerate() {
                            if j > 0 {
                                out.push(b',');
                            }
                            out.extend_from_slice(buf.format(x).as_bytes());
                        }
                        out.push(b'\n');
                    }
                    *piece = out;
                });
            for piece in pieces.iter() {
                w.write_all(piece)?;
            }
        }
        Ok(())
    }
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
