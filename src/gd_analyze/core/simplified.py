"""The simplified dynamic model of Sec. 3.4.1: keep only the dominant part of each element.

For each ranked element of D (upper triangle, mirrored to the lower) and h, the model keeps the
translational part, the rotational part, both, or nothing (negligible). Gravity c stays whole::

    tau_s = D_s qdd + h_s + c,   D_s = M_tran * D_tran + M_rot * D_rot,
                                 h_s = m_tran * h_tran + m_rot * h_rot

with 0/1 masks M and m from the choices. The model is written as JSON (``simplified_model.json``)
that carries its robot's parameters, so ``SimplifiedModel.load(path).torque(q, qd, qdd)`` works
on any machine.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from .dalembert import gd_terms
from ..errors import InputError
from .ranking import element_index, element_labels
from .robot import robot_from_dict

__all__ = ["SCHEMA_VERSION", "CHOICES", "SimplifiedModel", "choice_masks", "merge_choices",
           "simplified_torque", "torque_error", "TorqueErrorAccumulator", "parameters_sha256"]

#: Version of the simplified_model.json layout.
SCHEMA_VERSION = 1
#: What a simplified model keeps of an element: its translational part, its rotational part,
#: both, or nothing.
CHOICES = ("tran", "rot", "both", "none")


def choice_masks(choices, n):
    """0/1 masks that select the kept parts.

    Parameters
    ----------
    choices : dict
        Element label (``"D11"`` .. ``"Dnn"`` with i <= j, ``"h1"`` .. ``"hn"``) -> ``"tran"``,
        ``"rot"``, ``"both"`` or ``"none"``.
    n : int
        Number of joints.

    Returns
    -------
    D_tran_mask, D_rot_mask : ndarray, shape (n, n)
        Symmetric masks for D_tran and D_rot.
    h_tran_mask, h_rot_mask : ndarray, shape (n,)
        Masks for h_tran and h_rot.

    Raises
    ------
    ValueError
        If an element is missing or a choice is not one of the four.
    """
    Mt, Mr = np.zeros((n, n)), np.zeros((n, n))
    mt, mr = np.zeros(n), np.zeros(n)
    for label, (kind, i, j) in zip(element_labels(n), element_index(n)):
        if label not in choices:
            raise ValueError(f"no choice for element {label}")
        ch = choices[label]
        if ch not in CHOICES:
            raise ValueError(f"element {label}: choice must be one of {CHOICES}, got {ch!r}")
        keep_t, keep_r = ch in ("tran", "both"), ch in ("rot", "both")
        if kind == "D":
            Mt[i, j] = Mt[j, i] = keep_t
            Mr[i, j] = Mr[j, i] = keep_r
        else:
            mt[i], mr[i] = keep_t, keep_r
    return Mt, Mr, mt, mr


def simplified_torque(terms, choices, qdd):
    """Torques of the simplified model from already computed G-D terms.

    Parameters
    ----------
    terms : GDTerms
        D_tran, D_rot (N, n, n) [kg m^2]; h_tran, h_rot, c (N, n) [N m].
    choices : dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``.
    qdd : array_like, shape (N, n)
        Joint accelerations [rad/s^2].

    Returns
    -------
    ndarray, shape (N, n)
        tau_s = D_s qdd + h_s + c [N m].

    Raises
    ------
    ValueError
        As :func:`choice_masks`.
    """
    n = terms.c.shape[1]
    Mt, Mr, mt, mr = choice_masks(choices, n)
    D_s = Mt * terms.D_tran + Mr * terms.D_rot
    h_s = mt * terms.h_tran + mr * terms.h_rot
    qdd = np.asarray(qdd, dtype=float).reshape(terms.c.shape)
    return np.einsum("kij,kj->ki", D_s, qdd) + h_s + terms.c


class TorqueErrorAccumulator:
    """Accumulate a simplified model's per-joint torque error chunk by chunk.

    Parameters
    ----------
    n : int
        Number of joints.
    """

    def __init__(self, n):
        self.peak = np.zeros(n)
        self.sum_sq = np.zeros(n)
        self.peak_tau = np.zeros(n)
        self.count = 0

    def update(self, tau_simplified, tau_full):
        """Add a chunk of set points.

        Parameters
        ----------
        tau_simplified, tau_full : ndarray, shape (N, n)
            Torques of the simplified and the full model [N m].
        """
        err = np.abs(np.asarray(tau_simplified, float) - np.asarray(tau_full, float))
        if err.shape[0] == 0:
            return
        np.maximum(self.peak, err.max(axis=0), out=self.peak)
        self.sum_sq += (err**2).sum(axis=0)
        np.maximum(self.peak_tau, np.abs(tau_full).max(axis=0), out=self.peak_tau)
        self.count += err.shape[0]

    def result(self):
        """The error figures.

        Returns
        -------
        dict
            Lists of n floats: ``peak_abs_error`` and ``rms_error`` of |tau_s - tau| [N m],
            ``peak_tau`` = peak |tau| [N m], and ``relative_peak_error`` and
            ``relative_rms_error`` (the errors divided by peak |tau|; NaN for a joint whose
            torque is zero throughout).
        """
        rms = np.sqrt(self.sum_sq / max(self.count, 1))
        pt = self.peak_tau
        with np.errstate(invalid="ignore", divide="ignore"):
            rel_peak = np.where(pt > 0, self.peak / np.where(pt > 0, pt, 1), np.nan)
            rel_rms = np.where(pt > 0, rms / np.where(pt > 0, pt, 1), np.nan)
        return {"peak_abs_error": self.peak.tolist(), "rms_error": rms.tolist(),
                "peak_tau": pt.tolist(), "relative_peak_error": rel_peak.tolist(),
                "relative_rms_error": rel_rms.tolist()}


def torque_error(tau_simplified, tau_full):
    """Per-joint torque error of a simplified model along a trajectory.

    Parameters
    ----------
    tau_simplified, tau_full : ndarray, shape (N, n)
        Torques [N m].

    Returns
    -------
    dict
        As :meth:`TorqueErrorAccumulator.result`.
    """
    tau_full = np.asarray(tau_full, float)
    acc = TorqueErrorAccumulator(tau_full.shape[1])
    acc.update(tau_simplified, tau_full)
    return acc.result()


@dataclass(frozen=True, eq=False)
class SimplifiedModel:
    """A simplified G-D model: a robot and a choice per element of D and h.

    Attributes
    ----------
    robot : Robot
        The arm, with n joints.
    choices : dict
        Element label -> ``"tran"``, ``"rot"``, ``"both"`` or ``"none"``.
    dominance_threshold : float
        s used for the ranking.
    negligible_threshold : float
        e used for the ranking.
    trajectory_sha256 : str
        SHA-256 of the trajectory file the model was derived on.
    validation : dict
        The torque error along that trajectory, as :func:`torque_error` gives it.
    provenance : dict
        Tool version, input file names, settings.

    Notes
    -----
    Source: Sec. 3.4.1 of Fu, Gonzalez & Lee (1987): "The less dominant terms or elements can
    be neglected in calculating the dynamic equations of motion of the manipulator."
    """

    robot: object
    choices: dict
    dominance_threshold: float
    negligible_threshold: float
    trajectory_sha256: str = ""
    validation: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)

    def torque(self, q, qd, qdd):
        """Torques of the simplified model, tau_s = D_s qdd + h_s + c.

        Parameters
        ----------
        q : array_like, shape (N, n) or (n,)
            Joint positions [rad].
        qd : array_like, shape (N, n) or (n,)
            Joint velocities [rad/s].
        qdd : array_like, shape (N, n) or (n,)
            Joint accelerations [rad/s^2].

        Returns
        -------
        ndarray, shape (N, n)
            Joint torques [N m].

        Raises
        ------
        ValueError
            If the arrays do not have n columns or disagree on N.
        """
        terms = gd_terms(self.robot, q, qd)
        return simplified_torque(terms, self.choices, np.asarray(qdd, float).reshape(terms.c.shape))

    def to_dict(self):
        """The model in the layout of simplified_model.json.

        Returns
        -------
        dict
        """
        return {
            "schema_version": SCHEMA_VERSION,
            "kind": "gd-analyze simplified model",
            "robot": {"name": self.robot.name, "sha256": self.robot.sha256,
                      "parameters_sha256": parameters_sha256(self.robot.to_dict()),
                      "source": self.robot.source, "parameters": self.robot.to_dict()},
            "dominance_threshold": self.dominance_threshold,
            "negligible_threshold": self.negligible_threshold,
            "choices": dict(self.choices),
            "trajectory_sha256": self.trajectory_sha256,
            "validation": self.validation,
            "provenance": self.provenance,
        }

    def save(self, path):
        """Write the model as JSON, atomically.

        Parameters
        ----------
        path : str or os.PathLike
            Destination file.

        Raises
        ------
        OSError
            If the file cannot be written.
        """
        from ..files import atomic_path

        with atomic_path(path) as tmp:
            with open(tmp, "w", encoding="utf-8") as fh:
                json.dump(_json_safe(self.to_dict()), fh, indent=2)
                fh.write("\n")

    @classmethod
    def load(cls, path):
        """Read a simplified_model.json.

        Parameters
        ----------
        path : str or os.PathLike
            The file written by :meth:`save` or by ``gd-analyze``.

        Returns
        -------
        SimplifiedModel

        Raises
        ------
        InputError
            If the file is missing or not strict JSON (duplicate keys, NaN, numbers beyond a
            float, deep nesting), of another schema version, does not follow
            :data:`gd_analyze.core.schema.MODEL_SCHEMA` (types, unknown keys, finite
            thresholds in range), its robot's parameters do not match
            ``robot.parameters_sha256`` or fail validation, or its choices do not name exactly
            the elements of an n-joint robot. One line naming the key.
        """
        from .schema import MODEL_SCHEMA, load_json

        path = str(path)
        spec = load_json(path, "simplified-model JSON")
        if isinstance(spec, dict) and spec.get("schema_version") != SCHEMA_VERSION:
            raise InputError(f"expected schema_version {SCHEMA_VERSION}, got "
                             f"{spec.get('schema_version')!r}"[:120], path,
                             column="schema_version")
        MODEL_SCHEMA.check(spec, path, "")
        rob = spec["robot"]
        if parameters_sha256(rob["parameters"]) != rob["parameters_sha256"]:
            raise InputError("the robot's parameters do not match their SHA-256 (edited after "
                             "the model was written?)", path, column="robot.parameters_sha256")
        robot = robot_from_dict(rob["parameters"], source=f"{path}#robot",
                                sha256=rob["sha256"] or None)
        if robot.name != rob["name"]:
            raise InputError(f"robot.name {rob['name']!r} differs from the parameters' name "
                             f"{robot.name!r}", path, column="robot.name")
        labels = element_labels(robot.n)
        choices = spec["choices"]
        if set(choices) != set(labels):
            extra = sorted(set(choices) - set(labels))
            missing = [lab for lab in labels if lab not in choices]
            raise InputError((f"unknown element {extra[0]!r}" if extra else
                              f"missing element {missing[0]!r}")
                             + f" (a {robot.n}-joint robot has {labels[0]}..{labels[-1]})",
                             path, column="choices")
        return cls(robot=robot, choices=dict(choices),
                   dominance_threshold=float(spec["dominance_threshold"]),
                   negligible_threshold=float(spec["negligible_threshold"]),
                   trajectory_sha256=spec.get("trajectory_sha256", ""),
                   validation=spec.get("validation", {}),
                   provenance=spec.get("provenance", {}))


def parameters_sha256(parameters):
    """SHA-256 of a robot's parameters as stored in a model file (canonical JSON).

    Parameters
    ----------
    parameters : dict
        :meth:`Robot.to_dict` output, or the same as read back from JSON.

    Returns
    -------
    str
        64 hexadecimal digits of the SHA-256 of ``json.dumps(parameters, sort_keys=True)``;
        a float survives the JSON round trip exactly, so the digest does too.
    """
    import hashlib

    text = json.dumps(_json_safe(parameters), sort_keys=True, allow_nan=False)
    return hashlib.sha256(text.encode()).hexdigest()


def _json_safe(obj):
    """Replace NaN/inf (not valid JSON) by None, recursively."""
    if isinstance(obj, dict):
        return {k: _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v) for v in obj]
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    if isinstance(obj, np.generic):
        return _json_safe(obj.item())
    return obj


def merge_choices(choices_list):
    """Merge simplified models conservatively: drop a part only where every model drops it.

    Parameters
    ----------
    choices_list : sequence of dict
        One dict per trajectory: element label -> ``"tran"``, ``"rot"``, ``"both"`` or
        ``"none"``; all with the same labels.

    Returns
    -------
    dict
        Element label -> merged choice, in the label order of the first dict. With
        keep_tran = any choice in {tran, both} and keep_rot = any choice in {rot, both}:
        ``"both"`` if both are kept, ``"tran"`` or ``"rot"`` if only one, ``"none"`` if
        neither (the element is negligible in every trajectory).

    Raises
    ------
    ValueError
        If the sequence is empty, the dicts have different labels, or a choice is not one of
        the four.

    Notes
    -----
    The merged model keeps every part that any trajectory's own model keeps, so it is the
    smallest model of this form that is, element by element, at least as complete as each of
    them. Source: the simplified model of Sec. 3.4.1 of Fu, Gonzalez & Lee (1987), which
    "depends on the specific trajectory being considered".

    Examples
    --------
    >>> merge_choices([{"D11": "tran", "h1": "none"}, {"D11": "rot", "h1": "none"}])
    {'D11': 'both', 'h1': 'none'}
    """
    choices_list = list(choices_list)
    if not choices_list:
        raise ValueError("no simplified models to merge")
    labels = list(choices_list[0])
    keep_t = dict.fromkeys(labels, False)
    keep_r = dict.fromkeys(labels, False)
    for k, choices in enumerate(choices_list):
        if set(choices) != set(labels):
            diff = sorted(set(choices) ^ set(labels))
            raise ValueError(f"model {k} has other elements than model 0 (e.g. {diff[0]!r})")
        for label, ch in choices.items():
            if ch not in CHOICES:
                raise ValueError(f"model {k}, element {label}: choice must be one of "
                                 f"{CHOICES}, got {ch!r}")
            keep_t[label] |= ch in ("tran", "both")
            keep_r[label] |= ch in ("rot", "both")
    table = {(True, True): "both", (True, False): "tran", (False, True): "rot",
             (False, False): "none"}
    return {label: table[(keep_t[label], keep_r[label])] for label in labels}
