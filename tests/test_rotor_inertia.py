"""Reflected actuator rotor inertia (``rotor_inertia``) of the actuated walkers, checked
against closed forms and a conservation law, not against walker's own numbers.

A rotor geared with ratio N to a joint turns at N times the joint's relative rate ``w``, so
its kinetic energy is ``N^2 J w^2 / 2 = I_r w^2 / 2``: with ``w = A qd`` (``A`` the map from
the coordinates' rates to the relative joint rates, written out below from the models'
documented coordinates) the mass matrix gains exactly ``I_r A^T A`` and the kinetic energy
``I_r |A qd|^2 / 2``.  Without torques the total energy, rotors included, is conserved, and
at heel strike the links' angular momentum about the new stance foot is conserved (a
rotor's term depends on relative angles only, so it carries none of it).

RABBIT's published rotor: gear ratio 50, J = 3.32e-4 kg m^2 (Chevallereau et al., "RABBIT:
a testbed for advanced control theory", IEEE Control Systems Magazine 23(5), 2003), so
``I_r = 50^2 * 3.32e-4 = 0.83`` kg m^2.
"""

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker.models import get_model, hzd
from walker.params import FiveLinkParams, ThreeLinkParams
from walker.params._actuated_presets import RABBIT_ROTOR_INERTIA
from walker.simulation.stride import simulate
from walker.status import EVENT_STRIDE

RABBIT_ROTOR = 50.0**2 * 3.32e-4  # Chevallereau et al. 2003: N = 50, J = 3.32e-4 kg m^2
RNG = np.random.default_rng(20261128)


def _relative_five_link(q):
    """Relative joint angles (hip stance, hip swing, knee stance, knee swing) of the five-link
    coordinates (q_leg, q_knee, q_torso, q_femur_sw, q_tibia_sw): tibia_st = q_leg - q_knee/2,
    femur_st = q_leg + q_knee/2 (walker.symbolic.five_link's docstring)."""
    leg, knee, torso, fsw, tsw = q[:5]
    tst, fst = leg - knee / 2, leg + knee / 2
    return np.array([fst - torso, fsw - torso, tst - fst, tsw - fsw])


def _relative_three_link(q):
    """Relative hip angles (stance leg - torso, swing leg - torso)."""
    return np.array([q[0] - q[2], q[1] - q[2]])


def _map(relative, n):
    """``A = d(relative angles)/dq`` by central differences (exact: the map is linear)."""
    A = np.zeros((len(relative(np.zeros(n))), n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = 0.5
        A[:, j] = relative(e) - relative(-e)
    return A


CASES = {
    "five_link": (FiveLinkParams.rabbit, _relative_five_link, 5),
    "three_link": (ThreeLinkParams.grizzle, _relative_three_link, 3),
}


def test_published_rabbit_value():
    assert_allclose(RABBIT_ROTOR_INERTIA, RABBIT_ROTOR, rtol=1e-15, atol=0)
    assert_allclose(RABBIT_ROTOR_INERTIA, 0.83, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", sorted(CASES))
def test_presets_have_no_rotor_inertia(name):
    """The shipped presets model no rotors (their scenes say why)."""
    preset, _, _ = CASES[name]
    assert preset().rotor_inertia == 0.0


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("kernel", ["mass_matrix", "ext_mass_matrix"])
def test_mass_matrix_gains_I_r_A_T_A(name, kernel):
    """``D(I_r) - D(0) = I_r A^T A`` (pinned model; the floating base's hip position
    columns get nothing) at random configurations."""
    preset, relative, n = CASES[name]
    model = get_model(name)
    n_q = n if kernel == "mass_matrix" else n + 2
    A = np.zeros((len(relative(np.zeros(n))), n_q))
    A[:, :n] = _map(relative, n)
    I_r = RABBIT_ROTOR
    p0 = preset().as_array()
    p1 = preset().replace(rotor_inertia=I_r).as_array()
    for _ in range(5):
        q = RNG.uniform(-1.0, 1.0, n_q)
        D0 = model.kernel(kernel, p0, q)
        D1 = model.kernel(kernel, p1, q)
        assert_allclose(D1 - D0, I_r * A.T @ A, rtol=0, atol=1e-13)


@pytest.mark.parametrize("name", sorted(CASES))
def test_kinetic_energy_gains_rotor_energy(name):
    """``K(I_r) - K(0) = I_r |A qd|^2 / 2``; the potential energy is unchanged."""
    preset, relative, n = CASES[name]
    model = get_model(name)
    A = _map(relative, n)
    I_r = 0.37
    p0 = preset().as_array()
    p1 = preset().replace(rotor_inertia=I_r).as_array()
    for _ in range(5):
        x = np.zeros(2 * n + 2)
        x[: 2 * n] = RNG.uniform(-1.0, 1.0, 2 * n)
        K0, P0 = model.energy(x, p0)
        K1, P1 = model.energy(x, p1)
        w = A @ x[n : 2 * n]
        assert_allclose(K1 - K0, 0.5 * I_r * w @ w, rtol=1e-12, atol=1e-14)
        assert P1 == P0


def test_passive_five_link_with_rotors_conserves_energy():
    """Controller off (no torques), no joint friction, RABBIT's rotors: kinetic (links and
    rotors) plus potential energy is constant along the swing, to 1e-10 relative."""
    P = FiveLinkParams.rabbit().replace(controller=0.0, rotor_inertia=RABBIT_ROTOR)
    p = P.as_array()
    x0 = np.array([0.2, 0.2, -0.1, -0.1, -0.3, -0.9, 0.6, -0.2, -0.9, -0.9, 0.0, 0.0])
    times = np.linspace(0.0, 0.08, 9)
    sol = simulate("five_link", P, x0, n_strides=1, output="samples", sample_times=times)
    model = get_model("five_link")
    assert sol.samples.x.shape[0] == len(times), sol.status
    energies = np.array([sum(model.energy(x, p)) for x in sol.samples.x])
    kinetic = np.array([model.energy(x, p)[0] for x in sol.samples.x])
    w = np.array([_map(_relative_five_link, 5) @ x[5:10] for x in sol.samples.x])
    rotor = 0.5 * RABBIT_ROTOR * np.sum(w * w, axis=1)
    assert np.all(rotor > 0.01 * kinetic)  # the rotors hold a visible share of it
    assert np.all(np.abs(sol.samples.x[:, 10]) == 0.0)  # no actuator work
    assert_allclose(energies, energies[0], rtol=1e-10, atol=0)


def _link_angular_momentum(model, P, x, about):
    """Angular momentum of the five links [kg m^2/s] about ``about``, from the points
    kernel's positions and their velocities by central differences along ``qd``."""
    p = P.as_array()
    q, qd = x[:5], x[5:10]
    h = 1e-6

    def coms(q):
        pts = model.kernel("points", p, q)  # stance contact, stance knee, hip, swing knee,
        ks, hip, ksw = pts[1], pts[2], pts[3]  # swing contact, torso
        tst, fst = q[0] - q[1] / 2, q[0] + q[1] / 2
        u = lambda a: np.array([-math.sin(a), math.cos(a)])  # noqa: E731
        return [
            (P.mass_torso, hip + P.com_torso * u(q[2])),
            (P.mass_femur, hip - P.com_femur * u(fst)),
            (P.mass_tibia, ks - P.com_tibia * u(tst)),
            (P.mass_femur, hip - P.com_femur * u(q[3])),
            (P.mass_tibia, ksw - P.com_tibia * u(q[4])),
        ]

    now, ahead, behind = coms(q), coms(q + h * qd), coms(q - h * qd)
    orbital = 0.0
    for (m, c), (_, c1), (_, c0) in zip(now, ahead, behind, strict=True):
        v = (c1 - c0) / (2 * h)
        r = c - about
        orbital += m * (r[0] * v[1] - r[1] * v[0])
    tstd, fstd = qd[0] - qd[1] / 2, qd[0] + qd[1] / 2
    spin = P.inertia_torso * qd[2] + P.inertia_femur * (fstd + qd[3])
    return orbital + spin + P.inertia_tibia * (tstd + qd[4])


def test_heel_strike_with_rotors_conserves_link_momentum_about_new_foot():
    """With RABBIT's rotors the impact changes the rates (the rotors resist the joints'
    jumps) but conserves the links' angular momentum about the new stance foot (1e-8)."""
    model = get_model("five_link")
    P0 = FiveLinkParams.rabbit()
    P = P0.replace(rotor_inertia=RABBIT_ROTOR)
    q, sigma, _ = hzd.surface(P0, P0.theta_minus)
    x = np.r_[q, -1.3 * sigma, 0.0, 0.0]
    out = {}
    for name, params in (("without", P0), ("with", P)):
        p = params.as_array()
        action, _, status, x_new, impulse = model.reset(model.start_phase(x, p), 0, x, p)
        assert (action, status) == (EVENT_STRIDE, 0)
        before = _link_angular_momentum(model, params, x, model.kernel("points", p, x[:5])[4])
        after = _link_angular_momentum(
            model, params, x_new, model.kernel("points", p, x_new[:5])[0]
        )
        assert_allclose(after, before, rtol=1e-8, atol=0)
        out[name] = x_new
    assert np.max(np.abs(out["with"][5:10] - out["without"][5:10])) > 1e-3


@pytest.mark.parametrize(
    "scene",
    ["gaits/five_link_hzd.toml", "gaits/three_link_grizzle.toml", "gaits/three_link_book.toml"],
)
def test_scenes_and_files_before_the_field_read_without_rotors(scene):
    """Every shipped actuated scene states its rotor inertia (0: the published sets it
    follows have none in the model its gait is for); a file written before the field
    existed reads as 0, the model it was computed with."""
    from walker.cli import provenance
    from walker.plotting.gallery import _params_from_provenance
    from walker.scene import load_scene

    with open(scene, encoding="utf-8") as f:
        assert "rotor_inertia = 0.0" in f.read()
    loaded = load_scene(scene)
    assert loaded.params.rotor_inertia == 0.0
    prov = provenance(loaded)
    del prov["parameters"]["rotor_inertia"]
    _, params = _params_from_provenance(prov)
    assert params.rotor_inertia == 0.0
    assert params.as_array().tolist() == loaded.params.as_array().tolist()
