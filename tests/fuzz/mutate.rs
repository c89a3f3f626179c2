//! Mutations of a study's TOML: the ways a user (or a script) gets a study wrong.
//!
//! A case is a shipped study and one to three mutations. Each mutation picks its target by a
//! number taken modulo the places available (so that proptest can shrink it), and records the
//! dotted key it touched: an error message must name one of them.

use proptest::prelude::*;

/// A step of a path into a TOML document.
#[derive(Clone, Debug, PartialEq)]
pub enum Seg {
    Key(String),
    Index(usize),
}

/// The dotted key of a path, as the program's messages write it (`linear.speed_range[0]`).
pub fn dotted(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) if s.is_empty() => s.push_str(k),
            Seg::Key(k) => {
                s.push('.');
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// A value put where a study value was.
#[derive(Clone, Debug)]
pub enum Bad {
    Nan,
    Inf,
    NegInf,
    /// the value's sign flipped (numbers, and the number of a quantity string)
    Negate,
    Zero,
    /// ± 10^k, k in [-330, 330] (1e300, 1e-300, subnormals, 0 by underflow)
    Power(i32, bool),
    /// the value times 10^k, keeping its unit
    Scale(i32),
    /// the number with a unit of another dimension, or none known
    WrongUnit(usize),
    /// the number as a string without a unit
    MissingUnit,
    /// a string, a boolean, an array, a table, a date, an integer where a float was, …
    WrongType(usize),
    /// a very large integer (counts: points, nodes)
    HugeCount,
    /// a value inside the key's meaningful range (log-uniform where it spans decades), to
    /// reach the computation with extreme but accepted values; `u` in [0, 1)
    Meaningful(f64),
}

/// One mutation.
#[derive(Clone, Debug)]
pub enum Op {
    /// delete a key (a leaf), or a whole section
    Delete { pick: usize, section: bool },
    /// replace a leaf's value
    Set { pick: usize, bad: Bad },
    /// add an unknown key to a table, or an unknown section
    Unknown { pick: usize, section: bool },
    /// point a file key (geometry table, profiles) at the wrong file, or change a choice key
    /// (geometry, creep law, vehicle kind, spacing, …) to another choice
    File { pick: usize, to: usize },
}

const UNITS: &[&str] = &[
    "furlongs", "kg", "m", "mm", "N/mm", "N s/m", "GPa", "km/h", "deg", "s", "kg m^2", "N mm", "",
    "1:20",
];

const TYPES: usize = 9;

/// Files and choices a file or choice key may be set to (relative to the studies' folder).
const FILES: &[&str] = &[
    "tables/cubic-fold.csv",
    "tables/dtu-rsgeo-1o40.csv",
    "profiles/s1002.csv",
    "profiles/uic60_1in40.csv",
    "seed.toml",
    "missing.csv",
    "tables",
    "",
    "../Cargo.toml",
];
const CHOICES: &[&str] = &[
    "cone",
    "cone-on-arc",
    "table",
    "profiles",
    "kalker",
    "shen",
    "wheelset",
    "bogie",
    "car",
    "log",
    "linear",
    "1:40",
    "none",
    "nonlinear",
    "hopf",
    "bogus",
];

fn bad() -> impl Strategy<Value = Bad> {
    prop_oneof![
        1 => Just(Bad::Nan),
        1 => Just(Bad::Inf),
        1 => Just(Bad::NegInf),
        1 => Just(Bad::Negate),
        1 => Just(Bad::Zero),
        1 => (-330i32..=330, any::<bool>()).prop_map(|(k, neg)| Bad::Power(k, neg)),
        1 => prop_oneof![Just(300), Just(-300), Just(19), Just(-19), -20i32..=20].prop_map(Bad::Scale),
        1 => (0..UNITS.len()).prop_map(Bad::WrongUnit),
        1 => Just(Bad::MissingUnit),
        1 => (0..TYPES).prop_map(Bad::WrongType),
        1 => Just(Bad::HugeCount),
        4 => (0.0f64..1.0).prop_map(Bad::Meaningful),
    ]
}

/// One mutation, weighted towards bad values (most of what can go wrong).
pub fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        2 => (any::<usize>(), prop::bool::weighted(0.2))
            .prop_map(|(pick, section)| Op::Delete { pick, section }),
        8 => (any::<usize>(), bad()).prop_map(|(pick, bad)| Op::Set { pick, bad }),
        1 => (any::<usize>(), any::<bool>())
            .prop_map(|(pick, section)| Op::Unknown { pick, section }),
        2 => (any::<usize>(), any::<usize>()).prop_map(|(pick, to)| Op::File { pick, to }),
    ]
}

/// Every leaf (a value that is not a table, or an element of an array of values) and every
/// table, as paths.
fn places(t: &toml::Table) -> (Vec<Vec<Seg>>, Vec<Vec<Seg>>) {
    fn walk(
        v: &toml::Value,
        path: Vec<Seg>,
        leaves: &mut Vec<Vec<Seg>>,
        tables: &mut Vec<Vec<Seg>>,
    ) {
        match v {
            toml::Value::Table(t) => {
                tables.push(path.clone());
                for (k, x) in t {
                    let mut p = path.clone();
                    p.push(Seg::Key(k.clone()));
                    walk(x, p, leaves, tables);
                }
            }
            toml::Value::Array(a) => {
                leaves.push(path.clone());
                for (i, x) in a.iter().enumerate() {
                    let mut p = path.clone();
                    p.push(Seg::Index(i));
                    walk(x, p, leaves, tables);
                }
            }
            _ => leaves.push(path),
        }
    }
    let (mut leaves, mut tables) = (Vec::new(), Vec::new());
    walk(
        &toml::Value::Table(t.clone()),
        Vec::new(),
        &mut leaves,
        &mut tables,
    );
    (leaves, tables)
}

fn get<'a>(t: &'a toml::Table, path: &[Seg]) -> Option<&'a toml::Value> {
    let (first, rest) = path.split_first()?;
    let Seg::Key(k) = first else { return None };
    let mut cur = t.get(k)?;
    for seg in rest {
        cur = match (seg, cur) {
            (Seg::Key(k), toml::Value::Table(t)) => t.get(k)?,
            (Seg::Index(i), toml::Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

fn at<'a>(t: &'a mut toml::Table, path: &[Seg]) -> Option<&'a mut toml::Value> {
    let (first, rest) = path.split_first()?;
    let Seg::Key(k) = first else { return None };
    let mut cur = t.get_mut(k)?;
    for seg in rest {
        cur = match (seg, cur) {
            (Seg::Key(k), toml::Value::Table(t)) => t.get_mut(k)?,
            (Seg::Index(i), toml::Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

fn remove(t: &mut toml::Table, path: &[Seg]) {
    let Some((last, parent)) = path.split_last() else {
        return;
    };
    let holder = if parent.is_empty() {
        None
    } else {
        at(t, parent)
    };
    match (last, holder) {
        (Seg::Key(k), None) if parent.is_empty() => {
            t.remove(k);
        }
        (Seg::Key(k), Some(toml::Value::Table(p))) => {
            p.remove(k);
        }
        (Seg::Index(i), Some(toml::Value::Array(a))) if *i < a.len() => {
            a.remove(*i);
        }
        _ => {}
    }
}

/// The number a value holds (a float, an integer, or the number at the start of a string).
fn number(v: &toml::Value) -> Option<(f64, String)> {
    match v {
        toml::Value::Float(f) => Some((*f, String::new())),
        toml::Value::Integer(i) => Some((*i as f64, String::new())),
        toml::Value::String(s) => {
            let mut parts = s.trim().splitn(2, ' ');
            let n = parts.next()?.parse().ok()?;
            Some((n, parts.next().unwrap_or("").to_string()))
        }
        _ => None,
    }
}

/// A value inside `key`'s meaningful range at fraction `u` (log-uniform over ranges of
/// positive numbers spanning more than a decade); `None` for keys without a range.
fn meaningful(key: &str, u: f64) -> Option<f64> {
    let r = critspeed::study::plausible::range(key)?;
    let (lo, hi) = (r.meaningful.lo, r.meaningful.hi);
    let lo_log = if lo > 0.0 {
        lo
    } else {
        (hi * 1e-12).max(f64::MIN_POSITIVE)
    };
    let v = if lo_log > 0.0 && hi / lo_log > 10.0 {
        (lo_log.ln() + u * (hi / lo_log).ln()).exp()
    } else {
        lo + u * (hi - lo)
    };
    let v = v.clamp(lo, hi);
    // an open end is not inside: step off it
    Some(if r.meaningful.contains(v) {
        v
    } else {
        0.5 * (lo + hi)
    })
}

fn replaced(old: &toml::Value, bad: &Bad, key: &str) -> toml::Value {
    use toml::Value as V;
    let (n, unit) = number(old).unwrap_or((1.0, String::new()));
    let with_unit = |x: f64| {
        if unit.is_empty() {
            V::Float(x)
        } else {
            V::String(format!("{x:e} {unit}"))
        }
    };
    match bad {
        Bad::Nan => V::Float(f64::NAN),
        Bad::Inf => V::Float(f64::INFINITY),
        Bad::NegInf => V::Float(f64::NEG_INFINITY),
        Bad::Negate => match old {
            V::Integer(i) => V::Integer(i.saturating_neg()),
            _ => with_unit(-n),
        },
        Bad::Zero => match old {
            V::Integer(_) => V::Integer(0),
            _ => with_unit(0.0),
        },
        Bad::Power(k, neg) => {
            let x = 10f64.powi(*k);
            V::Float(if *neg { -x } else { x })
        }
        Bad::Scale(k) => with_unit(n * 10f64.powi(*k)),
        Bad::WrongUnit(u) => V::String(format!("{n} {}", UNITS[*u % UNITS.len()])),
        Bad::MissingUnit => V::String(format!("{n}")),
        Bad::WrongType(k) => match k % TYPES {
            0 => V::String("lots".into()),
            1 => V::Boolean(true),
            2 => V::Array(vec![V::Float(n), V::Float(n)]),
            3 => V::Table(toml::Table::new()),
            4 => "1979-05-27T07:32:00Z"
                .parse()
                .map(V::Datetime)
                .unwrap_or(V::Boolean(false)),
            5 => V::Integer(n as i64),
            6 => V::Array(Vec::new()),
            7 => V::String(String::new()),
            _ => V::Float(n + 0.5),
        },
        Bad::HugeCount => V::Integer(i64::MAX),
        Bad::Meaningful(u) => match (meaningful(key, *u), old) {
            (Some(x), V::Integer(_)) => V::Integer(x.round() as i64),
            (Some(x), _) => V::Float(x),
            (None, _) => old.clone(),
        },
    }
}

/// Keys whose value is a file, and keys whose value is a choice among words.
fn is_file_key(path: &[Seg]) -> bool {
    matches!(path.last(), Some(Seg::Key(k)) if k.ends_with("_table") || k.ends_with("_profile"))
}

/// Applies `op` to `t`; returns the dotted key it touched (`None`: nothing to touch).
pub fn apply(t: &mut toml::Table, op: &Op) -> Option<String> {
    let (leaves, tables) = places(t);
    match op {
        Op::Delete { pick, section } => {
            let from = if *section { &tables[1..] } else { &leaves[..] };
            let path = from.get(pick % from.len().max(1))?.clone();
            remove(t, &path);
            Some(dotted(&path))
        }
        Op::Set { pick, bad } => {
            let path = leaves.get(pick % leaves.len().max(1))?.clone();
            let key = dotted(&path);
            let v = at(t, &path)?;
            *v = replaced(v, bad, &key);
            Some(key)
        }
        Op::Unknown { pick, section } => {
            if *section {
                let mut s = toml::Table::new();
                s.insert("value".into(), toml::Value::Float(1.0));
                t.insert("bogus_section".into(), toml::Value::Table(s));
                return Some("bogus_section".into());
            }
            let path = tables.get(pick % tables.len().max(1))?.clone();
            let holder = if path.is_empty() {
                Some(&mut *t)
            } else {
                match at(t, &path)? {
                    toml::Value::Table(x) => Some(x),
                    _ => None,
                }
            }?;
            holder.insert("bogus_key".into(), toml::Value::Float(1.0));
            Some("bogus_key".into())
        }
        Op::File { pick, to } => {
            let strings: Vec<&Vec<Seg>> = leaves
                .iter()
                .filter(|p| matches!(get(t, p), Some(toml::Value::String(_))))
                .collect();
            let path = (*strings.get(pick % strings.len().max(1))?).clone();
            let pool = if is_file_key(&path) { FILES } else { CHOICES };
            let v = at(t, &path)?;
            *v = toml::Value::String(pool[to % pool.len()].into());
            Some(dotted(&path))
        }
    }
}

/// Whether `message` names one of the `touched` keys: the dotted key, the key without its
/// array indices, or its last name (a serde message names the field: "missing field `mass`").
pub fn names_a_key(message: &str, touched: &[String]) -> bool {
    touched.iter().any(|k| {
        let plain: String = k
            .split('[')
            .enumerate()
            .map(|(i, s)| {
                if i == 0 {
                    s
                } else {
                    s.split_once(']').map_or("", |x| x.1)
                }
            })
            .collect();
        let leaf = plain.rsplit('.').next().unwrap_or(&plain);
        // an element of an array of tables named as a whole: `sweep.axes[0]`
        let element = k.rfind(']').map(|i| &k[..=i]);
        message.contains(k.as_str())
            || message.contains(&plain)
            || message.contains(leaf)
            || element.is_some_and(|e| message.contains(e))
    })
}
