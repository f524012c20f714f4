"""`gd-analyze some.urdf traj.csv --tip LINK` end to end, on a URDF this test writes itself."""

import json

import pytest
import xarray as xr
from urdf_oracle import BAD_UR5, TOY_URDF, UR5

from gd_analyze.cli import main


@pytest.fixture()
def urdf(tmp_path):
    path = tmp_path / "some.urdf"
    path.write_text(TOY_URDF)
    return path


def test_urdf_end_to_end(urdf, tmp_path, capsys):
    traj = tmp_path / "traj.csv"
    assert main(["plan", str(urdf), "-o", str(traj), "--tip", "tool", "--start=-40,0.0,-30",
                 "--goal=60,0.2,45", "--setpoints", "21"]) == 0
    prov = json.loads((tmp_path / "traj.provenance.json").read_text())
    assert prov["qdd_max_source"].startswith("default 2 s^-1 x qd_max for joints 1, 2, 3")
    assert prov["robot_tip"] == "tool"
    out = tmp_path / "out"
    code = main([str(urdf), str(traj), "--tip", "tool", "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    for name in ("results.h5", "simplified_model.json", "report.html", "report.pdf"):
        assert (out / name).is_file(), name
    with xr.open_dataset(out / "results.h5", engine="h5netcdf") as ds:
        assert ds.attrs["robot"] == "toy"
        assert ds.attrs["robot_tip"] == "tool"
        assert ds.attrs["verification_passed"] in (True, 1)
        assert ds.sizes["joint"] == 3
    # j1 is continuous: its unlimited range goes into the model's JSON (as null, JSON has no
    # inf) and comes back as -inf..inf, so evaluate reads the model it wrote
    model = json.loads((out / "simplified_model.json").read_text())
    assert model["robot"]["parameters"]["link"][0]["q_limits"] == [None, None]
    assert main(["evaluate", str(out / "simplified_model.json"), str(traj)]) == 0


def test_urdf_base_and_tip_then_evaluate(tmp_path, capsys):
    """j1 a limited revolute joint; the chain from --base base to --tip l3 (the side branch
    locked and carried): the simplified model it writes is read back by evaluate."""
    urdf = tmp_path / "limited.urdf"
    urdf.write_text(TOY_URDF.replace('name="j1" type="continuous"', 'name="j1" type="revolute"')
                    .replace('<limit velocity="2.0" effort="5"/>',
                             '<limit lower="-2" upper="2" velocity="2.0" effort="5"/>'))
    traj = tmp_path / "traj.csv"
    chain = ["--base", "base", "--tip", "l3"]
    assert main(["plan", str(urdf), "-o", str(traj), *chain, "--qdd-max", "60,1,90"]) == 0
    prov = json.loads((tmp_path / "traj.provenance.json").read_text())
    assert prov["qdd_max_source"] == "--qdd-max" and prov["robot_base"] == "base"
    out = tmp_path / "out"
    code = main([str(urdf), str(traj), *chain, "-o", str(out), "--no-report", "-q"])
    assert code == 0, capsys.readouterr().err
    assert main(["evaluate", str(out / "simplified_model.json"), str(traj)]) == 0
    assert main(["compare", str(urdf), str(traj), *chain]) == 0


def test_urdf_with_two_chains_needs_a_tip(urdf, tmp_path, capsys):
    code = main([str(urdf), str(tmp_path / "none.csv")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "give --tip LINK (candidate tips: l3, side)" in err


@pytest.fixture(scope="module")
def ur5_traj(tmp_path_factory):
    """A short UR5 trajectory planned on the built-in robot (not on the broken copies)."""
    traj = tmp_path_factory.mktemp("ur5") / "traj.csv"
    assert main(["plan", "ur5", "-o", str(traj), "--setpoints", "11"]) == 0
    return traj


@pytest.mark.parametrize("case, old, new, column", BAD_UR5, ids=[c[0] for c in BAD_UR5])
def test_broken_urdf_exits_2_naming_link_and_attribute(ur5_traj, tmp_path, capfd, case, old,
                                                       new, column):
    """urdfdom drops a broken <inertial> (or ignores <mimic>) and the run used to pass
    "verified against Pinocchio" on the same wrong model: now one line, exit 2, nothing
    written (capfd: not even urdfdom's own messages on the C stderr)."""
    bad = tmp_path / "bad.urdf"
    bad.write_text(UR5.replace(old, new, 1))
    out = tmp_path / "out"
    code = main([str(bad), str(ur5_traj), "-o", str(out)])
    err = capfd.readouterr().err
    assert code == 2, err
    assert err.count("\n") == 1 and f"{bad}: {column}: " in err, err
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.urdf"]


@pytest.mark.slow
def test_the_model_of_an_arm_whose_urdf_writes_pi_with_12_digits_is_read_back(tmp_path,
                                                                               capsys):
    # example-robot-data's Kinova writes rpy="0 3.14159265359 0": read as written, its base
    # parameters' regrouping held only to 1e-12 and `evaluate` refused the model the main
    # job had just written ("exceeds its proved bound 0"). Oracle: the model reader's own
    # check of the program against the G-D terms at states of the region, exit status 0
    from identify_recordings import ERD

    urdf = ERD / "kinova_description/robots/kinova.urdf"
    assert "3.14159265359" in urdf.read_text()
    csv, out = tmp_path / "k.csv", tmp_path / "out"
    assert main(["plan", str(urdf), "-o", str(csv)]) == 0
    assert main([str(urdf), str(csv), "-o", str(out), "-q", "--no-report"]) == 0
    capsys.readouterr()
    assert main(["evaluate", str(out / "simplified_model.json"), str(csv)]) == 0, \
        capsys.readouterr().err
