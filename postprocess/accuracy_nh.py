"""make accuracy's Neo-Hookean study (nh.md): the model differences Neo-Hookean - linear and Neo-Hookean - SVK,
and its observed order in dt, on the paper's mesh."""
import os

from accuracy_common import SVK_DTS, SVK_WINDOW, T, diff_until, model_cases, order_row, run_material_cases, wall_line
from history import contact_intervals


def nh_study(out, reuse, have=None):
    """The Neo-Hookean body (-material neohookean) on the paper's mesh: the model differences
    Neo-Hookean - linear and Neo-Hookean - SVK (at the same dt and mesh) on the cases of svk_study,
    where SVK does not collapse, and on Test 1 to T = 40 with the paper's body (which the Neo-Hookean
    body runs through, linear beside it); its observed order in dt (self-convergence against
    dt = 0.0125) on the spin scene, the stiff Test 1 and Test 1. `have`: svk_study's histories (not run
    again). Returns the lines of nh.md."""
    nh = ["-material", "neohookean"]
    cases = model_cases("nh", nh, SVK_DTS)
    cases.update(model_cases("svk", ["-material", "svk"], (0.05, 0.0125)))
    cases.update(model_cases("linear", ["-solver", "activeset"], (0.05, 0.0125)))
    for dt in SVK_DTS:
        cases[f"nh_test1_dt{dt}"] = ("test1", T, nh + ["-dt", str(dt), "-probes", "0,40"])
        cases[f"nh_spin_dt{dt}"] = ("spin", 30.0, nh + ["-dt", str(dt)])
    for dt in (0.05, 0.0125):
        cases[f"linear_test1_dt{dt}"] = ("test1", T, ["-solver", "activeset", "-dt", str(dt), "-probes", "0,40"])
    runs = run_material_cases(out, reuse, cases, "neohookean", have)
    H = {k: r["history"] for k, r in runs.items()}
    top = ("u2_probe0",)
    rows = []
    for label, case, t_end, keys in (
            (f"Test 1 (lambda = mu = 30), t <= {SVK_WINDOW:g}, u2 of the top (0, 40)", "test1_T15_top", SVK_WINDOW, top),
            (f"Test 1 (lambda = mu = 30), t <= {T:g}, u2_low (SVK collapses at 16.8)", "test1", T, ("u2_low",)),
            (f"Test 1 (lambda = mu = 30), t <= {T:g}, u2 of the top (0, 40)", "test1", T, top),
            (f"stiff Test 1 (lambda = mu = 300), t <= {T:g}, u2_low", "stiff", T, ("u2_low",))):
        pairs = [(f"model, NH - {b}, dt = {dt:g}", f"nh_{case}_dt{dt}", f"{b}_{case}_dt{dt}")
                 for b in ("linear", "svk") for dt in (0.0125, 0.05)]
        pairs += [(f"dt error, {a} dt = 0.05 - dt = 0.0125", f"{a}_{case}_dt0.05", f"{a}_{case}_dt0.0125")
                  for a in ("nh", "linear")]
        for what, x, y in pairs:
            if x in H and y in H:        # (no SVK on Test 1 to T = 40: it collapses at t = 16.8)
                mx, l2 = diff_until(H[x], H[y], t_end, keys)
                rows.append(f"| {label} | {what.replace('nh ', 'NH ')} | {mx:.3g} | {l2:.3g} |")
    md = ["## Model differences: Neo-Hookean (NH) against linear and against SVK (paper's mesh)", "",
          "| case | what | max difference | L2-in-time difference |", "| --- | --- | ---: | ---: |"] + rows
    md += ["", "## Neo-Hookean's observed order in dt (self-convergence against dt = 0.0125, paper's mesh)", "",
           "| case | errors at dt = " + ", ".join(map(str, SVK_DTS[:-1])) + " (max over t) | observed order | "
           "L2-in-time errors | observed order (L2) |", "| --- | --- | ---: | --- | ---: |"]
    for label, prefix, t_end, keys in (
            ("spin (no contact, f = 0), T = 30, |u_low| (both components)", "nh_spin", 30.0, ("u1_low", "u2_low")),
            ("stiff Test 1 (lambda = mu = 300), T = 40, u2_low", "nh_stiff", T, ("u2_low",)),
            ("Test 1 (lambda = mu = 30), T = 40, u2_low", "nh_test1", T, ("u2_low",)),
            ("Test 1 (lambda = mu = 30), T = 40, u2 of the top (0, 40)", "nh_test1", T, top)):
        md.append(order_row(label, H, prefix, t_end, keys))
    intervals = {k: contact_intervals(H[k]["t"], H[k]["active_nodes"] > 0) for k in ("nh_test1_dt0.0125", "linear_test1_dt0.0125",
                                                                                    "nh_stiff_dt0.0125", "linear_stiff_dt0.0125")}
    md += ["", "Contact intervals at dt = 0.0125: " + "; ".join(
        f"{k.replace('_dt0.0125', '')} " + ", ".join(f"[{a:g}, {b:g}]" for a, b in v) for k, v in intervals.items()),
        "", wall_line("Neo-Hookean", runs)]
    with open(os.path.join(out, "nh.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    return md
