"""The Python API for a notebook: what ``import gd_analyze as gd`` offers, each
checked against an oracle (Pinocchio) or against the command line's own output."""

import numpy as np
import pinocchio as pin
import pytest
from urdf_oracle import UrdfOracle

import gd_analyze as gd
from gd_analyze.dynamics.base_parameters import random_states as _random_states
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.urdf import builtin_urdf_path


def _rnea_oracle(name, robot):
    """Pinocchio's rnea: the shipped URDF's own model for the Panda, else the robot's chain."""
    if name == "panda":
        oracle = UrdfOracle(builtin_urdf_path("panda"), robot.metadata["urdf_joints"])
        return oracle.rnea
    model = pinocchio_model(robot)
    data = model.createData()
    return lambda q, v, a: pin.rnea(model, data, q, v, a)


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford"])
def test_regressor_times_beta_is_rnea(name):
    robot = gd.load_robot(name)
    q, qd, qdd = _random_states(robot, 100, seed=7)
    Y, beta = gd.regressor(robot, q, qd, qdd)
    assert Y.shape == (100, robot.n, beta.size) and beta.ndim == 1
    rnea = _rnea_oracle(name, robot)
    tau_ref = np.array([rnea(*s) for s in zip(q, qd, qdd)])
    scale = np.abs(tau_ref).max(axis=0)
    assert (scale > 0).all()
    assert np.max(np.abs(Y @ beta - tau_ref) / scale) < 1e-10
    # fewer columns than the 10 n standard parameters, and none of them zero
    assert beta.size < 10 * robot.n and np.abs(Y).max(axis=(0, 1)).min() > 0


def test_regressor_of_one_state_and_prismatic_joint_is_used():
    robot = gd.load_robot("stanford")
    assert robot.prismatic.any()
    q, qd, qdd = (x[0] for x in _random_states(robot, 1, seed=3))
    Y, beta = gd.regressor(robot, q, qd, qdd)
    assert Y.shape == (1, robot.n, beta.size)
    with pytest.raises(ValueError, match="expected shape"):
        gd.regressor(robot, q[:-1], qd, qdd)


# --- analyze: the results dataset in memory, the same as the main job's results.h5 ----------

import matplotlib  # noqa: E402

matplotlib.use("Agg")

from urdf_oracle import TOY_URDF  # noqa: E402

from gd_analyze.errors import InputError  # noqa: E402
from gd_analyze.jobs.run import run_analysis  # noqa: E402
from gd_analyze.store.schema import open_results  # noqa: E402

#: Joint names a URDF may hold that a file must keep as they are: quotes, markup, non-ASCII.
HOSTILE = ['j1 "α" </x>', "j2 '; DROP", "j3\tβ/../"]


def _xml_attr(text):
    return (text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;")
            .replace(">", "&gt;").replace("\t", "&#9;"))


@pytest.fixture(scope="module")
def toy_run(tmp_path_factory):
    """The toy URDF arm with hostile joint names, analysed in memory and by the main job."""
    text = TOY_URDF
    for old, new in zip(('name="j1"', 'name="j2"', 'name="j3"'), HOSTILE):
        text = text.replace(old, f'name="{_xml_attr(new)}"')
    robot = gd.load_robot(text, tip="tool")
    t = np.linspace(0.0, 2.0, 41)
    q = np.column_stack([np.sin(t), 0.1 * t, np.cos(2 * t) - 1])
    options = gd.AnalysisOptions(formulations=False,
                                 simplify=gd.SimplifyOptions(guarantee="trajectory"))
    memory = gd.analyze(robot, (t, q), options)
    out = tmp_path_factory.mktemp("toy")
    trajectory = gd.trajectory.trajectory.trajectory_from_arrays(t, q, n_joints=3)
    run_analysis(robot, trajectory, options, out, report=None)
    return robot, t, q, memory, open_results(out / "results.h5")


def test_joint_names_are_the_joint_coordinate_and_survive_the_file(toy_run):
    robot, _, _, memory, stored = toy_run
    assert robot.joint_names() == HOSTILE
    for ds in (memory, stored):
        assert ds.joint.values.tolist() == HOSTILE == ds.joint_k.values.tolist()
        assert ds.tau.sel(joint=HOSTILE[1]).dims == ("t",)
    puma = gd.load_robot("puma560")
    assert puma.joint_names() == [f"joint{i}" for i in range(1, 7)]
    assert pinocchio_model(puma).names[1:].tolist() == puma.joint_names()


def test_t_is_the_set_points_coordinate_in_seconds_and_plots(toy_run):
    import matplotlib.pyplot as plt

    _, t, _, memory, stored = toy_run
    for ds in (memory, stored):
        element = ds.D_tran.isel(joint=0, joint_k=2)
        assert element.dims == ("t",) and "t" in element.indexes
        assert element.t.attrs["units"] == "s"
        np.testing.assert_array_equal(element.t.values, t)
        line, = element.plot()
        np.testing.assert_array_equal(line.get_xdata(), t)
        assert "[s]" in line.axes.get_xlabel()
        plt.close("all")
        assert float(ds.D_tran.sel(t=t[5]).isel(joint=0, joint_k=0)) == \
            float(ds.D_tran[5, 0, 0])


def test_analyze_in_memory_is_the_main_jobs_results_file(toy_run):
    """One code path: every variable, coordinate, value and attribute of the dataset
    gd.analyze returns is in the main job's results.h5, and the other way round."""
    _, _, _, memory, stored = toy_run
    assert set(memory.variables) == set(stored.variables)
    assert set(memory.coords) == set(stored.coords)
    for name, var in memory.variables.items():
        other = stored[name]
        assert var.dims == other.dims, name
        assert var.attrs.keys() == other.attrs.keys(), name
        for key, value in var.attrs.items():        # an attribute may be an array (flags)
            np.testing.assert_array_equal(np.asarray(value), np.asarray(other.attrs[key]),
                                          err_msg=f"{name}.{key}")
        if var.dtype.kind in "fiu":
            np.testing.assert_array_equal(var.values, other.values, err_msg=name)
        else:
            assert np.asarray(var.values, str).tolist() == \
                np.asarray(other.values, str).tolist(), name
    assert set(memory.attrs) == set(stored.attrs)
    assert memory.attrs["verification_passed"] == stored.attrs["verification_passed"] == 1


def test_trajectory_as_arrays_mapping_or_file(toy_run):
    robot, t, q, memory, _ = toy_run
    trajectory = gd.trajectory.trajectory.trajectory_from_arrays(t, q, n_joints=3)
    as_mapping = gd.trajectory.trajectory.as_trajectory(
        {"t": t, "q": q, "qd": trajectory.qd, "qdd": trajectory.qdd})
    np.testing.assert_array_equal(as_mapping.qdd, trajectory.qdd)
    assert as_mapping.derivatives == "arrays" and trajectory.derivatives == "cubic-spline"
    assert gd.read_trajectory is gd.trajectory.trajectory.read_trajectory
    for bad, match in (((t[::-1], q[::-1]), "not strictly increasing"),
                       ((t, q[:, :2]), "2 joints, the robot has 3"),
                       ((t, q[:-1]), "shape"),
                       ((t, np.where(q > 0.5, np.nan, q)), "not finite"),
                       ((t, q, q), "Trajectory"),
                       ({"t": t, "x": q}, "unknown: x"),
                       (42, "not a int")):
        with pytest.raises(InputError, match=match):
            gd.analyze(robot, bad)


def test_a_robot_or_options_of_another_type_is_one_input_error():
    """A robot's name in place of the Robot, or options of another type, raised
    AttributeError ("'str' object has no attribute 'n'") from inside the job."""
    t = np.linspace(0.0, 1.0, 5)
    q = np.outer(t, [1.0, -0.5])
    robot = gd.load_robot("two-link")
    for call, match in ((lambda: gd.analyze("two-link", (t, q)), "load_robot.*not a str"),
                        (lambda: gd.analyze(None, (t, q)), "not a NoneType"),
                        (lambda: gd.analyze(robot, (t, q), {"dominance": 0.9}),
                         "AnalysisOptions, not a dict")):
        with pytest.raises(InputError, match=match):
            call()


@pytest.mark.parametrize("bad, kind", [(1e-3j, "complex128"), ("x", "<U")])
def test_complex_and_text_arrays_are_refused(bad, kind):
    """numpy casts complex to float with a warning only, dropping the imaginary part: every
    API entry of q, qd, qdd and t refuses it on one line naming the array, and text too."""
    robot = gd.load_robot("two-link")
    q, qd, qdd = _random_states(robot, 4, 3)
    t = np.linspace(0.0, 1.0, 4)

    def spoilt(x):
        return np.full(x.shape, bad) if isinstance(bad, str) else x + bad

    cases = {
        "q": lambda: gd.gd_terms(robot, spoilt(q), qd),
        "qd": lambda: gd.gd_terms(robot, q, spoilt(qd)),
        "qdd": lambda: gd.regressor(robot, q, qd, spoilt(qdd)),
        "t": lambda: gd.analyze(robot, (spoilt(t), q, qd, qdd)),
    }
    for name, call in cases.items():
        with pytest.raises(gd.InputError, match=rf"{name} must hold real numbers, got {kind}"):
            call()
    model = gd.SimplifiedModel(robot=robot, choices={}, dominance_threshold=0.9,
                               negligible_threshold=0.01)
    with pytest.raises(gd.InputError, match="qdd must hold real numbers"):
        model.torque(q, qd, spoilt(qdd))
    # real numbers of any numeric type are still taken, as Pinocchio takes them
    ints = np.zeros((1, robot.n), dtype=int)
    want = pin.rnea(pinocchio_model(robot), pinocchio_model(robot).createData(),
                    np.zeros(robot.n), np.zeros(robot.n), np.zeros(robot.n))
    np.testing.assert_allclose(gd.gd_terms(robot, ints, ints).c[0], want, rtol=1e-12)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_nan_and_inf_states_are_refused_naming_the_first(bad):
    """gd_terms and regressor returned NaN terms silently for a NaN (or inf) in q, qd or qdd:
    each now raises a ValueError on one line naming the array, the first set point (counted
    from 0, as the array is indexed) and the joint (from 1) that holds one."""
    robot = gd.load_robot("two-link")
    q, qd, qdd = _random_states(robot, 5, seed=4)
    states = {"q": q, "qd": qd, "qdd": qdd}
    for name in states:
        spoilt = {k: v.copy() for k, v in states.items()}
        spoilt[name][3, 1] = spoilt[name][4, 0] = bad      # the first: set point 3, joint 2
        said = rf"^{name}: {bad} at set point 3, joint 2: must be finite$"
        calls = [lambda: gd.regressor(robot, spoilt["q"], spoilt["qd"], spoilt["qdd"])]
        if name != "qdd":
            calls.append(lambda: gd.gd_terms(robot, spoilt["q"], spoilt["qd"]))
        for call in calls:
            with pytest.raises(ValueError, match=said):
                call()
