"""Pole regions beyond the half-plane, and discrete-time observers."""

import numpy as np
import pytest
import control as ct

import controlext as cx
from conftest import error_system, grid_hinf
import controlext.synthesis.lmi as lmi

FAST = {'random_starts': 4}          # fewer refinement starts: speed only


def second_order():
    return ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]],
                 0)


def scalar():
    return ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)


def gi_plant():
    return ct.ss([[-1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
                 [[1.0, 0.0], [1.0, 0.0]], np.zeros((2, 1)))


GI_BW = np.array([[0.5, 0.2], [0.0, 1.0]])


def in_region(poles, spec):
    """Membership written out from each region's definition (independent
    of Region.margins)."""
    ok = np.ones(len(poles), dtype=bool)
    for kind, *args in spec:
        if kind == 'half':
            ok &= poles.real <= -args[0] + 1e-6
        elif kind == 'disk':
            ok &= np.abs(poles - args[1]) <= args[0] + 1e-6
        elif kind == 'sector':
            th = np.arccos(args[0])
            ok &= np.abs(poles.imag) <= -poles.real * np.tan(th) + 1e-6
    return bool(np.all(ok))


REGIONS = [
    pytest.param(cx.Disk(3.0, center=-4.0), [('disk', 3.0, -4.0)],
                 id='disk'),
    pytest.param(cx.Sector(0.7), [('sector', 0.7)], id='sector'),
    pytest.param(cx.HalfPlane(1.0) & cx.Sector(0.7),
                 [('half', 1.0), ('sector', 0.7)], id='half&sector'),
    pytest.param(cx.HalfPlane(1.0) & cx.Disk(4.0),
                 [('half', 1.0), ('disk', 4.0, 0.0)], id='half&disk'),
]


@pytest.mark.parametrize('region, spec', REGIONS)
@pytest.mark.parametrize('kind', ['luenberger', 'coupled', 'gi'])
def test_continuous_poles_in_region(region, spec, kind):
    if kind == 'luenberger':
        obs = cx.hinf_observer(second_order(), region=region,
                               refine_options=FAST)
    elif kind == 'coupled':
        obs = cx.coupled_observer(second_order(), region=region,
                                  refine_options=FAST)
    else:
        obs = cx.gi_observer(gi_plant(), GI_BW, region=region,
                             refine_options=FAST)
    assert in_region(np.linalg.eigvals(obs.A), spec)
    assert np.isfinite(obs.hinf)
    assert obs.report.region is region


DISCRETE = [
    pytest.param(None, 1.0, id='decay'),
    pytest.param(cx.Disk(0.9), None, id='disk'),
    pytest.param(cx.Disk(0.3, center=0.5) & cx.Disk(0.95), None,
                 id='disk&disk'),
]


@pytest.mark.parametrize('region, decay', DISCRETE)
@pytest.mark.parametrize('kind', ['luenberger', 'coupled', 'gi'])
def test_discrete_poles_in_region(region, decay, kind):
    dt = 0.05
    if kind == 'gi':
        plant = ct.c2d(gi_plant(), dt)
        obs = cx.gi_observer(plant, GI_BW, decay=decay, region=region,
                             refine_options=FAST)
    else:
        plant = ct.c2d(second_order(), dt)
        factory = cx.hinf_observer if kind == 'luenberger' \
            else cx.coupled_observer
        obs = factory(plant, decay=decay, region=region,
                      refine_options=FAST)
    assert obs.dt == dt
    z = np.linalg.eigvals(obs.A)
    if decay is not None:
        assert np.max(np.abs(z)) <= np.exp(-decay * dt) + 1e-9
        assert obs.decay >= decay - 1e-5
    else:
        assert region.contains(z, tol=1e-7)
    noise = {}
    if kind == 'gi':            # Bw (I − Π), Dw = I − Π, Π = I − C C⁺
        keep = plant.C @ np.linalg.pinv(plant.C)
        noise = dict(Bw=np.asarray(GI_BW) @ keep, Dw=keep)
    Acl, Bcl, Ccl = error_system(obs.plant, obs.G, obs.copies, **noise)
    np.testing.assert_allclose(np.linalg.eigvals(Acl)[np.argsort(
        np.linalg.eigvals(Acl).real)].real, np.sort(z.real), atol=1e-9)
    assert grid_hinf(Acl, Bcl, Ccl, dt) == pytest.approx(obs.hinf, rel=1e-6,
                                                         abs=1e-9)


@pytest.mark.parametrize('plant, sigma', [(scalar(), 2.5),
                                          (second_order(), 1.0)],
                         ids=['scalar', 'second-order'])
def test_discrete_paper_plants_coupled_not_worse(plant, sigma):
    pd = ct.c2d(plant, 0.05)                     # zero-order hold
    luen = cx.hinf_observer(pd, decay=sigma)
    pair = cx.coupled_observer(pd, decay=sigma)
    assert pair.hinf <= luen.hinf * (1 + 1e-9)
    assert np.max(np.abs(ct.poles(pair))) <= np.exp(-sigma * 0.05) + 1e-9


def test_discrete_optimum_approaches_continuous():
    """Scalar plant, σ = 2.5: the continuous optimum is k0 = σ + a with
    γ = (σ + a)/σ = 0.8 (closed form); the ZOH designs approach it."""
    gaps = []
    for dt in (0.2, 0.05, 0.01):
        obs = cx.hinf_observer(ct.c2d(scalar(), dt), decay=2.5,
                               refine_options=FAST)
        gaps.append(abs(obs.hinf - 0.8))
    assert gaps[0] > gaps[1] > gaps[2]
    assert gaps[2] < 0.01


def test_region_domain_mismatch():
    pd = ct.c2d(second_order(), 0.1)
    with pytest.raises(cx.RegionError, match='continuous-time region but '
                                             'the plant is discrete-time'):
        cx.hinf_observer(pd, region=cx.HalfPlane(1.0))
    with pytest.raises(cx.RegionError, match='discrete-time region but the '
                                             'plant is continuous-time'):
        cx.coupled_observer(second_order(),
                            region=cx.Disk(0.9, domain='discrete'))
    with pytest.raises(cx.ParameterError, match='cannot intersect'):
        cx.HalfPlane(1.0) & cx.Disk(0.9, domain='discrete')


def test_unobservable_mode_outside_disk_is_decided_before_solving(
        monkeypatch):
    monkeypatch.setattr(lmi.cp.Problem, 'solve',
                        lambda *a, **k: pytest.fail('solver ran'))
    plant = ct.ss([[-2.0, 0.0], [0.0, -0.5]], [[1.0], [1.0]], [[1.0, 0.0]],
                  0)
    with pytest.raises(cx.RegionError, match=r'mode at s = -0\.5 is '
                                             r'unobservable'):
        cx.hinf_observer(plant, region=cx.Disk(1.0, center=-3.0))
    with pytest.raises(cx.RegionError, match='unobservable'):
        cx.coupled_observer(plant, region=cx.Disk(1.0, center=-3.0))


@pytest.mark.parametrize('region, dt', [
    (cx.HalfPlane(2.0) & cx.Disk(1.0), 0),         # Re s <= -2, |s| <= 1
    (cx.Disk(0.5, center=2.0), 0),                  # all in Re s > 0
    (cx.Disk(0.2, center=1.5, domain='discrete'), 0.1),   # outside |z| < 1
    (cx.Disk(0.3, center=0.5) & cx.Disk(0.2, center=-0.5), 0.1),
], ids=['halfplane&disk', 'rhp-disk', 'outside-unit-circle', 'apart'])
def test_empty_region_is_refused_from_its_geometry(monkeypatch, region, dt):
    """An LMI region is convex and symmetric about the real axis: it has a
    stable point if and only if it has a stable real point, which the
    real-axis search decides before any solve."""
    monkeypatch.setattr(lmi.cp.Problem, 'solve',
                        lambda *a, **k: pytest.fail('solver ran'))
    plant = second_order() if not dt else ct.c2d(second_order(), dt)
    with pytest.raises(cx.RegionError, match='has no point'):
        cx.hinf_observer(plant, region=region)


def test_nonempty_regions_are_not_refused():
    # touching only in the interior of the left half-plane
    region = cx.Disk(1.0, center=-3.0) & cx.Disk(1.0, center=-1.5)
    a, b = region.stable_interval()
    assert a == pytest.approx(-2.5, abs=1e-6) and \
        b == pytest.approx(-2.0, abs=1e-6)
    z = cx.Disk(0.304, center=-0.08, domain='discrete').stable_interval(1)
    assert z[0] == pytest.approx(-0.384, abs=1e-6)


@pytest.mark.parametrize('make, match', [
    (lambda: cx.Disk(-1.0), 'radius must be > 0'),
    (lambda: cx.Disk(1.0, center=np.nan), 'center must be finite'),
    (lambda: cx.Sector(1.5), r'damping must lie in \[0, 1\)'),
    (lambda: cx.Disk(1.0, domain='z'), "domain must be"),
])
def test_bad_regions(make, match):
    with pytest.raises(cx.ParameterError, match=match):
        make()


def test_region_data_for_plots():
    region = cx.HalfPlane(1.0) & cx.Sector(0.5)
    pts = np.array([[-2 + 0.5j, -0.5 + 0j], [-2 + 5j, -3 - 1j]])
    np.testing.assert_array_equal(region.inside(pts),
                                  [[True, False], [False, True]])
    curves = region.boundary((-5, 1, -4, 4), num=50)
    assert len(curves) == 3                      # one line, two rays
    line = curves[0]
    np.testing.assert_allclose(line.real, -1.0)
    disk = cx.Disk(2.0, center=-3.0).boundary((-6, 0, -3, 3), num=64)[0]
    np.testing.assert_allclose(np.abs(disk + 3.0), 2.0)
