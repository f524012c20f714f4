"""The joint-limit region: its limits, the worst states over it, and the torque scale."""
import numpy as np
import pinocchio as pin
import pytest

from gd_analyze import load_robot
from gd_analyze.certify.region import (
    channel_values,
    full_channels,
    joint_region,
    missing_limits,
    qd_vertices,
    region_scale,
    sample_positions,
    worst_states,
)
from gd_analyze.cli.parsing import analyze_parser
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.errors import InputError
from gd_analyze.model.limits import LIMITS


def _rnea(robot, q, qd, qdd):
    model = pinocchio_model(robot)
    data = model.createData()
    return np.array([pin.rnea(model, data, a, b, c) for a, b, c in zip(q, qd, qdd)])


def test_region_of_the_robots_limits_and_the_missing_ones():
    robot = load_robot("ur5")                   # +-2 pi: more than a turn is the full circle
    region = joint_region(robot, np.full(6, 3.0))
    assert np.all(region.q_min[[0, 1, 3, 4, 5]] == -np.pi) and region.q_max[2] == np.pi
    assert missing_limits(load_robot("puma560")) == ""
    spec = load_robot("two-link")
    from dataclasses import replace
    assert missing_limits(replace(spec, qd_max=np.array([1.0, np.nan]))) == \
        "joint 2 has no velocity limit"
    with pytest.raises(ValueError, match="joint 2"):
        joint_region(replace(spec, qd_max=np.array([1.0, np.nan])), np.ones(2))
    q = sample_positions(region, 50)
    ok = region.contains(q, np.zeros_like(q), np.zeros_like(q))
    assert ok.all() and region.full_turn.all()      # every UR5 joint turns freely: any angle
    assert region.contains(q + 10, q * 0, q * 0)[0].all()
    puma = load_robot("puma560")
    limited = joint_region(puma, puma.qdd_max)
    q = sample_positions(limited, 50)
    assert not limited.contains(q + 10, q * 0, q * 0)[0][:5].any()


def _contains_elementwise(region, q, qd, qdd, rtol=1e-9):
    """The definition, state by state: each q within its limits (a full-turn joint's angle
    taken into [-pi, pi)), |qd| and |qdd| within theirs, up to rtol."""
    q = np.where(region.full_turn, np.mod(q + np.pi, 2 * np.pi) - np.pi, q)
    span = np.maximum(np.abs(region.q_max - region.q_min), 1e-300)
    return np.stack([
        np.all((q >= region.q_min - rtol * span) & (q <= region.q_max + rtol * span), axis=0),
        np.all(np.abs(qd) <= region.qd_max * (1 + rtol), axis=0),
        np.all(np.abs(qdd) <= region.qdd_max * (1 + rtol), axis=0)])


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_contains_is_the_statewise_definition_with_nan_and_inf(name):
    """contains (column extremes) equals the state-by-state definition on states inside,
    just outside (either side, each quantity) and holding NaN or +-inf."""
    robot = load_robot(name)
    region = joint_region(robot, robot.qdd_max if name == "puma560" else np.full(6, 3.0))
    rng = np.random.default_rng(5)
    q = sample_positions(region, 40)
    qd = rng.uniform(-1, 1, q.shape) * region.qd_max
    qdd = rng.uniform(-1, 1, q.shape) * region.qdd_max
    assert region.contains(q, qd, qdd).all()
    cases = []
    for k, x in enumerate((q, qd, qdd)):
        for bad in (1.1, -1.1, np.nan, np.inf, -np.inf):
            arrays = [q.copy(), qd.copy(), qdd.copy()]
            j = int(rng.integers(6))
            limit = (region.q_max if bad > 0 else region.q_min) if k == 0 and np.isfinite(
                bad) else (region.qd_max, region.qdd_max)[k - 1] if k else 0.0
            arrays[k][int(rng.integers(40)), j] = (
                bad if not np.isfinite(bad) else limit[j] * abs(bad) * np.sign(bad)
                + (0.1 * np.sign(bad) if k == 0 else 0.0))
            # a full-turn joint's angle wraps: any finite angle lies inside
            cases.append((arrays, k == 0 and region.full_turn[j] and np.isfinite(bad)))
    for arrays, inside in cases:
        got = region.contains(*arrays)
        assert got.all() == inside
        assert np.array_equal(got, _contains_elementwise(region, *arrays))
    assert region.contains(q[:0], qd[:0], qdd[:0]).all()


def test_worst_states_are_states_of_the_region_and_the_largest_over_the_vertices():
    """At each sampled position, the torque at the state worst_states returns equals its value
    (Pinocchio's rnea), and no vertex of the velocity and acceleration limits gives more."""
    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, 20, seed=3)[:20]
    V = channel_values(robot, q, cols)
    value, qd, qdd = worst_states(V, np.tile(base.beta, (3, 1)), region.qd_max, region.qdd_max)
    n = robot.n
    for i in range(n):
        tau = _rnea(robot, q, qd[:, i], qdd[:, i])[:, i]
        np.testing.assert_allclose(np.abs(tau), value[:, i], rtol=1e-9)
    rng = np.random.default_rng(0)
    for _ in range(20):                     # every vertex, not only qd_vertices' half
        sd = rng.choice([-1.0, 1.0], n) * region.qd_max
        sdd = rng.choice([-1.0, 1.0], n) * region.qdd_max
        tau = _rnea(robot, q, np.tile(sd, (20, 1)), np.tile(sdd, (20, 1)))
        assert np.all(np.abs(tau) <= value * (1 + 1e-9))


@pytest.mark.parametrize("name", ("puma560", "ur5"))
def test_worst_states_of_a_few_columns_search_only_their_joints_and_miss_nothing(name):
    """Weights on a few base parameters involve a few joints' velocities: the largest |tau_i|
    over the 2^(n-1) vertices searched on those joints only equals the brute force over every
    vertex of the velocity box (all 2^n sign patterns), and Pinocchio's rnea gives that value
    at the returned state (the regressor times the kept parameters)."""
    robot = load_robot(name)
    base = base_parameters(robot)
    region = joint_region(robot, np.full(robot.n, 3.0))
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, 6, seed=5)[:6]
    V = channel_values(robot, q, cols)
    n, b = robot.n, cols.size
    everything = np.array(list(__import__("itertools").product([-1.0, 1.0], repeat=n)))
    model = pinocchio_model(robot)
    data = model.createData()
    order = np.array([4, 5, 7, 6, 8, 9, 1, 2, 3, 0])        # ours (XX .. ZZ, MX .. M) in pin's
    pcols = 10 * (cols // 10) + order[cols % 10]
    reduced = 0
    for k in range(0, b, 2):
        weights = np.zeros((3, b))
        weights[:, k:k + 2] = np.asarray(base.beta, float)[k:k + 2]
        value, qd, qdd = worst_states(V, weights, region.qd_max, region.qdd_max)
        F = full_channels(V)
        Cq = F[:, 1 + n:] @ weights[1]                                  # (B, n n, n)
        vert = everything * region.qd_max
        quad = np.einsum("kj,kl,bjli->bik", vert, vert, Cq.reshape(-1, n, n, n)) + (
            F[:, 0] @ weights[2])[:, :, None]
        a = np.einsum("bjim,m->bij", F[:, 1:1 + n], weights[0])
        brute = np.abs(quad).max(axis=2) + np.abs(a) @ region.qdd_max
        np.testing.assert_allclose(value, brute, rtol=1e-12, atol=1e-12 * brute.max())
        reduced += int(np.any(np.all(Cq.reshape(-1, n, n, n) == 0, axis=(0, 2, 3))))
        for i in range(n):                  # Pinocchio's regressor times the kept columns
            tau = [pin.computeJointTorqueRegressor(model, data, q[p], qd[p, i], qdd[p, i])[
                i, pcols] @ weights[0] for p in range(q.shape[0])]
            np.testing.assert_allclose(np.abs(tau), value[:, i], rtol=1e-9,
                                       atol=1e-9 * max(value.max(), 1e-300))
    assert reduced > 0                      # some pairs involve fewer than n joints


def test_the_scale_is_reached_where_it_says():
    robot = load_robot("stanford")             # a prismatic joint
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    scale, state = region_scale(robot, region, cols, base.beta, samples=200)
    n = robot.n
    tau = _rnea(robot, state[:, :n], state[:, n:2 * n], state[:, 2 * n:])
    np.testing.assert_allclose(np.abs(tau[np.arange(n), np.arange(n)]), scale, rtol=1e-9)
    assert np.all(state[:, :n] >= region.q_min - 1e-12) and np.all(state[:, :n] <= region.q_max)
    assert np.all(np.abs(state[:, n:2 * n]) <= region.qd_max * (1 + 1e-12))
    floor = region_scale(robot, region, cols, base.beta, torque_floor=1e6, samples=20,
                         refine=0)[0]
    assert np.all(floor == 1e6)


def test_the_scale_of_a_range_narrower_than_the_local_search_s_step():
    """A joint range under the polish's 1e-6 difference step (--q-limits 10:10.00001, a
    URDF's lower="0" upper="1e-12") gave L-BFGS-B an upper bound below its lower one: an
    internal error, exit 4. Oracle: Pinocchio's rnea at the state named, within the range."""
    import dataclasses

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    q_min, q_max = region.q_min.copy(), region.q_max.copy()
    q_min[1], q_max[1] = 0.1, 0.1 + 1e-9
    region = dataclasses.replace(region, q_min=q_min, q_max=q_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    scale, state = region_scale(robot, region, cols, base.beta, samples=50)
    n = robot.n
    tau = _rnea(robot, state[:, :n], state[:, n:2 * n], state[:, 2 * n:])
    np.testing.assert_allclose(np.abs(tau[np.arange(n), np.arange(n)]), scale, rtol=1e-9)
    assert np.all(state[:, 1] >= 0.1) and np.all(state[:, 1] <= 0.1 + 1e-9)


def test_the_vertices_are_one_of_each_opposite_pair():
    """Half the box's vertices, one of each pair x, -x: together with their negatives, all."""
    qd_max = np.array([1.0, 2.0, 0.5, 3.0])
    verts = qd_vertices(qd_max)
    both = {tuple(v) for v in np.vstack([verts, -verts])}
    assert len(verts) == 8 and len(both) == 16
    assert both == {tuple(np.array(s) * qd_max) for s in
                    __import__("itertools").product([-1.0, 1.0], repeat=4)}


def test_one_joint_has_one_vertex():
    """One joint: the pair (qd_max, -qd_max) is one vertex, qd_max itself."""
    assert qd_vertices(np.array([1.5])).tolist() == [[1.5]]


@pytest.mark.parametrize("name", ("puma560", "stanford"))
def test_channel_values_rebuild_rnea(name):
    """The channels rebuild Pinocchio's rnea at a random state (tau = A qdd + qd^T C qd + G)."""
    robot = load_robot(name)
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = sample_positions(region, 30, seed=5)
    V = full_channels(channel_values(robot, q, cols))
    n = robot.n
    rng = np.random.default_rng(2)
    qd, qdd = rng.uniform(-1, 1, (q.shape[0], n)), rng.uniform(-1, 1, (q.shape[0], n))
    Y = V @ base.beta                                   # (B, C, n)
    tau = Y[:, 0] + np.einsum("bji,bj->bi", Y[:, 1:1 + n], qdd) + np.einsum(
        "bjli,bj,bl->bi", Y[:, 1 + n:].reshape(-1, n, n, n), qd, qd)
    ref = _rnea(robot, q, qd, qdd)
    assert np.abs(tau - ref).max() <= 1e-10 * np.abs(ref).max()


#: :func:`_pinocchio_parts`'s results by arm and state.
_PARTS: dict = {}


def _pinocchio_parts(robot, q, qd):
    """Pinocchio's mass matrix M(q), velocity torque h(q, qd) (no gravity) and gravity g(q):
    computed once per process for the same arm and state (the cases of
    :func:`test_the_sampled_error_of_dropped_parts_is_pinocchios_largest` ask for the same
    states, whatever parts they drop); read only."""
    key = (robot.name, robot.sha256, np.asarray(q, float).tobytes(),
           np.asarray(qd, float).tobytes())
    if key not in _PARTS:
        model = pinocchio_model(robot)
        data = model.createData()
        M = np.triu(pin.crba(model, data, q))
        g = pin.computeGeneralizedGravity(model, data, q).copy()
        model.gravity.linear = np.zeros(3)
        h = pin.rnea(model, model.createData(), q, qd, np.zeros(robot.n)).copy()
        _PARTS[key] = (M + np.triu(M, 1).T, h, g)
        for a in _PARTS[key]:
            a.setflags(write=False)
    return _PARTS[key]


@pytest.mark.parametrize("parts", [(0, 0, 1), (0, 1, 1), (1, 0, 0), (1, 1, 0), (1, 1, 1)])
def test_the_sampled_error_of_dropped_parts_is_pinocchios_largest(parts):
    """A trajectory model's ``region_sampled_error`` by sampling only. Dropping
    whole parts (inertial, velocity, gravity) of every base parameter, the error at a
    position is, by Pinocchio, sum_j |M_ij| qdd_max_j + the largest |h_i + g_i| over every
    vertex of the velocity box; the function gives its largest value over the sampled
    positions relative to s_i, and the state where it says it found it gives that error."""
    import itertools

    from gd_analyze.certify.region import region_samples, sampled_error

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    values = region_samples(robot, base, region, samples=40, seed=5)
    dropped = np.tile(np.array(parts, bool), (base.beta.size, 1))
    error, state = sampled_error(base, region, dropped, values)
    q, scale, n = values[0], values[2], robot.n
    inertial, velocity, gravity = parts
    verts = np.array(list(itertools.product([-1.0, 1.0], repeat=n))) * region.qd_max
    worst = np.zeros(n)
    for x in q:
        M, _, g = _pinocchio_parts(robot, x, np.zeros(n))
        quad = np.array([velocity * _pinocchio_parts(robot, x, v)[1] for v in verts]) + gravity * g
        worst = np.maximum(worst, inertial * np.abs(M) @ region.qdd_max
                           + np.abs(quad).max(axis=0))
    np.testing.assert_allclose(error, worst / scale, rtol=1e-9, atol=1e-12)   # 0: round-off
    for i in range(n):                       # the witness state gives the error it reports
        x, xd, xdd = state[i, :n], state[i, n:2 * n], state[i, 2 * n:]
        M, h, g = _pinocchio_parts(robot, x, xd)
        tau = inertial * M @ xdd + velocity * h + gravity * g
        np.testing.assert_allclose(abs(tau[i]), error[i] * scale[i], rtol=1e-9,
                                   atol=1e-12 * scale[i])
        assert np.all(np.abs(xdd) <= region.qdd_max * (1 + 1e-12))
    full = _rnea(robot, values[3][:, :n], values[3][:, n:2 * n], values[3][:, 2 * n:])
    np.testing.assert_allclose(np.abs(full[np.arange(n), np.arange(n)]), scale, rtol=1e-9)


def test_the_samples_are_those_a_certification_draws():
    """A certification made in the process is read in place of the samples
    (:func:`gd_analyze.simplify.region_memo.region_values`): the same positions, values and
    scale for the same count and seed."""
    from gd_analyze.certify.certify import certify
    from gd_analyze.certify.region import region_samples

    robot = load_robot("puma560")
    base = base_parameters(robot)
    region = joint_region(robot, robot.qdd_max)
    q, V, scale, state = region_samples(robot, base, region, samples=30)
    pb = certify(robot, base, region, max_boxes=2, samples=30)
    assert np.array_equal(pb.positions, q) and np.array_equal(pb.values.packed(), V.packed())
    assert np.array_equal(pb.scale, scale) and np.array_equal(pb.scale_state, state)


# --- the user's region ----------------------------------------------------------------------------
from gd_analyze.certify.region import FULL_TURN, Region, RegionLimits  # noqa: E402


@pytest.mark.parametrize("kwargs, option", [
    (dict(qd_max=(float("nan"),)), "--qd-max"), (dict(qd_max=(-1.0,)), "--qd-max"),
    (dict(qdd_max=(float("inf"),)), "--qdd-max"), (dict(qdd_max=(0.0,)), "--qdd-max"),
    (dict(q_limits=((1.0, float("nan")),)), "--q-limits"),
    (dict(q_limits=((1.0, 0.5),)), "--q-limits")])
def test_region_limits_refuse_nan_inf_and_negative_naming_the_option(kwargs, option):
    with pytest.raises(ValueError, match=f"^{option}:"):
        RegionLimits(**kwargs)


@pytest.mark.parametrize("kwargs, option", [
    (dict(qd_max=(True,)), "--qd-max"), (dict(qdd_max="2"), "--qdd-max"),
    (dict(q_limits=((0.0, "a"),)), "--q-limits"), (dict(q_limits=((False, True),)), "--q-limits")])
def test_region_limits_refuse_a_bool_or_str_naming_the_option(kwargs, option):
    """RegionLimits(qd_max=(True,)) was a limit of 1 rad/s and qdd_max="2" one of 2 rad/s^2,
    read through float(); q_limits=((0.0, "a"),) raised numpy's "could not convert string to
    float: 'a'", naming no option."""
    with pytest.raises(ValueError, match=f"^{option} must hold real numbers, got "):
        RegionLimits(**kwargs)


@pytest.mark.parametrize("field", ["qd_max", "qdd_max"])
def test_region_limits_refuse_what_the_command_line_refuses(field):
    """RegionLimits(qd_max=(1e-320,)) was accepted through the API though --qd-max refuses
    anything below 1e-9 deg/s (a denormal limit overflows a planned duration): the least the
    command line passes on, 1e-9 deg/s in rad/s, is the least the API takes."""
    least = float(np.radians(LIMITS["least_rate"]))
    option = "--" + field.replace("_", "-")
    for tiny in (1e-320, least * (1 - 1e-9)):
        with pytest.raises(ValueError, match=f"^{option}: every limit must be finite and at "
                                             f"least 1.745e-11, got "):
            RegionLimits(**{field: (1.0, tiny)})
        with pytest.raises(InputError, match=f"{option} limits must be at least"):
            analyze_parser().parse_intermixed_args(["puma560", "t.csv", option, f"{tiny!r}"])
    assert getattr(RegionLimits(**{field: (least,)}), field) == (least,)
    # the command line's least (in degrees) reaches the API as exactly that least
    assert analyze_parser().parse_intermixed_args(
        ["puma560", "t.csv", option, "1e-9"]).__dict__[field] == [1e-9]


def test_users_region_replaces_the_robots_and_is_clipped_to_its_limits():
    robot = load_robot("puma560")               # joint 1 [-160, 160] deg, qd 100 deg/s
    own = joint_region(robot, robot.qdd_max)
    wide = joint_region(robot, robot.qdd_max, RegionLimits(
        q_limits=((np.radians(-200), np.radians(30)),), qd_max=(np.radians(500),)))
    assert wide.q_min[0] == robot.q_min[0] and wide.q_max[0] == pytest.approx(np.radians(30))
    np.testing.assert_array_equal(wide.qd_max, own.qd_max)       # never above the robot's
    assert any("joint 1's lower position limit -200 deg" in n and "clipped to -160" in n
               for n in wide.notes)
    assert any("velocity limit 500 deg/s" in n for n in wide.notes)
    with pytest.raises(ValueError, match="--q-limits: joint 1's range lies outside"):
        joint_region(robot, robot.qdd_max, RegionLimits(
            q_limits=((np.radians(170), np.radians(180)),)))
    with pytest.raises(ValueError, match="--qd-max: 2 values for 6 joints"):
        joint_region(robot, robot.qdd_max, RegionLimits(qd_max=(1.0, 2.0)))


def test_full_turn_and_assumed_accelerations_are_printed_and_stored():
    robot = load_robot("ur5")                   # +-360 deg: a full turn; no qdd in a URDF
    from gd_analyze.simplify.deploy import robot_region

    region, missing = robot_region(robot)
    assert missing == "" and region.full_turn[[0, 1, 3, 4, 5]].all()
    assert region.assumed.all() and region.qdd_max == pytest.approx(2 * region.qd_max)
    lines = region.lines()
    assert lines[0].startswith("region: q [deg] 1 any angle (full turn), 2 any angle")
    assert "[-180, 180]" not in lines[0] and "[-360, 360]" not in lines[0]
    assert lines[2].startswith("qdd max [deg/s^2] (assumed: 2 s^-1 x qd max) 1 ")
    spec = region.to_dict()
    assert spec["q"][0] == FULL_TURN and spec["qdd_max_assumed"] == [True] * 6
    back = Region.from_dict(spec, 6)
    np.testing.assert_array_equal(back.q_min, region.q_min)
    np.testing.assert_array_equal(back.full_turn, region.full_turn)
    narrow, _ = robot_region(robot, RegionLimits(q_limits=((-1.0, 1.0),), qdd_max=(3.0,)))
    assert not narrow.full_turn.any() and not narrow.assumed.any()
    assert "assumed" not in narrow.lines()[2]


def test_excursion_names_joint_quantity_and_true_extreme():
    region = Region(np.array([-1.0, -np.pi]), np.array([1.0, np.pi]), np.array([2.0, 2.0]),
                    np.array([50.0, 50.0]))
    t = np.linspace(0, 1, 11)[:, None]
    qd = np.hstack([4.1 * t, 0 * t])                  # joint 1 reaches 4.1 > 2 at the end
    out = region.excursion(np.zeros((11, 2)), qd, np.zeros((11, 2)))
    assert (out.joint, out.quantity) == (0, "qd") and out.value == pytest.approx(4.1)
    assert out.ratio == pytest.approx(2.05)
    assert out.text().startswith("joint 1 qd reaches 2.05x its limit (234.9 deg/s > 114.6")
    q = np.hstack([0 * t, 7.0 * t])                   # joint 2 turns freely: inside
    assert region.excursion(q, 0 * q, 0 * q) is None


@pytest.mark.slow
def test_narrower_region_gives_smaller_scale_against_rnea():
    """s_i over a user's narrower region is below the robot's; Pinocchio's rnea at random
    states of each region stays below its s_i (the scale is a largest |tau_i| found), and
    the narrower region's sampled maximum below the wider region's s_i."""
    from gd_analyze.simplify.deploy import certified, robot_region

    robot = load_robot("puma560")
    base = base_parameters(robot)
    wide, _ = robot_region(robot)
    narrow, _ = robot_region(robot, RegionLimits(qd_max=(np.radians(30),),
                                                 qdd_max=(np.radians(20),)))
    s_wide = certified(robot, base, wide).scale
    s_narrow = certified(robot, base, narrow).scale
    assert (s_narrow <= s_wide * (1 + 1e-9)).all() and (s_narrow < s_wide).any()
    rng = np.random.default_rng(7)
    for region, scale in ((wide, s_wide), (narrow, s_narrow)):
        N = 3000
        q = rng.uniform(region.q_min, region.q_max, (N, 6))
        qd = rng.uniform(-1, 1, (N, 6)) * region.qd_max
        qd[: N // 2] = np.sign(qd[: N // 2]) * region.qd_max        # vertices
        qdd = np.sign(rng.uniform(-1, 1, (N, 6))) * region.qdd_max
        tau = np.abs(_rnea(robot, q, qd, qdd)).max(axis=0)
        assert (tau <= scale * (1 + 1e-9)).all(), (tau, scale)
        if region is narrow:
            assert (tau <= s_wide).all()


def test_mixed_arm_prints_each_limit_with_its_unit():
    """The Stanford arm's prismatic joint 3 in metres beside degrees (its TOML's limits)."""
    from gd_analyze.simplify.deploy import robot_region

    robot = load_robot("stanford")
    region, _ = robot_region(robot)
    q, qd, qdd = region.lines()
    assert f"3 [{robot.q_min[2]:.4g}, {robot.q_max[2]:.4g}] m" in q
    assert f"1 [{np.degrees(robot.q_min[0]):.4g}, {np.degrees(robot.q_max[0]):.4g}] deg" in q
    assert f"3 {robot.qd_max[2]:.4g} m/s" in qd and f"3 {robot.qdd_max[2]:.4g} m/s^2" in qdd
    assert not region.full_turn[2]


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_channel_values_store_each_velocity_pair_once(name):
    """The packed layout holds 1 + n + n (n + 1) / 2 channels; unpacked, C_jl = C_lj exactly,
    and the forms qd^T C qd rebuild Pinocchio's rnea with qdd = 0 and no gravity (oracle)."""
    from gd_analyze.certify.region import packed_channel_count, velocity_channels

    robot = load_robot(name)
    base = base_parameters(robot)
    n = robot.n
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = np.random.default_rng(3).uniform(robot.q_min, robot.q_max, (9, n))
    V = channel_values(robot, q, cols)
    assert V.packed().shape == (9, packed_channel_count(n), n, cols.size)
    assert (V.positions, V.columns) == (9, cols.size)
    held = sum(Vm.size for _, _, Vm in V.groups)
    assert held < V.packed().size
    assert sorted(set(velocity_channels(n).tolist())) == list(range(n * (n + 1) // 2))
    C = full_channels(V)[:, 1 + n:].reshape(9, n, n, n, -1)
    assert np.array_equal(C, C.transpose(0, 2, 1, 3, 4))
    qd = np.random.default_rng(4).uniform(-1, 1, (9, n))
    vel = np.einsum("bjlim,bj,bl,m->bi", C, qd, qd, base.beta)
    zero = np.zeros_like(qd)
    ref = _rnea(robot, q, qd, zero) - _rnea(robot, q, zero, zero)
    assert np.abs(vel - ref).max() <= 1e-10 * np.abs(ref).max()


def test_channel_values_are_the_regressor_at_the_channels_states():
    """Oracle: the regressor (array code) at the states that isolate each channel, as the
    channels were once computed, on a random 12-joint chain with prismatic joints and oblique
    axes: G = W(q, 0, 0), A_j + C_jj = W(q, e_j, e_j) and C_jj = W(q, e_j, 0) with g = 0,
    C_jl = (W(q, e_j + e_l, 0) - C_jj - C_ll) / 2; within 1e-12 of each column's scale."""
    from symbolic_helpers import mixed_chain

    from gd_analyze.dynamics.regressor_kernels import regressor_columns

    robot = mixed_chain(12, seed=4)
    n = robot.n
    base = base_parameters(robot)
    cols = np.flatnonzero(base.independent.reshape(-1))
    q = np.random.default_rng(6).uniform(-2.0, 2.0, (4, n))
    got = full_channels(channel_values(robot, q, cols))             # (B, 1 + n + n n, n, m)
    B, eye, g0 = q.shape[0], np.eye(n), np.zeros(3)
    rep = np.repeat(q, n, axis=0)
    zero = np.zeros_like(rep)
    units = np.tile(eye, (B, 1))
    G = regressor_columns(robot, cols, q, q * 0, q * 0)
    diag = regressor_columns(robot, cols, rep, units, zero, gravity=g0).reshape(B, n, n, -1)
    both = regressor_columns(robot, cols, rep, units, units, gravity=g0).reshape(B, n, n, -1)
    ref = np.empty_like(got)
    ref[:, 0] = G
    ref[:, 1:1 + n] = both - diag
    for j in range(n):
        for l in range(n):
            if j == l:
                ref[:, 1 + n + n * j + l] = diag[:, j]
                continue
            W = regressor_columns(robot, cols, q, np.tile(eye[j] + eye[l], (B, 1)), q * 0,
                                  gravity=g0)
            ref[:, 1 + n + n * j + l] = 0.5 * (W - diag[:, j] - diag[:, l])
    scale = np.abs(ref).max(axis=(0, 1, 2))
    assert np.all(scale > 0)
    assert np.all(np.abs(got - ref) <= 1e-12 * scale)


def test_the_sampled_torques_above_a_limit_are_those_of_the_full_search():
    """Oracle: worst_states, every velocity vertex at every position. worst_above gives its
    largest |tau_i| wherever that exceeds the limit, and at most the limit elsewhere, for
    limits below, at and above the sampled maxima."""
    from gd_analyze.certify.region import worst_above

    robot = load_robot("panda")
    base = base_parameters(robot)
    region = joint_region(robot, np.full(robot.n, 3.0))
    cols = np.flatnonzero(base.independent.reshape(-1))
    V = channel_values(robot, sample_positions(region, 300), cols)
    W = np.tile(np.asarray(base.beta, float), (3, 1))
    want = worst_states(V, W, region.qd_max, region.qdd_max)[0].max(axis=0)
    for factor in (0.5, 0.9, 1.0, 1.0 + 1e-9, 2.0):
        limit = want * factor
        got = worst_above(V, W, region.qd_max, region.qdd_max, limit)
        above = want > limit
        np.testing.assert_array_equal(got[above], want[above])
        assert np.all(got[~above] <= limit[~above])
