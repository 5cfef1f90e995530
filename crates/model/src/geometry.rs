//! The joint's reference geometry, derived from the config, and the checks
//! that reject geometry that cannot work.
//!
//! Frame: x along the bridge (the gap opens in +x), y across; the abutment
//! edge beam is the line x = 0, the deck edge beam the line x = G0 + u with
//! `G0 = (Nc + 1) s0`. Center beam `i = 1..Nc` lies on x = i s0. A support
//! beam is the line `y = y_k + x tan(theta_k)`; a joist pivots at (0, y_k)
//! and passes through the joist box (G0 + u, y_k + G0 tan theta_k) on the
//! deck. Bearing (i, k) sits where center beam i crosses support beam k.

use crate::config::{Config, SupportKind};
use crate::error::ModelError;

/// One support beam in the reference configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportGeometry {
    /// Guide or joist.
    pub kind: SupportKind,
    /// y of the axis at x = 0 (a joist's pivot) \[m\].
    pub y0: f64,
    /// Angle of the axis \[rad\].
    pub theta: f64,
    /// Transverse offset of the joist box from the pivot, `G0 tan theta` \[m\].
    pub box_dy: f64,
    /// Centre of mass (x, y) \[m\]: the midpoint between pivot and box for a
    /// joist, (G0/2, y0) for a guide.
    pub centre: [f64; 2],
    /// Distance from the centre of mass to the pivot along the axis \[m\].
    pub half_span: f64,
}

/// The whole reference geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// Number of center beams.
    pub center_beams: usize,
    /// Reference pitch `s0` \[m\].
    pub pitch: f64,
    /// Reference gap between the edge-beam lines, `G0 = (Nc + 1) s0` \[m\].
    pub gap: f64,
    /// Center beam width \[m\].
    pub width: f64,
    /// Half the center beam length \[m\]: the ends are at y = ±half_length.
    pub half_length: f64,
    /// x of each center beam's axis \[m\].
    pub center_x: Vec<f64>,
    /// The support beams.
    pub supports: Vec<SupportGeometry>,
    /// y of bearing (i, k) \[m\].
    pub bearing_y: Vec<Vec<f64>>,
}

impl Geometry {
    /// Derives and checks the geometry of a config.
    pub fn new(config: &Config) -> Result<Self, ModelError> {
        let j = &config.joint;
        let nc = j.center_beams;
        let s0 = j.pitch;
        let gap = (nc + 1) as f64 * s0;
        if j.center_beam.width >= s0 {
            return Err(ModelError::Geometry(format!(
                "joint.center_beam.width = {} m is not smaller than joint.pitch = {} m: the sub-gaps would be closed",
                j.center_beam.width, s0
            )));
        }
        let mut supports = Vec::with_capacity(j.support_beams.len());
        for (k, sb) in j.support_beams.iter().enumerate() {
            let key = format!("joint.support_beams[{k}]");
            if !sb.y.is_finite() || !sb.angle_deg.is_finite() {
                return Err(ModelError::Geometry(format!("{key}: y and angle_deg must be finite")));
            }
            if sb.angle_deg.abs() >= 90.0 {
                return Err(ModelError::Geometry(format!(
                    "{key}.angle_deg = {}: the angle to the bridge axis must be below 90 degrees in magnitude",
                    sb.angle_deg
                )));
            }
            if sb.kind == SupportKind::Guide && sb.angle_deg != 0.0 {
                return Err(ModelError::Geometry(format!(
                    "{key}.angle_deg = {}: a guide runs parallel to the bridge axis (angle_deg = 0)",
                    sb.angle_deg
                )));
            }
            let theta = sb.angle_deg.to_radians();
            let box_dy = gap * theta.tan();
            let (centre, half_span) = match sb.kind {
                SupportKind::Joist => ([0.5 * gap, sb.y + 0.5 * box_dy], 0.5 * gap / theta.cos()),
                SupportKind::Guide => ([0.5 * gap, sb.y], 0.5 * gap),
            };
            supports.push(SupportGeometry { kind: sb.kind, y0: sb.y, theta, box_dy, centre, half_span });
        }
        // support beams must not cross or coincide inside the gap
        for a in 0..supports.len() {
            for b in a + 1..supports.len() {
                let (sa, sb) = (&supports[a], &supports[b]);
                let (ta, tb) = (sa.theta.tan(), sb.theta.tan());
                if (ta - tb).abs() < 1e-12 {
                    if (sa.y0 - sb.y0).abs() < 1e-9 {
                        return Err(ModelError::Geometry(format!(
                            "joint.support_beams[{a}] and [{b}] lie on the same line (y = {}, angle {} deg)",
                            sa.y0,
                            sa.theta.to_degrees()
                        )));
                    }
                    continue;
                }
                let x = (sb.y0 - sa.y0) / (ta - tb);
                if (0.0..=gap).contains(&x) {
                    return Err(ModelError::Geometry(format!(
                        "joint.support_beams[{a}] and [{b}] cross inside the gap at x = {x:.4} m, y = {:.4} m",
                        sa.y0 + x * ta
                    )));
                }
            }
        }
        let center_x: Vec<f64> = (1..=nc).map(|i| i as f64 * s0).collect();
        let half = 0.5 * j.center_beam.length;
        let mut bearing_y = Vec::with_capacity(nc);
        for (i, &x) in center_x.iter().enumerate() {
            let mut row = Vec::with_capacity(supports.len());
            for (k, s) in supports.iter().enumerate() {
                let y = s.y0 + x * s.theta.tan();
                if y.abs() > half {
                    return Err(ModelError::Geometry(format!(
                        "bearing of center beam {} on joint.support_beams[{k}] at y = {y:.4} m lies outside the \
                         center beam (|y| <= joint.center_beam.length / 2 = {half} m)",
                        i + 1
                    )));
                }
                row.push(y);
            }
            bearing_y.push(row);
        }
        Ok(Self {
            center_beams: nc,
            pitch: s0,
            gap,
            width: j.center_beam.width,
            half_length: half,
            center_x,
            supports,
            bearing_y,
        })
    }

    /// Clear sub-gaps at both ends of the center beams (y = ±L/2), for
    /// center-beam axes at `x` turned by `phi` \[rad\], the deck displaced by
    /// `u` and the abutment side (an adjacent segment) by `u0` \[m\]:
    /// from the abutment's edge beam to the first beam, between beams, and
    /// from the last beam to the deck's edge beam, `[at y = -L/2, at y =
    /// +L/2]` \[m\]. A beam turned by phi has its faces at `x ∓ y sin(phi) ±
    /// (w/2) cos(phi)`; the edge beams do not turn. Turning makes one end
    /// of a sub-gap close before its middle: 1 mrad on a 15 m beam moves its
    /// ends by 7.5 mm.
    ///
    /// With `released` (an index into `x`: a fuse element's beam, gone out
    /// of the plane) its two cells are one, from its neighbours' faces: each
    /// of the two is reported as half of it.
    pub fn subgaps(
        &self,
        x: &[f64],
        phi: &[f64],
        (u, u0): (f64, f64),
        released: Option<usize>,
        out: &mut Vec<[f64; 2]>,
    ) {
        out.clear();
        let half_w = 0.5 * self.width;
        let ends = [-self.half_length, self.half_length];
        let mut push = |cell: [f64; 2], merged: bool| match merged {
            true => out.extend([cell.map(|c| 0.5 * c); 2]),
            false => out.push(cell),
        };
        // faces of the abutment's edge beam (axis x = u0)
        let mut prev = [u0 + half_w; 2];
        let mut merged = false;
        for (i, (&xi, &p)) in x.iter().zip(phi).enumerate() {
            if released == Some(i) {
                merged = true;
                continue;
            }
            let (sin, cos) = p.sin_cos();
            let back = ends.map(|y| xi - y * sin - half_w * cos);
            push([back[0] - prev[0], back[1] - prev[1]], std::mem::take(&mut merged));
            prev = ends.map(|y| xi - y * sin + half_w * cos);
        }
        let deck = self.gap + u - half_w;
        push([deck - prev[0], deck - prev[1]], merged);
    }
}
