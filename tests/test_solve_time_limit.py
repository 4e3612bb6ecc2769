"""A periodic solve that cannot finish says so within a bounded time (the ``solve_seconds``
limit): shooting stops marching periods, IPOPT stops at its wall time, and the one-line
error names the limit, how to raise it and the way on."""
import pytest

import symcable as sc
from symcable.errors import ConvergenceError
from symcable.limits import OPTIONS, Limits


def test_default_and_option():
    assert Limits().solve_seconds == 600
    assert OPTIONS["solve_seconds"][0] == "--max-solve-seconds"


@pytest.mark.parametrize("kw, says", [
    (dict(steps=1500), "stopped at the time limit of 1 s"),
    (dict(method="collocation", intervals=160), "method='shooting' is cheaper"),
])
def test_a_solve_past_its_limit_says_so(kw, says):
    """seed 001's line needs about 10 s at 1500 shooting steps a period, and 16 s by collocation on 160 intervals (8 times the limit at least):
    under a 1 s limit each stops and says why (the start-up run before the iterations is
    not counted: the error comes within seconds, not the solve's whole time)."""
    with sc.limits(solve_seconds=1), pytest.raises(ConvergenceError) as info:
        sc.solve_periodic("seed001", estimate=False, **kw)
    msg = str(info.value)
    assert says in msg and "solve_seconds" in msg


def test_ipopt_iterations_reach_the_progress_bar(monkeypatch):
    """Collocation with IPOPT counts its iterations into the progress bar (shown on a
    terminal once a solve has run a second; forced on here, into a string)."""
    import io

    import symcable.solvers.periodic_common as pc

    buf, made = io.StringIO(), pc.ProgressBar
    monkeypatch.setattr(pc, "ProgressBar",
                        lambda total, enabled, **kw: made(total, True, stream=buf, **kw))
    res = sc.solve_periodic("seed001", method="collocation", intervals=20, estimate=False)
    text = buf.getvalue()
    assert "(IPOPT)" in text and "iteration" in text
    assert f"{res.stats['iterations'] + 1}/100" in text  # iteration 0 is IPOPT's start
