//! A CSV file the library writes, read back as typed columns: how the Python package returns
//! `branch.csv`, `simulate.csv`, `sweep.csv`, `uncertainty.csv` and `geometry.csv` as arrays.
//! The CSV writers use Rust's shortest round-trip formatting, so every number read back is the
//! `f64` that was computed. Column types are declared by the caller (numbers unless named
//! otherwise), so a column has the same type whatever its cells (an empty branch still has a
//! boolean `stable` column).

use anyhow::anyhow;

use super::{compute, Failure};

/// The type of a column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// numbers; an empty cell is NaN
    F64,
    /// `true`/`false`
    Bool,
    /// `true`, `false` or empty (no value)
    OptBool,
    /// text as written
    Text,
}

/// One column of a CSV file.
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    /// [`Kind::F64`]
    F64(Vec<f64>),
    /// [`Kind::Bool`]
    Bool(Vec<bool>),
    /// [`Kind::OptBool`]
    OptBool(Vec<Option<bool>>),
    /// [`Kind::Text`]
    Text(Vec<String>),
}

/// The column types of `branch.csv` (numbers but `branch_kind` and `stable`).
pub const BRANCH: &[(&str, Kind)] = &[("branch_kind", Kind::Text), ("stable", Kind::Bool)];
/// The column types of `attractors.csv` (numbers but `source` and `kind`).
pub const ATTRACTORS: &[(&str, Kind)] = &[("source", Kind::Text), ("kind", Kind::Text)];
/// The column types of `sweep.csv` (numbers but `status` and `nonlinear_located`).
pub const SWEEP: &[(&str, Kind)] = &[("status", Kind::Text), ("nonlinear_located", Kind::OptBool)];
/// The column types of `uncertainty.csv` (numbers but `block` and `status`).
pub const UNCERTAINTY: &[(&str, Kind)] = &[("block", Kind::Text), ("status", Kind::Text)];
/// The column types of `simulate.csv` and `geometry.csv`: all numbers.
pub const NUMBERS: &[(&str, Kind)] = &[];

fn boolean(c: &str) -> Option<bool> {
    match c {
        "true" => Some(true),
        "false" => Some(false),
        _ => None,
    }
}

impl Column {
    fn read(kind: Kind, cells: &[&str]) -> Result<Column, usize> {
        // the error is the index of the first cell that does not fit the kind
        let bad = |ok: &dyn Fn(&str) -> bool| cells.iter().position(|c| !ok(c));
        match kind {
            Kind::F64 => cells
                .iter()
                .enumerate()
                .map(|(i, c)| {
                    if c.is_empty() {
                        Ok(f64::NAN)
                    } else {
                        c.parse::<f64>().map_err(|_| i)
                    }
                })
                .collect::<Result<_, _>>()
                .map(Column::F64),
            Kind::Bool => match bad(&|c| boolean(c).is_some()) {
                Some(i) => Err(i),
                None => Ok(Column::Bool(cells.iter().map(|c| c == &"true").collect())),
            },
            Kind::OptBool => match bad(&|c| c.is_empty() || boolean(c).is_some()) {
                Some(i) => Err(i),
                None => Ok(Column::OptBool(cells.iter().map(|c| boolean(c)).collect())),
            },
            Kind::Text => Ok(Column::Text(cells.iter().map(|c| c.to_string()).collect())),
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        match self {
            Column::F64(v) => v.len(),
            Column::Bool(v) => v.len(),
            Column::OptBool(v) => v.len(),
            Column::Text(v) => v.len(),
        }
    }

    /// Whether the column has no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The columns of a CSV text with a header line, in the header's order; a column is of the
/// kind `kinds` gives its name, else numbers. Lines starting with `#` are comments. Cells
/// never contain commas in the files the library writes; a row with another number of cells
/// than the header, or a cell that does not fit its column's kind, is an error naming it.
pub fn columns(csv: &str, kinds: &[(&str, Kind)]) -> Result<Vec<(String, Column)>, Failure> {
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| compute(anyhow!("CSV text has no header line")))?
        .split(',')
        .collect();
    let mut cells: Vec<Vec<&str>> = vec![Vec::new(); header.len()];
    for (k, line) in lines.enumerate() {
        let row: Vec<&str> = line.split(',').collect();
        if row.len() != header.len() {
            return Err(compute(anyhow!(
                "CSV row {} has {} cells, the header {}",
                k + 1,
                row.len(),
                header.len()
            )));
        }
        for (col, cell) in cells.iter_mut().zip(row) {
            col.push(cell);
        }
    }
    header
        .into_iter()
        .zip(cells)
        .map(|(name, c)| {
            let kind = kinds
                .iter()
                .find(|(n, _)| *n == name)
                .map_or(Kind::F64, |k| k.1);
            Column::read(kind, &c)
                .map(|col| (name.to_string(), col))
                .map_err(|i| {
                    compute(anyhow!(
                        "CSV column {name} row {}: {:?} is not of kind {kind:?}",
                        i + 1,
                        c[i]
                    ))
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_typed_and_numbers_round_trip() {
        let x = 0.1 + 0.2; // not 0.3: the shortest repr must bring back this exact f64
        let csv = format!("# comment\na,b,c,d\n{x},true,,s1\n-1e-300,false,true,2\n");
        let kinds = [("b", Kind::Bool), ("c", Kind::OptBool), ("d", Kind::Text)];
        let cols = columns(&csv, &kinds).expect("columns");
        let names: Vec<&str> = cols.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["a", "b", "c", "d"]);
        assert_eq!(cols[0].1, Column::F64(vec![x, -1e-300]));
        assert_eq!(cols[1].1, Column::Bool(vec![true, false]));
        assert_eq!(cols[2].1, Column::OptBool(vec![None, Some(true)]));
        assert_eq!(cols[3].1, Column::Text(vec!["s1".into(), "2".into()]));
    }

    #[test]
    fn kinds_hold_without_rows_and_bad_cells_fail() {
        let cols = columns("a,stable\n", BRANCH).expect("columns");
        assert_eq!(cols[1].1, Column::Bool(Vec::new()));
        let cols = columns("a,b\n1,\n,2\n", NUMBERS).expect("columns");
        match &cols[1].1 {
            Column::F64(v) => assert!(v[0].is_nan() && v[1] == 2.0),
            c => panic!("{c:?}"),
        }
        assert!(columns("a,b\n1\n", NUMBERS).is_err());
        assert!(columns("a\nx\n", NUMBERS).is_err());
        assert!(columns("stable\nyes\n", BRANCH).is_err());
        assert!(columns("", NUMBERS).is_err());
    }
}
