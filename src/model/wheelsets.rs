//! Per-wheelset contact geometry (docs/model.md §11): the wheelsets of one vehicle may wear
//! differently, so each may have its own contact table while the creep law, spin, flange and
//! axle load stay the common [`Vehicle::contact`]'s. Each table is one wheelset's right wheel;
//! its left wheel is the mirror image, so $f(−x) = −f(x)$ still holds.

use super::vehicle::{AssemblyError, Vehicle};
use crate::contact::table::ContactTable;
use crate::system::scalar::Scalar;

impl Vehicle {
    /// The same vehicle with wheelset `j`'s contact geometry `tables[j]` (front to rear;
    /// `None`: the common `contact.table`). More tables than wheelsets is an error.
    pub fn with_wheelset_tables(
        mut self,
        tables: Vec<Option<ContactTable>>,
    ) -> Result<Self, AssemblyError> {
        let wheelsets = self.wheelset_dofs().len();
        if tables.len() > wheelsets {
            return Err(AssemblyError::WheelsetTables {
                given: tables.len(),
                wheelsets,
            });
        }
        self.wheelset_tables = tables;
        Ok(self)
    }

    /// The per-wheelset tables as given to [`Self::with_wheelset_tables`] (empty: every
    /// wheelset has the common geometry).
    pub fn wheelset_tables(&self) -> &[Option<ContactTable>] {
        &self.wheelset_tables
    }

    /// The contact geometry of wheelset `j` (0 = leading): its own, else the common one.
    #[inline]
    pub fn wheelset_table(&self, j: usize) -> &ContactTable {
        match self.wheelset_tables.get(j) {
            Some(Some(t)) => t,
            _ => &self.contact.table,
        }
    }

    /// The generalised contact forces $(Q_y, Q_ψ)$ of wheelset `j` at its state
    /// $(y, ψ, \dot y, \dot ψ)$ ([`super::Wheelset::contact_forces_on`] with its table).
    #[inline]
    pub fn wheelset_forces<T: Scalar>(&self, j: usize, x: &[T; 4], v: f64) -> (T, T) {
        self.contact.contact_forces_on(self.wheelset_table(j), x, v)
    }

    /// Each wheelset's effective conicity at the centre (–), front to rear.
    pub fn wheelset_conicities(&self) -> Vec<f64> {
        (0..self.wheelset_dofs().len())
            .map(|j| super::centre_conicity(self.wheelset_table(j)))
            .collect()
    }

    /// Whether some wheelset's contact geometry differs from the leading one's centre
    /// conicity (then the single [`Self::centre_conicity`] is the leading wheelset's only).
    pub fn conicities_differ(&self) -> bool {
        let c = self.wheelset_conicities();
        let Some(&first) = c.first() else {
            return false;
        };
        c.iter().any(|&l| (l - first).abs() > 1e-12 * first.abs())
    }

    /// The wheelsets' centre conicities grouped by runs of equal value, e.g.
    /// `wheelsets 1–2: λ 0.1800, 3–4: λ 0.3100`.
    pub fn conicity_summary(&self) -> String {
        let c = self.wheelset_conicities();
        let mut groups: Vec<(usize, usize, f64)> = Vec::new();
        for (j, &l) in c.iter().enumerate() {
            match groups.last_mut() {
                Some(g) if (g.2 - l).abs() <= 1e-12 * l.abs() => g.1 = j + 1,
                _ => groups.push((j + 1, j + 1, l)),
            }
        }
        let parts: Vec<String> = groups
            .iter()
            .map(|&(a, b, l)| {
                if a == b {
                    format!("{a}: λ {l:.4}")
                } else {
                    format!("{a}–{b}: λ {l:.4}")
                }
            })
            .collect();
        format!("wheelsets {}", parts.join(", "))
    }
}
