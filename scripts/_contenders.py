"""The contenders' models the benchmark scripts (scripts/bench_*.py) run against walker.

* the hand-written numpy kneed walker the scipy contenders run: its equations of motion are
  derived here from the Lagrangian with sympy once (point masses on massless segments plus
  optional segment inertias, point feet), printed as scalar Python source (common
  subexpressions hoisted, parameter-only subexpressions computed once per parameter set) with
  the 3x3 / 2x2 linear solve written out in closed form (cofactors, no numpy.linalg), so one
  vector-field call costs a few dozen float operations and one small array;
* one kneed stride with ``scipy.integrate.solve_ivp`` on that model, and on walker's own
  compiled vector field, with terminal events for knee lock and heel strike and walker's
  impact maps (the impacts are not the integrator being compared); the same stride with
  heyoka; one stride of the one-phase walkers (compass, simplest) with solve_ivp, and of
  the compass with heyoka;
* :func:`section_map`: any of these strides as a map on walker's section.

Only walker's public API is used (``walker.params``, ``walker.models.get_model`` and the
model module's functions).
"""

from __future__ import annotations

import math
import time

import numpy as np

from walker.params import KneedParams

# ----------------------------------------------------------- hand-written kneed model
# Parameters the hand-written model leaves out, the segment offsets, the foot radius and the
# viscous dampers: they must be zero in the benchmarked scene.
KNEED_ZERO = tuple(
    n for n in KneedParams.names() if n.startswith(("offset_", "damping_")) or n == "foot_radius"
)
# Parameter order of the generated source: walker's KneedParams fields in their order, less
# the ones left out and the slope (the heel-strike guard takes it).
KNEED_PARAMS = tuple(n for n in KneedParams.names() if n not in (*KNEED_ZERO, "slope"))


def derive_kneed():
    """The kneed walker (point feet, point masses + segment inertias, absolute angles from
    the vertical, counterclockwise positive, gravity along -y) from its Lagrangian:
    ``D(q) qdd + h(q, qd) = 0`` for the unlocked (q1, q2, q3) and locked (q1, q2) swing,
    ``h = C(q, qd) qd + dV/dq`` with C from the Christoffel symbols of D.

    Returns ``{phase: (q symbols, qd symbols, D, h)}`` and the parameter symbols.
    """
    import sympy as sp

    mh, mt, ms, a1, b1, a2, b2, It, Is, g = sp.symbols(KNEED_PARAMS, positive=True)
    q = sp.symbols("q1 q2 q3", real=True)
    w = sp.symbols("w1 w2 w3", real=True)

    def u(a):  # unit vector foot -> hip of a segment at absolute angle a
        return sp.Matrix([-sp.sin(a), sp.cos(a)])

    ls, lt = a1 + b1, a2 + b2
    hip = (ls + lt) * u(q[0])
    knee = hip - lt * u(q[1])
    bodies = [  # (mass, position, angle, inertia about the centre of mass)
        (mh, hip, None, 0),
        (ms, a1 * u(q[0]), q[0], Is),  # stance shank
        (mt, hip - b2 * u(q[0]), q[0], It),  # stance thigh
        (mt, hip - b2 * u(q[1]), q[1], It),  # swing thigh
        (ms, knee - b1 * u(q[2]), q[2], Is),  # swing shank
    ]

    def equations(qs, ws, sub):
        n = len(qs)
        D = sp.zeros(n, n)
        V = 0
        for m, r, ang, inertia in bodies:
            r = r.subs(sub)
            Jr = r.jacobian(qs)
            D += m * Jr.T * Jr
            V += m * g * r[1]
            if ang is not None:
                Ja = sp.Matrix([[sp.diff(ang.subs(sub), qi) for qi in qs]])
                D += inertia * Ja.T * Ja
        D = D.applyfunc(lambda e: sp.factor_terms(sp.trigsimp(sp.expand(e))))
        h = []
        for i in range(n):
            # Christoffel: sum_jk (dD_ij/dq_k - 1/2 dD_jk/dq_i) w_j w_k
            c = sum(
                (sp.diff(D[i, j], qs[k]) - sp.diff(D[j, k], qs[i]) / 2) * ws[j] * ws[k]
                for j in range(n)
                for k in range(n)
            )
            h.append(sp.expand(c + sp.diff(V, qs[i])))
        return D, sp.Matrix(h)

    out = {}
    D3, h3 = equations(q, w, {})
    out["unlocked"] = (q, w, D3, h3)
    D2, h2 = equations(q[:2], w[:2], {q[2]: q[1]})
    out["locked"] = (q[:2], w[:2], D2, h2)
    return out, (mh, mt, ms, a1, b1, a2, b2, It, Is, g)


def _scalar_source(exprs, params, states, tag):
    """Scalar Python statements for ``exprs``.

    Each expression is expanded and its terms grouped by their state-dependent factor
    (``sin(q1 - q2) w2**2``, ``sin(q1)``, ...); the parameter-only coefficient of each group
    becomes a constant computed once per parameter set.  Common subexpressions of the
    state-dependent part are shared.  Returns (constant lines, per-call lines, results).
    """
    import sympy as sp
    from sympy.printing.pycode import PythonCodePrinter

    class Printer(PythonCodePrinter):
        # cos/sin are names bound by the generated factory (math's for floats, heyoka's
        # for expressions); squares as products.
        def _print_Function(self, e):
            return f"{e.func.__name__}({', '.join(self._print(a) for a in e.args)})"

        def _print_Pow(self, e, rational=False):
            b, ex = e.as_base_exp()
            if ex == 2:
                return f"{self.parenthesize(b, 100)}*{self.parenthesize(b, 100)}"
            return super()._print_Pow(e, rational)

    pr = Printer({"fully_qualified_modules": False})
    consts: dict = {}  # coefficient expression -> symbol
    const_lines = []
    grouped = []
    for e in exprs:
        groups: dict = {}
        for term in sp.Add.make_args(sp.expand(e)):
            coeff, state = term.as_independent(*states, as_Add=False)
            groups[state] = groups.get(state, 0) + coeff
        total = 0
        for state, coeff in groups.items():
            coeff = sp.factor(coeff)
            if coeff.is_number:
                total += coeff * state
                continue
            if coeff not in consts:
                sym = sp.Symbol(f"{tag}{len(consts)}")
                consts[coeff] = sym
                const_lines.append(f"{sym} = {pr.doprint(coeff)}")
            total += consts[coeff] * state
        grouped.append(total)
    repl, reduced = sp.cse(grouped, symbols=sp.numbered_symbols(f"{tag}s"))
    lines = [f"{sym} = {pr.doprint(e)}" for sym, e in repl]
    del params
    return const_lines, lines, [pr.doprint(r) for r in reduced]


def kneed_source() -> str:
    """Python source of ``make_kneed(p, cos, sin, out)``: returns the unlocked and locked
    vector fields of the kneed walker as closures over the parameters.

    ``p`` is a sequence in the order of :data:`KNEED_PARAMS`; ``cos``/``sin`` the functions to
    use (``math``'s for floats, ``heyoka``'s for expressions); ``out`` wraps the returned
    values (``numpy.array`` for solve_ivp, ``tuple`` for heyoka).  Unlocked: ``f3(q1, q2, q3,
    w1, w2, w3) -> out((w1, w2, w3, qdd1, qdd2, qdd3))``; locked: ``f2(q1, q2, w1, w2) ->
    out((w1, w2, qdd1, qdd2))``.  The accelerations solve ``D qdd = -h`` by cofactors.
    """
    eqs, params = derive_kneed()
    q3s, w3s, D3, h3 = eqs["unlocked"]
    q2s, w2s, D2, h2 = eqs["locked"]
    exprs3 = [D3[0, 0], D3[0, 1], D3[0, 2], D3[1, 1], D3[1, 2], D3[2, 2], *(-h3)]
    exprs2 = [D2[0, 0], D2[0, 1], D2[1, 1], *(-h2)]
    p3, s3, r3 = _scalar_source(exprs3, params, (*q3s, *w3s), "u")
    p2, s2, r2 = _scalar_source(exprs2, params, (*q2s, *w2s), "k")
    pnames = ", ".join(str(s) for s in params)
    ind = "    "
    src = [
        "# Generated by scripts/_contenders.py (kneed_source) from the kneed walker's Lagrangian.",
        "def make_kneed(p, cos, sin, out):",
        f"{ind}{pnames}, = p",
        *[ind + x for x in p3 + p2],
        "",
        f"{ind}def f3(q1, q2, q3, w1, w2, w3):",
        *[2 * ind + x for x in s3],
        f"{ind}{ind}a = {r3[0]}",
        f"{ind}{ind}b = {r3[1]}",
        f"{ind}{ind}c = {r3[2]}",
        f"{ind}{ind}d = {r3[3]}",
        f"{ind}{ind}e = {r3[4]}",
        f"{ind}{ind}f = {r3[5]}",
        f"{ind}{ind}r1 = {r3[6]}",
        f"{ind}{ind}r2 = {r3[7]}",
        f"{ind}{ind}r3 = {r3[8]}",
        f"{ind}{ind}A11 = d*f - e*e",
        f"{ind}{ind}A12 = c*e - b*f",
        f"{ind}{ind}A13 = b*e - c*d",
        f"{ind}{ind}A22 = a*f - c*c",
        f"{ind}{ind}A23 = b*c - a*e",
        f"{ind}{ind}A33 = a*d - b*b",
        f"{ind}{ind}inv = 1.0/(a*A11 + b*A12 + c*A13)",
        f"{ind}{ind}return out((w1, w2, w3, (A11*r1 + A12*r2 + A13*r3)*inv, "
        "(A12*r1 + A22*r2 + A23*r3)*inv, (A13*r1 + A23*r2 + A33*r3)*inv))",
        "",
        f"{ind}def f2(q1, q2, w1, w2):",
        *[2 * ind + x for x in s2],
        f"{ind}{ind}a = {r2[0]}",
        f"{ind}{ind}b = {r2[1]}",
        f"{ind}{ind}d = {r2[2]}",
        f"{ind}{ind}r1 = {r2[3]}",
        f"{ind}{ind}r2 = {r2[4]}",
        f"{ind}{ind}inv = 1.0/(a*d - b*b)",
        f"{ind}{ind}return out((w1, w2, (d*r1 - b*r2)*inv, (a*r2 - b*r1)*inv))",
        "",
        f"{ind}return f3, f2",
        "",
    ]
    return "\n".join(src)


_SOURCE_CACHE: dict[str, str] = {}


def kneed_factory():
    """``make_kneed`` compiled from :func:`kneed_source` (derived once per process)."""
    if "src" not in _SOURCE_CACHE:
        _SOURCE_CACHE["src"] = kneed_source()
    ns: dict = {}
    exec(compile(_SOURCE_CACHE["src"], "<kneed_numpy_model>", "exec"), ns)
    return ns["make_kneed"], _SOURCE_CACHE["src"]


def check_kneed_params(params) -> list:
    """The parameter values in :data:`KNEED_PARAMS` order; refuses a scene that uses a
    feature the hand-written model leaves out."""
    bad = [n for n in KNEED_ZERO if getattr(params, n) != 0.0]
    if bad:
        raise ValueError(f"the hand-written kneed model needs {bad} = 0")
    return [float(getattr(params, n)) for n in KNEED_PARAMS]


class _ScipyKneed:
    """One kneed stride with ``scipy.integrate.solve_ivp``: the unlocked swing from the state
    just after heel strike to knee lock, walker's knee-lock impact, the locked swing to heel
    strike, walker's heel-strike impact.

    A subclass sets ``p`` (walker's parameter vector), ``reset`` (walker's impact maps), the
    vector fields ``unlocked`` and ``locked`` with the terminal events ``knee`` and ``heel``,
    and says how the locked phase's state is written (:meth:`to_locked`, :meth:`from_locked`).
    """

    def to_locked(self, x6):
        """The locked phase's initial state from walker's state after knee lock."""
        return x6.copy()

    def from_locked(self, y):
        """walker's 6-state at heel strike from the locked phase's state."""
        return y

    def stride(self, x0, method="DOP853", rtol=1e-10, atol=1e-10, t_span=5.0):
        """One stride from the state just after heel strike; returns (state after the next
        heel strike, stride time, rhs evaluations) or (None, t, nfev) on failure."""
        from scipy.integrate import solve_ivp

        p = self.p
        imp = np.zeros(2)
        x6 = np.empty(6)
        sol = solve_ivp(
            self.unlocked,
            (0.0, t_span),
            np.asarray(x0, dtype=float),
            method=method,
            rtol=rtol,
            atol=atol,
            events=self.knee,
        )
        nfev = sol.nfev
        if sol.status != 1 or not len(sol.t_events[0]):
            return None, np.nan, nfev
        t1 = sol.t_events[0][0]
        action, phase, status = self.reset(0, 0, t1, sol.y_events[0][0], p, x6, imp)
        if action == 2:  # knee lock and heel strike at the same instant
            return x6.copy(), t1, nfev
        if status != 0 or phase != 1:
            return None, t1, nfev
        sol = solve_ivp(
            self.locked,
            (t1, t1 + t_span),
            self.to_locked(x6),
            method=method,
            rtol=rtol,
            atol=atol,
            events=self.heel,
        )
        nfev += sol.nfev
        if sol.status != 1 or not len(sol.t_events[0]):
            return None, np.nan, nfev
        t2 = sol.t_events[0][0]
        xe = self.from_locked(sol.y_events[0][0])
        action, phase, status = self.reset(1, 1, t2, xe, p, x6, imp)
        if status != 0 or action != 2:
            return None, t2, nfev
        return x6.copy(), t2, nfev


class _array_api:  # noqa: N801 - a namespace of functions, as a model module was
    """A walker model's compiled functions in the array form the contenders call them in
    (``rhs(phase, t, x, p, out)``, ``guards(...)``, ``reset(phase, k, t, x, p, x_new,
    impulse) -> (action, next phase, status)``), through the checked calls of
    :class:`walker.models.WalkerModel`."""

    def __init__(self, model):
        self.model = model
        self.guard_names = model.guard_names

    def rhs(self, phase, t, x, p, out):
        out[:] = self.model.rhs(phase, x, p, t)

    def guards(self, phase, t, x, p, out):
        out[:] = self.model.guards(phase, x, p, t)

    def reset(self, phase, k, t, x, p, x_new, impulse):
        action, next_phase, status, new, imp = self.model.reset(phase, k, x, p, t)
        x_new[:] = new
        impulse[: len(imp)] = imp
        return action, next_phase, status

    def swing_foot(self, x, p):
        """(height above the slope, distance ahead along it) of the kneed walker's swing
        foot: its compiled contact guard and drawing points."""
        pts = self.model.points(x, p)
        d = pts[-1] - pts[0]
        slope = p[self.model.params_class.names().index("slope")]
        ahead = d[0] * math.cos(slope) - d[1] * math.sin(slope)
        return self.model.guards(0, x, p)[1], ahead


class NumpyKneed(_ScipyKneed):
    """The hand-written kneed walker as a solve_ivp user writes it: scalar math in the
    vector fields (:func:`kneed_source`), the knee-lock and heel-strike guards in closed
    form, and walker's impact maps (``reset`` of walker.models.kneed) at the events."""

    def __init__(self, params):
        from walker.models import get_model

        pv = check_kneed_params(params)
        make, self.source = kneed_factory()
        f3, f2 = make(pv, math.cos, math.sin, np.array)
        self.p = params.as_array()
        self.reset = _array_api(get_model("kneed")).reset
        slope = float(params.slope)
        L = params.shank_length + params.thigh_length
        cos, sin = math.cos, math.sin

        def rhs3(t, y):
            q1, q2, q3, w1, w2, w3 = y.tolist()
            return f3(q1, q2, q3, w1, w2, w3)

        def rhs2(t, y):
            q1, q2, w1, w2 = y.tolist()
            return f2(q1, q2, w1, w2)

        def knee(t, y):
            return y[2] - y[1]

        def heel(t, y):
            # Swing-foot height above the slope (knee locked, point feet); a contact behind
            # the stance foot (the mid-stance scuff) is not a heel strike.
            q1, q2 = y[0] + slope, y[1] + slope
            if sin(q2) - sin(q1) <= 1e-8:
                return 1.0
            return L * (cos(q1) - cos(q2))

        knee.terminal, knee.direction = True, 1.0
        heel.terminal, heel.direction = True, -1.0
        self.unlocked, self.locked, self.knee, self.heel = rhs3, rhs2, knee, heel

    def to_locked(self, x6):
        # The locked swing has (q1, q2, w1, w2): the knee angle equals the thigh's.
        return np.array([x6[0], x6[1], x6[3], x6[4]])

    def from_locked(self, y):
        q1, q2, w1, w2 = y
        return np.array([q1, q2, q2, w1, w2, w2])


class CompiledKneed(_ScipyKneed):
    """solve_ivp on walker's own compiled kneed vector field (``rhs`` of
    walker.models.kneed, called from Python), its compiled guards as terminal events and
    its impact maps: only the integrator and its Python loop differ from walker."""

    def __init__(self, params):
        from walker.models import get_model

        m = _array_api(get_model("kneed"))
        self.p = p = params.as_array()
        self.reset = m.reset
        rhs, guards = m.rhs, m.guards
        g = np.empty(len(m.guard_names))

        def f0(t, y):
            dy = np.empty(6)
            rhs(0, t, y, p, dy)
            return dy

        def f1(t, y):
            dy = np.empty(6)
            rhs(1, t, y, p, dy)
            return dy

        swing_foot = m.swing_foot

        def knee(t, y):
            guards(0, t, y, p, g)
            return g[0]

        def heel(t, y):
            if swing_foot(y, p)[1] <= 1e-8:
                return 1.0
            guards(1, t, y, p, g)
            return g[1]

        knee.terminal, knee.direction = True, 1.0
        heel.terminal, heel.direction = True, -1.0
        self.unlocked, self.locked, self.knee, self.heel = f0, f1, knee, heel


def _impact_parts(obj, t0, params, name):
    """What a heyoka contender keeps once its integrators are built (``t0``: when their
    building began): the build time, the parameter vector, walker's impact map of model
    ``name`` and its output buffers."""
    from walker.models import get_model

    obj.compile_seconds = time.perf_counter() - t0
    obj.p = params.as_array()
    obj.reset = _array_api(get_model(name)).reset
    obj._imp = np.zeros(2)
    obj._x = np.empty(get_model(name).n_x)


class HeyokaKneed:
    """The kneed stride with heyoka: one Taylor integrator per phase (unlocked: 6 states,
    knee-lock event ``q3 - q2`` rising; locked: 4 states, heel-strike event = swing-foot
    height falling), built from the same generated equations as the numpy model with
    heyoka's ``cos``/``sin``.  ``runtime_pars``: model parameters as ``heyoka.par[i]``
    (one compiled integrator serves every parameter set); otherwise folded in as numbers
    (recompiled per parameter set)."""

    def __init__(self, params, tol, runtime_pars):
        import heyoka as hy

        make, _ = kneed_factory()
        pv = check_kneed_params(params)
        slope = float(params.slope)
        L = params.shank_length + params.thigh_length
        if runtime_pars:
            pars_values = [*pv, slope, L]
            P = [hy.par[i] for i in range(len(pars_values))]
            kw3, kw2 = {"pars": pars_values[:10]}, {"pars": pars_values}
        else:
            P = [*pv, slope, L]
            kw3 = kw2 = {}
        q1, q2, q3, w1, w2, w3 = hy.make_vars("q1", "q2", "q3", "w1", "w2", "w3")
        f3, f2 = make(P[:10], hy.cos, hy.sin, tuple)
        s, L_ = P[10], P[11]
        t0 = time.perf_counter()
        knee = hy.t_event(q3 - q2, direction=hy.event_direction.positive)
        self.ta3 = hy.taylor_adaptive(
            list(zip((q1, q2, q3, w1, w2, w3), f3(q1, q2, q3, w1, w2, w3), strict=True)),
            [0.0] * 6,
            tol=tol,
            t_events=[knee],
            **kw3,
        )
        heel = hy.t_event(
            L_ * (hy.cos(q1 + s) - hy.cos(q2 + s)), direction=hy.event_direction.negative
        )
        self.ta2 = hy.taylor_adaptive(
            list(zip((q1, q2, w1, w2), f2(q1, q2, w1, w2), strict=True)),
            [0.0] * 4,
            tol=tol,
            t_events=[heel],
            **kw2,
        )
        _impact_parts(self, t0, params, "kneed")

    def stride(self, x0, t_span=5.0):
        ta3, ta2, p, x6, imp = self.ta3, self.ta2, self.p, self._x, self._imp
        ta3.time = 0.0
        ta3.state[:] = x0
        ta3.reset_cooldowns()
        oc = ta3.propagate_until(t_span)[0]
        if int(oc) != -1:
            return None, math.nan
        t1 = ta3.time
        action, phase, status = self.reset(0, 0, t1, ta3.state, p, x6, imp)
        if action == 2:
            return x6.copy(), t1
        if status != 0 or phase != 1:
            return None, t1
        ta2.time = t1
        st = ta2.state
        st[0], st[1], st[2], st[3] = x6[0], x6[1], x6[3], x6[4]
        ta2.reset_cooldowns()
        oc = ta2.propagate_until(t1 + t_span)[0]
        if int(oc) != -1:
            return None, math.nan
        t2 = ta2.time
        q1, q2, w1, w2 = ta2.state
        xe = np.array([q1, q2, q2, w1, w2, w2])
        action, phase, status = self.reset(1, 1, t2, xe, p, x6, imp)
        if status != 0 or action != 2:
            return None, t2
        return x6.copy(), t2


class HeyokaCompass:
    """The compass stride (point feet, no leg inertia, no dampers) with heyoka's Taylor
    integrator, the parameters folded in as numbers.  The compass gait of Goswami, Thuilot
    and Espiau (1998), its Lagrange equations written here in the leg angles from the
    vertical (walker's coordinates): the 2x2 mass matrix ``[[(m_H + m) L^2 + m a^2,
    -m b L cos(q1 - q2)], [., m b^2]]`` solved by Cramer's rule.  Terminal events: the swing
    foot's height above the slope, ``L (cos(q1 + slope) - cos(q2 + slope))``, falling through
    zero, where walker's reset tells a heel strike from a scuff (after a scuff the run goes
    on, the event's cooldown keeping it from firing again at once), and the stance leg 70
    degrees from the slope normal (walker's threshold)."""

    FALL = math.radians(70.0)

    def __init__(self, params, tol):
        import heyoka as hy

        for name in ("foot_radius", "inertia_leg", "damping_hip", "damping_ankle"):
            if getattr(params, name) != 0.0:
                raise ValueError(f"the heyoka compass needs {name} = 0")
        mh, m = float(params.mass_hip), float(params.mass_leg)
        a, b = float(params.com_from_foot), float(params.com_to_hip)
        g, s = float(params.g), float(params.slope)
        L = a + b
        q1, q2, w1, w2 = hy.make_vars("q1", "q2", "w1", "w2")
        m11 = (mh + m) * L * L + m * a * a
        m12 = -m * b * L * hy.cos(q1 - q2)
        m22 = m * b * b
        sd = hy.sin(q1 - q2)
        r1 = m * b * L * sd * w2 * w2 + ((mh + m) * L + m * a) * g * hy.sin(q1)
        r2 = -m * b * L * sd * w1 * w1 - m * b * g * hy.sin(q2)
        det = m11 * m22 - m12 * m12
        negative, positive = hy.event_direction.negative, hy.event_direction.positive
        t0 = time.perf_counter()
        self.ta = hy.taylor_adaptive(
            [
                (q1, w1),
                (q2, w2),
                (w1, (m22 * r1 - m12 * r2) / det),
                (w2, (m11 * r2 - m12 * r1) / det),
            ],
            [0.0] * 4,
            tol=tol,
            t_events=[
                hy.t_event(L * (hy.cos(q1 + s) - hy.cos(q2 + s)), direction=negative),
                hy.t_event(q1 + s - self.FALL, direction=positive),
                hy.t_event(q1 + s + self.FALL, direction=negative),
            ],
        )
        _impact_parts(self, t0, params, "compass")

    def stride(self, x0, t_span=20.0):
        ta = self.ta
        ta.time = 0.0
        ta.state[:] = x0
        ta.reset_cooldowns()
        for _ in range(6):
            if int(ta.propagate_until(t_span)[0]) != -1:
                return None, math.nan  # a fall, or no event before t_span
            te, xe = ta.time, ta.state
            action, _, status = self.reset(0, 0, te, xe, self.p, self._x, self._imp)
            if action == 2 and status == 0:
                return self._x.copy(), te
            if action != 0:
                return None, te  # a nonphysical impact
        return None, ta.time


class CompiledSimple:
    """solve_ivp on walker's compiled vector field of a one-phase walker (``compass`` or
    ``simplest``): the model module's ``rhs`` called from Python, hand-written heel-strike
    and fall events, walker's impact map (``reset``) at the heel strike.

    Compass (point feet): the heel-strike event is the swing foot's height above the slope,
    ``L (cos(q1 + slope) - cos(q2 + slope))``, falling through zero; walker's reset decides
    whether it is a heel strike or a scuff (swing foot not ahead), and after a scuff the
    integration continues to the height's next rise through zero before watching for the
    next fall through it (three segments at most per stride for a rigid-legged walker).
    Simplest: ``phi - 2 theta`` rising through zero with ``theta < 0`` (Garcia's; the
    mid-stance scuff crosses it downward with ``theta > 0``).  Fall: the stance leg 70
    degrees from the slope normal (walker's threshold), terminal.
    """

    FALL = math.radians(70.0)

    def __init__(self, name, params):
        from walker.models import get_model

        model = get_model(name)
        m = _array_api(model)
        self.model = model
        self.p = p = params.as_array()
        self.reset = m.reset
        rhs = m.rhs
        n = model.n_x
        fall_angle = self.FALL

        def f(t, y):
            dy = np.empty(n)
            rhs(0, t, y, p, dy)
            return dy

        cos = math.cos
        if name == "compass":
            if params.foot_radius != 0.0:
                raise ValueError("the compass baseline needs point feet")
            slope = float(params.slope)
            L = params.leg_length

            def down(t, y):
                return L * (cos(y[0] + slope) - cos(y[1] + slope))

            def up(t, y):
                return L * (cos(y[0] + slope) - cos(y[1] + slope))

            def fall(t, y):
                return abs(y[0] + slope) - fall_angle

            down.direction, up.direction = -1.0, 1.0
            up.terminal = True
        elif name == "simplest":

            def down(t, y):
                # Garcia's heel strike: phi - 2 theta rising through zero with theta < 0
                # (just after heel strike it starts at zero and rises; the mid-stance scuff
                # crosses it downward with theta > 0).
                return y[1] - 2.0 * y[0] if y[0] < 0.0 else -1.0

            def fall(t, y):
                return abs(y[0]) - fall_angle

            down.direction = 1.0
            up = None
        else:
            raise ValueError(name)
        down.terminal = True
        fall.terminal, fall.direction = True, 1.0
        self.f, self.heel, self.up, self.fall, self.n = f, down, up, fall, n

    def stride(self, x0, method="DOP853", rtol=1e-10, atol=1e-10, t_span=20.0):
        from scipy.integrate import solve_ivp

        def until(event, t0, x):
            """The run from ``(t0, x)`` to the first ``event`` (terminal) or fall."""
            return solve_ivp(
                self.f,
                (t0, t_span),
                x,
                method=method,
                rtol=rtol,
                atol=atol,
                events=[event, self.fall],
            )

        x = np.asarray(x0, dtype=float)
        t, nfev = 0.0, 0
        x_new = np.empty(self.n)
        for _ in range(6):
            sol = until(self.heel, t, x)
            nfev += sol.nfev
            if sol.status != 1 or len(sol.t_events[1]) or not len(sol.t_events[0]):
                return None, np.nan, nfev  # fell, or no heel strike in t_span
            te, xe = sol.t_events[0][0], sol.y_events[0][0]
            action, _, status = self.reset(0, 0, te, xe, self.p, x_new, np.zeros(2))
            if action == 2 and status == 0:
                return x_new.copy(), te, nfev
            if action != 0 or self.up is None:
                return None, te, nfev  # a nonphysical impact
            # A scuff: go on to the height's next rise through zero, then watch again.
            sol = until(self.up, te, xe)
            nfev += sol.nfev
            if sol.status != 1 or len(sol.t_events[1]) or not len(sol.t_events[0]):
                return None, np.nan, nfev
            t, x = sol.t_events[0][0], sol.y_events[0][0]
        return None, t, nfev


def section_map(name, stride_obj, params):
    """``z -> P(z)`` on walker's section through ``stride_obj.stride`` and walker's
    lift/project (``get_model(name).lift/.project``); None when the stride fails."""
    from walker.models import get_model

    model = get_model(name)
    p = params.as_array()

    def P(z, rtol, atol, method="DOP853"):
        x, _, _ = stride_obj.stride(model.lift(z, p), method=method, rtol=rtol, atol=atol)
        return None if x is None else model.project(x, p)

    return P
