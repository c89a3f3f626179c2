//! The one V_NL of two analyses: the continuation with branch switching
//! ([`crate::bifurcation`]) and the search for attractors by simulation ([`crate::attractors`]).
//! Each gives its candidates ([`crate::bifurcation::vnl`] for the continuation's); this
//! module, which depends on both, takes the lowest and says in words where they disagree.
//! The commands (`critspeed attractors`), the API and the sweep's fast V_NL call it.

use crate::attractors::AttractorReport;
use crate::bifurcation::vnl::{continuation_candidates, lowest, VnlCandidate, VnlMethod};
use crate::bifurcation::BifurcationReport;

/// The search's candidate: its lowest hunting attractor.
pub fn search_candidate(r: &AttractorReport) -> Option<VnlCandidate> {
    let (v, bracket, id) = r.nonlinear_critical_speed?;
    let a = r.attractors.iter().find(|a| a.id == id)?;
    Some(VnlCandidate {
        speed_m_s: v,
        located: bracket.is_some() && !a.open_below,
        method: VnlMethod::AttractorSearch,
        what: format!("{} (attractor {id})", a.kind.name()),
        branch: a.branch.map(|b| b.0),
        bracket_m_s: bracket,
        bracket_open: a.open_below,
    })
}

/// Joins the search's result to the continuation's report: V_NL becomes the lowest of both,
/// the sources list each method's lowest candidate, and a disagreement larger than the search's
/// bracket is said in words in the report's notes.
pub fn combine(b: &mut BifurcationReport, search: &AttractorReport) {
    let cont = lowest(&continuation_candidates(b)).cloned();
    let found = search_candidate(search);
    let mut sources: Vec<VnlCandidate> = cont.iter().chain(found.iter()).cloned().collect();
    sources.sort_by(|x, y| x.speed_m_s.total_cmp(&y.speed_m_s));
    if let Some(best) = sources.first() {
        b.nonlinear_critical_speed = Some((best.speed_m_s, best.located));
    }
    let width = search.options.bracket;
    let text = match (&cont, &found) {
        (Some(c), Some(s)) if (c.speed_m_s - s.speed_m_s).abs() > width => Some(format!(
            "the continuation and the attractor search disagree: the continuation's lowest stable motion is {:.4} m/s ({}), the search's {:.4} m/s ({}{}), {:.3} m/s apart, more than the search's bracket of {width} m/s. {}",
            c.speed_m_s,
            c.what,
            s.speed_m_s,
            s.what,
            s.bracket_words(4),
            (c.speed_m_s - s.speed_m_s).abs(),
            if s.speed_m_s < c.speed_m_s {
                "The search found hunting below every stable cycle the continuation reached: an attractor that no followed branch leads to (or one on a branch not followed: see max_branches), a torus or chaos. V_NL is the search's."
            } else {
                "The continuation has stable cycles below where every attractor the search followed died: their basins missed the search's initial states, or the descents left them at a jump. V_NL is the continuation's."
            }
        )),
        (Some(c), None) => Some(format!(
            "the attractor search found no hunting attractor, while the continuation has stable cycles down to {:.4} m/s ({}): their basins missed the search's initial states",
            c.speed_m_s, c.what
        )),
        (None, Some(s)) => Some(format!(
            "the continuation found no stable cycle, while the search found hunting down to {:.4} m/s ({})",
            s.speed_m_s, s.what
        )),
        _ => None,
    };
    if let Some(t) = text {
        b.notes.push(t);
    } else if let (Some(c), Some(s)) = (&cont, &found) {
        b.notes.push(format!(
            "the continuation ({:.4} m/s, {}) and the attractor search ({:.4} m/s, {}) agree within the search's bracket of {width} m/s",
            c.speed_m_s, c.what, s.speed_m_s, s.what
        ));
    }
    b.nonlinear_sources = sources;
}
