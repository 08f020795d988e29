"""Luenberger rows of Li & Sanfelice, Section IV (DESIGN.md §5), checked
through python-control's own tools on the observer objects."""

import numpy as np
import pytest
import control as ct
import control.matlab as matlab

import controlext as cx

BIAS = 0.3     # measurement bias m of Section IV-A


def test_scalar_luenberger_rows(scalar_plant):
    obs = cx.LuenbergerObserver(scalar_plant, [[2.0]])
    gamma, _ = ct.linfnorm(obs)
    assert gamma == pytest.approx(0.8, abs=5e-2)          # printed "0.8"
    assert gamma == pytest.approx(2.0 / 2.5, rel=1e-9)    # k0 / (k0 - a)
    assert ct.poles(obs) == pytest.approx([-2.5])
    assert float(ct.dcgain(obs)) * BIAS == pytest.approx(0.24, abs=5e-3)
    resp = ct.step_response(obs, T=np.linspace(0, 10, 1001))
    assert resp.outputs[-1] * BIAS == pytest.approx(0.24, abs=5e-3)


@pytest.mark.parametrize('K0, gamma, decay', [
    ([[2.0], [5.0]], 0.4859, 1.0),
    ([[0.2852], [0.3574]], 0.2850, 1.0),
], ids=['K0=[2;5]', 'K0=optimised'])
def test_second_order_luenberger_rows(second_order_plant, K0, gamma, decay):
    obs = cx.LuenbergerObserver(second_order_plant, K0)
    assert ct.linfnorm(obs)[0] == pytest.approx(gamma, rel=1e-3)
    assert ct.norm(obs, 'inf') == pytest.approx(gamma, rel=1e-3)
    assert cx.hinfnorm(obs)[0] == pytest.approx(gamma, rel=1e-3)
    assert -max(ct.poles(obs).real) == pytest.approx(decay, abs=5e-4)
    assert obs.hinf == pytest.approx(gamma, rel=1e-3)


def test_matlab_tools_on_observer(second_order_plant):
    obs = cx.LuenbergerObserver(second_order_plant, [[2.0], [5.0]])
    # error poles: eig(A - K0 C) computed independently
    A, C = second_order_plant.A, second_order_plant.C
    expected = np.linalg.eigvals(A - np.array([[2.0], [5.0]]) @ C)
    assert np.sort_complex(matlab.pole(obs)) == \
        pytest.approx(np.sort_complex(expected))
    yout, t = matlab.step(obs, T=np.linspace(0, 20, 2001))
    # final value of the step response is the DC gain -Cz Acl^-1 Bcl
    dc = -obs.C @ np.linalg.solve(obs.A, obs.B)
    assert np.shape(yout) == (2001, 2, 1)
    assert yout[-1, :, 0] == pytest.approx(dc[:, 0], rel=1e-4)


def test_bode_and_forced_response(second_order_plant):
    import matplotlib
    matplotlib.use('Agg')
    obs = cx.LuenbergerObserver(second_order_plant, [[2.0], [5.0]])
    cplt = ct.bode_plot(obs, omega=np.logspace(-2, 2, 200), plot_phase=False)
    mags = np.concatenate([ln.get_ydata() for ln in cplt.lines.ravel()[0]])
    # the plotted peak over all outputs is bounded by the H∞ norm
    assert np.max(mags) <= 0.4859 * (1 + 1e-3)
    T = np.linspace(0, 20, 2001)
    resp = ct.forced_response(obs, T, BIAS * np.ones_like(T))
    assert resp.outputs[:, -1] == pytest.approx(
        BIAS * np.ravel(ct.dcgain(obs)), rel=1e-3)
    import matplotlib.pyplot as plt
    plt.close('all')
