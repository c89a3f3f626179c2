//! The records files (one line per finished point, appended and flushed as points finish) and
//! `sweep.csv` (the same rows sorted by point id, under the plain CSV header).
//!
//! Numbers are written with Rust's shortest round-trip formatting, so reading a record back
//! gives the same `f64` and writing it again gives the same bytes.

use std::fmt::Write as _;
use std::path::Path;

use super::point::PointRecord;
use super::spec::{Axis, SweepSpec};
use super::SweepError;

/// The columns after the axis columns, in order (the contract of `sweep.csv`).
/// `stable_up_to_m_s` holds the top of the speed range when some result is above range.
pub const RESULT_COLUMNS: [&str; 8] = [
    "kalker_critical_speed_m_s",
    "hopf_speed_m_s",
    "nonlinear_critical_speed_m_s",
    "status",
    "kalker_frequency_hz",
    "hopf_frequency_hz",
    "nonlinear_located",
    "stable_up_to_m_s",
];

/// The result columns written before `stable_up_to_m_s` existed (records format 1): no onset
/// in the speed range was then a failed point. `sweep.csv` files of this form are still read;
/// records files are refused (a resume would mix the two meanings).
pub const FORMAT1_COLUMNS: &[&str] = RESULT_COLUMNS.split_at(7).0;

/// The CSV header line (without line break) for these axes.
pub fn header(axes: &[Axis]) -> String {
    let mut cols = vec!["point_id".to_string()];
    cols.extend(axes.iter().map(Axis::column));
    cols.extend(RESULT_COLUMNS.iter().map(|s| s.to_string()));
    cols.join(",")
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |x| x.to_string())
}

/// One CSV row (without line break).
pub fn row(r: &PointRecord) -> String {
    let mut s = r.id.to_string();
    for v in &r.values {
        let _ = write!(s, ",{v}");
    }
    let _ = write!(
        s,
        ",{},{},{},{},{},{},{},{}",
        opt(r.kalker_m_s),
        opt(r.hopf_m_s),
        opt(r.nonlinear_m_s),
        r.status(),
        opt(r.kalker_frequency_hz),
        opt(r.hopf_frequency_hz),
        opt(r.nonlinear_located),
        opt(r.stable_up_to_m_s)
    );
    s
}

/// `sweep.csv`: header and rows sorted by point id.
pub fn sweep_csv(axes: &[Axis], rows: &[PointRecord]) -> String {
    let mut sorted: Vec<&PointRecord> = rows.iter().collect();
    sorted.sort_by_key(|r| r.id);
    let mut s = header(axes);
    s.push('\n');
    for r in sorted {
        s.push_str(&row(r));
        s.push('\n');
    }
    s
}

/// The comment lines and header that open a records file.
pub fn records_preamble(spec: &SweepSpec, fingerprint: &str, shard: (usize, usize)) -> String {
    preamble(&spec.axes, spec.len(), fingerprint, shard)
}

/// The comment lines and header that open a records file of `points` points over `axes`.
pub fn preamble(axes: &[Axis], points: usize, fingerprint: &str, shard: (usize, usize)) -> String {
    format!(
        "# critspeed sweep records: one line per finished point, in finishing order\n\
         # fingerprint: {fingerprint}\n# points: {}\n# shard: {}/{}\n{}\n",
        points,
        shard.0,
        shard.1,
        header(axes)
    )
}

/// Whether the header `cols` ends with the columns `tail`.
fn ends_with(cols: &[String], tail: &[&str]) -> bool {
    cols.len() >= tail.len()
        && cols[cols.len() - tail.len()..]
            .iter()
            .zip(tail)
            .all(|(a, b)| a == b)
}

fn bad(path: &Path, line: usize, problem: impl Into<String>) -> SweepError {
    SweepError::Records {
        path: path.display().to_string(),
        line,
        problem: problem.into(),
    }
}

fn parse_opt<T: std::str::FromStr>(
    path: &Path,
    line: usize,
    col: &str,
    s: &str,
) -> Result<Option<T>, SweepError> {
    if s.is_empty() {
        return Ok(None);
    }
    s.parse()
        .map(Some)
        .map_err(|_| bad(path, line, format!("column {col}: {s:?} is not a value")))
}

/// Parses one data row with `n_axes` axis columns and `n_results` result columns
/// ([`RESULT_COLUMNS`] or the format-1 [`FORMAT1_COLUMNS`]).
fn parse_row(
    path: &Path,
    line: usize,
    (n_axes, n_results): (usize, usize),
    text: &str,
) -> Result<PointRecord, SweepError> {
    let f: Vec<&str> = text.split(',').collect();
    if f.len() != 1 + n_axes + n_results {
        return Err(bad(
            path,
            line,
            format!("{} columns, expected {}", f.len(), 1 + n_axes + n_results),
        ));
    }
    let id = f[0]
        .parse()
        .map_err(|_| bad(path, line, format!("point_id {:?} is not an index", f[0])))?;
    let values = f[1..=n_axes]
        .iter()
        .map(|s| {
            parse_opt::<f64>(path, line, "axis", s)?
                .ok_or_else(|| bad(path, line, "empty axis value"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let r = &f[1 + n_axes..];
    let status = super::point::parse_status(r[3]).map_err(|e| bad(path, line, e))?;
    let (failures, above_range) = (status.failures, status.above);
    let stable_up_to_m_s = match r.get(7) {
        Some(s) => parse_opt(path, line, RESULT_COLUMNS[7], s)?,
        None => None,
    };
    if above_range.is_empty() != stable_up_to_m_s.is_none() {
        return Err(bad(
            path,
            line,
            format!(
                "status {:?} and {} {:?} disagree: a value is given exactly when some result is above range",
                r[3],
                RESULT_COLUMNS[7],
                r.get(7).unwrap_or(&"")
            ),
        ));
    }
    Ok(PointRecord {
        id,
        values,
        kalker_m_s: parse_opt(path, line, RESULT_COLUMNS[0], r[0])?,
        hopf_m_s: parse_opt(path, line, RESULT_COLUMNS[1], r[1])?,
        nonlinear_m_s: parse_opt(path, line, RESULT_COLUMNS[2], r[2])?,
        failures,
        kalker_frequency_hz: parse_opt(path, line, RESULT_COLUMNS[4], r[4])?,
        hopf_frequency_hz: parse_opt(path, line, RESULT_COLUMNS[5], r[5])?,
        nonlinear_located: parse_opt(path, line, RESULT_COLUMNS[6], r[6])?,
        above_range,
        stable_up_to_m_s,
        no_hopf: status.no_hopf,
    })
}

/// A records file as read.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordsFile {
    /// the study fingerprint it was written for
    pub fingerprint: String,
    /// grid size of that study
    pub points: usize,
    /// the column names of the header
    pub columns: Vec<String>,
    /// finished points, in file order
    pub rows: Vec<PointRecord>,
    /// bytes of complete lines (a trailing partial line, from an interrupted write, is ignored)
    pub complete_len: usize,
}

/// Reads a records file written by a sweep.
pub fn read_records(path: &Path) -> Result<RecordsFile, SweepError> {
    let text = std::fs::read_to_string(path).map_err(|source| SweepError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let complete_len = text.rfind('\n').map_or(0, |i| i + 1);
    let mut fingerprint = None;
    let mut points = None;
    let mut columns: Option<Vec<String>> = None;
    let mut rows = Vec::new();
    for (k, line) in text[..complete_len].lines().enumerate() {
        let n = k + 1;
        if let Some(c) = line.strip_prefix('#') {
            if let Some(v) = c.trim().strip_prefix("fingerprint:") {
                fingerprint = Some(v.trim().to_string());
            } else if let Some(v) = c.trim().strip_prefix("points:") {
                points = Some(
                    v.trim()
                        .parse()
                        .map_err(|_| bad(path, n, "points is not a count"))?,
                );
            }
        } else if let Some(cols) = &columns {
            let n_axes = cols.len() - 1 - RESULT_COLUMNS.len();
            rows.push(parse_row(path, n, (n_axes, RESULT_COLUMNS.len()), line)?);
        } else {
            let cols: Vec<String> = line.split(',').map(str::to_string).collect();
            if cols.first().map(String::as_str) != Some("point_id") {
                return Err(bad(
                    path,
                    n,
                    "expected the header line starting with point_id",
                ));
            }
            if cols.len() > 1 + FORMAT1_COLUMNS.len() && ends_with(&cols, FORMAT1_COLUMNS) {
                return Err(SweepError::OldRecords {
                    path: path.display().to_string(),
                });
            }
            if cols.len() < 2 + RESULT_COLUMNS.len() || !ends_with(&cols, &RESULT_COLUMNS) {
                return Err(bad(
                    path,
                    n,
                    format!(
                        "the header must be point_id, the axes, {}",
                        RESULT_COLUMNS.join(", ")
                    ),
                ));
            }
            columns = Some(cols);
        }
    }
    Ok(RecordsFile {
        fingerprint: fingerprint.ok_or_else(|| bad(path, 0, "no '# fingerprint:' line"))?,
        points: points.ok_or_else(|| bad(path, 0, "no '# points:' line"))?,
        columns: columns.ok_or_else(|| bad(path, 0, "no header line"))?,
        rows,
        complete_len,
    })
}

/// `sweep.csv` as read: the column names and the rows (sorted by point id).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepCsv {
    /// all column names, in file order
    pub columns: Vec<String>,
    /// the axis column names (key with SI unit suffix)
    pub axis_columns: Vec<String>,
    /// one record per point, sorted by id
    pub rows: Vec<PointRecord>,
}

/// Reads a `sweep.csv` written by `critspeed sweep` or `critspeed merge`.
pub fn read_csv(path: &Path) -> Result<SweepCsv, SweepError> {
    let text = std::fs::read_to_string(path).map_err(|source| SweepError::Io {
        path: path.display().to_string(),
        source,
    })?;
    let mut lines = text.lines().enumerate();
    let (_, head) = lines.next().ok_or_else(|| bad(path, 1, "empty file"))?;
    let columns: Vec<String> = head.split(',').map(str::to_string).collect();
    // the current header, or the format-1 one (no stable_up_to_m_s column)
    let n_results = if ends_with(&columns, &RESULT_COLUMNS) {
        RESULT_COLUMNS.len()
    } else if ends_with(&columns, FORMAT1_COLUMNS) {
        FORMAT1_COLUMNS.len()
    } else {
        0
    };
    let n_axes = columns.len().saturating_sub(1 + n_results);
    if columns.first().map(String::as_str) != Some("point_id") || n_axes == 0 || n_results == 0 {
        return Err(bad(
            path,
            1,
            format!(
                "header is not point_id, axes, {}",
                RESULT_COLUMNS.join(", ")
            ),
        ));
    }
    let mut rows = lines
        .filter(|(_, l)| !l.is_empty())
        .map(|(k, l)| parse_row(path, k + 1, (n_axes, n_results), l))
        .collect::<Result<Vec<_>, _>>()?;
    rows.sort_by_key(|r| r.id);
    Ok(SweepCsv {
        axis_columns: columns[1..=n_axes].to_vec(),
        columns,
        rows,
    })
}
