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
    .chain(c.has_fuse.then(|| {
        "WARNING: the joint has a fuse box ([joint.fuse]) and this element does not carry it: it is the joint \
         without its fuse (quakejoint's own link does carry it)"
            .to_string()
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

/// OpenSees Tcl: a procedure adding the link between two existing nodes,
/// and one creating its mass node ahead of an eigen analysis.
pub fn opensees_tcl(c: &Calibration, source: &str) -> String {
    let l = &c.link;
    format!(
        "{}#\n# quakejointLink abutNode deckNode newNode firstTag ?side?\n\
         #   abutNode, deckNode: existing nodes at the same place (never swap them);\n\
         #   side: +1 (default) where the deck lies toward +X (global X) of the joint, the\n\
         #   bridge's first end; -1 where it lies toward -X, the far end: the chain stays\n\
         #   abutment - slider - mass - spring - deck and the gap closes as the deck moves\n\
         #   toward the abutment; newNode: the moving mass's node tag; firstTag: the first\n\
         #   of 5 free material and element tags. 2D or 3D: the new node takes the deck node's\n\
         #   coordinates and DOFs, its mass and freedom along the first (global X).\n\
         # With modalDamping: call quakejointLinkNode deckNode newNode before the eigen command\n\
         #   (the mass node, held along X there) and quakejointLink after modalDamping (it frees\n\
         #   the node): a node with mass added after modalDamping makes OpenSees 3.7.1 end\n\
         #   without an error, and a link present at the eigen analysis has its modes damped too.\n\
         proc quakejointLinkNode {{deckNode newNode}} {{\n\
         \x20   set ndf [llength [nodeDisp $deckNode]]\n\
         \x20   set mass [list -mass {m:e}]\n\
         \x20   set fixed [list]\n\
         \x20   for {{set i 1}} {{$i < $ndf}} {{incr i}} {{ lappend mass 0.0 }}\n\
         \x20   for {{set i 0}} {{$i < $ndf}} {{incr i}} {{ lappend fixed 1 }}\n\
         \x20   node $newNode {{*}}[nodeCoord $deckNode] {{*}}$mass\n\
         \x20   fix $newNode {{*}}$fixed\n\
         }}\n\
         proc quakejointLink {{abutNode deckNode newNode firstTag {{side 1}}}} {{\n\
         \x20   if {{$side != 1 && $side != -1}} {{ error \"quakejointLink: side must be 1 or -1, not $side\" }}\n\
         \x20   if {{[lsearch -exact [getNodeTags] $newNode] < 0}} {{\n\
         \x20       quakejointLinkNode $deckNode $newNode\n\
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
         \x20   element zeroLength $firstTag $newNode $deckNode -mat $firstTag -dir 1\n\
         \x20   element zeroLength [expr {{$firstTag + 1}}] $abutNode $newNode -mat [expr {{$firstTag + 1}}] -dir 1\n\
         \x20   if {{$side == 1}} {{\n\
         \x20       element zeroLength [expr {{$firstTag + 2}}] $abutNode $deckNode -mat [expr {{$firstTag + 2}}] -dir 1\n\
         \x20   }} else {{\n\
         \x20       element zeroLength [expr {{$firstTag + 2}}] $deckNode $abutNode -mat [expr {{$firstTag + 2}}] -dir 1\n\
         \x20   }}\n\
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
         def add_link_node(ops, deck_node, new_node):\n\
         \x20   \"\"\"The link's mass node at the deck node, held along X until add_link frees it.\n\
         \x20   With modalDamping, call it before the eigen analysis and add_link after\n\
         \x20   modalDamping: a node with mass added after modalDamping makes OpenSees 3.7.1 end\n\
         \x20   the process without an error, and a link present at the eigen analysis has its\n\
         \x20   modes damped too (docs/link.md).\"\"\"\n\
         \x20   ndf = len(ops.nodeDisp(deck_node))\n\
         \x20   ops.node(new_node, *ops.nodeCoord(deck_node), \"-mass\", MASS, *([0.0] * (ndf - 1)))\n\
         \x20   ops.fix(new_node, *([1] * ndf))\n\n\n\
         def add_link(ops, abut_node, deck_node, new_node, first_tag, side=1):\n\
         \x20   \"\"\"Adds the link between two existing nodes at the same place (never swap\n\
         \x20   them). side: +1 where the deck lies toward +X (global X) of the joint, the\n\
         \x20   bridge's first end; -1 where it lies toward -X, the far end: the chain stays\n\
         \x20   abutment - slider - mass - spring - deck and the gap closes as the deck moves\n\
         \x20   toward the abutment. new_node: the moving mass's node tag (made here unless\n\
         \x20   add_link_node made it); first_tag: the first of 5 free material tags (and of 3\n\
         \x20   element tags). 2D or 3D: the new node takes the deck node's coordinates and\n\
         \x20   DOFs, its mass and freedom along the first (global X).\"\"\"\n\
         \x20   if side not in (1, -1):\n\
         \x20       raise ValueError(f\"add_link: side must be 1 or -1, not {{side!r}}\")\n\
         \x20   if new_node not in ops.getNodeTags():\n\
         \x20       add_link_node(ops, deck_node, new_node)\n\
         \x20   ops.remove(\"sp\", new_node, 1)\n\
         \x20   k_stick = STICK_FACTOR * STIFFNESS\n\
         \x20   ops.uniaxialMaterial(\"Elastic\", first_tag + 3, STIFFNESS)\n\
         \x20   ops.uniaxialMaterial(\"Viscous\", first_tag + 4, DAMPING, 1.0)\n\
         \x20   ops.uniaxialMaterial(\"Parallel\", first_tag, first_tag + 3, first_tag + 4)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPP\", first_tag + 1, k_stick, FRICTION / k_stick)\n\
         \x20   ops.uniaxialMaterial(\"ElasticPPGap\", first_tag + 2, GAP_STIFFNESS, -1.0e20, -GAP)\n\
         \x20   ops.element(\"zeroLength\", first_tag, new_node, deck_node, \"-mat\", first_tag, \"-dir\", 1)\n\
         \x20   ops.element(\"zeroLength\", first_tag + 1, abut_node, new_node, \"-mat\", first_tag + 1, \"-dir\", 1)\n\
         \x20   # (the gap's deformation is the opening's sign: it closes toward the abutment)\n\
         \x20   gap_nodes = (abut_node, deck_node) if side == 1 else (deck_node, abut_node)\n\
         \x20   ops.element(\"zeroLength\", first_tag + 2, *gap_nodes, \"-mat\", first_tag + 2, \"-dir\", 1)\n",
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
            "abutment (deck if side -1)",
            "deck (abutment if side -1)",
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
    out
}
