"""Golden outputs: run the jobs on the shipped robots, freeze what they
write and print, and compare a new run with the frozen files.

A *case* is one command-line run on a shipped trajectory (:data:`CASES`): the main job on
each built-in robot that ships one (``data/<robot>_trajectory.csv``), the sweep of the
PUMA 560 over its trajectory twice, and the control command on the PUMA 560's model. Frozen
per case, in ``tests/golden/<case>/``:

- ``cli.txt``: what the command printed, exactly, after masking the paths and the sweep's
  wall time and scheduler address (:func:`mask_text`);
- ``<name>.h5.frozen.json`` (``results``, ``sweep``, ``control``): the HDF5 file's structure
  (dimensions, coordinates, variables with their dims, dtypes and attributes, the global
  attributes) and its values (:func:`freeze_dataset`), the volatile attributes of
  :data:`VOLATILE` masked;
- ``<model>.json.frozen.json``: the model JSON, parsed, in the same form (:func:`freeze_json`);
- the emitted ``.h``, ``.c``, ``.py`` and ``_casadi.py``, as text, their provenance lines
  masked (:func:`mask_code`), each named ``<file>.golden``.

Comparison (:func:`compare_frozen`): names, dims, shapes, dtypes, strings, integers and
booleans exactly; floating values within :data:`RTOL` (:data:`RTOL_CONTROL` for control.h5)
of the value's scale: by default the largest finite magnitude of that variable (or JSON
array) in the golden file, and for the quantities that are round-off by nature (an error
against an exact model), the scale of :data:`SCALES` (a torque scale, or 1 for an error that
is already relative). A NaN stands for "not applicable" (the DH columns of a URDF arm): it
must be where the golden file has one; a NaN or inf where the golden file has a number
fails, and so does a number where it has a NaN.

The golden files are written by ``python tests/golden/regenerate.py`` (README.md here).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = Path(__file__).resolve().parent
DATA = ROOT / "data"

#: Relative tolerance of a floating value against its scale. The values differ in the last
#: bits between numpy/BLAS builds (about 1e-16 to 1e-13 of the scale); 1e-7 is far above that
#: and far below any change of a result that matters.
RTOL = 1e-7
#: control.h5 holds the simulation of an adaptive ODE integrator (DOP853, rtol 1e-8, atol
#: 1e-10): a last-bit difference may change a step and so the result by about the
#: integrator's tolerance, so its values are compared within 1e-5 of their scale.
RTOL_CONTROL = 1e-5

#: Masked global attributes of the HDF5 files (their value replaced by why), each volatile by
#: nature.
VOLATILE = {
    "history": "a timestamp and the package version",
    "source": "'gd-analyze <version>'",
    "gd_analyze_version": "the package version",
    "started": "the sweep's start time",
    "elapsed_s": "the sweep's wall time",
    "compute_s": "the sweep's compute wall time",
    "scheduler_address": "the dask scheduler's address, a random free port",
    "model_sha256": "control.h5: the SHA-256 of the model JSON, whose provenance holds the "
                    "package version and the paths",
    "inputs_sha256": "sweep.h5: a SHA-256 over the inputs' paths, which depend on the "
                     "checkout, and their contents (each input's own SHA-256 is kept)",
}
#: Masked keys of a sweep's merged model JSON: its trajectory digest is ``inputs_sha256``.
VOLATILE_MERGED = {"trajectory_sha256": "the sweep's inputs_sha256 (paths of the checkout)"}
#: Translational shares of elements that are identically zero (``round_off`` in sweep.h5,
#: ``element_round_off`` in results.h5): a ratio of round-off sums, which differs between
#: numpy and BLAS builds, so stored as NaN (the mark itself is compared).
SHARES = ("share_tran", "share_tran_min", "share_tran_median", "share_tran_max")
#: Masked keys of the model JSON.
VOLATILE_KEYS = {"gd_analyze_version": "the package version"}
#: Integers that count the steps of an adaptive integrator (control.h5): compared as floats
#: within :data:`RTOL_CONTROL` x 1000, since one step more or less is not a change of result.
STEP_COUNTS = {"nfev", "noise_nfev"}
RTOL_STEPS = 0.05
#: Where the region's largest |tau_i| was found (the scale s_i's state): the end point of a
#: local maximisation (L-BFGS-B, which stops once its projected gradient is below 1e-5). At a
#: smooth maximum the value is flat, so a last-bit difference in the samples the search
#: starts from (a BLAS build on another CPU) moves the point by far more than the value
#: (seen: 5e-7 of the scale). Compared within 1e-4 of their scale.
ARGMAX = {"scale_state"}
RTOL_ARGMAX = 1e-4
#: Values that are the largest found by that local maximisation rather than computed: they
#: move with its end point (seen: 1.6e-7 of their scale on another CPU), s_i itself too
#: (``scale`` of the model JSON's guarantee and recursive model, ``simplified_scale`` and
#: ``simplified_guarantee_scale`` of results.h5: the UR5's s_1 was 89.09915257 and
#: 89.09917038 on two machines, 2e-7 apart). Compared within 1e-6 of their scale.
SEARCHED = {"base_parameter_relative_peak", "ladder_worst_bound", "ladder_worst_error",
            "scale", "simplified_scale", "simplified_guarantee_scale"}
RTOL_SEARCHED = 1e-6
#: A number in an emitted source, with the sign or the binary + or - before it: not part of a
#: name (x12); compared as a float where it has a point or an exponent, as text otherwise.
_NUMBER = re.compile(r"(?<![\w.])(?:[-+] ?)?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")
#: Round-off constants of an emitted source (a coefficient a last bit away from cancelling,
#: e.g. -1.39e-16 on one CPU and 1.67e-16 on another) are compared within this share of the
#: file's largest constant.
ATOL_SOURCE = 1e-12

#: The scale of a quantity that is round-off by nature, by its name (a variable, attribute or
#: JSON key, its last part): another variable's largest magnitude, or 1 for an error that is
#: already relative to a scale. Their own largest value would be round-off itself.
SCALES = {
    # results.h5: the simplified model's error against the full model [N m], and relative
    "tau_error_peak": "tau_peak", "tau_error_rms": "tau_peak",
    "tau_error_relative_peak": 1.0, "tau_error_relative_rms": 1.0,
    "other_rule_error_relative_peak": 1.0,
    "formulation_disagreement": 1.0,            # relative differences between formulations
    "base_parameter_relative_peak": 1.0,
    "simplified_bound": "simplified_scale", "simplified_bound_inertia": "simplified_scale",
    "simplified_bound_coriolis": "simplified_scale",
    "simplified_bound_gravity": "simplified_scale", "simplified_bound_whole": "simplified_scale",
    "simplified_guarantee_bound": "simplified_scale",
    # sweep.h5
    "merged_tau_error_peak": "tau_peak", "merged_error_peak": "merged_error_tau_peak",
    "merged_error_rms": "merged_error_tau_peak", "merged_tau_error_relative_peak": 1.0,
    "merged_error_relative_peak": 1.0, "merged_error_relative_rms": 1.0,
    "merged_bound": "merged_scale",
    # control.h5: tracking errors [rad] against the largest, torque differences against tau
    "error": "error_peak_grid", "error_peak_setpoints": "error_peak_grid",
    "error_rms_setpoints": "error_peak_grid", "error_rms_grid": "error_peak_grid",
    "tau_difference": "tau_peak", "tau_difference_peak": "tau_peak",
    "tau_difference_rms": "tau_peak", "tau_difference_peak_setpoints": "tau_peak",
    "tau_difference_rms_setpoints": "tau_peak", "tau_difference_noise": "tau_peak",
    "tau_difference_floor": "tau_peak",
    # model JSON: validation against the full model
    "peak_abs_error": "peak_tau", "rms_error": "peak_tau", "relative_peak_error": 1.0,
    "relative_rms_error": 1.0, "bound": "scale", "sampled_error": 1.0,
}


def _scale_rule(name):
    """The :data:`SCALES` rule of a leaf, by its name's last part; verification errors are
    relative to their element's scale already."""
    last = name.split("/")[-1].lstrip("@")
    if last.startswith(("verification_max_rel_error", "verification_max_rel_excess")):
        return 1.0
    return SCALES.get(last)


@dataclass(frozen=True)
class Case:
    """One command-line run whose outputs are frozen.

    Attributes
    ----------
    name : str
        The folder of its golden files, ``tests/golden/<name>/``.
    argv : tuple of str
        The command line after ``gd-analyze``; ``{out}`` is the run's output folder,
        ``{data}`` the repository's data folder, ``{model}`` the model JSON of :attr:`after`.
    after : str
        The case whose output folder holds the model JSON this one reads ('' for none).
    """

    name: str
    argv: tuple
    after: str = ""


def _main(robot):
    return Case(robot, (robot, f"{{data}}/{robot}_trajectory.csv", "--no-report", "-o",
                        "{out}"))


#: The shipped robots with a shipped trajectory, the sweep and the control command.
CASES = {case.name: case for case in (
    _main("puma560"), _main("panda"), _main("ur5"), _main("stanford"),
    Case("puma560-sweep", ("sweep", "puma560", "{data}/puma560_trajectory.csv",
                           "{data}/puma560_trajectory.csv", "--workers", "1", "--held-out", "0",
                           "--no-report", "-o", "{out}")),
    Case("puma560-control", ("control", "{model}", "{data}/puma560_trajectory.csv",
                             "--no-report", "-o", "{out}"), after="puma560"),
)}

#: The files frozen, by the stem of their name in the output folder.
DATASETS = ("results.h5", "sweep.h5", "control.h5")
MODELS = ("simplified_model", "merged_model")
CODE_SUFFIXES = (".h", ".c", ".py", "_casadi.py")


def run_case(case, out, folders):
    """Run one case's command into ``out`` and return what it printed.

    Parameters
    ----------
    case : Case
    out : Path
        The (new) output folder.
    folders : dict of str to Path
        The output folders of the cases run before (for :attr:`Case.after`).

    Returns
    -------
    str
        Its standard output, unmasked.

    Raises
    ------
    AssertionError
        If the command's exit status is not 0.
    """
    from gd_analyze.cli import main

    model = ""
    if case.after:
        model = str(next(folders[case.after].glob("*_model.json")))
    argv = [a.format(out=out, data=DATA, model=model) for a in case.argv]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        status = main(argv)
    assert status == 0, (case.name, status, printed.getvalue()[-2000:])
    return printed.getvalue()


def mask_paths(text, roots):
    """``text`` with the runs' folders ``roots`` written ``<RUNS>`` and the repository
    ``<ROOT>``."""
    for root in sorted(map(str, roots), key=len, reverse=True):
        text = text.replace(root, "<RUNS>")
    return text.replace(str(ROOT), "<ROOT>")


def mask_text(text, roots):
    """The CLI's printed text with the paths (:func:`mask_paths`) and the sweep's wall time
    and scheduler address masked."""
    text = mask_paths(text, roots)
    return re.sub(r"in [0-9.]+ s on (\d+ dask workers?) \([^)]*\)",
                  r"in <TIME> s on \1 (<ADDRESS>)", text)


def mask_code(text):
    """An emitted source with its provenance masked: the package version and the input
    SHA-256s (robot, robot file, trajectory), nothing else."""
    text = re.sub(r"(gd-analyze version:) \S+", r"\1 <VERSION>", text)
    return re.sub(r"\b[0-9a-f]{64}\b", "<SHA256>", text)


def _leaf(value, roots):
    """A JSON-able leaf: dtype, shape and flat values (floats to 12 significant digits,
    non-finite ones as "nan", "inf", "-inf")."""
    array = np.asarray(value)
    kind = array.dtype.kind
    flat = array.reshape(-1).tolist()
    if kind == "f":
        flat = [x if math.isfinite(x) else str(x) for x in flat]
        dtype = array.dtype.str
    elif kind in "US" or kind == "O":
        flat = [mask_paths(str(x), roots) for x in flat]
        dtype = "str"                       # the width follows the masked paths' lengths
    else:
        dtype = array.dtype.str
    return {"dtype": dtype, "shape": list(array.shape), "values": flat}


def freeze_dataset(path, roots, rtol=RTOL):
    """The frozen form of an HDF5 dataset: its structure and values, volatile attributes
    masked.

    Parameters
    ----------
    path : Path
        ``results.h5``, ``sweep.h5`` or ``control.h5``.
    roots : sequence of Path
        The folders the runs wrote in (masked in strings, :func:`mask_paths`).
    rtol : float
        The tolerance it will be compared with (:func:`_quantized`).

    Returns
    -------
    dict
        ``{"dims": {dim: size}, "coords": [names], "leaves": {name: leaf}}``: one leaf per
        variable (``var/<name>``, with its ``dims``), per variable attribute
        (``var/<name>/@<attr>``) and per global attribute (``@<attr>``).
    """
    with xr.open_dataset(path) as ds:
        ds = ds.load()
    leaves = {}
    zero = next((ds[k].values.astype(bool) for k in ("round_off", "element_round_off")
                 if k in ds.variables), None)
    for name, variable in ds.variables.items():
        values = variable.values
        if name in SHARES and zero is not None:
            mark = zero if values.shape == zero.shape else zero.all(axis=0)
            values = np.where(mark, np.nan, values)
        leaf = _leaf(values, roots)
        leaf["dims"] = list(variable.dims)
        leaves[f"var/{name}"] = leaf
        for attr, value in variable.attrs.items():
            leaves[f"var/{name}/@{attr}"] = _leaf(value, roots)
    for attr, value in ds.attrs.items():
        leaves[f"@{attr}"] = ({"masked": VOLATILE[attr]} if attr in VOLATILE
                              else _leaf(value, roots))
    return {"dims": {k: int(v) for k, v in ds.sizes.items()},
            "coords": sorted(str(c) for c in ds.coords), "leaves": _quantized(leaves, rtol)}


def _quantized(leaves, rtol):
    """The leaves with every floating value rounded to a multiple of ``rtol / 1000`` of its
    scale (:func:`_scale`), written with the digits that needs: a value far below its scale
    takes few digits, and round-off differences below the quantum do not change the file."""
    out = {}
    for name, leaf in leaves.items():
        if leaf.get("dtype", "")[1:2] != "f":
            out[name] = leaf
            continue
        quantum = rtol / 1000 * _scale(name, leaves)
        values = []
        for x in leaf["values"]:
            if isinstance(x, str) or quantum == 0:
                values.append(x)
            elif abs(x) < quantum / 2:
                values.append(0.0)
            else:
                digits = min(17, max(1, math.floor(math.log10(abs(x) / quantum)) + 1))
                values.append(float(f"{x:.{digits}g}"))
        out[name] = {**leaf, "values": values}
    return out


def freeze_json(path, roots):
    """The frozen form of a model JSON: one leaf per scalar, string or array of numbers
    (``json/<key>/<key>/...``, list items by index), volatile keys masked."""
    leaves = {}

    def number(x):
        if isinstance(x, list):
            return bool(x) and all(number(i) for i in x)
        return isinstance(x, (int, float)) and not isinstance(x, bool)

    def numeric(x):                     # a non-empty rectangular array of numbers
        try:
            return number(x) and np.asarray(x).dtype.kind in "if"
        except ValueError:              # ragged
            return False

    volatile = VOLATILE_KEYS | (VOLATILE_MERGED if Path(path).name.startswith("merged_model")
                                else {})

    def walk(x, name):
        key = name.split("/")[-1]
        if key in volatile:
            leaves[name] = {"masked": volatile[key]}
        elif isinstance(x, dict):
            leaves[name] = {"keys": list(x)}
            for k, v in x.items():
                walk(v, f"{name}/{k}")
        elif isinstance(x, list) and not numeric(x):
            leaves[name] = {"length": len(x)}
            for i, v in enumerate(x):
                walk(v, f"{name}/{i}")
        else:
            leaves[name] = _leaf(np.asarray(x, dtype=object if isinstance(x, str) else None),
                                 roots)
    walk(json.loads(Path(path).read_text(encoding="utf-8")), "json")
    return {"leaves": _quantized(leaves, RTOL)}


def frozen_files(folder, roots, printed):
    """Every golden file of one run: name -> text.

    Parameters
    ----------
    folder : Path
        The run's output folder.
    roots : sequence of Path
        The folders the runs wrote in (masked, :func:`mask_paths`).
    printed : str
        What the command printed.

    Returns
    -------
    dict of str to str
    """
    files = {"cli.txt": mask_text(printed, roots)}
    for name in DATASETS:
        if (folder / name).is_file():
            rtol = RTOL_CONTROL if name == "control.h5" else RTOL
            files[f"{name}.frozen.json"] = dump(freeze_dataset(folder / name, roots, rtol))
    for stem in MODELS:
        if (folder / f"{stem}.json").is_file():
            files[f"{stem}.json.frozen.json"] = dump(freeze_json(folder / f"{stem}.json", roots))
            for suffix in CODE_SUFFIXES:
                text = (folder / f"{stem}{suffix}").read_text(encoding="utf-8")
                # named .golden, so that neither pytest nor ruff takes them for sources
                files[f"{stem}{suffix}.golden"] = mask_code(text)
    return files


def dump(frozen):
    """The frozen form as JSON text: one line per leaf, so that a change is a short diff."""
    lines = ["{"]
    for i, (key, value) in enumerate(frozen.items()):
        comma = "," if i < len(frozen) - 1 else ""
        if key != "leaves":
            lines.append(f" {json.dumps(key)}: {json.dumps(value)}{comma}")
            continue
        lines.append(' "leaves": {')
        items = list(value.items())
        for j, (name, leaf) in enumerate(items):
            lines.append(f"  {json.dumps(name)}: {json.dumps(leaf, ensure_ascii=False)}"
                         f"{',' if j < len(items) - 1 else ''}")
        lines.append(f" }}{comma}")
    lines.append("}")
    return "\n".join(lines) + "\n"


# --- comparison ---------------------------------------------------------------------------


def _floats(values):
    return np.array([float(v) for v in values], dtype=float)


def _scale(name, leaves):
    """The scale a floating leaf is compared against, from the golden leaves."""
    rule = _scale_rule(name)
    if isinstance(rule, float):
        return rule
    if isinstance(rule, str):
        prefix = name.rsplit("/", 1)[0]
        if name.startswith("var/") and name.count("/") == 1:
            prefix = "var"
        other = leaves.get(f"{prefix}/{rule}") or leaves.get(f"var/{rule}")
        if other is not None and "values" in other:
            finite = _floats(other["values"])
            finite = finite[np.isfinite(finite)]
            return float(np.max(np.abs(finite))) if finite.size else 0.0
    finite = _floats(leaves[name]["values"])
    finite = finite[np.isfinite(finite)]
    return float(np.max(np.abs(finite))) if finite.size else 0.0


def compare_frozen(golden, new, rtol=RTOL):
    """The differences between a golden frozen form and a new one, as lines.

    Parameters
    ----------
    golden, new : dict
        Frozen forms (:func:`freeze_dataset`, :func:`freeze_json`).
    rtol : float
        Relative tolerance of floating values against their scale (module docstring).

    Returns
    -------
    list of str
        Empty when they agree.
    """
    problems = []
    for key in ("dims", "coords"):
        if golden.get(key) != new.get(key):
            problems.append(f"{key}: golden {golden.get(key)}, new {new.get(key)}")
    old, now = golden["leaves"], new["leaves"]
    for name in sorted(set(old) - set(now)):
        problems.append(f"{name}: missing")
    for name in sorted(set(now) - set(old)):
        problems.append(f"{name}: new, not in the golden file")
    for name in sorted(set(old) & set(now)):
        problem = _compare_leaf(name, old, now, rtol)
        if problem:
            problems.append(f"{name}: {problem}")
    return problems


def _compare_leaf(name, old, now, rtol):
    a, b = old[name], now[name]
    if "values" not in a or "values" not in b:
        return "" if a == b else f"golden {a}, new {b}"
    for key in ("dtype", "shape", "dims"):
        if a.get(key) != b.get(key):
            return f"{key}: golden {a.get(key)}, new {b.get(key)}"
    if a["dtype"][1:2] != "f" and name.split("/")[-1] not in STEP_COUNTS:
        if a["values"] != b["values"]:
            diff = [i for i, (x, y) in enumerate(zip(a["values"], b["values"])) if x != y]
            i = diff[0]
            return (f"{len(diff)} values differ, first at {i}: golden {a['values'][i]!r}, "
                    f"new {b['values'][i]!r}")
        return ""
    x, y = _floats(a["values"]), _floats(b["values"])
    last = name.split("/")[-1].lstrip("@")
    if last in STEP_COUNTS:
        rtol, scale = RTOL_STEPS, float(np.max(np.abs(x))) if x.size else 0.0
    else:
        scale = _scale(name, old)
        if last in ARGMAX:
            rtol = max(rtol, RTOL_ARGMAX)
        elif last in SEARCHED:
            rtol = max(rtol, RTOL_SEARCHED)
    same_nan = np.isnan(x) == np.isnan(y)
    finite = np.isfinite(x) & np.isfinite(y)
    same_inf = np.where(np.isinf(x) | np.isinf(y), x == y, True)
    close = np.where(finite, np.abs(x - y) <= rtol * scale, True)
    bad = ~(same_nan & same_inf & close & (np.isfinite(x) == np.isfinite(y)))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        return (f"{int(bad.sum())} values differ by more than {rtol:g} x scale {scale:.6g}, "
                f"first at {i}: golden {float(x[i])!r}, new {float(y[i])!r}")
    return ""


def compare_files(case, files):
    """The differences between a run's frozen files (:func:`frozen_files`) and the golden
    files of its case, as lines (empty when they agree)."""
    folder = GOLDEN / case
    problems = []
    for name, text in files.items():
        path = folder / name
        if not path.is_file():
            problems.append(f"{case}/{name}: no golden file (run tests/golden/regenerate.py)")
            continue
        golden = path.read_text(encoding="utf-8")
        if name.endswith(".frozen.json"):
            rtol = RTOL_CONTROL if name.startswith("control.h5") else RTOL
            problems += [f"{case}/{name}: {p}"
                         for p in compare_frozen(json.loads(golden), json.loads(text), rtol)]
        elif golden != text:
            problem = _source_difference(golden, text, RTOL)
            if problem:
                problems.append(f"{case}/{name}: text differs\n" + problem)
    return problems


def _source_difference(golden, new, rtol):
    """The first difference between two emitted sources, or "" where they differ only in
    floating constants, each within ``rtol`` of itself plus :data:`ATOL_SOURCE` of the golden
    file's largest constant: the base parameters are the numbers of a QR decomposition, whose
    last bits differ between BLAS builds and CPUs (seen: 3.1535422856250017 and
    3.1535422856250004), and so do the round-off coefficients the recursion keeps. Everything
    else, integers included, must be equal."""
    old, now = golden.split("\n"), new.split("\n")
    if len(old) != len(now):
        return f"  golden has {len(old)} lines, new {len(now)}"
    constants = [abs(_float(u)) for u in _NUMBER.findall(golden) if _is_float(u)]
    atol = ATOL_SOURCE * max((c for c in constants if math.isfinite(c)), default=0.0)
    for i, (x, y) in enumerate(zip(old, now)):
        if x == y:
            continue
        a, b = _NUMBER.split(x), _NUMBER.split(y)
        na, nb = _NUMBER.findall(x), _NUMBER.findall(y)
        same = a == b and len(na) == len(nb) and all(
            u == v for u, v in zip(na, nb) if not _is_float(u) or not _is_float(v))
        if same:
            fa = np.array([_float(u) for u in na if _is_float(u)])
            fb = np.array([_float(v) for v in nb if _is_float(v)])
            same = bool(np.all(np.isfinite(fa)) and np.all(np.isfinite(fb)) and np.all(
                np.abs(fa - fb) <= rtol * np.maximum(np.abs(fa), np.abs(fb)) + atol))
        if not same:
            return f"  line {i + 1}:\n  golden: {x}\n  new:    {y}"
    return ""


def _is_float(token):
    """Whether a number token is a float (has a point or an exponent)."""
    return any(c in token for c in ".eE")


def _float(token):
    """A float token's value, its sign or binary operator included ("- 2.5" is -2.5)."""
    return float(token.replace(" ", ""))


def run_all(root, cases=None):
    """Run the cases (default all) into folders under ``root``; per case, its frozen files.

    Returns
    -------
    dict of str to dict of str to str
    """
    folders, result = {}, {}
    for name in cases or CASES:
        case = CASES[name]
        if case.after and case.after not in folders:
            folders[case.after] = root / case.after
            run_case(CASES[case.after], folders[case.after], folders)
        out = root / name
        printed = run_case(case, out, folders)
        folders[name] = out
        result[name] = frozen_files(out, (root,), printed)
    return result
