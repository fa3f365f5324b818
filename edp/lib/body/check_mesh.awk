# body/check_mesh.awk -- validate a gmsh MSH 2.2 ASCII file before FreeFEM's gmshload
# reads it (gmshload crashes, or reads garbage, on a defective file).
# usage: awk -v name=NAME -f run/numbers.awk -f body/check_mesh.awk FILE
# Prints one line "error: -mesh NAME: <defect>" and exits 3 on the first defect;
# silent with exit 0 for a mesh that gmshload can read: ASCII MSH 2.2, complete
# $Nodes and $Elements sections, finite coordinates, elements of type 15 (point),
# 1 (2-node line) or 2 (3-node triangle) on existing nodes, at least one triangle,
# every triangle counter-clockwise with a positive area, every node in a triangle,
# and every node in one plane z = const (a 2D mesh). With -v dimension=3 (edp/run.sh
# found tetrahedra in it): triangles are the boundary's faces, and the body is its 4-node
# tetrahedra (type 4), each with a positive volume, every node in one. In both, each physical label of the cells
# (a gmsh Physical Surface, 3D Physical Volume) is one body: its cells form one piece, and no node is in two bodies.
function fail(msg) { printf "error: -mesh %s: %s\n", name, msg; failed = 1; exit 3 }
# an edge's (a face's) key from its sorted node ids: a number while it stays exact in double precision (awk indexes
# numbers faster than strings), else a string; keyNodes and keyBase are set from $Nodes
function edgeKey(a, b,   t) {
  a += 0; b += 0
  if (a > b) { t = a; a = b; b = t }
  return numericKeys ? a * keyBase + b : a " " b
}
function faceKey(a, b, c,   t) {
  a += 0; b += 0; c += 0
  if (a > b) { t = a; a = b; b = t }
  if (b > c) { t = b; b = c; c = t }
  if (a > b) { t = a; a = b; b = t }
  return numericKeys ? (a * keyBase + b) * keyBase + c : a " " b " " c
}
function keyCorners(key, corner) {      # the sorted node ids of a key, into corner[1..]; their count
  if (!numericKeys) return split(key, corner, " ")
  if (dimension == 3) { corner[3] = key % keyBase; key = (key - corner[3]) / keyBase }
  corner[2] = key % keyBase; corner[1] = (key - corner[2]) / keyBase
  return (dimension == 3) ? 3 : 2
}
# the body's cells' labels (a gmsh Physical Surface, 3D Physical Volume, is one body) and its pieces: nodes joined by
# a cell are one piece (union-find)
function cellLabel(l) { if (!(l in labelCells)) labels[++nLabels] = l; labelCells[l]++; cellLabelNow = l }
# a node of the current cell: in no other body's cell (bodies that share a node would be glued at it)
function nodeOfBody(k) {
  if (!(k in nodeLabel)) nodeLabel[k] = cellLabelNow
  else if (nodeLabel[k] != cellLabelNow && !sharedNode) { sharedNode = k; sharedLabels = nodeLabel[k] " and " cellLabelNow }
}
function root(k) { while (parent[k] != k) { parent[k] = parent[parent[k]]; k = parent[k] }; return k }
function joinCell(a, b, c, d,   r, s) {
  r = root(a + 0)
  if ((s = root(b + 0)) != r) parent[s] = r
  if ((s = root(c + 0)) != r) parent[s] = r
  if (d != "" && (s = root(d + 0)) != r) parent[s] = r
}
function point(k) { return "(" X[k] ", " Y[k] ((dimension == 3) ? ", " Z[k] : "") ")" }
BEGIN {
  section = ""
  if ((getline first < ARGV[1]) < 0) fail("file missing or unreadable")
  close(ARGV[1])
}
{ sub(/\r$/, "") }
NR == 1 { if ($0 != "$MeshFormat") fail("not a gmsh MSH file (its first line is not $MeshFormat)"); section = "format"; next }
section == "format" {
  if ($0 == "$EndMeshFormat") { if (!version) fail("$MeshFormat is empty"); section = ""; next }
  if (version) fail("$MeshFormat has more than one line")
  version = $1
  # (gmsh's option of the body's dimension: -3 when edp/run.sh found volumes (body/mesh_volumes.awk, which reads an ASCII
  # file's $Entities); a binary file's are not read)
  if ($1 != "2.2" && dimension == 3) fail("MSH version " $1 ", not 2.2 (write it with gmsh -3 -format msh22" ($2 == "0" ? "" : ", without -bin") ")")
  if ($1 != "2.2" && $2 != "0") fail("binary MSH version " $1 ", not 2.2 (write it with gmsh -format msh22 and without -bin: gmsh -2 for a plane body, -3 for a volume)")
  if ($1 != "2.2") fail("MSH version " $1 ", not 2.2 (write it with gmsh -2 -format msh22)")
  if ($2 != "0") fail("binary MSH 2.2; FreeFEM's gmshload reads ASCII only (write it without -bin)")
  next
}
section == "" && /^\$/ {
  section = substr($0, 2)
  if (section == "Elements" && !done["Nodes"]) fail("$Elements before $Nodes")
  if (section == "Nodes" || section == "Elements") { count = -1; read = 0 }
  next
}
section == "" && NF == 0 { next }
section == "" { fail("unexpected line " NR " outside any section: '" substr($0, 1, 40) "'") }
# $Nodes and $Elements: a count, that many lines, then $EndNodes or $EndElements
section != "Nodes" && section != "Elements" { if ($0 == "$End" section) section = ""; next }
count < 0 {
  if (!isint($1) || NF != 1 || $1 + 0 == 0) fail("$" section " must start with a positive count, line " NR " is '" $0 "'")
  count = $1 + 0; next
}
$0 == "$End" section {
  if (read < count) fail("truncated in $" section ": " read " of " count " " tolower(section))
  done[section] = 1; section = ""; next
}
read == count { fail("$" section " has more than the " count " " tolower(section) " it announces (line " NR ")") }
section == "Nodes" {
  if (NF != 4 || !isint($1) || !isnum($2) || !isnum($3) || !isnum($4))
    fail("line " NR " in $Nodes is not 'id x y z': '" substr($0, 1, 60) "'")
  if (!isfinite($2) || !isfinite($3)) fail("node " $1 " has a coordinate that is not a finite number")
  if ($1 in X) fail("node " $1 " is defined twice")
  X[$1] = $2 + 0; Y[$1] = $3 + 0; Z[$1] = $4 + 0; read++; nodeId[++nNodes] = $1; parent[$1 + 0] = $1 + 0
  if ($1 + 1 > keyBase) keyBase = $1 + 1
  numericKeys = (dimension == 3 ? keyBase ^ 3 : keyBase ^ 2) < 2 ^ 52
  if (!isfinite($4)) fail("node " $1 " has a coordinate that is not a finite number")
  if (read == 1 || $4 + 0 < zmin) zmin = $4 + 0
  if (read == 1 || $4 + 0 > zmax) zmax = $4 + 0
  if (read == 1 || $2 + 0 < xmin) xmin = $2 + 0
  if (read == 1 || $2 + 0 > xmax) xmax = $2 + 0
  if (read == 1 || $3 + 0 < ymin) ymin = $3 + 0
  if (read == 1 || $3 + 0 > ymax) ymax = $3 + 0
  next
}
section == "Elements" {
  for (i = 1; i <= NF; i++) if (!isint($i)) fail("line " NR " in $Elements is not a list of integers: '" substr($0, 1, 60) "'")
  type = $2 + 0; ntags = $3 + 0
  nodes = (type == 15) ? 1 : (type == 1) ? 2 : (type == 2) ? 3 : (type == 4 && dimension == 3) ? 4 : -1
  if (nodes < 0 && dimension == 3)
    fail("element " $1 " has type " type "; a 3D mesh takes points (15), 2-node lines (1), 3-node triangles (2) and 4-node tetrahedra (4)")
  if (type == 5 || type == 6 || type == 7 || type == 12 || type == 13 || type == 14 || type == 17 || type == 18 || type == 19 || type == 29)
    fail("element " $1 " is a volume element of type " type "; a 3D body must be meshed with 4-node tetrahedra (type 4)")
  if (nodes < 0) fail("element " $1 " has type " type "; only points (15), 2-node lines (1) and 3-node triangles (2) are supported")
  if (NF != 3 + ntags + nodes) fail("element " $1 " (line " NR ") has " NF " fields, its type and tags need " 3 + ntags + nodes)
  for (i = NF - nodes + 1; i <= NF; i++) if (!($i in X)) fail("element " $1 " uses node " $i ", which $Nodes does not define")
  if (type == 15) { pointElement[$NF] = $1; pointPhysical[$NF] = (ntags >= 1) ? $4 + 0 : 0 }
  # the labelled boundary: a line's edge (2D), a triangle's face (3D), by its sorted nodes
  if (type == 1 && dimension != 3) labelled[edgeKey($(NF - 1), $NF)] = 1
  if (type == 2 && dimension == 3) labelled[faceKey($(NF - 2), $(NF - 1), $NF)] = 1
  if (type == 4) {
    a = $(NF - 3); b = $(NF - 2); c = $(NF - 1); d = $NF
    cellLabel(ntags >= 1 ? $4 + 0 : 0); joinCell(a, b, c, d); nodeOfBody(a); nodeOfBody(b); nodeOfBody(c); nodeOfBody(d)
    inTriangle[a] = 1; inTriangle[b] = 1; inTriangle[c] = 1; inTriangle[d] = 1
    ux = X[b] - X[a]; uy = Y[b] - Y[a]; uz = Z[b] - Z[a]; vx = X[c] - X[a]; vy = Y[c] - Y[a]; vz = Z[c] - Z[a]
    wx = X[d] - X[a]; wy = Y[d] - Y[a]; wz = Z[d] - Z[a]
    volume = (ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx)) / 6
    scale = (ux^2 + uy^2 + uz^2 + vx^2 + vy^2 + vz^2 + wx^2 + wy^2 + wz^2)^1.5
    if (!(volume > 1e-12 * scale)) fail("tetrahedron " $1 " is inverted or degenerate (volume " volume ")")
    faces[faceKey(a, b, c)]++; faces[faceKey(a, b, d)]++; faces[faceKey(a, c, d)]++; faces[faceKey(b, c, d)]++
    triangles++; read++; next
  }
  if (type == 2 && dimension == 3) { read++; next }
  if (type == 2) {
    a = $(NF - 2); b = $(NF - 1); c = $NF
    cellLabel(ntags >= 1 ? $4 + 0 : 0); joinCell(a, b, c, ""); nodeOfBody(a); nodeOfBody(b); nodeOfBody(c)
    inTriangle[a] = 1; inTriangle[b] = 1; inTriangle[c] = 1
    area = ((X[b] - X[a]) * (Y[c] - Y[a]) - (X[c] - X[a]) * (Y[b] - Y[a])) / 2
    scale = (X[b] - X[a])^2 + (Y[b] - Y[a])^2 + (X[c] - X[a])^2 + (Y[c] - Y[a])^2
    if (area < 0 && !firstInverted) { firstInverted = $1; firstInvertedArea = area }
    edges[edgeKey(a, b)]++; edges[edgeKey(b, c)]++; edges[edgeKey(c, a)]++
    if (area < 0) { inverted++; triangles++; read++; next }
    if (!(area > 1e-12 * scale)) fail("triangle " $1 " is degenerate (area " area ")")
    if (area < 1e-8) fail("triangle " $1 " has an area of " area ", below the 1e-8 that FreeFEM's gmshload accepts; scale the mesh up")
    triangles++
  }
  read++
  next
}
END {
  if (failed) exit 3
  if (NR == 0) fail("the file is empty")
  if (section == "format") fail("truncated in $MeshFormat")
  if (section == "Nodes" || section == "Elements") fail("truncated in $" section ": " read " of " count " " tolower(section) ", no $End" section)
  if (section != "") fail("truncated in $" section)
  if (!done["Nodes"]) fail("no $Nodes section")
  if (!done["Elements"]) fail("no $Elements section")
  if (!triangles && dimension == 3) fail("no tetrahedra (element type 4): mesh the Volume with gmsh -3")
  if (!triangles) fail("no triangles (element type 2)")
  if (inverted == triangles)
    fail("every triangle is clockwise: the body's curve loop is drawn clockwise in its .geo; reverse it (for example Curve Loop(1) = {-4, -3, -2, -1}; instead of {1, 2, 3, 4}), or add Reverse Surface{1};")
  if (inverted) fail("triangle " firstInverted " is inverted (clockwise, area " firstInvertedArea "); FreeFEM needs counter-clockwise triangles")
  size = (xmax - xmin) + (ymax - ymin)
  cell = (dimension == 3) ? "tetrahedron" : "triangle"
  cells = (dimension == 3) ? "tetrahedra" : "triangles"
  if (dimension != 3 && zmax - zmin > 1e-9 * size)
    fail("its nodes span z from " zmin " to " zmax ", not one plane, and it has no tetrahedra: a plane body needs its nodes in one plane (gmsh -2 of a plane geometry), a 3D body a Volume meshed into tetrahedra (gmsh -3)")
  groups = (dimension == 3) ? "Physical Volume and Physical Surface" : "Physical Surface and Physical Curve"
  # every boundary edge (3D: face) carries a physical label (docs/geometry.md): one without would take a label FreeFEM
  # guesses (and a saved mesh that does not match the run's)
  split("", missing); unlabelled = 0; boundary = 0
  if (dimension == 3) { for (key in faces) if (faces[key] == 1) { boundary++; if (!(key in labelled)) { unlabelled++; first = key } } }
  else for (key in edges) if (edges[key] == 1) { boundary++; if (!(key in labelled)) { unlabelled++; first = key } }
  if (unlabelled) {
    n = keyCorners(first, corner)
    where = (n == 3) ? "face " point(corner[1]) ", " point(corner[2]) ", " point(corner[3]) : "edge from " point(corner[1]) " to " point(corner[2])
    fail(unlabelled " of the " boundary " boundary " ((dimension == 3) ? "faces" : "edges") " carry no " ((dimension == 3) ? "Physical Surface" : "Physical Curve") " label, such as the " where ": every boundary " ((dimension == 3) ? "face" : "edge") " needs one (Gamma_C's, Gamma_D's or a traction-free label: docs/geometry.md); add them to the .geo's " ((dimension == 3) ? "Physical Surface" : "Physical Curve") " lines")
  }
  # each label of the cells is one body (docs/bodies.md): bodies share no node (they would be glued there), and each is
  # one piece (pieces apart would pass through each other: contact is between bodies, not within one)
  volumeWord = (dimension == 3) ? "Physical Volume" : "Physical Surface"
  if (sharedNode)
    fail("node " sharedNode " " point(sharedNode) " is in the " cells " of two bodies, " volumeWord " labels " sharedLabels ": each body needs its own nodes (bodies that share a node are glued there); draw the touching bodies with their own points and curves, with Geometry.AutoCoherence = 0; in the .geo (meshes/bars.geo), or give the " cells " one label")
  for (i = 1; i <= nNodes; i++) if ((k = nodeId[i]) in inTriangle) {
    r = root(k + 0)
    if (!(r in pieceAt)) { pieceAt[r] = k; l = nodeLabel[k]; if (++labelPieces[l] == 1) labelFirst[l] = k; else if (!splitSet) { splitSet = 1; splitLabel = l; splitSecond = k } }
  }
  if (splitSet) {
    n = labelPieces[splitLabel]
    fail("the body of " volumeWord " label " splitLabel " is " n " pieces that share no node, one at " point(labelFirst[splitLabel]) ", another at " point(splitSecond) "; a body is one piece (pieces apart would pass through each other: contact is between bodies): give each piece its own label")
  }
  for (i = 1; i <= nNodes; i++) if (!((k = nodeId[i]) in inTriangle)) {
    at = "(at " X[k] ", " Y[k] ((dimension == 3) ? ", " Z[k] : "") ")"
    if ((k in pointElement) && pointPhysical[k] == 0) fail("node " k " " at " is a geometric point in no physical group (element " pointElement[k] ", e.g. an arc's centre) and in no " cell ": the .geo defines no Physical groups, so gmsh saved every entity; add " groups " lines to it")
    if (k in pointElement) fail("node " k " " at " of the point element " pointElement[k] " (a gmsh Physical Point) is in no " cell ": the point is off the body; move it onto the body or remove it")
    fail("node " k " " at " is in no " cell ": an orphan node, which would make the system singular; remove it from the mesh")
  }
}
