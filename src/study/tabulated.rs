//! `geometry = "table"`: resolve and read the geometry table of a study (docs/model.md §3, method 3).

use std::path::Path;
use std::sync::Arc;

use super::{rule, schema::ContactSection, StudyError};
use crate::contact::geometry::Geometry;
use crate::contact::tabulated::TabulatedGeometry;
use crate::model::WheelsetParams;

/// The tabulated geometry of a `[contact]` section; the file path is relative to `folder`.
pub(super) fn geometry(
    c: &ContactSection,
    w: &WheelsetParams,
    folder: Option<&Path>,
) -> Result<Geometry, StudyError> {
    for (key, given) in [
        ("contact.conicity", c.conicity.is_some()),
        ("contact.crown_offset", c.crown_offset.is_some()),
    ] {
        if given {
            return Err(rule(
                key,
                "given",
                "does not apply to geometry \"table\" (the table gives the geometry)",
            ));
        }
    }
    let file = c
        .geometry_table
        .as_deref()
        .ok_or_else(|| StudyError::Missing {
            key: "contact.geometry_table".into(),
            why: "geometry \"table\" needs the CSV file (relative to the study file)".into(),
        })?;
    let path = match folder {
        Some(dir) => dir.join(file),
        None => Path::new(file).to_path_buf(),
    };
    let table = TabulatedGeometry::read(&path, w.rolling_radius).map_err(StudyError::Table)?;
    Ok(Geometry::Table(Arc::new(table)))
}
