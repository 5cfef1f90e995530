//! The calibrated link written for other programs: OpenSees (Tcl and
//! openseespy), SAP2000/CSiBridge (link properties as a table) and
//! quakejoint's own TOML. Every file states its units (N, m, kg, s).
//!
//! The same element everywhere: from the deck node a spring `k` to a node
//! carrying the joint's moving mass `m`, which slides on the abutment
//! against `F` (a rigid-plastic slider: OpenSees' `ElasticPP` with a
//! stiffness [`STICK_FACTOR`] times `k`), and between the abutment and the
//! deck a gap that closes after `g` with stiffness `k_c` (`ElasticPPGap`).

use super::Calibration;
use crate::config::Config;

/// A joint's fuse box (`[joint.fuse]`, docs/model.md "Seismic fuse") as
/// the exports carry it: behind the gap, between the abutment and a node
/// for the edge beam, a weld that breaks, the freed beam's friction, its
/// seat and its stop in parallel, and the ramp's lift as a constant load
/// on that node (docs/link.md, "With a fuse").
#[derive(Debug, Clone, PartialEq)]
pub struct FuseExport {
    /// The closing force through the closed joint at which it breaks \[N\].
    pub break_force: f64,
    /// The freed edge beam's travel to the stop \[m\].
    pub stroke: f64,
    /// The edge beam's mass \[kg\].
    pub mass: f64,
    /// The ramp's constant push on the freed beam back toward its seat \[N\].
    pub lift: f64,
    /// The freed beam's friction \[N\].
    pub resistance: f64,
    /// The seat's and the stop's stiffness: one contact of the joint's law
    /// as a secant at the closed joint's secant force
    /// ([`crate::link::stop_stiffness`]) \[N/m\].
    pub stop_stiffness: f64,
    /// The weld's stiffness, and the friction's while it sticks (rigid
    /// next to the closed joint, [`STICK_FACTOR`] times its `k_c`) \[N/m\].
    pub weld_stiffness: f64,
    /// The weld's compression at which it breaks \[m\]: where the weld and
    /// the sticking friction (both `weld_stiffness`, the friction at most
    /// `resistance`) hold the break force less the lift.
    pub break_strain: f64,
}

impl FuseExport {
    /// The fuse box of `config`'s joint (none without one), its seat and
    /// stop, and its weld rigid, next to the closed joint's
    /// `gap_stiffness` \[N/m\]; warns where the lift alone would break the
    /// exported weld.
    pub(super) fn of(config: &Config, gap_stiffness: f64, warnings: &mut Vec<String>) -> Option<Self> {
        let f = config.joint.fuse.as_ref()?;
        let (Some(stroke), Some((mass, [lift, resistance]))) = (f.stroke, crate::fuse::box_forces(&config.joint))
        else {
            return None;
        };
        let stop_stiffness = crate::link::stop_stiffness(&config.joint, gap_stiffness);
        let weld_stiffness = STICK_FACTOR * gap_stiffness;
        let mut held = f.break_force - lift;
        if held <= 0.0 {
            warnings.push(format!(
                "the fuse's ramp pushes its beam back with {lift:.3e} N, at least its break force: the exports' weld \
                 holds the break force without the lift"
            ));
            held = f.break_force;
        }
        let break_strain =
            if held >= 2.0 * resistance { (held - resistance) / weld_stiffness } else { held / (2.0 * weld_stiffness) };
        Some(Self {
            break_force: f.break_force,
            stroke,
            mass,
            lift,
            resistance,
            stop_stiffness,
            weld_stiffness,
            break_strain,
        })
    }
}

/// The slider's stick stiffness in the exports, relative to the spring's
/// [-]: rigid next to it (0.1 % of the stuck joint's deflection).
pub const STICK_FACTOR: f64 = 1000.0;

/// How `k_c` was taken: the Hertz contacts' secant at which force, from
/// where, and how to iterate it (nothing for linear contacts).
fn secant(c: &Calibration) -> String {
    match c.link.gap_hertz {
        Some(_) => format!(
            " (the closed cells' Hertz law as a secant at {:.3e} N, {}: where your model's closed joint meets \
             another force, rerun `quakejoint calibrate --contact-force` with it until the two agree; docs/link.md)",
            c.secant_force, c.secant_from
        ),
        None => String::new(),
    }
}

/// A joint's fuse element (`[joint.fuse]`, `kind = "element"`,
/// docs/model.md "Seismic fuse") as the exports carry it: the gap's
/// material fails for good (OpenSees' `MinMax`) where the closed joint's
/// force reaches the release force, and a second gap, the joint less one
/// cell, closes the beam's width later (docs/link.md, "With a fuse").
#[derive(Debug, Clone, PartialEq)]
pub struct ElementExport {
    /// The closed joint's force at which its beam leaves \[N\].
    pub break_force: f64,
    /// Which center beam leaves, 1 to `Nc`.
    pub beam: usize,
    /// The closing at which the gap's material fails, `g + F_r / k_c` \[m\].
    pub release_closing: f64,
    /// The second gap's closing movement, `g + w` \[m\].
    pub gap_after: f64,
    /// The second gap's stiffness, one cell fewer in series, `k_c (Nc +
    /// 1) / Nc` \[N/m\].
    pub stiffness_after: f64,
}

impl ElementExport {
    /// The fuse element of `config`'s joint (none without one), for a link
    /// of gap `gap` \[m\] and closed-joint stiffness `gap_stiffness`
    /// \[N/m\]; warns where the second gap would close before the first
    /// lets go (the exports then hold the joint stiffer before the
    /// release than quakejoint does).
    pub(super) fn of(config: &Config, (gap, gap_stiffness): (f64, f64), warnings: &mut Vec<String>) -> Option<Self> {
        let f = config.joint.fuse.as_ref().filter(|f| f.kind == crate::config::FuseKind::Element)?;
        let (w, cells) = (config.joint.center_beam.width, config.joint.cells() as f64);
        let squeeze = f.break_force / gap_stiffness;
        if squeeze >= w {
            warnings.push(format!(
                "the fuse element's release force closes the exports' linear gap by {squeeze:.3e} m, beyond the \
                 beam's width {w:.3e} m: their second gap closes before the first lets go"
            ));
        }
        Some(Self {
            break_force: f.break_force,
            beam: f.beam?,
            release_closing: gap + squeeze,
            gap_after: gap + w,
            stiffness_after: gap_stiffness * cells / (cells - 1.0),
        })
    }
}

fn header(c: &Calibration, comment: &str, source: &str) -> String {
    let l = &c.link;
    [
        format!("quakejoint link element, calibrated from {source}"),
        "units: N, m, kg, s".to_string(),
        format!("spring (stuck joint)      k   = {:.6e} N/m", l.stiffness),
        format!("slider (friction)         F   = {:.6e} N", l.friction),
        format!("moving mass               m   = {:.6e} kg", l.mass),
        format!("damper with the spring    c   = {:.6e} N s/m", l.damping.unwrap_or(0.0)),
        format!("closing movement (gap)    g   = {:.6e} m  ({} cells)", c.gap, c.cells),
        format!("closed-joint stiffness    k_c = {:.6e} N/m{}", l.gap_stiffness, secant(c)),
        format!(
            "first cell closes at          = {:.6e} m  (the narrowest cell, racked {:.1} mm behind the average: \
             the beams strike there; the element's force waits for g)",
            c.first_closure(),
            l.racking()[0] * 1e3
        ),
        format!(
            "opening capacity              = {:.6e} m  (the widest cell, racked {:.1} mm ahead of the average, at \
             joint.capacity.max_subgap)",
            c.capacity,
            l.racking()[1] * 1e3
        ),
        format!("racking from {}", c.racking_from),
        "the opening u is the deck's displacement away from the abutment; the element acts along it".to_string(),
    ]
    .into_iter()
    .chain(c.fuse.iter().flat_map(|f| {
        [
            format!(
                "fuse box behind the gap:  breaks at {:.6e} N, then slides {:.6e} m to its stop",
                f.break_force, f.stroke
            ),
            format!(
                "  edge beam {:.6e} kg, friction {:.6e} N, lift back to its seat {:.6e} N (a constant load)",
                f.mass, f.resistance, f.lift
            ),
            format!(
                "  seat and stop {:.6e} N/m (the joint's contact law as a secant at {:.3e} N); weld {:.6e} N/m, \
                 breaks at {:.6e} m",
                f.stop_stiffness, c.secant_force, f.weld_stiffness, f.break_strain
            ),
        ]
    }))
    .chain(c.fuse_element.iter().map(|e| {
        format!(
            "fuse element: beam {} leaves the plane at {:.6e} N (the gap closed by {:.6e} m); the gap then closes \
             after {:.6e} m with {:.6e} N/m (one cell fewer)",
            e.beam, e.break_force, e.release_closing, e.gap_after, e.stiffness_after
        )
    }))
    .map(|line| format!("{comment} {line}\n"))
    .collect()
}

/// quakejoint's own: the `[joint]` keys that make the joint its link.
pub fn toml(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    format!(
        "{}# In your config's [joint] table set model = \"link\" and add this table after it (for a joint\n\
         # of [[joints]], its [joints.joint] gets model = \"link\" and [joints.joint.link]); the\n\
         # [joint] table keeps its geometry: the gap and the capacity follow from it.\n\
         [joint.link]\nstiffness = {:e}      # [N/m]\nfriction = {:e}       # [N]\n\
         mass = {:e}           # [kg]\ndamping = {:e}        # [N s/m]\ngap_stiffness = {:e}  # [N/m]\n{}\
         racking_closing = {:e}  # [m] the narrowest cell behind the average\n\
         racking_opening = {:e}  # [m] the widest cell ahead of it\n",
        header(c, "#", source),
        l.stiffness,
        l.friction,
        l.mass,
        l.damping.unwrap_or(0.0),
        l.gap_stiffness,
        l.gap_hertz
            .map_or(String::new(), |k| format!("gap_hertz = {k:e}      # [N/m^1.5] (quakejoint's closed joint)\n")),
        l.racking()[0],
        l.racking()[1],
    )
}

/// The fuse box's part of the Tcl procedure (nothing without one).
fn fuse_tcl(c: &Calibration) -> String {
    let Some(f) = &c.fuse else { return String::new() };
    format!(
        "\x20   # the fuse box behind the gap: weld (MinMax, breaks), friction, seat, stop\n\
         \x20   remove sp $fuseNode 1\n\
         \x20   set kw {kw:e}\n\
         \x20   set ks {ks:e}\n\
         \x20   uniaxialMaterial Elastic [expr {{$firstTag + 5}}] $kw\n\
         \x20   uniaxialMaterial MinMax [expr {{$firstTag + 6}}] [expr {{$firstTag + 5}}] -min {eb:e}\n\
         \x20   uniaxialMaterial ElasticPP [expr {{$firstTag + 7}}] $kw [expr {{{r:e} / $kw}}]\n\
         \x20   uniaxialMaterial ElasticPPGap [expr {{$firstTag + 8}}] $ks 1.0e20 0.0\n\
         \x20   uniaxialMaterial ElasticPPGap [expr {{$firstTag + 9}}] $ks -1.0e20 {stroke:e}\n\
         \x20   if {{$side == 1}} {{ set ends [list $abutNode $fuseNode] }} else {{ set ends [list $fuseNode $abutNode] }}\n\
         \x20   for {{set i 0}} {{$i < 4}} {{incr i}} {{\n\
         \x20       if {{$i == 1 && {r:e} <= 0.0}} {{ continue }}\n\
         \x20       element zeroLength [expr {{$firstTag + 3 + $i}}] {{*}}$ends -mat [expr {{$firstTag + 6 + $i}}] -dir 1\n\
         \x20   }}\n\
         \x20   if {{{lift:e} != 0.0}} {{\n\
         \x20       set load [list [expr {{$side * {lift:e}}}]]\n\
         \x20       for {{set i 1}} {{$i < [llength [nodeDisp $deckNode]]}} {{incr i}} {{ lappend load 0.0 }}\n\
         \x20       timeSeries Constant $firstTag\n\
         \x20       pattern Plain $firstTag $firstTag {{ load $fuseNode {{*}}$load }}\n\
         \x20   }}\n",
        kw = f.weld_stiffness,
        ks = f.stop_stiffness,
        eb = -f.break_strain,
        r = f.resistance,
        stroke = -f.stroke,
        lift = f.lift,
    )
}

/// OpenSees Tcl: a procedure adding the link between two existing nodes,
/// and one creating its mass nodes ahead of an eigen analysis.
pub fn opensees_tcl(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    let fuse_mass = c.fuse.as_ref().map_or(0.0, |f| f.mass);
    format!(
        "{}#\n# quakejointLink abutNode deckNode newNode firstTag ?side? ?fuseNode?\n\
         #   abutNode, deckNode: existing nodes at the same place (never swap them);\n\
         #   side: +1 (default) where the deck lies toward +X (global X) of the joint, the\n\
         #   bridge's first end; -1 where it lies toward -X, the far end: the chain stays\n\
         #   abutment - slider - mass - spring - deck and the gap closes as the deck moves\n\
         #   toward the abutment; newNode: the moving mass's node tag; firstTag: the first\n\
         #   of 10 free material tags (7 element tags; with a fuse on a ramp a time series and\n\
         #   a load pattern). With a fuse box (hasFuse 1) the gap closes on the edge beam's node\n\
         #   fuseNode (newNode + 1 by default), held on the abutment by a weld that breaks\n\
         #   (MinMax), its friction, seat and stop, and pushed back by the ramp's lift.\n\
         #   2D or 3D: the new nodes take the deck node's coordinates and DOFs, their mass\n\
         #   and freedom along the first (global X).\n\
         # With modalDamping: call quakejointLinkNode deckNode newNode before the eigen command\n\
         #   (the mass nodes, held along X there) and quakejointLink after modalDamping (it frees\n\
         #   them): a node with mass added after modalDamping makes OpenSees 3.7.1 end\n\
         #   without an error, and a link present at the eigen analysis has its modes damped too.\n\
         set quakejointLinkHasFuse {has_fuse}\n\
         proc quakejointMassNode {{deckNode node mass}} {{\n\
         \x20   set ndf [llength [nodeDisp $deckNode]]\n\
         \x20   set masses [list -mass $mass]\n\
         \x20   set fixed [list]\n\
         \x20   for {{set i 1}} {{$i < $ndf}} {{incr i}} {{ lappend masses 0.0 }}\n\
         \x20   for {{set i 0}} {{$i < $ndf}} {{incr i}} {{ lappend fixed 1 }}\n\
         \x20   node $node {{*}}[nodeCoord $deckNode] {{*}}$masses\n\
         \x20   fix $node {{*}}$fixed\n\
         }}\n\
         proc quakejointLinkNode {{deckNode newNode {{fuseNode \"\"}}}} {{\n\
         \x20   global quakejointLinkHasFuse\n\
         \x20   quakejointMassNode $deckNode $newNode {m:e}\n\
         \x20   if {{$quakejointLinkHasFuse}} {{\n\
         \x20       if {{$fuseNode eq \"\"}} {{ set fuseNode [expr {{$newNode + 1}}] }}\n\
         \x20       quakejointMassNode $deckNode $fuseNode {fuse_mass:e}\n\
         \x20   }}\n\
         }}\n\
         proc quakejointLink {{abutNode deckNode newNode firstTag {{side 1}} {{fuseNode \"\"}}}} {{\n\
         \x20   global quakejointLinkHasFuse\n\
         \x20   if {{$side != 1 && $side != -1}} {{ error \"quakejointLink: side must be 1 or -1, not $side\" }}\n\
         \x20   if {{$fuseNode eq \"\"}} {{ set fuseNode [expr {{$newNode + 1}}] }}\n\
         \x20   if {{[lsearch -exact [getNodeTags] $newNode] < 0}} {{\n\
         \x20       quakejointLinkNode $deckNode $newNode $fuseNode\n\
         \x20   }}\n\
         \x20   remove sp $newNode 1\n\
         \x20   set k {k:e}\n\
         \x20   set F {f:e}\n\
         \x20   set kStick [expr {{{stick} * $k}}]\n\
         \x20   uniaxialMaterial Elastic [expr {{$firstTag + 3}}] $k\n\
         \x20   uniaxialMaterial Viscous [expr {{$firstTag + 4}}] {c:e} 1.0\n\
         \x20   uniaxialMaterial Parallel $firstTag [expr {{$firstTag + 3}}] [expr {{$firstTag + 4}}]\n\
         \x20   uniaxialMaterial ElasticPP [expr {{$firstTag + 1}}] $kStick [expr {{$F / $kStick}}]\n\
         \x20   uniaxialMaterial ElasticPPGap [expr {{$firstTag + 2}}] {kc:e} -1.0e20 {gap:e}\n\
         {element_materials}\
         \x20   element zeroLength $firstTag $newNode $deckNode -mat $firstTag -dir 1\n\
         \x20   element zeroLength [expr {{$firstTag + 1}}] $abutNode $newNode -mat [expr {{$firstTag + 1}}] -dir 1\n\
         \x20   if {{$quakejointLinkHasFuse}} {{ set base $fuseNode }} else {{ set base $abutNode }}\n\
         \x20   if {{$side == 1}} {{ set gapEnds [list $base $deckNode] }} else {{ set gapEnds [list $deckNode $base] }}\n\
         \x20   element zeroLength [expr {{$firstTag + 2}}] {{*}}$gapEnds -mat $gapMat -dir 1\n\
         {element_gap}\
         {fuse}\
         }}\n",
        header(c, "#", source),
        has_fuse = u8::from(c.fuse.is_some()),
        m = l.mass,
        k = l.stiffness,
        f = l.friction,
        stick = STICK_FACTOR,
        kc = l.gap_stiffness,
        gap = -c.gap,
        c = l.damping.unwrap_or(0.0),
        fuse = fuse_tcl(c),
        element_materials = match &c.fuse_element {
            None => "\x20   set gapMat [expr {$firstTag + 2}]\n".to_string(),
            Some(e) => format!(
                "\x20   # the fuse element: the gap fails for good at its release (MinMax), a second gap closes\n\
                 \x20   # the beam's width later\n\
                 \x20   uniaxialMaterial MinMax [expr {{$firstTag + 6}}] [expr {{$firstTag + 2}}] -min {:e}\n\
                 \x20   uniaxialMaterial ElasticPPGap [expr {{$firstTag + 5}}] {:e} -1.0e20 {:e}\n\
                 \x20   set gapMat [expr {{$firstTag + 6}}]\n",
                -e.release_closing, e.stiffness_after, -e.gap_after
            ),
        },
        element_gap = match c.fuse_element {
            None => "",
            Some(_) => "\x20   element zeroLength [expr {$firstTag + 3}] {*}$gapEnds -mat [expr {$firstTag + 5}] -dir 1\n",
        },
    )
}

/// The fuse's constants for openseespy (`FUSE = None` without one).
fn fuse_py(c: &Calibration) -> String {
    match &c.fuse {
        None => "FUSE = None  # the joint has no fuse box\n".to_string(),
        Some(f) => format!(
            "FUSE = {{  # the fuse box behind the gap (docs/link.md, \"With a fuse\")\n\
             \x20   \"break_force\": {:e},  # [N] the closing force that breaks it\n\
             \x20   \"stroke\": {:e},  # [m] the freed edge beam's travel to its stop\n\
             \x20   \"mass\": {:e},  # [kg] the edge beam\n\
             \x20   \"friction\": {:e},  # [N] the freed beam's friction\n\
             \x20   \"lift\": {:e},  # [N] the ramp's push back toward the seat\n\
             \x20   \"stop_stiffness\": {:e},  # [N/m] seat and stop\n\
             \x20   \"weld_stiffness\": {:e},  # [N/m] the weld, and the friction while it sticks\n\
             \x20   \"break_strain\": {:e},  # [m] the weld's compression at the break\n\
             }}\n",
            f.break_force, f.stroke, f.mass, f.resistance, f.lift, f.stop_stiffness, f.weld_stiffness, f.break_strain
        ),
    }
}

/// openseespy: a function adding the link between two existing nodes.
pub fn opensees_py(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    format!(
        "{}\"\"\"The quakejoint link for openseespy (units N, m, kg, s).\"\"\"\n\n\
         STIFFNESS = {k:e}  # [N/m] spring (stuck joint)\n\
         FRICTION = {f:e}  # [N] slider\n\
         MASS = {m:e}  # [kg] moving mass\n\
         DAMPING = {c:e}  # [N s/m] damper with the spring\n\
         GAP = {gap:e}  # [m] closing movement until every cell is closed\n\
         GAP_STIFFNESS = {kc:e}  # [N/m] closed joint\n\
         STICK_FACTOR = {stick}  # the slider's stick stiffness over STIFFNESS\n\
         {fuse}\
         {element}\n\n\
         def _mass_node(ops, deck_node, node, mass):\n\
         \x20   ndf = len(ops.nodeDisp(deck_node))\n\
         \x20   ops.node(node, *ops.nodeCoord(deck_node), \"-mass\", mass, *([0.0] * (ndf - 1)))\n\
         \x20   ops.fix(node, *([1] * ndf))\n\n\n\
         def add_link_node(ops, deck_node, new_node, fuse_node=None):\n\
         \x20   \"\"\"The link's mass node at the deck node, held along X until add_link frees it\n\
         \x20   (and, with a FUSE, the edge beam's node fuse_node, new_node + 1 by default).\n\
         \x20   With modalDamping, call it before the eigen analysis and add_link after\n\
         \x20   modalDamping: a node with mass added after modalDamping makes OpenSees 3.7.1 end\n\
         \x20   the process without an error, and a link present at the eigen analysis has its\n\
         \x20   modes damped too (docs/link.md).\"\"\"\n\
         \x20   _mass_node(ops, deck_node, new_node, MASS)\n\
         \x20   if FUSE is not None:\n\
         \x20       _mass_node(ops, deck_node, new_node + 1 if fuse_node is None else fuse_node, FUSE[\"mass\"])\n\n\n\
         def add_link(ops, abut_node, deck_node, new_node, first_tag, side=1, fuse_node=None):\n\
         \x20   \"\"\"Adds the link between two existing nodes at the same place (never swap\n\
         \x20   them). side: +1 where the deck lies toward +X (global X) of the joint, the\n\
         \x20   bridge's first end; -1 where it lies toward -X, the far end: the chain stays\n\
         \x20   abutment - slider - mass - spring - deck and the gap closes as the deck moves\n\
         \x20   toward the abutment. new_node: the moving mass's node tag (made here unless\n\
         \x20   add_link_node made it); first_tag: the first of 10 free material tags (and of 7\n\
         \x20   element tags, and with a FUSE on a ramp of a time series and a load pattern).\n\
         \x20   With a FUSE the gap closes on the edge beam's node fuse_node (new_node + 1 by\n\
         \x20   default), held on the abutment by a weld that breaks (MinMax), its friction\n\
         \x20   (ElasticPP), its seat and its stop (ElasticPPGap), and pushed back by the lift.\n\
         \x20   2D or 3D: the new nodes take the deck node's coordinates and DOFs, their mass\n\
         \x20   and freedom along the first (global X).\"\"\"\n\
         \x20   if side not in (1, -1):\n\
         \x20       raise ValueError(f\"add_link: side must be 1 or -1, not {{side!r}}\")\n\
         \x20   if FUSE is not None and fuse_node is None:\n\
         \x20       fuse_node = new_node + 1\n\
         \x20   if new_node not in ops.getNodeTags():\n\
         \x20       add_link_node(ops, deck_node, new_node, fuse_node)\n\
         \x20   ops.remove(\"sp\", new_node, 1)\n\
         \x20   k_stick = STICK_FACTOR * STIFFNESS\n\
         \x20   ops.uniaxialMaterial(\"Elastic\", first_tag + 3, STIFFNESS)\n\
         \x20   ops.uniaxialMaterial(\"Viscous\", first_tag + 4, DAMPING, 1.0)\n\
         \x20   ops.uniaxialMaterial(\"Parallel\", first_tag, first_tag + 3, first_tag + 4)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPP\", first_tag + 1, k_stick, FRICTION / k_stick)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPPGap\", first_tag + 2, GAP_STIFFNESS, -1.0e20, -GAP)\n\
         \x20   gap_mat = first_tag + 2\n\
         \x20   if ELEMENT is not None:\n\
         \x20       # the fuse element: the gap fails for good at its release (MinMax), a second gap\n\
         \x20       # closes the beam's width later\n\
         \x20       ops.uniaxialMaterial(\"MinMax\", first_tag + 6, first_tag + 2, \"-min\", -ELEMENT[\"release_closing\"])\n\
         \x20       ops.uniaxialMaterial(\"ElasticPPGap\", first_tag + 5, ELEMENT[\"stiffness_after\"], -1.0e20, -ELEMENT[\"gap_after\"])\n\
         \x20       gap_mat = first_tag + 6\n\
         \x20   ops.element(\"zeroLength\", first_tag, new_node, deck_node, \"-mat\", first_tag, \"-dir\", 1)\n\
         \x20   ops.element(\"zeroLength\", first_tag + 1, abut_node, new_node, \"-mat\", first_tag + 1, \"-dir\", 1)\n\
         \x20   # (each element's deformation is the opening's sign: it closes toward the abutment)\n\
         \x20   base = abut_node if FUSE is None else fuse_node\n\
         \x20   gap_nodes = (base, deck_node) if side == 1 else (deck_node, base)\n\
         \x20   ops.element(\"zeroLength\", first_tag + 2, *gap_nodes, \"-mat\", gap_mat, \"-dir\", 1)\n\
         \x20   if ELEMENT is not None:\n\
         \x20       ops.element(\"zeroLength\", first_tag + 3, *gap_nodes, \"-mat\", first_tag + 5, \"-dir\", 1)\n\
         \x20   if FUSE is None:\n\
         \x20       return\n\
         \x20   ops.remove(\"sp\", fuse_node, 1)\n\
         \x20   kw, ks = FUSE[\"weld_stiffness\"], FUSE[\"stop_stiffness\"]\n\
         \x20   ops.uniaxialMaterial(\"Elastic\", first_tag + 5, kw)\n\
         \x20   ops.uniaxialMaterial(\"MinMax\", first_tag + 6, first_tag + 5, \"-min\", -FUSE[\"break_strain\"])\n\
         \x20   ops.uniaxialMaterial(\"ElasticPP\", first_tag + 7, kw, FUSE[\"friction\"] / kw)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPPGap\", first_tag + 8, ks, 1.0e20, 0.0)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPPGap\", first_tag + 9, ks, -1.0e20, -FUSE[\"stroke\"])\n\
         \x20   fuse_nodes = (abut_node, fuse_node) if side == 1 else (fuse_node, abut_node)\n\
         \x20   # weld, friction, seat, stop\n\
         \x20   for i in range(4):\n\
         \x20       if i == 1 and FUSE[\"friction\"] <= 0.0:\n\
         \x20           continue\n\
         \x20       ops.element(\"zeroLength\", first_tag + 3 + i, *fuse_nodes, \"-mat\", first_tag + 6 + i, \"-dir\", 1)\n\
         \x20   if FUSE[\"lift\"] != 0.0:\n\
         \x20       ndf = len(ops.nodeDisp(deck_node))\n\
         \x20       ops.timeSeries(\"Constant\", first_tag)\n\
         \x20       ops.pattern(\"Plain\", first_tag, first_tag)\n\
         \x20       ops.load(fuse_node, side * FUSE[\"lift\"], *([0.0] * (ndf - 1)))\n",
        header(c, "#", source),
        k = l.stiffness,
        f = l.friction,
        m = l.mass,
        gap = c.gap,
        kc = l.gap_stiffness,
        stick = STICK_FACTOR,
        c = l.damping.unwrap_or(0.0),
        fuse = fuse_py(c),
        element = element_py(c),
    )
}

/// The fuse element's constants for openseespy (`ELEMENT = None` without
/// one).
fn element_py(c: &Calibration) -> String {
    match &c.fuse_element {
        None => "ELEMENT = None  # the joint has no fuse element\n".to_string(),
        Some(e) => format!(
            "ELEMENT = {{  # the fuse element (docs/link.md, \"With a fuse\")\n\
             \x20   \"beam\": {},  # which center beam leaves the plane\n\
             \x20   \"release_force\": {:e},  # [N] the closed joint's force at which it leaves\n\
             \x20   \"release_closing\": {:e},  # [m] the closing at which the gap lets go\n\
             \x20   \"gap_after\": {:e},  # [m] the second gap's closing movement (a beam's width more)\n\
             \x20   \"stiffness_after\": {:e},  # [N/m] the second gap (one cell fewer)\n\
             }}\n",
            e.beam, e.break_force, e.release_closing, e.gap_after, e.stiffness_after
        ),
    }
}

/// SAP2000/CSiBridge: the link properties to type in, as a table with
/// the fields as SAP2000's forms name them.
pub fn sap2000(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    let stick = STICK_FACTOR * l.stiffness;
    // property, Link/Support Type, joint I, joint J, the U1 fields
    let rows = [
        (
            "QJ_SPRING",
            "Linear",
            "J_mass",
            "deck",
            format!(
                "Effective Stiffness = {:.6e} N/m; Effective Damping = {:.6e} N-s/m",
                l.stiffness,
                l.damping.unwrap_or(0.0)
            ),
        ),
        (
            "QJ_SLIDER",
            "Plastic (Wen)",
            "abutment",
            "J_mass",
            format!(
                "Nonlinear: Effective Stiffness = {stick:.6e} N/m, Effective Damping = 0; Stiffness = {stick:.6e} N/m, \
                 Yield Strength = {:.6e} N, Post Yield Stiffness Ratio = 0, Yielding Exponent = 20",
                l.friction
            ),
        ),
        (
            "QJ_GAP",
            "Gap",
            if c.fuse.is_some() { "J_edge (deck if side -1)" } else { "abutment (deck if side -1)" },
            if c.fuse.is_some() { "deck (J_edge if side -1)" } else { "deck (abutment if side -1)" },
            format!(
                "Nonlinear: Effective Stiffness = 0, Effective Damping = 0; Stiffness = {:.6e} N/m, Open = {:.6e} m",
                l.gap_stiffness, c.gap
            ),
        ),
    ];
    let mut out = header(c, ";", source);
    out.push_str(
        "; Define > Section Properties > Link/Support Properties > Add New Property, one per row: its\n\
         ; Link/Support Type, direction U1 only (Fixed unchecked; Nonlinear checked where the row says so),\n\
         ; the fields below in the U1 Directional Properties form. Draw J_mass, a new joint at the deck\n\
         ; joint's place, with Mass U1 below (Assign > Joint > Masses), restrained in U2, U3, R1-R3. Draw\n\
         ; each link from its joint I to its joint J and set its local axis 1 along the bridge\n\
         ; (Assign > Link/Support > Local Axes: a zero-length link's axis 1 is otherwise vertical), pointing\n\
         ; to global +X. side +1: the deck lies toward +X of the joint (the bridge's first end); side -1:\n\
         ; toward -X (the far end), where only the gap's I and J swap, so that it closes as the deck moves\n\
         ; toward the abutment (SAP2000's Gap closes when the deformation U1(J) - U1(I) falls below -Open)\n\
         ; and the chain stays abutment - slider - mass - spring - deck.\n\
         ; Effective Stiffness is what linear load cases and the modes of FNA (fast nonlinear analysis)\n\
         ; see: the stuck joint and the open gap (0). Effective Damping is a dashpot [N-s/m], not a ratio:\n\
         ; nonlinear direct integration applies it as one; in linear cases SAP2000 turns it into modal\n\
         ; damping, and in FNA the links' damping enters through the modes too (check it against a direct-\n\
         ; integration run; docs/link.md). The slider's Yielding Exponent 20 is SAP2000's sharpest Wen\n\
         ; transition: the nearest it has to OpenSees' ElasticPP (a rigid-plastic slider).\n",
    );
    out.push_str("property\tLink/Support Type\tjoint I\tjoint J\tU1\n");
    for (name, kind, from, to, u1) in rows {
        out.push_str(&format!("{name}\t{kind}\t{from}\t{to}\t{u1}\n"));
    }
    out.push_str(&format!("J_mass\tjoint mass\t\t\tMass U1 = {:.6e} kg\n", l.mass));
    if let Some(f) = &c.fuse {
        out.push_str(&sap2000_fuse(f));
    }
    if let Some(e) = &c.fuse_element {
        out.push_str(&format!(
            "QJ_GAP_RELEASED\tGap\tabutment (deck if side -1)\tdeck (abutment if side -1)\tNonlinear: Effective \
             Stiffness = 0, Effective Damping = 0; Stiffness = {k:.6e} N/m, Open = {g:.6e} m\n\
             ; The fuse element (approximated): SAP2000 has no link that lets go for good. QJ_GAP is the joint\n\
             ; with beam {beam} in place: beyond its release force ({f:.6e} N, at a closing of {r:.6e} m) its\n\
             ; forces are an upper bound. QJ_GAP_RELEASED, in place of QJ_GAP, is the joint after the beam\n\
             ; left: one cell fewer, closing a beam's width later. Run both and check the first's peak gap\n\
             ; force against the release force.\n",
            k = e.stiffness_after,
            g = e.gap_after,
            beam = e.beam,
            f = e.break_force,
            r = e.release_closing,
        ));
    }
    out
}

/// The fuse box's SAP2000 rows: a Multi-Linear Plastic link from the
/// abutment to the edge beam's joint, and what it approximates.
fn sap2000_fuse(f: &FuseExport) -> String {
    let slide = f.resistance + f.lift;
    let (eb, s) = (f.break_strain, f.stroke);
    // (deformation, force) along U1, closing negative
    let points = [
        (-s - 0.01, -slide - f.stop_stiffness * 0.01),
        (-s, -slide),
        (-2.0 * eb, -slide),
        (-eb, -f.break_force),
        (0.0, 0.0),
        (0.01, f.stop_stiffness * 0.01),
    ];
    let curve: Vec<String> = points.iter().map(|(d, p)| format!("({d:.6e} m, {p:.6e} N)")).collect();
    format!(
        "QJ_FUSE\tMulti-Linear Plastic\tabutment (J_edge if side -1)\tJ_edge (abutment if side -1)\t\
         Nonlinear: Effective Stiffness = {k:.6e} N/m, Effective Damping = 0; Hysteresis Type = Kinematic; \
         Multi-Linear Force-Deformation Definition (Deformation, Force) = {curve}\n\
         J_edge\tjoint mass\t\t\tMass U1 = {m:.6e} kg\n\
         ; Draw J_edge, the edge beam, a new joint at the abutment joint's place, restrained as J_mass.\n\
         ; The fuse box (approximated): SAP2000 has no link that breaks for good. The curve rises with the\n\
         ; weld to the break force at {eb:.3e} m, drops to the freed edge beam's push up the ramp (friction\n\
         ; plus lift, {slide:.6e} N), slides to the stop after {s:.6e} m and meets it. Its kinematic\n\
         ; hysteresis does not remember the break: on a reversal the weld's strength comes back shifted,\n\
         ; and the lift that pushes the beam back to its seat ({lift:.6e} N) is not in it. Use it in\n\
         ; nonlinear direct integration only, and check the run's peak force against the break force.\n",
        k = f.weld_stiffness,
        curve = curve.join(", "),
        m = f.mass,
        eb = eb,
        slide = slide,
        s = s,
        lift = f.lift,
    )
}
