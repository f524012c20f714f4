"""Sec. 5.3's sentence on a region model's bound says, joint by joint, how the bound of the
model built was proved. Oracle: the certify functions called directly on the shipped PUMA
560's and Panda's region models (the certification of the main job's region and samples,
then each way's bound of the model's dropped pairs: the pairs' own bounds summed on the final
boxes, the final boxes' bound with the joint sums, the branch and bound on the joint sum, the
decomposition), the simplest way that reaches the stated bound named; the PUMA 560's bound is
the joint sum's branch and bound's on joints 1 and 2, the Panda's the decomposition's on
joints 1-4 (docs/performance.md)."""

import json
import re

import numpy as np
import pytest
import xarray as xr
from conftest import SHIPPED, golden_run

import gd_analyze
from gd_analyze.certify.certify import (
    JOINT_BOXES,
    JOINT_DIMS,
    certify,
    decomposed_bound,
    dropped_bound,
    joint_sums,
    leaf_bound,
    split_joints,
)
from gd_analyze.certify.regressor_bounds import BOX_MAX_JOINTS
from gd_analyze.dynamics.base_parameters import base_parameters
from gd_analyze.report.simplified_section import simplified_context

pytestmark = pytest.mark.slow

#: What the sentence says of each way (the start of its words after the joints).
_SAID = {"none": "is 0: nothing dropped acts there",
         "pairs": "is the sum of the pairs' own bounds on the certification's final boxes",
         "joint sum": "is the bound of their sum at the same state on the certification's",
         "branch and bound": "is proved by branch and bound on their sum at the same state",
         "decomposition": "is proved by a decomposition: branch and bound on the sum"}


def _ways_by_certify(path):
    """Per joint, the way the oracle finds for the model file's bound, and each way's bound."""
    model = gd_analyze.load_model(path)
    doc = json.loads(path.read_text())["guarantee"]
    robot, base = model.robot, base_parameters(model.robot)
    region = model.guarantee.region
    pb = certify(robot, base, region, torque_floor=float(model.torque_floor))
    dropped = np.asarray(model.recursive.dropped, bool)
    limit = float(model.tolerance) * np.asarray(pb.scale, float)
    sums = joint_sums(robot, base, region, pb.split_joint, pb.split_at, dropped, pb.zero)
    ways = {"pairs": pb.leaves[dropped].sum(axis=0).max(axis=0),
            "joint sum": leaf_bound(pb, sums, dropped)}
    if split_joints(robot, base, dropped, pb.zero).sum() <= JOINT_DIMS:
        ways["branch and bound"] = dropped_bound(robot, base, region, dropped, limit,
                                                 JOINT_BOXES, pb.zero)
    else:
        ways["decomposition"] = decomposed_bound(robot, base, region, pb, dropped, limit,
                                                    sums)
    stated = np.asarray(doc["bound"], float)
    least = np.minimum.reduce(list(ways.values()))
    assert np.allclose(least, stated, rtol=1e-9, atol=1e-12 * np.max(pb.scale))
    found = []
    for j in range(robot.n):
        if stated[j] == 0:
            found.append("none")
            continue
        found.append(next(w for w in ("pairs", "joint sum", "branch and bound",
                                      "decomposition")
                          if w in ways and ways[w][j] <= least[j] + 1e-12 * pb.scale[j]))
    return found, doc, robot.n


def _sentence_ways(text, n):
    """Per joint, the way Sec. 5.3's sentence names."""
    said = {}
    for joints, words in re.findall(r"(?:The bound|that) of (joints? [0-9,\u2013 and]+?) "
                                    r"(is [^;.]+)", text):
        way = next(w for w, start in _SAID.items() if words.startswith(start.split(":")[0]))
        for part in re.split(r", | and ", joints.split(" ", 1)[1]):
            lo, _, hi = part.partition("\u2013")
            for j in range(int(lo), int(hi or lo) + 1):
                said[j] = way
    assert sorted(said) == list(range(1, n + 1)), text
    return [said[j] for j in range(1, n + 1)]


@pytest.mark.parametrize("arm", ["puma560", "panda"])
def test_the_sentence_names_the_way_certify_used(arm, shared_main):
    # the Panda's main job without report on its shipped trajectory is its golden case's
    # command (tests/golden/freeze.py): that run, shared with tests/test_golden.py, read only
    out = shared_main(arm, SHIPPED) if arm == "puma560" else \
        golden_run(arm)[0][0] / arm
    found, doc, n = _ways_by_certify(out / "simplified_model.json")
    assert doc["bound_method"] == found
    with xr.open_dataset(out / "results.h5") as ds:
        text = simplified_context(ds.load())["text"]
    assert _sentence_ways(text, n) == found
    for way in set(found):
        assert _SAID[way] in text
    both = "those balls intersected with interval boxes" in text
    assert both == (n <= BOX_MAX_JOINTS) and doc["joint_sum_arithmetic"] == "both"
    if arm == "puma560":
        assert found[:2] == ["branch and bound"] * 2 and found[3:] == ["none"] * 3
    else:
        assert found[:4] == ["decomposition"] * 4 and found[-1] == "none"


def test_an_older_results_file_says_no_way(shared_main):
    """A results file written before the ways were stored (the PUMA 560's without the
    variable and attribute): read, the sentence names no way and no enclosures, the rest of it
    stands, and Figure 6's triangles fall back to the bound below the parts' sum."""
    from gd_analyze.report.simplified_section import joint_sum_lower

    with xr.open_dataset(shared_main("puma560", SHIPPED) / "results.h5") as ds:
        new = ds.load()
    old = new.drop_vars("simplified_guarantee_bound_method")
    del old.attrs["simplified_guarantee_joint_sum_arithmetic"]
    text = simplified_context(old)["text"]
    assert "The bound of" not in text and "midpoint-radius balls" not in text
    assert "The error at every state of the region is within that bound, the bound below." \
        in text
    assert "The bound of joints 1, 2 is proved by branch and bound" in \
        simplified_context(new)["text"]
    assert joint_sum_lower(old).tolist() == joint_sum_lower(new).tolist() == \
        [True, True, False, False, False, False]


def test_the_sweep_reports_sentence_names_the_way_certify_used(shared_main):
    """The sweep report's Sec. 5 says the same of the merged region model, from sweep.h5."""
    import html as html_lib

    out = shared_main("sweep", "puma560", "--random", "3", "--seed", "1", "--held-out", "0",
                      "--rule", "budget")
    found, doc, n = _ways_by_certify(out / "merged_model.json")
    with xr.open_dataset(out / "sweep.h5") as ds:
        assert [str(m) for m in ds["merged_bound_method"].values] == found
    page = html_lib.unescape(re.sub(r"<[^>]+>", "", (out / "sweep_report.html").read_text()))
    text = " ".join(page.split())
    assert _sentence_ways(text, n) == found
