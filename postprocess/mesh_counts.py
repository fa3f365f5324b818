"""Print the vertex, triangle and boundary-segment counts of an MSH 2.2 mesh."""
import sys


def msh22_counts(path):
    lines = open(path).read().split("\n")
    nodes = int(lines[lines.index("$Nodes") + 1])
    k = lines.index("$Elements")
    counts = {}
    for line in lines[k + 2:k + 2 + int(lines[k + 1])]:
        fields = line.split()
        elem_type, tag = int(fields[1]), int(fields[3])
        counts[(elem_type, tag)] = counts.get((elem_type, tag), 0) + 1
    triangles = sum(n for (t, _), n in counts.items() if t == 2)
    return nodes, triangles, counts.get((1, 1), 0), counts.get((1, 2), 0), counts.get((1, 3), 0)


def tetrahedra_counts(path):
    """A 3D mesh's vertices, tetrahedra and boundary triangles on Gamma_C (label 1) and elsewhere, or None for a
    plane mesh."""
    lines = open(path).read().split("\n")
    k = lines.index("$Elements")
    types = [line.split()[1:4:2] for line in lines[k + 2:k + 2 + int(lines[k + 1])]]
    tets = sum(1 for t, _ in types if t == "4")
    if not tets:
        return None
    contact = sum(1 for t, tag in types if t == "2" and tag == "1")
    other = sum(1 for t, tag in types if t == "2" and tag != "1")
    return int(lines[lines.index("$Nodes") + 1]), tets, contact, other


if __name__ == "__main__":
    for path in sys.argv[1:]:
        solid = tetrahedra_counts(path)
        if solid:
            print(f"{path}: {solid[0]} vertices, {solid[1]} tetrahedra, {solid[2]} triangles on Gamma_C (label 1), "
                  f"{solid[3]} elsewhere on the boundary")
            continue
        v, t, c, n, d = msh22_counts(path)
        clamped = f", {d} on Gamma_D (label 3)" if d else ""
        print(f"{path}: {v} vertices, {t} triangles, {c} segments on Gamma_C (label 1), {n} on Gamma_N (label 2){clamped}")
