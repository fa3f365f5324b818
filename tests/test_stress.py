"""The fast subset of `make stress`: hard cases pass the criteria of make stress (postprocess/stress_cases.py).
An SVK case may stop at an element collapse (exit 4); that passes only as the clean
break those criteria accept (one "newton failed at step N, t = X: reason" line, history
intact), and the subset pins which case breaks and when."""
import pytest

from stress_cases import CASES, FAST, evaluate, outcome

# what each SVK case of the subset does on its short horizon (docs/stress.md)
EXPECTED_BREAK_T = {"svk v0y -5": 0.95}


@pytest.mark.parametrize("name", list(FAST))
def test_hard_case_stays_stable(runs, run_status, name):
    returncode, stderr = run_status[f"stress: {name}"]
    metrics, failures = evaluate(name, runs[f"stress: {name}"], returncode, stderr)
    assert not failures, f"{name}: " + "; ".join(failures)
    assert metrics["steps"] > 0
    if name in EXPECTED_BREAK_T:
        assert metrics["broke"] and abs(metrics["broke"][1] - EXPECTED_BREAK_T[name]) < 1e-9, outcome(metrics, failures)
    else:
        assert metrics["broke"] is None and returncode == 0, outcome(metrics, failures)


def test_svk_break_is_told_apart():
    """Only one clean 'newton failed at step N, t = X' line of an SVK case counts as a break
    (its reason is reported); two lines, or another error, fail."""
    line = ("error: newton failed at step 19, t = 0.95: triangle 1798 inverted (det F = -0.13461 at (-1.74311, "
            "0.076106)); the retry from u^n with damped updates: no convergence in 100 Newton iterations; "
            "history.csv keeps every step before it\n")
    from stress_cases import svk_break
    assert svk_break(line)[:2] == (19, 0.95)
    assert svk_break(line + line) is None                                   # not one line
    assert svk_break(line.replace("triangle 1798 inverted (det F = -0.13461 at (-1.74311, 0.076106))",
                                  "no convergence in 25 Newton iterations"))[2].startswith("no convergence")
    assert svk_break("error: step 7 (t = 0.35) gave a non-finite solution; history.csv keeps every step before it") is None
    assert "svk" in CASES["svk v0y -5"][1] and "svk" not in CASES["v0y -5"][1]


def test_neohookean_rows_and_their_bound(tmp_path):
    """The Neo-Hookean rows are the cases where SVK collapses; their bound is the round-off one
    (a one-step rise of the modified energy above 1e-12 relative fails them, not an svk row)
    and min_J > 0 on every step."""
    from stress_cases import NEOHOOKEAN, NH_ROUNDOFF, SVK
    assert set(NEOHOOKEAN) <= set(SVK) and not any(n.startswith("f = 0") for n in NEOHOOKEAN)
    assert all(CASES[f"neohookean {n}"][2] == "roundoff" and "neohookean" in CASES[f"neohookean {n}"][1] for n in NEOHOOKEAN)
    columns = ["step", "t", "energy", "modified_energy", "active_nodes", "max_penetration", "qp_solved", "solver_status", "min_J"]

    def judged(name, rise, min_j=0.5):
        out = tmp_path / f"{name}_{rise}_{min_j}".replace(" ", "_")
        out.mkdir()
        (out / "parameters.txt").write_text("-T 0.1\n-dt 0.05\n")
        (out / "history.csv").write_text(",".join(columns) + "\n" + "".join(
            f"{k},{0.05 * k},1,{500 + (rise * 500 if k == 2 else 0)},0,0,0,0,{min_j if k else 1}\n" for k in range(3)))
        return evaluate(name, str(out), 0, "")[1]
    assert judged("neohookean v0y -5", 0.5 * NH_ROUNDOFF) == []
    assert any("rises" in f for f in judged("neohookean v0y -5", 2 * NH_ROUNDOFF))
    assert judged("svk v0y -5", 2 * NH_ROUNDOFF) == []                 # SVK rows keep the 1e-8 bound
    assert any("min_J" in f for f in judged("neohookean v0y -5", 0, min_j=-0.1))


def test_guard_stop_is_told_apart():
    """A "guarded" case (explicit Verlet near its critical step) may end at the energy guard: one line
    "error: the modified energy grew from A to B by step N (t = X), G% of ..." (exit 4); any other
    line, or two, is a failure."""
    from history import guard_stop
    line = ("error: the modified energy grew from 502.362 to 618.219 by step 1165 (t = 20.97), 10.6% of the run's energy "
            "1096.64, on a fixed foundation, where more than 10% is no valid result: explicit Verlet is stable only below "
            "its critical step 0.0206705 (-dt 0.018 is 87.1% of it), ...; history.csv keeps every step up to this one\n")
    assert guard_stop(line) == (1165, 20.97, 10.6)
    assert guard_stop(line + line) is None
    assert guard_stop("error: step 7 (t = 0.35) gave a non-finite solution; history.csv keeps every step before it") is None
    assert CASES["verlet penalty at 0.9 dt_c"][2] == "guarded"


def test_through_stop_is_told_apart():
    """A case of THROUGH (v0y -10: the disk squashed past Gamma_C) may end at the stop of the body through the
    foundation: one line "error: the body passed through the foundation at step N (t = X): ..., is D below it,
    P% of the body's size ..." (exit 4); any other line, or two, is a failure."""
    from stress_cases import THROUGH
    from history import through_stop
    line = ("error: the body passed through the foundation at step 43 (t = 2.15): its boundary vertex (-18.4776, 12.3463), "
            "not on Gamma_C (label 1), is 2.03314 below it, 5.08% of the body's size 40, beyond the 5% a run accepts (only "
            "Gamma_C is held by (10)); Gamma_C presses on the foundation (49 of its 49 vertices), ...; history.csv keeps every "
            "step up to this one\n")
    assert through_stop(line) == (43, 2.15, 2.03314, 5.08)
    assert through_stop(line + line) is None
    assert through_stop("error: the modified energy grew from 502.362 to 618.219 by step 1165 (t = 20.97), 10.6% of ...") is None
    assert THROUGH == {"v0y -10", "neohookean soft lambda = mu = 3", "ball soft Neo-Hookean lambda = mu = 3"}
