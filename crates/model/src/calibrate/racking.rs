//! The detailed joint's racking as the link carries it
//! (`joint.link.racking_closing`, `racking_opening`; docs/link.md,
//! "Racking"): measured in each service loop and under each record of the
//! calibration suite, the link's the largest.

use super::{DynamicFit, LoopSummary};
use crate::config::LinkConfig;

/// The racking `[closing, opening]` of a detailed joint's run \[m\]: how far
/// its narrowest cell `subgaps[0]` fell behind the cells' average at the
/// deck's smallest opening, `g0 + min u / (Nc + 1)`, and its widest
/// `subgaps[1]` led the average at the largest (NaN closing where a cell
/// closed: the contact stopped it, so the lag is not seen whole; negative
/// values as 0).
pub fn racking(cells: usize, clear: f64, u: &[f64], subgaps: [f64; 2]) -> [f64; 2] {
    let n = cells as f64;
    let lo = u.iter().copied().fold(0.0f64, f64::min);
    let hi = u.iter().copied().fold(0.0f64, f64::max);
    let closing = if subgaps[0] > 0.0 { (clear + lo / n - subgaps[0]).max(0.0) } else { f64::NAN };
    [closing, (subgaps[1] - (clear + hi / n)).max(0.0)]
}

/// Sets the link's racking to the largest the detailed joint showed in its
/// service loops and under the calibration suite (a record whose cell
/// closed gives none for closing), and says where from; warns where the
/// suite's racking is well beyond the loops' (the beams' inertia racks
/// them further than the slow loops do).
pub(super) fn set_racking(
    link: &mut LinkConfig,
    loops: &[LoopSummary],
    dynamic: &[DynamicFit],
    clear: f64,
    warnings: &mut Vec<String>,
) -> String {
    let largest = |it: &mut dyn Iterator<Item = f64>| it.filter(|x| x.is_finite()).fold(0.0f64, f64::max);
    let service = [0, 1].map(|i| largest(&mut loops.iter().map(|l| l.racking[i])));
    let suite = [0, 1].map(|i| largest(&mut dynamic.iter().map(|d| d.racking[i])));
    let both = [0, 1].map(|i| service[i].max(suite[i]));
    // (a cell closed at rest is refused by the config: keep the link usable)
    let closing = both[0].min(0.9 * clear);
    if closing < both[0] {
        warnings.push(format!(
            "the narrowest cell racked by {:.1} mm, nearly the clear sub-gap of {:.1} mm: the link's racking is \
             held at {:.1} mm",
            both[0] * 1e3,
            clear * 1e3,
            closing * 1e3
        ));
    }
    link.racking_closing = Some(closing);
    link.racking_opening = Some(both[1]);
    if dynamic.is_empty() {
        "the service loops alone (slow: the beams' inertia racks them further under an earthquake; give a \
         calibration suite)"
            .to_string()
    } else {
        format!(
            "the largest of the service loops ({:.1} / {:.1} mm closing / opening) and the calibration suite \
             ({:.1} / {:.1} mm)",
            service[0] * 1e3,
            service[1] * 1e3,
            suite[0] * 1e3,
            suite[1] * 1e3
        )
    }
}
