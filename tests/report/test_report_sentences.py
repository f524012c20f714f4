"""Report sentences that were false, each read from the report of a real
run: where the torque-error figure's bound holds and what the error-budget figure's bars are
(from the guarantee's kind), what s_i is when no torque floor is set, the equation of motion's
number (Eq. (3.4-24) in the chapter: the sum of the parts is tau), and the UR5's placeholder
inertia tensors. Oracle: the guarantee stored in the run's own results.h5, the chapter's
text (/work/shared/seed, Sec. 3.4) and the UR5 URDF's own inertials (cylinder stand-ins:
ixx = iyy on every link)."""

import dataclasses
import json
import re

import numpy as np
import pinocchio as pin
import pytest
import xarray as xr
from conftest import SHIPPED
from figure_checks import sweep_figure
from html_checks import html_text

from gd_analyze import load_robot
from gd_analyze.dynamics.pinocchio import pinocchio_model
from gd_analyze.model.urdf import builtin_urdf_path
from gd_analyze.report.simplified_section import budget_caption, cost_points, simplified_caption
from gd_analyze.store.datasets import stored_guarantee
from gd_analyze.trajectory.trajectory import read_trajectory

#: Over 5 s on an idle machine (the shared reports): run on one interpreter in CI.
pytestmark = pytest.mark.slow


def _report(folder):
    text = html_text((folder / "report.html").read_text(encoding="utf-8"), nbsp=True)
    with xr.open_dataset(folder / "results.h5", engine="h5netcdf") as ds:
        return text, stored_guarantee(ds.load())


def _caption(text, start):
    """The figure caption that begins with ``start`` (up to the next "Fig." or "Table")."""
    m = re.search(re.escape(start) + r".*?(?=Fig\. \d|Table \d|$)", text)
    assert m, start
    return m.group(0)


def test_puma_region_report_says_proved_bounds_and_the_region_scale(shared_puma):
    text, guarantee = _report(shared_puma["puma"][0])
    assert guarantee["kind"] == "region"
    torque = _caption(text, "Torque error of the simplified model")
    assert "proved at every state of the region" in torque
    assert "on this trajectory only" not in torque
    budget = _caption(text, "The error budget per joint")
    assert "bounds of the dropped terms proved over the region" in budget
    assert "peaks of the dropped terms" not in budget
    floor = re.search(r"torque floor of each joint's scale (none: .*?)(?= [a-z ,]+: |$)", text)
    # how s_i was found, as the model built stored it: a search, a lower bound
    assert floor and re.search(r"the largest \|τ ?i ?\| found at 1,014 sampled positions of the "
                               r"region and polished by local maximisation, a lower bound of the "
                               r"region's largest", floor.group(1)), text[:0]
    assert "its own peak" not in floor.group(1)
    contributions = _caption(text, "What the error budget acts on")
    assert "(Eq. (3.4-24))" in contributions and "3.4-25" not in contributions
    assert "placeholder" not in text


def test_the_chapter_numbers_the_equation_of_motion_3_4_24():
    """The seed's Sec. 3.4: the structured equation of motion, D qdd + h + c = tau, carries
    the number (3.4-24); (3.4-25) defines the elements of D."""
    seed = open("/work/shared/seed/000_030a2b5eb6ce2605.txt", encoding="utf-8").read()
    line = next(ln for ln in seed.splitlines() if "(3.4-24)" in ln and "=" in ln)
    assert line.rstrip().endswith("(3.4-24)") and "+" in line
    assert "Equation (3.4-25) reveals the acceleration effects" in seed


def test_ur5_report_says_its_inertias_are_placeholders(shared_reports):
    urdf = builtin_urdf_path("ur5").read_text()
    tensors = re.findall(r'<inertia ixx="([^"]+)"[^>]*iyy="([^"]+)"', urdf)
    moving = [(a, b) for a, b in tensors if float(a) > 0]
    assert moving and all(a == b for a, b in moving)      # cylinder stand-ins, not measured
    text, _ = _report(shared_reports["ur5"][0])
    leads = re.findall(r"— (\w+) effects lead( \(on this robot's placeholder inertia tensors)?",
                       text)
    assert leads
    for lead, said in leads:
        assert bool(said) == (lead != "translational"), (lead, said)


def test_a_trajectory_guarantee_says_trajectory(shipped_dataset):
    ds = shipped_dataset("puma560")
    assert stored_guarantee(ds)["kind"] == "trajectory"
    assert "guaranteed on this trajectory only" in simplified_caption(ds)
    assert "peaks of the dropped terms on this trajectory" in budget_caption(ds)


def test_drives_report_says_s_i_is_the_rigid_links(shared_main):
    """``gd-analyze puma560-drives data/puma560_trajectory.csv``: the region's s_i is the
    rigid links' largest |tau_i| (Pinocchio's rnea of the arm without its drives at the stored
    scale state gives it), not the torque with armature and friction the report's tables show;
    the report says which."""
    out = shared_main("puma560-drives", SHIPPED)     # shared, read only
    text, _ = _report(out)
    guarantee = json.loads((out / "simplified_model.json").read_text())["guarantee"]
    assert guarantee["kind"] == "region"
    drives = load_robot("puma560-drives")
    rigid = dataclasses.replace(drives, armature=np.zeros(drives.n), viscous=np.zeros(drives.n),
                                coulomb=np.zeros(drives.n))
    model = pinocchio_model(rigid)
    n = drives.n
    for i, state in enumerate(np.asarray(guarantee["scale_state"], float)):
        tau = pin.rnea(model, model.createData(), state[:n], state[n:2 * n], state[2 * n:])
        assert abs(tau[i]) == pytest.approx(guarantee["scale"][i], rel=1e-9)
    assert re.search(r"polished by local maximisation, a lower bound of the region's largest; "
                     r"τ ?i ?of the rigid links alone", text)
    floor = re.search(r"torque floor of each joint's scale (none: .*?)(?= [a-z ,]+: |$)", text)
    assert floor and "rigid links alone" in floor.group(1)


def test_cost_figure_puts_every_point_on_the_deployed_scale(shared_puma):
    """Fig. 7 under a region guarantee: the explicit budget model's bound (EPS times its own
    scale, the trajectory's peak |tau_i|) is drawn relative to the deployed model's s_i (the
    region's), as the measured points are; Pinocchio's rnea along the trajectory gives the
    peaks, the model file gives s_i; the caption says the scale."""
    folder = shared_puma["puma"][0]
    guarantee = json.loads((folder / "simplified_model.json").read_text())["guarantee"]
    robot = load_robot("puma560")
    traj = read_trajectory(SHIPPED, robot.n)
    model = pinocchio_model(robot)
    peak = np.max(np.abs([pin.rnea(model, model.createData(), *x)
                          for x in zip(traj.q, traj.qd, traj.qdd)]), axis=0)
    with xr.open_dataset(folder / "results.h5", engine="h5netcdf") as ds:
        ds = ds.load()
    eps = float(ds.attrs["simplified_tolerance"])
    bound = [p for p in cost_points(ds) if p[3] == "bound" and p[0].startswith("explicit")]
    assert len(bound) == 1
    want = np.max(eps * peak / np.asarray(guarantee["scale"]))
    assert bound[0][2] == pytest.approx(want, rel=1e-9) and bound[0][2] < eps
    text, _ = _report(folder)
    assert "relative to s i , the deployed model's scale, for every point" in \
        _caption(text, "Cost against accuracy")


def test_sweep_error_figure_is_on_one_scale(shared_reports):
    """The sweep's Fig. 4 under a region guarantee: the own models' errors, the merged model's
    per trajectory and over all of them, each divided by the merged model's s_i (the region's)
    on one axis, and the caption says so."""
    folder, _ = shared_reports["sweep"]
    with xr.open_dataset(folder / "sweep.h5", engine="h5netcdf") as ds:
        ds = ds.load()
    assert ds.attrs["merged_guarantee_kind"] == "region"
    s_i = ds["merged_scale"].values
    assert (s_i == s_i[0]).all()                    # one region, one s_i per joint
    fig = sweep_figure(ds, "error")
    ax = fig.axes[0]
    assert ax.get_ylabel() == "peak |Δτ| / s [1]"
    diamonds = [ln for ln in ax.lines if ln.get_marker() == "D"]
    want = ds["merged_error_peak"].values / s_i[0]
    got = {round(float(ln.get_xdata()[0])): float(ln.get_ydata()[0]) for ln in diamonds}
    for j, y in got.items():
        assert y == pytest.approx(want[j - 1], rel=1e-12)
    medians = [ln for ln in ax.lines if ln.get_color() == "#009E73" and len(ln.get_xdata())
               == 2 and ln.get_ydata()[0] == ln.get_ydata()[1]]
    own = ds["tau_error_peak"].values / s_i
    assert medians and all(own.min() - 1e-15 <= ln.get_ydata()[0] <= own.max() + 1e-15
                           for ln in medians)
    text = html_text((folder / "sweep_report.html").read_text(encoding="utf-8"), nbsp=True)
    assert "every mark relative to one scale, the merged model's s i over the region" in text \
        or "every mark relative to one scale, the merged model's si over the region" in text
