//! The sweep's CSV (read by column name, extra columns tolerated) and the trade's CSV.
//!
//! `sweep.csv`: an optional `point_id` column, one column per swept key named by the key with
//! its SI unit appended (`suspension.longitudinal_stiffness_n_per_m`), the result columns
//! `kalker_critical_speed_m_s`, `hopf_speed_m_s`, `nonlinear_critical_speed_m_s` (empty when
//! not computed or not found) and `status` (`ok`, `above range: <results>` or
//! `failed: <reasons>`, and `no Hopf point in range: nonlinear`, see
//! [`crate::sweep::point::parse_status`]); the optional
//! `stable_up_to_m_s` (the top of the speed range of a point with results above range). Fields
//! may be quoted (RFC 4180, one record per line).

use super::{ResultKind, Target, TradeError, TradePlan};
use crate::sweep::point::parse_status;
use crate::sweep::Computed;

/// One sweep point, as the trade sees it (SI values).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// `point_id`, or the 1-based data row number when the table has none
    pub id: String,
    /// swept key → value (SI), for the keys the trade names
    pub axes: Vec<(String, f64)>,
    /// results (m/s) in [`ResultKind::ALL`] order; `None` = empty or not finite
    pub results: [Option<f64>; 3],
    /// `ok`, `above range: <results>`, or the failure reason
    pub status: String,
    /// results (in [`ResultKind::ALL`] order) with no onset in the point's speed range
    pub above: [bool; 3],
    /// top of the speed range (m/s) when some result is above range
    pub stable_up_to_m_s: Option<f64>,
}

impl Row {
    /// The finite value of swept key `key`.
    pub fn axis(&self, key: &str) -> Option<f64> {
        let v = self.axes.iter().find(|(k, _)| k == key).map(|(_, v)| *v);
        v.filter(|v| v.is_finite())
    }

    /// A result (m/s), if present.
    pub fn result(&self, r: ResultKind) -> Option<f64> {
        let i = ResultKind::ALL.iter().position(|k| *k == r)?;
        self.results[i].filter(|v| v.is_finite())
    }

    /// Whether the sweep computed every result of this point without failure: status `ok` or
    /// `above range: …` (a V_NL not computed for want of a Hopf point counts as not computed).
    pub fn ok(&self) -> bool {
        parse_status(self.status.trim()).is_ok_and(|s| s.failures.is_empty() && !s.no_hopf)
    }

    /// The top of the speed range (m/s) when result `r` had no onset in it (V > that speed).
    pub fn above_range(&self, r: ResultKind) -> Option<f64> {
        let i = ResultKind::ALL.iter().position(|k| *k == r)?;
        self.stable_up_to_m_s
            .filter(|v| self.above[i] && v.is_finite())
    }

    /// The result capped at the top of the speed range, min(V, v_max): the found value, or
    /// v_max when above range. Known exactly for every point that has either.
    pub fn capped(&self, r: ResultKind) -> Option<f64> {
        self.result(r).or_else(|| self.above_range(r))
    }
}

/// Which results a status names as above range (none for a status that is not a sweep's).
fn above_flags(status: &str) -> [bool; 3] {
    let above = parse_status(status.trim()).map_or(Vec::new(), |s| s.above);
    Computed::ALL.map(|c| above.contains(&c))
}

/// A CSV table: header and string cells.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepTable {
    /// file name, for messages
    pub file: String,
    /// column names
    pub header: Vec<String>,
    /// data records, each as long as the header, with their 1-based line numbers
    pub records: Vec<(usize, Vec<String>)>,
}

fn split_record(line: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', true) => quoted = false,
            ('"', false) if cur.is_empty() => quoted = true,
            (',', false) => out.push(std::mem::take(&mut cur)),
            (c, _) => cur.push(c),
        }
    }
    if quoted {
        return Err("unterminated quoted field".into());
    }
    out.push(cur);
    Ok(out)
}

/// Quote a CSV field when it holds a comma, quote or line break.
pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Parse CSV text (first non-empty line = header).
pub fn read_sweep(text: &str, file: &str) -> Result<SweepTable, TradeError> {
    let err = |line: usize, problem: String| TradeError::Csv {
        file: file.to_string(),
        line,
        problem,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty());
    let (hl, h) = lines
        .next()
        .ok_or_else(|| err(1, "the file is empty".into()))?;
    let header: Vec<String> = split_record(h)
        .map_err(|p| err(hl, p))?
        .into_iter()
        .map(|c| c.trim().to_string())
        .collect();
    let mut records = Vec::new();
    for (n, l) in lines {
        let rec = split_record(l).map_err(|p| err(n, p))?;
        if rec.len() != header.len() {
            let p = format!("{} fields, the header has {}", rec.len(), header.len());
            return Err(err(n, p));
        }
        records.push((n, rec));
    }
    Ok(SweepTable {
        file: file.to_string(),
        header,
        records,
    })
}

impl SweepTable {
    fn missing(&self, what: String, wanted: String) -> TradeError {
        TradeError::MissingColumn {
            file: self.file.clone(),
            what,
            wanted,
            columns: self.header.join(","),
        }
    }

    /// Index of the column of swept key `key` (`<key>_<unit>`, or `<key>` when dimensionless).
    pub fn axis_column(&self, key: &str) -> Result<usize, TradeError> {
        let prefix = format!("{key}_");
        // dimensionless keys have no unit suffix
        let mut hits = self
            .header
            .iter()
            .enumerate()
            .filter(|(_, c)| c.starts_with(&prefix) || *c == key);
        match (hits.next(), hits.next()) {
            (Some((i, _)), None) => Ok(i),
            _ => Err(self.missing(
                format!("the swept key {key}"),
                format!("one column {key} or {prefix}<unit>"),
            )),
        }
    }

    fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|c| c == name)
    }

    /// The rows with the values `plan` needs. Errors: a needed column is missing, or a cell
    /// that should be a number is not.
    pub fn rows(&self, plan: &TradePlan) -> Result<Vec<Row>, TradeError> {
        let mut keys = vec![plan.objective.key.clone()];
        for c in &plan.constraints {
            if let Target::Axis { key, .. } = &c.target {
                keys.push(key.clone());
            }
        }
        let axis_cols = keys
            .iter()
            .map(|k| Ok((k.clone(), self.axis_column(k)?)))
            .collect::<Result<Vec<_>, TradeError>>()?;
        let needed: Vec<ResultKind> = plan
            .constraints
            .iter()
            .filter_map(|c| match c.target {
                Target::Result(r) => Some(r),
                Target::Axis { .. } => None,
            })
            .chain([plan.pareto])
            .collect();
        for r in &needed {
            if self.column(&r.column()).is_none() {
                return Err(self.missing(format!("the result {}", r.name()), r.column()));
            }
        }
        let status = self
            .column("status")
            .ok_or_else(|| self.missing("the point status".into(), "status".into()))?;
        let id = self.column("point_id");
        let top = self.column("stable_up_to_m_s");
        let result_cols = ResultKind::ALL.map(|r| self.column(&r.column()));
        self.records
            .iter()
            .enumerate()
            .map(|(k, (line, rec))| {
                let num = |c: usize| number(&self.file, *line, &self.header[c], &rec[c]);
                let axes = axis_cols
                    .iter()
                    .map(|(key, c)| Ok((key.clone(), num(*c)?.unwrap_or(f64::NAN))))
                    .collect::<Result<Vec<_>, TradeError>>()?;
                let mut results = [None; 3];
                for (slot, c) in results.iter_mut().zip(result_cols) {
                    *slot = c.map(num).transpose()?.flatten();
                }
                Ok(Row {
                    id: id.map_or_else(|| (k + 1).to_string(), |c| rec[c].trim().to_string()),
                    axes,
                    results,
                    status: rec[status].trim().to_string(),
                    above: above_flags(&rec[status]),
                    stable_up_to_m_s: top.map(num).transpose()?.flatten(),
                })
            })
            .collect()
    }
}

/// A cell as a number: empty → `None`; not a number → error naming line, column and value.
fn number(file: &str, line: usize, column: &str, cell: &str) -> Result<Option<f64>, TradeError> {
    let s = cell.trim();
    if s.is_empty() {
        return Ok(None);
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Some(v)),
        Ok(_) => Ok(None),
        Err(_) => Err(TradeError::Csv {
            file: file.to_string(),
            line,
            problem: format!("column {column} = {s:?} is not a number"),
        }),
    }
}

/// `trade.csv`: every column of the sweep, then `feasible`, `pareto`, `best` (true/false)
/// and `reason` (why infeasible; empty when feasible).
pub fn trade_csv(table: &SweepTable, verdicts: &[super::Assessment]) -> String {
    let mut out: Vec<String> = table.header.iter().map(|h| csv_field(h)).collect();
    out.extend(["feasible", "pareto", "best", "reason"].map(String::from));
    let mut text = out.join(",") + "\n";
    for ((_, rec), a) in table.records.iter().zip(verdicts) {
        let mut f: Vec<String> = rec.iter().map(|c| csv_field(c)).collect();
        f.extend([a.feasible, a.pareto, a.best].map(|b| b.to_string()));
        f.push(csv_field(&a.reason));
        text.push_str(&f.join(","));
        text.push('\n');
    }
    text
}
