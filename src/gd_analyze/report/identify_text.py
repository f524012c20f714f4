"""The identify report's words and tables, read from a stored identification.

Every sentence and number comes from the datasets of ``identification.h5`` (the root group and
one group per recording; layout in ``gd_analyze.store.stored_identification`` of the identify
command): nothing is recomputed but the percentages of the standard deviations. Every name read
from the data (robot, joints, files, settings) is cleaned of the report's markup characters
(:func:`gd_analyze.report.markup.clean`); the HTML escapes it and the PDF sets it as text.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..store.stored_identification import REQUIRED_RECORDING, REQUIRED_ROOT, StoredIdentification
from .common import keep_units, utc_now
from .identify_figures import MAX_POINTS, role_of, shown_recordings, stride
from .markup import clean
from .numbers import fmt, pct

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["identify_context", "REQUIRED_ROOT", "REQUIRED_RECORDING", "parameter_units",
           "plain_table"]

#: Units of a base parameter by its name's letters, and of each drive kind (revolute joints;
#: prismatic: kg, kg, N s/m, N, N).
_M2 = "kg m\u00b2"
_BASE_UNITS = {"XX": _M2, "XY": _M2, "XZ": _M2, "YY": _M2, "YZ": _M2, "ZZ": _M2,
               "MX": "kg m", "MY": "kg m", "MZ": "kg m", "M": "kg"}
_DRIVE_UNITS = {"armature": _M2, "viscous": "N m s/rad", "coulomb": "N m", "offset": "N m"}


def plain_table(header: Sequence[str], rows: Sequence[Sequence[Any]],
                align: Sequence[str] | None = None,
                colour_cols: Sequence[int] = ()) -> dict[str, Any]:
    """A table as :func:`gd_analyze.report.common.table` makes it, its cells left as text.

    (``common.table`` letters cells that look like a G-D element's label, ``D12``, as
    mathematics, its index a subscript: a joint or file named so is shown as named here.)

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


def _json(text, default):
    """A JSON attribute as stored, or ``default`` when absent (None) or not JSON."""
    if text is None:
        return default
    try:
        return json.loads(str(text))
    except ValueError:
        return str(text)


def _strings(values):
    return [clean(v.decode() if isinstance(v, bytes) else str(v))
            for v in np.asarray(values).reshape(-1)]


def _joints(ident, rec, n):
    for joint in (rec.joint, ident.joint):
        if joint is not None and joint.size == n:
            return _strings(joint)
    return [str(j + 1) for j in range(n)]


def _file_of(rec):
    return clean(str(rec.file_name))


def _recordings_table(groups):
    has_prior = any(rec.has_prior_total for rec in groups.values())
    has_simple = any(rec.has_simplified_total for rec in groups.values())
    header = ["recording", "role", "samples", "duration [s]", "identified model"]
    header += ["robot file as shipped"] * has_prior + ["simplified model"] * has_simple
    rows = []
    for rec in groups.values():
        t = rec.t
        row = [_file_of(rec), role_of(rec), f"{t.size:,}",
               fmt(t[-1] - t[0], 4) if t.size else "n/a", pct(rec.total_relative_error)]
        if has_prior:
            row.append(pct(rec.prior_total_relative_error))
        if has_simple:
            row.append(pct(rec.simplified_total_relative_error))
        rows.append(row)
    return plain_table(header, rows, align=["left", "left"] + ["right"] * (len(header) - 2))


def _joint_table(ident, rec):
    n = rec.n
    joints = _joints(ident, rec, n)
    cols = [(rec.rms_error, "RMS error [N m]", fmt),
            (rec.relative_error, "relative error", pct),
            (rec.prior_relative_error, "robot file: relative error", pct),
            (rec.simplified_relative_error, "simplified: relative error", pct)]
    cols = [c for c in cols if c[0] is not None]
    rows = [[str(j + 1), joints[j]] + [f(float(v[j])) for v, _, f in cols]
            for j in range(n)]
    return plain_table(["joint", "name"] + [h for _, h, _ in cols], rows,
                       align=["right", "left"] + ["right"] * len(cols))


def _parameter_table(stored):
    names = _strings(stored.parameter) if stored.parameter is not None \
        else [str(k + 1) for k in range(stored.value.size)]
    value, std = stored.value, stored.std
    kinds = _strings(stored.kind) if stored.kind is not None else ["base"] * len(names)
    prior = np.asarray(stored.prior, float) if stored.prior is not None else None
    ident = np.asarray(stored.identifiable, bool) if stored.identifiable is not None \
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


def _links_table(stored):
    if stored.link_consistent is None:
        return None
    links = np.asarray(stored.link).reshape(-1) if stored.link is not None \
        else np.arange(1, stored.link_consistent.size + 1)
    ok = np.asarray(stored.link_consistent, bool)
    eig = np.asarray(stored.pseudo_inertia_min_eigenvalue, float) \
        if stored.pseudo_inertia_min_eigenvalue is not None else np.full(ok.size, math.nan)
    return plain_table(["link", f"smallest pseudo-inertia eigenvalue [{_M2}]", "consistent"],
                       [[str(links[k]), fmt(eig[k], 4, (1e-3, 1e4)), "yes" if ok[k] else "no"]
                        for k in range(ok.size)], colour_cols=[2])


def _noise_table(stored):
    if stored.noise_std is None:
        return None
    noise = np.asarray(stored.noise_std, float)
    joints = _strings(stored.joint) if stored.joint is not None and \
        stored.joint.size == noise.size else [str(j + 1) for j in range(noise.size)]
    return plain_table(["joint", "name", "residual standard deviation [N m]"],
                       [[str(j + 1), joints[j], fmt(noise[j], 4)] for j in range(noise.size)],
                       align=["right", "left", "right"])


def _provenance(stored, created):
    version = stored.gd_analyze_version
    rows = [["report created", created],
            ["gd-analyze version", clean(str("\u2014" if version is None else version))]]
    for value, label in ((stored.robot, "robot"), (stored.robot_source, "robot file"),
                         (stored.robot_sha256, "robot file SHA-256"),
                         (stored.standard_method, "standard parameters"),
                         (stored.coulomb_model, "Coulomb friction model")):
        if value is not None:
            rows.append([label, clean(str(value))])
    inputs = _json(stored.inputs, {})
    if isinstance(inputs, dict):
        rows += [[f"input {clean(str(k))}", clean(str(v))] for k, v in inputs.items()]
    for rec in stored.recordings.values():
        if rec.sha256 is not None and not (isinstance(inputs, dict) and rec.file
                                           in inputs):
            rows.append([f"input {_file_of(rec)}", clean(str(rec.sha256))])
    settings = _json(stored.settings, {})
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


def identify_context(root: StoredIdentification | xr.Dataset,
                     groups: dict[str, xr.Dataset] | None = None) -> dict[str, Any]:
    """The report's words and tables.

    Parameters
    ----------
    root : StoredIdentification or xarray.Dataset
        The stored identification
        (:class:`gd_analyze.store.stored_identification.StoredIdentification`), or its root group: ``value``, ``std`` (parameter) and optionally ``prior``,
        ``identifiable``, ``kind``, ``noise_std``, ``link_consistent``,
        ``pseudo_inertia_min_eigenvalue``; attributes ``condition_number``, ``rank``,
        ``unidentifiable``, ``preprocessing``, ``settings``, ``inputs`` (JSON), ``robot``...
    groups : dict of str to xarray.Dataset, optional
        With a root group, one per recording: ``t``, ``tau_measured``, ``tau_predicted`` (t, joint), per joint
        ``rms_error``, ``relative_error`` (and the robot file's and simplified model's), the
        role and ``total_relative_error``.

    Returns
    -------
    dict
        ``title``, ``lead``, ``summary``, ``notes`` and the tables, each a dict of
        :func:`plain_table`.
    """
    stored = StoredIdentification.of(root, groups)
    recordings = stored.recordings
    robot = clean(str("the robot" if stored.robot is None else stored.robot))
    cond = stored.condition_number
    validate = [k for k, rec in recordings.items() if role_of(rec) == "validate"]
    shown = shown_recordings(recordings)
    parameters, n_unident, names = _parameter_table(stored)
    lead = []
    for name in validate:
        rec = recordings[name]
        text = (f"On {_file_of(rec)}, not used for fitting, the identified model's total "
                f"relative torque error ||E||_F / ||T||_F is "
                f"{pct(rec.total_relative_error)}")
        prior = rec.prior_total_relative_error
        if math.isfinite(prior):
            text += f"; the robot file's as shipped, {pct(prior)}"
        simple = rec.simplified_total_relative_error
        if math.isfinite(simple):
            text += f"; the simplified model's, {pct(simple)}"
        lead.append(text + ".")
    if not validate:
        lead.append("No recording was held out for validation: every error below is on the "
                    "recordings the model was fitted to, not a prediction.")
    unident = _json(stored.unidentifiable, [])
    which = (f": {', '.join(clean(str(u)) for u in unident)}" if isinstance(unident, list)
             and unident else "")
    summary = (f"{len(names)} parameters ("
               + (f"{n_unident} not identifiable on the data{which}; they keep the robot "
                  "file's value" if n_unident else "all identifiable on the data")
               + "), identified from "
               f"{sum(role_of(rec) == 'train' for rec in recordings.values())} recording(s); the "
               f"condition number of the column-scaled regressor is {fmt(cond, 4)}.")
    strides = {name: stride(int(recordings[name].t.size)) for name in shown}
    drawn = "; ".join(f"{_file_of(recordings[name])}: one sample in {k}"
                      for name, k in strides.items() if k > 1)
    return {
        "title": f"Identification of {robot}",
        "lead": " ".join(lead),
        "summary": summary,
        "recordings": _recordings_table(recordings),
        "joint_tables": {name: _joint_table(stored, rec) for name, rec in recordings.items()},
        "files": {name: _file_of(rec) for name, rec in recordings.items()},
        "roles": {name: role_of(rec) for name, rec in recordings.items()},
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
        "links": _links_table(stored),
        "noise": _noise_table(stored),
        "preprocessing": _sentences(_json(stored.preprocessing, [])),
        "notes": {name: _sentences(json.loads(rec.notes))
                  if _is_json_list(rec.notes) else [] for name, rec in recordings.items()},
        "provenance": _provenance(stored, utc_now().strftime("%Y-%m-%d %H:%M:%S UTC")),
        "version": clean(str("" if stored.gd_analyze_version is None
                             else stored.gd_analyze_version)),
        "keywords": f"identification; robot {robot}; condition number {fmt(cond, 4)}",
    }


def _is_json_list(text):
    try:
        return isinstance(json.loads(str(text)), list)
    except (TypeError, ValueError):
        return False
