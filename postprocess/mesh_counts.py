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


if __name__ == "__main__":
    for path in sys.argv[1:]:
        v, t, c, n, d = msh22_counts(path)
        clamped = f", {d} on Gamma_D (label 3)" if d else ""
        print(f"{path}: {v} vertices, {t} triangles, {c} segments on Gamma_C (label 1), {n} on Gamma_N (label 2){clamped}")
