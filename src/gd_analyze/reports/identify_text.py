"""The identify report's words and tables, read from a stored identification.

Every sentence and number comes from the datasets of ``identification.h5`` (the root group and
one group per recording; layout in ``gd_analyze.io.identification_dataset`` of the identify
command): nothing is recomputed but the percentages of the standard deviations. Every name read
from the data (robot, joints, files, settings) is cleaned of the report's markup characters
(:func:`gd_analyze.reports.markup.clean`); the HTML escapes it and the PDF sets it as text.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .common import keep_units, utc_now
from .identify_figures import MAX_POINTS, role_of, shown_recordings, stride
from .markup import clean
from .numbers import fmt, pct

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["identify_context", "REQUIRED_ROOT", "REQUIRED_RECORDING", "parameter_units",
           "plain_table"]

#: Variables the root group must have.
REQUIRED_ROOT = ("value", "std")
#: Variables every recording group must have.
REQUIRED_RECORDING = ("tau_measured", "tau_predicted")
#: Units of a base parameter by its name's letters, and of each drive kind (revolute joints;
#: prismatic: kg, kg, N s/m, N, N).
_M2 = "kg m\u00b2"
_BASE_UNITS = {"XX": _M2, "XY": _M2, "XZ": _M2, "YY": _M2, "YZ": _M2, "ZZ": _M2,
               "MX": "kg m", "MY": "kg m", "MZ": "kg m", "M": "kg"}
_DRIVE_UNITS = {"armature": _M2, "viscous": "N m s/rad", "coulomb": "N m", "offset": "N m"}


def plain_table(header: Sequence[str], rows: Sequence[Sequence[Any]],
                align: Sequence[str] | None = None,
                colour_cols: Sequence[int] = ()) -> dict[str, Any]:
    """A table as :func:`gd_analyze.reports.common.table` makes it, its cells left as text.

    (``common.table`` letters cells that look like a G-D element's label, ``D12`` as
    ``D₁₂``: a joint or file named so is shown as named here.)

    Parameters
    ----------
    header : sequence of str
    rows : sequence of sequence
    align : sequence of str, optional
        ``"left"`` or ``"right"`` per column; default the first left, the others right.
    colour_cols : sequence of int, optional
        Columns of yes/no cells, drawn in their colour.

    Returns
    -------
    dict
    """
    header = [keep_units(h) for h in header]
    return {"header": header, "rows": [[clean(str(c)) for c in row] for row in rows],
            "align": list(align or ["left"] + ["right"] * (len(header) - 1)),
            "widths": [1] * len(header), "colour_cols": list(colour_cols)}


def parameter_units(name: str, kind: str) -> str:
    """The SI units of an identified parameter (a revolute joint's).

    Parameters
    ----------
    name : str
        ``ZZ1``, ``MX2``, ``M3``, ``viscous_1``...
    kind : str
        ``base`` or a drive kind.

    Returns
    -------
    str
        E.g. ``"kg m²"``; ``""`` if unknown.
    """
    if kind in _DRIVE_UNITS:
        return _DRIVE_UNITS[kind]
    letters = name.rstrip("0123456789")
    return _BASE_UNITS.get(letters, "")


def _json(root, key, default):
    """A JSON attribute of the root, or ``default`` when absent or not JSON."""
    text = root.attrs.get(key)
    if text is None:
        return default
    try:
        return json.loads(str(text))
    except ValueError:
        return str(text)


def _strings(values):
    return [clean(v.decode() if isinstance(v, bytes) else str(v))
            for v in np.asarray(values).reshape(-1)]


def _float(ds, key):
    try:
        v = float(ds.attrs[key]) if key in ds.attrs else float(ds[key].values)
    except (KeyError, TypeError, ValueError):
        return math.nan
    return v


def _joints(root, ds, n):
    for src in (ds, root):
        if "joint" in src.coords and src["joint"].size == n:
            return _strings(src["joint"].values)
    return [str(j + 1) for j in range(n)]


def _file_of(name, ds):
    return clean(str(ds.attrs.get("file", name)))


def _recordings_table(groups):
    has_prior = any("prior_total_relative_error" in ds.attrs for ds in groups.values())
    has_simple = any("simplified_total_relative_error" in ds.attrs for ds in groups.values())
    header = ["recording", "role", "samples", "duration [s]", "identified model"]
    header += ["robot file as shipped"] * has_prior + ["simplified model"] * has_simple
    rows = []
    for name, ds in groups.items():
        t = np.asarray(ds["t"].values, float)
        row = [_file_of(name, ds), role_of(ds), f"{t.size:,}",
               fmt(t[-1] - t[0], 4) if t.size else "n/a",
               pct(_total(ds, "tau_predicted", "total_relative_error"))]
        if has_prior:
            row.append(pct(_total(ds, "tau_prior", "prior_total_relative_error")))
        if has_simple:
            row.append(pct(_total(ds, "tau_simplified", "simplified_total_relative_error")))
        rows.append(row)
    return plain_table(header, rows, align=["left", "left"] + ["right"] * (len(header) - 2))


def _total(ds, variable, key):
    """The stored total relative error ||E||_F / ||T||_F (NaN if neither it nor the torque)."""
    value = _float(ds, key)
    return value if math.isfinite(value) or variable not in ds.variables else math.nan


def _joint_table(root, ds):
    n = int(ds["tau_measured"].shape[1])
    joints = _joints(root, ds, n)
    cols = [("rms_error", "RMS error [N m]", fmt), ("relative_error", "relative error", pct),
            ("prior_relative_error", "robot file: relative error", pct),
            ("simplified_relative_error", "simplified: relative error", pct)]
    cols = [c for c in cols if c[0] in ds.variables]
    rows = [[str(j + 1), joints[j]] + [f(float(ds[v].values[j])) for v, _, f in cols]
            for j in range(n)]
    return plain_table(["joint", "name"] + [h for _, h, _ in cols], rows,
                       align=["right", "left"] + ["right"] * len(cols))


def _parameter_table(root):
    names = _strings(root["parameter"].values) if "parameter" in root.coords \
        else [str(k + 1) for k in range(root["value"].size)]
    value = np.asarray(root["value"].values, float)
    std = np.asarray(root["std"].values, float)
    kinds = _strings(root["kind"].values) if "kind" in root.variables else ["base"] * len(names)
    prior = np.asarray(root["prior"].values, float) if "prior" in root.variables else None
    ident = np.asarray(root["identifiable"].values, bool) if "identifiable" in root.variables \
        else np.ones(len(names), bool)
    rows = []
    for k, name in enumerate(names):
        rel = abs(std[k] / value[k]) if value[k] != 0 and ident[k] else math.nan
        row = [name, parameter_units(name, kinds[k]), fmt(value[k], 4, (1e-3, 1e4)),
               fmt(std[k], 3, (1e-3, 1e4)) if ident[k] else "\u2014",
               pct(rel) if math.isfinite(rel) else "\u2014"]
        if prior is not None:
            row.append(fmt(prior[k], 4, (1e-3, 1e4)))
        row.append("yes" if ident[k] else "no")
        rows.append(row)
    header = ["parameter", "units", "value", "std", "std [%]"] + \
        ["robot file"] * (prior is not None) + ["identifiable"]
    return plain_table(header, rows, align=["left", "left"] + ["right"] * (len(header) - 3)
                       + ["left"], colour_cols=[len(header) - 1]), int((~ident).sum()), names


def _links_table(root):
    if "link_consistent" not in root.variables:
        return None
    links = np.asarray(root["link"].values).reshape(-1) if "link" in root.coords \
        else np.arange(1, root["link_consistent"].size + 1)
    ok = np.asarray(root["link_consistent"].values, bool)
    eig = np.asarray(root["pseudo_inertia_min_eigenvalue"].values, float) \
        if "pseudo_inertia_min_eigenvalue" in root.variables else np.full(ok.size, math.nan)
    return plain_table(["link", f"smallest pseudo-inertia eigenvalue [{_M2}]", "consistent"],
                       [[str(links[k]), fmt(eig[k], 4, (1e-3, 1e4)), "yes" if ok[k] else "no"]
                        for k in range(ok.size)], colour_cols=[2])


def _noise_table(root):
    if "noise_std" not in root.variables:
        return None
    noise = np.asarray(root["noise_std"].values, float)
    joints = _joints(root, root, noise.size)
    return plain_table(["joint", "name", "residual standard deviation [N m]"],
                       [[str(j + 1), joints[j], fmt(noise[j], 4)] for j in range(noise.size)],
                       align=["right", "left", "right"])


def _provenance(root, groups, created):
    rows = [["report created", created],
            ["gd-analyze version", clean(str(root.attrs.get("gd_analyze_version", "\u2014")))]]
    for key, label in (("robot", "robot"), ("robot_source", "robot file"),
                       ("robot_sha256", "robot file SHA-256"),
                       ("standard_method", "standard parameters"),
                       ("coulomb_model", "Coulomb friction model")):
        if key in root.attrs:
            rows.append([label, clean(str(root.attrs[key]))])
    inputs = _json(root, "inputs", {})
    if isinstance(inputs, dict):
        rows += [[f"input {clean(str(k))}", clean(str(v))] for k, v in inputs.items()]
    for name, ds in groups.items():
        if "sha256" in ds.attrs and not (isinstance(inputs, dict)
                                         and ds.attrs.get("file") in inputs):
            rows.append([f"input {_file_of(name, ds)}", clean(str(ds.attrs["sha256"]))])
    settings = _json(root, "settings", {})
    if isinstance(settings, dict):
        rows += [[f"setting {clean(str(k))}",
                  clean(v if isinstance(v, str) else json.dumps(v, default=str))]
                 for k, v in sorted(settings.items())]
    elif settings:
        rows.append(["settings", clean(str(settings))])
    return plain_table(["item", "value"], rows, align=["left", "left"])


def _sentences(values):
    """Stored statements as sentences: cleaned, each ending with a full stop."""
    values = values if isinstance(values, list) else [values] if values else []
    out = []
    for v in values:
        text = clean(str(v)).strip()
        if text:
            out.append(text + ("" if text.endswith((".", "!", "?")) else "."))
    return out


def identify_context(root: xr.Dataset, groups: dict[str, xr.Dataset]) -> dict[str, Any]:
    """The report's words and tables.

    Parameters
    ----------
    root : xarray.Dataset
        The root group: ``value``, ``std`` (parameter) and optionally ``prior``,
        ``identifiable``, ``kind``, ``noise_std``, ``link_consistent``,
        ``pseudo_inertia_min_eigenvalue``; attributes ``condition_number``, ``rank``,
        ``unidentifiable``, ``preprocessing``, ``settings``, ``inputs`` (JSON), ``robot``...
    groups : dict of str to xarray.Dataset
        One per recording: ``t``, ``tau_measured``, ``tau_predicted`` (t, joint), per joint
        ``rms_error``, ``relative_error`` (and the robot file's and simplified model's), the
        role and ``total_relative_error``.

    Returns
    -------
    dict
        ``title``, ``lead``, ``summary``, ``notes`` and the tables, each a dict of
        :func:`plain_table`.
    """
    robot = clean(str(root.attrs.get("robot", "the robot")))
    cond = _float(root, "condition_number")
    validate = [k for k, ds in groups.items() if role_of(ds) == "validate"]
    shown = shown_recordings(groups)
    parameters, n_unident, names = _parameter_table(root)
    lead = []
    for name in validate:
        ds = groups[name]
        text = (f"On {_file_of(name, ds)}, not used for fitting, the identified model's total "
                f"relative torque error ||E||_F / ||T||_F is "
                f"{pct(_total(ds, 'tau_predicted', 'total_relative_error'))}")
        prior = _total(ds, "tau_prior", "prior_total_relative_error")
        if math.isfinite(prior):
            text += f"; the robot file's as shipped, {pct(prior)}"
        simple = _total(ds, "tau_simplified", "simplified_total_relative_error")
        if math.isfinite(simple):
            text += f"; the simplified model's, {pct(simple)}"
        lead.append(text + ".")
    if not validate:
        lead.append("No recording was held out for validation: every error below is on the "
                    "recordings the model was fitted to, not a prediction.")
    unident = _json(root, "unidentifiable", [])
    which = (f": {', '.join(clean(str(u)) for u in unident)}" if isinstance(unident, list)
             and unident else "")
    summary = (f"{len(names)} parameters ("
               + (f"{n_unident} not identifiable on the data{which}; they keep the robot "
                  "file's value" if n_unident else "all identifiable on the data")
               + "), identified from "
               f"{sum(role_of(ds) == 'train' for ds in groups.values())} recording(s); the "
               f"condition number of the column-scaled regressor is {fmt(cond, 4)}.")
    strides = {name: stride(int(groups[name]["t"].size)) for name in shown}
    drawn = "; ".join(f"{_file_of(name, groups[name])}: one sample in {k}"
                      for name, k in strides.items() if k > 1)
    return {
        "title": f"Identification of {robot}",
        "lead": " ".join(lead),
        "summary": summary,
        "recordings": _recordings_table(groups),
        "joint_tables": {name: _joint_table(root, ds) for name, ds in groups.items()},
        "files": {name: _file_of(name, ds) for name, ds in groups.items()},
        "roles": {name: role_of(ds) for name, ds in groups.items()},
        "shown": shown,
        "shown_note": ("The figures show the validation recordings." if validate else
                       "No recording was held out: the figures show the training "
                       "recordings.") + (f" At most {MAX_POINTS:,} points a line are drawn "
                                         f"({drawn})." if drawn else ""),
        "parameters": parameters,
        "parameter_note": ("Values of the weighted least-squares fit with their standard "
                           "deviations (std [%]: relative to |value|; \u2014 where the value "
                           "is 0 or the column is not identifiable on the data). Units are "
                           "those of a revolute joint; a prismatic joint's drive parameters "
                           "are in kg, N s/m and N. Base parameters regroup standard ones "
                           "(Gautier 1990)."),
        "links": _links_table(root),
        "noise": _noise_table(root),
        "preprocessing": _sentences(_json(root, "preprocessing", [])),
        "notes": {name: _sentences(json.loads(ds.attrs["notes"]))
                  if _is_json_list(ds.attrs.get("notes")) else [] for name, ds in groups.items()},
        "provenance": _provenance(root, groups, utc_now().strftime("%Y-%m-%d %H:%M:%S UTC")),
        "version": clean(str(root.attrs.get("gd_analyze_version", ""))),
        "keywords": f"identification; robot {robot}; condition number {fmt(cond, 4)}",
    }


def _is_json_list(text):
    try:
        return isinstance(json.loads(str(text)), list)
    except (TypeError, ValueError):
        return False
