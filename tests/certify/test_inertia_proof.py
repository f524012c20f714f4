"""The proof that D_s is positive definite over a box of q (certify/inertia_proof.py).

Oracles: matrices whose Gershgorin discs are known by hand; Pinocchio's crba at 100,000
positions (D never below the floor diag(f) the proof uses); the exact model (nothing dropped:
the proved bound is the floor) and numpy's eigenvalues at the box's samples."""

import numpy as np
import pytest
from robot_files import crba, inertia_arm

from gd_analyze import load_robot
from gd_analyze.certify.inertia_proof import gershgorin_lower, inertia_floor, prove_inertia
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.simplify.deploy import guarantee_region

SAMPLED = 100_000


def test_gershgorin_lower_on_known_matrices():
    """[[2, 1], [1, 2]]: eigenvalues 1 and 3, discs [1, 3]; [[1, 2], [2, 1]] is indefinite
    (-1), its discs reach -1; weights w = (1, 2) move [[4, 1], [1, 1]]'s discs to 4 - 2 = 2
    and 1 - 0.5 = 0.5, within its eigenvalue 0.697."""
    A = np.array([[[2.0, 1.0], [1.0, 2.0]], [[1.0, 2.0], [2.0, 1.0]]])
    got = gershgorin_lower(A, A)
    assert got[0] == pytest.approx(1.0) and got[0] < 1.0 and got[1] < -1.0 + 1e-12
    B = np.array([[[4.0, 1.0], [1.0, 1.0]]])
    assert gershgorin_lower(B, B, np.array([1.0, 2.0]))[0] == pytest.approx(0.5)
    assert gershgorin_lower(B, B)[0] == pytest.approx(0.0, abs=1e-12)
    assert np.linalg.eigvalsh(B[0])[0] >= gershgorin_lower(B, B, np.array([1.0, 2.0]))[0]


@pytest.mark.slow
@pytest.mark.parametrize("key", ["panda", "erd-panda", "kinova", "puma560"])
@pytest.mark.parametrize("kind", ["chain", "pairs"])
def test_the_floor_under_d_holds_at_100000_positions(key, kind):
    """D(q) - diag(f) is positive semidefinite (to round-off) at every sampled q: Pinocchio's
    crba, so lambda_min(D) is never below min f, the bound the proof uses."""
    robot = inertia_arm(key)
    f = inertia_floor(robot, kind)
    assert (f > 0).all() and np.isfinite(f).all()
    region, _, _ = guarantee_region(robot)
    q = np.random.default_rng(3).uniform(region.q_min, region.q_max, (SAMPLED, robot.n))
    D = crba(robot, q)
    lam = np.linalg.eigvalsh(D - np.diag(f))[:, 0]
    scale = np.abs(D).max(axis=(1, 2))
    assert (lam >= -1e-13 * scale).all()
    assert np.linalg.eigvalsh(D)[:, 0].min() >= f.min()




@pytest.mark.parametrize("key", ["ur5", "panda"])
def test_the_exact_model_is_proved_by_the_floor(key):
    """Nothing dropped: D_s = D, proved at once (no box) with the floor's least entry, and the
    ratio's denominator is above numpy's smallest eigenvalue of D at the witness."""
    robot = load_robot(key)
    region, _, _ = guarantee_region(robot)
    base = base_parameters(robot)
    proof = prove_inertia(robot, base, np.zeros((len(base.beta), 3), bool), region.q_min,
                          region.q_max, samples=300)
    f = inertia_floor(robot)
    assert proof.proved and proof.boxes == 0 and proof.lower == pytest.approx(f.min())
    assert proof.lower < f.min()
    assert np.linalg.eigvalsh(crba(robot, proof.witness[None]))[0, 0] <= proof.d_upper
    assert 0 < proof.ratio <= 1 and proof.sampled_min >= proof.lower


def test_a_proof_is_made_once_per_process(monkeypatch):
    """The same arm, box, settings and dropped inertial parts give the proof made before (the
    region search's trials and the deployed model's check ask for the same ones), its context
    read-only; other dropped parts, or the memo emptied, prove again, to the same outcome."""
    import gd_analyze.certify.inertia_proof as ip

    monkeypatch.setattr(ip, "_CONTEXTS", [])
    monkeypatch.setattr(ip, "_PROOFS", {})
    robot = load_robot("puma560")
    region, _, _ = guarantee_region(robot)
    base = base_parameters(robot)
    dropped = np.zeros((len(base.beta), 3), bool)
    names = list(base.names())
    dropped[names.index("YZ2"), 0] = True       # proved on some hundred boxes
    first = prove_inertia(robot, base, dropped, region.q_min, region.q_max, samples=300)
    assert first.proved and first.boxes > 1
    context = ip.inertia_context(robot, base, region.q_min, region.q_max, 300)
    assert prove_inertia(robot, base, dropped, region.q_min, region.q_max,
                         samples=300, context=context) is first
    with pytest.raises(ValueError):
        context["D"][0, 0, 0] = 1.0
    other = dropped.copy()
    other[names.index("XY3"), 0] = True
    assert prove_inertia(robot, base, other, region.q_min, region.q_max,
                         samples=300) is not first
    assert prove_inertia(robot, base, dropped, region.q_min, region.q_max, max_boxes=64,
                         samples=300) is not first
    monkeypatch.setattr(ip, "_CONTEXTS", [])
    monkeypatch.setattr(ip, "_PROOFS", {})
    again = prove_inertia(robot, base, dropped, region.q_min, region.q_max, samples=300)
    assert again is not first
    assert (again.proved, again.lower, again.boxes, again.sampled_min) == (
        first.proved, first.lower, first.boxes, first.sampled_min)


def test_no_floor_names_the_link_that_gives_none(tmp_path):
    """A PUMA 560 whose link 6 is a point mass off its axis gives no floor under D; the reason
    named link 1 (the first entry of the all-zero floor) whatever link it was. Oracle: the
    link made a point mass in the file."""
    from importlib import resources

    text = resources.files("gd_analyze").joinpath("data/puma560.toml").read_text()
    wrist = "com = [0.0, 0.0, 0.032]\ninertia = [0.15e-3, 0.15e-3, 0.04e-3]"
    assert text.count(wrist) == 1 and text.rindex("[[link]]") < text.index(wrist)
    path = tmp_path / "point_wrist.toml"
    path.write_text(text.replace(wrist, "com = [0.02, 0.0, 0.032]\ninertia = [0.0, 0.0, 0.0]"))
    robot = load_robot(path)
    region, _, _ = guarantee_region(robot)
    base = base_parameters(robot)
    proof = prove_inertia(robot, base, np.zeros((len(base.beta), 3), bool), region.q_min,
                          region.q_max, samples=50)
    assert not proof.proved
    assert proof.why == "no floor under D: link 6's spatial inertia gives none"
