# quakejoint link element, calibrated from configs/paper.toml
# units: N, m, kg, s
# spring (stuck joint)      k   = 5.690202e7 N/m
# slider (friction)         F   = 2.573247e5 N
# moving mass               m   = 4.974967e3 kg
# damper with the spring    c   = 1.000000e5 N s/m
# closing movement (gap)    g   = 1.120000e0 m  (28 cells)
# closed-joint stiffness    k_c = 5.165160e7 N/m (the closed cells' Hertz law as a secant at 1.000e6 N: rerun `quakejoint calibrate --contact-force` with the closed joint's force your model finds, until the two agree; docs/link.md)
# opening capacity              = 1.120000e0 m  (cells at joint.capacity.max_subgap)
# the opening u is the deck's displacement away from the abutment; the element acts along it
#
# quakejointLink abutNode deckNode newNode firstTag
#   abutNode, deckNode: existing nodes at the same place, the deck lying toward
#   +x (the global X) of the joint. Not for a deck lying toward -x: swapping the nodes
#   reverses the chain, the slider on the deck (docs/link.md);
#   newNode: a new node tag (the moving mass); firstTag: the first of 5 free material
#   and element tags. 2D or 3D: the new node takes the deck node's coordinates and DOFs,
#   its mass and freedom along the first (global X).
proc quakejointLink {abutNode deckNode newNode firstTag} {
    set ndf [llength [nodeDisp $deckNode]]
    set mass [list -mass 4.974967377404348e3]
    set fixed [list 0]
    for {set i 1} {$i < $ndf} {incr i} { lappend mass 0.0; lappend fixed 1 }
    node $newNode {*}[nodeCoord $deckNode] {*}$mass
    fix $newNode {*}$fixed
    set k 5.690202221956255e7
    set F 2.5732466057310026e5
    set kStick [expr {1000 * $k}]
    uniaxialMaterial Elastic [expr {$firstTag + 3}] $k
    uniaxialMaterial Viscous [expr {$firstTag + 4}] 1e5 1.0
    uniaxialMaterial Parallel $firstTag [expr {$firstTag + 3}] [expr {$firstTag + 4}]
    uniaxialMaterial ElasticPP [expr {$firstTag + 1}] $kStick [expr {$F / $kStick}]
    uniaxialMaterial ElasticPPGap [expr {$firstTag + 2}] 5.1651597924325414e7 -1.0e20 -1.12e0
    element zeroLength $firstTag $newNode $deckNode -mat $firstTag -dir 1
    element zeroLength [expr {$firstTag + 1}] $abutNode $newNode -mat [expr {$firstTag + 1}] -dir 1
    element zeroLength [expr {$firstTag + 2}] $abutNode $deckNode -mat [expr {$firstTag + 2}] -dir 1
}
