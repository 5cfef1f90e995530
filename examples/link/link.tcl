# quakejoint link element, calibrated from configs/paper.toml
# units: N, m, kg, s
# spring (stuck joint)      k   = 5.690202e7 N/m
# slider (friction)         F   = 2.573247e5 N
# moving mass               m   = 5.969961e3 kg
# damper with the spring    c   = 1.138040e4 N s/m
# closing movement (gap)    g   = 1.120000e0 m  (28 cells)
# closed-joint stiffness    k_c = 5.165160e7 N/m (the closed cells' Hertz law as a secant at 1.000e6 N, a default: the detailed joint did not close under the calibration suite: where your model's closed joint meets another force, rerun `quakejoint calibrate --contact-force` with it until the two agree; docs/link.md)
# first cell closes at          = 9.760989e-1 m  (the narrowest cell, racked 5.1 mm behind the average: the beams strike there; the element's force waits for g)
# opening capacity              = 9.493967e-1 m  (the widest cell, racked 6.1 mm ahead of the average, at joint.capacity.max_subgap)
# racking from the largest of the service loops (4.4 / 4.1 mm closing / opening) and the calibration suite (5.1 / 6.1 mm)
# the opening u is the deck's displacement away from the abutment; the element acts along it
#
# quakejointLink abutNode deckNode newNode firstTag ?side? ?fuseNode?
#   abutNode, deckNode: existing nodes at the same place (never swap them);
#   side: +1 (default) where the deck lies toward +X (global X) of the joint, the
#   bridge's first end; -1 where it lies toward -X, the far end: the chain stays
#   abutment - slider - mass - spring - deck and the gap closes as the deck moves
#   toward the abutment; newNode: the moving mass's node tag; firstTag: the first
#   of 10 free material tags (7 element tags; with a fuse on a ramp a time series and
#   a load pattern). With a fuse box (hasFuse 1) the gap closes on the edge beam's node
#   fuseNode (newNode + 1 by default), held on the abutment by a weld that breaks
#   (MinMax), its friction, seat and stop, and pushed back by the ramp's lift.
#   2D or 3D: the new nodes take the deck node's coordinates and DOFs, their mass
#   and freedom along the first (global X).
# With modalDamping: call quakejointLinkNode deckNode newNode before the eigen command
#   (the mass nodes, held along X there) and quakejointLink after modalDamping (it frees
#   them): a node with mass added after modalDamping makes OpenSees 3.7.1 end
#   without an error, and a link present at the eigen analysis has its modes damped too.
set quakejointLinkHasFuse 0
proc quakejointMassNode {deckNode node mass} {
    set ndf [llength [nodeDisp $deckNode]]
    set masses [list -mass $mass]
    set fixed [list]
    for {set i 1} {$i < $ndf} {incr i} { lappend masses 0.0 }
    for {set i 0} {$i < $ndf} {incr i} { lappend fixed 1 }
    node $node {*}[nodeCoord $deckNode] {*}$masses
    fix $node {*}$fixed
}
proc quakejointLinkNode {deckNode newNode {fuseNode ""}} {
    global quakejointLinkHasFuse
    quakejointMassNode $deckNode $newNode 5.969960852885217e3
    if {$quakejointLinkHasFuse} {
        if {$fuseNode eq ""} { set fuseNode [expr {$newNode + 1}] }
        quakejointMassNode $deckNode $fuseNode 0e0
    }
}
proc quakejointLink {abutNode deckNode newNode firstTag {side 1} {fuseNode ""}} {
    global quakejointLinkHasFuse
    if {$side != 1 && $side != -1} { error "quakejointLink: side must be 1 or -1, not $side" }
    if {$fuseNode eq ""} { set fuseNode [expr {$newNode + 1}] }
    if {[lsearch -exact [getNodeTags] $newNode] < 0} {
        quakejointLinkNode $deckNode $newNode $fuseNode
    }
    remove sp $newNode 1
    set k 5.690202221956255e7
    set F 2.5732466057310026e5
    set kStick [expr {1000 * $k}]
    uniaxialMaterial Elastic [expr {$firstTag + 3}] $k
    uniaxialMaterial Viscous [expr {$firstTag + 4}] 1.138040444391251e4 1.0
    uniaxialMaterial Parallel $firstTag [expr {$firstTag + 3}] [expr {$firstTag + 4}]
    uniaxialMaterial ElasticPP [expr {$firstTag + 1}] $kStick [expr {$F / $kStick}]
    uniaxialMaterial ElasticPPGap [expr {$firstTag + 2}] 5.1651597924325414e7 -1.0e20 -1.12e0
    set gapMat [expr {$firstTag + 2}]
    element zeroLength $firstTag $newNode $deckNode -mat $firstTag -dir 1
    element zeroLength [expr {$firstTag + 1}] $abutNode $newNode -mat [expr {$firstTag + 1}] -dir 1
    if {$quakejointLinkHasFuse} { set base $fuseNode } else { set base $abutNode }
    if {$side == 1} { set gapEnds [list $base $deckNode] } else { set gapEnds [list $deckNode $base] }
    element zeroLength [expr {$firstTag + 2}] {*}$gapEnds -mat $gapMat -dir 1
}
