"""Water exact solutions (partmesh.compare.exact.water, .stoker_ritter): linear waves from rest against d'Alembert,
Poisson's formula, adaptive Fourier quadrature, their own transforms and conservation;
the dam break against its jump conditions, Riemann invariant and conservation."""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import IntegrationWarning, quad, simpson
from scipy.special import dawsn, j0

from partmesh.compare.exact import (
    CRATER_GAUGES,
    PRINS_GAUGES,
    Crater,
    Gaussian,
    Mound,
    dam_break,
    dam_break_profile,
    dam_break_state,
    dispersion,
    group_velocity,
    linear_wave_fields,
    linear_waves,
)
from partmesh.compare.schema import parameters, validate

G = 9.81
PRINS = Mound(0.12, 0.61)  # Prins (1958): Q = 0.12 m, L = 0.61 m, d = 0.7 m
PRINS_DEPTH = 0.7
CRATER = Crater(0.3, 0.6)  # D_c = 0.3 m, R_c = 0.6 m, d = 1 m
SHAPES = {"mound": PRINS, "crater": CRATER, "gaussian": Gaussian(0.1, 0.8)}


def even(shape, s):
    return shape.profile(np.abs(s))


# ------------------------------------------------------------------------------------------------------------------
# transforms


def _planar_definition(shape, k, edge):
    return 2.0 * quad(lambda x: float(shape.profile(x)), 0.0, edge, weight="cos", wvar=k,
                      epsabs=0.0, epsrel=1e-12, limit=400)[0]


def _radial_definition(shape, k, edge):
    """Gauss-Legendre, 8 panels of 40 nodes on [0, edge]: exact to round-off for these smooth integrands
    (adaptive quadrature stalls on the crater's cancellation at small k)."""
    nodes, weights = np.polynomial.legendre.leggauss(40)
    ends = np.linspace(0.0, edge, 9)
    half = 0.5 * np.diff(ends)[:, None]
    r = (0.5 * (ends[1:] + ends[:-1])[:, None] + half * nodes).ravel()
    return float(np.sum((half * weights).ravel() * shape.profile(r, "radial") * j0(k * r) * r))


@pytest.mark.parametrize("name", ["mound", "crater"])
@pytest.mark.parametrize("k", [0.5, 3.0, 17.0, 60.0])
def test_closed_form_transforms_equal_quadrature_of_their_definitions(name, k):
    """F(k) = 2 int_0^inf eta0 cos(kx) dx and G(k) = int_0^inf eta0 J0(kr) r dr by adaptive quadrature."""
    shape = SHAPES[name]
    edge = shape.length
    assert shape.transform(k, "planar") == pytest.approx(_planar_definition(shape, k, edge), rel=1e-10)
    assert shape.transform(k, "radial") == pytest.approx(_radial_definition(shape, k, edge), rel=1e-10)


def test_transforms_at_zero_wavenumber_are_the_volumes():
    """F(0) = int eta0 dx over the line, 2 pi G(0) = int eta0 dA; the radial crater is volume-neutral."""
    assert PRINS.transform(0.0) == pytest.approx(2 * 0.12 * 0.61, rel=1e-15)
    assert PRINS.transform(0.0, "radial") == pytest.approx(0.12 * 0.61**2 / 2, rel=1e-15)
    assert CRATER.transform(0.0) == pytest.approx(-2 * 0.3 * 0.6 / 3, rel=1e-15)
    assert CRATER.transform(np.array([0.0, 1e-6]), "radial") == pytest.approx([0.0, 0.0], abs=1e-14)
    gauss = Gaussian(0.2, 1.5)
    assert gauss.transform(0.0) == pytest.approx(0.2 * 1.5 * math.sqrt(math.pi), rel=1e-15)
    assert gauss.transform(0.0, "radial") == pytest.approx(0.2 * 1.5**2 / 2, rel=1e-15)


@pytest.mark.parametrize("name", ["mound", "crater"])
@pytest.mark.parametrize("geometry", ["planar", "radial"])
def test_edge_form_is_the_transform(name, geometry):
    """The tail of the quadrature relies on transform(k) = Re sum_e a_e(k) exp(i k e) exactly
    (from the smallest cut-off, 4/size, on)."""
    shape = SHAPES[name]
    k = np.geomspace(4.0 / shape.length, 3e4, 200)
    edge_form = sum((e.amplitude(k) * np.exp(1j * k * e.position)).real for e in shape.edges(geometry))
    scale = np.abs(shape.transform(k, geometry)).max()
    np.testing.assert_allclose(edge_form, shape.transform(k, geometry), rtol=0, atol=1e-12 * scale)


def test_dispersion_relation_and_group_velocity():
    k = np.array([1e-8, 0.3, 2.0, 50.0])
    omega = dispersion(k, 0.7)
    np.testing.assert_allclose(omega**2, G * k * np.tanh(k * 0.7), rtol=1e-14)
    step = 1e-6 * k
    numeric = (dispersion(k + step, 0.7) - dispersion(k - step, 0.7)) / (2 * step)
    np.testing.assert_allclose(group_velocity(k, 0.7), numeric, rtol=1e-8)
    assert group_velocity(0.0, 0.7) == pytest.approx(math.sqrt(G * 0.7), rel=1e-15)
    np.testing.assert_allclose(dispersion(k, 0.7, dispersive=False), k * math.sqrt(G * 0.7), rtol=1e-15)


# ------------------------------------------------------------------------------------------------------------------
# linear waves: reconstruction, d'Alembert, Poisson


@pytest.mark.parametrize("geometry", ["planar", "radial"])
def test_gaussian_at_rest_reconstructs_its_initial_elevation(geometry):
    shape = Gaussian(0.1, 0.8)
    x = np.linspace(0.0, 5.0, 51)
    eta, u = linear_wave_fields(shape, x, [0.0], 1.0, geometry=geometry)
    assert np.abs(eta[0] - shape.profile(x, geometry)).max() <= 1e-6 * 0.1
    assert np.all(u == 0.0)


@pytest.mark.parametrize("name", ["mound", "crater"])
@pytest.mark.parametrize("geometry", ["planar", "radial"])
def test_discontinuous_shapes_reconstruct_away_from_their_edge(name, geometry):
    """At t = 0 the inverse transform converges to eta0 except at the discontinuity (Gibbs)."""
    shape = SHAPES[name]
    edge = shape.length
    x = np.array([0.0, 0.3, edge - 0.05, edge + 0.05, 1.5, 4.0])
    eta, _, resolved = linear_wave_fields(shape, x, [0.0], 1.0, geometry=geometry, return_resolved=True)
    assert resolved.all()
    assert np.abs(eta[0] - shape.profile(x, geometry)).max() <= 1e-6 * shape.amplitude
    # at the edge itself no cut-off suffices: the point is flagged, and the value is the mean of both sides
    eta_edge, _, resolved_edge = linear_wave_fields(shape, [edge], [0.0], 1.0, geometry=geometry,
                                                    return_resolved=True)
    assert not resolved_edge.any()
    assert eta_edge[0, 0] == pytest.approx(shape.profile(edge, geometry), abs=0.02 * shape.amplitude)


@pytest.mark.parametrize("name", ["gaussian", "mound", "crater"])
def test_planar_waves_without_dispersion_are_dalembert(name):
    """eta = [eta0e(x - ct) + eta0e(x + ct)]/2, u = c/(2d) [eta0e(x - ct) - eta0e(x + ct)], c = sqrt(g d)."""
    shape, d = SHAPES[name], 0.7
    c = math.sqrt(G * d)
    x = np.array([0.0, 0.25, 0.9, 2.0, 4.57, 6.0])
    t = np.array([0.0, 0.3, 0.8, 1.7, 2.9])
    eta, u = linear_wave_fields(shape, x, t, d, dispersive=False)
    left, right = even(shape, x[None, :] - c * t[:, None]), even(shape, x[None, :] + c * t[:, None])
    fronts = np.abs(np.abs(x[None, :, None] + np.array([-1.0, 1.0]) * c * t[:, None, None]) - shape.length)
    away = fronts.min(axis=-1) > 0.05 if name != "gaussian" else np.ones(eta.shape, bool)
    assert away.sum() >= 20
    assert np.abs(eta - 0.5 * (left + right))[away].max() <= 1e-6 * shape.amplitude
    assert np.abs(u - c / (2 * d) * (left - right))[away].max() <= 1e-6 * shape.amplitude * c / d


def test_radial_waves_without_dispersion_match_poisson_formula_at_the_axis():
    """2D wave equation, eta0 = A exp(-(r/sigma)^2), at rest: Poisson's formula at r = 0,
    eta(0, t) = d/dt [(1/c) int_0^ct eta0(s) s ds / sqrt(c^2 t^2 - s^2)] = A [1 - 2 tau D(tau)],
    tau = c t / sigma, D Dawson's integral (substitute q = sqrt(c^2 t^2 - s^2))."""
    shape, d = Gaussian(0.1, 0.8), 1.0
    t = np.array([0.0, 0.1, 0.25, 0.5, 1.0, 2.0, 5.0])
    eta, u = linear_wave_fields(shape, [0.0], t, d, geometry="radial", dispersive=False)
    tau = math.sqrt(G * d) * t / 0.8
    np.testing.assert_allclose(eta[:, 0], 0.1 * (1.0 - 2.0 * tau * dawsn(tau)), rtol=0, atol=1e-8 * 0.1)
    assert np.all(u[:, 0] == 0.0)


@pytest.mark.parametrize("geometry", ["planar", "radial"])
def test_velocity_satisfies_linear_mass_conservation(geometry):
    """d eta/dt + d (1/r^j) d(r^j u)/dr = 0 (j = 0 planar, 1 radial), by central differences."""
    shape, d = Gaussian(0.1, 0.8), 1.0
    x, t, h = np.array([0.4, 1.3, 3.0]), 1.7, 1e-4
    eta_t = np.diff(linear_wave_fields(shape, x, [t - h, t + h], d, geometry=geometry)[0], axis=0)[0] / (2 * h)
    moment = 0 if geometry == "planar" else 1
    flux = linear_wave_fields(shape, np.concatenate([x - h, x + h]), [t], d, geometry=geometry)[1][0]
    weights = np.concatenate([x - h, x + h]) ** moment
    div = (flux[3:] * weights[3:] - flux[:3] * weights[:3]) / (2 * h) / x**moment
    np.testing.assert_allclose(eta_t + d * div, 0.0, atol=1e-6 * np.abs(eta_t).max())


# ------------------------------------------------------------------------------------------------------------------
# linear waves: accuracy of the quadrature


def _qawf_mound(x, t, d):
    """Prins' box by QUADPACK's Fourier-integral routine (scipy quad, weight sin/cos on [1, inf)):
    eta = (Q/pi) int [sin k(x+L) - sin k(x-L)] cos(omega t)/k dk,
    u = (Q/pi) int [cos k(x-L) - cos k(x+L)] omega sin(omega t)/(d k^2) dk."""
    q, lv = PRINS.height, PRINS.half_length

    def omega(k):
        return math.sqrt(G * k * math.tanh(k * d))

    def flux(k):
        return omega(k) * math.sin(omega(k) * t) / (d * k * k)

    eta = u = 0.0
    for a, sign in ((x + lv, 1.0), (x - lv, -1.0)):
        eta += sign * (quad(lambda k, a=a: math.sin(k * a) * math.cos(omega(k) * t) / k, 0.0, 1.0, epsabs=1e-13)[0]
                       + math.copysign(1.0, a) * quad(lambda k: math.cos(omega(k) * t) / k, 1.0, np.inf,
                                                      weight="sin", wvar=abs(a), epsabs=1e-12, limlst=200)[0])
        u -= sign * (quad(lambda k, a=a: math.cos(k * a) * flux(k), 0.0, 1.0, epsabs=1e-13)[0]
                     + quad(flux, 1.0, np.inf, weight="cos", wvar=abs(a), epsabs=1e-12, limlst=200)[0])
    return q / math.pi * eta, q / math.pi * u


def test_dispersive_mound_matches_adaptive_fourier_quadrature():
    """Independent reference where QAWF's cycle extrapolation converges (early times; late near the
    box, where the waves are short, its extrapolation fails and it is not used)."""
    d = PRINS_DEPTH
    for x, t in ((2.0, 2.0), (2.0, 7.5), (4.57, 2.0), (4.57, 7.5), (8.0, 7.5), (8.0, 13.0)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", IntegrationWarning)
            eta_ref, u_ref = _qawf_mound(x, t, d)
        eta, u = linear_wave_fields(PRINS, [x], [t], d)
        assert abs(eta[0, 0] - eta_ref) <= 1e-7 * 0.12, (x, t)
        assert abs(u[0, 0] - u_ref) <= 1e-7 * 0.12 * math.sqrt(G / d), (x, t)


def test_quadrature_converges_for_prins_mound():
    """Doubling the node density and every cut-off changes eta at the 4.57 m gauge by < 1e-5 Q over 12 s."""
    t = np.linspace(0.0, 12.0, 49)
    eta, u = linear_wave_fields(PRINS, [4.57], t, PRINS_DEPTH)
    eta2, u2 = linear_wave_fields(PRINS, [4.57], t, PRINS_DEPTH, refine=2)
    change = np.abs(eta2 - eta).max() / 0.12
    print(f"refine 1 -> 2 at x = 4.57 m, t <= 12 s: max |d eta| = {change:.1e} Q, "
          f"max |d u| = {np.abs(u2 - u).max():.1e} m/s")
    assert change < 1e-5
    assert np.abs(u2 - u).max() < 1e-5 * 0.12 * math.sqrt(G / PRINS_DEPTH)
    assert np.abs(eta).max() > 0.1 * 0.12  # the wave has arrived


@pytest.mark.parametrize("geometry,gauges,shape,depth", [
    ("planar", PRINS_GAUGES, PRINS, PRINS_DEPTH), ("radial", CRATER_GAUGES, CRATER, 1.0)])
def test_scene_gauges_are_resolved_for_20_seconds(geometry, gauges, shape, depth):
    """Every gauge sample of the scenes meets the truncation criterion within k_max, and refining agrees."""
    t = np.linspace(0.0, 20.0, 41)
    eta, _, resolved = linear_wave_fields(shape, gauges, t, depth, geometry=geometry, return_resolved=True)
    assert resolved.all()
    eta2, _ = linear_wave_fields(shape, gauges, t, depth, geometry=geometry, refine=2)
    assert np.abs(eta2 - eta).max() < 1e-5 * shape.amplitude


@pytest.mark.parametrize("geometry", ["planar", "radial"])
def test_dispersive_gaussian_conserves_volume(geometry):
    """int eta dx (half-line) = F(0)/2, int eta 2 pi r dr = 2 pi G(0), at all times."""
    shape, d = Gaussian(0.1, 1.0), 1.0
    x = np.linspace(0.0, 40.0, 2001)  # holds the waves: c t + 4 sigma < 21 m
    eta, _ = linear_wave_fields(shape, x, [0.0, 2.0, 5.0], d, geometry=geometry)
    weight = 1.0 if geometry == "planar" else 2.0 * np.pi * x
    volume = simpson(eta * weight, x=x, axis=1)
    exact = 0.1 * math.sqrt(math.pi) / 2 if geometry == "planar" else math.pi * 0.1
    np.testing.assert_allclose(volume, exact, rtol=1e-6)


def test_long_waves_do_not_disperse_and_short_ones_do():
    """k d << 1 content (sigma = 10 d) follows the shallow-water wave equation to within 2 % of the
    amplitude after 19 m of travel; sigma = d does not (the crest lags and sheds a wave train)."""
    d, x, t = 1.0, np.linspace(0.0, 40.0, 801), [6.0]
    gaps = []
    for width in (10.0, 1.0):
        shape = Gaussian(0.1, width)
        dispersive, _ = linear_wave_fields(shape, x, t, d)
        long_wave, _ = linear_wave_fields(shape, x, t, d, dispersive=False)
        gaps.append(np.abs(dispersive - long_wave).max() / 0.1)
    assert gaps[0] < 0.02
    assert gaps[1] > 0.2


def test_planar_solution_is_even_in_eta_and_odd_in_u():
    x = np.array([-3.0, -1.0, 1.0, 3.0])
    eta, u = linear_wave_fields(PRINS, x, [1.5], PRINS_DEPTH)
    np.testing.assert_allclose(eta[0], eta[0][::-1], rtol=1e-14)
    np.testing.assert_allclose(u[0], -u[0][::-1], rtol=1e-14)
    assert np.abs(u).max() > 0.0


@pytest.mark.parametrize("geometry", ["planar", "radial"])
def test_linear_waves_dataset_follows_the_schema(geometry):
    x, times = np.linspace(0.0, 6.0, 61), [0.0, 1.0, 2.0]
    ds = validate(linear_waves(CRATER, x, times, 1.0, geometry=geometry))
    assert ds.attrs["method"] == "exact" and ds.attrs["case"] == "crater"
    np.testing.assert_allclose(ds["h"].values, 1.0 + ds["eta"].values, rtol=1e-15)
    assert ds["eta"].attrs["units"] == "m" and ds["u"].attrs["units"] == "m s-1"
    assert "depth-averaged" in ds["u"].attrs["long_name"]
    assert ("radial" in ds["u"].attrs["long_name"]) == (geometry == "radial")
    params = parameters(ds)
    assert params["shape"] == "crater" and params["geometry"] == geometry and params["d"] == 1.0


# ------------------------------------------------------------------------------------------------------------------
# dam break

DAMS = [(1.0, 0.5), (0.005, 0.001), (2.0, 0.01), (1.0, 1e-6)]


@pytest.mark.parametrize("h_left,h_right", DAMS)
def test_bore_satisfies_rankine_hugoniot(h_left, h_right):
    """Across the bore at speed s: h (u - s) and h u (u - s) + g h^2/2 are continuous."""
    state = dam_break_state(h_left, h_right)
    t = 2.0
    x = state.front_speed * t * (1.0 + np.array([-1e-12, 1e-12]))
    h, u = dam_break_profile(x, t, h_left, h_right)
    assert h[0] == state.h_middle and u[0] == state.u_middle and h[1] == h_right and u[1] == 0.0
    s = state.front_speed
    mass = h * (u - s)
    momentum = h * u * (u - s) + 0.5 * G * h**2
    assert mass[0] == pytest.approx(mass[1], rel=1e-12)
    assert momentum[0] == pytest.approx(momentum[1], rel=1e-12)
    assert h_right < state.h_middle < h_left


@pytest.mark.parametrize("h_left,h_right", DAMS + [(1.0, 0.0)])
def test_riemann_invariant_is_constant_through_the_rarefaction(h_left, h_right):
    """u + 2 sqrt(g h) = 2 sqrt(g h_l) on the left characteristics, and the fan is centred: u - sqrt(g h) = xi."""
    state = dam_break_state(h_left, h_right)
    t, xi = 3.0, np.linspace(state.head_speed, state.tail_speed, 43)[1:-1]
    h, u = dam_break_profile(xi * t, t, h_left, h_right)
    c = np.sqrt(G * h)
    np.testing.assert_allclose(u + 2.0 * c, 2.0 * math.sqrt(G * h_left), rtol=1e-13)
    np.testing.assert_allclose(u - c, xi, rtol=0, atol=1e-13 * math.sqrt(G * h_left))


@pytest.mark.parametrize("h_left,h_right", DAMS)
def test_middle_state_solves_the_swashes_polynomial(h_left, h_right):
    """Delestre et al. (2013) §4.1.1: -8 g h_r c_m^2 (sqrt(g h_l) - c_m)^2 + (c_m^2 - g h_r)^2 (c_m^2 + g h_r) = 0."""
    c_m2, g_hr, c_l = G * dam_break_state(h_left, h_right).h_middle, G * h_right, math.sqrt(G * h_left)
    terms = (8 * g_hr * c_m2 * (c_l - math.sqrt(c_m2)) ** 2, (c_m2 - g_hr) ** 2 * (c_m2 + g_hr))
    assert abs(terms[1] - terms[0]) <= 1e-12 * max(terms)


@pytest.mark.parametrize("h_left,h_right", DAMS + [(1.0, 0.0)])
def test_volume_and_momentum_balance(h_left, h_right):
    """int h dx is the initial volume; int h u dx grows by the net hydrostatic force g (h_l^2 - h_r^2)/2."""
    state, t, x0 = dam_break_state(h_left, h_right), 1.3, 0.7
    lo, hi = x0 + 2 * state.head_speed * t, x0 + 2 * state.front_speed * t
    breaks = sorted(x0 + np.array([state.head_speed, state.tail_speed, state.front_speed]) * t)

    def integral(f):
        return quad(f, lo, hi, points=breaks, epsabs=0.0, epsrel=1e-13, limit=200)[0]

    def depth(x):
        return float(dam_break_profile(x, t, h_left, h_right, x0)[0])

    def discharge(x):
        h, u = dam_break_profile(x, t, h_left, h_right, x0)
        return float(h * u)

    volume = h_left * (x0 - lo) + h_right * (hi - x0)
    assert integral(depth) == pytest.approx(volume, rel=1e-10)
    assert integral(discharge) == pytest.approx(0.5 * G * (h_left**2 - h_right**2) * t, rel=1e-10)


def test_dry_bed_is_ritter_and_the_wet_bed_approaches_it():
    h_left, t = 1.0, 1.0
    c_l = math.sqrt(G * h_left)
    x = np.linspace(-1.5 * c_l, 2.5 * c_l, 4001)
    h, _ = dam_break_profile(x, t, h_left, 0.0)
    fan = (x >= -c_l) & (x <= 2 * c_l)
    np.testing.assert_allclose(h[fan], (2 * c_l - x[fan]) ** 2 / (9 * G), rtol=1e-14)
    assert np.all(h[x > 2 * c_l] == 0.0) and np.all(h[x < -c_l] == h_left)
    gaps = []
    for ratio in (1e-2, 1e-4, 1e-6):
        h_wet, _ = dam_break_profile(x, t, h_left, ratio * h_left)
        gaps.append(np.abs(h_wet - h).mean() * 4 * c_l / h_left)  # L1 distance per unit of released volume
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 2e-3


def test_reversed_dam_is_the_mirror_image():
    x = np.linspace(-5.0, 5.0, 101)
    h, u = dam_break_profile(x, 0.8, 0.3, 1.1, x0=0.5)
    h_m, u_m = dam_break_profile(1.0 - x, 0.8, 1.1, 0.3, x0=0.5)
    np.testing.assert_array_equal(h, h_m)
    np.testing.assert_array_equal(u, -u_m)


def test_dam_break_dataset_follows_the_schema():
    x, times = np.linspace(0.0, 10.0, 201), [0.0, 1.0, 6.0]
    ds = validate(dam_break(x, times, 0.005, 0.001, x0=5.0))
    np.testing.assert_allclose(ds["eta"].values, ds["h"].values - 0.001, rtol=0, atol=1e-18)
    np.testing.assert_array_equal(ds["h"].values[0], np.where(x < 5.0, 0.005, 0.001))
    assert "h_right" in ds["eta"].attrs["long_name"] and ds["h"].attrs["units"] == "m"
    assert parameters(ds) == {"h_left": 0.005, "h_right": 0.001, "x0": 5.0, "g": G}
    assert ds.attrs["method"] == "exact"


# ------------------------------------------------------------------------------------------------------------------
# bad input


@pytest.mark.parametrize("call,name", [
    (lambda: linear_wave_fields(PRINS, [1.0], [1.0], 0.0), "d"),
    (lambda: linear_wave_fields(PRINS, [1.0], [1.0], 0.7, g=-9.81), "g"),
    (lambda: linear_wave_fields(PRINS, [1.0], [1.0], 0.7, geometry="spherical"), "geometry"),
    (lambda: linear_wave_fields(PRINS, [1.0], [1.0], 0.7, tol=0.0), "tol"),
    (lambda: linear_wave_fields(PRINS, [1.0], [1.0], 0.7, refine=0.5), "refine"),
    (lambda: linear_wave_fields(PRINS, [1.0], [1.0], 0.7, k_max=1.0), "k_max"),
    (lambda: linear_wave_fields(PRINS, [-1.0], [1.0], 0.7, geometry="radial"), "x"),
    (lambda: linear_wave_fields(PRINS, [1.0], [-1.0], 0.7), "times"),
    (lambda: linear_wave_fields("mound", [1.0], [1.0], 0.7), "shape"),
    (lambda: linear_waves(PRINS, [1.0, 0.5], [1.0], 0.7), "x"),
    (lambda: Mound(height=0.0), "height"),
    (lambda: Mound(half_length=-0.61), "half_length"),
    (lambda: Crater(radius=0.0), "radius"),
    (lambda: Gaussian(width=float("nan")), "width"),
    (lambda: dispersion([1.0], -1.0), "d"),
    (lambda: dam_break_profile([0.0], 1.0, -1.0, 0.5), "h_left"),
    (lambda: dam_break_profile([0.0], 1.0, 0.0, 0.0), "h_left"),
    (lambda: dam_break_profile([0.0], -1.0, 1.0, 0.5), "t"),
    (lambda: dam_break_profile([0.0], 1.0, 1.0, 0.5, x0=float("inf")), "x0"),
    (lambda: dam_break_state(1.0, 0.5, g=0.0), "g"),
])
def test_bad_input_is_refused_in_one_sentence_naming_the_parameter(call, name):
    with pytest.raises(ValueError) as err:
        call()
    message = str(err.value)
    assert message.startswith(f"{name} ") and message.endswith(".") and "\n" not in message
