# body/mesh_volumes.awk -- exits 0 when a gmsh mesh file has volume elements (a 3D body, docs/3d.md), 1 otherwise.
# edp/run.sh compiles the driver for the dimension it finds; body/mesh.idp checks the mesh the driver loads against it.
# usage: awk -f body/mesh_volumes.awk FILE
# MSH 2.2: in $Elements, each line is number, type, ...; types 4 and 11 are tetrahedra.
# MSH 4 (ASCII): the first line of $Entities counts the points, curves, surfaces and volumes.
{ sub(/\r$/, "") }
/^\$Entities$/ { getline; sub(/\r$/, ""); if ($4 + 0 > 0) found = 1; exit }
/^\$Elements$/ { on = 1; getline; next }
/^\$EndElements$/ { exit }
on && ($2 == 4 || $2 == 11) { found = 1; exit }
END { exit !found }
