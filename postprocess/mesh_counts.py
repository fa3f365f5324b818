"""Print the vertex, element and labelled boundary-element counts of an MSH 2.2 mesh: for a 2D mesh
triangles and the segments of Gamma_C, Gamma_N and Gamma_D (labels 1, 2, 3); for a 3D mesh (one with
tetrahedra) tetrahedra and the boundary triangles with those labels."""
import sys


def msh22_read(path):
    """An MSH 2.2 file's nodes, [(x, y, z)] in file order, and its elements,
    {(gmsh element type, physical tag): [their nodes' indices into that list]}."""
    lines = open(path).read().split("\n")
    k = lines.index("$Nodes")
    index, nodes = {}, []
    for line in lines[k + 2:k + 2 + int(lines[k + 1])]:
        fields = line.split()
        index[fields[0]] = len(nodes)
        nodes.append(tuple(float(x) for x in fields[1:4]))
    k = lines.index("$Elements")
    elements = {}
    for line in lines[k + 2:k + 2 + int(lines[k + 1])]:
        fields = line.split()
        elem_type, n_tags = int(fields[1]), int(fields[2])
        elements.setdefault((elem_type, int(fields[3])), []).append([index[f] for f in fields[3 + n_tags:]])
    return nodes, elements


def element_counts(path):
    """(vertices, {(gmsh element type, physical tag): count}) of an MSH 2.2 file."""
    nodes, elements = msh22_read(path)
    return len(nodes), {key: len(e) for key, e in elements.items()}


def msh22_counts(path):
    """A 2D mesh: vertices, triangles, segments labelled 1, 2 and 3."""
    nodes, counts = element_counts(path)
    triangles = sum(n for (t, _), n in counts.items() if t == 2)
    return nodes, triangles, counts.get((1, 1), 0), counts.get((1, 2), 0), counts.get((1, 3), 0)


def msh22_counts3(path):
    """A 3D mesh: vertices, tetrahedra, boundary triangles labelled 1, 2 and 3."""
    nodes, counts = element_counts(path)
    tetrahedra = sum(n for (t, _), n in counts.items() if t == 4)
    return nodes, tetrahedra, counts.get((2, 1), 0), counts.get((2, 2), 0), counts.get((2, 3), 0)


if __name__ == "__main__":
    for path in sys.argv[1:]:
        three = any(t == 4 for t, _ in element_counts(path)[1])
        v, e, c, n, d = (msh22_counts3 if three else msh22_counts)(path)
        cells, faces = ("tetrahedra", "triangles") if three else ("triangles", "segments")
        clamped = f", {d} on Gamma_D (label 3)" if d else ""
        print(f"{path}: {v} vertices, {e} {cells}, {c} {faces} on Gamma_C (label 1), {n} on Gamma_N (label 2){clamped}")
