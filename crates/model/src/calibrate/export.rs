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

/// The slider's stick stiffness in the exports, relative to the spring's
/// [-]: rigid next to it (0.1 % of the stuck joint's deflection).
pub const STICK_FACTOR: f64 = 1000.0;

/// How `k_c` was taken: the Hertz contacts' secant at the calibration's
/// contact force, with how to iterate it (nothing for linear contacts).
fn secant(c: &Calibration) -> String {
    match c.link.gap_hertz {
        Some(_) => format!(
            " (the closed cells' Hertz law as a secant at {:.3e} N: rerun `quakejoint calibrate --contact-force` \
             with the closed joint's force your model finds, until the two agree; docs/link.md)",
            c.options.contact_force
        ),
        None => String::new(),
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
        format!("opening capacity              = {:.6e} m  (cells at joint.capacity.max_subgap)", c.capacity),
        "the opening u is the deck's displacement away from the abutment; the element acts along it".to_string(),
    ]
    .iter()
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
         mass = {:e}           # [kg]\ndamping = {:e}        # [N s/m]\ngap_stiffness = {:e}  # [N/m]\n{}",
        header(c, "#", source),
        l.stiffness,
        l.friction,
        l.mass,
        l.damping.unwrap_or(0.0),
        l.gap_stiffness,
        l.gap_hertz
            .map_or(String::new(), |k| format!("gap_hertz = {k:e}      # [N/m^1.5] (quakejoint's closed joint)\n"))
    )
}

/// OpenSees Tcl: a procedure adding the link between two existing nodes.
pub fn opensees_tcl(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    format!(
        "{}#\n# quakejointLink abutNode deckNode newNode firstTag\n\
         #   abutNode, deckNode: existing nodes at the same place, the deck lying toward\n\
         #   +x (the global X) of the joint. Not for a deck lying toward -x: swapping the nodes\n\
         #   reverses the chain, the slider on the deck (docs/link.md);\n\
         #   newNode: a new node tag (the moving mass); firstTag: the first of 5 free material\n\
         #   and element tags. 2D or 3D: the new node takes the deck node's coordinates and DOFs,\n\
         #   its mass and freedom along the first (global X).\n\
         proc quakejointLink {{abutNode deckNode newNode firstTag}} {{\n\
         \x20   set ndf [llength [nodeDisp $deckNode]]\n\
         \x20   set mass [list -mass {m:e}]\n\
         \x20   set fixed [list 0]\n\
         \x20   for {{set i 1}} {{$i < $ndf}} {{incr i}} {{ lappend mass 0.0; lappend fixed 1 }}\n\
         \x20   node $newNode {{*}}[nodeCoord $deckNode] {{*}}$mass\n\
         \x20   fix $newNode {{*}}$fixed\n\
         \x20   set k {k:e}\n\
         \x20   set F {f:e}\n\
         \x20   set kStick [expr {{{stick} * $k}}]\n\
         \x20   uniaxialMaterial Elastic [expr {{$firstTag + 3}}] $k\n\
         \x20   uniaxialMaterial Viscous [expr {{$firstTag + 4}}] {c:e} 1.0\n\
         \x20   uniaxialMaterial Parallel $firstTag [expr {{$firstTag + 3}}] [expr {{$firstTag + 4}}]\n\
         \x20   uniaxialMaterial ElasticPP [expr {{$firstTag + 1}}] $kStick [expr {{$F / $kStick}}]\n\
         \x20   uniaxialMaterial ElasticPPGap [expr {{$firstTag + 2}}] {kc:e} -1.0e20 {gap:e}\n\
         \x20   element zeroLength $firstTag $newNode $deckNode -mat $firstTag -dir 1\n\
         \x20   element zeroLength [expr {{$firstTag + 1}}] $abutNode $newNode -mat [expr {{$firstTag + 1}}] -dir 1\n\
         \x20   element zeroLength [expr {{$firstTag + 2}}] $abutNode $deckNode -mat [expr {{$firstTag + 2}}] -dir 1\n\
         }}\n",
        header(c, "#", source),
        m = l.mass,
        k = l.stiffness,
        f = l.friction,
        stick = STICK_FACTOR,
        kc = l.gap_stiffness,
        gap = -c.gap,
        c = l.damping.unwrap_or(0.0),
    )
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
         STICK_FACTOR = {stick}  # the slider's stick stiffness over STIFFNESS\n\n\n\
         def add_link(ops, abut_node, deck_node, new_node, first_tag):\n\
         \x20   \"\"\"Adds the link between two existing nodes at the same place, the deck lying\n\
         \x20   toward +X of the joint (not for a deck toward -X: swapping the nodes reverses the\n\
         \x20   chain, the slider on the deck; docs/link.md); new_node: a new node tag (the\n\
         \x20   moving mass); first_tag: the first of 5 free material tags (and of 3 element tags).\n\
         \x20   2D or 3D: the new node takes the deck node's coordinates and DOFs, its mass\n\
         \x20   and freedom along the first (global X).\"\"\"\n\
         \x20   ndf = len(ops.nodeDisp(deck_node))\n\
         \x20   ops.node(new_node, *ops.nodeCoord(deck_node), \"-mass\", MASS, *([0.0] * (ndf - 1)))\n\
         \x20   ops.fix(new_node, 0, *([1] * (ndf - 1)))\n\
         \x20   k_stick = STICK_FACTOR * STIFFNESS\n\
         \x20   ops.uniaxialMaterial(\"Elastic\", first_tag + 3, STIFFNESS)\n\
         \x20   ops.uniaxialMaterial(\"Viscous\", first_tag + 4, DAMPING, 1.0)\n\
         \x20   ops.uniaxialMaterial(\"Parallel\", first_tag, first_tag + 3, first_tag + 4)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPP\", first_tag + 1, k_stick, FRICTION / k_stick)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPPGap\", first_tag + 2, GAP_STIFFNESS, -1.0e20, -GAP)\n\
         \x20   ops.element(\"zeroLength\", first_tag, new_node, deck_node, \"-mat\", first_tag, \"-dir\", 1)\n\
         \x20   ops.element(\"zeroLength\", first_tag + 1, abut_node, new_node, \"-mat\", first_tag + 1, \"-dir\", 1)\n\
         \x20   ops.element(\"zeroLength\", first_tag + 2, abut_node, deck_node, \"-mat\", first_tag + 2, \"-dir\", 1)\n",
        header(c, "#", source),
        k = l.stiffness,
        f = l.friction,
        m = l.mass,
        gap = c.gap,
        kc = l.gap_stiffness,
        stick = STICK_FACTOR,
        c = l.damping.unwrap_or(0.0),
    )
}

/// SAP2000/CSiBridge: the link properties to type in, as a table.
pub fn sap2000(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    let rows = [
        (
            "QJ_SPRING",
            "Linear",
            "deck joint",
            "joint J",
            format!("U1 K = {:.6e} N/m, C = {:.6e} N s/m", l.stiffness, l.damping.unwrap_or(0.0)),
        ),
        (
            "QJ_SLIDER",
            "Plastic (Wen)",
            "joint J",
            "abutment joint",
            format!(
                "U1 nonlinear: K = {:.6e} N/m, Yield = {:.6e} N, Ratio = 0, Exp = 20 (linear K = {:.6e})",
                STICK_FACTOR * l.stiffness,
                l.friction,
                STICK_FACTOR * l.stiffness
            ),
        ),
        (
            "QJ_GAP",
            "Gap",
            "abutment joint",
            "deck joint",
            format!("U1 nonlinear: K = {:.6e} N/m, Open = {:.6e} m", l.gap_stiffness, c.gap),
        ),
    ];
    let mut out = header(c, ";", source);
    out.push_str(
        "; Define > Section Properties > Link/Support Properties, one per row; a new joint J at the\n\
         ; deck joint's place with mass U1 below (Assign > Joint > Masses), restrained in U2, U3, R1-R3;\n\
         ; each link drawn from the first joint (I) to the second (J) of its row, its local axis 1 set along\n\
         ; the bridge (Assign > Link/Support > Local Axes: a zero-length link's axis 1 is otherwise vertical),\n\
         ; the deck lying toward +1 of the joint, so that the gap closes when the deck moves toward the\n\
         ; abutment. Nonlinear direct integration (or FNA) time history.\n",
    );
    out.push_str("property\ttype\tfrom\tto\tU1\n");
    for (name, kind, from, to, u1) in rows {
        out.push_str(&format!("{name}\t{kind}\t{from}\t{to}\t{u1}\n"));
    }
    out.push_str(&format!("joint J mass\t\t\t\tU1 = {:.6e} kg\n", l.mass));
    out
}
