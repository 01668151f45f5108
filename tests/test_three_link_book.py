"""The three-link walker with the book's controller and impact surface
(``gaits/three_link_book.toml``; Westervelt, Grizzle, Chevallereau, Choi, Morris, *Feedback
Control of Dynamic Bipedal Robot Locomotion*, CRC Press 2007, example code
``WGCCM_three_link_walker_example``).

The independent computation below is written from the book's equations in the book's own
coordinates (angles clockwise from the upward vertical, ``theta = -q``): point masses (legs'
at r/2, hip, torso at L above the hip), Lagrange's equations as ``sum_i m_i J_i^T (J_i qdd +
Jdot_i qd) + dV/dq = B u``, the book's outputs (torso cubic, swing ``th2 + th1 - p(th1) (th1 -
th1d)(th1 + th1d)``), the Bhat-Bernstein controller through input-output linearization, the
event ``th1 = th1d`` rising and the rigid impact in extended coordinates; integrated by scipy's
``solve_ivp`` (DOP853, rtol = atol = 1e-12).  Once the outputs have settled (they do, in finite
time, before every impact) the pre-impact state lies on the zero dynamics, so the gait is the
fixed point of the scalar map ``omega -> omega'`` of the stance rate just before impact (the
book's own parametrization, ``sigma_three_link.m``), and the one nontrivial Floquet multiplier
is that map's derivative (the stride map's Jacobian has rank one).
"""

import functools
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from walker import StrideMap, find_fixed_point, load_scene, simulate
from walker.models import three_link
from walker.params import ThreeLinkParams

SCENE = "gaits/three_link_book.toml"

# The book's example (model_params_three_link.m, control_params_three_link.m, walker_main.m)
R, M_LEG, M_HIP, M_TORSO, L_TORSO, G = 1.0, 5.0, 15.0, 10.0, 0.5, 9.8
TH1D, ALPHA, EPS = math.pi / 8, 0.9, 0.1
BOOK_A = (0.512, 0.073, 0.035, -0.819, -2.27, 3.26, 3.11, 1.89)
OMEGA_1 = 1.55

_P = np.polynomial.polynomial
_TORSO = np.array(BOOK_A[:4])  # p1(th1): desired torso angle
# swing output h2 = th2 + th1 - p2(th1) (th1^2 - th1d^2): h2 = th2 - s(th1) with
# s(th1) = -th1 + p2(th1) (th1^2 - th1d^2)
_SWING = _P.polyadd([0.0, -1.0], _P.polymul(np.array(BOOK_A[4:]), [-(TH1D**2), 0.0, 1.0]))


def _der(c, k=1):
    return _P.polyder(c, k)


# ----------------------------------------------------------------------------------------
# The book's example, independently (book coordinates: th = (th1 stance, th2 swing, th3
# torso), clockwise from the upward vertical)
# ----------------------------------------------------------------------------------------
def _bodies(th):
    """(mass, position, Jacobian d pos / d th, curvature term Jdot qd / qd^2 columns) of the
    four point masses, stance foot at the origin."""
    s1, c1 = math.sin(th[0]), math.cos(th[0])
    s2, c2 = math.sin(th[1]), math.cos(th[1])
    s3, c3 = math.sin(th[2]), math.cos(th[2])
    # u(th) = (sin th, cos th): hip = R u(th1); swing mass = hip - R/2 u(th2);
    # torso = hip + L u(th3); stance mass = R/2 u(th1)
    out = []
    for m, terms in (
        (M_LEG, ((0, 0.5 * R),)),
        (M_HIP, ((0, R),)),
        (M_LEG, ((0, R), (1, -0.5 * R))),
        (M_TORSO, ((0, R), (2, L_TORSO))),
    ):
        J = np.zeros((2, 3))
        K = np.zeros((2, 3))  # d2 pos / d th_j^2 (no cross terms: each term one angle)
        for j, a in terms:
            s, c = (s1, c1) if j == 0 else (s2, c2) if j == 1 else (s3, c3)
            J[:, j] += a * np.array([c, -s])
            K[:, j] += a * np.array([-s, -c])
        out.append((m, J, K))
    return out


def _dynamics(th, dth):
    """D (3, 3) and N (3,) with D thdd + N = B u (N: Coriolis, centrifugal, gravity)."""
    D = np.zeros((3, 3))
    N = np.zeros(3)
    for m, J, K in _bodies(th):
        D += m * J.T @ J
        N += m * J.T @ (K @ (dth * dth))
        N += m * G * J[1]  # dV/dth, V = m g height
    return D, N


# any input map with the hips' column space gives the same closed loop
_B = np.array([[-1.0, 0.0], [0.0, -1.0], [1.0, 1.0]])


def _sig(x, e):
    return math.copysign(abs(x) ** e, x) if x != 0.0 else 0.0


def _book_rhs(t, x):
    th, dth = x[:3], x[3:]
    D, N = _dynamics(th, dth)
    t1, w1 = th[0], dth[0]
    y = np.array([th[2] - _P.polyval(t1, _TORSO), th[1] - _P.polyval(t1, _SWING)])
    H = np.array(
        [[-_P.polyval(t1, _der(_TORSO)), 0.0, 1.0], [-_P.polyval(t1, _der(_SWING)), 1.0, 0.0]]
    )
    yd = H @ dth
    hdd = -np.array([_P.polyval(t1, _der(_TORSO, 2)), _P.polyval(t1, _der(_SWING, 2))]) * w1 * w1
    v = np.empty(2)
    for i in range(2):  # Bhat-Bernstein on the time scale epsilon (control_three_link.m)
        e = EPS * yd[i]
        phi = y[i] + _sig(e, 2.0 - ALPHA) / (2.0 - ALPHA)
        v[i] = (-_sig(e, ALPHA) - _sig(phi, ALPHA / (2.0 - ALPHA))) / EPS**2
    Dinv_B = np.linalg.solve(D, _B)
    Dinv_N = np.linalg.solve(D, N)
    u = np.linalg.solve(H @ Dinv_B, v - hdd + H @ Dinv_N)
    return np.concatenate([dth, Dinv_B @ u - Dinv_N])


def _impact(x):
    """Rigid impact at the swing foot, extended coordinates (th, stance foot position), then
    the relabelling; returns the post-impact state (book coordinates)."""
    th, dth = x[:3], x[3:]
    De = np.zeros((5, 5))
    for m, J, _ in _bodies(th):
        Je = np.hstack([J, np.eye(2)])
        De += m * Je.T @ Je
    # swing foot = hip - R u(th2)
    E = np.zeros((2, 5))
    E[:, 0] = R * np.array([math.cos(th[0]), -math.sin(th[0])])
    E[:, 1] = -R * np.array([math.cos(th[1]), -math.sin(th[1])])
    E[:, 3:] = np.eye(2)
    A = np.block([[De, -E.T], [E, np.zeros((2, 2))]])
    sol = np.linalg.solve(A, np.concatenate([De @ np.concatenate([dth, [0.0, 0.0]]), [0.0, 0.0]]))
    w = sol[:3]
    return np.array([th[1], th[0], th[2], w[1], w[0], w[2]])


def _sigma(omega):
    """The state on the zero dynamics just before impact with th1 = th1d, dth1 = omega."""
    return np.array(
        [
            TH1D,
            _P.polyval(TH1D, _SWING),
            _P.polyval(TH1D, _TORSO),
            omega,
            _P.polyval(TH1D, _der(_SWING)) * omega,
            _P.polyval(TH1D, _der(_TORSO)) * omega,
        ]
    )


def _event(t, x):
    return x[0] - TH1D


_event.terminal = True
_event.direction = 1.0


def _book_stride(x_plus):
    sol = solve_ivp(
        _book_rhs, (0.0, 5.0), x_plus, method="DOP853", rtol=1e-12, atol=1e-12, events=_event
    )
    assert sol.status == 1, sol.message
    return sol.t_events[0][0], sol.y_events[0][0]


def _rho(omega):
    """Stance rate just before the next impact, from the zero-dynamics state with rate omega."""
    return _book_stride(_impact(_sigma(omega)))[1][3]


@functools.cache
def _book_gait():
    """(omega*, the post-impact state in book coordinates, step time, multiplier)."""
    omega = brentq(lambda w: _rho(w) - w, 1.5, 1.6, xtol=1e-14, rtol=1e-15)
    x_plus = _impact(_sigma(omega))
    T, x_minus = _book_stride(x_plus)
    # central differences with Richardson extrapolation
    d = [(_rho(omega + h) - _rho(omega - h)) / (2 * h) for h in (2e-3, 1e-3)]
    lam = d[1] + (d[1] - d[0]) / 3.0
    return omega, x_plus, T, lam, x_minus


def _to_walker(x_book):
    return np.concatenate([-np.asarray(x_book), [0.0, 0.0]])


@functools.cache
def _walker_gait():
    scene = load_scene(SCENE)
    c = scene.compute
    P = StrideMap(scene.model, scene.params, rtol=c.rtol, atol=c.atol, t_max=c.t_max)
    fp = find_fixed_point(P, P.project(scene.state), tol=c.tol)
    assert fp.success, fp.message
    return fp


# ----------------------------------------------------------------------------------------
def test_scene_coefficients_are_the_books():
    """The scene's polynomial coefficients are the book's a in walker's angles, and the
    helper ThreeLinkParams.westervelt_book builds the same parameters."""
    scene = load_scene(SCENE)
    d = scene.params.to_dict()
    # the Bezier coefficients (controller 2 only) are the grizzle preset's in the scene
    book = ThreeLinkParams.westervelt_book().to_dict()
    for name, value in book.items():
        if not name.startswith("bezier_"):
            assert d[name] == pytest.approx(value, abs=1e-15), name
    swing = np.array([d[f"poly_swing_{k}"] for k in range(6)])
    torso = np.array([d[f"poly_torso_{k}"] for k in range(6)])
    q = np.linspace(-0.6, 0.6, 13)
    # desired angles in walker's coordinates are minus the book's at th1 = -q_stance
    np.testing.assert_allclose(_P.polyval(q, swing), -_P.polyval(-q, _SWING), atol=2e-15)
    np.testing.assert_allclose(_P.polyval(q, torso), -_P.polyval(-q, _TORSO), atol=2e-15)
    assert d["ft_alpha"] == ALPHA and d["ft_epsilon"] == EPS
    assert d["theta_minus"] == -TH1D and d["controller"] == 3.0 and d["step_event"] == 1.0
    assert (d["mass_hip"], d["mass_leg"], d["mass_torso"]) == (M_HIP, M_LEG, M_TORSO)
    assert (d["torso_length"], d["g"], d["com_from_foot"] + d["com_to_hip"]) == (L_TORSO, G, R)


def test_scene_starts_at_the_books_omega_1():
    """[initial] state is sigma(omega_1 = 1.55) through the impact, in walker's angles."""
    x = load_scene(SCENE).state
    np.testing.assert_allclose(x, _to_walker(_impact(_sigma(OMEGA_1))), atol=1e-14, rtol=0)


def test_one_stride_matches_the_independent_code():
    """One stride from the book's start: walker's state just before and after the impact
    and the impact time equal the independent solve_ivp code's."""
    scene = load_scene(SCENE)
    sol = simulate("three_link", scene.params, scene.state, rtol=1e-12, atol=1e-12, output="events")
    assert sol.success
    T, x_minus = _book_stride(_impact(_sigma(OMEGA_1)))
    ev = sol.events
    assert abs(ev.t[0] - T) < 1e-9
    np.testing.assert_allclose(ev.x_pre[0][:6], -x_minus, atol=1e-9, rtol=0)
    np.testing.assert_allclose(ev.x_post[0][:6], -_impact(x_minus), atol=1e-9, rtol=0)
    assert ev.guard[0] == 0  # the step_event = 1 surface, guard 0


@pytest.mark.slow  # about 35 s: the independent code's fixed point; one stride is checked above
def test_fixed_point_and_multiplier_match_the_independent_code():
    fp = _walker_gait()
    omega, x_plus, T, lam, x_minus = _book_gait()
    np.testing.assert_allclose(fp.state, _to_walker(x_plus), atol=1e-9, rtol=0)
    assert abs(fp.step_time - T) < 1e-9
    # on the gait the outputs have settled before the impact: the pre-impact state is on
    # the zero dynamics, so the independent fixed point of the scalar map is a fixed point
    # of the full stride (to the settling's round-off)
    np.testing.assert_allclose(x_minus, _sigma(omega), atol=1e-10, rtol=0)
    mult = fp.multipliers
    assert abs(mult[0].imag) == 0.0
    assert abs(mult[0].real - lam) < 3e-7, (mult[0], lam)
    # the other four: finite-time convergence kills every transverse perturbation
    assert np.all(np.abs(mult[1:]) < 1e-6)
    assert fp.stable


def test_regression_pin_walker_gait():
    """Regression pin: walker's own fixed point and dominant multiplier of the scene."""
    fp = _walker_gait()
    np.testing.assert_allclose(
        fp.state[:6],
        [0.3926990816991713, -0.39269908169872414, -0.4964665420092824,
         -0.9267511529444313, 0.23926707959818824, -1.483783219789023],
        atol=1e-10, rtol=0,
    )  # fmt: skip
    assert abs(fp.step_time - 1.1216327004294784) < 1e-10
    assert abs(fp.multipliers[0].real - 0.5770614001111616) < 1e-8


def test_walker_find_cli_prints_the_gait():
    out = subprocess.run(
        [sys.executable, "-m", "walker", "find", SCENE, "--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stderr
    rec = json.loads(out.stdout)
    assert rec["status"] == "COMPLETED" and rec["stable"]
    assert abs(rec["multipliers"][0][0] - 0.5770614) < 1e-6


def test_step_event_guard_and_section():
    """step_event = 1: guard 0 is q_stance - theta_minus, and the section's q_swing is
    theta_minus (the impact happened there), whatever q_stance is."""
    p = load_scene(SCENE).params.as_array()
    x = np.zeros(8)
    x[0], x[1] = 0.1, 0.3
    z = three_link.project(x, p)
    y = three_link.lift(z, p)
    assert y[1] == p[three_link.I_THETA_MINUS]
    J = three_link.lift_jacobian(z, p)
    np.testing.assert_array_equal(three_link.lift(z + 1.0, p), y + J @ np.ones(5))
    names = ThreeLinkParams.names()
    assert names.index("step_event") == three_link.I_STEP_EVENT
    assert names.index("ft_alpha") == three_link.I_FT
    assert names.index("damping_hip") == three_link.I_DAMPING_HIP
    assert names.index("coulomb_hip") == three_link.I_COULOMB_HIP


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("controller", 4.0, "`controller` must be in"),
        ("controller", 2.5, "`controller` must be 0, 1, 2 or 3"),
        ("step_event", 0.5, "`step_event` must be 0 or 1"),
        ("ft_alpha", 1.0, "`ft_alpha` must be in"),
        ("ft_epsilon", 0.0, "`ft_epsilon` must be > 0"),
    ],
)
def test_bad_settings_name_the_key(key, value, match):
    with pytest.raises(ValueError, match=match):
        ThreeLinkParams.westervelt_book(**{key: value})


def test_bad_scene_value_names_file_and_key(tmp_path):
    text = open(SCENE, encoding="utf-8").read().replace("ft_alpha = 0.9", "ft_alpha = 1.5")
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ValueError, match=r"bad\.toml.*ft_alpha"):
        load_scene(path)


def test_three_link_files_from_before_the_book_controller_still_plot(tmp_path):
    """results/gallery/three_link_walk.h5 was written with the 29-parameter layout (no
    step_event, ft_*, poly_*): it reads with the grizzle preset's values for those, the model
    it was computed with."""
    from walker.plotting.gallery import plot_file
    from walker.storage import read

    path = Path(__file__).resolve().parents[1] / "results/gallery/three_link_walk.h5"
    _, prov = read(path)
    assert "step_event" not in prov["parameters"]
    written = plot_file(path, tmp_path)
    assert any(str(p).endswith("_torques.png") for p in written)
