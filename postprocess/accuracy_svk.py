"""make accuracy's SVK study (svk.md): the model error, St Venant-Kirchhoff against linear, beside the dt and
h errors of the same case, and SVK's observed order in dt, on the paper's mesh."""
from accuracy_common import MESHES, STIFF, SVK_DTS, SVK_WINDOW, T, diff_until, order_row, run_material_cases, wall_line


def svk_study(out, reuse, finest_mesh):
    """Model error (SVK against linear) and SVK's observed order in dt; returns the lines of svk.md."""
    paper = MESHES["paper"][0]
    cases = {}      # key: (scene, T, args)
    # Test 1 on t <= 15: u2_low is pinned at 0 in contact, so compare the top vertex (0, 40) (probe 0)
    for dt in (0.05, 0.0125):
        for model, extra in (("svk", ["-material", "svk"]), ("linear", ["-solver", "activeset"])):
            cases[f"{model}_test1_T15_top_dt{dt}"] = ("test1", SVK_WINDOW, extra + ["-dt", str(dt), "-probes", "0,40"])
    cases["linear_test1_T15_top_refine4_dt0.0125"] = ("test1", SVK_WINDOW, ["-solver", "activeset", "-dt", "0.0125",
                                                                           "-probes", "0,40", "-mesh", MESHES["refine4"][0]])
    for dt in (0.05, 0.0125):
        cases[f"linear_stiff_dt{dt}"] = ("test1", T, STIFF + ["-solver", "activeset", "-dt", str(dt)])
    cases["linear_stiff_refine4_dt0.0125"] = ("test1", T, STIFF + ["-solver", "activeset", "-dt", "0.0125",
                                                                   "-mesh", MESHES["refine4"][0]])
    for dt in SVK_DTS:
        cases[f"svk_stiff_dt{dt}"] = ("test1", T, STIFF + ["-material", "svk", "-dt", str(dt)])
        cases[f"svk_spin_dt{dt}"] = ("spin", 30.0, ["-material", "svk", "-dt", str(dt)])
    runs = run_material_cases(out, reuse, cases, "svk")
    H = {k: r["history"] for k, r in runs.items()}
    top = ("u2_probe0",)

    def row(what, pair, t_end, keys=("u2_low",)):
        mx, l2 = diff_until(*pair, t_end, keys)
        return f"| {what} | {mx:.3g} | {l2:.3g} |"

    md = ["## Model error: SVK against linear, beside the discretisation errors (paper's mesh)", "",
          "| what | max error | L2-in-time error |", "| --- | ---: | ---: |",
          row(f"Test 1 (lambda = mu = 30), t <= {SVK_WINDOW:g}, u2 of the top (0, 40): model, SVK - linear, dt = 0.0125",
              (H["svk_test1_T15_top_dt0.0125"], H["linear_test1_T15_top_dt0.0125"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: model, SVK - linear, dt = 0.05",
              (H["svk_test1_T15_top_dt0.05"], H["linear_test1_T15_top_dt0.05"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: dt error, linear dt = 0.05 - dt = 0.0125",
              (H["linear_test1_T15_top_dt0.05"], H["linear_test1_T15_top_dt0.0125"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: dt error, SVK dt = 0.05 - dt = 0.0125",
              (H["svk_test1_T15_top_dt0.05"], H["svk_test1_T15_top_dt0.0125"]), SVK_WINDOW, top),
          row(f"Test 1, t <= {SVK_WINDOW:g}, top: h error, linear paper mesh - {finest_mesh}, dt = 0.0125",
              (H["linear_test1_T15_top_dt0.0125"], H["linear_test1_T15_top_refine4_dt0.0125"]), SVK_WINDOW, top),
          row(f"stiff Test 1 (lambda = mu = 300), t <= {T:g}: model, SVK - linear, dt = 0.0125",
              (H["svk_stiff_dt0.0125"], H["linear_stiff_dt0.0125"]), T),
          row(f"stiff Test 1, t <= {T:g}: model, SVK - linear, dt = 0.05",
              (H["svk_stiff_dt0.05"], H["linear_stiff_dt0.05"]), T),
          row(f"stiff Test 1, t <= {T:g}: dt error, linear dt = 0.05 - dt = 0.0125",
              (H["linear_stiff_dt0.05"], H["linear_stiff_dt0.0125"]), T),
          row(f"stiff Test 1, t <= {T:g}: dt error, SVK dt = 0.05 - dt = 0.0125",
              (H["svk_stiff_dt0.05"], H["svk_stiff_dt0.0125"]), T),
          row(f"stiff Test 1, t <= {T:g}: h error, linear paper mesh - {finest_mesh}, dt = 0.0125",
              (H["linear_stiff_dt0.0125"], H["linear_stiff_refine4_dt0.0125"]), T),
          "", "## SVK's observed order in dt (self-convergence against dt = 0.0125, paper's mesh)", "",
          "| case | errors at dt = " + ", ".join(map(str, SVK_DTS[:-1])) + " (max over t) | observed order | "
          "L2-in-time errors | observed order (L2) |", "| --- | --- | ---: | --- | ---: |"]
    for label, prefix, t_end, keys in (
            ("spin (no contact, f = 0), T = 30, |u_low| (both components)", "svk_spin", 30.0, ("u1_low", "u2_low")),
            ("stiff Test 1 (contact from t = 8.95 to 14.2 and from 31.75), T = 40, u2_low", "svk_stiff", T, ("u2_low",))):
        md.append(order_row(label, H, prefix, t_end, keys))
    md += ["", wall_line("SVK", runs)]
    return md, H
