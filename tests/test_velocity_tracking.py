"""The section 4 scenario of paper 003 on the Barrett WAM: SC crosses the boundary, baselines do not."""

import numpy as np
import pytest

from redkin.velocity import (
    AdaptiveDampedLeastSquares,
    DampedLeastSquares,
    Pseudoinverse,
    SingularityConsistent,
    simulate,
)
from tests.support.velocity_wam import EPS, Q0, TWIST

# Paper 003 section 4 (its start, twist and eps in tests.support.velocity_wam).
DURATION, DT = 4.0, 5e-3


@pytest.fixture(scope="module")
def runs(wam, wam_factor):
    methods = {
        "sc": SingularityConsistent(eps=EPS),
        "pinv": Pseudoinverse(),
        "dls": DampedLeastSquares(damping=0.05),
        "dls-adaptive": AdaptiveDampedLeastSquares(threshold=0.05, max_damping=0.05),
    }
    return {name: simulate(wam, Q0, TWIST, DURATION, m, dt=DT, index=wam_factor.index) for name, m in methods.items()}


def test_velocity_sc_crosses_once_and_realises_command_outside_region(runs):
    run = runs["sc"]
    d_e = run.index
    assert d_e[0] < -EPS  # the paper's threshold leaves the start outside the region (|D_e| = 0.19)
    assert np.count_nonzero(np.diff(np.sign(d_e)) != 0) == 1
    assert d_e[-1] > EPS  # through and out on the other side
    crossed = np.cumsum(np.r_[0, np.diff(np.sign(d_e)) != 0]) > 0
    intended = np.where(crossed[:, None], TWIST * [-1, -1, -1, 1, 1, 1], TWIST)  # translation reversed after
    outside = np.abs(d_e) > EPS
    assert outside.sum() > 100 and (~outside).sum() > 20
    assert np.abs(run.realised[outside] - intended[outside]).max() < 1e-9
    assert np.abs(run.realised - run.target).max() < 1e-9
    assert run.realised[:, 4].min() >= -1e-12  # rotation about +y never reverses
    # Inside the region the translation stays along x (direction exact).
    assert np.abs(run.realised[:, 1:3]).max() < 1e-9 and np.abs(run.realised[:, [3, 5]]).max() < 1e-9
    speed = np.linalg.norm(run.joint_velocity, axis=1)
    assert speed.max() < 5.0 and speed[np.argmin(np.abs(d_e))] > 0.1


def test_velocity_sc_controller_run_equals_the_exact_cofactor_run(runs, wam):
    # the default (lean) method steps through the controller; lean=False takes [003 eqs. 15-22] literally
    exact = simulate(wam, Q0, TWIST, DURATION, SingularityConsistent(eps=EPS, lean=False), dt=DT)
    np.testing.assert_allclose(runs["sc"].q, exact.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(runs["sc"].joint_velocity, exact.joint_velocity, rtol=0, atol=1e-8)


def test_velocity_sc_path_reverses_along_x(runs):
    run = runs["sc"]
    x = run.position[:, 0]
    turn = np.argmax(x)
    assert 0 < turn < len(x) - 1 and x[-1] < x[turn] - 0.1
    assert np.ptp(run.position[:, 1]) < 1e-6 and np.ptp(run.position[:, 2]) < 1e-6  # a straight line


def test_velocity_pinv_is_exact_until_it_explodes(runs, wam):
    run, sc = runs["pinv"], runs["sc"]
    sigma = np.linalg.svd(wam.jacobian(run.q), compute_uv=False)[:, -1]
    regular = sigma > 0.05
    assert np.abs(run.realised[regular] - TWIST).max() < 1e-9
    speed = np.linalg.norm(run.joint_velocity, axis=1)
    assert speed.max() > 10 * np.linalg.norm(sc.joint_velocity, axis=1).max()


def test_velocity_dls_bounded_but_stalls(runs, wam):
    for name, bound in (("dls", np.linalg.norm(TWIST) / (2 * 0.05)),
                        ("dls-adaptive", np.linalg.norm(TWIST) / (2 * 0.05))):
        run = runs[name]
        speed = np.linalg.norm(run.joint_velocity, axis=1)
        jac = wam.jacobian(run.q)
        sigma = np.linalg.svd(jac, compute_uv=False)[:, -1]
        assert np.all(speed <= np.maximum(bound, np.linalg.norm(TWIST) / sigma) * (1 + 1e-9))
        assert np.all(run.index < 0)  # never crosses the boundary
        error = np.linalg.norm(run.realised - TWIST, axis=1) / np.linalg.norm(TWIST)
        assert error[-1] > 0.5  # stalled at the boundary: most of the command is lost
    assert np.all(np.linalg.norm(runs["dls"].joint_velocity, axis=1) <= np.linalg.norm(TWIST) / 0.1 * (1 + 1e-9))


def test_velocity_rk4_converges_and_closed_loop_removes_drift(wam):
    method = SingularityConsistent(eps=EPS)
    coarse = simulate(wam, Q0, TWIST, 0.5, method, dt=0.05)
    fine = simulate(wam, Q0, TWIST, 0.5, method, dt=0.025)
    exact_x = wam.fk(Q0)[0, 3] + TWIST[0] * 0.5
    err_c, err_f = abs(coarse.position[-1, 0] - exact_x), abs(fine.position[-1, 0] - exact_x)
    assert err_f < err_c / 8 or err_f < 1e-12  # fourth order
    dls_open = simulate(wam, Q0, TWIST, 0.5, DampedLeastSquares(0.05), dt=0.01)
    dls_closed = simulate(wam, Q0, TWIST, 0.5, DampedLeastSquares(0.05), dt=0.01, gain=20.0)
    target = wam.fk(Q0)[:3, 3] + 0.5 * TWIST[:3]
    assert np.linalg.norm(dls_closed.position[-1] - target) < 0.2 * np.linalg.norm(dls_open.position[-1] - target)


def test_velocity_simulate_bad_input(wam):
    with pytest.raises(ValueError, match="q0"):
        simulate(wam, np.zeros(6), TWIST, 1.0, Pseudoinverse())
    with pytest.raises(ValueError, match="duration"):
        simulate(wam, Q0, TWIST, 0.0, Pseudoinverse())
    with pytest.raises(ValueError, match="twist"):
        simulate(wam, Q0, TWIST[:5], 1.0, Pseudoinverse())


@pytest.mark.parametrize("duration, dt", [(1e308, 0.005), (1e6, 1e-300)])
def test_a_step_count_past_any_size_is_refused_before_it_overflows(wam, duration, dt):
    """duration / dt overflows a float-to-int conversion (1e308 / 0.005 = inf): a SizeLimitError, not OverflowError."""
    from redkin.errors import SizeLimitError

    with pytest.raises(SizeLimitError, match="RK4 steps"):
        simulate(wam, Q0, TWIST, duration, Pseudoinverse(), dt=dt)
