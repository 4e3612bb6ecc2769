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


def test_one_deadline_for_the_whole_call():
    """``call_deadline``: every periodic solve inside shares one deadline, solve_seconds from
    the block's start (a solve_periodic call's retries, fallbacks and error estimate each
    had their own before: one call ran 936 s under a 120 s limit); nested blocks keep the
    outer one; outside, a solve has the whole limit."""
    import time

    from symcable.limits import call_deadline, past_deadline, remaining_seconds
    with sc.limits(solve_seconds=2):
        assert remaining_seconds() == 2.0 and not past_deadline()
        with call_deadline():
            left = remaining_seconds()
            assert 1.5 < left <= 2.0
            with call_deadline():  # nested: the outer deadline holds
                time.sleep(0.05)
                assert remaining_seconds() < left
        assert remaining_seconds() == 2.0


@pytest.mark.parametrize("kw", [{}, {"method": "collocation", "intervals": 20}])
def test_a_solve_inside_a_spent_deadline_stops_at_once(kw):
    """A periodic solve started after the call's deadline has passed (as a retry, a
    continuation or the estimate's second solve would be) does not iterate on: shooting
    stops marching, IPOPT at its first iteration (its callback; the solver, built once for
    every call, keeps max_wall_time at the limit), each saying so."""
    import time

    from symcable.limits import call_deadline
    with sc.limits(solve_seconds=1), call_deadline():
        time.sleep(1.05)
        with pytest.raises(ConvergenceError) as info:
            sc.solve_periodic("seed001", estimate=False, **kw)
    assert "time limit" in str(info.value) and "solve_seconds" in str(info.value)


def test_shooting_starts_no_monodromy_that_would_pass_the_limit():
    """A period with its monodromy is one long call (tens of plain periods in the virtual
    machine): shooting does not start one that would end past the deadline, judged by the
    last one's time, else MONODROMY_PERIODS plain periods. (Before, a fuzz scene stopped
    for its 180 s limit at 193 s.)"""
    import time

    from symcable.solvers import shooting_mech as sm
    sh = sm._Shots(pm=None, march=None, period=1.0, p=None, su=None, z0=None, nz=0, n_x=0,
                   step_tol=1e-8, deadline=time.perf_counter() + 100.0)
    sh.t_plain = 1.0  # s: a first monodromy taken as 30 s, inside the 100 s left
    assert not sh.late() and not sh.late(monodromy=True)
    sh.t_jac = 200.0  # s: the last one took longer than what is left
    assert sh.late(monodromy=True) and sh.timed_out and sh.late()  # and stays stopped
